//! Mesh sensitivities (the kernel's `sensitivity` module): the adjoint of the linear springs
//! (`dk_sensitivity_spring_adjoint_scratch_len`, `dk_sensitivity_spring_adjoint`) and the
//! tangent and adjoint of inverse-distance weighting of displacements
//! (`dk_sensitivity_idw_tangent`, `dk_sensitivity_idw_adjoint`). The springs' tangent is
//! `dk_spring_solve_linear` itself with the boundary perturbation as the fixed values (the
//! map is linear). See docs/sensitivities.md.
//!
//! Boundary nodes are read in `index_base` 0 or 1; with 1 the 0-based copy goes to the
//! caller's `uint32_t` `index_scratch` (`boundary_len` entries; NULL with 0 for base 0).

use deform_kernel::sensitivity::{
    idw_adjoint_many, idw_tangent_many, spring_adjoint, spring_adjoint_scratch_len,
};
use deform_kernel::spring::LinearSolver;
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{by_components, by_dim, done, mul_len, read_one, rebase, write_len};
use crate::slice::{chunks, chunks_mut, input, out_one, output, whole_chunks_mut, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report, DkSpringSystem, SystemC};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Scalars of `scratch` [`dk_sensitivity_spring_adjoint`] needs for `node_count` nodes,
/// `components` (1 to 7) and `options->method` (which must be `DK_LINEAR_CG`, else
/// `DK_ERR_INVALID_PARAMETER`): `components · (5 n + ⌈n / components⌉)` (the adjoint field,
/// the four CG vectors, the diagonal). The same for both precisions.
#[export(options[1], len_out[1])]
pub(crate) fn dk_sensitivity_spring_adjoint_scratch_len(
    node_count: usize,
    components: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        let solver = LinearSolver::Method(o.method::<f64>()?);
        let items = by_components!(components, adjoint_items::<f64>, (&solver, node_count))?;
        write_len(len_out, mul_len(items, components as usize)?)
    })())
}

/// The adjoint of the linear springs: for `w = dJ/dx` at every node (`node_count ·
/// components` scalars, node-major), `g = dJ/dx_b` at the fixed nodes and zero at the free
/// nodes, `(D − K_ff) λ = w_f`, `g_j = w_j + Σ_{i free} k_ij λ_i`: one CG solve with the
/// deformation's own operator and preconditioner (`options`: `DK_LINEAR_CG` only) on the
/// right-hand side `w_f`. `scratch`: [`dk_sensitivity_spring_adjoint_scratch_len`] scalars;
/// `index_scratch`: `node_count` entries (the system's validation); `*report` receives the
/// solve's report (not converged is `DK_OK` with `converged` false).
///
/// Errors: those of `dk_spring_solve_linear`, `DK_ERR_INVALID_PARAMETER` for a method other
/// than CG; on error `g` is unchanged.
#[export(twin, system[1], options[1], report[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_spring_adjoint<T: Real>(
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    components: u32,
    w: In<'_, T>,
    g: Out<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    report: Out<'_, dk_spring_solve_report>,
) -> dk_status {
    done((|| {
        let o = read_one(options)?;
        let sys = SystemC::read(system)?.build(output(index_scratch)?)?;
        let args = (&sys, &o, w, g, scratch, report);
        by_components!(components, adjoint_for_components::<T>, (args))
    })())
}

/// The tangent of inverse-distance weighting of displacements for `m` fields back to back in
/// `dx` (`m · N · dim` scalars): on entry each holds `δx_b` at the boundary nodes (other
/// entries ignored); on success every other node holds `Σ_k ω_ik δx_k / Σ_k ω_ik`, `ω_ik =
/// (d_min / d_ik)^exponent` on the undeformed `points` (`N · dim`, `dim` 2 or 3), as
/// `dk_deform_idw` weighs its translations. Errors: pointer and length errors,
/// `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_NON_FINITE`,
/// `DK_ERR_INVALID_PARAMETER` (no boundary node, bad exponent); on error `dx` is unchanged.
#[export(twin)]
pub(crate) fn dk_sensitivity_idw_tangent<T: Real>(
    points: In<'_, T>,
    dim: u32,
    boundary: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    exponent: T,
    dx: Out<'_, T>,
) -> dk_status {
    done((|| {
        let b = input(boundary)?;
        let (b, _) = rebase(b, index_base, output(index_scratch)?)?;
        by_dim!(dim, idw_tangent_for_dim::<T>, (points, b, exponent, dx))
    })())
}

/// The adjoint of [`dk_sensitivity_idw_tangent`] for `m` fields `w` back to back (`m · N ·
/// dim` scalars): `g` (as long) receives `g_k = w_k + Σ_i w_i ω_ik / Σ_j ω_ij` at the
/// boundary nodes and zero elsewhere. Errors as [`dk_sensitivity_idw_tangent`]; on error `g`
/// is unchanged.
#[export(twin)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_idw_adjoint<T: Real>(
    points: In<'_, T>,
    dim: u32,
    boundary: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    exponent: T,
    w: In<'_, T>,
    g: Out<'_, T>,
) -> dk_status {
    done((|| {
        let b = input(boundary)?;
        let (b, _) = rebase(b, index_base, output(index_scratch)?)?;
        by_dim!(dim, idw_adjoint_for_dim::<T>, (points, b, exponent, w, g))
    })())
}

// ---------------------------------------------------------------------------------------------
// Generic inner functions.
// ---------------------------------------------------------------------------------------------

fn adjoint_items<T: Real, const V: usize>(
    solver: &LinearSolver<'_, T>,
    n: usize,
) -> Result<usize, dk_status> {
    match spring_adjoint_scratch_len::<T, V>(solver, n) {
        usize::MAX => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        items => Ok(items),
    }
}

type AdjointArgs<'a, 's, T> = (
    &'s deform_kernel::spring::SpringSystem<'a, T>,
    &'s dk_spring_solve_options,
    In<'a, T>,
    Out<'a, T>,
    Out<'a, T>,
    Out<'a, dk_spring_solve_report>,
);

fn adjoint_for_components<T: Real, const V: usize>(
    (sys, o, w, g, scratch, report): AdjointArgs<'_, '_, T>,
) -> Result<(), dk_status> {
    let solver = LinearSolver::Method(o.method::<T>()?);
    let stop = o.stopping::<T>();
    let w = chunks::<T, V>(w)?;
    let g = chunks_mut::<T, V>(g)?;
    let s = whole_chunks_mut::<T, V>(scratch)?;
    let r = out_one(report)?;
    let rep = spring_adjoint(sys, solver, &stop, w, g, s)?;
    *r = dk_spring_solve_report::of(rep);
    Ok(())
}

fn idw_tangent_for_dim<T: Real, const D: usize>(
    points: In<'_, T>,
    boundary: &[u32],
    exponent: T,
    dx: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = chunks::<T, D>(points)?;
    let dx = chunks_mut::<T, D>(dx)?;
    idw_tangent_many(p, boundary, exponent, dx).map_err(dk_status::from)
}

fn idw_adjoint_for_dim<T: Real, const D: usize>(
    points: In<'_, T>,
    boundary: &[u32],
    exponent: T,
    w: In<'_, T>,
    g: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = chunks::<T, D>(points)?;
    let w = chunks::<T, D>(w)?;
    let g = chunks_mut::<T, D>(g)?;
    idw_adjoint_many(p, boundary, exponent, w, g).map_err(dk_status::from)
}
