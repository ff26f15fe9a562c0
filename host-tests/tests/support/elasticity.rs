//! Small meshes of every element kind for the elasticity tests (jittered structured grids on
//! the unit square / cube) and the whole pipeline (graph, moduli, assembly, system, solve)
//! on owned buffers.

use deform_kernel::elasticity::{
    assemble, cell_moduli, elastic_scratch_len, elasticity_graph, elasticity_graph_len, Block,
    ElasticSystem, Modulus,
};
use deform_kernel::spring::{SolveOptions, SolveReport};
use deform_kernel::{Cells, Graph, Real};

/// Which cells a test grid is made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Triangles (2D) or tetrahedra (3D, six per cube).
    Simplex,
    /// Quadrilaterals (2D) or hexahedra (3D).
    Box,
    /// Prisms (3D, two per cube).
    Prism,
    /// Pyramids (3D, six per cube around a centre node).
    Pyramid,
    /// Alternating: quads and triangles (2D); columns of hexahedra, prisms and pyramids (3D:
    /// every shared face is a quadrilateral on both sides, or a triangle on both).
    Mixed,
}

/// A mesh with owned buffers; `boundary[i]` marks nodes on the square's / cube's faces.
#[derive(Clone, Debug)]
pub struct Mesh<const D: usize> {
    pub points: Vec<[f64; D]>,
    pub offsets: Vec<u32>,
    pub nodes: Vec<u32>,
    pub kinds: Vec<u8>,
    pub boundary: Vec<bool>,
}

impl<const D: usize> Mesh<D> {
    pub fn cells(&self) -> Cells<'_> {
        Cells::new(self.points.len(), &self.offsets, &self.nodes, &self.kinds).expect("cells")
    }
    fn push(&mut self, kind: u8, nodes: &[u32]) {
        self.nodes.extend_from_slice(nodes);
        self.offsets.push(self.nodes.len() as u32);
        self.kinds.push(kind);
    }
    /// The points in `T`.
    pub fn points_as<T: Real>(&self) -> Vec<[T; D]> {
        self.points.iter().map(|p| p.map(T::from_f64)).collect()
    }
}

/// Deterministic jitter in `[-1, 1)` (SplitMix64).
pub fn jitter(i: u64) -> f64 {
    let mut z = i.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// An `n × n` grid of the unit square, interior nodes moved by up to `amp · h`.
pub fn grid2(n: usize, kind: Kind, amp: f64) -> Mesh<2> {
    let h = 1.0 / n as f64;
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut m = Mesh {
        points: vec![],
        offsets: vec![0],
        nodes: vec![],
        kinds: vec![],
        boundary: vec![],
    };
    for j in 0..=n {
        for i in 0..=n {
            let b = i == 0 || j == 0 || i == n || j == n;
            let k = m.points.len() as u64;
            let d = if b {
                [0.0; 2]
            } else {
                [jitter(2 * k), jitter(2 * k + 1)]
            };
            m.points
                .push([(i as f64 + amp * d[0]) * h, (j as f64 + amp * d[1]) * h]);
            m.boundary.push(b);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            let tri = kind == Kind::Simplex || (kind == Kind::Mixed && (i + j) % 2 == 0);
            if tri {
                m.push(5, &[q[0], q[1], q[2]]);
                m.push(5, &[q[0], q[2], q[3]]);
            } else {
                m.push(9, &q);
            }
        }
    }
    m
}

/// An `n × n × n` grid of the unit cube, interior nodes moved by up to `amp · h`; pyramid
/// cubes get a centre node.
pub fn grid3(n: usize, kind: Kind, amp: f64) -> Mesh<3> {
    let h = 1.0 / n as f64;
    let id = |i: usize, j: usize, k: usize| ((k * (n + 1) + j) * (n + 1) + i) as u32;
    let mut m = Mesh {
        points: vec![],
        offsets: vec![0],
        nodes: vec![],
        kinds: vec![],
        boundary: vec![],
    };
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let b = [i, j, k].iter().any(|&c| c == 0 || c == n);
                let s = 3 * m.points.len() as u64;
                let d = if b {
                    [0.0; 3]
                } else {
                    [jitter(s), jitter(s + 1), jitter(s + 2)]
                };
                m.points.push([
                    (i as f64 + amp * d[0]) * h,
                    (j as f64 + amp * d[1]) * h,
                    (k as f64 + amp * d[2]) * h,
                ]);
                m.boundary.push(b);
            }
        }
    }
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                let pick = match kind {
                    // Columns, so that every shared face is split alike (conforming).
                    Kind::Mixed => [Kind::Box, Kind::Prism, Kind::Pyramid][(i + j) % 3],
                    other => other,
                };
                cube(&mut m, &c, pick);
            }
        }
    }
    m
}

