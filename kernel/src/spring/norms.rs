//! Euclidean norms of whole value fields that neither overflow nor underflow.
//!
//! `Σ x²` overflows once a component exceeds `√MAX` (1.3e154 for `f64`, 1.8e19 for `f32`) and
//! underflows to 0 below `√MIN_POSITIVE` (1.5e-154, 1.1e-19). A relative residual built from
//! such sums is then `inf/inf = NaN`, `finite/inf = 0` or `0/0 → 0`, and a solve stops early
//! with a wrong answer that claims convergence. So every norm here is accumulated plainly
//! together with the largest `|x|` ([`SumSq`]); when the plain sum is outside the range where
//! it is exact to rounding, the caller accumulates once more with every term multiplied by
//! `2^−e`, `2^e` being the largest `|x|`'s binade. Powers of two scale exactly, so the
//! rescaled sum has the bits the plain sum would have had with an unlimited exponent range:
//! a field multiplied by `2^k` has its norm multiplied by exactly `2^k` and its relative
//! residual unchanged. Norms are kept as `value · 2^exp` ([`Norm`]) until a ratio is formed.
//!
//! The sums are exact ([`ExactSum`]) and the maximum is order-independent, so a norm does not
//! depend on the order of its terms or on how a caller splits the nodes.

use crate::exact_sum::ExactSum;
use crate::real::Real;

/// An exact running `Σ x²` (each `x²` rounded once) and `max |x|`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SumSq<T> {
    /// `Σ x²` (terms may have overflowed or underflowed).
    pub(crate) sum: ExactSum,
    /// `max |x|` (exact).
    pub(crate) max: T,
}

impl<T: Real> SumSq<T> {
    /// The empty sum.
    pub(crate) const fn new() -> Self {
        SumSq {
            sum: ExactSum::new(),
            max: T::ZERO,
        }
    }

    /// Adds `x²` (and `|x|` to the maximum).
    #[inline]
    pub(crate) fn add(&mut self, x: T) {
        self.sum.add(x * x);
        self.max = self.max.max(x.abs());
    }

    /// Adds `|v|²` summed first within `v` (the angle springs' node-by-node order) and every
    /// `|v_c|` to the maximum.
    #[inline]
    pub(crate) fn add_vector<const D: usize>(&mut self, v: &[T; D]) {
        self.sum.add(crate::vector::norm_sq(*v));
        for &x in v {
            self.max = self.max.max(x.abs());
        }
    }

    /// Merges the sum and maximum over all processes of `comm`.
    pub(crate) fn merge_over<C: crate::spring::Collective<T> + ?Sized>(&mut self, comm: &C) {
        comm.sum_exact(&mut [core::slice::from_mut(&mut self.sum)]);
        let mut m = [self.max];
        comm.max(&mut m);
        self.max = m[0];
    }

    /// The norm `√Σ x²` if the plain sum is exact to rounding (finite, and either large enough
    /// that no underflowed term matters or made of zeros only), else `Err(e)`: sum again with
    /// every term multiplied by [`Real::pow2`]`(−e)` and finish with [`Norm::from_sum`]`(s, e)`.
    #[inline]
    pub(crate) fn plain(&self) -> Result<Norm<T>, i32> {
        if !self.max.is_finite() {
            // A term itself overflowed: the norm is genuinely not representable.
            return Ok(Norm {
                value: T::INFINITY,
                exp: 0,
            });
        }
        let sum: T = self.sum.value();
        if sum.is_finite() && (sum >= T::MIN_POSITIVE / T::EPSILON || self.max == T::ZERO) {
            Ok(Norm::from_sum(sum, 0))
        } else {
            Err(scale_exponent(self.max))
        }
    }
}

/// The exponent `e` that brings `max` (finite, ≥ 0) into `[1, 2)` when multiplied by `2^−e`,
/// clamped so that `2^−e` and `2^e` are normal numbers.
#[inline]
pub(crate) fn scale_exponent<T: Real>(max: T) -> i32 {
    let limit = T::MAX.exponent() - 1;
    max.exponent().clamp(-limit, limit)
}

/// `x · 2^e` for any `e` (in steps that stay within the normal powers of two).
#[inline]
pub(crate) fn scale_by<T: Real>(mut x: T, mut e: i32) -> T {
    let step = T::MAX.exponent() - 1;
    // At most a few steps: exponents here are differences of two clamped exponents.
    for _ in 0..8 {
        if e > step {
            x *= T::pow2(step);
            e -= step;
        } else if e < -step {
            x *= T::pow2(-step);
            e += step;
        } else {
            break;
        }
    }
    x * T::pow2(e)
}

/// A Euclidean norm stored as `value · 2^exp`, so it never overflows or underflows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Norm<T> {
    value: T,
    exp: i32,
}

impl<T: Real> Norm<T> {
    /// The norm of terms that were summed as `Σ (x · 2^−exp)²`.
    #[inline]
    pub(crate) fn from_sum(sum: T, exp: i32) -> Self {
        Norm {
            value: sum.sqrt(),
            exp,
        }
    }

    /// The same norm for values that were scaled by `2^−k` (multiplies it by `2^k`).
    #[inline]
    pub(crate) fn shifted(self, k: i32) -> Self {
        Norm {
            value: self.value,
            exp: self.exp.saturating_add(k),
        }
    }

    /// The norm as a number (`+∞` if it exceeds the range).
    #[inline]
    pub(crate) fn to_real(self) -> T {
        scale_by(self.value, self.exp)
    }

