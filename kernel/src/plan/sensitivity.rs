//! The derivative of a plan's last step: tangent (`δx = J δd`) and adjoint (`d̄ = Jᵀ w`) of
//! the deformed mesh with respect to the deformed boundary positions, linearised where the
//! last step left the plan.
//!
//! A plan already holds what the derivative needs: the spring system and its multigrid
//! hierarchy (built once at `init`, reused as is: the operator is symmetric) and, for the
//! quaternion method, the last step's solved packed field `(Δ_i, S_i)`, whose unnormalised
//! rotations `S_i` the linearisation of `Q_i = S_i / |S_i|` needs. So each derivative costs
//! one linear solve (the stateless
//! [`deform_spring_adjoint`](crate::quaternion::deform_spring_adjoint) solves twice: it repeats
//! the deformation's solve first). The arithmetic is the stateless functions': the linear
//! springs' [`spring_tangent`] / [`spring_adjoint`] and the quaternion method's split after
//! its base solve ([`SolvedSpring`]).
//!
//! **Equality with the stateless functions.** After a cold step ([`Start::Cold`](super::Start))
//! the stored field is bit for bit the stateless base solve's, and the results are bit for bit
//! those of [`spring_tangent`] / [`spring_adjoint`] (linear springs, whose derivative does not
//! depend on the step at all) and [`deform_spring_tangent`](crate::quaternion::deform_spring_tangent)
//! / [`deform_spring_adjoint`](crate::quaternion::deform_spring_adjoint) on the plan's mesh and
//! solver (in the plan's numbering when it renumbers; to solver tolerance against the caller's
//! numbering). After a warm step the stored field is the same solution to the solver's
//! tolerance, and so are the quaternion method's derivatives.
//!
//! **The motion** passed in must be the last step's (the same deformed positions, rotation
//! source and origin; `start` is ignored): the quaternion method's boundary stage is
//! linearised at it. It is checked against the stored boundary values bit for bit, so another
//! motion is an [`Error::InvalidParameter`] (`"motion"`), not a derivative at the wrong point.

use super::layout::Meta;
use super::step::{fixed_view, hierarchy, out_at, sec, solver, Fixed};
use super::{Plan, PlanMethod, PlanMotion};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::quaternion::{deform_spring_sensitivity_scratch_len, BoundaryMotion, SolvedSpring};
use crate::real::Real;
use crate::sensitivity::{spring_adjoint, spring_adjoint_scratch_len, spring_tangent};
use crate::spring::{solve_linear_with_scratch_len, AmgHierarchy, LinearSolver, SolveReport};
use crate::vector::sub;

/// The two directions of a derivative.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    Tangent,
    Adjoint,
}

/// The read-only plan data a derivative needs.
struct View<'p, T: Real, const D: usize> {
    f: Fixed<'p, T, D>,
    h: Option<AmgHierarchy<'p, T>>,
    /// The last step's solution, `N V` scalars.
    state: &'p [T],
}

impl<T: Real, const D: usize> View<'_, T, D> {
    fn solver(&self, meta: &Meta) -> LinearSolver<'_, T> {
        solver(meta.solver, self.f.omega, self.h.as_ref())
    }
}

/// `[T; D]` items of the linear springs' scratch: the tangent's `(n + solve)` and the
/// adjoint's `(2 n + adjoint solve)` (`usize::MAX` for a solver the adjoint does not take).
fn spring_items<T: Real, const D: usize>(solver: &LinearSolver<'_, T>, n: usize) -> [usize; 2] {
    let tangent = n.saturating_add(solve_linear_with_scratch_len(solver, n));
    let adjoint = match spring_adjoint_scratch_len::<T, D>(solver, n) {
        usize::MAX => usize::MAX,
        a => a.saturating_add(n.saturating_mul(2)),
    };
    [tangent, adjoint]
}

