//! Radial-basis-function mesh deformation (de Boer, van der Schoot & Bijl 2007; SU2's and
//! pyGeM's RBF method), allocation-free on caller buffers.
//!
//! The boundary motion `d_k` at boundary nodes `y_k` is interpolated by
//!
//! ```text
//! s(x) = Σ_j λ_j φ(|x − y_j|) + p(x)
//! ```
//!
//! over a set of centres `y_j` (all boundary nodes, or a greedy subset), and every mesh node
//! moves by `s(x)`. Kernels ([`RbfKernel`]):
//! - **Wendland C2**, `φ(r) = (1 − r/R)⁴ (4 r/R + 1)` for `r < R` (support radius `R` chosen
//!   by the caller), no polynomial. The matrix `Φ_ij = φ(|y_i − y_j|)` is symmetric positive
//!   definite for distinct centres: **Cholesky**, factored row by row (left-looking), so a
//!   greedy step appends a row in `O(k²)`. Without a polynomial it reproduces a translation
//!   or rotation only at the centres: elsewhere the motion decays to zero beyond `R` from
//!   them (that is the point of a compact support), and inside it is close to rigid where
//!   `R` is large against the distance to the boundary.
//! - **Thin-plate spline**, `φ(r) = r² ln r`, with the linear polynomial `p(x) = a₀ + a·x`
//!   and the orthogonality conditions `Σ λ_j = 0`, `Σ λ_j y_j = 0`: the saddle-point system
//!   `[[Φ, P], [Pᵀ, 0]]` is indefinite, so it is solved by **LU with partial pivoting**
//!   (refactored at every greedy step: `O(k³)`). It reproduces every affine motion
//!   (translation, rotation's linear map, scaling) exactly in exact arithmetic. The
//!   polynomial is written in the frame `ξ = (x − c) s` (`c` the middle of the boundary's
//!   bounding box, `s` a power of two near its inverse half-extent), for conditioning; the
//!   interpolant is the same.
//!
//! **Greedy centres** ([`RbfOptions::tolerance`], [`RbfOptions::max_centres`]): as in SU2,
//! start from the node with the largest motion (thin-plate splines: plus the `D` nodes
//! farthest from the affine hull of those chosen) and add the boundary node with the largest
//! interpolation error until the largest error is at most the tolerance or the budget is
//! spent. A tolerance of 0 with a budget of at least `B` takes every boundary node at once.
//!
//! **The wall stays exact** ([`RbfOptions::correction_radius`] `R_c > 0`): a reduced fit
//! leaves an error at the boundary nodes that are not centres (SU2's greedy default: about
//! 7e-3 chord). It is carried into the volume by a correction that equals the residual at
//! every boundary node and fades to zero at `R_c` from the boundary (`rbf/correct.rs`), and
//! the boundary nodes are written with the prescribed motion itself. With `R_c = 0` the raw
//! interpolant is written everywhere, boundary nodes included.
//!
//! **Cost.** Wendland evaluation visits only the centres within `R` of a node (a bucket
//! grid of cell side `≥ R`), so it is `O(N · n_R)` with `n_R` the centres per support;
//! thin-plate splines are global, `O(N · k)`. Greedy errors are `O(B · k)` per step.
//!
//! **Determinism.** Factorizations run in a fixed index order without FMA; every evaluation
//! (kernel terms, polynomial terms, the correction's weighted sums) is an exact sum
//! ([`crate::exact_sum::ExactSum`]), so the search structure's visiting order changes no bit:
//! grid and brute force give the same result.

mod correct;
mod dense;
mod fit;
mod grid;
mod model;
mod sensitivity;

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use fit::{Problem, Work};
use grid::{grid_len, Grid};
use model::{frame_of, Model};
pub use sensitivity::{rbf_adjoint, rbf_tangent};

