//! `smooth_block`: Alter's arclength Taubin filter along one direction of a structured block,
//! with the options `deform smooth` gives it (cli/src/engine.rs `smooth_d`).

use deform_kernel::taubin::{
    smooth_arclength, smooth_arclength_scratch_len, Coarse, Prolongation, SmoothOptions,
    TaubinParams,
};
use deform_kernel::{Block, Direction};
use numpy::prelude::*;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::{kernel_error, rows, to_numpy};

/// The filter's settings, as the Python call gives them.
struct Settings {
    dims: [usize; 3],
    direction: Direction,
    iterations: usize,
    params: TaubinParams<f64>,
    normalised: bool,
    coarse: Option<usize>,
}

/// `(points, iterations, largest stretching before, after, largest point move)`.
type Smoothed<const D: usize> = (Vec<[f64; D]>, usize, f64, f64, f64);

fn run<const D: usize>(
    flat: &[f64],
    s: &Settings,
    fixed: Option<&[u8]>,
) -> Result<Smoothed<D>, (&'static str, deform_kernel::Error)> {
    let block = Block::new(s.dims).map_err(|e| ("block", e))?;
    let mut pts = rows::<D>(flat);
    let mut options = SmoothOptions::new(s.direction);
    options.params = s.params;
    options.iterations = s.iterations;
    options.normalised = s.normalised;
    options.fixed = fixed;
    if let Some(m) = s.coarse {
        let mut factor = [m; 3];
        factor[s.direction.index()] = 1;
        if D == 2 {
            factor[2] = 1;
        }
        options.coarse = Some(Coarse {
            factor,
            prolongation: Prolongation::Values,
        });
        options.coarse_iterations = (s.iterations / 2).max(1);
    }
    let len = smooth_arclength_scratch_len::<D>(&block, s.direction, options.coarse.as_ref());
    let mut scratch = vec![0.0; len];
    let r = smooth_arclength(&block, &mut pts, &options, &mut scratch)
        .map_err(|e| ("arclength smoothing", e))?;
    let (before, after) = (r.stretching_before.0, r.stretching_after.0);
    Ok((pts, r.iterations, before, after, r.max_displacement))
}

/// Smooths a block of `dims = (ni, nj, nk)` points stored i fastest (see
/// `deform_kernel.smooth_structured`): `(new_points, iterations, stretching_before,
/// stretching_after, max_point_move)`.
#[pyfunction]
#[pyo3(signature = (points, dims, direction, iterations, lam, mu, normalised, fixed, coarse))]
#[allow(clippy::too_many_arguments)]
pub fn smooth_block<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    dims: [usize; 3],
    direction: &str,
    iterations: usize,
    lam: f64,
    mu: f64,
    normalised: bool,
    fixed: Option<PyReadonlyArray1<'py, u8>>,
    coarse: Option<usize>,
) -> PyResult<(Bound<'py, PyAny>, usize, f64, f64, f64)> {
    let direction = match direction {
        "i" => Direction::I,
        "j" => Direction::J,
        "k" => Direction::K,
        d => {
            return Err(PyValueError::new_err(format!(
                "direction: {d:?} (i, j or k)"
            )))
        }
    };
    let s = Settings {
        dims,
        direction,
        iterations,
        params: TaubinParams { lambda: lam, mu },
        normalised,
        coarse,
    };
    let flat = points.as_slice()?.to_vec();
    let mask = match &fixed {
        Some(f) => Some(f.as_slice()?.to_vec()),
        None => None,
    };
    let mask = mask.as_deref();
    macro_rules! go {
        ($d:literal) => {{
            let r = py.detach(|| run::<$d>(&flat, &s, mask));
            let (p, it, b, a, m) = r.map_err(|(c, e)| kernel_error(c, e))?;
            Ok((to_numpy(py, p)?, it, b, a, m))
        }};
    }
    match points.shape()[1] {
        2 => go!(2),
        3 => go!(3),
        d => Err(PyValueError::new_err(format!(
            "points: {d} columns, not 2 or 3"
        ))),
    }
}

/// Taubin λ|μ fairing of mesh points on the edge graph of `cells` (the kernel's
/// `smooth_graph`), uniform or inverse-distance weights, optional fixed mask.
fn graph_run<const D: usize>(
    flat: &[f64],
    cells: &deform_cli::formats::CellList,
    g: &GraphSettings,
    fixed: Option<&[u8]>,
) -> Result<(Vec<[f64; D]>, f64), Failed> {
    use deform_kernel::taubin::{inverse_distance_weights, smooth_graph, GraphOptions};
    let mut pts = rows::<D>(flat);
    let n = pts.len();
    let c = deform_kernel::Cells::new(n, &cells.offsets, &cells.nodes, &cells.kinds)
        .map_err(|e| ("cells", e))?;
    let (offsets, targets) = crate::edge_graph(&c).map_err(|e| ("graph", e))?;
    let graph = deform_kernel::Graph::new(&offsets, &targets).map_err(|e| ("graph", e))?;
    let mut w = Vec::new();
    if g.inverse_distance {
        w = vec![0.0; graph.edge_count()];
        inverse_distance_weights(&graph, &pts, &mut w).map_err(|e| ("weights", e))?;
    }
    let options = GraphOptions {
        weights: g.inverse_distance.then_some(&w[..]),
        fixed,
    };
    let mut scratch = vec![[0.0; D]; n];
    let r = smooth_graph(
        &graph,
        &mut pts,
        g.params,
        g.iterations,
        &options,
        &mut scratch,
    )
    .map_err(|e| ("graph smoothing", e))?;
    Ok((pts, r.last_change))
}

/// A kernel error with the step that raised it.
type Failed = (&'static str, deform_kernel::Error);

/// The graph filter's settings.
struct GraphSettings {
    params: TaubinParams<f64>,
    iterations: usize,
    inverse_distance: bool,
}

/// Smooths unstructured mesh points (see `deform_kernel.smooth_graph`): `(new_points,
/// last_change)`, the largest coordinate change of the last iteration.
#[pyfunction]
#[pyo3(signature = (points, cells, iterations, lam, mu, inverse_distance, fixed))]
#[allow(clippy::too_many_arguments)]
pub fn smooth_mesh_graph<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    cells: crate::Csr<'py>,
    iterations: usize,
    lam: f64,
    mu: f64,
    inverse_distance: bool,
    fixed: Option<PyReadonlyArray1<'py, u8>>,
) -> PyResult<(Bound<'py, PyAny>, f64)> {
    let g = GraphSettings {
        params: TaubinParams { lambda: lam, mu },
        iterations,
        inverse_distance,
    };
    let cells = crate::cell_list(&cells)?;
    let flat = points.as_slice()?;
    let mask = match &fixed {
        Some(f) => Some(f.as_slice()?),
        None => None,
    };
    macro_rules! go {
        ($d:literal) => {{
            let r = py.detach(|| graph_run::<$d>(flat, &cells, &g, mask));
            let (p, change) = r.map_err(|(c, e)| kernel_error(c, e))?;
            Ok((to_numpy(py, p)?, change))
        }};
    }
    match points.shape()[1] {
        2 => go!(2),
        3 => go!(3),
        d => Err(PyValueError::new_err(format!(
            "points: {d} columns, not 2 or 3"
        ))),
    }
}
