//! SU2's surface design variables: `dk_design_*` (f64) and `dk_design_*_f32`.
//!
//! Hicks–Henne bumps on surface nodes, Bernstein FFD boxes evaluated at parametric
//! coordinates, the surface displacements after control points move, and the control-point
//! changes of SU2's `FFD_*` design variables (kernel: `deform_kernel::design`; the formulas and
//! what SU2 does are in docs/design-variables.md).
//!
//! Points, normals, parametric coordinates, control points and displacements are flat arrays
//! of `dim` scalars per item (`dim` 2 or 3). A box of degrees `degree[0..dim]` (each 1 to 32)
//! has `∏(degree[a] + 1)` control points in the order SU2 writes `FFD_CONTROL_POINTS` (first
//! index slowest, last fastest). Surface node indices are read in `index_base` (0 or 1); with
//! 1 their 0-based copies go to the caller's `index_scratch` (`nodes_len` entries; NULL with
//! length 0 for `index_base` 0). FFD control-point indices (`DV_PARAM`) are always 0-based, as
//! in SU2's files.

use deform_kernel::design::ffd::{ffd_displacements, ffd_displacements_between, ffd_eval, FfdBox};
use deform_kernel::design::hicks_henne::{hicks_henne, hicks_henne_bump, HicksHenne};
use deform_kernel::design::twist::{ffd_twist, FfdTwist};
use deform_kernel::design::variables::{
    ffd_camber, ffd_camber_2d, ffd_control_point, ffd_control_point_2d, ffd_thickness,
    ffd_thickness_2d,
};
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{read_array, read_points, rebase, write_one, Dim};
use crate::slice::{chunks_mut, input, output, In, Out};
use crate::status::dk_status;

/// `FFD_CONTROL_POINT`: `index` = (i, j, k), −1 = all along that direction; `values` = the
/// movement (dx·a, dy·a, dz·a).
pub const DK_FFD_CONTROL_POINT: u32 = 0;
/// `FFD_CONTROL_POINT_2D`: `index` = (i, j, unused), −1 = all; `values` = (dx·a, dy·a,
/// unused); layers k = 0 and 1 move.
pub const DK_FFD_CONTROL_POINT_2D: u32 = 1;
/// `FFD_CAMBER`: `index` = (i, j, unused); `values[0]` = a.
pub const DK_FFD_CAMBER: u32 = 2;
/// `FFD_THICKNESS`: `index` = (i, j, unused); `values[0]` = a.
pub const DK_FFD_THICKNESS: u32 = 3;
/// `FFD_CAMBER_2D`: `index` = (i, unused, unused); `values[0]` = a.
pub const DK_FFD_CAMBER_2D: u32 = 4;
/// `FFD_THICKNESS_2D`: `index` = (i, unused, unused); `values[0]` = a.
pub const DK_FFD_THICKNESS_2D: u32 = 5;

/// The degrees of a `D`-dimensional box (`degree_len` must be `D`).
fn read_degree<const D: usize>(degree: In<'_, u32>) -> Result<[usize; D], dk_status> {
    let d = input(degree)?;
    if d.len() != D {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    Ok(core::array::from_fn(|a| d[a] as usize))
}

/// A validated box from the caller's degrees and control points.
fn read_box<'a, T: Real, const D: usize>(
    degree: In<'_, u32>,
    control_points: In<'a, T>,
) -> Result<FfdBox<'a, T, D>, dk_status> {
    let degree = read_degree::<D>(degree)?;
    FfdBox::new(degree, read_points::<T, D>(control_points)?).map_err(dk_status::from)
}

/// A node list read in `index_base` (rebased into `index_scratch` when it is 1).
fn read_nodes<'a>(
    nodes: In<'a, u32>,
    index_base: u32,
    index_scratch: Out<'a, u32>,
) -> Result<&'a [u32], dk_status> {
    let (n, _) = rebase(input(nodes)?, index_base, output(index_scratch)?)?;
    Ok(n)
}

/// An SU2 index: `Some(i)` for `i ≥ 0`, `None` for −1 where `wild` allows it.
fn su2_index(i: i32, wild: bool) -> Result<Option<usize>, dk_status> {
    match i {
        -1 if wild => Ok(None),
        i if i >= 0 => Ok(Some(i as usize)),
        _ => Err(dk_status::DK_ERR_INDEX_OUT_OF_RANGE),
    }
}

/// A fixed (non-wildcard) SU2 index.
fn fixed(i: i32) -> Result<usize, dk_status> {
    su2_index(i, false)?.ok_or(dk_status::DK_ERR_INDEX_OUT_OF_RANGE)
}

