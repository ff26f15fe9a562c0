//! Spring-analogy mesh motion: `dk_spring_*` (f64) and `dk_spring_*_f32`.
//!
//! Batina's linear springs and Yang & Özgen's angle-inclusion springs on a 0-based CSR graph
//! (from `dk_graph_from_*`). Every solver call validates the *spring system* first: the graph
//! (symmetric), one finite positive stiffness per directed edge (equal on `i → j` and
//! `j → i`, as `dk_spring_batina_stiffness` writes it), and the fixed mask (one byte per node,
//! nonzero = fixed/Dirichlet), with every free node connected to a fixed node. That check
//! needs an `index_scratch` of `node_count` `uint32_t` (see `dk_spring_index_scratch_len`);
//! its contents afterwards are unspecified.
//!
//! Values are flat arrays of `node_count * components` scalars (`components` 1 to 7: a
//! scalar, a displacement, a quaternion, or both together) for the linear springs, and of
//! `node_count * dim` displacements for the angle springs (`dim` 2 or 3, as the points).
//! Node ranges of the sweeps honour `index_base` (0: `start <= i < end`; 1: 1-based inclusive
//! `start <= i <= end`), so an MPI code sweeps the nodes it owns and exchanges halos between
//! sweeps.
//!
//! Options and reports are `#[repr(C)]` structs with `double` fields for both precisions (the
//! `_f32` functions round the options to `float` and widen the results exactly); the
//! `*_options_default` functions have `_f32` twins because the default tolerance depends on
//! the precision. Values updated in place are unchanged on any error.
#![allow(unsafe_code)] // a parameter struct's arrays become `In`/`Out` tokens (`In::new`) here.

use deform_kernel::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use deform_kernel::spring::constraints::{
    fit_plane, plane_intersection, slide_points, Constraints,
};
use deform_kernel::spring::{
    amg_setup_work_len, angle_scratch_items, angle_sliding_scratch_items, batina_stiffness,
    solve_linear_scratch_len, solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AmgPools,
    AmgSmoother, AmgSolve, AngleMethod, AngleSystem, LinearMethod, LinearSolver, Preconditioner,
    SolveOptions, SolveReport, SpringSystem, Sweep, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{
    assert_layout, mul_len, range, read_array, read_one, read_points, rebase, write_array,
    write_len, write_one, Components, Dim,
};
use crate::graph::{dk_graph, read_graph, GraphIn};
use crate::pools::{dk_plan_sizes, DkPlanPools, PoolsC};
use crate::slice::{
    chunks, chunks_mut, input, input_n, out_one, output, output_n, whole_chunks_mut, In, Out,
};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// repr(C) types and constants.
// ---------------------------------------------------------------------------------------------

/// `dk_spring_solve_options::method`: the paper's Jacobi iteration (every node from the
/// previous field).
pub const DK_LINEAR_JACOBI: u32 = 0;
/// `dk_spring_solve_options::method`: Gauss–Seidel, in place, in node order.
pub const DK_LINEAR_GAUSS_SEIDEL: u32 = 1;
/// `dk_spring_solve_options::method`: successive over-relaxation with `omega` in (0, 2).
pub const DK_LINEAR_SOR: u32 = 2;
/// `dk_spring_solve_options::method`: preconditioned conjugate gradients (see
/// `preconditioner`).
pub const DK_LINEAR_CG: u32 = 3;

/// `dk_spring_solve_options::preconditioner`: plain CG.
pub const DK_PRECONDITIONER_NONE: u32 = 0;
/// `dk_spring_solve_options::preconditioner`: diagonal (Jacobi).
pub const DK_PRECONDITIONER_JACOBI: u32 = 1;
/// `dk_spring_solve_options::preconditioner`: symmetric SOR with `omega` in (0, 2).
pub const DK_PRECONDITIONER_SSOR: u32 = 2;

/// `dk_spring_angle_options::method`: direct method (each node's 2×2/3×3 system by Cramer's
/// rule), Gauss–Seidel order. Converges (the operator is SPD).
pub const DK_ANGLE_DIRECT_GAUSS_SEIDEL: u32 = 0;
/// `dk_spring_angle_options::method`: direct method, Jacobi order (not guaranteed to converge;
/// non-convergence is reported).
pub const DK_ANGLE_DIRECT_JACOBI: u32 = 1;
/// `dk_spring_angle_options::method`: matrix-free conjugate gradients with the node blocks as
/// preconditioner.
pub const DK_ANGLE_CG: u32 = 2;

/// Method and stopping rules of `dk_spring_solve_linear`. Fill with
/// `dk_spring_solve_options_default` (or `_f32`) and change fields as needed.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_spring_solve_options {
    /// Iteration cap (sweeps, or CG iterations). Default 10 000.
    pub max_iterations: usize,
    /// Converged when the relative residual `‖b − A x‖ / ‖b‖` is at most this (finite, ≥ 0).
    /// Default `max(1e-10, 100 ε)`: 1e-10 for f64, about 1.2e-5 for f32.
    pub residual_tol: f64,
    /// Also converged when the largest change of one iteration is at most this (finite, ≥ 0;
    /// default 0 = off).
    pub update_tol: f64,
    /// Relaxation factor in (0, 2) for `DK_LINEAR_SOR` and `DK_PRECONDITIONER_SSOR` (ignored
    /// otherwise). Default 1.
    pub omega: f64,
    /// `DK_LINEAR_JACOBI`, `DK_LINEAR_GAUSS_SEIDEL`, `DK_LINEAR_SOR` or `DK_LINEAR_CG`
    /// (default).
    pub method: u32,
    /// For `DK_LINEAR_CG`: `DK_PRECONDITIONER_NONE`, `DK_PRECONDITIONER_JACOBI` (default) or
    /// `DK_PRECONDITIONER_SSOR`; ignored by the other methods.
    pub preconditioner: u32,
}
assert_layout!(
    dk_spring_solve_options, 40;
    max_iterations = 0, residual_tol = 8, update_tol = 16, omega = 24, method = 32,
    preconditioner = 36,
);

impl dk_spring_solve_options {
    /// The kernel's linear method (`DK_ERR_INVALID_PARAMETER` for an unknown method or
    /// preconditioner code).
    pub(crate) fn method<T: Real>(&self) -> Result<LinearMethod<T>, dk_status> {
        let omega = T::from_f64(self.omega);
        Ok(match self.method {
            DK_LINEAR_JACOBI => LinearMethod::Jacobi,
            DK_LINEAR_GAUSS_SEIDEL => LinearMethod::GaussSeidel,
            DK_LINEAR_SOR => LinearMethod::Sor { omega },
            DK_LINEAR_CG => LinearMethod::Cg {
                preconditioner: match self.preconditioner {
                    DK_PRECONDITIONER_NONE => Preconditioner::None,
                    DK_PRECONDITIONER_JACOBI => Preconditioner::Jacobi,
                    DK_PRECONDITIONER_SSOR => Preconditioner::Ssor { omega },
                    _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
                },
            },
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        })
    }

    /// The defaults for precision `T`: CG with the Jacobi preconditioner and the kernel's
    /// stopping rules, `omega` 1.
    pub(crate) fn default_for<T: Real>() -> Self {
        let k = SolveOptions::<T>::default();
        dk_spring_solve_options {
            max_iterations: k.max_iterations,
            residual_tol: k.residual_tol.to_f64(),
            update_tol: k.update_tol.to_f64(),
            omega: 1.0,
            method: DK_LINEAR_CG,
            preconditioner: DK_PRECONDITIONER_JACOBI,
        }
    }

    /// The kernel's stopping rules (tolerances rounded to `T`).
    pub(crate) fn stopping<T: Real>(&self) -> SolveOptions<T> {
        stopping(self.max_iterations, self.residual_tol, self.update_tol)
    }
}

/// The kernel's stopping rules from the C fields (tolerances rounded to `T`).
fn stopping<T: Real>(max_iterations: usize, residual_tol: f64, update_tol: f64) -> SolveOptions<T> {
    SolveOptions {
        max_iterations,
        residual_tol: T::from_f64(residual_tol),
        update_tol: T::from_f64(update_tol),
    }
}

