//! `deform su2 CONFIG`: SU2_DEF's job from its own configuration file.
//!
//! The configuration becomes the arguments of `deform move` (so every check, the failure
//! policy and the report are `move`'s): MESH_FILENAME / MESH_OUT_FILENAME, the design
//! variables on DV_MARKER, MARKER_DEFORM_MESH_SYM_PLANE as sliding markers, every other
//! marker fixed, and the DEFORM_* options. Options deformation does not use are reported
//! once as ignored; an option it cannot honour is an error that names it.

mod design;

use std::path::PathBuf;

use crate::args::{Command, Coords, Method, MoveArgs, Solver, StiffnessArg, Su2Args};
use crate::error::CliError;
use crate::files::read_bytes;
use crate::formats::su2_config::{list_groups, list_items, parse_su2_config, Su2Config};
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

/// `deform su2`.
pub(crate) fn su2(a: &Su2Args, quiet: bool) -> Result<Outcome, CliError> {
    let bytes = read_bytes(&a.config)?;
    let config = parse_su2_config(&bytes).map_err(|source| CliError::Read {
        path: a.config.clone(),
        source,
    })?;
    let (args, console) = move_args(a, &config)?;
    let ignored = ignored_options(&config, args.method());
    if !ignored.is_empty() && !quiet {
        eprintln!(
            "deform: note: {}: options not used by mesh deformation, ignored: {}",
            a.config.display(),
            ignored.join(", ")
        );
    }
    let command = Command::Move(args.clone());
    let (inputs, outputs) = super::files_of(&command);
    crate::guard::check_outputs(&inputs, &outputs)?;
    crate::guard::register_inputs(&inputs);
    let mut outcome = super::r#move::move_mesh(&args, quiet || !console, None)?;
    if let Some(report) = outcome.json.as_object_mut() {
        report.insert("command".into(), "su2".into());
        report.insert("config".into(), a.config.display().to_string().into());
        report.insert("ignored_options".into(), ignored.into());
    }
    Ok(outcome)
}

/// An error naming the option (and its line) that cannot be honoured.
fn option_error(config: &Su2Config, key: &str, why: impl std::fmt::Display) -> CliError {
    match config.get(key) {
        Some(e) => CliError::Invalid(format!("{key} (line {}): {why}", e.line)),
        None => CliError::Invalid(format!("{key}: {why}")),
    }
}

/// A number option, or `default` when the file does not set it.
fn number<T: std::str::FromStr>(config: &Su2Config, key: &str, default: T) -> Result<T, CliError> {
    match config.get(key) {
        None => Ok(default),
        Some(e) => (e.value.parse())
            .map_err(|_| option_error(config, key, format!("{:?} is not a number", e.value))),
    }
}

/// The options the file sets that deformation does not use, in file order.
fn ignored_options(config: &Su2Config, method: Method) -> Vec<String> {
    let elasticity = is_elasticity(method);
    (config.entries.iter())
        .map(|e| e.key.as_str())
        .filter(|k| !HONOURED.contains(k) && !k.starts_with("MARKER_"))
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
        PathBuf::from(text("MESH_OUT_FILENAME", "mesh_out.su2")),
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
    let dim = mesh_dim(&args.mesh)?;
    design_variables(config, dim, &mut args)?;
    Ok((args, console))
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
        stiffness: None,
        poisson: 0.3,
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
/// 0.3) for CONSTANT_STIFFNESS; for INVERSE_VOLUME and SOLID_WALL_DISTANCE SU2 sets μ = E and
/// λ = DEFORM_COEFF · E (default 1e6), which is ν = c / (2 (c + 1)).
fn poisson_ratio(config: &Su2Config, stiffness: StiffnessArg) -> Result<f64, CliError> {
    if stiffness == StiffnessArg::Constant {
        return number(config, "DEFORM_POISSONS_RATIO", 0.3);
    }
    let c: f64 = number(config, "DEFORM_COEFF", 1e6)?;
    if !(c.is_finite() && c > -1.0) {
        return Err(option_error(
            config,
            "DEFORM_COEFF",
            "must be a number above -1",
        ));
    }
    Ok(c / (2.0 * (c + 1.0)))
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

/// DV_KIND, DV_PARAM, DV_VALUE (and DV_FILENAME) as the motion of the DV_MARKER markers.
fn design_variables(config: &Su2Config, dim: usize, args: &mut MoveArgs) -> Result<(), CliError> {
    let kinds: Vec<String> = config
        .get("DV_KIND")
        .map(|e| {
            list_items(&e.value)
                .iter()
                .map(|k| k.to_ascii_uppercase())
                .collect()
        })
        .unwrap_or_default();
    if let Some(first) = kinds.first() {
        if matches!(
            first.as_str(),
            "HICKS_HENNE" | "FFD_CONTROL_POINT" | "FFD_CONTROL_POINT_2D"
        ) {
            return surface_design(config, &kinds, dim, args);
        }
    }
    let [kind] = kinds.as_slice() else {
        return Err(option_error(
            config,
            "DV_KIND",
            format!(
                "{} design variables: deform su2 applies one SURFACE_FILE, TRANSLATION or ROTATION (or several HICKS_HENNE or FFD_CONTROL_POINT(_2D))",
                kinds.len()
            ),
        ));
    };
    if kind == "SURFACE_FILE" {
        let file = config
            .get("DV_FILENAME")
            .map_or("surface_positions.dat", |e| &e.value);
        args.surface_positions = Some(PathBuf::from(file));
        return Ok(());
    }
    let value = config
        .get("DV_VALUE")
        .map(|e| list_items(&e.value))
        .unwrap_or_default();
    let [value] = value.as_slice() else {
        return Err(option_error(
            config,
            "DV_VALUE",
            "one value for the one design variable",
        ));
    };
    let value: f64 = (value.parse().ok())
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| option_error(config, "DV_VALUE", format!("{value:?} is not a number")))?;
    let params = parameters(config)?;
    match kind.as_str() {
        "TRANSLATION" => translation(config, &params, value, dim, args),
        "ROTATION" => rotation(config, &params, value, dim, args),
        other => Err(option_error(
            config,
            "DV_KIND",
            format!("{other} is not supported yet (SURFACE_FILE, TRANSLATION, ROTATION, HICKS_HENNE and FFD_CONTROL_POINT(_2D) are)"),
        )),
    }
}

/// DV_PARAM's one group, as numbers.
fn parameters(config: &Su2Config) -> Result<Vec<f64>, CliError> {
    let groups = config.get("DV_PARAM").map(|e| list_groups(&e.value));
    let Some([group]) = groups.as_deref() else {
        return Err(option_error(
            config,
            "DV_PARAM",
            "one parameter group, e.g. ( 1.0, 0.0, 0.0 )",
        ));
    };
    group
        .iter()
        .map(|t| t.parse().ok().filter(|v: &f64| v.is_finite()))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| option_error(config, "DV_PARAM", "parameters must be numbers"))
}

