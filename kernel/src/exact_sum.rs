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
//!
//! **Blocks.** Adding a term only stores it in a small buffer (64 terms on 64-bit hosts; none
//! on narrower targets, whose small stacks add every term on its own). A full buffer is summed exactly with plain `f64` arithmetic the compiler
//! vectorises, and only the block's partial sums reach the digits: Rump, Ogita and Oishi's
//! error-free extraction (*Accurate floating-point summation part I*, 2008) against a power of
//! two `σ ≥ 2^(b+1) · max |t|` (`2^b` terms a block) splits every term exactly into a high
//! part, whose sum over the block is exact in any order, and a remainder below `2^−53 σ`.
//! Two such levels take every bit of the terms within about `2^−39` of the block's largest;
//! one more pass of two levels is made if bits remain, and what is still left (a block
//! spanning more than some 180 binades) is added term by term, as are blocks holding a
//! non-finite term or a term of `2^1016` or more. The sum is exact either way, so the value
//! and the words are those of adding every term on its own, bit for bit
//! (`host-tests/tests/exact_sum_blocks.rs` keeps that path as the reference). The common
//! block (every bit in the first two levels) is read twice (maximum, extraction) and never
//! written.
//!
//! **Loops.** A loop that adds a few terms per row (CG's inner products) uses [`Gather`]: its
//! rows go to a stack block whose fill count stays in a register, and each column is summed
//! as a block when full, so a term costs a store instead of a buffered add.

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

/// Terms buffered before they are summed as one block: `2^BLOCK_BITS` = 64 on 64-bit hosts.
#[cfg(target_pointer_width = "64")]
const BLOCK_BITS: i32 = 6;
/// Terms a block holds.
#[cfg(target_pointer_width = "64")]
const BLOCK: usize = 1 << BLOCK_BITS;
/// Narrower targets keep no block: their stacks are small (a Cortex-M4F has 64 KiB of RAM in
/// all, and the footprint run's multigrid angle solve had 16 bytes to spare), so every term
/// takes the per-term path and an accumulator keeps its old size (584 bytes).
#[cfg(not(target_pointer_width = "64"))]
const BLOCK_BITS: i32 = 0;
#[cfg(not(target_pointer_width = "64"))]
const BLOCK: usize = 0;
/// Independent lanes of the block loops (kept in vector registers by the compiler).
const LANES: usize = 4;
/// Passes of two extraction levels a block gets before its remaining low parts are added
/// one by one.
const PASSES: usize = 2;

/// The fixed-point digits and their bookkeeping (Neal's small superaccumulator).
#[derive(Clone, Copy)]
struct Digits {
    words: [i64; EXACT_SUM_WORDS],
    /// Terms added since the words' load was last updated (kept apart from the words so that
    /// counting is a register increment, not a memory round trip in the add loop).
    pending: u32,
    /// Terms in the owning [`ExactSum`]'s block not yet added to the words (here, in what
    /// would be padding, so that an accumulator without a block is no larger than before).
    buffered: u32,
}

/// An exact, order-independent sum of `f32`/`f64` terms (see the [module docs](self)).
#[derive(Clone, Copy)]
pub struct ExactSum {
    digits: Digits,
    block: [f64; BLOCK],
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

/// Two sums are equal when they hold the same exact number and the same non-finite counts
/// (whatever the order, blocking or carries of their terms).
impl PartialEq for ExactSum {
    fn eq(&self, other: &Self) -> bool {
        self.to_words() == other.to_words()
    }
}

impl Eq for ExactSum {}

impl ExactSum {
    /// The empty sum (value `+0`).
    pub const fn new() -> Self {
        ExactSum {
            digits: Digits {
                words: [0; EXACT_SUM_WORDS],
                pending: 0,
                buffered: 0,
            },
            block: [0.0; BLOCK],
        }
    }

    /// Adds `x` exactly.
    #[inline]
    pub fn add<T: Real>(&mut self, x: T) {
        self.add_f64(x.to_f64());
    }

    /// Adds `x` exactly (no block on 32-bit targets: straight into the digits, inline, as
    /// before blocks, so that the solvers' stack frames on a Cortex-M do not grow).
    #[cfg(not(target_pointer_width = "64"))]
    #[inline]
    pub fn add_f64(&mut self, x: f64) {
        self.digits.add(x);
    }

