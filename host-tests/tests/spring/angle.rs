//! Angle-inclusion springs (Yang & Özgen eq. 2–4): direct (node-wise Cramer) and indirect (CG)
//! methods against a dense reference, monotone energy, singular node and mechanism detection,
//! typed errors.
#![allow(clippy::needless_range_loop)]

#[path = "../support/mod.rs"]
mod support;

use deform_host_tests::spring_ref;
use deform_kernel::spring::{
    AngleMethod, AngleSystem, SolveOptions, SolveReport, SpringSystem, DEFAULT_ANGLE_EPSILON,
    MAX_AMPLIFICATION,
};
use deform_kernel::{Error, Real};
use support::spring::*;

const METHODS: [AngleMethod; 3] = [
    AngleMethod::DirectGaussSeidel,
    AngleMethod::DirectJacobi,
    AngleMethod::Cg,
];

fn solve<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    x: &mut [[T; D]],
    m: AngleMethod,
    opts: &SolveOptions<T>,
) -> deform_kernel::Result<SolveReport<T>> {
    let mut scratch = vec![[T::ZERO; D]; sys.angle_scratch_len(m)];
    sys.solve_angle(x, m, opts, &mut scratch)
}

/// The Jacobi-order direct sweep equals a naive sweep that solves each node block by dense
/// elimination instead of Cramer's rule. Different algorithms, so not bitwise: within
/// 1e-12 (node blocks here have condition numbers below 1e3; values are O(1)).
#[test]
fn angle_jacobi_sweep_matches_reference() {
    fn check<const D: usize>(case: &Case<f64, D>, eps: f64) {
        let sys = case.angle(eps);
        let net = case.net::<f64>();
        let x: Vec<[f64; D]> = field(case, &mut Lcg(11), None);
        let want = spring_ref::angle_jacobi_sweep(&net, &case.points, eps, &x).unwrap();
        let n = case.n();
        for range in [0..n, 7..n / 2] {
            let mut out = vec![[-5.0; D]; n];
            sys.angle_jacobi_sweep(range.clone(), &x, &mut out).unwrap();
            for i in 0..n {
                for c in 0..D {
                    if range.contains(&i) {
                        assert!((out[i][c] - want[i][c]).abs() <= 1e-12, "node {i}");
                    } else {
                        assert_eq!(out[i][c], -5.0);
                    }
                }
            }
        }
    }
    check(&annulus::<f64>(7, 20), 0.0);
    check(&annulus::<f64>(7, 20), DEFAULT_ANGLE_EPSILON);
    check(&cube::<f64>(5), 0.0);
    check(&cube::<f64>(5), 0.3);
}

/// Over-relaxed direct method (issue 14 item 8): `ω = 1` is Gauss–Seidel bit for bit (sweep
/// and solve); `ω ∈ {1.2, 1.5, 1.8}` converges to the dense solution, and a suitable `ω`
/// (1.8 on the graded annulus, 1.2 on the small cube) in fewer sweeps than Gauss–Seidel;
/// `ω` outside `(0, 2)` is a typed error that leaves the values alone.
#[test]
fn angle_sor_matches_gauss_seidel_at_one_and_converges_faster() {
    fn check<const D: usize>(case: &Case<f64, D>, eps: f64, x0: Vec<[f64; D]>, faster: f64) {
        let sys = case.angle(eps);
        let n = case.n();
        let mut a = x0.clone();
        let mut b = x0.clone();
        let sa = sys.angle_gauss_seidel_sweep(0..n, &mut a).unwrap();
        let sb = sys.angle_sor_sweep(0..n, &mut b, 1.0).unwrap();
        assert_eq!(sa, sb);
        assert_eq!(bits(&a), bits(&b));
        let exact =
            spring_ref::solve_angle_dense(&case.net::<f64>(), &case.points, eps, &x0).unwrap();
        let opts = SolveOptions {
            residual_tol: 1e-12,
            max_iterations: 200_000,
            ..Default::default()
        };
        let mut scratch = vec![[0.0; D]; sys.angle_scratch_len(AngleMethod::DirectGaussSeidel)];
        let mut gs = x0.clone();
        let rgs = solve(&sys, &mut gs, AngleMethod::DirectGaussSeidel, &opts).unwrap();
        let mut one = x0.clone();
        let r1 = sys
            .solve_angle_sor(&mut one, 1.0, &opts, &mut scratch)
            .unwrap();
        assert_eq!(r1, rgs);
        assert_eq!(bits(&one), bits(&gs));
        for omega in [1.2, 1.5, 1.8] {
            let mut x = x0.clone();
            let r = sys
                .solve_angle_sor(&mut x, omega, &opts, &mut scratch)
                .unwrap();
            assert!(r.converged, "omega {omega}: {r:?}");
            assert!(
                omega != faster || r.iterations < rgs.iterations,
                "omega {omega}: {} sweeps vs Gauss–Seidel {}",
                r.iterations,
                rgs.iterations
            );
            for i in 0..n {
                for c in 0..D {
                    assert!(
                        (x[i][c] - exact[i][c]).abs() <= 1e-8,
                        "omega {omega} node {i}"
                    );
                }
            }
        }
        for omega in [0.0, 2.0, -1.0, f64::NAN] {
            let mut x = x0.clone();
            assert!(matches!(
                sys.solve_angle_sor(&mut x, omega, &opts, &mut scratch),
                Err(Error::InvalidParameter { arg: "omega", .. })
            ));
            assert!(matches!(
                sys.angle_sor_sweep(0..n, &mut x, omega),
                Err(Error::InvalidParameter { arg: "omega", .. })
            ));
            assert_eq!(bits(&x), bits(&x0));
        }
    }
    let a = annulus::<f64>(8, 24);
    check(&a, DEFAULT_ANGLE_EPSILON, inner_rotation(&a, 25.0), 1.8);
    let c = cube::<f64>(5);
    check(
        &c,
        DEFAULT_ANGLE_EPSILON,
        field(&c, &mut Lcg(2), Some(0.0)),
        1.2,
    );
}

