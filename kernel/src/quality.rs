//! Mesh quality: signed cell measures, inverted and folded cells, area ratios, wall angles.
//!
//! Everything works for 2D points (`D = 2`: triangles and quads) and 3D points (`D = 3`:
//! tetrahedra, hexahedra, prisms and pyramids), in VTK node order, for `f32` and `f64`.
//!
//! - **Signed measure** ([`cell_measures`]): triangle `½ (x1 − x0) × (x2 − x0)`; quad
//!   `½ (x2 − x0) × (x3 − x1)` (the shoelace area, equal to a quarter of the sum of the four
//!   corner Jacobians); tetrahedron `det(x1 − x0, x2 − x0, x3 − x0) / 6`; hexahedron by the
//!   divergence theorem over its bilinear faces (exact for trilinear cells); prism and pyramid as collapsed
//!   hexahedra (exact for their bilinear quad faces). Positive for counter-clockwise 2D cells
//!   and VTK-positive 3D cells (the VTK wedge's base `0,1,2` turns *away* from `3,4,5`).
//! - **Corner Jacobians** ([`min_corner_jacobians`]): in 2D `(next − c) × (previous − c)` at
//!   each corner; in 3D `det` of the corner's three edges in right-handed order (8 for a hex,
//!   6 for a prism, 4 for a tetrahedron, the 4 base corners for a pyramid). *Scaled*: divided
//!   by the product of the edge lengths (the sine of the corner angle in 2D).
//! - **Inverted** cell: the sign of the measure changed against the undeformed mesh (`> 0`
//!   became `≤ 0` or `< 0` became `≥ 0`). **Folded** cell: some corner Jacobian `≤ 0` (this
//!   also catches a bow-tie quad whose net area is still positive).
//! - **Measure ratio** deformed/undeformed, min and max over cells with a non-zero undeformed
//!   measure.
//! - **Wall angle**: change of the first grid-line angle at a marked wall
//!   ([`wall_angle_change`], defined precisely there).
//!
//! [`compare`] does all of it in one call and returns a [`QualityReport`]. Every routine
//! validates all inputs before writing anything.
//!
//! ```
//! use deform_kernel::quality::compare;
//! use deform_kernel::Cells;
//! // Two counter-clockwise triangles; the deformation pushes node 2 through edge 0–1.
//! let cells = Cells::new(4, &[0, 3, 6], &[0, 1, 2, 0, 2, 3], &[5, 5])?;
//! let before = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let after = [[0.0, 0.0], [1.0, 0.0], [0.5, -0.5], [0.0, 1.0]];
//! let r = compare(&cells, &before, &after, None, &mut [])?;
//! assert_eq!((r.inverted_cells, r.folded_cells), (1, 1));
//! assert_eq!(r.min_measure_ratio, -0.5);
//! # Ok::<(), deform_kernel::Error>(())
//! ```

mod element;
mod wall;

pub use element::CellQuality;
pub use wall::{wall_angle_change, wall_angle_scratch_len, Wall, WallAngleChange};

use crate::cells::{CellKind, Cells};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// Points match the cells, are finite, and every cell kind fits `D`.
fn check_cells<T: Real, const D: usize>(
    cells: &Cells<'_>,
    arg: &'static str,
    points: &[[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    check::len(arg, points.len(), cells.node_count())?;
    for (c, &code) in cells.kinds().iter().enumerate() {
        let dim = CellKind::from_vtk(code).map(CellKind::dimension);
        if dim != Some(D) {
            return Err(Error::CellDimension {
                cell: c,
                kind: code,
                dimension: D,
            });
        }
    }
    check::finite_items(arg, points)
}

fn check_out<T>(cells: &Cells<'_>, out: &[T]) -> Result<()> {
    check::len("out", out.len(), cells.len())?;
    Ok(())
}

/// Quality of every cell, in order (validated inputs).
fn each_cell<'c, T: Real, const D: usize>(
    cells: &Cells<'c>,
    points: &'c [[T; D]],
) -> impl Iterator<Item = CellQuality<T>> + 'c {
    cells.iter().map(move |(kind, nodes)| {
        let p = element::gather(points, nodes);
        element::evaluate(kind, &p, D == 2).unwrap_or(CellQuality {
            measure: T::ZERO,
            min_jacobian: T::ZERO,
            min_scaled_jacobian: T::ZERO,
        })
    })
}