/// Method, regularisation and stopping rules of the angle-inclusion springs
/// (`dk_spring_solve_angle`, `dk_spring_angle_rigidity_probe`). Fill with
/// `dk_spring_angle_options_default` (or `_f32`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_spring_angle_options {
    /// Iteration cap. Default 10 000.
    pub max_iterations: usize,
    /// Relative-residual tolerance (as `dk_spring_solve_options`).
    pub residual_tol: f64,
    /// Update tolerance (default 0 = off).
    pub update_tol: f64,
    /// Regularisation `ε ≥ 0`: every edge block is `k (d dᵀ/|d|² + ε I)`. Default 0.01. With
    /// 0 (the paper's operator) the solve first runs the rigidity probe and rejects a
    /// near-mechanism with `DK_ERR_SINGULAR_SYSTEM`.
    pub epsilon: f64,
    /// `DK_ANGLE_DIRECT_GAUSS_SEIDEL` (default), `DK_ANGLE_DIRECT_JACOBI` or `DK_ANGLE_CG`.
    pub method: u32,
}
assert_layout!(
    dk_spring_angle_options, 40;
    max_iterations = 0, residual_tol = 8, update_tol = 16, epsilon = 24, method = 32,
);

impl dk_spring_angle_options {
    pub(crate) fn method(&self) -> Result<AngleMethod, dk_status> {
        match self.method {
            DK_ANGLE_DIRECT_GAUSS_SEIDEL => Ok(AngleMethod::DirectGaussSeidel),
            DK_ANGLE_DIRECT_JACOBI => Ok(AngleMethod::DirectJacobi),
            DK_ANGLE_CG => Ok(AngleMethod::Cg),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }
    }

    pub(crate) fn stopping<T: Real>(&self) -> SolveOptions<T> {
        stopping(self.max_iterations, self.residual_tol, self.update_tol)
    }

    /// The method, and whether the rigidity probe runs (`epsilon` 0 in `T`), of a scratch
    /// query in dimension `dim` (2 or 3, else `DK_ERR_INVALID_PARAMETER`).
    fn scratch_query<T: Real>(&self, dim: u32) -> Result<(AngleMethod, bool), dk_status> {
        let method = self.method()?;
        if !(2..=3).contains(&dim) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        Ok((method, T::from_f64(self.epsilon) == T::ZERO))
    }
}

/// What a whole spring solve did. Non-convergence is reported here (`converged` false, status
/// `DK_OK`), never hidden; the values then hold the last iterate.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_spring_solve_report {
    /// Iterations performed (sweeps, or CG iterations).
    pub iterations: usize,
    /// True relative residual `‖b − A x‖ / ‖b‖` of the returned values.
    pub residual: f64,
    /// Largest absolute change in the last iteration.
    pub max_update: f64,
    /// Whether a stopping rule was met.
    pub converged: bool,
}
assert_layout!(
    dk_spring_solve_report, 32;
    iterations = 0, residual = 8, max_update = 16, converged = 24,
);

impl dk_spring_solve_report {
    /// The C report of a kernel report (values widened exactly).
    pub(crate) fn of<T: Real>(r: SolveReport<T>) -> Self {
        dk_spring_solve_report {
            iterations: r.iterations,
            residual: r.residual.to_f64(),
            max_update: r.max_update.to_f64(),
            converged: r.converged,
        }
    }
}

/// [`dk_amg_options::smoother`]: damped Jacobi.
pub const DK_AMG_JACOBI: u32 = 0;
/// [`dk_amg_options::smoother`]: Chebyshev polynomial smoothing (default).
pub const DK_AMG_CHEBYSHEV: u32 = 1;

/// The smoothed-aggregation multigrid preconditioner (the kernel's `AmgOptions`; see
/// docs/amg.md) of [`dk_spring_solve_linear_amg`], [`dk_spring_solve_angle_amg`] and of plans
/// with `DK_PLAN_SOLVER_AMG`. [`dk_amg_options_default`] (and `dk_plan_options_default`) fill
/// the defaults (pyamg's, but for the strength threshold). The same struct serves both precisions (the `_f32` functions round
/// `strength_theta` to `float`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_amg_options {
    /// Strength-of-connection threshold θ in `[0, 1)`: a spring is strong when it is at least θ
    /// times the geometric mean of the stiffest springs at its two nodes (default 0.25; 0:
    /// every spring strong, and hierarchy sizes that do not depend on the stiffness).
    pub strength_theta: f64,
    /// Most levels, 1 to 16 (default 10).
    pub max_levels: usize,
    /// Coarsening stops at a level with at most this many unknowns, solved by dense Cholesky;
    /// 1 to 2048 (default 256).
    pub max_coarse: usize,
    /// Smoothing steps before and after the coarse correction, 1 to 16 (default 2).
    pub sweeps: usize,
    /// [`DK_AMG_CHEBYSHEV`] (default) or [`DK_AMG_JACOBI`].
    pub smoother: u32,
}
assert_layout!(
    dk_amg_options, 40;
    strength_theta = 0, max_levels = 8, max_coarse = 16, sweeps = 24, smoother = 32,
);

impl dk_amg_options {
    /// The C struct of the kernel's options.
    pub(crate) fn of<T: Real>(a: AmgOptions<T>) -> Self {
        dk_amg_options {
            strength_theta: a.strength_theta.to_f64(),
            max_levels: a.max_levels,
            max_coarse: a.max_coarse,
            sweeps: a.sweeps,
            smoother: match a.smoother {
                AmgSmoother::Jacobi => DK_AMG_JACOBI,
                AmgSmoother::Chebyshev => DK_AMG_CHEBYSHEV,
            },
        }
    }

    /// The kernel's options (checked by the kernel when the hierarchy is set up).
    pub(crate) fn to_kernel<T: Real>(self) -> Result<AmgOptions<T>, dk_status> {
        Ok(AmgOptions {
            strength_theta: T::from_f64(self.strength_theta),
            max_levels: self.max_levels,
            max_coarse: self.max_coarse,
            sweeps: self.sweeps,
            smoother: match self.smoother {
                DK_AMG_JACOBI => AmgSmoother::Jacobi,
                DK_AMG_CHEBYSHEV => AmgSmoother::Chebyshev,
                _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
            },
        })
    }
}

/// Result of one sweep over a node range.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_spring_sweep {
    /// Largest `|new − old|` over the range's free nodes and all components (0 for an empty
    /// range).
    pub max_change: f64,
    /// `Σ |r_i|²` over the range's free nodes and all components (exact residual of the input
    /// for Jacobi sweeps, an estimate for Gauss–Seidel/SOR); summed over ranks it gives a
    /// global residual.
    pub residual_sq: f64,
}
assert_layout!(dk_spring_sweep, 16; max_change = 0, residual_sq = 8);

impl dk_spring_sweep {
    fn of<T: Real>(s: Sweep<T>) -> Self {
        dk_spring_sweep {
            max_change: s.max_change.to_f64(),
            residual_sq: s.residual_sq.to_f64(),
        }
    }
}

/// A spring system for the solvers and sweeps: the graph, one stiffness per directed edge
/// (symmetric, finite, positive) and the fixed mask (one byte per node, nonzero = fixed).
/// Borrowed for the call that receives it, as [`dk_graph`]. The ABI's one struct for "the
/// system", so a caller builds it once and hands it to every solver.
#[export(twin = dk_spring_system)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct DkSpringSystem<T> {
    /// The 0-based CSR graph.
    pub graph: dk_graph,
    /// Stiffness of each directed edge (`graph.targets_len` entries).
    pub stiffness: *const T,
    /// Entries of `stiffness`.
    pub stiffness_len: usize,
    /// One byte per node, nonzero = fixed (Dirichlet).
    pub fixed: *const u8,
    /// Entries of `fixed` (the node count).
    pub fixed_len: usize,
}
assert_layout!(DkSpringSystem<f64>, 64; graph = 0, stiffness = 32, fixed = 48, fixed_len = 56);

/// The arrays of a spring-system struct as tokens.
#[derive(Clone, Copy)]
pub(crate) struct SystemIn<'a, T> {
    graph: GraphIn<'a>,
    stiffness: In<'a, T>,
    fixed: In<'a, u8>,
}

