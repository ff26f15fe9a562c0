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
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::spring::{
    angle_gauss_seidel_sweep, angle_jacobi_sweep, angle_rigidity_probe, batina_stiffness,
    jacobi_sweep, relative_residual, solve_angle, solve_linear, solve_linear_scratch_len,
    sor_sweep, AngleMethod, AngleSystem, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem, Sweep, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::Real;

use crate::args::{
    assert_layout, by_components, by_dim, done, graph, mul_len, range, read_one, read_points,
    write_len, write_one,
};
use crate::slice::{chunks, chunks_mut, input, out_one, output, In, Out};
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
#[cfg(target_pointer_width = "64")]
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
#[cfg(target_pointer_width = "64")]
assert_layout!(
    dk_spring_angle_options, 40;
    max_iterations = 0, residual_tol = 8, update_tol = 16, epsilon = 24, method = 32,
);

impl dk_spring_angle_options {
    fn method(&self) -> Result<AngleMethod, dk_status> {
        match self.method {
            DK_ANGLE_DIRECT_GAUSS_SEIDEL => Ok(AngleMethod::DirectGaussSeidel),
            DK_ANGLE_DIRECT_JACOBI => Ok(AngleMethod::DirectJacobi),
            DK_ANGLE_CG => Ok(AngleMethod::Cg),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }
    }

    fn stopping<T: Real>(&self) -> SolveOptions<T> {
        stopping(self.max_iterations, self.residual_tol, self.update_tol)
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
#[cfg(target_pointer_width = "64")]
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
#[cfg(target_pointer_width = "64")]
assert_layout!(dk_spring_sweep, 16; max_change = 0, residual_sq = 8);

impl dk_spring_sweep {
    fn of<T: Real>(s: Sweep<T>) -> Self {
        dk_spring_sweep {
            max_change: s.max_change.to_f64(),
            residual_sq: s.residual_sq.to_f64(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Shared argument handling.
// ---------------------------------------------------------------------------------------------

/// The arguments that describe a spring system.
struct SysArgs<'a, T> {
    offsets: In<'a, u32>,
    offsets_len: usize,
    targets: In<'a, u32>,
    targets_len: usize,
    stiffness: In<'a, T>,
    stiffness_len: usize,
    fixed: In<'a, u8>,
    fixed_len: usize,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
}

impl<'a, T: Real> SysArgs<'a, T> {
    /// Borrows and validates the system (writes only `index_scratch`).
    fn build(self) -> Result<SpringSystem<'a, T>, dk_status> {
        let g = graph(
            self.offsets,
            self.offsets_len,
            self.targets,
            self.targets_len,
        )?;
        let k = input(self.stiffness, self.stiffness_len)?;
        let f = input(self.fixed, self.fixed_len)?;
        let s = output(self.index_scratch, self.index_scratch_len)?;
        SpringSystem::new(g, k, f, s).map_err(dk_status::from)
    }
}

// ---------------------------------------------------------------------------------------------
// Generic inner functions.
// ---------------------------------------------------------------------------------------------

fn batina_d<T: Real, const D: usize>(
    g: &deform_kernel::Graph<'_>,
    points: In<'_, T>,
    points_len: usize,
    exponent: T,
    stiffness: Out<'_, T>,
    stiffness_len: usize,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points, points_len)?;
    let k = output(stiffness, stiffness_len)?;
    batina_stiffness(g, p, exponent, k).map_err(dk_status::from)
}

#[allow(clippy::too_many_arguments)]
fn batina_t<T: Real>(
    offsets: In<'_, u32>,
    offsets_len: usize,
    targets: In<'_, u32>,
    targets_len: usize,
    points: In<'_, T>,
    points_len: usize,
    dim: u32,
    exponent: T,
    stiffness: Out<'_, T>,
    stiffness_len: usize,
) -> dk_status {
    done((|| {
        let g = graph(offsets, offsets_len, targets, targets_len)?;
        by_dim!(
            dim,
            batina_d::<T>,
            (&g, points, points_len, exponent, stiffness, stiffness_len)
        )
    })())
}

fn solve_options_default<T: Real>(out: Out<'_, dk_spring_solve_options>) -> dk_status {
    let k = SolveOptions::<T>::default();
    let v = dk_spring_solve_options {
        max_iterations: k.max_iterations,
        residual_tol: k.residual_tol.to_f64(),
        update_tol: k.update_tol.to_f64(),
        omega: 1.0,
        method: DK_LINEAR_CG,
        preconditioner: DK_PRECONDITIONER_JACOBI,
    };
    done(write_one(out, v))
}

fn angle_options_default<T: Real>(out: Out<'_, dk_spring_angle_options>) -> dk_status {
    let k = SolveOptions::<T>::default();
    let v = dk_spring_angle_options {
        max_iterations: k.max_iterations,
        residual_tol: k.residual_tol.to_f64(),
        update_tol: k.update_tol.to_f64(),
        epsilon: DEFAULT_ANGLE_EPSILON,
        method: DK_ANGLE_DIRECT_GAUSS_SEIDEL,
    };
    done(write_one(out, v))
}

#[allow(clippy::too_many_arguments)]
fn solve_linear_v<T: Real, const V: usize>(
    sys: SysArgs<'_, T>,
    options: &dk_spring_solve_options,
    values: Out<'_, T>,
    values_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let method = options.method::<T>()?;
    let stop = options.stopping::<T>();
    let v = chunks_mut::<T, V>(values, values_len)?;
    // Only whole items of the scratch are used.
    let scratch_len = scratch_len - scratch_len % V;
    let s = chunks_mut::<T, V>(scratch, scratch_len)?;
    let r = out_one(report)?;
    let system = sys.build()?;
    // The kernel validates before it writes, and CG works on a copy in the scratch: on any
    // error `values` is unchanged.
    let rep = solve_linear(&system, v, method, &stop, s).map_err(dk_status::from)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn solve_linear_t<T: Real>(
    sys: SysArgs<T>,
    options: In<'_, dk_spring_solve_options>,
    components: u32,
    values: Out<'_, T>,
    values_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_spring_solve_report>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        by_components!(
            components,
            solve_linear_v::<T>,
            (sys, &o, values, values_len, scratch, scratch_len, report)
        )
    })())
}

#[allow(clippy::too_many_arguments)]
fn jacobi_sweep_v<T: Real, const V: usize>(
    sys: SysArgs<'_, T>,
    nodes: [usize; 2],
    src: In<'_, T>,
    src_len: usize,
    dst: Out<'_, T>,
    dst_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let s = chunks::<T, V>(src, src_len)?;
    let d = chunks_mut::<T, V>(dst, dst_len)?;
    let w = out_one(sweep)?;
    let system = sys.build()?;
    let [a, b] = nodes;
    *w = dk_spring_sweep::of(jacobi_sweep(&system, a..b, s, d).map_err(dk_status::from)?);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn jacobi_sweep_t<T: Real>(
    sys: SysArgs<T>,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    components: u32,
    src: In<'_, T>,
    src_len: usize,
    dst: Out<'_, T>,
    dst_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> dk_status {
    done((|| {
        let nodes = range(nodes_start, nodes_end, index_base)?;
        by_components!(
            components,
            jacobi_sweep_v::<T>,
            (sys, nodes, src, src_len, dst, dst_len, sweep)
        )
    })())
}

fn sor_sweep_v<T: Real, const V: usize>(
    sys: SysArgs<'_, T>,
    nodes: [usize; 2],
    omega: T,
    values: Out<'_, T>,
    values_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let v = chunks_mut::<T, V>(values, values_len)?;
    let w = out_one(sweep)?;
    let system = sys.build()?;
    let [a, b] = nodes;
    *w = dk_spring_sweep::of(sor_sweep(&system, a..b, v, omega).map_err(dk_status::from)?);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn sor_sweep_t<T: Real>(
    sys: SysArgs<T>,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    omega: T,
    components: u32,
    values: Out<'_, T>,
    values_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> dk_status {
    done((|| {
        let nodes = range(nodes_start, nodes_end, index_base)?;
        by_components!(
            components,
            sor_sweep_v::<T>,
            (sys, nodes, omega, values, values_len, sweep)
        )
    })())
}

fn relative_residual_v<T: Real, const V: usize>(
    sys: SysArgs<'_, T>,
    values: In<'_, T>,
    values_len: usize,
    residual_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let v = chunks::<T, V>(values, values_len)?;
    let r = out_one(residual_out)?;
    let system = sys.build()?;
    *r = relative_residual(&system, v).map_err(dk_status::from)?;
    Ok(())
}

fn relative_residual_t<T: Real>(
    sys: SysArgs<T>,
    components: u32,
    values: In<'_, T>,
    values_len: usize,
    residual_out: Out<'_, T>,
) -> dk_status {
    done(by_components!(
        components,
        relative_residual_v::<T>,
        (sys, values, values_len, residual_out)
    ))
}

/// Scalars of scratch `dk_spring_solve_angle` needs for precision `T`.
fn angle_scratch_scalars<T: Real>(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_angle_options>,
    len_out: Out<'_, usize>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        let method = o.method()?;
        if !(2..=3).contains(&dim) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        // Mirrors deform_kernel::spring::angle_scratch_len (items of [T; D]).
        let four = mul_len(node_count, 4)?;
        let solve = match method {
            AngleMethod::DirectJacobi => node_count,
            AngleMethod::DirectGaussSeidel => 0,
            AngleMethod::Cg => four,
        };
        let items = if T::from_f64(o.epsilon) == T::ZERO {
            solve.max(four)
        } else {
            solve
        };
        let len = mul_len(items, dim as usize)?;
        write_len(len_out, len)
    })())
}

/// The angle system's arguments beyond the spring system.
struct AngleArgs<'a, T> {
    points: In<'a, T>,
    points_len: usize,
}

impl<'a, T: Real> AngleArgs<'a, T> {
    fn build<const D: usize>(
        &self,
        base: SpringSystem<'a, T>,
        epsilon: T,
    ) -> Result<AngleSystem<'a, T, D>, dk_status> {
        let p = read_points::<T, D>(self.points, self.points_len)?;
        AngleSystem::new(base, p, epsilon).map_err(dk_status::from)
    }
}

#[allow(clippy::too_many_arguments)]
fn solve_angle_d<T: Real, const D: usize>(
    sys: SysArgs<'_, T>,
    pts: &AngleArgs<T>,
    options: &dk_spring_angle_options,
    values: Out<'_, T>,
    values_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let method = options.method()?;
    let stop = options.stopping::<T>();
    let v = chunks_mut::<T, D>(values, values_len)?;
    let scratch_len = scratch_len - scratch_len % D;
    let s = chunks_mut::<T, D>(scratch, scratch_len)?;
    let r = out_one(report)?;
    let base = sys.build()?;
    let system = pts.build::<D>(base, T::from_f64(options.epsilon))?;
    // Values are written only after the probe and only by a successful solve.
    let rep = solve_angle(&system, v, method, &stop, s).map_err(dk_status::from)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn solve_angle_t<T: Real>(
    sys: SysArgs<T>,
    pts: AngleArgs<T>,
    dim: u32,
    options: In<'_, dk_spring_angle_options>,
    values: Out<'_, T>,
    values_len: usize,
    scratch: Out<'_, T>,
    scratch_len: usize,
    report: Out<'_, dk_spring_solve_report>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        by_dim!(
            dim,
            solve_angle_d::<T>,
            (
                sys,
                &pts,
                &o,
                values,
                values_len,
                scratch,
                scratch_len,
                report
            )
        )
    })())
}

