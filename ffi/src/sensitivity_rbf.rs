//! Tangent and adjoint of the RBF deformation (the kernel's `rbf_tangent`, `rbf_adjoint`):
//! `dk_sensitivity_rbf_tangent`, `dk_sensitivity_rbf_adjoint`. Both fit `motion` (the
//! linearisation point) as `dk_rbf_deform` does and differentiate with its centres kept;
//! workspaces as `dk_rbf_deform`'s (`dk_rbf_index_scratch_len`, `dk_rbf_scratch_len`). See
//! docs/sensitivities.md.

use deform_kernel::rbf::{rbf_adjoint, rbf_tangent, RbfOptions};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{by_dim, check_base, done, read_one, read_points, rebase};
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
pub(crate) fn dk_sensitivity_rbf_tangent<T: Real>(
    points: In<'_, T>,
    dim: u32,
    boundary: In<'_, u32>,
    index_base: u32,
    motion: In<'_, T>,
    options: In<'_, dk_rbf_options>,
    index_scratch: Out<'_, u32>,
    scratch: Out<'_, T>,
    dmotion: In<'_, T>,
    dx: Out<'_, T>,
) -> dk_status {
    let args = (
        points,
        boundary,
        index_base,
        motion,
        index_scratch,
        scratch,
        dmotion,
        dx,
    );
    done(read_one(options).and_then(|o| by_dim!(dim, run::<T>, (true, &o, args))))
}

/// The adjoint of `dk_rbf_deform` (arguments as [`dk_sensitivity_rbf_tangent`]) at `motion`:
/// for `m` fields `w = dJ/du` back to back (`m · N · dim` scalars, one per mesh node), `g =
/// dJ/dmotion` (`m · B · dim` scalars, boundary order). Errors as
/// [`dk_sensitivity_rbf_tangent`]; on an error found before the first field `g` is unchanged.
#[export(twin, options[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_sensitivity_rbf_adjoint<T: Real>(
    points: In<'_, T>,
    dim: u32,
    boundary: In<'_, u32>,
    index_base: u32,
    motion: In<'_, T>,
    options: In<'_, dk_rbf_options>,
    index_scratch: Out<'_, u32>,
    scratch: Out<'_, T>,
    w: In<'_, T>,
    g: Out<'_, T>,
) -> dk_status {
    let args = (
        points,
        boundary,
        index_base,
        motion,
        index_scratch,
        scratch,
        w,
        g,
    );
    done(read_one(options).and_then(|o| by_dim!(dim, run::<T>, (false, &o, args))))
}

type Args<'a, T> = (
    In<'a, T>,
    In<'a, u32>,
    u32,
    In<'a, T>,
    Out<'a, u32>,
    Out<'a, T>,
    In<'a, T>,
    Out<'a, T>,
);

/// Either direction: `tangent` maps `x` (perturbations) to `y` (fields), else `x` (`w`) to
/// `y` (`g`).
fn run<T: Real, const D: usize>(
    tangent: bool,
    o: &dk_rbf_options,
    (points, boundary, base, motion, index, scratch, x, y): Args<'_, T>,
) -> Result<(), dk_status> {
    check_base(base)?;
    let o: RbfOptions<T> = o.kernel_options::<T>()?;
    let (p, m) = (read_points::<T, D>(points)?, read_points::<T, D>(motion)?);
    let (x, y) = (read_points::<T, D>(x)?, chunks_mut::<T, D>(y)?);
    let s = output(scratch)?;
    let (b, idx) = rebase(input(boundary)?, base, output(index)?)?;
    let r = if tangent {
        rbf_tangent(p, b, m, &o, idx, s, x, y)
    } else {
        rbf_adjoint(p, b, m, &o, idx, s, x, y)
    };
    r.map(|_| ()).map_err(dk_status::from)
}
