//! The kernel's one preconditioned conjugate-gradient loop ([`pcg`]), over an [`Operator`]
//! (linear springs, angle springs, the sliding projection `P K P`, the rigidity probe) and a
//! [`Precondition`]er (none, Jacobi, node blocks, SSOR, the multigrid V-cycle, their
//! projections), with one stopping rule and one scratch layout.
//!
//! **Lanes.** A solve of `V`-component values runs `L` independent CG recurrences: `L = V`
//! (one `α`, `β` per component: the linear springs, whose components do not couple) or
//! `L = 1` (one for the whole field: the angle springs and sliding nodes couple them). A
//! lane's inner products are summed exactly ([`ExactSum`]): per component for `L = V`, each
//! node's `aᵢ · bᵢ` (rounded, in component order) for `L = 1`.
//!
//! **Stopping rule.** Each iteration's recurrence residual `Σ r²` is the estimate; when it and
//! the largest update meet [`SolveOptions`], the true residual of the iterate decides, and if
//! they disagree CG restarts from the true residual. An overflowing estimate asks the true
//! residual too. A lane whose `rᵀz` or curvature scale is exactly zero has converged and
//! stays put; non-positive curvature (`pᵀAp ≤ ε · max_i pᵢᵀAᵢᵢpᵢ`) is
//! [`Error::SingularSystem`]; a non-finite inner product is [`Error::Overflow`].
//!
//! **Scaling.** CG runs on a copy scaled by a power of two per component, `x_c · 2^−e_c`, so
//! its inner products stay near 1 whatever the scale of values and stiffness; the operator's
//! norms are those of the unscaled field.
//!
//! **Distribution.** Every row loop runs over the owned rows of a [`Collective`]; sums and
//! maxima are merged, fields shared. With [`Serial`](super::Serial) this compiles to the
//! serial loops. A [`Precondition`] that is node-local is fused into the update pass.
//!
//! **Scratch.** [`CG_VECTORS`] vectors of `n` items (iterate, residual, direction, and one
//! shared by `A p` and `M⁻¹ r`) in front of whatever the preconditioner keeps.
//!
//! **Adding a solve.** A new operator (elasticity, a distributed one) implements [`Operator`]
//! with its lanes; a new preconditioner [`Precondition`]; the solve calls [`solve_scaled`]
//! (or [`pcg`] on its own scaled copy, as the sliding solves do). All is monomorphised: no
//! `dyn`, no allocation, every access checked.

use core::ops::Range;

use super::distributed::{
    merged, merged_max, merged_one, merged_with, share_field, share_halo, Collective,
};
use super::norms::{pair_norms, scale_by, Norm, Pairs};
use super::system::{SolveOptions, SolveReport};
use crate::error::{Error, Result};
use crate::exact_sum::{ExactSum, Gather};
use crate::real::Real;
use crate::vector;

/// Vectors of `n` `[T; V]` items the CG loop itself needs: iterate, residual, direction, and
/// one shared by `A p` and the preconditioned residual.
pub(crate) const CG_VECTORS: usize = 4;

/// `[T; V]` scratch items of the CG vectors for `n` nodes ([`CG_VECTORS`]` · n`), `None` on
/// overflow.
pub(crate) const fn cg_len(n: usize) -> Option<usize> {
    n.checked_mul(CG_VECTORS)
}

/// A symmetric positive definite operator on the free nodes, matrix-free, with `L` lanes.
pub(crate) trait Operator<T: Real, const V: usize, const L: usize> {
    /// `(b − A x)_i` at node `i` (zero at a fixed node); `x` current at `i`'s neighbours.
    fn residual(&self, i: usize, x: &[[T; V]]) -> [T; V];
    /// `q = A p` over `rows` (zero at fixed nodes; `p` is zero there), adding each lane's
    /// `pᵀq` to `pq` and raising its curvature scale `max_i pᵢᵀ Aᵢᵢ pᵢ` in `dpp`.
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; V]],
        q: &mut [[T; V]],
        pq: &mut [ExactSum; L],
        dpp: &mut [T; L],
    );
    /// `(‖b − A x‖, ‖b‖)` of the field stored as `x_c · 2^−exps[c]`, unscaled, summed over
    /// the owned rows of `comm` and merged (`x` current on every node).
    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; V]],
        exps: &[i32; V],
        comm: &C,
    ) -> (Norm<T>, Norm<T>);
}

