//! Property tests of the quaternion algebra (`Quat`, `QuatAverage`), in `f64` and `f32`.
//!
//! Every property is checked on random inputs with proptest and its error is measured in
//! units of the scalar type's machine epsilon `ε` (`f64`: 2.2e-16, `f32`: 1.2e-7). Vectors
//! are measured relative to their length: "k ε" for a vector result means
//! `|computed − exact| ≤ k ε |v|`. The worst error seen over all cases is printed
//! (`cargo test -p deform-host-tests --test quat_properties -- --nocapture`) and each property
//! states its bound next to its test. The exact values are computed in `f64` from the `T`
//! inputs by naive formulas written here (no kernel code); for `f32` the `f64` reference is
//! exact to far below the bound.

use std::cell::Cell;

use deform_kernel::{Error, Quat, QuatAverage, Real};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// Cases per property and scalar type.
const CASES: u32 = 4096;

// ---------------------------------------------------------------------------------------------
// Naive f64 helpers (independent of the kernel)

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn norm3(a: [f64; 3]) -> f64 {
    dot3(a, a).sqrt()
}
fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale3(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit3(a: [f64; 3]) -> [f64; 3] {
    scale3(a, 1.0 / norm3(a))
}
/// `a / |a|` without overflow or underflow (scaled by the largest component first).
fn unit3s(a: [f64; 3]) -> [f64; 3] {
    let m = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    unit3(scale3(a, 1.0 / m))
}
fn norm4(a: [f64; 4]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]).sqrt()
}
fn dot4(a: [f64; 4], b: [f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}
fn dist4(a: [f64; 4], b: [f64; 4]) -> f64 {
    norm4([a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]])
}
/// Distance between two rotations given as quaternions: `min(|a − b|, |a + b|)`.
fn rot_dist4(a: [f64; 4], b: [f64; 4]) -> f64 {
    dist4(a, b).min(dist4(a, [-b[0], -b[1], -b[2], -b[3]]))
}
/// Angle between unit quaternions on the 4-sphere (after hemisphere alignment).
fn angle4(a: [f64; 4], b: [f64; 4]) -> f64 {
    let b = if dot4(a, b) < 0.0 {
        [-b[0], -b[1], -b[2], -b[3]]
    } else {
        b
    };
    let d = dist4(a, b);
    let s = norm4([a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]);
    2.0 * d.atan2(s)
}
/// Angle between two 3D vectors, `atan2(|a × b|, a · b)`.
fn angle3(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm3(cross3(a, b)).atan2(dot3(a, b))
}

fn eps<T: Real>() -> f64 {
    T::EPSILON.to_f64()
}
fn q64<T: Real>(q: Quat<T>) -> [f64; 4] {
    [q.w.to_f64(), q.x.to_f64(), q.y.to_f64(), q.z.to_f64()]
}
fn v64<T: Real>(v: [T; 3]) -> [f64; 3] {
    [v[0].to_f64(), v[1].to_f64(), v[2].to_f64()]
}
fn vt<T: Real>(v: [f64; 3]) -> [T; 3] {
    [T::from_f64(v[0]), T::from_f64(v[1]), T::from_f64(v[2])]
}
fn qt<T: Real>(a: [f64; 4]) -> Quat<T> {
    Quat::new(
        T::from_f64(a[0]),
        T::from_f64(a[1]),
        T::from_f64(a[2]),
        T::from_f64(a[3]),
    )
}
/// A unit quaternion in `T`, normalised naively in `f64` and rounded.
fn unit_qt<T: Real>(a: [f64; 4]) -> Quat<T> {
    let n = norm4(a);
    qt([a[0] / n, a[1] / n, a[2] / n, a[3] / n])
}
/// `Q [0, v] Q*` by two naive Hamilton products in f64.
fn rotate_ref(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let mul = |a: [f64; 4], b: [f64; 4]| {
        [
            a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
        ]
    };
    let r = mul(mul(q, [0.0, v[0], v[1], v[2]]), [q[0], -q[1], -q[2], -q[3]]);
    [r[1], r[2], r[3]]
}

// ---------------------------------------------------------------------------------------------
// Strategies

