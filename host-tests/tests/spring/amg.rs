//! Multigrid-preconditioned CG for the linear springs: agreement with a dense direct solve,
//! robustness on a NACA mesh (iterations far below CG+Jacobi), an exact two-phase size query,
//! typed errors that leave buffers untouched, a symmetric positive definite preconditioner,
//! repeatable bits, f32 and f64.
#![allow(clippy::needless_range_loop)]

#[path = "../support/mod.rs"]
mod support;

use deform_host_tests::spring_ref;
use deform_kernel::spring::{
    amg_cg_scratch_len, amg_precondition_scratch_len, amg_sliding_cg_scratch_len,
    solve_linear_amg_scratch_len, solve_linear_scratch_len, AmgHierarchy, AmgOptions, AmgPools,
    AmgSizes, AmgSmoother, AmgSolve, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem,
};
use deform_kernel::{Error, Graph, Real};
use deform_meshgen::AirfoilGrid;
use support::spring::*;

/// Builds the hierarchy and solves with AMG-CG.
fn amg_solve<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    opts: &AmgOptions<T>,
    x: &mut [[T; V]],
    stop: &SolveOptions<T>,
) -> deform_kernel::Result<SolveReport<T>> {
    let mut b = AmgBuffers::new(sys, opts);
    let h = AmgHierarchy::setup(sys, opts, &mut b.work, &mut b.index, &mut b.values)?;
    let mut scratch = vec![[T::ZERO; V]; solve_linear_amg_scratch_len(&h)];
    sys.solve_linear_amg(&h, x, stop, &mut scratch)
}

/// A field with the given Dirichlet data on the fixed nodes (from a smooth function) and a
/// zero initial guess elsewhere.
fn field<T: Real, const V: usize, const D: usize>(case: &Case<T, D>) -> Vec<[T; V]> {
    case.points
        .iter()
        .zip(&case.fixed)
        .map(|(p, &f)| {
            let mut v = [T::ZERO; V];
            if f != 0 {
                for (c, x) in v.iter_mut().enumerate() {
                    let a = p[0].to_f64();
                    let b = p[1 % D].to_f64();
                    *x = T::from_f64((a * (c as f64 + 1.0)).sin() + 0.3 * b * b - 0.1 * c as f64);
                }
            }
            v
        })
        .collect()
}

fn max_diff_to_reference<T: Real, const V: usize, const D: usize>(
    case: &Case<T, D>,
    x0: &[[T; V]],
    x: &[[T; V]],
) -> f64 {
    let net = case.net::<f64>();
    let start: Vec<Vec<f64>> = x0
        .iter()
        .map(|v| v.iter().map(|c| c.to_f64()).collect())
        .collect();
    let exact = spring_ref::solve_linear_dense(&net, &start).unwrap();
    let mut worst: f64 = 0.0;
    for (e, v) in exact.iter().zip(x) {
        for (a, b) in e.iter().zip(v) {
            worst = worst.max((a - b.to_f64()).abs());
        }
    }
    worst
}

fn tight<T: Real>() -> SolveOptions<T> {
    SolveOptions {
        max_iterations: 500,
        residual_tol: T::from_f64(1e-12).max(T::from_f64(50.0) * T::EPSILON),
        update_tol: T::ZERO,
    }
}

#[test]
fn matches_dense_reference_2d_and_3d_f64() {
    let ann = annulus::<f64>(14, 40);
    let sys = ann.system();
    let x0 = field::<f64, 2, 2>(&ann);
    for smoother in [AmgSmoother::Jacobi, AmgSmoother::Chebyshev] {
        let opts = AmgOptions {
            smoother,
            max_coarse: 16,
            ..AmgOptions::default()
        };
        let mut x = x0.clone();
        let rep = amg_solve(&sys, &opts, &mut x, &tight()).unwrap();
        assert!(rep.converged, "{smoother:?}: {rep:?}");
        let err = max_diff_to_reference(&ann, &x0, &x);
        assert!(err < 1e-9, "{smoother:?}: max error {err:e}");
        // Fixed values come back bit for bit.
        for (i, (a, b)) in x0.iter().zip(&x).enumerate() {
            if ann.fixed[i] != 0 {
                assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
            }
        }
    }
    let cube = cube::<f64>(9);
    let sys = cube.system();
    let x0 = field::<f64, 3, 3>(&cube);
    let opts = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::default()
    };
    let mut x = x0.clone();
    let rep = amg_solve(&sys, &opts, &mut x, &tight()).unwrap();
    assert!(rep.converged, "{rep:?}");
    let err = max_diff_to_reference(&cube, &x0, &x);
    assert!(err < 1e-9, "cube: max error {err:e}");
}

