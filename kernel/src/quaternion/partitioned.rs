//! Samareh's quaternion deformation with spring propagation on distributed data
//! ([`deform_spring_partitioned`]): each process passes its partition's springs
//! ([`PartitionedSprings`]) and the boundary nodes it owns, and gets the serial
//! [`deform_spring_with`](super::deform_spring_with) result (CG + Jacobi) on its owned nodes,
//! bit for bit.
//!
//! **How.** The boundary stage needs every boundary node (a wall node's normal needs its
//! neighbours, which may live on other processes; the origin and the cold start are means over
//! the whole boundary), and the boundary is small, so it is *gathered* to every process through
//! the caller's [`Exchange`] without a new primitive: integers (global ids, elements) as a
//! `sum_words` in which only the contributing process writes each slot (the others write 0),
//! reals as a `max` in which the others write `−∞` (both exact). Every process then runs the
//! serial functions ([`origin_core`](super::origin_core),
//! [`rotations_core`](super::rotations_core), [`translation`](super::translation)) on the
//! gathered boundary in the global boundary order, forms the cold start in global-id order (the
//! serial node order), solves the `V = D + 4` lanes with [`PartitionedSprings::solve_cg`], and
//! updates its owned nodes as [`update_points`](super::update_points) does.
//!
//! **Cost** (docs/scaling.md): two small `sum_words` (agreement), one `sum_words` of
//! `2 B + 6 E + 1` words and one `max` of `2 D B` reals (`B` boundary nodes, `E` boundary
//! elements), i.e. `8 (2 B + 6 E + 1) + 8 · 2 D B` bytes per process for `f64`, once per
//! deformation; and `2 D B + 4 B` reals of storage per process.

use super::rotations::{origin_core, rigid_node_rotation, rotations_core, translation};
use super::springs::{pack, unpack};
use super::update::apply;
use super::{boundary_rotations_scratch_len, Pts, RotationSource};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::order::sort::{heap_sort, ByKey};
use crate::partition::{agree, fault, Exchange};
use crate::quat::Quat;
use crate::real::Real;
use crate::spring::{
    partitioned_cg_scratch_len, PartitionedSprings, Preconditioner, SolveOptions, SolveReport,
};

/// Words per gathered boundary node: a presence count and the global id.
const NODE_WORDS: usize = 2;
/// Words per gathered boundary element: a presence count, the VTK kind, up to four nodes.
const ELEMENT_WORDS: usize = 6;
/// Words of the size agreement: fault flag, process count, and for each of `B` and `E` the
/// low and high 16-bit halves and their squares.
const SIZE_WORDS: usize = 10;

/// The boundary elements one process contributes, each given by exactly one process (for
/// example the owner of its first node), in global boundary numbering.
#[derive(Clone, Copy, Debug)]
pub struct BoundaryElements<'a> {
    /// Global element number of each element (`< count`): the serial element order.
    pub ids: &'a [u32],
    /// CSR offsets into `nodes` (`ids.len() + 1` entries).
    pub offsets: &'a [u32],
    /// The elements' nodes as positions in the global boundary list.
    pub nodes: &'a [u32],
    /// VTK kinds (segments in 2D, triangles/quadrilaterals in 3D).
    pub kinds: &'a [u8],
    /// Number of boundary elements over all processes (`E`, the same on every process).
    pub count: usize,
}

/// One process's share of the prescribed boundary motion.
#[derive(Clone, Copy, Debug)]
pub struct PartitionedMotion<'a, T, const D: usize> {
    /// The owned local nodes on the boundary: exactly the owned nodes the springs' fixed mask
    /// marks.
    pub nodes: &'a [u32],
    /// Position of each in the global boundary list (the serial `motion.nodes` order).
    pub positions: &'a [u32],
    /// Deformed position of each.
    pub deformed: &'a [[T; D]],
    /// Number of boundary nodes over all processes (`B`, the same on every process).
    pub boundary_count: usize,
    /// This process's boundary elements (needed for [`RotationSource::Shape`]).
    pub elements: Option<BoundaryElements<'a>>,
    /// [`RotationSource::Shape`] or [`RotationSource::Rigid`].
    pub rotations: RotationSource<'a, T>,
    /// The rotation origin; `None` for the centroid of the moving boundary.
    pub origin: Option<[T; D]>,
}

/// The buffers of [`deform_spring_partitioned`] (contents unspecified afterwards).
#[derive(Debug)]
pub struct PartitionedWorkspace<'w, T> {
    /// The gather's words: [`PartitionedLens::words`].
    pub words: &'w mut [i64],
    /// The gathered points, rotations and the rotation scratch: [`PartitionedLens::reals`].
    pub reals: &'w mut [T],
    /// The gathered elements and the global-id order: [`PartitionedLens::index`].
    pub index: &'w mut [u32],
    /// The gathered element kinds: [`PartitionedLens::kinds`].
    pub kinds: &'w mut [u8],
    /// The packed solve: [`PartitionedLens::values`].
    pub values: &'w mut [T],
}

