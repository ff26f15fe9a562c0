//! Shared helpers of the deformation tests: small structured meshes, their boundaries (as
//! boundary-local elements), rigid motions computed in `f64`, and error measures.
#![allow(dead_code)]

use std::collections::BTreeMap;

use deform_host_tests::deformation_ref::{quat_matrix, Mat3};
use deform_kernel::{Block, CellKind, Real};

/// A structured test block with its cells and boundary.
pub struct TestMesh<const D: usize> {
    /// Block dims (`nk = 1` in 2D).
    pub dims: [usize; 3],
    /// Undeformed points (f64).
    pub points: Vec<[f64; D]>,
    /// Cells (quads in 2D, hexahedra in 3D): offsets, nodes, kinds.
    pub cell_offsets: Vec<u32>,
    /// Cell nodes.
    pub cell_nodes: Vec<u32>,
    /// Cell kinds.
    pub cell_kinds: Vec<u8>,
    /// Mesh node of each boundary point.
    pub boundary: Vec<u32>,
    /// Boundary elements over boundary-local indices: offsets, nodes, kinds.
    pub el_offsets: Vec<u32>,
    /// Element nodes (local).
    pub el_nodes: Vec<u32>,
    /// Element kinds.
    pub el_kinds: Vec<u8>,
}

impl<const D: usize> TestMesh<D> {
    /// The block.
    pub fn block(&self) -> Block {
        Block::new(self.dims).unwrap()
    }
    /// Points converted to `T`.
    pub fn points_t<T: Real>(&self) -> Vec<[T; D]> {
        self.points.iter().map(|p| p.map(T::from_f64)).collect()
    }
    /// Boundary elements as a validated kernel view.
    pub fn elements(&self) -> deform_kernel::Cells<'_> {
        deform_kernel::Cells::new(
            self.boundary.len(),
            &self.el_offsets,
            &self.el_nodes,
            &self.el_kinds,
        )
        .unwrap()
    }
    /// Mesh cells as a validated kernel view.
    pub fn cells(&self) -> deform_kernel::Cells<'_> {
        deform_kernel::Cells::new(
            self.points.len(),
            &self.cell_offsets,
            &self.cell_nodes,
            &self.cell_kinds,
        )
        .unwrap()
    }
}

/// A curved, non-uniformly spaced 2D block `ni × nj` (all four sides are boundary; the
/// boundary loop is counter-clockwise, so segment normals point out).
pub fn block2(ni: usize, nj: usize) -> TestMesh<2> {
    let mut points = Vec::new();
    for j in 0..nj {
        for i in 0..ni {
            let s = i as f64 / (ni - 1) as f64;
            let t = j as f64 / (nj - 1) as f64;
            let s2 = s * s * (1.5 - 0.5 * s); // stretched
            let t2 = t * (0.6 + 0.4 * t);
            let x = 2.0 * s2 + 0.15 * (std::f64::consts::PI * t2).sin();
            let y = 1.2 * t2 + 0.1 * (2.0 * std::f64::consts::PI * s2).sin() * (1.0 - t2);
            points.push([x + 0.37, y - 0.21]);
        }
    }
    let id = |i: usize, j: usize| (i + ni * j) as u32;
    let mut cell_offsets = vec![0u32];
    let mut cell_nodes = Vec::new();
    let mut cell_kinds = Vec::new();
    for j in 0..nj - 1 {
        for i in 0..ni - 1 {
            cell_nodes.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            cell_kinds.push(CellKind::Quad.vtk_code());
            cell_offsets.push(cell_nodes.len() as u32);
        }
    }
    // Counter-clockwise loop: bottom, right, top, left.
    let mut boundary = Vec::new();
    for i in 0..ni - 1 {
        boundary.push(id(i, 0));
    }
    for j in 0..nj - 1 {
        boundary.push(id(ni - 1, j));
    }
    for i in (1..ni).rev() {
        boundary.push(id(i, nj - 1));
    }
    for j in (1..nj).rev() {
        boundary.push(id(0, j));
    }
    let b = boundary.len() as u32;
    let mut el_offsets = vec![0u32];
    let mut el_nodes = Vec::new();
    let mut el_kinds = Vec::new();
    for k in 0..b {
        el_nodes.extend([k, (k + 1) % b]);
        el_kinds.push(CellKind::Line.vtk_code());
        el_offsets.push(el_nodes.len() as u32);
    }
    TestMesh {
        dims: [ni, nj, 1],
        points,
        cell_offsets,
        cell_nodes,
        cell_kinds,
        boundary,
        el_offsets,
        el_nodes,
        el_kinds,
    }
}

