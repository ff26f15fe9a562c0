//! The validated spring system (graph + stiffness + fixed mask) and the types shared by every
//! spring solver: options, report, sweep result.

use core::ops::Range;

use super::norms::Norm;
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::ExactSum;
use crate::graph::Graph;
use crate::real::Real;

/// `true` when mask byte `m` marks a fixed (Dirichlet) node: any nonzero byte.
#[inline]
pub fn is_fixed(m: u8) -> bool {
    m != 0
}

/// A validated spring network: a symmetric graph, one positive stiffness per directed edge
/// (equal on `i → j` and `j → i`, so the operator is symmetric) and a fixed mask in which every
/// free node reaches a fixed node through the graph (so the free-node operator is positive
/// definite: Yang & Özgen eq. 4, `K_aa` invertible).
///
/// Built once, then shared by every sweep and solve: the per-call checks are only on the
/// values.
#[derive(Clone, Copy, Debug)]
pub struct SpringSystem<'a, T: Real> {
    graph: Graph<'a>,
    stiffness: &'a [T],
    fixed: &'a [u8],
}

impl<'a, T: Real> SpringSystem<'a, T> {
    /// Length of the `u32` scratch [`SpringSystem::new`] needs: one entry per node (the
    /// anchoring search queue).
    #[inline]
    pub fn scratch_len(node_count: usize) -> usize {
        node_count
    }

    /// Validates and wraps graph, stiffness and fixed mask (nonzero byte = fixed, see
    /// [`is_fixed`]).
    ///
    /// # Errors
    /// `stiffness.len() != graph.edge_count()` or `fixed.len() != graph.node_count()`
    /// ([`Error::LengthMismatch`]); a NaN/infinite stiffness ([`Error::NonFinite`]) or a zero or
    /// negative one ([`Error::NonPositive`]); an edge without its reverse, or
    /// `stiffness[i → j] != stiffness[j → i]` ([`Error::NotSymmetric`]); `scratch` shorter than
    /// [`SpringSystem::scratch_len`] ([`Error::BufferTooSmall`]); a free node with no path to a
    /// fixed node ([`Error::Unanchored`], the smallest such node). Only `scratch` is written.
    pub fn new(
        graph: Graph<'a>,
        stiffness: &'a [T],
        fixed: &'a [u8],
        scratch: &mut [u32],
    ) -> Result<Self> {
        let n = graph.node_count();
        check::len("stiffness", stiffness.len(), graph.edge_count())?;
        check::len("fixed", fixed.len(), n)?;
        check::buffer("scratch", scratch.len(), n)?;
        // The anchoring search stores node indices and `n` as an end marker in u32.
        if u32::try_from(n).map_or(true, |m| m == u32::MAX) {
            return Err(Error::TooLarge {
                arg: "fixed",
                value: n,
            });
        }
        for (e, &k) in stiffness.iter().enumerate() {
            if !k.is_finite() {
                return Err(Error::NonFinite {
                    arg: "stiffness",
                    position: e,
                });
            }
            if k <= T::ZERO {
                return Err(Error::NonPositive {
                    arg: "stiffness",
                    position: e,
                });
            }
        }
        for (i, first, row) in graph.rows() {
            for (off, &j) in row.iter().enumerate() {
                let back = graph.find_edge(j as usize, i);
                let k_ij = stiffness.get(first + off);
                let k_ji = back.and_then(|b| stiffness.get(b));
                match (k_ij, k_ji) {
                    (Some(a), Some(b)) if a == b => {}
                    _ => {
                        return Err(Error::NotSymmetric {
                            from: i,
                            to: j as usize,
                        })
                    }
                }
            }
        }
        let sys = SpringSystem {
            graph,
            stiffness,
            fixed,
        };
        if let Some(node) = sys.first_unanchored(scratch) {
            return Err(Error::Unanchored { node });
        }
        Ok(sys)
    }

    /// Wraps parts that were validated by [`SpringSystem::new`] before (a prepared plan's
    /// copies): no check at all.
    #[inline]
    pub(crate) fn trusted(graph: Graph<'a>, stiffness: &'a [T], fixed: &'a [u8]) -> Self {
        SpringSystem {
            graph,
            stiffness,
            fixed,
        }
    }

    /// Breadth-first search from every fixed node; returns the smallest free node never
    /// reached. The queue is a linked list threaded through `state`: `UNSEEN` = not reached,
    /// `end` (= n) = reached and last in the queue, otherwise the next node in the queue.
    fn first_unanchored(&self, state: &mut [u32]) -> Option<usize> {
        const UNSEEN: u32 = u32::MAX;
        let n = self.node_count();
        let end = n as u32;
        let state = state.get_mut(..n)?;
        state.fill(UNSEEN);
        let mut head = end;
        let mut tail = end;
        for (i, &m) in self.fixed.iter().enumerate() {
            if is_fixed(m) {
                if let Some(s) = state.get_mut(i) {
                    *s = end;
                }
                if tail == end {
                    head = i as u32;
                } else if let Some(t) = state.get_mut(tail as usize) {
                    *t = i as u32;
                }
                tail = i as u32;
            }
        }
        while head != end {
            let node = head as usize;
            for &j in self.graph.neighbors(node) {
                if state.get(j as usize) == Some(&UNSEEN) {
                    if let Some(s) = state.get_mut(j as usize) {
                        *s = end;
                    }
                    if let Some(t) = state.get_mut(tail as usize) {
                        *t = j;
                    }
                    tail = j;
                }
            }
            head = state.get(node).copied().unwrap_or(end);
        }
        state.iter().position(|&s| s == UNSEEN)
    }

