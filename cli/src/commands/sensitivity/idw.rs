//! `--method idw` of `deform adjoint` and `deform tangent`: the derivative of Samareh's
//! quaternion method with inverse-distance propagation (`deform move --method idw`, exact or
//! with `--idw-theta` the fast tree-based sums) with respect to the deformed boundary
//! positions, through the kernel's `quaternion::deform_idw_tangent` / `_adjoint` and
//! `deform_idw_fast_tangent` / `_adjoint` (the forward's cluster choices held). Linearised
//! about the boundary of `--deformed`, as `--method quaternion` (`quaternion.rs`).

use deform_kernel::quaternion::{
    deform_idw_adjoint, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_sensitivity_scratch_len, deform_idw_tangent,
    propagate_idw_fast_index_len, propagate_idw_fast_scratch_len, BoundaryMotion, IdwFastOptions,
};
use deform_kernel::Quat;

use super::quaternion::Point;
use super::{kernel, scatter, Solved};
use crate::args::SensitivitySetup;
use crate::error::CliError;
use crate::formats::su2::Su2Mesh;

/// The fast form's workspaces (as `deform move --idw-theta` sizes them) and options.
struct Fast<const D: usize> {
    options: IdwFastOptions<f64>,
    translations: Vec<[f64; D]>,
    rotations: Vec<Quat<f64>>,
    scratch: Vec<f64>,
    index: Vec<u32>,
    tree: Vec<f64>,
}

impl<const D: usize> Fast<D> {
    fn new(theta: f64, tolerance: f64, n: usize, b: usize) -> Self {
        Fast {
            options: IdwFastOptions { theta, tolerance },
            translations: vec![[0.0; D]; n],
            rotations: vec![Quat::identity(); n],
            scratch: vec![0.0; deform_idw_fast_sensitivity_scratch_len::<D>(n, b)],
            index: vec![0u32; propagate_idw_fast_index_len(b)],
            tree: vec![0.0; propagate_idw_fast_scratch_len::<D>(b)],
        }
    }
}

/// Which direction: `(input, out)`, the tangent's `(δd per boundary point, δR per node)` or
/// the adjoint's `(w per node, dJ/dd per boundary point)`.
type Io<'a, const D: usize> = (&'a [[f64; D]], &'a mut [[f64; D]]);

/// Runs the exact or fast tangent (`tangent`) or adjoint on `motion`.
fn run<const D: usize>(
    setup: &SensitivitySetup,
    p: &Point<D>,
    motion: &BoundaryMotion<'_, f64, D>,
    tangent: bool,
    (input, out): Io<'_, D>,
) -> Result<(), CliError> {
    let (n, b, e) = (p.points.len(), motion.nodes.len(), setup.idw_exponent);
    let Some(theta) = setup.idw_theta else {
        let mut s = vec![0.0; deform_idw_sensitivity_scratch_len::<D>(n, b)];
        return if tangent {
            deform_idw_tangent(&p.points, motion, e, input, &mut s, out)
                .map_err(kernel("quaternion IDW tangent"))
        } else {
            deform_idw_adjoint(&p.points, motion, e, input, &mut s, out)
                .map_err(kernel("quaternion IDW adjoint"))
        };
    };
    let mut f = Fast::<D>::new(theta, setup.idw_tolerance, n, b);
    let (tr, rot, s) = (&mut f.translations, &mut f.rotations, &mut f.scratch);
    let (index, tree, o) = (&mut f.index, &mut f.tree, &f.options);
    if tangent {
        deform_idw_fast_tangent(&p.points, motion, e, o, input, tr, rot, s, index, tree, out)
            .map_err(kernel("fast quaternion IDW tangent"))
    } else {
        deform_idw_fast_adjoint(&p.points, motion, e, o, input, tr, rot, s, index, tree, out)
            .map_err(kernel("fast quaternion IDW adjoint"))
    }
}

/// `J v` for `dx` holding `v` at the boundary nodes.
pub(super) fn tangent<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    dx: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let p = Point::<D>::new(setup, mesh, boundary)?;
    let direction: Vec<[f64; D]> = boundary.iter().map(|&b| dx[b as usize]).collect();
    let mut out = vec![[0.0; D]; p.points.len()];
    run(
        setup,
        &p,
        &p.motion(boundary)?,
        true,
        (&direction, &mut out),
    )?;
    Ok((out, None))
}

/// `Jᵀ w` at every node (zero off the boundary).
pub(super) fn adjoint<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let p = Point::<D>::new(setup, mesh, boundary)?;
    let mut back = vec![[0.0; D]; boundary.len()];
    run(setup, &p, &p.motion(boundary)?, false, (w, &mut back))?;
    Ok((scatter(boundary, &back, p.points.len()), None))
}
