//! `deform su2 CONFIG`: SU2_DEF's job from its own configuration file.
//!
//! The configuration becomes the arguments of `deform move` (so every check, the failure
//! policy and the report are `move`'s): MESH_FILENAME / MESH_OUT_FILENAME, the design
//! variables on DV_MARKER, MARKER_DEFORM_MESH_SYM_PLANE as sliding markers, every other
//! marker fixed, and the DEFORM_* options. Options deformation does not use are reported
//! once as ignored; an option it cannot honour is an error that names it.

mod design;
mod ffd_planes;
pub(super) mod gradient;
mod variables;

use std::path::PathBuf;

use crate::args::{Command, Method, MoveArgs, Solver, StiffnessArg, Su2Args};
use crate::error::CliError;
use crate::files::read_bytes;
use crate::formats::su2_config::{list_items, parse_su2_config, Su2Config};
use crate::report::Outcome;

/// The options `deform su2` honours (besides the `MARKER_*` boundary lists, whose markers are
/// fixed unless moved or sliding).
const HONOURED: &[&str] = &[
    "MESH_FILENAME",
    "MESH_OUT_FILENAME",
    "MESH_FORMAT",
    "DV_KIND",
    "DV_MARKER",
    "DV_PARAM",
    "DV_VALUE",
    "DV_FILENAME",
    "MARKER_DEFORM_MESH_SYM_PLANE",
    "DEFORM_STIFFNESS_TYPE",
    "DEFORM_NONLINEAR_ITER",
    "DEFORM_LINEAR_SOLVER_ITER",
    "DEFORM_LINEAR_SOLVER_ERROR",
    "DEFORM_CONSOLE_OUTPUT",
    "OPT_RELAX_FACTOR",
];

/// Options only SU2's elasticity uses: ignored (and said so) with another `--method`.
const ELASTICITY_ONLY: &[&str] = &[
    "DEFORM_COEFF",
    "DEFORM_POISSONS_RATIO",
    "DEFORM_ELASTICITY_MODULUS",
];

/// The method when `--method` is not given: SU2_DEF's (finite-element elasticity) once the
/// tool has it.
const DEFAULT_METHOD: Option<Method> = Some(Method::Elasticity);

/// Whether `method` is SU2's elasticity (which reads DEFORM_COEFF and the Poisson ratio).
fn is_elasticity(method: Method) -> bool {
    method == Method::Elasticity
}

/// `deform su2`: the config read, the mesh read once (for the design variables and the
/// deformation both).
pub(crate) fn su2(a: &Su2Args, quiet: bool) -> Result<Outcome, CliError> {
    let bytes = read_bytes(&a.config)?;
    let config = parse_su2_config(&bytes).map_err(|source| CliError::Read {
        path: a.config.clone(),
        source,
    })?;
    let (mut args, console) = move_args(a, &config)?;
    let dvs = variables::read_dvs(&config)?;
    let ignored = ignored_options(&config, args.method(), &used_options(&dvs));
    let command = Command::Move(args.clone());
    let (inputs, outputs) = super::files_of(&command);
    crate::guard::check_outputs(&inputs, &outputs)?;
    crate::files::check_su2_output(&args.mesh, &args.out)?;
    let names: [&[String]; 2] = [&args.markers, &args.slide];
    let loaded = crate::files::read_su2_zone(&args.mesh, &names, None)?;
    variables::apply_dvs(&config, &dvs, &loaded.0, &mut args)?;
    if !ignored.is_empty() && !quiet {
        eprintln!(
            "deform: note: {}: options not used by mesh deformation, ignored: {}",
            a.config.display(),
            ignored.join(", ")
        );
    }
    crate::guard::register_inputs(&inputs);
    let mut outcome = super::r#move::move_loaded(&args, quiet || !console, loaded)?;
    if let Some(report) = outcome.json.as_object_mut() {
        report.insert("command".into(), "su2".into());
        report.insert("config".into(), a.config.display().to_string().into());
        report.insert("ignored_options".into(), ignored.into());
    }
    Ok(outcome)
}

/// The options the design variables read besides DV_* (the FFD ones with FFD variables,
/// REF_LENGTH with FFD_TWIST).
fn used_options(dvs: &[variables::Dv]) -> Vec<&'static str> {
    let ffd = dvs.iter().any(|d| d.kind.starts_with("FFD_"));
    let twist = dvs.iter().any(|d| d.kind == "FFD_TWIST");
    (ffd_planes::FFD_OPTIONS.iter().copied())
        .filter(|&k| ffd && (k != "REF_LENGTH" || twist))
        .collect()
}

