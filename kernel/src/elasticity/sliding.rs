//! Sliding nodes in the elasticity solve (symmetry planes), as the springs have them
//! ([`Constraints`]): node `i` may move by `P_i d` only (`I − n nᵀ` on a plane, `t tᵀ` on a
//! line, `0` fixed, `I` free), and the displacement minimises the elastic energy over those
//! motions: `P K P d = P b` on `range(P)`, by CG with the projected preconditioner
//! `z = P M⁻¹ r` (`P M⁻¹ P` is symmetric positive definite on `range(P)`, so CG's guarantees
//! hold). The initial guess at sliding nodes is projected first and every sliding result once
//! more at the end, so `n · d` is at rounding level of `|d|`.

use core::ops::Range;

use super::rigid::{elastic_rigid_amg_scratch_len, rigid_split};
use super::system::{elastic_amg_scratch_len, elastic_scratch_len};
use super::ElasticSystem;
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::ExactSum;
use crate::real::Real;
use crate::spring::constraints::{Constraints, NodeKind};
use crate::spring::krylov::NodeBlocks;
use crate::spring::krylov::{solve_rhs, Operator, Precondition, RhsLayout, Vectors};
use crate::spring::norms::scaled_pair_norms;
use crate::spring::norms::{Norm, Pairs};
use crate::spring::{
    AmgHierarchy, AmgOptions, Collective, RigidAmg, RigidVcycle, Serial, SolveOptions, SolveReport,
    SpringSystem, Vcycle,
};

/// `[T; D]` scratch items of [`ElasticSystem::solve_sliding`]: the four CG vectors and a
/// copy of the values (`5 n`; `None` on overflow).
pub const fn elastic_sliding_scratch_len(node_count: usize) -> Option<usize> {
    match elastic_scratch_len(node_count) {
        Some(s) => s.checked_add(node_count),
        None => None,
    }
}

/// `[T; D]` scratch items of [`ElasticSystem::solve_amg_sliding`]:
/// [`elastic_amg_scratch_len`] and `n` more (`None` on overflow).
pub const fn elastic_amg_sliding_scratch_len(
    node_count: usize,
    coarse_unknowns: usize,
) -> Option<usize> {
    match elastic_amg_scratch_len(node_count, coarse_unknowns) {
        Some(s) => s.checked_add(node_count),
        None => None,
    }
}

/// `[T; D]` scratch items of [`ElasticSystem::solve_rigid_amg_sliding`]:
/// [`elastic_rigid_amg_scratch_len`] and `n` more (`None` on overflow).
pub const fn elastic_rigid_amg_sliding_scratch_len(
    node_count: usize,
    coarse_scalars: usize,
    dim: usize,
) -> Option<usize> {
    match elastic_rigid_amg_scratch_len(node_count, coarse_scalars, dim) {
        Some(s) => s.checked_add(node_count),
        None => None,
    }
}

/// The projected operator `P K P`.
struct Slid<'s, 'a, T: Real, const D: usize> {
    sys: &'s ElasticSystem<'a, T, D>,
    c: &'s Constraints<'s, T, D>,
}

/// The projected residual pairs of the free and sliding nodes of some rows.
struct SlidPairs<'s, 'a, 'x, T: Real, const D: usize> {
    op: &'s Slid<'s, 'a, T, D>,
    rows: &'s [Range<usize>],
    x: &'x [[T; D]],
}

impl<T: Real, const D: usize> Pairs<T, D> for SlidPairs<'_, '_, '_, T, D> {
    fn each<F: FnMut(&[T; D], &[T; D])>(&self, mut f: F) {
        for i in self.rows.iter().flat_map(|r| r.clone()) {
            if !self.op.sys.is_fixed(i) {
                let (r, b) = self.op.sys.pair(i, self.x);
                f(&self.op.c.project(i, r), &self.op.c.project(i, b));
            }
        }
    }
}

impl<T: Real, const D: usize> Operator<T, D, 1> for Slid<'_, '_, T, D> {
    #[inline]
    fn residual(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        self.c
            .project(i, Operator::<T, D, 1>::residual(self.sys, i, x))
    }

    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; D]],
        q: &mut [[T; D]],
        pq: &mut [ExactSum; 1],
        dpp: &mut [T; 1],
    ) {
        // p ∈ range(P): pᵀ K p = pᵀ P K p, so the inner product is the unprojected one.
        self.sys.apply(rows.clone(), p, q, pq, dpp);
        if let Some(qs) = q.get_mut(rows.clone()) {
            for (i, qi) in rows.zip(qs) {
                *qi = self.c.project(i, *qi);
            }
        }
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; D]],
        exps: &[i32; D],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        let pairs = SlidPairs {
            op: self,
            rows: comm.owned(),
            x,
        };
        scaled_pair_norms(&pairs, exps, true, comm)
    }
}

