//! Reference implementation: spring-analogy mesh motion, written naively (std, `Vec`, dense
//! Gaussian elimination) and sharing no code with the kernel.
//!
//! - [`stiffness`]: Batina's `1/|r_i − r_j|^p` per directed edge.
//! - [`jacobi_sweep`], [`sor_sweep`]: the linear-spring iterations, written in the same
//!   delta form and summation order as the kernel documents, so the parity tests can demand
//!   identical bits.
//! - [`solve_linear_dense`], [`solve_angle_dense`]: direct solves of the eliminated free-node
//!   systems (Yang & Özgen eq. 4, `K_aa q_a = −K_ab q_b`) by Gaussian elimination with partial
//!   pivoting, in `f64`.
//! - [`linear_energy`], [`angle_energy`]: the spring energy `½ Σ_edges (x_i − x_j)ᵀ B (x_i − x_j)`
//!   whose minimiser the solvers compute (Gauss–Seidel and CG must decrease it).
//! - Small mesh generators (triangulated annulus, sheared cube) for the tests.

// Index loops on purpose: the reference reads like the paper's formulas.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, Div, Mul, Sub};

/// The two float types, for the generic reference sweeps.
pub trait Float:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + std::fmt::Debug
{
    /// 0.
    fn zero() -> Self;
    /// Conversion from f64.
    fn of(x: f64) -> Self;
    /// Conversion to f64.
    fn f64(self) -> f64;
    /// Square root (std).
    fn root(self) -> Self;
}

impl Float for f64 {
    fn zero() -> Self {
        0.0
    }
    fn of(x: f64) -> Self {
        x
    }
    fn f64(self) -> f64 {
        self
    }
    fn root(self) -> Self {
        self.sqrt()
    }
}

impl Float for f32 {
    fn zero() -> Self {
        0.0
    }
    fn of(x: f64) -> Self {
        x as f32
    }
    fn f64(self) -> f64 {
        self as f64
    }
    fn root(self) -> Self {
        self.sqrt()
    }
}

/// A plain CSR graph with per-directed-edge stiffness and a fixed flag per node.
#[derive(Clone, Debug)]
pub struct Net<F> {
    /// Row offsets (n + 1).
    pub offsets: Vec<u32>,
    /// Column indices.
    pub targets: Vec<u32>,
    /// Stiffness per directed edge.
    pub k: Vec<F>,
    /// Fixed flag per node (nonzero = fixed).
    pub fixed: Vec<u8>,
}

impl<F: Float> Net<F> {
    /// Node count.
    pub fn n(&self) -> usize {
        self.offsets.len() - 1
    }
    /// `(j, k_ij)` of node `i` in CSR order.
    pub fn row(&self, i: usize) -> Vec<(usize, F)> {
        let a = self.offsets[i] as usize;
        let b = self.offsets[i + 1] as usize;
        (a..b)
            .map(|e| (self.targets[e] as usize, self.k[e]))
            .collect()
    }
}

/// Batina stiffness `1 / |r_i − r_j|^p` for every directed edge (std `sqrt`/`powf`).
pub fn stiffness<const D: usize>(
    offsets: &[u32],
    targets: &[u32],
    points: &[[f64; D]],
    p: f64,
) -> Vec<f64> {
    let mut k = Vec::new();
    for i in 0..offsets.len() - 1 {
        for e in offsets[i] as usize..offsets[i + 1] as usize {
            let j = targets[e] as usize;
            let mut s = 0.0;
            for c in 0..D {
                let d = points[j][c] - points[i][c];
                s += d * d;
            }
            let len = s.sqrt();
            k.push(if p == 1.0 {
                1.0 / len
            } else if p == 2.0 {
                1.0 / s
            } else {
                1.0 / len.powf(p)
            });
        }
    }
    k
}

/// One Jacobi sweep over all nodes:
/// `out_i = x_i + (Σ_j k_ij (x_j − x_i)) / Σ_j k_ij` for free nodes (sums in CSR order), copy
/// for fixed nodes.
pub fn jacobi_sweep<F: Float>(
    net: &Net<F>,
    x: &[Vec<F>],
    range: std::ops::Range<usize>,
) -> Vec<Vec<F>> {
    let mut out = x.to_vec();
    for i in range {
        if net.fixed[i] != 0 {
            continue;
        }
        let v = x[i].len();
        let mut acc = vec![F::zero(); v];
        let mut d = F::zero();
        for (j, k) in net.row(i) {
            for c in 0..v {
                acc[c] = acc[c] + k * (x[j][c] - x[i][c]);
            }
            d = d + k;
        }
        for c in 0..v {
            out[i][c] = x[i][c] + acc[c] / d;
        }
    }
    out
}

