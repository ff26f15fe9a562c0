//! Tangent and adjoint of the quaternion deformation with linear-spring propagation
//! ([`deform_spring_with`](crate::quaternion::deform_spring_with), `deform move --method
//! quaternion`).
//!
//! The forward packs `(Δ_k, ±Q_k)` at the fixed nodes (`V = D + 4` lanes, the signs of the
//! hemisphere alignment held), solves `A x_f = B x_b` with the spring operator, normalises
//! `Q_i = S_i / |S_i|` at the free nodes and updates `R_i = o + Δ_i + Q_i (r_i − o) Q_i*`.
//! The spring map is linear, so
//!
//! - **tangent**: the boundary stage gives `(δΔ_k, ±δQ_k)`; one more solve with the same
//!   operator and solver gives `(δΔ_i, δS_i)`; `δQ_i = (I − Q_i Q_iᵀ) δS_i / |S_i|` and
//!   `δR_i = δΔ_i + M(Q_i, r_i − o) δQ_i`;
//! - **adjoint**: `Δ̄_i = w_i`, `S̄_i = (I − Q_i Q_iᵀ) M(Q_i, r_i − o)ᵀ w_i / |S_i|` at the free
//!   nodes; `A λ = (Δ̄, S̄)_f` (the operator is symmetric: the same CG and preconditioner or
//!   multigrid hierarchy), `(Δ̄_k, ±Q̄_k) = B_kᵀ λ` at the fixed nodes; then the boundary
//!   stage's transpose.
//!
//! Both first repeat the forward's solve (same packing, start and solver) for `S_i`, so each
//! costs two solves; a prepared plan ([`Plan::tangent`](crate::plan::Plan::tangent),
//! [`Plan::adjoint`](crate::plan::Plan::adjoint)) keeps its last step's solved field and
//! skips that repetition (the split after the base solve, [`SolvedSpring`]). The solves are iterative: the results are the derivative of the exact
//! solve to the solver's tolerance, and tangent and adjoint agree (`⟨J v, w⟩ = ⟨v, Jᵀ w⟩`) to
//! that tolerance; pick `options.residual_tol` tight.

use super::boundary::get3;
use super::lin::{drot, mul34, mul34t, proj4};
use super::{
    boundary_adjoint, boundary_adjoint_check, boundary_tangent, deform_idw_sensitivity_scratch_len,
    prepare,
};
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::quaternion::springs::{check_rotations, pack, start_at_fixed_mean, unpack};
use crate::quaternion::{drop3, lift, load, store, take, translation, BoundaryMotion, Pts};
use crate::real::Real;
use crate::sensitivity::{merge, spring_adjoint, spring_adjoint_scratch_len};
use crate::spring::{
    solve_linear_with_scratch_len, LinearSolver, SolveOptions, SolveReport, SpringSystem,
};
use crate::vector::{add, sub};

/// Length of the `scratch` slice [`deform_spring_tangent`] and [`deform_spring_adjoint`]
/// need: two packed fields (`2 N (D + 4)`), the boundary stage (`max(N, 32 B)`) and the
/// solver's own (`(D + 4)` times the larger of the deformation's and the adjoint's solve
/// scratch). `usize::MAX` on overflow.
pub fn deform_spring_sensitivity_scratch_len<T: Real, const D: usize>(
    solver: &LinearSolver<'_, T>,
    node_count: usize,
    boundary_len: usize,
) -> usize {
    check::mesh_dim::<D>();
    let v = D + 4;
    let forward = solve_linear_with_scratch_len(solver, node_count);
    let adjoint = if D == 2 {
        spring_adjoint_scratch_len::<T, 6>(solver, node_count)
    } else {
        spring_adjoint_scratch_len::<T, 7>(solver, node_count)
    };
    // A solver the adjoint does not take still serves the tangent.
    let solve = if adjoint == usize::MAX {
        forward
    } else {
        forward.max(adjoint)
    };
    node_count
        .saturating_mul(2)
        .saturating_add(solve)
        .saturating_mul(v)
        .saturating_add(deform_idw_sensitivity_scratch_len::<D>(
            node_count,
            boundary_len,
        ))
}

/// The fixed problem of both modes.
struct Setup<'a, 'm, T: Real, const D: usize> {
    points: &'a [[T; D]],
    motion: &'a BoundaryMotion<'m, T, D>,
    sys: &'a SpringSystem<'a, T>,
    solver: LinearSolver<'a, T>,
    options: &'a SolveOptions<T>,
    /// The forward's solved packed field (`N (D + 4)` scalars) when the caller has it (a
    /// plan's last step): then the base solve is not repeated. `None`: solve it here.
    solved: Option<&'a [T]>,
    /// The caller's node of solve node `i`: `order[i]` (empty: `i`), for `out` and `weights`.
    order: &'a [u32],
}

