//! The motion of `deform move` on SU2 meshes: from `--motions` (one rigid motion per marker),
//! a displacement or surface-position file, `--translate` or `--rotate`.

use std::path::Path;

use crate::args::{Coords, MoveArgs};
use crate::engine::Motion;
use crate::error::CliError;
use crate::files::{marker_nodes, read_bytes};
use crate::formats::displacements::{parse_displacements, parse_surface_positions};
use crate::formats::motions::{parse_motions, MarkerMotionSpec};
use crate::formats::su2::Su2Mesh;

/// `(node, displacement)` pairs, ascending by node.
pub(super) type NodeDisplacements = Vec<(u32, [f64; 3])>;

/// `--motions`: the markers' specs and their motions as one displacement field.
pub(super) type PerMarker = Option<(Vec<MarkerMotionSpec>, NodeDisplacements)>;

/// The motion the arguments ask for, and the surface positions to place exactly afterwards
/// (old + (new − old) can differ from new in the last bit). `moved` (ascending) are the nodes
/// of the moved markers: a file may move only those.
pub(super) fn motion_from_args(
    a: &MoveArgs,
    mesh: &Su2Mesh,
    moved: &[u32],
    per_marker: &PerMarker,
) -> Result<(Motion, NodeDisplacements), CliError> {
    if let Some((_, field)) = per_marker {
        return Ok((Motion::Field(field.clone()), Vec::new()));
    }
    if let Some(field) = &a.design_field {
        return Ok((Motion::Field(field.clone()), Vec::new()));
    }
    let table = match (&a.displacements, &a.surface_positions) {
        (Some(path), _) => Some((path, false)),
        (None, Some(path)) => Some((path, true)),
        (None, None) => None,
    };
    if let Some((path, absolute)) = table {
        return file_motion(path, absolute, mesh, moved);
    }
    let xyz = |v: &[f64], z: f64| {
        [
            v.first().copied().unwrap_or(0.0),
            v.get(1).copied().unwrap_or(0.0),
            v.get(2).copied().unwrap_or(z),
        ]
    };
    if let Some(Coords(t)) = &a.translate {
        return Ok((Motion::Translate(xyz(t, 0.0)), Vec::new()));
    }
    let axis = a
        .axis
        .as_ref()
        .map_or([0.0, 0.0, 1.0], |Coords(v)| xyz(v, 1.0));
    let center = a.center.as_ref().map(|Coords(c)| xyz(c, 0.0));
    let rotate = Motion::Rotate {
        degrees: a.rotate.unwrap_or(0.0),
        axis,
        center,
    };
    Ok((rotate, Vec::new()))
}

/// A `--displacements` (or, `absolute`, `--surface-positions`) file as displacements of moved
/// nodes, with the positions to place exactly.
fn file_motion(
    path: &Path,
    absolute: bool,
    mesh: &Su2Mesh,
    moved: &[u32],
) -> Result<(Motion, NodeDisplacements), CliError> {
    let bytes = read_bytes(path)?;
    let parse = if absolute {
        parse_surface_positions
    } else {
        parse_displacements
    };
    let mut list = parse(&bytes, mesh.dim).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut exact_positions = Vec::new();
    if absolute {
        exact_positions = list.clone();
        // New positions → displacements from the mesh's own coordinates.
        for (node, p) in &mut list {
            let Some(old) = mesh.points.get(*node as usize) else {
                return Err(CliError::Invalid(format!(
                    "{}: node {node} is not in the mesh ({} points)",
                    path.display(),
                    mesh.points.len()
                )));
            };
            for (c, o) in p.iter_mut().zip(old) {
                *c -= o;
            }
        }
    }
    for (node, _) in &list {
        if moved.binary_search(node).is_err() {
            return Err(CliError::Invalid(format!(
                "{}: node {node} is not on the moved markers",
                path.display()
            )));
        }
    }
    Ok((Motion::Field(list), exact_positions))
}

/// A marker's rigid motion in words, for the report.
pub(super) fn describe(m: &Motion, dim: usize) -> String {
    match m {
        Motion::Rotate {
            degrees, center, ..
        } => match center {
            Some(c) => format!("rotate {degrees} deg about {:?}", &c[..dim]),
            None => format!("rotate {degrees} deg about its centroid"),
        },
        Motion::Translate(t) => format!("translate {:?}", &t[..dim]),
        Motion::Field(list) => format!("displacements of {} nodes", list.len()),
    }
}

