//! `move_points`: one mesh motion through the `deform` tool's own engine
//! (`deform_cli::engine::run_move_in_steps` behind `deform move --renumber`, and
//! `run_elasticity`), so every method, `steps`, sliding planes and renumbering give the bits of
//! `deform move` on the same input.

use deform_cli::engine::{
    run_elasticity, Motion, MoveInput, MoveMethod, MoveResult, MoveSolver, RbfFunction,
    RbfSettings, SlideMarker, Stiffness,
};
use deform_cli::error::CliError;
use deform_cli::formats::CellList;
use deform_cli::renumber::{run_move_renumbered, Renumber};
use deform_kernel::elasticity::Modulus;
use numpy::prelude::*;
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::{cell_list, cli_error, Csr, KernelError};

/// The options of a motion (a dict built by `deform_kernel.deform`, checked there).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct Options {
    method: String,
    solver: String,
    stiffness: String,
    tol: f64,
    max_iter: usize,
    idw_exponent: f64,
    steps: usize,
    renumber: String,
    poisson: f64,
    rigid_layer: Option<f64>,
    reach: Option<f64>,
    rbf_kernel: String,
    rbf_radius: Option<f64>,
    rbf_tolerance: f64,
    rbf_max_centres: usize,
    rbf_correction: Option<f64>,
    allow_unconverged: bool,
    allow_folds: bool,
    idw_theta: Option<f64>,
    idw_tolerance: f64,
    amg_strength: Option<f64>,
}

/// A motion's kind and numbers, as `deform_kernel.deform` passes them.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct MotionArgs<'py> {
    kind: String,
    degrees: f64,
    axis: [f64; 3],
    center: Option<[f64; 3]>,
    vector: [f64; 3],
    field: Option<PyReadonlyArray2<'py, f64>>,
}

/// The boundary of a motion: moved and fixed elements (or nodes), and the sliding markers.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct Roles<'py> {
    moved: Csr<'py>,
    fixed: Csr<'py>,
    slide: Vec<Csr<'py>>,
    /// The node of each row of a displacement field (the moved nodes in the caller's order).
    field_nodes: PyReadonlyArray1<'py, u32>,
}

fn invalid(m: impl Into<String>) -> PyErr {
    PyValueError::new_err(m.into())
}

/// The engine's motion (a field's rows by node, ascending, as the tool's reader gives them).
fn motion(m: &MotionArgs<'_>, nodes: &[u32], dim: usize) -> PyResult<Motion> {
    Ok(match m.kind.as_str() {
        "rotate" => Motion::Rotate {
            degrees: m.degrees,
            axis: m.axis,
            center: m.center,
        },
        "translate" => Motion::Translate(m.vector),
        "field" => {
            let f = m
                .field
                .as_ref()
                .ok_or_else(|| invalid("displacement: missing"))?;
            let mut rows: Vec<(u32, [f64; 3])> = (nodes.iter().copied())
                .zip(f.as_slice()?.chunks_exact(dim))
                .map(|(n, d)| {
                    (
                        n,
                        core::array::from_fn(|k| d.get(k).copied().unwrap_or(0.0)),
                    )
                })
                .collect();
            rows.sort_by_key(|r| r.0);
            Motion::Field(rows)
        }
        other => return Err(invalid(format!("motion: unknown {other:?}"))),
    })
}

fn method(o: &Options) -> PyResult<MoveMethod> {
    Ok(match o.method.as_str() {
        "quaternion" => MoveMethod::Quaternion,
        "idw" => MoveMethod::Idw,
        "spring" | "elasticity" => MoveMethod::Spring,
        "angle-direct" => MoveMethod::AngleDirect,
        "angle-cg" => MoveMethod::AngleCg,
        "rbf" => MoveMethod::Rbf(RbfSettings {
            function: match o.rbf_kernel.as_str() {
                "wendland" => RbfFunction::Wendland,
                "tps" => RbfFunction::Tps,
                k => return Err(invalid(format!("rbf_kernel: unknown {k:?}"))),
            },
            radius: o.rbf_radius,
            tolerance: o.rbf_tolerance,
            max_centres: o.rbf_max_centres,
            correction: o.rbf_correction,
        }),
        m => return Err(invalid(format!("method: unknown {m:?}"))),
    })
}

