//! Sliding boundaries: per-node motion constraints (free, fixed, sliding on a plane, sliding on
//! a line) and the least-squares plane fit that derives a plane from a marker's nodes.
//!
//! **Representation** (plain slices, so the C ABI can pass caller arrays through):
//! - `kinds: &[u8]`, one [`NodeKind`] code per node: 0 free, 1 fixed, 2 sliding on a plane,
//!   3 sliding on a line. Any other byte is an error (unlike the fixed mask, where any nonzero
//!   byte means fixed: a kind table has more than two values, so a stray byte is a bug).
//! - `directions: &[[T; D]]`, one vector per node: the plane's unit **normal** for kind 2, the
//!   line's unit **tangent** for kind 3; ignored (any bits, NaN included) for kinds 0 and 1.
//!   In 2D a "plane" is a line: kind 2 with the line's normal and kind 3 with its tangent
//!   allow the same motion.
//!
//! [`Constraints::new`] validates both once: kinds in range, directions of sliding nodes finite
//! and of unit length within [`unit_tolerance`] (`√ε`: 1.5e-8 for `f64`, 3.5e-4 for `f32`).
//! The projections divide by `|n|²` anyway, so a normal that is unit only to that tolerance
//! still keeps nodes on their planes to rounding.
//!
//! **Projection.** A sliding node may move by `P d` only: `P = I − n nᵀ` (plane) or
//! `P = t tᵀ` (line), evaluated as `d − n (n·d)/(n·n)` and `t (t·d)/(t·t)`, so
//! `n · (P d)` is at rounding level of `|d|`. The final position `x_old + P d` then stays on the
//! plane through `x_old` to rounding of `|x|` (tested to 1e-12 of the mesh size).
//!
//! **Where constraints apply.** The linear and angle spring solvers take them directly
//! ([`SpringSystem::solve_linear_sliding`](crate::spring::SpringSystem::solve_linear_sliding),
//! [`AngleSystem::solve_angle_sliding`](crate::spring::AngleSystem::solve_angle_sliding)): the
//! constrained minimum-energy problem `P K P d = P b` is solved jointly over the components.
//! The quaternion pipelines and IDW propagate a sliding node like any free node (it is *not* a
//! boundary node, so not an interpolation source with a fixed value); [`slide_points`] then
//! projects its displacement. A line sliding on the intersection of two planes gets its
//! tangent from [`plane_intersection`]; a plane given by a marker's nodes gets its normal from
//! [`fit_plane`], which refuses node sets that are not planar within a tolerance.
//!
//! ```
//! use deform_kernel::spring::constraints::{fit_plane, slide_points, Constraints, NodeKind};
//! // Nodes 1 and 2 lie on the symmetry plane z = 0; node 0 is fixed, node 3 free.
//! let points = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [3.0, 1.0, 0.0]];
//! let fit = fit_plane(&points, &[1, 2, 3], 1e-12)?;
//! assert_eq!(fit.normal, [0.0, 0.0, 1.0]);
//! let kinds = [NodeKind::Fixed as u8, NodeKind::Plane as u8, NodeKind::Plane as u8, 0];
//! let dirs = [[0.0; 3], fit.normal, fit.normal, [0.0; 3]];
//! let c = Constraints::new(&kinds, &dirs)?;
//! // A propagation moved every node by (0.1, 0.2, 0.3); the plane nodes keep z = 0.
//! let mut moved = points.map(|p| [p[0] + 0.1, p[1] + 0.2, p[2] + 0.3]);
//! slide_points(&c, &points, &mut moved)?;
//! assert_eq!(moved[1], [1.1, 0.2, 0.0]);
//! assert_eq!(moved[3][2], 0.3);
//! # Ok::<(), deform_kernel::Error>(())
//! ```

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::vector;

/// What a node may do. The `u8` codes are the ABI (`repr(u8)`).
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NodeKind {
    /// Moves freely (an unknown of the solve).
    Free = 0,
    /// Prescribed (Dirichlet): keeps the value the caller gives.
    Fixed = 1,
    /// Slides on the plane through its position with the given unit normal.
    Plane = 2,
    /// Slides on the line through its position with the given unit tangent.
    Line = 3,
}

impl NodeKind {
    /// The kind of code `c`, or `None` for a code above 3.
    #[inline]
    pub const fn from_code(c: u8) -> Option<Self> {
        match c {
            0 => Some(NodeKind::Free),
            1 => Some(NodeKind::Fixed),
            2 => Some(NodeKind::Plane),
            3 => Some(NodeKind::Line),
            _ => None,
        }
    }

