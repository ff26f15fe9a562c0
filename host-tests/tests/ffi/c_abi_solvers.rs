//! The solver ABI (`dk_spring_*`, `dk_quality_*`, `dk_taubin_*`) seen from C: builds
//! `libdeform_kernel` (static and shared), compiles `ffi/tests/solvers.c` (every solver
//! function in f64 and f32 on cases with known answers, plus bad input that must return the
//! documented status and write nothing) and `ffi/tests/solvers_parity.c` (bit patterns of a
//! spring solve, a structured Taubin smoothing, an arclength smoothing and a graph smoothing),
//! runs them, and compares the parity program's output with the Rust API on the same inputs;
//! and `ffi/tests/solvers_amg.c` (the stateless multigrid solves `dk_spring_solve_linear_amg`
//! and `dk_spring_solve_angle_amg` with their pool-size queries, f64 and f32, on a graded
//! 3,072-node grid, plus their bad input), whose sizes, reports and values must equal the
//! kernel's `AmgHierarchy::setup_len` / `setup` / `solve_linear_amg` / `solve_angle_amg` on the
//! same inputs. Needs `gcc` on PATH.
//!
//! The header's layout of the `#[repr(C)]` option and report structs is checked at compile
//! time in the ffi crate; here the tests compare what C sees. (Calling the `extern "C"`
//! functions directly from Rust would need `unsafe`, which the workspace lints forbid in this
//! crate.)

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::Direction;
use support::c_build::*;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions, AngleMethod,
    AngleSystem, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::taubin::{
    smooth_arclength, smooth_arclength_scratch_len, smooth_graph, smooth_structured, GraphOptions,
    SmoothOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{graph_from_edges, Block, Graph, Real};

/// The C flags, plus an old-style RPATH for the shared-library runs: cargo's test runner puts
/// its own target directories (which may hold an older debug `libdeform_kernel.so`) on
/// `LD_LIBRARY_PATH`, which a RUNPATH would not override.
fn flags() -> Vec<String> {
    let mut f = c_flags();
    f.push("-Wl,--disable-new-dtags".to_string());
    f
}

#[test]
fn solvers_c_program_passes_against_static_and_shared_library() {
    let src = workspace().join("ffi/tests/solvers.c");
    let flags = flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "solvers_static"),
        (Link::Shared, "solvers_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        assert_eq!(run(&exe), "solvers: every check held\n", "{name}");
    }
}

/// A CSR graph: offsets and targets.
type Csr = (Vec<u32>, Vec<u32>);

/// CSR of an undirected edge list.
fn csr(n: usize, edges: &[[u32; 2]]) -> Csr {
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; 2 * edges.len()];
    let used = graph_from_edges(n, edges, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    (offsets, targets)
}

/// The 4 x 4 grid graph (node i + 4 j) and the chain 0-1-2-3-4, as solvers_parity.c builds
/// them.
fn graphs() -> (Csr, Csr) {
    let mut e = Vec::new();
    for j in 0..4u32 {
        for i in 0..4u32 {
            if i + 1 < 4 {
                e.push([i + 4 * j, i + 1 + 4 * j]);
            }
            if j + 1 < 4 {
                e.push([i + 4 * j, i + 4 * (j + 1)]);
            }
        }
    }
    let chain: Vec<[u32; 2]> = (0..4u32).map(|i| [i, i + 1]).collect();
    (csr(16, &e), csr(5, &chain))
}

