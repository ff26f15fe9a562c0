//! The scalar type: a sealed [`Real`] trait implemented for `f32` and `f64`.
//!
//! Arithmetic comes from `core`; square root and every transcendental function come from
//! [`libm`], a pure-Rust implementation that gives the same bits on every platform (x86-64,
//! Cortex-M with soft-float `f64`, RISC-V). Nothing here uses fused multiply-add.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A floating-point scalar: `f32` or `f64`. Sealed: no other type can implement it.
pub trait Real:
    sealed::Sealed
    + Copy
    + Default
    + PartialEq
    + PartialOrd
    + Debug
    + Display
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Send
    + Sync
    + 'static
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 0.5.
    const HALF: Self;
    /// π.
    const PI: Self;
    /// Machine epsilon (difference between 1 and the next representable value).
    const EPSILON: Self;
    /// Smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// Largest finite value.
    const MAX: Self;
    /// Positive infinity.
    const INFINITY: Self;
    /// Number of mantissa bits including the implicit one (24 or 53).
    const MANTISSA_DIGITS: u32;

    /// Converts from `f64` (rounding to nearest for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts to `f64` (exact).
    fn to_f64(self) -> f64;
    /// Converts from `u32` (rounding to nearest for `f32` above 2²⁴).
    fn from_u32(x: u32) -> Self;
    /// Converts from `usize` (rounding to nearest).
    fn from_usize(x: usize) -> Self;
    /// Raw bit pattern widened to `u64` (for golden-bit hashing).
    fn to_bits_u64(self) -> u64;

    /// Square root (libm).
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Sine (libm).
    fn sin(self) -> Self;
    /// Cosine (libm).
    fn cos(self) -> Self;
    /// Sine and cosine at once (libm).
    fn sin_cos(self) -> (Self, Self);
    /// Tangent (libm).
    fn tan(self) -> Self;
    /// Arc sine (libm).
    fn asin(self) -> Self;
    /// Arc cosine (libm).
    fn acos(self) -> Self;
    /// Arc tangent (libm).
    fn atan(self) -> Self;
    /// Four-quadrant arc tangent of `self / x` (libm).
    fn atan2(self, x: Self) -> Self;
    /// `sqrt(self² + y²)` without undue overflow or underflow (libm).
    fn hypot(self, y: Self) -> Self;
    /// `e^self` (libm).
    fn exp(self) -> Self;
    /// Natural logarithm (libm).
    fn ln(self) -> Self;
    /// `self^y` (libm).
    fn powf(self, y: Self) -> Self;
    /// Largest integer not greater than `self` (libm).
    fn floor(self) -> Self;
    /// Magnitude of `self` with the sign of `sign` (libm).
    fn copysign(self, sign: Self) -> Self;
    /// `true` when neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// `true` when NaN.
    fn is_nan(self) -> bool;
    /// `true` when the sign bit is set (also for `-0.0` and negative NaN).
    fn is_sign_negative(self) -> bool;
    /// The binary exponent `e` with `2^e ≤ |self| < 2^(e+1)` for a normal `self`; the smallest
    /// normal exponent (−1022 / −126) for zero and subnormals, one above the largest (1024 /
    /// 128) for infinities and NaN. Read from the bits: exact and branch-free.
    fn exponent(self) -> i32;
    /// `2^e` exactly, with `e` clamped to the normal exponents (−1022..=1023 / −126..=127).
    fn pow2(e: i32) -> Self;

    /// Minimum; if one argument is NaN the other is returned (IEEE 754 `minNum`).
    #[inline]
    fn min(self, other: Self) -> Self {
        if other < self || self.is_nan() {
            other
        } else {
            self
        }
    }
    /// Maximum; if one argument is NaN the other is returned (IEEE 754 `maxNum`).
    #[inline]
    fn max(self, other: Self) -> Self {
        if other > self || self.is_nan() {
            other
        } else {
            self
        }
    }
    /// Clamps into `[lo, hi]` (no panic when `lo > hi`: the result is then `hi`).
    #[inline]
    fn clamp_to(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    /// `self²`.
    #[inline]
    fn sq(self) -> Self {
        self * self
    }

    /// Fast approximate `1 / √self` (feature `micromath`; **excluded from bit parity**: not
    /// used by any other routine, so enabling the feature changes no existing result).
    ///
    /// `f32`: micromath's magic-constant estimate ([`micromath::F32Ext::invsqrt`], about 3.4 %
    /// off) refined by two Newton steps `y ← y (1.5 − ½ x y²)`: measured maximum relative
    /// error [`FAST_INV_SQRT_F32_MAX_REL_ERROR`] over every `f32` in `[1, 4)` (the error
    /// pattern repeats every two binades) and tested on host and on target. No square root
    /// and no division (libm's `sqrtf` is a software routine on a Cortex-M4F).
    ///
    /// `f64`: the exact `1 / sqrt(self)` (libm); micromath has no `f64` functions.
    ///
    /// Only for positive, finite, normal `self` (smaller inputs give a meaningless but finite
    /// result, never a panic); callers fall back to the exact path elsewhere.
    #[cfg(feature = "micromath")]
    fn fast_inv_sqrt(self) -> Self;
}