    /// The kind's code.
    #[inline]
    pub const fn code(self) -> u8 {
        self as u8
    }
}

/// How far `|n|²` of a sliding node's direction may be from 1: `√ε` (1.5e-8 for `f64`,
/// 3.5e-4 for `f32`).
#[inline]
pub fn unit_tolerance<T: Real>() -> T {
    T::EPSILON.sqrt()
}

/// A validated constraint table (see the [module documentation](self)).
#[derive(Clone, Copy, Debug)]
pub struct Constraints<'a, T, const D: usize> {
    kinds: &'a [u8],
    directions: &'a [[T; D]],
}

impl<'a, T: Real, const D: usize> Constraints<'a, T, D> {
    /// Validates a kind table and its directions.
    ///
    /// # Errors
    /// `directions.len() != kinds.len()`
    /// ([`Error::LengthMismatch`]); a kind code above 3 ([`Error::IndexOutOfRange`] on
    /// `kinds`, `bound` 4); a sliding node's direction not finite ([`Error::NonFinite`]) or
    /// not of unit length within [`unit_tolerance`] ([`Error::NotUnit`]).
    pub fn new(kinds: &'a [u8], directions: &'a [[T; D]]) -> Result<Self> {
        check::mesh_dim::<D>();
        check::len("directions", directions.len(), kinds.len())?;
        let tol = unit_tolerance::<T>();
        for (position, (&k, d)) in kinds.iter().zip(directions).enumerate() {
            match NodeKind::from_code(k) {
                None => {
                    return Err(Error::IndexOutOfRange {
                        arg: "kinds",
                        position,
                        index: k as usize,
                        bound: 4,
                    })
                }
                Some(NodeKind::Plane | NodeKind::Line) => {
                    if !d.iter().all(|c| c.is_finite()) {
                        return Err(Error::NonFinite {
                            arg: "directions",
                            position,
                        });
                    }
                    if (vector::norm_sq(*d) - T::ONE).abs() > tol {
                        return Err(Error::NotUnit {
                            arg: "directions",
                            position,
                        });
                    }
                }
                Some(_) => {}
            }
        }
        Ok(Constraints { kinds, directions })
    }

    /// The kind codes.
    #[inline]
    pub fn kinds(&self) -> &'a [u8] {
        self.kinds
    }

    /// The directions (normals / tangents).
    #[inline]
    pub fn directions(&self) -> &'a [[T; D]] {
        self.directions
    }

    /// Number of nodes.
    #[inline]
    pub fn len(&self) -> usize {
        self.kinds.len()
    }

    /// `true` when the table has no nodes.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.kinds.is_empty()
    }

    /// Node `i`'s kind ([`NodeKind::Fixed`] out of range: such a node never moves).
    #[inline]
    pub fn kind(&self, i: usize) -> NodeKind {
        self.kinds
            .get(i)
            .and_then(|&k| NodeKind::from_code(k))
            .unwrap_or(NodeKind::Fixed)
    }

    /// `P_i v`: `v` (free), 0 (fixed), `v − n (n·v)/(n·n)` (plane), `t (t·v)/(t·t)` (line).
    #[inline]
    pub fn project(&self, i: usize, v: [T; D]) -> [T; D] {
        let d = self.directions.get(i).copied().unwrap_or([T::ZERO; D]);
        match self.kind(i) {
            NodeKind::Free => v,
            NodeKind::Fixed => [T::ZERO; D],
            NodeKind::Plane => {
                let s = vector::dot(d, v) / vector::norm_sq(d);
                vector::sub(v, vector::scale(d, s))
            }
            NodeKind::Line => {
                let s = vector::dot(d, v) / vector::norm_sq(d);
                vector::scale(d, s)
            }
        }
    }

    /// `P_i` as a matrix (rows), for the block solves of the angle springs.
    pub(crate) fn matrix(&self, i: usize) -> [[T; D]; D] {
        let mut m = [[T::ZERO; D]; D];
        for (c, row) in m.iter_mut().enumerate() {
            let mut e = [T::ZERO; D];
            if let Some(x) = e.get_mut(c) {
                *x = T::ONE;
            }
            // P is symmetric: column c = row c.
            *row = self.project(i, e);
        }
        m
    }

    /// Writes the fixed mask (1 where the kind is [`NodeKind::Fixed`], else 0) that the
    /// [`SpringSystem`](crate::spring::SpringSystem) of a constrained solve must be built with.
    ///
    /// # Errors
    /// `mask.len() != self.len()` ([`Error::LengthMismatch`]; nothing written).
    pub fn fixed_mask(&self, mask: &mut [u8]) -> Result<()> {
        check::len("mask", mask.len(), self.len())?;
        for (m, &k) in mask.iter_mut().zip(self.kinds) {
            *m = u8::from(k == NodeKind::Fixed.code());
        }
        Ok(())
    }

    /// Checks that `fixed` (a spring system's mask, nonzero = fixed) marks exactly the nodes
    /// of kind [`NodeKind::Fixed`].
    pub(crate) fn check_mask(&self, fixed: &[u8]) -> Result<()> {
        check::len("constraints", self.len(), fixed.len())?;
        for (&m, &k) in fixed.iter().zip(self.kinds) {
            if (m != 0) != (k == NodeKind::Fixed.code()) {
                return Err(Error::InvalidParameter {
                    arg: "constraints",
                    reason: "must give kind 1 (fixed) exactly to the spring system's fixed nodes",
                });
            }
        }
        Ok(())
    }
}

