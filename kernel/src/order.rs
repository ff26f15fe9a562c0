//! Node orders for memory locality: reverse Cuthill–McKee on a [`Graph`], a Hilbert-curve
//! order of points, and the helpers that apply a permutation to points, fields, graphs and
//! cell node lists, and undo it.
//!
//! A mesh numbered as a generator writes it puts neighbours far apart in memory, and every
//! sweep, product and multigrid level then misses the cache (issue 34: half of a spring solve
//! on a 234k-node gmsh mesh). Renumbering once, solving, and writing back in the input's
//! numbering removes those misses without changing the problem.
//!
//! A permutation is two arrays: `order[new] = old` and `inverse[old] = new`. The orderings
//! write both; [`Permutation::new`] checks a pair in `O(n)` without scratch
//! (`inverse[order[k]] == k` for every `k` makes `order` one-to-one). Undoing a permutation
//! is applying [`Permutation::inverted`], the same two arrays swapped.
//!
//! ```
//! use deform_kernel::order::{rcm_order, permute, Permutation};
//! use deform_kernel::{graph_from_edges, Graph};
//! // A path numbered 0-2-4-1-3: far apart; RCM numbers it along the path.
//! let mut off = [0u32; 6];
//! let mut tgt = [0u32; 8];
//! let used = graph_from_edges(5, &[[0, 2], [2, 4], [4, 1], [1, 3]], &mut off, &mut tgt)?;
//! let g = Graph::new(&off, &tgt[..used])?;
//! let (mut order, mut inverse) = ([0u32; 5], [0u32; 5]);
//! rcm_order(&g, &mut order, &mut inverse)?;
//! let p = Permutation::new(&order, &inverse)?;
//! assert_eq!(deform_kernel::order::index_distance(&g, Some(p))?.max, 1);
//! let x = [10.0, 11.0, 12.0, 13.0, 14.0];
//! let (mut y, mut back) = ([0.0; 5], [0.0; 5]);
//! permute(p, &x, &mut y)?;
//! permute(p.inverted(), &y, &mut back)?;
//! assert_eq!(back, x);
//! # Ok::<(), deform_kernel::Error>(())
//! ```

mod hilbert;
mod rcm;
pub(crate) mod sort;

use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use sort::{heap_sort, ByKey, RowWithEdges};

/// A checked permutation of `n` nodes: `order[new] = old`, `inverse[old] = new`.
#[derive(Clone, Copy, Debug)]
pub struct Permutation<'a> {
    order: &'a [u32],
    inverse: &'a [u32],
}

impl<'a> Permutation<'a> {
    /// Checks that `order` is a permutation of `0..n` and `inverse` its inverse.
    ///
    /// # Errors
    /// Lengths that differ ([`Error::LengthMismatch`], `inverse`); `n >= u32::MAX`
    /// ([`Error::TooLarge`]); an `order` entry `>= n` ([`Error::IndexOutOfRange`]); an entry
    /// with `inverse[order[k]] != k` ([`Error::InvalidParameter`], `inverse`).
    pub fn new(order: &'a [u32], inverse: &'a [u32]) -> Result<Self> {
        let n = order.len();
        check::len("inverse", inverse.len(), n)?;
        node_count_fits(n)?;
        check::indices("order", order, n)?;
        for (k, &old) in order.iter().enumerate() {
            if inverse.get(old as usize).map(|&v| v as usize) != Some(k) {
                return Err(Error::InvalidParameter {
                    arg: "inverse",
                    reason:
                        "inverse[order[k]] must be k (order a permutation, inverse its inverse)",
                });
            }
        }
        Ok(Permutation { order, inverse })
    }

    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Whether it permutes no node.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.order.is_empty()
    }

    /// `order[new] = old`.
    #[inline]
    pub fn order(&self) -> &'a [u32] {
        self.order
    }

    /// `inverse[old] = new`.
    #[inline]
    pub fn inverse(&self) -> &'a [u32] {
        self.inverse
    }

    /// The inverse permutation (the two arrays swapped): applying it undoes `self`.
    #[inline]
    pub fn inverted(&self) -> Permutation<'a> {
        Permutation {
            order: self.inverse,
            inverse: self.order,
        }
    }

    /// Whether every node keeps its index.
    pub fn is_identity(&self) -> bool {
        self.order.iter().enumerate().all(|(k, &v)| v as usize == k)
    }
}

/// Node counts an order can hold: below `u32::MAX - 1` (two `u32` values mark nodes).
fn node_count_fits(n: usize) -> Result<()> {
    if n >= (u32::MAX - 1) as usize {
        return Err(Error::TooLarge {
            arg: "order",
            value: n,
        });
    }
    Ok(())
}

/// Both output arrays have one entry a node.
fn check_outputs(n: usize, order: &[u32], inverse: &[u32]) -> Result<()> {
    node_count_fits(n)?;
    check::len("order", order.len(), n)?;
    check::len("inverse", inverse.len(), n)
}

