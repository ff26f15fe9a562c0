//! Tangent and adjoint of the deformations with sliding nodes (symmetry planes,
//! [`Constraints`]): single-step linear elasticity and the linear springs, each node `i`
//! moving by `P_i d` only (`I` free, `0` fixed, `I − n nᵀ` on a plane, `t tᵀ` on a line).
//!
//! With the planes fixed the deformation is linear in the boundary displacement `x_b`: on the
//! non-fixed nodes `U`, `x_U = P y` with `P A P y = P B x_b` (`A` the free-node operator, `B`
//! the coupling to the fixed nodes), so `x_U = P (P A P)⁺ P B x_b`. The tangent is that solve
//! with `δx_b` as Dirichlet data (the deformation's own sliding solve); the adjoint of
//! `w = dJ/dx` is its transpose,
//!
//! ```text
//! P A P λ = P w_U   (λ ∈ range(P)),    g_b = w_b + Bᵀ λ   (g zero off the fixed nodes)
//! ```
//!
//! one projected CG solve with the deformation's operator and preconditioner (`P A P` and
//! `P M⁻¹ P` are symmetric, positive definite on `range(P)`), then the pull-back.

use super::elasticity::check_pre;
use super::springs::{check_solver, pull_back, spring_adjoint_scratch_len};
use super::{check_adjoint, ElasticPreconditioner};
use crate::check;
use crate::elasticity::ElasticSystem;
use crate::elasticity::{elastic_amg_sliding_scratch_len, elastic_sliding_scratch_len};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::constraints::Constraints;
use crate::spring::krylov::{NodeBlocks, Vectors};
use crate::spring::{
    solve_linear_sliding_rhs, LinearSolver, SolveOptions, SolveReport, SpringSystem, Vcycle,
};

/// `[T; D]` scratch items of [`elastic_sliding_tangent`]: [`elastic_sliding_scratch_len`]
/// or [`elastic_amg_sliding_scratch_len`] (`usize::MAX` on overflow).
pub fn elastic_sliding_tangent_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
) -> usize {
    match pre {
        ElasticPreconditioner::Blocks => elastic_sliding_scratch_len(node_count),
        ElasticPreconditioner::Amg(_, h) => {
            elastic_amg_sliding_scratch_len(node_count, h.coarse_unknowns())
        }
    }
    .unwrap_or(usize::MAX)
}

/// `[T; D]` scratch items of [`elastic_sliding_adjoint`]: the adjoint field `λ`, the
/// projected `P w` and the solve's own ([`elastic_sliding_tangent_scratch_len`] holds one of
/// those `n`).
pub fn elastic_sliding_adjoint_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
) -> usize {
    elastic_sliding_tangent_scratch_len(pre, node_count).saturating_add(node_count)
}

/// The tangent `δu = J δu_b` of single-step elasticity with sliding nodes: the deformation's
/// own sliding solve ([`ElasticSystem::solve_sliding`], or
/// [`ElasticSystem::solve_amg_sliding`] with the scalar multigrid) with the boundary
/// perturbation as Dirichlet data (`dx`: `δu_b` at fixed nodes, the initial guess elsewhere;
/// `δu` at every node on `Ok`, in its plane or line at sliding nodes).
///
/// # Errors
/// Those of the sliding solves; `dx` untouched on error.
pub fn elastic_sliding_tangent<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    constraints: &Constraints<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    match pre {
        ElasticPreconditioner::Blocks => sys.solve_sliding(constraints, dx, options, scratch),
        ElasticPreconditioner::Amg(s, h) => {
            sys.solve_amg_sliding(constraints, s, h, dx, options, scratch)
        }
    }
}

/// The adjoint `g = Jᵀ w` of single-step elasticity with sliding nodes: for `w = dJ/du` at
/// every node,
///
/// ```text
/// P K P λ = P w   (λ ∈ range(P), zero at fixed nodes),    g_b = w_b − K_bU λ
/// ```
///
/// (`g` zero off the fixed nodes): one projected CG solve with the deformation's operator and
/// preconditioner (`P M⁻¹ P`) from a zero guess.
///
/// # Errors
/// Nothing is written on error: `w`, `g` not one item per node ([`Error::LengthMismatch`]);
/// non-finite `w`; bad options; constraints of another length or whose fixed nodes differ
/// from the system's; `scratch` shorter than [`elastic_sliding_adjoint_scratch_len`]
/// ([`Error::BufferTooSmall`]); a multigrid `spring` or hierarchy of another size or fixed
/// mask; the CG errors ([`Error::SingularSystem`], [`Error::Overflow`]).
pub fn elastic_sliding_adjoint<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    constraints: &Constraints<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    check_adjoint(n, w, g, options)?;
    check::len("constraints", constraints.len(), n)?;
    sys.check_kinds(constraints)?;
    check_pre(sys, &pre)?;
    let needed = elastic_sliding_adjoint_scratch_len(&pre, n);
    let (lambda, pw, v, rest) = parts(scratch, n, needed)?;
    project(constraints, w, pw);
    let report = match pre {
        ElasticPreconditioner::Blocks => {
            sys.solve_sliding_rhs(constraints, NodeBlocks(sys), v, pw, lambda, options)
        }
        ElasticPreconditioner::Amg(s, h) => {
            let m = Vcycle::new(s, h, rest);
            sys.solve_sliding_rhs(constraints, m, v, pw, lambda, options)
        }
    }?;
    // g = K λ (λ zero at fixed nodes: the fixed rows give K_bU λ), then g_b = w_b − g_b.
    sys.multiply(lambda, g)?;
    for (i, (gi, &wi)) in g.iter_mut().zip(w).enumerate() {
        *gi = if sys.is_fixed(i) {
            crate::vector::sub(wi, *gi)
        } else {
            [T::ZERO; D]
        };
    }
    Ok(report)
}

