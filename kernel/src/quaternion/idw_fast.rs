//! Fast inverse-distance propagation: far-field aggregation over a k-d tree of the boundary
//! nodes (Barnes–Hut with a first-order cluster expansion), with a rigorous per-point error
//! bound.
//!
//! # The approximation
//!
//! [`propagate_idw`](super::propagate_idw) computes at a field point `x`, with `d_k = |x − y_k|`
//! the distance to boundary node `k` and `v_k` its value (translation `Δ_k`, or the
//! hemisphere-aligned rotation `±Q_k`),
//!
//! ```text
//! v(x) = Σ w_k v_k / W,   w_k = d_k^−p,   W = Σ w_k.
//! ```
//!
//! Here the boundary nodes are put into a k-d tree. A subtree `C` with `n_C` nodes, centroid
//! `c` (the plain mean of its nodes) and bounding radius `r` (every node within `r` of `c`)
//! at distance `d = |x − c|` is used *as a whole* when `r < θ d`: each of its nodes gets the
//! first-order Taylor weight about the centroid,
//!
//! ```text
//! w̃_k = w_C (1 + p (x − c)·δ_k / d²),   w_C = d^−p,   δ_k = y_k − c,
//! ```
//!
//! so the cluster adds `n_C w_C` to the denominator (the linear terms cancel because `c` is
//! the centroid) and `n_C w_C (v̄_C + Mᵀ a)` to the numerator, with `v̄_C` the mean value,
//! `M = Σ δ_k ⊗ v_k / n_C` the stored first moments and `a = p (x − c) / d²`. Clusters that
//! fail the test are opened; leaves are weighted node by node exactly as the exact method
//! weighs them. The cost per point is then a few hundred node visits instead of `B`.
//!
//! # The error bound
//!
//! `w̃_k` is the linear Taylor polynomial of `f(y) = |x − y|^−p` at `c`, so `|w̃_k − w_k|` is
//! at most half the largest second directional derivative on the ball `|y − c| ≤ r`
//! (where `|x − y| ≥ d − r`) times `|δ_k|²`. The Hessian of `|z|^−p` has eigenvalues
//! `p (p + 1) |z|^−p−2` (radial) and `−p |z|^−p−2`, hence
//!
//! ```text
//! Σ_{k∈C} |w̃_k − w_k| ≤ e_C := ½ p (p + 1) (d − r)^−p−2 Σ_{k∈C} |δ_k|²,
//! ```
//!
//! and `w̃_k = w_k` for nodes weighted exactly. Write `ṽ = Σ w̃_k v_k / W̃` for the computed
//! value. Because `Σ w_k (v_k − v) = 0`,
//!
//! ```text
//! ṽ − v = Σ w̃_k (v_k − v) / W̃ = Σ (w̃_k − w_k)(v_k − v) / W̃,
//! ```
//!
//! hence, in any norm,
//!
//! ```text
//! |ṽ(x) − v(x)| ≤ η(x) · max_k |v_k − v(x)|,   η(x) = Σ_C e_C / W̃(x),
//! ```
//!
//! the sum over the clusters used at `x`. `η` is computed alongside the value (one more power
//! per cluster) and reported per point. Since `v(x)` is a convex combination of the `v_k`,
//! `max_k |v_k − v(x)|` is at most the diameter of the boundary values: the bound is relative
//! to the *spread* of the data. A uniform boundary value (a pure translation; one rigid
//! rotation, whatever the quaternion signs) therefore comes out exactly in exact arithmetic,
//! as with the exact method, and in floating point to rounding (tested: within 64 ε). The
//! bound holds for the translation and for the weighted quaternion mean before
//! normalisation; normalising can amplify an error `ε` of a mean of length `m` to at most
//! `2 ε / m`.
//!
//! A priori, `W̃ ≥ Σ_C n_C w_C` gives `η ≤ max_C e_C / (n_C w_C) ≤ ½ p (p + 1) θ² (1 − θ)^−p−2`;
//! in practice the exactly weighted near field dominates `W̃` and `η` is far smaller, and the
//! error itself smaller still (measured in `docs/idw.md`).
//!
//! # Caller control
//!
//! [`IdwFastOptions::tolerance`] `τ` bounds `η` at every point. With a finite `τ` a cluster
//! must also satisfy `e_C ≤ β n_C w_C`, and since `Σ e_C ≤ τ W̃` is what is needed, `β =
//! τ W̃ / W̃_far` (`W̃_far` the clustered part of `W̃`) spends the budget exactly: the first
//! pass at a point takes that ratio from the previous point (mesh order is usually local); if
//! `η > τ` a second pass takes it from the first; a third uses `β = τ`, which guarantees `η ≤
//! τ` (`Σ e_C ≤ τ Σ n_C w_C ≤ τ W̃`); a fourth with `θ = 0` (no clusters, `η = 0`) catches
//! rounding. So every returned point has `η ≤ τ`. The bound is for exact arithmetic of the
//! weights; rounding adds `O(B ε)` relative, as in the exact method.
//!
//! # Rotations
//!
//! The exact method flips each `Q_k` into the hemisphere of the nearest node's rotation
//! `Q_n`. A cluster stores its quaternions aligned to a reference `R_C` (its first node) and
//! `c_C = min_k cos∠(R_C, ±Q_k)`; it is used as a whole only if `(Q̂_n·R_C)² + c_C² > 1`
//! (with a rounding margin), i.e. `∠(Q_n, ±R_C) + ∠(R_C, ±Q_k) < 90°`, which makes every
//! member's flip the one the exact method would choose. Otherwise the cluster is opened.
//!
//! # Exactness and determinism
//!
//! The nearest node is found exactly (smallest computed squared distance, first in `boundary`
//! order on ties), so zero-distance points, the hemisphere reference and the `d_min^p`
//! scaling of the weights are those of the exact method. With `θ = 0` no cluster is used and
//! the result is the exact method's up to summation order (tree order instead of `boundary`
//! order). The tree is built by a fixed rule (median split on the longest box side, first
//! axis on ties, ties in coordinate broken by `boundary` position; children of node `i` are
//! `2i + 1` and `2i + 2`) and traversed depth first, left before right; the per-point hints
//! follow mesh order. The same input gives the same bits. Points whose squared distances
//! leave the normal range (coordinates beyond about 1e154 or closer than 1e-154 in `f64`)
//! are computed by the exact method's robust path.