#[allow(clippy::too_many_arguments)]
fn angle_jacobi_d<T: Real, const D: usize>(
    sys: SysArgs<'_, T>,
    pts: &AngleArgs<T>,
    epsilon: T,
    nodes: [usize; 2],
    src: In<'_, T>,
    src_len: usize,
    dst: Out<'_, T>,
    dst_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let s = chunks::<T, D>(src, src_len)?;
    let d = chunks_mut::<T, D>(dst, dst_len)?;
    let w = out_one(sweep)?;
    let system = pts.build::<D>(sys.build()?, epsilon)?;
    let [a, b] = nodes;
    *w = dk_spring_sweep::of(angle_jacobi_sweep(&system, a..b, s, d).map_err(dk_status::from)?);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn angle_jacobi_t<T: Real>(
    sys: SysArgs<T>,
    pts: AngleArgs<T>,
    dim: u32,
    epsilon: T,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    src: In<'_, T>,
    src_len: usize,
    dst: Out<'_, T>,
    dst_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> dk_status {
    done((|| {
        let nodes = range(nodes_start, nodes_end, index_base)?;
        by_dim!(
            dim,
            angle_jacobi_d::<T>,
            (sys, &pts, epsilon, nodes, src, src_len, dst, dst_len, sweep)
        )
    })())
}

#[allow(clippy::too_many_arguments)]
fn angle_gs_d<T: Real, const D: usize>(
    sys: SysArgs<'_, T>,
    pts: &AngleArgs<T>,
    epsilon: T,
    nodes: [usize; 2],
    values: Out<'_, T>,
    values_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> Result<(), dk_status> {
    let v = chunks_mut::<T, D>(values, values_len)?;
    let w = out_one(sweep)?;
    let system = pts.build::<D>(sys.build()?, epsilon)?;
    let [a, b] = nodes;
    *w = dk_spring_sweep::of(angle_gauss_seidel_sweep(&system, a..b, v).map_err(dk_status::from)?);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn angle_gs_t<T: Real>(
    sys: SysArgs<T>,
    pts: AngleArgs<T>,
    dim: u32,
    epsilon: T,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    values: Out<'_, T>,
    values_len: usize,
    sweep: Out<'_, dk_spring_sweep>,
) -> dk_status {
    done((|| {
        let nodes = range(nodes_start, nodes_end, index_base)?;
        by_dim!(
            dim,
            angle_gs_d::<T>,
            (sys, &pts, epsilon, nodes, values, values_len, sweep)
        )
    })())
}

#[allow(clippy::too_many_arguments)]
fn probe_d<T: Real, const D: usize>(
    sys: SysArgs<'_, T>,
    pts: &AngleArgs<T>,
    options: &dk_spring_angle_options,
    scratch: Out<'_, T>,
    scratch_len: usize,
    amplification_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let stop = options.stopping::<T>();
    let scratch_len = scratch_len - scratch_len % D;
    let s = chunks_mut::<T, D>(scratch, scratch_len)?;
    let a = out_one(amplification_out)?;
    let system = pts.build::<D>(sys.build()?, T::from_f64(options.epsilon))?;
    *a = angle_rigidity_probe(&system, &stop, s).map_err(dk_status::from)?;
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn probe_t<T: Real>(
    sys: SysArgs<T>,
    pts: AngleArgs<T>,
    dim: u32,
    options: In<'_, dk_spring_angle_options>,
    scratch: Out<'_, T>,
    scratch_len: usize,
    amplification_out: Out<'_, T>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        by_dim!(
            dim,
            probe_d::<T>,
            (sys, &pts, &o, scratch, scratch_len, amplification_out)
        )
    })())
}

// ---------------------------------------------------------------------------------------------
// Stiffness and sizes.
// ---------------------------------------------------------------------------------------------

/// Batina's stiffness `k_ij = 1 / |r_i − r_j|^exponent` for every directed edge of the 0-based
/// CSR graph into `stiffness` (`stiffness_len` = `targets_len`). `exponent` 1 is the papers'
/// choice (computed as `1/|d|`), 2 is `1/(d·d)`, 0 the uniform Laplacian. The result is
/// exactly symmetric, as the solvers require. `points`: `node_count * dim` scalars, `dim` 2
/// or 3. Errors (nothing written): `DK_ERR_ZERO_LENGTH_EDGE`, `DK_ERR_NON_FINITE`,
/// `DK_ERR_INVALID_PARAMETER` (`exponent` negative or not finite, `dim`), graph, length and
/// pointer errors.
///
/// # Safety
/// Inputs readable for their lengths; `stiffness` writable for `stiffness_len` scalars, not
/// overlapping the inputs.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_batina_stiffness(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    exponent: f64,
    stiffness: *mut f64,
    stiffness_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, points, stiffness) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(points, points_len),
            Out::new(stiffness, stiffness_len),
        )
    };
    batina_t(
        offsets,
        offsets_len,
        targets,
        targets_len,
        points,
        points_len,
        dim,
        exponent,
        stiffness,
        stiffness_len,
    )
}

