//! The inverse-distance field stage linearised. The weights belong to the undeformed mesh and
//! do not move; `Δ` is averaged linearly, `Q` as the hemisphere-aligned sum `S = Σ ±w_k Q_k`
//! normalised (`δQ = (I − Q Qᵀ) δS / |S|`), and the update `R = o + Δ + Q (r − o) Q*` adds
//! `∂(Q (r − o) Q*)/∂Q δQ`.

use super::boundary::{add_to, get3};
use super::lin::{axpy, drot, mul34, mul34t, proj4};
use crate::quat::Quat;
use crate::quaternion::propagate::{idw_scan, idw_weight, IdwScan};
use crate::quaternion::{drop3, lift, load, store};
use crate::real::Real;
use crate::vector::{add, scale, sub};

/// The fixed quantities of one field point: boundary rotations and where they are.
pub(super) struct Field<'a, T, const D: usize> {
    pub(super) points: &'a [[T; D]],
    pub(super) boundary: &'a [u32],
    pub(super) exponent: T,
    pub(super) origin: [T; D],
    /// Base boundary rotations `Q_k` (4 per boundary point, as propagated).
    pub(super) qs: &'a [T],
}

impl<T: Real, const D: usize> Field<'_, T, D> {
    /// Boundary point `k`'s mesh position.
    #[inline]
    fn at(&self, b: u32) -> [T; D] {
        self.points.get(b as usize).copied().unwrap_or([T::ZERO; D])
    }

    /// The signed weight `±w_k` of boundary point `k` (sign of `Q_nearest · Q_k`, as
    /// [`QuatAverage`](crate::QuatAverage) flips) and `Q_k`.
    #[inline]
    fn weight(&self, scan: &IdwScan<T>, qn: Quat<T>, x: [T; D], k: usize, b: u32) -> (T, [T; 4]) {
        let w = idw_weight(scan, self.exponent, x, self.at(b));
        let q: [T; 4] = load(self.qs, k);
        (
            if qn.dot(Quat::from_array(q)) < T::ZERO {
                -w
            } else {
                w
            },
            q,
        )
    }

    /// The unit propagated rotation from `S` and `|S|` (the nearest rotation when `S` cannot
    /// be normalised, where the forward falls back to it; then `|S| = 1`).
    #[inline]
    fn unit(s: [T; 4], qn: Quat<T>) -> (Quat<T>, T) {
        let s = Quat::from_array(s);
        match s.normalize() {
            Ok(q) => (q, s.norm()),
            Err(_) => (qn.normalize().unwrap_or(Quat::identity()), T::ONE),
        }
    }
}

/// Tangent: `out[i] = δR_i` (every field node from `δQ` in `dq` and `δΔ` in `dt`, 4 and 3
/// per boundary point; boundary nodes take `δd`).
pub(super) fn idw_tangent<T: Real, const D: usize>(
    f: &Field<'_, T, D>,
    dq: &[T],
    dt: &[T],
    dd: &[[T; D]],
    out: &mut [[T; D]],
) {
    for (i, (x, o)) in f.points.iter().zip(out.iter_mut()).enumerate() {
        if let Some(v) = tangent_at(f, dq, dt, i, *x) {
            *o = v;
        }
    }
    for (k, &b) in f.boundary.iter().enumerate() {
        if let Some(o) = out.get_mut(b as usize) {
            *o = dd.get(k).copied().unwrap_or([T::ZERO; D]);
        }
    }
}

/// Tangent at field point `x` (mesh node `i`; `None` for a boundary node).
pub(super) fn tangent_at<T: Real, const D: usize>(
    f: &Field<'_, T, D>,
    dq: &[T],
    dt: &[T],
    i: usize,
    x: [T; D],
) -> Option<[T; D]> {
    let scan = idw_scan(f.points, f.boundary, i, x)?;
    let qn = Quat::from_array(load(f.qs, scan.nearest_pos));
    let (mut s, mut ds, mut dtv) = ([T::ZERO; 4], [T::ZERO; 4], [T::ZERO; 3]);
    if scan.dmin > T::ZERO {
        let mut wsum = T::ZERO;
        for (k, &b) in f.boundary.iter().enumerate() {
            let (sw, q) = f.weight(&scan, qn, x, k, b);
            axpy(&mut s, sw, q);
            axpy(&mut ds, sw, load(dq, k));
            axpy(&mut dtv, sw.abs(), load(dt, k));
            wsum += sw.abs();
        }
        dtv = scale(dtv, T::ONE / wsum);
    } else {
        s = qn.to_array();
        ds = load(dq, scan.nearest_pos);
        dtv = load(dt, scan.nearest_pos);
    }
    Some(f.update_tangent(x, s, qn, ds, dtv))
}