    /// `self / b`, or `self` when `b = 0` (the relative residual `‖r‖ / ‖b‖` of
    /// [`SolveOptions`](super::SolveOptions)).
    #[inline]
    pub(crate) fn relative_to(self, b: Norm<T>) -> T {
        if b.value > T::ZERO {
            scale_by(self.value / b.value, self.exp - b.exp)
        } else {
            self.to_real()
        }
    }
}

/// The power-of-two exponent `e` in which a stationary solve accumulates its sweeps'
/// `Σ (2^−e r)²`, from the initial residual and right-hand-side norms: 0 (plain sums, today's
/// bits) when both were summed plainly, else the larger of their exponents, so the sums stay in
/// range while the residual falls from `‖r₀‖` towards `tol · ‖b‖`.
#[inline]
pub(crate) fn sweep_exponent<T: Real>(r0: &Norm<T>, b: &Norm<T>) -> i32 {
    match (r0.exp, b.exp) {
        (0, 0) => 0,
        (er, eb) if b.value > T::ZERO && r0.value > T::ZERO => er.max(eb),
        (er, _) if r0.value > T::ZERO => er,
        (_, eb) => eb,
    }
}

/// A field's residual and right-hand side, node by node: what [`pair_norms`] measures.
pub(crate) trait Pairs<T: Real, const V: usize> {
    /// Calls `f(r_i, b_i)` for every node that counts (the free nodes of this process's
    /// rows, in node order): the residual `r_i = (b − A x)_i` and the right-hand side `b_i`.
    fn each<F: FnMut(&[T; V], &[T; V])>(&self, f: F);
}

/// [`pair_norms`] of a field stored as `x_c · 2^−exps[c]`, unscaled: every component is
/// brought to the largest component's scale first (factors 1 when unscaled) and the norms are
/// scaled back. The norms every [`Operator`](super::krylov::Operator) reports.
pub(crate) fn scaled_pair_norms<T, const V: usize, P, C>(
    pairs: &P,
    exps: &[i32; V],
    per_node: bool,
    comm: &C,
) -> (Norm<T>, Norm<T>)
where
    T: Real,
    P: Pairs<T, V>,
    C: crate::spring::Collective<T> + ?Sized,
{
    let top = exps.iter().copied().max().unwrap_or(0);
    let g = exps.map(|e| scale_by(T::ONE, e - top));
    let (r, b) = pair_norms(pairs, &g, per_node, comm);
    (r.shifted(top), b.shifted(top))
}

/// `(‖r‖₂, ‖b‖₂)` over every pair of `pairs`, merged over the processes of `comm`, without
/// overflow or underflow: summed plainly, and once more with every term multiplied by a power
/// of two when a plain sum is out of range (see the module documentation). Component `c` is
/// multiplied by `g[c]` first (a power of two: the scaled CG iterate's components brought to
/// one scale; 1 otherwise). `per_node` adds each node's `|v|²`, rounded, as one term (the
/// angle springs' order); otherwise every component's square is a term.
pub(crate) fn pair_norms<T, const V: usize, P, C>(
    pairs: &P,
    g: &[T; V],
    per_node: bool,
    comm: &C,
) -> (Norm<T>, Norm<T>)
where
    T: Real,
    P: Pairs<T, V>,
    C: crate::spring::Collective<T> + ?Sized,
{
    let mut rs = SumSq::new();
    let mut bs = SumSq::new();
    pairs.each(|r, b| {
        let (r, b) = (mul(r, g), mul(b, g));
        if per_node {
            rs.add_vector(&r);
            bs.add_vector(&b);
        } else {
            for (&r, &b) in r.iter().zip(&b) {
                rs.add(r);
                bs.add(b);
            }
        }
    });
    rs.merge_over(comm);
    bs.merge_over(comm);
    let (pr, pb) = (rs.plain(), bs.plain());
    if let (Ok(r), Ok(b)) = (pr, pb) {
        return (r, b);
    }
    // Second pass, each sum scaled by its own power of two; the first pass's accumulators
    // are reused (no more sums on the stack).
    let qr = T::pow2(-pr.err().unwrap_or(0));
    let qb = T::pow2(-pb.err().unwrap_or(0));
    let (sr, sb) = (&mut rs.sum, &mut bs.sum);
    (*sr, *sb) = (ExactSum::new(), ExactSum::new());
    pairs.each(|r, b| {
        let r = mul(r, g).map(|x| x * qr);
        let b = mul(b, g).map(|x| x * qb);
        if per_node {
            sr.add(crate::vector::norm_sq(r));
            sb.add(crate::vector::norm_sq(b));
        } else {
            for (&r, &b) in r.iter().zip(&b) {
                sr.add(r * r);
                sb.add(b * b);
            }
        }
    });
    comm.sum_exact(&mut [core::slice::from_mut(sr), core::slice::from_mut(sb)]);
    let (sr, sb) = (sr.value(), sb.value());
    (
        pr.unwrap_or_else(|e| Norm::from_sum(sr, e)),
        pb.unwrap_or_else(|e| Norm::from_sum(sb, e)),
    )
}

/// `a ⊙ g`, component by component.
#[inline]
fn mul<T: Real, const V: usize>(a: &[T; V], g: &[T; V]) -> [T; V] {
    let mut out = *a;
    for (o, &g) in out.iter_mut().zip(g) {
        *o *= g;
    }
    out
}
