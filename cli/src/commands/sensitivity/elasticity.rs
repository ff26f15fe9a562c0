//! `--method elasticity` of `deform adjoint` and `deform tangent`: the derivative of
//! `deform move --method elasticity` (its --stiffness, --poisson and --steps) with respect to
//! the boundary displacement, through the kernel's `sensitivity::elastic_tangent` /
//! `elastic_adjoint` (one step: linear, one more solve with the deformation's operator) and
//! `elastic_incremental_tangent` / `_adjoint` (`--steps N`: the increments re-assembled on the
//! moved mesh, linearised about the boundary of `--deformed`). Every solve is CG
//! preconditioned by a scalar multigrid V-cycle on the cell-pair graph (projected on the
//! sliding planes with `--slide`: `elastic_sliding_tangent` / `_adjoint`, one step only) (`deform move`'s
//! default solver is another multigrid: the solves agree to the tolerance).

use deform_kernel::elasticity::{
    assemble, cell_moduli, Block, ElasticSystem, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::sensitivity::{
    elastic_adjoint, elastic_adjoint_scratch_len, elastic_incremental_adjoint,
    elastic_incremental_adjoint_scratch_len, elastic_incremental_tangent,
    elastic_incremental_tangent_scratch_len, elastic_sliding_adjoint,
    elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    elastic_sliding_tangent_scratch_len, elastic_tangent, elastic_tangent_scratch_len,
    ElasticPreconditioner, IncrementProblem,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{AmgHierarchy, AmgOptions, SolveOptions, SpringSystem};
use deform_kernel::{Cells, Graph};

use super::options::DEFAULT_POISSON;
use super::quaternion::deformed_points;
use super::{kernel, Report, Slide, Solved};
use crate::args::{SensitivitySetup, StiffnessArg};
use crate::engine::{cell_pair_graph, cells_view, points_d};
use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::su2::Su2Mesh;

/// The mesh side of the problem: cells, cell-pair graph, fixed mask, wall distances, the
/// undeformed points and the boundary displacement of the linearisation point.
struct Mesh<'m, const D: usize> {
    cells: Cells<'m>,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    fixed: Vec<u8>,
    wall: Option<Vec<f64>>,
    points: Vec<[f64; D]>,
    displacement: Vec<[f64; D]>,
}

impl<'m, const D: usize> Mesh<'m, D> {
    fn new(
        setup: &SensitivitySetup,
        mesh: &'m Su2Mesh,
        boundary: &[u32],
    ) -> Result<Self, CliError> {
        let n = mesh.points.len();
        let cells = cells_view(&mesh.elements, n)?;
        let (offsets, targets) = cell_pair_graph(&cells)?;
        let mut fixed = vec![0u8; n];
        for &b in boundary {
            fixed[b as usize] = 1;
        }
        let points = points_d::<D>(&mesh.points);
        let wall = if modulus(setup) == Modulus::WallDistance {
            let moved = marker_nodes(mesh, &setup.wall_markers, &setup.mesh)?;
            let mut d = vec![0.0; n];
            deform_kernel::spring::wall_distances(&points, &moved, &mut d)
                .map_err(kernel("wall distances"))?;
            Some(d)
        } else {
            None
        };
        let at = points_d::<D>(&deformed_points(setup, mesh)?);
        let displacement = (0..n)
            .map(|i| match fixed[i] {
                0 => [0.0; D],
                _ => std::array::from_fn(|c| at[i][c] - points[i][c]),
            })
            .collect();
        Ok(Mesh {
            cells,
            offsets,
            targets,
            fixed,
            wall,
            points,
            displacement,
        })
    }
}

/// `--stiffness` as the kernel's modulus (batina refused by the option checks).
fn modulus(setup: &SensitivitySetup) -> Modulus {
    match setup.stiffness {
        Some(StiffnessArg::WallDistance) => Modulus::WallDistance,
        Some(StiffnessArg::Constant) => Modulus::Constant,
        _ => Modulus::InverseVolume,
    }
}

/// What a derivative needs: the stiffness on the undeformed mesh, its multigrid
/// preconditioner, the increments and the stopping rules.
struct Solver<'a, const D: usize> {
    sys: ElasticSystem<'a, f64, D>,
    pre: ElasticPreconditioner<'a, f64>,
    params: Increments<'a, f64>,
    options: SolveOptions<f64>,
}

