//! Orientation: clockwise (2D) and left-handed (3D) meshes are valid, and folds are counted
//! against each connected region's own orientation. The expected counts come from an
//! independent corner-cross-product count written here, not from the tool's quality code.

mod common;

use std::path::Path;
use std::process::Command;

use common::{su2_bytes, tmp_dir};
use deform_cli::formats::su2::Su2Mesh;
use serde_json::Value;

fn deform_json(dir: &Path, args: &[&str]) -> Value {
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .arg("--json")
        .args(args)
        .output()
        .expect("run deform");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("JSON report")
}

fn tiny_viscous(dir: &Path) -> Su2Mesh {
    deform_json(
        dir,
        &[
            "mesh",
            "naca",
            "--code",
            "2412",
            "--kind",
            "viscous",
            "--out",
            "ccw.su2",
            "--surface-points",
            "32",
            "--radial-points",
            "12",
            "--boundary-layers",
            "4",
            "--first-layer",
            "0.01",
        ],
    );
    deform_cli::parse_su2(&std::fs::read(dir.join("ccw.su2")).unwrap()).unwrap()
}

/// Per 2D cell (triangles and quads): the signs of its corner cross products.
fn corner_signs(mesh: &Su2Mesh, c: usize) -> Vec<f64> {
    let e = &mesh.elements;
    let nodes = &e.nodes[e.offsets[c] as usize..e.offsets[c + 1] as usize];
    let k = nodes.len();
    (0..k)
        .map(|i| {
            let p = mesh.points[nodes[i] as usize];
            let a = mesh.points[nodes[(i + 1) % k] as usize];
            let b = mesh.points[nodes[(i + k - 1) % k] as usize];
            let cross = (a[0] - p[0]) * (b[1] - p[1]) - (a[1] - p[1]) * (b[0] - p[0]);
            cross.signum()
        })
        .collect()
}

/// Independent fold count for a connected 2D mesh: the mesh's sense is the sign most cells'
/// corners agree on; a cell is folded when some corner has the other sign.
fn folded_against_majority(mesh: &Su2Mesh) -> (usize, f64) {
    let signs: Vec<Vec<f64>> = (0..mesh.elements.len())
        .map(|c| corner_signs(mesh, c))
        .collect();
    let positive = signs.iter().filter(|s| s.iter().all(|&x| x > 0.0)).count();
    let negative = signs.iter().filter(|s| s.iter().all(|&x| x < 0.0)).count();
    let sense = if negative > positive { -1.0 } else { 1.0 };
    let folded = signs
        .iter()
        .filter(|s| s.iter().any(|&x| x == -sense))
        .count();
    (folded, sense)
}

fn mirrored(mesh: &Su2Mesh) -> Su2Mesh {
    let mut m = mesh.clone();
    for p in &mut m.points {
        p[0] = -p[0];
    }
    m
}

#[test]
fn a_clockwise_mesh_is_valid_and_its_real_folds_are_found() {
    let d = tmp_dir("orientation-cw");
    let ccw = tiny_viscous(&d);
    let cw = mirrored(&ccw);
    assert_eq!(folded_against_majority(&cw), (0, -1.0));
    std::fs::write(d.join("cw.su2"), su2_bytes(&cw)).unwrap();
    let q = deform_json(&d, &["quality", "cw.su2"]);
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["nonpositive_cells"], 0, "{q}");
    assert_eq!(q["degenerate_cells"], 0, "{q}");
    assert_eq!(q["orientation"]["negative_regions"], 1, "{q}");
    assert_eq!(q["orientation"]["positive_regions"], 0, "{q}");

    // A real fold in the clockwise mesh: push one wall-adjacent node through its neighbours.
    let mut folded = cw.clone();
    let wall = folded.marker("airfoil").unwrap().elements.nodes[0] as usize;
    let target = folded.points.len() / 2;
    let (w, t) = (folded.points[wall], folded.points[target]);
    folded.points[target] = [2.0 * w[0] - t[0], 2.0 * w[1] - t[1], 0.0];
    let (expected, sense) = folded_against_majority(&folded);
    assert_eq!(sense, -1.0);
    assert!(expected > 0, "the edit must fold cells");
    std::fs::write(d.join("folded.su2"), su2_bytes(&folded)).unwrap();
    let q = deform_json(&d, &["quality", "folded.su2"]);
    assert_eq!(q["folded_cells"], expected, "{q}");
    let q = deform_json(&d, &["quality", "folded.su2", "--reference", "cw.su2"]);
    assert_eq!(q["folded_cells"], expected, "{q}");
}

