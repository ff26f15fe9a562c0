//! The adjoint of the angle-inclusion springs (the kernel's `sensitivity::angle_adjoint`):
//! `dk_sensitivity_angle_adjoint_scratch_len`, `dk_sensitivity_angle_adjoint`. The tangent is
//! `dk_spring_solve_angle` itself with the boundary perturbation as the fixed values (the map
//! is linear). See docs/sensitivities.md.

use deform_kernel::sensitivity::{angle_adjoint, angle_adjoint_scratch_items, AngleSolver};
use deform_kernel::spring::AngleSystem;
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{mul_len, read_one, read_points, write_len, Dim};
use crate::slice::{chunks, chunks_mut, out_one, output, whole_chunks_mut, In, Out};
use crate::spring::{dk_spring_angle_options, dk_spring_solve_report, DkSpringSystem, SystemC};
use crate::status::dk_status;

/// Scalars of `scratch` [`dk_sensitivity_angle_adjoint`] needs for `node_count` nodes in
/// `dim` (2 or 3) dimensions: `5 · node_count · dim` (the adjoint field and the four CG
/// vectors, which also hold the rigidity probe's when `ε = 0`).
#[export(len_out[1])]
pub(crate) fn dk_sensitivity_angle_adjoint_scratch_len<const D: usize>(
    node_count: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let items = angle_adjoint_scratch_items(node_count).ok_or(dk_status::DK_ERR_TOO_LARGE)?;
    write_len(len_out, mul_len(items, D)?)
}

/// The adjoint of the angle-inclusion springs (`dk_spring_solve_angle`'s system, `points`
/// and `options`): for `w = dJ/dx` at every node (`node_count · dim` scalars), `g = dJ/dx_b`
/// at the fixed nodes and zero at the free nodes: `A λ = w_f`, `g_j = w_j + Σ_{i free} B_ij
/// λ_i`, one block-Jacobi CG solve with the deformation's own operator (symmetric) and
/// stopping rule (`options->method` must be `DK_ANGLE_CG`, else `DK_ERR_INVALID_PARAMETER`;
/// with `epsilon` 0 the rigidity probe runs first). `scratch`:
/// [`dk_sensitivity_angle_adjoint_scratch_len`] scalars; `index_scratch`: `node_count`
/// entries; `*report` receives the solve's report (not converged is `DK_OK` with `converged`
/// false). Errors: those of `dk_spring_solve_angle`; on error `g` is unchanged.
#[export(twin, system[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_angle_adjoint<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    points: In<'_, T>,
    _dim: Dim<D>,
    options: In<'_, dk_spring_angle_options>,
    w: In<'_, T>,
    g: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let sys = SystemC::read(system)?.build(output(index_scratch)?)?;
    let p = read_points::<T, D>(points)?;
    let asys = AngleSystem::new(sys, p, T::from_f64(o.epsilon))?;
    let (w, g) = (chunks::<T, D>(w)?, chunks_mut::<T, D>(g)?);
    let (s, r) = (whole_chunks_mut::<T, D>(scratch)?, out_one(report)?);
    let solver = AngleSolver::Method(o.method()?);
    let rep = angle_adjoint(&asys, solver, &o.stopping::<T>(), w, g, s)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}
