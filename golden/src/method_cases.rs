//! Golden cases for linear elasticity and RBF deformation on small jittered meshes: a 2D
//! square of quadrilaterals and triangles and a 3D cube of hexahedra (cell-pair graph, the
//! three moduli, assembly, load increments with block-Jacobi CG, the rigid-mode multigrid,
//! sliding nodes), and RBF (Wendland C2 and thin-plate splines, all centres and greedy with
//! the wall correction) in 2D and 3D. The hashes cover every output value, every report field
//! and the error codes of rejected input.

use deform_kernel::elasticity::{
    assemble, cell_moduli, deform_incremental_on, elastic_rigid_amg_scratch_len,
    elastic_sliding_scratch_len, elasticity_graph, Block, ElasticSystem, IncrementBuffers,
    IncrementReport, Increments, Modulus,
};
use deform_kernel::rbf::{rbf_deform, RbfKernel, RbfOptions, RbfReport};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{AmgOptions, RigidAmg, SolveOptions, SolveReport, SpringSystem};
use deform_kernel::{CellKind, Cells, Graph, Real};

use crate::{Fnv, XorShift};

/// Nodes along x and y of the 2D square.
const S2: usize = 6;
const N2: usize = S2 * S2;
/// Cells of the 2D square: at most two per quad.
const C2: usize = 2 * (S2 - 1) * (S2 - 1);
/// Nodes along each axis of the 3D cube.
const S3: usize = 3;
const N3: usize = S3 * S3 * S3;
const C3: usize = (S3 - 1) * (S3 - 1) * (S3 - 1);
/// Directed edges (upper bounds): `Σ n_c (n_c − 1)` of the cells.
const E2: usize = 12 * C2;
const E3: usize = 56 * C3;
/// Edge buffers for both meshes.
const EMAX: usize = if E2 > E3 { E2 } else { E3 };
/// Multigrid buffers (upper bounds; the sizes are hashed).
const WORK: usize = 4 * (N2 + EMAX) + 64;
const INDEX: usize = 4096;
const VALUES: usize = 8192;

/// sin and cos of 15° and 10° (inputs, written out so no transcendental is evaluated).
const SIN_15: f64 = 0.258_819_045_102_520_74;
const COS_15: f64 = 0.965_925_826_289_068_3;
const SIN_10: f64 = 0.173_648_177_666_930_33;
const COS_10: f64 = 0.984_807_753_012_208;

/// A mesh on borrowed arrays: cells, jittered points, its cell-pair graph.
struct Mesh<'a, T, const D: usize> {
    cells: Cells<'a>,
    points: &'a [[T; D]],
    graph: Graph<'a>,
}

/// Writes the `s × s` square (quads where `i + j` is odd, two triangles elsewhere), the
/// interior jittered by up to 0.15 of a cell; returns the cell count.
fn square<T: Real>(
    pts: &mut [[T; 2]; N2],
    offs: &mut [u32; C2 + 1],
    nodes: &mut [u32; 4 * C2],
    kinds: &mut [u8; C2],
) -> usize {
    let mut rng = XorShift::new(0x5EED_0E1A);
    for (n, p) in pts.iter_mut().enumerate() {
        let (i, j) = (n % S2, n / S2);
        let inner = i > 0 && j > 0 && i < S2 - 1 && j < S2 - 1;
        let a = if inner { 0.3 } else { 0.0 };
        *p = [
            T::from_f64((i as f64 + a * (rng.unit_f64() - 0.5)) / (S2 - 1) as f64),
            T::from_f64((j as f64 + a * (rng.unit_f64() - 0.5)) / (S2 - 1) as f64),
        ];
    }
    let (mut c, mut k) = (0, 0);
    for j in 0..S2 - 1 {
        for i in 0..S2 - 1 {
            let a = (i + S2 * j) as u32;
            let q = [a, a + 1, a + 1 + S2 as u32, a + S2 as u32];
            let parts: [&[u32]; 2] = if (i + j) % 2 == 1 {
                [&q, &[]]
            } else {
                [&[q[0], q[1], q[2]], &[q[0], q[2], q[3]]]
            };
            for part in parts.iter().filter(|p| !p.is_empty()) {
                for (slot, &v) in nodes.iter_mut().skip(k).zip(part.iter()) {
                    *slot = v;
                }
                k += part.len();
                let kind = if part.len() == 4 {
                    CellKind::Quad
                } else {
                    CellKind::Triangle
                };
                set(kinds, c, kind.vtk_code());
                c += 1;
                set(offs, c, k as u32);
            }
        }
    }
    c
}

