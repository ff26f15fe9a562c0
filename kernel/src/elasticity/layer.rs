//! A rigid wall layer for elasticity (issue 28): the nodes within a distance of the moving
//! wall move with the wall's local rigid motion, the quaternion method's near-wall rotation,
//! and only the rest of the mesh is solved. The first grid lines then keep their angle to the
//! wall by construction (a rigid motion turns wall and grid line alike). With a Poisson
//! ratio of 0.45 outside (volume change costlier than shear), this is the kernel's best
//! method on a viscous airfoil pitched 50° (docs/methods.md).

use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::spring::is_fixed;
use crate::vector::{add, sub};

/// Marks the nodes within `thickness` of a wall node as fixed and gives each the rigid motion
/// of its nearest wall node `w`: `d = d_w + Q_w (x − x_w) Q_w* − (x − x_w)` with `d_w` the
/// wall node's displacement (read from `displacement[w]`) and `Q_w` its rotation
/// (`rotations[k]` for `wall[k]`, e.g. [`rigid_rotations`](crate::quaternion::rigid_rotations)
/// or [`boundary_rotations`](crate::quaternion::boundary_rotations)). For a rigid motion of
/// the wall (every `Q_w` the same, `d_w` its motion) this is that motion, to rounding.
///
/// Distances are Euclidean in `points` (the undeformed mesh); the nearest wall node is the
/// first in `wall` order on ties. Nodes already fixed (`fixed[i]` set: the wall, other
/// markers) keep their displacement. Returns the number of nodes added. `O(N · B)`.
///
/// # Errors
/// Nothing is written on error: lengths ([`Error::LengthMismatch`]: `fixed`, `displacement`
/// of `points.len()`, `rotations` of `wall.len()`), an empty `wall`
/// ([`Error::InvalidParameter`]), a wall index out of range ([`Error::IndexOutOfRange`]),
/// non-finite points, displacements or rotations ([`Error::NonFinite`]), a rotation too short
/// to normalise ([`Error::ZeroLength`]), a negative or non-finite `thickness`
/// ([`Error::InvalidParameter`]).
pub fn rigid_layer<T: Real, const D: usize>(
    points: &[[T; D]],
    wall: &[u32],
    rotations: &[Quat<T>],
    thickness: T,
    fixed: &mut [u8],
    displacement: &mut [[T; D]],
) -> Result<usize> {
    check::mesh_dim::<D>();
    let n = points.len();
    check::len("fixed", fixed.len(), n)?;
    check::len("displacement", displacement.len(), n)?;
    check::len("rotations", rotations.len(), wall.len())?;
    if wall.is_empty() {
        return Err(Error::InvalidParameter {
            arg: "wall",
            reason: "must name at least one node",
        });
    }
    check::indices("wall", wall, n)?;
    check::finite_items("points", points)?;
    check::finite_items("displacement", displacement)?;
    check::quats("rotations", rotations)?;
    if !(thickness.is_finite() && thickness >= T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "thickness",
            reason: "must be finite and not negative",
        });
    }
    let limit = thickness * thickness;
    let mut added = 0;
    for i in 0..n {
        if is_fixed(fixed.get(i).copied().unwrap_or(1)) {
            continue;
        }
        let Some(&x) = points.get(i) else { continue };
        let Some((k, d2)) = nearest(points, wall, x) else {
            continue;
        };
        if d2 > limit {
            continue;
        }
        let w = wall.get(k).map_or(0, |&w| w as usize);
        let (Some(&xw), Some(&dw)) = (points.get(w), displacement.get(w)) else {
            continue;
        };
        let q = rotations
            .get(k)
            .and_then(|q| q.normalize().ok())
            .unwrap_or_else(Quat::identity);
        let arm = sub(x, xw);
        let turned = crate::quaternion::rotate_d(q, arm);
        if let (Some(f), Some(d)) = (fixed.get_mut(i), displacement.get_mut(i)) {
            *d = add(dw, sub(turned, arm));
            *f = 1;
            added += 1;
        }
    }
    Ok(added)
}

/// The wall node nearest to `x` (position in `wall`) and its squared distance: the first
/// in `wall` order on ties.
fn nearest<T: Real, const D: usize>(
    points: &[[T; D]],
    wall: &[u32],
    x: [T; D],
) -> Option<(usize, T)> {
    let mut best: Option<(usize, T)> = None;
    for (k, &w) in wall.iter().enumerate() {
        let Some(&p) = points.get(w as usize) else {
            continue;
        };
        let e = sub(x, p);
        let d2 = e.iter().fold(T::ZERO, |s, &c| s + c * c);
        if best.is_none_or(|(_, b)| d2 < b) {
            best = Some((k, d2));
        }
    }
    best
}
