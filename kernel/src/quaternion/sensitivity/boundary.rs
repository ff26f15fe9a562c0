//! The boundary stage linearised: rotations from the shape (2D edge angles; 3D normals, `Q1`,
//! twist, `Q = Q2 Q1`) and the translations `Δ_k`, tangent and adjoint.

use super::lin::{axpy, drot, mul34, mul34t, proj3, proj4};
use crate::cells::{CellKind, Cells};
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::quaternion::normals::{element_normal, unit_normals};
use crate::quaternion::{lift, load, store, take, Pts};
use crate::real::Real;
use crate::vector::{add, cross, dot, norm, norm_sq, scale, sub};

/// `v[k]` lifted to 3D (zero when out of range).
#[inline]
pub(super) fn get3<T: Real, const D: usize>(v: &[[T; D]], k: usize) -> [T; 3] {
    lift(v.get(k).copied().unwrap_or([T::ZERO; D]))
}

/// Adds the first `D` components of `x` to `v[k]` (ignored when out of range).
#[inline]
pub(super) fn add_to<T: Real, const D: usize>(v: &mut [[T; D]], k: usize, x: [T; 3]) {
    if let Some(a) = v.get_mut(k) {
        for (c, &y) in a.iter_mut().zip(&x) {
            *c += y;
        }
    }
}

/// Sets every entry of `s` to zero.
#[inline]
pub(super) fn zero<T: Real>(s: &mut [T]) {
    for x in s.iter_mut() {
        *x = T::ZERO;
    }
}

/// `δΔ_k = δd_k − ∂(Q̂_k (u_k − o) Q̂_k*)/∂Q δQ_k` into `dt` (3 per point), `Q̂_k` the
/// normalised base rotation.
pub(super) fn translations_tangent<T: Real, const D: usize>(
    u: Pts<'_, T, D>,
    origin: [T; D],
    qs: &[T],
    dq: &[T],
    dd: &[[T; D]],
    dt: &mut [T],
) {
    for k in 0..dd.len() {
        let m = drot(unit(qs, k), lift(sub(u.get(k), origin)));
        store(dt, k, sub(get3(dd, k), mul34(&m, load(dq, k))));
    }
}

/// The transpose of [`translations_tangent`]: `d̄_k += Δ̄_k`, `Q̄_k −= Mᵀ Δ̄_k`.
pub(super) fn translations_adjoint<T: Real, const D: usize>(
    u: Pts<'_, T, D>,
    origin: [T; D],
    qs: &[T],
    dt: &[T],
    dq: &mut [T],
    out: &mut [[T; D]],
) {
    for k in 0..out.len() {
        let m = drot(unit(qs, k), lift(sub(u.get(k), origin)));
        let tb: [T; 3] = load(dt, k);
        add_to(out, k, tb);
        let mut qb: [T; 4] = load(dq, k);
        axpy(&mut qb, -T::ONE, mul34t(&m, tb));
        store(dq, k, qb);
    }
}

/// Base rotation `k`, normalised as the translations and the update use it.
#[inline]
pub(super) fn unit<T: Real>(qs: &[T], k: usize) -> Quat<T> {
    Quat::from_array(load(qs, k))
        .normalize()
        .unwrap_or(Quat::identity())
}

/// The two end points of a 2D boundary segment and its deformed direction `t_d`.
#[inline]
fn segment<T: Real, const D: usize>(
    d: Pts<'_, T, D>,
    nodes: &[u32],
) -> Option<(usize, usize, [T; 3])> {
    let (a, c) = (*nodes.first()? as usize, *nodes.get(1)? as usize);
    Some((a, c, sub(d.get3(c), d.get3(a))))
}

/// Counts the segments at every node into `cnt`.
fn count_segments<T: Real, const D: usize>(d: Pts<'_, T, D>, elements: &Cells<'_>, cnt: &mut [T]) {
    zero(cnt);
    for (_, nodes) in elements.iter() {
        if let Some((a, c, _)) = segment(d, nodes) {
            for v in [a, c] {
                if let Some(x) = cnt.get_mut(v) {
                    *x += T::ONE;
                }
            }
        }
    }
}

