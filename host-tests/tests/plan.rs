//! Prepared plans (`deform_kernel::plan`): a pitching NACA airfoil stepped 20 time steps
//! through a plan gives the bits of the stateless calls with the same initial guesses (cold
//! steps of the quaternion method against `deform_spring_with`, warm steps of the linear
//! springs against `solve_linear_with` from the previous solution), warm starts need fewer
//! iterations than cold ones (printed), copied pools resume bit for bit, corrupted pools are
//! `BadPlan`, bad step input is a typed error that leaves `out` and the plan unchanged. f32 and
//! f64, multigrid and one-level solvers.
//!
//! `cargo test -p deform-host-tests --test plan -- --nocapture` prints the iteration counts.

use deform_kernel::plan::{
    Plan, PlanCounts, PlanMethod, PlanMotion, PlanSizes, PlanSolver, PlanSpec, PlanStiffness,
    PlanStorage, PlanWork, Start, StepReport,
};
use deform_kernel::quaternion::{
    deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, LinearMethod,
    LinearSolver, Preconditioner, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Error, Graph, Quat, Real};
use deform_meshgen::{extrude, naca_hybrid, naca_triangulated, AirfoilGrid, Mesh, Mesh2};

const STEPS: usize = 20;

#[path = "plan/sensitivity.rs"]
mod sensitivity;

/// A NACA mesh with its graph and boundary (airfoil then far field, elements in boundary
/// numbering), in precision `T`.
struct Case<T, const D: usize = 2> {
    points: Vec<[T; D]>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    nodes: Vec<u32>,
    el_offsets: Vec<u32>,
    el_nodes: Vec<u32>,
    el_kinds: Vec<u8>,
    airfoil: usize,
}

impl<T: Real, const D: usize> Case<T, D> {
    fn new(mesh: &Mesh<D>) -> Self {
        // In 3D the end caps share nodes with the airfoil and the far field.
        let names = ["airfoil", "farfield", "zmin", "zmax"];
        Self::with_markers(mesh, &names[..D + D - 2], "airfoil")
    }

    /// The boundary of the markers `names` in order; the points of those up to `moving`
    /// included pitch.
    fn with_markers(mesh: &Mesh<D>, names: &[&str], moving: &str) -> Self {
        let n = mesh.points.len();
        let cells = mesh.cells().unwrap();
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
        let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        let mut local = vec![u32::MAX; n];
        let mut c = Case {
            points: mesh.points.iter().map(|p| p.map(T::from_f64)).collect(),
            offsets,
            targets,
            nodes: Vec::new(),
            el_offsets: vec![0],
            el_nodes: Vec::new(),
            el_kinds: Vec::new(),
            airfoil: 0,
        };
        for name in names {
            let m = mesh.marker(name).unwrap();
            for &i in &m.node_list {
                if local[i as usize] == u32::MAX {
                    local[i as usize] = c.nodes.len() as u32;
                    c.nodes.push(i);
                }
            }
            if *name == moving {
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

    fn graph(&self) -> Graph<'_> {
        Graph::new(&self.offsets, &self.targets).unwrap()
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

    /// Boundary positions at time step `s`: the airfoil pitched by `5° sin(2π s / 20)` about
    /// the quarter chord, the far field fixed.
    fn deformed(&self, s: usize) -> Vec<[T; D]> {
        self.pitched(s, 20)
    }

    /// The airfoil pitched by `5° sin(2π s / period)`.
    fn pitched(&self, s: usize, period: usize) -> Vec<[T; D]> {
        let a =
            (5.0f64).to_radians() * (2.0 * std::f64::consts::PI * s as f64 / period as f64).sin();
        let (sn, cs) = a.sin_cos();
        let c = AirfoilGrid::quarter_chord();
        self.nodes
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let p = self.points[i as usize];
                let mut p = p;
                if k < self.airfoil {
                    let (x, y) = (p[0].to_f64() - c[0], p[1].to_f64() - c[1]);
                    p[0] = T::from_f64(c[0] + cs * x - sn * y);
                    p[1] = T::from_f64(c[1] + sn * x + cs * y);
                }
                p
            })
            .collect()
    }

    fn fixed(&self) -> Vec<u8> {
        let mut f = vec![0u8; self.points.len()];
        for &i in &self.nodes {
            f[i as usize] = 1;
        }
        f
    }

    fn stiffness(&self) -> Vec<T> {
        let mut k = vec![T::ZERO; self.targets.len()];
        batina_stiffness(&self.graph(), &self.points, T::ONE, &mut k).unwrap();
        k
    }

    fn spec(&self, method: PlanMethod, solver: PlanSolver<T>) -> PlanSpec<'_, T, D> {
        PlanSpec {
            points: &self.points,
            graph: self.graph(),
            boundary: &self.nodes,
            elements: Some(self.elements()),
            constraints: None,
            method,
            stiffness: PlanStiffness::Batina { exponent: T::ONE },
            solver,
            options: options(),
            renumber: deform_kernel::plan::PlanOrder::AsGiven,
        }
    }
}

fn options<T: Real>() -> SolveOptions<T> {
    SolveOptions {
        residual_tol: T::from_f64(if T::EPSILON > T::from_f64(1e-10) {
            1e-5
        } else {
            1e-10
        }),
        ..SolveOptions::default()
    }
}

fn mesh() -> Mesh2 {
    naca_hybrid(&AirfoilGrid {
        surface_points: 64,
        radial_points: 24,
        first_layer: 1e-3,
        boundary_layers: 8,
        ..AirfoilGrid::default()
    })
    .unwrap()
}

/// Owned plan pools.
#[derive(Clone, PartialEq)]
struct Pools<T> {
    reals: Vec<T>,
    indices: Vec<u32>,
    bytes: Vec<u8>,
}

