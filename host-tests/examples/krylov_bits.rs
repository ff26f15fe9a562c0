//! Every conjugate-gradient solve of the spring module on one small airfoil mesh, printed as
//! report and FNV-1a hash of the values: a before/after bit check for changes to the Krylov
//! core, and a small workload for `valgrind --tool=callgrind` instruction counts.
//!
//! `cargo run --release -p deform-host-tests --example krylov_bits [-- cg|amg|all]`

use deform_kernel::spring::constraints::{Constraints, NodeKind};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_amg_scratch_len, solve_linear_scratch_len,
    solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AngleMethod, AngleSystem,
    LinearMethod, LinearSolver, Preconditioner, SolveOptions, SolveReport, SpringSystem,
    DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

/// FNV-1a over the values' bits.
fn hash(v: &[[f64; 2]]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in v.iter().flatten().flat_map(|x| x.to_bits().to_le_bytes()) {
        h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn show(name: &str, r: Result<SolveReport<f64>, deform_kernel::Error>, v: &[[f64; 2]]) {
    match r {
        Ok(r) => println!(
            "{name:22} it {:4} res {:e} upd {:e} conv {} hash {:016x}",
            r.iterations,
            r.residual,
            r.max_update,
            r.converged,
            hash(v)
        ),
        Err(e) => println!("{name:22} error {e:?}"),
    }
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    let grid = AirfoilGrid {
        surface_points: 128,
        radial_points: 40,
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
    let opts = SolveOptions {
        max_iterations: 400,
        residual_tol: 1e-10,
        update_tol: 0.0,
    };
    println!("{n} nodes");
    if which == "cg" || which == "all" {
        for (name, pre) in [
            ("cg none", Preconditioner::None),
            ("cg jacobi", Preconditioner::Jacobi),
            ("cg ssor", Preconditioner::Ssor { omega: 1.2 }),
        ] {
            let m = LinearMethod::Cg {
                preconditioner: pre,
            };
            let mut scratch = vec![[0.0f64; 2]; solve_linear_scratch_len(&m, n)];
            let mut x = x0.clone();
            let r = sys.solve_linear(&mut x, m, &opts, &mut scratch);
            show(name, r, &x);
        }
    }
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &AmgOptions::default(), &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut vals = vec![0.0f64; sizes.values];
    let h = AmgHierarchy::setup(
        &sys,
        &AmgOptions::default(),
        &mut work,
        &mut index,
        &mut vals,
    )
    .unwrap();
    if which == "amg" || which == "all" {
        let mut scratch = vec![[0.0f64; 2]; solve_linear_amg_scratch_len(&h)];
        let mut x = x0.clone();
        let r = sys.solve_linear_amg(&h, &mut x, &opts, &mut scratch);
        show("amg-cg", r, &x);
    }
    if which != "all" {
        return;
    }
    for eps in [DEFAULT_ANGLE_EPSILON, 0.0] {
        let a = AngleSystem::new(sys, &mesh.points, eps).unwrap();
        let opts = SolveOptions {
            max_iterations: if eps == 0.0 { 4000 } else { 400 },
            ..opts
        };
        let mut scratch = vec![[0.0f64; 2]; a.angle_scratch_len(AngleMethod::Cg)];
        let mut x = x0.clone();
        let r = a.solve_angle(&mut x, AngleMethod::Cg, &opts, &mut scratch);
        show(&format!("angle cg eps {eps}"), r, &x);
        let mut scratch = vec![[0.0f64; 2]; a.angle_amg_scratch_len(&h)];
        let mut x = x0.clone();
        let r = a.solve_angle_amg(&h, &mut x, &opts, &mut scratch);
        show(&format!("angle amg eps {eps}"), r, &x);
        let mut probe = vec![[0.0f64; 2]; a.angle_probe_scratch_len()];
        match a.angle_rigidity_probe(&opts, &mut probe) {
            Ok(s) => println!("probe eps {eps:22} {:016x}", s.to_bits()),
            Err(e) => println!("probe eps {eps:22} error {e:?}"),
        }
    }
    // Sliding: the far field slides along its circle (a line with the radial normal).
    let far = &mesh.marker("farfield").unwrap().node_list;
    let mut kinds: Vec<u8> = fixed.clone();
    let mut dirs = vec![[0.0f64; 2]; n];
    for &i in far {
        let i = i as usize;
        let p = mesh.points[i];
        let l = (p[0] * p[0] + p[1] * p[1]).sqrt();
        kinds[i] = NodeKind::Plane.code();
        dirs[i] = [p[0] / l, p[1] / l];
    }
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = vec![0u8; n];
    c.fixed_mask(&mut mask).unwrap();
    let mut s2 = vec![0u32; n];
    let ssys = SpringSystem::new(g, &k, &mask, &mut s2).unwrap();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&ssys)];
    let sizes = AmgHierarchy::setup_len(&ssys, &AmgOptions::default(), &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut vals = vec![0.0f64; sizes.values];
    let sh = AmgHierarchy::setup(
        &ssys,
        &AmgOptions::default(),
        &mut work,
        &mut index,
        &mut vals,
    )
    .unwrap();
    for (name, solver) in [
        (
            "slide cg jacobi",
            LinearSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            }),
        ),
        (
            "slide cg ssor",
            LinearSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: 1.2 },
            }),
        ),
        ("slide amg", LinearSolver::Amg(&sh)),
    ] {
        let mut scratch = vec![[0.0f64; 2]; solve_linear_sliding_scratch_len(&solver, n)];
        let mut x = x0.clone();
        let r = ssys.solve_linear_sliding(&c, &mut x, solver, &opts, &mut scratch);
        show(name, r, &x);
    }
    let a = AngleSystem::new(ssys, &mesh.points, DEFAULT_ANGLE_EPSILON).unwrap();
    let mut scratch = vec![[0.0f64; 2]; a.solve_angle_sliding_scratch_len(AngleMethod::Cg)];
    let mut x = x0.clone();
    let r = a.solve_angle_sliding(&c, &mut x, AngleMethod::Cg, 1.0, &opts, &mut scratch);
    show("slide angle cg", r, &x);
    let mut scratch = vec![[0.0f64; 2]; a.solve_angle_sliding_amg_scratch_len(&sh)];
    let mut x = x0.clone();
    let r = a.solve_angle_sliding_amg(&c, &mut x, &sh, &opts, &mut scratch);
    show("slide angle amg", r, &x);
}
