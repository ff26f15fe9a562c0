//! A plan's node order ([`PlanSpec::renumber`]): the mesh as the plan stores it (the
//! caller's, or renumbered in the init work), the stored permutation, and errors mapped back
//! to the caller's numbering.

use super::layout::Sections;
use super::{PlanOrder, PlanSpec, PlanStiffness, PlanWork};
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::order::{gather, hilbert_order_words, permute, permute_graph, rcm_order, Permutation};
use crate::real::Real;
use crate::spring::batina_stiffness;

/// The mesh a plan is built on, in the plan's numbering.
pub(super) struct Mesh<'m, T, const D: usize> {
    pub graph: Graph<'m>,
    pub points: &'m [[T; D]],
    pub stiffness: &'m [T],
    /// The fixed mask (1 at the boundary nodes).
    pub mask: &'m [u8],
    /// `order[new] = old`; `None`: the caller's numbering.
    pub perm: Option<Permutation<'m>>,
    /// The old directed-edge index of each new one (empty without `perm`).
    pub edge_map: &'m [u32],
    /// The rest of the index work (anchoring search, the hierarchy's symbolic pass).
    pub scratch: &'m mut [u32],
}

/// Index work words an ordered plan takes before the scratch: the permutation (`2 n`), the
/// permuted graph (`n + 1 + e`) and its edge map (`e`).
pub(super) const fn ordered_words(n: usize, e: usize) -> usize {
    n.saturating_mul(3)
        .saturating_add(1)
        .saturating_add(e.saturating_mul(2))
}

/// Splits the first `len` items off `s`.
fn carve<'b, X>(s: &mut &'b mut [X], len: usize) -> &'b mut [X] {
    let t = core::mem::take(s);
    let (a, b) = t.split_at_mut_checked(len).unwrap_or_default();
    *s = b;
    a
}

/// The mesh in the plan's numbering. `work.bytes` holds the fixed mask in the caller's
/// numbering (validated); the work lengths are checked. The stiffness (Batina's, or the given
/// one gathered) and, for a renumbered plan, the permutation, graph, points and mask are
/// written to the work buffers.
pub(super) fn mesh<'m, T: Real, const D: usize>(
    spec: &PlanSpec<'m, T, D>,
    work: &'m mut PlanWork<'_, T>,
) -> Result<Mesh<'m, T, D>> {
    let n = spec.graph.node_count();
    let e = spec.graph.edge_count();
    let PlanWork {
        reals,
        indices,
        bytes,
    } = work;
    let (k_work, p_work) = reals.split_at_mut_checked(e).unwrap_or_default();
    let mask = bytes.get_mut(..n).unwrap_or(&mut []);
    if spec.renumber == PlanOrder::AsGiven {
        let stiffness: &'m [T] = match spec.stiffness {
            PlanStiffness::Given(k) => k,
            PlanStiffness::Batina { exponent } => {
                batina_stiffness(&spec.graph, spec.points, exponent, k_work)?;
                k_work
            }
        };
        return Ok(Mesh {
            graph: spec.graph,
            points: spec.points,
            stiffness,
            mask,
            perm: None,
            edge_map: &[],
            scratch: indices,
        });
    }
    let mut rest: &'m mut [u32] = indices;
    let order = carve(&mut rest, n);
    let inverse = carve(&mut rest, n);
    let offsets = carve(&mut rest, n + 1);
    let targets = carve(&mut rest, e);
    let edge_map = carve(&mut rest, e);
    match spec.renumber {
        PlanOrder::Hilbert => hilbert_order_words(spec.points, order, inverse, rest),
        _ => rcm_order(&spec.graph, order, inverse)?,
    }
    let perm = Permutation::new(order, inverse)?;
    let points = p_work
        .as_chunks_mut::<D>()
        .0
        .get_mut(..n)
        .unwrap_or(&mut []);
    permute(perm, spec.points, points)?;
    permute_graph(perm, &spec.graph, offsets, targets, Some(&mut *edge_map))?;
    let graph = Graph::trusted(offsets, targets);
    let edge_map: &'m [u32] = edge_map;
    let points: &'m [[T; D]] = points;
    match spec.stiffness {
        PlanStiffness::Given(k) => gather(edge_map, k, k_work)?,
        PlanStiffness::Batina { exponent } => batina_stiffness(&graph, points, exponent, k_work)
            .map_err(|err| to_caller(err, Some(perm), edge_map, false))?,
    }
    // The mask in the new numbering (the boundary was checked in range and distinct).
    mask.fill(0);
    for &old in spec.boundary {
        if let Some(m) = inverse_of(perm, old).and_then(|i| mask.get_mut(i as usize)) {
            *m = 1;
        }
    }
    Ok(Mesh {
        graph,
        points,
        stiffness: k_work,
        mask,
        perm: Some(perm),
        edge_map,
        scratch: rest,
    })
}

/// `perm.inverse()[old]`.
#[inline]
pub(super) fn inverse_of(perm: Permutation<'_>, old: u32) -> Option<u32> {
    perm.inverse().get(old as usize).copied()
}

/// An error of the permuted system in the caller's numbering: node indices through
/// `order`, and (`edges`: the stiffness positions are directed edges, as
/// [`SpringSystem::new`](crate::spring::SpringSystem::new) reports them; otherwise nodes, as
/// [`batina_stiffness`] does) stiffness positions through `edge_map`.
pub(super) fn to_caller(
    err: Error,
    perm: Option<Permutation<'_>>,
    edge_map: &[u32],
    edges: bool,
) -> Error {
    let Some(p) = perm else { return err };
    let node = |i: usize| p.order().get(i).map_or(i, |&o| o as usize);
    let position = |i: usize| match edges {
        true => edge_map.get(i).map_or(i, |&o| o as usize),
        false => node(i),
    };
    match err {
        Error::NotSymmetric { from, to } => Error::NotSymmetric {
            from: node(from),
            to: node(to),
        },
        Error::ZeroLengthEdge { from, to } => Error::ZeroLengthEdge {
            from: node(from),
            to: node(to),
        },
        Error::Unanchored { node: i } => Error::Unanchored { node: node(i) },
        Error::NonFinite {
            arg: "stiffness",
            position: i,
        } => Error::NonFinite {
            arg: "stiffness",
            position: position(i),
        },
        Error::NonPositive {
            arg: "stiffness",
            position: i,
        } => Error::NonPositive {
            arg: "stiffness",
            position: position(i),
        },
        other => other,
    }
}

/// The permutation stored in a renumbered plan's index pool, `None` when there is none or it
/// is not one (checked in `O(N)`).
pub(super) fn stored<'p>(sec: &Sections, indices: &'p [u32]) -> Option<Permutation<'p>> {
    let words = indices.get(sec.perm.clone())?;
    if words.is_empty() {
        return None;
    }
    let (order, inverse) = words.split_at_checked(words.len() / 2)?;
    Permutation::new(order, inverse).ok()
}
