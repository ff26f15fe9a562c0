//! The elasticity solves beyond block-Jacobi CG: the rigid-mode smoothed-aggregation
//! multigrid (the kernel's `ElasticSystem::rigid_amg`, as pyamg's
//! `smoothed_aggregation_solver(A, B=rigid_modes)`) and sliding nodes (symmetry planes, the
//! kernel's `solve_sliding` / `solve_rigid_amg_sliding`), each in load increments with
//! re-assembly as `dk_elasticity_deform`: `dk_elasticity_amg_pool_sizes`,
//! `dk_elasticity_deform_amg`, `dk_elasticity_sliding_scratch_len`,
//! `dk_elasticity_deform_sliding` and `dk_elasticity_deform_sliding_amg`.
//!
//! Cells are read in `index_base` 0 or 1 as in `dk_elasticity_deform`.

use deform_kernel::elasticity::{
    deform_incremental_on, elastic_rigid_amg_scratch_len, elastic_rigid_amg_sliding_scratch_len,
    elastic_sliding_scratch_len, ElasticSystem, IncrementBuffers, IncrementReport,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    amg_setup_work_len, AmgHierarchy, AmgOptions, RigidAmg, SolveReport, SpringSystem,
};
use deform_kernel::{Cells, Graph, Real};
use deform_kernel_ffi_export::export;

use crate::args::{mul_len, optional, read_one, write_len, Dim};
use crate::elasticity::{
    dk_elasticity_options, dk_elasticity_report, increment_buffers, increment_scalars,
};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::pools::{dk_plan_sizes, DkPlanPools, PoolsC};
use crate::slice::{chunks, chunks_mut, input, out_one, output, In, Out};
use crate::spring::{dk_amg_options, DkConstraints};
use crate::status::dk_status;

/// Where the pools of a multigrid deformation go: `reals` = increments' buffers, spring
/// weights (one per edge), hierarchy values, solve scratch; `indices` = symbolic work (whose
/// front also anchors the spring system), hierarchy index.
#[derive(Clone, Copy, Debug)]
struct AmgLayout {
    increments: usize,
    weights: usize,
    values: usize,
    scratch: usize,
    work: usize,
    index: usize,
}

impl AmgLayout {
    /// Runs the hierarchy's symbolic pass on `spring` (in `work`) and lays the pools out for
    /// `cells` cells in dimension `D`, with sliding nodes or without.
    fn of<T: Real, const D: usize>(
        spring: &SpringSystem<'_, T>,
        cells: usize,
        sliding: bool,
        amg: &AmgOptions<T>,
        work: &mut [u32],
    ) -> Result<Self, dk_status> {
        let n = spring.node_count();
        let e = spring.graph().edge_count();
        let work_len = AmgHierarchy::setup_work_len(spring);
        let front = work
            .get_mut(..work_len)
            .ok_or(dk_status::DK_ERR_BUFFER_TOO_SMALL)?;
        let sizes = RigidAmg::setup_len(spring, D, amg, front)?;
        let items = if sliding {
            elastic_rigid_amg_sliding_scratch_len(n, sizes.coarse_scalars, D)
        } else {
            elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, D)
        };
        Ok(AmgLayout {
            increments: increment_scalars(cells, n, e, D)?,
            weights: e,
            values: sizes.values,
            scratch: mul_len(items.ok_or(dk_status::DK_ERR_TOO_LARGE)?, D)?,
            work: work_len,
            index: sizes.index,
        })
    }

    /// The pool lengths.
    fn sizes(&self) -> Result<dk_plan_sizes, dk_status> {
        let big = dk_status::DK_ERR_TOO_LARGE;
        let reals = [self.weights, self.values, self.scratch]
            .iter()
            .try_fold(self.increments, |s, &x| s.checked_add(x))
            .ok_or(big)?;
        Ok(dk_plan_sizes {
            reals,
            indices: self.work.checked_add(self.index).ok_or(big)?,
            bytes: 0,
        })
    }
}

/// The spring system the aggregation runs on: unit weights (written to `weights`) on the
/// graph and fixed mask, anchored in the front of `work`.
fn unit_spring<'a, T: Real>(
    graph: Graph<'a>,
    fixed: &'a [u8],
    weights: &'a mut [T],
    work: &mut [u32],
) -> Result<SpringSystem<'a, T>, dk_status> {
    for w in weights.iter_mut() {
        *w = T::ONE;
    }
    SpringSystem::new(graph, weights, fixed, work).map_err(dk_status::from)
}

