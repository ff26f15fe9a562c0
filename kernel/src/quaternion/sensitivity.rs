//! Tangent (forward) and adjoint (reverse) linearisation of the quaternion deformation with
//! inverse-distance propagation ([`deform_idw`](super::deform_idw)).
//!
//! The deformed mesh is a function `R(d)` of the deformed boundary positions `d` (the
//! undeformed mesh is fixed). [`deform_idw_tangent`] computes `δR = (∂R/∂d) δd` for one
//! boundary perturbation `δd`; [`deform_idw_adjoint`] computes `d̄ = (∂R/∂d)ᵀ w` for one
//! weight field `w = dJ/dR` (a flow adjoint's volume sensitivity), i.e. `dJ/dd` at the
//! boundary points. Both cost about one deformation (`O(N · B)` weights, evaluated once).
//!
//! **Derivation** (stages of the forward, each linearised; the adjoint applies their
//! transposes in reverse order; every small Jacobian is written once and used both ways):
//! 1. *Normals* (3D): `a_i = Σ_e N_e` (raw element normals, `N = (p_b1 − p_a1) × (p_b2 −
//!    p_a2)`), `n_i = a_i / |a_i|`: `δN = δe1 × e2 + e1 × δe2`,
//!    `δn = (I − n nᵀ) δa / |a|`.
//! 2. *Alignment* `Q1 = rotation_arc(n_u, n_d)` `= m / |m|`, `m = [|n_u + n_d|²/2,
//!    n_u × (n_u + n_d)]`: `δQ1 = (I − Q1 Q1ᵀ) δm / |m|`, `δm = [(n_u + n_d) · δn_d,
//!    n_u × δn_d]` (`|m| = |n_u + n_d|`: antiparallel normals have no derivative and are an
//!    error).
//! 3. *Twist* `θ = atan2(S, C)`, `S = Σ (e_u × e_d) · n`, `C = Σ e_u · e_d − (e_u · n)(e_d ·
//!    n)`, `e_u = Q1 (u_j − u_i) Q1*`: `δθ = (C δS − S δC) / (S² + C²)`.
//! 4. *Composition* `Q = P / |P|`, `P = Q2 Q1`, `Q2 = [cos θ/2, n sin θ/2]`:
//!    `δP = δQ2 Q1 + Q2 δQ1`, `δQ = (I − Q Qᵀ) δP / |P|`. In 2D instead each segment turns by
//!    `δα = (t_d × δt_d)_z / |t_d|²`, a node by the mean `δθ`, `δQ = ½ δθ [−Q_z, 0, 0, Q_w]`.
//! 5. *Translations* `Δ_k = (d_k − o) − Q_k (u_k − o) Q_k*`:
//!    `δΔ_k = δd_k − M(Q_k, u_k − o) δQ_k`, `M` the 3×4 Jacobian of the rotation in `Q`.
//! 6. *Propagation*: the weights `w_ik` of the undeformed mesh are constants, so
//!    `δΔ_i = Σ w_ik δΔ_k / Σ w_ik`; `Q_i = S_i / |S_i|`, `S_i = Σ ±w_ik Q_k` (the signs of the
//!    hemisphere alignment are held): `δQ_i = (I − Q_i Q_iᵀ) Σ ±w_ik δQ_k / |S_i|`.
//! 7. *Update* `R_i = o + Δ_i + Q_i (r_i − o) Q_i*`: `δR_i = δΔ_i + M(Q_i, r_i − o) δQ_i`;
//!    boundary nodes are `d` itself: `δR = δd`.
//!
//! Held constant (piecewise-constant choices, whose derivative is zero where it exists): the
//! origin (given, or the centroid of the *undeformed* positions of the moving points), the
//! rotations of [`RotationSource::Rigid`] and [`RotationSource::PerNode`], the angle
//! unwrapping in 2D and the hemisphere signs. A perturbation that makes a resting boundary
//! point move changes the default origin's point set, a jump the derivative does not see.
//!
//! The adjoint of the field stage runs two passes over the boundary per field point (the sum
//! `S_i` must be known before `Q̄_i` is scattered); the weights of the first pass are kept in
//! scratch, so `powf` runs once per pair as in the deformation.

mod boundary;
mod field;
mod idw_fast;
mod lin;
mod spring;
mod tfi;

