//! The boundary gather shared by the partitioned quaternion pipelines (springs and IDW):
//! the local checks of a [`PartitionedMotion`], the agreement on `B` and `E`, the gather of
//! the whole boundary through the caller's [`Exchange`] (integers as a `sum_words` in which
//! only the contributing process writes each slot, reals as a `max` in which the others write
//! `−∞`; both exact) and the serial boundary stage (origin and rotations) run on it.

use super::super::rotations::{origin_core, rigid_node_rotation, rotations_core};
use super::super::{take, Pts, RotationSource};
use super::PartitionedMotion;
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::order::sort::{heap_sort, ByKey};
use crate::partition::{agree, fault, Exchange, Partition};
use crate::quat::Quat;
use crate::real::Real;

/// Words per gathered boundary node: a presence count and the global id.
const NODE_WORDS: usize = 2;
/// Words per gathered boundary element: a presence count, the VTK kind, up to four nodes.
const ELEMENT_WORDS: usize = 6;
/// Words of the size agreement: fault flag, process count, and for each of `B` and `E` the
/// low and high 16-bit halves and their squares.
const SIZE_WORDS: usize = 10;

/// Length of the gather's words for `B` boundary nodes and `E` elements: `1 + 2 B + 6 E`.
pub(super) fn words_len(b: usize, e: usize) -> usize {
    b.saturating_mul(NODE_WORDS)
        .saturating_add(e.saturating_mul(ELEMENT_WORDS))
        .saturating_add(1)
}

/// Length of the gather's `u32` index (elements, then the global-id order): `5 E + 1 + B`.
pub(super) fn index_len(b: usize, e: usize) -> usize {
    e.saturating_mul(5).saturating_add(1).saturating_add(b)
}

/// Number of boundary elements `motion` declares (0 without elements).
pub(super) fn element_count<T, const D: usize>(motion: &PartitionedMotion<'_, T, D>) -> usize {
    motion.elements.map_or(0, |e| e.count)
}

/// The checks of `motion` one process can make alone, for `owned` owned nodes.
pub(super) fn check_motion<T: Real, const D: usize>(
    motion: &PartitionedMotion<'_, T, D>,
    owned: usize,
) -> Result<()> {
    let b = motion.boundary_count;
    let listed = motion.nodes.len();
    check::len("motion.positions", motion.positions.len(), listed)?;
    check::len("motion.deformed", motion.deformed.len(), listed)?;
    if b == 0 || u32::try_from(b).is_err() {
        return Err(Error::InvalidParameter {
            arg: "motion.boundary_count",
            reason: "must be positive and fit a u32",
        });
    }
    check::indices("motion.nodes", motion.nodes, owned)?;
    check::indices("motion.positions", motion.positions, b)?;
    check::finite_items("motion.deformed", motion.deformed)?;
    check_source(motion)
}

/// The rotation source, origin and elements of `motion`.
fn check_source<T: Real, const D: usize>(motion: &PartitionedMotion<'_, T, D>) -> Result<()> {
    match (motion.rotations, motion.elements) {
        (RotationSource::Shape, None) => {
            return Err(Error::InvalidParameter {
                arg: "motion.elements",
                reason: "is required for rotations from the boundary shape",
            })
        }
        (RotationSource::Rigid(q), _) => check::quats("motion.rotations", &[q])?,
        (RotationSource::PerNode(q), _) => {
            check::len("motion.rotations", q.len(), motion.nodes.len())?;
            check::quats("motion.rotations", q)?;
        }
        (RotationSource::Shape, Some(_)) => {}
    }
    for x in motion.origin.into_iter().flatten() {
        check::scalar("motion.origin", x)?;
    }
    if let Some(e) = motion.elements {
        check::len("elements.ids", e.ids.len(), e.kinds.len())?;
        check::indices("elements.ids", e.ids, e.count)?;
        let cells = Cells::new(motion.boundary_count, e.offsets, e.nodes, e.kinds)?;
        if let Some((c, _)) = cells.iter().enumerate().find(|(_, (_, v))| v.len() > 4) {
            return Err(Error::WrongNodeCount {
                cell: c,
                kind: e.kinds.get(c).copied().unwrap_or(0),
                expected: 4,
                actual: cells.cell(c).map_or(0, |(_, v)| v.len()),
            });
        }
    }
    Ok(())
}

