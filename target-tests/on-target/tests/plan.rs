//! Prepared plans on target, in f32 and f64, on the small jittered triangle mesh (perimeter
//! prescribed): a few time steps through a plan give the bits of the stateless calls with the
//! same initial guesses (linear springs with the multigrid solver, warm: the previous solution,
//! then the extrapolation of the last two; the quaternion method with rigid rotations, cold),
//! copied pools resume bit for bit, and bad input or a corrupted header is a typed error with
//! the output untouched. Storage is `PlanStorage`, sized at compile time by `Plan::capacity`
//! where the solver is one-level (exactly what the plan uses, checked), one of them a
//! `static`; storage one entry short is a typed refusal.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::plan::{
    Plan, PlanCounts, PlanMethod, PlanMotion, PlanSizes, PlanSolver, PlanSpec, PlanStiffness,
    PlanStorage, Start,
};
use deform_kernel::quaternion::{
    deform_spring_scratch_len, deform_spring_with, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, LinearMethod,
    LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Error, Quat, Real};
use deform_on_target::mesh::{turned_bottom_row as deformed, Mesh, EDGES, N, NB, NE};
use deform_on_target::same_bits;

/// Mesh counts, known at compile time.
const COUNTS: PlanCounts = PlanCounts {
    nodes: N,
    edges: EDGES,
    boundary: NB,
    elements: None,
};
/// The one-level solver of the quaternion plans.
const CG: LinearMethod<f32> = LinearMethod::Cg {
    preconditioner: Preconditioner::Jacobi,
};
/// Exact pools of the quaternion plan with CG, from the counts alone (the sizes do not
/// depend on the scalar type).
const QUATERNION_CG: PlanSizes =
    match Plan::<f32, 2>::capacity(&COUNTS, PlanMethod::QuaternionSpring, &CG) {
        Some(s) => s,
        None => panic!("the plan does not fit"),
    };
/// Exact pools of the spring plan with CG.
const SPRING_CG: PlanSizes = match Plan::<f32, 2>::capacity(&COUNTS, PlanMethod::Spring, &CG) {
    Some(s) => s,
    None => panic!("the plan does not fit"),
};
/// Transient work, exact.
const WORK: PlanSizes = Plan::<f32, 2>::work_capacity(&COUNTS);
/// Steps per run.
const STEPS: usize = 4;

/// Pools for the multigrid plans: their sizes depend on the hierarchy the setup finds, so
/// this is a bound (measured with `Plan::sizes`, which the test checks against it).
type Pools<T> = PlanStorage<T, AMG_REALS, AMG_INDICES, 128>;
/// The bound of the multigrid plans' real and index pools.
const AMG_REALS: usize = 3072;
const AMG_INDICES: usize = 2048;
/// Pools of the quaternion plan with CG, exactly as large as `Plan::capacity` says.
type QuaternionPools<T> =
    PlanStorage<T, { QUATERNION_CG.reals }, { QUATERNION_CG.indices }, { QUATERNION_CG.bytes }>;
/// The transient work.
type Work<T> = PlanStorage<T, { WORK.reals }, { WORK.indices }, { WORK.bytes }>;

fn amg<T: Real>() -> PlanSolver<T> {
    PlanSolver::Amg(AmgOptions {
        max_coarse: 4,
        ..AmgOptions::default()
    })
}

/// The plan of `m` with its perimeter prescribed.
fn spec<T: Real>(m: &Mesh<T>, method: PlanMethod, solver: PlanSolver<T>) -> PlanSpec<'_, T, 2> {
    PlanSpec {
        points: &m.points,
        graph: m.graph(),
        boundary: &m.boundary,
        elements: None,
        constraints: None,
        method,
        stiffness: PlanStiffness::Batina { exponent: T::ONE },
        solver,
        options: SolveOptions::default(),
        renumber: deform_kernel::plan::PlanOrder::AsGiven,
    }
}

/// Builds a plan into `pools`; returns the exact sizes (`Plan::sizes`).
fn build<T: Real, const R: usize, const I: usize, const B: usize>(
    m: &Mesh<T>,
    method: PlanMethod,
    solver: PlanSolver<T>,
    pools: &mut PlanStorage<T, R, I, B>,
) -> PlanSizes {
    defmt::assert!(m.used == EDGES);
    let spec = spec(m, method, solver);
    let mut work = Work::<T>::new();
    defmt::assert!(Plan::<T, 2>::work_sizes(&spec) == Ok(work.capacity()));
    let sizes = Plan::<T, 2>::sizes(&spec, &mut work.work()).unwrap();
    let p = pools.init(&spec, &mut work.work()).unwrap();
    defmt::assert!(p.used() == sizes);
    sizes
}