/// The two C spring-system structs, seen through [`SystemIn`].
pub(crate) trait SystemC: Copy {
    type T: Real;
    /// Reads the struct and wraps its arrays in tokens of the struct's lifetime.
    fn read(p: In<'_, Self>) -> Result<SystemIn<'_, Self::T>, dk_status>;
}

impl<T: Real> SystemC for DkSpringSystem<T> {
    type T = T;
    fn read(p: In<'_, Self>) -> Result<SystemIn<'_, T>, dk_status> {
        let s = read_one(p)?;
        // SAFETY: a token for a system struct carries the contract of the functions that take
        // one: its arrays are readable for their lengths while it is.
        Ok(unsafe {
            SystemIn {
                graph: s.graph.tokens(),
                stiffness: In::new(s.stiffness, s.stiffness_len),
                fixed: In::new(s.fixed, s.fixed_len),
            }
        })
    }
}

impl<'a, T: Real> SystemIn<'a, T> {
    /// Borrows and validates the system, with `node_count` entries of `scratch`.
    pub(crate) fn build(self, scratch: &mut [u32]) -> Result<SpringSystem<'a, T>, dk_status> {
        let g = self.graph.graph()?;
        let k = input(self.stiffness)?;
        let f = input(self.fixed)?;
        SpringSystem::new(g, k, f, scratch).map_err(dk_status::from)
    }
}

/// What every node of a sliding (symmetry-plane) solve may do: the kernel's
/// `slide::Constraints`, for [`dk_spring_solve_linear_sliding`],
/// [`dk_spring_solve_angle_sliding`], their multigrid variants, [`dk_slide_points`] and
/// [`dk_constraints_fixed_mask`]. `kinds` holds one code per node: 0 free, 1 fixed
/// (Dirichlet), 2 slides on the plane (a line in 2D) through its position, 3 slides on the
/// line through its position. `directions` holds `dim` scalars per node: the unit normal of a
/// kind-2 node, the unit tangent of a kind-3 node (`| |n|² − 1 |` at most `√ε`: 1.5e-8 in
/// double, 3.5e-4 in float), ignored (any bits) for kinds 0 and 1. These functions require
/// the struct: there is no "absent" value, and an all-NULL struct (zero nodes) matches only a
/// zero-node system. Borrowed for the call that receives it, as [`dk_graph`].
#[export(twin = dk_constraints)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct DkConstraints<T> {
    /// One kind code (0 to 3) per node.
    pub kinds: *const u8,
    /// Entries of `kinds` (the node count).
    pub kinds_len: usize,
    /// `dim` scalars per node (`x, y[, z]`): normals (kind 2) and tangents (kind 3).
    pub directions: *const T,
    /// Entries of `directions` (`kinds_len * dim`).
    pub directions_len: usize,
}
assert_layout!(DkConstraints<f64>, 32; kinds = 0, kinds_len = 8, directions = 16, directions_len = 24);

/// The arrays of a constraints struct as tokens.
#[derive(Clone, Copy)]
pub(crate) struct ConstraintsIn<'a, T> {
    kinds: In<'a, u8>,
    directions: In<'a, T>,
}

/// The two C constraints structs, seen through [`ConstraintsIn`].
pub(crate) trait ConstraintsC: Copy {
    type T: Real;
    /// Reads the struct and wraps its arrays in tokens of the struct's lifetime.
    fn read(p: In<'_, Self>) -> Result<ConstraintsIn<'_, Self::T>, dk_status>;
}

impl<T: Real> ConstraintsC for DkConstraints<T> {
    type T = T;
    fn read(p: In<'_, Self>) -> Result<ConstraintsIn<'_, T>, dk_status> {
        let c = read_one(p)?;
        // SAFETY: a token for a constraints struct carries the contract of the functions that
        // take one: its arrays are readable for their lengths while it is.
        Ok(unsafe {
            ConstraintsIn {
                kinds: In::new(c.kinds, c.kinds_len),
                directions: In::new(c.directions, c.directions_len),
            }
        })
    }
}

impl<'a, T: Real> ConstraintsIn<'a, T> {
    /// Borrows and validates the table (the kernel's `Constraints::new`): `directions_len`
    /// not a multiple of `D` or not `D * kinds_len` is `DK_ERR_LENGTH_MISMATCH`, a code above
    /// 3 `DK_ERR_INDEX_OUT_OF_RANGE`, a sliding node's direction `DK_ERR_NON_FINITE` /
    /// `DK_ERR_NOT_UNIT`.
    pub(crate) fn build<const D: usize>(self) -> Result<Constraints<'a, T, D>, dk_status> {
        let kinds = input(self.kinds)?;
        let directions = chunks::<T, D>(self.directions)?;
        Constraints::new(kinds, directions).map_err(dk_status::from)
    }
}

// ---------------------------------------------------------------------------------------------
// Shared argument handling.
// ---------------------------------------------------------------------------------------------

impl<T: Real> DkSpringSystem<T> {
    /// Reads the struct behind `p`, then borrows and validates the system with
    /// `index_scratch` (`node_count` entries) for the anchoring check.
    pub(crate) fn open<'a>(
        p: In<'a, Self>,
        index_scratch: Out<'a, u32>,
    ) -> Result<SpringSystem<'a, T>, dk_status> {
        Self::read(p)?.build(output(index_scratch)?)
    }
}

impl<T: Real> DkConstraints<T> {
    /// Reads the struct behind `p`, then borrows and validates the table in dimension `D`.
    pub(crate) fn open<const D: usize>(
        p: In<'_, Self>,
    ) -> Result<Constraints<'_, T, D>, dk_status> {
        Self::read(p)?.build::<D>()
    }
}

/// The angle springs of a validated system on the undeformed `points`.
fn angle_system<'a, T: Real, const D: usize>(
    base: SpringSystem<'a, T>,
    points: In<'a, T>,
    epsilon: T,
) -> Result<AngleSystem<'a, T, D>, dk_status> {
    let p = read_points::<T, D>(points)?;
    Ok(AngleSystem::new(base, p, epsilon)?)
}

/// Words of an exact sum ([`ExactSum::to_words`]): the C ABI's merge protocol.
pub const DK_EXACT_SUM_WORDS: usize = 72;
const _: () = assert!(DK_EXACT_SUM_WORDS == EXACT_SUM_WORDS);

