//! Derivatives of the design variables, for SU2_DOT's projection of a surface sensitivity
//! onto the design variables: `dJ/dα = Σ_p (dJ/dx_p) · (dx_p/dα)` over the moved surface
//! nodes `p` (docs/sensitivities.md, "Design variables").
//!
//! SU2_DOT differentiates at `α = 0` (the current design: `SetProjection_AD` registers every
//! `DV_VALUE` as 0). There every variable here is linear in its amplitude, so:
//!
//! - **Hicks–Henne**: the tangent is [`hicks_henne`](super::hicks_henne::hicks_henne) with
//!   amplitude 1 (`dy = ±f(x)`); the adjoint is [`hicks_henne_adjoint`].
//! - **FFD**: the surface is linear in the control points, `x_p = Σ_c B_c(u_p) P_c`, so the
//!   tangent for control-point changes `δP` is the box of `δP` evaluated at the surface points
//!   ([`ffd_eval`](super::ffd::ffd_eval)), and the adjoint is its transpose
//!   `P̄_c = Σ_p B_c(u_p) x̄_p` ([`ffd_adjoint`]). A design variable's control-point change at
//!   amplitude 1 (the [`variables`](super::variables) functions on zero control points, or
//!   [`ffd_twist_tangent`](super::twist::ffd_twist_tangent)) then gives
//!   `dJ/dα = Σ_c δP_c · P̄_c`.
//!
//! Allocation-free, panic-free, validated before anything is written.

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::ffd::{basis, check_box, next_index, weight};
use super::hicks_henne::{check_inputs, increment, HicksHenne};

/// `dJ/da` of one `HICKS_HENNE` variable at any amplitude (the bump is linear in it):
/// `Σ_p ±f(x_p) · dj_dx[p][1]` over the listed nodes on the bump's side (`upper`, `x_max` as
/// [`HicksHenne`]), where `dj_dx[p]` is `dJ/dx` at node `nodes[p]`. Multiply by SU2's
/// `OPT_RELAX_FACTOR` for the derivative with respect to `DV_VALUE`.
///
/// # Errors
/// As [`hicks_henne`](super::hicks_henne::hicks_henne) (`dj_dx` in place of the
/// displacements); [`Error::Overflow`] when the sum is not finite.
pub fn hicks_henne_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    normals: &[[T; D]],
    upper: bool,
    x_max: T,
    dj_dx: &[[T; D]],
) -> Result<T> {
    let bump = HicksHenne {
        upper,
        x_max,
        amplitude: T::ONE,
    };
    check_inputs(points, nodes, normals, bump, ("dj_dx", dj_dx.len()))?;
    check::finite_items("dj_dx", dj_dx)?;
    let mut sum = T::ZERO;
    for (p, g) in dj_dx.iter().enumerate() {
        if let (Some(dy), Some(&gy)) = (increment(points, nodes, normals, bump, p), g.get(1)) {
            sum += dy * gy;
        }
    }
    if sum.is_finite() {
        Ok(sum)
    } else {
        Err(Error::Overflow { arg: "dj_dx" })
    }
}

/// The transpose of evaluating a box at the surface points: `out[c] = Σ_p B_c(params[p]) ·
/// dj_dx[p]` for every control point `c` (flat order of
/// [`FfdBox::index`](super::ffd::FfdBox::index)), `dj_dx[p]` being `dJ/dx` at surface point
/// `p`. Then `Σ_c δP_c · out[c] = Σ_p dj_dx[p] · box(δP)(params[p])` for any control-point
/// change `δP` (same products as the evaluation, in the same order). Overwrites `out`.
///
/// # Errors
/// [`Error::InvalidParameter`] for a degree of 0 or above
/// [`MAX_DEGREE`](super::ffd::MAX_DEGREE); [`Error::LengthMismatch`] when `out` does not hold
/// one item per control point or `dj_dx` one per parametric coordinate; [`Error::NonFinite`]
/// for a non-finite parametric coordinate or sensitivity; [`Error::Overflow`] when the result
/// could not be finite (a bound on it overflows). Nothing is written on error.
pub fn ffd_adjoint<T: Real, const D: usize>(
    degree: [usize; D],
    params: &[[T; D]],
    dj_dx: &[[T; D]],
    out: &mut [[T; D]],
) -> Result<()> {
    check_box(degree, out)?;
    check::len("dj_dx", dj_dx.len(), params.len())?;
    check::finite_items("params", params)?;
    check::finite_items("dj_dx", dj_dx)?;
    // |out[c]| ≤ Σ_p Π_a (Σ_i |B_a,i|) · Σ |dj_dx[p]|: finite bound, finite result.
    let mut bound = T::ZERO;
    for (&u, g) in params.iter().zip(dj_dx) {
        let b = basis(degree, u);
        let spread = (b.iter().zip(&degree))
            .map(|(row, &n)| row.iter().take(n + 1).fold(T::ZERO, |s, x| s + x.abs()))
            .fold(T::ONE, |s, x| s * x);
        bound += spread * g.iter().fold(T::ZERO, |s, x| s + x.abs());
    }
    if !bound.is_finite() {
        return Err(Error::Overflow { arg: "params" });
    }
    out.iter_mut().for_each(|o| *o = [T::ZERO; D]);
    for (&u, g) in params.iter().zip(dj_dx) {
        let b = basis(degree, u);
        let mut ijk = [0usize; D];
        for o in out.iter_mut() {
            for (oc, &gc) in o.iter_mut().zip(g) {
                *oc += weight(&b, &ijk, gc);
            }
            next_index(&mut ijk, degree);
        }
    }
    Ok(())
}
