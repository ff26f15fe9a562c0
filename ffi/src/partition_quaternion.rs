//! Samareh's quaternion deformation with spring propagation on distributed data, from C and
//! Fortran: `dk_partitioned_deform_spring*` (the kernel's `deform_spring_partitioned`).
//!
//! Each process passes its partition and local cells as for `dk_partitioned_spring_solve`
//! (a `dk_partition`, a `dk_cells`, the local points and fixed mask), and its share of the
//! boundary motion ([`dk_partitioned_motion`]): the owned boundary nodes with their positions
//! in the global boundary list and their deformed points, and the boundary elements it
//! contributes. Every process gets the serial `dk_deform_spring` result (CG, Jacobi or no
//! preconditioner) on its owned nodes, bit for bit (docs/scaling.md).
//!
//! **Errors** are agreed as in `dk_partitioned_spring_solve` (the same `CExchange`): what a
//! process checks alone in a first one-word sum, then the kernel's collective checks, and a
//! failing callback seen by every process at the same reduction. Every
//! `deform_kernel::error::PartitionFault` (the partition's, the rows', and
//! `PartitionFault::Boundary`: boundary lists that do not match between processes) is
//! `DK_ERR_BAD_PARTITION` on every process. The kernel writes into a copy in `scratch`;
//! `out`, `origin_out` and `*report` are written only once every process has agreed on
//! success.
#![allow(unsafe_code)] // the structs' arrays become tokens here.

use deform_kernel::partition::Partition;
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_spring_partitioned, deform_spring_partitioned_lens, BoundaryElements, PartitionedLens,
    PartitionedMotion, PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::{partitioned_targets_len, Preconditioner, SolveOptions, SolveReport};
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, mul_len, read_one, write_array, Dim};
use crate::deformation::{DK_ROTATIONS_PER_NODE, DK_ROTATIONS_RIGID, DK_ROTATIONS_SHAPE};
use crate::graph::dk_cells;
use crate::partition::{dk_exchange, dk_partition, springs, CExchange, Local};
use crate::slice::{input, out_one, output, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report};
use crate::status::dk_status;

/// One process's share of the prescribed boundary motion of
/// [`dk_partitioned_deform_spring`] (the kernel's `PartitionedMotion`). Indices are 0-based.
/// The arrays are borrowed for the call that receives the struct.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_partitioned_motion {
    /// The owned local nodes on the boundary: exactly the owned nodes the fixed mask marks.
    pub nodes: *const u32,
    /// Entries of `nodes`.
    pub nodes_len: usize,
    /// Position of each node in the global boundary list (`0..boundary_count`; the order of
    /// the serial `dk_boundary_motion`'s `nodes`).
    pub positions: *const u32,
    /// Entries of `positions` (`nodes_len`).
    pub positions_len: usize,
    /// Deformed position of each node (`dim` doubles a node); reproduced exactly in `out`.
    pub deformed: *const f64,
    /// Doubles in `deformed` (`nodes_len * dim`).
    pub deformed_len: usize,
    /// Number of boundary nodes over all processes (`B`, the same on every process).
    pub boundary_count: usize,
    /// Global element number (`0..element_count`, the serial element order) of each of this
    /// process's boundary elements. Each element is given by exactly one process.
    pub element_ids: *const u32,
    /// Entries of `element_ids`.
    pub element_ids_len: usize,
    /// This process's boundary elements, their nodes as global boundary positions: segments
    /// (VTK 3) in 2D, triangles or quadrilaterals (5, 9) in 3D. A process without elements
    /// may pass every array NULL with length 0.
    pub elements: dk_cells,
    /// Number of boundary elements over all processes (`E`, the same on every process); 0
    /// for no elements (then `rotation_source` must be [`DK_ROTATIONS_RIGID`]).
    pub element_count: usize,
    /// With [`DK_ROTATIONS_RIGID`]: the rotation `(w, x, y, z)` of the moving boundary nodes
    /// (normalised by the library). Ignored otherwise.
    pub rigid_rotation: [f64; 4],
    /// The rotation origin, used when `has_origin` is nonzero (the first `dim` entries).
    pub origin: [f64; 3],
    /// [`DK_ROTATIONS_SHAPE`] or [`DK_ROTATIONS_RIGID`]; [`DK_ROTATIONS_PER_NODE`] only with
    /// [`dk_partitioned_deform_idw`](crate::partition_idw::dk_partitioned_deform_idw) (its
    /// `node_rotations`), refused by [`dk_partitioned_deform_spring`].
    pub rotation_source: u32,
    /// Nonzero: rotate about `origin`; 0: about the centroid of the moving boundary points.
    pub has_origin: u32,
}
assert_layout!(
    dk_partitioned_motion, 192;
    positions = 16, deformed = 32, boundary_count = 48, element_ids = 56, elements = 72,
    element_count = 120, rigid_rotation = 128, origin = 160, rotation_source = 184,
    has_origin = 188,
);

