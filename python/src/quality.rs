//! `cell_quality`: signed measures and smallest scaled corner Jacobians of every cell.

use deform_cli::formats::CellList;
use deform_kernel::quality::{cell_measures, min_corner_jacobians};
use deform_kernel::Cells;
use numpy::prelude::*;
use numpy::{PyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::{cell_list, kernel_error, rows, Csr};

/// Two new float64 arrays.
type Pair<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);

/// `(measures, min_scaled_jacobians)` of `D`-dimensional points.
fn run<const D: usize>(flat: &[f64], c: &CellList) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let pts = rows::<D>(flat);
    let cells = Cells::new(pts.len(), &c.offsets, &c.nodes, &c.kinds)
        .map_err(|e| kernel_error("cells", e))?;
    let mut measures = vec![0.0; cells.len()];
    let mut jac = vec![0.0; cells.len()];
    cell_measures(&cells, &pts, &mut measures).map_err(|e| kernel_error("quality", e))?;
    min_corner_jacobians(&cells, &pts, true, &mut jac).map_err(|e| kernel_error("quality", e))?;
    Ok((measures, jac))
}

/// Signed measure (length, area, volume) and smallest scaled corner Jacobian of every cell.
#[pyfunction]
pub fn cell_quality<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    cells: Csr<'py>,
) -> PyResult<Pair<'py>> {
    let cells = cell_list(&cells)?;
    let flat = points.as_slice()?;
    let (m, j) = match points.shape()[1] {
        2 => run::<2>(flat, &cells)?,
        3 => run::<3>(flat, &cells)?,
        d => {
            return Err(PyValueError::new_err(format!(
                "points: {d} columns, not 2 or 3"
            )))
        }
    };
    Ok((PyArray1::from_vec(py, m), PyArray1::from_vec(py, j)))
}
