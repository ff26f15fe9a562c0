//! `limit_reach` (issue 15 item 4, the decay control): the weight is 1 at the moving boundary,
//! falls smoothly to 0 at the radius and stays 0 beyond; translations are scaled by it and
//! rotations slerped toward the identity; bad input changes nothing.

use deform_kernel::quaternion::{limit_reach, reach_weight};
use deform_kernel::{Error, Quat};

#[test]
fn the_weight_falls_smoothly_from_one_to_zero() {
    assert_eq!(reach_weight(0.0f64, 2.0), 1.0);
    assert_eq!(reach_weight(2.0f64, 2.0), 0.0);
    assert_eq!(reach_weight(7.0f64, 2.0), 0.0);
    assert_eq!(reach_weight(1.0f64, 2.0), 0.5);
    let mut last = 1.0;
    for k in 0..=200 {
        let d = 2.0 * k as f64 / 200.0;
        let w = reach_weight(d, 2.0);
        assert!(w <= last && (0.0..=1.0).contains(&w), "{d}: {w}");
        // Independent: 1 − smoothstep.
        let r: f64 = d / 2.0;
        let expect = 1.0 - r * r * (3.0 - 2.0 * r);
        assert!((w - expect).abs() <= 1e-15, "{d}");
        last = w;
    }
    // Zero slope at both ends: the finite difference vanishes like h.
    let h = 1e-6;
    assert!((1.0 - reach_weight(h, 1.0)) < 1e-11);
    assert!(reach_weight(1.0 - h, 1.0) < 1e-11);
    assert_eq!(reach_weight(0.5f32, 1.0), 0.5);
}

#[test]
fn motion_is_kept_at_the_boundary_faded_in_between_and_gone_beyond() {
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.6f64)
        .unwrap()
        .scale(3.0); // not unit
    let distances = [0.0, 0.5, 1.0, 4.0];
    let mut t = [[2.0, -4.0]; 4];
    let mut r = [q; 4];
    limit_reach(&distances, 1.0, &mut t, &mut r).unwrap();
    // d = 0: full motion (rotation normalised).
    assert_eq!(t[0], [2.0, -4.0]);
    assert!((r[0].angle() - 0.6).abs() < 1e-15);
    // d = radius / 2: half the translation, half the angle.
    assert_eq!(t[1], [1.0, -2.0]);
    assert!((r[1].angle() - 0.3).abs() < 1e-15, "{}", r[1].angle());
    // d ≥ radius: no motion at all.
    for k in 2..4 {
        assert_eq!(t[k], [0.0, 0.0]);
        assert_eq!(r[k].to_array(), [1.0, 0.0, 0.0, 0.0]);
    }
    // f32 too.
    let mut t32 = [[1.0f32, 1.0]];
    let mut r32 = [Quat::<f32>::identity()];
    limit_reach(&[0.25f32], 0.5, &mut t32, &mut r32).unwrap();
    assert_eq!(t32[0], [0.5, 0.5]);
}

#[test]
fn bad_input_changes_nothing() {
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.2f64).unwrap();
    let t0 = [[1.0, 2.0, 3.0]; 3];
    let r0 = [q; 3];
    let check = |d: &[f64], radius: f64, r: &[Quat<f64>], expect: fn(&Error) -> bool| {
        let mut t = t0;
        let mut rr = [r[0], r[1], r[2]];
        let e = limit_reach(d, radius, &mut t, &mut rr).unwrap_err();
        assert!(expect(&e), "{e:?}");
        assert_eq!(t, t0);
        assert_eq!(
            rr.map(|x| x.to_array()),
            [r[0], r[1], r[2]].map(|x| x.to_array())
        );
    };
    check(&[0.0, 1.0, 2.0], 0.0, &r0, |e| {
        matches!(e, Error::InvalidParameter { arg: "radius", .. })
    });
    check(&[0.0, 1.0, 2.0], f64::NAN, &r0, |e| {
        matches!(e, Error::InvalidParameter { .. })
    });
    check(&[0.0, -1.0, 2.0], 1.0, &r0, |e| {
        matches!(
            e,
            Error::NonPositive {
                arg: "distances",
                position: 1
            }
        )
    });
    check(&[0.0, 1.0, f64::INFINITY], 1.0, &r0, |e| {
        matches!(
            e,
            Error::NonFinite {
                arg: "distances",
                position: 2
            }
        )
    });
    let zero = [q, Quat::from_array([0.0; 4]), q];
    check(&[0.0, 1.0, 2.0], 1.0, &zero, |_| true);
    let mut t = [[0.0; 3]; 2];
    let mut r = [q; 3];
    assert!(matches!(
        limit_reach(&[0.0; 3], 1.0, &mut t, &mut r),
        Err(Error::LengthMismatch {
            arg: "translations",
            ..
        })
    ));
}