/// Converged solutions of every method agree with the dense solve of eq. 4 within 1e-8
/// (relative residual 1e-13; the block operators here have condition numbers well below 1e5).
#[test]
fn angle_converged_solutions_match_dense_solve() {
    fn check<const D: usize>(case: &Case<f64, D>, eps: f64, x0: Vec<[f64; D]>) {
        let sys = case.angle(eps);
        let exact =
            spring_ref::solve_angle_dense(&case.net::<f64>(), &case.points, eps, &x0).unwrap();
        let opts = SolveOptions {
            residual_tol: 1e-13,
            max_iterations: 200_000,
            ..Default::default()
        };
        for m in METHODS {
            let mut x = x0.clone();
            let rep = solve(&sys, &mut x, m, &opts).unwrap();
            assert!(rep.converged, "{m:?} eps {eps}: {rep:?}");
            let r = spring_ref::angle_residual(&case.net::<f64>(), &case.points, eps, &x);
            assert!(r.is_finite());
            for i in 0..case.n() {
                for c in 0..D {
                    assert!(
                        (x[i][c] - exact[i][c]).abs() <= 1e-8,
                        "{m:?} eps {eps} node {i}"
                    );
                }
            }
        }
    }
    let a = annulus::<f64>(8, 24);
    for eps in [0.0, DEFAULT_ANGLE_EPSILON, 1.0] {
        check(&a, eps, inner_rotation(&a, 25.0));
        check(&a, eps, field(&a, &mut Lcg(1), Some(0.0)));
    }
    let c = cube::<f64>(5);
    for eps in [0.0, DEFAULT_ANGLE_EPSILON] {
        check(&c, eps, field(&c, &mut Lcg(2), Some(0.0)));
    }
}

#[test]
fn angle_f32_converges() {
    let a = annulus::<f32>(8, 24);
    let sys = a.angle(DEFAULT_ANGLE_EPSILON);
    let x0 = inner_rotation(&a, 10.0);
    let exact = spring_ref::solve_angle_dense(
        &a.net::<f64>(),
        &a.points_f64(),
        DEFAULT_ANGLE_EPSILON as f32 as f64,
        &x0.iter().map(|v| v.map(|c| c as f64)).collect::<Vec<_>>(),
    )
    .unwrap();
    for m in [AngleMethod::DirectGaussSeidel, AngleMethod::Cg] {
        let mut x = x0.clone();
        let rep = solve(&sys, &mut x, m, &SolveOptions::default()).unwrap();
        assert!(rep.converged, "{m:?}");
        for i in 0..a.n() {
            for c in 0..2 {
                assert!((x[i][c] as f64 - exact[i][c]).abs() <= 1e-3, "{m:?}");
            }
        }
    }
}

