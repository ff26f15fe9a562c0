//! Radial-basis-function mesh deformation: `dk_rbf_*` (the kernel's `deform_kernel::rbf`).
//!
//! Wendland C2 (compact support, Cholesky) or thin-plate splines with linear terms (LU with
//! partial pivoting of the saddle-point system), greedy centre selection, and a wall
//! correction that keeps the boundary motion exact when the centres are reduced. Points and
//! motions are flat arrays of `dim` (2 or 3) scalars per node. Options and report are
//! `#[repr(C)]` structs with `double` fields for both precisions (the `_f32` function rounds
//! the options to `float` and widens the report exactly).

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{
    assert_layout, check_base, read_one, read_points, rebase, write_len, write_one, Dim,
};
use crate::slice::{chunks_mut, input, out_one, output, In, Out};
use crate::status::dk_status;

/// `dk_rbf_options::kernel`: Wendland's C2 function with compact support `radius`.
pub const DK_RBF_WENDLAND: u32 = 0;
/// `dk_rbf_options::kernel`: the thin-plate spline `r² ln r` with linear terms.
pub const DK_RBF_THIN_PLATE: u32 = 1;

/// Kernel, greedy selection and wall correction of `dk_rbf_deform`. Fill with
/// `dk_rbf_options_default` and set `radius` (Wendland) and what else you need.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_rbf_options {
    /// Most centres (at least 1; at least `dim + 1` for thin-plate splines). Default
    /// `SIZE_MAX` (every boundary node may be a centre).
    pub max_centres: usize,
    /// Wendland support radius (finite, positive; mesh units); ignored by thin-plate splines.
    /// Default 0: must be set for `DK_RBF_WENDLAND`.
    pub radius: f64,
    /// Greedy selection stops once the largest boundary error is at most this (finite, ≥ 0;
    /// mesh units). With 0 and `max_centres` at least the boundary size every boundary node
    /// is a centre (no selection). Default 0.
    pub tolerance: f64,
    /// The remaining boundary error is faded into the volume over this distance and the
    /// boundary nodes get their motion exactly (finite, ≥ 0; 0 writes the raw interpolant).
    /// Default 0.
    pub correction_radius: f64,
    /// `DK_RBF_WENDLAND` (default) or `DK_RBF_THIN_PLATE`.
    pub kernel: u32,
}
assert_layout!(
    dk_rbf_options, 40;
    max_centres = 0, radius = 8, tolerance = 16, correction_radius = 24, kernel = 32,
);

/// What `dk_rbf_deform` did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_rbf_report {
    /// Centres used.
    pub centres: usize,
    /// Largest error of the interpolant at the boundary nodes, before the correction.
    pub max_error: f64,
    /// 1 when the selection stopped at a node numerically dependent on the centres.
    pub dependent: u32,
}
assert_layout!(dk_rbf_report, 24; centres = 0, max_error = 8, dependent = 16);

