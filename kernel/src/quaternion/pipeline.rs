//! One-call deformation pipelines: boundary rotations and translations, propagation, update.

use super::idw_fast::check_options_and_buffers;
use super::rotations::{origin_core, rigid_node_rotation, rotations_core, translation};
use super::springs::{propagate_spring_with, propagate_spring_with_scratch_len};
use super::{
    boundary_rotations_scratch_len, check_exponent, propagate_idw, propagate_idw_fast,
    propagate_tfi, tfi_scratch_len, update_points, IdwFastOptions, IdwFastReport, Pts,
};
use crate::block::{Block, Directions};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::spring::{LinearMethod, LinearSolver, SolveOptions, SolveReport, SpringSystem};

/// Where the boundary rotations come from.
#[derive(Clone, Copy, Debug)]
pub enum RotationSource<'a, T> {
    /// From the undeformed and deformed boundary shapes
    /// ([`boundary_rotations`](super::boundary_rotations)); needs
    /// [`BoundaryMotion::elements`].
    Shape,
    /// One rigid rotation for the moving boundary (a rigid body whose motion is known). A node
    /// that stays exactly in place although the rotation about the origin would move it is
    /// not part of the body (a fixed far field or wall) and gets the identity, as `deform
    /// move` gives it; nodes on the rotation axis keep the rotation.
    Rigid(Quat<T>),
    /// One rotation per boundary node, in [`BoundaryMotion::nodes`] order (for example several
    /// markers filled with [`rigid_rotations`](super::rigid_rotations) and
    /// [`boundary_rotations`](super::boundary_rotations) on sub-slices).
    PerNode(&'a [Quat<T>]),
}

/// The prescribed boundary motion of a mesh: which nodes move where, and how they turn.
#[derive(Clone, Copy, Debug)]
pub struct BoundaryMotion<'a, T, const D: usize> {
    /// Mesh node of each of the `B` boundary points (distinct). Include fixed boundaries (far
    /// field) with `deformed` equal to their position: they anchor the propagation.
    pub nodes: &'a [u32],
    /// Deformed position `r^d` of each boundary point; reproduced exactly in the output.
    pub deformed: &'a [[T; D]],
    /// Boundary elements indexing `0..B` (segments in 2D, triangles/quadrilaterals in 3D);
    /// needed for [`RotationSource::Shape`].
    pub elements: Option<Cells<'a>>,
    /// Where the rotations come from.
    pub rotations: RotationSource<'a, T>,
    /// The rotation origin `o`; `None` for [`boundary_origin`](super::boundary_origin) (the
    /// centroid of the moving boundary points).
    pub origin: Option<[T; D]>,
}

/// Validates the sizes and the motion. Leaves marks in `scratch[..N]`: 1 at boundary nodes,
/// 0 elsewhere (checked for duplicates here, for block-face coverage by [`deform_tfi`]).
fn validate<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    scratch: &mut [T],
    rot_scratch_needed: usize,
    out: &[[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = points.len();
    check::len("translations", translations.len(), n)?;
    check::len("rotations", rotations.len(), n)?;
    check::len("out", out.len(), n)?;
    validate_motion(points, motion, scratch, rot_scratch_needed)
}

/// The checks of [`validate`] on the points and the motion alone (also those of the
/// sensitivities); leaves the same marks in `scratch[..N]`.
pub(super) fn validate_motion<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    scratch: &mut [T],
    rot_scratch_needed: usize,
) -> Result<()> {
    check::mesh_dim::<D>();
    let n = points.len();
    let b = motion.nodes.len();
    check::len("motion.deformed", motion.deformed.len(), b)?;
    if b == 0 {
        return Err(Error::InvalidParameter {
            arg: "motion.nodes",
            reason: "must not be empty",
        });
    }
    check::buffer("scratch", scratch.len(), n.max(rot_scratch_needed))?;
    check::indices("motion.nodes", motion.nodes, n)?;
    match motion.rotations {
        RotationSource::Shape => {
            if motion.elements.is_none() {
                return Err(Error::InvalidParameter {
                    arg: "motion.elements",
                    reason: "is required for rotations from the boundary shape",
                });
            }
        }
        RotationSource::Rigid(q) => {
            check::quats("motion.rotations", core::slice::from_ref(&q))?;
        }
        RotationSource::PerNode(q) => {
            check::len("motion.rotations", q.len(), b)?;
            check::quats("motion.rotations", q)?;
        }
    }
    if let Some(o) = motion.origin {
        for x in o {
            check::scalar("motion.origin", x)?;
        }
    }
    check::finite_items("points", points)?;
    check::finite_items("motion.deformed", motion.deformed)?;
    // Duplicate check, leaving the marks in scratch[..n].
    let marks = scratch.get_mut(..n).unwrap_or(&mut []);
    for m in marks.iter_mut() {
        *m = T::ZERO;
    }
    for (position, &node) in motion.nodes.iter().enumerate() {
        if let Some(m) = marks.get_mut(node as usize) {
            if *m != T::ZERO {
                return Err(Error::DuplicateNode {
                    arg: "motion.nodes",
                    position,
                    node: node as usize,
                });
            }
            *m = T::ONE;
        }
    }
    Ok(())
}

