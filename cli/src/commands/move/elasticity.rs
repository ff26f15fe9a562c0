//! `deform move --method elasticity`: its own arguments (--stiffness, --poisson, --steps,
//! which solvers apply) and the run.

use crate::args::{Method, MoveArgs, Solver, StiffnessArg};
use crate::engine::{run_elasticity, MoveInput, MoveResult, SlideMarker};
use crate::error::CliError;
use crate::report::value_name;
use deform_kernel::elasticity::Modulus;

/// Refuses what elasticity does not take (and `--stiffness constant` elsewhere).
pub(super) fn check_args(a: &MoveArgs) -> Result<(), CliError> {
    let elasticity = a.method() == Method::Elasticity;
    if !elasticity {
        if a.stiffness == Some(StiffnessArg::Constant) {
            return Err(CliError::Invalid(format!(
                "--stiffness constant applies to --method elasticity; --method {} takes batina, wall-distance or inverse-volume",
                value_name(&a.method())
            )));
        }
        if a.rigid_layer.is_some() {
            return Err(CliError::Invalid(format!(
                "--rigid-layer applies to --method elasticity, not --method {}",
                value_name(&a.method())
            )));
        }
        return Ok(());
    }
    if let Some(t) = a.rigid_layer {
        if !(t.is_finite() && t >= 0.0) {
            return Err(CliError::Invalid(
                "--rigid-layer must be a finite distance, not negative".into(),
            ));
        }
    }
    if a.stiffness() == StiffnessArg::Batina {
        return Err(CliError::Invalid(
            "--stiffness batina is a spring stiffness; --method elasticity takes inverse-volume, wall-distance or constant".into(),
        ));
    }
    check_poisson(a.poisson)?;
    if a.reach.is_some() || !matches!(a.solver, Solver::Amg | Solver::Cg) {
        return Err(CliError::Invalid(format!(
            "--method elasticity takes --solver amg or cg{}",
            if a.reach.is_some() {
                " and no --reach"
            } else {
                ""
            }
        )));
    }
    Ok(())
}

/// `--poisson` (also of `deform adjoint`/`tangent --method elasticity`).
pub(crate) fn check_poisson(poisson: f64) -> Result<(), CliError> {
    if !(poisson.is_finite() && poisson > -1.0 && poisson != 0.5) {
        return Err(CliError::Invalid(
            "--poisson must be finite, above -1 and not 0.5 ((-1, 0.5) is the stable range; \
             above 0.5 is SU2's DEFORM_COEFF convention)"
                .into(),
        ));
    }
    Ok(())
}

/// Runs the elasticity method with the command line's modulus, Poisson ratio and steps; the
/// nodes of the `slide` markers slide on their planes.
pub(super) fn run(
    a: &MoveArgs,
    input: &MoveInput<'_>,
    slide: &[SlideMarker<'_>],
) -> Result<MoveResult, CliError> {
    let modulus = match a.stiffness() {
        StiffnessArg::WallDistance => Modulus::WallDistance,
        StiffnessArg::Constant => Modulus::Constant,
        StiffnessArg::InverseVolume | StiffnessArg::Batina => Modulus::InverseVolume,
    };
    run_elasticity(
        input,
        slide,
        modulus,
        (a.poisson, a.rigid_layer),
        a.steps as usize,
    )
}