/// Projects the motion of every sliding node onto its plane or line:
/// `points[i] = original[i] + P_i (points[i] − original[i])` for kinds 2 and 3; free and fixed
/// nodes are left as they are. Call it after a propagation ([`crate::quaternion`]'s IDW, TFI
/// or spring pipelines) in which the sliding nodes were ordinary field nodes.
///
/// # Errors
/// Nothing is written on error:
/// Lengths differ from `constraints.len()`; non-finite `original` or
/// `points`; a projected position that is not finite ([`Error::Overflow`] on `points`).
pub fn slide_points<T: Real, const D: usize>(
    constraints: &Constraints<'_, T, D>,
    original: &[[T; D]],
    points: &mut [[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = constraints.len();
    for (arg, len) in [("original", original.len()), ("points", points.len())] {
        check::len(arg, len, n)?;
    }
    for (arg, v) in [("original", original), ("points", &*points)] {
        check::finite_items(arg, v)?;
    }
    let moved = |i: usize, o: [T; D], p: [T; D]| -> [T; D] {
        vector::add(o, constraints.project(i, vector::sub(p, o)))
    };
    for (i, (&o, &p)) in original.iter().zip(points.iter()).enumerate() {
        if matches!(constraints.kind(i), NodeKind::Plane | NodeKind::Line)
            && !moved(i, o, p).iter().all(|c| c.is_finite())
        {
            return Err(Error::Overflow { arg: "points" });
        }
    }
    for (i, (&o, p)) in original.iter().zip(points.iter_mut()).enumerate() {
        if matches!(constraints.kind(i), NodeKind::Plane | NodeKind::Line) {
            *p = moved(i, o, *p);
        }
    }
    Ok(())
}

/// A least-squares plane (a line in 2D) through a node set.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFit<T, const D: usize> {
    /// Unit normal; its largest-magnitude component is positive (a deterministic sign).
    pub normal: [T; D],
    /// The centroid of the nodes (a point of the plane).
    pub point: [T; D],
    /// The fit residual: the largest distance `|n · (x − point)|` of a node from the plane.
    pub residual: T,
    /// The largest distance of a node from the centroid (the set's size, the scale of the
    /// tolerance).
    pub extent: T,
}

/// Fits a plane (3D) or line (2D) to `points[nodes[k]]` by least squares: the normal is the
/// eigenvector of the smallest eigenvalue of the centred scatter matrix (closed form in 2D,
/// cyclic Jacobi rotations in 3D), and refuses sets farther from it than
/// `tolerance · extent`. Pass `T::INFINITY` to never refuse and read [`PlaneFit::residual`].
///
/// # Errors
/// Fewer than `D` nodes or nodes that do not span a
/// plane (all coincident, or collinear in 3D) ([`Error::InvalidParameter`] on `nodes`); an
/// index `>= points.len()` ([`Error::IndexOutOfRange`]); a non-finite coordinate
/// ([`Error::NonFinite`] on `points`, position = the node index); `tolerance` NaN or negative
/// ([`Error::InvalidParameter`]); coordinates whose differences overflow
/// ([`Error::Overflow`]); a node farther than `tolerance · extent` from the plane
/// ([`Error::NotPlanar`] on `nodes`, position = the farthest one's position in `nodes`).
pub fn fit_plane<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    tolerance: T,
) -> Result<PlaneFit<T, D>> {
    check::mesh_dim::<D>();
    if tolerance.is_nan() || tolerance < T::ZERO {
        return Err(Error::InvalidParameter {
            arg: "tolerance",
            reason: "must be >= 0 (infinity: never refuse)",
        });
    }
    if nodes.len() < D {
        return Err(Error::InvalidParameter {
            arg: "nodes",
            reason: "needs at least D nodes",
        });
    }
    for (position, &i) in nodes.iter().enumerate() {
        match points.get(i as usize) {
            None => {
                return Err(Error::IndexOutOfRange {
                    arg: "nodes",
                    position,
                    index: i as usize,
                    bound: points.len(),
                })
            }
            Some(p) if !p.iter().all(|c| c.is_finite()) => {
                return Err(Error::NonFinite {
                    arg: "points",
                    position: i as usize,
                })
            }
            Some(_) => {}
        }
    }
    let at = |k: usize| -> [T; D] {
        nodes
            .get(k)
            .and_then(|&i| points.get(i as usize))
            .copied()
            .unwrap_or([T::ZERO; D])
    };
    // Running mean (cannot overflow for finite points).
    let mut c = [T::ZERO; D];
    for k in 0..nodes.len() {
        let w = T::ONE / T::from_usize(k + 1);
        c = vector::add(c, vector::scale(vector::sub(at(k), c), w));
    }
    let mut extent = T::ZERO;
    for k in 0..nodes.len() {
        extent = extent.max(vector::norm_robust(vector::sub(at(k), c)));
    }
    if !extent.is_finite() {
        return Err(Error::Overflow { arg: "points" });
    }
    if extent == T::ZERO {
        return Err(Error::InvalidParameter {
            arg: "nodes",
            reason: "coincide, so they do not span a plane",
        });
    }
    // Scatter of the centred points scaled by a power of two into [-2, 2].
    let s = T::pow2(-extent.exponent());
    let mut m = [[T::ZERO; D]; D];
    for k in 0..nodes.len() {
        let y = vector::scale(vector::sub(at(k), c), s);
        for (row, &a) in m.iter_mut().zip(&y) {
            for (e, &b) in row.iter_mut().zip(&y) {
                *e += a * b;
            }
        }
    }
    let normal = smallest_eigenvector(&m).ok_or(Error::InvalidParameter {
        arg: "nodes",
        reason: "are collinear, so they do not span a plane",
    })?;
    let mut residual = T::ZERO;
    let mut worst = 0;
    for k in 0..nodes.len() {
        let dist = vector::dot(normal, vector::sub(at(k), c)).abs();
        if dist > residual {
            residual = dist;
            worst = k;
        }
    }
    if residual > tolerance * extent {
        return Err(Error::NotPlanar {
            arg: "nodes",
            position: worst,
        });
    }
    Ok(PlaneFit {
        normal,
        point: c,
        residual,
        extent,
    })
}

