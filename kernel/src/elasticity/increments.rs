//! Load increments with re-assembly (SU2_DEF's `DEFORM_NONLINEAR_ITER`): the prescribed
//! boundary displacement is applied in `N` equal steps; before each, the moduli and the
//! stiffness are recomputed on the mesh the previous steps produced, so cells that have
//! been squeezed stiffen before they are squeezed further.

use super::{assemble, cell_moduli, Block, ElasticSystem, Modulus};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::spring::{is_fixed, SolveReport};

/// What [`deform_incremental`] is asked to do.
#[derive(Clone, Copy, Debug)]
pub struct Increments<'w, T> {
    /// How each cell's Young's modulus is chosen, on the mesh of each step.
    pub modulus: Modulus,
    /// Per-node wall distances for [`Modulus::WallDistance`] (of the reference mesh, as
    /// SU2 computes them once); ignored otherwise.
    pub wall_distance: Option<&'w [T]>,
    /// Poisson ratio: `(−1, ½)`, or above ½ for SU2's `DEFORM_COEFF` convention.
    pub poisson: T,
    /// Number of increments `N ≥ 1` (1: one linear solve).
    pub steps: usize,
}

/// The caller's buffers for [`deform_incremental`].
#[derive(Debug)]
pub struct IncrementBuffers<'b, T, const D: usize> {
    /// One modulus per cell.
    pub moduli: &'b mut [T],
    /// One block per node.
    pub diag: &'b mut [Block<T, D>],
    /// One block per directed edge of the graph.
    pub off: &'b mut [Block<T, D>],
    /// The mesh of the current step (`n` points).
    pub current: &'b mut [[T; D]],
    /// The current step's displacement (`n` items).
    pub step: &'b mut [[T; D]],
}

/// What the increments did. A step whose solve did not converge is counted, never hidden.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct IncrementReport<T> {
    /// Steps taken.
    pub steps: usize,
    /// CG iterations of all steps.
    pub iterations: usize,
    /// The most iterations one step needed.
    pub max_step_iterations: usize,
    /// The largest final relative residual of a step.
    pub residual: T,
    /// Whether every step's solve converged.
    pub converged: bool,
}

