//! Spring solves with sliding nodes ([`Constraints`]): the linear and angle springs restricted
//! to each node's allowed motion.
//!
//! **Problem.** With `P` the block-diagonal projector (`P_i` = `I` free, `0` fixed,
//! `I − n nᵀ` on a plane, `t tᵀ` on a line) the displacements minimise the spring energy
//! `½ dᵀ K d` over `d_i ∈ range(P_i)` with the fixed nodes' values given, i.e. they solve
//!
//! `P K P d = P b`   (on `range(P)`),
//!
//! where `K` is the free-node operator (`k I` per linear edge, `B_ij` per angle edge) and `b`
//! the fixed nodes' pull. `P` couples the components, so the solve is joint over `D`
//! components (one `α`, `β` in CG instead of one per component). `P K P` is symmetric positive
//! definite on `range(P)` whenever `K` is (every free and sliding node anchored, as
//! [`SpringSystem::new`] checks): for `v ∈ range(P)`, `vᵀ P K P v = vᵀ K v > 0`.
//!
//! **Methods.**
//! - Stationary sweeps (Jacobi, Gauss–Seidel, SOR; the angle springs' direct method): node
//!   `i` solves its own projected block, `δ = (P A_ii P)⁺ P r_i`. For linear springs
//!   `A_ii = d_i I`, so `δ = P r_i / d_i`; for the angle springs `δ = P (P A P + s (I − P))⁻¹
//!   P r` with `s = tr A / D` (the added term only fills the null space, so `δ ∈ range(P)`).
//!   Block Gauss–Seidel/SOR converge for any SPD operator.
//! - CG: on `range(P)` with the preconditioner `z = P M⁻¹ r`, `M` any symmetric positive
//!   definite preconditioner of the unconstrained operator applied component-wise (Jacobi,
//!   SSOR, or the [`AmgHierarchy`] V-cycle of the scalar operator, built for the system with
//!   the sliding nodes free); `P M⁻¹ P` is SPD on `range(P)`, so CG's guarantees hold. The
//!   angle springs' CG uses the projected node blocks `(P A_ii P)⁺`, or the scalar V-cycle per
//!   component ([`solve_angle_sliding_amg`](crate::spring::AngleSystem::solve_angle_sliding_amg)).
//!
//! **Values** are displacements: prescribed at fixed nodes, an initial guess elsewhere (the
//! guess at sliding nodes is projected first). Every method runs on a power-of-two-scaled copy
//! (exact), writes back only on success, and projects every sliding node's result once more,
//! so `n · d` is at rounding level of `|d|`.

use core::ops::Range;

use super::amg::{amg_sliding_cg_scratch_len, AmgHierarchy, Vcycle};
use super::angle::{angle_sliding_scratch_items, cramer, AngleMethod, AngleSystem};
use super::distributed::{Collective, Serial};
use super::krylov::{
    apply_local, cg_len, exponents, pcg, solve_rhs, Operator, Precondition, RhsLayout, Vectors,
};
use super::linear::{
    diagonal, drive_sweeps, node_residual, solve_linear_scratch_len, OneLevel, Sweeps,
};
use super::norms::{pair_norms, scale_by, Norm, Pairs};
use super::solver::LinearSolver;
use super::system::{
    check_omega, check_values, LinearMethod, Preconditioner, SolveOptions, SolveReport,
    SpringSystem, Sweep,
};
use crate::check;
use crate::error::{Error, Result};
use crate::exact_sum::{ExactSum, Gather};
use crate::real::Real;
use crate::spring::constraints::{Constraints, NodeKind};
use crate::vector;

/// The operator a constrained solve needs: node residuals and blocks.
trait BlockOp<T: Real, const D: usize> {
    /// Number of nodes.
    fn n(&self) -> usize;
    /// `true` at fixed nodes.
    fn fixed(&self, i: usize) -> bool;
    /// `r_i = Σ_j B_ij (x_j − x_i)` and the block `A_ii = Σ_j B_ij`.
    fn node(&self, i: usize, x: &[[T; D]]) -> ([T; D], [[T; D]; D]);
    /// The fixed nodes' pull `b_i = Σ_{j fixed} B_ij x_j`.
    fn pull(&self, i: usize, x: &[[T; D]]) -> [T; D];
    /// `δ ∈ range(P_i)` with `P A P δ = pr` (`pr` already projected).
    fn block_solve(
        &self,
        c: &Constraints<'_, T, D>,
        i: usize,
        m: &[[T; D]; D],
        pr: [T; D],
    ) -> [T; D];
    /// The edge stiffness (its largest sets the scale of the scaled copy).
    fn stiffness(&self) -> &[T];
    /// Largest row sum `Σ_j k_ij (1 + ε)`: bounds every `|B v|` per unit `|v|`.
    fn row_max(&self) -> T;
}

