//! Per-cell geometry: signed measure and corner Jacobians of one cell.
//!
//! Corners are gathered into a fixed `[[T; 3]; 8]` (unused slots and the `z` of 2D points are
//! zero) and every table index is masked with `& 7`, so no bounds check survives.

use crate::cells::CellKind;
use crate::real::Real;
use crate::vector::{add, cross, dot, norm, sub};

/// Signed measure and corner-Jacobian summary of one cell.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct CellQuality<T> {
    /// Signed area (2D) or volume (3D); positive for a correctly oriented cell.
    pub measure: T,
    /// Smallest corner Jacobian (a 2D cross product or 3D triple product of the corner's
    /// edges, in the cell's orientation); `≤ 0` means the cell is folded at that corner.
    pub min_jacobian: T,
    /// Smallest scaled corner Jacobian: each corner Jacobian divided by the product of its
    /// edge lengths (the sine of the corner angle in 2D), clamped to `[−1, 1]`; 0 when an edge
    /// has zero length.
    pub min_scaled_jacobian: T,
}

/// 2D corners: `[corner, next, previous]` with Jacobian `(next − c) × (previous − c)`.
const TRI_CORNERS: [[u8; 3]; 3] = [[0, 1, 2], [1, 2, 0], [2, 0, 1]];
const QUAD_CORNERS: [[u8; 3]; 4] = [[0, 1, 3], [1, 2, 0], [2, 3, 1], [3, 0, 2]];

/// 3D corners: `[corner, a, b, c]` with Jacobian `det(a − corner, b − corner, c − corner)`,
/// positive for a VTK-positive cell.
const TET_CORNERS: [[u8; 4]; 4] = [[0, 1, 2, 3], [1, 2, 0, 3], [2, 0, 1, 3], [3, 0, 2, 1]];
const HEX_CORNERS: [[u8; 4]; 8] = [
    [0, 1, 3, 4],
    [1, 2, 0, 5],
    [2, 3, 1, 6],
    [3, 0, 2, 7],
    [4, 7, 5, 0],
    [5, 4, 6, 1],
    [6, 5, 7, 2],
    [7, 6, 4, 3],
];
/// VTK wedge: base `0,1,2` turns away from the top `3,4,5` (3 above 0, 4 above 1, 5 above 2).
const PRISM_CORNERS: [[u8; 4]; 6] = [
    [0, 2, 1, 3],
    [1, 0, 2, 4],
    [2, 1, 0, 5],
    [3, 4, 5, 0],
    [4, 5, 3, 1],
    [5, 3, 4, 2],
];
/// Pyramid: the four base corners (each with the apex); the apex has four edges and no single
/// corner Jacobian, and every base-corner tetrahedron already contains it.
const PYRAMID_CORNERS: [[u8; 4]; 4] = [[0, 1, 3, 4], [1, 2, 0, 4], [2, 3, 1, 4], [3, 0, 2, 4]];

/// Collapsed-hexahedron node lists: a prism and a pyramid are hexahedra with coincident
/// nodes, and the hexahedron volume formula is exact for any trilinear (bilinear-faced) cell,
/// so it gives their exact volumes too.
const PRISM_AS_HEX: [u8; 8] = [0, 2, 1, 1, 3, 5, 4, 4];
const PYRAMID_AS_HEX: [u8; 8] = [0, 1, 2, 3, 4, 4, 4, 4];

#[inline(always)]
fn at<T: Copy>(p: &[[T; 3]; 8], k: u8) -> [T; 3] {
    p[usize::from(k & 7)]
}

#[inline(always)]
fn xy<T: Copy>(a: [T; 3]) -> [T; 2] {
    [a[0], a[1]]
}

#[inline]
fn scaled<T: Real>(jac: T, lengths: T) -> T {
    if lengths > T::ZERO && lengths.is_finite() {
        (jac / lengths).max(-T::ONE).min(T::ONE)
    } else {
        T::ZERO
    }
}

/// Gathers the corner coordinates of a cell (padding with zeros).
#[inline]
pub(crate) fn gather<T: Real, const D: usize>(points: &[[T; D]], nodes: &[u32]) -> [[T; 3]; 8] {
    let mut out = [[T::ZERO; 3]; 8];
    for (slot, &n) in out.iter_mut().zip(nodes) {
        if let Some(p) = points.get(n as usize) {
            for (s, &x) in slot.iter_mut().zip(p.iter()) {
                *s = x;
            }
        }
    }
    out
}

