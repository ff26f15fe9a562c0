//! Iteration counts of every spring solver on the ~20k-node NACA 2412 mesh (meshgen's
//! `preset_20k`, triangulated and hybrid) with the airfoil rotated 10° about the quarter chord,
//! to relative residual 1e-10.
//!
//! `cargo run --release -p deform-host-tests --example spring_iterations [-- linear|angle|probe]`

use std::time::Instant;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_scratch_len, AngleMethod, AngleSystem, LinearMethod,
    Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_hybrid, naca_triangulated, rotate_markers2, AirfoilGrid, Mesh2};

fn run(label: &str, mesh: &Mesh2, diagonals: bool, linear: bool, angle: bool, what: &str) {
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
    let rot = rotate_markers2(mesh, &["airfoil"], AirfoilGrid::quarter_chord(), 10.0).unwrap();
    let x0 = rot.to_field(n);
    println!(
        "\n{label}: {n} nodes, {} directed edges, {} fixed",
        g.edge_count(),
        fixed.iter().filter(|&&f| f != 0).count()
    );
    let opts = SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 2_000_000,
        update_tol: 0.0,
    };
    let methods: [(&str, LinearMethod<f64>); 7] = [
        ("linear Jacobi", LinearMethod::Jacobi),
        ("linear Gauss-Seidel", LinearMethod::GaussSeidel),
        ("linear SOR 1.9", LinearMethod::Sor { omega: 1.9 }),
        (
            "linear CG",
            LinearMethod::Cg {
                preconditioner: Preconditioner::None,
            },
        ),
        (
            "linear CG+Jacobi",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            },
        ),
        (
            "linear CG+SSOR 1.0",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.0 },
            },
        ),
        (
            "linear CG+SSOR 1.5",
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.5 },
            },
        ),
    ];
    for (name, m) in methods.into_iter().filter(|_| linear) {
        let mut x = x0.clone();
        let mut scratch = vec![[0.0; 2]; solve_linear_scratch_len(&m, n)];
        let t = Instant::now();
        let rep = sys.solve_linear(&mut x, m, &opts, &mut scratch).unwrap();
        println!(
            "  {name:24} iterations {:>8}  residual {:.2e}  converged {}  ({:.2} s)",
            rep.iterations,
            rep.residual,
            rep.converged,
            t.elapsed().as_secs_f64()
        );
    }
    for eps in [0.01, 0.0].into_iter().filter(|_| angle) {
        let asys = match AngleSystem::new(sys, &mesh.points, eps) {
            Ok(a) => a,
            Err(e) => {
                println!("  angle eps={eps}: {e}");
                continue;
            }
        };
        let mut probe = vec![[0.0; 2]; asys.angle_probe_scratch_len()];
        let t = Instant::now();
        match asys.angle_rigidity_probe(&opts, &mut probe) {
            Ok(s) => println!(
                "  angle eps={eps:<5} rigidity probe amplification {s:.3e} ({:.2} s)",
                t.elapsed().as_secs_f64()
            ),
            Err(e) => println!(
                "  angle eps={eps:<5} rigidity probe: {e} ({:.2} s)",
                t.elapsed().as_secs_f64()
            ),
        }
        for m in [
            AngleMethod::Cg,
            AngleMethod::DirectJacobi,
            AngleMethod::DirectGaussSeidel,
        ]
        .into_iter()
        .filter(|_| what != "probe")
        {
            let mut x = x0.clone();
            let mut scratch = vec![[0.0; 2]; asys.angle_scratch_len(m)];
            let t = Instant::now();
            // The direct (node-wise) methods converge slowly on this mesh: capped at 20 000
            // sweeps to keep the run short (Gauss–Seidel needed 109 031 sweeps with ε = 0.01 on
            // the triangulated mesh in a capped-at-200 000 run).
            let o = SolveOptions {
                max_iterations: if m == AngleMethod::Cg {
                    100_000
                } else {
                    20_000
                },
                ..opts
            };
            match asys.solve_angle(&mut x, m, &o, &mut scratch) {
                Ok(rep) => println!(
                    "  angle eps={eps:<5} {m:?}: iterations {:>8}  residual {:.2e}  converged {}  ({:.2} s)",
                    rep.iterations, rep.residual, rep.converged, t.elapsed().as_secs_f64()
                ),
                Err(e) => println!("  angle eps={eps:<5} {m:?}: error {e} ({:.2} s)", t.elapsed().as_secs_f64()),
            }
        }
    }
}

fn main() {
    // `spring_iterations [linear|angle|probe|all]` (default all).
    let what = std::env::args().nth(1).unwrap_or_else(|| "all".to_string());
    let (linear, angle) = (what == "all" || what == "linear", what != "linear");
    let grid = AirfoilGrid::preset_20k();
    let tri = naca_triangulated(&grid).unwrap();
    let hyb = naca_hybrid(&grid).unwrap();
    let w = what.as_str();
    run(
        "NACA 2412 triangulated (preset_20k)",
        &tri,
        false,
        linear,
        angle,
        w,
    );
    run(
        "NACA 2412 hybrid (preset_20k)",
        &hyb,
        false,
        linear,
        angle,
        w,
    );
    run(
        "NACA 2412 hybrid + quad diagonals",
        &hyb,
        true,
        linear,
        angle,
        w,
    );
    if what == "probe" {
        let inv = naca_triangulated(&AirfoilGrid::inviscid()).unwrap();
        let vis = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
        run("inviscid preset", &inv, false, false, true, w);
        run("viscous preset", &vis, false, false, true, w);
        run("viscous preset + diagonals", &vis, true, false, true, w);
    }
}
