//! `deform demo`: the papers' experiments on generated meshes, with pictures, VTK files and a
//! Markdown report.
//!
//! - Samareh / Yang & Özgen: NACA 2412 meshes (inviscid triangles, viscous split-quad hybrid,
//!   O-grid) pitched nose-down about the quarter chord by several angles, deformed by every
//!   method; the table counts inverted and folded cells, the smallest area ratio and the
//!   largest change of the first grid-line angle at the wall.
//! - Alter: Taubin λ|μ arclength smoothing of a noisy structured grid and of a cavity-like grid
//!   with abrupt stretching jumps; the table gives the largest stretching ratio before and
//!   after, and the pictures colour every cell by its spacing ratio along the smoothed lines
//!   (before and after on one scale, so the difference shows).
//! - Alter's own case ([`adapted`]): a solution-adapted volume grid with a rough outer
//!   boundary, smoothed along k with the outer end free (pictures of the outer-boundary
//!   arclength, his figures 6 and 7, and of a cut through the grid).
//! - Wall close-ups are sized to the first-layer height at mid-chord, so the first grid line's
//!   angle at the wall (kept by the quaternion method, sheared by springs) is visible.
//!
//! Every file is staged and renamed into the output directory only when the whole demo
//! succeeded.

mod adapted;

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use deform_kernel::Direction;
use serde::Serialize;

use crate::args::DemoArgs;
use crate::engine::{
    quality, run_move, smooth_block, structured_cells, Motion, MoveInput, MoveMethod, MoveSolver,
    Stiffness,
};
use crate::error::CliError;
use crate::files::su2_from_mesh2;
use crate::formats::su2::{write_su2, Su2Mesh};
use crate::formats::vtk::{write_vts, write_vtu, VtkEncoding, VtkField};
use crate::formats::CellList;
use crate::output::Staged;
use crate::plot::{
    bounding_window, png, png_panels, svg, svg_panels, zoom, Picture, Shading, Window,
};
use crate::report::Outcome;

/// One deformation run of the table.
#[derive(Clone, Debug, Serialize)]
pub struct DeformRow {
    /// Mesh name.
    pub mesh: String,
    /// Method (command-line spelling).
    pub method: String,
    /// Pitch angle, degrees (positive = counter-clockwise = nose down).
    pub angle_deg: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Converged.
    pub converged: bool,
    /// Cells whose signed area changed sign.
    pub inverted_cells: usize,
    /// Cells with a corner Jacobian ≤ 0.
    pub folded_cells: usize,
    /// Smallest deformed/undeformed area ratio.
    pub min_area_ratio: Option<f64>,
    /// Largest first grid-line angle change at the airfoil, degrees.
    pub max_wall_angle_change_deg: Option<f64>,
    /// Wall-clock seconds of the deformation.
    pub seconds: f64,
}

/// One smoothing run of the table.
#[derive(Clone, Debug, Serialize)]
pub struct SmoothRow {
    /// Grid name.
    pub grid: String,
    /// Settings.
    pub settings: String,
    /// Iterations.
    pub iterations: usize,
    /// Largest stretching ratio before.
    pub max_stretching_before: f64,
    /// Largest stretching ratio after.
    pub max_stretching_after: f64,
    /// Largest point move.
    pub max_point_move: f64,
    /// Folded cells after smoothing.
    pub folded_cells: usize,
}

#[derive(Serialize)]
struct DemoReport {
    command: &'static str,
    out: String,
    deformation: Vec<DeformRow>,
    smoothing: Vec<SmoothRow>,
    files: Vec<String>,
    seconds: f64,
}

/// A deformed mesh kept for the side-by-side picture: method, points, highlighted cells.
type Compared<'a> = (&'a str, Vec<[f64; 3]>, Vec<bool>);

/// A smoothing case: grid name, grid, direction, normalised, coarse factor, description.
type SmoothCase<'a> = (
    &'a str,
    &'a deform_meshgen::Mesh2,
    Direction,
    bool,
    Option<usize>,
    &'a str,
);

