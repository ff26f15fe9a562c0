//! Parity of `deform_kernel::Quat` with nalgebra's `Quaternion`/`UnitQuaternion` and glam's
//! `DQuat` (f64) and `Quat` (f32).
//!
//! Each comparison runs on random proptest inputs, measures the distance between the kernel's
//! result and the library's in units of the scalar's machine epsilon `ε` (quaternions: the
//! 4-vector distance, up to sign where the libraries may pick the other sign; vectors:
//! relative to `|v|`), prints the worst value over all cases
//! (`cargo test -p deform-host-tests --test quat_parity -- --nocapture`) and fails when it
//! exceeds the bound stated on the test. The bounds leave room for both sides' rounding:
//! nalgebra and glam use `std` (or their own) `sin`/`cos`/`acos` and their own operation
//! orders, the kernel uses libm.
//!
//! Where a library's own formula is ill-conditioned, the distance is divided by that
//! formula's condition factor and the test says so: glam's `from_rotation_arc`
//! (`[u × v, 1 + u·v]` normalised) loses accuracy near 180°, nalgebra's `rotation_between` and
//! both libraries' `slerp` take the angle from `acos`, which loses accuracy near 0°; both
//! errors grow like `ε / sin θ`, so those comparisons are measured in units of
//! `ε (1 + 1/sin θ)`. The kernel's own accuracy in those regions is checked against exact
//! references in `quat_properties.rs` (and against an `f64` slerp below).

use std::cell::Cell;

use deform_kernel::Quat;
use nalgebra::{Quaternion, Unit, UnitQuaternion, Vector3};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

/// Cases per comparison and scalar type.
const CASES: u32 = 4096;