/// Linear springs: `B_ij = k_ij I`.
struct LinearOp<'s, 'a, T: Real>(&'s SpringSystem<'a, T>);

impl<T: Real, const D: usize> BlockOp<T, D> for LinearOp<'_, '_, T> {
    fn n(&self) -> usize {
        self.0.node_count()
    }
    fn fixed(&self, i: usize) -> bool {
        self.0.is_fixed(i)
    }
    fn node(&self, i: usize, x: &[[T; D]]) -> ([T; D], [[T; D]; D]) {
        let xi = x.get(i).copied().unwrap_or([T::ZERO; D]);
        let (r, d) = node_residual(self.0, i, xi, x);
        let mut m = [[T::ZERO; D]; D];
        for (c, row) in m.iter_mut().enumerate() {
            if let Some(e) = row.get_mut(c) {
                *e = d;
            }
        }
        (r, m)
    }
    fn pull(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        let mut b = [T::ZERO; D];
        for (j, k) in self.0.row(i) {
            if self.0.is_fixed(j) {
                let xj = x.get(j).copied().unwrap_or([T::ZERO; D]);
                for (a, &v) in b.iter_mut().zip(&xj) {
                    *a += k * v;
                }
            }
        }
        b
    }
    fn block_solve(
        &self,
        _: &Constraints<'_, T, D>,
        _: usize,
        m: &[[T; D]; D],
        pr: [T; D],
    ) -> [T; D] {
        let d = m.first().and_then(|r| r.first()).copied().unwrap_or(T::ONE);
        pr.map(|v| v / d)
    }
    fn stiffness(&self) -> &[T] {
        self.0.stiffness()
    }
    fn row_max(&self) -> T {
        self.0.rows().fold(T::ZERO, |m, (_, _, row)| {
            m.max(row.fold(T::ZERO, |d, (_, k)| d + k))
        })
    }
}

/// Angle springs: `B_ij = k (e eᵀ + ε I)`.
struct AngleOp<'s, 'a, T: Real, const D: usize>(&'s AngleSystem<'a, T, D>);

impl<T: Real, const D: usize> BlockOp<T, D> for AngleOp<'_, '_, T, D> {
    fn n(&self) -> usize {
        self.0.base().node_count()
    }
    fn fixed(&self, i: usize) -> bool {
        self.0.base().is_fixed(i)
    }
    fn node(&self, i: usize, x: &[[T; D]]) -> ([T; D], [[T; D]; D]) {
        let xi = x.get(i).copied().unwrap_or([T::ZERO; D]);
        self.0.node_residual(i, xi, x)
    }
    fn pull(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        let mut b = [T::ZERO; D];
        for (j, k) in self.0.base().row(i) {
            if let (true, Some((d, d2))) = (self.0.base().is_fixed(j), self.0.direction(i, j)) {
                let xj = x.get(j).copied().unwrap_or([T::ZERO; D]);
                b = vector::add(b, self.0.edge_apply(k, &d, d2, &xj));
            }
        }
        b
    }
    fn block_solve(
        &self,
        c: &Constraints<'_, T, D>,
        i: usize,
        m: &[[T; D]; D],
        pr: [T; D],
    ) -> [T; D] {
        if c.kind(i) == NodeKind::Free {
            return cramer(m, &pr).unwrap_or([T::ZERO; D]);
        }
        // (P A P + s (I − P)) δ = P r, then δ ← P δ.
        let p = c.matrix(i);
        let mut tr = T::ZERO;
        for (k, row) in m.iter().enumerate() {
            tr += row.get(k).copied().unwrap_or(T::ZERO);
        }
        let s = tr / T::from_usize(D);
        let mut ap = [[T::ZERO; D]; D]; // A P
        for (row_ap, row_a) in ap.iter_mut().zip(m) {
            for (k, e) in row_ap.iter_mut().enumerate() {
                for (l, &a) in row_a.iter().enumerate() {
                    let plk = p.get(l).and_then(|r| r.get(k)).copied().unwrap_or(T::ZERO);
                    *e += a * plk;
                }
            }
        }
        let mut mm = [[T::ZERO; D]; D];
        for (r, row) in mm.iter_mut().enumerate() {
            for (k, e) in row.iter_mut().enumerate() {
                let mut acc = T::ZERO;
                for l in 0..D {
                    let prl = p.get(r).and_then(|x| x.get(l)).copied().unwrap_or(T::ZERO);
                    let aplk = ap.get(l).and_then(|x| x.get(k)).copied().unwrap_or(T::ZERO);
                    acc += prl * aplk;
                }
                let id = if r == k { T::ONE } else { T::ZERO };
                let prk = p.get(r).and_then(|x| x.get(k)).copied().unwrap_or(T::ZERO);
                *e = acc + s * (id - prk);
            }
        }
        c.project(i, cramer(&mm, &pr).unwrap_or([T::ZERO; D]))
    }
    fn stiffness(&self) -> &[T] {
        self.0.base().stiffness()
    }
    fn row_max(&self) -> T {
        let e1 = T::ONE + self.0.epsilon();
        self.0.base().rows().fold(T::ZERO, |m, (_, _, row)| {
            m.max(row.fold(T::ZERO, |d, (_, k)| d + k) * e1)
        })
    }
}

