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
            Ok((to_numpy(py, &p)?, it, b, a, m))
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