/// TRANSLATION: DV_PARAM = ( dx, dy, dz ) times DV_VALUE (`p`: the mesh's dimension's first
/// parameters; dz is unused in 2D, as in SU2).
fn translation(
    config: &Su2Config,
    p: &[f64],
    value: f64,
    dim: usize,
    args: &mut MoveArgs,
) -> Result<(), CliError> {
    if p.len() < dim {
        return Err(option_error(
            config,
            "DV_PARAM",
            "TRANSLATION needs ( dx, dy, dz )",
        ));
    }
    let t: Vec<f64> = p.iter().take(dim).map(|x| x * value).collect();
    args.translate = Some(Coords(t));
    Ok(())
}

/// ROTATION: DV_PARAM = ( x0, y0, z0, x1, y1, z1 ), the axis from point 0 to point 1 through
/// point 0, DV_VALUE degrees. In 2D SU2 rotates about +z through (x0, y0) (its axis is
/// (x1 − x0, y1 − y0, 1)): a 2D axis with an x or y part would turn the plane out of itself and
/// is refused.
fn rotation(
    config: &Su2Config,
    p: &[f64],
    value: f64,
    dim: usize,
    args: &mut MoveArgs,
) -> Result<(), CliError> {
    let [x0, y0, z0, x1, y1, z1] = p[..] else {
        return Err(option_error(
            config,
            "DV_PARAM",
            "ROTATION needs ( x0, y0, z0, x1, y1, z1 ): the axis from point 0 to point 1",
        ));
    };
    args.rotate = Some(value);
    if dim == 2 {
        if x1 != x0 || y1 != y0 {
            return Err(option_error(
                config,
                "DV_PARAM",
                "a 2D mesh rotates about z: x1 = x0 and y1 = y0",
            ));
        }
        args.axis = Some(Coords(vec![0.0, 0.0, 1.0]));
        args.center = Some(Coords(vec![x0, y0]));
    } else {
        args.axis = Some(Coords(vec![x1 - x0, y1 - y0, z1 - z0]));
        args.center = Some(Coords(vec![x0, y0, z0]));
    }
    Ok(())
}

