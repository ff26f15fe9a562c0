//! Hierarchy construction: the symbolic pass (aggregation, prolongator and Galerkin sparsity)
//! and the numeric pass (diagonals, smoothed prolongator, Galerkin values, dense coarsest
//! Cholesky factor).

use super::mis2;
use super::{
    at, seg, seg_mut, AmgOptions, AmgSmoother, Layout, Level, AMG_MAX_LEVELS, AMG_MAX_SWEEPS,
};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::system::SpringSystem;

/// "In no aggregate" / "unset" marker.
pub(crate) const NONE: u32 = u32::MAX;
/// Not yet aggregated (aggregation pass 1).
const FREE: u32 = u32::MAX - 1;
/// Flag of a node that joined an aggregate in pass 2 (so pass 2 never chains through it).
const JOINED: u32 = 1 << 31;

/// Symbolic work budget: `4 (N + E) + 64`.
pub(crate) const fn budget(n: usize, e: usize) -> usize {
    n.saturating_add(e).saturating_mul(4).saturating_add(64)
}

/// Calls `f(j)` for every active off-diagonal neighbour `j` of `i` on level `l` (level 0: free
/// neighbours in the system; coarse levels: the stored columns).
#[inline]
fn neighbours<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    lv: &Level,
    fine: bool,
    i: usize,
    mut f: impl FnMut(usize),
) {
    if fine {
        for &j in sys.graph().neighbors(i) {
            if !sys.is_fixed(j as usize) {
                f(j as usize);
            }
        }
    } else {
        let a = at(index, lv.a_offs.saturating_add(i));
        let b = at(index, lv.a_offs.saturating_add(i).saturating_add(1));
        for &j in index
            .get(lv.a_cols.saturating_add(a)..lv.a_cols.saturating_add(b))
            .unwrap_or(&[])
        {
            f(j as usize);
        }
    }
}

/// Calls `f(j, a_ij)` for every active off-diagonal entry of row `i` on level `l`.
#[inline]
pub(crate) fn entries<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    values: &[T],
    lv: &Level,
    fine: bool,
    i: usize,
    mut f: impl FnMut(usize, T),
) {
    if fine {
        for (j, k) in sys.row(i) {
            if !sys.is_fixed(j) {
                f(j, -k);
            }
        }
    } else {
        let a = at(index, lv.a_offs.saturating_add(i));
        let b = at(index, lv.a_offs.saturating_add(i).saturating_add(1));
        let cols = index
            .get(lv.a_cols.saturating_add(a)..lv.a_cols.saturating_add(b))
            .unwrap_or(&[]);
        let vals = values
            .get(lv.a_vals.saturating_add(a)..lv.a_vals.saturating_add(b))
            .unwrap_or(&[]);
        for (&j, &v) in cols.iter().zip(vals) {
            f(j as usize, v);
        }
    }
}

/// Row `i` of a CSR array pair stored at `offs`/`cols` (offsets relative to `cols`).
#[inline]
pub(crate) fn csr_row(index: &[u32], offs: usize, cols: usize, i: usize) -> (usize, usize) {
    let a = at(index, offs.saturating_add(i));
    let b = at(index, offs.saturating_add(i).saturating_add(1));
    (cols.saturating_add(a), b.saturating_sub(a))
}

/// Diagonal of fine row `i`: `Σ_j k_ij` over all neighbours, in CSR order.
#[inline]
fn fine_diag<T: Real>(sys: &SpringSystem<'_, T>, i: usize) -> T {
    let mut d = T::ZERO;
    for (_, k) in sys.row(i) {
        d += k;
    }
    d
}

/// The stiffest spring at node `i` (every neighbour, fixed ones too): the scale of the strength
/// test.
fn fine_max<T: Real>(sys: &SpringSystem<'_, T>, i: usize) -> T {
    let mut m = T::ZERO;
    for (_, k) in sys.row(i) {
        m = m.max(k);
    }
    m
}