/// What solvers_parity.c prints for one precision.
fn expected_for<T: Real>(tag: &str, hex: fn(&str, &[T]) -> String) -> String {
    let ((go, gt), (co, ct)) = graphs();
    let grid = Graph::new(&go, &gt).unwrap();
    let chain = Graph::new(&co, &ct).unwrap();
    let mut out = String::new();

    // Linear springs: Batina stiffness on a perturbed 4 x 4 grid, CG + Jacobi, defaults.
    let mut pts = vec![[T::ZERO; 2]; 16];
    let mut fixed = vec![0u8; 16];
    let mut v = vec![[T::ZERO; 1]; 16];
    for j in 0..4usize {
        for i in 0..4usize {
            let n = i + 4 * j;
            pts[n] = [
                T::from_f64(i as f64 + 0.1 * (j * j) as f64),
                T::from_f64(j as f64 + 0.05 * (i * i) as f64),
            ];
            let boundary = i == 0 || j == 0 || i == 3 || j == 3;
            fixed[n] = u8::from(boundary);
            if boundary {
                v[n] = [T::from_f64(((n * 5) % 7) as f64 / 7.0)];
            }
        }
    }
    let mut k = vec![T::ZERO; gt.len()];
    batina_stiffness(&grid, &pts, T::ONE, &mut k).unwrap();
    let mut idx = vec![0u32; 16];
    let sys = SpringSystem::new(grid, &k, &fixed, &mut idx).unwrap();
    let mut scratch = vec![[T::ZERO; 1]; 80];
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    sys.solve_linear(&mut v, method, &SolveOptions::default(), &mut scratch)
        .unwrap();
    let flat: Vec<T> = v.iter().map(|x| x[0]).collect();
    out += &hex(&format!("spring_{tag}"), &flat);

    // Structured Taubin filter on a 5 x 4 x 3 block, 5 iterations, the paper's λ, μ.
    let block = Block::new([5, 4, 3]).unwrap();
    let mut field: Vec<T> = (0..60usize)
        .map(|i| T::from_f64(((i * 7919) % 13) as f64 / 13.0))
        .collect();
    let mut fs = vec![T::ZERO; 60];
    smooth_structured(
        &block,
        &mut field,
        TaubinParams::paper(),
        5,
        &StructuredOptions::default(),
        &mut fs,
    )
    .unwrap();
    out += &hex(&format!("structured_{tag}"), &field);

    // Alter's arclength smoothing of a 6 x 3 grid along i, normalised.
    let xs = [0.0, 1.0, 2.0, 3.0, 6.0, 9.0];
    let block = Block::new([6, 3, 1]).unwrap();
    let mut grid_pts = vec![[T::ZERO; 2]; 18];
    for j in 0..3usize {
        for (i, &x) in xs.iter().enumerate() {
            grid_pts[i + 6 * j] = [T::from_f64(x + 0.25 * j as f64), T::from_f64(j as f64)];
        }
    }
    let mut opts = SmoothOptions::new(Direction::I);
    opts.normalised = true;
    let mut gs = vec![T::ZERO; smooth_arclength_scratch_len::<2>(&block, Direction::I, None)];
    smooth_arclength(&block, &mut grid_pts, &opts, &mut gs).unwrap();
    let flat: Vec<T> = grid_pts.iter().flatten().copied().collect();
    out += &hex(&format!("arclength_{tag}"), &flat);

    // Graph fairing of 2-component values on the chain, 3 iterations.
    let mut gv: Vec<[T; 2]> = (0..5usize)
        .map(|n| {
            let c = |i: usize| T::from_f64(((i * 37) % 11) as f64 / 11.0);
            [c(2 * n), c(2 * n + 1)]
        })
        .collect();
    let mut cs = vec![[T::ZERO; 2]; 5];
    smooth_graph(
        &chain,
        &mut gv,
        TaubinParams::paper(),
        3,
        &GraphOptions::default(),
        &mut cs,
    )
    .unwrap();
    let flat: Vec<T> = gv.iter().flatten().copied().collect();
    out += &hex(&format!("graph_{tag}"), &flat);
    out
}

/// The angle-spring scratch lengths from the kernel (in scalars), f64 and f32 per case.
fn expected_angle_scratch() -> String {
    let ((go, gt), _) = graphs();
    let grid = Graph::new(&go, &gt).unwrap();
    let mut s = String::from("angle_scratch");
    for epsilon in [0.01, 0.0] {
        for method in [
            AngleMethod::DirectGaussSeidel,
            AngleMethod::DirectJacobi,
            AngleMethod::Cg,
        ] {
            s += &format!(" {}", angle_len::<f64>(grid, epsilon, method));
            s += &format!(" {}", angle_len::<f32>(grid, epsilon, method));
        }
    }
    s + "\n"
}

