//! `move_points`: one mesh motion (springs, Samareh's quaternion method with spring
//! propagation, or quaternion IDW) through the kernel's public API, in the order `deform move`
//! runs it (cli/src/engine.rs), so the bits are the tool's.

use deform_kernel::quaternion::{BoundaryMotion, RotationSource};
use deform_kernel::spring::{
    AmgHierarchy, AmgOptions, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SolveReport, SpringSystem,
};
use deform_kernel::{Cells, Error, Graph, Quat};
use numpy::prelude::*;
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::{kernel_error, rows, to_numpy, CellArrays};

/// Why a motion failed: a kernel error in a named step, or an input the kernel never saw.
enum Fail {
    Kernel(&'static str, Error),
    Invalid(String),
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Kernel(step, e) => kernel_error(step, e),
            Fail::Invalid(m) => PyValueError::new_err(m),
        }
    }
}

/// `map_err` helper: a kernel error in `step`.
fn step(name: &'static str) -> impl Fn(Error) -> Fail {
    move |e| Fail::Kernel(name, e)
}

/// How the moved nodes move.
#[derive(Clone, Debug)]
enum Motion {
    /// Rigid rotation by `degrees` about `axis` through `center` (`None`: moved nodes' centroid).
    Rotate {
        degrees: f64,
        axis: [f64; 3],
        center: Option<[f64; 3]>,
    },
    /// Rigid translation.
    Translate([f64; 3]),
    /// One displacement row per entry of the caller's `moved` array.
    Field(Vec<f64>),
}

/// Everything a motion needs, owned (the solve runs without the GIL).
struct Job {
    points: Vec<f64>,
    cells: (Vec<u32>, Vec<u32>, Vec<u8>),
    moved: Vec<u32>,
    fixed: Vec<u32>,
    motion: Motion,
    method: String,
    solver: String,
    stiffness: String,
    options: SolveOptions<f64>,
    idw_exponent: f64,
}

/// The prescribed boundary: sorted moved nodes, every boundary node, the displacement of each
/// node (zero off the moved nodes), the rotation centre and the rigid rotation.
struct Prescribed<const D: usize> {
    moved: Vec<u32>,
    boundary: Vec<u32>,
    disp: Vec<[f64; D]>,
    center: Option<[f64; D]>,
    rigid_q: Option<Quat<f64>>,
}

fn sorted(v: &[u32]) -> Vec<u32> {
    let mut v = v.to_vec();
    v.sort_unstable();
    v.dedup();
    v
}

/// A point in 3 coordinates (z = 0 in 2D), as `deform move` holds it.
fn p3<const D: usize>(p: &[f64; D]) -> [f64; 3] {
    core::array::from_fn(|k| p.get(k).copied().unwrap_or(0.0))
}

/// The centroid of the moved nodes, summed in ascending node order as `deform move` does.
fn centroid<const D: usize>(pts: &[[f64; D]], moved: &[u32]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &m in moved {
        let p = p3(&pts[m as usize]);
        for k in 0..3 {
            c[k] += p[k];
        }
    }
    c.map(|x| x / moved.len() as f64)
}

/// What `job`'s motion prescribes on the boundary, checked against the mesh.
fn prescribe<const D: usize>(job: &Job, pts: &[[f64; D]]) -> Result<Prescribed<D>, Fail> {
    let n = pts.len();
    let moved = sorted(&job.moved);
    if moved.is_empty() {
        return Err(Fail::Invalid("moved: no nodes".into()));
    }
    let mut boundary = moved.clone();
    boundary.extend(&job.fixed);
    let boundary = sorted(&boundary);
    if let Some(&bad) = boundary.iter().find(|&&b| b as usize >= n) {
        return Err(Fail::Invalid(format!(
            "boundary node {bad} is not a mesh node"
        )));
    }
    let mut pre = Prescribed {
        disp: vec![[0.0; D]; n],
        center: None,
        rigid_q: None,
        moved,
        boundary,
    };
    match &job.motion {
        Motion::Rotate {
            degrees,
            axis,
            center,
        } => {
            let c = center.unwrap_or_else(|| centroid(pts, &pre.moved));
            let c = if D == 2 { [c[0], c[1], 0.0] } else { c };
            let q = Quat::from_axis_angle(*axis, degrees.to_radians()).map_err(step("rotation"))?;
            for &m in &pre.moved {
                let p = p3(&pts[m as usize]);
                let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
                let d = [c[0] + r[0] - p[0], c[1] + r[1] - p[1], c[2] + r[2] - p[2]];
                pre.disp[m as usize] = core::array::from_fn(|k| d[k]);
            }
            pre.center = Some(core::array::from_fn(|k| c[k]));
            pre.rigid_q = Some(q);
        }
        Motion::Translate(t) => {
            for &m in &pre.moved {
                pre.disp[m as usize] = core::array::from_fn(|k| t[k]);
            }
            pre.rigid_q = Some(Quat::identity());
        }
        Motion::Field(flat) => {
            for (&m, d) in job.moved.iter().zip(flat.chunks_exact(D)) {
                pre.disp[m as usize] = core::array::from_fn(|k| d[k]);
            }
        }
    }
    Ok(pre)
}

