//! The symmetric V-cycle: damped-Jacobi pre-smoothing, restriction by `Pᵀ`, coarse
//! correction (dense Cholesky or smoothing on the coarsest level), prolongation by `P`, the
//! same damped-Jacobi post-smoothing. Every operation is node-local or a fixed-order sum, so
//! the result does not depend on how the nodes would be partitioned.

use core::ops::Range;

use super::setup::{csr_row, entries};
use super::{at, seg, AmgHierarchy, Level};
use crate::real::Real;
use crate::spring::distributed::{share_field, share_halo, Collective};
use crate::spring::system::SpringSystem;

/// `t = b − A x` on level `l` (zero on fixed nodes of level 0, where `x` is zero); on level 0
/// only at the `rows` (a process's own; `x` current on their neighbours).
fn residual<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    l: usize,
    x: &[[T; V]],
    b: &[[T; V]],
    t: &mut [[T; V]],
    rows: &[Range<usize>],
) {
    let lv = h.layout.level(l);
    let diag = seg(h.values, lv.diag, lv.n);
    if l == 0 {
        for range in rows {
            let (Some(ts), Some(bs), Some(xs), Some(ds)) = (
                t.get_mut(range.clone()),
                b.get(range.clone()),
                x.get(range.clone()),
                diag.get(range.clone()),
            ) else {
                continue;
            };
            for (((_, fixed, row), (ti, &bi)), (&xi, &d)) in sys
                .rows_in(range.clone())
                .zip(ts.iter_mut().zip(bs))
                .zip(xs.iter().zip(ds))
            {
                if fixed {
                    *ti = [T::ZERO; V];
                    continue;
                }
                let mut ax = [T::ZERO; V];
                for (a, &v) in ax.iter_mut().zip(&xi) {
                    *a = d * v;
                }
                for (j, k) in row {
                    let xj = x.get(j).copied().unwrap_or([T::ZERO; V]);
                    for (a, &v) in ax.iter_mut().zip(&xj) {
                        *a -= k * v;
                    }
                }
                for ((r, &bv), &a) in ti.iter_mut().zip(&bi).zip(&ax) {
                    *r = bv - a;
                }
            }
        }
    } else {
        for (i, ((ti, &bi), (&xi, &d))) in t.iter_mut().zip(b).zip(x.iter().zip(diag)).enumerate() {
            let mut ax = [T::ZERO; V];
            for (a, &v) in ax.iter_mut().zip(&xi) {
                *a = d * v;
            }
            entries(sys, h.index, h.values, &lv, false, i, |j, a| {
                let xj = x.get(j).copied().unwrap_or([T::ZERO; V]);
                for (s, &v) in ax.iter_mut().zip(&xj) {
                    *s += a * v;
                }
            });
            for ((r, &bv), &a) in ti.iter_mut().zip(&bi).zip(&ax) {
                *r = bv - a;
            }
        }
    }
}

/// `x += (ω_s / d) t` on the active unknowns of level `l` (step `s`'s weight); on level 0
/// only at the `rows`.
fn jacobi_update<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    l: usize,
    s: usize,
    x: &mut [[T; V]],
    t: &[[T; V]],
    rows: &[Range<usize>],
) {
    let lv = h.layout.level(l);
    let w = h
        .weights
        .get(l)
        .and_then(|w| w.get(s))
        .copied()
        .unwrap_or(T::ZERO);
    let diag = seg(h.values, lv.diag, lv.n);
    if l == 0 {
        for range in rows {
            let (Some(xs), Some(ts), Some(ds)) = (
                x.get_mut(range.clone()),
                t.get(range.clone()),
                diag.get(range.clone()),
            ) else {
                continue;
            };
            for (i, ((xi, ti), &d)) in (range.start..).zip(xs.iter_mut().zip(ts).zip(ds)) {
                if sys.is_fixed(i) {
                    continue;
                }
                let c = w / d;
                for (xv, &tv) in xi.iter_mut().zip(ti) {
                    *xv += c * tv;
                }
            }
        }
        return;
    }
    for ((xi, ti), &d) in x.iter_mut().zip(t).zip(diag) {
        let c = w / d;
        for (xv, &tv) in xi.iter_mut().zip(ti) {
            *xv += c * tv;
        }
    }
}