impl<T: Real> Pools<T> {
    fn build<const D: usize>(spec: &PlanSpec<'_, T, D>) -> (Self, PlanSizes) {
        let ws = Plan::<T, D>::work_sizes(spec).unwrap();
        let mut wr = vec![T::ZERO; ws.reals];
        let mut wi = vec![0u32; ws.indices];
        let mut wb = vec![0u8; ws.bytes];
        let mut work = PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        };
        let sizes = Plan::<T, D>::sizes(spec, &mut work).unwrap();
        let mut p = Pools {
            reals: vec![T::ZERO; sizes.reals],
            indices: vec![0; sizes.indices],
            bytes: vec![0; sizes.bytes],
        };
        let plan = Plan::init(spec, &mut work, &mut p.reals, &mut p.indices, &mut p.bytes).unwrap();
        assert_eq!(plan.used(), sizes);
        (p, sizes)
    }

    fn open(&mut self) -> deform_kernel::Result<Plan<'_, T, 2>> {
        Plan::open(&mut self.reals, &mut self.indices, &mut self.bytes)
    }

    fn open_d<const D: usize>(&mut self) -> deform_kernel::Result<Plan<'_, T, D>> {
        Plan::open(&mut self.reals, &mut self.indices, &mut self.bytes)
    }

    /// Bitwise equality (NaN-safe).
    fn same_bits(&self, o: &Self) -> bool {
        self.indices == o.indices
            && self.bytes == o.bytes
            && self.reals.len() == o.reals.len()
            && self
                .reals
                .iter()
                .zip(&o.reals)
                .all(|(a, b)| a.to_bits_u64() == b.to_bits_u64())
    }
}

fn bits<T: Real, const D: usize>(v: &[[T; D]]) -> Vec<u64> {
    v.iter().flatten().map(|x| x.to_bits_u64()).collect()
}

fn amg<T: Real>() -> PlanSolver<T> {
    PlanSolver::Amg(AmgOptions {
        max_coarse: 32,
        ..AmgOptions::default()
    })
}

fn cg<T: Real>() -> PlanSolver<T> {
    PlanSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    })
}

/// The stateless quaternion pipeline at step `s` (cold start: the mean of the boundary
/// values), with the same hierarchy options.
fn stateless_quaternion<T: Real, const D: usize>(
    c: &Case<T, D>,
    solver: &PlanSolver<T>,
    s: usize,
    period: usize,
) -> (Vec<[T; D]>, SolveReport<T>) {
    let deformed = c.pitched(s, period);
    let motion = BoundaryMotion {
        nodes: &c.nodes,
        deformed: &deformed,
        elements: Some(c.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    with_system(c, solver, |sys, ls| stateless_deform(c, &motion, sys, ls))
}

/// The stateless spring system of `c` (Batina stiffness, fixed at the boundary) and the solver
/// of `solver` (its own hierarchy, set up with the plan's options), handed to `f`.
fn with_system<T: Real, const D: usize, R>(
    c: &Case<T, D>,
    solver: &PlanSolver<T>,
    f: impl FnOnce(&SpringSystem<'_, T>, LinearSolver<'_, T>) -> R,
) -> R {
    let n = c.points.len();
    let k = c.stiffness();
    let fixed = c.fixed();
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(c.graph(), &k, &fixed, &mut ss).unwrap();
    let (mut work, mut index, mut values);
    let h;
    let ls = match solver {
        PlanSolver::Amg(o) => {
            work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
            let sz = AmgHierarchy::setup_len(&sys, o, &mut work).unwrap();
            index = vec![0u32; sz.index];
            values = vec![T::ZERO; sz.values];
            h = AmgHierarchy::setup(&sys, o, &mut work, &mut index, &mut values).unwrap();
            LinearSolver::Amg(&h)
        }
        PlanSolver::Method(m) => LinearSolver::Method(*m),
    };
    f(&sys, ls)
}

/// `deform_spring_with` of `motion` on `sys` with `ls`.
fn stateless_deform<T: Real, const D: usize>(
    c: &Case<T, D>,
    motion: &BoundaryMotion<'_, T, D>,
    sys: &SpringSystem<'_, T>,
    ls: LinearSolver<'_, T>,
) -> (Vec<[T; D]>, SolveReport<T>) {
    let n = c.points.len();
    let mut t = vec![[T::ZERO; D]; n];
    let mut q = vec![Quat::identity(); n];
    let mut sc = vec![T::ZERO; deform_spring_scratch_len::<D>(n, c.nodes.len())];
    let mut v = vec![T::ZERO; propagate_spring_with_scratch_len::<D>(&ls, n)];
    let mut out = vec![[T::ZERO; D]; n];
    let (_, rep) = deform_spring_with::<T, D>(
        &c.points,
        motion,
        sys,
        ls,
        &options(),
        &mut t,
        &mut q,
        &mut sc,
        &mut v,
        &mut out,
    )
    .unwrap();
    (out, rep)
}

fn quaternion_cold_equals_stateless<T: Real>(solver: PlanSolver<T>) {
    let c = Case::<T>::new(&mesh());
    let n = c.points.len();
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::QuaternionSpring, solver));
    let mut plan = pools.open().unwrap();
    let mut out = vec![[T::ZERO; 2]; n];
    for s in 1..=STEPS {
        let deformed = c.deformed(s);
        let motion = PlanMotion {
            start: Start::Cold,
            ..PlanMotion::new(&deformed)
        };
        let rep = plan.step(&motion, &mut out).unwrap();
        let (expect, erep) = stateless_quaternion::<T, 2>(&c, &solver, s, 20);
        assert_eq!(bits(&out), bits(&expect), "step {s}");
        assert_eq!(rep.solve.iterations, erep.iterations);
        assert!(!rep.warm && rep.solve.converged && rep.step == s as u64);
    }
}

