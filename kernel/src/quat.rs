//! Quaternions for rotations: [`Quat`] and the hemisphere-aligned [`QuatAverage`].
//!
//! Conventions (Samareh, NASA TM-2002-211646): `Q = [s, v] = w + x i + y j + z k`, scalar
//! first; a unit quaternion rotates a vector as `v' = Q [0, v] Q*`; "apply `Q1` then `Q2`" is
//! the product `Q2 Q1`.

use core::ops::{Mul, Neg};

use crate::error::{Error, Result};
use crate::real::Real;
use crate::vector::{add, any_orthogonal, cross, dot, norm, normalize, scale, sub};

/// A quaternion `w + x i + y j + z k`, stored scalar first (`#[repr(C)]`: four scalars, so a
/// caller's `[T; 4]` buffer has the same layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quat<T> {
    /// Scalar part.
    pub w: T,
    /// `i` component.
    pub x: T,
    /// `j` component.
    pub y: T,
    /// `k` component.
    pub z: T,
}

impl<T: Real> Quat<T> {
    /// `w + x i + y j + z k`.
    #[inline]
    pub const fn new(w: T, x: T, y: T, z: T) -> Self {
        Quat { w, x, y, z }
    }

    /// The identity rotation `[1, 0]`.
    #[inline]
    pub fn identity() -> Self {
        Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO)
    }

    /// `[s, v]`.
    #[inline]
    pub fn from_scalar_vector(s: T, v: [T; 3]) -> Self {
        Quat::new(s, v[0], v[1], v[2])
    }

    /// `[w, x, y, z]`.
    #[inline]
    pub fn from_array(a: [T; 4]) -> Self {
        Quat::new(a[0], a[1], a[2], a[3])
    }

    /// `[w, x, y, z]`.
    #[inline]
    pub fn to_array(self) -> [T; 4] {
        [self.w, self.x, self.y, self.z]
    }

    /// The vector part `(x, y, z)`.
    #[inline]
    pub fn vector(self) -> [T; 3] {
        [self.x, self.y, self.z]
    }

    /// Conjugate `[s, −v]`.
    #[inline]
    pub fn conjugate(self) -> Self {
        Quat::new(self.w, -self.x, -self.y, -self.z)
    }

    /// Four-dimensional dot product.
    #[inline]
    pub fn dot(self, o: Self) -> T {
        self.w * o.w + self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `|Q|²`.
    #[inline]
    pub fn norm_sq(self) -> T {
        self.dot(self)
    }

    /// `|Q|`.
    #[inline]
    pub fn norm(self) -> T {
        self.norm_sq().sqrt()
    }

    /// `true` when all four components are finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.w.is_finite() && self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// `s · Q`.
    #[inline]
    pub fn scale(self, s: T) -> Self {
        Quat::new(self.w * s, self.x * s, self.y * s, self.z * s)
    }

    /// `Q / |Q|`. A quaternion whose components are all zero or subnormal is an error
    /// (`ZeroLength`), as is a non-finite one (`NonFinite`), never NaN. When `|Q|²` would
    /// overflow or underflow, `Q` is first divided by its largest component, so every finite
    /// quaternion with a normal component normalises to full accuracy.
    ///
    /// # Errors
    /// A non-finite component ([`Error::NonFinite`]); all components zero or subnormal
    /// ([`Error::ZeroLength`]).
    pub fn normalize(self) -> Result<Self> {
        if !self.is_finite() {
            return Err(Error::NonFinite {
                arg: "quaternion",
                position: 0,
            });
        }
        let n2 = self.norm_sq();
        if n2.is_finite() && n2 >= T::MIN_POSITIVE {
            return Ok(self.scale(T::ONE / n2.sqrt()));
        }
        // |Q|² overflowed or underflowed: rescale by the largest component (norm in [1, 2]).
        let m = self
            .w
            .abs()
            .max(self.x.abs())
            .max(self.y.abs())
            .max(self.z.abs());
        if m < T::MIN_POSITIVE {
            return Err(Error::ZeroLength {
                arg: "quaternion",
                position: 0,
            });
        }
        let r = Quat::new(self.w / m, self.x / m, self.y / m, self.z / m);
        Ok(r.scale(T::ONE / r.norm()))
    }

    /// Fast approximate `Q / |Q|` (feature `micromath`; **excluded from bit parity**, and not
    /// used by any other kernel routine): `Q` times [`Real::fast_inv_sqrt`]`(|Q|²)`, no square
    /// root, no division. For `f32` the result's norm is within
    /// [`NORMALIZE_FAST_F32_MAX_NORM_ERROR`] of 1 (measured; tested on host and on target);
    /// for `f64` it equals [`Quat::normalize`] (micromath has no `f64` functions). When `|Q|²`
    /// is not a finite normal number the exact path is taken.
    ///
    /// # Errors
    /// Those of [`Quat::normalize`].
    #[cfg(feature = "micromath")]
    pub fn normalize_fast(self) -> Result<Self> {
        let n2 = self.norm_sq();
        if self.is_finite() && n2.is_finite() && n2 >= T::MIN_POSITIVE {
            Ok(self.scale(n2.fast_inv_sqrt()))
        } else {
            self.normalize()
        }
    }

    /// `Q⁻¹ = Q* / |Q|²` (equals the conjugate for unit quaternions).
    ///
    /// # Errors
    /// Like
    /// [`Quat::normalize`]; when `|Q|²` would overflow or underflow, `Q` is rescaled by its
    /// largest component first (accuracy is then lost only where the true inverse is itself
    /// subnormal or beyond the largest finite value).
    pub fn inverse(self) -> Result<Self> {
        if !self.is_finite() {
            return Err(Error::NonFinite {
                arg: "quaternion",
                position: 0,
            });
        }
        let n2 = self.norm_sq();
        if n2.is_finite() && n2 >= T::MIN_POSITIVE {
            return Ok(self.conjugate().scale(T::ONE / n2));
        }
        // |Q|² overflowed or underflowed: Q⁻¹ = (Q/m)* / (|Q/m|² m), m the largest component.
        let m = self
            .w
            .abs()
            .max(self.x.abs())
            .max(self.y.abs())
            .max(self.z.abs());
        if m < T::MIN_POSITIVE {
            return Err(Error::ZeroLength {
                arg: "quaternion",
                position: 0,
            });
        }
        let r = Quat::new(self.w / m, self.x / m, self.y / m, self.z / m);
        let d = r.norm_sq() * m;
        Ok(Quat::new(r.w / d, -r.x / d, -r.y / d, -r.z / d))
    }

    /// Rotation by `angle` radians about `axis` (normalised here; a zero axis is an error):
    /// `[cos(θ/2), û sin(θ/2)]` (Samareh eq. 3).
    ///
    /// # Errors
    /// A non-finite axis or angle ([`Error::NonFinite`]); a zero axis ([`Error::ZeroLength`]).
    pub fn from_axis_angle(axis: [T; 3], angle: T) -> Result<Self> {
        if !axis.iter().all(|c| c.is_finite()) || !angle.is_finite() {
            return Err(Error::NonFinite {
                arg: "axis_angle",
                position: 0,
            });
        }
        let u = normalize(axis).ok_or(Error::ZeroLength {
            arg: "axis",
            position: 0,
        })?;
        let (s, c) = (angle * T::HALF).sin_cos();
        Ok(Quat::from_scalar_vector(c, scale(u, s)))
    }

    /// Rotation by `angle` radians about the z axis (the 2D rotation).
    #[inline]
    pub fn from_rotation_z(angle: T) -> Self {
        let (s, c) = (angle * T::HALF).sin_cos();
        Quat::new(c, T::ZERO, T::ZERO, s)
    }

    /// Rotation angle in `[0, π]` (`q` and `−q` give the same angle), computed as
    /// `2 atan2(|v|, |w|)`, accurate for tiny angles.
    #[inline]
    pub fn angle(self) -> T {
        T::TWO * norm(self.vector()).atan2(self.w.abs())
    }

    /// Axis and angle with the angle in `[0, π]`. For the identity the axis is `(1, 0, 0)`.
    pub fn to_axis_angle(self) -> ([T; 3], T) {
        let q = if self.w.is_sign_negative() {
            -self
        } else {
            self
        };
        let v = q.vector();
        let angle = T::TWO * norm(v).atan2(q.w);
        let axis = normalize(v).unwrap_or([T::ONE, T::ZERO, T::ZERO]);
        (axis, angle)
    }

    /// Signed angle of a rotation about z, in `(−π, π]` (for 2D: `atan2(z, w)` doubled).
    #[inline]
    pub fn rotation_z_angle(self) -> T {
        let q = if self.w.is_sign_negative() {
            -self
        } else {
            self
        };
        T::TWO * q.z.atan2(q.w)
    }

    /// The shortest rotation taking the direction of `from` to the direction of `to` (both
    /// normalised here; zero vectors are errors).
    ///
    /// For angles up to 90° this is the half-way construction `[u·h, u×h]` with
    /// `h = (u + v)/|u + v|`, accurate for tiny angles. Beyond 90° it uses
    /// `[|u + v|/2, n̂ |u − v|/2]` with `n̂` the direction of `u × (u + v)` (equal to `u × v`,
    /// but computed from the small sum `u + v`, which has a relative rounding error of at
    /// most ε/2, so the axis stays accurate and orthogonal to `u` near 180°; `u × v` itself
    /// loses all accuracy there); exactly antiparallel vectors turn by 180° about an axis
    /// orthogonal to `u`.
    ///
    /// # Errors
    /// A non-finite vector ([`Error::NonFinite`]); a zero vector ([`Error::ZeroLength`]).
    pub fn rotation_arc(from: [T; 3], to: [T; 3]) -> Result<Self> {
        if !from.iter().chain(to.iter()).all(|c| c.is_finite()) {
            return Err(Error::NonFinite {
                arg: "rotation_arc",
                position: 0,
            });
        }
        let u = normalize(from).ok_or(Error::ZeroLength {
            arg: "from",
            position: 0,
        })?;
        let v = normalize(to).ok_or(Error::ZeroLength {
            arg: "to",
            position: 0,
        })?;
        if dot(u, v) >= T::ZERO {
            let h = normalize(add(u, v)).unwrap_or(u);
            return Ok(Quat::from_scalar_vector(dot(u, h), cross(u, h)));
        }
        let c = norm(add(u, v)) * T::HALF;
        let s = norm(sub(u, v)) * T::HALF;
        let axis = normalize(cross(u, add(u, v))).unwrap_or_else(|| any_orthogonal(u));
        // Renormalise: c and s come from two independent roundings.
        Quat::from_scalar_vector(c, scale(axis, s)).normalize()
    }

    /// Rotates `v` by this unit quaternion: `Q [0, v] Q*`, evaluated in the cross-product form
    /// `v + w t + q × t` with `t = 2 q × v` (fewer operations and roundings than two products).
    #[inline]
    pub fn rotate(self, v: [T; 3]) -> [T; 3] {
        let q = self.vector();
        let t = scale(cross(q, v), T::TWO);
        add(add(v, scale(t, self.w)), cross(q, t))
    }

    /// Rotates the 2D point `v` (taken at `z = 0`) and drops the z component. Exact for
    /// rotations about z; for other rotations it is the projection of the rotated point.
    #[inline]
    pub fn rotate_2d(self, v: [T; 2]) -> [T; 2] {
        let r = self.rotate([v[0], v[1], T::ZERO]);
        [r[0], r[1]]
    }

    /// The 3×3 rotation matrix (row major) of this unit quaternion.
    pub fn to_matrix(self) -> [[T; 3]; 3] {
        let Quat { w, x, y, z } = self;
        let two = T::TWO;
        [
            [
                T::ONE - two * (y * y + z * z),
                two * (x * y - w * z),
                two * (x * z + w * y),
            ],
            [
                two * (x * y + w * z),
                T::ONE - two * (x * x + z * z),
                two * (y * z - w * x),
            ],
            [
                two * (x * z - w * y),
                two * (y * z + w * x),
                T::ONE - two * (x * x + y * y),
            ],
        ]
    }

    /// Normalised linear interpolation on the shorter arc (`b` is negated when `a·b < 0`).
    ///
    /// # Errors
    /// Those of [`Quat::normalize`] on the interpolated quaternion (non-finite input, or a
    /// blend that cancels).
    pub fn nlerp(a: Self, b: Self, t: T) -> Result<Self> {
        let b = if a.dot(b) < T::ZERO { -b } else { b };
        let s = T::ONE - t;
        Quat::new(
            s * a.w + t * b.w,
            s * a.x + t * b.x,
            s * a.y + t * b.y,
            s * a.z + t * b.z,
        )
        .normalize()
    }

    /// Spherical linear interpolation of unit quaternions on the shorter arc: constant angular
    /// speed, `t = 0` gives `a` and `t = 1` gives `b` (up to sign alignment). The arc angle is
    /// `2 atan2(|a − b|, |a + b|)`, accurate near 0; below a tiny angle it falls back to
    /// [`Quat::nlerp`].
    ///
    /// # Errors
    /// Non-finite input ([`Error::NonFinite`]); a quaternion that cannot be normalised
    /// ([`Error::ZeroLength`]).
    pub fn slerp(a: Self, b: Self, t: T) -> Result<Self> {
        if !a.is_finite() || !b.is_finite() || !t.is_finite() {
            return Err(Error::NonFinite {
                arg: "slerp",
                position: 0,
            });
        }
        let b = if a.dot(b) < T::ZERO { -b } else { b };
        let d = (a - b).norm();
        let s = (a + b).norm();
        let theta = T::TWO * d.atan2(s); // angle between a and b on the 4-sphere
        let sin_theta = theta.sin();
        if sin_theta <= T::EPSILON.sqrt() * T::EPSILON.sqrt().sqrt() {
            return Quat::nlerp(a, b, t);
        }
        let wa = ((T::ONE - t) * theta).sin() / sin_theta;
        let wb = (t * theta).sin() / sin_theta;
        Quat::new(
            wa * a.w + wb * b.w,
            wa * a.x + wb * b.x,
            wa * a.y + wb * b.y,
            wa * a.z + wb * b.z,
        )
        .normalize()
    }
}