/// `a[i] = v` when `i` is in range.
fn set<X: Copy>(a: &mut [X], i: usize, v: X) {
    if let Some(s) = a.get_mut(i) {
        *s = v;
    }
}

/// Writes the `s³` cube of hexahedra (VTK order), the interior node jittered.
fn cube<T: Real>(pts: &mut [[T; 3]; N3], offs: &mut [u32; C3 + 1], nodes: &mut [u32; 8 * C3]) {
    let mut rng = XorShift::new(0x5EED_0E1B);
    for (n, p) in pts.iter_mut().enumerate() {
        let ijk = [n % S3, (n / S3) % S3, n / (S3 * S3)];
        let inner = ijk.iter().all(|&x| x > 0 && x < S3 - 1);
        let a = if inner { 0.3 } else { 0.0 };
        *p = ijk.map(|x| T::from_f64((x as f64 + a * (rng.unit_f64() - 0.5)) / (S3 - 1) as f64));
    }
    let id = |i: usize, j: usize, k: usize| (i + S3 * (j + S3 * k)) as u32;
    let mut c = 0;
    for k in 0..S3 - 1 {
        for j in 0..S3 - 1 {
            for i in 0..S3 - 1 {
                let h = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                for (slot, v) in nodes.iter_mut().skip(8 * c).zip(h) {
                    *slot = v;
                }
                c += 1;
                set(offs, c, 8 * c as u32);
            }
        }
    }
}

fn hash_points<T: Real, const D: usize>(h: &mut Fnv, pts: &[[T; D]]) {
    for p in pts {
        h.reals(*p);
    }
}

fn hash_blocks<T: Real, const D: usize>(h: &mut Fnv, b: &[Block<T, D>]) {
    for m in b {
        for r in m {
            h.reals(*r);
        }
    }
}

fn hash_increments<T: Real>(h: &mut Fnv, r: deform_kernel::Result<IncrementReport<T>>) {
    match r {
        Ok(r) => {
            h.usize(r.steps);
            h.usize(r.iterations);
            h.usize(r.max_step_iterations);
            h.real(r.residual);
            h.byte(r.converged as u8);
        }
        Err(e) => h.error(&e),
    }
}

/// Which solve each increment runs.
#[derive(Clone, Copy, PartialEq)]
enum Solve {
    BlockJacobi,
    RigidAmg,
    Sliding,
}

/// The buffers of one deformation (upper bounds for both meshes).
struct Bufs<T, const D: usize> {
    moduli: [T; C2],
    diag: [Block<T, D>; N2],
    off: [Block<T, D>; EMAX],
    current: [[T; D]; N2],
    step: [[T; D]; N2],
}

impl<T: Real, const D: usize> Bufs<T, D> {
    fn new() -> Self {
        Bufs {
            moduli: [T::ZERO; C2],
            diag: [[[T::ZERO; D]; D]; N2],
            off: [[[T::ZERO; D]; D]; EMAX],
            current: [[T::ZERO; D]; N2],
            step: [[T::ZERO; D]; N2],
        }
    }
}

/// What every increment's solve needs besides the system.
struct Step<'a, T, const D: usize> {
    how: Solve,
    graph: Graph<'a>,
    fixed: &'a [u8],
    constraints: &'a Constraints<'a, T, D>,
}