/// `z = P M⁻¹ r`.
struct Projected<'s, T: Real, const D: usize, M> {
    inner: M,
    c: &'s Constraints<'s, T, D>,
}

impl<T: Real, const D: usize, M: Precondition<T, D>> Precondition<T, D> for Projected<'_, T, D, M> {
    fn local(&self) -> bool {
        self.inner.local()
    }
    #[inline]
    fn node(&self, i: usize, r: [T; D]) -> [T; D] {
        self.c.project(i, self.inner.node(i, r))
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; D]], z: &mut [[T; D]], comm: &C) {
        self.inner.apply(r, z, comm);
        for (i, z) in z.iter_mut().enumerate() {
            *z = self.c.project(i, *z);
        }
    }
}

impl<T: Real, const D: usize> ElasticSystem<'_, T, D> {
    /// [`solve`](Self::solve) with sliding nodes: `constraints` gives every node's kind
    /// (fixed exactly at this system's fixed nodes; plane and line nodes are free in the
    /// system) and direction. Block-Jacobi preconditioned; `values` as for
    /// [`solve`](Self::solve) (the guess at sliding nodes is projected first).
    ///
    /// # Errors
    /// Those of [`solve`](Self::solve), `scratch` shorter than
    /// [`elastic_sliding_scratch_len`]; constraints of another length or whose fixed nodes
    /// differ from the system's ([`Error::LengthMismatch`], [`Error::InvalidParameter`]).
    /// `values` is unchanged on error.
    pub fn solve_sliding(
        &self,
        constraints: &Constraints<'_, T, D>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        let needed = elastic_sliding_scratch_len(n).unwrap_or(usize::MAX);
        self.check_sliding(constraints, values, options, scratch.len(), needed)?;
        let too_small = Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: scratch.len(),
        };
        let (saved, rest) = scratch.split_at_mut_checked(n).ok_or(too_small)?;
        let v = Vectors::split(rest, n).ok_or(too_small)?;
        let pre = NodeBlocks(self);
        self.sliding_cg(constraints, pre, v.0, saved, values, options)
    }

    /// [`solve_rigid_amg`](Self::solve_rigid_amg) with sliding nodes (see
    /// [`solve_sliding`](Self::solve_sliding)), with a hierarchy from
    /// [`rigid_amg_sliding`](Self::rigid_amg_sliding) (the same constraints).
    ///
    /// # Errors
    /// Those of [`solve_sliding`](Self::solve_sliding) and
    /// [`solve_rigid_amg`](Self::solve_rigid_amg); `scratch` shorter than
    /// [`elastic_rigid_amg_sliding_scratch_len`].
    pub fn solve_rigid_amg_sliding(
        &self,
        constraints: &Constraints<'_, T, D>,
        hierarchy: &RigidAmg<'_, T>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        let needed = self.rigid_needed(hierarchy, 1)?;
        self.check_sliding(constraints, values, options, scratch.len(), needed)?;
        let (saved, rest) = scratch
            .split_at_mut_checked(n)
            .ok_or(Error::BufferTooSmall {
                arg: "scratch",
                needed,
                actual: 0,
            })?;
        let (v, t, coarse) = rigid_split(rest, n, needed)?;
        let mut fine = self.fine();
        fine.slide = Some((constraints.kinds(), constraints.directions().as_flattened()));
        let pre = RigidVcycle::new(hierarchy, &fine, t, coarse);
        self.sliding_cg(constraints, pre, v, saved, values, options)
    }

    /// [`solve_amg`](Self::solve_amg) with sliding nodes (see
    /// [`solve_sliding`](Self::solve_sliding)): the scalar V-cycle of `hierarchy` (built on
    /// `spring`, the sliding nodes free in it) per component, projected (`z = P M⁻¹ r`).
    ///
    /// # Errors
    /// Those of [`solve_sliding`](Self::solve_sliding) and [`solve_amg`](Self::solve_amg);
    /// `scratch` shorter than [`elastic_amg_sliding_scratch_len`].
    pub fn solve_amg_sliding(
        &self,
        constraints: &Constraints<'_, T, D>,
        spring: &SpringSystem<'_, T>,
        hierarchy: &AmgHierarchy<'_, T>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        self.check_amg(spring, hierarchy)?;
        let needed =
            elastic_amg_sliding_scratch_len(n, hierarchy.coarse_unknowns()).unwrap_or(usize::MAX);
        self.check_sliding(constraints, values, options, scratch.len(), needed)?;
        let too_small = Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: scratch.len(),
        };
        let (saved, rest) = scratch.split_at_mut_checked(n).ok_or(too_small)?;
        let (v, rest) = Vectors::split(rest, n).ok_or(too_small)?;
        let pre = Vcycle::new(spring, hierarchy, rest);
        self.sliding_cg(constraints, pre, v, saved, values, options)
    }

    /// `P K P λ = f` on `range(P)` for an arbitrary right-hand side `f` (`rhs`, already in
    /// `range(P)`: projected at sliding nodes, ignored at fixed ones) from a zero initial
    /// guess, by the sliding solves' projected CG with `inner` projected as the
    /// preconditioner: the adjoint solves. `λ` (`out`) is zero at fixed nodes, projected once
    /// more at sliding ones, and written only on `Ok`. The caller checks sizes and finiteness.
    pub(crate) fn solve_sliding_rhs<M: Precondition<T, D>>(
        &self,
        c: &Constraints<'_, T, D>,
        inner: M,
        v: Vectors<'_, T, D>,
        rhs: &[[T; D]],
        out: &mut [[T; D]],
        options: &SolveOptions<T>,
    ) -> Result<SolveReport<T>> {
        let op = Slid { sys: self, c };
        let mut pre = Projected { inner, c };
        let layout = RhsLayout {
            kmax: self.kmax(),
            joint: true,
            per_node: true,
        };
        let fixed = |i| self.is_fixed(i);
        let serial = Serial::new(self.node_count());
        let report = solve_rhs(&op, &mut pre, v, rhs, out, layout, fixed, options, &serial)?;
        for (i, x) in out.iter_mut().enumerate() {
            *x = c.project(i, *x);
        }
        Ok(report)
    }

    /// [`rigid_amg`](Self::rigid_amg) for [`solve_rigid_amg_sliding`](Self::solve_rigid_amg_sliding):
    /// the hierarchy of `K + s N` with a stiff spring across each sliding node's allowed
    /// motion (`N_i = n nᵀ` on a plane, `I − t tᵀ` on a line, `s` the node's mean diagonal
    /// entry), whose inverse approaches the constrained operator's; the hierarchy of the
    /// unconstrained `K` preconditions the projected problem poorly (the normal motion of the
    /// sliding nodes is free in it).
    ///
    /// # Errors
    /// Those of [`rigid_amg`](Self::rigid_amg); constraints of another length or whose fixed
    /// nodes differ from the system's.
    #[allow(clippy::too_many_arguments)]
    pub fn rigid_amg_sliding<'h>(
        &self,
        constraints: &Constraints<'_, T, D>,
        spring: &SpringSystem<'_, T>,
        points: &[[T; D]],
        options: &AmgOptions<T>,
        work: &mut [u32],
        index: &'h mut [u32],
        values: &'h mut [T],
    ) -> Result<RigidAmg<'h, T>> {
        check::len("constraints", constraints.len(), self.node_count())?;
        self.check_kinds(constraints)?;
        check::len("points", points.len(), self.node_count())?;
        check::finite_items("points", points)?;
        let mut fine = self.fine();
        fine.slide = Some((constraints.kinds(), constraints.directions().as_flattened()));
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

    /// Kind 1 exactly at the system's fixed nodes.
    pub(crate) fn check_kinds(&self, c: &Constraints<'_, T, D>) -> Result<()> {
        if (0..c.len()).any(|i| (c.kind(i) == NodeKind::Fixed) != self.is_fixed(i)) {
            return Err(Error::InvalidParameter {
                arg: "constraints",
                reason: "must give kind 1 (fixed) exactly to the system's fixed nodes",
            });
        }
        Ok(())
    }

    /// The checks of the sliding solves, before anything is written.
    fn check_sliding(
        &self,
        c: &Constraints<'_, T, D>,
        values: &[[T; D]],
        options: &SolveOptions<T>,
        actual: usize,
        needed: usize,
    ) -> Result<()> {
        check::len("constraints", c.len(), self.node_count())?;
        self.check_kinds(c)?;
        self.check_solve(values, options, actual, needed)
    }

    /// Projected CG: the guess at sliding nodes projected (the original kept in `saved` and
    /// restored on error), the results projected once more.
    fn sliding_cg<M: Precondition<T, D>>(
        &self,
        c: &Constraints<'_, T, D>,
        inner: M,
        v: Vectors<'_, T, D>,
        saved: &mut [[T; D]],
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
    ) -> Result<SolveReport<T>> {
        let sliding = |i: usize| matches!(c.kind(i), NodeKind::Plane | NodeKind::Line);
        for (i, (s, x)) in saved.iter_mut().zip(values.iter_mut()).enumerate() {
            *s = *x;
            if sliding(i) {
                *x = c.project(i, *x);
            }
        }
        let op = Slid { sys: self, c };
        let mut pre = Projected { inner, c };
        match self.cg_on(&op, &mut pre, v, values, options) {
            Ok(r) => {
                for (i, x) in values.iter_mut().enumerate() {
                    if sliding(i) {
                        *x = c.project(i, *x);
                    }
                }
                Ok(r)
            }
            Err(e) => {
                for (x, s) in values.iter_mut().zip(saved.iter()) {
                    *x = *s;
                }
                Err(e)
            }
        }
    }
}
