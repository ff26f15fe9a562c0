//! The spring analogy on target, in f32 and f64, on a small jittered triangle mesh (30 nodes,
//! perimeter fixed): every linear method (Jacobi, Gauss–Seidel, SOR, CG with each
//! preconditioner) and every angle method (direct Gauss–Seidel, direct Jacobi, CG, and the
//! multigrid-preconditioned CG, with golden bits) converges, obeys the maximum principle
//! (linear springs), agrees with the others within the solver tolerance, and the sweeps
//! compose into the whole solves. Bad input gives typed errors.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, AmgHierarchy, AmgOptions, AngleMethod, AngleSystem,
    LinearMethod, Preconditioner, SolveOptions, SpringSystem, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::{Error, Quat, Real};
use deform_on_target::mesh::{Mesh, N, NE, NX};
use deform_on_target::{max_abs, max_diff, precision, same_bits};

/// Boundary data: the bottom row turns by 20° about its midpoint, the rest of the perimeter
/// stays; zero inside (the initial guess).
fn boundary_values<T: Real>(m: &Mesh<T>) -> [[T; 2]; N] {
    let q = Quat::from_rotation_z(T::from_f64(20f64.to_radians()));
    let c = [T::from_f64((NX - 1) as f64 * 0.5), T::ZERO];
    let mut d = [[T::ZERO; 2]; N];
    for (p, di) in m.points.iter().zip(d.iter_mut()).take(NX) {
        let r = q.rotate_2d([p[0] - c[0], p[1] - c[1]]);
        *di = [r[0] + c[0] - p[0], r[1] + c[1] - p[1]];
    }
    d
}

/// Runs `f` on the Batina system of the mesh (stiffness `1/|e|`, perimeter fixed).
fn with_system<T: Real>(m: &Mesh<T>, f: impl FnOnce(&SpringSystem<'_, T>)) {
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
    f(&sys);
}

/// Agreement tolerance between two converged solutions, relative to the data size: the
/// residual tolerance (1e-10 / 1.2e-5) times a condition-number allowance.
fn agree_tol<T: Real>() -> T {
    if T::MANTISSA_DIGITS == 24 {
        T::from_f64(2e-3)
    } else {
        T::from_f64(1e-7)
    }
}

fn linear_methods<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    with_system(&m, |sys| {
        let data = boundary_values(&m);
        let scale = max_abs(&data);
        let (lo, hi) = data
            .iter()
            .fold(([T::MAX; 2], [-T::MAX; 2]), |(lo, hi), v| {
                (
                    [lo[0].min(v[0]), lo[1].min(v[1])],
                    [hi[0].max(v[0]), hi[1].max(v[1])],
                )
            });
        let omega = T::from_f64(1.2);
        let methods = [
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega },
            },
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
            LinearMethod::Cg {
                preconditioner: Preconditioner::None,
            },
            LinearMethod::Jacobi,
            LinearMethod::GaussSeidel,
            LinearMethod::Sor {
                omega: T::from_f64(1.5),
            },
        ];
        let opts = SolveOptions {
            max_iterations: 5000,
            ..SolveOptions::default()
        };
        let mut reference = data;
        for (n, method) in methods.into_iter().enumerate() {
            let mut values = data;
            let mut scratch = [[T::ZERO; 2]; 5 * N];
            let len = solve_linear_scratch_len(&method, N);
            let r = sys
                .solve_linear(&mut values, method, &opts, &mut scratch[..len])
                .unwrap();
            defmt::info!(
                "{=str} linear method {=usize}: {=usize} iterations, residual {=f64}",
                precision::<T>(),
                n,
                r.iterations,
                r.residual.to_f64()
            );
            defmt::assert!(r.converged);
            defmt::assert!(r.residual <= opts.residual_tol);
            let true_res = sys.relative_residual(&values).unwrap();
            defmt::assert!(true_res == r.residual);
            // Fixed nodes keep their bits; free nodes obey the maximum principle.
            for ((v, d), &f) in values.iter().zip(&data).zip(&m.fixed) {
                if f != 0 {
                    defmt::assert!(same_bits(&[*v], &[*d]));
                } else {
                    let slack = scale * T::EPSILON * T::from_f64(64.0);
                    for c in 0..2 {
                        defmt::assert!(v[c] >= lo[c] - slack && v[c] <= hi[c] + slack);
                    }
                }
            }
            if n == 0 {
                reference = values;
            } else {
                let d = max_diff(&values, &reference);
                defmt::assert!(d <= agree_tol::<T>() * scale, "method {=usize} differs", n);
            }
        }
    });
}