#[test]
fn matches_dense_reference_f32_and_joint_components() {
    let ann = annulus::<f32>(12, 36);
    let sys = ann.system();
    // V = 6 (the quaternion method's D + 4) in f32.
    let x0 = field::<f32, 6, 2>(&ann);
    let mut x = x0.clone();
    let opts = AmgOptions {
        max_coarse: 10,
        ..AmgOptions::default()
    };
    let rep = amg_solve(&sys, &opts, &mut x, &tight()).unwrap();
    assert!(rep.converged, "{rep:?}");
    let err = max_diff_to_reference(&ann, &x0, &x);
    assert!(err < 5e-5, "f32: max error {err:e}");
}

#[test]
fn hierarchy_shape_and_all_level_counts() {
    let ann = annulus::<f64>(14, 40);
    let sys = ann.system();
    for max_levels in 1..=4 {
        let opts = AmgOptions {
            max_levels,
            max_coarse: 4,
            ..AmgOptions::default()
        };
        let mut b = AmgBuffers::new(&sys, &opts);
        let h = AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
        assert!(h.levels() <= max_levels);
        assert_eq!(h.levels(), b.sizes.levels);
        assert_eq!(h.level_size(0), ann.n());
        for l in 1..h.levels() {
            assert!(h.level_size(l) < h.level_size(l - 1));
        }
        assert_eq!(
            h.coarse_unknowns(),
            (1..h.levels()).map(|l| h.level_size(l)).sum::<usize>()
        );
        // Every depth still solves the problem (the preconditioner only changes the speed).
        let x0 = field::<f64, 2, 2>(&ann);
        let mut x = x0.clone();
        let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
        let rep = sys
            .solve_linear_amg(&h, &mut x, &tight(), &mut scratch)
            .unwrap();
        assert!(rep.converged, "levels {max_levels}: {rep:?}");
        assert!(max_diff_to_reference(&ann, &x0, &x) < 1e-9);
    }
}

#[test]
fn far_fewer_iterations_than_cg_jacobi_on_a_naca_mesh() {
    let m = naca(&AirfoilGrid::inviscid());
    let g = Graph::new(&m.offsets, &m.targets).unwrap();
    let mut s = vec![0u32; m.fixed.len()];
    let sys = SpringSystem::new(g, &m.k, &m.fixed, &mut s).unwrap();
    let stop = SolveOptions {
        max_iterations: 5000,
        residual_tol: 1e-8,
        update_tol: 0.0,
    };
    let mut x = m.x0.clone();
    let amg = amg_solve(&sys, &AmgOptions::default(), &mut x, &stop).unwrap();
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut y = m.x0.clone();
    let mut scratch = vec![[0.0; 2]; solve_linear_scratch_len(&cg, y.len())];
    let jac = sys.solve_linear(&mut y, cg, &stop, &mut scratch).unwrap();
    assert!(amg.converged && jac.converged);
    // Robustness, not speed: multigrid keeps the iteration count nearly mesh-independent.
    assert!(
        amg.iterations <= 40,
        "AMG-CG took {} iterations",
        amg.iterations
    );
    assert!(
        amg.iterations * 5 <= jac.iterations,
        "AMG-CG {} vs CG+Jacobi {}",
        amg.iterations,
        jac.iterations
    );
    // Both solve the same problem.
    let worst = x
        .iter()
        .zip(&y)
        .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| (p - q).abs()))
        .fold(0.0f64, f64::max);
    assert!(worst < 1e-6, "solutions differ by {worst:e}");
}