/// The energy `½ Σ (x_i − x_j)ᵀ B (x_i − x_j)` never increases over direct Gauss–Seidel sweeps
/// (each node solve minimises it exactly in that node's coordinates) nor over CG iterations
/// (A-norm error minimisation), and strictly decreases until the minimum is reached.
#[test]
fn angle_energy_decreases_for_gauss_seidel_and_cg() {
    let a = annulus::<f64>(8, 24);
    let net = a.net::<f64>();
    for eps in [0.0, DEFAULT_ANGLE_EPSILON] {
        let sys = a.angle(eps);
        let x0 = inner_rotation(&a, 20.0);
        let exact = spring_ref::solve_angle_dense(&net, &a.points, eps, &x0).unwrap();
        let e_min = spring_ref::angle_energy(&net, &a.points, eps, &exact);
        for m in [AngleMethod::DirectGaussSeidel, AngleMethod::Cg] {
            let mut prev = spring_ref::angle_energy(&net, &a.points, eps, &x0);
            for k in 1..30 {
                let mut x = x0.clone();
                let opts = SolveOptions {
                    residual_tol: 0.0,
                    max_iterations: k,
                    ..Default::default()
                };
                let rep = solve(&sys, &mut x, m, &opts).unwrap();
                assert_eq!(rep.iterations, k);
                let e = spring_ref::angle_energy(&net, &a.points, eps, &x);
                assert!(e <= prev * (1.0 + 1e-12), "{m:?}: energy rose at {k}");
                if prev - e_min > 1e-10 * e_min {
                    assert!(e < prev, "{m:?}: energy stalled at {k}");
                }
                prev = e;
            }
        }
    }
}

/// A uniform translation is a bit-exact fixed point of the angle sweeps and solves.
#[test]
fn angle_uniform_translation_is_exact() {
    let a = annulus::<f64>(6, 16);
    let c = [0.7, -0.03125];
    for eps in [0.0, DEFAULT_ANGLE_EPSILON] {
        let sys = a.angle(eps);
        let x = vec![c; a.n()];
        let mut out = vec![[0.0; 2]; a.n()];
        let s = sys.angle_jacobi_sweep(0..a.n(), &x, &mut out).unwrap();
        assert_eq!((s.max_change, s.residual_sq), (0.0, 0.0));
        assert_eq!(bits(&out), bits(&x));
        let mut y = x.clone();
        assert_eq!(
            sys.angle_gauss_seidel_sweep(0..a.n(), &mut y)
                .unwrap()
                .max_change,
            0.0
        );
        assert_eq!(bits(&y), bits(&x));
        for m in METHODS {
            let mut y = x.clone();
            let rep = solve(&sys, &mut y, m, &SolveOptions::default()).unwrap();
            assert!(rep.converged && rep.iterations == 0, "{m:?}");
            assert_eq!(bits(&y), bits(&x));
        }
    }
}

/// A free node whose edges are colinear (2D) or coplanar (3D) has a singular block: typed
/// error at construction with `ε = 0`, solvable with the regularisation.
#[test]
fn colinear_and_coplanar_nodes_are_singular() {
    // 2D: 0 — 1 — 2 on a line, 1 free.
    let p = [[0.0, 0.0], [1.0, 0.0], [2.5, 0.0]];
    let c = Case::<f64, 2>::new(&p, &[[0, 1], [1, 2]], vec![1, 0, 1]);
    let err = AngleSystem::new(c.system(), &c.points, 0.0).unwrap_err();
    assert_eq!(err, Error::SingularNode { node: 1 });
    let sys = c.angle(DEFAULT_ANGLE_EPSILON);
    let mut x = vec![[0.0, 1.0], [0.0, 0.0], [0.0, 1.0]];
    let rep = solve(
        &sys,
        &mut x,
        AngleMethod::DirectGaussSeidel,
        &SolveOptions::default(),
    )
    .unwrap();
    assert!(rep.converged);
    assert!(
        (x[1][1] - 1.0).abs() < 1e-9,
        "ε spring carries the transverse motion"
    );
    // Nearly colinear (1e-10 rad) is also rejected: the block's normalised determinant is
    // ~1e-20, far below √ε.
    let p = [[0.0, 0.0], [1.0, 1e-10], [2.5, 0.0]];
    let c = Case::<f64, 2>::new(&p, &[[0, 1], [1, 2]], vec![1, 0, 1]);
    assert_eq!(
        AngleSystem::new(c.system(), &c.points, 0.0).unwrap_err(),
        Error::SingularNode { node: 1 }
    );
    // 3D: the centre of a planar star.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.2, 0.0],
        [0.3, -1.0, 0.0],
    ];
    let c = Case::<f64, 3>::new(&p, &[[0, 1], [0, 2], [0, 3], [0, 4]], vec![0, 1, 1, 1, 1]);
    assert_eq!(
        AngleSystem::new(c.system(), &c.points, 0.0).unwrap_err(),
        Error::SingularNode { node: 0 }
    );
    assert!(AngleSystem::new(c.system(), &c.points, 0.01).is_ok());
}