#[test]
fn quaternion_cold_steps_equal_stateless_pipeline_f64_amg() {
    quaternion_cold_equals_stateless::<f64>(amg());
}

#[test]
fn quaternion_cold_steps_equal_stateless_pipeline_f32_amg() {
    quaternion_cold_equals_stateless::<f32>(amg());
}

#[test]
fn quaternion_cold_steps_equal_stateless_pipeline_f64_cg() {
    quaternion_cold_equals_stateless::<f64>(cg());
}

/// The stateless linear-spring solve from a given initial guess: Batina stiffness, system,
/// hierarchy, `solve_linear_with`, points plus displacements, boundary copied.
fn stateless_spring<T: Real, const D: usize>(
    c: &Case<T, D>,
    solver: &PlanSolver<T>,
    s: usize,
    guess: &mut [[T; D]],
) -> (Vec<[T; D]>, SolveReport<T>) {
    let n = c.points.len();
    let k = c.stiffness();
    let fixed = c.fixed();
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(c.graph(), &k, &fixed, &mut ss).unwrap();
    let (mut work, mut index, mut values);
    let h;
    let ls = match solver {
        PlanSolver::Amg(o) => {
            work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
            let sz = AmgHierarchy::setup_len(&sys, o, &mut work).unwrap();
            index = vec![0u32; sz.index];
            values = vec![T::ZERO; sz.values];
            h = AmgHierarchy::setup(&sys, o, &mut work, &mut index, &mut values).unwrap();
            LinearSolver::Amg(&h)
        }
        PlanSolver::Method(m) => LinearSolver::Method(*m),
    };
    let deformed = c.deformed(s);
    for (&i, d) in c.nodes.iter().zip(&deformed) {
        let p = c.points[i as usize];
        guess[i as usize] = std::array::from_fn(|j| d[j] - p[j]);
    }
    let mut scratch = vec![[T::ZERO; D]; solve_linear_with_scratch_len(&ls, n)];
    let rep = sys
        .solve_linear_with(guess, ls, &options(), &mut scratch)
        .unwrap();
    let mut out: Vec<[T; D]> = c
        .points
        .iter()
        .zip(guess.iter())
        .map(|(p, v)| std::array::from_fn(|j| p[j] + v[j]))
        .collect();
    for (&i, d) in c.nodes.iter().zip(&deformed) {
        out[i as usize] = *d;
    }
    (out, rep)
}

/// Linear springs: warm steps equal the stateless solve started from the previous solution;
/// cold steps equal it started from zero. Returns the total iterations (warm, cold).
fn spring_equals_stateless<T: Real>(solver: PlanSolver<T>) -> (usize, usize) {
    let c = Case::<T>::new(&mesh());
    let n = c.points.len();
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::Spring, solver));
    let mut cold_pools = pools.clone();
    let mut plan = pools.open().unwrap();
    let mut cold_plan = cold_pools.open().unwrap();
    let mut out = vec![[T::ZERO; 2]; n];
    let mut history = History::default();
    let (mut warm_it, mut cold_it, mut warm_steps, mut extrapolated) = (0, 0, 0, 0);
    for s in 1..=STEPS {
        let deformed = c.deformed(s);
        let rep = plan.step(&PlanMotion::new(&deformed), &mut out).unwrap();
        // The plan starts from zero, the previous solution or the extrapolation of the last
        // two, whichever has the smallest residual: the stateless solve gets the same guess.
        let mut guess = history.guess(&rep, n);
        let (expect, erep) = stateless_spring(&c, &solver, s, &mut guess);
        history.push(guess);
        assert_eq!(bits(&out), bits(&expect), "step {s}");
        assert_eq!(rep.solve.iterations, erep.iterations);
        warm_steps += usize::from(rep.warm);
        extrapolated += usize::from(rep.extrapolated);
        warm_it += rep.solve.iterations;

        let motion = PlanMotion {
            start: Start::Cold,
            ..PlanMotion::new(&deformed)
        };
        let crep = cold_plan.step(&motion, &mut out).unwrap();
        let mut zero = vec![[T::ZERO; 2]; n];
        let (expect, erep) = stateless_spring(&c, &solver, s, &mut zero);
        assert_eq!(bits(&out), bits(&expect), "cold step {s}");
        assert_eq!(crep.solve.iterations, erep.iterations);
        cold_it += crep.solve.iterations;
    }
    // Every step starts warm but the first (no previous solution) and the two at rest (zero
    // motion: the cold guess is exact). Step 11 starts from the extrapolation `0 + (0 − x_9)`,
    // the mirror image of step 9 and so (nearly) its exact solution.
    println!("  {warm_steps} warm starts, {extrapolated} of them extrapolated");
    assert_eq!(warm_steps, STEPS - 3);
    assert!(extrapolated > 0);
    (warm_it, cold_it)
}

/// A one-level multigrid hierarchy (`max_levels` 1: the coarse factor is the whole system)
/// is a plan like any other, with the stateless solve's bits (issue 26: it was refused as a
/// bad plan after the pools were written).
#[test]
fn one_level_multigrid_plans_equal_stateless() {
    let one = PlanSolver::Amg(AmgOptions {
        max_levels: 1,
        max_coarse: 32,
        ..AmgOptions::default()
    });
    let c = Case::<f64>::new(&mesh());
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::Spring, one));
    assert_eq!(pools.open().unwrap().amg_levels(), 1);
    spring_equals_stateless::<f64>(one);
}

/// The last two stateless solutions, to rebuild the plan's initial guess.
#[derive(Default)]
struct History<T, const D: usize> {
    last: Option<Vec<[T; D]>>,
    before: Option<Vec<[T; D]>>,
}

