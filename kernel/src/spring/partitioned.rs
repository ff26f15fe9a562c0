//! The linear springs on distributed data: each process builds the rows of its owned nodes
//! from its own cells and coordinates ([`PartitionedSprings::new`]) and solves with the
//! kernel's one CG loop ([`pcg`](super::krylov::pcg)) over a halo-exchanging collective
//! ([`PartitionedSprings::solve_cg`]).
//!
//! **Why the bits are the serial ones.** A row's sums run in CSR order, and the serial graph
//! builder sorts each row by neighbour number; here each row is sorted by the neighbours'
//! *global* ids, which are the serial numbers, so every owned row forms the serial row's
//! terms in the serial order. Batina's stiffness of an edge depends only on its two points.
//! The scaling exponents come from the merged maxima, every inner product and norm is an
//! exact sum merged over the processes ([`ExactSum`](crate::exact_sum::ExactSum): the merge
//! is order-independent), and each node's update is the serial update. So the iterates, the
//! iteration count and the reported residual are the serial ones on every process, for every
//! partition and local numbering.
//!
//! **What is exchanged.** Per CG iteration: one halo exchange of the search direction (the
//! ghosts' `V` reals), one `max` of `V` reals (curvature scale), two exact-sum merges (`pᵀAp`
//! per component; the recurrence residual with the next `rᵀz`) and one `max` of `V` reals
//! (largest update); see docs/scaling.md for the bytes.

use super::krylov::{cg_len, component_max, exponents_from, pcg, Vectors};
use super::linear::{diagonal, Laplacian, OneLevel};
use super::system::{Preconditioner, SolveOptions, SolveReport, SpringSystem};
use super::Collective;
use crate::cells::{CellKind, Cells};
use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::graph::Graph;
use crate::graph_builder::graph_from_cells;
use crate::order::sort::{heap_sort, ByKey};
use crate::partition::check::{hash, negate, P, SEEDS};
use crate::partition::{agree, fault, Exchange, HaloCollective, Partition};
use crate::real::Real;

/// The linear springs of one process's partition: complete rows for the owned nodes (each
/// sorted by global id), rows of ghosts as far as the local cells reach (never used).
#[derive(Clone, Copy, Debug)]
pub struct PartitionedSprings<'a, T: Real> {
    part: Partition<'a>,
    sys: SpringSystem<'a, T>,
}

/// `[T; V]` scratch items [`PartitionedSprings::solve_cg`] needs for `local_count` nodes: the
/// four CG vectors and the diagonal packed `V` scalars to an item, `4 n + ⌈n / V⌉`.
pub const fn partitioned_cg_scratch_len<const V: usize>(local_count: usize) -> usize {
    let diag = local_count.div_ceil(if V == 0 { 1 } else { V });
    match cg_len(local_count) {
        Some(cg) => cg.saturating_add(diag),
        None => usize::MAX,
    }
}

/// One process's cells in local numbering: the arrays of [`Cells::new`] (CSR offsets, nodes,
/// VTK kinds), checked inside [`PartitionedSprings::new`] so that a bad array fails on every
/// process together; with `face_diagonals`, quadrilateral faces' diagonals are springs too
/// (as in [`graph_from_cells`]).
#[derive(Clone, Copy, Debug)]
pub struct LocalCells<'c> {
    /// `nodes[offsets[c]..offsets[c + 1]]` are cell `c`'s local nodes.
    pub offsets: &'c [u32],
    /// The cells' local nodes.
    pub nodes: &'c [u32],
    /// VTK cell kinds, one per cell.
    pub kinds: &'c [u8],
    /// Quadrilateral-face diagonals as springs.
    pub face_diagonals: bool,
}

/// Length of the `targets` buffer [`PartitionedSprings::new`] needs for `cells` (twice the
/// cells' edges, as [`graph_from_cells_len`](crate::graph_builder::graph_from_cells_len);
/// unknown kinds count nothing: they fail later); `stiffness` needs as many.
pub fn partitioned_targets_len(cells: &LocalCells<'_>) -> usize {
    cells.kinds.iter().fold(0usize, |n, &k| {
        let edges = CellKind::from_vtk(k).map_or(0, |kind| {
            let diagonals = if cells.face_diagonals {
                kind.face_diagonals().len()
            } else {
                0
            };
            kind.edges().len() + diagonals
        });
        n.saturating_add(edges.saturating_mul(2))
    })
}

