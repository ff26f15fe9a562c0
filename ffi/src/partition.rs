//! Distributed storage from C and Fortran: `dk_partitioned_spring_*`.
//!
//! Each process passes only its partition ([`dk_partition`]: owned nodes first, then ghosts,
//! each with its global id, and per neighbour process the local nodes it sends and the ghosts
//! it receives) and its local cells, and the kernel solves the linear springs with CG on the
//! distributed field: the owned values, the iteration count and the residual are those of the
//! serial `dk_spring_solve_linear` (CG, Jacobi or no preconditioner) on the whole mesh, bit
//! for bit, for every partition and local numbering (docs/scaling.md).
//!
//! **Exchanges** go through the caller's callbacks ([`dk_exchange`]: an all-reduce sum of
//! `int64_t` words, an all-reduce maximum of `double`s, a halo exchange over the partition's
//! lists) with a `void *user` pointer, so the caller may use MPI (`mpi/c/deform_kernel_mpi.c`
//! fills the struct from an `MPI_Comm` or an `MPI_Fint`), a GPU-aware MPI or its own transport.
//!
//! **How every process agrees on an error.** All indices are 0-based local node numbers.
//! What a process can check alone (pointers, lengths, scratch sizes) is merged in a first
//! one-word sum, so all processes go on or all return (`DK_ERR_BAD_PARTITION` on those that
//! found nothing); the kernel then checks the partition and the rows collectively (all
//! `DK_OK` or all an error). A callback that returns nonzero has failed on its process: every
//! later reduction carries that process's failure flag in one extra word (sums) or value
//! (maxima), and a last one-word sum after the solve, so all processes learn of it at the
//! same reduction; from there no process calls a callback again (the solve runs out on local
//! data) and every one returns `DK_ERR_EXCHANGE`, the caller's values and report unchanged.
//! A failing callback must still have taken its part in the operation (as an MPI call that
//! returns an error code has): a transport that leaves a peer waiting cannot be agreed over.
#![allow(unsafe_code)] // the callbacks are called and the structs' arrays become tokens here.

use core::cell::Cell;
use core::ffi::c_void;

use deform_kernel::exact_sum::EXACT_SUM_WORDS;
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::spring::{
    partitioned_cg_scratch_len, partitioned_targets_len, LocalCells, PartitionedSprings,
    Preconditioner, SolveOptions, SolveReport,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, by_components, by_dim, mul_len, read_one, write_one};
use crate::graph::dk_cells;
use crate::slice::{input, output, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report};
use crate::status::dk_status;

/// Sums `len` `int64_t` words over all processes, in place (`MPI_Allreduce`, `MPI_SUM`,
/// `MPI_INT64_T`). Returns 0 on success.
#[allow(non_camel_case_types)]
pub type dk_exchange_sum_words = Option<unsafe extern "C" fn(*mut c_void, *mut i64, usize) -> i32>;
/// Maximum of `len` `double`s over all processes, element-wise, in place (`MPI_Allreduce`,
/// `MPI_MAX`, `MPI_DOUBLE`). Returns 0 on success.
#[allow(non_camel_case_types)]
pub type dk_exchange_max = Option<unsafe extern "C" fn(*mut c_void, *mut f64, usize) -> i32>;
/// The halo exchange over `partition`'s lists: for every neighbour `k`, send the `width`
/// doubles of each node of its send list (in list order) to `neighbour_ranks[k]`, and store
/// the doubles received from it at the nodes of its receive list (in list order). `field`
/// holds `field_len` doubles (`width` per local node). Returns 0 on success.
#[allow(non_camel_case_types)]
pub type dk_exchange_halo =
    Option<unsafe extern "C" fn(*mut c_void, *const dk_partition, *mut f64, usize, usize) -> i32>;

/// The caller's exchanges, one struct per process: every callback is collective over the
/// processes of the partition (the halo exchange only between neighbours), called with `user`
/// as its first argument. Every callback is required.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_exchange {
    /// Passed back to every callback (an MPI communicator, a context).
    pub user: *mut c_void,
    /// All-reduce sum of `int64_t` words.
    pub sum_words: dk_exchange_sum_words,
    /// All-reduce maximum of doubles.
    pub max: dk_exchange_max,
    /// Halo exchange of a field (`width` doubles per local node).
    pub halo: dk_exchange_halo,
}
assert_layout!(dk_exchange, 32; user = 0, sum_words = 8, max = 16, halo = 24);