impl<T: Real, const D: usize> History<T, D> {
    /// The guess the plan reports having used: zero (cold), the last solution, or
    /// `x_n + (x_n − x_{n−1})` (boundary entries are overwritten by the solve's data).
    fn guess(&self, rep: &StepReport<T, D>, n: usize) -> Vec<[T; D]> {
        match (rep.warm, rep.extrapolated, &self.last, &self.before) {
            (false, _, _, _) => vec![[T::ZERO; D]; n],
            (true, false, Some(a), _) => a.clone(),
            (true, true, Some(a), Some(b)) => a
                .iter()
                .zip(b)
                .map(|(p, q)| std::array::from_fn(|j| p[j] + (p[j] - q[j])))
                .collect(),
            _ => panic!("warm start without stored solutions"),
        }
    }

    fn push(&mut self, x: Vec<[T; D]>) {
        self.before = self.last.replace(x);
    }
}

#[test]
fn spring_steps_equal_stateless_with_the_same_initial_guess() {
    for (name, (w, c)) in [
        ("f64 amg", spring_equals_stateless::<f64>(amg())),
        ("f32 amg", spring_equals_stateless::<f32>(amg())),
        ("f64 cg", spring_equals_stateless::<f64>(cg())),
    ] {
        println!("linear springs, {name}: {STEPS} steps, iterations warm {w}, cold {c}");
        assert!(w < c, "{name}: warm {w} not below cold {c}");
    }
}

/// Quaternion method: warm steps converge to the stateless (cold) answer within the solver
/// tolerance and need fewer iterations in total.
fn quaternion_warm<T: Real>(solver: PlanSolver<T>, name: &str, tol: f64, period: usize) {
    let c = Case::<T>::new(&mesh());
    let n = c.points.len();
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::QuaternionSpring, solver));
    let mut plan = pools.open().unwrap();
    let mut out = vec![[T::ZERO; 2]; n];
    let (mut warm_it, mut cold_it, mut max_diff) = (0, 0, 0.0f64);
    let mut per_step = Vec::new();
    for s in 1..=STEPS {
        let deformed = c.pitched(s, period);
        let rep: StepReport<T, 2> = plan.step(&PlanMotion::new(&deformed), &mut out).unwrap();
        assert!(rep.solve.converged);
        let (expect, erep) = stateless_quaternion::<T, 2>(&c, &solver, s, period);
        for (a, b) in out.iter().zip(&expect) {
            for (x, y) in a.iter().zip(b) {
                max_diff = max_diff.max((x.to_f64() - y.to_f64()).abs());
            }
        }
        for (&i, d) in c.nodes.iter().zip(&deformed) {
            assert_eq!(bits(&[out[i as usize]]), bits(&[*d]));
        }
        warm_it += rep.solve.iterations;
        cold_it += erep.iterations;
        per_step.push((rep.solve.iterations, erep.iterations));
    }
    println!(
        "quaternion method, {name}, period {period} steps: {STEPS} steps, iterations warm \
         {warm_it}, cold {cold_it}; per step (warm, cold) {per_step:?}; max |warm − cold| \
         {max_diff:.2e}"
    );
    assert!(
        warm_it < cold_it,
        "{name}: warm {warm_it} not below cold {cold_it}"
    );
    assert!(max_diff < tol, "{name}: {max_diff}");
}

#[test]
fn quaternion_warm_starts_take_fewer_iterations() {
    // A full pitch period in 20 steps (large changes per step), and the first 20 steps of a
    // 200-step period (the time steps of an unsteady flow solver).
    for period in [20, 200] {
        // The two answers differ by the solver's error (relative residual 1e-10 / 1e-5 on an
        // ill-conditioned network); the trailing edge moves by up to 0.065 chords.
        quaternion_warm::<f64>(amg(), "f64 amg", 1e-5, period);
        quaternion_warm::<f32>(amg(), "f32 amg", 1e-2, period);
    }
    quaternion_warm::<f64>(cg(), "f64 cg", 1e-5, 20);
}

fn copy_resume<T: Real>(method: PlanMethod) {
    let c = Case::<T>::new(&mesh());
    let n = c.points.len();
    let (mut pools, _) = Pools::build(&c.spec(method, amg()));
    let mut a = vec![[T::ZERO; 2]; n];
    let mut b = vec![[T::ZERO; 2]; n];
    let copy;
    {
        let mut plan = pools.open().unwrap();
        for s in 1..=STEPS / 2 {
            let d = c.deformed(s);
            plan.step(&PlanMotion::new(&d), &mut a).unwrap();
        }
        // Checkpoint while the plan is in use.
        let (r, i, y) = plan.buffers();
        copy = Pools {
            reals: r.to_vec(),
            indices: i.to_vec(),
            bytes: y.to_vec(),
        };
    }
    let mut copy = copy;
    let mut p1 = pools.open().unwrap();
    let mut p2 = copy.open().unwrap();
    assert_eq!(p2.steps(), (STEPS / 2) as u64);
    for s in STEPS / 2 + 1..=STEPS {
        let d = c.deformed(s);
        let r1 = p1.step(&PlanMotion::new(&d), &mut a).unwrap();
        let r2 = p2.step(&PlanMotion::new(&d), &mut b).unwrap();
        assert_eq!(bits(&a), bits(&b), "step {s}");
        assert_eq!(r1.solve.iterations, r2.solve.iterations);
        assert_eq!(
            r1.solve.residual.to_bits_u64(),
            r2.solve.residual.to_bits_u64()
        );
        assert_eq!(r1.warm, r2.warm);
        assert_eq!(r2.step, s as u64);
    }
    assert!(pools.same_bits(&copy));
}

#[test]
fn copied_pools_resume_bit_identically() {
    copy_resume::<f64>(PlanMethod::QuaternionSpring);
    copy_resume::<f32>(PlanMethod::QuaternionSpring);
    copy_resume::<f64>(PlanMethod::Spring);
}