impl<'a, T: Real, const D: usize> Plan<'a, T, D> {
    fn view(&self) -> View<'_, T, D> {
        let s = &self.meta.sec;
        let reals: &[T] = self.reals;
        let fixed = reals.get(..s.state.start).unwrap_or(&[]);
        View {
            f: fixed_view(&self.meta, fixed, self.indices, self.bytes),
            h: hierarchy(&self.meta, &self.amg, fixed, self.indices),
            state: sec(reals, &s.state),
        }
    }

    /// Scalars of `scratch` that [`Plan::tangent`] and [`Plan::adjoint`] need (one length for
    /// both): linear springs `D` times the larger of `N` plus the solve's scratch (tangent)
    /// and `2 N` plus [`spring_adjoint_scratch_len`] (adjoint); the quaternion method
    /// [`deform_spring_sensitivity_scratch_len`] (two packed fields, the boundary stage, the
    /// solve's). `usize::MAX` on overflow.
    pub fn sensitivity_scratch_len(&self) -> usize {
        let v = self.view();
        let solver = v.solver(&self.meta);
        let (n, b) = (self.meta.n, self.meta.b);
        match self.meta.method {
            PlanMethod::Spring => {
                let [t, a] = spring_items::<T, D>(&solver, n);
                let items = if a == usize::MAX { t } else { t.max(a) };
                items.saturating_mul(D)
            }
            PlanMethod::QuaternionSpring => {
                deform_spring_sensitivity_scratch_len::<T, D>(&solver, n, b)
            }
        }
    }

    /// The tangent at the last step: `out = δx` (`N` points, the caller's numbering) for the
    /// perturbation `direction = δd` of the deformed boundary positions (`B`, in
    /// [`PlanSpec::boundary`](super::PlanSpec::boundary) order); boundary nodes get `δd`
    /// exactly. One solve with the plan's solver and hierarchy, from a zero guess at the free
    /// nodes. `motion`: the last step's (see the module doc). `scratch`:
    /// [`Plan::sensitivity_scratch_len`] scalars. Returns the solve's report (not converged is
    /// `Ok`; check `converged`).
    ///
    /// # Errors
    /// Checked before anything is written: `direction` not `B` or `out` not `N` long
    /// ([`Error::LengthMismatch`]); a plan that has not stepped yet
    /// ([`Error::InvalidParameter`], `"plan"`); a short `scratch`
    /// ([`Error::BufferTooSmall`]); a non-finite `direction` ([`Error::NonFinite`]); a
    /// `motion` that is not the last step's ([`Error::InvalidParameter`], `"motion"`, or the
    /// motion's own errors); the boundary stage's (antiparallel normals) and the solver's
    /// errors. On `Err`, `out` is unchanged; the plan is never written.
    pub fn tangent(
        &self,
        motion: &PlanMotion<'_, T, D>,
        direction: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check::len("direction", direction.len(), self.meta.b)?;
        check::len("out", out.len(), self.meta.n)?;
        self.derivative(Mode::Tangent, motion, direction, scratch, out)
    }

    /// The adjoint at the last step: `out = Jᵀ w = dJ/dd` (`B` items, in
    /// [`PlanSpec::boundary`](super::PlanSpec::boundary) order) for `weights = w = dJ/dx`
    /// (`N`, the caller's numbering): the transpose of [`Plan::tangent`], one CG solve with
    /// the plan's operator and preconditioner (the multigrid hierarchy reused; the operator is
    /// symmetric). The plan's solver must be CG or multigrid. Returns the solve's report.
    ///
    /// # Errors
    /// Those of [`Plan::tangent`] with `weights` (`N`, finite) for `direction` and `out` `B`
    /// long; a stationary one-level solver ([`Error::InvalidParameter`], `"solver"`). On `Err`,
    /// `out` is unchanged; the plan is never written.
    pub fn adjoint(
        &self,
        motion: &PlanMotion<'_, T, D>,
        weights: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check::len("weights", weights.len(), self.meta.n)?;
        check::len("out", out.len(), self.meta.b)?;
        self.derivative(Mode::Adjoint, motion, weights, scratch, out)
    }

    /// The checks common to both directions, then the method's derivative.
    fn derivative(
        &self,
        mode: Mode,
        motion: &PlanMotion<'_, T, D>,
        input: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        if self.meta.stored == 0 {
            return Err(Error::InvalidParameter {
                arg: "plan",
                reason: "the plan has not stepped yet (the derivative is taken at its last step)",
            });
        }
        let v = self.view();
        let solver = v.solver(&self.meta);
        match self.meta.method {
            PlanMethod::Spring => {
                let [t, a] = spring_items::<T, D>(&solver, self.meta.n);
                let items = if mode == Mode::Tangent { t } else { a };
                if items == usize::MAX {
                    return Err(Error::InvalidParameter {
                        arg: "solver",
                        reason: "the adjoint needs CG or multigrid",
                    });
                }
                check::buffer("scratch", scratch.len(), self.sensitivity_scratch_len())?;
                check::finite_items(
                    if mode == Mode::Tangent {
                        "direction"
                    } else {
                        "weights"
                    },
                    input,
                )?;
                self.check_spring_motion(&v, motion)?;
                let scratch = scratch.as_chunks_mut::<D>().0;
                match mode {
                    Mode::Tangent => spring_tangent_at(&v, solver, input, scratch, out),
                    Mode::Adjoint => spring_adjoint_at(&v, solver, input, scratch, out),
                }
            }
            PlanMethod::QuaternionSpring => {
                let bm = self.boundary_motion(&v, motion);
                let solved = SolvedSpring {
                    points: v.f.points,
                    motion: &bm,
                    sys: &v.f.sys,
                    solver,
                    options: &v.f.options,
                    field: v.state,
                    order: v.f.order,
                };
                match mode {
                    Mode::Tangent => solved.tangent(input, scratch, out),
                    Mode::Adjoint => solved.adjoint(input, scratch, out),
                }
            }
        }
    }

    /// The linear springs' motion check: `motion.deformed` minus the reference points is the
    /// stored boundary displacement, bit for bit.
    fn check_spring_motion(&self, v: &View<'_, T, D>, motion: &PlanMotion<'_, T, D>) -> Result<()> {
        check::len("motion.deformed", motion.deformed.len(), self.meta.b)?;
        let state = v.state.as_chunks::<D>().0;
        let same = v.f.boundary.iter().zip(motion.deformed).all(|(&i, d)| {
            let i = i as usize;
            match (state.get(i), v.f.points.get(i)) {
                (Some(s), Some(p)) => *s == sub(*d, *p),
                _ => false,
            }
        });
        if same {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                arg: "motion",
                reason: "not the motion of the plan's last step",
            })
        }
    }

    /// The quaternion method's motion on the plan's data (nodes in the plan's numbering).
    fn boundary_motion<'m>(
        &'m self,
        v: &View<'m, T, D>,
        motion: &PlanMotion<'m, T, D>,
    ) -> BoundaryMotion<'m, T, D> {
        let s = &self.meta.sec;
        let elements = self.meta.counts.has_elements.then(|| {
            Cells::trusted(
                self.meta.b,
                sec(self.indices, &s.cell_offs),
                sec(self.indices, &s.cell_nodes),
                sec(self.bytes, &s.cell_kinds),
            )
        });
        BoundaryMotion {
            nodes: v.f.boundary,
            deformed: motion.deformed,
            elements,
            rotations: motion.rotations,
            origin: motion.origin,
        }
    }
}