impl<'a, T: Real> PartitionedSprings<'a, T> {
    /// Builds this process's rows: the graph of its local `cells` (local numbering; every cell
    /// that touches an owned node must be there; checked as [`Cells::new`] checks) into `offsets` (`local_count + 1`) and
    /// `targets` ([`partitioned_targets_len`]), each row sorted by global id, and Batina's
    /// stiffness with `exponent` from the local `points` into `stiffness` (as long as
    /// `targets`). `fixed` marks Dirichlet nodes (nonzero), ghosts as their owners.
    /// **Collective** (one `sum_words`): every process returns `Ok`, or every one `Err`.
    ///
    /// Checked across processes (as hashes that cancel, in the same reduction): every edge of
    /// an owned row is seen from both ends with the same stiffness and fixed flags, so an
    /// owned row that misses an edge (a cell missing at a partition boundary, unless other
    /// local cells have its edges), or a ghost whose coordinates or mask differ from its
    /// owner's, is found. Whether every free node reaches a fixed one (serial
    /// [`SpringSystem::new`]'s check) is global and not checked; CG reports a singular system.
    ///
    /// # Errors
    /// Those of [`Cells::new`], [`graph_from_cells`] and
    /// [`batina_stiffness`](super::batina_stiffness) on the local data, lengths ([`Error::LengthMismatch`], [`Error::BufferTooSmall`]), and
    /// [`Error::BadPartition`] with [`PartitionFault::Rows`] or
    /// [`PartitionFault::OtherProcess`].
    #[allow(clippy::too_many_arguments)]
    pub fn new<const D: usize, E: Exchange<T> + ?Sized>(
        part: Partition<'a>,
        cells: LocalCells<'_>,
        points: &[[T; D]],
        exponent: T,
        fixed: &'a [u8],
        offsets: &'a mut [u32],
        targets: &'a mut [u32],
        stiffness: &'a mut [T],
        exchange: &E,
    ) -> Result<Self> {
        let built = build_rows(
            &part, cells, points, exponent, fixed, offsets, targets, stiffness,
        );
        let (offsets, targets, stiffness): (&'a [u32], &'a [u32], &'a [T]) =
            (offsets, targets, stiffness);
        let used = *built.as_ref().unwrap_or(&0);
        let sys = SpringSystem::trusted(
            Graph::trusted(offsets, targets.get(..used).unwrap_or(&[])),
            stiffness.get(..used).unwrap_or(&[]),
            fixed,
        );
        let mut words = [0i64; 3];
        if built.is_ok() {
            for (w, s) in words.iter_mut().skip(1).zip(SEEDS) {
                *w = rows_hash(&part, &sys, s) as i64;
            }
        }
        agree(exchange, built.map(|_| ()), &mut words)?;
        if words.iter().skip(1).any(|&w| w as u64 % P != 0) {
            return Err(fault(PartitionFault::Rows, 0));
        }
        Ok(PartitionedSprings { part, sys })
    }

    /// The partition.
    pub fn partition(&self) -> &Partition<'a> {
        &self.part
    }

    /// The local system (owned rows complete; its anchoring was not checked).
    pub fn system(&self) -> &SpringSystem<'a, T> {
        &self.sys
    }
}

/// The local graph (rows sorted by global id) and stiffness; the number of `targets` used.
#[allow(clippy::too_many_arguments)]
fn build_rows<T: Real, const D: usize>(
    part: &Partition<'_>,
    cells: LocalCells<'_>,
    points: &[[T; D]],
    exponent: T,
    fixed: &[u8],
    offsets: &mut [u32],
    targets: &mut [u32],
    stiffness: &mut [T],
) -> Result<usize> {
    let n = part.local_count();
    let local = Cells::new(n, cells.offsets, cells.nodes, cells.kinds)?;
    check::len("points", points.len(), n)?;
    check::len("fixed", fixed.len(), n)?;
    let used = graph_from_cells(&local, cells.face_diagonals, offsets, targets)?;
    for w in offsets.windows(2) {
        if let [a, b] = *w {
            if let Some(row) = targets.get_mut(a as usize..(b as usize).min(used)) {
                heap_sort(&mut ByKey {
                    items: row,
                    key: |j| part.global_id(j as usize),
                });
            }
        }
    }
    check::buffer("stiffness", stiffness.len(), used)?;
    let graph = Graph::new(offsets, targets.get(..used).unwrap_or(&[]))?;
    let k = stiffness.get_mut(..used).unwrap_or(&mut []);
    super::batina_stiffness(&graph, points, exponent, k)?;
    Ok(used)
}

/// `Σ ±H(lo, f_lo, hi, f_hi, k)` over the owned rows' edges (`+` from the end with the smaller
/// global id), mod [`P`]: over all processes 0 when every edge is seen from both ends alike.
fn rows_hash<T: Real>(part: &Partition<'_>, sys: &SpringSystem<'_, T>, seed: u64) -> u64 {
    let mut h = 0u64;
    for (i, fi, row) in sys.rows_in(0..part.owned()) {
        let gi = part.global_id(i);
        for (j, k) in row {
            let gj = part.global_id(j);
            let fj = sys.is_fixed(j);
            let (lo, flo, hi, fhi) = if gi < gj {
                (gi, fi, gj, fj)
            } else {
                (gj, fj, gi, fi)
            };
            let e = hash(
                seed,
                &[lo, u64::from(flo), hi, u64::from(fhi), k.to_bits_u64()],
            );
            h = (h + if gi < gj { e } else { negate(e) }) % P;
        }
    }
    h
}

