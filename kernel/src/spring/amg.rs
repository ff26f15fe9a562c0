//! Smoothed-aggregation algebraic multigrid (SA-AMG) as a conjugate-gradient preconditioner
//! for the linear springs.
//!
//! Every value component of a linear-spring solve (displacements `V = D`, the quaternion
//! method's `V = D + 4`, joint solves) sees the same scalar operator: the weighted graph
//! Laplacian restricted to the free nodes (`A_ii = Σ_j k_ij` over all neighbours, `A_ij = −k_ij`
//! for free `j`). So the hierarchy is built once on that scalar operator and applied to all `V`
//! components at once.
//!
//! Construction (Vaněk, Mandel & Brezina's smoothed aggregation, as in pyamg's defaults):
//! - **strength of connection** on the fine level: a spring is strong when `k_ij ≥ θ √(m_i m_j)`,
//!   `m_i` the stiffest spring at node `i` (θ = 0.25 by default: on a stretched boundary layer
//!   the long, soft springs along the layer are weak, so aggregates follow the layer; on an
//!   isotropic mesh nearly every spring is strong); coarse levels use all their connections
//!   (their sparsity is then known before their values, which makes the size query exact);
//! - **aggregation**: pyamg's standard two-pass aggregation in fixed node order (roots with all
//!   their free neighbours, then leftovers join a neighbouring aggregate); fixed nodes belong to
//!   no aggregate, so they are eliminated from every coarse problem;
//! - **tentative prolongator** `T`: piecewise constant (the constant is the near-null space of a
//!   free spring network);
//! - **smoothed prolongator** `P = (I − ω D⁻¹ A) T`, `ω = (4/3) / ρ`, with `ρ` the Gershgorin
//!   bound of `ρ(D⁻¹A)` (an upper bound, so the smoother and the prolongator stay stable);
//! - **Galerkin coarse operators** `Pᵀ A P` (sparse triple product, symbolic then numeric),
//!   symmetrised exactly;
//! - **coarsest level**: dense Cholesky when it has at most `max_coarse` unknowns, otherwise
//!   the smoother;
//! - **V-cycle**: damped Jacobi pre- and post-smoothing with the same weight and sweep count
//!   (a symmetric preconditioner, so CG stays valid; no Gauss–Seidel, so the result does not
//!   depend on a node partition).
//!
//! Storage: all of it in caller buffers. [`AmgHierarchy::setup_len`] runs the symbolic pass in
//! a `work` buffer of [`AmgHierarchy::setup_work_len`] entries and returns the exact
//! [`AmgSizes`]; [`AmgHierarchy::setup`] fills an `index` (`u32`) and a `values` (`T`) buffer of
//! those sizes. The buffers are reusable: a new setup (new stiffness, next time step) writes
//! them again. [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) then runs the preconditioned CG.
//!
//! The angle-inclusion springs use the same scalar hierarchy: [`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg)
//! applies its V-cycle to each displacement component as the preconditioner of the
//! angle-inclusion CG (SPD, and spectrally equivalent to the angle operator for `ε > 0`).

mod cycle;
mod mis2;
mod partitioned;
mod pcg;
mod pools;
pub(crate) use pcg::{solve_amg_on, Vcycle};
mod rigid;
mod rigid_cycle;
mod rigid_numeric;
mod setup;

pub(crate) use rigid::Fine;
pub use rigid::{rigid_mode_count, RigidAmg, RigidAmgSizes};
pub(crate) use rigid_cycle::RigidVcycle;

pub use mis2::{
    aggregate_mis2, aggregate_mis2_partitioned, mis2_exchange_len, mis2_scratch_len, Mis2Report,
    MIS2_NONE,
};
pub use partitioned::{prolongator_partitioned, prolongator_partitioned_len};
pub use pcg::{
    amg_cg_scratch_len, amg_precondition_scratch_len, amg_sliding_cg_scratch_len,
    solve_linear_amg_scratch_len,
};
pub use pools::{AmgPools, AmgSolve};

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::system::SpringSystem;

