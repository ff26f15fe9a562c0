//! Argument checks shared by every module: lengths, buffer sizes, finiteness, index bounds
//! and the mesh dimension. Each returns the typed [`Error`] a caller sees, so every entry
//! point reports the same failure the same way, and validates before it mutates anything.

use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;

/// Compile-time proof that `D` is a mesh dimension (2 or 3). Instantiating a function that
/// calls it with another `D` fails to compile, so no entry point needs a run-time check (or an
/// error variant) for it.
#[inline(always)]
pub(crate) const fn mesh_dim<const D: usize>() {
    const { assert!(D == 2 || D == 3, "the mesh dimension D must be 2 or 3") }
}

/// `actual == expected` ([`Error::LengthMismatch`] otherwise).
#[inline]
pub(crate) fn len(arg: &'static str, actual: usize, expected: usize) -> Result<()> {
    if actual == expected {
        Ok(())
    } else {
        Err(Error::LengthMismatch {
            arg,
            expected,
            actual,
        })
    }
}

/// A buffer holds at least `needed` items ([`Error::BufferTooSmall`] otherwise).
#[inline]
pub(crate) fn buffer(arg: &'static str, actual: usize, needed: usize) -> Result<()> {
    if actual >= needed {
        Ok(())
    } else {
        Err(Error::BufferTooSmall {
            arg,
            needed,
            actual,
        })
    }
}

/// Every component of every item finite ([`Error::NonFinite`] at the first item that is not).
#[inline]
pub(crate) fn finite_items<T: Real, const N: usize>(
    arg: &'static str,
    values: &[[T; N]],
) -> Result<()> {
    match crate::real::first_non_finite(values) {
        Some(position) => Err(Error::NonFinite { arg, position }),
        None => Ok(()),
    }
}

/// Every value finite ([`Error::NonFinite`] at the first that is not).
#[inline]
pub(crate) fn finite<T: Real>(arg: &'static str, values: &[T]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(position) => Err(Error::NonFinite { arg, position }),
        None => Ok(()),
    }
}

/// An optional per-node mask (pins, fixed nodes) has `n` entries when given
/// ([`Error::LengthMismatch`]).
#[inline]
pub(crate) fn mask(arg: &'static str, mask: Option<&[u8]>, n: usize) -> Result<()> {
    match mask {
        Some(m) => len(arg, m.len(), n),
        None => Ok(()),
    }
}

/// A scalar is finite ([`Error::NonFinite`] at position 0).
#[inline]
pub(crate) fn scalar<T: Real>(arg: &'static str, x: T) -> Result<()> {
    if x.is_finite() {
        Ok(())
    } else {
        Err(Error::NonFinite { arg, position: 0 })
    }
}

/// Every quaternion finite ([`Error::NonFinite`]) and not too short to normalise
/// ([`Error::ZeroLength`]).
#[inline]
pub(crate) fn quats<T: Real>(arg: &'static str, q: &[Quat<T>]) -> Result<()> {
    for (position, r) in q.iter().enumerate() {
        if !r.is_finite() {
            return Err(Error::NonFinite { arg, position });
        }
        if r.normalize().is_err() {
            return Err(Error::ZeroLength { arg, position });
        }
    }
    Ok(())
}

/// Every index below `bound` ([`Error::IndexOutOfRange`] at the first that is not).
#[inline]
pub(crate) fn indices(arg: &'static str, nodes: &[u32], bound: usize) -> Result<()> {
    for (position, &n) in nodes.iter().enumerate() {
        if n as usize >= bound {
            return Err(Error::IndexOutOfRange {
                arg,
                position,
                index: n as usize,
                bound,
            });
        }
    }
    Ok(())
}
