//! The field update `R^d = o + Δ + Q (R^u − o) Q*` (Samareh eq. 6).

use super::{
    check_dim, check_finite, check_indices, check_len, check_quats, check_scalar, rotate_d,
};
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
/// Errors: length mismatches (`translations`, `rotations` and `out` have one entry per point,
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
    check_dim::<D>()?;
    let n = points.len();
    check_len("translations", translations.len(), n)?;
    check_len("rotations", rotations.len(), n)?;
    check_len("out", out.len(), n)?;
    check_len("boundary_deformed", boundary_deformed.len(), boundary.len())?;
    for &x in origin.iter() {
        check_scalar("origin", x)?;
    }
    check_indices("boundary", boundary, n)?;
    check_finite("points", points)?;
    check_finite("translations", translations)?;
    check_finite("boundary_deformed", boundary_deformed)?;
    check_quats("rotations", rotations)?;
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

/// `o + (t + q (r − o) q*)` for a unit `q`.
#[inline]
pub(super) fn apply<T: Real, const D: usize>(
    origin: [T; D],
    r: [T; D],
    t: [T; D],
    q: Quat<T>,
) -> [T; D] {
    add(origin, add(t, rotate_d(q, sub(r, origin))))
}
