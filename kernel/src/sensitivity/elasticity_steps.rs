//! Tangent and adjoint of multi-step linear elasticity ([`deform_incremental`]): the
//! boundary displacement `d` applied in `N` increments, the moduli and the stiffness
//! re-assembled on the moved mesh before each. The map `d ↦ x_N` is not linear; its exact
//! linearisation, step by step (`x_0` the undeformed mesh, `u_s` step `s`'s displacement),
//!
//! ```text
//! x_s = x_{s−1} + u_s,     K(x_{s−1}) u_s = 0 at free nodes,  u_s = d/N at fixed nodes
//! δx_s = δx_{s−1} + δu_s,  K_ff δu_s = −K_fb δd/N − ((∂K/∂x · δx_{s−1}) u_s)_f
//! ```
//!
//! and its adjoint, backwards from `x̄_N = w`: `K_ff λ_s = x̄_{s,f}`, `ḡ += (x̄_s − K λ_s)_b / N`,
//! `x̄_{s−1} = x̄_s − ∇ₓ(λ_sᵀ K(x_{s−1}) u_s)`. `∂K/∂x` is that of the element stiffness and
//! of the inverse-volume modulus (see `elastic_geometry`). Held fixed, as not differentiable:
//! nothing else here (the wall-distance modulus uses the reference mesh's distances and its
//! clamp does not see the moved mesh; the sign of `det J` does not change on a valid mesh).
//!
//! The tangent runs each step's deformation solve and one derivative solve (`2N` solves);
//! the adjoint runs the deformation once, keeping each `u_s` (`N·n` items of scratch), then
//! rebuilds `x_{s−1}` bit for bit from them and solves once per step backwards (`2N` solves,
//! `2N` assemblies).

use super::elastic_geometry::Stiffness;
use super::elasticity::{elastic_tangent, elastic_tangent_scratch_len, solve_free};
use super::ElasticPreconditioner;
use crate::cells::Cells;
use crate::check;
use crate::elasticity::{
    advance, assemble, cell_moduli, check_poisson, step_data, Block, ElasticSystem,
    IncrementBuffers, IncrementReport, Increments,
};
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::spring::{is_fixed, SolveOptions, SolveReport};
use crate::vector;

#[cfg(doc)]
use crate::elasticity::deform_incremental;

/// The multi-step deformation being differentiated: the arguments of [`deform_incremental`]
/// (with `points` the undeformed mesh, unchanged) and the solver of every step.
#[derive(Clone, Copy, Debug)]
pub struct IncrementProblem<'a, T: Real, const D: usize> {
    /// The cells.
    pub cells: &'a Cells<'a>,
    /// The cell-pair graph ([`elasticity_graph`](crate::elasticity::elasticity_graph)).
    pub graph: &'a Graph<'a>,
    /// Fixed mask (nonzero: prescribed displacement).
    pub fixed: &'a [u8],
    /// Modulus, Poisson ratio, number of steps.
    pub params: &'a Increments<'a, T>,
    /// The undeformed mesh.
    pub points: &'a [[T; D]],
    /// The prescribed displacement `d` (read at fixed nodes).
    pub displacement: &'a [[T; D]],
    /// The preconditioner of every solve (the deformation's and the derivative's).
    pub pre: ElasticPreconditioner<'a, T>,
    /// Stopping rules of every solve.
    pub options: SolveOptions<T>,
}

/// `[T; D]` scratch items of [`elastic_incremental_tangent`]: `4 n` and the solves'
/// ([`elastic_tangent_scratch_len`]); `usize::MAX` on overflow.
pub fn elastic_incremental_tangent_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
) -> usize {
    node_count
        .saturating_mul(4)
        .saturating_add(elastic_tangent_scratch_len(pre, node_count))
}

/// `[T; D]` scratch items of [`elastic_incremental_adjoint`]: every step's displacement
/// (`steps · n`) and [`elastic_incremental_tangent_scratch_len`]; `usize::MAX` on overflow.
pub fn elastic_incremental_adjoint_scratch_len<T: Real>(
    pre: &ElasticPreconditioner<'_, T>,
    node_count: usize,
    steps: usize,
) -> usize {
    node_count
        .saturating_mul(steps)
        .saturating_add(elastic_incremental_tangent_scratch_len(pre, node_count))
}

