//! Derivatives of SU2's design variables for SU2_DOT's `dJ/dα` (kernel:
//! `deform_kernel::design::sensitivity`; docs/sensitivities.md, "Design variables"):
//! `dk_design_hicks_henne_adjoint`, `dk_design_ffd_adjoint`, `dk_design_ffd_twist_tangent`
//! (f64) and `_f32` twins. Layouts as in `dk_design_*`: flat arrays of `dim` scalars per item.

use deform_kernel::design::sensitivity::{ffd_adjoint, hicks_henne_adjoint};
use deform_kernel::design::twist::{ffd_twist_tangent, FfdTwist};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{read_array, read_points, rebase, write_one, Dim};
use crate::slice::{chunks_mut, input, output, In, Out};
use crate::status::dk_status;

/// The degrees of a `D`-dimensional box (`degree_len` must be `D`).
fn degree<const D: usize>(degree: In<'_, u32>) -> Result<[usize; D], dk_status> {
    let d = read_points::<u32, D>(degree)?;
    match d {
        [d] => Ok(d.map(|x| x as usize)),
        _ => Err(dk_status::DK_ERR_LENGTH_MISMATCH),
    }
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// `dJ/da` of one `HICKS_HENNE` variable (as `dk_design_hicks_henne`: `points`, `nodes` in
/// `index_base` with `index_scratch`, `normals`, `upper`, `x_max`) into `*out`:
/// `Σ_p ±bump(x) · dj_dx[p].y` over the listed nodes on the bump's side, `dj_dx` holding
/// `dJ/dx` per listed node (`nodes_len × dim`). Multiply by `OPT_RELAX_FACTOR` for the
/// derivative in `DV_VALUE`. Errors (nothing written): as `dk_design_hicks_henne`, plus
/// `DK_ERR_OVERFLOW`.
#[export(twin, out[1])]
pub(crate) fn dk_design_hicks_henne_adjoint<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    nodes: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    normals: In<'_, T>,
    upper: bool,
    x_max: T,
    dj_dx: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let (nodes, _) = rebase(input(nodes)?, index_base, output(index_scratch)?)?;
    let (p, n, g) = (
        read_points(points)?,
        read_points(normals)?,
        read_points(dj_dx)?,
    );
    let v = hicks_henne_adjoint::<T, D>(p, nodes, n, upper, x_max, g)?;
    write_one(out, v)
}

/// The transpose of evaluating a box (degrees `degree[0..dim]`) at `params`:
/// `out[c] = Σ_p B_c(params[p]) · dj_dx[p]` for every control point `c` (`out` holds
/// `∏(degree+1) × dim` scalars, overwritten; `dj_dx` one item per parametric coordinate).
/// `Σ_c δP_c · out[c]` is then `dJ/dα` for a control-point change `δP` per unit `α`.
/// Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (`dim`, degree), `DK_ERR_NON_FINITE`,
/// `DK_ERR_OVERFLOW`, length and pointer errors.
#[export(twin)]
pub(crate) fn dk_design_ffd_adjoint<T: Real, const D: usize>(
    degree: In<'_, u32>,
    _dim: Dim<D>,
    params: In<'_, T>,
    dj_dx: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let d = self::degree::<D>(degree)?;
    let (u, g) = (read_points(params)?, read_points(dj_dx)?);
    Ok(ffd_adjoint::<T, D>(d, u, g, chunks_mut(out)?)?)
}

/// The derivative of `dk_design_ffd_twist`'s control points in `amplitude` at amplitude 0
/// (SU2_DOT's point) into `out` (`3 ∏(degree+1)` scalars, overwritten): layer `j`'s points
/// not on a fixed plane move by `(0, 1/ref_length, 0) × (p − pivot)`, the rest by 0. Errors
/// (nothing written): as `dk_design_ffd_twist`.
#[export(twin, degree[3], segment[6])]
pub(crate) fn dk_design_ffd_twist_tangent<T: Real>(
    degree: In<'_, u32>,
    control_points: In<'_, T>,
    j: u32,
    segment: In<'_, T>,
    ref_length: T,
    fixed_i: In<'_, u32>,
    fixed_k: In<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let d = read_array::<u32, 3>(degree)?.map(|x| x as usize);
    let s = read_array::<T, 6>(segment)?;
    let twist = FfdTwist {
        j: j as usize,
        segment: [[s[0], s[1], s[2]], [s[3], s[4], s[5]]],
        amplitude: T::ZERO,
        ref_length,
    };
    let (cps, fi, fk) = (
        read_points(control_points)?,
        input(fixed_i)?,
        input(fixed_k)?,
    );
    Ok(ffd_twist_tangent(d, cps, twist, fi, fk, chunks_mut(out)?)?)
}
