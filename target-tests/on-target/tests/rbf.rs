//! RBF deformation on target, in f32 and f64, on the small jittered triangle mesh (its
//! perimeter the boundary, the bottom row turned): Wendland C2 and thin-plate splines exact
//! at the centres, thin-plate splines reproducing a rigid motion of the whole perimeter, a
//! greedy fit with the wall correction writing the wall exactly, and typed errors with the
//! output untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::{Error, Real};
use deform_on_target::mesh::{turned_bottom_row, Mesh, N, NB};

/// Room for the largest workspace below (thin-plate splines over all `NB` nodes).
const SCRATCH: usize = (NB + 3) * (NB + 3) + 2 * (NB + 3) + 2 * NB;
const INDEX: usize = 8 * NB + 16;

/// The perimeter nodes and their motion to the turned bottom row.
fn perimeter<T: Real>(m: &Mesh<T>) -> ([u32; NB], [[T; 2]; NB]) {
    let deformed = turned_bottom_row(m, 5);
    let mut motion = [[T::ZERO; 2]; NB];
    for (k, (d, &b)) in motion.iter_mut().zip(m.boundary.iter()).enumerate() {
        let p = m.points[b as usize];
        *d = [deformed[k][0] - p[0], deformed[k][1] - p[1]];
    }
    (m.boundary, motion)
}

fn run<T: Real>(
    m: &Mesh<T>,
    boundary: &[u32],
    motion: &[[T; 2]],
    o: &RbfOptions<T>,
    out: &mut [[T; 2]; N],
) -> Result<usize, Error> {
    defmt::assert!(rbf_scratch_len::<T, 2>(boundary.len(), o) <= SCRATCH);
    defmt::assert!(rbf_index_len::<T, 2>(boundary.len(), o) <= INDEX);
    let mut scratch = [T::ZERO; SCRATCH];
    let mut index = [0u32; INDEX];
    rbf_deform(
        &m.points,
        boundary,
        motion,
        o,
        &mut index,
        &mut scratch,
        out,
    )
    .map(|r| r.centres)
}

fn exact_at_centres<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let (boundary, motion) = perimeter(&m);
    let tol = T::from_f64(if T::MANTISSA_DIGITS == 24 {
        1e-3
    } else {
        1e-10
    });
    for kernel in [
        RbfKernel::Wendland {
            radius: T::from_f64(6.0),
        },
        RbfKernel::ThinPlate,
    ] {
        let o = RbfOptions {
            kernel,
            tolerance: T::ZERO,
            max_centres: NB,
            correction_radius: T::ZERO,
        };
        let mut out = [[T::ZERO; 2]; N];
        defmt::assert_eq!(run(&m, &boundary, &motion, &o, &mut out), Ok(NB));
        for (&b, d) in boundary.iter().zip(&motion) {
            let e = out[b as usize];
            defmt::assert!((e[0] - d[0]).abs() <= tol && (e[1] - d[1]).abs() <= tol);
        }
    }
}

fn thin_plate_is_rigid<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let (s, c) = T::from_f64(0.3).sin_cos();
    let moved = |p: [T; 2]| {
        [
            c * p[0] - s * p[1] + T::HALF - p[0],
            s * p[0] + c * p[1] - p[1],
        ]
    };
    let mut motion = [[T::ZERO; 2]; NB];
    for (d, &b) in motion.iter_mut().zip(m.boundary.iter()) {
        *d = moved(m.points[b as usize]);
    }
    let o = RbfOptions {
        kernel: RbfKernel::ThinPlate,
        tolerance: T::ZERO,
        max_centres: NB,
        correction_radius: T::ZERO,
    };
    let mut out = [[T::ZERO; 2]; N];
    run(&m, &m.boundary, &motion, &o, &mut out).unwrap();
    let tol = T::from_f64(if T::MANTISSA_DIGITS == 24 {
        1e-3
    } else {
        1e-11
    });
    for (p, e) in m.points.iter().zip(&out) {
        let x = moved(*p);
        defmt::assert!((e[0] - x[0]).abs() <= tol && (e[1] - x[1]).abs() <= tol);
    }
}

fn greedy_keeps_the_wall<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let (boundary, motion) = perimeter(&m);
    let o = RbfOptions {
        kernel: RbfKernel::Wendland {
            radius: T::from_f64(6.0),
        },
        tolerance: T::from_f64(0.05),
        max_centres: NB,
        correction_radius: T::ONE,
    };
    let mut out = [[T::ZERO; 2]; N];
    let centres = run(&m, &boundary, &motion, &o, &mut out).unwrap();
    defmt::assert!(centres > 0 && centres < NB);
    for (&b, d) in boundary.iter().zip(&motion) {
        defmt::assert!(out[b as usize] == *d);
    }
    // Bad input: typed errors, nothing written.
    let mut before = [[T::from_f64(7.0); 2]; N];
    let bad = RbfOptions {
        max_centres: 0,
        ..o
    };
    defmt::assert!(matches!(
        run(&m, &boundary, &motion, &bad, &mut before),
        Err(Error::InvalidParameter {
            arg: "options.max_centres",
            ..
        })
    ));
    let mut twice = boundary;
    twice[3] = twice[1];
    defmt::assert!(matches!(
        run(&m, &twice, &motion, &o, &mut before),
        Err(Error::DuplicateNode {
            arg: "boundary",
            position: 3,
            ..
        })
    ));
    defmt::assert!(before.iter().all(|p| *p == [T::from_f64(7.0); 2]));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn rbf_exact_at_centres_f64_f32() {
        exact_at_centres::<f64>();
        exact_at_centres::<f32>();
    }

    #[test]
    fn rbf_thin_plate_rigid_f64_f32() {
        thin_plate_is_rigid::<f64>();
        thin_plate_is_rigid::<f32>();
    }

    #[test]
    fn rbf_greedy_wall_exact_f64_f32() {
        greedy_keeps_the_wall::<f64>();
        greedy_keeps_the_wall::<f32>();
    }
}