fn angle_len<T: Real>(grid: Graph<'_>, epsilon: f64, method: AngleMethod) -> usize {
    let k = vec![T::ONE; grid.edge_count()];
    let mut fixed = vec![0u8; 16];
    let mut pts = vec![[T::ZERO; 2]; 16];
    for j in 0..4usize {
        for i in 0..4usize {
            pts[i + 4 * j] = [T::from_usize(i), T::from_usize(j)];
            fixed[i + 4 * j] = u8::from(i == 0 || j == 0 || i == 3 || j == 3);
        }
    }
    let mut idx = vec![0u32; 16];
    let base = SpringSystem::new(grid, &k, &fixed, &mut idx).unwrap();
    let sys = AngleSystem::new(base, &pts, T::from_f64(epsilon)).unwrap();
    sys.angle_scratch_len(method) * 2
}

#[test]
fn solver_abi_matches_rust_bit_for_bit() {
    let expected = expected_angle_scratch()
        + &expected_for::<f64>("f64", hex64)
        + &expected_for::<f32>("f32", hex32);
    let src = workspace().join("ffi/tests/solvers_parity.c");
    let flags = flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "solvers_parity_static"),
        (Link::Shared, "solvers_parity_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        assert_eq!(run(&exe), expected, "{name}");
    }
}

/// The grid of solvers_amg.c: 64 x 48 nodes (node i + 64 j), edges along i, along j and one
/// diagonal per cell, in the C program's order; the fixed mask (the outer boundary).
fn amg_mesh() -> (Csr, Vec<u8>) {
    const NI: usize = 64;
    const NJ: usize = 48;
    let mut e = Vec::new();
    let mut fixed = vec![0u8; NI * NJ];
    for j in 0..NJ {
        for i in 0..NI {
            let n = (i + NI * j) as u32;
            fixed[i + NI * j] = u8::from(i == 0 || j == 0 || i == NI - 1 || j == NJ - 1);
            if i + 1 < NI {
                e.push([n, n + 1]);
            }
            if j + 1 < NJ {
                e.push([n, n + NI as u32]);
            }
            if i + 1 < NI && j + 1 < NJ {
                e.push([n, n + NI as u32 + 1]);
            }
        }
    }
    (csr(NI * NJ, &e), fixed)
}

/// What solvers_amg.c prints for one precision, from the kernel called directly: the pool
/// sizes (`setup_work_len`, then the hierarchy's sizes and the solve scratch, for 2 and 1
/// components), the linear and the angle (ε = 0.1) multigrid solves with the default options.
fn amg_expected<T: Real>(
    tag: &str,
    points: &[f64],
    values0: &[f64],
    hex: fn(&str, &[T]) -> String,
) -> Vec<String> {
    let ((offsets, targets), fixed) = amg_mesh();
    let g = Graph::new(&offsets, &targets).unwrap();
    let n = g.node_count();
    let pts: Vec<[T; 2]> = points
        .chunks_exact(2)
        .map(|p| [T::from_f64(p[0]), T::from_f64(p[1])])
        .collect();
    let v0: Vec<[T; 2]> = values0
        .chunks_exact(2)
        .map(|p| [T::from_f64(p[0]), T::from_f64(p[1])])
        .collect();
    assert_eq!(pts.len(), n);
    let mut k = vec![T::ZERO; g.edge_count()];
    batina_stiffness(&g, &pts, T::ONE, &mut k).unwrap();
    let mut idx = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut idx).unwrap();
    let opts = AmgOptions::<T>::default();
    let stop = SolveOptions::<T>::default();
    let mut out = Vec::new();

    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut hv = vec![T::ZERO; sizes.values];
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut hv).unwrap();
    let items = solve_linear_amg_scratch_len(&h);
    out.push(format!(
        "sizes_{tag} {} {} {} 0 {}",
        work.len(),
        sizes.values + 2 * items,
        work.len() + sizes.index,
        sizes.values + items
    ));

    let mut v = v0.clone();
    let mut scratch = vec![[T::ZERO; 2]; items];
    let r = sys
        .solve_linear_amg(&h, &mut v, &stop, &mut scratch)
        .unwrap();
    out.push(format!(
        "linear_{tag} {} {}",
        r.iterations,
        u8::from(r.converged)
    ));
    out.push(hex64(
        &format!("linear_report_{tag}"),
        &[r.residual.to_f64(), r.max_update.to_f64()],
    ));
    let flat: Vec<T> = v.iter().flatten().copied().collect();
    out.push(hex(&format!("linear_values_{tag}"), &flat));

    let asys = AngleSystem::new(sys, &pts, T::from_f64(0.1)).unwrap();
    // A hierarchy set up again on the angle system's base, as the C entry does.
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(asys.base())];
    let mut index = vec![0u32; sizes.index];
    let mut hv = vec![T::ZERO; sizes.values];
    let h = AmgHierarchy::setup(asys.base(), &opts, &mut work, &mut index, &mut hv).unwrap();
    assert_eq!(asys.angle_amg_scratch_len(&h), items);
    let mut v = v0.clone();
    let mut scratch = vec![[T::ZERO; 2]; items];
    let r = asys
        .solve_angle_amg(&h, &mut v, &stop, &mut scratch)
        .unwrap();
    out.push(format!(
        "angle_{tag} {} {}",
        r.iterations,
        u8::from(r.converged)
    ));
    out.push(hex64(
        &format!("angle_report_{tag}"),
        &[r.residual.to_f64(), r.max_update.to_f64()],
    ));
    let flat: Vec<T> = v.iter().flatten().copied().collect();
    out.push(hex(&format!("angle_values_{tag}"), &flat));
    out.into_iter().map(|l| l.trim_end().to_string()).collect()
}