/// Sweep cap of the node-wise angle-spring runs. Plain Gauss–Seidel needs more than 2·10⁴
/// sweeps on these 10⁴-node meshes; over-relaxed (the CLI's default, ω from
/// [`crate::engine::angle_direct_omega`]) it needs about 800–1200 at 15°. Capped runs are
/// reported as not converged, and angle-cg solves the same system.
const ANGLE_DIRECT_SWEEPS: usize = 3000;

const METHODS: [(MoveMethod, &str); 5] = [
    (MoveMethod::Quaternion, "quaternion"),
    (MoveMethod::Idw, "idw"),
    (MoveMethod::Spring, "spring"),
    (MoveMethod::AngleDirect, "angle-direct"),
    (MoveMethod::AngleCg, "angle-cg"),
];

/// The wall node of `wall` nearest to `near`, and the distance from it to its nearest
/// neighbour off the wall (the first-layer height there), so that a close-up can be sized to
/// the boundary layer's first cells instead of a fixed fraction of the chord.
fn wall_node_near(
    points: &[[f64; 3]],
    cells: &CellList,
    wall: &CellList,
    near: [f64; 2],
) -> ([f64; 2], f64) {
    let d2 = |p: &[f64; 3], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let on_wall: std::collections::BTreeSet<u32> = wall.nodes.iter().copied().collect();
    let Some(&w) = on_wall.iter().min_by(|&&a, &&b| {
        let pa = points
            .get(a as usize)
            .map_or(f64::INFINITY, |p| d2(p, near));
        let pb = points
            .get(b as usize)
            .map_or(f64::INFINITY, |p| d2(p, near));
        pa.total_cmp(&pb)
    }) else {
        return (near, 0.015);
    };
    let Some(pw) = points.get(w as usize).copied() else {
        return (near, 0.015);
    };
    let first = cells
        .iter()
        .filter(|(_, nodes)| nodes.contains(&w))
        .flat_map(|(_, nodes)| nodes.iter().copied())
        .filter(|n| !on_wall.contains(n))
        .filter_map(|n| points.get(n as usize).map(|p| d2(p, [pw[0], pw[1]]).sqrt()))
        .fold(f64::INFINITY, f64::min);
    let first = if first.is_finite() && first > 0.0 {
        first
    } else {
        0.015
    };
    ([pw[0], pw[1]], first)
}

/// Per cell of a 2D structured grid (in [`structured_cells`]' order): the largest ratio of
/// its spacing along `direction` (0 = i, 1 = j) to a neighbour's on the same line (≥ 1; 1 =
/// uniform), so pictures show where the grid stretches abruptly.
fn cell_spacing_ratios(dims: [usize; 3], points: &[[f64; 3]], direction: usize) -> Vec<f64> {
    let [ni, nj, _] = dims;
    let p = |i: usize, j: usize| points.get(i + ni * j).copied().unwrap_or([0.0; 3]);
    let len = |a: [f64; 3], b: [f64; 3]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    // Spacing of the line segment starting at (i, j) in `direction`, if it exists.
    let step = |i: usize, j: usize| -> Option<f64> {
        if direction == 0 {
            (i + 1 < ni && j < nj).then(|| len(p(i, j), p(i + 1, j)))
        } else {
            (j + 1 < nj && i < ni).then(|| len(p(i, j), p(i, j + 1)))
        }
    };
    let ratio = |a: f64, b: f64| {
        if a > 0.0 && b > 0.0 {
            a.max(b) / a.min(b)
        } else {
            1.0
        }
    };
    let mut out = Vec::with_capacity(ni.saturating_sub(1) * nj.saturating_sub(1));
    for j in 0..nj.saturating_sub(1) {
        for i in 0..ni.saturating_sub(1) {
            let (here, prev, next) = if direction == 0 {
                (
                    step(i, j),
                    i.checked_sub(1).and_then(|i| step(i, j)),
                    step(i + 1, j),
                )
            } else {
                (
                    step(i, j),
                    j.checked_sub(1).and_then(|j| step(i, j)),
                    step(i, j + 1),
                )
            };
            let h = here.unwrap_or(0.0);
            let r = [prev, next]
                .iter()
                .flatten()
                .map(|&n| ratio(h, n))
                .fold(1.0, f64::max);
            out.push(r);
        }
    }
    out
}