/// A symmetric positive definite preconditioner `z = M⁻¹ r`, zero at fixed nodes.
pub(crate) trait Precondition<T: Real, const V: usize> {
    /// `z_i` depends on `r_i` alone ([`node`](Self::node)): fused into the update pass.
    fn local(&self) -> bool;
    /// `z_i` of a node-local preconditioner (unused when not [`local`](Self::local)).
    fn node(&self, i: usize, r: [T; V]) -> [T; V];
    /// `z = M⁻¹ r` on (at least) the owned rows of `comm`; `r` current on them.
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; V]], z: &mut [[T; V]], comm: &C);
}

/// [`Operator::apply`] of a one-lane block operator, row by row: `row(i, p_i)` is
/// `Some(((A p)_i, p_iᵀ A_ii p_i))` at a free node and `None` at a fixed one (`q_i = 0`).
pub(crate) fn apply_block_rows<T: Real, const D: usize>(
    rows: Range<usize>,
    p: &[[T; D]],
    q: &mut [[T; D]],
    pq: &mut [ExactSum; 1],
    dpp: &mut [T; 1],
    row: impl Fn(usize, [T; D]) -> Option<([T; D], T)>,
) {
    let [dpp] = dpp;
    let (Some(qs), Some(ps)) = (q.get_mut(rows.clone()), p.get(rows.clone())) else {
        return;
    };
    let mut pq = Gather::lanes(pq);
    for (i, (qi, &pi)) in rows.zip(qs.iter_mut().zip(ps)) {
        let Some((acc, curvature)) = row(i, pi) else {
            *qi = [T::ZERO; D];
            continue;
        };
        *dpp = dpp.max(curvature);
        pq.push([vector::dot(pi, acc)]);
        *qi = acc;
    }
}

/// An operator whose diagonal node blocks `A_ii` can be solved node by node.
pub(crate) trait NodeSolve<T: Real, const V: usize> {
    /// `A_ii⁻¹ r` at a free node, zero at a fixed node (or where the block is singular).
    fn node_solve(&self, i: usize, r: [T; V]) -> [T; V];
}

/// The block-Jacobi preconditioner `z_i = A_ii⁻¹ r_i` of a [`NodeSolve`] operator: node-local.
pub(crate) struct NodeBlocks<'s, S>(pub(crate) &'s S);

impl<T: Real, const V: usize, S: NodeSolve<T, V>> Precondition<T, V> for NodeBlocks<'_, S> {
    fn local(&self) -> bool {
        true
    }
    #[inline]
    fn node(&self, i: usize, r: [T; V]) -> [T; V] {
        self.0.node_solve(i, r)
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; V]], z: &mut [[T; V]], comm: &C) {
        apply_local(self, r, z, comm);
    }
}

/// Applies a node-local preconditioner over the owned rows.
pub(crate) fn apply_local<T, const V: usize, M, C>(
    pre: &M,
    r: &[[T; V]],
    z: &mut [[T; V]],
    comm: &C,
) where
    T: Real,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    for range in comm.owned() {
        let (Some(zs), Some(rs)) = (z.get_mut(range.clone()), r.get(range.clone())) else {
            continue;
        };
        for ((i, z), &r) in range.clone().zip(zs).zip(rs) {
            *z = pre.node(i, r);
        }
    }
}

/// A node's terms of the lanes' `Σ aᵢ · bᵢ`: per component (`L = V`) or the node's dot
/// product in component order, rounded (`L = 1`).
#[inline(always)]
pub(crate) fn lane_terms<T: Real, const V: usize, const L: usize>(
    a: &[T; V],
    b: &[T; V],
) -> [T; L] {
    let mut t = [T::ZERO; L];
    if L == 1 {
        if let Some(t) = t.first_mut() {
            *t = vector::dot(*a, *b);
        }
    } else {
        for ((t, &a), &b) in t.iter_mut().zip(a).zip(b) {
            *t = a * b;
        }
    }
    t
}

/// The lane of component `c`.
#[inline]
const fn lane<const L: usize>(c: usize) -> usize {
    if L == 1 {
        0
    } else {
        c
    }
}