/// The checks of [`deform_incremental`], `field` (one finite item per node) and the options.
fn check_problem<T: Real, const D: usize>(
    p: &IncrementProblem<'_, T, D>,
    field: (&'static str, &[[T; D]]),
    buffers: &IncrementBuffers<'_, T, D>,
) -> Result<()> {
    let n = p.points.len();
    check::len("displacement", p.displacement.len(), n)?;
    check::finite_items("displacement", p.displacement)?;
    check::len("fixed", p.fixed.len(), n)?;
    check::len("current", buffers.current.len(), n)?;
    check::len("step", buffers.step.len(), n)?;
    check::len(field.0, field.1.len(), n)?;
    check::finite_items(field.0, field.1)?;
    if p.params.steps == 0 {
        return Err(Error::InvalidParameter {
            arg: "steps",
            reason: "must be at least 1",
        });
    }
    check_poisson(p.params.poisson)?;
    p.options.check()
}

/// Moduli, stiffness and system on the mesh `current`.
fn system_at<'b, 'p: 'b, T: Real, const D: usize>(
    p: &IncrementProblem<'p, T, D>,
    current: &[[T; D]],
    moduli: &'b mut [T],
    diag: &'b mut [Block<T, D>],
    off: &'b mut [Block<T, D>],
) -> Result<(ElasticSystem<'b, T, D>, &'b [T])> {
    let params = p.params;
    cell_moduli(
        p.cells,
        current,
        params.modulus,
        params.wall_distance,
        moduli,
    )?;
    assemble(p.cells, current, p.graph, moduli, params.poisson, diag, off)?;
    let (diag, off): (&'b [Block<T, D>], &'b [Block<T, D>]) = (diag, off);
    Ok((ElasticSystem::new(*p.graph, diag, off, p.fixed)?, moduli))
}

/// The next `len` items of `rest`.
fn take<'s, X>(rest: &mut &'s mut [X], len: usize, needed: usize) -> Result<&'s mut [X]> {
    let all = core::mem::take(rest);
    let actual = all.len();
    let (a, b) = all.split_at_mut_checked(len).ok_or(Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual,
    })?;
    *rest = b;
    Ok(a)
}

/// `dst = src` item by item.
fn copy<X: Copy>(dst: &mut [X], src: &[X]) {
    dst.iter_mut().zip(src).for_each(|(d, s)| *d = *s);
}

/// Adds one solve to the report.
fn count<T: Real>(report: &mut IncrementReport<T>, r: SolveReport<T>) {
    report.iterations = report.iterations.saturating_add(r.iterations);
    report.max_step_iterations = report.max_step_iterations.max(r.iterations);
    report.residual = report.residual.max(r.residual);
    report.converged &= r.converged;
}

fn empty_report<T: Real>() -> IncrementReport<T> {
    IncrementReport {
        steps: 0,
        iterations: 0,
        max_step_iterations: 0,
        residual: T::ZERO,
        converged: true,
    }
}

/// `[before, fraction]` of step `s` of `n` (1-based) and whether it is the last.
fn fractions<T: Real>(s: usize, n: usize) -> ([T; 2], bool) {
    let total = T::from_usize(n);
    let before = T::from_usize(s.saturating_sub(1)) / total;
    ([before, T::from_usize(s) / total], s == n)
}

/// The error of a cell the derivative could not evaluate (the assembly rejects it first).
const DEGENERATE: Error = Error::NonPositive {
    arg: "cells",
    position: 0,
};