/// The tangent `δx = J δx_b` of the linear springs with sliding nodes: the deformation's own
/// [`SpringSystem::solve_linear_sliding`] with the boundary perturbation as Dirichlet data
/// (`dx`: `δx_b` at fixed nodes, the initial guess elsewhere; `δx` on `Ok`). `scratch` as
/// [`solve_linear_sliding_scratch_len`](crate::spring::solve_linear_sliding_scratch_len).
///
/// # Errors
/// Those of [`SpringSystem::solve_linear_sliding`]; `dx` untouched on error.
pub fn spring_sliding_tangent<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    constraints: &Constraints<'_, T, D>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    sys.solve_linear_sliding(constraints, dx, solver, options, scratch)
}

/// `[T; D]` scratch items of [`spring_sliding_adjoint`]: [`spring_adjoint_scratch_len`] and
/// `n` more for `P w` (`usize::MAX` for a solver the adjoint does not take).
pub fn spring_sliding_adjoint_scratch_len<T: Real, const D: usize>(
    solver: &LinearSolver<'_, T>,
    node_count: usize,
) -> usize {
    spring_adjoint_scratch_len::<T, D>(solver, node_count).saturating_add(node_count)
}

/// The adjoint `g = Jᵀ w` of the linear springs with sliding nodes: for `w = dJ/dx` at every
/// node, `g = dJ/dx_b` at the fixed nodes (zero elsewhere):
///
/// ```text
/// P (D − K) P λ = P w   (λ ∈ range(P)),    g_j = w_j + Σ_{i not fixed} k_ij λ_i   (j fixed)
/// ```
///
/// one projected CG solve jointly over the components (the deformation's operator and
/// preconditioner: Jacobi, SSOR, none, or the multigrid V-cycle of the hierarchy built with
/// the sliding nodes free). `solver` must be CG or [`LinearSolver::Amg`].
///
/// # Errors
/// Nothing is written on error: `w`, `g` not one item per node; non-finite `w`; bad options
/// or `omega`; constraints of another length or whose fixed nodes differ from the system's
/// mask; a stationary or distributed solver ([`Error::InvalidParameter`]); `scratch` shorter
/// than [`spring_sliding_adjoint_scratch_len`]; a hierarchy of another system; the CG errors.
pub fn spring_sliding_adjoint<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    constraints: &Constraints<'_, T, D>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    check_adjoint(n, w, g, options)?;
    constraints.check_mask(sys.fixed())?;
    check_solver(sys, solver)?;
    let needed = spring_sliding_adjoint_scratch_len::<T, D>(&solver, n);
    let (lambda, pw, v, rest) = parts(scratch, n, needed)?;
    project(constraints, w, pw);
    let report = solve_linear_sliding_rhs(sys, constraints, solver, options, pw, lambda, v, rest)?;
    let lambda: &[[T; D]] = lambda;
    pull_back(
        sys,
        w,
        |i| lambda.get(i).copied().unwrap_or([T::ZERO; D]),
        g,
    );
    Ok(report)
}

/// `λ`, `P w`, the CG vectors and the rest from the front of `scratch` (`needed` items).
type Parts<'s, T, const D: usize> = (
    &'s mut [[T; D]],
    &'s mut [[T; D]],
    Vectors<'s, T, D>,
    &'s mut [[T; D]],
);

fn parts<T: Real, const D: usize>(
    scratch: &mut [[T; D]],
    n: usize,
    needed: usize,
) -> Result<Parts<'_, T, D>> {
    check::buffer("scratch", scratch.len(), needed)?;
    let small = Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual: scratch.len(),
    };
    let (lambda, rest) = scratch.split_at_mut_checked(n).ok_or(small)?;
    let (pw, rest) = rest.split_at_mut_checked(n).ok_or(small)?;
    let (v, rest) = Vectors::split(rest, n).ok_or(small)?;
    Ok((lambda, pw, v, rest))
}

/// `pw = P w` (zero at fixed nodes).
fn project<T: Real, const D: usize>(c: &Constraints<'_, T, D>, w: &[[T; D]], pw: &mut [[T; D]]) {
    for (i, (p, &x)) in pw.iter_mut().zip(w).enumerate() {
        *p = c.project(i, x);
    }
}