/// Computes the boundary rotations and translations into the field arrays (everything that can
/// fail in the rotation step fails before the first write). Returns the origin.
fn boundary_values<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
) -> Result<[T; D]> {
    let origin = motion_origin(points, motion)?;
    boundary_rotations_with(points, motion, origin, scratch, |k, q| {
        if let Some(r) = motion
            .nodes
            .get(k)
            .and_then(|&i| rotations.get_mut(i as usize))
        {
            *r = q;
        }
    })?;
    let u = Pts::mapped(points, motion.nodes);
    for (k, (&i, &dk)) in motion.nodes.iter().zip(motion.deformed).enumerate() {
        let q = rotations
            .get(i as usize)
            .copied()
            .unwrap_or(Quat::identity())
            .normalize()
            .unwrap_or(Quat::identity());
        if let Some(t) = translations.get_mut(i as usize) {
            *t = translation(origin, u.get(k), dk, q);
        }
    }
    Ok(origin)
}

/// The origin of a validated motion: `motion.origin`, or [`origin_core`]'s default.
pub(super) fn motion_origin<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
) -> Result<[T; D]> {
    match motion.origin {
        Some(o) => Ok(o),
        None => origin_core(
            Pts::mapped(points, motion.nodes),
            Pts::direct(motion.deformed),
        ),
    }
}

/// The boundary rotation of every boundary point `k` (from `motion.rotations`), handed to
/// `put(k, Q_k)`; for the shape every rotation is computed before the first call.
pub(super) fn boundary_rotations_with<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    origin: [T; D],
    scratch: &mut [T],
    mut put: impl FnMut(usize, Quat<T>),
) -> Result<()> {
    let u = Pts::mapped(points, motion.nodes);
    let d = Pts::direct(motion.deformed);
    match (motion.rotations, motion.elements.as_ref()) {
        (RotationSource::Shape, Some(elements)) => rotations_core(u, d, elements, scratch, put)?,
        (RotationSource::Shape, None) => {
            return Err(Error::InvalidParameter {
                arg: "motion.elements",
                reason: "is required for rotations from the boundary shape",
            })
        }
        (RotationSource::Rigid(q), _) => {
            let q = q.normalize()?;
            for k in 0..motion.nodes.len() {
                put(k, rigid_node_rotation(q, origin, u.get(k), d.get(k)));
            }
        }
        (RotationSource::PerNode(qs), _) => {
            for (k, &q) in qs.iter().enumerate().take(motion.nodes.len()) {
                put(k, q);
            }
        }
    }
    Ok(())
}

/// [`validate`] with the scratch the boundary rotations need: the checks [`deform_idw`],
/// [`deform_idw_fast`] and [`deform_spring_with`] share.
fn validate_unstructured<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    translations: &[[T; D]],
    rotations: &[Quat<T>],
    scratch: &mut [T],
    out: &[[T; D]],
) -> Result<()> {
    validate(
        points,
        motion,
        translations,
        rotations,
        scratch,
        boundary_rotations_scratch_len::<D>(motion.nodes.len()),
        out,
    )
}

/// Length of the `scratch` slice [`deform_idw`] needs: `max(N, rotation scratch)`.
#[inline]
pub fn deform_idw_scratch_len<const D: usize>(node_count: usize, boundary_len: usize) -> usize {
    node_count.max(boundary_rotations_scratch_len::<D>(boundary_len))
}

