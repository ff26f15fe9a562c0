//! Area-weighted boundary node normals.

use super::{drop3, load, store, Pts};
use crate::cells::{CellKind, Cells};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::vector::{cross, norm, scale, sub};

/// Checks that `elements` indexes `point_count` points and has the kinds `D` allows: line
/// segments in 2D, triangles and quadrilaterals in 3D.
pub(crate) fn check_elements<const D: usize>(
    elements: &Cells<'_>,
    point_count: usize,
) -> Result<()> {
    check::mesh_dim::<D>();
    check::len("elements.node_count", elements.node_count(), point_count)?;
    for (cell, (kind, _)) in elements.iter().enumerate() {
        let ok = match kind {
            CellKind::Line => D == 2,
            CellKind::Triangle | CellKind::Quad => D == 3,
            _ => false,
        };
        if !ok {
            return Err(Error::CellDimension {
                cell,
                kind: kind.vtk_code(),
                dimension: D,
            });
        }
    }
    Ok(())
}

/// The raw (area-weighted) normal of one boundary element, lifted to 3D: `(t_y, −t_x)` for a
/// segment with tangent `t` (length = segment length), `(b − a) × (c − a)` for a triangle and
/// `(c − a) × (d − b)` for a quadrilateral (both twice the area).
#[inline]
pub(super) fn element_normal<T: Real, const D: usize>(
    points: Pts<'_, T, D>,
    kind: CellKind,
    nodes: &[u32],
) -> [T; 3] {
    let p = |k: usize| -> [T; 3] { points.get3(nodes.get(k).map_or(usize::MAX, |&n| n as usize)) };
    match kind {
        CellKind::Line => {
            let t = sub(p(1), p(0));
            [t[1], -t[0], T::ZERO]
        }
        CellKind::Triangle => cross(sub(p(1), p(0)), sub(p(2), p(0))),
        CellKind::Quad => cross(sub(p(2), p(0)), sub(p(3), p(1))),
        _ => [T::ZERO; 3],
    }
}

/// Unit node normals into `acc` (flat, 3 per node). Elements and points must be validated.
/// Errors: [`Error::IsolatedNode`] for a node in no element, [`Error::ZeroLength`] (argument
/// `"normals"`, position = node) when the element normals cancel (for example two antiparallel
/// faces meeting at a cusp).
pub(super) fn unit_normals<T: Real, const D: usize>(
    points: Pts<'_, T, D>,
    elements: &Cells<'_>,
    acc: &mut [T],
) -> Result<()> {
    for x in acc.iter_mut() {
        *x = T::ZERO;
    }
    for (kind, nodes) in elements.iter() {
        let n = element_normal(points, kind, nodes);
        for &v in nodes {
            let a: [T; 3] = load(acc, v as usize);
            store(acc, v as usize, [a[0] + n[0], a[1] + n[1], a[2] + n[2]]);
        }
    }
    for i in 0..points.len() {
        let a: [T; 3] = load(acc, i);
        let l = norm(a);
        if !(l.is_finite() && l >= T::MIN_POSITIVE) {
            let used = elements.nodes().iter().any(|&v| v as usize == i);
            return Err(if used {
                Error::ZeroLength {
                    arg: "normals",
                    position: i,
                }
            } else {
                Error::IsolatedNode { node: i }
            });
        }
        store(acc, i, scale(a, T::ONE / l));
    }
    Ok(())
}

/// Length of the `scratch` slice [`boundary_normals`] needs: `3 × boundary_len`.
#[inline]
pub fn boundary_normals_scratch_len(boundary_len: usize) -> usize {
    boundary_len.saturating_mul(3)
}

/// Unit normals of a boundary at its nodes, area-weighted: each node's normal is the sum of
/// the raw normals of the elements around it (length = segment length in 2D, twice the face
/// area in 3D), normalised. This is the `n` of Samareh's step 2 (eq. 5).
///
/// `points` are the boundary's `B` points; `elements` index them: line segments in 2D,
/// triangles and quadrilaterals in 3D. The orientation follows each element's node order
/// (right-hand rule; in 2D the normal of `a → b` is `(t_y, −t_x)`, outward for a
/// counter-clockwise loop), so elements must be ordered consistently: where neighbouring
/// elements disagree their normals cancel. `scratch` needs [`boundary_normals_scratch_len`]
/// entries; its contents afterwards are unspecified.
///
/// # Errors
/// Length mismatches, non-finite points, wrong element kinds,
/// [`Error::IsolatedNode`] for a point in no element, [`Error::ZeroLength`] (`"normals"`,
/// position = node) when the element normals at a node cancel. On error `normals` is unchanged.
pub fn boundary_normals<T: Real, const D: usize>(
    points: &[[T; D]],
    elements: &Cells<'_>,
    scratch: &mut [T],
    normals: &mut [[T; D]],
) -> Result<()> {
    check_elements::<D>(elements, points.len())?;
    check::len("normals", normals.len(), points.len())?;
    check::buffer(
        "scratch",
        scratch.len(),
        boundary_normals_scratch_len(points.len()),
    )?;
    let pts = Pts::direct(points);
    pts.check_finite("points")?;
    unit_normals(pts, elements, scratch)?;
    for (i, n) in normals.iter_mut().enumerate() {
        *n = drop3(load(scratch, i));
    }
    Ok(())
}
