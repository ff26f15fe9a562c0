//! The assembled elasticity operator on the free nodes ([`ElasticSystem`]) and its solves:
//! conjugate gradients of the kernel's Krylov core, preconditioned by the node blocks
//! (block Jacobi) or by the scalar smoothed-aggregation V-cycle applied to each displacement
//! component (the "unknown approach").
//!
//! Dirichlet data are eliminated symmetrically: a fixed node's prescribed displacement is
//! moved to the right-hand side (`b_i = −Σ_{j fixed} K_ij u_j` at free nodes) and its own
//! row and column are dropped, so CG sees the symmetric positive definite block `K_ff`.

use core::ops::Range;

use super::assemble::Block;
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::ExactSum;
use crate::graph::Graph;
use crate::real::Real;
use crate::spring::krylov::{
    apply_block_rows, cg_len, exponents, solve_scaled, NodeBlocks, NodeSolve, Operator,
    Precondition, Vectors,
};
use crate::spring::norms::{scaled_pair_norms, Norm, Pairs};
use crate::spring::{
    amg_cg_scratch_len, is_fixed, AmgHierarchy, Collective, Serial, SolveOptions, SolveReport,
    SpringSystem, Vcycle,
};
use crate::vector;

/// The assembled stiffness (from [`assemble`](super::assemble)) with its fixed mask
/// (nonzero byte = fixed: a prescribed displacement), validated once.
#[derive(Clone, Copy, Debug)]
pub struct ElasticSystem<'a, T: Real, const D: usize> {
    graph: Graph<'a>,
    diag: &'a [Block<T, D>],
    off: &'a [Block<T, D>],
    fixed: &'a [u8],
}

impl<'a, T: Real, const D: usize> ElasticSystem<'a, T, D> {
    /// Validates and wraps the blocks.
    ///
    /// # Errors
    /// `diag`, `off` or `fixed` of the wrong length ([`Error::LengthMismatch`]); a
    /// non-finite entry ([`Error::NonFinite`], `"diag"` or `"off"`); an edge block that is not
    /// the exact transpose of its mirror ([`Error::NotSymmetric`]); no fixed node
    /// ([`Error::InvalidParameter`]: rigid-body motion would be free); a free node whose
    /// diagonal block is not positive definite ([`Error::SingularNode`]).
    pub fn new(
        graph: Graph<'a>,
        diag: &'a [Block<T, D>],
        off: &'a [Block<T, D>],
        fixed: &'a [u8],
    ) -> Result<Self> {
        check::mesh_dim::<D>();
        let n = graph.node_count();
        check::len("diag", diag.len(), n)?;
        check::len("off", off.len(), graph.edge_count())?;
        check::len("fixed", fixed.len(), n)?;
        check_blocks("diag", diag)?;
        check_blocks("off", off)?;
        for (i, first, row) in graph.rows() {
            for (k, &j) in row.iter().enumerate() {
                let a = off.get(first + k);
                let b = graph.find_edge(j as usize, i).and_then(|e| off.get(e));
                if !matches!((a, b), (Some(a), Some(b)) if transposed(a, b)) {
                    return Err(Error::NotSymmetric {
                        from: i,
                        to: j as usize,
                    });
                }
            }
        }
        if !fixed.iter().any(|&m| is_fixed(m)) {
            return Err(Error::InvalidParameter {
                arg: "fixed",
                reason: "must fix at least one node (rigid-body motion is free otherwise)",
            });
        }
        for (i, (d, &m)) in diag.iter().zip(fixed).enumerate() {
            if !is_fixed(m) && solve_block(d, &[T::ZERO; D]).is_none() {
                return Err(Error::SingularNode { node: i });
            }
        }
        Ok(ElasticSystem {
            graph,
            diag,
            off,
            fixed,
        })
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.graph.node_count()
    }

    /// Whether node `i` is fixed.
    pub fn is_fixed(&self, i: usize) -> bool {
        self.fixed.get(i).is_some_and(|&m| is_fixed(m))
    }

    /// `(K x)_i` of the whole (unconstrained) matrix.
    fn row_product(&self, i: usize, x: &[[T; D]], skip_fixed: bool) -> [T; D] {
        let xi = x.get(i).copied().unwrap_or([T::ZERO; D]);
        let mut acc = self.diag.get(i).map_or([T::ZERO; D], |d| mat_vec(d, &xi));
        let r = self.graph.edge_range(i);
        let (Some(ts), Some(bs)) = (self.graph.targets().get(r.clone()), self.off.get(r)) else {
            return acc;
        };
        for (&j, b) in ts.iter().zip(bs) {
            if skip_fixed && self.is_fixed(j as usize) {
                continue;
            }
            let xj = x.get(j as usize).copied().unwrap_or([T::ZERO; D]);
            acc = vector::add(acc, mat_vec(b, &xj));
        }
        acc
    }

