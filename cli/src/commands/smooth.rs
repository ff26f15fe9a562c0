//! `deform smooth`: Alter's Taubin arclength smoothing of Plot3D grids, with every line end,
//! seam and interface held and every cell checked against the input for flips.

use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::{Direction, SmoothArgs};
use crate::formats::plot3d::{Plot3dBlock, Plot3dGrid};
use crate::output::Staged;

use crate::error::CliError;
use crate::files::{
    cell_dim, file_kind, input_kind, io_err, plot3d_options, read_plot3d, write_grid, FileKind,
};
use crate::report::{seconds, value_name, Outcome};

#[derive(Serialize)]
pub(crate) struct SmoothReport {
    command: &'static str,
    grid: String,
    output: String,
    format: String,
    blocks: usize,
    direction: String,
    normalized: bool,
    iterations: usize,
    max_stretching_before: f64,
    max_stretching_after: f64,
    max_point_move: f64,
    max_laplacian_s_before: f64,
    max_laplacian_s_after: f64,
    pinned_coincident_points: usize,
    free_ends: Vec<String>,
    flipped_cells: usize,
    unchecked_blocks: usize,
    folded_lines: usize,
    seconds: f64,
}

/// Per block, a mask of the points whose coordinates (bit for bit, `−0 = +0`) occur at more
/// than one grid position of the file: O-grid seams, C-grid wake cuts, block interfaces,
/// collapsed axes. Smoothing holds them so that what was closed stays closed.
pub(crate) fn coincident_points(grid: &Plot3dGrid) -> (Vec<Vec<u8>>, usize) {
    use std::collections::HashMap;
    let key = |p: &[f64; 3]| p.map(|x| (x + 0.0).to_bits());
    let mut count: HashMap<[u64; 3], u32> = HashMap::new();
    for b in &grid.blocks {
        for p in &b.points {
            *count.entry(key(p)).or_insert(0) += 1;
        }
    }
    let mut total = 0;
    let masks = grid
        .blocks
        .iter()
        .map(|b| {
            b.points
                .iter()
                .map(|p| {
                    let shared = count.get(&key(p)).copied().unwrap_or(0) > 1;
                    total += usize::from(shared);
                    u8::from(shared)
                })
                .collect()
        })
        .collect();
    (masks, total)
}

/// Per block, whether the last face of `direction` is free, from the `--free-end [B:]FACE`
/// values: only that face can be named (the first face is where arclength is measured from),
/// blocks are 1-based.
fn free_blocks(
    specs: &[String],
    direction: Direction,
    blocks: usize,
    normalized: bool,
) -> Result<Vec<bool>, CliError> {
    let mut free = vec![false; blocks];
    let last = format!("{}max", value_name(&direction));
    for spec in specs {
        let (block, face) = match spec.split_once(':') {
            Some((b, f)) => {
                let b: usize = b.trim().parse().map_err(|_| {
                    CliError::Invalid(format!("--free-end {spec}: `{b}` is not a block number"))
                })?;
                if b == 0 || b > blocks {
                    return Err(CliError::Invalid(format!(
                        "--free-end {spec}: the grid has blocks 1 to {blocks}"
                    )));
                }
                (Some(b - 1), f.trim())
            }
            None => (None, spec.trim()),
        };
        if face != last {
            return Err(CliError::Invalid(format!(
                "--free-end {spec}: only the face at the end of the smoothing direction ({last}) can be free; the first face is where arclength is measured from and the others are not line ends"
            )));
        }
        match block {
            Some(b) => free[b] = true,
            None => free.fill(true),
        }
    }
    if normalized && free.contains(&true) {
        return Err(CliError::Invalid(
            "--free-end needs the physical arclength (with --normalized the line ends never move)"
                .into(),
        ));
    }
    Ok(free)
}