/// Fills one cube (VTK hexahedron node order `c`) with cells of `kind`.
fn cube(m: &mut Mesh<3>, c: &[u32; 8], kind: Kind) {
    match kind {
        Kind::Box | Kind::Mixed => m.push(12, c),
        Kind::Prism => {
            // The bottom and top quads split along 0-2 / 4-6: conforming on every face.
            m.push(13, &[c[0], c[1], c[2], c[4], c[5], c[6]]);
            m.push(13, &[c[0], c[2], c[3], c[4], c[6], c[7]]);
        }
        Kind::Simplex => {
            // Kuhn's six tetrahedra around the diagonal 0-6 (conforming between cubes).
            for path in [[1, 2], [2, 3], [3, 7], [7, 4], [4, 5], [5, 1]] {
                m.push(10, &[c[0], c[path[0]], c[path[1]], c[6]]);
            }
        }
        Kind::Pyramid => {
            let centre = m.points.len() as u32;
            let mut p = [0.0; 3];
            for &v in c {
                let q = m.points[v as usize];
                for (p, q) in p.iter_mut().zip(q) {
                    *p += q / 8.0;
                }
            }
            m.points.push(p);
            m.boundary.push(false);
            let faces = [
                [0, 3, 2, 1],
                [4, 5, 6, 7],
                [0, 1, 5, 4],
                [1, 2, 6, 5],
                [2, 3, 7, 6],
                [3, 0, 4, 7],
            ];
            for f in faces {
                m.push(14, &[c[f[0]], c[f[1]], c[f[2]], c[f[3]], centre]);
            }
        }
    }
}

/// The assembled operator of a mesh: graph and blocks.
pub struct Assembled<T: Real, const D: usize> {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
    pub moduli: Vec<T>,
    pub diag: Vec<Block<T, D>>,
    pub off: Vec<Block<T, D>>,
}

impl<T: Real, const D: usize> Assembled<T, D> {
    pub fn graph(&self) -> Graph<'_> {
        Graph::new(&self.offsets, &self.targets).expect("graph")
    }
    pub fn system<'a>(&'a self, fixed: &'a [u8]) -> ElasticSystem<'a, T, D> {
        ElasticSystem::new(self.graph(), &self.diag, &self.off, fixed).expect("system")
    }
}

/// Graph, moduli and assembly of `mesh` at `points`.
pub fn assembled<T: Real, const D: usize>(
    mesh: &Mesh<D>,
    points: &[[T; D]],
    modulus: Modulus,
    wall: Option<&[T]>,
    poisson: T,
) -> Assembled<T, D> {
    let cells = mesh.cells();
    let n = points.len();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut offsets, &mut targets).expect("graph");
    targets.truncate(used);
    let mut moduli = vec![T::ZERO; cells.len()];
    cell_moduli(&cells, points, modulus, wall, &mut moduli).expect("moduli");
    let graph = Graph::new(&offsets, &targets).expect("graph");
    let mut diag = vec![[[T::ZERO; D]; D]; n];
    let mut off = vec![[[T::ZERO; D]; D]; used];
    assemble(
        &cells, points, &graph, &moduli, poisson, &mut diag, &mut off,
    )
    .expect("assemble");
    Assembled {
        offsets,
        targets,
        moduli,
        diag,
        off,
    }
}

/// Block-Jacobi CG on `a` with `values` (prescribed at fixed nodes).
pub fn solve<T: Real, const D: usize>(
    a: &Assembled<T, D>,
    fixed: &[u8],
    values: &mut [[T; D]],
    options: &SolveOptions<T>,
) -> SolveReport<T> {
    let sys = a.system(fixed);
    let mut scratch = vec![[T::ZERO; D]; elastic_scratch_len(values.len()).unwrap()];
    sys.solve(values, options, &mut scratch).expect("solve")
}

/// The cells of ffi/tests/elasticity.c and elasticity_solvers.c on an `s × s` node square
/// (offsets, nodes, VTK kinds): quads where `i + j` is odd, two triangles elsewhere.
pub fn c_square_cells(s: usize) -> (Vec<u32>, Vec<u32>, Vec<u8>) {
    let (mut offs, mut nodes, mut kinds) = (vec![0u32], vec![], vec![]);
    for j in 0..s - 1 {
        for i in 0..s - 1 {
            let a = (i + s * j) as u32;
            let q = [a, a + 1, a + 1 + s as u32, a + s as u32];
            let parts: Vec<Vec<u32>> = if (i + j) % 2 == 1 {
                vec![q.to_vec()]
            } else {
                vec![vec![q[0], q[1], q[2]], vec![q[0], q[2], q[3]]]
            };
            for p in parts {
                kinds.push(if p.len() == 4 { 9 } else { 5 });
                nodes.extend(p);
                offs.push(nodes.len() as u32);
            }
        }
    }
    (offs, nodes, kinds)
}

/// FNV-1a over the bits of a field.
pub fn fnv<T: Real, const D: usize>(v: &[[T; D]]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for x in v.iter().flatten() {
        for b in x.to_bits_u64().to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
        }
    }
    h
}
