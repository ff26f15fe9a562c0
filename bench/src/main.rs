//! The kernel side of `cargo xtask bench` (issue 14 item 9): the problems at the
//! issue's sizes, timed here, with their inputs written for the Python peers
//! (`bench/peers/peers.py`) so both sides solve the very same problem in the same run.
//!
//! `cargo run --release --manifest-path bench/Cargo.toml -- --out DIR [--quick] [--only a,b]
//! [--reps N]` (`--reps`: runs of each sensitivity row)
//! (`--only` picks among graph, structured, spring, rotation, elasticity, rbf, sensitivity,
//! sensitivity-spring, sensitivity-quaternion; with sensitivity-default or sensitivity-theta0
//! only that hierarchy's sensitivity rows, with sensitivity-pitch or sensitivity-shape only
//! that motion's)
//!
//! Writes `DIR/kernel.txt` (`name value` lines: the figures) and raw little-endian inputs and
//! results (`*.f64`, `*.u32`, plus `*.dims` text files) that peers.py reads back. Speed is
//! measured here, never asserted anywhere.

use std::fmt::Write as _;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, solve_linear_scratch_len, AmgHierarchy,
    AmgOptions, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::taubin::{
    smooth_graph, smooth_structured, GraphOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Block, CellKind, Cells, Graph, Quat};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

mod elasticity;
mod rbf;
mod reductions;
mod sensitivity;

/// Sizes of one run.
struct Sizes {
    torus: [usize; 2],
    cube: usize,
    airfoil: [usize; 2],
    rotations: usize,
    repeats: usize,
    /// Nodes per side of the elasticity square (2D) and cube (3D).
    elastic: [usize; 2],
    /// The RBF row's NACA mesh (every boundary node a centre: the evaluation is `N · B`).
    rbf_airfoil: [usize; 2],
}

const FULL: Sizes = Sizes {
    torus: [1000, 1000],
    cube: 256,
    airfoil: [1024, 229],
    rotations: 10_000_000,
    repeats: 5,
    elastic: [450, 59],
    rbf_airfoil: [512, 160],
};

const QUICK: Sizes = Sizes {
    torus: [200, 100],
    cube: 64,
    airfoil: [256, 80],
    rotations: 1_000_000,
    repeats: 3,
    elastic: [60, 14],
    rbf_airfoil: [256, 80],
};

/// Taubin iterations per filter run: 10 λ|μ iterations = 20 passes, as in the issue.
const TAUBIN_ITERATIONS: usize = 10;

