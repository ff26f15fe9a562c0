//! Per-step cost of the stateless calls against a prepared plan, on meshgen's triangulated
//! NACA 2412 meshes (first layer 1e-5 chords), the airfoil pitching `5° sin(2π s / period)`
//! about the quarter chord, 20 time steps, multigrid-preconditioned CG, relative residual
//! 1e-8.
//!
//! Stateless step: graph check (`Graph::new`), Batina stiffness, `SpringSystem::new`
//! (symmetry, anchoring), hierarchy size query and setup, then the solve from the cold guess
//! (`solve_linear_with` from zero, or `deform_spring_with`), into buffers allocated once.
//! Plan step: `Plan::step` with a warm start. Also: `Plan::sizes` + `Plan::init` once, and
//! `Plan::open` (header and checksum).
//!
//! `cargo run --release -p deform-host-tests --example plan_steps [-- 20k|234k|both] [period]`

use std::time::{Duration, Instant};

use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanSolver, PlanSpec, PlanStiffness, PlanWork,
};
use deform_kernel::quaternion::{
    deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, LinearSolver,
    SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph, Quat};
use deform_meshgen::{naca_triangulated, AirfoilGrid, Mesh2};

const STEPS: usize = 20;

fn grid(label: &str) -> AirfoilGrid {
    match label {
        "234k" => AirfoilGrid {
            surface_points: 1024,
            radial_points: 229,
            first_layer: 1e-5,
            boundary_layers: 40,
            ..AirfoilGrid::default()
        },
        _ => AirfoilGrid::preset_20k(),
    }
}

/// Mesh, graph and boundary (airfoil then far field, elements in boundary numbering).
struct Case {
    points: Vec<[f64; 2]>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    nodes: Vec<u32>,
    el_offsets: Vec<u32>,
    el_nodes: Vec<u32>,
    el_kinds: Vec<u8>,
    airfoil: usize,
}

impl Case {
    fn new(mesh: &Mesh2) -> Self {
        let n = mesh.points.len();
        let cells = mesh.cells().unwrap();
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        let mut local = vec![u32::MAX; n];
        let mut c = Case {
            points: mesh.points.clone(),
            offsets,
            targets,
            nodes: vec![],
            el_offsets: vec![0],
            el_nodes: vec![],
            el_kinds: vec![],
            airfoil: 0,
        };
        for name in ["airfoil", "farfield"] {
            let m = mesh.marker(name).unwrap();
            for &i in &m.node_list {
                local[i as usize] = c.nodes.len() as u32;
                c.nodes.push(i);
            }
            if name == "airfoil" {
                c.airfoil = c.nodes.len();
            }
            for e in 0..m.kinds.len() {
                for &i in &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize] {
                    c.el_nodes.push(local[i as usize]);
                }
                c.el_kinds.push(m.kinds[e]);
                c.el_offsets.push(c.el_nodes.len() as u32);
            }
        }
        c
    }

    fn elements(&self) -> Cells<'_> {
        Cells::new(
            self.nodes.len(),
            &self.el_offsets,
            &self.el_nodes,
            &self.el_kinds,
        )
        .unwrap()
    }

    fn deformed(&self, s: usize, period: usize) -> Vec<[f64; 2]> {
        let a = 5f64.to_radians() * (2.0 * std::f64::consts::PI * s as f64 / period as f64).sin();
        let (sn, cs) = a.sin_cos();
        let c = AirfoilGrid::quarter_chord();
        self.nodes
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let p = self.points[i as usize];
                if k < self.airfoil {
                    let (x, y) = (p[0] - c[0], p[1] - c[1]);
                    [c[0] + cs * x - sn * y, c[1] + sn * x + cs * y]
                } else {
                    p
                }
            })
            .collect()
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn options() -> SolveOptions<f64> {
    SolveOptions {
        residual_tol: 1e-8,
        ..SolveOptions::default()
    }
}