/// The four CG vectors ([`CG_VECTORS`]), carved from the front of a scratch slice.
pub(crate) struct Vectors<'s, T, const V: usize> {
    /// The scaled iterate.
    pub x: &'s mut [[T; V]],
    r: &'s mut [[T; V]],
    p: &'s mut [[T; V]],
    /// `A p`, then the preconditioned residual.
    w: &'s mut [[T; V]],
}

impl<'s, T, const V: usize> Vectors<'s, T, V> {
    /// Splits `cg_len(n)` items off the front of `scratch`; returns them and the rest, or
    /// `None` when `scratch` is shorter.
    pub(crate) fn split(scratch: &'s mut [[T; V]], n: usize) -> Option<(Self, &'s mut [[T; V]])> {
        let (x, rest) = scratch.split_at_mut_checked(n)?;
        let (r, rest) = rest.split_at_mut_checked(n)?;
        let (p, rest) = rest.split_at_mut_checked(n)?;
        let (w, rest) = rest.split_at_mut_checked(n)?;
        Some((Vectors { x, r, p, w }, rest))
    }
}

/// Per-component power-of-two exponents `e_c` for the scaled iterate `x_c · 2^−e_c`: brings
/// `max_i |x_ic|` (over all components when `joint`: their exponents must agree) to about
/// `1/√k_max`, so every product CG forms (`k x²` in `rᵀz`, `pᵀAp`) is near 1. Powers of two
/// scale exactly: the iterates are the unscaled ones times `2^−e_c`, bit for bit.
pub(crate) fn exponents<T: Real, const V: usize>(
    stiffness: &[T],
    x: &[[T; V]],
    joint: bool,
) -> [i32; V] {
    let kmax = stiffness.iter().fold(T::ZERO, |m, &k| m.max(k));
    exponents_from(kmax, component_max(x), joint)
}

/// `max_i |x_ic|` per component.
pub(crate) fn component_max<T: Real, const V: usize>(x: &[[T; V]]) -> [T; V] {
    let mut vmax = [T::ZERO; V];
    for xi in x {
        for (m, &v) in vmax.iter_mut().zip(xi) {
            *m = m.max(v.abs());
        }
    }
    vmax
}

/// [`exponents`] from the largest stiffness and the per-component `max |x|` (merged over the
/// processes first in a partitioned solve).
pub(crate) fn exponents_from<T: Real, const V: usize>(
    kmax: T,
    mut vmax: [T; V],
    joint: bool,
) -> [i32; V] {
    let ek = if kmax > T::ZERO {
        kmax.exponent() / 2
    } else {
        0
    };
    if joint {
        let all = vmax.iter().fold(T::ZERO, |m, &v| m.max(v));
        vmax = [all; V];
    }
    let limit = T::MAX.exponent() - 1;
    vmax.map(|m| {
        let ev = if m > T::ZERO { m.exponent() } else { 0 };
        (ev + ek).clamp(-limit, limit)
    })
}

/// Runs [`pcg`] on a copy of `values` scaled by `exps` (in `v.x`) and writes the free
/// nodes back (fixed values come back bit for bit: CG would turn a fixed −0.0 into +0.0,
/// and scaling could round a fixed subnormal). On error `values` is untouched.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_scaled<T, const V: usize, const L: usize, O, M, C>(
    op: &O,
    pre: &mut M,
    mut v: Vectors<'_, T, V>,
    values: &mut [[T; V]],
    exps: [i32; V],
    fixed: impl Fn(usize) -> bool,
    options: &SolveOptions<T>,
    comm: &C,
) -> Result<SolveReport<T>>
where
    T: Real,
    O: Operator<T, V, L>,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    scale_into(v.x, values, &exps.map(|e| T::pow2(-e)), |_| true);
    let report = pcg(op, pre, &mut v, &exps, options, comm)?;
    if report.converged && report.iterations == 0 {
        return Ok(report); // a solution already: untouched (no rounding of subnormals)
    }
    scale_into(values, v.x, &exps.map(|e| T::pow2(e)), |i| !fixed(i));
    Ok(report)
}