impl<T: Real> core::ops::Add for Quat<T> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Quat::new(self.w + o.w, self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<T: Real> core::ops::Sub for Quat<T> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Quat::new(self.w - o.w, self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<T: Real> Neg for Quat<T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Quat::new(-self.w, -self.x, -self.y, -self.z)
    }
}

/// Hamilton product `[s₁s₂ − v₁·v₂, s₁v₂ + s₂v₁ + v₁×v₂]`.
/// Largest `| |Quat::<f32>::normalize_fast(q)| − 1 |` (measured over 10⁶ random quaternions
/// of magnitudes 1e-3 … 1e3 on host, also asserted on target): the inverse square root's
/// relative error [`FAST_INV_SQRT_F32_MAX_REL_ERROR`](crate::real::FAST_INV_SQRT_F32_MAX_REL_ERROR)
/// plus the rounding of `|Q|²` and of the scaling. The exact [`Quat::normalize`] is within
/// about 2 ulp (1.2e-7).
#[cfg(feature = "micromath")]
pub const NORMALIZE_FAST_F32_MAX_NORM_ERROR: f64 = 5.0e-6;

impl<T: Real> Mul for Quat<T> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Quat::new(
            self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
            self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
        )
    }
}

/// Weighted average of rotations with hemisphere alignment.
///
/// `q` and `−q` are the same rotation, so each added quaternion is first flipped into the
/// hemisphere of the reference (the first one added, unless set explicitly); the weighted
/// component sum is renormalised by [`QuatAverage::result`]. This is the normalised linear
/// average, accurate for rotations within a cluster (as in mesh deformation, where
/// neighbouring nodes rotate alike). Summation order is the call order.
#[derive(Clone, Copy, Debug, Default)]
pub struct QuatAverage<T> {
    sum: [T; 4],
    reference: Option<Quat<T>>,
    weight: T,
}

