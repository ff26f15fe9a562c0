//! Sensitivities of the quaternion deformation with inverse-distance propagation
//! (`dk_deform_idw`): the tangent `dk_deform_idw_tangent` (`δR = (∂R/∂d) δd`) and the adjoint
//! `dk_deform_idw_adjoint` (`d̄ = (∂R/∂d)ᵀ w`, the boundary sensitivity `dJ/dd` from a volume
//! sensitivity `w = dJ/dR`), the kernel's `deform_idw_tangent` / `deform_idw_adjoint`. The
//! motion travels in the same [`dk_boundary_motion`](crate::deformation::dk_boundary_motion)
//! as for the deformation, with the same index rules; see docs/sensitivities-quaternion.md
//! for the derivation. The same two for the spring propagation (`dk_deform_spring`):
//! `dk_deform_spring_tangent`, `dk_deform_spring_adjoint` (docs/sensitivities.md), and for the
//! transfinite interpolation of a structured block (`dk_deform_tfi`): `dk_deform_tfi_tangent`,
//! `dk_deform_tfi_adjoint`.

use deform_kernel::quaternion::{
    deform_idw_adjoint, deform_idw_sensitivity_scratch_len, deform_idw_tangent,
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
};
use deform_kernel::spring::LinearSolver;
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{block, by_dim, done, read_one, read_points, write_len, Dim};
use crate::deformation::{read_raw, tfi_setup, DkBoundaryMotion, MotionC};
use crate::slice::{chunks, chunks_mut, out_one, output, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report, DkSpringSystem, SystemC};
use crate::status::dk_status;

/// The two modes of [`sensitivity_for_dim`].
#[derive(Clone, Copy)]
enum Mode {
    Tangent,
    Adjoint,
}

/// Reads the arguments and runs one mode in dimension `D`.
#[allow(clippy::too_many_arguments)]
fn sensitivity_for_dim<M: MotionC, const D: usize>(
    mode: Mode,
    points: In<'_, M::T>,
    motion: In<'_, M>,
    exponent: M::T,
    input: In<'_, M::T>,
    scratch: Out<'_, M::T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, M::T>,
) -> Result<(), dk_status> {
    let raw = read_raw(motion)?;
    let points = read_points::<M::T, D>(points)?;
    let input = chunks::<M::T, D>(input)?;
    let scratch = output(scratch)?;
    let index_scratch = output(index_scratch)?;
    let out = chunks_mut::<M::T, D>(out)?;
    let (motion, _) = raw.view::<D>(index_scratch)?;
    match mode {
        Mode::Tangent => deform_idw_tangent(points, &motion, exponent, input, scratch, out),
        Mode::Adjoint => deform_idw_adjoint(points, &motion, exponent, input, scratch, out),
    }
    .map_err(dk_status::from)
}

/// Number of scalars the `scratch` of [`dk_deform_idw_tangent`] and [`dk_deform_idw_adjoint`]
/// needs for `node_count` mesh nodes and `boundary_len` boundary nodes in dimension `dim` (2
/// or 3): `max(node_count, 32 boundary_len)` (the kernel's
/// `deform_idw_sensitivity_scratch_len`). The same for both precisions. Errors:
/// `DK_ERR_INVALID_PARAMETER` (`dim` not 2 or 3).
#[export(len_out[1])]
pub(crate) fn dk_deform_idw_sensitivity_scratch_len(
    node_count: usize,
    boundary_len: usize,
    dim: u32,
    len_out: Out<'_, usize>,
) -> dk_status {
    done(match dim {
        2 => write_len(
            len_out,
            deform_idw_sensitivity_scratch_len::<2>(node_count, boundary_len),
        ),
        3 => write_len(
            len_out,
            deform_idw_sensitivity_scratch_len::<3>(node_count, boundary_len),
        ),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    })
}

