//! SU2's surface design variables for `deform su2`, evaluated by the kernel
//! (`deform_kernel::design`): HICKS_HENNE bumps on a 2D mesh's DV_MARKER nodes, and
//! FFD_CONTROL_POINT(_2D) moves of the FFD boxes stored in the mesh file. The result is one
//! displacement per DV_MARKER node, as `deform move --displacements` takes it.

use std::collections::BTreeMap;

use deform_kernel::design::ffd::{ffd_displacements, FfdBox};
use deform_kernel::design::hicks_henne::{hicks_henne, HicksHenne};
use deform_kernel::design::variables::{ffd_control_point, ffd_control_point_2d};

use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_ffd::{parse_ffd_boxes, FfdBox as StoredBox};

/// A displacement per node, ascending by node.
pub(super) type Field = Vec<(u32, [f64; 3])>;

/// A kernel error in the design variables, named by the option.
fn kernel(what: &str) -> impl Fn(deform_kernel::Error) -> CliError + '_ {
    move |source| CliError::Kernel {
        context: format!("DV_KIND= {what}"),
        source,
    }
}

/// The 2D normals of the `nodes` of the `markers` (summed over their boundary edges, each
/// turned to point into the fluid: towards the volume cell on the edge, SU2's convention).
fn fluid_normals(mesh: &Su2Mesh, markers: &[String], nodes: &[u32]) -> Vec<[f64; 2]> {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut edges: BTreeMap<(u32, u32), Option<[f64; 2]>> = BTreeMap::new();
    for m in mesh.markers.iter().filter(|m| markers.contains(&m.name)) {
        for (_, e) in m.elements.iter() {
            if let [a, b] = e {
                edges.insert(key(*a, *b), None);
            }
        }
    }
    let point = |n: u32| mesh.points.get(n as usize).copied().unwrap_or([0.0; 3]);
    for (_, cell) in mesh.elements.iter() {
        let k = cell.len() as f64;
        let c = cell.iter().fold([0.0; 2], |s, &n| {
            [s[0] + point(n)[0] / k, s[1] + point(n)[1] / k]
        });
        for (i, &a) in cell.iter().enumerate() {
            let b = cell[(i + 1) % cell.len()];
            if let Some(slot @ None) = edges.get_mut(&key(a, b)) {
                *slot = Some(c);
            }
        }
    }
    let mut normals = vec![[0.0; 2]; nodes.len()];
    for (&(a, b), centroid) in &edges {
        let (pa, pb) = (point(a), point(b));
        let mut n = [pb[1] - pa[1], pa[0] - pb[0]];
        if let Some(c) = centroid {
            let mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
            if (c[0] - mid[0]) * n[0] + (c[1] - mid[1]) * n[1] < 0.0 {
                n = [-n[0], -n[1]];
            }
        }
        for v in [a, b] {
            if let Ok(p) = nodes.binary_search(&v) {
                normals[p] = [normals[p][0] + n[0], normals[p][1] + n[1]];
            }
        }
    }
    normals
}

/// HICKS_HENNE: one bump per design variable, `(upper, x_max, amplitude)`, added up on the
/// DV_MARKER nodes of a 2D mesh (x as SU2 uses it: not normalised by the chord).
pub(super) fn hicks_henne_field(
    mesh: &Su2Mesh,
    markers: &[String],
    bumps: &[(bool, f64, f64)],
) -> Result<Field, CliError> {
    let nodes = marker_nodes(mesh, markers, std::path::Path::new("DV_MARKER"))?;
    let normals = fluid_normals(mesh, markers, &nodes);
    let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let mut d = vec![[0.0; 2]; nodes.len()];
    for &(upper, x_max, amplitude) in bumps {
        let bump = HicksHenne {
            upper,
            x_max,
            amplitude,
        };
        hicks_henne(&points, &nodes, &normals, bump, &mut d).map_err(kernel("HICKS_HENNE"))?;
    }
    Ok(nodes
        .into_iter()
        .zip(d)
        .map(|(n, d)| (n, [d[0], d[1], 0.0]))
        .collect())
}