    /// `y = K x` with the whole (unconstrained) matrix, fixed rows and columns included:
    /// its null space holds the rigid-body motions.
    ///
    /// # Errors
    /// `x` or `y` of the wrong length ([`Error::LengthMismatch`]); nothing is written.
    pub fn multiply(&self, x: &[[T; D]], y: &mut [[T; D]]) -> Result<()> {
        check::len("x", x.len(), self.node_count())?;
        check::len("y", y.len(), self.node_count())?;
        for (i, y) in y.iter_mut().enumerate() {
            *y = self.row_product(i, x, false);
        }
        Ok(())
    }

    /// `(r_i, b_i)` at a free node `i`: residual `b − K_ff x_f` and `b_i = −Σ_{j fixed} K_ij x_j`.
    pub(super) fn pair(&self, i: usize, x: &[[T; D]]) -> ([T; D], [T; D]) {
        let all = self.row_product(i, x, false);
        let free = self.row_product(i, x, true);
        let b = vector::sub(free, all); // −Σ_{j fixed} K_ij x_j, exactly as the residual sees it
        (vector::scale(all, -T::ONE), b)
    }
}

/// Every entry of every block finite ([`Error::NonFinite`] at the first block that is not).
fn check_blocks<T: Real, const D: usize>(arg: &'static str, b: &[Block<T, D>]) -> Result<()> {
    match b
        .iter()
        .position(|b| b.iter().flatten().any(|x| !x.is_finite()))
    {
        Some(position) => Err(Error::NonFinite { arg, position }),
        None => Ok(()),
    }
}

/// `a == bᵀ` bit for bit.
fn transposed<T: Real, const D: usize>(a: &Block<T, D>, b: &Block<T, D>) -> bool {
    (0..D).all(|i| {
        (0..D).all(|j| {
            let x = a.get(i).and_then(|r| r.get(j));
            let y = b.get(j).and_then(|r| r.get(i));
            matches!((x, y), (Some(x), Some(y)) if x.to_bits_u64() == y.to_bits_u64())
        })
    })
}

/// `m v`.
#[inline]
fn mat_vec<T: Real, const D: usize>(m: &Block<T, D>, v: &[T; D]) -> [T; D] {
    let mut out = [T::ZERO; D];
    for (o, row) in out.iter_mut().zip(m) {
        *o = vector::dot(*row, *v);
    }
    out
}

/// `m⁻¹ r` of a symmetric positive definite block (Cholesky), `None` when it is not one.
fn solve_block<T: Real, const D: usize>(m: &Block<T, D>, r: &[T; D]) -> Option<[T; D]> {
    let mut l = [[T::ZERO; D]; D];
    for i in 0..D {
        for j in 0..=i {
            let mut s = *m.get(i)?.get(j)?;
            for k in 0..j {
                s -= *l.get(i)?.get(k)? * *l.get(j)?.get(k)?;
            }
            if i == j {
                if s <= T::ZERO || !s.is_finite() {
                    return None;
                }
                *l.get_mut(i)?.get_mut(i)? = s.sqrt();
            } else {
                *l.get_mut(i)?.get_mut(j)? = s / *l.get(j)?.get(j)?;
            }
        }
    }
    let mut y = *r;
    for i in 0..D {
        let mut s = *y.get(i)?;
        for k in 0..i {
            s -= *l.get(i)?.get(k)? * *y.get(k)?;
        }
        *y.get_mut(i)? = s / *l.get(i)?.get(i)?;
    }
    for i in (0..D).rev() {
        let mut s = *y.get(i)?;
        for k in i + 1..D {
            s -= *l.get(k)?.get(i)? * *y.get(k)?;
        }
        *y.get_mut(i)? = s / *l.get(i)?.get(i)?;
    }
    Some(y)
}

/// The residual pairs of the free nodes of some rows.
struct ElasticPairs<'s, 'a, 'x, T: Real, const D: usize> {
    sys: &'s ElasticSystem<'a, T, D>,
    rows: &'s [Range<usize>],
    x: &'x [[T; D]],
}