    /// Adds `x` exactly (buffered: the block is summed when it is full).
    #[cfg(target_pointer_width = "64")]
    #[inline]
    pub fn add_f64(&mut self, x: f64) {
        let len = self.digits.buffered as usize;
        match self.block.get_mut(len) {
            Some(slot) => {
                *slot = x;
                self.digits.buffered = len as u32 + 1;
                if len + 1 == BLOCK {
                    self.flush();
                }
            }
            None => self.add_cold(x), // no block (narrow targets); else `len < BLOCK` between calls
        }
    }

    /// The per-term path, out of line (keeps the buffered add small where it is inlined).
    #[cfg(target_pointer_width = "64")]
    #[cold]
    #[inline(never)]
    fn add_cold(&mut self, x: f64) {
        self.digits.add(x);
    }

    /// Adds every term of `xs`, in any order (the result does not depend on it).
    pub fn add_all<T: Real>(&mut self, xs: &[T]) {
        for &x in xs {
            self.add(x);
        }
    }

    /// Sums the buffered terms into the digits.
    fn flush(&mut self) {
        let n = self.digits.buffered as usize; // at most BLOCK (`add_block` checks)
        self.digits.buffered = 0;
        if let Some(terms) = self.block.get_mut(..n) {
            add_block(&mut self.digits, terms);
        }
    }

    /// Adds another partial sum (element-wise word addition: associative and commutative).
    pub fn merge(&mut self, other: &ExactSum) {
        self.digits.merge(&other.digits);
        let n = other.digits.buffered as usize; // at most BLOCK
        for &x in other.block.get(..n).unwrap_or(&[]) {
            self.add_f64(x);
        }
    }

    /// Sums this partial sum over all processes in place: the words are brought to the form
    /// [`ExactSum::to_words`] returns, `sum_words` adds every other process's words into them
    /// (`MPI_Allreduce` with `MPI_SUM` on `MPI_INT64_T`), and they are read back as
    /// [`ExactSum::from_words`] would. No copy of the accumulator is made.
    pub fn exchange(&mut self, sum_words: impl FnOnce(&mut [i64; EXACT_SUM_WORDS])) {
        self.flush();
        let d = &mut self.digits;
        d.pending = 0;
        d.normalize();
        d.words[LOAD] = 1;
        sum_words(&mut d.words);
        d.words[LOAD] = d.words[LOAD].max(0);
        if d.words[LOAD] >= LOAD_LIMIT {
            d.normalize();
        }
    }

    /// The words to send to another rank: carries propagated, so that adding up to `2^29`
    /// such word arrays element-wise (`MPI_SUM` on `MPI_INT64_T`) and reading the result with
    /// [`ExactSum::from_words`] is the same as [`ExactSum::merge`].
    pub fn to_words(&self) -> [i64; EXACT_SUM_WORDS] {
        let mut s = *self;
        s.flush();
        s.digits.normalize();
        s.digits.words[LOAD] = 1;
        s.digits.words
    }

    /// A sum from words made by [`ExactSum::to_words`] (or element-wise sums of them).
    pub fn from_words(words: [i64; EXACT_SUM_WORDS]) -> Self {
        let mut s = ExactSum::new();
        s.digits.words = words;
        let d = &mut s.digits;
        d.words[LOAD] = d.words[LOAD].max(0);
        if d.words[LOAD] >= LOAD_LIMIT {
            d.normalize();
        }
        s
    }

    /// The exact sum rounded once to `T` (to nearest, ties to even; for `f32` via `f64`).
    /// Values below `f64`'s normal range may round twice; an exactly zero sum is `+0`.
    pub fn value<T: Real>(&self) -> T {
        if self.digits.buffered == 0 {
            return self.digits.value();
        }
        self.value_flushed()
    }