/// `f32` twin of [`dk_spring_batina_stiffness`].
///
/// # Safety
/// As [`dk_spring_batina_stiffness`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_batina_stiffness_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    exponent: f32,
    stiffness: *mut f32,
    stiffness_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, points, stiffness) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(points, points_len),
            Out::new(stiffness, stiffness_len),
        )
    };
    batina_t(
        offsets,
        offsets_len,
        targets,
        targets_len,
        points,
        points_len,
        dim,
        exponent,
        stiffness,
        stiffness_len,
    )
}

/// Length of the `uint32_t` `index_scratch` every spring solver and sweep needs to validate
/// its system (the anchoring search): `node_count`.
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_index_scratch_len(
    node_count: usize,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    done(write_len(
        len_out,
        SpringSystem::<f64>::scratch_len(node_count),
    ))
}

/// Fills `*out` with the default linear-spring settings for f64: CG with the Jacobi
/// preconditioner, 10 000 iterations, residual tolerance 1e-10, update tolerance off,
/// `omega` 1.
///
/// # Safety
/// `out` points to one writable options struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_options_default(
    out: *mut dk_spring_solve_options,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    solve_options_default::<f64>(out)
}

/// As [`dk_spring_solve_options_default`] with the f32 default residual tolerance
/// (`100 ε_f32` ≈ 1.19e-5).
///
/// # Safety
/// As [`dk_spring_solve_options_default`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_options_default_f32(
    out: *mut dk_spring_solve_options,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    solve_options_default::<f32>(out)
}