/// The preconditioner of a constrained CG.
#[derive(Clone, Copy)]
enum Pre<'h, T: Real> {
    /// A one-level preconditioner of the linear springs (component-wise).
    Linear(Preconditioner<T>),
    /// The multigrid V-cycle of the linear springs (component-wise).
    Amg(&'h AmgHierarchy<'h, T>),
    /// The projected node blocks `(P A_ii P)⁺` (angle springs).
    Blocks,
}

/// A constrained method.
#[derive(Clone, Copy)]
enum Method<'h, T: Real> {
    Jacobi,
    Sor(T),
    Cg(Pre<'h, T>),
}

/// Number of `[T; D]` scratch items [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) needs for `node_count` nodes:
/// `n` more than the unconstrained solve
/// ([`solve_linear_scratch_len`](crate::spring::solve_linear_scratch_len): `2 n` for Jacobi,
/// `n` for Gauss–Seidel/SOR, `6 n` for CG; with a multigrid hierarchy
/// [`amg_sliding_cg_scratch_len`](crate::spring::amg_sliding_cg_scratch_len), `6 n + 3 coarse`).
/// The stationary methods keep a scaled copy there; CG runs in the unconstrained CG's layout
/// (the copy is its iterate) and leaves the last `n` unused, kept so that sizes computed from
/// these counts (the C ABI's among them) stay exact.
pub fn solve_linear_sliding_scratch_len<T: Real>(
    solver: &LinearSolver<'_, T>,
    node_count: usize,
) -> usize {
    let n = node_count;
    match solver {
        LinearSolver::Method(m) => n.saturating_add(solve_linear_scratch_len(m, n)),
        LinearSolver::Amg(h) => {
            amg_sliding_cg_scratch_len(n, h.coarse_unknowns()).unwrap_or(usize::MAX)
        }
        LinearSolver::Distributed(..) | LinearSolver::DistributedAmg(..) => 0,
    }
}

impl<T: Real> SpringSystem<'_, T> {
    /// Solves the linear springs with sliding nodes ([`Constraints`]): the displacements that
    /// minimise the spring energy over each node's allowed motions, i.e. `P K P d = P b` on
    /// `range(P)` (`P_i` = `I` free, `0` fixed, `I − n nᵀ` plane, `t tᵀ` line), solved jointly
    /// over the components. It is symmetric positive definite whenever the unconstrained system
    /// is (`vᵀ P K P v = vᵀ K v` on `range(P)`), and a preconditioner `M` of the unconstrained
    /// operator (Jacobi, SSOR, one V-cycle of the scalar [`AmgHierarchy`] built for the system
    /// with the sliding nodes free) is applied as `P M⁻¹ P`, which keeps CG's guarantees.
    /// `values` are displacements, prescribed at the fixed nodes, the initial guess elsewhere.
    /// `sys` must be built with the mask [`Constraints::fixed_mask`] writes (sliding nodes are
    /// free in it). Any [`LinearSolver`] works: Jacobi/Gauss–Seidel/SOR project each node's
    /// update, CG (with its preconditioner, or the multigrid hierarchy) runs on the projected
    /// system. On `Ok` every sliding node's displacement lies in its plane or line to rounding,
    /// and the report's residual is `‖P(b − K d)‖ / ‖P b‖`.
    ///
    /// # Errors
    /// `values` is untouched on error:
    /// Wrong length or non-finite `values`; constraints of another length or whose fixed nodes
    /// differ from the system's mask ([`Error::InvalidParameter`] on `constraints`); bad options or
    /// `omega`; a hierarchy built for another system; `scratch` shorter than
    /// [`solve_linear_sliding_scratch_len`]; [`Error::SingularSystem`] when CG meets non-positive
    /// curvature; [`Error::Overflow`] when stiffness and values exceed the range.
    pub fn solve_linear_sliding<const D: usize>(
        &self,
        constraints: &Constraints<'_, T, D>,
        values: &mut [[T; D]],
        solver: LinearSolver<'_, T>,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let n = self.node_count();
        check_values("values", values, n)?;
        constraints.check_mask(self.fixed())?;
        options.check()?;
        let method = match solver {
            LinearSolver::Method(LinearMethod::Jacobi) => Method::Jacobi,
            LinearSolver::Method(LinearMethod::GaussSeidel) => Method::Sor(T::ONE),
            LinearSolver::Method(LinearMethod::Sor { omega }) => {
                check_omega(omega)?;
                Method::Sor(omega)
            }
            LinearSolver::Method(LinearMethod::Cg { preconditioner }) => {
                if let Preconditioner::Ssor { omega } = preconditioner {
                    check_omega(omega)?;
                }
                Method::Cg(Pre::Linear(preconditioner))
            }
            LinearSolver::Distributed(..) | LinearSolver::DistributedAmg(..) => {
                return Err(Error::InvalidParameter {
                    arg: "solver",
                    reason: "sliding solves are not split across processes yet",
                })
            }
            LinearSolver::Amg(h) => {
                h.check_system(self)?;
                Method::Cg(Pre::Amg(h))
            }
        };
        let needed = solve_linear_sliding_scratch_len(&solver, n);
        check::buffer("scratch", scratch.len(), needed)?;
        solve(
            &LinearOp(self),
            Some(self),
            constraints,
            values,
            method,
            options,
            scratch,
        )
    }
}