    /// The graph.
    #[inline]
    pub fn graph(&self) -> Graph<'a> {
        self.graph
    }

    /// The per-directed-edge stiffness.
    #[inline]
    pub fn stiffness(&self) -> &'a [T] {
        self.stiffness
    }

    /// The fixed mask (nonzero = fixed).
    #[inline]
    pub fn fixed(&self) -> &'a [u8] {
        self.fixed
    }

    /// Number of nodes.
    #[inline]
    pub fn node_count(&self) -> usize {
        self.graph.node_count()
    }

    /// `true` when node `i` is fixed (out-of-range nodes count as fixed: they are never
    /// updated).
    #[inline]
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed.get(i).is_none_or(|&m| is_fixed(m))
    }

    /// Node `i`'s row: `(neighbour, stiffness)` pairs in CSR order.
    #[inline]
    pub(crate) fn row(&self, i: usize) -> impl Iterator<Item = (usize, T)> + 'a {
        let r = self.graph.edge_range(i);
        let targets = self.graph.targets().get(r.clone()).unwrap_or(&[]);
        let k = self.stiffness.get(r).unwrap_or(&[]);
        targets.iter().zip(k).map(|(&j, &k)| (j as usize, k))
    }

    /// Rows in node order: `(node, fixed?, row iterator)`.
    #[inline]
    pub(crate) fn rows(
        &self,
    ) -> impl Iterator<Item = (usize, bool, impl Iterator<Item = (usize, T)> + 'a)> + 'a {
        let stiffness = self.stiffness;
        let fixed = self.fixed;
        self.graph.rows().map(move |(i, first, row)| {
            let k = stiffness.get(first..first + row.len()).unwrap_or(&[]);
            let f = fixed.get(i).is_none_or(|&m| is_fixed(m));
            (i, f, row.iter().zip(k).map(|(&j, &k)| (j as usize, k)))
        })
    }

    /// Rows `nodes` in node order: `(node, fixed?, row iterator)` (empty past the end).
    #[inline]
    pub(crate) fn rows_in(
        &self,
        nodes: Range<usize>,
    ) -> impl Iterator<Item = (usize, bool, impl Iterator<Item = (usize, T)> + 'a)> + 'a {
        let stiffness = self.stiffness;
        let fixed = self.fixed;
        let targets = self.graph.targets();
        let start = nodes.start;
        let offsets = self
            .graph
            .offsets()
            .get(nodes.start..nodes.end.saturating_add(1))
            .unwrap_or(&[]);
        offsets.windows(2).enumerate().map(move |(k, w)| {
            let i = start + k;
            let (a, b) = match *w {
                [a, b] => (a as usize, b as usize),
                _ => (0, 0),
            };
            let t = targets.get(a..b).unwrap_or(&[]);
            let kk = stiffness.get(a..b).unwrap_or(&[]);
            let f = fixed.get(i).is_none_or(|&m| is_fixed(m));
            (i, f, t.iter().zip(kk).map(|(&j, &k)| (j as usize, k)))
        })
    }

    /// Checks a node range against the node count.
    pub(crate) fn check_range(&self, nodes: &Range<usize>) -> Result<()> {
        let n = self.node_count();
        if nodes.end > n {
            return Err(Error::IndexOutOfRange {
                arg: "nodes",
                position: 1,
                index: nodes.end,
                bound: n + 1,
            });
        }
        Ok(())
    }
}

/// Checks that a value field has one finite entry per node.
pub(crate) fn check_values<T: Real, const V: usize>(
    arg: &'static str,
    values: &[[T; V]],
    n: usize,
) -> Result<()> {
    check::len(arg, values.len(), n)?;
    check::finite_items(arg, values)?;
    Ok(())
}

/// Result of one sweep over a node range.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sweep<T> {
    /// Largest `|new − old|` over the range's free nodes and all components (0 for an empty
    /// range): the paper's "no more variation" convergence measure.
    pub max_change: T,
    /// `Σ |r_i|²` over the range's free nodes and all components, where `r_i` is the residual
    /// `b − A x` at node `i` seen by the sweep. For a Jacobi sweep this is exactly the residual
    /// of the input field; for Gauss–Seidel/SOR it is the residual of the partly updated field
    /// at the moment node `i` was visited (an estimate; the whole solves confirm convergence
    /// with the true residual). Rounded from [`Sweep::residual_sum`].
    pub residual_sq: T,
    /// The same `Σ |r_i|²`, exact: [`ExactSum::merge`] the sweeps of several ranges (or
    /// ranks) and round once with [`ExactSum::value`] to get the bits one sweep over their
    /// union gives, however the nodes were split.
    pub residual_sum: ExactSum,
}