/// Most levels a hierarchy can have (the level table is a fixed-size array).
pub const AMG_MAX_LEVELS: usize = 16;

/// Largest `max_coarse` accepted (the dense coarsest factor needs `max_coarse²` values).
pub const AMG_MAX_DENSE: usize = 2048;

/// Options of the multigrid hierarchy and its V-cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AmgOptions<T> {
    /// Strength-of-connection threshold θ in `[0, 1)` for the fine level: a spring `i–j` is
    /// strong when `k_ij ≥ θ √(m_i m_j)`, `m_i` the stiffest spring at node `i` (the classical
    /// measure relative to the row's largest entry, made symmetric). Default 0.25; 0 makes every
    /// spring strong (pyamg's smoothed-aggregation default). Only the preconditioner depends
    /// on it, not the answer (docs/amg.md, "Strength of connection").
    pub strength_theta: T,
    /// Most levels, in `1..=`[`AMG_MAX_LEVELS`] (1 = the smoother alone). Default 10.
    pub max_levels: usize,
    /// Coarsening stops at a coarse level with at most this many unknowns, which is then solved
    /// by dense Cholesky; in `1..=`[`AMG_MAX_DENSE`]. Default 256.
    pub max_coarse: usize,
    /// The smoother of every level (the same before and after the coarse correction, so the
    /// V-cycle is symmetric). Default Chebyshev.
    pub smoother: AmgSmoother,
    /// Smoothing steps before and after the coarse correction (the Chebyshev degree), in
    /// `1..=`[`AMG_MAX_SWEEPS`]. Default 2.
    pub sweeps: usize,
}

/// Most smoothing steps per application ([`AmgOptions::sweeps`]).
pub const AMG_MAX_SWEEPS: usize = 16;

/// The V-cycle's smoother. Both are Richardson steps `x += ω_s D⁻¹ (b − A x)` (node-local,
/// partition-independent) and differ in the weights.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AmgSmoother {
    /// Damped Jacobi: `ω = (4/3) / ρ` every step, `ρ` the Gershgorin bound of `ρ(D⁻¹A)`.
    Jacobi,
    /// Chebyshev polynomial in `D⁻¹A` in product form: step `s` of `m` uses `ω_s = 1 / λ_s` with
    /// `λ_s` the roots of the degree-`m` Chebyshev polynomial on `[ρ/30, ρ]` (the interval
    /// pyamg's Chebyshev smoother targets).
    Chebyshev,
}

impl<T: Real> Default for AmgOptions<T> {
    fn default() -> Self {
        AmgOptions {
            strength_theta: T::from_f64(0.25),
            max_levels: 10,
            max_coarse: 256,
            smoother: AmgSmoother::Chebyshev,
            sweeps: 2,
        }
    }
}

/// `options` with every connection strong (`strength_theta` = 0): the MIS-2 hierarchy's.
fn every_connection<T: Real>(options: &AmgOptions<T>) -> AmgOptions<T> {
    AmgOptions {
        strength_theta: T::ZERO,
        ..*options
    }
}

impl<T: Real> AmgOptions<T> {
    /// Checks every option (see the field docs).
    fn check(&self) -> Result<()> {
        let t = self.strength_theta;
        if !(t.is_finite() && t >= T::ZERO && t < T::ONE) {
            return Err(Error::InvalidParameter {
                arg: "strength_theta",
                reason: "must be in [0, 1)",
            });
        }
        if self.max_levels == 0 || self.max_levels > AMG_MAX_LEVELS {
            return Err(Error::InvalidParameter {
                arg: "max_levels",
                reason: "must be in 1..=AMG_MAX_LEVELS",
            });
        }
        if self.max_coarse == 0 || self.max_coarse > AMG_MAX_DENSE {
            return Err(Error::InvalidParameter {
                arg: "max_coarse",
                reason: "must be in 1..=AMG_MAX_DENSE",
            });
        }
        if self.sweeps == 0 || self.sweeps > AMG_MAX_SWEEPS {
            return Err(Error::InvalidParameter {
                arg: "sweeps",
                reason: "must be in 1..=AMG_MAX_SWEEPS",
            });
        }
        Ok(())
    }
}