/// The radial function.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RbfKernel<T> {
    /// Wendland's C2 function with compact support `radius` (finite, positive; mesh units).
    Wendland {
        /// Support radius `R`.
        radius: T,
    },
    /// `r² ln r` with linear polynomial augmentation.
    ThinPlate,
}

/// Options of [`rbf_deform`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RbfOptions<T> {
    /// The radial function.
    pub kernel: RbfKernel<T>,
    /// Greedy selection stops once the largest interpolation error at the boundary nodes
    /// (Euclidean, mesh units) is at most this; finite, not negative.
    pub tolerance: T,
    /// Most centres (at least 1; at least `D + 1` for thin-plate splines).
    pub max_centres: usize,
    /// Radius over which the remaining boundary error is faded into the volume (finite, not
    /// negative); 0 writes the raw interpolant, boundary nodes included.
    pub correction_radius: T,
}

/// What [`rbf_deform`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct RbfReport<T> {
    /// Centres used.
    pub centres: usize,
    /// Largest error of the interpolant at the boundary nodes (before the correction).
    pub max_error: T,
    /// Selection stopped because the next node was numerically dependent on the centres.
    pub dependent: bool,
}

/// Sizes for `B` boundary nodes and these options: `(centres m, polynomial terms p)`.
fn sizes<T: Real, const D: usize>(boundary_len: usize, options: &RbfOptions<T>) -> (usize, usize) {
    let p = match options.kernel {
        RbfKernel::ThinPlate => D + 1,
        RbfKernel::Wendland { .. } => 0,
    };
    (options.max_centres.min(boundary_len), p)
}

/// Scalars of the `scratch` buffer [`rbf_deform`] needs: the `a × a` matrix (`a = m + p`,
/// `m = min(max_centres, B)`, `p = D + 1` for thin-plate splines, else 0), `a × D`
/// coefficients and `B × D` residuals; `usize::MAX` on overflow.
pub fn rbf_scratch_len<T: Real, const D: usize>(
    boundary_len: usize,
    options: &RbfOptions<T>,
) -> usize {
    let (m, p) = sizes::<T, D>(boundary_len, options);
    let a = m.saturating_add(p);
    a.saturating_mul(a)
        .saturating_add(a.saturating_mul(D))
        .saturating_add(boundary_len.saturating_mul(D))
}

/// `u32`s of the `index` buffer [`rbf_deform`] needs: centres (`m`), pivots (`a`), flags
/// (`B`), and the two search grids (`2 m + 2` and `2 B + 2`); `usize::MAX` on overflow.
pub fn rbf_index_len<T: Real, const D: usize>(
    boundary_len: usize,
    options: &RbfOptions<T>,
) -> usize {
    let (m, p) = sizes::<T, D>(boundary_len, options);
    m.saturating_add(m.saturating_add(p))
        .saturating_add(boundary_len)
        .saturating_add(grid_len(m))
        .saturating_add(grid_len(boundary_len))
}

/// Checks the options against `B` boundary nodes.
fn check_options<T: Real, const D: usize>(b: usize, options: &RbfOptions<T>) -> Result<()> {
    if let RbfKernel::Wendland { radius } = options.kernel {
        if !(radius.is_finite() && radius > T::ZERO) {
            return Err(Error::InvalidParameter {
                arg: "options.kernel.radius",
                reason: "must be finite and positive",
            });
        }
    }
    if !(options.tolerance.is_finite() && options.tolerance >= T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "options.tolerance",
            reason: "must be finite and not negative",
        });
    }
    if !(options.correction_radius.is_finite() && options.correction_radius >= T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "options.correction_radius",
            reason: "must be finite and not negative",
        });
    }
    let least = match options.kernel {
        RbfKernel::ThinPlate => D + 1,
        RbfKernel::Wendland { .. } => 1,
    };
    if options.max_centres < least {
        return Err(Error::InvalidParameter {
            arg: "options.max_centres",
            reason: "must be at least 1 (thin-plate splines: at least D + 1)",
        });
    }
    if b < least {
        return Err(Error::InvalidParameter {
            arg: "boundary",
            reason: "needs at least 1 node (thin-plate splines: at least D + 1)",
        });
    }
    if u32::try_from(b).is_err() {
        return Err(Error::TooLarge {
            arg: "boundary",
            value: b,
        });
    }
    Ok(())
}