/// Runs `f` with the elasticity system of `m` and its multigrid.
fn with_solver<const D: usize, R>(
    setup: &SensitivitySetup,
    m: &Mesh<'_, D>,
    f: impl FnOnce(&Solver<'_, D>, &Graph<'_>) -> Result<R, CliError>,
) -> Result<R, CliError> {
    let n = m.points.len();
    let graph = Graph::new(&m.offsets, &m.targets).map_err(kernel("elasticity graph"))?;
    let params = Increments {
        modulus: modulus(setup),
        wall_distance: m.wall.as_deref(),
        poisson: setup.poisson.unwrap_or(DEFAULT_POISSON),
        steps: setup.steps as usize,
    };
    let mut moduli = vec![0.0; m.cells.len()];
    cell_moduli(
        &m.cells,
        &m.points,
        params.modulus,
        m.wall.as_deref(),
        &mut moduli,
    )
    .map_err(kernel("elastic moduli"))?;
    let mut diag: Vec<Block<f64, D>> = vec![[[0.0; D]; D]; n];
    let mut off: Vec<Block<f64, D>> = vec![[[0.0; D]; D]; graph.edge_count()];
    assemble(
        &m.cells,
        &m.points,
        &graph,
        &moduli,
        params.poisson,
        &mut diag,
        &mut off,
    )
    .map_err(kernel("elastic stiffness"))?;
    let sys = ElasticSystem::new(graph, &diag, &off, &m.fixed).map_err(kernel("elasticity"))?;
    let mut weights = vec![0.0; graph.edge_count()];
    sys.amg_weights(&mut weights).map_err(kernel("multigrid"))?;
    let mut anchor = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let spring =
        SpringSystem::new(graph, &weights, &m.fixed, &mut anchor).map_err(kernel("multigrid"))?;
    let opts = AmgOptions::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = AmgHierarchy::setup_len(&spring, &opts, &mut work).map_err(kernel("multigrid"))?;
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![0.0; sizes.values]);
    let h = AmgHierarchy::setup(&spring, &opts, &mut work, &mut index, &mut values)
        .map_err(kernel("multigrid"))?;
    let solver = Solver {
        sys,
        pre: ElasticPreconditioner::Amg(&spring, &h),
        params,
        options: SolveOptions {
            residual_tol: setup.tol,
            max_iterations: setup.max_iter,
            update_tol: 0.0,
        },
    };
    f(&solver, &graph)
}

/// The increments' buffers, owned.
struct Buffers<const D: usize> {
    moduli: Vec<f64>,
    diag: Vec<Block<f64, D>>,
    off: Vec<Block<f64, D>>,
    current: Vec<[f64; D]>,
    step: Vec<[f64; D]>,
}

impl<const D: usize> Buffers<D> {
    fn new(cells: usize, n: usize, edges: usize) -> Self {
        Buffers {
            moduli: vec![0.0; cells],
            diag: vec![[[0.0; D]; D]; n],
            off: vec![[[0.0; D]; D]; edges],
            current: vec![[0.0; D]; n],
            step: vec![[0.0; D]; n],
        }
    }

    fn view(&mut self) -> IncrementBuffers<'_, f64, D> {
        IncrementBuffers {
            moduli: &mut self.moduli,
            diag: &mut self.diag,
            off: &mut self.off,
            current: &mut self.current,
            step: &mut self.step,
        }
    }
}

/// The incremental problem of `s` on `m`, and buffers for it.
fn problem<'a, const D: usize>(
    s: &'a Solver<'a, D>,
    m: &'a Mesh<'a, D>,
    graph: &'a Graph<'a>,
) -> (IncrementProblem<'a, f64, D>, Buffers<D>) {
    let p = IncrementProblem {
        cells: &m.cells,
        graph,
        fixed: &m.fixed,
        params: &s.params,
        points: &m.points,
        displacement: &m.displacement,
        pre: s.pre,
        options: s.options,
    };
    let b = Buffers::new(m.cells.len(), m.points.len(), graph.edge_count());
    (p, b)
}

