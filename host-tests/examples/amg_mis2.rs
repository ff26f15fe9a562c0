//! The serial AMG-CG solve with today's greedy aggregation against the partition-independent
//! MIS-2 aggregation ([`AmgHierarchy::setup_mis2`]) on meshgen's NACA 2412 meshes (airfoil
//! rotated 10° about the quarter chord), default options, to relative residual 1e-8:
//! iterations, hierarchy shape and operator complexity, setup and solve time.
//!
//! `cargo run --release -p deform-host-tests --example amg_mis2 [-- 20k|234k|both]`

use std::time::Instant;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions, SolveOptions,
    SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid, Mesh2};

/// The 234k-node grid of `cargo xtask bench` and the spring_amg example.
fn grid_234k() -> AirfoilGrid {
    AirfoilGrid {
        surface_points: 1024,
        radial_points: 229,
        first_layer: 1e-5,
        boundary_layers: 40,
        ..AirfoilGrid::default()
    }
}

fn run(label: &str, mesh: &Mesh2) {
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
    let rot = rotate_markers2(mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0).unwrap();
    let x0 = rot.to_field(n);
    println!("\n{label}: {n} nodes, {} directed edges", g.edge_count());
    let stop = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 100_000,
        update_tol: 0.0,
    };
    let opts = AmgOptions::default();
    for mis2 in [false, true] {
        let t = Instant::now();
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
        let mut mwork = vec![0u64; AmgHierarchy::mis2_work_len(&sys)];
        let sizes = if mis2 {
            AmgHierarchy::setup_len_mis2(&sys, &opts, &mut work, &mut mwork)
        } else {
            AmgHierarchy::setup_len(&sys, &opts, &mut work)
        }
        .unwrap();
        let mut index = vec![0u32; sizes.index];
        let mut values = vec![0.0f64; sizes.values];
        let h = if mis2 {
            AmgHierarchy::setup_mis2(&sys, &opts, &mut work, &mut mwork, &mut index, &mut values)
        } else {
            AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values)
        }
        .unwrap();
        let t_setup = t.elapsed().as_secs_f64();
        let shape: Vec<String> = (0..h.levels())
            .map(|l| h.level_size(l).to_string())
            .collect();
        let nnz: usize = (0..h.levels())
            .map(|l| h.level_entries(l) + h.level_size(l))
            .sum();
        let complexity = nnz as f64 / (h.level_entries(0) + h.level_size(0)) as f64;
        let mut x = x0.clone();
        let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
        let t = Instant::now();
        let rep = sys
            .solve_linear_amg(&h, &mut x, &stop, &mut scratch)
            .unwrap();
        println!(
            "  {:<6} iterations {:>4}  converged {}  setup {:.3} s  solve {:.3} s  \
             operator complexity {complexity:.3}  levels [{}]",
            if mis2 { "MIS-2" } else { "greedy" },
            rep.iterations,
            rep.converged,
            t_setup,
            t.elapsed().as_secs_f64(),
            shape.join(", ")
        );
    }
}

fn main() {
    let what = std::env::args().nth(1).unwrap_or_else(|| "20k".into());
    if what == "20k" || what == "both" {
        let m = naca_triangulated(&AirfoilGrid::preset_20k()).unwrap();
        run("NACA 2412 triangulated 20k", &m);
    }
    if what == "234k" || what == "both" {
        let m = naca_triangulated(&grid_234k()).unwrap();
        run("NACA 2412 triangulated 234k", &m);
    }
}
