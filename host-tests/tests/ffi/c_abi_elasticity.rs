//! Linear elasticity through the C ABI: builds `libdeform_kernel` (static and shared),
//! compiles `ffi/tests/elasticity.c` (graph, scratch size, default options and
//! `dk_elasticity_deform` in f64 with 0-based cells and in f32 with 1-based ones, plus bad
//! input that must return its status and leave the points untouched), runs it, and compares
//! the printed bits and reports with the kernel (`elasticity_graph`, `deform_incremental` with
//! block-Jacobi CG) on the same inputs. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;
use support::elasticity::c_square_cells;

use deform_kernel::elasticity::{
    deform_incremental, elasticity_graph, elasticity_graph_len, IncrementBuffers, Increments,
    Modulus,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Cells, Graph, Real};

const S: usize = 6;
const N: usize = S * S;

/// The kernel's run on the C program's inputs, printed as the C program prints it.
fn expected<T: Real>(
    tag: &str,
    points: &[f64],
    disp: &[f64],
    hex: fn(&str, &[T]) -> String,
) -> String {
    let (offs, nodes, kinds) = c_square_cells(S);
    let cells = Cells::new(N, &offs, &nodes, &kinds).unwrap();
    let mut go = vec![0u32; N + 1];
    let mut gt = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut go, &mut gt).unwrap();
    let graph = Graph::new(&go, &gt[..used]).unwrap();
    let mut p: Vec<[T; 2]> = points
        .chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect();
    let d: Vec<[T; 2]> = disp
        .chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect();
    let fixed: Vec<u8> = (0..N)
        .map(|n| (n % S == 0 || n / S == 0 || n % S == S - 1 || n / S == S - 1) as u8)
        .collect();
    let mut moduli = vec![T::ZERO; cells.len()];
    let (mut diag, mut off) = (vec![[[T::ZERO; 2]; 2]; N], vec![[[T::ZERO; 2]; 2]; used]);
    let (mut cur, mut step) = (vec![[T::ZERO; 2]; N], vec![[T::ZERO; 2]; N]);
    let mut cg = vec![[T::ZERO; 2]; 4 * N];
    let params = Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps: 3,
    };
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut cur,
        step: &mut step,
    };
    let options = SolveOptions::<T>::default();
    let r = deform_incremental(
        &cells,
        &graph,
        &fixed,
        &params,
        &mut p,
        &d,
        buffers,
        |sys, u| sys.solve(u, &options, &mut cg),
    )
    .unwrap();
    let flat: Vec<T> = p.iter().flatten().copied().collect();
    hex(tag, &flat)
        + &format!(
            "{tag} report {} {} {} {:016X} {}\n",
            r.steps,
            r.iterations,
            r.max_step_iterations,
            r.residual.to_f64().to_bits(),
            r.converged as i32
        )
}

#[test]
fn elasticity_from_c_equals_the_kernel_bit_for_bit() {
    for (name, printed) in run_c_both("elasticity") {
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"elasticity: every check held"),
            "{name}: {printed}"
        );
        let points = parse_hex64(lines[0], "points");
        let disp = parse_hex64(lines[1], "disp");
        let want = expected::<f64>("f64", &points, &disp, hex64)
            + &expected::<f32>("f32", &points, &disp, hex32);
        let got = lines[2..6].join("\n") + "\n";
        assert_eq!(got, want, "{name}");
    }
}