/// Scalars of `scratch` [`dk_spring_solve_linear`] needs for `options->method`:
/// `node_count * components` for Jacobi, 0 for Gauss–Seidel and SOR, `5 * node_count *
/// components` for CG (four vectors and the diagonal; same count for both precisions).
///
/// # Safety
/// `options` points to one readable struct; `len_out` to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_linear_scratch_len(
    node_count: usize,
    components: u32,
    options: *const dk_spring_solve_options,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (options, len_out) = unsafe { (In::new(options, 1), Out::new(len_out, 1)) };
    done((|| {
        let o = read_one(options)?;
        let method = o.method::<f64>()?;
        if !(1..=7).contains(&components) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        if node_count > usize::MAX / 4 {
            return Err(dk_status::DK_ERR_TOO_LARGE);
        }
        let items = solve_linear_scratch_len(&method, node_count);
        write_len(len_out, mul_len(items, components as usize)?)
    })())
}

// ---------------------------------------------------------------------------------------------
// Linear springs.
// ---------------------------------------------------------------------------------------------

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
///
/// # Safety
/// Every input pointer is readable for its length; `options` points to one readable struct;
/// `values` is readable and writable for `values_len` scalars; `scratch` and `index_scratch`
/// writable for their lengths; `report` points to one writable report; writable buffers
/// overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_linear(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    components: u32,
    values: *mut f64,
    values_len: usize,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, options, values, scratch, index_scratch, report) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(values, values_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(report, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    solve_linear_t(
        sys,
        options,
        components,
        values,
        values_len,
        scratch,
        scratch_len,
        report,
    )
}

/// `f32` twin of [`dk_spring_solve_linear`].
///
/// # Safety
/// As [`dk_spring_solve_linear`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_linear_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    components: u32,
    values: *mut f32,
    values_len: usize,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, options, values, scratch, index_scratch, report) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(values, values_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(report, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    solve_linear_t(
        sys,
        options,
        components,
        values,
        values_len,
        scratch,
        scratch_len,
        report,
    )
}

/// One Jacobi sweep of the linear springs over the nodes `nodes_start..nodes_end` (read with
/// `index_base`): each free node in the range gets
/// `dst_i = src_i + Σ_j k_ij (src_j − src_i) / Σ_j k_ij`, fixed nodes in the range are copied,
/// `dst` outside the range is untouched. `src` and `dst` hold the whole field
/// (`node_count * components` scalars; neighbours outside the range, e.g. halo nodes, are
/// read). `*sweep` receives the range's maximum change and residual. Nothing is written on
/// error.
///
/// # Safety
/// As [`dk_spring_solve_linear`]; `src` readable for `src_len` scalars, `dst` writable for
/// `dst_len` and not overlapping `src`; `sweep` points to one writable struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_jacobi_sweep(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    components: u32,
    src: *const f64,
    src_len: usize,
    dst: *mut f64,
    dst_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, src, dst, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(src, src_len),
            Out::new(dst, dst_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    jacobi_sweep_t(
        sys,
        nodes_start,
        nodes_end,
        index_base,
        components,
        src,
        src_len,
        dst,
        dst_len,
        sweep,
    )
}

/// `f32` twin of [`dk_spring_jacobi_sweep`].
///
/// # Safety
/// As [`dk_spring_jacobi_sweep`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_jacobi_sweep_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    components: u32,
    src: *const f32,
    src_len: usize,
    dst: *mut f32,
    dst_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, src, dst, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(src, src_len),
            Out::new(dst, dst_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    jacobi_sweep_t(
        sys,
        nodes_start,
        nodes_end,
        index_base,
        components,
        src,
        src_len,
        dst,
        dst_len,
        sweep,
    )
}

/// One in-place Gauss–Seidel (`omega` = 1) or SOR sweep of the linear springs over the nodes
/// `nodes_start..nodes_end` (read with `index_base`), in increasing node order:
/// `x_i ← x_i + ω Σ_j k_ij (x_j − x_i) / Σ_j k_ij` with the newest values; fixed nodes are
/// skipped. `*sweep` receives the range's maximum change and residual estimate. Errors
/// (nothing written): as [`dk_spring_jacobi_sweep`], plus `DK_ERR_INVALID_PARAMETER` for
/// `omega` outside (0, 2).
///
/// # Safety
/// As [`dk_spring_solve_linear`]; `values` readable and writable for `values_len` scalars;
/// `sweep` points to one writable struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_sor_sweep(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    omega: f64,
    components: u32,
    values: *mut f64,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, values, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    sor_sweep_t(
        sys,
        nodes_start,
        nodes_end,
        index_base,
        omega,
        components,
        values,
        values_len,
        sweep,
    )
}

