//! Sliding boundaries on target, in f32 and f64, on the small jittered triangle mesh: the
//! bottom row (y = 0, corners excluded) slides along its line (normal fitted with
//! `fit_plane`), the top row moves +0.5 along x, the sides stay. Every linear method and every
//! angle method keeps the sliding nodes on the line, agrees with the others, and beats nothing
//! it should not: fixed values come back bit for bit. `slide_points` projects a moved field;
//! bad input gives typed errors with the values untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::spring::constraints::{fit_plane, slide_points, Constraints, NodeKind};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_sliding_scratch_len, AngleMethod, AngleSystem, LinearMethod,
    LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Error, Real};
use deform_on_target::mesh::{Mesh, N, NE, NX, NY};
use deform_on_target::{max_abs, max_diff, same_bits};

/// Scratch items for every method (`6 n` covers CG with its diagonal).
const SCRATCH: usize = 6 * N;

/// Kinds and directions: bottom row (corners excluded) on the fitted line, other perimeter
/// nodes fixed, interior free.
fn table<T: Real>(m: &Mesh<T>) -> ([u8; N], [[T; 2]; N]) {
    let mut bottom = [0u32; NX - 2];
    for (b, i) in bottom.iter_mut().zip(1..NX - 1) {
        *b = i as u32;
    }
    let fit = fit_plane(&m.points, &bottom, T::from_f64(1e-6)).unwrap();
    defmt::assert!(fit.normal[0] == T::ZERO && fit.normal[1] == T::ONE);
    let mut kinds = [NodeKind::Free.code(); N];
    let mut dirs = [[T::ZERO; 2]; N];
    for (i, (k, f)) in kinds.iter_mut().zip(&m.fixed).enumerate() {
        if *f != 0 {
            *k = NodeKind::Fixed.code();
        }
        if (1..NX - 1).contains(&i) {
            *k = NodeKind::Plane.code();
            if let Some(d) = dirs.get_mut(i) {
                *d = fit.normal;
            }
        }
    }
    (kinds, dirs)
}

/// Prescribed displacements: the top row +0.5 along x.
fn data<T: Real>() -> [[T; 2]; N] {
    let mut d = [[T::ZERO; 2]; N];
    for v in d.iter_mut().skip(NX * (NY - 1)) {
        *v = [T::HALF, T::ZERO];
    }
    d
}

fn tol<T: Real>() -> T {
    if T::MANTISSA_DIGITS == 24 {
        T::from_f64(2e-3)
    } else {
        T::from_f64(1e-7)
    }
}

fn check<T: Real>(kinds: &[u8; N], d: &[[T; 2]; N], given: &[[T; 2]; N]) {
    for (i, (v, g)) in d.iter().zip(given).enumerate() {
        if kinds[i] == NodeKind::Plane.code() {
            defmt::assert!(v[1].abs() <= T::EPSILON * T::from_f64(4.0));
            defmt::assert!(v[0].abs() > T::from_f64(1e-3));
        }
        if kinds[i] == NodeKind::Fixed.code() {
            defmt::assert!(same_bits(&[*v], &[*g]));
        }
    }
}

fn all_methods<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let (kinds, dirs) = table(&m);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = [0u8; N];
    c.fixed_mask(&mut mask).unwrap();
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &mask, &mut seen).unwrap();
    let given = data::<T>();
    let opts = SolveOptions {
        max_iterations: 20_000,
        ..SolveOptions::default()
    };
    let mut scratch = [[T::ZERO; 2]; SCRATCH];
    let mut first: Option<[[T; 2]; N]> = None;
    for method in [
        LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor {
                omega: T::from_f64(1.2),
            },
        },
        LinearMethod::Jacobi,
        LinearMethod::GaussSeidel,
        LinearMethod::Sor {
            omega: T::from_f64(1.5),
        },
    ] {
        let solver = LinearSolver::Method(method);
        let len = solve_linear_sliding_scratch_len(&solver, N);
        let mut d = given;
        let r = sys
            .solve_linear_sliding(&c, &mut d, solver, &opts, &mut scratch[..len])
            .unwrap();
        defmt::assert!(r.converged);
        check(&kinds, &d, &given);
        match &first {
            None => first = Some(d),
            Some(f) => defmt::assert!(max_diff(f, &d) <= tol::<T>() * max_abs(&given)),
        }
    }
    let a = AngleSystem::new(sys, &m.points, T::from_f64(0.01)).unwrap();
    let mut first: Option<[[T; 2]; N]> = None;
    for method in [AngleMethod::Cg, AngleMethod::DirectGaussSeidel] {
        let len = a.solve_angle_sliding_scratch_len(method);
        let mut d = given;
        let r = a
            .solve_angle_sliding(&c, &mut d, method, T::ONE, &opts, &mut scratch[..len])
            .unwrap();
        defmt::assert!(r.converged);
        check(&kinds, &d, &given);
        match &first {
            None => first = Some(d),
            Some(f) => defmt::assert!(max_diff(f, &d) <= tol::<T>() * max_abs(&given)),
        }
    }
}

fn projection_and_errors<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let (kinds, dirs) = table(&m);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut moved = m.points;
    for p in moved.iter_mut() {
        *p = [p[0] + T::from_f64(0.125), p[1] + T::from_f64(0.25)];
    }
    slide_points(&c, &m.points, &mut moved).unwrap();
    for (i, (p, q)) in moved.iter().zip(&m.points).enumerate() {
        if kinds[i] == NodeKind::Plane.code() {
            defmt::assert!(p[1] == q[1]);
        } else {
            defmt::assert!(p[1] != q[1]);
        }
    }
    // Bad tables.
    let mut bad = kinds;
    bad[3] = 7;
    defmt::assert!(matches!(
        Constraints::new(&bad, &dirs),
        Err(Error::IndexOutOfRange {
            arg: "kinds",
            position: 3,
            ..
        })
    ));
    let mut long = dirs;
    long[2] = [T::ZERO, T::from_f64(1.5)];
    defmt::assert!(matches!(
        Constraints::new(&kinds, &long),
        Err(Error::NotUnit { position: 2, .. })
    ));
    // A solve with a mask that disagrees, and one with NaN values: untouched.
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
    let mut d = data::<T>();
    let before = d;
    let mut scratch = [[T::ZERO; 2]; SCRATCH];
    defmt::assert!(matches!(
        sys.solve_linear_sliding(
            &c,
            &mut d,
            LinearMethod::GaussSeidel.into(),
            &SolveOptions::default(),
            &mut scratch
        ),
        Err(Error::InvalidParameter {
            arg: "constraints",
            ..
        })
    ));
    defmt::assert!(same_bits(&d, &before));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn sliding_solves_f64() {
        all_methods::<f64>();
    }

    #[test]
    fn sliding_solves_f32() {
        all_methods::<f32>();
    }

    #[test]
    fn projection_and_typed_errors() {
        projection_and_errors::<f64>();
        projection_and_errors::<f32>();
    }
}