/// `P (D − K) P λ = f` on `range(P)` for the linear springs and an arbitrary right-hand side
/// `f` (`rhs`, already in `range(P)`, ignored at fixed nodes), from a zero initial guess, by
/// the projected CG of [`solve_linear_sliding`](SpringSystem::solve_linear_sliding) (one
/// lane, the same preconditioner `P M⁻¹ P`): the adjoint solves. `solver` must be CG or
/// multigrid (the caller checks it, `omega`, the hierarchy, sizes and finiteness); `rest`
/// holds the preconditioner's scratch (the diagonal, `⌈n / D⌉` items, or the V-cycle's). `λ`
/// (`out`) is zero at fixed nodes, projected once more at sliding ones, written only on `Ok`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_linear_sliding_rhs<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    c: &Constraints<'_, T, D>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    rhs: &[[T; D]],
    out: &mut [[T; D]],
    v: Vectors<'_, T, D>,
    rest: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = sys.node_count();
    let op = LinearOp(sys);
    let proj = Projected { op: &op, c };
    let layout = RhsLayout {
        kmax: sys.stiffness().iter().fold(T::ZERO, |m, &k| m.max(k)),
        joint: true,
        per_node: false,
    };
    let fixed = |i| sys.is_fixed(i);
    let serial = Serial::new(n);
    let report = match solver {
        LinearSolver::Amg(h) => {
            let inner = Vcycle::new(sys, h, rest);
            let mut m = ProjectedPre { op: &op, c, inner };
            solve_rhs(&proj, &mut m, v, rhs, out, layout, fixed, options, &serial)
        }
        LinearSolver::Method(LinearMethod::Cg { preconditioner }) => {
            let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
            diagonal(sys, diag);
            let diag: &[T] = diag;
            let inner = OneLevel {
                sys,
                diag,
                pre: preconditioner,
            };
            let mut m = ProjectedPre { op: &op, c, inner };
            solve_rhs(&proj, &mut m, v, rhs, out, layout, fixed, options, &serial)
        }
        _ => Err(Error::InvalidParameter {
            arg: "solver",
            reason: "the sliding adjoint needs CG (LinearMethod::Cg) or multigrid",
        }),
    }?;
    for (i, x) in out.iter_mut().enumerate() {
        *x = c.project(i, *x);
    }
    Ok(report)
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Number of `[T; D]` scratch items [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding) needs: `n` more than the
    /// unconstrained method itself (`2 n` for [`AngleMethod::DirectJacobi`], `n` for
    /// [`AngleMethod::DirectGaussSeidel`], `5 n` for [`AngleMethod::Cg`], of which CG leaves
    /// the last `n` unused); at least the rigidity probe's `4 n` when `ε = 0`.
    pub fn solve_angle_sliding_scratch_len(&self, method: AngleMethod) -> usize {
        let probe = self.epsilon() == T::ZERO;
        angle_sliding_scratch_items(self.base().node_count(), method, probe).unwrap_or(usize::MAX)
    }

    /// The checks every sliding angle solve starts with: `values`, the constraints against
    /// the system's mask, the options.
    fn check_sliding(
        &self,
        constraints: &Constraints<'_, T, D>,
        values: &[[T; D]],
        options: &SolveOptions<T>,
    ) -> Result<()> {
        check_values("values", values, self.base().node_count())?;
        constraints.check_mask(self.base().fixed())?;
        options.check()
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Solves the angle-inclusion springs with sliding nodes (the problem of
    /// [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) with the angle springs' edge blocks): the direct method solves
    /// each node's projected block `(P A P + s (I − P)) δ = P r`, `s = tr A / D` (in
    /// Gauss–Seidel order over-relaxed by `omega`, 1 = plain, or in Jacobi order), CG runs on the
    /// projected system with the projected node blocks as preconditioner. With `ε = 0` the
    /// unconstrained system's rigidity probe runs first (a rigid unconstrained system stays rigid
    /// when nodes are restricted further). Values, report and sliding guarantee as in
    /// [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding).
    ///
    /// # Errors
    /// `values` is untouched on error:
    /// Those of [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) and of [`solve_angle`](crate::spring::AngleSystem::solve_angle) (probe);
    /// `omega` outside `(0, 2)` for any method.
    pub fn solve_angle_sliding(
        &self,
        constraints: &Constraints<'_, T, D>,
        values: &mut [[T; D]],
        method: AngleMethod,
        omega: T,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        self.check_sliding(constraints, values, options)?;
        check_omega(omega)?;
        self.probe_rigidity(
            options,
            scratch,
            self.solve_angle_sliding_scratch_len(method),
        )?;
        let m = match method {
            AngleMethod::DirectGaussSeidel => Method::Sor(omega),
            AngleMethod::DirectJacobi => Method::Jacobi,
            AngleMethod::Cg => Method::Cg(Pre::Blocks),
        };
        solve(
            &AngleOp(self),
            None,
            constraints,
            values,
            m,
            options,
            scratch,
        )
    }
}

impl<T: Real, const D: usize> AngleSystem<'_, T, D> {
    /// Number of `[T; D]` scratch items [`solve_angle_sliding_amg`](crate::spring::AngleSystem::solve_angle_sliding_amg) needs:
    /// [`amg_sliding_cg_scratch_len`](crate::spring::amg_sliding_cg_scratch_len) (`6 n + 3 coarse`); at least the rigidity
    /// probe's `4 n` when `ε = 0`.
    pub fn solve_angle_sliding_amg_scratch_len(&self, hierarchy: &AmgHierarchy<'_, T>) -> usize {
        let n = self.base().node_count();
        self.with_probe(
            amg_sliding_cg_scratch_len(n, hierarchy.coarse_unknowns()).unwrap_or(usize::MAX),
        )
    }

    /// [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding)'s projected CG preconditioned by one V-cycle of the
    /// *scalar* linear-spring [`AmgHierarchy`] per component, applied as `P M⁻¹ P` (symmetric
    /// positive definite on `range(P)`, so CG's guarantees hold): the sliding counterpart of
    /// [`solve_angle_amg`](crate::spring::AngleSystem::solve_angle_amg). `hierarchy` is built on [`base`](crate::spring::AngleSystem::base), i.e. with the mask
    /// [`Constraints::fixed_mask`] writes (sliding nodes free), the hierarchy
    /// [`solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding) takes. The operator, every residual, the scaling, the
    /// report and the sliding guarantee are those of [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding) with
    /// [`AngleMethod::Cg`]; only the preconditioner differs, so a hierarchy of other stiffness
    /// values on the same graph slows convergence but cannot change the answer.
    ///
    /// # Errors
    /// `values` is untouched on error: those of [`solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding), a hierarchy built for
    /// a system of another size ([`Error::LengthMismatch`], `"hierarchy"`), `scratch` shorter
    /// than [`solve_angle_sliding_amg_scratch_len`](crate::spring::AngleSystem::solve_angle_sliding_amg_scratch_len).
    pub fn solve_angle_sliding_amg(
        &self,
        constraints: &Constraints<'_, T, D>,
        values: &mut [[T; D]],
        hierarchy: &AmgHierarchy<'_, T>,
        options: &SolveOptions<T>,
        scratch: &mut [[T; D]],
    ) -> Result<SolveReport<T>> {
        let base = self.base();
        self.check_sliding(constraints, values, options)?;
        hierarchy.check_system(base)?;
        let needed = self.solve_angle_sliding_amg_scratch_len(hierarchy);
        self.probe_rigidity(options, scratch, needed)?;
        solve(
            &AngleOp(self),
            Some(base),
            constraints,
            values,
            Method::Cg(Pre::Amg(hierarchy)),
            options,
            scratch,
        )
    }
}

