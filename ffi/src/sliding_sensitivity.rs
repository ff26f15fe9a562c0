//! Tangent and adjoint of the deformations with sliding nodes (symmetry planes; the kernel's
//! `sensitivity::sliding`): the linear springs (`dk_sensitivity_spring_sliding_tangent`,
//! `dk_sensitivity_spring_sliding_adjoint_scratch_len`, `dk_sensitivity_spring_sliding_adjoint`)
//! and single-step elasticity (`dk_elasticity_sliding_sensitivity_scratch_len`,
//! `dk_elasticity_sliding_tangent`, `dk_elasticity_sliding_adjoint`). With the planes fixed the
//! deformation is linear in the boundary displacement, so the derivative holds everywhere.
//! The nodes' kinds and directions come in the `dk_constraints` of the forward sliding solves
//! (`dk_spring_solve_linear_sliding`, `dk_elasticity_deform_sliding`). See
//! docs/sensitivities.md, "Sliding nodes".
//!
//! Cells are read in `index_base` 0 or 1 as in `dk_elasticity_deform_sliding`.

use deform_kernel::elasticity::{assemble, cell_moduli, ElasticSystem};
use deform_kernel::sensitivity::{
    elastic_sliding_adjoint, elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    spring_sliding_adjoint, spring_sliding_adjoint_scratch_len, spring_sliding_tangent,
    ElasticPreconditioner,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{LinearMethod, LinearSolver, SolveOptions, SolveReport};
use deform_kernel::{Cells, Graph, Real};
use deform_kernel_ffi_export::export;

use crate::args::{mul_len, optional, read_one, write_len, Dim};
use crate::elasticity::{blocks, dk_elasticity_options};
use crate::graph::{dk_cells, dk_graph, read_graph, CellsIn};
use crate::slice::{chunks, chunks_mut, input, out_one, output, whole_chunks_mut, In, Out};
use crate::spring::{
    dk_spring_solve_options, dk_spring_solve_report, DkConstraints, DkSpringSystem,
};
use crate::status::dk_status;

/// `[T; dim]` items of the elastic adjoint's own scratch (the tangent needs one `n` fewer).
fn elastic_items(n: usize) -> Result<usize, dk_status> {
    match elastic_sliding_adjoint_scratch_len::<f64>(&ElasticPreconditioner::Blocks, n) {
        usize::MAX => Err(dk_status::DK_ERR_TOO_LARGE),
        items => Ok(items),
    }
}

/// Scalars of the elastic scratch: the moduli (one per cell), the node and edge blocks, then
/// the adjoint's items.
fn elastic_scalars(cells: usize, n: usize, e: usize, dim: usize) -> Result<usize, dk_status> {
    let big = dk_status::DK_ERR_TOO_LARGE;
    let blocks = mul_len(mul_len(dim, dim)?, n.checked_add(e).ok_or(big)?)?;
    let fields = mul_len(elastic_items(n)?, dim)?;
    cells
        .checked_add(blocks)
        .and_then(|s| s.checked_add(fields))
        .ok_or(big)
}

/// The elastic arguments both directions share (read, not yet borrowed).
struct ElasticArgs<'a, T> {
    cells: In<'a, dk_cells>,
    index_base: u32,
    index_scratch: Out<'a, u32>,
    graph: In<'a, dk_graph>,
    fixed: In<'a, u8>,
    constraints: In<'a, DkConstraints<T>>,
    options: In<'a, dk_elasticity_options>,
    wall_distance: In<'a, T>,
    points: In<'a, T>,
    scratch: Out<'a, T>,
}

impl<T: Real> ElasticArgs<'_, T> {
    /// Validates the arguments, assembles the stiffness on `points` in the front of `scratch`
    /// (as the first increment of `dk_elasticity_deform_sliding`) and runs `f` on the system,
    /// the constraints, the stopping rules and the rest of the scratch.
    fn with_system<const D: usize, R>(
        self,
        f: impl FnOnce(
            &ElasticSystem<'_, T, D>,
            &Constraints<'_, T, D>,
            &SolveOptions<T>,
            &mut [[T; D]],
        ) -> Result<R, dk_status>,
    ) -> Result<R, dk_status> {
        let options = read_one(self.options)?;
        if options.steps != 1 {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        let c = DkConstraints::open::<D>(self.constraints)?;
        let points = chunks::<T, D>(self.points)?;
        let n = points.len();
        let iscr = output(self.index_scratch)?;
        let (cells, _): (Cells<'_>, _) =
            CellsIn::read(self.cells)?.cells(n, self.index_base, iscr)?;
        let graph: Graph<'_> = read_graph(self.graph)?;
        let fixed = input(self.fixed)?;
        let params = options.increments(optional(self.wall_distance)?)?;
        let e = graph.edge_count();
        let scratch = output(self.scratch)?;
        if scratch.len() < elastic_scalars(cells.len(), n, e, D)? {
            return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
        }
        let short = dk_status::DK_ERR_BUFFER_TOO_SMALL;
        let (moduli, rest) = scratch.split_at_mut_checked(cells.len()).ok_or(short)?;
        let (diag, rest) = rest.split_at_mut_checked(mul_len(D * D, n)?).ok_or(short)?;
        let (off, rest) = rest.split_at_mut_checked(mul_len(D * D, e)?).ok_or(short)?;
        let (diag, off) = (blocks::<T, D>(diag), blocks::<T, D>(off));
        cell_moduli(&cells, points, params.modulus, params.wall_distance, moduli)?;
        assemble(&cells, points, &graph, moduli, params.poisson, diag, off)?;
        let sys = ElasticSystem::new(graph, diag, off, fixed)?;
        f(
            &sys,
            &c,
            &options.solve_options(),
            rest.as_chunks_mut::<D>().0,
        )
    }
}

/// The spring adjoint's solver: CG with the options' preconditioner (else
/// `DK_ERR_INVALID_PARAMETER`).
fn cg_solver<T: Real>(o: &dk_spring_solve_options) -> Result<LinearSolver<'static, T>, dk_status> {
    match o.method::<T>()? {
        m @ LinearMethod::Cg { .. } => Ok(LinearSolver::Method(m)),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    }
}