/// The one-level method of a solver name (`None` for multigrid).
fn linear_method(name: &str) -> Result<Option<LinearMethod<f64>>, Fail> {
    Ok(Some(match name {
        "amg" => return Ok(None),
        "cg" => LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        "cg-ssor" => LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: 1.5 },
        },
        "gauss-seidel" => LinearMethod::GaussSeidel,
        "jacobi" => LinearMethod::Jacobi,
        other => return Err(Fail::Invalid(format!("solver: unknown solver {other:?}"))),
    }))
}

/// Owned storage of a multigrid hierarchy.
#[derive(Default)]
struct AmgStorage {
    index: Vec<u32>,
    values: Vec<f64>,
}

impl AmgStorage {
    /// Builds the hierarchy of `sys` with the default options (exact sizes, then values).
    fn build<'a>(&'a mut self, sys: &SpringSystem<'_, f64>) -> Result<AmgHierarchy<'a, f64>, Fail> {
        let opts = AmgOptions::default();
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
        let sizes = AmgHierarchy::setup_len(sys, &opts, &mut work).map_err(step("multigrid"))?;
        self.index = vec![0; sizes.index];
        self.values = vec![0.0; sizes.values];
        AmgHierarchy::setup(sys, &opts, &mut work, &mut self.index, &mut self.values)
            .map_err(step("multigrid"))
    }
}

/// Runs `f` with the linear solver named `name` on `sys` (a multigrid hierarchy is built for
/// "amg" and lives for the call).
fn with_solver<R>(
    name: &str,
    sys: &SpringSystem<'_, f64>,
    f: impl FnOnce(LinearSolver<'_, f64>) -> Result<R, Fail>,
) -> Result<R, Fail> {
    match linear_method(name)? {
        Some(m) => f(LinearSolver::Method(m)),
        None => {
            let mut storage = AmgStorage::default();
            let hierarchy = storage.build(sys)?;
            f(LinearSolver::Amg(&hierarchy))
        }
    }
}

/// The mesh in the kernel's terms: points, cells, edge graph, Batina stiffness and the mask
/// of boundary nodes.
struct Mesh<'a, const D: usize> {
    pts: &'a [[f64; D]],
    graph: Graph<'a>,
    k: Vec<f64>,
    fixed: Vec<u8>,
}

/// `(iterations, residual, converged)` of a solve.
type Solved = (usize, f64, bool);

fn report(r: SolveReport<f64>) -> Solved {
    (r.iterations, r.residual, r.converged)
}

/// The stiffness of every directed edge: Batina's `1 / L`, times the mean of the two nodes'
/// `d̄ / d` (distance to the moved nodes `walls`, "wall-distance") or `V̄ / V` (dual volume,
/// "inverse-volume"), as `deform move --stiffness`.
fn stiffness<const D: usize>(
    g: &Graph<'_>,
    cells: &Cells<'_>,
    pts: &[[f64; D]],
    walls: &[u32],
    choice: &str,
) -> Result<Vec<f64>, Fail> {
    use deform_kernel::spring::{
        batina_stiffness, dual_volumes, inverse_volume_factors, scale_stiffness,
        wall_distance_factors, wall_distances,
    };
    let mut k = vec![0.0; g.edge_count()];
    batina_stiffness(g, pts, 1.0, &mut k).map_err(step("stiffness"))?;
    let mut factors = vec![0.0; pts.len()];
    match choice {
        "batina" => return Ok(k),
        "wall-distance" => {
            wall_distances(pts, walls, &mut factors).map_err(step("wall distances"))?;
            wall_distance_factors(&mut factors, 1.0).map_err(step("wall distances"))?;
        }
        "inverse-volume" => {
            let mut measures = vec![0.0; cells.len()];
            dual_volumes(cells, pts, &mut factors, &mut measures).map_err(step("dual volumes"))?;
            inverse_volume_factors(&mut factors, 1.0).map_err(step("dual volumes"))?;
        }
        other => return Err(Fail::Invalid(format!("stiffness: unknown {other:?}"))),
    }
    scale_stiffness(g, &factors, &mut k).map_err(step("stiffness"))?;
    Ok(k)
}

