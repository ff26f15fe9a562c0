//! SU2_DOT's projection for `deform adjoint --config`: the surface sensitivity `dJ/dx` (at
//! every node, from the deformation's adjoint) onto the design variables of an SU2 config,
//! `dJ/dα_k = Σ_p dJ/dx_p · dx_p/dα_k` at `α = 0` (SU2_DOT's point: `SetProjection_AD`
//! registers every DV_VALUE as 0), through the kernel's `design::sensitivity`. Covered:
//! TRANSLATION, ROTATION, HICKS_HENNE and the FFD variables `deform su2` applies (FFD_CONTROL_POINT(_2D),
//! FFD_CAMBER(_2D), FFD_THICKNESS(_2D), FFD_TWIST), with SU2_DEF's fixed planes and
//! OPT_RELAX_FACTOR, exactly as `deform su2` moves the surface. MARKER_DEFORM_MESH_SYM_PLANE
//! markers slide in the deformation's adjoint as in `deform su2` (`--method spring` and
//! single-step `elasticity`; the other methods refuse them before any solve).

use std::collections::BTreeSet;

use deform_kernel::design::sensitivity::{ffd_adjoint, hicks_henne_adjoint};
use deform_kernel::design::twist::ffd_twist_tangent;

use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_config::{list_items, Su2Config};
use crate::formats::su2_ffd::{parse_ffd_boxes, FfdBox as StoredBox};

use super::design::FfdSetup;
use super::design::{apply, control_points, fluid_normals, on_fixed, FfdChange};
use super::ffd_planes::{fixed_planes, setup};
use super::variables::{dv_numbers, ffd_moves, hicks_henne_params, read_dvs, rotation_z0, Dv};
use super::{design_markers, number, option_error};

/// `dJ/dα` for each design variable (one value each), and the objective's name as SU2_DOT
/// writes it in `of_grad.dat`'s first line.
pub(crate) struct Gradient {
    pub objective: String,
    pub values: Vec<f64>,
    /// `OUTPUT_PRECISION` (6 unless set), the digits SU2_DOT writes.
    pub precision: usize,
}

fn kernel(what: &str) -> impl Fn(deform_kernel::Error) -> CliError + '_ {
    move |source| CliError::Kernel {
        context: format!("DV_KIND= {what} (gradient)"),
        source,
    }
}

/// The gradient of the config's design variables for the sensitivity `g` (`dJ/dx` at every
/// node of `mesh`, z = 0 in 2D).
pub(crate) fn design_gradient(
    config: &Su2Config,
    mesh: &Su2Mesh,
    g: &[[f64; 3]],
) -> Result<Gradient, CliError> {
    let dvs = read_dvs(config)?;
    let markers = design_markers(config)?;
    let relax: f64 = number(config, "OPT_RELAX_FACTOR", 1.0)?;
    let mut values = Vec::with_capacity(dvs.len());
    let mut boxes = None;
    for dv in &dvs {
        let value = match dv.kind.as_str() {
            "HICKS_HENNE" => relax * hicks_henne_gradient(config, dv, mesh, &markers, g)?,
            "TRANSLATION" | "ROTATION" => {
                relax * rigid_gradient(config, (&dvs, dv), mesh, &markers, g)?
            }
            k if k.starts_with("FFD_") => {
                if boxes.is_none() {
                    boxes = Some(box_adjoints(config, mesh, &markers, g)?);
                }
                let (b, _) = boxes.as_ref().ok_or(CliError::Invalid("FFD".into()))?;
                ffd_gradient(config, dv, relax, b, mesh)?
            }
            k => {
                return Err(option_error(
                    config,
                    "DV_KIND",
                    format!(
                        "{k}: deform adjoint --config projects HICKS_HENNE and the FFD variables"
                    ),
                ))
            }
        };
        values.push(value);
    }
    let objective = config
        .get("OBJECTIVE_FUNCTION")
        .and_then(|e| list_items(&e.value).first().map(|s| s.to_ascii_uppercase()))
        .unwrap_or_else(|| "DRAG".into());
    let precision = number(config, "OUTPUT_PRECISION", 6usize)?;
    Ok(Gradient {
        objective,
        values,
        precision,
    })
}