    /// [`ExactSum::value`] of a sum with buffered terms: a copy with its block summed. Out of
    /// line, so that the copy's stack frame exists only when there is a block to sum (never
    /// on 32-bit targets, whose small stacks would otherwise pay for it in every caller).
    #[cold]
    #[inline(never)]
    fn value_flushed<T: Real>(&self) -> T {
        let mut s = *self;
        s.flush();
        s.digits.value()
    }
}

/// Terms of a loop, a row of `C` at a time, gathered for exact sums: column `c` goes to sum
/// `c` (or every column to one sum, [`Gather::one`]). On 64-bit hosts the rows are kept in a
/// stack block of 64 and each full column is summed at once (`add_block`), so a term costs
/// a store where [`ExactSum::add`] keeps its own fill count in memory; on narrower targets
/// (small stacks) each term goes straight to its sum. The block is summed when full and when
/// the gather is dropped, so the sums are complete once it is gone. The result is the exact
/// sum either way: the same words and bits as adding every term on its own.
pub struct Gather<'s, const C: usize> {
    sums: &'s mut [ExactSum],
    #[cfg(target_pointer_width = "64")]
    block: [[f64; BLOCK]; C],
    #[cfg(target_pointer_width = "64")]
    len: usize,
}

impl<'s, const C: usize> Gather<'s, C> {
    /// Column `c` into `sums[c]`.
    #[inline]
    pub fn lanes(sums: &'s mut [ExactSum; C]) -> Self {
        Self::over(sums)
    }

    /// Every column into `sum`.
    #[inline]
    pub fn one(sum: &'s mut ExactSum) -> Self {
        Self::over(core::slice::from_mut(sum))
    }

    #[inline]
    fn over(sums: &'s mut [ExactSum]) -> Self {
        Gather {
            sums,
            #[cfg(target_pointer_width = "64")]
            block: [[0.0; BLOCK]; C],
            #[cfg(target_pointer_width = "64")]
            len: 0,
        }
    }

    /// The sum column `c` goes to.
    #[inline(always)]
    fn target(sums: &mut [ExactSum], c: usize) -> Option<&mut ExactSum> {
        let last = sums.len().saturating_sub(1);
        sums.get_mut(c.min(last))
    }

    /// Adds one row of terms, `row[c]` to column `c`'s sum.
    #[cfg(not(target_pointer_width = "64"))]
    #[inline(always)]
    pub fn push<T: Real>(&mut self, row: [T; C]) {
        for (c, t) in row.into_iter().enumerate() {
            if let Some(s) = Self::target(self.sums, c) {
                s.add(t);
            }
        }
    }

    /// Adds one row of terms, `row[c]` to column `c`'s sum.
    #[cfg(target_pointer_width = "64")]
    #[inline(always)]
    pub fn push<T: Real>(&mut self, row: [T; C]) {
        let n = self.len % BLOCK; // `len < BLOCK` between calls: the mask only tells the compiler
        for (col, t) in self.block.iter_mut().zip(row) {
            if let Some(slot) = col.get_mut(n) {
                *slot = t.to_f64();
            }
        }
        self.len = n + 1;
        if self.len == BLOCK {
            self.flush();
        }
    }

    /// Sums the gathered rows into their sums (the fill count stays a local of the caller's
    /// loop: only the block and the sums are passed).
    #[cfg(target_pointer_width = "64")]
    #[inline]
    fn flush(&mut self) {
        let n = core::mem::take(&mut self.len);
        flush_columns(self.sums, &mut self.block, n);
    }
}

/// Sums the first `n` terms of each column of `block` into its sum ([`Gather`]).
#[cfg(target_pointer_width = "64")]
#[inline(never)]
fn flush_columns<const C: usize>(sums: &mut [ExactSum], block: &mut [[f64; BLOCK]; C], n: usize) {
    for (c, col) in block.iter_mut().enumerate() {
        if let (Some(s), Some(terms)) = (Gather::<C>::target(sums, c), col.get_mut(..n)) {
            add_block(&mut s.digits, terms);
        }
    }
}

/// Sums what is left in the block (nothing to do where terms go straight to their sums).
impl<const C: usize> Drop for Gather<'_, C> {
    #[inline]
    fn drop(&mut self) {
        #[cfg(target_pointer_width = "64")]
        if self.len > 0 {
            self.flush();
        }
    }
}