/// A curved, non-uniformly spaced 3D block `ni × nj × nk`; the boundary is every surface
/// point, with outward-oriented surface quads.
pub fn block3(ni: usize, nj: usize, nk: usize) -> TestMesh<3> {
    let mut points = Vec::new();
    for k in 0..nk {
        for j in 0..nj {
            for i in 0..ni {
                let s = i as f64 / (ni - 1) as f64;
                let t = j as f64 / (nj - 1) as f64;
                let r = k as f64 / (nk - 1) as f64;
                let s2 = s * s * (1.5 - 0.5 * s);
                let t2 = t * (0.7 + 0.3 * t);
                let x = 1.5 * s2 + 0.1 * (std::f64::consts::PI * t2).sin();
                let y = 1.1 * t2 + 0.08 * (2.0 * std::f64::consts::PI * s2).sin();
                let z = 0.9 * r + 0.05 * (std::f64::consts::PI * s2).sin() * t2;
                points.push([x - 0.3, y + 0.4, z + 0.1]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + ni * (j + nj * k)) as u32;
    let mut cell_offsets = vec![0u32];
    let mut cell_nodes = Vec::new();
    let mut cell_kinds = Vec::new();
    for k in 0..nk - 1 {
        for j in 0..nj - 1 {
            for i in 0..ni - 1 {
                cell_nodes.extend([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
                cell_kinds.push(CellKind::Hexahedron.vtk_code());
                cell_offsets.push(cell_nodes.len() as u32);
            }
        }
    }
    // Surface quads in global numbering, oriented outward (checked against the block centre).
    let centre = {
        let mut c = [0.0; 3];
        for p in &points {
            for d in 0..3 {
                c[d] += p[d] / points.len() as f64;
            }
        }
        c
    };
    let mut quads: Vec<[u32; 4]> = Vec::new();
    let dims = [ni, nj, nk];
    for dir in 0..3 {
        let (a, b) = ((dir + 1) % 3, (dir + 2) % 3);
        for side in [0, dims[dir] - 1] {
            for u in 0..dims[a] - 1 {
                for v in 0..dims[b] - 1 {
                    let mk = |du: usize, dv: usize| {
                        let mut c = [0usize; 3];
                        c[dir] = side;
                        c[a] = u + du;
                        c[b] = v + dv;
                        id(c[0], c[1], c[2])
                    };
                    let mut q = [mk(0, 0), mk(1, 0), mk(1, 1), mk(0, 1)];
                    let p = |n: u32| points[n as usize];
                    let d1 = sub(p(q[2]), p(q[0]));
                    let d2 = sub(p(q[3]), p(q[1]));
                    let n = cross(d1, d2);
                    let mid = p(q[0]);
                    if dot(n, sub(mid, centre)) < 0.0 {
                        q.reverse();
                    }
                    quads.push(q);
                }
            }
        }
    }
    let mut local: BTreeMap<u32, u32> = BTreeMap::new();
    let mut boundary = Vec::new();
    for q in &quads {
        for &n in q {
            local.entry(n).or_insert_with(|| {
                boundary.push(n);
                (boundary.len() - 1) as u32
            });
        }
    }
    let mut el_offsets = vec![0u32];
    let mut el_nodes = Vec::new();
    let mut el_kinds = Vec::new();
    for q in &quads {
        el_nodes.extend(q.iter().map(|n| local[n]));
        el_kinds.push(CellKind::Quad.vtk_code());
        el_offsets.push(el_nodes.len() as u32);
    }
    TestMesh {
        dims,
        points,
        cell_offsets,
        cell_nodes,
        cell_kinds,
        boundary,
        el_offsets,
        el_nodes,
        el_kinds,
    }
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `[x, y] → [x, y, 0]`, `[x, y, z]` unchanged.
pub fn to3<const D: usize>(p: [f64; D]) -> [f64; 3] {
    let mut r = [0.0; 3];
    r[..D].copy_from_slice(&p);
    r
}

/// First `D` components.
pub fn from3<const D: usize>(p: [f64; 3]) -> [f64; D] {
    let mut r = [0.0; D];
    r.copy_from_slice(&p[..D]);
    r
}

/// A rigid motion `x ↦ c + t + R (x − c)` evaluated in f64.
#[derive(Clone, Copy)]
pub struct Rigid {
    pub r: Mat3,
    pub c: [f64; 3],
    pub t: [f64; 3],
}

impl Rigid {
    /// From a quaternion `[w, x, y, z]` (normalised in f64).
    pub fn new(q: [f64; 4], c: [f64; 3], t: [f64; 3]) -> Self {
        Rigid {
            r: quat_matrix(q),
            c,
            t,
        }
    }
    /// Applies the motion.
    pub fn apply<const D: usize>(&self, p: [f64; D]) -> [f64; D] {
        let x = sub(to3(p), self.c);
        let rx = [dot(self.r[0], x), dot(self.r[1], x), dot(self.r[2], x)];
        from3([
            self.c[0] + self.t[0] + rx[0],
            self.c[1] + self.t[1] + rx[1],
            self.c[2] + self.t[2] + rx[2],
        ])
    }
}

/// Largest component difference between `a` (type `T`) and the f64 `b`.
pub fn max_err<T: Real, const D: usize>(a: &[[T; D]], b: &[[f64; D]]) -> f64 {
    let mut e: f64 = 0.0;
    for (x, y) in a.iter().zip(b) {
        for d in 0..D {
            e = e.max((x[d].to_f64() - y[d]).abs());
        }
    }
    e
}

/// Largest absolute coordinate.
pub fn scale<const D: usize>(p: &[[f64; D]]) -> f64 {
    p.iter()
        .flat_map(|x| x.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()))
}

/// Bit patterns of a point list (for bitwise comparisons).
pub fn bits<T: Real, const D: usize>(p: &[[T; D]]) -> Vec<u64> {
    p.iter()
        .flat_map(|x| x.iter().map(|c| c.to_bits_u64()))
        .collect()
}
