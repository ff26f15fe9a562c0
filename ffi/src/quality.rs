//! Mesh quality: `dk_quality_*` (f64) and `dk_quality_*_f32`.
//!
//! Signed cell measures, corner Jacobians, inverted and folded cells, measure ratios and the
//! wall-angle change, for 2D points (triangles, quads) and 3D points (tetrahedra, hexahedra,
//! prisms, pyramids) in VTK node order.
//!
//! Cells cross the ABI exactly as in `dk_graph_from_cells`: `cell_offsets` (cell count + 1
//! entries), `cell_nodes`, `cell_kinds` (VTK codes), with offsets and node indices read in
//! `index_base` (0 or 1). Points are flat arrays of `node_count * dim` scalars (`dim` 2 or 3);
//! the node count is `points_len / dim`. Cell and node indices *returned* (in
//! `dk_quality_report`, `dk_wall_angle_change`) are in the same `index_base`, or
//! `DK_NO_INDEX` (`SIZE_MAX`; Fortran reads −1) when there is none. Reports have `double`
//! fields for both precisions (the `_f32` results are widened exactly).
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::quality::{
    cell_measures, cell_quality, compare, folded_cells, inverted_cells, min_corner_jacobians,
    wall_angle_change, wall_angle_scratch_len, CellQuality, QualityReport, Wall, WallAngleChange,
};
use deform_kernel::{CellKind, Cells, Real};

use crate::args::{assert_layout, by_dim, done, graph, mul_len, read_points, write_len};
use crate::graph::{read_cells, OwnedCells};
use crate::slice::{chunks_mut, out_one, output, In, Out};
use crate::status::dk_status;

/// "No such index" in the quality reports: `SIZE_MAX`.
pub const DK_NO_INDEX: usize = -1isize as usize;

/// Signed measure and corner-Jacobian summary of one cell (`dk_quality_cell_quality`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_cell_quality {
    /// Signed area (2D) or volume (3D); positive for a correctly oriented cell.
    pub measure: f64,
    /// Smallest corner Jacobian; `≤ 0` means the cell is folded at that corner.
    pub min_jacobian: f64,
    /// Smallest corner Jacobian divided by the product of its edge lengths, in `[−1, 1]`.
    pub min_scaled_jacobian: f64,
}
assert_layout!(dk_cell_quality, 24; measure = 0, min_jacobian = 8, min_scaled_jacobian = 16);

impl dk_cell_quality {
    fn of<T: Real>(q: CellQuality<T>) -> Self {
        dk_cell_quality {
            measure: q.measure.to_f64(),
            min_jacobian: q.min_jacobian.to_f64(),
            min_scaled_jacobian: q.min_scaled_jacobian.to_f64(),
        }
    }
}

/// Result of `dk_quality_wall_angle_change`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_wall_angle_change {
    /// Largest change of the first grid-line angle over the measured wall nodes, in radians
    /// (0 when no node was measured).
    pub max_change: f64,
    /// The wall node where it occurs (in `index_base`), or `DK_NO_INDEX`.
    pub node: usize,
    /// Wall nodes measured.
    pub measured: usize,
    /// Wall nodes skipped (no off-wall neighbour, zero normal or zero-length edge).
    pub skipped: usize,
}
#[cfg(target_pointer_width = "64")]
assert_layout!(dk_wall_angle_change, 32; max_change = 0, node = 8, measured = 16, skipped = 24);

/// An optional 0-based index as `index_base` or `DK_NO_INDEX`.
fn based(i: Option<usize>, index_base: u32) -> usize {
    match i {
        Some(i) => i.saturating_add(index_base as usize),
        None => DK_NO_INDEX,
    }
}

impl dk_wall_angle_change {
    fn of<T: Real>(w: WallAngleChange<T>, index_base: u32) -> Self {
        dk_wall_angle_change {
            max_change: w.max_change.to_f64(),
            node: based(w.node, index_base),
            measured: w.measured,
            skipped: w.skipped,
        }
    }
}

