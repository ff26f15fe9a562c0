//! SU2's `FFD_TWIST` design variable (`CSurfaceMovement::SetFFDTwist`).
//!
//! `DV_PARAM = (box, j, x0, y0, z0, x1, y1, z1)`, amplitude `a = DV_VALUE × OPT_RELAX_FACTOR`:
//! the control points of layer `j` turn by `θ = atan(a / REF_LENGTH)` about the axis parallel
//! to y through the point where the segment `(x0, y0, z0)–(x1, y1, z1)` crosses the plane
//! `y = y(0, j, 0)` (the current y of control point `(0, j, 0)`). Control points on a fixed
//! i or k plane (SU2's `FFD_FIX_I`/`FFD_FIX_K`, or the planes SU2 fixes where the surface cuts
//! the box) stay. The movement adds to what earlier design variables did.
//!
//! The crossing is SU2's `CGeometry::SegmentIntersectsPlane`, which adds `1e-6` to the plane
//! point and to every component of the plane normal before it solves; the rotation is SU2's
//! closed form for a turn about an arbitrary axis, in SU2's order of operations.

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::ffd::{check_box, flat};

/// One `FFD_TWIST` design variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FfdTwist<T> {
    /// `DV_PARAM[1]`: the layer (j index) that turns.
    pub j: usize,
    /// `DV_PARAM[2..8]`: the segment whose crossing with the layer's plane is the pivot.
    pub segment: [[T; 3]; 2],
    /// `DV_VALUE × OPT_RELAX_FACTOR`.
    pub amplitude: T,
    /// SU2's `REF_LENGTH` (1 by default): `θ = atan(amplitude / ref_length)`.
    pub ref_length: T,
}

/// SU2's `SegmentIntersectsPlane` for the normal `(0, 1, 0)` through `plane_p0`: the crossing
/// point, or `None` where SU2 finds none.
fn crossing<T: Real>(s: [[T; 3]; 2], plane_p0: [T; 3]) -> Option<[T; 3]> {
    let eps = T::from_f64(1e-6);
    let n = [T::ZERO + eps, T::ONE + eps, T::ZERO + eps];
    let dot = |a: [T; 3]| n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
    let [s0, s1] = s;
    let u = zip_with(s1, s0, |a, b| a - b);
    let v = zip_with(plane_p0, s0, |p, b| (p + eps) - b);
    let (num, den) = (dot(v), dot(u));
    if den.abs() <= T::ZERO {
        return None;
    }
    let aux = num / den;
    if aux < T::ZERO || aux > T::ONE {
        return None;
    }
    let x = zip_with(s0, u, |a, d| a + aux * d);
    let a = zip_with(s0, x, |p, q| p - q);
    let b = zip_with(s1, x, |p, q| p - q);
    if dot(b) * dot(a) > T::ZERO {
        return None;
    }
    Some(x)
}

/// `f` applied component by component (no indexing: no panic path).
fn zip_with<T: Real>(a: [T; 3], b: [T; 3], f: impl Fn(T, T) -> T) -> [T; 3] {
    let [a0, a1, a2] = a;
    let [b0, b1, b2] = b;
    [f(a0, b0), f(a1, b1), f(a2, b2)]
}

/// SU2's closed form for turning point `p` about the line through `c` with direction `axis`
/// by the angle whose cosine and sine are given, as a movement (new position minus `p`), in
/// SU2's order of operations (`SetRotation`, `SetFFDTwist`, `SetFFDRotation`).
pub fn su2_rotation_movement<T: Real>(
    p: [T; 3],
    c: [T; 3],
    axis: [T; 3],
    (cos_t, sin_t): (T, T),
) -> [T; 3] {
    let ([x, y, z], [a, b, cc], [u, v, w]) = (p, c, axis);
    let (u2, v2, w2) = (u * u, v * v, w * w);
    let l2 = u2 + v2 + w2;
    let l = l2.sqrt();
    let m0 = a * (v2 + w2)
        + u * (-b * v - cc * w + u * x + v * y + w * z)
        + (-a * (v2 + w2) + u * (b * v + cc * w - v * y - w * z) + (v2 + w2) * x) * cos_t
        + l * (-cc * v + b * w - w * y + v * z) * sin_t;
    let m1 = b * (u2 + w2)
        + v * (-a * u - cc * w + u * x + v * y + w * z)
        + (-b * (u2 + w2) + v * (a * u + cc * w - u * x - w * z) + (u2 + w2) * y) * cos_t
        + l * (cc * u - a * w + w * x - u * z) * sin_t;
    let m2 = cc * (u2 + v2)
        + w * (-a * u - b * v + u * x + v * y + w * z)
        + (-cc * (u2 + v2) + w * (a * u + b * v - u * x - v * y) + (u2 + v2) * z) * cos_t
        + l * (-b * u + a * v - v * x + u * y) * sin_t;
    [m0 / l2 - x, m1 / l2 - y, m2 / l2 - z]
}

