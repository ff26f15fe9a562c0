//! SU2's surface design variables for `deform su2`, evaluated by the kernel
//! (`deform_kernel::design`): HICKS_HENNE bumps on a 2D mesh's DV_MARKER nodes, and the FFD
//! design variables (FFD_CONTROL_POINT(_2D), FFD_CAMBER(_2D), FFD_THICKNESS(_2D), FFD_TWIST)
//! on the FFD boxes stored in the mesh file. The result is one displacement per node, as
//! `deform move --displacements` takes it.

use std::collections::BTreeMap;

use deform_kernel::design::ffd::{ffd_displacements, FfdBox};
use deform_kernel::design::hicks_henne::{hicks_henne, HicksHenne};
use deform_kernel::design::twist::{ffd_twist, FfdTwist};
use deform_kernel::design::variables::{
    ffd_camber, ffd_camber_2d, ffd_control_point, ffd_control_point_2d, ffd_thickness,
    ffd_thickness_2d,
};

use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::su2::Su2Mesh;
use crate::formats::su2_ffd::{parse_ffd_boxes, FfdBox as StoredBox};

use super::ffd_planes::{fixed_planes, PlaneRules};

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
pub(super) fn fluid_normals(mesh: &Su2Mesh, markers: &[String], nodes: &[u32]) -> Vec<[f64; 2]> {
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

/// One FFD design variable's change of the control points (amplitudes already times
/// OPT_RELAX_FACTOR; `None` indices are SU2's −1).
#[derive(Clone, Debug)]
pub(super) enum FfdChange {
    Point([Option<usize>; 3], [f64; 3]),
    Point2d([Option<usize>; 2], [f64; 2]),
    Camber([usize; 2], f64),
    Thickness([usize; 2], f64),
    Camber2d(usize, f64),
    Thickness2d(usize, f64),
    Twist(FfdTwist<f64>),
}

/// An FFD design variable: its box tag, its change and its DV_KIND (for messages).
pub(super) struct ControlMove {
    pub tag: String,
    pub change: FfdChange,
    pub kind: &'static str,
}

/// What the FFD design variables need besides the moves: the DV_MARKER markers, the fixed
/// planes' rules and OPT_LINE_SEARCH_BOUND.
pub(super) struct FfdSetup<'a> {
    pub markers: &'a [String],
    pub rules: PlaneRules,
    pub bound: f64,
}

/// The FFD design variables on the boxes stored in the mesh file, as SU2_DEF applies them:
/// every level-0 box, in file order, gets the variables of its tag (skipped where they would
/// move a fixed plane) and is evaluated at its DV_MARKER surface points (minus the mesh point,
/// as SU2's SetCartesianCoord; a node in two boxes takes the last box's value, as in SU2).
pub(super) fn ffd_field(
    mesh: &Su2Mesh,
    moves: &[ControlMove],
    setup: &FfdSetup<'_>,
) -> Result<Field, CliError> {
    let boxes = parse_ffd_boxes(&mesh.passthrough, 1).map_err(|source| CliError::Read {
        path: "MESH_FILENAME (its FFD sections)".into(),
        source,
    })?;
    if let Some(m) = moves.iter().find(|m| !boxes.iter().any(|b| b.tag == m.tag)) {
        return Err(CliError::Invalid(format!(
            "DV_PARAM: the mesh file has no FFD box {:?}",
            m.tag
        )));
    }
    if let Some(b) = boxes.iter().find(|b| b.level > 0) {
        return Err(CliError::Invalid(format!(
            "FFD box {}: level {} (parent/child boxes are not supported)",
            b.tag, b.level
        )));
    }
    let mut field: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
    for b in &boxes {
        let mine: Vec<&ControlMove> = moves.iter().filter(|m| m.tag == b.tag).collect();
        field.extend(box_field(mesh, b, &mine, setup)?);
    }
    Ok(field.into_iter().collect())
}

/// A box's control points in flat order (checked: each listed once, all listed).
pub(super) fn control_points(b: &StoredBox) -> Result<Vec<[f64; 3]>, CliError> {
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
    Ok(cps)
}

/// Whether SU2 skips the variable: an index it names lies on a fixed plane (`k`: the k
/// indices SU2 checks).
pub(super) fn on_fixed(fixed: &[Vec<u32>; 3], ij: [Option<usize>; 2], k: &[usize]) -> bool {
    let hit = |axis: usize, x: usize| fixed[axis].contains(&(x as u32));
    ij.iter()
        .enumerate()
        .any(|(a, x)| x.is_some_and(|x| hit(a, x)))
        || k.iter().any(|&x| hit(2, x))
}