/// Calls `f(j)` for every strong neighbour of `i`: level 0 with `θ > 0` keeps the free
/// neighbours whose spring is at least `θ` times the geometric mean of the stiffest springs at
/// `i` and at `j`, `k_ij ≥ θ √(m_i m_j)` (symmetric; on a stretched boundary layer it drops the
/// long, soft springs along the layer, on an isotropic mesh next to nothing); otherwise every
/// neighbour is strong.
#[inline]
fn strong<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    lv: &Level,
    fine: bool,
    theta: T,
    i: usize,
    mut f: impl FnMut(usize),
) {
    if fine && theta > T::ZERO {
        let mi = fine_max(sys, i);
        for (j, k) in sys.row(i) {
            if !sys.is_fixed(j) && k >= theta * (mi * fine_max(sys, j)).sqrt() {
                f(j);
            }
        }
    } else {
        neighbours(sys, index, lv, fine, i, f);
    }
}

/// pyamg's standard aggregation in node order; returns the number of aggregates. `agg[i]` ends
/// as the aggregate of `i` or [`NONE`] (fixed node, or no strong neighbour).
fn aggregate<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    lv: &Level,
    fine: bool,
    theta: T,
    agg: &mut [u32],
) -> usize {
    for (i, a) in agg.iter_mut().enumerate() {
        *a = if fine && sys.is_fixed(i) { NONE } else { FREE };
    }
    let mut nc: u32 = 0;
    // Pass 1: a node whose strong neighbours are all unaggregated becomes the root of an
    // aggregate with all of them; a node without strong neighbours stays out.
    for i in 0..agg.len() {
        if agg.get(i) != Some(&FREE) {
            continue;
        }
        let mut has = false;
        let mut clear = true;
        strong(sys, index, lv, fine, theta, i, |j| {
            if j != i {
                has = true;
                if agg.get(j) != Some(&FREE) {
                    clear = false;
                }
            }
        });
        if !has {
            if let Some(a) = agg.get_mut(i) {
                *a = NONE;
            }
        } else if clear {
            if let Some(a) = agg.get_mut(i) {
                *a = nc;
            }
            strong(sys, index, lv, fine, theta, i, |j| {
                if let Some(a) = agg.get_mut(j) {
                    *a = nc;
                }
            });
            nc += 1;
        }
    }
    // Pass 2: leftovers join the first pass-1 aggregate among their strong neighbours.
    for i in 0..agg.len() {
        if agg.get(i) != Some(&FREE) {
            continue;
        }
        let mut found = NONE;
        strong(sys, index, lv, fine, theta, i, |j| {
            if found == NONE {
                if let Some(&a) = agg.get(j) {
                    if a < JOINED {
                        found = a;
                    }
                }
            }
        });
        if found != NONE {
            if let Some(a) = agg.get_mut(i) {
                *a = found | JOINED;
            }
        }
    }
    // Pass 3 (rarely used): what is left forms aggregates with its unaggregated neighbours.
    for i in 0..agg.len() {
        if agg.get(i) != Some(&FREE) {
            continue;
        }
        if let Some(a) = agg.get_mut(i) {
            *a = nc;
        }
        strong(sys, index, lv, fine, theta, i, |j| {
            if let Some(a) = agg.get_mut(j) {
                if *a == FREE {
                    *a = nc;
                }
            }
        });
        nc += 1;
    }
    for a in agg.iter_mut() {
        if *a != NONE {
            *a &= !JOINED;
        }
    }
    nc as usize
}

/// One level's strong graph as [`mis2`] reads it.
struct LevelGraph<'s, 'g, T: Real> {
    sys: &'s SpringSystem<'g, T>,
    index: &'s [u32],
    lv: &'s Level,
    fine: bool,
    theta: T,
}

impl<T: Real> mis2::Adjacency for LevelGraph<'_, '_, T> {
    fn free(&self, i: usize) -> bool {
        !(self.fine && self.sys.is_fixed(i))
    }
    fn each(&self, i: usize, mut f: impl FnMut(usize)) {
        let (sys, index, lv) = (self.sys, self.index, self.lv);
        strong(sys, index, lv, self.fine, self.theta, i, |j| {
            if j != i {
                f(j);
            }
        });
    }
}