/// Refuses a free face with a point that coincides with another grid point (`pins`: the
/// coincident points of the block), naming the first.
fn check_free_face(
    grid: &Path,
    b: usize,
    dims: [usize; 3],
    direction: Direction,
    pins: &[u8],
) -> Result<(), CliError> {
    let [ni, nj, nk] = dims;
    let last = match direction {
        Direction::I => ni - 1,
        Direction::J => nj - 1,
        Direction::K => nk - 1,
    };
    let on_face = |p: usize| {
        let (i, j, k) = (p % ni, (p / ni) % nj, p / (ni * nj));
        [i, j, k][direction as usize] == last
    };
    match (0..pins.len()).find(|&p| pins[p] != 0 && on_face(p)) {
        Some(p) => Err(CliError::Invalid(format!(
            "{}: block {}: the free face {}max has point i={}, j={}, k={} that coincides with another grid point (a seam or an interface); keep that face fixed",
            grid.display(),
            b + 1,
            value_name(&direction),
            p % ni + 1,
            (p / ni) % nj + 1,
            p / (ni * nj) + 1
        ))),
        None => Ok(()),
    }
}

/// The cells (0-based, i-fastest) whose smallest corner Jacobian was > 0 and is ≤ 0.
pub(crate) fn flipped(before: &[f64], after: &[f64]) -> Vec<usize> {
    before
        .iter()
        .zip(after)
        .enumerate()
        .filter(|(_, (&b, &a))| b > 0.0 && a <= 0.0)
        .map(|(c, _)| c)
        .collect()
}

/// `i=…, j=…[, k=…]` (1-based, as Plot3D users count) of cell `c` of a block.
pub(crate) fn cell_name(dims: [usize; 3], dim: usize, c: usize) -> String {
    let ci = dims[0].saturating_sub(1).max(1);
    let cj = dims[1].saturating_sub(1).max(1);
    let (i, j, k) = (c % ci, (c / ci) % cj, c / (ci * cj));
    if dim == 2 {
        format!("i={}, j={}", i + 1, j + 1)
    } else {
        format!("i={}, j={}, k={}", i + 1, j + 1, k + 1)
    }
}

pub(crate) fn smooth(a: &SmoothArgs, quiet: bool) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    check_smooth_args(a)?;
    let (mut grid, layout) = read_plot3d(&a.grid, &plot3d_options(&a.layout))?;
    if grid.dim == 2 && a.direction == Direction::K {
        return Err(CliError::Invalid(format!(
            "{}: --direction k needs a 3D grid, this one is 2D",
            a.grid.display()
        )));
    }
    let free = free_blocks(&a.free_end, a.direction, grid.blocks.len(), a.normalized)?;
    let bar = crate::progress::bar(grid.blocks.len() as u64, "smoothing", quiet);
    let mut report = new_report(a, &layout, grid.blocks.len(), &free);
    let (pins, shared) = coincident_points(&grid);
    report.pinned_coincident_points = shared;
    for (b, (blk, pin)) in grid.blocks.iter().zip(&pins).enumerate() {
        if free[b] {
            check_free_face(&a.grid, b, blk.dims, a.direction, pin)?;
        }
    }
    let dim = grid.dim;
    for (b, (blk, pin)) in grid.blocks.iter_mut().zip(&pins).enumerate() {
        let job = BlockJob {
            a,
            dim,
            b,
            pin,
            free: free[b],
        };
        job.run(blk, &mut report)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut staged = Staged::new();
    staged
        .write(&a.out, |f| write_grid(&a.grid, &a.out, &grid, &layout, f))
        .map_err(io_err(&a.out))?;
    staged.commit().map_err(io_err(&a.out))?;
    report.seconds = seconds(t0);
    Ok(Outcome {
        text: smooth_text(&report),
        json: serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
    })
}