/// Reverse Cuthill–McKee order of `g`'s nodes: `order[new] = old`, `inverse[old] = new`.
///
/// Each connected component (in node-index order of its lowest node) is numbered
/// breadth-first from a pseudo-peripheral node (George and Liu), each node's unnumbered
/// neighbours in increasing degree (ties: lower index first), and the whole order is
/// reversed. Deterministic; `O(edges × searches)` time, no scratch. On a symmetric graph
/// (every mesh graph the builders write) it narrows the band of the spring matrices; on a
/// non-symmetric one it follows out-edges and still returns a permutation.
///
/// # Errors
/// `order` or `inverse` not of `g.node_count()` entries ([`Error::LengthMismatch`]); more
/// than `u32::MAX - 2` nodes ([`Error::TooLarge`]). Nothing is written on error.
pub fn rcm_order(g: &Graph<'_>, order: &mut [u32], inverse: &mut [u32]) -> Result<()> {
    check_outputs(g.node_count(), order, inverse)?;
    rcm::rcm(g, order, inverse);
    Ok(())
}

/// Hilbert-curve order of points: `order[new] = old`, `inverse[old] = new`, nodes sorted by
/// the Hilbert key of their cell on the bounding box (32 bits an axis in 2D, 21 in 3D),
/// ties by index. `keys` is scratch (at least `points.len()` entries; on return `keys[old]`
/// is node `old`'s key). Deterministic and free of any graph: for meshes without
/// connectivity, or as a cheaper start than RCM on point clouds.
///
/// # Errors
/// A non-finite coordinate ([`Error::NonFinite`], `points`); `order` or `inverse` not of
/// `points.len()` entries ([`Error::LengthMismatch`]); `keys` shorter
/// ([`Error::BufferTooSmall`]); too many points ([`Error::TooLarge`]). Nothing is written on
/// error.
pub fn hilbert_order<T: Real, const D: usize>(
    points: &[[T; D]],
    order: &mut [u32],
    inverse: &mut [u32],
    keys: &mut [u64],
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = points.len();
    check::finite_items("points", points)?;
    check_outputs(n, order, inverse)?;
    check::buffer("keys", keys.len(), n)?;
    let frame = hilbert::half_box(points);
    for (k, p) in keys.iter_mut().zip(points) {
        *k = hilbert::key(p, &frame);
    }
    let keys: &[u64] = keys;
    sort_by_key(order, inverse, |v| keys.get(v as usize).copied());
    Ok(())
}

/// [`hilbert_order`] with its keys kept in `2 × points.len()` words of `keys` (low and high
/// halves), for callers whose scratch is `u32` (a plan's init work): the same order.
/// Arguments are checked by the caller (finite points, lengths).
pub(crate) fn hilbert_order_words<T: Real, const D: usize>(
    points: &[[T; D]],
    order: &mut [u32],
    inverse: &mut [u32],
    keys: &mut [u32],
) {
    let frame = hilbert::half_box(points);
    for (k, p) in keys.chunks_exact_mut(2).zip(points) {
        let key = hilbert::key(p, &frame);
        if let [lo, hi] = k {
            (*lo, *hi) = (key as u32, (key >> 32) as u32);
        }
    }
    let keys: &[u32] = keys;
    sort_by_key(order, inverse, |v| {
        let at = (v as usize).checked_mul(2)?;
        let (lo, hi) = (keys.get(at)?, keys.get(at.checked_add(1)?)?);
        Some(u64::from(*lo) | (u64::from(*hi) << 32))
    });
}

/// `order` sorted by `(key(node), node)` (a missing key sorts last), `inverse` its inverse.
fn sort_by_key(order: &mut [u32], inverse: &mut [u32], key: impl Fn(u32) -> Option<u64>) {
    for (k, o) in order.iter_mut().enumerate() {
        *o = k as u32;
    }
    heap_sort(&mut ByKey {
        items: order,
        key: |v| (key(v).unwrap_or(u64::MAX), v),
    });
    for (k, &v) in order.iter().enumerate() {
        if let Some(slot) = inverse.get_mut(v as usize) {
            *slot = k as u32;
        }
    }
}

/// How far apart in memory the two ends of a graph's edges are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct IndexDistance {
    /// The largest `|i − j|` over the directed edges `i → j` (the matrix bandwidth).
    pub max: u32,
    /// The sum of `|i − j|` over the directed edges (the profile's cousin; over
    /// [`IndexDistance::edges`] it is the mean distance).
    pub sum: u64,
    /// The number of directed edges.
    pub edges: u64,
}