/// The base field and the report of its solve (`None`: given, not solved).
type Base<'v, T, const V: usize> = (&'v [[T; V]], Option<SolveReport<T>>);

/// A deformation whose propagation solve is done: the problem and the solved packed field
/// `(Δ_i, S_i)` (solve numbering, hemisphere-aligned as the forward leaves it), e.g. a plan's
/// last step. [`SolvedSpring::tangent`] and [`SolvedSpring::adjoint`] are
/// [`deform_spring_tangent`] and [`deform_spring_adjoint`] without the repeated base solve
/// (the same bits when `field` is the bits that solve gives), with the same scratch length.
pub(crate) struct SolvedSpring<'a, 'm, T: Real, const D: usize> {
    /// Mesh points in the solve's numbering.
    pub points: &'a [[T; D]],
    /// The motion of the solved step (its `nodes` in the solve's numbering).
    pub motion: &'a BoundaryMotion<'m, T, D>,
    /// The spring system of the solve.
    pub sys: &'a SpringSystem<'a, T>,
    /// Its solver (the adjoint needs CG or multigrid).
    pub solver: LinearSolver<'a, T>,
    /// Its stopping rules.
    pub options: &'a SolveOptions<T>,
    /// The solved packed field, `N (D + 4)` scalars.
    pub field: &'a [T],
    /// `order[i]`: the caller's node of solve node `i` (empty: the same numbering).
    pub order: &'a [u32],
}

impl<T: Real, const D: usize> SolvedSpring<'_, '_, T, D> {
    fn setup(&self) -> Setup<'_, '_, T, D> {
        Setup {
            points: self.points,
            motion: self.motion,
            sys: self.sys,
            solver: self.solver,
            options: self.options,
            solved: Some(self.field),
            order: self.order,
        }
    }

    /// [`deform_spring_tangent`] at the solved field (`out` in the caller's numbering).
    ///
    /// # Errors
    /// Those of [`deform_spring_tangent`]; a `motion` whose packed boundary values are not
    /// the field's ([`Error::InvalidParameter`], `"motion"`). On error `out` is unchanged.
    pub fn tangent(
        &self,
        direction: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check::len("direction", direction.len(), self.motion.nodes.len())?;
        check::len("out", out.len(), self.points.len())?;
        self.setup().run(Mode::Tangent, direction, scratch, out)
    }

    /// [`deform_spring_adjoint`] at the solved field (`weights` in the caller's numbering).
    ///
    /// # Errors
    /// As [`SolvedSpring::tangent`], with those of [`deform_spring_adjoint`].
    pub fn adjoint(
        &self,
        weights: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check::len("weights", weights.len(), self.points.len())?;
        check::len("out", out.len(), self.motion.nodes.len())?;
        self.setup().run(Mode::Adjoint, weights, scratch, out)
    }
}

/// The caller's node of solve node `i`.
#[inline]
fn caller(order: &[u32], i: usize) -> usize {
    order.get(i).map_or(i, |&o| o as usize)
}

/// The scratch of both modes: two packed fields, the boundary stage, the solver's.
struct Parts<'s, T, const V: usize> {
    base: &'s mut [[T; V]],
    second: &'s mut [[T; V]],
    bnd: &'s mut [T],
    solve: &'s mut [[T; V]],
}

/// The two modes.
#[derive(Clone, Copy)]
enum Mode {
    Tangent,
    Adjoint,
}

/// The arguments of [`Setup`] in the order the public functions take them.
type Args<'a, 'm, T, const D: usize> = (
    &'a [[T; D]],
    &'a BoundaryMotion<'m, T, D>,
    &'a SpringSystem<'a, T>,
    LinearSolver<'a, T>,
    &'a SolveOptions<T>,
);

impl<'a, 'm, T: Real, const D: usize> From<Args<'a, 'm, T, D>> for Setup<'a, 'm, T, D> {
    fn from((points, motion, sys, solver, options): Args<'a, 'm, T, D>) -> Self {
        Setup {
            points,
            motion,
            sys,
            solver,
            options,
            solved: None,
            order: &[],
        }
    }
}

