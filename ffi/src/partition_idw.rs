//! Samareh's quaternion deformation with inverse-distance propagation on distributed data, from
//! C and Fortran: `dk_partitioned_deform_idw*` (the kernel's `deform_idw_partitioned`).
//!
//! Each process passes its partition (a `dk_partition`: no cells, IDW needs no graph), its
//! local points and its share of the boundary motion (a `dk_partitioned_motion`, as for
//! `dk_partitioned_deform_spring`, here also with per-node rotations). The boundary is
//! gathered to every process and weighed into the owned nodes in the serial order, so every
//! owned node gets the serial `dk_deform_idw` bits for every partition and local numbering
//! (docs/scaling.md). No halo exchange: the cost is the gather (words and reals in the
//! boundary's size) and `owned · B` distance evaluations.
//!
//! **Errors** are agreed as in `dk_partitioned_deform_spring` (the same `CExchange`): what a
//! process checks alone in a first one-word sum, then the kernel's collective checks, and a
//! failing callback seen by every process at the same reduction. The kernel writes into a
//! copy in `scratch`; `out` and `origin_out` are written only once every process has agreed
//! on success.
#![allow(unsafe_code)] // the structs' arrays become tokens here.

use deform_kernel::partition::Partition;
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_idw_partitioned, deform_idw_partitioned_lens, PartitionedIdwLens,
    PartitionedIdwWorkspace,
};
use deform_kernel_ffi_export::export;

use crate::args::{mul_len, read_one, write_array, Dim};
use crate::graph::dk_cells;
use crate::partition::{dk_exchange, dk_partition, CExchange, Local};
use crate::partition_quaternion::{carve, dk_partitioned_motion, MotionIn, Source};
use crate::slice::{input, output, quats, quats_of_mut, In, Out};
use crate::status::dk_status;

/// No cells: the IDW reads only the partition's lists.
const NO_CELLS: dk_cells = dk_cells {
    offsets: core::ptr::null(),
    offsets_len: 0,
    nodes: core::ptr::null(),
    nodes_len: 0,
    kinds: core::ptr::null(),
    kinds_len: 0,
};

/// The lengths of the four scratch buffers and of the pieces carved from them.
struct Lens {
    kernel: PartitionedIdwLens,
    /// Doubles of the copy of `out` (`owned * dim`).
    out: usize,
    /// Doubles of the boundary rotations (`4 B`).
    rotations: usize,
    /// Total doubles of `scratch`.
    reals: usize,
    /// Total entries of `index_scratch`.
    index: usize,
}

/// The lengths for `owned` of `local` nodes, `B` boundary nodes and `E` boundary elements in
/// dimension `D`.
fn lens<const D: usize>(
    owned: usize,
    local: usize,
    boundary_count: usize,
    element_count: usize,
) -> Result<Lens, dk_status> {
    let kernel = deform_idw_partitioned_lens::<D>(boundary_count, element_count);
    let too_large = dk_status::DK_ERR_TOO_LARGE;
    let k = [kernel.words, kernel.reals, kernel.index, kernel.kinds];
    if k.contains(&usize::MAX) {
        return Err(too_large);
    }
    let out = mul_len(owned, D)?;
    let rotations = mul_len(kernel.rotations, 4)?;
    let reals = kernel
        .reals
        .checked_add(rotations)
        .and_then(|r| r.checked_add(out))
        .ok_or(too_large)?;
    let index = Partition::scratch_len(local)
        .checked_add(kernel.index)
        .ok_or(too_large)?;
    Ok(Lens {
        kernel,
        out,
        rotations,
        reals,
        index,
    })
}

/// The lengths for `dim` 2 or 3 (else `DK_ERR_INVALID_PARAMETER`).
fn lens_for(dim: u32, p: &dk_partition, b: usize, e: usize) -> Result<Lens, dk_status> {
    match dim {
        2 => lens::<2>(p.owned, p.global_ids_len, b, e),
        3 => lens::<3>(p.owned, p.global_ids_len, b, e),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    }
}