use super::check_exponent;
use super::propagate::{check_boundary_entries, idw_point};
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::vector::{norm_sq, scale, sub};

/// Boundary nodes per tree leaf.
pub const IDW_FAST_LEAF: usize = 8;

/// Options of [`propagate_idw_fast`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct IdwFastOptions<T> {
    /// Opening parameter `θ ∈ [0, 1)`: a cluster of radius `r` whose centroid is at distance
    /// `d` is used as a whole when `r < θ d`. Smaller is more accurate and slower; `0` weighs
    /// every boundary node individually (the exact method up to summation order).
    pub theta: T,
    /// Largest accepted per-point bound `η` (see the module documentation): clusters whose
    /// own bound would exceed their share of it are opened, and a point above it is
    /// recomputed with a stricter share. `+∞` uses `θ` alone; must not be negative or NaN.
    pub tolerance: T,
}

impl<T: Real> Default for IdwFastOptions<T> {
    /// `θ = 0.5`, `tolerance = 0.1`.
    fn default() -> Self {
        IdwFastOptions {
            theta: T::HALF,
            tolerance: T::from_f64(0.1),
        }
    }
}

/// What [`propagate_idw_fast`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct IdwFastReport<T> {
    /// The largest per-point bound `η` over the field points written: every written
    /// translation is within `η · max_k |Δ_k − Δ(x)|` of the exact one.
    pub max_bound: T,
    /// Clusters used as a whole (summed over points and passes).
    pub clusters: u64,
    /// Boundary nodes weighted individually (summed likewise); the exact method does `N · B`.
    pub direct: u64,
    /// Points that needed more than one pass because their bound exceeded the tolerance.
    pub refined: usize,
    /// Points computed by the exact method's robust path (squared distances out of range).
    pub robust: usize,
}

/// Scalars stored per tree node: box `lo`, `hi`, centroid (`D` each), radius, mean
/// translation (`D`), mean aligned rotation (4), reference rotation (4), cone cosine, mean
/// squared distance to the centroid, first moments (`D × (D + 4)`).
pub(super) const fn node_len(d: usize) -> usize {
    4 * d + 11 + d * (d + 4)
}

/// Depth of the tree over `b` nodes: the smallest `h` with `⌈b / 2^h⌉ ≤` [`IDW_FAST_LEAF`].
fn depth(b: usize) -> u32 {
    let mut len = b;
    let mut h = 0;
    while len > IDW_FAST_LEAF {
        len -= len / 2;
        h += 1;
    }
    h
}

/// Number of node slots (heap numbering: children of `i` are `2i + 1`, `2i + 2`).
fn slots(b: usize) -> usize {
    if b == 0 {
        return 0;
    }
    1usize
        .checked_shl(depth(b) + 1)
        .map_or(usize::MAX, |s| s - 1)
}

/// Length of the `index` buffer [`propagate_idw_fast`] needs: one `u32` per boundary node.
#[inline]
pub fn propagate_idw_fast_index_len(boundary_len: usize) -> usize {
    boundary_len
}

/// Length of the `scratch` buffer [`propagate_idw_fast`] needs: `D² + 8 D + 11` scalars per
/// tree node (at most about `4 B / 8` nodes) plus `2 D + 4` per boundary node (position and
/// values in tree order); `usize::MAX` when that overflows.
#[inline]
pub fn propagate_idw_fast_scratch_len<const D: usize>(boundary_len: usize) -> usize {
    nodes_len::<D>(boundary_len).saturating_add(boundary_len.saturating_mul(leaf_len(D)))
}

/// Scalars of the node records.
pub(super) fn nodes_len<const D: usize>(b: usize) -> usize {
    slots(b).saturating_mul(node_len(D))
}

/// Scalars per boundary node in tree order: position, translation, rotation.
pub(super) const fn leaf_len(d: usize) -> usize {
    2 * d + 4
}

