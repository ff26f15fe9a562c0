//! Stiffness choices and the reach control on target, in f32 and f64, on the small jittered
//! triangle mesh: wall distances to the bottom row, dual volumes summing to the mesh area,
//! factors normalised by the mean, exactly symmetric scaled stiffness, the reach weight and
//! `limit_reach`; bad input gives typed errors with buffers untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::quaternion::{limit_reach, reach_weight};
use deform_kernel::spring::{
    batina_stiffness, dual_volumes, inverse_volume_factors, scale_stiffness, wall_distance_factors,
    wall_distances,
};
use deform_kernel::{Error, Quat, Real};
use deform_on_target::mesh::{Mesh, DY, N, NE, NT, NX, NY};

fn stiffening<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    // Distances to the bottom row (y = 0): the bottom row itself is at 0, the top row at
    // least (NY − 1)·DY minus the jitter.
    let mut bottom = [0u32; NX];
    for (b, i) in bottom.iter_mut().zip(0..NX) {
        *b = i as u32;
    }
    let mut d = [T::ZERO; N];
    wall_distances(&m.points, &bottom, &mut d).unwrap();
    for (i, &v) in d.iter().enumerate() {
        if i < NX {
            defmt::assert!(v == T::ZERO);
        } else {
            defmt::assert!(v > T::ZERO);
        }
    }
    defmt::assert!(d[N - 1] >= T::from_f64((NY - 1) as f64 * DY - 0.5));
    // Dual volumes add up to the mesh area (sum of |cell areas|).
    let cells = m.cells();
    let mut v = [T::ZERO; N];
    let mut measures = [T::ZERO; NT];
    dual_volumes(&cells, &m.points, &mut v, &mut measures).unwrap();
    let area = measures.iter().fold(T::ZERO, |s, &a| s + a.abs());
    let total = v.iter().fold(T::ZERO, |s, &a| s + a);
    defmt::assert!((total - area).abs() <= T::from_f64(1e-5) * area);
    // Factors, then scaling: exact symmetry kept.
    wall_distance_factors(&mut d, T::ONE).unwrap();
    inverse_volume_factors(&mut v, T::ONE).unwrap();
    defmt::assert!(d
        .iter()
        .chain(v.iter())
        .all(|&f| f.is_finite() && f > T::ZERO));
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    scale_stiffness(&g, &d, k).unwrap();
    scale_stiffness(&g, &v, k).unwrap();
    let offsets = &m.graph_offsets;
    for (i, _, row) in g.rows() {
        for (a, &j) in row.iter().enumerate() {
            let e = offsets[i] as usize + a;
            let back = g.neighbors(j as usize).binary_search(&(i as u32)).unwrap();
            let eb = offsets[j as usize] as usize + back;
            defmt::assert!(k[e] == k[eb]);
        }
    }
    // Bad factor: typed error, stiffness untouched.
    let mut bad = d;
    bad[4] = -T::ONE;
    let mut copy = [T::ZERO; NE];
    copy[..m.used].copy_from_slice(k);
    defmt::assert!(matches!(
        scale_stiffness(&g, &bad, k),
        Err(Error::NonPositive {
            arg: "factors",
            position: 4
        })
    ));
    defmt::assert!(k == &copy[..m.used]);
}

fn reach<T: Real>() {
    defmt::assert!(reach_weight(T::ZERO, T::TWO) == T::ONE);
    defmt::assert!(reach_weight(T::ONE, T::TWO) == T::HALF);
    defmt::assert!(reach_weight(T::TWO, T::TWO) == T::ZERO);
    let q = Quat::from_axis_angle([T::ZERO, T::ZERO, T::ONE], T::from_f64(0.5)).unwrap();
    let distances = [T::ZERO, T::HALF, T::TWO];
    let mut t = [[T::ONE, T::TWO]; 3];
    let mut r = [q; 3];
    limit_reach(&distances, T::ONE, &mut t, &mut r).unwrap();
    defmt::assert!(t[0] == [T::ONE, T::TWO]);
    defmt::assert!(t[1] == [T::HALF, T::ONE]);
    defmt::assert!(t[2] == [T::ZERO, T::ZERO]);
    defmt::assert!(r[2] == Quat::identity());
    let tol = if T::MANTISSA_DIGITS == 24 {
        1e-6
    } else {
        1e-14
    };
    defmt::assert!((r[1].angle() - T::from_f64(0.25)).abs() <= T::from_f64(tol));
    let before = t;
    defmt::assert!(matches!(
        limit_reach(&distances, -T::ONE, &mut t, &mut r),
        Err(Error::InvalidParameter { arg: "radius", .. })
    ));
    defmt::assert!(t == before);
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn stiffness_choices_f64_f32() {
        stiffening::<f64>();
        stiffening::<f32>();
    }

    #[test]
    fn reach_control_f64_f32() {
        reach::<f64>();
        reach::<f32>();
    }
}
