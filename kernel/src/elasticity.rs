//! Mesh deformation by linear elasticity, as SU2_DEF does it: the mesh is an isotropic
//! elastic solid (plane strain in 2D) whose boundary displacements are prescribed, and the
//! interior follows by solving `K u = 0` at the free nodes.
//!
//! - **Elements**: P1 triangles and tetrahedra, Q1 quadrilaterals and hexahedra (2×2 and
//!   2×2×2 Gauss points), prisms (3×2) and pyramids (the collapsed hexahedron, 2×2×2), the
//!   kernel's [`CellKind`](crate::CellKind)s in VTK node order; every element passes the patch
//!   test (a linear displacement field is reproduced to rounding).
//! - **Young's modulus** per cell ([`Modulus`], SU2's `DEFORM_STIFFNESS_TYPE`): constant,
//!   inverse volume or inverse wall distance ([`cell_moduli`]); Poisson ratio `ν ∈ (−1, ½)` (above ½:
//!   SU2's `DEFORM_COEFF` convention, λ ≈ −μ).
//! - **Assembly** ([`assemble`]) into `D×D` blocks on the graph of node pairs that share a
//!   cell ([`elasticity_graph`]): one block per node, one per directed edge, in cell order
//!   (the same bits everywhere; block `i → j` is exactly the transpose of `j → i`).
//! - **Solve** ([`ElasticSystem`]): Dirichlet data eliminated symmetrically, conjugate
//!   gradients of the kernel's Krylov core with exact inner products, preconditioned by the
//!   node blocks or by the scalar smoothed-aggregation V-cycle on every displacement
//!   component ([`ElasticSystem::solve_amg`]).
//! - **Rigid wall layer** ([`rigid_layer`]): the nodes near the moving wall take its local
//!   rigid motion (the quaternion method's near-wall rotation), so the first grid lines keep
//!   their angle to the wall.
//! - **Load increments** ([`deform_incremental`], SU2's `DEFORM_NONLINEAR_ITER`): the
//!   boundary displacement in `N` equal steps, the moduli and stiffness recomputed on the
//!   updated mesh before each.

mod assemble;
pub(crate) mod element;
mod increments;
mod layer;
mod modulus;
mod rigid;
mod sliding;
mod system;

pub use assemble::{assemble, elasticity_graph, elasticity_graph_len, Block};
pub(crate) use increments::{advance, step_data};
pub use increments::{
    deform_incremental, deform_incremental_on, IncrementBuffers, IncrementReport, Increments,
};
pub use layer::rigid_layer;
pub use modulus::{cell_moduli, Modulus};
pub use rigid::elastic_rigid_amg_scratch_len;
pub use sliding::{
    elastic_amg_sliding_scratch_len, elastic_rigid_amg_sliding_scratch_len,
    elastic_sliding_scratch_len,
};
pub use system::{elastic_amg_scratch_len, elastic_scratch_len, ElasticSystem};

use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// `points` fit `cells` (length, finite) and every cell is a volume element of dimension `D`.
fn check_mesh<T: Real, const D: usize>(cells: &Cells<'_>, points: &[[T; D]]) -> Result<()> {
    check::len("points", points.len(), cells.node_count())?;
    check::finite_items("points", points)?;
    for (cell, (kind, _)) in cells.iter().enumerate() {
        if kind.dimension() != D {
            return Err(Error::CellDimension {
                cell,
                kind: kind.vtk_code(),
                dimension: D,
            });
        }
    }
    Ok(())
}

/// The Poisson ratio is finite, above −1 and not ½ (where λ is infinite). `(−1, ½)` is the
/// stable range; above ½ is SU2's convention for mesh deformation (`DEFORM_COEFF`, 1e6 by
/// default; Dwight 2009): λ ≈ −μ, a bulk modulus near zero that favours locally rigid-and-
/// scaled motion. Such a material is not stable in general: a solve whose operator is not
/// positive definite stops with [`Error::SingularSystem`], it never returns a wrong answer.
pub(crate) fn check_poisson<T: Real>(nu: T) -> Result<()> {
    if nu.is_finite() && nu > -T::ONE && nu != T::HALF {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            arg: "poisson",
            reason: "must be finite, above -1 and not 1/2",
        })
    }
}
