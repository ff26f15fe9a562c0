//! `deform tangent` and `deform adjoint` on Plot3D grids (the TFI of `deform move --wall`):
//! the tangent of a rigid motion's derivative (the wall nodes' `d/dθ`, written as a
//! perturbation file) is the central difference of two `deform move --rotate θ ± h` runs,
//! the error falling as `h²` until rounding, for the quaternion and the displacement TFI, in
//! 2D, 3D and on one block of two; the tangent and adjoint files satisfy the dot-product
//! identity `⟨J v, w⟩ = ⟨v, Jᵀ w⟩` to rounding; a grid of several blocks is its blocks run one
//! by one; options the Plot3D path does not take are refused with nothing written.

mod common;

use std::fmt::Write as _;
use std::path::Path;

use common::{deform, deform_json, deform_refused, read_csv, tmp_dir, Rng};

/// A block: `dims` and its points (`i` fastest).
type Block = ([usize; 3], Vec<[f64; 3]>);

/// A curved 2D block: `ni` points around an annular sector from `a0` to `a1` radians, `nj`
/// outward from radius 1 (graded), jittered.
fn sector(ni: usize, nj: usize, a0: f64, a1: f64, seed: u64) -> Block {
    let mut rng = Rng(seed);
    let mut pts = Vec::new();
    for j in 0..nj {
        let r = 1.0 + (j as f64 / (nj - 1) as f64).powf(1.4);
        for i in 0..ni {
            let a = a0 + (a1 - a0) * i as f64 / (ni - 1) as f64;
            let inner = 0 < i && i + 1 < ni && 0 < j && j + 1 < nj;
            let e = if inner { 0.02 } else { 0.0 };
            pts.push([
                r * a.cos() + e * rng.real(),
                0.7 * r * a.sin() + e * rng.real(),
                0.0,
            ]);
        }
    }
    ([ni, nj, 1], pts)
}

/// A curved 3D block: `i` around, `j` up, `k` outward (graded), jittered inside.
fn shell(seed: u64) -> Block {
    let (ni, nj, nk) = (5, 4, 5);
    let mut rng = Rng(seed);
    let mut pts = Vec::new();
    for k in 0..nk {
        let r = 1.0 + 0.8 * (k as f64 / (nk - 1) as f64).powf(1.3);
        for j in 0..nj {
            for i in 0..ni {
                let a = 0.3 * i as f64;
                let inner = [i, j, k]
                    .iter()
                    .zip([ni, nj, nk])
                    .all(|(&c, n)| 0 < c && c + 1 < n);
                let e = if inner { 0.02 } else { 0.0 };
                pts.push([
                    r * a.cos() + e * rng.real(),
                    r * a.sin() + e * rng.real(),
                    0.4 * j as f64 + 0.1 * a.sin() * r + e * rng.real(),
                ]);
            }
        }
    }
    ([ni, nj, nk], pts)
}

/// Writes an ASCII multi-block Plot3D grid (round-trip digits).
fn write_grid(path: &Path, dim: usize, blocks: &[Block]) {
    let mut s = format!("{}\n", blocks.len());
    for (dims, _) in blocks {
        let d: Vec<String> = dims[..dim].iter().map(|n| n.to_string()).collect();
        writeln!(s, "{}", d.join(" ")).unwrap();
    }
    for (_, pts) in blocks {
        for c in 0..dim {
            let v: Vec<String> = pts.iter().map(|p| format!("{:?}", p[c])).collect();
            writeln!(s, "{}", v.join(" ")).unwrap();
        }
    }
    std::fs::write(path, s).unwrap();
}

/// Every point of a Plot3D grid file, block by block.
fn read_points(path: &Path) -> Vec<[f64; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let g = deform_cli::parse_plot3d(&bytes, &Default::default())
        .unwrap()
        .0;
    g.blocks.iter().flat_map(|b| b.points.clone()).collect()
}