/// `f32` twin of [`dk_spring_sor_sweep`].
///
/// # Safety
/// As [`dk_spring_sor_sweep`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_sor_sweep_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    omega: f32,
    components: u32,
    values: *mut f32,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, values, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    sor_sweep_t(
        sys,
        nodes_start,
        nodes_end,
        index_base,
        omega,
        components,
        values,
        values_len,
        sweep,
    )
}

/// The relative residual `‖b − A x‖₂ / ‖b‖₂` of a value field for the linear springs (the
/// measure of `residual_tol` and of the solve report; `b` = the fixed nodes' pull on the free
/// nodes, plain `‖b − A x‖₂` when `b = 0`) into `*residual_out`.
///
/// # Safety
/// As [`dk_spring_solve_linear`]; `values` readable for `values_len` scalars; `residual_out`
/// writable for one scalar.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_relative_residual(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    components: u32,
    values: *const f64,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    residual_out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, values, index_scratch, residual_out) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(residual_out, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    relative_residual_t(sys, components, values, values_len, residual_out)
}

/// `f32` twin of [`dk_spring_relative_residual`].
///
/// # Safety
/// As [`dk_spring_relative_residual`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_relative_residual_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    components: u32,
    values: *const f32,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    residual_out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, values, index_scratch, residual_out) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(residual_out, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    relative_residual_t(sys, components, values, values_len, residual_out)
}

