//! The symmetric V-cycle of the rigid-mode hierarchy ([`RigidAmg`]) on flat scalar vectors
//! (`b` unknowns per node of a level): smoothing, restriction by `Pᵀ`, the coarsest solve,
//! prolongation by `P`, the same smoothing; as a CG preconditioner ([`RigidVcycle`]).

use super::rigid::{blk, block, get, Fine, RigidAmg, MAX_B};
use super::rigid_numeric::Op;
use super::setup::csr_row;
use super::{at, seg};
use crate::real::Real;
use crate::spring::distributed::Collective;
use crate::spring::krylov::Precondition;

/// `t = b − A x` at the active nodes (zero elsewhere).
fn residual<T: Real>(op: &Op<'_, T>, x: &[T], b: &[T], t: &mut [T]) {
    let bs = op.b;
    for i in 0..op.lv.n {
        let mut ax = [T::ZERO; MAX_B];
        if op.active(i) {
            let mut add = |j: usize, a: &[T]| {
                let xj = seg(x, j * bs, bs);
                for (r, s) in ax.iter_mut().enumerate().take(bs) {
                    for (c, &v) in xj.iter().enumerate() {
                        *s += get(a, r * bs + c) * v;
                    }
                }
            };
            add(i, &op.diag(i));
            op.row(i, add);
        }
        for (r, o) in t.iter_mut().skip(i * bs).take(bs).enumerate() {
            *o = if op.active(i) {
                get(b, i * bs + r) - get(&ax, r)
            } else {
                T::ZERO
            };
        }
    }
}

/// `x += (w / a_rr) t` at the active scalar rows.
fn update<T: Real>(op: &Op<'_, T>, w: T, x: &mut [T], t: &[T]) {
    let bs = op.b;
    for i in 0..op.lv.n {
        if !op.active(i) {
            continue;
        }
        for r in 0..bs {
            let d = op.pd(i, r);
            if d > T::ZERO {
                if let Some(v) = x.get_mut(i * bs + r) {
                    *v += w / d * get(t, i * bs + r);
                }
            }
        }
    }
}

/// The smoother's steps on level `op.l`; from `x = 0` when `from_zero`.
fn smooth<T: Real>(
    h: &RigidAmg<'_, T>,
    op: &Op<'_, T>,
    x: &mut [T],
    b: &[T],
    t: &mut [T],
    from_zero: bool,
) {
    let w = |s: usize| {
        h.weights
            .get(op.l)
            .and_then(|w| w.get(s))
            .copied()
            .unwrap_or(T::ZERO)
    };
    let mut first = 0;
    if from_zero {
        x.fill(T::ZERO);
        update(op, w(0), x, b);
        first = 1;
    }
    for s in first..h.sweeps {
        residual(op, x, b, t);
        update(op, w(s), x, t);
    }
}

/// `bc = Pᵀ t` on level `l`'s prolongator.
fn restrict<T: Real>(h: &RigidAmg<'_, T>, l: usize, t: &[T], bc: &mut [T]) {
    let lv = h.layout.level(l);
    let (b, k) = (block(h.d, h.k, l), h.k);
    let p_at = h.vals.p.get(l).copied().unwrap_or(0);
    for big in 0..h.layout.level(l + 1).n {
        let mut s = [T::ZERO; MAX_B];
        for q in at(h.index, lv.pt_offs + big)..at(h.index, lv.pt_offs + big + 1) {
            let i = at(h.index, lv.pt_rows + q);
            let p = blk(h.values, p_at, at(h.index, lv.pt_pos + q), b * k);
            let ti = seg(t, i * b, b);
            for (c, sc) in s.iter_mut().enumerate().take(k) {
                for (r, &v) in ti.iter().enumerate() {
                    *sc += get(p, r * k + c) * v;
                }
            }
        }
        for (o, &v) in bc.iter_mut().skip(big * k).take(k).zip(&s) {
            *o = v;
        }
    }
}

/// `x += P xc` on level `l`'s prolongator.
fn prolong<T: Real>(h: &RigidAmg<'_, T>, l: usize, xc: &[T], x: &mut [T]) {
    let lv = h.layout.level(l);
    let (b, k) = (block(h.d, h.k, l), h.k);
    let p_at = h.vals.p.get(l).copied().unwrap_or(0);
    for i in 0..lv.n {
        let (s, len) = csr_row(h.index, lv.p_offs, lv.p_cols, i);
        let rel = s.saturating_sub(lv.p_cols);
        let mut add = [T::ZERO; MAX_B];
        for (q, &c) in seg(h.index, s, len).iter().enumerate() {
            let p = blk(h.values, p_at, rel + q, b * k);
            let xcc = seg(xc, c as usize * k, k);
            for (r, a) in add.iter_mut().enumerate().take(b) {
                for (cc, &v) in xcc.iter().enumerate() {
                    *a += get(p, r * k + cc) * v;
                }
            }
        }
        for (o, &a) in x.iter_mut().skip(i * b).take(b).zip(&add) {
            *o += a;
        }
    }
}