/// Global numbers of the points of `blocks[b]` on the face `index` = 0 or last of
/// direction `dir`, for each `(b, dir, max)`.
fn wall_nodes(blocks: &[Block], faces: &[(usize, usize, bool)]) -> Vec<usize> {
    let mut out = Vec::new();
    let mut start = 0;
    for (b, (dims, pts)) in blocks.iter().enumerate() {
        for &(_, dir, max) in faces.iter().filter(|f| f.0 == b) {
            let at = if max { dims[dir] - 1 } else { 0 };
            for p in 0..pts.len() {
                let ijk = [p % dims[0], (p / dims[0]) % dims[1], p / dims[0] / dims[1]];
                if ijk[dir] == at {
                    out.push(start + p);
                }
            }
        }
        start += pts.len();
    }
    out.sort_unstable();
    out
}

fn write_rows(path: &Path, rows: impl Iterator<Item = (usize, Vec<f64>)>) {
    let mut s = String::from("# node values\n");
    for (i, v) in rows {
        let v: Vec<String> = v.iter().map(|x| format!("{x:e}")).collect();
        writeln!(s, "{i} {}", v.join(" ")).unwrap();
    }
    std::fs::write(path, s).unwrap();
}

/// A rotation of the linearisation point: degrees, axis (3D), centre.
struct Turn {
    degrees: f64,
    axis: [f64; 3],
    center: [f64; 3],
}

impl Turn {
    fn args(&self, dim: usize, degrees: f64) -> Vec<String> {
        let c: Vec<String> = self.center[..dim]
            .iter()
            .map(|x| format!("{x:?}"))
            .collect();
        let mut a = vec![
            "--rotate".into(),
            format!("{degrees:?}"),
            "--center".into(),
            c.join(","),
        ];
        if dim == 3 {
            let x: Vec<String> = self.axis.iter().map(|x| format!("{x:?}")).collect();
            a.extend(["--axis".into(), x.join(",")]);
        }
        a
    }
}

