//! The cost of the mesh sensitivities (issue 30 item 5): on the spring rows' NACA 2412 mesh
//! (1024 × 229 = 234,496 nodes; `--quick` 256 × 80), the airfoil pitched 10° about the quarter
//! chord and the far field fixed, for the linear springs and for the quaternion method with
//! spring propagation (rotations from the boundary shape), both multigrid-preconditioned CG
//! with the default hierarchy options and a relative residual of 1e-8:
//!
//! - the deformation: a prepared plan's `init` (sizes, stiffness, hierarchy set-up) and one
//!   cold `step`, setup included;
//! - the adjoint of that step through the plan (`Plan::adjoint`: the hierarchy and, for the
//!   quaternion method, the step's solved field reused), for a fixed pseudo-random `dJ/dx`,
//!   and again for a smooth `dJ/dx` gathered at the wall (`*_wall_adjoint_*`), as a flow
//!   adjoint gives;
//!
//! each the median of `reps` runs, and their ratio (`*_adjoint_over_deformation`; the issue
//! asks for at most 1.5).
//!
//! The `*_shape_*` rows do the same for a change of shape as an optimisation step makes: the
//! airfoil's camber raised by a Hicks–Henne bump of 1 % chord peaking at 40 % chord, then
//! pitched as above. There the boundary rotations vary along the wall and the translations
//! are not zero, so the quaternion deformation solves all of its lanes (the rigid pitch's
//! translation lanes are exactly zero and skipped).

use std::time::Instant;

use deform_kernel::design::hicks_henne::hicks_henne_bump;
use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanOrder, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::spring::{AmgOptions, SolveOptions, SolveReport};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph};
use deform_meshgen::{naca_triangulated, rotate_markers2, AirfoilGrid};

use crate::{lcg, Figures};

/// The mesh, its graph, boundary (airfoil then far field) with segments over it, and the
/// pitched boundary positions.
struct Problem {
    points: Vec<[f64; 2]>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    boundary: Vec<u32>,
    el: (Vec<u32>, Vec<u32>, Vec<u8>),
    deformed: Vec<[f64; 2]>,
    /// Boundary nodes `..wall` are the airfoil's.
    wall: usize,
}

impl Problem {
    /// `shape`: the bumped and pitched airfoil of the `*_shape_*` rows, else the pitch alone.
    fn new(airfoil: [usize; 2], shape: bool) -> Self {
        let [surface, radial] = airfoil;
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
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).expect("graph");
        targets.truncate(used);
        let (mut boundary, mut local) = (Vec::new(), vec![u32::MAX; n]);
        let mut el = (vec![0u32], Vec::new(), Vec::new());
        let mut wall = 0;
        for name in ["airfoil", "farfield"] {
            if name == "farfield" {
                wall = boundary.len();
            }
            let m = mesh.marker(name).expect("marker");
            for &i in &m.node_list {
                local[i as usize] = boundary.len() as u32;
                boundary.push(i);
            }
            for (e, &kind) in m.kinds.iter().enumerate() {
                let nodes = &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize];
                el.1.extend(nodes.iter().map(|&i| local[i as usize]));
                el.2.push(kind);
                el.0.push(el.1.len() as u32);
            }
        }
        let rot = rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0)
            .expect("rotation");
        // The rotation's displacement field, added to the points.
        let field: Vec<[f64; 2]> = rot.to_field(n);
        let deformed = boundary
            .iter()
            .enumerate()
            .map(|(k, &b)| {
                let p = mesh.points[b as usize];
                if shape && k < wall {
                    return bumped_pitch(p);
                }
                let u = field[b as usize];
                [p[0] + u[0], p[1] + u[1]]
            })
            .collect();
        Problem {
            points: mesh.points.clone(),
            offsets,
            targets,
            boundary,
            el,
            deformed,
            wall,
        }
    }

    fn spec(&self, method: PlanMethod, amg: AmgOptions<f64>) -> PlanSpec<'_, f64, 2> {
        let b = self.boundary.len();
        PlanSpec {
            points: &self.points,
            graph: Graph::new(&self.offsets, &self.targets).expect("graph"),
            boundary: &self.boundary,
            elements: Some(Cells::new(b, &self.el.0, &self.el.1, &self.el.2).expect("cells")),
            constraints: None,
            method,
            stiffness: PlanStiffness::Batina { exponent: 1.0 },
            solver: PlanSolver::Amg(amg),
            options: SolveOptions {
                residual_tol: 1e-8,
                max_iterations: 100_000,
                update_tol: 0.0,
            },
            renumber: PlanOrder::AsGiven,
        }
    }
}

