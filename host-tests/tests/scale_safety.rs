//! Scale safety (issue 14 item 3): solvers, residuals, IDW, arclength and stretching give the
//! same answers for fields and coordinates near the edges of the floating-point range as at
//! scale 1, in `f32` and `f64`. Powers of two scale exactly, so at `2^k` the kernel must
//! return exactly `2^k` times the scale-1 bits (same iterations, same residual); at other
//! extreme scales (1e154, 1e-300, 1.5e19, …) the answers must match to the solver tolerance.
#![allow(clippy::needless_range_loop)]

mod support;

use deform_kernel::quaternion::{propagate_idw, propagate_spring, propagate_spring_scratch_len};
use deform_kernel::spring::{
    solve_linear_scratch_len, AmgHierarchy, AmgOptions, AngleMethod, LinearMethod, Preconditioner,
    SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::taubin::{arclength, stretching};
use deform_kernel::Direction;
use deform_kernel::{Block, Error, Graph, Quat, Real};
use support::spring::*;

fn methods<T: Real>() -> Vec<(&'static str, LinearMethod<T>)> {
    let cg = |preconditioner| LinearMethod::Cg { preconditioner };
    vec![
        ("jacobi", LinearMethod::Jacobi),
        ("gauss-seidel", LinearMethod::GaussSeidel),
        (
            "sor 1.5",
            LinearMethod::Sor {
                omega: T::from_f64(1.5),
            },
        ),
        ("cg", cg(Preconditioner::None)),
        ("cg+jacobi", cg(Preconditioner::Jacobi)),
        (
            "cg+ssor",
            cg(Preconditioner::Ssor {
                omega: T::from_f64(1.2),
            }),
        ),
    ]
}

fn solve<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    x: &mut [[T; V]],
    m: LinearMethod<T>,
) -> deform_kernel::Result<SolveReport<T>> {
    let mut scratch = vec![[T::ZERO; V]; solve_linear_scratch_len(&m, x.len())];
    let opts = SolveOptions {
        max_iterations: 20_000,
        ..SolveOptions::default()
    };
    sys.solve_linear(x, m, &opts, &mut scratch)
}

fn scaled<T: Real, const V: usize>(x: &[[T; V]], s: f64) -> Vec<[T; V]> {
    x.iter().map(|v| v.map(|c| c * T::from_f64(s))).collect()
}

/// Relative distance of `got` from `want` in the max norm.
fn rel_err<T: Real, const V: usize>(got: &[[T; V]], want: &[[f64; V]]) -> f64 {
    let scale = want.iter().flatten().fold(0.0f64, |m, w| m.max(w.abs()));
    let err = got
        .iter()
        .flatten()
        .zip(want.iter().flatten())
        .fold(0.0f64, |m, (g, w)| m.max((g.to_f64() - w).abs()));
    err / scale
}

/// Every linear method at `2^k`: exactly `2^k` times the scale-1 bits, same report.
fn linear_power_of_two<T: Real>(scales: &[f64]) {
    let case = annulus::<T>(5, 16);
    let sys = case.system();
    let x0: Vec<[T; 2]> = field(&case, &mut Lcg(7), Some(0.0));
    for (name, m) in methods::<T>() {
        let mut base = x0.clone();
        let rep = solve(&sys, &mut base, m).unwrap();
        assert!(rep.converged, "{name}: scale 1 must converge");
        for &s in scales {
            let mut x = scaled(&x0, s);
            let got = solve(&sys, &mut x, m).unwrap();
            assert_eq!(got.iterations, rep.iterations, "{name} at {s:e}");
            assert!(got.converged, "{name} at {s:e}");
            assert_eq!(
                got.residual.to_bits_u64(),
                rep.residual.to_bits_u64(),
                "{name} at {s:e}: relative residual"
            );
            assert_eq!(
                got.max_update.to_bits_u64(),
                (rep.max_update * T::from_f64(s)).to_bits_u64(),
                "{name} at {s:e}: max update"
            );
            assert_eq!(bits(&x), bits(&scaled(&base, s)), "{name} at {s:e}: values");
        }
    }
}

#[test]
fn linear_solves_scale_by_powers_of_two_bit_for_bit() {
    linear_power_of_two::<f64>(&[2f64.powi(512), 2f64.powi(-960), 2f64.powi(900)]);
    linear_power_of_two::<f32>(&[2f64.powi(64), 2f64.powi(-100), 2f64.powi(100)]);
}