/// Lengths of the [`PartitionedWorkspace`] buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartitionedLens {
    /// `1 + 2 B + 6 E`.
    pub words: usize,
    /// `2 D B + 4 B` plus the boundary-rotation scratch.
    pub reals: usize,
    /// `5 E + 1 + B`.
    pub index: usize,
    /// `E`.
    pub kinds: usize,
    /// `(D + 4) (n + cg scratch)` for `n` local nodes.
    pub values: usize,
}

/// The workspace lengths for `local_count` local nodes, `B` boundary nodes and `E` boundary
/// elements in dimension `D`.
pub fn deform_spring_partitioned_lens<const D: usize>(
    local_count: usize,
    boundary_count: usize,
    element_count: usize,
) -> PartitionedLens {
    let (b, e) = (boundary_count, element_count);
    let cg = if D == 2 {
        partitioned_cg_scratch_len::<6>(local_count)
    } else {
        partitioned_cg_scratch_len::<7>(local_count)
    };
    PartitionedLens {
        words: b
            .saturating_mul(NODE_WORDS)
            .saturating_add(e.saturating_mul(ELEMENT_WORDS))
            .saturating_add(1),
        reals: b
            .saturating_mul(2 * D + 4)
            .saturating_add(boundary_rotations_scratch_len::<D>(b)),
        index: e.saturating_mul(5).saturating_add(1).saturating_add(b),
        kinds: e,
        values: local_count.saturating_add(cg).saturating_mul(D + 4),
    }
}

/// The quaternion deformation with linear-spring propagation on distributed data: the result
/// of the serial [`deform_spring_with`](super::deform_spring_with) with CG and
/// `preconditioner` (Jacobi or none) on the whole mesh, bit for bit, written to `out` at the
/// owned nodes (`out[i]` for local node `i < owned`). `points` are the local undeformed points
/// (those given to [`PartitionedSprings::new`]). Returns the origin and the solver report.
/// **Collective**: every process calls it, and all return `Ok` or all `Err`.
///
/// # Errors
/// On every process alike (a process's own error, [`PartitionFault::OtherProcess`] on the
/// others): lengths and buffers, non-finite points, a listed node that is not an owned fixed
/// node or an owned fixed node not listed, positions or element ids out of range, bad element
/// arrays, [`RotationSource::PerNode`] ([`Error::InvalidParameter`]); `B` or `E` differing
/// between processes, or a boundary position or element given by no process or by two
/// ([`Error::BadPartition`] with [`PartitionFault::Boundary`]); then the errors of the serial
/// boundary stage and of [`PartitionedSprings::solve_cg`], and [`Error::ZeroLength`]
/// (`"rotations"`, position = global id) for a solved quaternion that cancels. `out` is
/// unchanged on error.
#[allow(clippy::too_many_arguments)]
pub fn deform_spring_partitioned<T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    springs: &PartitionedSprings<'_, T>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    preconditioner: Preconditioner<T>,
    options: &SolveOptions<T>,
    work: PartitionedWorkspace<'_, T>,
    out: &mut [[T; D]],
    exchange: &E,
) -> Result<([T; D], SolveReport<T>)> {
    check::mesh_dim::<D>();
    let local = check_local(springs, points, motion, &work, out.len());
    agree_sizes(exchange, local, motion)?;
    if D == 2 {
        run::<T, D, 6, E>(
            springs,
            points,
            motion,
            preconditioner,
            options,
            work,
            out,
            exchange,
        )
    } else {
        run::<T, D, 7, E>(
            springs,
            points,
            motion,
            preconditioner,
            options,
            work,
            out,
            exchange,
        )
    }
}

/// Number of boundary elements `motion` declares (0 without elements).
fn element_count<T, const D: usize>(motion: &PartitionedMotion<'_, T, D>) -> usize {
    motion.elements.map_or(0, |e| e.count)
}

