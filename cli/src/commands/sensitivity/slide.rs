//! `--slide` for `deform adjoint` and `deform tangent` (and `adjoint --config`'s
//! MARKER_DEFORM_MESH_SYM_PLANE): the sliding markers' nodes slide on their planes as in
//! `deform move --slide` / `deform su2` (the same constraint table: planes fitted to the
//! markers, lines where two meet, nodes on more planes pinned, nodes also on another marker
//! fixed), and the derivative is that of the constrained deformation (the kernel's
//! `sensitivity::*_sliding_*`). Covered: the linear springs and single-step elasticity; any
//! other method is refused (its derivative would be that of another map).

use crate::args::{SensitivityMethod, SensitivitySetup};
use crate::engine::{points_d, slide_constraints, SlideMarker};
use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::su2::Su2Mesh;

/// Each node's constraint kind (the kernel's codes) and direction (zero-padded to 3).
pub(super) struct Slide {
    pub kinds: Vec<u8>,
    pub directions: Vec<[f64; 3]>,
}

impl Slide {
    /// The directions in `D` components.
    pub(super) fn directions<const D: usize>(&self) -> Vec<[f64; D]> {
        points_d::<D>(&self.directions)
    }
}

/// Refuses `--slide` for a method whose sliding derivative is not built.
pub(super) fn check(setup: &SensitivitySetup) -> Result<(), CliError> {
    if setup.slide.is_empty() {
        return Ok(());
    }
    match setup.method() {
        SensitivityMethod::Spring => Ok(()),
        SensitivityMethod::Elasticity if setup.steps == 1 => Ok(()),
        _ => Err(CliError::NotAvailable {
            feature: "sliding markers (--slide, MARKER_DEFORM_MESH_SYM_PLANE) in the derivative",
            needs: "--method spring or --method elasticity with one step (--steps 1); the \
                    other methods' derivatives hold the sliding markers fixed, another map \
                    than deform move --slide",
        }),
    }
}

/// The boundary (prescribed) nodes: every marker's but the sliding ones', and the sliding
/// nodes pinned on too many planes; with the sliding markers, their constraint table.
pub(super) fn boundary(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
) -> Result<(Vec<u32>, Option<Slide>), CliError> {
    let fixed: Vec<String> = (mesh.markers.iter())
        .map(|m| m.name.clone())
        .filter(|m| !setup.slide.contains(m))
        .collect();
    let mut boundary = marker_nodes(mesh, &fixed, &setup.mesh)?;
    if setup.slide.is_empty() {
        return Ok((boundary, None));
    }
    marker_nodes(mesh, &setup.slide, &setup.mesh)?; // every name exists
    let sliding: Vec<SlideMarker<'_>> = (mesh.markers.iter())
        .filter(|m| setup.slide.contains(&m.name))
        .map(|m| SlideMarker {
            name: &m.name,
            elements: &m.elements,
        })
        .collect();
    let (kinds, directions, pinned) = if mesh.dim == 2 {
        let (k, d, p) = slide_constraints(&points_d::<2>(&mesh.points), &boundary, &sliding)?;
        (k, d.iter().map(|v| [v[0], v[1], 0.0]).collect(), p)
    } else {
        slide_constraints(&points_d::<3>(&mesh.points), &boundary, &sliding)?
    };
    boundary.extend(pinned);
    boundary.sort_unstable();
    boundary.dedup();
    Ok((boundary, Some(Slide { kinds, directions })))
}

/// `--slide` on a Plot3D grid (which has no markers).
pub(super) fn not_on_grid(setup: &SensitivitySetup) -> Result<(), CliError> {
    if setup.slide.is_empty() {
        return Ok(());
    }
    Err(CliError::Invalid(
        "--slide names SU2 markers; a Plot3D grid has none".into(),
    ))
}