fn variable<T: Real>(
    kind: u32,
    degree: [usize; 3],
    cps: &mut [[T; 3]],
    index: [i32; 3],
    values: [T; 3],
) -> Result<(), dk_status> {
    let [i, j, k] = index;
    let a = values[0];
    match kind {
        DK_FFD_CONTROL_POINT => {
            let ijk = [
                su2_index(i, true)?,
                su2_index(j, true)?,
                su2_index(k, true)?,
            ];
            ffd_control_point(degree, cps, ijk, values)
        }
        DK_FFD_CONTROL_POINT_2D => {
            let ij = [su2_index(i, true)?, su2_index(j, true)?];
            ffd_control_point_2d(degree, cps, ij, [values[0], values[1]])
        }
        DK_FFD_CAMBER => ffd_camber(degree, cps, fixed(i)?, fixed(j)?, a),
        DK_FFD_THICKNESS => ffd_thickness(degree, cps, fixed(i)?, fixed(j)?, a),
        DK_FFD_CAMBER_2D => ffd_camber_2d(degree, cps, fixed(i)?, a),
        DK_FFD_THICKNESS_2D => ffd_thickness_2d(degree, cps, fixed(i)?, a),
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    }
    .map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// SU2's Hicks–Henne bump `sin(π max(0,x)^e)^3`, `e = log10(0.5)/log10(x_max)` (0 where
/// `max(0,x) ≤ 1e-15`) into `*out`. Never fails except for a NULL `out`.
#[export(twin, out[1])]
pub(crate) fn dk_design_hicks_henne_bump<T: Real>(
    x: T,
    x_max: T,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    write_one(out, hicks_henne_bump(x, x_max))
}

/// Adds one `HICKS_HENNE` design variable (`DV_PARAM = (upper ? 1 : 0, x_max)`, `DV_VALUE ×
/// OPT_RELAX_FACTOR = amplitude`) to `displacements` (`nodes_len × dim`, one item per listed
/// node): y of node `nodes[p]` gains `±amplitude · bump(x)` where `normals[p]` (pointing into
/// the fluid) has y > 0 (upper) or y < 0 (lower, minus sign). `points` is the whole mesh
/// (`node_count × dim`). Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (`dim`, `x_max`
/// not in (0, 1)), `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_NON_FINITE`, `DK_ERR_BAD_INDEX_BASE`,
/// length, buffer and pointer errors.
#[export(twin)]
pub(crate) fn dk_design_hicks_henne<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    nodes: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    normals: In<'_, T>,
    upper: bool,
    x_max: T,
    amplitude: T,
    displacements: Out<'_, T>,
) -> Result<(), dk_status> {
    let bump = HicksHenne {
        upper,
        x_max,
        amplitude,
    };
    let p = read_points::<T, D>(points)?;
    let n = read_points::<T, D>(normals)?;
    let nodes = read_nodes(nodes, index_base, index_scratch)?;
    let d = chunks_mut::<T, D>(displacements)?;
    Ok(hicks_henne(p, nodes, n, bump, d)?)
}

/// Evaluates an FFD box (degrees `degree[0..dim]`, `control_points`) at every parametric
/// coordinate of `params` into `out` (same length as `params`). Errors (nothing written):
/// `DK_ERR_INVALID_PARAMETER` (`dim`, a degree of 0 or above 32), `DK_ERR_NON_FINITE`, length
/// and pointer errors.
#[export(twin)]
pub(crate) fn dk_design_ffd_eval<T: Real, const D: usize>(
    degree: In<'_, u32>,
    control_points: In<'_, T>,
    _dim: Dim<D>,
    params: In<'_, T>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = read_box::<T, D>(degree, control_points)?;
    let u = read_points::<T, D>(params)?;
    Ok(ffd_eval(&b, u, chunks_mut::<T, D>(out)?)?)
}

/// SU2's `SetCartesianCoord`: for each surface point p (node `nodes[p]` at parametric
/// coordinates `params[p]`), `displacements[p]` = box(`params[p]`) − `points[nodes[p]]`, each
/// component of magnitude ≤ 1e-16 set to 0 (overwrites). `control_points` are the moved
/// ones. Errors (nothing written): as `dk_design_ffd_eval`, plus
/// `DK_ERR_INDEX_OUT_OF_RANGE` and `DK_ERR_BAD_INDEX_BASE`.
#[export(twin)]
pub(crate) fn dk_design_ffd_displacements<T: Real, const D: usize>(
    degree: In<'_, u32>,
    control_points: In<'_, T>,
    _dim: Dim<D>,
    points: In<'_, T>,
    nodes: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    params: In<'_, T>,
    displacements: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = read_box::<T, D>(degree, control_points)?;
    let p = read_points::<T, D>(points)?;
    let u = read_points::<T, D>(params)?;
    let nodes = read_nodes(nodes, index_base, index_scratch)?;
    let d = chunks_mut::<T, D>(displacements)?;
    Ok(ffd_displacements(&b, p, nodes, u, d)?)
}