/// Fixed nodes at the constant `c`, free nodes from 0: every method must converge to `c`
/// (the field is reproduced to the tolerance, with at least one iteration), and a field that is
/// already constant everywhere must come back bit for bit after 0 iterations.
fn constant_fields<T: Real>(values: &[f64], tol: f64) {
    let case = annulus::<T>(5, 16);
    let sys = case.system();
    for &c in values {
        for (name, m) in methods::<T>() {
            let mut x: Vec<[T; 2]> = (0..case.n())
                .map(|i| {
                    let v = if case.fixed[i] != 0 { c } else { 0.0 };
                    [T::from_f64(v), T::from_f64(-v)]
                })
                .collect();
            let rep = solve(&sys, &mut x, m).unwrap();
            assert!(rep.converged, "{name} at {c:e}: {rep:?}");
            assert!(
                rep.iterations > 0,
                "{name} at {c:e}: stopped at the initial guess"
            );
            let want = vec![[T::from_f64(c).to_f64(), -T::from_f64(c).to_f64()]; case.n()];
            let err = rel_err(&x, &want);
            assert!(err <= tol, "{name} at {c:e}: relative error {err:e}");
            let r = sys.relative_residual(&x).unwrap();
            assert!(
                r.is_finite() && r <= T::from_f64(10.0) * SolveOptions::<T>::default().residual_tol,
                "{name} at {c:e}: relative_residual {r:?}"
            );

            let mut flat = vec![[T::from_f64(c), T::from_f64(-c)]; case.n()];
            let before = bits(&flat);
            let rep = solve(&sys, &mut flat, m).unwrap();
            assert!(rep.converged && rep.iterations == 0, "{name} at {c:e}");
            assert_eq!(
                bits(&flat),
                before,
                "{name} at {c:e}: constant field changed"
            );
        }
    }
}

#[test]
fn constant_fields_survive_extreme_scales() {
    constant_fields::<f64>(&[1e154, 1e-300, 1e300, 3e-305], 1e-8);
    constant_fields::<f32>(&[1.5e19, 1e-30, 1e36, 3e-36], 1e-3);
}

#[test]
fn relative_residual_is_scale_invariant() {
    fn check<T: Real>(pow2: f64, other: f64) {
        let case = annulus::<T>(5, 16);
        let sys = case.system();
        let x: Vec<[T; 3]> = field(&case, &mut Lcg(3), None);
        let r1 = sys.relative_residual(&x).unwrap();
        let rs = sys.relative_residual(&scaled(&x, pow2)).unwrap();
        assert_eq!(rs.to_bits_u64(), r1.to_bits_u64(), "at {pow2:e}");
        let ro = sys.relative_residual(&scaled(&x, other)).unwrap();
        assert!(ro.is_finite(), "at {other:e}: {ro:?}");
        let d = (ro.to_f64() - r1.to_f64()).abs() / r1.to_f64();
        assert!(d < 1e-4, "at {other:e}: {ro:?} vs {r1:?}");
    }
    check::<f64>(2f64.powi(600), 1e154);
    check::<f64>(2f64.powi(-990), 1e-300);
    check::<f32>(2f64.powi(70), 1.5e19);
    check::<f32>(2f64.powi(-110), 1e-30);
}

