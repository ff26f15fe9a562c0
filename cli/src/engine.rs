//! The one place that calls deform-kernel (through its public API): graphs, quality, and the
//! deformation and smoothing runs. Everything here takes the file-level types (`[f64; 3]`
//! points, [`CellList`]) and converts to the kernel's `[T; D]` views.

use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Direction, Directions, Graph};
use serde::Serialize;

use crate::error::CliError;
use crate::formats::CellList;
use crate::orientation::{Orientation, OrientationSummary};

mod compare;
mod elasticity;
pub(crate) mod rbf;
mod tfi_sensitivity;
pub use elasticity::{cell_pair_graph, run_elasticity};
pub use rbf::{RbfFunction, RbfInfo, RbfSettings};
pub use tfi_sensitivity::{tfi_block_adjoint, tfi_block_tangent, tfi_wall_nodes};

fn kernel(context: &str) -> impl Fn(deform_kernel::Error) -> CliError + '_ {
    move |source| CliError::Kernel {
        context: context.to_string(),
        source,
    }
}

/// A validated kernel [`Cells`] view of a [`CellList`].
pub fn cells_view<'a>(cells: &'a CellList, node_count: usize) -> Result<Cells<'a>, CliError> {
    Cells::new(node_count, &cells.offsets, &cells.nodes, &cells.kinds).map_err(kernel("cells"))
}

/// An owned CSR edge graph.
#[derive(Clone, Debug, Default)]
pub struct OwnedGraph {
    /// `n + 1` offsets.
    pub offsets: Vec<u32>,
    /// Neighbours.
    pub targets: Vec<u32>,
}

impl OwnedGraph {
    /// The kernel view.
    pub fn view(&self) -> Result<Graph<'_>, CliError> {
        Graph::new(&self.offsets, &self.targets).map_err(kernel("graph"))
    }
}

/// The edge graph of a mesh (with quadrilateral face diagonals when `diagonals`).
pub fn edge_graph(cells: &Cells<'_>, diagonals: bool) -> Result<OwnedGraph, CliError> {
    let mut offsets = vec![0u32; cells.node_count() + 1];
    let mut targets = vec![0u32; graph_from_cells_len(cells, diagonals)];
    let used =
        graph_from_cells(cells, diagonals, &mut offsets, &mut targets).map_err(kernel("graph"))?;
    targets.truncate(used);
    Ok(OwnedGraph { offsets, targets })
}

/// `[f64; 3]` points as `[f64; D]`.
pub fn points_d<const D: usize>(points: &[[f64; 3]]) -> Vec<[f64; D]> {
    points
        .iter()
        .map(|p| {
            let mut q = [0.0; D];
            for (s, &x) in q.iter_mut().zip(p) {
                *s = x;
            }
            q
        })
        .collect()
}

/// The quality table of a mesh, optionally against its undeformed reference.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct QualitySummary {
    /// Number of cells.
    pub cells: usize,
    /// Cells whose signed measure changed sign against the reference (`None` without one).
    pub inverted_cells: Option<usize>,
    /// Cells with some corner Jacobian < 0 relative to their region's orientation (see
    /// [`crate::orientation`]): a valid mesh has 0 whichever way its cells turn.
    pub folded_cells: usize,
    /// Cells with no negative but some zero corner Jacobian (a collapsed edge, e.g. on a
    /// singular axis): degenerate, not folded.
    pub degenerate_cells: usize,
    /// Cells with signed measure ≤ 0 relative to their region's orientation.
    pub nonpositive_cells: usize,
    /// Which way the mesh's connected regions turn (decided on the reference mesh).
    pub orientation: OrientationSummary,
    /// Smallest signed measure relative to the region's orientation (area in 2D, volume in
    /// 3D).
    pub min_measure: f64,
    /// Smallest scaled corner Jacobian (sine of the worst corner angle in 2D).
    pub min_scaled_jacobian: f64,
    /// Smallest deformed/reference measure ratio.
    pub min_area_ratio: Option<f64>,
    /// Largest deformed/reference measure ratio.
    pub max_area_ratio: Option<f64>,
    /// Largest change of the first grid-line angle at the wall, degrees.
    pub max_wall_angle_change_deg: Option<f64>,
    /// Per-cell signed measure relative to the region's orientation (for VTK output; not
    /// serialised).
    #[serde(skip)]
    pub measure: Vec<f64>,
    /// Per-cell smallest scaled Jacobian (for VTK output; not serialised).
    #[serde(skip)]
    pub scaled_jacobian: Vec<f64>,
    /// Per-cell measure ratio deformed/reference (empty without a reference; 0/0 gives NaN).
    #[serde(skip)]
    pub ratio: Vec<f64>,
    /// Per cell: the signed measure changed sign against the reference.
    #[serde(skip)]
    pub inverted: Vec<bool>,
    /// Per cell: folded (a corner against the cell's own reference orientation, or overlapping
    /// a neighbour; see [`crate::validity`]).
    #[serde(skip)]
    pub folded: Vec<bool>,
    /// Per cell: folded already in the reference mesh.
    #[serde(skip)]
    pub reference_folded: Vec<bool>,
    /// The faces (edges in 2D) that belong to one cell only, as node cycles in key order:
    /// [`crate::validity::boundary_faces`], found by the same face sort as the overlaps.
    #[serde(skip)]
    pub boundary_faces: Vec<Vec<u32>>,
}

impl QualitySummary {
    /// Cells inverted or folded in this mesh that were valid in the reference: what the
    /// failure policy of `move` and `smooth` refuses without `--allow-folds`.
    pub fn new_failures(&self) -> usize {
        (0..self.folded.len())
            .filter(|&c| {
                let bad = self.folded[c] || self.inverted.get(c).copied().unwrap_or(false);
                bad && !self.reference_folded.get(c).copied().unwrap_or(false)
            })
            .count()
    }
}

/// Computes the quality table. `wall` (boundary elements) is used only with a reference.
pub fn quality(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
    reference: Option<&[[f64; 3]]>,
    wall: Option<&CellList>,
) -> Result<QualitySummary, CliError> {
    quality_with_graph(dim, cells, points, reference, wall, None)
}

/// [`quality`], with the cells' edge graph (no face diagonals, [`edge_graph`]) when the
/// caller has it, so that the wall angles do not build it again.
pub fn quality_with_graph(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
    reference: Option<&[[f64; 3]]>,
    wall: Option<&CellList>,
    graph: Option<&OwnedGraph>,
) -> Result<QualitySummary, CliError> {
    quality_prepared(dim, cells, points, reference, None, wall, graph)
}

/// The reference mesh's half of the quality table (each cell's own orientation, overlaps,
/// boundary faces, regions): it does not depend on the deformation, so `deform move` prepares
/// it while the solve runs ([`quality_prepared`]).
pub struct PreparedReference(Reference);

/// [`PreparedReference`] of the mesh `cells` at `points`.
pub fn prepare_reference(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
) -> Result<PreparedReference, CliError> {
    fn run<const D: usize>(cells: &CellList, points: &[[f64; 3]]) -> Result<Reference, CliError> {
        let view = cells_view(cells, points.len())?;
        reference_cells(cells, &view, &points_d::<D>(points))
    }
    match dim {
        2 => run::<2>(cells, points).map(PreparedReference),
        3 => run::<3>(cells, points).map(PreparedReference),
        _ => Err(CliError::Invalid(format!("dimension {dim} is not 2 or 3"))),
    }
}

/// [`quality_with_graph`] with the reference's half already prepared (by
/// [`prepare_reference`] on `reference`, or on `points` without one): the same table.
pub fn quality_prepared(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
    reference: Option<&[[f64; 3]]>,
    prepared: Option<PreparedReference>,
    wall: Option<&CellList>,
    graph: Option<&OwnedGraph>,
) -> Result<QualitySummary, CliError> {
    let wall = wall.map(|w| (w, graph));
    let prepared = prepared.map(|p| p.0);
    match dim {
        2 => quality_d::<2>(cells, points, reference, prepared, wall),
        3 => quality_d::<3>(cells, points, reference, prepared, wall),
        _ => Err(CliError::Invalid(format!("dimension {dim} is not 2 or 3"))),
    }
}

/// Wall elements, with the cells' edge graph when the caller has one.
type WallInput<'w> = Option<(&'w CellList, Option<&'w OwnedGraph>)>;

/// Per-cell measure, smallest scaled and unscaled corner Jacobian, each relative to the cell's
/// own orientation in the reference mesh (`negative[c]`: negated, exactly, by evaluating the
/// cell on the points mirrored in `x`).
struct Relative {
    measure: Vec<f64>,
    scaled: Vec<f64>,
    corner: Vec<f64>,
}

/// Per-cell signed measure and smallest corner Jacobians as the cells are listed.
fn qualities<const D: usize>(view: &Cells<'_>, p: &[[f64; D]]) -> Result<Relative, CliError> {
    let mut r = Relative {
        measure: vec![0.0; view.len()],
        scaled: vec![0.0; view.len()],
        corner: vec![0.0; view.len()],
    };
    deform_kernel::quality::cell_qualities(view, p, &mut r.measure, &mut r.corner, &mut r.scaled)
        .map_err(kernel("quality"))?;
    Ok(r)
}

/// The cells measured relative to their own orientation, from their [`qualities`] at `pts`: the `negative` cells re-evaluated on
/// the mirrored points.
fn mirror_negative<const D: usize>(
    view: &Cells<'_>,
    pts: &[[f64; D]],
    negative: &[bool],
    mut out: Relative,
) -> Result<Relative, CliError> {
    if negative.iter().any(|&n| n) {
        let mirrored: Vec<[f64; D]> = pts
            .iter()
            .map(|p| {
                let mut q = *p;
                q[0] = -q[0];
                q
            })
            .collect();
        let m = qualities(view, &mirrored)?;
        for (c, _) in negative.iter().enumerate().filter(|(_, &n)| n) {
            out.measure[c] = m.measure[c];
            out.scaled[c] = m.scaled[c];
            out.corner[c] = m.corner[c];
        }
    }
    Ok(out)
}

