//! Angle-inclusion springs (Yang & Özgen §2.2); see [`AngleSystem`].

use core::ops::Range;

use super::amg::{amg_cg_scratch_len, AmgHierarchy, Vcycle};
use super::distributed::{Collective, Serial};
use super::krylov::{
    apply_block_rows, cg_len, exponents, pcg, solve_scaled, NodeBlocks, NodeSolve, Operator,
    Precondition, Vectors,
};
use super::linear::{drive_sweeps, gauss_seidel_order, jacobi_order, Sweeps};
use super::norms::{pair_norms, scaled_pair_norms, Norm, Pairs};
use super::system::{check_omega, check_values, SolveOptions, SolveReport, SpringSystem, Sweep};
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::ExactSum;
use crate::real::Real;
use crate::vector;

/// Default regularisation `ε` of the angle-inclusion springs (fraction of the linear spring
/// added to every edge block). See the [`AngleSystem`] documentation.
pub const DEFAULT_ANGLE_EPSILON: f64 = 0.01;

/// Largest rigidity-probe amplification ([`angle_rigidity_probe`](crate::spring::AngleSystem::angle_rigidity_probe)) [`solve_angle`](crate::spring::AngleSystem::solve_angle) accepts
/// when `ε = 0`; above it the system is reported as [`Error::SingularSystem`] (numerically a
/// mechanism: its solution would be dominated by near-zero-energy modes).
pub const MAX_AMPLIFICATION: f64 = 1e6;

/// A validated angle-inclusion spring system: a [`SpringSystem`] plus the (undeformed) node
/// coordinates that give each edge its direction, and the regularisation `ε`.
///
/// For the edge `i → j` with `d = r_j − r_i` (undeformed coordinates), stiffness `k` and
/// regularisation `ε`, the edge block is
///
/// `B_ij = k (d dᵀ / |d|² + ε I)`,
///
/// which is the paper's eq. 2 (`k [[c², cs], [cs, s²]]`, with `c`, `s` the cosine and sine of
/// the edge angle) in 2D, and `k e eᵀ` in 3D, plus `ε` times the linear spring. Equilibrium at
/// a free node is `Σ_j B_ij (x_j − x_i) = 0` (eq. 3 = 0).
///
/// **Regularisation (default [`DEFAULT_ANGLE_EPSILON`] = 0.01).** With `ε = 0` the operator is
/// the paper's but may be singular: a node whose edges are colinear (2D) or coplanar (3D) has a
/// singular 2×2/3×3 block, and a truss of quads without diagonals is a mechanism. With `ε > 0`
/// the operator lies between `ε L` and `(1 + ε) L` (`L` = the linear-spring Laplacian), so it is
/// positive definite whenever the linear springs are, with condition number at most
/// `(1 + ε)/ε` times theirs; 0.01 changes the paper's operator by 1 % while keeping every
/// node and global system solvable. Quad and hex meshes can instead (or also) be stiffened
/// with face diagonals from [`graph_from_cells`](crate::graph_from_cells).
///
/// **Singularity detection.** [`AngleSystem::new`] rejects a free node whose block is singular
/// ([`Error::SingularNode`]): its normalised determinant `det / (tr/D)^D` (1 for an isotropic
/// block, 0 for a singular one) must exceed `√ε_machine` (about 1.5e-8 for `f64`, 3.5e-4 for
/// `f32`). A singular *global* system cannot be seen by CG on the user's data: the right-hand
/// side of a zero-energy mechanism is always orthogonal to the mechanism (fixed nodes push only
/// along edges the mechanism does not stretch), so Krylov methods quietly converge to one of
/// infinitely many answers; a *nearly* singular one converges to a garbage mesh. Therefore,
/// when `ε = 0`, every solve first runs a **rigidity probe** ([`angle_rigidity_probe`](crate::spring::AngleSystem::angle_rigidity_probe)):
/// block-Jacobi CG on a deterministic pseudo-random right-hand side, which has a component in
/// any null space. It must reach a relative residual of `max(1e-6, 100 ε_mach)` within
/// `max(max_iterations, 100)` iterations with positive curvature, and its amplification must
/// not exceed [`MAX_AMPLIFICATION`] (1e6), else the solve returns [`Error::SingularSystem`]
/// before touching the values. The probe costs about one extra solve.
#[derive(Clone, Copy, Debug)]
pub struct AngleSystem<'a, T: Real, const D: usize> {
    base: SpringSystem<'a, T>,
    points: &'a [[T; D]],
    epsilon: T,
}

/// Solution method for the angle-inclusion springs ([`solve_angle`](crate::spring::AngleSystem::solve_angle)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum AngleMethod {
    /// Direct method (Yang & Özgen §2.2.1): each node's 2×2/3×3 system solved by Cramer's rule,
    /// in place, in node order (Gauss–Seidel). Converges: the operator is symmetric positive
    /// definite.
    DirectGaussSeidel,
    /// Direct method in Jacobi order (every node from the previous field). Block Jacobi is
    /// *not* guaranteed to converge on this operator; non-convergence is reported.
    DirectJacobi,
    /// Indirect method (§2.2.2): conjugate gradients on the assembled block operator
    /// (`q_a = −K_aa⁻¹ K_ab q_b`, eq. 4), matrix-free, with the node blocks as preconditioner.
    /// [`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg) is the same CG with a multigrid preconditioner (far fewer
    /// iterations on large meshes).
    Cg,
}