/// Writes the C report of one solve.
fn report_of<T: Real>(
    r: &mut dk_spring_solve_report,
    rep: SolveReport<T>,
) -> Result<(), dk_status> {
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// The tangent of the linear springs with sliding nodes: `dk_spring_solve_linear_sliding` with
/// the boundary perturbation as Dirichlet data (the kernel's
/// `sensitivity::spring_sliding_tangent`, the same bits). `dx` (`node_count * dim` scalars)
/// holds `δx_b` at the fixed nodes and the initial guess (zero, usually) elsewhere; on `DK_OK`
/// it receives `δx = J δx_b` at every node, in its plane or on its line at sliding nodes.
/// Arguments, `scratch` (`dk_spring_solve_linear_sliding_scratch_len`) and `index_scratch` as
/// for `dk_spring_solve_linear_sliding` (any one-level method).
///
/// Errors (`dx` and report unchanged): those of `dk_spring_solve_linear_sliding`.
#[export(twin, system[1], constraints[1], options[1], report[1])]
pub(crate) fn dk_sensitivity_spring_sliding_tangent<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_solve_options>,
    _dim: Dim<D>,
    dx: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let solver = LinearSolver::Method(o.method::<T>()?);
    let c = DkConstraints::open::<D>(constraints)?;
    let dx = chunks_mut::<T, D>(dx)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let sys = DkSpringSystem::open(system, index_scratch)?;
    // The kernel validates before it writes and iterates on a copy in the scratch.
    let rep = spring_sliding_tangent(&sys, &c, solver, &o.stopping(), dx, s)?;
    report_of(r, rep)
}