fn norm4(a: [f64; 4]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + a[3] * a[3]).sqrt()
}
fn dist4(a: [f64; 4], b: [f64; 4]) -> f64 {
    norm4([a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]])
}
/// Distance between rotations: `min(|a − b|, |a + b|)`.
fn rot_dist4(a: [f64; 4], b: [f64; 4]) -> f64 {
    dist4(a, b).min(dist4(a, [-b[0], -b[1], -b[2], -b[3]]))
}
fn norm3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
fn dist3(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm3([a[0] - b[0], a[1] - b[1], a[2] - b[2]])
}
/// Angle between unit quaternions on the 4-sphere after hemisphere alignment.
fn angle4(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d = dist4(a, b).min(dist4(a, [-b[0], -b[1], -b[2], -b[3]]));
    let s = dist4(a, [-b[0], -b[1], -b[2], -b[3]]).max(dist4(a, b));
    2.0 * d.atan2(s)
}
/// Angle between 3D vectors.
fn angle3(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    norm3(c).atan2(a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
}
fn unit4(a: [f64; 4]) -> [f64; 4] {
    let n = norm4(a);
    [a[0] / n, a[1] / n, a[2] / n, a[3] / n]
}
fn unit3(a: [f64; 3]) -> [f64; 3] {
    let n = norm3(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

fn quat_raw() -> impl Strategy<Value = [f64; 4]> + Clone {
    prop::array::uniform4(-1.0f64..1.0).prop_filter("not tiny", |a| norm4(*a) > 0.1)
}
fn vec_raw(r: f64) -> impl Strategy<Value = [f64; 3]> + Clone {
    prop::array::uniform3(-r..r).prop_filter("not tiny", move |a| norm3(*a) > 1e-3 * r)
}

/// Runs `f` on `CASES` inputs; `f` returns the error in units of ε (NaN fails). Prints the
/// worst error; fails when it exceeds `bound`.
fn measure<S: Strategy>(name: &str, strategy: S, bound: f64, f: impl Fn(S::Value) -> f64)
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
        "parity {name}: worst {:.3} ε over {CASES} cases (bound {bound} ε)",
        worst.get()
    );
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
}

/// One parity suite per scalar type: `$t` the scalar, `$gq`/`$gv`/`$gm` glam's quaternion,
/// 3-vector and 3×3 matrix types of that precision.
macro_rules! parity_suite {
    ($module:ident, $t:ty, $gq:ty, $gv:ty, $gm:ty) => {
        mod $module {
            use super::*;

            type T = $t;
            const EPS: f64 = <$t>::EPSILON as f64;

            fn kq(a: [f64; 4]) -> Quat<T> {
                Quat::new(a[0] as T, a[1] as T, a[2] as T, a[3] as T)
            }
            fn k64(q: Quat<T>) -> [f64; 4] {
                [q.w as f64, q.x as f64, q.y as f64, q.z as f64]
            }
            fn nq(q: Quat<T>) -> Quaternion<T> {
                Quaternion::new(q.w, q.x, q.y, q.z)
            }
            fn n64(q: Quaternion<T>) -> [f64; 4] {
                [q.w as f64, q.i as f64, q.j as f64, q.k as f64]
            }
            fn gq(q: Quat<T>) -> $gq {
                <$gq>::from_xyzw(q.x, q.y, q.z, q.w)
            }
            fn g64(q: $gq) -> [f64; 4] {
                [q.w as f64, q.x as f64, q.y as f64, q.z as f64]
            }
            fn kv(v: [f64; 3]) -> [T; 3] {
                [v[0] as T, v[1] as T, v[2] as T]
            }
            fn v64(v: [T; 3]) -> [f64; 3] {
                [v[0] as f64, v[1] as f64, v[2] as f64]
            }
            fn unit_kq(a: [f64; 4]) -> Quat<T> {
                kq(unit4(a))
            }

            /// Hamilton product of non-unit quaternions (`|a|, |b| ≤ 2`): `≤ 8 ε` from
            /// nalgebra's `Quaternion` product and from glam's.
            #[test]
            fn product() {
                measure(
                    concat!("product ", stringify!($t)),
                    (quat_raw(), quat_raw()),
                    8.0,
                    |(a, b)| {
                        let (a, b) = (kq(a), kq(b));
                        let k = k64(a * b);
                        let n = n64(nq(a) * nq(b));
                        let g = g64(gq(a) * gq(b));
                        dist4(k, n).max(dist4(k, g)) / EPS
                    },
                );
            }

            /// Rotating a vector: `≤ 8 ε |v|` from `UnitQuaternion * Vector3` and from glam's
            /// `Quat * Vec3`.
            #[test]
            fn rotate() {
                measure(
                    concat!("rotate ", stringify!($t)),
                    (quat_raw(), vec_raw(100.0)),
                    8.0,
                    |(q, v)| {
                        let q = unit_kq(q);
                        let v = kv(v);
                        let k = v64(q.rotate(v));
                        let nu = UnitQuaternion::new_unchecked(nq(q));
                        let n = nu * Vector3::new(v[0], v[1], v[2]);
                        let n = [n.x as f64, n.y as f64, n.z as f64];
                        let g = gq(q) * <$gv>::new(v[0], v[1], v[2]);
                        let g = [g.x as f64, g.y as f64, g.z as f64];
                        dist3(k, n).max(dist3(k, g)) / (norm3(v64(v)) * EPS)
                    },
                );
            }

            /// The rotation matrix: `≤ 8 ε` (max entry) from nalgebra's
            /// `to_rotation_matrix` and glam's `Mat3::from_quat` (column major there).
            #[test]
            fn to_matrix() {
                measure(
                    concat!("to_matrix ", stringify!($t)),
                    quat_raw(),
                    8.0,
                    |q| {
                        let q = unit_kq(q);
                        let m = q.to_matrix();
                        let nm = UnitQuaternion::new_unchecked(nq(q)).to_rotation_matrix();
                        let gm = <$gm>::from_quat(gq(q));
                        let mut e = 0.0f64;
                        for r in 0..3 {
                            for c in 0..3 {
                                let k = m[r][c] as f64;
                                e = e.max((k - nm[(r, c)] as f64).abs());
                                e = e.max((k - gm.col(c)[r] as f64).abs());
                            }
                        }
                        e / EPS
                    },
                );
            }

            /// `from_axis_angle` with an unnormalised axis and an angle in `[−2π, 2π]`: `≤ 4 ε`
            /// from nalgebra and glam (each normalising the axis its own way).
            #[test]
            fn from_axis_angle() {
                measure(
                    concat!("from_axis_angle ", stringify!($t)),
                    (vec_raw(1.0), -std::f64::consts::TAU..std::f64::consts::TAU),
                    4.0,
                    |(axis, angle)| {
                        let (a, th) = (kv(axis), angle as T);
                        let Ok(k) = Quat::from_axis_angle(a, th) else {
                            return f64::NAN;
                        };
                        let na = Unit::new_normalize(Vector3::new(a[0], a[1], a[2]));
                        let n = UnitQuaternion::from_axis_angle(&na, th);
                        let g =
                            <$gq>::from_axis_angle(<$gv>::new(a[0], a[1], a[2]).normalize(), th);
                        let k = k64(k);
                        dist4(k, n64(*n.quaternion())).max(dist4(k, g64(g))) / EPS
                    },
                );
            }

            /// `to_axis_angle` versus nalgebra's `axis_angle` for rotation angles in
            /// `[0.01, π − 0.01]` (away from the identity, where the axis is undefined, and
            /// from 180°, where both signs are equally valid): axis and angle `≤ 8 ε`.
            #[test]
            fn to_axis_angle() {
                measure(
                    concat!("to_axis_angle ", stringify!($t)),
                    quat_raw().prop_filter("angle away from 0 and π", |a| {
                        let w = unit4(*a)[0].abs();
                        let ang = 2.0 * w.acos();
                        (0.01..std::f64::consts::PI - 0.01).contains(&ang)
                    }),
                    8.0,
                    |q| {
                        let q = unit_kq(q);
                        let (ax, an) = q.to_axis_angle();
                        let Some((nax, nan)) = UnitQuaternion::new_unchecked(nq(q)).axis_angle()
                        else {
                            return f64::NAN;
                        };
                        let nax = [nax.x as f64, nax.y as f64, nax.z as f64];
                        dist3(v64(ax), nax).max((an as f64 - nan as f64).abs()) / EPS
                    },
                );
            }

            /// Slerp between unit quaternions at least 10⁻³ apart on the 4-sphere, `t` in
            /// `[0, 1]`, either hemisphere: `≤ 8 ε (1 + 1/sin θ)` (up to sign) from nalgebra
            /// and glam, θ the arc between `a` and `±b`. Both libraries take θ from
            /// `acos(a·b)`, whose error grows like `ε / sin θ`; the kernel (atan2 of `|a − b|`
            /// and `|a + b|`) is checked here against a slerp evaluated in `f64` from the same
            /// inputs, `≤ 4 ε`, which shows the spread is the libraries'.
            #[test]
            fn slerp() {
                measure(
                    concat!("slerp, in units of ε(1 + 1/sin θ), ", stringify!($t)),
                    (quat_raw(), quat_raw(), 0.0f64..=1.0)
                        .prop_filter("not nearly equal rotations", |(a, b, _)| {
                            angle4(unit4(*a), unit4(*b)) > 1e-3
                        }),
                    8.0,
                    |(a, b, t)| {
                        let (a, b, t) = (unit_kq(a), unit_kq(b), t as T);
                        let Ok(k) = Quat::slerp(a, b, t) else {
                            return f64::NAN;
                        };
                        let na = UnitQuaternion::new_unchecked(nq(a));
                        let nb = UnitQuaternion::new_unchecked(nq(b));
                        let Some(n) = na.try_slerp(&nb, t, 0.0) else {
                            return f64::NAN;
                        };
                        let g = gq(a).slerp(gq(b), t);
                        let cond = 1.0 + 1.0 / angle4(k64(a), k64(b)).sin();
                        let k = k64(k);
                        rot_dist4(k, n64(*n.quaternion())).max(rot_dist4(k, g64(g))) / (EPS * cond)
                    },
                );
                measure(
                    concat!("slerp vs f64 reference ", stringify!($t)),
                    (quat_raw(), quat_raw(), 0.0f64..=1.0),
                    4.0,
                    |(a, b, t)| {
                        let (a, b, t) = (unit_kq(a), unit_kq(b), t as T);
                        let Ok(k) = Quat::slerp(a, b, t) else {
                            return f64::NAN;
                        };
                        let (a, b, t) = (k64(a), k64(b), t as f64);
                        let dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
                        let b = if dot < 0.0 {
                            [-b[0], -b[1], -b[2], -b[3]]
                        } else {
                            b
                        };
                        let th = angle4(a, b);
                        let exact = if th < 1e-300 {
                            a
                        } else {
                            let (wa, wb) =
                                (((1.0 - t) * th).sin() / th.sin(), (t * th).sin() / th.sin());
                            unit4([
                                wa * a[0] + wb * b[0],
                                wa * a[1] + wb * b[1],
                                wa * a[2] + wb * b[2],
                                wa * a[3] + wb * b[3],
                            ])
                        };
                        dist4(k64(k), exact) / EPS
                    },
                );
            }

            /// `rotation_arc` versus glam's `from_rotation_arc` and nalgebra's
            /// `rotation_between` for directions between 10⁻³ and π − 10⁻³ rad apart:
            /// `≤ 8 ε (1 + 1/sin θ)`, θ the angle between them (glam is ill-conditioned near
            /// π, nalgebra near 0; see the module docs).
            #[test]
            fn rotation_arc() {
                measure(
                    concat!("rotation_arc, in units of ε(1 + 1/sin θ), ", stringify!($t)),
                    (vec_raw(1.0), vec_raw(1.0)).prop_filter("well-conditioned angle", |(u, v)| {
                        (1e-3..std::f64::consts::PI - 1e-3).contains(&angle3(*u, *v))
                    }),
                    8.0,
                    |(u, v)| {
                        let (u, v) = (kv(unit3(u)), kv(unit3(v)));
                        let Ok(k) = Quat::rotation_arc(u, v) else {
                            return f64::NAN;
                        };
                        let g = <$gq>::from_rotation_arc(
                            <$gv>::new(u[0], u[1], u[2]),
                            <$gv>::new(v[0], v[1], v[2]),
                        );
                        let Some(n) = UnitQuaternion::rotation_between(
                            &Vector3::new(u[0], u[1], u[2]),
                            &Vector3::new(v[0], v[1], v[2]),
                        ) else {
                            return f64::NAN;
                        };
                        let cond = 1.0 + 1.0 / angle3(v64(u), v64(v)).sin();
                        let k = k64(k);
                        rot_dist4(k, n64(*n.quaternion())).max(rot_dist4(k, g64(g))) / (EPS * cond)
                    },
                );
            }

            /// The vector helpers against nalgebra's `Vector3`: `dot`, `cross`, `norm`,
            /// `distance`, `lerp` (relative to the operands' magnitudes) and `normalize` (also
            /// for vectors scaled by 2^k up to about 10^±300 in f64 and 10^±30 in f32, where
            /// `|v|²` overflows or underflows; nalgebra normalises the unscaled vector, since
            /// its own `normalize` overflows there); `any_orthogonal` gives a unit vector
            /// orthogonal to its input. All `≤ 4 ε`.
            #[test]
            fn vector_helpers() {
                use deform_kernel::vector;
                let emax = if EPS < 1e-10 { 300 } else { 30 };
                measure(
                    concat!("vector helpers ", stringify!($t)),
                    (vec_raw(10.0), vec_raw(10.0), 0.0f64..1.0, -emax..=emax),
                    4.0,
                    |(a, b, t, e)| {
                        let (a, b, t) = (kv(a), kv(b), t as T);
                        let (na, nb) = (
                            Vector3::new(a[0], a[1], a[2]),
                            Vector3::new(b[0], b[1], b[2]),
                        );
                        let (la, lb) = (norm3(v64(a)), norm3(v64(b)));
                        let rel = |x: f64, y: f64, scale: f64| (x - y).abs() / (scale * EPS);
                        let vrel = |x: [T; 3], y: Vector3<T>, scale: f64| {
                            dist3(v64(x), [y.x as f64, y.y as f64, y.z as f64]) / (scale * EPS)
                        };
                        let mut err = rel(vector::dot(a, b) as f64, na.dot(&nb) as f64, la * lb);
                        err = err.max(vrel(vector::cross(a, b), na.cross(&nb), la * lb));
                        err = err.max(rel(vector::norm(a) as f64, na.norm() as f64, la));
                        err = err.max(rel(
                            vector::distance(a, b) as f64,
                            (na - nb).norm() as f64,
                            la + lb,
                        ));
                        err = err.max(vrel(vector::lerp(a, b, t), na.lerp(&nb, t), la + lb));
                        let s = (2.0 as T).powi((e as f64 * std::f64::consts::LOG2_10) as i32);
                        let big = [a[0] * s, a[1] * s, a[2] * s];
                        let Some(u) = vector::normalize(big) else {
                            return f64::NAN;
                        };
                        err = err.max(vrel(u, na.normalize(), 1.0));
                        let o = vector::any_orthogonal(v64(u).map(|x| x as T));
                        let o64 = v64(o);
                        let u64_ = v64(u);
                        err = err.max((norm3(o64) - 1.0).abs() / EPS);
                        err = err.max(
                            (o64[0] * u64_[0] + o64[1] * u64_[1] + o64[2] * u64_[2]).abs() / EPS,
                        );
                        err
                    },
                );
                assert_eq!(vector::normalize([0.0 as T; 3]), None);
                assert_eq!(
                    vector::normalize([<$t>::MIN_POSITIVE / 2.0, 0.0, 0.0]),
                    None
                );
                assert_eq!(vector::normalize([<$t>::NAN, 1.0, 0.0]), None);
                assert_eq!(vector::normalize([<$t>::INFINITY, 1.0, 0.0]), None);
                assert_eq!(
                    vector::normalize([<$t>::MAX, <$t>::MAX, 0.0]).map(|u| u[0] == u[1]),
                    Some(true)
                );
                assert_eq!(vector::cross2([1.0 as T, 2.0], [3.0, 4.0]), -2.0);
                assert_eq!(vector::to_3d([1.0 as T, 2.0]), [1.0, 2.0, 0.0]);
            }

            /// The glam conversions are exact and keep the component order (w first in the
            /// kernel, `from_xyzw` in glam).
            #[test]
            fn glam_conversions_are_exact() {
                measure(
                    concat!("glam From/Into ", stringify!($t)),
                    quat_raw(),
                    0.0,
                    |a| {
                        let k = kq(a);
                        let g: $gq = k.into();
                        let back: Quat<T> = g.into();
                        let same = g.w == k.w && g.x == k.x && g.y == k.y && g.z == k.z;
                        if same && back == k {
                            0.0
                        } else {
                            f64::NAN
                        }
                    },
                );
            }
        }
    };
}

parity_suite!(f64_parity, f64, glam::DQuat, glam::DVec3, glam::DMat3);
parity_suite!(f32_parity, f32, glam::Quat, glam::Vec3, glam::Mat3);
