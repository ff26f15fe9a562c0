//! The method options of `deform adjoint` and `deform tangent`, checked before any file is
//! read: an option the chosen method does not take is refused, never ignored (a derivative of
//! another map than the one asked for would be a wrong answer that looks right).

use crate::args::{SensitivityMethod, SensitivitySetup, StiffnessArg};
use crate::error::CliError;
use crate::report::value_name;

/// `deform move`'s Poisson ratio default.
pub(super) const DEFAULT_POISSON: f64 = 0.3;

/// An option refused for the chosen method.
fn only(flag: &str, methods: &str, method: SensitivityMethod) -> Result<(), CliError> {
    Err(CliError::Invalid(format!(
        "{flag} applies to --method {methods}, not --method {}",
        value_name(&method)
    )))
}

/// Whether `--deformed` (the linearisation point) means anything for this method and steps.
pub(super) fn nonlinear(setup: &SensitivitySetup) -> bool {
    match setup.method() {
        SensitivityMethod::Quaternion | SensitivityMethod::Idw | SensitivityMethod::Rbf => true,
        SensitivityMethod::Elasticity => setup.steps > 1,
        _ => false,
    }
}

/// `--method tfi` or `tfi-displacement` on an SU2 mesh.
pub(super) fn tfi_on_su2() -> CliError {
    CliError::NotAvailable {
        feature: "transfinite interpolation on SU2 meshes",
        needs: "a structured Plot3D grid with --wall (TFI interpolates along grid lines)",
    }
}

/// Refuses the options the method does not take and out-of-range values (SU2 meshes).
pub(super) fn check(setup: &SensitivitySetup) -> Result<(), CliError> {
    let m = setup.method();
    if matches!(
        m,
        SensitivityMethod::Tfi | SensitivityMethod::TfiDisplacement
    ) {
        return Err(tfi_on_su2());
    }
    if setup.grid.any() {
        return Err(CliError::Invalid(
            "--wall, --rotate, --translate, --axis and --center set the motion of a Plot3D \
             grid's TFI; on an SU2 mesh the linearisation point is --deformed"
                .into(),
        ));
    }
    if setup.deformed.is_some() && !nonlinear(setup) {
        return Err(CliError::Invalid(
            "--deformed is the linearisation point of --method quaternion, idw, rbf and \
             elasticity with --steps above 1; this map is linear"
                .into(),
        ));
    }
    check_idw(setup)?;
    check_amg_strength(setup)?;
    if m == SensitivityMethod::Elasticity {
        return check_elasticity(setup);
    }
    if setup.stiffness.is_some() {
        return only(
            "--stiffness",
            "elasticity (the spring methods are differentiated with Batina stiffness)",
            m,
        );
    }
    if setup.poisson.is_some() {
        return only("--poisson", "elasticity", m);
    }
    if setup.steps != 1 {
        return only("--steps", "elasticity", m);
    }
    if !setup.wall_markers.is_empty() {
        return only("--wall-markers", "elasticity", m);
    }
    Ok(())
}

/// `--amg-strength`: in [0, 1), for the methods whose solves use the multigrid.
fn check_amg_strength(setup: &SensitivitySetup) -> Result<(), CliError> {
    let Some(theta) = setup.amg_strength else {
        return Ok(());
    };
    if matches!(
        setup.method(),
        SensitivityMethod::Idw
            | SensitivityMethod::IdwDisplacements
            | SensitivityMethod::Rbf
            | SensitivityMethod::Elasticity
    ) {
        return only(
            "--amg-strength",
            "spring, quaternion or angle",
            setup.method(),
        );
    }
    if !(theta.is_finite() && (0.0..1.0).contains(&theta)) {
        return Err(CliError::Invalid("--amg-strength must be in [0, 1)".into()));
    }
    Ok(())
}

/// `--idw-theta`, `--idw-tolerance`, `--idw-exponent`.
fn check_idw(setup: &SensitivitySetup) -> Result<(), CliError> {
    if let Some(theta) = setup.idw_theta {
        if setup.method() != SensitivityMethod::Idw {
            return only("--idw-theta", "idw", setup.method());
        }
        if !(0.0..1.0).contains(&theta) {
            return Err(CliError::Invalid("--idw-theta must be in [0, 1)".into()));
        }
        if setup.idw_tolerance.is_nan() || setup.idw_tolerance < 0.0 {
            return Err(CliError::Invalid(
                "--idw-tolerance must be a non-negative number (inf: θ alone)".into(),
            ));
        }
    }
    if !(setup.idw_exponent.is_finite() && setup.idw_exponent > 0.0) {
        return Err(CliError::Invalid(
            "--idw-exponent must be finite and positive".into(),
        ));
    }
    Ok(())
}

/// The elasticity options: `deform move --method elasticity`'s, with its refusals.
fn check_elasticity(setup: &SensitivitySetup) -> Result<(), CliError> {
    let stiffness = setup.stiffness.unwrap_or(StiffnessArg::InverseVolume);
    if stiffness == StiffnessArg::Batina {
        return Err(CliError::Invalid(
            "--stiffness batina is a spring stiffness; --method elasticity takes \
             inverse-volume, wall-distance or constant"
                .into(),
        ));
    }
    let wall = stiffness == StiffnessArg::WallDistance;
    if wall && setup.wall_markers.is_empty() {
        return Err(CliError::Invalid(
            "--stiffness wall-distance needs --wall-markers: the markers `deform move --marker` \
             moved (the distances are measured to their nodes)"
                .into(),
        ));
    }
    if !wall && !setup.wall_markers.is_empty() {
        return Err(CliError::Invalid(
            "--wall-markers applies to --stiffness wall-distance".into(),
        ));
    }
    crate::commands::r#move::check_poisson(setup.poisson.unwrap_or(DEFAULT_POISSON))
}
