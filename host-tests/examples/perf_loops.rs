//! Timings of the kernel's inner loops (issue 14 items 2, 4, 5, 6): linear-spring CG per
//! iteration, structured and graph Taubin per point-pass, `update_points` per point.
//! Speed is measured here, never asserted in tests.
//!
//! `cargo run --release -p deform-host-tests --example perf_loops [-- cg|structured|graph|update|angle-sor|all]`

use std::hint::black_box;
use std::time::Instant;

use deform_kernel::quaternion::update_points;
use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, AngleMethod, AngleSystem, LinearMethod,
    Preconditioner, SolveOptions, SpringSystem, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::taubin::{
    inverse_distance_weights, smooth_graph, smooth_structured, GraphOptions, StructuredOptions,
    TaubinParams,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Block, Graph, Quat};
use deform_meshgen::{
    naca_hybrid, naca_ogrid, naca_triangulated, rotate_markers2, AirfoilGrid, Mesh2,
};

/// Best of `reps` runs of `f`, in seconds.
fn best<F: FnMut()>(reps: usize, mut f: F) -> f64 {
    let mut t = f64::INFINITY;
    for _ in 0..reps {
        let s = Instant::now();
        f();
        t = t.min(s.elapsed().as_secs_f64());
    }
    t
}

fn cg() {
    // ~234k nodes: 1024 × 229 triangulated NACA 2412 O-grid.
    let grid = AirfoilGrid {
        surface_points: 1024,
        radial_points: 229,
        ..AirfoilGrid::inviscid()
    };
    let mesh = naca_triangulated(&grid).unwrap();
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![0.0f64; g.edge_count()];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let fixed = mesh.boundary_mask();
    let mut s = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut s).unwrap();
    let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0).unwrap();
    let x0: Vec<[f64; 2]> = rot.to_field(n);
    println!("cg: {n} nodes, {} directed edges", g.edge_count());
    let iters = 200;
    for (name, pre) in [
        ("none", Preconditioner::None),
        ("jacobi", Preconditioner::Jacobi),
        ("ssor 1.0", Preconditioner::Ssor { omega: 1.0 }),
    ] {
        let m = LinearMethod::Cg {
            preconditioner: pre,
        };
        let opts = SolveOptions {
            max_iterations: iters,
            residual_tol: 0.0,
            update_tol: 0.0,
        };
        let mut scratch = vec![[0.0f64; 2]; solve_linear_scratch_len(&m, n)];
        let mut its = 0;
        let t = best(3, || {
            let mut x = x0.clone();
            let r = sys.solve_linear(&mut x, m, &opts, &mut scratch).unwrap();
            its = r.iterations;
            black_box(&x);
        });
        println!(
            "  cg+{name:9} {its} it: {:.3} ms/iteration ({:.2} ns/node-iteration)",
            t * 1e3 / its as f64,
            t * 1e9 / (its * n) as f64
        );
        if matches!(pre, Preconditioner::None) {
            continue; // ~18k iterations: too long for a quick run
        }
        let opts = SolveOptions {
            max_iterations: 100_000,
            residual_tol: 1e-8,
            update_tol: 0.0,
        };
        let mut x = x0.clone();
        let s = Instant::now();
        let r = sys.solve_linear(&mut x, m, &opts, &mut scratch).unwrap();
        println!(
            "  cg+{name:9} to 1e-8: {} iterations, {:.3} s, converged {}",
            r.iterations,
            s.elapsed().as_secs_f64(),
            r.converged
        );
    }
}

