//! `deform move --method rbf` (issue 28 item 2 through the tool): a viscous NACA 2412 hybrid
//! mesh pitched 50° about its quarter chord keeps every cell valid with both kernels, the
//! first grid line turns with the wall (Wendland C2, 20-chord support: within 0.25°, the
//! figure SU2-style RBF reaches), a greedy fit at SU2's default tolerance still moves the wall
//! exactly as prescribed, and the `--rbf-*` options are checked.

mod common;

use std::path::Path;

use common::{deform_json, deform_refused, naca_mesh, read_su2, tmp_dir};
use serde_json::Value;

fn pitch(dir: &Path, out: &str, extra: &[&str]) -> Value {
    let mut args = vec![
        "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "50", "--center", "0.25,0",
        "--method", "rbf", "--out", out,
    ];
    args.extend_from_slice(extra);
    deform_json(dir, &args)
}

#[test]
fn rbf_pitches_a_viscous_airfoil_50_degrees_without_inverting_a_cell() {
    let d = tmp_dir("move-rbf-50");
    naca_mesh(&d, "viscous", 96, 32, "m.su2");
    let wendland = pitch(&d, "w.su2", &["--rbf-radius", "20"]);
    let tps = pitch(&d, "t.su2", &["--rbf-kernel", "tps"]);
    let greedy = pitch(
        &d,
        "g.su2",
        &["--rbf-radius", "20", "--rbf-tolerance", "1e-3"],
    );
    for (name, r) in [("wendland", &wendland), ("tps", &tps), ("greedy", &greedy)] {
        let angle = r["max_wall_angle_change_deg"].as_f64().expect("angle");
        eprintln!(
            "{name}: inverted {}, folded {}, min area ratio {}, wall angle change {angle:.4} deg, {} of {} centres, boundary error {}",
            r["inverted_cells"], r["folded_cells"], r["min_area_ratio"],
            r["rbf"]["centres"], r["rbf"]["boundary_nodes"], r["rbf"]["max_error"]
        );
        assert_eq!(r["inverted_cells"], 0, "{name}");
        assert_eq!(r["folded_cells"], 0, "{name}");
        assert_eq!(r["method"], "rbf");
    }
    let angle = |r: &Value| r["max_wall_angle_change_deg"].as_f64().expect("angle");
    assert!(angle(&wendland) < 0.25, "{}", angle(&wendland));
    assert!(angle(&tps) < 5.0, "{}", angle(&tps));
    let b = wendland["rbf"]["boundary_nodes"].as_u64().unwrap();
    assert_eq!(wendland["rbf"]["centres"].as_u64().unwrap(), b);
    let reduced = greedy["rbf"]["centres"].as_u64().unwrap();
    assert!(reduced < b / 4, "{reduced} of {b}");
    // The greedy fit misses the wall by its tolerance; the written wall is still exact: the
    // same bits as the full fit's (both write the prescribed motion).
    let max_move = wendland["max_displacement"].as_f64().unwrap();
    let err = greedy["rbf"]["max_error"].as_f64().unwrap();
    assert!(err > 0.0 && err <= 1e-3 * max_move * 1.0000001, "{err}");
    let (full, red) = (read_su2(&d.join("w.su2")), read_su2(&d.join("g.su2")));
    let wall = &full
        .markers
        .iter()
        .find(|m| m.name == "airfoil")
        .unwrap()
        .elements;
    for &n in &wall.nodes {
        assert_eq!(
            full.points[n as usize], red.points[n as usize],
            "wall node {n}"
        );
    }
}

#[test]
fn rbf_options_are_checked() {
    let d = tmp_dir("move-rbf-bad");
    naca_mesh(&d, "inviscid", 32, 8, "m.su2");
    for (extra, needle) in [
        (
            &["--method", "rbf", "--rbf-radius", "0"][..],
            "positive distances",
        ),
        (
            &[
                "--method",
                "rbf",
                "--rbf-kernel",
                "tps",
                "--rbf-radius",
                "2",
            ][..],
            "thin-plate",
        ),
        (
            &["--method", "rbf", "--rbf-tolerance=-1"][..],
            "non-negative",
        ),
        (
            &["--method", "rbf", "--rbf-max-centres", "2"][..],
            "at least 4",
        ),
        (
            &["--method", "idw", "--rbf-tolerance", "1e-3"][..],
            "apply to --method rbf",
        ),
        (
            &["--method", "rbf", "--stiffness", "inverse-volume"][..],
            "no springs",
        ),
    ] {
        let mut args = vec![
            "move", "m.su2", "--marker", "airfoil", "--rotate", "3", "--out", "o.su2",
        ];
        args.extend_from_slice(extra);
        deform_refused(&d, &args, 1, needle, "o.su2");
    }
}