/// One-call comparison of a deformed mesh against the undeformed one (`dk_quality_compare`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_quality_report {
    /// Number of cells.
    pub cells: usize,
    /// Cells whose signed measure changed sign.
    pub inverted_cells: usize,
    /// Deformed cells with some corner Jacobian `≤ 0`.
    pub folded_cells: usize,
    /// Undeformed cells with some corner Jacobian `≤ 0` (0 for a valid input mesh).
    pub folded_cells_undeformed: usize,
    /// Cells with zero undeformed measure (excluded from the ratios).
    pub degenerate_cells: usize,
    /// Cell of `min_measure_ratio` (in `index_base`, first on ties), or `DK_NO_INDEX`.
    pub min_ratio_cell: usize,
    /// Cell of `max_measure_ratio` (in `index_base`, first on ties), or `DK_NO_INDEX`.
    pub max_ratio_cell: usize,
    /// The wall node of `wall.max_change` (in `index_base`), or `DK_NO_INDEX`.
    pub wall_node: usize,
    /// Wall nodes measured (0 without a wall).
    pub wall_measured: usize,
    /// Wall nodes skipped (0 without a wall).
    pub wall_skipped: usize,
    /// Smallest deformed/undeformed measure ratio (`+∞` when no cell has one); negative when
    /// some cell inverted.
    pub min_measure_ratio: f64,
    /// Largest deformed/undeformed measure ratio (`−∞` when no cell has one).
    pub max_measure_ratio: f64,
    /// Smallest deformed measure (`+∞` for an empty mesh).
    pub min_measure: f64,
    /// Smallest scaled corner Jacobian of the deformed mesh (`+∞` for an empty mesh).
    pub min_scaled_jacobian: f64,
    /// Largest wall-angle change in radians (0 without a wall).
    pub wall_max_change: f64,
    /// Whether a wall was given (the `wall_*` fields are meaningful).
    pub has_wall: bool,
}
#[cfg(target_pointer_width = "64")]
assert_layout!(
    dk_quality_report, 128;
    cells = 0, inverted_cells = 8, folded_cells = 16, folded_cells_undeformed = 24,
    degenerate_cells = 32, min_ratio_cell = 40, max_ratio_cell = 48, wall_node = 56,
    wall_measured = 64, wall_skipped = 72, min_measure_ratio = 80, max_measure_ratio = 88,
    min_measure = 96, min_scaled_jacobian = 104, wall_max_change = 112, has_wall = 120,
);