fn rotate_about(p: [f64; 2], c: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, co) = deg.to_radians().sin_cos();
    let (x, y) = (p[0] - c[0], p[1] - c[1]);
    [c[0] + co * x - s * y, c[1] + s * x + co * y]
}

struct Files<'a> {
    staged: Staged,
    dir: &'a Path,
    names: Vec<String>,
}

impl Files<'_> {
    fn put(&mut self, name: &str, bytes: &[u8]) -> Result<(), CliError> {
        let path = self.dir.join(name);
        self.staged
            .write(&path, |f| std::io::Write::write_all(f, bytes))
            .map_err(|source| CliError::Io { path, source })?;
        self.names.push(name.to_string());
        Ok(())
    }

    fn picture(&mut self, stem: &str, pic: &Picture<'_>, w: Window) -> Result<(), CliError> {
        self.put(&format!("{stem}.svg"), svg(pic, w, 900).as_bytes())?;
        let bytes = png(pic, w, 900).map_err(CliError::Invalid)?;
        self.put(&format!("{stem}.png"), &bytes)
    }
}

fn vtu_bytes(
    mesh: &Su2Mesh,
    points: &[[f64; 3]],
    disp: &[f64],
    cell_fields: &[VtkField<'_>],
) -> Result<Vec<u8>, CliError> {
    let mut v = Vec::new();
    write_vtu(
        &mut v,
        points,
        &mesh.elements,
        &[VtkField {
            name: "displacement",
            components: 3,
            values: disp,
        }],
        cell_fields,
        VtkEncoding::Base64,
    )
    .map_err(|e| CliError::Invalid(e.to_string()))?;
    Ok(v)
}

/// Runs the demo.
pub fn demo(a: &DemoArgs, quiet: bool) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let dir: PathBuf = a.out.clone();
    let created = !dir.exists();
    fs::create_dir_all(&dir).map_err(|source| CliError::Io {
        path: dir.clone(),
        source,
    })?;
    let result = run(a, &dir, quiet, t0);
    if result.is_err() && created {
        let _ = fs::remove_dir(&dir);
    }
    result
}

fn run(a: &DemoArgs, dir: &Path, quiet: bool, t0: Instant) -> Result<Outcome, CliError> {
    let mut files = Files {
        staged: Staged::new(),
        dir,
        names: Vec::new(),
    };
    let angles: &[f64] = if a.quick { &[20.0] } else { &[5.0, 15.0, 30.0] };
    let methods: Vec<(MoveMethod, &str)> = METHODS
        .iter()
        .copied()
        .filter(|(m, _)| !(a.quick && *m == MoveMethod::AngleDirect))
        .collect();
    let meshes = demo_meshes(a.quick)?;
    let runs = meshes.len() * angles.len() * methods.len();
    let bar = crate::progress::bar(runs as u64 + 2, "demo", quiet);
    let mut rows = Vec::new();
    for (name, mesh) in &meshes {
        let cases = MeshCases {
            name,
            mesh,
            angles,
            methods: &methods,
            bar: &bar,
        };
        cases.run(&mut files, &mut rows)?;
    }
    let mut smooth_rows = smoothing_cases(a.quick, &mut files, &bar)?;
    smooth_rows.push(adapted::adapted_case(a.quick, &mut files)?);
    bar.finish_and_clear();
    finish(dir, files, rows, smooth_rows, angles, t0)
}