/// Deterministic values in [-1, 1) (test data only).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn structured() {
    let n = 256;
    let block = Block::new([n, n, n]).unwrap();
    let mut s = 1u64;
    let field0: Vec<f64> = (0..block.point_count()).map(|_| lcg(&mut s)).collect();
    let mut scratch = vec![0.0f64; block.point_count()];
    let iterations = 5;
    let mut field = field0.clone();
    let t = best(3, || {
        field.copy_from_slice(&field0);
        smooth_structured(
            &block,
            &mut field,
            TaubinParams::paper(),
            iterations,
            &StructuredOptions::default(),
            &mut scratch,
        )
        .unwrap();
    });
    let sum: f64 = field.iter().sum();
    println!(
        "structured {n}^3 f64, {} passes: {:.2} ns/point-pass (checksum {sum:.17e})",
        2 * iterations,
        t * 1e9 / (2 * iterations * block.point_count()) as f64
    );
}

fn graph() {
    let grid = AirfoilGrid {
        surface_points: 2048,
        radial_points: 488,
        ..AirfoilGrid::inviscid()
    };
    let mesh = naca_triangulated(&grid).unwrap();
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut w = vec![0.0f64; g.edge_count()];
    inverse_distance_weights(&g, &mesh.points, &mut w).unwrap();
    let fixed = mesh.boundary_mask();
    let values0: Vec<[f64; 3]> = mesh.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let mut scratch = vec![[0.0f64; 3]; n];
    let iterations = 5;
    println!("graph: {n} nodes, {} directed edges, V = 3", g.edge_count());
    for (name, opts) in [
        ("uniform", GraphOptions::default()),
        (
            "uniform+fixed",
            GraphOptions {
                weights: None,
                fixed: Some(&fixed[..]),
            },
        ),
        (
            "weights+fixed",
            GraphOptions {
                weights: Some(&w[..]),
                fixed: Some(&fixed[..]),
            },
        ),
    ] {
        let mut values = values0.clone();
        let t = best(3, || {
            values.copy_from_slice(&values0);
            smooth_graph(
                &g,
                &mut values,
                TaubinParams::paper(),
                iterations,
                &opts,
                &mut scratch,
            )
            .unwrap();
        });
        let sum: f64 = values.iter().flatten().sum();
        println!(
            "  {name:14} {:.2} ns/vertex-pass (checksum {sum:.17e})",
            t * 1e9 / (2 * iterations * n) as f64
        );
    }
}

fn update() {
    let n = 4_000_000;
    let mut s = 3u64;
    let points: Vec<[f64; 3]> = (0..n)
        .map(|_| [lcg(&mut s), lcg(&mut s), lcg(&mut s)])
        .collect();
    let translations: Vec<[f64; 3]> = (0..n)
        .map(|_| [lcg(&mut s), lcg(&mut s), lcg(&mut s)])
        .collect();
    let rotations: Vec<Quat<f64>> = (0..n)
        .map(|_| {
            Quat::new(
                1.0 + lcg(&mut s).abs(),
                lcg(&mut s),
                lcg(&mut s),
                lcg(&mut s),
            )
        })
        .collect();
    let mut out = vec![[0.0f64; 3]; n];
    let t = best(5, || {
        update_points(
            [0.1, 0.2, 0.3],
            &points,
            &translations,
            &rotations,
            &[],
            &[],
            &mut out,
        )
        .unwrap();
        black_box(&out);
    });
    let t_rot = best(5, || {
        for ((o, p), q) in out.iter_mut().zip(&points).zip(&rotations) {
            *o = q.rotate(*p);
        }
        black_box(&out);
    });
    // The compute pass alone (normalise, rotate about the origin, translate), no validation.
    let o = [0.1, 0.2, 0.3];
    let t_fused = best(5, || {
        for (((out, p), t), q) in out
            .iter_mut()
            .zip(&points)
            .zip(&translations)
            .zip(&rotations)
        {
            let q = q.normalize().unwrap_or(Quat::identity());
            let r = q.rotate([p[0] - o[0], p[1] - o[1], p[2] - o[2]]);
            *out = [
                o[0] + (t[0] + r[0]),
                o[1] + (t[1] + r[1]),
                o[2] + (t[2] + r[2]),
            ];
        }
        black_box(&out);
    });
    println!(
        "update_points 3D f64, {n} points: {:.2} ns/point; compute loop alone: {:.2}; plain Quat::rotate loop: {:.2} ns/point",
        t * 1e9 / n as f64,
        t_fused * 1e9 / n as f64,
        t_rot * 1e9 / n as f64
    );
}

