//! Multi-step elasticity sensitivities through the C ABI: builds `libdeform_kernel` (static
//! and shared), compiles `ffi/tests/elasticity_sensitivity.c` (`dk_elasticity_tangent` and
//! `dk_elasticity_adjoint` and their `_f32` twins: the dot-product identity, central
//! differences of `dk_elasticity_deform`, bad input), runs it, and recomputes the f64
//! tangent and adjoint it printed with the kernel's `elastic_incremental_tangent` /
//! `elastic_incremental_adjoint` on the same inputs, bit for bit. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::elasticity::{
    elasticity_graph, elasticity_graph_len, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::sensitivity::{
    elastic_incremental_adjoint, elastic_incremental_adjoint_scratch_len,
    elastic_incremental_tangent, ElasticPreconditioner, IncrementProblem,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Cells, Graph};

const S: usize = 5;
const N: usize = S * S;

/// The C program's triangles: two per square.
fn triangles() -> (Vec<u32>, Vec<u32>, Vec<u8>) {
    let (mut offsets, mut nodes, mut kinds) = (vec![0u32], vec![], vec![]);
    for j in 0..S - 1 {
        for i in 0..S - 1 {
            let a = (i + S * j) as u32;
            for t in [
                [a, a + 1, a + 1 + S as u32],
                [a, a + 1 + S as u32, a + S as u32],
            ] {
                nodes.extend_from_slice(&t);
                offsets.push(nodes.len() as u32);
                kinds.push(5);
            }
        }
    }
    (offsets, nodes, kinds)
}

/// Owned increment buffers.
struct Bufs {
    moduli: Vec<f64>,
    diag: Vec<[[f64; 2]; 2]>,
    off: Vec<[[f64; 2]; 2]>,
    current: Vec<[f64; 2]>,
    step: Vec<[f64; 2]>,
}

impl Bufs {
    fn buffers(&mut self) -> IncrementBuffers<'_, f64, 2> {
        IncrementBuffers {
            moduli: &mut self.moduli,
            diag: &mut self.diag,
            off: &mut self.off,
            current: &mut self.current,
            step: &mut self.step,
        }
    }
}

fn pairs(v: &[f64]) -> Vec<[f64; 2]> {
    v.chunks(2).map(|c| [c[0], c[1]]).collect()
}

/// The kernel's tangent along `v` and adjoint of `w`, printed as the C program prints them.
fn expected(points: &[f64], disp: &[f64], v: &[f64], w: &[f64]) -> String {
    let (offsets, nodes, kinds) = triangles();
    let cells = Cells::new(N, &offsets, &nodes, &kinds).unwrap();
    let mut goffs = vec![0u32; N + 1];
    let mut targets = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut goffs, &mut targets).unwrap();
    let graph = Graph::new(&goffs, &targets[..used]).unwrap();
    let fixed: Vec<u8> = (0..N)
        .map(|k| u8::from(k % S == 0 || k / S == 0 || k % S == S - 1 || k / S == S - 1))
        .collect();
    let params = Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: 0.3,
        steps: 3,
    };
    let (points, disp) = (pairs(points), pairs(disp));
    let p = IncrementProblem {
        cells: &cells,
        graph: &graph,
        fixed: &fixed,
        params: &params,
        points: &points,
        displacement: &disp,
        pre: ElasticPreconditioner::Blocks,
        options: SolveOptions {
            max_iterations: 10_000,
            residual_tol: 1e-13,
            update_tol: 0.0,
        },
    };
    let mut b = Bufs {
        moduli: vec![0.0; kinds.len()],
        diag: vec![[[0.0; 2]; 2]; N],
        off: vec![[[0.0; 2]; 2]; used],
        current: vec![[0.0; 2]; N],
        step: vec![[0.0; 2]; N],
    };
    let len = elastic_incremental_adjoint_scratch_len(&p.pre, N, 3);
    let mut scratch = vec![[0.0; 2]; len];
    let mut jv = pairs(v);
    elastic_incremental_tangent(&p, &mut jv, b.buffers(), &mut scratch).unwrap();
    let mut g = vec![[0.0; 2]; N];
    elastic_incremental_adjoint(&p, &pairs(w), &mut g, b.buffers(), &mut scratch).unwrap();
    let flat = |x: &[[f64; 2]]| -> Vec<f64> { x.iter().flatten().copied().collect() };
    hex64("jv", &flat(&jv)) + &hex64("g", &flat(&g))
}

#[test]
fn elasticity_sensitivities_from_c_equal_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "elasticity_sensitivity_c_static"),
        (Link::Shared, "elasticity_sensitivity_c_shared"),
    ] {
        let printed = run_c_test("elasticity_sensitivity", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"elasticity_sensitivity: every check held"),
            "{name}: {printed}"
        );
        let input = |k: usize, what: &str| parse_hex64(lines[k], what);
        let want = expected(
            &input(0, "points"),
            &input(1, "disp"),
            &input(2, "v"),
            &input(3, "w"),
        );
        assert_eq!(lines[4..6].join("\n") + "\n", want, "{name}");
    }
}