/// The projected residual pairs `(P (b − K x), P b)` of the non-fixed nodes.
struct ProjectedPairs<'o, 'c, 'x, T: Real, const D: usize, O: BlockOp<T, D>> {
    op: &'o O,
    c: &'o Constraints<'c, T, D>,
    x: &'x [[T; D]],
}

impl<T: Real, const D: usize, O: BlockOp<T, D>> Pairs<T, D>
    for ProjectedPairs<'_, '_, '_, T, D, O>
{
    fn each<F: FnMut(&[T; D], &[T; D])>(&self, mut f: F) {
        for i in 0..self.op.n() {
            if !self.op.fixed(i) {
                let r = self.c.project(i, self.op.node(i, self.x).0);
                let b = self.c.project(i, self.op.pull(i, self.x));
                f(&r, &b);
            }
        }
    }
}

/// `(‖P (b − K x)‖, ‖P b‖)` over the non-fixed nodes, without overflow or underflow.
fn norms<T: Real, const D: usize, O: BlockOp<T, D>>(
    op: &O,
    c: &Constraints<'_, T, D>,
    x: &[[T; D]],
) -> (Norm<T>, Norm<T>) {
    let pairs = ProjectedPairs { op, c, x };
    pair_norms(&pairs, &[T::ONE; D], false, &Serial::new(op.n()))
}