/// Inverse-distance propagation of `(Δ, Q)` like [`propagate_idw`](super::propagate_idw),
/// with far-field clusters of a k-d tree over the boundary nodes (see the module
/// documentation for the method and the error bound). Same inputs and outputs, plus:
///
/// - `options`: the opening parameter `θ` and the per-point tolerance on the bound `η`;
/// - `index` ([`propagate_idw_fast_index_len`] `u32`s) and `scratch`
///   ([`propagate_idw_fast_scratch_len`] scalars): the tree, rebuilt on every call
///   (`O(B log² B)`, small next to the `N` queries);
/// - `bounds`: if given (`N` entries), receives `η` at every non-boundary node (0 where the
///   value is exact); boundary entries are left unchanged.
///
/// Returns the largest `η` and the work done. Every written point satisfies `η ≤
/// options.tolerance`.
///
/// # Errors
/// Those of [`propagate_idw`](super::propagate_idw), plus `theta` not in `[0, 1)`,
/// `tolerance` negative or NaN, buffers too small, `bounds` of the wrong length, more than
/// `u32::MAX` boundary nodes. On error `translations`, `rotations` and `bounds` are unchanged
/// (`index` and `scratch` are workspaces).
#[allow(clippy::too_many_arguments)]
pub fn propagate_idw_fast<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    options: &IdwFastOptions<T>,
    index: &mut [u32],
    scratch: &mut [T],
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    mut bounds: Option<&mut [T]>,
) -> Result<IdwFastReport<T>> {
    check::mesh_dim::<D>();
    let n = points.len();
    let b = boundary.len();
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    if let Some(bd) = bounds.as_deref() {
        check::len("bounds", bd.len(), n)?;
    }
    if b == 0 {
        return Err(Error::InvalidParameter {
            arg: "boundary",
            reason: "must not be empty",
        });
    }
    if u32::try_from(b).is_err() {
        return Err(Error::TooLarge {
            arg: "boundary",
            value: b,
        });
    }
    check_exponent(exponent)?;
    check_options_and_buffers::<T, D>(options, b, index.len(), scratch.len(), "scratch")?;
    check::finite_items("points", points)?;
    check_boundary_entries(boundary, translations, rotations)?;

    let (index, nodes, leaves) = grow(points, boundary, translations, rotations, index, scratch);
    let mut hint = Hint::new();

    let mut report = IdwFastReport {
        max_bound: T::ZERO,
        ..IdwFastReport::default()
    };
    for i in 0..n {
        let x = points.get(i).copied().unwrap_or([T::ZERO; D]);
        let tree = Tree {
            points,
            boundary,
            index,
            nodes,
            leaves,
            translations,
            rotations,
            half_p: exponent * T::HALF,
        };
        let Some((t, q, eta)) = tree.point(i, x, options, &mut hint, &mut report, &mut |_| {})
        else {
            continue;
        };
        if eta > report.max_bound {
            report.max_bound = eta;
        }
        if let Some(v) = translations.get_mut(i) {
            *v = t;
        }
        if let Some(v) = rotations.get_mut(i) {
            *v = q;
        }
        if let Some(v) = bounds.as_deref_mut().and_then(|bd| bd.get_mut(i)) {
            *v = eta;
        }
    }
    Ok(report)
}

/// Checks `θ`, the tolerance and the sizes of the tree buffers for `b` boundary nodes
/// (`scratch_arg` names the scalar buffer in errors).
pub(super) fn check_options_and_buffers<T: Real, const D: usize>(
    options: &IdwFastOptions<T>,
    b: usize,
    index_len: usize,
    scratch_len: usize,
    scratch_arg: &'static str,
) -> Result<()> {
    let theta = options.theta;
    if !(theta.is_finite() && theta >= T::ZERO && theta < T::ONE) {
        return Err(Error::InvalidParameter {
            arg: "options.theta",
            reason: "must be in [0, 1)",
        });
    }
    if options.tolerance.is_nan() || options.tolerance < T::ZERO {
        return Err(Error::InvalidParameter {
            arg: "options.tolerance",
            reason: "must be non-negative (+inf for no refinement)",
        });
    }
    check::buffer("index", index_len, propagate_idw_fast_index_len(b))?;
    check::buffer(
        scratch_arg,
        scratch_len,
        propagate_idw_fast_scratch_len::<D>(b),
    )
}

/// Builds the tree over `boundary` (sizes checked by the caller): `index` in tree order, the
/// node records and the leaves (position, translation, rotation per boundary node in tree
/// order, so that leaves are read contiguously). Only the boundary entries of
/// `translations` and `rotations` are read.
pub(super) fn grow<'s, T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    index: &'s mut [u32],
    scratch: &'s mut [T],
) -> (&'s [u32], &'s [T], &'s [T]) {
    let b = boundary.len();
    let index = index.get_mut(..b).unwrap_or(&mut []);
    let (nodes, leaves) = scratch
        .get_mut(..propagate_idw_fast_scratch_len::<D>(b))
        .unwrap_or(&mut [])
        .split_at_mut_checked(nodes_len::<D>(b))
        .unwrap_or_default();
    build(points, boundary, translations, rotations, index, nodes);
    for (&pos, rec) in index.iter().zip(leaves.chunks_exact_mut(leaf_len(D))) {
        let m = boundary.get(pos as usize).copied().unwrap_or(0) as usize;
        let y = points.get(m).copied().unwrap_or([T::ZERO; D]);
        let t = translations.get(m).copied().unwrap_or([T::ZERO; D]);
        let q = rotations.get(m).copied().unwrap_or(Quat::identity());
        put_n(rec, 0, y);
        put_n(rec, D, t);
        put_n(rec, 2 * D, q.to_array());
    }
    (index, nodes, leaves)
}