#[test]
fn corrupted_pools_are_bad_plan_errors_and_nothing_is_written() {
    let c = Case::<f64>::new(&mesh());
    let (mut good, _) = Pools::build(&c.spec(PlanMethod::QuaternionSpring, amg()));
    let fresh = good.clone();
    {
        let mut p = good.open().unwrap();
        let d = c.deformed(1);
        let mut out = vec![[0.0; 2]; c.points.len()];
        p.step(&PlanMotion::new(&d), &mut out).unwrap();
    }
    good.open().unwrap();
    let n = c.points.len();
    // The first real a step changed lies in the stored solution (the state comes first).
    let state = (0..good.reals.len())
        .find(|&i| good.reals[i].to_bits() != fresh.reals[i].to_bits())
        .unwrap();
    type Corrupt = Box<dyn Fn(&mut Pools<f64>)>;
    let cases: Vec<(&str, Corrupt)> = vec![
        ("magic", Box::new(|p| p.indices[0] ^= 1)),
        ("version", Box::new(|p| p.indices[1] = 99)),
        ("scalar", Box::new(|p| p.indices[2] = 4)),
        ("dimension", Box::new(|p| p.indices[3] = 3)),
        ("method", Box::new(|p| p.indices[4] = 9)),
        ("node count", Box::new(|p| p.indices[6] += 1)),
        (
            "graph target",
            Box::new(move |p| p.indices[48 + n + 5] ^= 1),
        ),
        (
            "last index word",
            Box::new(|p| *p.indices.last_mut().unwrap() ^= 1),
        ),
        ("mask byte", Box::new(move |p| p.bytes[n + 3] ^= 1)),
        (
            "point",
            Box::new(|p| p.reals[7] = f64::from_bits(p.reals[7].to_bits() ^ 1)),
        ),
        ("stiffness", Box::new(move |p| p.reals[2 * n + 1] *= 2.0)),
        ("state NaN", Box::new(move |p| p.reals[state] = f64::NAN)),
        ("checksum", Box::new(|p| p.indices[40] ^= 1 << 7)),
        (
            "short reals",
            Box::new(|p| p.reals.truncate(p.reals.len() - 1)),
        ),
        ("short indices", Box::new(|p| p.indices.truncate(40))),
        (
            "short bytes",
            Box::new(|p| p.bytes.truncate(p.bytes.len() - 1)),
        ),
        ("state flag", Box::new(|p| p.indices[42] = 3)),
    ];
    for (name, corrupt) in cases {
        let mut p = good.clone();
        corrupt(&mut p);
        let before = p.clone();
        match p.open() {
            Err(Error::BadPlan { reason }) => println!("{name}: {reason}"),
            Err(e) => panic!("{name}: unexpected {e:?}"),
            Ok(_) => panic!("{name}: corrupted pools accepted"),
        }
        assert!(p.same_bits(&before), "{name}: open wrote to the pools");
    }
    // The wrong `D` or scalar type in the caller's own types.
    let mut p = good.clone();
    assert!(matches!(
        Plan::<f64, 3>::open(&mut p.reals, &mut p.indices, &mut p.bytes),
        Err(Error::BadPlan { .. })
    ));
    let mut r32 = vec![0.0f32; p.reals.len()];
    assert!(matches!(
        Plan::<f32, 2>::open(&mut r32, &mut p.indices, &mut p.bytes),
        Err(Error::BadPlan { .. })
    ));
}

#[test]
fn bad_step_input_is_a_typed_error_and_changes_nothing() {
    let c = Case::<f64>::new(&mesh());
    let n = c.points.len();
    let b = c.nodes.len();
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::QuaternionSpring, amg()));
    let d1 = c.deformed(1);
    let d2 = c.deformed(2);
    let mut out = vec![[0.0; 2]; n];
    pools
        .open()
        .unwrap()
        .step(&PlanMotion::new(&d1), &mut out)
        .unwrap();
    let reference = pools.clone();

    let mut nan = d2.clone();
    nan[3][1] = f64::NAN;
    let mut collapsed = d2.clone();
    collapsed[1] = collapsed[0]; // a zero-length airfoil segment: rotations fail mid-step
    let zero_q = vec![Quat::new(0.0, 0.0, 0.0, 0.0); b];
    let short_q = vec![Quat::identity(); b - 1];
    type BadStep<'m> = (
        &'static str,
        PlanMotion<'m, f64, 2>,
        usize,
        fn(&Error) -> bool,
    );
    let cases: Vec<BadStep<'_>> = vec![
        ("short deformed", PlanMotion::new(&d2[1..]), n, |e| {
            matches!(
                e,
                Error::LengthMismatch {
                    arg: "motion.deformed",
                    ..
                }
            )
        }),
        ("short out", PlanMotion::new(&d2), n - 1, |e| {
            matches!(e, Error::LengthMismatch { arg: "out", .. })
        }),
        ("NaN position", PlanMotion::new(&nan), n, |e| {
            matches!(
                e,
                Error::NonFinite {
                    arg: "motion.deformed",
                    position: 3
                }
            )
        }),
        (
            "NaN origin",
            PlanMotion {
                origin: Some([0.25, f64::NAN]),
                ..PlanMotion::new(&d2)
            },
            n,
            |e| {
                matches!(
                    e,
                    Error::NonFinite {
                        arg: "motion.origin",
                        ..
                    }
                )
            },
        ),
        (
            "zero rotation",
            PlanMotion {
                rotations: RotationSource::PerNode(&zero_q),
                ..PlanMotion::new(&d2)
            },
            n,
            |e| {
                matches!(
                    e,
                    Error::ZeroLength {
                        arg: "motion.rotations",
                        ..
                    }
                )
            },
        ),
        (
            "rotation count",
            PlanMotion {
                rotations: RotationSource::PerNode(&short_q),
                ..PlanMotion::new(&d2)
            },
            n,
            |e| {
                matches!(
                    e,
                    Error::LengthMismatch {
                        arg: "motion.rotations",
                        ..
                    }
                )
            },
        ),
        ("collapsed wall", PlanMotion::new(&collapsed), n, |e| {
            matches!(e, Error::ZeroLengthEdge { .. })
        }),
    ];
    for (name, motion, len, expected) in cases {
        let mut out = vec![[7.0; 2]; len];
        let mut plan = pools.open().unwrap();
        let e = plan.step(&motion, &mut out).unwrap_err();
        assert!(expected(&e), "{name}: {e:?}");
        assert!(out.iter().all(|p| *p == [7.0, 7.0]), "{name}: out written");
        // Validation errors touch nothing at all; a failure inside the step touches only the
        // step workspaces, never the state.
        if name != "collapsed wall" {
            assert!(pools.same_bits(&reference), "{name}: pools written");
        }
        // Either way the next step gives the bits of a plan that never saw the bad input.
        let mut fresh = reference.clone();
        let mut o1 = vec![[0.0; 2]; n];
        let mut o2 = vec![[0.0; 2]; n];
        let r1 = pools
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d2), &mut o1)
            .unwrap();
        let r2 = fresh
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d2), &mut o2)
            .unwrap();
        assert_eq!(bits(&o1), bits(&o2), "{name}");
        assert_eq!(
            (r1.step, r1.solve.iterations),
            (r2.step, r2.solve.iterations)
        );
        pools = reference.clone();
    }
}

