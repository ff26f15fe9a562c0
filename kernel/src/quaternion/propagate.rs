//! Inverse-distance propagation of `(Δ, Q)` into the field.

use super::check_exponent;
use crate::check;
use crate::error::{Error, Result};
use crate::quat::{Quat, QuatAverage};
use crate::real::Real;
use crate::vector::{norm_robust, norm_sq, scale, sub};

/// Validates the boundary entries of field arrays: indices, finite translations and
/// normalisable rotations at every boundary node.
pub(super) fn check_boundary_entries<T: Real, const D: usize>(
    boundary: &[u32],
    translations: &[[T; D]],
    rotations: &[Quat<T>],
) -> Result<()> {
    check::indices(
        "boundary",
        boundary,
        translations.len().min(rotations.len()),
    )?;
    for &b in boundary {
        let b = b as usize;
        if let Some(t) = translations.get(b) {
            check::finite_items("translations", core::slice::from_ref(t)).map_err(|_| {
                Error::NonFinite {
                    arg: "translations",
                    position: b,
                }
            })?;
        }
        if let Some(q) = rotations.get(b) {
            if !q.is_finite() {
                return Err(Error::NonFinite {
                    arg: "rotations",
                    position: b,
                });
            }
            if q.normalize().is_err() {
                return Err(Error::ZeroLength {
                    arg: "rotations",
                    position: b,
                });
            }
        }
    }
    Ok(())
}

/// Inverse-distance weighting of the boundary translations and rotations into the rest of the
/// mesh. On entry `translations` and `rotations` hold the boundary values at the nodes listed
/// in `boundary` (other entries are ignored); on exit every other node holds, with `d_k` the
/// distance (undeformed `points`) to boundary node `k`,
///
/// ```text
/// w_k = (d_min / d_k)^p,   Δ = Σ w_k Δ_k / Σ w_k,   Q = normalise(Σ w_k ±Q_k)
/// ```
///
/// (the usual `d^−p` weights scaled by `d_min^p`: they stay in `(0, 1]` and cannot overflow).
/// Each `Q_k` is flipped into the hemisphere of the nearest boundary node's rotation (`q` and
/// `−q` are one rotation) and the sum is renormalised. A node at zero distance from a
/// boundary node takes that node's values exactly (the first such in `boundary` order); the
/// boundary entries themselves are never written. Summation is in `boundary` order.
///
/// Cost: `O(N · B)` distance evaluations (and `powf` unless `p = 2`), with no scratch; fine
/// for the 10⁴–10⁵-node meshes and 10²–10³-node boundaries this targets. Larger problems
/// should subsample the boundary. `exponent` `p` must be finite and positive; 2–5 is typical
/// (larger is more local).
///
/// # Errors
/// Length mismatches (`translations`, `rotations` have one entry per point), an empty
/// boundary, out-of-range boundary indices, non-finite points or boundary values, zero
/// boundary rotations, a bad exponent. On error nothing is written.
pub fn propagate_idw<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = points.len();
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    if boundary.is_empty() {
        return Err(Error::InvalidParameter {
            arg: "boundary",
            reason: "must not be empty",
        });
    }
    check_exponent(exponent)?;
    check::finite_items("points", points)?;
    check_boundary_entries(boundary, translations, rotations)?;

    for (i, x) in points.iter().enumerate() {
        if let Some((t, q)) = idw_point(points, boundary, exponent, translations, rotations, i, *x)
        {
            if let Some(x) = translations.get_mut(i) {
                *x = t;
            }
            if let Some(x) = rotations.get_mut(i) {
                *x = q;
            }
        }
    }
    Ok(())
}

/// What [`idw_point`] learns in its first pass over the boundary at one field point: the
/// nearest boundary node and the distance scale of the weights.
#[derive(Clone, Copy)]
pub(crate) struct IdwScan<T> {
    /// Mesh node of the nearest boundary point (the first wins ties).
    pub(crate) nearest: u32,
    /// Position of the nearest boundary point in `boundary`.
    pub(super) nearest_pos: usize,
    /// `true` when every squared distance is a normal number (or an exact zero): weights from
    /// squared distances; `false`: from the robust distances.
    plain: bool,
    /// The smallest squared distance (`plain`) or robust distance (otherwise); zero when the
    /// point coincides with a boundary point.
    pub(crate) dmin: T,
}