/// Offsets of the fields of a node record.
pub(super) struct Layout<const D: usize>;

impl<const D: usize> Layout<D> {
    const LO: usize = 0;
    const HI: usize = D;
    pub(super) const C: usize = 2 * D;
    const R: usize = 3 * D;
    pub(super) const T: usize = 3 * D + 1;
    pub(super) const QS: usize = 4 * D + 1;
    pub(super) const QR: usize = 4 * D + 5;
    const QC: usize = 4 * D + 9;
    const S2: usize = 4 * D + 10;
    pub(super) const M: usize = 4 * D + 11;
}

/// Reads `N` scalars at `at` (zeros when out of range).
#[inline]
pub(super) fn get_n<T: Real, const N: usize>(s: &[T], at: usize) -> [T; N] {
    let mut r = [T::ZERO; N];
    if let Some(c) = s.get(at..at.wrapping_add(N)) {
        for (a, b) in r.iter_mut().zip(c) {
            *a = *b;
        }
    }
    r
}

/// Writes `N` scalars at `at` (ignored when out of range).
#[inline]
pub(super) fn put_n<T: Real, const N: usize>(s: &mut [T], at: usize, v: [T; N]) {
    if let Some(c) = s.get_mut(at..at.wrapping_add(N)) {
        for (a, b) in c.iter_mut().zip(v) {
            *a = b;
        }
    }
}

/// Reads one scalar (zero when out of range).
#[inline]
fn get1<T: Real>(s: &[T], at: usize) -> T {
    s.get(at).copied().unwrap_or(T::ZERO)
}

/// A depth-first work stack of `(node, start, end)` (no allocation; the tree depth is at most
/// 32 and a pre-order walk holds at most one pending sibling per level).
pub(super) struct Stack {
    items: [(usize, usize, usize); 72],
    len: usize,
}

impl Stack {
    pub(super) fn new(root: (usize, usize, usize)) -> Self {
        let mut s = Stack {
            items: [(0, 0, 0); 72],
            len: 0,
        };
        s.push(root);
        s
    }

    #[inline]
    pub(super) fn push(&mut self, v: (usize, usize, usize)) {
        if let Some(slot) = self.items.get_mut(self.len) {
            *slot = v;
            self.len += 1;
        }
    }

    #[inline]
    pub(super) fn pop(&mut self) -> Option<(usize, usize, usize)> {
        self.len = self.len.checked_sub(1)?;
        self.items.get(self.len).copied()
    }
}

/// The children of node `(i, s, e)`: left `[s, s + len/2)`, right `[s + len/2, e)`.
#[inline]
pub(super) fn children(i: usize, s: usize, e: usize) -> [(usize, usize, usize); 2] {
    let m = s + (e - s) / 2;
    let l = i.wrapping_mul(2).wrapping_add(1);
    [(l, s, m), (l.wrapping_add(1), m, e)]
}