/// The reference mesh seen cell by cell: each cell's own orientation, the cells that overlap a
/// neighbour (see [`crate::validity`]), and the regions' orientation.
struct Reference {
    /// Per cell: negative signed measure in the reference (listed clockwise / mirrored).
    negative: Vec<bool>,
    /// Per cell: overlaps a neighbour and is blamed for it.
    overlap: Vec<bool>,
    /// The mesh's boundary faces ([`crate::validity::boundary_faces`]).
    boundary: Vec<Vec<u32>>,
    /// The reference measured relative to each cell's own orientation.
    rel: Relative,
    /// The reference's signed measures as the cells are listed.
    listed: Vec<f64>,
    orientation: Orientation,
}

fn reference_cells<const D: usize>(
    cells: &CellList,
    view: &Cells<'_>,
    undeformed: &[[f64; D]],
) -> Result<Reference, CliError> {
    // The measures as listed (`cell_measures`' bits) come with the qualities: one evaluation.
    let listed = qualities(view, undeformed)?;
    let measure = listed.measure.clone();
    let negative: Vec<bool> = measure.iter().map(|&m| m < 0.0).collect();
    let orientation = Orientation::of(cells, undeformed.len(), &measure);
    let rel = mirror_negative(view, undeformed, &negative, listed)?;
    // The outward direction is known only for cells whose corners agree and whose measure is
    // not 0.
    let sense: Vec<i8> = measure
        .iter()
        .zip(&rel.corner)
        .map(|(&m, &j)| {
            if j < 0.0 || m == 0.0 {
                0
            } else if m > 0.0 {
                1
            } else {
                -1
            }
        })
        .collect();
    let against = orientation.against(cells, &measure);
    let (overlap, boundary) = crate::validity::overlapping_and_boundary(cells, &sense, &against);
    Ok(Reference {
        negative,
        overlap,
        boundary,
        rel,
        listed: measure,
        orientation,
    })
}

/// Per cell: valid but listed clockwise (2D) or mirrored (3D), against the SU2/VTK convention
/// (what `deform convert --reorient` rewrites).
pub fn reversed_cells(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
) -> Result<Vec<bool>, CliError> {
    fn run<const D: usize>(cells: &CellList, points: &[[f64; 3]]) -> Result<Vec<bool>, CliError> {
        let view = cells_view(cells, points.len())?;
        let r = reference_cells(cells, &view, &points_d::<D>(points))?;
        Ok((0..view.len())
            .map(|c| r.negative[c] && !(r.rel.corner[c] < 0.0 || r.overlap[c]))
            .collect())
    }
    match dim {
        2 => run::<2>(cells, points),
        3 => run::<3>(cells, points),
        _ => Err(CliError::Invalid(format!("dimension {dim} is not 2 or 3"))),
    }
}

/// Per cell: the measure ratio after/before (0/0 gives NaN) and whether the sign changed.
fn ratios_and_inversions(before: &[f64], after: &[f64]) -> (Vec<f64>, Vec<bool>) {
    before
        .iter()
        .zip(after)
        .map(|(&b, &a)| (a / b, (b > 0.0 && a <= 0.0) || (b < 0.0 && a >= 0.0)))
        .unzip()
}

/// The reference's half (`prepared`, or computed here) and the deformed cells' qualities as
/// listed; the latter do not depend on the former, so without `prepared` they run alongside.
fn both_halves<const D: usize>(
    cells: &CellList,
    view: &Cells<'_>,
    undeformed: &[[f64; D]],
    deformed: &[[f64; D]],
    prepared: Option<Reference>,
) -> Result<(Reference, Relative), CliError> {
    let (base, listed) = match prepared {
        Some(base) => (Ok(base), qualities(view, deformed)),
        None => std::thread::scope(|s| {
            let listed = s.spawn(|| qualities(view, deformed));
            let base = reference_cells(cells, view, undeformed);
            let listed = listed
                .join()
                .unwrap_or_else(|p| std::panic::resume_unwind(p));
            (base, listed)
        }),
    };
    Ok((base?, listed?))
}

/// Inversions and measure ratios on the canonical points `[undeformed, deformed]`: with every
/// region positive those are the input's points, whose measures are at hand (the reference's
/// in `base`, the deformed cells' `listed`); otherwise the canonical cells are measured.
fn canonical_ratios<const D: usize>(
    view: &Cells<'_>,
    base: &Reference,
    listed: &[f64],
    [undeformed, deformed]: [&[[f64; D]]; 2],
) -> Result<compare::MeasureRatios, CliError> {
    if base.orientation.all_positive() {
        return Ok(compare::measure_ratios(&base.listed, listed));
    }
    let before = compare::measures(view, undeformed)?;
    Ok(compare::measure_ratios(
        &before,
        &compare::measures(view, deformed)?,
    ))
}

fn quality_d<const D: usize>(
    cells: &CellList,
    points: &[[f64; 3]],
    reference: Option<&[[f64; 3]]>,
    prepared: Option<Reference>,
    wall: WallInput<'_>,
) -> Result<QualitySummary, CliError> {
    let n = points.len();
    let view = cells_view(cells, n)?;
    if let Some(r) = reference.filter(|r| r.len() != n) {
        return Err(CliError::Invalid(format!(
            "the reference has {} points, the mesh {n}",
            r.len()
        )));
    }
    let input_undeformed = points_d::<D>(reference.unwrap_or(points));
    let input_deformed = points_d::<D>(points);
    let (base, listed) = both_halves(cells, &view, &input_undeformed, &input_deformed, prepared)?;
    let listed_deformed = listed.measure.clone();
    let rel = mirror_negative(&view, &input_deformed, &base.negative, listed)?;
    // Ratios, inversions and wall angles on canonical coordinates (negative regions mirrored):
    // the same numbers as on the input's, angles measured the same way in every region.
    let undeformed = base.orientation.canonical(&input_undeformed);
    let pts = base.orientation.canonical(&input_deformed);
    let wall = wall.filter(|(w, _)| reference.is_some() && !w.is_empty());
    let r = canonical_ratios(&view, &base, &listed_deformed, [&undeformed, &pts])?;
    let wall_change = compare::wall_angles(&view, &undeformed, &pts, wall)?;
    let has_ref = reference.is_some();
    let folded_in = |corner: &[f64]| -> Vec<bool> {
        corner
            .iter()
            .zip(&base.overlap)
            .map(|(&j, &o)| j < 0.0 || o)
            .collect()
    };
    let reference_folded = folded_in(&base.rel.corner);
    let folded = folded_in(&rel.corner);
    let mut orientation = base.orientation.summary.clone();
    orientation.cells_listed_reversed = base
        .negative
        .iter()
        .zip(&reference_folded)
        .filter(|(&neg, &f)| neg && !f)
        .count();
    let (ratio, inverted) = if has_ref {
        ratios_and_inversions(&base.rel.measure, &rel.measure)
    } else {
        (Vec::new(), Vec::new())
    };
    let finite = |x: f64| has_ref.then_some(x).filter(|x| x.is_finite());
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    Ok(QualitySummary {
        cells: view.len(),
        inverted_cells: has_ref.then_some(r.inverted_cells),
        folded_cells: folded.iter().filter(|&&f| f).count(),
        degenerate_cells: folded
            .iter()
            .zip(&rel.corner)
            .filter(|(&f, &j)| !f && j == 0.0)
            .count(),
        orientation,
        nonpositive_cells: rel.measure.iter().filter(|&&m| m <= 0.0).count(),
        min_measure: min(&rel.measure),
        min_scaled_jacobian: min(&rel.scaled),
        min_area_ratio: finite(r.min_measure_ratio),
        max_area_ratio: finite(r.max_measure_ratio),
        max_wall_angle_change_deg: wall_change.map(|w| w.max_change.to_degrees()),
        measure: rel.measure,
        scaled_jacobian: rel.scaled,
        ratio,
        inverted,
        folded,
        reference_folded,
        boundary_faces: base.boundary,
    })
}

/// Quads (2D) or hexes (3D) of a structured block `[ni, nj, nk]`, oriented so that the block's
/// total signed measure is positive (left-handed blocks are renumbered cell by cell).
pub fn structured_cells(dims: [usize; 3], points: &[[f64; 3]], dim: usize) -> CellList {
    let [ni, nj, nk] = dims;
    let id = |i: usize, j: usize, k: usize| (i + ni * (j + nj * k)) as u32;
    let mut cells = CellList::new();
    let p = |n: u32| points.get(n as usize).copied().unwrap_or([0.0; 3]);
    if dim == 2 || nk == 1 {
        let mut area = 0.0;
        let mut quads = Vec::new();
        for j in 0..nj.saturating_sub(1) {
            for i in 0..ni.saturating_sub(1) {
                let q = [
                    id(i, j, 0),
                    id(i + 1, j, 0),
                    id(i + 1, j + 1, 0),
                    id(i, j + 1, 0),
                ];
                let (a, b, c, d) = (p(q[0]), p(q[1]), p(q[2]), p(q[3]));
                area += (c[0] - a[0]) * (d[1] - b[1]) - (c[1] - a[1]) * (d[0] - b[0]);
                quads.push(q);
            }
        }
        for q in quads {
            let q = if area < 0.0 {
                [q[0], q[3], q[2], q[1]]
            } else {
                q
            };
            cells.push(deform_kernel::CellKind::Quad, &q);
        }
    } else {
        let mut vol = 0.0;
        let mut hexes = Vec::new();
        for k in 0..nk.saturating_sub(1) {
            for j in 0..nj.saturating_sub(1) {
                for i in 0..ni.saturating_sub(1) {
                    let h = [
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ];
                    // Sign of the volume from the main diagonal triple product.
                    let (o, a, b, c) = (p(h[0]), p(h[1]), p(h[3]), p(h[4]));
                    let u = [a[0] - o[0], a[1] - o[1], a[2] - o[2]];
                    let v = [b[0] - o[0], b[1] - o[1], b[2] - o[2]];
                    let w = [c[0] - o[0], c[1] - o[1], c[2] - o[2]];
                    vol += u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                        + u[2] * (v[0] * w[1] - v[1] * w[0]);
                    hexes.push(h);
                }
            }
        }
        for h in hexes {
            let h = if vol < 0.0 {
                [h[4], h[5], h[6], h[7], h[0], h[1], h[2], h[3]]
            } else {
                h
            };
            cells.push(deform_kernel::CellKind::Hexahedron, &h);
        }
    }
    cells
}