/// Moved box minus original box at each of `params` into `displacements` (exactly zero where
/// nothing moved). Errors (nothing written): as `dk_design_ffd_eval`.
#[export(twin)]
pub(crate) fn dk_design_ffd_displacements_between<T: Real, const D: usize>(
    degree: In<'_, u32>,
    original: In<'_, T>,
    moved: In<'_, T>,
    _dim: Dim<D>,
    params: In<'_, T>,
    displacements: Out<'_, T>,
) -> Result<(), dk_status> {
    let a = read_box::<T, D>(degree, original)?;
    let b = read_box::<T, D>(degree, moved)?;
    let u = read_points::<T, D>(params)?;
    let d = chunks_mut::<T, D>(displacements)?;
    Ok(ffd_displacements_between(&a, &b, u, d)?)
}

/// Applies one SU2 FFD design variable (`kind`: `DK_FFD_CONTROL_POINT`, `_2D`, `DK_FFD_CAMBER`,
/// `DK_FFD_THICKNESS`, `DK_FFD_CAMBER_2D`, `DK_FFD_THICKNESS_2D`; `index` and `values` as
/// each constant says) to the control points of an always-3D SU2 box (`degree[3]`,
/// `control_points` of `3 ∏(degree+1)` scalars, changed in place; movements add, as in SU2).
/// Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (unknown kind, bad degree, all three
/// indices −1), `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_NON_FINITE`, length and pointer errors.
#[export(twin, degree[3], index[3], values[3])]
pub(crate) fn dk_design_ffd_variable<T: Real>(
    kind: u32,
    degree: In<'_, u32>,
    control_points: Out<'_, T>,
    index: In<'_, i32>,
    values: In<'_, T>,
) -> Result<(), dk_status> {
    let degree = read_degree::<3>(degree)?;
    let index = read_array::<i32, 3>(index)?;
    let values = read_array::<T, 3>(values)?;
    let cps = chunks_mut::<T, 3>(control_points)?;
    variable(kind, degree, cps, index, values)
}

/// Applies one SU2 `FFD_TWIST` design variable to the control points of an always-3D SU2 box
/// (`degree[3]`, `control_points` of `3 ∏(degree+1)` scalars, changed in place): layer `j`
/// turns by `atan(amplitude / ref_length)` about the y-parallel axis through the point where
/// the segment `segment[0..3]`–`segment[3..6]` crosses the plane `y = y(0, j, 0)` (SU2's
/// `SetFFDTwist`; `amplitude` = `DV_VALUE × OPT_RELAX_FACTOR`, `ref_length` = `REF_LENGTH`).
/// Control points whose i is listed in `fixed_i` or whose k is in `fixed_k` stay. Errors
/// (nothing written): `DK_ERR_INVALID_PARAMETER` (bad degree, `ref_length ≤ 0`, a segment that
/// does not cross the plane), `DK_ERR_INDEX_OUT_OF_RANGE` (`j`), `DK_ERR_NON_FINITE`,
/// `DK_ERR_OVERFLOW`, length and pointer errors.
#[export(twin, degree[3], segment[6])]
pub(crate) fn dk_design_ffd_twist<T: Real>(
    degree: In<'_, u32>,
    control_points: Out<'_, T>,
    j: u32,
    segment: In<'_, T>,
    amplitude: T,
    ref_length: T,
    fixed_i: In<'_, u32>,
    fixed_k: In<'_, u32>,
) -> Result<(), dk_status> {
    let degree = read_degree::<3>(degree)?;
    let s = read_array::<T, 6>(segment)?;
    let twist = FfdTwist {
        j: j as usize,
        segment: [[s[0], s[1], s[2]], [s[3], s[4], s[5]]],
        amplitude,
        ref_length,
    };
    let (fi, fk) = (input(fixed_i)?, input(fixed_k)?);
    let cps = chunks_mut::<T, 3>(control_points)?;
    Ok(ffd_twist(degree, cps, twist, fi, fk)?)
}
