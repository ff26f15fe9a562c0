//! A small shape optimisation driven by the adjoint (issue 30): three Hicks–Henne bumps on
//! the inner wall of an annulus, the volume mesh deformed by Batina's linear springs, and the
//! objective `J(α) = ½ Σ_i |x_i(α) − x_i*|²` over every node, the mismatch with the mesh that
//! the bump amplitudes `α*` give. The gradient `dJ/dα` comes from one adjoint solve
//! (`dJ/dx_b`, [`spring_adjoint`]) pulled back through the bumps; it is checked against
//! central finite differences of `J` itself, and steepest descent with the exact line search
//! (the step from one tangent solve, [`spring_tangent`]) recovers `α*`.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::design::hicks_henne::hicks_henne_bump;
use deform_kernel::sensitivity::{spring_adjoint, spring_adjoint_scratch_len, spring_tangent};
use deform_kernel::spring::{
    solve_linear_with_scratch_len, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SpringSystem,
};
use support::spring::annulus;

/// Grid of the annulus: rings × points per ring (ring 0 is the wall of radius 1).
const RINGS: usize = 14;
const AROUND: usize = 48;
/// Where the three bumps peak along the wall (`t = θ / 2π`).
const PEAKS: [f64; 3] = [0.25, 0.5, 0.75];
/// The amplitudes the target mesh was made with.
const TARGET: [f64; 3] = [0.03, -0.02, 0.015];

fn solver() -> LinearSolver<'static, f64> {
    LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    })
}

fn options() -> SolveOptions<f64> {
    SolveOptions {
        residual_tol: 1e-14,
        max_iterations: 20_000,
        ..SolveOptions::default()
    }
}

/// The wall displacement of bump `k` with amplitude 1 at wall node `i`: along the outward
/// normal (the radius), `sin(π t^e)^3` of SU2's Hicks–Henne bump at `t = θ / 2π`.
fn shape(points: &[[f64; 2]], k: usize, i: usize) -> [f64; 2] {
    let [x, y] = points[i];
    let r = x.hypot(y);
    let t = y.atan2(x).rem_euclid(2.0 * std::f64::consts::PI) / (2.0 * std::f64::consts::PI);
    let b = hicks_henne_bump(t, PEAKS[k]);
    [b * x / r, b * y / r]
}

/// The mesh displacement for amplitudes `alpha` (the springs' solve with the wall moved).
fn deform(sys: &SpringSystem<'_, f64>, points: &[[f64; 2]], alpha: [f64; 3]) -> Vec<[f64; 2]> {
    let mut dx = vec![[0.0; 2]; points.len()];
    for (i, d) in dx.iter_mut().enumerate().take(AROUND) {
        for (k, a) in alpha.iter().enumerate() {
            let s = shape(points, k, i);
            *d = [d[0] + a * s[0], d[1] + a * s[1]];
        }
    }
    let mut scratch = vec![[0.0; 2]; solve_linear_with_scratch_len(&solver(), points.len())];
    let rep = spring_tangent(sys, solver(), &options(), &mut dx, &mut scratch).unwrap();
    assert!(rep.converged);
    dx
}

/// `J` and the mismatch `x − x*` (which is `dJ/dx`).
fn objective(dx: &[[f64; 2]], target: &[[f64; 2]]) -> (f64, Vec<[f64; 2]>) {
    let w: Vec<[f64; 2]> = dx
        .iter()
        .zip(target)
        .map(|(a, b)| [a[0] - b[0], a[1] - b[1]])
        .collect();
    (
        0.5 * w.iter().map(|v| v[0] * v[0] + v[1] * v[1]).sum::<f64>(),
        w,
    )
}

/// `dJ/dα` by the adjoint: `g = dJ/dx_b` from one solve, then `Σ_b g_b · ∂x_b/∂α_k`.
fn gradient(sys: &SpringSystem<'_, f64>, points: &[[f64; 2]], w: &[[f64; 2]]) -> [f64; 3] {
    let n = points.len();
    let mut g = vec![[0.0; 2]; n];
    let mut scratch = vec![[0.0; 2]; spring_adjoint_scratch_len::<f64, 2>(&solver(), n)];
    let rep = spring_adjoint(sys, solver(), &options(), w, &mut g, &mut scratch).unwrap();
    assert!(rep.converged);
    let mut out = [0.0; 3];
    for (k, o) in out.iter_mut().enumerate() {
        *o = (0..AROUND)
            .map(|i| {
                let s = shape(points, k, i);
                g[i][0] * s[0] + g[i][1] * s[1]
            })
            .sum();
    }
    out
}

#[test]
fn adjoint_gradient_matches_finite_differences_and_drives_the_optimisation() {
    let case = annulus::<f64>(RINGS, AROUND);
    let sys = case.system();
    let points = &case.points;
    assert!(
        (0..AROUND).all(|i| case.fixed[i] != 0),
        "ring 0 is the wall"
    );
    let target = deform(&sys, points, TARGET);
    let j = |alpha: [f64; 3]| objective(&deform(&sys, points, alpha), &target).0;

    // The gradient at the start against central differences of J (quadratic in α: exact up
    // to rounding and the solver's tolerance at any step).
    let start = [0.0; 3];
    let (j0, w) = objective(&deform(&sys, points, start), &target);
    let grad = gradient(&sys, points, &w);
    for (k, &gk) in grad.iter().enumerate() {
        let h = 1e-3;
        let (mut up, mut down) = (start, start);
        up[k] += h;
        down[k] -= h;
        let fd = (j(up) - j(down)) / (2.0 * h);
        assert!(
            (gk - fd).abs() <= 1e-7 * gk.abs().max(1e-12),
            "dJ/dα_{k}: adjoint {gk:e}, finite differences {fd:e}"
        );
    }

    // Steepest descent with the exact step of a quadratic: τ = |∇J|² / |J_x ∇J|², where
    // J_x ∇J is the tangent of the mesh along the gradient's bumps.
    let mut alpha = start;
    let mut its = 0;
    loop {
        let (jv, w) = objective(&deform(&sys, points, alpha), &target);
        let g = gradient(&sys, points, &w);
        let gg: f64 = g.iter().map(|x| x * x).sum();
        if jv <= 1e-24 * j0 || its == 200 {
            break;
        }
        let along = deform(&sys, points, g);
        let aa: f64 = along.iter().map(|v| v[0] * v[0] + v[1] * v[1]).sum();
        let tau = gg / aa;
        for (a, gk) in alpha.iter_mut().zip(g) {
            *a -= tau * gk;
        }
        its += 1;
    }
    let (jend, _) = objective(&deform(&sys, points, alpha), &target);
    println!("J: {j0:.3e} -> {jend:.3e} in {its} steps; alpha {alpha:?} (target {TARGET:?})");
    assert!(jend <= 1e-20 * j0, "J fell from {j0:e} to {jend:e} only");
    for (a, t) in alpha.iter().zip(TARGET) {
        assert!((a - t).abs() <= 1e-8, "alpha {alpha:?} against {TARGET:?}");
    }
}
