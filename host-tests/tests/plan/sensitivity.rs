//! `Plan::tangent` and `Plan::adjoint` (kernel/src/plan/sensitivity.rs), the derivative of a
//! plan's last step, against the stateless sensitivities on the same mesh, motion and solver
//! (their own hierarchy, set up with the plan's options): after a cold last step bit for bit
//! (the stored field is the stateless base solve's bits), after warm steps to the solver's
//! tolerance (the quaternion method; the linear springs' derivative does not depend on the
//! step, so bit for bit still); the dot-product identity `⟨J v, w⟩ = ⟨v, Jᵀ w⟩`; a
//! renumbered plan against the plain one; bad input (no step yet, another motion, short
//! scratch, lengths, non-finite input, a stationary solver's adjoint) is a typed error that
//! leaves `out` and the plan unchanged. Linear springs and the quaternion method, 2D and 3D,
//! f32 and f64, multigrid and CG.

use super::*;
use deform_kernel::plan::PlanOrder;
use deform_kernel::quaternion::{
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
};
use deform_kernel::sensitivity::{spring_adjoint, spring_adjoint_scratch_len, spring_tangent};

/// Deterministic values in [-1, 1).
fn field<T: Real, const D: usize>(n: usize, seed: u64) -> Vec<[T; D]> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            std::array::from_fn(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                T::from_f64((s >> 11) as f64 / (1u64 << 52) as f64 - 1.0)
            })
        })
        .collect()
}

/// A tangent `J v` (`N` points) and an adjoint `Jᵀ w` (`B` points).
type Derivatives<T, const D: usize> = (Vec<[T; D]>, Vec<[T; D]>);

/// The plan's and the stateless derivatives at the last step, with their `v` and `w`.
struct Pair<T, const D: usize> {
    plan: Derivatives<T, D>,
    stateless: Derivatives<T, D>,
    v: Vec<[T; D]>,
    w: Vec<[T; D]>,
}

/// Steps `plan` through `steps` steps of `c`'s pitching motion (warm, the last one `last`).
fn run<T: Real, const D: usize>(
    plan: &mut Plan<'_, T, D>,
    c: &Case<T, D>,
    steps: usize,
    last: Start,
) {
    let mut out = vec![[T::ZERO; D]; c.points.len()];
    for s in 1..=steps {
        let d = c.deformed(s);
        let start = if s == steps { last } else { Start::Warm };
        plan.step(
            &PlanMotion {
                start,
                ..PlanMotion::new(&d)
            },
            &mut out,
        )
        .unwrap();
    }
}

/// The plan's tangent of `v` and adjoint of `w` at `motion`.
fn plan_derivatives<T: Real, const D: usize>(
    plan: &Plan<'_, T, D>,
    motion: &PlanMotion<'_, T, D>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> Derivatives<T, D> {
    let mut scratch = vec![T::ZERO; plan.sensitivity_scratch_len()];
    let mut jv = vec![[T::ZERO; D]; plan.node_count()];
    let mut jw = vec![[T::ZERO; D]; plan.boundary_len()];
    plan.tangent(motion, v, &mut scratch, &mut jv).unwrap();
    plan.adjoint(motion, w, &mut scratch, &mut jw).unwrap();
    (jv, jw)
}

/// A plan of `method` and `solver` stepped `steps` times (the last one `last`), its
/// derivatives and the stateless ones at the last motion.
fn pair<T: Real, const D: usize>(
    c: &Case<T, D>,
    method: PlanMethod,
    solver: PlanSolver<T>,
    steps: usize,
    last: Start,
) -> Pair<T, D> {
    let (n, b) = (c.points.len(), c.nodes.len());
    let (mut pools, _) = Pools::build(&c.spec(method, solver));
    let mut plan = pools.open_d::<D>().unwrap();
    run(&mut plan, c, steps, last);
    let d = c.deformed(steps);
    let (v, w) = (field::<T, D>(b, 11), field::<T, D>(n, 12));
    let plan = plan_derivatives(&plan, &PlanMotion::new(&d), &v, &w);
    let stateless = with_system(c, &solver, |sys, ls| match method {
        PlanMethod::Spring => stateless_springs(c, sys, ls, &v, &w),
        PlanMethod::QuaternionSpring => stateless_quaternion_pair(c, &d, sys, ls, &v, &w),
    });
    Pair {
        plan,
        stateless,
        v,
        w,
    }
}