/// 2D tangent: each segment turns by `δα = (t_d × δt_d)_z / |t_d|²`, a node by the mean
/// `δθ` of its segments, and `δQ = ½ δθ [−Q_z, 0, 0, Q_w]` (`Q = [cos θ/2, 0, 0, sin θ/2]`).
/// `work` needs `2 B` entries.
pub(super) fn rotations2_tangent<T: Real, const D: usize>(
    d: Pts<'_, T, D>,
    elements: &Cells<'_>,
    dd: &[[T; D]],
    qs: &[T],
    work: &mut [T],
    dq: &mut [T],
) {
    let b = dd.len();
    let (cnt, rest) = take(work, b);
    let (th, _) = take(rest, b);
    count_segments(d, elements, cnt);
    zero(th);
    for (_, nodes) in elements.iter() {
        if let Some((a, c, td)) = segment(d, nodes) {
            let dtd = sub(get3(dd, c), get3(dd, a));
            let da = (td[0] * dtd[1] - td[1] * dtd[0]) / norm_sq(td);
            for v in [a, c] {
                if let Some(x) = th.get_mut(v) {
                    *x += da;
                }
            }
        }
    }
    for (k, (&t, &n)) in th.iter().zip(cnt.iter()).enumerate() {
        let q: [T; 4] = load(qs, k);
        let h = t / n * T::HALF;
        store(dq, k, [-q[3] * h, T::ZERO, T::ZERO, q[0] * h]);
    }
}

/// The transpose of [`rotations2_tangent`]: from `Q̄` in `dq`, adds `d̄` to `out`.
pub(super) fn rotations2_adjoint<T: Real, const D: usize>(
    d: Pts<'_, T, D>,
    elements: &Cells<'_>,
    qs: &[T],
    dq: &[T],
    work: &mut [T],
    out: &mut [[T; D]],
) {
    let b = out.len();
    let (cnt, rest) = take(work, b);
    let (th, _) = take(rest, b);
    count_segments(d, elements, cnt);
    for (k, (t, &n)) in th.iter_mut().zip(cnt.iter()).enumerate() {
        let q: [T; 4] = load(qs, k);
        let qb: [T; 4] = load(dq, k);
        *t = (qb[3] * q[0] - qb[0] * q[3]) * T::HALF / n;
    }
    for (_, nodes) in elements.iter() {
        if let Some((a, c, td)) = segment(d, nodes) {
            let ab = th.get(a).copied().unwrap_or(T::ZERO) + th.get(c).copied().unwrap_or(T::ZERO);
            let g = scale([-td[1], td[0], T::ZERO], ab / norm_sq(td));
            add_to(out, c, g);
            add_to(out, a, scale(g, -T::ONE));
        }
    }
}

/// The 3D workspace (`21 B` scalars): deformed unit normals `nd`, their raw lengths `alen`,
/// undeformed unit normals `nu`, `δn` / `n̄` (`dn`), `Q1` (`q1`), `δQ1` / `Q̄1` (`dq1`), the
/// twist sums `(S, C)` (`sc`) and `δθ` / `θ̄` (`th`).
struct Work3<'a, T> {
    nd: &'a mut [T],
    alen: &'a mut [T],
    nu: &'a mut [T],
    dn: &'a mut [T],
    q1: &'a mut [T],
    dq1: &'a mut [T],
    sc: &'a mut [T],
    th: &'a mut [T],
}

/// Scalars of the 3D workspace per boundary point.
pub(super) const WORK3: usize = 21;

/// Splits `work` into the [`Work3`] arrays for `b` points.
fn work3<T>(work: &mut [T], b: usize) -> Work3<'_, T> {
    let (nd, rest) = take(work, 3 * b);
    let (alen, rest) = take(rest, b);
    let (nu, rest) = take(rest, 3 * b);
    let (dn, rest) = take(rest, 3 * b);
    let (q1, rest) = take(rest, 4 * b);
    let (dq1, rest) = take(rest, 4 * b);
    let (sc, rest) = take(rest, 2 * b);
    let (th, _) = take(rest, b);
    Work3 {
        nd,
        alen,
        nu,
        dn,
        q1,
        dq1,
        sc,
        th,
    }
}

/// Calls `f(i, j)` for every twist term of the 3D rotations: each element edge, both ways.
fn for_each_term(elements: &Cells<'_>, mut f: impl FnMut(usize, usize)) {
    for (kind, nodes) in elements.iter() {
        for &[la, lb] in kind.edges() {
            let (Some(&a), Some(&c)) = (nodes.get(la as usize), nodes.get(lb as usize)) else {
                continue;
            };
            for (i, j) in [(a, c), (c, a)] {
                f(i as usize, j as usize);
            }
        }
    }
}