/// Measured maximum relative error of [`Real::fast_inv_sqrt`] for `f32` (every `f32` in
/// `[1, 4)`, checked by the kernel's unit tests, `host-tests/tests/micromath.rs` and the
/// on-target suite): 4.8e-6 (measured maximum 4.735e-6, about 40 ulp). The exact
/// `1 / sqrtf(x)` is within 1 ulp.
#[cfg(feature = "micromath")]
pub const FAST_INV_SQRT_F32_MAX_REL_ERROR: f64 = 4.8e-6;

/// `f32` fast inverse square root: micromath's estimate and two Newton steps.
#[cfg(feature = "micromath")]
#[inline]
fn fast_inv_sqrt_f32(x: f32) -> f32 {
    let y = micromath::F32Ext::invsqrt(x);
    // `x y y` is near 1 for every normal x, so no intermediate is subnormal (`0.5 x` would be
    // for x < 2 MIN_POSITIVE).
    let y = y * (1.5 - x * y * y * 0.5);
    y * (1.5 - x * y * y * 0.5)
}

/// `f64`: exact (libm).
#[cfg(feature = "micromath")]
#[inline]
fn fast_inv_sqrt_f64(x: f64) -> f64 {
    1.0 / libm::sqrt(x)
}

macro_rules! impl_real {
    ($t:ty, $bits:ty, $sqrt:path, $fabs:path, $sin:path, $cos:path, $sincos:path, $tan:path,
     $asin:path, $acos:path, $atan:path, $atan2:path, $hypot:path, $exp:path, $ln:path,
     $pow:path, $floor:path, $copysign:path, $fast_inv_sqrt:ident) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const PI: Self = core::f64::consts::PI as $t;
            const EPSILON: Self = <$t>::EPSILON;
            const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
            const MAX: Self = <$t>::MAX;
            const INFINITY: Self = <$t>::INFINITY;
            const MANTISSA_DIGITS: u32 = <$t>::MANTISSA_DIGITS;

            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn from_u32(x: u32) -> Self {
                x as $t
            }
            #[inline]
            fn from_usize(x: usize) -> Self {
                x as $t
            }
            #[inline]
            fn to_bits_u64(self) -> u64 {
                self.to_bits() as u64
            }
            #[inline]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline]
            fn abs(self) -> Self {
                $fabs(self)
            }
            #[inline]
            fn sin(self) -> Self {
                $sin(self)
            }
            #[inline]
            fn cos(self) -> Self {
                $cos(self)
            }
            #[inline]
            fn sin_cos(self) -> (Self, Self) {
                $sincos(self)
            }
            #[inline]
            fn tan(self) -> Self {
                $tan(self)
            }
            #[inline]
            fn asin(self) -> Self {
                $asin(self)
            }
            #[inline]
            fn acos(self) -> Self {
                $acos(self)
            }
            #[inline]
            fn atan(self) -> Self {
                $atan(self)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                $atan2(self, x)
            }
            #[inline]
            fn hypot(self, y: Self) -> Self {
                $hypot(self, y)
            }
            #[inline]
            fn exp(self) -> Self {
                $exp(self)
            }
            #[inline]
            fn ln(self) -> Self {
                $ln(self)
            }
            #[inline]
            fn powf(self, y: Self) -> Self {
                $pow(self, y)
            }
            #[inline]
            fn floor(self) -> Self {
                $floor(self)
            }
            #[inline]
            fn copysign(self, sign: Self) -> Self {
                $copysign(self, sign)
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline]
            fn is_nan(self) -> bool {
                <$t>::is_nan(self)
            }
            #[inline]
            fn is_sign_negative(self) -> bool {
                <$t>::is_sign_negative(self)
            }
            #[inline]
            fn exponent(self) -> i32 {
                const FRACTION_BITS: u32 = <$t>::MANTISSA_DIGITS - 1;
                const BIAS: i32 = <$t>::MAX_EXP - 1;
                let field = (self.to_bits() >> FRACTION_BITS) as i32 & (2 * BIAS + 1);
                field.max(1) - BIAS
            }
            #[inline]
            fn pow2(e: i32) -> Self {
                const FRACTION_BITS: u32 = <$t>::MANTISSA_DIGITS - 1;
                const BIAS: i32 = <$t>::MAX_EXP - 1;
                let field = e.clamp(1 - BIAS, BIAS) + BIAS;
                <$t>::from_bits((field as $bits) << FRACTION_BITS)
            }
            #[cfg(feature = "micromath")]
            #[inline]
            fn fast_inv_sqrt(self) -> Self {
                $fast_inv_sqrt(self)
            }
        }
    };
}

