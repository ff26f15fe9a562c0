//! Shared pieces of the sensitivity tests: inner products, random fields, the dot-product
//! check and the dense reference of `ref_dense.py`.
#![allow(dead_code)]

use std::fmt::Write as _;
use std::path::Path;

use deform_kernel::spring::SolveOptions;
use deform_kernel::Real;

use crate::support::python::run_script;
use crate::support::spring::Lcg;

/// Tight stopping for the solves (1e-13 in f64, 1e-6 in f32): the dot-product identity
/// then holds to about this.
pub fn tight<T: Real>() -> SolveOptions<T> {
    SolveOptions {
        residual_tol: T::from_f64(if T::EPSILON.to_f64() < 1e-10 {
            1e-13
        } else {
            1e-6
        }),
        max_iterations: 5000,
        ..SolveOptions::default()
    }
}

/// `Σ_i a_i · b_i` in f64.
pub fn dot<T: Real, const V: usize>(a: &[[T; V]], b: &[[T; V]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| x.to_f64() * y.to_f64())
        .sum()
}

/// `‖a‖₂` in f64.
pub fn norm<T: Real, const V: usize>(a: &[[T; V]]) -> f64 {
    dot(a, a).sqrt()
}

/// A random field in [-1, 1) where `on(i)`, zero elsewhere.
pub fn random<T: Real, const V: usize>(
    n: usize,
    rng: &mut Lcg,
    on: impl Fn(usize) -> bool,
) -> Vec<[T; V]> {
    (0..n)
        .map(|i| {
            let v: [f64; V] = std::array::from_fn(|_| rng.next());
            if on(i) {
                v.map(T::from_f64)
            } else {
                [T::ZERO; V]
            }
        })
        .collect()
}

/// The dot-product test: `|⟨J v, w⟩ − ⟨v, Jᵀ w⟩| ≤ tol · ‖J v‖ ‖w‖`.
pub fn assert_dot<T: Real, const V: usize>(
    jv: &[[T; V]],
    w: &[[T; V]],
    v: &[[T; V]],
    jtw: &[[T; V]],
    tol: f64,
    what: &str,
) {
    let (a, b) = (dot(jv, w), dot(v, jtw));
    let scale = norm(jv) * norm(w);
    assert!(scale > 0.0, "{what}: trivial fields");
    let err = (a - b).abs() / scale;
    assert!(
        err <= tol,
        "{what}: <Jv,w> = {a:e}, <v,J^T w> = {b:e}, rel {err:e} > {tol:e}"
    );
}

/// The dot-product test, its relative error printed (the docs quote it).
pub fn check_dot<T: Real, const V: usize>(
    jv: &[[T; V]],
    w: &[[T; V]],
    v: &[[T; V]],
    g: &[[T; V]],
    tol: f64,
    what: &str,
) {
    let err = (dot(jv, w) - dot(v, g)).abs() / (norm(jv) * norm(w));
    eprintln!("{what}: dot-product relative error {err:.1e}");
    assert_dot(jv, w, v, g, tol, what);
}

/// Largest `|a − b|` over `max |b|`.
pub fn rel_err<T: Real, const V: usize>(a: &[[T; V]], b: &[[f64; V]]) -> f64 {
    let scale = b.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let err = a
        .iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x.to_f64() - y).abs()));
    err / scale
}

fn push_rows<T: Real, const V: usize>(s: &mut String, rows: &[[T; V]]) {
    for r in rows {
        let r: Vec<String> = r.iter().map(|x| format!("{:e}", x.to_f64())).collect();
        writeln!(s, "{}", r.join(" ")).unwrap();
    }
}

/// Runs `ref_dense.py MODE FILE` on `body` (after the header line `MODE`-specific) and parses
/// its output: `J v` (`n` rows) then `Jᵀ w` (`n` rows), `V` columns each.
pub fn reference<const V: usize>(
    mode: &str,
    body: String,
    n: usize,
) -> (Vec<[f64; V]>, Vec<[f64; V]>) {
    let dir = std::env::temp_dir().join(format!("deform-sensitivity-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let input = dir.join(format!("{mode}-{call}.txt"));
    std::fs::write(&input, body).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/sensitivity/ref_dense.py");
    let out = run_script(&script, &[mode, input.to_str().unwrap()]);
    let rows: Vec<[f64; V]> = out
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            std::array::from_fn(|c| v[c])
        })
        .collect();
    assert_eq!(rows.len(), 2 * n, "reference output");
    let (a, b) = rows.split_at(n);
    (a.to_vec(), b.to_vec())
}

/// Input of the `springs` mode: points, undirected edges (stiffness `1/|e|` computed by the
/// reference), fixed mask, `v`, `w`.
pub fn springs_input<T: Real, const D: usize, const V: usize>(
    points: &[[T; D]],
    offsets: &[u32],
    targets: &[u32],
    fixed: &[u8],
    v: &[[T; V]],
    w: &[[T; V]],
) -> String {
    let mut edges = vec![];
    for i in 0..points.len() {
        for &j in &targets[offsets[i] as usize..offsets[i + 1] as usize] {
            let j = j as usize;
            if i < j {
                edges.push((i, j));
            }
        }
    }
    let mut s = format!("{} {D} {V} {}\n", points.len(), edges.len());
    push_rows(&mut s, points);
    for (i, j) in edges {
        writeln!(s, "{i} {j}").unwrap();
    }
    for f in fixed {
        writeln!(s, "{f}").unwrap();
    }
    push_rows(&mut s, v);
    push_rows(&mut s, w);
    s
}

/// Input of the `matrix` mode: the dense matrix over node-major dofs (`n · V` square), the
/// fixed mask per node, `v`, `w`.
pub fn matrix_input<const V: usize>(
    k: &[Vec<f64>],
    fixed: &[bool],
    v: &[[f64; V]],
    w: &[[f64; V]],
) -> String {
    let mut s = format!("{} {V}\n", fixed.len());
    for r in k {
        let r: Vec<String> = r.iter().map(|x| format!("{x:e}")).collect();
        writeln!(s, "{}", r.join(" ")).unwrap();
    }
    for &f in fixed {
        writeln!(s, "{}", f as u8).unwrap();
    }
    push_rows(&mut s, v);
    push_rows(&mut s, w);
    s
}

/// Input of the `idw` mode: points, boundary nodes, exponent, `v`, `w`.
pub fn idw_input<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    p: f64,
    v: &[[T; D]],
    w: &[[T; D]],
) -> String {
    let mut s = format!("{} {D} {} {p:e}\n", points.len(), boundary.len());
    push_rows(&mut s, points);
    for b in boundary {
        writeln!(s, "{b}").unwrap();
    }
    push_rows(&mut s, v);
    push_rows(&mut s, w);
    s
}
