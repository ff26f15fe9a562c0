//! The assembled elasticity stiffness and its Dirichlet solution against scikit-fem
//! (ElementTriP1, ElementQuad1, ElementTetP1, ElementHex1 with 2×2(×2) Gauss points, the
//! same element-wise Young's modulus and Poisson ratio, plane strain) on small jittered
//! meshes: `ref_skfem.py` beside this file.

#[path = "../support/mod.rs"]
mod support;

use std::fmt::Write as _;
use std::path::Path;

use deform_kernel::elasticity::Modulus;
use deform_kernel::spring::SolveOptions;
use support::elasticity::{assembled, grid2, grid3, solve, Kind, Mesh};
use support::python::run_script;

/// The reference's dense stiffness (node-major dofs) and solution.
fn reference<const D: usize>(
    m: &Mesh<D>,
    moduli: &[f64],
    nu: f64,
    bc: &[[f64; D]],
) -> (Vec<Vec<f64>>, Vec<[f64; D]>) {
    let n = m.points.len();
    let mut s = format!("{D} {n} {} {nu:e}\n", moduli.len());
    for p in &m.points {
        let row: Vec<String> = p.iter().map(|x| format!("{x:e}")).collect();
        writeln!(s, "{}", row.join(" ")).unwrap();
    }
    let cells = m.cells();
    for ((kind, nodes), e) in cells.iter().zip(moduli) {
        let ns: Vec<String> = nodes.iter().map(|v| v.to_string()).collect();
        writeln!(s, "{} {e:e} {}", kind.vtk_code(), ns.join(" ")).unwrap();
    }
    for (i, u) in bc.iter().enumerate() {
        let us: Vec<String> = u.iter().map(|x| format!("{x:e}")).collect();
        writeln!(s, "{} {}", m.boundary[i] as u8, us.join(" ")).unwrap();
    }
    let dir = std::env::temp_dir().join(format!("deform-elasticity-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One file per call: tests run in parallel threads of one process.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let input = dir.join(format!("mesh{D}-{}-{call}.txt", m.kinds[0]));
    std::fs::write(&input, s).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/elasticity/ref_skfem.py");
    let out = run_script(&script, &[input.to_str().unwrap()]);
    let rows: Vec<Vec<f64>> = out
        .lines()
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect();
    let (k, u) = rows.split_at(n * D);
    let u = u.iter().map(|r| std::array::from_fn(|c| r[c])).collect();
    (k.to_vec(), u)
}

fn compare<const D: usize>(m: &Mesh<D>) {
    let nu = 0.3;
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, nu);
    // A smooth, non-polynomial boundary motion.
    let bc: Vec<[f64; D]> = m
        .points
        .iter()
        .zip(&m.boundary)
        .map(|(p, &b)| {
            std::array::from_fn(|c| {
                if b {
                    0.05 * (2.0 * p[(c + 1) % D] + c as f64).sin()
                } else {
                    0.0
                }
            })
        })
        .collect();
    let (k, u_ref) = reference(m, &a.moduli, nu, &bc);
    // Every block of ours against the reference's dense matrix (zero outside the graph).
    let kmax = k.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    let g = a.graph();
    let n = m.points.len();
    let mut ours = vec![vec![0.0; n * D]; n * D];
    for i in 0..n {
        let mut put = |j: usize, b: &[[f64; D]; D]| {
            for r in 0..D {
                for c in 0..D {
                    ours[i * D + r][j * D + c] = b[r][c];
                }
            }
        };
        put(i, &a.diag[i]);
        for e in g.edge_range(i) {
            put(g.targets()[e] as usize, &a.off[e]);
        }
    }
    let err = ours
        .iter()
        .flatten()
        .zip(k.iter().flatten())
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    assert!(
        err <= 1e-13 * kmax,
        "{:?} stiffness: {err:e} of {kmax:e}",
        m.kinds[0]
    );
    let fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let mut u = bc.clone();
    let options = SolveOptions {
        residual_tol: 1e-14,
        ..SolveOptions::default()
    };
    assert!(solve(&a, &fixed, &mut u, &options).converged);
    let umax = u_ref.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    let err = u
        .iter()
        .flatten()
        .zip(u_ref.iter().flatten())
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    assert!(
        err <= 1e-11 * umax,
        "{:?} solution: {err:e} of {umax:e}",
        m.kinds[0]
    );
}

#[test]
fn triangles_and_quads_match_scikit_fem() {
    compare(&grid2(5, Kind::Simplex, 0.3));
    compare(&grid2(5, Kind::Box, 0.3));
}

#[test]
fn tetrahedra_and_hexahedra_match_scikit_fem() {
    compare(&grid3(3, Kind::Simplex, 0.2));
    compare(&grid3(3, Kind::Box, 0.2));
}