/// The arguments every deformation here shares (read, not yet borrowed).
struct Common<'a, T> {
    cells: In<'a, dk_cells>,
    index_base: u32,
    index_scratch: Out<'a, u32>,
    graph: In<'a, dk_graph>,
    fixed: In<'a, u8>,
    options: In<'a, dk_elasticity_options>,
    wall_distance: In<'a, T>,
    displacement: In<'a, T>,
    points: Out<'a, T>,
}

/// A [`Common`] opened: validated where the ABI validates, the rest left to the kernel.
struct Open<'a, T: Real, const D: usize> {
    cells: Cells<'a>,
    graph: Graph<'a>,
    fixed: &'a [u8],
    options: dk_elasticity_options,
    wall_distance: Option<&'a [T]>,
    displacement: &'a [[T; D]],
    points: &'a mut [[T; D]],
}

impl<'a, T: Real> Common<'a, T> {
    fn open<const D: usize>(self) -> Result<Open<'a, T, D>, dk_status> {
        let options = read_one(self.options)?;
        let points = chunks_mut::<T, D>(self.points)?;
        let n = points.len();
        let scratch = output(self.index_scratch)?;
        let (cells, _) = CellsIn::read(self.cells)?.cells(n, self.index_base, scratch)?;
        let displacement = chunks::<T, D>(self.displacement)?;
        if displacement.len() != n {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        Ok(Open {
            cells,
            graph: read_graph(self.graph)?,
            fixed: input(self.fixed)?,
            options,
            wall_distance: optional(self.wall_distance)?,
            displacement,
            points,
        })
    }
}

impl<T: Real, const D: usize> Open<'_, T, D> {
    /// The increments, each solved by `solve(system, mesh, step)`.
    fn run<S>(
        self,
        buffers: IncrementBuffers<'_, T, D>,
        solve: S,
    ) -> Result<dk_elasticity_report, dk_status>
    where
        S: FnMut(
            &ElasticSystem<'_, T, D>,
            &[[T; D]],
            &mut [[T; D]],
        ) -> deform_kernel::Result<SolveReport<T>>,
    {
        let params = self.options.increments(self.wall_distance)?;
        let r: IncrementReport<T> = deform_incremental_on(
            &self.cells,
            &self.graph,
            self.fixed,
            &params,
            self.points,
            self.displacement,
            buffers,
            solve,
        )?;
        Ok(dk_elasticity_report::of(r))
    }
}

/// A multigrid deformation: the pools split as [`AmgLayout`] says, the hierarchy rebuilt
/// with the rigid-body modes of each increment's mesh, sliding nodes when `constraints` is
/// given.
/// The multigrid deformation, with sliding nodes or without.
fn deform_amg_for_dim<'a, T: Real, const D: usize>(
    common: Common<'a, T>,
    constraints: Option<In<'a, DkConstraints<T>>>,
    amg: In<'a, dk_amg_options>,
    pools: In<'a, DkPlanPools<T>>,
) -> Result<dk_elasticity_report, dk_status> {
    let amg = read_one(amg)?.to_kernel::<T>()?;
    let c: Option<Constraints<'_, T, D>> = constraints.map(DkConstraints::open::<D>).transpose()?;
    let (reals, indices, _) = DkPlanPools::read(pools)?.borrow()?;
    let a = common.open::<D>()?;
    let (n, e, short) = (
        a.points.len(),
        a.graph.edge_count(),
        dk_status::DK_ERR_BUFFER_TOO_SMALL,
    );
    let (work, index) = indices
        .split_at_mut_checked(amg_setup_work_len(n, e))
        .ok_or(short)?;
    let weights_at = increment_scalars(a.cells.len(), n, e, D)?;
    let (front, rest) = reals.split_at_mut_checked(weights_at).ok_or(short)?;
    let (weights, rest) = rest.split_at_mut_checked(e).ok_or(short)?;
    let spring = unit_spring(a.graph, a.fixed, weights, work)?;
    let layout = AmgLayout::of::<T, D>(&spring, a.cells.len(), c.is_some(), &amg, work)?;
    if index.len() < layout.index {
        return Err(short);
    }
    let (values, scratch) = rest.split_at_mut_checked(layout.values).ok_or(short)?;
    if scratch.len() < layout.scratch {
        return Err(short);
    }
    let scratch = scratch.as_chunks_mut::<D>().0;
    let (buffers, _) = increment_buffers::<T, D>(front, a.cells.len(), n, e)?;
    let stop = a.options.solve_options::<T>();
    a.run(buffers, |sys, mesh, u| {
        let (w, i, v) = (&mut *work, &mut *index, &mut *values);
        match &c {
            Some(c) => {
                let h = sys.rigid_amg_sliding(c, &spring, mesh, &amg, w, i, v)?;
                sys.solve_rigid_amg_sliding(c, &h, u, &stop, scratch)
            }
            None => {
                let h = sys.rigid_amg(&spring, mesh, &amg, w, i, v)?;
                sys.solve_rigid_amg(&h, u, &stop, scratch)
            }
        }
    })
}

