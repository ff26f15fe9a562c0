//! Reference implementation: Taubin λ|μ filtering (structured and graph) and the grid-line
//! tools, written the obvious way with `Vec` and `(i, j, k)` loops. Shares no code with the
//! kernel (own scalar trait over std floats; std `sqrt`, which IEEE 754 rounds correctly, as
//! libm's does).
//!
//! The floating-point formulas are the ones the paper prints, in the order they are written:
//! neighbour values are summed direction by direction (i, j, k), lower neighbour first, then
//! divided by their count; a pass is `x + w (avg − x)`. Parity tests compare bits.

use std::ops::{Add, Div, Mul, Sub};

/// The scalar operations the reference needs, for `f32` and `f64`.
pub trait Float:
    Copy
    + PartialOrd
    + std::fmt::Debug
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
{
    /// 0.
    fn zero() -> Self;
    /// 1.
    fn one() -> Self;
    /// Conversion from a count.
    fn count(n: usize) -> Self;
    /// Square root (correctly rounded).
    fn root(self) -> Self;
}

impl Float for f64 {
    fn zero() -> Self {
        0.0
    }
    fn one() -> Self {
        1.0
    }
    fn count(n: usize) -> Self {
        n as f64
    }
    fn root(self) -> Self {
        self.sqrt()
    }
}

impl Float for f32 {
    fn zero() -> Self {
        0.0
    }
    fn one() -> Self {
        1.0
    }
    fn count(n: usize) -> Self {
        n as f32
    }
    fn root(self) -> Self {
        self.sqrt()
    }
}

/// Linear index `i + ni (j + nj k)`.
fn at(dims: [usize; 3], i: usize, j: usize, k: usize) -> usize {
    i + dims[0] * (j + dims[1] * k)
}

/// The neighbour values the paper's stencil uses at `(i, j, k)`, in order: for each direction
/// i, j, k with more than one point, `(lower, upper)`; on a face normal to that direction the
/// pair is dropped, or with `mirror` the missing neighbour is the inside one.
fn neighbours<T: Float>(dims: [usize; 3], x: &[T], ijk: [usize; 3], mirror: [bool; 3]) -> Vec<T> {
    let mut out = Vec::new();
    for d in 0..3 {
        let n = dims[d];
        if n < 2 {
            continue;
        }
        let c = ijk[d];
        let mut lo = ijk;
        let mut hi = ijk;
        if c == 0 {
            if !mirror[d] {
                continue;
            }
            lo[d] = 1;
            hi[d] = 1;
        } else if c == n - 1 {
            if !mirror[d] {
                continue;
            }
            lo[d] = n - 2;
            hi[d] = n - 2;
        } else {
            lo[d] = c - 1;
            hi[d] = c + 1;
        }
        out.push(x[at(dims, lo[0], lo[1], lo[2])]);
        out.push(x[at(dims, hi[0], hi[1], hi[2])]);
    }
    out
}

/// One Jacobi pass `x + w (avg − x)` over the index box `lo..hi`; other points copied from
/// `x` (the kernel's sweep leaves them untouched in `dst` instead).
#[allow(clippy::too_many_arguments)]
pub fn structured_pass<T: Float>(
    dims: [usize; 3],
    x: &[T],
    w: T,
    mirror: [bool; 3],
    pinned: Option<&[u8]>,
    lo: [usize; 3],
    hi: [usize; 3],
) -> Vec<T> {
    let mut y = x.to_vec();
    for k in lo[2]..hi[2] {
        for j in lo[1]..hi[1] {
            for i in lo[0]..hi[0] {
                let p = at(dims, i, j, k);
                if pinned.is_some_and(|m| m[p] != 0) {
                    continue;
                }
                let nb = neighbours(dims, x, [i, j, k], mirror);
                if nb.is_empty() {
                    continue;
                }
                let mut sum = T::zero();
                for v in &nb {
                    sum = sum + *v;
                }
                let avg = sum / T::count(nb.len());
                y[p] = x[p] + w * (avg - x[p]);
            }
        }
    }
    y
}