/// The dimension an SU2 mesh declares (its NDIME= line), read before the mesh itself so the
/// design variables can be checked against it.
fn mesh_dim(path: &std::path::Path) -> Result<usize, CliError> {
    let bytes = read_bytes(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let ndime = text.lines().find_map(|l| {
        let (key, value) = l.split('%').next()?.split_once('=')?;
        key.trim()
            .eq_ignore_ascii_case("NDIME")
            .then(|| value.trim().parse::<usize>().ok())?
    });
    match ndime {
        Some(d @ (2 | 3)) => Ok(d),
        _ => Err(CliError::Invalid(format!(
            "{}: no NDIME= 2 or 3 line (is MESH_FILENAME an SU2 mesh?)",
            path.display()
        ))),
    }
}

/// Several design variables of one kind (HICKS_HENNE, FFD_CONTROL_POINT or
/// FFD_CONTROL_POINT_2D) on the DV_MARKER surface, evaluated by the kernel on the mesh.
fn surface_design(
    config: &Su2Config,
    kinds: &[String],
    dim: usize,
    args: &mut MoveArgs,
) -> Result<(), CliError> {
    let kind = kinds[0].clone();
    if kinds.iter().any(|k| *k != kind) {
        return Err(option_error(
            config,
            "DV_KIND",
            "design variables of one kind per run",
        ));
    }
    let values: Vec<f64> = config
        .get("DV_VALUE")
        .map(|e| list_items(&e.value))
        .unwrap_or_default()
        .iter()
        .map(|v| v.parse().ok().filter(|v: &f64| v.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| option_error(config, "DV_VALUE", "values must be numbers"))?;
    let groups: Vec<Vec<String>> = config.get("DV_PARAM").map_or_else(Vec::new, |e| {
        let g = list_groups(&e.value);
        g.into_iter()
            .map(|g| g.into_iter().map(String::from).collect())
            .collect()
    });
    if values.len() != kinds.len() || groups.len() != kinds.len() {
        return Err(option_error(
            config,
            "DV_PARAM",
            format!(
                "{} design variables need {0} DV_VALUE and {0} DV_PARAM groups; found {} and {}",
                kinds.len(),
                values.len(),
                groups.len()
            ),
        ));
    }
    let relax: f64 = number(config, "OPT_RELAX_FACTOR", 1.0)?;
    let mesh = crate::files::read_su2(&args.mesh)?;
    let field = if kind == "HICKS_HENNE" {
        if dim != 2 {
            return Err(option_error(
                config,
                "DV_KIND",
                "HICKS_HENNE needs a 2D mesh",
            ));
        }
        let bumps = hicks_henne_params(config, &groups, &values, relax)?;
        design::hicks_henne_field(&mesh, &args.markers, &bumps)?
    } else {
        let moves = ffd_moves(config, &groups, &values, kind == "FFD_CONTROL_POINT_2D")?;
        design::ffd_field(&mesh, &moves)?
    };
    args.design_field = Some(field);
    Ok(())
}

/// HICKS_HENNE's `( 0 | 1, x_max )` groups as `(upper, x_max, DV_VALUE × OPT_RELAX_FACTOR)`.
fn hicks_henne_params(
    config: &Su2Config,
    groups: &[Vec<String>],
    values: &[f64],
    relax: f64,
) -> Result<Vec<(bool, f64, f64)>, CliError> {
    let bad = || {
        option_error(
            config,
            "DV_PARAM",
            "HICKS_HENNE needs ( 0 or 1, x of the peak )",
        )
    };
    groups
        .iter()
        .zip(values)
        .map(|(g, &v)| match g.as_slice() {
            [side, x] => {
                let upper = match side.as_str() {
                    "1" | "1.0" => true,
                    "0" | "0.0" => false,
                    _ => return Err(bad()),
                };
                let x: f64 = x.parse().map_err(|_| bad())?;
                Ok((upper, x, v * relax))
            }
            _ => Err(bad()),
        })
        .collect()
}

/// FFD_CONTROL_POINT `( box, i, j, k, dx, dy, dz )` or FFD_CONTROL_POINT_2D
/// `( box, i, j, dx, dy )` groups as control-point moves by DV_VALUE × the direction (an index
/// of −1: every index, as in SU2).
fn ffd_moves(
    config: &Su2Config,
    groups: &[Vec<String>],
    values: &[f64],
    two_d: bool,
) -> Result<Vec<design::ControlMove>, CliError> {
    let n = if two_d { 5 } else { 7 };
    let bad = || {
        let what = if two_d {
            "FFD_CONTROL_POINT_2D needs ( box, i, j, dx, dy )"
        } else {
            "FFD_CONTROL_POINT needs ( box, i, j, k, dx, dy, dz )"
        };
        option_error(config, "DV_PARAM", what)
    };
    let index = |t: &str| -> Result<Option<usize>, CliError> {
        let v: f64 = t.parse().map_err(|_| bad())?;
        match v {
            -1.0 => Ok(None),
            v if v >= 0.0 && v.fract() == 0.0 => Ok(Some(v as usize)),
            _ => Err(bad()),
        }
    };
    let number = |t: &str| -> Result<f64, CliError> {
        t.parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(bad)
    };
    let mut moves = Vec::new();
    for (g, &value) in groups.iter().zip(values) {
        if g.len() != n {
            return Err(bad());
        }
        let nidx = if two_d { 2 } else { 3 };
        let mut ijk = [None; 3];
        for (slot, t) in ijk.iter_mut().zip(&g[1..=nidx]) {
            *slot = index(t)?;
        }
        let mut movement = [0.0; 3];
        for (slot, t) in movement.iter_mut().zip(&g[1 + nidx..]) {
            *slot = value * number(t)?;
        }
        moves.push(design::ControlMove {
            tag: g[0].clone(),
            ijk,
            movement,
            two_d,
        });
    }
    Ok(moves)
}