/// Squared distances between the points (and the support radius squared) must be finite:
/// otherwise `φ` would read an overflowed distance as "outside the support"
/// ([`Error::Overflow`] on `points`, or on `options.kernel.radius`).
fn check_extent<T: Real, const D: usize>(points: &[[T; D]], options: &RbfOptions<T>) -> Result<()> {
    let (lo, hi) = model::bounds(points.iter().copied());
    let mut diag2 = T::ZERO;
    for a in 0..D {
        let e = hi[a] - lo[a];
        diag2 += if e > T::ZERO { e * e } else { T::ZERO };
    }
    if !diag2.is_finite() {
        return Err(Error::Overflow { arg: "points" });
    }
    if let RbfKernel::Wendland { radius } = options.kernel {
        if !(radius * radius).is_finite() {
            return Err(Error::Overflow {
                arg: "options.kernel.radius",
            });
        }
    }
    Ok(())
}

/// A boundary node listed twice ([`Error::DuplicateNode`]): equal nodes share a position, so
/// they meet in one bucket of the grid.
fn check_duplicates<T: Real, const D: usize>(
    boundary: &[u32],
    pos: impl Fn(usize) -> [T; D],
    grid: &Grid<'_, T, D>,
) -> Result<()> {
    for (k, &node) in boundary.iter().enumerate() {
        let mut first = k;
        grid.for_near(pos(k), T::ZERO, |j| {
            if boundary.get(j) == Some(&node) {
                first = first.min(j);
            }
        });
        if first < k {
            return Err(Error::DuplicateNode {
                arg: "boundary",
                position: k,
                node: node as usize,
            });
        }
    }
    Ok(())
}

/// An upper bound of `|s(x)|` over the points' bounding box (`k` centres), times 4: `Σ |λ|`
/// times the largest `|φ|` there plus the polynomial's largest term sum. When it is finite no
/// evaluation can overflow, so the output is checked before anything is written.
fn output_bound<T: Real, const D: usize>(
    points: &[[T; D]],
    kernel: RbfKernel<T>,
    k: usize,
    coeffs: &[T],
    frame: ([T; D], T),
) -> T {
    let (lo, hi) = model::bounds(points.iter().copied());
    let mut diag2 = T::ZERO;
    let mut xi = T::ZERO;
    for a in 0..D {
        diag2 += (hi[a] - lo[a]) * (hi[a] - lo[a]);
        let far = (hi[a] - frame.0[a]).abs().max((lo[a] - frame.0[a]).abs());
        xi = xi.max(far * frame.1);
    }
    let phi_max = match kernel {
        RbfKernel::Wendland { .. } => T::ONE,
        // r² ln r: its minimum −1/(2e) at r = e^(−1/2), its maximum at the diameter.
        RbfKernel::ThinPlate => T::from_f64(0.19).max(model::phi(kernel, diag2)),
    };
    let mut bound = T::ZERO;
    for c in 0..D {
        let mut sum = T::ZERO;
        for (j, row) in coeffs.chunks_exact(D).enumerate() {
            let v = row.get(c).copied().unwrap_or(T::ZERO).abs();
            sum += if j < k {
                v * phi_max
            } else {
                v * xi.max(T::ONE)
            };
        }
        bound = bound.max(sum);
    }
    bound * T::from_f64(4.0)
}

