//! Tangent and adjoint of the angle-inclusion springs: the dot-product test on random fields
//! (2D and 3D, f32 and f64, block-Jacobi CG and multigrid, `ε = 0.01` and `ε = 0`), against a
//! dense numpy Jacobian (the blocks recomputed from the points), against central differences
//! of the deformation itself, infinitesimal rigid motions reproduced (`ε = 0`: the blocks
//! `d dᵀ` do not see a rotation), several right-hand sides, typed errors that write nothing.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::sensitivity::{
    angle_adjoint, angle_adjoint_many, angle_adjoint_scratch_len, angle_tangent,
    angle_tangent_many, angle_tangent_scratch_len, AngleSolver,
};
use deform_kernel::spring::{AmgOptions, AngleMethod, AngleSystem, SolveOptions};
use deform_kernel::{Error, Real};
use support::spring::{annulus, cube, AmgBuffers, Case, Lcg};

/// `J v` (tangent) and `Jᵀ w` (adjoint) with `solver`.
fn both<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    solver: AngleSolver<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let n = v.len();
    let opts = tight::<T>();
    let mut jv = v.to_vec();
    let mut s = vec![[T::ZERO; D]; angle_tangent_scratch_len(sys, &solver)];
    let r = angle_tangent(sys, solver, &opts, &mut jv, &mut s).unwrap();
    assert!(r.converged, "tangent {r:?}");
    let mut g = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; angle_adjoint_scratch_len(sys, &solver)];
    let r = angle_adjoint(sys, solver, &opts, w, &mut g, &mut s).unwrap();
    assert!(r.converged, "adjoint {r:?}");
    (jv, g)
}

fn dot_test<T: Real, const D: usize>(case: &Case<T, D>, eps: f64, tol: f64) {
    let sys = case.angle(eps);
    let n = case.n();
    let mut rng = Lcg(17 + D as u64);
    let v: Vec<[T; D]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let w: Vec<[T; D]> = random(n, &mut rng, |_| true);
    let (jv, g) = both(&sys, AngleSolver::Method(AngleMethod::Cg), &v, &w);
    check_dot(&jv, &w, &v, &g, tol, &format!("{D}D eps {eps} block CG"));
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(sys.base(), &opts);
    let h = b.build(sys.base(), &opts);
    let (jv, g) = both(&sys, AngleSolver::Amg(&h), &v, &w);
    check_dot(&jv, &w, &v, &g, tol, &format!("{D}D eps {eps} multigrid"));
}

#[test]
fn dot_product_2d_and_3d_f64() {
    dot_test::<f64, 2>(&annulus(6, 16), 0.01, 1e-11);
    dot_test::<f64, 2>(&annulus(6, 16), 0.0, 1e-11);
    dot_test::<f64, 3>(&cube(5), 0.01, 1e-11);
}

#[test]
fn dot_product_2d_and_3d_f32() {
    dot_test::<f32, 2>(&annulus(6, 16), 0.01, 2e-5);
    dot_test::<f32, 3>(&cube(5), 0.01, 2e-5);
}

/// Both directions against the dense numpy Jacobian (blocks recomputed from the points).
fn dense<T: Real, const D: usize>(case: &Case<T, D>, eps: f64, tol: f64) {
    let sys = case.angle(eps);
    let n = case.n();
    let mut rng = Lcg(23);
    let v: Vec<[T; D]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let w: Vec<[T; D]> = random(n, &mut rng, |_| true);
    let (jv, g) = both(&sys, AngleSolver::Method(AngleMethod::Cg), &v, &w);
    let body = springs_input(
        &case.points,
        &case.offsets,
        &case.targets,
        &case.fixed,
        &v,
        &w,
    );
    let (head, rest) = body.split_once('\n').unwrap();
    let body = format!("{head} {eps:e}\n{rest}");
    let (jv_ref, g_ref) = reference::<D>("angle", body, n);
    let (e1, e2) = (rel_err(&jv, &jv_ref), rel_err(&g, &g_ref));
    eprintln!("{D}D eps {eps}: against numpy, tangent {e1:.1e}, adjoint {e2:.1e}");
    assert!(
        e1 <= tol && e2 <= tol,
        "{D}D eps {eps}: tangent {e1:e}, adjoint {e2:e}"
    );
}