/// Entry `(i, j)` of a `D×D` array (0 outside).
#[inline]
fn at<T: Real, const D: usize>(m: &[[T; D]; D], i: usize, j: usize) -> T {
    m.get(i)
        .and_then(|row| row.get(j))
        .copied()
        .unwrap_or(T::ZERO)
}

/// Solves the symmetric `D×D` system `m x = r` by Cramer's rule (cofactors), or `None` when its
/// normalised determinant `det / (tr/D)^D` is at most `√ε`.
pub(super) fn cramer<T: Real, const D: usize>(m: &[[T; D]; D], r: &[T; D]) -> Option<[T; D]> {
    let g = |i, j| at(m, i, j);
    let rv = |i: usize| r.get(i).copied().unwrap_or(T::ZERO);
    let tol = T::EPSILON.sqrt();
    let mut out = [T::ZERO; D];
    if D == 2 {
        let (a, b, c) = (g(0, 0), g(0, 1), g(1, 1));
        let det = a * c - b * b;
        let t = (a + c) * T::HALF;
        if det <= tol * t * t || !det.is_finite() {
            return None;
        }
        let x = [(rv(0) * c - b * rv(1)) / det, (a * rv(1) - b * rv(0)) / det];
        for (o, v) in out.iter_mut().zip(x) {
            *o = v;
        }
        Some(out)
    } else if D == 3 {
        let (m00, m01, m02) = (g(0, 0), g(0, 1), g(0, 2));
        let (m11, m12, m22) = (g(1, 1), g(1, 2), g(2, 2));
        let c00 = m11 * m22 - m12 * m12;
        let c01 = m02 * m12 - m01 * m22;
        let c02 = m01 * m12 - m02 * m11;
        let c11 = m00 * m22 - m02 * m02;
        let c12 = m01 * m02 - m00 * m12;
        let c22 = m00 * m11 - m01 * m01;
        let det = m00 * c00 + m01 * c01 + m02 * c02;
        let t = (m00 + m11 + m22) / T::from_f64(3.0);
        if det <= tol * t * t * t || !det.is_finite() {
            return None;
        }
        let (r0, r1, r2) = (rv(0), rv(1), rv(2));
        let x = [
            (c00 * r0 + c01 * r1 + c02 * r2) / det,
            (c01 * r0 + c11 * r1 + c12 * r2) / det,
            (c02 * r0 + c12 * r1 + c22 * r2) / det,
        ];
        for (o, v) in out.iter_mut().zip(x) {
            *o = v;
        }
        Some(out)
    } else {
        None
    }
}

impl<'a, T: Real, const D: usize> AngleSystem<'a, T, D> {
    /// Validates the coordinates and `epsilon` against `base` and checks every free node's
    /// block (see the [`AngleSystem`] documentation).
    ///
    /// # Errors
    /// `points.len() != node_count` ([`Error::LengthMismatch`]); a non-finite coordinate
    /// ([`Error::NonFinite`]); `epsilon` not finite or negative ([`Error::InvalidParameter`]);
    /// a zero-length edge ([`Error::ZeroLengthEdge`]); a free node whose block is singular
    /// ([`Error::SingularNode`], colinear edges in 2D, coplanar in 3D).
    pub fn new(base: SpringSystem<'a, T>, points: &'a [[T; D]], epsilon: T) -> Result<Self> {
        crate::check::mesh_dim::<D>();
        check_values("points", points, base.node_count())?;
        if !(epsilon.is_finite() && epsilon >= T::ZERO) {
            return Err(Error::InvalidParameter {
                arg: "epsilon",
                reason: "must be finite and >= 0",
            });
        }
        let sys = AngleSystem {
            base,
            points,
            epsilon,
        };
        for i in 0..base.node_count() {
            for (j, _) in base.row(i) {
                if sys.direction(i, j).is_none() {
                    return Err(Error::ZeroLengthEdge { from: i, to: j });
                }
            }
        }
        for i in 0..base.node_count() {
            if !base.is_fixed(i) && cramer(&sys.node_block(i), &[T::ZERO; D]).is_none() {
                return Err(Error::SingularNode { node: i });
            }
        }
        Ok(sys)
    }