fn quat_raw() -> impl Strategy<Value = [f64; 4]> + Clone {
    prop::array::uniform4(-1.0f64..1.0).prop_filter("not tiny", |a| norm4(*a) > 0.1)
}
fn vec_raw(r: f64) -> impl Strategy<Value = [f64; 3]> + Clone {
    prop::array::uniform3(-r..r).prop_filter("not tiny", move |a| norm3(*a) > 1e-3 * r)
}

/// Runs `f` on `CASES` inputs; `f` returns the error in units of ε (NaN counts as a failure).
/// Prints and returns the worst error; fails when it exceeds `bound`.
fn measure<S: Strategy>(name: &str, strategy: S, bound: f64, f: impl Fn(S::Value) -> f64) -> f64
where
    S::Value: std::fmt::Debug,
{
    let worst = Cell::new(0.0f64);
    let mut runner = TestRunner::new(Config::with_cases(CASES));
    let result = runner.run(&strategy, |v| {
        let e = f(v);
        if e > worst.get() || e.is_nan() {
            worst.set(e);
        }
        prop_assert!(
            e <= bound,
            "{}: error {} ε exceeds the bound {} ε",
            name,
            e,
            bound
        );
        Ok(())
    });
    eprintln!(
        "{name}: worst {:.3} ε over {CASES} cases (bound {bound} ε)",
        worst.get()
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    worst.get()
}

// ---------------------------------------------------------------------------------------------
// Generic properties (each instantiated for f64 and f32 below)

/// Unit norm is kept by products: `||a b| − 1| ≤ 4 ε` for unit `a`, `b`.
fn product_keeps_unit_norm<T: Real>() {
    measure(
        &format!("product unit norm {}", std::any::type_name::<T>()),
        (quat_raw(), quat_raw()),
        4.0,
        |(a, b)| {
            let p = unit_qt::<T>(a) * unit_qt::<T>(b);
            (norm4(q64(p)) - 1.0).abs() / eps::<T>()
        },
    );
}

/// `normalize` gives a unit quaternion, `||q̂| − 1| ≤ 4 ε`, parallel to `q`
/// (`|q̂ − q/|q|| ≤ 4 ε`) for any finite non-zero `q` whose norm is a normal number, including
/// components near the overflow and underflow thresholds (scale 10^±300 in f64, 10^±36 in f32).
fn normalize_is_unit<T: Real>() {
    let emax = if T::MANTISSA_DIGITS > 24 { 300 } else { 36 };
    measure(
        &format!("normalize {}", std::any::type_name::<T>()),
        (quat_raw(), -emax..=emax),
        4.0,
        |(a, e)| {
            let s = 10f64.powi(e);
            let q = qt::<T>([a[0] * s, a[1] * s, a[2] * s, a[3] * s]);
            let qa = q64(q);
            let exact = scale4(qa, 1.0 / norm4_scaled(qa));
            match q.normalize() {
                Ok(u) => ((norm4(q64(u)) - 1.0).abs().max(dist4(q64(u), exact))) / eps::<T>(),
                Err(_) => f64::NAN,
            }
        },
    );
}
fn scale4(a: [f64; 4], s: f64) -> [f64; 4] {
    [a[0] * s, a[1] * s, a[2] * s, a[3] * s]
}
/// Norm of a 4-vector without overflow or underflow (scaled by the largest component).
fn norm4_scaled(a: [f64; 4]) -> f64 {
    let m = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    m * norm4(scale4(a, 1.0 / m))
}

/// `q q⁻¹ = 1` and `q⁻¹ q = 1` for non-unit `q` (norm in [0.1, 2] times a power of two near
/// 10^e, |e| ≤ 300 in f64 and 36 in f32, so also where `|q|²` overflows or underflows):
/// `≤ 4 ε` distance to the identity.
fn inverse_is_inverse<T: Real>() {
    let emax = if T::MANTISSA_DIGITS > 24 { 300 } else { 36 };
    measure(
        &format!("q q^-1 = 1 {}", std::any::type_name::<T>()),
        (quat_raw(), -emax..=emax),
        4.0,
        |(a, e)| {
            // Scale by an exact power of two near 10^e, so q and q⁻¹ stay exactly reciprocal
            // in magnitude and the products are not disturbed by the scaling's rounding.
            let s = 2f64.powi((e as f64 * std::f64::consts::LOG2_10).round() as i32);
            let q = qt::<T>(scale4(a, s));
            let Ok(inv) = q.inverse() else {
                return f64::NAN;
            };
            let one = [1.0, 0.0, 0.0, 0.0];
            dist4(q64(q * inv), one).max(dist4(q64(inv * q), one)) / eps::<T>()
        },
    );
}

/// Rotation preserves lengths (`||Rv| − |v|| ≤ 8 ε |v|`; the input quaternion itself is
/// only unit to about ε after rounding to `T`, which alone accounts for 2 ε) and dot products
/// (`|Ra·Rb − a·b| ≤ 12 ε |a||b|`), and agrees with `Q [0, v] Q*` (`≤ 6 ε |v|`).
fn rotation_is_orthogonal<T: Real>() {
    let name = std::any::type_name::<T>();
    measure(
        &format!("rotate keeps length {name}"),
        (quat_raw(), vec_raw(100.0)),
        8.0,
        |(q, v)| {
            let q = unit_qt::<T>(q);
            let v = vt::<T>(v);
            let (r, v) = (v64(q.rotate(v)), v64(v));
            (norm3(r) - norm3(v)).abs() / (norm3(v) * eps::<T>())
        },
    );
    measure(
        &format!("rotate keeps dot products {name}"),
        (quat_raw(), vec_raw(100.0), vec_raw(100.0)),
        12.0,
        |(q, a, b)| {
            let q = unit_qt::<T>(q);
            let (a, b) = (vt::<T>(a), vt::<T>(b));
            let (ra, rb) = (v64(q.rotate(a)), v64(q.rotate(b)));
            let (a, b) = (v64(a), v64(b));
            (dot3(ra, rb) - dot3(a, b)).abs() / (norm3(a) * norm3(b) * eps::<T>())
        },
    );
    measure(
        &format!("rotate = Q v Q* {name}"),
        (quat_raw(), vec_raw(100.0)),
        6.0,
        |(q, v)| {
            let q = unit_qt::<T>(q);
            let v = vt::<T>(v);
            let exact = rotate_ref(q64(q), v64(v));
            norm3(sub3(v64(q.rotate(v)), exact)) / (norm3(v64(v)) * eps::<T>())
        },
    );
}

/// Composition: rotating by `q2 q1` equals rotating by `q1` then by `q2`
/// (`≤ 12 ε |v|` apart).
fn composition_is_sequential<T: Real>() {
    measure(
        &format!("compose {}", std::any::type_name::<T>()),
        (quat_raw(), quat_raw(), vec_raw(100.0)),
        12.0,
        |(a, b, v)| {
            let (q1, q2) = (unit_qt::<T>(a), unit_qt::<T>(b));
            let v = vt::<T>(v);
            let once = v64((q2 * q1).rotate(v));
            let twice = v64(q2.rotate(q1.rotate(v)));
            norm3(sub3(once, twice)) / (norm3(v64(v)) * eps::<T>())
        },
    );
}

/// `to_matrix` agrees with `rotate`: `|M v − q.rotate(v)| ≤ 8 ε |v|`.
fn matrix_agrees_with_rotate<T: Real>() {
    measure(
        &format!("to_matrix {}", std::any::type_name::<T>()),
        (quat_raw(), vec_raw(100.0)),
        8.0,
        |(q, v)| {
            let q = unit_qt::<T>(q);
            let vv = vt::<T>(v);
            let m = q.to_matrix();
            let v = v64(vv);
            let mv: Vec<f64> = m.iter().map(|row| dot3(v64(*row), v)).collect();
            norm3(sub3([mv[0], mv[1], mv[2]], v64(q.rotate(vv)))) / (norm3(v) * eps::<T>())
        },
    );
}

/// Slerp: `slerp(a, b, 0) = a` and `slerp(a, b, 1) = ±b` (`≤ 4 ε`); the result is unit
/// (`≤ 4 ε`); constant angular speed: the arc from `a` to `slerp(a, b, t)` is `t θ` and the
/// rest is `(1 − t) θ` (`≤ 6 ε` absolute in radians), including nearly equal inputs (the
/// nlerp fallback) and inputs in opposite hemispheres.
fn slerp_properties<T: Real>() {
    let name = std::any::type_name::<T>();
    // `b` is `a` perturbed by 10^-k (k up to 12), or unrelated (k = 0), possibly negated.
    let pair = (quat_raw(), quat_raw(), 0i32..=12, any::<bool>()).prop_map(|(a, d, k, neg)| {
        let b = if k == 0 {
            d
        } else {
            let s = 10f64.powi(-k);
            [
                a[0] + s * d[0],
                a[1] + s * d[1],
                a[2] + s * d[2],
                a[3] + s * d[3],
            ]
        };
        (a, if neg { scale4(b, -1.0) } else { b })
    });
    measure(
        &format!("slerp end points {name}"),
        pair.clone(),
        4.0,
        |(a, b)| {
            let (a, b) = (unit_qt::<T>(a), unit_qt::<T>(b));
            let (Ok(s0), Ok(s1)) = (Quat::slerp(a, b, T::ZERO), Quat::slerp(a, b, T::ONE)) else {
                return f64::NAN;
            };
            dist4(q64(s0), q64(a)).max(rot_dist4(q64(s1), q64(b))) / eps::<T>()
        },
    );
    measure(
        &format!("slerp constant speed {name}"),
        (pair, 0.0f64..=1.0),
        6.0,
        |((a, b), t)| {
            let (a, b) = (unit_qt::<T>(a), unit_qt::<T>(b));
            let t = T::from_f64(t);
            let Ok(r) = Quat::slerp(a, b, t) else {
                return f64::NAN;
            };
            let (a, b, r, t) = (q64(a), q64(b), q64(r), t.to_f64());
            let theta = angle4(a, b);
            let unit_err = (norm4(r) - 1.0).abs();
            let e1 = (angle4(a, r) - t * theta).abs();
            let e2 = (angle4(r, b) - (1.0 - t) * theta).abs();
            unit_err.max(e1).max(e2) / eps::<T>()
        },
    );
}

/// The weighted average of copies of one rotation, some given as `−q`, is that rotation
/// (`≤ 4 ε` in rotation distance, and of the sign of the first copy added).
fn average_of_copies<T: Real>() {
    measure(
        &format!("average of copies {}", std::any::type_name::<T>()),
        (
            quat_raw(),
            prop::collection::vec((any::<bool>(), 0.01f64..10.0), 1..12),
        ),
        4.0,
        |(q, copies)| {
            let q = unit_qt::<T>(q);
            let mut avg = QuatAverage::new();
            for &(neg, w) in &copies {
                avg.add(if neg { -q } else { q }, T::from_f64(w));
            }
            let Ok(r) = avg.result() else {
                return f64::NAN;
            };
            let first = if copies[0].0 { -q } else { q };
            dist4(q64(r), q64(first)) / eps::<T>()
        },
    );
}

/// `rotation_arc(u, v)` maps `û` to `v̂`, is a unit quaternion, and is the shortest arc: its
/// angle is the angle between `u` and `v` and its axis is orthogonal to `u` (all `≤ 10 ε`). Inputs: unrelated directions, nearly parallel and nearly antiparallel
/// directions (`v = ±u + 10^-k w`, k up to 15) and exactly antiparallel ones (`v = −u`,
/// `v = −2u`); both vectors scaled by independent powers of ten up to the overflow and
/// underflow thresholds (10^±300 in f64, 10^±36 in f32).
fn rotation_arc_properties<T: Real>() {
    let name = std::any::type_name::<T>();
    let emax = if T::MANTISSA_DIGITS > 24 { 300 } else { 36 };
    let pair = (
        vec_raw(1.0),
        vec_raw(1.0),
        0i32..=15,
        0u8..4,
        -emax..=emax,
        -emax..=emax,
    )
        .prop_map(|(u, w, k, mode, eu, ev)| {
            let s = 10f64.powi(-k);
            let v = match mode {
                0 => w,
                1 => [u[0] + s * w[0], u[1] + s * w[1], u[2] + s * w[2]],
                2 => [-u[0] + s * w[0], -u[1] + s * w[1], -u[2] + s * w[2]],
                _ => scale3(u, if k % 2 == 0 { -1.0 } else { -2.0 }),
            };
            // Power-of-ten scaling keeps the mode-3 pairs exactly antiparallel only when
            // both use the same factor.
            let ev = if mode == 3 { eu } else { ev };
            (scale3(u, 10f64.powi(eu)), scale3(v, 10f64.powi(ev)))
        });
    measure(&format!("rotation_arc {name}"), pair, 10.0, |(u, v)| {
        let (ut, vtt) = (vt::<T>(u), vt::<T>(v));
        let Ok(q) = Quat::rotation_arc(ut, vtt) else {
            return f64::NAN;
        };
        let (u, v) = (unit3s(v64(ut)), unit3s(v64(vtt)));
        let qa = q64(q);
        let ru = unit3s(v64(q.rotate(vt::<T>(scale3(u, 1.0)))));
        let maps = norm3(sub3(ru, v));
        let unit = (norm4(qa) - 1.0).abs();
        let angle = (2.0 * angle4([1.0, 0.0, 0.0, 0.0], qa) - angle3(u, v)).abs();
        let axis = dot3([qa[1], qa[2], qa[3]], u).abs();
        maps.max(unit).max(angle).max(axis) / eps::<T>()
    });
}

/// `from_axis_angle` → `to_axis_angle` returns the axis and angle for angles in `(0, π]`, and
/// `(−axis, 2π − angle)` for angles in `(π, 2π)`: the angle to `8 ε` absolute and the axis to
/// `8 ε / sin(θ/2)` (the axis is the direction of the vector part, whose length is
/// `sin(θ/2)`; angles start at 10^-3), and `angle()` gives the same angle; the rotation
/// round trip `from_axis_angle(to_axis_angle(q)) = ±q` holds for every unit `q`
/// (`≤ 8 ε`).
fn axis_angle_round_trip<T: Real>() {
    let name = std::any::type_name::<T>();
    measure(
        &format!("axis-angle round trip {name}"),
        (vec_raw(1.0), 1e-3f64..(2.0 * std::f64::consts::PI - 1e-3)),
        8.0,
        |(axis, angle)| {
            let (at, ant) = (vt::<T>(axis), T::from_f64(angle));
            let Ok(q) = Quat::from_axis_angle(at, ant) else {
                return f64::NAN;
            };
            let (ax, an) = q.to_axis_angle();
            let (axis, angle) = (unit3(v64(at)), ant.to_f64());
            let (want_axis, want_angle) = if angle <= std::f64::consts::PI {
                (axis, angle)
            } else {
                (scale3(axis, -1.0), 2.0 * std::f64::consts::PI - angle)
            };
            let s = (0.5 * angle).sin().abs();
            let axis_err = norm3(sub3(v64(ax), want_axis)) * s;
            let angle_err = (an.to_f64() - want_angle).abs();
            let angle_fn_err = (q.angle().to_f64() - want_angle).abs();
            axis_err.max(angle_err).max(angle_fn_err) / eps::<T>()
        },
    );
    measure(
        &format!("to_axis_angle -> from_axis_angle {name}"),
        quat_raw(),
        8.0,
        |a| {
            let q = unit_qt::<T>(a);
            let (ax, an) = q.to_axis_angle();
            let Ok(r) = Quat::from_axis_angle(ax, an) else {
                return f64::NAN;
            };
            rot_dist4(q64(r), q64(q)) / eps::<T>()
        },
    );
}

/// `from_rotation_z(θ)` rotates 2D points like the matrix `[[cos θ, −sin θ], [sin θ, cos θ]]`
/// (`≤ 6 ε |p|`) and `rotation_z_angle` recovers θ for θ in `(−π, π)` (`≤ 6 ε (1 + |θ|)`).
fn rotation_z_properties<T: Real>() {
    let name = std::any::type_name::<T>();
    measure(
        &format!("rotation z {name}"),
        (
            -3.1f64..3.1,
            prop::array::uniform2(-100.0f64..100.0)
                .prop_filter("nonzero", |p| p[0].abs() + p[1].abs() > 1e-3),
        ),
        6.0,
        |(theta, p)| {
            let th = T::from_f64(theta);
            let q = Quat::from_rotation_z(th);
            let pt = [T::from_f64(p[0]), T::from_f64(p[1])];
            let r = q.rotate_2d(pt);
            let (th, p) = (th.to_f64(), [pt[0].to_f64(), pt[1].to_f64()]);
            let (s, c) = th.sin_cos();
            let want = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
            let np = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let e_rot =
                ((r[0].to_f64() - want[0]).powi(2) + (r[1].to_f64() - want[1]).powi(2)).sqrt() / np;
            let e_angle = (q.rotation_z_angle().to_f64() - th).abs() / (1.0 + th.abs());
            e_rot.max(e_angle) / eps::<T>()
        },
    );
}

macro_rules! both_types {
    ($($f:ident),* $(,)?) => {
        mod f64_props {
            $( #[test] fn $f() { super::$f::<f64>(); } )*
        }
        mod f32_props {
            $( #[test] fn $f() { super::$f::<f32>(); } )*
        }
    };
}

both_types!(
    product_keeps_unit_norm,
    normalize_is_unit,
    inverse_is_inverse,
    rotation_is_orthogonal,
    composition_is_sequential,
    matrix_agrees_with_rotate,
    slerp_properties,
    average_of_copies,
    rotation_arc_properties,
    axis_angle_round_trip,
    rotation_z_properties,
);

// ---------------------------------------------------------------------------------------------
// Error cases

fn error_cases<T: Real>() {
    let z = T::ZERO;
    let one = T::ONE;
    let nan = T::from_f64(f64::NAN);
    let inf = T::INFINITY;
    let zero_q = Quat::new(z, z, z, z);
    assert!(matches!(zero_q.normalize(), Err(Error::ZeroLength { .. })));
    assert!(matches!(zero_q.inverse(), Err(Error::ZeroLength { .. })));
    // A subnormal quaternion is treated as zero (documented).
    let sub = Quat::new(T::MIN_POSITIVE * T::HALF, z, z, z);
    assert!(matches!(sub.normalize(), Err(Error::ZeroLength { .. })));
    for bad in [
        Quat::new(nan, z, z, z),
        Quat::new(one, nan, z, z),
        Quat::new(one, z, inf, z),
        Quat::new(one, z, z, -inf),
    ] {
        assert!(
            matches!(bad.normalize(), Err(Error::NonFinite { .. })),
            "{bad:?}"
        );
        assert!(
            matches!(bad.inverse(), Err(Error::NonFinite { .. })),
            "{bad:?}"
        );
        assert!(matches!(
            Quat::slerp(Quat::identity(), bad, T::HALF),
            Err(Error::NonFinite { .. })
        ));
    }
    assert!(matches!(
        Quat::slerp(Quat::identity(), Quat::identity(), nan),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Quat::from_axis_angle([z, z, z], one),
        Err(Error::ZeroLength { arg: "axis", .. })
    ));
    assert!(matches!(
        Quat::from_axis_angle([one, z, z], nan),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Quat::from_axis_angle([inf, z, z], one),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Quat::rotation_arc([z, z, z], [one, z, z]),
        Err(Error::ZeroLength { arg: "from", .. })
    ));
    assert!(matches!(
        Quat::rotation_arc([one, z, z], [z, z, z]),
        Err(Error::ZeroLength { arg: "to", .. })
    ));
    assert!(matches!(
        Quat::rotation_arc([one, nan, z], [one, z, z]),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        QuatAverage::<T>::new().result(),
        Err(Error::ZeroLength { .. })
    ));
    let mut cancel = QuatAverage::<T>::new();
    cancel.add(Quat::identity(), one);
    cancel.add(-Quat::<T>::identity(), -one); // aligned to +1, weight −1: cancels
    assert!(matches!(cancel.result(), Err(Error::ZeroLength { .. })));
    assert_eq!(cancel.total_weight(), z);
    // The identity's axis is (1, 0, 0) and its angle 0.
    assert_eq!(Quat::<T>::identity().to_axis_angle(), ([one, z, z], z));
}

#[test]
fn error_cases_f64() {
    error_cases::<f64>();
}

#[test]
fn error_cases_f32() {
    error_cases::<f32>();
}

/// An explicit hemisphere reference decides the sign of the average.
#[test]
fn average_with_reference_takes_its_sign() {
    let q = unit_qt::<f64>([0.3, -0.2, 0.9, 0.1]);
    let mut avg = QuatAverage::with_reference(-q);
    avg.add(q, 1.0);
    avg.add(q, 2.0);
    let r = avg.result().unwrap();
    assert!(dist4(q64(r), q64(-q)) <= 4.0 * f64::EPSILON);
    assert_eq!(avg.total_weight(), 3.0);
}
