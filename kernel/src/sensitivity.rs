//! Mesh sensitivities: the derivative of a deformation with respect to the prescribed
//! boundary motion, forward (tangent) and reverse (adjoint).
//!
//! Every method here is, with the undeformed mesh fixed, a **linear** map from the boundary
//! displacement `δx_b` to the displacement of every node, `δx = J δx_b`:
//!
//! - linear springs (Batina) and single-step linear elasticity: `x_f = A⁻¹ B x_b` with `A`
//!   the free-node operator (symmetric positive definite) and `B` the free–fixed coupling
//!   (`A = D − K_ff`, `B = K_fb` for the springs; `A = K_ff`, `B = −K_fb` for elasticity);
//! - the angle-inclusion springs: the same form with `D×D` edge blocks (`angle_*`);
//! - radial basis functions with the centres of a fit kept (`rbf_tangent`, `rbf_adjoint`,
//!   in [`crate::rbf`]: the greedy selection is differentiated about a linearisation point);
//! - inverse-distance weighting of the displacements: `x_i = Σ_k w_ik x_k / Σ_k w_ik`, the
//!   weights from the undeformed distances alone.
//!
//! With sliding nodes (symmetry planes, [`Constraints`](crate::spring::constraints::Constraints))
//! the linear springs and single-step elasticity stay linear (the planes are fixed): the
//! `*_sliding_*` functions solve the projected system `P A P` (see that module).
//!
//! Multi-step elasticity (load increments re-assembled on the moved mesh,
//! `elastic_incremental_tangent` / `_adjoint`) is not linear: its exact linearisation adds the
//! derivative of the stiffness with respect to the mesh, step by step (see that module).
//!
//! So the **tangent** is the deformation itself applied to `δx_b` (one more solve with the
//! same operator and preconditioner, or one more weighting pass), and the **adjoint** of a
//! given `w = dJ/dx` at every node is
//!
//! ```text
//! A λ = w_f,    g_b = w_b + Bᵀ λ     (g = dJ/dx_b, zero at free nodes)
//! ```
//!
//! one solve with the same operator (symmetric: `Aᵀ = A`, so the same conjugate-gradient loop
//! and the same preconditioner or multigrid hierarchy) whose right-hand side is `w_f` instead
//! of the fixed nodes' pull. The IDW adjoint is the transposed weighting, `g_k = w_k + Σ_i
//! w_i ω_ik / Σ_j ω_ij`. Nothing here is non-symmetric; the quaternion method's linearisation
//! (normals, rotations, normalisation: not linear) lives with that method.
//!
//! **Several right-hand sides**: the `*_many` functions take `m` fields back to back and
//! loop over them with one setup (the multigrid hierarchy, the validated system); the linear
//! springs also solve any `V` components in one pass (pack `m` fields of `D` components as
//! `V = m·D`: one lane per component).
//!
//! **Accuracy**: the iterative solves meet [`SolveOptions`], so
//! tangent and adjoint agree with each other (`⟨J v, w⟩ = ⟨v, Jᵀ w⟩`) to the solver
//! tolerance, not to rounding; pick `residual_tol` accordingly. The report says whether the
//! solve converged.
//!
//! Everything works on caller slices (`*_scratch_len` gives the sizes), validates before it
//! writes and returns typed errors.

mod angle;
mod elastic_geometry;
mod elasticity;
mod elasticity_steps;
mod idw;
mod sliding;
mod springs;
mod zero_lanes;

pub use crate::rbf::{rbf_adjoint, rbf_tangent};
pub use angle::{
    angle_adjoint, angle_adjoint_many, angle_adjoint_scratch_items, angle_adjoint_scratch_len,
    angle_tangent, angle_tangent_many, angle_tangent_scratch_len, AngleSolver,
};
pub use elasticity::{
    elastic_adjoint, elastic_adjoint_many, elastic_adjoint_scratch_len, elastic_tangent,
    elastic_tangent_many, elastic_tangent_scratch_len, ElasticPreconditioner,
};
pub use elasticity_steps::{
    elastic_incremental_adjoint, elastic_incremental_adjoint_scratch_len,
    elastic_incremental_tangent, elastic_incremental_tangent_scratch_len, IncrementProblem,
};
pub use idw::{idw_adjoint, idw_adjoint_many, idw_tangent, idw_tangent_many};
pub use sliding::{
    elastic_sliding_adjoint, elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    elastic_sliding_tangent_scratch_len, spring_sliding_adjoint,
    spring_sliding_adjoint_scratch_len, spring_sliding_tangent,
};
pub use springs::{
    spring_adjoint, spring_adjoint_many, spring_adjoint_scratch_len, spring_tangent,
    spring_tangent_many,
};

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::krylov::Vectors;
use crate::spring::{SolveOptions, SolveReport};

