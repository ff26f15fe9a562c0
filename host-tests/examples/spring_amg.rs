//! Multigrid-preconditioned CG against CG+Jacobi on meshgen's NACA 2412 meshes (airfoil rotated
//! 10° about the quarter chord), both displacement components together, to relative residual
//! 1e-8: iterations, setup and solve time, hierarchy shape; and the default options on the
//! partition-independent MIS-2 aggregation ([`AmgHierarchy::setup_mis2`], docs/amg.md) with
//! the operator complexity of both.
//!
//! `cargo run --release -p deform-host-tests --example spring_amg [-- 20k|234k|both] [--csr DIR]`
//!
//! `--csr DIR` also writes the free-node matrix and right-hand side (`DIR/<mesh>.{indptr,indices,
//! data,rhs}.txt`, one number a line) so the same system can be handed to pyamg.

use std::io::Write;
use std::time::Instant;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, solve_linear_scratch_len, AmgHierarchy,
    AmgOptions, AmgSmoother, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid, Mesh2};

/// The 234k-node grid (the size of the gmsh mesh pyamg was measured on).
fn grid_234k() -> AirfoilGrid {
    AirfoilGrid {
        surface_points: 1024,
        radial_points: 229,
        first_layer: 1e-5,
        boundary_layers: 40,
        ..AirfoilGrid::default()
    }
}

fn write_lines<T: std::fmt::Display>(path: &str, v: &[T]) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for x in v {
        writeln!(f, "{x}").unwrap();
    }
}

fn run(label: &str, mesh: &Mesh2, csr: Option<&str>) {
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
    println!(
        "\n{label}: {n} nodes, {} directed edges, {} fixed",
        g.edge_count(),
        fixed.iter().filter(|&&f| f != 0).count()
    );
    if let Some(dir) = csr {
        // Free-node matrix (CSR) and right-hand side per component.
        let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
        let mut pos = vec![usize::MAX; n];
        for (p, &i) in free.iter().enumerate() {
            pos[i] = p;
        }
        let (mut indptr, mut indices, mut data, mut rhs) = (vec![0usize], vec![], vec![], vec![]);
        for &i in &free {
            let mut d = 0.0;
            let mut b = [0.0; 2];
            let mut row = vec![];
            for e in offsets[i] as usize..offsets[i + 1] as usize {
                let j = targets[e] as usize;
                d += k[e];
                if fixed[j] != 0 {
                    b[0] += k[e] * x0[j][0];
                    b[1] += k[e] * x0[j][1];
                } else {
                    row.push((pos[j], -k[e]));
                }
            }
            row.push((pos[i], d));
            row.sort_by_key(|r| r.0);
            for (c, v) in row {
                indices.push(c);
                data.push(format!("{v:e}"));
            }
            indptr.push(indices.len());
            rhs.push(format!("{:e} {:e}", b[0], b[1]));
        }
        let base = format!("{dir}/{}", label.split_whitespace().last().unwrap());
        write_lines(&format!("{base}.indptr.txt"), &indptr);
        write_lines(&format!("{base}.indices.txt"), &indices);
        write_lines(&format!("{base}.data.txt"), &data);
        write_lines(&format!("{base}.rhs.txt"), &rhs);
        println!("  wrote {base}.*.txt ({} free unknowns)", free.len());
    }
    let opts = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 100_000,
        update_tol: 0.0,
    };
    let variants = [
        (AmgSmoother::Jacobi, 1usize, 0.0),
        (AmgSmoother::Chebyshev, 2, 0.0),
        (AmgSmoother::Chebyshev, 3, 0.0),
        (AmgSmoother::Chebyshev, 2, 0.08),
        (AmgSmoother::Chebyshev, 2, 0.25),
        (AmgSmoother::Chebyshev, 3, 0.25),
    ];
    for (smoother, sweeps, theta) in variants {
        let amg_opts = AmgOptions {
            smoother,
            sweeps,
            strength_theta: theta,
            ..AmgOptions::default()
        };
        let t = Instant::now();
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
        let sizes = AmgHierarchy::setup_len(&sys, &amg_opts, &mut work).unwrap();
        let t_len = t.elapsed().as_secs_f64();
        let mut index = vec![0u32; sizes.index];
        let mut values = vec![0.0f64; sizes.values];
        let h = AmgHierarchy::setup(&sys, &amg_opts, &mut work, &mut index, &mut values).unwrap();
        let t_setup = t.elapsed().as_secs_f64();
        let shape: Vec<String> = (0..h.levels())
            .map(|l| format!("{}/{}", h.level_size(l), h.level_entries(l)))
            .collect();
        let mut x = x0.clone();
        let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
        let t = Instant::now();
        let rep = sys
            .solve_linear_amg(&h, &mut x, &opts, &mut scratch)
            .unwrap();
        let t_solve = t.elapsed().as_secs_f64();
        println!(
            "  AMG-CG {smoother:?} {sweeps} θ={theta}: iterations {:>5}  residual {:.2e}  converged {}  setup {:.3} s (sizes {:.3} s) solve {:.3} s  levels [{}]  index {} values {}",
            rep.iterations,
            rep.residual,
            rep.converged,
            t_setup,
            t_len,
            t_solve,
            shape.join(", "),
            sizes.index,
            sizes.values
        );
    }
    for mis2 in [false, true] {
        mis2_row(&sys, &x0, &opts, mis2);
    }
    let m = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut x = x0.clone();
    let mut scratch = vec![[0.0; 2]; solve_linear_scratch_len(&m, n)];
    let t = Instant::now();
    let rep = sys.solve_linear(&mut x, m, &opts, &mut scratch).unwrap();
    println!(
        "  CG+Jacobi: iterations {:>5}  residual {:.2e}  converged {}  ({:.3} s)",
        rep.iterations,
        rep.residual,
        rep.converged,
        t.elapsed().as_secs_f64()
    );
}

