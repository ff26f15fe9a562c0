//! One time step of a plan: validate the motion, set up the solve (warm or cold), solve, write
//! the mesh, commit the new state. The arithmetic is the stateless pipelines': the same
//! functions in the same order, so a cold step gives their bits.

use super::layout::{self, set_hw, w, AmgParts, Meta, SolverKind};
use super::{Plan, PlanMethod, PlanMotion, Start, StepReport};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::quat::Quat;
use crate::quaternion::springs::{check_rotations, pack, start_at_fixed_mean, unpack};
use crate::quaternion::{
    apply, origin_core, rigid_node_rotation, rotations_core, translation, Pts, RotationSource,
};
use crate::real::Real;
use crate::spring::{
    AmgHierarchy, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SolveReport,
    SpringSystem,
};
use crate::vector::{add, sub};

/// `buf[r]`, empty when out of range.
#[inline]
pub(super) fn sec<'b, X>(buf: &'b [X], r: &core::ops::Range<usize>) -> &'b [X] {
    buf.get(r.clone()).unwrap_or(&[])
}

/// Splits the first `n` items off `s`.
#[inline]
fn carve<'b, X>(s: &mut &'b mut [X], n: usize) -> &'b mut [X] {
    let t = core::mem::take(s);
    let (a, b) = t.split_at_mut_checked(n).unwrap_or_default();
    *s = b;
    a
}

/// The checks on the motion and `out` (nothing is written before they pass).
fn validate<T: Real, const D: usize>(
    meta: &Meta,
    motion: &PlanMotion<'_, T, D>,
    out: &[[T; D]],
) -> Result<()> {
    check::len("out", out.len(), meta.n)?;
    check::len("motion.deformed", motion.deformed.len(), meta.b)?;
    if let Some(p) = crate::real::first_non_finite(motion.deformed) {
        return Err(Error::NonFinite {
            arg: "motion.deformed",
            position: p,
        });
    }
    if meta.method != PlanMethod::QuaternionSpring {
        return Ok(());
    }
    if let Some(o) = motion.origin {
        if o.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite {
                arg: "motion.origin",
                position: 0,
            });
        }
    }
    match motion.rotations {
        RotationSource::Shape => {
            if !meta.counts.has_elements {
                return Err(Error::InvalidParameter {
                    arg: "motion.rotations",
                    reason: "rotations from the boundary shape need a plan built with elements",
                });
            }
        }
        RotationSource::Rigid(q) => check::quats("motion.rotations", core::slice::from_ref(&q))?,
        RotationSource::PerNode(q) => {
            check::len("motion.rotations", q.len(), meta.b)?;
            check::quats("motion.rotations", q)?;
        }
    }
    Ok(())
}

/// The stored solver.
pub(super) fn solver<'h, T: Real>(
    kind: SolverKind,
    omega: T,
    amg: Option<&'h AmgHierarchy<'h, T>>,
) -> LinearSolver<'h, T> {
    let m = match kind {
        SolverKind::Jacobi => LinearMethod::Jacobi,
        SolverKind::GaussSeidel => LinearMethod::GaussSeidel,
        SolverKind::Sor => LinearMethod::Sor { omega },
        SolverKind::CgNone => LinearMethod::Cg {
            preconditioner: Preconditioner::None,
        },
        SolverKind::CgJacobi | SolverKind::Amg => LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        SolverKind::CgSsor => LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega },
        },
    };
    match (kind, amg) {
        (SolverKind::Amg, Some(h)) => LinearSolver::Amg(h),
        _ => LinearSolver::Method(m),
    }
}