/// One in-place Gauss–Seidel/SOR sweep in node order:
/// `x_i ← x_i + ω (Σ_j k_ij (x_j − x_i) / Σ_j k_ij)`.
pub fn sor_sweep<F: Float>(net: &Net<F>, x: &mut [Vec<F>], omega: F) {
    for i in 0..net.n() {
        if net.fixed[i] != 0 {
            continue;
        }
        let v = x[i].len();
        let mut acc = vec![F::zero(); v];
        let mut d = F::zero();
        for (j, k) in net.row(i) {
            for c in 0..v {
                acc[c] = acc[c] + k * (x[j][c] - x[i][c]);
            }
            d = d + k;
        }
        for c in 0..v {
            x[i][c] = x[i][c] + omega * (acc[c] / d);
        }
    }
}

/// Solves `A x = b` (dense, row-major `n×n`) by Gaussian elimination with partial pivoting.
/// Returns `None` when a pivot is below `1e-13 × max|A|` (singular to working precision).
pub fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let scale = a
        .iter()
        .flat_map(|r| r.iter())
        .fold(0.0f64, |m, &x| m.max(x.abs()));
    for col in 0..n {
        let piv = (col..n).max_by(|&p, &q| a[p][col].abs().total_cmp(&a[q][col].abs()))?;
        if a[piv][col].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(col, piv);
        b.swap(col, piv);
        for row in col + 1..n {
            let f = a[row][col] / a[col][col];
            if f != 0.0 {
                for c in col..n {
                    a[row][c] -= f * a[col][c];
                }
                b[row] -= f * b[col];
            }
        }
    }
    let mut x = vec![0.0; n];
    for row in (0..n).rev() {
        let mut s = b[row];
        for c in row + 1..n {
            s -= a[row][c] * x[c];
        }
        x[row] = s / a[row][row];
    }
    Some(x)
}

/// Exact (dense) linear-spring solution: free values solve `Σ_j k_ij (x_j − x_i) = 0`, each
/// component separately; fixed values are kept.
pub fn solve_linear_dense(net: &Net<f64>, x: &[Vec<f64>]) -> Option<Vec<Vec<f64>>> {
    let free: Vec<usize> = (0..net.n()).filter(|&i| net.fixed[i] == 0).collect();
    let mut pos = vec![usize::MAX; net.n()];
    for (p, &i) in free.iter().enumerate() {
        pos[i] = p;
    }
    let m = free.len();
    let mut out = x.to_vec();
    let v = x.first().map_or(0, |r| r.len());
    for c in 0..v {
        let mut a = vec![vec![0.0; m]; m];
        let mut b = vec![0.0; m];
        for (p, &i) in free.iter().enumerate() {
            for (j, k) in net.row(i) {
                a[p][p] += k;
                if net.fixed[j] != 0 {
                    b[p] += k * x[j][c];
                } else {
                    a[p][pos[j]] -= k;
                }
            }
        }
        let sol = dense_solve(a, b)?;
        for (p, &i) in free.iter().enumerate() {
            out[i][c] = sol[p];
        }
    }
    Some(out)
}

/// Edge block `k (d dᵀ/|d|² + ε I)` as a dense `D×D` matrix.
fn edge_block<const D: usize>(pi: [f64; D], pj: [f64; D], k: f64, eps: f64) -> Vec<Vec<f64>> {
    let d: Vec<f64> = (0..D).map(|c| pj[c] - pi[c]).collect();
    let d2: f64 = d.iter().map(|x| x * x).sum();
    (0..D)
        .map(|r| {
            (0..D)
                .map(|c| k * d[r] * d[c] / d2 + if r == c { k * eps } else { 0.0 })
                .collect()
        })
        .collect()
}