/// A solve (or every increment's) that did not converge is an error.
fn converged(iterations: usize, residual: f64, ok: bool) -> Result<Report, CliError> {
    if ok {
        Ok(Report {
            iterations,
            residual,
        })
    } else {
        Err(CliError::Unconverged(format!(
            "the elasticity solves stopped after {iterations} iterations at relative residual \
             {residual:e}"
        )))
    }
}

/// `J v` (`dx` holds `v` at the boundary, zero elsewhere).
pub(super) fn tangent<const D: usize>(
    setup: &SensitivitySetup,
    (mesh, boundary, table): (&Su2Mesh, &[u32], Option<&Slide>),
    mut dx: Vec<[f64; D]>,
) -> Result<Solved<D>, CliError> {
    let m = Mesh::<D>::new(setup, mesh, boundary)?;
    let n = dx.len();
    with_solver(setup, &m, |s, graph| {
        let r = if let Some(t) = table {
            let dirs = t.directions::<D>();
            let c = Constraints::new(&t.kinds, &dirs).map_err(kernel("sliding"))?;
            let mut scratch = vec![[0.0; D]; elastic_sliding_tangent_scratch_len(&s.pre, n)];
            let r = elastic_sliding_tangent(&s.sys, &c, s.pre, &s.options, &mut dx, &mut scratch)
                .map_err(kernel("elasticity tangent"))?;
            converged(r.iterations, r.residual, r.converged)?
        } else if s.params.steps == 1 {
            let mut scratch = vec![[0.0; D]; elastic_tangent_scratch_len(&s.pre, n)];
            let r = elastic_tangent(&s.sys, s.pre, &s.options, &mut dx, &mut scratch)
                .map_err(kernel("elasticity tangent"))?;
            converged(r.iterations, r.residual, r.converged)?
        } else {
            let (p, mut b) = problem(s, &m, graph);
            let len = elastic_incremental_tangent_scratch_len(&s.pre, n);
            let mut scratch = vec![[0.0; D]; len];
            let r = elastic_incremental_tangent(&p, &mut dx, b.view(), &mut scratch)
                .map_err(kernel("elasticity tangent"))?;
            converged(r.iterations, r.residual, r.converged)?
        };
        Ok((dx, Some(r)))
    })
}

/// `Jᵀ w` (zero off the boundary).
pub(super) fn adjoint<const D: usize>(
    setup: &SensitivitySetup,
    (mesh, boundary, table): (&Su2Mesh, &[u32], Option<&Slide>),
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let m = Mesh::<D>::new(setup, mesh, boundary)?;
    let n = w.len();
    let mut g = vec![[0.0; D]; n];
    with_solver(setup, &m, |s, graph| {
        let r = if let Some(t) = table {
            let dirs = t.directions::<D>();
            let c = Constraints::new(&t.kinds, &dirs).map_err(kernel("sliding"))?;
            let len = elastic_sliding_adjoint_scratch_len(&s.pre, n);
            let mut scratch = vec![[0.0; D]; len];
            let r = elastic_sliding_adjoint(&s.sys, &c, s.pre, &s.options, w, &mut g, &mut scratch)
                .map_err(kernel("elasticity adjoint"))?;
            converged(r.iterations, r.residual, r.converged)?
        } else if s.params.steps == 1 {
            let mut scratch = vec![[0.0; D]; elastic_adjoint_scratch_len(&s.pre, n)];
            let r = elastic_adjoint(&s.sys, s.pre, &s.options, w, &mut g, &mut scratch)
                .map_err(kernel("elasticity adjoint"))?;
            converged(r.iterations, r.residual, r.converged)?
        } else {
            let (p, mut b) = problem(s, &m, graph);
            let len = elastic_incremental_adjoint_scratch_len(&s.pre, n, s.params.steps);
            let mut scratch = vec![[0.0; D]; len];
            let r = elastic_incremental_adjoint(&p, w, &mut g, b.view(), &mut scratch)
                .map_err(kernel("elasticity adjoint"))?;
            converged(r.iterations, r.residual, r.converged)?
        };
        Ok((g, Some(r)))
    })
}
