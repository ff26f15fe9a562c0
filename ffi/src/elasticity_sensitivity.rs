//! Tangent and adjoint of the multi-step elasticity of `dk_elasticity_deform` (the kernel's
//! `elastic_incremental_tangent` / `elastic_incremental_adjoint`, block-Jacobi CG):
//! `dk_elasticity_sensitivity_scratch_len`, `dk_elasticity_tangent` and
//! `dk_elasticity_adjoint`. The derivative is exact for the increments with re-assembly: the
//! stiffness's (and the inverse-volume modulus's) dependence on the moved mesh is
//! linearised. See docs/sensitivities.md.
//!
//! Cells are read in `index_base` 0 or 1 as in `dk_elasticity_deform`.

use deform_kernel::elasticity::IncrementBuffers;
use deform_kernel::sensitivity::{
    elastic_incremental_adjoint, elastic_incremental_tangent, ElasticPreconditioner,
    IncrementProblem,
};
use deform_kernel::{Cells, Graph, Real};
use deform_kernel_ffi_export::export;

use crate::args::{mul_len, optional, read_one, write_len, Dim};
use crate::elasticity::{
    dk_elasticity_options, dk_elasticity_report, increment_buffers, increment_scalars,
};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::slice::{chunks, chunks_mut, input, out_one, output, In, Out};
use crate::status::dk_status;

/// Scalars of `scratch` for `steps` increments: the increments' buffers, then
/// `dim · node_count · (steps + 8)` (every step's displacement for the adjoint, four fields,
/// the four CG vectors).
fn scratch_scalars(
    cells: usize,
    nodes: usize,
    edges: usize,
    dim: usize,
    steps: usize,
) -> Result<usize, dk_status> {
    let fields = steps.checked_add(8).ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    increment_scalars(cells, nodes, edges, dim)?
        .checked_add(mul_len(mul_len(dim, nodes)?, fields)?)
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// The cells, the graph and the carved scratch of one call, then `f` on the problem.
#[allow(clippy::too_many_arguments)]
fn with_problem<T: Real, const D: usize, R>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    (fixed, options, wall_distance): (In<'_, u8>, In<'_, dk_elasticity_options>, In<'_, T>),
    (points, displacement): (In<'_, T>, In<'_, T>),
    scratch: Out<'_, T>,
    f: impl FnOnce(
        &IncrementProblem<'_, T, D>,
        IncrementBuffers<'_, T, D>,
        &mut [[T; D]],
    ) -> Result<R, dk_status>,
) -> Result<R, dk_status> {
    let options = read_one(options)?;
    let points = chunks::<T, D>(points)?;
    let n = points.len();
    let (cells, _): (Cells<'_>, _) =
        CellsIn::read(cells)?.cells(n, index_base, output(index_scratch)?)?;
    let graph: Graph<'_> = read_graph(graph)?;
    let e = graph.edge_count();
    let steps = options.steps as usize;
    let need = scratch_scalars(cells.len(), n, e, D, steps)?;
    let scratch = output(scratch)?;
    if scratch.len() < need {
        return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
    }
    let (buffers, rest) = increment_buffers::<T, D>(scratch, cells.len(), n, e)?;
    let params = options.increments(optional(wall_distance)?)?;
    let p = IncrementProblem {
        cells: &cells,
        graph: &graph,
        fixed: input(fixed)?,
        params: &params,
        points,
        displacement: chunks::<T, D>(displacement)?,
        pre: ElasticPreconditioner::Blocks,
        options: options.solve_options(),
    };
    f(&p, buffers, rest.as_chunks_mut::<D>().0)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Scalars of `scratch` [`dk_elasticity_tangent`] and [`dk_elasticity_adjoint`] need for
/// `steps` increments: `cell_count + dim²·(node_count + edge_count) + dim·node_count·(steps +
/// 10)`, `edge_count` the graph's `targets_len` (the same count for both precisions).
#[export(len_out[1])]
pub(crate) fn dk_elasticity_sensitivity_scratch_len(
    node_count: usize,
    cell_count: usize,
    edge_count: usize,
    dim: u32,
    steps: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let n = scratch_scalars(
        cell_count,
        node_count,
        edge_count,
        dim as usize,
        steps as usize,
    )?;
    write_len(len_out, n)
}

/// The tangent of `dk_elasticity_deform` with
/// the same arguments (`points`, the undeformed mesh, is read only): `dx` (`node_count * dim`
/// scalars) holds the boundary perturbation `δd` at fixed nodes on entry and receives the
/// first-order change of the deformed mesh `δx = J δd` at every node (exactly `δd` at fixed
/// nodes). The deformation runs alongside (two block-Jacobi CG solves per increment);
/// `*report` counts both. `scratch` needs [`dk_elasticity_sensitivity_scratch_len`]
/// scalars. On any error `dx` is unchanged.
#[export(twin, cells[1], graph[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_tangent<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    points: In<'_, T>,
    displacement: In<'_, T>,
    dx: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let out = out_one(report)?;
    let dx = chunks_mut::<T, D>(dx)?;
    let r = with_problem::<T, D, _>(
        cells,
        index_base,
        index_scratch,
        graph,
        (fixed, options, wall_distance),
        (points, displacement),
        scratch,
        |p, buffers, rest| Ok(elastic_incremental_tangent(p, dx, buffers, rest)?),
    )?;
    *out = dk_elasticity_report::of(r);
    Ok(())
}

/// The adjoint of [`dk_elasticity_tangent`]: for `w = dJ/dx` of the deformed mesh
/// (`node_count * dim` scalars), `g` (as long) receives `dJ/dd` at the fixed nodes and zero
/// at the free nodes, so that `⟨J δd, w⟩ = ⟨δd, g⟩`: the deformation once, then one
/// block-Jacobi CG solve per increment backwards; `*report` counts both sweeps. Arguments
/// otherwise as [`dk_elasticity_tangent`]. On any error `g` is unchanged.
#[export(twin, cells[1], graph[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_adjoint<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    points: In<'_, T>,
    displacement: In<'_, T>,
    w: In<'_, T>,
    g: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let out = out_one(report)?;
    let w = chunks::<T, D>(w)?;
    let g = chunks_mut::<T, D>(g)?;
    let r = with_problem::<T, D, _>(
        cells,
        index_base,
        index_scratch,
        graph,
        (fixed, options, wall_distance),
        (points, displacement),
        scratch,
        |p, buffers, rest| Ok(elastic_incremental_adjoint(p, w, g, buffers, rest)?),
    )?;
    *out = dk_elasticity_report::of(r);
    Ok(())
}