/// Quad annulus edges (rings + spokes, optionally one diagonal per quad).
fn quad_annulus(nr: usize, nt: usize, diagonals: bool) -> Case<f64, 2> {
    let (p, _, f) = spring_ref::annulus(nr, nt, 1.0, 4.0, 1.2);
    let id = |j: usize, i: usize| (j * nt + i % nt) as u32;
    let mut e = vec![];
    for j in 0..nr {
        for i in 0..nt {
            e.push([id(j, i), id(j, i + 1)]);
            if j + 1 < nr {
                e.push([id(j, i), id(j + 1, i)]);
                if diagonals {
                    e.push([id(j, i), id(j + 1, i + 1)]);
                }
            }
        }
    }
    Case::new(&p, &e, f)
}

/// Trusses of quads are mechanisms. (1) A strip of two quads fixed along its bottom: the top
/// row can shear sideways with no edge stretching. (2) A polar quad grid with both rings
/// fixed: every interior ring can rotate rigidly (ring edges move rigidly; spokes move
/// perpendicular to themselves). No node block is singular, and CG on the user's data would
/// converge quietly (the data is orthogonal to the mechanism), so the rigidity probe must
/// catch both: `SingularSystem`, values untouched. The regularisation or face diagonals cure
/// them.
#[test]
fn quad_truss_mechanisms_are_detected() {
    let p = [
        [0.0, 0.0],
        [1.0, 0.0],
        [2.0, 0.0],
        [0.0, 1.0],
        [1.0, 1.0],
        [2.0, 1.0],
    ];
    let quads = [[0, 1], [1, 2], [3, 4], [4, 5], [0, 3], [1, 4], [2, 5]];
    let strip = Case::<f64, 2>::new(&p, &quads, vec![1, 1, 1, 0, 0, 0]);
    let ring = quad_annulus(5, 16, false);
    for case in [&strip, &ring] {
        let sys = AngleSystem::new(case.system(), &case.points, 0.0).expect("node blocks are fine");
        let x0: Vec<[f64; 2]> = field(case, &mut Lcg(4), Some(0.0));
        for m in METHODS {
            let mut x = x0.clone();
            let err = solve(&sys, &mut x, m, &SolveOptions::default()).unwrap_err();
            assert!(
                matches!(err, Error::SingularSystem { .. }),
                "{m:?}: {err:?}"
            );
            assert_eq!(bits(&x), bits(&x0));
        }
        let reg = case.angle(DEFAULT_ANGLE_EPSILON);
        let mut x = x0.clone();
        assert!(
            solve(&reg, &mut x, AngleMethod::Cg, &SolveOptions::default())
                .unwrap()
                .converged
        );
    }
    // Diagonals make both rigid with ε = 0.
    let mut braced = quads.to_vec();
    braced.extend([[0, 4], [1, 5]]);
    let strip = Case::<f64, 2>::new(&p, &braced, vec![1, 1, 1, 0, 0, 0]);
    let ring = quad_annulus(5, 16, true);
    for case in [&strip, &ring] {
        let sys = case.angle(0.0);
        let x0: Vec<[f64; 2]> = field(case, &mut Lcg(4), Some(0.0));
        for m in [AngleMethod::DirectGaussSeidel, AngleMethod::Cg] {
            let mut x = x0.clone();
            let rep = solve(&sys, &mut x, m, &SolveOptions::default()).unwrap();
            assert!(rep.converged, "{m:?}");
        }
    }
}