/// `out_i = from_i ⊙ f` at every node `i` where `at(i)`.
fn scale_into<T: Real, const V: usize>(
    out: &mut [[T; V]],
    from: &[[T; V]],
    f: &[T; V],
    at: impl Fn(usize) -> bool,
) {
    for (i, (o, v)) in out.iter_mut().zip(from).enumerate() {
        if at(i) {
            for ((o, &v), &f) in o.iter_mut().zip(v).zip(f) {
                *o = v * f;
            }
        }
    }
}

/// Preconditioned conjugate gradients on the scaled iterate `v.x` (component `c` stored as
/// `x_c · 2^−exps[c]`, current on every node) until the stopping rule of the module
/// documentation holds or `options.max_iterations` have run; `v.x` is current on every node on
/// return. The report's residual and largest update are unscaled.
///
/// # Errors
/// [`Error::SingularSystem`] on non-positive curvature, [`Error::Overflow`] when an inner
/// product is not finite.
pub(crate) fn pcg<T, const V: usize, const L: usize, O, M, C>(
    op: &O,
    pre: &mut M,
    v: &mut Vectors<'_, T, V>,
    exps: &[i32; V],
    options: &SolveOptions<T>,
    comm: &C,
) -> Result<SolveReport<T>>
where
    T: Real,
    O: Operator<T, V, L>,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    // The recurrence residual is summed at the largest component's scale.
    let top = exps.iter().copied().max().unwrap_or(0);
    let to_top = exps.map(|e| scale_by(T::ONE, e - top));
    let (r0, bnorm) = op.norms(v.x, exps, comm);
    let mut report = SolveReport::start(r0, bnorm, options);
    if report.converged {
        return Ok(report);
    }
    // One set of per-lane accumulators for every per-lane sum of an iteration (each is
    // rounded before the next begins): an accumulator (584 bytes on 32-bit targets, 1,096 on 64-bit hosts) a lane matters on a small stack.
    let mut sums = [ExactSum::new(); L];
    let local = pre.local();
    let mut rz = restart(op, pre, v, &mut sums, comm);
    let mut checked = true;
    while report.iterations < options.max_iterations {
        report.iterations += 1;
        let alpha = step_length(op, v, &rz, &mut sums, report.iterations, comm)?;
        let (max_update, mut rr) = update(pre, v, &alpha, &to_top, &mut sums, comm);
        report.max_update = max_update
            .iter()
            .zip(exps)
            .fold(T::ZERO, |m, (&u, &e)| m.max(scale_by(u, e)));
        let (rr, mut rz_new) = if local {
            merged_with(comm, &mut rr, &mut sums)
        } else {
            (merged_one(comm, &mut rr), [T::ZERO; L])
        };
        checked = false;
        // An overflowing recurrence sum cannot say "converged": ask the true residual.
        let estimate_ok = rr.is_finite();
        let estimate = Norm::from_sum(rr, top).relative_to(bnorm);
        if !estimate_ok || options.met(estimate, report.max_update) {
            share_halo(comm, v.x);
            let (rt, _) = op.norms(v.x, exps, comm);
            report.residual = rt.relative_to(bnorm);
            checked = true;
            if options.met(report.residual, report.max_update) {
                report.converged = true;
                break;
            }
            if estimate_ok {
                // Recurrence and true residual disagree: restart from the true residual.
                rz = restart(op, pre, v, &mut sums, comm);
                continue;
            }
        }
        if !local {
            pre.apply(v.r, v.w, comm);
            rz_new = owned_dots(v.r, v.w, &mut sums, comm);
        }
        new_direction(v, &rz_new, &rz, comm);
        rz = rz_new;
    }
    share_field(comm, v.x);
    if !checked {
        let (rt, _) = op.norms(v.x, exps, comm);
        report.residual = rt.relative_to(bnorm);
    }
    Ok(report)
}

/// (Re)start: `r = b − A x`, `z = M⁻¹ r`, `p = z` on the owned rows (`x` current
/// everywhere), `p` shared; returns the lanes' `rᵀz`.
fn restart<T, const V: usize, const L: usize, O, M, C>(
    op: &O,
    pre: &mut M,
    v: &mut Vectors<'_, T, V>,
    sums: &mut [ExactSum; L],
    comm: &C,
) -> [T; L]
where
    T: Real,
    O: Operator<T, V, L>,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    let x: &[[T; V]] = v.x;
    for i in comm.owned().iter().flat_map(|r| r.clone()) {
        if let Some(r) = v.r.get_mut(i) {
            *r = op.residual(i, x);
        }
    }
    if pre.local() {
        apply_local(pre, v.r, v.w, comm);
    } else {
        pre.apply(v.r, v.w, comm);
    }
    for range in comm.owned() {
        if let (Some(p), Some(w)) = (v.p.get_mut(range.clone()), v.w.get(range.clone())) {
            for (p, &z) in p.iter_mut().zip(w) {
                *p = z;
            }
        }
    }
    share_halo(comm, v.p);
    owned_dots(v.r, v.w, sums, comm)
}