impl<T: Real, const D: usize> Pairs<T, D> for ElasticPairs<'_, '_, '_, T, D> {
    fn each<F: FnMut(&[T; D], &[T; D])>(&self, mut f: F) {
        for i in self.rows.iter().flat_map(|r| r.clone()) {
            if !self.sys.is_fixed(i) {
                let (r, b) = self.sys.pair(i, self.x);
                f(&r, &b);
            }
        }
    }
}

/// The block operator `K_ff` for the Krylov core: one lane (the blocks couple components).
impl<T: Real, const D: usize> Operator<T, D, 1> for ElasticSystem<'_, T, D> {
    #[inline]
    fn residual(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        if self.is_fixed(i) {
            return [T::ZERO; D];
        }
        vector::scale(self.row_product(i, x, false), -T::ONE)
    }

    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; D]],
        q: &mut [[T; D]],
        pq: &mut [ExactSum; 1],
        dpp: &mut [T; 1],
    ) {
        apply_block_rows(rows, p, q, pq, dpp, |i, pi| {
            if self.is_fixed(i) {
                return None;
            }
            // p is zero at fixed nodes: the whole row is K_ff's.
            let acc = self.row_product(i, p, false);
            let d = self.diag.get(i).map_or([T::ZERO; D], |d| mat_vec(d, &pi));
            Some((acc, vector::dot(pi, d)))
        });
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; D]],
        exps: &[i32; D],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        let pairs = ElasticPairs {
            sys: self,
            rows: comm.owned(),
            x,
        };
        scaled_pair_norms(&pairs, exps, true, comm)
    }
}

/// Block Jacobi, `z_i = K_ii⁻¹ r_i` by Cholesky (zero at fixed nodes).
impl<T: Real, const D: usize> NodeSolve<T, D> for ElasticSystem<'_, T, D> {
    #[inline]
    fn node_solve(&self, i: usize, r: [T; D]) -> [T; D] {
        match self.diag.get(i) {
            Some(d) if !self.is_fixed(i) => solve_block(d, &r).unwrap_or([T::ZERO; D]),
            _ => [T::ZERO; D],
        }
    }
}

/// `[T; D]` scratch items of [`ElasticSystem::solve`] for `node_count` nodes: the four CG
/// vectors, `4 n` (`None` on overflow).
pub const fn elastic_scratch_len(node_count: usize) -> Option<usize> {
    cg_len(node_count)
}

/// `[T; D]` scratch items of [`ElasticSystem::solve_amg`]: `5 n + 3 coarse` (the formula of
/// [`amg_cg_scratch_len`]; `None` on overflow).
pub const fn elastic_amg_scratch_len(node_count: usize, coarse_unknowns: usize) -> Option<usize> {
    amg_cg_scratch_len(node_count, coarse_unknowns)
}

