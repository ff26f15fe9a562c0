//! `deform move --renumber`: a run renumbered for the solve writes exactly what the same
//! method writes on the renumbered mesh, put back in the input's numbering (rotation,
//! prescribed displacements, several steps; RCM and Hilbert); `auto` leaves ordered meshes
//! alone, bits included, and renumbers a scattered one; the renumbered solution agrees with
//! the unrenumbered one to the solver's tolerance.

mod common;

use std::path::Path;

use common::{deform_json, naca_mesh, read_su2, su2_bytes, tmp_dir, Rng};
use deform_cli::engine::{cells_view, edge_graph, points_d};
use deform_cli::formats::su2::Su2Mesh;
use deform_kernel::order::{hilbert_order, rcm_order};

/// `order[new] = old` and its inverse.
struct Perm {
    order: Vec<u32>,
    inverse: Vec<u32>,
}

impl Perm {
    fn from_order(order: Vec<u32>) -> Perm {
        let mut inverse = vec![0; order.len()];
        for (k, &v) in order.iter().enumerate() {
            inverse[v as usize] = k as u32;
        }
        Perm { order, inverse }
    }

    fn random(n: usize, seed: u64) -> Perm {
        let mut rng = Rng(seed);
        let mut order: Vec<u32> = (0..n as u32).collect();
        for i in (1..n).rev() {
            order.swap(i, rng.below(i + 1));
        }
        Perm::from_order(order)
    }

    /// The order the tool computes for `--renumber rcm|hilbert` (through the same kernel
    /// calls on the same graph).
    fn of(mesh: &Su2Mesh, how: &str) -> Perm {
        let n = mesh.points.len();
        let (mut order, mut inverse) = (vec![0; n], vec![0; n]);
        if how == "rcm" {
            let g = edge_graph(&cells_view(&mesh.elements, n).unwrap(), false).unwrap();
            rcm_order(&g.view().unwrap(), &mut order, &mut inverse).unwrap();
        } else {
            let mut keys = vec![0; n];
            hilbert_order(
                &points_d::<2>(&mesh.points),
                &mut order,
                &mut inverse,
                &mut keys,
            )
            .unwrap();
        }
        Perm { order, inverse }
    }
}

/// The mesh with node `old` renamed `p.inverse[old]` (points moved, every index renamed).
fn renumbered(mesh: &Su2Mesh, p: &Perm) -> Su2Mesh {
    let mut out = mesh.clone();
    out.points = p.order.iter().map(|&o| mesh.points[o as usize]).collect();
    let rename = |nodes: &mut Vec<u32>| {
        for v in nodes.iter_mut() {
            *v = p.inverse[*v as usize];
        }
    };
    rename(&mut out.elements.nodes);
    for m in &mut out.markers {
        rename(&mut m.elements.nodes);
    }
    out
}

/// A NACA inviscid mesh as generated (numbered along grid lines).
fn ordered_naca(dir: &Path, surface: usize, radial: usize) -> Su2Mesh {
    naca_mesh(dir, "inviscid", surface, radial, "ordered.su2");
    read_su2(&dir.join("ordered.su2"))
}

fn bits(points: &[[f64; 3]]) -> Vec<[u64; 3]> {
    points.iter().map(|p| p.map(f64::to_bits)).collect()
}

/// Runs `deform move IN --out OUT EXTRA... --json`, returns the report.
fn run(dir: &Path, input: &str, out: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["move", input, "--out", out, "--json"];
    args.extend_from_slice(extra);
    deform_json(dir, &args)
}

/// Writes a displacement file for the airfoil's nodes (`node dx dy` lines) in the numbering
/// `rename` gives them.
fn displacement_file(mesh: &Su2Mesh, rename: impl Fn(u32) -> u32) -> String {
    let wall = mesh.markers.iter().find(|m| m.name == "airfoil").unwrap();
    let mut nodes = wall.elements.nodes.clone();
    nodes.sort_unstable();
    nodes.dedup();
    let mut lines: Vec<(u32, String)> = nodes
        .iter()
        .map(|&v| {
            let p = mesh.points[v as usize];
            (
                rename(v),
                format!("{:e} {:e}", 0.02 * p[0] * p[0], -0.01 * p[0]),
            )
        })
        .collect();
    lines.sort();
    lines.iter().map(|(v, d)| format!("{v} {d}\n")).collect()
}