/// Agrees on this process's verdict and on `B` and `E` (the same on every process: each
/// splits into 16-bit halves `h`, and `n Σ h² = (Σ h)²` holds exactly when all `h` are equal).
pub(super) fn agree_sizes<T: Real, E: Exchange<T> + ?Sized, const D: usize>(
    exchange: &E,
    local: Result<()>,
    motion: &PartitionedMotion<'_, T, D>,
) -> Result<()> {
    let mut words = [0i64; SIZE_WORDS];
    if let Some(w) = words.get_mut(1) {
        *w = 1;
    }
    let sizes = [motion.boundary_count, element_count(motion)];
    let halves = sizes.iter().flat_map(|&s| [s & 0xffff, (s >> 16) & 0xffff]);
    for (k, h) in halves.enumerate() {
        let h = h as i64;
        if let Some(w) = words.get_mut(2 + 2 * k) {
            *w = h;
        }
        if let Some(w) = words.get_mut(3 + 2 * k) {
            *w = h * h;
        }
    }
    agree(exchange, local, &mut words)?;
    let count = i128::from(words.get(1).copied().unwrap_or(0));
    let equal = words
        .get(2..)
        .unwrap_or(&[])
        .chunks_exact(2)
        .all(|p| match *p {
            [h, h2] => count * i128::from(h2) == i128::from(h) * i128::from(h),
            _ => false,
        });
    if !equal || motion.boundary_count > u32::MAX as usize {
        return Err(fault(PartitionFault::Boundary, 0));
    }
    Ok(())
}

/// The whole boundary on every process, and what the serial boundary stage made of it.
pub(super) struct Gathered<'w, T, const D: usize> {
    /// Undeformed boundary points in global boundary order.
    pub(super) u: &'w [[T; D]],
    /// Deformed boundary points in global boundary order.
    pub(super) d: &'w [[T; D]],
    /// The boundary rotations as the serial boundary stage gives them (not normalised).
    pub(super) quats: &'w [[T; 4]],
    /// The rotation origin.
    pub(super) origin: [T; D],
    /// The boundary positions sorted by global id (the serial node order).
    pub(super) order: &'w mut [u32],
    /// The position of the smallest global id.
    pub(super) first: usize,
    /// The gathered words (global ids at `1 + 2 k + 1`).
    words: &'w [i64],
}

impl<T, const D: usize> Gathered<'_, T, D> {
    /// Global id of boundary position `k`.
    pub(super) fn global_id(&self, k: usize) -> usize {
        let w = self
            .words
            .get(1 + NODE_WORDS * k + 1)
            .copied()
            .unwrap_or(-1);
        usize::try_from(w).unwrap_or(usize::MAX)
    }
}

/// The buffers of [`gather_boundary`]: `words` ([`words_len`]), `reals` (`(2 D + 4) B` plus the
/// boundary-rotation scratch), `index` ([`index_len`]) and `kinds` (`E`).
pub(super) struct GatherBuffers<'w, T> {
    pub(super) words: &'w mut [i64],
    pub(super) reals: &'w mut [T],
    pub(super) index: &'w mut [u32],
    pub(super) kinds: &'w mut [u8],
}