/// Runs `method` on a scaled copy in the front of `scratch` and writes the result back on
/// success.
fn solve<T: Real, const D: usize, O: BlockOp<T, D>>(
    op: &O,
    sys: Option<&SpringSystem<'_, T>>,
    c: &Constraints<'_, T, D>,
    values: &mut [[T; D]],
    method: Method<'_, T>,
    options: &SolveOptions<T>,
    scratch: &mut [[T; D]],
) -> Result<SolveReport<T>> {
    let n = op.n();
    // Scale: values to about 1/√k_max, so k x² and the residuals stay near 1.
    let e = exponents(op.stiffness(), values, true)
        .first()
        .copied()
        .unwrap_or(0);
    let vmax = values
        .iter()
        .flatten()
        .fold(T::ZERO, |m, &v| m.max(v.abs()));
    let down = T::pow2(-e);
    if !(op.row_max() * T::from_f64(4.0) * (vmax * down)).is_finite() {
        return Err(Error::Overflow { arg: "stiffness" });
    }
    let Some((x, rest)) = scratch.split_at_mut_checked(n) else {
        return Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: n,
            actual: 0,
        });
    };
    for (i, (x, &v)) in x.iter_mut().zip(values.iter()).enumerate() {
        let s = vector::scale(v, down);
        *x = if op.fixed(i) { s } else { c.project(i, s) };
    }
    let report = match method {
        Method::Jacobi | Method::Sor(_) => {
            let omega = match method {
                Method::Sor(w) => Some(w),
                _ => None,
            };
            let mut report = stationary(op, c, x, rest, omega, options, e);
            report.max_update = scale_by(report.max_update, e);
            report
        }
        Method::Cg(pre) => cg(op, sys, c, scratch, pre, options, e)?,
    };
    let x = scratch.get(..n).unwrap_or(&[]);
    let up = T::pow2(e);
    for (i, xi) in x.iter().enumerate() {
        if !op.fixed(i)
            && !c
                .project(i, vector::scale(*xi, up))
                .iter()
                .all(|v| v.is_finite())
        {
            return Err(Error::Overflow { arg: "values" });
        }
    }
    for (i, (v, xi)) in values.iter_mut().zip(x.iter()).enumerate() {
        if !op.fixed(i) {
            *v = c.project(i, vector::scale(*xi, up));
        }
    }
    Ok(report)
}

/// Block Jacobi (`omega = None`, second field in `other`) or in-place block SOR on `x`, as
/// [`drive_sweeps`] runs them.
struct BlockSweeps<'o, 'c, 'x, T: Real, const D: usize, O: BlockOp<T, D>> {
    op: &'o O,
    c: &'c Constraints<'c, T, D>,
    x: &'x mut [[T; D]],
    other: &'x mut [[T; D]],
    omega: Option<T>,
    in_other: bool,
}

