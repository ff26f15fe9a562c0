//! Reproducible sums: an exact, fixed-size accumulator whose result does not depend on the
//! order in which terms are added or partial sums are merged.
//!
//! Floating-point addition is not associative, so a sum split across node ranges, threads or
//! MPI ranks usually changes its last bits with the split. [`ExactSum`] instead adds every
//! term *exactly* into a long fixed-point integer (Kulisch's idea, in the "small
//! superaccumulator" form of R. M. Neal, *Fast exact summation using small and large
//! superaccumulators*, 2015): 68 signed 64-bit words, each holding 32 bits of the number plus
//! room for carries, cover every finite `f64` (bits `2^−1074 … 2^1024`) with headroom for
//! 2^29 terms between carry propagations. Integer addition is associative, so any order of
//! adds and merges gives the same words, and [`ExactSum::value`] rounds that one exact number
//! once (to nearest, ties to even; `f32` results are rounded to `f64` first).
//!
//! Merging is element-wise addition of the words ([`ExactSum::merge`]); after
//! [`ExactSum::to_words`] it is literally `MPI_SUM` on `MPI_INT64_T`, so partial sums from
//! any number of ranks combine with plain `MPI_Allreduce`.
//!
//! Non-finite terms are counted, not added: any NaN, or `+∞` together with `−∞`, makes the
//! value NaN; otherwise an infinity makes it that infinity (the IEEE result of a plain sum).

use crate::real::Real;

/// Number of 32-bit digit words: positions `0 … 32·68` relative to `2^−1074`.
const DIGITS: usize = 68;
/// Word holding the number of NaN terms.
const NAN: usize = DIGITS;
/// Word holding the number of `+∞` terms.
const POS_INF: usize = DIGITS + 1;
/// Word holding the number of `−∞` terms.
const NEG_INF: usize = DIGITS + 2;
/// Word bounding the digits: every `|digit| ≤ (load + 1) · 2^32`.
const LOAD: usize = DIGITS + 3;
/// Carries are propagated once the load reaches this (far below the `2^31` the words allow).
const LOAD_LIMIT: i64 = 1 << 29;
/// Pending terms are moved into the load counter after this many.
const PENDING_LIMIT: u32 = 1 << 20;

/// Number of `i64` words in [`ExactSum::to_words`]: 68 digits, three non-finite counts and a
/// load counter. The layout is stable (part of the C ABI's merge protocol).
pub const EXACT_SUM_WORDS: usize = DIGITS + 4;

/// An exact, order-independent sum of `f32`/`f64` terms (see the [module docs](self)).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct ExactSum {
    words: [i64; EXACT_SUM_WORDS],
    /// Terms added since the words' load was last updated (kept apart from the words so that
    /// counting is a register increment, not a memory round trip in the add loop).
    pending: u32,
}

impl core::fmt::Debug for ExactSum {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ExactSum")
            .field("value", &self.value::<f64>())
            .finish()
    }
}

impl Default for ExactSum {
    fn default() -> Self {
        Self::new()
    }
}

impl ExactSum {
    /// The empty sum (value `+0`).
    pub const fn new() -> Self {
        ExactSum {
            words: [0; EXACT_SUM_WORDS],
            pending: 0,
        }
    }

    /// Adds `x` exactly.
    #[inline]
    pub fn add<T: Real>(&mut self, x: T) {
        self.add_f64(x.to_f64());
    }