impl_real!(
    f64,
    u64,
    libm::sqrt,
    libm::fabs,
    libm::sin,
    libm::cos,
    libm::sincos,
    libm::tan,
    libm::asin,
    libm::acos,
    libm::atan,
    libm::atan2,
    libm::hypot,
    libm::exp,
    libm::log,
    libm::pow,
    libm::floor,
    libm::copysign,
    fast_inv_sqrt_f64
);
impl_real!(
    f32,
    u32,
    libm::sqrtf,
    libm::fabsf,
    libm::sinf,
    libm::cosf,
    libm::sincosf,
    libm::tanf,
    libm::asinf,
    libm::acosf,
    libm::atanf,
    libm::atan2f,
    libm::hypotf,
    libm::expf,
    libm::logf,
    libm::powf,
    libm::floorf,
    libm::copysignf,
    fast_inv_sqrt_f32
);

/// Returns `true` when every component of every element is finite.
#[inline]
pub fn all_finite<T: Real, const N: usize>(values: &[[T; N]]) -> bool {
    values.iter().all(|v| v.iter().all(|c| c.is_finite()))
}

/// Index of the first element with a non-finite component, if any.
#[inline]
pub fn first_non_finite<T: Real, const N: usize>(values: &[[T; N]]) -> Option<usize> {
    values.iter().position(|v| v.iter().any(|c| !c.is_finite()))
}

#[cfg(all(test, feature = "micromath"))]
mod micromath_tests {
    use super::{Real, FAST_INV_SQRT_F32_MAX_REL_ERROR};

    /// Relative error of the fast path against the exact `1/√x` in f64.
    fn rel_error(x: f32) -> f64 {
        let exact = 1.0 / libm::sqrt(x as f64);
        ((x.fast_inv_sqrt() as f64) - exact).abs() / exact
    }

    #[test]
    fn fast_inv_sqrt_f32_bound_over_two_binades() {
        // [1, 4): every f32 (the error repeats with period 4 in x).
        let (lo, hi) = (1.0f32.to_bits(), 4.0f32.to_bits());
        let worst = (lo..hi)
            .map(|b| rel_error(f32::from_bits(b)))
            .fold(0.0, f64::max);
        assert!(worst <= FAST_INV_SQRT_F32_MAX_REL_ERROR, "{worst:e}");
        assert!(
            worst > FAST_INV_SQRT_F32_MAX_REL_ERROR * 0.5,
            "bound not tight: {worst:e}"
        );
    }

    #[test]
    fn fast_inv_sqrt_f32_bound_across_the_normal_range() {
        let mut b = f32::MIN_POSITIVE.to_bits();
        while b < f32::MAX.to_bits() {
            let x = f32::from_bits(b);
            assert!(rel_error(x) <= FAST_INV_SQRT_F32_MAX_REL_ERROR, "x = {x:e}");
            b += 4099;
        }
    }

    #[test]
    fn fast_inv_sqrt_f64_is_exact() {
        for x in [1e-300, 0.3, 1.0, 2.0, 7.5e12] {
            assert_eq!(x.fast_inv_sqrt(), 1.0 / libm::sqrt(x));
        }
    }
}