/// Index distance across `g`'s edges, in `g`'s numbering or (with `perm`) in the numbering
/// `perm` gives the nodes (node `i` becomes `perm.inverse()[i]`).
///
/// # Errors
/// `perm` of another node count than `g` ([`Error::LengthMismatch`], `perm`).
pub fn index_distance(g: &Graph<'_>, perm: Option<Permutation<'_>>) -> Result<IndexDistance> {
    if let Some(p) = perm {
        check::len("perm", p.len(), g.node_count())?;
    }
    let new = |i: usize| match perm {
        Some(p) => p.inverse.get(i).copied().unwrap_or(0),
        None => i as u32,
    };
    let mut d = IndexDistance::default();
    for (i, _, row) in g.rows() {
        let a = new(i);
        for &j in row {
            let b = new(j as usize);
            let gap = a.abs_diff(b);
            d.max = d.max.max(gap);
            d.sum = d.sum.saturating_add(u64::from(gap));
            d.edges += 1;
        }
    }
    Ok(d)
}

/// Items in the new numbering: `dst[new] = src[perm.order()[new]]` (points, fields, masks;
/// `perm.inverted()` brings them back).
///
/// # Errors
/// `src` or `dst` not of `perm.len()` entries ([`Error::LengthMismatch`]).
pub fn permute<X: Copy>(perm: Permutation<'_>, src: &[X], dst: &mut [X]) -> Result<()> {
    check::len("src", src.len(), perm.len())?;
    check::len("dst", dst.len(), perm.len())?;
    gather_unchecked(perm.order, src, dst);
    Ok(())
}

/// `dst[k] = src[map[k]]`: per-directed-edge data (stiffness) after [`permute_graph`], with
/// its `edge_map`.
///
/// # Errors
/// `dst` not of `map.len()` entries ([`Error::LengthMismatch`]); a `map` entry `>=
/// src.len()` ([`Error::IndexOutOfRange`]).
pub fn gather<X: Copy>(map: &[u32], src: &[X], dst: &mut [X]) -> Result<()> {
    check::len("dst", dst.len(), map.len())?;
    check::indices("map", map, src.len())?;
    gather_unchecked(map, src, dst);
    Ok(())
}

/// `dst[k] = src[map[k]]` for checked arguments.
fn gather_unchecked<X: Copy>(map: &[u32], src: &[X], dst: &mut [X]) {
    for (d, &m) in dst.iter_mut().zip(map) {
        if let Some(&s) = src.get(m as usize) {
            *d = s;
        }
    }
}

/// Node indices (cell node lists, marker lists, boundary node lists) in the new numbering,
/// in place: `i` becomes `perm.inverse()[i]` (`perm.inverted()` brings them back).
///
/// # Errors
/// An index `>= perm.len()` ([`Error::IndexOutOfRange`], `indices`); nothing is changed.
pub fn renumber(perm: Permutation<'_>, indices: &mut [u32]) -> Result<()> {
    check::indices("indices", indices, perm.len())?;
    for i in indices.iter_mut() {
        if let Some(&v) = perm.inverse.get(*i as usize) {
            *i = v;
        }
    }
    Ok(())
}

/// The graph in the new numbering: row `new` is old row `perm.order()[new]`, its targets
/// renumbered and sorted (canonical, as the builders write). `offsets` and `targets` take
/// `g.node_count() + 1` and `g.edge_count()` entries; `edge_map`, when given
/// (`g.edge_count()` entries), receives the old directed-edge index of each new one, for
/// [`gather`] of per-edge data.
///
/// # Errors
/// `perm` of another node count ([`Error::LengthMismatch`], `perm`); `offsets`, `targets`
/// or `edge_map` of the wrong length ([`Error::LengthMismatch`]). Nothing is written on error.
pub fn permute_graph(
    perm: Permutation<'_>,
    g: &Graph<'_>,
    offsets: &mut [u32],
    targets: &mut [u32],
    mut edge_map: Option<&mut [u32]>,
) -> Result<()> {
    let n = g.node_count();
    check::len("perm", perm.len(), n)?;
    check::len("offsets", offsets.len(), n + 1)?;
    check::len("targets", targets.len(), g.edge_count())?;
    if let Some(m) = edge_map.as_deref() {
        check::len("edge_map", m.len(), g.edge_count())?;
    }
    let mut at = 0usize;
    if let Some(o) = offsets.first_mut() {
        *o = 0;
    }
    for (k, &old) in perm.order.iter().enumerate() {
        let range = g.edge_range(old as usize);
        let len = range.len();
        let Some(row) = targets.get_mut(at..at + len) else {
            break;
        };
        for (t, e) in row.iter_mut().zip(range.clone()) {
            let old_t = g.targets().get(e).copied().unwrap_or(0);
            *t = perm.inverse.get(old_t as usize).copied().unwrap_or(0);
        }
        let mut scratch = [0u32; 0];
        let edges = match edge_map
            .as_deref_mut()
            .and_then(|m| m.get_mut(at..at + len))
        {
            Some(m) => {
                for (slot, e) in m.iter_mut().zip(range) {
                    *slot = e as u32;
                }
                m
            }
            None => &mut scratch[..],
        };
        heap_sort(&mut RowWithEdges {
            targets: row,
            edges,
        });
        at += len;
        if let Some(o) = offsets.get_mut(k + 1) {
            *o = at as u32;
        }
    }
    Ok(())
}