pub use crate::motion::Motion;

/// The propagation method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveMethod {
    /// Samareh quaternions propagated by linear springs.
    Quaternion,
    /// Samareh quaternions propagated by inverse distance weighting.
    Idw,
    /// Batina linear springs on the displacements.
    Spring,
    /// Yang & Özgen angle-inclusion springs, node-wise direct solve.
    AngleDirect,
    /// Yang & Özgen angle-inclusion springs, conjugate gradients.
    AngleCg,
    /// Radial basis functions on the displacements (`engine/rbf.rs`).
    Rbf(RbfSettings),
}

/// Over-relaxation factor of `--method angle-direct` (default solver, block SOR over the
/// nodes) for a mesh of `n` nodes in `dim` dimensions: `ω = 2 / (1 + 1.5 h)`, `h = n^(−1/dim)`
/// (SOR's optimal factor is `1 − O(h)`). The constant 1.5 was fitted on NACA 2412 meshes
/// (`cargo run --release -p deform-host-tests --example perf_loops -- angle-sor more`, 15°
/// pitch, tol 1e-10): the best ω was 1.85 at 384 nodes, 1.97 at 9–10k (1179, 802 and 808
/// sweeps on the three `deform demo` meshes, where plain Gauss–Seidel stops unconverged at
/// the 3000-sweep cap), 1.98 at 20k. Not calibrated on 3D meshes.
pub fn angle_direct_omega(n: usize, dim: usize) -> f64 {
    let h = (n.max(1) as f64).powf(-1.0 / dim.max(1) as f64);
    2.0 / (1.0 + 1.5 * h)
}

/// Linear solver for the spring systems.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveSolver {
    /// Conjugate gradients preconditioned by smoothed-aggregation algebraic multigrid.
    Amg,
    /// Jacobi-preconditioned conjugate gradients.
    Cg,
    /// SSOR-preconditioned conjugate gradients (ω = 1.5).
    CgSsor,
    /// Gauss–Seidel.
    GaussSeidel,
    /// Jacobi.
    Jacobi,
}

/// Inputs of a mesh motion.
#[derive(Clone, Debug)]
pub struct MoveInput<'a> {
    /// 2 or 3.
    pub dim: usize,
    /// Undeformed points.
    pub points: &'a [[f64; 3]],
    /// Volume cells.
    pub cells: &'a CellList,
    /// Boundary elements of the moved markers.
    pub moved: Vec<&'a CellList>,
    /// Boundary elements of the markers that stay put.
    pub fixed: Vec<&'a CellList>,
    /// The motion of the moved markers.
    pub motion: Motion,
    /// Method.
    pub method: MoveMethod,
    /// Solver (spring-based methods).
    pub solver: MoveSolver,
    /// Multigrid strength threshold θ (`MoveSolver::Amg`; 0 is the kernel's default).
    pub amg_strength: f64,
    /// Relative residual tolerance.
    pub tol: f64,
    /// Iteration cap.
    pub max_iter: usize,
    /// Inverse-distance exponent (IDW).
    pub idw_exponent: f64,
    /// Spring stiffness (spring, angle-spring and quaternion-spring methods).
    pub stiffness: Stiffness,
    /// `--method idw` with the fast tree-based propagation: `(θ, tolerance)` (`None`: exact).
    pub idw_fast: Option<(f64, f64)>,
    /// Quaternion and IDW methods: no motion beyond this distance from the moved markers
    /// (`None`: the propagation's own reach).
    pub reach: Option<f64>,
    /// The spring solves' rows split across processes (`mpirun`; `None`: this process
    /// alone). The result is bit-identical either way.
    pub split: Option<&'a dyn crate::split::Splitter>,
    /// The edge graph of `cells` (no face diagonals) when the caller has it (renumbering
    /// builds one; steps share one); `None`: built here. The same graph either way.
    pub graph: Option<&'a OwnedGraph>,
}

/// `solver` with its rows split over `split`'s processes (unchanged when `None`).
fn split_solver<'a>(
    solver: deform_kernel::spring::LinearSolver<'a, f64>,
    split: Option<&'a dyn deform_kernel::spring::Collective<f64>>,
) -> deform_kernel::spring::LinearSolver<'a, f64> {
    use deform_kernel::spring::LinearSolver;
    match (solver, split) {
        (LinearSolver::Method(m), Some(c)) => LinearSolver::Distributed(m, c),
        (LinearSolver::Amg(h), Some(c)) => LinearSolver::DistributedAmg(h, c),
        (s, _) => s,
    }
}

/// How stiff each spring is (`deform move --stiffness`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stiffness {
    /// Batina's `1 / L` (the papers' choice).
    #[default]
    Batina,
    /// `1 / L` times the mean of the two nodes' `d̄ / d` (distance to the moved markers), as
    /// SU2's `WALL_DISTANCE`: cells near the moving wall move almost rigidly with it.
    WallDistance,
    /// `1 / L` times the mean of the two nodes' `V̄ / V` (dual volume), as SU2's
    /// `INVERSE_VOLUME`: small cells are stiffer.
    InverseVolume,
}

/// The stiffness of every directed edge of `g` for the chosen [`Stiffness`]; `walls` are the
/// nodes the wall distance is measured to.
fn spring_stiffness<const D: usize>(
    g: &deform_kernel::Graph<'_>,
    cells: &Cells<'_>,
    pts: &[[f64; D]],
    walls: &[u32],
    choice: Stiffness,
) -> Result<Vec<f64>, CliError> {
    use deform_kernel::spring::{
        dual_volumes, inverse_volume_factors, scale_stiffness, wall_distance_factors,
        wall_distances,
    };
    let mut k = vec![0.0; g.edge_count()];
    deform_kernel::spring::batina_stiffness(g, pts, 1.0, &mut k).map_err(kernel("stiffness"))?;
    let mut factors = vec![0.0; pts.len()];
    match choice {
        Stiffness::Batina => return Ok(k),
        Stiffness::WallDistance => {
            wall_distances(pts, walls, &mut factors).map_err(kernel("wall distances"))?;
            wall_distance_factors(&mut factors, 1.0).map_err(kernel("wall distances"))?;
        }
        Stiffness::InverseVolume => {
            let mut measures = vec![0.0; cells.len()];
            dual_volumes(cells, pts, &mut factors, &mut measures)
                .map_err(kernel("dual volumes"))?;
            inverse_volume_factors(&mut factors, 1.0).map_err(kernel("dual volumes"))?;
        }
    }
    scale_stiffness(g, &factors, &mut k).map_err(kernel("stiffness"))?;
    Ok(k)
}

/// Result of a mesh motion.
#[derive(Clone, Debug)]
pub struct MoveResult {
    /// The largest per-point error bound of the fast IDW (relative to the spread of the
    /// boundary motion; `None` when the exact propagation ran).
    pub idw_max_bound: Option<f64>,
    /// What the RBF fit did (`--method rbf`; the last step's with `--steps`).
    pub rbf: Option<RbfInfo>,
    /// Deformed points.
    pub deformed: Vec<[f64; 3]>,
    /// Displacement of every point.
    pub displacement: Vec<[f64; 3]>,
    /// Solver iterations (0 for IDW).
    pub iterations: usize,
    /// Final relative residual (0 for IDW).
    pub residual: f64,
    /// Whether the solver converged (true for IDW).
    pub converged: bool,
    /// Nodes on the moved markers.
    pub moved_nodes: usize,
    /// Boundary nodes held fixed.
    pub fixed_nodes: usize,
    /// Rotation centre used, when rotating.
    pub center: Option<[f64; 3]>,
    /// Nodes sliding on a plane or on the line where two sliding planes meet (`--slide`).
    pub sliding_nodes: usize,
    /// Largest distance of a sliding node from its plane(s) after the motion, measured from
    /// the written coordinates (0 without `--slide`).
    pub max_slide_offset: f64,
    /// The mesh's edge graph (no face diagonals) in the input's numbering, when the run built
    /// it: the quality pass's wall angles use it instead of building it again.
    pub graph: Option<OwnedGraph>,
}

/// A marker whose nodes slide on the plane (a line in 2D) fitted to them (`deform move
/// --slide`).
#[derive(Clone, Copy, Debug)]
pub struct SlideMarker<'a> {
    /// The marker's name (for messages).
    pub name: &'a str,
    /// Its boundary elements.
    pub elements: &'a CellList,
}

/// How far a `--slide` marker's nodes may be from their least-squares plane: this fraction
/// of the marker's size (the largest node distance from its centroid).
pub const SLIDE_PLANE_TOLERANCE: f64 = 1e-6;

/// The per-node constraint table of the sliding markers: kinds, directions, the normals of
/// each sliding node's planes (for the offset check), and the nodes pinned because they lie
/// on too many planes (3D: three or more; 2D: two) and are not on a moved or fixed marker.
struct SlideTable<const D: usize> {
    kinds: Vec<u8>,
    directions: Vec<[f64; D]>,
    planes: Vec<(u32, [f64; D])>,
    pinned: Vec<u32>,
    sliding: usize,
}

