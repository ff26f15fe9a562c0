//! End-to-end runs of `mesh`, `quality`, `move` and `smooth` on generated files.

mod common;

use std::path::Path;

use common::{deform, listing, tmp_dir};
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
    serde_json::from_slice(&o.stdout).expect("JSON report")
}

fn fails(dir: &Path, args: &[&str], code: i32, needle: &str) {
    let o = deform(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err:?}");
}

const TINY: &[&str] = &[
    "--surface-points",
    "32",
    "--radial-points",
    "12",
    "--boundary-layers",
    "4",
    "--first-layer",
    "0.01",
];

fn tiny_mesh(dir: &Path, kind: &str, out: &str) -> Value {
    let mut args = vec![
        "mesh", "naca", "--code", "2412", "--kind", kind, "--out", out,
    ];
    args.extend_from_slice(TINY);
    json(dir, &args)
}

#[test]
fn mesh_naca_kinds_and_quality() {
    let d = tmp_dir("mesh-naca");
    for (kind, cells) in [("inviscid", 704), ("viscous", 576), ("ogrid", 352)] {
        let out = format!("{kind}.su2");
        let r = tiny_mesh(&d, kind, &out);
        assert_eq!(r["nodes"], 384, "{kind}");
        assert_eq!(r["cells"], cells, "{kind}");
        assert_eq!(r["markers"], serde_json::json!(["airfoil", "farfield"]));
        let q = json(&d, &["quality", &out]);
        assert_eq!(q["cells"], cells);
        assert_eq!(q["folded_cells"], 0, "{kind}");
        assert_eq!(q["nonpositive_cells"], 0, "{kind}");
        assert!(q["inverted_cells"].is_null());
        assert!(q["min_scaled_jacobian"].as_f64().expect("number") > 0.0);
    }
    fails(
        &d,
        &[
            "mesh", "naca", "--kind", "ogrid", "--code", "24x2", "--out", "bad.su2",
        ],
        1,
        "not a NACA 4-digit code",
    );
    fails(
        &d,
        &[
            "mesh",
            "naca",
            "--kind",
            "ogrid",
            "--surface-points",
            "7",
            "--out",
            "bad.su2",
        ],
        1,
        "surface_points must be even",
    );
    assert!(!listing(&d).contains(&"bad.su2".to_string()));
}

#[test]
fn quality_finds_an_inverted_cell() {
    let d = tmp_dir("quality-inverted");
    tiny_mesh(&d, "ogrid", "m.su2");
    // Move one interior node far across its neighbours: its cells invert.
    let text = std::fs::read_to_string(d.join("m.su2")).expect("read");
    let mut out = String::new();
    let mut in_points = false;
    let mut k = 0;
    for line in text.lines() {
        if line.starts_with("NPOIN=") {
            in_points = true;
        } else if line.starts_with("NMARK=") {
            in_points = false;
        } else if in_points {
            // Node 32 * 3 + 5 is on the fourth ring; push it to the far side of the airfoil.
            if k == 101 {
                out.push_str("0.5 -0.5 101\n");
                k += 1;
                continue;
            }
            k += 1;
        }
        out.push_str(line);
        out.push('\n');
    }
    std::fs::write(d.join("bad.su2"), out).expect("write");
    let q = json(
        &d,
        &[
            "quality",
            "bad.su2",
            "--reference",
            "m.su2",
            "--wall",
            "airfoil",
            "--vtk",
            "q.vtu",
        ],
    );
    assert!(q["inverted_cells"].as_u64().expect("count") >= 1, "{q}");
    assert!(q["folded_cells"].as_u64().expect("count") >= 1, "{q}");
    assert!(q["min_area_ratio"].as_f64().expect("ratio") < 0.0, "{q}");
    let vtu = std::fs::read_to_string(d.join("q.vtu")).expect("vtu");
    assert!(vtu.contains("Name=\"scaled_jacobian\""));
    fails(
        &d,
        &["quality", "bad.su2", "--wall", "airfoil"],
        1,
        "--wall needs --reference",
    );
    fails(
        &d,
        &[
            "quality",
            "bad.su2",
            "--reference",
            "m.su2",
            "--wall",
            "nose",
        ],
        1,
        "marker \"nose\" not found",
    );
}