/// Tangent of [`dk_deform_idw`](crate::deformation::dk_deform_idw): the first-order change
/// `out = δR` of every mesh point (`N * dim` scalars) for the change `direction = δd` of the
/// deformed boundary positions (`B * dim` scalars, in `motion->nodes` order), the undeformed
/// `points` held; boundary nodes get `δd` exactly. Held constant: the weights, the origin
/// (given, or the centroid of the undeformed moving points), rigid and per-node rotations.
///
/// - `points`, `dim`, `motion`, `exponent`, `index_scratch`: as for `dk_deform_idw`.
/// - `scratch`: [`dk_deform_idw_sensitivity_scratch_len`] scalars.
///
/// Errors: those of `dk_deform_idw`; `DK_ERR_NON_FINITE` for a non-finite `direction`;
/// `DK_ERR_ZERO_LENGTH` where (3D shape rotations) a point's undeformed and deformed normals
/// are antiparallel (no derivative). On error `out` is unchanged.
#[export(twin, motion[1])]
pub(crate) fn dk_deform_idw_tangent<T: Real>(
    points: In<'_, T>,
    dim: u32,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    direction: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> dk_status {
    done(by_dim!(
        dim,
        sensitivity_for_dim::<DkBoundaryMotion<T>>,
        (
            Mode::Tangent,
            points,
            motion,
            exponent,
            direction,
            scratch,
            index_scratch,
            out
        )
    ))
}

/// Adjoint of [`dk_deform_idw`](crate::deformation::dk_deform_idw), the transpose of
/// [`dk_deform_idw_tangent`]: `out = (∂R/∂d)ᵀ w` (`B * dim` scalars, in `motion->nodes`
/// order) for `weights = w = dJ/dR` (`N * dim` scalars, e.g. a flow adjoint's volume
/// sensitivity): the sensitivity of `J` to the deformed boundary positions.
///
/// Arguments and errors as for [`dk_deform_idw_tangent`], with `weights` (finite) in place of
/// `direction`. On error `out` is unchanged.
#[export(twin, motion[1])]
pub(crate) fn dk_deform_idw_adjoint<T: Real>(
    points: In<'_, T>,
    dim: u32,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    weights: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> dk_status {
    done(by_dim!(
        dim,
        sensitivity_for_dim::<DkBoundaryMotion<T>>,
        (
            Mode::Adjoint,
            points,
            motion,
            exponent,
            weights,
            scratch,
            index_scratch,
            out
        )
    ))
}

/// Reads the arguments of [`dk_deform_spring_tangent`] / [`dk_deform_spring_adjoint`] and
/// runs one mode in dimension `D`.
#[allow(clippy::too_many_arguments)]
fn spring_sensitivity_for_dim<M: MotionC, const D: usize>(
    mode: Mode,
    points: In<'_, M::T>,
    motion: In<'_, M>,
    system: In<'_, DkSpringSystem<M::T>>,
    options: In<'_, dk_spring_solve_options>,
    input: In<'_, M::T>,
    bufs: (Out<'_, M::T>, Out<'_, u32>, Out<'_, M::T>),
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let (scratch, index_scratch, out) = bufs;
    let o = read_one(options)?;
    let solver = LinearSolver::Method(o.method::<M::T>()?);
    let stop = o.stopping::<M::T>();
    let raw = read_raw(motion)?;
    let points = read_points::<M::T, D>(points)?;
    let input = chunks::<M::T, D>(input)?;
    let scratch = output(scratch)?;
    let out = chunks_mut::<M::T, D>(out)?;
    let report = out_one(report)?;
    let (motion, rest) = raw.view::<D>(output(index_scratch)?)?;
    let sys = SystemC::read(system)?.build(rest)?;
    let (m, s) = (&motion, &sys);
    let rep = match mode {
        Mode::Tangent => deform_spring_tangent(points, m, s, solver, &stop, input, scratch, out),
        Mode::Adjoint => deform_spring_adjoint(points, m, s, solver, &stop, input, scratch, out),
    }?;
    *report = dk_spring_solve_report::of(rep);
    Ok(())
}

/// Number of scalars the `scratch` of [`dk_deform_spring_tangent`] and
/// [`dk_deform_spring_adjoint`] needs for `node_count` mesh nodes, `boundary_len` boundary
/// nodes, dimension `dim` (2 or 3) and `options->method` (the kernel's
/// `deform_spring_sensitivity_scratch_len`: two packed fields of `dim + 4` scalars a node, the
/// boundary stage and the solver's). `index_scratch` needs
/// [`dk_deform_spring_index_scratch_len`](crate::deformation::dk_deform_spring_index_scratch_len)
/// entries, as for `dk_deform_spring`. The same for both precisions. Errors:
/// `DK_ERR_INVALID_PARAMETER` (`dim`, method), `DK_ERR_TOO_LARGE`.
#[export(options[1], len_out[1])]
pub(crate) fn dk_deform_spring_sensitivity_scratch_len(
    node_count: usize,
    boundary_len: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> dk_status {
    done((|| {
        let solver = LinearSolver::Method(read_one(options)?.method::<f64>()?);
        let len = match dim {
            2 => deform_spring_sensitivity_scratch_len::<f64, 2>(&solver, node_count, boundary_len),
            3 => deform_spring_sensitivity_scratch_len::<f64, 3>(&solver, node_count, boundary_len),
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        if len == usize::MAX {
            return Err(dk_status::DK_ERR_TOO_LARGE);
        }
        write_len(len_out, len)
    })())
}

/// Tangent of [`dk_deform_spring`](crate::deformation::dk_deform_spring) (the quaternion
/// method with linear-spring propagation): the first-order change `out = δR` of every mesh
/// point (`N * dim` scalars) for the change `direction = δd` of the deformed boundary
/// positions (`B * dim` scalars, in `motion->nodes` order), the undeformed `points` held;
/// boundary nodes get `δd` exactly. It repeats the deformation's spring solve and solves once
/// more with the same operator and `options`, so the result is the derivative to the solver
/// tolerance (set it tight). `*report` receives the merged report of the two solves (not
/// converged is `DK_OK` with `converged` false).
///
/// - `points`, `dim`, `motion`, `system`, `options`, `index_scratch`: as for
///   `dk_deform_spring`.
/// - `scratch`: [`dk_deform_spring_sensitivity_scratch_len`] scalars.
///
/// Errors: those of `dk_deform_spring`; `DK_ERR_NON_FINITE` for a non-finite `direction`;
/// `DK_ERR_ZERO_LENGTH` where (3D shape rotations) a point's undeformed and deformed normals
/// are antiparallel. On error `out` and `*report` are unchanged.
#[export(twin, motion[1], system[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_spring_tangent<T: Real>(
    points: In<'_, T>,
    dim: u32,
    motion: In<'_, DkBoundaryMotion<T>>,
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    direction: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> dk_status {
    let bufs = (scratch, index_scratch, out);
    done(by_dim!(
        dim,
        spring_sensitivity_for_dim::<DkBoundaryMotion<T>>,
        (
            Mode::Tangent,
            points,
            motion,
            system,
            options,
            direction,
            bufs,
            report
        )
    ))
}

/// Adjoint of [`dk_deform_spring`](crate::deformation::dk_deform_spring), the transpose of
/// [`dk_deform_spring_tangent`]: `out = (∂R/∂d)ᵀ w` (`B * dim` scalars, in `motion->nodes`
/// order) for `weights = w = dJ/dR` (`N * dim` scalars, e.g. a flow adjoint's volume
/// sensitivity). The adjoint solve has the deformation's operator (symmetric) and
/// preconditioner; `options->method` must be `DK_LINEAR_CG`.
///
/// Arguments and errors as for [`dk_deform_spring_tangent`], with `weights` (finite) in place
/// of `direction`, and `DK_ERR_INVALID_PARAMETER` for a method other than CG. On error `out`
/// and `*report` are unchanged.
#[export(twin, motion[1], system[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_spring_adjoint<T: Real>(
    points: In<'_, T>,
    dim: u32,
    motion: In<'_, DkBoundaryMotion<T>>,
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    weights: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> dk_status {
    let bufs = (scratch, index_scratch, out);
    done(by_dim!(
        dim,
        spring_sensitivity_for_dim::<DkBoundaryMotion<T>>,
        (
            Mode::Adjoint,
            points,
            motion,
            system,
            options,
            weights,
            bufs,
            report
        )
    ))
}

/// Number of scalars the `scratch` of [`dk_deform_tfi_tangent`] and [`dk_deform_tfi_adjoint`]
/// needs for a `ni × nj × nk` block with `boundary_len` boundary nodes in dimension `dim`:
/// `max(N, 32 boundary_len) + (dim + 11) N`, `N = ni nj nk` (the kernel's
/// `deform_tfi_sensitivity_scratch_len`). The same for both precisions. Errors:
/// `DK_ERR_BAD_DIMENSIONS` (a zero dimension, too many points), `DK_ERR_INVALID_PARAMETER`
/// (`dim` not 2 or 3).
#[export(len_out[1])]
pub(crate) fn dk_deform_tfi_sensitivity_scratch_len<const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    boundary_len: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    write_len(
        len_out,
        deform_tfi_sensitivity_scratch_len::<D>(&b, boundary_len),
    )
}

/// Reads the arguments of [`dk_deform_tfi_tangent`] / [`dk_deform_tfi_adjoint`] and runs one
/// mode.
#[allow(clippy::too_many_arguments)]
fn tfi_sensitivity<T: Real, const D: usize>(
    mode: Mode,
    dims: [usize; 3],
    directions: u32,
    points: In<'_, T>,
    motion: In<'_, DkBoundaryMotion<T>>,
    input: In<'_, T>,
    bufs: (Out<'_, T>, Out<'_, u32>, Out<'_, T>),
) -> Result<(), dk_status> {
    let (scratch, index_scratch, out) = bufs;
    let (block, directions) = tfi_setup(dims[0], dims[1], dims[2], directions)?;
    let raw = read_raw(motion)?;
    let points = read_points::<T, D>(points)?;
    let input = chunks::<T, D>(input)?;
    let scratch = output(scratch)?;
    let out = chunks_mut::<T, D>(out)?;
    let (motion, _) = raw.view::<D>(output(index_scratch)?)?;
    let (b, m) = (&block, &motion);
    match mode {
        Mode::Tangent => deform_tfi_tangent(b, directions, points, m, input, scratch, out),
        Mode::Adjoint => deform_tfi_adjoint(b, directions, points, m, input, scratch, out),
    }
    .map_err(dk_status::from)
}

/// Tangent of [`dk_deform_tfi`](crate::deformation::dk_deform_tfi): the first-order change
/// `out = δR` of every block point (`N * dim` scalars) for the change `direction = δd` of the
/// deformed boundary positions (`B * dim` scalars, in `motion->nodes` order), the undeformed
/// `points` held; listed nodes get `δd` exactly. Held constant: the blending weights (the
/// undeformed arclengths), the origin (given, or the centroid of the undeformed moving
/// points), rigid and per-node rotations, the hemisphere signs.
///
/// - `ni`, `nj`, `nk`, `directions`, `points`, `dim`, `motion`, `index_scratch`: as for
///   `dk_deform_tfi`.
/// - `scratch`: [`dk_deform_tfi_sensitivity_scratch_len`] scalars.
///
/// Errors: those of `dk_deform_tfi`; `DK_ERR_NON_FINITE` for a non-finite `direction`;
/// `DK_ERR_ZERO_LENGTH` where (3D shape rotations) a point's undeformed and deformed normals
/// are antiparallel, or a blended rotation cancels. On error `out` is unchanged.
#[export(twin, motion[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_tfi_tangent<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    direction: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let bufs = (scratch, index_scratch, out);
    let dims = [ni, nj, nk];
    tfi_sensitivity::<T, D>(
        Mode::Tangent,
        dims,
        directions,
        points,
        motion,
        direction,
        bufs,
    )
}

/// Adjoint of [`dk_deform_tfi`](crate::deformation::dk_deform_tfi), the transpose of
/// [`dk_deform_tfi_tangent`]: `out = (∂R/∂d)ᵀ w` (`B * dim` scalars, in `motion->nodes`
/// order) for `weights = w = dJ/dR` (`N * dim` scalars).
///
/// Arguments and errors as for [`dk_deform_tfi_tangent`], with `weights` (finite) in place of
/// `direction`. On error `out` is unchanged.
#[export(twin, motion[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_tfi_adjoint<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    weights: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let bufs = (scratch, index_scratch, out);
    let dims = [ni, nj, nk];
    tfi_sensitivity::<T, D>(
        Mode::Adjoint,
        dims,
        directions,
        points,
        motion,
        weights,
        bufs,
    )
}
