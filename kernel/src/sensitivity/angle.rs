//! Tangent and adjoint of the angle-inclusion springs (Yang & Özgen): `A x_f = C x_b` with
//! the block operator assembled on the undeformed mesh, `A_ii = Σ_j B_ij`, `A_ij = −B_ij`
//! (free `j`), `C_ij = B_ij` (fixed `j`), `B_ij = k_ij (d dᵀ / |d|² + ε I)`, `d = r_j − r_i`.
//!
//! **Symmetry.** `B_ij` is a symmetric `D×D` block and `B_ji = B_ij` (the edge `j → i` has
//! direction `−d`, and `(−d)(−d)ᵀ = d dᵀ`; `k_ji = k_ij`), bit for bit: negating a difference
//! is exact. So `Aᵀ = A` and the adjoint is one more solve with the deformation's own operator
//! and preconditioner (the node blocks, or the scalar multigrid V-cycle per component).

use super::{adjoint_parts, check_adjoint, for_each_field, for_each_field_mut};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::krylov::{solve_rhs, NodeBlocks, RhsLayout};
use crate::spring::Vcycle;
use crate::spring::{
    angle_scratch_items, AmgHierarchy, AngleMethod, AngleSystem, Serial, SolveOptions, SolveReport,
};
use crate::vector;

/// How the angle springs are solved: [`AngleSystem::solve_angle`] with a method, or
/// [`AngleSystem::solve_angle_amg`] with the multigrid hierarchy of the linear springs
/// ([`AngleSystem::base`]).
#[derive(Clone, Copy, Debug)]
pub enum AngleSolver<'a, T: Real> {
    /// [`AngleSystem::solve_angle`] with this method.
    Method(AngleMethod),
    /// [`AngleSystem::solve_angle_amg`] with this hierarchy.
    Amg(&'a AmgHierarchy<'a, T>),
}

/// The error for a solver the adjoint does not take.
const NOT_CG: Error = Error::InvalidParameter {
    arg: "solver",
    reason: "the adjoint needs CG (AngleMethod::Cg) or multigrid (AngleSolver::Amg)",
};

/// `[T; D]` scratch items of [`angle_tangent`]: the solve's own
/// ([`AngleSystem::angle_scratch_len`] or [`AngleSystem::angle_amg_scratch_len`]).
pub fn angle_tangent_scratch_len<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: &AngleSolver<'_, T>,
) -> usize {
    match solver {
        AngleSolver::Method(m) => sys.angle_scratch_len(*m),
        AngleSolver::Amg(h) => sys.angle_amg_scratch_len(h),
    }
}

/// `[T; D]` scratch items of [`angle_adjoint`]: the adjoint field `λ` (`n`) and the CG
/// solve's (the rigidity probe's when `ε = 0` included); `usize::MAX` for a direct method
/// (the adjoint takes CG or multigrid only).
pub fn angle_adjoint_scratch_len<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: &AngleSolver<'_, T>,
) -> usize {
    let n = sys.base().node_count();
    match solver {
        AngleSolver::Method(AngleMethod::Cg) => {
            angle_adjoint_scratch_items(n).unwrap_or(usize::MAX)
        }
        AngleSolver::Amg(h) => sys.angle_amg_scratch_len(h).saturating_add(n),
        AngleSolver::Method(_) => usize::MAX,
    }
}

/// [`angle_adjoint_scratch_len`] with block-Jacobi CG ([`AngleMethod::Cg`]) for callers
/// without a system (a size query): `n` for `λ` and the CG solve's `4 n` (which also holds
/// the rigidity probe's when `ε = 0`); `None` on overflow.
pub const fn angle_adjoint_scratch_items(node_count: usize) -> Option<usize> {
    match angle_scratch_items(node_count, AngleMethod::Cg, false) {
        Some(s) => s.checked_add(node_count),
        None => None,
    }
}

/// The tangent `δx = J δx_b` of the angle springs: the deformation's own solve with the
/// boundary perturbation as Dirichlet data (the map is linear: the operator depends on the
/// undeformed mesh only). `dx` holds `δx_b` at the fixed nodes and the initial guess at the
/// free nodes (zero is fine); on `Ok` it holds `δx` at every node.
///
/// # Errors
/// Those of [`AngleSystem::solve_angle`] / [`AngleSystem::solve_angle_amg`]; `dx` is
/// untouched on error.
pub fn angle_tangent<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: AngleSolver<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    match solver {
        AngleSolver::Method(m) => sys.solve_angle(dx, m, options, scratch),
        AngleSolver::Amg(h) => sys.solve_angle_amg(h, dx, options, scratch),
    }
}