/// One increment's solve with stack buffers (the multigrid's sizes hashed).
fn solve_step<T: Real, const D: usize>(
    h: &mut Fnv,
    st: &Step<'_, T, D>,
    sys: &ElasticSystem<'_, T, D>,
    mesh: &[[T; D]],
    u: &mut [[T; D]],
) -> deform_kernel::Result<SolveReport<T>> {
    let n = u.len();
    let stop = SolveOptions {
        max_iterations: 400,
        ..SolveOptions::default()
    };
    let mut scratch = [[T::ZERO; D]; 8 * N2];
    let len = |l: Option<usize>| l.unwrap_or(usize::MAX).min(8 * N2);
    match st.how {
        Solve::BlockJacobi => {
            let s = scratch.get_mut(..len(Some(4 * n))).unwrap_or(&mut []);
            return sys.solve(u, &stop, s);
        }
        Solve::Sliding => {
            let s = scratch
                .get_mut(..len(elastic_sliding_scratch_len(n)))
                .unwrap_or(&mut []);
            return sys.solve_sliding(st.constraints, u, &stop, s);
        }
        Solve::RigidAmg => {}
    }
    let ones = [T::ONE; EMAX];
    let mut anchor = [0u32; N2];
    let w = ones.get(..st.graph.edge_count()).unwrap_or(&[]);
    let spring = SpringSystem::new(st.graph, w, st.fixed, &mut anchor)?;
    let opts = AmgOptions {
        max_coarse: 4,
        ..AmgOptions::default()
    };
    let (mut work, mut index, mut values) = ([0u32; WORK], [0u32; INDEX], [T::ZERO; VALUES]);
    let sizes = RigidAmg::setup_len(&spring, D, &opts, &mut work)?;
    h.usize(sizes.index);
    h.usize(sizes.values);
    h.usize(sizes.levels);
    h.usize(sizes.coarse_scalars);
    let hier = sys.rigid_amg(&spring, mesh, &opts, &mut work, &mut index, &mut values)?;
    let need = elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, D);
    let s = scratch.get_mut(..len(need)).unwrap_or(&mut []);
    sys.solve_rigid_amg(&hier, u, &stop, s)
}

/// The moduli (all three choices) and the assembly of `m`, hashed; `moduli`, `diag` and `off`
/// keep the inverse-volume assembly.
fn assembly<T: Real, const D: usize>(h: &mut Fnv, m: &Mesh<'_, T, D>, b: &mut Bufs<T, D>) {
    let (n, nc, e) = (m.points.len(), m.cells.len(), m.graph.edge_count());
    h.u32s(m.graph.offsets());
    h.u32s(m.graph.targets());
    let moduli = b.moduli.get_mut(..nc).unwrap_or(&mut []);
    let wall: [T; N2] = core::array::from_fn(|i| {
        m.points
            .get(i)
            .map_or(T::ONE, |p| p[D - 1] + T::from_f64(0.1))
    });
    let wall = wall.get(..n);
    for modulus in [
        Modulus::Constant,
        Modulus::WallDistance,
        Modulus::InverseVolume,
    ] {
        match cell_moduli(&m.cells, m.points, modulus, wall, moduli) {
            Ok(()) => moduli.iter().for_each(|&x| h.real(x)),
            Err(e) => h.error(&e),
        }
    }
    let diag = b.diag.get_mut(..n).unwrap_or(&mut []);
    let off = b.off.get_mut(..e).unwrap_or(&mut []);
    match assemble(
        &m.cells,
        m.points,
        &m.graph,
        moduli,
        T::from_f64(0.3),
        diag,
        off,
    ) {
        Ok(()) => {
            hash_blocks(h, diag);
            hash_blocks(h, off);
        }
        Err(e) => h.error(&e),
    }
}