impl<T: Real> QuatAverage<T> {
    /// An empty accumulator; the first quaternion added becomes the reference.
    #[inline]
    pub fn new() -> Self {
        QuatAverage {
            sum: [T::ZERO; 4],
            reference: None,
            weight: T::ZERO,
        }
    }

    /// An empty accumulator with an explicit hemisphere reference.
    #[inline]
    pub fn with_reference(reference: Quat<T>) -> Self {
        QuatAverage {
            sum: [T::ZERO; 4],
            reference: Some(reference),
            weight: T::ZERO,
        }
    }

    /// Adds `q` with weight `w`.
    #[inline]
    pub fn add(&mut self, q: Quat<T>, w: T) {
        let r = *self.reference.get_or_insert(q);
        let q = if r.dot(q) < T::ZERO { -q } else { q };
        for (s, c) in self.sum.iter_mut().zip(q.to_array()) {
            *s += w * c;
        }
        self.weight += w;
    }

    /// The sum of the weights added so far.
    #[inline]
    pub fn total_weight(&self) -> T {
        self.weight
    }

    /// The normalised average. Empty or cancelling input is an error.
    ///
    /// # Errors
    /// No quaternion added, or a sum that cancels ([`Error::ZeroLength`]); an overflowing sum
    /// ([`Error::NonFinite`]).
    #[inline]
    pub fn result(&self) -> Result<Quat<T>> {
        Quat::from_array(self.sum).normalize()
    }
}

#[cfg(feature = "glam")]
mod glam_interop {
    use super::Quat;

    impl From<glam::DQuat> for Quat<f64> {
        #[inline]
        fn from(q: glam::DQuat) -> Self {
            Quat::new(q.w, q.x, q.y, q.z)
        }
    }
    impl From<Quat<f64>> for glam::DQuat {
        #[inline]
        fn from(q: Quat<f64>) -> Self {
            glam::DQuat::from_xyzw(q.x, q.y, q.z, q.w)
        }
    }
    impl From<glam::Quat> for Quat<f32> {
        #[inline]
        fn from(q: glam::Quat) -> Self {
            Quat::new(q.w, q.x, q.y, q.z)
        }
    }
    impl From<Quat<f32>> for glam::Quat {
        #[inline]
        fn from(q: Quat<f32>) -> Self {
            glam::Quat::from_xyzw(q.x, q.y, q.z, q.w)
        }
    }
}