/// Quality of one cell of kind `kind` from its corner coordinates (in VTK order).
///
/// # Errors
/// A kind that does not fit `D` ([`Error::CellDimension`] with
/// `cell` 0), the wrong number of corners, a non-finite coordinate.
pub fn cell_quality<T: Real, const D: usize>(
    kind: CellKind,
    corners: &[[T; D]],
) -> Result<CellQuality<T>> {
    check::mesh_dim::<D>();
    if kind.dimension() != D {
        return Err(Error::CellDimension {
            cell: 0,
            kind: kind.vtk_code(),
            dimension: D,
        });
    }
    check::len("corners", corners.len(), kind.node_count())?;
    check::finite_items("corners", corners)?;
    let mut p = [[T::ZERO; 3]; 8];
    for (slot, c) in p.iter_mut().zip(corners) {
        for (s, &x) in slot.iter_mut().zip(c.iter()) {
            *s = x;
        }
    }
    element::evaluate(kind, &p, D == 2).ok_or(Error::CellDimension {
        cell: 0,
        kind: kind.vtk_code(),
        dimension: D,
    })
}

/// Signed area (2D) or volume (3D) of every cell into `out` (`out.len() == cells.len()`).
///
/// # Errors
/// Nothing is written on error: `points.len() != cells.node_count()`, a cell kind that does not
/// fit `D`, a non-finite coordinate, `out` of the wrong length. `D` is 2 or 3, checked at
/// compile time:
///
/// ```compile_fail,E0080
/// # use deform_kernel::{cells::Cells, quality::cell_measures};
/// let cells = Cells::new(2, &[0, 2], &[0, 1], &[3]).unwrap();
/// let mut out = [0.0f64; 1];
/// // A 4-vector is not a mesh point: this does not compile.
/// let _ = cell_measures(&cells, &[[0.0f64; 4]; 2], &mut out);
/// ```
pub fn cell_measures<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    out: &mut [T],
) -> Result<()> {
    check_cells(cells, "points", points)?;
    check_out(cells, out)?;
    for (o, q) in out.iter_mut().zip(each_cell(cells, points)) {
        *o = q.measure;
    }
    Ok(())
}

/// Smallest corner Jacobian of every cell into `out`, scaled by the edge lengths when
/// `scaled` (see [`CellQuality`]). Same errors as [`cell_measures`].
///
/// # Errors
/// Those of [`cell_measures`] (nothing written).
pub fn min_corner_jacobians<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    scaled: bool,
    out: &mut [T],
) -> Result<()> {
    check_cells(cells, "points", points)?;
    check_out(cells, out)?;
    for (o, q) in out.iter_mut().zip(each_cell(cells, points)) {
        *o = if scaled {
            q.min_scaled_jacobian
        } else {
            q.min_jacobian
        };
    }
    Ok(())
}

/// Every cell's signed measure, smallest corner Jacobian and smallest scaled corner Jacobian
/// in one pass: the values of [`cell_measures`] and [`min_corner_jacobians`] (both kinds),
/// each cell evaluated once.
///
/// # Errors
/// As [`cell_measures`]; any output of the wrong length ([`Error::LengthMismatch`]). Nothing
/// is written on error.
pub fn cell_qualities<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    measure: &mut [T],
    min_jacobian: &mut [T],
    min_scaled_jacobian: &mut [T],
) -> Result<()> {
    check_cells(cells, "points", points)?;
    check::len("measure", measure.len(), cells.len())?;
    check::len("min_jacobian", min_jacobian.len(), cells.len())?;
    check::len(
        "min_scaled_jacobian",
        min_scaled_jacobian.len(),
        cells.len(),
    )?;
    let outs = measure
        .iter_mut()
        .zip(min_jacobian.iter_mut())
        .zip(min_scaled_jacobian.iter_mut());
    for (((m, j), s), q) in outs.zip(each_cell(cells, points)) {
        *m = q.measure;
        *j = q.min_jacobian;
        *s = q.min_scaled_jacobian;
    }
    Ok(())
}

/// `true` when the measure changed sign (a positive measure became `≤ 0`, a negative one
/// `≥ 0`). Cells with zero undeformed measure are never counted.
#[inline]
fn inverted<T: Real>(before: T, after: T) -> bool {
    (before > T::ZERO && after <= T::ZERO) || (before < T::ZERO && after >= T::ZERO)
}

/// Number of cells whose signed measure changed sign between `undeformed` and `deformed`.
///
/// # Errors
/// Either point array not matching `cells` ([`Error::LengthMismatch`]), a cell kind that does
/// not fit `D` ([`Error::CellDimension`]), a non-finite coordinate ([`Error::NonFinite`]).
pub fn inverted_cells<T: Real, const D: usize>(
    cells: &Cells<'_>,
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
) -> Result<usize> {
    check_cells(cells, "undeformed", undeformed)?;
    check_cells(cells, "deformed", deformed)?;
    Ok(each_cell(cells, undeformed)
        .zip(each_cell(cells, deformed))
        .filter(|(u, d)| inverted(u.measure, d.measure))
        .count())
}