/// One Jacobi sweep of the system (with its index scratch); with `residual_words`, also the
/// range's exact residual sum.
fn jacobi_sweep<T: Real, const V: usize>(
    (system, index_scratch): (In<'_, DkSpringSystem<T>>, Out<'_, u32>),
    [a, b]: [usize; 2],
    src: In<'_, T>,
    dst: Out<'_, T>,
    sweep: Out<'_, dk_spring_sweep>,
    residual_words: Option<Out<'_, i64>>,
) -> Result<(), dk_status> {
    let s = chunks::<T, V>(src)?;
    let d = chunks_mut::<T, V>(dst)?;
    let w = out_one(sweep)?;
    let words = match residual_words {
        Some(p) => Some(output_n(p, EXACT_SUM_WORDS)?),
        None => None,
    };
    let system = DkSpringSystem::open(system, index_scratch)?;
    let result = system.jacobi_sweep(a..b, s, d)?;
    *w = dk_spring_sweep::of(result);
    // A zip, not `copy_from_slice`: no length check left for the panic proof to remove.
    if let Some(words) = words {
        for (w, v) in words.iter_mut().zip(result.residual_sum.to_words()) {
            *w = v;
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Stateless multigrid solves: the hierarchy set up in the caller's pools every call.
// ---------------------------------------------------------------------------------------------

/// The pools of a stateless multigrid solve, opened: the multigrid options and the `reals`
/// and `indices` buffers (`bytes` is not used).
struct AmgBuffers<'a, T: Real> {
    options: AmgOptions<T>,
    reals: &'a mut [T],
    indices: &'a mut [u32],
}

/// Reads the multigrid options, borrows the pools (each NULL only with length 0) and
/// validates the system with the front of `indices` as its `index_scratch`.
fn amg_open<'a, T: Real>(
    system: In<'a, DkSpringSystem<T>>,
    amg: In<'a, dk_amg_options>,
    pools: In<'a, DkPlanPools<T>>,
) -> Result<(SpringSystem<'a, T>, AmgBuffers<'a, T>), dk_status> {
    let options = read_one(amg)?.to_kernel::<T>()?;
    let (reals, indices, _bytes) = DkPlanPools::read(pools)?.borrow()?;
    let system = DkSpringSystem::read(system)?.build(indices)?;
    let pools = AmgBuffers {
        options,
        reals,
        indices,
    };
    Ok((system, pools))
}

impl<'a, T: Real> AmgBuffers<'a, T> {
    /// Lays the pools out for `solve` (the symbolic pass of `sys` in the front of `indices`),
    /// checks their lengths (a pool too short is `DK_ERR_BUFFER_TOO_SMALL`, before anything
    /// else is written), then sets the hierarchy up: returns it with the solve's scratch.
    fn hierarchy<const V: usize>(
        self,
        sys: &SpringSystem<'_, T>,
        solve: AmgSolve,
    ) -> Result<(AmgHierarchy<'a, T>, &'a mut [[T; V]]), dk_status> {
        let layout = AmgPools::layout(sys, &self.options, solve, self.indices)?;
        Ok(layout.setup::<T, V>(sys, &self.options, self.reals, self.indices)?)
    }
}

/// The pool lengths of a multigrid solve of `V` components.
fn amg_pool_sizes<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    sizes_out: Out<'_, dk_plan_sizes>,
    solve: AmgSolve,
) -> Result<(), dk_status> {
    let options = read_one(amg)?.to_kernel::<T>()?;
    let work = output(work)?;
    let out = out_one(sizes_out)?;
    let sys = DkSpringSystem::read(system)?.build(work)?;
    let [reals, indices] = AmgPools::layout(&sys, &options, solve, work)?.lens(V)?;
    *out = dk_plan_sizes {
        reals,
        indices,
        bytes: 0,
    };
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Batina's stiffness `k_ij = 1 / |r_i − r_j|^exponent` for every directed edge of the 0-based
/// CSR graph into `stiffness` (`stiffness_len` = `graph->targets_len`). `exponent` 1 is the papers'
/// choice (computed as `1/|d|`), 2 is `1/(d·d)`, 0 the uniform Laplacian. The result is
/// exactly symmetric, as the solvers require. `points`: `node_count * dim` scalars, `dim` 2
/// or 3. Errors (nothing written): `DK_ERR_ZERO_LENGTH_EDGE`, `DK_ERR_NON_FINITE`,
/// `DK_ERR_INVALID_PARAMETER` (`exponent` negative or not finite, `dim`), graph, length and
/// pointer errors.
#[export(twin, graph[1])]
pub(crate) fn dk_spring_batina_stiffness<T: Real, const D: usize>(
    graph: In<'_, dk_graph>,
    points: In<'_, T>,
    _dim: Dim<D>,
    exponent: T,
    stiffness: Out<'_, T>,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    let p = read_points::<T, D>(points)?;
    Ok(batina_stiffness(&g, p, exponent, output(stiffness)?)?)
}

/// Length of the `uint32_t` `index_scratch` every spring solver and sweep needs to validate
/// its system (the anchoring search): `node_count`.
#[export(len_out[1])]
pub(crate) fn dk_spring_index_scratch_len(
    node_count: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    write_len(len_out, SpringSystem::<f64>::scratch_len(node_count))
}

/// Fills `*out` with the default linear-spring settings for f64: CG with the Jacobi
/// preconditioner, 10 000 iterations, residual tolerance 1e-10, update tolerance off,
/// `omega` 1.
///
/// # f32 twin
/// As [`dk_spring_solve_options_default`] with the f32 default residual tolerance
/// (`100 ε_f32` ≈ 1.19e-5).
#[export(twin, out[1])]
pub(crate) fn dk_spring_solve_options_default<T: Real>(
    out: Out<'_, dk_spring_solve_options>,
) -> Result<(), dk_status> {
    write_one(out, dk_spring_solve_options::default_for::<T>())
}

/// Scalars of `scratch` [`dk_spring_solve_linear`] needs for `options->method`:
/// `node_count * components` for Jacobi, 0 for Gauss–Seidel and SOR, `5 * node_count *
/// components` for CG (four vectors and the diagonal; same count for both precisions).
#[export(options[1], len_out[1])]
pub(crate) fn dk_spring_solve_linear_scratch_len(
    node_count: usize,
    components: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let method = read_one(options)?.method::<f64>()?;
    if !(1..=7).contains(&components) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    if node_count > usize::MAX / 4 {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    let items = solve_linear_scratch_len(&method, node_count);
    write_len(len_out, mul_len(items, components as usize)?)
}

/// Solves the linear springs for every free node, `Σ_j k_ij (x_j − x_i) = 0` per component
/// (Batina; Yang & Özgen eq. 1), fixed nodes keeping their values. `values` holds
/// `node_count * components` scalars: Dirichlet data at fixed nodes and the initial guess at
/// free nodes; on `DK_OK` the last iterate, and `*report` says whether it converged
/// (non-convergence is not an error). `scratch` needs [`dk_spring_solve_linear_scratch_len`]
/// scalars, `index_scratch` [`dk_spring_index_scratch_len`] entries.
///
/// Errors (values and report unchanged): `DK_ERR_NOT_SYMMETRIC`, `DK_ERR_NON_POSITIVE`,
/// `DK_ERR_UNANCHORED` (system), `DK_ERR_NON_FINITE` (values, stiffness),
/// `DK_ERR_INVALID_PARAMETER` (method, preconditioner, `omega` outside (0, 2), tolerances,
/// `components`), `DK_ERR_BUFFER_TOO_SMALL`, `DK_ERR_SINGULAR_SYSTEM` (CG breakdown), graph,
/// length and pointer errors.
#[export(twin, system[1], options[1], report[1])]
pub(crate) fn dk_spring_solve_linear<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    _components: Components<V>,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method::<T>()?;
    let v = chunks_mut::<T, V>(values)?;
    // Only whole items of the scratch are used.
    let s = whole_chunks_mut::<T, V>(scratch)?;
    let r = out_one(report)?;
    let system = DkSpringSystem::open(system, index_scratch)?;
    // The kernel validates before it writes, and CG works on a copy in the scratch: on any
    // error `values` is unchanged.
    *r = dk_spring_solve_report::of(system.solve_linear(v, method, &o.stopping(), s)?);
    Ok(())
}

/// One Jacobi sweep of the linear springs over the nodes `nodes_start..nodes_end` (read with
/// `index_base`): each free node in the range gets
/// `dst_i = src_i + Σ_j k_ij (src_j − src_i) / Σ_j k_ij`, fixed nodes in the range are copied,
/// `dst` outside the range is untouched. `src` and `dst` hold the whole field
/// (`node_count * components` scalars; neighbours outside the range, e.g. halo nodes, are
/// read). `*sweep` receives the range's maximum change and residual. Nothing is written on
/// error.
#[export(twin, system[1], sweep[1])]
pub(crate) fn dk_spring_jacobi_sweep<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    _components: Components<V>,
    src: In<'_, T>,
    dst: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let nodes = range(nodes_start, nodes_end, index_base)?;
    let sys = (system, index_scratch);
    jacobi_sweep::<T, V>(sys, nodes, src, dst, sweep, None)
}

/// [`dk_spring_jacobi_sweep`], and the range's `Σ |r_i|²` as the words of an exact sum:
/// `residual_words` receives [`DK_EXACT_SUM_WORDS`] `int64_t`. Words of several ranges or
/// processes add element-wise (`MPI_Allreduce` with `MPI_SUM` on `MPI_INT64_T`); rounded
/// with [`dk_exact_sum_value`] they give the bits of one sweep over all their nodes, however
/// the nodes were split (docs/reductions.md). Nothing is written on error.
#[export(twin, system[1], sweep[1], residual_words[72])]
pub(crate) fn dk_spring_jacobi_sweep_exact<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    _components: Components<V>,
    src: In<'_, T>,
    dst: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    sweep: Out<'_, dk_spring_sweep>,
    residual_words: Out<'_, i64>,
) -> Result<(), dk_status> {
    let nodes = range(nodes_start, nodes_end, index_base)?;
    let sys = (system, index_scratch);
    jacobi_sweep::<T, V>(sys, nodes, src, dst, sweep, Some(residual_words))
}

/// Rounds an exact sum given by its words (from [`dk_spring_jacobi_sweep_exact`], or the
/// element-wise sum of such word arrays) to the nearest `double`, ties to even. Errors:
/// pointer errors.
#[export(words[72], value_out[1])]
pub(crate) fn dk_exact_sum_value(
    words: In<'_, i64>,
    value_out: Out<'_, f64>,
) -> Result<(), dk_status> {
    let w: &[i64] = input_n(words, EXACT_SUM_WORDS)?;
    let out = out_one(value_out)?;
    let mut a = [0i64; EXACT_SUM_WORDS];
    a.copy_from_slice(w);
    *out = ExactSum::from_words(a).value();
    Ok(())
}