fn slide_table<const D: usize>(
    pts: &[[f64; D]],
    boundary: &[u32],
    sliding: &[SlideMarker<'_>],
) -> Result<SlideTable<D>, CliError> {
    use deform_kernel::spring::constraints::{fit_plane, NodeKind};
    let n = pts.len();
    let mut normals: Vec<Vec<[f64; D]>> = vec![Vec::new(); n];
    for m in sliding {
        let nodes = sorted_nodes(&[m.elements]);
        if let Some(&bad) = nodes.iter().find(|&&b| b as usize >= n) {
            return Err(CliError::Invalid(format!(
                "--slide {}: marker node {bad} is not a mesh node",
                m.name
            )));
        }
        let fit = fit_plane(pts, &nodes, f64::INFINITY)
            .map_err(|e| CliError::Invalid(format!("--slide {}: {e}", m.name)))?;
        if fit.residual > SLIDE_PLANE_TOLERANCE * fit.extent {
            let what = if D == 2 { "straight" } else { "planar" };
            return Err(CliError::Invalid(format!(
                "--slide {}: the marker is not {what}: a node is {:.3e} from the best-fit {} \
                 (more than {SLIDE_PLANE_TOLERANCE:e} x the marker's size {:.3e}); only flat \
                 symmetry planes can slide",
                m.name,
                fit.residual,
                if D == 2 { "line" } else { "plane" },
                fit.extent
            )));
        }
        for &v in &nodes {
            if let Some(list) = normals.get_mut(v as usize) {
                list.push(fit.normal);
            }
        }
    }
    let mut t = SlideTable {
        kinds: vec![NodeKind::Free.code(); n],
        directions: vec![[0.0; D]; n],
        planes: Vec::new(),
        pinned: Vec::new(),
        sliding: 0,
    };
    for &b in boundary {
        if let Some(k) = t.kinds.get_mut(b as usize) {
            *k = NodeKind::Fixed.code();
        }
    }
    for (i, list) in normals.iter().enumerate() {
        if list.is_empty() || t.kinds.get(i) == Some(&NodeKind::Fixed.code()) {
            continue;
        }
        let (kind, dir, distinct) = node_constraint(list)?;
        t.kinds[i] = kind.code();
        t.directions[i] = dir;
        if kind == NodeKind::Fixed {
            t.pinned.push(i as u32);
        } else {
            t.sliding += 1;
            for nv in &distinct {
                t.planes.push((i as u32, *nv));
            }
        }
    }
    Ok(t)
}

/// The constraint table of the `sliding` markers as `deform move --slide` builds it, for the
/// derivatives (`deform adjoint` / `tangent --slide`): each node's kind code and direction,
/// and the nodes pinned because they lie on too many sliding planes (fixed, besides
/// `boundary`).
pub(crate) type SlideConstraints<const D: usize> = (Vec<u8>, Vec<[f64; D]>, Vec<u32>);

pub(crate) fn slide_constraints<const D: usize>(
    pts: &[[f64; D]],
    boundary: &[u32],
    sliding: &[SlideMarker<'_>],
) -> Result<SlideConstraints<D>, CliError> {
    let t = slide_table(pts, boundary, sliding)?;
    Ok((t.kinds, t.directions, t.pinned))
}

/// The slide table of the `sliding` markers (none without), the nodes it pins added to the
/// prescribed boundary.
fn slide_setup<const D: usize>(
    pts: &[[f64; D]],
    pre: &mut Prescribed,
    sliding: &[SlideMarker<'_>],
) -> Result<Option<SlideTable<D>>, CliError> {
    if sliding.is_empty() {
        return Ok(None);
    }
    let t = slide_table(pts, &pre.boundary, sliding)?;
    // Nodes on too many sliding planes are held where they are.
    pre.boundary.extend(&t.pinned);
    pre.boundary.sort_unstable();
    Ok(Some(t))
}

/// A sliding node's kind, its direction (normal or line), and its distinct plane normals.
type NodeConstraint<const D: usize> = (
    deform_kernel::spring::constraints::NodeKind,
    [f64; D],
    Vec<[f64; D]>,
);

/// What a node on the sliding planes with these normals may do: slide on one plane (its
/// normal), on the line where two meet (3D; its direction), or nothing (more planes, or two in
/// 2D). Parallel normals count once; the distinct ones come back too.
fn node_constraint<const D: usize>(normals: &[[f64; D]]) -> Result<NodeConstraint<D>, CliError> {
    use deform_kernel::spring::constraints::{plane_intersection, NodeKind};
    let mut distinct: Vec<[f64; D]> = Vec::new();
    for nv in normals {
        let parallel = distinct
            .iter()
            .any(|d| d.iter().zip(nv).map(|(a, b)| a * b).sum::<f64>().abs() >= 1.0 - 1e-9);
        if !parallel {
            distinct.push(*nv);
        }
    }
    let (kind, dir) = match distinct.as_slice() {
        [a] => (NodeKind::Plane, *a),
        [a, b] if D == 3 => {
            let lift = |v: &[f64; D]| [v[0], v[1], v.get(2).copied().unwrap_or(0.0)];
            let tan = plane_intersection(lift(a), lift(b))
                .map_err(|e| CliError::Invalid(format!("--slide: {e}")))?;
            let mut d = [0.0; D];
            for (x, y) in d.iter_mut().zip(tan) {
                *x = y;
            }
            (NodeKind::Line, d)
        }
        _ => (NodeKind::Fixed, [0.0; D]),
    };
    Ok((kind, dir, distinct))
}

fn sorted_nodes(lists: &[&CellList]) -> Vec<u32> {
    let mut v: Vec<u32> = lists.iter().flat_map(|l| l.nodes.iter().copied()).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Runs a mesh motion.
pub fn run_move(input: &MoveInput<'_>) -> Result<MoveResult, CliError> {
    run_move_sliding(input, &[])
}

/// Runs a mesh motion in which the nodes of the `sliding` markers (not on a moved or fixed
/// marker) slide on their markers' least-squares planes, and nodes on two such planes (3D)
/// on the line where they meet; a marker that is not planar within
/// [`SLIDE_PLANE_TOLERANCE`] is refused. Springs solve the constrained system; the quaternion
/// methods and IDW propagate the sliding nodes as field nodes and then project their motion.
pub fn run_move_sliding(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
) -> Result<MoveResult, CliError> {
    match input.dim {
        2 => move_d::<2>(input, sliding),
        3 => move_d::<3>(input, sliding),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

/// Runs a large motion as `steps` increments (`deform move --steps N`): step `s` moves the
/// moved markers to `s/N` of the motion (a rotation by `s·θ/N` about the same centre, a
/// translation or displacement field scaled by `s/N`), starting from the mesh the previous step
/// produced, so stiffness, wall distances, dual volumes and the quaternion method's rotations are
/// re-derived on the current mesh every step. After each step the moved nodes are put exactly
/// on their prescribed positions (the composed increments would drift by a few ulps), so the
/// last step ends with the exact prescribed motion. `steps = 1` is [`run_move_sliding`].
pub fn run_move_in_steps(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
    steps: usize,
) -> Result<MoveResult, CliError> {
    if steps <= 1 {
        return run_move_sliding(input, sliding);
    }
    let original = input.points;
    let mut plan = Steps {
        input,
        steps,
        moved: sorted_nodes(&input.moved),
        field: match &input.motion {
            Motion::Field(list) => list.iter().copied().collect(),
            _ => std::collections::BTreeMap::new(),
        },
        center: None,
    };
    // Every step has the same cells, so one edge graph.
    let built = match input.graph {
        Some(_) => None,
        None => Some(edge_graph(
            &cells_view(input.cells, original.len())?,
            false,
        )?),
    };
    let graph = input.graph.or(built.as_ref());
    let mut current = original.to_vec();
    let (mut iterations, mut residual, mut converged) = (0, 0.0f64, true);
    let mut last = None;
    let mut idw_bound: Option<f64> = None;
    for s in 1..=steps {
        let step_input = MoveInput {
            points: &current,
            moved: input.moved.clone(),
            fixed: input.fixed.clone(),
            motion: plan.motion(s, &current),
            graph,
            ..*input
        };
        let r = run_move_sliding(&step_input, sliding)?;
        if plan.center.is_none() {
            plan.center = r.center;
        }
        iterations += r.iterations;
        residual = residual.max(r.residual);
        idw_bound = match (idw_bound, r.idw_max_bound) {
            (Some(a), Some(b)) => Some(f64::max(a, b)),
            (a, b) => a.or(b),
        };
        converged &= r.converged;
        current = r.deformed.clone();
        plan.place_moved(s, &mut current)?;
        last = Some(r);
    }
    let Some(mut result) = last else {
        return run_move_sliding(input, sliding);
    };
    result.displacement = current
        .iter()
        .zip(original)
        .map(|(q, p)| [q[0] - p[0], q[1] - p[1], q[2] - p[2]])
        .collect();
    result.deformed = current;
    result.iterations = iterations;
    result.residual = residual;
    result.converged = converged;
    result.center = plan.center;
    result.idw_max_bound = idw_bound;
    result.graph = result.graph.or(built);
    Ok(result)
}

/// A motion split into equal steps: each step's motion, and where the moved nodes must be
/// after it, exactly.
struct Steps<'i, 'a> {
    input: &'i MoveInput<'a>,
    steps: usize,
    /// The moved markers' nodes, ascending.
    moved: Vec<u32>,
    /// A displacement field's values by node (empty for rigid motions).
    field: std::collections::BTreeMap<u32, [f64; 3]>,
    /// The rotation centre the first step used.
    center: Option<[f64; 3]>,
}

impl Steps<'_, '_> {
    /// The part `s / steps` of `x` (all of it in the last step).
    fn fraction(&self, s: usize, x: f64) -> f64 {
        if s == self.steps {
            x
        } else {
            x * s as f64 / self.steps as f64
        }
    }

    /// Step `s`'s motion from the `current` points.
    fn motion(&self, s: usize, current: &[[f64; 3]]) -> Motion {
        let steps = self.steps as f64;
        match &self.input.motion {
            Motion::Rotate {
                degrees,
                axis,
                center: c,
            } => Motion::Rotate {
                degrees: degrees / steps,
                axis: *axis,
                center: c.or(self.center),
            },
            Motion::Translate(t) => Motion::Translate(t.map(|x| x / steps)),
            Motion::Field(list) => Motion::Field(
                list.iter()
                    .map(|(n, d)| {
                        let p = (self.input.points.get(*n as usize).copied()).unwrap_or([0.0; 3]);
                        let q = current.get(*n as usize).copied().unwrap_or([0.0; 3]);
                        let target = [0, 1, 2].map(|c| p[c] + self.fraction(s, d[c]));
                        (*n, [0, 1, 2].map(|c| target[c] - q[c]))
                    })
                    .collect(),
            ),
        }
    }

    /// Puts the moved nodes where `s` steps of the motion take them, exactly.
    fn place_moved(&self, s: usize, current: &mut [[f64; 3]]) -> Result<(), CliError> {
        let rotation = match &self.input.motion {
            Motion::Rotate { degrees, axis, .. } => Some(
                deform_kernel::Quat::from_axis_angle(
                    *axis,
                    self.fraction(s, *degrees).to_radians(),
                )
                .map_err(kernel("rotation"))?,
            ),
            _ => None,
        };
        for &m in &self.moved {
            let Some(p) = self.input.points.get(m as usize).copied() else {
                continue;
            };
            let target = match (&self.input.motion, rotation, self.center) {
                (Motion::Rotate { .. }, Some(q), Some(c)) => {
                    // The same arithmetic as a single step: p + ((c + r) − p).
                    let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
                    let mut d = [0, 1, 2].map(|k| c[k] + r[k] - p[k]);
                    if self.input.dim == 2 {
                        d[2] = 0.0;
                    }
                    [0, 1, 2].map(|k| p[k] + d[k])
                }
                (Motion::Translate(t), _, _) => [0, 1, 2].map(|c| p[c] + self.fraction(s, t[c])),
                (Motion::Field(_), _, _) => match self.field.get(&m) {
                    Some(d) => [0, 1, 2].map(|c| p[c] + self.fraction(s, d[c])),
                    None => p,
                },
                _ => continue,
            };
            if let Some(x) = current.get_mut(m as usize) {
                *x = target;
            }
        }
        Ok(())
    }
}

/// The one-level method of a solver choice (`None` for multigrid).
fn linear_method(s: MoveSolver) -> Option<deform_kernel::spring::LinearMethod<f64>> {
    use deform_kernel::spring::{LinearMethod, Preconditioner};
    match s {
        MoveSolver::Amg => None,
        MoveSolver::Cg => Some(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        }),
        MoveSolver::CgSsor => Some(LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: 1.5 },
        }),
        MoveSolver::GaussSeidel => Some(LinearMethod::GaussSeidel),
        MoveSolver::Jacobi => Some(LinearMethod::Jacobi),
    }
}

/// The multigrid strength threshold when none is given: the kernel's default
/// (`AmgOptions::default().strength_theta`).
pub fn default_amg_strength() -> f64 {
    deform_kernel::spring::AmgOptions::<f64>::default().strength_theta
}

/// Owned storage of a multigrid hierarchy (`index`, `values`; the setup's work buffer is
/// freed before the solve).
#[derive(Default)]
struct AmgStorage {
    index: Vec<u32>,
    values: Vec<f64>,
}

impl AmgStorage {
    /// Builds the hierarchy of `sys` with the default options and strength threshold
    /// `theta` in one symbolic pass (not
    /// `setup_len` and then `setup`, which runs it again): `index` and `values` are allocated
    /// at bounds that hold every hierarchy of `sys` ([`amg_bounds`]). The kernel writes only
    /// the prefixes it needs and gives the same bits in larger buffers; the untouched zeroed
    /// tails cost address space, not memory.
    fn build<'a>(
        &'a mut self,
        sys: &deform_kernel::spring::SpringSystem<'_, f64>,
        theta: f64,
    ) -> Result<deform_kernel::spring::AmgHierarchy<'a, f64>, CliError> {
        use deform_kernel::spring::{AmgHierarchy, AmgOptions};
        let opts = AmgOptions {
            strength_theta: theta,
            ..AmgOptions::default()
        };
        let work_len = AmgHierarchy::setup_work_len(sys);
        let mut work = vec![0u32; work_len];
        let (index_len, values_len) = amg_bounds(sys.node_count(), work_len, opts.max_coarse);
        self.index = vec![0; index_len];
        self.values = vec![0.0; values_len];
        AmgHierarchy::setup(sys, &opts, &mut work, &mut self.index, &mut self.values)
            .map_err(kernel("multigrid setup"))
    }
}

/// Bounds on a hierarchy's `index` and `values` lengths for `n` nodes and a symbolic `work`
/// of `work_len` (from the kernel's layout): `index` is a prefix of `work`; `values` holds the
/// fine diagonal (`n`), per level the prolongator, coarse diagonal and coarse operator (fewer
/// entries than their structure takes in `index`, so at most `work_len` together), the dense
/// coarsest factor (at most `max_coarse²`) and an accumulator (a coarse size, below `n`).
/// Were a bound ever short, `setup` would refuse the buffer (`BufferTooSmall`), not guess.
fn amg_bounds(n: usize, work_len: usize, max_coarse: usize) -> (usize, usize) {
    let dense = max_coarse.saturating_mul(max_coarse);
    let values = n
        .saturating_mul(2)
        .saturating_add(work_len)
        .saturating_add(dense);
    (work_len, values)
}

fn move_d<const D: usize>(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
) -> Result<MoveResult, CliError> {
    use deform_kernel::spring::constraints::{slide_points, Constraints};
    use deform_kernel::spring::SolveOptions;
    let n = input.points.len();
    let mut pre = prescribe::<D>(input)?;
    let view = cells_view(input.cells, n)?;
    let pts = points_d::<D>(input.points);
    let table = slide_setup(&pts, &mut pre, sliding)?;
    let constraints = match &table {
        Some(t) => {
            Some(Constraints::new(&t.kinds, &t.directions).map_err(kernel("sliding constraints"))?)
        }
        None => None,
    };
    let mut fixed = vec![0u8; n];
    for &b in &pre.boundary {
        if let Some(f) = fixed.get_mut(b as usize) {
            *f = 1;
        }
    }
    let diagonals = matches!(input.method, MoveMethod::AngleDirect | MoveMethod::AngleCg);
    let built = match input.graph.filter(|_| !diagonals) {
        Some(_) => None,
        None => Some(edge_graph(&view, diagonals)?),
    };
    let Some(graph) = built.as_ref().or(input.graph) else {
        return Err(CliError::Invalid("no edge graph".into()));
    };
    let run = MoveRun {
        input,
        pre: &pre,
        pts: &pts,
        view: &view,
        g: graph.view()?,
        fixed: &fixed,
        constraints: constraints.as_ref(),
        options: SolveOptions {
            max_iterations: input.max_iter,
            residual_tol: input.tol,
            update_tol: 0.0,
        },
    };
    let mut out = pts.clone();
    let mut rbf_info = None;
    let solved = match input.method {
        MoveMethod::Rbf(settings) => {
            let (moved_out, info) =
                rbf::move_rbf(&settings, &pts, &pre.boundary, &pre.moved, &pre.disp)?;
            out = moved_out;
            rbf_info = Some(info);
            (0, 0.0, true, None)
        }
        MoveMethod::Spring | MoveMethod::AngleDirect | MoveMethod::AngleCg => {
            run.springs(&mut out)?
        }
        MoveMethod::Quaternion | MoveMethod::Idw => run.quaternion(&mut out)?,
    };
    if let Some(c) = &constraints {
        // Spring solves already moved the sliding nodes along their planes; the quaternion
        // methods and IDW moved them as field nodes: project their motion (exact for springs
        // up to rounding, so done for every method).
        slide_points(c, &pts, &mut out).map_err(kernel("sliding"))?;
    }
    let mut result = move_result(input, &pre, table.as_ref(), &pts, &out, solved);
    result.rbf = rbf_info;
    result.graph = built.filter(|_| !diagonals);
    Ok(result)
}

/// The boundary of a motion: the moved markers' nodes, every boundary node (moved and
/// fixed), the prescribed displacement of each, and the rigid motion when there is one.
pub(crate) struct Prescribed {
    moved: Vec<u32>,
    boundary: Vec<u32>,
    disp: Vec<[f64; 3]>,
    /// The rotation centre used (rotations only).
    center: Option<[f64; 3]>,
    /// The rigid rotation of the moved nodes (identity for a translation; `None` for a field).
    rigid_q: Option<deform_kernel::Quat<f64>>,
}

/// What the motion prescribes on the boundary, checked against the mesh.
pub(crate) fn prescribe<const D: usize>(input: &MoveInput<'_>) -> Result<Prescribed, CliError> {
    use deform_kernel::Quat;
    let n = input.points.len();
    let moved = sorted_nodes(&input.moved);
    if moved.is_empty() {
        return Err(CliError::Invalid("the moved markers have no nodes".into()));
    }
    let mut boundary = moved.clone();
    boundary.extend(sorted_nodes(&input.fixed));
    boundary.sort_unstable();
    boundary.dedup();
    if let Some(&bad) = boundary.iter().find(|&&b| b as usize >= n) {
        return Err(CliError::Invalid(format!(
            "marker node {bad} is not a mesh node"
        )));
    }
    let point = |m: u32| input.points.get(m as usize).copied().unwrap_or([0.0; 3]);
    let mut pre = Prescribed {
        disp: vec![[0.0f64; 3]; n],
        center: None,
        rigid_q: None,
        moved,
        boundary,
    };
    match &input.motion {
        Motion::Rotate {
            degrees,
            axis,
            center,
        } => {
            let c = center.unwrap_or_else(|| {
                let mut c = [0.0; 3];
                for &m in &pre.moved {
                    let p = point(m);
                    for k in 0..3 {
                        c[k] += p[k];
                    }
                }
                c.map(|x| x / pre.moved.len() as f64)
            });
            let c = if D == 2 { [c[0], c[1], 0.0] } else { c };
            let q =
                Quat::from_axis_angle(*axis, degrees.to_radians()).map_err(kernel("rotation"))?;
            for &m in &pre.moved {
                let p = point(m);
                let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
                if let Some(d) = pre.disp.get_mut(m as usize) {
                    *d = [c[0] + r[0] - p[0], c[1] + r[1] - p[1], c[2] + r[2] - p[2]];
                    if D == 2 {
                        d[2] = 0.0;
                    }
                }
            }
            pre.center = Some(c);
            pre.rigid_q = Some(q);
        }
        Motion::Translate(t) => {
            for &m in &pre.moved {
                if let Some(d) = pre.disp.get_mut(m as usize) {
                    *d = *t;
                }
            }
            pre.rigid_q = Some(Quat::identity());
        }
        Motion::Field(list) => {
            for (node, d) in list {
                if pre.moved.binary_search(node).is_err() {
                    return Err(CliError::Invalid(format!(
                        "node {node} is not on the moved markers"
                    )));
                }
                if let Some(slot) = pre.disp.get_mut(*node as usize) {
                    *slot = *d;
                }
            }
        }
    }
    Ok(pre)
}

/// `(iterations, residual, converged)` of a solve, and the fast IDW's error bound.
type Solved = (usize, f64, bool, Option<f64>);

/// One motion, set up: the mesh in `D` coordinates, its graph and boundary, and the options.
struct MoveRun<'r, const D: usize> {
    input: &'r MoveInput<'r>,
    pre: &'r Prescribed,
    pts: &'r [[f64; D]],
    view: &'r Cells<'r>,
    g: Graph<'r>,
    fixed: &'r [u8],
    constraints: Option<&'r deform_kernel::spring::constraints::Constraints<'r, f64, D>>,
    options: deform_kernel::spring::SolveOptions<f64>,
}