/// Exact (dense) angle-inclusion solution (Yang & Özgen eq. 4): free displacements solve
/// `Σ_j B_ij (x_j − x_i) = 0` with `B_ij = k (d dᵀ/|d|² + ε I)`. `None` when singular.
pub fn solve_angle_dense<const D: usize>(
    net: &Net<f64>,
    points: &[[f64; D]],
    eps: f64,
    x: &[[f64; D]],
) -> Option<Vec<[f64; D]>> {
    let free: Vec<usize> = (0..net.n()).filter(|&i| net.fixed[i] == 0).collect();
    let mut pos = vec![usize::MAX; net.n()];
    for (p, &i) in free.iter().enumerate() {
        pos[i] = p;
    }
    let m = free.len() * D;
    let mut a = vec![vec![0.0; m]; m];
    let mut b = vec![0.0; m];
    for (p, &i) in free.iter().enumerate() {
        for (j, k) in net.row(i) {
            let blk = edge_block(points[i], points[j], k, eps);
            for r in 0..D {
                for c in 0..D {
                    a[p * D + r][p * D + c] += blk[r][c];
                    if net.fixed[j] != 0 {
                        b[p * D + r] += blk[r][c] * x[j][c];
                    } else {
                        a[p * D + r][pos[j] * D + c] -= blk[r][c];
                    }
                }
            }
        }
    }
    let sol = dense_solve(a, b)?;
    let mut out = x.to_vec();
    for (p, &i) in free.iter().enumerate() {
        for c in 0..D {
            out[i][c] = sol[p * D + c];
        }
    }
    Some(out)
}

/// Linear-spring energy `½ Σ_{directed edges} ½ k (x_i − x_j)²` (each undirected edge once),
/// summed over components.
pub fn linear_energy(net: &Net<f64>, x: &[Vec<f64>]) -> f64 {
    let mut e = 0.0;
    for i in 0..net.n() {
        for (j, k) in net.row(i) {
            for c in 0..x[i].len() {
                let d = x[i][c] - x[j][c];
                e += 0.25 * k * d * d;
            }
        }
    }
    e
}

/// Angle-spring energy `½ Σ_edges (x_i − x_j)ᵀ B_ij (x_i − x_j)` (each undirected edge once).
pub fn angle_energy<const D: usize>(
    net: &Net<f64>,
    points: &[[f64; D]],
    eps: f64,
    x: &[[f64; D]],
) -> f64 {
    let mut e = 0.0;
    for i in 0..net.n() {
        for (j, k) in net.row(i) {
            let blk = edge_block(points[i], points[j], k, eps);
            for r in 0..D {
                for c in 0..D {
                    e += 0.25 * (x[i][r] - x[j][r]) * blk[r][c] * (x[i][c] - x[j][c]);
                }
            }
        }
    }
    e
}

/// Naive angle residual `‖Σ_j B_ij (x_j − x_i)‖₂` over free nodes.
pub fn angle_residual<const D: usize>(
    net: &Net<f64>,
    points: &[[f64; D]],
    eps: f64,
    x: &[[f64; D]],
) -> f64 {
    let mut s = 0.0;
    for i in 0..net.n() {
        if net.fixed[i] != 0 {
            continue;
        }
        let mut r = [0.0; D];
        for (j, k) in net.row(i) {
            let blk = edge_block(points[i], points[j], k, eps);
            for a in 0..D {
                for c in 0..D {
                    r[a] += blk[a][c] * (x[j][c] - x[i][c]);
                }
            }
        }
        s += r.iter().map(|v| v * v).sum::<f64>();
    }
    s.sqrt()
}

/// Symmetric CSR (rows sorted) from an undirected edge list, naively with `BTreeSet`s.
pub fn csr(n: usize, edges: &[[u32; 2]]) -> (Vec<u32>, Vec<u32>) {
    let mut rows = vec![std::collections::BTreeSet::new(); n];
    for &[a, b] in edges {
        rows[a as usize].insert(b);
        rows[b as usize].insert(a);
    }
    let mut offsets = vec![0u32];
    let mut targets = Vec::new();
    for r in rows {
        targets.extend(r);
        offsets.push(targets.len() as u32);
    }
    (offsets, targets)
}

