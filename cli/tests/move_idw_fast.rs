//! `deform move --method idw --idw-theta θ` (issue 14 item 7 through the tool): the fast,
//! tree-based propagation agrees with the exact one (θ = 0: to rounding; θ = 0.5: within its
//! reported bound, which stays under the tolerance) and is refused for other methods.

mod common;

use std::path::Path;

use common::{deform_json, deform_refused, naca_mesh, read_su2, tmp_dir};
use serde_json::Value;

fn run(dir: &Path, out: &str, extra: &[&str]) -> (Value, Vec<[f64; 3]>) {
    let mut args = vec![
        "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "10", "--center", "0.25,0",
        "--method", "idw", "--out", out,
    ];
    args.extend_from_slice(extra);
    let r = deform_json(dir, &args);
    (r, read_su2(&dir.join(out)).points)
}

#[test]
fn fast_idw_agrees_with_the_exact_propagation_within_its_bound() {
    let d = tmp_dir("move-idw-fast");
    naca_mesh(&d, "inviscid", 96, 24, "m.su2");
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
    naca_mesh(&d, "inviscid", 32, 8, "m.su2");
    for (method, theta, needle) in [
        ("spring", "0.5", "applies to --method idw"),
        ("idw", "1.5", "[0, 1)"),
        ("idw", "nan", "[0, 1)"),
    ] {
        deform_refused(
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
            1,
            needle,
            "o.su2",
        );
    }
}
