//! Linear (Batina) springs: Jacobi and SOR sweeps, and the whole solves (Jacobi, Gauss–Seidel,
//! SOR, preconditioned CG) built on them.

use core::ops::Range;

use super::distributed::{
    check_owned, merged, merged_max, merged_with, share_field, share_halo, Collective, Serial,
};
use super::norms::{scale_by, sweep_exponent, Norm, SumSq};
use super::system::{
    check_omega, check_values, is_fixed, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem, Sweep,
};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::reduce::ExactSum;

/// Node `i`'s residual `r_i = Σ_j k_ij (x_j − x_i)` (= `b − A x` at a free node, Yang & Özgen
/// eq. 1 with the sign flipped) and diagonal `d_i = Σ_j k_ij`, summed in CSR order.
#[inline]
fn node_residual<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    i: usize,
    xi: [T; V],
    x: &[[T; V]],
) -> ([T; V], T) {
    let mut acc = [T::ZERO; V];
    let mut d = T::ZERO;
    for (j, k) in sys.row(i) {
        let xj = x.get(j).copied().unwrap_or(xi);
        for ((a, &b), &c) in acc.iter_mut().zip(&xj).zip(&xi) {
            *a += k * (b - c);
        }
        d += k;
    }
    (acc, d)
}

/// `max(|δ|)` and `Σ (σ r)²` bookkeeping for one node (`σ` a power of two, 1 in the public
/// sweeps; the whole solves pick it so the sum neither overflows nor underflows). The sum is
/// exact ([`ExactSum`]): a sweep split into ranges sums to the same bits.
#[inline]
fn tally<T: Real, const V: usize>(
    max_change: &mut T,
    residual_sq: &mut ExactSum,
    change: &[T; V],
    r: &[T; V],
    sigma: T,
) {
    for (&c, &r) in change.iter().zip(r) {
        *max_change = max_change.max(c.abs());
        let r = r * sigma;
        residual_sq.add(r * r);
    }
}

/// Jacobi sweep without validation (the solve validates once).
pub(crate) fn jacobi_core<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    nodes: Range<usize>,
    input: &[[T; V]],
    output: &mut [[T; V]],
    sigma: T,
) -> Sweep<T> {
    let mut max_change = T::ZERO;
    let mut residual_sq = ExactSum::new();
    for i in nodes {
        let Some(&xi) = input.get(i) else { continue };
        let new = if sys.is_fixed(i) {
            xi
        } else {
            let (r, d) = node_residual(sys, i, xi, input);
            let mut new = xi;
            let mut change = [T::ZERO; V];
            for ((n, c), &r) in new.iter_mut().zip(change.iter_mut()).zip(&r) {
                *c = r / d;
                *n += *c;
            }
            tally(&mut max_change, &mut residual_sq, &change, &r, sigma);
            new
        };
        if let Some(o) = output.get_mut(i) {
            *o = new;
        }
    }
    Sweep {
        max_change,
        residual_sq: residual_sq.value(),
        residual_sum: residual_sq,
    }
}

impl<T: Real> SpringSystem<'_, T> {
    /// One Jacobi sweep of the linear springs over `nodes` (Yang & Özgen §2.1, Samareh eq. 2):
    /// for each free node `i` in the range, `output[i] = x_i + Σ_j k_ij (x_j − x_i) / Σ_j k_ij`
    /// with every `x` read from `input`; fixed nodes in the range are copied; `output` outside the
    /// range is not touched. Returns the range's maximum change and residual (of `input`).
    ///
    /// `input` and `output` hold one `[T; V]` per node (the whole field: neighbours outside the
    /// range are read, e.g. halo nodes in a distributed mesh).
    ///
    /// # Errors
    /// Nothing is written on error: wrong lengths, non-finite `input`, `nodes.end > node_count`.
    pub fn jacobi_sweep<const V: usize>(
        &self,
        nodes: Range<usize>,
        input: &[[T; V]],
        output: &mut [[T; V]],
    ) -> Result<Sweep<T>> {
        let n = self.node_count();
        check_values("input", input, n)?;
        check::len("output", output.len(), n)?;
        self.check_range(&nodes)?;
        Ok(jacobi_core(self, nodes, input, output, T::ONE))
    }
}

/// SOR sweep without validation.
pub(crate) fn sor_core<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    nodes: Range<usize>,
    values: &mut [[T; V]],
    omega: T,
    sigma: T,
) -> Sweep<T> {
    let mut max_change = T::ZERO;
    let mut residual_sq = ExactSum::new();
    for i in nodes {
        if sys.is_fixed(i) {
            continue;
        }
        let Some(&xi) = values.get(i) else { continue };
        let (r, d) = node_residual(sys, i, xi, values);
        let mut new = xi;
        let mut change = [T::ZERO; V];
        for ((n, c), &r) in new.iter_mut().zip(change.iter_mut()).zip(&r) {
            *c = omega * (r / d);
            *n += *c;
        }
        tally(&mut max_change, &mut residual_sq, &change, &r, sigma);
        if let Some(o) = values.get_mut(i) {
            *o = new;
        }
    }
    Sweep {
        max_change,
        residual_sq: residual_sq.value(),
        residual_sum: residual_sq,
    }
}