/// Everything one process can check alone.
fn check_local<T: Real, const D: usize>(
    springs: &PartitionedSprings<'_, T>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    work: &PartitionedWorkspace<'_, T>,
    out_len: usize,
) -> Result<()> {
    let part = springs.partition();
    let (n, owned, b) = (part.local_count(), part.owned(), motion.boundary_count);
    check::len("points", points.len(), n)?;
    check::len("out", out_len, owned)?;
    check::len(
        "motion.positions",
        motion.positions.len(),
        motion.nodes.len(),
    )?;
    check::len("motion.deformed", motion.deformed.len(), motion.nodes.len())?;
    let lens = deform_spring_partitioned_lens::<D>(n, b, element_count(motion));
    check::buffer("work.words", work.words.len(), lens.words)?;
    check::buffer("work.reals", work.reals.len(), lens.reals)?;
    check::buffer("work.index", work.index.len(), lens.index)?;
    check::buffer("work.kinds", work.kinds.len(), lens.kinds)?;
    check::buffer("work.values", work.values.len(), lens.values)?;
    if b == 0 || u32::try_from(b).is_err() {
        return Err(Error::InvalidParameter {
            arg: "motion.boundary_count",
            reason: "must be positive and fit a u32",
        });
    }
    check::indices("motion.nodes", motion.nodes, owned)?;
    check::indices("motion.positions", motion.positions, b)?;
    check::finite_items("points", points.get(..owned).unwrap_or(&[]))?;
    check::finite_items("motion.deformed", motion.deformed)?;
    let sys = springs.system();
    let fixed_owned = (0..owned).filter(|&i| sys.is_fixed(i)).count();
    let all_fixed = motion.nodes.iter().all(|&i| sys.is_fixed(i as usize));
    if !all_fixed || fixed_owned != motion.nodes.len() {
        return Err(Error::InvalidParameter {
            arg: "motion.nodes",
            reason: "must list exactly the owned nodes the fixed mask marks",
        });
    }
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
        (RotationSource::PerNode(_), _) => {
            return Err(Error::InvalidParameter {
                arg: "motion.rotations",
                reason: "partitioned: from the shape or one rigid rotation",
            })
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
fn agree_sizes<T: Real, E: Exchange<T> + ?Sized, const D: usize>(
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

/// The stages after the agreement, with `V = D + 4` lanes.
#[allow(clippy::too_many_arguments)]
fn run<T: Real, const D: usize, const V: usize, E: Exchange<T> + ?Sized>(
    springs: &PartitionedSprings<'_, T>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    preconditioner: Preconditioner<T>,
    options: &SolveOptions<T>,
    work: PartitionedWorkspace<'_, T>,
    out: &mut [[T; D]],
    exchange: &E,
) -> Result<([T; D], SolveReport<T>)> {
    let b = motion.boundary_count;
    let e = element_count(motion);
    gather_words(springs, motion, work.words, exchange)?;
    let (up, rest) = super::take(work.reals, 2 * D * b);
    gather_points(points, motion, up, exchange);
    let (quats, rot_scratch) = super::take(rest, 4 * b);
    let (elements, order) = super::take(work.index, 5 * e + 1);
    let words: &[i64] = work.words;
    let cells = decode_elements(words, b, e, elements, work.kinds, motion.elements.is_some())?;
    let up = up.as_chunks::<D>().0;
    let (u, d) = up.split_at(b.min(up.len()));
    let (u, d) = (Pts::direct(u), Pts::direct(d));
    let origin = match motion.origin {
        Some(o) => o,
        None => origin_core(u, d)?,
    };
    let quats = quats.as_chunks_mut::<4>().0;
    let mut put = |k: usize, q: Quat<T>| {
        if let Some(s) = quats.get_mut(k) {
            *s = q.to_array();
        }
    };
    match (motion.rotations, cells) {
        (RotationSource::Shape, Some(cells)) => rotations_core(u, d, &cells, rot_scratch, put)?,
        (RotationSource::Rigid(q), _) => {
            let q = q.normalize()?;
            for k in 0..b {
                put(k, rigid_node_rotation(q, origin, u.get(k), d.get(k)));
            }
        }
        _ => return Err(fault(PartitionFault::Boundary, 0)),
    }
    let order = order.get_mut(..b).unwrap_or(&mut []);
    let reference = sort_by_global_id(words, order)?;
    let quats: &[[T; 4]] = quats;
    let boundary = Boundary {
        u,
        d,
        quats,
        origin,
        reference: quats
            .get(reference)
            .map_or(Quat::identity(), |&q| Quat::from_array(q)),
    };
    let values = work.values.as_chunks_mut::<V>().0;
    let (values, scratch) = super::take(values, springs.partition().local_count());
    start::<T, D, V>(motion, &boundary, order, values);
    let report = springs.solve_cg(values, preconditioner, options, scratch, exchange)?;
    check_solved::<T, D, V, E>(springs, values, exchange)?;
    update_owned::<T, D, V>(springs, points, motion, &boundary, values, out);
    Ok((origin, report))
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
    springs: &PartitionedSprings<'_, T>,
    motion: &PartitionedMotion<'_, T, D>,
    words: &mut [i64],
    exchange: &E,
) -> Result<()> {
    let b = motion.boundary_count;
    let e = element_count(motion);
    let words = words
        .get_mut(..1 + NODE_WORDS * b + ELEMENT_WORDS * e)
        .unwrap_or(&mut []);
    words.fill(0);
    let part = springs.partition();
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

/// The gather of the reals (one `max`): undeformed then deformed position of every boundary
/// point, `−∞` where another process gives it.
fn gather_points<T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    up: &mut [T],
    exchange: &E,
) {
    let b = motion.boundary_count;
    up.fill(T::from_f64(f64::NEG_INFINITY));
    let up_items = up.as_chunks_mut::<D>().0;
    let (u, d) = super::take(up_items, b);
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
    exchange.max(up);
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
    let (offsets, nodes) = super::take(index, e + 1);
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

/// The gathered boundary and what the serial boundary stage made of it.
struct Boundary<'b, T, const D: usize> {
    u: Pts<'b, T, D>,
    d: Pts<'b, T, D>,
    quats: &'b [[T; 4]],
    origin: [T; D],
    /// The rotation of the boundary node with the smallest global id.
    reference: Quat<T>,
}

impl<T: Real, const D: usize> Boundary<'_, T, D> {
    /// Boundary point `k`'s packed `(Δ, Q)` as the serial propagation packs it: `Δ` from the
    /// normalised rotation, `Q` as computed, flipped into the reference's hemisphere.
    fn packed<const V: usize>(&self, k: usize) -> [T; V] {
        let q = self
            .quats
            .get(k)
            .map_or(Quat::identity(), |&q| Quat::from_array(q));
        let unit = q.normalize().unwrap_or(Quat::identity());
        let t = translation(self.origin, self.u.get(k), self.d.get(k), unit);
        let q = if q.dot(self.reference) < T::ZERO {
            -q
        } else {
            q
        };
        pack(t, q)
    }
}

/// The cold start of the packed solve: owned boundary nodes their packed values, every other
/// node the mean of all boundary values summed in global-id order (the serial node order).
fn start<T: Real, const D: usize, const V: usize>(
    motion: &PartitionedMotion<'_, T, D>,
    boundary: &Boundary<'_, T, D>,
    order: &[u32],
    values: &mut [[T; V]],
) {
    let mut mean = [T::ZERO; V];
    for &k in order {
        for (m, x) in mean.iter_mut().zip(boundary.packed::<V>(k as usize)) {
            *m += x;
        }
    }
    let c = T::from_usize(order.len().max(1));
    for m in mean.iter_mut() {
        *m /= c;
    }
    values.fill(mean);
    for (&i, &p) in motion.nodes.iter().zip(motion.positions) {
        if let Some(v) = values.get_mut(i as usize) {
            *v = boundary.packed::<V>(p as usize);
        }
    }
}

/// Checks that every owned free node's solved quaternion normalises; agreed by all processes.
///
/// # Errors
/// [`Error::ZeroLength`] (`"rotations"`, position = global id) where one does not.
fn check_solved<T: Real, const D: usize, const V: usize, E: Exchange<T> + ?Sized>(
    springs: &PartitionedSprings<'_, T>,
    values: &[[T; V]],
    exchange: &E,
) -> Result<()> {
    let (part, sys) = (springs.partition(), springs.system());
    let bad = values
        .iter()
        .take(part.owned())
        .enumerate()
        .find(|(i, v)| !sys.is_fixed(*i) && unpack::<T, D, V>(v).1.normalize().is_err());
    let local = match bad {
        Some((i, _)) => Err(Error::ZeroLength {
            arg: "rotations",
            position: part.global_id(i) as usize,
        }),
        None => Ok(()),
    };
    agree(exchange, local, &mut [0i64])
}

/// The field update of the owned nodes as [`update_points`](super::update_points) does it:
/// free nodes `o + Δ + Q (R − o) Q*` with the serial normalisations, boundary nodes their
/// deformed positions exactly.
fn update_owned<T: Real, const D: usize, const V: usize>(
    springs: &PartitionedSprings<'_, T>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    boundary: &Boundary<'_, T, D>,
    values: &[[T; V]],
    out: &mut [[T; D]],
) {
    let sys = springs.system();
    for (i, ((o, r), v)) in out.iter_mut().zip(points).zip(values).enumerate() {
        if !sys.is_fixed(i) {
            let (t, q) = unpack::<T, D, V>(v);
            let q = q.normalize().unwrap_or(boundary.reference);
            let q = q.normalize().unwrap_or(Quat::identity());
            *o = apply(boundary.origin, *r, t, q);
        }
    }
    for (&i, &d) in motion.nodes.iter().zip(motion.deformed) {
        if let Some(o) = out.get_mut(i as usize) {
            *o = d;
        }
    }
}
