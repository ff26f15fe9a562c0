//! Derivatives of the quaternion deformation (`deform_kernel::quaternion`, issue 30): the
//! tangent and adjoint of the exact IDW, the fast (tree) IDW, TFI and the spring propagation
//! on jittered structured blocks in 2D and 3D, whose surface moves (rotation, arbitrary
//! moves), every rotation source, with NaN injections, scratch one item short, invalid
//! parameters and a collapsed point.
//!
//! - An error leaves `out` bit-identical; a NaN, a short scratch or an invalid parameter is
//!   an error.
//! - On `Ok` every output is finite.
//! - On well-shaped inputs (no collapsed point), with `J` assembled column by column from
//!   tangents of unit vectors and `S = Σ |w_i| |J_ik| |v_k|`: the tangent is linear
//!   (`|J v − Σ v_k J e_k|` within `10⁻¹⁰ S` summed over the outputs) and
//!   `|⟨J v, w⟩ − ⟨v, Jᵀ w⟩| ≤ 10⁻¹⁰ S` (exact methods: rounding of `O(N B)` terms on
//!   geometry of unit scale) or `10⁻⁶ S` (springs: both solves converged to 10⁻¹³ on a
//!   jittered grid).
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::quaternion::{
    deform_idw_adjoint, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_sensitivity_scratch_len, deform_idw_tangent,
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
    propagate_idw_fast_index_len, propagate_idw_fast_scratch_len, BoundaryMotion, IdwFastOptions,
    RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_edges, Block, Cells, Directions, Error, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    dims: [u8; 3],
    three_d: bool,
    jitter: Vec<[i8; 3]>,
    moves: Vec<[i8; 3]>,
    v: Vec<[i8; 3]>,
    w: Vec<[i8; 3]>,
    angle: i8,
    /// 0: shape, 1: rigid, 2: per node, 3: shape about a given origin.
    source: u8,
    /// 0: IDW, 1: fast IDW, 2: TFI, 3: springs.
    method: u8,
    exponent: u8,
    theta: u8,
    /// Bit 0: NaN in `w`; 1: NaN in `v`; 2: scratch one short; 3: invalid parameter;
    /// 4: point `at` collapsed onto point 0.
    faults: u8,
    at: u8,
}

fuzz_target!(|inp: Input| {
    if inp.three_d {
        run::<3>(&inp);
    } else {
        run::<2>(&inp);
    }
});

/// A mesh and its moving surface.
struct Mesh<const D: usize> {
    block: Block,
    points: Vec<[f64; D]>,
    boundary: Vec<u32>,
    deformed: Vec<[f64; D]>,
    el_offsets: Vec<u32>,
    el_nodes: Vec<u32>,
    el_kinds: Vec<u8>,
}

