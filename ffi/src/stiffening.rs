//! Stiffness choices beyond Batina's `1/L`, as SU2's `DEFORM_STIFFNESS_TYPE`:
//! `dk_spring_wall_distances`, `dk_spring_wall_distance_factors` (`WALL_DISTANCE`),
//! `dk_spring_dual_volumes`, `dk_spring_inverse_volume_factors` (`INVERSE_VOLUME`) and
//! `dk_spring_scale_stiffness`, which multiplies a stiffness by the nodes' factors (the
//! kernel's `spring::stiffening`). The scaled stiffness goes to the solvers, `dk_deform_spring`
//! or a plan (`dk_plan_init`'s `stiffness`).
//!
//! Wall nodes and cells are read in `index_base` 0 or 1; with 1 the 0-based copies go to the
//! caller's `uint32_t` `index_scratch` (`wall_len`, or `cells->offsets_len + cells->nodes_len`
//! entries).

use deform_kernel::spring::{
    dual_volumes, inverse_volume_factors, scale_stiffness, wall_distance_factors, wall_distances,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{read_points, rebase, Dim};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::slice::{input, output, In, Out};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// The distance from every node to the nearest node of `wall` (node indices in `index_base`)
/// into `out` (one scalar per node; wall nodes get 0): exact distances to the wall nodes, an
/// upper bound of the distance to the wall surface by at most half a wall element's
/// diagonal. `O(N·B)`: about 0.5 s for a 2D mesh of 234k nodes and 1,024 wall nodes; for large
/// 3D meshes pass distances of your own to [`dk_spring_wall_distance_factors`].
/// `points`: `N * dim` scalars, `dim` 2 or 3. With `index_base` 1, `index_scratch` needs
/// `wall_len` entries (NULL with length 0 for base 0). Errors (nothing written to `out`):
/// `DK_ERR_INVALID_PARAMETER` (empty wall, `dim`), `DK_ERR_INDEX_OUT_OF_RANGE`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_BUFFER_TOO_SMALL`, length and pointer
/// errors.
#[export(twin)]
pub(crate) fn dk_spring_wall_distances<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    wall: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (w, _) = rebase(input(wall)?, index_base, output(index_scratch)?)?;
    Ok(wall_distances(p, w, output(out)?)?)
}

/// Turns wall distances into stiffness factors in place (SU2's `WALL_DISTANCE`):
/// `d ← (d̄ / max(d, 10⁻³ d̄))^exponent`, `d̄` the mean distance, so the median spring keeps a
/// factor of order one and the first cells off the wall are the stiffest. `exponent` 1 is
/// SU2's `1/d`. Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (`exponent` negative or
/// not finite, or factors that overflow), `DK_ERR_NON_FINITE`, an empty array
/// (`DK_ERR_INVALID_PARAMETER`), pointer errors.
#[export(twin)]
pub(crate) fn dk_spring_wall_distance_factors<T: Real>(
    distances: Out<'_, T>,
    exponent: T,
) -> Result<(), dk_status> {
    Ok(wall_distance_factors(output(distances)?, exponent)?)
}

/// The dual volume of every node (each cell's absolute area or volume shared equally among
/// its nodes) into `out` (one scalar per node). Cells as `dk_graph_from_cells` takes them;
/// with `index_base` 1, `index_scratch` needs `cells->offsets_len + cells->nodes_len` entries
/// (NULL with length 0 for base 0). `scratch` needs one scalar per cell (`cells->kinds_len`).
/// Errors (nothing written to `out`): cell errors, `DK_ERR_CELL_DIMENSION`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_INVALID_PARAMETER` (`dim`), length and pointer errors.
#[export(twin, cells[1])]
pub(crate) fn dk_spring_dual_volumes<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    points: In<'_, T>,
    _dim: Dim<D>,
    out: Out<'_, T>,
    scratch: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let s = output(index_scratch)?;
    let (c, _) = CellsIn::read(cells)?.cells(p.len(), index_base, s)?;
    Ok(dual_volumes(&c, p, output(out)?, output(scratch)?)?)
}

/// Turns dual volumes into stiffness factors in place (SU2's `INVERSE_VOLUME`):
/// `v ← (v̄ / max(v, 10⁻¹² v̄))^exponent`, `v̄` the mean volume: small cells get stiff springs.
/// Errors as [`dk_spring_wall_distance_factors`].
#[export(twin)]
pub(crate) fn dk_spring_inverse_volume_factors<T: Real>(
    volumes: Out<'_, T>,
    exponent: T,
) -> Result<(), dk_status> {
    Ok(inverse_volume_factors(output(volumes)?, exponent)?)
}

/// Multiplies every directed edge's stiffness by the mean factor of its two nodes, in place:
/// `k_ij ← k_ij (f_i + f_j) / 2`; an exactly symmetric stiffness stays exactly symmetric (as
/// the solvers require). `factors`: one per node (from the two `*_factors` functions or your
/// own, finite and positive); `stiffness`: one per directed edge of the 0-based CSR graph.
/// Errors (nothing written): `DK_ERR_LENGTH_MISMATCH`, `DK_ERR_NON_FINITE`,
/// `DK_ERR_NON_POSITIVE`, graph and pointer errors.
#[export(twin, graph[1])]
pub(crate) fn dk_spring_scale_stiffness<T: Real>(
    graph: In<'_, dk_graph>,
    factors: In<'_, T>,
    stiffness: Out<'_, T>,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    let f = input(factors)?;
    scale_stiffness(&g, f, output(stiffness)?).map_err(dk_status::from)
}
