//! Small helpers for points stored as `[T; 2]` and `[T; 3]`.
//!
//! Deliberately minimal: the kernel needs dot and cross products, norms and a few
//! element-wise operations, not a linear-algebra library. All operations are written out so
//! the order of floating-point operations (and hence the bits) is fixed.

use crate::real::Real;

/// `a + b`.
#[inline]
pub fn add<T: Real, const D: usize>(a: [T; D], b: [T; D]) -> [T; D] {
    let mut r = a;
    for (x, y) in r.iter_mut().zip(b) {
        *x += y;
    }
    r
}

/// `a − b`.
#[inline]
pub fn sub<T: Real, const D: usize>(a: [T; D], b: [T; D]) -> [T; D] {
    let mut r = a;
    for (x, y) in r.iter_mut().zip(b) {
        *x -= y;
    }
    r
}

/// `s · a`.
#[inline]
pub fn scale<T: Real, const D: usize>(a: [T; D], s: T) -> [T; D] {
    let mut r = a;
    for x in r.iter_mut() {
        *x *= s;
    }
    r
}

/// `a · b`, summed in index order.
#[inline]
pub fn dot<T: Real, const D: usize>(a: [T; D], b: [T; D]) -> T {
    let mut s = T::ZERO;
    for (x, y) in a.iter().zip(b.iter()) {
        s += *x * *y;
    }
    s
}

/// `|a|²`.
#[inline]
pub fn norm_sq<T: Real, const D: usize>(a: [T; D]) -> T {
    dot(a, a)
}

/// `|a|` (libm square root of the dot product).
#[inline]
pub fn norm<T: Real, const D: usize>(a: [T; D]) -> T {
    norm_sq(a).sqrt()
}

/// `|a|` without overflow or underflow of `|a|²`: bit-identical to [`norm`] whenever `|a|²`
/// is a finite normal number (or `a` has a non-finite component); otherwise computed as
/// `m·|a/m|` with `m` the largest `|a_k|`.
#[inline]
pub fn norm_robust<T: Real, const D: usize>(a: [T; D]) -> T {
    let n2 = norm_sq(a);
    if (n2.is_finite() && n2 >= T::MIN_POSITIVE) || !a.iter().all(|x| x.is_finite()) {
        return n2.sqrt();
    }
    let m = a.iter().fold(T::ZERO, |m, x| m.max(x.abs()));
    if m == T::ZERO {
        return T::ZERO;
    }
    m * norm(a.map(|x| x / m))
}

/// `|a − b|`, computed as [`norm_robust`]: bit-identical to `norm(sub(a, b))` in the normal
/// range, and exact to rounding when `|a − b|²` would overflow (points beyond about 1e154 in
/// `f64`, 1.8e19 in `f32`) or underflow (points closer than about 1e-154 / 1e-19). `+∞` only
/// when `a − b` itself overflows.
#[inline]
pub fn distance<T: Real, const D: usize>(a: [T; D], b: [T; D]) -> T {
    norm_robust(sub(a, b))
}

/// `a / |a|`, or `None` when every component is zero or subnormal, or any is not finite.
/// When `|a|²` would overflow or underflow, `a` is first divided by its largest component,
/// so every finite vector with a normal component normalises to full accuracy.
#[inline]
pub fn normalize<T: Real, const D: usize>(a: [T; D]) -> Option<[T; D]> {
    let n2 = norm_sq(a);
    if n2.is_finite() && n2 >= T::MIN_POSITIVE {
        return Some(scale(a, T::ONE / n2.sqrt()));
    }
    if !a.iter().all(|x| x.is_finite()) {
        return None;
    }
    // |a|² overflowed or underflowed: rescale by the largest component (norm in [1, √D]).
    let m = a.iter().fold(T::ZERO, |m, x| m.max(x.abs()));
    if m < T::MIN_POSITIVE {
        return None;
    }
    let mut r = a;
    for x in r.iter_mut() {
        *x /= m;
    }
    Some(scale(r, T::ONE / norm(r)))
}

/// The 3D cross product `a × b`.
#[inline]
pub fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The 2D cross product (z component of `a × b`), `a.x b.y − a.y b.x`.
#[inline]
pub fn cross2<T: Real>(a: [T; 2], b: [T; 2]) -> T {
    a[0] * b[1] - a[1] * b[0]
}

/// Linear interpolation `a + t (b − a)`.
#[inline]
pub fn lerp<T: Real, const D: usize>(a: [T; D], b: [T; D], t: T) -> [T; D] {
    add(a, scale(sub(b, a), t))
}

/// Lifts a 2D point into 3D with `z = 0`.
#[inline]
pub fn to_3d<T: Real>(a: [T; 2]) -> [T; 3] {
    [a[0], a[1], T::ZERO]
}

/// Any unit vector orthogonal to the unit vector `a` (used for antiparallel rotation arcs).
#[inline]
pub fn any_orthogonal<T: Real>(a: [T; 3]) -> [T; 3] {
    // Cross with the coordinate axis least aligned with `a`: never degenerate for unit `a`.
    let ax = a[0].abs();
    let ay = a[1].abs();
    let az = a[2].abs();
    let axis = if ax <= ay && ax <= az {
        [T::ONE, T::ZERO, T::ZERO]
    } else if ay <= az {
        [T::ZERO, T::ONE, T::ZERO]
    } else {
        [T::ZERO, T::ZERO, T::ONE]
    };
    let c = cross(a, axis);
    let n = norm(c);
    if n > T::ZERO {
        scale(c, T::ONE / n)
    } else {
        axis
    }
}