/// Exact buffer sizes of one hierarchy ([`AmgHierarchy::setup_len`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AmgSizes {
    /// `u32` entries of the `index` buffer (aggregates, prolongator and coarse-operator
    /// sparsity).
    pub index: usize,
    /// `T` entries of the `values` buffer (diagonals, prolongator and coarse-operator values,
    /// dense coarsest factor, one accumulator row).
    pub values: usize,
    /// Number of levels (1 = no coarse level).
    pub levels: usize,
    /// Unknowns on all coarse levels together (the V-cycle's vectors; see
    /// [`solve_linear_amg_scratch_len`]).
    pub coarse_unknowns: usize,
}

/// Where one level's arrays live in the `index` / `values` buffers. Level 0 reads its operator
/// from the [`SpringSystem`]; levels `≥ 1` have a CSR operator (off-diagonal entries, sorted
/// columns) and a separate diagonal. Every level but the coarsest has an aggregate map and a
/// prolongator to the next level, stored by rows (`p_*`) and by columns (`pt_*`: row index and
/// position of the entry in `p_*`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Level {
    /// Unknowns on this level (level 0: all nodes, fixed ones inactive).
    pub n: usize,
    /// `values`: diagonal (`n`).
    pub diag: usize,
    /// `index`: operator row offsets (`n + 1`, levels ≥ 1).
    pub a_offs: usize,
    /// `index`: operator columns (`a_nnz`).
    pub a_cols: usize,
    /// Off-diagonal operator entries.
    pub a_nnz: usize,
    /// `values`: operator values (`a_nnz`).
    pub a_vals: usize,
    /// `index`: aggregate of every unknown (`n`; `NONE` = in no aggregate).
    pub agg: usize,
    /// `index`: prolongator row offsets (`n + 1`).
    pub p_offs: usize,
    /// `index`: prolongator columns (`p_nnz`).
    pub p_cols: usize,
    /// Prolongator entries.
    pub p_nnz: usize,
    /// `values`: prolongator values (`p_nnz`).
    pub p_vals: usize,
    /// `index`: transposed prolongator offsets (`n_next + 1`).
    pub pt_offs: usize,
    /// `index`: transposed prolongator rows (`p_nnz`).
    pub pt_rows: usize,
    /// `index`: position in `p_cols`/`p_vals` of each transposed entry (`p_nnz`).
    pub pt_pos: usize,
}

/// The whole buffer layout of a hierarchy: computed by the symbolic pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// The level table (the first `count` entries are used).
    pub levels: [Level; AMG_MAX_LEVELS],
    /// Levels in use (≥ 1).
    pub count: usize,
    /// `index` entries used.
    pub index_len: usize,
    /// `values` entries used.
    pub values_len: usize,
    /// `values`: dense coarsest Cholesky factor (`dense_n²`), when `dense_n > 0`.
    pub dense: usize,
    /// Size of the dense coarsest factor (0 = the coarsest level is smoothed, not factored).
    pub dense_n: usize,
    /// `values`: accumulator row of the setup (`acc_len`).
    pub acc: usize,
    /// Accumulator length (largest coarse level).
    pub acc_len: usize,
    /// Nodes and directed edges of the system the layout was built for.
    pub nodes: usize,
    /// Directed edges of the system.
    pub edges: usize,
}

impl Layout {
    /// The level table entry `l` (a default, empty level when out of range).
    #[inline]
    pub fn level(&self, l: usize) -> Level {
        self.levels.get(l).copied().unwrap_or_default()
    }

    /// The buffer sizes this layout needs.
    pub fn sizes(&self) -> AmgSizes {
        AmgSizes {
            index: self.index_len,
            values: self.values_len,
            levels: self.count,
            coarse_unknowns: self.coarse_unknowns(),
        }
    }