/// An error naming the option (and its line) that cannot be honoured.
pub(super) fn option_error(config: &Su2Config, key: &str, why: impl std::fmt::Display) -> CliError {
    match config.get(key) {
        Some(e) => CliError::Invalid(format!("{key} (line {}): {why}", e.line)),
        None => CliError::Invalid(format!("{key}: {why}")),
    }
}

/// A number option, or `default` when the file does not set it.
pub(super) fn number<T: std::str::FromStr>(
    config: &Su2Config,
    key: &str,
    default: T,
) -> Result<T, CliError> {
    match config.get(key) {
        None => Ok(default),
        Some(e) => (e.value.parse())
            .map_err(|_| option_error(config, key, format!("{:?} is not a number", e.value))),
    }
}

/// The options the file sets that deformation does not use, in file order.
fn ignored_options(config: &Su2Config, method: Method, used: &[&str]) -> Vec<String> {
    let elasticity = is_elasticity(method);
    (config.entries.iter())
        .map(|e| e.key.as_str())
        .filter(|k| !HONOURED.contains(k) && !k.starts_with("MARKER_"))
        .filter(|k| !used.contains(k))
        .filter(|k| !(elasticity && ELASTICITY_ONLY.contains(k)))
        .map(String::from)
        .collect()
}

/// The `deform move` arguments the configuration asks for, and whether it wants console
/// output (DEFORM_CONSOLE_OUTPUT).
fn move_args(a: &Su2Args, config: &Su2Config) -> Result<(MoveArgs, bool), CliError> {
    let text = |key: &str, default: &str| {
        config
            .get(key)
            .map_or_else(|| default.to_string(), |e| e.value.clone())
    };
    let format = text("MESH_FORMAT", "SU2").to_ascii_uppercase();
    if format != "SU2" {
        return Err(option_error(
            config,
            "MESH_FORMAT",
            format!("{format}: only SU2 meshes"),
        ));
    }
    let method = match a.method.or(DEFAULT_METHOD) {
        Some(m) => m,
        None => {
            return Err(CliError::NotAvailable {
                feature: "SU2's finite-element elasticity in deform su2",
                needs: "--method quaternion, spring, angle-cg, angle-direct or idw",
            })
        }
    };
    let stiffness = stiffness(config, method)?;
    let console = match text("DEFORM_CONSOLE_OUTPUT", "YES")
        .to_ascii_uppercase()
        .as_str()
    {
        "YES" => true,
        "NO" => false,
        v => {
            return Err(option_error(
                config,
                "DEFORM_CONSOLE_OUTPUT",
                format!("{v}: YES or NO"),
            ))
        }
    };
    let steps: u32 = number(config, "DEFORM_NONLINEAR_ITER", 1)?;
    if !(1..=10_000).contains(&steps) {
        return Err(option_error(
            config,
            "DEFORM_NONLINEAR_ITER",
            "must be 1 to 10000",
        ));
    }
    let slide = config
        .get("MARKER_DEFORM_MESH_SYM_PLANE")
        .map(|e| list_items(&e.value).into_iter().map(String::from).collect())
        .unwrap_or_default();
    let mut args = move_defaults(
        PathBuf::from(text("MESH_FILENAME", "mesh.su2")),
        out_name(&text("MESH_OUT_FILENAME", "mesh_out.su2")),
    );
    args.markers = design_markers(config)?;
    args.slide = slide;
    args.method = Some(method);
    args.stiffness = Some(stiffness);
    args.poisson = poisson_ratio(config, stiffness)?;
    args.steps = steps;
    args.tol = number(config, "DEFORM_LINEAR_SOLVER_ERROR", 1e-10)?;
    args.max_iter = number(config, "DEFORM_LINEAR_SOLVER_ITER", 10_000)?;
    args.allow_folds = a.allow_folds;
    args.allow_unconverged = a.allow_unconverged;
    Ok((args, console))
}

/// MESH_OUT_FILENAME as SU2 writes it: its SU2 mesh writer adds `.su2` to a name without an
/// extension (SU2's own test configs say `MESH_OUT_FILENAME= mesh_out`).
fn out_name(name: &str) -> PathBuf {
    let path = PathBuf::from(name);
    if path.extension().is_none() {
        return path.with_extension("su2");
    }
    path
}