/// One in-place Gauss–Seidel (`omega` = 1) or SOR sweep of the linear springs over the nodes
/// `nodes_start..nodes_end` (read with `index_base`), in increasing node order:
/// `x_i ← x_i + ω Σ_j k_ij (x_j − x_i) / Σ_j k_ij` with the newest values; fixed nodes are
/// skipped. `*sweep` receives the range's maximum change and residual estimate. Errors
/// (nothing written): as [`dk_spring_jacobi_sweep`], plus `DK_ERR_INVALID_PARAMETER` for
/// `omega` outside (0, 2).
#[export(twin, system[1], sweep[1])]
pub(crate) fn dk_spring_sor_sweep<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    omega: T,
    _components: Components<V>,
    values: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let [a, b] = range(nodes_start, nodes_end, index_base)?;
    let v = chunks_mut::<T, V>(values)?;
    let w = out_one(sweep)?;
    let system = DkSpringSystem::open(system, index_scratch)?;
    *w = dk_spring_sweep::of(system.sor_sweep(a..b, v, omega)?);
    Ok(())
}

/// The relative residual `‖b − A x‖₂ / ‖b‖₂` of a value field for the linear springs (the
/// measure of `residual_tol` and of the solve report; `b` = the fixed nodes' pull on the free
/// nodes, plain `‖b − A x‖₂` when `b = 0`) into `*residual_out`.
#[export(twin, system[1], residual_out[1])]
pub(crate) fn dk_spring_relative_residual<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    _components: Components<V>,
    values: In<'_, T>,
    index_scratch: Out<'_, u32>,
    residual_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let v = chunks::<T, V>(values)?;
    let r = out_one(residual_out)?;
    *r = DkSpringSystem::open(system, index_scratch)?.relative_residual(v)?;
    Ok(())
}

/// Fills `*out` with the default angle-spring settings for f64: direct Gauss–Seidel,
/// `ε` = 0.01, 10 000 iterations, residual tolerance 1e-10, update tolerance off.
///
/// # f32 twin
/// As [`dk_spring_angle_options_default`] with the f32 default residual tolerance.
#[export(twin, out[1])]
pub(crate) fn dk_spring_angle_options_default<T: Real>(
    out: Out<'_, dk_spring_angle_options>,
) -> Result<(), dk_status> {
    let k = SolveOptions::<T>::default();
    let v = dk_spring_angle_options {
        max_iterations: k.max_iterations,
        residual_tol: k.residual_tol.to_f64(),
        update_tol: k.update_tol.to_f64(),
        epsilon: DEFAULT_ANGLE_EPSILON,
        method: DK_ANGLE_DIRECT_GAUSS_SEIDEL,
    };
    write_one(out, v)
}

/// Scalars of `scratch` [`dk_spring_solve_angle`] needs: per node and coordinate, 1 for
/// direct Jacobi, 0 for direct Gauss–Seidel, 4 for CG, and at least 4 whenever
/// `options->epsilon` is 0 (the rigidity probe).
///
/// # f32 twin
/// `f32` twin of [`dk_spring_solve_angle_scratch_len`] (differs only when `epsilon` rounds to
/// 0 in `float`).
#[export(twin, options[1], len_out[1])]
pub(crate) fn dk_spring_solve_angle_scratch_len<T: Real>(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_angle_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (method, probe) = read_one(options)?.scratch_query::<T>(dim)?;
    let items =
        angle_scratch_items(node_count, method, probe).ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    write_len(len_out, mul_len(items, dim as usize)?)
}

/// Scalars of `scratch` [`dk_spring_angle_rigidity_probe`] needs: `4 * node_count * dim`.
#[export(len_out[1])]
pub(crate) fn dk_spring_angle_rigidity_probe_scratch_len(
    node_count: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let items = mul_len(node_count, 4)?;
    write_len(len_out, mul_len(items, dim as usize)?)
}

/// Solves the angle-inclusion springs (Yang & Özgen §2.2) for the free nodes' displacements:
/// `Σ_j B_ij (x_j − x_i) = 0` with the edge blocks `B_ij = k_ij (d dᵀ/|d|² + ε I)`, `d` the
/// edge in the (undeformed) `points`. `values` holds `node_count * dim` scalars: prescribed
/// displacements at fixed nodes, the initial guess at free ones; on `DK_OK` the last iterate,
/// and `*report` says whether it converged. Method and `ε` come from `options`; with `ε` = 0
/// the rigidity probe runs first. `scratch` needs [`dk_spring_solve_angle_scratch_len`]
/// scalars.
///
/// Errors (values and report unchanged): `DK_ERR_SINGULAR_NODE` (a free node with colinear /
/// coplanar edges), `DK_ERR_SINGULAR_SYSTEM` (probe or CG breakdown),
/// `DK_ERR_ZERO_LENGTH_EDGE`, the errors of [`dk_spring_solve_linear`].
#[export(twin, system[1], options[1], report[1])]
pub(crate) fn dk_spring_solve_angle<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    options: In<'_, dk_spring_angle_options>,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method()?;
    let v = chunks_mut::<T, D>(values)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let base = DkSpringSystem::open(system, index_scratch)?;
    let system = angle_system::<T, D>(base, points, T::from_f64(o.epsilon))?;
    // Values are written only after the probe and only by a successful solve.
    *r = dk_spring_solve_report::of(system.solve_angle(v, method, &o.stopping(), s)?);
    Ok(())
}

/// One Jacobi-order sweep of the angle-spring direct method over the nodes
/// `nodes_start..nodes_end` (read with `index_base`): each free node solves its own 2×2/3×3
/// system with neighbours read from `src`, `dst_i = src_i + A_ii⁻¹ Σ_j B_ij (src_j − src_i)`;
/// fixed nodes in the range are copied, `dst` outside the range is untouched. `*sweep`
/// receives the range's maximum change and the residual of `src`. Nothing is written on
/// error.
#[export(twin, system[1], sweep[1])]
pub(crate) fn dk_spring_angle_jacobi_sweep<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    epsilon: T,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    src: In<'_, T>,
    dst: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let [a, b] = range(nodes_start, nodes_end, index_base)?;
    let s = chunks::<T, D>(src)?;
    let d = chunks_mut::<T, D>(dst)?;
    let w = out_one(sweep)?;
    let base = DkSpringSystem::open(system, index_scratch)?;
    let system = angle_system::<T, D>(base, points, epsilon)?;
    *w = dk_spring_sweep::of(system.angle_jacobi_sweep(a..b, s, d)?);
    Ok(())
}

/// One in-place Gauss–Seidel-order sweep of the angle-spring direct method over the nodes
/// `nodes_start..nodes_end` (read with `index_base`): like
/// [`dk_spring_angle_jacobi_sweep`] but each node uses its neighbours' newest values.
/// Nothing is written on error.
#[export(twin, system[1], sweep[1])]
pub(crate) fn dk_spring_angle_gauss_seidel_sweep<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    epsilon: T,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    values: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let [a, b] = range(nodes_start, nodes_end, index_base)?;
    let v = chunks_mut::<T, D>(values)?;
    let w = out_one(sweep)?;
    let base = DkSpringSystem::open(system, index_scratch)?;
    let system = angle_system::<T, D>(base, points, epsilon)?;
    *w = dk_spring_sweep::of(system.angle_gauss_seidel_sweep(a..b, v)?);
    Ok(())
}

/// The rigidity probe of the angle springs: block-Jacobi CG on a deterministic pseudo-random
/// right-hand side; `*amplification_out` receives the amplification (a condition estimate:
/// tens to hundreds for healthy meshes, huge for a near-mechanism; `dk_spring_solve_angle`
/// rejects more than 1e6 when `ε` = 0). Uses `options->epsilon` and the stopping rules
/// (`method` is ignored). `scratch` needs [`dk_spring_angle_rigidity_probe_scratch_len`]
/// scalars. Errors: `DK_ERR_SINGULAR_SYSTEM` (no convergence or non-positive curvature), and
/// those of [`dk_spring_solve_angle`]; nothing is written on error.
#[export(twin, system[1], options[1], amplification_out[1])]
pub(crate) fn dk_spring_angle_rigidity_probe<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    options: In<'_, dk_spring_angle_options>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    amplification_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let a = out_one(amplification_out)?;
    let base = DkSpringSystem::open(system, index_scratch)?;
    let system = angle_system::<T, D>(base, points, T::from_f64(o.epsilon))?;
    *a = system.angle_rigidity_probe(&o.stopping(), s)?;
    Ok(())
}