/// The lengths of the four scratch buffers and of the pieces carved from them.
struct Lens {
    kernel: PartitionedLens,
    /// Stiffness and column entries of the owned rows.
    targets: usize,
    /// Doubles of the copy of `out` (`owned * dim`).
    out: usize,
    /// Total doubles of `scratch`.
    reals: usize,
    /// Total entries of `index_scratch`.
    index: usize,
}

/// The lengths for `owned` of `local` nodes, `targets` row entries, `B` boundary nodes and
/// `E` boundary elements in dimension `D`.
fn lens<const D: usize>(
    owned: usize,
    local: usize,
    targets: usize,
    boundary_count: usize,
    element_count: usize,
) -> Result<Lens, dk_status> {
    let kernel = deform_spring_partitioned_lens::<D>(local, boundary_count, element_count);
    let too_large = dk_status::DK_ERR_TOO_LARGE;
    let k = [
        kernel.words,
        kernel.reals,
        kernel.index,
        kernel.kinds,
        kernel.values,
    ];
    if k.contains(&usize::MAX) {
        return Err(too_large);
    }
    let out = mul_len(owned, D)?;
    let sum = |parts: &[usize]| {
        parts
            .iter()
            .try_fold(0usize, |a, &b| a.checked_add(b))
            .ok_or(too_large)
    };
    let reals = sum(&[targets, kernel.reals, kernel.values, out])?;
    let rows = local.checked_add(1).ok_or(too_large)?;
    let index = sum(&[Partition::scratch_len(local), rows, targets, kernel.index])?;
    Ok(Lens {
        kernel,
        targets,
        out,
        reals,
        index,
    })
}

/// The lengths for `dim` 2 or 3 (else `DK_ERR_INVALID_PARAMETER`).
fn lens_for(
    dim: u32,
    owned: usize,
    local: &Local<'_>,
    boundary_count: usize,
    element_count: usize,
) -> Result<Lens, dk_status> {
    let (n, t) = (local.ids.len(), partitioned_targets_len(&local.cells));
    match dim {
        2 => lens::<2>(owned, n, t, boundary_count, element_count),
        3 => lens::<3>(owned, n, t, boundary_count, element_count),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    }
}

/// The scratch lengths of [`dk_partitioned_deform_spring`] for this partition, these cells,
/// `boundary_count` boundary nodes and `element_count` boundary elements in dimension `dim`
/// (2 or 3): `lens_out[0]` doubles of `scratch`, `lens_out[1]` entries of `index_scratch`
/// (`uint32_t`), `lens_out[2]` entries of `word_scratch` (`int64_t`: the boundary gather's
/// words, `1 + 2 B + 6 E`), `lens_out[3]` bytes of `kind_scratch` (`E`). Local only (no
/// exchange). Errors: `DK_ERR_TOO_LARGE`, pointer errors; nothing written on error.
#[export(partition[1], cells[1], lens_out[4])]
pub(crate) fn dk_partitioned_deform_spring_lens<const D: usize>(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    _dim: Dim<D>,
    boundary_count: usize,
    element_count: usize,
    lens_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (p, c) = (read_one(partition)?, read_one(cells)?);
    // SAFETY: the contract of this function: the structs' arrays are readable.
    let local = unsafe { Local::read(&p, &c, face_diagonals)? };
    let (n, t) = (local.ids.len(), partitioned_targets_len(&local.cells));
    let l = lens::<D>(p.owned, n, t, boundary_count, element_count)?;
    let k = l.kernel;
    write_array(lens_out, [l.reals, l.index, k.words, k.kinds])
}