/// Runs one step (see [`Plan::step`]).
pub(super) fn step<T: Real, const D: usize>(
    plan: &mut Plan<'_, T, D>,
    motion: &PlanMotion<'_, T, D>,
    out: &mut [[T; D]],
) -> Result<StepReport<T, D>> {
    validate(&plan.meta, motion, out)?;
    let warm = motion.start == Start::Warm && plan.meta.stored >= 1;
    let (solve, guess, origin) = match (plan.meta.method, D) {
        (PlanMethod::Spring, _) => run_spring(plan, motion, warm, out)?,
        (PlanMethod::QuaternionSpring, 2) => run_quaternion::<T, D, 6>(plan, motion, warm, out)?,
        (PlanMethod::QuaternionSpring, 3) => run_quaternion::<T, D, 7>(plan, motion, warm, out)?,
        _ => return Err(Error::BadDimensions { arg: "D" }),
    };
    // Commit: the solution is in the state section already; record it in the header.
    let steps = plan.meta.steps.wrapping_add(1);
    let stored = plan.meta.stored.saturating_add(1).min(2);
    set_hw(plan.indices, w::HAS_STATE, stored);
    set_hw(plan.indices, w::STEPS_LO, steps as u32);
    set_hw(plan.indices, w::STEPS_HI, (steps >> 32) as u32);
    plan.meta.stored = stored;
    plan.meta.steps = steps;
    Ok(StepReport {
        solve,
        warm: guess != Guess::Cold,
        extrapolated: guess == Guess::Extrapolated,
        step: steps,
        origin,
    })
}

/// The read-only parts every step needs.
pub(super) struct Fixed<'p, T: Real, const D: usize> {
    pub sys: SpringSystem<'p, T>,
    pub points: &'p [[T; D]],
    pub boundary: &'p [u32],
    /// `order[new] = old` of a renumbered plan (empty: the caller's numbering).
    pub order: &'p [u32],
    pub options: SolveOptions<T>,
    pub omega: T,
}

/// The step workspaces and the state, as `V`-vectors.
struct Mutable<'p, T, const V: usize> {
    state: &'p mut [[T; V]],
    state_ref: &'p mut [T],
    state2: &'p mut [[T; V]],
    state2_ref: &'p mut [T],
    work: &'p mut [[T; V]],
    scratch: &'p mut [[T; V]],
    rot: &'p mut [T],
    bq: &'p mut [[T; 4]],
}

/// Splits the pools into the read-only plan data and the mutable sections.
#[allow(clippy::type_complexity)]
fn views<'p, T: Real, const D: usize, const V: usize>(
    meta: &Meta,
    reals: &'p mut [T],
    indices: &'p [u32],
    bytes: &'p [u8],
) -> (Fixed<'p, T, D>, &'p [T], Mutable<'p, T, V>) {
    let s = &meta.sec;
    let (fixed, mut rest) = reals
        .split_at_mut_checked(s.state.start)
        .unwrap_or_default();
    let fixed: &'p [T] = fixed;
    let state = carve(&mut rest, s.state.len()).as_chunks_mut::<V>().0;
    let state_ref = carve(&mut rest, s.state_ref.len());
    let state2 = carve(&mut rest, s.state2.len()).as_chunks_mut::<V>().0;
    let state2_ref = carve(&mut rest, s.state2_ref.len());
    let work = carve(&mut rest, s.work.len()).as_chunks_mut::<V>().0;
    let scratch = carve(&mut rest, s.scratch.len()).as_chunks_mut::<V>().0;
    let rot = carve(&mut rest, s.rot.len());
    let bq = carve(&mut rest, s.bq.len()).as_chunks_mut::<4>().0;
    (
        fixed_view(meta, fixed, indices, bytes),
        fixed,
        Mutable {
            state,
            state_ref,
            state2,
            state2_ref,
            work,
            scratch,
            rot,
            bq,
        },
    )
}