    /// The underlying linear-spring system (graph, stiffness, fixed mask).
    #[inline]
    pub fn base(&self) -> &SpringSystem<'a, T> {
        &self.base
    }

    /// The coordinates that define the edge directions.
    #[inline]
    pub fn points(&self) -> &'a [[T; D]] {
        self.points
    }

    /// The regularisation `ε`.
    #[inline]
    pub fn epsilon(&self) -> T {
        self.epsilon
    }

    /// `d = r_j − r_i` and `|d|²`, or `None` for a zero-length (or overflowing) edge.
    #[inline]
    pub(crate) fn direction(&self, i: usize, j: usize) -> Option<([T; D], T)> {
        let d = vector::sub(*self.points.get(j)?, *self.points.get(i)?);
        let d2 = vector::norm_sq(d);
        (d2 > T::ZERO && d2.is_finite()).then_some((d, d2))
    }

    /// `B v = k (d (d·v) / |d|² + ε v)` for one edge.
    #[inline]
    pub(crate) fn edge_apply(&self, k: T, d: &[T; D], d2: T, v: &[T; D]) -> [T; D] {
        let s = k * vector::dot(*d, *v) / d2;
        let ke = k * self.epsilon;
        let mut out = [T::ZERO; D];
        for ((o, &dc), &vc) in out.iter_mut().zip(d).zip(v) {
            *o = s * dc + ke * vc;
        }
        out
    }

    /// Node `i`'s block `A_ii = Σ_j B_ij`, summed in CSR order.
    pub(super) fn node_block(&self, i: usize) -> [[T; D]; D] {
        let mut m = [[T::ZERO; D]; D];
        for (j, k) in self.base.row(i) {
            let Some((d, d2)) = self.direction(i, j) else {
                continue;
            };
            let s = k / d2;
            let ke = k * self.epsilon;
            for (r, (row, &dr)) in m.iter_mut().zip(&d).enumerate() {
                for (c, (e, &dc)) in row.iter_mut().zip(&d).enumerate() {
                    *e += s * dr * dc;
                    if r == c {
                        *e += ke;
                    }
                }
            }
        }
        m
    }

    /// Node `i`'s residual `Σ_j B_ij (x_j − x_i)` and block `A_ii`, in one pass over the row
    /// (both summed in CSR order, exactly as [`Self::node_block`] sums the block).
    pub(super) fn node_residual(
        &self,
        i: usize,
        xi: [T; D],
        x: &[[T; D]],
    ) -> ([T; D], [[T; D]; D]) {
        let mut r = [T::ZERO; D];
        let mut m = [[T::ZERO; D]; D];
        for (j, k) in self.base.row(i) {
            let Some((d, d2)) = self.direction(i, j) else {
                continue;
            };
            let xj = x.get(j).copied().unwrap_or(xi);
            let f = self.edge_apply(k, &d, d2, &vector::sub(xj, xi));
            r = vector::add(r, f);
            let s = k / d2;
            let ke = k * self.epsilon;
            for (row_i, (row, &dr)) in m.iter_mut().zip(&d).enumerate() {
                for (col, (e, &dc)) in row.iter_mut().zip(&d).enumerate() {
                    *e += s * dr * dc;
                    if row_i == col {
                        *e += ke;
                    }
                }
            }
        }
        (r, m)
    }

    /// Calls `f(r_i, b_i)` for every free node of `rows` in node order: the residual
    /// `r_i = Σ_j B_ij (x_j − x_i)` and the fixed nodes' pull `b_i = Σ_{j fixed} B_ij x_j`.
    fn for_each_free_residual<F: FnMut(&[T; D], &[T; D])>(
        &self,
        rows: &[Range<usize>],
        x: &[[T; D]],
        mut f: F,
    ) {
        for i in rows.iter().flat_map(|r| r.clone()) {
            let Some(&xi) = x.get(i) else { continue };
            if self.base.is_fixed(i) {
                continue;
            }
            let mut r = [T::ZERO; D];
            let mut b = [T::ZERO; D];
            for (j, k) in self.base.row(i) {
                let Some((d, d2)) = self.direction(i, j) else {
                    continue;
                };
                let xj = x.get(j).copied().unwrap_or(xi);
                r = vector::add(r, self.edge_apply(k, &d, d2, &vector::sub(xj, xi)));
                if self.base.is_fixed(j) {
                    b = vector::add(b, self.edge_apply(k, &d, d2, &xj));
                }
            }
            f(&r, &b);
        }
    }

    /// `(‖b − A x‖₂, ‖b‖₂)` over the free nodes, `b_i = Σ_{j fixed} B_ij x_j`, without
    /// overflow or underflow (see [`super::norms`]; each node's `|v|²` one term).
    fn residual_norms(&self, x: &[[T; D]]) -> (Norm<T>, Norm<T>) {
        self.norms(x, &[0; D], &Serial::new(self.base.node_count()))
    }

    /// Jacobi-order sweep without validation.
    fn jacobi_core(
        &self,
        nodes: Range<usize>,
        input: &[[T; D]],
        output: &mut [[T; D]],
        sigma: T,
    ) -> Sweep<T> {
        let fixed = |i| self.base.is_fixed(i);
        jacobi_order(fixed, nodes, input, output, sigma, |i, xi, x| {
            let (r, m) = self.node_residual(i, xi, x);
            (cramer(&m, &r).unwrap_or([T::ZERO; D]), r)
        })
    }

    /// Gauss–Seidel-order sweep without validation, over-relaxed by `omega` (1 = plain
    /// Gauss–Seidel: `1 · δ` is `δ`, so those bits do not depend on the factor).
    fn gauss_seidel_core(
        &self,
        nodes: Range<usize>,
        values: &mut [[T; D]],
        omega: T,
        sigma: T,
    ) -> Sweep<T> {
        let fixed = |i| self.base.is_fixed(i);
        gauss_seidel_order(fixed, nodes, values, sigma, |i, xi, x| {
            let (r, m) = self.node_residual(i, xi, x);
            let dx = cramer(&m, &r).unwrap_or([T::ZERO; D]);
            (vector::scale(dx, omega), r)
        })
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// One Jacobi-order sweep of the angle-inclusion direct method over `nodes`: each free node
    /// solves its own 2×2/3×3 system (Yang & Özgen §2.2.1, Cramer's rule) with its neighbours
    /// read from `input`, `output[i] = x_i + A_ii⁻¹ Σ_j B_ij (x_j − x_i)`. Fixed nodes in the range
    /// are copied; `output` outside the range is untouched. Returns the range's maximum change and
    /// the residual of `input` there.
    ///
    /// # Errors
    /// Nothing is written on error: wrong lengths, non-finite `input`, `nodes.end > node_count`.
    pub fn angle_jacobi_sweep(
        &self,
        nodes: Range<usize>,
        input: &[[T; D]],
        output: &mut [[T; D]],
    ) -> Result<Sweep<T>> {
        let n = self.base.node_count();
        check_values("input", input, n)?;
        check::len("output", output.len(), n)?;
        self.base.check_range(&nodes)?;
        Ok(self.jacobi_core(nodes, input, output, T::ONE))
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// One in-place Gauss–Seidel-order sweep of the angle-inclusion direct method over `nodes`
    /// (Yang & Özgen §2.2.1): like [`angle_jacobi_sweep`](crate::spring::AngleSystem::angle_jacobi_sweep) but each node uses its neighbours'
    /// newest values. Returns the range's maximum change and residual estimate.
    ///
    /// # Errors
    /// Nothing is written on error: wrong length, non-finite `values`, `nodes.end > node_count`.
    pub fn angle_gauss_seidel_sweep(
        &self,
        nodes: Range<usize>,
        values: &mut [[T; D]],
    ) -> Result<Sweep<T>> {
        check_values("values", values, self.base.node_count())?;
        self.base.check_range(&nodes)?;
        Ok(self.gauss_seidel_core(nodes, values, T::ONE, T::ONE))
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Number of `[T; D]` scratch items [`solve_angle`](crate::spring::AngleSystem::solve_angle) needs: `n` for [`AngleMethod::DirectJacobi`]
    /// (second field), 0 for [`AngleMethod::DirectGaussSeidel`], `4 n` for [`AngleMethod::Cg`];
    /// at least `4 n` whenever `ε = 0` (the rigidity probe, [`angle_probe_scratch_len`](crate::spring::AngleSystem::angle_probe_scratch_len)).
    pub fn angle_scratch_len(&self, method: AngleMethod) -> usize {
        let n = self.base.node_count();
        angle_scratch_items(n, method, self.epsilon == T::ZERO).unwrap_or(usize::MAX)
    }

    /// `scratch` of at least `needed` items, then (for `ε = 0`) the unconstrained rigidity
    /// probe in it: a rigid unconstrained system stays rigid when nodes are restricted further.
    pub(crate) fn probe_rigidity(
        &self,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
        needed: usize,
    ) -> Result<()> {
        check::buffer("scratch", scratch.len(), needed)?;
        if self.epsilon() == T::ZERO {
            let s = self.angle_rigidity_probe(options, scratch)?;
            if s > T::from_f64(MAX_AMPLIFICATION) {
                return Err(Error::SingularSystem { iteration: 0 });
            }
        }
        Ok(())
    }

    /// `solve` scratch items, raised to the rigidity probe's when `ε = 0` (it runs first, in
    /// the same scratch).
    pub(super) fn with_probe(&self, solve: usize) -> usize {
        let n = self.base.node_count();
        with_probe_items(Some(solve), n, self.epsilon == T::ZERO).unwrap_or(usize::MAX)
    }
}

/// The angle springs' residual pairs ([`Pairs`]) of a field over some rows.
struct AnglePairs<'s, 'a, 'x, T: Real, const D: usize> {
    sys: &'s AngleSystem<'a, T, D>,
    rows: &'s [Range<usize>],
    x: &'x [[T; D]],
}

impl<T: Real, const D: usize> Pairs<T, D> for AnglePairs<'_, '_, '_, T, D> {
    fn each<F: FnMut(&[T; D], &[T; D])>(&self, f: F) {
        self.sys.for_each_free_residual(self.rows, self.x, f);
    }
}