    /// Unknowns on all coarse levels.
    pub fn coarse_unknowns(&self) -> usize {
        self.levels
            .iter()
            .take(self.count)
            .skip(1)
            .fold(0usize, |s, l| s.saturating_add(l.n))
    }
}

/// A smoothed-aggregation multigrid hierarchy for one [`SpringSystem`], stored in caller
/// buffers; the preconditioner of [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg).
///
/// ```
/// use deform_kernel::spring::{
///     solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions, SolveOptions,
///     SpringSystem,
/// };
/// use deform_kernel::{graph_from_edges, graph_from_edges_len, Graph};
/// // A chain of 40 springs, both ends fixed (at 0 and 1).
/// let n = 41;
/// let edges: Vec<[u32; 2]> = (0..n as u32 - 1).map(|i| [i, i + 1]).collect();
/// let mut offsets = vec![0u32; n + 1];
/// let mut targets = vec![0u32; graph_from_edges_len(&edges)];
/// let used = graph_from_edges(n, &edges, &mut offsets, &mut targets)?;
/// let g = Graph::new(&offsets, &targets[..used])?;
/// let k = vec![1.0f64; g.edge_count()];
/// let mut fixed = vec![0u8; n];
/// fixed[0] = 1;
/// fixed[n - 1] = 1;
/// let mut s = vec![0u32; n];
/// let sys = SpringSystem::new(g, &k, &fixed, &mut s)?;
///
/// // Symbolic pass (exact sizes), then the hierarchy in buffers of exactly those sizes.
/// let opts = AmgOptions { max_coarse: 4, ..AmgOptions::default() };
/// let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
/// let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work)?;
/// let mut index = vec![0u32; sizes.index];
/// let mut values = vec![0.0f64; sizes.values];
/// let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values)?;
/// assert!(h.levels() >= 2);
///
/// let mut x = vec![[0.0f64]; n];
/// x[n - 1] = [1.0];
/// let mut scratch = vec![[0.0f64]; solve_linear_amg_scratch_len(&h)];
/// let report = sys.solve_linear_amg(&h, &mut x, &SolveOptions::default(), &mut scratch)?;
/// assert!(report.converged);
/// assert!((x[10][0] - 0.25).abs() < 1e-8); // linear between the fixed ends
/// # Ok::<(), deform_kernel::Error>(())
/// ```
#[derive(Clone, Copy, Debug)]
pub struct AmgHierarchy<'a, T: Real> {
    layout: Layout,
    /// Smoothing weights of every level and step.
    weights: [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS],
    index: &'a [u32],
    values: &'a [T],
    sweeps: usize,
}

/// `u32` entries of the `work` buffer of the hierarchy's symbolic pass for a system of
/// `node_count` nodes and `edge_count` directed edges: `4 (N + E) + 64`, saturating (what
/// [`AmgHierarchy::setup_work_len`] returns), for callers that size buffers before they have a
/// validated system (plans, the C ABI).
pub const fn amg_setup_work_len(node_count: usize, edge_count: usize) -> usize {
    setup::budget(node_count, edge_count)
}

impl<'a, T: Real> AmgHierarchy<'a, T> {
    /// `u32` entries of the `work` buffer [`AmgHierarchy::setup_len`] and
    /// [`AmgHierarchy::setup`] need for their symbolic pass: `4 (N + E) + 64` for `N` nodes
    /// and `E` directed edges. The hierarchy never needs more: coarsening stops at a level whose
    /// successor would not fit (which does not happen on meshes; see [`AmgSizes::levels`]).
    pub fn setup_work_len(sys: &SpringSystem<'_, T>) -> usize {
        setup::budget(sys.node_count(), sys.graph().edge_count())
    }

    /// The symbolic pass: aggregation and the sparsity of every prolongator and coarse
    /// operator, in `work`; returns the exact buffer sizes [`AmgHierarchy::setup`] needs.
    ///
    /// # Errors
    /// Invalid `options` ([`Error::InvalidParameter`]), `work` shorter than
    /// [`AmgHierarchy::setup_work_len`] ([`Error::BufferTooSmall`]), more than `2³¹ − 2`
    /// nodes ([`Error::TooLarge`]). Only `work` is written.
    pub fn setup_len(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        work: &mut [u32],
    ) -> Result<AmgSizes> {
        let layout = setup::symbolic(sys, options, work)?;
        Ok(layout.sizes())
    }