/// One process's partition, in its own local numbering (0-based): local nodes `0..owned` are
/// owned, the rest (`global_ids_len - owned`) are ghosts; `global_ids[i]` is local node `i`'s
/// global id, below `global_count`. Neighbour `k` (rank `neighbour_ranks[k]`) is sent the
/// owned nodes `send[send_offsets[k]..send_offsets[k + 1]]` and sends the ghosts
/// `recv[recv_offsets[k]..recv_offsets[k + 1]]`; position `q` of one process's send list to
/// another is position `q` of the other's receive list (ordering both by global id is one way
/// to agree). Borrowed for the call that receives it, and passed back to the halo callback.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_partition {
    /// This process's rank.
    pub rank: u32,
    /// Number of processes.
    pub size: u32,
    /// Number of owned nodes (the first local nodes).
    pub owned: usize,
    /// Number of nodes over all processes.
    pub global_count: u64,
    /// The global id of each local node.
    pub global_ids: *const u64,
    /// Entries of `global_ids` (the local node count, owned and ghosts).
    pub global_ids_len: usize,
    /// The rank of each neighbour process.
    pub neighbour_ranks: *const u32,
    /// Entries of `neighbour_ranks` (the neighbour count).
    pub neighbour_ranks_len: usize,
    /// Start of each neighbour's list in `send`, and the end (`neighbour_ranks_len + 1`).
    pub send_offsets: *const u32,
    /// Entries of `send_offsets`.
    pub send_offsets_len: usize,
    /// The owned local nodes sent, neighbour by neighbour.
    pub send: *const u32,
    /// Entries of `send`.
    pub send_len: usize,
    /// Start of each neighbour's list in `recv`, and the end (`neighbour_ranks_len + 1`).
    pub recv_offsets: *const u32,
    /// Entries of `recv_offsets`.
    pub recv_offsets_len: usize,
    /// The ghosts received, neighbour by neighbour.
    pub recv: *const u32,
    /// Entries of `recv`.
    pub recv_len: usize,
}
assert_layout!(
    dk_partition, 120;
    owned = 8, global_count = 16, global_ids = 24, neighbour_ranks = 40, send_offsets = 56,
    send = 72, recv_offsets = 88, recv = 104, recv_len = 112,
);

impl dk_partition {
    /// No nodes, no neighbours: what the halo callback sees when the caller's struct could not
    /// be read (it is then never called).
    pub(crate) const NONE: dk_partition = dk_partition {
        rank: 0,
        size: 0,
        owned: 0,
        global_count: 0,
        global_ids: core::ptr::null(),
        global_ids_len: 0,
        neighbour_ranks: core::ptr::null(),
        neighbour_ranks_len: 0,
        send_offsets: core::ptr::null(),
        send_offsets_len: 0,
        send: core::ptr::null(),
        send_len: 0,
        recv_offsets: core::ptr::null(),
        recv_offsets_len: 0,
        recv: core::ptr::null(),
        recv_len: 0,
    };
}

/// The borrowed arrays of a [`dk_partition`] and a [`dk_cells`].
pub(crate) struct Local<'a> {
    pub(crate) ids: &'a [u64],
    pub(crate) halo: Halo<'a>,
    pub(crate) cells: LocalCells<'a>,
}

impl<'a> Local<'a> {
    /// Borrows the arrays.
    ///
    /// # Safety
    /// The arrays are NULL or readable for their lengths for `'a` (the contract of the
    /// functions that take the structs).
    pub(crate) unsafe fn read(
        p: &dk_partition,
        c: &dk_cells,
        face_diagonals: bool,
    ) -> Result<Self, dk_status> {
        // SAFETY: forwarded from the caller.
        let t = unsafe {
            [
                In::new(p.neighbour_ranks, p.neighbour_ranks_len),
                In::new(p.send_offsets, p.send_offsets_len),
                In::new(p.send, p.send_len),
                In::new(p.recv_offsets, p.recv_offsets_len),
                In::new(p.recv, p.recv_len),
                In::new(c.offsets, c.offsets_len),
                In::new(c.nodes, c.nodes_len),
            ]
        };
        // SAFETY: forwarded from the caller.
        let (ids, kinds) = unsafe {
            (
                In::new(p.global_ids, p.global_ids_len),
                In::new(c.kinds, c.kinds_len),
            )
        };
        let [ranks, so, s, ro, r, co, cn] = t.map(input);
        Ok(Local {
            ids: input(ids)?,
            halo: Halo::new(ranks?, so?, s?, ro?, r?),
            cells: LocalCells {
                offsets: co?,
                nodes: cn?,
                kinds: input(kinds)?,
                face_diagonals,
            },
        })
    }
}