impl<T: Real> PartitionedSprings<'_, T> {
    /// Solves the linear springs on the distributed field with CG and a Jacobi or no
    /// preconditioner: the result on the owned nodes, the iteration count and the residual
    /// are those of the serial
    /// [`solve_linear`](SpringSystem::solve_linear) with `LinearMethod::Cg` on the whole mesh,
    /// bit for bit. `values` holds `V` reals per local node (the owned ones are read; ghosts
    /// are taken from their owners); on `Ok` every local node holds the last iterate.
    /// **Collective**: every process calls it, and all return `Ok` or all `Err`.
    ///
    /// # Errors
    /// `values` untouched on error: a wrong length or non-finite owned value, bad options,
    /// another preconditioner ([`Error::InvalidParameter`]), `scratch` shorter than
    /// [`partitioned_cg_scratch_len`] (on any process: the others report
    /// [`PartitionFault::OtherProcess`]); [`Error::SingularSystem`] and [`Error::Overflow`]
    /// as the serial solve (on every process alike: they follow from merged sums).
    pub fn solve_cg<const V: usize, E: Exchange<T> + ?Sized>(
        &self,
        values: &mut [[T; V]],
        preconditioner: Preconditioner<T>,
        options: &SolveOptions<T>,
        scratch: &mut [[T; V]],
        exchange: &E,
    ) -> Result<SolveReport<T>> {
        let (n, owned) = (self.part.local_count(), self.part.owned());
        let local = self.check_solve(values, preconditioner, options, scratch.len());
        agree(exchange, local, &mut [0i64])?;
        let comm = HaloCollective::new(owned, self.part.halo(), exchange);
        // The serial exponents from the merged maxima (owned rows: all of them once).
        let owned_edges = self.sys.graph().edge_range(owned.saturating_sub(1)).end;
        let kmax = self
            .sys
            .stiffness()
            .get(..owned_edges)
            .unwrap_or(&[])
            .iter()
            .fold(T::ZERO, |m, &k| m.max(k));
        let mut kmax = [kmax];
        comm.max(&mut kmax);
        let mut vmax = component_max(values.get(..owned).unwrap_or(&[]));
        comm.max(&mut vmax);
        let exps = exponents_from(kmax[0], vmax, false);
        let actual = scratch.len();
        let Some((mut v, rest)) = Vectors::split(scratch, n) else {
            return Err(Error::BufferTooSmall {
                arg: "scratch",
                needed: partitioned_cg_scratch_len::<V>(n),
                actual,
            });
        };
        let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
        diagonal(&self.sys, diag);
        let diag: &[T] = diag;
        let sys = &self.sys;
        let op = Laplacian::<T, true> { sys, diag };
        let mut pre = OneLevel {
            sys,
            diag,
            pre: preconditioner,
        };
        scale_owned(v.x, values, exps.map(|e| T::pow2(-e)), owned, |_| true);
        comm.share(v.x.as_flattened_mut(), V);
        let report = pcg(&op, &mut pre, &mut v, &exps, options, &comm)?;
        if !(report.converged && report.iterations == 0) {
            let up = exps.map(|e| T::pow2(e));
            scale_owned(values, v.x, up, owned, |i| !sys.is_fixed(i));
        }
        comm.share(values.as_flattened_mut(), V);
        Ok(report)
    }

    /// What this process can check of a solve's arguments alone.
    fn check_solve<const V: usize>(
        &self,
        values: &[[T; V]],
        preconditioner: Preconditioner<T>,
        options: &SolveOptions<T>,
        scratch_len: usize,
    ) -> Result<()> {
        let (n, owned) = (self.part.local_count(), self.part.owned());
        check::len("values", values.len(), n)?;
        check::finite_items("values", values.get(..owned).unwrap_or(&[]))?;
        options.check()?;
        if matches!(preconditioner, Preconditioner::Ssor { .. }) {
            return Err(Error::InvalidParameter {
                arg: "preconditioner",
                reason: "partitioned: Jacobi or none (SSOR sweeps every node in order)",
            });
        }
        check::buffer("scratch", scratch_len, partitioned_cg_scratch_len::<V>(n))
    }
}

/// `out_i = from_i ⊙ f` at the owned nodes `i` where `at(i)`.
fn scale_owned<T: Real, const V: usize>(
    out: &mut [[T; V]],
    from: &[[T; V]],
    f: [T; V],
    owned: usize,
    at: impl Fn(usize) -> bool,
) {
    for (i, (o, v)) in out.iter_mut().zip(from).enumerate().take(owned) {
        if at(i) {
            for ((o, &v), &f) in o.iter_mut().zip(v).zip(&f) {
                *o = v * f;
            }
        }
    }
}
