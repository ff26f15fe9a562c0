//! One handle for every linear-spring solver: a [`LinearMethod`] (stationary or CG with a
//! one-level preconditioner) or the multigrid-preconditioned CG with a prebuilt
//! [`AmgHierarchy`]. The deformation pipelines take this, so they run with either.

use super::amg::{solve_amg_on, solve_linear_amg_scratch_len, AmgHierarchy};
use super::distributed::Collective;
use super::linear::{solve_linear_on, solve_linear_scratch_len};
use super::system::{LinearMethod, SolveOptions, SolveReport, SpringSystem};
use crate::error::Result;
use crate::real::Real;

/// A linear-spring solver.
#[derive(Clone, Copy, Debug)]
pub enum LinearSolver<'a, T: Real> {
    /// [`solve_linear`](crate::spring::SpringSystem::solve_linear) with this method.
    Method(LinearMethod<T>),
    /// [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) with this hierarchy (built for the system being solved).
    Amg(&'a AmgHierarchy<'a, T>),
    /// This method with the rows split over the processes of a [`Collective`]: every
    /// process calls with the whole system and field and gets the serial bits. CG with a
    /// Jacobi or no preconditioner only (the others visit nodes in order).
    Distributed(LinearMethod<T>, &'a dyn Collective<T>),
    /// Multigrid-preconditioned CG with the rows split over the processes (the V-cycle runs
    /// whole on each; the serial bits on every process).
    DistributedAmg(&'a AmgHierarchy<'a, T>, &'a dyn Collective<T>),
}

impl<T: Real> From<LinearMethod<T>> for LinearSolver<'_, T> {
    fn from(m: LinearMethod<T>) -> Self {
        LinearSolver::Method(m)
    }
}

/// Number of `[T; V]` scratch items [`solve_linear_with`](crate::spring::SpringSystem::solve_linear_with) needs for `node_count` nodes.
pub fn solve_linear_with_scratch_len<T: Real>(
    solver: &LinearSolver<'_, T>,
    node_count: usize,
) -> usize {
    match solver {
        LinearSolver::Method(m) | LinearSolver::Distributed(m, _) => {
            solve_linear_scratch_len(m, node_count)
        }
        LinearSolver::Amg(h) | LinearSolver::DistributedAmg(h, _) => {
            solve_linear_amg_scratch_len(h)
        }
    }
}

impl<T: Real> SpringSystem<'_, T> {
    /// Solves the linear springs with `solver`: [`solve_linear`](crate::spring::SpringSystem::solve_linear) or [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) (same
    /// problem, same report, same errors).
    ///
    /// # Errors
    /// Those of [`solve_linear`](crate::spring::SpringSystem::solve_linear) or [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg), whichever `solver` selects.
    pub fn solve_linear_with<const V: usize>(
        &self,
        values: &mut [[T; V]],
        solver: LinearSolver<'_, T>,
        options: &SolveOptions<T>,
        scratch: &mut [[T; V]],
    ) -> Result<SolveReport<T>> {
        match solver {
            LinearSolver::Method(m) => self.solve_linear(values, m, options, scratch),
            LinearSolver::Amg(h) => self.solve_linear_amg(h, values, options, scratch),
            LinearSolver::Distributed(m, c) => {
                solve_linear_on(self, values, m, options, scratch, Some(c))
            }
            LinearSolver::DistributedAmg(h, c) => {
                solve_amg_on(self, h, values, options, scratch, c)
            }
        }
    }
}
