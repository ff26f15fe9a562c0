//! Tangent and adjoint of the linear springs: the dot-product test on random fields (2D and
//! 3D, f32 and f64, CG with each one-level preconditioner and multigrid, several right-hand
//! sides), against a dense numpy Jacobian, against central finite differences of the
//! deformation itself (a linear map: exact up to rounding and solver tolerance at every step),
//! a uniform translation reproduced, and typed errors that write nothing.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::sensitivity::{
    spring_adjoint, spring_adjoint_many, spring_adjoint_scratch_len, spring_tangent,
    spring_tangent_many,
};
use deform_kernel::spring::{
    solve_linear_with_scratch_len, AmgOptions, LinearMethod, LinearSolver, Preconditioner,
    SolveOptions, SpringSystem,
};
use deform_kernel::{Error, Real};
use support::spring::{annulus, cube, AmgBuffers, Case, Lcg};

/// `J v` (tangent) and `Jᵀ w` (adjoint) with `solver`.
fn both<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    v: &[[T; V]],
    w: &[[T; V]],
) -> (Vec<[T; V]>, Vec<[T; V]>) {
    let n = sys.node_count();
    let opts = tight::<T>();
    let mut jv = v.to_vec();
    let mut s = vec![[T::ZERO; V]; solve_linear_with_scratch_len(&solver, n)];
    assert!(
        spring_tangent(sys, solver, &opts, &mut jv, &mut s)
            .unwrap()
            .converged
    );
    let mut g = vec![[T::ZERO; V]; n];
    let mut s = vec![[T::ZERO; V]; spring_adjoint_scratch_len::<T, V>(&solver, n)];
    assert!(
        spring_adjoint(sys, solver, &opts, w, &mut g, &mut s)
            .unwrap()
            .converged
    );
    (jv, g)
}

fn dot_test<T: Real, const D: usize, const V: usize>(case: &Case<T, D>, tol: f64) {
    let sys = case.system();
    let n = case.n();
    let mut rng = Lcg(7 + V as u64);
    let v: Vec<[T; V]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let w: Vec<[T; V]> = random(n, &mut rng, |_| true);
    for pre in [
        Preconditioner::None,
        Preconditioner::Jacobi,
        Preconditioner::Ssor { omega: T::ONE },
    ] {
        let solver = LinearSolver::Method(LinearMethod::Cg {
            preconditioner: pre,
        });
        let (jv, g) = both(&sys, solver, &v, &w);
        assert_dot(&jv, &w, &v, &g, tol, &format!("{D}D V={V} {pre:?}"));
    }
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&sys, &opts);
    let h = b.build(&sys, &opts);
    let (jv, g) = both(&sys, LinearSolver::Amg(&h), &v, &w);
    assert_dot(&jv, &w, &v, &g, tol, &format!("{D}D V={V} multigrid"));
}

#[test]
fn dot_product_2d_and_3d_f64() {
    dot_test::<f64, 2, 2>(&annulus(6, 16), 1e-11);
    dot_test::<f64, 3, 3>(&cube(5), 1e-11);
    // Two right-hand sides packed as V = 2 D: one lane per component.
    dot_test::<f64, 2, 4>(&annulus(6, 16), 1e-11);
}

#[test]
fn dot_product_2d_and_3d_f32() {
    dot_test::<f32, 2, 2>(&annulus(6, 16), 2e-5);
    dot_test::<f32, 3, 3>(&cube(5), 2e-5);
}

/// Both directions against the dense numpy Jacobian (stiffness recomputed there).
fn dense<T: Real, const D: usize>(case: &Case<T, D>, tol: f64) {
    let sys = case.system();
    let n = case.n();
    let mut rng = Lcg(11);
    let v: Vec<[T; D]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let w: Vec<[T; D]> = random(n, &mut rng, |_| true);
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let (jv, g) = both(&sys, solver, &v, &w);
    let body = springs_input(
        &case.points,
        &case.offsets,
        &case.targets,
        &case.fixed,
        &v,
        &w,
    );
    let (jv_ref, g_ref) = reference::<D>("springs", body, n);
    let (e1, e2) = (rel_err(&jv, &jv_ref), rel_err(&g, &g_ref));
    assert!(
        e1 <= tol && e2 <= tol,
        "{D}D: tangent {e1:e}, adjoint {e2:e}"
    );
}