/// Scalars of `scratch` [`dk_sensitivity_spring_sliding_adjoint`] needs for `node_count`
/// nodes in dimension `dim` (2 or 3) with `options->method` (`DK_LINEAR_CG` only, else
/// `DK_ERR_INVALID_PARAMETER`): `dim · (6 n + ⌈n / dim⌉)` (the adjoint field, `P w`, the four
/// CG vectors, the diagonal). The same for both precisions.
#[export(options[1], len_out[1])]
pub(crate) fn dk_sensitivity_spring_sliding_adjoint_scratch_len(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let solver = cg_solver::<f64>(&read_one(options)?)?;
    let items = match dim {
        2 => spring_sliding_adjoint_scratch_len::<f64, 2>(&solver, node_count),
        3 => spring_sliding_adjoint_scratch_len::<f64, 3>(&solver, node_count),
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    if items == usize::MAX {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    write_len(len_out, mul_len(items, dim as usize)?)
}

/// The adjoint of [`dk_sensitivity_spring_sliding_tangent`]: for `w = dJ/dx` at every node
/// (`node_count * dim` scalars), `g` (as long) receives `dJ/dx_b` at the fixed nodes and zero
/// elsewhere, so that `⟨J δx_b, w⟩ = ⟨δx_b, g⟩`: `P (D − K) P λ = P w` by one projected CG
/// solve jointly over the components with the deformation's operator and preconditioner
/// (`options`: `DK_LINEAR_CG` with any preconditioner), then `g_j = w_j + Σ_{i not fixed}
/// k_ij λ_i` (the kernel's `sensitivity::spring_sliding_adjoint`, the same bits). `scratch`
/// needs [`dk_sensitivity_spring_sliding_adjoint_scratch_len`] scalars, `index_scratch`
/// `node_count` entries; `*report` is the solve's (not converged is `DK_OK` with `converged`
/// false).
///
/// Errors (`g` and report unchanged): those of [`dk_sensitivity_spring_sliding_tangent`],
/// `DK_ERR_INVALID_PARAMETER` for a method other than CG, `DK_ERR_NON_FINITE` (`w`),
/// `DK_ERR_LENGTH_MISMATCH` (`w`, `g`), `DK_ERR_BUFFER_TOO_SMALL` (`scratch`).
#[export(twin, system[1], constraints[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_spring_sliding_adjoint<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_solve_options>,
    _dim: Dim<D>,
    w: In<'_, T>,
    g: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let solver = cg_solver::<T>(&o)?;
    let c = DkConstraints::open::<D>(constraints)?;
    let w = chunks::<T, D>(w)?;
    let g = chunks_mut::<T, D>(g)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let sys = DkSpringSystem::open(system, index_scratch)?;
    // The kernel validates everything before it writes `g`.
    let rep = spring_sliding_adjoint(&sys, &c, solver, &o.stopping(), w, g, s)?;
    report_of(r, rep)
}

/// Scalars of `scratch` [`dk_elasticity_sliding_tangent`] and
/// [`dk_elasticity_sliding_adjoint`] need: `cell_count + dim²·(node_count + edge_count) +
/// 6·dim·node_count` (the moduli, the node and edge blocks, then `λ`, `P w` and the four CG
/// vectors), `edge_count` the graph's `targets_len` (the same for both precisions).
#[export(len_out[1])]
pub(crate) fn dk_elasticity_sliding_sensitivity_scratch_len(
    node_count: usize,
    cell_count: usize,
    edge_count: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let n = elastic_scalars(cell_count, node_count, edge_count, dim as usize)?;
    write_len(len_out, n)
}

/// The tangent of `dk_elasticity_deform_sliding` with one step (`options->steps` must be 1:
/// the map is then linear): the stiffness assembled on `points` (the undeformed mesh, read
/// only) and the deformation's own projected block-Jacobi CG solve with the boundary
/// perturbation as Dirichlet data (the kernel's `sensitivity::elastic_sliding_tangent`, the
/// same bits). `dx` (`node_count * dim` scalars) holds `δu_b` at the fixed nodes and the
/// initial guess (zero, usually) elsewhere; on `DK_OK` it receives `δu = J δu_b` at every
/// node, in its plane or on its line at sliding nodes. Other arguments as
/// `dk_elasticity_deform_sliding`; `scratch` needs
/// [`dk_elasticity_sliding_sensitivity_scratch_len`] scalars; `*report` is the solve's.
///
/// Errors (`dx` and report unchanged): those of `dk_elasticity_deform_sliding`,
/// `DK_ERR_INVALID_PARAMETER` for `steps` other than 1.
#[export(twin, cells[1], graph[1], constraints[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_sliding_tangent<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    points: In<'_, T>,
    dx: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let r = out_one(report)?;
    let dx = chunks_mut::<T, D>(dx)?;
    let args = ElasticArgs {
        cells,
        index_base,
        index_scratch,
        graph,
        fixed,
        constraints,
        options,
        wall_distance,
        points,
        scratch,
    };
    let rep = args.with_system::<D, _>(|sys, c, stop, s| {
        Ok(elastic_sliding_tangent(
            sys,
            c,
            ElasticPreconditioner::Blocks,
            stop,
            dx,
            s,
        )?)
    })?;
    report_of(r, rep)
}

/// The adjoint of [`dk_elasticity_sliding_tangent`]: for `w = dJ/du` at every node
/// (`node_count * dim` scalars), `g` (as long) receives `dJ/du_b` at the fixed nodes and zero
/// elsewhere, so that `⟨J δu_b, w⟩ = ⟨δu_b, g⟩`: `P K P λ = P w` by one projected
/// block-Jacobi CG solve from a zero guess, then `g_b = w_b − (K λ)_b` (the kernel's
/// `sensitivity::elastic_sliding_adjoint`, the same bits). Arguments otherwise as
/// [`dk_elasticity_sliding_tangent`].
///
/// Errors (`g` and report unchanged): those of [`dk_elasticity_sliding_tangent`],
/// `DK_ERR_NON_FINITE` (`w`), `DK_ERR_LENGTH_MISMATCH` (`w`, `g`).
#[export(twin, cells[1], graph[1], constraints[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_sliding_adjoint<T: Real, const D: usize>(
    cells: In<'_, dk_cells>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    graph: In<'_, dk_graph>,
    _dim: Dim<D>,
    fixed: In<'_, u8>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_elasticity_options>,
    wall_distance: In<'_, T>,
    points: In<'_, T>,
    w: In<'_, T>,
    g: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let r = out_one(report)?;
    let w = chunks::<T, D>(w)?;
    let g = chunks_mut::<T, D>(g)?;
    let args = ElasticArgs {
        cells,
        index_base,
        index_scratch,
        graph,
        fixed,
        constraints,
        options,
        wall_distance,
        points,
        scratch,
    };
    let rep = args.with_system::<D, _>(|sys, c, stop, s| {
        Ok(elastic_sliding_adjoint(
            sys,
            c,
            ElasticPreconditioner::Blocks,
            stop,
            w,
            g,
            s,
        )?)
    })?;
    report_of(r, rep)
}