impl dk_quality_report {
    fn of<T: Real>(r: QualityReport<T>, index_base: u32) -> Self {
        let w = r.wall.map(|w| dk_wall_angle_change::of(w, index_base));
        dk_quality_report {
            cells: r.cells,
            inverted_cells: r.inverted_cells,
            folded_cells: r.folded_cells,
            folded_cells_undeformed: r.folded_cells_undeformed,
            degenerate_cells: r.degenerate_cells,
            min_ratio_cell: based(r.min_ratio_cell, index_base),
            max_ratio_cell: based(r.max_ratio_cell, index_base),
            wall_node: w.map_or(DK_NO_INDEX, |w| w.node),
            wall_measured: w.map_or(0, |w| w.measured),
            wall_skipped: w.map_or(0, |w| w.skipped),
            min_measure_ratio: r.min_measure_ratio.to_f64(),
            max_measure_ratio: r.max_measure_ratio.to_f64(),
            min_measure: r.min_measure.to_f64(),
            min_scaled_jacobian: r.min_scaled_jacobian.to_f64(),
            wall_max_change: w.map_or(0.0, |w| w.max_change),
            has_wall: w.is_some(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Argument handling.
// ---------------------------------------------------------------------------------------------

/// A caller's cell arrays (as `dk_graph_from_cells` takes them).
#[derive(Clone, Copy)]
struct CellArgs<'a> {
    offsets: In<'a, u32>,
    offsets_len: usize,
    nodes: In<'a, u32>,
    nodes_len: usize,
    kinds: In<'a, u8>,
    kinds_len: usize,
    index_base: u32,
}

impl<'a> CellArgs<'a> {
    /// Reads the cells into owned 0-based arrays (validated later against the node count).
    fn read(&self) -> Result<OwnedCells<'_>, dk_status> {
        read_cells(
            self.offsets,
            self.offsets_len,
            self.nodes,
            self.nodes_len,
            self.kinds,
            self.kinds_len,
            self.index_base,
        )
    }
}

/// Validates owned cell arrays over `node_count` nodes.
fn cells_of<'a>(owned: &'a OwnedCells<'_>, node_count: usize) -> Result<Cells<'a>, dk_status> {
    let (o, n, k) = owned;
    Cells::new(node_count, o, n, k).map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// Generic inner functions.
// ---------------------------------------------------------------------------------------------

fn cell_quality_d<T: Real, const D: usize>(
    kind: u8,
    corners: In<'_, T>,
    corners_len: usize,
    out: Out<'_, dk_cell_quality>,
) -> Result<(), dk_status> {
    let kind = CellKind::from_vtk(kind).ok_or(dk_status::DK_ERR_UNKNOWN_CELL_KIND)?;
    let c = read_points::<T, D>(corners, corners_len)?;
    let o = out_one(out)?;
    *o = dk_cell_quality::of(cell_quality(kind, c).map_err(dk_status::from)?);
    Ok(())
}

fn cell_quality_t<T: Real>(
    kind: u8,
    corners: In<'_, T>,
    corners_len: usize,
    dim: u32,
    out: Out<'_, dk_cell_quality>,
) -> dk_status {
    done(by_dim!(
        dim,
        cell_quality_d::<T>,
        (kind, corners, corners_len, out)
    ))
}

/// Per-cell output: measures (`jacobians` None) or minimum corner Jacobians.
fn per_cell_d<T: Real, const D: usize>(
    cells: CellArgs,
    pts: In<'_, T>,
    pts_len: usize,
    jacobians: Option<bool>,
    out: Out<'_, T>,
    out_len: usize,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(pts, pts_len)?;
    let owned = cells.read()?;
    let c = cells_of(&owned, p.len())?;
    let o = output(out, out_len)?;
    match jacobians {
        None => cell_measures(&c, p, o),
        Some(scaled) => min_corner_jacobians(&c, p, scaled, o),
    }
    .map_err(dk_status::from)
}

#[allow(clippy::too_many_arguments)]
fn per_cell_t<T: Real>(
    cells: CellArgs,
    pts: In<'_, T>,
    pts_len: usize,
    dim: u32,
    jacobians: Option<bool>,
    out: Out<'_, T>,
    out_len: usize,
) -> dk_status {
    done(by_dim!(
        dim,
        per_cell_d::<T>,
        (cells, pts, pts_len, jacobians, out, out_len)
    ))
}

#[allow(clippy::too_many_arguments)]
fn inverted_d<T: Real, const D: usize>(
    cells: CellArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    count_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed, undeformed_len)?;
    let d = read_points::<T, D>(deformed, deformed_len)?;
    let owned = cells.read()?;
    let c = cells_of(&owned, u.len())?;
    let o = out_one(count_out)?;
    *o = inverted_cells(&c, u, d).map_err(dk_status::from)?;
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn inverted_t<T: Real>(
    cells: CellArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    dim: u32,
    count_out: Out<'_, usize>,
) -> dk_status {
    done(by_dim!(
        dim,
        inverted_d::<T>,
        (
            cells,
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            count_out
        )
    ))
}

fn folded_d<T: Real, const D: usize>(
    cells: CellArgs,
    pts: In<'_, T>,
    pts_len: usize,
    count_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(pts, pts_len)?;
    let owned = cells.read()?;
    let c = cells_of(&owned, p.len())?;
    let o = out_one(count_out)?;
    *o = folded_cells(&c, p).map_err(dk_status::from)?;
    Ok(())
}

fn folded_t<T: Real>(
    cells: CellArgs,
    pts: In<'_, T>,
    pts_len: usize,
    dim: u32,
    count_out: Out<'_, usize>,
) -> dk_status {
    done(by_dim!(
        dim,
        folded_d::<T>,
        (cells, pts, pts_len, count_out)
    ))
}

/// The arguments describing a wall: its elements (cells, in the mesh's `index_base`) and the
/// mesh's 0-based CSR edge graph.
#[derive(Clone, Copy)]
struct WallArgs<'a> {
    elements: CellArgs<'a>,
    graph_offsets: In<'a, u32>,
    graph_offsets_len: usize,
    graph_targets: In<'a, u32>,
    graph_targets_len: usize,
}

impl<'a> WallArgs<'a> {
    /// `true` when no wall was given (every wall pointer NULL, every length 0).
    fn absent(&self) -> bool {
        let e = &self.elements;
        e.offsets.is_null()
            && e.offsets_len == 0
            && e.nodes.is_null()
            && e.nodes_len == 0
            && e.kinds.is_null()
            && e.kinds_len == 0
            && self.graph_offsets.is_null()
            && self.graph_offsets_len == 0
            && self.graph_targets.is_null()
            && self.graph_targets_len == 0
    }
}

#[allow(clippy::too_many_arguments)]
fn compare_d<T: Real, const D: usize>(
    cells: CellArgs,
    wall: WallArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_quality_report>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed, undeformed_len)?;
    let d = read_points::<T, D>(deformed, deformed_len)?;
    let owned = cells.read()?;
    let c = cells_of(&owned, u.len())?;
    let scratch_len = scratch_len - scratch_len % D;
    let s = chunks_mut::<T, D>(scratch, scratch_len)?;
    let r = out_one(report)?;
    let rep = if wall.absent() {
        compare(&c, u, d, None, s)
    } else {
        let wowned = wall.elements.read()?;
        let we = cells_of(&wowned, u.len())?;
        let g = graph(
            wall.graph_offsets,
            wall.graph_offsets_len,
            wall.graph_targets,
            wall.graph_targets_len,
        )?;
        let w = Wall::new(we, g).map_err(dk_status::from)?;
        compare(&c, u, d, Some(&w), s)
    }
    .map_err(dk_status::from)?;
    *r = dk_quality_report::of(rep, cells.index_base);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn compare_t<T: Real>(
    cells: CellArgs,
    wall: WallArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    dim: u32,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_quality_report>,
) -> dk_status {
    done(by_dim!(
        dim,
        compare_d::<T>,
        (
            cells,
            wall,
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            scratch,
            scratch_len,
            report
        )
    ))
}

#[allow(clippy::too_many_arguments)]
fn wall_angle_d<T: Real, const D: usize>(
    wall: WallArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    out: Out<'_, dk_wall_angle_change>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed, undeformed_len)?;
    let d = read_points::<T, D>(deformed, deformed_len)?;
    let wowned = wall.elements.read()?;
    let we = cells_of(&wowned, u.len())?;
    let g = graph(
        wall.graph_offsets,
        wall.graph_offsets_len,
        wall.graph_targets,
        wall.graph_targets_len,
    )?;
    let w = Wall::new(we, g).map_err(dk_status::from)?;
    let scratch_len = scratch_len - scratch_len % D;
    let s = chunks_mut::<T, D>(scratch, scratch_len)?;
    let o = out_one(out)?;
    let r = wall_angle_change(&w, u, d, s).map_err(dk_status::from)?;
    *o = dk_wall_angle_change::of(r, wall.elements.index_base);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn wall_angle_t<T: Real>(
    wall: WallArgs,
    undeformed: In<'_, T>,
    undeformed_len: usize,
    deformed: In<'_, T>,
    deformed_len: usize,
    dim: u32,
    scratch: Out<'_, T>,
    scratch_len: usize,
    out: Out<'_, dk_wall_angle_change>,
) -> dk_status {
    done(by_dim!(
        dim,
        wall_angle_d::<T>,
        (
            wall,
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            scratch,
            scratch_len,
            out
        )
    ))
}

// ---------------------------------------------------------------------------------------------
// Public functions.
// ---------------------------------------------------------------------------------------------

/// Quality of one cell of VTK kind `kind` from its corner coordinates (`corners_len` =
/// node count of the kind × `dim`, VTK order): signed measure, smallest corner Jacobian,
/// smallest scaled corner Jacobian. Errors (nothing written): `DK_ERR_UNKNOWN_CELL_KIND`,
/// `DK_ERR_CELL_DIMENSION` (kind does not fit `dim`), `DK_ERR_LENGTH_MISMATCH`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_INVALID_PARAMETER` (`dim`), `DK_ERR_NULL_POINTER`.
///
/// # Safety
/// `corners` readable for `corners_len` scalars; `out` points to one writable struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_cell_quality(
    kind: u8,
    corners: *const f64,
    corners_len: usize,
    dim: u32,
    out: *mut dk_cell_quality,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (corners, out) = unsafe { (In::new(corners, corners_len), Out::new(out, 1)) };
    cell_quality_t(kind, corners, corners_len, dim, out)
}

/// `f32` twin of [`dk_quality_cell_quality`].
///
/// # Safety
/// As [`dk_quality_cell_quality`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_cell_quality_f32(
    kind: u8,
    corners: *const f32,
    corners_len: usize,
    dim: u32,
    out: *mut dk_cell_quality,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (corners, out) = unsafe { (In::new(corners, corners_len), Out::new(out, 1)) };
    cell_quality_t(kind, corners, corners_len, dim, out)
}

/// Signed area (`dim` 2) or volume (`dim` 3) of every cell into `out` (one scalar per cell).
/// Positive for counter-clockwise 2D cells and VTK-positive 3D cells. Errors (nothing
/// written): cell errors as `dk_cells_check`, `DK_ERR_CELL_DIMENSION` (a kind that does not
/// fit `dim`), `DK_ERR_NON_FINITE`, length and pointer errors.
///
/// # Safety
/// The cell arrays and `points` are readable for their lengths; `out` writable for `out_len`
/// scalars, not overlapping the inputs.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_cell_measures(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    out: *mut f64,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    per_cell_t(cells, points, points_len, dim, None, out, out_len)
}