/// One twist term at node `i` towards `j`: the rotated undeformed edge `e_u = Q1 (u_j − u_i)`,
/// the deformed edge `e_d`, the deformed normal `n` and `∂e_u/∂Q1`.
struct Term<T> {
    eu: [T; 3],
    ed: [T; 3],
    n: [T; 3],
    m: [[T; 4]; 3],
}

impl<T: Real> Term<T> {
    fn new<const D: usize>(
        u: Pts<'_, T, D>,
        d: Pts<'_, T, D>,
        nd: &[T],
        q1: &[T],
        i: usize,
        j: usize,
    ) -> Self {
        let q = Quat::from_array(load(q1, i));
        let v = sub(u.get3(j), u.get3(i));
        Term {
            eu: q.rotate(v),
            ed: sub(d.get3(j), d.get3(i)),
            n: load(nd, i),
            m: drot(q, v),
        }
    }

    /// `(s, c) = ((p_u × p_d) · n, p_u · p_d)`, evaluated as the rotations do.
    fn sc(&self) -> [T; 2] {
        let (eu, ed, n) = (self.eu, self.ed, self.n);
        let pu = sub(eu, scale(n, dot(eu, n)));
        let pd = sub(ed, scale(n, dot(ed, n)));
        [dot(cross(pu, pd), n), dot(pu, pd)]
    }

    /// The gradient of this term's share of `θ = atan2(S, C)` (sums `S`, `C` at `i`) with
    /// respect to `Q1_i`, `n_i` and `e_d`, using `s = (e_u × e_d) · n` and
    /// `c = e_u · e_d − (e_u · n)(e_d · n)` (equal for a unit `n`, and `δn ⊥ n`).
    fn grad(&self, sum: [T; 2]) -> ([T; 4], [T; 3], [T; 3]) {
        let [s, c] = sum;
        let h = s * s + c * c;
        let (eu, ed, n) = (self.eu, self.ed, self.n);
        let (un, dn) = (dot(eu, n), dot(ed, n));
        let pu = sub(eu, scale(n, un));
        let pd = sub(ed, scale(n, dn));
        let mix = |gs: [T; 3], gc: [T; 3]| scale(sub(scale(gs, c), scale(gc, s)), T::ONE / h);
        let g_eu = mix(cross(ed, n), pd);
        let g_n = mix(
            cross(eu, ed),
            scale(add(scale(ed, un), scale(eu, dn)), -T::ONE),
        );
        let g_ed = mix(cross(n, eu), pu);
        (mul34t(&self.m, g_eu), g_n, g_ed)
    }
}

/// The base state of the 3D rotations: normals, `Q1`, twist sums.
///
/// # Errors
/// [`Error::ZeroLength`] (`"normals"`) where element normals cancel, (`"normal_sum"`) where
/// the undeformed and deformed normals are antiparallel (`Q1` has no derivative there).
fn prep3<T: Real, const D: usize>(
    u: Pts<'_, T, D>,
    d: Pts<'_, T, D>,
    elements: &Cells<'_>,
    w: &mut Work3<'_, T>,
) -> Result<()> {
    unit_normals(u, elements, w.nu)?;
    zero(w.nd);
    for (kind, nodes) in elements.iter() {
        let n = element_normal(d, kind, nodes);
        for &v in nodes {
            let a: [T; 3] = load(w.nd, v as usize);
            store(w.nd, v as usize, add(a, n));
        }
    }
    for (i, l) in w.alen.iter_mut().enumerate() {
        let a: [T; 3] = load(w.nd, i);
        *l = norm(a);
        if !(l.is_finite() && *l >= T::MIN_POSITIVE) {
            return Err(Error::ZeroLength {
                arg: "normals",
                position: i,
            });
        }
        let n = scale(a, T::ONE / *l);
        store(w.nd, i, n);
        let nu: [T; 3] = load(w.nu, i);
        let sum = norm(add(nu, n));
        if !(sum.is_finite() && sum >= T::EPSILON) {
            return Err(Error::ZeroLength {
                arg: "normal_sum",
                position: i,
            });
        }
        store(w.q1, i, Quat::rotation_arc(nu, n)?.to_array());
    }
    zero(w.sc);
    let (nd, q1, sc) = (&*w.nd, &*w.q1, &mut *w.sc);
    for_each_term(elements, |i, j| {
        let t = Term::new(u, d, nd, q1, i, j);
        let mut acc: [T; 2] = load(sc, i);
        axpy(&mut acc, T::ONE, t.sc());
        store(sc, i, acc);
    });
    Ok(())
}