/// One HICKS_HENNE variable's `dJ/da` on the DV_MARKER nodes of a 2D mesh.
fn hicks_henne_gradient(
    config: &Su2Config,
    dv: &Dv,
    mesh: &Su2Mesh,
    markers: &[String],
    g: &[[f64; 3]],
) -> Result<f64, CliError> {
    if mesh.dim != 2 {
        return Err(option_error(
            config,
            "DV_KIND",
            "HICKS_HENNE needs a 2D mesh",
        ));
    }
    let (upper, x_max, _) = hicks_henne_params(config, std::slice::from_ref(dv))?[0];
    let nodes = marker_nodes(mesh, markers, std::path::Path::new("DV_MARKER"))?;
    let normals = fluid_normals(mesh, markers, &nodes);
    let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let gn: Vec<[f64; 2]> = nodes
        .iter()
        .map(|&n| [g[n as usize][0], g[n as usize][1]])
        .collect();
    hicks_henne_adjoint(&points, &nodes, &normals, upper, x_max, &gn).map_err(kernel("HICKS_HENNE"))
}

/// One TRANSLATION's or ROTATION's `dJ/da` on the DV_MARKER nodes (`deform su2`'s movement
/// differentiated at 0: the direction `(dx, dy, dz)`; `ω × (x − c)` with `ω` the unit axis
/// times π/180 per degree, c with SU2's z0 of the first variable).
fn rigid_gradient(
    config: &Su2Config,
    (dvs, dv): (&[Dv], &Dv),
    mesh: &Su2Mesh,
    markers: &[String],
    g: &[[f64; 3]],
) -> Result<f64, CliError> {
    let p = dv_numbers(config, dv, mesh.dim)?;
    let three = mesh.dim == 3;
    let nodes = marker_nodes(mesh, markers, std::path::Path::new("DV_MARKER"))?;
    let rate: Box<dyn Fn([f64; 3]) -> [f64; 3]> = if dv.kind == "TRANSLATION" {
        Box::new(|_| [p[0], p[1], p[2]])
    } else {
        let z0 = rotation_z0(config, dvs, dv, three)?;
        let a = [
            p[3] - p[0],
            p[4] - p[1],
            if three { p[5] - z0 } else { 1.0 },
        ];
        let len = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        let w = a.map(|c| c / len * std::f64::consts::PI / 180.0);
        let c = [p[0], p[1], z0];
        Box::new(move |x: [f64; 3]| {
            let r = [x[0] - c[0], x[1] - c[1], x[2] - c[2]];
            [
                w[1] * r[2] - w[2] * r[1],
                w[2] * r[0] - w[0] * r[2],
                w[0] * r[1] - w[1] * r[0],
            ]
        })
    };
    Ok((nodes.iter().map(|&n| n as usize))
        .map(|n| {
            let (v, gn) = (rate(mesh.points[n]), g[n]);
            v[0] * gn[0] + v[1] * gn[1] + if three { v[2] * gn[2] } else { 0.0 }
        })
        .sum())
}

/// A box with its original control points, fixed planes and `P̄ = Σ_p B(u_p) dJ/dx_p`.
struct BoxAdjoint {
    tag: String,
    degree: [usize; 3],
    control: Vec<[f64; 3]>,
    fixed: [Vec<u32>; 3],
    bar: Vec<[f64; 3]>,
}

/// Every level-0 box's control-point adjoint over its DV_MARKER surface points; a node in
/// two boxes counts for the later one only (SU2_DEF's SetCartesianCoord overwrites).
fn box_adjoints<'a>(
    config: &Su2Config,
    mesh: &Su2Mesh,
    markers: &'a [String],
    g: &[[f64; 3]],
) -> Result<(Vec<BoxAdjoint>, FfdSetup<'a>), CliError> {
    let setup = setup(config, markers)?;
    let boxes = parse_ffd_boxes(&mesh.passthrough, 1).map_err(|source| CliError::Read {
        path: "MESH_FILENAME (its FFD sections)".into(),
        source,
    })?;
    if let Some(b) = boxes.iter().find(|b| b.level > 0) {
        return Err(CliError::Invalid(format!(
            "FFD box {}: level {} (parent/child boxes are not supported)",
            b.tag, b.level
        )));
    }
    let mut later: BTreeSet<u32> = BTreeSet::new();
    let mut out = Vec::new();
    for b in boxes.iter().rev() {
        out.push(box_adjoint(mesh, b, &setup, g, &later)?);
        later.extend(surface(b, markers).map(|s| s.node));
    }
    out.reverse();
    Ok((out, setup))
}