fn solver(name: &str) -> PyResult<MoveSolver> {
    Ok(match name {
        "amg" => MoveSolver::Amg,
        "cg" => MoveSolver::Cg,
        "cg-ssor" => MoveSolver::CgSsor,
        "gauss-seidel" => MoveSolver::GaussSeidel,
        "jacobi" => MoveSolver::Jacobi,
        s => return Err(invalid(format!("solver: unknown {s:?}"))),
    })
}

fn renumber(name: &str) -> PyResult<Renumber> {
    Ok(match name {
        "auto" => Renumber::Auto,
        "off" => Renumber::Off,
        "rcm" => Renumber::Rcm,
        "hilbert" => Renumber::Hilbert,
        r => return Err(invalid(format!("renumber: unknown {r:?}"))),
    })
}

/// The spring stiffness (and the elasticity modulus) of a stiffness name.
fn stiffness(name: &str) -> PyResult<(Stiffness, Modulus)> {
    Ok(match name {
        "batina" => (Stiffness::Batina, Modulus::InverseVolume),
        "wall-distance" => (Stiffness::WallDistance, Modulus::WallDistance),
        "inverse-volume" => (Stiffness::InverseVolume, Modulus::InverseVolume),
        "constant" => (Stiffness::Batina, Modulus::Constant),
        s => return Err(invalid(format!("stiffness: unknown {s:?}"))),
    })
}

/// Everything the engine needs, owned or borrowed from numpy (runs without the GIL).
struct Job<'a> {
    dim: usize,
    points: &'a [[f64; 3]],
    cells: CellList,
    moved: CellList,
    fixed: CellList,
    slide: Vec<CellList>,
    motion: Motion,
    method: MoveMethod,
    solver: MoveSolver,
    stiffness: (Stiffness, Modulus),
    options: &'a Options,
    renumber: Renumber,
}

impl Job<'_> {
    /// Runs the motion as `deform move` does (elasticity: its own increments, no renumbering;
    /// `--renumber auto` leaves IDW alone).
    fn run(&self) -> Result<MoveResult, CliError> {
        let o = self.options;
        let input = MoveInput {
            dim: self.dim,
            points: self.points,
            cells: &self.cells,
            moved: vec![&self.moved],
            fixed: vec![&self.fixed],
            motion: self.motion.clone(),
            method: self.method,
            solver: self.solver,
            amg_strength: o
                .amg_strength
                .unwrap_or_else(deform_cli::engine::default_amg_strength),
            tol: o.tol,
            max_iter: o.max_iter,
            idw_exponent: o.idw_exponent,
            stiffness: self.stiffness.0,
            idw_fast: o.idw_theta.map(|theta| (theta, o.idw_tolerance)),
            reach: o.reach,
            split: None,
            graph: None,
        };
        let names: Vec<String> = (0..self.slide.len())
            .map(|k| format!("slide[{k}]"))
            .collect();
        let sliding: Vec<SlideMarker<'_>> = (names.iter().zip(&self.slide))
            .map(|(name, elements)| SlideMarker { name, elements })
            .collect();
        if o.method == "elasticity" {
            return run_elasticity(
                &input,
                &sliding,
                self.stiffness.1,
                (o.poisson, o.rigid_layer),
                o.steps,
            );
        }
        let how = match (self.method, self.renumber) {
            (MoveMethod::Idw, Renumber::Auto) => Renumber::Off,
            (_, r) => r,
        };
        Ok(run_move_renumbered(&input, &sliding, o.steps, how)?.0)
    }
}

