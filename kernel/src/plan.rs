//! Prepared deformation plans in caller memory: validate and set up once, step many times.
//!
//! A flow or structural solver moves its boundary every time step. The stateless entry points
//! re-validate the graph (symmetry, anchoring), rebuild stiffness and multigrid hierarchy and
//! start the solve from a cold guess on every call. A [`Plan`] does that work once, in
//! [`Plan::init`], into three caller buffers (pools):
//!
//! - `reals: &mut [T]`: reference points, stiffness, solver parameters, the hierarchy's
//!   values, the previous solution (warm start) and the step workspaces;
//! - `indices: &mut [u32]`: a header (magic, version, counts, checksum, step counter), the
//!   mesh graph (copied in), the boundary node list and elements, the hierarchy's layout and
//!   index arrays;
//! - `bytes: &mut [u8]`: the per-node constraint table (kind codes as in
//!   [`crate::spring::constraints`]: 0 free, 1 fixed) and the fixed mask of the spring system.
//!
//! [`Plan::sizes`] returns their exact lengths ([`PlanSizes`]); both need a transient
//! [`PlanWork`] (sizes from [`Plan::work_sizes`]), which can be freed after `init`. Then
//! [`Plan::step`] takes the new boundary positions and writes the deformed mesh; the previous
//! step's solution is the initial guess ([`Start::Warm`]) and the [`StepReport`] says how many
//! iterations the solve took.
//!
//! **Offsets, not pointers.** The plan stores only counts and positions inside its pools, so
//! the pools can be copied, written to disk and read back: [`Plan::open`] checks the header
//! (magic, version, scalar type, dimension, sizes) and a 64-bit checksum of every part that
//! never changes, and resumes with the same bits (the warm-start state travels with the pools).
//! A corrupted or foreign buffer is [`Error::BadPlan`](crate::Error::BadPlan), never garbage.
//!
//! **Lifetime rules.** After `init` the plan borrows nothing from the caller but its three
//! pools: points, graph, boundary list, elements and stiffness are copied in. The plan stays
//! valid while the mesh connectivity, the reference points, the boundary node list (the fixed
//! set) and the constraint table stay the same; changing any of them means a new plan
//! ([`Plan::init`] again, the same pools can be reused when the sizes still fit). Each step
//! deforms the *reference* mesh (positions are absolute), so stiffness and hierarchy never go
//! stale. A plan holds no pointers, so moving or copying the pools is always safe; a `Plan`
//! value is only a view, cheap to drop and reopen.
//!
//! **Methods** ([`PlanMethod`]): linear springs on the displacements (`V = D` values per
//! node) and the quaternion method with linear-spring propagation (`V = D + 4`), each with any
//! linear-spring solver ([`PlanSolver`]: the multigrid-preconditioned CG or a one-level
//! method). A cold step gives exactly the bits of the stateless calls
//! ([`solve_linear_with`](crate::spring::SpringSystem::solve_linear_with) from zero free displacements,
//! [`deform_spring_with`](crate::quaternion::deform_spring_with)); a warm step starts from
//! the previous solution instead.
//!
//! **Constraints.** The pools already hold a per-node kind table and a reserved section for
//! sliding directions ([`PlanSpec::constraints`]); today a plan accepts only free and fixed
//! nodes, and a table with sliding kinds is refused with
//! [`Error::InvalidParameter`](crate::Error::InvalidParameter).
//!
//! **Node order** ([`PlanSpec::renumber`], [`PlanOrder`]). A mesh numbered as a generator
//! writes it puts neighbours far apart in memory, and every sweep, product and multigrid
//! level of every step misses the cache (issue 34: half of a spring solve on a 234k-node gmsh
//! mesh). Asked to, `init` renumbers the mesh once for locality (reverse Cuthill–McKee from
//! the graph, or a Hilbert curve through the points), in the init work, and stores the
//! permutation in the index pool (checksummed, so a copied plan reopens with it) and the
//! graph, points, boundary list and stiffness permuted. The caller sees nothing of it:
//! `step` takes the boundary positions in [`PlanSpec::boundary`] order as always and writes
//! `out` in the caller's numbering. The output is bit for bit the un-permuted output of a
//! plan built without the option on the mesh renumbered by the same permutation
//! ([`Plan::permutation`] returns it), and equal to the unordered plan's to solver
//! tolerance. Node indices in `init`'s errors are the caller's. The default,
//! [`PlanOrder::AsGiven`], keeps every plan's bits and pool sizes. A solver that already
//! orders its mesh (most finite-volume codes renumber for their own sweeps) should leave it
//! off and not pay twice: the ordering costs `O(E)` (RCM) or `O(N log N)` (Hilbert) at init,
//! `2N` indices in the pool and a scattered write of `out` each step.
//!
//! **Derivatives** ([`Plan::tangent`], [`Plan::adjoint`], scratch from
//! [`Plan::sensitivity_scratch_len`]): the tangent and adjoint of the last step with respect to
//! the deformed boundary positions, one solve each with the stored hierarchy and, for the
//! quaternion method, the stored solved field (the stateless
//! [`deform_spring_adjoint`](crate::quaternion::deform_spring_adjoint) solves the deformation
//! again first). They read the plan and never write it.
//!
//! **Errors.** `step` validates its input before it touches anything: on `Err` the caller's
//! `out` and the plan's state (previous solution, step counter) are unchanged.