/// Scalars of `scratch` [`dk_elasticity_deform_sliding`] needs.
fn sliding_scalars(cells: usize, n: usize, e: usize, dim: usize) -> Result<usize, dk_status> {
    let items = elastic_sliding_scratch_len(n).ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    increment_scalars(cells, n, e, dim)?
        .checked_add(mul_len(items, dim)?)
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// The exact pool lengths [`dk_elasticity_deform_amg`] (`sliding` 0) or
/// [`dk_elasticity_deform_sliding_amg`] (`sliding` 1) needs for `cell_count` cells on `graph`
/// (from `dk_elasticity_graph`) with the fixed mask `fixed` (one byte per node) in dimension
/// `dim`: validates the graph, the mask and `amg` and runs the rigid-mode hierarchy's symbolic
/// pass (aggregation and the sparsity of every level; it depends on the graph and the mask
/// only). `work` needs `dk_spring_amg_work_len(node_count, graph->targets_len)` entries,
/// `weight_scratch` `graph->targets_len`; both are overwritten. `sizes_out->reals` counts
/// scalars of either precision (the same for both), `sizes_out->bytes` is 0. The `amg`
/// options' `max_coarse` counts nodes here (`dim (dim + 1) / 2` unknowns each); the tool uses
/// 64.
///
/// Errors (only `work` and `weight_scratch` are written): `DK_ERR_INVALID_PARAMETER` (`dim`,
/// `sliding`, multigrid options, a free node with no path to a fixed one),
/// `DK_ERR_BUFFER_TOO_SMALL`, the graph's and the mask's errors, `DK_ERR_TOO_LARGE`, pointer
/// errors.
#[export(graph[1], amg[1], sizes_out[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_amg_pool_sizes<const D: usize>(
    cell_count: usize,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    sliding: u32,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    weight_scratch: Out<'_, f64>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    if sliding > 1 {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let amg = read_one(amg)?.to_kernel::<f64>()?;
    let (graph, fixed) = (read_graph(graph)?, input(fixed)?);
    let (work, weights) = (output(work)?, output(weight_scratch)?);
    let out = out_one(sizes_out)?;
    let spring = unit_spring(graph, fixed, weights, work)?;
    let layout = AmgLayout::of::<f64, D>(&spring, cell_count, sliding == 1, &amg, work)?;
    *out = layout.sizes()?;
    Ok(())
}

/// `dk_elasticity_deform`'s motion with every increment solved by CG preconditioned with
/// one V-cycle of smoothed aggregation with the rigid-body modes of the increment's mesh as
/// near-null space (the kernel's `ElasticSystem::rigid_amg` and `solve_rigid_amg`, the same
/// bits; the hierarchy is rebuilt on every increment). Arguments as
/// `dk_elasticity_deform`, with `amg` (`dk_amg_options_default`) and `pools` instead of
/// `scratch`: `reals` and `indices` of at least the lengths [`dk_elasticity_amg_pool_sizes`]
/// gave with `sliding` 0 (`bytes` unused; contents afterwards unspecified).
///
/// Errors (points and report unchanged): those of `dk_elasticity_deform`,
/// `DK_ERR_BUFFER_TOO_SMALL` (a pool), `DK_ERR_INVALID_PARAMETER` (multigrid options),
/// `DK_ERR_SINGULAR_SYSTEM` (a coarse level not positive definite, or a CG breakdown).
#[export(twin, cells[1], graph[1], options[1], amg[1], pools[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_deform_amg<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    options: In<'_, dk_elasticity_options>,
    amg: In<'_, dk_amg_options>,
    wall_distance: In<'_, T>,
    displacement: In<'_, T>,
    points: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let common = Common {
        cells,
        index_base,
        index_scratch,
        graph,
        fixed,
        options,
        wall_distance,
        displacement,
        points,
    };
    let out = out_one(report)?;
    *out = deform_amg_for_dim::<T, D>(common, None, amg, pools)?;
    Ok(())
}

