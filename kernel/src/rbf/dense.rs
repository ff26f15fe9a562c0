//! Dense factorizations of the interpolation matrix, in caller memory (row-major `a × a`).
//!
//! Every inner product runs in index order with plain multiply-then-add (no FMA): the matrix
//! is never split, so this fixed order gives the same bits on every platform.

use crate::real::Real;

/// Smallest accepted Cholesky pivot `L_kk²` relative to the diagonal `φ(0) = 1`: a new centre
/// whose kernel function is within `√(16 ε)` of the span of the earlier ones is numerically
/// dependent (a coincident or nearly coincident node).
pub(super) fn min_pivot<T: Real>() -> T {
    T::EPSILON * T::from_f64(16.0)
}

/// Swaps `v[i]` and `v[j]` (nothing when either is out of range; no panic path).
#[inline]
fn swap_at<T: Copy>(v: &mut [T], i: usize, j: usize) {
    if let (Some(&a), Some(&b)) = (v.get(i), v.get(j)) {
        if let Some(x) = v.get_mut(i) {
            *x = b;
        }
        if let Some(x) = v.get_mut(j) {
            *x = a;
        }
    }
}

/// `Σ_{i<n} x[i] y[i]` in index order.
#[inline]
fn dot_prefix<T: Real>(x: &[T], y: &[T], n: usize) -> T {
    let mut s = T::ZERO;
    for (&a, &b) in x.iter().zip(y).take(n) {
        s += a * b;
    }
    s
}

/// Factors row `k` of `A = L Lᵀ` in place (row `k` holds `A_k0 … A_kk` on entry and `L_k0 …
/// L_kk` on return; rows `0 … k−1` already hold `L`). Left-looking, so a greedy selection
/// appends a centre in `O(k²)`. Returns `false` (row `k` then undefined) when the pivot is
/// not above [`min_pivot`] or not finite.
pub(super) fn cholesky_row<T: Real>(m: &mut [T], a: usize, k: usize) -> bool {
    let (head, tail) = m.split_at_mut(k.saturating_mul(a).min(m.len()));
    let Some(row) = tail.get_mut(..=k) else {
        return false;
    };
    for j in 0..=k {
        let lj: &[T] = if j < k {
            head.get(j * a..j * a + j).unwrap_or(&[])
        } else {
            &[]
        };
        let Some((done, rest)) = row.split_at_mut_checked(j) else {
            return false;
        };
        let s = match rest.first() {
            Some(&v) => {
                v - if j < k {
                    dot_prefix(done, lj, j)
                } else {
                    dot_prefix(done, done, j)
                }
            }
            None => return false,
        };
        let v = if j < k {
            s / head.get(j * a + j).copied().unwrap_or(T::ONE)
        } else if s > min_pivot() && s.is_finite() {
            s.sqrt()
        } else {
            return false;
        };
        if let Some(x) = rest.first_mut() {
            *x = v;
        }
    }
    true
}

/// Solves `L Lᵀ x = b` in place for the first `k` rows (`b` strided by `stride`, component
/// `c`), with `L` from [`cholesky_row`].
pub(super) fn cholesky_solve<T: Real>(
    m: &[T],
    a: usize,
    k: usize,
    b: &mut [T],
    stride: usize,
    c: usize,
) {
    let at = |i: usize, j: usize| m.get(i * a + j).copied().unwrap_or(T::ONE);
    let get = |b: &[T], i: usize| b.get(i * stride + c).copied().unwrap_or(T::ZERO);
    for i in 0..k {
        let mut s = get(b, i);
        for j in 0..i {
            s -= at(i, j) * get(b, j);
        }
        if let Some(x) = b.get_mut(i * stride + c) {
            *x = s / at(i, i);
        }
    }
    for i in (0..k).rev() {
        let mut s = get(b, i);
        for j in i + 1..k {
            s -= at(j, i) * get(b, j);
        }
        if let Some(x) = b.get_mut(i * stride + c) {
            *x = s / at(i, i);
        }
    }
}