impl<T: Real, const D: usize> Setup<'_, '_, T, D> {
    /// Runs `mode` on `V = D + 4` lanes (`input`: `δd` or `w`).
    fn run(
        &self,
        mode: Mode,
        input: &[[T; D]],
        scratch: &mut [T],
        out: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check::mesh_dim::<D>();
        match (mode, D) {
            (Mode::Tangent, 2) => tangent_packed::<T, D, 6>(self, input, scratch, out),
            (Mode::Tangent, _) => tangent_packed::<T, D, 7>(self, input, scratch, out),
            (Mode::Adjoint, 2) => adjoint_packed::<T, D, 6>(self, input, scratch, out),
            (Mode::Adjoint, _) => adjoint_packed::<T, D, 7>(self, input, scratch, out),
        }
    }

    /// Validates the input (those of [`deform_spring_with`](crate::quaternion::deform_spring_with)),
    /// splits `scratch` and computes the boundary rotations into `bnd`. Returns the origin.
    fn prepare<'s, const V: usize>(
        &self,
        scratch: &'s mut [T],
    ) -> Result<([T; D], Parts<'s, T, V>)> {
        let (n, b) = (self.points.len(), self.motion.nodes.len());
        check::len("sys", self.sys.node_count(), n)?;
        let needed = deform_spring_sensitivity_scratch_len::<T, D>(&self.solver, n, b);
        check::buffer("scratch", scratch.len(), needed)?;
        self.options.check()?;
        let (packed, bnd) = take(scratch, n.saturating_mul(V).saturating_mul(2));
        let (base, second) = packed
            .as_chunks_mut::<V>()
            .0
            .split_at_mut_checked(n)
            .unwrap_or_default();
        let (bnd, solve) = take(bnd, deform_idw_sensitivity_scratch_len::<D>(n, b));
        let sys = self.sys;
        let origin = prepare(self.points, self.motion, bnd, |marks| {
            let same = marks
                .iter()
                .zip(sys.fixed())
                .all(|(m, &f)| (*m != T::ZERO) == crate::spring::is_fixed(f));
            if same {
                Ok(())
            } else {
                Err(Error::InvalidParameter {
                    arg: "sys",
                    reason: "the fixed mask must mark exactly the boundary nodes",
                })
            }
        })?;
        let solve = solve.as_chunks_mut::<V>().0;
        Ok((
            origin,
            Parts {
                base,
                second,
                bnd,
                solve,
            },
        ))
    }

    /// The hemisphere reference of the forward: the rotation of the first fixed node (in node
    /// order). `qs` holds `Q_k` per boundary point.
    fn reference(&self, qs: &[T]) -> Quat<T> {
        let first = self
            .motion
            .nodes
            .iter()
            .enumerate()
            .min_by_key(|p| *p.1)
            .map_or(0, |(k, _)| k);
        Quat::from_array(load(qs, first))
    }

    /// The forward's packed boundary values `(Δ_k, ±Q_k)`, given to `f` with their node.
    fn pack_boundary<const V: usize>(
        &self,
        origin: [T; D],
        qs: &[T],
        mut f: impl FnMut(usize, [T; V]),
    ) {
        let reference = self.reference(qs);
        let u = Pts::mapped(self.points, self.motion.nodes);
        for (k, (&i, &dk)) in self
            .motion
            .nodes
            .iter()
            .zip(self.motion.deformed)
            .enumerate()
        {
            let q = Quat::from_array(load(qs, k));
            let t = translation(
                origin,
                u.get(k),
                dk,
                q.normalize().unwrap_or(Quat::identity()),
            );
            let q = if q.dot(reference) < T::ZERO { -q } else { q };
            f(i as usize, pack(t, q));
        }
    }

    /// The forward's propagation solve: `(Δ_k, ±Q_k)` packed at the fixed nodes, the free
    /// nodes started at their mean, solved; every free `S_i` must normalise.
    fn base_solve<const V: usize>(
        &self,
        origin: [T; D],
        qs: &[T],
        values: &mut [[T; V]],
        solve: &mut [[T; V]],
    ) -> Result<SolveReport<T>> {
        self.pack_boundary::<V>(origin, qs, |i, p| {
            if let Some(v) = values.get_mut(i) {
                *v = p;
            }
        });
        start_at_fixed_mean(self.sys, values);
        let report = self
            .sys
            .solve_linear_with(values, self.solver, self.options, solve)?;
        check_rotations::<T, D, V>(self.sys, values)?;
        Ok(report)
    }

    /// The base field: the given solved one (checked: `N` packed values whose boundary
    /// values are this motion's, bit for bit) or the base solve into `values`. `None` for
    /// the report when nothing was solved.
    fn base<'v, const V: usize>(
        &'v self,
        origin: [T; D],
        qs: &[T],
        values: &'v mut [[T; V]],
        solve: &mut [[T; V]],
    ) -> Result<Base<'v, T, V>> {
        let Some(field) = self.solved else {
            let report = self.base_solve(origin, qs, values, solve)?;
            return Ok((values, Some(report)));
        };
        let field = field.as_chunks::<V>().0;
        check::len("field", field.len(), self.points.len())?;
        let mut same = true;
        self.pack_boundary::<V>(origin, qs, |i, p| same &= field.get(i) == Some(&p));
        if !same {
            return Err(Error::InvalidParameter {
                arg: "motion",
                reason: "not the motion of the solved step (the plan's last step)",
            });
        }
        Ok((field, None))
    }

    /// `±1`: the hemisphere sign the forward gave boundary rotation `k`.
    fn sign(q: [T; 4], reference: Quat<T>) -> T {
        if Quat::from_array(q).dot(reference) < T::ZERO {
            -T::ONE
        } else {
            T::ONE
        }
    }
}