impl<const D: usize> MoveRun<'_, D> {
    /// The spring system on the boundary's mask, with the stiffness the input asks for.
    fn spring_system<'s>(
        &'s self,
        k: &'s [f64],
        scratch: &'s mut [u32],
    ) -> Result<deform_kernel::spring::SpringSystem<'s, f64>, CliError> {
        deform_kernel::spring::SpringSystem::new(self.g, k, self.fixed, scratch)
            .map_err(kernel("springs"))
    }

    /// The stiffness of every edge ([`Stiffness`] of the input).
    fn stiffness(&self) -> Result<Vec<f64>, CliError> {
        let (pts, moved) = (self.pts, &self.pre.moved);
        spring_stiffness(&self.g, self.view, pts, moved, self.input.stiffness)
    }

    /// The linear solver the input asks for (one-level, or multigrid built in `storage`),
    /// split over the processes when there are several.
    fn linear_solve(
        &self,
        sys: &deform_kernel::spring::SpringSystem<'_, f64>,
        values: &mut [[f64; D]],
    ) -> Result<deform_kernel::spring::SolveReport<f64>, CliError> {
        use deform_kernel::spring::{
            solve_linear_sliding_scratch_len, solve_linear_with_scratch_len, LinearSolver,
        };
        let n = values.len();
        let mut storage = AmgStorage::default();
        let hierarchy;
        let solver = match linear_method(self.input.solver) {
            Some(m) => LinearSolver::Method(m),
            None => {
                hierarchy = storage.build(sys, self.input.amg_strength)?;
                LinearSolver::Amg(&hierarchy)
            }
        };
        let collective = (self.input.split)
            .map(|s| s.collective(self.input.points, self.g.offsets(), self.g.targets()));
        let solver = split_solver(solver, collective.as_deref());
        match self.constraints {
            Some(c) => {
                let mut scratch = vec![[0.0; D]; solve_linear_sliding_scratch_len(&solver, n)];
                sys.solve_linear_sliding(c, values, solver, &self.options, &mut scratch)
            }
            None => {
                let mut scratch = vec![[0.0; D]; solve_linear_with_scratch_len(&solver, n)];
                sys.solve_linear_with(values, solver, &self.options, &mut scratch)
            }
        }
        .map_err(kernel("linear springs"))
    }

    /// Linear or angle springs on the displacement; `out` = points + displacement.
    fn springs(&self, out: &mut [[f64; D]]) -> Result<Solved, CliError> {
        let n = self.pts.len();
        let k = self.stiffness()?;
        let mut sscratch = vec![0u32; deform_kernel::spring::SpringSystem::<f64>::scratch_len(n)];
        let sys = self.spring_system(&k, &mut sscratch)?;
        let mut values: Vec<[f64; D]> = (self.pre.disp.iter())
            .map(|d| core::array::from_fn(|c| d[c]))
            .collect();
        let report = if self.input.method == MoveMethod::Spring {
            self.linear_solve(&sys, &mut values)?
        } else {
            self.angle_solve(sys, &mut values)?
        };
        for ((o, p), v) in out.iter_mut().zip(self.pts).zip(&values) {
            for k in 0..D {
                o[k] = p[k] + v[k];
            }
        }
        Ok((report.iterations, report.residual, report.converged, None))
    }

    /// The angle springs by the method and solver the input asks for.
    fn angle_solve(
        &self,
        sys: deform_kernel::spring::SpringSystem<'_, f64>,
        values: &mut [[f64; D]],
    ) -> Result<deform_kernel::spring::SolveReport<f64>, CliError> {
        use deform_kernel::spring::{AngleMethod, AngleSystem, DEFAULT_ANGLE_EPSILON};
        let (input, n, options) = (self.input, self.pts.len(), &self.options);
        let mut storage = AmgStorage::default();
        let amg = input.method == MoveMethod::AngleCg && input.solver == MoveSolver::Amg;
        // CG preconditioned by the linear springs' multigrid V-cycle per component.
        let hierarchy = if amg {
            Some(storage.build(&sys, input.amg_strength)?)
        } else {
            None
        };
        let asys = AngleSystem::new(sys, self.pts, DEFAULT_ANGLE_EPSILON)
            .map_err(kernel("angle springs"))?;
        let method = match (input.method, input.solver) {
            (MoveMethod::AngleCg, _) => AngleMethod::Cg,
            (_, MoveSolver::Jacobi) => AngleMethod::DirectJacobi,
            _ => AngleMethod::DirectGaussSeidel,
        };
        let sor = input.method == MoveMethod::AngleDirect
            && !matches!(input.solver, MoveSolver::GaussSeidel | MoveSolver::Jacobi);
        let omega = if sor { angle_direct_omega(n, D) } else { 1.0 };
        match (&hierarchy, self.constraints) {
            (Some(h), Some(c)) => {
                let mut scratch = vec![[0.0; D]; asys.solve_angle_sliding_amg_scratch_len(h)];
                asys.solve_angle_sliding_amg(c, values, h, options, &mut scratch)
            }
            (Some(h), None) => {
                let mut scratch = vec![[0.0; D]; asys.angle_amg_scratch_len(h)];
                asys.solve_angle_amg(h, values, options, &mut scratch)
            }
            (None, Some(c)) => {
                let mut scratch = vec![[0.0; D]; asys.solve_angle_sliding_scratch_len(method)];
                asys.solve_angle_sliding(c, values, method, omega, options, &mut scratch)
            }
            (None, None) => {
                let mut scratch = vec![[0.0; D]; asys.angle_scratch_len(method)];
                if sor {
                    asys.solve_angle_sor(values, omega, options, &mut scratch)
                } else {
                    asys.solve_angle(values, method, options, &mut scratch)
                }
            }
        }
        .map_err(kernel("angle springs"))
    }
}