/// The unit eigenvector of the smallest eigenvalue of the symmetric `m` (2×2 closed form,
/// 3×3 cyclic Jacobi), sign fixed so its largest component is positive; `None` when the
/// smallest eigenvalue is not separated from the next one (3D: a collinear set).
fn smallest_eigenvector<T: Real, const D: usize>(m: &[[T; D]; D]) -> Option<[T; D]> {
    let g = |i: usize, j: usize| m.get(i).and_then(|r| r.get(j)).copied().unwrap_or(T::ZERO);
    let mut out = [T::ZERO; D];
    if D == 2 {
        let (a, b, d) = (g(0, 0), g(0, 1), g(1, 1));
        let half = (a - d) * T::HALF;
        let lmin = (a + d) * T::HALF - half.hypot(b);
        let v = if b == T::ZERO {
            if a <= d {
                [T::ONE, T::ZERO]
            } else {
                [T::ZERO, T::ONE]
            }
        } else {
            let v1 = [b, lmin - a];
            let v2 = [lmin - d, b];
            if vector::norm_sq(v1) >= vector::norm_sq(v2) {
                v1
            } else {
                v2
            }
        };
        for (o, x) in out.iter_mut().zip(v) {
            *o = x;
        }
    } else {
        let mut a = [[T::ZERO; 3]; 3];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = g(i, j);
            }
        }
        let mut v = [
            [T::ONE, T::ZERO, T::ZERO],
            [T::ZERO, T::ONE, T::ZERO],
            [T::ZERO, T::ZERO, T::ONE],
        ];
        jacobi_eigen(&mut a, &mut v);
        let l = [a[0][0], a[1][1], a[2][2]];
        // Index of the smallest eigenvalue (first on ties), and the other two.
        let lo = if l[1] < l[0] {
            if l[2] < l[1] {
                2
            } else {
                1
            }
        } else if l[2] < l[0] {
            2
        } else {
            0
        };
        let (others, col) = match lo {
            0 => ([l[1], l[2]], [v[0][0], v[1][0], v[2][0]]),
            1 => ([l[0], l[2]], [v[0][1], v[1][1], v[2][1]]),
            _ => ([l[0], l[1]], [v[0][2], v[1][2], v[2][2]]),
        };
        let (lmid, lmax) = (others[0].min(others[1]), others[0].max(others[1]));
        if lmid.is_nan() || lmid <= T::from_f64(64.0) * T::EPSILON * lmax {
            return None;
        }
        for (o, x) in out.iter_mut().zip(col) {
            *o = x;
        }
    }
    let mut n = vector::normalize(out)?;
    let big = n
        .iter()
        .copied()
        .fold(T::ZERO, |acc, x| if x.abs() > acc.abs() { x } else { acc });
    if big < T::ZERO {
        n = vector::scale(n, -T::ONE);
    }
    Some(n)
}