#[test]
fn init_errors_are_typed() {
    let c = Case::<f64>::new(&mesh());
    let n = c.points.len();
    let try_sizes = |spec: &PlanSpec<'_, f64, 2>| {
        let ws = Plan::<f64, 2>::work_sizes(spec)?;
        let mut wr = vec![0.0; ws.reals];
        let mut wi = vec![0u32; ws.indices];
        let mut wb = vec![0u8; ws.bytes];
        Plan::<f64, 2>::sizes(
            spec,
            &mut PlanWork {
                reals: &mut wr,
                indices: &mut wi,
                bytes: &mut wb,
            },
        )
    };
    let good = c.spec(PlanMethod::QuaternionSpring, amg());
    try_sizes(&good).unwrap();

    let mut dup = c.nodes.clone();
    dup[5] = dup[4];
    let spec = PlanSpec {
        boundary: &dup,
        ..good
    };
    assert!(matches!(
        try_sizes(&spec),
        Err(Error::DuplicateNode {
            arg: "boundary",
            position: 5,
            ..
        })
    ));
    let airfoil_only = &c.nodes[..c.airfoil];
    let spec = PlanSpec {
        boundary: &c.nodes[c.airfoil..],
        elements: None,
        ..good
    };
    try_sizes(&spec).unwrap();
    let spec = PlanSpec {
        boundary: airfoil_only,
        elements: None,
        ..good
    };
    // The far field is free: still anchored (the airfoil is fixed), so this plan is valid.
    try_sizes(&spec).unwrap();
    let spec = PlanSpec {
        boundary: &[],
        elements: None,
        ..good
    };
    assert!(matches!(
        try_sizes(&spec),
        Err(Error::InvalidParameter {
            arg: "boundary",
            ..
        })
    ));
    // Sliding kinds are refused (the place for them is reserved).
    let mut kinds = c.fixed();
    let dirs = vec![[0.0, 1.0]; n];
    let spec = PlanSpec {
        constraints: Some(Constraints::new(&kinds, &dirs).unwrap()),
        ..good
    };
    try_sizes(&spec).unwrap();
    let free = kinds.iter().position(|&k| k == 0).unwrap();
    kinds[free] = 2;
    let spec = PlanSpec {
        constraints: Some(Constraints::new(&kinds, &dirs).unwrap()),
        ..good
    };
    assert!(matches!(
        try_sizes(&spec),
        Err(Error::InvalidParameter {
            arg: "constraints",
            ..
        })
    ));
    // Pools one entry short.
    let (pools, sizes) = Pools::build(&good);
    let ws = Plan::<f64, 2>::work_sizes(&good).unwrap();
    let mut wr = vec![0.0; ws.reals];
    let mut wi = vec![0u32; ws.indices];
    let mut wb = vec![0u8; ws.bytes];
    let mut r = vec![0.0; sizes.reals - 1];
    let mut i = vec![0u32; sizes.indices];
    let mut y = vec![0u8; sizes.bytes];
    let e = Plan::init(
        &good,
        &mut PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        },
        &mut r,
        &mut i,
        &mut y,
    )
    .unwrap_err();
    assert!(matches!(e, Error::BufferTooSmall { arg: "reals", .. }));
    assert!(r.iter().all(|&x| x == 0.0) && i.iter().all(|&x| x == 0));
    // Larger pools work and give the same plan.
    let mut r = vec![0.0; sizes.reals + 3];
    let mut i = vec![0u32; sizes.indices + 3];
    let mut y = vec![0u8; sizes.bytes + 3];
    Plan::init(
        &good,
        &mut PlanWork {
            reals: &mut wr,
            indices: &mut wi,
            bytes: &mut wb,
        },
        &mut r,
        &mut i,
        &mut y,
    )
    .unwrap();
    assert_eq!(&i[..sizes.indices], &pools.indices[..]);
    assert_eq!(&y[..sizes.bytes], &pools.bytes[..]);
}