impl<T: Real> SpringSystem<'_, T> {
    /// One in-place Gauss–Seidel (`omega = 1`) or SOR sweep of the linear springs over `nodes`, in
    /// increasing node order: `x_i ← x_i + ω Σ_j k_ij (x_j − x_i) / Σ_j k_ij` using the newest
    /// values. Fixed nodes are skipped. Returns the range's maximum change and residual estimate.
    ///
    /// # Errors
    /// Nothing is written on error: wrong length, non-finite `values`, `nodes.end > node_count`,
    /// `omega` outside `(0, 2)`.
    pub fn sor_sweep<const V: usize>(
        &self,
        nodes: Range<usize>,
        values: &mut [[T; V]],
        omega: T,
    ) -> Result<Sweep<T>> {
        check_values("values", values, self.node_count())?;
        self.check_range(&nodes)?;
        check_omega(omega)?;
        Ok(sor_core(self, nodes, values, omega, T::ONE))
    }
}

/// Calls `f(r_i, b_i)` for every free node `i` of the ranges, in node order: the residual
/// `r_i = Σ_j k_ij (x_j − x_i)` (= `b − A x`) and the fixed nodes' pull `b_i = Σ_{j fixed} k_ij x_j`.
#[inline]
fn for_each_free_residual<T: Real, const V: usize, F: FnMut(&[T; V], &[T; V])>(
    sys: &SpringSystem<'_, T>,
    ranges: &[Range<usize>],
    x: &[[T; V]],
    mut f: F,
) {
    for range in ranges {
        let xs = x.get(range.clone()).unwrap_or(&[]);
        for_each_free_residual_in(sys, range.clone(), xs, x, &mut f);
    }
}

#[inline]
fn for_each_free_residual_in<T: Real, const V: usize, F: FnMut(&[T; V], &[T; V])>(
    sys: &SpringSystem<'_, T>,
    range: Range<usize>,
    xs: &[[T; V]],
    x: &[[T; V]],
    f: &mut F,
) {
    for ((_, fixed, row), &xi) in sys.rows_in(range).zip(xs) {
        if fixed {
            continue;
        }
        let mut r = [T::ZERO; V];
        let mut b = [T::ZERO; V];
        for (j, k) in row {
            let xj = x.get(j).copied().unwrap_or(xi);
            let fj = sys.is_fixed(j);
            for (((r, b), &vj), &vi) in r.iter_mut().zip(b.iter_mut()).zip(&xj).zip(&xi) {
                *r += k * (vj - vi);
                if fj {
                    *b += k * vj;
                }
            }
        }
        f(&r, &b);
    }
}

/// `(‖b − A x‖₂, ‖b‖₂)` over free nodes and all components, `b_i = Σ_{j fixed} k_ij x_j`,
/// without overflow or underflow (see [`super::norms`]).
pub(crate) fn residual_norms<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    x: &[[T; V]],
) -> (Norm<T>, Norm<T>) {
    residual_norms_scaled(sys, x, &[0; V], &Serial::new(sys.node_count()))
}

/// [`residual_norms`] of a field whose component `c` is stored as `x_c · 2^−exps[c]` (the
/// scaled CG iterate): the norms of the unscaled field. Each process sums its owned rows; the
/// sums and maxima are merged (`x` must be current on every node).
pub(crate) fn residual_norms_scaled<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    x: &[[T; V]],
    exps: &[i32; V],
    comm: &dyn Collective<T>,
) -> (Norm<T>, Norm<T>) {
    let owned = comm.owned();
    // Bring every component to the largest component's scale (factors are 1 when unscaled).
    let top = exps.iter().copied().max().unwrap_or(0);
    let g = exps.map(|e| scale_by(T::ONE, e - top));
    let mut rs = SumSq::new();
    let mut bs = SumSq::new();
    for_each_free_residual(sys, owned, x, |r, b| {
        for ((&r, &b), &g) in r.iter().zip(b).zip(&g) {
            rs.add(r * g);
            bs.add(b * g);
        }
    });
    rs.merge_over(comm);
    bs.merge_over(comm);
    let (pr, pb) = (rs.plain(), bs.plain());
    let (r, b) = match (pr, pb) {
        (Ok(r), Ok(b)) => (r, b),
        _ => {
            // Second pass, each sum scaled by its own power of two.
            let qr = T::pow2(-pr.err().unwrap_or(0));
            let qb = T::pow2(-pb.err().unwrap_or(0));
            // The first pass's accumulators are reused (no more sums on the stack).
            let (sr, sb) = (&mut rs.sum, &mut bs.sum);
            (*sr, *sb) = (ExactSum::new(), ExactSum::new());
            for_each_free_residual(sys, owned, x, |r, b| {
                for ((&r, &b), &g) in r.iter().zip(b).zip(&g) {
                    let (r, b) = (r * g * qr, b * g * qb);
                    sr.add(r * r);
                    sb.add(b * b);
                }
            });
            comm.sum_exact(&mut [core::slice::from_mut(sr), core::slice::from_mut(sb)]);
            let (sr, sb) = (sr.value(), sb.value());
            (
                pr.unwrap_or_else(|e| Norm::from_sum(sr, e)),
                pb.unwrap_or_else(|e| Norm::from_sum(sb, e)),
            )
        }
    };
    (r.shifted(top), b.shifted(top))
}