/// What `smooth` checks before reading the grid.
fn check_smooth_args(a: &SmoothArgs) -> Result<(), CliError> {
    if matches!(
        file_kind(&a.out),
        Some(FileKind::Su2 | FileKind::Vtu | FileKind::Vts)
    ) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a Plot3D grid (written in the input's layout; any extension but .su2, .vtu, .vts)",
            a.out.display()
        )));
    }
    if input_kind(&a.grid)? != FileKind::Plot3d {
        return Err(CliError::Invalid(format!(
            "{}: smooth needs a structured Plot3D grid, this is an SU2 mesh",
            a.grid.display()
        )));
    }
    if !(a.lambda.is_finite() && a.lambda > 0.0 && a.mu.is_finite() && a.mu <= 0.0) {
        return Err(CliError::Invalid(
            "--lambda must be > 0 and --mu <= 0 (Taubin: mu slightly below -lambda)".into(),
        ));
    }
    if a.coarse == Some(0) {
        return Err(CliError::Invalid("--coarse must be at least 1".into()));
    }
    Ok(())
}

/// The report before any block is smoothed.
fn new_report(
    a: &SmoothArgs,
    layout: &impl std::fmt::Display,
    blocks: usize,
    free: &[bool],
) -> SmoothReport {
    SmoothReport {
        command: "smooth",
        grid: a.grid.display().to_string(),
        output: a.out.display().to_string(),
        format: format!("Plot3D {layout}"),
        blocks,
        direction: value_name(&a.direction),
        normalized: a.normalized,
        iterations: 0,
        max_stretching_before: 1.0,
        max_stretching_after: 1.0,
        max_point_move: 0.0,
        max_laplacian_s_before: 0.0,
        max_laplacian_s_after: 0.0,
        pinned_coincident_points: 0,
        free_ends: (free.iter().enumerate())
            .filter(|(_, &f)| f)
            .map(|(b, _)| format!("block {}: {}max", b + 1, value_name(&a.direction)))
            .collect(),
        flipped_cells: 0,
        unchecked_blocks: 0,
        folded_lines: 0,
        seconds: 0.0,
    }
}

/// Smoothing one block: the arguments, the grid's dimension, the block's index, its held
/// points and whether its last face is free.
struct BlockJob<'j> {
    a: &'j SmoothArgs,
    dim: usize,
    b: usize,
    pin: &'j [u8],
    free: bool,
}

