//! Reference implementation: mesh quality, written naively in `f64` with `Vec` and
//! `BTreeMap`, sharing no code with the kernel.
//!
//! Independent routes to the same quantities:
//! - 2D measures by the polygon shoelace sum; corner Jacobians as explicit cross products
//!   (the same formula and order as the kernel, so those agree exactly).
//! - 3D measures by Gauss quadrature of the isoparametric Jacobian determinant (2×2×2 points
//!   for hexahedra and pyramids-as-collapsed-hexahedra, centroid × 2-point Gauss for the
//!   wedge): exact for these polynomial maps, but a different evaluation order than the
//!   kernel's closed forms, so they agree to rounding only.
//! - 3D corner Jacobians as the determinant of the shape-function Jacobian evaluated at each
//!   corner's parametric point.
//! - Wall angles from `atan2` of each vector separately (2D) or `acos` (3D).

use std::collections::{BTreeMap, BTreeSet};

/// VTK hexahedron corners in parametric coordinates.
const HEX_PARAM: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];

fn det(m: [[f64; 3]; 3]) -> f64 {
    // Rule of Sarrus, columns m[0], m[1], m[2].
    let [a, b, c] = m;
    a[0] * b[1] * c[2] + b[0] * c[1] * a[2] + c[0] * a[1] * b[2]
        - c[0] * b[1] * a[2]
        - b[0] * a[1] * c[2]
        - a[0] * c[1] * b[2]
}

/// Jacobian columns `∂x/∂ξ, ∂x/∂η, ∂x/∂ζ` of the trilinear map of 8 points at `(u, v, w)`.
fn hex_jacobian(p: &[[f64; 3]], u: f64, v: f64, w: f64) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (n, q) in HEX_PARAM.iter().enumerate() {
        let f = |t: f64, s: f64| if s == 1.0 { t } else { 1.0 - t };
        let df = |s: f64| if s == 1.0 { 1.0 } else { -1.0 };
        let d = [
            df(q[0]) * f(v, q[1]) * f(w, q[2]),
            f(u, q[0]) * df(q[1]) * f(w, q[2]),
            f(u, q[0]) * f(v, q[1]) * df(q[2]),
        ];
        for (col, dn) in j.iter_mut().zip(d) {
            for k in 0..3 {
                col[k] += dn * p[n][k];
            }
        }
    }
    j
}

const GAUSS2: [f64; 2] = [0.211_324_865_405_187_1, 0.788_675_134_594_812_9];

fn hex_volume_quadrature(p: &[[f64; 3]]) -> f64 {
    let mut v = 0.0;
    for &a in &GAUSS2 {
        for &b in &GAUSS2 {
            for &c in &GAUSS2 {
                v += det(hex_jacobian(p, a, b, c)) / 8.0;
            }
        }
    }
    v
}

