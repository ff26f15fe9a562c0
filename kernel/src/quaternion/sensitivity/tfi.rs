//! Tangent and adjoint of the quaternion deformation of a structured block with transfinite
//! interpolation ([`deform_tfi`](crate::quaternion::deform_tfi)).
//!
//! The blending weights `w_pj` (Soni's arclength of the *undeformed* grid lines, boolean-sum
//! signs) are constants, so after the boundary stage the propagation is linear in the face
//! values but for the normalisation of the blended rotation: at an interior point `p`
//! `Δ_p = Σ_j w_pj Δ_j` and `Q_p = S_p / |S_p|`, `S_p = Σ_j w_pj s_pj Q_j` with the hemisphere
//! signs `s_pj` (alignment to the first term's rotation) held. Hence
//!
//! - **tangent**: `δΔ_p = Σ w_pj δΔ_j`, `δQ_p = (I − Q_p Q_pᵀ) Σ w_pj s_pj δQ_j / |S_p|`,
//!   `δR_p = δΔ_p + M(Q_p, r_p − o) δQ_p`; listed nodes take `δd`;
//! - **adjoint**: `Δ̄_j += w_pj w_p`, `Q̄_j += w_pj s_pj (I − Q_p Q_pᵀ) M(Q_p, r_p − o)ᵀ w_p /
//!   |S_p|` over the interior points not listed in the motion, then the boundary stage's
//!   transpose (shared with [`deform_idw_adjoint`](super::deform_idw_adjoint)).
//!
//! Face values live at mesh nodes (the blend indexes the block), so both modes scatter the
//! boundary stage's `Q_k`, `δQ_k`/`Q̄_k`, `δΔ_k`/`Δ̄_k` to per-node arrays in scratch.

use super::boundary::{add_to, get3};
use super::field::accumulate;
use super::lin::{axpy, drot, mul34, mul34t, proj4};
use super::{
    boundary_adjoint, boundary_adjoint_check, boundary_tangent, deform_idw_sensitivity_scratch_len,
    prepare,
};
use crate::block::{Block, Directions};
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::quaternion::tfi::{setup, Setup, MAX_TERMS};
use crate::quaternion::{drop3, lift, load, store, take, BoundaryMotion};
use crate::real::Real;
use crate::vector::{add, sub};

/// Scalars per mesh node besides the arclength parameters: `Q` (4), `δQ`/`Q̄` (4), `δΔ`/`Δ̄`
/// (3).
const PER_NODE: usize = 11;

/// Length of the `scratch` slice [`deform_tfi_tangent`] and [`deform_tfi_adjoint`] need:
/// `max(N, 32 B) + (D + 11) N` for the block's `N` points (`usize::MAX` on overflow).
#[inline]
pub fn deform_tfi_sensitivity_scratch_len<const D: usize>(
    block: &Block,
    boundary_len: usize,
) -> usize {
    let n = block.point_count();
    deform_idw_sensitivity_scratch_len::<D>(n, boundary_len)
        .saturating_add(n.saturating_mul(D + PER_NODE))
}

/// The parts of the scratch: the boundary stage's, the arclength parameters, per-node `Q`,
/// `δQ`/`Q̄` and `δΔ`/`Δ̄`.
struct Parts<'s, T> {
    bnd: &'s mut [T],
    params: &'s mut [T],
    q: &'s mut [T],
    dq: &'s mut [T],
    dt: &'s mut [T],
}

/// The fixed problem of both modes.
struct Problem<'a, 'm, T: Real, const D: usize> {
    block: &'a Block,
    directions: Directions,
    points: &'a [[T; D]],
    motion: &'a BoundaryMotion<'m, T, D>,
}