fn corners_2d<T: Real>(p: &[[T; 3]; 8], table: &[[u8; 3]]) -> (T, T) {
    let mut min_j = T::INFINITY;
    let mut min_s = T::INFINITY;
    for c in table {
        let o = xy(at(p, c[0]));
        let a = sub(xy(at(p, c[1])), o);
        let b = sub(xy(at(p, c[2])), o);
        let j = a[0] * b[1] - a[1] * b[0];
        let s = scaled(j, norm(a) * norm(b));
        min_j = min_j.min(j);
        min_s = min_s.min(s);
    }
    (min_j, min_s)
}

fn det3<T: Real>(a: [T; 3], b: [T; 3], c: [T; 3]) -> T {
    dot(a, cross(b, c))
}

fn corners_3d<T: Real>(p: &[[T; 3]; 8], table: &[[u8; 4]]) -> (T, T) {
    let mut min_j = T::INFINITY;
    let mut min_s = T::INFINITY;
    for c in table {
        let o = at(p, c[0]);
        let a = sub(at(p, c[1]), o);
        let b = sub(at(p, c[2]), o);
        let d = sub(at(p, c[3]), o);
        let j = det3(a, b, d);
        let s = scaled(j, norm(a) * norm(b) * norm(d));
        min_j = min_j.min(j);
        min_s = min_s.min(s);
    }
    (min_j, min_s)
}

/// Outward faces of a VTK hexahedron.
const HEX_FACES: [[u8; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// Exact volume of a trilinear hexahedron (VTK order) by the divergence theorem over its
/// bilinear faces: `V = Σ_faces (a + b + c + d) · ((c − a) × (d − b)) / 24`, with coordinates
/// taken relative to corner 0 (no cancellation far from the origin). For a bilinear face the
/// flux of `x/3` equals its centroid fan's, which this sum is, so the result equals
/// `∫ det J` over the unit cube (checked against 2×2×2 Gauss quadrature in the tests).
fn hex_volume<T: Real>(h: &[[T; 3]; 8]) -> T {
    let o = h[0];
    let mut r = [[T::ZERO; 3]; 8];
    for (slot, p) in r.iter_mut().zip(h) {
        *slot = sub(*p, o);
    }
    let mut v = T::ZERO;
    for f in &HEX_FACES {
        let a = at(&r, f[0]);
        let b = at(&r, f[1]);
        let c = at(&r, f[2]);
        let d = at(&r, f[3]);
        v += dot(add(add(a, b), add(c, d)), cross(sub(c, a), sub(d, b)));
    }
    v / T::from_f64(24.0)
}

fn collapsed_hex_volume<T: Real>(p: &[[T; 3]; 8], map: &[u8; 8]) -> T {
    let mut h = [[T::ZERO; 3]; 8];
    for (slot, &k) in h.iter_mut().zip(map) {
        *slot = at(p, k);
    }
    hex_volume(&h)
}

/// Evaluates one cell from gathered corners. `planar` selects the 2D kinds (triangle, quad)
/// versus the 3D kinds; `None` when the kind does not fit.
pub(crate) fn evaluate<T: Real>(
    kind: CellKind,
    p: &[[T; 3]; 8],
    planar: bool,
) -> Option<CellQuality<T>> {
    let (measure, (min_jacobian, min_scaled_jacobian)) = match (planar, kind) {
        (true, CellKind::Triangle) => {
            let a = sub(xy(p[1]), xy(p[0]));
            let b = sub(xy(p[2]), xy(p[0]));
            (
                T::HALF * (a[0] * b[1] - a[1] * b[0]),
                corners_2d(p, &TRI_CORNERS),
            )
        }
        (true, CellKind::Quad) => {
            // Shoelace via the diagonals: ½ (x2 − x0) × (x3 − x1) = ¼ Σ corner Jacobians.
            let a = sub(xy(p[2]), xy(p[0]));
            let b = sub(xy(p[3]), xy(p[1]));
            (
                T::HALF * (a[0] * b[1] - a[1] * b[0]),
                corners_2d(p, &QUAD_CORNERS),
            )
        }
        (false, CellKind::Tetra) => {
            let v = det3(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
            (v / T::from_f64(6.0), corners_3d(p, &TET_CORNERS))
        }
        (false, CellKind::Hexahedron) => (hex_volume(p), corners_3d(p, &HEX_CORNERS)),
        (false, CellKind::Prism) => (
            collapsed_hex_volume(p, &PRISM_AS_HEX),
            corners_3d(p, &PRISM_CORNERS),
        ),
        (false, CellKind::Pyramid) => (
            collapsed_hex_volume(p, &PYRAMID_AS_HEX),
            corners_3d(p, &PYRAMID_CORNERS),
        ),
        _ => return None,
    };
    Some(CellQuality {
        measure,
        min_jacobian,
        min_scaled_jacobian,
    })
}
