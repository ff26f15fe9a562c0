//! Hilbert-curve keys of points: coordinates quantised on the bounding box to integers (32
//! bits an axis in 2D, 21 in 3D), then Skilling's transform ("Programming the Hilbert curve",
//! AIP Conf. Proc. 707, 2004) and bit interleaving into one `u64`. Integer arithmetic after
//! the quantisation, which is two correctly rounded `f64` operations a coordinate, so the keys
//! are the same on every platform.

use crate::real::Real;

/// Bits a coordinate keeps in `D` dimensions (the key has `D × bits ≤ 64` bits).
pub(super) const fn bits(d: usize) -> u32 {
    if d == 2 {
        32
    } else {
        21
    }
}

/// Per axis: the lower corner and the extent of the bounding box, halved (so that no
/// difference of finite coordinates overflows).
pub(super) fn half_box<T: Real, const D: usize>(points: &[[T; D]]) -> [(f64, f64); D] {
    let mut lo = [f64::INFINITY; D];
    let mut hi = [f64::NEG_INFINITY; D];
    for p in points {
        for ((l, h), x) in lo.iter_mut().zip(hi.iter_mut()).zip(p) {
            let x = x.to_f64() * 0.5;
            *l = l.min(x);
            *h = h.max(x);
        }
    }
    core::array::from_fn(|k| match (lo.get(k), hi.get(k)) {
        (Some(&l), Some(&h)) => (l, h - l),
        _ => (0.0, 0.0),
    })
}

/// The integer cell of a point: `floor((x − lo) / extent × (2^bits − 1))` per axis (0 on a
/// flat axis).
fn quantise<T: Real, const D: usize>(p: &[T; D], frame: &[(f64, f64); D], b: u32) -> [u32; D] {
    let scale = ((1u64 << b) - 1) as f64;
    core::array::from_fn(|k| match (p.get(k), frame.get(k)) {
        (Some(x), Some(&(lo, ext))) if ext > 0.0 => {
            let t = (x.to_f64() * 0.5 - lo) / ext;
            let q = t * scale;
            // `as` saturates; the clamp keeps rounding at the top inside the grid.
            (q as u64).min((1u64 << b) - 1) as u32
        }
        _ => 0,
    })
}

/// Skilling's axes-to-transpose: turns the cell coordinates into the transposed Hilbert
/// index (bit `j` of the index's `k`-th digit group sits in `x[k]`).
fn axes_to_transpose<const D: usize>(x: &mut [u32; D], b: u32) {
    let m = 1u32 << (b - 1);
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..D {
            let xi = x.get(i).copied().unwrap_or(0);
            if xi & q != 0 {
                if let Some(x0) = x.first_mut() {
                    *x0 ^= p;
                }
            } else {
                let t = (x.first().copied().unwrap_or(0) ^ xi) & p;
                if let Some(x0) = x.first_mut() {
                    *x0 ^= t;
                }
                if let Some(xi) = x.get_mut(i) {
                    *xi ^= t;
                }
            }
        }
        q >>= 1;
    }
    // Gray encode.
    for i in 1..D {
        let prev = x.get(i - 1).copied().unwrap_or(0);
        if let Some(xi) = x.get_mut(i) {
            *xi ^= prev;
        }
    }
    let mut t = 0u32;
    let last = x.last().copied().unwrap_or(0);
    let mut q = m;
    while q > 1 {
        if last & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for xi in x.iter_mut() {
        *xi ^= t;
    }
}

/// The Hilbert key of a point in the frame of [`half_box`].
pub(super) fn key<T: Real, const D: usize>(p: &[T; D], frame: &[(f64, f64); D]) -> u64 {
    let b = bits(D);
    let mut x = quantise(p, frame, b);
    axes_to_transpose(&mut x, b);
    let mut key = 0u64;
    for bit in (0..b).rev() {
        for xi in &x {
            key = (key << 1) | u64::from((xi >> bit) & 1);
        }
    }
    key
}
