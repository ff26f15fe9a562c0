//! Conjugate gradients preconditioned by the multigrid V-cycle.

use super::cycle::vcycle;
use super::AmgHierarchy;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::reduce::ExactSum;
use crate::spring::distributed::{
    check_owned, merged, merged_max, merged_one, share_field, share_halo, Collective, Serial,
};
use crate::spring::linear::{cg_exponents, residual_norms_scaled};
use crate::spring::norms::{scale_by, Norm};
use crate::spring::system::{check_values, SolveOptions, SolveReport, SpringSystem};

/// Number of `[T; V]` scratch items [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) needs: `5 N` for the CG vectors
/// (iterate, residual, direction, `A p`, preconditioned residual) plus three vectors per coarse
/// level (`3 ×` [`AmgHierarchy::coarse_unknowns`]).
pub fn solve_linear_amg_scratch_len<T: Real>(hierarchy: &AmgHierarchy<'_, T>) -> usize {
    hierarchy
        .layout
        .nodes
        .saturating_mul(5)
        .saturating_add(hierarchy.coarse_unknowns().saturating_mul(3))
}

/// Number of `[T; V]` scratch items [`amg_precondition`](crate::spring::SpringSystem::amg_precondition) needs: one fine vector plus three
/// per coarse unknown.
pub fn amg_precondition_scratch_len<T: Real>(hierarchy: &AmgHierarchy<'_, T>) -> usize {
    hierarchy
        .layout
        .nodes
        .saturating_add(hierarchy.coarse_unknowns().saturating_mul(3))
}

impl<T: Real> SpringSystem<'_, T> {
    /// Applies the preconditioner once, `z = M⁻¹ r`: one V-cycle from zero (symmetric positive
    /// definite on the free nodes). Entries of `r` at fixed nodes are ignored and `z` is zero there.
    /// For callers with their own Krylov solver (e.g. a distributed CG).
    ///
    /// # Errors
    /// Nothing is written on error: a hierarchy for a system of another size, wrong lengths,
    /// non-finite `r`, `scratch` shorter than [`amg_precondition_scratch_len`].
    pub fn amg_precondition<const V: usize>(
        &self,
        hierarchy: &AmgHierarchy<'_, T>,
        r: &[[T; V]],
        z: &mut [[T; V]],
        scratch: &mut [[T; V]],
    ) -> Result<()> {
        let n = self.node_count();
        hierarchy.check_system(self)?;
        check_values("r", r, n)?;
        check::len("z", z.len(), n)?;
        let needed = amg_precondition_scratch_len(hierarchy);
        let Some((t, coarse)) = scratch
            .get_mut(..needed)
            .and_then(|s| s.split_at_mut_checked(n))
        else {
            return Err(Error::BufferTooSmall {
                arg: "scratch",
                needed,
                actual: scratch.len(),
            });
        };
        amg_vcycle(self, hierarchy, r, z, t, coarse);
        Ok(())
    }
}

/// `z = M⁻¹ r` without checks: one serial V-cycle from zero, then `z` zeroed at fixed nodes.
/// `t` is one fine vector, `coarse` three per coarse unknown (the callers check the sizes;
/// short slices cannot panic, every access is checked). Applied to each of the `V`
/// components alike: [`amg_precondition`](crate::spring::SpringSystem::amg_precondition) and the angle-inclusion CG
/// ([`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg), `V = D`).
pub(crate) fn amg_vcycle<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    hierarchy: &AmgHierarchy<'_, T>,
    r: &[[T; V]],
    z: &mut [[T; V]],
    t: &mut [[T; V]],
    coarse: &mut [[T; V]],
) {
    vcycle(
        sys,
        hierarchy,
        r,
        z,
        t,
        coarse,
        &Serial::new(sys.node_count()),
    );
    zero_fixed(sys, z);
}

/// `r = b − A x` at free nodes (`Σ_j k_ij (x_j − x_i)`, fixed values as Dirichlet data), zero at
/// fixed nodes.
fn fine_residual<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    owned: &[core::ops::Range<usize>],
    x: &[[T; V]],
    r: &mut [[T; V]],
) {
    for range in owned {
        let (Some(rs), Some(xs)) = (r.get_mut(range.clone()), x.get(range.clone())) else {
            continue;
        };
        for ((_, fixed, row), (ri, &xi)) in sys.rows_in(range.clone()).zip(rs.iter_mut().zip(xs)) {
            let mut acc = [T::ZERO; V];
            if !fixed {
                for (j, k) in row {
                    let xj = x.get(j).copied().unwrap_or(xi);
                    for ((a, &b), &c) in acc.iter_mut().zip(&xj).zip(&xi) {
                        *a += k * (b - c);
                    }
                }
            }
            *ri = acc;
        }
    }
}