impl<T: Real> SpringSystem<'_, T> {
    /// The relative residual `‖b − A x‖₂ / ‖b‖₂` of a value field for the linear springs (the
    /// measure [`SolveOptions::residual_tol`] and [`SolveReport::residual`] use).
    ///
    /// # Errors
    /// Wrong length or non-finite `values`.
    pub fn relative_residual<const V: usize>(&self, values: &[[T; V]]) -> Result<T> {
        check_values("values", values, self.node_count())?;
        let (r, b) = residual_norms(self, values);
        Ok(r.relative_to(b))
    }
}

/// The stationary sweeps form `Σ_j k_ij (x_j − x_i)` unscaled; it stays finite when
/// `max_i Σ_j k_ij · 2 max |x| ` does (the iterates stay within the data's range).
/// Otherwise [`Error::Overflow`] on `stiffness`, before anything is written.
pub(crate) fn check_sweep_range<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &[[T; V]],
) -> Result<()> {
    let vmax = values
        .iter()
        .flatten()
        .fold(T::ZERO, |m, &v| m.max(v.abs()));
    let dmax = sys.rows().fold(T::ZERO, |m, (_, _, row)| {
        m.max(row.fold(T::ZERO, |d, (_, k)| d + k))
    });
    if (dmax * (T::TWO * vmax)).is_finite() {
        Ok(())
    } else {
        Err(Error::Overflow { arg: "stiffness" })
    }
}

/// Number of `[T; V]` scratch items [`solve_linear`](crate::spring::SpringSystem::solve_linear) needs: `n` for Jacobi (the second
/// field), 0 for Gauss–Seidel and SOR, `5 n` for CG: `4 n` vectors (iterate, residual,
/// direction, and one shared by `A p` and the preconditioned residual) and the diagonal
/// `Σ_j k_ij`, `n` scalars packed `V` to an item (`⌈n / V⌉` items; `n` covers every `V`).
pub const fn solve_linear_scratch_len<T>(method: &LinearMethod<T>, node_count: usize) -> usize {
    match method {
        LinearMethod::Jacobi => node_count,
        LinearMethod::GaussSeidel | LinearMethod::Sor { .. } => 0,
        LinearMethod::Cg { .. } => node_count.saturating_mul(5),
    }
}

/// The exact CG scratch need for `V` components: `4 n + ⌈n / V⌉` items.
fn cg_scratch_len<const V: usize>(n: usize) -> usize {
    n.saturating_mul(4).saturating_add(n.div_ceil(V.max(1)))
}

impl<T: Real> SpringSystem<'_, T> {
    /// Solves the linear springs for every free node: `Σ_j k_ij (x_j − x_i) = 0` per component
    /// (Yang & Özgen eq. 1 = 0), with fixed nodes keeping their values. `values` holds the
    /// Dirichlet data at fixed nodes and the initial guess at free nodes; on `Ok` it holds the
    /// last iterate, and the report says whether it converged.
    ///
    /// Stationary methods stop on the sweep's residual estimate and then confirm with the true
    /// residual; CG confirms its recurrence residual the same way and restarts from the true
    /// residual if they disagree. The reported residual is always recomputed from the values.
    ///
    /// Residuals are measured with scaled norms and CG runs on a power-of-two-scaled copy, so any
    /// finite values are handled: the result at `2^k ·` values is exactly `2^k ·` the result
    /// (while no value is subnormal).
    ///
    /// # Errors
    /// `values` is untouched on error: wrong lengths, non-finite values, bad options or `omega`,
    /// `scratch` shorter than [`solve_linear_scratch_len`] (CG needs exactly `4 n + ⌈n / V⌉`
    /// items of it), [`Error::SingularSystem`] if CG
    /// meets non-positive curvature (cannot happen for a validated system in exact arithmetic;
    /// reported rather than hidden if rounding causes it), [`Error::Overflow`] when stiffness and
    /// values together exceed the range: for Jacobi/Gauss–Seidel/SOR when `max_i Σ_j k_ij ·
    /// 2 max |x|` overflows (`arg` = `"stiffness"`), for CG when an inner product overflows even
    /// after rescaling (`"values"`; for example `k ≈ 1e308` without a preconditioner).
    pub fn solve_linear<const V: usize>(
        &self,
        values: &mut [[T; V]],
        method: LinearMethod<T>,
        options: &SolveOptions<T>,
        scratch: &mut [[T; V]],
    ) -> Result<SolveReport<T>> {
        solve_linear_on(self, values, method, options, scratch, None)
    }
}