/// Builds the tree: sorts `index` (boundary positions) node by node and fills the records.
fn build<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    index: &mut [u32],
    nodes: &mut [T],
) {
    for (k, v) in index.iter_mut().enumerate() {
        *v = k as u32;
    }
    let b = index.len();
    let pos_point = |pos: u32| -> [T; D] {
        boundary
            .get(pos as usize)
            .and_then(|&m| points.get(m as usize))
            .copied()
            .unwrap_or([T::ZERO; D])
    };
    let nl = node_len(D);
    let eps = T::EPSILON;
    let mut stack = Stack::new((0, 0, b));
    while let Some((i, s, e)) = stack.pop() {
        let members = index.get(s..e).unwrap_or(&[]);
        let count = members.len();
        let base = i.saturating_mul(nl);
        // Bounding box.
        let mut lo = [T::INFINITY; D];
        let mut hi = [-T::INFINITY; D];
        for &pos in members {
            let y = pos_point(pos);
            for ((l, h), c) in lo.iter_mut().zip(hi.iter_mut()).zip(y) {
                *l = l.min(c);
                *h = h.max(c);
            }
        }
        // Centroid as a sum of y / n (cannot overflow), radius about it (inflated by a few
        // ulps so that rounding cannot put a member outside).
        let nt = T::from_usize(count.max(1));
        let mut c = [T::ZERO; D];
        for &pos in members {
            let y = pos_point(pos);
            for (a, v) in c.iter_mut().zip(y) {
                *a += v / nt;
            }
        }
        let mut r = T::ZERO;
        for &pos in members {
            let d = norm_sq(sub(pos_point(pos), c)).sqrt();
            r = r.max(d);
        }
        let r = r * (T::ONE + T::from_f64(8.0) * eps);
        // Rotations: reference (first member, normalised), aligned mean, cone cosine.
        let rot = |pos: u32| -> Quat<T> {
            boundary
                .get(pos as usize)
                .and_then(|&m| rotations.get(m as usize))
                .copied()
                .unwrap_or(Quat::identity())
        };
        let qref = members
            .first()
            .map(|&p| rot(p))
            .unwrap_or(Quat::identity())
            .normalize()
            .unwrap_or(Quat::identity());
        let mut cmin = T::ONE;
        for &pos in members {
            let q = rot(pos);
            let q = if qref.dot(q) < T::ZERO { -q } else { q };
            let cosine = q.normalize().map_or(T::ZERO, |u| qref.dot(u));
            cmin = cmin.min(cosine);
        }
        let cmin = (cmin - T::from_f64(64.0) * eps).max(T::ZERO);
        // The mean squared distance `Σ |δ_k|² / n` to the centroid.
        let mut s2 = T::ZERO;
        for &pos in members {
            s2 += norm_sq(sub(pos_point(pos), c)) / nt;
        }
        if let Some(rec) = nodes.get_mut(base..base.saturating_add(nl)) {
            put_n(rec, Layout::<D>::LO, lo);
            put_n(rec, Layout::<D>::HI, hi);
            put_n(rec, Layout::<D>::C, c);
            put_n(rec, Layout::<D>::R, [r]);
            put_n(rec, Layout::<D>::QR, qref.to_array());
            put_n(rec, Layout::<D>::QC, [cmin]);
            put_n(rec, Layout::<D>::S2, [s2]);
            let value = |pos: u32| {
                let m = boundary.get(pos as usize).copied().unwrap_or(0) as usize;
                let t = translations.get(m).copied().unwrap_or([T::ZERO; D]);
                let q = rot(pos);
                (t, if qref.dot(q) < T::ZERO { -q } else { q }.to_array())
            };
            moments(members, c, nt, pos_point, value, rec);
        }
        if count > IDW_FAST_LEAF {
            // Split the longest side (first axis on ties) at the median.
            let mut axis = 0;
            let mut best = -T::ONE;
            for (a, (l, h)) in lo.iter().zip(hi.iter()).enumerate() {
                let ext = *h - *l;
                if ext > best {
                    best = ext;
                    axis = a;
                }
            }
            let key = |pos: u32| pos_point(pos).get(axis).copied().unwrap_or(T::ZERO);
            let range = index.get_mut(s..e).unwrap_or(&mut []);
            heapsort_by(range, |a, b| {
                let (ka, kb) = (key(a), key(b));
                ka < kb || (ka == kb && a < b)
            });
            let [l, rr] = children(i, s, e);
            stack.push(rr);
            stack.push(l);
        }
    }
}

/// Writes the value moments of a node record (at its start): the means `Σ v_k / n` of the
/// translations and aligned rotations and the first moments `Σ δ_k ⊗ v_k / n` (`δ_k = y_k −
/// c`) of the `members` (boundary positions; `nt = n`, `value(pos) = (Δ, ±Q)`).
pub(super) fn moments<T: Real, const D: usize>(
    members: &[u32],
    c: [T; D],
    nt: T,
    pos_point: impl Fn(u32) -> [T; D],
    value: impl Fn(u32) -> ([T; D], [T; 4]),
    rec: &mut [T],
) {
    let mut tm = [T::ZERO; D];
    let mut qm = [T::ZERO; 4];
    let mut mom = [[T::ZERO; 7]; 3];
    for &pos in members {
        let (t, q) = value(pos);
        for (a, v) in tm.iter_mut().zip(t) {
            *a += v / nt;
        }
        for (a, v) in qm.iter_mut().zip(q) {
            *a += v / nt;
        }
        let delta = sub(pos_point(pos), c);
        for (row, dj) in mom.iter_mut().zip(delta) {
            let (rt, rq) = row.split_at_mut(D.min(7));
            for (a, v) in rt.iter_mut().zip(t) {
                *a += dj * v / nt;
            }
            for (a, v) in rq.iter_mut().zip(q) {
                *a += dj * v / nt;
            }
        }
    }
    put_n(rec, Layout::<D>::T, tm);
    put_n(rec, Layout::<D>::QS, qm);
    for (j, row) in mom.iter().take(D).enumerate() {
        let at = Layout::<D>::M + j * (D + 4);
        if let Some(dst) = rec.get_mut(at..at + D + 4) {
            for (a, v) in dst.iter_mut().zip(row) {
                *a = *v;
            }
        }
    }
}

/// In-place heapsort of `v` by the strict order `less` (no allocation, no panic path).
fn heapsort_by(v: &mut [u32], less: impl Fn(u32, u32) -> bool + Copy) {
    let n = v.len();
    let mut start = n / 2;
    while start > 0 {
        start -= 1;
        sift_down(v, start, n, less);
    }
    let mut end = n;
    while end > 1 {
        end -= 1;
        if end < v.len() {
            v.swap(0, end);
        }
        sift_down(v, 0, end, less);
    }
}

fn sift_down(v: &mut [u32], mut root: usize, end: usize, less: impl Fn(u32, u32) -> bool) {
    let end = end.min(v.len());
    loop {
        let mut child = 2 * root + 1;
        if child >= end {
            break;
        }
        if child + 1 < end {
            if let (Some(&a), Some(&b)) = (v.get(child), v.get(child + 1)) {
                if less(a, b) {
                    child += 1;
                }
            }
        }
        match (v.get(root), v.get(child)) {
            (Some(&r), Some(&c)) if less(r, c) => {
                if root < v.len() && child < v.len() {
                    v.swap(root, child);
                }
                root = child;
            }
            _ => break,
        }
    }
}