impl<T: Real, const D: usize> Problem<'_, '_, T, D> {
    /// Validates everything [`deform_tfi`](crate::quaternion::deform_tfi) validates, splits
    /// `scratch`, computes the boundary rotations and the blending parameters, and scatters
    /// `Q_k` to the nodes (zero elsewhere). Returns the origin, the TFI set-up and the parts.
    fn prepare<'s>(&self, scratch: &'s mut [T]) -> Result<([T; D], Setup, Parts<'s, T>)> {
        let (n, b) = (self.points.len(), self.motion.nodes.len());
        check::len("points", n, self.block.point_count())?;
        let needed = deform_tfi_sensitivity_scratch_len::<D>(self.block, b);
        check::buffer("scratch", scratch.len(), needed)?;
        let (bnd, rest) = take(scratch, deform_idw_sensitivity_scratch_len::<D>(n, b));
        let (params, rest) = take(rest, n.saturating_mul(D));
        let (q, rest) = take(rest, 4 * n);
        let (dq, dt) = take(rest, 4 * n);
        let (block, directions) = (self.block, self.directions);
        let mut faces = None;
        let origin = prepare(self.points, self.motion, bnd, |marks| {
            let s = setup::<T, D>(block, directions, self.points, n, "points", n * D)?;
            if let Some(p) = (0..n).find(|&p| s.on_face(s.ijk(p)) && marks.get(p) == Some(&T::ZERO))
            {
                return Err(Error::Unanchored { node: p });
            }
            faces = Some(s);
            Ok(())
        })?;
        let s = faces.ok_or(Error::InvalidParameter {
            arg: "block",
            reason: "no set-up",
        })?;
        s.arclength(self.points, params);
        q.fill(T::ZERO);
        for (k, &i) in self.motion.nodes.iter().enumerate() {
            store::<T, 4>(q, i as usize, load(bnd, k));
        }
        let parts = Parts {
            bnd,
            params,
            q,
            dq,
            dt,
        };
        check_blends(&s, &parts)?;
        Ok((origin, s, parts))
    }
}

/// The unit rotation `Q_p = S_p / |S_p|` and `|S_p|` of an interior point with blending
/// `terms`: `S_p = Σ w_pj s_pj Q_j`, the hemisphere signs against the first term's rotation
/// (as the forward flips); `None` when `S_p` cannot be normalised.
fn rotation<T: Real>(terms: &[(usize, T)], q: &[T]) -> Option<(Quat<T>, T)> {
    let r = reference(terms, q);
    let mut sum = [T::ZERO; 4];
    for &(j, w) in terms {
        axpy(&mut sum, w * sign(q, j, r), load(q, j));
    }
    let sum = Quat::from_array(sum);
    sum.normalize().ok().map(|u| (u, sum.norm()))
}

/// The hemisphere reference of a blend: the first term's rotation.
#[inline]
fn reference<T: Real>(terms: &[(usize, T)], q: &[T]) -> Quat<T> {
    Quat::from_array(terms.first().map_or([T::ZERO; 4], |t| load(q, t.0)))
}

/// The forward's dry run: every interior blended rotation must normalise.
fn check_blends<T: Real>(s: &Setup, parts: &Parts<'_, T>) -> Result<()> {
    let mut terms = [(0usize, T::ZERO); MAX_TERMS];
    for p in (0..s.n).filter(|&p| !s.on_face(s.ijk(p))) {
        let m = s.terms(p, parts.params, &mut terms);
        if rotation(terms.get(..m).unwrap_or_default(), parts.q).is_none() {
            return Err(Error::ZeroLength {
                arg: "rotations",
                position: p,
            });
        }
    }
    Ok(())
}

/// The hemisphere sign `s_pj` of term node `j` against reference `r`.
#[inline]
fn sign<T: Real>(q: &[T], j: usize, r: Quat<T>) -> T {
    if Quat::from_array(load(q, j)).dot(r) < T::ZERO {
        -T::ONE
    } else {
        T::ONE
    }
}