#[test]
fn a_clockwise_mesh_moved_rigidly_reports_no_folds() {
    let d = tmp_dir("orientation-move");
    let cw = mirrored(&tiny_viscous(&d));
    std::fs::write(d.join("cw.su2"), su2_bytes(&cw)).unwrap();
    let r = deform_json(
        &d,
        &[
            "move",
            "cw.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "5",
            "--center",
            "-0.25,0",
            "--method",
            "quaternion",
            "--out",
            "moved.su2",
        ],
    );
    let moved = deform_cli::parse_su2(&std::fs::read(d.join("moved.su2")).unwrap()).unwrap();
    assert_eq!(r["folded_cells"], folded_against_majority(&moved).0, "{r}");
    assert_eq!(r["folded_cells"], 0, "{r}");
    assert_eq!(r["orientation"], "clockwise", "{r}");
}

#[test]
fn regions_of_opposite_orientation_are_each_valid() {
    let d = tmp_dir("orientation-regions");
    let ccw = tiny_viscous(&d);
    // Two copies side by side, the second mirrored: two regions, one each way.
    let mut both = ccw.clone();
    let n = ccw.points.len() as u32;
    both.points
        .extend(ccw.points.iter().map(|p| [-p[0] - 100.0, p[1], p[2]]));
    let e = &ccw.elements;
    for c in 0..e.len() {
        let nodes: Vec<u32> = e.nodes[e.offsets[c] as usize..e.offsets[c + 1] as usize]
            .iter()
            .map(|&v| v + n)
            .collect();
        let kind = deform_kernel::CellKind::from_vtk(e.kinds[c]).unwrap();
        both.elements.push(kind, &nodes);
    }
    std::fs::write(d.join("both.su2"), su2_bytes(&both)).unwrap();
    let q = deform_json(&d, &["quality", "both.su2"]);
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["orientation"]["regions"], 2, "{q}");
    assert_eq!(q["orientation"]["negative_regions"], 1, "{q}");
    let text = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .args(["quality", "both.su2"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("mixed (1 regions counter-clockwise, 1 clockwise)"),
        "{text}"
    );
}

/// A 2×2×2-cell hexahedral box (VTK-positive node order), SU2 3D.
fn hex_box() -> Su2Mesh {
    use deform_cli::formats::CellList;
    let id = |i: u32, j: u32, k: u32| i + 3 * j + 9 * k;
    let mut points = Vec::new();
    for k in 0..3 {
        for j in 0..3 {
            for i in 0..3 {
                points.push([i as f64, j as f64, k as f64]);
            }
        }
    }
    let mut elements = CellList::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..2 {
                elements.push(
                    deform_kernel::CellKind::Hexahedron,
                    &[
                        id(i, j, k),
                        id(i + 1, j, k),
                        id(i + 1, j + 1, k),
                        id(i, j + 1, k),
                        id(i, j, k + 1),
                        id(i + 1, j, k + 1),
                        id(i + 1, j + 1, k + 1),
                        id(i, j + 1, k + 1),
                    ],
                );
            }
        }
    }
    Su2Mesh {
        dim: 3,
        points,
        elements,
        markers: Vec::new(),
        passthrough: Vec::new(),
        text: Default::default(),
    }
}

#[test]
fn a_left_handed_3d_mesh_is_valid_and_a_collapsed_edge_is_degenerate() {
    let d = tmp_dir("orientation-3d");
    let left = mirrored(&hex_box());
    std::fs::write(d.join("left.su2"), su2_bytes(&left)).unwrap();
    let q = deform_json(&d, &["quality", "left.su2"]);
    assert_eq!(q["folded_cells"], 0, "{q}");
    assert_eq!(q["degenerate_cells"], 0, "{q}");
    assert_eq!(q["orientation"]["negative_regions"], 1, "{q}");
    let text = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .args(["quality", "left.su2"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(text.contains("left-handed"), "{text}");
    assert!(text.contains("min volume"), "{text}");
    assert!(!text.contains("area"), "{text}");

    // Collapse the corner edge (0,0,0)-(0,0,1) of the box onto a line, as on a singular axis:
    // node (0,0,1) moves onto node (0,0,0). The one cell that has both nodes gets zero corner
    // Jacobians and no negative one: degenerate, not folded.
    let mut collapsed = left.clone();
    collapsed.points[9] = collapsed.points[0];
    std::fs::write(d.join("collapsed.su2"), su2_bytes(&collapsed)).unwrap();
    let q = deform_json(&d, &["quality", "collapsed.su2"]);
    assert_eq!(q["degenerate_cells"], 1, "{q}");
    assert_eq!(q["folded_cells"], 0, "{q}");
}
