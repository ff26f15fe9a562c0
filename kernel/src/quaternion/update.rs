//! The field update `R^d = o + Δ + Q (R^u − o) Q*` (Samareh eq. 6).

use super::rotate_d;
use crate::check;
use crate::error::Result;
use crate::quat::Quat;
use crate::real::Real;
use crate::vector::{add, sub};

/// Moves every mesh point by its propagated translation and rotation (Samareh eq. 6, about
/// `origin`): `out_i = o + (Δ_i + Q_i (R_i^u − o) Q_i*)`, each `Q_i` normalised first (as in
/// [`boundary_translations`](super::boundary_translations)). Every node listed in `boundary`
/// is then set to its `boundary_deformed` position exactly (see the module note on boundary
/// exactness; a node listed twice takes its last entry). Every entry of `out` is written; its
/// previous contents are ignored.
///
/// # Errors
/// Length mismatches (`translations`, `rotations` and `out` have one entry per point,
/// `boundary_deformed` one per boundary node), out-of-range boundary indices, non-finite
/// input, zero rotations. On error `out` is unchanged.
pub fn update_points<T: Real, const D: usize>(
    origin: [T; D],
    points: &[[T; D]],
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    boundary: &[u32],
    boundary_deformed: &[[T; D]],
    out: &mut [[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = points.len();
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    check::len("out", out.len(), n)?;
    check::len("boundary_deformed", boundary_deformed.len(), boundary.len())?;
    for &x in origin.iter() {
        check::scalar("origin", x)?;
    }
    check::indices("boundary", boundary, n)?;
    // One fused pass over points, translations and rotations (no square roots); only when it
    // finds a problem do the per-array checks run, to report the same first error as always.
    let valid = all_valid(points, translations, rotations);
    if !valid {
        check::finite_items("points", points)?;
        check::finite_items("translations", translations)?;
    }
    check::finite_items("boundary_deformed", boundary_deformed)?;
    if !valid {
        check::quats("rotations", rotations)?;
    }
    for (((o, r), t), q) in out.iter_mut().zip(points).zip(translations).zip(rotations) {
        let q = q.normalize().unwrap_or(Quat::identity());
        *o = apply(origin, *r, *t, q);
    }
    for (b, d) in boundary.iter().zip(boundary_deformed) {
        if let Some(o) = out.get_mut(*b as usize) {
            *o = *d;
        }
    }
    Ok(())
}

/// `true` when every point and translation is finite and every rotation can be normalised
/// (finite, largest component at least `MIN_POSITIVE`: exactly when [`Quat::normalize`]
/// succeeds). Branch-free per item so the pass runs at memory speed.
#[inline]
fn all_valid<T: Real, const D: usize>(
    points: &[[T; D]],
    translations: &[[T; D]],
    rotations: &[Quat<T>],
) -> bool {
    let mut ok = true;
    for ((r, t), q) in points.iter().zip(translations).zip(rotations) {
        let m = q.w.abs().max(q.x.abs()).max(q.y.abs()).max(q.z.abs());
        ok &= r.iter().chain(t).fold(true, |a, c| a & c.is_finite())
            & q.is_finite()
            & (m >= T::MIN_POSITIVE);
    }
    ok
}

/// `o + (t + q (r − o) q*)` for a unit `q`.
#[inline]
pub(crate) fn apply<T: Real, const D: usize>(
    origin: [T; D],
    r: [T; D],
    t: [T; D],
    q: Quat<T>,
) -> [T; D] {
    add(origin, add(t, rotate_d(q, sub(r, origin))))
}