/// The quaternion deformation with linear-spring propagation on distributed data (the
/// kernel's `deform_spring_partitioned`): each process passes its partition, its local cells
/// and points (`dim` 2 or 3 doubles per local node, ghosts as their owners), Batina's
/// `exponent`, the fixed mask (one byte per local node, nonzero = fixed: the boundary) and its
/// share of the boundary motion (`*motion`). `options->method` must be `DK_LINEAR_CG` with
/// `DK_PRECONDITIONER_JACOBI` or `DK_PRECONDITIONER_NONE`. On `DK_OK`, `out` (`owned * dim`
/// doubles) holds the deformed owned nodes, `origin_out` the origin (`dim` doubles, or NULL
/// with length 0) and `*report` the solver's report: the bits of the serial
/// [`dk_deform_spring`](crate::deformation::dk_deform_spring) with the same options on the
/// whole mesh, for every partition and local numbering. The four scratch buffers need the
/// lengths of [`dk_partitioned_deform_spring_lens`].
///
/// **Collective**: every process of the partition calls it with its own part, and all return
/// `DK_OK` or all an error: `DK_ERR_BAD_PARTITION` for a partition fault on any process
/// (inconsistent ghost or send/receive lists, duplicate global ids, counts, rows that
/// disagree), boundary lists that do not match between processes (`boundary_count` or
/// `element_count` differing, a boundary position or element given by no process or by two,
/// one global id at two positions), or another process's own error; `DK_ERR_EXCHANGE` (a
/// callback returned nonzero on some process); the errors of the local arrays and of the
/// serial deformation (on the process concerned, or on every process when they follow from
/// the gathered boundary), among them `DK_ERR_INVALID_PARAMETER` (`dim`, method, rotation
/// source, a listed node that is not an owned fixed node or an owned fixed node not listed).
/// A NULL `exchange` or callback is `DK_ERR_NULL_POINTER` at once, without any exchange.
/// `out`, `origin_out` and `*report` are unchanged on every error; the scratch buffers are
/// workspaces.
#[export(partition[1], cells[1], motion[1], options[1], exchange[1], report[1])]
pub(crate) fn dk_partitioned_deform_spring(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    points: In<'_, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'_, u8>,
    motion: In<'_, dk_partitioned_motion>,
    options: In<'_, dk_spring_solve_options>,
    scratch: Out<'_, f64>,
    index_scratch: Out<'_, u32>,
    word_scratch: Out<'_, i64>,
    kind_scratch: Out<'_, u8>,
    exchange: In<'_, dk_exchange>,
    out: Out<'_, f64>,
    origin_out: Out<'_, f64>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let ex = read_one(exchange)?;
    let part = read_one(partition);
    let comm = CExchange::new(ex, *part.as_ref().unwrap_or(&dk_partition::NONE))?;
    let args = Args {
        points,
        dim,
        exponent,
        fixed,
        scratch,
        index_scratch,
        word_scratch,
        kind_scratch,
        out,
        origin_out,
    };
    let prepared = part.and_then(|p| {
        let (c, m, o) = (read_one(cells)?, read_one(motion)?, read_one(options)?);
        // SAFETY: the contract of this function: the structs' arrays are readable.
        let local = unsafe { Local::read(&p, &c, face_diagonals)? };
        // SAFETY: as above.
        let motion = unsafe { MotionIn::read(&m)? };
        let report = out_one(report)?;
        prepare(p, local, motion, &o, args).map(|w| (w, report))
    });
    let (mut work, report) = comm.agree_local(prepared)?;
    let solved = work.run(&comm);
    comm.verdict()?;
    let (origin, r) = solved?;
    for (o, &c) in work.out.iter_mut().zip(work.copy.iter()) {
        *o = c;
    }
    for (o, c) in work.origin_out.iter_mut().zip(origin) {
        *o = c;
    }
    *report = dk_spring_solve_report::of(r);
    Ok(())
}

/// Where a [`dk_partitioned_motion`]'s rotations come from.
#[derive(Clone, Copy)]
pub(crate) enum Source {
    Shape,
    Rigid(Quat<f64>),
    /// From an argument beside the struct (`node_rotations`).
    PerNode,
}

