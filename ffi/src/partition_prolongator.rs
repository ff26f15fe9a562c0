//! The distributed multigrid's fine level from C and Fortran: `dk_partitioned_prolongator*`
//! (the kernel's `aggregate_mis2_partitioned` and `prolongator_partitioned`).
//!
//! Each process passes its partition and local cells, points and fixed mask as for
//! `dk_partitioned_spring_solve`; the library builds the local spring rows, aggregates the
//! free nodes by the partition-independent MIS-2 (docs/amg.md) and writes this process's
//! owned rows of the smoothed-aggregation prolongator `P = (I − ω D⁻¹ A) T`: every row bit for
//! bit the row the serial MIS-2 hierarchy (the kernel's `AmgHierarchy::setup_mis2`, read with
//! `AmgHierarchy::prolongator_row`) builds for that node, its columns named by the global ids
//! of the aggregates' roots (which sort as the serial coarse numbers do), for every partition
//! and local numbering.
//!
//! **Errors** are agreed as in `dk_partitioned_spring_solve` (the same `CExchange`). The
//! kernel writes into copies in the scratch buffers; `offsets`, `columns`, `values` and
//! `counts_out` are written only once every process has agreed on success.
#![allow(unsafe_code)] // the structs' arrays become tokens here.

use deform_kernel::partition::Partition;
use deform_kernel::spring::{
    aggregate_mis2_partitioned, mis2_exchange_len, mis2_scratch_len, partitioned_targets_len,
    prolongator_partitioned,
};
use deform_kernel_ffi_export::export;

use crate::args::{read_one, write_array};
use crate::graph::dk_cells;
use crate::partition::{dk_exchange, dk_partition, springs, CExchange, Local};
use crate::partition_quaternion::carve;
use crate::slice::{input, output, In, Out};
use crate::status::dk_status;

/// The lengths of the three scratch buffers, of the pieces carved from them and of the
/// outputs.
struct Lens {
    /// Local nodes.
    local: usize,
    /// Stiffness and column entries of the local rows.
    targets: usize,
    /// Entries `columns` and `values` need: one per owned node and per row entry.
    entries: usize,
    /// Total doubles of `scratch`.
    reals: usize,
    /// Total entries of `index_scratch`.
    index: usize,
    /// Total entries of `id_scratch`.
    ids: usize,
}

/// The lengths for `owned` of `local` nodes and `targets` row entries.
fn lens(owned: usize, local: usize, targets: usize) -> Result<Lens, dk_status> {
    let too_large = dk_status::DK_ERR_TOO_LARGE;
    let sum = |parts: &[usize]| {
        parts
            .iter()
            .try_fold(0usize, |a, &b| a.checked_add(b))
            .ok_or(too_large)
    };
    let entries = sum(&[targets, owned])?;
    let (exchange, words) = (mis2_exchange_len(local), mis2_scratch_len(local));
    if exchange == usize::MAX || words == usize::MAX {
        return Err(too_large);
    }
    let rows = sum(&[local, 1])?;
    let owned_rows = sum(&[owned, 1])?;
    Ok(Lens {
        local,
        targets,
        entries,
        reals: sum(&[targets, exchange, entries])?,
        index: sum(&[Partition::scratch_len(local), rows, targets, owned_rows])?,
        ids: sum(&[local, words, entries])?,
    })
}

/// The lengths of this partition and these cells.
fn lens_of(p: &dk_partition, local: &Local<'_>) -> Result<Lens, dk_status> {
    lens(
        p.owned,
        local.ids.len(),
        partitioned_targets_len(&local.cells),
    )
}

/// The buffer lengths of [`dk_partitioned_prolongator`] for this partition and these cells:
/// `lens_out[0]` doubles of `scratch`, `lens_out[1]` entries of `index_scratch`
/// (`uint32_t`), `lens_out[2]` entries of `id_scratch` (`uint64_t`), `lens_out[3]` entries
/// `columns` and `values` need (a bound: one per owned node and per local row entry; the
/// rows written may be shorter). Local only (no exchange). Errors: `DK_ERR_TOO_LARGE`,
/// pointer errors; nothing written on error.
#[export(partition[1], cells[1], lens_out[4])]
pub(crate) fn dk_partitioned_prolongator_lens(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    lens_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (p, c) = (read_one(partition)?, read_one(cells)?);
    // SAFETY: the contract of this function: the structs' arrays are readable.
    let local = unsafe { Local::read(&p, &c, face_diagonals)? };
    let l = lens_of(&p, &local)?;
    write_array(lens_out, [l.reals, l.index, l.ids, l.entries])
}