impl<const D: usize> MoveRun<'_, D> {
    /// The boundary elements renumbered into `0..B` (for rotations from the shape).
    fn boundary_elements(&self) -> CellList {
        let boundary = &self.pre.boundary;
        let mut local = vec![u32::MAX; self.pts.len()];
        for (k, &b) in boundary.iter().enumerate() {
            if let Some(l) = local.get_mut(b as usize) {
                *l = k as u32;
            }
        }
        let mut elems = CellList::new();
        for list in self.input.moved.iter().chain(&self.input.fixed) {
            for (code, nodes) in list.iter() {
                let ln: Vec<u32> = nodes
                    .iter()
                    .map(|&v| local.get(v as usize).copied().unwrap_or(u32::MAX))
                    .collect();
                if let Some(kind) = deform_kernel::CellKind::from_vtk(code) {
                    elems.push(kind, &ln);
                }
            }
        }
        elems
    }

    /// Samareh's quaternion method (spring propagation) or IDW, then `--reach`.
    fn quaternion(&self, out: &mut [[f64; D]]) -> Result<Solved, CliError> {
        use deform_kernel::quaternion::{BoundaryMotion, RotationSource};
        use deform_kernel::Quat;
        let (pre, pts, n) = (self.pre, self.pts, self.pts.len());
        let deformed: Vec<[f64; D]> = (pre.boundary.iter())
            .map(|&b| {
                let p = pts.get(b as usize).copied().unwrap_or([0.0; D]);
                let d = pre.disp.get(b as usize).copied().unwrap_or([0.0; 3]);
                core::array::from_fn(|k| p[k] + d[k])
            })
            .collect();
        let elems = self.boundary_elements();
        let evw = cells_view(&elems, pre.boundary.len())?;
        let per_node: Vec<Quat<f64>> = match pre.rigid_q {
            Some(q) => (pre.boundary.iter())
                .map(|b| match pre.moved.binary_search(b) {
                    Ok(_) => q,
                    Err(_) => Quat::identity(),
                })
                .collect(),
            None => Vec::new(),
        };
        let motion = BoundaryMotion {
            nodes: &pre.boundary,
            deformed: &deformed,
            elements: Some(evw),
            rotations: match pre.rigid_q {
                Some(_) => RotationSource::PerNode(&per_node),
                None => RotationSource::Shape,
            },
            origin: pre.center.map(|c| core::array::from_fn(|k| c[k])),
        };
        let mut field = Field {
            translations: vec![[0.0; D]; n],
            rotations: vec![Quat::identity(); n],
        };
        let (origin, solved) = if self.input.method == MoveMethod::Idw {
            self.idw(&motion, &mut field, out)?
        } else {
            self.quaternion_springs(&motion, &mut field, out)?
        };
        if let Some(radius) = self.input.reach {
            self.reach(radius, origin, &deformed, &mut field, out)?;
        }
        Ok(solved)
    }

    /// IDW (exact, or fast with `--idw-theta`); returns the origin used.
    fn idw(
        &self,
        motion: &deform_kernel::quaternion::BoundaryMotion<'_, f64, D>,
        field: &mut Field<D>,
        out: &mut [[f64; D]],
    ) -> Result<([f64; D], Solved), CliError> {
        use deform_kernel::quaternion::{
            deform_idw, deform_idw_fast, deform_idw_scratch_len, propagate_idw_fast_index_len,
            propagate_idw_fast_scratch_len, IdwFastOptions,
        };
        let (n, b, exponent) = (
            self.pts.len(),
            self.pre.boundary.len(),
            self.input.idw_exponent,
        );
        let mut scratch = vec![0.0; deform_idw_scratch_len::<D>(n, b)];
        let (tr, rot) = (&mut field.translations, &mut field.rotations);
        let Some((theta, tolerance)) = self.input.idw_fast else {
            let origin = deform_idw(self.pts, motion, exponent, tr, rot, &mut scratch, out)
                .map_err(kernel("quaternion IDW"))?;
            return Ok((origin, (0, 0.0, true, None)));
        };
        let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
        let mut tree = vec![0.0; propagate_idw_fast_scratch_len::<D>(b)];
        let options = IdwFastOptions { theta, tolerance };
        let (origin, report) = deform_idw_fast(
            self.pts,
            motion,
            exponent,
            &options,
            tr,
            rot,
            &mut scratch,
            &mut index,
            &mut tree,
            out,
        )
        .map_err(kernel("fast quaternion IDW"))?;
        Ok((origin, (0, 0.0, true, Some(report.max_bound))))
    }

    /// The quaternion method with spring propagation; returns the origin used.
    fn quaternion_springs(
        &self,
        motion: &deform_kernel::quaternion::BoundaryMotion<'_, f64, D>,
        field: &mut Field<D>,
        out: &mut [[f64; D]],
    ) -> Result<([f64; D], Solved), CliError> {
        use deform_kernel::quaternion::{
            deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
        };
        use deform_kernel::spring::{LinearSolver, SpringSystem};
        let (n, b) = (self.pts.len(), self.pre.boundary.len());
        let k = self.stiffness()?;
        let mut sscratch = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
        let sys = self.spring_system(&k, &mut sscratch)?;
        let mut storage = AmgStorage::default();
        let hierarchy;
        let solver = match linear_method(self.input.solver) {
            Some(m) => LinearSolver::Method(m),
            None => {
                hierarchy = storage.build(&sys, self.input.amg_strength)?;
                LinearSolver::Amg(&hierarchy)
            }
        };
        let collective = (self.input.split)
            .map(|s| s.collective(self.input.points, self.g.offsets(), self.g.targets()));
        let solver = split_solver(solver, collective.as_deref());
        let mut scratch = vec![0.0; deform_spring_scratch_len::<D>(n, b)];
        let mut values = vec![0.0; propagate_spring_with_scratch_len::<D>(&solver, n)];
        let (origin, report) = deform_spring_with::<f64, D>(
            self.pts,
            motion,
            &sys,
            solver,
            &self.options,
            &mut field.translations,
            &mut field.rotations,
            &mut scratch,
            &mut values,
            out,
        )
        .map_err(kernel("quaternion springs"))?;
        let solved = (report.iterations, report.residual, report.converged, None);
        Ok((origin, solved))
    }

    /// `--reach`: fades (Δ, Q) to no motion beyond `radius` from the moving markers, then
    /// redoes the field update.
    fn reach(
        &self,
        radius: f64,
        origin: [f64; D],
        deformed: &[[f64; D]],
        field: &mut Field<D>,
        out: &mut [[f64; D]],
    ) -> Result<(), CliError> {
        use deform_kernel::quaternion::{limit_reach, update_points};
        let pts = self.pts;
        let mut distances = vec![0.0; pts.len()];
        deform_kernel::spring::wall_distances(pts, &self.pre.moved, &mut distances)
            .map_err(kernel("reach"))?;
        let (tr, rot) = (&mut field.translations, &mut field.rotations);
        limit_reach(&distances, radius, tr, rot).map_err(kernel("reach"))?;
        update_points(origin, pts, tr, rot, &self.pre.boundary, deformed, out)
            .map_err(kernel("reach"))?;
        // Beyond the reach the update is o + (p − o), which can differ from p in the last
        // bit: those nodes keep their coordinates exactly.
        for ((o, p), &d) in out.iter_mut().zip(pts).zip(&distances) {
            if d >= radius {
                *o = *p;
            }
        }
        Ok(())
    }
}