#[test]
fn size_query_is_exact_and_short_buffers_are_refused_untouched() {
    let ann = annulus::<f64>(10, 30);
    let sys = ann.system();
    for opts in [
        AmgOptions {
            max_coarse: 8,
            ..AmgOptions::default()
        },
        AmgOptions {
            strength_theta: 0.2,
            max_coarse: 8,
            ..AmgOptions::default()
        },
        AmgOptions {
            max_levels: 1,
            ..AmgOptions::default()
        },
    ] {
        let mut b = AmgBuffers::new(&sys, &opts);
        let AmgSizes { index, values, .. } = b.sizes;
        // One less index entry: typed error, both buffers untouched.
        let mut short_index = vec![7u32; index.saturating_sub(1)];
        let mut vals = vec![3.5f64; values];
        if index > 0 {
            let e = AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut short_index, &mut vals)
                .unwrap_err();
            assert_eq!(
                e,
                Error::BufferTooSmall {
                    arg: "index",
                    needed: index,
                    actual: index - 1
                }
            );
            assert!(short_index.iter().all(|&v| v == 7));
            assert!(vals.iter().all(|&v| v == 3.5));
        }
        // One less value.
        let mut idx = vec![7u32; index];
        let mut short_vals = vec![3.5f64; values - 1];
        let e =
            AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut idx, &mut short_vals).unwrap_err();
        assert_eq!(
            e,
            Error::BufferTooSmall {
                arg: "values",
                needed: values,
                actual: values - 1
            }
        );
        assert!(idx.iter().all(|&v| v == 7));
        assert!(short_vals.iter().all(|&v| v == 3.5));
        // Exactly the sizes work; larger buffers give the same bits and leave the tail alone.
        let exact = {
            let h =
                AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
            solve_bits(&sys, &h, &ann)
        };
        let mut big_index = vec![9u32; index + 5];
        let mut big_vals = vec![-1.0f64; values + 5];
        let big = {
            let h = AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut big_index, &mut big_vals)
                .unwrap();
            solve_bits(&sys, &h, &ann)
        };
        assert_eq!(exact, big);
        assert!(big_index[index..].iter().all(|&v| v == 9));
        assert!(big_vals[values..].iter().all(|&v| v == -1.0));
        // The work buffer: one less is refused.
        let need = AmgHierarchy::setup_work_len(&sys);
        let mut w = vec![0u32; need - 1];
        assert_eq!(
            AmgHierarchy::setup_len(&sys, &opts, &mut w).unwrap_err(),
            Error::BufferTooSmall {
                arg: "work",
                needed: need,
                actual: need - 1
            }
        );
    }
}

fn solve_bits<const D: usize>(
    sys: &SpringSystem<'_, f64>,
    h: &AmgHierarchy<'_, f64>,
    case: &Case<f64, D>,
) -> Vec<[u64; 2]> {
    let mut x = field::<f64, 2, D>(case);
    let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(h)];
    sys.solve_linear_amg(h, &mut x, &tight(), &mut scratch)
        .unwrap();
    x.iter().map(|v| v.map(f64::to_bits)).collect()
}

#[test]
fn bits_repeat_across_runs_and_reused_buffers() {
    let ann = annulus::<f64>(12, 32);
    let sys = ann.system();
    let opts = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::default()
    };
    let mut b = AmgBuffers::new(&sys, &opts);
    let first = {
        let h = AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
        let a = solve_bits(&sys, &h, &ann);
        // The same hierarchy, solved again.
        assert_eq!(a, solve_bits(&sys, &h, &ann));
        a
    };
    // Dirty buffers (a previous hierarchy, then garbage) give the same hierarchy.
    b.index.fill(12345);
    b.values.fill(f64::NAN);
    b.work.fill(u32::MAX);
    let h = AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
    assert_eq!(first, solve_bits(&sys, &h, &ann));
}

