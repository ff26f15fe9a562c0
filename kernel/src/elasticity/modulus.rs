//! Element-wise Young's modulus, SU2's `DEFORM_STIFFNESS_TYPE` for its mesh solver:
//! constant, inverse cell volume (`E = 1/V`: small cells stiffer) or inverse wall distance
//! (`E = 1/d`: cells near the walls stiffer). The moduli are normalised by their mean
//! volume or distance: a global factor does not change the displacement (the boundary
//! data are displacements, not loads), and values near 1 keep the solve well scaled.

use super::element;
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// How each cell's Young's modulus is chosen (SU2 `DEFORM_STIFFNESS_TYPE`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Modulus {
    /// `E = 1` everywhere (SU2 `CONSTANT_STIFFNESS`).
    Constant,
    /// `E = V̄ / V_c` (SU2 `INVERSE_VOLUME`; `V̄` the mean cell measure).
    InverseVolume,
    /// `E = d̄ / max(d_c, 10⁻³ d̄)` with `d_c` the mean wall distance of the cell's nodes
    /// (SU2 `WALL_DISTANCE`; `d̄` the mean of the `d_c`).
    WallDistance,
}

/// Young's modulus of every cell into `out` (`cells.len()` values). `wall_distance` (one
/// value per node, e.g. from [`wall_distances`](crate::spring::wall_distances)) is needed by
/// [`Modulus::WallDistance`] and ignored otherwise.
///
/// # Errors
/// Nothing is written on error: `points.len() != cells.node_count()` or `out` of the wrong
/// length ([`Error::LengthMismatch`]); a non-finite coordinate ([`Error::NonFinite`]); a cell
/// whose kind does not fit `D` ([`Error::CellDimension`]); a degenerate cell
/// ([`Error::NonPositive`], `"cells"`, for [`Modulus::InverseVolume`]); a missing, mis-sized,
/// negative or non-finite `wall_distance`, or distances that are all zero
/// ([`Error::InvalidParameter`], [`Error::LengthMismatch`], [`Error::NonPositive`],
/// [`Error::NonFinite`]).
pub fn cell_moduli<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    modulus: Modulus,
    wall_distance: Option<&[T]>,
    out: &mut [T],
) -> Result<()> {
    check::mesh_dim::<D>();
    super::check_mesh(cells, points)?;
    check::len("out", out.len(), cells.len())?;
    match modulus {
        Modulus::Constant => out.iter_mut().for_each(|e| *e = T::ONE),
        Modulus::InverseVolume => inverse_volume(cells, points, out)?,
        Modulus::WallDistance => {
            let d = wall_distance.ok_or(Error::InvalidParameter {
                arg: "wall_distance",
                reason: "is needed by the wall-distance modulus",
            })?;
            inverse_distance(cells, d, out)?;
        }
    }
    Ok(())
}

/// `E_c = V̄ / V_c`; checks every cell before writing.
fn inverse_volume<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    out: &mut [T],
) -> Result<()> {
    let mut total = T::ZERO;
    for (c, (kind, nodes)) in cells.iter().enumerate() {
        let v = cell_measure(kind, nodes, points).unwrap_or(T::ZERO);
        if v <= T::ZERO || !v.is_finite() {
            return Err(Error::NonPositive {
                arg: "cells",
                position: c,
            });
        }
        total += v;
    }
    let mean = total / T::from_usize(cells.len().max(1));
    for ((kind, nodes), e) in cells.iter().zip(out.iter_mut()) {
        let v = cell_measure(kind, nodes, points).unwrap_or(T::ONE);
        *e = mean / v;
    }
    Ok(())
}

/// `E_c = d̄ / max(d_c, 10⁻³ d̄)`; checks the distances before writing.
fn inverse_distance<T: Real>(cells: &Cells<'_>, d: &[T], out: &mut [T]) -> Result<()> {
    check::len("wall_distance", d.len(), cells.node_count())?;
    check::finite("wall_distance", d)?;
    if let Some(position) = d.iter().position(|&x| x < T::ZERO) {
        return Err(Error::NonPositive {
            arg: "wall_distance",
            position,
        });
    }
    let cell_d = |nodes: &[u32]| {
        let s = nodes.iter().fold(T::ZERO, |s, &n| {
            s + d.get(n as usize).copied().unwrap_or(T::ZERO)
        });
        s / T::from_usize(nodes.len().max(1))
    };
    let total = cells
        .iter()
        .fold(T::ZERO, |s, (_, nodes)| s + cell_d(nodes));
    let mean = total / T::from_usize(cells.len().max(1));
    if mean <= T::ZERO || !mean.is_finite() {
        return Err(Error::InvalidParameter {
            arg: "wall_distance",
            reason: "must not be zero at every node",
        });
    }
    let floor = mean * T::from_f64(1e-3);
    for ((_, nodes), e) in cells.iter().zip(out.iter_mut()) {
        *e = mean / cell_d(nodes).max(floor);
    }
    Ok(())
}

/// The cell's measure from its Gauss points (`None` when degenerate).
pub(crate) fn cell_measure<T: Real, const D: usize>(
    kind: crate::cells::CellKind,
    nodes: &[u32],
    points: &[[T; D]],
) -> Option<T> {
    let mut x = [[T::ZERO; D]; element::MAX_NODES];
    for (x, &n) in x.iter_mut().zip(nodes) {
        *x = *points.get(n as usize)?;
    }
    element::measure(kind, x.get(..nodes.len())?)
}