/// Fills `*out` with the default multigrid options (the same for both precisions): θ = 0
/// (every spring strong), at most 10 levels, a dense coarsest level of at most 256 unknowns,
/// Chebyshev smoothing of degree 2 (docs/amg.md).
#[export(out[1])]
pub(crate) fn dk_amg_options_default(out: Out<'_, dk_amg_options>) -> Result<(), dk_status> {
    write_one(out, dk_amg_options::of(AmgOptions::<f64>::default()))
}

/// Length of the `uint32_t` `work` buffer [`dk_spring_solve_linear_amg_pool_sizes`] and
/// [`dk_spring_solve_angle_amg_pool_sizes`] need (the multigrid hierarchy's symbolic pass, and
/// the system's validation in its front): `4 * (node_count + directed_edges) + 64`, with
/// `directed_edges` the graph's `targets_len`. The same count is the front of the `indices`
/// pool of the solves. Errors: `DK_ERR_TOO_LARGE`, pointer errors.
#[export(len_out[1])]
pub(crate) fn dk_spring_amg_work_len(
    node_count: usize,
    directed_edges: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    match amg_setup_work_len(node_count, directed_edges) {
        usize::MAX => Err(dk_status::DK_ERR_TOO_LARGE),
        len => write_len(len_out, len),
    }
}

/// The exact pool lengths [`dk_spring_solve_linear_amg`] needs for this system, `components`
/// (1 to 7) and multigrid options: validates the system and the options and runs the
/// hierarchy's symbolic pass (aggregation and the sparsity of every level) in `work`
/// ([`dk_spring_amg_work_len`] entries). `sizes_out->reals` = the hierarchy's values + `(5 N +
/// 3 × coarse unknowns) * components` scratch scalars; `sizes_out->indices` = the work length +
/// the hierarchy's index entries; `sizes_out->bytes` = 0. The sizes depend on the graph and
/// the fixed mask, and on the stiffness when `strength_theta` > 0 (the default): a time loop
/// whose stiffness changes queries again before each setup, or passes `strength_theta` = 0 to
/// query once.
///
/// Errors (only `work` is written): `DK_ERR_INVALID_PARAMETER` (`components`, multigrid
/// options), `DK_ERR_BUFFER_TOO_SMALL` (`work`), the system's errors (as
/// [`dk_spring_solve_linear`]), `DK_ERR_TOO_LARGE`, pointer errors.
#[export(twin, system[1], amg[1], sizes_out[1])]
pub(crate) fn dk_spring_solve_linear_amg_pool_sizes<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    _components: Components<V>,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    amg_pool_sizes::<T, V>(system, amg, work, sizes_out, AmgSolve::Cg)
}

/// [`dk_spring_solve_linear`]'s problem solved by conjugate gradients preconditioned with one
/// smoothed-aggregation multigrid V-cycle per iteration (the kernel's `AmgHierarchy::setup`
/// then `solve_linear_amg`, with the same bits): 15–25× fewer iterations than CG+Jacobi on
/// the 20k–234k-node meshes of docs/amg.md. The hierarchy is rebuilt in `pools` on every
/// call; a prepared plan (`dk_plan_*`) builds it once and keeps it across time steps.
///
/// `values` holds `node_count * components` scalars as for [`dk_spring_solve_linear`]; on
/// `DK_OK` the last iterate, and `*report` says whether it converged. `options` gives the
/// stopping rules (`max_iterations`, `residual_tol`, `update_tol`; `method`, `preconditioner`
/// and `omega` are ignored), `amg` the hierarchy ([`dk_amg_options_default`]). `pools`: the
/// `reals` and `indices` buffers of at least the lengths
/// [`dk_spring_solve_linear_amg_pool_sizes`] gave (longer ones give the same bits; `bytes`
/// is not used and may be NULL with length 0); their contents afterwards are unspecified.
///
/// Errors (values and report unchanged): `DK_ERR_BUFFER_TOO_SMALL` (a pool shorter than the
/// query's length), `DK_ERR_INVALID_PARAMETER` (multigrid options, tolerances,
/// `components`), `DK_ERR_SINGULAR_SYSTEM` (a coarse level not positive definite in floating
/// point, or a CG breakdown), `DK_ERR_OVERFLOW`, and the system's, length and pointer errors
/// of [`dk_spring_solve_linear`].
#[export(twin, system[1], options[1], amg[1], pools[1], report[1])]
pub(crate) fn dk_spring_solve_linear_amg<T: Real, const V: usize>(
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    amg: In<'_, dk_amg_options>,
    _components: Components<V>,
    values: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let stop = read_one(options)?.stopping::<T>();
    let v = chunks_mut::<T, V>(values)?;
    let r = out_one(report)?;
    let (base, pools) = amg_open(system, amg, pools)?;
    let (h, scratch) = pools.hierarchy::<V>(&base, AmgSolve::Cg)?;
    // The kernel validates before it writes and iterates on a copy in the scratch: on any
    // error `values` is unchanged.
    *r = dk_spring_solve_report::of(base.solve_linear_amg(&h, v, &stop, scratch)?);
    Ok(())
}

/// The exact pool lengths [`dk_spring_solve_angle_amg`] needs for this system, `dim` (2 or 3)
/// and multigrid options: [`dk_spring_solve_linear_amg_pool_sizes`] with `components` =
/// `dim` (the angle solve uses the scalar linear-spring hierarchy of the same system, applied
/// to each displacement component; its `5 N + 3 × coarse unknowns` scratch items also cover
/// the rigidity probe when `epsilon` is 0). Errors as
/// [`dk_spring_solve_linear_amg_pool_sizes`] (`dim` instead of `components`).
#[export(twin, system[1], amg[1], sizes_out[1])]
pub(crate) fn dk_spring_solve_angle_amg_pool_sizes<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    _dim: Dim<D>,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    amg_pool_sizes::<T, D>(system, amg, work, sizes_out, AmgSolve::Cg)
}

/// [`dk_spring_solve_angle`]'s problem (angle-inclusion springs) solved by its CG with one
/// V-cycle of the scalar linear-spring multigrid hierarchy per displacement component as the
/// preconditioner, in place of the node blocks (the kernel's `AmgHierarchy::setup` on the
/// system, then `AngleSystem::solve_angle_amg`, with the same bits): 8–19× fewer iterations
/// than `DK_ANGLE_CG` on meshes of 6k–98k nodes (docs/amg.md). The hierarchy is rebuilt in
/// `pools` on every call; a prepared plan keeps a hierarchy across time steps (plans run the
/// linear and quaternion methods, not the angle springs).
///
/// Arguments as [`dk_spring_solve_angle`], with `options->method` ignored (`epsilon` and the
/// stopping rules are used; with `epsilon` 0 the rigidity probe runs first), plus `amg` and
/// `pools` as for [`dk_spring_solve_linear_amg`] (lengths from
/// [`dk_spring_solve_angle_amg_pool_sizes`]).
///
/// Errors (values and report unchanged): those of [`dk_spring_solve_angle`] and of
/// [`dk_spring_solve_linear_amg`].
#[export(twin, system[1], options[1], amg[1], pools[1], report[1])]
pub(crate) fn dk_spring_solve_angle_amg<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    options: In<'_, dk_spring_angle_options>,
    amg: In<'_, dk_amg_options>,
    values: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let v = chunks_mut::<T, D>(values)?;
    let r = out_one(report)?;
    let (base, pools) = amg_open(system, amg, pools)?;
    let system = angle_system::<T, D>(base, points, T::from_f64(o.epsilon))?;
    let (h, scratch) = pools.hierarchy::<D>(system.base(), AmgSolve::Cg)?;
    // Values are written only after the probe and only by a successful solve.
    *r = dk_spring_solve_report::of(system.solve_angle_amg(&h, v, &o.stopping(), scratch)?);
    Ok(())
}

