//! DV_KIND, DV_PARAM and DV_VALUE read as SU2 reads them (one value per variable; a last
//! parameter group may carry extra trailing numbers, which SU2 ignores), and turned into the
//! motion of the DV_MARKER surface:
//!
//! - SURFACE_FILE: DV_FILENAME's positions.
//! - One TRANSLATION or ROTATION: `deform move --translate` / `--rotate`.
//! - Any other mix of TRANSLATION, ROTATION, SCALE and HICKS_HENNE: SU2's per-node sums
//!   (SetScale, SetTranslation, SetRotation from the original coordinates, then the bumps).
//! - FFD variables: the boxes in the mesh file (design.rs).

use std::path::PathBuf;

use deform_kernel::design::twist::su2_rotation_movement;
use deform_kernel::Real;

use crate::args::{Coords, MoveArgs};
use crate::error::CliError;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_config::{list_groups, list_items, Su2Config};

use super::design::{self, ControlMove, FfdChange};
use super::{number, option_error};

/// The FFD kinds `deform su2` applies.
const FFD_KINDS: &[&str] = &[
    "FFD_CONTROL_POINT",
    "FFD_CONTROL_POINT_2D",
    "FFD_CAMBER",
    "FFD_THICKNESS",
    "FFD_TWIST",
    "FFD_CAMBER_2D",
    "FFD_THICKNESS_2D",
];

/// The kinds SU2 applies directly to the surface (in its one branch for them).
const SURFACE_KINDS: &[&str] = &["TRANSLATION", "ROTATION", "SCALE", "HICKS_HENNE"];

/// One design variable: kind, parameters (as written), DV_VALUE × OPT_RELAX_FACTOR.
pub(super) struct Dv {
    pub kind: String,
    pub params: Vec<String>,
    pub amplitude: f64,
}

/// How many parameters SU2 reads for `kind` (SCALE: none).
fn param_count(kind: &str) -> usize {
    match kind {
        "FFD_CONTROL_POINT" | "FFD_TWIST" => 7 + usize::from(kind == "FFD_TWIST"),
        "FFD_CONTROL_POINT_2D" | "ROTATION" => 5 + usize::from(kind == "ROTATION"),
        "FFD_CAMBER" | "FFD_THICKNESS" | "TRANSLATION" => 3,
        "FFD_CAMBER_2D" | "FFD_THICKNESS_2D" | "HICKS_HENNE" => 2,
        _ => 0,
    }
}

/// The design variables of the config, checked against the kinds `deform su2` applies.
/// Returns them and the config options they read besides DV_*.
pub(super) fn read_dvs(config: &Su2Config) -> Result<Vec<Dv>, CliError> {
    let kinds: Vec<String> = config.get("DV_KIND").map_or_else(Vec::new, |e| {
        list_items(&e.value)
            .iter()
            .map(|k| k.to_ascii_uppercase())
            .collect()
    });
    let first = kinds.first().map(String::as_str).unwrap_or("");
    let family: &[&str] = if FFD_KINDS.contains(&first) {
        FFD_KINDS
    } else if SURFACE_KINDS.contains(&first) {
        SURFACE_KINDS
    } else if first == "SURFACE_FILE" && kinds.len() == 1 {
        return Ok(vec![Dv {
            kind: first.into(),
            params: Vec::new(),
            amplitude: 0.0,
        }]);
    } else {
        let why = format!(
            "{first:?}: deform su2 applies SURFACE_FILE (alone), TRANSLATION, ROTATION, SCALE, HICKS_HENNE, {}",
            FFD_KINDS.join(", ")
        );
        return Err(option_error(config, "DV_KIND", why));
    };
    if let Some(k) = kinds.iter().find(|k| !family.contains(&k.as_str())) {
        let why = format!("{k} after {first}: SU2 applies only {} in that run (the rest silently not), so deform su2 refuses the mix", family.join(", "));
        return Err(option_error(config, "DV_KIND", why));
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
        (list_groups(&e.value).into_iter())
            .map(|g| g.into_iter().map(String::from).collect())
            .collect()
    });
    if values.len() != kinds.len() || groups.len() != kinds.len() {
        let why = format!(
            "{} design variables need {0} DV_VALUE and {0} DV_PARAM groups; found {} and {}",
            kinds.len(),
            values.len(),
            groups.len()
        );
        return Err(option_error(config, "DV_PARAM", why));
    }
    let relax: f64 = number(config, "OPT_RELAX_FACTOR", 1.0)?;
    let last = kinds.len() - 1;
    let mut dvs = Vec::new();
    for (n, ((kind, mut params), value)) in kinds.into_iter().zip(groups).zip(values).enumerate() {
        let want = param_count(&kind);
        if params.len() < want || (params.len() > want && n < last && kind != "SCALE") {
            let why = format!(
                "design variable {} ({kind}) needs {want} parameters, has {}",
                n + 1,
                params.len()
            );
            return Err(option_error(config, "DV_PARAM", why));
        }
        params.truncate(want);
        dvs.push(Dv {
            kind,
            params,
            amplitude: value * relax,
        });
    }
    Ok(dvs)
}