/// The whole quaternion deformation with inverse-distance propagation: boundary rotations
/// (from `motion.rotations`), origin, translations `Δ` (see
/// [`boundary_translations`](super::boundary_translations)), [`propagate_idw`] with
/// `exponent`, and [`update_points`] into `out`. Returns the origin used.
///
/// `points` are the undeformed mesh points (`N`). `translations` and `rotations` (`N`
/// entries each) receive the propagated fields; `scratch` needs [`deform_idw_scratch_len`]
/// entries.
///
/// # Errors
/// Those of the steps, plus [`Error::DuplicateNode`] for a node listed twice.
/// On error `out` is unchanged (`translations`, `rotations` and `scratch` are workspaces and
/// may have been written).
pub fn deform_idw<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<[T; D]> {
    validate_unstructured(points, motion, translations, rotations, scratch, out)?;
    check_exponent(exponent)?;
    let origin = boundary_values(points, motion, translations, rotations, scratch)?;
    propagate_idw(points, motion.nodes, exponent, translations, rotations)?;
    update_points(
        origin,
        points,
        translations,
        rotations,
        motion.nodes,
        motion.deformed,
        out,
    )?;
    Ok(origin)
}

/// [`deform_idw`] with the fast, tree-based propagation
/// [`propagate_idw_fast`](super::propagate_idw_fast) (far-field clusters, per-point bound
/// `η ≤ options.tolerance`). `index` and `tree` are its buffers
/// ([`propagate_idw_fast_index_len`](super::propagate_idw_fast_index_len),
/// [`propagate_idw_fast_scratch_len`](super::propagate_idw_fast_scratch_len) for `B =
/// motion.nodes.len()`); `scratch` as for [`deform_idw`]. Returns the origin and the
/// propagation report.
///
/// # Errors
/// Those of [`deform_idw`] and of the options and buffers; on
/// error `out` is unchanged.
#[allow(clippy::too_many_arguments)]
pub fn deform_idw_fast<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    exponent: T,
    options: &IdwFastOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    index: &mut [u32],
    tree: &mut [T],
    out: &mut [[T; D]],
) -> Result<([T; D], IdwFastReport<T>)> {
    validate_unstructured(points, motion, translations, rotations, scratch, out)?;
    check_exponent(exponent)?;
    check_options_and_buffers::<T, D>(
        options,
        motion.nodes.len(),
        index.len(),
        tree.len(),
        "tree",
    )?;
    let origin = boundary_values(points, motion, translations, rotations, scratch)?;
    let report = propagate_idw_fast(
        points,
        motion.nodes,
        exponent,
        options,
        index,
        tree,
        translations,
        rotations,
        None,
    )?;
    update_points(
        origin,
        points,
        translations,
        rotations,
        motion.nodes,
        motion.deformed,
        out,
    )?;
    Ok((origin, report))
}

/// Length of the `scratch` slice [`deform_tfi`] needs: `max(D N, rotation scratch)`.
#[inline]
pub fn deform_tfi_scratch_len<const D: usize>(block: &Block, boundary_len: usize) -> usize {
    tfi_scratch_len::<D>(block).max(boundary_rotations_scratch_len::<D>(boundary_len))
}

/// The whole quaternion deformation of a structured block with transfinite interpolation:
/// as [`deform_idw`], with [`propagate_tfi`] over the active `directions` instead. Every point
/// on a face of an active direction must be listed in `motion.nodes` (else
/// [`Error::Unanchored`] names the first missing point); listed points off those faces are
/// placed exactly but do not steer the interpolation.
///
/// `scratch` needs [`deform_tfi_scratch_len`] entries. On error `out` is unchanged; only a
/// blended rotation that cancels to zero (see [`propagate_tfi`]) is detected after
/// `translations` and `rotations` were written.
///
/// # Errors
/// Those of [`deform_idw`] for the motion and points, the block's errors of [`propagate_tfi`]
/// (inactive or degenerate directions, a face point missing from `motion.nodes`:
/// [`Error::Unanchored`]), `scratch` too short ([`Error::BufferTooSmall`]).
#[allow(clippy::too_many_arguments)]
pub fn deform_tfi<T: Real, const D: usize>(
    block: &Block,
    directions: Directions,
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    out: &mut [[T; D]],
) -> Result<[T; D]> {
    validate(
        points,
        motion,
        translations,
        rotations,
        scratch,
        deform_tfi_scratch_len::<D>(block, motion.nodes.len()),
        out,
    )?;
    check::len("points", points.len(), block.point_count())?;
    super::tfi::check_directions::<D>(block, directions)?;
    let dims = block.dims();
    for (p, m) in scratch.iter().take(points.len()).enumerate() {
        let c = block.ijk(p);
        let on_face = c
            .iter()
            .zip(dims.iter())
            .zip(directions.flags().iter())
            .any(|((&x, &nd), &on)| on && (x == 0 || x + 1 == nd));
        if on_face && *m == T::ZERO {
            return Err(Error::Unanchored { node: p });
        }
    }
    let origin = boundary_values(points, motion, translations, rotations, scratch)?;
    propagate_tfi(block, directions, points, translations, rotations, scratch)?;
    update_points(
        origin,
        points,
        translations,
        rotations,
        motion.nodes,
        motion.deformed,
        out,
    )?;
    Ok(origin)
}

