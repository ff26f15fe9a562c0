//! Quaternion mesh deformation (Samareh, NASA TM-2002-211646).
//!
//! The boundary motion is split into a rotation `Q_i` and a translation `Δ_i` per boundary
//! node; both are propagated into the field and every point is moved by (eq. 6)
//!
//! ```text
//! R^d = o + Δ + Q (R^u − o) Q*
//! ```
//!
//! about an origin `o`. Because the rotation is carried along, cells near a rotating wall turn
//! with it instead of being sheared, so large rotations keep near-wall cells intact.
//!
//! The steps, each a separate entry point so callers can mix them:
//! 1. [`boundary_normals`]: area-weighted node normals of the boundary elements.
//! 2. [`boundary_rotations`] (from the boundary shape: normal alignment and twist in 3D, change
//!    of edge direction in 2D), or [`rigid_rotations`] when the caller knows the rotation.
//! 3. [`boundary_origin`] (default origin) and [`boundary_translations`]:
//!    `Δ_i = (r_i^d − o) − Q_i (r_i^u − o) Q_i*` (Samareh's `Δ` with the erratum in
//!    ARCHITECTURE.md).
//! 4. Propagation of `(Δ, Q)` into the field: [`propagate_idw`] (inverse distance),
//!    [`propagate_tfi`] (transfinite interpolation of structured blocks, arclength blending),
//!    [`propagate_spring`] (linear springs, one solve for `Δ` and `Q` together),
//!    [`propagate_idw_fast`] (inverse distance with far-field clusters of a k-d tree and a
//!    per-point error bound, for large boundaries).
//!    [`displacement_tfi`] is plain displacement TFI for comparison.
//!    [`limit_reach`] optionally fades `(Δ, Q)` to no motion beyond a radius from the moving
//!    boundary.
//! 5. [`update_points`]: the field update (eq. 6); boundary nodes are copied from `r^d`.
//!
//! [`deform_idw`], [`deform_idw_fast`], [`deform_tfi`] and [`deform_spring`] run the whole
//! pipeline in one call.
//! [`deform_spring_partitioned`] and [`deform_idw_partitioned`] run the spring and the exact
//! IDW pipelines on partitioned data (each process its owned nodes), with the serial bits.
//!
//! **Boundary exactness.** `o + ((r^d − o) − x) + x` is not `r^d` in floating point (the
//! subtraction can lose the low bits of `r^d`), so no evaluation order of eq. 6 reproduces the
//! boundary bit for bit in general. [`update_points`] therefore writes the caller's `r^d`
//! directly at every boundary node; every other node uses eq. 6.
//!
//! **Choices beyond the paper.** Translations are measured about an origin `o` (default: the
//! centroid of the moving boundary, see [`boundary_origin`] for why a far origin hurts). The 3D
//! twist is a circular mean weighted by the projected edge lengths (robust at sharp trailing
//! edges). Antiparallel undeformed/deformed normals are not an error: `Q1` turns by 180° about
//! a tangent axis and the twist completes the rotation; element normals that cancel *at* a
//! node are ([`Error::ZeroLength`], `"normals"`): a folded sheet in 3D, a cusp for
//! [`boundary_normals`] in 2D (2D rotations use edge directions, not normals).
//!
//! **Cost.** Normals, rotations, translations, TFI and the update are `O(B)` or `O(N)`;
//! [`propagate_idw`] is `O(N · B)`, [`propagate_idw_fast`] about `O(N log B)` node visits
//! for a fixed `θ` (plus an `O(B log² B)` tree build); [`propagate_spring`] is one linear-spring solve.
//!
//! **Storage.** Boundary-level routines work on the boundary's own point list (`B` points,
//! elements indexing `0..B`); field-level routines work on the mesh (`N` points) with
//! `boundary: &[u32]` naming the mesh node of each boundary point; [`localize_nodes`] renumbers
//! a marker's element nodes from mesh to boundary numbering.

mod idw_fast;
mod localize;
pub(crate) mod normals;
mod partitioned;
mod pipeline;
mod propagate;
mod reach;
mod rotations;
mod sensitivity;
pub(crate) mod springs;
mod tfi;
mod update;

pub use idw_fast::{
    propagate_idw_fast, propagate_idw_fast_index_len, propagate_idw_fast_scratch_len,
    IdwFastOptions, IdwFastReport, IDW_FAST_LEAF,
};
pub use localize::{localize_nodes, localize_nodes_scratch_len};
pub use normals::{boundary_normals, boundary_normals_scratch_len};
pub use partitioned::{
    deform_idw_partitioned, deform_idw_partitioned_lens, deform_spring_partitioned,
    deform_spring_partitioned_lens, BoundaryElements, PartitionedIdwLens, PartitionedIdwWorkspace,
    PartitionedLens, PartitionedMotion, PartitionedWorkspace,
};
pub use pipeline::{
    deform_idw, deform_idw_fast, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len,
    deform_spring_with, deform_tfi, deform_tfi_scratch_len, BoundaryMotion, RotationSource,
};
pub use propagate::propagate_idw;
/// The inverse-distance weights, shared with the IDW sensitivities.
pub(crate) use propagate::{idw_scan, idw_weight, IdwScan};
pub use reach::{limit_reach, reach_weight};
pub use rotations::{
    boundary_origin, boundary_rotations, boundary_rotations_scratch_len, boundary_translations,
    rigid_rotations,
};
pub use sensitivity::{
    deform_idw_adjoint, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_sensitivity_scratch_len, deform_idw_tangent,
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
};
pub use springs::{
    propagate_spring, propagate_spring_scratch_len, propagate_spring_with,
    propagate_spring_with_scratch_len,
};
pub use tfi::{displacement_tfi, propagate_tfi, tfi_scratch_len};
pub use update::update_points;