mod build;
mod layout;
mod order;
mod sensitivity;
mod step;
mod storage;

pub use storage::PlanStorage;

use crate::cells::Cells;
use crate::check;
use crate::error::Result;
use crate::graph::Graph;
use crate::order::Permutation;
use crate::quaternion::RotationSource;
use crate::real::Real;
use crate::spring::constraints::Constraints;
use crate::spring::{
    AmgOptions, LinearMethod, SolveOptions, SolveReport, AMG_MAX_LEVELS, AMG_MAX_SWEEPS,
};

use layout::Meta;

/// What a plan computes each step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlanMethod {
    /// Linear (Batina) springs on the displacements: the boundary displacements are the
    /// Dirichlet data, every free node's displacement solves the spring network.
    Spring,
    /// The quaternion method (Samareh) with linear-spring propagation of `(Δ, Q)`.
    QuaternionSpring,
}

/// The linear-spring solver of a plan.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlanSolver<T> {
    /// CG preconditioned by a smoothed-aggregation hierarchy, built once at `init`.
    Amg(AmgOptions<T>),
    /// A one-level method ([`LinearMethod`]).
    Method(LinearMethod<T>),
}

/// Where the plan's stiffness comes from (computed or copied once, at `init`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlanStiffness<'a, T> {
    /// [`batina_stiffness`](crate::spring::batina_stiffness) of the reference points with
    /// this exponent (1 is Batina's).
    Batina {
        /// The exponent `p` of `1 / |r_i − r_j|^p`.
        exponent: T,
    },
    /// One stiffness per directed edge of the graph (e.g. from
    /// [`scale_stiffness`](crate::spring::scale_stiffness)); copied in.
    Given(&'a [T]),
}

/// How a plan numbers its mesh for the solve ([`PlanSpec::renumber`]; see the module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PlanOrder {
    /// The caller's numbering: no permutation stored (the sizes and bits of every plan built
    /// before the option existed).
    #[default]
    AsGiven,
    /// Reverse Cuthill–McKee of the graph ([`rcm_order`](crate::order::rcm_order)).
    Rcm,
    /// A Hilbert curve through the reference points
    /// ([`hilbert_order`](crate::order::hilbert_order)).
    Hilbert,
}

