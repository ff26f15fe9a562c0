//! Linear elasticity (issue 28 item 4): assembly + rigid-mode multigrid setup + CG solve of
//! the kernel's elasticity on a jittered square of P1 triangles and a jittered cube of Q1
//! hexahedra, inverse-volume moduli, ν = 0.3, relative residual 1e-8. The meshes, the
//! boundary data and the kernel's solution go to `DIR/elastic{2,3}d_*` for
//! `bench/peers/elasticity.py` (scikit-fem assembly + pyamg `smoothed_aggregation_solver(A,
//! B=rigid_modes)` on the same mesh).

use std::path::Path;
use std::time::Instant;

use deform_kernel::elasticity::{
    assemble, cell_moduli, elastic_rigid_amg_scratch_len, elasticity_graph, elasticity_graph_len,
    ElasticSystem, Modulus,
};
use deform_kernel::spring::{AmgHierarchy, AmgOptions, RigidAmg, SolveOptions, SpringSystem};
use deform_kernel::{CellKind, Cells, Graph};

use crate::{lcg, write_f64, write_u32, Figures};

/// A mesh with its Dirichlet data: every boundary node fixed, the bottom side moved.
struct Problem<const D: usize> {
    points: Vec<[f64; D]>,
    /// Nodes of each cell (`D + 1` for triangles, 8 for hexahedra), flat.
    nodes: Vec<u32>,
    per_cell: usize,
    kind: CellKind,
    fixed: Vec<u8>,
    disp: Vec<[f64; D]>,
}

/// `n × n` nodes on the unit square, interior jittered by ±0.2 cell, two triangles a cell;
/// the bottom edge moves by `(0.02, 0.05) sin(πx)`.
fn square(n: usize) -> Problem<2> {
    let h = 1.0 / (n - 1) as f64;
    let mut s = 11u64;
    let mut points = Vec::with_capacity(n * n);
    let (mut fixed, mut disp) = (vec![0u8; n * n], vec![[0.0; 2]; n * n]);
    for j in 0..n {
        for i in 0..n {
            let edge = i == 0 || j == 0 || i == n - 1 || j == n - 1;
            let a = if edge { 0.0 } else { 0.2 * h };
            let p = [
                i as f64 * h + a * lcg(&mut s),
                j as f64 * h + a * lcg(&mut s),
            ];
            let k = i + n * j;
            fixed[k] = edge as u8;
            if j == 0 {
                let b = (std::f64::consts::PI * p[0]).sin();
                disp[k] = [0.02 * b, 0.05 * b];
            }
            points.push(p);
        }
    }
    let mut nodes = Vec::with_capacity(6 * (n - 1) * (n - 1));
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (i + n * j) as u32;
            let (b, c, d) = (a + 1, a + 1 + n as u32, a + n as u32);
            nodes.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    Problem {
        points,
        nodes,
        per_cell: 3,
        kind: CellKind::Triangle,
        fixed,
        disp,
    }
}