impl<T: Real, const D: usize, O: BlockOp<T, D>> Sweeps<T> for BlockSweeps<'_, '_, '_, T, D, O> {
    fn sweep(&mut self, sigma: T) -> Sweep<T> {
        let (op, c, omega, n) = (self.op, self.c, self.omega, self.op.n());
        let mut max_change = T::ZERO;
        let mut residual_sq = ExactSum::new();
        let mut visit = |i: usize, src: &[[T; D]]| -> Option<[T; D]> {
            if op.fixed(i) {
                return None;
            }
            let (r, m) = op.node(i, src);
            let pr = c.project(i, r);
            let d = op.block_solve(c, i, &m, pr);
            let d = match omega {
                Some(w) => vector::scale(d, w),
                None => d,
            };
            for (&dc, &rc) in d.iter().zip(&pr) {
                max_change = max_change.max(dc.abs());
                let rs = rc * sigma;
                residual_sq.add(rs * rs);
            }
            Some(d)
        };
        match omega {
            Some(_) => {
                for i in 0..n {
                    if let Some(d) = visit(i, self.x) {
                        if let Some(xi) = self.x.get_mut(i) {
                            *xi = vector::add(*xi, d);
                        }
                    }
                }
            }
            None => {
                let (src, dst): (&[[T; D]], &mut [[T; D]]) = if self.in_other {
                    (&*self.other, &mut *self.x)
                } else {
                    (&*self.x, &mut *self.other)
                };
                for i in 0..n {
                    let new = match visit(i, src) {
                        Some(d) => vector::add(src.get(i).copied().unwrap_or([T::ZERO; D]), d),
                        None => src.get(i).copied().unwrap_or([T::ZERO; D]),
                    };
                    if let Some(o) = dst.get_mut(i) {
                        *o = new;
                    }
                }
                self.in_other = !self.in_other;
            }
        }
        Sweep {
            max_change,
            residual_sq: residual_sq.value(),
            residual_sum: residual_sq,
        }
    }
    fn residual(&mut self) -> Norm<T> {
        let current: &[[T; D]] = if self.in_other { self.other } else { self.x };
        norms(self.op, self.c, current).0
    }
}

/// Jacobi (`omega = None`, second field in `other`) or in-place block SOR sweeps on `x`.
fn stationary<T: Real, const D: usize, O: BlockOp<T, D>>(
    op: &O,
    c: &Constraints<'_, T, D>,
    x: &mut [[T; D]],
    other: &mut [[T; D]],
    omega: Option<T>,
    options: &SolveOptions<T>,
    e: i32,
) -> SolveReport<T> {
    let n = op.n();
    let other = other.get_mut(..n).unwrap_or(&mut []);
    if omega.is_none() {
        for (o, &v) in other.iter_mut().zip(x.iter()) {
            *o = v;
        }
    }
    let (r0, bnorm) = norms(op, c, x);
    let mut sweeps = BlockSweeps {
        op,
        c,
        x,
        other,
        omega,
        in_other: false,
    };
    let report = drive_sweeps(&mut sweeps, r0, bnorm, e, options);
    if sweeps.in_other {
        for (v, o) in sweeps.x.iter_mut().zip(sweeps.other.iter()) {
            *v = *o;
        }
    }
    report
}

/// `pᵀ M p` of a node block.
fn quad_form<T: Real, const D: usize>(m: &[[T; D]; D], p: &[T; D]) -> T {
    let mut s = T::ZERO;
    for (row, &pr) in m.iter().zip(p) {
        s += pr * vector::dot(*row, *p);
    }
    s
}

/// The projected operator `P K P` for [`pcg`] on the scaled copy: one lane (`P` couples the
/// components), the curvature scale `max_i pᵢᵀ Aᵢᵢ pᵢ` from the node blocks.
struct Projected<'o, 'c, T: Real, const D: usize, O: BlockOp<T, D>> {
    op: &'o O,
    c: &'o Constraints<'c, T, D>,
}

impl<T: Real, const D: usize, O: BlockOp<T, D>> Operator<T, D, 1> for Projected<'_, '_, T, D, O> {
    #[inline]
    fn residual(&self, i: usize, x: &[[T; D]]) -> [T; D] {
        if self.op.fixed(i) {
            [T::ZERO; D]
        } else {
            self.c.project(i, self.op.node(i, x).0)
        }
    }

    /// `q = P K p` (`p` is zero at fixed nodes: `node()` gives `−(K p)_i`).
    fn apply(
        &self,
        rows: Range<usize>,
        p: &[[T; D]],
        q: &mut [[T; D]],
        pq: &mut [ExactSum; 1],
        dpp: &mut [T; 1],
    ) {
        let [dpp] = dpp;
        let mut pq = Gather::lanes(pq);
        for i in rows {
            let Some(qi) = q.get_mut(i) else { continue };
            if self.op.fixed(i) {
                *qi = [T::ZERO; D];
                continue;
            }
            let (r, m) = self.op.node(i, p);
            *qi = self.c.project(i, vector::scale(r, -T::ONE));
            let pi = p.get(i).copied().unwrap_or([T::ZERO; D]);
            pq.push([vector::dot(pi, *qi)]);
            *dpp = dpp.max(quad_form(&m, &pi));
        }
    }