/// The three NACA 2412 meshes of the deformation cases (smaller with `--quick`).
fn demo_meshes(quick: bool) -> Result<Vec<(&'static str, Su2Mesh)>, CliError> {
    let mut opts_inv = deform_meshgen::AirfoilGrid::inviscid();
    let mut opts_visc = deform_meshgen::AirfoilGrid::viscous();
    if quick {
        for o in [&mut opts_inv, &mut opts_visc] {
            o.surface_points = 32;
            o.radial_points = 12;
            o.first_layer = 1e-2;
            o.boundary_layers = o.boundary_layers.min(4);
        }
    }
    let err = |e: deform_meshgen::MeshError| CliError::Invalid(e.to_string());
    Ok(vec![
        (
            "inviscid",
            su2_from_mesh2(&deform_meshgen::naca_triangulated(&opts_inv).map_err(err)?),
        ),
        (
            "viscous",
            su2_from_mesh2(&deform_meshgen::naca_hybrid(&opts_visc).map_err(err)?),
        ),
        (
            "ogrid",
            su2_from_mesh2(&deform_meshgen::naca_ogrid(&opts_visc).map_err(err)?),
        ),
    ])
}

/// The report, the tables and the files of a finished demo.
fn finish(
    dir: &Path,
    mut files: Files<'_>,
    rows: Vec<DeformRow>,
    smooth_rows: Vec<SmoothRow>,
    angles: &[f64],
    t0: Instant,
) -> Result<Outcome, CliError> {
    let table = deform_table(&rows);
    let stable = smooth_table(&smooth_rows);
    let seconds = t0.elapsed().as_secs_f64();
    let md = markdown(&rows, &smooth_rows, angles, &files.names, seconds);
    files.put("report.md", md.as_bytes())?;
    let names = files.names.clone();
    files.staged.commit().map_err(|source| CliError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let report = DemoReport {
        command: "demo",
        out: dir.display().to_string(),
        deformation: rows,
        smoothing: smooth_rows,
        files: names,
        seconds,
    };
    Ok(Outcome {
        text: format!(
            "{table}\n{stable}\nwrote {} files to {} ({:.1} s); see {}",
            report.files.len(),
            report.out,
            seconds,
            dir.join("report.md").display()
        ),
        json: serde_json::to_value(&report)
            .unwrap_or_else(|e| serde_json::json!({ "error": e.to_string() })),
    })
}

/// One mesh's deformation cases: every angle × method, the pictures of the viscous mesh.
struct MeshCases<'c> {
    name: &'c str,
    mesh: &'c Su2Mesh,
    angles: &'c [f64],
    methods: &'c [(MoveMethod, &'c str)],
    bar: &'c indicatif::ProgressBar,
}

impl MeshCases<'_> {
    fn run(&self, files: &mut Files<'_>, rows: &mut Vec<DeformRow>) -> Result<(), CliError> {
        let (name, mesh) = (self.name, self.mesh);
        let mut buf = Vec::new();
        write_su2(mesh, &mut buf).map_err(|e| CliError::Invalid(e.to_string()))?;
        files.put(&format!("naca2412_{name}.su2"), &buf)?;
        let airfoil = mesh.marker("airfoil").map(|m| &m.elements);
        let farfield = mesh.marker("farfield").map(|m| &m.elements);
        let (Some(airfoil), Some(farfield)) = (airfoil, farfield) else {
            return Err(CliError::Invalid("generated mesh lacks its markers".into()));
        };
        if name == "viscous" {
            original_pictures(files, name, mesh, airfoil)?;
        }
        let max_angle = self.angles.iter().copied().fold(0.0, f64::max);
        let mut compare: Vec<Compared<'_>> = Vec::new();
        for &angle in self.angles {
            for &(method, mname) in self.methods {
                let (row, r, q) = one_case(mesh, airfoil, farfield, angle, method, mname)?;
                rows.push(DeformRow {
                    mesh: name.to_string(),
                    ..row
                });
                if name == "viscous" && angle == max_angle {
                    let case = (mname, angle);
                    let bad = worst_case_files(files, name, case, mesh, airfoil, &r, &q)?;
                    if matches!(mname, "quaternion" | "spring" | "angle-cg") {
                        compare.push((mname, r.deformed, bad));
                    }
                }
                self.bar.inc(1);
            }
        }
        if name == "viscous" {
            compare_panels(files, name, mesh, airfoil, &compare, max_angle)?;
        }
        Ok(())
    }
}