/// Everything a plan is built from. Nothing here is borrowed after [`Plan::init`].
#[derive(Clone, Copy, Debug)]
pub struct PlanSpec<'a, T: Real, const D: usize> {
    /// Reference (undeformed) mesh points, `N`. Every step deforms these.
    pub points: &'a [[T; D]],
    /// The mesh graph (edges of the cells), symmetric, `N` nodes.
    pub graph: Graph<'a>,
    /// Mesh node of each of the `B` prescribed boundary points (distinct): moved walls and
    /// fixed far field alike. Exactly these nodes are fixed in the spring system.
    pub boundary: &'a [u32],
    /// Boundary elements indexing `0..B` (segments in 2D, triangles/quadrilaterals in 3D),
    /// for [`RotationSource::Shape`] in the quaternion method; ignored by
    /// [`PlanMethod::Spring`].
    pub elements: Option<Cells<'a>>,
    /// Per-node kinds (the place for sliding boundaries): `None` derives free/fixed from
    /// `boundary`. A table must mark exactly the boundary nodes fixed; sliding kinds (plane,
    /// line) are not supported by plans yet.
    pub constraints: Option<Constraints<'a, T, D>>,
    /// What each step computes.
    pub method: PlanMethod,
    /// Spring stiffness.
    pub stiffness: PlanStiffness<'a, T>,
    /// Linear-spring solver.
    pub solver: PlanSolver<T>,
    /// Stopping rules of every step's solve.
    pub options: SolveOptions<T>,
    /// Renumber the mesh for memory locality at init ([`PlanOrder::AsGiven`]: no).
    pub renumber: PlanOrder,
}

/// Lengths of the three plan pools (or of the transient [`PlanWork`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanSizes {
    /// `T` entries.
    pub reals: usize,
    /// `u32` entries.
    pub indices: usize,
    /// `u8` entries.
    pub bytes: usize,
}

/// The mesh counts a plan's pool sizes depend on, for [`Plan::capacity`] and
/// [`Plan::work_capacity`] (sizing storage at compile time).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PlanCounts {
    /// Mesh nodes `N`.
    pub nodes: usize,
    /// Directed graph edges `E`: the graph's `targets` length, twice the mesh's edges.
    pub edges: usize,
    /// Boundary points `B`.
    pub boundary: usize,
    /// Boundary elements and their total node count (`cells.len()`, `cells.nodes().len()`)
    /// when the quaternion method is given [`PlanSpec::elements`]; `None` otherwise (ignored
    /// by [`PlanMethod::Spring`]).
    pub elements: Option<(usize, usize)>,
}

/// Transient buffers of [`Plan::sizes`] and [`Plan::init`] (lengths from
/// [`Plan::work_sizes`]); free them after `init`.
#[derive(Debug)]
pub struct PlanWork<'w, T> {
    /// `T` entries (the stiffness before it is validated).
    pub reals: &'w mut [T],
    /// `u32` entries (anchoring search, the hierarchy's symbolic pass).
    pub indices: &'w mut [u32],
    /// `u8` entries (the fixed mask before it is validated).
    pub bytes: &'w mut [u8],
}

/// How a step starts its solve.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Start {
    /// From the stored solutions: the last one, or the linear extrapolation `x_n + (x_n −
    /// x_{n−1})` of the last two, whichever has the smallest true relative residual, and the
    /// cold guess when that is smaller still (up to three residual evaluations decide). After
    /// a small motion, e.g. a pitching wall passing its rest position, the stored solutions
    /// can be the worse guesses.
    #[default]
    Warm,
    /// As the stateless calls do: zero free displacements ([`PlanMethod::Spring`]) or the
    /// mean of the boundary values ([`PlanMethod::QuaternionSpring`]).
    Cold,
}

/// One time step's boundary motion.
#[derive(Clone, Copy, Debug)]
pub struct PlanMotion<'a, T, const D: usize> {
    /// New position of each of the `B` boundary points (in [`PlanSpec::boundary`] order);
    /// reproduced exactly in the output.
    pub deformed: &'a [[T; D]],
    /// Where the rotations come from (quaternion method; ignored by [`PlanMethod::Spring`]).
    /// [`RotationSource::Shape`] uses the plan's elements.
    pub rotations: RotationSource<'a, T>,
    /// Rotation origin (quaternion method); `None` for the centroid of the moving points.
    pub origin: Option<[T; D]>,
    /// Warm or cold start.
    pub start: Start,
}