/// The lanes' `Σ aᵢ · bᵢ` over the owned rows, merged and rounded.
fn owned_dots<T, const V: usize, const L: usize, C>(
    a: &[[T; V]],
    b: &[[T; V]],
    sums: &mut [ExactSum; L],
    comm: &C,
) -> [T; L]
where
    T: Real,
    C: Collective<T> + ?Sized,
{
    sums.iter_mut().for_each(|s| *s = ExactSum::new());
    let mut terms = Gather::lanes(sums);
    for range in comm.owned() {
        let (Some(a), Some(b)) = (a.get(range.clone()), b.get(range.clone())) else {
            continue;
        };
        for (a, b) in a.iter().zip(b) {
            terms.push(lane_terms(a, b));
        }
    }
    drop(terms);
    merged(comm, sums)
}

/// `q = A p` (into `w`) and each lane's step `α = rᵀz / pᵀq`: zero for a lane that has
/// converged exactly (`rᵀz` or its curvature scale zero).
///
/// # Errors
/// [`Error::Overflow`] for a non-finite inner product, [`Error::SingularSystem`] when
/// `pᵀq ≤ ε · max_i pᵢᵀAᵢᵢpᵢ`.
fn step_length<T, const V: usize, const L: usize, O, C>(
    op: &O,
    v: &mut Vectors<'_, T, V>,
    rz: &[T; L],
    sums: &mut [ExactSum; L],
    iteration: usize,
    comm: &C,
) -> Result<[T; L]>
where
    T: Real,
    O: Operator<T, V, L>,
    C: Collective<T> + ?Sized,
{
    let mut dpp = [T::ZERO; L];
    sums.iter_mut().for_each(|s| *s = ExactSum::new());
    for range in comm.owned() {
        op.apply(range.clone(), v.p, v.w, sums, &mut dpp);
    }
    let dpp = merged_max(comm, dpp);
    let pq = merged(comm, sums);
    let mut alpha = [T::ZERO; L];
    for (((a, &pq), &dpp), &rz) in alpha.iter_mut().zip(&pq).zip(&dpp).zip(rz) {
        if !(pq.is_finite() && rz.is_finite() && dpp.is_finite()) {
            return Err(Error::Overflow { arg: "values" });
        }
        if dpp == T::ZERO || rz == T::ZERO {
            continue; // this lane has converged exactly
        }
        if pq <= T::EPSILON * dpp {
            return Err(Error::SingularSystem { iteration });
        }
        *a = rz / pq;
    }
    Ok(alpha)
}

/// One pass over the owned rows: `x += α p`, `r −= α q`, the largest update per component
/// and the recurrence residual `Σ (r · to_top)²` (returned unmerged), and for a node-local
/// preconditioner `z = M⁻¹ r` (into `w`, over `q`) with the lanes' `rᵀz` in `sums`.
fn update<T, const V: usize, const L: usize, M, C>(
    pre: &M,
    v: &mut Vectors<'_, T, V>,
    alpha: &[T; L],
    to_top: &[T; V],
    sums: &mut [ExactSum; L],
    comm: &C,
) -> ([T; V], ExactSum)
where
    T: Real,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    let mut a = [T::ZERO; V];
    for (c, a) in a.iter_mut().enumerate() {
        *a = alpha.get(lane::<L>(c)).copied().unwrap_or(T::ZERO);
    }
    let mut max_update = [T::ZERO; V];
    let mut rr = ExactSum::new();
    let local = pre.local();
    if local {
        sums.iter_mut().for_each(|s| *s = ExactSum::new());
    }
    let (mut rr_terms, mut rz_terms) = (Gather::<1>::one(&mut rr), Gather::lanes(sums));
    for range in comm.owned() {
        let rows = range.clone();
        let (Some(x), Some(r), Some(p), Some(w)) = (
            v.x.get_mut(rows.clone()),
            v.r.get_mut(rows.clone()),
            v.p.get(rows.clone()),
            v.w.get_mut(rows.clone()),
        ) else {
            continue;
        };
        for (i, (((x, r), &p), w)) in rows.zip(x.iter_mut().zip(r.iter_mut()).zip(p).zip(w)) {
            for ((((((x, r), &p), &q), &a), m), &g) in x
                .iter_mut()
                .zip(r.iter_mut())
                .zip(&p)
                .zip(w.iter())
                .zip(&a)
                .zip(max_update.iter_mut())
                .zip(to_top)
            {
                let dx = a * p;
                *x += dx;
                *r -= a * q;
                *m = m.max(dx.abs());
                let rg = *r * g;
                // One term a push: no row array, which a Cortex-M's frame would hold.
                rr_terms.push([rg * rg]);
            }
            if local {
                *w = pre.node(i, *r);
                rz_terms.push(lane_terms(r, w));
            }
        }
    }
    drop((rr_terms, rz_terms));
    (merged_max(comm, max_update), rr)
}