/// Linear springs with the multigrid solver: warm steps equal the stateless solve from the
/// same guess; a copy of the pools resumes with the same bits.
fn spring_plan<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let mut pools = Pools::<T>::new();
    build(&m, PlanMethod::Spring, amg(), &mut pools);
    // The stateless side: system and hierarchy built as the plan does.
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
    let PlanSolver::Amg(opts) = amg::<T>() else {
        return;
    };
    let mut work = [0u32; WORK.indices];
    let mut index = [0u32; AMG_INDICES];
    let mut values = [T::ZERO; AMG_REALS];
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
    let solver = LinearSolver::Amg(&h);
    let mut scratch = [[T::ZERO; 2]; 8 * N];
    let len = solve_linear_with_scratch_len(&solver, N);
    let mut last = [[T::ZERO; 2]; N];
    let mut before = [[T::ZERO; 2]; N];
    let mut out = [[T::ZERO; 2]; N];
    let mut copy = None;
    for s in 1..=STEPS {
        let d = deformed(&m, s);
        let rep = pools
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut out)
            .unwrap();
        // The guess the plan used: zero, the last solution or `x_n + (x_n − x_{n−1})`.
        let mut guess = [[T::ZERO; 2]; N];
        if rep.warm {
            for ((g, a), b) in guess.iter_mut().zip(&last).zip(&before) {
                *g = if rep.extrapolated {
                    [a[0] + (a[0] - b[0]), a[1] + (a[1] - b[1])]
                } else {
                    *a
                };
            }
        }
        for (&i, di) in m.boundary.iter().zip(&d) {
            let p = m.points[i as usize];
            guess[i as usize] = [di[0] - p[0], di[1] - p[1]];
        }
        let r = sys
            .solve_linear_with(
                &mut guess,
                solver,
                &SolveOptions::default(),
                &mut scratch[..len],
            )
            .unwrap();
        defmt::assert!(r.iterations == rep.solve.iterations && rep.warm == (s > 1));
        defmt::assert!(rep.extrapolated == (s > 2));
        before = last;
        last = guess;
        let mut expect = [[T::ZERO; 2]; N];
        for ((e, p), v) in expect.iter_mut().zip(&m.points).zip(&guess) {
            *e = [p[0] + v[0], p[1] + v[1]];
        }
        for (&i, di) in m.boundary.iter().zip(&d) {
            expect[i as usize] = *di;
        }
        defmt::assert!(same_bits(&out, &expect));
        if s == 2 {
            copy = Some(pools.clone());
        }
    }
    // Resume the copy taken after step 2: steps 3 and 4 again, same bits.
    let Some(mut copy) = copy else {
        return;
    };
    let mut again = [[T::ZERO; 2]; N];
    for s in 3..=STEPS {
        let d = deformed(&m, s);
        let rep = copy
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut again)
            .unwrap();
        defmt::assert!(rep.step == s as u64);
    }
    defmt::assert!(same_bits(&out, &again));
}

/// The quaternion method with rigid rotations and CG: cold steps equal `deform_spring_with`.
fn quaternion_plan<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut pools = QuaternionPools::<T>::new();
    let sizes = build(
        &m,
        PlanMethod::QuaternionSpring,
        PlanSolver::Method(cg),
        &mut pools,
    );
    // Storage from `Plan::capacity` is exactly what the plan uses.
    defmt::assert!(sizes == QUATERNION_CG && pools.capacity() == QUATERNION_CG);
    let g = m.graph();
    let mut k = [T::ZERO; NE];
    let k = &mut k[..m.used];
    batina_stiffness(&g, &m.points, T::ONE, k).unwrap();
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).unwrap();
    let mut out = [[T::ZERO; 2]; N];
    let mut expect = [[T::ZERO; 2]; N];
    for s in 1..=STEPS {
        let d = deformed(&m, s);
        let q = Quat::from_rotation_z(T::from_f64((4.0 * s as f64).to_radians()));
        let motion = PlanMotion {
            rotations: RotationSource::Rigid(q),
            start: Start::Cold,
            ..PlanMotion::new(&d)
        };
        let rep = pools.open().unwrap().step(&motion, &mut out).unwrap();
        let bm = BoundaryMotion {
            nodes: &m.boundary,
            deformed: &d,
            elements: None,
            rotations: RotationSource::Rigid(q),
            origin: None,
        };
        let mut t = [[T::ZERO; 2]; N];
        let mut r = [Quat::identity(); N];
        let mut sc = [T::ZERO; 3 * NB + N];
        let sl = deform_spring_scratch_len::<2>(N, NB);
        let mut v = [T::ZERO; 36 * N];
        let (_, erep) = deform_spring_with::<T, 2>(
            &m.points,
            &bm,
            &sys,
            LinearSolver::Method(cg),
            &SolveOptions::default(),
            &mut t,
            &mut r,
            &mut sc[..sl],
            &mut v,
            &mut expect,
        )
        .unwrap();
        defmt::assert!(erep.iterations == rep.solve.iterations && !rep.warm);
        defmt::assert!(same_bits(&out, &expect));
    }
}