/// Adds `terms` (at most [`BLOCK`]; more take the per-term path) exactly to `digits` with a
/// few additions for the whole block (see "Blocks" in the [module docs](self)), using
/// `terms` as scratch (their values are left unspecified). Level by level, each term `t` is
/// split exactly into `q + t'` against `σ`, a power of two at least `2^(b+1)` times the
/// terms' `max |t|` (`2^b` = [`BLOCK`]); the `q` are multiples of `2^−53 σ` and their sum is
/// at most `σ` in magnitude, so their plain `f64` sum is exact in any order and is added as
/// one term. Non-finite terms and terms too large for a finite `σ` take the per-term path.
///
/// The first pass only reads the terms (the common case, every bit taken in two levels, needs
/// no stores and no copy); only when bits remain are the remainders formed in place again.
fn add_block(digits: &mut Digits, terms: &mut [f64]) {
    if terms.is_empty() {
        return;
    }
    if terms.len() > BLOCK {
        // More terms than the bound below holds for (no caller passes them): per term.
        return terms.iter().for_each(|&t| digits.add(t));
    }
    let max = max_abs(terms);
    let Some(k) = sigma_exponent(max) else {
        // ±∞ or a term too large for a finite σ: per term.
        return terms.iter().for_each(|&t| digits.add(t));
    };
    // Two levels a pass: the second's σ follows from the first's bound `|t'| ≤ 2^−53 σ`.
    let levels = |k: i32| (pow2_or_zero(k), pow2_or_zero(k - 53 + BLOCK_BITS + 1));
    let (s1, s2) = levels(k);
    let (sum1, sum2, mut max) = extract2::<false>(terms, s1, s2);
    if sum1.is_nan() {
        // A NaN term (the maximum and σ may be wrong; nothing is touched yet): per term.
        return terms.iter().for_each(|&t| digits.add(t));
    }
    digits.add(sum1);
    digits.add(sum2);
    if max == 0.0 {
        return;
    }
    // Bits remain: form the remainders in place (the same splits), then more passes.
    extract2::<true>(terms, s1, s2);
    for _ in 1..PASSES {
        let Some(k) = sigma_exponent(max) else {
            break; // unreachable: the remainders are far below the first σ
        };
        let (s1, s2) = levels(k);
        let (sum1, sum2, m) = extract2::<true>(terms, s1, s2);
        digits.add(sum1);
        digits.add(sum2);
        max = m;
        if max == 0.0 {
            return;
        }
    }
    // Low parts left (a block spanning more than some 180 binades): one by one.
    terms.iter().for_each(|&t| digits.add(t));
}

/// `max |t|` over `terms` (meaningless when a term is NaN: see [`greater`]).
fn max_abs(terms: &[f64]) -> f64 {
    max_lanes(terms).iter().fold(0.0, |a, &b| greater(a, b))
}

/// [`max_abs`] per lane (out of line, for the same reason as [`extract2_lanes`]).
#[inline(never)]
fn max_lanes(terms: &[f64]) -> [f64; LANES] {
    let mut m = [0.0f64; LANES];
    let (chunks, tail) = terms.as_chunks::<LANES>();
    for c in chunks {
        // Indexed lanes of fixed-size arrays: what the compiler turns into vector operations.
        for j in 0..LANES {
            m[j] = greater(m[j], c[j].abs());
        }
    }
    for (m, t) in m.iter_mut().zip(tail) {
        *m = greater(*m, t.abs());
    }
    m
}

/// Two extraction levels (see [`split`]) of every term `t` into `q1 + q2 + t''`; returns
/// `(Σ q1, Σ q2, max |t''|)`, and when `STORE` leaves `t''` in place of `t` (else the terms
/// are only read).
fn extract2<const STORE: bool>(terms: &mut [f64], s1: f64, s2: f64) -> (f64, f64, f64) {
    let [q1, q2, m] = extract2_lanes::<STORE>(terms, s1, s2);
    let sum = |q: [f64; LANES]| q.iter().fold(0.0, |a, &b| a + b);
    (sum(q1), sum(q2), m.iter().fold(0.0, |a, &b| greater(a, b)))
}