    fn norms<C: Collective<T> + ?Sized>(
        &self,
        x: &[[T; D]],
        exps: &[i32; D],
        _: &C,
    ) -> (Norm<T>, Norm<T>) {
        let top = exps.iter().copied().max().unwrap_or(0);
        let (r, b) = norms(self.op, self.c, x);
        (r.shifted(top), b.shifted(top))
    }
}

/// `z = P M⁻¹ r` (zero at fixed nodes) for a preconditioner `M` of the unconstrained operator.
struct ProjectedPre<'o, 'c, T: Real, const D: usize, O: BlockOp<T, D>, M> {
    op: &'o O,
    c: &'o Constraints<'c, T, D>,
    inner: M,
}

impl<T: Real, const D: usize, O: BlockOp<T, D>, M: Precondition<T, D>> Precondition<T, D>
    for ProjectedPre<'_, '_, T, D, O, M>
{
    fn local(&self) -> bool {
        self.inner.local()
    }
    #[inline]
    fn node(&self, i: usize, r: [T; D]) -> [T; D] {
        if self.op.fixed(i) {
            [T::ZERO; D]
        } else {
            self.c.project(i, self.inner.node(i, r))
        }
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; D]], z: &mut [[T; D]], comm: &C) {
        self.inner.apply(r, z, comm);
        for (i, z) in z.iter_mut().enumerate() {
            *z = if self.op.fixed(i) {
                [T::ZERO; D]
            } else {
                self.c.project(i, *z)
            };
        }
    }
}

/// The projected node blocks `(P A_ii P)⁺` (before the projection of [`ProjectedPre`]).
struct Blocks<'o, 'c, T: Real, const D: usize, O: BlockOp<T, D>> {
    op: &'o O,
    c: &'o Constraints<'c, T, D>,
}

impl<T: Real, const D: usize, O: BlockOp<T, D>> Precondition<T, D> for Blocks<'_, '_, T, D, O> {
    fn local(&self) -> bool {
        true
    }
    #[inline]
    fn node(&self, i: usize, r: [T; D]) -> [T; D] {
        if self.op.fixed(i) {
            [T::ZERO; D]
        } else {
            let (_, m) = self.op.node(i, &[]);
            self.op.block_solve(self.c, i, &m, r)
        }
    }
    fn apply<C: Collective<T> + ?Sized>(&mut self, r: &[[T; D]], z: &mut [[T; D]], comm: &C) {
        apply_local(self, r, z, comm);
    }
}

/// Projected preconditioned CG ([`pcg`]) on the scaled copy in the front of `scratch`
/// (scaled by `2^−e`), the CG vectors after it, then the preconditioner's (the diagonal, or
/// the V-cycle's vectors).
fn cg<T: Real, const D: usize, O: BlockOp<T, D>>(
    op: &O,
    sys: Option<&SpringSystem<'_, T>>,
    c: &Constraints<'_, T, D>,
    scratch: &mut [[T; D]],
    pre: Pre<'_, T>,
    options: &SolveOptions<T>,
    e: i32,
) -> Result<SolveReport<T>> {
    let n = op.n();
    let Some((mut v, rest)) = Vectors::split(scratch, n) else {
        return Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: cg_len(n).unwrap_or(usize::MAX),
            actual: 0,
        });
    };
    let proj = Projected { op, c };
    let exps = [e; D];
    let serial = Serial::new(n);
    match (pre, sys) {
        (Pre::Linear(pre), Some(sys)) => {
            let diag = rest.as_flattened_mut().get_mut(..n).unwrap_or(&mut []);
            diagonal(sys, diag);
            let inner = OneLevel { sys, diag, pre };
            let mut m = ProjectedPre { op, c, inner };
            pcg(&proj, &mut m, &mut v, &exps, options, &serial)
        }
        (Pre::Amg(h), Some(sys)) => {
            let inner = Vcycle::new(sys, h, rest);
            let mut m = ProjectedPre { op, c, inner };
            pcg(&proj, &mut m, &mut v, &exps, options, &serial)
        }
        _ => {
            let inner = Blocks { op, c };
            let mut m = ProjectedPre { op, c, inner };
            pcg(&proj, &mut m, &mut v, &exps, options, &serial)
        }
    }
}