    /// Adds `x` exactly.
    #[inline]
    pub fn add_f64(&mut self, x: f64) {
        let bits = x.to_bits();
        if bits << 1 == 0 {
            return; // ±0 changes no sum
        }
        let field = ((bits >> 52) & 0x7ff) as u32;
        let negative = bits >> 63 != 0;
        let mut m = bits & ((1u64 << 52) - 1);
        if field == 0x7ff {
            let slot = match (m != 0, negative) {
                (true, _) => NAN,
                (false, false) => POS_INF,
                (false, true) => NEG_INF,
            };
            self.bump(slot);
            return;
        }
        // x = m · 2^(p − 1074) with p = field − 1 for normal numbers and 0 for subnormals.
        let p = if field == 0 {
            0
        } else {
            m |= 1u64 << 52;
            field - 1
        };
        let shift = p & 31;
        // `p ≤ 2045`, so `c ≤ 63` and `c + 2 < DIGITS`: the mask only tells the compiler.
        let c = (p >> 5) as usize & 63;
        // Branch-free sign: terms of random sign would mispredict half the time.
        let sign = -i64::from(negative);
        let lo = (((m << shift) & 0xffff_ffff) as i64 ^ sign) - sign;
        let high = m >> (32 - shift);
        let mid = ((high & 0xffff_ffff) as i64 ^ sign) - sign;
        let top = ((high >> 32) as i64 ^ sign) - sign;
        let w = &mut self.words;
        w[c] += lo;
        w[c + 1] += mid;
        w[c + 2] += top;
        self.pending += 1;
        if self.pending >= PENDING_LIMIT {
            self.settle();
        }
    }

    /// Adds every term of `xs`, in any order (the result does not depend on it).
    pub fn add_all<T: Real>(&mut self, xs: &[T]) {
        for &x in xs {
            self.add(x);
        }
    }

    /// Moves the pending count into the load (and propagates carries if it is due).
    fn settle(&mut self) {
        self.words[LOAD] = self.words[LOAD].saturating_add(i64::from(self.pending));
        self.pending = 0;
        if self.words[LOAD] >= LOAD_LIMIT {
            self.normalize();
        }
    }

    fn bump(&mut self, slot: usize) {
        if let Some(w) = self.words.get_mut(slot) {
            *w = w.saturating_add(1);
        }
    }

    /// Adds another partial sum (element-wise word addition: associative and commutative).
    pub fn merge(&mut self, other: &ExactSum) {
        self.settle();
        // `other` is read in place (no copy: 584 bytes matter on a small stack). Its digits
        // obey `|d| ≤ (load + pending + 1) 2^32`; the sum obeys the bound with the two loads
        // plus one, which stays far below `2^63` (each load is below `2^29 + 2^20`).
        let other_load = other.words[LOAD].saturating_add(i64::from(other.pending));
        for (k, (a, &b)) in self.words.iter_mut().zip(&other.words).enumerate() {
            if k < DIGITS {
                *a = a.wrapping_add(b);
            } else if k != LOAD {
                *a = a.saturating_add(b);
            }
        }
        self.words[LOAD] = self.words[LOAD]
            .saturating_add(other_load)
            .saturating_add(1);
        if self.words[LOAD] >= LOAD_LIMIT {
            self.normalize();
        }
    }

    /// Sums this partial sum over all processes in place: the words are brought to the form
    /// [`ExactSum::to_words`] returns, `sum_words` adds every other process's words into them
    /// (`MPI_Allreduce` with `MPI_SUM` on `MPI_INT64_T`), and they are read back as
    /// [`ExactSum::from_words`] would. No copy of the accumulator is made.
    pub fn exchange(&mut self, sum_words: impl FnOnce(&mut [i64; EXACT_SUM_WORDS])) {
        self.pending = 0;
        self.normalize();
        self.words[LOAD] = 1;
        sum_words(&mut self.words);
        self.words[LOAD] = self.words[LOAD].max(0);
        if self.words[LOAD] >= LOAD_LIMIT {
            self.normalize();
        }
    }

    /// Propagates carries: digits `0 … 66` end in `[0, 2^32)`, the top digit holds the sign.
    fn normalize(&mut self) {
        let mut carry = 0i64;
        for d in self.words.iter_mut().take(DIGITS) {
            let v = d.wrapping_add(carry);
            carry = v >> 32;
            *d = v & 0xffff_ffff;
        }
        if let Some(top) = self.words.get_mut(DIGITS - 1) {
            *top = top.wrapping_add(carry << 32);
        }
        self.words[LOAD] = 0;
    }

    /// The words to send to another rank: carries propagated, so that adding up to `2^29`
    /// such word arrays element-wise (`MPI_SUM` on `MPI_INT64_T`) and reading the result with
    /// [`ExactSum::from_words`] is the same as [`ExactSum::merge`].
    pub fn to_words(&self) -> [i64; EXACT_SUM_WORDS] {
        let mut s = *self;
        s.normalize();
        s.words[LOAD] = 1;
        s.words
    }