#[test]
fn angle_errors_are_typed_and_leave_buffers_unchanged() {
    let a = annulus::<f64>(5, 12);
    let base = a.system();
    let mut p = a.points.clone();
    p[3][0] = f64::NAN;
    assert_eq!(
        AngleSystem::new(base, &p, 0.0).unwrap_err(),
        Error::NonFinite {
            arg: "points",
            position: 3
        }
    );
    assert!(matches!(
        AngleSystem::new(base, &a.points[1..], 0.0),
        Err(Error::LengthMismatch { arg: "points", .. })
    ));
    for eps in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            AngleSystem::new(base, &a.points, eps),
            Err(Error::InvalidParameter { arg: "epsilon", .. })
        ));
    }
    // Zero-length edge: move a node onto its neighbour (stiffness is kept from the valid mesh).
    let mut p = a.points.clone();
    let j = base.graph().neighbors(20)[0] as usize;
    p[20] = p[j];
    assert!(matches!(
        AngleSystem::new(base, &p, 0.0),
        Err(Error::ZeroLengthEdge { .. })
    ));
    // 1D points are refused at compile time (`D` is 2 or 3; see `cell_measures`'
    // compile_fail doctest).

    let sys = a.angle(DEFAULT_ANGLE_EPSILON);
    let n = a.n();
    let mut x = inner_rotation(&a, 10.0);
    x[30][0] = f64::INFINITY;
    let before = bits(&x);
    let mut out = vec![[1.0; 2]; n];
    assert_eq!(
        sys.angle_jacobi_sweep(0..n, &x, &mut out),
        Err(Error::NonFinite {
            arg: "input",
            position: 30
        })
    );
    assert!(out.iter().all(|v| *v == [1.0; 2]));
    assert_eq!(
        sys.angle_gauss_seidel_sweep(0..n, &mut x),
        Err(Error::NonFinite {
            arg: "values",
            position: 30
        })
    );
    for m in METHODS {
        assert_eq!(
            solve(&sys, &mut x, m, &SolveOptions::default()),
            Err(Error::NonFinite {
                arg: "values",
                position: 30
            })
        );
    }
    assert_eq!(bits(&x), before);
    x[30][0] = 0.0;
    let before = bits(&x);
    assert!(matches!(
        sys.angle_jacobi_sweep(2..n + 3, &x, &mut out),
        Err(Error::IndexOutOfRange { arg: "nodes", .. })
    ));
    assert!(matches!(
        sys.angle_gauss_seidel_sweep(0..n + 1, &mut x),
        Err(Error::IndexOutOfRange { arg: "nodes", .. })
    ));
    let mut small = vec![[0.0; 2]; sys.angle_scratch_len(AngleMethod::Cg) - 1];
    assert!(matches!(
        sys.solve_angle(
            &mut x,
            AngleMethod::Cg,
            &SolveOptions::default(),
            &mut small
        ),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    // ε = 0 needs probe scratch even for Gauss–Seidel.
    let sys0 = a.angle(0.0);
    assert_eq!(
        sys0.angle_scratch_len(AngleMethod::DirectGaussSeidel),
        4 * n
    );
    assert_eq!(sys.angle_scratch_len(AngleMethod::DirectGaussSeidel), 0);
    let mut none: Vec<[f64; 2]> = vec![];
    assert!(matches!(
        sys0.solve_angle(
            &mut x,
            AngleMethod::DirectGaussSeidel,
            &SolveOptions::default(),
            &mut none
        ),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    assert_eq!(bits(&x), before);
    assert!(out.iter().all(|v| *v == [1.0; 2]));
    let _: Option<SpringSystem<'_, f64>> = None;
}

/// The rigidity probe's amplification separates healthy systems from mechanisms: small (and
/// deterministic) on a triangulated annulus, an error or far above the limit on the quad ring.
#[test]
fn rigidity_probe_amplification() {
    let opts = SolveOptions::default();
    let tri = annulus::<f64>(8, 24);
    let sys = tri.angle(0.0);
    let mut scratch = vec![[0.0; 2]; sys.angle_probe_scratch_len()];
    let s1 = sys.angle_rigidity_probe(&opts, &mut scratch).unwrap();
    let s2 = sys.angle_rigidity_probe(&opts, &mut scratch).unwrap();
    assert_eq!(s1.to_bits(), s2.to_bits());
    assert!(s1 > 0.0 && s1 < 1e3, "{s1}");
    assert!(matches!(
        sys.angle_rigidity_probe(&opts, &mut scratch[1..]),
        Err(Error::BufferTooSmall { .. })
    ));
    let ring = quad_annulus(5, 16, false);
    let sys = ring.angle(0.0);
    match sys.angle_rigidity_probe(&opts, &mut scratch) {
        Err(Error::SingularSystem { .. }) => {}
        Ok(s) => assert!(s > MAX_AMPLIFICATION, "{s}"),
        Err(e) => panic!("{e}"),
    }
}