/// `spring_tangent` (the boundary perturbation at the fixed nodes, zero elsewhere) and
/// `spring_adjoint` (read at the boundary nodes).
fn stateless_springs<T: Real, const D: usize>(
    c: &Case<T, D>,
    sys: &SpringSystem<'_, T>,
    ls: LinearSolver<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> Derivatives<T, D> {
    let n = c.points.len();
    let mut dx = vec![[T::ZERO; D]; n];
    for (k, &i) in c.nodes.iter().enumerate() {
        dx[i as usize] = v[k];
    }
    let mut s = vec![[T::ZERO; D]; solve_linear_with_scratch_len(&ls, n)];
    spring_tangent(sys, ls, &options(), &mut dx, &mut s).unwrap();
    let mut g = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; spring_adjoint_scratch_len::<T, D>(&ls, n)];
    spring_adjoint(sys, ls, &options(), w, &mut g, &mut s).unwrap();
    (dx, c.nodes.iter().map(|&i| g[i as usize]).collect())
}

/// `deform_spring_tangent` and `deform_spring_adjoint` at the deformed boundary `d`.
fn stateless_quaternion_pair<T: Real, const D: usize>(
    c: &Case<T, D>,
    d: &[[T; D]],
    sys: &SpringSystem<'_, T>,
    ls: LinearSolver<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> Derivatives<T, D> {
    let (n, b) = (c.points.len(), c.nodes.len());
    let motion = BoundaryMotion {
        nodes: &c.nodes,
        deformed: d,
        elements: Some(c.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let mut s = vec![T::ZERO; deform_spring_sensitivity_scratch_len::<T, D>(&ls, n, b)];
    let (mut jv, mut jw) = (vec![[T::ZERO; D]; n], vec![[T::ZERO; D]; b]);
    let o = options();
    deform_spring_tangent(&c.points, &motion, sys, ls, &o, v, &mut s, &mut jv).unwrap();
    deform_spring_adjoint(&c.points, &motion, sys, ls, &o, w, &mut s, &mut jw).unwrap();
    (jv, jw)
}

/// `max |a − b| / max |b|`.
fn relative<T: Real, const D: usize>(a: &[[T; D]], b: &[[T; D]]) -> f64 {
    let flat = |x: &[[T; D]]| x.iter().flatten().map(|v| v.to_f64()).collect::<Vec<_>>();
    let (a, b) = (flat(a), flat(b));
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

/// `⟨a, b⟩` in f64.
fn dot<T: Real, const D: usize>(a: &[[T; D]], b: &[[T; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| x.to_f64() * y.to_f64())
        .sum()
}

/// The tolerance of a comparison to solver tolerance in `T` (relative residuals 1e-5 in f32
/// and 1e-10 in f64, times the conditioning of the spring operator).
fn tol<T: Real>() -> f64 {
    if T::EPSILON > T::from_f64(1e-10) {
        1e-2
    } else {
        1e-7
    }
}

const METHODS: [PlanMethod; 2] = [PlanMethod::Spring, PlanMethod::QuaternionSpring];

fn cold_bits<T: Real, const D: usize>(c: &Case<T, D>, solvers: &[PlanSolver<T>]) {
    for &solver in solvers {
        for method in METHODS {
            let p = pair(c, method, solver, 4, Start::Cold);
            let what = format!("{method:?} {solver:?} D={D}");
            assert_eq!(bits(&p.plan.0), bits(&p.stateless.0), "tangent {what}");
            assert_eq!(bits(&p.plan.1), bits(&p.stateless.1), "adjoint {what}");
            assert!(p.plan.1.iter().flatten().any(|x| *x != T::ZERO), "{what}");
        }
    }
}

#[test]
fn after_a_cold_step_the_plan_gives_the_stateless_bits_2d() {
    let c64 = Case::<f64>::new(&mesh());
    cold_bits(&c64, &[amg(), cg()]);
    let c32 = Case::<f32>::new(&mesh());
    cold_bits(&c32, &[amg(), cg()]);
}

/// A box with a cubic hole (the hole pitches about the z axis): the extruded airfoil of the
/// 3D plan test has trailing-edge points whose shape rotations have no derivative (their
/// normals sum to zero), where the tangent is `ZeroLength` by design.
fn case3<T: Real>() -> Case<T, 3> {
    let mesh = deform_meshgen::box_with_inner_box3(6, 2).unwrap();
    Case::<T, 3>::with_markers(&mesh, &["inner", "outer"], "inner")
}

#[test]
fn after_a_cold_step_the_plan_gives_the_stateless_bits_3d() {
    cold_bits(&case3::<f64>(), &[amg(), cg()]);
    cold_bits(&case3::<f32>(), &[amg()]);
}

/// After warm steps: the springs still bit for bit, the quaternion method to solver
/// tolerance; the dot-product identity to solver tolerance for both.
fn warm<T: Real, const D: usize>(c: &Case<T, D>) {
    for solver in [amg(), cg()] {
        for method in METHODS {
            let p = pair(c, method, solver, 6, Start::Warm);
            let what = format!("{method:?} {solver:?} D={D}");
            let (rt, ra) = (
                relative(&p.plan.0, &p.stateless.0),
                relative(&p.plan.1, &p.stateless.1),
            );
            println!("{what}: tangent {rt:.2e}, adjoint {ra:.2e} from the stateless");
            if method == PlanMethod::Spring {
                assert_eq!(bits(&p.plan.0), bits(&p.stateless.0), "{what}");
                assert_eq!(bits(&p.plan.1), bits(&p.stateless.1), "{what}");
            }
            assert!(rt < tol::<T>() && ra < tol::<T>(), "{what}: {rt:e} {ra:e}");
            let (left, right) = (dot(&p.plan.0, &p.w), dot(&p.v, &p.plan.1));
            let norms = (dot(&p.plan.0, &p.plan.0) * dot(&p.w, &p.w)).sqrt();
            let gap = (left - right).abs() / norms;
            println!("{what}: <J v, w> = {left:.12e}, <v, J^T w> = {right:.12e}");
            assert!(gap < tol::<T>(), "{what}: dot-product gap {gap:e}");
        }
    }
}

#[test]
fn after_warm_steps_derivatives_match_to_solver_tolerance_and_transpose() {
    warm(&Case::<f64>::new(&mesh()));
    warm(&Case::<f32>::new(&mesh()));
    warm(&case3::<f64>());
    warm(&case3::<f32>());
}

#[test]
fn a_renumbered_plan_gives_the_same_derivatives_in_the_callers_numbering() {
    let c = Case::<f64>::new(&mesh());
    let (n, b) = (c.points.len(), c.nodes.len());
    let (v, w) = (field::<f64, 2>(b, 5), field::<f64, 2>(n, 6));
    for method in METHODS {
        let mut results = Vec::new();
        for renumber in [PlanOrder::AsGiven, PlanOrder::Rcm] {
            let spec = PlanSpec {
                renumber,
                ..c.spec(method, amg())
            };
            let (mut pools, _) = Pools::build(&spec);
            let mut plan = pools.open_d::<2>().unwrap();
            run(&mut plan, &c, 3, Start::Cold);
            let d = c.deformed(3);
            results.push(plan_derivatives(&plan, &PlanMotion::new(&d), &v, &w));
        }
        let (rt, ra) = (
            relative(&results[1].0, &results[0].0),
            relative(&results[1].1, &results[0].1),
        );
        assert!(rt < 1e-7 && ra < 1e-7, "{method:?}: {rt:e} {ra:e}");
        // Boundary nodes get the perturbation exactly, in the caller's numbering.
        for (k, &i) in c.nodes.iter().enumerate() {
            assert_eq!(results[1].0[i as usize], v[k]);
        }
    }
}

/// Every bad call is its typed error, leaves `out` as it was and the pools untouched.
fn bad_input(method: PlanMethod, solver: PlanSolver<f64>) {
    let c = Case::<f64>::new(&mesh());
    let (n, b) = (c.points.len(), c.nodes.len());
    let (mut pools, _) = Pools::build(&c.spec(method, solver));
    let (v, w) = (field::<f64, 2>(b, 1), field::<f64, 2>(n, 2));
    let d = c.deformed(2);
    let motion = PlanMotion::new(&d);
    let sentinel = [7.5, -3.25];
    let mut jv = vec![sentinel; n];
    let mut jw = vec![sentinel; b];
    {
        let plan = pools.open_d::<2>().unwrap();
        let mut s = vec![0.0; plan.sensitivity_scratch_len()];
        let e = plan.tangent(&motion, &v, &mut s, &mut jv).unwrap_err();
        assert!(
            matches!(e, Error::InvalidParameter { arg: "plan", .. }),
            "{e:?}"
        );
        let e = plan.adjoint(&motion, &w, &mut s, &mut jw).unwrap_err();
        assert!(
            matches!(e, Error::InvalidParameter { arg: "plan", .. }),
            "{e:?}"
        );
    }
    run(&mut pools.open_d::<2>().unwrap(), &c, 2, Start::Warm);
    let before = pools.clone();
    let plan = pools.open_d::<2>().unwrap();
    let len = plan.sensitivity_scratch_len();
    let mut s = vec![0.0; len];
    let other = c.deformed(3);
    let moved = PlanMotion::new(&other);
    let shifted = PlanMotion {
        origin: Some([0.25, 0.0]),
        ..motion
    };
    let mut nan = v.clone();
    nan[3][1] = f64::NAN;
    let mut nan_w = w.clone();
    nan_w[n / 2][0] = f64::INFINITY;
    let (short_v, long_out) = (&v[..b - 1], &mut vec![sentinel; n + 1]);
    let mut short = vec![0.0; len - 1];
    let t = |m: &PlanMotion<'_, f64, 2>, v: &[[f64; 2]], s: &mut [f64], o: &mut [[f64; 2]]| {
        plan.tangent(m, v, s, o).unwrap_err()
    };
    let motion_err = |e: Error| matches!(e, Error::InvalidParameter { arg: "motion", .. });
    assert!(motion_err(t(&moved, &v, &mut s, &mut jv)));
    if method == PlanMethod::QuaternionSpring {
        assert!(motion_err(t(&shifted, &v, &mut s, &mut jv)));
    }
    assert!(matches!(
        t(&motion, &v, &mut short, &mut jv),
        Error::BufferTooSmall { .. }
    ));
    assert!(matches!(
        t(&motion, &nan, &mut s, &mut jv),
        Error::NonFinite { .. }
    ));
    assert!(matches!(
        t(&motion, short_v, &mut s, &mut jv),
        Error::LengthMismatch { .. }
    ));
    assert!(matches!(
        t(&motion, &v, &mut s, long_out),
        Error::LengthMismatch { .. }
    ));
    let a = |m: &PlanMotion<'_, f64, 2>, w: &[[f64; 2]], s: &mut [f64], o: &mut [[f64; 2]]| {
        plan.adjoint(m, w, s, o).unwrap_err()
    };
    assert!(motion_err(a(&moved, &w, &mut s, &mut jw)));
    assert!(matches!(
        a(&motion, &w, &mut short, &mut jw),
        Error::BufferTooSmall { .. }
    ));
    assert!(matches!(
        a(&motion, &nan_w, &mut s, &mut jw),
        Error::NonFinite { .. }
    ));
    assert!(matches!(
        a(&motion, &w[1..], &mut s, &mut jw),
        Error::LengthMismatch { .. }
    ));
    assert!(jv
        .iter()
        .chain(&jw)
        .chain(long_out.iter())
        .all(|x| *x == sentinel));
    // The good calls work, and nothing of this wrote the plan.
    plan.tangent(&motion, &v, &mut s, &mut jv).unwrap();
    plan.adjoint(&motion, &w, &mut s, &mut jw).unwrap();
    assert!(pools.same_bits(&before));
}

#[test]
fn bad_input_is_a_typed_error_that_writes_nothing() {
    for method in METHODS {
        bad_input(method, amg());
        bad_input(method, cg());
    }
}

#[test]
fn a_stationary_solver_has_a_tangent_but_no_adjoint() {
    let c = Case::<f64>::new(&mesh());
    let (n, b) = (c.points.len(), c.nodes.len());
    let jacobi = PlanSolver::Method(LinearMethod::Jacobi);
    for method in METHODS {
        let (mut pools, _) = Pools::build(&c.spec(method, jacobi));
        let mut plan = pools.open_d::<2>().unwrap();
        run(&mut plan, &c, 1, Start::Cold);
        let d = c.deformed(1);
        let motion = PlanMotion::new(&d);
        let mut s = vec![0.0; plan.sensitivity_scratch_len()];
        let mut jv = vec![[0.0; 2]; n];
        plan.tangent(&motion, &field(b, 3), &mut s, &mut jv)
            .unwrap();
        let mut jw = vec![[1.0; 2]; b];
        let e = plan
            .adjoint(&motion, &field(n, 4), &mut s, &mut jw)
            .unwrap_err();
        assert!(
            matches!(e, Error::InvalidParameter { arg: "solver", .. }),
            "{e:?}"
        );
        assert!(jw.iter().all(|x| *x == [1.0; 2]));
    }
}
