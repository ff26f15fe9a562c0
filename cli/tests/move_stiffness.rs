//! `deform move --stiffness`: the spring stiffness choices of issue 15 item 4 through the tool,
//! on a generated viscous NACA 2412 mesh pitched 10°.

mod common;

use std::path::Path;

use common::{deform_json, deform_refused, naca_mesh, tmp_dir};
use serde_json::Value;

fn pitch(dir: &Path, method: &str, stiffness: &str) -> Value {
    let out = format!("{method}_{stiffness}.su2");
    deform_json(
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
            // Counting inverted cells is the point: the results are written anyway.
            "--allow-folds",
        ],
    )
}

#[test]
fn stiffer_small_and_near_wall_cells_invert_fewer_cells() {
    let d = tmp_dir("move-stiffness");
    naca_mesh(&d, "viscous", 128, 40, "v.su2");
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
    naca_mesh(&d, "inviscid", 32, 8, "m.su2");
    deform_refused(
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
        1,
        "has no springs",
        "o.su2",
    );
}
