//! The elasticity multigrid and sliding solves through the C ABI: builds `libdeform_kernel`
//! (static and shared), compiles `ffi/tests/elasticity_solvers.c` (pool sizes,
//! `dk_elasticity_deform_amg`, `dk_elasticity_deform_sliding` and
//! `dk_elasticity_deform_sliding_amg`, each in f64 with 0-based cells and in f32 with 1-based
//! ones, plus bad input that must return its status and leave the points untouched), runs
//! it, and compares the printed bits and reports with the kernel's own pipeline
//! (`deform_incremental_on` with `rigid_amg` / `solve_rigid_amg`, `solve_sliding`,
//! `rigid_amg_sliding` / `solve_rigid_amg_sliding`) on the same inputs. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;
use support::elasticity::c_square_cells;

use deform_kernel::elasticity::{
    deform_incremental_on, elastic_rigid_amg_scratch_len, elastic_rigid_amg_sliding_scratch_len,
    elastic_sliding_scratch_len, elasticity_graph, elasticity_graph_len, ElasticSystem,
    IncrementBuffers, IncrementReport, Increments, Modulus,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    AmgHierarchy, AmgOptions, RigidAmg, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::{Cells, Graph, Real};

const S: usize = 6;
const N: usize = S * S;

/// Which solve every increment runs.
#[derive(Clone, Copy, PartialEq)]
enum Solver {
    Amg,
    Sliding,
    SlidingAmg,
}

/// One increment's solve with buffers of its own, as the C function does it in its pools.
fn solve_step<T: Real>(
    solver: Solver,
    sys: &ElasticSystem<'_, T, 2>,
    spring: &SpringSystem<'_, T>,
    c: &Constraints<'_, T, 2>,
    mesh: &[[T; 2]],
    u: &mut [[T; 2]],
) -> deform_kernel::Result<SolveReport<T>> {
    let stop = SolveOptions {
        update_tol: T::ZERO,
        ..SolveOptions::<T>::default()
    };
    if solver == Solver::Sliding {
        let mut s = vec![[T::ZERO; 2]; elastic_sliding_scratch_len(N).unwrap()];
        return sys.solve_sliding(c, u, &stop, &mut s);
    }
    let amg = AmgOptions {
        max_coarse: 8,
        ..AmgOptions::<T>::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(spring)];
    let sizes = RigidAmg::setup_len(spring, 2, &amg, &mut work)?;
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![T::ZERO; sizes.values]);
    let (w, i, v) = (&mut work, &mut index, &mut values);
    if solver == Solver::Amg {
        let mut s =
            vec![[T::ZERO; 2]; elastic_rigid_amg_scratch_len(N, sizes.coarse_scalars, 2).unwrap()];
        let h = sys.rigid_amg(spring, mesh, &amg, w, i, v)?;
        sys.solve_rigid_amg(&h, u, &stop, &mut s)
    } else {
        let len = elastic_rigid_amg_sliding_scratch_len(N, sizes.coarse_scalars, 2).unwrap();
        let mut s = vec![[T::ZERO; 2]; len];
        let h = sys.rigid_amg_sliding(c, spring, mesh, &amg, w, i, v)?;
        sys.solve_rigid_amg_sliding(c, &h, u, &stop, &mut s)
    }
}

/// The kernel's run of `solver` on the C program's inputs, printed as the C program prints it.
fn expected<T: Real>(
    tag: &str,
    solver: Solver,
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
    let to_t = |v: &[f64]| -> Vec<[T; 2]> {
        v.chunks(2)
            .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
            .collect()
    };
    let (mut p, d) = (to_t(points), to_t(disp));
    let edge = |n: usize| n % S == 0 || n / S == 0 || n % S == S - 1 || n / S == S - 1;
    let slides = |n: usize| n / S == 0 && n % S != 0 && n % S != S - 1;
    let sliding = solver != Solver::Amg;
    let fixed: Vec<u8> = (0..N)
        .map(|n| (edge(n) && !(sliding && slides(n))) as u8)
        .collect();
    let ckinds: Vec<u8> = (0..N)
        .map(|n| if slides(n) { 2 } else { fixed[n] })
        .collect();
    let normals = vec![[T::ZERO, T::ONE]; N];
    let c = Constraints::new(&ckinds, &normals).unwrap();
    let w = vec![T::ONE; used];
    let mut anchor = vec![0u32; N];
    let spring = SpringSystem::new(graph, &w, &fixed, &mut anchor).unwrap();
    let mut moduli = vec![T::ZERO; cells.len()];
    let (mut diag, mut off) = (vec![[[T::ZERO; 2]; 2]; N], vec![[[T::ZERO; 2]; 2]; used]);
    let (mut cur, mut step) = (vec![[T::ZERO; 2]; N], vec![[T::ZERO; 2]; N]);
    let params = Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps: 2,
    };
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut cur,
        step: &mut step,
    };
    let r: IncrementReport<T> = deform_incremental_on(
        &cells,
        &graph,
        &fixed,
        &params,
        &mut p,
        &d,
        buffers,
        |sys, mesh, u| solve_step(solver, sys, &spring, &c, mesh, u),
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
fn elasticity_multigrid_and_sliding_from_c_equal_the_kernel_bit_for_bit() {
    for (name, printed) in run_c_both("elasticity_solvers") {
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"elasticity solvers: every check held"),
            "{name}: {printed}"
        );
        let points = parse_hex64(lines[0], "points");
        let disp = parse_hex64(lines[1], "disp");
        let mut want = String::new();
        for (solver, t64, t32) in [
            (Solver::Amg, "amg64", "amg32"),
            (Solver::Sliding, "slide64", "slide32"),
            (Solver::SlidingAmg, "slamg64", "slamg32"),
        ] {
            want += &expected::<f64>(t64, solver, &points, &disp, hex64);
            want += &expected::<f32>(t32, solver, &points, &disp, hex32);
        }
        let got = lines[2..14].join("\n") + "\n";
        assert_eq!(got, want, "{name}");
    }
}
