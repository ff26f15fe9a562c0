//! Mesh quality: `dk_quality_*` (f64) and `dk_quality_*_f32`.
//!
//! Signed cell measures, corner Jacobians, inverted and folded cells, measure ratios and the
//! wall-angle change, for 2D points (triangles, quads) and 3D points (tetrahedra, hexahedra,
//! prisms, pyramids) in VTK node order.
//!
//! Cells cross the ABI as a `dk_cells`, as in `dk_graph_from_cells`: `offsets` (cell count + 1
//! entries), `nodes`, `kinds` (VTK codes), with offsets and node indices read in
//! `index_base` (0 or 1); with `index_base` 1 their 0-based copies go to the caller's
//! `uint32_t` `index_scratch` (`offsets_len + nodes_len` entries of the cells, plus those
//! of a wall; NULL with length 0 for `index_base` 0; no
//! allocation). Points are flat arrays of `node_count * dim` scalars (`dim` 2 or 3);
//! the node count is `points_len / dim`. Cell and node indices *returned* (in
//! `dk_quality_report`, `dk_wall_angle_change`) are in the same `index_base`, or
//! `DK_NO_INDEX` (`SIZE_MAX`; Fortran reads −1) when there is none. Reports have `double`
//! fields for both precisions (the `_f32` results are widened exactly).

use deform_kernel::quality::{
    cell_measures, cell_quality, compare, folded_cells, inverted_cells, min_corner_jacobians,
    wall_angle_change, wall_angle_scratch_len, CellQuality, QualityReport, Wall, WallAngleChange,
};
use deform_kernel::{CellKind, Cells, Real};
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, mul_len, read_points, write_len, Dim};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn, GraphIn};
use crate::slice::{out_one, output, whole_chunks_mut, In, Out};
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

/// Reads cells as 0-based arrays (with `index_base` 1, copies at the front of `scratch`, whose
/// rest is returned) and validates them over `node_count` nodes.
fn read_cells<'a>(
    cells: In<'a, dk_cells>,
    index_base: u32,
    node_count: usize,
    scratch: &'a mut [u32],
) -> Result<(Cells<'a>, &'a mut [u32]), dk_status> {
    CellsIn::read(cells)?.cells(node_count, index_base, scratch)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Quality of one cell of VTK kind `kind` from its corner coordinates (`corners_len` =
/// node count of the kind × `dim`, VTK order): signed measure, smallest corner Jacobian,
/// smallest scaled corner Jacobian. Errors (nothing written): `DK_ERR_UNKNOWN_CELL_KIND`,
/// `DK_ERR_CELL_DIMENSION` (kind does not fit `dim`), `DK_ERR_LENGTH_MISMATCH`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_INVALID_PARAMETER` (`dim`), `DK_ERR_NULL_POINTER`.
#[export(twin, out[1])]
pub(crate) fn dk_quality_cell_quality<T: Real, const D: usize>(
    kind: u8,
    corners: In<'_, T>,
    _dim: Dim<D>,
    out: Out<'_, dk_cell_quality>,
) -> Result<(), dk_status> {
    let kind = CellKind::from_vtk(kind).ok_or(dk_status::DK_ERR_UNKNOWN_CELL_KIND)?;
    let c = read_points::<T, D>(corners)?;
    let o = out_one(out)?;
    *o = dk_cell_quality::of(cell_quality(kind, c)?);
    Ok(())
}

/// Signed area (`dim` 2) or volume (`dim` 3) of every cell into `out` (one scalar per cell).
/// Positive for counter-clockwise 2D cells and VTK-positive 3D cells. Errors (nothing
/// written): cell errors as `dk_cells_check`, `DK_ERR_CELL_DIMENSION` (a kind that does not
/// fit `dim`), `DK_ERR_NON_FINITE`, length and pointer errors. With `index_base` 1,
/// `index_scratch` receives the 0-based copies of the cell arrays and needs
/// `cells->offsets_len + cells->nodes_len` entries (else `DK_ERR_BUFFER_TOO_SMALL`); with 0 it
/// may be NULL with length 0.
#[export(twin, cells[1])]
pub(crate) fn dk_quality_cell_measures<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    points: In<'_, T>,
    _dim: Dim<D>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (c, _) = read_cells(cells, index_base, p.len(), output(index_scratch)?)?;
    Ok(cell_measures(&c, p, output(out)?)?)
}

/// Smallest corner Jacobian of every cell into `out` (one scalar per cell), divided by the
/// product of the corner's edge lengths when `scaled`. Errors as
/// [`dk_quality_cell_measures`].
#[export(twin, cells[1])]
pub(crate) fn dk_quality_min_corner_jacobians<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    points: In<'_, T>,
    _dim: Dim<D>,
    scaled: bool,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (c, _) = read_cells(cells, index_base, p.len(), output(index_scratch)?)?;
    Ok(min_corner_jacobians(&c, p, scaled, output(out)?)?)
}