/// The median of `reps` timings of `f` (seconds), after one untimed warm-up run.
fn median<F: FnMut()>(reps: usize, mut f: F) -> f64 {
    f();
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// Deterministic values in [-1, 1) (benchmark data only).
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

fn write_f64(path: &Path, v: impl IntoIterator<Item = f64>) {
    let bytes: Vec<u8> = v.into_iter().flat_map(f64::to_le_bytes).collect();
    std::fs::write(path, bytes).expect("write benchmark input");
}

fn write_u32(path: &Path, v: &[u32]) {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(path, bytes).expect("write benchmark input");
}

/// Collects the `name value` lines of kernel.txt.
struct Figures(String);

impl Figures {
    fn put(&mut self, name: &str, value: impl std::fmt::Display) {
        println!("  {name} = {value}");
        let _ = writeln!(self.0, "{name} {value}");
    }
}

/// A closed triangulated torus of `nu × nv` vertices (every vertex has six neighbours).
fn torus(nu: usize, nv: usize) -> (Vec<[f64; 3]>, Vec<u32>) {
    let (r_major, r_minor) = (1.0, 0.35);
    let mut points = Vec::with_capacity(nu * nv);
    let mut s = 7u64;
    for j in 0..nv {
        let v = std::f64::consts::TAU * j as f64 / nv as f64;
        for i in 0..nu {
            let u = std::f64::consts::TAU * i as f64 / nu as f64;
            let r = r_minor * (1.0 + 0.05 * lcg(&mut s));
            let w = r_major + r * v.cos();
            points.push([w * u.cos(), w * u.sin(), r * v.sin()]);
        }
    }
    let id = |i: usize, j: usize| ((i % nu) + nu * (j % nv)) as u32;
    let mut tris = Vec::with_capacity(6 * nu * nv);
    for j in 0..nv {
        for i in 0..nu {
            tris.extend_from_slice(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.extend_from_slice(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (points, tris)
}

fn graph_taubin(sz: &Sizes, dir: &Path, fig: &mut Figures) {
    let [nu, nv] = sz.torus;
    let (points, tris) = torus(nu, nv);
    let n = points.len();
    let tri_count = tris.len() / 3;
    let offsets_c: Vec<u32> = (0..=tri_count).map(|c| (3 * c) as u32).collect();
    let kinds = vec![CellKind::Triangle.vtk_code(); tri_count];
    let cells = Cells::new(n, &offsets_c, &tris, &kinds).expect("torus cells");
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).expect("graph");
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).expect("graph");
    println!(
        "graph Taubin: torus {nu} × {nv} = {n} vertices, {} directed edges",
        g.edge_count()
    );
    let mut values = points.clone();
    let mut scratch = vec![[0.0f64; 3]; n];
    let t = median(sz.repeats, || {
        values.copy_from_slice(&points);
        // The report is kept (as `deform smooth` prints it), so the filter computes its
        // largest change as a user's call does.
        let report = smooth_graph(
            &g,
            &mut values,
            TaubinParams::paper(),
            TAUBIN_ITERATIONS,
            &GraphOptions::default(),
            &mut scratch,
        )
        .expect("smooth_graph");
        black_box((&values, report));
    });
    let passes = 2 * TAUBIN_ITERATIONS;
    fig.put("graph_vertices", n);
    fig.put("graph_passes", passes);
    fig.put("graph_ns_per_vertex_pass", t * 1e9 / (passes * n) as f64);
    write_u32(&dir.join("graph_offsets.u32"), &offsets);
    write_u32(&dir.join("graph_targets.u32"), &targets);
    write_u32(&dir.join("graph_triangles.u32"), &tris);
    write_f64(
        &dir.join("graph_points.f64"),
        points.iter().flatten().copied(),
    );
    write_f64(
        &dir.join("graph_result.f64"),
        values.iter().flatten().copied(),
    );
}

fn structured_taubin(sz: &Sizes, dir: &Path, fig: &mut Figures) {
    let n = sz.cube;
    let block = Block::new([n, n, n]).expect("block");
    let mut s = 1u64;
    let field0: Vec<f64> = (0..block.point_count()).map(|_| lcg(&mut s)).collect();
    let mut field = field0.clone();
    let mut scratch = vec![0.0f64; block.point_count()];
    println!("structured Taubin: {n}³ f64 field");
    let t = median(sz.repeats, || {
        field.copy_from_slice(&field0);
        smooth_structured(
            &block,
            &mut field,
            TaubinParams::paper(),
            TAUBIN_ITERATIONS,
            &StructuredOptions::default(),
            &mut scratch,
        )
        .expect("smooth_structured");
        black_box(&field);
    });
    let passes = 2 * TAUBIN_ITERATIONS;
    fig.put("structured_points", block.point_count());
    fig.put("structured_passes", passes);
    fig.put(
        "structured_ns_per_point_pass",
        t * 1e9 / (passes * block.point_count()) as f64,
    );
    std::fs::write(dir.join("structured.dims"), format!("{n} {n} {n}\n")).expect("write");
    write_f64(&dir.join("structured_field.f64"), field0.iter().copied());
    write_f64(&dir.join("structured_result.f64"), field.iter().copied());
}

fn spring(sz: &Sizes, dir: &Path, fig: &mut Figures) {
    let [surface, radial] = sz.airfoil;
    let grid = AirfoilGrid {
        surface_points: surface,
        radial_points: radial,
        first_layer: 1e-5,
        boundary_layers: 40,
        ..AirfoilGrid::default()
    };
    let mesh = naca_triangulated(&grid).expect("mesh");
    let n = mesh.node_count();
    let cells = mesh.cells().expect("cells");
    let t_setup = Instant::now();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).expect("graph");
    targets.truncate(used);
    let g = Graph::new(&offsets, &targets).expect("graph");
    let mut k = vec![0.0f64; g.edge_count()];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).expect("stiffness");
    let fixed = mesh.boundary_mask();
    let mut s = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut s).expect("system");
    let t_graph = t_setup.elapsed().as_secs_f64();
    let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0)
        .expect("rotation");
    let x0: Vec<[f64; 2]> = rot.to_field(n);
    println!(
        "spring solve: NACA 2412 {surface} × {radial} = {n} nodes, {} directed edges",
        g.edge_count()
    );
    let opts = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 100_000,
        update_tol: 0.0,
    };
    // AMG-preconditioned CG (the default of `deform move`): setup + solve of both components.
    let amg_opts = AmgOptions::default();
    let mut x = x0.clone();
    let mut iterations = 0;
    let (mut t_amg_setup, mut t_amg_solve) = (Vec::new(), Vec::new());
    for _ in 0..sz.repeats.min(3) {
        let t = Instant::now();
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
        let sizes = AmgHierarchy::setup_len(&sys, &amg_opts, &mut work).expect("amg sizes");
        let mut index = vec![0u32; sizes.index];
        let mut values = vec![0.0f64; sizes.values];
        let h = AmgHierarchy::setup(&sys, &amg_opts, &mut work, &mut index, &mut values)
            .expect("amg setup");
        drop(work);
        t_amg_setup.push(t.elapsed().as_secs_f64());
        x.copy_from_slice(&x0);
        let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(&h)];
        let t = Instant::now();
        let rep = sys
            .solve_linear_amg(&h, &mut x, &opts, &mut scratch)
            .expect("amg solve");
        t_amg_solve.push(t.elapsed().as_secs_f64());
        assert!(rep.converged, "AMG-CG did not converge");
        iterations = rep.iterations;
    }
    let med = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    fig.put("spring_nodes", n);
    fig.put("spring_graph_stiffness_s", t_graph);
    fig.put("spring_amg_iterations", iterations);
    fig.put("spring_amg_setup_s", med(&mut t_amg_setup));
    fig.put("spring_amg_solve_s", med(&mut t_amg_solve));
    // CG + Jacobi, once (it takes seconds).
    let m = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut y = x0.clone();
    let mut scratch = vec![[0.0f64; 2]; solve_linear_scratch_len(&m, n)];
    let t = Instant::now();
    let rep = sys
        .solve_linear(&mut y, m, &opts, &mut scratch)
        .expect("cg");
    let t_cg = t.elapsed().as_secs_f64();
    fig.put("spring_cg_jacobi_iterations", rep.iterations);
    fig.put("spring_cg_jacobi_s", t_cg);
    // What the exact sums cost of one of those iterations (issue 27 item 6).
    let iteration_s = t_cg / rep.iterations.max(1) as f64;
    reductions::cost(&y, &x, &x0, iteration_s, sz.repeats, fig);
    // The free-node system for the peers: K_ff u_f = −K_fb u_b per component (CSR, sorted
    // columns), and the kernel's solution of it.
    let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
    let mut pos = vec![u32::MAX; n];
    for (p, &i) in free.iter().enumerate() {
        pos[i] = p as u32;
    }
    let (mut indptr, mut indices, mut data, mut rhs) = (vec![0u32], vec![], vec![], vec![]);
    for &i in &free {
        let (mut d, mut b) = (0.0, [0.0; 2]);
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
            data.push(v);
        }
        indptr.push(indices.len() as u32);
        rhs.extend_from_slice(&b);
    }
    fig.put("spring_free_unknowns", free.len());
    write_u32(&dir.join("spring_indptr.u32"), &indptr);
    write_u32(&dir.join("spring_indices.u32"), &indices);
    write_f64(&dir.join("spring_data.f64"), data);
    write_f64(&dir.join("spring_rhs.f64"), rhs);
    write_f64(
        &dir.join("spring_solution.f64"),
        free.iter().flat_map(|&i| x[i]),
    );
}

