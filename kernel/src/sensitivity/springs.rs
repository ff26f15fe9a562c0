//! Tangent and adjoint of the linear springs (Batina): `A x_f = B x_b` with `A = D − K_ff`
//! the weighted graph Laplacian on the free nodes (symmetric positive definite) and `B = K_fb`.

use super::zero_lanes::adjoint_nonzero;
use super::{adjoint_parts, check_adjoint, for_each_field, for_each_field_mut};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::krylov::{cg_len, solve_rhs, RhsLayout, Vectors};
use crate::spring::{
    diagonal, solve_linear_amg_scratch_len, Laplacian, LinearMethod, LinearSolver, OneLevel,
    Serial, SolveOptions, SolveReport, SpringSystem, Vcycle,
};

/// The error for a solver the adjoint does not take.
const NOT_CG: Error = Error::InvalidParameter {
    arg: "solver",
    reason: "the adjoint needs CG (LinearMethod::Cg) or multigrid (LinearSolver::Amg)",
};

/// The tangent `δx = J δx_b` of the linear springs: the same solve as the deformation with
/// the boundary perturbation as Dirichlet data (the map is linear). `dx` holds `δx_b` at the
/// fixed nodes and the initial guess at the free nodes (zero is fine); on `Ok` it holds `δx`
/// at every node. `scratch` as for
/// [`solve_linear_with`](crate::spring::SpringSystem::solve_linear_with)
/// ([`solve_linear_with_scratch_len`](crate::spring::solve_linear_with_scratch_len)).
///
/// # Errors
/// Those of [`solve_linear_with`](crate::spring::SpringSystem::solve_linear_with); `dx` is
/// untouched on error.
pub fn spring_tangent<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; V]],
    scratch: &mut [[T; V]],
) -> Result<SolveReport<T>> {
    sys.solve_linear_with(dx, solver, options, scratch)
}

/// [`spring_tangent`] for `m` perturbations back to back in `dx` (`m · n` items), one after
/// the other with the same system and solver (and hierarchy). Returns the merged report
/// (most iterations, largest residual, converged when all did).
///
/// # Errors
/// `dx` not a whole number `m ≥ 1` of fields ([`Error::LengthMismatch`]); those of
/// [`spring_tangent`] (the fields before the failing one are written).
pub fn spring_tangent_many<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; V]],
    scratch: &mut [[T; V]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    for_each_field_mut(n, dx, |f| spring_tangent(sys, solver, options, f, scratch))
}

/// `[T; V]` scratch items of [`spring_adjoint`]: the adjoint field `λ` (`n`) and the CG
/// solve's own (`4 n + ⌈n / V⌉` for CG with a one-level preconditioner, as
/// [`solve_linear_amg_scratch_len`] for multigrid). `usize::MAX` for a solver the adjoint
/// does not take (stationary methods, distributed solvers).
pub fn spring_adjoint_scratch_len<T: Real, const V: usize>(
    solver: &LinearSolver<'_, T>,
    node_count: usize,
) -> usize {
    let solve = match solver {
        LinearSolver::Method(LinearMethod::Cg { .. }) => cg_len(node_count)
            .and_then(|c| c.checked_add(node_count.div_ceil(V.max(1))))
            .unwrap_or(usize::MAX),
        LinearSolver::Amg(h) => solve_linear_amg_scratch_len(h),
        _ => return usize::MAX,
    };
    solve.saturating_add(node_count)
}