// ---------------------------------------------------------------------------------------------
// Angle-inclusion springs.
// ---------------------------------------------------------------------------------------------

/// Fills `*out` with the default angle-spring settings for f64: direct Gauss–Seidel,
/// `ε` = 0.01, 10 000 iterations, residual tolerance 1e-10, update tolerance off.
///
/// # Safety
/// `out` points to one writable options struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_options_default(
    out: *mut dk_spring_angle_options,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    angle_options_default::<f64>(out)
}

/// As [`dk_spring_angle_options_default`] with the f32 default residual tolerance.
///
/// # Safety
/// As [`dk_spring_angle_options_default`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_options_default_f32(
    out: *mut dk_spring_angle_options,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    angle_options_default::<f32>(out)
}

/// Scalars of `scratch` [`dk_spring_solve_angle`] needs: per node and coordinate, 1 for
/// direct Jacobi, 0 for direct Gauss–Seidel, 4 for CG, and at least 4 whenever
/// `options->epsilon` is 0 (the rigidity probe).
///
/// # Safety
/// `options` points to one readable struct; `len_out` to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_angle_scratch_len(
    node_count: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (options, len_out) = unsafe { (In::new(options, 1), Out::new(len_out, 1)) };
    angle_scratch_scalars::<f64>(node_count, dim, options, len_out)
}