/// The borrowed arrays and settings of a [`dk_partitioned_motion`].
pub(crate) struct MotionIn<'a> {
    pub(crate) nodes: &'a [u32],
    positions: &'a [u32],
    pub(crate) deformed: &'a [f64],
    pub(crate) boundary_count: usize,
    ids: &'a [u32],
    offsets: &'a [u32],
    element_nodes: &'a [u32],
    kinds: &'a [u8],
    pub(crate) element_count: usize,
    pub(crate) source: Source,
    origin: Option<[f64; 3]>,
}

/// The offsets of an empty element list (a process that gives no element).
const NO_ELEMENTS: &[u32] = &[0];

impl<'a> MotionIn<'a> {
    /// Borrows the arrays and reads the rotation source (else `DK_ERR_INVALID_PARAMETER`).
    ///
    /// # Safety
    /// The arrays are NULL or readable for their lengths for `'a`.
    pub(crate) unsafe fn read(m: &dk_partitioned_motion) -> Result<Self, dk_status> {
        // SAFETY: forwarded from the caller.
        let t = unsafe {
            [
                In::new(m.nodes, m.nodes_len),
                In::new(m.positions, m.positions_len),
                In::new(m.element_ids, m.element_ids_len),
                In::new(m.elements.offsets, m.elements.offsets_len),
                In::new(m.elements.nodes, m.elements.nodes_len),
            ]
        };
        // SAFETY: as above.
        let (deformed, kinds) = unsafe {
            (
                In::new(m.deformed, m.deformed_len),
                In::new(m.elements.kinds, m.elements.kinds_len),
            )
        };
        let [nodes, positions, ids, offsets, element_nodes] = t.map(input);
        let source = match m.rotation_source {
            DK_ROTATIONS_SHAPE => Source::Shape,
            DK_ROTATIONS_RIGID => Source::Rigid(Quat::from_array(m.rigid_rotation)),
            DK_ROTATIONS_PER_NODE => Source::PerNode,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        let offsets = offsets?;
        Ok(MotionIn {
            nodes: nodes?,
            positions: positions?,
            deformed: input(deformed)?,
            boundary_count: m.boundary_count,
            ids: ids?,
            offsets: if offsets.is_empty() {
                NO_ELEMENTS
            } else {
                offsets
            },
            element_nodes: element_nodes?,
            kinds: input(kinds)?,
            element_count: m.element_count,
            source,
            origin: (m.has_origin != 0).then_some(m.origin),
        })
    }

    /// The kernel's view in dimension `D` (`deformed` is a whole number of points: checked
    /// when the work is prepared), with `per_node` as the rotations of [`Source::PerNode`].
    pub(crate) fn view<const D: usize>(
        &self,
        per_node: &'a [Quat<f64>],
    ) -> PartitionedMotion<'a, f64, D> {
        let elements = (self.element_count > 0).then_some(BoundaryElements {
            ids: self.ids,
            offsets: self.offsets,
            nodes: self.element_nodes,
            kinds: self.kinds,
            count: self.element_count,
        });
        PartitionedMotion {
            nodes: self.nodes,
            positions: self.positions,
            deformed: self.deformed.as_chunks::<D>().0,
            boundary_count: self.boundary_count,
            elements,
            rotations: match self.source {
                Source::Shape => RotationSource::Shape,
                Source::Rigid(q) => RotationSource::Rigid(q),
                Source::PerNode => RotationSource::PerNode(per_node),
            },
            origin: self
                .origin
                .map(|o| core::array::from_fn(|d| o.get(d).copied().unwrap_or(0.0))),
        }
    }
}

/// The per-node arrays and buffers of a deformation, as the caller passed them.
struct Args<'a> {
    points: In<'a, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'a, u8>,
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
    points: &'a [f64],
    dim: u32,
    exponent: f64,
    fixed: &'a [u8],
    preconditioner: Preconditioner<f64>,
    options: SolveOptions<f64>,
    stiffness: &'a mut [f64],
    reals: &'a mut [f64],
    values: &'a mut [f64],
    /// The owned nodes the kernel writes (copied to `out` on success only).
    copy: &'a mut [f64],
    part_scratch: &'a mut [u32],
    offsets: &'a mut [u32],
    targets: &'a mut [u32],
    index: &'a mut [u32],
    words: &'a mut [i64],
    kinds: &'a mut [u8],
    out: &'a mut [f64],
    origin_out: &'a mut [f64],
}