/// The assembled block operator for [`pcg`]: one lane (the edge blocks couple the
/// components).
impl<T: Real, const D: usize> Operator<T, D, 1> for AngleSystem<'_, T, D> {
    #[inline]
    fn residual(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        if self.base.is_fixed(i) {
            return [T::ZERO; D];
        }
        let xi = x.get(i).copied().unwrap_or([T::ZERO; D]);
        self.node_residual(i, xi, x).0
    }

    /// `q = A p` with `pᵀq` and the curvature scale `max_i pᵢᵀ Aᵢᵢ pᵢ`.
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; D]],
        q: &mut [[T; D]],
        pq: &mut [ExactSum; 1],
        dpp: &mut [T; 1],
    ) {
        apply_block_rows(rows, p, q, pq, dpp, |i, pi| {
            if self.base.is_fixed(i) {
                return None;
            }
            let mut acc = [T::ZERO; D];
            let mut diag = [T::ZERO; D];
            for (j, k) in self.base.row(i) {
                let Some((d, d2)) = self.direction(i, j) else {
                    continue;
                };
                let pj = p.get(j).copied().unwrap_or([T::ZERO; D]);
                acc = vector::add(acc, self.edge_apply(k, &d, d2, &vector::sub(pi, pj)));
                diag = vector::add(diag, self.edge_apply(k, &d, d2, &pi));
            }
            Some((acc, vector::dot(pi, diag)))
        });
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; D]],
        exps: &[i32; D],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        let pairs = AnglePairs {
            sys: self,
            rows: comm.owned(),
            x,
        };
        scaled_pair_norms(&pairs, exps, true, comm)
    }
}

/// Block Jacobi, `z_i = A_ii⁻¹ r_i` by Cramer's rule (zero on fixed nodes).
impl<T: Real, const D: usize> NodeSolve<T, D> for AngleSystem<'_, T, D> {
    #[inline]
    fn node_solve(&self, i: usize, r: [T; D]) -> [T; D] {
        if self.base.is_fixed(i) {
            [T::ZERO; D]
        } else {
            cramer(&self.node_block(i), &r).unwrap_or([T::ZERO; D])
        }
    }
}