#[test]
fn tangent_and_adjoint_match_dense_numpy() {
    dense::<f64, 2>(&annulus(5, 12), 0.01, 1e-10);
    dense::<f64, 2>(&annulus(5, 12), 0.0, 1e-10);
    dense::<f64, 3>(&cube(4), 0.01, 1e-10);
    dense::<f32, 2>(&annulus(5, 12), 0.01, 1e-4);
}

/// Central differences of the deformation `x(d)` (the angle solve with boundary data `d`)
/// along `v` at steps 10⁻¹…10⁻⁶, against the tangent. The map is linear, so there is no `h²`
/// truncation term: the difference is the tangent up to rounding and the solves' tolerance
/// divided by `h`, at every step.
#[test]
fn tangent_matches_central_differences_at_every_step() {
    let case = annulus::<f64>(6, 16);
    let sys = case.angle(0.01);
    let n = case.n();
    let mut rng = Lcg(3);
    let d0: Vec<[f64; 2]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let v: Vec<[f64; 2]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let method = AngleMethod::Cg;
    let solver = AngleSolver::Method(method);
    let opts = tight::<f64>();
    let mut s = vec![[0.0; 2]; angle_tangent_scratch_len(&sys, &solver)];
    let mut jv = v.clone();
    angle_tangent(&sys, solver, &opts, &mut jv, &mut s).unwrap();
    let mut errs = vec![];
    for k in 1..=6 {
        let h = 10f64.powi(-k);
        let at = |sign: f64| -> Vec<[f64; 2]> {
            let mut x: Vec<[f64; 2]> = d0
                .iter()
                .zip(&v)
                .map(|(a, b)| [a[0] + sign * h * b[0], a[1] + sign * h * b[1]])
                .collect();
            let mut s = vec![[0.0; 2]; sys.angle_scratch_len(method)];
            sys.solve_angle(&mut x, method, &opts, &mut s).unwrap();
            x
        };
        let (plus, minus) = (at(1.0), at(-1.0));
        let fd: Vec<[f64; 2]> = plus
            .iter()
            .zip(&minus)
            .map(|(p, m)| [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)])
            .collect();
        errs.push(rel_err(&fd, &jv));
    }
    eprintln!("central differences, h = 1e-1 … 1e-6: {errs:?}");
    for (k, e) in errs.iter().enumerate() {
        let h = 10f64.powi(-(k as i32 + 1));
        assert!(*e <= 1e-11 / h, "step 1e-{}: {e:e} ({errs:?})", k + 1);
    }
}

