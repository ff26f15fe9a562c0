//! `deform move --method elasticity`: SU2_DEF's finite-element linear elasticity through the
//! kernel's `elasticity` module, in `--steps` load increments with re-assembly (SU2's
//! `DEFORM_NONLINEAR_ITER`): the boundary displacement is split into equal parts and the
//! moduli and stiffness are recomputed on the mesh of each step.

use deform_kernel::elasticity::{
    deform_incremental, elastic_amg_scratch_len, elastic_scratch_len, elasticity_graph,
    elasticity_graph_len, ElasticSystem, IncrementBuffers, IncrementReport, Increments, Modulus,
};
use deform_kernel::spring::{SolveOptions, SolveReport, SpringSystem};
use deform_kernel::Graph;

use super::{
    cells_view, kernel, points_d, prescribe, AmgStorage, MoveInput, MoveResult, MoveSolver,
    Prescribed,
};
use crate::error::CliError;
use crate::motion::Motion;

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
    let Prescribed {
        moved,
        boundary,
        disp: disp3,
        center,
        ..
    } = prescribe::<D>(input)?;
    let mut fixed = vec![0u8; n];
    for &b in &boundary {
        fixed[b as usize] = 1;
    }
    let cells = cells_view(input.cells, n)?;
    let (offsets, targets) = cell_pair_graph(&cells)?;
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
    let run = Run {
        cells: &cells,
        graph: &graph,
        fixed: &fixed,
        wall: wall.as_deref(),
        modulus,
        poisson,
        options: SolveOptions {
            max_iterations: input.max_iter,
            residual_tol: input.tol,
            update_tol: 0.0,
        },
        amg: input.solver == MoveSolver::Amg,
    };
    let mut out = pts.clone();
    let total = match (&input.motion, steps > 1) {
        (Motion::Rotate { degrees, axis, .. }, true) => {
            let arc = Arc {
                input,
                boundary: &boundary,
                degrees: *degrees,
                axis: *axis,
                center,
            };
            arc.run(&run, &pts, &mut out, steps)?
        }
        _ => {
            let mut total = Totals::default();
            total.add(run.increments(&mut out, &points_d::<D>(&disp3), steps)?);
            total
        }
    };
    Ok(move_result(
        input.points,
        &out,
        &total,
        [moved.len(), boundary.len() - moved.len()],
        center,
    ))
}

/// The tool's result of a run: the moved points in 3D, displacements, solve totals, the
/// moved and fixed node counts and the rotation centre.
fn move_result<const D: usize>(
    points: &[[f64; 3]],
    out: &[[f64; D]],
    total: &Totals,
    [moved, fixed]: [usize; 2],
    center: Option<[f64; 3]>,
) -> MoveResult {
    let deformed: Vec<[f64; 3]> = out
        .iter()
        .map(|p| std::array::from_fn(|c| p.get(c).copied().unwrap_or(0.0)))
        .collect();
    let displacement = deformed
        .iter()
        .zip(points)
        .map(|(q, p)| [q[0] - p[0], q[1] - p[1], q[2] - p[2]])
        .collect();
    MoveResult {
        rbf: None,
        idw_max_bound: None,
        deformed,
        displacement,
        iterations: total.iterations,
        residual: total.residual,
        converged: total.converged,
        moved_nodes: moved,
        fixed_nodes: fixed,
        center,
        sliding_nodes: 0,
        max_slide_offset: 0.0,
    }
}

/// The cell-pair graph of the stiffness: offsets and targets.
fn cell_pair_graph(cells: &deform_kernel::Cells<'_>) -> Result<(Vec<u32>, Vec<u32>), CliError> {
    let mut offsets = vec![0u32; cells.node_count() + 1];
    let mut targets = vec![0u32; elasticity_graph_len(cells)];
    let used =
        elasticity_graph(cells, &mut offsets, &mut targets).map_err(kernel("elasticity graph"))?;
    targets.truncate(used);
    Ok((offsets, targets))
}

/// A rotation applied along its arc: step `s` puts the moved markers at the rotation by
/// `s·θ/N` (a chord split would shrink the body half-way by `cos(θ/2)`), and the interior
/// follows by one solve on the current mesh.
struct Arc<'a, 'i> {
    input: &'a MoveInput<'i>,
    boundary: &'a [u32],
    degrees: f64,
    axis: [f64; 3],
    center: Option<[f64; 3]>,
}

