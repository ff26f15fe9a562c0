//! The quaternion deformation with the fast, tree-based inverse-distance propagation (the
//! kernel's `deform_idw_fast`: a k-d tree of the boundary, far clusters weighted as a whole,
//! a per-point error bound; docs/idw.md) and its tangent and adjoint
//! (`deform_idw_fast_tangent`, `deform_idw_fast_adjoint`): `dk_deform_idw_fast_lens`,
//! `dk_deform_idw_fast`, `dk_deform_idw_fast_tangent`, `dk_deform_idw_fast_adjoint`. The
//! motion travels in a [`dk_boundary_motion`](crate::deformation::dk_boundary_motion), with the
//! index rules of `dk_deform_idw`.

use deform_kernel::quaternion::{
    deform_idw_fast, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_scratch_len, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, IdwFastOptions,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{read_points, write_array, Dim};
use crate::deformation::{pipeline, read_raw, write_optional, DkBoundaryMotion};
use crate::slice::{chunks, chunks_mut, output, quats_mut, In, Out};
use crate::status::dk_status;

/// The two directions of [`derivative`].
#[derive(Clone, Copy)]
enum Mode {
    Tangent,
    Adjoint,
}

/// The tree's workspaces: `tree_index` (`u32`) and `tree` (scalars).
type Tree<'a, T> = (Out<'a, u32>, Out<'a, T>);

/// Reads the arguments of the tangent or the adjoint and runs it.
#[allow(clippy::too_many_arguments)]
fn derivative<T: Real, const D: usize>(
    mode: Mode,
    (points, motion): (In<'_, T>, In<'_, DkBoundaryMotion<T>>),
    (exponent, theta, tolerance): (T, T, T),
    input: In<'_, T>,
    (scratch, index_scratch): (Out<'_, T>, Out<'_, u32>),
    (tree_index, tree): Tree<'_, T>,
    (translations, rotations): (Out<'_, T>, Out<'_, T>),
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let raw = read_raw(motion)?;
    let points = read_points::<T, D>(points)?;
    let input = chunks::<T, D>(input)?;
    let (scratch, index, tree) = (output(scratch)?, output(tree_index)?, output(tree)?);
    let (tr, rot) = (chunks_mut::<T, D>(translations)?, quats_mut(rotations)?);
    let out = chunks_mut::<T, D>(out)?;
    let (motion, _) = raw.view::<D>(output(index_scratch)?)?;
    let (m, o) = (&motion, &IdwFastOptions { theta, tolerance });
    match mode {
        Mode::Tangent => deform_idw_fast_tangent(
            points, m, exponent, o, input, tr, rot, scratch, index, tree, out,
        ),
        Mode::Adjoint => deform_idw_fast_adjoint(
            points, m, exponent, o, input, tr, rot, scratch, index, tree, out,
        ),
    }
    .map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// The buffer lengths of the fast IDW for `node_count` mesh nodes and `boundary_len` boundary
/// nodes in dimension `dim` (2 or 3), the same for both precisions: `lens_out[0]` the
/// `scratch` scalars of [`dk_deform_idw_fast`] (those of `dk_deform_idw`), `lens_out[1]` the
/// `tree_index` entries, `lens_out[2]` the `tree` scalars, `lens_out[3]` the `scratch`
/// scalars of [`dk_deform_idw_fast_tangent`] and [`dk_deform_idw_fast_adjoint`] (the kernel's
/// `deform_idw_scratch_len`, `propagate_idw_fast_index_len`, `propagate_idw_fast_scratch_len`
/// and `deform_idw_fast_sensitivity_scratch_len`; `SIZE_MAX` where a length overflows).
#[export(lens_out[4])]
pub(crate) fn dk_deform_idw_fast_lens<const D: usize>(
    node_count: usize,
    boundary_len: usize,
    _dim: Dim<D>,
    lens_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let (n, b) = (node_count, boundary_len);
    write_array(
        lens_out,
        [
            deform_idw_scratch_len::<D>(n, b),
            propagate_idw_fast_index_len(b),
            propagate_idw_fast_scratch_len::<D>(b),
            deform_idw_fast_sensitivity_scratch_len::<D>(n, b),
        ],
    )
}

/// The quaternion deformation of [`dk_deform_idw`](crate::deformation::dk_deform_idw) with the
/// fast propagation (the kernel's `deform_idw_fast`): a cluster of boundary nodes of radius `r`
/// at distance `d` from a point is weighted as a whole when `r < theta d` and its share of the
/// per-point error bound stays within `tolerance`.
///
/// - `points`, `dim`, `motion`, `exponent`, `index_scratch`, `translations`, `rotations`,
///   `out`, `origin_out`: as for `dk_deform_idw`.
/// - `theta` in `[0, 1)` (0: every node weighted individually, the exact method up to
///   summation order; 0.5 is typical); `tolerance`: the largest accepted per-point bound `η`
///   (`INFINITY`: `theta` alone; 0.1 is typical), not negative or NaN.
/// - `scratch`, `tree_index`, `tree`: the lengths of [`dk_deform_idw_fast_lens`].
/// - `bound_out`: the largest per-point bound `η` (every translation is within `η · max_k
///   |Δ_k − Δ(x)|` of the exact method's), or NULL with length 0.
///
/// Errors: those of `dk_deform_idw`; `DK_ERR_INVALID_PARAMETER` (`theta`, `tolerance`),
/// `DK_ERR_BUFFER_TOO_SMALL` (`tree_index`, `tree`). On error `out`, `origin_out` and
/// `bound_out` are unchanged.
#[export(twin, motion[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_idw_fast<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    theta: T,
    tolerance: T,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    tree_index: Out<'_, u32>,
    tree: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
    origin_out: Out<'_, T>,
    bound_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let raw = read_raw(motion)?;
    let points = read_points::<T, D>(points)?;
    let b = pipeline::<T, D>(
        [scratch, translations, rotations, out, origin_out],
        index_scratch,
    )?;
    let (index, tree) = (output(tree_index)?, output(tree)?);
    let bound = match bound_out.len() {
        0 => None,
        1 => Some(output(bound_out)?),
        _ => return Err(dk_status::DK_ERR_LENGTH_MISMATCH),
    };
    let (motion, _) = raw.view::<D>(b.index_scratch)?;
    let options = IdwFastOptions { theta, tolerance };
    let (origin, report) = deform_idw_fast(
        points,
        &motion,
        exponent,
        &options,
        b.translations,
        b.rotations,
        b.scratch,
        index,
        tree,
        b.out,
    )?;
    write_optional(b.origin_out, origin);
    write_optional(bound, [report.max_bound]);
    Ok(())
}

/// Tangent of [`dk_deform_idw_fast`]: `out = δR` (`N * dim` scalars) for the change
/// `direction = δd` of the deformed boundary positions (`B * dim` scalars, in
/// `motion->nodes` order), with the clusters the deformation opens held (the derivative of
/// what it computed); boundary nodes get `δd` exactly. Held constant as for
/// `dk_deform_idw_tangent`: the undeformed points, the origin, rigid and per-node rotations.
///
/// - Arguments as for [`dk_deform_idw_fast`]; `scratch`: `lens_out[3]` of
///   [`dk_deform_idw_fast_lens`]; `translations` and `rotations` are workspaces.
///
/// Errors: those of `dk_deform_idw_fast`; `DK_ERR_NON_FINITE` for a non-finite `direction`;
/// `DK_ERR_ZERO_LENGTH` where (3D shape rotations) a point's normals are antiparallel. On
/// error `out` is unchanged.
#[export(twin, motion[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_idw_fast_tangent<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    theta: T,
    tolerance: T,
    direction: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    tree_index: Out<'_, u32>,
    tree: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    derivative::<T, D>(
        Mode::Tangent,
        (points, motion),
        (exponent, theta, tolerance),
        direction,
        (scratch, index_scratch),
        (tree_index, tree),
        (translations, rotations),
        out,
    )
}

/// Adjoint of [`dk_deform_idw_fast`], the transpose of [`dk_deform_idw_fast_tangent`]:
/// `out = (∂R/∂d)ᵀ w` (`B * dim` scalars, in `motion->nodes` order) for `weights = w =
/// dJ/dR` (`N * dim` scalars). Arguments and errors as for the tangent, with `weights`
/// (finite) in place of `direction`. On error `out` is unchanged.
#[export(twin, motion[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_deform_idw_fast_adjoint<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    theta: T,
    tolerance: T,
    weights: In<'_, T>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    tree_index: Out<'_, u32>,
    tree: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    derivative::<T, D>(
        Mode::Adjoint,
        (points, motion),
        (exponent, theta, tolerance),
        weights,
        (scratch, index_scratch),
        (tree_index, tree),
        (translations, rotations),
        out,
    )
}