/// An airfoil point raised by a Hicks–Henne bump (1 % chord at 40 % chord), then pitched by
/// the rows' −10° about the quarter chord.
fn bumped_pitch(p: [f64; 2]) -> [f64; 2] {
    let bump = 0.01 * hicks_henne_bump(p[0].clamp(0.0, 1.0), 0.4);
    let [cx, cy] = AirfoilGrid::quarter_chord();
    let (x, y) = (p[0] - cx, p[1] + bump - cy);
    let (sin, cos) = (-10.0f64).to_radians().sin_cos();
    [cx + cos * x - sin * y, cy + sin * x + cos * y]
}

/// A smooth `dJ/dx` gathered at the wall, as a flow adjoint's: `(sin(3x + 1), cos 2y)`
/// times `exp(−d / 0.05)`, `d` the distance to the nearest airfoil node.
fn wall_weights(p: &Problem) -> Vec<[f64; 2]> {
    let wall: Vec<[f64; 2]> = p.boundary[..p.wall]
        .iter()
        .map(|&b| p.points[b as usize])
        .collect();
    p.points
        .iter()
        .map(|x| {
            let d2 = wall
                .iter()
                .map(|y| (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2))
                .fold(f64::MAX, f64::min);
            let e = (-d2.sqrt() / 0.05).exp();
            [(3.0 * x[0] + 1.0).sin() * e, (2.0 * x[1]).cos() * e]
        })
        .collect()
}

/// Owned pools of one plan.
struct Pools {
    reals: Vec<f64>,
    indices: Vec<u32>,
    bytes: Vec<u8>,
}

/// The deformation as a caller runs it once: work and pool sizes, `init`, one cold step.
/// Never inlined, so callgrind counts it as one function (`--quick` under callgrind).
#[inline(never)]
fn deform(
    p: &Problem,
    method: PlanMethod,
    amg: AmgOptions<f64>,
    out: &mut [[f64; 2]],
) -> (Pools, usize) {
    let spec = p.spec(method, amg);
    let ws = Plan::<f64, 2>::work_sizes(&spec).expect("work sizes");
    let (mut wr, mut wi, mut wb) = (vec![0.0; ws.reals], vec![0; ws.indices], vec![0; ws.bytes]);
    let mut work = PlanWork {
        reals: &mut wr,
        indices: &mut wi,
        bytes: &mut wb,
    };
    let sizes = Plan::<f64, 2>::sizes(&spec, &mut work).expect("sizes");
    let mut pools = Pools {
        reals: vec![0.0; sizes.reals],
        indices: vec![0; sizes.indices],
        bytes: vec![0; sizes.bytes],
    };
    let mut plan = Plan::init(
        &spec,
        &mut work,
        &mut pools.reals,
        &mut pools.indices,
        &mut pools.bytes,
    )
    .expect("init");
    let motion = PlanMotion {
        start: Start::Cold,
        ..PlanMotion::new(&p.deformed)
    };
    let r = plan.step(&motion, out).expect("step");
    assert!(r.solve.converged, "the plan's step did not converge");
    (pools, r.solve.iterations)
}

/// The plan's adjoint of the last step (never inlined, as [`deform`]).
#[inline(never)]
fn adjoint(
    plan: &Plan<'_, f64, 2>,
    motion: &PlanMotion<'_, f64, 2>,
    w: &[[f64; 2]],
    scratch: &mut [f64],
    g: &mut [[f64; 2]],
) -> SolveReport<f64> {
    plan.adjoint(motion, w, scratch, g).expect("adjoint")
}

/// [`adjoint`] for the wall-gathered `dJ/dx`: its own never-inlined caller, so callgrind
/// separates the two (`adjoint` inclusive counts both).
#[inline(never)]
fn wall_adjoint(
    plan: &Plan<'_, f64, 2>,
    motion: &PlanMotion<'_, f64, 2>,
    w: &[[f64; 2]],
    scratch: &mut [f64],
    g: &mut [[f64; 2]],
) -> SolveReport<f64> {
    adjoint(plan, motion, w, scratch, g)
}

