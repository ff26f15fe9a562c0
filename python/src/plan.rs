//! `NativePlan`: a kernel [`Plan`] whose three pools are owned by the Python object
//! (`deform_kernel.Plan` checks the arguments and wraps it). Validation, stiffness and the
//! multigrid hierarchy are done once; each step reopens the pools (a header and checksum
//! check) and solves from the previous solution.

use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanOrder, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::quaternion::RotationSource;
use deform_kernel::spring::{AmgOptions, LinearMethod, Preconditioner, SolveOptions};
use deform_kernel::{Cells, Error, Graph, Quat};
use numpy::prelude::*;
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::{cell_list, kernel_error, rows, to_numpy, Csr};

/// A kernel error with the step that raised it.
type Failed = (&'static str, Error);

fn at(step: &'static str) -> impl Fn(Error) -> Failed {
    move |e| (step, e)
}

/// The plan's solver of a solver name.
fn plan_solver(name: &str) -> PyResult<PlanSolver<f64>> {
    let m = match name {
        "amg" => return Ok(PlanSolver::Amg(AmgOptions::default())),
        "cg" => LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        "cg-ssor" => LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: 1.5 },
        },
        "gauss-seidel" => LinearMethod::GaussSeidel,
        "jacobi" => LinearMethod::Jacobi,
        s => return Err(PyValueError::new_err(format!("solver: unknown {s:?}"))),
    };
    Ok(PlanSolver::Method(m))
}

/// What a plan is built from (owned: the build runs without the GIL).
struct Build {
    points: Vec<f64>,
    cells: deform_cli::formats::CellList,
    boundary: Vec<u32>,
    method: PlanMethod,
    solver: PlanSolver<f64>,
    options: SolveOptions<f64>,
    renumber: PlanOrder,
}

/// The three pools.
type Pools = (Vec<f64>, Vec<u32>, Vec<u8>);

/// Builds the plan in new pools of exactly the sizes it needs.
fn build<const D: usize>(b: &Build) -> Result<Pools, Failed> {
    let pts = rows::<D>(&b.points);
    let n = pts.len();
    let c = &b.cells;
    let cells = Cells::new(n, &c.offsets, &c.nodes, &c.kinds).map_err(at("cells"))?;
    let (offsets, targets) = crate::edge_graph(&cells).map_err(at("graph"))?;
    let graph = Graph::new(&offsets, &targets).map_err(at("graph"))?;
    let spec = PlanSpec {
        points: &pts,
        graph,
        boundary: &b.boundary,
        elements: None,
        constraints: None,
        method: b.method,
        stiffness: PlanStiffness::Batina { exponent: 1.0 },
        solver: b.solver,
        options: b.options,
        renumber: b.renumber,
    };
    let ws = Plan::work_sizes(&spec).map_err(at("plan"))?;
    let (mut wr, mut wi, mut wb) = (
        vec![0.0; ws.reals],
        vec![0u32; ws.indices],
        vec![0u8; ws.bytes],
    );
    let mut work = PlanWork {
        reals: &mut wr,
        indices: &mut wi,
        bytes: &mut wb,
    };
    let s = Plan::sizes(&spec, &mut work).map_err(at("plan"))?;
    let (mut r, mut i, mut by) = (
        vec![0.0; s.reals],
        vec![0u32; s.indices],
        vec![0u8; s.bytes],
    );
    Plan::init(&spec, &mut work, &mut r, &mut i, &mut by).map_err(at("plan"))?;
    Ok((r, i, by))
}

/// One step's input, owned or borrowed.
struct StepIn<'a> {
    deformed: &'a [f64],
    rotations: Option<&'a [f64]>,
    origin: Option<[f64; 3]>,
    cold: bool,
}

/// `(iterations, residual, converged, warm, extrapolated, step)` of a plan step.
type Stepped = (usize, f64, bool, bool, bool, u64);

fn step<const D: usize>(
    pools: &mut Pools,
    s: &StepIn<'_>,
) -> Result<(Vec<[f64; D]>, Stepped), Failed> {
    let (r, i, b) = pools;
    let mut plan = Plan::<f64, D>::open(r, i, b).map_err(at("plan"))?;
    let deformed = rows::<D>(s.deformed);
    let quats: Vec<Quat<f64>> = (s.rotations.unwrap_or(&[]).chunks_exact(4))
        .map(|q| Quat::new(q[0], q[1], q[2], q[3]))
        .collect();
    let motion = PlanMotion {
        deformed: &deformed,
        rotations: match s.rotations {
            Some(_) => RotationSource::PerNode(&quats),
            None => RotationSource::Shape,
        },
        origin: s.origin.map(|o| core::array::from_fn(|k| o[k])),
        start: if s.cold { Start::Cold } else { Start::Warm },
    };
    let mut out = vec![[0.0; D]; plan.node_count()];
    let rep = plan.step(&motion, &mut out).map_err(at("plan step"))?;
    let sv = rep.solve;
    Ok((
        out,
        (
            sv.iterations,
            sv.residual,
            sv.converged,
            rep.warm,
            rep.extrapolated,
            rep.step,
        ),
    ))
}