/// RBF deformation: fits the boundary motion (`motion[k]` for mesh node `boundary[k]`) and
/// writes the displacement of every mesh node into `displacements` (see the [module
/// documentation](self) for the kernels, the greedy selection and the wall correction).
/// `index` ([`rbf_index_len`]) and `scratch` ([`rbf_scratch_len`]) are workspaces.
///
/// # Errors
/// `displacements` not `points.len()` long, `motion` not `boundary.len()` long
/// ([`Error::LengthMismatch`]); a boundary index out of range or listed twice; non-finite
/// points or motion; invalid options ([`Error::InvalidParameter`]); buffers too small;
/// an interpolation matrix that is singular or not positive definite to working precision
/// (coincident boundary nodes, or a Wendland support so wide that `f32` cannot resolve the
/// nodes: [`Error::SingularSystem`]); coefficients or values that could overflow
/// ([`Error::Overflow`]).
/// On error `displacements` is unchanged.
pub fn rbf_deform<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    motion: &[[T; D]],
    options: &RbfOptions<T>,
    index: &mut [u32],
    scratch: &mut [T],
    displacements: &mut [[T; D]],
) -> Result<RbfReport<T>> {
    check::len("displacements", displacements.len(), points.len())?;
    let fitted = fit(points, boundary, motion, options, index, scratch)?;
    fitted.write(displacements)?;
    Ok(fitted.report)
}

/// A fitted interpolant in the caller's buffers: the problem, the centres and the factor of
/// their matrix, the coefficients and boundary residuals of the last motion solved for, and
/// the two search grids. [`rbf_deform`] writes it; the derivatives re-solve it for other
/// motions with the same centres and factor.
struct Fitted<'a, T: Real, const D: usize> {
    problem: Problem<'a, T, D>,
    work: Work<'a, T>,
    grid_b: Grid<'a, T, D>,
    grid_c: Grid<'a, T, D>,
    correction_radius: T,
    report: RbfReport<T>,
}

/// Validates the inputs and fits `motion` (the centres chosen, their matrix factored).
fn fit<'a, T: Real, const D: usize>(
    points: &'a [[T; D]],
    boundary: &'a [u32],
    motion: &'a [[T; D]],
    options: &RbfOptions<T>,
    index: &'a mut [u32],
    scratch: &'a mut [T],
) -> Result<Fitted<'a, T, D>> {
    check::mesh_dim::<D>();
    let n = points.len();
    let b = boundary.len();
    check::len("motion", motion.len(), b)?;
    check_options::<T, D>(b, options)?;
    check::buffer("index", index.len(), rbf_index_len::<T, D>(b, options))?;
    check::buffer(
        "scratch",
        scratch.len(),
        rbf_scratch_len::<T, D>(b, options),
    )?;
    check::indices("boundary", boundary, n)?;
    check::finite_items("points", points)?;
    check::finite_items("motion", motion)?;

    check_extent(points, options)?;

    let (m, p) = sizes::<T, D>(b, options);
    let a = m + p;
    let pos = |k: usize| {
        let node = boundary.get(k).copied().unwrap_or(0) as usize;
        points.get(node).copied().unwrap_or([T::ZERO; D])
    };
    // The sizes were checked above; the checked splits only keep panic paths out.
    let (centres, rest) = index.split_at_mut_checked(m).unwrap_or_default();
    let (piv, rest) = rest.split_at_mut_checked(a).unwrap_or_default();
    let (flags, rest) = rest.split_at_mut_checked(b).unwrap_or_default();
    let (grid_c_buf, rest) = rest.split_at_mut_checked(grid_len(m)).unwrap_or_default();
    let grid_b_buf = rest.get_mut(..grid_len(b)).unwrap_or(&mut []);
    let (matrix, rest) = scratch.split_at_mut_checked(a * a).unwrap_or_default();
    let (coeffs, rest) = rest.split_at_mut_checked(a * D).unwrap_or_default();
    let residual = rest.get_mut(..b * D).unwrap_or(&mut []);

    let rc = options.correction_radius;
    let search = if rc > T::ZERO { rc } else { T::MIN_POSITIVE };
    let grid_b = Grid::build(b, search, pos, grid_b_buf);
    check_duplicates(boundary, pos, &grid_b)?;

    flags.iter_mut().for_each(|f| *f = 0);
    let problem = Problem {
        kernel: options.kernel,
        points,
        boundary,
        motion,
        frame: frame_of(b, pos),
        m,
        a,
    };
    let mut work = Work {
        centres,
        piv,
        flags,
        matrix,
        coeffs,
        residual,
    };
    let fitted = if options.tolerance == T::ZERO && m == b {
        problem.fit_all(&mut work)?
    } else {
        problem.fit_greedy(&mut work, options.tolerance)?
    };
    let k = fitted.centres;
    let radius = match options.kernel {
        RbfKernel::Wendland { radius } => radius,
        RbfKernel::ThinPlate => T::INFINITY,
    };
    let centre = |j: usize| pos(work.centres.get(j).copied().unwrap_or(0) as usize);
    let grid_c = Grid::build(k, radius, centre, grid_c_buf);
    Ok(Fitted {
        problem,
        work,
        grid_b,
        grid_c,
        correction_radius: rc,
        report: RbfReport {
            centres: k,
            max_error: fitted.max_error,
            dependent: fitted.dependent,
        },
    })
}