/// `n³` nodes on the unit cube, interior jittered by ±0.2 cell, hexahedra; the bottom face
/// moves by `(0.02, 0.01, 0.05) sin(πx) sin(πy)`.
fn cube(n: usize) -> Problem<3> {
    let h = 1.0 / (n - 1) as f64;
    let mut s = 13u64;
    let mut points = Vec::with_capacity(n * n * n);
    let (mut fixed, mut disp) = (vec![0u8; n * n * n], vec![[0.0; 3]; n * n * n]);
    let pi = std::f64::consts::PI;
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let edge = [i, j, k].iter().any(|&x| x == 0 || x == n - 1);
                let a = if edge { 0.0 } else { 0.2 * h };
                let p = [i, j, k].map(|x| x as f64 * h + a * lcg(&mut s));
                let id = i + n * (j + n * k);
                fixed[id] = edge as u8;
                if k == 0 {
                    let b = (pi * p[0]).sin() * (pi * p[1]).sin();
                    disp[id] = [0.02 * b, 0.01 * b, 0.05 * b];
                }
                points.push(p);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (i + n * (j + n * k)) as u32;
    let mut nodes = Vec::with_capacity(8 * (n - 1).pow(3));
    for k in 0..n - 1 {
        for j in 0..n - 1 {
            for i in 0..n - 1 {
                nodes.extend_from_slice(&[
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    Problem {
        points,
        nodes,
        per_cell: 8,
        kind: CellKind::Hexahedron,
        fixed,
        disp,
    }
}

/// Seconds of each phase of one run, and what the solve reported.
struct Run<const D: usize> {
    assembly: f64,
    setup: f64,
    solve: f64,
    iterations: usize,
    residual: f64,
    levels: usize,
    solution: Vec<[f64; D]>,
}

/// Graph, moduli and assembly; then the rigid-mode hierarchy and the solve, timed apart.
fn run<const D: usize>(p: &Problem<D>) -> Run<D> {
    let n = p.points.len();
    let nc = p.nodes.len() / p.per_cell;
    let offsets: Vec<u32> = (0..=nc).map(|c| (c * p.per_cell) as u32).collect();
    let kinds = vec![p.kind.vtk_code(); nc];
    let cells = Cells::new(n, &offsets, &p.nodes, &kinds).expect("cells");
    let t = Instant::now();
    let mut go = vec![0u32; n + 1];
    let mut gt = vec![0u32; elasticity_graph_len(&cells)];
    let used = elasticity_graph(&cells, &mut go, &mut gt).expect("graph");
    gt.truncate(used);
    let graph = Graph::new(&go, &gt).expect("graph");
    let mut moduli = vec![0.0; nc];
    cell_moduli(&cells, &p.points, Modulus::InverseVolume, None, &mut moduli).expect("moduli");
    let (mut diag, mut off) = (vec![[[0.0; D]; D]; n], vec![[[0.0; D]; D]; used]);
    assemble(&cells, &p.points, &graph, &moduli, 0.3, &mut diag, &mut off).expect("assembly");
    let sys = ElasticSystem::new(graph, &diag, &off, &p.fixed).expect("system");
    let assembly = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let w = vec![1.0; used];
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(graph, &w, &p.fixed, &mut anchor).expect("spring");
    let opts = AmgOptions {
        max_coarse: 64,
        ..AmgOptions::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = RigidAmg::setup_len(&spring, D, &opts, &mut work).expect("sizes");
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![0.0; sizes.values]);
    let h = sys
        .rigid_amg(
            &spring,
            &p.points,
            &opts,
            &mut work,
            &mut index,
            &mut values,
        )
        .expect("hierarchy");
    let setup = t.elapsed().as_secs_f64();
    let stop = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 10_000,
        update_tol: 0.0,
    };
    let mut u = p.disp.clone();
    let len = elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, D).expect("scratch");
    let mut scratch = vec![[0.0; D]; len];
    let t = Instant::now();
    let r = sys
        .solve_rigid_amg(&h, &mut u, &stop, &mut scratch)
        .expect("solve");
    let solve = t.elapsed().as_secs_f64();
    assert!(r.converged, "elasticity AMG-CG did not converge");
    Run {
        assembly,
        setup,
        solve,
        iterations: r.iterations,
        residual: r.residual,
        levels: sizes.levels,
        solution: u,
    }
}

/// The median run (by total time) of `reps`, its figures under `tag`, and the inputs and the
/// solution for the peer.
fn measure<const D: usize>(p: &Problem<D>, tag: &str, reps: usize, dir: &Path, fig: &mut Figures) {
    let n = p.points.len();
    println!(
        "elasticity {tag}: {n} nodes, {} cells",
        p.nodes.len() / p.per_cell
    );
    let mut runs: Vec<Run<D>> = (0..reps.max(1)).map(|_| run(p)).collect();
    runs.sort_by(|a, b| {
        (a.assembly + a.setup + a.solve).total_cmp(&(b.assembly + b.setup + b.solve))
    });
    let r = runs.swap_remove(runs.len() / 2);
    fig.put(&format!("{tag}_nodes"), n);
    fig.put(&format!("{tag}_assembly_s"), r.assembly);
    fig.put(&format!("{tag}_amg_setup_s"), r.setup);
    fig.put(&format!("{tag}_solve_s"), r.solve);
    fig.put(&format!("{tag}_iterations"), r.iterations);
    fig.put(&format!("{tag}_residual"), r.residual);
    fig.put(&format!("{tag}_levels"), r.levels);
    let file = |s: &str| dir.join(format!("{tag}_{s}"));
    std::fs::write(file("dims"), format!("{n} {D} {}\n", p.per_cell)).expect("write dims");
    write_f64(&file("points.f64"), p.points.iter().flatten().copied());
    write_u32(&file("cells.u32"), &p.nodes);
    let fixed: Vec<u32> = p.fixed.iter().map(|&f| u32::from(f)).collect();
    write_u32(&file("fixed.u32"), &fixed);
    write_f64(&file("disp.f64"), p.disp.iter().flatten().copied());
    write_f64(&file("solution.f64"), r.solution.iter().flatten().copied());
}

/// Both meshes: `n2²` nodes in 2D, `n3³` in 3D.
pub fn elasticity(n2: usize, n3: usize, reps: usize, dir: &Path, fig: &mut Figures) {
    measure(&square(n2), "elastic2d", reps, dir, fig);
    measure(&cube(n3), "elastic3d", reps, dir, fig);
}
