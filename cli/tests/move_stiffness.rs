//! `deform move --stiffness`: the spring stiffness choices of issue 15 item 4 through the tool,
//! on a generated viscous NACA 2412 mesh pitched 10°.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::tmp_dir;
use serde_json::Value;

fn deform(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run deform")
}

fn pitch(dir: &Path, method: &str, stiffness: &str) -> Value {
    let out = format!("{method}_{stiffness}.su2");
    let o = deform(
        dir,
        &[
            "--json",
            "move",
            "v.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "-10",
            "--center",
            "0.25,0",
            "--method",
            method,
            "--stiffness",
            stiffness,
            "--out",
            &out,
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("JSON report")
}

#[test]
fn stiffer_small_and_near_wall_cells_invert_fewer_cells() {
    let d = tmp_dir("move-stiffness");
    let o = deform(
        &d,
        &[
            "mesh",
            "naca",
            "--kind",
            "viscous",
            "--surface-points",
            "128",
            "--radial-points",
            "40",
            "--out",
            "v.su2",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let inverted = |r: &Value| r["inverted_cells"].as_u64().expect("count");
    let batina = pitch(&d, "spring", "batina");
    let wall = pitch(&d, "spring", "wall-distance");
    let volume = pitch(&d, "spring", "inverse-volume");
    assert_eq!(batina["stiffness"], "batina");
    assert_eq!(volume["stiffness"], "inverse-volume");
    assert!(
        inverted(&batina) > 0,
        "the test needs inverted cells with 1/L"
    );
    assert!(inverted(&wall) < inverted(&batina), "{wall} vs {batina}");
    assert!(
        inverted(&volume) < inverted(&batina),
        "{volume} vs {batina}"
    );
    // The quaternion method's spring propagation takes the choice too.
    let q = pitch(&d, "quaternion", "inverse-volume");
    assert_eq!(q["stiffness"], "inverse-volume");
    assert_eq!(inverted(&q), 0);
}

#[test]
fn a_stiffness_for_a_method_without_springs_is_refused() {
    let d = tmp_dir("move-stiffness-idw");
    let o = deform(
        &d,
        &[
            "mesh",
            "naca",
            "--kind",
            "inviscid",
            "--surface-points",
            "32",
            "--radial-points",
            "8",
            "--out",
            "m.su2",
        ],
    );
    assert!(o.status.success());
    let o = deform(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "2",
            "--method",
            "idw",
            "--stiffness",
            "wall-distance",
            "--out",
            "o.su2",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("has no springs"), "{err}");
    assert!(!d.join("o.su2").exists());
}
