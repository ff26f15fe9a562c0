//! `read_su2` and `read_plot3d`: the `deform` tool's own readers (`deform_cli::files`), so a
//! script sees exactly the points, cells and markers `deform move` sees.

use std::path::PathBuf;

use deform_cli::formats::plot3d::Plot3dOptions;
use deform_cli::formats::CellList;
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::{cli_error, to_numpy};

/// CSR cells as three new numpy arrays.
type CsrOut<'py> = (
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<u32>>,
    Bound<'py, PyArray1<u8>>,
);

fn csr(py: Python<'_>, c: CellList) -> CsrOut<'_> {
    (
        PyArray1::from_vec(py, c.offsets),
        PyArray1::from_vec(py, c.nodes),
        PyArray1::from_vec(py, c.kinds),
    )
}

/// The `(N, dim)` points of `[f64; 3]` rows.
fn points(py: Python<'_>, p: Vec<[f64; 3]>, dim: usize) -> PyResult<Bound<'_, PyAny>> {
    if dim == 3 {
        return to_numpy(py, p);
    }
    to_numpy(py, p.into_iter().map(|q| [q[0], q[1]]).collect::<Vec<_>>())
}

/// An SU2 mesh: `(dim, points (N, dim), cells, [(marker, elements), ...])`.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn read_su2(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(
    usize,
    Bound<'_, PyAny>,
    CsrOut<'_>,
    Vec<(String, CsrOut<'_>)>,
)> {
    let mesh = py
        .detach(|| deform_cli::files::read_su2(&path))
        .map_err(cli_error)?;
    let markers = (mesh.markers.into_iter())
        .map(|m| (m.name, csr(py, m.elements)))
        .collect();
    let pts = points(py, mesh.points, mesh.dim)?;
    Ok((mesh.dim, pts, csr(py, mesh.elements), markers))
}

/// A Plot3D grid: `(dim, [(dims [ni, nj, nk], points (ni·nj·nk, dim) i fastest), ...])`.
#[pyfunction]
#[allow(clippy::type_complexity)]
pub fn read_plot3d(
    py: Python<'_>,
    path: PathBuf,
) -> PyResult<(usize, Vec<([usize; 3], Bound<'_, PyAny>)>)> {
    let (grid, _) = py
        .detach(|| deform_cli::files::read_plot3d(&path, &Plot3dOptions::default()))
        .map_err(cli_error)?;
    let dim = grid.dim;
    let blocks = (grid.blocks.into_iter())
        .map(|b| Ok((b.dims, points(py, b.points, dim)?)))
        .collect::<PyResult<_>>()?;
    Ok((dim, blocks))
}
