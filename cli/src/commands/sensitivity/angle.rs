//! `--method angle` of `deform adjoint` and `deform tangent`: the angle-inclusion springs
//! (`deform move --method angle-cg`: Batina stiffness on the graph with face diagonals,
//! ε = 0.01, CG preconditioned by the linear springs' multigrid), through the kernel's
//! `sensitivity::angle_tangent` / `angle_adjoint`. The map is linear.

use deform_kernel::sensitivity::{
    angle_adjoint, angle_adjoint_scratch_len, angle_tangent, angle_tangent_scratch_len, AngleSolver,
};
use deform_kernel::spring::{AngleSystem, LinearSolver, SolveOptions, DEFAULT_ANGLE_EPSILON};

use super::{converged, kernel, with_springs, Solved};
use crate::args::SensitivitySetup;
use crate::engine::points_d;
use crate::error::CliError;
use crate::formats::su2::Su2Mesh;

/// Runs `f` with the angle system and its multigrid solver.
fn with_angle<const D: usize, R>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    f: impl FnOnce(
        &AngleSystem<'_, f64, D>,
        AngleSolver<'_, f64>,
        &SolveOptions<f64>,
    ) -> Result<R, CliError>,
) -> Result<R, CliError> {
    let points = points_d::<D>(&mesh.points);
    with_springs::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
        let LinearSolver::Amg(h) = solver else {
            return Err(CliError::Invalid(
                "the angle springs need the multigrid".into(),
            ));
        };
        let asys = AngleSystem::new(*sys, &points, DEFAULT_ANGLE_EPSILON)
            .map_err(kernel("angle springs"))?;
        f(&asys, AngleSolver::Amg(h), stop)
    })
}

/// `Jᵀ w`.
pub(super) fn adjoint<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    with_angle::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
        let mut g = vec![[0.0; D]; w.len()];
        let mut s = vec![[0.0; D]; angle_adjoint_scratch_len(sys, &solver)];
        let r =
            angle_adjoint(sys, solver, stop, w, &mut g, &mut s).map_err(kernel("angle adjoint"))?;
        Ok((g, Some(converged(r)?)))
    })
}

/// `J v` (`dx` holds `v` at the boundary).
pub(super) fn tangent<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    mut dx: Vec<[f64; D]>,
) -> Result<Solved<D>, CliError> {
    with_angle::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
        let mut s = vec![[0.0; D]; angle_tangent_scratch_len(sys, &solver)];
        let r =
            angle_tangent(sys, solver, stop, &mut dx, &mut s).map_err(kernel("angle tangent"))?;
        Ok((dx, Some(converged(r)?)))
    })
}