/// The quaternion method's per-node field: translations Δ and rotations Q.
struct Field<const D: usize> {
    translations: Vec<[f64; D]>,
    rotations: Vec<deform_kernel::Quat<f64>>,
}

/// The result of a motion: the points back in 3 coordinates, their displacement, the
/// solve's figures, and the sliding nodes' largest distance from their planes.
fn move_result<const D: usize>(
    input: &MoveInput<'_>,
    pre: &Prescribed,
    table: Option<&SlideTable<D>>,
    pts: &[[f64; D]],
    out: &[[f64; D]],
    (iterations, residual, converged, idw_max_bound): Solved,
) -> MoveResult {
    let max_slide_offset = table.map_or(0.0, |t| {
        t.planes.iter().fold(0.0f64, |m, &(i, nv)| {
            let (a, b) = (
                out.get(i as usize).copied().unwrap_or([0.0; D]),
                pts.get(i as usize).copied().unwrap_or([0.0; D]),
            );
            let d: f64 = nv
                .iter()
                .zip(a.iter().zip(&b))
                .map(|(n, (x, y))| n * (x - y))
                .sum();
            m.max(d.abs())
        })
    });
    let deformed: Vec<[f64; 3]> = out
        .iter()
        .map(|p| core::array::from_fn(|k| p.get(k).copied().unwrap_or(0.0)))
        .collect();
    let displacement = deformed
        .iter()
        .zip(input.points)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1], a[2] - b[2]])
        .collect();
    MoveResult {
        idw_max_bound,
        rbf: None,
        deformed,
        displacement,
        iterations,
        residual,
        converged,
        moved_nodes: pre.moved.len(),
        fixed_nodes: pre.boundary.len() - pre.moved.len(),
        center: pre.center,
        sliding_nodes: table.map_or(0, |t| t.sliding),
        max_slide_offset,
        graph: None,
    }
}

/// What smoothing one block did.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BlockSmoothing {
    /// Iterations performed (fine + coarse).
    pub iterations: usize,
    /// Largest stretching ratio along the direction before.
    pub max_stretching_before: f64,
    /// Largest stretching ratio along the direction after.
    pub max_stretching_after: f64,
    /// Largest distance a point moved.
    pub max_point_move: f64,
}