/// `iterations` λ|μ iterations on the whole block.
pub fn structured_filter<T: Float>(
    dims: [usize; 3],
    field: &[T],
    lambda: T,
    mu: T,
    iterations: usize,
    mirror: [bool; 3],
    pinned: Option<&[u8]>,
) -> Vec<T> {
    let mut x = field.to_vec();
    for _ in 0..iterations {
        let a = structured_pass(dims, &x, lambda, mirror, pinned, [0; 3], dims);
        x = structured_pass(dims, &a, mu, mirror, pinned, [0; 3], dims);
    }
    x
}

/// Coarse count per direction: `0, m, 2m, …` and the last index.
fn coarse_indices(n: usize, m: usize) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).step_by(m.max(1)).collect();
    if *v.last().unwrap() != n - 1 {
        v.push(n - 1);
    }
    v
}

/// Coarse-grid filter: restriction by injection, filter, multilinear prolongation in index
/// space (`correction`: add the interpolated change instead of replacing). Pinned fine points
/// keep their value and pin their coarse image.
#[allow(clippy::too_many_arguments)]
pub fn coarse_filter(
    dims: [usize; 3],
    field: &[f64],
    factor: [usize; 3],
    lambda: f64,
    mu: f64,
    iterations: usize,
    pinned: Option<&[u8]>,
    correction: bool,
) -> Vec<f64> {
    let idx: Vec<Vec<usize>> = (0..3).map(|d| coarse_indices(dims[d], factor[d])).collect();
    let cd = [idx[0].len(), idx[1].len(), idx[2].len()];
    let mut c = vec![0.0; cd[0] * cd[1] * cd[2]];
    let mut cpin = vec![0u8; c.len()];
    for k in 0..cd[2] {
        for j in 0..cd[1] {
            for i in 0..cd[0] {
                let f = at(dims, idx[0][i], idx[1][j], idx[2][k]);
                c[at(cd, i, j, k)] = field[f];
                cpin[at(cd, i, j, k)] = pinned.map_or(0, |m| m[f]);
            }
        }
    }
    let orig = c.clone();
    let c = structured_filter(cd, &c, lambda, mu, iterations, [false; 3], Some(&cpin));
    let delta: Vec<f64> = if correction {
        c.iter().zip(&orig).map(|(a, b)| a - b).collect()
    } else {
        c
    };
    // 1D weights per direction.
    let weights = |d: usize, i: usize| -> Vec<(usize, f64)> {
        let v = &idx[d];
        if v.len() == 1 {
            return vec![(0, 1.0)];
        }
        for s in 0..v.len() - 1 {
            if i >= v[s] && i <= v[s + 1] {
                let t = (i - v[s]) as f64 / (v[s + 1] - v[s]) as f64;
                return vec![(s, 1.0 - t), (s + 1, t)];
            }
        }
        unreachable!()
    };
    let mut out = field.to_vec();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let p = at(dims, i, j, k);
                if pinned.is_some_and(|m| m[p] != 0) {
                    continue;
                }
                let mut v = 0.0;
                for &(ck, wk) in &weights(2, k) {
                    for &(cj, wj) in &weights(1, j) {
                        for &(ci, wi) in &weights(0, i) {
                            v += wk * wj * wi * delta[at(cd, ci, cj, ck)];
                        }
                    }
                }
                out[p] = if correction { field[p] + v } else { v };
            }
        }
    }
    out
}

/// Graph λ|μ filter on CSR adjacency: `x_i + w (Σ w_ij x_j / Σ w_ij − x_i)`, weights 1 when
/// `weights` is `None`; fixed nodes and isolated nodes unchanged.
#[allow(clippy::too_many_arguments)]
pub fn graph_filter<T: Float, const V: usize>(
    offsets: &[u32],
    targets: &[u32],
    weights: Option<&[T]>,
    fixed: Option<&[u8]>,
    values: &[[T; V]],
    lambda: T,
    mu: T,
    iterations: usize,
) -> Vec<[T; V]> {
    let pass = |x: &Vec<[T; V]>, w: T| -> Vec<[T; V]> {
        let mut y = x.clone();
        for i in 0..x.len() {
            if fixed.is_some_and(|f| f[i] != 0) {
                continue;
            }
            let a = offsets[i] as usize;
            let b = offsets[i + 1] as usize;
            if a == b {
                continue;
            }
            let mut num = [T::zero(); V];
            let mut den = T::zero();
            for e in a..b {
                let wij = weights.map_or(T::one(), |ws| ws[e]);
                den = den + wij;
                let xj = x[targets[e] as usize];
                for c in 0..V {
                    num[c] = num[c] + wij * xj[c];
                }
            }
            for c in 0..V {
                y[i][c] = x[i][c] + w * (num[c] / den - x[i][c]);
            }
        }
        y
    };
    let mut x = values.to_vec();
    for _ in 0..iterations {
        let a = pass(&x, lambda);
        x = pass(&a, mu);
    }
    x
}