/// The deformed points as `(N, dim)` float64: written into `out` when given (and `None`
/// returned), else a new array (3D: the engine's own buffer, not copied).
fn deformed<'py>(
    py: Python<'py>,
    result: MoveResult,
    dim: usize,
    out: Option<PyReadwriteArray2<'py, f64>>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let n = result.deformed.len();
    if let Some(mut o) = out {
        let dst = o.as_slice_mut()?;
        for (d, p) in dst.chunks_exact_mut(dim).zip(&result.deformed) {
            d.copy_from_slice(&p[..dim]);
        }
        return Ok(None);
    }
    let flat: Vec<f64> = if dim == 3 {
        result.deformed.into_flattened()
    } else {
        result.deformed.iter().flat_map(|p| [p[0], p[1]]).collect()
    };
    Ok(Some(
        PyArray1::from_vec(py, flat).reshape([n, dim])?.into_any(),
    ))
}

/// The tool's failure policy (`deform move` without `--allow-folds`): a result with cells
/// inverted or folded that were valid in the input is an error, and nothing is written.
fn refuse_new_folds(job: &Job<'_>, r: &MoveResult) -> PyResult<()> {
    let q = deform_cli::engine::quality(job.dim, &job.cells, &r.deformed, Some(job.points), None)
        .map_err(cli_error)?;
    let bad = q.new_failures();
    if bad == 0 {
        return Ok(());
    }
    Err(KernelError::new_err(format!(
        "{}: the result has {bad} cell(s) inverted or folded that were valid in the input \
         ({} inverted, {} folded in all); nothing was written (allow_folds=True returns it \
         anyway)",
        job.options.method,
        q.inverted_cells.unwrap_or(0),
        q.folded_cells
    )))
}

/// `(deformed or None, iterations, residual, converged, info)`: `info` holds the sliding
/// nodes, the largest distance of a sliding node from its plane, and the RBF centres used.
type Moved<'py> = (
    Option<Bound<'py, PyAny>>,
    usize,
    f64,
    bool,
    (usize, f64, Option<usize>),
);

/// Moves a mesh (see `deform_kernel.deform`, which checks the arrays and builds the dicts).
/// 3D points are read in place (no copy); `out`, when given, receives the result.
#[pyfunction]
#[pyo3(signature = (points, cells, roles, motion_args, options, out))]
pub fn move_points<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    cells: Csr<'py>,
    roles: Roles<'py>,
    motion_args: MotionArgs<'py>,
    options: Options,
    out: Option<PyReadwriteArray2<'py, f64>>,
) -> PyResult<Moved<'py>> {
    let dim = points.shape()[1];
    if !(dim == 2 || dim == 3) {
        return Err(invalid(format!("points: {dim} columns, not 2 or 3")));
    }
    let flat = points.as_slice()?;
    let padded: Vec<[f64; 3]>;
    let pts: &[[f64; 3]] = if dim == 3 {
        flat.as_chunks::<3>().0
    } else {
        padded = flat.chunks_exact(2).map(|p| [p[0], p[1], 0.0]).collect();
        &padded
    };
    let field_nodes = roles.field_nodes.as_slice()?;
    let job = Job {
        dim,
        points: pts,
        cells: cell_list(&cells)?,
        moved: cell_list(&roles.moved)?,
        fixed: cell_list(&roles.fixed)?,
        slide: roles.slide.iter().map(cell_list).collect::<PyResult<_>>()?,
        motion: motion(&motion_args, field_nodes, dim)?,
        method: method(&options)?,
        solver: solver(&options.solver)?,
        stiffness: stiffness(&options.stiffness)?,
        options: &options,
        renumber: renumber(&options.renumber)?,
    };
    let r = py.detach(|| job.run()).map_err(cli_error)?;
    if !r.converged && !options.allow_unconverged {
        return Err(KernelError::new_err(format!(
            "{}: the solve stopped at relative residual {:.3e} after {} iterations (tol {:e}); \
             raise max_iter or pass allow_unconverged (nothing was written)",
            options.method, r.residual, r.iterations, options.tol
        )));
    }
    if !options.allow_folds {
        refuse_new_folds(&job, &r)?;
    }
    let info = (
        r.sliding_nodes,
        r.max_slide_offset,
        r.rbf.map(|i| i.centres),
    );
    let (it, res, conv) = (r.iterations, r.residual, r.converged);
    Ok((deformed(py, r, dim, out)?, it, res, conv, info))
}