/// Swaps `v[a]` and `v[b]` when both exist.
#[inline]
fn swap_u32(v: &mut [u32], a: usize, b: usize) {
    if let (Some(&x), Some(&y)) = (v.get(a), v.get(b)) {
        if let Some(p) = v.get_mut(a) {
            *p = y;
        }
        if let Some(p) = v.get_mut(b) {
            *p = x;
        }
    }
}

/// In-place heapsort of a `u32` slice (no recursion, no panics, `O(n log n)`).
pub(crate) fn sort_u32(v: &mut [u32]) {
    let n = v.len();
    let sift = |v: &mut [u32], mut root: usize, end: usize| loop {
        let mut child = 2 * root + 1;
        if child >= end {
            break;
        }
        if child + 1 < end && v.get(child) < v.get(child + 1) {
            child += 1;
        }
        if v.get(root) < v.get(child) {
            swap_u32(v, root, child);
            root = child;
        } else {
            break;
        }
    };
    for start in (0..n / 2).rev() {
        sift(v, start, n);
    }
    for end in (1..n).rev() {
        swap_u32(v, 0, end);
        sift(v, 0, end);
    }
}

/// Builds level `l + 1`'s structure above `ic` in `work`. Returns the updated level `l`
/// (aggregates and prolongator), level `l + 1` and the new index cursor; `None` when level `l`
/// does not coarsen (no aggregate, no reduction, or the next level would not fit the budget).
/// `mis2`: aggregate by MIS-2 in this scratch instead of greedily.
#[allow(clippy::too_many_arguments)]
fn build_next<T: Real>(
    sys: &SpringSystem<'_, T>,
    theta: T,
    work: &mut [u32],
    ic: usize,
    l: usize,
    cur: Level,
    active: usize,
    mis2: Option<&mut [u64]>,
) -> Option<(Level, Level, usize)> {
    let fine = l == 0;
    let nl = cur.n;
    let (done, rest) = work.split_at_mut_checked(ic)?;
    let done: &[u32] = done;
    let (agg, r1) = rest.split_at_mut_checked(nl)?;
    let nc = match mis2 {
        None => aggregate(sys, done, &cur, fine, theta, agg),
        Some(scratch) => {
            let adj = LevelGraph {
                sys,
                index: done,
                lv: &cur,
                fine,
                theta,
            };
            mis2::hierarchy_aggregates(&adj, agg, NONE, scratch)
        }
    };
    if nc == 0 || nc >= active {
        return None;
    }
    let agg: &[u32] = agg;
    let (mid, marker) = r1.split_at_mut_checked(r1.len().checked_sub(nc)?)?;
    marker.fill(NONE);
    // Prolongator sparsity: row i holds the aggregates of i and of its neighbours.
    let mut p_nnz = 0usize;
    for i in 0..nl {
        let stamp = i as u32;
        if fine && sys.is_fixed(i) {
            continue;
        }
        let mut add = |j: usize| {
            if let Some(&a) = agg.get(j) {
                if let Some(m) = marker.get_mut(a as usize) {
                    if *m != stamp {
                        *m = stamp;
                        p_nnz += 1;
                    }
                }
            }
        };
        add(i);
        neighbours(sys, done, &cur, fine, i, add);
    }
    let p_len = (nl + 1).checked_add(p_nnz)?;
    let pt_len = (nc + 1).checked_add(p_nnz.checked_mul(2)?)?;
    let (p_offs, r2) = mid.split_at_mut_checked(nl + 1)?;
    let (p_cols, r3) = r2.split_at_mut_checked(p_nnz)?;
    let (pt_offs, r4) = r3.split_at_mut_checked(nc + 1)?;
    let (pt_rows, r5) = r4.split_at_mut_checked(p_nnz)?;
    let (pt_pos, r6) = r5.split_at_mut_checked(p_nnz)?;
    marker.fill(NONE);
    let mut pos = 0usize;
    for i in 0..nl {
        if let Some(o) = p_offs.get_mut(i) {
            *o = pos as u32;
        }
        let start = pos;
        if !(fine && sys.is_fixed(i)) {
            let stamp = i as u32;
            let mut add = |j: usize| {
                if let Some(&a) = agg.get(j) {
                    if let Some(m) = marker.get_mut(a as usize) {
                        if *m != stamp {
                            *m = stamp;
                            if let Some(c) = p_cols.get_mut(pos) {
                                *c = a;
                            }
                            pos += 1;
                        }
                    }
                }
            };
            add(i);
            neighbours(sys, done, &cur, fine, i, add);
        }
        sort_u32(p_cols.get_mut(start..pos).unwrap_or(&mut []));
    }
    if let Some(o) = p_offs.get_mut(nl) {
        *o = pos as u32;
    }
    // Transpose: counting sort by column, rows in increasing order.
    pt_offs.fill(0);
    for &c in p_cols.iter() {
        if let Some(o) = pt_offs.get_mut(c as usize + 1) {
            *o += 1;
        }
    }
    let mut run = 0u32;
    for o in pt_offs.iter_mut() {
        run += *o;
        *o = run;
    }
    // pt_offs[c + 1] now holds the end of column c; marker = insertion cursor per column.
    for (c, m) in marker.iter_mut().enumerate() {
        *m = pt_offs.get(c).copied().unwrap_or(0);
    }
    for i in 0..nl {
        let a = at(p_offs, i);
        let b = at(p_offs, i + 1);
        for q in a..b {
            let c = at(p_cols, q);
            if let Some(m) = marker.get_mut(c) {
                let k = *m as usize;
                *m += 1;
                if let Some(r) = pt_rows.get_mut(k) {
                    *r = i as u32;
                }
                if let Some(p) = pt_pos.get_mut(k) {
                    *p = q as u32;
                }
            }
        }
    }
    let p_offs: &[u32] = p_offs;
    let p_cols: &[u32] = p_cols;
    let pt_offs: &[u32] = pt_offs;
    let pt_rows: &[u32] = pt_rows;
    // Galerkin sparsity of Pᵀ A P: coarse row I reaches the prolongator rows of the fine
    // neighbours (and itself) of every fine row in column I.
    let galerkin_row = |big: usize, marker: &mut [u32], emit: &mut dyn FnMut(u32)| {
        let stamp = big as u32;
        if let Some(m) = marker.get_mut(big) {
            *m = stamp;
        }
        let a = at(pt_offs, big);
        let b = at(pt_offs, big + 1);
        for k in a..b {
            let i = at(pt_rows, k);
            let mut visit = |j: usize| {
                let s = at(p_offs, j);
                let e = at(p_offs, j + 1);
                for &c in p_cols.get(s..e).unwrap_or(&[]) {
                    if let Some(m) = marker.get_mut(c as usize) {
                        if *m != stamp {
                            *m = stamp;
                            emit(c);
                        }
                    }
                }
            };
            visit(i);
            neighbours(sys, done, &cur, fine, i, &mut visit);
        }
    };
    // One pass writes the rows straight into the rest of `work` (no counting pass first);
    // rows that would run past it mean the level does not fit the budget, as a count would.
    let (a_offs, a_cols) = r6.split_at_mut_checked(nc + 1)?;
    marker.fill(NONE);
    let mut pos = 0usize;
    for big in 0..nc {
        if let Some(o) = a_offs.get_mut(big) {
            *o = pos as u32;
        }
        let start = pos;
        galerkin_row(big, marker, &mut |c| {
            if let Some(x) = a_cols.get_mut(pos) {
                *x = c;
            }
            pos += 1;
        });
        if pos > a_cols.len() {
            return None;
        }
        sort_u32(a_cols.get_mut(start..pos).unwrap_or(&mut []));
    }
    if let Some(o) = a_offs.get_mut(nc) {
        *o = pos as u32;
    }
    let a_nnz = pos;
    let mut cur = cur;
    cur.agg = ic;
    cur.p_offs = ic + nl;
    cur.p_cols = cur.p_offs + nl + 1;
    cur.p_nnz = p_nnz;
    cur.pt_offs = ic + nl + p_len;
    cur.pt_rows = cur.pt_offs + nc + 1;
    cur.pt_pos = cur.pt_rows + p_nnz;
    let next = Level {
        n: nc,
        a_offs: ic + nl + p_len + pt_len,
        a_cols: ic + nl + p_len + pt_len + nc + 1,
        a_nnz,
        ..Level::default()
    };
    Some((cur, next, next.a_cols + a_nnz))
}