fn sweeps<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    with_system(&m, |sys| {
        let data = boundary_values(&m);
        // K whole-range Jacobi sweeps == the Jacobi solve capped at K iterations, bit for bit.
        const K: usize = 25;
        let mut a = data;
        let mut b = [[T::ZERO; 2]; N];
        for _ in 0..K {
            let s = sys.jacobi_sweep(0..N, &a, &mut b).unwrap();
            defmt::assert!(s.max_change >= T::ZERO && s.residual_sq >= T::ZERO);
            a = b;
        }
        let mut solved = data;
        let mut scratch = [[T::ZERO; 2]; N];
        let opts = SolveOptions {
            max_iterations: K,
            residual_tol: T::ZERO,
            update_tol: T::ZERO,
        };
        let r = sys
            .solve_linear(&mut solved, LinearMethod::Jacobi, &opts, &mut scratch)
            .unwrap();
        defmt::assert_eq!(r.iterations, K);
        defmt::assert!(same_bits(&a, &solved));
        // A Jacobi sweep split into two ranges equals the whole-range sweep.
        let mut whole = [[T::ZERO; 2]; N];
        let mut split = [[T::ZERO; 2]; N];
        sys.jacobi_sweep(0..N, &data, &mut whole).unwrap();
        sys.jacobi_sweep(0..N / 2, &data, &mut split).unwrap();
        sys.jacobi_sweep(N / 2..N, &data, &mut split).unwrap();
        defmt::assert!(same_bits(&whole, &split));
        // K SOR sweeps (ω = 1.5) == the SOR solve capped at K iterations.
        let omega = T::from_f64(1.5);
        let mut a = data;
        let mut last = T::INFINITY;
        for _ in 0..K {
            last = sys.sor_sweep(0..N, &mut a, omega).unwrap().max_change;
        }
        defmt::assert!(last < T::from_f64(1e-3));
        let mut solved = data;
        sys.solve_linear(&mut solved, LinearMethod::Sor { omega }, &opts, &mut [])
            .unwrap();
        defmt::assert!(same_bits(&a, &solved));
    });
}

fn angle_methods<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    with_system(&m, |sys| {
        let asys = AngleSystem::new(*sys, &m.points, T::from_f64(DEFAULT_ANGLE_EPSILON)).unwrap();
        let data = boundary_values(&m);
        let scale = max_abs(&data);
        let opts = SolveOptions {
            max_iterations: 5000,
            ..SolveOptions::default()
        };
        let mut reference = data;
        for (n, method) in [
            AngleMethod::DirectGaussSeidel,
            AngleMethod::Cg,
            AngleMethod::DirectJacobi,
        ]
        .into_iter()
        .enumerate()
        {
            let mut values = data;
            let mut scratch = [[T::ZERO; 2]; 4 * N];
            let len = asys.angle_scratch_len(method);
            let r = asys
                .solve_angle(&mut values, method, &opts, &mut scratch[..len])
                .unwrap();
            defmt::info!(
                "{=str} angle method {=usize}: {=usize} iterations, residual {=f64}, converged {=bool}",
                precision::<T>(),
                n,
                r.iterations,
                r.residual.to_f64(),
                r.converged
            );
            defmt::assert!(r.residual.is_finite());
            for ((v, d), &f) in values.iter().zip(&data).zip(&m.fixed) {
                if f != 0 {
                    defmt::assert!(same_bits(&[*v], &[*d]));
                }
            }
            if method == AngleMethod::DirectJacobi && !r.converged {
                // Block Jacobi is not guaranteed to converge: reported, never hidden.
                continue;
            }
            defmt::assert!(r.converged);
            if n == 0 {
                reference = values;
            } else {
                let d = max_diff(&values, &reference);
                defmt::assert!(d <= agree_tol::<T>() * scale, "angle method {=usize}", n);
            }
        }
        // The angle sweeps reduce the change from sweep to sweep.
        let mut a = data;
        let first = asys
            .angle_gauss_seidel_sweep(0..N, &mut a)
            .unwrap()
            .max_change;
        let mut last = first;
        for _ in 0..30 {
            last = asys
                .angle_gauss_seidel_sweep(0..N, &mut a)
                .unwrap()
                .max_change;
        }
        defmt::assert!(first > T::ZERO && last < first);
        let mut b = [[T::ZERO; 2]; N];
        let s = asys.angle_jacobi_sweep(0..N, &a, &mut b).unwrap();
        defmt::assert!(s.max_change <= first);
    });
}