/// [`solve_linear`](crate::spring::SpringSystem::solve_linear), with the rows split over the processes of `comm` when given (CG with a
/// Jacobi or no preconditioner only: the other methods visit the nodes in order).
pub(crate) fn solve_linear_on<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    method: LinearMethod<T>,
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
    comm: Option<&dyn Collective<T>>,
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    if let Some(c) = comm {
        check_owned(c, n)?;
        if !matches!(
            method,
            LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi | Preconditioner::None
            }
        ) {
            return Err(Error::InvalidParameter {
                arg: "method",
                reason:
                    "split across processes: CG with a Jacobi or no preconditioner, or multigrid",
            });
        }
    }
    check_values("values", values, n)?;
    options.check()?;
    match method {
        LinearMethod::Sor { omega } => check_omega(omega)?,
        LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega },
        } => check_omega(omega)?,
        _ => {}
    }
    let needed = match method {
        LinearMethod::Cg { .. } => cg_scratch_len::<V>(n),
        _ => solve_linear_scratch_len(&method, n),
    };
    check::buffer("scratch", scratch.len(), needed)?;
    if !matches!(method, LinearMethod::Cg { .. }) {
        check_sweep_range(sys, values)?;
    }
    match method {
        LinearMethod::Jacobi => Ok(solve_jacobi(sys, values, options, scratch)),
        LinearMethod::GaussSeidel => Ok(solve_sor(sys, values, options, T::ONE)),
        LinearMethod::Sor { omega } => Ok(solve_sor(sys, values, options, omega)),
        LinearMethod::Cg { preconditioner } => match comm {
            Some(c) => solve_cg(sys, values, options, preconditioner, scratch, c),
            None => solve_cg(
                sys,
                values,
                options,
                preconditioner,
                scratch,
                &Serial::new(n),
            ),
        },
    }
}

/// A stationary method as [`drive_sweeps`] runs it: one sweep of the current iterate, and the
/// residual norm of the current iterate (Jacobi variants alternate two buffers).
pub(crate) trait Sweeps<T: Real> {
    /// One sweep; the residuals it sees, scaled by `sigma`, are summed in the result.
    fn sweep(&mut self, sigma: T) -> Sweep<T>;
    /// `‖b − A x‖` of the current iterate.
    fn residual(&mut self) -> Norm<T>;
}

/// The iteration every stationary solve shares (linear Jacobi/SOR, the sliding block sweeps,
/// the angle springs' direct method): sweep until the one-step-late residual estimate and the
/// largest update meet `options`, confirm with the true residual, and report the final
/// residual. `update_exp` unscales the update for the test (0 when the values are unscaled);
/// the report's `max_update` is the sweep's own.
pub(crate) fn drive_sweeps<T: Real, S: Sweeps<T>>(
    method: &mut S,
    r0: Norm<T>,
    bnorm: Norm<T>,
    update_exp: i32,
    options: &SolveOptions<T>,
) -> SolveReport<T> {
    let est_exp = sweep_exponent(&r0, &bnorm);
    let sigma = T::pow2(-est_exp);
    let mut report = SolveReport {
        iterations: 0,
        residual: r0.relative_to(bnorm),
        max_update: T::ZERO,
        converged: false,
    };
    if report.residual <= options.residual_tol {
        report.converged = true;
        return report;
    }
    let mut checked = false;
    while report.iterations < options.max_iterations {
        let stats = method.sweep(sigma);
        report.iterations += 1;
        report.max_update = stats.max_change;
        // The sweep's residual is that of its input: a cheap, one-step-late estimate.
        let estimate = Norm::from_sum(stats.residual_sq, est_exp).relative_to(bnorm);
        let update = scale_by(stats.max_change, update_exp);
        checked = false;
        if options.met(estimate, update) {
            report.residual = method.residual().relative_to(bnorm);
            checked = true;
            if options.met(report.residual, update) {
                report.converged = true;
                break;
            }
        }
    }
    if !checked {
        report.residual = method.residual().relative_to(bnorm);
    }
    report
}