/// Number of cells with a corner Jacobian `≤ 0` (folded or inverted at some corner).
///
/// # Errors
/// Those of [`inverted_cells`] for one point array.
pub fn folded_cells<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
) -> Result<usize> {
    check_cells(cells, "points", points)?;
    Ok(each_cell(cells, points)
        .filter(|q| q.min_jacobian <= T::ZERO)
        .count())
}

/// One-call quality comparison of a deformed mesh against the undeformed one.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct QualityReport<T> {
    /// Number of cells.
    pub cells: usize,
    /// Cells whose signed measure changed sign.
    pub inverted_cells: usize,
    /// Deformed cells with some corner Jacobian `≤ 0`.
    pub folded_cells: usize,
    /// Undeformed cells with some corner Jacobian `≤ 0` (should be 0 for a valid input mesh).
    pub folded_cells_undeformed: usize,
    /// Cells with zero undeformed measure (excluded from the ratios).
    pub degenerate_cells: usize,
    /// Smallest deformed/undeformed measure ratio (`+∞` when no cell has a ratio); negative
    /// when some cell inverted.
    pub min_measure_ratio: T,
    /// The cell where the smallest ratio occurs (first on ties).
    pub min_ratio_cell: Option<usize>,
    /// Largest deformed/undeformed measure ratio (`−∞` when no cell has a ratio).
    pub max_measure_ratio: T,
    /// The cell where the largest ratio occurs (first on ties).
    pub max_ratio_cell: Option<usize>,
    /// Smallest deformed measure (`+∞` for an empty mesh).
    pub min_measure: T,
    /// Smallest scaled corner Jacobian of the deformed mesh (`+∞` for an empty mesh).
    pub min_scaled_jacobian: T,
    /// The wall-angle change, when a wall was given.
    pub wall: Option<WallAngleChange<T>>,
}

/// Compares `deformed` against `undeformed` over `cells`: inverted and folded cells, measure
/// ratios, smallest scaled Jacobian and, when `wall` is given, the first grid-line angle
/// change at that wall ([`wall_angle_change`]; `scratch` then needs
/// [`wall_angle_scratch_len`] items and is overwritten, otherwise it may be empty).
///
/// # Errors
/// Nothing is written on error: as [`cell_measures`] for both point arrays, and as
/// [`wall_angle_change`] for the wall.
pub fn compare<T: Real, const D: usize>(
    cells: &Cells<'_>,
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
    wall: Option<&Wall<'_>>,
    scratch: &mut [[T; D]],
) -> Result<QualityReport<T>> {
    check_cells(cells, "undeformed", undeformed)?;
    check_cells(cells, "deformed", deformed)?;
    if let Some(w) = wall {
        wall::check_wall(w, undeformed, deformed)?;
        let needed = wall_angle_scratch_len(undeformed.len());
        check::buffer("scratch", scratch.len(), needed)?;
    }
    let mut r = QualityReport {
        cells: cells.len(),
        inverted_cells: 0,
        folded_cells: 0,
        folded_cells_undeformed: 0,
        degenerate_cells: 0,
        min_measure_ratio: T::INFINITY,
        min_ratio_cell: None,
        max_measure_ratio: -T::INFINITY,
        max_ratio_cell: None,
        min_measure: T::INFINITY,
        min_scaled_jacobian: T::INFINITY,
        wall: None,
    };
    let pairs = each_cell(cells, undeformed).zip(each_cell(cells, deformed));
    for (c, (u, d)) in pairs.enumerate() {
        if inverted(u.measure, d.measure) {
            r.inverted_cells += 1;
        }
        if d.min_jacobian <= T::ZERO {
            r.folded_cells += 1;
        }
        if u.min_jacobian <= T::ZERO {
            r.folded_cells_undeformed += 1;
        }
        r.min_measure = r.min_measure.min(d.measure);
        r.min_scaled_jacobian = r.min_scaled_jacobian.min(d.min_scaled_jacobian);
        if u.measure == T::ZERO {
            r.degenerate_cells += 1;
            continue;
        }
        let ratio = d.measure / u.measure;
        if r.min_ratio_cell.is_none() || ratio < r.min_measure_ratio {
            r.min_measure_ratio = ratio;
            r.min_ratio_cell = Some(c);
        }
        if r.max_ratio_cell.is_none() || ratio > r.max_measure_ratio {
            r.max_measure_ratio = ratio;
            r.max_ratio_cell = Some(c);
        }
    }
    if let Some(w) = wall {
        r.wall = Some(wall::compute(w, undeformed, deformed, scratch));
    }
    Ok(r)
}
