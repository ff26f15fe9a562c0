//! The numeric pass of the rigid-mode hierarchy ([`RigidAmg`]): rigid-body modes, tentative
//! prolongator by Gram–Schmidt per aggregate, smoothed prolongator, Galerkin blocks, dense
//! coarsest Cholesky factor.

use super::rigid::{blk, blk_mut, block, get, Fine, RigidAmg, Values, MAX_B};
use super::setup::{csr_row, NONE};
use super::{at, seg, Level, AMG_MAX_LEVELS};
use crate::error::{Error, Result};
use crate::real::Real;

const SINGULAR: Error = Error::SingularSystem { iteration: 0 };

/// Read access to the operator of one level: the fine blocks at level 0, the stored coarse
/// blocks above (from `values`, which must hold them).
#[derive(Clone, Copy)]
pub(crate) struct Op<'s, T> {
    pub fine: &'s Fine<'s, T>,
    pub index: &'s [u32],
    pub values: &'s [T],
    pub lv: Level,
    pub vals: &'s Values,
    pub l: usize,
    pub b: usize,
}

impl<'s, T: Real> Op<'s, T> {
    pub fn new(
        h: &'s RigidAmg<'_, T>,
        fine: &'s Fine<'s, T>,
        index: &'s [u32],
        values: &'s [T],
        l: usize,
    ) -> Self {
        Op {
            fine,
            index,
            values,
            lv: h.layout.level(l),
            vals: &h.vals,
            l,
            b: block(h.d, h.k, l),
        }
    }

    /// Whether node `i` takes part (level 0: free).
    #[inline]
    pub fn active(&self, i: usize) -> bool {
        self.l > 0 || !self.fine.is_fixed(i)
    }

    /// Diagonal block of node `i` (`b × b`, row-major); at level 0 a sliding node's block
    /// gains a stiff spring across its allowed motion (see [`Fine::slide`]).
    #[inline]
    pub fn diag(&self, i: usize) -> [T; MAX_B * MAX_B] {
        let bb = self.b * self.b;
        let mut out = [T::ZERO; MAX_B * MAX_B];
        let src = if self.l == 0 {
            blk(self.fine.diag, 0, i, bb)
        } else {
            blk(
                self.values,
                self.vals.diag.get(self.l).copied().unwrap_or(0),
                i,
                bb,
            )
        };
        for (o, &v) in out.iter_mut().zip(src) {
            *o = v;
        }
        if self.l == 0 {
            self.fine.add_slide(i, &mut out);
        }
        out
    }

    /// Point diagonal entry of scalar row `r` of node `i`.
    #[inline]
    pub fn pd(&self, i: usize, r: usize) -> T {
        let start = self.vals.pd.get(self.l).copied().unwrap_or(0);
        get(self.values, start + i * self.b + r)
    }

    /// `f(j, A_ij)` for every active off-diagonal block of row `i`.
    #[inline]
    pub fn row(&self, i: usize, mut f: impl FnMut(usize, &[T])) {
        let bb = self.b * self.b;
        if self.l == 0 {
            let g = self.fine.graph;
            for e in g.edge_range(i) {
                let j = at(g.targets(), e);
                if !self.fine.is_fixed(j) {
                    f(j, blk(self.fine.off, 0, e, bb));
                }
            }
        } else {
            let (s, len) = csr_row(self.index, self.lv.a_offs, self.lv.a_cols, i);
            let start = self.vals.a.get(self.l).copied().unwrap_or(0);
            let rel = s.saturating_sub(self.lv.a_cols);
            for q in 0..len {
                f(at(self.index, s + q), blk(self.values, start, rel + q, bb));
            }
        }
    }
}