/// The angle-inclusion CG preconditioned by the scalar multigrid V-cycle
/// (`solve_angle_amg`): converges, keeps the fixed bits, agrees with the block-Jacobi CG, needs
/// no more iterations than it; a short scratch or a hierarchy of another system is a typed
/// error that leaves the values alone; a uniform translation comes back bit for bit.
fn angle_amg<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    with_system(&m, |sys| {
        let opts = AmgOptions {
            max_coarse: 4,
            ..AmgOptions::default()
        };
        let mut work = [0u32; 4 * (N + NE) + 64];
        let mut index = [0u32; 2048];
        let mut vals = [T::ZERO; 1024];
        let h = AmgHierarchy::setup(sys, &opts, &mut work, &mut index, &mut vals).unwrap();
        defmt::assert!(h.levels() >= 2);
        let asys = AngleSystem::new(*sys, &m.points, T::from_f64(DEFAULT_ANGLE_EPSILON)).unwrap();
        let data = boundary_values(&m);
        let scale = max_abs(&data);
        let stop = SolveOptions {
            max_iterations: 500,
            ..SolveOptions::default()
        };
        let len = asys.angle_amg_scratch_len(&h);
        defmt::assert_eq!(len, 5 * N + 3 * h.coarse_unknowns());
        let mut scratch = [[T::ZERO; 2]; 8 * N];
        let mut values = data;
        defmt::assert!(matches!(
            asys.solve_angle_amg(&h, &mut values, &stop, &mut scratch[..len - 1]),
            Err(Error::BufferTooSmall { .. })
        ));
        defmt::assert!(same_bits(&values, &data));
        let r = asys
            .solve_angle_amg(&h, &mut values, &stop, &mut scratch[..len])
            .unwrap();
        let mut cg = data;
        let rc = asys
            .solve_angle(&mut cg, AngleMethod::Cg, &stop, &mut scratch[..4 * N])
            .unwrap();
        defmt::info!(
            "{=str} angle AMG-CG: {=usize} iterations (block-Jacobi CG {=usize}), residual {=f64}",
            precision::<T>(),
            r.iterations,
            rc.iterations,
            r.residual.to_f64()
        );
        defmt::assert!(r.converged && rc.converged);
        defmt::assert!(r.iterations <= rc.iterations);
        for ((v, d), &f) in values.iter().zip(&data).zip(&m.fixed) {
            if f != 0 {
                defmt::assert!(same_bits(&[*v], &[*d]));
            }
        }
        defmt::assert!(max_diff(&values, &cg) <= agree_tol::<T>() * scale);
        // A uniform translation is a solution: 0 iterations, the same bits.
        let t = [T::from_f64(0.3125), T::from_f64(-1.75)];
        let mut tv = [t; N];
        let r = asys
            .solve_angle_amg(&h, &mut tv, &stop, &mut scratch[..len])
            .unwrap();
        defmt::assert!(r.converged && r.iterations == 0);
        defmt::assert!(same_bits(&tv, &[t; N]));
    });
    // A hierarchy of another system (a 3-node path) is refused.
    let offsets: [u32; 4] = [0, 1, 3, 4];
    let targets: [u32; 4] = [1, 0, 2, 1];
    let g = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    let k = [T::ONE; 4];
    let fixed = [1u8, 0, 1];
    let mut seen = [0u32; 3];
    let small = SpringSystem::new(g, &k, &fixed, &mut seen).unwrap();
    let mut work = [0u32; 4 * (3 + 4) + 64];
    let mut index = [0u32; 64];
    let mut vals = [T::ZERO; 64];
    let other = AmgHierarchy::setup(
        &small,
        &AmgOptions::default(),
        &mut work,
        &mut index,
        &mut vals,
    )
    .unwrap();
    with_system(&m, |sys| {
        let asys = AngleSystem::new(*sys, &m.points, T::from_f64(DEFAULT_ANGLE_EPSILON)).unwrap();
        let data = boundary_values(&m);
        let mut values = data;
        let mut scratch = [[T::ZERO; 2]; 8 * N];
        defmt::assert!(matches!(
            asys.solve_angle_amg(&other, &mut values, &SolveOptions::default(), &mut scratch),
            Err(Error::LengthMismatch {
                arg: "hierarchy",
                ..
            })
        ));
        defmt::assert!(same_bits(&values, &data));
    });
}

/// The golden case of the AMG angle solve (`deform-golden`'s `spring_angle_amg`, on the golden
/// crate's 42-node mesh) has the host's bits here too (also checked with every other case by
/// the `golden` test binary).
fn angle_amg_golden_bits() {
    let case = deform_golden::CASES
        .iter()
        .find(|c| c.name == "spring_angle_amg")
        .unwrap();
    let got = case.run();
    defmt::info!(
        "golden spring_angle_amg: f64 {=u64:#x}, f32 {=u64:#x}",
        got.got_f64,
        got.got_f32
    );
    defmt::assert!(case.matches(&got));
}

