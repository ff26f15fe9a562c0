//! `--method quaternion` of `deform adjoint` and `deform tangent`: the derivative of Samareh's
//! quaternion method with linear-spring propagation (`deform move --method quaternion`, Batina
//! stiffness, multigrid CG) with respect to the deformed boundary positions, through the
//! kernel's `quaternion::deform_spring_tangent` / `deform_spring_adjoint`. The method is
//! nonlinear: it is linearised about the deformed boundary of `--deformed` (default: the
//! undeformed mesh, zero motion), rotations from the boundary shape (every marker's elements),
//! origin the centroid of the moving boundary nodes.

use deform_kernel::quaternion::{
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    BoundaryMotion, RotationSource,
};

use super::{converged, kernel, scatter, with_springs, Solved};
use crate::args::SensitivitySetup;
use crate::engine::{cells_view, points_d};
use crate::error::CliError;
use crate::files::read_su2;
use crate::formats::su2::Su2Mesh;
use crate::formats::CellList;

/// The points of `--deformed` (same count and dimension as `mesh`), or `mesh`'s own.
pub(super) fn deformed_points(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
) -> Result<Vec<[f64; 3]>, CliError> {
    let Some(path) = &setup.deformed else {
        return Ok(mesh.points.clone());
    };
    let (def, n) = (read_su2(path)?, mesh.points.len());
    if def.points.len() != n || def.dim != mesh.dim {
        return Err(CliError::Invalid(format!(
            "{}: {} points in {}D, the mesh has {n} in {}D",
            path.display(),
            def.points.len(),
            def.dim,
            mesh.dim
        )));
    }
    Ok(def.points)
}

/// The linearisation point: the undeformed points, the deformed boundary (one per boundary
/// node, in `boundary` order) and every marker's elements in boundary numbering (also that of
/// `--method idw`).
pub(super) struct Point<const D: usize> {
    pub(super) points: Vec<[f64; D]>,
    deformed: Vec<[f64; D]>,
    elements: CellList,
}

impl<const D: usize> Point<D> {
    pub(super) fn new(
        setup: &SensitivitySetup,
        mesh: &Su2Mesh,
        boundary: &[u32],
    ) -> Result<Self, CliError> {
        let n = mesh.points.len();
        let at = deformed_points(setup, mesh)?;
        let mut local = vec![u32::MAX; n];
        for (k, &b) in boundary.iter().enumerate() {
            local[b as usize] = k as u32;
        }
        let mut elements = CellList::new();
        for m in &mesh.markers {
            for c in 0..m.elements.len() {
                let (a, b) = (m.elements.offsets[c], m.elements.offsets[c + 1]);
                let nodes: Vec<u32> = m.elements.nodes[a as usize..b as usize]
                    .iter()
                    .map(|&v| local[v as usize])
                    .collect();
                if !elements.push_code(m.elements.kinds[c], &nodes) {
                    return Err(CliError::Invalid("too many boundary elements".into()));
                }
            }
        }
        let deformed = boundary.iter().map(|&b| at[b as usize]).collect::<Vec<_>>();
        Ok(Point {
            points: points_d::<D>(&mesh.points),
            deformed: points_d::<D>(&deformed),
            elements,
        })
    }

    /// The boundary motion of this point (`boundary`: the mesh node of each boundary point).
    pub(super) fn motion<'a>(
        &'a self,
        boundary: &'a [u32],
    ) -> Result<BoundaryMotion<'a, f64, D>, CliError> {
        Ok(BoundaryMotion {
            nodes: boundary,
            deformed: &self.deformed,
            elements: Some(cells_view(&self.elements, boundary.len())?),
            rotations: RotationSource::Shape,
            origin: None,
        })
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
    let n = p.points.len();
    with_springs::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
        let motion = p.motion(boundary)?;
        let len = deform_spring_sensitivity_scratch_len::<f64, D>(&solver, n, boundary.len());
        let (mut s, mut out) = (vec![0.0; len], vec![[0.0; D]; n]);
        let r = deform_spring_tangent(
            &p.points, &motion, sys, solver, stop, &direction, &mut s, &mut out,
        )
        .map_err(kernel("quaternion tangent"))?;
        Ok((out, Some(converged(r)?)))
    })
}

/// `Jᵀ w` at every node (zero off the boundary).
pub(super) fn adjoint<const D: usize>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let p = Point::<D>::new(setup, mesh, boundary)?;
    let n = p.points.len();
    with_springs::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
        let motion = p.motion(boundary)?;
        let len = deform_spring_sensitivity_scratch_len::<f64, D>(&solver, n, boundary.len());
        let (mut s, mut back) = (vec![0.0; len], vec![[0.0; D]; boundary.len()]);
        let r = deform_spring_adjoint(&p.points, &motion, sys, solver, stop, w, &mut s, &mut back)
            .map_err(kernel("quaternion adjoint"))?;
        Ok((scatter(boundary, &back, n), Some(converged(r)?)))
    })
}
