//! `deform move` accepts SU2_DEF's surface-position files, reports the maximum displacement
//! and each marker's motion, and refuses a 3D rotation centre on a 2D mesh.

mod common;

use std::path::Path;

use common::{deform, tmp_dir};
use serde_json::Value;

fn json(dir: &Path, args: &[&str]) -> Value {
    let mut v = vec!["--json"];
    v.extend_from_slice(args);
    let o = deform(dir, &v);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).unwrap()
}

fn naca(dir: &Path) -> deform_cli::formats::su2::Su2Mesh {
    let o = deform(
        dir,
        &[
            "mesh",
            "naca",
            "--code",
            "2412",
            "--kind",
            "inviscid",
            "--out",
            "m.su2",
            "--surface-points",
            "32",
            "--radial-points",
            "10",
        ],
    );
    assert!(o.status.success());
    deform_cli::parse_su2(&std::fs::read(dir.join("m.su2")).unwrap()).unwrap()
}

#[test]
fn surface_positions_place_the_wall_exactly_and_match_displacements() {
    let d = tmp_dir("move-surface-positions");
    let mesh = naca(&d);
    let mut wall = mesh.marker("airfoil").unwrap().elements.nodes.clone();
    wall.sort_unstable();
    wall.dedup();
    // A bump: new absolute positions (SU2_DEF SURFACE_FILE: GlobalIndex x y), and the same
    // motion as displacements.
    let mut positions = String::from("% GlobalIndex x y\n");
    let mut displacements = String::new();
    for &n in &wall {
        let p = mesh.points[n as usize];
        let dy = 0.01 * (std::f64::consts::PI * p[0].clamp(0.0, 1.0)).sin();
        positions.push_str(&format!("{n} {:?} {:?}\n", p[0], p[1] + dy));
        displacements.push_str(&format!("{n} 0 {:?}\n", (p[1] + dy) - p[1]));
    }
    std::fs::write(d.join("surface.dat"), positions).unwrap();
    std::fs::write(d.join("disp.txt"), displacements).unwrap();
    let r = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--surface-positions",
            "surface.dat",
            "--method",
            "spring",
            "--out",
            "a.su2",
        ],
    );
    let a = deform_cli::parse_su2(&std::fs::read(d.join("a.su2")).unwrap()).unwrap();
    for &n in &wall {
        let p = mesh.points[n as usize];
        let dy = 0.01 * (std::f64::consts::PI * p[0].clamp(0.0, 1.0)).sin();
        assert_eq!(
            a.points[n as usize],
            [p[0], p[1] + dy, 0.0],
            "node {n} exactly as given"
        );
    }
    json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--displacements",
            "disp.txt",
            "--method",
            "spring",
            "--out",
            "b.su2",
        ],
    );
    let b = deform_cli::parse_su2(&std::fs::read(d.join("b.su2")).unwrap()).unwrap();
    let worst = a
        .points
        .iter()
        .zip(&b.points)
        .map(|(x, y)| (x[0] - y[0]).abs().max((x[1] - y[1]).abs()))
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-12,
        "the two files describe one motion: {worst:e}"
    );
    // The report: the largest displacement, and each marker's motion.
    let max = r["max_displacement"].as_f64().unwrap();
    assert!((max - 0.01).abs() < 2e-4, "{r}");
    assert_eq!(r["markers"][0]["marker"], "airfoil");
    assert_eq!(r["markers"][0]["nodes"], wall.len());
    assert!(
        r["markers"][0]["motion"]
            .as_str()
            .unwrap()
            .contains("surface positions"),
        "{r}"
    );
    // A node that is not in the mesh is refused.
    std::fs::write(d.join("bad.dat"), "999999 0 0\n").unwrap();
    let o = deform(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--surface-positions",
            "bad.dat",
            "--method",
            "spring",
            "--out",
            "c.su2",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(!d.join("c.su2").exists());
}

#[test]
fn a_3d_center_on_a_2d_mesh_is_refused_and_text_reports_the_motion() {
    let d = tmp_dir("move-center");
    naca(&d);
    let o = deform(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--rotate", "2", "--center", "0.25,0,1",
            "--method", "spring", "--out", "x.su2",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("2D mesh rotates about a point x,y"), "{err}");
    let o = deform(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--rotate", "2", "--center", "0.25,0",
            "--method", "spring", "--out", "y.su2",
        ],
    );
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(text.contains("max displacement"), "{text}");
    assert!(text.contains("marker airfoil:"), "{text}");
    assert!(text.contains("rotate 2 deg about [0.25, 0.0]"), "{text}");
    assert!(text.contains("area ratio min"), "{text}");
}