#[test]
fn move_every_method() {
    let d = tmp_dir("move-methods");
    tiny_mesh(&d, "viscous", "m.su2");
    for method in ["quaternion", "idw", "spring", "angle-cg"] {
        let out = format!("{method}.su2");
        let r = json(
            &d,
            &[
                "move",
                "m.su2",
                "--marker",
                "airfoil",
                "--rotate",
                "5",
                "--center",
                "0.25,0",
                "--method",
                method,
                "--out",
                &out,
                "--allow-folds",
            ],
        );
        for key in [
            "nodes",
            "cells",
            "method",
            "iterations",
            "residual",
            "converged",
            "inverted_cells",
            "folded_cells",
            "min_area_ratio",
            "max_wall_angle_change_deg",
            "seconds",
        ] {
            assert!(r.get(key).is_some(), "{method}: {key} missing in {r}");
        }
        assert_eq!(r["method"], method);
        assert_eq!(r["converged"], true, "{method}");
        assert_eq!(r["nodes"], 384);
        assert_eq!(r["moved_nodes"], 32);
        assert_eq!(r["fixed_nodes"], 32);
        // The moved wall node 0 (trailing edge at (1, 0)) went where the rotation says.
        let m = deform_cli::parse_su2(&std::fs::read(d.join(&out)).expect("out")).expect("valid");
        let a = 5f64.to_radians();
        let expect = [0.25 + 0.75 * a.cos(), 0.75 * a.sin()];
        let te = m
            .points
            .iter()
            .map(|p| (p[0] - expect[0]).hypot(p[1] - expect[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(te < 1e-12, "{method}: trailing edge off by {te}");
    }
    // The quaternion method keeps the wall-normal grid lines (the papers' point).
    let q = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "20",
            "--center",
            "0.25,0",
            "--method",
            "quaternion",
            "--out",
            "q20.su2",
            "--vtk",
            "q20.vtu",
            "--plot",
            "q20.svg",
        ],
    );
    let s = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "20",
            "--center",
            "0.25,0",
            "--method",
            "spring",
            "--out",
            "s20.su2",
            "--plot",
            "s20.png",
            "--allow-folds",
        ],
    );
    let qa = q["max_wall_angle_change_deg"].as_f64().expect("angle");
    let sa = s["max_wall_angle_change_deg"].as_f64().expect("angle");
    assert!(qa < sa, "quaternion {qa} vs spring {sa}");
    assert_eq!(q["inverted_cells"], 0);
    assert!(std::fs::read(d.join("s20.png"))
        .expect("png")
        .starts_with(b"\x89PNG"));
    assert!(std::fs::read_to_string(d.join("q20.svg"))
        .expect("svg")
        .contains("<svg"));
    assert!(std::fs::read_to_string(d.join("q20.vtu"))
        .expect("vtu")
        .contains("Name=\"displacement\""));
}

#[test]
fn move_translate_displacements_and_non_convergence() {
    let d = tmp_dir("move-other");
    tiny_mesh(&d, "ogrid", "m.su2");
    let r = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--translate",
            "0.01,-0.02",
            "--method",
            "spring",
            "--solver",
            "gs",
            "--out",
            "t.su2",
        ],
    );
    assert_eq!(r["converged"], true);
    assert_eq!(r["solver"], "gs");
    std::fs::write(d.join("disp.txt"), "% node dx dy\n0 0.0 0.01\n16 0 -0.01\n").expect("write");
    let r = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--displacements",
            "disp.txt",
            "--method",
            "quaternion",
            "--out",
            "d.su2",
            "--allow-folds",
        ],
    );
    assert_eq!(r["converged"], true);
    // Not converging is an error (exit 5, nothing written) …
    let unconverged = [
        "--json",
        "move",
        "m.su2",
        "--marker",
        "airfoil",
        "--rotate",
        "5",
        "--method",
        "spring",
        "--solver",
        "jacobi",
        "--max-iter",
        "3",
        "--out",
        "j.su2",
    ];
    common::deform_refused(&d, &unconverged, 5, "did not converge", "j.su2");
    // … unless --allow-unconverged: reported (JSON and a warning), and the result written.
    let mut allowed = unconverged.to_vec();
    allowed.extend(["--allow-unconverged", "--allow-folds"]);
    let o = deform(&d, &allowed);
    assert_eq!(o.status.code(), Some(0));
    let v: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["converged"], false);
    assert_eq!(v["iterations"], 3);
    assert!(String::from_utf8_lossy(&o.stderr).contains("did not converge"));
    // Failures leave nothing behind.
    let before = listing(&d);
    fails(
        &d,
        &[
            "move", "m.su2", "--marker", "wing", "--rotate", "5", "--method", "spring", "--out",
            "x.su2",
        ],
        1,
        "marker \"wing\" not found (markers: airfoil, farfield)",
    );
    fails(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--rotate", "5", "--method", "spring", "--out",
            "x.su2", "--plot", "x.gif",
        ],
        1,
        "--plot must be a .svg or .png",
    );
    assert_eq!(listing(&d), before);
}