/// `f32` twin of [`dk_quality_cell_measures`].
///
/// # Safety
/// As [`dk_quality_cell_measures`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_cell_measures_f32(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    out: *mut f32,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    per_cell_t(cells, points, points_len, dim, None, out, out_len)
}

/// Smallest corner Jacobian of every cell into `out` (one scalar per cell), divided by the
/// product of the corner's edge lengths when `scaled`. Errors as
/// [`dk_quality_cell_measures`].
///
/// # Safety
/// As [`dk_quality_cell_measures`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_min_corner_jacobians(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    scaled: bool,
    out: *mut f64,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    per_cell_t(cells, points, points_len, dim, Some(scaled), out, out_len)
}

/// `f32` twin of [`dk_quality_min_corner_jacobians`].
///
/// # Safety
/// As [`dk_quality_min_corner_jacobians`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_min_corner_jacobians_f32(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    scaled: bool,
    out: *mut f32,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    per_cell_t(cells, points, points_len, dim, Some(scaled), out, out_len)
}

/// Number of cells whose signed measure changed sign between `undeformed` and `deformed`
/// (cells with zero undeformed measure never count) into `*count_out`. Errors as
/// [`dk_quality_cell_measures`] for both point arrays.
///
/// # Safety
/// The cell arrays and point arrays are readable for their lengths; `count_out` points to one
/// writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_inverted_cells(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    count_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, undeformed, deformed, count_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(count_out, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    inverted_t(
        cells,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        count_out,
    )
}