/// A deformation plan that owns its pools (see `deform_kernel.Plan`).
#[pyclass(module = "deform_kernel._native")]
pub struct NativePlan {
    dim: usize,
    pools: Pools,
}

#[pymethods]
impl NativePlan {
    /// Validates the mesh and builds the plan (stiffness, hierarchy) with the GIL released.
    #[new]
    #[pyo3(signature = (points, cells, boundary, method, solver, tol, max_iter, renumber))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        points: PyReadonlyArray2<'_, f64>,
        cells: Csr<'_>,
        boundary: PyReadonlyArray1<'_, u32>,
        method: &str,
        solver: &str,
        tol: f64,
        max_iter: usize,
        renumber: &str,
    ) -> PyResult<Self> {
        let dim = points.shape()[1];
        let b = Build {
            points: points.as_slice()?.to_vec(),
            cells: cell_list(&cells)?,
            boundary: boundary.as_slice()?.to_vec(),
            method: match method {
                "spring" => PlanMethod::Spring,
                "quaternion" => PlanMethod::QuaternionSpring,
                m => return Err(PyValueError::new_err(format!("method: unknown {m:?}"))),
            },
            solver: plan_solver(solver)?,
            options: SolveOptions {
                max_iterations: max_iter,
                residual_tol: tol,
                update_tol: 0.0,
            },
            renumber: match renumber {
                "off" => PlanOrder::AsGiven,
                "rcm" => PlanOrder::Rcm,
                "hilbert" => PlanOrder::Hilbert,
                r => return Err(PyValueError::new_err(format!("renumber: unknown {r:?}"))),
            },
        };
        let pools = match dim {
            2 => py.detach(|| build::<2>(&b)),
            3 => py.detach(|| build::<3>(&b)),
            d => return Err(PyValueError::new_err(format!("points: {d} columns"))),
        };
        let pools = pools.map_err(|(c, e)| kernel_error(c, e))?;
        Ok(NativePlan { dim, pools })
    }

    /// One step: `deformed` `(B, dim)` boundary positions, `rotations` `(B, 4)` quaternions
    /// `(w, x, y, z)` (quaternion plans), `origin`, `cold`; the result goes into `out` (and
    /// `None` comes back) or a new array. Returns `(points, iterations, residual, converged,
    /// warm, extrapolated, step)`. On error nothing is written and the plan is unchanged.
    #[pyo3(signature = (deformed, rotations, origin, cold, out))]
    #[allow(clippy::type_complexity)]
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        deformed: PyReadonlyArray2<'py, f64>,
        rotations: Option<PyReadonlyArray2<'py, f64>>,
        origin: Option<[f64; 3]>,
        cold: bool,
        out: Option<PyReadwriteArray2<'py, f64>>,
    ) -> PyResult<(Option<Bound<'py, PyAny>>, usize, f64, bool, bool, bool, u64)> {
        let s = StepIn {
            deformed: deformed.as_slice()?,
            rotations: match &rotations {
                Some(r) => Some(r.as_slice()?),
                None => None,
            },
            origin,
            cold,
        };
        let pools = &mut self.pools;
        macro_rules! go {
            ($d:literal) => {{
                let (pts, r) = py
                    .detach(|| step::<$d>(pools, &s))
                    .map_err(|(c, e)| kernel_error(c, e))?;
                let res = match out {
                    Some(mut o) => {
                        o.as_slice_mut()?.copy_from_slice(pts.as_flattened());
                        None
                    }
                    None => Some(to_numpy(py, pts)?),
                };
                Ok((res, r.0, r.1, r.2, r.3, r.4, r.5))
            }};
        }
        match self.dim {
            2 => go!(2),
            _ => go!(3),
        }
    }

    /// `(reals, indices, bytes)`: the lengths of the pools this plan owns.
    fn pool_sizes(&self) -> (usize, usize, usize) {
        (self.pools.0.len(), self.pools.1.len(), self.pools.2.len())
    }
}
