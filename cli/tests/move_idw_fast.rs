//! `deform move --method idw --idw-theta θ` (issue 14 item 7 through the tool): the fast,
//! tree-based propagation agrees with the exact one (θ = 0: to rounding; θ = 0.5: within its
//! reported bound, which stays under the tolerance) and is refused for other methods.

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

fn run(dir: &Path, out: &str, extra: &[&str]) -> (Value, Vec<[f64; 3]>) {
    let mut args = vec![
        "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "10", "--center", "0.25,0",
        "--method", "idw", "--out", out,
    ];
    args.extend_from_slice(extra);
    let o = deform(dir, &args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let r = serde_json::from_slice(&o.stdout).expect("json");
    let m = deform_cli::parse_su2(&std::fs::read(dir.join(out)).expect("read")).expect("parse");
    (r, m.points)
}

#[test]
fn fast_idw_agrees_with_the_exact_propagation_within_its_bound() {
    let d = tmp_dir("move-idw-fast");
    let o = deform(
        &d,
        &[
            "mesh",
            "naca",
            "--kind",
            "inviscid",
            "--surface-points",
            "96",
            "--radial-points",
            "24",
            "--out",
            "m.su2",
        ],
    );
    assert!(o.status.success());
    let (exact_r, exact) = run(&d, "exact.su2", &[]);
    assert!(exact_r["idw_max_bound"].is_null());
    let max_move = exact_r["max_displacement"].as_f64().expect("max");
    let diff = |a: &[[f64; 3]], b: &[[f64; 3]]| {
        a.iter()
            .zip(b)
            .map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt())
            .fold(0.0, f64::max)
    };
    let (r0, theta0) = run(&d, "t0.su2", &["--idw-theta", "0"]);
    assert_eq!(r0["idw_max_bound"], 0.0);
    assert!(
        diff(&theta0, &exact) <= 1e-12 * max_move,
        "{}",
        diff(&theta0, &exact)
    );
    let (r5, fast) = run(
        &d,
        "t5.su2",
        &["--idw-theta", "0.5", "--idw-tolerance", "0.01"],
    );
    let bound = r5["idw_max_bound"].as_f64().expect("bound");
    assert!(bound > 0.0 && bound <= 0.01, "{bound}");
    let e = diff(&fast, &exact);
    assert!(
        e > 0.0 && e <= 0.05 * max_move,
        "fast vs exact {e} (max motion {max_move})"
    );
    assert_eq!(r5["inverted_cells"], 0);
}

#[test]
fn idw_theta_is_checked_and_only_for_idw() {
    let d = tmp_dir("move-idw-fast-bad");
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
    for (method, theta, needle) in [
        ("spring", "0.5", "applies to --method idw"),
        ("idw", "1.5", "[0, 1)"),
        ("idw", "nan", "[0, 1)"),
    ] {
        let o = deform(
            &d,
            &[
                "move",
                "m.su2",
                "--marker",
                "airfoil",
                "--rotate",
                "3",
                "--method",
                method,
                "--idw-theta",
                theta,
                "--out",
                "o.su2",
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "{err}");
        assert!(!d.join("o.su2").exists());
    }
}