/// Scalars of `scratch` [`dk_elasticity_deform_sliding`] needs: `cell_count +
/// dim²·(node_count + edge_count) + 7·dim·node_count`, `edge_count` the graph's
/// `targets_len` (the same count for both precisions).
#[export(len_out[1])]
pub(crate) fn dk_elasticity_sliding_scratch_len(
    node_count: usize,
    cell_count: usize,
    edge_count: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let n = sliding_scalars(cell_count, node_count, edge_count, dim as usize)?;
    write_len(len_out, n)
}

/// `dk_elasticity_deform` with sliding nodes: `constraints` (as for
/// `dk_spring_solve_linear_sliding`) gives every node's kind and direction, `fixed` must be
/// nonzero exactly at its kind-1 nodes (`dk_constraints_fixed_mask`); a kind-2 node moves in
/// its plane (a line in 2D), a kind-3 node along its line, and the motion minimises the
/// elastic energy over those (the kernel's `ElasticSystem::solve_sliding`, projected
/// block-Jacobi CG, in every increment; the same bits). `scratch` needs
/// [`dk_elasticity_sliding_scratch_len`] scalars.
///
/// Errors (points and report unchanged): those of `dk_elasticity_deform`, the constraints'
/// (as `dk_spring_solve_linear_sliding`), `DK_ERR_INVALID_PARAMETER` when `fixed` and the
/// kind-1 nodes differ.
#[export(twin, cells[1], graph[1], constraints[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_deform_sliding<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    displacement: In<'_, T>,
    points: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let common = Common {
        cells,
        index_base,
        index_scratch,
        graph,
        fixed,
        options,
        wall_distance,
        displacement,
        points,
    };
    let out = out_one(report)?;
    let c = DkConstraints::open::<D>(constraints)?;
    let scratch = output(scratch)?;
    let a = common.open::<D>()?;
    let (n, e) = (a.points.len(), a.graph.edge_count());
    let need = sliding_scalars(a.cells.len(), n, e, D)?;
    if scratch.len() < need {
        return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
    }
    let (buffers, rest) = increment_buffers::<T, D>(scratch, a.cells.len(), n, e)?;
    let cg = rest.as_chunks_mut::<D>().0;
    let stop = a.options.solve_options::<T>();
    *out = a.run(buffers, |sys, _, u| sys.solve_sliding(&c, u, &stop, cg))?;
    Ok(())
}

/// [`dk_elasticity_deform_sliding`] with every increment solved by the rigid-mode multigrid
/// of [`dk_elasticity_deform_amg`] (built for the constrained operator: the kernel's
/// `rigid_amg_sliding` and `solve_rigid_amg_sliding`, the same bits). `pools` as for
/// [`dk_elasticity_deform_amg`], with the lengths [`dk_elasticity_amg_pool_sizes`] gave with
/// `sliding` 1.
///
/// Errors (points and report unchanged): those of [`dk_elasticity_deform_sliding`] and
/// [`dk_elasticity_deform_amg`].
#[export(twin, cells[1], graph[1], constraints[1], options[1], amg[1], pools[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_deform_sliding_amg<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_elasticity_options>,
    amg: In<'_, dk_amg_options>,
    wall_distance: In<'_, T>,
    displacement: In<'_, T>,
    points: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_elasticity_report>,
) -> Result<(), dk_status> {
    let common = Common {
        cells,
        index_base,
        index_scratch,
        graph,
        fixed,
        options,
        wall_distance,
        displacement,
        points,
    };
    let out = out_one(report)?;
    let c = Some(constraints);
    *out = deform_amg_for_dim::<T, D>(common, c, amg, pools)?;
    Ok(())
}