/// The symbolic pass (see [`AmgHierarchy::setup_len`](super::AmgHierarchy::setup_len)).
pub(crate) fn symbolic<T: Real>(
    sys: &SpringSystem<'_, T>,
    options: &AmgOptions<T>,
    work: &mut [u32],
) -> Result<Layout> {
    symbolic_with(sys, options, work, None)
}

/// [`symbolic`], aggregating every level by MIS-2 ([`mis2`]) when `mis2` holds
/// [`mis2::hierarchy_scratch_len`] words of scratch for the fine level.
pub(crate) fn symbolic_with<T: Real>(
    sys: &SpringSystem<'_, T>,
    options: &AmgOptions<T>,
    work: &mut [u32],
    mut mis2: Option<&mut [u64]>,
) -> Result<Layout> {
    options.check()?;
    let n = sys.node_count();
    let e = sys.graph().edge_count();
    let b = budget(n, e);
    // Indices, aggregate numbers and positions are stored in u32 with one flag bit spare.
    if n >= (JOINED as usize) - 2 || b >= JOINED as usize {
        return Err(Error::TooLarge {
            arg: "sys",
            value: n,
        });
    }
    let Some(work) = work.get_mut(..b) else {
        return Err(Error::BufferTooSmall {
            arg: "work",
            needed: b,
            actual: work.len(),
        });
    };
    let mut layout = Layout {
        levels: [Level::default(); AMG_MAX_LEVELS],
        count: 1,
        index_len: 0,
        values_len: 0,
        dense: 0,
        dense_n: 0,
        acc: 0,
        acc_len: 0,
        nodes: n,
        edges: e,
    };
    if let Some(l0) = layout.levels.get_mut(0) {
        *l0 = Level {
            n,
            ..Level::default()
        };
    }
    let free = sys.fixed().iter().filter(|&&m| m == 0).count();
    let mut ic = 0usize;
    let mut vc = n;
    let mut l = 0usize;
    loop {
        let cur = layout.level(l);
        let active = if l == 0 { free } else { cur.n };
        if l + 1 >= options.max_levels || (l > 0 && active <= options.max_coarse) || active == 0 {
            break;
        }
        let Some((cur, next, new_ic)) = build_next(
            sys,
            options.strength_theta,
            work,
            ic,
            l,
            cur,
            active,
            mis2.as_deref_mut(),
        ) else {
            break;
        };
        let mut cur = cur;
        cur.p_vals = vc;
        vc += cur.p_nnz;
        let mut next = next;
        next.diag = vc;
        vc += next.n;
        next.a_vals = vc;
        vc += next.a_nnz;
        layout.acc_len = layout.acc_len.max(next.n);
        if let Some(x) = layout.levels.get_mut(l) {
            *x = cur;
        }
        if let Some(x) = layout.levels.get_mut(l + 1) {
            *x = next;
        }
        layout.count = l + 2;
        ic = new_ic;
        l += 1;
    }
    let last = layout.level(layout.count - 1);
    if layout.count > 1 && last.n <= options.max_coarse {
        layout.dense = vc;
        layout.dense_n = last.n;
        vc += last.n * last.n;
    }
    layout.acc = vc;
    layout.index_len = ic;
    layout.values_len = vc + layout.acc_len;
    Ok(layout)
}

