//! Tangent and adjoint of the quaternion deformation with the fast, tree-based
//! inverse-distance propagation ([`deform_idw_fast`](crate::quaternion::deform_idw_fast)).
//!
//! At a field point the forward computes `Δ = Σ_k w̃_k Δ_k / W̃` and `Q = S / |S|`, `S = Σ_k
//! ±w̃_k Q_k`, where `w̃_k` is the exact weight for nodes weighted individually and the Taylor
//! weight `w_C (1 + a·δ_k)` (`a = p (x − c) / d²`, `δ_k = y_k − c`) for the members of a
//! cluster used as a whole. The weights depend on the undeformed geometry and on which
//! clusters are opened; the opening also depends on the rotations (the cone test), a
//! piecewise-constant choice held at the linearisation point like the hemisphere signs. Then
//! the propagation is linear in `(Δ_k, Q_k)`:
//!
//! - **tangent**: the same traversal (the forward's own query, replayed on the base tree)
//!   applied to `(δΔ_k, ±δQ_k)`: a used cluster adds `n_C w_C (δv̄_C + δMᵀ a)` from cluster
//!   moments of the perturbation built on the base tree; then `δQ = (I − Q Qᵀ) δS / |S|`,
//!   `δR = δΔ + M(Q, x − o) δQ`;
//! - **adjoint**: the transposed traversal. With `ū = (w / W̃, ±S̄)`, `S̄ = (I − Q Qᵀ) M(Q, x −
//!   o)ᵀ w / |S|`, a leaf adds `w̃_k ū` to its node; a used cluster accumulates `n_C w_C ū` and
//!   `n_C w_C a ⊗ ū`; one downward pass then gives each member `(A_C + δ_k · B_C) / n_C`,
//!   `O(B log B)`. The query runs twice per point (the base sums must be known before the
//!   scatter), from the same hint, so the second replays the first's decisions.
//!
//! Points the forward computes by the exact method's robust path are linearised by the exact
//! method's point functions.

use super::boundary::{add_to, get3, zero};
use super::field::{accumulate, adjoint_at, tangent_at, Field};
use super::lin::axpy;
use super::{
    boundary_adjoint, boundary_adjoint_check, boundary_tangent, deform_idw_sensitivity_scratch_len,
    prepare,
};
use crate::check;
use crate::error::Result;
use crate::quat::Quat;
use crate::quaternion::idw_fast::{
    check_options_and_buffers, children, get_n, grow, leaf_len, moments, node_len, nodes_len, Hint,
    Layout, Stack, Tree, Visit,
};
use crate::quaternion::{
    check_exponent, lift, load, take, translation, BoundaryMotion, IdwFastOptions, IdwFastReport,
    Pts, IDW_FAST_LEAF,
};
use crate::real::Real;
use crate::vector::{scale, sub};

/// Length of the `scratch` slice [`deform_idw_fast_tangent`] and [`deform_idw_fast_adjoint`]
/// need: the boundary stage's `max(N, 32 B)` plus one tree-node record per node of the tree
/// (`usize::MAX` on overflow). `index` and `tree` are those of
/// [`deform_idw_fast`](crate::quaternion::deform_idw_fast).
#[inline]
pub fn deform_idw_fast_sensitivity_scratch_len<const D: usize>(
    node_count: usize,
    boundary_len: usize,
) -> usize {
    deform_idw_sensitivity_scratch_len::<D>(node_count, boundary_len)
        .saturating_add(nodes_len::<D>(boundary_len))
}

/// Validates (as [`deform_idw_fast`](crate::quaternion::deform_idw_fast) does, and the mode's
/// `io`: the input, its name — `"direction"`, one per boundary point, or `"weights"`, one per
/// mesh point — and the length of `out`) and computes the boundary rotations into `scratch`
/// (the layout of the exact IDW's sensitivities), then fills the boundary entries of
/// `translations` and `rotations` as the forward does. Returns the origin.
#[allow(clippy::too_many_arguments)]
fn validate<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    options: &IdwFastOptions<T>,
    io: (&[[T; D]], &'static str, usize),
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    buffers: (usize, usize),
) -> Result<[T; D]> {
    let (n, b) = (points.len(), motion.nodes.len());
    let (input, arg, out_len) = io;
    let (input_len, out_needed) = if arg == "direction" { (b, n) } else { (n, b) };
    check::len(arg, input.len(), input_len)?;
    check::len("out", out_len, out_needed)?;
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    let needed = deform_idw_fast_sensitivity_scratch_len::<D>(n, b);
    check::buffer("scratch", scratch.len(), needed)?;
    let origin = prepare(points, motion, scratch, |_| {
        check_exponent(exponent)?;
        check_options_and_buffers::<T, D>(options, b, buffers.0, buffers.1, "tree")
    })?;
    check::finite_items(arg, input)?;
    let u = Pts::mapped(points, motion.nodes);
    for (k, (&i, &dk)) in motion.nodes.iter().zip(motion.deformed).enumerate() {
        let q = Quat::from_array(load(scratch, k));
        if let Some(r) = rotations.get_mut(i as usize) {
            *r = q;
        }
        if let Some(t) = translations.get_mut(i as usize) {
            *t = translation(
                origin,
                u.get(k),
                dk,
                q.normalize().unwrap_or(Quat::identity()),
            );
        }
    }
    Ok(origin)
}