/// 3D: the tiny triangulated airfoil extruded over 3 layers (wedges; boundary = airfoil, far
/// field and both end caps, quads and triangles), the wall pitching about the z axis. Cold
/// quaternion steps (`V = 7`) equal `deform_spring_with`, warm spring steps (`V = 3`) equal
/// `solve_linear_with` from the same guess; a copy resumes.
#[test]
fn three_dimensional_plans_equal_the_stateless_calls() {
    let m2 = naca_triangulated(&AirfoilGrid::tiny()).unwrap();
    let mesh = extrude(&m2, 0.5, 3).unwrap();
    let c = Case::<f64, 3>::new(&mesh);
    let n = c.points.len();
    let solver = amg::<f64>();
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::QuaternionSpring, solver));
    let mut out = vec![[0.0; 3]; n];
    for s in 1..=5 {
        let d = c.deformed(s);
        let motion = PlanMotion {
            start: Start::Cold,
            ..PlanMotion::new(&d)
        };
        let rep = pools
            .open_d::<3>()
            .unwrap()
            .step(&motion, &mut out)
            .unwrap();
        let (expect, erep) = stateless_quaternion::<f64, 3>(&c, &solver, s, 20);
        assert_eq!(bits(&out), bits(&expect), "step {s}");
        assert_eq!(rep.solve.iterations, erep.iterations);
    }
    let (mut pools, _) = Pools::build(&c.spec(PlanMethod::Spring, solver));
    let mut history = History::default();
    let mut copy = None;
    for s in 1..=5 {
        let d = c.deformed(s);
        let rep = pools
            .open_d::<3>()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut out)
            .unwrap();
        let mut guess = history.guess(&rep, n);
        let (expect, _) = stateless_spring(&c, &solver, s, &mut guess);
        history.push(guess);
        assert_eq!(bits(&out), bits(&expect), "step {s}");
        assert_eq!(rep.warm, s > 1);
        if s == 3 {
            copy = Some(pools.clone());
        }
    }
    let mut copy = copy.unwrap();
    let mut again = vec![[0.0; 3]; n];
    for s in 4..=5 {
        let d = c.deformed(s);
        copy.open_d::<3>()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut again)
            .unwrap();
    }
    assert_eq!(bits(&out), bits(&again));
}

/// The one-level solvers a plan can use.
fn one_level<T: Real>() -> [LinearMethod<T>; 6] {
    let omega = T::from_f64(1.5);
    [
        LinearMethod::Jacobi,
        LinearMethod::GaussSeidel,
        LinearMethod::Sor { omega },
        LinearMethod::Cg {
            preconditioner: Preconditioner::None,
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega },
        },
    ]
}

/// `Plan::capacity` (counts only, `const`) is exactly `Plan::sizes` for every one-level
/// solver and both methods, with and without elements, 2D and 3D, f32 and f64, and larger
/// counts give sizes at least as large; `Plan::work_capacity` is `Plan::work_sizes`.
fn capacity_equals_sizes<T: Real, const D: usize>(c: &Case<T, D>) {
    for method in [PlanMethod::Spring, PlanMethod::QuaternionSpring] {
        for with_elements in [false, true] {
            for solver in one_level::<T>() {
                let mut spec = c.spec(method, PlanSolver::Method(solver));
                if !with_elements {
                    spec.elements = None;
                }
                let counts = PlanCounts {
                    nodes: c.points.len(),
                    edges: c.targets.len(),
                    boundary: c.nodes.len(),
                    elements: with_elements.then_some((c.el_kinds.len(), c.el_nodes.len())),
                };
                let ws = Plan::<T, D>::work_sizes(&spec).unwrap();
                assert_eq!(Plan::<T, D>::work_capacity(&counts), ws);
                let mut wr = vec![T::ZERO; ws.reals];
                let mut wi = vec![0u32; ws.indices];
                let mut wb = vec![0u8; ws.bytes];
                let mut work = PlanWork {
                    reals: &mut wr,
                    indices: &mut wi,
                    bytes: &mut wb,
                };
                let sizes = Plan::<T, D>::sizes(&spec, &mut work).unwrap();
                let what = format!("{method:?} {solver:?} elements {with_elements} D {D}");
                assert_eq!(
                    Plan::<T, D>::capacity(&counts, method, &solver),
                    Some(sizes),
                    "{what}"
                );
                let more = PlanCounts {
                    nodes: counts.nodes + 3,
                    edges: counts.edges + 10,
                    boundary: counts.boundary + 1,
                    elements: Some((c.el_kinds.len() + 1, c.el_nodes.len() + 4)),
                };
                let bound = Plan::<T, D>::capacity(&more, method, &solver).unwrap();
                assert!(
                    bound.reals >= sizes.reals
                        && bound.indices >= sizes.indices
                        && bound.bytes >= sizes.bytes,
                    "{what}"
                );
            }
        }
    }
}

#[test]
fn capacity_from_counts_equals_the_exact_sizes() {
    let m2 = mesh();
    capacity_equals_sizes(&Case::<f64>::new(&m2));
    capacity_equals_sizes(&Case::<f32>::new(&m2));
    let m3 = extrude(&naca_triangulated(&AirfoilGrid::tiny()).unwrap(), 0.5, 3).unwrap();
    capacity_equals_sizes(&Case::<f64, 3>::new(&m3));
    capacity_equals_sizes(&Case::<f32, 3>::new(&m3));
    // Sizes beyond usize or u32 are None, not a wrapped number.
    let huge = PlanCounts {
        nodes: usize::MAX / 2,
        edges: 10,
        boundary: 1,
        elements: None,
    };
    let cg = LinearMethod::<f64>::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    assert_eq!(
        Plan::<f64, 3>::capacity(&huge, PlanMethod::Spring, &cg),
        None
    );
    let beyond_u32 = PlanCounts {
        nodes: 1 << 30,
        ..huge
    };
    assert_eq!(
        Plan::<f64, 3>::capacity(&beyond_u32, PlanMethod::Spring, &cg),
        None
    );
}