/// The elasticity run of one mesh: graph, moduli, assembly, then increments by each solve
/// (the last with Poisson ratio ½, which must be rejected). `fixed` is the mask of the plain
/// runs, `slide_fixed` the kind-1 nodes of `constraints`.
fn elasticity<T: Real, const D: usize>(
    m: &Mesh<'_, T, D>,
    fixed: &[u8],
    slide_fixed: &[u8],
    disp: &[[T; D]],
    constraints: &Constraints<'_, T, D>,
) -> u64 {
    let mut h = Fnv::new();
    let (n, nc, e) = (m.points.len(), m.cells.len(), m.graph.edge_count());
    let mut b = Bufs::<T, D>::new();
    assembly(&mut h, m, &mut b);
    for (how, steps, poisson) in [
        (Solve::BlockJacobi, 2, 0.3),
        (Solve::RigidAmg, 2, 0.3),
        (Solve::Sliding, 2, 0.25),
        (Solve::BlockJacobi, 1, 0.5),
    ] {
        let mut pts = [[T::ZERO; D]; N2];
        let pts = pts.get_mut(..n).unwrap_or(&mut []);
        pts.copy_from_slice(m.points);
        let fx = if how == Solve::Sliding {
            slide_fixed
        } else {
            fixed
        };
        let params = Increments {
            modulus: Modulus::InverseVolume,
            wall_distance: None,
            poisson: T::from_f64(poisson),
            steps,
        };
        let buffers = IncrementBuffers {
            moduli: b.moduli.get_mut(..nc).unwrap_or(&mut []),
            diag: b.diag.get_mut(..n).unwrap_or(&mut []),
            off: b.off.get_mut(..e).unwrap_or(&mut []),
            current: b.current.get_mut(..n).unwrap_or(&mut []),
            step: b.step.get_mut(..n).unwrap_or(&mut []),
        };
        let st = Step {
            how,
            graph: m.graph,
            fixed: fx,
            constraints,
        };
        let hh = &mut h;
        let r = deform_incremental_on(
            &m.cells,
            &m.graph,
            fx,
            &params,
            pts,
            disp,
            buffers,
            |sys, mesh, u| solve_step(hh, &st, sys, mesh, u),
        );
        hash_increments(&mut h, r);
        hash_points(&mut h, pts);
    }
    h.finish()
}

/// Linear elasticity on the 2D square: the boundary moves by a rotation of 15° about the
/// centre plus a stretch of the top edge; the sliding runs let the bottom edge's inner nodes
/// slide along `y = 0`.
pub fn elasticity_2d<T: Real>() -> u64 {
    let mut pts = [[T::ZERO; 2]; N2];
    let (mut offs, mut nodes, mut kinds) = ([0u32; C2 + 1], [0u32; 4 * C2], [0u8; C2]);
    let nc = square(&mut pts, &mut offs, &mut nodes, &mut kinds);
    let len = offs.get(nc).copied().unwrap_or(0) as usize;
    let (o, nd, k) = (
        offs.get(..=nc).unwrap_or(&[]),
        nodes.get(..len).unwrap_or(&[]),
        kinds.get(..nc).unwrap_or(&[]),
    );
    let Ok(cells) = Cells::new(N2, o, nd, k) else {
        return 0;
    };
    let (mut go, mut gt) = ([0u32; N2 + 1], [0u32; E2]);
    let Ok(used) = elasticity_graph(&cells, &mut go, &mut gt) else {
        return 0;
    };
    let Ok(graph) = Graph::new(&go, gt.get(..used).unwrap_or(&[])) else {
        return 0;
    };
    let edge = |n: usize| n % S2 == 0 || n / S2 == 0 || n % S2 == S2 - 1 || n / S2 == S2 - 1;
    let slides = |n: usize| n / S2 == 0 && n % S2 != 0 && n % S2 != S2 - 1;
    let fixed: [u8; N2] = core::array::from_fn(|n| edge(n) as u8);
    let slide_fixed: [u8; N2] = core::array::from_fn(|n| (edge(n) && !slides(n)) as u8);
    let ckinds: [u8; N2] = core::array::from_fn(|n| if slides(n) { 2 } else { slide_fixed[n] });
    let normals = [[T::ZERO, T::ONE]; N2];
    let Ok(c) = Constraints::new(&ckinds, &normals) else {
        return 0;
    };
    let (sn, cs) = (T::from_f64(SIN_15), T::from_f64(COS_15));
    let half = T::HALF;
    let disp: [[T; 2]; N2] = core::array::from_fn(|n| {
        let [x, y] = pts[n];
        let (dx, dy) = (x - half, y - half);
        let stretch = if n / S2 == S2 - 1 {
            T::from_f64(0.05) * x
        } else {
            T::ZERO
        };
        [cs * dx - sn * dy - dx + stretch, sn * dx + cs * dy - dy]
    });
    let m = Mesh {
        cells,
        points: &pts,
        graph,
    };
    elasticity(&m, &fixed, &slide_fixed, &disp, &c)
}