/// The parts of the validated `scratch`: `Q_k`, `δQ_k`/`Q̄_k`, `δΔ_k`/`Δ̄_k` (per boundary
/// position), the boundary stage's workspace, the cluster records.
type Split<'s, T> = (
    &'s mut [T],
    &'s mut [T],
    &'s mut [T],
    &'s mut [T],
    &'s mut [T],
);

/// Splits the validated `scratch` for `n` mesh and `b` boundary points.
fn split<T: Real, const D: usize>(scratch: &mut [T], n: usize, b: usize) -> Split<'_, T> {
    let (bnd, cl) = take(scratch, deform_idw_sensitivity_scratch_len::<D>(n, b));
    let (qs, rest) = take(bnd, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let (dt, work) = take(rest, 3 * b);
    (qs, dq, dt, work, cl)
}

/// The tree as grown by [`grow`]: `index` (tree order), node records, leaves.
type Grown<'s, T> = (&'s [u32], &'s [T], &'s [T]);

/// Calls `each(base, start, members)` for every tree node that holds more than one boundary
/// node (only those can be used as clusters), `base` its record's offset, `start` the tree
/// position of its first member.
fn for_clusters<const D: usize>(index: &[u32], mut each: impl FnMut(usize, usize, &[u32])) {
    let mut stack = Stack::new((0, 0, index.len()));
    while let Some((node, s, e)) = stack.pop() {
        if e - s > 1 {
            each(
                node.saturating_mul(node_len(D)),
                s,
                index.get(s..e).unwrap_or(&[]),
            );
        }
        if e - s > IDW_FAST_LEAF {
            let [l, r] = children(node, s, e);
            stack.push(r);
            stack.push(l);
        }
    }
}

/// `±1`: the sign that aligns rotation `q` with `r` (as the tree aligns to a reference).
#[inline]
fn sign<T: Real>(q: [T; 4], r: [T; 4]) -> T {
    if Quat::from_array(r).dot(Quat::from_array(q)) < T::ZERO {
        -T::ONE
    } else {
        T::ONE
    }
}

/// The cluster records of the perturbation `(δΔ, ±δQ)` into `cl` (the layout of the base
/// records' value moments), with the base tree's centroids and reference rotations (the
/// alignment signs are the base rotations').
fn perturbation_moments<T: Real, const D: usize>(
    grown: Grown<'_, T>,
    points: &[[T; D]],
    boundary: &[u32],
    qs: &[T],
    dq: &[T],
    dt: &[T],
    cl: &mut [T],
) {
    let (index, nodes, _) = grown;
    let pos_point = |pos: u32| {
        boundary
            .get(pos as usize)
            .and_then(|&m| points.get(m as usize))
            .copied()
            .unwrap_or([T::ZERO; D])
    };
    for_clusters::<D>(index, |base, _, members| {
        let c: [T; D] = get_n(nodes, base + Layout::<D>::C);
        let qref: [T; 4] = get_n(nodes, base + Layout::<D>::QR);
        let value = |pos: u32| {
            let k = pos as usize;
            let t: [T; 3] = load(dt, k);
            let sg = sign(load(qs, k), qref);
            (first_d(t), load::<T, 4>(dq, k).map(|x| sg * x))
        };
        let nt = T::from_usize(members.len().max(1));
        let rec = cl
            .get_mut(base..base.saturating_add(node_len(D)))
            .unwrap_or_default();
        moments(members, c, nt, pos_point, value, rec);
    });
}

/// The first `D` of three components.
#[inline]
fn first_d<T: Real, const D: usize>(v: [T; 3]) -> [T; D] {
    core::array::from_fn(|i| v.get(i).copied().unwrap_or(T::ZERO))
}