/// `x = A⁻¹ b` with the dense coarsest factor.
fn dense_solve<T: Real>(h: &RigidAmg<'_, T>, x: &mut [T], b: &[T]) {
    let m = h.vals.dense_n;
    let f = seg(h.values, h.vals.dense, m * m);
    for (x, &b) in x.iter_mut().zip(b) {
        *x = b;
    }
    for i in 0..m {
        let mut s = get(x, i);
        for q in 0..i {
            s -= get(f, i * m + q) * get(x, q);
        }
        if let Some(v) = x.get_mut(i) {
            *v = s / get(f, i * m + i);
        }
    }
    for i in (0..m).rev() {
        let mut s = get(x, i);
        for q in i + 1..m {
            s -= get(f, q * m + i) * get(x, q);
        }
        if let Some(v) = x.get_mut(i) {
            *v = s / get(f, i * m + i);
        }
    }
}

/// Start of level `l`'s vectors in the coarse scratch (levels ≥ 1).
fn offset<T: Real>(h: &RigidAmg<'_, T>, l: usize) -> usize {
    (1..l).fold(0usize, |s, q| s.saturating_add(3 * h.level_unknowns(q)))
}

/// The three vectors `(x, b, t)` of level `l ≥ 1` starting at `off` in `buf`.
fn parts<'c, T: Real>(
    h: &RigidAmg<'_, T>,
    buf: &'c mut [T],
    off: usize,
    l: usize,
) -> (&'c mut [T], &'c mut [T], &'c mut [T]) {
    let n = h.level_unknowns(l);
    let rest = buf.get_mut(off..).unwrap_or(&mut []);
    let (x, rest) = rest.split_at_mut(n.min(rest.len()));
    let (b, rest) = rest.split_at_mut(n.min(rest.len()));
    let t = rest.get_mut(..n).unwrap_or(&mut []);
    (x, b, t)
}

/// `coarse` split before level `l + 1`'s vectors.
fn split<'c, T: Real>(
    h: &RigidAmg<'_, T>,
    coarse: &'c mut [T],
    l: usize,
) -> (&'c mut [T], &'c mut [T]) {
    let at = offset(h, l + 1);
    coarse.split_at_mut(at.min(coarse.len()))
}

/// `z = M⁻¹ r`: one V-cycle from zero on flat fine vectors; `t` one fine vector, `coarse`
/// three vectors per coarse level.
fn vcycle<T: Real>(
    h: &RigidAmg<'_, T>,
    fine: &Fine<'_, T>,
    r: &[T],
    z: &mut [T],
    t: &mut [T],
    coarse: &mut [T],
) {
    let last = h.layout.count.saturating_sub(1);
    let op = |l: usize| Op::new(h, fine, h.index, h.values, l);
    smooth(h, &op(0), z, r, t, true);
    if last == 0 {
        smooth(h, &op(0), z, r, t, false);
        return;
    }
    residual(&op(0), z, r, t);
    restrict(h, 0, t, parts(h, coarse, 0, 1).1);
    for l in 1..last {
        let (lo, hi) = split(h, coarse, l);
        let (x, b, tl) = parts(h, lo, offset(h, l), l);
        smooth(h, &op(l), x, b, tl, true);
        residual(&op(l), x, b, tl);
        restrict(h, l, tl, parts(h, hi, 0, l + 1).1);
    }
    {
        let (x, b, tl) = parts(h, coarse, offset(h, last), last);
        if h.vals.dense_n > 0 {
            dense_solve(h, x, b);
        } else {
            smooth(h, &op(last), x, b, tl, true);
            smooth(h, &op(last), x, b, tl, false);
        }
    }
    for l in (1..last).rev() {
        let (lo, hi) = split(h, coarse, l);
        let (x, b, tl) = parts(h, lo, offset(h, l), l);
        prolong(h, l, parts(h, hi, 0, l + 1).0, x);
        smooth(h, &op(l), x, b, tl, false);
    }
    prolong(h, 0, parts(h, coarse, 0, 1).0, z);
    smooth(h, &op(0), z, r, t, false);
}

/// [`RigidAmg`]'s V-cycle as the preconditioner of the elasticity CG (`z` zero at fixed
/// nodes). `t` is one fine vector (`n D` scalars), `coarse` three per coarse scalar unknown.
pub(crate) struct RigidVcycle<'s, 'a, 'h, T: Real> {
    pub(crate) h: &'s RigidAmg<'h, T>,
    pub(crate) fine: &'s Fine<'a, T>,
    pub(crate) t: &'s mut [T],
    pub(crate) coarse: &'s mut [T],
}

impl<'s, 'a, 'h, T: Real> RigidVcycle<'s, 'a, 'h, T> {
    /// The preconditioner of `h` on `fine` with its fine and coarse scratch.
    pub(crate) fn new(
        h: &'s RigidAmg<'h, T>,
        fine: &'s Fine<'a, T>,
        t: &'s mut [T],
        coarse: &'s mut [T],
    ) -> Self {
        RigidVcycle { h, fine, t, coarse }
    }
}

impl<T: Real, const D: usize> Precondition<T, D> for RigidVcycle<'_, '_, '_, T> {
    fn local(&self) -> bool {
        false
    }
    fn node(&self, _: usize, r: [T; D]) -> [T; D] {
        r
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; D]], z: &mut [[T; D]], _: &C) {
        vcycle(
            self.h,
            self.fine,
            r.as_flattened(),
            z.as_flattened_mut(),
            self.t,
            self.coarse,
        );
        for (i, z) in z.iter_mut().enumerate() {
            if self.fine.is_fixed(i) {
                *z = [T::ZERO; D];
            }
        }
    }
}
