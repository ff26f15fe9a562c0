//! `deform adjoint` and `deform tangent` for linear elasticity (one step and load increments,
//! each modulus) and the quaternion method with IDW propagation (exact and tree-based), end
//! to end through the files: the tangent is the central difference of `deform move` itself
//! (exact for the linear one-step map; for the nonlinear maps the difference's error falls
//! as h²), tangent and adjoint satisfy `⟨J v, w⟩ = ⟨v, Jᵀ w⟩`, a uniform translation of the
//! boundary is reproduced exactly, and options a method cannot honour or files of the wrong
//! size are refused with nothing written.

mod common;

use std::fmt::Write as _;
use std::path::PathBuf;

use common::{deform_json, deform_refused, mesh_2d, read_csv, read_su2, su2_bytes};
use common::{tmp_dir, Rng};
use deform_cli::formats::su2::{Su2Marker, Su2Mesh};
use deform_cli::formats::CellList;
use deform_kernel::CellKind;

/// The linearisation point: a point stretched, sheared and bent (`z = 0` stays 0).
fn bent(p: [f64; 3]) -> [f64; 3] {
    let (x, y, z) = (p[0], p[1], p[2]);
    let bend = 0.08 * (0.9 * x).sin() * (1.0 + 0.2 * y);
    [
        1.04 * x + 0.06 * y + 0.05,
        0.97 * y + bend - 0.03,
        z * (1.03 + 0.05 * (0.8 * x).sin()),
    ]
}

/// A 3D box of `3 × 3 × 3` jittered hexahedra, markers "wall" (z = 0) and "farfield" (the
/// other faces).
fn box_3d() -> Su2Mesh {
    let mut rng = Rng(99);
    let id = |i: usize, j: usize, k: usize| (i + 4 * (j + 4 * k)) as u32;
    let mut points = Vec::new();
    for k in 0..4 {
        for j in 0..4 {
            for i in 0..4 {
                points.push([i, j, k].map(|c| c as f64 + 0.1 * rng.real()));
            }
        }
    }
    let mut elements = CellList::new();
    for (i, j, k) in (0..27).map(|c| (c % 3, (c / 3) % 3, c / 9)) {
        let f = |a: usize, b: usize, c: usize| id(i + a, j + b, k + c);
        let hex = [f(0, 0, 0), f(1, 0, 0), f(1, 1, 0), f(0, 1, 0)];
        let top = [f(0, 0, 1), f(1, 0, 1), f(1, 1, 1), f(0, 1, 1)];
        elements.push(CellKind::Hexahedron, &[hex, top].concat());
    }
    let (mut wall, mut far) = (CellList::new(), CellList::new());
    for (a, b) in (0..9).map(|c| (c % 3, c / 3)) {
        let quad =
            |f: &dyn Fn(usize, usize) -> u32| [f(a, b), f(a + 1, b), f(a + 1, b + 1), f(a, b + 1)];
        // The six faces: z = 0 (the wall), z = 3, y = 0, y = 3, x = 0, x = 3.
        wall.push(CellKind::Quad, &quad(&|u, v| id(u, v, 0)));
        far.push(CellKind::Quad, &quad(&|u, v| id(u, v, 3)));
        far.push(CellKind::Quad, &quad(&|u, v| id(u, 0, v)));
        far.push(CellKind::Quad, &quad(&|u, v| id(u, 3, v)));
        far.push(CellKind::Quad, &quad(&|u, v| id(0, u, v)));
        far.push(CellKind::Quad, &quad(&|u, v| id(3, u, v)));
    }
    let marker = |name: &str, elements| Su2Marker {
        name: name.into(),
        elements,
    };
    Su2Mesh {
        dim: 3,
        points,
        elements,
        markers: vec![marker("wall", wall), marker("farfield", far)],
        passthrough: Vec::new(),
        text: Default::default(),
    }
}

/// A case in its own directory: `m.su2`, `def.su2` (the moving nodes bent), the boundary
/// nodes, the moving ones (files list them) and the markers `deform move` moves.
struct Case {
    dir: PathBuf,
    mesh: Su2Mesh,
    boundary: Vec<usize>,
    moving: Vec<usize>,
    markers: Vec<String>,
}

impl Case {
    fn new(name: &str) -> Case {
        Case::sized(name, 7, 5)
    }