#[test]
fn smooth_noisy_blocks() {
    let d = tmp_dir("smooth");
    let r = json(
        &d,
        &[
            "mesh", "block", "--dims", "25,13", "--noise", "0.3", "--out", "n.x",
        ],
    );
    assert_eq!(r["nodes"], 325);
    let s = json(
        &d,
        &[
            "smooth",
            "n.x",
            "--direction",
            "j",
            "--iterations",
            "30",
            "--out",
            "s.x",
        ],
    );
    for key in [
        "blocks",
        "iterations",
        "max_stretching_before",
        "max_stretching_after",
        "max_point_move",
        "folded_lines",
    ] {
        assert!(s.get(key).is_some(), "{key} missing in {s}");
    }
    let before = s["max_stretching_before"].as_f64().expect("number");
    let after = s["max_stretching_after"].as_f64().expect("number");
    assert!(after < before, "stretching {before} -> {after}");
    // Output keeps the input layout (binary f64 with records), so it reads back the same way.
    let q = json(&d, &["quality", "s.x", "--reference", "n.x"]);
    assert_eq!(q["folded_cells"], 0);
    assert!(q["format"]
        .as_str()
        .expect("str")
        .contains("Fortran records"));
    // 3D, normalised arclength, coarse pass, ASCII.
    json(
        &d,
        &[
            "mesh", "block", "--dims", "7,6,9", "--noise", "0.3", "--out", "n3.xyz",
        ],
    );
    let s = json(
        &d,
        &[
            "smooth",
            "n3.xyz",
            "--direction",
            "k",
            "--normalized",
            "--iterations",
            "20",
            "--coarse",
            "2",
            "--out",
            "s3.p3d",
        ],
    );
    assert_eq!(s["blocks"], 1);
    assert_eq!(s["normalized"], true);
    fails(
        &d,
        &[
            "smooth",
            "n.x",
            "--direction",
            "k",
            "--iterations",
            "3",
            "--out",
            "x.x",
        ],
        1,
        "--direction k needs a 3D grid",
    );
    fails(
        &d,
        &[
            "smooth",
            "n.x",
            "--direction",
            "i",
            "--iterations",
            "3",
            "--mu",
            "0.2",
            "--out",
            "x.x",
        ],
        1,
        "--mu <= 0",
    );
    // An unstable filter folds a line: the run stops, names the line, writes nothing.
    fails(
        &d,
        &[
            "smooth",
            "n.x",
            "--direction",
            "i",
            "--iterations",
            "50",
            "--lambda",
            "1.5",
            "--mu",
            "0",
            "--out",
            "x.x",
        ],
        1,
        "folded (arclength not increasing)",
    );
    assert!(!listing(&d).contains(&"x.x".to_string()));
}

#[test]
fn move_in_3d_with_every_method() {
    let d = tmp_dir("move-3d");
    let r = json(
        &d,
        &[
            "mesh", "block", "--dims", "5,5,5", "--noise", "0.2", "--out", "b.su2",
        ],
    );
    assert_eq!(r["cells"], 64);
    for method in ["quaternion", "idw", "spring", "angle-direct", "angle-cg"] {
        let out = format!("{method}.su2");
        let r = json(
            &d,
            &[
                "move",
                "b.su2",
                "--marker",
                "kmin",
                "--translate",
                "0,0,0.05",
                "--method",
                method,
                "--out",
                &out,
            ],
        );
        assert_eq!(r["converged"], true, "{method}: {r}");
        assert_eq!(r["inverted_cells"], 0, "{method}: {r}");
        assert_eq!(r["moved_nodes"], 25);
        let m = deform_cli::parse_su2(&std::fs::read(d.join(&out)).expect("out")).expect("valid");
        assert_eq!(m.dim, 3);
        // The moved face went up by exactly 0.05 (z was 0).
        let lowest = m.points.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
        assert!((lowest - 0.05).abs() < 1e-15, "{method}: {lowest}");
    }
    let r = json(
        &d,
        &[
            "move",
            "b.su2",
            "--marker",
            "imin",
            "--rotate",
            "10",
            "--axis",
            "1,0,0",
            "--center",
            "0,0.5,0.5",
            "--method",
            "quaternion",
            "--out",
            "r.su2",
            "--vtk",
            "r.vtu",
        ],
    );
    assert_eq!(r["center"], serde_json::json!([0.0, 0.5, 0.5]));
    assert_eq!(r["inverted_cells"], 0);
    // A 3D translation needs three components.
    fails(
        &d,
        &[
            "move",
            "b.su2",
            "--marker",
            "kmin",
            "--translate",
            "0,0.1",
            "--method",
            "spring",
            "--out",
            "x.su2",
        ],
        1,
        "a 3D mesh needs dx,dy,dz",
    );
}