/// Cyclic Jacobi eigenvalue iteration on a symmetric 3×3 matrix: on return `a` is (nearly)
/// diagonal with the eigenvalues and the columns of `v` are the eigenvectors. At most 32
/// sweeps (quadratic convergence needs fewer than 10).
fn jacobi_eigen<T: Real>(a: &mut [[T; 3]; 3], v: &mut [[T; 3]; 3]) {
    for _ in 0..32 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= T::EPSILON * T::EPSILON * diag || off == T::ZERO {
            return;
        }
        jacobi_rotate::<T, 0, 1>(a, v);
        jacobi_rotate::<T, 0, 2>(a, v);
        jacobi_rotate::<T, 1, 2>(a, v);
    }
}

/// One Jacobi rotation zeroing `a[P][Q]` (`A ← Jᵀ A J`, `V ← V J`); constant indices, so no
/// bounds checks.
fn jacobi_rotate<T: Real, const P: usize, const Q: usize>(
    a: &mut [[T; 3]; 3],
    v: &mut [[T; 3]; 3],
) {
    let apq = a[P][Q];
    if apq == T::ZERO {
        return;
    }
    let theta = (a[Q][Q] - a[P][P]) / (T::TWO * apq);
    // t = sign(θ) / (|θ| + √(θ² + 1)), or 1/(2θ) when θ² would overflow.
    let t = if theta.abs() > T::ONE / T::EPSILON {
        T::ONE / (T::TWO * theta)
    } else {
        let t = T::ONE / (theta.abs() + (theta * theta + T::ONE).sqrt());
        if theta < T::ZERO {
            -t
        } else {
            t
        }
    };
    let c = T::ONE / (t * t + T::ONE).sqrt();
    let s = t * c;
    for row in a.iter_mut() {
        let (akp, akq) = (row[P], row[Q]);
        row[P] = c * akp - s * akq;
        row[Q] = s * akp + c * akq;
    }
    let (rp, rq) = (a[P], a[Q]);
    for (k, (&apk, &aqk)) in rp.iter().zip(&rq).enumerate() {
        if let Some(x) = a[P].get_mut(k) {
            *x = c * apk - s * aqk;
        }
        if let Some(x) = a[Q].get_mut(k) {
            *x = s * apk + c * aqk;
        }
    }
    a[P][Q] = T::ZERO;
    a[Q][P] = T::ZERO;
    for row in v.iter_mut() {
        let (vp, vq) = (row[P], row[Q]);
        row[P] = c * vp - s * vq;
        row[Q] = s * vp + c * vq;
    }
}

/// The unit tangent of the line where two planes with normals `a` and `b` meet:
/// `(a × b) / |a × b|`.
///
/// # Errors
/// A non-finite component ([`Error::NonFinite`] on `normals`, position 0 or 1); planes
/// parallel to within `√ε` (`|a × b| ≤ √ε |a| |b|`, [`Error::ZeroLength`] on `normals`).
pub fn plane_intersection<T: Real>(a: [T; 3], b: [T; 3]) -> Result<[T; 3]> {
    for (position, v) in [a, b].iter().enumerate() {
        if !v.iter().all(|c| c.is_finite()) {
            return Err(Error::NonFinite {
                arg: "normals",
                position,
            });
        }
    }
    let (Some(a), Some(b)) = (vector::normalize(a), vector::normalize(b)) else {
        return Err(Error::ZeroLength {
            arg: "normals",
            position: 0,
        });
    };
    let t = vector::cross(a, b);
    if vector::norm(t) <= T::EPSILON.sqrt() {
        return Err(Error::ZeroLength {
            arg: "normals",
            position: 0,
        });
    }
    vector::normalize(t).ok_or(Error::ZeroLength {
        arg: "normals",
        position: 0,
    })
}