/// Default options on the greedy (today) or the MIS-2 aggregation: iterations, levels,
/// operator complexity, setup and solve time.
fn mis2_row(sys: &SpringSystem<'_, f64>, x0: &[[f64; 2]], stop: &SolveOptions<f64>, mis2: bool) {
    let opts = AmgOptions::default();
    let t = Instant::now();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
    let mut mwork = vec![0u64; AmgHierarchy::mis2_work_len(sys)];
    let sizes = if mis2 {
        AmgHierarchy::setup_len_mis2(sys, &opts, &mut work, &mut mwork)
    } else {
        AmgHierarchy::setup_len(sys, &opts, &mut work)
    }
    .unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0f64; sizes.values];
    let (w, m, i, v) = (&mut work, &mut mwork, &mut index, &mut values);
    let h = if mis2 {
        AmgHierarchy::setup_mis2(sys, &opts, w, m, i, v)
    } else {
        AmgHierarchy::setup(sys, &opts, w, i, v)
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
    let mut x = x0.to_vec();
    let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
    let t = Instant::now();
    let rep = sys
        .solve_linear_amg(&h, &mut x, stop, &mut scratch)
        .unwrap();
    println!(
        "  AMG-CG default, {} aggregation: iterations {:>4}  converged {}  setup {:.3} s  \
         solve {:.3} s  operator complexity {complexity:.3}  levels [{}]",
        if mis2 { "MIS-2" } else { "greedy" },
        rep.iterations,
        rep.converged,
        t_setup,
        t.elapsed().as_secs_f64(),
        shape.join(", ")
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let what = args.first().cloned().unwrap_or_else(|| "20k".into());
    let csr = args
        .iter()
        .position(|a| a == "--csr")
        .and_then(|p| args.get(p + 1))
        .map(String::as_str);
    if what == "20k" || what == "both" {
        let m = naca_triangulated(&AirfoilGrid::preset_20k()).unwrap();
        run("NACA 2412 triangulated 20k", &m, csr);
    }
    if what == "234k" || what == "both" {
        let m = naca_triangulated(&grid_234k()).unwrap();
        run("NACA 2412 triangulated 234k", &m, csr);
    }
}