    /// Builds the hierarchy: the symbolic pass again in `work` (scratch), then the numeric pass
    /// into `index` and `values`, which need at least the [`AmgSizes`] of
    /// [`AmgHierarchy::setup_len`] (larger buffers work; the tail is untouched). The hierarchy
    /// borrows the two buffers; they are reusable for the next setup.
    ///
    /// # Errors
    /// Those of [`AmgHierarchy::setup_len`]; `index` or `values` too short
    /// ([`Error::BufferTooSmall`], checked before either is written); a coarse operator that is
    /// not positive definite in floating point, e.g. from overflowing stiffness
    /// ([`Error::SingularSystem`] with `iteration: 0`; `index` and `values` then hold no
    /// hierarchy).
    pub fn setup(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        work: &mut [u32],
        index: &'a mut [u32],
        values: &'a mut [T],
    ) -> Result<Self> {
        let layout = setup::symbolic(sys, options, work)?;
        Self::numeric(sys, options, layout, work, index, values)
    }

    /// `u64` entries of the extra scratch of [`AmgHierarchy::setup_len_mis2`] and
    /// [`AmgHierarchy::setup_mis2`]: three per node.
    pub fn mis2_work_len(sys: &SpringSystem<'_, T>) -> usize {
        mis2::hierarchy_scratch_len(sys.node_count())
    }

    /// [`AmgHierarchy::setup_len`] with every level aggregated by the partition-independent
    /// MIS-2 ([`aggregate_mis2`]) instead of the greedy node-order aggregation, on every
    /// connection (`strength_theta` is not used: the partitioned aggregation,
    /// [`aggregate_mis2_partitioned`](crate::spring::aggregate_mis2_partitioned), has no
    /// strength test). Experimental: not the default (docs/amg.md, "Partition-independent
    /// aggregation").
    ///
    /// # Errors
    /// Those of [`AmgHierarchy::setup_len`]; `mis2_work` shorter than
    /// [`AmgHierarchy::mis2_work_len`] ([`Error::BufferTooSmall`]). Only the two work
    /// buffers are written.
    pub fn setup_len_mis2(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        work: &mut [u32],
        mis2_work: &mut [u64],
    ) -> Result<AmgSizes> {
        check::buffer("mis2_work", mis2_work.len(), Self::mis2_work_len(sys))?;
        let layout = setup::symbolic_with(sys, &every_connection(options), work, Some(mis2_work))?;
        Ok(layout.sizes())
    }

    /// [`AmgHierarchy::setup`] with the aggregation of [`AmgHierarchy::setup_len_mis2`].
    ///
    /// # Errors
    /// Those of [`AmgHierarchy::setup`] and [`AmgHierarchy::setup_len_mis2`].
    pub fn setup_mis2(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        work: &mut [u32],
        mis2_work: &mut [u64],
        index: &'a mut [u32],
        values: &'a mut [T],
    ) -> Result<Self> {
        check::buffer("mis2_work", mis2_work.len(), Self::mis2_work_len(sys))?;
        let layout = setup::symbolic_with(sys, &every_connection(options), work, Some(mis2_work))?;
        Self::numeric(sys, options, layout, work, index, values)
    }

    /// The numeric pass of a setup on the symbolic `layout` in `work`.
    fn numeric(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        layout: Layout,
        work: &[u32],
        index: &'a mut [u32],
        values: &'a mut [T],
    ) -> Result<Self> {
        check::buffer("index", index.len(), layout.index_len)?;
        check::buffer("values", values.len(), layout.values_len)?;
        let index = index.get_mut(..layout.index_len).unwrap_or(&mut []);
        let values = values.get_mut(..layout.values_len).unwrap_or(&mut []);
        for (d, &s) in index.iter_mut().zip(work.iter()) {
            *d = s;
        }
        let rho = setup::numeric(sys, &layout, index, values)?;
        let weights = setup::smoothing_weights(&rho, options.smoother, options.sweeps);
        Ok(AmgHierarchy {
            layout,
            weights,
            index,
            values,
            sweeps: options.sweeps,
        })
    }

