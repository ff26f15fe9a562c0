//! `dk_elasticity_rigid_layer`: the rigid wall layer of elasticity (the kernel's
//! `elasticity::rigid_layer`). The nodes near the moving wall are marked fixed and given the
//! wall's local rigid motion before the increments (`dk_elasticity_deform` and its
//! multigrid and sliding twins), so the first grid lines keep their angle to the wall.

use deform_kernel::elasticity::rigid_layer;
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{read_points, rebase, Dim};
use crate::slice::{chunks_mut, input, output, quats, In, Out};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Marks every node within `thickness` of a `wall` node (node indices in `index_base`) as
/// fixed (`fixed[i] = 1`) and writes its displacement: the rigid motion of its nearest wall
/// node `w`, `d_w + Q_w (x − x_w) Q_w* − (x − x_w)`, `d_w` read from `displacement` at `w` and
/// `Q_w` from `rotations` (4 scalars per wall node, scalar first; one rotation repeated for a
/// rigid body). Nodes already fixed keep their displacement; `added` gets the number of nodes
/// marked. Then run the increments with this `fixed` and `displacement`. `points`: `N * dim`
/// scalars of the undeformed mesh, `dim` 2 or 3; `fixed`: `N` bytes; `displacement`:
/// `N * dim`. With `index_base` 1, `index_scratch` needs `wall_len` entries (NULL with length
/// 0 for base 0). `O(N·B)`. Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (empty wall,
/// `thickness` negative or not finite, `dim`), `DK_ERR_INDEX_OUT_OF_RANGE`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a rotation too short to normalise),
/// `DK_ERR_BAD_INDEX_BASE`, length and pointer errors.
#[export(twin, added[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_elasticity_rigid_layer<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    wall: In<'_, u32>,
    index_base: u32,
    index_scratch: Out<'_, u32>,
    rotations: In<'_, T>,
    thickness: T,
    fixed: Out<'_, u8>,
    displacement: Out<'_, T>,
    added: Out<'_, usize>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let (w, _) = rebase(input(wall)?, index_base, output(index_scratch)?)?;
    let q = quats(rotations)?;
    let count = crate::slice::out_one(added)?;
    let displacement = chunks_mut::<T, D>(displacement)?;
    *count = rigid_layer(p, w, q, thickness, output(fixed)?, displacement)?;
    Ok(())
}