/// [`extract2`]'s pass, per lane: `[Σ q1, Σ q2, max |t''|]` of the terms `j mod LANES`. Out
/// of line so that the compiler lays each accumulator's lanes out in one vector (folded in
/// line, it paired `q1` and `q2` lanes for the final sums and shuffled them every step).
#[inline(never)]
fn extract2_lanes<const STORE: bool>(terms: &mut [f64], s1: f64, s2: f64) -> [[f64; LANES]; 3] {
    let (mut q1, mut q2, mut m) = ([0.0f64; LANES], [0.0f64; LANES], [0.0f64; LANES]);
    let (chunks, tail) = terms.as_chunks_mut::<LANES>();
    #[inline(always)]
    fn step<const STORE: bool>(t: &mut f64, s: (f64, f64), q: (&mut f64, &mut f64), m: &mut f64) {
        let mut v = *t;
        *q.0 += split(&mut v, s.0);
        *q.1 += split(&mut v, s.1);
        *m = greater(*m, v.abs());
        if STORE {
            *t = v;
        }
    }
    for c in chunks {
        for j in 0..LANES {
            step::<STORE>(&mut c[j], (s1, s2), (&mut q1[j], &mut q2[j]), &mut m[j]);
        }
    }
    for (j, t) in tail.iter_mut().enumerate() {
        if let (Some(a), Some(b), Some(m)) = (q1.get_mut(j), q2.get_mut(j), m.get_mut(j)) {
            step::<STORE>(t, (s1, s2), (a, b), m);
        }
    }
    [q1, q2, m]
}

/// The exponent `k = e + 2 + b` of the extraction constant `σ = 2^k` for terms of magnitude
/// at most `max < 2^(e+1)` in a block of at most `2^b` = [`BLOCK`] terms, so that
/// `BLOCK · max ≤ σ/2`; `None` when `σ` would not be finite (`max ≥ 2^(1022−b)`, `±∞`).
fn sigma_exponent(max: f64) -> Option<i32> {
    let field = ((max.to_bits() >> 52) & 0x7ff) as i32;
    let k = field - 1023 + 2 + BLOCK_BITS;
    (k <= 1023).then_some(k)
}

/// `2^k` for `−1021 < k ≤ 1023`; zero for smaller `k`. A zero `σ` makes `q = t`: the terms'
/// plain sum is then exact, every partial sum being a multiple of `2^−1074` smaller than
/// `σ_k ≤ 2^−1021` in magnitude (bits a subnormal holds).
fn pow2_or_zero(k: i32) -> f64 {
    if k <= -1021 {
        0.0
    } else {
        f64::from_bits(((k.min(1023) + 1023) as u64) << 52)
    }
}

/// `a` if `a > b`, else `b` (one `maxpd`, in place on `a`). With a NaN among the terms a
/// running maximum may come out NaN or too small; [`add_block`] never uses it then: a NaN
/// `σ` takes the per-term path, and otherwise the first pass's `Σ q1` is NaN and the
/// per-term path is taken before the digits or the terms are touched.
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// One extraction step: `t` becomes `t' = t − q` and `q = (σ + t) − σ` is returned. Exact
/// when `|t| ≤ σ/2` (σ a power of two, or zero): `σ + t` lies in `[σ/2, 3σ/2]`, so `q` is a
/// multiple of `u σ` (`u = 2^−53`) computed without error (Sterbenz), and `t'` is the
/// rounding error of `σ + t`, representable, with `|t'| ≤ u σ`. With `n · max |t| ≤ σ/2` and
/// `n ≤ 2^52`, every partial sum of the `q` is a multiple of `u σ` of magnitude at most
/// `Σ (|t| + u σ) ≤ σ`: representable, so their sum in any order is exact (Rump, Ogita and
/// Oishi, *Accurate floating-point summation part I*, SIAM J. Sci. Comput. 31, 2008,
/// `ExtractVector`).
#[inline(always)]
fn split(t: &mut f64, sigma: f64) -> f64 {
    let q = (sigma + *t) - sigma;
    *t -= q;
    q
}

impl Digits {
    /// Adds `x` exactly to the digits (the per-term path).
    #[inline]
    fn add(&mut self, x: f64) {
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

    /// Adds another sum's digits (element-wise word addition: associative and commutative).
    fn merge(&mut self, other: &Digits) {
        self.settle();
        // `other` is read in place (no copy: 584 bytes on a 32-bit target matter on a small stack). Its digits
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

    /// The digits' exact sum rounded once to `T` (to nearest, ties to even; for `f32` via `f64`).
    /// Values below `f64`'s normal range may round twice; an exactly zero sum is `+0`.
    fn value<T: Real>(&self) -> T {
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