/// `Σ_j a_j M_j` over the first-moment rows of the record at `base` (`D + 4` lanes, padded
/// to 7).
#[inline]
fn moment_sum<T: Real, const D: usize>(cl: &[T], base: usize, a: [T; D]) -> [T; 7] {
    let mut corr = [T::ZERO; 7];
    for (j, &aj) in a.iter().enumerate() {
        let row = cl
            .get(base + Layout::<D>::M + j * (D + 4)..base + Layout::<D>::M + (j + 1) * (D + 4))
            .unwrap_or(&[]);
        for (cv, mv) in corr.iter_mut().zip(row) {
            *cv += aj * *mv;
        }
    }
    corr
}

/// The sums of one query of the tangent: base `S` and `W̃` (the forward's), `δS`, `Σ w̃ δΔ`,
/// and which path gave the value.
struct TangentSums<T> {
    s: [T; 4],
    w: T,
    ds: [T; 4],
    dt: [T; 3],
    robust: bool,
    coincident: Option<usize>,
}

impl<T: Real> TangentSums<T> {
    fn new() -> Self {
        TangentSums {
            s: [T::ZERO; 4],
            w: T::ONE,
            ds: [T::ZERO; 4],
            dt: [T::ZERO; 3],
            robust: false,
            coincident: None,
        }
    }

    /// Follows the query's decisions on the perturbation (`cl`: its cluster records; `dq`,
    /// `dt` per boundary position).
    fn visit<const D: usize>(&mut self, v: Visit<T, D>, index: &[u32], p: (&[T], &[T], &[T])) {
        let (cl, dq, dt) = p;
        match v {
            Visit::Pass => {
                self.ds = [T::ZERO; 4];
                self.dt = [T::ZERO; 3];
            }
            Visit::Cluster { node, nw, a, neg } => {
                let base = node.saturating_mul(node_len(D));
                let corr = moment_sum(cl, base, a);
                let tm: [T; D] = get_n(cl, base + Layout::<D>::T);
                let qm: [T; 4] = get_n(cl, base + Layout::<D>::QS);
                for ((acc, m), c) in self.dt.iter_mut().zip(tm).zip(corr) {
                    *acc += nw * (m + c);
                }
                let sw = if neg { -nw } else { nw };
                for ((acc, m), c) in self.ds.iter_mut().zip(qm).zip(corr.iter().skip(D)) {
                    *acc += sw * (m + *c);
                }
            }
            Visit::Leaf { k, w, neg } => {
                let pos = index.get(k).copied().unwrap_or(0) as usize;
                axpy(&mut self.dt, w, load(dt, pos));
                axpy(&mut self.ds, if neg { -w } else { w }, load(dq, pos));
            }
            Visit::Totals { q, w } => {
                self.s = q;
                self.w = w;
            }
            Visit::Robust => self.robust = true,
            Visit::Coincident { pos } => self.coincident = Some(pos),
        }
    }
}

/// Tangent of [`deform_idw_fast`](crate::quaternion::deform_idw_fast): the first-order change
/// `out = δR` of every mesh point for the change `direction = δd` of the deformed boundary
/// positions, the undeformed `points` held, with the forward's cluster decisions held (see the
/// module documentation). Boundary nodes get `δd` exactly. `translations`, `rotations`,
/// `index` and `tree` are workspaces as for the deformation; `scratch` needs
/// [`deform_idw_fast_sensitivity_scratch_len`] entries.
///
/// # Errors
/// Those of [`deform_idw_fast`](crate::quaternion::deform_idw_fast) for the points, motion,
/// exponent, options and buffers, and those of [`deform_idw_tangent`](super::deform_idw_tangent)
/// for `direction` and `out`. On error `out` is unchanged.
#[allow(clippy::too_many_arguments)]
pub fn deform_idw_fast_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    options: &IdwFastOptions<T>,
    direction: &[[T; D]],
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    index: &mut [u32],
    tree: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let (n, b) = (points.len(), motion.nodes.len());
    let (sizes, io) = (
        (index.len(), tree.len()),
        (direction, "direction", out.len()),
    );
    let (tr, rot) = (translations, rotations);
    let origin = validate(
        points, motion, exponent, options, io, tr, rot, scratch, sizes,
    )?;
    boundary_tangent(points, motion, origin, direction, scratch)?;
    let (translations, rotations) = (&*tr, &*rot);
    let (qs, dq, dt, _, cl) = split::<T, D>(scratch, n, b);
    let grown = grow(points, motion.nodes, translations, rotations, index, tree);
    perturbation_moments(grown, points, motion.nodes, qs, dq, dt, cl);
    let t = Tree::new(
        points,
        motion.nodes,
        exponent,
        grown,
        translations,
        rotations,
    );
    let field = Field {
        points,
        boundary: motion.nodes,
        exponent,
        origin,
        qs,
    };
    let (mut hint, mut report) = (Hint::new(), IdwFastReport::default());
    for (i, (x, o)) in points.iter().zip(out.iter_mut()).enumerate() {
        let mut sums = TangentSums::new();
        let mut visit = |v| sums.visit(v, grown.0, (&*cl, &*dq, &*dt));
        if t.point(i, *x, options, &mut hint, &mut report, &mut visit)
            .is_none()
        {
            continue;
        }
        *o = if sums.robust {
            tangent_at(&field, dq, dt, i, *x).unwrap_or([T::ZERO; D])
        } else if let Some(pos) = sums.coincident {
            let q = load(qs, pos);
            field.update_tangent(*x, q, Quat::from_array(q), load(dq, pos), load(dt, pos))
        } else {
            let dtv = scale(sums.dt, T::ONE / sums.w);
            field.update_tangent(*x, sums.s, Quat::identity(), sums.ds, dtv)
        };
    }
    for (&i, &dd) in motion.nodes.iter().zip(direction) {
        if let Some(o) = out.get_mut(i as usize) {
            *o = dd;
        }
    }
    Ok(())
}