/// The tangent `δx_N = J δd` of [`deform_incremental`]: `dx` holds `δd` at fixed nodes
/// (read there only) and, on `Ok`, `δx_N` at every node (exactly `δd` at fixed nodes). The
/// deformation itself runs alongside in `buffers` (its mesh ends in `buffers.current`).
/// The report counts the deformation's and the derivative's solves.
///
/// # Errors
/// `dx` is unchanged on error: those of [`deform_incremental`] at any step; `dx` not one
/// finite item per node; bad options; `scratch` shorter than
/// [`elastic_incremental_tangent_scratch_len`] ([`Error::BufferTooSmall`]); the solves'
/// ([`Error::SingularSystem`], [`Error::Overflow`]); a non-finite result
/// ([`Error::NonFinite`]).
pub fn elastic_incremental_tangent<T: Real, const D: usize>(
    p: &IncrementProblem<'_, T, D>,
    dx: &mut [[T; D]],
    buffers: IncrementBuffers<'_, T, D>,
    scratch: &mut [[T; D]],
) -> Result<IncrementReport<T>> {
    check_problem(p, ("dx", dx), &buffers)?;
    let n = p.points.len();
    let needed = elastic_incremental_tangent_scratch_len(&p.pre, n);
    check::buffer("scratch", scratch.len(), needed)?;
    let mut rest = scratch;
    let acc = take(&mut rest, n, needed)?;
    let du = take(&mut rest, n, needed)?;
    let r = take(&mut rest, n, needed)?;
    let z = take(&mut rest, n, needed)?;
    let IncrementBuffers {
        moduli,
        diag,
        off,
        current,
        step,
    } = buffers;
    copy(current, p.points);
    acc.iter_mut().for_each(|a| *a = [T::ZERO; D]);
    let inv = T::ONE / T::from_usize(p.params.steps);
    let mut report = empty_report();
    for s in 1..=p.params.steps {
        let (sys, moduli) = system_at(p, current, &mut *moduli, &mut *diag, &mut *off)?;
        let (range, last) = fractions::<T>(s, p.params.steps);
        step_data(step, p.displacement, p.fixed, range, last);
        count(
            &mut report,
            elastic_tangent(&sys, p.pre, &p.options, step, rest)?,
        );
        for (i, (d, &v)) in du.iter_mut().zip(dx.iter()).enumerate() {
            *d = if sys.is_fixed(i) {
                vector::scale(v, inv)
            } else {
                [T::ZERO; D]
            };
        }
        sys.multiply(du, z)?;
        r.iter_mut().for_each(|x| *x = [T::ZERO; D]);
        let k = stiffness(p, current, moduli);
        if !k.forward(acc, step, r) {
            return Err(DEGENERATE);
        }
        for (i, (ri, zi)) in r.iter_mut().zip(z.iter()).enumerate() {
            *ri = if sys.is_fixed(i) {
                [T::ZERO; D]
            } else {
                vector::scale(vector::add(*ri, *zi), -T::ONE)
            };
        }
        count(
            &mut report,
            solve_free(&sys, p.pre, &p.options, r, z, rest)?,
        );
        for (i, ((a, d), zi)) in acc.iter_mut().zip(du.iter()).zip(z.iter()).enumerate() {
            let step_i = if sys.is_fixed(i) { *d } else { *zi };
            *a = vector::add(*a, step_i);
        }
        advance(
            current,
            step,
            p.points,
            p.displacement,
            p.fixed,
            range[1],
            last,
        );
        report.steps = s;
    }
    check::finite_items("dx", acc)?;
    for (i, (d, a)) in dx.iter_mut().zip(acc.iter()).enumerate() {
        if !is_fixed(p.fixed.get(i).copied().unwrap_or(0)) {
            *d = *a;
        }
    }
    Ok(report)
}

fn stiffness<'a, T: Real, const D: usize>(
    p: &IncrementProblem<'a, T, D>,
    current: &'a [[T; D]],
    moduli: &'a [T],
) -> Stiffness<'a, T, D> {
    Stiffness {
        cells: p.cells,
        points: current,
        moduli,
        poisson: p.params.poisson,
        modulus: p.params.modulus,
    }
}

