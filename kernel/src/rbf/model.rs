//! The interpolant: kernel values, the polynomial frame and evaluation with exact sums.

use super::grid::Grid;
use super::RbfKernel;
use crate::exact_sum::ExactSum;
use crate::real::Real;

/// `φ` at squared distance `r2`.
#[inline]
pub(super) fn phi<T: Real>(kernel: RbfKernel<T>, r2: T) -> T {
    match kernel {
        RbfKernel::Wendland { radius } => wendland(r2.sqrt() / radius),
        // r² ln r = ½ r² ln r², 0 at r = 0.
        RbfKernel::ThinPlate => {
            if r2 > T::ZERO {
                T::HALF * r2 * r2.ln()
            } else {
                T::ZERO
            }
        }
    }
}

/// Wendland's C2 function `(1 − ρ)⁴ (4ρ + 1)` for `ρ < 1`, 0 beyond.
#[inline]
pub(super) fn wendland<T: Real>(rho: T) -> T {
    if rho < T::ONE {
        let u = T::ONE - rho;
        let u2 = u * u;
        u2 * u2 * (T::from_f64(4.0) * rho + T::ONE)
    } else {
        T::ZERO
    }
}

/// Squared distance, summed in axis order.
#[inline]
pub(super) fn dist_sq<T: Real, const D: usize>(a: [T; D], b: [T; D]) -> T {
    let mut s = T::ZERO;
    for k in 0..D {
        let d = a[k] - b[k];
        s += d * d;
    }
    s
}

/// A solved interpolant: centres (positions into `boundary`), coefficients `(k + p) × D`
/// (`p = D + 1` polynomial terms for thin-plate splines, in the frame `ξ = (x − c) s`).
pub(super) struct Model<'a, T, const D: usize> {
    pub kernel: RbfKernel<T>,
    pub points: &'a [[T; D]],
    pub boundary: &'a [u32],
    pub centres: &'a [u32],
    pub coeffs: &'a [T],
    pub frame: ([T; D], T),
}

impl<T: Real, const D: usize> Model<'_, T, D> {
    /// Position of boundary entry `k`.
    #[inline]
    pub fn boundary_point(&self, k: usize) -> [T; D] {
        let node = self.boundary.get(k).copied().unwrap_or(0) as usize;
        self.points.get(node).copied().unwrap_or([T::ZERO; D])
    }

    /// Position of centre `j`.
    #[inline]
    pub fn centre(&self, j: usize) -> [T; D] {
        self.boundary_point(self.centres.get(j).copied().unwrap_or(0) as usize)
    }

    /// Adds centre `j`'s term at `x` into `sums`.
    #[inline]
    fn add_centre(&self, x: [T; D], j: usize, sums: &mut [ExactSum; D]) {
        let f = phi(self.kernel, dist_sq(x, self.centre(j)));
        if f != T::ZERO {
            for (c, s) in sums.iter_mut().enumerate() {
                s.add(self.coeffs.get(j * D + c).copied().unwrap_or(T::ZERO) * f);
            }
        }
    }

    /// The interpolant at `x`; with a grid (compact support), only the centres near `x`.
    pub fn eval(&self, x: [T; D], grid: Option<&Grid<'_, T, D>>) -> [T; D] {
        let mut sums = [ExactSum::new(); D];
        match (grid, self.kernel) {
            (Some(g), RbfKernel::Wendland { radius }) => {
                g.for_near(x, radius, |j| self.add_centre(x, j, &mut sums));
            }
            _ => (0..self.centres.len()).for_each(|j| self.add_centre(x, j, &mut sums)),
        }
        if let RbfKernel::ThinPlate = self.kernel {
            let k = self.centres.len();
            let xi = to_frame(x, self.frame);
            for (c, s) in sums.iter_mut().enumerate() {
                s.add(self.coeffs.get(k * D + c).copied().unwrap_or(T::ZERO));
                for (a, &v) in xi.iter().enumerate() {
                    s.add(
                        self.coeffs
                            .get((k + 1 + a) * D + c)
                            .copied()
                            .unwrap_or(T::ZERO)
                            * v,
                    );
                }
            }
        }
        sums.map(|s| s.value())
    }
}

/// `(x − c) s`: the polynomial terms' coordinates.
#[inline]
pub(super) fn to_frame<T: Real, const D: usize>(x: [T; D], frame: ([T; D], T)) -> [T; D] {
    let mut r = x;
    for k in 0..D {
        r[k] = (x[k] - frame.0[k]) * frame.1;
    }
    r
}

/// The polynomial frame of the boundary: the middle of its bounding box and the power of two
/// nearest below the inverse of its half-extent (exact scaling; order-independent).
pub(super) fn frame_of<T: Real, const D: usize>(
    n: usize,
    pos: impl Fn(usize) -> [T; D],
) -> ([T; D], T) {
    let (lo, hi) = bounds((0..n).map(pos));
    let mut c = [T::ZERO; D];
    let mut half = T::ZERO;
    for a in 0..D {
        c[a] = lo[a] * T::HALF + hi[a] * T::HALF;
        half = half.max(hi[a] * T::HALF - lo[a] * T::HALF);
    }
    let s = if half > T::ZERO {
        T::pow2(-half.exponent())
    } else {
        T::ONE
    };
    (c, s)
}

/// The bounding box `(lo, hi)` of `points` (`(+∞, −∞)` when empty); order-independent.
pub(super) fn bounds<T: Real, const D: usize>(
    points: impl Iterator<Item = [T; D]>,
) -> ([T; D], [T; D]) {
    let mut lo = [T::INFINITY; D];
    let mut hi = [-T::INFINITY; D];
    for p in points {
        for a in 0..D {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}