/// `[T; D]` scratch items [`solve_angle`](crate::spring::AngleSystem::solve_angle) needs
/// for `node_count` nodes with `method` (`n` for [`AngleMethod::DirectJacobi`], 0 for
/// [`AngleMethod::DirectGaussSeidel`], the four CG vectors `4 n` for [`AngleMethod::Cg`]),
/// raised to the rigidity probe's `4 n` when `rigidity_probe` (`ε = 0`); `None` when the
/// count overflows. The formula of
/// [`angle_scratch_len`](crate::spring::AngleSystem::angle_scratch_len), for callers without
/// a system (a size query).
pub const fn angle_scratch_items(
    node_count: usize,
    method: AngleMethod,
    rigidity_probe: bool,
) -> Option<usize> {
    let solve = match method {
        AngleMethod::DirectJacobi => Some(node_count),
        AngleMethod::DirectGaussSeidel => Some(0),
        AngleMethod::Cg => cg_len(node_count),
    };
    with_probe_items(solve, node_count, rigidity_probe)
}

/// `[T; D]` scratch items
/// [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding) needs: `n` more
/// than the method itself (see [`angle_scratch_items`]), then raised to the rigidity probe's
/// `4 n` when `rigidity_probe`; `None` on overflow. The formula of
/// [`solve_angle_sliding_scratch_len`](crate::spring::AngleSystem::solve_angle_sliding_scratch_len).
pub const fn angle_sliding_scratch_items(
    node_count: usize,
    method: AngleMethod,
    rigidity_probe: bool,
) -> Option<usize> {
    let solve = match angle_scratch_items(node_count, method, false) {
        Some(s) => s.checked_add(node_count),
        None => None,
    };
    with_probe_items(solve, node_count, rigidity_probe)
}

/// `solve` raised to the rigidity probe's CG vectors when `probe`.
const fn with_probe_items(solve: Option<usize>, n: usize, probe: bool) -> Option<usize> {
    match (solve, probe) {
        (Some(s), false) => Some(s),
        (Some(s), true) => match cg_len(n) {
            Some(p) if p > s => Some(p),
            Some(_) => Some(s),
            None => None,
        },
        (None, _) => None,
    }
}

/// Deterministic pseudo-random number in `[-1, 1)` for probe entry `i` (SplitMix64).
fn probe_value<T: Real>(i: u64) -> T {
    let mut z = i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    T::from_f64((z >> 11) as f64 / (1u64 << 52) as f64 - 1.0)
}

/// The rigidity probe's problem `A y = ρ` for [`pcg`]: the block operator with the
/// pseudo-random right-hand side `ρ` on the free nodes (zero at fixed ones), generated on the
/// fly.
struct Probe<'s, 'a, T: Real, const D: usize>(&'s AngleSystem<'a, T, D>);

impl<T: Real, const D: usize> Probe<'_, '_, T, D> {
    /// `ρ_i` (zero at a fixed node).
    fn rho(&self, i: usize) -> [T; D] {
        let mut r = [T::ZERO; D];
        if !self.0.base.is_fixed(i) {
            for (c, rc) in r.iter_mut().enumerate() {
                *rc = probe_value((i as u64).wrapping_mul(D as u64).wrapping_add(c as u64));
            }
        }
        r
    }
}

impl<T: Real, const D: usize> Operator<T, D, 1> for Probe<'_, '_, T, D> {
    #[inline]
    fn residual(&self, i: usize, y: &[[T; D]]) -> [T; D] {
        vector::add(self.rho(i), self.0.residual(i, y))
    }
    #[inline]
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; D]],
        q: &mut [[T; D]],
        pq: &mut [ExactSum; 1],
        dpp: &mut [T; 1],
    ) {
        self.0.apply(rows, p, q, pq, dpp);
    }
    fn norms<C: Collective<T> + ?Sized>(
        &self,
        y: &[[T; D]],
        _: &[i32; D],
        comm: &C,
    ) -> (Norm<T>, Norm<T>) {
        pair_norms(&ProbePairs { probe: self, y }, &[T::ONE; D], false, comm)
    }
}

/// The probe's `(ρ − A y, ρ)` pairs of the free nodes (serial).
struct ProbePairs<'p, 's, 'a, 'y, T: Real, const D: usize> {
    probe: &'p Probe<'s, 'a, T, D>,
    y: &'y [[T; D]],
}

