//! The arguments of `deform move`, checked before anything is read or written (in the order
//! the errors were always reported).

use crate::args::{Coords, Method, MoveArgs, Solver, StiffnessArg};
use crate::error::CliError;
use crate::files::{file_kind, is_cgns_path, FileKind};
use crate::report::value_name;

/// The method against the kind of input (`su2`: an SU2 mesh, else a Plot3D grid).
pub(super) fn check_method(a: &MoveArgs, su2: bool) -> Result<(), CliError> {
    let tfi = matches!(a.method(), Method::Tfi | Method::TfiDisplacement);
    crate::args::check_rbf_args(&a.rbf, a.method() == Method::Rbf)?;
    if a.stiffness() != StiffnessArg::Batina
        && (tfi || matches!(a.method(), Method::Idw | Method::Rbf))
    {
        return Err(CliError::Invalid(format!(
            "--stiffness {} applies to the spring, angle-spring, quaternion and elasticity methods; --method {} has no springs",
            value_name(&a.stiffness()),
            value_name(&a.method())
        )));
    }
    super::elasticity::check_args(a)?;
    check_amg_strength(a)?;
    if !su2 && !tfi {
        return Err(CliError::NotAvailable {
            feature: "this method on Plot3D grids",
            needs: "--method tfi or tfi-displacement with --wall FACE (or an SU2 mesh)",
        });
    }
    if su2 && tfi {
        return Err(CliError::NotAvailable {
            feature: "transfinite interpolation on SU2 meshes",
            needs: "a structured Plot3D grid (TFI interpolates along grid lines)",
        });
    }
    Ok(())
}

/// `--amg-strength`: a threshold in [0, 1) for a method and solver that build a multigrid
/// hierarchy (refused, never ignored, elsewhere).
fn check_amg_strength(a: &MoveArgs) -> Result<(), CliError> {
    let Some(theta) = a.amg_strength else {
        return Ok(());
    };
    let multigrid = matches!(
        a.method(),
        Method::Spring | Method::Quaternion | Method::AngleCg
    ) && a.solver == Solver::Amg;
    // Elasticity's multigrid (rigid-body modes) keeps every connection.
    if !multigrid {
        return Err(CliError::Invalid(format!(
            "--amg-strength applies to --solver amg with --method spring, quaternion or angle-cg, not --method {} --solver {}",
            value_name(&a.method()),
            value_name(&a.solver)
        )));
    }
    if !(theta.is_finite() && (0.0..1.0).contains(&theta)) {
        return Err(CliError::Invalid("--amg-strength must be in [0, 1)".into()));
    }
    Ok(())
}

/// What an SU2 run needs before the mesh is read: moved markers, output kinds, a tolerance.
pub(super) fn check_su2_args(a: &MoveArgs) -> Result<(), CliError> {
    if a.markers.is_empty() && a.motions.is_none() {
        return Err(CliError::Invalid(
            "--marker (or --motions FILE) is required for SU2 meshes (the markers that move)"
                .into(),
        ));
    }
    if file_kind(&a.out) != Some(FileKind::Su2) && !is_cgns_path(&a.out) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a .su2 file (or .cgns)",
            a.out.display()
        )));
    }
    if let Some(v) = &a.vtk {
        if file_kind(v) != Some(FileKind::Vtu) {
            return Err(CliError::Invalid(format!(
                "{}: --vtk must be a .vtu file",
                v.display()
            )));
        }
    }
    if !(a.tol.is_finite() && a.tol > 0.0) {
        return Err(CliError::Invalid("--tol must be a positive number".into()));
    }
    Ok(())
}

/// `--slide` markers: not also moved (`moved`: the moving markers' names), named once.
pub(super) fn check_slide_markers(a: &MoveArgs, moved: &[String]) -> Result<(), CliError> {
    for (k, name) in a.slide.iter().enumerate() {
        if moved.contains(name) {
            return Err(CliError::Invalid(format!(
                "marker {name:?} is given to both --marker and --slide (a marker either moves or slides)"
            )));
        }
        if a.slide[..k].contains(name) {
            return Err(CliError::Invalid(format!("--slide {name} is given twice")));
        }
    }
    Ok(())
}

/// `--translate`, `--rotate`, `--axis`, `--center` against the mesh's dimension.
pub(super) fn check_rigid_args(a: &MoveArgs, dim: usize) -> Result<(), CliError> {
    let invalid = |m: &str| Err(CliError::Invalid(m.into()));
    if let Some(Coords(t)) = &a.translate {
        if dim == 2 && t.get(2).is_some_and(|&z| z != 0.0) {
            return invalid("--translate: a 2D mesh cannot move in z");
        }
        if dim == 3 && t.len() != 3 {
            return invalid("--translate: a 3D mesh needs dx,dy,dz");
        }
    }
    let Some(r) = a.rotate else { return Ok(()) };
    if !r.is_finite() {
        return invalid("--rotate must be a finite angle in degrees");
    }
    if let Some(Coords(ax)) = &a.axis {
        if ax.iter().all(|&v| v == 0.0) {
            return invalid("--axis must not be the zero vector");
        }
        if dim == 2 && (ax.first() != Some(&0.0) || ax.get(1) != Some(&0.0)) {
            return invalid("--axis: a 2D mesh rotates about z only (axis 0,0,1)");
        }
    }
    if let Some(Coords(c)) = &a.center {
        if dim == 3 && c.len() != 3 {
            return invalid("--center: a 3D mesh needs x,y,z");
        }
        if dim == 2 && c.len() != 2 {
            return invalid("--center: a 2D mesh rotates about a point x,y (no z)");
        }
    }
    Ok(())
}

/// `--plot`, `--reach` and the IDW options against the method.
pub(super) fn check_method_options(a: &MoveArgs) -> Result<(), CliError> {
    if let Some(p) = &a.plot {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("svg") && !ext.eq_ignore_ascii_case("png") {
            return Err(CliError::Invalid(format!(
                "{}: --plot must be a .svg or .png file",
                p.display()
            )));
        }
    }
    if let Some(r) = a.reach {
        if !matches!(a.method(), Method::Quaternion | Method::Idw) {
            return Err(CliError::Invalid(format!(
                "--reach applies to the quaternion and idw methods, not {}",
                value_name(&a.method())
            )));
        }
        if !(r.is_finite() && r > 0.0) {
            return Err(CliError::Invalid(
                "--reach must be a positive distance".into(),
            ));
        }
    }
    check_idw_options(a)
}

/// `--idw-theta`, `--idw-tolerance`, `--idw-exponent`.
fn check_idw_options(a: &MoveArgs) -> Result<(), CliError> {
    if let Some(theta) = a.idw_theta {
        if a.method() != Method::Idw {
            return Err(CliError::Invalid(format!(
                "--idw-theta applies to --method idw, not {}",
                value_name(&a.method())
            )));
        }
        if !(0.0..1.0).contains(&theta) {
            return Err(CliError::Invalid("--idw-theta must be in [0, 1)".into()));
        }
        if a.idw_tolerance.is_nan() || a.idw_tolerance < 0.0 {
            return Err(CliError::Invalid(
                "--idw-tolerance must be a non-negative number (inf: θ alone)".into(),
            ));
        }
    }
    if !(a.idw_exponent.is_finite() && a.idw_exponent > 0.0) {
        return Err(CliError::Invalid("--idw-exponent must be positive".into()));
    }
    Ok(())
}