/// Writes the fixed mask of the spring system a sliding solve needs: `mask[i]` = 1 where
/// `constraints->kinds[i]` is 1 (fixed), else 0 (free and sliding nodes are unknowns of the
/// system). Build the [`dk_spring_system`] of [`dk_spring_solve_linear_sliding`] and its
/// siblings with it: they refuse a mask that differs (`DK_ERR_INVALID_PARAMETER`).
/// `mask_len` = `constraints->kinds_len`; `dim` (2 or 3) says how the directions are read.
///
/// Errors (nothing written): `DK_ERR_LENGTH_MISMATCH` (`mask_len`, `directions_len` not
/// `dim * kinds_len`), `DK_ERR_INDEX_OUT_OF_RANGE` (a kind above 3), `DK_ERR_NON_FINITE`,
/// `DK_ERR_NOT_UNIT` (a sliding node's direction), `DK_ERR_INVALID_PARAMETER` (`dim`),
/// pointer errors.
#[export(twin, constraints[1])]
pub(crate) fn dk_constraints_fixed_mask<T: Real, const D: usize>(
    constraints: In<'_, DkConstraints<T>>,
    _dim: Dim<D>,
    mask: Out<'_, u8>,
) -> Result<(), dk_status> {
    let c = DkConstraints::open::<D>(constraints)?;
    // The kernel checks the length before it writes.
    Ok(c.fixed_mask(output(mask)?)?)
}

/// Projects the motion of every sliding node onto its plane or line (the kernel's
/// `slide::slide_points`): `points[i] = original[i] + P_i (points[i] − original[i])` for
/// kinds 2 and 3 (`P` = `I − n nᵀ` for a plane, `t tᵀ` for a line); free and fixed nodes are
/// left as they are. Call it after a propagation in which the sliding nodes were ordinary
/// field nodes (e.g. `dk_deform_idw`). `original` and `points`: `dim` scalars per node,
/// `kinds_len` nodes.
///
/// Errors (`points` unchanged): `DK_ERR_LENGTH_MISMATCH`, `DK_ERR_NON_FINITE` (`original`,
/// `points`), `DK_ERR_OVERFLOW` (a projected position not finite), the constraints' errors
/// of [`dk_constraints_fixed_mask`], pointer errors.
#[export(twin, constraints[1])]
pub(crate) fn dk_slide_points<T: Real, const D: usize>(
    constraints: In<'_, DkConstraints<T>>,
    _dim: Dim<D>,
    original: In<'_, T>,
    points: Out<'_, T>,
) -> Result<(), dk_status> {
    let c = DkConstraints::open::<D>(constraints)?;
    let o = chunks::<T, D>(original)?;
    // The kernel checks every node before it writes any.
    Ok(slide_points(&c, o, chunks_mut::<T, D>(points)?)?)
}

/// Fits a plane (3D) or line (2D) to the nodes `nodes` (read with `index_base`) of `points`
/// by least squares (the kernel's `slide::fit_plane`): the unit normal (its largest-magnitude
/// component positive) into `normal_out`, the centroid into `point_out` (`dim` scalars each,
/// `normal_out_len` = `point_out_len` = `dim`), the residual `max |n · (x − c)|` into
/// `*residual_out` and the largest distance of a node from the centroid into `*extent_out`.
/// A set farther from its plane than `tolerance * extent` is refused (`DK_ERR_NOT_PLANAR`;
/// pass `INFINITY` to never refuse and read the residual). Use the normal as a kind-2
/// direction of [`dk_constraints`]. `index_scratch`: `nodes_len` entries for `index_base` 1,
/// NULL with length 0 for 0.
///
/// Errors (outputs unchanged): `DK_ERR_INVALID_PARAMETER` (fewer than `dim` nodes, nodes that
/// do not span a plane, `tolerance` NaN or negative, `dim`), `DK_ERR_INDEX_OUT_OF_RANGE`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_OVERFLOW`, `DK_ERR_NOT_PLANAR`, `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_BUFFER_TOO_SMALL` (`index_scratch`), length and pointer errors.
#[export(twin, residual_out[1], extent_out[1])]
pub(crate) fn dk_fit_plane<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    nodes: In<'_, u32>,
    index_base: u32,
    tolerance: T,
    index_scratch: Out<'_, u32>,
    normal_out: Out<'_, T>,
    point_out: Out<'_, T>,
    residual_out: Out<'_, T>,
    extent_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let nodes = input(nodes)?;
    if normal_out.len() != D || point_out.len() != D {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let normal = output_n(normal_out, D)?;
    let point = output_n(point_out, D)?;
    let residual = out_one(residual_out)?;
    let extent = out_one(extent_out)?;
    let (nodes, _) = rebase(nodes, index_base, output(index_scratch)?)?;
    let fit = fit_plane(p, nodes, tolerance)?;
    normal.copy_from_slice(&fit.normal);
    point.copy_from_slice(&fit.point);
    *residual = fit.residual;
    *extent = fit.extent;
    Ok(())
}

/// The unit tangent `(a × b) / |a × b|` of the line where two planes with normals `a` and `b`
/// (3 scalars each) meet (the kernel's `slide::plane_intersection`). Errors (nothing
/// written): `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a zero normal, or planes parallel to
/// within `√ε`), pointer errors.
#[export(twin, a[3], b[3], out[3])]
pub(crate) fn dk_plane_intersection<T: Real>(
    a: In<'_, T>,
    b: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    write_array(out, plane_intersection(read_array(a)?, read_array(b)?)?)
}

/// Scalars of `scratch` [`dk_spring_solve_linear_sliding`] needs for `options->method`:
/// `2 * node_count * dim` for Jacobi, `node_count * dim` for Gauss–Seidel and SOR, `6 *
/// node_count * dim` for CG (a scaled copy of the values, the CG vectors and the diagonal;
/// same count for both precisions).
#[export(options[1], len_out[1])]
pub(crate) fn dk_spring_solve_linear_sliding_scratch_len(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let method = read_one(options)?.method::<f64>()?;
    if !(2..=3).contains(&dim) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    // The kernel's count saturates; the largest is 6 n.
    mul_len(node_count, 6)?;
    let items = solve_linear_sliding_scratch_len(&LinearSolver::Method(method), node_count);
    write_len(len_out, mul_len(items, dim as usize)?)
}

/// [`dk_spring_solve_linear`] with sliding nodes (symmetry planes; the kernel's
/// `SpringSystem::solve_linear_sliding`, with the same bits): the displacements minimise the
/// spring energy over each node's allowed motions, `P K P d = P b` on `range(P)` with `P_i` =
/// `I` (free), 0 (fixed), `I − n nᵀ` (plane), `t tᵀ` (line), solved jointly over the `dim`
/// components (2 or 3, as the directions). `values` holds `node_count * dim` displacements:
/// prescribed at fixed nodes, the initial guess elsewhere; on `DK_OK` the last iterate, every
/// sliding node's displacement in its plane or line to rounding, and `*report` (residual
/// `‖P (b − K d)‖ / ‖P b‖`) says whether it converged. The one-level methods of `options`
/// (Jacobi, Gauss–Seidel, SOR project each node's update; CG with its preconditioner applied
/// as `P M⁻¹ P`). `system` must be built with the mask [`dk_constraints_fixed_mask`] writes.
/// `scratch` needs [`dk_spring_solve_linear_sliding_scratch_len`] scalars, `index_scratch`
/// [`dk_spring_index_scratch_len`] entries.
///
/// Errors (values and report unchanged): `DK_ERR_INVALID_PARAMETER` (a fixed mask that
/// differs from the constraints' kind 1, `dim`, and as [`dk_spring_solve_linear`]), the
/// constraints' errors of [`dk_constraints_fixed_mask`] (`DK_ERR_LENGTH_MISMATCH` when they
/// do not have `node_count` nodes), `DK_ERR_OVERFLOW`, and those of
/// [`dk_spring_solve_linear`].
#[export(twin, system[1], constraints[1], options[1], report[1])]
pub(crate) fn dk_spring_solve_linear_sliding<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_solve_options>,
    _dim: Dim<D>,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = LinearSolver::Method(o.method::<T>()?);
    let c = DkConstraints::open::<D>(constraints)?;
    let v = chunks_mut::<T, D>(values)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let system = DkSpringSystem::open(system, index_scratch)?;
    // The kernel validates (the mask against the constraints too) before it writes and
    // iterates on a scaled copy in the scratch: on any error `values` is unchanged.
    let rep = system.solve_linear_sliding(&c, v, method, &o.stopping(), s)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