/// One FFD control-point move: box tag, `(i, j, k)` (`None`: every index, SU2's −1) and the
/// movement; `two_d` for FFD_CONTROL_POINT_2D (both k layers, no z).
pub(super) struct ControlMove {
    pub tag: String,
    pub ijk: [Option<usize>; 3],
    pub movement: [f64; 3],
    pub two_d: bool,
}

/// FFD_CONTROL_POINT(_2D): the boxes stored in the mesh file, their control points moved,
/// evaluated at their surface points' stored parametric coordinates (minus the mesh point, as
/// SU2's SetCartesianCoord).
pub(super) fn ffd_field(mesh: &Su2Mesh, moves: &[ControlMove]) -> Result<Field, CliError> {
    let boxes = parse_ffd_boxes(&mesh.passthrough, 1).map_err(|source| CliError::Read {
        path: "MESH_FILENAME (its FFD sections)".into(),
        source,
    })?;
    let mut field: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
    for b in &boxes {
        let mine: Vec<&ControlMove> = moves.iter().filter(|m| m.tag == b.tag).collect();
        if mine.is_empty() {
            continue;
        }
        for (node, d) in box_field(mesh, b, &mine)? {
            if field.insert(node, d).is_some() {
                return Err(CliError::Invalid(format!(
                    "FFD boxes: node {node} is in two boxes that move (parent/child boxes are not supported)"
                )));
            }
        }
    }
    if let Some(m) = moves.iter().find(|m| !boxes.iter().any(|b| b.tag == m.tag)) {
        return Err(CliError::Invalid(format!(
            "DV_PARAM: the mesh file has no FFD box {:?}",
            m.tag
        )));
    }
    Ok(field.into_iter().collect())
}

/// One box's surface displacements after its control-point moves.
fn box_field(mesh: &Su2Mesh, b: &StoredBox, moves: &[&ControlMove]) -> Result<Field, CliError> {
    let [l, m, n] = b.degree;
    let mut cps = vec![[0.0f64; 3]; (l + 1) * (m + 1) * (n + 1)];
    let mut seen = vec![false; cps.len()];
    for &([i, j, k], p) in &b.control {
        let at = (i * (m + 1) + j) * (n + 1) + k;
        match (i <= l && j <= m && k <= n, seen.get_mut(at)) {
            (true, Some(s)) if !*s => {
                *s = true;
                cps[at] = p;
            }
            _ => {
                return Err(CliError::Invalid(format!(
                "FFD box {}: control point ({i}, {j}, {k}) is out of its degrees or listed twice",
                b.tag
            )))
            }
        }
    }
    if seen.iter().any(|s| !s) {
        return Err(CliError::Invalid(format!(
            "FFD box {}: the mesh file lists {} of its {} control points (run SU2_DEF with FFD_SETTING first)",
            b.tag,
            b.control.len(),
            cps.len()
        )));
    }
    for mv in moves {
        let r = if mv.two_d {
            let [dx, dy, _] = mv.movement;
            ffd_control_point_2d(b.degree, &mut cps, [mv.ijk[0], mv.ijk[1]], [dx, dy])
        } else {
            ffd_control_point(b.degree, &mut cps, mv.ijk, mv.movement)
        };
        r.map_err(kernel("FFD_CONTROL_POINT"))?;
    }
    let moved = FfdBox::new(b.degree, &cps).map_err(kernel("FFD_CONTROL_POINT"))?;
    let nodes: Vec<u32> = b.surface.iter().map(|s| s.node).collect();
    let params: Vec<[f64; 3]> = b.surface.iter().map(|s| s.uvw).collect();
    let mut d = vec![[0.0; 3]; nodes.len()];
    ffd_displacements(&moved, &mesh.points, &nodes, &params, &mut d)
        .map_err(kernel("FFD_CONTROL_POINT"))?;
    if mesh.dim == 2 {
        d.iter_mut().for_each(|v| v[2] = 0.0);
    }
    Ok(nodes.into_iter().zip(d).collect())
}