/// Gathers the boundary of every process and runs the serial boundary stage on it: the origin
/// (`motion.origin` or [`origin_core`]) and the rotations (from the shape, rigid, or the
/// gathered per-node rotations). **Collective**; to be called after [`agree_sizes`].
///
/// # Errors
/// On every process alike (all work on the same merged data): [`PartitionFault::Boundary`]
/// for a boundary position or element given by no process or by two, or one global id at two
/// positions; the errors of [`Cells::new`], [`origin_core`] and [`rotations_core`].
pub(super) fn gather_boundary<'w, T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    part: &Partition<'_>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    buffers: GatherBuffers<'w, T>,
    exchange: &E,
) -> Result<Gathered<'w, T, D>> {
    let b = motion.boundary_count;
    let e = element_count(motion);
    gather_words(part, motion, buffers.words, exchange)?;
    let words: &'w [i64] = buffers.words;
    let (head, rot_scratch) = take(buffers.reals, (2 * D + 4) * b);
    gather_reals(points, motion, head, exchange);
    let (up, quats) = take(head, 2 * D * b);
    let (elements, order) = take(buffers.index, 5 * e + 1);
    let with_elements = motion.elements.is_some();
    let cells = decode_elements(words, b, e, elements, buffers.kinds, with_elements)?;
    let up: &'w [[T; D]] = up.as_chunks::<D>().0;
    let (u, d) = up.split_at(b.min(up.len()));
    let (pu, pd) = (Pts::direct(u), Pts::direct(d));
    let origin = match motion.origin {
        Some(o) => o,
        None => origin_core(pu, pd)?,
    };
    let quats = quats.as_chunks_mut::<4>().0;
    let mut put = |k: usize, q: Quat<T>| {
        if let Some(s) = quats.get_mut(k) {
            *s = q.to_array();
        }
    };
    match (motion.rotations, cells) {
        (RotationSource::Shape, Some(cells)) => rotations_core(pu, pd, &cells, rot_scratch, put)?,
        (RotationSource::Rigid(q), _) => {
            let q = q.normalize()?;
            for k in 0..b {
                put(k, rigid_node_rotation(q, origin, pu.get(k), pd.get(k)));
            }
        }
        (RotationSource::PerNode(_), _) => {}
        (RotationSource::Shape, None) => return Err(fault(PartitionFault::Boundary, 0)),
    }
    let order = order.get_mut(..b).unwrap_or(&mut []);
    let first = sort_by_global_id(words, order)?;
    Ok(Gathered {
        u,
        d,
        quats,
        origin,
        order,
        first,
        words,
    })
}

/// Fills `order` with the boundary positions sorted by global id (the serial node order) and
/// returns the first one (the serial reference for the quaternion hemisphere).
///
/// # Errors
/// [`PartitionFault::Boundary`] when two positions hold one global id.
fn sort_by_global_id(words: &[i64], order: &mut [u32]) -> Result<usize> {
    for (k, o) in order.iter_mut().enumerate() {
        *o = k as u32;
    }
    let gid = |k: u32| {
        words
            .get(1 + NODE_WORDS * k as usize + 1)
            .copied()
            .unwrap_or(i64::MAX)
    };
    heap_sort(&mut ByKey {
        items: order,
        key: gid,
    });
    let same = |w: &[u32]| matches!(*w, [a, b] if gid(a) == gid(b));
    if let Some(p) = order.windows(2).position(same) {
        return Err(fault(PartitionFault::Boundary, p + 1));
    }
    Ok(order.first().map_or(0, |&k| k as usize))
}

/// The gather of the integers: per boundary position its presence count and global id, per
/// element its presence count, kind and nodes (one `sum_words`; each slot written by the one
/// process that gives it).
///
/// # Errors
/// [`PartitionFault::Boundary`] (position: the boundary position, or `B +` the element) when a
/// slot was given by no process or by two: on every process alike.
fn gather_words<T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    part: &Partition<'_>,
    motion: &PartitionedMotion<'_, T, D>,
    words: &mut [i64],
    exchange: &E,
) -> Result<()> {
    let b = motion.boundary_count;
    let e = element_count(motion);
    let words = words.get_mut(..words_len(b, e)).unwrap_or(&mut []);
    words.fill(0);
    for (&i, &p) in motion.nodes.iter().zip(motion.positions) {
        let slot = 1 + NODE_WORDS * p as usize;
        if let Some([count, gid]) = words.get_mut(slot..slot + NODE_WORDS) {
            // Counted, not set: a position listed twice, even by one process, is found.
            *count += 1;
            *gid = part.global_id(i as usize) as i64;
        }
    }
    if let Some(el) = motion.elements {
        let cells = Cells::trusted(b, el.offsets, el.nodes, el.kinds);
        for (&id, (kind, nodes)) in el.ids.iter().zip(cells.iter()) {
            let slot = 1 + NODE_WORDS * b + ELEMENT_WORDS * id as usize;
            if let Some([count, code, rest @ ..]) = words.get_mut(slot..slot + ELEMENT_WORDS) {
                *count += 1;
                *code = i64::from(kind.vtk_code());
                for (x, &v) in rest.iter_mut().zip(nodes) {
                    *x = i64::from(v);
                }
            }
        }
    }
    exchange.sum_words(words);
    let counts = words.iter().skip(1).step_by(NODE_WORDS).take(b).chain(
        words
            .iter()
            .skip(1 + NODE_WORDS * b)
            .step_by(ELEMENT_WORDS)
            .take(e),
    );
    if let Some(p) = counts.clone().position(|&c| c != 1) {
        return Err(fault(PartitionFault::Boundary, p));
    }
    Ok(())
}

