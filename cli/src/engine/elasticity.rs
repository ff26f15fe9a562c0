//! `deform move --method elasticity`: SU2_DEF's finite-element linear elasticity through the
//! kernel's `elasticity` module, in `--steps` load increments with re-assembly (SU2's
//! `DEFORM_NONLINEAR_ITER`): the boundary displacement is split into equal parts and the
//! moduli and stiffness are recomputed on the mesh of each step.

use deform_kernel::elasticity::{
    deform_incremental, elastic_amg_scratch_len, elastic_scratch_len, elasticity_graph,
    elasticity_graph_len, ElasticSystem, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::spring::{SolveOptions, SolveReport, SpringSystem};
use deform_kernel::Graph;

use super::{
    cells_view, kernel, points_d, prescribed_displacements, sorted_nodes, AmgStorage, MoveInput,
    MoveResult, MoveSolver,
};
use crate::error::CliError;

/// Runs the elasticity method on `input` (no sliding markers) with `modulus`, Poisson ratio
/// `poisson` and `steps` increments; `--solver amg` preconditions CG with the scalar
/// smoothed-aggregation V-cycle on every displacement component, any other solver with the
/// node blocks.
pub fn run_elasticity(
    input: &MoveInput<'_>,
    modulus: Modulus,
    poisson: f64,
    steps: usize,
) -> Result<MoveResult, CliError> {
    match input.dim {
        2 => run_d::<2>(input, modulus, poisson, steps),
        3 => run_d::<3>(input, modulus, poisson, steps),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

fn run_d<const D: usize>(
    input: &MoveInput<'_>,
    modulus: Modulus,
    poisson: f64,
    steps: usize,
) -> Result<MoveResult, CliError> {
    let n = input.points.len();
    let moved = sorted_nodes(&input.moved);
    if moved.is_empty() {
        return Err(CliError::Invalid("the moved markers have no nodes".into()));
    }
    let mut boundary = moved.clone();
    boundary.extend(sorted_nodes(&input.fixed));
    boundary.sort_unstable();
    boundary.dedup();
    if let Some(&bad) = boundary.iter().find(|&&b| b as usize >= n) {
        return Err(CliError::Invalid(format!(
            "marker node {bad} is not a mesh node"
        )));
    }
    let (disp3, center, _) = prescribed_displacements::<D>(input, &moved)?;
    let disp: Vec<[f64; D]> = points_d::<D>(&disp3);
    let mut fixed = vec![0u8; n];
    for &b in &boundary {
        fixed[b as usize] = 1;
    }
    let cells = cells_view(input.cells, n)?;
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; elasticity_graph_len(&cells)];
    let used =
        elasticity_graph(&cells, &mut offsets, &mut targets).map_err(kernel("elasticity graph"))?;
    targets.truncate(used);
    let graph = Graph::new(&offsets, &targets).map_err(kernel("elasticity graph"))?;
    let pts = points_d::<D>(input.points);
    let wall = if modulus == Modulus::WallDistance {
        let mut d = vec![0.0; n];
        deform_kernel::spring::wall_distances(&pts, &moved, &mut d)
            .map_err(kernel("wall distances"))?;
        Some(d)
    } else {
        None
    };
    let params = Increments {
        modulus,
        wall_distance: wall.as_deref(),
        poisson,
        steps,
    };
    let options = SolveOptions {
        max_iterations: input.max_iter,
        residual_tol: input.tol,
        update_tol: 0.0,
    };
    let mut moduli = vec![0.0; cells.len()];
    let mut diag = vec![[[0.0; D]; D]; n];
    let mut off = vec![[[0.0; D]; D]; used];
    let (mut current, mut step) = (vec![[0.0; D]; n], vec![[0.0; D]; n]);
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut current,
        step: &mut step,
    };
    let mut out = pts.clone();
    let amg = input.solver == MoveSolver::Amg;
    let mut failure = None;
    let solve = |sys: &ElasticSystem<'_, f64, D>, u: &mut [[f64; D]]| {
        let r = if amg {
            solve_amg(sys, &graph, &fixed, u, &options)
        } else {
            let mut scratch = vec![[0.0; D]; elastic_scratch_len(n).unwrap_or(0)];
            sys.solve(u, &options, &mut scratch)
                .map_err(kernel("elasticity solve"))
        };
        r.map_err(|e| {
            failure = Some(e);
            deform_kernel::Error::SingularSystem { iteration: 0 }
        })
    };
    let report = deform_incremental(
        &cells, &graph, &fixed, &params, &mut out, &disp, buffers, solve,
    );
    if let Some(e) = failure {
        return Err(e);
    }
    let report = report.map_err(kernel("elasticity"))?;
    let deformed: Vec<[f64; 3]> = out
        .iter()
        .map(|p| std::array::from_fn(|c| p.get(c).copied().unwrap_or(0.0)))
        .collect();
    let displacement = deformed
        .iter()
        .zip(input.points)
        .map(|(q, p)| [q[0] - p[0], q[1] - p[1], q[2] - p[2]])
        .collect();
    Ok(MoveResult {
        idw_max_bound: None,
        deformed,
        displacement,
        iterations: report.iterations,
        residual: report.residual,
        converged: report.converged,
        moved_nodes: moved.len(),
        fixed_nodes: boundary.len() - moved.len(),
        center,
        sliding_nodes: 0,
        max_slide_offset: 0.0,
    })
}

/// One multigrid-preconditioned solve: the hierarchy of the system's scalar edge weights.
fn solve_amg<const D: usize>(
    sys: &ElasticSystem<'_, f64, D>,
    graph: &Graph<'_>,
    fixed: &[u8],
    u: &mut [[f64; D]],
    options: &SolveOptions<f64>,
) -> Result<SolveReport<f64>, CliError> {
    let n = u.len();
    let mut w = vec![0.0; graph.edge_count()];
    sys.amg_weights(&mut w)
        .map_err(kernel("elasticity multigrid"))?;
    let mut anchor = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let spring = SpringSystem::new(*graph, &w, fixed, &mut anchor)
        .map_err(kernel("elasticity multigrid"))?;
    let mut storage = AmgStorage::default();
    let h = storage.build(&spring)?;
    let len = elastic_amg_scratch_len(n, h.coarse_unknowns()).unwrap_or(0);
    let mut scratch = vec![[0.0; D]; len];
    sys.solve_amg(&spring, &h, u, options, &mut scratch)
        .map_err(kernel("elasticity solve"))
}