/// Median of `v`.
fn med(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The rows of one method and hierarchy (`tag`: `spring` or `quaternion`, with `_theta0` for
/// [`all_strong`]'s).
fn rows(
    p: &Problem,
    (method, amg): (PlanMethod, AmgOptions<f64>),
    tag: &str,
    reps: usize,
    fig: &mut Figures,
) {
    let n = p.points.len();
    let mut state = 3u64;
    let w: Vec<[f64; 2]> = (0..n).map(|_| [lcg(&mut state), lcg(&mut state)]).collect();
    let mut out = vec![[0.0; 2]; n];
    let mut g = vec![[0.0; 2]; p.boundary.len()];
    let w_wall = wall_weights(p);
    let (mut t_def, mut t_adj, mut t_wall) = (Vec::new(), Vec::new(), Vec::new());
    let (mut it_def, mut it_adj, mut it_wall) = (0, 0, 0);
    for _ in 0..reps {
        let t = Instant::now();
        let (mut pools, iterations) = deform(p, method, amg, &mut out);
        t_def.push(t.elapsed().as_secs_f64());
        it_def = iterations;
        let plan = Plan::<f64, 2>::open(&mut pools.reals, &mut pools.indices, &mut pools.bytes)
            .expect("open");
        let mut scratch = vec![0.0; plan.sensitivity_scratch_len()];
        let motion = PlanMotion::new(&p.deformed);
        let t = Instant::now();
        let r = adjoint(&plan, &motion, &w, &mut scratch, &mut g);
        t_adj.push(t.elapsed().as_secs_f64());
        assert!(r.converged, "the adjoint did not converge");
        it_adj = r.iterations;
        let t = Instant::now();
        let r = wall_adjoint(&plan, &motion, &w_wall, &mut scratch, &mut g);
        t_wall.push(t.elapsed().as_secs_f64());
        assert!(r.converged, "the wall adjoint did not converge");
        it_wall = r.iterations;
    }
    let (d, a) = (med(&mut t_def), med(&mut t_adj));
    fig.put(&format!("sensitivity_{tag}_deformation_s"), d);
    fig.put(&format!("sensitivity_{tag}_deformation_iterations"), it_def);
    fig.put(&format!("sensitivity_{tag}_adjoint_s"), a);
    fig.put(&format!("sensitivity_{tag}_adjoint_iterations"), it_adj);
    fig.put(
        &format!("sensitivity_{tag}_adjoint_over_deformation"),
        a / d,
    );
    let aw = med(&mut t_wall);
    fig.put(&format!("sensitivity_{tag}_wall_adjoint_s"), aw);
    fig.put(
        &format!("sensitivity_{tag}_wall_adjoint_iterations"),
        it_wall,
    );
    fig.put(
        &format!("sensitivity_{tag}_wall_adjoint_over_deformation"),
        aw / d,
    );
}

/// The hierarchy with every spring strong (strength threshold 0, pyamg's default and the
/// kernel's before 2026-11-29), for comparison with the default θ = 0.25 (docs/amg.md).
fn all_strong() -> AmgOptions<f64> {
    AmgOptions {
        strength_theta: 0.0,
        ..AmgOptions::default()
    }
}

/// Which sensitivity rows to run: per method (linear springs, quaternion), per hierarchy
/// (default, [`all_strong`]) and per motion (the pitch, the bumped pitch).
pub(crate) struct Which {
    pub(crate) methods: [bool; 2],
    pub(crate) hierarchies: [bool; 2],
    pub(crate) motions: [bool; 2],
}

/// The sensitivity rows on the NACA mesh of `airfoil` points, `reps` runs each, for the
/// chosen methods, hierarchies and motions (`_shape` in the tags of the bumped pitch's).
pub(crate) fn sensitivity(airfoil: [usize; 2], reps: usize, which: &Which, fig: &mut Figures) {
    let theta0 = all_strong();
    for (shape, suffix) in [(false, ""), (true, "_shape")] {
        if !which.motions[usize::from(shape)] {
            continue;
        }
        let p = Problem::new(airfoil, shape);
        println!(
            "sensitivities{suffix}: NACA 2412 {} × {} = {} nodes, {} boundary points",
            airfoil[0],
            airfoil[1],
            p.points.len(),
            p.boundary.len()
        );
        fig.put("sensitivity_nodes", p.points.len());
        for (k, (method, tag)) in [
            (PlanMethod::Spring, "spring"),
            (PlanMethod::QuaternionSpring, "quaternion"),
        ]
        .into_iter()
        .enumerate()
        {
            if which.methods[k] && which.hierarchies[0] {
                let t = format!("{tag}{suffix}");
                rows(&p, (method, AmgOptions::default()), &t, reps, fig);
            }
            if which.methods[k] && which.hierarchies[1] {
                let t = format!("{tag}_theta0{suffix}");
                rows(&p, (method, theta0), &t, reps, fig);
            }
        }
    }
}
