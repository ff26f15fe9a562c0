//! Limiting how far the propagated motion reaches.

use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;

/// The reach weight: 1 at distance 0, falling smoothly (`1 − 3r² + 2r³`, zero slope at both
/// ends) to 0 at `r = d / radius = 1`, and 0 beyond.
#[inline]
pub fn reach_weight<T: Real>(distance: T, radius: T) -> T {
    let r = distance / radius;
    if r >= T::ONE {
        T::ZERO
    } else if r <= T::ZERO {
        T::ONE
    } else {
        T::ONE - r * r * (T::from_f64(3.0) - T::TWO * r)
    }
}

/// Limits how far the propagated motion reaches (issue: inverse-distance and spring
/// propagation of Samareh's `(Δ, Q)` move nodes far from the moving boundary, because a small
/// interpolated rotation turns a far node about the origin): each node's translation is scaled
/// by `w = `[`reach_weight`]`(d_i, radius)` and its rotation moved toward the identity,
/// `Q_i ← slerp(1, Q_i / |Q_i|, w)`. Nodes farther than `radius` from the moving boundary
/// (`distances`, e.g. [`wall_distances`](crate::spring::wall_distances) to the moving nodes)
/// do not move at all; nodes on it (`d = 0`) keep their motion. Call it between the
/// propagation and [`update_points`](super::update_points). Nodes beyond the radius get the
/// identity and a zero translation; the update then computes `o + (p − o)`, which can differ
/// from `p` in the last bit, so copy `p` for them if you need their bits unchanged.
///
/// # Errors
/// Nothing is written on error: length mismatches, `radius` not finite and positive
/// ([`Error::InvalidParameter`]), a distance that is negative or not finite, a rotation that
/// is not finite or is zero ([`Error::NonFinite`] / [`Error::NonPositive`] /
/// [`Error::ZeroLength`] from normalisation).
pub fn limit_reach<T: Real, const D: usize>(
    distances: &[T],
    radius: T,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
) -> Result<()> {
    check::len("translations", translations.len(), distances.len())?;
    check::len("rotations", rotations.len(), distances.len())?;
    if !(radius.is_finite() && radius > T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "radius",
            reason: "must be finite and positive",
        });
    }
    let limited = |d: T, q: Quat<T>| -> Result<(T, Quat<T>)> {
        let w = reach_weight(d, radius);
        let q = Quat::slerp(Quat::identity(), q.normalize()?, w)?;
        Ok((w, q))
    };
    // Validate every node first (the slerp can fail only on a bad rotation), then write.
    for (position, (&d, &q)) in distances.iter().zip(rotations.iter()).enumerate() {
        if !d.is_finite() {
            return Err(Error::NonFinite {
                arg: "distances",
                position,
            });
        }
        if d < T::ZERO {
            return Err(Error::NonPositive {
                arg: "distances",
                position,
            });
        }
        limited(d, q)?;
    }
    for ((&d, t), q) in distances
        .iter()
        .zip(translations.iter_mut())
        .zip(rotations.iter_mut())
    {
        if let Ok((w, r)) = limited(d, *q) {
            for c in t.iter_mut() {
                *c *= w;
            }
            *q = r;
        }
    }
    Ok(())
}