/// With `ε = 0` every block is `k d dᵀ / |d|²` and `dᵀ (ω × d) = 0`: an infinitesimal rigid
/// motion `t + ω × r` of the boundary moves every node rigidly (`J` reproduces it), and the
/// adjoint conserves force and moment: `Σ g = Σ w`, `Σ r × g = Σ r × w`.
#[test]
fn infinitesimal_rigid_motion_is_reproduced_with_eps_zero() {
    let case = annulus::<f64>(6, 16);
    let sys = case.angle(0.0);
    let n = case.n();
    let (t, om) = ([0.3, -1.25], 0.7);
    let rigid: Vec<[f64; 2]> = case
        .points
        .iter()
        .map(|p| [t[0] - om * p[1], t[1] + om * p[0]])
        .collect();
    let mut dx: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            if case.fixed[i] != 0 {
                rigid[i]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let solver = AngleSolver::Method(AngleMethod::Cg);
    let mut s = vec![[0.0; 2]; angle_adjoint_scratch_len(&sys, &solver)];
    angle_tangent(&sys, solver, &tight(), &mut dx, &mut s).unwrap();
    let e = rel_err(&dx, &rigid);
    eprintln!("eps 0, rigid field reproduced to {e:.1e}");
    assert!(e <= 1e-11, "rigid field: {e:e}");
    let mut rng = Lcg(9);
    let w: Vec<[f64; 2]> = random(n, &mut rng, |_| true);
    let mut g = vec![[0.0; 2]; n];
    angle_adjoint(&sys, solver, &tight(), &w, &mut g, &mut s).unwrap();
    let moments = |f: &[[f64; 2]]| -> [f64; 3] {
        let mut m = [0.0; 3];
        for (p, x) in case.points.iter().zip(f) {
            m[0] += x[0];
            m[1] += x[1];
            m[2] += p[0] * x[1] - p[1] * x[0];
        }
        m
    };
    let (mg, mw) = (moments(&g), moments(&w));
    for c in 0..3 {
        assert!(
            (mg[c] - mw[c]).abs() <= 1e-10 * norm(&w),
            "{mg:?} vs {mw:?}"
        );
    }
}

/// With `ε > 0` a uniform translation is still reproduced, in 3D too.
#[test]
fn uniform_translation_is_reproduced() {
    let case = cube::<f64>(5);
    let sys = case.angle(0.01);
    let n = case.n();
    let t = [0.3, -1.25, 2.0];
    let mut dx: Vec<[f64; 3]> = (0..n)
        .map(|i| if case.fixed[i] != 0 { t } else { [0.0; 3] })
        .collect();
    let solver = AngleSolver::Method(AngleMethod::Cg);
    let mut s = vec![[0.0; 3]; angle_tangent_scratch_len(&sys, &solver)];
    angle_tangent(&sys, solver, &tight(), &mut dx, &mut s).unwrap();
    assert!(rel_err(&dx, &vec![t; n]) <= 1e-12);
}

/// `*_many` on three fields back to back equals three single calls, bit for bit.
#[test]
fn several_right_hand_sides_match_single_calls() {
    let case = annulus::<f64>(5, 12);
    let sys = case.angle(0.01);
    let n = case.n();
    let mut rng = Lcg(5);
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(sys.base(), &opts);
    let h = b.build(sys.base(), &opts);
    let solver = AngleSolver::Amg(&h);
    let w: Vec<[f64; 2]> = random(3 * n, &mut rng, |_| true);
    let mut g = vec![[0.0; 2]; 3 * n];
    let mut s = vec![[0.0; 2]; angle_adjoint_scratch_len(&sys, &solver)];
    angle_adjoint_many(&sys, solver, &tight(), &w, &mut g, &mut s).unwrap();
    let mut dx: Vec<[f64; 2]> = random(3 * n, &mut rng, |i| case.fixed[i % n] != 0);
    let dx0 = dx.clone();
    angle_tangent_many(&sys, solver, &tight(), &mut dx, &mut s).unwrap();
    for f in 0..3 {
        let r = f * n..(f + 1) * n;
        let mut one = vec![[0.0; 2]; n];
        angle_adjoint(&sys, solver, &tight(), &w[r.clone()], &mut one, &mut s).unwrap();
        assert_eq!(one, g[r.clone()]);
        let mut t = dx0[r.clone()].to_vec();
        angle_tangent(&sys, solver, &tight(), &mut t, &mut s).unwrap();
        assert_eq!(t, dx[r]);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let case = annulus::<f64>(4, 10);
    let sys = case.angle(0.01);
    let n = case.n();
    let cg = AngleSolver::Method(AngleMethod::Cg);
    let mut w = vec![[1.0, 0.5]; n];
    let mut g = vec![[7.0; 2]; n];
    let len = angle_adjoint_scratch_len(&sys, &cg);
    let mut s = vec![[0.0; 2]; len];
    let o = SolveOptions::default();
    let short = angle_adjoint(&sys, cg, &o, &w, &mut g, &mut s[..len - 1]);
    assert!(matches!(short, Err(Error::BufferTooSmall { .. })));
    let gs = AngleSolver::Method(AngleMethod::DirectGaussSeidel);
    assert_eq!(angle_adjoint_scratch_len(&sys, &gs), usize::MAX);
    let r = angle_adjoint(&sys, gs, &o, &w, &mut g, &mut s);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter { arg: "solver", .. })
    ));
    let bad = SolveOptions {
        residual_tol: -1.0,
        ..o
    };
    assert!(angle_adjoint(&sys, cg, &bad, &w, &mut g, &mut s).is_err());
    w[3][1] = f64::NAN;
    let r = angle_adjoint(&sys, cg, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    let r = angle_adjoint(&sys, cg, &o, &w[1..], &mut g, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { arg: "w", .. })));
    assert!(g.iter().all(|x| *x == [7.0; 2]));
    let mut dx = vec![[f64::INFINITY, 0.0]; n];
    assert!(angle_tangent(&sys, cg, &o, &mut dx, &mut s).is_err());
    assert!(dx.iter().all(|x| *x == [f64::INFINITY, 0.0]));
    let mut wm = vec![[0.0; 2]; n + 1];
    let mut gm = vec![[0.0; 2]; n + 1];
    let r = angle_adjoint_many(&sys, cg, &o, &wm, &mut gm, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
    let r = angle_tangent_many(&sys, cg, &o, &mut wm, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
}