/// The undeformed viscous mesh: whole, airfoil, trailing edge.
fn original_pictures(
    files: &mut Files<'_>,
    name: &str,
    mesh: &Su2Mesh,
    airfoil: &CellList,
) -> Result<(), CliError> {
    let none = vec![false; mesh.elements.len()];
    let original = Picture {
        points: &mesh.points,
        cells: &mesh.elements,
        boundaries: &[airfoil],
        highlight: &none,
        title: &format!("NACA 2412 {name}: {} nodes", mesh.points.len()),
        shading: None,
    };
    files.picture(
        &format!("{name}_original_whole"),
        &original,
        bounding_window(&mesh.points),
    )?;
    files.picture(
        &format!("{name}_original_airfoil"),
        &original,
        [-0.2, -0.6, 1.2, 0.6],
    )?;
    files.picture(
        &format!("{name}_original_te"),
        &original,
        zoom([1.0, 0.0], 0.04),
    )
}

/// One method at one angle: the row (mesh name left empty), the result and its quality.
fn one_case(
    mesh: &Su2Mesh,
    airfoil: &CellList,
    farfield: &CellList,
    angle: f64,
    method: MoveMethod,
    mname: &str,
) -> Result<
    (
        DeformRow,
        crate::engine::MoveResult,
        crate::engine::QualitySummary,
    ),
    CliError,
> {
    let centre = deform_meshgen::AirfoilGrid::quarter_chord();
    let input = MoveInput {
        split: None,
        graph: None,
        dim: 2,
        points: &mesh.points,
        cells: &mesh.elements,
        moved: vec![airfoil],
        fixed: vec![farfield],
        motion: Motion::Rotate {
            degrees: angle,
            axis: [0.0, 0.0, 1.0],
            center: Some([centre[0], centre[1], 0.0]),
        },
        method,
        solver: MoveSolver::Cg,
        amg_strength: crate::engine::default_amg_strength(),
        tol: 1e-10,
        max_iter: if method == MoveMethod::AngleDirect {
            ANGLE_DIRECT_SWEEPS
        } else {
            20_000
        },
        idw_exponent: 2.0,
        stiffness: Stiffness::Batina,
        idw_fast: None,
        reach: None,
    };
    let t = Instant::now();
    let r = run_move(&input)?;
    let secs = t.elapsed().as_secs_f64();
    let q = quality(
        2,
        &mesh.elements,
        &r.deformed,
        Some(&mesh.points),
        Some(airfoil),
    )?;
    let row = DeformRow {
        mesh: String::new(),
        method: mname.to_string(),
        angle_deg: angle,
        iterations: r.iterations,
        converged: r.converged,
        inverted_cells: q.inverted_cells.unwrap_or(0),
        folded_cells: q.folded_cells,
        min_area_ratio: q.min_area_ratio,
        max_wall_angle_change_deg: q.max_wall_angle_change_deg,
        seconds: secs,
    };
    Ok((row, r, q))
}

