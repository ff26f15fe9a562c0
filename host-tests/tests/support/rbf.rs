//! Point clouds and motions of the RBF tests: an elliptic "wall" (2D ellipse, 3D ellipsoid)
//! inside a circular / spherical far field, volume points between them from a Halton
//! sequence, and a runner that sizes the buffers.

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfOptions, RbfReport};
use deform_kernel::Real;

/// Points: the wall's `inner` nodes, the far field's nodes, then volume points; `boundary`
/// lists wall then far field.
pub struct Case<const D: usize> {
    pub points: Vec<[f64; D]>,
    pub boundary: Vec<u32>,
    pub inner: usize,
}

/// Radical inverse of `i` in base `b` (Halton).
fn halton(mut i: usize, b: usize) -> f64 {
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f /= b as f64;
        r += f * (i % b) as f64;
        i /= b;
    }
    r
}

/// Semi-axes of the wall (centred at (0.5, 0, 0)) and the far-field radius.
const AXES: [f64; 3] = [0.5, 0.08, 0.2];
const FAR: f64 = 5.0;

/// A direction on the unit circle / Fibonacci sphere, `k` of `n`.
fn direction<const D: usize>(k: usize, n: usize) -> [f64; D] {
    let mut d = [0.0; D];
    if D == 2 {
        let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        d[0] = t.cos();
        d[1] = t.sin();
    } else {
        let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
        let t = 2.399_963_229_728_653 * k as f64;
        let s = (1.0 - z * z).sqrt();
        d[0] = s * t.cos();
        d[1] = s * t.sin();
        d[2] = z;
    }
    d
}

fn inside_wall<const D: usize>(p: [f64; D]) -> bool {
    let mut s = ((p[0] - 0.5) / AXES[0]).powi(2);
    for a in 1..D {
        s += (p[a] / AXES[a]).powi(2);
    }
    s <= 1.05
}

/// `n_in` wall nodes, `n_out` far-field nodes, `n_vol` volume points.
pub fn case<const D: usize>(n_in: usize, n_out: usize, n_vol: usize) -> Case<D> {
    let mut points = Vec::new();
    for k in 0..n_in {
        let d = direction::<D>(k, n_in);
        points.push(std::array::from_fn(|a| {
            d[a] * AXES[a] + if a == 0 { 0.5 } else { 0.0 }
        }));
    }
    for k in 0..n_out {
        points.push(direction::<D>(k, n_out).map(|v| v * FAR));
    }
    let bases = [2, 3, 5];
    let mut i = 1;
    while points.len() < n_in + n_out + n_vol {
        let p: [f64; D] = std::array::from_fn(|a| FAR * (2.0 * halton(i, bases[a]) - 1.0));
        i += 1;
        let r2: f64 = p.iter().map(|v| v * v).sum();
        if r2 < 0.95 * FAR * FAR && !inside_wall(p) {
            points.push(p);
        }
    }
    Case {
        points,
        boundary: (0..(n_in + n_out) as u32).collect(),
        inner: n_in,
    }
}

/// Rotation by `deg` about the z axis through (0.25, 0, 0).
pub fn rotate<const D: usize>(p: [f64; D], deg: f64) -> [f64; D] {
    let (s, c) = deg.to_radians().sin_cos();
    let (x, y) = (p[0] - 0.25, p[1]);
    let mut q = p;
    q[0] = 0.25 + c * x - s * y;
    q[1] = s * x + c * y;
    q
}

/// The wall pitched by `deg` (plus a smooth bump of `bump` chord, so the field is not affine),
/// the far field fixed.
pub fn pitch_motion<const D: usize>(case: &Case<D>, deg: f64, bump: f64) -> Vec<[f64; D]> {
    case.boundary
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let p = case.points[n as usize];
            if k >= case.inner {
                return [0.0; D];
            }
            let q = rotate(p, deg);
            std::array::from_fn(|a| {
                q[a] - p[a]
                    + if a == 1 {
                        bump * (3.0 * p[0]).sin()
                    } else {
                        0.0
                    }
            })
        })
        .collect()
}

/// Converts to `T`.
pub fn cast<T: Real, const D: usize>(v: &[[f64; D]]) -> Vec<[T; D]> {
    v.iter().map(|p| p.map(T::from_f64)).collect()
}

/// [`rbf_deform`] with buffers of exactly the queried sizes.
pub fn run<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    motion: &[[T; D]],
    options: &RbfOptions<T>,
) -> deform_kernel::Result<(Vec<[T; D]>, RbfReport<T>)> {
    let mut index = vec![0u32; rbf_index_len::<T, D>(boundary.len(), options)];
    let mut scratch = vec![T::ZERO; rbf_scratch_len::<T, D>(boundary.len(), options)];
    let mut out = vec![[T::ZERO; D]; points.len()];
    let report = rbf_deform(
        points,
        boundary,
        motion,
        options,
        &mut index,
        &mut scratch,
        &mut out,
    )?;
    Ok((out, report))
}

/// Largest Euclidean length of the rows of `v`.
pub fn max_norm<const D: usize>(v: &[[f64; D]]) -> f64 {
    v.iter()
        .map(|p| p.iter().map(|x| x * x).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}
