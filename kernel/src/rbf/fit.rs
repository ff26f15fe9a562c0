//! Choosing the centres and solving for the coefficients: the whole boundary at once, or
//! greedily (SU2's data reduction: add the boundary node with the largest error until the
//! largest error is at most the tolerance or the centre budget is spent).

use super::dense::{cholesky_row, cholesky_solve, lu_factor, lu_solve};
use super::model::{dist_sq, phi, to_frame, Model};
use super::RbfKernel;
use crate::error::{Error, Result};
use crate::real::Real;

/// The caller's workspaces for a fit, split by [`super::rbf_deform`].
pub(super) struct Work<'a, T> {
    /// Chosen centres (positions into `boundary`), `m` at most.
    pub centres: &'a mut [u32],
    /// LU pivots (`a` entries).
    pub piv: &'a mut [u32],
    /// Per boundary entry: 1 once it is a centre.
    pub flags: &'a mut [u32],
    /// The `a × a` matrix (row stride `a`).
    pub matrix: &'a mut [T],
    /// Right-hand sides, then coefficients: `a × D`.
    pub coeffs: &'a mut [T],
    /// Per boundary entry: motion minus interpolant (`B × D`).
    pub residual: &'a mut [T],
}

/// What the fit chose.
pub(super) struct Fitted<T> {
    pub centres: usize,
    pub max_error: T,
    pub dependent: bool,
}

/// The problem of one fit.
#[derive(Clone, Copy)]
pub(super) struct Problem<'a, T, const D: usize> {
    pub kernel: RbfKernel<T>,
    pub points: &'a [[T; D]],
    pub boundary: &'a [u32],
    pub motion: &'a [[T; D]],
    pub frame: ([T; D], T),
    /// Centre budget `m` and matrix stride `a = m + p`.
    pub m: usize,
    pub a: usize,
}