/// The viscous mesh at the largest angle: pictures (whole, airfoil, trailing edge, wall) and
/// the `.vtu`; returns the inverted-or-folded flags.
fn worst_case_files(
    files: &mut Files<'_>,
    name: &str,
    (mname, angle): (&str, f64),
    mesh: &Su2Mesh,
    airfoil: &CellList,
    r: &crate::engine::MoveResult,
    q: &crate::engine::QualitySummary,
) -> Result<Vec<bool>, CliError> {
    let centre = deform_meshgen::AirfoilGrid::quarter_chord();
    let bad: Vec<bool> = q
        .inverted
        .iter()
        .zip(&q.scaled_jacobian)
        .map(|(&i, &j)| i || j <= 0.0)
        .collect();
    let title = format!(
        "{name}, {mname}, {angle} deg: {} inverted, {} folded (red)",
        q.inverted_cells.unwrap_or(0),
        q.folded_cells
    );
    let pic = Picture {
        points: &r.deformed,
        cells: &mesh.elements,
        boundaries: &[airfoil],
        highlight: &bad,
        title: &title,
        shading: None,
    };
    let te = rotate_about([1.0, 0.0], centre, angle);
    let stem = format!("{name}_{mname}_{angle}");
    files.picture(&format!("{stem}_whole"), &pic, bounding_window(&r.deformed))?;
    files.picture(&format!("{stem}_airfoil"), &pic, [-0.2, -0.6, 1.2, 0.6])?;
    files.picture(&format!("{stem}_te"), &pic, zoom(te, 0.04))?;
    let (wall, first) = wall_node_near(
        &r.deformed,
        &mesh.elements,
        airfoil,
        rotate_about([0.5, 0.07], centre, angle),
    );
    let wall_title =
        format!("{title}; first cells at the upper wall, x/c = 0.5 (first layer {first:.1e})");
    let wall_pic = Picture {
        title: &wall_title,
        ..pic
    };
    files.picture(&format!("{stem}_wall"), &wall_pic, zoom(wall, 8.0 * first))?;
    let disp: Vec<f64> = r.displacement.iter().flatten().copied().collect();
    let inverted: Vec<f64> = q.inverted.iter().map(|&b| f64::from(u8::from(b))).collect();
    let vtu = vtu_bytes(
        mesh,
        &r.deformed,
        &disp,
        &[
            VtkField {
                name: "scaled_jacobian",
                components: 1,
                values: &q.scaled_jacobian,
            },
            VtkField {
                name: "area_ratio",
                components: 1,
                values: &q.ratio,
            },
            VtkField {
                name: "inverted",
                components: 1,
                values: &inverted,
            },
        ],
    )?;
    files.put(&format!("{stem}.vtu"), &vtu)?;
    Ok(bad)
}

