//! Target 1: quaternion algebra against an independent f64 reference (the textbook formulas,
//! evaluated here in a different order), and the invariants: normalisation gives unit norm or
//! a typed error (never NaN), rotation preserves length, q q⁻¹ = 1, rotation_arc maps u to v.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::{Error, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    a: [f64; 4],
    b: [f64; 4],
    v: [f64; 3],
    u: [f64; 3],
    t: f64,
}

/// Reference Hamilton product `[s1 s2 − v1·v2, s1 v2 + s2 v1 + v1 × v2]`.
fn product(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let (s1, v1) = (a[0], [a[1], a[2], a[3]]);
    let (s2, v2) = (b[0], [b[1], b[2], b[3]]);
    let dot = v1[0] * v2[0] + v1[1] * v2[1] + v1[2] * v2[2];
    let cross = [
        v1[1] * v2[2] - v1[2] * v2[1],
        v1[2] * v2[0] - v1[0] * v2[2],
        v1[0] * v2[1] - v1[1] * v2[0],
    ];
    [
        s1 * s2 - dot,
        s1 * v2[0] + s2 * v1[0] + cross[0],
        s1 * v2[1] + s2 * v1[1] + cross[1],
        s1 * v2[2] + s2 * v1[2] + cross[2],
    ]
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Keeps magnitudes where no product overflows or underflows to garbage.
fn tame(x: f64) -> bool {
    x.is_finite() && (x == 0.0 || (x.abs() > 1e-100 && x.abs() < 1e100))
}

fuzz_target!(|inp: Input| {
    let qa = Quat::from_array(inp.a);
    let qb = Quat::from_array(inp.b);

    // Normalisation: unit norm or a typed error, never NaN.
    match qa.normalize() {
        Ok(n) => {
            assert!(n.is_finite());
            assert!((n.norm() - 1.0).abs() <= 4.0 * f64::EPSILON, "{n:?}");
        }
        Err(Error::ZeroLength { .. } | Error::NonFinite { .. }) => {}
        Err(e) => panic!("unexpected error {e:?}"),
    }
    if !inp
        .a
        .iter()
        .chain(&inp.b)
        .chain(&inp.v)
        .chain(&inp.u)
        .all(|&x| tame(x))
    {
        return;
    }

    // Product against the reference, relative to the size of the factors.
    let p = (qa * qb).to_array();
    let r = product(inp.a, inp.b);
    let scale = norm(&inp.a) * norm(&inp.b);
    for k in 0..4 {
        assert!(
            (p[k] - r[k]).abs() <= 8.0 * f64::EPSILON * scale,
            "{p:?} vs {r:?}"
        );
    }

    let (Ok(na), Ok(nb)) = (qa.normalize(), qb.normalize()) else {
        return;
    };
    // Rotation preserves length.
    let rv = na.rotate(inp.v);
    assert!((norm(&rv) - norm(&inp.v)).abs() <= 16.0 * f64::EPSILON * norm(&inp.v));
    // q q⁻¹ = 1.
    let one = (na * na.inverse().unwrap()).to_array();
    assert!((one[0] - 1.0).abs() <= 8.0 * f64::EPSILON && norm(&one[1..]) <= 8.0 * f64::EPSILON);
    // Composition equals sequential rotation.
    let seq = nb.rotate(na.rotate(inp.v));
    let comp = (nb * na).rotate(inp.v);
    for k in 0..3 {
        assert!((seq[k] - comp[k]).abs() <= 64.0 * f64::EPSILON * norm(&inp.v));
    }
    // slerp stays unit and hits its end points.
    if inp.t.is_finite() && (0.0..=1.0).contains(&inp.t) {
        let s = Quat::slerp(na, nb, inp.t).unwrap();
        assert!((s.norm() - 1.0).abs() <= 8.0 * f64::EPSILON);
    }
    // rotation_arc maps the direction of u onto the direction of v.
    if norm(&inp.u) > 0.0 && norm(&inp.v) > 0.0 {
        let arc = Quat::rotation_arc(inp.u, inp.v).unwrap();
        let mapped = arc.rotate(inp.u);
        let (nu, nv) = (norm(&inp.u), norm(&inp.v));
        for k in 0..3 {
            assert!(
                (mapped[k] / nu - inp.v[k] / nv).abs() <= 1e-12,
                "{mapped:?}"
            );
        }
    }
});