fn run<const D: usize>(inp: &Input) {
    let m = mesh::<D>(inp);
    let Ok(elements) = Cells::new(m.boundary.len(), &m.el_offsets, &m.el_nodes, &m.el_kinds) else {
        return;
    };
    let given: Vec<Quat<f64>> = (0..m.boundary.len())
        .map(|k| Quat::from_rotation_z(f64::from(inp.angle) / 200.0 + k as f64 / 50.0))
        .collect();
    let q = Quat::from_axis_angle([0.3, -0.5, 1.0], f64::from(inp.angle) / 100.0).unwrap();
    let rotations = match inp.source % 4 {
        0 | 3 => RotationSource::Shape,
        1 => RotationSource::Rigid(q),
        _ => RotationSource::PerNode(&given),
    };
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &m.deformed,
        elements: Some(elements),
        rotations,
        origin: (inp.source % 4 == 3).then_some([0.25; D]),
    };
    let (n, b) = (m.points.len(), m.boundary.len());
    let v = field::<D>(&inp.v, b, inp.faults & 2 != 0, inp.at);
    let w = field::<D>(&inp.w, n, inp.faults & 1 != 0, inp.at);
    let bad = inp.faults & 8 != 0;
    let short = usize::from(inp.faults & 4 != 0);
    // The derivative into `out`: tangent when `x` has one item per boundary node.
    let sens = |x: &[[f64; D]], out: &mut [[f64; D]], short: usize| {
        derivative(inp, &m, &motion, bad, x, out, short)
    };
    let mut jv = vec![[7.0; D]; n];
    let tangent = sens(&v, &mut jv, short);
    let mut g = vec![[5.0; D]; b];
    let adjoint = sens(&w, &mut g, short);
    let expect_error = short == 1 || bad;
    for (r, out, fill, nan) in [(&tangent, &jv, 7.0, 2), (&adjoint, &g, 5.0, 1)] {
        match r {
            Err(_) => assert!(out.iter().flatten().all(|x| *x == fill), "wrote on error"),
            Ok(_) => {
                assert!(!expect_error && inp.faults & nan == 0, "no error: {r:?}");
                assert!(out.iter().flatten().all(|x| x.is_finite()), "non-finite");
            }
        }
    }
    if tangent != Ok(true) || adjoint != Ok(true) || inp.faults & 16 != 0 {
        return;
    }
    // J column by column.
    let mut cols = Vec::with_capacity(b * D);
    for k in 0..b * D {
        let mut e = vec![[0.0; D]; b];
        e[k / D][k % D] = 1.0;
        let mut col = vec![[0.0; D]; n];
        if sens(&e, &mut col, 0) != Ok(true) {
            return; // a spring solve that did not converge on this column
        }
        cols.push(col);
    }
    let (mut s, mut lin, mut jtw) = (0.0f64, 0.0f64, 0.0f64);
    for (k, col) in cols.iter().enumerate() {
        let vk = v[k / D][k % D];
        for (i, c) in col.iter().enumerate() {
            for d in 0..D {
                s += (w[i][d] * c[d] * vk).abs();
                jtw += w[i][d] * c[d] * vk;
            }
        }
    }
    for (i, x) in jv.iter().enumerate() {
        for d in 0..D {
            let combo: f64 = cols
                .iter()
                .enumerate()
                .map(|(k, c)| c[i][d] * v[k / D][k % D])
                .sum();
            lin += ((x[d] - combo) * w[i][d]).abs();
        }
    }
    let rel = if inp.method % 4 == 3 { 1e-6 } else { 1e-10 };
    assert!(
        lin <= rel * s + 1e-300,
        "tangent not linear: {lin} (S = {s})"
    );
    let lhs: f64 = jv.iter().zip(&w).map(|(x, y)| dot(x, y)).sum();
    let rhs: f64 = v.iter().zip(&g).map(|(x, y)| dot(x, y)).sum();
    assert!(
        (lhs - rhs).abs() <= rel * s + 1e-300,
        "dot product: {lhs} vs {rhs} (Σ v·Jᵀw by columns {jtw}, S = {s})"
    );
}

/// The tangent (`x` per boundary node) or adjoint (`x` per node) of the chosen method;
/// `Ok(false)` when a spring solve did not converge.
fn derivative<const D: usize>(
    inp: &Input,
    m: &Mesh<D>,
    motion: &BoundaryMotion<'_, f64, D>,
    bad: bool,
    x: &[[f64; D]],
    out: &mut [[f64; D]],
    short: usize,
) -> Result<bool, Error> {
    let (n, b) = (m.points.len(), m.boundary.len());
    let tangent = x.len() == b && out.len() == n;
    let p = &m.points;
    let e = if bad && inp.method % 4 == 0 {
        -1.0
    } else {
        1.0 + f64::from(inp.exponent % 4)
    };
    match inp.method % 4 {
        0 => {
            let mut s = vec![0.0; deform_idw_sensitivity_scratch_len::<D>(n, b) - short];
            let f = if tangent {
                deform_idw_tangent
            } else {
                deform_idw_adjoint
            };
            f(p, motion, e, x, &mut s, out).map(|()| true)
        }
        1 => {
            let mut s = vec![0.0; deform_idw_fast_sensitivity_scratch_len::<D>(n, b) - short];
            let mut index = vec![0; propagate_idw_fast_index_len(b)];
            let mut tree = vec![0.0; propagate_idw_fast_scratch_len::<D>(b)];
            let (mut tr, mut rot) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
            let o = IdwFastOptions {
                theta: if bad {
                    1.5
                } else {
                    f64::from(inp.theta % 4) * 0.2
                },
                tolerance: if inp.theta & 4 != 0 {
                    0.1
                } else {
                    f64::INFINITY
                },
            };
            let f = if tangent {
                deform_idw_fast_tangent
            } else {
                deform_idw_fast_adjoint
            };
            let (s, ix) = (&mut s, &mut index);
            f(
                p, motion, e, &o, x, &mut tr, &mut rot, s, ix, &mut tree, out,
            )
            .map(|_| true)
        }
        2 => {
            // No active direction is the invalid parameter.
            let dirs = Directions::from_flags([!bad, !bad, D == 3 && !bad]);
            let len = deform_tfi_sensitivity_scratch_len::<D>(&m.block, b) - short;
            let mut s = vec![0.0; len];
            let f = if tangent {
                deform_tfi_tangent
            } else {
                deform_tfi_adjoint
            };
            f(&m.block, dirs, p, motion, x, &mut s, out).map(|()| true)
        }
        _ => springs(m, motion, bad, x, out, short, tangent),
    }
}