fn rotations(sz: &Sizes, fig: &mut Figures) {
    let n = sz.rotations;
    let mut s = 3u64;
    let points: Vec<[f64; 3]> = (0..n)
        .map(|_| [lcg(&mut s), lcg(&mut s), lcg(&mut s)])
        .collect();
    let quats: Vec<Quat<f64>> = (0..n)
        .map(|_| {
            Quat::from_array([lcg(&mut s), lcg(&mut s), lcg(&mut s), lcg(&mut s)])
                .normalize()
                .unwrap_or(Quat::identity())
        })
        .collect();
    println!("rotations: {n} points, one unit quaternion each");
    let mut out = vec![[0.0f64; 3]; n];
    let t = median(sz.repeats, || {
        for ((o, p), q) in out.iter_mut().zip(&points).zip(&quats) {
            *o = q.rotate(*p);
        }
        black_box(&out);
    });
    fig.put("rotation_points", n);
    fig.put("rotation_kernel_ns_per_point", t * 1e9 / n as f64);
    // nalgebra, the Rust peer: UnitQuaternion * Vector3 on the same inputs.
    let nq: Vec<nalgebra::UnitQuaternion<f64>> = quats
        .iter()
        .map(|q| {
            let [w, x, y, z] = q.to_array();
            nalgebra::UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(w, x, y, z))
        })
        .collect();
    let np: Vec<nalgebra::Vector3<f64>> = points
        .iter()
        .map(|p| nalgebra::Vector3::new(p[0], p[1], p[2]))
        .collect();
    let mut nout = vec![nalgebra::Vector3::zeros(); n];
    let t = median(sz.repeats, || {
        for ((o, p), q) in nout.iter_mut().zip(&np).zip(&nq) {
            *o = q * p;
        }
        black_box(&nout);
    });
    fig.put("rotation_nalgebra_ns_per_point", t * 1e9 / n as f64);
    let diff = out
        .iter()
        .zip(&nout)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0, f64::max);
    fig.put("rotation_max_difference_to_nalgebra", format!("{diff:e}"));
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let quick = args.iter().any(|a| a == "--quick");
    let dir = args
        .iter()
        .position(|a| a == "--out")
        .and_then(|i| args.get(i + 1))
        .map_or_else(|| PathBuf::from("target/bench"), PathBuf::from);
    let only: Vec<&str> = args
        .iter()
        .position(|a| a == "--only")
        .and_then(|i| args.get(i + 1))
        .map(|s| s.split(',').collect())
        .unwrap_or_default();
    // `--reps N`: runs of each sensitivity row (default 3; 1 for a full-size callgrind run).
    let reps: Option<usize> = args
        .iter()
        .position(|a| a == "--reps")
        .and_then(|i| args.get(i + 1))
        .map(|s| s.parse().expect("--reps N"));
    std::fs::create_dir_all(&dir).expect("create the output directory");
    let sz = if quick { &QUICK } else { &FULL };
    let mut fig = Figures(String::new());
    fig.put("quick", quick);
    let want = |c: &str| only.is_empty() || only.contains(&c);
    if want("graph") {
        graph_taubin(sz, &dir, &mut fig);
    }
    if want("structured") {
        structured_taubin(sz, &dir, &mut fig);
    }
    if want("spring") {
        spring(sz, &dir, &mut fig);
    }
    if want("rotation") {
        rotations(sz, &mut fig);
    }
    if want("elasticity") {
        let [n2, n3] = sz.elastic;
        elasticity::elasticity(n2, n3, sz.repeats.min(3), &dir, &mut fig);
    }
    if want("rbf") {
        rbf::rbf(sz.rbf_airfoil, if quick { 3 } else { 1 }, &dir, &mut fig);
    }
    // `sensitivity-spring` / `sensitivity-quaternion`: one method's rows (one callgrind run each);
    // `sensitivity-default` / `sensitivity-theta0`: one hierarchy's, `sensitivity-pitch` /
    // `sensitivity-shape` one motion's (both when neither).
    let pick = |a: &str, b: &str| match (only.contains(&a), only.contains(&b)) {
        (false, false) => [true, true],
        (x, y) => [x, y],
    };
    let which = sensitivity::Which {
        methods: [
            want("sensitivity") || only.contains(&"sensitivity-spring"),
            want("sensitivity") || only.contains(&"sensitivity-quaternion"),
        ],
        hierarchies: pick("sensitivity-default", "sensitivity-theta0"),
        motions: pick("sensitivity-pitch", "sensitivity-shape"),
    };
    if which.methods.contains(&true) {
        let reps = reps.unwrap_or(sz.repeats.min(3));
        sensitivity::sensitivity(sz.airfoil, reps, &which, &mut fig);
    }
    std::fs::write(dir.join("kernel.txt"), &fig.0).expect("write kernel.txt");
}