/// The caller's callbacks as the kernel's [`Exchange`], with the failure flag every reduction
/// carries (see the module doc).
#[derive(Debug)]
pub(crate) struct CExchange {
    ex: dk_exchange,
    part: dk_partition,
    /// A callback of this process returned nonzero.
    failed: Cell<bool>,
    /// Every process knows that one failed: no callback is called any more.
    agreed: Cell<bool>,
}

/// Words of one `sum_words` call besides the flag (longer calls are split).
const WORD_CHUNK: usize = EXACT_SUM_WORDS;
/// Values of one `max` call besides the flag.
const MAX_CHUNK: usize = 8;

impl CExchange {
    /// Checks that every callback is there.
    pub(crate) fn new(ex: dk_exchange, part: dk_partition) -> Result<Self, dk_status> {
        if ex.sum_words.is_none() || ex.max.is_none() || ex.halo.is_none() {
            return Err(dk_status::DK_ERR_NULL_POINTER);
        }
        Ok(CExchange {
            ex,
            part,
            failed: Cell::new(false),
            agreed: Cell::new(false),
        })
    }

    fn note(&self, status: i32) {
        if status != 0 {
            self.failed.set(true);
        }
    }

    /// One flagged sum: `buf[0]` this process's flag, the rest the words.
    fn flagged_sum(&self, buf: &mut [i64]) {
        if let Some(first) = buf.first_mut() {
            *first = i64::from(self.failed.get());
        }
        if let Some(f) = self.ex.sum_words {
            // SAFETY: the contract of `dk_exchange`: `f` is a C function that reads and
            // writes `len` words at the pointer (a live buffer here) and keeps no pointer.
            self.note(unsafe { f(self.ex.user, buf.as_mut_ptr(), buf.len()) });
        }
        // Only the merged flag: a process whose callback failed just now tells the others in
        // the next reduction, and they all stop there together.
        if buf.first().is_some_and(|&w| w != 0) {
            self.agreed.set(true);
        }
    }

    /// `Err(DK_ERR_EXCHANGE)` on every process when a callback failed on any: one last
    /// flagged sum unless all know already.
    pub(crate) fn verdict(&self) -> Result<(), dk_status> {
        if !self.agreed.get() {
            self.flagged_sum(&mut [0i64]);
        }
        // A failure in this last sum itself is known here only: reported here all the same.
        if self.agreed.get() || self.failed.get() {
            return Err(dk_status::DK_ERR_EXCHANGE);
        }
        Ok(())
    }

    /// The first agreement: `Err` on every process when any found a fault of its own
    /// (`local`; the others report `DK_ERR_BAD_PARTITION`).
    pub(crate) fn agree_local<U>(&self, local: Result<U, dk_status>) -> Result<U, dk_status> {
        let mut words = [0, i64::from(local.is_err())];
        self.flagged_sum(&mut words);
        let any = words.get(1).is_some_and(|&w| w != 0);
        self.verdict_if_agreed()?;
        let v = local?;
        if any {
            return Err(dk_status::DK_ERR_BAD_PARTITION);
        }
        Ok(v)
    }

    fn verdict_if_agreed(&self) -> Result<(), dk_status> {
        if self.agreed.get() {
            return Err(dk_status::DK_ERR_EXCHANGE);
        }
        Ok(())
    }
}