/// Gershgorin bound of `ρ(D⁻¹A)` over the active rows (0 when there is none).
fn spectral_bound<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    values: &[T],
    lv: &Level,
    fine: bool,
) -> T {
    let diag = seg(values, lv.diag, lv.n);
    let mut rho = T::ZERO;
    for (i, &d) in diag.iter().enumerate() {
        if fine && sys.is_fixed(i) {
            continue;
        }
        let mut s = d;
        entries(sys, index, values, lv, fine, i, |_, a| s += a.abs());
        rho = rho.max(s / d);
    }
    if rho.is_finite() {
        rho
    } else {
        T::ZERO
    }
}

/// The prolongator-smoothing (and Jacobi) weight `(4/3) / ρ` (0 when `ρ = 0`).
#[inline]
pub(crate) fn jacobi_weight<T: Real>(rho: T) -> T {
    if rho > T::ZERO {
        T::from_f64(4.0 / 3.0) / rho
    } else {
        T::ZERO
    }
}

/// Smoothing weights per level and step (see [`AmgSmoother`]).
pub(crate) fn smoothing_weights<T: Real>(
    rho: &[T; AMG_MAX_LEVELS],
    smoother: AmgSmoother,
    sweeps: usize,
) -> [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS] {
    let mut w = [[T::ZERO; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS];
    for (wl, &r) in w.iter_mut().zip(rho) {
        if r <= T::ZERO {
            continue;
        }
        match smoother {
            AmgSmoother::Jacobi => wl.fill(jacobi_weight(r)),
            AmgSmoother::Chebyshev => {
                let upper = r;
                let lower = r / T::from_f64(30.0);
                let mid = (upper + lower) * T::from_f64(0.5);
                let half = (upper - lower) * T::from_f64(0.5);
                let m = T::from_usize(sweeps.max(1));
                for (s, x) in wl.iter_mut().take(sweeps).enumerate() {
                    let angle = T::PI * (T::from_usize(2 * s + 1) / (T::TWO * m));
                    *x = T::ONE / (mid + half * angle.cos());
                }
            }
        }
    }
    w
}

/// The numeric pass: fills `values` for the structure in `index`; returns the per-level
/// Gershgorin bounds of `ρ(D⁻¹A)`.
pub(crate) fn numeric<T: Real>(
    sys: &SpringSystem<'_, T>,
    layout: &Layout,
    index: &[u32],
    values: &mut [T],
) -> Result<[T; AMG_MAX_LEVELS]> {
    let singular = Error::SingularSystem { iteration: 0 };
    let mut weights = [T::ZERO; AMG_MAX_LEVELS];
    for (i, d) in seg_mut(values, 0, sys.node_count()).iter_mut().enumerate() {
        *d = fine_diag(sys, i);
    }
    let (main, acc) = values.split_at_mut_checked(layout.acc).ok_or(singular)?;
    for l in 0..layout.count {
        let lv = layout.level(l);
        let fine = l == 0;
        let rho = spectral_bound(sys, index, main, &lv, fine);
        if let Some(x) = weights.get_mut(l) {
            *x = rho;
        }
        let w = jacobi_weight(rho);
        if l + 1 >= layout.count {
            break;
        }
        let next = layout.level(l + 1);
        let (lo, hi) = main.split_at_mut_checked(lv.p_vals).ok_or(singular)?;
        let lo: &[T] = lo;
        let diag = seg(lo, lv.diag, lv.n);
        let agg = seg(index, lv.agg, lv.n);
        let (pv, rest) = hi.split_at_mut_checked(lv.p_nnz).ok_or(singular)?;
        let nd_off = next.diag.saturating_sub(lv.p_vals + lv.p_nnz);
        let nv_off = next.a_vals.saturating_sub(lv.p_vals + lv.p_nnz);
        // The coarse diagonal's slots first hold each aggregate's tentative energy `tᵀ A t`.
        seg_mut(rest, nd_off, next.n).fill(T::ZERO);
        // P = (I − ω D⁻¹ A) T, row by row.
        for i in 0..lv.n {
            let (s, len) = csr_row(index, lv.p_offs, lv.p_cols, i);
            let cols = seg(index, s, len);
            for &c in cols {
                if let Some(x) = acc.get_mut(c as usize) {
                    *x = T::ZERO;
                }
            }
            let ai = agg.get(i).copied().unwrap_or(NONE);
            let di = diag.get(i).copied().unwrap_or(T::ONE);
            if let Some(x) = acc.get_mut(ai as usize) {
                *x += di;
            }
            entries(sys, index, lo, &lv, fine, i, |j, a| {
                let aj = agg.get(j).copied().unwrap_or(NONE);
                if let Some(x) = acc.get_mut(aj as usize) {
                    *x += a;
                }
            });
            let slot = nd_off.saturating_add(ai as usize);
            if let (Some(e), Some(&x)) = (rest.get_mut(slot), acc.get(ai as usize)) {
                *e += x;
            }
            let scale = w / di;
            let rel = s.saturating_sub(lv.p_cols);
            for (&c, p) in cols.iter().zip(seg_mut(pv, rel, len)) {
                let t = if c == ai { T::ONE } else { T::ZERO };
                *p = t - scale * acc.get(c as usize).copied().unwrap_or(T::ZERO);
            }
        }
        let pv: &[T] = pv;
        // Pᵀ A P, coarse row by coarse row, then exact symmetrisation.
        let p_row = |j: usize| {
            let (s, len) = csr_row(index, lv.p_offs, lv.p_cols, j);
            let rel = s.saturating_sub(lv.p_cols);
            (seg(index, s, len), seg(pv, rel, len))
        };
        for big in 0..next.n {
            let (s, len) = csr_row(index, next.a_offs, next.a_cols, big);
            let cols = seg(index, s, len);
            if let Some(x) = acc.get_mut(big) {
                *x = T::ZERO;
            }
            for &c in cols {
                if let Some(x) = acc.get_mut(c as usize) {
                    *x = T::ZERO;
                }
            }
            let a = at(index, lv.pt_offs + big);
            let b = at(index, lv.pt_offs + big + 1);
            for k in a..b {
                let i = at(index, lv.pt_rows + k);
                let pi = pv.get(at(index, lv.pt_pos + k)).copied().unwrap_or(T::ZERO);
                let mut spread = |j: usize, a: T| {
                    let v = pi * a;
                    let (pc, pvals) = p_row(j);
                    for (&c, &p) in pc.iter().zip(pvals) {
                        if let Some(x) = acc.get_mut(c as usize) {
                            *x += v * p;
                        }
                    }
                };
                spread(i, diag.get(i).copied().unwrap_or(T::ZERO));
                entries(sys, index, lo, &lv, fine, i, &mut spread);
            }
            if let Some(d) = rest.get_mut(nd_off + big) {
                *d = degenerate_mark(acc.get(big).copied().unwrap_or(T::ZERO), *d)?;
            }
            let rel = s.saturating_sub(next.a_cols);
            for (&c, v) in cols.iter().zip(seg_mut(rest, nv_off + rel, len)) {
                *v = acc.get(c as usize).copied().unwrap_or(T::ZERO);
            }
        }
        isolate_degenerate(index, &next, rest, nd_off, nv_off);
        let half = T::from_f64(0.5);
        for big in 0..next.n {
            let (s, len) = csr_row(index, next.a_offs, next.a_cols, big);
            for q in 0..len {
                let c = at(index, s + q);
                if c <= big {
                    continue;
                }
                let (s2, len2) = csr_row(index, next.a_offs, next.a_cols, c);
                let Ok(q2) = seg(index, s2, len2).binary_search(&(big as u32)) else {
                    return Err(singular);
                };
                let i1 = nv_off + (s - next.a_cols) + q;
                let i2 = nv_off + (s2 - next.a_cols) + q2;
                let x = rest.get(i1).copied().unwrap_or(T::ZERO);
                let y = rest.get(i2).copied().unwrap_or(T::ZERO);
                let m = (x + y) * half;
                if let Some(v) = rest.get_mut(i1) {
                    *v = m;
                }
                if let Some(v) = rest.get_mut(i2) {
                    *v = m;
                }
            }
        }
        for &d in seg(rest, nd_off, next.n) {
            if !(d > T::ZERO && d.is_finite()) {
                return Err(singular);
            }
        }
        if seg(rest, nv_off, next.a_nnz).iter().any(|v| !v.is_finite()) {
            return Err(singular);
        }
    }
    if layout.dense_n > 0 {
        let lv = layout.level(layout.count - 1);
        let (lo, dense) = main.split_at_mut_checked(layout.dense).ok_or(singular)?;
        cholesky(sys, index, lo, &lv, layout.dense_n, dense)?;
    }
    Ok(weights)
}

/// The coarse diagonal `d = pᵀ A p` of an aggregate whose tentative energy is `e = tᵀ A t`,
/// or `−e` when smoothing annihilated the column (`d ≤ √ε e`: the aggregate's indicator is, to
/// rounding, an eigenvector of `D⁻¹ A` for the eigenvalue `1/ω`, which small symmetric
/// structures with power-of-two springs hit exactly). A degenerate column adds nothing to the
/// coarse space but would make the coarse operator singular.
fn degenerate_mark<T: Real>(d: T, e: T) -> Result<T> {
    let kept = d > T::EPSILON.sqrt() * e; // false for NaN too
    if e > T::ZERO && e.is_finite() && !kept {
        Ok(-e)
    } else if d > T::ZERO && d.is_finite() {
        Ok(d)
    } else {
        Err(Error::SingularSystem { iteration: 0 })
    }
}

/// Decouples the coarse unknowns [`degenerate_mark`] marked: their rows and columns become zero
/// and their diagonal the tentative energy, so the coarse operator stays positive definite and
/// the V-cycle symmetric (the coarse correction then ignores that direction, as a
/// pseudo-inverse would). Unmarked operators are untouched, bit for bit.
fn isolate_degenerate<T: Real>(
    index: &[u32],
    next: &Level,
    rest: &mut [T],
    nd_off: usize,
    nv_off: usize,
) {
    let marked = |rest: &[T], i: usize| rest.get(nd_off + i).is_some_and(|&d| d < T::ZERO);
    if !(0..next.n).any(|i| marked(rest, i)) {
        return;
    }
    for big in 0..next.n {
        let (s, len) = csr_row(index, next.a_offs, next.a_cols, big);
        let row_marked = marked(rest, big);
        for q in 0..len {
            let c = at(index, s + q);
            if row_marked || marked(rest, c) {
                if let Some(v) = rest.get_mut(nv_off + s.saturating_sub(next.a_cols) + q) {
                    *v = T::ZERO;
                }
            }
        }
    }
    for d in seg_mut(rest, nd_off, next.n) {
        *d = d.abs();
    }
}

/// Assembles the coarsest operator densely (lower triangle, row-major `m × m`) and factors it
/// in place, `A = L Lᵀ`.
fn cholesky<T: Real>(
    sys: &SpringSystem<'_, T>,
    index: &[u32],
    values: &[T],
    lv: &Level,
    m: usize,
    dense: &mut [T],
) -> Result<()> {
    let singular = Error::SingularSystem { iteration: 0 };
    let dense = dense.get_mut(..m * m).ok_or(singular)?;
    dense.fill(T::ZERO);
    let diag = seg(values, lv.diag, lv.n);
    for r in 0..m {
        if let Some(x) = dense.get_mut(r * m + r) {
            *x = diag.get(r).copied().unwrap_or(T::ZERO);
        }
        entries(sys, index, values, lv, false, r, |c, v| {
            if c < r {
                if let Some(x) = dense.get_mut(r * m + c) {
                    *x = v;
                }
            }
        });
    }
    for j in 0..m {
        let ajj = dense.get(j * m + j).copied().unwrap_or(T::ZERO);
        let mut s = ajj;
        for k in 0..j {
            let x = dense.get(j * m + k).copied().unwrap_or(T::ZERO);
            s -= x * x;
        }
        if !(s > T::EPSILON * ajj && s.is_finite()) {
            return Err(singular);
        }
        let ljj = s.sqrt();
        if let Some(x) = dense.get_mut(j * m + j) {
            *x = ljj;
        }
        for i in j + 1..m {
            let mut s = dense.get(i * m + j).copied().unwrap_or(T::ZERO);
            for k in 0..j {
                let a = dense.get(i * m + k).copied().unwrap_or(T::ZERO);
                let b = dense.get(j * m + k).copied().unwrap_or(T::ZERO);
                s -= a * b;
            }
            if let Some(x) = dense.get_mut(i * m + j) {
                *x = s / ljj;
            }
        }
    }
    Ok(())
}