/// The checks every adjoint makes before anything else: `w` and `g` one item per node, `w`
/// finite, the options valid.
fn check_adjoint<T: Real, const V: usize>(
    n: usize,
    w: &[[T; V]],
    g: &[[T; V]],
    options: &SolveOptions<T>,
) -> Result<()> {
    check::len("w", w.len(), n)?;
    check::len("g", g.len(), n)?;
    check::finite_items("w", w)?;
    options.check()
}

/// The adjoint field `λ` (`n` items), the CG vectors and the rest (the preconditioner's) from
/// the front of `scratch`, which must hold `needed` items.
type AdjointParts<'s, T, const V: usize> = (&'s mut [[T; V]], Vectors<'s, T, V>, &'s mut [[T; V]]);

fn adjoint_parts<T: Real, const V: usize>(
    scratch: &mut [[T; V]],
    n: usize,
    needed: usize,
) -> Result<AdjointParts<'_, T, V>> {
    check::buffer("scratch", scratch.len(), needed)?;
    let small = Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual: scratch.len(),
    };
    let (lambda, rest) = scratch.split_at_mut_checked(n).ok_or(small)?;
    let (v, rest) = Vectors::split(rest, n).ok_or(small)?;
    Ok((lambda, v, rest))
}

/// `m · n` items hold `m ≥ 1` whole fields of `n` items.
fn check_fields(arg: &'static str, n: usize, len: usize) -> Result<()> {
    if n == 0 || len == 0 || len % n != 0 {
        return Err(Error::LengthMismatch {
            arg,
            expected: n,
            actual: len,
        });
    }
    Ok(())
}

/// The reports of several solves as one: the most iterations, the largest residual and
/// update, converged only when every solve did.
pub(crate) fn merge<T: Real>(a: Option<SolveReport<T>>, b: SolveReport<T>) -> SolveReport<T> {
    match a {
        None => b,
        Some(a) => SolveReport {
            iterations: a.iterations.max(b.iterations),
            residual: a.residual.max(b.residual),
            max_update: a.max_update.max(b.max_update),
            converged: a.converged && b.converged,
        },
    }
}

/// Calls `f` on each of the `m` back-to-back fields of `n` items in `a` (input) and `b`
/// (output, as long as `a`) in turn and merges the reports; stops at the first error (the
/// fields before it are written, the others untouched).
fn for_each_field<T: Real, X, Y>(
    n: usize,
    a: &[X],
    b: &mut [Y],
    mut f: impl FnMut(&[X], &mut [Y]) -> Result<SolveReport<T>>,
) -> Result<SolveReport<T>> {
    check_fields("inputs", n, a.len())?;
    check::len("outputs", b.len(), a.len())?;
    let mut all = None;
    for (a, b) in a.chunks_exact(n).zip(b.chunks_exact_mut(n)) {
        all = Some(merge(all, f(a, b)?));
    }
    all.ok_or(Error::LengthMismatch {
        arg: "inputs",
        expected: n,
        actual: 0,
    })
}

/// [`for_each_field`] for in-place fields (tangents).
fn for_each_field_mut<T: Real, X>(
    n: usize,
    a: &mut [X],
    mut f: impl FnMut(&mut [X]) -> Result<SolveReport<T>>,
) -> Result<SolveReport<T>> {
    check_fields("fields", n, a.len())?;
    let mut all = None;
    for a in a.chunks_exact_mut(n) {
        all = Some(merge(all, f(a)?));
    }
    all.ok_or(Error::LengthMismatch {
        arg: "fields",
        expected: n,
        actual: 0,
    })
}