/// The stateless steps: returns (setup time, solve time, iterations) summed over the steps.
fn stateless(c: &Case, method: PlanMethod, period: usize) -> (Duration, Duration, usize) {
    let n = c.points.len();
    let opts = AmgOptions::default();
    let mut k = vec![0.0; c.targets.len()];
    let mut fixed = vec![0u8; n];
    for &i in &c.nodes {
        fixed[i as usize] = 1;
    }
    let mut seen = vec![0u32; n];
    let mut work = vec![0u32; 4 * (n + c.targets.len()) + 64];
    let (mut index, mut values) = (Vec::new(), Vec::new());
    let mut t = vec![[0.0; 2]; n];
    let mut q = vec![Quat::identity(); n];
    let mut sc = vec![0.0; deform_spring_scratch_len::<2>(n, c.nodes.len())];
    let mut packed: Vec<f64> = Vec::new();
    let mut v2: Vec<[f64; 2]> = Vec::new();
    let mut x = vec![[0.0; 2]; n];
    let mut out = vec![[0.0; 2]; n];
    let (mut setup, mut solve, mut iterations) = (Duration::ZERO, Duration::ZERO, 0);
    for s in 1..=STEPS {
        let d = c.deformed(s, period);
        let t0 = Instant::now();
        let g = Graph::new(&c.offsets, &c.targets).unwrap();
        batina_stiffness(&g, &c.points, 1.0, &mut k).unwrap();
        let sys = SpringSystem::new(g, &k, &fixed, &mut seen).unwrap();
        let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
        index.resize(sizes.index, 0);
        values.resize(sizes.values, 0.0);
        let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
        let ls = LinearSolver::Amg(&h);
        let t1 = Instant::now();
        let rep = match method {
            PlanMethod::Spring => {
                v2.resize(solve_linear_with_scratch_len(&ls, n), [0.0; 2]);
                x.fill([0.0; 2]);
                for (&i, di) in c.nodes.iter().zip(&d) {
                    let p = c.points[i as usize];
                    x[i as usize] = [di[0] - p[0], di[1] - p[1]];
                }
                let r = sys
                    .solve_linear_with(&mut x, ls, &options(), &mut v2)
                    .unwrap();
                for ((o, p), v) in out.iter_mut().zip(&c.points).zip(&x) {
                    *o = [p[0] + v[0], p[1] + v[1]];
                }
                r
            }
            PlanMethod::QuaternionSpring => {
                packed.resize(propagate_spring_with_scratch_len::<2>(&ls, n), 0.0);
                let motion = BoundaryMotion {
                    nodes: &c.nodes,
                    deformed: &d,
                    elements: Some(c.elements()),
                    rotations: RotationSource::Shape,
                    origin: None,
                };
                deform_spring_with::<f64, 2>(
                    &c.points,
                    &motion,
                    &sys,
                    ls,
                    &options(),
                    &mut t,
                    &mut q,
                    &mut sc,
                    &mut packed,
                    &mut out,
                )
                .unwrap()
                .1
            }
        };
        let t2 = Instant::now();
        assert!(rep.converged);
        setup += t1 - t0;
        solve += t2 - t1;
        iterations += rep.iterations;
    }
    (setup, solve, iterations)
}

fn run(label: &str, period: usize) {
    let mesh = naca_triangulated(&grid(label)).unwrap();
    let c = Case::new(&mesh);
    let n = c.points.len();
    println!(
        "\n{label}: {n} nodes, {} directed edges, {} boundary nodes; {STEPS} steps of a \
         {period}-step pitch period",
        c.targets.len(),
        c.nodes.len()
    );
    for method in [PlanMethod::Spring, PlanMethod::QuaternionSpring] {
        let (setup, solve, it_cold) = stateless(&c, method, period);
        let spec = PlanSpec {
            points: &c.points,
            graph: Graph::new(&c.offsets, &c.targets).unwrap(),
            boundary: &c.nodes,
            elements: Some(c.elements()),
            constraints: None,
            method,
            stiffness: PlanStiffness::Batina { exponent: 1.0 },
            solver: PlanSolver::Amg(AmgOptions::default()),
            options: options(),
            renumber: deform_kernel::plan::PlanOrder::AsGiven,
        };
        let t0 = Instant::now();
        let ws = Plan::<f64, 2>::work_sizes(&spec).unwrap();
        let (mut wr, mut wi, mut wb) = (
            vec![0.0; ws.reals],
            vec![0u32; ws.indices],
            vec![0u8; ws.bytes],
        );
        let mut work = PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        };
        let sizes = Plan::<f64, 2>::sizes(&spec, &mut work).unwrap();
        let mut reals = vec![0.0; sizes.reals];
        let mut indices = vec![0u32; sizes.indices];
        let mut bytes = vec![0u8; sizes.bytes];
        Plan::init(&spec, &mut work, &mut reals, &mut indices, &mut bytes).unwrap();
        let init = t0.elapsed();
        drop((wr, wi, wb));
        let t0 = Instant::now();
        let mut plan = Plan::<f64, 2>::open(&mut reals, &mut indices, &mut bytes).unwrap();
        let open = t0.elapsed();
        let mut out = vec![[0.0; 2]; n];
        let (mut step_time, mut it_warm, mut warm_steps, mut extrapolated) =
            (Duration::ZERO, 0, 0, 0);
        let mut per_step = Vec::new();
        for s in 1..=STEPS {
            let d = c.deformed(s, period);
            let t0 = Instant::now();
            let rep = plan.step(&PlanMotion::new(&d), &mut out).unwrap();
            step_time += t0.elapsed();
            assert!(rep.solve.converged);
            it_warm += rep.solve.iterations;
            warm_steps += usize::from(rep.warm);
            extrapolated += usize::from(rep.extrapolated);
            per_step.push(rep.solve.iterations);
        }
        let mb = (sizes.reals * 8 + sizes.indices * 4 + sizes.bytes) as f64 / 1e6;
        let name = match method {
            PlanMethod::Spring => "linear springs",
            PlanMethod::QuaternionSpring => "quaternion + springs",
        };
        let st = STEPS as f64;
        println!(
            "  {name}: stateless {:.1} ms/step (setup {:.1} + solve {:.1}), {} iterations; \
             plan {:.1} ms/step, {} iterations ({warm_steps} warm, {extrapolated} extrapolated), init {:.1} ms, open {:.1} \
             ms, pools {mb:.1} MB; plan iterations per step {per_step:?}",
            ms(setup + solve) / st,
            ms(setup) / st,
            ms(solve) / st,
            it_cold,
            ms(step_time) / st,
            it_warm,
            ms(init),
            ms(open),
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let which = args.first().map_or("20k", String::as_str);
    let period = args.get(1).map_or(200, |p| p.parse().unwrap());
    match which {
        "both" => {
            run("20k", period);
            run("234k", period);
        }
        w => run(w, period),
    }
}