/// Jacobi on the linear springs: `values` and `other` alternate as input and output.
struct LinearJacobi<'s, 'a, 'v, T: Real, const V: usize> {
    sys: &'s SpringSystem<'a, T>,
    values: &'v mut [[T; V]],
    other: &'v mut [[T; V]],
    in_other: bool,
}

impl<T: Real, const V: usize> Sweeps<T> for LinearJacobi<'_, '_, '_, T, V> {
    fn sweep(&mut self, sigma: T) -> Sweep<T> {
        let n = self.sys.node_count();
        let stats = if self.in_other {
            jacobi_core(self.sys, 0..n, self.other, self.values, sigma)
        } else {
            jacobi_core(self.sys, 0..n, self.values, self.other, sigma)
        };
        self.in_other = !self.in_other;
        stats
    }
    fn residual(&mut self) -> Norm<T> {
        let current: &[[T; V]] = if self.in_other {
            self.other
        } else {
            self.values
        };
        residual_norms(self.sys, current).0
    }
}

/// Gauss–Seidel / SOR on the linear springs, in place.
struct LinearSor<'s, 'a, 'v, T: Real, const V: usize> {
    sys: &'s SpringSystem<'a, T>,
    values: &'v mut [[T; V]],
    omega: T,
}

impl<T: Real, const V: usize> Sweeps<T> for LinearSor<'_, '_, '_, T, V> {
    fn sweep(&mut self, sigma: T) -> Sweep<T> {
        let n = self.sys.node_count();
        sor_core(self.sys, 0..n, self.values, self.omega, sigma)
    }
    fn residual(&mut self) -> Norm<T> {
        residual_norms(self.sys, self.values).0
    }
}

fn solve_jacobi<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
) -> SolveReport<T> {
    let n = sys.node_count();
    let other = scratch.get_mut(..n).unwrap_or(&mut []);
    let (r0, bnorm) = residual_norms(sys, values);
    let mut jacobi = LinearJacobi {
        sys,
        values,
        other,
        in_other: false,
    };
    let report = drive_sweeps(&mut jacobi, r0, bnorm, 0, options);
    if jacobi.in_other {
        for (v, o) in jacobi.values.iter_mut().zip(jacobi.other.iter()) {
            *v = *o;
        }
    }
    report
}

fn solve_sor<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    omega: T,
) -> SolveReport<T> {
    let (r0, bnorm) = residual_norms(sys, values);
    let mut sor = LinearSor { sys, values, omega };
    drive_sweeps(&mut sor, r0, bnorm, 0, options)
}

/// `d_i = Σ_j k_ij` for every node, summed in CSR order (the same sums the sweeps form):
/// computed once per CG solve instead of once per row per iteration.
pub(crate) fn diagonal<T: Real>(sys: &SpringSystem<'_, T>, diag: &mut [T]) {
    for ((_, _, row), d) in sys.rows().zip(diag.iter_mut()) {
        *d = row.fold(T::ZERO, |s, (_, k)| s + k);
    }
}

/// `q = A p` on free nodes (`A` = weighted Laplacian restricted to free nodes; `p` is zero on
/// fixed nodes), with per component the curvature scale `max_i d_i p_i²` (a maximum: exact and
/// order-independent) and `pᵀq` (summed exactly; the fixed nodes' zero terms are skipped).
/// The curvature test compares `pᵀq = Σ d_i p_i² − Σ_j k_ij p_i p_j` with this scale.
fn laplacian_apply<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    owned: &[Range<usize>],
    diag: &[T],
    p: &[[T; V]],
    q: &mut [[T; V]],
    pq: &mut [ExactSum; V],
) -> [T; V] {
    let mut dpp = [T::ZERO; V];
    pq.iter_mut().for_each(|s| *s = ExactSum::new());
    for range in owned {
        let (Some(qs), Some(ps), Some(ds)) = (
            q.get_mut(range.clone()),
            p.get(range.clone()),
            diag.get(range.clone()),
        ) else {
            continue;
        };
        for ((_, fixed, row), ((qi, &pi), &d)) in sys
            .rows_in(range.clone())
            .zip(qs.iter_mut().zip(ps).zip(ds))
        {
            if fixed {
                *qi = [T::ZERO; V];
                continue;
            }
            let mut acc = [T::ZERO; V];
            for (j, k) in row {
                let pj = p.get(j).copied().unwrap_or([T::ZERO; V]);
                for ((a, &x), &y) in acc.iter_mut().zip(&pi).zip(&pj) {
                    *a += k * (x - y);
                }
            }
            for (((s, t), &x), &a) in dpp.iter_mut().zip(pq.iter_mut()).zip(&pi).zip(&acc) {
                *s = s.max(d * x * x);
                t.add(x * a);
            }
            *qi = acc;
        }
    }
    dpp
}