/// The adjoint `g = Jᵀ w` of the linear springs: for `w = dJ/dx` at every node, `g = dJ/dx_b`
/// at the fixed nodes (zero at the free nodes):
///
/// ```text
/// (D − K_ff) λ = w_f,    g_j = w_j + Σ_{i free} k_ij λ_i   (j fixed)
/// ```
///
/// One CG solve with the deformation's own operator (symmetric) and preconditioner (Jacobi,
/// SSOR or none; or the multigrid V-cycle of the given hierarchy, reused as is) on the right-
/// hand side `w_f`, from a zero initial guess; each component is one lane, as in the
/// deformation. `solver` must be CG ([`LinearMethod::Cg`]) or [`LinearSolver::Amg`].
///
/// # Errors
/// Nothing is written on error: `w`, `g` not one item per node ([`Error::LengthMismatch`]);
/// non-finite `w` ([`Error::NonFinite`]); bad options; a stationary or distributed solver
/// ([`Error::InvalidParameter`]); `scratch` shorter than [`spring_adjoint_scratch_len`]
/// ([`Error::BufferTooSmall`]); a hierarchy of another system; the CG errors
/// ([`Error::SingularSystem`], [`Error::Overflow`]).
pub fn spring_adjoint<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; V]],
    g: &mut [[T; V]],
    scratch: &mut [[T; V]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    check_adjoint(n, w, g, options)?;
    check_solver(sys, solver)?;
    let needed = spring_adjoint_scratch_len::<T, V>(&solver, n);
    if let Some(packed) = adjoint_nonzero(sys, solver, options, w, g, scratch) {
        return packed;
    }
    let (lambda, v, rest) = adjoint_parts(scratch, n, needed)?;
    let report = adjoint_solve(sys, solver, options, w, lambda, v, rest)?;
    let lambda: &[[T; V]] = lambda;
    pull_back(
        sys,
        w,
        |i| lambda.get(i).copied().unwrap_or([T::ZERO; V]),
        g,
    );
    Ok(report)
}

/// The adjoint's solver: CG (a valid SSOR `omega`) or multigrid with a hierarchy of `sys`.
pub(super) fn check_solver<T: Real>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
) -> Result<()> {
    match solver {
        LinearSolver::Method(LinearMethod::Cg { preconditioner }) => {
            if let crate::spring::Preconditioner::Ssor { omega } = preconditioner {
                crate::spring::check_omega(omega)?;
            }
            Ok(())
        }
        LinearSolver::Amg(h) => h.check_system(sys),
        _ => Err(NOT_CG),
    }
}

/// `(D − K_ff) λ = w_f` with `solver`'s preconditioner (`rest`: its scratch).
pub(super) fn adjoint_solve<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; V]],
    lambda: &mut [[T; V]],
    v: Vectors<'_, T, V>,
    rest: &mut [[T; V]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let layout = RhsLayout {
        kmax: sys.stiffness().iter().fold(T::ZERO, |m, &k| m.max(k)),
        joint: false,
        per_node: false,
    };
    let fixed = |i| sys.is_fixed(i);
    let serial = Serial::new(n);
    match solver {
        LinearSolver::Amg(h) => {
            let op = Laplacian::<T, false> { sys, diag: &[] };
            let mut pre = Vcycle::new(sys, h, rest);
            solve_rhs(&op, &mut pre, v, w, lambda, layout, fixed, options, &serial)
        }
        LinearSolver::Method(LinearMethod::Cg { preconditioner }) => {
            let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
            diagonal(sys, diag);
            let diag: &[T] = diag;
            let op = Laplacian::<T, true> { sys, diag };
            let mut pre = OneLevel {
                sys,
                diag,
                pre: preconditioner,
            };
            solve_rhs(&op, &mut pre, v, w, lambda, layout, fixed, options, &serial)
        }
        _ => Err(NOT_CG),
    }
}

/// `g_j = w_j + Σ_{i free} k_ji λ_i` at fixed `j` (CSR order; `k_ji = k_ij`), zero at free.
pub(super) fn pull_back<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    w: &[[T; V]],
    lambda: impl Fn(usize) -> [T; V],
    g: &mut [[T; V]],
) {
    for (j, (gj, &wj)) in g.iter_mut().zip(w).enumerate() {
        if !sys.is_fixed(j) {
            *gj = [T::ZERO; V];
            continue;
        }
        let mut acc = wj;
        for (i, k) in sys.row(j) {
            if sys.is_fixed(i) {
                continue;
            }
            for (a, &l) in acc.iter_mut().zip(&lambda(i)) {
                *a += k * l;
            }
        }
        *gj = acc;
    }
}

/// [`spring_adjoint`] for `m` fields `w` back to back (`m · n` items; `g` as long), one after
/// the other with one setup (the system, the hierarchy). Returns the merged report.
///
/// # Errors
/// `w` not a whole number `m ≥ 1` of fields or `g` of another length
/// ([`Error::LengthMismatch`]); those of [`spring_adjoint`] (fields before the failing one
/// are written).
pub fn spring_adjoint_many<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; V]],
    g: &mut [[T; V]],
    scratch: &mut [[T; V]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    for_each_field(n, w, g, |w, g| {
        spring_adjoint(sys, solver, options, w, g, scratch)
    })
}