/// The scratch lengths of [`dk_partitioned_deform_idw`] for this partition, `boundary_count`
/// boundary nodes and `element_count` boundary elements in dimension `dim` (2 or 3):
/// `lens_out[0]` doubles of `scratch`, `lens_out[1]` entries of `index_scratch` (`uint32_t`),
/// `lens_out[2]` entries of `word_scratch` (`int64_t`: the boundary gather's words,
/// `1 + 2 B + 6 E`), `lens_out[3]` bytes of `kind_scratch` (`E`). Apart from the partition's
/// node counts, all are in the boundary's size. Local only (no exchange). Errors:
/// `DK_ERR_TOO_LARGE`, pointer errors; nothing written on error.
#[export(partition[1], lens_out[4])]
pub(crate) fn dk_partitioned_deform_idw_lens<const D: usize>(
    partition: In<'_, dk_partition>,
    _dim: Dim<D>,
    boundary_count: usize,
    element_count: usize,
    lens_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let p = read_one(partition)?;
    let l = lens::<D>(p.owned, p.global_ids_len, boundary_count, element_count)?;
    let k = l.kernel;
    write_array(lens_out, [l.reals, l.index, k.words, k.kinds])
}

/// The quaternion deformation with inverse-distance propagation on distributed data (the
/// kernel's `deform_idw_partitioned`): each process passes its partition, its local points
/// (`dim` 2 or 3 doubles per local node, ghosts as their owners; only the owned ones are
/// read), the IDW `exponent` and its share of the boundary motion (`*motion`; elements are
/// needed only for `DK_ROTATIONS_SHAPE`). With `motion->rotation_source`
/// `DK_ROTATIONS_PER_NODE`, `node_rotations` holds one quaternion `(w, x, y, z)` per listed
/// node (`4 * motion->nodes_len` doubles, in the order of `motion->nodes`); otherwise it is
/// ignored (NULL with length 0). On `DK_OK`, `out` (`owned * dim` doubles) holds the deformed
/// owned nodes and `origin_out` the origin (`dim` doubles, or NULL with length 0): the bits of
/// the serial [`dk_deform_idw`](crate::deformation::dk_deform_idw) with the same exponent on
/// the whole mesh, for every partition and local numbering. The four scratch buffers need the
/// lengths of [`dk_partitioned_deform_idw_lens`].
///
/// **Collective**: every process of the partition calls it with its own part, and all return
/// `DK_OK` or all an error: `DK_ERR_BAD_PARTITION` for a partition fault on any process
/// (inconsistent ghost or send/receive lists, duplicate global ids, counts), boundary lists
/// that do not match between processes (`boundary_count` or `element_count` differing, a
/// boundary position or element given by no process or by two, one global id at two
/// positions), or another process's own error; `DK_ERR_EXCHANGE` (a callback returned nonzero
/// on some process); the errors of the local arrays and of the serial deformation (on the
/// process concerned, or on every process when they follow from the gathered boundary), among
/// them `DK_ERR_INVALID_PARAMETER` (`dim`, the rotation source, the exponent, a listed node
/// that is not owned) and `DK_ERR_LENGTH_MISMATCH` (`node_rotations` not 4 doubles per listed
/// node). A NULL `exchange` or callback is `DK_ERR_NULL_POINTER` at once, without any
/// exchange. `out` and `origin_out` are unchanged on every error; the scratch buffers are
/// workspaces.
#[export(partition[1], motion[1], exchange[1])]
pub(crate) fn dk_partitioned_deform_idw(
    partition: In<'_, dk_partition>,
    points: In<'_, f64>,
    dim: u32,
    exponent: f64,
    motion: In<'_, dk_partitioned_motion>,
    node_rotations: In<'_, f64>,
    scratch: Out<'_, f64>,
    index_scratch: Out<'_, u32>,
    word_scratch: Out<'_, i64>,
    kind_scratch: Out<'_, u8>,
    exchange: In<'_, dk_exchange>,
    out: Out<'_, f64>,
    origin_out: Out<'_, f64>,
) -> Result<(), dk_status> {
    let ex = read_one(exchange)?;
    let part = read_one(partition);
    let comm = CExchange::new(ex, *part.as_ref().unwrap_or(&dk_partition::NONE))?;
    let args = Args {
        points,
        dim,
        exponent,
        node_rotations,
        scratch,
        index_scratch,
        word_scratch,
        kind_scratch,
        out,
        origin_out,
    };
    let prepared = part.and_then(|p| {
        let m = read_one(motion)?;
        // SAFETY: the contract of this function: the structs' arrays are readable.
        let local = unsafe { Local::read(&p, &NO_CELLS, false)? };
        // SAFETY: as above.
        let motion = unsafe { MotionIn::read(&m)? };
        prepare(p, local, motion, args)
    });
    let mut work = comm.agree_local(prepared)?;
    let deformed = work.run(&comm);
    comm.verdict()?;
    let origin = deformed?;
    for (o, &c) in work.out.iter_mut().zip(work.copy.iter()) {
        *o = c;
    }
    for (o, c) in work.origin_out.iter_mut().zip(origin) {
        *o = c;
    }
    Ok(())
}