/// [`angle_tangent`] for `m` perturbations back to back in `dx` (`m · n` items), one after
/// the other with one setup. Returns the merged report.
///
/// # Errors
/// `dx` not a whole number `m ≥ 1` of fields ([`Error::LengthMismatch`]); those of
/// [`angle_tangent`] (the fields before the failing one are written).
pub fn angle_tangent_many<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: AngleSolver<'_, T>,
    options: &SolveOptions<T>,
    dx: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    for_each_field_mut(sys.base().node_count(), dx, |f| {
        angle_tangent(sys, solver, options, f, scratch)
    })
}

/// The adjoint `g = Jᵀ w` of the angle springs: for `w = dJ/dx` at every node, `g = dJ/dx_b`
/// at the fixed nodes (zero at the free nodes):
///
/// ```text
/// A λ = w_f,    g_j = w_j + Σ_{i free} B_ij λ_i   (j fixed)
/// ```
///
/// One CG solve with the deformation's operator (`Aᵀ = A`, see the module documentation) and
/// preconditioner (the node blocks for [`AngleMethod::Cg`], or the V-cycle of the given
/// hierarchy) on the right-hand side `w_f`, from a zero initial guess; one lane (the blocks
/// couple the components). When `ε = 0` the rigidity probe runs first, as in the deformation.
///
/// # Errors
/// Nothing is written on error: `w`, `g` not one item per node ([`Error::LengthMismatch`]);
/// non-finite `w` ([`Error::NonFinite`]); bad options; a direct method
/// ([`Error::InvalidParameter`]); `scratch` shorter than [`angle_adjoint_scratch_len`]
/// ([`Error::BufferTooSmall`]); a hierarchy of another system; the probe's and CG's errors
/// ([`Error::SingularSystem`], [`Error::Overflow`]).
pub fn angle_adjoint<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: AngleSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let base = sys.base();
    let n = base.node_count();
    check_adjoint(n, w, g, options)?;
    if let AngleSolver::Amg(h) = solver {
        h.check_system(base)?;
    }
    let needed = angle_adjoint_scratch_len(sys, &solver);
    if needed == usize::MAX {
        return Err(NOT_CG);
    }
    sys.probe_rigidity(options, scratch, needed)?;
    let (lambda, v, rest) = adjoint_parts(scratch, n, needed)?;
    let layout = RhsLayout {
        kmax: base.stiffness().iter().fold(T::ZERO, |m, &k| m.max(k)),
        joint: true,
        per_node: true,
    };
    let fixed = |i| base.is_fixed(i);
    let serial = Serial::new(n);
    let report = match solver {
        AngleSolver::Amg(h) => {
            let mut pre = Vcycle::new(base, h, rest);
            solve_rhs(sys, &mut pre, v, w, lambda, layout, fixed, options, &serial)?
        }
        AngleSolver::Method(_) => {
            let mut pre = NodeBlocks(sys);
            solve_rhs(sys, &mut pre, v, w, lambda, layout, fixed, options, &serial)?
        }
    };
    pull_back(sys, w, lambda, g);
    Ok(report)
}

/// `g_j = w_j + Σ_{i free} B_ji λ_i` at fixed `j` (CSR order; `B_ji = B_ij`), zero at free.
fn pull_back<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    w: &[[T; D]],
    lambda: &[[T; D]],
    g: &mut [[T; D]],
) {
    let base = sys.base();
    for (j, (gj, &wj)) in g.iter_mut().zip(w).enumerate() {
        if !base.is_fixed(j) {
            *gj = [T::ZERO; D];
            continue;
        }
        let mut acc = wj;
        for (i, k) in base.row(j) {
            if base.is_fixed(i) {
                continue;
            }
            let (Some((d, d2)), Some(li)) = (sys.direction(j, i), lambda.get(i)) else {
                continue;
            };
            acc = vector::add(acc, sys.edge_apply(k, &d, d2, li));
        }
        *gj = acc;
    }
}

/// [`angle_adjoint`] for `m` fields `w` back to back (`m · n` items; `g` as long), one after
/// the other with one setup. Returns the merged report.
///
/// # Errors
/// `w` not a whole number `m ≥ 1` of fields or `g` of another length
/// ([`Error::LengthMismatch`]); those of [`angle_adjoint`] (fields before the failing one are
/// written).
pub fn angle_adjoint_many<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: AngleSolver<'_, T>,
    options: &SolveOptions<T>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    for_each_field(sys.base().node_count(), w, g, |w, g| {
        angle_adjoint(sys, solver, options, w, g, scratch)
    })
}
