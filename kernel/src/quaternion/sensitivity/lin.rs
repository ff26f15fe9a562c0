//! The small linear maps of the quaternion method's stages. Each is written once and used
//! both ways, as `J v` (tangent) and `Jᵀ w` (adjoint), so the two modes are transposes of
//! each other to rounding by construction.

use crate::quat::Quat;
use crate::real::Real;
use crate::vector::{add, cross, dot, scale};

/// The 3×4 Jacobian of [`Quat::rotate`]`(q, v)` with respect to `q = (w, x, y, z)`, `v` held.
/// The cross-product form `v + w t + q_v × t`, `t = 2 q_v × v`, is differentiated as written;
/// for a unit `q` and a tangent `δq ⊥ q` it is the derivative of `q v q*`.
pub(crate) fn drot<T: Real>(q: Quat<T>, v: [T; 3]) -> [[T; 4]; 3] {
    let qv = q.vector();
    let t = scale(cross(qv, v), T::TWO);
    let mut m = [[T::ZERO; 4]; 3];
    for (c, e) in [
        [T::ONE, T::ZERO, T::ZERO],
        [T::ZERO, T::ONE, T::ZERO],
        [T::ZERO, T::ZERO, T::ONE],
    ]
    .into_iter()
    .enumerate()
    {
        // δq_v = e: δt = 2 e × v; δr = w δt + e × t + q_v × δt.
        let dt = scale(cross(e, v), T::TWO);
        let col = add(add(scale(dt, q.w), cross(e, t)), cross(qv, dt));
        for (row, x) in m.iter_mut().zip(col) {
            if let Some(slot) = row.get_mut(c + 1) {
                *slot = x;
            }
        }
    }
    for (row, x) in m.iter_mut().zip(t) {
        if let Some(slot) = row.first_mut() {
            *slot = x;
        }
    }
    m
}

/// `M x` for a 3×4 matrix.
#[inline]
pub(crate) fn mul34<T: Real>(m: &[[T; 4]; 3], x: [T; 4]) -> [T; 3] {
    let mut r = [T::ZERO; 3];
    for (ri, row) in r.iter_mut().zip(m) {
        *ri = dot(*row, x);
    }
    r
}

/// `Mᵀ y` for a 3×4 matrix.
#[inline]
pub(crate) fn mul34t<T: Real>(m: &[[T; 4]; 3], y: [T; 3]) -> [T; 4] {
    let mut r = [T::ZERO; 4];
    for (row, &yi) in m.iter().zip(&y) {
        for (rc, &mc) in r.iter_mut().zip(row) {
            *rc += mc * yi;
        }
    }
    r
}

/// The derivative of `S / |S|` at `S` (`q` its unit direction, `len = |S|`) applied to `x`:
/// `(x − q (q · x)) / len`. Symmetric, so it is its own adjoint.
#[inline]
pub(crate) fn proj4<T: Real>(q: Quat<T>, len: T, x: [T; 4]) -> [T; 4] {
    let qa = q.to_array();
    let c = dot(qa, x);
    let mut r = [T::ZERO; 4];
    for ((ri, &xi), &qi) in r.iter_mut().zip(&x).zip(&qa) {
        *ri = (xi - qi * c) / len;
    }
    r
}

/// The derivative of `a / |a|` (`n` the unit direction, `len = |a|`) applied to `x`;
/// symmetric.
#[inline]
pub(crate) fn proj3<T: Real>(n: [T; 3], len: T, x: [T; 3]) -> [T; 3] {
    let c = dot(n, x);
    let mut r = [T::ZERO; 3];
    for ((ri, &xi), &ni) in r.iter_mut().zip(&x).zip(&n) {
        *ri = (xi - ni * c) / len;
    }
    r
}

/// Adds `s x` to `acc`.
#[inline]
pub(crate) fn axpy<T: Real, const N: usize>(acc: &mut [T; N], s: T, x: [T; N]) {
    for (a, &b) in acc.iter_mut().zip(&x) {
        *a += s * b;
    }
}