impl Exchange<f64> for CExchange {
    fn sum_words(&self, words: &mut [i64]) {
        for chunk in words.chunks_mut(WORD_CHUNK) {
            if self.agreed.get() {
                // Everyone knows: no more calls; zero sums end the solve soon.
                chunk.fill(0);
                continue;
            }
            let mut buf = [0i64; WORD_CHUNK + 1];
            let Some((_, tail)) = buf.split_first_mut() else {
                continue;
            };
            for (b, &w) in tail.iter_mut().zip(chunk.iter()) {
                *b = w;
            }
            let len = chunk.len().saturating_add(1);
            self.flagged_sum(buf.get_mut(..len).unwrap_or(&mut []));
            for (w, &b) in chunk.iter_mut().zip(buf.iter().skip(1)) {
                *w = b;
            }
        }
    }

    fn max(&self, values: &mut [f64]) {
        for chunk in values.chunks_mut(MAX_CHUNK) {
            if self.agreed.get() {
                continue;
            }
            let mut buf = [0.0f64; MAX_CHUNK + 1];
            let flag = if self.failed.get() { 1.0 } else { 0.0 };
            for (b, &v) in buf
                .iter_mut()
                .zip(core::iter::once(&flag).chain(chunk.iter()))
            {
                *b = v;
            }
            let buf = buf
                .get_mut(..chunk.len().saturating_add(1))
                .unwrap_or(&mut []);
            if let Some(f) = self.ex.max {
                // SAFETY: as in `flagged_sum`.
                self.note(unsafe { f(self.ex.user, buf.as_mut_ptr(), buf.len()) });
            }
            if buf.first().is_some_and(|&v| v != 0.0) {
                self.agreed.set(true);
            }
            for (v, &b) in chunk.iter_mut().zip(buf.iter().skip(1)) {
                *v = b;
            }
        }
    }

    fn exchange(&self, _: &Halo<'_>, field: &mut [f64], width: usize) {
        if self.agreed.get() {
            return;
        }
        if let Some(f) = self.ex.halo {
            // SAFETY: the contract of `dk_exchange`: `f` reads the partition struct (a copy of
            // the caller's, whose arrays the caller keeps readable for the call) and writes
            // at most `field.len()` doubles at `field`, keeping no pointer. The kernel's halo
            // is this partition's (the only one it exchanges over).
            let s = unsafe {
                f(
                    self.ex.user,
                    &self.part,
                    field.as_mut_ptr(),
                    field.len(),
                    width,
                )
            };
            self.note(s);
        }
    }
}

/// Lengths of the two scratch buffers: `(doubles, uint32_t)`.
fn scratch_lens(
    local: usize,
    targets: usize,
    components: usize,
) -> Result<(usize, usize), dk_status> {
    let items = by_components!(components, cg_items::<f64>, (local))?;
    let values = mul_len(local, components)?;
    let reals = mul_len(items, components)?
        .checked_add(values)
        .and_then(|r| r.checked_add(targets))
        .ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    let index = local
        .checked_mul(2)
        .and_then(|i| i.checked_add(targets))
        .and_then(|i| i.checked_add(1))
        .ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    Ok((reals, index))
}

/// `[T; V]` items of the partitioned CG (as a `Result` for the dispatch).
#[allow(clippy::extra_unused_type_parameters)] // `by_components!` names the real type
fn cg_items<T: Real, const V: usize>(local: usize) -> Result<usize, dk_status> {
    match partitioned_cg_scratch_len::<V>(local) {
        usize::MAX => Err(dk_status::DK_ERR_TOO_LARGE),
        n => Ok(n),
    }
}

/// Lengths of `scratch` (doubles) and `index_scratch` (`uint32_t`) that
/// [`dk_partitioned_spring_solve`] needs for this partition, these cells and `components`
/// (1 to 7) values per node. Local only (no exchange). Errors: `DK_ERR_INVALID_PARAMETER`
/// (`components`), `DK_ERR_TOO_LARGE`, pointer errors.
#[export(partition[1], cells[1], scratch_len_out[1], index_scratch_len_out[1])]
pub(crate) fn dk_partitioned_spring_scratch_len(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    components: u32,
    scratch_len_out: Out<'_, usize>,
    index_scratch_len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (p, c) = (read_one(partition)?, read_one(cells)?);
    // SAFETY: the contract of this function: the structs' arrays are readable.
    let local = unsafe { Local::read(&p, &c, face_diagonals)? };
    let targets = partitioned_targets_len(&local.cells);
    let (reals, index) = scratch_lens(local.ids.len(), targets, components as usize)?;
    write_one(scratch_len_out, reals)?;
    write_one(index_scratch_len_out, index)
}

