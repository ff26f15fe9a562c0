//! `deform adjoint` and `deform tangent` end to end: on a 2D mesh, for the spring and IDW
//! methods, the adjoint of a volume sensitivity in SU2's restart CSV form and the tangent of a
//! boundary perturbation satisfy the dot-product identity `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` through the
//! files; the adjoint of a uniform sensitivity sums to it (a translation is reproduced); bad
//! files are refused with nothing written. `--method quaternion` (linearised about
//! `--deformed`) satisfies the identity too, and its tangent is the central difference of
//! `deform move --method quaternion` itself; so are those of `--method angle` (`deform move
//! --method angle-cg`) and `--method rbf`, whose greedy form satisfies the identity about
//! `--deformed`.

mod common;

use std::fmt::Write as _;

use common::{deform_json, deform_refused, mesh_2d, read_csv, read_su2, su2_bytes, tmp_dir, Rng};

fn identity_holds(method: &str, extra: &[&str]) {
    let d = tmp_dir(&format!("sensitivity-{method}"));
    let mesh = mesh_2d(7, 5);
    std::fs::write(d.join("m.su2"), su2_bytes(&mesh)).unwrap();
    if !extra.is_empty() {
        // The linearisation point of --method quaternion: `deform move`'s own output.
        let mut moved = mesh.clone();
        for (i, p) in moved.points.iter_mut().enumerate() {
            let [x, y] = turned(mesh.points[i]);
            *p = [x, y, 0.0];
        }
        std::fs::write(d.join("def.su2"), su2_bytes(&moved)).unwrap();
    }
    let n = mesh.points.len();
    let mut boundary = vec![false; n];
    for m in &mesh.markers {
        for &i in &m.elements.nodes {
            boundary[i as usize] = true;
        }
    }
    let mut rng = Rng(7);
    let w: Vec<[f64; 2]> = (0..n).map(|_| [rng.real(), rng.real()]).collect();
    let mut sens = String::from("\"PointID\",\"x\",\"y\",\"Sensitivity_x\",\"Sensitivity_y\"\n");
    for (i, (p, w)) in mesh.points.iter().zip(&w).enumerate() {
        writeln!(sens, "{i},{:e},{:e},{:e},{:e}", p[0], p[1], w[0], w[1]).unwrap();
    }
    std::fs::write(d.join("sens.csv"), sens).unwrap();
    let v: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            if boundary[i] {
                [rng.real(), rng.real()]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let mut pert = String::from("% node dx dy\n");
    for (i, v) in v.iter().enumerate().filter(|(i, _)| boundary[*i]) {
        writeln!(pert, "{i} {:e} {:e}", v[0], v[1]).unwrap();
    }
    std::fs::write(d.join("v.txt"), pert).unwrap();
    let mut common = vec!["--method", method, "--tol", "1e-14"];
    common.extend(extra);
    let mut a = vec![
        "--json",
        "adjoint",
        "m.su2",
        "--sensitivity",
        "sens.csv",
        "--out",
        "g.csv",
    ];
    a.extend(&common);
    let r = deform_json(&d, &a);
    assert_eq!(r["command"], "adjoint");
    let mut t = vec![
        "--json",
        "tangent",
        "m.su2",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    t.extend(&common);
    deform_json(&d, &t);
    let g = read_csv(&d.join("g.csv"));
    let jv = read_csv(&d.join("t.csv"));
    assert_eq!(g.len(), boundary.iter().filter(|&&b| b).count());
    assert_eq!(jv.len(), n);
    let lhs: f64 = jv
        .iter()
        .map(|(i, x)| x[0] * w[*i][0] + x[1] * w[*i][1])
        .sum();
    let rhs: f64 = g
        .iter()
        .map(|(i, x)| x[2] * v[*i][0] + x[3] * v[*i][1])
        .sum();
    assert!(
        (lhs - rhs).abs() <= 1e-10 * lhs.abs().max(1.0),
        "{method}: {lhs} vs {rhs}"
    );
    // Coordinates come back as written.
    for (i, x) in &g {
        assert_eq!([x[0], x[1]], [mesh.points[*i][0], mesh.points[*i][1]]);
    }
}

#[test]
fn adjoint_and_tangent_files_satisfy_the_dot_product_identity() {
    identity_holds("spring", &[]);
    identity_holds("idw-displacements", &[]);
    identity_holds("quaternion", &["--deformed", "def.su2"]);
    identity_holds("angle", &[]);
    identity_holds("rbf", &["--rbf-kernel", "tps", "--rbf-correction", "2"]);
    // Greedy centres: linearised about the motion of --deformed, its centres kept.
    let greedy = [
        "--deformed",
        "def.su2",
        "--rbf-max-centres",
        "8",
        "--rbf-radius",
        "4",
    ];
    identity_holds("rbf", &greedy);
}

/// A point of `mesh_2d(7, 5)` turned by 0.15 rad about the centre `(3.5, 1.75)`, shifted and
/// bulged.
fn turned(p: [f64; 3]) -> [f64; 2] {
    let (x, y) = (p[0] - 3.5, p[1] - 1.75);
    let (c, s) = (0.15f64.cos(), 0.15f64.sin());
    [
        3.5 + c * x - s * y + 0.1 + 0.05 * (0.8 * p[1]).sin(),
        1.75 + s * x + c * y - 0.05 + 0.05 * (0.6 * p[0]).cos(),
    ]
}

/// Writes `node dx dy` rows for the boundary nodes.
fn write_rows(path: &std::path::Path, rows: &[(usize, [f64; 2])]) {
    let mut text = String::new();
    for (i, v) in rows {
        writeln!(text, "{i} {:e} {:e}", v[0], v[1]).unwrap();
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn quaternion_tangent_is_the_central_difference_of_deform_move() {
    tangent_vs_move("quaternion", "quaternion", &["--deformed", "d0.su2"], &[]);
}

#[test]
fn angle_and_rbf_tangents_are_the_central_differences_of_deform_move() {
    tangent_vs_move("angle", "angle-cg", &[], &[]);
    let rbf = ["--rbf-kernel", "tps", "--rbf-correction", "2"];
    tangent_vs_move("rbf", "rbf", &rbf, &rbf);
}

/// The tangent of `--method sens` along a random boundary direction against the central
/// difference of `deform move --method mv` (`mv_extra` its options) about the turned
/// boundary, `h = 1e-4`.
fn tangent_vs_move(sens: &str, mv: &str, sens_extra: &[&str], mv_extra: &[&str]) {
    let d = tmp_dir(&format!("sensitivity-{sens}-fd"));
    let mesh = mesh_2d(7, 5);
    std::fs::write(d.join("m.su2"), su2_bytes(&mesh)).unwrap();
    let mut boundary: Vec<usize> = (mesh.markers.iter())
        .flat_map(|m| m.elements.nodes.iter().map(|&i| i as usize))
        .collect();
    boundary.sort_unstable();
    boundary.dedup();
    let mut rng = Rng(11);
    let h = 1e-4;
    let (mut d0, mut dp, mut dm, mut v) = (vec![], vec![], vec![], vec![]);
    for &i in &boundary {
        let (p, t) = (mesh.points[i], turned(mesh.points[i]));
        let base = [t[0] - p[0], t[1] - p[1]];
        let dir = [rng.real(), rng.real()];
        d0.push((i, base));
        dp.push((i, [base[0] + h * dir[0], base[1] + h * dir[1]]));
        dm.push((i, [base[0] - h * dir[0], base[1] - h * dir[1]]));
        v.push((i, dir));
    }
    for (name, rows) in [("d0", &d0), ("dp", &dp), ("dm", &dm), ("v", &v)] {
        write_rows(&d.join(format!("{name}.txt")), rows);
    }
    for name in ["d0", "dp", "dm"] {
        let (input, out) = (format!("{name}.txt"), format!("{name}.su2"));
        let mut args = vec!["--json", "move", "m.su2", "--method", mv];
        args.extend([
            "--marker",
            "wall",
            "--marker",
            "farfield",
            "--displacements",
        ]);
        args.extend([input.as_str(), "--tol", "1e-14", "--out", &out]);
        args.extend(mv_extra);
        deform_json(&d, &args);
    }
    let mut args = vec!["--json", "tangent", "m.su2", "--method", sens];
    args.extend([
        "--perturbation",
        "v.txt",
        "--tol",
        "1e-14",
        "--out",
        "t.csv",
    ]);
    args.extend(sens_extra);
    deform_json(&d, &args);
    let t = read_csv(&d.join("t.csv"));
    let (p, m) = (read_su2(&d.join("dp.su2")), read_su2(&d.join("dm.su2")));
    let (mut err, mut big) = (0.0f64, 0.0f64);
    for (i, x) in &t {
        for (c, &xc) in x.iter().enumerate() {
            let fd = (p.points[*i][c] - m.points[*i][c]) / (2.0 * h);
            err = err.max((fd - xc).abs());
            big = big.max(xc.abs());
        }
    }
    println!(
        "{sens} tangent vs central difference (h = {h:e}): {:.2e}",
        err / big
    );
    assert!(big > 0.1, "{sens}: a trivial tangent: {big}");
    assert!(
        err <= 1e-6 * big,
        "{sens}: tangent vs central difference: {err:e} (max {big:e})"
    );
}

#[test]
fn bad_files_are_refused_and_nothing_is_written() {
    let d = tmp_dir("sensitivity-bad");
    let mesh = mesh_2d(4, 3);
    std::fs::write(d.join("m.su2"), su2_bytes(&mesh)).unwrap();
    // A node missing from the volume sensitivity.
    std::fs::write(d.join("short.txt"), "0 1 2\n1 1 2\n").unwrap();
    let args = [
        "adjoint",
        "m.su2",
        "--sensitivity",
        "short.txt",
        "--out",
        "g.csv",
    ];
    deform_refused(&d, &args, 1, "has no sensitivity", "g.csv");
    // A perturbation of an interior node.
    let interior = (0..mesh.points.len())
        .find(|&i| {
            !mesh
                .markers
                .iter()
                .any(|m| m.elements.nodes.contains(&(i as u32)))
        })
        .unwrap();
    std::fs::write(d.join("v.txt"), format!("{interior} 1 0\n")).unwrap();
    let args = [
        "tangent",
        "m.su2",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    deform_refused(&d, &args, 1, "not on a marker", "t.csv");
    std::fs::write(d.join("nan.txt"), "0 nan 0\n").unwrap();
    let args = [
        "tangent",
        "m.su2",
        "--perturbation",
        "nan.txt",
        "--out",
        "t.csv",
    ];
    deform_refused(&d, &args, 1, "not a finite number", "t.csv");
}