/// The read-only plan data (`fixed`: the real pool before the state section).
pub(super) fn fixed_view<'p, T: Real, const D: usize>(
    meta: &Meta,
    fixed: &'p [T],
    indices: &'p [u32],
    bytes: &'p [u8],
) -> Fixed<'p, T, D> {
    let s = &meta.sec;
    let graph = Graph::trusted(sec(indices, &s.offs), sec(indices, &s.targets));
    let sys = SpringSystem::trusted(graph, sec(fixed, &s.stiffness), sec(bytes, &s.mask));
    let params = sec(fixed, &s.params);
    let p = |i: usize| params.get(i).copied().unwrap_or(T::ZERO);
    let options = SolveOptions {
        max_iterations: meta.max_iterations,
        residual_tol: p(layout::P_RESIDUAL),
        update_tol: p(layout::P_UPDATE),
    };
    Fixed {
        sys,
        points: sec(fixed, &s.points).as_chunks::<D>().0,
        boundary: sec(indices, &s.boundary),
        order: sec(indices, &s.perm).get(..meta.n).unwrap_or(&[]),
        options,
        omega: p(layout::P_OMEGA),
    }
}

/// The hierarchy view, when the plan has one.
pub(super) fn hierarchy<'p, T: Real>(
    meta: &Meta,
    amg: &Option<AmgParts<T>>,
    fixed: &'p [T],
    indices: &'p [u32],
) -> Option<AmgHierarchy<'p, T>> {
    amg.as_ref().map(|a| {
        AmgHierarchy::from_parts(
            a.layout,
            a.weights,
            a.sweeps,
            sec(indices, &meta.sec.amg_index),
            sec(fixed, &meta.sec.amg_values),
        )
    })
}

/// Linear springs on the displacements (`V = D`).
fn run_spring<T: Real, const D: usize>(
    plan: &mut Plan<'_, T, D>,
    motion: &PlanMotion<'_, T, D>,
    warm: bool,
    out: &mut [[T; D]],
) -> Result<(SolveReport<T>, Guess, [T; D])> {
    let Plan {
        reals,
        indices,
        bytes,
        meta,
        amg,
    } = plan;
    let (f, fixed, mut m) = views::<T, D, D>(meta, reals, indices, bytes);
    let h = hierarchy(meta, amg, fixed, indices);
    let solver = solver(meta.solver, f.omega, h.as_ref());
    m.work.fill([T::ZERO; D]);
    for (&i, d) in f.boundary.iter().zip(motion.deformed) {
        let i = i as usize;
        if let (Some(v), Some(p)) = (m.work.get_mut(i), f.points.get(i)) {
            *v = sub(*d, *p);
        }
    }
    let guess = if warm {
        let previous = Previous {
            last: m.state,
            before: (meta.stored >= 2).then_some(&*m.state2),
            flip_last: false,
            flip_before: false,
        };
        choose_start::<T, D, D>(&f.sys, m.work, &previous, |v| *v = [T::ZERO; D])?
    } else {
        Guess::Cold
    };
    let report = f
        .sys
        .solve_linear_with(m.work, solver, &f.options, m.scratch)?;
    if crate::real::first_non_finite(m.work).is_some() {
        return Err(Error::Overflow { arg: "values" });
    }
    for (i, (p, v)) in f.points.iter().zip(m.work.iter()).enumerate() {
        if let Some(o) = out_at(out, f.order, i) {
            *o = add(*p, *v);
        }
    }
    for (&i, d) in f.boundary.iter().zip(motion.deformed) {
        if let Some(o) = out_at(out, f.order, i as usize) {
            *o = *d;
        }
    }
    commit(&mut m, meta.stored, Quat::identity());
    Ok((report, guess, [T::ZERO; D]))
}

/// `out`'s entry for plan node `i`: the caller's node `order[i]` (`i` without an order).
#[inline]
pub(super) fn out_at<'o, T, const D: usize>(
    out: &'o mut [[T; D]],
    order: &[u32],
    i: usize,
) -> Option<&'o mut [T; D]> {
    match order.get(i) {
        Some(&old) => out.get_mut(old as usize),
        None => out.get_mut(i),
    }
}

/// Stores the solution in `work` as the last one (the last becomes the one before).
fn commit<T: Real, const V: usize>(m: &mut Mutable<'_, T, V>, stored: u32, reference: Quat<T>) {
    if stored >= 1 {
        for (a, b) in m.state2.iter_mut().zip(m.state.iter()) {
            *a = *b;
        }
        for (a, b) in m.state2_ref.iter_mut().zip(m.state_ref.iter()) {
            *a = *b;
        }
    }
    for (s, v) in m.state.iter_mut().zip(m.work.iter()) {
        *s = *v;
    }
    for (a, b) in m.state_ref.iter_mut().zip(reference.to_array()) {
        *a = b;
    }
}

