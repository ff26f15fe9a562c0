//! The elasticity solve preconditioned by smoothed aggregation with the rigid-body modes as
//! near-null space ([`RigidAmg`]): the vector problem coarsened as a whole (3 modes per
//! aggregate in 2D, 6 in 3D), as pyamg's `smoothed_aggregation_solver(A, B=rigid_modes)`.

use super::ElasticSystem;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::krylov::{cg_len, Vectors};
use crate::spring::{AmgOptions, RigidAmg, RigidVcycle, SolveOptions, SolveReport, SpringSystem};

/// `[T; D]` scratch items of [`ElasticSystem::solve_rigid_amg`] for `node_count` nodes and a
/// hierarchy with `coarse_scalars` ([`RigidAmgSizes::coarse_scalars`](crate::spring::RigidAmgSizes)):
/// the four CG vectors, one fine vector and `⌈3 coarse / D⌉` items (`None` on overflow or
/// `dim` 0).
pub const fn elastic_rigid_amg_scratch_len(
    node_count: usize,
    coarse_scalars: usize,
    dim: usize,
) -> Option<usize> {
    let (Some(cg), Some(c3)) = (cg_len(node_count), coarse_scalars.checked_mul(3)) else {
        return None;
    };
    if dim == 0 {
        return None;
    }
    match cg.checked_add(node_count) {
        Some(s) => s.checked_add(c3.div_ceil(dim)),
        None => None,
    }
}

impl<T: Real, const D: usize> ElasticSystem<'_, T, D> {
    /// Builds the rigid-mode multigrid hierarchy of this system into `index` and `values`
    /// (sizes from [`RigidAmg::setup_len`] with `dim = D`), with the rigid-body modes of
    /// `points` (the mesh the stiffness was assembled on). `spring` supplies the graph and fixed
    /// mask the aggregation runs on (a [`SpringSystem`] on the same graph and fixed mask; its
    /// weights are not used); `work` needs
    /// [`AmgHierarchy::setup_work_len`](crate::spring::AmgHierarchy::setup_work_len) entries.
    ///
    /// # Errors
    /// Those of [`RigidAmg::setup_len`]; `points` of the wrong length or non-finite
    /// ([`Error::LengthMismatch`], [`Error::NonFinite`]); `spring` of another size or fixed
    /// mask; short buffers ([`Error::BufferTooSmall`]); a coarse operator that is not
    /// positive definite ([`Error::SingularSystem`], `iteration: 0`).
    pub fn rigid_amg<'h>(
        &self,
        spring: &SpringSystem<'_, T>,
        points: &[[T; D]],
        options: &AmgOptions<T>,
        work: &mut [u32],
        index: &'h mut [u32],
        values: &'h mut [T],
    ) -> Result<RigidAmg<'h, T>> {
        check::len("points", points.len(), self.node_count())?;
        check::finite_items("points", points)?;
        let fine = self.fine();
        RigidAmg::setup(
            &fine,
            spring,
            points.as_flattened(),
            options,
            work,
            index,
            values,
        )
    }

    /// [`solve`](Self::solve) preconditioned by one V-cycle of the rigid-mode hierarchy
    /// `hierarchy` (built by [`rigid_amg`](Self::rigid_amg) on this system) per iteration.
    /// The hierarchy only preconditions: one built for other stiffness values of the same graph
    /// slows convergence but cannot change the answer.
    ///
    /// # Errors
    /// Those of [`solve`](Self::solve); `scratch` shorter than
    /// [`elastic_rigid_amg_scratch_len`]; a hierarchy of another size or dimension
    /// ([`Error::LengthMismatch`]).
    pub fn solve_rigid_amg(
        &self,
        hierarchy: &RigidAmg<'_, T>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let needed = self.rigid_needed(hierarchy, 0)?;
        self.check_solve(values, options, scratch.len(), needed)?;
        let (v, t, coarse) = rigid_split(scratch, self.node_count(), needed)?;
        let fine = self.fine();
        self.cg(
            &mut RigidVcycle::new(hierarchy, &fine, t, coarse),
            v,
            values,
            options,
        )
    }

    /// The scratch a rigid-multigrid solve needs (plus `extra` fine vectors), after checking
    /// that the hierarchy fits this system.
    pub(super) fn rigid_needed(&self, h: &RigidAmg<'_, T>, extra: usize) -> Result<usize> {
        let n = self.node_count();
        check::len("hierarchy", h.node_count(), n)?;
        check::len("hierarchy", h.level_unknowns(0), n.saturating_mul(D))?;
        Ok(elastic_rigid_amg_scratch_len(n, h.coarse_scalars(), D)
            .and_then(|s| s.checked_add(extra.saturating_mul(n)))
            .unwrap_or(usize::MAX))
    }
}

/// The CG vectors, the V-cycle's fine vector and its coarse vectors from `scratch` (checked
/// to hold `needed` items).
pub(super) fn rigid_split<T: Real, const D: usize>(
    scratch: &mut [[T; D]],
    n: usize,
    needed: usize,
) -> Result<(Vectors<'_, T, D>, &mut [T], &mut [T])> {
    let too_small = Error::BufferTooSmall {
        arg: "scratch",
        needed,
        actual: scratch.len(),
    };
    let (v, rest) = Vectors::split(scratch, n).ok_or(too_small)?;
    let (t, coarse) = rest
        .as_flattened_mut()
        .split_at_mut_checked(n.saturating_mul(D))
        .ok_or(too_small)?;
    Ok((v, t, coarse))
}