#[test]
fn angle_direct_reports_non_convergence() {
    let d = tmp_dir("angle-direct");
    tiny_mesh(&d, "viscous", "m.su2");
    let o = deform(
        &d,
        &[
            "--json",
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "5",
            "--method",
            "angle-direct",
            "--max-iter",
            "20",
            "--out",
            "a.su2",
            "--allow-unconverged",
        ],
    );
    assert_eq!(o.status.code(), Some(0));
    let v: Value = serde_json::from_slice(&o.stdout).expect("JSON");
    assert_eq!(v["converged"], false);
    assert_eq!(v["iterations"], 20);
    assert_eq!(v["solver"], "sor 1.858");
    assert!(String::from_utf8_lossy(&o.stderr).contains("did not converge"));
}

/// angle-direct over-relaxes its node-wise sweeps by default (issue 14 item 8): on the tiny
/// viscous mesh it converges within a sweep budget in which plain Gauss–Seidel (`--solver gs`)
/// does not, to the angle-cg answer (multigrid-preconditioned CG by default, fewer iterations
/// than the block-Jacobi CG of `--solver cg`).
#[test]
fn angle_direct_over_relaxation_converges_where_gauss_seidel_does_not() {
    let d = tmp_dir("angle-direct-sor");
    tiny_mesh(&d, "viscous", "m.su2");
    let run = |extra: &[&str], out: &str| {
        let mut args = vec![
            "--json",
            "move",
            "m.su2",
            "--marker",
            "airfoil",
            "--rotate",
            "5",
            "--max-iter",
            "400",
            "--out",
            out,
        ];
        args.extend_from_slice(extra);
        let o = deform(&d, &args);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice::<Value>(&o.stdout).expect("JSON")
    };
    let sor = run(&["--method", "angle-direct"], "sor.su2");
    assert_eq!(sor["solver"], "sor 1.858"); // 2 / (1 + 1.5 / √384)
    assert_eq!(sor["converged"], true, "{sor}");
    let gs = run(
        &[
            "--method",
            "angle-direct",
            "--solver",
            "gs",
            "--allow-unconverged",
        ],
        "gs.su2",
    );
    assert_eq!(gs["solver"], "gs");
    assert_eq!(gs["converged"], false, "{gs}");
    assert!(sor["iterations"].as_u64() < gs["iterations"].as_u64());
    let cg = run(&["--method", "angle-cg"], "cg.su2");
    assert_eq!(cg["converged"], true);
    // angle-cg's default solver is the multigrid-preconditioned CG; --solver cg is block
    // Jacobi: both converge, the multigrid one in fewer iterations.
    assert_eq!(cg["solver"], "amg");
    let bj = run(&["--method", "angle-cg", "--solver", "cg"], "bj.su2");
    assert_eq!(bj["solver"], "cg");
    assert_eq!(bj["converged"], true, "{bj}");
    assert!(
        cg["iterations"].as_u64() < bj["iterations"].as_u64(),
        "{cg} {bj}"
    );
    let a = std::fs::read_to_string(d.join("sor.su2")).unwrap();
    let b = std::fs::read_to_string(d.join("cg.su2")).unwrap();
    let nums = |s: &str| -> Vec<f64> {
        s.split_whitespace()
            .filter_map(|t| t.parse::<f64>().ok())
            .collect()
    };
    let (a, b) = (nums(&a), nums(&b));
    assert_eq!(a.len(), b.len());
    let err = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    assert!(err < 1e-6, "sor vs cg: {err:e}");
}

#[test]
fn move_plot_of_a_3d_mesh_draws_a_section_through_the_moved_marker() {
    let d = tmp_dir("move-plot-3d");
    std::fs::write(d.join("m.su2"), common::su2_bytes(&common::mesh_3d())).expect("write");
    let r = json(
        &d,
        &[
            "move",
            "m.su2",
            "--marker",
            "top",
            "--translate",
            "0,0,1e-4",
            "--method",
            "idw",
            "--out",
            "o.su2",
            "--plot",
            "o.svg",
        ],
    );
    assert_eq!(r["inverted_cells"], 0, "{r}");
    let svg = std::fs::read_to_string(d.join("o.svg")).expect("svg");
    assert!(svg.contains("(section z = "), "{svg}");
    // Section polygons only: every drawn cell edge lies in one plane z = z0, so there are far
    // fewer than the 30 distinct edges of the four volume cells projected on x–y.
    let grey = svg
        .lines()
        .find(|l| l.contains("stroke=\"#505050\""))
        .expect("cell edges");
    let drawn = grey.matches('M').count();
    assert!(drawn > 0 && drawn < 12, "{drawn} section edges");
}
