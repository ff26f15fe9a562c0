//! Quaternion algebra: `dk_quat_*` (f64) and `dk_quat_*_f32`.
//!
//! Quaternions are 4 scalars, scalar first `(w, x, y, z)`, as in Samareh's paper and in the
//! kernel's `Quat` (`#[repr(C)]`). Vectors are 3 scalars.
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::{Quat, QuatAverage, Real};

use crate::args::{done, optional, read_array, write_array};
use crate::slice::{input, out_one, output, In, Out};
use crate::status::dk_status;

fn read4<T: Real>(p: In<'_, T>) -> Result<Quat<T>, dk_status> {
    read_array::<T, 4>(p, 4).map(Quat::from_array)
}

fn read3<T: Real>(p: In<'_, T>) -> Result<[T; 3], dk_status> {
    read_array::<T, 3>(p, 3)
}

fn finite_quat<T: Real>(q: Quat<T>) -> Result<Quat<T>, dk_status> {
    if q.is_finite() {
        Ok(q)
    } else {
        Err(dk_status::DK_ERR_NON_FINITE)
    }
}

fn mul<T: Real>(a: In<'_, T>, b: In<'_, T>, out: Out<'_, T>) -> dk_status {
    done((|| {
        let q = finite_quat(read4(a)?)? * finite_quat(read4(b)?)?;
        write_array(out, q.to_array())
    })())
}

fn normalize<T: Real>(q: In<'_, T>, out: Out<'_, T>) -> dk_status {
    done((|| {
        let n = read4(q)?.normalize()?;
        write_array(out, n.to_array())
    })())
}

fn inverse<T: Real>(q: In<'_, T>, out: Out<'_, T>) -> dk_status {
    done((|| {
        let n = read4(q)?.inverse()?;
        write_array(out, n.to_array())
    })())
}

fn from_axis_angle<T: Real>(axis: In<'_, T>, angle: T, out: Out<'_, T>) -> dk_status {
    done((|| {
        let q = Quat::from_axis_angle(read3(axis)?, angle)?;
        write_array(out, q.to_array())
    })())
}

fn to_axis_angle<T: Real>(q: In<'_, T>, axis_out: Out<'_, T>, angle_out: Out<'_, T>) -> dk_status {
    done((|| {
        let q = read4(q)?.normalize()?;
        let (axis, angle) = q.to_axis_angle();
        // Check both outputs before writing either.
        let angle_slot = out_one(angle_out)?;
        let axis_slot = output(axis_out, 3)?;
        for (d, x) in axis_slot.iter_mut().zip(axis) {
            *d = x;
        }
        *angle_slot = angle;
        Ok(())
    })())
}

fn rotation_arc<T: Real>(from: In<'_, T>, to: In<'_, T>, out: Out<'_, T>) -> dk_status {
    done((|| {
        let q = Quat::rotation_arc(read3(from)?, read3(to)?)?;
        write_array(out, q.to_array())
    })())
}