/// `Q2 = [cos θ/2, n sin θ/2]` (θ from the sums), `Q1`, `sin θ/2`, `cos θ/2`, the normal,
/// the unit `Q = Q2 Q1 / |Q2 Q1|` and `|Q2 Q1|` at node `i`.
struct Compose<T> {
    q1: Quat<T>,
    q2: Quat<T>,
    sh: T,
    ch: T,
    n: [T; 3],
    q: Quat<T>,
    len: T,
}

impl<T: Real> Compose<T> {
    fn at(w: &Work3<'_, T>, i: usize) -> Self {
        let [s, c]: [T; 2] = load(w.sc, i);
        let (sh, ch) = (s.atan2(c) * T::HALF).sin_cos();
        let n: [T; 3] = load(w.nd, i);
        let q1 = Quat::from_array(load(w.q1, i));
        let q2 = Quat::from_scalar_vector(ch, scale(n, sh));
        let p = q2 * q1;
        let len = p.norm();
        Compose {
            q1,
            q2,
            sh,
            ch,
            n,
            q: p.scale(T::ONE / len),
            len,
        }
    }
}

/// The raw normal of a triangle or quadrilateral as `(p_b1 − p_a1) × (p_b2 − p_a2)`: the
/// local node pairs `[[b1, a1], [b2, a2]]`.
#[inline]
fn normal_pairs(kind: CellKind) -> Option<[[usize; 2]; 2]> {
    match kind {
        CellKind::Triangle => Some([[1, 0], [2, 0]]),
        CellKind::Quad => Some([[2, 0], [3, 1]]),
        _ => None,
    }
}

/// Boundary point indices of the two edges of [`normal_pairs`].
#[inline]
fn normal_nodes(kind: CellKind, nodes: &[u32]) -> Option<[[usize; 2]; 2]> {
    let [[b1, a1], [b2, a2]] = normal_pairs(kind)?;
    let at = |l: usize| nodes.get(l).map(|&v| v as usize);
    Some([[at(b1)?, at(a1)?], [at(b2)?, at(a2)?]])
}

/// 3D tangent of the boundary rotations: `δQ` into `dq` from `δd`. `work` needs
/// [`WORK3`]` B` scalars.
///
/// # Errors
/// Those of [`prep3`].
pub(super) fn rotations3_tangent<T: Real, const D: usize>(
    u: Pts<'_, T, D>,
    d: Pts<'_, T, D>,
    elements: &Cells<'_>,
    dd: &[[T; D]],
    work: &mut [T],
    dq: &mut [T],
) -> Result<()> {
    let mut w = work3(work, dd.len());
    prep3(u, d, elements, &mut w)?;
    // δa = Σ δN_e; δn = (I − n nᵀ) δa / |a|.
    zero(w.dn);
    for (kind, nodes) in elements.iter() {
        let Some([[b1, a1], [b2, a2]]) = normal_nodes(kind, nodes) else {
            continue;
        };
        let e1 = sub(d.get3(b1), d.get3(a1));
        let e2 = sub(d.get3(b2), d.get3(a2));
        let de1 = sub(get3(dd, b1), get3(dd, a1));
        let de2 = sub(get3(dd, b2), get3(dd, a2));
        let dn = add(cross(de1, e2), cross(e1, de2));
        for &v in nodes {
            let a: [T; 3] = load(w.dn, v as usize);
            store(w.dn, v as usize, add(a, dn));
        }
    }
    for (i, &l) in w.alen.iter().enumerate() {
        let n: [T; 3] = load(w.nd, i);
        let dn = proj3(n, l, load(w.dn, i));
        store(w.dn, i, dn);
        // δQ1 = P_Q1 δm / |m|, m = [|u + v|²/2, u × (u + v)] (v = n).
        let nu: [T; 3] = load(w.nu, i);
        let s = add(nu, n);
        let [c0, c1, c2] = cross(nu, dn);
        let dm = [dot(s, dn), c0, c1, c2];
        store(
            w.dq1,
            i,
            proj4(Quat::from_array(load(w.q1, i)), norm(s), dm),
        );
    }
    zero(w.th);
    let (nd, q1, sc) = (&*w.nd, &*w.q1, &*w.sc);
    let (dn, dq1, th) = (&*w.dn, &*w.dq1, &mut *w.th);
    for_each_term(elements, |i, j| {
        let (gq, gn, ge) = Term::new(u, d, nd, q1, i, j).grad(load(sc, i));
        let ded = sub(get3(dd, j), get3(dd, i));
        let v = dot(gq, load(dq1, i)) + dot(gn, load(dn, i)) + dot(ge, ded);
        if let Some(t) = th.get_mut(i) {
            *t += v;
        }
    });
    for (i, &dth) in w.th.iter().enumerate() {
        let c = Compose::at(&w, i);
        let dn: [T; 3] = load(w.dn, i);
        let h = dth * T::HALF;
        let dq2 = Quat::from_scalar_vector(-c.sh * h, add(scale(dn, c.sh), scale(c.n, c.ch * h)));
        let dp = dq2 * c.q1 + c.q2 * Quat::from_array(load(w.dq1, i));
        store(dq, i, proj4(c.q, c.len, dp.to_array()));
    }
    Ok(())
}

