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
//! costs two solves. The solves are iterative: the results are the derivative of the exact
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

    /// The forward's propagation solve: `(Δ_k, ±Q_k)` packed at the fixed nodes, the free
    /// nodes started at their mean, solved; every free `S_i` must normalise.
    fn base_solve<const V: usize>(
        &self,
        origin: [T; D],
        qs: &[T],
        values: &mut [[T; V]],
        solve: &mut [[T; V]],
    ) -> Result<SolveReport<T>> {
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
            if let Some(v) = values.get_mut(i as usize) {
                *v = pack(t, q);
            }
        }
        start_at_fixed_mean(self.sys, values);
        let report = self
            .sys
            .solve_linear_with(values, self.solver, self.options, solve)?;
        check_rotations::<T, D, V>(self.sys, values)?;
        Ok(report)
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
    let base = s.base_solve(origin, qs, p.base, p.solve)?;
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
    for (i, (o, (v, dv))) in out
        .iter_mut()
        .zip(p.base.iter().zip(p.second.iter()))
        .enumerate()
    {
        let r = s.points.get(i).copied().unwrap_or([T::ZERO; D]);
        let (q, len, m) = free_rotation::<T, D, V>(v, r, origin);
        let (dtv, ds) = unpack::<T, D, V>(dv);
        *o = add(dtv, drop3(mul34(&m, proj4(q, len, ds.to_array()))));
    }
    for (k, &i) in s.motion.nodes.iter().enumerate() {
        if let Some(o) = out.get_mut(i as usize) {
            *o = direction.get(k).copied().unwrap_or([T::ZERO; D]);
        }
    }
    Ok(merge(Some(base), report))
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
    let base = {
        let qs = p.bnd.get(..4 * b).unwrap_or_default();
        s.base_solve(origin, qs, p.base, p.solve)?
    };
    // The free nodes' sources (Δ̄_i, S̄_i) into `second`; zero at the fixed nodes.
    for (i, (f, v)) in p.second.iter_mut().zip(p.base.iter()).enumerate() {
        if s.sys.is_fixed(i) {
            *f = [T::ZERO; V];
            continue;
        }
        let r = s.points.get(i).copied().unwrap_or([T::ZERO; D]);
        let (q, len, m) = free_rotation::<T, D, V>(v, r, origin);
        let w = weights.get(i).copied().unwrap_or([T::ZERO; D]);
        let sb = proj4(q, len, mul34t(&m, lift(w)));
        *f = pack(w, Quat::from_array(sb));
    }
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
        *o = drop3(get3(weights, i as usize));
    }
    boundary_adjoint(s.points, s.motion, origin, p.bnd, out)?;
    Ok(merge(Some(base), report))
}