/// The rigid-body modes of node `i` at centred coordinates `x` (`d × k`, row-major).
fn modes_at<T: Real>(x: &[T], d: usize, k: usize, out: &mut [T]) {
    out.iter_mut().for_each(|v| *v = T::ZERO);
    let c = |a: usize| get(x, a);
    let mut set = |r: usize, col: usize, v: T| {
        if let Some(o) = out.get_mut(r * k + col) {
            *o = v;
        }
    };
    for r in 0..d {
        set(r, r, T::ONE);
    }
    if d == 2 {
        set(0, 2, -c(1));
        set(1, 2, c(0));
    } else {
        // Rotations about x, y, z: ω × x.
        set(1, 3, -c(2));
        set(2, 3, c(1));
        set(0, 4, c(2));
        set(2, 4, -c(0));
        set(0, 5, -c(1));
        set(1, 5, c(0));
    }
}

/// Level 0's point diagonal and modes (coordinates centred on the bounding box).
fn fine_start<T: Real>(h: &RigidAmg<'_, T>, fine: &Fine<'_, T>, points: &[T], values: &mut [T]) {
    let (d, k) = (h.d, h.k);
    let n = h.layout.level(0).n;
    let mut centre = [T::ZERO; 3];
    for (a, c) in centre.iter_mut().enumerate().take(d) {
        let mut lo = get(points, a);
        let mut hi = lo;
        for i in 0..n {
            let v = get(points, i * d + a);
            lo = lo.min(v);
            hi = hi.max(v);
        }
        *c = (lo + hi) * T::HALF;
    }
    for i in 0..n {
        let mut db = [T::ZERO; MAX_B * MAX_B];
        for (o, &v) in db.iter_mut().zip(blk(fine.diag, 0, i, d * d)) {
            *o = v;
        }
        fine.add_slide(i, &mut db);
        for (r, p) in blk_mut(values, h.vals.pd.first().copied().unwrap_or(0), i, d)
            .iter_mut()
            .enumerate()
        {
            *p = if fine.is_fixed(i) {
                T::ZERO
            } else {
                get(&db, r * d + r)
            };
        }
        let mut x = [T::ZERO; 3];
        for (a, xa) in x.iter_mut().enumerate().take(d) {
            *xa = get(points, i * d + a) - centre.get(a).copied().unwrap_or(T::ZERO);
        }
        let m = blk_mut(values, h.vals.modes.first().copied().unwrap_or(0), i, d * k);
        modes_at(&x, d, k, m);
    }
}

/// Gershgorin bound of `ρ(D⁻¹A)` over the active scalar rows of a level.
fn spectral_bound<T: Real>(op: &Op<'_, T>) -> T {
    let b = op.b;
    let mut rho = T::ZERO;
    for i in 0..op.lv.n {
        if !op.active(i) {
            continue;
        }
        for r in 0..b {
            let d = op.pd(i, r);
            if d <= T::ZERO {
                continue;
            }
            let mut s = T::ZERO;
            for &v in seg(&op.diag(i), r * b, b) {
                s += v.abs();
            }
            op.row(i, |_, a| {
                for &v in seg(a, r * b, b) {
                    s += v.abs();
                }
            });
            rho = rho.max(s / d);
        }
    }
    if rho.is_finite() {
        rho
    } else {
        T::ZERO
    }
}