/// Sweeps of the direct (node-wise) angle-spring method, plain Gauss–Seidel and
/// over-relaxed, on the `deform demo` meshes (inviscid triangles; viscous hybrid with quad
/// diagonals, as `deform move --method angle-direct` builds it), 15° pitch, tol 1e-10.
fn angle_sor() {
    let run = |label: &str, mesh: &Mesh2, diagonals: bool| {
        let n = mesh.node_count();
        let cells = mesh.cells().unwrap();
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, diagonals)];
        let used = graph_from_cells(&cells, diagonals, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        let g = Graph::new(&offsets, &targets).unwrap();
        let mut k = vec![0.0f64; g.edge_count()];
        batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
        let fixed = mesh.boundary_mask();
        let mut s = vec![0u32; n];
        let sys = SpringSystem::new(g, &k, &fixed, &mut s).unwrap();
        let asys = AngleSystem::new(sys, &mesh.points, DEFAULT_ANGLE_EPSILON).unwrap();
        let rot = rotate_markers2(mesh, &["airfoil"], AirfoilGrid::quarter_chord(), 15.0).unwrap();
        let x0: Vec<[f64; 2]> = rot.to_field(n);
        println!("angle direct, {label}: {n} nodes");
        let opts = SolveOptions {
            max_iterations: 3000,
            residual_tol: 1e-10,
            update_tol: 0.0,
        };
        let mut scratch = vec![[0.0; 2]; asys.angle_scratch_len(AngleMethod::Cg)];
        let mut x = x0.clone();
        let t = Instant::now();
        let r = asys
            .solve_angle(&mut x, AngleMethod::Cg, &opts, &mut scratch)
            .unwrap();
        println!(
            "  cg (reference)  {:>6} iterations, residual {:.2e}, converged {} ({:.2} s)",
            r.iterations,
            r.residual,
            r.converged,
            t.elapsed().as_secs_f64()
        );
        let reference = x;
        for omega in [1.0, 1.7, 1.8, 1.85, 1.9, 1.95, 1.97, 1.98, 1.99] {
            let mut x = x0.clone();
            let t = Instant::now();
            let r = asys
                .solve_angle_sor(&mut x, omega, &opts, &mut scratch)
                .unwrap();
            let diff = x
                .iter()
                .flatten()
                .zip(reference.iter().flatten())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            println!(
                "  sor omega {omega:<5} {:>6} sweeps, residual {:.2e}, converged {}, max |x - x_cg| {diff:.1e} ({:.2} s)",
                r.iterations,
                r.residual,
                r.converged,
                t.elapsed().as_secs_f64()
            );
        }
    };
    let inv = naca_triangulated(&AirfoilGrid::inviscid()).unwrap();
    let vis = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
    run("inviscid triangles (demo)", &inv, false);
    run("viscous hybrid + diagonals (demo)", &vis, true);
    let og = naca_ogrid(&AirfoilGrid::viscous()).unwrap();
    run("viscous O-grid + diagonals (demo)", &og, true);
    if std::env::args().nth(2).as_deref() == Some("more") {
        let tiny = naca_hybrid(&AirfoilGrid::tiny()).unwrap();
        run("tiny hybrid + diagonals", &tiny, true);
        let big = naca_hybrid(&AirfoilGrid::preset_20k()).unwrap();
        run("20k hybrid + diagonals", &big, true);
    }
}

fn main() {
    let what = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    if what == "cg" || what == "all" {
        cg();
    }
    if what == "structured" || what == "all" {
        structured();
    }
    if what == "graph" || what == "all" {
        graph();
    }
    if what == "update" || what == "all" {
        update();
    }
    if what == "angle-sor" || what == "all" {
        angle_sor();
    }
}