/// Side by side: the undeformed viscous mesh, then each compared method at the largest angle
/// (trailing edge and airfoil, SVG and PNG).
fn compare_panels(
    files: &mut Files<'_>,
    name: &str,
    mesh: &Su2Mesh,
    airfoil: &CellList,
    compare: &[Compared<'_>],
    max_angle: f64,
) -> Result<(), CliError> {
    let centre = deform_meshgen::AirfoilGrid::quarter_chord();
    let none = vec![false; mesh.elements.len()];
    let walls = [airfoil];
    let te = rotate_about([1.0, 0.0], centre, max_angle);
    let mut panels = vec![(
        Picture {
            points: &mesh.points,
            cells: &mesh.elements,
            boundaries: &walls,
            highlight: &none,
            title: "undeformed",
            shading: None,
        },
        zoom([1.0, 0.0], 0.04),
    )];
    let mut airfoil_panels = vec![(panels[0].0, [-0.2, -0.6, 1.2, 0.6])];
    for (m, pts, bad) in compare {
        let pic = Picture {
            points: pts,
            cells: &mesh.elements,
            boundaries: &walls,
            highlight: bad,
            title: m,
            shading: None,
        };
        panels.push((pic, zoom(te, 0.04)));
        airfoil_panels.push((pic, [-0.2, -0.6, 1.2, 0.6]));
    }
    let stem = format!("compare_{name}_{max_angle}");
    files.put(
        &format!("{stem}_te.svg"),
        svg_panels(&panels, 480).as_bytes(),
    )?;
    let bytes = png_panels(&panels, 480).map_err(CliError::Invalid)?;
    files.put(&format!("{stem}_te.png"), &bytes)?;
    files.put(
        &format!("{stem}_airfoil.svg"),
        svg_panels(&airfoil_panels, 480).as_bytes(),
    )?;
    let bytes = png_panels(&airfoil_panels, 480).map_err(CliError::Invalid)?;
    files.put(&format!("{stem}_airfoil.png"), &bytes)?;
    Ok(())
}

/// Alter's Taubin arclength smoothing on a noisy block and a cavity grid: the table rows,
/// pictures coloured by the spacing ratio (before and after on one scale) and `.vts` files.
fn smoothing_cases(
    quick: bool,
    files: &mut Files<'_>,
    bar: &indicatif::ProgressBar,
) -> Result<Vec<SmoothRow>, CliError> {
    let err = |e: deform_meshgen::MeshError| CliError::Invalid(e.to_string());
    let (nb, cav) = if quick {
        ([25, 13], [24, 9])
    } else {
        ([97, 49], [145, 61])
    };
    let noisy = deform_meshgen::noisy_block2(
        &deform_meshgen::BlockSpec {
            dims: [nb[0], nb[1], 1],
            lengths: [2.0, 1.0, 1.0],
            ratios: [1.0, 1.03, 1.0],
        },
        0.35,
        2412,
    )
    .map_err(err)?;
    let cavity = deform_meshgen::cavity2(cav[0], cav[1], 3.25).map_err(err)?;
    let cases: [SmoothCase<'_>; 3] = [
        (
            "noisy",
            &noisy,
            Direction::J,
            true,
            None,
            "j lines, normalized, 30 iterations",
        ),
        (
            "noisy",
            &noisy,
            Direction::I,
            true,
            Some(4),
            "i lines, normalized, 30 + 15 coarse (factor 4) iterations",
        ),
        (
            "cavity",
            &cavity,
            Direction::I,
            true,
            None,
            "i lines, normalized, 30 iterations",
        ),
    ];
    let mut smooth_rows = Vec::new();
    for (k, case) in cases.iter().enumerate() {
        smooth_rows.push(smooth_case(files, k, case)?);
        bar.inc(1);
    }
    Ok(smooth_rows)
}

/// One smoothing case (`k`: its index; the second repeats the first's grid).
fn smooth_case(
    files: &mut Files<'_>,
    k: usize,
    case: &SmoothCase<'_>,
) -> Result<SmoothRow, CliError> {
    let (gname, m, direction, normalized, coarse, settings) = case;
    let Some(dims) = m.dims else {
        return Err(CliError::Invalid("generated grid is not structured".into()));
    };
    let before: Vec<[f64; 3]> = m.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let mut after = before.clone();
    let r = smooth_block(
        2,
        dims,
        &mut after,
        *direction,
        (*normalized, false),
        30,
        0.330,
        -0.334,
        *coarse,
        None,
    )?;
    let cells = structured_cells(dims, &after, 2);
    let q = quality(2, &cells, &after, Some(&before), None)?;
    let row = SmoothRow {
        grid: gname.to_string(),
        settings: settings.to_string(),
        iterations: r.iterations,
        max_stretching_before: r.max_stretching_before,
        max_stretching_after: r.max_stretching_after,
        max_point_move: r.max_point_move,
        folded_cells: q.folded_cells,
    };
    let none = vec![false; cells.len()];
    let empty: [&CellList; 0] = [];
    let stem = format!("smooth{}_{gname}", k + 1);
    let line = ["i", "j"].get(direction.index()).copied().unwrap_or("k");
    let label = format!("spacing ratio along {line} lines");
    let ratios_before = cell_spacing_ratios(dims, &before, direction.index());
    let top = ratios_before.iter().copied().fold(1.0, f64::max);
    for (tag, pts) in [("before", &before), ("after", &after)] {
        if k == 1 && tag == "before" {
            continue; // same grid as case 1
        }
        let ratios = cell_spacing_ratios(dims, pts, direction.index());
        let title = format!("{gname} grid {tag}: {settings}; colour: {label}");
        let pic = Picture {
            points: pts,
            cells: &cells,
            boundaries: &empty,
            highlight: &none,
            title: &title,
            shading: Some(Shading {
                values: &ratios,
                range: [1.0, top],
                label: &label,
            }),
        };
        // Room below the grid for the colour bar.
        let mut window = bounding_window(pts);
        window[1] -= 0.25 * (window[3] - window[1]);
        files.picture(&format!("{stem}_{tag}"), &pic, window)?;
        let mut v = Vec::new();
        write_vts(&mut v, dims, pts, &[], &[], VtkEncoding::Base64)
            .map_err(|e| CliError::Invalid(e.to_string()))?;
        files.put(&format!("{stem}_{tag}.vts"), &v)?;
    }
    Ok(row)
}

fn opt(v: Option<f64>, prec: usize) -> String {
    v.map_or_else(|| "-".into(), |x| format!("{x:.prec$}"))
}

fn deform_table(rows: &[DeformRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| mesh | method | angle (deg) | iterations | converged | inverted | folded | min area ratio | max wall angle change (deg) | seconds |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|:---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} |",
            r.mesh,
            r.method,
            r.angle_deg,
            r.iterations,
            if r.converged { "yes" } else { "**no**" },
            r.inverted_cells,
            r.folded_cells,
            opt(r.min_area_ratio, 4),
            opt(r.max_wall_angle_change_deg, 3),
            r.seconds
        );
    }
    s
}