/// Per-component exact `Σ a·b` over the owned rows into `s` (merged by the caller).
fn dots_in<'s, T: Real, const V: usize>(
    owned: &[core::ops::Range<usize>],
    a: &[[T; V]],
    b: &[[T; V]],
    s: &'s mut [ExactSum; V],
) -> &'s mut [ExactSum; V] {
    s.iter_mut().for_each(|s| *s = ExactSum::new());
    for range in owned {
        let (Some(a), Some(b)) = (a.get(range.clone()), b.get(range.clone())) else {
            continue;
        };
        for (x, y) in a.iter().zip(b) {
            for ((s, &x), &y) in s.iter_mut().zip(x).zip(y) {
                s.add(x * y);
            }
        }
    }
    s
}

/// Zeroes `z` at fixed nodes (the V-cycle already does unless the hierarchy was built for
/// another fixed mask; the search direction must never move a fixed node).
fn zero_fixed<T: Real, const V: usize>(sys: &SpringSystem<'_, T>, z: &mut [[T; V]]) {
    for (z, &m) in z.iter_mut().zip(sys.fixed()) {
        if crate::spring::is_fixed(m) {
            *z = [T::ZERO; V];
        }
    }
}

/// `q = A p` at free nodes (`p` is zero at fixed nodes), and per component the curvature
/// scale `max_i d_i p_i²` (exact and order-independent) and `pᵀq` (summed exactly into `pq`).
fn apply<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    owned: &[core::ops::Range<usize>],
    p: &[[T; V]],
    q: &mut [[T; V]],
    pq: &mut [ExactSum; V],
) -> [T; V] {
    let mut dpp = [T::ZERO; V];
    pq.iter_mut().for_each(|s| *s = ExactSum::new());
    for range in owned {
        let (Some(qs), Some(ps)) = (q.get_mut(range.clone()), p.get(range.clone())) else {
            continue;
        };
        for ((_, fixed, row), (qi, &pi)) in sys.rows_in(range.clone()).zip(qs.iter_mut().zip(ps)) {
            if fixed {
                *qi = [T::ZERO; V];
                continue;
            }
            let mut acc = [T::ZERO; V];
            let mut d = T::ZERO;
            for (j, k) in row {
                let pj = p.get(j).copied().unwrap_or([T::ZERO; V]);
                for ((a, &x), &y) in acc.iter_mut().zip(&pi).zip(&pj) {
                    *a += k * (x - y);
                }
                d += k;
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

impl<T: Real> SpringSystem<'_, T> {
    /// Solves the linear springs (the problem of [`solve_linear`](crate::spring::SpringSystem::solve_linear)) by
    /// conjugate gradients preconditioned with one multigrid V-cycle per iteration, one `α`, `β`
    /// per value component. `values` holds the Dirichlet data at fixed nodes and the initial guess
    /// at free nodes; on `Ok` it holds the last iterate (fixed values untouched, bit for bit) and
    /// the report says whether it converged. The operator and every residual come from `sys`
    /// itself; the hierarchy only preconditions, so a hierarchy built for other stiffness values of
    /// the same graph slows convergence down but cannot change the answer.
    ///
    /// # Errors
    /// `values` is untouched on error: a hierarchy built for a system of another size
    /// ([`Error::LengthMismatch`], `"hierarchy"`), wrong length or non-finite `values`, bad
    /// options, `scratch` shorter than [`solve_linear_amg_scratch_len`], and
    /// [`Error::SingularSystem`] if CG meets non-positive curvature, [`Error::Overflow`] if its
    /// inner products overflow even after the power-of-two rescaling the plain CG uses.
    pub fn solve_linear_amg<const V: usize>(
        &self,
        hierarchy: &AmgHierarchy<'_, T>,
        values: &mut [[T; V]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; V]],
    ) -> Result<SolveReport<T>> {
        solve_amg_on(
            self,
            hierarchy,
            values,
            options,
            scratch,
            &Serial::new(self.node_count()),
        )
    }
}

/// [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) with the rows split over the processes of `comm` (the V-cycle runs
/// whole on every process, on the shared residual; everything else on the owned rows).
pub(crate) fn solve_amg_on<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    hierarchy: &AmgHierarchy<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
    comm: &dyn Collective<T>,
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let owned = comm.owned();
    hierarchy.check_system(sys)?;
    check_owned(comm, n)?;
    check_values("values", values, n)?;
    options.check()?;
    let needed = solve_linear_amg_scratch_len(hierarchy);
    check::buffer("scratch", scratch.len(), needed)?;
    let too_small = Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual: scratch.len(),
    };
    let (x, rest) = scratch.split_at_mut_checked(n).ok_or(too_small)?;
    let (r, rest) = rest.split_at_mut_checked(n).ok_or(too_small)?;
    let (p, rest) = rest.split_at_mut_checked(n).ok_or(too_small)?;
    let (q, rest) = rest.split_at_mut_checked(n).ok_or(too_small)?;
    let (z, coarse) = rest.split_at_mut_checked(n).ok_or(too_small)?;
    // CG runs on the scaled field x_c · 2^−e_c, as the plain CG does (the preconditioner is
    // linear, so it commutes with the scaling).
    let exps = cg_exponents(sys, values);
    let down = exps.map(|e| T::pow2(-e));
    for (x, v) in x.iter_mut().zip(values.iter()) {
        for ((x, &v), &f) in x.iter_mut().zip(v).zip(&down) {
            *x = v * f;
        }
    }
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
    // (Re)start: r = b − A x, z = M⁻¹ r, p = z; returns r·z per component.
    let restart = |x: &[[T; V]],
                   r: &mut [[T; V]],
                   p: &mut [[T; V]],
                   q: &mut [[T; V]],
                   z: &mut [[T; V]],
                   coarse: &mut [[T; V]],
                   sums: &mut [ExactSum; V]| {
        fine_residual(sys, owned, x, r);
        vcycle(sys, hierarchy, r, z, q, coarse, comm);
        zero_fixed(sys, z);
        for (p, &z) in p.iter_mut().zip(z.iter()) {
            *p = z;
        }
        share_halo(comm, p);
        merged(comm, dots_in(owned, r, z, sums))
    };
    // One set of per-component accumulators for every sum of an iteration (each is rounded
    // before the next begins): 584 bytes a component matter on a small stack.
    let mut sums = [ExactSum::new(); V];
    let mut rz = restart(x, r, p, q, z, coarse, &mut sums);
    let mut checked = true;
    let tiny = T::EPSILON;
    while report.iterations < options.max_iterations {
        report.iterations += 1;
        let dpp = apply(sys, owned, p, q, &mut sums);
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
        let mut max_update = [T::ZERO; V];
        let mut rr = ExactSum::new();
        for range in owned {
            let (Some(x), Some(r), Some(p), Some(q)) = (
                x.get_mut(range.clone()),
                r.get_mut(range.clone()),
                p.get(range.clone()),
                q.get(range.clone()),
            ) else {
                continue;
            };
            for (((x, r), &p), &q) in x.iter_mut().zip(r.iter_mut()).zip(p.iter()).zip(q.iter()) {
                for ((((((x, r), &p), &q), &a), m), &g) in x
                    .iter_mut()
                    .zip(r.iter_mut())
                    .zip(&p)
                    .zip(&q)
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
            }
        }
        let max_update = merged_max(comm, max_update);
        report.max_update = max_update
            .iter()
            .zip(&exps)
            .fold(T::ZERO, |m, (&u, &e)| m.max(scale_by(u, e)));
        let rr = merged_one(comm, &mut rr);
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
                rz = restart(x, r, p, q, z, coarse, &mut sums);
                continue;
            }
        }
        vcycle(sys, hierarchy, r, z, q, coarse, comm);
        zero_fixed(sys, z);
        let rz_new = merged(comm, dots_in(owned, r, z, &mut sums));
        let mut beta = [T::ZERO; V];
        for ((b, &new), &old) in beta.iter_mut().zip(&rz_new).zip(&rz) {
            if old != T::ZERO {
                *b = new / old;
            }
        }
        for range in owned {
            let (Some(p), Some(z)) = (p.get_mut(range.clone()), z.get(range.clone())) else {
                continue;
            };
            for (p, &z) in p.iter_mut().zip(z.iter()) {
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
    // Free nodes only: fixed values come back bit for bit.
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
