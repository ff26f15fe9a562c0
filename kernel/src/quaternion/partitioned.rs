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
//! deformation (the `max` takes `4 B` more reals with [`RotationSource::PerNode`], whose
//! rotations it gathers too); and `2 D B + 4 B` reals of storage per process.
//!
//! [`deform_idw_partitioned`] gathers the same way and then weighs the gathered boundary into
//! each owned node exactly as [`propagate_idw`](super::propagate_idw) does (no solve).

mod gather;
mod idw;

pub use idw::{
    deform_idw_partitioned, deform_idw_partitioned_lens, PartitionedIdwLens,
    PartitionedIdwWorkspace,
};

use super::rotations::translation;
use super::springs::{pack, unpack};
use super::update::apply;
use super::{boundary_rotations_scratch_len, Pts, RotationSource};
use crate::check;
use crate::error::{Error, Result};
use crate::partition::{agree, Exchange};
use crate::quat::Quat;
use crate::real::Real;
use crate::spring::{
    partitioned_cg_scratch_len, PartitionedSprings, Preconditioner, SolveOptions, SolveReport,
};
use gather::{
    agree_sizes, check_motion, element_count, gather_boundary, index_len, words_len, GatherBuffers,
};

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
    /// The owned local nodes on the boundary, distinct (for the springs exactly the owned
    /// nodes the fixed mask marks).
    pub nodes: &'a [u32],
    /// Position of each in the global boundary list (the serial `motion.nodes` order).
    pub positions: &'a [u32],
    /// Deformed position of each.
    pub deformed: &'a [[T; D]],
    /// Number of boundary nodes over all processes (`B`, the same on every process).
    pub boundary_count: usize,
    /// This process's boundary elements (needed for [`RotationSource::Shape`]).
    pub elements: Option<BoundaryElements<'a>>,
    /// Where the rotations come from; [`RotationSource::PerNode`] gives one rotation per entry
    /// of `nodes` (in `nodes` order, gathered to every process with the points).
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
        words: words_len(b, e),
        reals: b
            .saturating_mul(2 * D + 4)
            .saturating_add(boundary_rotations_scratch_len::<D>(b)),
        index: index_len(b, e),
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
/// On every process alike (a process's own error, [`PartitionFault::OtherProcess`](crate::error::PartitionFault::OtherProcess) on the
/// others): lengths and buffers, non-finite points, a listed node that is not an owned fixed
/// node or an owned fixed node not listed, positions or element ids out of range, bad element
/// arrays, per-node rotations not one per listed node or not normalisable; `B` or `E` differing
/// between processes, or a boundary position or element given by no process or by two
/// ([`Error::BadPartition`] with [`PartitionFault::Boundary`](crate::error::PartitionFault::Boundary)); then the errors of the serial
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
    let lens = deform_spring_partitioned_lens::<D>(n, b, element_count(motion));
    check::buffer("work.words", work.words.len(), lens.words)?;
    check::buffer("work.reals", work.reals.len(), lens.reals)?;
    check::buffer("work.index", work.index.len(), lens.index)?;
    check::buffer("work.kinds", work.kinds.len(), lens.kinds)?;
    check::buffer("work.values", work.values.len(), lens.values)?;
    check_motion(motion, owned)?;
    check::finite_items("points", points.get(..owned).unwrap_or(&[]))?;
    let sys = springs.system();
    let fixed_owned = (0..owned).filter(|&i| sys.is_fixed(i)).count();
    let all_fixed = motion.nodes.iter().all(|&i| sys.is_fixed(i as usize));
    if !all_fixed || fixed_owned != motion.nodes.len() {
        return Err(Error::InvalidParameter {
            arg: "motion.nodes",
            reason: "must list exactly the owned nodes the fixed mask marks",
        });
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
    let buffers = GatherBuffers {
        words: work.words,
        reals: work.reals,
        index: work.index,
        kinds: work.kinds,
    };
    let g = gather_boundary(springs.partition(), points, motion, buffers, exchange)?;
    let boundary = Boundary {
        u: Pts::direct(g.u),
        d: Pts::direct(g.d),
        quats: g.quats,
        origin: g.origin,
        reference: g
            .quats
            .get(g.first)
            .map_or(Quat::identity(), |&q| Quat::from_array(q)),
    };
    let order: &[u32] = g.order;
    let origin = g.origin;
    let values = work.values.as_chunks_mut::<V>().0;
    let (values, scratch) = super::take(values, springs.partition().local_count());
    start::<T, D, V>(motion, &boundary, order, values);
    let report = springs.solve_cg(values, preconditioner, options, scratch, exchange)?;
    check_solved::<T, D, V, E>(springs, values, exchange)?;
    update_owned::<T, D, V>(springs, points, motion, &boundary, values, out);
    Ok((origin, report))
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