/// FFD_CONTROL_POINT with SU2's fixed-plane rules: skipped if a given index is on a fixed
/// plane; with one −1, the fixed planes along it are left out; with two, nothing is checked.
fn control_point(
    degree: [usize; 3],
    cps: &mut [[f64; 3]],
    fixed: &[Vec<u32>; 3],
    ijk: [Option<usize>; 3],
    m: [f64; 3],
) -> Result<(), deform_kernel::Error> {
    let named = |a: usize| ijk[a].is_some_and(|x| fixed[a].contains(&(x as u32)));
    if (0..3).any(named) {
        return Ok(());
    }
    let free: Vec<usize> = (0..3).filter(|&a| ijk[a].is_none()).collect();
    let [axis] = free[..] else {
        return ffd_control_point(degree, cps, ijk, m);
    };
    for x in (0..=degree[axis]).filter(|&x| !fixed[axis].contains(&(x as u32))) {
        let mut one = ijk;
        one[axis] = Some(x);
        ffd_control_point(degree, cps, one, m)?;
    }
    Ok(())
}

/// Applies one design variable to the control points of a box with fixed planes `fixed`.
pub(super) fn apply(
    degree: [usize; 3],
    cps: &mut [[f64; 3]],
    fixed: &[Vec<u32>; 3],
    change: &FfdChange,
) -> Result<(), deform_kernel::Error> {
    match *change {
        FfdChange::Point(ijk, m) => control_point(degree, cps, fixed, ijk, m),
        FfdChange::Point2d(ij, m) if !on_fixed(fixed, ij, &[0]) => {
            ffd_control_point_2d(degree, cps, ij, m)
        }
        FfdChange::Camber([i, j], a) if !on_fixed(fixed, [Some(i), Some(j)], &[0, 1]) => {
            ffd_camber(degree, cps, i, j, a)
        }
        FfdChange::Thickness([i, j], a) if !on_fixed(fixed, [Some(i), Some(j)], &[0, 1]) => {
            ffd_thickness(degree, cps, i, j, a)
        }
        FfdChange::Camber2d(i, a) => ffd_camber_2d(degree, cps, i, a),
        FfdChange::Thickness2d(i, a) => ffd_thickness_2d(degree, cps, i, a),
        FfdChange::Twist(t) if !on_fixed(fixed, [None, Some(t.j)], &[]) => {
            ffd_twist(degree, cps, t, &fixed[0], &fixed[2])
        }
        _ => Ok(()),
    }
}

/// One box's surface displacements after its design variables.
fn box_field(
    mesh: &Su2Mesh,
    b: &StoredBox,
    moves: &[&ControlMove],
    setup: &FfdSetup<'_>,
) -> Result<Field, CliError> {
    let mut cps = control_points(b)?;
    let [_, m, n] = b.degree;
    let original = cps.clone();
    let cp = |[i, j, k]: [usize; 3]| original[(i * (m + 1) + j) * (n + 1) + k];
    let fixed = fixed_planes(mesh, setup.markers, b.degree, &cp, &setup.rules);
    for mv in moves {
        apply(b.degree, &mut cps, &fixed, &mv.change).map_err(kernel(mv.kind))?;
    }
    let moved = FfdBox::new(b.degree, &cps).map_err(kernel("FFD"))?;
    let surface: Vec<_> = (b.surface.iter())
        .filter(|s| setup.markers.contains(&s.marker))
        .collect();
    let nodes: Vec<u32> = surface.iter().map(|s| s.node).collect();
    let params: Vec<[f64; 3]> = surface.iter().map(|s| s.uvw).collect();
    let mut d = vec![[0.0; 3]; nodes.len()];
    ffd_displacements(&moved, &mesh.points, &nodes, &params, &mut d).map_err(kernel("FFD"))?;
    if mesh.dim == 2 {
        d.iter_mut().for_each(|v| v[2] = 0.0);
    }
    let largest = d
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    if largest > setup.bound {
        return Err(CliError::Invalid(format!(
            "OPT_LINE_SEARCH_BOUND: FFD box {} moves the surface by {largest:e}, more than {:e} (SU2 would rescale OPT_RELAX_FACTOR and apply the variables again; not done here)",
            b.tag, setup.bound
        )));
    }
    Ok(nodes.into_iter().zip(d).collect())
}
