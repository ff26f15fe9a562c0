//! Linear (Batina) springs: Jacobi and SOR sweeps, and the whole solves (Jacobi, Gauss–Seidel,
//! SOR, preconditioned CG) built on them.

use core::ops::Range;

use super::distributed::{check_owned, Collective, Serial};
use super::krylov::{
    apply_local, cg_len, exponents, solve_scaled, Operator, Precondition, Vectors,
};
use super::norms::{scale_by, scaled_pair_norms, sweep_exponent, Norm, Pairs};
use super::system::{
    check_omega, check_values, is_fixed, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem, Sweep,
};
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::{ExactSum, Gather};
use crate::real::Real;

/// Node `i`'s residual `r_i = Σ_j k_ij (x_j − x_i)` (= `b − A x` at a free node, Yang & Özgen
/// eq. 1 with the sign flipped) and diagonal `d_i = Σ_j k_ij`, summed in CSR order.
#[inline]
pub(crate) fn node_residual<T: Real, const V: usize>(
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

/// One Jacobi-order sweep of a node-wise method over `nodes`: `step(i, x_i, input)` gives a
/// free node's correction `δ` and residual `r`, `output[i] = x_i + δ`; fixed nodes are
/// copied, `output` outside the range is not touched. The linear springs' and the angle
/// springs' direct method share it.
pub(crate) fn jacobi_order<T: Real, const V: usize, F>(
    fixed: impl Fn(usize) -> bool,
    nodes: Range<usize>,
    input: &[[T; V]],
    output: &mut [[T; V]],
    sigma: T,
    mut step: F,
) -> Sweep<T>
where
    F: FnMut(usize, [T; V], &[[T; V]]) -> ([T; V], [T; V]),
{
    let mut max_change = T::ZERO;
    let mut residual_sq = ExactSum::new();
    for i in nodes {
        let Some(&xi) = input.get(i) else { continue };
        let new = if fixed(i) {
            xi
        } else {
            let (dx, r) = step(i, xi, input);
            tally(&mut max_change, &mut residual_sq, &dx, &r, sigma);
            crate::vector::add(xi, dx)
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

/// One in-place Gauss–Seidel-order sweep of a node-wise method over `nodes`, in increasing
/// node order: `step(i, x_i, values)` gives a free node's (over-relaxed) correction `δ` and
/// residual `r` from the newest values, `values[i] = x_i + δ`; fixed nodes are skipped.
pub(crate) fn gauss_seidel_order<T: Real, const V: usize, F>(
    fixed: impl Fn(usize) -> bool,
    nodes: Range<usize>,
    values: &mut [[T; V]],
    sigma: T,
    mut step: F,
) -> Sweep<T>
where
    F: FnMut(usize, [T; V], &[[T; V]]) -> ([T; V], [T; V]),
{
    let mut max_change = T::ZERO;
    let mut residual_sq = ExactSum::new();
    for i in nodes {
        if fixed(i) {
            continue;
        }
        let Some(&xi) = values.get(i) else { continue };
        let (dx, r) = step(i, xi, values);
        tally(&mut max_change, &mut residual_sq, &dx, &r, sigma);
        if let Some(o) = values.get_mut(i) {
            *o = crate::vector::add(xi, dx);
        }
    }
    Sweep {
        max_change,
        residual_sq: residual_sq.value(),
        residual_sum: residual_sq,
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
    let fixed = |i| sys.is_fixed(i);
    jacobi_order(fixed, nodes, input, output, sigma, |i, xi, x| {
        let (r, d) = node_residual(sys, i, xi, x);
        (r.map(|r| r / d), r)
    })
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
    let fixed = |i| sys.is_fixed(i);
    gauss_seidel_order(fixed, nodes, values, sigma, |i, xi, x| {
        let (r, d) = node_residual(sys, i, xi, x);
        (r.map(|r| omega * (r / d)), r)
    })
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

/// The linear springs' residual pairs ([`Pairs`]) of a field over some rows.
struct LinearPairs<'s, 'a, 'x, T: Real, const V: usize> {
    sys: &'s SpringSystem<'a, T>,
    rows: &'s [Range<usize>],
    x: &'x [[T; V]],
}

impl<T: Real, const V: usize> Pairs<T, V> for LinearPairs<'_, '_, '_, T, V> {
    #[inline]
    fn each<F: FnMut(&[T; V], &[T; V])>(&self, f: F) {
        for_each_free_residual(self.sys, self.rows, self.x, f);
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
pub(crate) fn residual_norms_scaled<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    sys: &SpringSystem<'_, T>,
    x: &[[T; V]],
    exps: &[i32; V],
    comm: &C,
) -> (Norm<T>, Norm<T>) {
    let pairs = LinearPairs {
        sys,
        rows: comm.owned(),
        x,
    };
    scaled_pair_norms(&pairs, exps, false, comm)
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
        LinearMethod::Cg { .. } => match cg_len(node_count) {
            Some(cg) => cg.saturating_add(node_count),
            None => usize::MAX,
        },
    }
}

/// The exact CG scratch need for `V` components: the CG vectors and the diagonal packed `V`
/// scalars to an item, `4 n + ⌈n / V⌉` items.
fn cg_scratch_len<const V: usize>(n: usize) -> usize {
    cg_len(n).map_or(usize::MAX, |cg| cg.saturating_add(n.div_ceil(V.max(1))))
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
        if matches!(method, LinearMethod::Cg { .. }) {
            let packed = super::zero_components::Packed::Cg(method);
            let solved =
                super::zero_components::solve_nonzero(self, values, packed, options, scratch);
            if let Some(report) = solved {
                return report;
            }
        }
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
                &Serial::new(n) as &dyn Collective<T>,
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
    let mut report = SolveReport::start(r0, bnorm, options);
    if report.converged {
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

/// The linear springs' operator for [`pcg`](super::krylov::pcg): the weighted graph
/// Laplacian on the free nodes, one lane per component. With `STORED` the diagonal comes
/// from `diag` (computed once per solve by [`diagonal`]), else each row sums its own (no
/// scratch for it: the multigrid CG).
pub(crate) struct Laplacian<'s, 'a, T: Real, const STORED: bool> {
    pub(crate) sys: &'s SpringSystem<'a, T>,
    pub(crate) diag: &'s [T],
}

impl<T: Real, const V: usize, const STORED: bool> Operator<T, V, V>
    for Laplacian<'_, '_, T, STORED>
{
    #[inline]
    fn residual(&self, i: usize, x: &[[T; V]]) -> [T; V] {
        if self.sys.is_fixed(i) {
            return [T::ZERO; V];
        }
        let xi = x.get(i).copied().unwrap_or([T::ZERO; V]);
        node_residual(self.sys, i, xi, x).0
    }

    /// `q = A p` with the curvature scale `max_i d_i p_i²` per component (`pᵀq = Σ d_i p_i² −
    /// Σ_j k_ij p_i p_j` is compared with it); the fixed nodes' zero terms are skipped.
    #[inline]
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; V]],
        q: &mut [[T; V]],
        pq: &mut [ExactSum; V],
        dpp: &mut [T; V],
    ) {
        if STORED {
            let ds = self.diag.get(rows.clone()).unwrap_or(&[]);
            laplacian_rows::<T, V, true>(self.sys, rows, ds, p, q, pq, dpp);
        } else {
            laplacian_rows::<T, V, false>(self.sys, rows, &[], p, q, pq, dpp);
        }
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; V]],
        exps: &[i32; V],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        residual_norms_scaled(self.sys, x, exps, comm)
    }
}

/// [`Laplacian::apply`] over `rows`, with the diagonal from `diag` (one per row) when
/// `STORED`, else summed from each row (`diag` ignored). The two iterations differ only in
/// the zip (a slice zip keeps the loop free of per-row checks).
#[inline]
fn laplacian_rows<T: Real, const V: usize, const STORED: bool>(
    sys: &SpringSystem<'_, T>,
    rows: Range<usize>,
    diag: &[T],
    p: &[[T; V]],
    q: &mut [[T; V]],
    pq: &mut [ExactSum; V],
    dpp: &mut [T; V],
) {
    let (Some(qs), Some(ps)) = (q.get_mut(rows.clone()), p.get(rows.clone())) else {
        return;
    };
    let rows = sys.rows_in(rows);
    let mut pq = Gather::lanes(pq);
    if STORED {
        for ((_, fixed, row), ((qi, &pi), &d)) in rows.zip(qs.iter_mut().zip(ps).zip(diag)) {
            *qi = laplacian_row::<T, V, true>(fixed, row, pi, d, p, &mut pq, dpp);
        }
    } else {
        for ((_, fixed, row), (qi, &pi)) in rows.zip(qs.iter_mut().zip(ps)) {
            *qi = laplacian_row::<T, V, false>(fixed, row, pi, T::ZERO, p, &mut pq, dpp);
        }
    }
}

/// One row of [`laplacian_rows`]: `(A p)_i` (zero at a fixed node), adding `p_i (A p)_i` to
/// `pq` and raising `dpp` by `d_i p_i²` (`d_i` given when `STORED`, else summed here).
#[inline(always)]
fn laplacian_row<T: Real, const V: usize, const STORED: bool>(
    fixed: bool,
    row: impl Iterator<Item = (usize, T)>,
    pi: [T; V],
    d: T,
    p: &[[T; V]],
    pq: &mut Gather<'_, V>,
    dpp: &mut [T; V],
) -> [T; V] {
    if fixed {
        return [T::ZERO; V];
    }
    let mut acc = [T::ZERO; V];
    let mut sum = T::ZERO;
    for (j, k) in row {
        let pj = p.get(j).copied().unwrap_or([T::ZERO; V]);
        for ((a, &x), &y) in acc.iter_mut().zip(&pi).zip(&pj) {
            *a += k * (x - y);
        }
        if !STORED {
            sum += k;
        }
    }
    let d = if STORED { d } else { sum };
    let mut terms = [T::ZERO; V];
    for (((s, t), &x), &a) in dpp.iter_mut().zip(&mut terms).zip(&pi).zip(&acc) {
        *s = s.max(d * x * x);
        *t = x * a;
    }
    pq.push(terms);
    acc
}

/// The linear springs' one-level preconditioners ([`Preconditioner`]: none, Jacobi `z_i =
/// r_i / d_i`, SSOR), chosen at run time so that one CG serves all three; zero at fixed
/// nodes. None and Jacobi are node-local (fused into the update pass), SSOR sweeps every node
/// in order (serial only).
pub(crate) struct OneLevel<'s, 'a, T: Real> {
    pub(crate) sys: &'s SpringSystem<'a, T>,
    pub(crate) diag: &'s [T],
    pub(crate) pre: Preconditioner<T>,
}

impl<T: Real, const V: usize> Precondition<T, V> for OneLevel<'_, '_, T> {
    fn local(&self) -> bool {
        !matches!(self.pre, Preconditioner::Ssor { .. })
    }
    #[inline]
    fn node(&self, i: usize, r: [T; V]) -> [T; V] {
        match self.pre {
            Preconditioner::Jacobi => match (self.diag.get(i), self.sys.fixed().get(i)) {
                (Some(&d), Some(&m)) => jacobi_node(r, d, is_fixed(m)),
                _ => [T::ZERO; V],
            },
            _ => r,
        }
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; V]], z: &mut [[T; V]], comm: &C) {
        match self.pre {
            Preconditioner::Ssor { omega } => ssor(self.sys, self.diag, omega, r, z),
            _ => apply_local(self, r, z, comm),
        }
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

/// The SSOR preconditioner `M = (D + ωL) D⁻¹ (D + ωU) / (ω (2 − ω))`, `z = M⁻¹ r`.
/// The two SSOR sweeps. No per-edge fixed-mask test: `z` is zero at fixed nodes (set by the
/// forward sweep before any later row reads it), so their terms add nothing.
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

/// CG on the linear springs ([`pcg`](super::krylov::pcg)) with a one-level preconditioner:
/// the four CG vectors and the diagonal (`n` scalars packed `V` to an item) in `scratch`.
fn solve_cg<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    sys: &SpringSystem<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    pre: Preconditioner<T>,
    scratch: &mut [[T; V]],
    comm: &C,
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let needed = cg_scratch_len::<V>(n);
    let actual = scratch.len();
    let Some((v, rest)) = Vectors::split(scratch, n) else {
        return Err(Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual,
        });
    };
    let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
    diagonal(sys, diag);
    let diag: &[T] = diag;
    let op = Laplacian::<T, true> { sys, diag };
    let exps = exponents(sys.stiffness(), values, false);
    let fixed = |i| sys.is_fixed(i);
    let mut pre = OneLevel { sys, diag, pre };
    solve_scaled(&op, &mut pre, v, values, exps, fixed, options, comm)
}