/// `f32` twin of [`dk_spring_solve_angle_scratch_len`] (differs only when `epsilon` rounds to
/// 0 in `float`).
///
/// # Safety
/// As [`dk_spring_solve_angle_scratch_len`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_angle_scratch_len_f32(
    node_count: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (options, len_out) = unsafe { (In::new(options, 1), Out::new(len_out, 1)) };
    angle_scratch_scalars::<f32>(node_count, dim, options, len_out)
}

/// Scalars of `scratch` [`dk_spring_angle_rigidity_probe`] needs: `4 * node_count * dim`.
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_rigidity_probe_scratch_len(
    node_count: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    done((|| {
        if !(2..=3).contains(&dim) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        let items = mul_len(node_count, 4)?;
        write_len(len_out, mul_len(items, dim as usize)?)
    })())
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
///
/// # Safety
/// As [`dk_spring_solve_linear`]; `points` readable for `points_len` scalars.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_angle(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    values: *mut f64,
    values_len: usize,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        points,
        options,
        values,
        scratch,
        index_scratch,
        report,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(options, 1),
            Out::new(values, values_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(report, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    solve_angle_t(
        sys,
        pts,
        dim,
        options,
        values,
        values_len,
        scratch,
        scratch_len,
        report,
    )
}

/// `f32` twin of [`dk_spring_solve_angle`].
///
/// # Safety
/// As [`dk_spring_solve_angle`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_solve_angle_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    values: *mut f32,
    values_len: usize,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        points,
        options,
        values,
        scratch,
        index_scratch,
        report,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(options, 1),
            Out::new(values, values_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(report, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    solve_angle_t(
        sys,
        pts,
        dim,
        options,
        values,
        values_len,
        scratch,
        scratch_len,
        report,
    )
}

/// One Jacobi-order sweep of the angle-spring direct method over the nodes
/// `nodes_start..nodes_end` (read with `index_base`): each free node solves its own 2×2/3×3
/// system with neighbours read from `src`, `dst_i = src_i + A_ii⁻¹ Σ_j B_ij (src_j − src_i)`;
/// fixed nodes in the range are copied, `dst` outside the range is untouched. `*sweep`
/// receives the range's maximum change and the residual of `src`. Nothing is written on
/// error.
///
/// # Safety
/// As [`dk_spring_solve_angle`]; `src` readable for `src_len` scalars; `dst` writable for
/// `dst_len`, not overlapping `src`; `sweep` points to one writable struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_jacobi_sweep(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    epsilon: f64,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    src: *const f64,
    src_len: usize,
    dst: *mut f64,
    dst_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, points, src, dst, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(src, src_len),
            Out::new(dst, dst_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    angle_jacobi_t(
        sys,
        pts,
        dim,
        epsilon,
        nodes_start,
        nodes_end,
        index_base,
        src,
        src_len,
        dst,
        dst_len,
        sweep,
    )
}

/// `f32` twin of [`dk_spring_angle_jacobi_sweep`].
///
/// # Safety
/// As [`dk_spring_angle_jacobi_sweep`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_jacobi_sweep_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    epsilon: f32,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    src: *const f32,
    src_len: usize,
    dst: *mut f32,
    dst_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, points, src, dst, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(src, src_len),
            Out::new(dst, dst_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    angle_jacobi_t(
        sys,
        pts,
        dim,
        epsilon,
        nodes_start,
        nodes_end,
        index_base,
        src,
        src_len,
        dst,
        dst_len,
        sweep,
    )
}

/// One in-place Gauss–Seidel-order sweep of the angle-spring direct method over the nodes
/// `nodes_start..nodes_end` (read with `index_base`): like
/// [`dk_spring_angle_jacobi_sweep`] but each node uses its neighbours' newest values.
/// Nothing is written on error.
///
/// # Safety
/// As [`dk_spring_solve_angle`]; `values` readable and writable for `values_len` scalars;
/// `sweep` points to one writable struct.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_gauss_seidel_sweep(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    epsilon: f64,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    values: *mut f64,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, points, values, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    angle_gs_t(
        sys,
        pts,
        dim,
        epsilon,
        nodes_start,
        nodes_end,
        index_base,
        values,
        values_len,
        sweep,
    )
}

/// `f32` twin of [`dk_spring_angle_gauss_seidel_sweep`].
///
/// # Safety
/// As [`dk_spring_angle_gauss_seidel_sweep`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_gauss_seidel_sweep_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    epsilon: f32,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    values: *mut f32,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    sweep: *mut dk_spring_sweep,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (offsets, targets, stiffness, fixed, points, values, index_scratch, sweep) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(sweep, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    angle_gs_t(
        sys,
        pts,
        dim,
        epsilon,
        nodes_start,
        nodes_end,
        index_base,
        values,
        values_len,
        sweep,
    )
}