/// The numeric pass (see [`RigidAmg`]); returns the per-level spectral bounds.
pub(crate) fn numeric<T: Real>(
    h: &RigidAmg<'_, T>,
    fine: &Fine<'_, T>,
    points: &[T],
    index: &[u32],
    values: &mut [T],
) -> Result<[T; AMG_MAX_LEVELS]> {
    let mut rho = [T::ZERO; AMG_MAX_LEVELS];
    fine_start(h, fine, points, values);
    let layout = &h.layout;
    for l in 0..layout.count {
        let p_at = h.vals.p.get(l).copied().unwrap_or(0);
        let last = l + 1 >= layout.count;
        let split = if last { h.vals.t } else { p_at };
        let (lo, hi) = values.split_at_mut_checked(split).ok_or(SINGULAR)?;
        let op = Op::new(h, fine, index, lo, l);
        let r = spectral_bound(&op);
        if let Some(x) = rho.get_mut(l) {
            *x = r;
        }
        if last {
            break;
        }
        let lv = layout.level(l);
        let p_len = lv.p_nnz * op.b * h.k;
        let (pv, rest) = hi.split_at_mut_checked(p_len).ok_or(SINGULAR)?;
        let next_at = p_at + p_len;
        let (next, tail) = rest
            .split_at_mut_checked(h.vals.t.saturating_sub(next_at))
            .ok_or(SINGULAR)?;
        let lvls = Levels {
            h,
            index,
            l,
            next_at,
        };
        lvls.tentative(&op, next, tail)?;
        lvls.prolongator(&op, r, pv, tail);
        lvls.galerkin(&op, pv, next, tail)?;
    }
    if h.vals.dense_n > 0 {
        let l = layout.count - 1;
        let (lo, dense) = values.split_at_mut_checked(h.vals.dense).ok_or(SINGULAR)?;
        let op = Op::new(h, fine, index, lo, l);
        cholesky(&op, h.vals.dense_n, dense)?;
    }
    Ok(rho)
}

/// One level's construction: level `l` read-only, level `l + 1` written into `next` (whose
/// first entry is `values[next_at]`), `T` and the accumulator in `tail` (from `vals.t`).
struct Levels<'s, 'a, T: Real> {
    h: &'s RigidAmg<'a, T>,
    index: &'s [u32],
    l: usize,
    next_at: usize,
}

impl<T: Real> Levels<'_, '_, T> {
    fn next_level(&self) -> Level {
        self.h.layout.level(self.l + 1)
    }

    /// Offset in `next` of a `Values` entry of level `l + 1`.
    fn rel(&self, v: &[usize; AMG_MAX_LEVELS]) -> usize {
        v.get(self.l + 1)
            .copied()
            .unwrap_or(0)
            .saturating_sub(self.next_at)
    }

    fn acc_rel(&self) -> usize {
        self.h.vals.acc - self.h.vals.t
    }

    /// `T` (in `tail`) = the level's modes on aggregated nodes, orthonormalised per aggregate;
    /// the factors `R` become the next level's modes.
    fn tentative(&self, op: &Op<'_, T>, next: &mut [T], tail: &mut [T]) -> Result<()> {
        let (b, k) = (op.b, self.h.k);
        let lv = op.lv;
        let agg = seg(self.index, lv.agg, lv.n);
        let modes_at = self.h.vals.modes.get(self.l).copied().unwrap_or(0);
        for i in 0..lv.n {
            let src = blk(op.values, modes_at, i, b * k);
            let keep = agg.get(i).is_some_and(|&a| a != NONE);
            for (t, &m) in blk_mut(tail, 0, i, b * k).iter_mut().zip(src) {
                *t = if keep { m } else { T::ZERO };
            }
        }
        let tol = T::EPSILON.sqrt() * T::from_f64(1e-2);
        let r_at = self.rel(&self.h.vals.modes);
        for a in 0..self.next_level().n {
            let mut r = [T::ZERO; MAX_B * MAX_B];
            let members = Members {
                index: self.index,
                lv,
                agg,
                a,
            };
            for c in 0..k {
                let norm0 = members.dot(tail, b, k, c, c).sqrt();
                for c2 in 0..c {
                    let x = members.dot(tail, b, k, c2, c);
                    if let Some(v) = r.get_mut(c2 * k + c) {
                        *v = x;
                    }
                    members.axpy(tail, b, k, c2, c, -x);
                }
                let nrm = members.dot(tail, b, k, c, c).sqrt();
                let keep = nrm > tol * norm0 && nrm > T::ZERO;
                members.scale(tail, b, k, c, if keep { T::ONE / nrm } else { T::ZERO });
                if let Some(v) = r.get_mut(c * k + c) {
                    *v = if keep { nrm } else { T::ZERO };
                }
            }
            for (o, &v) in blk_mut(next, r_at, a, k * k).iter_mut().zip(&r) {
                *o = v;
            }
        }
        if tail.iter().take(lv.n * b * k).any(|v| !v.is_finite()) {
            return Err(SINGULAR);
        }
        Ok(())
    }