/// What the first query of the adjoint learns: the base sums, the number of passes and which
/// path gave the value.
#[derive(Default)]
struct Record<T> {
    s: [T; 4],
    w: T,
    passes: usize,
    robust: bool,
    coincident: Option<usize>,
}

impl<T: Real> Record<T> {
    fn visit<const D: usize>(&mut self, v: Visit<T, D>) {
        match v {
            Visit::Pass => self.passes += 1,
            Visit::Totals { q, w } => {
                self.s = q;
                self.w = w;
            }
            Visit::Robust => self.robust = true,
            Visit::Coincident { pos } => self.coincident = Some(pos),
            Visit::Cluster { .. } | Visit::Leaf { .. } => {}
        }
    }
}

/// The transposed query: in the last pass (`last`), scatters `ū = (ū_t, ±S̄)` to the leaves
/// (`dq`, `dt` per boundary position) and to the cluster accumulators in `cl` (`A` at the
/// moments' means, `B` at their rows).
struct Scatter<'s, T> {
    pass: usize,
    last: usize,
    ut: [T; 3],
    sb: [T; 4],
    index: &'s [u32],
    cl: &'s mut [T],
    dq: &'s mut [T],
    dt: &'s mut [T],
}

impl<T: Real> Scatter<'_, T> {
    fn visit<const D: usize>(&mut self, v: Visit<T, D>) {
        match v {
            Visit::Pass => self.pass += 1,
            Visit::Cluster { node, nw, a, neg } if self.pass == self.last => {
                let base = node.saturating_mul(node_len(D));
                let sw = if neg { -nw } else { nw };
                let mut u = [T::ZERO; 7];
                for (j, x) in u.iter_mut().enumerate() {
                    *x = if j < D {
                        nw * self.ut.get(j).copied().unwrap_or(T::ZERO)
                    } else {
                        sw * self.sb.get(j - D).copied().unwrap_or(T::ZERO)
                    };
                }
                add_lanes(self.cl, base + Layout::<D>::T, T::ONE, &u[..D + 4]);
                for (j, &aj) in a.iter().enumerate() {
                    add_lanes(
                        self.cl,
                        base + Layout::<D>::M + j * (D + 4),
                        aj,
                        &u[..D + 4],
                    );
                }
            }
            Visit::Leaf { k, w, neg } if self.pass == self.last => {
                let pos = self.index.get(k).copied().unwrap_or(0) as usize;
                accumulate(self.dt, pos, w, self.ut);
                accumulate(self.dq, pos, if neg { -w } else { w }, self.sb);
            }
            _ => {}
        }
    }
}

/// `s[at + l] += f x_l`.
#[inline]
fn add_lanes<T: Real>(s: &mut [T], at: usize, f: T, x: &[T]) {
    if let Some(dst) = s.get_mut(at..at + x.len()) {
        for (d, &v) in dst.iter_mut().zip(x) {
            *d += f * v;
        }
    }
}