#[test]
fn tangent_and_adjoint_match_dense_numpy() {
    dense::<f64, 2>(&annulus(5, 12), 1e-10);
    dense::<f64, 3>(&cube(4), 1e-10);
    dense::<f32, 2>(&annulus(5, 12), 1e-4);
}

/// Central differences of the deformation `x(d)` (the solve with boundary data `d`) along
/// `v`, at steps 10⁻¹…10⁻⁶, against the tangent. The map is linear, so there is no `h²`
/// truncation term: the difference is the tangent up to rounding and the solves' tolerance
/// divided by `h` (it grows slowly as `h` shrinks, never falls as `h²`).
#[test]
fn tangent_matches_central_differences_at_every_step() {
    let case = annulus::<f64>(6, 16);
    let sys = case.system();
    let n = case.n();
    let mut rng = Lcg(3);
    let d0: Vec<[f64; 2]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let v: Vec<[f64; 2]> = random(n, &mut rng, |i| case.fixed[i] != 0);
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let opts = tight::<f64>();
    let mut s = vec![[0.0; 2]; solve_linear_with_scratch_len(&solver, n)];
    let mut jv = v.clone();
    spring_tangent(&sys, solver, &opts, &mut jv, &mut s).unwrap();
    let mut errs = vec![];
    for k in 1..=6 {
        let h = 10f64.powi(-k);
        let mut plus: Vec<[f64; 2]> = d0
            .iter()
            .zip(&v)
            .map(|(a, b)| [a[0] + h * b[0], a[1] + h * b[1]])
            .collect();
        let mut minus: Vec<[f64; 2]> = d0
            .iter()
            .zip(&v)
            .map(|(a, b)| [a[0] - h * b[0], a[1] - h * b[1]])
            .collect();
        sys.solve_linear_with(&mut plus, solver, &opts, &mut s)
            .unwrap();
        sys.solve_linear_with(&mut minus, solver, &opts, &mut s)
            .unwrap();
        let fd: Vec<[f64; 2]> = plus
            .iter()
            .zip(&minus)
            .map(|(p, m)| [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)])
            .collect();
        errs.push(rel_err(&fd, &jv));
    }
    for (k, e) in errs.iter().enumerate() {
        // rounding and tolerance over h: 1e-13 · |d0| / h, with room.
        let h = 10f64.powi(-(k as i32 + 1));
        assert!(*e <= 1e-11 / h, "step 1e-{}: {e:e} ({errs:?})", k + 1);
    }
}

/// A uniform translation of every fixed node moves every node by it: `J t = t`, and the
/// adjoint of a uniform `w` sums it onto the boundary (`Σ g = Σ w`).
#[test]
fn uniform_translation_is_reproduced() {
    let case = cube::<f64>(5);
    let sys = case.system();
    let n = case.n();
    let t = [0.3, -1.25, 2.0];
    let mut dx = vec![t; n];
    for (i, d) in dx.iter_mut().enumerate() {
        if case.fixed[i] == 0 {
            *d = [0.0; 3];
        }
    }
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let mut s = vec![[0.0; 3]; solve_linear_with_scratch_len(&solver, n)];
    spring_tangent(&sys, solver, &tight(), &mut dx, &mut s).unwrap();
    assert!(rel_err(&dx, &vec![t; n]) <= 1e-12);
    let w = vec![[1.0, 2.0, 3.0]; n];
    let mut g = vec![[0.0; 3]; n];
    let mut s = vec![[0.0; 3]; spring_adjoint_scratch_len::<f64, 3>(&solver, n)];
    spring_adjoint(&sys, solver, &tight(), &w, &mut g, &mut s).unwrap();
    for c in 0..3 {
        let total: f64 = g.iter().map(|x| x[c]).sum();
        let want = (c + 1) as f64 * n as f64;
        assert!(
            (total - want).abs() <= 1e-10 * want,
            "component {c}: {total} vs {want}"
        );
    }
}