/// Scalars of `scratch` [`dk_spring_solve_angle_sliding`] needs: per node and coordinate, 2
/// for direct Jacobi, 1 for direct Gauss–Seidel, 5 for CG, and at least 4 whenever
/// `options->epsilon` is 0 (the rigidity probe).
///
/// # f32 twin
/// `f32` twin of [`dk_spring_solve_angle_sliding_scratch_len`] (differs only when `epsilon`
/// rounds to 0 in `float`).
#[export(twin, options[1], len_out[1])]
pub(crate) fn dk_spring_solve_angle_sliding_scratch_len<T: Real>(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_angle_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (method, probe) = read_one(options)?.scratch_query::<T>(dim)?;
    let items = angle_sliding_scratch_items(node_count, method, probe)
        .ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    write_len(len_out, mul_len(items, dim as usize)?)
}

/// [`dk_spring_solve_angle`] with sliding nodes (the kernel's
/// `AngleSystem::solve_angle_sliding`, with the same bits): the problem of
/// [`dk_spring_solve_linear_sliding`] with the angle springs' edge blocks. The direct methods
/// solve each node's projected block `(P A P + s (I − P)) δ = P r` (`s = tr A / dim`), in
/// Gauss–Seidel order over-relaxed by `omega` (1 = plain) or in Jacobi order; `DK_ANGLE_CG`
/// runs on the projected system with the projected node blocks as preconditioner. `omega`
/// must be in (0, 2) for every method. With `options->epsilon` 0 the unconstrained rigidity
/// probe runs first. `scratch` needs [`dk_spring_solve_angle_sliding_scratch_len`] scalars.
/// Values, report and the sliding guarantee as [`dk_spring_solve_linear_sliding`].
///
/// Errors (values and report unchanged): those of [`dk_spring_solve_angle`] and of
/// [`dk_spring_solve_linear_sliding`]; `DK_ERR_INVALID_PARAMETER` for `omega`.
#[export(twin, system[1], constraints[1], options[1], report[1])]
pub(crate) fn dk_spring_solve_angle_sliding<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_angle_options>,
    omega: T,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method()?;
    let c = DkConstraints::open::<D>(constraints)?;
    let v = chunks_mut::<T, D>(values)?;
    let s = whole_chunks_mut::<T, D>(scratch)?;
    let r = out_one(report)?;
    let base = DkSpringSystem::open(system, index_scratch)?;
    let system = angle_system::<T, D>(base, points, T::from_f64(o.epsilon))?;
    // Values are written only after the probe and only by a successful solve.
    let rep = system.solve_angle_sliding(&c, v, method, omega, &o.stopping(), s)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

/// The exact pool lengths [`dk_spring_solve_linear_sliding_amg`] needs for this system (built
/// with [`dk_constraints_fixed_mask`]), `dim` (2 or 3) and multigrid options, as
/// [`dk_spring_solve_linear_amg_pool_sizes`] (the same `work`, from
/// [`dk_spring_amg_work_len`]) but with `(6 N + 3 × coarse unknowns) * dim` scratch scalars
/// (the sliding solve also keeps a scaled copy of the values). The sizes do not depend on the
/// constraints. Errors as [`dk_spring_solve_linear_amg_pool_sizes`] (`dim` instead of
/// `components`).
#[export(twin, system[1], amg[1], sizes_out[1])]
pub(crate) fn dk_spring_solve_linear_sliding_amg_pool_sizes<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    _dim: Dim<D>,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    amg_pool_sizes::<T, D>(system, amg, work, sizes_out, AmgSolve::SlidingCg)
}

/// [`dk_spring_solve_linear_sliding`]'s problem solved by its projected CG preconditioned
/// with one smoothed-aggregation multigrid V-cycle per iteration, applied as `P M⁻¹ P` (the
/// kernel's `AmgHierarchy::setup` on the system, sliding nodes free, then
/// `solve_linear_sliding` with `LinearSolver::Amg`, with the same bits). The hierarchy is
/// rebuilt in `pools` on every call (lengths from
/// [`dk_spring_solve_linear_sliding_amg_pool_sizes`]; `bytes` unused); plans do not take
/// sliding kinds yet.
///
/// Arguments as [`dk_spring_solve_linear_sliding`] (`options` gives only the stopping rules),
/// plus `amg` and `pools` as for [`dk_spring_solve_linear_amg`].
///
/// Errors (values and report unchanged): those of [`dk_spring_solve_linear_sliding`] and of
/// [`dk_spring_solve_linear_amg`].
#[export(twin, system[1], constraints[1], options[1], amg[1], pools[1], report[1])]
pub(crate) fn dk_spring_solve_linear_sliding_amg<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_solve_options>,
    amg: In<'_, dk_amg_options>,
    _dim: Dim<D>,
    values: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let stop = read_one(options)?.stopping::<T>();
    let c = DkConstraints::open::<D>(constraints)?;
    let v = chunks_mut::<T, D>(values)?;
    let r = out_one(report)?;
    let (base, pools) = amg_open(system, amg, pools)?;
    let (h, scratch) = pools.hierarchy::<D>(&base, AmgSolve::SlidingCg)?;
    // The kernel validates before it writes and iterates on a copy in the scratch: on any
    // error `values` is unchanged.
    let rep = base.solve_linear_sliding(&c, v, LinearSolver::Amg(&h), &stop, scratch)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

/// The exact pool lengths [`dk_spring_solve_angle_sliding_amg`] needs: the same as
/// [`dk_spring_solve_linear_sliding_amg_pool_sizes`] with the same `dim` (the angle solve
/// applies the scalar linear-spring hierarchy to each displacement component; its scratch
/// also covers the rigidity probe when `epsilon` is 0). Errors as
/// [`dk_spring_solve_linear_sliding_amg_pool_sizes`].
#[export(twin, system[1], amg[1], sizes_out[1])]
pub(crate) fn dk_spring_solve_angle_sliding_amg_pool_sizes<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    _dim: Dim<D>,
    amg: In<'_, dk_amg_options>,
    work: Out<'_, u32>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    amg_pool_sizes::<T, D>(system, amg, work, sizes_out, AmgSolve::SlidingCg)
}

/// [`dk_spring_solve_angle_sliding`]'s projected CG preconditioned by one V-cycle of the
/// scalar linear-spring multigrid hierarchy per displacement component, applied as `P M⁻¹ P`
/// (the kernel's `AmgHierarchy::setup` on the system, then
/// `AngleSystem::solve_angle_sliding_amg`, with the same bits). The hierarchy is rebuilt in
/// `pools` on every call (lengths from [`dk_spring_solve_angle_sliding_amg_pool_sizes`]).
///
/// Arguments as [`dk_spring_solve_angle_sliding`] without `omega` and the scratch buffers,
/// `options->method` ignored (`epsilon` and the stopping rules are used; with `epsilon` 0 the
/// rigidity probe runs first), plus `amg` and `pools` as for [`dk_spring_solve_angle_amg`].
///
/// Errors (values and report unchanged): those of [`dk_spring_solve_angle_sliding`] and of
/// [`dk_spring_solve_angle_amg`].
#[export(twin, system[1], constraints[1], options[1], amg[1], pools[1], report[1])]
pub(crate) fn dk_spring_solve_angle_sliding_amg<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    constraints: In<'_, DkConstraints<T>>,
    options: In<'_, dk_spring_angle_options>,
    amg: In<'_, dk_amg_options>,
    values: Out<'_, T>,
    pools: In<'_, DkPlanPools<T>>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let c = DkConstraints::open::<D>(constraints)?;
    let v = chunks_mut::<T, D>(values)?;
    let r = out_one(report)?;
    let (base, pools) = amg_open(system, amg, pools)?;
    let system = angle_system::<T, D>(base, points, T::from_f64(o.epsilon))?;
    let (h, scratch) = pools.hierarchy::<D>(system.base(), AmgSolve::SlidingCg)?;
    // Values are written only after the probe and only by a successful solve.
    let rep = system.solve_angle_sliding_amg(&c, v, &h, &o.stopping(), scratch)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}