    /// `P = (I − ω D⁻¹ A) T`, row by row, into `pv`.
    fn prolongator(&self, op: &Op<'_, T>, rho: T, pv: &mut [T], tail: &mut [T]) {
        let (b, k) = (op.b, self.h.k);
        let lv = op.lv;
        let agg = seg(self.index, lv.agg, lv.n);
        let omega = if rho > T::ZERO {
            T::from_f64(4.0 / 3.0) / rho
        } else {
            T::ZERO
        };
        let (t, acc) = tail.split_at_mut(self.acc_rel().min(tail.len()));
        let t: &[T] = t;
        for i in 0..lv.n {
            let (s, len) = csr_row(self.index, lv.p_offs, lv.p_cols, i);
            let cols = seg(self.index, s, len);
            for &c in cols {
                blk_mut(acc, 0, c as usize, b * k).fill(T::ZERO);
            }
            if !op.active(i) {
                continue;
            }
            let mut add = |j: usize, a: &[T]| {
                let aj = agg.get(j).copied().unwrap_or(NONE);
                if aj == NONE {
                    return;
                }
                mul_add(
                    a,
                    blk(t, 0, j, b * k),
                    blk_mut(acc, 0, aj as usize, b * k),
                    [b, b, k],
                );
            };
            add(i, &op.diag(i));
            op.row(i, &mut add);
            let ai = agg.get(i).copied().unwrap_or(NONE);
            let rel = s.saturating_sub(lv.p_cols);
            for (q, &c) in cols.iter().enumerate() {
                let own = blk(t, 0, i, b * k);
                let ac = blk(acc, 0, c as usize, b * k);
                let out = blk_mut(pv, 0, rel + q, b * k);
                for r in 0..b {
                    let d = op.pd(i, r);
                    let w = if d > T::ZERO { omega / d } else { T::ZERO };
                    for col in 0..k {
                        let tv = if c == ai {
                            get(own, r * k + col)
                        } else {
                            T::ZERO
                        };
                        if let Some(o) = out.get_mut(r * k + col) {
                            *o = tv - w * get(ac, r * k + col);
                        }
                    }
                }
            }
        }
    }