impl<T: Real, const D: usize> Pairs<T, D> for ProbePairs<'_, '_, '_, '_, T, D> {
    fn each<F: FnMut(&[T; D], &[T; D])>(&self, mut f: F) {
        for i in 0..self.probe.0.base.node_count() {
            if !self.probe.0.base.is_fixed(i) {
                f(&self.probe.residual(i, self.y), &self.probe.rho(i));
            }
        }
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Number of `[T; D]` scratch items [`angle_rigidity_probe`](crate::spring::AngleSystem::angle_rigidity_probe) needs: `4 n`.
    pub fn angle_probe_scratch_len(&self) -> usize {
        cg_len(self.base.node_count()).unwrap_or(usize::MAX)
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// The rigidity probe (see the [`AngleSystem`] documentation): solves `A y = ρ` for a
    /// deterministic pseudo-random `ρ` on the free nodes by block-Jacobi CG and returns the
    /// *amplification* `s = √(yᵀ M y / ρᵀ M⁻¹ ρ)`, `M` = the node blocks. `s` lies between
    /// `1/λ_max` and `1/λ_min` of the block-scaled operator and is close to `1/λ_min` when the
    /// system is nearly singular (a random `ρ` excites every mode, so `s² ≈ mean(1/λ_i²)`): a
    /// condition estimate that needs no eigenvalue solver. Measured with `ε = 0`: 60–150 on the
    /// NACA 2412 triangle meshes and on the hybrid mesh with quad diagonals (9k–20k nodes);
    /// 5.4e13 on the hybrid mesh whose quad boundary layer has no diagonals (a near-mechanism,
    /// whose converged "solution" had cells blown up by a factor 1e9).
    ///
    /// [`solve_angle`](crate::spring::AngleSystem::solve_angle) runs it when `ε = 0` and rejects `s > `[`MAX_AMPLIFICATION`]. It is public
    /// so callers can check a system once and reuse it.
    ///
    /// # Errors
    /// `scratch` shorter than [`angle_probe_scratch_len`](crate::spring::AngleSystem::angle_probe_scratch_len); [`Error::SingularSystem`] when
    /// CG meets non-positive curvature or does not reach a relative residual of
    /// `max(1e-6, 100 ε_mach)` within `max(options.max_iterations, 100)` iterations.
    pub fn angle_rigidity_probe(
        &self,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<T> {
        let n = self.base.node_count();
        let needed = self.angle_probe_scratch_len();
        check::buffer("scratch", scratch.len(), needed)?;
        options.check()?;
        let Some((mut v, _)) = Vectors::split(scratch, n) else {
            return Ok(T::ZERO); // unreachable: the length was checked
        };
        let probe = Probe(self);
        let blocks = NodeBlocks(self);
        // ‖ρ‖² and ρᵀ M⁻¹ ρ.
        let mut bb = ExactSum::new();
        let mut rmr = ExactSum::new();
        for i in 0..n {
            let rho = probe.rho(i);
            for &r in &rho {
                bb.add(r * r);
            }
            rmr.add(vector::dot(rho, blocks.node(i, rho)));
        }
        let bb: T = bb.value();
        if bb == T::ZERO {
            return Ok(T::ZERO); // no free node
        }
        let rho_m_rho: T = rmr.value();
        for y in v.x.iter_mut() {
            *y = [T::ZERO; D];
        }
        let tol = T::from_f64(1e-6).max(T::from_f64(100.0) * T::EPSILON);
        let probe_options = SolveOptions {
            max_iterations: options.max_iterations.max(100),
            residual_tol: tol,
            update_tol: T::ZERO,
        };
        let serial = Serial::new(n);
        let mut blocks = blocks;
        let report = pcg(
            &probe,
            &mut blocks,
            &mut v,
            &[0; D],
            &probe_options,
            &serial,
        )?;
        let it = report.iterations;
        if !report.converged {
            return Err(Error::SingularSystem { iteration: it });
        }
        let y: &[[T; D]] = v.x;
        let mut ymy = ExactSum::new();
        for (i, yi) in y.iter().enumerate() {
            if !self.base.is_fixed(i) {
                let m = self.node_block(i);
                for (row, &a) in m.iter().zip(yi) {
                    ymy.add(a * vector::dot(*row, *yi));
                }
            }
        }
        let ymy: T = ymy.value();
        let s = (ymy / rho_m_rho).sqrt();
        if s.is_finite() {
            Ok(s)
        } else {
            Err(Error::SingularSystem { iteration: it })
        }
    }
}

/// The angle springs' direct method as [`drive_sweeps`] runs it: node-wise Cramer solves in
/// Jacobi order (`values` and `other` alternating) or Gauss–Seidel order, over-relaxed by
/// `omega`.
struct DirectSweeps<'s, 'a, 'v, T: Real, const D: usize> {
    sys: &'s AngleSystem<'a, T, D>,
    values: &'v mut [[T; D]],
    other: &'v mut [[T; D]],
    jacobi: bool,
    omega: T,
    in_other: bool,
}

impl<T: Real, const D: usize> Sweeps<T> for DirectSweeps<'_, '_, '_, T, D> {
    fn sweep(&mut self, sigma: T) -> Sweep<T> {
        let n = self.sys.base.node_count();
        if !self.jacobi {
            return self
                .sys
                .gauss_seidel_core(0..n, self.values, self.omega, sigma);
        }
        let stats = if self.in_other {
            self.sys.jacobi_core(0..n, self.other, self.values, sigma)
        } else {
            self.sys.jacobi_core(0..n, self.values, self.other, sigma)
        };
        self.in_other = !self.in_other;
        stats
    }
    fn residual(&mut self) -> Norm<T> {
        let current: &[[T; D]] = if self.in_other {
            self.other
        } else {
            self.values
        };
        self.sys.residual_norms(current).0
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Solves the angle-inclusion springs for the free nodes' displacements:
    /// `Σ_j B_ij (x_j − x_i) = 0` (Yang & Özgen eq. 3 = 0, eq. 4 `K_aa q_a = −K_ab q_b`).
    /// `values` holds the prescribed displacements at fixed nodes and the initial guess at free
    /// nodes; on `Ok` it holds the last iterate and the report says whether it converged. The
    /// residual is the block operator's, relative to `‖b‖` as in [`SolveOptions`]. When
    /// `ε = 0` the rigidity probe runs first (see the [`AngleSystem`] documentation).
    ///
    /// # Errors
    /// `values` is untouched on error: wrong length or non-finite values, bad options, `scratch`
    /// shorter than [`angle_scratch_len`](crate::spring::AngleSystem::angle_scratch_len), [`Error::SingularSystem`] from the probe (`iteration`
    /// = the probe's CG iteration, or 0 when the probe converged but its amplification exceeded
    /// [`MAX_AMPLIFICATION`]) or from CG (non-positive curvature); [`Error::Overflow`] when
    /// stiffness and values together exceed the range (direct methods: `max_i Σ_j k_ij (1 + ε) ·
    /// 4 max |x|` overflows, `arg` = `"stiffness"`; CG: an inner product overflows even after
    /// power-of-two rescaling, `"values"`). Residuals use scaled norms and CG a rescaled copy, so
    /// the result at `2^k ·` values is exactly `2^k ·` the result (while no value is subnormal).
    pub fn solve_angle(
        &self,
        values: &mut [[T; D]],
        method: AngleMethod,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        solve_angle_core(self, values, method, T::ONE, options, scratch)
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// The direct method with over-relaxation (block SOR, in node order): each free node moves by
    /// `ω` times its own 2×2/3×3 correction, `x_i ← x_i + ω A_ii⁻¹ Σ_j B_ij (x_j − x_i)`. For the
    /// symmetric positive definite operator every `0 < ω < 2` converges; `ω = 1` is
    /// [`AngleMethod::DirectGaussSeidel`] bit for bit. Plain Gauss–Seidel needs `O(h⁻²)` sweeps on
    /// a fine mesh (it hits any practical cap on 10⁴-node airfoil meshes); a good `ω` near 2 cuts
    /// that to `O(h⁻¹)`. Everything else (residual, probe when `ε = 0`, report, errors) is as in
    /// [`solve_angle`](crate::spring::AngleSystem::solve_angle); `scratch` needs [`angle_scratch_len`](crate::spring::AngleSystem::angle_scratch_len) for
    /// [`AngleMethod::DirectGaussSeidel`] (none unless `ε = 0`).
    ///
    /// # Errors
    /// Those of [`solve_angle`](crate::spring::AngleSystem::solve_angle), and `omega` outside `(0, 2)` ([`Error::InvalidParameter`]).
    pub fn solve_angle_sor(
        &self,
        values: &mut [[T; D]],
        omega: T,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        check_omega(omega)?;
        solve_angle_core(
            self,
            values,
            AngleMethod::DirectGaussSeidel,
            omega,
            options,
            scratch,
        )
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// One in-place over-relaxed sweep of the direct method over `nodes` (see
    /// [`solve_angle_sor`](crate::spring::AngleSystem::solve_angle_sor)): [`angle_gauss_seidel_sweep`](crate::spring::AngleSystem::angle_gauss_seidel_sweep) with every correction scaled by `omega`.
    /// Returns the range's maximum change and residual estimate.
    ///
    /// # Errors
    /// Nothing is written on error: wrong length, non-finite `values`, `nodes.end > node_count`,
    /// `omega` outside `(0, 2)`.
    pub fn angle_sor_sweep(
        &self,
        nodes: Range<usize>,
        values: &mut [[T; D]],
        omega: T,
    ) -> Result<Sweep<T>> {
        check_values("values", values, self.base.node_count())?;
        self.base.check_range(&nodes)?;
        check_omega(omega)?;
        Ok(self.gauss_seidel_core(nodes, values, omega, T::ONE))
    }
}

/// The checks every angle solve makes before touching `values` (length and finiteness,
/// options, `scratch` of at least `needed` items, the rigidity probe when `ε = 0`), then the
/// initial residual: the report of the initial guess, its residual norm and `‖b‖`.
fn start_solve<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    values: &[[T; D]],
    options: &SolveOptions<T>,
    scratch: &mut [[T; D]],
    needed: usize,
) -> Result<(SolveReport<T>, Norm<T>, Norm<T>)> {
    check_values("values", values, sys.base.node_count())?;
    options.check()?;
    sys.probe_rigidity(options, scratch, needed)?;
    let (r0, bnorm) = sys.residual_norms(values);
    Ok((SolveReport::start(r0, bnorm, options), r0, bnorm))
}

/// [`solve_angle`](crate::spring::AngleSystem::solve_angle) with the over-relaxation factor of the Gauss–Seidel-order direct method
/// (1 for the other methods).
fn solve_angle_core<T: Real, const D: usize>(
    sys: &AngleSystem<'_, T, D>,
    values: &mut [[T; D]],
    method: AngleMethod,
    omega: T,
    options: &SolveOptions<T>,
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.base.node_count();
    let needed = sys.angle_scratch_len(method);
    let (report, r0, bnorm) = start_solve(sys, values, options, scratch, needed)?;
    if method != AngleMethod::Cg {
        // The direct sweeps form `Σ_j B_ij (x_j − x_i)` unscaled (|B_ij v| ≤ (1 + ε) k |v|).
        let vmax = values
            .iter()
            .flatten()
            .fold(T::ZERO, |m, &v| m.max(v.abs()));
        let dmax = (0..n).fold(T::ZERO, |m, i| {
            m.max(sys.base.row(i).fold(T::ZERO, |d, (_, k)| d + k))
        });
        let four = T::TWO * T::TWO;
        if !(dmax * (T::ONE + sys.epsilon) * (four * vmax)).is_finite() {
            return Err(Error::Overflow { arg: "stiffness" });
        }
    }
    if report.converged {
        return Ok(report);
    }
    match method {
        AngleMethod::DirectGaussSeidel | AngleMethod::DirectJacobi => {
            let other = scratch.get_mut(..n).unwrap_or(&mut []);
            let mut direct = DirectSweeps {
                sys,
                values,
                other,
                jacobi: method == AngleMethod::DirectJacobi,
                omega,
                in_other: false,
            };
            let report = drive_sweeps(&mut direct, r0, bnorm, 0, options);
            if direct.in_other {
                for (v, o) in direct.values.iter_mut().zip(direct.other.iter()) {
                    *v = *o;
                }
            }
            Ok(report)
        }
        AngleMethod::Cg => {
            let (v, _) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
                arg: "scratch",
                needed,
                actual: 0,
            })?;
            cg_solve(sys, &mut NodeBlocks(sys), v, values, options)
        }
    }
}

/// The preconditioned CG of the angle solves ([`pcg`] with the block operator) on a
/// power-of-two-scaled copy of `values` (one exponent: the edge blocks couple the
/// components), the free nodes written back on success.
fn cg_solve<T: Real, const D: usize, M: Precondition<T, D>>(
    sys: &AngleSystem<'_, T, D>,
    pre: &mut M,
    v: Vectors<'_, T, D>,
    values: &mut [[T; D]],
    options: &SolveOptions<T>,
) -> Result<SolveReport<T>> {
    let base = &sys.base;
    let exps = exponents(base.stiffness(), values, true);
    let serial = Serial::new(base.node_count());
    let fixed = |i| base.is_fixed(i);
    solve_scaled(sys, pre, v, values, exps, fixed, options, &serial)
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Number of `[T; D]` scratch items [`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg) needs with `hierarchy`: `5 n` for the
    /// CG vectors (iterate, residual, direction, `A p` / preconditioned residual, the V-cycle's
    /// fine temporary) plus three vectors per coarse level (`3 ×`
    /// [`AmgHierarchy::coarse_unknowns`]); this covers the rigidity probe's `4 n` when `ε = 0`.
    /// The same count as [`solve_linear_amg_scratch_len`](crate::spring::solve_linear_amg_scratch_len) for `V = D`.
    pub fn angle_amg_scratch_len(&self, hierarchy: &AmgHierarchy<'_, T>) -> usize {
        amg_cg_scratch_len(self.base.node_count(), hierarchy.coarse_unknowns())
            .unwrap_or(usize::MAX)
    }

    /// Solves the angle-inclusion springs (the problem of [`solve_angle`](crate::spring::AngleSystem::solve_angle)) by conjugate
    /// gradients preconditioned with one V-cycle of the *scalar* linear-spring multigrid
    /// hierarchy per iteration, applied to each displacement component (issue 14 item 8).
    /// `hierarchy` is an [`AmgHierarchy`] built on [`base`](crate::spring::AngleSystem::base) (the same graph, stiffness and
    /// fixed mask; the one [`solve_linear_amg`](crate::spring::SpringSystem::solve_linear_amg) uses). The V-cycle is symmetric positive
    /// definite, and for `ε > 0` the angle operator lies between `ε` and `1 + ε` times the
    /// linear-spring operator it approximates, so CG's iteration count is bounded independently
    /// of the mesh size up to the factor `(1 + ε)/ε`; measured 8–19× fewer iterations than
    /// block-Jacobi [`AngleMethod::Cg`] on NACA 2412 meshes of 6k–98k nodes (docs/amg.md).
    /// For `ε = 0` nothing bounds it, but it stays a valid SPD preconditioner (and the rigidity
    /// probe runs first, as in [`solve_angle`](crate::spring::AngleSystem::solve_angle)).
    ///
    /// Everything else is [`AngleMethod::Cg`]'s: the block operator and every residual come
    /// from `self` (the hierarchy only preconditions: one built for other stiffness values of
    /// the same graph slows convergence down but cannot change the answer), the iterate is
    /// scaled by a power of two, the true residual confirms convergence, fixed values come back
    /// bit for bit and a field that is already a solution (a uniform translation) is returned
    /// untouched after 0 iterations.
    ///
    /// # Errors
    /// `values` is untouched on error: a hierarchy built for a system of another size
    /// ([`Error::LengthMismatch`], `"hierarchy"`), wrong length or non-finite `values`, bad
    /// options, `scratch` shorter than [`angle_amg_scratch_len`](crate::spring::AngleSystem::angle_amg_scratch_len), and the rigidity
    /// probe's and CG's errors of [`solve_angle`](crate::spring::AngleSystem::solve_angle) ([`Error::SingularSystem`],
    /// [`Error::Overflow`]).
    pub fn solve_angle_amg(
        &self,
        hierarchy: &AmgHierarchy<'_, T>,
        values: &mut [[T; D]],
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        hierarchy.check_system(&self.base)?;
        let n = self.base.node_count();
        let needed = self.angle_amg_scratch_len(hierarchy);
        let (report, _, _) = start_solve(self, values, options, scratch, needed)?;
        if report.converged {
            return Ok(report);
        }
        let (v, rest) = Vectors::split(scratch, n).ok_or(Error::BufferTooSmall {
            arg: "scratch",
            needed,
            actual: 0,
        })?;
        cg_solve(
            self,
            &mut Vcycle::new(&self.base, hierarchy, rest),
            v,
            values,
            options,
        )
    }
}