/// Number of cells whose signed measure changed sign between `undeformed` and `deformed`
/// (cells with zero undeformed measure never count) into `*count_out`. Errors as
/// [`dk_quality_cell_measures`] for both point arrays.
#[export(twin, cells[1], count_out[1])]
pub(crate) fn dk_quality_inverted_cells<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    count_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let (c, _) = read_cells(cells, index_base, u.len(), output(index_scratch)?)?;
    let o = out_one(count_out)?;
    *o = inverted_cells(&c, u, d)?;
    Ok(())
}

/// Number of cells with some corner Jacobian `≤ 0` (folded or inverted at a corner; also
/// catches a bow-tie quad whose net area is positive) into `*count_out`. Errors as
/// [`dk_quality_cell_measures`].
#[export(twin, cells[1], count_out[1])]
pub(crate) fn dk_quality_folded_cells<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    points: In<'_, T>,
    _dim: Dim<D>,
    count_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (c, _) = read_cells(cells, index_base, p.len(), output(index_scratch)?)?;
    let o = out_one(count_out)?;
    *o = folded_cells(&c, p)?;
    Ok(())
}

/// Scalars of `scratch` [`dk_quality_wall_angle_change`] (and [`dk_quality_compare`] with a
/// wall) needs: `2 * node_count * dim`.
#[export(len_out[1])]
pub(crate) fn dk_quality_wall_angle_scratch_len(
    node_count: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    if node_count > usize::MAX / 2 {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    let len = mul_len(wall_angle_scratch_len(node_count), dim as usize)?;
    write_len(len_out, len)
}

/// Compares `deformed` against `undeformed` over the cells in one call: inverted and folded
/// cells, measure ratios, smallest measure and scaled Jacobian, and, when a wall is given,
/// the wall-angle change (as [`dk_quality_wall_angle_change`]). The wall is its elements
/// (`*wall`: lines for `dim` 2, triangles or quads for `dim` 3, in the same `index_base` as
/// the cells) and the mesh's 0-based CSR edge graph (`*graph`); pass both structs with every
/// array NULL with length 0 for no wall (then `scratch` may be NULL with `scratch_len` 0; with
/// a wall it needs [`dk_quality_wall_angle_scratch_len`] scalars). `index_scratch` as in
/// [`dk_quality_cell_measures`], with `wall->offsets_len + wall->nodes_len` more entries for
/// a wall. Errors (nothing written): as
/// [`dk_quality_cell_measures`] for both point arrays and as
/// [`dk_quality_wall_angle_change`] for the wall.
#[export(twin, cells[1], wall[1], graph[1], report[1])]
pub(crate) fn dk_quality_compare<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    wall: In<'_, dk_cells>,
    graph: In<'_, dk_graph>,
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_quality_report>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let (c, index_rest) = read_cells(cells, index_base, u.len(), output(index_scratch)?)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let absent = CellsIn::read(wall)?.is_absent() && GraphIn::read(graph)?.is_absent();
    let rep = if absent {
        compare(&c, u, d, None, s)
    } else {
        let (we, _) = read_cells(wall, index_base, u.len(), index_rest)?;
        let w = Wall::new(we, read_graph(graph)?)?;
        compare(&c, u, d, Some(&w), s)
    }?;
    *r = dk_quality_report::of(rep, index_base);
    Ok(())
}

/// Change of the first grid-line angle at a wall, in radians (boundary-layer orthogonality):
/// for every wall node, the angle between the wall normal and its most normal off-wall edge,
/// undeformed vs deformed; `*out` receives the maximum change, its node (in `index_base`) and
/// the counts of measured and skipped wall nodes. The wall elements (`*wall`, read with
/// `index_base`: lines for `dim` 2, triangles or quads for `dim` 3, consistently oriented)
/// index the mesh nodes; `*graph` is the mesh's 0-based CSR edge graph. `scratch` needs
/// [`dk_quality_wall_angle_scratch_len`] scalars; with `index_base` 1, `index_scratch` needs
/// `wall->offsets_len + wall->nodes_len` entries (NULL with 0 for `index_base` 0). Errors (nothing written): cell and graph
/// errors, `DK_ERR_CELL_DIMENSION` (wrong element kind), `DK_ERR_NON_FINITE`, length and
/// pointer errors.
#[export(twin, wall[1], graph[1], out[1])]
pub(crate) fn dk_quality_wall_angle_change<T: Real, const D: usize>(
    wall: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    out: Out<'_, dk_wall_angle_change>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let (we, _) = read_cells(wall, index_base, u.len(), output(index_scratch)?)?;
    let w = Wall::new(we, read_graph(graph)?)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let o = out_one(out)?;
    *o = dk_wall_angle_change::of(wall_angle_change(&w, u, d, s)?, index_base);
    Ok(())
}