/// The downward pass of the adjoint: every member `k` of a cluster gets `(A_C + δ_k · B_C) /
/// n_C` (`δ_k = y_k − c`), its rotation lanes aligned to the cluster's reference as the
/// forward aligned them.
fn distribute<T: Real, const D: usize>(
    grown: Grown<'_, T>,
    qs: &[T],
    cl: &[T],
    dq: &mut [T],
    dt: &mut [T],
) {
    let (index, nodes, leaves) = grown;
    for_clusters::<D>(index, |base, start, members| {
        let c: [T; D] = get_n(nodes, base + Layout::<D>::C);
        let qref: [T; 4] = get_n(nodes, base + Layout::<D>::QR);
        let nt = T::from_usize(members.len());
        let tm: [T; D] = get_n(cl, base + Layout::<D>::T);
        let qm: [T; 4] = get_n(cl, base + Layout::<D>::QS);
        for (j, &pos) in members.iter().enumerate() {
            let k = pos as usize;
            let y: [T; D] = get_n(leaves, (start + j).wrapping_mul(leaf_len(D)));
            let corr = moment_sum(cl, base, sub(y, c));
            let mut t = [T::ZERO; 3];
            for ((a, m), cv) in t.iter_mut().zip(tm).zip(corr) {
                *a = (m + cv) / nt;
            }
            let sg = sign(load(qs, k), qref);
            let mut q = [T::ZERO; 4];
            for ((a, m), cv) in q.iter_mut().zip(qm).zip(corr.iter().skip(D)) {
                *a = sg * (m + *cv) / nt;
            }
            accumulate(dt, k, T::ONE, t);
            accumulate(dq, k, T::ONE, q);
        }
    });
}

/// Adjoint of [`deform_idw_fast`](crate::quaternion::deform_idw_fast): `out = (∂R/∂d)ᵀ w` for
/// the weights `weights = w = dJ/dR` (one per mesh point), i.e. `dJ/dd` at each boundary point
/// (in `motion.nodes` order): the transpose of [`deform_idw_fast_tangent`]. Buffers as there.
///
/// # Errors
/// Those of [`deform_idw_fast_tangent`], with `weights` (one per point, finite) in place of
/// `direction` and `out` one per boundary point. On error `out` is unchanged.
#[allow(clippy::too_many_arguments)]
pub fn deform_idw_fast_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    options: &IdwFastOptions<T>,
    weights: &[[T; D]],
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    index: &mut [u32],
    tree: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let (n, b) = (points.len(), motion.nodes.len());
    let (sizes, io) = ((index.len(), tree.len()), (weights, "weights", out.len()));
    let (tr, rot) = (translations, rotations);
    let origin = validate(
        points, motion, exponent, options, io, tr, rot, scratch, sizes,
    )?;
    boundary_adjoint_check(points, motion, scratch)?;
    let (translations, rotations) = (&*tr, &*rot);
    let (qs, dq, dt, work, cl) = split::<T, D>(scratch, n, b);
    zero(dq);
    zero(dt);
    zero(cl);
    let grown = grow(points, motion.nodes, translations, rotations, index, tree);
    let t = Tree::new(
        points,
        motion.nodes,
        exponent,
        grown,
        translations,
        rotations,
    );
    let field = Field {
        points,
        boundary: motion.nodes,
        exponent,
        origin,
        qs,
    };
    let (mut hint, mut report) = (Hint::new(), IdwFastReport::default());
    for (i, (x, g)) in points.iter().zip(weights).enumerate() {
        let start = hint;
        let mut rec = Record::default();
        if t.point(i, *x, options, &mut hint, &mut report, &mut |v| {
            rec.visit(v)
        })
        .is_none()
        {
            continue;
        }
        let gb = lift(*g);
        if rec.robust {
            adjoint_at(&field, i, *x, gb, work, dq, dt);
        } else if let Some(pos) = rec.coincident {
            let q = load(qs, pos);
            accumulate(
                dq,
                pos,
                T::ONE,
                field.update_adjoint(*x, q, Quat::from_array(q), gb),
            );
            accumulate(dt, pos, T::ONE, gb);
        } else {
            let mut scatter = Scatter {
                pass: 0,
                last: rec.passes,
                ut: scale(gb, T::ONE / rec.w),
                sb: field.update_adjoint(*x, rec.s, Quat::identity(), gb),
                index: grown.0,
                cl,
                dq,
                dt,
            };
            let mut h = start;
            t.point(i, *x, options, &mut h, &mut report, &mut |v| {
                scatter.visit(v)
            });
        }
    }
    distribute::<T, D>(grown, qs, cl, dq, dt);
    for o in out.iter_mut() {
        *o = [T::ZERO; D];
    }
    for (k, &i) in motion.nodes.iter().enumerate() {
        add_to(out, k, get3(weights, i as usize));
    }
    boundary_adjoint(points, motion, origin, scratch, out)
}
