//! `deform move --steps N` (issue 15 item 3): a large rotation in increments, re-deriving the
//! springs on the deforming mesh, inverts fewer cells than one step, and ends exactly on the
//! prescribed motion (the moved markers' final positions equal the single-step ones bit for
//! bit).

mod common;

use std::path::Path;

use common::{deform, deform_json, deform_ok, deform_refused, naca_mesh, read_su2, tmp_dir};
use serde_json::Value;

fn moved(dir: &Path, method: &str, steps: &str, extra: &[&str]) -> Value {
    let out = format!("{method}_{steps}.su2");
    let mut args = vec![
        "--json",
        "move",
        "m.su2",
        "--marker",
        "airfoil",
        "--center",
        "0.25,0",
        "--method",
        method,
        "--steps",
        steps,
        "--out",
        &out,
        // Counting inverted cells is the point: the results are written anyway.
        "--allow-folds",
    ];
    args.extend_from_slice(extra);
    deform_json(dir, &args)
}

fn points(path: &Path) -> Vec<[f64; 3]> {
    read_su2(path).points
}

#[test]
fn a_large_rotation_in_steps_inverts_fewer_cells_and_ends_on_the_exact_motion() {
    let d = tmp_dir("move-steps");
    naca_mesh(&d, "inviscid", 64, 20, "m.su2");
    let one = moved(&d, "spring", "1", &["--rotate", "60"]);
    let eight = moved(&d, "spring", "8", &["--rotate", "60"]);
    assert_eq!(eight["steps"], 8);
    let inv = |r: &Value| r["inverted_cells"].as_u64().expect("count");
    assert!(
        inv(&one) > 0,
        "the test needs a motion one step cannot take"
    );
    assert!(
        inv(&eight) < inv(&one),
        "8 steps {} vs 1 step {}",
        inv(&eight),
        inv(&one)
    );
    // The airfoil ends where one step puts it, bit for bit; the far field has not moved.
    let mesh = read_su2(&d.join("m.su2"));
    let (p1, p8) = (
        points(&d.join("spring_1.su2")),
        points(&d.join("spring_8.su2")),
    );
    for m in &mesh.markers {
        for &n in &m.elements.nodes {
            let n = n as usize;
            assert_eq!(
                p1[n].map(f64::to_bits),
                p8[n].map(f64::to_bits),
                "{} node {n}",
                m.name
            );
            if m.name == "farfield" {
                assert_eq!(p8[n], mesh.points[n]);
            }
        }
    }
    // Translations and the quaternion method take steps too.
    let t = moved(&d, "quaternion", "3", &["--translate", "0.3,0.1"]);
    assert_eq!(t["inverted_cells"], 0);
    let (q, p0) = (points(&d.join("quaternion_3.su2")), &mesh.points);
    for m in mesh.markers.iter().filter(|m| m.name == "airfoil") {
        for &n in &m.elements.nodes {
            let n = n as usize;
            assert_eq!(q[n][0], p0[n][0] + 0.3);
            assert_eq!(q[n][1], p0[n][1] + 0.1);
        }
    }
}

#[test]
fn steps_must_be_positive_and_are_not_offered_for_plot3d() {
    let d = tmp_dir("move-steps-bad");
    let o = deform(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--rotate", "5", "--method", "spring",
            "--steps", "0", "--out", "o.su2",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    deform_ok(&d, &["mesh", "block", "--dims", "5,4", "--out", "g.x"]);
    deform_refused(
        &d,
        &[
            "move", "g.x", "--wall", "jmin", "--rotate", "5", "--method", "tfi", "--steps", "3",
            "--out", "o.x",
        ],
        3,
        "--steps",
        "o.x",
    );
}