/// Stiffness near the top of the range (row sums just below `MAX`): CG without a
/// preconditioner forms `rᵀr ≈ k² x²`, which no rescaling brings into range, and must say so
/// ([`Error::Overflow`], values untouched) instead of "singular"; every other method agrees
/// with the unit-stiffness solution (it does not depend on a common stiffness factor). With
/// values 1e10 times larger the stationary sweeps' `Σ k (x_j − x_i)` would overflow (NaN
/// values with `Ok` before): refused up front, while the rescaled CGs still solve.
#[test]
fn huge_stiffness_overflow_is_typed_and_other_methods_solve() {
    fn check<T: Real>(k: f64, tol: f64) {
        let case = annulus::<T>(4, 12);
        let g = Graph::new(&case.offsets, &case.targets).unwrap();
        let unit = vec![T::ONE; case.targets.len()];
        let huge = vec![T::from_f64(k); case.targets.len()];
        let mut s1 = vec![0u32; case.n()];
        let mut s2 = vec![0u32; case.n()];
        let sys1 = SpringSystem::new(g, &unit, &case.fixed, &mut s1).unwrap();
        let sysk = SpringSystem::new(g, &huge, &case.fixed, &mut s2).unwrap();
        let x0: Vec<[T; 2]> = field(&case, &mut Lcg(11), Some(0.0));
        let plain = LinearMethod::Cg {
            preconditioner: Preconditioner::None,
        };
        let mut x = x0.clone();
        assert_eq!(
            solve(&sysk, &mut x, plain),
            Err(Error::Overflow { arg: "values" })
        );
        assert_eq!(bits(&x), bits(&x0), "values changed on error");
        let mut want = x0.clone();
        assert!(solve(&sys1, &mut want, plain).unwrap().converged);
        let want: Vec<[f64; 2]> = want.iter().map(|v| v.map(|c| c.to_f64())).collect();
        for (name, m) in methods::<T>().into_iter().filter(|(n, _)| *n != "cg") {
            let mut x = x0.clone();
            let rep = solve(&sysk, &mut x, m).unwrap();
            assert!(rep.converged, "{name}: {rep:?}");
            let err = rel_err(&x, &want);
            assert!(err <= tol, "{name}: relative error {err:e}");
            // Values 1e10 times larger: the sweeps' `Σ k (x_j − x_i)` would overflow and is
            // refused up front; CG rescales and solves.
            let big = scaled(&x0, 1e10);
            let mut x = big.clone();
            if matches!(m, LinearMethod::Cg { .. }) {
                assert!(solve(&sysk, &mut x, m).unwrap().converged, "{name}");
            } else {
                assert_eq!(
                    solve(&sysk, &mut x, m),
                    Err(Error::Overflow { arg: "stiffness" }),
                    "{name}"
                );
                assert_eq!(bits(&x), bits(&big), "{name}: values changed on error");
            }
        }
    }
    check::<f64>(5e306, 1e-7);
    check::<f32>(1e37, 1e-2);
}

