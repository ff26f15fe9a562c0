//! Linear (Batina) springs: parity with the naive reference, agreement with a dense direct
//! solve, the maximum principle, monotone energy, exact translation, typed errors.
#![allow(clippy::needless_range_loop)]

#[path = "../support/mod.rs"]
mod support;

use deform_host_tests::spring_ref;
use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, LinearMethod, Preconditioner, SolveOptions,
    SpringSystem,
};
use deform_kernel::{Error, Graph, Real};
use support::spring::*;

/// Every whole-solve method, with its name.
fn methods<T: Real>() -> Vec<(&'static str, LinearMethod<T>)> {
    vec![
        ("jacobi", LinearMethod::Jacobi),
        ("gauss-seidel", LinearMethod::GaussSeidel),
        (
            "sor 1.5",
            LinearMethod::Sor {
                omega: T::from_f64(1.5),
            },
        ),
        (
            "cg",
            LinearMethod::Cg {
                preconditioner: Preconditioner::None,
            },
        ),
        (
            "cg+jacobi",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
        ),
        (
            "cg+ssor",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor {
                    omega: T::from_f64(1.2),
                },
            },
        ),
    ]
}

fn solve<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    x: &mut [[T; V]],
    m: LinearMethod<T>,
    opts: &SolveOptions<T>,
) -> deform_kernel::Result<deform_kernel::spring::SolveReport<T>> {
    let mut scratch = vec![[T::ZERO; V]; solve_linear_scratch_len(&m, x.len())];
    sys.solve_linear(x, m, opts, &mut scratch)
}

#[test]
fn stiffness_matches_reference() {
    let (p, e, _) = spring_ref::annulus(6, 20, 1.0, 4.0, 1.3);
    let (off, tg) = spring_ref::csr(p.len(), &e);
    let g = Graph::new(&off, &tg).unwrap();
    for exponent in [1.0, 2.0, 1.5, 0.0] {
        let want = spring_ref::stiffness(&off, &tg, &p, exponent);
        let mut got = vec![0.0f64; tg.len()];
        batina_stiffness(&g, &p, exponent, &mut got).unwrap();
        for (a, b) in got.iter().zip(&want) {
            if exponent == 1.0 || exponent == 2.0 || exponent == 0.0 {
                // sqrt and division are correctly rounded in libm and std alike.
                assert_eq!(a.to_bits(), b.to_bits(), "p = {exponent}");
            } else {
                // powf: libm and the platform may differ by an ulp or two.
                assert!(
                    (a - b).abs() <= 4.0 * f64::EPSILON * b.abs(),
                    "p = {exponent}"
                );
            }
        }
        let pf: Vec<[f32; 2]> = p.iter().map(|q| q.map(|x| x as f32)).collect();
        let mut gotf = vec![0.0f32; tg.len()];
        batina_stiffness(&g, &pf, exponent as f32, &mut gotf).unwrap();
        for (a, b) in gotf.iter().zip(&want) {
            assert!((*a as f64 - b).abs() <= 1e-5 * b.abs());
        }
    }
    // Symmetric bit for bit, as SpringSystem requires.
    let mut k = vec![0.0f64; tg.len()];
    batina_stiffness(&g, &p, 1.0, &mut k).unwrap();
    for (i, _, row) in g.rows() {
        for (o, &j) in row.iter().enumerate() {
            let back = g.find_edge(j as usize, i).unwrap();
            assert_eq!(k[g.edge_range(i).start + o].to_bits(), k[back].to_bits());
        }
    }
}

