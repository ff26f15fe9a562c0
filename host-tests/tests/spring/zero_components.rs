//! Components that are provably zero (every fixed value ±0, every free value +0) are left out
//! of the CG and multigrid-CG solves. The other components, the report and the zero
//! component's bits must be those of the full solve: the full solve is forced by giving one
//! free node of the zero component a `-0.0` initial guess (then the component is no longer
//! provably `+0`, and CG runs every lane), and the two are compared bit for bit.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::spring::{
    solve_linear_amg_scratch_len, solve_linear_scratch_len, AmgOptions, LinearMethod,
    Preconditioner, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::Real;
use support::spring::*;

/// `field` with the components in `zero` set to zero: `-0.0` at every other fixed node (the
/// sign must not matter there), `+0.0` at free nodes.
fn with_zero_components<T: Real, const V: usize>(
    case_fixed: &[u8],
    mut x: Vec<[T; V]>,
    zero: &[usize],
) -> Vec<[T; V]> {
    for (i, v) in x.iter_mut().enumerate() {
        for &c in zero {
            v[c] = if case_fixed[i] != 0 && i % 2 == 0 {
                -T::ZERO
            } else {
                T::ZERO
            };
        }
    }
    x
}

/// The same field with one free node's zero component at `-0.0`: not provably `+0`, so the
/// full solve runs every lane.
fn forcing_full<T: Real, const V: usize>(fixed: &[u8], x: &[[T; V]], c: usize) -> Vec<[T; V]> {
    let mut y = x.to_vec();
    let free = fixed.iter().position(|&f| f == 0).unwrap();
    y[free][c] = -T::ZERO;
    y
}

type Solve<'s, T, const V: usize> =
    dyn Fn(&SpringSystem<'_, T>, &mut [[T; V]]) -> deform_kernel::Result<SolveReport<T>> + 's;

/// Solves `x` (packed path) and the forced full solve; checks the nonzero components and the
/// report agree bit for bit and the zero components come back `+0` (free) and untouched
/// (fixed).
fn check_same<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    fixed: &[u8],
    x0: &[[T; V]],
    zero: &[usize],
    solve: &Solve<'_, T, V>,
) {
    let mut packed = x0.to_vec();
    let rp = solve(sys, &mut packed).unwrap();
    let mut full = forcing_full(fixed, x0, zero[0]);
    let rf = solve(sys, &mut full).unwrap();
    assert!(rp.converged && rp.iterations > 1, "{rp:?}");
    assert_eq!(rp.iterations, rf.iterations);
    assert_eq!(rp.residual.to_bits_u64(), rf.residual.to_bits_u64());
    assert_eq!(rp.max_update.to_bits_u64(), rf.max_update.to_bits_u64());
    assert_eq!(rp.converged, rf.converged);
    for (i, ((p, f), x0)) in packed.iter().zip(&full).zip(x0).enumerate() {
        for c in 0..V {
            if zero.contains(&c) {
                let want = if fixed[i] != 0 { x0[c] } else { T::ZERO };
                assert_eq!(p[c].to_bits_u64(), want.to_bits_u64(), "node {i} comp {c}");
            } else {
                assert_eq!(p[c].to_bits_u64(), f[c].to_bits_u64(), "node {i} comp {c}");
            }
        }
    }
    // The full solve really ran the zero lane: its -0 start became +0 or stayed -0, and
    // every other free value of it is zero.
    assert!(full.iter().all(|v| zero.iter().all(|&c| v[c] == T::ZERO)));
}

fn amg_solver<T: Real, const V: usize>(
    opts: AmgOptions<T>,
    stop: SolveOptions<T>,
) -> impl Fn(&SpringSystem<'_, T>, &mut [[T; V]]) -> deform_kernel::Result<SolveReport<T>> {
    move |sys, x| {
        let mut b = AmgBuffers::new(sys, &opts);
        let h = b.build(sys, &opts);
        let mut scratch = vec![[T::ZERO; V]; solve_linear_amg_scratch_len(&h)];
        sys.solve_linear_amg(&h, x, &stop, &mut scratch)
    }
}