use self::boundary::{
    rotations2_adjoint, rotations2_tangent, rotations3_adjoint, rotations3_tangent,
    translations_adjoint, translations_tangent, zero, WORK3,
};
use self::field::{idw_adjoint, idw_tangent, Field};
pub use self::idw_fast::{
    deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len, deform_idw_fast_tangent,
};
pub(crate) use self::spring::SolvedSpring;
pub use self::spring::{
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
};
pub use self::tfi::{deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent};
use super::pipeline::{boundary_rotations_with, motion_origin, validate_motion};
use super::{check_exponent, store, take, BoundaryMotion, Pts, RotationSource};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// Scalars of scratch per boundary point: `Q` (4), `δQ`/`Q̄` (4), `δΔ`/`Δ̄` (3), workspace.
const PER_POINT: usize = 11 + WORK3;

/// Length of the `scratch` slice [`deform_idw_tangent`] and [`deform_idw_adjoint`] need:
/// `max(N, 32 B)`.
#[inline]
pub fn deform_idw_sensitivity_scratch_len<const D: usize>(
    node_count: usize,
    boundary_len: usize,
) -> usize {
    node_count.max(boundary_len.saturating_mul(PER_POINT))
}

/// The base state every mode shares: validated input (`check` sees the boundary marks the
/// validation leaves in `scratch[..N]`: 1 at boundary nodes, 0 elsewhere), the origin, the
/// boundary rotations `Q_k` in `scratch[..4 B]`. Returns the origin.
pub(super) fn prepare<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    scratch: &mut [T],
    check: impl FnOnce(&[T]) -> Result<()>,
) -> Result<[T; D]> {
    let (n, b) = (points.len(), motion.nodes.len());
    validate_motion(
        points,
        motion,
        scratch,
        deform_idw_sensitivity_scratch_len::<D>(n, b),
    )?;
    check(scratch.get(..n).unwrap_or_default())?;
    let origin = motion_origin(points, motion)?;
    let (qs, work) = take(scratch, 4 * b);
    let work = work.get_mut(7 * b..).unwrap_or_default();
    boundary_rotations_with(points, motion, origin, work, |k, q| {
        store(qs, k, q.to_array())
    })?;
    Ok(origin)
}

/// The boundary stage of the tangent: with `Q_k` in `scratch[..4 B]` (from [`prepare`]),
/// writes `δQ_k` to `scratch[4 B..8 B]` and `δΔ_k` to `scratch[8 B..11 B]` for the
/// perturbation `direction = δd`.
///
/// # Errors
/// [`Error::ZeroLength`] (`"normal_sum"`, antiparallel normals), [`Error::NonFinite`]
/// (`"tangent"`) when the derivatives overflow.
pub(super) fn boundary_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    origin: [T; D],
    direction: &[[T; D]],
    scratch: &mut [T],
) -> Result<()> {
    let b = motion.nodes.len();
    let (qs, rest) = take(scratch, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (dt, work) = take(rest, 3 * b);
    zero(dq);
    let u = Pts::mapped(points, motion.nodes);
    let d = Pts::direct(motion.deformed);
    if let Some(elements) = shape(motion) {
        if D == 2 {
            rotations2_tangent(d, &elements, direction, qs, work, dq);
        } else {
            rotations3_tangent(u, d, &elements, direction, work, dq)?;
        }
    }
    translations_tangent(u, origin, qs, dq, direction, dt);
    if let Some(position) = dq.iter().chain(dt.iter()).position(|x| !x.is_finite()) {
        return Err(Error::NonFinite {
            arg: "tangent",
            position,
        });
    }
    Ok(())
}

/// Everything in the boundary stage of the adjoint that can fail (the 3D rotations of
/// antiparallel normals), run before `out` is written. `scratch` as for [`boundary_tangent`].
pub(super) fn boundary_adjoint_check<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    scratch: &mut [T],
) -> Result<()> {
    let b = motion.nodes.len();
    let (_, rest) = take(scratch, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (_, work) = take(rest, 3 * b);
    if let (Some(el), 3) = (shape(motion).as_ref(), D) {
        zero(dq);
        let u = Pts::mapped(points, motion.nodes);
        rotations3_adjoint(u, Pts::direct(motion.deformed), el, dq, work, &mut [])?;
    }
    Ok(())
}

/// The boundary stage of the adjoint: with `Q_k`, `Q̄_k` and `Δ̄_k` in `scratch` (the layout
/// of [`boundary_tangent`]), adds `d̄_k` to `out` (`B` items). Call
/// [`boundary_adjoint_check`] first: the error here comes after `out` was written.
pub(super) fn boundary_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    origin: [T; D],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let b = motion.nodes.len();
    let (qs, rest) = take(scratch, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (dt, work) = take(rest, 3 * b);
    let u = Pts::mapped(points, motion.nodes);
    let d = Pts::direct(motion.deformed);
    translations_adjoint(u, origin, qs, dt, dq, out);
    match shape(motion) {
        Some(el) if D == 2 => rotations2_adjoint(d, &el, qs, dq, work, out),
        Some(el) => rotations3_adjoint(u, d, &el, dq, work, out)?,
        None => {}
    }
    Ok(())
}

/// The boundary elements when the rotations come from the shape (the only source whose
/// rotations depend on `d`).
#[inline]
fn shape<'a, T, const D: usize>(motion: &BoundaryMotion<'a, T, D>) -> Option<Cells<'a>> {
    match motion.rotations {
        RotationSource::Shape => motion.elements,
        _ => None,
    }
}