/// The linear springs' tangent: `δd` at the fixed nodes, zero at the free, one solve
/// ([`spring_tangent`]); `scratch` holds the field (`N`) and the solve's.
fn spring_tangent_at<T: Real, const D: usize>(
    v: &View<'_, T, D>,
    solver: LinearSolver<'_, T>,
    direction: &[[T; D]],
    scratch: &mut [[T; D]],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = v.f.points.len();
    let (dx, solve) = scratch.split_at_mut_checked(n).unwrap_or_default();
    dx.fill([T::ZERO; D]);
    for (&i, d) in v.f.boundary.iter().zip(direction) {
        if let Some(x) = dx.get_mut(i as usize) {
            *x = *d;
        }
    }
    let report = spring_tangent(&v.f.sys, solver, &v.f.options, dx, solve)?;
    for (i, x) in dx.iter().enumerate() {
        if let Some(o) = out_at(out, v.f.order, i) {
            *o = *x;
        }
    }
    for (&i, d) in v.f.boundary.iter().zip(direction) {
        if let Some(o) = out_at(out, v.f.order, i as usize) {
            *o = *d;
        }
    }
    Ok(report)
}

/// The linear springs' adjoint ([`spring_adjoint`]) on `w` in the plan's numbering; `scratch`
/// holds the permuted `w` (`N`), `g` (`N`) and the adjoint's own.
fn spring_adjoint_at<T: Real, const D: usize>(
    v: &View<'_, T, D>,
    solver: LinearSolver<'_, T>,
    weights: &[[T; D]],
    scratch: &mut [[T; D]],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = v.f.points.len();
    let (w, rest) = scratch.split_at_mut_checked(n).unwrap_or_default();
    let (g, rest) = rest.split_at_mut_checked(n).unwrap_or_default();
    let w: &[[T; D]] = if v.f.order.is_empty() {
        weights
    } else {
        for (x, &old) in w.iter_mut().zip(v.f.order) {
            *x = weights.get(old as usize).copied().unwrap_or([T::ZERO; D]);
        }
        w
    };
    let report = spring_adjoint(&v.f.sys, solver, &v.f.options, w, g, rest)?;
    for (o, &i) in out.iter_mut().zip(v.f.boundary) {
        *o = g.get(i as usize).copied().unwrap_or([T::ZERO; D]);
    }
    Ok(report)
}