#[test]
fn stiffness_errors_leave_output_untouched() {
    let p = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let edges = [[0, 1], [1, 2], [2, 3], [3, 0]];
    let (off, tg) = spring_ref::csr(4, &edges);
    let g = Graph::new(&off, &tg).unwrap();
    let mut k = vec![7.0f64; tg.len()];
    let err = batina_stiffness(&g, &p, 1.0, &mut k).unwrap_err();
    assert_eq!(err, Error::ZeroLengthEdge { from: 1, to: 2 });
    assert!(k.iter().all(|&x| x == 7.0));
    let mut q = p;
    q[1] = [1.0, 0.5];
    q[3][1] = f64::NAN;
    assert_eq!(
        batina_stiffness(&g, &q, 1.0, &mut k).unwrap_err(),
        Error::NonFinite {
            arg: "points",
            position: 3
        }
    );
    q[3][1] = 1.0;
    assert!(matches!(
        batina_stiffness(&g, &q, -1.0, &mut k),
        Err(Error::InvalidParameter {
            arg: "exponent",
            ..
        })
    ));
    assert!(matches!(
        batina_stiffness(&g, &q[..3], 1.0, &mut k),
        Err(Error::LengthMismatch { arg: "points", .. })
    ));
    assert!(matches!(
        batina_stiffness(&g, &q, 1.0, &mut k[1..]),
        Err(Error::LengthMismatch {
            arg: "stiffness",
            ..
        })
    ));
    assert!(k.iter().all(|&x| x == 7.0));
}

fn jacobi_parity<T: Real + spring_ref::Float, const V: usize>() {
    let case = annulus::<T>(7, 18);
    let sys = case.system();
    let net = case.net::<T>();
    let mut rng = Lcg(42);
    let x: Vec<[T; V]> = field(&case, &mut rng, None);
    let n = case.n();
    for range in [0..n, 20..77, 0..0, n - 5..n] {
        let sentinel = T::from_f64(-123.0);
        let mut out = vec![[sentinel; V]; n];
        sys.jacobi_sweep(range.clone(), &x, &mut out).unwrap();
        let want = spring_ref::jacobi_sweep(&net, &to_ref::<T, T, V>(&x), range.clone());
        for i in 0..n {
            for c in 0..V {
                if range.contains(&i) {
                    assert_eq!(
                        out[i][c].to_bits_u64(),
                        want[i][c].to_bits_u64(),
                        "node {i} comp {c}"
                    );
                } else {
                    assert_eq!(out[i][c], sentinel, "outside the range must be untouched");
                }
            }
        }
    }
    // SOR / Gauss–Seidel sweeps, in place, also bit for bit.
    for omega in [1.0, 1.6, 0.7] {
        let mut a = x.clone();
        let mut b = to_ref::<T, T, V>(&x);
        for _ in 0..3 {
            sys.sor_sweep(0..n, &mut a, T::from_f64(omega)).unwrap();
            spring_ref::sor_sweep(&net, &mut b, <T as spring_ref::Float>::of(omega));
        }
        assert_eq!(
            bits(&a),
            bits(
                &b.iter()
                    .map(|v| {
                        let mut o = [T::ZERO; V];
                        for (o, &c) in o.iter_mut().zip(v) {
                            *o = c;
                        }
                        o
                    })
                    .collect::<Vec<_>>()
            )
        );
    }
}

/// A sweep split into node ranges (as ranks or threads would run it) gives, after merging the
/// ranges' exact residual sums, the bits of one sweep over all nodes: for every split.
fn split_sweeps_merge_to_the_whole<T: Real, const V: usize>() {
    let case = annulus::<T>(9, 21);
    let sys = case.system();
    let mut rng = Lcg(7);
    let x: Vec<[T; V]> = field(&case, &mut rng, None);
    let n = case.n();
    let mut out = vec![[T::ZERO; V]; n];
    let whole = sys.jacobi_sweep(0..n, &x, &mut out).unwrap();
    assert!(whole.residual_sq > T::ZERO);
    assert_eq!(whole.residual_sq, whole.residual_sum.value::<T>());
    for cuts in [
        vec![1],
        vec![n / 3, 2 * n / 3],
        vec![5, 6, 50, 51, n - 1],
        (1..n).step_by(7).collect(),
    ] {
        let mut bounds = vec![0];
        bounds.extend(cuts);
        bounds.push(n);
        // Merge in reverse order too: the result may not depend on it.
        let mut merged = deform_kernel::exact_sum::ExactSum::new();
        let mut max_change = T::ZERO;
        for w in bounds.windows(2).rev() {
            let s = sys.jacobi_sweep(w[0]..w[1], &x, &mut out).unwrap();
            merged.merge(&s.residual_sum);
            max_change = max_change.max(s.max_change);
        }
        assert_eq!(
            merged.value::<T>().to_bits_u64(),
            whole.residual_sq.to_bits_u64()
        );
        assert_eq!(max_change, whole.max_change);
    }
}

