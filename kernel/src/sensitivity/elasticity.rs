//! Tangent and adjoint of single-step linear elasticity: `K_ff u_f = −K_fb u_b` with the
//! stiffness assembled on the undeformed mesh (symmetric positive definite on the free
//! nodes). Load increments re-assemble on the moved mesh and are not linear: see
//! `elasticity_steps`.

use super::{check_adjoint, for_each_field, for_each_field_mut};
use crate::check;
use crate::elasticity::{elastic_amg_scratch_len, elastic_scratch_len, ElasticSystem};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::krylov::{solve_rhs, NodeBlocks, RhsLayout, Vectors};
use crate::spring::{AmgHierarchy, Serial, SolveOptions, SolveReport, SpringSystem, Vcycle};

/// Which preconditioner the elasticity solves use (the deformation's and its derivative's).
#[derive(Clone, Copy, Debug)]
pub enum ElasticPreconditioner<'a, T: Real> {
    /// The node blocks (block Jacobi): [`ElasticSystem::solve`].
    Blocks,
    /// The scalar V-cycle of `hierarchy`, built on `spring` (same graph and fixed mask):
    /// [`ElasticSystem::solve_amg`].
    Amg(&'a SpringSystem<'a, T>, &'a AmgHierarchy<'a, T>),
}

/// `[T; D]` scratch items of [`elastic_tangent`]: [`elastic_scratch_len`] or
/// [`elastic_amg_scratch_len`] (`usize::MAX` on overflow).
pub fn elastic_tangent_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
) -> usize {
    match pre {
        ElasticPreconditioner::Blocks => elastic_scratch_len(node_count),
        ElasticPreconditioner::Amg(_, h) => {
            elastic_amg_scratch_len(node_count, h.coarse_unknowns())
        }
    }
    .unwrap_or(usize::MAX)
}

/// `[T; D]` scratch items of [`elastic_adjoint`]: the adjoint field `λ` (`n`) and the
/// solve's own ([`elastic_tangent_scratch_len`]).
pub fn elastic_adjoint_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
) -> usize {
    elastic_tangent_scratch_len(pre, node_count).saturating_add(node_count)
}

/// The tangent `δu = J δu_b` of single-step elasticity: the deformation's own solve with the
/// boundary perturbation as Dirichlet data (`dx`: `δu_b` at fixed nodes, the initial guess
/// at free nodes; `δu` at every node on `Ok`).
///
/// # Errors
/// Those of [`ElasticSystem::solve`] / [`ElasticSystem::solve_amg`]; `dx` untouched on error.
pub fn elastic_tangent<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    match pre {
        ElasticPreconditioner::Blocks => sys.solve(dx, options, scratch),
        ElasticPreconditioner::Amg(s, h) => sys.solve_amg(s, h, dx, options, scratch),
    }
}

/// [`elastic_tangent`] for `m` perturbations back to back in `dx` (`m · n` items), one after
/// the other with one setup. Returns the merged report.
///
/// # Errors
/// `dx` not a whole number `m ≥ 1` of fields ([`Error::LengthMismatch`]); those of
/// [`elastic_tangent`] (fields before the failing one are written).
pub fn elastic_tangent_many<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    for_each_field_mut(sys.node_count(), dx, |f| {
        elastic_tangent(sys, pre, options, f, scratch)
    })
}

/// The adjoint `g = Jᵀ w` of single-step elasticity: for `w = dJ/du` at every node,
///
/// ```text
/// K_ff λ = w_f,    g_b = w_b − K_bf λ     (g zero at free nodes)
/// ```
///
/// one CG solve with the deformation's operator (`K_ff`, symmetric) and preconditioner on
/// the right-hand side `w_f` (zero initial guess, one lane: the blocks couple components).
///
/// # Errors
/// Nothing is written on error: `w`, `g` not one item per node ([`Error::LengthMismatch`]);
/// non-finite `w`; bad options; `scratch` shorter than [`elastic_adjoint_scratch_len`]
/// ([`Error::BufferTooSmall`]); a multigrid `spring` or hierarchy of another size or fixed
/// mask; the CG errors ([`Error::SingularSystem`], [`Error::Overflow`]).
pub fn elastic_adjoint<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    check_adjoint(n, w, g, options)?;
    check_pre(sys, &pre)?;
    let needed = elastic_adjoint_scratch_len(&pre, n);
    check::buffer("scratch", scratch.len(), needed)?;
    let (lambda, rest) = scratch
        .split_at_mut_checked(n)
        .ok_or(Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: 0,
        })?;
    let report = solve_free(sys, pre, options, w, lambda, rest)?;
    // g = K λ (λ zero at fixed nodes: the fixed rows give K_bf λ), then g_b = w_b − g_b.
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

/// A multigrid preconditioner's spring system and hierarchy fit `sys` (same size and fixed
/// mask, the hierarchy built on the spring system); nothing to check for the blocks.
pub(super) fn check_pre<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: &ElasticPreconditioner<'_, T>,
) -> Result<()> {
    match pre {
        ElasticPreconditioner::Blocks => Ok(()),
        ElasticPreconditioner::Amg(s, h) => sys.check_amg(s, h),
    }
}

/// Solves `K_ff λ = w_f` (zero initial guess, `λ` zero at fixed nodes) with the deformation's
/// preconditioner; `scratch` holds [`elastic_tangent_scratch_len`] items. `λ` is written only
/// on `Ok`.
pub(super) fn solve_free<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    lambda: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let needed = elastic_tangent_scratch_len(&pre, n);
    check::buffer("scratch", scratch.len(), needed)?;
    let (v, rest) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual: 0,
    })?;
    let layout = RhsLayout {
        kmax: sys.kmax(),
        joint: true,
        per_node: true,
    };
    let fixed = |i| sys.is_fixed(i);
    let serial = Serial::new(n);
    match pre {
        ElasticPreconditioner::Blocks => {
            let mut m = NodeBlocks(sys);
            solve_rhs(sys, &mut m, v, w, lambda, layout, fixed, options, &serial)
        }
        ElasticPreconditioner::Amg(s, h) => {
            let mut m = Vcycle::new(s, h, rest);
            solve_rhs(sys, &mut m, v, w, lambda, layout, fixed, options, &serial)
        }
    }
}

/// [`elastic_adjoint`] for `m` fields `w` back to back (`m · n` items; `g` as long), one
/// after the other with one setup. Returns the merged report.
///
/// # Errors
/// `w` not a whole number `m ≥ 1` of fields or `g` of another length
/// ([`Error::LengthMismatch`]); those of [`elastic_adjoint`] (fields before the failing one
/// are written).
pub fn elastic_adjoint_many<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    for_each_field(sys.node_count(), w, g, |w, g| {
        elastic_adjoint(sys, pre, options, w, g, scratch)
    })
}