/// `β = rᵀz_new / rᵀz_old` per lane (zero where the old one is) and `p = z + β p` on the
/// owned rows, then shared.
fn new_direction<T, const V: usize, const L: usize, C>(
    v: &mut Vectors<'_, T, V>,
    rz_new: &[T; L],
    rz: &[T; L],
    comm: &C,
) where
    T: Real,
    C: Collective<T> + ?Sized,
{
    let mut beta = [T::ZERO; V];
    for (c, b) in beta.iter_mut().enumerate() {
        let l = lane::<L>(c);
        let (new, old) = (
            rz_new.get(l).copied().unwrap_or(T::ZERO),
            rz.get(l).copied().unwrap_or(T::ZERO),
        );
        if old != T::ZERO {
            *b = new / old;
        }
    }
    for range in comm.owned() {
        let (Some(p), Some(w)) = (v.p.get_mut(range.clone()), v.w.get(range.clone())) else {
            continue;
        };
        for (p, &z) in p.iter_mut().zip(w) {
            for ((p, &z), &b) in p.iter_mut().zip(&z).zip(&beta) {
                *p = z + b * *p;
            }
        }
    }
    share_halo(comm, v.p);
}

/// An [`Operator`] whose own right-hand side (the fixed nodes' pull) is replaced by an
/// arbitrary one `f`: `(f − A x)_i` at a free node. The inner operator's residual must be
/// `−(A x)_i` when `x` is zero at every fixed node (true of every operator here: the pull is
/// the only affine part), and [`solve_rhs`] keeps `x` zero there. `f` is the caller's,
/// unscaled; `scale` (`2^−e_c`) brings it to the scaled iterate's units on the fly (exact: a
/// power of two), so no copy of it is needed. The adjoint solves use it.
struct WithRhs<'s, T, O, F, const V: usize> {
    op: &'s O,
    rhs: &'s [[T; V]],
    scale: [T; V],
    fixed: F,
    per_node: bool,
}

impl<T: Real, O, F: Fn(usize) -> bool, const V: usize> WithRhs<'_, T, O, F, V> {
    /// `f_i` in the scaled units, zero at a fixed node.
    #[inline]
    fn rhs_at(&self, i: usize) -> [T; V] {
        match self.rhs.get(i) {
            Some(f) if !(self.fixed)(i) => {
                let mut out = *f;
                for (o, &s) in out.iter_mut().zip(&self.scale) {
                    *o *= s;
                }
                out
            }
            _ => [T::ZERO; V],
        }
    }
}

impl<T, O, F, const V: usize, const L: usize> Operator<T, V, L> for WithRhs<'_, T, O, F, V>
where
    T: Real,
    O: Operator<T, V, L>,
    F: Fn(usize) -> bool,
{
    #[inline]
    fn residual(&self, i: usize, x: &[[T; V]]) -> [T; V] {
        vector::add(self.rhs_at(i), self.op.residual(i, x))
    }

    #[inline]
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; V]],
        q: &mut [[T; V]],
        pq: &mut [ExactSum; L],
        dpp: &mut [T; L],
    ) {
        self.op.apply(rows, p, q, pq, dpp);
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; V]],
        exps: &[i32; V],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        let top = exps.iter().copied().max().unwrap_or(0);
        let g = exps.map(|e| scale_by(T::ONE, e - top));
        let pairs = RhsPairs {
            op: self,
            rows: comm.owned(),
            x,
            lanes: core::marker::PhantomData::<[(); L]>,
        };
        let (r, b) = pair_norms(&pairs, &g, self.per_node, comm);
        (r.shifted(top), b.shifted(top))
    }
}