/// The built tree and the field it interpolates (read-only during the queries).
pub(super) struct Tree<'a, T, const D: usize> {
    points: &'a [[T; D]],
    boundary: &'a [u32],
    index: &'a [u32],
    nodes: &'a [T],
    leaves: &'a [T],
    translations: &'a [[T; D]],
    rotations: &'a [Quat<T>],
    half_p: T,
}

/// What the previous point leaves for the next (mesh order is usually local).
#[derive(Clone, Copy)]
pub(super) struct Hint<T> {
    /// Tree position of its nearest boundary node: the nearest-node search starts there.
    nearest: usize,
    /// Its `W̃ / W̃_far` (total over clustered weight): the first pass's budget factor.
    gamma: T,
}

impl<T: Real> Hint<T> {
    /// The hint before the first point.
    pub(super) fn new() -> Self {
        Hint {
            nearest: 0,
            gamma: T::INFINITY,
        }
    }
}

/// What a query decided, step by step, for callers that replay its weights (the
/// sensitivities): the weights depend on the geometry and on these decisions only.
#[derive(Clone, Copy)]
pub(super) enum Visit<T, const D: usize> {
    /// A pass starts (the sums restart from zero).
    Pass,
    /// Tree node `node` used as a whole with total weight `nw = n_C w_C` and `a = p (x − c) /
    /// d²` (member `k` weighs `nw / n_C (1 + a·δ_k)`); its aligned rotations enter negated
    /// when `neg`.
    Cluster {
        node: usize,
        nw: T,
        a: [T; D],
        neg: bool,
    },
    /// Tree position `k` weighted individually by `w`; its rotation negated when `neg`.
    Leaf { k: usize, w: T, neg: bool },
    /// The pass's sums: the rotation sum `S = Σ ±w̃_k Q_k` and `W̃ = Σ w̃_k`.
    Totals { q: [T; 4], w: T },
    /// The point's value comes from the exact method's robust path.
    Robust,
    /// The point lies on boundary position `pos` (its value is that node's).
    Coincident { pos: usize },
}

/// Sums of one weighted traversal.
struct Sums<T, const D: usize> {
    t: [T; D],
    q: [T; 4],
    w: T,
    w_far: T,
    err: T,
    plain: bool,
}

impl<'a, T: Real, const D: usize> Tree<'a, T, D> {
    /// The tree of [`grow`] over the field (`translations`, `rotations` at the boundary nodes).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        points: &'a [[T; D]],
        boundary: &'a [u32],
        exponent: T,
        grown: (&'a [u32], &'a [T], &'a [T]),
        translations: &'a [[T; D]],
        rotations: &'a [Quat<T>],
    ) -> Self {
        Tree {
            points,
            boundary,
            index: grown.0,
            nodes: grown.1,
            leaves: grown.2,
            translations,
            rotations,
            half_p: exponent * T::HALF,
        }
    }

    /// Mesh node, point of tree position `k`.
    #[inline]
    fn at(&self, k: usize) -> [T; D] {
        get_n(self.leaves, k.wrapping_mul(leaf_len(D)))
    }

    /// Boundary position and mesh node of tree position `k`.
    #[inline]
    fn node_of(&self, k: usize) -> (usize, usize) {
        let pos = self.index.get(k).copied().unwrap_or(0) as usize;
        (pos, self.boundary.get(pos).copied().unwrap_or(0) as usize)
    }

    /// `(ratio)^(p/2)` as the exact method computes it.
    #[inline]
    fn weight(&self, ratio: T) -> T {
        if self.half_p == T::ONE {
            ratio
        } else {
            ratio.powf(self.half_p)
        }
    }

    /// `true` when a squared distance is in the range the exact method's plain path accepts.
    #[inline]
    fn plain(d2: T, diff: &[T; D]) -> bool {
        d2.is_finite() && (d2 >= T::MIN_POSITIVE || diff.iter().all(|&c| c == T::ZERO))
    }

    /// The nearest boundary node of `x` (smallest squared distance, first `boundary` position
    /// on ties): `(d², position, x is boundary node i, every distance seen in range)`.
    fn nearest(&self, i: usize, x: [T; D], hint: &mut Hint<T>) -> (T, usize, bool, bool) {
        let b = self.index.len();
        let nl = node_len(D);
        let mut best = (T::INFINITY, usize::MAX, 0);
        let mut is_boundary = false;
        let mut plain = true;
        let mut visit = |k: usize, best: &mut (T, usize, usize)| {
            let diff = sub(x, self.at(k));
            let d2 = norm_sq(diff);
            plain &= Self::plain(d2, &diff);
            if d2 <= best.0 {
                // Only a zero difference can be node `i` itself.
                let (pos, m) = self.node_of(k);
                is_boundary |= m == i;
                if d2 < best.0 || pos < best.1 {
                    *best = (d2, pos, k);
                }
            }
        };
        // Start from the previous point's nearest node (mesh order is usually local): a
        // real candidate, so the minimum is unchanged, and most subtrees are pruned at once.
        if hint.nearest < b {
            visit(hint.nearest, &mut best);
        }
        let lower = |node: usize| -> T {
            let base = node.saturating_mul(nl);
            let lo: [T; D] = get_n(self.nodes, base + Layout::<D>::LO);
            let hi: [T; D] = get_n(self.nodes, base + Layout::<D>::HI);
            let mut s = T::ZERO;
            for ((l, h), c) in lo.iter().zip(hi.iter()).zip(x) {
                let g = (*l - c).max(c - *h).max(T::ZERO);
                s += g * g;
            }
            s
        };
        let mut stack = Stack::new((0, 0, b));
        while let Some((node, s, e)) = stack.pop() {
            if lower(node) > best.0 {
                continue;
            }
            if e - s <= IDW_FAST_LEAF {
                for k in s..e {
                    visit(k, &mut best);
                }
            } else {
                let [l, r] = children(node, s, e);
                // Nearer child first (popped last pushed).
                if lower(l.0) <= lower(r.0) {
                    stack.push(r);
                    stack.push(l);
                } else {
                    stack.push(l);
                    stack.push(r);
                }
            }
        }
        hint.nearest = best.2;
        (best.0, best.1, is_boundary, plain)
    }