/// The pieces of the pipelines a prepared plan ([`crate::plan`]) reuses, so its steps run the
/// very same arithmetic.
pub(crate) use normals::check_elements;
pub(crate) use rotations::{origin_core, rigid_node_rotation, rotations_core, translation};
/// The quaternion-spring sensitivities at a solved field (a plan's last step).
pub(crate) use sensitivity::SolvedSpring;
pub(crate) use update::apply;

use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;

/// A read-only view of `B` points: either a slice, or a mesh slice gathered through a node
/// list (indices validated by the caller of [`Pts::mapped`]).
#[derive(Clone, Copy)]
pub(crate) struct Pts<'a, T, const D: usize> {
    points: &'a [[T; D]],
    map: Option<&'a [u32]>,
}

impl<'a, T: Real, const D: usize> Pts<'a, T, D> {
    /// The points themselves.
    #[inline]
    pub(crate) fn direct(points: &'a [[T; D]]) -> Self {
        Pts { points, map: None }
    }

    /// `points[map[k]]` for `k` in `0..map.len()`.
    #[inline]
    pub(crate) fn mapped(points: &'a [[T; D]], map: &'a [u32]) -> Self {
        Pts {
            points,
            map: Some(map),
        }
    }

    /// Number of points in the view.
    #[inline]
    fn len(&self) -> usize {
        match self.map {
            Some(m) => m.len(),
            None => self.points.len(),
        }
    }

    /// Point `k` (zero when out of range).
    #[inline]
    pub(crate) fn get(&self, k: usize) -> [T; D] {
        let i = match self.map {
            Some(m) => m.get(k).map_or(usize::MAX, |&i| i as usize),
            None => k,
        };
        self.points.get(i).copied().unwrap_or([T::ZERO; D])
    }

    /// Point `k` lifted to 3D.
    #[inline]
    fn get3(&self, k: usize) -> [T; 3] {
        lift(self.get(k))
    }

    /// Checks that every point in the view is finite.
    fn check_finite(&self, arg: &'static str) -> Result<()> {
        for k in 0..self.len() {
            if !self.get(k).iter().all(|c| c.is_finite()) {
                return Err(Error::NonFinite { arg, position: k });
            }
        }
        Ok(())
    }
}

/// Lifts a `D`-vector into 3D (missing components are zero).
#[inline]
fn lift<T: Real, const D: usize>(v: [T; D]) -> [T; 3] {
    let mut r = [T::ZERO; 3];
    for (a, b) in r.iter_mut().zip(v.iter()) {
        *a = *b;
    }
    r
}

/// Drops a 3-vector to its first `D` components.
#[inline]
fn drop3<T: Real, const D: usize>(v: [T; 3]) -> [T; D] {
    let mut r = [T::ZERO; D];
    for (a, b) in r.iter_mut().zip(v.iter()) {
        *a = *b;
    }
    r
}

/// Rotates a `D`-vector (2D points are taken at `z = 0`).
#[inline]
pub(crate) fn rotate_d<T: Real, const D: usize>(q: Quat<T>, v: [T; D]) -> [T; D] {
    drop3(q.rotate(lift(v)))
}

/// Checks the IDW exponent `p`: finite and positive.
#[inline]
fn check_exponent<T: Real>(exponent: T) -> Result<()> {
    if exponent.is_finite() && exponent > T::ZERO {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            arg: "exponent",
            reason: "must be finite and positive",
        })
    }
}

/// Reads element `i` of a flat slice viewed as `[[T; N]]` (zeros when out of range).
#[inline]
fn load<T: Real, const N: usize>(s: &[T], i: usize) -> [T; N] {
    let mut r = [T::ZERO; N];
    let start = i.wrapping_mul(N);
    if let Some(c) = s.get(start..start.wrapping_add(N)) {
        for (a, b) in r.iter_mut().zip(c) {
            *a = *b;
        }
    }
    r
}

/// Writes element `i` of a flat slice viewed as `[[T; N]]` (ignored when out of range).
#[inline]
fn store<T: Real, const N: usize>(s: &mut [T], i: usize, v: [T; N]) {
    let start = i.wrapping_mul(N);
    if let Some(c) = s.get_mut(start..start.wrapping_add(N)) {
        for (a, b) in c.iter_mut().zip(v) {
            *a = b;
        }
    }
}

/// Splits `s` into `[..n]` and the rest (the rest is empty and the head short when `s` is).
#[inline]
fn take<T>(s: &mut [T], n: usize) -> (&mut [T], &mut [T]) {
    let n = n.min(s.len());
    s.split_at_mut_checked(n).unwrap_or_default()
}