/// The rigidity probe of the angle springs: block-Jacobi CG on a deterministic pseudo-random
/// right-hand side; `*amplification_out` receives the amplification (a condition estimate:
/// tens to hundreds for healthy meshes, huge for a near-mechanism; `dk_spring_solve_angle`
/// rejects more than 1e6 when `ε` = 0). Uses `options->epsilon` and the stopping rules
/// (`method` is ignored). `scratch` needs [`dk_spring_angle_rigidity_probe_scratch_len`]
/// scalars. Errors: `DK_ERR_SINGULAR_SYSTEM` (no convergence or non-positive curvature), and
/// those of [`dk_spring_solve_angle`]; nothing is written on error.
///
/// # Safety
/// As [`dk_spring_solve_angle`]; `amplification_out` writable for one scalar.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_rigidity_probe(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    amplification_out: *mut f64,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        points,
        options,
        scratch,
        index_scratch,
        amplification_out,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(options, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(amplification_out, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    probe_t(
        sys,
        pts,
        dim,
        options,
        scratch,
        scratch_len,
        amplification_out,
    )
}

/// `f32` twin of [`dk_spring_angle_rigidity_probe`].
///
/// # Safety
/// As [`dk_spring_angle_rigidity_probe`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_spring_angle_rigidity_probe_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    options: *const dk_spring_angle_options,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    amplification_out: *mut f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        points,
        options,
        scratch,
        index_scratch,
        amplification_out,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(points, points_len),
            In::new(options, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(amplification_out, 1),
        )
    };
    let sys = SysArgs {
        offsets,
        offsets_len,
        targets,
        targets_len,
        stiffness,
        stiffness_len,
        fixed,
        fixed_len,
        index_scratch,
        index_scratch_len,
    };
    let pts = AngleArgs { points, points_len };
    probe_t(
        sys,
        pts,
        dim,
        options,
        scratch,
        scratch_len,
        amplification_out,
    )
}