/// `f32` twin of [`dk_quality_inverted_cells`].
///
/// # Safety
/// As [`dk_quality_inverted_cells`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_inverted_cells_f32(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    count_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, undeformed, deformed, count_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(count_out, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    inverted_t(
        cells,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        count_out,
    )
}

/// Number of cells with some corner Jacobian `≤ 0` (folded or inverted at a corner; also
/// catches a bow-tie quad whose net area is positive) into `*count_out`. Errors as
/// [`dk_quality_cell_measures`].
///
/// # Safety
/// The cell arrays and `points` are readable for their lengths; `count_out` points to one
/// writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_folded_cells(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    count_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, count_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(count_out, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    folded_t(cells, points, points_len, dim, count_out)
}

/// `f32` twin of [`dk_quality_folded_cells`].
///
/// # Safety
/// As [`dk_quality_folded_cells`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_folded_cells_f32(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    count_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (cell_offsets, cell_nodes, cell_kinds, points, count_out) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(points, points_len),
            Out::new(count_out, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    folded_t(cells, points, points_len, dim, count_out)
}

/// Scalars of `scratch` [`dk_quality_wall_angle_change`] (and [`dk_quality_compare`] with a
/// wall) needs: `2 * node_count * dim`.
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_wall_angle_scratch_len(
    node_count: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    done((|| {
        if !(2..=3).contains(&dim) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        if node_count > usize::MAX / 2 {
            return Err(dk_status::DK_ERR_TOO_LARGE);
        }
        write_len(
            len_out,
            mul_len(wall_angle_scratch_len(node_count), dim as usize)?,
        )
    })())
}