impl<T: Real, const D: usize> Field<'_, T, D> {
    /// `δR = δΔ + M(Q, x − o) (I − Q Qᵀ) δS / |S|` from the rotation sum `S` (`qn` the
    /// fallback when it cannot be normalised), `δS` and `δΔ`.
    pub(super) fn update_tangent(
        &self,
        x: [T; D],
        s: [T; 4],
        qn: Quat<T>,
        ds: [T; 4],
        dtv: [T; 3],
    ) -> [T; D] {
        let (q, len) = Field::<T, D>::unit(s, qn);
        let m = drot(q, lift(sub(x, self.origin)));
        drop3(add(dtv, mul34(&m, proj4(q, len, ds))))
    }

    /// The transpose of [`Field::update_tangent`] for `w = R̄`: `S̄ = (I − Q Qᵀ) M(Q, x −
    /// o)ᵀ w / |S|` (and `Δ̄ = w`).
    pub(super) fn update_adjoint(&self, x: [T; D], s: [T; 4], qn: Quat<T>, g: [T; 3]) -> [T; 4] {
        let (q, len) = Field::<T, D>::unit(s, qn);
        let m = drot(q, lift(sub(x, self.origin)));
        proj4(q, len, mul34t(&m, g))
    }
}

/// Adjoint: from `w = dJ/dR` adds `Q̄` to `dq`, `Δ̄` to `dt` (field nodes) and `w` at the
/// boundary nodes to `out` (`d̄`, one per boundary point). `wk` needs `B` scalars.
pub(super) fn idw_adjoint<T: Real, const D: usize>(
    f: &Field<'_, T, D>,
    weights: &[[T; D]],
    wk: &mut [T],
    dq: &mut [T],
    dt: &mut [T],
    out: &mut [[T; D]],
) {
    for (i, (x, g)) in f.points.iter().zip(weights).enumerate() {
        adjoint_at(f, i, *x, lift(*g), wk, dq, dt);
    }
    for (k, &b) in f.boundary.iter().enumerate() {
        add_to(out, k, get3(weights, b as usize));
    }
}

/// Adjoint at field point `x` (mesh node `i`, nothing for a boundary node) for `g = R̄_i`:
/// adds to `Q̄` in `dq` and `Δ̄` in `dt`. `wk` needs `B` scalars.
pub(super) fn adjoint_at<T: Real, const D: usize>(
    f: &Field<'_, T, D>,
    i: usize,
    x: [T; D],
    gb: [T; 3],
    wk: &mut [T],
    dq: &mut [T],
    dt: &mut [T],
) {
    let Some(scan) = idw_scan(f.points, f.boundary, i, x) else {
        return;
    };
    let qn = Quat::from_array(load(f.qs, scan.nearest_pos));
    if scan.dmin > T::ZERO {
        let (mut s, mut wsum) = ([T::ZERO; 4], T::ZERO);
        for ((k, &b), slot) in f.boundary.iter().enumerate().zip(wk.iter_mut()) {
            let (sw, q) = f.weight(&scan, qn, x, k, b);
            *slot = sw;
            axpy(&mut s, sw, q);
            wsum += sw.abs();
        }
        let qb = f.update_adjoint(x, s, qn, gb);
        for (k, &sw) in wk.iter().enumerate().take(f.boundary.len()) {
            accumulate(dq, k, sw, qb);
            accumulate(dt, k, sw.abs() / wsum, gb);
        }
    } else {
        let qb = f.update_adjoint(x, qn.to_array(), qn, gb);
        accumulate(dq, scan.nearest_pos, T::ONE, qb);
        accumulate(dt, scan.nearest_pos, T::ONE, gb);
    }
}

/// `s[k] += a x` on a flat slice of `N`-vectors.
#[inline]
pub(super) fn accumulate<T: Real, const N: usize>(s: &mut [T], k: usize, a: T, x: [T; N]) {
    let mut v: [T; N] = load(s, k);
    axpy(&mut v, a, x);
    store(s, k, v);
}
