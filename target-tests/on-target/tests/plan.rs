//! Prepared plans on target, in f32 and f64, on the small jittered triangle mesh (perimeter
//! prescribed): a few time steps through a plan give the bits of the stateless calls with the
//! same initial guesses (linear springs with the multigrid solver, warm: the previous solution,
//! then the extrapolation of the last two; the quaternion method with rigid rotations, cold), copied pools resume bit for bit, and bad input or a corrupted
//! header is a typed error with the output untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::deformation::{
    deform_spring_scratch_len, deform_spring_with, BoundaryMotion, RotationSource,
};
use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_with, solve_linear_with_scratch_len, AmgHierarchy, AmgOptions,
    LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Error, Quat, Real};
use deform_on_target::mesh::{turned_bottom_row as deformed, Mesh, N, NB, NE};
use deform_on_target::same_bits;

/// Pool lengths (generous for the 30-node mesh; the exact sizes are checked against them).
const REALS: usize = 3072;
const INDICES: usize = 2048;
const BYTES: usize = 128;
/// Transient work (`4 (N + E) + 64` indices).
const WORK: usize = 4 * (N + NE) + 64;
/// Steps per run.
const STEPS: usize = 4;

/// Owned pools.
#[derive(Clone, Copy)]
struct Pools<T> {
    reals: [T; REALS],
    indices: [u32; INDICES],
    bytes: [u8; BYTES],
}

impl<T: Real> Pools<T> {
    fn new() -> Self {
        Pools {
            reals: [T::ZERO; REALS],
            indices: [0; INDICES],
            bytes: [0; BYTES],
        }
    }

    fn open(&mut self) -> deform_kernel::Result<Plan<'_, T, 2>> {
        Plan::open(&mut self.reals, &mut self.indices, &mut self.bytes)
    }
}

fn amg<T: Real>() -> PlanSolver<T> {
    PlanSolver::Amg(AmgOptions {
        max_coarse: 4,
        ..AmgOptions::default()
    })
}

/// Builds a plan into `pools`.
fn build<T: Real>(m: &Mesh<T>, method: PlanMethod, solver: PlanSolver<T>, pools: &mut Pools<T>) {
    let spec = PlanSpec {
        points: &m.points,
        graph: m.graph(),
        boundary: &m.boundary,
        elements: None,
        constraints: None,
        method,
        stiffness: PlanStiffness::Batina { exponent: T::ONE },
        solver,
        options: SolveOptions::default(),
    };
    let mut wr = [T::ZERO; NE];
    let mut wi = [0u32; WORK];
    let mut wb = [0u8; N];
    let ws = Plan::<T, 2>::work_sizes(&spec);
    defmt::assert!(ws.reals <= NE && ws.indices <= WORK && ws.bytes <= N);
    let mut work = PlanWork {
        reals: &mut wr,
        indices: &mut wi,
        bytes: &mut wb,
    };
    let sizes = Plan::<T, 2>::sizes(&spec, &mut work).unwrap();
    defmt::assert!(sizes.reals <= REALS && sizes.indices <= INDICES && sizes.bytes <= BYTES);
    let p = Plan::init(
        &spec,
        &mut work,
        &mut pools.reals,
        &mut pools.indices,
        &mut pools.bytes,
    )
    .unwrap();
    defmt::assert!(p.used() == sizes);
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
    let mut work = [0u32; WORK];
    let mut index = [0u32; INDICES];
    let mut values = [T::ZERO; REALS];
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
        let r = solve_linear_with(
            &sys,
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
            copy = Some(pools);
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
    let mut pools = Pools::<T>::new();
    build(
        &m,
        PlanMethod::QuaternionSpring,
        PlanSolver::Method(cg),
        &mut pools,
    );
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
        let mut v = [[T::ZERO; 6]; 6 * N];
        let (_, erep) = deform_spring_with::<T, 2, 6>(
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
    let mut bad = pools;
    bad.indices[60] ^= 1;
    defmt::assert!(matches!(bad.open(), Err(Error::BadPlan { .. })));
    let mut bad = pools;
    bad.indices[0] = 0;
    defmt::assert!(matches!(bad.open(), Err(Error::BadPlan { .. })));
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
    fn typed_errors() {
        errors::<f64>();
        errors::<f32>();
    }
}
