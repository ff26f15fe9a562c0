//! The FFD design variables as control-point changes (`CSurfaceMovement::SetFFDCPChange`,
//! `SetFFDCPChange_2D`, `SetFFDCamber(_2D)`, `SetFFDThickness(_2D)`).
//!
//! Each adds a movement to some control points of one box (SU2's `SetControlPoints` adds),
//! on SU2's always-3D boxes: `degree = [l, m, n]`, control points in the flat order of
//! [`FfdBox::index`](super::ffd::FfdBox::index). Several design variables on the same box
//! accumulate; evaluate the surface afterwards with
//! [`ffd_displacements`](super::ffd::ffd_displacements).
//!
//! The amplitude `a` below is `DV_VALUE × OPT_RELAX_FACTOR` (the factor is 1 unless the config
//! sets it). Not done here (the caller's part): matching `DV_PARAM`'s box tag, SU2's
//! `FFD_FIX_I/J/K` planes (SU2 skips a variable whose index lies on a fixed plane, and with one
//! `-1` index skips the fixed planes along it), and polar/cylindrical/spherical boxes.

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::ffd::{check_box, flat};

/// Adds `movement` to every control point whose index matches `ijk` (`None` matches all).
fn add_where<T: Real>(degree: [usize; 3], cps: &mut [[T; 3]], ijk: [Option<usize>; 3], m: [T; 3]) {
    for i in 0..=degree[0] {
        for j in 0..=degree[1] {
            for k in 0..=degree[2] {
                let hit = [i, j, k]
                    .iter()
                    .zip(&ijk)
                    .all(|(&x, f)| f.is_none_or(|f| f == x));
                if let (true, Some(p)) = (hit, cps.get_mut(flat(degree, [i, j, k]))) {
                    for (c, &d) in p.iter_mut().zip(&m) {
                        *c += d;
                    }
                }
            }
        }
    }
}

/// Box, index and finiteness checks shared by every design variable.
fn check_dv<T: Real, const N: usize>(
    degree: [usize; 3],
    cps: &[[T; 3]],
    ijk: [Option<usize>; 3],
    values: [T; N],
) -> Result<()> {
    check_box(degree, cps)?;
    for (position, (i, d)) in ijk.iter().zip(&degree).enumerate() {
        if let Some(i) = *i {
            if i > *d {
                return Err(Error::IndexOutOfRange {
                    arg: "index",
                    position,
                    index: i,
                    bound: d + 1,
                });
            }
        }
    }
    check::finite("movement", &values)
}

/// `FFD_CONTROL_POINT`, `DV_PARAM = (box, i, j, k, dx, dy, dz)`: adds `movement` to control
/// point `(i, j, k)`; a `None` index is SU2's `-1` (every control point along that direction).
/// `movement` is `(dx·a, dy·a, dz·a)`, or the three `DV_VALUE`s when the variable has three
/// (SU2 then ignores dx, dy, dz and the relax factor).
///
/// # Errors
/// [`Error::InvalidParameter`] for bad degrees, or for three `None`s (SU2 moves nothing then,
/// silently); [`Error::LengthMismatch`] when `control_points` does not fit the degrees;
/// [`Error::IndexOutOfRange`] for an index above its degree (`position` 0, 1, 2 = i, j, k);
/// [`Error::NonFinite`] for a non-finite movement. Nothing is written on error.
pub fn ffd_control_point<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    ijk: [Option<usize>; 3],
    movement: [T; 3],
) -> Result<()> {
    check_dv(degree, control_points, ijk, movement)?;
    if ijk.iter().all(Option::is_none) {
        return Err(Error::InvalidParameter {
            arg: "index",
            reason: "SU2 moves no control point when i, j and k are all -1",
        });
    }
    add_where(degree, control_points, ijk, movement);
    Ok(())
}

