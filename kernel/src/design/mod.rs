//! SU2's surface design variables, evaluated as SU2_DEF does (`CSurfaceMovement`,
//! `CFreeFormDefBox`, `CBezierBlending`), so a solver (or `deform su2`) can apply them itself:
//!
//! - [`hicks_henne`]: `HICKS_HENNE` bumps on a set of surface nodes.
//! - [`ffd`]: Bernstein free-form deformation boxes (`FFD_*` sections of an SU2 mesh): the
//!   box evaluated at stored parametric coordinates, surface displacements after control
//!   points move.
//! - [`variables`]: the control-point changes of `FFD_CONTROL_POINT(_2D)`,
//!   `FFD_CAMBER(_2D)` and `FFD_THICKNESS(_2D)`.
//! - [`twist`]: `FFD_TWIST`, a layer of control points turned about a y-parallel axis.
//! - [`sensitivity`]: their derivatives (tangent and adjoint), for SU2_DOT's `dJ/dα`.
//!
//! Everything is allocation-free (the Bernstein basis lives in fixed stack arrays, hence
//! [`ffd::MAX_DEGREE`]), validates before it writes, and uses libm for every transcendental
//! function, without fused multiply-add. `docs/design-variables.md` maps each SU2 `DV_KIND` to
//! these calls.

pub mod ffd;
pub mod hicks_henne;
pub mod sensitivity;
pub mod twist;
pub mod variables;

/// SU2's `EPS` (`option_structure.hpp`): displacements this small are set to zero by SU2's
/// `SetCartesianCoord`, and Hicks–Henne bumps vanish for `x ≤ 10 EPS`.
pub const SU2_EPS: f64 = 1e-16;

use crate::error::{Error, Result};
use crate::real::Real;

/// Every listed point finite ([`Error::NonFinite`] naming the first bad node).
fn listed_points_finite<T: Real, const D: usize>(points: &[[T; D]], nodes: &[u32]) -> Result<()> {
    match nodes
        .iter()
        .find(|&&n| (points.get(n as usize)).is_some_and(|p| !p.iter().all(|c| c.is_finite())))
    {
        Some(&n) => Err(Error::NonFinite {
            arg: "points",
            position: n as usize,
        }),
        None => Ok(()),
    }
}