/// The DV_MARKER surface points of a box.
fn surface<'b>(
    b: &'b StoredBox,
    markers: &'b [String],
) -> impl Iterator<Item = &'b crate::formats::su2_ffd::FfdSurfacePoint> {
    b.surface.iter().filter(|s| markers.contains(&s.marker))
}

fn box_adjoint(
    mesh: &Su2Mesh,
    b: &StoredBox,
    setup: &FfdSetup<'_>,
    g: &[[f64; 3]],
    later: &BTreeSet<u32>,
) -> Result<BoxAdjoint, CliError> {
    let control = control_points(b)?;
    let [_, m, n] = b.degree;
    let cp = |[i, j, k]: [usize; 3]| control[(i * (m + 1) + j) * (n + 1) + k];
    let fixed = fixed_planes(mesh, setup.markers, b.degree, &cp, &setup.rules);
    let own: Vec<_> = surface(b, setup.markers)
        .filter(|s| !later.contains(&s.node))
        .collect();
    let params: Vec<[f64; 3]> = own.iter().map(|s| s.uvw).collect();
    let gs: Vec<[f64; 3]> = (own.iter())
        .map(|s| g.get(s.node as usize).copied().unwrap_or([0.0; 3]))
        .collect();
    let mut bar = vec![[0.0; 3]; control.len()];
    ffd_adjoint(b.degree, &params, &gs, &mut bar).map_err(kernel("FFD"))?;
    Ok(BoxAdjoint {
        tag: b.tag.clone(),
        degree: b.degree,
        control,
        fixed,
        bar,
    })
}

/// One FFD variable's `dJ/dDV_VALUE`: its control-point change per unit DV_VALUE (times
/// OPT_RELAX_FACTOR) dotted with the adjoint of its box.
fn ffd_gradient(
    config: &Su2Config,
    dv: &Dv,
    relax: f64,
    boxes: &[BoxAdjoint],
    mesh: &Su2Mesh,
) -> Result<f64, CliError> {
    let unit = Dv {
        kind: dv.kind.clone(),
        params: dv.params.clone(),
        amplitude: relax,
    };
    let mv = ffd_moves(config, std::slice::from_ref(&unit))?.remove(0);
    let mine: Vec<&BoxAdjoint> = boxes.iter().filter(|b| b.tag == mv.tag).collect();
    if mine.is_empty() {
        return Err(CliError::Invalid(format!(
            "DV_PARAM: the mesh file has no FFD box {:?}",
            mv.tag
        )));
    }
    let mut sum = 0.0;
    for b in mine {
        let mut delta = vec![[0.0; 3]; b.control.len()];
        match mv.change {
            FfdChange::Twist(t) if !on_fixed(&b.fixed, [None, Some(t.j)], &[]) => {
                ffd_twist_tangent(
                    b.degree,
                    &b.control,
                    t,
                    &b.fixed[0],
                    &b.fixed[2],
                    &mut delta,
                )
                .map_err(kernel(mv.kind))?;
                delta.iter_mut().flatten().for_each(|x| *x *= relax);
            }
            FfdChange::Twist(_) => {}
            ref change => apply(b.degree, &mut delta, &b.fixed, change).map_err(kernel(mv.kind))?,
        }
        if mesh.dim == 2 {
            delta.iter_mut().for_each(|d| d[2] = 0.0);
        }
        sum += (delta.iter().zip(&b.bar))
            .map(|(d, p)| d[0] * p[0] + d[1] * p[1] + d[2] * p[2])
            .sum::<f64>();
    }
    Ok(sum)
}

/// `x` as C++'s `ostream << x` writes it with `precision(p)` and the default float format
/// (`%.{p}g`: the shorter of fixed and scientific, trailing zeros dropped).
pub(crate) fn cpp_general(x: f64, p: usize) -> String {
    if !x.is_finite() {
        return format!("{x}");
    }
    let p = p.max(1);
    let sci = format!("{:.*e}", p - 1, x);
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let trim = |s: &str| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    if exp < -4 || exp >= p as i32 {
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim(mantissa), exp.abs())
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        trim(&format!("{x:.decimals$}"))
    }
}