/// Runs `job` in `D` dimensions: the deformed points and the solve's figures.
fn run<const D: usize>(job: &Job) -> Result<(Vec<[f64; D]>, Solved), Fail> {
    let pts = rows::<D>(&job.points);
    let n = pts.len();
    let pre = prescribe(job, &pts)?;
    let (offsets, nodes, kinds) = &job.cells;
    let cells = Cells::new(n, offsets, nodes, kinds).map_err(step("cells"))?;
    let mut g_offsets = vec![0u32; n + 1];
    let mut g_targets = vec![0u32; deform_kernel::graph_from_cells_len(&cells, false)];
    let used = deform_kernel::graph_from_cells(&cells, false, &mut g_offsets, &mut g_targets)
        .map_err(step("graph"))?;
    g_targets.truncate(used);
    let graph = Graph::new(&g_offsets, &g_targets).map_err(step("graph"))?;
    let k = stiffness(&graph, &cells, &pts, &pre.moved, &job.stiffness)?;
    let mut fixed = vec![0u8; n];
    for &b in &pre.boundary {
        fixed[b as usize] = 1;
    }
    let mesh = Mesh {
        pts: &pts,
        graph,
        k,
        fixed,
    };
    let mut out = pts.clone();
    let solved = match job.method.as_str() {
        "spring" => springs(job, &mesh, &pre, &mut out)?,
        "quaternion" | "idw" => quaternion(job, &mesh, &pre, &mut out)?,
        other => return Err(Fail::Invalid(format!("method: unknown method {other:?}"))),
    };
    Ok((out, solved))
}

/// Linear springs on the displacement; `out` = points + displacement.
fn springs<const D: usize>(
    job: &Job,
    mesh: &Mesh<'_, D>,
    pre: &Prescribed<D>,
    out: &mut [[f64; D]],
) -> Result<Solved, Fail> {
    use deform_kernel::spring::solve_linear_with_scratch_len;
    let n = mesh.pts.len();
    let mut sscratch = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let sys = SpringSystem::new(mesh.graph, &mesh.k, &mesh.fixed, &mut sscratch)
        .map_err(step("springs"))?;
    let mut values = pre.disp.clone();
    let r = with_solver(&job.solver, &sys, |solver| {
        let mut scratch = vec![[0.0; D]; solve_linear_with_scratch_len(&solver, n)];
        sys.solve_linear_with(&mut values, solver, &job.options, &mut scratch)
            .map_err(step("linear springs"))
    })?;
    for ((o, p), v) in out.iter_mut().zip(mesh.pts).zip(&values) {
        for k in 0..D {
            o[k] = p[k] + v[k];
        }
    }
    Ok(report(r))
}

/// Samareh's quaternion method (spring propagation) or quaternion IDW, for a rigid motion.
fn quaternion<const D: usize>(
    job: &Job,
    mesh: &Mesh<'_, D>,
    pre: &Prescribed<D>,
    out: &mut [[f64; D]],
) -> Result<Solved, Fail> {
    let Some(q) = pre.rigid_q else {
        return Err(Fail::Invalid(format!(
            "method {:?} needs a rigid motion (rotate or translate) in this version",
            job.method
        )));
    };
    let deformed: Vec<[f64; D]> = (pre.boundary.iter())
        .map(|&b| {
            let (p, d) = (mesh.pts[b as usize], pre.disp[b as usize]);
            core::array::from_fn(|k| p[k] + d[k])
        })
        .collect();
    let per_node: Vec<Quat<f64>> = (pre.boundary.iter())
        .map(|b| match pre.moved.binary_search(b) {
            Ok(_) => q,
            Err(_) => Quat::identity(),
        })
        .collect();
    let motion = BoundaryMotion {
        nodes: &pre.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&per_node),
        origin: pre.center,
    };
    let n = mesh.pts.len();
    let mut tr = vec![[0.0; D]; n];
    let mut rot = vec![Quat::identity(); n];
    if job.method == "idw" {
        use deform_kernel::quaternion::{deform_idw, deform_idw_scratch_len};
        let mut scratch = vec![0.0; deform_idw_scratch_len::<D>(n, pre.boundary.len())];
        let e = job.idw_exponent;
        deform_idw(mesh.pts, &motion, e, &mut tr, &mut rot, &mut scratch, out)
            .map_err(step("quaternion IDW"))?;
        return Ok((0, 0.0, true));
    }
    quaternion_springs(job, mesh, &motion, (&mut tr[..], &mut rot[..]), out)
}