/// The residual pairs `(f − A x, f)` of [`WithRhs`] over the free nodes of some rows.
struct RhsPairs<'s, 'x, T, O, F, const V: usize, const L: usize> {
    op: &'s WithRhs<'s, T, O, F, V>,
    rows: &'s [Range<usize>],
    x: &'x [[T; V]],
    lanes: core::marker::PhantomData<[(); L]>,
}

impl<T, O, F, const V: usize, const L: usize> Pairs<T, V> for RhsPairs<'_, '_, T, O, F, V, L>
where
    T: Real,
    O: Operator<T, V, L>,
    F: Fn(usize) -> bool,
{
    fn each<G: FnMut(&[T; V], &[T; V])>(&self, mut f: G) {
        for i in self.rows.iter().flat_map(|r| r.clone()) {
            if !(self.op.fixed)(i) {
                let b = self.op.rhs_at(i);
                let r = vector::add(b, self.op.op.residual(i, self.x));
                f(&r, &b);
            }
        }
    }
}

/// How [`solve_rhs`] scales and measures: the largest stiffness entry `kmax` (sets the
/// scale), `joint` (one exponent for every component: operators that couple them) and
/// `per_node` (each node's `|r_i|²` one term of the norms, as the coupled operators sum).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RhsLayout<T> {
    pub kmax: T,
    pub joint: bool,
    pub per_node: bool,
}

/// Solves `A x = f` on the free nodes for an arbitrary right-hand side `f` (`rhs`, one item
/// per node, ignored at fixed nodes) from a zero initial guess, with the same [`pcg`] loop,
/// stopping rule and preconditioner as the operator's own solves; writes `x` into `out`
/// (zero at fixed nodes). The iterate is scaled by `2^−e_c` with `e_c` chosen so that
/// `x ≈ f / kmax` lands near `1/√kmax` (as [`exponents`] does for the Dirichlet solves).
/// `rhs` must be finite (the caller checks); `out` is written only on `Ok`.
///
/// # Errors
/// Those of [`pcg`].
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_rhs<T, const V: usize, const L: usize, O, M, C>(
    op: &O,
    pre: &mut M,
    mut v: Vectors<'_, T, V>,
    rhs: &[[T; V]],
    out: &mut [[T; V]],
    layout: RhsLayout<T>,
    fixed: impl Fn(usize) -> bool + Copy,
    options: &SolveOptions<T>,
    comm: &C,
) -> Result<SolveReport<T>>
where
    T: Real,
    O: Operator<T, V, L>,
    M: Precondition<T, V>,
    C: Collective<T> + ?Sized,
{
    let ek = if layout.kmax > T::ZERO {
        layout.kmax.exponent() / 2
    } else {
        0
    };
    let limit = T::MAX.exponent() - 1;
    // `exponents` gives e_f + ek for the field f; the solution is about f / kmax: e_f − ek.
    let exps = exponents(&[layout.kmax], rhs, layout.joint)
        .map(|e| e.saturating_sub(ek).saturating_sub(ek).clamp(-limit, limit));
    v.x.iter_mut().for_each(|x| *x = [T::ZERO; V]);
    let wrapped = WithRhs {
        op,
        rhs,
        scale: exps.map(|e| T::pow2(-e)),
        fixed,
        per_node: layout.per_node,
    };
    let report = pcg(&wrapped, pre, &mut v, &exps, options, comm)?;
    for (i, (o, x)) in out.iter_mut().zip(v.x.iter()).enumerate() {
        *o = if fixed(i) {
            [T::ZERO; V]
        } else {
            let mut y = *x;
            for (y, &e) in y.iter_mut().zip(&exps) {
                *y = scale_by(*y, e);
            }
            y
        };
    }
    Ok(report)
}