/// The adjoint `g = Jᵀ w` of [`deform_incremental`]: for `w = dJ/dx_N` at every node,
/// `g = dJ/dd` at fixed nodes (zero at free ones). Runs the deformation once (its mesh
/// ends in `buffers.current` only through the backward sweep's last rebuild: treat
/// `buffers` as scratch), then one adjoint solve per step backwards. The report counts
/// both sweeps' solves.
///
/// # Errors
/// `g` is unchanged on error: those of [`elastic_incremental_tangent`] with `w` for `dx`,
/// `g` not one item per node, `scratch` shorter than
/// [`elastic_incremental_adjoint_scratch_len`].
pub fn elastic_incremental_adjoint<T: Real, const D: usize>(
    p: &IncrementProblem<'_, T, D>,
    w: &[[T; D]],
    g: &mut [[T; D]],
    buffers: IncrementBuffers<'_, T, D>,
    scratch: &mut [[T; D]],
) -> Result<IncrementReport<T>> {
    check_problem(p, ("w", w), &buffers)?;
    let n = p.points.len();
    check::len("g", g.len(), n)?;
    let steps = p.params.steps;
    let needed = elastic_incremental_adjoint_scratch_len(&p.pre, n, steps);
    check::buffer("scratch", scratch.len(), needed)?;
    let mut rest = scratch;
    let trajectory = take(&mut rest, n.saturating_mul(steps), needed)?;
    let bar = take(&mut rest, n, needed)?;
    let lambda = take(&mut rest, n, needed)?;
    let tmp = take(&mut rest, n, needed)?;
    let acc = take(&mut rest, n, needed)?;
    let IncrementBuffers {
        moduli,
        diag,
        off,
        current,
        step,
    } = buffers;
    let mut report = empty_report();
    copy(current, p.points);
    for (s, keep) in (1..=steps).zip(trajectory.chunks_exact_mut(n.max(1))) {
        let (sys, _) = system_at(p, current, &mut *moduli, &mut *diag, &mut *off)?;
        let (range, last) = fractions::<T>(s, steps);
        step_data(step, p.displacement, p.fixed, range, last);
        count(
            &mut report,
            elastic_tangent(&sys, p.pre, &p.options, step, rest)?,
        );
        copy(keep, step);
        advance(
            current,
            step,
            p.points,
            p.displacement,
            p.fixed,
            range[1],
            last,
        );
        report.steps = s;
    }
    copy(bar, w);
    acc.iter_mut().for_each(|a| *a = [T::ZERO; D]);
    let inv = T::ONE / T::from_usize(steps);
    for s in (1..=steps).rev() {
        copy(current, p.points);
        for (k, u) in (1..s).zip(trajectory.chunks_exact(n.max(1))) {
            let (range, last) = fractions::<T>(k, steps);
            advance(
                current,
                u,
                p.points,
                p.displacement,
                p.fixed,
                range[1],
                last,
            );
        }
        let (sys, moduli) = system_at(p, current, &mut *moduli, &mut *diag, &mut *off)?;
        count(
            &mut report,
            solve_free(&sys, p.pre, &p.options, bar, lambda, rest)?,
        );
        sys.multiply(lambda, tmp)?;
        for (i, (a, (b, t))) in acc.iter_mut().zip(bar.iter().zip(tmp.iter())).enumerate() {
            if sys.is_fixed(i) {
                *a = vector::add(*a, vector::scale(vector::sub(*b, *t), inv));
            }
        }
        let u = trajectory
            .chunks_exact(n.max(1))
            .nth(s - 1)
            .ok_or(DEGENERATE)?;
        tmp.iter_mut().for_each(|x| *x = [T::ZERO; D]);
        if !stiffness(p, current, moduli).reverse(lambda, u, tmp) {
            return Err(DEGENERATE);
        }
        for (b, t) in bar.iter_mut().zip(tmp.iter()) {
            *b = vector::sub(*b, *t);
        }
    }
    check::finite_items("g", acc)?;
    for (i, (gi, a)) in g.iter_mut().zip(acc.iter()).enumerate() {
        *gi = if is_fixed(p.fixed.get(i).copied().unwrap_or(0)) {
            *a
        } else {
            [T::ZERO; D]
        };
    }
    Ok(report)
}