impl Arc<'_, '_> {
    fn run<const D: usize>(
        &self,
        run: &Run<'_, D>,
        pts: &[[f64; D]],
        out: &mut [[f64; D]],
        steps: usize,
    ) -> Result<Totals, CliError> {
        let mut total = Totals::default();
        let mut before = vec![[0.0; D]; pts.len()];
        for s in 1..=steps {
            let partial = MoveInput {
                motion: Motion::Rotate {
                    degrees: self.degrees * s as f64 / steps as f64,
                    axis: self.axis,
                    center: self.center,
                },
                moved: self.input.moved.clone(),
                fixed: self.input.fixed.clone(),
                ..*self.input
            };
            let now = points_d::<D>(&prescribe::<D>(&partial)?.disp);
            let step: Vec<[f64; D]> = now
                .iter()
                .zip(&before)
                .map(|(a, b)| std::array::from_fn(|c| a[c] - b[c]))
                .collect();
            total.add(run.increments(out, &step, 1)?);
            // The moved markers exactly on the rotation by s·θ/N (not the sum of the steps).
            for &b in self.boundary {
                let i = b as usize;
                out[i] = std::array::from_fn(|c| pts[i][c] + now[i][c]);
            }
            before = now;
        }
        Ok(total)
    }
}

/// What every increment needs besides the mesh and the displacement.
struct Run<'r, const D: usize> {
    cells: &'r deform_kernel::Cells<'r>,
    graph: &'r Graph<'r>,
    fixed: &'r [u8],
    wall: Option<&'r [f64]>,
    modulus: Modulus,
    poisson: f64,
    options: SolveOptions<f64>,
    amg: bool,
}

/// Iterations, worst residual and convergence over the increments.
struct Totals {
    iterations: usize,
    residual: f64,
    converged: bool,
}

impl Default for Totals {
    fn default() -> Self {
        Totals {
            iterations: 0,
            residual: 0.0,
            converged: true,
        }
    }
}

impl Totals {
    fn add(&mut self, r: IncrementReport<f64>) {
        self.iterations += r.iterations;
        self.residual = self.residual.max(r.residual);
        self.converged &= r.converged;
    }
}

impl<const D: usize> Run<'_, D> {
    /// The kernel's increments: `points` moved by `disp` (at fixed nodes) in `steps` equal
    /// parts, the stiffness re-assembled on the mesh of each.
    fn increments(
        &self,
        points: &mut [[f64; D]],
        disp: &[[f64; D]],
        steps: usize,
    ) -> Result<IncrementReport<f64>, CliError> {
        let n = points.len();
        let params = Increments {
            modulus: self.modulus,
            wall_distance: self.wall,
            poisson: self.poisson,
            steps,
        };
        let mut moduli = vec![0.0; self.cells.len()];
        let mut diag = vec![[[0.0; D]; D]; n];
        let mut off = vec![[[0.0; D]; D]; self.graph.edge_count()];
        let (mut current, mut step) = (vec![[0.0; D]; n], vec![[0.0; D]; n]);
        let buffers = IncrementBuffers {
            moduli: &mut moduli,
            diag: &mut diag,
            off: &mut off,
            current: &mut current,
            step: &mut step,
        };
        let mut failure = None;
        let solve = |sys: &ElasticSystem<'_, f64, D>, u: &mut [[f64; D]]| {
            let r = if self.amg {
                solve_amg(sys, self.graph, self.fixed, u, &self.options)
            } else {
                let mut scratch = vec![[0.0; D]; elastic_scratch_len(n).unwrap_or(0)];
                sys.solve(u, &self.options, &mut scratch)
                    .map_err(kernel("elasticity solve"))
            };
            r.map_err(|e| {
                failure = Some(e);
                deform_kernel::Error::SingularSystem { iteration: 0 }
            })
        };
        let report = deform_incremental(
            self.cells, self.graph, self.fixed, &params, points, disp, buffers, solve,
        );
        if let Some(e) = failure {
            return Err(e);
        }
        report.map_err(kernel("elasticity"))
    }
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