/// Linear elasticity on the 3D cube of hexahedra: the top face (z = 1) shears by 0.1 in x
/// and twists; the rest of the boundary stays; the sliding runs let the bottom face's
/// non-corner nodes slide in `z = 0`.
pub fn elasticity_3d<T: Real>() -> u64 {
    let mut pts = [[T::ZERO; 3]; N3];
    let (mut offs, mut nodes) = ([0u32; C3 + 1], [0u32; 8 * C3]);
    cube(&mut pts, &mut offs, &mut nodes);
    let kinds = [CellKind::Hexahedron.vtk_code(); C3];
    let Ok(cells) = Cells::new(N3, &offs, &nodes, &kinds) else {
        return 0;
    };
    let (mut go, mut gt) = ([0u32; N3 + 1], [0u32; E3]);
    let Ok(used) = elasticity_graph(&cells, &mut go, &mut gt) else {
        return 0;
    };
    let Ok(graph) = Graph::new(&go, gt.get(..used).unwrap_or(&[])) else {
        return 0;
    };
    let ijk = |n: usize| [n % S3, (n / S3) % S3, n / (S3 * S3)];
    let edge = |n: usize| ijk(n).iter().any(|&x| x == 0 || x == S3 - 1);
    let slides = |n: usize| {
        let [i, j, k] = ijk(n);
        k == 0 && !((i == 0 || i == S3 - 1) && (j == 0 || j == S3 - 1))
    };
    let fixed: [u8; N3] = core::array::from_fn(|n| edge(n) as u8);
    let slide_fixed: [u8; N3] = core::array::from_fn(|n| (edge(n) && !slides(n)) as u8);
    let ckinds: [u8; N3] = core::array::from_fn(|n| if slides(n) { 2 } else { slide_fixed[n] });
    let normals = [[T::ZERO, T::ZERO, T::ONE]; N3];
    let Ok(c) = Constraints::new(&ckinds, &normals) else {
        return 0;
    };
    let disp: [[T; 3]; N3] = core::array::from_fn(|n| {
        let [x, y, z] = pts[n];
        let top = if ijk(n)[2] == S3 - 1 { T::ONE } else { T::ZERO };
        let tw = T::from_f64(0.08) * top;
        [
            top * T::from_f64(0.1) - tw * (y - T::HALF),
            tw * (x - T::HALF),
            T::from_f64(0.02) * z * top,
        ]
    });
    let m = Mesh {
        cells,
        points: &pts,
        graph,
    };
    elasticity(&m, &fixed, &slide_fixed, &disp, &c)
}

fn hash_rbf<T: Real, const D: usize>(
    h: &mut Fnv,
    r: deform_kernel::Result<RbfReport<T>>,
    d: &[[T; D]],
) {
    match r {
        Ok(r) => {
            h.usize(r.centres);
            h.real(r.max_error);
            h.byte(r.dependent as u8);
        }
        Err(e) => h.error(&e),
    }
    hash_points(h, d);
}