/// The initial guess a step used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Guess {
    /// The stateless pipelines' guess.
    Cold,
    /// The last solution.
    Previous,
    /// `x_n + (x_n − x_{n−1})` from the last two solutions.
    Extrapolated,
}

/// The stored solutions, with whether their quaternion components must be negated into the
/// current reference hemisphere.
struct Previous<'s, T, const V: usize> {
    last: &'s [[T; V]],
    before: Option<&'s [[T; V]]>,
    flip_last: bool,
    flip_before: bool,
}

/// `v` with its components from `D` on negated when `flip`.
#[inline]
fn aligned<T: Real, const D: usize, const V: usize>(mut v: [T; V], flip: bool) -> [T; V] {
    if flip {
        for x in v.iter_mut().skip(D) {
            *x = -*x;
        }
    }
    v
}

/// `work` holds the cold initial guess (boundary values set). Tries the last solution and,
/// when two are stored, the linear extrapolation `x_n + (x_n − x_{n−1})` at the free nodes,
/// and keeps the guess with the smallest true relative residual (ties go to the simpler one);
/// otherwise puts the cold guess back (`cold`). After a small motion, e.g. a pitching wall
/// passing its rest position, the previous solution can be the worse guess: the residual
/// decides.
fn choose_start<T: Real, const D: usize, const V: usize>(
    sys: &SpringSystem<'_, T>,
    work: &mut [[T; V]],
    prev: &Previous<'_, T, V>,
    cold: impl Fn(&mut [T; V]),
) -> Result<Guess> {
    let fill = |work: &mut [[T; V]], g: Guess| {
        for (i, v) in work.iter_mut().enumerate() {
            if sys.is_fixed(i) {
                continue;
            }
            let last = prev
                .last
                .get(i)
                .map(|&a| aligned::<T, D, V>(a, prev.flip_last));
            let before = prev
                .before
                .and_then(|b| b.get(i))
                .map(|&b| aligned::<T, D, V>(b, prev.flip_before));
            match (g, last, before) {
                (Guess::Previous, Some(a), _) => *v = a,
                (Guess::Extrapolated, Some(a), Some(b)) => {
                    for ((x, &p), &q) in v.iter_mut().zip(a.iter()).zip(b.iter()) {
                        *x = p + (p - q);
                    }
                }
                _ => cold(v),
            }
        }
    };
    let r_cold = sys.relative_residual(work)?;
    fill(work, Guess::Previous);
    let r_prev = sys.relative_residual(work)?;
    let (mut best, r_best) = if r_prev < r_cold {
        (Guess::Previous, r_prev)
    } else {
        (Guess::Cold, r_cold)
    };
    if prev.before.is_some() {
        fill(work, Guess::Extrapolated);
        if sys.relative_residual(work)? < r_best {
            best = Guess::Extrapolated;
        }
    }
    let current = if prev.before.is_some() {
        Guess::Extrapolated
    } else {
        Guess::Previous
    };
    if best != current {
        fill(work, best);
    }
    Ok(best)
}