/// Bad step input and a corrupted header: typed errors, `out` untouched.
fn errors<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let mut pools = Pools::<T>::new();
    build(&m, PlanMethod::Spring, amg(), &mut pools);
    let mut d = deformed(&m, 1);
    d[3][0] = T::from_f64(f64::NAN);
    let mut out = [[T::HALF; 2]; N];
    let e = pools.open().unwrap().step(&PlanMotion::new(&d), &mut out);
    defmt::assert!(matches!(
        e,
        Err(Error::NonFinite {
            arg: "motion.deformed",
            position: 3
        })
    ));
    let e = pools
        .open()
        .unwrap()
        .step(&PlanMotion::new(&d[1..]), &mut out);
    defmt::assert!(matches!(e, Err(Error::LengthMismatch { .. })));
    defmt::assert!(out.iter().all(|p| p[0] == T::HALF && p[1] == T::HALF));
    let mut bad = pools.clone();
    bad.pools_mut().1[60] ^= 1;
    defmt::assert!(matches!(bad.open::<2>(), Err(Error::BadPlan { .. })));
    let mut bad = pools.clone();
    bad.pools_mut().1[0] = 0;
    defmt::assert!(matches!(bad.open::<2>(), Err(Error::BadPlan { .. })));
    // Storage one index short: a typed refusal with the length needed, nothing written.
    let mut short =
        PlanStorage::<T, { SPRING_CG.reals }, { SPRING_CG.indices - 1 }, { SPRING_CG.bytes }>::new(
        );
    let cg = PlanSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let spec_ok = spec(&m, PlanMethod::Spring, cg);
    let mut work = Work::<T>::new();
    let e = short.init(&spec_ok, &mut work.work());
    defmt::assert!(matches!(
        e,
        Err(Error::BufferTooSmall { arg: "indices", needed, actual })
            if needed == SPRING_CG.indices && actual == SPRING_CG.indices - 1
    ));
    defmt::assert!(short.pools().1.iter().all(|&w| w == 0));
}

/// A plan in a `static` (sized from the counts at compile time, nothing by hand) steps with
/// the bits of the same plan on the stack.
fn static_plan() {
    type Storage =
        PlanStorage<f32, { SPRING_CG.reals }, { SPRING_CG.indices }, { SPRING_CG.bytes }>;
    let Some(fixed) = cortex_m::singleton!(: Storage = Storage::new()) else {
        defmt::panic!("singleton taken twice");
    };
    let m = Mesh::<f32>::new(0.25);
    let cg = PlanSolver::Method(CG);
    defmt::assert!(build(&m, PlanMethod::Spring, cg, fixed) == SPRING_CG);
    let mut local = Storage::new();
    build(&m, PlanMethod::Spring, cg, &mut local);
    let mut a = [[0.0f32; 2]; N];
    let mut b = [[0.0f32; 2]; N];
    for s in 1..=STEPS {
        let d = deformed(&m, s);
        let ra = fixed
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut a)
            .unwrap();
        let rb = local
            .open()
            .unwrap()
            .step(&PlanMotion::new(&d), &mut b)
            .unwrap();
        defmt::assert!(same_bits(&a, &b) && ra.solve.iterations == rb.solve.iterations);
        defmt::assert!(ra.solve.converged && ra.warm == (s > 1));
    }
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn spring_plan_f64() {
        spring_plan::<f64>();
    }

    #[test]
    fn spring_plan_f32() {
        spring_plan::<f32>();
    }

    #[test]
    fn quaternion_plan_f64() {
        quaternion_plan::<f64>();
    }

    #[test]
    fn quaternion_plan_f32() {
        quaternion_plan::<f32>();
    }

    #[test]
    fn static_storage() {
        static_plan();
    }

    #[test]
    fn typed_errors() {
        errors::<f64>();
        errors::<f32>();
    }
}