/// The angle-inclusion springs (direct Gauss–Seidel and Jacobi, CG, AMG-CG): bit-for-bit
/// scaling by powers of two and constant fields at 1e154 / 1e-300 (f64), 1.5e19 / 1e-30 (f32).
#[test]
fn angle_solves_survive_extreme_scales() {
    fn check<T: Real>(pow2: &[f64], constants: &[f64], tol: f64) {
        let case = annulus::<T>(5, 16);
        let sys = case.angle(0.01);
        let n = case.n();
        let x0: Vec<[T; 2]> = field(&case, &mut Lcg(5), Some(0.0));
        let opts = SolveOptions {
            max_iterations: 5_000,
            ..SolveOptions::default()
        };
        for m in [
            AngleMethod::DirectGaussSeidel,
            AngleMethod::DirectJacobi,
            AngleMethod::Cg,
        ] {
            let mut scratch = vec![[T::ZERO; 2]; 4 * n];
            let mut base = x0.clone();
            let rep = sys.solve_angle(&mut base, m, &opts, &mut scratch).unwrap();
            for &s in pow2 {
                let mut x = scaled(&x0, s);
                let got = sys.solve_angle(&mut x, m, &opts, &mut scratch).unwrap();
                assert_eq!(got.iterations, rep.iterations, "{m:?} at {s:e}");
                assert_eq!(got.converged, rep.converged, "{m:?} at {s:e}");
                assert_eq!(
                    got.residual.to_bits_u64(),
                    rep.residual.to_bits_u64(),
                    "{m:?} at {s:e}"
                );
                assert_eq!(bits(&x), bits(&scaled(&base, s)), "{m:?} at {s:e}");
            }
            if m == AngleMethod::DirectJacobi {
                continue; // block Jacobi is not guaranteed to converge on this operator
            }
            for &c in constants {
                let mut x: Vec<[T; 2]> = (0..n)
                    .map(|i| {
                        let v = if case.fixed[i] != 0 { c } else { 0.0 };
                        [T::from_f64(v), T::from_f64(0.5 * v)]
                    })
                    .collect();
                let rep = sys.solve_angle(&mut x, m, &opts, &mut scratch).unwrap();
                assert!(
                    rep.converged && rep.iterations > 0,
                    "{m:?} at {c:e}: {rep:?}"
                );
                let cv = T::from_f64(c).to_f64();
                let hv = T::from_f64(0.5 * c).to_f64();
                let err = rel_err(&x, &vec![[cv, hv]; n]);
                assert!(err <= tol, "{m:?} at {c:e}: relative error {err:e}");
            }
        }
        // The multigrid-preconditioned CG (hierarchy of the base system).
        let amg_opts = AmgOptions {
            max_coarse: 8,
            ..AmgOptions::default()
        };
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys.base())];
        let sizes = AmgHierarchy::setup_len(sys.base(), &amg_opts, &mut work).unwrap();
        let (mut index, mut values) = (vec![0u32; sizes.index], vec![T::ZERO; sizes.values]);
        let h =
            AmgHierarchy::setup(sys.base(), &amg_opts, &mut work, &mut index, &mut values).unwrap();
        let mut scratch = vec![[T::ZERO; 2]; sys.angle_amg_scratch_len(&h)];
        let mut base = x0.clone();
        let rep = sys
            .solve_angle_amg(&h, &mut base, &opts, &mut scratch)
            .unwrap();
        for &s in pow2 {
            let mut x = scaled(&x0, s);
            let got = sys
                .solve_angle_amg(&h, &mut x, &opts, &mut scratch)
                .unwrap();
            assert_eq!(got.iterations, rep.iterations, "AMG at {s:e}");
            assert_eq!(got.converged, rep.converged, "AMG at {s:e}");
            assert_eq!(
                got.residual.to_bits_u64(),
                rep.residual.to_bits_u64(),
                "AMG at {s:e}"
            );
            assert_eq!(bits(&x), bits(&scaled(&base, s)), "AMG at {s:e}");
        }
        for &c in constants {
            let mut x: Vec<[T; 2]> = (0..n)
                .map(|i| {
                    let v = if case.fixed[i] != 0 { c } else { 0.0 };
                    [T::from_f64(v), T::from_f64(0.5 * v)]
                })
                .collect();
            let rep = sys
                .solve_angle_amg(&h, &mut x, &opts, &mut scratch)
                .unwrap();
            assert!(rep.converged && rep.iterations > 0, "AMG at {c:e}: {rep:?}");
            let cv = T::from_f64(c).to_f64();
            let hv = T::from_f64(0.5 * c).to_f64();
            let err = rel_err(&x, &vec![[cv, hv]; n]);
            assert!(err <= tol, "AMG at {c:e}: relative error {err:e}");
        }
    }
    check::<f64>(&[2f64.powi(512), 2f64.powi(-960)], &[1e154, 1e-300], 1e-7);
    check::<f32>(&[2f64.powi(64), 2f64.powi(-100)], &[1.5e19, 1e-30], 1e-2);
}

/// `deform move --method spring` with a 1e153 wall translation: the inner ring moves by
/// `(s, s/2)`, the outer ring stays. The spring propagation must give `s` times the unit
/// solution (bit for bit at `2^508`), converged with a finite, non-zero initial residual.
#[test]
fn spring_propagation_of_huge_translations() {
    fn run<T: Real>(case: &Case<T, 2>, s: f64) -> (Vec<[T; 2]>, SolveReport<T>) {
        let sys = case.system();
        let n = case.n();
        let mut t: Vec<[T; 2]> = (0..n)
            .map(|i| {
                let p = case.points[i].map(|x| x.to_f64());
                if (p[0] * p[0] + p[1] * p[1]).sqrt() < 1.5 {
                    [T::from_f64(s), T::from_f64(0.5 * s)]
                } else {
                    [T::ZERO; 2]
                }
            })
            .collect();
        let mut q = vec![Quat::<T>::identity(); n];
        let m = LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        };
        let mut scratch = vec![T::ZERO; propagate_spring_scratch_len::<2>(&m, n)];
        let rep = propagate_spring(
            &sys,
            m,
            &SolveOptions::default(),
            &mut t,
            &mut q,
            &mut scratch,
        )
        .unwrap();
        (t, rep)
    }
    fn check<T: Real>(pow2: f64, other: f64, tol: f64) {
        let case = annulus::<T>(5, 16);
        let (unit, rep1) = run(&case, 1.0);
        assert!(rep1.converged);
        let (t, rep) = run(&case, pow2);
        assert_eq!(rep.iterations, rep1.iterations);
        assert_eq!(bits(&t), bits(&scaled(&unit, pow2)));
        let (t, rep) = run(&case, other);
        assert!(rep.converged && rep.iterations > 0, "{rep:?}");
        let want: Vec<[f64; 2]> = unit
            .iter()
            .map(|v| v.map(|c| c.to_f64() * T::from_f64(other).to_f64()))
            .collect();
        let err = rel_err(&t, &want);
        assert!(err <= tol, "relative error {err:e}");
    }
    check::<f64>(2f64.powi(508), 1e153, 1e-8);
    check::<f32>(2f64.powi(62), 1.5e19, 1e-3);
}

