//! A solution-adapted volume grid with a rough outer boundary: Alter's test case (a grid
//! adapted to a bow shock by interpolating K-direction distribution functions, whose noise
//! shows most at the outer boundary).

use crate::rng::XorShift64;
use crate::{invalid, Result};

/// Settings of [`adapted_block`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptedSpec {
    /// `[ni, nj, nk]`: i streamwise, j circumferential, k from the wall to the outer boundary
    /// (each ≥ 3).
    pub dims: [usize; 3],
    /// Relative amplitude of the noise on each k-line's length (the outer-boundary distance
    /// varies by `1 ± noise` from line to line), in `[0, 0.2]`.
    pub noise: f64,
    /// Clustering of the k-distribution at both ends (wall and shock), `β` of a two-sided
    /// tanh stretching; larger is tighter, in `[0.5, 8]`.
    pub clustering: f64,
    /// Seed of the noise.
    pub seed: u64,
}

impl Default for AdaptedSpec {
    /// The case: 65 × 49 × 65, 1 % line-length noise, `β = 3`.
    fn default() -> Self {
        AdaptedSpec {
            dims: [65, 49, 65],
            noise: 0.01,
            clustering: 3.0,
            seed: 33,
        }
    }
}

/// The wall point of a unit sphere seen from the nose (streamwise angle `θ`, circumferential
/// `φ`), which is also its outward normal, and the streamwise unit tangent.
fn wall(theta: f64, phi: f64) -> ([f64; 3], [f64; 3]) {
    let (st, ct) = (libm::sin(theta), libm::cos(theta));
    let (sp, cp) = (libm::sin(phi), libm::cos(phi));
    ([-ct, st * cp, st * sp], [st, ct * cp, ct * sp])
}

/// Two-sided tanh clustering: `u(0) = 0`, `u(1) = 1`, fine cells at both ends.
fn cluster(eta: f64, beta: f64) -> f64 {
    let h = libm::tanh(0.5 * beta);
    0.5 * (1.0 + libm::tanh(beta * (eta - 0.5)) / h)
}

/// A single-block volume grid adapted to a bow-shock-like outer boundary, i fastest
/// (`i + ni (j + nj k)`), `k = 0` on the wall (a unit sphere, `θ ∈ [0.2, 1.3]` from the
/// nose, `φ ∈ [0, π]`).
///
/// Each k-line leaves the wall along the normal and bends downstream (a quadratic drift of
/// 15 % of its length along the streamwise tangent); its length is the shock standoff
/// `d(θ) = 0.25 (1 + 1.5 θ²)` times `1 + noise · ξ(i, j)` with `ξ` uniform in `[−1, 1]` per
/// line (the interpolation noise of Alter's adaptation: rough k-surfaces, most visible at the
/// outer boundary), and its points follow a two-sided tanh distribution clustered at the wall
/// and at the shock. Cells are right-handed (positive volumes) and every line's arclength
/// increases.
///
/// # Errors
/// `InvalidOption` for a dimension below 3, `noise` outside `[0, 0.2]` or `clustering`
/// outside `[0.5, 8]`.
pub fn adapted_block(spec: &AdaptedSpec) -> Result<Vec<[f64; 3]>> {
    let [ni, nj, nk] = spec.dims;
    if ni < 3 || nj < 3 || nk < 3 {
        return invalid("adapted block dimensions must be at least 3");
    }
    if !(0.0..=0.2).contains(&spec.noise) {
        return invalid("adapted block noise must be in [0, 0.2]");
    }
    if !(0.5..=8.0).contains(&spec.clustering) {
        return invalid("adapted block clustering must be in [0.5, 8]");
    }
    let mut rng = XorShift64::new(spec.seed);
    let lengths: Vec<f64> = (0..ni * nj)
        .map(|l| {
            let theta = 0.2 + 1.1 * (l % ni) as f64 / (ni - 1) as f64;
            0.25 * (1.0 + 1.5 * theta * theta) * (1.0 + spec.noise * rng.symmetric())
        })
        .collect();
    let mut points = vec![[0.0; 3]; ni * nj * nk];
    for k in 0..nk {
        let u = cluster(k as f64 / (nk - 1) as f64, spec.clustering);
        for j in 0..nj {
            // φ from π down to 0, so that (i, j, k) is right-handed.
            let phi = std::f64::consts::PI * (nj - 1 - j) as f64 / (nj - 1) as f64;
            for i in 0..ni {
                let theta = 0.2 + 1.1 * i as f64 / (ni - 1) as f64;
                let (n, t) = wall(theta, phi);
                let d = lengths[i + ni * j];
                let (a, b) = (d * u, 0.15 * d * u * u);
                points[i + ni * (j + nj * k)] = [0, 1, 2].map(|c| (1.0 + a) * n[c] + b * t[c]);
            }
        }
    }
    Ok(points)
}