#[test]
fn split_sweeps_give_the_bits_of_one_sweep() {
    split_sweeps_merge_to_the_whole::<f64, 2>();
    split_sweeps_merge_to_the_whole::<f32, 3>();
}

#[test]
fn jacobi_and_sor_sweeps_are_bitwise_equal_to_naive_reference() {
    jacobi_parity::<f64, 2>();
    jacobi_parity::<f64, 6>();
    jacobi_parity::<f32, 2>();
    jacobi_parity::<f32, 6>();
    jacobi_parity::<f64, 1>();
}

#[test]
fn jacobi_sweep_3d_bitwise() {
    let case = cube::<f64>(5);
    let sys = case.system();
    let net = case.net::<f64>();
    let x: Vec<[f64; 7]> = field(&case, &mut Lcg(9), None);
    let mut out = x.clone();
    sys.jacobi_sweep(0..case.n(), &x, &mut out).unwrap();
    let want = spring_ref::jacobi_sweep(&net, &to_ref::<f64, f64, 7>(&x), 0..case.n());
    for (a, b) in out.iter().zip(&want) {
        for (p, q) in a.iter().zip(b) {
            assert_eq!(p.to_bits(), q.to_bits());
        }
    }
}

/// Converged solutions agree with a dense direct solve. Tolerance: with relative residual
/// 1e-13 the error is at most cond(A) × 1e-13 × |x|; for these ~150-unknown meshes cond(A) is
/// below 1e4, so 1e-8 absolute on O(1) values has a wide margin yet catches any wrong operator.
#[test]
fn converged_solutions_match_dense_solve() {
    for case2 in [annulus::<f64>(8, 24)] {
        let net = case2.net::<f64>();
        let sys = case2.system();
        let x0: Vec<[f64; 3]> = field(&case2, &mut Lcg(3), Some(0.0));
        let exact = spring_ref::solve_linear_dense(&net, &to_ref::<f64, f64, 3>(&x0)).unwrap();
        let opts = SolveOptions {
            residual_tol: 1e-13,
            max_iterations: 100_000,
            ..Default::default()
        };
        for (name, m) in methods::<f64>() {
            let mut x = x0.clone();
            let rep = solve(&sys, &mut x, m, &opts).unwrap();
            assert!(rep.converged, "{name}: {rep:?}");
            assert!(rep.residual <= 1e-13, "{name}");
            let rr = sys.relative_residual(&x).unwrap();
            assert_eq!(
                rr, rep.residual,
                "{name}: reported residual is the true one"
            );
            for i in 0..case2.n() {
                for c in 0..3 {
                    assert!((x[i][c] - exact[i][c]).abs() <= 1e-8, "{name} node {i}");
                }
            }
        }
    }
    // 3D and f32.
    let case3 = cube::<f32>(6);
    let net = case3.net::<f64>();
    let sys = case3.system();
    let x0: Vec<[f32; 3]> = field(&case3, &mut Lcg(5), Some(0.0));
    let exact = spring_ref::solve_linear_dense(&net, &to_ref::<f32, f64, 3>(&x0)).unwrap();
    for (name, m) in methods::<f32>() {
        let mut x = x0.clone();
        let rep = solve(&sys, &mut x, m, &SolveOptions::default()).unwrap();
        assert!(rep.converged, "{name}: {rep:?}");
        for i in 0..case3.n() {
            for c in 0..3 {
                // f32: residual 1.2e-5 (the f32 default) and rounding, values O(1).
                assert!(
                    (x[i][c] as f64 - exact[i][c]).abs() <= 1e-3,
                    "{name} node {i}"
                );
            }
        }
    }
}