#[test]
fn a_renumbered_run_is_the_renumbered_mesh_run_put_back() {
    let dir = tmp_dir("renumber-equivalence");
    let ordered = ordered_naca(&dir, 64, 24);
    let shuffled = renumbered(&ordered, &Perm::random(ordered.points.len(), 0x5eed));
    std::fs::write(dir.join("shuffled.su2"), su2_bytes(&shuffled)).unwrap();
    let cases: [(&str, &[&str]); 4] = [
        (
            "rcm",
            &["--method", "spring", "--marker", "airfoil", "--rotate", "4"],
        ),
        (
            "hilbert",
            &[
                "--method",
                "quaternion",
                "--marker",
                "airfoil",
                "--rotate",
                "6",
            ],
        ),
        (
            "rcm",
            &[
                "--method", "spring", "--marker", "airfoil", "--rotate", "8", "--steps", "2",
            ],
        ),
        (
            "rcm",
            &[
                "--method",
                "spring",
                "--marker",
                "airfoil",
                "--displacements",
                "DISP",
            ],
        ),
    ];
    for (how, extra) in cases {
        let p = Perm::of(&shuffled, how);
        let renum = renumbered(&shuffled, &p);
        std::fs::write(dir.join("renum.su2"), su2_bytes(&renum)).unwrap();
        std::fs::write(dir.join("d_old.txt"), displacement_file(&shuffled, |v| v)).unwrap();
        std::fs::write(
            dir.join("d_new.txt"),
            displacement_file(&shuffled, |v| p.inverse[v as usize]),
        )
        .unwrap();
        let with = |file: &str| -> Vec<&str> {
            let file: &'static str = if file == "old" {
                "d_old.txt"
            } else {
                "d_new.txt"
            };
            extra
                .iter()
                .map(|&a| if a == "DISP" { file } else { a })
                .collect()
        };
        let mut a_args = with("old");
        a_args.extend(["--renumber", how]);
        let a = run(&dir, "shuffled.su2", "a.su2", &a_args);
        let mut b_args = with("new");
        b_args.extend(["--renumber", "off"]);
        let b = run(&dir, "renum.su2", "b.su2", &b_args);
        assert_eq!(a["renumber"]["method"], how, "{extra:?}");
        assert_eq!(b["renumber"]["method"], "off");
        assert_eq!(a["iterations"], b["iterations"], "{extra:?}");
        let pa = read_su2(&dir.join("a.su2")).points;
        let pb = read_su2(&dir.join("b.su2")).points;
        let back: Vec<[f64; 3]> = p.inverse.iter().map(|&k| pb[k as usize]).collect();
        assert_eq!(
            bits(&pa),
            bits(&back),
            "{how} {extra:?}: not the renumbered run's bits"
        );
        // The same solution as without renumbering, to the solver's tolerance.
        let mut c_args = with("old");
        c_args.extend(["--renumber", "off"]);
        run(&dir, "shuffled.su2", "c.su2", &c_args);
        let pc = read_su2(&dir.join("c.su2")).points;
        let moved = pa
            .iter()
            .zip(&shuffled.points)
            .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]));
        let scale = moved.fold(0.0, f64::max);
        let gap = pa
            .iter()
            .zip(&pc)
            .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
            .fold(0.0, f64::max);
        assert!(
            scale > 0.0 && gap <= 1e-6 * scale,
            "{how} {extra:?}: {gap} vs {scale}"
        );
    }
}

#[test]
fn auto_leaves_ordered_meshes_alone_and_renumbers_scattered_ones() {
    let dir = tmp_dir("renumber-auto");
    let ordered = ordered_naca(&dir, 256, 80);
    let n = ordered.points.len();
    assert!(n >= deform_cli::renumber::AUTO_MIN_NODES, "{n}");
    let spring = [
        "--method", "spring", "--marker", "airfoil", "--rotate", "3", "--tol", "1e-8",
    ];
    let auto = run(&dir, "ordered.su2", "auto.su2", &spring);
    let mut off_args = spring.to_vec();
    off_args.extend(["--renumber", "off"]);
    run(&dir, "ordered.su2", "off.su2", &off_args);
    assert_eq!(auto["renumber"]["method"], "off", "{}", auto["renumber"]);
    assert_eq!(
        std::fs::read(dir.join("auto.su2")).unwrap(),
        std::fs::read(dir.join("off.su2")).unwrap(),
        "auto on an ordered mesh changed the bits"
    );
    // The same mesh numbered at random: auto renumbers it and the band shrinks.
    let shuffled = renumbered(&ordered, &Perm::random(n, 77));
    std::fs::write(dir.join("shuffled.su2"), su2_bytes(&shuffled)).unwrap();
    let r = run(&dir, "shuffled.su2", "s.su2", &spring)["renumber"].clone();
    assert_eq!(r["method"], "rcm", "{r}");
    let (before, after) = (
        r["mean_distance_before"].as_f64().unwrap(),
        r["mean_distance_after"].as_f64().unwrap(),
    );
    assert!(before > n as f64 / 4.0 && after < 1000.0, "{r}");
    assert!(r["bandwidth_after"].as_u64().unwrap() < r["bandwidth_before"].as_u64().unwrap());
    // Small meshes stay as given whatever their numbering.
    let small = ordered_naca(&dir, 64, 24);
    let small = renumbered(&small, &Perm::random(small.points.len(), 78));
    std::fs::write(dir.join("small.su2"), su2_bytes(&small)).unwrap();
    let r = run(&dir, "small.su2", "t.su2", &spring)["renumber"].clone();
    assert_eq!(r["method"], "off", "{r}");
}