impl dk_rbf_options {
    /// The kernel's options in `T` (`DK_ERR_INVALID_PARAMETER` for an unknown kernel code).
    pub(crate) fn kernel_options<T: Real>(&self) -> Result<RbfOptions<T>, dk_status> {
        let kernel = match self.kernel {
            DK_RBF_WENDLAND => RbfKernel::Wendland {
                radius: T::from_f64(self.radius),
            },
            DK_RBF_THIN_PLATE => RbfKernel::ThinPlate,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        Ok(RbfOptions {
            kernel,
            tolerance: T::from_f64(self.tolerance),
            max_centres: self.max_centres,
            correction_radius: T::from_f64(self.correction_radius),
        })
    }
}

/// Fills `*out` with the defaults: Wendland (set `radius`), every boundary node a centre, no
/// correction.
#[export(out[1])]
pub(crate) fn dk_rbf_options_default(out: Out<'_, dk_rbf_options>) -> Result<(), dk_status> {
    write_one(
        out,
        dk_rbf_options {
            max_centres: usize::MAX,
            radius: 0.0,
            tolerance: 0.0,
            correction_radius: 0.0,
            kernel: DK_RBF_WENDLAND,
        },
    )
}

/// The two workspace sizes for `boundary_len` boundary nodes: scalars and `uint32_t`s.
fn sizes(
    boundary_len: usize,
    dim: u32,
    index_base: u32,
    options: In<'_, dk_rbf_options>,
) -> Result<[usize; 2], dk_status> {
    check_base(index_base)?;
    let o = read_one(options)?.kernel_options::<f64>()?;
    let [reals, ints] = match dim {
        2 => [
            rbf_scratch_len::<f64, 2>(boundary_len, &o),
            rbf_index_len::<f64, 2>(boundary_len, &o),
        ],
        3 => [
            rbf_scratch_len::<f64, 3>(boundary_len, &o),
            rbf_index_len::<f64, 3>(boundary_len, &o),
        ],
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    let rebased = if index_base == 1 { boundary_len } else { 0 };
    match (reals, ints.checked_add(rebased)) {
        (usize::MAX, _) | (_, None) => Err(dk_status::DK_ERR_TOO_LARGE),
        (r, Some(i)) => Ok([r, i]),
    }
}

/// Scalars of `scratch` [`dk_rbf_deform`] needs (the same for both precisions): the dense
/// matrix `a²` (`a` = centres + `dim + 1` for thin-plate splines), coefficients and boundary
/// residuals. Errors: `DK_ERR_INVALID_PARAMETER` (`dim`, kernel code), `DK_ERR_TOO_LARGE`.
#[export(options[1], len_out[1])]
pub(crate) fn dk_rbf_scratch_len(
    boundary_len: usize,
    dim: u32,
    options: In<'_, dk_rbf_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    sizes(boundary_len, dim, 0, options).and_then(|[r, _]| write_len(len_out, r))
}

/// `uint32_t`s of `index_scratch` [`dk_rbf_deform`] needs: centres, pivots, flags, the
/// search grids, and `boundary_len` more with `index_base` 1. Errors as
/// [`dk_rbf_scratch_len`], plus `DK_ERR_BAD_INDEX_BASE`.
#[export(options[1], len_out[1])]
pub(crate) fn dk_rbf_index_scratch_len(
    boundary_len: usize,
    dim: u32,
    index_base: u32,
    options: In<'_, dk_rbf_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    sizes(boundary_len, dim, index_base, options).and_then(|[_, i]| write_len(len_out, i))
}

/// RBF deformation (the kernel's `rbf_deform`): interpolates the motion of the boundary
/// nodes and writes the displacement of every mesh node.
///
/// - `points`: `N * dim` scalars; `boundary`: `B` mesh nodes in `index_base` (0 or 1);
///   `motion`: `B * dim` scalars, the displacement of each boundary node.
/// - `options`: see [`dk_rbf_options`]; `index_scratch` ([`dk_rbf_index_scratch_len`]) and
///   `scratch` ([`dk_rbf_scratch_len`]) are workspaces.
/// - `displacements`: `N * dim` scalars, written on success; `report`: one struct.
///
/// Errors: pointer and length errors, `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_INDEX_OUT_OF_RANGE`,
/// `DK_ERR_DUPLICATE_NODE`, `DK_ERR_NON_FINITE`, `DK_ERR_INVALID_PARAMETER` (options, too few
/// boundary nodes, thin-plate splines on a boundary in one line/plane),
/// `DK_ERR_BUFFER_TOO_SMALL`, `DK_ERR_SINGULAR_SYSTEM` (coincident boundary nodes, or a
/// support too wide for the precision), `DK_ERR_OVERFLOW`. On error `displacements` and
/// `report` are unchanged.
#[export(twin, options[1], report[1])]
pub(crate) fn dk_rbf_deform<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    boundary: In<'_, u32>,
    index_base: u32,
    motion: In<'_, T>,
    options: In<'_, dk_rbf_options>,
    index_scratch: Out<'_, u32>,
    scratch: Out<'_, T>,
    displacements: Out<'_, T>,
    report: Out<'_, dk_rbf_report>,
) -> Result<(), dk_status> {
    check_base(index_base)?;
    let o = read_one(options)?.kernel_options::<T>()?;
    // Borrowed first: a NULL report is refused before anything is written.
    let rep = out_one(report)?;
    let p = read_points::<T, D>(points)?;
    let m = read_points::<T, D>(motion)?;
    let b = input(boundary)?;
    let idx = output(index_scratch)?;
    let s = output(scratch)?;
    let out = chunks_mut::<T, D>(displacements)?;
    let (b, idx) = rebase(b, index_base, idx)?;
    let r = rbf_deform(p, b, m, &o, idx, s, out)?;
    *rep = dk_rbf_report {
        centres: r.centres,
        max_error: r.max_error.to_f64(),
        dependent: u32::from(r.dependent),
    };
    Ok(())
}