    /// On `mesh_2d(nx, ny)`.
    fn sized(name: &str, nx: usize, ny: usize) -> Case {
        Case::on(name, mesh_2d(nx, ny))
    }

    /// On `mesh`, every marker moving.
    fn on(name: &str, mesh: Su2Mesh) -> Case {
        let markers: Vec<String> = mesh.markers.iter().map(|m| m.name.clone()).collect();
        Case::moving(name, mesh, &markers)
    }

    /// On `mesh`, the `markers` moving, the others fixed.
    fn moving(name: &str, mesh: Su2Mesh, markers: &[String]) -> Case {
        let dir = tmp_dir(&format!("sensitivity-methods-{name}"));
        std::fs::write(dir.join("m.su2"), su2_bytes(&mesh)).unwrap();
        let nodes = |keep: &dyn Fn(&str) -> bool| {
            let mut v: Vec<usize> = (mesh.markers.iter().filter(|m| keep(&m.name)))
                .flat_map(|m| m.elements.nodes.iter().map(|&i| i as usize))
                .collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        let (boundary, moving) = (nodes(&|_| true), nodes(&|m| markers.iter().any(|k| k == m)));
        let mut def = mesh.clone();
        for &i in &moving {
            def.points[i] = bent(def.points[i]);
        }
        std::fs::write(dir.join("def.su2"), su2_bytes(&def)).unwrap();
        Case {
            dir,
            mesh,
            boundary,
            moving,
            markers: markers.to_vec(),
        }
    }

    /// Writes `node dx dy [dz]` rows `f(k, node)` for the moving nodes into `name`.
    fn rows(&self, name: &str, f: impl Fn(usize, usize) -> [f64; 3]) {
        let mut text = String::from("% node dx dy [dz]\n");
        for (k, &i) in self.moving.iter().enumerate() {
            write!(text, "{i}").unwrap();
            for x in &f(k, i)[..self.mesh.dim] {
                write!(text, " {x:e}").unwrap();
            }
            text.push('\n');
        }
        std::fs::write(self.dir.join(name), text).unwrap();
    }

    /// The bent boundary's displacement at node `i`.
    fn base(&self, i: usize) -> [f64; 3] {
        let (p, b) = (self.mesh.points[i], bent(self.mesh.points[i]));
        [b[0] - p[0], b[1] - p[1], b[2] - p[2]]
    }

    /// `deform tangent` of the perturbation file `input` into `out`, read back.
    fn tangent(&self, input: &str, sens: &[&str]) -> Vec<(usize, Vec<f64>)> {
        let mut args = vec!["--json", "tangent", "m.su2", "--perturbation", input];
        args.extend(["--tol", "1e-13", "--out", "t.csv"]);
        args.extend(sens);
        let r = deform_json(&self.dir, &args);
        assert_eq!(r["command"], "tangent");
        read_csv(&self.dir.join("t.csv"))
    }

    /// `deform move` with the boundary displacement file `input` into `out`.
    fn moved(&self, input: &str, out: &str, mv: &[&str]) -> Su2Mesh {
        let mut args = vec!["--json", "move", "m.su2", "--displacements", input];
        for m in &self.markers {
            args.extend(["--marker", m]);
        }
        args.extend(["--tol", "1e-13", "--out", out]);
        args.extend(mv);
        deform_json(&self.dir, &args);
        read_su2(&self.dir.join(out))
    }
}

/// The random direction at the `k`-th boundary node.
fn dir(k: usize) -> [f64; 3] {
    let mut rng = Rng(31 + k as u64);
    [rng.real(), rng.real(), rng.real()]
}

/// The largest difference between the tangent `t` and the central difference of `deform
/// move` (`mv`) about the bent boundary along `dir` (direction file `v.txt`), step `h`,
/// relative to the largest tangent entry.
fn central_difference_error(c: &Case, t: &[(usize, Vec<f64>)], mv: &[&str], h: f64) -> f64 {
    for (name, s) in [("dp.txt", h), ("dm.txt", -h)] {
        c.rows(name, |k, i| {
            let (b, v) = (c.base(i), dir(k));
            [0, 1, 2].map(|d| b[d] + s * v[d])
        });
    }
    let (p, m) = (
        c.moved("dp.txt", "dp.su2", mv),
        c.moved("dm.txt", "dm.su2", mv),
    );
    let (mut err, mut big) = (0.0f64, 0.0f64);
    for (i, x) in t {
        for (k, &xk) in x.iter().enumerate() {
            let fd = (p.points[*i][k] - m.points[*i][k]) / (2.0 * h);
            err = err.max((fd - xk).abs());
            big = big.max(xk.abs());
        }
    }
    assert!(big > 0.1, "a trivial tangent: {big}");
    err / big
}

/// The tangent of `--method` `sens` along a random boundary direction against central
/// differences of `deform move` `mv` at `h` and `h/2`: within `exact` of it for a linear
/// map (`quadratic` false), else an error that falls about fourfold when `h` halves.
/// Returns the tangent.
fn step_study(
    c: &Case,
    sens: &[&str],
    mv: &[&str],
    h: f64,
    quadratic: bool,
) -> Vec<(usize, Vec<f64>)> {
    let name = c.dir.file_name().unwrap_or_default().to_string_lossy();
    c.rows("v.txt", |k, _| dir(k));
    let t = c.tangent("v.txt", sens);
    let e1 = central_difference_error(c, &t, mv, h);
    let e2 = central_difference_error(c, &t, mv, h / 2.0);
    println!("{name}: tangent vs central difference: {e1:.3e} (h = {h:e}), {e2:.3e} (h/2)");
    if quadratic {
        assert!(e1 < 1e-2, "{name}: {e1:e}");
        let ratio = e1 / e2;
        assert!(
            (3.0..5.5).contains(&ratio),
            "{name}: the error does not fall as h²: {e1:e} then {e2:e}"
        );
    } else {
        assert!(e1.max(e2) < 1e-8, "{name}: {e1:e}, {e2:e}");
    }
    t
}

#[test]
fn elasticity_one_step_tangent_is_the_difference_of_deform_move() {
    let mv = ["--method", "elasticity"];
    step_study(&Case::new("el1"), &mv, &mv, 1e-2, false);
    let constant = ["--stiffness", "constant", "--poisson", "0.4"];
    let sens = [&mv[..], &constant[..]].concat();
    step_study(&Case::new("el1c"), &sens, &sens, 1e-2, false);
}

#[test]
fn elasticity_increments_tangent_is_the_difference_of_deform_move() {
    let mv = ["--method", "elasticity", "--steps", "3"];
    let sens = [&mv[..], &["--deformed", "def.su2"][..]].concat();
    step_study(&Case::new("el3"), &sens, &mv, 4e-2, true);
    // Wall distances to the moved markers' nodes (here every marker).
    let wall = ["--stiffness", "wall-distance"];
    let mv = [&mv[..], &wall[..]].concat();
    let every = ["--wall-markers", "wall", "farfield"];
    let both = [&sens[..], &wall[..], &every[..]].concat();
    step_study(&Case::new("el3w"), &both, &mv, 4e-2, true);
    // Only the wall moves (the far field is fixed): the distances to the wall's nodes.
    let one = [&sens[..], &wall[..], &["--wall-markers", "wall"][..]].concat();
    let c = Case::moving("el3w-wall", mesh_2d(7, 5), &["wall".to_string()]);
    step_study(&c, &one, &mv, 4e-2, true);
}

#[test]
fn quaternion_idw_tangent_is_the_difference_of_deform_move() {
    let mv = ["--method", "idw"];
    let sens = [&mv[..], &["--deformed", "def.su2"][..]].concat();
    // A boundary of 64 nodes (8 leaves): the tree's far-field clusters are used.
    let exact = step_study(&Case::sized("idw", 20, 12), &sens, &mv, 4e-2, true);
    let fast = ["--idw-theta", "0.7", "--idw-tolerance", "0.5"];
    let mv = [&mv[..], &fast[..]].concat();
    let sens = [&sens[..], &fast[..]].concat();
    let c = Case::sized("idw-fast", 20, 12);
    let t = step_study(&c, &sens, &mv, 4e-2, true);
    let apart = (t.iter().zip(&exact))
        .flat_map(|((_, a), (_, b))| a.iter().zip(b).map(|(a, b)| (a - b).abs()))
        .fold(0.0f64, f64::max);
    println!("fast vs exact IDW tangent: {apart:.3e}");
    assert!(apart > 1e-6, "the fast tangent is the exact one: {apart:e}");
}

/// `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` through the files for `--method` `sens`, and the tangent of a
/// uniform translation of the boundary is that translation at every node.
fn identity_holds(name: &str, sens: &[&str]) {
    identity_holds_on(&Case::new(name), sens);
}

/// [`identity_holds`] on the case `c` (2D or 3D).
fn identity_holds_on(c: &Case, sens: &[&str]) {
    let (n, dim) = (c.mesh.points.len(), c.mesh.dim);
    let name = c.dir.file_name().unwrap_or_default().to_string_lossy();
    let mut rng = Rng(7);
    let mut random = || [rng.real(), rng.real(), rng.real()];
    let w: Vec<[f64; 3]> = (0..n).map(|_| random()).collect();
    let mut text =
        String::from("\"PointID\",\"Sensitivity_x\",\"Sensitivity_y\",\"Sensitivity_z\"\n");
    for (i, w) in w.iter().enumerate() {
        writeln!(text, "{i},{:e},{:e},{:e}", w[0], w[1], w[2]).unwrap();
    }
    std::fs::write(c.dir.join("sens.csv"), text).unwrap();
    assert_eq!(
        c.moving, c.boundary,
        "the identity pairs every boundary row"
    );
    let v: Vec<[f64; 3]> = (0..c.boundary.len()).map(|_| random()).collect();
    c.rows("v.txt", |k, _| v[k]);
    let jv = c.tangent("v.txt", sens);
    let mut args = vec!["--json", "adjoint", "m.su2", "--sensitivity", "sens.csv"];
    args.extend(["--tol", "1e-13", "--out", "g.csv"]);
    args.extend(sens);
    deform_json(&c.dir, &args);
    let g = read_csv(&c.dir.join("g.csv"));
    assert_eq!((jv.len(), g.len()), (n, c.boundary.len()));
    let dot = |a: &[f64], b: &[f64; 3]| (0..dim).map(|d| a[d] * b[d]).sum::<f64>();
    let lhs: f64 = jv.iter().map(|(i, x)| dot(x, &w[*i])).sum();
    // The adjoint rows: node, coordinates, then dJ/dx_b.
    let rhs: f64 = (g.iter().zip(&v))
        .map(|((_, x), v)| dot(&x[dim..], v))
        .sum();
    println!("{name}: <Jv, w> = {lhs:e}, <v, J^T w> = {rhs:e}");
    assert!(
        (lhs - rhs).abs() <= 1e-9 * lhs.abs().max(1.0),
        "{name}: {lhs} vs {rhs}"
    );
    let shift = [0.3, -0.2, 0.1];
    c.rows("u.txt", |_, _| shift);
    for (i, x) in c.tangent("u.txt", sens) {
        let e = (0..dim)
            .map(|d| (x[d] - shift[d]).abs())
            .fold(0.0, f64::max);
        assert!(e < 1e-9, "{name}: node {i} of a translation moves by {x:?}");
    }
}

#[test]
fn adjoint_and_tangent_files_satisfy_the_dot_product_identity() {
    identity_holds("dot-el1", &["--method", "elasticity"]);
    let steps = [
        "--method",
        "elasticity",
        "--steps",
        "3",
        "--deformed",
        "def.su2",
    ];
    identity_holds("dot-el3", &steps);
    let wall = ["--stiffness", "wall-distance", "--wall-markers", "wall"];
    identity_holds("dot-el3w", &[&steps[..], &wall[..]].concat());
    let idw = ["--method", "idw", "--deformed", "def.su2"];
    identity_holds("dot-idw", &idw);
    let fast = ["--idw-theta", "0.5"];
    identity_holds("dot-idw-fast", &[&idw[..], &fast[..]].concat());
    let theta = ["--method", "spring", "--amg-strength", "0.25"];
    identity_holds("dot-spring-theta", &theta);
}

#[test]
fn in_3d_the_identity_holds_and_translations_are_reproduced() {
    let el = [
        "--method",
        "elasticity",
        "--steps",
        "2",
        "--deformed",
        "def.su2",
    ];
    identity_holds_on(&Case::on("dot3-el2", box_3d()), &el);
    identity_holds_on(&Case::on("dot3-el1", box_3d()), &el[..2]);
    let idw = ["--method", "idw", "--deformed", "def.su2"];
    identity_holds_on(&Case::on("dot3-idw", box_3d()), &idw);
    let fast = ["--idw-theta", "0.6"];
    let c = Case::on("dot3-idw-fast", box_3d());
    identity_holds_on(&c, &[&idw[..], &fast[..]].concat());
}

#[test]
fn in_3d_the_tangents_are_the_differences_of_deform_move() {
    let mv = ["--method", "elasticity", "--steps", "2"];
    let sens = [&mv[..], &["--deformed", "def.su2"][..]].concat();
    step_study(&Case::on("fd3-el2", box_3d()), &sens, &mv, 4e-2, true);
    step_study(
        &Case::on("fd3-el1", box_3d()),
        &mv[..2],
        &mv[..2],
        1e-2,
        false,
    );
    let mv = ["--method", "idw"];
    let sens = [&mv[..], &["--deformed", "def.su2"][..]].concat();
    step_study(&Case::on("fd3-idw", box_3d()), &sens, &mv, 4e-2, true);
}

/// Runs `tangent` with `extra` and expects exit 1 with `needle` on stderr, nothing written.
fn refused(c: &Case, extra: &[&str], needle: &str) {
    let mut args = vec![
        "tangent",
        "m.su2",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    args.extend(extra);
    deform_refused(&c.dir, &args, 1, needle, "t.csv");
}

#[test]
fn options_a_method_cannot_honour_and_bad_sizes_are_refused() {
    let c = Case::new("bad");
    c.rows("v.txt", |_, _| [0.1, 0.0, 0.0]);
    let el = ["--method", "elasticity"];
    // Each line: the method, an option it cannot honour, what the error says.
    let cases: [(&str, &[&str], &str); 10] = [
        ("spring", &["--steps", "2"], "--steps applies"),
        ("idw", &["--poisson", "0.3"], "--poisson applies"),
        ("quaternion", &["--idw-theta", "0.5"], "--idw-theta applies"),
        ("angle", &["--stiffness", "constant"], "--stiffness applies"),
        ("elasticity", &["--stiffness", "batina"], "spring stiffness"),
        (
            "elasticity",
            &["--stiffness", "wall-distance"],
            "--wall-markers",
        ),
        ("elasticity", &["--poisson", "0.5"], "--poisson must be"),
        (
            "elasticity",
            &["--deformed", "def.su2"],
            "this map is linear",
        ),
        ("idw", &["--idw-theta", "1.5"], "[0, 1)"),
        (
            "elasticity",
            &["--stiffness", "wall-distance", "--wall-markers", "nowhere"],
            "nowhere",
        ),
    ];
    for (method, extra, needle) in cases {
        refused(&c, &[&["--method", method][..], extra].concat(), needle);
    }
    // A linearisation point with another number of nodes.
    std::fs::write(c.dir.join("small.su2"), su2_bytes(&mesh_2d(4, 3))).unwrap();
    let small = ["--deformed", "small.su2"];
    refused(
        &c,
        &[&["--method", "idw"][..], &small[..]].concat(),
        "points in 2D",
    );
    let steps = ["--method", "elasticity", "--steps", "2"];
    refused(&c, &[&steps[..], &small[..]].concat(), "points in 2D");
    // Solves that stop short of --tol: exit 5, nothing written.
    let short = ["--max-iter", "1"];
    let args = [
        "tangent",
        "m.su2",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    let unconverged = [&args[..], &el[..], &short[..]].concat();
    deform_refused(
        &c.dir,
        &unconverged,
        5,
        "elasticity solves stopped",
        "t.csv",
    );
    let steps = [&unconverged[..], &["--steps", "2"][..]].concat();
    deform_refused(&c.dir, &steps, 5, "elasticity solves stopped", "t.csv");
    // A volume sensitivity with a node missing, for the adjoint.
    std::fs::write(c.dir.join("short.txt"), "0 1 2\n1 1 2\n").unwrap();
    let args = [
        "adjoint",
        "m.su2",
        "--sensitivity",
        "short.txt",
        "--out",
        "g.csv",
    ];
    let args = [&args[..], &el[..]].concat();
    deform_refused(&c.dir, &args, 1, "has no sensitivity", "g.csv");
}