/// Splits `n` entries off the front of `buf` (`DK_ERR_BUFFER_TOO_SMALL` when shorter).
pub(crate) fn carve<T>(buf: &mut [T], n: usize) -> Result<(&mut [T], &mut [T]), dk_status> {
    buf.split_at_mut_checked(n)
        .ok_or(dk_status::DK_ERR_BUFFER_TOO_SMALL)
}

/// What one process can check alone, and the buffers carved.
fn prepare<'a>(
    p: dk_partition,
    local: Local<'a>,
    motion: MotionIn<'a>,
    o: &dk_spring_solve_options,
    a: Args<'a>,
) -> Result<Work<'a>, dk_status> {
    let preconditioner = match o.method::<f64>()? {
        deform_kernel::spring::LinearMethod::Cg { preconditioner } => preconditioner,
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    if matches!(motion.source, Source::PerNode) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let (b, e) = (motion.boundary_count, motion.element_count);
    let l = lens_for(a.dim, p.owned, &local, b, e)?;
    let dim = a.dim as usize;
    if motion.deformed.len() != mul_len(motion.nodes.len(), dim)? {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let out = output(a.out)?;
    let origin_out = output(a.origin_out)?;
    if out.len() != l.out || !(origin_out.is_empty() || origin_out.len() == dim) {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let (stiffness, rest) = carve(output(a.scratch)?, l.targets)?;
    let (reals, rest) = carve(rest, l.kernel.reals)?;
    let (values, rest) = carve(rest, l.kernel.values)?;
    let (copy, _) = carve(rest, l.out)?;
    let n = local.ids.len();
    let (part_scratch, rest) = carve(output(a.index_scratch)?, Partition::scratch_len(n))?;
    let (offsets, rest) = carve(rest, n.saturating_add(1))?;
    let (targets, rest) = carve(rest, l.targets)?;
    let (index, _) = carve(rest, l.kernel.index)?;
    let (words, _) = carve(output(a.word_scratch)?, l.kernel.words)?;
    let (kinds, _) = carve(output(a.kind_scratch)?, l.kernel.kinds)?;
    Ok(Work {
        p,
        local,
        motion,
        points: input(a.points)?,
        dim: a.dim,
        exponent: a.exponent,
        fixed: input(a.fixed)?,
        preconditioner,
        options: o.stopping(),
        stiffness,
        reals,
        values,
        copy,
        part_scratch,
        offsets,
        targets,
        index,
        words,
        kinds,
        out,
        origin_out,
    })
}

impl Work<'_> {
    /// The kernel's collective calls: the partition, the rows, the deformation (into `copy`).
    /// Returns the origin (`dim` entries used) and the solver report.
    fn run(&mut self, comm: &CExchange) -> Result<([f64; 3], SolveReport<f64>), dk_status> {
        match self.dim {
            2 => self.deform::<2>(comm),
            3 => self.deform::<3>(comm),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }
    }

    fn deform<const D: usize>(
        &mut self,
        comm: &CExchange,
    ) -> Result<([f64; 3], SolveReport<f64>), dk_status> {
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
        let springs = springs::<f64, D>(
            part,
            self.local.cells,
            self.points,
            self.exponent,
            self.fixed,
            &mut *self.offsets,
            &mut *self.targets,
            &mut *self.stiffness,
            comm,
        )?;
        let (pts, rest) = self.points.as_chunks::<D>();
        // A ragged point array: the kernel's collective length check finds it.
        let pts = if rest.is_empty() { pts } else { &[] };
        let work = PartitionedWorkspace {
            words: &mut *self.words,
            reals: &mut *self.reals,
            index: &mut *self.index,
            kinds: &mut *self.kinds,
            values: &mut *self.values,
        };
        let copy = self.copy.as_chunks_mut::<D>().0;
        let motion = self.motion.view::<D>(&[]);
        let (origin, report) = deform_spring_partitioned(
            &springs,
            pts,
            &motion,
            self.preconditioner,
            &self.options,
            work,
            copy,
            comm,
        )?;
        let mut o = [0.0; 3];
        for (x, y) in o.iter_mut().zip(origin) {
            *x = y;
        }
        Ok((o, report))
    }
}
