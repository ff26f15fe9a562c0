//! `deform move --reach R` (issue 15 item 4, decay control): with the quaternion and IDW
//! methods, nodes farther than R from the moved markers keep their coordinates bit for bit,
//! and the motion of the far field shrinks; other methods refuse the option.

mod common;

use std::path::Path;

use common::{deform_json, deform_refused, naca_mesh, read_su2, tmp_dir};
use serde_json::Value;

fn pitched(dir: &Path, method: &str, out: &str, extra: &[&str]) -> Value {
    let mut args = vec![
        "--json", "move", "m.su2", "--marker", "airfoil", "--rotate", "30", "--center", "0.25,0",
        "--method", method, "--out", out,
    ];
    args.extend_from_slice(extra);
    deform_json(dir, &args)
}

#[test]
fn nothing_moves_beyond_the_reach() {
    let d = tmp_dir("move-reach");
    naca_mesh(&d, "inviscid", 64, 20, "m.su2");
    let mesh = read_su2(&d.join("m.su2"));
    let airfoil: Vec<[f64; 3]> = mesh
        .markers
        .iter()
        .filter(|m| m.name == "airfoil")
        .flat_map(|m| m.elements.nodes.iter().map(|&n| mesh.points[n as usize]))
        .collect();
    let dist = |p: [f64; 3]| {
        airfoil
            .iter()
            .map(|q| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt())
            .fold(f64::INFINITY, f64::min)
    };
    for method in ["quaternion", "idw"] {
        let free = pitched(&d, method, "free.su2", &[]);
        let near = pitched(&d, method, "near.su2", &["--reach", "2"]);
        let moved = read_su2(&d.join("near.su2")).points;
        let mut beyond = 0;
        for (p, q) in mesh.points.iter().zip(&moved) {
            if dist(*p) >= 2.0 {
                beyond += 1;
                assert_eq!(
                    p.map(f64::to_bits),
                    q.map(f64::to_bits),
                    "{method}: {p:?} moved"
                );
            }
        }
        assert!(
            beyond > 100,
            "{method}: the test needs nodes beyond the reach ({beyond})"
        );
        let m = |r: &Value| r["max_displacement"].as_f64().expect("max");
        assert!(
            m(&near) < m(&free),
            "{method}: {} vs {}",
            m(&near),
            m(&free)
        );
        assert_eq!(near["inverted_cells"], 0, "{method}");
    }
    deform_refused(
        &d,
        &[
            "move", "m.su2", "--marker", "airfoil", "--rotate", "3", "--method", "spring",
            "--reach", "2", "--out", "o.su2",
        ],
        1,
        "--reach applies",
        "o.su2",
    );
}
