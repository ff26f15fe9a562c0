//! Bernstein free-form deformation boxes as SU2 evaluates them (`CFreeFormDefBox`,
//! `CBezierBlending`, `CSurfaceMovement::SetCartesianCoord` and the `SetFFD*` design
//! variables).
//!
//! A box of degree `(l, m, n)` has `(l+1)(m+1)(n+1)` control points `P[i][j][k]`; a point with
//! parametric coordinates `(u, v, w)` sits at
//!
//! ```text
//! x(u,v,w) = Σ_i Σ_j Σ_k P[i][j][k] · B_l,i(u) · B_m,j(v) · B_n,k(w),   B_n,i(t) = C(n,i) t^i (1−t)^(n−i)
//! ```
//!
//! Control points are stored flat in the order SU2 writes `FFD_CONTROL_POINTS` (i slowest, k
//! fastest): `index = (i·(m+1) + j)·(n+1) + k` ([`FfdBox::index`]); a 2D box (`D = 2`) has
//! `index = i·(m+1) + j`.
//!
//! SU2's boxes are always 3D, also for 2D meshes: degree `(l, m, 1)`, control points at
//! `z = ±0.5`, and the stored surface points at `w = 0.5`. To reproduce SU2 bit for bit on a
//! 2D mesh, use `D = 3` with the mesh points padded by `z = 0` and keep x and y of the
//! result. `D = 2` is a true bivariate box (same values up to rounding).
//!
//! The Bernstein basis is SU2's `GetBernstein` (including its special cases at `t = 0` and
//! `t = 1`), with exact binomial coefficients, and the sum runs in SU2's order with SU2's
//! products `((P · B_i) · B_j) · B_k`, so in `f64` the evaluation matches SU2's wherever libm's
//! `pow` and the C library's agree.

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// Largest degree per direction (SU2 has no bound; 32 keeps the basis on the stack and every
/// binomial coefficient exact in `f64`).
pub const MAX_DEGREE: usize = 32;

/// Number of control points of a box of the given degrees, or `None` when a degree is 0 or
/// above [`MAX_DEGREE`].
pub fn ffd_control_point_count<const D: usize>(degree: [usize; D]) -> Option<usize> {
    let mut count = 1usize;
    for &d in &degree {
        if d == 0 || d > MAX_DEGREE {
            return None;
        }
        count *= d + 1;
    }
    Some(count)
}

/// The binomial coefficient `C(n, i)` (exact for `n ≤ MAX_DEGREE`: below 2^53).
fn binomial(n: usize, i: usize) -> u64 {
    let mut c = 1u64;
    for r in 0..i {
        c = c * (n - r) as u64 / (r + 1) as u64;
    }
    c
}

/// SU2's Bernstein polynomial `B_n,i(t)` (`CBezierBlending::GetBernstein`): 0 for `i > n`;
/// for `i = 0`: 1 at `t = 0`, 0 at `t = 1`, else `C(n,0) t^0 (1−t)^n`; for `i = n`: 0 at
/// `t = 0`, 1 at `t = 1`, else `t^n`; otherwise `C(n,i) t^i (1−t)^(n−i)`; powers by libm's
/// `pow`. `t` may lie slightly outside `[0, 1]` (points just outside a box).
pub fn bernstein<T: Real>(n: usize, i: usize, t: T) -> T {
    if i > n {
        return T::ZERO;
    }
    let general = |i: usize| {
        T::from_f64(binomial(n, i) as f64)
            * t.powf(T::from_usize(i))
            * (T::ONE - t).powf(T::from_usize(n - i))
    };
    if i == 0 {
        if t == T::ZERO {
            T::ONE
        } else if t == T::ONE {
            T::ZERO
        } else {
            general(0)
        }
    } else if i == n {
        if t == T::ZERO {
            T::ZERO
        } else if t == T::ONE {
            T::ONE
        } else {
            t.powf(T::from_usize(n))
        }
    } else {
        general(i)
    }
}

/// A validated view of one box: its degrees and its control points.
#[derive(Clone, Copy, Debug)]
pub struct FfdBox<'a, T, const D: usize> {
    degree: [usize; D],
    control_points: &'a [[T; D]],
}