fn rotate_points<T: Real>(
    q: In<'_, T>,
    points: In<'_, T>,
    points_len: usize,
    out: Out<'_, T>,
    out_len: usize,
) -> dk_status {
    done((|| {
        let q = read4(q)?.normalize()?;
        let p = input(points, points_len)?;
        if points_len % 3 != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        if out_len != points_len {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        if p.iter().any(|x| !x.is_finite()) {
            return Err(dk_status::DK_ERR_NON_FINITE);
        }
        let o = output(out, out_len)?;
        for (src, dst) in p.chunks_exact(3).zip(o.chunks_exact_mut(3)) {
            if let ([x, y, z], [a, b, c]) = (src, dst) {
                let r = q.rotate([*x, *y, *z]);
                *a = r[0];
                *b = r[1];
                *c = r[2];
            }
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

fn average<T: Real>(
    quats: In<'_, T>,
    quats_len: usize,
    weights: In<'_, T>,
    weights_len: usize,
    out: Out<'_, T>,
) -> dk_status {
    done((|| {
        let qs = input(quats, quats_len)?;
        if quats_len % 4 != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        let w = optional(weights, weights_len)?;
        if w.is_some() && weights_len != quats_len / 4 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        if qs
            .iter()
            .chain(w.unwrap_or(&[]).iter())
            .any(|x| !x.is_finite())
        {
            return Err(dk_status::DK_ERR_NON_FINITE);
        }
        let mut acc = QuatAverage::new();
        for (k, c) in qs.chunks_exact(4).enumerate() {
            if let [qw, qx, qy, qz] = *c {
                let wk = w.and_then(|w| w.get(k).copied()).unwrap_or(T::ONE);
                acc.add(Quat::new(qw, qx, qy, qz), wk);
            }
        }
        write_array(out, acc.result()?.to_array())
    })())
}

/// Hamilton product `out = a b` (each 4 scalars, scalar first). `out` may alias `a` or `b`.
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars (or NULL: error).
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_mul(a: *const f64, b: *const f64, out: *mut f64) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    mul(a, b, out)
}

/// `out = q / |q|`; a zero quaternion gives `DK_ERR_ZERO_LENGTH`, never NaN.
///
/// # Safety
/// `q` points to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_normalize(q: *const f64, out: *mut f64) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, out) = unsafe { (In::new(q, 4), Out::new(out, 4)) };
    normalize(q, out)
}

/// `out = q⁻¹ = q* / |q|²`.
///
/// # Safety
/// `q` points to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_inverse(q: *const f64, out: *mut f64) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, out) = unsafe { (In::new(q, 4), Out::new(out, 4)) };
    inverse(q, out)
}

/// Rotation by `angle` radians about `axis` (3 scalars, normalised here).
///
/// # Safety
/// `axis` points to 3 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_from_axis_angle(
    axis: *const f64,
    angle: f64,
    out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (axis, out) = unsafe { (In::new(axis, 3), Out::new(out, 4)) };
    from_axis_angle(axis, angle, out)
}

/// Axis (3 scalars, unit) and angle in `[0, π]` of the rotation `q` (normalised here).
///
/// # Safety
/// `q` points to 4 readable scalars, `axis_out` to 3 and `angle_out` to 1 writable scalar.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_to_axis_angle(
    q: *const f64,
    axis_out: *mut f64,
    angle_out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, axis_out, angle_out) =
        unsafe { (In::new(q, 4), Out::new(axis_out, 3), Out::new(angle_out, 1)) };
    to_axis_angle(q, axis_out, angle_out)
}

/// Shortest rotation taking direction `from` to direction `to` (3 scalars each).
///
/// # Safety
/// `from`, `to` point to 3 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_rotation_arc(
    from: *const f64,
    to: *const f64,
    out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (from, to, out) = unsafe { (In::new(from, 3), In::new(to, 3), Out::new(out, 4)) };
    rotation_arc(from, to, out)
}

/// Rotates `points_len / 3` points `(x, y, z)` by `q` (normalised here) into `out`.
/// `out_len` must equal `points_len`, a multiple of 3.
///
/// # Safety
/// `q` points to 4 readable scalars; `points` to `points_len` readable scalars; `out`
/// to `out_len` writable scalars not overlapping `points`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_rotate_points(
    q: *const f64,
    points: *const f64,
    points_len: usize,
    out: *mut f64,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, points, out) = unsafe {
        (
            In::new(q, 4),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    rotate_points(q, points, points_len, out, out_len)
}

/// Spherical linear interpolation on the shorter arc (`t` = 0 gives `a`, 1 gives `b`).
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_slerp(
    a: *const f64,
    b: *const f64,
    t: f64,
    out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    interpolate(a, b, t, out, true)
}

/// Normalised linear interpolation on the shorter arc.
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_nlerp(
    a: *const f64,
    b: *const f64,
    t: f64,
    out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    interpolate(a, b, t, out, false)
}

/// Hemisphere-aligned weighted average of `quats_len / 4` quaternions (`q` and `−q` are
/// one rotation), renormalised. `weights` may be NULL with `weights_len` 0 (all 1);
/// otherwise `weights_len == quats_len / 4`.
///
/// # Safety
/// `quats` points to `quats_len` readable scalars, `weights` to `weights_len` (or is
/// NULL with 0), `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_average(
    quats: *const f64,
    quats_len: usize,
    weights: *const f64,
    weights_len: usize,
    out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (quats, weights, out) = unsafe {
        (
            In::new(quats, quats_len),
            In::new(weights, weights_len),
            Out::new(out, 4),
        )
    };
    average(quats, quats_len, weights, weights_len, out)
}