/// The RBF option sets every RBF case runs: Wendland (all centres; greedy with the wall
/// correction), thin-plate splines (all centres; greedy with the correction), and a rejected
/// one (a zero support).
fn rbf_options<T: Real>(b: usize) -> [RbfOptions<T>; 5] {
    let w = RbfKernel::Wendland {
        radius: T::from_f64(1.5),
    };
    let o = |kernel, tol: f64, max, corr: f64| RbfOptions {
        kernel,
        tolerance: T::from_f64(tol),
        max_centres: max,
        correction_radius: T::from_f64(corr),
    };
    [
        o(w, 0.0, b, 0.0),
        o(w, 1e-3, 6, 0.6),
        o(RbfKernel::ThinPlate, 0.0, b, 0.0),
        o(RbfKernel::ThinPlate, 1e-3, 7, 0.6),
        o(RbfKernel::Wendland { radius: T::ZERO }, 0.0, b, 0.0),
    ]
}

/// One RBF deformation per option set of [`rbf_options`].
fn rbf_runs<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    motion: &[[T; D]],
) -> u64 {
    let mut h = Fnv::new();
    for opts in rbf_options::<T>(boundary.len()) {
        let mut index = [0u32; 512];
        let mut scratch = [T::ZERO; 2048];
        let mut d = [[T::ZERO; D]; N2];
        let d = d.get_mut(..points.len()).unwrap_or(&mut []);
        let r = rbf_deform(points, boundary, motion, &opts, &mut index, &mut scratch, d);
        hash_rbf(&mut h, r, d);
    }
    h.finish()
}

/// RBF on the 2D square's points: the perimeter (20 nodes) turns by 15° about the centre of
/// its bottom edge, which bends the motion across the square.
pub fn rbf_2d<T: Real>() -> u64 {
    let mut pts = [[T::ZERO; 2]; N2];
    let (mut offs, mut nodes, mut kinds) = ([0u32; C2 + 1], [0u32; 4 * C2], [0u8; C2]);
    square(&mut pts, &mut offs, &mut nodes, &mut kinds);
    let mut boundary = [0u32; 4 * (S2 - 1)];
    let mut motion = [[T::ZERO; 2]; 4 * (S2 - 1)];
    let (sn, cs) = (T::from_f64(SIN_15), T::from_f64(COS_15));
    let on =
        (0..N2).filter(|&n| n % S2 == 0 || n / S2 == 0 || n % S2 == S2 - 1 || n / S2 == S2 - 1);
    for (k, n) in on.enumerate() {
        set(&mut boundary, k, n as u32);
        let [x, y] = pts[n];
        let dx = x - T::HALF;
        let lift = T::from_f64(0.1) * y * y;
        set(
            &mut motion,
            k,
            [cs * dx - sn * y - dx, sn * dx + cs * y - y + lift],
        );
    }
    rbf_runs(&pts, &boundary, &motion)
}

/// RBF on the 3D cube's points: its 26 surface nodes move by a rotation of 10° about z plus a
/// bulge in z.
pub fn rbf_3d<T: Real>() -> u64 {
    let mut pts = [[T::ZERO; 3]; N3];
    let (mut offs, mut nodes) = ([0u32; C3 + 1], [0u32; 8 * C3]);
    cube(&mut pts, &mut offs, &mut nodes);
    let (mut boundary, mut motion) = ([0u32; N3 - 1], [[T::ZERO; 3]; N3 - 1]);
    let (sn, cs) = (T::from_f64(SIN_10), T::from_f64(COS_10));
    let centre = (N3 - 1) / 2;
    for (k, n) in (0..N3).filter(|&n| n != centre).enumerate() {
        set(&mut boundary, k, n as u32);
        let [x, y, z] = pts[n];
        let (dx, dy) = (x - T::HALF, y - T::HALF);
        let bulge = T::from_f64(0.05) * x * y;
        set(
            &mut motion,
            k,
            [
                cs * dx - sn * dy - dx,
                sn * dx + cs * dy - dy,
                bulge + T::from_f64(0.01) * z,
            ],
        );
    }
    rbf_runs(&pts, &boundary, &motion)
}
