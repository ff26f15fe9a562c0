//! The design variables' derivatives (kernel/src/design/sensitivity.rs, twist.rs): the
//! adjoint of a Hicks–Henne bump and of an FFD box's evaluation equal the tangent's dot
//! product (`⟨J v, w⟩ = ⟨v, Jᵀ w⟩`) in 2D and 3D, f64 and f32; the tangent of FFD_TWIST at
//! amplitude 0 is the central difference of `ffd_twist` (falling as h²); bad input is refused
//! with `out` unchanged. The whole chain through a mesh deformation is tested from the tool
//! (cli/tests/sensitivity_design.rs).

use deform_kernel::design::ffd::{ffd_control_point_count, ffd_eval, FfdBox};
use deform_kernel::design::hicks_henne::{hicks_henne, HicksHenne};
use deform_kernel::design::sensitivity::{ffd_adjoint, hicks_henne_adjoint};
use deform_kernel::design::twist::{ffd_twist, ffd_twist_tangent, FfdTwist};
use deform_kernel::{Error, Real};

/// Deterministic numbers in [-1, 1) (splitmix64; test data only).
struct Rng(u64);
impl Rng {
    fn real(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        2.0 * (((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
    fn items<T: Real, const D: usize>(&mut self, n: usize, scale: f64, shift: f64) -> Vec<[T; D]> {
        (0..n)
            .map(|_| std::array::from_fn(|_| T::from_f64(shift + scale * self.real())))
            .collect()
    }
}

fn dot<T: Real, const D: usize>(a: &[[T; D]], b: &[[T; D]]) -> f64 {
    (a.iter().zip(b))
        .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| p.to_f64() * q.to_f64()))
        .sum()
}

/// Points on a unit-chord "airfoil": x in (0, 1), normals up or down.
fn hicks_henne_identity<T: Real, const D: usize>(tol: f64) {
    let mut rng = Rng(3 + D as u64);
    let n = 40;
    let mut points: Vec<[T; D]> = rng.items(n + 5, 0.5, 0.5);
    points[0][0] = T::ZERO; // the leading edge: no bump
    let nodes: Vec<u32> = (0..n as u32).map(|i| i + 3).chain([0]).collect();
    let normals: Vec<[T; D]> = rng.items(nodes.len(), 1.0, 0.0);
    let g: Vec<[T; D]> = rng.items(nodes.len(), 1.0, 0.0);
    for (upper, x_max) in [(true, 0.3), (false, 0.7)] {
        let bump = HicksHenne {
            upper,
            x_max: T::from_f64(x_max),
            amplitude: T::ONE,
        };
        let mut v = vec![[T::ZERO; D]; nodes.len()];
        hicks_henne(&points, &nodes, &normals, bump, &mut v).unwrap();
        let adj = hicks_henne_adjoint(&points, &nodes, &normals, upper, bump.x_max, &g).unwrap();
        let lhs = dot(&v, &g);
        assert!(lhs.abs() > 0.1, "a test that cannot fail: {lhs}");
        let err = (lhs - adj.to_f64()).abs() / lhs.abs();
        assert!(
            err <= tol,
            "D = {D}, upper = {upper}: {lhs} vs {adj:?} ({err:e})"
        );
    }
}

#[test]
fn hicks_henne_adjoint_is_the_tangents_transpose() {
    hicks_henne_identity::<f64, 2>(1e-15);
    hicks_henne_identity::<f64, 3>(1e-15);
    hicks_henne_identity::<f32, 2>(1e-6);
    hicks_henne_identity::<f32, 3>(1e-6);
}

fn ffd_identity<T: Real, const D: usize>(degree: [usize; D], tol: f64) {
    let mut rng = Rng(11 + D as u64);
    let count = ffd_control_point_count(degree).unwrap();
    let params: Vec<[T; D]> = rng.items(57, 0.55, 0.5); // a little outside the box too
    let g: Vec<[T; D]> = rng.items(params.len(), 1.0, 0.0);
    let dp: Vec<[T; D]> = rng.items(count, 1.0, 0.0);
    let mut v = vec![[T::ZERO; D]; params.len()];
    ffd_eval(&FfdBox::new(degree, &dp).unwrap(), &params, &mut v).unwrap();
    let mut bar = vec![[T::ONE; D]; count];
    ffd_adjoint(degree, &params, &g, &mut bar).unwrap();
    let (lhs, rhs) = (dot(&v, &g), dot(&dp, &bar));
    assert!(lhs.abs() > 0.01, "a test that cannot fail: {lhs}");
    let err = (lhs - rhs).abs() / lhs.abs();
    assert!(err <= tol, "{degree:?}: {lhs} vs {rhs} ({err:e})");
    println!(
        "FFD {degree:?} {}: ⟨J v, w⟩ − ⟨v, Jᵀ w⟩ relative {err:.1e}",
        core::any::type_name::<T>()
    );
}

#[test]
fn ffd_adjoint_is_the_evaluations_transpose() {
    ffd_identity::<f64, 2>([4, 2], 1e-14);
    ffd_identity::<f64, 3>([3, 2, 1], 1e-14);
    ffd_identity::<f64, 3>([10, 1, 1], 1e-14);
    ffd_identity::<f32, 2>([4, 2], 1e-5);
    ffd_identity::<f32, 3>([3, 2, 1], 1e-5);
}

#[test]
fn ffd_twist_tangent_is_the_derivative_at_zero() {
    let degree = [3usize, 2, 1];
    let mut rng = Rng(5);
    let count = ffd_control_point_count(degree).unwrap();
    let mut cps: Vec<[f64; 3]> = Vec::new();
    for f in 0..count {
        let (i, j, k) = (f / 6, (f / 2) % 3, f % 2);
        let jitter = 0.05 * rng.real();
        cps.push([
            i as f64 / 3.0 + jitter,
            j as f64 * 0.5,
            k as f64 * 0.2 - 0.1,
        ]);
    }
    let twist = FfdTwist {
        j: 1,
        segment: [[0.3, -1.0, 0.02], [0.3, 2.0, 0.02]],
        amplitude: 0.0,
        ref_length: 1.7,
    };
    let (fi, fk) = ([0u32], [] as [u32; 0]);
    let mut t = vec![[9.0; 3]; count];
    ffd_twist_tangent(degree, &cps, twist, &fi, &fk, &mut t).unwrap();
    let moved = t.iter().filter(|v| v.iter().any(|c| *c != 0.0)).count();
    assert_eq!(moved, 3 * 2, "layer j = 1 without i = 0");
    let mut errors = Vec::new();
    for h in [1e-2, 1e-3, 1e-4] {
        let at = |a: f64| {
            let mut c = cps.clone();
            ffd_twist(
                degree,
                &mut c,
                FfdTwist {
                    amplitude: a,
                    ..twist
                },
                &fi,
                &fk,
            )
            .unwrap();
            c
        };
        let (p, m) = (at(h), at(-h));
        let err = (p.iter().zip(&m).zip(&t))
            .flat_map(|((p, m), t)| (0..3).map(move |c| ((p[c] - m[c]) / (2.0 * h) - t[c]).abs()))
            .fold(0.0, f64::max);
        println!("FFD_TWIST h = {h:e}: max |FD − tangent| = {err:.2e}");
        errors.push(err);
    }
    assert!(errors[0] > 1e-8 && errors[0] < 1e-3, "{errors:?}");
    assert!(
        errors[1] < errors[0] / 50.0 && errors[2] < 1e-8,
        "{errors:?}"
    );
}

#[test]
fn bad_input_is_refused_and_out_is_unchanged() {
    let params = [[0.5f64; 3]; 4];
    let g = [[1.0f64; 3]; 4];
    let mut out = vec![[7.0f64; 3]; 8];
    let before = out.clone();
    let bad = |r: Result<(), Error>| assert!(r.is_err(), "{r:?}");
    bad(ffd_adjoint([1, 1, 1], &params, &g[..3], &mut out));
    bad(ffd_adjoint([1, 1, 2], &params, &g, &mut out));
    bad(ffd_adjoint([0, 1, 1], &params, &g, &mut out));
    let mut nan = g;
    nan[2][1] = f64::NAN;
    bad(ffd_adjoint([1, 1, 1], &params, &nan, &mut out));
    let far = [[1e300f64; 3]; 4];
    assert_eq!(
        ffd_adjoint([1, 1, 1], &far, &g, &mut out),
        Err(Error::Overflow { arg: "params" })
    );
    assert_eq!(out, before);
    let pts = [[0.5f64, 0.0]; 3];
    let r = hicks_henne_adjoint(&pts, &[0, 1], &[[0.0, 1.0]; 2], true, 1.5, &[[1.0; 2]; 2]);
    assert!(
        matches!(r, Err(Error::InvalidParameter { arg: "x_max", .. })),
        "{r:?}"
    );
    let r = hicks_henne_adjoint(&pts, &[0, 1], &[[0.0, 1.0]; 2], true, 0.3, &[[1.0; 2]; 1]);
    assert!(
        matches!(r, Err(Error::LengthMismatch { arg: "dj_dx", .. })),
        "{r:?}"
    );
}