fn uniform_translation_is_exact<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    with_system(&m, |sys| {
        let t = [T::from_f64(0.3125), T::from_f64(-1.75)];
        let data = [t; N];
        let mut values = data;
        let mut scratch = [[T::ZERO; 2]; 5 * N];
        let r = sys
            .solve_linear(
                &mut values,
                LinearMethod::Jacobi,
                &SolveOptions::default(),
                &mut scratch[..N],
            )
            .unwrap();
        defmt::assert!(r.converged);
        defmt::assert!(same_bits(&values, &data));
        let asys = AngleSystem::new(*sys, &m.points, T::from_f64(DEFAULT_ANGLE_EPSILON)).unwrap();
        let r = asys
            .solve_angle(
                &mut values,
                AngleMethod::DirectGaussSeidel,
                &SolveOptions::default(),
                &mut [],
            )
            .unwrap();
        defmt::assert!(r.converged);
        defmt::assert!(same_bits(&values, &data));
    });
}

fn typed_errors<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let g = m.graph();
    let mut k = [T::ONE; NE];
    let k = &mut k[..m.used];
    // Zero-length edge.
    let mut pts = m.points;
    pts[1] = pts[0];
    let before = [T::ONE; NE];
    defmt::assert!(matches!(
        batina_stiffness(&g, &pts, T::ONE, k),
        Err(Error::ZeroLengthEdge { .. })
    ));
    defmt::assert!(k.iter().zip(&before).all(|(a, b)| a == b));
    defmt::assert!(matches!(
        batina_stiffness(&g, &m.points, -T::ONE, k),
        Err(Error::InvalidParameter { .. })
    ));
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let mut seen = [0u32; N];
    // No fixed node: unanchored.
    let free = [0u8; N];
    defmt::assert!(matches!(
        SpringSystem::new(g, k, &free, &mut seen),
        Err(Error::Unanchored { node: 0 })
    ));
    // Asymmetric stiffness.
    let mut bad = [T::ONE; NE];
    bad[..m.used].copy_from_slice(k);
    bad[0] += T::ONE;
    defmt::assert!(matches!(
        SpringSystem::new(g, &bad[..m.used], &m.fixed, &mut seen),
        Err(Error::NotSymmetric { .. })
    ));
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
    let mut values = [[T::ZERO; 2]; N];
    let opts = SolveOptions::default();
    defmt::assert!(matches!(
        sys.solve_linear(
            &mut values,
            LinearMethod::Sor { omega: T::TWO },
            &opts,
            &mut []
        ),
        Err(Error::InvalidParameter { arg: "omega", .. })
    ));
    defmt::assert!(matches!(
        sys.solve_linear(&mut values, LinearMethod::Jacobi, &opts, &mut []),
        Err(Error::BufferTooSmall { .. })
    ));
    defmt::assert!(matches!(
        sys.solve_linear(
            &mut values[..N - 1],
            LinearMethod::GaussSeidel,
            &opts,
            &mut []
        ),
        Err(Error::LengthMismatch { .. })
    ));
    values[3][1] = T::INFINITY;
    defmt::assert!(matches!(
        sys.solve_linear(&mut values, LinearMethod::GaussSeidel, &opts, &mut []),
        Err(Error::NonFinite { position: 3, .. })
    ));
    defmt::assert!(matches!(
        AngleSystem::new(sys, &m.points, -T::ONE),
        Err(Error::InvalidParameter { .. })
    ));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn linear_methods_f64() {
        linear_methods::<f64>();
    }

    #[test]
    fn linear_methods_f32() {
        linear_methods::<f32>();
    }

    #[test]
    fn sweeps_compose_into_solves_f64() {
        sweeps::<f64>();
    }

    #[test]
    fn sweeps_compose_into_solves_f32() {
        sweeps::<f32>();
    }

    #[test]
    fn angle_methods_f64() {
        angle_methods::<f64>();
    }

    #[test]
    fn angle_methods_f32() {
        angle_methods::<f32>();
    }

    #[test]
    fn angle_amg_f64() {
        angle_amg::<f64>();
    }

    #[test]
    fn angle_amg_f32() {
        angle_amg::<f32>();
    }

    #[test]
    fn angle_amg_has_the_golden_bits() {
        angle_amg_golden_bits();
    }

    #[test]
    fn uniform_translation_is_a_bit_exact_fixed_point() {
        uniform_translation_is_exact::<f64>();
        uniform_translation_is_exact::<f32>();
    }

    #[test]
    fn typed_errors_f64_f32() {
        typed_errors::<f64>();
        typed_errors::<f32>();
    }
}