/// The unit propagated rotation `Q_i`, `|S_i|` and the rotation Jacobian `M(Q_i, r_i − o)` at
/// free node `i` from the solved packed value.
#[inline]
fn free_rotation<T: Real, const D: usize, const V: usize>(
    v: &[T; V],
    r: [T; D],
    origin: [T; D],
) -> (Quat<T>, T, [[T; 4]; 3]) {
    let s = unpack::<T, D, V>(v).1;
    let q = s.normalize().unwrap_or(Quat::identity());
    (q, s.norm(), drot(q, lift(sub(r, origin))))
}

/// Tangent of [`deform_spring_with`](crate::quaternion::deform_spring_with): the first-order
/// change `out = δR` of every mesh point for the change `direction = δd` of the deformed
/// boundary positions, the undeformed `points` held. `sys`, `solver` and `options` are the
/// deformation's (the fixed mask of `sys` marks exactly `motion.nodes`); boundary nodes get
/// `δd` exactly. Returns the merged report of the two solves (converged when both did).
/// `scratch` needs [`deform_spring_sensitivity_scratch_len`] scalars.
///
/// # Errors
/// Those of [`deform_spring_with`](crate::quaternion::deform_spring_with) and of
/// [`deform_idw_tangent`](crate::quaternion::deform_idw_tangent) for `direction` and `out`.
/// On error `out` is unchanged.
#[allow(clippy::too_many_arguments)]
pub fn deform_spring_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    direction: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    check::len("direction", direction.len(), motion.nodes.len())?;
    check::len("out", out.len(), points.len())?;
    let s = (points, motion, sys, solver, options);
    Setup::from(s).run(Mode::Tangent, direction, scratch, out)
}

/// [`deform_spring_tangent`] on `V = D + 4` lanes, after its length checks.
fn tangent_packed<T: Real, const D: usize, const V: usize>(
    s: &Setup<'_, '_, T, D>,
    direction: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let (origin, p) = s.prepare::<V>(scratch)?;
    check::finite_items("direction", direction)?;
    boundary_tangent(s.points, s.motion, origin, direction, p.bnd)?;
    let b = s.motion.nodes.len();
    let (qs, rest) = take(p.bnd, 4 * b);
    let (dq, rest) = take(rest, 4 * b);
    let dt = rest.get(..3 * b).unwrap_or_default();
    let (base, base_report) = s.base(origin, qs, p.base, p.solve)?;
    let reference = s.reference(qs);
    for v in p.second.iter_mut() {
        *v = [T::ZERO; V];
    }
    for (k, &i) in s.motion.nodes.iter().enumerate() {
        let sign = Setup::<T, D>::sign(load(qs, k), reference);
        let dqk: [T; 4] = load(dq, k).map(|x: T| sign * x);
        if let Some(v) = p.second.get_mut(i as usize) {
            *v = pack(drop3::<T, D>(load(dt, k)), Quat::from_array(dqk));
        }
    }
    let report = s
        .sys
        .solve_linear_with(p.second, s.solver, s.options, p.solve)?;
    for (i, (v, dv)) in base.iter().zip(p.second.iter()).enumerate() {
        let r = s.points.get(i).copied().unwrap_or([T::ZERO; D]);
        let (q, len, m) = free_rotation::<T, D, V>(v, r, origin);
        let (dtv, ds) = unpack::<T, D, V>(dv);
        if let Some(o) = out.get_mut(caller(s.order, i)) {
            *o = add(dtv, drop3(mul34(&m, proj4(q, len, ds.to_array()))));
        }
    }
    for (k, &i) in s.motion.nodes.iter().enumerate() {
        if let Some(o) = out.get_mut(caller(s.order, i as usize)) {
            *o = direction.get(k).copied().unwrap_or([T::ZERO; D]);
        }
    }
    Ok(merge(base_report, report))
}