/// Euclidean distance, squares summed in component order.
pub fn dist<T: Float, const D: usize>(a: [T; D], b: [T; D]) -> T {
    let mut s = T::zero();
    for c in 0..D {
        let d = a[c] - b[c];
        s = s + d * d;
    }
    s.root()
}

/// The points of every line along `dir`, as lists of linear indices.
pub fn lines(dims: [usize; 3], dir: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let (a, b) = match dir {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    for v in 0..dims[b] {
        for u in 0..dims[a] {
            let mut line = Vec::new();
            for t in 0..dims[dir] {
                let mut ijk = [0; 3];
                ijk[a] = u;
                ijk[b] = v;
                ijk[dir] = t;
                line.push(at(dims, ijk[0], ijk[1], ijk[2]));
            }
            out.push(line);
        }
    }
    out
}

/// Arclength along `dir` (normalised: divided by the line length; a zero-length line gets
/// `t / (n − 1)`).
pub fn arclength<T: Float, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    dir: usize,
    normalised: bool,
) -> Vec<T> {
    let mut s = vec![T::zero(); points.len()];
    for line in lines(dims, dir) {
        let mut acc = T::zero();
        for t in 0..line.len() {
            if t > 0 {
                acc = acc + dist(points[line[t - 1]], points[line[t]]);
            }
            s[line[t]] = acc;
        }
        if normalised {
            for t in 0..line.len() {
                s[line[t]] = if acc > T::zero() {
                    s[line[t]] / acc
                } else if line.len() > 1 {
                    T::count(t) / T::count(line.len() - 1)
                } else {
                    T::zero()
                };
            }
        }
    }
    s
}

/// Point at arclength `target` on a polyline, by a fresh linear search each time; beyond the
/// ends, extrapolation along the first/last segment of non-zero length.
pub fn point_at(poly: &[[f64; 3]], target: f64) -> [f64; 3] {
    let mut s = vec![0.0];
    for w in poly.windows(2) {
        let last = *s.last().unwrap();
        s.push(last + dist(w[0], w[1]));
    }
    let total = *s.last().unwrap();
    if total == 0.0 {
        return poly[0];
    }
    let lerp = |a: [f64; 3], b: [f64; 3], f: f64| {
        [
            a[0] + f * (b[0] - a[0]),
            a[1] + f * (b[1] - a[1]),
            a[2] + f * (b[2] - a[2]),
        ]
    };
    let segs: Vec<usize> = (0..poly.len() - 1).filter(|&m| s[m + 1] > s[m]).collect();
    if target < 0.0 {
        let m = segs[0];
        return lerp(poly[m], poly[m + 1], (target - s[m]) / (s[m + 1] - s[m]));
    }
    for &m in &segs {
        if target >= s[m] && target <= s[m + 1] {
            return lerp(poly[m], poly[m + 1], (target - s[m]) / (s[m + 1] - s[m]));
        }
    }
    let m = *segs.last().unwrap();
    lerp(poly[m], poly[m + 1], (target - s[m]) / (s[m + 1] - s[m]))
}

/// Stretching at every point along `dir`: max/min of the two adjacent cells (1 at line ends
/// and between two zero cells, infinity next to one zero cell).
pub fn stretching<T: Float + Into<f64>, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    dir: usize,
) -> Vec<f64> {
    let mut out = vec![1.0; points.len()];
    for line in lines(dims, dir) {
        for t in 1..line.len().saturating_sub(1) {
            let a: f64 = dist(points[line[t - 1]], points[line[t]]).into();
            let b: f64 = dist(points[line[t]], points[line[t + 1]]).into();
            out[line[t]] = if a == 0.0 && b == 0.0 {
                1.0
            } else if a == 0.0 || b == 0.0 {
                f64::INFINITY
            } else {
                a.max(b) / a.min(b)
            };
        }
    }
    out
}