impl<'a, T, const D: usize> PlanMotion<'a, T, D> {
    /// A motion with rotations from the boundary shape, the default origin and a warm start.
    pub fn new(deformed: &'a [[T; D]]) -> Self {
        PlanMotion {
            deformed,
            rotations: RotationSource::Shape,
            origin: None,
            start: Start::Warm,
        }
    }
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct StepReport<T, const D: usize> {
    /// The solve's report (iterations, true relative residual, convergence). The output is
    /// written even when the solve did not converge; check `converged`.
    pub solve: SolveReport<T>,
    /// Whether the solve started from the stored solutions (see [`Start::Warm`]).
    pub warm: bool,
    /// Whether that start was the extrapolation from the last two solutions.
    pub extrapolated: bool,
    /// Steps completed by this plan, this one included.
    pub step: u64,
    /// The rotation origin used (quaternion method; zero for [`PlanMethod::Spring`]).
    pub origin: [T; D],
}

/// A prepared plan: a view of three caller pools ([`Plan::init`], [`Plan::open`]).
pub struct Plan<'a, T: Real, const D: usize> {
    reals: &'a mut [T],
    indices: &'a mut [u32],
    bytes: &'a mut [u8],
    meta: Meta,
    amg: Option<layout::AmgParts<T>>,
}

/// The counts, not the pools (which can hold hundreds of megabytes).
impl<T: Real, const D: usize> core::fmt::Debug for Plan<'_, T, D> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Plan")
            .field("method", &self.meta.method)
            .field("nodes", &self.meta.n)
            .field("boundary", &self.meta.b)
            .field("used", &self.meta.sizes)
            .field("steps", &self.meta.steps)
            .field("amg_levels", &self.amg_levels())
            .field("renumbering", &self.renumbering())
            .finish()
    }
}

impl<'a, T: Real, const D: usize> Plan<'a, T, D> {
    /// Lengths of the transient [`PlanWork`] for this spec: `E` reals, `max(4 (N + E) + 64,
    /// N)` indices, `N` bytes; renumbered ([`PlanSpec::renumber`]) `E + N D` reals and
    /// `3 N + 1 + 2 E` indices more (the permutation, the permuted graph with its edge map,
    /// the permuted points).
    ///
    /// # Errors
    /// The length checks of [`Plan::sizes`] that need no work buffers: `points` not `N`
    /// long, a given stiffness not `E` long, constraints not `N` long
    /// ([`Error::LengthMismatch`](crate::Error::LengthMismatch)), an empty boundary
    /// ([`Error::InvalidParameter`](crate::Error::InvalidParameter)). So a spec that
    /// [`Plan::sizes`] would refuse for its lengths is refused here already.
    pub fn work_sizes(spec: &PlanSpec<'_, T, D>) -> Result<PlanSizes> {
        build::check_lengths(spec)?;
        Ok(build::work_sizes(spec))
    }