/// This process's rows of the fine level's smoothed-aggregation prolongator on distributed
/// data: each process passes its partition, its local cells (0-based local nodes; every cell
/// that touches an owned node, as `VTK` kinds), its local points (`dim` 2 or 3 per local node,
/// ghosts as their owners), Batina's `exponent` (1 is the papers') and the fixed mask (one
/// byte per local node, nonzero = fixed). The spring rows are built as by
/// [`dk_partitioned_spring_solve`](crate::partition::dk_partitioned_spring_solve), the free
/// nodes aggregated by the partition-independent MIS-2, and on `DK_OK` owned row `i` is
/// `columns[offsets[i]..offsets[i + 1]]` (the global ids of the aggregates' roots, increasing;
/// no entry for a fixed node) with `values` alike: bit for bit row `i` of the serial MIS-2
/// hierarchy's fine prolongator on the whole mesh. `offsets` has `owned + 1` entries;
/// `columns` (`uint64_t`) and `values` at least `lens_out[3]` of
/// [`dk_partitioned_prolongator_lens`], which also gives the scratch lengths.
/// `counts_out[0]` = the entries written on this process (`offsets[owned]`), `counts_out[1]`
/// = the aggregates over all processes (the coarse level's size).
///
/// **Collective**: every process of the partition calls it with its own part, and all return
/// `DK_OK` or all an error: `DK_ERR_BAD_PARTITION` (inconsistent ghost or send/receive lists,
/// duplicate global ids, counts, rows that disagree across processes, or another process's
/// fault), `DK_ERR_EXCHANGE` (a callback returned nonzero on some process), and the errors of
/// the local arrays (on the process concerned; the others report `DK_ERR_BAD_PARTITION`):
/// `DK_ERR_INVALID_PARAMETER` (`dim`), `DK_ERR_LENGTH_MISMATCH` (`offsets`, `points`,
/// `fixed`), `DK_ERR_BUFFER_TOO_SMALL` (scratch, `columns`, `values`). A NULL `exchange` or
/// callback is `DK_ERR_NULL_POINTER` at once, without any exchange. `offsets`, `columns`,
/// `values` and `counts_out` are unchanged on every error; the scratch buffers are
/// workspaces.
#[export(partition[1], cells[1], exchange[1], counts_out[2])]
pub(crate) fn dk_partitioned_prolongator(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    points: In<'_, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'_, u8>,
    scratch: Out<'_, f64>,
    index_scratch: Out<'_, u32>,
    id_scratch: Out<'_, u64>,
    exchange: In<'_, dk_exchange>,
    offsets: Out<'_, u32>,
    columns: Out<'_, u64>,
    values: Out<'_, f64>,
    counts_out: Out<'_, usize>,
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
        id_scratch,
        offsets,
        columns,
        values,
    };
    let prepared = part.and_then(|p| {
        let c = read_one(cells)?;
        // SAFETY: the contract of this function: the structs' arrays are readable.
        let local = unsafe { Local::read(&p, &c, face_diagonals)? };
        let counts = output(counts_out)?;
        prepare(p, local, args).map(|w| (w, counts))
    });
    let (mut work, counts) = comm.agree_local(prepared)?;
    let built = work.run(&comm);
    comm.verdict()?;
    let (entries, aggregates) = built?;
    work.publish(entries);
    for (c, v) in counts.iter_mut().zip([entries, aggregates]) {
        *c = v;
    }
    Ok(())
}

/// The arrays and buffers of a set-up, as the caller passed them.
struct Args<'a> {
    points: In<'a, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'a, u8>,
    scratch: Out<'a, f64>,
    index_scratch: Out<'a, u32>,
    id_scratch: Out<'a, u64>,
    offsets: Out<'a, u32>,
    columns: Out<'a, u64>,
    values: Out<'a, f64>,
}