#[test]
fn preconditioner_is_symmetric_positive_definite() {
    let ann = annulus::<f64>(12, 32);
    let sys = ann.system();
    for smoother in [AmgSmoother::Jacobi, AmgSmoother::Chebyshev] {
        for sweeps in [1, 3] {
            let opts = AmgOptions {
                smoother,
                sweeps,
                max_coarse: 8,
                ..AmgOptions::default()
            };
            let mut b = AmgBuffers::new(&sys, &opts);
            let h =
                AmgHierarchy::setup(&sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
            assert!(h.levels() >= 2);
            let n = ann.n();
            let vec_of = |seed: f64| -> Vec<[f64; 1]> {
                (0..n)
                    .map(|i| [((i as f64 * 0.37 + seed).sin() * 3.0).round() + seed])
                    .collect()
            };
            let mut scratch = vec![[0.0; 1]; amg_precondition_scratch_len(&h)];
            let apply = |r: &[[f64; 1]], scratch: &mut Vec<[f64; 1]>| {
                let mut z = vec![[0.0; 1]; n];
                sys.amg_precondition(&h, r, &mut z, scratch).unwrap();
                z
            };
            let free_dot = |a: &[[f64; 1]], b: &[[f64; 1]]| -> f64 {
                (0..n)
                    .filter(|&i| ann.fixed[i] == 0)
                    .map(|i| a[i][0] * b[i][0])
                    .sum()
            };
            for (s1, s2) in [(0.1, 0.7), (1.3, -0.4), (2.0, 5.0)] {
                let a = vec_of(s1);
                let bv = vec_of(s2);
                let ma = apply(&a, &mut scratch);
                let mb = apply(&bv, &mut scratch);
                let lhs = free_dot(&ma, &bv);
                let rhs = free_dot(&a, &mb);
                let scale = free_dot(&ma, &a).abs() + free_dot(&mb, &bv).abs();
                assert!(
                    (lhs - rhs).abs() <= 1e-12 * scale,
                    "{smoother:?}/{sweeps}: <Ma,b> = {lhs}, <a,Mb> = {rhs}"
                );
                assert!(free_dot(&ma, &a) > 0.0);
                // Zero at fixed nodes, whatever r holds there.
                for i in 0..n {
                    if ann.fixed[i] != 0 {
                        assert_eq!(ma[i][0], 0.0);
                    }
                }
            }
        }
    }
}

#[test]
fn bad_inputs_are_typed() {
    let ann = annulus::<f64>(8, 24);
    let sys = ann.system();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let bad = |o: AmgOptions<f64>, arg: &str, work: &mut Vec<u32>| {
        let e = AmgHierarchy::setup_len(&sys, &o, work).unwrap_err();
        assert!(
            matches!(e, Error::InvalidParameter { arg: a, .. } if a == arg),
            "{arg}: {e:?}"
        );
    };
    let d = AmgOptions::<f64>::default();
    for theta in [-0.1, 1.0, f64::NAN, f64::INFINITY] {
        bad(
            AmgOptions {
                strength_theta: theta,
                ..d
            },
            "strength_theta",
            &mut work,
        );
    }
    for max_levels in [0, 17] {
        bad(AmgOptions { max_levels, ..d }, "max_levels", &mut work);
    }
    for max_coarse in [0, 4096] {
        bad(AmgOptions { max_coarse, ..d }, "max_coarse", &mut work);
    }
    for sweeps in [0, 17] {
        bad(AmgOptions { sweeps, ..d }, "sweeps", &mut work);
    }

    let mut b = AmgBuffers::new(&sys, &d);
    let h = AmgHierarchy::setup(&sys, &d, &mut b.work, &mut b.index, &mut b.values).unwrap();
    let x0 = field::<f64, 2, 2>(&ann);
    let need = solve_linear_amg_scratch_len(&h);
    // Short scratch.
    let mut x = x0.clone();
    let mut scratch = vec![[0.0; 2]; need - 1];
    assert!(matches!(
        sys.solve_linear_amg(&h, &mut x, &tight(), &mut scratch),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    assert_eq!(x, x0);
    // Non-finite values.
    let mut scratch = vec![[0.0; 2]; need];
    let mut x = x0.clone();
    x[40][1] = f64::NAN;
    let before: Vec<[u64; 2]> = x.iter().map(|v| v.map(f64::to_bits)).collect();
    assert!(matches!(
        sys.solve_linear_amg(&h, &mut x, &tight(), &mut scratch),
        Err(Error::NonFinite { arg: "values", .. })
    ));
    assert_eq!(
        before,
        x.iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>()
    );
    // Bad stopping options.
    let mut x = x0.clone();
    let o = SolveOptions {
        residual_tol: -1.0,
        ..tight()
    };
    assert!(matches!(
        sys.solve_linear_amg(&h, &mut x, &o, &mut scratch),
        Err(Error::InvalidParameter { .. })
    ));
    // A hierarchy of another system.
    let other = annulus::<f64>(9, 24);
    let osys = other.system();
    let mut y = field::<f64, 2, 2>(&other);
    let mut big = vec![[0.0; 2]; 10 * other.n()];
    assert!(matches!(
        osys.solve_linear_amg(&h, &mut y, &tight(), &mut big),
        Err(Error::LengthMismatch {
            arg: "hierarchy",
            ..
        })
    ));
    let mut z = vec![[0.0; 2]; other.n()];
    assert!(matches!(
        osys.amg_precondition(&h, &y, &mut z, &mut big),
        Err(Error::LengthMismatch {
            arg: "hierarchy",
            ..
        })
    ));
}

#[test]
fn hierarchy_of_other_stiffness_still_gives_the_exact_answer() {
    // A hierarchy built for stale stiffness (the previous time step) only preconditions: the
    // answer is that of the current system.
    let ann = annulus::<f64>(12, 32);
    let sys = ann.system();
    // Symmetric perturbation: scale by a function of the unordered edge.
    let g = ann.graph();
    let mut stale = ann.k.clone();
    for i in 0..ann.n() {
        for e in g.edge_range(i) {
            let j = ann.targets[e] as usize;
            let a = i.min(j) as f64;
            let b = i.max(j) as f64;
            stale[e] = ann.k[e] * (1.0 + 0.5 * ((a * 3.1 + b * 1.7).sin() + 1.0));
        }
    }
    let mut s = vec![0u32; ann.n()];
    let stale_sys = SpringSystem::new(g, &stale, &ann.fixed, &mut s).unwrap();
    let opts = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::default()
    };
    let mut b = AmgBuffers::new(&stale_sys, &opts);
    let h =
        AmgHierarchy::setup(&stale_sys, &opts, &mut b.work, &mut b.index, &mut b.values).unwrap();
    let x0 = field::<f64, 2, 2>(&ann);
    let mut x = x0.clone();
    let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
    let rep = sys
        .solve_linear_amg(&h, &mut x, &tight(), &mut scratch)
        .unwrap();
    assert!(rep.converged);
    assert!(max_diff_to_reference(&ann, &x0, &x) < 1e-9);
}

#[test]
fn degenerate_systems() {
    // Every node fixed: nothing to solve, values unchanged.
    let ann = annulus::<f64>(2, 12);
    let sys = ann.system();
    let mut x = field::<f64, 2, 2>(&ann);
    let x0 = x.clone();
    let rep = amg_solve(&sys, &AmgOptions::default(), &mut x, &tight()).unwrap();
    assert!(rep.converged);
    assert_eq!(rep.iterations, 0);
    assert_eq!(x, x0);
    // One free ring between two fixed rings: every free node has free neighbours.
    let ann = annulus::<f64>(3, 12);
    let sys = ann.system();
    let x0 = field::<f64, 2, 2>(&ann);
    let mut x = x0.clone();
    let rep = amg_solve(&sys, &AmgOptions::default(), &mut x, &tight()).unwrap();
    assert!(rep.converged);
    assert!(max_diff_to_reference(&ann, &x0, &x) < 1e-9);
    // A strength threshold that leaves free nodes without strong neighbours.
    let ann = annulus::<f64>(10, 24);
    let sys = ann.system();
    let x0 = field::<f64, 2, 2>(&ann);
    let mut x = x0.clone();
    let o = AmgOptions {
        strength_theta: 0.9,
        ..AmgOptions::default()
    };
    let rep = amg_solve(&sys, &o, &mut x, &tight()).unwrap();
    assert!(rep.converged);
    assert!(max_diff_to_reference(&ann, &x0, &x) < 1e-9);
}

#[test]
fn power_of_two_scaling_is_exact() {
    // Values times 2^k solve to exactly 2^k times the solution (the CG iterate is rescaled by
    // powers of two, as in the plain CG), also far outside the range where Σ x² is finite.
    let ann = annulus::<f64>(10, 28);
    let sys = ann.system();
    let opts = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::default()
    };
    let x0 = field::<f64, 2, 2>(&ann);
    let mut base = x0.clone();
    let rep = amg_solve(&sys, &opts, &mut base, &tight()).unwrap();
    for k in [512, -960, 30] {
        let f = 2f64.powi(k);
        let mut x: Vec<[f64; 2]> = x0.iter().map(|v| v.map(|c| c * f)).collect();
        let r = amg_solve(&sys, &opts, &mut x, &tight()).unwrap();
        assert_eq!(r.iterations, rep.iterations, "2^{k}");
        for (a, b) in base.iter().zip(&x) {
            assert_eq!(a.map(|c| (c * f).to_bits()), b.map(f64::to_bits), "2^{k}");
        }
    }
    // A constant field (every fixed value 1e154) is reproduced exactly.
    let mut c = vec![[1e154f64; 2]; ann.n()];
    for (v, &f) in c.iter_mut().zip(&ann.fixed) {
        if f == 0 {
            *v = [0.0; 2];
        }
    }
    let r = amg_solve(&sys, &opts, &mut c, &tight()).unwrap();
    assert!(r.converged);
    for v in &c {
        for &x in v {
            assert!((x - 1e154).abs() <= 1e154 * 1e-10, "{x:e}");
        }
    }
}

/// The two-buffer layout of `AmgPools`: its lengths are exact (one entry less in either buffer
/// is `BufferTooSmall`, both buffers untouched), and a solve with the hierarchy and scratch it
/// lays out gives the bits of separately allocated buffers, for both kinds of CG.
#[test]
fn pools_layout_is_exact_and_gives_the_same_bits() {
    let ann = annulus::<f64>(12, 32);
    let sys = ann.system();
    let opts = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::default()
    };
    let expected = {
        let mut b = AmgBuffers::new(&sys, &opts);
        let h = b.build(&sys, &opts);
        solve_bits(&sys, &h, &ann)
    };
    for solve in [AmgSolve::Cg, AmgSolve::SlidingCg] {
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
        let layout = AmgPools::layout(&sys, &opts, solve, &mut work).unwrap();
        let [r, i] = layout.lens(2).unwrap();
        let items = match solve {
            AmgSolve::Cg => amg_cg_scratch_len(ann.n(), 0),
            AmgSolve::SlidingCg => amg_sliding_cg_scratch_len(ann.n(), 0),
        };
        assert!(r > items.unwrap() * 2 && i > work.len());
        for (dr, di) in [(1, 0), (0, 1)] {
            let (mut reals, mut indices) = (vec![7.0; r - dr], vec![7u32; i - di]);
            let e = layout.setup::<f64, 2>(&sys, &opts, &mut reals, &mut indices);
            assert!(matches!(e, Err(Error::BufferTooSmall { .. })));
            assert!(reals.iter().all(|&x| x == 7.0) && indices.iter().all(|&x| x == 7));
        }
        let (mut reals, mut indices) = (vec![0.0; r], vec![0u32; i]);
        let (h, scratch) = layout
            .setup::<f64, 2>(&sys, &opts, &mut reals, &mut indices)
            .unwrap();
        assert!(scratch.len() >= solve_linear_amg_scratch_len(&h));
        let mut x = field::<f64, 2, 2>(&ann);
        sys.solve_linear_amg(
            &h,
            &mut x,
            &tight(),
            &mut scratch[..solve_linear_amg_scratch_len(&h)],
        )
        .unwrap();
        let bits: Vec<[u64; 2]> = x.iter().map(|v| v.map(f64::to_bits)).collect();
        assert_eq!(bits, expected);
    }
    let mut short = vec![0u32; AmgHierarchy::setup_work_len(&sys) - 1];
    let e = AmgPools::layout(&sys, &opts, AmgSolve::Cg, &mut short);
    assert!(matches!(e, Err(Error::BufferTooSmall { .. })));
}