/// Maximum principle (the free values are weighted averages of their neighbours, weights
/// positive): every converged free value lies within [min, max] of the fixed values, per
/// component. Slack: 1e-12 of the data range (the converged solution is within the solver
/// tolerance of the exact one, which obeys the principle exactly).
#[test]
fn maximum_principle() {
    let case = annulus::<f64>(10, 30);
    let sys = case.system();
    let x0: Vec<[f64; 4]> = field(&case, &mut Lcg(77), Some(5.0)); // start far outside
    for (name, m) in methods::<f64>() {
        let mut x = x0.clone();
        let opts = SolveOptions {
            residual_tol: 1e-14,
            max_iterations: 200_000,
            ..Default::default()
        };
        let rep = solve(&sys, &mut x, m, &opts).unwrap();
        assert!(rep.converged, "{name}");
        for c in 0..4 {
            let fixed: Vec<f64> = (0..case.n())
                .filter(|&i| case.fixed[i] != 0)
                .map(|i| x[i][c])
                .collect();
            let lo = fixed.iter().cloned().fold(f64::INFINITY, f64::min);
            let hi = fixed.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let slack = 1e-12 * (hi - lo);
            for i in 0..case.n() {
                assert!(
                    x[i][c] >= lo - slack && x[i][c] <= hi + slack,
                    "{name} node {i} comp {c}"
                );
            }
        }
    }
}

/// Energy `½ Σ k |x_i − x_j|²` (which the solution minimises) never increases over
/// Gauss–Seidel sweeps (exact minimisation in each node's coordinate) nor over CG iterations
/// (CG minimises the A-norm of the error over a growing Krylov space; the energy is that norm
/// squared plus a constant). The residual 2-norm of CG is *not* monotone and is not tested.
#[test]
fn energy_decreases_for_gauss_seidel_and_cg() {
    let case = annulus::<f64>(12, 36);
    let net = case.net::<f64>();
    let sys = case.system();
    let x0: Vec<[f64; 2]> = inner_rotation(&case, 10.0);
    let slack = 1e-12;
    for (name, m) in methods::<f64>() {
        if name == "jacobi" {
            continue;
        }
        let mut prev = spring_ref::linear_energy(&net, &to_ref::<f64, f64, 2>(&x0));
        let exact = spring_ref::solve_linear_dense(&net, &to_ref::<f64, f64, 2>(&x0)).unwrap();
        let e_min = spring_ref::linear_energy(&net, &exact);
        for k in 1..40 {
            let mut x = x0.clone();
            let opts = SolveOptions {
                residual_tol: 0.0,
                max_iterations: k,
                ..Default::default()
            };
            let rep = solve(&sys, &mut x, m, &opts).unwrap();
            assert_eq!(rep.iterations, k);
            let e = spring_ref::linear_energy(&net, &to_ref::<f64, f64, 2>(&x));
            assert!(
                e <= prev * (1.0 + slack),
                "{name}: energy rose at iteration {k}: {prev} -> {e}"
            );
            // Strictly, as long as the iterate is not yet at the minimum (to rounding).
            if prev - e_min > 1e-10 * e_min {
                assert!(e < prev, "{name}: energy stalled at iteration {k}");
            }
            assert!(
                e >= e_min * (1.0 - slack),
                "{name}: below the minimum energy"
            );
            prev = e;
        }
    }
}

/// Uniform translation. (a) The translated state is a bit-exact fixed point of every sweep
/// and every solver: the delta form sums `k (x_j − x_i)` = exact zeros. (b) From a zero initial
/// guess every method converges to the translation; the error bound 1e-9·|c| follows from the
/// residual tolerance 1e-13 (bitwise equality is not claimed: an iterative method approaches
/// the translation, it does not land on it).
#[test]
fn uniform_translation_is_reproduced() {
    let case = annulus::<f64>(9, 25);
    let sys = case.system();
    let c = [0.3125f64, -1.7, 1e-3];
    let x: Vec<[f64; 3]> = vec![c; case.n()];
    let mut out = vec![[9.0; 3]; case.n()];
    let s = sys.jacobi_sweep(0..case.n(), &x, &mut out).unwrap();
    assert_eq!(s.max_change, 0.0);
    assert_eq!(s.residual_sq, 0.0);
    assert_eq!(bits(&out), bits(&x));
    let mut y = x.clone();
    assert_eq!(
        sys.sor_sweep(0..case.n(), &mut y, 1.5).unwrap().max_change,
        0.0
    );
    assert_eq!(bits(&y), bits(&x));
    for (name, m) in methods::<f64>() {
        let mut y = x.clone();
        let rep = solve(&sys, &mut y, m, &SolveOptions::default()).unwrap();
        assert!(
            rep.converged && rep.iterations == 0 && rep.residual == 0.0,
            "{name}"
        );
        assert_eq!(bits(&y), bits(&x), "{name}");
        // (b) from zero.
        let mut z: Vec<[f64; 3]> = (0..case.n())
            .map(|i| if case.fixed[i] != 0 { c } else { [0.0; 3] })
            .collect();
        let opts = SolveOptions {
            residual_tol: 1e-13,
            max_iterations: 100_000,
            ..Default::default()
        };
        let rep = solve(&sys, &mut z, m, &opts).unwrap();
        assert!(rep.converged, "{name}");
        for v in &z {
            for k in 0..3 {
                assert!((v[k] - c[k]).abs() <= 1e-9 * 1.7, "{name}");
            }
        }
    }
}

