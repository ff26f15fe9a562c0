//! `deform move --motions FILE` (issue 15 item 3): a different rigid motion per marker in one
//! run. Each marker ends exactly where a single-marker run with the same motion puts it; a
//! node two markers move differently, bad lines and rotations in steps are refused.

mod common;

use common::{deform_json, deform_ok, deform_refused, naca_mesh, read_su2, tmp_dir};

#[test]
fn each_marker_moves_exactly_as_it_would_alone() {
    let d = tmp_dir("move-motions");
    naca_mesh(&d, "inviscid", 64, 20, "m.su2");
    std::fs::write(
        d.join("motions.txt"),
        "# airfoil pitches, far field drifts\nairfoil rotate -5 center 0.25,0  % nose up\n\nfarfield translate 0.5,0\n",
    )
    .expect("write");
    deform_ok(
        &d,
        &[
            "move",
            "m.su2",
            "--motions",
            "motions.txt",
            "--method",
            "spring",
            "--out",
            "both.su2",
        ],
    );
    deform_ok(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "-5",
            "--center",
            "0.25,0",
            "--method",
            "spring",
            "--out",
            "alone.su2",
        ],
    );
    let (m, both, alone) = (
        read_su2(&d.join("m.su2")),
        read_su2(&d.join("both.su2")),
        read_su2(&d.join("alone.su2")),
    );
    for marker in &m.markers {
        for &n in &marker.elements.nodes {
            let n = n as usize;
            if marker.name == "airfoil" {
                assert_eq!(
                    both.points[n].map(f64::to_bits),
                    alone.points[n].map(f64::to_bits),
                    "airfoil node {n}"
                );
            } else {
                assert_eq!(
                    both.points[n][0],
                    m.points[n][0] + 0.5,
                    "far field node {n}"
                );
                assert_eq!(both.points[n][1], m.points[n][1]);
            }
        }
    }
    // The report names each marker's own motion.
    let r = deform_json(
        &d,
        &[
            "--json",
            "move",
            "m.su2",
            "--motions",
            "motions.txt",
            "--method",
            "quaternion",
            "--out",
            "q.su2",
        ],
    );
    let motions: Vec<String> = r["markers"]
        .as_array()
        .expect("markers")
        .iter()
        .map(|m| m["motion"].as_str().unwrap_or("").to_string())
        .collect();
    assert_eq!(
        motions,
        ["rotate -5 deg about [0.25, 0.0]", "translate [0.5, 0.0]"]
    );
}

#[test]
fn conflicting_or_malformed_motions_are_refused_before_anything_is_written() {
    let d = tmp_dir("move-motions-bad");
    deform_ok(&d, &["mesh", "block", "--dims", "6,5", "--out", "b.su2"]);
    let run = |text: &str, extra: &[&str], code: i32, needle: &str| {
        std::fs::write(d.join("mot.txt"), text).expect("write");
        let mut args = vec![
            "move",
            "b.su2",
            "--motions",
            "mot.txt",
            "--method",
            "spring",
            "--out",
            "o.su2",
        ];
        args.extend_from_slice(extra);
        deform_refused(&d, &args, code, needle, "o.su2");
    };
    // imin and jmin share the corner node 0.
    run(
        "imin translate 0.1,0\njmin translate 0,0.1\n",
        &[],
        1,
        "which move it differently",
    );
    run("imin translate 0.1,0\nimin rotate 3\n", &[], 1, "line 2");
    run("imin spin 3\n", &[], 1, "`rotate` or `translate`");
    run("imin translate 0.1\n", &[], 1, "line 1");
    run("imin rotate 10 axis 1,0,0\n", &[], 1, "the z axis");
    run("imin rotate nan\n", &[], 1, "line 1");
    run("# nothing\n", &[], 1, "at least one");
    run("nosuch translate 0.1,0\n", &[], 1, "not found");
    run("imin rotate 3\n", &["--steps", "2"], 3, "--steps");
    // Two markers that agree on their shared node are fine.
    std::fs::write(
        d.join("mot.txt"),
        "imin translate 0.1,0\njmin translate 0.1,0\n",
    )
    .expect("write");
    deform_ok(
        &d,
        &[
            "move",
            "b.su2",
            "--motions",
            "mot.txt",
            "--method",
            "spring",
            "--out",
            "o.su2",
        ],
    );
}