/// Compares `deformed` against `undeformed` over the cells in one call: inverted and folded
/// cells, measure ratios, smallest measure and scaled Jacobian, and, when a wall is given,
/// the wall-angle change (as [`dk_quality_wall_angle_change`]). The wall is its elements
/// (`wall_offsets`/`wall_nodes`/`wall_kinds`, lines for `dim` 2, triangles or quads for
/// `dim` 3, in the same `index_base` as the cells) and the mesh's 0-based CSR edge graph
/// (`graph_offsets`/`graph_targets`); pass all six wall pointers NULL with length 0 for no
/// wall (then `scratch` may be NULL with `scratch_len` 0; with a wall it needs
/// [`dk_quality_wall_angle_scratch_len`] scalars). Errors (nothing written): as
/// [`dk_quality_cell_measures`] for both point arrays and as
/// [`dk_quality_wall_angle_change`] for the wall.
///
/// # Safety
/// Every input array is NULL with length 0 or readable for its length; `scratch` writable for
/// `scratch_len` scalars; `report` points to one writable report; writable buffers overlap
/// nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_compare(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    wall_offsets: *const u32,
    wall_offsets_len: usize,
    wall_nodes: *const u32,
    wall_nodes_len: usize,
    wall_kinds: *const u8,
    wall_kinds_len: usize,
    graph_offsets: *const u32,
    graph_offsets_len: usize,
    graph_targets: *const u32,
    graph_targets_len: usize,
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    scratch: *mut f64,
    scratch_len: usize,
    report: *mut dk_quality_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        cell_offsets,
        cell_nodes,
        cell_kinds,
        wall_offsets,
        wall_nodes,
        wall_kinds,
        graph_offsets,
        graph_targets,
        undeformed,
        deformed,
        scratch,
        report,
    ) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(wall_offsets, wall_offsets_len),
            In::new(wall_nodes, wall_nodes_len),
            In::new(wall_kinds, wall_kinds_len),
            In::new(graph_offsets, graph_offsets_len),
            In::new(graph_targets, graph_targets_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(scratch, scratch_len),
            Out::new(report, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    let wall = WallArgs {
        elements: CellArgs {
            offsets: wall_offsets,
            offsets_len: wall_offsets_len,
            nodes: wall_nodes,
            nodes_len: wall_nodes_len,
            kinds: wall_kinds,
            kinds_len: wall_kinds_len,
            index_base,
        },
        graph_offsets,
        graph_offsets_len,
        graph_targets,
        graph_targets_len,
    };
    compare_t(
        cells,
        wall,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        scratch,
        scratch_len,
        report,
    )
}

/// `f32` twin of [`dk_quality_compare`].
///
/// # Safety
/// As [`dk_quality_compare`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_compare_f32(
    cell_offsets: *const u32,
    cell_offsets_len: usize,
    cell_nodes: *const u32,
    cell_nodes_len: usize,
    cell_kinds: *const u8,
    cell_kinds_len: usize,
    index_base: u32,
    wall_offsets: *const u32,
    wall_offsets_len: usize,
    wall_nodes: *const u32,
    wall_nodes_len: usize,
    wall_kinds: *const u8,
    wall_kinds_len: usize,
    graph_offsets: *const u32,
    graph_offsets_len: usize,
    graph_targets: *const u32,
    graph_targets_len: usize,
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    scratch: *mut f32,
    scratch_len: usize,
    report: *mut dk_quality_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        cell_offsets,
        cell_nodes,
        cell_kinds,
        wall_offsets,
        wall_nodes,
        wall_kinds,
        graph_offsets,
        graph_targets,
        undeformed,
        deformed,
        scratch,
        report,
    ) = unsafe {
        (
            In::new(cell_offsets, cell_offsets_len),
            In::new(cell_nodes, cell_nodes_len),
            In::new(cell_kinds, cell_kinds_len),
            In::new(wall_offsets, wall_offsets_len),
            In::new(wall_nodes, wall_nodes_len),
            In::new(wall_kinds, wall_kinds_len),
            In::new(graph_offsets, graph_offsets_len),
            In::new(graph_targets, graph_targets_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(scratch, scratch_len),
            Out::new(report, 1),
        )
    };
    let cells = CellArgs {
        offsets: cell_offsets,
        offsets_len: cell_offsets_len,
        nodes: cell_nodes,
        nodes_len: cell_nodes_len,
        kinds: cell_kinds,
        kinds_len: cell_kinds_len,
        index_base,
    };
    let wall = WallArgs {
        elements: CellArgs {
            offsets: wall_offsets,
            offsets_len: wall_offsets_len,
            nodes: wall_nodes,
            nodes_len: wall_nodes_len,
            kinds: wall_kinds,
            kinds_len: wall_kinds_len,
            index_base,
        },
        graph_offsets,
        graph_offsets_len,
        graph_targets,
        graph_targets_len,
    };
    compare_t(
        cells,
        wall,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        scratch,
        scratch_len,
        report,
    )
}