/// Tangent of [`deform_idw`](super::deform_idw): the first-order change `out = δR` of every
/// mesh point for the change `direction = δd` of the deformed boundary positions
/// (`motion.deformed`, one per boundary point), the undeformed `points` held. Boundary nodes
/// get `δd` exactly. `scratch` needs [`deform_idw_sensitivity_scratch_len`] entries.
///
/// # Errors
/// Those of [`deform_idw`](super::deform_idw) for the points, motion and exponent; `direction`
/// or `out` of the wrong length, a non-finite `direction`; [`Error::ZeroLength`]
/// (`"normal_sum"`, 3D shape rotations) where a point's undeformed and deformed normals are
/// antiparallel (the rotation is not differentiable there); [`Error::NonFinite`]
/// (`"tangent"`) when the boundary derivatives overflow. On error `out` is unchanged.
pub fn deform_idw_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    direction: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let b = motion.nodes.len();
    check::len("direction", direction.len(), b)?;
    check::len("out", out.len(), points.len())?;
    let origin = prepare(points, motion, scratch, |_| check_exponent(exponent))?;
    check::finite_items("direction", direction)?;
    boundary_tangent(points, motion, origin, direction, scratch)?;
    let (qs, rest) = take(scratch, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (dt, _) = take(rest, 3 * b);
    let field = Field {
        points,
        boundary: motion.nodes,
        exponent,
        origin,
        qs,
    };
    idw_tangent(&field, dq, dt, direction, out);
    Ok(())
}

/// Adjoint of [`deform_idw`](super::deform_idw): `out = (∂R/∂d)ᵀ w` for the weights
/// `weights = w = dJ/dR` (one per mesh point), i.e. `dJ/dd` at each boundary point (in
/// `motion.nodes` order): the transpose of [`deform_idw_tangent`]. `scratch` needs
/// [`deform_idw_sensitivity_scratch_len`] entries.
///
/// # Errors
/// Those of [`deform_idw_tangent`], with `weights` (one per point, finite) in place of
/// `direction` and `out` one per boundary point. On error `out` is unchanged.
pub fn deform_idw_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    weights: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let b = motion.nodes.len();
    check::len("weights", weights.len(), points.len())?;
    check::len("out", out.len(), b)?;
    let origin = prepare(points, motion, scratch, |_| check_exponent(exponent))?;
    check::finite_items("weights", weights)?;
    boundary_adjoint_check(points, motion, scratch)?;
    let (qs, rest) = take(scratch, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (dt, work) = take(rest, 3 * b);
    zero(dq);
    zero(dt);
    let field = Field {
        points,
        boundary: motion.nodes,
        exponent,
        origin,
        qs,
    };
    for o in out.iter_mut() {
        *o = [T::ZERO; D];
    }
    idw_adjoint(&field, weights, work, dq, dt, out);
    boundary_adjoint(points, motion, origin, scratch, out)?;
    Ok(())
}