/// Checks degrees and the control-point count shared by [`FfdBox::new`] and the design
/// variables.
pub(super) fn check_box<T: Real, const D: usize>(
    degree: [usize; D],
    control_points: &[[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    let count = ffd_control_point_count(degree).ok_or(Error::InvalidParameter {
        arg: "degree",
        reason: "each degree must be between 1 and MAX_DEGREE (32)",
    })?;
    check::len("control_points", control_points.len(), count)
}

/// Flat index of control point `ijk` (see the module docs) without bound checks.
pub(super) fn flat<const D: usize>(degree: [usize; D], ijk: [usize; D]) -> usize {
    let mut index = 0;
    for a in 0..D {
        index = index * (degree[a] + 1) + ijk[a];
    }
    index
}

impl<'a, T: Real, const D: usize> FfdBox<'a, T, D> {
    /// A box of degrees `degree` (`FFD_DEGREE_I/J/K`; each 1..=[`MAX_DEGREE`]) with
    /// `control_points` in the flat order of [`FfdBox::index`].
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for a degree of 0 or above [`MAX_DEGREE`];
    /// [`Error::LengthMismatch`] when `control_points` does not hold
    /// [`ffd_control_point_count`] points; [`Error::NonFinite`] for a non-finite control point.
    pub fn new(degree: [usize; D], control_points: &'a [[T; D]]) -> Result<Self> {
        check_box(degree, control_points)?;
        check::finite_items("control_points", control_points)?;
        Ok(FfdBox {
            degree,
            control_points,
        })
    }

    /// The degrees.
    pub fn degree(&self) -> [usize; D] {
        self.degree
    }

    /// The control points.
    pub fn control_points(&self) -> &'a [[T; D]] {
        self.control_points
    }

    /// Flat index of control point `(i, j[, k])`, or `None` when an index exceeds its degree.
    pub fn index(&self, ijk: [usize; D]) -> Option<usize> {
        if ijk.iter().zip(&self.degree).any(|(&i, &d)| i > d) {
            return None;
        }
        Some(flat(self.degree, ijk))
    }

    /// The box at parametric coordinates `param` (SU2's `EvalCartesianCoord`). No checks:
    /// a non-finite `param` gives a non-finite point.
    pub fn eval(&self, param: [T; D]) -> [T; D] {
        let basis = basis(self.degree, param);
        let mut out = [T::ZERO; D];
        let mut ijk = [0usize; D];
        for p in self.control_points {
            for (o, &c) in out.iter_mut().zip(p) {
                *o += weight(&basis, &ijk, c);
            }
            next_index(&mut ijk, self.degree);
        }
        out
    }
}

/// The Bernstein basis of every axis at `param` (row `a`: `B_n,i(param[a])`, `i ≤ n`).
pub(super) fn basis<T: Real, const D: usize>(
    degree: [usize; D],
    param: [T; D],
) -> [[T; MAX_DEGREE + 1]; D] {
    let mut basis = [[T::ZERO; MAX_DEGREE + 1]; D];
    for ((row, &n), &t) in basis.iter_mut().zip(&degree).zip(&param) {
        for (i, b) in row.iter_mut().enumerate().take(n + 1) {
            *b = bernstein(n, i, t);
        }
    }
    basis
}

/// `c` times the axes' basis values at multi-index `ijk`, in axis order (SU2's
/// `((c · B_i) · B_j) · B_k`).
pub(super) fn weight<T: Real, const D: usize>(
    basis: &[[T; MAX_DEGREE + 1]; D],
    ijk: &[usize; D],
    c: T,
) -> T {
    (basis.iter().zip(ijk)).fold(c, |term, (row, &i)| {
        term * row.get(i).copied().unwrap_or(T::ZERO)
    })
}

/// The next multi-index in storage order (last axis fastest).
pub(super) fn next_index<const D: usize>(ijk: &mut [usize; D], degree: [usize; D]) {
    for (i, &n) in ijk.iter_mut().zip(&degree).rev() {
        *i += 1;
        if *i <= n {
            break;
        }
        *i = 0;
    }
}

/// [`Error::Overflow`] when some result is not finite (finite inputs far outside the box can
/// overflow `t^n`); checked before anything is written, so results are computed twice.
fn all_finite<T: Real, const D: usize>(mut items: impl Iterator<Item = [T; D]>) -> Result<()> {
    if items.all(|x| x.iter().all(|c| c.is_finite())) {
        Ok(())
    } else {
        Err(Error::Overflow { arg: "params" })
    }
}

/// Evaluates `ffd` at every `params[p]` into `out[p]`.
///
/// # Errors
/// [`Error::LengthMismatch`] when `out` and `params` differ in length; [`Error::NonFinite`]
/// for a non-finite parametric coordinate; [`Error::Overflow`] when a result is not finite.
/// Nothing is written on error.
pub fn ffd_eval<T: Real, const D: usize>(
    ffd: &FfdBox<'_, T, D>,
    params: &[[T; D]],
    out: &mut [[T; D]],
) -> Result<()> {
    check::len("out", out.len(), params.len())?;
    check::finite_items("params", params)?;
    all_finite(params.iter().map(|&u| ffd.eval(u)))?;
    for (o, &u) in out.iter_mut().zip(params) {
        *o = ffd.eval(u);
    }
    Ok(())
}

/// Surface displacements as SU2's `SetCartesianCoord` computes them: for each surface point
/// `p` (an `FFD_SURFACE_POINTS` line: node `nodes[p]` at parametric coordinates
/// `params[p]`), `displacements[p] = moved.eval(params[p]) − points[nodes[p]]`, each
/// component with `|d| ≤ SU2_EPS` (1e-16) set to 0. Overwrites (SU2 sets, not adds: a node in
/// two boxes takes the last box's value).
///
/// The reference is the mesh point, not the unmoved box: with no control point moved the
/// result is the (tiny) error of the stored parametric coordinates, exactly as in SU2. Use
/// [`ffd_displacements_between`] for "moved box minus original box" (exactly zero when
/// nothing moved).
///
/// # Errors
/// [`Error::LengthMismatch`] when `params` or `displacements` does not have one entry per
/// node; [`Error::IndexOutOfRange`] for a node outside `points`; [`Error::NonFinite`] for a
/// non-finite parametric coordinate or listed point; [`Error::Overflow`] when a displacement
/// is not finite. Nothing is written on error.
pub fn ffd_displacements<T: Real, const D: usize>(
    moved: &FfdBox<'_, T, D>,
    points: &[[T; D]],
    nodes: &[u32],
    params: &[[T; D]],
    displacements: &mut [[T; D]],
) -> Result<()> {
    check::len("params", params.len(), nodes.len())?;
    check::len("displacements", displacements.len(), nodes.len())?;
    check::indices("nodes", nodes, points.len())?;
    check::finite_items("params", params)?;
    super::listed_points_finite(points, nodes)?;
    let eps = T::from_f64(super::SU2_EPS);
    let x_zero = [T::ZERO; D];
    let su2 = |n: u32, u: [T; D]| {
        let (x, p) = (
            moved.eval(u),
            points.get(n as usize).copied().unwrap_or(x_zero),
        );
        core::array::from_fn(|a| {
            let v = x[a] - p[a];
            if v.abs() <= eps {
                T::ZERO
            } else {
                v
            }
        })
    };
    all_finite(nodes.iter().zip(params).map(|(&n, &u)| su2(n, u)))?;
    for ((&n, &u), d) in nodes.iter().zip(params).zip(displacements.iter_mut()) {
        *d = su2(n, u);
    }
    Ok(())
}

/// Surface displacements as "moved box minus original box" at the same parametric
/// coordinates: `displacements[p] = moved.eval(params[p]) − original.eval(params[p])`.
/// Exactly zero where no control point moved (bit-identical evaluations), and independent of
/// how well the stored parametric coordinates reproduce the mesh.
///
/// # Errors
/// [`Error::InvalidParameter`] when the boxes differ in degree ("moved");
/// [`Error::LengthMismatch`] when `displacements` and `params` differ in length; [`Error::NonFinite`] for a non-finite
/// parametric coordinate; [`Error::Overflow`] when a displacement is not finite. Nothing is
/// written on error.
pub fn ffd_displacements_between<T: Real, const D: usize>(
    original: &FfdBox<'_, T, D>,
    moved: &FfdBox<'_, T, D>,
    params: &[[T; D]],
    displacements: &mut [[T; D]],
) -> Result<()> {
    if original.degree != moved.degree {
        return Err(Error::InvalidParameter {
            arg: "moved",
            reason: "must have the same degrees as the original box",
        });
    }
    check::len("displacements", displacements.len(), params.len())?;
    check::finite_items("params", params)?;
    let diff = |u: [T; D]| {
        let (a, b) = (moved.eval(u), original.eval(u));
        core::array::from_fn(|c| a[c] - b[c])
    };
    all_finite(params.iter().map(|&u| diff(u)))?;
    for (d, &u) in displacements.iter_mut().zip(params) {
        *d = diff(u);
    }
    Ok(())
}