/// Length of the `scratch` slice [`deform_spring`] needs: `max(N, rotation scratch)` (its
/// `values` workspace needs [`propagate_spring_scratch_len`](super::propagate_spring_scratch_len) scalars).
#[inline]
pub fn deform_spring_scratch_len<const D: usize>(node_count: usize, boundary_len: usize) -> usize {
    deform_idw_scratch_len::<D>(node_count, boundary_len)
}

/// The whole quaternion deformation with linear-spring propagation (Samareh's unstructured
/// variant): boundary rotations and translations as in [`deform_idw`], then
/// [`propagate_spring`](super::propagate_spring) on `sys` (whose fixed mask must mark exactly `motion.nodes`), then
/// [`update_points`]. Returns the origin and the solver report; `out` is written even when the
/// solver did not converge (check the report).
///
/// `scratch` needs [`deform_spring_scratch_len`] entries and `values`
/// [`propagate_spring_scratch_len`](super::propagate_spring_scratch_len) scalars. On error
/// `out` is unchanged; solver errors are detected after the boundary entries of
/// `translations` and `rotations` were written.
///
/// # Errors
/// Those of [`deform_idw`] for the motion and points; a system whose fixed mask differs from
/// `motion.nodes` ([`Error::InvalidParameter`]); buffers too short
/// ([`Error::BufferTooSmall`]); the solver's errors ([`Error::SingularSystem`],
/// [`Error::Overflow`]).
#[allow(clippy::too_many_arguments)]
pub fn deform_spring<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    sys: &SpringSystem<'_, T>,
    method: LinearMethod<T>,
    options: &SolveOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    values: &mut [T],
    out: &mut [[T; D]],
) -> Result<([T; D], SolveReport<T>)> {
    deform_spring_with(
        points,
        motion,
        sys,
        LinearSolver::Method(method),
        options,
        translations,
        rotations,
        scratch,
        values,
        out,
    )
}

/// [`deform_spring`] with any linear-spring solver, e.g. the multigrid-preconditioned CG
/// ([`LinearSolver::Amg`], hierarchy built for `sys`); `values` needs
/// [`propagate_spring_with_scratch_len`](super::propagate_spring_with_scratch_len) scalars.
/// Otherwise identical.
///
/// # Errors
/// Those of [`deform_spring`], and a hierarchy built for another system.
#[allow(clippy::too_many_arguments)]
pub fn deform_spring_with<T: Real, const D: usize>(
    points: &[[T; D]],
    motion: &BoundaryMotion<'_, T, D>,
    sys: &SpringSystem<'_, T>,
    solver: LinearSolver<'_, T>,
    options: &SolveOptions<T>,
    translations: &mut [[T; D]],
    rotations: &mut [Quat<T>],
    scratch: &mut [T],
    values: &mut [T],
    out: &mut [[T; D]],
) -> Result<([T; D], SolveReport<T>)> {
    validate_unstructured(points, motion, translations, rotations, scratch, out)?;
    check::len("sys", sys.node_count(), points.len())?;
    check::buffer(
        "values",
        values.len(),
        propagate_spring_with_scratch_len::<D>(&solver, points.len()),
    )?;
    for (m, &f) in scratch.iter().zip(sys.fixed()) {
        if (*m != T::ZERO) != crate::spring::is_fixed(f) {
            return Err(Error::InvalidParameter {
                arg: "sys",
                reason: "the fixed mask must mark exactly the boundary nodes",
            });
        }
    }
    let origin = boundary_values(points, motion, translations, rotations, scratch)?;
    let report = propagate_spring_with(sys, solver, options, translations, rotations, values)?;
    update_points(
        origin,
        points,
        translations,
        rotations,
        motion.nodes,
        motion.deformed,
        out,
    )?;
    Ok((origin, report))
}