/// Distance / 4 without overflow or underflow (the quarter keeps `x − b` finite): the
/// fallback when a squared distance leaves the normal range.
#[inline]
fn robust<T: Real, const D: usize>(x: [T; D], b: [T; D]) -> T {
    let quarter = T::HALF * T::HALF;
    norm_robust(sub(scale(x, quarter), scale(b, quarter)))
}

/// The first pass of [`idw_point`] at field point `x` (mesh node `i`); `None` when `i` is a
/// boundary node.
pub(crate) fn idw_scan<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    i: usize,
    x: [T; D],
) -> Option<IdwScan<T>> {
    let at = |i: u32| points.get(i as usize).copied().unwrap_or([T::ZERO; D]);
    // Nearest boundary node (squared distances; the first wins ties); skip boundary nodes.
    let mut d2min = T::INFINITY;
    let mut nearest = 0u32;
    let mut nearest_pos = 0usize;
    let mut is_boundary = false;
    let mut plain = true;
    for (k, &b) in boundary.iter().enumerate() {
        is_boundary |= b as usize == i;
        let diff = sub(x, at(b));
        let d2 = norm_sq(diff);
        plain &= d2.is_finite() && (d2 >= T::MIN_POSITIVE || diff.iter().all(|&c| c == T::ZERO));
        if d2 < d2min {
            d2min = d2;
            nearest = b;
            nearest_pos = k;
        }
    }
    if is_boundary {
        return None;
    }
    // Squared distances overflowed or underflowed (points beyond ~1e154 or closer than
    // ~1e-154 in f64): weigh by robust distances instead, `w = (h_min / h)^p`.
    if !plain {
        let mut hmin = T::INFINITY;
        for (k, &b) in boundary.iter().enumerate() {
            let h = robust(x, at(b));
            if h < hmin {
                hmin = h;
                nearest = b;
                nearest_pos = k;
            }
        }
        d2min = hmin;
    }
    Some(IdwScan {
        nearest,
        nearest_pos,
        plain,
        dmin: d2min,
    })
}

/// The weight `(d_min / d_b)^p` of boundary point `xb` at field point `x` (`scan.dmin > 0`).
#[inline]
pub(crate) fn idw_weight<T: Real, const D: usize>(
    scan: &IdwScan<T>,
    exponent: T,
    x: [T; D],
    xb: [T; D],
) -> T {
    let half_p = exponent * T::HALF;
    if scan.plain {
        let ratio = scan.dmin / norm_sq(sub(x, xb));
        if half_p == T::ONE {
            ratio
        } else {
            ratio.powf(half_p)
        }
    } else {
        let ratio = scan.dmin / robust(x, xb);
        if half_p == T::ONE {
            ratio * ratio
        } else {
            ratio.powf(exponent)
        }
    }
}

/// The exact inverse-distance value at one field point `x` (mesh node `i`), as
/// [`propagate_idw`] computes it; `None` when `i` is a boundary node. Inputs are validated by
/// the caller. Also the fast method's fallback for points whose squared distances leave the
/// normal range.
pub(super) fn idw_point<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    i: usize,
    x: [T; D],
) -> Option<([T; D], Quat<T>)> {
    let scan = idw_scan(points, boundary, i, x)?;
    let at = |i: u32| points.get(i as usize).copied().unwrap_or([T::ZERO; D]);
    let nearest = scan.nearest;
    let tn = translations
        .get(nearest as usize)
        .copied()
        .unwrap_or([T::ZERO; D]);
    let qn = rotations
        .get(nearest as usize)
        .copied()
        .unwrap_or(Quat::identity());
    if scan.dmin > T::ZERO {
        let mut sum = [T::ZERO; D];
        let mut wsum = T::ZERO;
        let mut qavg = QuatAverage::with_reference(qn);
        for &b in boundary {
            let w = idw_weight(&scan, exponent, x, at(b));
            let bt = translations.get(b as usize).copied().unwrap_or(tn);
            for (s, c) in sum.iter_mut().zip(bt) {
                *s += w * c;
            }
            wsum += w;
            qavg.add(rotations.get(b as usize).copied().unwrap_or(qn), w);
        }
        for s in sum.iter_mut() {
            *s /= wsum;
        }
        Some((sum, qavg.result().unwrap_or(qn)))
    } else {
        Some((tn, qn))
    }
}