/// The quaternion method with spring propagation.
fn quaternion_springs<const D: usize>(
    job: &Job,
    mesh: &Mesh<'_, D>,
    motion: &BoundaryMotion<'_, f64, D>,
    (tr, rot): (&mut [[f64; D]], &mut [Quat<f64>]),
    out: &mut [[f64; D]],
) -> Result<Solved, Fail> {
    use deform_kernel::quaternion::{
        deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
    };
    let (n, b) = (mesh.pts.len(), motion.nodes.len());
    let mut sscratch = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let sys = SpringSystem::new(mesh.graph, &mesh.k, &mesh.fixed, &mut sscratch)
        .map_err(step("springs"))?;
    let r = with_solver(&job.solver, &sys, |solver| {
        let mut scratch = vec![0.0; deform_spring_scratch_len::<D>(n, b)];
        let mut values = vec![0.0; propagate_spring_with_scratch_len::<D>(&solver, n)];
        let o = &job.options;
        let (sc, v) = (&mut scratch, &mut values);
        deform_spring_with::<f64, D>(mesh.pts, motion, &sys, solver, o, tr, rot, sc, v, out)
            .map_err(step("quaternion springs"))
    })?;
    Ok(report(r.1))
}

/// The motion from the Python arguments.
fn motion_of(
    kind: &str,
    degrees: f64,
    axis: [f64; 3],
    center: Option<[f64; 3]>,
    vector: [f64; 3],
    field: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<Motion> {
    Ok(match kind {
        "rotate" => Motion::Rotate {
            degrees,
            axis,
            center,
        },
        "translate" => Motion::Translate(vector),
        "field" => match field {
            Some(f) => Motion::Field(f.as_slice()?.to_vec()),
            None => return Err(PyValueError::new_err("displacement: missing")),
        },
        other => return Err(PyValueError::new_err(format!("motion: unknown {other:?}"))),
    })
}

/// Moves a mesh (see `deform_kernel.deform`, which checks the arrays and calls this):
/// returns `(new_points, iterations, residual, converged)`.
#[pyfunction]
#[pyo3(signature = (points, offsets, nodes, kinds, moved, fixed, motion, degrees, axis, center,
    vector, field, method, solver, stiffness, tol, max_iter, idw_exponent))]
#[allow(clippy::too_many_arguments)]
pub fn move_points<'py>(
    py: Python<'py>,
    points: PyReadonlyArray2<'py, f64>,
    offsets: PyReadonlyArray1<'py, u32>,
    nodes: PyReadonlyArray1<'py, u32>,
    kinds: PyReadonlyArray1<'py, u8>,
    moved: PyReadonlyArray1<'py, u32>,
    fixed: PyReadonlyArray1<'py, u32>,
    motion: &str,
    degrees: f64,
    axis: [f64; 3],
    center: Option<[f64; 3]>,
    vector: [f64; 3],
    field: Option<PyReadonlyArray2<'py, f64>>,
    method: &str,
    solver: &str,
    stiffness: &str,
    tol: f64,
    max_iter: usize,
    idw_exponent: f64,
) -> PyResult<(Bound<'py, PyAny>, usize, f64, bool)> {
    let dim = points.shape()[1];
    let cells = CellArrays {
        offsets,
        nodes,
        kinds,
    };
    let job = Job {
        points: points.as_slice()?.to_vec(),
        cells: cells.to_vecs()?,
        moved: moved.as_slice()?.to_vec(),
        fixed: fixed.as_slice()?.to_vec(),
        motion: motion_of(motion, degrees, axis, center, vector, field)?,
        method: method.to_string(),
        solver: solver.to_string(),
        stiffness: stiffness.to_string(),
        options: SolveOptions {
            max_iterations: max_iter,
            residual_tol: tol,
            update_tol: 0.0,
        },
        idw_exponent,
    };
    match dim {
        2 => {
            let (out, s) = py.detach(|| run::<2>(&job))?;
            Ok((to_numpy(py, &out)?, s.0, s.1, s.2))
        }
        3 => {
            let (out, s) = py.detach(|| run::<3>(&job))?;
            Ok((to_numpy(py, &out)?, s.0, s.1, s.2))
        }
        d => Err(PyValueError::new_err(format!(
            "points: {d} columns, not 2 or 3"
        ))),
    }
}