/// Stopping rules shared by every spring solver.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SolveOptions<T> {
    /// Iteration cap (sweeps, or CG iterations). Default 10 000.
    pub max_iterations: usize,
    /// Converged when the relative residual `‖b − A x‖₂ / ‖b‖₂` (all free nodes, all
    /// components; `b` = the fixed nodes' pull on the free nodes; the plain `‖b − A x‖₂` when
    /// `b = 0`) is at most this. Default `max(1e-10, 100 ε)`: 1e-10 for `f64`, about 1.2e-5
    /// for `f32`.
    pub residual_tol: T,
    /// Also converged when the largest absolute change of one iteration (in the values' own
    /// units) is at most this. Default 0 = off: a small update of a slowly converging
    /// stationary method does not mean a small error.
    pub update_tol: T,
}

impl<T: Real> Default for SolveOptions<T> {
    fn default() -> Self {
        let hundred_eps = T::from_f64(100.0) * T::EPSILON;
        SolveOptions {
            max_iterations: 10_000,
            residual_tol: T::from_f64(1e-10).max(hundred_eps),
            update_tol: T::ZERO,
        }
    }
}

impl<T: Real> SolveOptions<T> {
    /// Checks the tolerances (finite, non-negative).
    pub(crate) fn check(&self) -> Result<()> {
        if !(self.residual_tol.is_finite() && self.residual_tol >= T::ZERO) {
            return Err(Error::InvalidParameter {
                arg: "residual_tol",
                reason: "must be finite and >= 0",
            });
        }
        if !(self.update_tol.is_finite() && self.update_tol >= T::ZERO) {
            return Err(Error::InvalidParameter {
                arg: "update_tol",
                reason: "must be finite and >= 0",
            });
        }
        Ok(())
    }

    /// The convergence test: residual rule or (when enabled) update rule.
    #[inline]
    pub(crate) fn met(&self, relative_residual: T, max_update: T) -> bool {
        relative_residual <= self.residual_tol
            || (self.update_tol > T::ZERO && max_update <= self.update_tol)
    }
}

/// What a whole solve did. Non-convergence is reported here (`converged == false`), never
/// hidden; the values then hold the last iterate.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct SolveReport<T> {
    /// Iterations performed (sweeps, or CG iterations).
    pub iterations: usize,
    /// True relative residual `‖b − A x‖₂ / ‖b‖₂` of the returned values (recomputed from the
    /// values, not a recurrence).
    pub residual: T,
    /// Largest absolute change in the last iteration (0 when no iteration was needed).
    pub max_update: T,
    /// Whether a stopping rule of [`SolveOptions`] was met.
    pub converged: bool,
}

impl<T: Real> SolveReport<T> {
    /// The report before the first iteration: the initial relative residual `‖r₀‖ / ‖b‖`,
    /// converged when it already meets [`SolveOptions::residual_tol`] (every solve's first
    /// stopping test).
    pub(crate) fn start(r0: Norm<T>, bnorm: Norm<T>, options: &SolveOptions<T>) -> Self {
        let residual = r0.relative_to(bnorm);
        SolveReport {
            iterations: 0,
            residual,
            max_update: T::ZERO,
            converged: residual <= options.residual_tol,
        }
    }
}

/// Preconditioner for the linear-spring conjugate gradient.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Preconditioner<T> {
    /// None (plain CG).
    None,
    /// Diagonal (Jacobi): `z_i = r_i / Σ_j k_ij`.
    Jacobi,
    /// Symmetric SOR, `M = (D + ωL) D⁻¹ (D + ωU) / (ω (2 − ω))`, `0 < ω < 2`; one forward and
    /// one backward sweep per application.
    Ssor {
        /// Relaxation factor in `(0, 2)`; 1 gives symmetric Gauss–Seidel.
        omega: T,
    },
}

/// Solution method for the linear springs ([`solve_linear`](crate::spring::SpringSystem::solve_linear)).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LinearMethod<T> {
    /// The paper's iteration (Yang & Özgen §2.1, Samareh eq. 2): every node from the previous
    /// field.
    Jacobi,
    /// Gauss–Seidel: in place, in node order.
    GaussSeidel,
    /// Successive over-relaxation, `0 < ω < 2`.
    Sor {
        /// Relaxation factor in `(0, 2)`.
        omega: T,
    },
    /// Preconditioned conjugate gradients, one `α`, `β` per value component.
    Cg {
        /// The preconditioner.
        preconditioner: Preconditioner<T>,
    },
}

/// Checks a relaxation factor: finite and in `(0, 2)`.
pub(crate) fn check_omega<T: Real>(omega: T) -> Result<()> {
    if omega.is_finite() && omega > T::ZERO && omega < T::TWO {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            arg: "omega",
            reason: "must be in (0, 2)",
        })
    }
}