/// A parameter as a number (`what` names the variable in errors).
fn num(config: &Su2Config, t: &str, what: &str) -> Result<f64, CliError> {
    t.parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| option_error(config, "DV_PARAM", format!("{what}: {t:?} is not a number")))
}

/// An FFD index: a whole number ≥ 0, or −1 (`None`: every index) where `any` allows it.
fn index(config: &Su2Config, t: &str, any: bool, what: &str) -> Result<Option<usize>, CliError> {
    match num(config, t, what)? {
        v if v == -1.0 && any => Ok(None),
        v if v >= 0.0 && v.fract() == 0.0 && v < 1e6 => Ok(Some(v as usize)),
        v => Err(option_error(
            config,
            "DV_PARAM",
            format!("{what}: index {v} (0, 1, ...)"),
        )),
    }
}

/// The motion of the DV_MARKER markers for the design variables, set in `args`; `mesh` is the
/// mesh already read.
pub(super) fn apply_dvs(
    config: &Su2Config,
    dvs: &[Dv],
    mesh: &Su2Mesh,
    args: &mut MoveArgs,
) -> Result<(), CliError> {
    let first = dvs.first().map_or("", |d| d.kind.as_str());
    if first == "SURFACE_FILE" {
        let file = (config.get("DV_FILENAME")).map_or("surface_positions.dat", |e| &e.value);
        args.surface_positions = Some(PathBuf::from(file));
        return Ok(());
    }
    if FFD_KINDS.contains(&first) {
        let moves = ffd_moves(config, dvs)?;
        let setup = super::ffd_planes::setup(config, &args.markers)?;
        args.design_field = Some(design::ffd_field(mesh, &moves, &setup)?);
        return Ok(());
    }
    if let [dv] = dvs {
        if rigid(config, dv, mesh.dim, args)? {
            return Ok(());
        }
    }
    args.design_field = Some(surface_field(config, dvs, mesh, &args.markers)?);
    Ok(())
}

/// One TRANSLATION, or one ROTATION about z in 2D or any axis in 3D, as `deform move`'s rigid
/// motion (false: not one of those).
fn rigid(config: &Su2Config, dv: &Dv, dim: usize, args: &mut MoveArgs) -> Result<bool, CliError> {
    let p = dv_numbers(config, dv, dim)?;
    match dv.kind.as_str() {
        "TRANSLATION" => {
            let t = p.iter().take(dim).map(|x| dv.amplitude * x).collect();
            args.translate = Some(Coords(t));
        }
        "ROTATION" => {
            let [x0, y0, z0, x1, y1, z1] = p[..] else {
                return Ok(false);
            };
            args.rotate = Some(dv.amplitude);
            if dim == 2 {
                args.axis = Some(Coords(vec![0.0, 0.0, 1.0]));
                args.center = Some(Coords(vec![x0, y0]));
            } else {
                args.axis = Some(Coords(vec![x1 - x0, y1 - y0, z1 - z0]));
                args.center = Some(Coords(vec![x0, y0, z0]));
            }
        }
        _ => return Ok(false),
    }
    Ok(true)
}