/// Solves the linear springs on distributed data: each process passes its partition, the
/// local cells (0-based local nodes; every cell that touches an owned node, as `VTK` kinds),
/// the local points (`dim` 2 or 3 per local node, ghosts as their owners), Batina's
/// `exponent` (1 is the papers'), the fixed mask (one byte per local node, nonzero = fixed)
/// and `values` (`components` doubles per local node: Dirichlet data and the initial guess at
/// the owned nodes; ghosts' values are ignored). The method is CG with `options->
/// preconditioner` `DK_PRECONDITIONER_JACOBI` or `DK_PRECONDITIONER_NONE` (`options->method`
/// must be `DK_LINEAR_CG`). On `DK_OK` every local node holds the last iterate and `*report`
/// the serial solve's report: the owned values, the iterations and the residual are those of
/// [`dk_spring_solve_linear`](crate::spring::dk_spring_solve_linear) on the whole mesh, bit
/// for bit. `scratch` and `index_scratch` need [`dk_partitioned_spring_scratch_len`] entries.
///
/// **Collective**: every process of the partition calls it with its own part, and all return
/// `DK_OK` or all an error (see the module doc for how they agree): `DK_ERR_BAD_PARTITION`
/// (inconsistent ghost or send/receive lists, duplicate global ids, a process without owned
/// nodes, counts that do not add up, rows that disagree across processes, or another
/// process's fault), `DK_ERR_EXCHANGE` (a callback returned nonzero on some process), and the
/// errors of the serial solve and of the local arrays (on the process concerned; the others
/// report `DK_ERR_BAD_PARTITION`). A NULL `exchange` or callback is `DK_ERR_NULL_POINTER`
/// at once, without any exchange. Values and report unchanged on every error.
#[export(partition[1], cells[1], options[1], exchange[1], report[1])]
pub(crate) fn dk_partitioned_spring_solve(
    partition: In<'_, dk_partition>,
    cells: In<'_, dk_cells>,
    face_diagonals: bool,
    points: In<'_, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'_, u8>,
    options: In<'_, dk_spring_solve_options>,
    components: u32,
    values: Out<'_, f64>,
    scratch: Out<'_, f64>,
    index_scratch: Out<'_, u32>,
    exchange: In<'_, dk_exchange>,
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
        values,
        scratch,
        index_scratch,
    };
    let prepared = part.and_then(|p| {
        let c = read_one(cells)?;
        // SAFETY: the contract of this function: the structs' arrays are readable.
        let local = unsafe { Local::read(&p, &c, face_diagonals)? };
        let o = read_one(options)?;
        let report = crate::slice::out_one(report)?;
        prepare(p, local, &o, components as usize, args).map(|w| (w, report))
    });
    let (mut work, report) = comm.agree_local(prepared)?;
    let solved = work.solve(&comm);
    comm.verdict()?;
    let r = solved?;
    for (v, c) in work.values.iter_mut().zip(work.copy.iter()) {
        *v = *c;
    }
    *report = dk_spring_solve_report::of(r);
    Ok(())
}

/// The per-node arrays and buffers of a solve, as the caller passed them.
struct Args<'a> {
    points: In<'a, f64>,
    dim: u32,
    exponent: f64,
    fixed: In<'a, u8>,
    values: Out<'a, f64>,
    scratch: Out<'a, f64>,
    index_scratch: Out<'a, u32>,
}

/// A solve with every buffer borrowed and carved.
struct Work<'a> {
    rank: u32,
    size: u32,
    owned: usize,
    global_count: u64,
    local: Local<'a>,
    points: &'a [f64],
    dim: u32,
    exponent: f64,
    fixed: &'a [u8],
    components: usize,
    preconditioner: Preconditioner<f64>,
    options: SolveOptions<f64>,
    values: &'a mut [f64],
    /// The values the solve works on (copied back on success only).
    copy: &'a mut [f64],
    stiffness: &'a mut [f64],
    cg: &'a mut [f64],
    part_scratch: &'a mut [u32],
    offsets: &'a mut [u32],
    targets: &'a mut [u32],
}