fn cg_solver<T: Real, const V: usize>(
    preconditioner: Preconditioner<T>,
    stop: SolveOptions<T>,
) -> impl Fn(&SpringSystem<'_, T>, &mut [[T; V]]) -> deform_kernel::Result<SolveReport<T>> {
    move |sys, x| {
        let m = LinearMethod::Cg { preconditioner };
        let mut scratch = vec![[T::ZERO; V]; solve_linear_scratch_len(&m, x.len())];
        sys.solve_linear(x, m, &stop, &mut scratch)
    }
}

fn stop<T: Real>(tol: f64) -> SolveOptions<T> {
    SolveOptions {
        max_iterations: 500,
        residual_tol: T::from_f64(tol),
        update_tol: T::ZERO,
    }
}

/// Fixed data scaled so that the nonzero components' exponents sit far below the zero
/// component's (whose exponent comes from the stiffness alone): the common scale of the
/// norms differs between the packed and the full solve.
fn scaled<T: Real, const V: usize>(mut x: Vec<[T; V]>, s: f64) -> Vec<[T; V]> {
    for v in x.iter_mut() {
        for c in v.iter_mut() {
            *c *= T::from_f64(s);
        }
    }
    x
}

#[test]
fn rotation_about_z_in_3d_amg_and_cg() {
    let cube = cube::<f64>(8);
    let sys = cube.system();
    for s in [1.0, 0.05, 1e-6, 3e4] {
        let x0 = scaled(field::<f64, 3, 3>(&cube, &mut Lcg(7), Some(0.0)), s);
        let x0 = with_zero_components(&cube.fixed, x0, &[2]);
        let amg = amg_solver::<f64, 3>(AmgOptions::default(), stop(1e-9));
        check_same(&sys, &cube.fixed, &x0, &[2], &amg);
        for pre in [Preconditioner::Jacobi, Preconditioner::None] {
            check_same(&sys, &cube.fixed, &x0, &[2], &cg_solver(pre, stop(1e-9)));
        }
        check_same(
            &sys,
            &cube.fixed,
            &x0,
            &[2],
            &cg_solver(Preconditioner::Ssor { omega: 1.3 }, stop(1e-9)),
        );
    }
}

#[test]
fn several_zero_components_of_seven_and_f32() {
    let cube = cube::<f64>(7);
    let sys = cube.system();
    let x0 = field::<f64, 3, 7>(&cube, &mut Lcg(11), Some(0.0));
    for zero in [&[0usize, 1, 2, 4, 5][..], &[6], &[1, 3]] {
        let x0 = with_zero_components(&cube.fixed, scaled(x0.clone(), 0.01), zero);
        let amg = amg_solver::<f64, 7>(AmgOptions::default(), stop(1e-10));
        check_same(&sys, &cube.fixed, &x0, zero, &amg);
    }
    let ann = annulus::<f32>(10, 32);
    let sys = ann.system();
    let x0 = field::<f32, 2, 2>(&ann, &mut Lcg(3), Some(0.0));
    let x0 = with_zero_components(&ann.fixed, x0, &[0]);
    let amg = amg_solver::<f32, 2>(AmgOptions::default(), stop(1e-5));
    check_same(&sys, &ann.fixed, &x0, &[0], &amg);
}

#[test]
fn all_zero_and_short_scratch_behave_as_before() {
    let cube = cube::<f64>(6);
    let sys = cube.system();
    // Every component zero: converged at once, nothing written.
    let x0 = with_zero_components(&cube.fixed, vec![[1.0f64; 3]; cube.n()], &[0, 1, 2]);
    let mut x = x0.clone();
    let rep = amg_solver::<f64, 3>(AmgOptions::default(), stop(1e-9))(&sys, &mut x).unwrap();
    assert!(rep.converged && rep.iterations == 0, "{rep:?}");
    assert_eq!(bits(&x), bits(&x0));
    // A scratch one item short of the full solve's is refused with the full solve's numbers,
    // although the packed solve would fit, and nothing is written.
    let x0 = with_zero_components(
        &cube.fixed,
        field::<f64, 3, 3>(&cube, &mut Lcg(5), Some(0.0)),
        &[2],
    );
    let m = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let needed = 4 * cube.n() + cube.n().div_ceil(3);
    let mut scratch = vec![[0.0; 3]; needed - 1];
    let mut x = x0.clone();
    let err = sys.solve_linear(&mut x, m, &stop(1e-9), &mut scratch);
    assert_eq!(
        err.unwrap_err(),
        deform_kernel::Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: needed - 1
        }
    );
    assert_eq!(bits(&x), bits(&x0));
}