/// The quaternion method with spring propagation (`V = D + 4`): the steps of
/// [`deform_spring_with`](crate::quaternion::deform_spring_with) on the plan's data.
fn run_quaternion<T: Real, const D: usize, const V: usize>(
    plan: &mut Plan<'_, T, D>,
    motion: &PlanMotion<'_, T, D>,
    warm: bool,
    out: &mut [[T; D]],
) -> Result<(SolveReport<T>, Guess, [T; D])> {
    if V != D + 4 {
        return Err(Error::BadDimensions { arg: "D" });
    }
    let Plan {
        reals,
        indices,
        bytes,
        meta,
        amg,
    } = plan;
    let (f, fixed, mut m) = views::<T, D, V>(meta, reals, indices, bytes);
    let h = hierarchy(meta, amg, fixed, indices);
    let solver = solver(meta.solver, f.omega, h.as_ref());
    let s = &meta.sec;
    let u = Pts::mapped(f.points, f.boundary);
    let d = Pts::direct(motion.deformed);
    let origin = match motion.origin {
        Some(o) => o,
        None => origin_core(u, d)?,
    };
    // Boundary rotations (raw, as the stateless pipeline stores them).
    match motion.rotations {
        RotationSource::Shape => {
            let cells = Cells::trusted(
                meta.b,
                sec(indices, &s.cell_offs),
                sec(indices, &s.cell_nodes),
                sec(bytes, &s.cell_kinds),
            );
            let bq = &mut *m.bq;
            rotations_core(u, d, &cells, m.rot, |k, q| {
                if let Some(r) = bq.get_mut(k) {
                    *r = q.to_array();
                }
            })?;
        }
        RotationSource::Rigid(q) => {
            let q = q.normalize()?;
            for (k, r) in m.bq.iter_mut().enumerate() {
                *r = rigid_node_rotation(q, origin, u.get(k), d.get(k)).to_array();
            }
        }
        RotationSource::PerNode(qs) => {
            for (r, q) in m.bq.iter_mut().zip(qs) {
                *r = q.to_array();
            }
        }
    }
    let reference =
        m.bq.get(meta.k_first)
            .map_or(Quat::identity(), |&a| Quat::from_array(a));
    // Translations, packed with the hemisphere-aligned rotations at the boundary nodes.
    for (k, ((&i, &dk), q)) in f
        .boundary
        .iter()
        .zip(motion.deformed)
        .zip(m.bq.iter())
        .enumerate()
    {
        let q = Quat::from_array(*q);
        let t = translation(
            origin,
            u.get(k),
            dk,
            q.normalize().unwrap_or(Quat::identity()),
        );
        let q = if q.dot(reference) < T::ZERO { -q } else { q };
        if let Some(v) = m.work.get_mut(i as usize) {
            *v = pack(t, q);
        }
    }
    // Initial guess at the free nodes: the cold one (as the stateless pipeline), then the
    // stored solutions if their residual is smaller.
    let guess = {
        let mean = start_at_fixed_mean(&f.sys, m.work);
        let flip = |r: &[T]| {
            let q = r
                .as_chunks::<4>()
                .0
                .first()
                .map_or(reference, |&a| Quat::from_array(a));
            q.dot(reference) < T::ZERO
        };
        if warm {
            let previous = Previous {
                last: m.state,
                before: (meta.stored >= 2).then_some(&*m.state2),
                flip_last: flip(m.state_ref),
                flip_before: flip(m.state2_ref),
            };
            choose_start::<T, D, V>(&f.sys, m.work, &previous, |v| *v = mean)?
        } else {
            Guess::Cold
        }
    };
    let report = f
        .sys
        .solve_linear_with(m.work, solver, &f.options, m.scratch)?;
    check_rotations::<T, D, V>(&f.sys, m.work)?;
    if crate::real::first_non_finite(m.work).is_some() {
        return Err(Error::Overflow { arg: "values" });
    }
    // The field update (eq. 6) with the twice-normalised rotations of the stateless path.
    for (i, (p, v)) in f.points.iter().zip(m.work.iter()).enumerate() {
        if f.sys.is_fixed(i) {
            continue;
        }
        let (t, q) = unpack::<T, D, V>(v);
        let q = q.normalize().unwrap_or(reference);
        let q = q.normalize().unwrap_or(Quat::identity());
        if let Some(o) = out_at(out, f.order, i) {
            *o = apply(origin, *p, t, q);
        }
    }
    for (&i, dk) in f.boundary.iter().zip(motion.deformed) {
        if let Some(o) = out_at(out, f.order, i as usize) {
            *o = *dk;
        }
    }
    commit(&mut m, meta.stored, reference);
    Ok((report, guess, origin))
}