/// Moves `points` by linear elasticity in `params.steps` increments: the fixed nodes move
/// by `displacement` (read at fixed nodes only), a fraction `s/N` after step `s`; each step
/// recomputes the moduli and the stiffness on the current mesh, builds its
/// [`ElasticSystem`] and calls `solve(system, step)`, where `step` holds the step's
/// displacement at fixed nodes and zero (the initial guess) at free ones (use
/// [`ElasticSystem::solve`] or [`ElasticSystem::solve_amg`] with buffers of your own). The
/// fixed nodes end at `points + displacement` bit for bit.
///
/// # Errors
/// `points` is unchanged on error: wrong lengths ([`Error::LengthMismatch`]), non-finite
/// `displacement` ([`Error::NonFinite`]), `steps == 0` ([`Error::InvalidParameter`]), and
/// those of [`cell_moduli`], [`assemble`], [`ElasticSystem::new`] and `solve` at any step
/// (a cell that degenerates on the way: [`Error::NonPositive`], `"cells"`).
#[allow(clippy::too_many_arguments)]
pub fn deform_incremental<T, const D: usize, S>(
    cells: &Cells<'_>,
    graph: &Graph<'_>,
    fixed: &[u8],
    params: &Increments<'_, T>,
    points: &mut [[T; D]],
    displacement: &[[T; D]],
    buffers: IncrementBuffers<'_, T, D>,
    mut solve: S,
) -> Result<IncrementReport<T>>
where
    T: Real,
    S: FnMut(&ElasticSystem<'_, T, D>, &mut [[T; D]]) -> Result<SolveReport<T>>,
{
    deform_incremental_on(
        cells,
        graph,
        fixed,
        params,
        points,
        displacement,
        buffers,
        |sys, _, step| solve(sys, step),
    )
}

/// [`deform_incremental`] whose `solve` also sees the mesh of the step (the points the
/// stiffness was assembled on), e.g. for the rigid-body modes of
/// [`ElasticSystem::rigid_amg`]: `solve(system, mesh, step)`.
///
/// # Errors
/// Those of [`deform_incremental`].
#[allow(clippy::too_many_arguments)]
pub fn deform_incremental_on<T, const D: usize, S>(
    cells: &Cells<'_>,
    graph: &Graph<'_>,
    fixed: &[u8],
    params: &Increments<'_, T>,
    points: &mut [[T; D]],
    displacement: &[[T; D]],
    buffers: IncrementBuffers<'_, T, D>,
    mut solve: S,
) -> Result<IncrementReport<T>>
where
    T: Real,
    S: FnMut(&ElasticSystem<'_, T, D>, &[[T; D]], &mut [[T; D]]) -> Result<SolveReport<T>>,
{
    let n = points.len();
    check::len("displacement", displacement.len(), n)?;
    check::finite_items("displacement", displacement)?;
    check::len("fixed", fixed.len(), n)?;
    check::len("current", buffers.current.len(), n)?;
    check::len("step", buffers.step.len(), n)?;
    if params.steps == 0 {
        return Err(Error::InvalidParameter {
            arg: "steps",
            reason: "must be at least 1",
        });
    }
    super::check_poisson(params.poisson)?;
    let IncrementBuffers {
        moduli,
        diag,
        off,
        current,
        step,
    } = buffers;
    for (c, p) in current.iter_mut().zip(points.iter()) {
        *c = *p;
    }
    let mut report = IncrementReport {
        steps: 0,
        iterations: 0,
        max_step_iterations: 0,
        residual: T::ZERO,
        converged: true,
    };
    let total = T::from_usize(params.steps);
    for s in 1..=params.steps {
        cell_moduli(cells, current, params.modulus, params.wall_distance, moduli)?;
        assemble(cells, current, graph, moduli, params.poisson, diag, off)?;
        let sys = ElasticSystem::new(*graph, diag, off, fixed)?;
        let fraction = T::from_usize(s) / total;
        let before = T::from_usize(s - 1) / total;
        step_data(
            step,
            displacement,
            fixed,
            [before, fraction],
            s == params.steps,
        );
        let r = solve(&sys, current, step)?;
        report.steps = s;
        report.iterations = report.iterations.saturating_add(r.iterations);
        report.max_step_iterations = report.max_step_iterations.max(r.iterations);
        report.residual = report.residual.max(r.residual);
        report.converged &= r.converged;
        advance(
            current,
            step,
            points,
            displacement,
            fixed,
            fraction,
            s == params.steps,
        );
    }
    if let Some(position) = current
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(Error::NonFinite {
            arg: "points",
            position,
        });
    }
    for (p, c) in points.iter_mut().zip(current.iter()) {
        *p = *c;
    }
    Ok(report)
}

/// Moves `current` by the step's displacement `step`: free nodes by `step`, fixed nodes to
/// `points + fraction · displacement` (exactly `points + displacement` after the `last`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn advance<T: Real, const D: usize>(
    current: &mut [[T; D]],
    step: &[[T; D]],
    points: &[[T; D]],
    displacement: &[[T; D]],
    fixed: &[u8],
    fraction: T,
    last: bool,
) {
    for (i, (c, d)) in current.iter_mut().zip(step.iter()).enumerate() {
        *c = if is_fixed(fixed.get(i).copied().unwrap_or(0)) {
            target(points, displacement, i, fraction, last)
        } else {
            crate::vector::add(*c, *d)
        };
    }
}

/// The step's displacement: `(to − from) · d` at fixed nodes (`to` exactly 1 for the last
/// step), zero (the initial guess) at free ones.
pub(crate) fn step_data<T: Real, const D: usize>(
    step: &mut [[T; D]],
    displacement: &[[T; D]],
    fixed: &[u8],
    [from, to]: [T; 2],
    last: bool,
) {
    for (i, st) in step.iter_mut().enumerate() {
        *st = [T::ZERO; D];
        if is_fixed(fixed.get(i).copied().unwrap_or(0)) {
            let d = displacement.get(i).copied().unwrap_or([T::ZERO; D]);
            *st = crate::vector::sub(part(d, to, last), part(d, from, false));
        }
    }
}

/// Fixed node `i`'s position after the step with `fraction` of the way done (exactly
/// `points + displacement` after the last).
fn target<T: Real, const D: usize>(
    points: &[[T; D]],
    displacement: &[[T; D]],
    i: usize,
    fraction: T,
    last: bool,
) -> [T; D] {
    let p = points.get(i).copied().unwrap_or([T::ZERO; D]);
    let d = displacement.get(i).copied().unwrap_or([T::ZERO; D]);
    crate::vector::add(p, part(d, fraction, last))
}

/// `fraction · d` (exactly `d` for the last step, zero before the first).
fn part<T: Real, const D: usize>(d: [T; D], fraction: T, last: bool) -> [T; D] {
    if last {
        d
    } else {
        crate::vector::scale(d, fraction)
    }
}
