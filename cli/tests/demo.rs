//! `deform demo --quick` end to end: tables, pictures, VTK files, report; and a failing run
//! that leaves nothing behind.

mod common;

use std::process::Command;

use common::{listing, tmp_dir};

#[test]
fn quick_demo_writes_everything() {
    let d = tmp_dir("demo");
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .args(["--json", "demo", "--quick", "--out", "out"])
        .output()
        .expect("run");
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let rows = v["deformation"].as_array().expect("rows");
    assert_eq!(rows.len(), 3 * 4, "3 meshes x 4 methods x 1 angle");
    for r in rows {
        assert_eq!(r["converged"], true, "{r}");
        if r["method"] == "quaternion" || r["method"] == "idw" {
            assert_eq!(r["inverted_cells"], 0, "{r}");
        }
    }
    // Samareh's point: the quaternion method keeps the first grid-line angle far better
    // than linear springs.
    for mesh in ["inviscid", "viscous", "ogrid"] {
        let get = |m: &str| {
            rows.iter()
                .find(|r| r["mesh"] == mesh && r["method"] == m)
                .and_then(|r| r["max_wall_angle_change_deg"].as_f64())
                .expect("row")
        };
        assert!(get("quaternion") < get("spring"), "{mesh}");
    }
    let smooth = v["smoothing"].as_array().expect("smoothing rows");
    assert_eq!(smooth.len(), 4);
    // Alter's adapted grid, free outer end: no fold, and the outer boundary much smoother.
    let adapted = &smooth[3];
    assert_eq!(adapted["folded_cells"], 0);
    let settings = adapted["settings"].as_str().expect("text");
    assert!(settings.contains("free outer end"), "{settings}");
    let cut: f64 = settings
        .rsplit_once('(')
        .and_then(|(_, t)| t.split('×').next())
        .and_then(|t| t.parse().ok())
        .expect("roughness factor");
    assert!(cut >= 5.0, "{settings}");
    for r in &smooth[..3] {
        let before = r["max_stretching_before"].as_f64().expect("number");
        let after = r["max_stretching_after"].as_f64().expect("number");
        assert!(after < before, "{r}");
        assert_eq!(r["folded_cells"], 0);
    }
    let files = listing(&d.join("out"));
    for f in [
        "report.md",
        "naca2412_viscous.su2",
        "viscous_quaternion_20_te.png",
        "viscous_spring_20_te.svg",
        "viscous_spring_20_wall.png",
        "viscous_spring_20_whole.png",
        "viscous_angle-cg_20.vtu",
        "smooth1_noisy_before.png",
        "smooth3_cavity_after.vts",
        "smooth4_adapted_outer_arclength_before.png",
        "smooth4_adapted_outer_arclength_after.svg",
        "smooth4_adapted_grid_after.png",
        "smooth4_adapted_before.vts",
        "compare_viscous_20_te.png",
        "compare_viscous_20_airfoil.svg",
    ] {
        assert!(files.contains(&f.to_string()), "{f} missing: {files:?}");
    }
    assert!(!files.iter().any(|f| f.contains("deform-tmp")), "{files:?}");
    let md = std::fs::read_to_string(d.join("out/report.md")).expect("report");
    assert!(md.contains("| viscous | quaternion | 20 |"), "{md}");
    assert!(md.contains("![quaternion trailing edge](viscous_quaternion_20_te.png)"));
    for f in &files {
        if let Some(stem) = f.strip_suffix(".png") {
            let bytes = std::fs::read(d.join("out").join(f)).expect("png");
            assert!(bytes.starts_with(b"\x89PNG"), "{stem}");
        }
    }
}

#[test]
fn demo_into_a_file_fails_cleanly() {
    let d = tmp_dir("demo-fail");
    std::fs::write(d.join("taken"), "not a directory").expect("write");
    let o = Command::new(env!("CARGO_BIN_EXE_deform"))
        .current_dir(&d)
        .args(["demo", "--quick", "--out", "taken"])
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.starts_with("deform: error: taken"), "{err}");
    assert_eq!(listing(&d), ["taken"]);
}