    /// A sum from words made by [`ExactSum::to_words`] (or element-wise sums of them).
    pub fn from_words(words: [i64; EXACT_SUM_WORDS]) -> Self {
        let mut s = ExactSum { words, pending: 0 };
        s.words[LOAD] = s.words[LOAD].max(0);
        if s.words[LOAD] >= LOAD_LIMIT {
            s.normalize();
        }
        s
    }

    /// The exact sum rounded once to `T` (to nearest, ties to even; for `f32` via `f64`).
    /// Values below `f64`'s normal range may round twice; an exactly zero sum is `+0`.
    pub fn value<T: Real>(&self) -> T {
        let w = &self.words;
        let (nan, pos, neg) = (w[NAN], w[POS_INF], w[NEG_INF]);
        if nan > 0 || (pos > 0 && neg > 0) {
            return T::from_f64(f64::NAN);
        }
        if pos > 0 {
            return T::INFINITY;
        }
        if neg > 0 {
            return -T::INFINITY;
        }
        // Two streaming passes over the digits, no copy of the accumulator: the first
        // propagates the carries to find the sign (the top digit of the normalized number),
        // the second normalizes again and, for a negative sum, negates and normalizes the
        // digits on the fly, keeping the three highest non-zero magnitude digits seen so far
        // and whether anything below them is non-zero.
        let digits = &w[..DIGITS];
        let mut carry = 0i64;
        let mut top_digit = 0i64;
        for (k, &d) in digits.iter().enumerate() {
            let v = d.wrapping_add(carry);
            if k + 1 == DIGITS {
                top_digit = v;
            }
            carry = v >> 32;
        }
        let negative = top_digit < 0;
        let (mut carry, mut neg_carry) = (0i64, 0i64);
        // Magnitude digits at positions k − 2, k − 1, k (rolling), and at the highest
        // non-zero position found so far.
        let mut window = [0u64; 3];
        let mut found: Option<(usize, [u64; 3], bool)> = None;
        let mut sticky_rest = false; // any non-zero magnitude digit below position k − 2
        for (k, &d) in digits.iter().enumerate() {
            let last = k + 1 == DIGITS;
            let v = d.wrapping_add(carry);
            carry = v >> 32;
            let n = if last { v } else { v & 0xffff_ffff };
            let m = if negative {
                let u = n.wrapping_neg().wrapping_add(neg_carry);
                neg_carry = u >> 32;
                if last {
                    u
                } else {
                    u & 0xffff_ffff
                }
            } else {
                n
            };
            sticky_rest |= window[0] != 0;
            window = [window[1], window[2], m as u64];
            if m != 0 {
                found = Some((k, window, sticky_rest));
            }
        }
        let Some((h, [d2, d1, dh], sticky_rest)) = found else {
            return T::ZERO;
        };
        // Bits from 2^(32·66 − 1074) = 2^1038 up: beyond every finite number.
        if h >= DIGITS - 2 {
            return if negative { -T::INFINITY } else { T::INFINITY };
        }
        // 64-bit window with its top bit set, the bits below it folded into a sticky bit.
        let top = (dh << 32) | d1;
        let lz = top.leading_zeros();
        let (window, lost) = if lz == 0 {
            (top, d2)
        } else {
            let filled = (top << lz) | (d2 >> (32 - lz));
            (filled, d2 & ((1u64 << (32 - lz)) - 1))
        };
        let sticky = u64::from(lost != 0 || sticky_rest);
        // The value is `window · 2^e` (digit `k` weighs `2^(32 k − 1074)`); the integer
        // conversion rounds to nearest even, exactly as rounding the whole number would.
        let e = 32 * (h as i32 - 1) - 1074 - lz as i32;
        let v = scale_f64((window | sticky) as f64, e);
        let v = if negative { -v } else { v };
        T::from_f64(v)
    }
}

/// `x · 2^e` in steps of normal powers of two (exact unless the result leaves the normal range).
fn scale_f64(mut x: f64, mut e: i32) -> f64 {
    for _ in 0..4 {
        let step = e.clamp(-1022, 1023);
        x *= f64::from_bits(((step + 1023) as u64) << 52);
        e -= step;
        if e == 0 {
            break;
        }
    }
    x
}