impl<'a, T: Real, const D: usize> ElasticSystem<'a, T, D> {
    /// Solves `K u = 0` at the free nodes for the displacements `values` (prescribed at fixed
    /// nodes, the initial guess at free ones) by conjugate gradients preconditioned with the
    /// node blocks (block Jacobi). On `Ok`, `values` holds the last iterate (fixed values
    /// untouched bit for bit) and the report says whether it converged.
    ///
    /// # Errors
    /// `values` is untouched on error: wrong length or non-finite `values`, bad `options`,
    /// `scratch` shorter than [`elastic_scratch_len`] ([`Error::BufferTooSmall`]),
    /// [`Error::SingularSystem`] on non-positive curvature, [`Error::Overflow`].
    pub fn solve(
        &self,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        let needed = elastic_scratch_len(n).unwrap_or(usize::MAX);
        self.check_solve(values, options, scratch.len(), needed)?;
        let (v, _) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: 0,
        })?;
        self.cg(&mut NodeBlocks(self), v, values, options)
    }

    /// [`solve`](Self::solve) preconditioned by one V-cycle of a scalar smoothed-aggregation
    /// hierarchy per iteration, applied to each displacement component. `spring` is a system
    /// on the same graph and fixed mask with the weights of [`amg_weights`](Self::amg_weights)
    /// (or any positive symmetric ones), `hierarchy` built on it; they only precondition, so
    /// other weights slow convergence but cannot change the answer.
    ///
    /// # Errors
    /// Those of [`solve`](Self::solve), `scratch` shorter than [`elastic_amg_scratch_len`];
    /// `spring` or `hierarchy` of another size or fixed mask ([`Error::LengthMismatch`],
    /// [`Error::InvalidParameter`]).
    pub fn solve_amg(
        &self,
        spring: &SpringSystem<'_, T>,
        hierarchy: &AmgHierarchy<'_, T>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        self.check_amg(spring, hierarchy)?;
        let needed = elastic_amg_scratch_len(n, hierarchy.coarse_unknowns()).unwrap_or(usize::MAX);
        self.check_solve(values, options, scratch.len(), needed)?;
        let (v, rest) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: 0,
        })?;
        self.cg(
            &mut Vcycle::new(spring, hierarchy, rest),
            v,
            values,
            options,
        )
    }

    /// A scalar multigrid preconditioner's spring system and hierarchy fit this system: same
    /// size and fixed mask, the hierarchy built on `spring`.
    pub(crate) fn check_amg(
        &self,
        spring: &SpringSystem<'_, T>,
        hierarchy: &AmgHierarchy<'_, T>,
    ) -> Result<()> {
        let n = self.node_count();
        check::len("spring", spring.node_count(), n)?;
        hierarchy.check_system(spring)?;
        if (0..n).any(|i| spring.is_fixed(i) != self.is_fixed(i)) {
            return Err(Error::InvalidParameter {
                arg: "spring",
                reason: "must have the same fixed nodes",
            });
        }
        Ok(())
    }

    /// The fine operator of the rigid-mode multigrid: the blocks flattened.
    pub(super) fn fine(&self) -> crate::spring::Fine<'a, T> {
        crate::spring::Fine {
            graph: self.graph,
            diag: self.diag.as_flattened().as_flattened(),
            off: self.off.as_flattened().as_flattened(),
            fixed: self.fixed,
            d: D,
            slide: None,
        }
    }

    /// The checks every solve makes before it writes.
    pub(super) fn check_solve(
        &self,
        values: &[[T; D]],
        options: &SolveOptions<T>,
        actual: usize,
        needed: usize,
    ) -> Result<()> {
        check::len("values", values.len(), self.node_count())?;
        check::finite_items("values", values)?;
        options.check()?;
        check::buffer("scratch", actual, needed)
    }

    /// The largest `|entry|` of the diagonal blocks: the scale CG works at.
    pub(crate) fn kmax(&self) -> T {
        self.diag
            .iter()
            .flatten()
            .flatten()
            .fold(T::ZERO, |m, &k| m.max(k.abs()))
    }

    /// CG of the Krylov core on the jointly scaled iterate.
    pub(super) fn cg<M: Precondition<T, D>>(
        &self,
        pre: &mut M,
        v: Vectors<'_, T, D>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
    ) -> Result<SolveReport<T>> {
        self.cg_on(self, pre, v, values, options)
    }

    /// [`cg`](Self::cg) with another operator on this system's nodes (the projected one of
    /// the sliding solves).
    pub(super) fn cg_on<O: Operator<T, D, 1>, M: Precondition<T, D>>(
        &self,
        op: &O,
        pre: &mut M,
        v: Vectors<'_, T, D>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
    ) -> Result<SolveReport<T>> {
        let exps = exponents(&[self.kmax()], values, true);
        let serial = Serial::new(self.node_count());
        solve_scaled(
            op,
            pre,
            v,
            values,
            exps,
            |i| self.is_fixed(i),
            options,
            &serial,
        )
    }

    /// Scalar edge weights (one per directed edge, indexed like the graph's targets) for a
    /// [`SpringSystem`] whose multigrid hierarchy preconditions [`solve_amg`](Self::solve_amg):
    /// the largest `|entry|` of each edge block, at least `ε (m_i + m_j)` with `m_i` the
    /// largest `|entry|` of node `i`'s diagonal block (positive, and symmetric bit for bit).
    ///
    /// # Errors
    /// `out` of the wrong length ([`Error::LengthMismatch`]); nothing is written.
    pub fn amg_weights(&self, out: &mut [T]) -> Result<()> {
        check::len("out", out.len(), self.graph.edge_count())?;
        let m = |b: &Block<T, D>| b.iter().flatten().fold(T::ZERO, |m, &x| m.max(x.abs()));
        let dm = |i: usize| self.diag.get(i).map_or(T::ZERO, m);
        for (i, first, row) in self.graph.rows() {
            for (k, &j) in row.iter().enumerate() {
                let w = self.off.get(first + k).map_or(T::ZERO, m);
                let floor = T::EPSILON * (dm(i) + dm(j as usize));
                if let Some(o) = out.get_mut(first + k) {
                    *o = w.max(floor).max(T::MIN_POSITIVE);
                }
            }
        }
        Ok(())
    }
}
