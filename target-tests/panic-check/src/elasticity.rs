//! Panic-check calls for linear elasticity (`deform_kernel::elasticity`): the graph, the
//! moduli (every choice), the assembly, the system, its unconstrained product, both solves
//! (block Jacobi and the scalar multigrid per component), the increments and their tangent
//! and adjoint (`deform_kernel::sensitivity`, both preconditioners), the sliding solves and
//! derivatives (`solve_amg_sliding`, `elastic_sliding_tangent` / `_adjoint`), for `f32` and
//! `f64` in 2D and 3D.
//!
//! The meshes are opaque: a unit square of two triangles and a quad, a cube of a hexahedron
//! (small enough for stack buffers).

use core::hint::black_box;

use deform_kernel::elasticity::{
    assemble, cell_moduli, deform_incremental, elastic_amg_scratch_len,
    elastic_amg_sliding_scratch_len, elastic_scratch_len, elasticity_graph, elasticity_graph_len,
    ElasticSystem, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::sensitivity::{
    elastic_incremental_adjoint, elastic_incremental_adjoint_scratch_len,
    elastic_incremental_tangent, elastic_incremental_tangent_scratch_len, elastic_sliding_adjoint,
    elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    elastic_sliding_tangent_scratch_len, ElasticPreconditioner, IncrementProblem,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{AmgHierarchy, AmgOptions, SolveOptions, SpringSystem};
use deform_kernel::{Cells, Graph, Real};

/// Most nodes of the meshes.
const N: usize = 8;
/// Most directed edges (the hexahedron's 28 pairs, both ways).
const E: usize = 56;

/// Calls every elasticity entry point with opaque inputs.
pub fn exercise() {
    let square = bb(Mesh {
        offsets: &[0, 3, 6],
        nodes: &[0, 1, 2, 0, 2, 3],
        kinds: &[5, 5],
        nodes_count: 4,
    });
    let cube = bb(Mesh {
        offsets: &[0, 8],
        nodes: &[0, 1, 2, 3, 4, 5, 6, 7],
        kinds: &[12],
        nodes_count: 8,
    });
    run::<f32, 2>(&square);
    run::<f64, 2>(&square);
    run::<f32, 3>(&cube);
    run::<f64, 3>(&cube);
}

#[derive(Clone, Copy)]
struct Mesh {
    offsets: &'static [u32],
    nodes: &'static [u32],
    kinds: &'static [u8],
    nodes_count: usize,
}

#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

#[inline(never)]
fn run<T: Real, const D: usize>(m: &Mesh) {
    let Ok(cells) = Cells::new(m.nodes_count, m.offsets, m.nodes, m.kinds) else {
        return;
    };
    let n = m.nodes_count;
    keep(elasticity_graph_len(&cells));
    let (mut offsets, mut targets) = ([0u32; N + 1], [0u32; E]);
    let o = offsets.get_mut(..n + 1).unwrap_or(&mut []);
    let Ok(used) = elasticity_graph(&cells, bb(o), bb(&mut targets[..])) else {
        return;
    };
    let (o, t) = (
        offsets.get(..n + 1).unwrap_or(&[]),
        targets.get(..used).unwrap_or(&[]),
    );
    let Ok(graph) = Graph::new(o, t) else {
        return;
    };
    let points: [[T; D]; N] = bb([[T::HALF; D]; N]);
    let points = points.get(..n).unwrap_or(&[]);
    let wall: [T; N] = bb([T::ONE; N]);
    let mut moduli = [T::ZERO; 2];
    let moduli = moduli.get_mut(..cells.len()).unwrap_or(&mut []);
    for modulus in bb([
        Modulus::Constant,
        Modulus::InverseVolume,
        Modulus::WallDistance,
    ]) {
        keep(cell_moduli(
            &cells,
            points,
            modulus,
            wall.get(..n),
            bb(&mut *moduli),
        ));
    }
    let mut diag = [[[T::ZERO; D]; D]; N];
    let mut off = [[[T::ZERO; D]; D]; E];
    let (diag, off) = (
        diag.get_mut(..n).unwrap_or(&mut []),
        off.get_mut(..used).unwrap_or(&mut []),
    );
    keep(assemble(
        &cells,
        points,
        &graph,
        moduli,
        bb(T::from_f64(0.3)),
        bb(&mut *diag),
        bb(&mut *off),
    ));
    let fixed: [u8; N] = bb([1, 0, 1, 0, 1, 0, 1, 0]);
    let fixed = fixed.get(..n).unwrap_or(&[]);
    solves(&graph, diag, off, fixed, &cells, points);
    increment_derivatives(&cells, &graph, fixed, points, ElasticPreconditioner::Blocks);
    let mut p = [[T::HALF; D]; N];
    let d: [[T; D]; N] = bb([[T::ONE; D]; N]);
    let (mut cur, mut step) = ([[T::ZERO; D]; N], [[T::ZERO; D]; N]);
    let mut cg = [[T::ZERO; D]; 4 * N];
    let params = bb(Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps: 2,
    });
    let buffers = IncrementBuffers {
        moduli,
        diag,
        off,
        current: cur.get_mut(..n).unwrap_or(&mut []),
        step: step.get_mut(..n).unwrap_or(&mut []),
    };
    let opts = bb(SolveOptions::<T>::default());
    let p = p.get_mut(..n).unwrap_or(&mut []);
    keep(deform_incremental(
        &cells,
        &graph,
        fixed,
        &params,
        bb(p),
        d.get(..n).unwrap_or(&[]),
        buffers,
        |s, u| s.solve(u, &opts, &mut cg[..]),
    ));
}

#[inline(never)]
fn solves<T: Real, const D: usize>(
    graph: &Graph<'_>,
    diag: &[[[T; D]; D]],
    off: &[[[T; D]; D]],
    fixed: &[u8],
    cells: &Cells<'_>,
    points: &[[T; D]],
) {
    let Ok(sys) = ElasticSystem::new(*graph, diag, off, fixed) else {
        return;
    };
    let sys = bb(sys);
    let n = sys.node_count();
    let x: [[T; D]; N] = bb([[T::HALF; D]; N]);
    let mut y = [[T::ZERO; D]; N];
    keep(sys.multiply(
        x.get(..n).unwrap_or(&[]),
        bb(y.get_mut(..n).unwrap_or(&mut [])),
    ));
    let opts = bb(SolveOptions::<T>::default());
    let mut scratch = [[T::ZERO; D]; 8 * N];
    let mut u = x;
    keep(elastic_scratch_len(bb(n)));
    keep(sys.solve(
        bb(u.get_mut(..n).unwrap_or(&mut [])),
        &opts,
        bb(&mut scratch[..]),
    ));
    let mut w = [T::ZERO; E];
    let w = w.get_mut(..graph.edge_count()).unwrap_or(&mut []);
    keep(sys.amg_weights(bb(&mut *w)));
    let mut anchor = [0u32; N];
    let Ok(spring) = SpringSystem::new(*graph, w, fixed, &mut anchor[..]) else {
        return;
    };
    let amg = bb(AmgOptions {
        max_coarse: 2,
        ..AmgOptions::<T>::default()
    });
    let (mut work, mut index, mut values) = ([0u32; 4 * (N + E) + 64], [0u32; 512], [T::ZERO; 512]);
    let Ok(h) = AmgHierarchy::setup(
        &spring,
        &amg,
        &mut work[..],
        &mut index[..],
        &mut values[..],
    ) else {
        return;
    };
    keep(elastic_amg_scratch_len(bb(n), h.coarse_unknowns()));
    keep(sys.solve_amg(
        &spring,
        &h,
        bb(u.get_mut(..n).unwrap_or(&mut [])),
        &opts,
        bb(&mut scratch[..]),
    ));
    keep(elastic_amg_sliding_scratch_len(bb(n), h.coarse_unknowns()));
    let pre = bb(ElasticPreconditioner::Amg(&spring, &h));
    sliding(&sys, pre);
    sliding(&sys, bb(ElasticPreconditioner::Blocks));
    increment_derivatives(cells, graph, fixed, points, pre);
}

/// The sliding solve and derivatives with `pre` (the free nodes of the system on a plane).
#[inline(never)]
fn sliding<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
) {
    let n = sys.node_count();
    let kinds: [u8; N] = bb([1, 2, 1, 0, 1, 2, 1, 0]);
    let mut e = [T::ZERO; D];
    if let Some(x) = e.last_mut() {
        *x = T::ONE;
    }
    let dirs: [[T; D]; N] = bb([e; N]);
    let Ok(c) = Constraints::new(kinds.get(..n).unwrap_or(&[]), dirs.get(..n).unwrap_or(&[]))
    else {
        return;
    };
    let opts = bb(SolveOptions::<T>::default());
    let mut scratch = [[T::ZERO; D]; 16 * N];
    let x: [[T; D]; N] = bb([[T::HALF; D]; N]);
    let mut u = x;
    let len = elastic_sliding_tangent_scratch_len(&pre, bb(n));
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    let u = u.get_mut(..n).unwrap_or(&mut []);
    keep(elastic_sliding_tangent(sys, &c, pre, &opts, bb(u), bb(sc)));
    if let ElasticPreconditioner::Amg(s, h) = pre {
        let mut v = x;
        let v = v.get_mut(..n).unwrap_or(&mut []);
        keep(sys.solve_amg_sliding(&c, s, h, bb(v), &opts, bb(&mut scratch[..])));
    }
    let len = elastic_sliding_adjoint_scratch_len(&pre, bb(n));
    let mut g = [[T::ZERO; D]; N];
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    let (w, g) = (x.get(..n).unwrap_or(&[]), g.get_mut(..n).unwrap_or(&mut []));
    keep(elastic_sliding_adjoint(
        sys,
        &c,
        pre,
        &opts,
        bb(w),
        bb(g),
        bb(sc),
    ));
}

