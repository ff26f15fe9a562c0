//! Batina's edge stiffness from coordinates.

use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::vector;

/// Writes Batina's stiffness `k_ij = 1 / |r_i − r_j|^p` for every directed edge of `graph`
/// into `stiffness` (Samareh eq. 2, Yang & Özgen §2.1; `p = 1` is the papers' choice, larger
/// `p` stiffens small cells more; `p = 0` gives the uniform graph Laplacian).
///
/// `p = 1` is computed as `1 / |d|` and `p = 2` as `1 / (d·d)` (no `powf`), other exponents as
/// `1 / powf(|d|, p)`. `|r_i − r_j|` and `|r_j − r_i|` are bit-identical, so the result is
/// exactly symmetric, as [`SpringSystem`](super::SpringSystem) requires.
///
/// # Errors
/// Nothing is written on error: `points.len() != graph.node_count()` or
/// `stiffness.len() != graph.edge_count()` ([`Error::LengthMismatch`]); a NaN/infinite
/// coordinate ([`Error::NonFinite`]); `exponent` not finite or negative
/// ([`Error::InvalidParameter`]); an edge of zero length, or so short that `k` overflows
/// ([`Error::ZeroLengthEdge`], the first such directed edge); an edge so long that `k`
/// underflows to zero ([`Error::NonPositive`] with `arg = "stiffness"` and the edge's source
/// node as `position`). Edges longer than `√MAX` (where `|d|²` overflows) get their stiffness
/// from the rescaled length.
pub fn batina_stiffness<T: Real, const D: usize>(
    graph: &Graph<'_>,
    points: &[[T; D]],
    exponent: T,
    stiffness: &mut [T],
) -> Result<()> {
    stiffness_with(graph, points, exponent, stiffness, |d2| T::ONE / d2.sqrt())
}

/// [`batina_stiffness`] with the fast inverse square root (feature `micromath`; **excluded
/// from bit parity**, and used by no other kernel routine): for `p = 1`,
/// `k = `[`Real::fast_inv_sqrt`]`(d·d)` instead of `1 / sqrt(d·d)` (no square root, no
/// division); other exponents, and squared lengths that are not normal numbers, use the
/// exact formulas. For `f32` each `k` is within
/// [`FAST_INV_SQRT_F32_MAX_REL_ERROR`](crate::real::FAST_INV_SQRT_F32_MAX_REL_ERROR) (4.8e-6)
/// relative of [`batina_stiffness`]'s (tested on host and on target); for `f64` the two are
/// identical. Still exactly symmetric (`k_ij` and `k_ji` come from the same `d·d` bits), with
/// the same validation.
///
/// # Errors
/// Those of [`batina_stiffness`].
#[cfg(feature = "micromath")]
pub fn batina_stiffness_fast<T: Real, const D: usize>(
    graph: &Graph<'_>,
    points: &[[T; D]],
    exponent: T,
    stiffness: &mut [T],
) -> Result<()> {
    stiffness_with(graph, points, exponent, stiffness, |d2| {
        if d2 >= T::MIN_POSITIVE {
            d2.fast_inv_sqrt()
        } else {
            T::ONE / d2.sqrt()
        }
    })
}

/// The body of [`batina_stiffness`], with `inv_len(d·d)` giving `1 / |d|` for `p = 1`.
fn stiffness_with<T: Real, const D: usize>(
    graph: &Graph<'_>,
    points: &[[T; D]],
    exponent: T,
    stiffness: &mut [T],
    inv_len: impl Fn(T) -> T,
) -> Result<()> {
    check::len("points", points.len(), graph.node_count())?;
    check::len("stiffness", stiffness.len(), graph.edge_count())?;
    check::finite_items("points", points)?;
    if !(exponent.is_finite() && exponent >= T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "exponent",
            reason: "must be finite and >= 0",
        });
    }
    // `Ok(k)`, or the error of the edge: zero length (or so short that `k` overflows), or so
    // long that `k` underflows to 0.
    let k = |i: usize, j: usize| -> Result<T> {
        let zero_length = Error::ZeroLengthEdge { from: i, to: j };
        let (Some(a), Some(b)) = (points.get(i), points.get(j)) else {
            return Err(zero_length);
        };
        let d = vector::sub(*b, *a);
        let d2 = vector::norm_sq(d);
        let k = if d2.is_finite() && d2 > T::ZERO {
            if exponent == T::ONE {
                inv_len(d2)
            } else if exponent == T::TWO {
                T::ONE / d2
            } else {
                T::ONE / d2.sqrt().powf(exponent)
            }
        } else {
            // |d|² overflowed (an edge longer than ~1e154 in f64) or underflowed: use the
            // rescaled length, so a long edge gets its tiny stiffness instead of 1/∞ = 0.
            let len = vector::norm_robust(d);
            if len == T::ZERO {
                return Err(zero_length);
            }
            if exponent == T::ONE {
                T::ONE / len
            } else if exponent == T::TWO {
                T::ONE / (len * len)
            } else {
                T::ONE / len.powf(exponent)
            }
        };
        if !k.is_finite() {
            Err(zero_length)
        } else if k <= T::ZERO {
            Err(Error::NonPositive {
                arg: "stiffness",
                position: i,
            })
        } else {
            Ok(k)
        }
    };
    // Validate every edge first, then write: on error `stiffness` is untouched.
    for (i, _, row) in graph.rows() {
        for &j in row {
            k(i, j as usize)?;
        }
    }
    for (i, first, row) in graph.rows() {
        let out = stiffness
            .get_mut(first..first + row.len())
            .unwrap_or(&mut []);
        for (o, &j) in out.iter_mut().zip(row) {
            *o = k(i, j as usize).unwrap_or(T::ZERO);
        }
    }
    Ok(())
}