    /// `Pᵀ A P` into the next level's blocks, symmetrised exactly, and its point diagonal.
    fn galerkin(&self, op: &Op<'_, T>, pv: &[T], next: &mut [T], tail: &mut [T]) -> Result<()> {
        let (b, k) = (op.b, self.h.k);
        let (lv, nl) = (op.lv, self.next_level());
        let kk = k * k;
        let acc = tail.get_mut(self.acc_rel()..).unwrap_or(&mut []);
        let (d_at, a_at) = (self.rel(&self.h.vals.diag), self.rel(&self.h.vals.a));
        let p_row = |j: usize| {
            let (s, len) = csr_row(self.index, lv.p_offs, lv.p_cols, j);
            (seg(self.index, s, len), s.saturating_sub(lv.p_cols))
        };
        for big in 0..nl.n {
            let (s, len) = csr_row(self.index, nl.a_offs, nl.a_cols, big);
            let cols = seg(self.index, s, len);
            blk_mut(acc, 0, big, kk).fill(T::ZERO);
            for &c in cols {
                blk_mut(acc, 0, c as usize, kk).fill(T::ZERO);
            }
            for q in at(self.index, lv.pt_offs + big)..at(self.index, lv.pt_offs + big + 1) {
                let i = at(self.index, lv.pt_rows + q);
                let pi = blk(pv, 0, at(self.index, lv.pt_pos + q), b * k);
                let mut visit = |j: usize, a: &[T]| {
                    // m = P_iIᵀ A_ij (k × b)
                    let mut m = [T::ZERO; MAX_B * MAX_B];
                    mul_tn_add(pi, a, &mut m, [b, k, b]);
                    let (pc, rel) = p_row(j);
                    for (x, &c) in pc.iter().enumerate() {
                        let pj = blk(pv, 0, rel + x, b * k);
                        mul_add(&m, pj, blk_mut(acc, 0, c as usize, kk), [k, b, k]);
                    }
                };
                visit(i, &op.diag(i));
                op.row(i, &mut visit);
            }
            let acc: &[T] = acc;
            for (o, &v) in blk_mut(next, d_at, big, kk)
                .iter_mut()
                .zip(blk(acc, 0, big, kk))
            {
                *o = v;
            }
            let rel = s.saturating_sub(nl.a_cols);
            for (x, &c) in cols.iter().enumerate() {
                let src = blk(acc, 0, c as usize, kk);
                for (o, &v) in blk_mut(next, a_at, rel + x, kk).iter_mut().zip(src) {
                    *o = v;
                }
            }
        }
        self.symmetrise(next, k)?;
        let pd_at = self.rel(&self.h.vals.pd);
        for i in 0..nl.n {
            for r in 0..k {
                let v = get(blk(next, d_at, i, kk), r * k + r);
                if !(v >= T::ZERO && v.is_finite()) {
                    return Err(SINGULAR);
                }
                if let Some(o) = blk_mut(next, pd_at, i, k).get_mut(r) {
                    *o = v;
                }
            }
        }
        if seg(next, a_at, nl.a_nnz * kk)
            .iter()
            .any(|v| !v.is_finite())
        {
            return Err(SINGULAR);
        }
        Ok(())
    }

    /// Mirror blocks become exact transposes of their mean; diagonal blocks symmetric.
    fn symmetrise(&self, next: &mut [T], k: usize) -> Result<()> {
        let nl = self.next_level();
        let kk = k * k;
        let (d_at, a_at) = (self.rel(&self.h.vals.diag), self.rel(&self.h.vals.a));
        let half = T::HALF;
        for big in 0..nl.n {
            let d = blk_mut(next, d_at, big, kk);
            for r in 0..k {
                for c in r + 1..k {
                    let m = (get(d, r * k + c) + get(d, c * k + r)) * half;
                    set(d, r * k + c, m);
                    set(d, c * k + r, m);
                }
            }
            let (s, len) = csr_row(self.index, nl.a_offs, nl.a_cols, big);
            for q in 0..len {
                let c = at(self.index, s + q);
                if c <= big {
                    continue;
                }
                let (s2, len2) = csr_row(self.index, nl.a_offs, nl.a_cols, c);
                let Ok(q2) = seg(self.index, s2, len2).binary_search(&(big as u32)) else {
                    return Err(SINGULAR);
                };
                let i1 = a_at + (s - nl.a_cols + q) * kk;
                let i2 = a_at + (s2 - nl.a_cols + q2) * kk;
                for r in 0..k {
                    for cc in 0..k {
                        let x = get(next, i1 + r * k + cc);
                        let y = get(next, i2 + cc * k + r);
                        let m = (x + y) * half;
                        set(next, i1 + r * k + cc, m);
                        set(next, i2 + cc * k + r, m);
                    }
                }
            }
        }
        Ok(())
    }
}

/// `v[i] = x` when in range.
#[inline]
fn set<T>(v: &mut [T], i: usize, x: T) {
    if let Some(o) = v.get_mut(i) {
        *o = x;
    }
}

/// The members of aggregate `a` (the rows of `Pᵀ`'s column `a` that lie in it), and the
/// column operations of Gram–Schmidt on `T` restricted to them.
struct Members<'s> {
    index: &'s [u32],
    lv: Level,
    agg: &'s [u32],
    a: usize,
}

