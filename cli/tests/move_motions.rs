//! `deform move --motions FILE` (issue 15 item 3): a different rigid motion per marker in one
//! run. Each marker ends exactly where a single-marker run with the same motion puts it; a
//! node two markers move differently, bad lines and rotations in steps are refused.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::tmp_dir;

fn deform(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run deform")
}

fn ok(dir: &Path, args: &[&str]) {
    let o = deform(dir, args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn fails(dir: &Path, args: &[&str], code: i32, needle: &str) {
    let o = deform(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    assert!(!dir.join("o.su2").exists());
}

fn mesh(path: &Path) -> deform_cli::formats::su2::Su2Mesh {
    deform_cli::parse_su2(&std::fs::read(path).expect("read")).expect("parse")
}

#[test]
fn each_marker_moves_exactly_as_it_would_alone() {
    let d = tmp_dir("move-motions");
    ok(
        &d,
        &[
            "mesh",
            "naca",
            "--kind",
            "inviscid",
            "--surface-points",
            "64",
            "--radial-points",
            "20",
            "--out",
            "m.su2",
        ],
    );
    std::fs::write(
        d.join("motions.txt"),
        "# airfoil pitches, far field drifts\nairfoil rotate -5 center 0.25,0  % nose up\n\nfarfield translate 0.5,0\n",
    )
    .expect("write");
    ok(
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
    ok(
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
        mesh(&d.join("m.su2")),
        mesh(&d.join("both.su2")),
        mesh(&d.join("alone.su2")),
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
    let o = deform(
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
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value = serde_json::from_slice(&o.stdout).expect("json");
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
    ok(&d, &["mesh", "block", "--dims", "6,5", "--out", "b.su2"]);
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
        fails(&d, &args, code, needle);
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
    ok(
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