/// Smooths one structured block in place with Alter's arclength Taubin filter.
#[allow(clippy::too_many_arguments)]
pub fn smooth_block(
    dim: usize,
    dims: [usize; 3],
    points: &mut [[f64; 3]],
    direction: Direction,
    (normalised, free_end): (bool, bool),
    iterations: usize,
    lambda: f64,
    mu: f64,
    coarse: Option<usize>,
    pinned: Option<&[u8]>,
) -> Result<BlockSmoothing, CliError> {
    let modes = (normalised, free_end);
    match dim {
        2 => smooth_d::<2>(
            dims, points, direction, modes, iterations, lambda, mu, coarse, pinned,
        ),
        3 => smooth_d::<3>(
            dims, points, direction, modes, iterations, lambda, mu, coarse, pinned,
        ),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

#[allow(clippy::too_many_arguments)]
fn smooth_d<const D: usize>(
    dims: [usize; 3],
    points: &mut [[f64; 3]],
    direction: Direction,
    (normalised, free_end): (bool, bool),
    iterations: usize,
    lambda: f64,
    mu: f64,
    coarse: Option<usize>,
    pinned: Option<&[u8]>,
) -> Result<BlockSmoothing, CliError> {
    use deform_kernel::taubin::{
        smooth_arclength, smooth_arclength_scratch_len, Coarse, LineEnd, Prolongation,
        SmoothOptions, TaubinParams,
    };
    let block = deform_kernel::Block::new(dims).map_err(kernel("block"))?;
    let mut pts = points_d::<D>(points);
    let mut options = SmoothOptions::new(direction);
    options.params = TaubinParams { lambda, mu };
    options.iterations = iterations;
    options.normalised = normalised;
    if free_end {
        options.ends[1] = LineEnd::Free;
    }
    options.fixed = pinned;
    if let Some(m) = coarse {
        let mut factor = [m; 3];
        if let Some(f) = factor.get_mut(direction.index()) {
            *f = 1;
        }
        if D == 2 {
            factor[2] = 1;
        }
        options.coarse = Some(Coarse {
            factor,
            prolongation: Prolongation::Values,
        });
        options.coarse_iterations = (iterations / 2).max(1);
    }
    let mut scratch =
        vec![0.0; smooth_arclength_scratch_len::<D>(&block, direction, options.coarse.as_ref())];
    let r = smooth_arclength(&block, &mut pts, &options, &mut scratch)
        .map_err(kernel("arclength smoothing"))?;
    for (p, q) in points.iter_mut().zip(&pts) {
        for (s, &x) in p.iter_mut().zip(q) {
            *s = x;
        }
    }
    Ok(BlockSmoothing {
        iterations: r.iterations,
        max_stretching_before: r.stretching_before.0,
        max_stretching_after: r.stretching_after.0,
        max_point_move: r.max_displacement,
    })
}

/// Per-cell smallest corner Jacobian of `cells` at `points` (2D: quads of a 2D grid; 3D:
/// hexahedra). Compare two point sets with the same `cells` to find cells that flipped.
pub fn corner_jacobians(
    dim: usize,
    cells: &CellList,
    points: &[[f64; 3]],
) -> Result<Vec<f64>, CliError> {
    fn run<const D: usize>(cells: &CellList, points: &[[f64; 3]]) -> Result<Vec<f64>, CliError> {
        let view = cells_view(cells, points.len())?;
        let mut out = vec![0.0; view.len()];
        deform_kernel::quality::min_corner_jacobians(
            &view,
            &points_d::<D>(points),
            false,
            &mut out,
        )
        .map_err(kernel("corner Jacobians"))?;
        Ok(out)
    }
    match dim {
        2 => run::<2>(cells, points),
        3 => run::<3>(cells, points),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

/// Alter's cell-size stretching measure (his eq. 1): the largest `|∇²S|` over the points that
/// are interior in every direction with at least three points, where `S` is the dimensional
/// arclength along `direction` and `∇²S = Σ_axes (S₋ − 2S + S₊) / 2`. 0 for a grid whose
/// arclength is linear in the indices (uniform, straight and equally long lines).
pub fn max_arclength_laplacian(
    dim: usize,
    dims: [usize; 3],
    points: &[[f64; 3]],
    direction: Direction,
) -> Result<f64, CliError> {
    fn run<const D: usize>(
        dims: [usize; 3],
        points: &[[f64; 3]],
        direction: Direction,
    ) -> Result<f64, CliError> {
        let block = deform_kernel::Block::new(dims).map_err(kernel("block"))?;
        let pts = points_d::<D>(points);
        let mut s = vec![0.0; pts.len()];
        deform_kernel::taubin::arclength(&block, &pts, direction, false, &mut s)
            .map_err(kernel("arclength"))?;
        let [ni, nj, nk] = dims;
        let strides = [1, ni, ni * nj];
        let inside = |t: usize, n: usize| n < 3 || (t > 0 && t + 1 < n);
        let mut max = 0.0f64;
        for k in 0..nk {
            for j in 0..nj {
                for i in 0..ni {
                    let idx = [i, j, k];
                    if !(0..3).all(|a| inside(idx[a], dims[a])) {
                        continue;
                    }
                    let p = i + ni * (j + nj * k);
                    let mut lap = 0.0;
                    for a in 0..3 {
                        if dims[a] >= 3 {
                            lap += (s[p - strides[a]] - 2.0 * s[p] + s[p + strides[a]]) / 2.0;
                        }
                    }
                    max = max.max(lap.abs());
                }
            }
        }
        Ok(max)
    }
    match dim {
        2 => run::<2>(dims, points, direction),
        3 => run::<3>(dims, points, direction),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

/// A block face: the direction normal to it and which end (`false` = min).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Face {
    /// The direction normal to the face.
    pub direction: Direction,
    /// The `max` face (index `n − 1`) rather than the `min` face (index 0).
    pub max: bool,
}

/// Transfinite interpolation on a structured block: the `wall` face moves rigidly, the
/// opposite face stays, and the interior follows along the wall's direction, either with
/// Samareh's quaternion TFI (`quaternion`: rotations blended, rigid motion reproduced) or
/// with plain displacement TFI. Returns the new points (same numbering).
pub fn tfi_block(
    dim: usize,
    dims: [usize; 3],
    points: &[[f64; 3]],
    wall: Face,
    motion: &Motion,
    quaternion: bool,
) -> Result<Vec<[f64; 3]>, CliError> {
    match dim {
        2 => tfi_d::<2>(dims, points, wall, motion, quaternion),
        3 => tfi_d::<3>(dims, points, wall, motion, quaternion),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

fn tfi_d<const D: usize>(
    dims: [usize; 3],
    points: &[[f64; 3]],
    wall: Face,
    motion: &Motion,
    quaternion: bool,
) -> Result<Vec<[f64; 3]>, CliError> {
    let block = deform_kernel::Block::new(dims).map_err(kernel("block"))?;
    let pts = points_d::<D>(points);
    let faces = TfiFaces::new(&block, wall);
    let rigid = WallMotion::new(motion, points, &faces.wall)?;
    let out = if quaternion {
        quaternion_tfi(&block, wall, (points, &pts), &faces, &rigid)?
    } else {
        displacement_tfi_d(&block, wall, (points, &pts), &faces.wall, &rigid)?
    };
    Ok(out
        .iter()
        .zip(points)
        .map(|(o, p)| {
            let mut r = *p;
            r[..D].copy_from_slice(o);
            r
        })
        .collect())
}

/// The nodes of a block's moving wall face and of the opposite face, which stays.
struct TfiFaces {
    wall: Vec<u32>,
    far: Vec<u32>,
}

impl TfiFaces {
    /// The nodes (ascending) on `wall` and on the face opposite it.
    fn new(block: &deform_kernel::Block, wall: Face) -> Self {
        let len = block.dims()[wall.direction.index()];
        let wall_t = if wall.max { len - 1 } else { 0 };
        let far_t = if wall.max { 0 } else { len - 1 };
        let mut faces = TfiFaces {
            wall: Vec::new(),
            far: Vec::new(),
        };
        for p in 0..block.point_count() {
            let t = block.ijk(p)[wall.direction.index()];
            if t == wall_t {
                faces.wall.push(p as u32);
            } else if t == far_t {
                faces.far.push(p as u32);
            }
        }
        faces
    }
}

/// A wall's rigid motion: `p ↦ Q (p − c) + c + shift`.
struct WallMotion {
    q: deform_kernel::Quat<f64>,
    shift: [f64; 3],
    center: [f64; 3],
}

impl WallMotion {
    /// From a rotation (about its centre, or the wall's centroid) or a translation.
    fn new(motion: &Motion, points: &[[f64; 3]], wall: &[u32]) -> Result<Self, CliError> {
        use deform_kernel::Quat;
        let mut centroid = [0.0; 3];
        for &p in wall {
            for (s, x) in centroid.iter_mut().zip(points[p as usize]) {
                *s += x;
            }
        }
        let centroid = centroid.map(|s| s / wall.len().max(1) as f64);
        match motion {
            &Motion::Rotate {
                degrees,
                axis,
                center,
            } => Ok(WallMotion {
                q: Quat::from_axis_angle(axis, degrees.to_radians()).map_err(kernel("rotation"))?,
                shift: [0.0; 3],
                center: center.unwrap_or(centroid),
            }),
            &Motion::Translate(t) => Ok(WallMotion {
                q: Quat::identity(),
                shift: t,
                center: centroid,
            }),
            Motion::Field(_) => Err(CliError::Invalid(
                "a Plot3D wall moves rigidly: --rotate DEG or --translate DX,DY[,DZ]".into(),
            )),
        }
    }

    /// Where the motion takes `p`.
    fn apply<const D: usize>(&self, p: [f64; 3]) -> [f64; D] {
        let c = self.center;
        let r = self.q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
        core::array::from_fn(|k| r[k] + c[k] + self.shift[k])
    }
}

/// Samareh's quaternion TFI along the wall's direction: the wall's nodes move and turn by the
/// rigid motion, the far face's stay (`points`: the grid's, and in `D` coordinates).
fn quaternion_tfi<const D: usize>(
    block: &deform_kernel::Block,
    wall: Face,
    (points, pts): (&[[f64; 3]], &[[f64; D]]),
    faces: &TfiFaces,
    rigid: &WallMotion,
) -> Result<Vec<[f64; D]>, CliError> {
    use deform_kernel::quaternion::{
        deform_tfi, deform_tfi_scratch_len, BoundaryMotion, RotationSource,
    };
    use deform_kernel::Quat;
    let n = pts.len();
    let nodes: Vec<u32> = faces.wall.iter().chain(&faces.far).copied().collect();
    let on_wall = |k: usize| k < faces.wall.len();
    let deformed: Vec<[f64; D]> = (nodes.iter().enumerate())
        .map(|(k, &p)| match on_wall(k) {
            true => rigid.apply(points[p as usize]),
            false => pts[p as usize],
        })
        .collect();
    let rotations: Vec<Quat<f64>> = (0..nodes.len())
        .map(|k| {
            if on_wall(k) {
                rigid.q
            } else {
                Quat::identity()
            }
        })
        .collect();
    let m = BoundaryMotion {
        nodes: &nodes,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&rotations),
        origin: Some(core::array::from_fn(|k| rigid.center[k])),
    };
    let directions = Directions::only(wall.direction);
    let mut tr = vec![[0.0; D]; n];
    let mut rot = vec![Quat::identity(); n];
    let mut scratch = vec![0.0; deform_tfi_scratch_len::<D>(block, nodes.len())];
    let mut out = vec![[0.0; D]; n];
    deform_tfi(
        block,
        directions,
        pts,
        &m,
        &mut tr,
        &mut rot,
        &mut scratch,
        &mut out,
    )
    .map_err(kernel("quaternion TFI"))?;
    Ok(out)
}

/// Displacement TFI along the wall's direction; the wall is placed exactly afterwards
/// (p + (new − p) may differ from new in the last bit).
fn displacement_tfi_d<const D: usize>(
    block: &deform_kernel::Block,
    wall: Face,
    (points, pts): (&[[f64; 3]], &[[f64; D]]),
    wall_nodes: &[u32],
    rigid: &WallMotion,
) -> Result<Vec<[f64; D]>, CliError> {
    use deform_kernel::quaternion::{displacement_tfi, tfi_scratch_len};
    let n = pts.len();
    let mut disp = vec![[0.0; D]; n];
    for &p in wall_nodes {
        let new: [f64; D] = rigid.apply(points[p as usize]);
        disp[p as usize] = core::array::from_fn(|k| new[k] - pts[p as usize][k]);
    }
    let directions = Directions::only(wall.direction);
    let mut scratch = vec![0.0; tfi_scratch_len::<D>(block)];
    displacement_tfi(block, directions, pts, &mut disp, &mut scratch)
        .map_err(kernel("displacement TFI"))?;
    let mut out: Vec<[f64; D]> = (pts.iter().zip(&disp))
        .map(|(p, d)| core::array::from_fn(|k| p[k] + d[k]))
        .collect();
    for &p in wall_nodes {
        out[p as usize] = rigid.apply(points[p as usize]);
    }
    Ok(out)
}
