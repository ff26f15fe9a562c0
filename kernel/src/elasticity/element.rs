//! Isoparametric element geometry: reference shape-function gradients of every volume
//! [`CellKind`] at its Gauss points, the Jacobian, and the element stiffness of isotropic
//! linear elasticity (plane strain in 2D).
//!
//! Quadrature as SU2's mesh solver: one point for P1 triangles and tetrahedra, 2×2 (2×2×2)
//! for Q1 quadrilaterals (hexahedra), 3×2 for prisms; the pyramid is the hexahedron with its
//! four top nodes collapsed into the apex (2×2×2 points, the standard trilinear pyramid).
//! Every element reproduces linear fields exactly (the patch test).

use crate::cells::CellKind;
use crate::real::Real;

/// Most nodes of a cell (the hexahedron).
pub(crate) const MAX_NODES: usize = 8;
/// Node pairs `a ≤ b` of a cell with [`MAX_NODES`] nodes.
pub(crate) const MAX_PAIRS: usize = MAX_NODES * (MAX_NODES + 1) / 2;

/// `1/√3`, the 2-point Gauss abscissa.
const G: f64 = 0.577_350_269_189_625_8;
/// The 2-point rule on `[−1, 1]`.
const LINE2: [f64; 2] = [-G, G];
/// The 3-point rule of the reference triangle (weights `1/6` each).
const TRI3: [[f64; 2]; 3] = [
    [1.0 / 6.0, 1.0 / 6.0],
    [2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0],
];
/// Corner signs of the quadrilateral and the hexahedron, VTK order.
const CORNERS: [[f64; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Number of Gauss points of `kind` (0 for a line, which has no volume).
pub(crate) fn point_count(kind: CellKind) -> usize {
    match kind {
        CellKind::Line => 0,
        CellKind::Triangle | CellKind::Tetra => 1,
        CellKind::Quad => 4,
        CellKind::Prism => 6,
        CellKind::Hexahedron | CellKind::Pyramid => 8,
    }
}

/// Gauss point `g` of `kind`: reference coordinates and weight.
fn point(kind: CellKind, g: usize) -> ([f64; 3], f64) {
    let l = |k: usize| LINE2.get(k & 1).copied().unwrap_or(0.0);
    match kind {
        CellKind::Line => ([0.0; 3], 0.0),
        CellKind::Triangle => ([1.0 / 3.0, 1.0 / 3.0, 0.0], 0.5),
        CellKind::Tetra => ([0.25, 0.25, 0.25], 1.0 / 6.0),
        CellKind::Quad => ([l(g), l(g >> 1), 0.0], 1.0),
        CellKind::Hexahedron | CellKind::Pyramid => ([l(g), l(g >> 1), l(g >> 2)], 1.0),
        CellKind::Prism => {
            let [r, s] = TRI3.get(g % 3).copied().unwrap_or([0.0; 2]);
            ([r, s, l(g / 3)], 1.0 / 6.0)
        }
    }
}

/// Reference gradients `∂N_a/∂ξ` of every node of `kind` at `xi`, into `out` (the first
/// `node_count` entries).
fn reference_gradients(kind: CellKind, xi: [f64; 3], out: &mut [[f64; 3]; MAX_NODES]) {
    let [x, y, z] = xi;
    let corner = |a: usize| CORNERS.get(a).copied().unwrap_or([0.0; 3]);
    match kind {
        CellKind::Line => {}
        CellKind::Triangle => {
            let g = [[-1.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
            out.iter_mut().zip(g).for_each(|(o, g)| *o = g);
        }
        CellKind::Tetra => {
            let g = [
                [-1.0, -1.0, -1.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
            ];
            out.iter_mut().zip(g).for_each(|(o, g)| *o = g);
        }
        CellKind::Quad => {
            for (a, o) in out.iter_mut().take(4).enumerate() {
                let [p, q, _] = corner(a);
                *o = [p * (1.0 + q * y) / 4.0, q * (1.0 + p * x) / 4.0, 0.0];
            }
        }
        CellKind::Hexahedron => {
            for (a, o) in out.iter_mut().enumerate() {
                let [p, q, r] = corner(a);
                let (u, v, w) = (1.0 + p * x, 1.0 + q * y, 1.0 + r * z);
                *o = [p * v * w / 8.0, q * u * w / 8.0, r * u * v / 8.0];
            }
        }
        CellKind::Pyramid => {
            for (a, o) in out.iter_mut().take(4).enumerate() {
                let [p, q, _] = corner(a);
                let (u, v, w) = (1.0 + p * x, 1.0 + q * y, 1.0 - z);
                *o = [p * v * w / 8.0, q * u * w / 8.0, -u * v / 8.0];
            }
            out[4] = [0.0, 0.0, 0.5];
        }
        CellKind::Prism => {
            let (lo, hi) = ((1.0 - z) / 2.0, (1.0 + z) / 2.0);
            let tri = [[-1.0, -1.0, 1.0 - x - y], [1.0, 0.0, x], [0.0, 1.0, y]];
            let (bottom, top) = out.split_at_mut(3);
            for ((b, t), [dr, ds, n]) in bottom.iter_mut().zip(top.iter_mut()).zip(tri) {
                *b = [dr * lo, ds * lo, -n / 2.0];
                *t = [dr * hi, ds * hi, n / 2.0];
            }
        }
    }
}

/// `(adj(J), det J)` of a 2×2 or 3×3 matrix (`adj(J) J = det J · I`).
fn adjugate<T: Real, const D: usize>(j: &[[T; D]; D]) -> ([[T; D]; D], T) {
    let m = |r: usize, c: usize| {
        j.get(r)
            .and_then(|row| row.get(c))
            .copied()
            .unwrap_or(T::ZERO)
    };
    let mut adj = [[T::ZERO; D]; D];
    if D == 2 {
        let v = [[m(1, 1), -m(0, 1)], [-m(1, 0), m(0, 0)]];
        for (row, vr) in adj.iter_mut().zip(v) {
            for (a, x) in row.iter_mut().zip(vr) {
                *a = x;
            }
        }
        return (adj, m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0));
    }
    for (r, row) in adj.iter_mut().enumerate() {
        for (c, a) in row.iter_mut().enumerate() {
            // adj[r][c] = cofactor C[c][r]
            let (r1, r2) = ((c + 1) % 3, (c + 2) % 3);
            let (c1, c2) = ((r + 1) % 3, (r + 2) % 3);
            *a = m(r1, c1) * m(r2, c2) - m(r1, c2) * m(r2, c1);
        }
    }
    let det = m(0, 0) * adj[0][0] + m(0, 1) * adj[1][0] + m(0, 2) * adj[2][0];
    (adj, det)
}

/// Physical gradients `∇N_a` of a cell at one Gauss point and the point's weight `w |det J|`.
pub(crate) struct GaussPoint<T, const D: usize> {
    /// `∇N_a` for the cell's nodes (the first `node_count` entries).
    pub grads: [[T; D]; MAX_NODES],
    /// Quadrature weight times `|det J|`.
    pub weight: T,
}

/// The cell's Gauss point `g` for node coordinates `x` (of `kind`), or `None` when the
/// Jacobian is singular or not finite there (a degenerate cell).
pub(crate) fn gauss_point<T: Real, const D: usize>(
    kind: CellKind,
    x: &[[T; D]],
    g: usize,
) -> Option<GaussPoint<T, D>> {
    let (xi, w) = point(kind, g);
    let mut rg = [[0.0f64; 3]; MAX_NODES];
    reference_gradients(kind, xi, &mut rg);
    let mut refs = [[T::ZERO; D]; MAX_NODES];
    for (r, g) in refs.iter_mut().zip(&rg) {
        for (r, &g) in r.iter_mut().zip(g) {
            *r = T::from_f64(g);
        }
    }
    let mut j = [[T::ZERO; D]; D];
    for (xa, ga) in x.iter().zip(&refs) {
        for (row, &xi) in j.iter_mut().zip(xa) {
            for (e, &gk) in row.iter_mut().zip(ga) {
                *e += xi * gk;
            }
        }
    }
    let (adj, det) = adjugate(&j);
    if det == T::ZERO || !det.is_finite() {
        return None;
    }
    let mut grads = [[T::ZERO; D]; MAX_NODES];
    for (out, ga) in grads.iter_mut().zip(&refs).take(x.len()) {
        // ∇N = J⁻ᵀ ∂N/∂ξ: component i is Σ_k adj[k][i] g_k / det.
        for (i, o) in out.iter_mut().enumerate() {
            let mut s = T::ZERO;
            for (k, &gk) in ga.iter().enumerate() {
                s += adj
                    .get(k)
                    .and_then(|r| r.get(i))
                    .copied()
                    .unwrap_or(T::ZERO)
                    * gk;
            }
            *o = s / det;
        }
    }
    Some(GaussPoint {
        grads,
        weight: T::from_f64(w) * det.abs(),
    })
}

/// The cell's measure `Σ_g w |det J|` (area or volume), or `None` for a degenerate cell.
pub(crate) fn measure<T: Real, const D: usize>(kind: CellKind, x: &[[T; D]]) -> Option<T> {
    let mut v = T::ZERO;
    for g in 0..point_count(kind) {
        v += gauss_point(kind, x, g)?.weight;
    }
    Some(v)
}

/// Lamé parameters `(λ, μ)` of Young's modulus `e` and Poisson ratio `nu` (plane strain in
/// 2D: the same formulas).
pub(crate) fn lame<T: Real>(e: T, nu: T) -> (T, T) {
    let lambda = e * nu / ((T::ONE + nu) * (T::ONE - T::TWO * nu));
    let mu = e / (T::TWO * (T::ONE + nu));
    (lambda, mu)
}

/// Index of the block of nodes `a ≤ b` in the upper-triangle block list of a cell.
#[inline]
pub(crate) fn pair_index(a: usize, b: usize) -> usize {
    b * (b + 1) / 2 + a
}

/// The element stiffness `K_ab = Σ_g w|J| [λ ∇N_a ∇N_bᵀ + μ ∇N_b ∇N_aᵀ + μ (∇N_a·∇N_b) I]`
/// for every node pair `a ≤ b`, into `out` at [`pair_index`]; the diagonal blocks are
/// computed on and above their diagonal and mirrored, so every block of the assembled
/// matrix is the exact transpose of its mirror. `None` for a degenerate cell.
pub(crate) fn stiffness<T: Real, const D: usize>(
    kind: CellKind,
    x: &[[T; D]],
    lambda: T,
    mu: T,
    out: &mut [[[T; D]; D]; MAX_PAIRS],
) -> Option<()> {
    let n = x.len().min(MAX_NODES);
    for b in out.iter_mut() {
        *b = [[T::ZERO; D]; D];
    }
    for g in 0..point_count(kind) {
        let p = gauss_point(kind, x, g)?;
        let (l, m) = (lambda * p.weight, mu * p.weight);
        for b in 0..n {
            for a in 0..=b {
                let (Some(ga), Some(gb), Some(blk)) = (
                    p.grads.get(a),
                    p.grads.get(b),
                    out.get_mut(pair_index(a, b)),
                ) else {
                    continue;
                };
                add_block(blk, ga, gb, l, m, a == b);
            }
        }
    }
    Some(())
}

/// `blk += l ga gbᵀ + m gb gaᵀ + m (ga·gb) I`; for a diagonal block only on and above the
/// diagonal, then mirrored.
#[inline]
fn add_block<T: Real, const D: usize>(
    blk: &mut [[T; D]; D],
    ga: &[T; D],
    gb: &[T; D],
    l: T,
    m: T,
    diagonal: bool,
) {
    let dot = crate::vector::dot(*ga, *gb);
    for i in 0..D {
        let start = if diagonal { i } else { 0 };
        for j in start..D {
            let (ai, aj, bi, bj) = (at(ga, i), at(ga, j), at(gb, i), at(gb, j));
            let mut v = l * ai * bj + m * aj * bi;
            if i == j {
                v += m * dot;
            }
            if let Some(e) = blk.get_mut(i).and_then(|r| r.get_mut(j)) {
                *e += v;
            }
        }
    }
    if diagonal {
        for i in 0..D {
            for j in 0..i {
                let v = blk
                    .get(j)
                    .and_then(|r| r.get(i))
                    .copied()
                    .unwrap_or(T::ZERO);
                if let Some(e) = blk.get_mut(i).and_then(|r| r.get_mut(j)) {
                    *e = v;
                }
            }
        }
    }
}

#[inline]
fn at<T: Real, const D: usize>(v: &[T; D], i: usize) -> T {
    v.get(i).copied().unwrap_or(T::ZERO)
}