    /// The pool sizes of a plan with a one-level solver (`PlanSolver::Method(solver)`), from
    /// the counts alone: exactly what [`Plan::sizes`] returns for a spec with these counts,
    /// and, as every size grows with every count, an upper bound when the counts are upper
    /// bounds. A `const fn`, so static storage can be declared from it ([`PlanStorage`]):
    ///
    /// ```
    /// use deform_kernel::plan::{Plan, PlanCounts, PlanMethod, PlanSizes, PlanStorage};
    /// use deform_kernel::spring::{LinearMethod, Preconditioner};
    ///
    /// const COUNTS: PlanCounts = PlanCounts { nodes: 30, edges: 138, boundary: 18, elements: None };
    /// const CG: LinearMethod<f32> = LinearMethod::Cg { preconditioner: Preconditioner::Jacobi };
    /// const POOLS: PlanSizes = match Plan::<f32, 2>::capacity(&COUNTS, PlanMethod::Spring, &CG) {
    ///     Some(s) => s,
    ///     None => panic!("the plan does not fit in memory"),
    /// };
    /// static PLAN: PlanStorage<f32, { POOLS.reals }, { POOLS.indices }, { POOLS.bytes }> =
    ///     PlanStorage::new();
    /// # assert_eq!(PLAN.capacity(), POOLS);
    /// ```
    ///
    /// The multigrid solver's sizes depend on the hierarchy its setup finds: take them from
    /// [`Plan::sizes`] once (on the host) and keep a margin; storage that is too small is
    /// refused by [`Plan::init`] with [`Error::BufferTooSmall`](crate::Error::BufferTooSmall)
    /// and the sizes it needs. `None` when a size overflows `usize` or a pool exceeds `u32`
    /// entries.
    pub const fn capacity(
        counts: &PlanCounts,
        method: PlanMethod,
        solver: &LinearMethod<T>,
    ) -> Option<PlanSizes> {
        Self::capacity_ordered(counts, method, solver, PlanOrder::AsGiven)
    }

    /// [`Plan::capacity`] of a plan that renumbers its mesh (`renumber`, as
    /// [`PlanSpec::renumber`]): `2 N` indices more than without.
    pub const fn capacity_ordered(
        counts: &PlanCounts,
        method: PlanMethod,
        solver: &LinearMethod<T>,
        renumber: PlanOrder,
    ) -> Option<PlanSizes> {
        check::mesh_dim::<D>();
        build::one_level_sizes(counts, D, method, solver, renumber)
    }

    /// The transient work sizes from the counts alone: what [`Plan::work_sizes`] returns for a
    /// spec with `counts.nodes` nodes and `counts.edges` directed edges (`const`, as
    /// [`Plan::capacity`]).
    pub const fn work_capacity(counts: &PlanCounts) -> PlanSizes {
        Self::work_capacity_ordered(counts, PlanOrder::AsGiven)
    }

    /// [`Plan::work_capacity`] of a plan that renumbers its mesh (`renumber`).
    pub const fn work_capacity_ordered(counts: &PlanCounts, renumber: PlanOrder) -> PlanSizes {
        build::work_sizes_of(counts.nodes, counts.edges, D, renumber)
    }

    /// The exact pool sizes for `spec` (validates the spec and runs the hierarchy's symbolic
    /// pass in `work`).
    ///
    /// # Errors
    /// Those of [`Plan::init`]'s validation; only `work` is written.
    pub fn sizes(spec: &PlanSpec<'_, T, D>, work: &mut PlanWork<'_, T>) -> Result<PlanSizes> {
        build::sizes(spec, work).map(|(s, _)| s)
    }

    /// Builds the plan in the pools (each at least [`Plan::sizes`] long; larger pools work,
    /// the tail is untouched): validates the spec once (points finite, boundary distinct and in
    /// range, graph symmetric with a positive symmetric stiffness, every free node anchored,
    /// elements of the right kinds, solver options), copies mesh data in, computes the
    /// stiffness and sets up the hierarchy.
    ///
    /// # Errors
    /// Length mismatches, non-finite points, an empty, repeated or
    /// out-of-range boundary node, the errors of [`SpringSystem::new`](crate::spring::SpringSystem::new),
    /// [`batina_stiffness`](crate::spring::batina_stiffness) and
    /// [`AmgHierarchy::setup`](crate::spring::AmgHierarchy::setup), invalid options,
    /// sliding constraints ([`Error::InvalidParameter`](crate::Error::InvalidParameter)), pools
    /// or work too small ([`Error::BufferTooSmall`](crate::Error::BufferTooSmall)), counts
    /// beyond `u32` ([`Error::TooLarge`](crate::Error::TooLarge)). Every check on the spec
    /// runs before a pool is written; only a hierarchy setup that breaks down in floating
    /// point fails after, and then the pools hold no plan (the header is written last).
    pub fn init(
        spec: &PlanSpec<'_, T, D>,
        work: &mut PlanWork<'_, T>,
        reals: &'a mut [T],
        indices: &'a mut [u32],
        bytes: &'a mut [u8],
    ) -> Result<Self> {
        build::init(spec, work, reals, indices, bytes)?;
        Plan::open(reals, indices, bytes)
    }

