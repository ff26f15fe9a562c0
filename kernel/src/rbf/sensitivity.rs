//! Tangent and adjoint of [`rbf_deform`](super::rbf_deform) with respect to the prescribed
//! boundary motion `d`.
//!
//! With the centres fixed, every stage is linear in `d`: the coefficients `c = M⁻¹ S d` (`S`
//! picks the centres' motion and pads the polynomial rows with zeros; `M` the Wendland matrix
//! or the thin-plate saddle-point matrix), the interpolant `s(x) = E_x c`, the residuals
//! `r_k = d_k − s(y_k)`, the correction `C_x r` and the overwrite of the boundary nodes by `d`.
//! The greedy selection is not: it picks centres from `d` (largest motion, largest error),
//! a piecewise-constant choice. Both directions therefore first run the deformation's own fit
//! on `motion` (the linearisation point), keep its centres and factor, and differentiate that
//! fixed-centre map, which is what the method computes in a neighbourhood of `motion` where
//! the selection does not change (everywhere but on the boundaries between selections, where
//! the deformation itself jumps). With every boundary node a centre (tolerance 0 and
//! `max_centres ≥ B`) the map is globally linear and `motion` does not matter.
//!
//! ```text
//! tangent:  δc = M⁻¹ S δd,  δr_k = δd_k − E_{y_k} δc,  δu(x) = E_x δc + C_x δr
//! adjoint:  r̄ = Σ_x C_xᵀ w_x,  c̄ = Σ_x E_xᵀ w_x − Σ_k E_{y_k}ᵀ r̄_k,  z = M⁻¹ c̄,
//!           g = r̄ + w_b + Sᵀ z          (w_b: the boundary nodes' own w, when R_c > 0)
//! ```
//!
//! `M` is symmetric bit for bit (`φ(|y_i − y_j|) = φ(|y_j − y_i|)`, `P` and `Pᵀ` the same
//! numbers), so `M⁻ᵀ = M⁻¹` and the adjoint reuses the Cholesky or LU factor of the fit.
//! Both are direct: exact to rounding, `O(N · n_R)` (Wendland) or `O(N · k)` (thin-plate)
//! per field plus one triangular solve pair.

use super::{fit, Fitted, RbfOptions, RbfReport};
use crate::check;
use crate::error::{Error, Result};
use crate::rbf::model::{dist_sq, phi, to_frame, Model};
use crate::rbf::RbfKernel;
use crate::real::Real;

/// `len` items hold `m ≥ 1` whole fields of `per` items; returns `m`.
fn fields(arg: &'static str, per: usize, len: usize) -> Result<usize> {
    if per == 0 || len == 0 || len % per != 0 {
        return Err(Error::LengthMismatch {
            arg,
            expected: per,
            actual: len,
        });
    }
    Ok(len / per)
}

/// The tangent of [`rbf_deform`](super::rbf_deform) at `motion`: for `m` boundary
/// perturbations `δd` back to back in `dmotion` (`m · B` items, boundary order), the first-
/// order change of every node's displacement into `dx` (`m · N` items), with the centres and
/// factor of the fit of `motion` (see docs/sensitivities.md). `index` and
/// `scratch` as for `rbf_deform`. Returns the fit's report.
///
/// # Errors
/// Those of `rbf_deform`; `dmotion` or `dx` not whole fields of `B` and `N` items of the same
/// count ([`Error::LengthMismatch`]); non-finite `dmotion`. Nothing is written on an error
/// found before the first field; a field whose values would overflow stops the loop
/// ([`Error::Overflow`]) with the fields before it written.
#[allow(clippy::too_many_arguments)]
pub fn rbf_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    motion: &[[T; D]],
    options: &RbfOptions<T>,
    index: &mut [u32],
    scratch: &mut [T],
    dmotion: &[[T; D]],
    dx: &mut [[T; D]],
) -> Result<RbfReport<T>> {
    let (n, b) = (points.len(), boundary.len());
    let m = fields("dmotion", b, dmotion.len())?;
    check::len("dx", dx.len(), m.saturating_mul(n))?;
    check::finite_items("dmotion", dmotion)?;
    let mut fitted = fit(points, boundary, motion, options, index, scratch)?;
    for (dm, out) in dmotion.chunks_exact(b).zip(dx.chunks_exact_mut(n.max(1))) {
        fitted.resolve(dm);
        fitted.write(out)?;
    }
    Ok(fitted.report)
}

/// The adjoint of [`rbf_deform`](super::rbf_deform) at `motion`: for `m` fields `w = dJ/du`
/// back to back (`m · N` items, one per mesh node), `g = dJ/dd` at the boundary entries
/// (`m · B` items, boundary order), with the centres and factor of the fit of `motion` (see
/// docs/sensitivities.md). `index` and `scratch` as for `rbf_deform`. Returns the
/// fit's report.
///
/// # Errors
/// Those of `rbf_deform`; `w` or `g` not whole fields of `N` and `B` items of the same count
/// ([`Error::LengthMismatch`]); non-finite `w`; a sum that overflows ([`Error::Overflow`]).
/// Nothing is written on an error found before the first field; the fields before an
/// overflowing one are written.
#[allow(clippy::too_many_arguments)]
pub fn rbf_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    motion: &[[T; D]],
    options: &RbfOptions<T>,
    index: &mut [u32],
    scratch: &mut [T],
    w: &[[T; D]],
    g: &mut [[T; D]],
) -> Result<RbfReport<T>> {
    let (n, b) = (points.len(), boundary.len());
    let m = fields("w", n, w.len())?;
    check::len("g", g.len(), m.saturating_mul(b))?;
    check::finite_items("w", w)?;
    let mut fitted = fit(points, boundary, motion, options, index, scratch)?;
    for (wf, gf) in w.chunks_exact(n).zip(g.chunks_exact_mut(b.max(1))) {
        fitted.adjoint(wf, gf)?;
    }
    Ok(fitted.report)
}