    /// One weighted traversal: a cluster is used as a whole when `r < θ d`, its rotations
    /// pass the cone test, and its bound `e_C ≤ budget · n_C w_C` (`budget = ∞`: no limit).
    #[allow(clippy::too_many_arguments)]
    fn sums(
        &self,
        x: [T; D],
        d2min: T,
        qn: Quat<T>,
        qn_unit: Quat<T>,
        theta: T,
        budget: T,
        visit: &mut impl FnMut(Visit<T, D>),
    ) -> (Sums<T, D>, u64, u64) {
        visit(Visit::Pass);
        let b = self.index.len();
        let nl = node_len(D);
        let theta2 = theta * theta;
        let shrink = (T::ONE - theta) * (T::ONE - theta);
        let four = T::TWO * T::TWO;
        let cone_margin = T::ONE + T::from_f64(64.0) * T::EPSILON;
        let p = self.half_p * T::TWO;
        let half_pp1 = self.half_p * (p + T::ONE);
        let mut acc = Sums {
            t: [T::ZERO; D],
            q: [T::ZERO; 4],
            w: T::ZERO,
            w_far: T::ZERO,
            err: T::ZERO,
            plain: true,
        };
        let (mut clusters, mut direct) = (0u64, 0u64);
        let mut stack = Stack::new((0, 0, b));
        while let Some((node, s, e)) = stack.pop() {
            let count = e - s;
            if count > 1 && theta > T::ZERO {
                let base = node.saturating_mul(nl);
                let c: [T; D] = get_n(self.nodes, base + Layout::<D>::C);
                let r = get1(self.nodes, base + Layout::<D>::R);
                let dc2 = norm_sq(sub(x, c));
                let qref = Quat::from_array(get_n(self.nodes, base + Layout::<D>::QR));
                let far = r * r < theta2 * dc2 && {
                    let qc = get1(self.nodes, base + Layout::<D>::QC);
                    let dq = qn_unit.dot(qref);
                    dq * dq + qc * qc > cone_margin
                };
                if far {
                    if !(dc2.is_finite()
                        && dc2 <= T::MAX / four
                        && dc2 * shrink >= four * T::MIN_POSITIVE)
                    {
                        acc.plain = false;
                        break;
                    }
                    let nt = T::from_usize(count);
                    let nw = self.weight(d2min / dc2) * nt;
                    let near = dc2.sqrt() - r;
                    let near2 = near * near;
                    // Taylor remainder: |w̃_k − w_k| ≤ ½ p (p + 1) (d − r)^(−p−2) |δ_k|².
                    let s2 = get1(self.nodes, base + Layout::<D>::S2);
                    let e_c = half_pp1 * self.weight(d2min / near2) * (s2 / near2) * nt;
                    if e_c <= budget * nw {
                        self.add_cluster(&mut acc, x, base, c, dc2, p, nw, qn, qref);
                        visit(Visit::Cluster {
                            node,
                            nw,
                            a: scale(sub(x, c), p / dc2),
                            neg: qn.dot(qref) < T::ZERO,
                        });
                        acc.err += e_c;
                        clusters += 1;
                        continue;
                    }
                }
            }
            if count <= IDW_FAST_LEAF {
                for k in s..e {
                    let at = k.wrapping_mul(leaf_len(D));
                    let diff = sub(x, get_n(self.leaves, at));
                    let d2 = norm_sq(diff);
                    acc.plain &= Self::plain(d2, &diff);
                    let w = self.weight(d2min / d2);
                    let bt: [T; D] = get_n(self.leaves, at + D);
                    for (a, v) in acc.t.iter_mut().zip(bt) {
                        *a += w * v;
                    }
                    acc.w += w;
                    let q = Quat::from_array(get_n(self.leaves, at + 2 * D));
                    let neg = qn.dot(q) < T::ZERO;
                    visit(Visit::Leaf { k, w, neg });
                    let q = if neg { -q } else { q };
                    for (a, v) in acc.q.iter_mut().zip(q.to_array()) {
                        *a += w * v;
                    }
                }
                direct += count as u64;
            } else {
                let [l, r] = children(node, s, e);
                stack.push(r);
                stack.push(l);
            }
        }
        visit(Visit::Totals { q: acc.q, w: acc.w });
        (acc, clusters, direct)
    }