impl Members<'_> {
    fn each(&self, mut f: impl FnMut(usize)) {
        let lv = self.lv;
        for q in at(self.index, lv.pt_offs + self.a)..at(self.index, lv.pt_offs + self.a + 1) {
            let i = at(self.index, lv.pt_rows + q);
            if self.agg.get(i).is_some_and(|&x| x as usize == self.a) {
                f(i);
            }
        }
    }

    fn dot<T: Real>(&self, t: &[T], b: usize, k: usize, c1: usize, c2: usize) -> T {
        let mut s = T::ZERO;
        self.each(|i| {
            let m = blk(t, 0, i, b * k);
            for r in 0..b {
                s += get(m, r * k + c1) * get(m, r * k + c2);
            }
        });
        s
    }

    /// Column `c` += `x` · column `src`.
    fn axpy<T: Real>(&self, t: &mut [T], b: usize, k: usize, src: usize, c: usize, x: T) {
        self.each(|i| {
            let m = blk_mut(t, 0, i, b * k);
            for r in 0..b {
                let v = get(m, r * k + c) + x * get(m, r * k + src);
                set(m, r * k + c, v);
            }
        });
    }

    fn scale<T: Real>(&self, t: &mut [T], b: usize, k: usize, c: usize, x: T) {
        self.each(|i| {
            let m = blk_mut(t, 0, i, b * k);
            for r in 0..b {
                let v = get(m, r * k + c) * x;
                set(m, r * k + c, v);
            }
        });
    }
}

/// `out += x y` with `x` `m × n`, `y` `n × p` (row-major).
#[inline]
pub(crate) fn mul_add<T: Real>(x: &[T], y: &[T], out: &mut [T], [m, n, p]: [usize; 3]) {
    for r in 0..m {
        for c in 0..p {
            let mut s = get(out, r * p + c);
            for q in 0..n {
                s += get(x, r * n + q) * get(y, q * p + c);
            }
            set(out, r * p + c, s);
        }
    }
}

/// `out += xᵀ y` with `x` `n × m`, `y` `n × p` (`out` `m × p`).
#[inline]
fn mul_tn_add<T: Real>(x: &[T], y: &[T], out: &mut [T], [n, m, p]: [usize; 3]) {
    for r in 0..m {
        for c in 0..p {
            let mut s = get(out, r * p + c);
            for q in 0..n {
                s += get(x, q * m + r) * get(y, q * p + c);
            }
            set(out, r * p + c, s);
        }
    }
}

/// The coarsest operator densely (lower triangle, `m × m` scalars) factored in place; inactive
/// unknowns (zero diagonal, zero row) get a unit pivot.
fn cholesky<T: Real>(op: &Op<'_, T>, m: usize, dense: &mut [T]) -> Result<()> {
    let dense = dense.get_mut(..m * m).ok_or(SINGULAR)?;
    dense.fill(T::ZERO);
    let b = op.b;
    for i in 0..op.lv.n {
        let mut put = |j: usize, a: &[T]| {
            for r in 0..b {
                for c in 0..b {
                    let (gr, gc) = (i * b + r, j * b + c);
                    if gc <= gr {
                        set(dense, gr * m + gc, get(a, r * b + c));
                    }
                }
            }
        };
        put(i, &op.diag(i));
        op.row(i, put);
    }
    for j in 0..m {
        let ajj = get(dense, j * m + j);
        if ajj == T::ZERO {
            set(dense, j * m + j, T::ONE);
            continue;
        }
        let mut s = ajj;
        for q in 0..j {
            let x = get(dense, j * m + q);
            s -= x * x;
        }
        if !(s > T::EPSILON * ajj && s.is_finite()) {
            return Err(SINGULAR);
        }
        let ljj = s.sqrt();
        set(dense, j * m + j, ljj);
        for i in j + 1..m {
            let mut s = get(dense, i * m + j);
            for q in 0..j {
                s -= get(dense, i * m + q) * get(dense, j * m + q);
            }
            set(dense, i * m + j, s / ljj);
        }
    }
    Ok(())
}
