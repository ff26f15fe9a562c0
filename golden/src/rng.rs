//! A tiny deterministic generator for canonical inputs (xorshift64*, Vigna 2016).
//!
//! Written here rather than taken from a crate so the golden inputs can never change under a
//! dependency update. Not for statistics: only for reproducible, well-spread test inputs.

use deform_kernel::{Quat, Real};

/// xorshift64* generator. The same seed gives the same sequence on every platform.
#[derive(Clone, Copy, Debug)]
pub struct XorShift(u64);

impl XorShift {
    /// A generator from a seed (a zero seed is replaced by a fixed non-zero constant, since
    /// zero is the one fixed point of xorshift).
    pub const fn new(seed: u64) -> Self {
        if seed == 0 {
            XorShift(0x9E37_79B9_7F4A_7C15)
        } else {
            XorShift(seed)
        }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `[0, n)` (`0` when `n == 0`; the tiny modulo bias is irrelevant here).
    pub fn below(&mut self, n: u32) -> u32 {
        let r = (self.next_u64() >> 32) as u32;
        if n == 0 {
            0
        } else {
            r % n
        }
    }

    /// Uniform in `[0, 1)` with 53 random bits.
    pub fn unit_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    /// Uniform in `[lo, hi)`, generated in `f64` and rounded to `T`.
    pub fn uniform<T: Real>(&mut self, lo: f64, hi: f64) -> T {
        T::from_f64(lo + (hi - lo) * self.unit_f64())
    }

    /// A vector with components uniform in `[lo, hi)`.
    pub fn vec3<T: Real>(&mut self, lo: f64, hi: f64) -> [T; 3] {
        [
            self.uniform(lo, hi),
            self.uniform(lo, hi),
            self.uniform(lo, hi),
        ]
    }

    /// A quaternion with components uniform in `[-1, 1)` (not normalised).
    pub fn quat<T: Real>(&mut self) -> Quat<T> {
        Quat::new(
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
        )
    }

    /// A unit quaternion (the kernel's normalisation of [`XorShift::quat`]; the identity in
    /// the practically impossible case of a zero draw).
    pub fn unit_quat<T: Real>(&mut self) -> Quat<T> {
        self.quat().normalize().unwrap_or(Quat::identity())
    }
}