#[test]
fn multigrid_solves_from_c_equal_the_kernel_bit_for_bit() {
    let src = workspace().join("ffi/tests/solvers_amg.c");
    let flags = flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    for (link, name) in [
        (Link::Static, "solvers_amg_static"),
        (Link::Shared, "solvers_amg_shared"),
    ] {
        let exe = tmp(name);
        compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
        let printed = run(&exe);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"solvers_amg: every check held"),
            "{name}"
        );
        let points = parse_hex64(lines[0], "points");
        let values0 = parse_hex64(lines[1], "values0");
        let mut expected = amg_expected::<f64>("f64", &points, &values0, hex64);
        expected.extend(amg_expected::<f32>("f32", &points, &values0, hex32));
        let got: Vec<&str> = lines
            .iter()
            .copied()
            .filter(|l| {
                !["points", "values0", "cg_", "solvers_amg"]
                    .iter()
                    .any(|p| l.starts_with(p))
            })
            .collect();
        assert_eq!(got.len(), expected.len(), "{name}: lines");
        for (g, e) in got.iter().zip(&expected) {
            let head = |s: &str| s.split(' ').next().unwrap_or("").to_string();
            assert!(
                g == e,
                "{name}: {} differs from the kernel's {}",
                head(g),
                head(e)
            );
        }
        // The one-level solves on the same problems take at least 4 times as many iterations.
        for (amg, one_level) in [
            ("linear_f64", "cg_linear_f64"),
            ("angle_f64", "cg_angle_f64"),
            ("linear_f32", "cg_linear_f32"),
            ("angle_f32", "cg_angle_f32"),
        ] {
            let count = |prefix: &str| -> usize {
                let l = lines
                    .iter()
                    .find(|l| l.starts_with(&format!("{prefix} ")))
                    .unwrap_or_else(|| panic!("{name}: no {prefix} line"));
                l.split(' ').nth(1).unwrap().parse().unwrap()
            };
            let (a, c) = (count(amg), count(one_level));
            assert!(
                a > 0 && 4 * a <= c,
                "{name}: {amg} {a} against {one_level} {c}"
            );
        }
    }
}

/// `ffi/examples/spring_amg_timing.c` (the timing program of docs/amg.md) builds with the
/// strict flags and runs at its default size (3,072 nodes): every solve converges and the
/// multigrid ones take fewer iterations than the one-level ones.
#[test]
fn multigrid_timing_example_runs() {
    let src = workspace().join("ffi/examples/spring_amg_timing.c");
    let flags = flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let exe = tmp("spring_amg_timing");
    compile(
        "gcc",
        std::slice::from_ref(&src),
        &flags,
        Link::Static,
        &exe,
    );
    let printed = run(&exe);
    let iterations = |prefix: &str| -> usize {
        let l = printed
            .lines()
            .find(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no line {prefix}:\n{printed}"));
        assert!(l.contains("converged 1"), "{l}");
        let it = l.split(": ").nth(1).unwrap().split(' ').next().unwrap();
        it.parse().unwrap()
    };
    assert!(iterations("linear, multigrid") < iterations("linear, CG + Jacobi"));
    assert!(iterations("angle, multigrid") < iterations("angle, block-Jacobi CG"));
}