/// Runs `deform` with `args` (and `extra`), asserting success.
fn run(dir: &Path, args: &[&str], extra: &[String]) {
    let mut v: Vec<&str> = args.to_vec();
    v.extend(extra.iter().map(String::as_str));
    let o = deform(dir, &v);
    assert!(
        o.status.success(),
        "{v:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// `max |FD(h) − tangent| / max |tangent|` off the wall for `h` = 1, 0.1, 0.01, 0.001
/// degrees, the tangent taken along `d/dθ` of the wall nodes (per degree), FD of `deform
/// move` itself.
fn step_study(
    dir: &Path,
    dim: usize,
    method: &str,
    wall: &str,
    walls: &[usize],
    t: &Turn,
) -> Vec<f64> {
    let common = ["--method", method, "--wall", wall];
    let mv = |deg: f64, out: &str| {
        let mut a = vec!["move", "g.x", "--out", out];
        a.extend(common);
        run(dir, &a, &t.args(dim, deg));
        read_points(&dir.join(out))
    };
    let base = mv(t.degrees, "base.x");
    // d/dθ of q(θ)(p − c) + c is a × (moved − c), per radian; per degree × π/180.
    let norm = t.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
    let a = t.axis.map(|x| x / norm);
    let k = std::f64::consts::PI / 180.0;
    let v = walls.iter().map(|&i| {
        let r: Vec<f64> = (0..3).map(|c| base[i][c] - t.center[c]).collect();
        let x = [
            a[1] * r[2] - a[2] * r[1],
            a[2] * r[0] - a[0] * r[2],
            a[0] * r[1] - a[1] * r[0],
        ];
        (i, x[..dim].iter().map(|x| k * x).collect())
    });
    write_rows(&dir.join("v.txt"), v);
    let mut a = vec![
        "tangent",
        "g.x",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    a.extend(common);
    run(dir, &a, &t.args(dim, t.degrees));
    let tan = read_csv(&dir.join("t.csv"));
    assert_eq!(tan.len(), base.len());
    let scale = tan
        .iter()
        .flat_map(|r| r.1.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    [1.0, 0.1, 0.01, 0.001]
        .iter()
        .map(|&h| {
            let (p, m) = (mv(t.degrees + h, "p.x"), mv(t.degrees - h, "m.x"));
            let mut err = 0.0f64;
            // Off the wall: the wall nodes' own difference is the rotation's.
            for (i, (_, x)) in tan.iter().enumerate() {
                if walls.binary_search(&i).is_ok() {
                    continue;
                }
                for c in 0..dim {
                    err = err.max(((p[i][c] - m[i][c]) / (2.0 * h) - x[c]).abs());
                }
            }
            err / scale
        })
        .collect()
}

/// The errors of a step study, three digits each.
fn show(e: &[f64]) -> String {
    let v: Vec<String> = e.iter().map(|x| format!("{x:.3e}")).collect();
    v.join(", ")
}

/// The error falls as `h²` (about 100× per decade) over the first steps, the first is a
/// visible truncation error (the map is not linear in θ), and it reaches `floor`.
fn assert_h2(e: &[f64], floor: f64, what: &str) {
    assert!(e[0] > 1e-7, "{what}: no truncation at h = 1°: {e:?}");
    for w in e[..3].windows(2) {
        let r = w[0] / w[1];
        assert!((60.0..170.0).contains(&r), "{what}: not h²: {e:?}");
    }
    assert!(
        e.iter().cloned().fold(f64::MAX, f64::min) < floor,
        "{what}: {e:?}"
    );
}

#[test]
fn tangent_is_the_central_difference_of_deform_move_2d() {
    let d = tmp_dir("tfi-sens-fd-2d");
    let blocks = [sector(9, 6, 0.1, 1.6, 3)];
    write_grid(&d.join("g.x"), 2, &blocks);
    let walls = wall_nodes(&blocks, &[(0, 1, false)]);
    let t = Turn {
        degrees: 25.0,
        axis: [0.0, 0.0, 1.0],
        center: [0.3, -0.2, 0.0],
    };
    for method in ["tfi", "tfi-displacement"] {
        let e = step_study(&d, 2, method, "jmin", &walls, &t);
        eprintln!("2D {method}: {}", show(&e));
        assert_h2(&e, 1e-9, method);
    }
}

#[test]
fn tangent_is_the_central_difference_of_deform_move_3d() {
    let d = tmp_dir("tfi-sens-fd-3d");
    let blocks = [shell(5)];
    write_grid(&d.join("g.x"), 3, &blocks);
    let walls = wall_nodes(&blocks, &[(0, 2, false)]);
    let t = Turn {
        degrees: 20.0,
        axis: [0.3, 0.5, 1.0],
        center: [0.2, -0.1, 0.3],
    };
    for method in ["tfi", "tfi-displacement"] {
        let e = step_study(&d, 3, method, "kmin", &walls, &t);
        eprintln!("3D {method}: {}", show(&e));
        assert_h2(&e, 1e-9, method);
    }
}

#[test]
fn tangent_of_one_block_of_two_is_the_central_difference() {
    let d = tmp_dir("tfi-sens-fd-blocks");
    let blocks = [sector(7, 5, 0.1, 0.8, 1), sector(9, 6, 0.8, 1.9, 2)];
    write_grid(&d.join("g.x"), 2, &blocks);
    let walls = wall_nodes(&blocks, &[(1, 0, true)]);
    let t = Turn {
        degrees: -15.0,
        axis: [0.0, 0.0, 1.0],
        center: [-0.1, 0.6, 0.0],
    };
    let e = step_study(&d, 2, "tfi", "2:imax", &walls, &t);
    eprintln!("block 2 of 2: {}", show(&e));
    assert_h2(&e, 1e-9, "2:imax");
    // Block 1 stays, in the move and in the derivative.
    let tan = read_csv(&d.join("t.csv"));
    assert!(tan[..35].iter().all(|(_, x)| x.iter().all(|&v| v == 0.0)));
}

/// `⟨J v, w⟩` and `⟨v, Jᵀ w⟩` through the files, random `v` on the wall nodes and `w`
/// everywhere, about a turned wall; returns them.
fn dot_products(dir: &Path, dim: usize, args: &[&str], walls: &[usize], n: usize) -> (f64, f64) {
    let mut rng = Rng(0x5eed + n as u64);
    let w: Vec<Vec<f64>> = (0..n)
        .map(|_| (0..dim).map(|_| rng.real()).collect())
        .collect();
    let v: Vec<Vec<f64>> = walls
        .iter()
        .map(|_| (0..dim).map(|_| rng.real()).collect())
        .collect();
    let mut sens = String::from("\"PointID\",\"Sensitivity_x\",\"Sensitivity_y\"");
    sens.push_str(if dim == 3 {
        ",\"Sensitivity_z\"\n"
    } else {
        "\n"
    });
    for (i, w) in w.iter().enumerate() {
        let s: Vec<String> = w.iter().map(|x| format!("{x:e}")).collect();
        writeln!(sens, "{i},{}", s.join(",")).unwrap();
    }
    std::fs::write(dir.join("sens.csv"), sens).unwrap();
    write_rows(
        &dir.join("v.txt"),
        walls.iter().copied().zip(v.iter().cloned()),
    );
    let mut t = vec![
        "--json",
        "tangent",
        "g.x",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    t.extend(args);
    let r = deform_json(dir, &t);
    assert_eq!(r["rows"], n, "{r}");
    assert_eq!(r["wall_nodes"], walls.len(), "{r}");
    let mut a = vec![
        "--json",
        "adjoint",
        "g.x",
        "--sensitivity",
        "sens.csv",
        "--out",
        "g.csv",
    ];
    a.extend(args);
    let r = deform_json(dir, &a);
    assert_eq!(r["rows"], walls.len(), "{r}");
    let (jv, g) = (read_csv(&dir.join("t.csv")), read_csv(&dir.join("g.csv")));
    let rows: Vec<usize> = g.iter().map(|r| r.0).collect();
    assert_eq!(rows, walls, "the adjoint lists the wall nodes");
    let lhs: f64 = jv
        .iter()
        .map(|(i, x)| (0..dim).map(|c| x[c] * w[*i][c]).sum::<f64>())
        .sum();
    let rhs: f64 = (g.iter().zip(&v))
        .map(|((_, x), v)| (0..dim).map(|c| x[dim + c] * v[c]).sum::<f64>())
        .sum();
    (lhs, rhs)
}

fn assert_identity(dir: &Path, dim: usize, args: &[&str], walls: &[usize], n: usize) {
    let (lhs, rhs) = dot_products(dir, dim, args, walls, n);
    eprintln!("{args:?}: <Jv, w> = {lhs:.17e}, <v, J'w> = {rhs:.17e}");
    assert!(
        (lhs - rhs).abs() <= 1e-13 * lhs.abs().max(1.0),
        "{args:?}: {lhs} vs {rhs}"
    );
}

#[test]
fn tangent_and_adjoint_satisfy_the_dot_product_identity() {
    let d = tmp_dir("tfi-sens-dot");
    let blocks = [sector(9, 6, 0.1, 1.6, 3)];
    write_grid(&d.join("g.x"), 2, &blocks);
    let walls = wall_nodes(&blocks, &[(0, 1, false)]);
    for m in ["tfi", "tfi-displacement"] {
        let args = [
            "--method", m, "--wall", "jmin", "--rotate", "30", "--center", "0.1,0.2",
        ];
        assert_identity(&d, 2, &args, &walls, 54);
    }
    // Default method (tfi), default centre, and the undeformed grid as the point.
    assert_identity(&d, 2, &["--wall", "jmin", "--rotate", "30"], &walls, 54);
    assert_identity(&d, 2, &["--wall", "jmin"], &walls, 54);
    let d3 = tmp_dir("tfi-sens-dot-3d");
    let blocks = [shell(5)];
    write_grid(&d3.join("g.x"), 3, &blocks);
    let walls = wall_nodes(&blocks, &[(0, 0, true)]);
    for m in ["tfi", "tfi-displacement"] {
        let args = [
            "--method",
            m,
            "--wall",
            "imax",
            "--rotate",
            "-35",
            "--axis",
            "1,0.2,0.4",
        ];
        assert_identity(&d3, 3, &args, &walls, 100);
        let args = [
            "--method",
            m,
            "--wall",
            "imax",
            "--translate",
            "0.1,-0.3,0.2",
        ];
        assert_identity(&d3, 3, &args, &walls, 100);
    }
    let d2 = tmp_dir("tfi-sens-dot-blocks");
    let blocks = [sector(7, 5, 0.1, 0.8, 1), sector(9, 6, 0.8, 1.9, 2)];
    write_grid(&d2.join("g.x"), 2, &blocks);
    let walls = wall_nodes(&blocks, &[(0, 1, false), (1, 1, false)]);
    assert_identity(
        &d2,
        2,
        &["--wall", "all:jmin", "--rotate", "12"],
        &walls,
        89,
    );
}

#[test]
fn a_grid_of_blocks_is_its_blocks_one_by_one() {
    let d = tmp_dir("tfi-sens-blocks");
    let blocks = [sector(7, 5, 0.1, 0.8, 1), sector(9, 6, 0.8, 1.9, 2)];
    write_grid(&d.join("g.x"), 2, &blocks);
    let mut rng = Rng(99);
    let n = 35 + 54;
    let walls = wall_nodes(&blocks, &[(0, 1, false), (1, 1, false)]);
    let v: Vec<(usize, Vec<f64>)> = walls
        .iter()
        .map(|&i| (i, vec![rng.real(), rng.real()]))
        .collect();
    write_rows(&d.join("v.txt"), v.iter().cloned());
    let args = ["--wall", "all:jmin", "--rotate", "12"];
    let mut t = vec![
        "tangent",
        "g.x",
        "--perturbation",
        "v.txt",
        "--out",
        "t.csv",
    ];
    t.extend(args);
    run(&d, &t, &[]);
    let whole = read_csv(&d.join("t.csv"));
    assert_eq!(whole.len(), n);
    // Each block alone (the default centre is its own wall's centroid in both runs).
    let mut start = 0;
    for (b, blk) in blocks.iter().enumerate() {
        let len = blk.1.len();
        write_grid(&d.join("one.x"), 2, std::slice::from_ref(blk));
        let mine = v.iter().filter(|(i, _)| (start..start + len).contains(i));
        write_rows(&d.join("vb.txt"), mine.map(|(i, x)| (i - start, x.clone())));
        let t = [
            "tangent",
            "one.x",
            "--perturbation",
            "vb.txt",
            "--out",
            "tb.csv",
            "--wall",
            "jmin",
            "--rotate",
            "12",
        ];
        run(&d, &t, &[]);
        let alone = read_csv(&d.join("tb.csv"));
        for (k, (_, x)) in alone.iter().enumerate() {
            assert_eq!(*x, whole[start + k].1, "block {} node {k}", b + 1);
        }
        start += len;
    }
}

#[test]
fn options_the_grid_does_not_take_are_refused_and_nothing_is_written() {
    let d = tmp_dir("tfi-sens-refusals");
    let blocks = [sector(9, 6, 0.1, 1.6, 3)];
    write_grid(&d.join("g.x"), 2, &blocks);
    write_grid(
        &d.join("two.x"),
        2,
        &[sector(7, 5, 0.1, 0.8, 1), sector(9, 6, 0.8, 1.9, 2)],
    );
    std::fs::write(d.join("m.su2"), common::su2_bytes(&common::mesh_2d(4, 3))).unwrap();
    let t = |extra: &[&str]| {
        let mut v = vec![
            "tangent",
            "g.x",
            "--perturbation",
            "missing.txt",
            "--out",
            "t.csv",
        ];
        v.extend(extra);
        v.into_iter().map(String::from).collect::<Vec<_>>()
    };
    // Refused before any file is read: the perturbation file does not even exist.
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--wall", "jmin", "--tol", "1e-8"], "--tol"),
        (vec!["--wall", "jmin", "--max-iter", "5"], "--max-iter"),
        (vec!["--wall", "jmin", "--deformed", "g.x"], "--deformed"),
        (vec!["--wall", "jmin", "--steps", "2"], "--steps"),
        (vec!["--wall", "jmin", "--poisson", "0.2"], "--poisson"),
        (
            vec!["--wall", "jmin", "--idw-exponent", "3"],
            "--idw-exponent",
        ),
        (vec!["--wall", "jmin", "--rbf-kernel", "tps"], "--rbf-"),
        (
            vec!["--wall", "jmin", "--rotate", "5", "--translate", "1,0"],
            "--rotate",
        ),
        (vec!["--rotate", "5"], "--wall"),
    ];
    for (extra, needle) in &cases {
        let v = t(extra);
        let v: Vec<&str> = v.iter().map(String::as_str).collect();
        deform_refused(&d, &v, 1, needle, "t.csv");
    }
    let v = t(&["--wall", "jmin", "--method", "spring"]);
    let v: Vec<&str> = v.iter().map(String::as_str).collect();
    deform_refused(&d, &v, 3, "--method tfi", "t.csv");
    // The adjoint's SU2-only options.
    std::fs::write(d.join("w.txt"), "0 1 1\n").unwrap();
    let a = [
        "adjoint",
        "g.x",
        "--sensitivity",
        "w.txt",
        "--out",
        "g.csv",
        "--wall",
        "jmin",
    ];
    let with = |extra: &[&'static str]| [&a[..], extra].concat();
    deform_refused(&d, &with(&["--markers", "wall"]), 1, "--markers", "g.csv");
    deform_refused(
        &d,
        &with(&["--config", "c.cfg", "--grad-out", "o.dat"]),
        1,
        "--config",
        "g.csv",
    );
    assert!(!d.join("o.dat").exists());
    // A short sensitivity file, a node off the wall, a node listed twice, a bare face on two
    // blocks: refused when read.
    deform_refused(&d, &a, 1, "node 1 has no sensitivity", "g.csv");
    std::fs::write(d.join("p.txt"), "20 0.1 0.1\n").unwrap();
    let p = [
        "tangent",
        "g.x",
        "--perturbation",
        "p.txt",
        "--out",
        "t.csv",
        "--wall",
        "jmin",
    ];
    deform_refused(&d, &p, 1, "node 20 is not on a moving --wall face", "t.csv");
    std::fs::write(d.join("p.txt"), "2 0.1 0.1\n2 0 0\n").unwrap();
    deform_refused(&d, &p, 1, "listed twice", "t.csv");
    std::fs::write(d.join("p.txt"), "2 0.1 0.1\n").unwrap();
    let two = [
        "tangent",
        "two.x",
        "--perturbation",
        "p.txt",
        "--out",
        "t.csv",
        "--wall",
        "jmin",
    ];
    deform_refused(&d, &two, 1, "2 blocks", "t.csv");
    let k = [
        "tangent",
        "g.x",
        "--perturbation",
        "p.txt",
        "--out",
        "t.csv",
        "--wall",
        "kmin",
    ];
    deform_refused(&d, &k, 1, "needs a 3D block", "t.csv");
    // The grid options on an SU2 mesh, TFI on an SU2 mesh.
    let s = [
        "tangent",
        "m.su2",
        "--perturbation",
        "p.txt",
        "--out",
        "t.csv",
    ];
    deform_refused(
        &d,
        &[&s[..], &["--wall", "jmin"]].concat(),
        1,
        "--wall",
        "t.csv",
    );
    deform_refused(
        &d,
        &[&s[..], &["--rotate", "3"]].concat(),
        1,
        "--rotate",
        "t.csv",
    );
    deform_refused(
        &d,
        &[&s[..], &["--method", "tfi"]].concat(),
        3,
        "transfinite",
        "t.csv",
    );
    assert!(!d.join("t.csv").exists() && !d.join("g.csv").exists());
}