impl<T: Real, const D: usize> Problem<'_, T, D> {
    pub fn poly_terms(&self) -> usize {
        match self.kernel {
            RbfKernel::ThinPlate => D + 1,
            RbfKernel::Wendland { .. } => 0,
        }
    }

    pub fn pos(&self, k: usize) -> [T; D] {
        let node = self.boundary.get(k).copied().unwrap_or(0) as usize;
        self.points.get(node).copied().unwrap_or([T::ZERO; D])
    }

    fn model<'b>(&'b self, w: &'b Work<'_, T>, k: usize) -> Model<'b, T, D> {
        Model {
            kernel: self.kernel,
            points: self.points,
            boundary: self.boundary,
            centres: w.centres.get(..k).unwrap_or(&[]),
            coeffs: &*w.coeffs,
            frame: self.frame,
        }
    }

    /// Residuals at every boundary entry for `k` centres; returns the largest error (2-norm)
    /// and the first non-centre entry with the largest error.
    pub fn residuals(&self, w: &mut Work<'_, T>, k: usize) -> (T, Option<usize>) {
        let mut worst = (T::ZERO, None, -T::ONE);
        for b in 0..self.boundary.len() {
            let s = if k == 0 {
                [T::ZERO; D]
            } else {
                self.model(w, k).eval(self.pos(b), None)
            };
            let d = self.motion.get(b).copied().unwrap_or([T::ZERO; D]);
            let mut e2 = T::ZERO;
            for (c, (&dc, &sc)) in d.iter().zip(&s).enumerate() {
                let r = dc - sc;
                e2 += r * r;
                if let Some(x) = w.residual.get_mut(b * D + c) {
                    *x = r;
                }
            }
            let e = e2.sqrt();
            worst.0 = worst.0.max(e);
            if w.flags.get(b).copied().unwrap_or(1) == 0 && e > worst.2 {
                worst = (worst.0, Some(b), e);
            }
        }
        (worst.0, worst.1)
    }

    /// Right-hand sides for `k` centres: their motion, then zeros for the polynomial.
    fn load_rhs(&self, w: &mut Work<'_, T>, k: usize) {
        for j in 0..k + self.poly_terms() {
            let b = w.centres.get(j).copied().unwrap_or(0) as usize;
            let d = self.motion.get(b).copied().unwrap_or([T::ZERO; D]);
            for (c, &dc) in d.iter().enumerate() {
                if let Some(x) = w.coeffs.get_mut(j * D + c) {
                    *x = if j < k { dc } else { T::ZERO };
                }
            }
        }
    }

    /// Makes boundary entry `b` centre number `k`: for Wendland, appends its Cholesky row.
    /// `false` when it is numerically dependent on the earlier centres.
    fn add_centre(&self, w: &mut Work<'_, T>, k: usize, b: usize) -> bool {
        if let Some(x) = w.centres.get_mut(k) {
            *x = b as u32;
        }
        if let Some(f) = w.flags.get_mut(b) {
            *f = 1;
        }
        if let RbfKernel::Wendland { .. } = self.kernel {
            let y = self.pos(b);
            for j in 0..=k {
                let cj = w.centres.get(j).copied().unwrap_or(0) as usize;
                let v = phi(self.kernel, dist_sq(y, self.pos(cj)));
                if let Some(x) = w.matrix.get_mut(k * self.a + j) {
                    *x = v;
                }
            }
            return cholesky_row(w.matrix, self.a, k);
        }
        true
    }

    /// Solves for the coefficients of `k` centres (Wendland: the factor is already there;
    /// thin-plate splines: assembles and factors the saddle-point system). `false` if singular.
    fn solve(&self, w: &mut Work<'_, T>, k: usize) -> bool {
        self.load_rhs(w, k);
        if let RbfKernel::Wendland { .. } = self.kernel {
            for c in 0..D {
                cholesky_solve(w.matrix, self.a, k, w.coeffs, D, c);
            }
            return true;
        }
        let n = k + D + 1;
        self.assemble_tps(w, k);
        if !lu_factor(w.matrix, self.a, n, w.piv) {
            return false;
        }
        for c in 0..D {
            lu_solve(w.matrix, self.a, n, w.piv, w.coeffs, D, c);
        }
        true
    }

    /// The coefficients of this problem's motion with the factor the last fit of `k` centres
    /// left (the derivative: the same matrix, another right-hand side), then the residuals.
    pub fn resolve(&self, w: &mut Work<'_, T>, k: usize) {
        self.load_rhs(w, k);
        self.solve_factored(w, k);
        self.residuals(w, k);
    }

    /// Solves in place in `w.coeffs` with the factor of `k` centres (nothing for `k = 0`).
    /// The matrix is symmetric (`φ(|y_i − y_j|)` bit for bit both ways), so this is also
    /// the transposed solve.
    pub fn solve_factored(&self, w: &mut Work<'_, T>, k: usize) {
        if k == 0 {
            return;
        }
        for c in 0..D {
            match self.kernel {
                RbfKernel::Wendland { .. } => cholesky_solve(w.matrix, self.a, k, w.coeffs, D, c),
                RbfKernel::ThinPlate => {
                    lu_solve(w.matrix, self.a, k + D + 1, w.piv, w.coeffs, D, c);
                }
            }
        }
    }

    /// `[[Φ, P], [Pᵀ, 0]]` for `k` centres, `P` rows `[1, ξ]`.
    fn assemble_tps(&self, w: &mut Work<'_, T>, k: usize) {
        let n = k + D + 1;
        let mut put = |i: usize, j: usize, v: T| {
            if let Some(x) = w.matrix.get_mut(i * self.a + j) {
                *x = v;
            }
        };
        for i in 0..n {
            for j in 0..n {
                put(i, j, T::ZERO);
            }
        }
        for i in 0..k {
            let yi = self.pos(w.centres.get(i).copied().unwrap_or(0) as usize);
            for j in 0..k {
                let yj = self.pos(w.centres.get(j).copied().unwrap_or(0) as usize);
                put(i, j, phi(self.kernel, dist_sq(yi, yj)));
            }
            put(i, k, T::ONE);
            put(k, i, T::ONE);
            for (t, &v) in to_frame(yi, self.frame).iter().enumerate() {
                put(i, k + 1 + t, v);
                put(k + 1 + t, i, v);
            }
        }
    }

    /// Every boundary entry a centre, in boundary order.
    pub fn fit_all(&self, w: &mut Work<'_, T>) -> Result<Fitted<T>> {
        let k = self.boundary.len();
        for b in 0..k {
            if !self.add_centre(w, b, b) {
                return Err(Error::SingularSystem { iteration: b });
            }
        }
        if !self.solve(w, k) {
            return Err(Error::SingularSystem { iteration: k });
        }
        let (max_error, _) = self.residuals(w, k);
        Ok(Fitted {
            centres: k,
            max_error,
            dependent: false,
        })
    }

    /// Greedy selection (see the module documentation).
    pub fn fit_greedy(&self, w: &mut Work<'_, T>, tolerance: T) -> Result<Fitted<T>> {
        let (mut max_error, mut next) = self.residuals(w, 0);
        let mut k = 0;
        if max_error > tolerance && self.poly_terms() > 0 {
            k = self.seed_tps(w, next.unwrap_or(0))?;
            if !self.solve(w, k) {
                return Err(Error::SingularSystem { iteration: k });
            }
            (max_error, next) = self.residuals(w, k);
        }
        let mut dependent = false;
        while max_error > tolerance && k < self.m {
            let Some(b) = next else { break };
            if !self.add_centre(w, k, b) || !self.solve(w, k + 1) {
                // Numerically dependent: keep the previous solution.
                dependent = true;
                if let Some(f) = w.centres.get(k).and_then(|&b| w.flags.get_mut(b as usize)) {
                    *f = 0;
                }
                if !self.solve(w, k) {
                    return Err(Error::SingularSystem { iteration: k });
                }
                break;
            }
            k += 1;
            (max_error, next) = self.residuals(w, k);
        }
        if dependent {
            (max_error, _) = self.residuals(w, k);
        }
        Ok(Fitted {
            centres: k,
            max_error,
            dependent,
        })
    }

    /// The `D + 1` first thin-plate centres: the entry with the largest motion, then each time
    /// the one farthest from the affine hull of those chosen (distance, then area, then
    /// volume), so the polynomial part is determined.
    fn seed_tps(&self, w: &mut Work<'_, T>, first: usize) -> Result<usize> {
        self.add_centre(w, 0, first);
        for s in 1..=D {
            let mut best = (T::ZERO, None);
            for b in 0..self.boundary.len() {
                let v = self.hull_measure(w, s, self.pos(b));
                if v > best.0 {
                    best = (v, Some(b));
                }
            }
            let Some(b) = best.1 else {
                return Err(Error::InvalidParameter {
                    arg: "boundary",
                    reason: "thin-plate splines need boundary nodes that span the space (not all on one line or plane)",
                });
            };
            self.add_centre(w, s, b);
        }
        Ok(D + 1)
    }

    /// Squared length / area / volume spanned with the first `s` centres (`s = 1, 2, 3`).
    fn hull_measure(&self, w: &Work<'_, T>, s: usize, y: [T; D]) -> T {
        let c = |j: usize| pad(self.pos(w.centres.get(j).copied().unwrap_or(0) as usize));
        let o = c(0);
        let v = sub3(pad(y), o);
        match s {
            1 => dot3(v, v),
            2 => {
                let x = cross3(sub3(c(1), o), v);
                dot3(x, x)
            }
            _ => {
                let d = dot3(cross3(sub3(c(1), o), sub3(c(2), o)), v);
                d * d
            }
        }
    }
}

fn pad<T: Real, const D: usize>(p: [T; D]) -> [T; 3] {
    core::array::from_fn(|i| p.get(i).copied().unwrap_or(T::ZERO))
}
fn sub3<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot3<T: Real>(a: [T; 3], b: [T; 3]) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross3<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