/// The gather of the reals (one `max`, `−∞` where another process gives the value): the
/// undeformed then the deformed position of every boundary point into `head[..2 D B]`, and
/// with [`RotationSource::PerNode`] the rotations into `head[2 D B..]` (one `max` over both).
fn gather_reals<T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    head: &mut [T],
    exchange: &E,
) {
    let b = motion.boundary_count;
    head.fill(T::from_f64(f64::NEG_INFINITY));
    let (up, quats) = take(head, 2 * D * b);
    let (u, d) = take(up.as_chunks_mut::<D>().0, b);
    for ((&i, &p), &dk) in motion
        .nodes
        .iter()
        .zip(motion.positions)
        .zip(motion.deformed)
    {
        if let (Some(x), Some(&r)) = (u.get_mut(p as usize), points.get(i as usize)) {
            *x = r;
        }
        if let Some(x) = d.get_mut(p as usize) {
            *x = dk;
        }
    }
    if let RotationSource::PerNode(qs) = motion.rotations {
        let slots = quats.as_chunks_mut::<4>().0;
        for (&p, q) in motion.positions.iter().zip(qs) {
            if let Some(s) = slots.get_mut(p as usize) {
                *s = q.to_array();
            }
        }
        exchange.max(head);
    } else {
        exchange.max(head.get_mut(..2 * D * b).unwrap_or(&mut []));
    }
}

/// The gathered elements as cells over the `B` boundary points (`None` without elements).
///
/// # Errors
/// Those of [`Cells::new`] (on every process alike: the words are the same everywhere).
fn decode_elements<'w>(
    words: &[i64],
    b: usize,
    e: usize,
    index: &'w mut [u32],
    kinds: &'w mut [u8],
    with_elements: bool,
) -> Result<Option<Cells<'w>>> {
    if !with_elements {
        return Ok(None);
    }
    let (offsets, nodes) = take(index, e + 1);
    let slots = words.get(1 + NODE_WORDS * b..).unwrap_or(&[]);
    let mut used = 0usize;
    if let Some(o) = offsets.first_mut() {
        *o = 0;
    }
    for (c, slot) in slots.chunks_exact(ELEMENT_WORDS).take(e).enumerate() {
        let kind = slot.get(1).copied().unwrap_or(0) as u8;
        let count = crate::cells::CellKind::from_vtk(kind).map_or(0, |k| k.node_count());
        for &v in slot.iter().skip(2).take(count) {
            if let Some(x) = nodes.get_mut(used) {
                *x = v as u32;
            }
            used += 1;
        }
        if let Some(k) = kinds.get_mut(c) {
            *k = kind;
        }
        if let Some(o) = offsets.get_mut(c + 1) {
            *o = used as u32;
        }
    }
    let (offsets, nodes, kinds): (&'w [u32], &'w [u32], &'w [u8]) = (offsets, nodes, kinds);
    let nodes = nodes.get(..used).unwrap_or(&[]);
    Cells::new(b, offsets, nodes, kinds.get(..e).unwrap_or(&[])).map(Some)
}