/// A structured grid of `GX × GY` nodes split into triangles (one diagonal per quad), its
/// perimeter prescribed: counts known at compile time.
const GX: usize = 7;
const GY: usize = 5;
const GRID: PlanCounts = PlanCounts {
    nodes: GX * GY,
    edges: 2 * ((GX - 1) * GY + GX * (GY - 1) + (GX - 1) * (GY - 1)),
    boundary: 2 * (GX + GY) - 4,
    elements: None,
};
const GRID_CG: LinearMethod<f64> = LinearMethod::Cg {
    preconditioner: Preconditioner::Jacobi,
};
const GRID_POOLS: PlanSizes = match Plan::<f64, 2>::capacity(&GRID, PlanMethod::Spring, &GRID_CG) {
    Some(s) => s,
    None => panic!("too large"),
};
const GRID_WORK: PlanSizes = Plan::<f64, 2>::work_capacity(&GRID);
type GridPools =
    PlanStorage<f64, { GRID_POOLS.reals }, { GRID_POOLS.indices }, { GRID_POOLS.bytes }>;
type GridWork = PlanStorage<f64, { GRID_WORK.reals }, { GRID_WORK.indices }, { GRID_WORK.bytes }>;
/// One real short of what the plan needs.
type ShortPools =
    PlanStorage<f64, { GRID_POOLS.reals - 1 }, { GRID_POOLS.indices }, { GRID_POOLS.bytes }>;

/// The grid: points (interior nudged), triangle cells, graph, perimeter.
struct Grid {
    points: Vec<[f64; 2]>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    boundary: Vec<u32>,
}

impl Grid {
    fn new() -> Self {
        let id = |i: usize, j: usize| (i + GX * j) as u32;
        let mut points = Vec::new();
        let mut boundary = Vec::new();
        for j in 0..GY {
            for i in 0..GX {
                let edge = i == 0 || j == 0 || i == GX - 1 || j == GY - 1;
                let nudge = if edge {
                    0.0
                } else {
                    0.01 * ((i * 7 + j * 3) % 5) as f64
                };
                points.push([i as f64 + nudge, j as f64 * 0.8 - nudge]);
                if edge {
                    boundary.push(id(i, j));
                }
            }
        }
        let (mut offs, mut nodes) = (vec![0u32], Vec::new());
        for j in 0..GY - 1 {
            for i in 0..GX - 1 {
                for t in [
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1)],
                    [id(i, j), id(i + 1, j + 1), id(i, j + 1)],
                ] {
                    nodes.extend(t);
                    offs.push(nodes.len() as u32);
                }
            }
        }
        let kinds = vec![deform_kernel::CellKind::Triangle.vtk_code(); offs.len() - 1];
        let cells = Cells::new(points.len(), &offs, &nodes, &kinds).unwrap();
        let mut offsets = vec![0u32; points.len() + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
        let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        Grid {
            points,
            offsets,
            targets,
            boundary,
        }
    }

    fn spec(&self) -> PlanSpec<'_, f64, 2> {
        PlanSpec {
            points: &self.points,
            graph: Graph::new(&self.offsets, &self.targets).unwrap(),
            boundary: &self.boundary,
            elements: None,
            constraints: None,
            method: PlanMethod::Spring,
            stiffness: PlanStiffness::Batina { exponent: 1.0 },
            solver: PlanSolver::Method(GRID_CG),
            options: options(),
            renumber: deform_kernel::plan::PlanOrder::AsGiven,
        }
    }
}

/// Storage declared from `Plan::capacity` at compile time holds the plan exactly
/// (`used() == capacity()`), steps with the bits of heap pools, clones into a checkpoint that
/// resumes bit for bit, and one entry less is `BufferTooSmall` with the length needed.
#[test]
fn static_storage_sized_at_compile_time_holds_the_plan() {
    static WORK_TEMPLATE: GridWork = GridWork::new();
    let g = Grid::new();
    let spec = g.spec();
    assert_eq!(g.targets.len(), GRID.edges);
    assert_eq!(g.boundary.len(), GRID.boundary);
    let mut work = WORK_TEMPLATE.clone();
    let mut storage = Box::new(GridPools::new());
    assert_eq!(
        storage.init(&spec, &mut work.work()).unwrap().used(),
        GRID_POOLS
    );
    assert_eq!(storage.capacity(), GRID_POOLS);
    // Debug shows the capacity, not the pools.
    assert_eq!(
        format!("{storage:?}"),
        format!(
            "PlanStorage {{ reals: {}, indices: {}, bytes: {} }}",
            GRID_POOLS.reals, GRID_POOLS.indices, GRID_POOLS.bytes
        )
    );
    let (mut heap, _) = Pools::build(&spec);
    let deformed = |s: usize| -> Vec<[f64; 2]> {
        g.boundary
            .iter()
            .map(|&i| {
                let p = g.points[i as usize];
                if (i as usize) < GX {
                    [p[0] + 0.05 * s as f64, p[1] + 0.1 * s as f64]
                } else {
                    p
                }
            })
            .collect()
    };
    let n = g.points.len();
    let (mut a, mut b) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
    let mut checkpoint = None;
    for s in 1..=4 {
        let d = deformed(s);
        let ra = storage
            .open::<2>()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut a)
            .unwrap();
        let rb = heap
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut b)
            .unwrap();
        assert_eq!(bits(&a), bits(&b), "step {s}");
        assert_eq!(ra.solve.iterations, rb.solve.iterations);
        if s == 2 {
            checkpoint = Some(storage.clone());
        }
    }
    let mut resumed = checkpoint.unwrap();
    for s in 3..=4 {
        let d = deformed(s);
        resumed
            .open::<2>()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut b)
            .unwrap();
    }
    assert_eq!(bits(&a), bits(&b));
    let mut short = Box::new(ShortPools::new());
    let untouched = short.clone();
    assert_eq!(
        short.init(&spec, &mut work.work()).unwrap_err(),
        Error::BufferTooSmall {
            arg: "reals",
            needed: GRID_POOLS.reals,
            actual: GRID_POOLS.reals - 1
        }
    );
    assert_eq!(short.pools(), untouched.pools());
}