/// The smoother's steps on `A x = b`; from `x = 0` when `from_zero`. On level 0 only the
/// `rows` are computed, and `x`'s halo is shared before every residual.
#[allow(clippy::too_many_arguments)]
fn smooth<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    l: usize,
    x: &mut [[T; V]],
    b: &[[T; V]],
    t: &mut [[T; V]],
    from_zero: bool,
    rows: &[Range<usize>],
    comm: &C,
) {
    let mut first = 0;
    if from_zero {
        // First step from zero: x = (ω_0 / d) b (the residual of 0 is b).
        for x in x.iter_mut() {
            *x = [T::ZERO; V];
        }
        jacobi_update(sys, h, l, 0, x, b, rows);
        first = 1;
    }
    for s in first..h.sweeps {
        if l == 0 {
            share_halo(comm, x);
        }
        residual(sys, h, l, x, b, t, rows);
        jacobi_update(sys, h, l, s, x, t, rows);
    }
}

/// `bc = Pᵀ t` (gather by coarse unknown, fine rows in increasing order).
fn restrict<T: Real, const V: usize>(
    h: &AmgHierarchy<'_, T>,
    lv: &Level,
    t: &[[T; V]],
    bc: &mut [[T; V]],
) {
    for (big, b) in bc.iter_mut().enumerate() {
        let mut s = [T::ZERO; V];
        let a = at(h.index, lv.pt_offs + big);
        let e = at(h.index, lv.pt_offs + big + 1);
        for k in a..e {
            let i = at(h.index, lv.pt_rows + k);
            let p = h
                .values
                .get(lv.p_vals.saturating_add(at(h.index, lv.pt_pos + k)))
                .copied()
                .unwrap_or(T::ZERO);
            let ti = t.get(i).copied().unwrap_or([T::ZERO; V]);
            for (s, &v) in s.iter_mut().zip(&ti) {
                *s += p * v;
            }
        }
        *b = s;
    }
}

/// `x += P xc` at the `rows` of `x`.
fn prolong<T: Real, const V: usize>(
    h: &AmgHierarchy<'_, T>,
    lv: &Level,
    xc: &[[T; V]],
    x: &mut [[T; V]],
    rows: &[Range<usize>],
) {
    for range in rows {
        let Some(xs) = x.get_mut(range.clone()) else {
            continue;
        };
        prolong_rows(h, lv, xc, xs, range.start);
    }
}

/// [`prolong`] on `x`, the rows from `first` on.
fn prolong_rows<T: Real, const V: usize>(
    h: &AmgHierarchy<'_, T>,
    lv: &Level,
    xc: &[[T; V]],
    x: &mut [[T; V]],
    first: usize,
) {
    for (i, xi) in (first..).zip(x.iter_mut()) {
        let (s, len) = csr_row(h.index, lv.p_offs, lv.p_cols, i);
        let cols = seg(h.index, s, len);
        let vals = seg(h.values, lv.p_vals + (s - lv.p_cols), len);
        let mut add = [T::ZERO; V];
        for (&c, &p) in cols.iter().zip(vals) {
            let xj = xc.get(c as usize).copied().unwrap_or([T::ZERO; V]);
            for (a, &v) in add.iter_mut().zip(&xj) {
                *a += p * v;
            }
        }
        for (xv, &a) in xi.iter_mut().zip(&add) {
            *xv += a;
        }
    }
}

/// `x = A⁻¹ b` on the coarsest level with the dense Cholesky factor (`L y = b`, `Lᵀ x = y`).
fn dense_solve<T: Real, const V: usize>(h: &AmgHierarchy<'_, T>, x: &mut [[T; V]], b: &[[T; V]]) {
    let m = h.layout.dense_n;
    let f = seg(h.values, h.layout.dense, m * m);
    for (x, &b) in x.iter_mut().zip(b) {
        *x = b;
    }
    for i in 0..m {
        let mut s = x.get(i).copied().unwrap_or([T::ZERO; V]);
        for k in 0..i {
            let l = f.get(i * m + k).copied().unwrap_or(T::ZERO);
            let xk = x.get(k).copied().unwrap_or([T::ZERO; V]);
            for (s, &v) in s.iter_mut().zip(&xk) {
                *s -= l * v;
            }
        }
        let d = f.get(i * m + i).copied().unwrap_or(T::ONE);
        if let Some(xi) = x.get_mut(i) {
            for (xv, &sv) in xi.iter_mut().zip(&s) {
                *xv = sv / d;
            }
        }
    }
    for i in (0..m).rev() {
        let mut s = x.get(i).copied().unwrap_or([T::ZERO; V]);
        for k in i + 1..m {
            let l = f.get(k * m + i).copied().unwrap_or(T::ZERO);
            let xk = x.get(k).copied().unwrap_or([T::ZERO; V]);
            for (s, &v) in s.iter_mut().zip(&xk) {
                *s -= l * v;
            }
        }
        let d = f.get(i * m + i).copied().unwrap_or(T::ONE);
        if let Some(xi) = x.get_mut(i) {
            for (xv, &sv) in xi.iter_mut().zip(&s) {
                *xv = sv / d;
            }
        }
    }
}