/// A displacement as a function of the point it moves.
type PointMotion = Box<dyn Fn([f64; 3]) -> [f64; 3]>;

/// Reads a `--motions` file and turns every marker's rigid motion into displacements of its
/// nodes (`(node, d)`, ascending): `c + Q (p − c) − p` for a rotation (centre: given, or the
/// centroid of the marker's nodes), `t` for a translation. A node on two markers must get the
/// same displacement (bit for bit) from both. `--steps` > 1 scales displacements linearly, which
/// would shrink a rotating marker between steps, so it is refused when any marker rotates.
pub(super) fn marker_motions_field(
    mesh: &Su2Mesh,
    path: &Path,
    steps: u32,
) -> Result<(Vec<MarkerMotionSpec>, NodeDisplacements), CliError> {
    let bytes = read_bytes(path)?;
    let specs = parse_motions(&bytes, mesh.dim).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    if steps > 1
        && specs
            .iter()
            .any(|m| matches!(m.motion, Motion::Rotate { .. }))
    {
        return Err(CliError::NotAvailable {
            feature: "--steps with per-marker rotations from --motions",
            needs: "one step, or --rotate for a single rigid rotation in steps",
        });
    }
    let mut field: std::collections::BTreeMap<u32, ([f64; 3], usize)> =
        std::collections::BTreeMap::new();
    for (k, spec) in specs.iter().enumerate() {
        let nodes = marker_nodes(mesh, std::slice::from_ref(&spec.marker), path)?;
        let displacement = rigid_displacement(mesh, path, spec, &nodes)?;
        let point = |n: u32| mesh.points.get(n as usize).copied().unwrap_or([0.0; 3]);
        for &n in &nodes {
            let d = displacement(point(n));
            match field.get(&n) {
                Some((other, j)) if other.map(f64::to_bits) != d.map(f64::to_bits) => {
                    return Err(CliError::Invalid(format!(
                        "{}: node {n} is on markers {:?} and {:?}, which move it differently (lines {} and {})",
                        path.display(),
                        specs[*j].marker,
                        spec.marker,
                        specs[*j].line,
                        spec.line
                    )));
                }
                _ => {
                    field.insert(n, (d, k));
                }
            }
        }
    }
    Ok((specs, field.into_iter().map(|(n, (d, _))| (n, d)).collect()))
}

/// One marker's rigid motion as a function of the point (`nodes`: the marker's, for the
/// centroid when no centre is given).
fn rigid_displacement(
    mesh: &Su2Mesh,
    path: &Path,
    spec: &MarkerMotionSpec,
    nodes: &[u32],
) -> Result<PointMotion, CliError> {
    let point = |n: u32| mesh.points.get(n as usize).copied().unwrap_or([0.0; 3]);
    match &spec.motion {
        Motion::Translate(t) => {
            let t = *t;
            Ok(Box::new(move |_| t))
        }
        Motion::Rotate {
            degrees,
            axis,
            center,
        } => {
            let c = center.unwrap_or_else(|| {
                let n = nodes.len().max(1) as f64;
                let s = nodes.iter().fold([0.0; 3], |s, &i| {
                    let p = point(i);
                    [s[0] + p[0], s[1] + p[1], s[2] + p[2]]
                });
                [s[0] / n, s[1] / n, s[2] / n]
            });
            let q = deform_kernel::Quat::from_axis_angle(*axis, degrees.to_radians()).map_err(
                |source| CliError::Kernel {
                    context: format!("{}: line {}: rotation", path.display(), spec.line),
                    source,
                },
            )?;
            let dim = mesh.dim;
            Ok(Box::new(move |p: [f64; 3]| {
                let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
                let mut d = [0, 1, 2].map(|i| c[i] + r[i] - p[i]);
                if dim == 2 {
                    d[2] = 0.0;
                }
                d
            }))
        }
        // parse_motions gives rigid motions only.
        Motion::Field(_) => Err(CliError::Invalid(format!(
            "{}: line {}: a motion file gives rigid motions only",
            path.display(),
            spec.line
        ))),
    }
}
