//! Quaternion algebra: `dk_quat_*` (f64) and `dk_quat_*_f32`.
//!
//! Quaternions are 4 scalars, scalar first `(w, x, y, z)`, as in Samareh's paper and in the
//! kernel's `Quat` (`#[repr(C)]`). Vectors are 3 scalars, the plane points of
//! `dk_quat_rotate_points_2d` 2.

use deform_kernel::{Quat, QuatAverage, Real, Result as KernelResult};
use deform_kernel_ffi_export::export;

use crate::args::{done, optional, read_array, write_array};
use crate::slice::{chunks, chunks_mut, out_one, output_n, In, Out};
use crate::status::dk_status;

fn read4<T: Real>(p: In<'_, T>) -> Result<Quat<T>, dk_status> {
    read_array::<T, 4>(p).map(Quat::from_array)
}

fn finite_quat<T: Real>(q: Quat<T>) -> Result<Quat<T>, dk_status> {
    if q.is_finite() {
        Ok(q)
    } else {
        Err(dk_status::DK_ERR_NON_FINITE)
    }
}

/// `f(q)` into `out` (`f` is `Quat::normalize` or `Quat::inverse`).
fn map<T: Real>(
    q: In<'_, T>,
    out: Out<'_, T>,
    f: fn(Quat<T>) -> KernelResult<Quat<T>>,
) -> dk_status {
    done((|| write_array(out, f(read4(q)?)?.to_array()))())
}