/// The arrays and buffers of a deformation, as the caller passed them.
struct Args<'a> {
    points: In<'a, f64>,
    dim: u32,
    exponent: f64,
    node_rotations: In<'a, f64>,
    scratch: Out<'a, f64>,
    index_scratch: Out<'a, u32>,
    word_scratch: Out<'a, i64>,
    kind_scratch: Out<'a, u8>,
    out: Out<'a, f64>,
    origin_out: Out<'a, f64>,
}

/// A deformation with every buffer borrowed and carved.
struct Work<'a> {
    p: dk_partition,
    local: Local<'a>,
    motion: MotionIn<'a>,
    per_node: &'a [Quat<f64>],
    points: &'a [f64],
    dim: u32,
    exponent: f64,
    reals: &'a mut [f64],
    rotations: &'a mut [Quat<f64>],
    /// The owned nodes the kernel writes (copied to `out` on success only).
    copy: &'a mut [f64],
    part_scratch: &'a mut [u32],
    index: &'a mut [u32],
    words: &'a mut [i64],
    kinds: &'a mut [u8],
    out: &'a mut [f64],
    origin_out: &'a mut [f64],
}

/// What one process can check alone, and the buffers carved.
fn prepare<'a>(
    p: dk_partition,
    local: Local<'a>,
    motion: MotionIn<'a>,
    a: Args<'a>,
) -> Result<Work<'a>, dk_status> {
    let l = lens_for(a.dim, &p, motion.boundary_count, motion.element_count)?;
    let dim = a.dim as usize;
    if motion.deformed.len() != mul_len(motion.nodes.len(), dim)? {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let per_node = match motion.source {
        Source::PerNode => quats(a.node_rotations)?,
        _ => &[],
    };
    let out = output(a.out)?;
    let origin_out = output(a.origin_out)?;
    if out.len() != l.out || !(origin_out.is_empty() || origin_out.len() == dim) {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let (reals, rest) = carve(output(a.scratch)?, l.kernel.reals)?;
    let (rotations, rest) = carve(rest, l.rotations)?;
    let (copy, _) = carve(rest, l.out)?;
    let n = local.ids.len();
    let (part_scratch, rest) = carve(output(a.index_scratch)?, Partition::scratch_len(n))?;
    let (index, _) = carve(rest, l.kernel.index)?;
    let (words, _) = carve(output(a.word_scratch)?, l.kernel.words)?;
    let (kinds, _) = carve(output(a.kind_scratch)?, l.kernel.kinds)?;
    Ok(Work {
        p,
        local,
        motion,
        per_node,
        points: input(a.points)?,
        dim: a.dim,
        exponent: a.exponent,
        reals,
        rotations: quats_of_mut(rotations),
        copy,
        part_scratch,
        index,
        words,
        kinds,
        out,
        origin_out,
    })
}

impl Work<'_> {
    /// The kernel's collective calls: the partition, the deformation (into `copy`). Returns
    /// the origin (`dim` entries used).
    fn run(&mut self, comm: &CExchange) -> Result<[f64; 3], dk_status> {
        match self.dim {
            2 => self.deform::<2>(comm),
            3 => self.deform::<3>(comm),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }
    }

    fn deform<const D: usize>(&mut self, comm: &CExchange) -> Result<[f64; 3], dk_status> {
        let p = &self.p;
        let part = Partition::new(
            p.rank,
            p.size,
            p.owned,
            self.local.ids,
            p.global_count,
            self.local.halo,
            comm,
            &mut *self.part_scratch,
        )?;
        let (pts, rest) = self.points.as_chunks::<D>();
        // A ragged point array: the kernel's collective length check finds it.
        let pts = if rest.is_empty() { pts } else { &[] };
        let work = PartitionedIdwWorkspace {
            words: &mut *self.words,
            reals: &mut *self.reals,
            index: &mut *self.index,
            kinds: &mut *self.kinds,
            rotations: &mut *self.rotations,
        };
        let copy = self.copy.as_chunks_mut::<D>().0;
        let motion = self.motion.view::<D>(self.per_node);
        let origin = deform_idw_partitioned(&part, pts, &motion, self.exponent, work, copy, comm)?;
        let mut o = [0.0; 3];
        for (x, y) in o.iter_mut().zip(origin) {
            *x = y;
        }
        Ok(o)
    }
}