/// `*_many` on three fields back to back equals three single calls, bit for bit.
#[test]
fn several_right_hand_sides_match_single_calls() {
    let case = annulus::<f64>(5, 12);
    let sys = case.system();
    let n = case.n();
    let mut rng = Lcg(5);
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&sys, &opts);
    let h = b.build(&sys, &opts);
    let solver = LinearSolver::Amg(&h);
    let w: Vec<[f64; 2]> = random(3 * n, &mut rng, |_| true);
    let mut g = vec![[0.0; 2]; 3 * n];
    let mut s = vec![[0.0; 2]; spring_adjoint_scratch_len::<f64, 2>(&solver, n)];
    spring_adjoint_many(&sys, solver, &tight(), &w, &mut g, &mut s).unwrap();
    let mut dx: Vec<[f64; 2]> = random(3 * n, &mut rng, |i| case.fixed[i % n] != 0);
    let dx0 = dx.clone();
    let mut st = vec![[0.0; 2]; solve_linear_with_scratch_len(&solver, n)];
    spring_tangent_many(&sys, solver, &tight(), &mut dx, &mut st).unwrap();
    for f in 0..3 {
        let mut one = vec![[0.0; 2]; n];
        spring_adjoint(
            &sys,
            solver,
            &tight(),
            &w[f * n..(f + 1) * n],
            &mut one,
            &mut s,
        )
        .unwrap();
        assert_eq!(one, g[f * n..(f + 1) * n]);
        let mut t = dx0[f * n..(f + 1) * n].to_vec();
        spring_tangent(&sys, solver, &tight(), &mut t, &mut st).unwrap();
        assert_eq!(t, dx[f * n..(f + 1) * n]);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let case = annulus::<f64>(4, 10);
    let sys = case.system();
    let n = case.n();
    let cg = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let mut w = vec![[1.0, 0.5]; n];
    let mut g = vec![[7.0; 2]; n];
    let len = spring_adjoint_scratch_len::<f64, 2>(&cg, n);
    let mut s = vec![[0.0; 2]; len];
    let o = SolveOptions::default();
    let short = spring_adjoint(&sys, cg, &o, &w, &mut g, &mut s[..len - 1]);
    assert!(matches!(short, Err(Error::BufferTooSmall { .. })));
    let sor = LinearSolver::Method(LinearMethod::Sor { omega: 1.5 });
    let r = spring_adjoint(&sys, sor, &o, &w, &mut g, &mut s);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter { arg: "solver", .. })
    ));
    w[3][1] = f64::NAN;
    let r = spring_adjoint(&sys, cg, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    let r = spring_adjoint(&sys, cg, &o, &w[1..], &mut g, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { arg: "w", .. })));
    assert!(g.iter().all(|x| *x == [7.0; 2]));
    let mut wm = vec![[0.0; 2]; n + 1];
    let mut gm = vec![[0.0; 2]; n + 1];
    let r = spring_adjoint_many(&sys, cg, &o, &wm, &mut gm, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
    let r = spring_tangent_many(&sys, cg, &o, &mut wm, &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
}

/// Lanes of `w` that are `±0` at every free node are not solved (64-bit hosts): the other
/// lanes, the report and the dropped lanes' `g` must be what the solve of the kept lanes
/// alone gives (`V = 2` has none to drop and runs the full path), bit for bit, with multigrid
/// and CG, in f64 and f32; the dropped lanes' `g_j = w_j + Σ k·(+0)`: `w_j`, or `+0` for a
/// `-0` with a free neighbour. On 32-bit targets the full 6-lane solve runs on the same golden
/// case (`quaternion_spring_adjoint`) and gives the same hash.
#[test]
fn zero_lanes_of_the_adjoint_give_the_kept_lanes_solve() {
    zero_lanes::<f64>(1e-11);
    zero_lanes::<f32>(1e-5);
}

fn zero_lanes<T: Real>(tol: f64) {
    let case = annulus::<T>(6, 20);
    let sys = case.system();
    let n = case.n();
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&sys, &opts);
    let h = b.build(&sys, &opts);
    let cg = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let stop = SolveOptions {
        residual_tol: T::from_f64(tol),
        max_iterations: 1000,
        update_tol: T::ZERO,
    };
    let mut rng = Lcg(17);
    let kept: Vec<[T; 4]> = random(n, &mut rng, |_| true);
    // Lanes 1 and 4 of 6 zero at free nodes (a signed zero, or a value at fixed nodes).
    let wide: Vec<[T; 6]> = (0..n)
        .map(|i| {
            let (k, fixed) = (kept[i], case.fixed[i] != 0);
            let z = if fixed && i % 3 == 0 {
                T::from_f64(0.25)
            } else if i % 2 == 0 {
                -T::ZERO
            } else {
                T::ZERO
            };
            [k[0], z, k[1], k[2], z, k[3]]
        })
        .collect();
    let narrow: Vec<[T; 4]> = wide.iter().map(|v| [v[0], v[2], v[3], v[5]]).collect();
    for solver in [LinearSolver::Amg(&h), cg] {
        let mut g6 = vec![[T::ZERO; 6]; n];
        let mut s6 = vec![[T::ZERO; 6]; spring_adjoint_scratch_len::<T, 6>(&solver, n)];
        let r6 = spring_adjoint(&sys, solver, &stop, &wide, &mut g6, &mut s6).unwrap();
        let mut g4 = vec![[T::ZERO; 4]; n];
        let mut s4 = vec![[T::ZERO; 4]; spring_adjoint_scratch_len::<T, 4>(&solver, n)];
        let r4 = spring_adjoint(&sys, solver, &stop, &narrow, &mut g4, &mut s4).unwrap();
        assert!(r6.converged && r6.iterations > 3, "{r6:?}");
        assert_eq!(r6.iterations, r4.iterations);
        assert_eq!(r6.residual.to_bits_u64(), r4.residual.to_bits_u64());
        assert_eq!(r6.max_update.to_bits_u64(), r4.max_update.to_bits_u64());
        for i in 0..n {
            let (a, b) = (g6[i], g4[i]);
            let kept = [a[0], a[2], a[3], a[5]];
            assert_eq!(kept.map(|x| x.to_bits_u64()), b.map(|x| x.to_bits_u64()));
            let row = case.offsets[i] as usize..case.offsets[i + 1] as usize;
            let free_neighbour = case.targets[row]
                .iter()
                .any(|&j| case.fixed[j as usize] == 0);
            for c in [1, 4] {
                let free = case.fixed[i] == 0;
                let want = if free || (wide[i][c] == T::ZERO && free_neighbour) {
                    T::ZERO
                } else {
                    wide[i][c]
                };
                assert_eq!(a[c].to_bits_u64(), want.to_bits_u64(), "node {i} lane {c}");
            }
        }
    }
}

/// A scratch one item short of the full adjoint's is refused with the full solve's numbers
/// even when zero lanes would let the packed solve fit, and `g` is untouched.
#[test]
fn short_scratch_is_refused_although_zero_lanes_would_fit() {
    let case = annulus::<f64>(5, 16);
    let sys = case.system();
    let n = case.n();
    let cg = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let w: Vec<[f64; 6]> = (0..n)
        .map(|i| [1.0, 0.0, 0.5, 0.0, 0.0, i as f64])
        .collect();
    let needed = spring_adjoint_scratch_len::<f64, 6>(&cg, n);
    let mut s = vec![[0.0; 6]; needed - 1];
    let mut g = vec![[7.0; 6]; n];
    let r = spring_adjoint(&sys, cg, &tight(), &w, &mut g, &mut s);
    assert_eq!(
        r.unwrap_err(),
        Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: needed - 1
        }
    );
    assert!(g.iter().all(|v| *v == [7.0; 6]));
}
