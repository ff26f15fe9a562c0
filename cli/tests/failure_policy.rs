//! One failure policy for `move` and `smooth` (issue 31 item 5): a result with cells that the
//! input did not have inverted or folded is not written (exit 4) unless `--allow-folds`; an
//! unconverged solve is an error (exit 5) unless `--allow-unconverged`; cells folded already in
//! the input do not count. Inverted cells are counted here independently of the tool, with the
//! shoelace formula on the files it wrote.

mod common;

use std::path::Path;

use common::{deform, deform_json, deform_refused, naca_mesh, read_su2, su2_bytes, tmp_dir};

/// Signed shoelace area of every cell of a 2D SU2 mesh.
fn areas(mesh: &deform_cli::formats::su2::Su2Mesh, points: &[[f64; 3]]) -> Vec<f64> {
    mesh.elements
        .iter()
        .map(|(_, nodes)| {
            let n = nodes.len();
            (0..n)
                .map(|i| {
                    let p = points[nodes[i] as usize];
                    let q = points[nodes[(i + 1) % n] as usize];
                    p[0] * q[1] - q[0] * p[1]
                })
                .sum::<f64>()
                / 2.0
        })
        .collect()
}

fn pitch<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "20", "--center", "0.25,0",
        "--method", "spring", "--out", "s.su2",
    ];
    v.extend_from_slice(extra);
    v
}

#[test]
fn move_refuses_new_inverted_cells_unless_allowed() {
    let d = tmp_dir("policy-move");
    naca_mesh(&d, "viscous", 64, 32, "m.su2");
    deform_refused(&d, &pitch(&[]), 4, "that were valid in the input", "s.su2");
    let o = deform(&d, &pitch(&["--allow-folds"]));
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stderr).contains("written because of --allow-folds"));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    // Independent count: cells whose shoelace area changed sign.
    let input = read_su2(&d.join("m.su2"));
    let output = read_su2(&d.join("s.su2"));
    let before = areas(&input, &input.points);
    let after = areas(&input, &output.points);
    let inverted = before
        .iter()
        .zip(&after)
        .filter(|(b, a)| b.signum() != a.signum())
        .count();
    assert!(inverted > 0, "the case must invert cells");
    assert_eq!(r["inverted_cells"], inverted);
    let new = r["new_invalid_cells"].as_u64().expect("count") as usize;
    assert!(new >= inverted, "{r}");
    // The quaternion method (the default without --method) inverts nothing here.
    let q = deform_json(
        &d,
        &[
            "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "20", "--center",
            "0.25,0", "--out", "q.su2",
        ],
    );
    assert_eq!(q["method"], "quaternion");
    assert_eq!(q["new_invalid_cells"], 0);
}

/// A 2D grid mesh whose quad at row 2, column 2 is already a dart (one node pushed through the
/// opposite diagonal): folded in the input.
fn mesh_with_a_dart(dir: &Path) {
    let mut m = common::mesh_2d(6, 5);
    // Node (3, 3) sits on the corner shared by four quads; push it deep into quad (2, 2).
    let id = 3 + 7 * 3;
    m.points[id] = [2.1, 1.5, 0.0];
    std::fs::write(dir.join("dart.su2"), su2_bytes(&m)).expect("write");
}

#[test]
fn cells_folded_in_the_input_do_not_block_a_move() {
    let d = tmp_dir("policy-input-folds");
    mesh_with_a_dart(&d);
    let q = deform_json(&d, &["--json", "quality", "dart.su2"]);
    let folded = q["folded_cells"].as_u64().expect("count");
    assert!(folded > 0, "{q}");
    let r = deform_json(
        &d,
        &[
            "--json",
            "move",
            "dart.su2",
            "--marker",
            "wall",
            "--translate",
            "0.01,0",
            "--method",
            "spring",
            "--out",
            "out.su2",
        ],
    );
    assert_eq!(r["folded_cells"], folded);
    assert_eq!(r["new_invalid_cells"], 0);
}

#[test]
fn tfi_on_plot3d_follows_the_same_policy() {
    let d = tmp_dir("policy-tfi");
    common::deform_ok(&d, &["mesh", "block", "--dims", "11,6", "--out", "b.xy"]);
    // The wall face jmin moved far beyond the opposite face: every cell turns over.
    let args = [
        "--json",
        "move",
        "b.xy",
        "--method",
        "tfi-displacement",
        "--wall",
        "jmin",
        "--translate",
        "0,30",
        "--out",
        "o.xy",
    ];
    deform_refused(&d, &args, 4, "--allow-folds", "o.xy");
    let mut allowed = args.to_vec();
    allowed.push("--allow-folds");
    let r = deform_json(&d, &allowed);
    assert_eq!(r["inverted_cells"], 50);
    assert_eq!(r["new_invalid_cells"], 50);
}

#[test]
fn the_exit_codes_and_flags_are_documented() {
    let d = tmp_dir("policy-help");
    let help = String::from_utf8_lossy(&deform(&d, &["--help"]).stdout).into_owned();
    for needle in ["4 the result would have cells", "5 a solve did"] {
        assert!(help.contains(needle), "{needle:?} in {help}");
    }
    let help = String::from_utf8_lossy(&deform(&d, &["move", "--help"]).stdout).into_owned();
    for needle in [
        "--allow-folds",
        "--allow-unconverged",
        "exit status 4",
        "exit status 5",
    ] {
        assert!(help.contains(needle), "{needle:?} in {help}");
    }
    let readme = include_str!("../README.md");
    for needle in ["--allow-folds", "--allow-unconverged", "| 4 |", "| 5 |"] {
        assert!(readme.contains(needle), "{needle:?} in cli/README.md");
    }
}