fn smooth_table(rows: &[SmoothRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| grid | settings | iterations | max stretching before | after | max point move | folded cells |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.4} | {:.4} | {:.3e} | {} |",
            r.grid,
            r.settings,
            r.iterations,
            r.max_stretching_before,
            r.max_stretching_after,
            r.max_point_move,
            r.folded_cells
        );
    }
    s
}

fn markdown(
    rows: &[DeformRow],
    smooth: &[SmoothRow],
    angles: &[f64],
    files: &[String],
    seconds: f64,
) -> String {
    let max_angle = angles.iter().copied().fold(0.0, f64::max);
    let mut s = String::new();
    let _ = writeln!(s, "# deform demo\n");
    let _ = writeln!(
        s,
        "Generated by `deform demo` in {seconds:.1} s. NACA 2412 meshes (inviscid: triangles; viscous: split-quad hybrid; ogrid: structured quads) pitched counter-clockwise (nose down) about the quarter chord with the far field fixed, deformed by Samareh's quaternion method (spring or inverse-distance propagation), Batina's linear springs, and Yang & Özgen's angle-inclusion springs (direct Gauss–Seidel and CG). Quality is measured against the undeformed mesh: *inverted* = signed area changed sign, *folded* = some corner Jacobian < 0 relative to the cell's own orientation or overlapping a neighbour, *wall angle change* = change of the first grid-line angle at the airfoil. The demo writes every result, folded or not, to compare the methods; `deform move` refuses a result with new inverted or folded cells (exit 4) unless given `--allow-folds`, and an unconverged solve (exit 5) unless given `--allow-unconverged`.\n"
    );
    let _ = writeln!(s, "## Deformation\n\n{}", deform_table(rows));
    let _ = writeln!(
        s,
        "angle-direct (Yang & Özgen's node-wise direct method, Gauss–Seidel order over-relaxed, ω = 2/(1 + 1.5/√n), about 1.97 here) is capped at {ANGLE_DIRECT_SWEEPS} sweeps to keep the demo short; a capped run is marked **no** under *converged*. angle-cg solves the same equations with conjugate gradients.\n"
    );
    let _ = writeln!(
        s,
        "## Pictures (viscous mesh, {max_angle}°; inverted/folded cells in red)\n"
    );
    let _ = writeln!(
        s,
        "Trailing edge, left to right: undeformed, quaternion, linear springs, angle springs (CG):\n\n![comparison](compare_viscous_{max_angle}_te.png)\n\n![comparison, airfoil](compare_viscous_{max_angle}_airfoil.png)\n"
    );
    let _ = writeln!(s, "Undeformed: ![undeformed](viscous_original_airfoil.png) ![trailing edge](viscous_original_te.png)\n");
    for (_, m) in METHODS {
        let stem = format!("viscous_{m}_{max_angle}");
        if files.iter().any(|f| f == &format!("{stem}_te.png")) {
            let _ = writeln!(
                s,
                "**{m}**: ![{m} airfoil]({stem}_airfoil.png) ![{m} trailing edge]({stem}_te.png) ![{m} wall]({stem}_wall.png)\n"
            );
        }
    }
    let _ = writeln!(
        s,
        "## Smoothing (Alter: Taubin λ = 0.330, μ = −0.334 on the arclength along one family of grid lines)\n\n{}",
        smooth_table(smooth)
    );
    for f in files
        .iter()
        .filter(|f| f.starts_with("smooth") && f.ends_with(".png"))
    {
        let _ = writeln!(s, "![{f}]({f})");
    }
    let _ = writeln!(
        s,
        "\nVTK files (`.vtu`, `.vts`) open in ParaView with displacement and per-cell quality fields."
    );
    s
}