/// Start of level `l`'s vectors `[x | b | t]` in the coarse scratch (levels ≥ 1).
fn offset<T: Real>(h: &AmgHierarchy<'_, T>, l: usize) -> usize {
    (1..l).fold(0usize, |s, k| s.saturating_add(3 * h.layout.level(k).n))
}

/// The level's three vectors `(x, b, t)` starting at `off` in `buf`.
#[allow(clippy::type_complexity)]
fn parts<X>(buf: &mut [X], off: usize, n: usize) -> (&mut [X], &mut [X], &mut [X]) {
    let rest = buf.get_mut(off..).unwrap_or(&mut []);
    let (x, rest) = rest.split_at_mut(n.min(rest.len()));
    let (b, rest) = rest.split_at_mut(n.min(rest.len()));
    let t = rest.get_mut(..n).unwrap_or(&mut []);
    (x, b, t)
}

/// `z = M⁻¹ r`: one V-cycle from zero. `t` is a fine-level temporary, `coarse` holds three
/// vectors per coarse level ([`AmgSizes::coarse_unknowns`](super::AmgSizes) × 3 items).
/// `z` is zero on fixed nodes.
///
/// Split over the processes of `comm`: the fine level is computed at the own rows only
/// (`r` needed there; `z` comes back right there), with `z`'s halo shared before each fine
/// residual and the fine residual shared whole before the restriction; the coarse levels run
/// whole on every process. Every row is computed as in one process, so `z` has the same bits.
pub(crate) fn vcycle<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    sys: &SpringSystem<'_, T>,
    h: &AmgHierarchy<'_, T>,
    r: &[[T; V]],
    z: &mut [[T; V]],
    t: &mut [[T; V]],
    coarse: &mut [[T; V]],
    comm: &C,
) {
    let rows = comm.owned();
    let last = h.layout.count.saturating_sub(1);
    // Down: pre-smooth, residual, restrict.
    for l in 0..last {
        let lv = h.layout.level(l);
        let next = h.layout.level(l + 1);
        if l == 0 {
            smooth(sys, h, 0, z, r, t, true, rows, comm);
            share_halo(comm, z);
            residual(sys, h, 0, z, r, t, rows);
            share_field(comm, t);
            let (_, bc, _) = parts(coarse, 0, next.n);
            restrict(h, &lv, t, bc);
        } else {
            let all = [Range {
                start: 0,
                end: lv.n,
            }];
            let split = offset(h, l + 1);
            let (lo, hi) = coarse.split_at_mut(split.min(coarse.len()));
            let (x, b, tl) = parts(lo, offset(h, l), lv.n);
            smooth(sys, h, l, x, b, tl, true, &all, comm);
            residual(sys, h, l, x, b, tl, &all);
            let (_, bc, _) = parts(hi, 0, next.n);
            restrict(h, &lv, tl, bc);
        }
    }
    // Coarsest level.
    if last == 0 {
        smooth(sys, h, 0, z, r, t, true, rows, comm);
        smooth(sys, h, 0, z, r, t, false, rows, comm);
        return;
    }
    {
        let lv = h.layout.level(last);
        let all = [Range {
            start: 0,
            end: lv.n,
        }];
        let (x, b, tl) = parts(coarse, offset(h, last), lv.n);
        if h.layout.dense_n > 0 {
            dense_solve(h, x, b);
        } else {
            smooth(sys, h, last, x, b, tl, true, &all, comm);
            smooth(sys, h, last, x, b, tl, false, &all, comm);
        }
    }
    // Up: prolong, post-smooth.
    for l in (0..last).rev() {
        let lv = h.layout.level(l);
        let next = h.layout.level(l + 1);
        let split = offset(h, l + 1);
        if l == 0 {
            let (xc, _, _) = parts(coarse, 0, next.n);
            prolong(h, &lv, xc, z, rows);
            smooth(sys, h, 0, z, r, t, false, rows, comm);
        } else {
            let all = [Range {
                start: 0,
                end: lv.n,
            }];
            let (lo, hi) = coarse.split_at_mut(split.min(coarse.len()));
            let (xc, _, _) = parts(hi, 0, next.n);
            let (x, b, tl) = parts(lo, offset(h, l), lv.n);
            prolong(h, &lv, xc, x, &all);
            smooth(sys, h, l, x, b, tl, false, &all, comm);
        }
    }
}