/// What one process can check alone, and the buffers carved.
fn prepare<'a>(
    p: dk_partition,
    local: Local<'a>,
    o: &dk_spring_solve_options,
    components: usize,
    a: Args<'a>,
) -> Result<Work<'a>, dk_status> {
    let preconditioner = match o.method::<f64>()? {
        deform_kernel::spring::LinearMethod::Cg { preconditioner } => preconditioner,
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    let n = local.ids.len();
    let targets = partitioned_targets_len(&local.cells);
    let (reals, index) = scratch_lens(n, targets, components)?;
    let values = output(a.values)?;
    let scratch = output(a.scratch)?;
    let index_scratch = output(a.index_scratch)?;
    if values.len() != mul_len(n, components)? {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    if !(2..=3).contains(&a.dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    if scratch.len() < reals || index_scratch.len() < index {
        return Err(dk_status::DK_ERR_BUFFER_TOO_SMALL);
    }
    let short = dk_status::DK_ERR_BUFFER_TOO_SMALL;
    let (stiffness, rest) = scratch.split_at_mut_checked(targets).ok_or(short)?;
    let (copy, cg) = rest.split_at_mut_checked(values.len()).ok_or(short)?;
    for (c, &v) in copy.iter_mut().zip(values.iter()) {
        *c = v;
    }
    let (part_scratch, rest) = index_scratch.split_at_mut_checked(n).ok_or(short)?;
    let (offsets, rest) = rest
        .split_at_mut_checked(n.saturating_add(1))
        .ok_or(short)?;
    Ok(Work {
        rank: p.rank,
        size: p.size,
        owned: p.owned,
        global_count: p.global_count,
        local,
        points: input(a.points)?,
        dim: a.dim,
        exponent: a.exponent,
        fixed: input(a.fixed)?,
        components,
        preconditioner,
        options: o.stopping(),
        values,
        copy,
        stiffness,
        cg,
        part_scratch,
        offsets,
        targets: rest,
    })
}

impl Work<'_> {
    /// The kernel's collective calls: the partition, the rows, the CG solve (on `copy`).
    fn solve(&mut self, comm: &CExchange) -> Result<SolveReport<f64>, dk_status> {
        let part = Partition::new(
            self.rank,
            self.size,
            self.owned,
            self.local.ids,
            self.global_count,
            self.local.halo,
            comm,
            self.part_scratch,
        )?;
        let springs = by_dim!(
            self.dim,
            springs::<f64>,
            (
                part,
                self.local.cells,
                self.points,
                self.exponent,
                self.fixed,
                &mut *self.offsets,
                &mut *self.targets,
                &mut *self.stiffness,
                comm
            )
        )?;
        let (pre, opts) = (self.preconditioner, &self.options);
        by_components!(
            self.components,
            solve_v::<f64>,
            (&springs, &mut *self.copy, pre, opts, &mut *self.cg, comm)
        )
    }
}

/// The local rows ([`PartitionedSprings::new`]) with `D`-dimensional points.
#[allow(clippy::too_many_arguments)]
pub(crate) fn springs<'a, T: Real, const D: usize>(
    part: Partition<'a>,
    cells: LocalCells<'_>,
    points: &[T],
    exponent: T,
    fixed: &'a [u8],
    offsets: &'a mut [u32],
    targets: &'a mut [u32],
    stiffness: &'a mut [T],
    comm: &CExchange,
) -> Result<PartitionedSprings<'a, T>, dk_status>
where
    CExchange: Exchange<T>,
{
    let (pts, rest) = points.as_chunks::<D>();
    // A ragged point array is a wrong length: checked with the others, collectively.
    let pts = if rest.is_empty() { pts } else { &[] };
    PartitionedSprings::new(
        part, cells, pts, exponent, fixed, offsets, targets, stiffness, comm,
    )
    .map_err(dk_status::from)
}

/// The CG solve with `V` components per node.
fn solve_v<T: Real, const V: usize>(
    springs: &PartitionedSprings<'_, T>,
    values: &mut [T],
    pre: Preconditioner<T>,
    options: &SolveOptions<T>,
    scratch: &mut [T],
    comm: &CExchange,
) -> Result<SolveReport<T>, dk_status>
where
    CExchange: Exchange<T>,
{
    let values = values.as_chunks_mut::<V>().0;
    let scratch = scratch.as_chunks_mut::<V>().0;
    springs
        .solve_cg(values, pre, options, scratch, comm)
        .map_err(dk_status::from)
}
