//! A small jittered triangle mesh (6 × 5 nodes, 40 triangles, perimeter fixed) and a small
//! structured block, built into fixed-size arrays (no allocation), shared by the test binaries.

use deform_golden::XorShift;
use deform_kernel::{graph_from_cells, Block, CellKind, Cells, Graph, Quat, Real};

/// Grid points along x.
pub const NX: usize = 6;
/// Grid points along y.
pub const NY: usize = 5;
/// Nodes.
pub const N: usize = NX * NY;
/// Triangles (two per quad).
pub const NT: usize = 2 * (NX - 1) * (NY - 1);
/// Perimeter nodes.
pub const NB: usize = 2 * (NX + NY) - 4;
/// Upper bound of directed edges.
pub const NE: usize = 6 * NT;
/// Directed edges of the graph: rows, columns and one diagonal per quad, both ways.
pub const EDGES: usize = 2 * ((NX - 1) * NY + NX * (NY - 1) + (NX - 1) * (NY - 1));
/// Grid spacing in y (x spacing is 1).
pub const DY: f64 = 0.8;

/// The mesh: points, triangle cells, edge graph, perimeter list and fixed mask.
pub struct Mesh<T> {
    /// Node coordinates (interior nodes jittered).
    pub points: [[T; 2]; N],
    /// Cell offsets.
    pub offsets: [u32; NT + 1],
    /// Cell nodes.
    pub nodes: [u32; 3 * NT],
    /// Cell kinds (all triangles).
    pub kinds: [u8; NT],
    /// Graph offsets.
    pub graph_offsets: [u32; N + 1],
    /// Graph targets (the first `used` are valid).
    pub targets: [u32; NE],
    /// Valid graph targets.
    pub used: usize,
    /// Perimeter nodes in row-major order.
    pub boundary: [u32; NB],
    /// 1 on the perimeter.
    pub fixed: [u8; N],
}

impl<T: Real> Mesh<T> {
    /// A mesh with interior jitter `jitter` (0 = regular), from a fixed seed.
    pub fn new(jitter: f64) -> Self {
        let mut rng = XorShift::new(0x0A7A_46E7);
        let mut m = Mesh {
            points: [[T::ZERO; 2]; N],
            offsets: [0; NT + 1],
            nodes: [0; 3 * NT],
            kinds: [CellKind::Triangle.vtk_code(); NT],
            graph_offsets: [0; N + 1],
            targets: [0; NE],
            used: 0,
            boundary: [0; NB],
            fixed: [0; N],
        };
        let mut b = 0;
        for j in 0..NY {
            for i in 0..NX {
                let on_edge = i == 0 || j == 0 || i == NX - 1 || j == NY - 1;
                let jit = if on_edge { 0.0 } else { jitter };
                let x = i as f64 + jit * (rng.unit_f64() - 0.5);
                let y = j as f64 * DY + jit * (rng.unit_f64() - 0.5);
                let p = i + NX * j;
                if let Some(pt) = m.points.get_mut(p) {
                    *pt = [T::from_f64(x), T::from_f64(y)];
                }
                if on_edge {
                    if let (Some(s), Some(f)) = (m.boundary.get_mut(b), m.fixed.get_mut(p)) {
                        *s = p as u32;
                        *f = 1;
                    }
                    b += 1;
                }
            }
        }
        let mut c = 0;
        for j in 0..NY - 1 {
            for i in 0..NX - 1 {
                let a = (i + NX * j) as u32;
                let (b1, c1, d1) = (a + 1, a + 1 + NX as u32, a + NX as u32);
                let tris = if (i + j) % 2 == 0 {
                    [[a, b1, c1], [a, c1, d1]]
                } else {
                    [[a, b1, d1], [b1, c1, d1]]
                };
                for t in tris {
                    for (k, v) in t.into_iter().enumerate() {
                        if let Some(s) = m.nodes.get_mut(3 * c + k) {
                            *s = v;
                        }
                    }
                    c += 1;
                    if let Some(o) = m.offsets.get_mut(c) {
                        *o = 3 * c as u32;
                    }
                }
            }
        }
        let cells = Cells::new(N, &m.offsets, &m.nodes, &m.kinds).unwrap();
        m.used = graph_from_cells(&cells, false, &mut m.graph_offsets, &mut m.targets).unwrap();
        m
    }

    /// The triangle cells.
    pub fn cells(&self) -> Cells<'_> {
        Cells::new(N, &self.offsets, &self.nodes, &self.kinds).unwrap()
    }

    /// The edge graph.
    pub fn graph(&self) -> Graph<'_> {
        Graph::new(&self.graph_offsets, &self.targets[..self.used]).unwrap()
    }
}

/// The perimeter's positions at step `s`: the bottom row turns by `4° s` about its midpoint,
/// the rest stays (the time steps of the plan tests).
pub fn turned_bottom_row<T: Real>(m: &Mesh<T>, s: usize) -> [[T; 2]; NB] {
    let q = Quat::from_rotation_z(T::from_f64((4.0 * s as f64).to_radians()));
    let c = [T::from_f64((NX - 1) as f64 * 0.5), T::ZERO];
    let mut d = [[T::ZERO; 2]; NB];
    for (di, &i) in d.iter_mut().zip(&m.boundary) {
        let p = m.points.get(i as usize).copied().unwrap_or([T::ZERO; 2]);
        *di = if (i as usize) < NX {
            let r = q.rotate_2d([p[0] - c[0], p[1] - c[1]]);
            [r[0] + c[0], r[1] + c[1]]
        } else {
            p
        };
    }
    d
}

/// The regular `NX × NY` grid as a structured block (same node numbering as [`Mesh`]).
pub fn block() -> Block {
    Block::new([NX, NY, 1]).unwrap()
}