/// `FFD_TWIST` on the control points of an always-3D SU2 box (`degree = [l, m, n]`, the flat
/// order of [`FfdBox::index`](super::ffd::FfdBox::index)): layer `twist.j` turns, except the
/// points whose i is in `fixed_i` or whose k is in `fixed_k`.
///
/// # Errors
/// [`Error::InvalidParameter`] for bad degrees, a non-positive `ref_length`, or a segment that
/// does not cross the layer's plane ("segment": SU2 then moves nothing, silently);
/// [`Error::LengthMismatch`] when `control_points` does not fit the degrees;
/// [`Error::IndexOutOfRange`] for `j` above its degree; [`Error::NonFinite`] for a non-finite
/// input; [`Error::Overflow`] when a moved point is not finite. Nothing is written on error.
pub fn ffd_twist<T: Real>(
    degree: [usize; 3],
    control_points: &mut [[T; 3]],
    twist: FfdTwist<T>,
    fixed_i: &[u32],
    fixed_k: &[u32],
) -> Result<()> {
    let pivot = pivot(degree, control_points, twist)?;
    let theta = (twist.amplitude / twist.ref_length).atan();
    let cs = (theta.cos(), theta.sin());
    let moved = |i: usize, k: usize, p: [T; 3]| -> [T; 3] {
        if fixed_i.contains(&(i as u32)) || fixed_k.contains(&(k as u32)) {
            return p;
        }
        let axis = [T::ZERO, T::ONE, T::ZERO];
        zip_with(p, su2_rotation_movement(p, pivot, axis, cs), |a, m| a + m)
    };
    let layer = |i: usize, k: usize| flat(degree, [i, twist.j, k]);
    let mut ok = true;
    for i in 0..=degree[0] {
        for k in 0..=degree[2] {
            if let Some(&p) = control_points.get(layer(i, k)) {
                ok &= moved(i, k, p).iter().all(|c| c.is_finite());
            }
        }
    }
    if !ok {
        return Err(Error::Overflow { arg: "amplitude" });
    }
    for i in 0..=degree[0] {
        for k in 0..=degree[2] {
            if let Some(p) = control_points.get_mut(layer(i, k)) {
                *p = moved(i, k, *p);
            }
        }
    }
    Ok(())
}

/// The checks of [`ffd_twist`] and the pivot of the turn.
fn pivot<T: Real>(
    degree: [usize; 3],
    control_points: &[[T; 3]],
    twist: FfdTwist<T>,
) -> Result<[T; 3]> {
    check_box(degree, control_points)?;
    check::finite_items("control_points", control_points)?;
    check::finite_items("segment", &twist.segment)?;
    check::scalar("amplitude", twist.amplitude)?;
    check::scalar("ref_length", twist.ref_length)?;
    if twist.j > degree[1] {
        return Err(Error::IndexOutOfRange {
            arg: "j",
            position: 0,
            index: twist.j,
            bound: degree[1] + 1,
        });
    }
    if twist.ref_length <= T::ZERO {
        return Err(Error::InvalidParameter {
            arg: "ref_length",
            reason: "must be positive",
        });
    }
    let origin = control_points
        .get(flat(degree, [0, twist.j, 0]))
        .copied()
        .unwrap_or([T::ZERO; 3]);
    crossing(twist.segment, origin).ok_or(Error::InvalidParameter {
        arg: "segment",
        reason: "does not cross the plane of layer j (SU2 moves nothing then)",
    })
}

/// The derivative of [`ffd_twist`]'s control points with respect to `twist.amplitude` at
/// amplitude 0 (SU2_DOT's linearisation point; `twist.amplitude` itself is not read): the
/// turned points of layer `twist.j` (except the fixed planes) move by `ω × (p − pivot)` with
/// `ω = (0, 1/ref_length, 0)` (`dθ/da = 1/ref_length` at 0), everything else by 0. Overwrites
/// `out` (one item per control point).
///
/// # Errors
/// As [`ffd_twist`]; [`Error::LengthMismatch`] when `out` does not hold one item per control
/// point. Nothing is written on error.
pub fn ffd_twist_tangent<T: Real>(
    degree: [usize; 3],
    control_points: &[[T; 3]],
    twist: FfdTwist<T>,
    fixed_i: &[u32],
    fixed_k: &[u32],
    out: &mut [[T; 3]],
) -> Result<()> {
    let twist = FfdTwist {
        amplitude: T::ZERO,
        ..twist
    };
    let c = pivot(degree, control_points, twist)?;
    check::len("out", out.len(), control_points.len())?;
    out.iter_mut().for_each(|o| *o = [T::ZERO; 3]);
    let rate = T::ONE / twist.ref_length;
    for i in (0..=degree[0]).filter(|&i| !fixed_i.contains(&(i as u32))) {
        for k in (0..=degree[2]).filter(|&k| !fixed_k.contains(&(k as u32))) {
            let at = flat(degree, [i, twist.j, k]);
            if let (Some(&[x, _, z]), Some(o)) = (control_points.get(at), out.get_mut(at)) {
                *o = [rate * (z - c[2]), T::ZERO, rate * (c[0] - x)];
            }
        }
    }
    Ok(())
}