/// `z = M⁻¹ r` for the chosen preconditioner (zero on fixed nodes), `diag` from [`diagonal`].
pub(crate) fn precondition<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    diag: &[T],
    pre: Preconditioner<T>,
    r: &[[T; V]],
    z: &mut [[T; V]],
) {
    match pre {
        Preconditioner::None => {
            for (z, &r) in z.iter_mut().zip(r) {
                *z = r;
            }
        }
        Preconditioner::Jacobi => {
            for (((z, &r), &d), &m) in z.iter_mut().zip(r).zip(diag).zip(sys.fixed()) {
                *z = jacobi_node(r, d, is_fixed(m));
            }
        }
        Preconditioner::Ssor { omega } => ssor(sys, diag, omega, r, z),
    }
}

/// One node of the Jacobi preconditioner: `r / d`, or zero at a fixed node.
#[inline]
fn jacobi_node<T: Real, const V: usize>(r: [T; V], d: T, fixed: bool) -> [T; V] {
    if fixed {
        [T::ZERO; V]
    } else {
        r.map(|r| r / d)
    }
}

/// The SSOR preconditioner, `M = (D + ωL) D⁻¹ (D + ωU) / (ω (2 − ω))`: one forward and one
/// backward sweep. No per-edge fixed-mask test: `z` is zero at fixed nodes (set by the forward
/// sweep before any later row reads it), so their terms add nothing.
fn ssor<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    diag: &[T],
    omega: T,
    r: &[[T; V]],
    z: &mut [[T; V]],
) {
    let scale = omega * (T::TWO - omega);
    // Forward: (D + ωL) y = ω(2 − ω) r, with L_ij = −k_ij for free j < i.
    for (i, ((&ri, &d), &m)) in r.iter().zip(diag).zip(sys.fixed()).enumerate() {
        let new = if is_fixed(m) {
            [T::ZERO; V]
        } else {
            let mut acc = ri.map(|x| scale * x);
            for (j, k) in sys.row(i) {
                if j < i {
                    let zj = z.get(j).copied().unwrap_or([T::ZERO; V]);
                    for (a, &y) in acc.iter_mut().zip(&zj) {
                        *a += omega * k * y;
                    }
                }
            }
            acc.map(|a| a / d)
        };
        if let Some(zi) = z.get_mut(i) {
            *zi = new;
        }
    }
    // Backward: (D + ωU) z = D y, i.e. z_i = y_i + ω Σ_{free j > i} k_ij z_j / d_i.
    for (i, (&d, &m)) in diag.iter().zip(sys.fixed()).enumerate().rev() {
        if is_fixed(m) {
            continue;
        }
        let mut acc = [T::ZERO; V];
        for (j, k) in sys.row(i) {
            if j > i {
                let zj = z.get(j).copied().unwrap_or([T::ZERO; V]);
                for (a, &y) in acc.iter_mut().zip(&zj) {
                    *a += k * y;
                }
            }
        }
        if let Some(zi) = z.get_mut(i) {
            for (zi, &a) in zi.iter_mut().zip(&acc) {
                *zi += omega * a / d;
            }
        }
    }
}

/// Per-component `Σ a·b` over all nodes, summed exactly ([`ExactSum`]: any split of the nodes
/// gives the same bits), accumulated in `s`.
#[inline]
pub(crate) fn dots<T: Real, const V: usize>(
    a: &[[T; V]],
    b: &[[T; V]],
    s: &mut [ExactSum; V],
) -> [T; V] {
    s.iter_mut().for_each(|s| *s = ExactSum::new());
    for (x, y) in a.iter().zip(b) {
        for ((s, &x), &y) in s.iter_mut().zip(x).zip(y) {
            s.add(x * y);
        }
    }
    s.each_ref().map(|s| s.value())
}

/// Per-component power-of-two exponents `e_c` for the scaled CG iterate `x_c · 2^−e_c`:
/// brings `max_i |x_ic|` to about `1/√k_max`, so every product CG forms (`k x²` in `rᵀz`,
/// `pᵀAp`) is near 1 whatever the scale of the values or the stiffness. Powers of two scale
/// exactly: the iterates are the unscaled ones times `2^−e_c`, bit for bit.
pub(crate) fn cg_exponents<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    x: &[[T; V]],
) -> [i32; V] {
    let kmax = sys.stiffness().iter().fold(T::ZERO, |m, &k| m.max(k));
    let ek = if kmax > T::ZERO {
        kmax.exponent() / 2
    } else {
        0
    };
    let mut vmax = [T::ZERO; V];
    for xi in x {
        for (m, &v) in vmax.iter_mut().zip(xi) {
            *m = m.max(v.abs());
        }
    }
    let limit = T::MAX.exponent() - 1;
    vmax.map(|m| {
        let ev = if m > T::ZERO { m.exponent() } else { 0 };
        (ev + ek).clamp(-limit, limit)
    })
}