/// A triangulated annulus, radii `r0 < r1`, `nr` rings × `nt` points per ring, rings
/// geometrically graded (ratio `grade`), each quad split along alternating diagonals.
/// Returns `(points, edges, fixed)` with both rings fixed.
pub fn annulus(
    nr: usize,
    nt: usize,
    r0: f64,
    r1: f64,
    grade: f64,
) -> (Vec<[f64; 2]>, Vec<[u32; 2]>, Vec<u8>) {
    let mut radii = vec![0.0; nr];
    let mut h = 1.0;
    let mut tot = 0.0;
    let mut steps = vec![];
    for _ in 0..nr - 1 {
        steps.push(h);
        tot += h;
        h *= grade;
    }
    radii[0] = r0;
    for j in 1..nr {
        radii[j] = radii[j - 1] + (r1 - r0) * steps[j - 1] / tot;
    }
    radii[nr - 1] = r1;
    let id = |j: usize, i: usize| (j * nt + i % nt) as u32;
    let mut pts = Vec::new();
    for &r in &radii {
        for i in 0..nt {
            let t = 2.0 * std::f64::consts::PI * i as f64 / nt as f64;
            pts.push([r * t.cos(), r * t.sin()]);
        }
    }
    let mut edges = Vec::new();
    for j in 0..nr {
        for i in 0..nt {
            edges.push([id(j, i), id(j, i + 1)]);
            if j + 1 < nr {
                edges.push([id(j, i), id(j + 1, i)]);
                if (i + j) % 2 == 0 {
                    edges.push([id(j, i), id(j + 1, i + 1)]);
                } else {
                    edges.push([id(j, i + 1), id(j + 1, i)]);
                }
            }
        }
    }
    let fixed = (0..nr * nt)
        .map(|p| u8::from(p < nt || p >= (nr - 1) * nt))
        .collect();
    (pts, edges, fixed)
}

/// A 3D structured block of `n³` points on `[0,1]³` (slightly sheared so edges are not axis
/// aligned), tetrahedralised edges (cube edges plus one face/body diagonal per cube), boundary
/// nodes fixed.
pub fn cube(n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 2]>, Vec<u8>) {
    let id = |i: usize, j: usize, k: usize| (i + n * (j + n * k)) as u32;
    let h = 1.0 / (n - 1) as f64;
    let mut pts = Vec::new();
    let mut fixed = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let (x, y, z) = (i as f64 * h, j as f64 * h, k as f64 * h);
                pts.push([x + 0.2 * y * z, y + 0.1 * x * x, z + 0.15 * x * y]);
                let b = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
                fixed.push(u8::from(b));
            }
        }
    }
    let mut edges = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                if i + 1 < n {
                    edges.push([id(i, j, k), id(i + 1, j, k)]);
                }
                if j + 1 < n {
                    edges.push([id(i, j, k), id(i, j + 1, k)]);
                }
                if k + 1 < n {
                    edges.push([id(i, j, k), id(i, j, k + 1)]);
                }
                if i + 1 < n && j + 1 < n {
                    edges.push([id(i, j, k), id(i + 1, j + 1, k)]);
                }
                if j + 1 < n && k + 1 < n {
                    edges.push([id(i, j, k), id(i, j + 1, k + 1)]);
                }
                if i + 1 < n && k + 1 < n {
                    edges.push([id(i, j, k), id(i + 1, j, k + 1)]);
                }
                if i + 1 < n && j + 1 < n && k + 1 < n {
                    edges.push([id(i, j, k), id(i + 1, j + 1, k + 1)]);
                }
            }
        }
    }
    (pts, edges, fixed)
}

/// Rigid rotation by `deg` degrees about `centre`, as a displacement of `p`.
pub fn rotation_displacement(p: [f64; 2], centre: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    let (dx, dy) = (p[0] - centre[0], p[1] - centre[1]);
    [
        centre[0] + c * dx - s * dy - p[0],
        centre[1] + s * dx + c * dy - p[1],
    ]
}

/// One Jacobi-order sweep of the angle-inclusion direct method: each free node solves its
/// own block system `A_ii δ = Σ_j B_ij (x_j − x_i)` (dense elimination here, Cramer's rule in
/// the kernel) with neighbours from `x`. `None` when a node block is singular.
pub fn angle_jacobi_sweep<const D: usize>(
    net: &Net<f64>,
    points: &[[f64; D]],
    eps: f64,
    x: &[[f64; D]],
) -> Option<Vec<[f64; D]>> {
    let mut out = x.to_vec();
    for i in 0..net.n() {
        if net.fixed[i] != 0 {
            continue;
        }
        let mut a = vec![vec![0.0; D]; D];
        let mut r = vec![0.0; D];
        for (j, k) in net.row(i) {
            let blk = edge_block(points[i], points[j], k, eps);
            for p in 0..D {
                for c in 0..D {
                    a[p][c] += blk[p][c];
                    r[p] += blk[p][c] * (x[j][c] - x[i][c]);
                }
            }
        }
        let dx = dense_solve(a, r)?;
        for c in 0..D {
            out[i][c] = x[i][c] + dx[c];
        }
    }
    Some(out)
}