/// Adjoint of [`deform_spring_with`](crate::quaternion::deform_spring_with): `out = (∂R/∂d)ᵀ
/// w` for `weights = w = dJ/dR` (one per mesh point), i.e. `dJ/dd` per boundary point (in
/// `motion.nodes` order): the transpose of [`deform_spring_tangent`]. `solver` must be CG
/// ([`LinearMethod::Cg`](crate::spring::LinearMethod::Cg)) or [`LinearSolver::Amg`] (the
/// adjoint solve is [`spring_adjoint`]'s). Returns the merged report of the two solves.
/// `scratch` needs [`deform_spring_sensitivity_scratch_len`] scalars.
///
/// # Errors
/// Those of [`deform_spring_tangent`] with `weights` (one per point, finite) in place of
/// `direction` and `out` one per boundary point, and those of [`spring_adjoint`]. On error
/// `out` is unchanged.
#[allow(clippy::too_many_arguments)]
pub fn deform_spring_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    weights: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    check::len("weights", weights.len(), points.len())?;
    check::len("out", out.len(), motion.nodes.len())?;
    let s = (points, motion, sys, solver, options);
    Setup::from(s).run(Mode::Adjoint, weights, scratch, out)
}

/// [`deform_spring_adjoint`] on `V = D + 4` lanes, after its length checks.
fn adjoint_packed<T: Real, const D: usize, const V: usize>(
    s: &Setup<'_, '_, T, D>,
    weights: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    if spring_adjoint_scratch_len::<T, V>(&s.solver, s.points.len()) == usize::MAX {
        return Err(Error::InvalidParameter {
            arg: "solver",
            reason: "the adjoint needs CG (LinearMethod::Cg) or multigrid (LinearSolver::Amg)",
        });
    }
    let (origin, p) = s.prepare::<V>(scratch)?;
    check::finite_items("weights", weights)?;
    boundary_adjoint_check(s.points, s.motion, p.bnd)?;
    let b = s.motion.nodes.len();
    let base_report = {
        let qs = p.bnd.get(..4 * b).unwrap_or_default();
        let (base, report) = s.base(origin, qs, &mut *p.base, &mut *p.solve)?;
        sources(s, origin, base, weights, p.second);
        report
    };
    // `base` is free again: it receives the adjoint solve's `g`.
    let report = spring_adjoint(s.sys, s.solver, s.options, p.second, p.base, p.solve)?;
    let (qs, rest) = take(p.bnd, 4 * b);
    let (dq, dt) = take(rest, 4 * b);
    let reference = s.reference(qs);
    for (k, (&i, o)) in s.motion.nodes.iter().zip(out.iter_mut()).enumerate() {
        let g = p.base.get(i as usize).copied().unwrap_or([T::ZERO; V]);
        let (tb, qb) = unpack::<T, D, V>(&g);
        let sign = Setup::<T, D>::sign(load(qs, k), reference);
        store(dq, k, qb.to_array().map(|x| sign * x));
        store(dt, k, lift(tb));
        *o = drop3(get3(weights, caller(s.order, i as usize)));
    }
    boundary_adjoint(s.points, s.motion, origin, p.bnd, out)?;
    Ok(merge(base_report, report))
}

/// The free nodes' adjoint sources `(Δ̄_i, S̄_i)` from the solved field `base` into `f`;
/// zero at the fixed nodes.
fn sources<T: Real, const D: usize, const V: usize>(
    s: &Setup<'_, '_, T, D>,
    origin: [T; D],
    base: &[[T; V]],
    weights: &[[T; D]],
    f: &mut [[T; V]],
) {
    for (i, (f, v)) in f.iter_mut().zip(base.iter()).enumerate() {
        if s.sys.is_fixed(i) {
            *f = [T::ZERO; V];
            continue;
        }
        let r = s.points.get(i).copied().unwrap_or([T::ZERO; D]);
        let (q, len, m) = free_rotation::<T, D, V>(v, r, origin);
        let w = weights
            .get(caller(s.order, i))
            .copied()
            .unwrap_or([T::ZERO; D]);
        let sb = proj4(q, len, mul34t(&m, lift(w)));
        *f = pack(w, Quat::from_array(sb));
    }
}