/// LU factorization with partial pivoting of the leading `n × n` block (row stride `a`), in
/// place (`L` unit lower, `U` upper); `piv[i]` is the row swapped into row `i` at step `i`.
/// The first largest magnitude wins ties. Returns `false` when a pivot is zero or not finite.
pub(super) fn lu_factor<T: Real>(m: &mut [T], a: usize, n: usize, piv: &mut [u32]) -> bool {
    for k in 0..n {
        let mut p = k;
        let mut best = T::ZERO;
        for i in k..n {
            let v = m.get(i * a + k).copied().unwrap_or(T::ZERO).abs();
            if v > best {
                best = v;
                p = i;
            }
        }
        if !(best > T::ZERO && best.is_finite()) {
            return false;
        }
        if let Some(x) = piv.get_mut(k) {
            *x = p as u32;
        }
        if p != k {
            for j in 0..n {
                swap_at(m, k * a + j, p * a + j);
            }
        }
        let pivot = m.get(k * a + k).copied().unwrap_or(T::ONE);
        for i in k + 1..n {
            let f = m.get(i * a + k).copied().unwrap_or(T::ZERO) / pivot;
            if let Some(x) = m.get_mut(i * a + k) {
                *x = f;
            }
            for j in k + 1..n {
                let u = m.get(k * a + j).copied().unwrap_or(T::ZERO);
                if let Some(x) = m.get_mut(i * a + j) {
                    *x -= f * u;
                }
            }
        }
    }
    true
}

/// Solves `A x = b` in place with the factors of [`lu_factor`] (`b` strided by `stride`,
/// component `c`).
pub(super) fn lu_solve<T: Real>(
    m: &[T],
    a: usize,
    n: usize,
    piv: &[u32],
    b: &mut [T],
    stride: usize,
    c: usize,
) {
    let at = |i: usize, j: usize| m.get(i * a + j).copied().unwrap_or(T::ONE);
    for k in 0..n {
        let p = piv.get(k).copied().unwrap_or(0) as usize;
        if p != k {
            swap_at(b, k * stride + c, p * stride + c);
        }
    }
    let get = |b: &[T], i: usize| b.get(i * stride + c).copied().unwrap_or(T::ZERO);
    for i in 0..n {
        let mut s = get(b, i);
        for j in 0..i {
            s -= at(i, j) * get(b, j);
        }
        if let Some(x) = b.get_mut(i * stride + c) {
            *x = s;
        }
    }
    for i in (0..n).rev() {
        let mut s = get(b, i);
        for j in i + 1..n {
            s -= at(i, j) * get(b, j);
        }
        if let Some(x) = b.get_mut(i * stride + c) {
            *x = s / at(i, i);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_and_lu_solve_a_small_system() {
        // A = [[4, 2, 0.4], [2, 5, 1], [0.4, 1, 3]], b = A [1, -2, 0.5].
        let a = [[4.0, 2.0, 0.4], [2.0, 5.0, 1.0], [0.4, 1.0, 3.0]];
        let x = [1.0, -2.0, 0.5];
        let b: [f64; 3] = core::array::from_fn(|i| (0..3).map(|j| a[i][j] * x[j]).sum());
        let mut m = [0.0f64; 9];
        for k in 0..3 {
            m[k * 3..k * 3 + k + 1].copy_from_slice(&a[k][..=k]);
            assert!(cholesky_row(&mut m, 3, k));
        }
        let mut y = b;
        cholesky_solve(&m, 3, 3, &mut y, 1, 0);
        for i in 0..3 {
            assert!((y[i] - x[i]).abs() < 1e-14, "{y:?}");
        }
        let mut m: [f64; 9] = core::array::from_fn(|k| a[k / 3][k % 3]);
        let mut piv = [0u32; 3];
        assert!(lu_factor(&mut m, 3, 3, &mut piv));
        let mut y = b;
        lu_solve(&m, 3, 3, &piv, &mut y, 1, 0);
        for i in 0..3 {
            assert!((y[i] - x[i]).abs() < 1e-14, "{y:?}");
        }
    }

    #[test]
    fn singular_matrices_are_refused() {
        let mut m = [1.0f64, 0.0, 1.0, 1.0];
        assert!(cholesky_row(&mut m, 2, 0));
        assert!(!cholesky_row(&mut m, 2, 1));
        let mut m = [1.0f64, 2.0, 2.0, 4.0];
        let mut piv = [0u32; 2];
        assert!(!lu_factor(&mut m, 2, 2, &mut piv));
    }
}
