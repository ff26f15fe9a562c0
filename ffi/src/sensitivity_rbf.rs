//! Tangent and adjoint of the RBF deformation (the kernel's `rbf_tangent`, `rbf_adjoint`):
//! `dk_sensitivity_rbf_tangent`, `dk_sensitivity_rbf_adjoint`. Both fit `motion` (the
//! linearisation point) as `dk_rbf_deform` does and differentiate with its centres kept;
//! workspaces as `dk_rbf_deform`'s (`dk_rbf_index_scratch_len`, `dk_rbf_scratch_len`). See
//! docs/sensitivities.md.

use deform_kernel::rbf::{rbf_adjoint, rbf_tangent, RbfOptions};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{check_base, read_one, read_points, rebase, Dim};
use crate::rbf::dk_rbf_options;
use crate::slice::{chunks_mut, input, output, In, Out};
use crate::status::dk_status;

/// The tangent of `dk_rbf_deform` (same `points`, `dim`, `boundary`, `index_base`, `motion`,
/// `options`, workspaces) at `motion`: for `m` boundary perturbations back to back in
/// `dmotion` (`m · B · dim` scalars, boundary order), the first-order change of every node's
/// displacement into `dx` (`m · N · dim` scalars). Errors: those of `dk_rbf_deform`, and
/// `dmotion`/`dx` not whole fields of the same count; on an error found before the first
/// field `dx` is unchanged.
#[export(twin, options[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_rbf_tangent<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    boundary: In<'_, u32>,
    index_base: u32,
    motion: In<'_, T>,
    options: In<'_, dk_rbf_options>,
    index_scratch: Out<'_, u32>,
    scratch: Out<'_, T>,
    dmotion: In<'_, T>,
    dx: Out<'_, T>,
) -> Result<(), dk_status> {
    let fit = Fit::<T, D>::read(points, boundary, index_base, motion, options, index_scratch)?;
    fit.run(true, scratch, dmotion, dx)
}

/// The adjoint of `dk_rbf_deform` (arguments as [`dk_sensitivity_rbf_tangent`]) at `motion`:
/// for `m` fields `w = dJ/du` back to back (`m · N · dim` scalars, one per mesh node), `g =
/// dJ/dmotion` (`m · B · dim` scalars, boundary order). Errors as
/// [`dk_sensitivity_rbf_tangent`]; on an error found before the first field `g` is unchanged.
#[export(twin, options[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_rbf_adjoint<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    boundary: In<'_, u32>,
    index_base: u32,
    motion: In<'_, T>,
    options: In<'_, dk_rbf_options>,
    index_scratch: Out<'_, u32>,
    scratch: Out<'_, T>,
    w: In<'_, T>,
    g: Out<'_, T>,
) -> Result<(), dk_status> {
    let fit = Fit::<T, D>::read(points, boundary, index_base, motion, options, index_scratch)?;
    fit.run(false, scratch, w, g)
}

/// What both directions read: points, boundary (rebased), motion and options.
struct Fit<'a, T, const D: usize> {
    points: &'a [[T; D]],
    boundary: &'a [u32],
    index: &'a mut [u32],
    motion: &'a [[T; D]],
    options: RbfOptions<T>,
}

impl<'a, T: Real, const D: usize> Fit<'a, T, D> {
    fn read(
        points: In<'a, T>,
        boundary: In<'a, u32>,
        base: u32,
        motion: In<'a, T>,
        options: In<'_, dk_rbf_options>,
        index: Out<'a, u32>,
    ) -> Result<Self, dk_status> {
        let options = read_one(options)?.kernel_options::<T>()?;
        check_base(base)?;
        let (points, motion) = (read_points::<T, D>(points)?, read_points::<T, D>(motion)?);
        let (boundary, index) = rebase(input(boundary)?, base, output(index)?)?;
        Ok(Fit {
            points,
            boundary,
            index,
            motion,
            options,
        })
    }

    /// Either direction: `tangent` maps `x` (perturbations) to `y` (fields), else `x` (`w`)
    /// to `y` (`g`).
    fn run(
        self,
        tangent: bool,
        scratch: Out<'_, T>,
        x: In<'_, T>,
        y: Out<'_, T>,
    ) -> Result<(), dk_status> {
        let (x, y) = (read_points::<T, D>(x)?, chunks_mut::<T, D>(y)?);
        let (p, b, m, o, idx, s) = (
            self.points,
            self.boundary,
            self.motion,
            &self.options,
            self.index,
            output(scratch)?,
        );
        let r = if tangent {
            rbf_tangent(p, b, m, o, idx, s, x, y)
        } else {
            rbf_adjoint(p, b, m, o, idx, s, x, y)
        };
        r.map(|_| ()).map_err(dk_status::from)
    }
}