    /// The layout, smoothing weights and sweep count: what a prepared plan stores beside the
    /// two buffers to rebuild the hierarchy with [`AmgHierarchy::from_parts`].
    #[inline]
    pub(crate) fn parts(&self) -> (Layout, [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS], usize) {
        (self.layout, self.weights, self.sweeps)
    }

    /// A hierarchy from parts [`AmgHierarchy::setup`] produced before (no check: the plan
    /// validates its header and checksum instead).
    #[inline]
    pub(crate) fn from_parts(
        layout: Layout,
        weights: [[T; AMG_MAX_SWEEPS]; AMG_MAX_LEVELS],
        sweeps: usize,
        index: &'a [u32],
        values: &'a [T],
    ) -> Self {
        AmgHierarchy {
            layout,
            weights,
            index,
            values,
            sweeps,
        }
    }

    /// Number of levels (1 = the smoother alone).
    #[inline]
    pub fn levels(&self) -> usize {
        self.layout.count
    }

    /// Unknowns on level `l` (level 0: every node, fixed ones included; 0 beyond the last
    /// level).
    #[inline]
    pub fn level_size(&self, l: usize) -> usize {
        if l < self.layout.count {
            self.layout.level(l).n
        } else {
            0
        }
    }

    /// Off-diagonal entries of level `l`'s operator (level 0: the directed edges of the
    /// system).
    #[inline]
    pub fn level_entries(&self, l: usize) -> usize {
        match l {
            0 => self.layout.edges,
            l if l < self.layout.count => self.layout.level(l).a_nnz,
            _ => 0,
        }
    }

    /// Row `i` of level `l`'s prolongator (`l + 1 < levels()`): its columns (level `l + 1`
    /// unknowns, increasing) and values; empty past the end.
    pub fn prolongator_row(&self, l: usize, i: usize) -> (&'a [u32], &'a [T]) {
        if l + 1 >= self.layout.count || i >= self.layout.level(l).n {
            return (&[], &[]);
        }
        let lv = self.layout.level(l);
        let (s, len) = setup::csr_row(self.index, lv.p_offs, lv.p_cols, i);
        let rel = s.saturating_sub(lv.p_cols);
        (
            seg(self.index, s, len),
            seg(self.values, lv.p_vals.saturating_add(rel), len),
        )
    }

    /// Unknowns on all coarse levels together.
    #[inline]
    pub fn coarse_unknowns(&self) -> usize {
        self.layout.coarse_unknowns()
    }

    /// Checks that the hierarchy was built for a system of this shape.
    pub(crate) fn check_system(&self, sys: &SpringSystem<'_, T>) -> Result<()> {
        check::len("hierarchy", self.layout.nodes, sys.node_count())?;
        check::len("hierarchy", self.layout.edges, sys.graph().edge_count())?;
        Ok(())
    }
}

/// `buf[start .. start + len]`, empty when out of range (never panics).
#[inline]
pub(crate) fn seg<X>(buf: &[X], start: usize, len: usize) -> &[X] {
    buf.get(start..start.saturating_add(len)).unwrap_or(&[])
}

/// Mutable [`seg`].
#[inline]
pub(crate) fn seg_mut<X>(buf: &mut [X], start: usize, len: usize) -> &mut [X] {
    buf.get_mut(start..start.saturating_add(len))
        .unwrap_or(&mut [])
}

/// Entry `i` of a `u32` array as `usize` (`usize::MAX` when out of range).
#[inline]
pub(crate) fn at(buf: &[u32], i: usize) -> usize {
    buf.get(i).map_or(usize::MAX, |&x| x as usize)
}