impl BlockJob<'_> {
    /// `iterations` (and the coarse pass) on a copy of `original`.
    fn smoothed(
        &self,
        blk: &Plot3dBlock,
        original: &[[f64; 3]],
        iterations: usize,
        coarse: Option<usize>,
    ) -> Result<(Vec<[f64; 3]>, crate::engine::BlockSmoothing), CliError> {
        let mut pts = original.to_vec();
        let direction = kernel_direction(self.a.direction);
        let modes = (self.a.normalized, self.free);
        let (a, pin) = (self.a, Some(self.pin));
        crate::engine::smooth_block(
            self.dim, blk.dims, &mut pts, direction, modes, iterations, a.lambda, a.mu, coarse, pin,
        )
        .map(|r| (pts, r))
        .map_err(|e| e.within(&format!("block {}", self.b + 1)))
    }

    /// Smooths the block in place and adds what it did to `report`; a flipped cell is an
    /// error naming it and the first iteration after which it is flipped (unless
    /// `--allow-folds`).
    fn run(&self, blk: &mut Plot3dBlock, report: &mut SmoothReport) -> Result<(), CliError> {
        let (a, dim) = (self.a, self.dim);
        let direction = kernel_direction(a.direction);
        let original = blk.points.clone();
        let (smoothed, r) = (self.smoothed(blk, &original, a.iterations, a.coarse))
            .map_err(|e| e.in_file(&a.grid))?;
        let laplacian =
            |p: &[[f64; 3]]| crate::engine::max_arclength_laplacian(dim, blk.dims, p, direction);
        report.max_laplacian_s_before = report.max_laplacian_s_before.max(laplacian(&original)?);
        report.max_laplacian_s_after = report.max_laplacian_s_after.max(laplacian(&smoothed)?);
        // The cell check: every corner Jacobian against the input's.
        let cdim = cell_dim(dim, blk);
        if cdim == 3 && blk.dims.contains(&1) {
            report.unchecked_blocks += 1;
        } else {
            let cells = crate::engine::structured_cells(blk.dims, &original, cdim);
            let before = crate::engine::corner_jacobians(cdim, &cells, &original)?;
            let after = crate::engine::corner_jacobians(cdim, &cells, &smoothed)?;
            let bad = flipped(&before, &after);
            if !bad.is_empty() && !a.allow_folds {
                let flips_after = |k: usize| -> Result<bool, CliError> {
                    let (p, _) = self.smoothed(blk, &original, k, None)?;
                    let after = crate::engine::corner_jacobians(cdim, &cells, &p)?;
                    Ok(!flipped(&before, &after).is_empty())
                };
                let when = first_flip(a.iterations, flips_after)?;
                return Err(CliError::Folded(format!(
                    "{}: block {}: smoothing flips {} cell(s) (first: cell {}, {when}); nothing was written (--allow-folds writes them anyway)",
                    a.grid.display(),
                    self.b + 1,
                    bad.len(),
                    cell_name(blk.dims, dim, bad[0]),
                )));
            }
            report.flipped_cells += bad.len();
        }
        blk.points = smoothed;
        report.iterations = report.iterations.max(r.iterations);
        report.max_stretching_before = report.max_stretching_before.max(r.max_stretching_before);
        report.max_stretching_after = report.max_stretching_after.max(r.max_stretching_after);
        report.max_point_move = report.max_point_move.max(r.max_point_move);
        Ok(())
    }
}

/// The kernel's direction of `--direction`.
fn kernel_direction(d: Direction) -> deform_kernel::Direction {
    match d {
        Direction::I => deform_kernel::Direction::I,
        Direction::J => deform_kernel::Direction::J,
        Direction::K => deform_kernel::Direction::K,
    }
}

/// The first iteration after which a cell is flipped (fine iterations 1..=`iterations` by
/// bisection, assuming a flip persists), or the coarse-grid pass when the fine iterations
/// alone flip nothing.
fn first_flip(
    iterations: usize,
    flips_after: impl Fn(usize) -> Result<bool, CliError>,
) -> Result<String, CliError> {
    if iterations == 0 || !flips_after(iterations)? {
        return Ok("in the coarse-grid pass".to_string());
    }
    let (mut lo, mut hi) = (1, iterations);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if flips_after(mid)? {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Ok(format!("after iteration {lo}"))
}

/// The text form of the report.
fn smooth_text(report: &SmoothReport) -> String {
    let mut text = format!(
        "{} -> {}: {} block(s), {} iterations along {}{}{}, max stretching {:.4} -> {:.4}, max |∇²S| {:.4e} -> {:.4e}, max point move {:.3e}, {} coincident points held",
        report.grid,
        report.output,
        report.blocks,
        report.iterations,
        report.direction,
        if report.normalized { " (normalized)" } else { "" },
        if report.free_ends.is_empty() {
            String::new()
        } else {
            format!(" (free ends: {})", report.free_ends.join(", "))
        },
        report.max_stretching_before,
        report.max_stretching_after,
        report.max_laplacian_s_before,
        report.max_laplacian_s_after,
        report.max_point_move,
        report.pinned_coincident_points,
    );
    if report.flipped_cells > 0 {
        text.push_str(&format!(
            "\n  WARNING: {} cell(s) flipped (written because of --allow-folds)",
            report.flipped_cells
        ));
    }
    if report.unchecked_blocks > 0 {
        text.push_str(&format!(
            "\n  note: {} surface block(s) of a 3D grid have no volume cells; their cells were not checked",
            report.unchecked_blocks
        ));
    }
    text
}
