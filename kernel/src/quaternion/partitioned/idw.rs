//! Samareh's quaternion deformation with inverse-distance propagation on distributed data
//! ([`deform_idw_partitioned`]): the boundary is gathered to every process as for the
//! springs, and each process weighs it into its owned nodes with the serial
//! [`propagate_idw`](crate::quaternion::propagate_idw) arithmetic, in the serial boundary
//! order, so every owned node gets the serial [`deform_idw`](crate::quaternion::deform_idw)
//! bits. No halo exchange and no solve: the field values depend on the boundary alone.

use super::super::propagate::idw_point;
use super::super::rotations::translation;
use super::super::update::apply;
use super::super::{boundary_rotations_scratch_len, check_exponent, take, Pts};
use super::gather::{
    agree_sizes, check_motion, element_count, gather_boundary, index_len, words_len, GatherBuffers,
    Gathered,
};
use super::PartitionedMotion;
use crate::check;
use crate::error::{Error, Result};
use crate::partition::{agree, Exchange, Partition};
use crate::quat::Quat;
use crate::real::Real;

/// The buffers of [`deform_idw_partitioned`] (contents unspecified afterwards).
#[derive(Debug)]
pub struct PartitionedIdwWorkspace<'w, T> {
    /// The gather's words: [`PartitionedIdwLens::words`].
    pub words: &'w mut [i64],
    /// The gathered points, translations and the rotation scratch:
    /// [`PartitionedIdwLens::reals`].
    pub reals: &'w mut [T],
    /// The gathered elements and the global-id order: [`PartitionedIdwLens::index`].
    pub index: &'w mut [u32],
    /// The gathered element kinds: [`PartitionedIdwLens::kinds`].
    pub kinds: &'w mut [u8],
    /// The boundary rotations: [`PartitionedIdwLens::rotations`].
    pub rotations: &'w mut [Quat<T>],
}

/// Lengths of the [`PartitionedIdwWorkspace`] buffers: all in the boundary's size, none in the
/// mesh's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartitionedIdwLens {
    /// `1 + 2 B + 6 E`.
    pub words: usize,
    /// `3 D B + 4 B` plus the boundary-rotation scratch.
    pub reals: usize,
    /// `5 E + 1 + B`.
    pub index: usize,
    /// `E`.
    pub kinds: usize,
    /// `B`.
    pub rotations: usize,
}

/// The workspace lengths for `B` boundary nodes and `E` boundary elements in dimension `D`.
pub fn deform_idw_partitioned_lens<const D: usize>(
    boundary_count: usize,
    element_count: usize,
) -> PartitionedIdwLens {
    let (b, e) = (boundary_count, element_count);
    PartitionedIdwLens {
        words: words_len(b, e),
        reals: b
            .saturating_mul(3 * D + 4)
            .saturating_add(boundary_rotations_scratch_len::<D>(b)),
        index: index_len(b, e),
        kinds: e,
        rotations: b,
    }
}

/// The quaternion deformation with inverse-distance propagation on distributed data: the
/// result of the serial [`deform_idw`](crate::quaternion::deform_idw) with `exponent` on the
/// whole mesh (whose boundary, in the global boundary order, is the serial `motion.nodes`),
/// bit for bit, written to `out` at the owned nodes (`out[i]` for local node `i < owned`).
/// `points` are the local undeformed points (`partition.local_count()`; only the owned ones
/// are read). Returns the origin. **Collective**: every process calls it, and all return `Ok`
/// or all `Err`.
///
/// Cost: the gather of [`deform_spring_partitioned`](super::deform_spring_partitioned)
/// (docs/scaling.md), then `O(owned · B)` distance evaluations; no halo exchange.
///
/// # Errors
/// On every process alike (a process's own error,
/// [`PartitionFault::OtherProcess`](crate::error::PartitionFault::OtherProcess) on the others):
/// lengths and buffers, non-finite owned points, a bad exponent, listed nodes not owned,
/// positions or element ids out of range, bad element arrays, per-node rotations not one per
/// listed node or not normalisable; `B` or `E` differing between processes, a boundary
/// position or element given by no process or by two, or one global id at two positions
/// ([`Error::BadPartition`] with
/// [`PartitionFault::Boundary`](crate::error::PartitionFault::Boundary)); then the errors of the
/// serial boundary stage, and those of [`propagate_idw`](crate::quaternion::propagate_idw) for
/// the boundary values ([`Error::NonFinite`], [`Error::ZeroLength`]; position = global id).
/// `out` is unchanged on all these errors. Only a propagated translation that overflows
/// (boundary displacements near the largest finite value; [`Error::NonFinite`],
/// `"translations"`, position = global id) is found after `out` was written.
pub fn deform_idw_partitioned<T: Real, const D: usize, E: Exchange<T> + ?Sized>(
    partition: &Partition<'_>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    exponent: T,
    work: PartitionedIdwWorkspace<'_, T>,
    out: &mut [[T; D]],
    exchange: &E,
) -> Result<[T; D]> {
    check::mesh_dim::<D>();
    let local = check_local(partition, points, motion, exponent, &work, out.len());
    agree_sizes(exchange, local, motion)?;
    let b = motion.boundary_count;
    let (translations, reals) = take(work.reals, D * b);
    let buffers = GatherBuffers {
        words: work.words,
        reals,
        index: work.index,
        kinds: work.kinds,
    };
    let g = gather_boundary(partition, points, motion, buffers, exchange)?;
    let translations = translations.as_chunks_mut::<D>().0;
    let rotations = work.rotations.get_mut(..b).unwrap_or(&mut []);
    boundary_values(&g, translations, rotations)?;
    // The boundary as the serial IDW sees it: positions `0..B` into the gathered points.
    for (k, o) in g.order.iter_mut().enumerate() {
        *o = k as u32;
    }
    let field = Field {
        points: g.u,
        boundary: g.order,
        exponent,
        translations,
        rotations,
        origin: g.origin,
    };
    let bad = field.update_owned(points, motion, out);
    let local = match bad {
        Some(i) => Err(Error::NonFinite {
            arg: "translations",
            position: partition.global_id(i) as usize,
        }),
        None => Ok(()),
    };
    agree(exchange, local, &mut [0i64])?;
    Ok(g.origin)
}

