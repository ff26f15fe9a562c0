//! SU2 design variables on target, in f32 and f64: the Hicks–Henne bump peaks at x_max and
//! moves only the chosen side; an unjittered FFD lattice reproduces its affine map; an
//! FFD_CONTROL_POINT and FFD_THICKNESS move exactly their control points; a box minus itself
//! is exactly zero; bad input is a typed error that writes nothing.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::design::ffd::{ffd_displacements_between, ffd_eval, FfdBox};
use deform_kernel::design::hicks_henne::{hicks_henne, hicks_henne_bump, HicksHenne};
use deform_kernel::design::variables::{ffd_control_point, ffd_thickness};
use deform_kernel::{Error, Real};

/// Degree (3, 2, 1) lattice: P_ijk = (i/3, 2 j/2, k − 0.5), flat in SU2's order.
fn lattice<T: Real>() -> [[T; 3]; 24] {
    let mut cp = [[T::ZERO; 3]; 24];
    let mut at = 0;
    for i in 0..4 {
        for j in 0..3 {
            for k in 0..2 {
                cp[at] = [
                    T::from_f64(i as f64 / 3.0),
                    T::from_f64(j as f64),
                    T::from_f64(k as f64 - 0.5),
                ];
                at += 1;
            }
        }
    }
    cp
}

fn hicks_henne_side<T: Real>() {
    let f = T::from_f64;
    let peak = hicks_henne_bump(f(0.3), f(0.3));
    defmt::assert!((peak - T::ONE).abs() <= f(8.0) * T::EPSILON);
    let points = [[f(0.3), f(0.05)], [f(0.3), f(-0.05)], [f(-0.1), f(0.0)]];
    let normals = [[T::ZERO, T::ONE], [T::ZERO, -T::ONE], [T::ZERO, T::ONE]];
    let mut d = [[T::ZERO; 2]; 3];
    let bump = HicksHenne {
        upper: false,
        x_max: f(0.3),
        amplitude: f(0.01),
    };
    hicks_henne(&points, &[0, 1, 2], &normals, bump, &mut d).unwrap();
    defmt::assert!(d[0] == [T::ZERO; 2] && d[2] == [T::ZERO; 2]);
    defmt::assert!((d[1][1] + f(0.01) * peak).abs() <= T::EPSILON);
    let bad = HicksHenne {
        x_max: T::ONE,
        ..bump
    };
    let before = d;
    defmt::assert!(matches!(
        hicks_henne(&points, &[0, 1, 2], &normals, bad, &mut d),
        Err(Error::InvalidParameter { .. })
    ));
    defmt::assert!(d == before);
}

fn ffd_lattice<T: Real>() {
    let f = T::from_f64;
    let cp = lattice::<T>();
    let ffd = FfdBox::new([3, 2, 1], &cp).unwrap();
    let params = [
        [f(0.2), f(0.7), f(0.5)],
        [T::ONE, T::ZERO, T::ONE],
        [f(0.9), f(0.1), f(0.3)],
    ];
    let mut x = [[T::ZERO; 3]; 3];
    ffd_eval(&ffd, &params, &mut x).unwrap();
    for (x, u) in x.iter().zip(&params) {
        defmt::assert!((x[0] - u[0]).abs() <= f(8.0) * T::EPSILON);
        defmt::assert!((x[1] - T::TWO * u[1]).abs() <= f(16.0) * T::EPSILON);
        defmt::assert!((x[2] - (u[2] - T::HALF)).abs() <= f(8.0) * T::EPSILON);
    }
    let mut moved = cp;
    ffd_control_point(
        [3, 2, 1],
        &mut moved,
        [Some(1), None, Some(0)],
        [T::ZERO, f(0.1), T::ZERO],
    )
    .unwrap();
    ffd_thickness([3, 2, 1], &mut moved, 2, 1, f(0.05)).unwrap();
    let changed = cp.iter().zip(&moved).filter(|(a, b)| a != b).count();
    defmt::assert!(changed == 3 + 2);
    let mut d = [[T::ONE; 3]; 3];
    ffd_displacements_between(&ffd, &ffd, &params, &mut d).unwrap();
    defmt::assert!(d == [[T::ZERO; 3]; 3]);
    let b = FfdBox::new([3, 2, 1], &moved).unwrap();
    ffd_displacements_between(&ffd, &b, &params, &mut d).unwrap();
    defmt::assert!(d[0][0] == T::ZERO && d[0][1] > T::ZERO);
    defmt::assert!(matches!(
        FfdBox::new([3, 2, 0], &cp),
        Err(Error::InvalidParameter { .. })
    ));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn hicks_henne_f64() {
        hicks_henne_side::<f64>();
    }

    #[test]
    fn hicks_henne_f32() {
        hicks_henne_side::<f32>();
    }

    #[test]
    fn ffd_f64() {
        ffd_lattice::<f64>();
    }

    #[test]
    fn ffd_f32() {
        ffd_lattice::<f32>();
    }
}
