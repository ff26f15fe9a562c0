//! The wall correction: after a reduced fit, the boundary residual `r_k` (motion minus
//! interpolant) is carried into the volume by
//!
//! ```text
//! c(x) = ψ(d_min / R) · Σ w_k r_k / Σ w_k,   w_k = ((1 − ρ_k) / ρ_k)²,  ρ_k = |x − y_k| / R,
//! ```
//!
//! over the boundary entries within `R` (the correction radius), `ψ` Wendland's C2 function
//! and `d_min` the distance to the nearest boundary entry. At a boundary node the weighted
//! mean is that node's residual and `ψ = 1`, so interpolant plus correction is the prescribed
//! motion (to one rounding; the kernel then writes the motion itself); `c` is continuous,
//! bounded by the largest residual, and exactly zero farther than `R` from the boundary. The
//! sums are exact ([`ExactSum`]), so the bucket order does not change a bit.

use super::grid::Grid;
use super::model::{dist_sq, wendland, Model};
use crate::exact_sum::ExactSum;
use crate::real::Real;

/// Calls `each(k, w_k)` for every boundary entry strictly within `radius` of `x` and not at
/// it; returns the first entry at `x` (if any) and the smallest `ρ_k` of the others.
fn weights<T: Real, const D: usize>(
    model: &Model<'_, T, D>,
    grid: &Grid<'_, T, D>,
    radius: T,
    x: [T; D],
    mut each: impl FnMut(usize, T),
) -> (Option<usize>, T) {
    let r2max = radius * radius;
    let mut nearest = T::INFINITY;
    let mut hit: Option<usize> = None;
    grid.for_near(x, radius, |k| {
        let d2 = dist_sq(x, model.boundary_point(k));
        if d2 >= r2max {
            return;
        }
        if d2 == T::ZERO {
            hit = Some(hit.map_or(k, |h| h.min(k)));
            return;
        }
        let rho = (d2.sqrt() / radius).max(T::EPSILON);
        nearest = nearest.min(rho);
        let q = (T::ONE - rho) / rho;
        each(k, q * q);
    });
    (hit, nearest)
}

/// The correction at `x` (zeros when no boundary entry is within `radius`).
pub(super) fn correction<T: Real, const D: usize>(
    model: &Model<'_, T, D>,
    grid: &Grid<'_, T, D>,
    residual: &[T],
    radius: T,
    x: [T; D],
) -> [T; D] {
    let mut sums = [ExactSum::new(); D];
    let mut weight = ExactSum::new();
    let res = |k: usize, c: usize| residual.get(k * D + c).copied().unwrap_or(T::ZERO);
    let (hit, nearest) = weights(model, grid, radius, x, |k, w| {
        weight.add(w);
        for (c, s) in sums.iter_mut().enumerate() {
            s.add(w * res(k, c));
        }
    });
    if let Some(k) = hit {
        return core::array::from_fn(|c| res(k, c));
    }
    let total: T = weight.value();
    if total <= T::ZERO || total.is_nan() {
        return [T::ZERO; D];
    }
    let fade = wendland(nearest);
    core::array::from_fn(|c| {
        let mean = sums.get(c).map_or(T::ZERO, |s| s.value::<T>()) / total;
        fade * mean
    })
}

/// The transpose of [`correction`] at `x` applied to `wx`: adds `∂c(x)/∂r_k ᵀ wx` to
/// `rbar[k]` for every boundary entry `k` (`fade · w_k / Σ w` times `wx`, or `wx` itself at
/// the entry `x` sits on). The correction is linear in the residuals.
pub(super) fn correction_adjoint<T: Real, const D: usize>(
    model: &Model<'_, T, D>,
    grid: &Grid<'_, T, D>,
    radius: T,
    x: [T; D],
    wx: [T; D],
    rbar: &mut [T],
) {
    let mut weight = ExactSum::new();
    let (hit, nearest) = weights(model, grid, radius, x, |_, w| weight.add(w));
    let mut add = |k: usize, f: T| {
        for (c, &wc) in wx.iter().enumerate() {
            if let Some(r) = rbar.get_mut(k * D + c) {
                *r += f * wc;
            }
        }
    };
    if let Some(k) = hit {
        add(k, T::ONE);
        return;
    }
    let total: T = weight.value();
    if total <= T::ZERO || total.is_nan() {
        return;
    }
    let fade = wendland(nearest) / total;
    weights(model, grid, radius, x, |k, w| add(k, fade * w));
}