/// The spring propagation's derivative on the block's grid edges (Batina stiffness, CG with
/// Jacobi; SSOR with ω = 2.5 when `bad`).
fn springs<const D: usize>(
    m: &Mesh<D>,
    motion: &BoundaryMotion<'_, f64, D>,
    bad: bool,
    x: &[[f64; D]],
    out: &mut [[f64; D]],
    short: usize,
    tangent: bool,
) -> Result<bool, Error> {
    let n = m.points.len();
    let mut edges = Vec::new();
    for p in 0..n {
        let c = m.block.ijk(p);
        for a in 0..3 {
            if c[a] + 1 < m.block.dims()[a] {
                let mut q = c;
                q[a] += 1;
                edges.push([p as u32, m.block.index(q[0], q[1], q[2]) as u32]);
            }
        }
    }
    let (mut offsets, mut targets) = (vec![0u32; n + 1], vec![0u32; 2 * edges.len()]);
    let used = graph_from_edges(n, &edges, &mut offsets, &mut targets)?;
    let graph = Graph::new(&offsets, &targets[..used])?;
    let mut k = vec![0.0; used];
    batina_stiffness(&graph, &m.points, 1.0, &mut k)?;
    let mut fixed = vec![0u8; n];
    for &i in &m.boundary {
        fixed[i as usize] = 1;
    }
    let mut seen = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut seen)?;
    let omega = if bad { 2.5 } else { 1.0 };
    let preconditioner = [Preconditioner::Jacobi, Preconditioner::Ssor { omega }][usize::from(bad)];
    let solver = LinearSolver::Method(LinearMethod::Cg { preconditioner });
    let options = SolveOptions {
        residual_tol: 1e-13,
        max_iterations: 2000,
        ..SolveOptions::default()
    };
    let len = deform_spring_sensitivity_scratch_len::<f64, D>(&solver, n, m.boundary.len());
    let mut s = vec![0.0; len - short];
    let p = &m.points;
    let report = if tangent {
        deform_spring_tangent(p, motion, &sys, solver, &options, x, &mut s, out)?
    } else {
        deform_spring_adjoint(p, motion, &sys, solver, &options, x, &mut s, out)?
    };
    Ok(report.converged)
}