/// IDW on coordinates scaled to 1e155 / 1e-170 (f64) and 1e30 / 1e-25 (f32) gives the
/// translations of the unscaled geometry: the weights depend only on distance ratios.
#[test]
fn idw_is_scale_invariant_in_the_coordinates() {
    fn check<T: Real>(scales: &[f64], tol: f64) {
        let case = annulus::<T>(4, 12);
        let n = case.n();
        let boundary: Vec<u32> = (0..n as u32)
            .filter(|&i| case.fixed[i as usize] != 0)
            .collect();
        let mut rng = Lcg(9);
        let t0: Vec<[T; 2]> = (0..n)
            .map(|_| [T::from_f64(rng.next()), T::from_f64(rng.next())])
            .collect();
        let q0 = vec![Quat::<T>::identity(); n];
        for p in [2.0, 3.0] {
            let run = |points: &[[T; 2]]| {
                let mut t = t0.clone();
                let mut q = q0.clone();
                propagate_idw(points, &boundary, T::from_f64(p), &mut t, &mut q).unwrap();
                t
            };
            let want: Vec<[f64; 2]> = run(&case.points)
                .iter()
                .map(|v| v.map(|c| c.to_f64()))
                .collect();
            for &s in scales {
                let got = run(&scaled(&case.points, s));
                assert!(
                    got.iter().flatten().all(|c| c.is_finite()),
                    "p {p} at {s:e}"
                );
                let err = rel_err(&got, &want);
                assert!(err <= tol, "p {p} at {s:e}: relative error {err:e}");
            }
        }
    }
    check::<f64>(&[1e155, 1e300, 1e-170, 1e-300], 1e-12);
    check::<f32>(&[1e30, 1e-25], 1e-5);
}

/// Arclength and stretching of a grid whose coordinates are near 1e200 / 1e-200 (f64),
/// 1e30 / 1e-30 (f32): `s` times (arclength) and equal to (stretching) the unscaled values.
#[test]
fn arclength_and_stretching_are_scale_invariant() {
    fn check<T: Real>(scales: &[f64], tol: f64) {
        let dims = [7, 4, 1];
        let block = Block::new(dims).unwrap();
        let mut rng = Lcg(21);
        let points: Vec<[T; 2]> = (0..7 * 4)
            .map(|p| {
                let (i, j) = ((p % 7) as f64, (p / 7) as f64);
                [
                    T::from_f64(i * (1.0 + 0.1 * i) + 0.05 * rng.next()),
                    T::from_f64(j + 0.05 * rng.next()),
                ]
            })
            .collect();
        let n = points.len();
        let mut s1 = vec![T::ZERO; n];
        let mut r1 = vec![T::ZERO; n];
        arclength(&block, &points, Direction::I, false, &mut s1).unwrap();
        stretching(&block, &points, Direction::I, &mut r1).unwrap();
        for &s in scales {
            let sp = scaled(&points, s);
            let mut a = vec![T::ZERO; n];
            let mut r = vec![T::ZERO; n];
            arclength(&block, &sp, Direction::I, false, &mut a).unwrap();
            stretching(&block, &sp, Direction::I, &mut r).unwrap();
            for p in 0..n {
                let want = s1[p].to_f64() * s;
                let got = a[p].to_f64();
                assert!(
                    got.is_finite() && (got - want).abs() <= tol * want.abs(),
                    "arclength at {s:e}, point {p}: {got:e} vs {want:e}"
                );
                let (got, want) = (r[p].to_f64(), r1[p].to_f64());
                assert!(
                    got.is_finite() && (got - want).abs() <= tol * want,
                    "stretching at {s:e}, point {p}: {got} vs {want}"
                );
            }
        }
    }
    check::<f64>(&[1e200, 1e-200], 1e-14);
    check::<f32>(&[1e30, 1e-30], 1e-5);
}