/// The transpose of [`rotations3_tangent`]: from `Q̄` in `dq`, adds `d̄` to `out`.
///
/// # Errors
/// Those of [`prep3`].
pub(super) fn rotations3_adjoint<T: Real, const D: usize>(
    u: Pts<'_, T, D>,
    d: Pts<'_, T, D>,
    elements: &Cells<'_>,
    dq: &[T],
    work: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let mut w = work3(work, dq.len() / 4);
    prep3(u, d, elements, &mut w)?;
    for i in 0..w.alen.len() {
        let c = Compose::at(&w, i);
        let pb = Quat::from_array(proj4(c.q, c.len, load(dq, i)));
        let q2b = pb * c.q1.conjugate();
        store(w.dq1, i, (c.q2.conjugate() * pb).to_array());
        store(
            w.th,
            i,
            [(dot(q2b.vector(), c.n) * c.ch - q2b.w * c.sh) * T::HALF],
        );
        store(w.dn, i, scale(q2b.vector(), c.sh));
    }
    {
        let (nd, q1, sc, th) = (&*w.nd, &*w.q1, &*w.sc, &*w.th);
        let (dn, dq1) = (&mut *w.dn, &mut *w.dq1);
        for_each_term(elements, |i, j| {
            let (gq, gn, ge) = Term::new(u, d, nd, q1, i, j).grad(load(sc, i));
            let tb = th.get(i).copied().unwrap_or(T::ZERO);
            let mut a: [T; 4] = load(dq1, i);
            axpy(&mut a, tb, gq);
            store(dq1, i, a);
            let mut b: [T; 3] = load(dn, i);
            axpy(&mut b, tb, gn);
            store(dn, i, b);
            add_to(out, j, scale(ge, tb));
            add_to(out, i, scale(ge, -tb));
        });
    }
    for (i, &l) in w.alen.iter().enumerate() {
        let n: [T; 3] = load(w.nd, i);
        let nu: [T; 3] = load(w.nu, i);
        let s = add(nu, n);
        let mb = proj4(Quat::from_array(load(w.q1, i)), norm(s), load(w.dq1, i));
        let mut nb: [T; 3] = load(w.dn, i);
        axpy(&mut nb, mb[0], s);
        nb = add(nb, cross([mb[1], mb[2], mb[3]], nu));
        store(w.dn, i, proj3(n, l, nb));
    }
    for (kind, nodes) in elements.iter() {
        let Some([[b1, a1], [b2, a2]]) = normal_nodes(kind, nodes) else {
            continue;
        };
        let mut nb = [T::ZERO; 3];
        for &v in nodes {
            nb = add(nb, load(w.dn, v as usize));
        }
        let e1 = sub(d.get3(b1), d.get3(a1));
        let e2 = sub(d.get3(b2), d.get3(a2));
        let g1 = cross(e2, nb);
        let g2 = cross(nb, e1);
        add_to(out, b1, g1);
        add_to(out, a1, scale(g1, -T::ONE));
        add_to(out, b2, g2);
        add_to(out, a2, scale(g2, -T::ONE));
    }
    Ok(())
}