    /// Adds an accepted cluster (record at `base`, centroid `c` at squared distance `dc2`,
    /// total weight `nw = n_C w_C`): with `w̃_k = w_C (1 + p (x − c)·δ_k / d²)` it contributes
    /// `n_C w_C (v̄ + Mᵀ a)`, `a = p (x − c) / d²`, `M` the first moments.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn add_cluster(
        &self,
        acc: &mut Sums<T, D>,
        x: [T; D],
        base: usize,
        c: [T; D],
        dc2: T,
        p: T,
        nw: T,
        qn: Quat<T>,
        qref: Quat<T>,
    ) {
        let a = scale(sub(x, c), p / dc2);
        let mut corr = [T::ZERO; 7];
        for (j, aj) in a.iter().enumerate() {
            let at = base + Layout::<D>::M + j * (D + 4);
            let row = self.nodes.get(at..at + D + 4).unwrap_or(&[]);
            for (cv, mv) in corr.iter_mut().zip(row) {
                *cv += *aj * *mv;
            }
        }
        let (ct, cq) = corr.split_at(D.min(7));
        let tm: [T; D] = get_n(self.nodes, base + Layout::<D>::T);
        for ((a, v), cv) in acc.t.iter_mut().zip(tm).zip(ct) {
            *a += nw * (v + *cv);
        }
        let qm: [T; 4] = get_n(self.nodes, base + Layout::<D>::QS);
        let sw = if qn.dot(qref) < T::ZERO { -nw } else { nw };
        for ((a, v), cv) in acc.q.iter_mut().zip(qm).zip(cq) {
            *a += sw * (v + *cv);
        }
        acc.w += nw;
        acc.w_far += nw;
    }

    /// The value at field point `x` (mesh node `i`) and its bound `η`; `None` for a boundary
    /// node. `visit` sees every decision ([`Visit`]).
    pub(super) fn point(
        &self,
        i: usize,
        x: [T; D],
        options: &IdwFastOptions<T>,
        hint: &mut Hint<T>,
        report: &mut IdwFastReport<T>,
        visit: &mut impl FnMut(Visit<T, D>),
    ) -> Option<([T; D], Quat<T>, T)> {
        let (d2min, pos, is_boundary, plain) = self.nearest(i, x, hint);
        if is_boundary {
            return None;
        }
        let exact = |report: &mut IdwFastReport<T>, visit: &mut dyn FnMut(Visit<T, D>)| {
            visit(Visit::Robust);
            report.robust += 1;
            idw_point(
                self.points,
                self.boundary,
                self.half_p * T::TWO,
                self.translations,
                self.rotations,
                i,
                x,
            )
            .map(|(t, q)| (t, q, T::ZERO))
        };
        if !plain {
            return exact(report, visit);
        }
        let m = self.boundary.get(pos).copied().unwrap_or(0) as usize;
        let tn = self.translations.get(m).copied().unwrap_or([T::ZERO; D]);
        let qn = self.rotations.get(m).copied().unwrap_or(Quat::identity());
        if d2min <= T::ZERO {
            visit(Visit::Coincident { pos });
            return Some((tn, qn, T::ZERO));
        }
        let qn_unit = qn.normalize().unwrap_or(Quat::identity());
        // Every pass uses clusters with r < θ d; with a finite tolerance τ they must also
        // satisfy e_C ≤ budget · n_C w_C. Σ e_C ≤ τ W̃ is what is needed, so budget =
        // τ W̃ / W̃_far (W̃_far the clustered part) spends it exactly: pass 0 takes that ratio
        // from the previous point, pass 1 from pass 0; pass 2 uses budget = τ, which
        // guarantees η ≤ τ (Σ e_C ≤ τ Σ n_C w_C ≤ τ W̃), and pass 3 θ = 0 (exact; only
        // rounding can get there).
        let tol = options.tolerance;
        let scaled = |gamma: T| {
            if gamma.is_finite() {
                tol * gamma
            } else {
                T::INFINITY
            }
        };
        let mut theta = options.theta;
        let mut budget = scaled(hint.gamma);
        let mut round = 0;
        loop {
            let (acc, clusters, direct) = self.sums(x, d2min, qn, qn_unit, theta, budget, visit);
            report.clusters += clusters;
            report.direct += direct;
            let eta = acc.err / acc.w;
            if !acc.plain || acc.w <= T::ZERO || !eta.is_finite() {
                return exact(report, visit);
            }
            let gamma = if acc.w_far > T::ZERO {
                acc.w / acc.w_far
            } else {
                T::INFINITY
            };
            if acc.w_far > T::ZERO {
                hint.gamma = gamma;
            }
            if eta <= tol || theta == T::ZERO {
                let mut t = acc.t;
                for v in t.iter_mut() {
                    *v /= acc.w;
                }
                if !(t.iter().all(|v| v.is_finite()) && acc.q.iter().all(|v| v.is_finite())) {
                    // Moments out of range (values near the overflow threshold).
                    return exact(report, visit);
                }
                let q = Quat::from_array(acc.q).normalize().unwrap_or(qn);
                return Some((t, q, eta));
            }
            if round == 0 {
                report.refined += 1;
                budget = scaled(gamma).min(budget);
            } else if round == 1 {
                budget = tol;
            } else {
                theta = T::ZERO;
            }
            round += 1;
        }
    }
}