/// Tangent of [`deform_tfi`](crate::quaternion::deform_tfi): the first-order change `out = δR`
/// of every block point for the change `direction = δd` of the deformed boundary positions
/// (`motion.deformed`, one per boundary point), the undeformed `points` held. Listed nodes
/// get `δd` exactly. `scratch` needs [`deform_tfi_sensitivity_scratch_len`] entries.
///
/// # Errors
/// Those of [`deform_tfi`](crate::quaternion::deform_tfi) (motion, points, block, directions,
/// an unlisted face point: [`Error::Unanchored`], a blended rotation that cancels:
/// [`Error::ZeroLength`] `"rotations"`); `direction` or `out` of the wrong length, a
/// non-finite `direction`; those of the boundary stage of
/// [`deform_idw_tangent`](super::deform_idw_tangent) (antiparallel normals). On error `out` is
/// unchanged.
pub fn deform_tfi_tangent<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    direction: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let b = motion.nodes.len();
    check::len("direction", direction.len(), b)?;
    check::len("out", out.len(), points.len())?;
    let problem = Problem {
        block,
        directions,
        points,
        motion,
    };
    let (origin, s, parts) = problem.prepare(scratch)?;
    check::finite_items("direction", direction)?;
    boundary_tangent(points, motion, origin, direction, parts.bnd)?;
    let (_, rest) = take(parts.bnd, 4 * b);
    let (dqb, rest) = take(rest, 4 * b);
    let (dtb, _) = take(rest, 3 * b);
    for (k, &i) in motion.nodes.iter().enumerate() {
        store::<T, 4>(parts.dq, i as usize, load(dqb, k));
        store::<T, 3>(parts.dt, i as usize, load(dtb, k));
    }
    let mut terms = [(0usize, T::ZERO); MAX_TERMS];
    for p in 0..s.n {
        if s.on_face(s.ijk(p)) {
            continue;
        }
        let m = s.terms(p, parts.params, &mut terms);
        let t = terms.get(..m).unwrap_or_default();
        let (q, len) = rotation(t, parts.q).unwrap_or((Quat::identity(), T::ONE));
        let r = reference(t, parts.q);
        let (mut ds, mut dtv) = ([T::ZERO; 4], [T::ZERO; 3]);
        for &(j, w) in t.iter() {
            axpy(&mut ds, w * sign(parts.q, j, r), load(parts.dq, j));
            axpy(&mut dtv, w, load(parts.dt, j));
        }
        let x = points.get(p).copied().unwrap_or([T::ZERO; D]);
        let mrot = drot(q, lift(sub(x, origin)));
        if let Some(o) = out.get_mut(p) {
            *o = drop3(add(dtv, mul34(&mrot, proj4(q, len, ds))));
        }
    }
    for (&i, &dd) in motion.nodes.iter().zip(direction) {
        if let Some(o) = out.get_mut(i as usize) {
            *o = dd;
        }
    }
    Ok(())
}

/// Adjoint of [`deform_tfi`](crate::quaternion::deform_tfi): `out = (∂R/∂d)ᵀ w` for the
/// weights `weights = w = dJ/dR` (one per block point), i.e. `dJ/dd` at each boundary point
/// (in `motion.nodes` order): the transpose of [`deform_tfi_tangent`]. `scratch` needs
/// [`deform_tfi_sensitivity_scratch_len`] entries.
///
/// # Errors
/// Those of [`deform_tfi_tangent`], with `weights` (one per point, finite) in place of
/// `direction` and `out` one per boundary point. On error `out` is unchanged.
pub fn deform_tfi_adjoint<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    weights: &[[T; D]],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<()> {
    let b = motion.nodes.len();
    check::len("weights", weights.len(), points.len())?;
    check::len("out", out.len(), b)?;
    let problem = Problem {
        block,
        directions,
        points,
        motion,
    };
    let (origin, s, parts) = problem.prepare(scratch)?;
    check::finite_items("weights", weights)?;
    boundary_adjoint_check(points, motion, parts.bnd)?;
    parts.dq.fill(T::ZERO);
    parts.dt.fill(T::ZERO);
    let mut terms = [(0usize, T::ZERO); MAX_TERMS];
    for p in 0..s.n {
        // Listed points are placed at `d`: their weight does not pass through the blend.
        let listed = load::<T, 4>(parts.q, p) != [T::ZERO; 4];
        if listed || s.on_face(s.ijk(p)) {
            continue;
        }
        let m = s.terms(p, parts.params, &mut terms);
        let t = terms.get(..m).unwrap_or_default();
        let (q, len) = rotation(t, parts.q).unwrap_or((Quat::identity(), T::ONE));
        let r = reference(t, parts.q);
        let g = get3(weights, p);
        let x = points.get(p).copied().unwrap_or([T::ZERO; D]);
        let qb = proj4(q, len, mul34t(&drot(q, lift(sub(x, origin))), g));
        for &(j, w) in t.iter() {
            accumulate(parts.dq, j, w * sign(parts.q, j, r), qb);
            accumulate(parts.dt, j, w, g);
        }
    }
    let (_, rest) = take(parts.bnd, 4 * b);
    let (dqb, rest) = take(rest, 4 * b);
    let (dtb, _) = take(rest, 3 * b);
    for (k, &i) in motion.nodes.iter().enumerate() {
        store::<T, 4>(dqb, k, load(parts.dq, i as usize));
        store::<T, 3>(dtb, k, load(parts.dt, i as usize));
    }
    for o in out.iter_mut() {
        *o = [T::ZERO; D];
    }
    for (k, &i) in motion.nodes.iter().enumerate() {
        add_to(out, k, get3(weights, i as usize));
    }
    boundary_adjoint(points, motion, origin, parts.bnd, out)
}
