//! Naive `f64` inverse-distance weighting with the quantities the fast method's error bound
//! is stated in: the exact weighted means (translation, and the hemisphere-aligned quaternion
//! mean *before* normalisation) and the spread `max_k |v_k − v(x)|` at each point.
//!
//! Written from the formulas (textbook weights `|x − b_k|^−p`, `O(N · B)` loops, `Vec`), no
//! code shared with the kernel.

/// The exact inverse-distance values at one field point.
#[derive(Clone, Debug)]
pub struct IdwPoint {
    /// `true` for a boundary node (its values are the caller's, nothing below is computed).
    pub boundary: bool,
    /// `true` when the point coincides with a boundary node (values copied from it).
    pub coincident: bool,
    /// Weighted mean translation.
    pub t: Vec<f64>,
    /// Weighted mean of the hemisphere-aligned quaternions (not normalised).
    pub q_mean: [f64; 4],
    /// `q_mean` normalised.
    pub q: [f64; 4],
    /// `max_k |Δ_k − t|` (Euclidean).
    pub spread_t: f64,
    /// `max_k |±Q_k − q_mean|` (Euclidean, aligned quaternions).
    pub spread_q: f64,
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

fn dot4(a: [f64; 4], b: [f64; 4]) -> f64 {
    (0..4).map(|c| a[c] * b[c]).sum()
}

/// Exact IDW at every point of `points` (any dimension; each point a slice of equal length).
/// `boundary[k]` is the mesh node of boundary value `k`; `delta[k]` and `quats[k]` its
/// values. The hemisphere reference is the rotation of the nearest boundary node (the first
/// in `boundary` order on ties), as the kernel documents.
pub fn idw_with_spread(
    points: &[Vec<f64>],
    boundary: &[usize],
    delta: &[Vec<f64>],
    quats: &[[f64; 4]],
    p: f64,
) -> Vec<IdwPoint> {
    points
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let dim = x.len();
            if boundary.contains(&i) {
                return IdwPoint {
                    boundary: true,
                    coincident: false,
                    t: vec![0.0; dim],
                    q_mean: [0.0; 4],
                    q: [0.0; 4],
                    spread_t: 0.0,
                    spread_q: 0.0,
                };
            }
            let d: Vec<f64> = boundary.iter().map(|&b| dist(x, &points[b])).collect();
            let mut kmin = 0;
            for k in 1..d.len() {
                if d[k] < d[kmin] {
                    kmin = k;
                }
            }
            let refq = quats[kmin];
            let aligned: Vec<[f64; 4]> = quats
                .iter()
                .map(|&q| {
                    if dot4(q, refq) < 0.0 {
                        [-q[0], -q[1], -q[2], -q[3]]
                    } else {
                        q
                    }
                })
                .collect();
            let (t, q_mean, coincident) = if d[kmin] == 0.0 {
                (delta[kmin].clone(), refq, true)
            } else {
                let w: Vec<f64> = d.iter().map(|&dk| dk.powf(-p)).collect();
                let ws: f64 = w.iter().sum();
                let mut t = vec![0.0; dim];
                let mut q = [0.0; 4];
                for k in 0..w.len() {
                    for c in 0..dim {
                        t[c] += w[k] * delta[k][c] / ws;
                    }
                    for c in 0..4 {
                        q[c] += w[k] * aligned[k][c] / ws;
                    }
                }
                (t, q, false)
            };
            let spread_t = delta.iter().map(|v| dist(v, &t)).fold(0.0, f64::max);
            let spread_q = aligned.iter().map(|v| dist(v, &q_mean)).fold(0.0, f64::max);
            let l = dot4(q_mean, q_mean).sqrt();
            IdwPoint {
                boundary: false,
                coincident,
                t,
                q_mean,
                q: q_mean.map(|c| c / l),
                spread_t,
                spread_q,
            }
        })
        .collect()
}

/// The a-priori bound of the fast method (first-order cluster expansion, Taylor remainder):
/// `½ p (p + 1) θ² (1 − θ)^−(p+2)`.
pub fn a_priori_bound(theta: f64, p: f64) -> f64 {
    0.5 * p * (p + 1.0) * theta * theta * (1.0 - theta).powf(-(p + 2.0))
}