/// Everything one process can check alone.
fn check_local<T: Real, const D: usize>(
    part: &Partition<'_>,
    points: &[[T; D]],
    motion: &PartitionedMotion<'_, T, D>,
    exponent: T,
    work: &PartitionedIdwWorkspace<'_, T>,
    out_len: usize,
) -> Result<()> {
    let (n, owned) = (part.local_count(), part.owned());
    check::len("points", points.len(), n)?;
    check::len("out", out_len, owned)?;
    let lens = deform_idw_partitioned_lens::<D>(motion.boundary_count, element_count(motion));
    check::buffer("work.words", work.words.len(), lens.words)?;
    check::buffer("work.reals", work.reals.len(), lens.reals)?;
    check::buffer("work.index", work.index.len(), lens.index)?;
    check::buffer("work.kinds", work.kinds.len(), lens.kinds)?;
    check::buffer("work.rotations", work.rotations.len(), lens.rotations)?;
    check_exponent(exponent)?;
    check_motion(motion, owned)?;
    check::finite_items("points", points.get(..owned).unwrap_or(&[]))
}

/// The boundary values of the serial pipeline at every boundary position: the rotation as the
/// boundary stage gave it and `Δ` from its normalised form; then the checks
/// [`propagate_idw`](crate::quaternion::propagate_idw) makes of them, in boundary order.
///
/// # Errors
/// [`Error::NonFinite`] (`"translations"` or `"rotations"`) and [`Error::ZeroLength`]
/// (`"rotations"`), position = the boundary node's global id.
fn boundary_values<T: Real, const D: usize>(
    g: &Gathered<'_, T, D>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
) -> Result<()> {
    let items = translations.iter_mut().zip(rotations.iter_mut());
    for (k, ((t, r), &q)) in items.zip(g.quats).enumerate() {
        let q = Quat::from_array(q);
        let unit = q.normalize().unwrap_or(Quat::identity());
        let (u, d) = (Pts::direct(g.u).get(k), Pts::direct(g.d).get(k));
        *t = translation(g.origin, u, d, unit);
        *r = q;
    }
    for (k, (t, q)) in translations.iter().zip(rotations.iter()).enumerate() {
        let position = g.global_id(k);
        if !t.iter().all(|c| c.is_finite()) {
            return Err(Error::NonFinite {
                arg: "translations",
                position,
            });
        }
        if !q.is_finite() {
            return Err(Error::NonFinite {
                arg: "rotations",
                position,
            });
        }
        if q.normalize().is_err() {
            return Err(Error::ZeroLength {
                arg: "rotations",
                position,
            });
        }
    }
    Ok(())
}

/// The gathered boundary with its values, as the serial IDW reads them.
struct Field<'f, T, const D: usize> {
    points: &'f [[T; D]],
    boundary: &'f [u32],
    exponent: T,
    translations: &'f [[T; D]],
    rotations: &'f [Quat<T>],
    origin: [T; D],
}

impl<T: Real, const D: usize> Field<'_, T, D> {
    /// Writes every owned node as [`update_points`](crate::quaternion::update_points) does
    /// after the serial IDW: `o + Δ + Q (R − o) Q*` with the weighted `(Δ, Q)`, the listed
    /// boundary nodes their deformed points exactly. Returns the first owned node whose
    /// weighted translation is not finite.
    fn update_owned(
        &self,
        points: &[[T; D]],
        motion: &PartitionedMotion<'_, T, D>,
        out: &mut [[T; D]],
    ) -> Option<usize> {
        let mut bad = None;
        for (i, (o, &r)) in out.iter_mut().zip(points).enumerate() {
            // `usize::MAX` is no boundary position: every owned node is weighed (a boundary
            // node is at distance zero from itself and is overwritten below).
            let value = idw_point(
                self.points,
                self.boundary,
                self.exponent,
                self.translations,
                self.rotations,
                usize::MAX,
                r,
            );
            let (t, q) = value.unwrap_or(([T::ZERO; D], Quat::identity()));
            if bad.is_none() && !t.iter().all(|c| c.is_finite()) {
                bad = Some(i);
            }
            let q = q.normalize().unwrap_or(Quat::identity());
            *o = apply(self.origin, r, t, q);
        }
        for (&i, &d) in motion.nodes.iter().zip(motion.deformed) {
            if let Some(o) = out.get_mut(i as usize) {
                *o = d;
            }
        }
        bad
    }
}