    /// Reopens pools that hold a plan (e.g. copied from a checkpoint): checks the header
    /// (magic, version, scalar type, `D`, counts, pool lengths), the consistency of the
    /// hierarchy's layout, a 64-bit checksum of every part that never changes and the
    /// finiteness of the stored solution. Cost: one pass over the pools.
    ///
    /// # Errors
    /// [`Error::BadPlan`](crate::Error::BadPlan) with the reason; nothing is written.
    pub fn open(reals: &'a mut [T], indices: &'a mut [u32], bytes: &'a mut [u8]) -> Result<Self> {
        let (meta, amg) = layout::open::<T, D>(reals, indices, bytes)?;
        Ok(Plan {
            reals,
            indices,
            bytes,
            meta,
            amg,
        })
    }

    /// One time step: the new boundary positions in, the deformed mesh (`N` points) out.
    /// The previous solution is the initial guess when `motion.start` is [`Start::Warm`].
    ///
    /// # Errors
    /// Checked before anything is written: `out.len() != N`, `motion.deformed.len() != B`
    /// ([`Error::LengthMismatch`](crate::Error::LengthMismatch)), non-finite positions or
    /// origin ([`Error::NonFinite`](crate::Error::NonFinite)), rotations that cannot be
    /// normalised, [`RotationSource::Shape`] without elements. Then, still before `out` or
    /// the state is written: the boundary rotations' errors (degenerate deformed shape), the
    /// solver's errors, and a propagated rotation that cancels to zero
    /// ([`Error::ZeroLength`](crate::Error::ZeroLength)). On `Err`, `out`, the stored
    /// solution and the step counter are unchanged.
    pub fn step(
        &mut self,
        motion: &PlanMotion<'_, T, D>,
        out: &mut [[T; D]],
    ) -> Result<StepReport<T, D>> {
        step::step(self, motion, out)
    }

    /// The three pools, read-only (to checkpoint a plan while it is in use).
    pub fn buffers(&self) -> (&[T], &[u32], &[u8]) {
        (self.reals, self.indices, self.bytes)
    }

    /// The pool lengths this plan uses.
    pub fn used(&self) -> PlanSizes {
        self.meta.sizes
    }

    /// Nodes `N`.
    pub fn node_count(&self) -> usize {
        self.meta.n
    }

    /// Boundary points `B`.
    pub fn boundary_len(&self) -> usize {
        self.meta.b
    }

    /// The method.
    pub fn method(&self) -> PlanMethod {
        self.meta.method
    }

    /// Steps completed.
    pub fn steps(&self) -> u64 {
        self.meta.steps
    }

    /// Levels of the multigrid hierarchy (0 without one).
    pub fn amg_levels(&self) -> usize {
        self.amg.as_ref().map_or(0, |a| a.layout.count)
    }

    /// How the plan numbers its mesh ([`PlanSpec::renumber`]).
    pub fn renumbering(&self) -> PlanOrder {
        self.meta.counts.order
    }

    /// The permutation the plan solves in (`order[new] = old`), `None` for
    /// [`PlanOrder::AsGiven`]: renumbering the mesh by it and building a plan without the
    /// option gives the same bits, permuted.
    pub fn permutation(&self) -> Option<Permutation<'_>> {
        order::stored(&self.meta.sec, self.indices)
    }
}

/// Largest number of words the hierarchy's layout takes in the index pool.
const AMG_LAYOUT_WORDS: usize = AMG_MAX_LEVELS * 14 + 11;

/// Number of weights the hierarchy stores (every level and step).
const AMG_WEIGHTS: usize = AMG_MAX_LEVELS * AMG_MAX_SWEEPS;
