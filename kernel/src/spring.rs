//! Spring-analogy mesh motion: Batina's linear springs and Yang & Özgen's angle-inclusion
//! springs.
//!
//! Geometry and solvers are separate. [`batina_stiffness`] turns coordinates and a
//! [`Graph`](crate::Graph) into one stiffness per directed edge. [`SpringSystem`] validates
//! graph + stiffness + fixed mask once (symmetry, positivity, every free node anchored to a
//! fixed node). The solvers then propagate values:
//!
//! - **Linear springs** (Batina; Yang & Özgen eq. 1; Samareh eq. 2): every value component
//!   solves the weighted graph Laplacian `Σ_j k_ij (x_j − x_i) = 0` at free nodes, with the
//!   fixed nodes as Dirichlet data. Values are `[T; V]` for any `V`: displacements (`V = D`),
//!   quaternion components (`V = 4`) or both together (`V = D + 4`), all in one pass over the
//!   matrix. Methods: the paper's Jacobi iteration, Gauss–Seidel, SOR, and preconditioned
//!   conjugate gradients (no, Jacobi or SSOR preconditioner) with per-component `α`, `β`
//!   ([`solve_linear`](crate::spring::SpringSystem::solve_linear)), and CG preconditioned by smoothed-aggregation algebraic multigrid
//!   ([`AmgHierarchy`], [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg)): the hierarchy is built once on the scalar
//!   operator (caller buffers, exact size query) and applied to all `V` components;
//!   [`LinearSolver`] names either kind for the deformation pipelines.
//! - **Angle inclusion** (Yang & Özgen eq. 2; in 3D the block `k e eᵀ`): displacements couple
//!   through the edge direction `e`. The direct method solves each node's 2×2 / 3×3 system by
//!   Cramer's rule (Gauss–Seidel or Jacobi order); the indirect method is matrix-free CG on the
//!   assembled block operator ([`solve_angle`](crate::spring::AngleSystem::solve_angle)), preconditioned by the node blocks or, with
//!   [`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg), by the linear springs' [`AmgHierarchy`] V-cycle applied to
//!   each component (8–19× fewer iterations on airfoil meshes).
//! - **Sweeps** over a node range ([`jacobi_sweep`](crate::spring::SpringSystem::jacobi_sweep), [`sor_sweep`](crate::spring::SpringSystem::sor_sweep), [`angle_jacobi_sweep`](crate::spring::AngleSystem::angle_jacobi_sweep),
//!   [`angle_gauss_seidel_sweep`](crate::spring::AngleSystem::angle_gauss_seidel_sweep)) return the local maximum change, so a distributed-memory
//!   code can exchange halos between sweeps. The whole solves are built on the same sweeps.
//!
//! All updates are written in *delta form* (`x_i + Σ k (x_j − x_i) / Σ k`, algebraically the
//! paper's `Σ k x_j / Σ k`): a field that is uniform over a node's neighbourhood is then a
//! bit-exact fixed point, so a uniform translation of every boundary is reproduced exactly.
//!
//! - **One Krylov core**: every conjugate-gradient solve above (and the rigidity probe) is
//!   the one loop of `krylov.rs` over an operator (linear springs, angle springs, the
//!   sliding projection `P K P`) and a preconditioner (none, Jacobi, node blocks, SSOR, the
//!   V-cycle), with one stopping rule; every CG scratch length comes from its CG vectors
//!   and [`amg_cg_scratch_len`].
//! - **Sliding nodes** ([`Constraints`](crate::spring::constraints::Constraints): a node slides on a plane
//!   or a line): [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) and [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding) solve the projected
//!   system `P K P d = P b` jointly over the components (see their module for why it stays
//!   symmetric positive definite and how the multigrid hierarchy is used).
//!
//! **Fixed mask**: `&[u8]`, one byte per node, nonzero = fixed (Dirichlet). Not `&[bool]`: a
//! C `_Bool`, `char` or Fortran `logical(c_bool)` array may hold bytes other than 0 and 1,
//! which is undefined behaviour for a Rust `bool` but just "fixed" for a `u8`. So the C ABI can
//! pass the caller's array through without a copy.

mod amg;
mod angle;
pub mod constraints;
mod distributed;
pub(crate) mod krylov;
mod linear;
pub(crate) mod norms;
mod partitioned;
mod sliding;
mod solver;
mod stiffening;
mod stiffness;
mod system;
mod zero_components;

pub use amg::rigid_mode_count;
pub use amg::{
    aggregate_mis2, aggregate_mis2_partitioned, mis2_exchange_len, mis2_scratch_len,
    prolongator_partitioned, prolongator_partitioned_len, Mis2Report, MIS2_NONE,
};
pub use amg::{
    amg_cg_scratch_len, amg_precondition_scratch_len, amg_setup_work_len,
    amg_sliding_cg_scratch_len, solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions, AmgPools,
    AmgSizes, AmgSmoother, AmgSolve, RigidAmg, RigidAmgSizes, AMG_MAX_DENSE, AMG_MAX_LEVELS,
    AMG_MAX_SWEEPS,
};
pub(crate) use amg::{Fine, Layout, Level, RigidVcycle, Vcycle};
pub use angle::{
    angle_scratch_items, angle_sliding_scratch_items, AngleMethod, AngleSystem,
    DEFAULT_ANGLE_EPSILON, MAX_AMPLIFICATION,
};
pub use distributed::{Collective, Serial};
pub use linear::solve_linear_scratch_len;
pub(crate) use linear::{diagonal, Laplacian, OneLevel};
pub use partitioned::{
    partitioned_cg_scratch_len, partitioned_targets_len, LocalCells, PartitionedSprings,
};
pub(crate) use sliding::solve_linear_sliding_rhs;
pub use sliding::solve_linear_sliding_scratch_len;
pub use solver::{solve_linear_with_scratch_len, LinearSolver};
pub use stiffening::{
    dual_volumes, inverse_volume_factors, scale_stiffness, wall_distance_factors, wall_distances,
};
pub use stiffness::batina_stiffness;
#[cfg(feature = "micromath")]
pub use stiffness::batina_stiffness_fast;
pub(crate) use system::check_omega;
pub use system::{
    is_fixed, LinearMethod, Preconditioner, SolveOptions, SolveReport, SpringSystem, Sweep,
};