/// `deform move MESH --out OUT` with every other option at its default (no motion yet).
fn move_defaults(mesh: PathBuf, out: PathBuf) -> MoveArgs {
    MoveArgs {
        mesh,
        markers: Vec::new(),
        slide: Vec::new(),
        wall: None,
        rotate: None,
        axis: None,
        center: None,
        translate: None,
        displacements: None,
        surface_positions: None,
        motions: None,
        method: None,
        solver: Solver::Amg,
        amg_strength: None,
        stiffness: None,
        poisson: 0.3,
        rigid_layer: None,
        steps: 1,
        tol: 1e-10,
        max_iter: 10_000,
        idw_exponent: 2.0,
        idw_theta: None,
        idw_tolerance: f64::INFINITY,
        reach: None,
        allow_folds: false,
        allow_unconverged: false,
        renumber: crate::renumber::Renumber::Auto,
        distributed: false,
        design_field: None,
        rbf: crate::args::RbfArgs {
            rbf_kernel: crate::args::RbfKernelArg::Wendland,
            rbf_radius: None,
            rbf_tolerance: 0.0,
            rbf_max_centres: 1000,
            rbf_correction: None,
        },
        out,
        vtk: None,
        plot: None,
    }
}

/// DV_MARKER: the markers the design variables move.
fn design_markers(config: &Su2Config) -> Result<Vec<String>, CliError> {
    let markers: Vec<String> = config
        .get("DV_MARKER")
        .map(|e| list_items(&e.value).into_iter().map(String::from).collect())
        .unwrap_or_default();
    if markers.is_empty() {
        return Err(option_error(
            config,
            "DV_MARKER",
            "no marker to deform (list the moving markers, e.g. DV_MARKER= ( airfoil ))",
        ));
    }
    Ok(markers)
}

/// The Poisson ratio of the elasticity solve as SU2 reads it: DEFORM_POISSONS_RATIO (default
/// 0.3) for CONSTANT_STIFFNESS; for INVERSE_VOLUME and SOLID_WALL_DISTANCE ν = DEFORM_COEFF
/// itself (default 1e6: "Nu is normally a very large number, for rigid-body rotations, see
/// Dwight (2009)", SU2's CMeshSolver; μ = E/(2(1+ν)), λ = νE/((1+ν)(1−2ν)), so λ ≈ −μ).
fn poisson_ratio(config: &Su2Config, stiffness: StiffnessArg) -> Result<f64, CliError> {
    if stiffness == StiffnessArg::Constant {
        return number(config, "DEFORM_POISSONS_RATIO", 0.3);
    }
    let c: f64 = number(config, "DEFORM_COEFF", 1e6)?;
    if !(c.is_finite() && c > -1.0 && c != 0.5) {
        return Err(option_error(
            config,
            "DEFORM_COEFF",
            "must be a number above -1 other than 0.5",
        ));
    }
    Ok(c)
}

/// DEFORM_STIFFNESS_TYPE for `method`: SU2's element stiffness for elasticity, the matching
/// spring stiffness for the spring and quaternion methods (CONSTANT_STIFFNESS: Batina's springs
/// unchanged); IDW has none.
fn stiffness(config: &Su2Config, method: Method) -> Result<StiffnessArg, CliError> {
    let kind = config.get("DEFORM_STIFFNESS_TYPE").map_or_else(
        || "SOLID_WALL_DISTANCE".to_string(),
        |e| e.value.to_ascii_uppercase(),
    );
    let s = match kind.as_str() {
        "SOLID_WALL_DISTANCE" | "WALL_DISTANCE" => StiffnessArg::WallDistance,
        "INVERSE_VOLUME" => StiffnessArg::InverseVolume,
        "CONSTANT_STIFFNESS" if method == Method::Elasticity => StiffnessArg::Constant,
        "CONSTANT_STIFFNESS" => StiffnessArg::Batina,
        other => {
            return Err(option_error(
                config,
                "DEFORM_STIFFNESS_TYPE",
                format!("{other}: SOLID_WALL_DISTANCE, INVERSE_VOLUME or CONSTANT_STIFFNESS"),
            ))
        }
    };
    let springless = matches!(
        method,
        Method::Idw | Method::Rbf | Method::Tfi | Method::TfiDisplacement
    );
    Ok(if springless { StiffnessArg::Batina } else { s })
}