#[test]
fn non_convergence_is_reported() {
    let case = annulus::<f64>(10, 30);
    let sys = case.system();
    let x0: Vec<[f64; 2]> = inner_rotation(&case, 10.0);
    for (name, m) in methods::<f64>() {
        let mut x = x0.clone();
        let opts = SolveOptions {
            max_iterations: 3,
            ..Default::default()
        };
        let rep = solve(&sys, &mut x, m, &opts).unwrap();
        assert!(!rep.converged, "{name}");
        assert_eq!(rep.iterations, 3);
        assert!(rep.residual > opts.residual_tol);
        assert_eq!(rep.residual, sys.relative_residual(&x).unwrap());
        assert!(rep.max_update > 0.0);
    }
    // The update rule alone (residual rule off) stops a stationary method early and says so.
    let mut x = x0.clone();
    let opts = SolveOptions {
        residual_tol: 0.0,
        update_tol: 1e-6,
        max_iterations: 100_000,
    };
    let rep = solve(&sys, &mut x, LinearMethod::GaussSeidel, &opts).unwrap();
    assert!(rep.converged && rep.max_update <= 1e-6 && rep.residual > 0.0);
}

#[test]
fn system_validation_errors() {
    let case = annulus::<f64>(4, 10);
    let g = case.graph();
    let mut scratch = vec![0u32; case.n()];
    let sys = |k: &[f64], f: &[u8], s: &mut [u32]| SpringSystem::new(g, k, f, s).map(|_| ());
    let mut k = case.k.clone();
    k[5] = f64::NAN;
    assert_eq!(
        sys(&k, &case.fixed, &mut scratch),
        Err(Error::NonFinite {
            arg: "stiffness",
            position: 5
        })
    );
    k[5] = 0.0;
    assert_eq!(
        sys(&k, &case.fixed, &mut scratch),
        Err(Error::NonPositive {
            arg: "stiffness",
            position: 5
        })
    );
    k[5] = case.k[5] * 2.0;
    assert!(matches!(
        sys(&k, &case.fixed, &mut scratch),
        Err(Error::NotSymmetric { .. })
    ));
    assert!(matches!(
        sys(&case.k[1..], &case.fixed, &mut scratch),
        Err(Error::LengthMismatch {
            arg: "stiffness",
            ..
        })
    ));
    assert!(matches!(
        sys(&case.k, &case.fixed[1..], &mut scratch),
        Err(Error::LengthMismatch { arg: "fixed", .. })
    ));
    assert!(matches!(
        sys(&case.k, &case.fixed, &mut scratch[1..]),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    // A free island: nodes 0..=2 of an extra triangle not connected to anything fixed.
    let mut p = case.points.clone();
    p.extend([[10.0, 10.0], [11.0, 10.0], [10.0, 11.0]]);
    let n = case.n() as u32;
    let mut edges = vec![];
    for (i, _, row) in g.rows() {
        for &j in row {
            edges.push([i as u32, j]);
        }
    }
    edges.extend([[n, n + 1], [n + 1, n + 2], [n + 2, n]]);
    let mut fixed = case.fixed.clone();
    fixed.extend([0, 0, 0]);
    let c2 = Case::<f64, 2>::new(&p, &edges, fixed.clone());
    let mut s2 = vec![0u32; c2.n()];
    assert_eq!(
        SpringSystem::new(c2.graph(), &c2.k, &c2.fixed, &mut s2).map(|_| ()),
        Err(Error::Unanchored { node: n as usize })
    );
    // Fixing one island node anchors it; any nonzero byte counts as fixed.
    fixed[n as usize + 1] = 0xA5;
    let c3 = Case::<f64, 2>::new(&p, &edges, fixed);
    assert!(SpringSystem::new(c3.graph(), &c3.k, &c3.fixed, &mut s2).is_ok());
}

#[test]
fn bad_values_give_typed_errors_and_leave_buffers_unchanged() {
    let case = annulus::<f64>(5, 12);
    let sys = case.system();
    let n = case.n();
    let mut x: Vec<[f64; 2]> = inner_rotation(&case, 10.0);
    x[17][1] = f64::NAN;
    let before = bits(&x);
    let mut out = vec![[4.0; 2]; n];
    assert_eq!(
        sys.jacobi_sweep(0..n, &x, &mut out),
        Err(Error::NonFinite {
            arg: "input",
            position: 17
        })
    );
    assert!(out.iter().all(|v| *v == [4.0; 2]));
    assert_eq!(
        sys.sor_sweep(0..n, &mut x, 1.0),
        Err(Error::NonFinite {
            arg: "values",
            position: 17
        })
    );
    for (name, m) in methods::<f64>() {
        let mut scratch = vec![[0.5; 2]; solve_linear_scratch_len(&m, n)];
        let e = sys.solve_linear(&mut x, m, &SolveOptions::default(), &mut scratch);
        assert_eq!(
            e,
            Err(Error::NonFinite {
                arg: "values",
                position: 17
            }),
            "{name}"
        );
        assert_eq!(bits(&x), before);
        assert!(scratch.iter().all(|v| *v == [0.5; 2]));
    }
    x[17][1] = f64::INFINITY;
    assert!(matches!(
        sys.relative_residual(&x),
        Err(Error::NonFinite { .. })
    ));
    x[17][1] = 0.0;
    let before = bits(&x);
    assert!(matches!(
        sys.jacobi_sweep(0..n + 1, &x, &mut out),
        Err(Error::IndexOutOfRange { arg: "nodes", .. })
    ));
    assert!(matches!(
        sys.jacobi_sweep(0..n, &x, &mut out[1..]),
        Err(Error::LengthMismatch { arg: "output", .. })
    ));
    assert!(matches!(
        sys.jacobi_sweep(0..n, &x[1..], &mut out),
        Err(Error::LengthMismatch { arg: "input", .. })
    ));
    assert!(out.iter().all(|v| *v == [4.0; 2]));
    for omega in [0.0, 2.0, -1.0, f64::NAN] {
        assert!(matches!(
            sys.sor_sweep(0..n, &mut x, omega),
            Err(Error::InvalidParameter { arg: "omega", .. })
        ));
        let m = LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega },
        };
        let mut scratch = vec![[0.0; 2]; 4 * n];
        assert!(matches!(
            sys.solve_linear(&mut x, m, &SolveOptions::default(), &mut scratch),
            Err(Error::InvalidParameter { arg: "omega", .. })
        ));
    }
    let m = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut small = vec![[0.0; 2]; 4 * n - 1];
    assert!(matches!(
        sys.solve_linear(&mut x, m, &SolveOptions::default(), &mut small),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    let bad = SolveOptions {
        residual_tol: f64::NAN,
        ..Default::default()
    };
    assert!(matches!(
        solve(&sys, &mut x, m, &bad),
        Err(Error::InvalidParameter {
            arg: "residual_tol",
            ..
        })
    ));
    let bad = SolveOptions {
        update_tol: -1.0,
        ..Default::default()
    };
    assert!(matches!(
        solve(&sys, &mut x, m, &bad),
        Err(Error::InvalidParameter {
            arg: "update_tol",
            ..
        })
    ));
    assert!(matches!(
        solve(&sys, &mut x[1..], m, &SolveOptions::default()),
        Err(Error::LengthMismatch { arg: "values", .. })
    ));
    assert_eq!(bits(&x), before);
}