/// Change of the first grid-line angle at a wall, in radians (boundary-layer orthogonality):
/// for every wall node, the angle between the wall normal and its most normal off-wall edge,
/// undeformed vs deformed; `*out` receives the maximum change, its node (in `index_base`) and
/// the counts of measured and skipped wall nodes. The wall elements (`wall_offsets`,
/// `wall_nodes`, `wall_kinds`, read with `index_base`: lines for `dim` 2, triangles or quads
/// for `dim` 3, consistently oriented) index the mesh nodes; `graph_offsets`/`graph_targets`
/// is the mesh's 0-based CSR edge graph. `scratch` needs
/// [`dk_quality_wall_angle_scratch_len`] scalars. Errors (nothing written): cell and graph
/// errors, `DK_ERR_CELL_DIMENSION` (wrong element kind), `DK_ERR_NON_FINITE`, length and
/// pointer errors.
///
/// # Safety
/// Every input array is readable for its length; `scratch` writable for `scratch_len`
/// scalars; `out` points to one writable struct; writable buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_wall_angle_change(
    wall_offsets: *const u32,
    wall_offsets_len: usize,
    wall_nodes: *const u32,
    wall_nodes_len: usize,
    wall_kinds: *const u8,
    wall_kinds_len: usize,
    index_base: u32,
    graph_offsets: *const u32,
    graph_offsets_len: usize,
    graph_targets: *const u32,
    graph_targets_len: usize,
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    scratch: *mut f64,
    scratch_len: usize,
    out: *mut dk_wall_angle_change,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        wall_offsets,
        wall_nodes,
        wall_kinds,
        graph_offsets,
        graph_targets,
        undeformed,
        deformed,
        scratch,
        out,
    ) = unsafe {
        (
            In::new(wall_offsets, wall_offsets_len),
            In::new(wall_nodes, wall_nodes_len),
            In::new(wall_kinds, wall_kinds_len),
            In::new(graph_offsets, graph_offsets_len),
            In::new(graph_targets, graph_targets_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(scratch, scratch_len),
            Out::new(out, 1),
        )
    };
    let wall = WallArgs {
        elements: CellArgs {
            offsets: wall_offsets,
            offsets_len: wall_offsets_len,
            nodes: wall_nodes,
            nodes_len: wall_nodes_len,
            kinds: wall_kinds,
            kinds_len: wall_kinds_len,
            index_base,
        },
        graph_offsets,
        graph_offsets_len,
        graph_targets,
        graph_targets_len,
    };
    wall_angle_t(
        wall,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        scratch,
        scratch_len,
        out,
    )
}

/// `f32` twin of [`dk_quality_wall_angle_change`].
///
/// # Safety
/// As [`dk_quality_wall_angle_change`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quality_wall_angle_change_f32(
    wall_offsets: *const u32,
    wall_offsets_len: usize,
    wall_nodes: *const u32,
    wall_nodes_len: usize,
    wall_kinds: *const u8,
    wall_kinds_len: usize,
    index_base: u32,
    graph_offsets: *const u32,
    graph_offsets_len: usize,
    graph_targets: *const u32,
    graph_targets_len: usize,
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    scratch: *mut f32,
    scratch_len: usize,
    out: *mut dk_wall_angle_change,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        wall_offsets,
        wall_nodes,
        wall_kinds,
        graph_offsets,
        graph_targets,
        undeformed,
        deformed,
        scratch,
        out,
    ) = unsafe {
        (
            In::new(wall_offsets, wall_offsets_len),
            In::new(wall_nodes, wall_nodes_len),
            In::new(wall_kinds, wall_kinds_len),
            In::new(graph_offsets, graph_offsets_len),
            In::new(graph_targets, graph_targets_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(scratch, scratch_len),
            Out::new(out, 1),
        )
    };
    let wall = WallArgs {
        elements: CellArgs {
            offsets: wall_offsets,
            offsets_len: wall_offsets_len,
            nodes: wall_nodes,
            nodes_len: wall_nodes_len,
            kinds: wall_kinds,
            kinds_len: wall_kinds_len,
            index_base,
        },
        graph_offsets,
        graph_offsets_len,
        graph_targets,
        graph_targets_len,
    };
    wall_angle_t(
        wall,
        undeformed,
        undeformed_len,
        deformed,
        deformed_len,
        dim,
        scratch,
        scratch_len,
        out,
    )
}
