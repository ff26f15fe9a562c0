//! Conjugate gradients preconditioned by the multigrid V-cycle.

use super::cycle::vcycle;
use super::AmgHierarchy;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::distributed::{check_owned, Collective, Serial};
use crate::spring::krylov::{cg_len, exponents, solve_scaled, Precondition, Vectors};
use crate::spring::linear::Laplacian;
use crate::spring::system::{check_values, SolveOptions, SolveReport, SpringSystem};

/// `[T; V]` scratch items of a multigrid-preconditioned CG over `node_count` nodes whose
/// hierarchy has `coarse_unknowns` ([`AmgSizes::coarse_unknowns`](super::AmgSizes)), or
/// `None` when the count overflows: the four CG vectors, the V-cycle's fine vector and three
/// vectors per coarse unknown (`5 N + 3 coarse`). The one formula of every multigrid scratch
/// length ([`solve_linear_amg_scratch_len`], [`angle_amg_scratch_len`](crate::spring::AngleSystem::angle_amg_scratch_len),
/// the prepared plans, the C ABI).
pub const fn amg_cg_scratch_len(node_count: usize, coarse_unknowns: usize) -> Option<usize> {
    match (
        cg_len(node_count),
        vcycle_scratch_len(node_count, coarse_unknowns),
    ) {
        (Some(cg), Some(v)) => cg.checked_add(v),
        _ => None,
    }
}

/// `[T; V]` scratch items of a sliding multigrid-preconditioned CG
/// ([`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) with a
/// hierarchy, [`solve_angle_sliding_amg`](crate::spring::AngleSystem::solve_angle_sliding_amg)),
/// or `None` on overflow: [`amg_cg_scratch_len`] and `N` more (`6 N + 3 coarse`).
pub const fn amg_sliding_cg_scratch_len(
    node_count: usize,
    coarse_unknowns: usize,
) -> Option<usize> {
    match amg_cg_scratch_len(node_count, coarse_unknowns) {
        Some(s) => s.checked_add(node_count),
        None => None,
    }
}

/// One V-cycle's scratch: one fine vector and three per coarse unknown, `None` on overflow.
const fn vcycle_scratch_len(node_count: usize, coarse_unknowns: usize) -> Option<usize> {
    match coarse_unknowns.checked_mul(3) {
        Some(c) => node_count.checked_add(c),
        None => None,
    }
}

/// Number of `[T; V]` scratch items [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) needs: `5 N` for the CG vectors
/// (iterate, residual, direction, `A p`, preconditioned residual) plus three vectors per coarse
/// level (`3 ×` [`AmgHierarchy::coarse_unknowns`]).
pub fn solve_linear_amg_scratch_len<T: Real>(hierarchy: &AmgHierarchy<'_, T>) -> usize {
    amg_cg_scratch_len(hierarchy.layout.nodes, hierarchy.coarse_unknowns()).unwrap_or(usize::MAX)
}

/// Number of `[T; V]` scratch items [`amg_precondition`](crate::spring::SpringSystem::amg_precondition) needs: one fine vector plus three
/// per coarse unknown.
pub fn amg_precondition_scratch_len<T: Real>(hierarchy: &AmgHierarchy<'_, T>) -> usize {
    vcycle_scratch_len(hierarchy.layout.nodes, hierarchy.coarse_unknowns()).unwrap_or(usize::MAX)
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
/// components alike.
pub(crate) fn amg_vcycle<T: Real, const V: usize>(
    sys: &SpringSystem<'_, T>,
    hierarchy: &AmgHierarchy<'_, T>,
    r: &[[T; V]],
    z: &mut [[T; V]],
    t: &mut [[T; V]],
    coarse: &mut [[T; V]],
) {
    let mut pre = Vcycle {
        sys,
        hierarchy,
        t,
        coarse,
    };
    pre.apply(r, z, &Serial::new(sys.node_count()));
}

/// The multigrid V-cycle as a CG preconditioner (one cycle from zero, `z` zeroed at fixed
/// nodes): [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg), the angle and
/// sliding multigrid solves. `t` is one fine vector, `coarse` three per coarse unknown.
pub(crate) struct Vcycle<'s, 'a, 'h, T: Real, const V: usize> {
    pub(crate) sys: &'s SpringSystem<'a, T>,
    pub(crate) hierarchy: &'s AmgHierarchy<'h, T>,
    pub(crate) t: &'s mut [[T; V]],
    pub(crate) coarse: &'s mut [[T; V]],
}

impl<'s, 'a, 'h, T: Real, const V: usize> Vcycle<'s, 'a, 'h, T, V> {
    /// The V-cycle's vectors from `scratch` (one fine vector, then the rest for the coarse
    /// levels).
    pub(crate) fn new(
        sys: &'s SpringSystem<'a, T>,
        hierarchy: &'s AmgHierarchy<'h, T>,
        scratch: &'s mut [[T; V]],
    ) -> Self {
        let n = sys.node_count();
        let (t, coarse) = scratch
            .split_at_mut_checked(n)
            .unwrap_or((&mut [], &mut []));
        Vcycle {
            sys,
            hierarchy,
            t,
            coarse,
        }
    }
}

impl<T: Real, const V: usize> Precondition<T, V> for Vcycle<'_, '_, '_, T, V> {
    fn local(&self) -> bool {
        false
    }
    fn node(&self, _: usize, r: [T; V]) -> [T; V] {
        r
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; V]], z: &mut [[T; V]], comm: &C) {
        vcycle(self.sys, self.hierarchy, r, z, self.t, self.coarse, comm);
        // The V-cycle already does unless the hierarchy was built for another fixed mask;
        // the search direction must never move a fixed node.
        for (z, &m) in z.iter_mut().zip(self.sys.fixed()) {
            if crate::spring::is_fixed(m) {
                *z = [T::ZERO; V];
            }
        }
    }
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
        let packed = crate::spring::zero_components::Packed::Amg(hierarchy);
        let solved =
            crate::spring::zero_components::solve_nonzero(self, values, packed, options, scratch);
        if let Some(report) = solved {
            return report;
        }
        solve_amg_on(
            self,
            hierarchy,
            values,
            options,
            scratch,
            &Serial::new(self.node_count()) as &dyn Collective<T>,
        )
    }
}

/// [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) with the rows split over the processes of `comm` (the V-cycle runs
/// whole on every process, on the shared residual; everything else on the owned rows).
pub(crate) fn solve_amg_on<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    sys: &SpringSystem<'_, T>,
    hierarchy: &AmgHierarchy<'_, T>,
    values: &mut [[T; V]],
    options: &SolveOptions<T>,
    scratch: &mut [[T; V]],
    comm: &C,
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    hierarchy.check_system(sys)?;
    check_owned(comm, n)?;
    check_values("values", values, n)?;
    options.check()?;
    let needed = solve_linear_amg_scratch_len(hierarchy);
    check::buffer("scratch", scratch.len(), needed)?;
    let actual = scratch.len();
    let (v, rest) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual,
    })?;
    let op = Laplacian::<T, false> { sys, diag: &[] };
    let mut pre = Vcycle::new(sys, hierarchy, rest);
    // CG runs on the scaled field x_c · 2^−e_c, as the plain CG does (the preconditioner is
    // linear, so it commutes with the scaling).
    let exps = exponents(sys.stiffness(), values, false);
    let fixed = |i| sys.is_fixed(i);
    solve_scaled(&op, &mut pre, v, values, exps, fixed, options, comm)
}