/// A jittered `ni × nj (× nk)` block, its surface the boundary (segments or outward quads),
/// moved by a rotation and arbitrary small moves.
fn mesh<const D: usize>(inp: &Input) -> Mesh<D> {
    let r = |x: u8, hi: u8| usize::from(x % hi) + 2;
    let dims = if D == 2 {
        [r(inp.dims[0], 4), r(inp.dims[1], 4), 1]
    } else {
        [r(inp.dims[0], 2), r(inp.dims[1], 2), r(inp.dims[2], 2)]
    };
    let block = Block::new(dims).unwrap();
    let n = block.point_count();
    let mut points: Vec<[f64; D]> = (0..n)
        .map(|p| {
            let (c, j) = (block.ijk(p), inp.jitter.get(p).copied().unwrap_or([0; 3]));
            core::array::from_fn(|d| c[d] as f64 + f64::from(j[d]) / 400.0)
        })
        .collect();
    if inp.faults & 16 != 0 {
        points[usize::from(inp.at) % n] = points[0];
    }
    let boundary = surface(&block);
    let (el_offsets, el_nodes, el_kinds) = elements::<D>(&block, &boundary);
    let q = Quat::from_rotation_z(f64::from(inp.angle) / 200.0);
    let deformed = boundary
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let mv = inp.moves.get(k).copied().unwrap_or([0; 3]);
            let mut x = [0.0; 3];
            x[..D].copy_from_slice(&points[p as usize]);
            let y = q.rotate(x);
            core::array::from_fn(|d| y[d] + f64::from(mv[d]) / 200.0)
        })
        .collect();
    Mesh {
        block,
        points,
        boundary,
        deformed,
        el_offsets,
        el_nodes,
        el_kinds,
    }
}

/// The block's surface nodes: the perimeter ring in order (2D), or in index order (3D).
fn surface(block: &Block) -> Vec<u32> {
    let [ni, nj, nk] = block.dims();
    if nk > 1 {
        let on = |c: [usize; 3]| (0..3).any(|a| c[a] == 0 || c[a] + 1 == block.dims()[a]);
        return (0..block.point_count())
            .filter(|&p| on(block.ijk(p)))
            .map(|p| p as u32)
            .collect();
    }
    let mut ring: Vec<[usize; 2]> = (0..ni).map(|i| [i, 0]).collect();
    ring.extend((1..nj).map(|j| [ni - 1, j]));
    ring.extend((0..ni - 1).rev().map(|i| [i, nj - 1]));
    ring.extend((1..nj - 1).rev().map(|j| [0, j]));
    ring.iter()
        .map(|&[i, j]| block.index(i, j, 0) as u32)
        .collect()
}

/// Boundary elements over positions in `boundary`: the ring's segments (2D) or the faces'
/// outward quadrilaterals (3D).
fn elements<const D: usize>(block: &Block, boundary: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<u8>) {
    let b = boundary.len() as u32;
    let (mut nodes, mut kinds) = (Vec::new(), Vec::new());
    if D == 2 {
        for k in 0..b {
            nodes.extend([k, (k + 1) % b]);
            kinds.push(3u8);
        }
    } else {
        let dims = block.dims();
        let pos = |p: usize| boundary.iter().position(|&x| x as usize == p).unwrap() as u32;
        for a in 0..3 {
            let (bb, cc) = ((a + 1) % 3, (a + 2) % 3);
            for side in [0, dims[a] - 1] {
                for i in 0..dims[bb] - 1 {
                    for j in 0..dims[cc] - 1 {
                        let at = |di: usize, dj: usize| {
                            let mut x = [0usize; 3];
                            (x[a], x[bb], x[cc]) = (side, i + di, j + dj);
                            pos(block.index(x[0], x[1], x[2]))
                        };
                        let mut q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
                        if side == 0 {
                            q.reverse();
                        }
                        nodes.extend(q);
                        kinds.push(9u8);
                    }
                }
            }
        }
    }
    let per = if D == 2 { 2 } else { 4 };
    let offsets = (0..=kinds.len() as u32).map(|e| e * per).collect();
    (offsets, nodes, kinds)
}

/// `len` items from `src` (`[1, −1, 1]` past its end) / 16, a NaN at `at` when `nan`.
fn field<const D: usize>(src: &[[i8; 3]], len: usize, nan: bool, at: u8) -> Vec<[f64; D]> {
    (0..len)
        .map(|i| {
            let m = src.get(i).copied().unwrap_or([1, -1, 1]);
            let mut x: [f64; D] = core::array::from_fn(|d| f64::from(m[d]) / 16.0);
            if nan && i == usize::from(at) % len {
                x[0] = f64::NAN;
            }
            x
        })
        .collect()
}

fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