/// A set-up with every buffer borrowed and carved.
struct Work<'a> {
    p: dk_partition,
    local: Local<'a>,
    points: &'a [f64],
    dim: u32,
    exponent: f64,
    fixed: &'a [u8],
    stiffness: &'a mut [f64],
    mis2_reals: &'a mut [f64],
    part_scratch: &'a mut [u32],
    rows: &'a mut [u32],
    targets: &'a mut [u32],
    agg: &'a mut [u64],
    mis2_words: &'a mut [u64],
    /// The kernel's output (copied to the caller's on success only).
    offsets_copy: &'a mut [u32],
    columns_copy: &'a mut [u64],
    values_copy: &'a mut [f64],
    offsets: &'a mut [u32],
    columns: &'a mut [u64],
    values: &'a mut [f64],
}

/// What one process can check alone, and the buffers carved.
fn prepare<'a>(p: dk_partition, local: Local<'a>, a: Args<'a>) -> Result<Work<'a>, dk_status> {
    if !(2..=3).contains(&a.dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let l = lens_of(&p, &local)?;
    let (offsets, columns, values) = (output(a.offsets)?, output(a.columns)?, output(a.values)?);
    if offsets.len() != p.owned.saturating_add(1) {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    if columns.len() < l.entries || values.len() < l.entries {
        return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
    }
    let (stiffness, rest) = carve(output(a.scratch)?, l.targets)?;
    let (mis2_reals, rest) = carve(rest, mis2_exchange_len(l.local))?;
    let (values_copy, _) = carve(rest, l.entries)?;
    let scratch_len = Partition::scratch_len(l.local);
    let (part_scratch, rest) = carve(output(a.index_scratch)?, scratch_len)?;
    let (rows, rest) = carve(rest, l.local.saturating_add(1))?;
    let (targets, rest) = carve(rest, l.targets)?;
    let (offsets_copy, _) = carve(rest, offsets.len())?;
    let (agg, rest) = carve(output(a.id_scratch)?, l.local)?;
    let (mis2_words, rest) = carve(rest, mis2_scratch_len(l.local))?;
    let (columns_copy, _) = carve(rest, l.entries)?;
    Ok(Work {
        p,
        local,
        points: input(a.points)?,
        dim: a.dim,
        exponent: a.exponent,
        fixed: input(a.fixed)?,
        stiffness,
        mis2_reals,
        part_scratch,
        rows,
        targets,
        agg,
        mis2_words,
        offsets_copy,
        columns_copy,
        values_copy,
        offsets,
        columns,
        values,
    })
}

impl Work<'_> {
    /// The kernel's collective calls: the partition, the rows, the aggregation and the
    /// prolongator (into the copies). Returns the entries written and the aggregates.
    fn run(&mut self, comm: &CExchange) -> Result<(usize, usize), dk_status> {
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
        let (cells, points, exponent, fixed) =
            (self.local.cells, self.points, self.exponent, self.fixed);
        let (rows, targets) = (&mut *self.rows, &mut *self.targets);
        let stiffness = &mut *self.stiffness;
        let springs = match self.dim {
            2 => springs::<f64, 2>(
                part, cells, points, exponent, fixed, rows, targets, stiffness, comm,
            ),
            _ => springs::<f64, 3>(
                part, cells, points, exponent, fixed, rows, targets, stiffness, comm,
            ),
        }?;
        let report = aggregate_mis2_partitioned(
            springs.partition(),
            &springs.system().graph(),
            self.fixed,
            comm,
            &mut *self.agg,
            &mut *self.mis2_words,
            &mut *self.mis2_reals,
        )?;
        let entries = prolongator_partitioned(
            &springs,
            self.agg,
            comm,
            &mut *self.offsets_copy,
            &mut *self.columns_copy,
            &mut *self.values_copy,
        )?;
        let aggregates = usize::try_from(report.aggregates).unwrap_or(usize::MAX);
        Ok((entries, aggregates))
    }

    /// Copies the kernel's `entries` entries and the offsets to the caller's buffers.
    fn publish(&mut self, entries: usize) {
        for (o, &c) in self.offsets.iter_mut().zip(self.offsets_copy.iter()) {
            *o = c;
        }
        let copied = self.columns_copy.iter().zip(self.values_copy.iter());
        let outs = self.columns.iter_mut().zip(self.values.iter_mut());
        for ((col, val), (&c, &v)) in outs.zip(copied).take(entries) {
            *col = c;
            *val = v;
        }
    }
}