/// Rotates `D`-vectors with the kernel's `rotate` (`Quat::rotate`, or `Quat::rotate_2d` for
/// points at z = 0: then `q` must turn about z, its x and y components zero, else
/// `DK_ERR_INVALID_PARAMETER`, as a tilted `q` would leave the plane).
fn rotate_points<T: Real, const D: usize>(
    q: In<'_, T>,
    points: In<'_, T>,
    out: Out<'_, T>,
    rotate: impl Fn(Quat<T>, [T; D]) -> [T; D],
) -> dk_status {
    done((|| {
        let q = read4(q)?.normalize()?;
        if D == 2 && (q.x != T::ZERO || q.y != T::ZERO) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        let p = chunks::<T, D>(points)?;
        if out.len() != points.len() {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        if p.iter().flatten().any(|x| !x.is_finite()) {
            return Err(dk_status::DK_ERR_NON_FINITE);
        }
        for (src, dst) in p.iter().zip(chunks_mut::<T, D>(out)?) {
            *dst = rotate(q, *src);
        }
        Ok(())
    })())
}

fn interpolate<T: Real>(
    a: In<'_, T>,
    b: In<'_, T>,
    t: T,
    out: Out<'_, T>,
    spherical: bool,
) -> dk_status {
    done((|| {
        let a = finite_quat(read4(a)?)?;
        let b = finite_quat(read4(b)?)?;
        if !t.is_finite() {
            return Err(dk_status::DK_ERR_NON_FINITE);
        }
        let q = if spherical {
            Quat::slerp(a, b, t)?
        } else {
            Quat::nlerp(a, b, t)?
        };
        write_array(out, q.to_array())
    })())
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Hamilton product `out = a b` (each 4 scalars, scalar first). `out` may alias `a` or `b`.
#[export(twin, a[4], b[4], out[4])]
pub(crate) fn dk_quat_mul<T: Real>(
    a: In<'_, T>,
    b: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let q = finite_quat(read4(a)?)? * finite_quat(read4(b)?)?;
    write_array(out, q.to_array())
}

/// `out = q / |q|`; a zero quaternion gives `DK_ERR_ZERO_LENGTH`, never NaN.
#[export(twin, q[4], out[4])]
pub(crate) fn dk_quat_normalize<T: Real>(q: In<'_, T>, out: Out<'_, T>) -> dk_status {
    map(q, out, Quat::normalize)
}

/// `out = q⁻¹ = q* / |q|²`.
#[export(twin, q[4], out[4])]
pub(crate) fn dk_quat_inverse<T: Real>(q: In<'_, T>, out: Out<'_, T>) -> dk_status {
    map(q, out, Quat::inverse)
}

/// Rotation by `angle` radians about `axis` (3 scalars, normalised here).
#[export(twin, axis[3], out[4])]
pub(crate) fn dk_quat_from_axis_angle<T: Real>(
    axis: In<'_, T>,
    angle: T,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let q = Quat::from_axis_angle(read_array(axis)?, angle)?;
    write_array(out, q.to_array())
}

/// Axis (3 scalars, unit) and angle in `[0, π]` of the rotation `q` (normalised here).
#[export(twin, q[4], axis_out[3], angle_out[1])]
pub(crate) fn dk_quat_to_axis_angle<T: Real>(
    q: In<'_, T>,
    axis_out: Out<'_, T>,
    angle_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let q = read4(q)?.normalize()?;
    let (axis, angle) = q.to_axis_angle();
    // Check both outputs before writing either.
    let angle_slot = out_one(angle_out)?;
    let axis_slot = output_n(axis_out, 3)?;
    for (d, x) in axis_slot.iter_mut().zip(axis) {
        *d = x;
    }
    *angle_slot = angle;
    Ok(())
}

/// Shortest rotation taking direction `from` to direction `to` (3 scalars each).
#[export(twin, from[3], to[3], out[4])]
pub(crate) fn dk_quat_rotation_arc<T: Real>(
    from: In<'_, T>,
    to: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let q = Quat::rotation_arc(read_array(from)?, read_array(to)?)?;
    write_array(out, q.to_array())
}

/// Rotates `points_len / 3` points `(x, y, z)` by `q` (normalised here) into `out`.
/// `out_len` must equal `points_len`, a multiple of 3.
#[export(twin, q[4])]
pub(crate) fn dk_quat_rotate_points<T: Real>(
    q: In<'_, T>,
    points: In<'_, T>,
    out: Out<'_, T>,
) -> dk_status {
    rotate_points(q, points, out, Quat::rotate)
}

/// Rotates `points_len / 2` points `(x, y)` of the plane z = 0 by `q` (normalised here) into
/// `out`: the bits of [`dk_quat_rotate_points`] on `(x, y, 0)`, without padding. `q` must be
/// a rotation about z (x and y components zero, as in every product of rotations about z);
/// any other `q` is `DK_ERR_INVALID_PARAMETER`, since it would move points out of the plane.
/// `out_len` must equal `points_len`, a multiple of 2.
#[export(twin, q[4])]
pub(crate) fn dk_quat_rotate_points_2d<T: Real>(
    q: In<'_, T>,
    points: In<'_, T>,
    out: Out<'_, T>,
) -> dk_status {
    rotate_points(q, points, out, Quat::rotate_2d)
}

/// Spherical linear interpolation on the shorter arc (`t` = 0 gives `a`, 1 gives `b`).
#[export(twin, a[4], b[4], out[4])]
pub(crate) fn dk_quat_slerp<T: Real>(
    a: In<'_, T>,
    b: In<'_, T>,
    t: T,
    out: Out<'_, T>,
) -> dk_status {
    interpolate(a, b, t, out, true)
}

/// Normalised linear interpolation on the shorter arc.
#[export(twin, a[4], b[4], out[4])]
pub(crate) fn dk_quat_nlerp<T: Real>(
    a: In<'_, T>,
    b: In<'_, T>,
    t: T,
    out: Out<'_, T>,
) -> dk_status {
    interpolate(a, b, t, out, false)
}

/// Hemisphere-aligned weighted average of `quats_len / 4` quaternions (`q` and `−q` are
/// one rotation), renormalised. `weights` may be NULL with `weights_len` 0 (all 1);
/// otherwise `weights_len == quats_len / 4`.
#[export(twin, out[4])]
pub(crate) fn dk_quat_average<T: Real>(
    quats: In<'_, T>,
    weights: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let qs = chunks::<T, 4>(quats)?;
    let w = optional(weights)?;
    if w.is_some_and(|w| w.len() != qs.len()) {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let mut all = qs.iter().flatten().chain(w.unwrap_or(&[]));
    if all.any(|x| !x.is_finite()) {
        return Err(dk_status::DK_ERR_NON_FINITE);
    }
    let mut acc = QuatAverage::new();
    for (k, &c) in qs.iter().enumerate() {
        let wk = w.and_then(|w| w.get(k).copied()).unwrap_or(T::ONE);
        acc.add(Quat::from_array(c), wk);
    }
    write_array(out, acc.result()?.to_array())
}