/// A variable's parameters as numbers; a 2D ROTATION must turn about z (SU2 would tilt its
/// axis to (x1 − x0, y1 − y0, 1) and drop the z movement).
pub(super) fn dv_numbers(config: &Su2Config, dv: &Dv, dim: usize) -> Result<Vec<f64>, CliError> {
    let p = (dv.params.iter())
        .map(|t| num(config, t, &dv.kind))
        .collect::<Result<Vec<f64>, _>>()?;
    if dv.kind == "ROTATION" && (p[3] != p[0] || p[4] != p[1]) && dim == 2 {
        return Err(option_error(
            config,
            "DV_PARAM",
            "a 2D mesh rotates about z: x1 = x0 and y1 = y0",
        ));
    }
    Ok(p)
}

/// SU2's surface variables summed per DV_MARKER node, from the original coordinates: SCALE,
/// TRANSLATION and ROTATION in order, then HICKS_HENNE (SU2's two passes).
fn surface_field(
    config: &Su2Config,
    dvs: &[Dv],
    mesh: &Su2Mesh,
    markers: &[String],
) -> Result<design::Field, CliError> {
    if dvs[0].kind == "HICKS_HENNE" && dvs.iter().any(|d| d.kind != "HICKS_HENNE") {
        return Err(option_error(config, "DV_KIND", "HICKS_HENNE first: SU2 then discards the TRANSLATION, ROTATION and SCALE variables after it; list HICKS_HENNE last"));
    }
    let nodes = crate::files::marker_nodes(mesh, markers, std::path::Path::new("DV_MARKER"))?;
    let mut d = vec![[0.0f64; 3]; nodes.len()];
    let three = mesh.dim == 3;
    for dv in dvs.iter().filter(|d| d.kind != "HICKS_HENNE") {
        let p = dv_numbers(config, dv, mesh.dim)?;
        let a = dv.amplitude;
        let z0 = rotation_z0(config, dvs, dv, three)?;
        for (v, &n) in d.iter_mut().zip(&nodes) {
            let x = mesh.points[n as usize];
            let m = match dv.kind.as_str() {
                "SCALE" => [(a - 1.0) * x[0], (a - 1.0) * x[1], (a - 1.0) * x[2]],
                "TRANSLATION" => [a * p[0], a * p[1], a * p[2]],
                _ => su2_rotation(x, [p[0], p[1], z0], [p[3], p[4], p[5]], a, three),
            };
            let dims = if three { 3 } else { 2 };
            for k in 0..dims {
                v[k] += m[k];
            }
        }
    }
    let bumps = hicks_henne_params(config, dvs)?;
    if !bumps.is_empty() {
        if three {
            return Err(option_error(
                config,
                "DV_KIND",
                "HICKS_HENNE needs a 2D mesh",
            ));
        }
        let hh = design::hicks_henne_field(mesh, markers, &bumps)?;
        for ((_, h), v) in hh.iter().zip(d.iter_mut()) {
            v[1] += h[1];
        }
    }
    Ok(nodes.into_iter().zip(d).collect())
}

/// The z of the rotation point: SU2's SetRotation reads it from the *first* design variable's
/// DV_PARAM in 3D (0 in 2D); refused where that differs from the variable's own z0.
pub(super) fn rotation_z0(
    config: &Su2Config,
    dvs: &[Dv],
    dv: &Dv,
    three: bool,
) -> Result<f64, CliError> {
    if dv.kind != "ROTATION" || !three {
        return Ok(0.0);
    }
    let own = num(config, &dv.params[2], "ROTATION")?;
    let first = dvs[0].params.get(2).map(|t| num(config, t, "ROTATION"));
    match first {
        Some(Ok(z)) if z == own => Ok(z),
        _ => Err(option_error(config, "DV_PARAM", "SU2 takes a ROTATION's z0 from the first design variable's DV_PARAM: make the first variable a ROTATION with the same z0")),
    }
}