impl<T: Real, const D: usize> Fitted<'_, T, D> {
    /// `c̄ += E_xᵀ wx`: the interpolant's terms at `x` (kernel values of the centres near `x`,
    /// then `1` and `ξ(x)` for thin-plate splines), transposed, into `work.coeffs`.
    fn eval_adjoint(&mut self, x: [T; D], wx: [T; D]) {
        let k = self.report.centres;
        let problem = &self.problem;
        let centres = &*self.work.centres;
        let coeffs = &mut *self.work.coeffs;
        let mut put = |row: usize, f: T| {
            for (c, &wc) in wx.iter().enumerate() {
                if let Some(s) = coeffs.get_mut(row * D + c) {
                    *s += f * wc;
                }
            }
        };
        let mut centre = |j: usize| {
            let y = problem.pos(centres.get(j).copied().unwrap_or(0) as usize);
            let f = phi(problem.kernel, dist_sq(x, y));
            if f != T::ZERO {
                put(j, f);
            }
        };
        match problem.kernel {
            RbfKernel::Wendland { radius } => self.grid_c.for_near(x, radius, &mut centre),
            RbfKernel::ThinPlate => {
                (0..k).for_each(&mut centre);
                put(k, T::ONE);
                for (t, &v) in to_frame(x, problem.frame).iter().enumerate() {
                    put(k + 1 + t, v);
                }
            }
        }
    }

    /// Whether mesh node `i` (at `x`) is a boundary entry (found in the boundary grid).
    fn is_boundary(&self, i: usize, x: [T; D]) -> bool {
        let mut found = false;
        self.grid_b.for_near(x, T::ZERO, |k| {
            found |= self
                .problem
                .boundary
                .get(k)
                .is_some_and(|&b| b as usize == i);
        });
        found
    }

    /// `g = Jᵀ w` for one field (see the [module documentation](self)); `g` written only
    /// when every entry is finite.
    fn adjoint(&mut self, w: &[[T; D]], g: &mut [[T; D]]) -> Result<()> {
        let k = self.report.centres;
        let rc = self.correction_radius;
        self.work.coeffs.iter_mut().for_each(|c| *c = T::ZERO);
        self.work.residual.iter_mut().for_each(|r| *r = T::ZERO);
        let points = self.problem.points;
        for (i, (&x, &wx)) in points.iter().zip(w).enumerate() {
            if rc > T::ZERO {
                if self.is_boundary(i, x) {
                    continue; // written with the motion itself
                }
                // Only the boundary positions of the model are read.
                let model = Model {
                    kernel: self.problem.kernel,
                    points,
                    boundary: self.problem.boundary,
                    centres: &[],
                    coeffs: &[],
                    frame: self.problem.frame,
                };
                super::correct::correction_adjoint(
                    &model,
                    &self.grid_b,
                    rc,
                    x,
                    wx,
                    self.work.residual,
                );
            }
            if k > 0 {
                self.eval_adjoint(x, wx);
            }
        }
        if rc > T::ZERO {
            for (kb, &node) in self.problem.boundary.iter().enumerate() {
                let r: [T; D] = core::array::from_fn(|c| {
                    self.work
                        .residual
                        .get(kb * D + c)
                        .copied()
                        .unwrap_or(T::ZERO)
                });
                if k > 0 {
                    self.eval_adjoint(self.problem.pos(kb), r.map(|v| -v));
                }
                let wb = w.get(node as usize).copied().unwrap_or([T::ZERO; D]);
                for (c, &wc) in wb.iter().enumerate() {
                    if let Some(s) = self.work.residual.get_mut(kb * D + c) {
                        *s += wc;
                    }
                }
            }
        }
        self.problem.solve_factored(&mut self.work, k);
        self.scatter_centres(k);
        self.copy_out(g)
    }

    /// `g += Sᵀ z`: the solved `z` of each centre onto its boundary entry's accumulator.
    fn scatter_centres(&mut self, k: usize) {
        for j in 0..k {
            let kb = self.work.centres.get(j).copied().unwrap_or(0) as usize;
            for c in 0..D {
                let z = self.work.coeffs.get(j * D + c).copied().unwrap_or(T::ZERO);
                if let Some(s) = self.work.residual.get_mut(kb * D + c) {
                    *s += z;
                }
            }
        }
    }

    /// Copies the accumulator (`work.residual`) into `g` if every entry is finite.
    fn copy_out(&self, g: &mut [[T; D]]) -> Result<()> {
        let acc = &*self.work.residual;
        if !acc.iter().all(|v| v.is_finite()) {
            return Err(Error::Overflow { arg: "w" });
        }
        for (gk, a) in g.iter_mut().zip(acc.chunks_exact(D)) {
            *gk = core::array::from_fn(|c| a.get(c).copied().unwrap_or(T::ZERO));
        }
        Ok(())
    }
}