/// Tangent and adjoint of two load increments (inverse-volume modulus) with `pre`.
#[inline(never)]
fn increment_derivatives<T: Real, const D: usize>(
    cells: &Cells<'_>,
    graph: &Graph<'_>,
    fixed: &[u8],
    points: &[[T; D]],
    pre: ElasticPreconditioner<'_, T>,
) {
    let n = points.len();
    let d: [[T; D]; N] = bb([[T::ONE; D]; N]);
    let params = bb(Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps: 2,
    });
    let p = IncrementProblem {
        cells,
        graph,
        fixed,
        params: &params,
        points,
        displacement: d.get(..n).unwrap_or(&[]),
        pre,
        options: bb(SolveOptions::default()),
    };
    keep(elastic_incremental_tangent_scratch_len(&pre, bb(n)));
    keep(elastic_incremental_adjoint_scratch_len(&pre, bb(n), bb(2)));
    let mut moduli = [T::ZERO; 2];
    let mut diag = [[[T::ZERO; D]; D]; N];
    let mut off = [[[T::ZERO; D]; D]; E];
    let (mut cur, mut step) = ([[T::ZERO; D]; N], [[T::ZERO; D]; N]);
    let mut scratch = [[T::ZERO; D]; 20 * N];
    let mut dx: [[T; D]; N] = bb([[T::HALF; D]; N]);
    macro_rules! buffers {
        () => {
            IncrementBuffers {
                moduli: moduli.get_mut(..cells.len()).unwrap_or(&mut []),
                diag: diag.get_mut(..n).unwrap_or(&mut []),
                off: off.get_mut(..graph.edge_count()).unwrap_or(&mut []),
                current: cur.get_mut(..n).unwrap_or(&mut []),
                step: step.get_mut(..n).unwrap_or(&mut []),
            }
        };
    }
    keep(elastic_incremental_tangent(
        &p,
        bb(dx.get_mut(..n).unwrap_or(&mut [])),
        buffers!(),
        bb(&mut scratch[..]),
    ));
    let mut g = [[T::ZERO; D]; N];
    keep(elastic_incremental_adjoint(
        &p,
        dx.get(..n).unwrap_or(&[]),
        bb(g.get_mut(..n).unwrap_or(&mut [])),
        buffers!(),
        bb(&mut scratch[..]),
    ));
    keep(&g);
}