/// Single-precision twin of [`dk_quat_mul`].
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars (or NULL: error).
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_mul_f32(a: *const f32, b: *const f32, out: *mut f32) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    mul(a, b, out)
}

/// Single-precision twin of [`dk_quat_normalize`].
///
/// # Safety
/// `q` points to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_normalize_f32(q: *const f32, out: *mut f32) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, out) = unsafe { (In::new(q, 4), Out::new(out, 4)) };
    normalize(q, out)
}

/// Single-precision twin of [`dk_quat_inverse`].
///
/// # Safety
/// `q` points to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_inverse_f32(q: *const f32, out: *mut f32) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, out) = unsafe { (In::new(q, 4), Out::new(out, 4)) };
    inverse(q, out)
}

/// Single-precision twin of [`dk_quat_from_axis_angle`].
///
/// # Safety
/// `axis` points to 3 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_from_axis_angle_f32(
    axis: *const f32,
    angle: f32,
    out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (axis, out) = unsafe { (In::new(axis, 3), Out::new(out, 4)) };
    from_axis_angle(axis, angle, out)
}

/// Single-precision twin of [`dk_quat_to_axis_angle`].
///
/// # Safety
/// `q` points to 4 readable scalars, `axis_out` to 3 and `angle_out` to 1 writable scalar.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_to_axis_angle_f32(
    q: *const f32,
    axis_out: *mut f32,
    angle_out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, axis_out, angle_out) =
        unsafe { (In::new(q, 4), Out::new(axis_out, 3), Out::new(angle_out, 1)) };
    to_axis_angle(q, axis_out, angle_out)
}

/// Single-precision twin of [`dk_quat_rotation_arc`].
///
/// # Safety
/// `from`, `to` point to 3 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_rotation_arc_f32(
    from: *const f32,
    to: *const f32,
    out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (from, to, out) = unsafe { (In::new(from, 3), In::new(to, 3), Out::new(out, 4)) };
    rotation_arc(from, to, out)
}

/// Single-precision twin of [`dk_quat_rotate_points`].
///
/// # Safety
/// `q` points to 4 readable scalars; `points` to `points_len` readable scalars; `out`
/// to `out_len` writable scalars not overlapping `points`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_rotate_points_f32(
    q: *const f32,
    points: *const f32,
    points_len: usize,
    out: *mut f32,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, points, out) = unsafe {
        (
            In::new(q, 4),
            In::new(points, points_len),
            Out::new(out, out_len),
        )
    };
    rotate_points(q, points, points_len, out, out_len)
}

/// Single-precision twin of [`dk_quat_slerp`].
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_slerp_f32(
    a: *const f32,
    b: *const f32,
    t: f32,
    out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    interpolate(a, b, t, out, true)
}

/// Single-precision twin of [`dk_quat_nlerp`].
///
/// # Safety
/// `a`, `b` point to 4 readable scalars, `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_nlerp_f32(
    a: *const f32,
    b: *const f32,
    t: f32,
    out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (a, b, out) = unsafe { (In::new(a, 4), In::new(b, 4), Out::new(out, 4)) };
    interpolate(a, b, t, out, false)
}

/// Single-precision twin of [`dk_quat_average`].
///
/// # Safety
/// `quats` points to `quats_len` readable scalars, `weights` to `weights_len` (or is
/// NULL with 0), `out` to 4 writable scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_quat_average_f32(
    quats: *const f32,
    quats_len: usize,
    weights: *const f32,
    weights_len: usize,
    out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (quats, weights, out) = unsafe {
        (
            In::new(quats, quats_len),
            In::new(weights, weights_len),
            Out::new(out, 4),
        )
    };
    average(quats, quats_len, weights, weights_len, out)
}