/// Wedge map `x = Σ λ_i (1 − ζ) b_i + λ_i ζ t_i` with `λ = (1 − ξ − η, ξ, η)`.
fn wedge_jacobian(p: &[[f64; 3]], xi: f64, eta: f64, zeta: f64) -> [[f64; 3]; 3] {
    let lam = [1.0 - xi - eta, xi, eta];
    let dxi = [-1.0, 1.0, 0.0];
    let deta = [-1.0, 0.0, 1.0];
    let mut j = [[0.0; 3]; 3];
    for i in 0..3 {
        let b = p[i];
        let t = p[i + 3];
        for k in 0..3 {
            let along = (1.0 - zeta) * b[k] + zeta * t[k];
            j[0][k] += dxi[i] * along;
            j[1][k] += deta[i] * along;
            j[2][k] += lam[i] * (t[k] - b[k]);
        }
    }
    j
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn len3(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Corners relative to the first one (translation-invariant quantities lose no digits to
/// cancellation far from the origin).
fn relative(p: &[[f64; 3]]) -> Vec<[f64; 3]> {
    p.iter().map(|&q| sub3(q, p[0])).collect()
}

/// Signed measure of one cell (VTK code `kind`, corner coordinates padded to 3D).
pub fn measure(kind: u8, p: &[[f64; 3]]) -> f64 {
    let p = &relative(p)[..];
    match kind {
        5 | 9 => {
            // Shoelace on coordinates relative to the first corner (avoids cancellation far
            // from the origin).
            let n = p.len();
            let o = p[0];
            let mut s = 0.0;
            for i in 0..n {
                let a = sub3(p[i], o);
                let b = sub3(p[(i + 1) % n], o);
                s += a[0] * b[1] - b[0] * a[1];
            }
            0.5 * s
        }
        10 => det([sub3(p[1], p[0]), sub3(p[2], p[0]), sub3(p[3], p[0])]) / 6.0,
        12 => hex_volume_quadrature(p),
        13 => {
            // Triangle centroid rule (area ½) × 2-point Gauss in ζ. The VTK wedge's base turns
            // away from its top, so its parametric Jacobian is negative for a valid cell.
            let mut v = 0.0;
            for &z in &GAUSS2 {
                v += det(wedge_jacobian(p, 1.0 / 3.0, 1.0 / 3.0, z)) * 0.5 * 0.5;
            }
            -v
        }
        14 => {
            let h = [p[0], p[1], p[2], p[3], p[4], p[4], p[4], p[4]];
            hex_volume_quadrature(&h)
        }
        _ => panic!("unsupported kind {kind}"),
    }
}

/// Corner Jacobians of one cell, and each one scaled by its edge lengths.
pub fn corner_jacobians(kind: u8, p: &[[f64; 3]]) -> Vec<(f64, f64)> {
    let rel = relative(p);
    // 2D corner Jacobians use the same differences as the kernel (exact parity); 3D ones the
    // shifted corners.
    let p = if matches!(kind, 5 | 9) { p } else { &rel[..] };
    let mut out = Vec::new();
    match kind {
        5 | 9 => {
            let n = p.len();
            for i in 0..n {
                let o = p[i];
                let a = [p[(i + 1) % n][0] - o[0], p[(i + 1) % n][1] - o[1]];
                let b = [p[(i + n - 1) % n][0] - o[0], p[(i + n - 1) % n][1] - o[1]];
                let j = a[0] * b[1] - a[1] * b[0];
                let l = (a[0] * a[0] + a[1] * a[1]).sqrt() * (b[0] * b[0] + b[1] * b[1]).sqrt();
                out.push((j, scale(j, l)));
            }
        }
        10 => {
            let j = det([sub3(p[1], p[0]), sub3(p[2], p[0]), sub3(p[3], p[0])]);
            for i in 0..4 {
                let others: Vec<usize> = (0..4).filter(|&k| k != i).collect();
                let l: f64 = others.iter().map(|&k| len3(sub3(p[k], p[i]))).product();
                out.push((j, scale(j, l)));
            }
        }
        12 => {
            for (n, q) in HEX_PARAM.iter().enumerate() {
                let j = det(hex_jacobian(p, q[0], q[1], q[2]));
                // The three corners differing from this one in exactly one parametric axis.
                let mut l = 1.0;
                for (m, r) in HEX_PARAM.iter().enumerate() {
                    let diff = (0..3).filter(|&k| q[k] != r[k]).count();
                    if diff == 1 {
                        l *= len3(sub3(p[m], p[n]));
                    }
                }
                out.push((j, scale(j, l)));
            }
        }
        13 => {
            let corners = [
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [0.0, 1.0, 1.0],
            ];
            for (n, c) in corners.iter().enumerate() {
                let j = -det(wedge_jacobian(p, c[0], c[1], c[2]));
                let tri = n - n % 3;
                let l = len3(sub3(p[tri + (n + 1) % 3], p[n]))
                    * len3(sub3(p[tri + (n + 2) % 3], p[n]))
                    * len3(sub3(p[(n + 3) % 6], p[n]));
                out.push((j, scale(j, l)));
            }
        }
        14 => {
            let h = [p[0], p[1], p[2], p[3], p[4], p[4], p[4], p[4]];
            for n in 0..4 {
                let q = HEX_PARAM[n];
                let j = det(hex_jacobian(&h, q[0], q[1], q[2]));
                let l = len3(sub3(p[(n + 1) % 4], p[n]))
                    * len3(sub3(p[(n + 3) % 4], p[n]))
                    * len3(sub3(p[4], p[n]));
                out.push((j, scale(j, l)));
            }
        }
        _ => panic!("unsupported kind {kind}"),
    }
    out
}

fn scale(j: f64, l: f64) -> f64 {
    if l > 0.0 {
        (j / l).clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

/// A cell list in plain vectors: `(kind, nodes)` per cell.
pub type CellList = Vec<(u8, Vec<u32>)>;

/// Splits CSR arrays into a [`CellList`].
pub fn cell_list(offsets: &[u32], nodes: &[u32], kinds: &[u8]) -> CellList {
    kinds
        .iter()
        .enumerate()
        .map(|(c, &k)| {
            (
                k,
                nodes[offsets[c] as usize..offsets[c + 1] as usize].to_vec(),
            )
        })
        .collect()
}

fn corners_of(points: &[Vec<f64>], nodes: &[u32]) -> Vec<[f64; 3]> {
    nodes
        .iter()
        .map(|&n| {
            let p = &points[n as usize];
            [p[0], p[1], p.get(2).copied().unwrap_or(0.0)]
        })
        .collect()
}

/// Signed measure of every cell.
pub fn measures(cells: &CellList, points: &[Vec<f64>]) -> Vec<f64> {
    cells
        .iter()
        .map(|(k, n)| measure(*k, &corners_of(points, n)))
        .collect()
}

/// Smallest corner Jacobian (or scaled Jacobian) of every cell.
pub fn min_jacobians(cells: &CellList, points: &[Vec<f64>], scaled: bool) -> Vec<f64> {
    cells
        .iter()
        .map(|(k, n)| {
            corner_jacobians(*k, &corners_of(points, n))
                .into_iter()
                .map(|(j, s)| if scaled { s } else { j })
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// The reference quality report.
#[derive(Clone, Debug, PartialEq)]
pub struct RefReport {
    /// Cells whose measure changed sign.
    pub inverted: usize,
    /// Deformed cells with a corner Jacobian ≤ 0.
    pub folded: usize,
    /// Smallest ratio deformed/undeformed.
    pub min_ratio: f64,
    /// Largest ratio.
    pub max_ratio: f64,
}

/// Inverted/folded counts and ratio range.
pub fn compare(cells: &CellList, undeformed: &[Vec<f64>], deformed: &[Vec<f64>]) -> RefReport {
    let mu = measures(cells, undeformed);
    let md = measures(cells, deformed);
    let jd = min_jacobians(cells, deformed, false);
    let mut r = RefReport {
        inverted: 0,
        folded: 0,
        min_ratio: f64::INFINITY,
        max_ratio: f64::NEG_INFINITY,
    };
    for c in 0..cells.len() {
        let (u, d) = (mu[c], md[c]);
        if (u > 0.0 && d <= 0.0) || (u < 0.0 && d >= 0.0) {
            r.inverted += 1;
        }
        if jd[c] <= 0.0 {
            r.folded += 1;
        }
        if u != 0.0 {
            r.min_ratio = r.min_ratio.min(d / u);
            r.max_ratio = r.max_ratio.max(d / u);
        }
    }
    r
}

/// Node adjacency from the cells' edges (ascending neighbour sets).
pub fn adjacency(cells: &CellList, node_count: usize) -> Vec<BTreeSet<u32>> {
    let mut adj = vec![BTreeSet::new(); node_count];
    let mut link = |a: u32, b: u32| {
        adj[a as usize].insert(b);
        adj[b as usize].insert(a);
    };
    for (k, n) in cells {
        let pairs: Vec<(usize, usize)> = match k {
            5 => vec![(0, 1), (1, 2), (2, 0)],
            9 => vec![(0, 1), (1, 2), (2, 3), (3, 0)],
            10 => vec![(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)],
            12 => (0..4)
                .flat_map(|i| [(i, (i + 1) % 4), (i + 4, (i + 1) % 4 + 4), (i, i + 4)])
                .collect(),
            13 => vec![
                (0, 1),
                (1, 2),
                (2, 0),
                (3, 4),
                (4, 5),
                (5, 3),
                (0, 3),
                (1, 4),
                (2, 5),
            ],
            14 => (0..4).flat_map(|i| [(i, (i + 1) % 4), (i, 4)]).collect(),
            _ => vec![],
        };
        for (a, b) in pairs {
            link(n[a], n[b]);
        }
    }
    adj
}

/// Reference wall-angle change (same definition as the kernel's `wall_angle_change`):
/// returns `(max change, node, measured, skipped)`.
pub fn wall_angle_change(
    wall: &CellList,
    adj: &[BTreeSet<u32>],
    undeformed: &[Vec<f64>],
    deformed: &[Vec<f64>],
) -> (f64, Option<usize>, usize, usize) {
    let dim = undeformed.first().map_or(2, |p| p.len());
    let normal = |pts: &[Vec<f64>], k: u8, n: &[u32]| -> Vec<f64> {
        let q = corners_of(pts, n);
        match k {
            3 => vec![q[1][1] - q[0][1], q[0][0] - q[1][0]],
            _ => {
                let (a, b) = if k == 5 {
                    (sub3(q[1], q[0]), sub3(q[2], q[0]))
                } else {
                    (sub3(q[2], q[0]), sub3(q[3], q[1]))
                };
                vec![
                    0.5 * (a[1] * b[2] - a[2] * b[1]),
                    0.5 * (a[2] * b[0] - a[0] * b[2]),
                    0.5 * (a[0] * b[1] - a[1] * b[0]),
                ]
            }
        }
    };
    let mut nu: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
    let mut nd: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
    for (k, n) in wall {
        let eu = normal(undeformed, *k, n);
        let ed = normal(deformed, *k, n);
        for &v in n {
            let su = nu.entry(v).or_insert_with(|| vec![0.0; dim]);
            let sd = nd.entry(v).or_insert_with(|| vec![0.0; dim]);
            for i in 0..dim {
                su[i] += eu[i];
                sd[i] += ed[i];
            }
        }
    }
    let unit = |v: &[f64]| -> Option<Vec<f64>> {
        let l = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        (l > 0.0).then(|| v.iter().map(|x| x / l).collect())
    };
    let diff = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x - y).collect() };
    let dotp = |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| x * y).sum() };
    let angle = |n: &[f64], e: &[f64]| -> f64 {
        if dim == 2 {
            e[1].atan2(e[0]) - n[1].atan2(n[0])
        } else {
            let l = dotp(e, e).sqrt();
            (dotp(n, e) / l).clamp(-1.0, 1.0).acos()
        }
    };
    let (mut best, mut node, mut measured, mut skipped) = (0.0, None, 0, 0);
    for (&w, su) in &nu {
        let (Some(n_u), Some(n_d)) = (unit(su), unit(&nd[&w])) else {
            skipped += 1;
            continue;
        };
        let xu = &undeformed[w as usize];
        let mut pick: Option<(f64, u32)> = None;
        for &j in &adj[w as usize] {
            if nu.contains_key(&j) {
                continue;
            }
            let e = diff(&undeformed[j as usize], xu);
            let l = dotp(&e, &e).sqrt();
            if l == 0.0 {
                continue;
            }
            let s = dotp(&n_u, &e).abs() / l;
            if pick.is_none_or(|(b, _)| s > b) {
                pick = Some((s, j));
            }
        }
        let Some((_, j)) = pick else {
            skipped += 1;
            continue;
        };
        let eu = diff(&undeformed[j as usize], xu);
        let ed = diff(&deformed[j as usize], &deformed[w as usize]);
        if dotp(&ed, &ed) == 0.0 {
            skipped += 1;
            continue;
        }
        let mut d = angle(&n_d, &ed) - angle(&n_u, &eu);
        if dim == 2 {
            let tau = 2.0 * std::f64::consts::PI;
            d = d.rem_euclid(tau);
            if d > std::f64::consts::PI {
                d = tau - d;
            }
        }
        let d = d.abs();
        measured += 1;
        if node.is_none() || d > best {
            best = d;
            node = Some(w as usize);
        }
    }
    (best, node, measured, skipped)
}