/// SU2's SetRotation movement of `x` about the axis from `p0` to `p1` (2D: `w = 1`, no z
/// movement) by `degrees`.
fn su2_rotation(x: [f64; 3], p0: [f64; 3], p1: [f64; 3], degrees: f64, three: bool) -> [f64; 3] {
    let [a, b, c] = p0;
    let w = if three { p1[2] - c } else { 1.0 };
    let theta = degrees * std::f64::consts::PI / 180.0;
    let cs = (<f64 as Real>::cos(theta), <f64 as Real>::sin(theta));
    let m = su2_rotation_movement(x, p0, [p1[0] - a, p1[1] - b, w], cs);
    [m[0], m[1], if three { m[2] } else { 0.0 }]
}

/// HICKS_HENNE's `( 0 | 1, x_max )` groups as `(upper, x_max, amplitude)`.
pub(super) fn hicks_henne_params(
    config: &Su2Config,
    dvs: &[Dv],
) -> Result<Vec<(bool, f64, f64)>, CliError> {
    let bad = || {
        option_error(
            config,
            "DV_PARAM",
            "HICKS_HENNE needs ( 0 or 1, x of the peak )",
        )
    };
    (dvs.iter().filter(|d| d.kind == "HICKS_HENNE"))
        .map(|d| {
            let upper = match num(config, &d.params[0], "HICKS_HENNE")? {
                1.0 => true,
                0.0 => false,
                _ => return Err(bad()),
            };
            Ok((
                upper,
                num(config, &d.params[1], "HICKS_HENNE")?,
                d.amplitude,
            ))
        })
        .collect()
}

/// The FFD variables as control-point changes.
pub(super) fn ffd_moves(config: &Su2Config, dvs: &[Dv]) -> Result<Vec<ControlMove>, CliError> {
    let ref_length: f64 = number(config, "REF_LENGTH", 1.0)?;
    dvs.iter()
        .map(|dv| {
            let k = dv.kind.as_str();
            let p = &dv.params;
            let idx = |n: usize, any: bool| index(config, &p[n], any, k);
            let x = |n: usize| num(config, &p[n], k);
            let a = dv.amplitude;
            let change = match k {
                "FFD_CONTROL_POINT" => FfdChange::Point(
                    [idx(1, true)?, idx(2, true)?, idx(3, true)?],
                    [x(4)? * a, x(5)? * a, x(6)? * a],
                ),
                "FFD_CONTROL_POINT_2D" => {
                    FfdChange::Point2d([idx(1, true)?, idx(2, true)?], [x(3)? * a, x(4)? * a])
                }
                "FFD_CAMBER" | "FFD_THICKNESS" => {
                    let ij = [idx(1, false)?.unwrap_or(0), idx(2, false)?.unwrap_or(0)];
                    if k == "FFD_CAMBER" {
                        FfdChange::Camber(ij, a)
                    } else {
                        FfdChange::Thickness(ij, a)
                    }
                }
                "FFD_CAMBER_2D" => FfdChange::Camber2d(idx(1, false)?.unwrap_or(0), a),
                "FFD_THICKNESS_2D" => FfdChange::Thickness2d(idx(1, false)?.unwrap_or(0), a),
                _ => FfdChange::Twist(deform_kernel::design::twist::FfdTwist {
                    j: idx(1, false)?.unwrap_or(0),
                    segment: [[x(2)?, x(3)?, x(4)?], [x(5)?, x(6)?, x(7)?]],
                    amplitude: a,
                    ref_length,
                }),
            };
            let kind = FFD_KINDS
                .iter()
                .find(|&&f| f == k)
                .copied()
                .unwrap_or("FFD");
            Ok(ControlMove {
                tag: p[0].clone(),
                change,
                kind,
            })
        })
        .collect()
}
