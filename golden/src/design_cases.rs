//! Golden case of the design-variable derivatives SU2_DOT's projection uses
//! (`design::sensitivity`, `design::twist::ffd_twist_tangent`), so they run on the Cortex-M4F
//! as well: one Hicks–Henne bump's `dJ/da` on both sides, the transposed FFD evaluation in 2D
//! and 3D, the twist's control-point tangent, then one typed error of each.

use deform_kernel::design::sensitivity::{ffd_adjoint, hicks_henne_adjoint};
use deform_kernel::design::twist::{ffd_twist_tangent, FfdTwist};
use deform_kernel::Real;

use crate::{Fnv, XorShift};

/// Surface points of the bump case.
const P: usize = 12;

/// Hicks–Henne on a random chord (x in (0, 1)), FFD adjoints of degree (2, 1) and (1, 1, 2),
/// the twist tangent of a (3, 2, 1) box, and the errors of `x_max` = 1.5 and a short `out`.
pub fn design_adjoints<T: Real>() -> u64 {
    let mut rng = XorShift::new(0xD0E5_16A0);
    let mut h = Fnv::new();
    hicks_henne_case::<T>(&mut rng, &mut h);
    ffd_case::<T, 2>(&mut rng, &mut h, [2, 1]);
    ffd_case::<T, 3>(&mut rng, &mut h, [1, 1, 2]);
    twist_case::<T>(&mut rng, &mut h);
    h.finish()
}

fn hicks_henne_case<T: Real>(rng: &mut XorShift, h: &mut Fnv) {
    let points: [[T; 2]; P] =
        core::array::from_fn(|_| [rng.uniform(0.01, 0.99), rng.uniform(-0.1, 0.1)]);
    let nodes: [u32; P] = core::array::from_fn(|p| p as u32);
    let normals: [[T; 2]; P] =
        core::array::from_fn(|p| [T::ZERO, if p % 3 == 0 { -T::ONE } else { T::ONE }]);
    let dj: [[T; 2]; P] =
        core::array::from_fn(|_| [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)]);
    for (upper, x_max) in [(true, 0.3), (false, 0.7), (true, 1.5)] {
        match hicks_henne_adjoint(&points, &nodes, &normals, upper, T::from_f64(x_max), &dj) {
            Ok(v) => h.real(v),
            Err(e) => h.error(&e),
        }
    }
}

fn ffd_case<T: Real, const D: usize>(rng: &mut XorShift, h: &mut Fnv, degree: [usize; D]) {
    const Q: usize = 9;
    let params: [[T; D]; Q] =
        core::array::from_fn(|_| core::array::from_fn(|_| rng.uniform(0.0, 1.0)));
    let dj: [[T; D]; Q] =
        core::array::from_fn(|_| core::array::from_fn(|_| rng.uniform(-1.0, 1.0)));
    let count: usize = degree.iter().map(|d| d + 1).product();
    let mut out = [[T::from_f64(7.0); D]; 12];
    for len in [count, count - 1] {
        match ffd_adjoint(degree, &params, &dj, out.get_mut(..len).unwrap_or(&mut [])) {
            Ok(()) => out.iter().for_each(|o| h.reals(*o)),
            Err(e) => h.error(&e),
        }
    }
}

fn twist_case<T: Real>(rng: &mut XorShift, h: &mut Fnv) {
    let degree = [3usize, 2, 1];
    let cps: [[T; 3]; 24] = core::array::from_fn(|f| {
        let (i, j, k) = (f / 6, (f / 2) % 3, f % 2);
        let jitter: f64 = 0.05 * rng.uniform::<f64>(-1.0, 1.0);
        [
            T::from_f64(i as f64 / 3.0 + jitter),
            T::from_f64(j as f64 * 0.5),
            T::from_f64(k as f64 * 0.2 - 0.1),
        ]
    });
    let twist = FfdTwist {
        j: 1,
        segment: [
            [T::from_f64(0.3), -T::ONE, T::from_f64(0.02)],
            [T::from_f64(0.3), T::from_f64(2.0), T::from_f64(0.02)],
        ],
        amplitude: T::ZERO,
        ref_length: T::from_f64(1.7),
    };
    let mut out = [[T::from_f64(9.0); 3]; 24];
    for len in [24, 23] {
        match ffd_twist_tangent(
            degree,
            &cps,
            twist,
            &[0],
            &[],
            out.get_mut(..len).unwrap_or(&mut []),
        ) {
            Ok(()) => out.iter().for_each(|o| h.reals(*o)),
            Err(e) => h.error(&e),
        }
    }
}