fn solve_cg<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    pre: Preconditioner<T>,
    scratch: &mut [[T; V]],
    comm: &dyn Collective<T>,
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let too_small = Error::BufferTooSmall {
        arg: "scratch",
        needed: cg_scratch_len::<V>(n),
        actual: scratch.len(),
    };
    let Some((x, rest)) = scratch.split_at_mut_checked(n) else {
        return Err(too_small);
    };
    let Some((r, rest)) = rest.split_at_mut_checked(n) else {
        return Err(too_small);
    };
    let Some((p, rest)) = rest.split_at_mut_checked(n) else {
        return Err(too_small);
    };
    let Some((w, rest)) = rest.split_at_mut_checked(n) else {
        return Err(too_small);
    };
    let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
    diagonal(sys, diag);
    let diag: &[T] = diag;
    let owned = comm.owned();
    // SSOR sweeps the nodes in order: only whole (serial) solves may use it.
    let local = !matches!(pre, Preconditioner::Ssor { .. });
    // CG runs on the scaled field x_c · 2^−e_c (see `cg_exponents`).
    let exps = cg_exponents(sys, values);
    let down = exps.map(|e| T::pow2(-e));
    for (x, v) in x.iter_mut().zip(values.iter()) {
        for ((x, &v), &f) in x.iter_mut().zip(v).zip(&down) {
            *x = v * f;
        }
    }
    // The recurrence residual summed at the largest component's scale.
    let top = exps.iter().copied().max().unwrap_or(0);
    let to_top = exps.map(|e| scale_by(T::ONE, e - top));
    let (r0, bnorm) = residual_norms_scaled(sys, x, &exps, comm);
    let mut report = SolveReport {
        iterations: 0,
        residual: r0.relative_to(bnorm),
        max_update: T::ZERO,
        converged: false,
    };
    if report.residual <= options.residual_tol {
        report.converged = true;
        return Ok(report);
    }
    // (Re)start: r = b − A x, z = M⁻¹ r, p = z on the owned rows (x current everywhere),
    // then p shared; returns rᵀz.
    let restart = |x: &[[T; V]],
                   r: &mut [[T; V]],
                   p: &mut [[T; V]],
                   w: &mut [[T; V]],
                   rz: &mut [ExactSum; V]| {
        rz.iter_mut().for_each(|s| *s = ExactSum::new());
        if local {
            for range in owned {
                for i in range.clone() {
                    let xi = x.get(i).copied().unwrap_or([T::ZERO; V]);
                    let ri = if sys.is_fixed(i) {
                        [T::ZERO; V]
                    } else {
                        node_residual(sys, i, xi, x).0
                    };
                    let d = diag.get(i).copied().unwrap_or(T::ONE);
                    let zi = match pre {
                        Preconditioner::Jacobi => jacobi_node(ri, d, sys.is_fixed(i)),
                        _ => ri,
                    };
                    for ((s, &a), &b) in rz.iter_mut().zip(&ri).zip(&zi) {
                        s.add(a * b);
                    }
                    if let (Some(r), Some(w), Some(p)) = (r.get_mut(i), w.get_mut(i), p.get_mut(i))
                    {
                        (*r, *w, *p) = (ri, zi, zi);
                    }
                }
            }
            share_halo(comm, p);
        } else {
            for (i, ri) in r.iter_mut().enumerate() {
                let xi = x.get(i).copied().unwrap_or([T::ZERO; V]);
                *ri = if sys.is_fixed(i) {
                    [T::ZERO; V]
                } else {
                    node_residual(sys, i, xi, x).0
                };
            }
            precondition(sys, diag, pre, r, w);
            for (p, &z) in p.iter_mut().zip(w.iter()) {
                *p = z;
            }
            for (ri, zi) in r.iter().zip(w.iter()) {
                for ((s, &a), &b) in rz.iter_mut().zip(ri).zip(zi) {
                    s.add(a * b);
                }
            }
        }
        merged(comm, rz)
    };
    if !local && owned.len() != 1 {
        return Err(Error::InvalidParameter {
            arg: "solver",
            reason: "SSOR sweeps the nodes in order: not with nodes split across processes",
        });
    }
    // One set of per-component accumulators for every per-component sum of an iteration
    // (each is rounded before the next begins): 584 bytes a component matter on a small stack.
    let mut sums = [ExactSum::new(); V];
    let mut rz = restart(x, r, p, w, &mut sums);
    let mut checked = true;
    let tiny = T::EPSILON;
    while report.iterations < options.max_iterations {
        report.iterations += 1;
        let dpp = laplacian_apply(sys, owned, diag, p, w, &mut sums);
        let dpp = merged_max(comm, dpp);
        let pq = merged(comm, &mut sums);
        let mut alpha = [T::ZERO; V];
        for (((a, &pq), &dpp), &rz) in alpha.iter_mut().zip(&pq).zip(&dpp).zip(&rz) {
            if !(pq.is_finite() && rz.is_finite() && dpp.is_finite()) {
                return Err(Error::Overflow { arg: "values" });
            }
            if dpp == T::ZERO || rz == T::ZERO {
                continue; // this component has converged exactly
            }
            if pq <= tiny * dpp {
                return Err(Error::SingularSystem {
                    iteration: report.iterations,
                });
            }
            *a = rz / pq;
        }
        // One pass over the owned rows: x += α p, r −= α q, the recurrence residual, and
        // (Jacobi or none) the preconditioned residual z (into w, over q) with rᵀz.
        let mut max_update = [T::ZERO; V];
        let mut rr = ExactSum::new();
        let rz_exact = &mut sums;
        rz_exact.iter_mut().for_each(|s| *s = ExactSum::new());
        for range in owned {
            let rows = range.clone();
            let (Some(x), Some(r), Some(p), Some(w), Some(d), Some(m)) = (
                x.get_mut(rows.clone()),
                r.get_mut(rows.clone()),
                p.get(rows.clone()),
                w.get_mut(rows.clone()),
                diag.get(rows.clone()),
                sys.fixed().get(rows),
            ) else {
                continue;
            };
            for ((((x, r), &p), w), (&d, &m)) in x
                .iter_mut()
                .zip(r.iter_mut())
                .zip(p.iter())
                .zip(w.iter_mut())
                .zip(d.iter().zip(m))
            {
                for ((((((x, r), &p), &q), &a), m), &g) in x
                    .iter_mut()
                    .zip(r.iter_mut())
                    .zip(&p)
                    .zip(w.iter())
                    .zip(&alpha)
                    .zip(max_update.iter_mut())
                    .zip(&to_top)
                {
                    let dx = a * p;
                    *x += dx;
                    *r -= a * q;
                    *m = m.max(dx.abs());
                    let rg = *r * g;
                    rr.add(rg * rg);
                }
                if local {
                    *w = match pre {
                        Preconditioner::Jacobi => jacobi_node(*r, d, is_fixed(m)),
                        _ => *r,
                    };
                    for ((s, &r), &z) in rz_exact.iter_mut().zip(r.iter()).zip(w.iter()) {
                        s.add(r * z);
                    }
                }
            }
        }
        let max_update = merged_max(comm, max_update);
        report.max_update = max_update
            .iter()
            .zip(&exps)
            .fold(T::ZERO, |m, (&u, &e)| m.max(scale_by(u, e)));
        // rr and rᵀz in one exchange.
        let (rr, mut rz_new) = merged_with(comm, &mut rr, rz_exact);
        checked = false;
        // An overflowing recurrence sum cannot say "converged": ask the true residual.
        let estimate_ok = rr.is_finite();
        let estimate = Norm::from_sum(rr, top).relative_to(bnorm);
        if !estimate_ok || options.met(estimate, report.max_update) {
            share_halo(comm, x);
            let (rt, _) = residual_norms_scaled(sys, x, &exps, comm);
            report.residual = rt.relative_to(bnorm);
            checked = true;
            if options.met(report.residual, report.max_update) {
                report.converged = true;
                break;
            }
            if estimate_ok {
                // Recurrence and true residual disagree: restart from the true residual.
                rz = restart(x, r, p, w, &mut sums);
                continue;
            }
        }
        if !local {
            precondition(sys, diag, pre, r, w);
            rz_new = dots(r, w, &mut sums);
        }
        let mut beta = [T::ZERO; V];
        for ((b, &new), &old) in beta.iter_mut().zip(&rz_new).zip(&rz) {
            if old != T::ZERO {
                *b = new / old;
            }
        }
        for range in owned {
            let (Some(p), Some(w)) = (p.get_mut(range.clone()), w.get(range.clone())) else {
                continue;
            };
            for (p, &z) in p.iter_mut().zip(w.iter()) {
                for ((p, &z), &b) in p.iter_mut().zip(&z).zip(&beta) {
                    *p = z + b * *p;
                }
            }
        }
        share_halo(comm, p);
        rz = rz_new;
    }
    share_field(comm, x);
    if !checked {
        let (rt, _) = residual_norms_scaled(sys, x, &exps, comm);
        report.residual = rt.relative_to(bnorm);
    }
    // Free nodes only: CG adds `α·p` with `p = 0` at fixed nodes, which would turn a fixed
    // −0.0 into +0.0 (and scaling could round a fixed subnormal); fixed values must come back
    // bit for bit.
    let up = exps.map(|e| T::pow2(e));
    for (i, (v, x)) in values.iter_mut().zip(x.iter()).enumerate() {
        if !sys.is_fixed(i) {
            for ((v, &x), &f) in v.iter_mut().zip(x).zip(&up) {
                *v = x * f;
            }
        }
    }
    Ok(report)
}