/// `FFD_CONTROL_POINT_2D`, `DV_PARAM = (box, i, j, dx, dy)`: adds `(movement[0], movement[1],
/// 0)` to control points `(i, j, 0)` and `(i, j, 1)` (both layers of SU2's 2D box); a `None`
/// index is SU2's `-1`. `movement` is `(dx·a, dy·a)` or the two `DV_VALUE`s.
///
/// # Errors
/// As [`ffd_control_point`], except that two `None`s are allowed (SU2 moves the whole layer).
pub fn ffd_control_point_2d<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    ij: [Option<usize>; 2],
    movement: [T; 2],
) -> Result<()> {
    let m = [movement[0], movement[1], T::ZERO];
    check_dv(degree, control_points, [ij[0], ij[1], Some(1)], m)?;
    for k in 0..2 {
        add_where(degree, control_points, [ij[0], ij[1], Some(k)], m);
    }
    Ok(())
}

/// `FFD_CAMBER` (`sign = 1`) and `FFD_THICKNESS` (`sign = -1`) in 3D: `(i, j, 0)` moves by
/// `sign · a` in z and `(i, j, 1)` by `a`.
fn camber_thickness<T: Real>(
    degree: [usize; 3],
    cps: &mut [[T; 3]],
    ij: [usize; 2],
    a: T,
    lower: T,
) -> Result<()> {
    check_dv(degree, cps, [Some(ij[0]), Some(ij[1]), Some(1)], [a, lower])?;
    add_where(
        degree,
        cps,
        [Some(ij[0]), Some(ij[1]), Some(0)],
        [T::ZERO, T::ZERO, lower],
    );
    add_where(
        degree,
        cps,
        [Some(ij[0]), Some(ij[1]), Some(1)],
        [T::ZERO, T::ZERO, a],
    );
    Ok(())
}

/// `FFD_CAMBER`, `DV_PARAM = (box, i, j)`: control points `(i, j, 0)` and `(i, j, 1)` move by
/// `amplitude` in z.
///
/// # Errors
/// As [`ffd_control_point`] (`position` 0, 1 = i, j).
pub fn ffd_camber<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    i: usize,
    j: usize,
    amplitude: T,
) -> Result<()> {
    camber_thickness(degree, control_points, [i, j], amplitude, amplitude)
}

/// `FFD_THICKNESS`, `DV_PARAM = (box, i, j)`: control point `(i, j, 0)` moves by
/// `−amplitude` in z and `(i, j, 1)` by `+amplitude`.
///
/// # Errors
/// As [`ffd_camber`].
pub fn ffd_thickness<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    i: usize,
    j: usize,
    amplitude: T,
) -> Result<()> {
    camber_thickness(degree, control_points, [i, j], amplitude, -amplitude)
}

/// `FFD_CAMBER_2D` (`lower = a`) and `FFD_THICKNESS_2D` (`lower = −a`): `(i, 0, k)` moves by
/// `lower` in y and `(i, 1, k)` by `a`, for `k = 0, 1`.
fn camber_thickness_2d<T: Real>(
    degree: [usize; 3],
    cps: &mut [[T; 3]],
    i: usize,
    a: T,
    lower: T,
) -> Result<()> {
    check_dv(degree, cps, [Some(i), Some(1), Some(1)], [a, lower])?;
    for k in 0..2 {
        add_where(
            degree,
            cps,
            [Some(i), Some(0), Some(k)],
            [T::ZERO, lower, T::ZERO],
        );
        add_where(
            degree,
            cps,
            [Some(i), Some(1), Some(k)],
            [T::ZERO, a, T::ZERO],
        );
    }
    Ok(())
}

/// `FFD_CAMBER_2D`, `DV_PARAM = (box, i)`: control points `(i, j, k)`, `j, k ∈ {0, 1}`, move
/// by `amplitude` in y.
///
/// # Errors
/// As [`ffd_control_point`].
pub fn ffd_camber_2d<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    i: usize,
    amplitude: T,
) -> Result<()> {
    camber_thickness_2d(degree, control_points, i, amplitude, amplitude)
}

/// `FFD_THICKNESS_2D`, `DV_PARAM = (box, i)`: control points `(i, 0, k)` move by `−amplitude`
/// in y and `(i, 1, k)` by `+amplitude`, `k ∈ {0, 1}`.
///
/// # Errors
/// As [`ffd_control_point`].
pub fn ffd_thickness_2d<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    i: usize,
    amplitude: T,
) -> Result<()> {
    camber_thickness_2d(degree, control_points, i, amplitude, -amplitude)
}