impl<'a, T: Real, const D: usize> Fitted<'a, T, D> {
    /// The interpolant of the last motion solved for.
    fn model(&self) -> Model<'_, T, D> {
        let k = self.report.centres;
        Model {
            kernel: self.problem.kernel,
            points: self.problem.points,
            boundary: self.problem.boundary,
            centres: self.work.centres.get(..k).unwrap_or(&[]),
            coeffs: &*self.work.coeffs,
            frame: self.problem.frame,
        }
    }

    /// The displacement at `x`: the interpolant plus the wall correction.
    fn value(&self, model: &Model<'_, T, D>, x: [T; D]) -> [T; D] {
        let rc = self.correction_radius;
        let mut v = if self.report.centres == 0 {
            [T::ZERO; D]
        } else {
            model.eval(x, Some(&self.grid_c))
        };
        if rc > T::ZERO {
            let c = correct::correction(model, &self.grid_b, &*self.work.residual, rc, x);
            for (vi, ci) in v.iter_mut().zip(c) {
                *vi += ci;
            }
        }
        v
    }

    /// Writes the displacement of every node for the last motion solved for (boundary nodes:
    /// that motion itself when there is a correction). Nothing is written on error.
    fn write(&self, displacements: &mut [[T; D]]) -> Result<()> {
        let points = self.problem.points;
        let k = self.report.centres;
        let p = self.problem.poly_terms();
        let used = (k + if k > 0 { p } else { 0 }) * D;
        let coeffs = self.work.coeffs.get(..used).unwrap_or(&[]);
        let kernel = self.problem.kernel;
        if !output_bound::<T, D>(points, kernel, k, coeffs, self.problem.frame).is_finite() {
            return Err(Error::Overflow { arg: "motion" });
        }
        let model = self.model();
        // `output_bound` does not cover every intermediate near the overflow range (fuzzing
        // found a NaN at coordinates of 1e151): every value is checked before any is written,
        // so `displacements` stays unchanged on error. This evaluates the model twice.
        if !points
            .iter()
            .all(|&x| self.value(&model, x).iter().all(|v| v.is_finite()))
        {
            return Err(Error::Overflow { arg: "motion" });
        }
        for (x, out) in points.iter().zip(displacements.iter_mut()) {
            *out = self.value(&model, *x);
        }
        if self.correction_radius > T::ZERO {
            for (&node, d) in self.problem.boundary.iter().zip(self.problem.motion) {
                if let Some(out) = displacements.get_mut(node as usize) {
                    *out = *d;
                }
            }
        }
        Ok(())
    }

    /// Solves for `motion` with the centres and factor of the fit (linear in `motion`).
    fn resolve(&mut self, motion: &'a [[T; D]]) {
        self.problem.motion = motion;
        self.problem.resolve(&mut self.work, self.report.centres);
    }
}
