//! `deform move --method elasticity`: SU2_DEF's finite-element linear elasticity through the
//! kernel's `elasticity` module, in `--steps` load increments with re-assembly (SU2's
//! `DEFORM_NONLINEAR_ITER`): the boundary displacement is split into equal parts and the
//! moduli and stiffness are recomputed on the mesh of each step.

use deform_kernel::elasticity::{
    deform_incremental_on, elastic_rigid_amg_scratch_len, elastic_rigid_amg_sliding_scratch_len,
    elastic_scratch_len, elastic_sliding_scratch_len, elasticity_graph, elasticity_graph_len,
    ElasticSystem, IncrementBuffers, IncrementReport, Increments, Modulus,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    AmgHierarchy, AmgOptions, RigidAmg, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::Graph;

use super::{
    cells_view, kernel, move_result, points_d, prescribe, slide_setup, MoveInput, MoveResult,
    MoveSolver, Prescribed, SlideMarker,
};
use crate::error::CliError;
use crate::motion::Motion;

/// Runs the elasticity method on `input` with `modulus`, Poisson ratio `poisson` and `steps`
/// increments; the nodes of the `sliding` markers slide on their planes (as
/// [`run_move_sliding`](super::run_move_sliding) sets them up). `--solver amg` preconditions
/// CG with smoothed aggregation with the rigid-body modes as near-null space, any other
/// solver with the node blocks. `layer`: the nodes within this distance of the moved
/// markers move rigidly with them (the kernel's `rigid_layer`; rigid motions only).
pub fn run_elasticity(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
    modulus: Modulus,
    (poisson, layer): (f64, Option<f64>),
    steps: usize,
) -> Result<MoveResult, CliError> {
    match input.dim {
        2 => run_d::<2>(input, sliding, modulus, (poisson, layer), steps),
        3 => run_d::<3>(input, sliding, modulus, (poisson, layer), steps),
        d => Err(CliError::Invalid(format!("dimension {d} is not 2 or 3"))),
    }
}

fn run_d<const D: usize>(
    input: &MoveInput<'_>,
    sliding: &[SlideMarker<'_>],
    modulus: Modulus,
    (poisson, layer): (f64, Option<f64>),
    steps: usize,
) -> Result<MoveResult, CliError> {
    let n = input.points.len();
    let mut pre = prescribe::<D>(input)?;
    let pts = points_d::<D>(input.points);
    let table = slide_setup(&pts, &mut pre, sliding)?;
    let constraints = match &table {
        Some(t) => {
            Some(Constraints::new(&t.kinds, &t.directions).map_err(kernel("sliding constraints"))?)
        }
        None => None,
    };
    let mut fixed = vec![0u8; n];
    for &b in &pre.boundary {
        fixed[b as usize] = 1;
    }
    let base = fixed.clone();
    if let Some(thickness) = layer {
        with_layer::<D>(&pre, &pts, thickness, &mut fixed)?;
    }
    let cells = cells_view(input.cells, n)?;
    let (offsets, targets) = cell_pair_graph(&cells)?;
    let graph = Graph::new(&offsets, &targets).map_err(kernel("elasticity graph"))?;
    let wall = if modulus == Modulus::WallDistance {
        let mut d = vec![0.0; n];
        deform_kernel::spring::wall_distances(&pts, &pre.moved, &mut d)
            .map_err(kernel("wall distances"))?;
        Some(d)
    } else {
        None
    };
    let run = Run {
        cells: &cells,
        graph: &graph,
        fixed: &fixed,
        constraints: constraints.as_ref(),
        wall: wall.as_deref(),
        modulus,
        poisson,
        options: SolveOptions {
            max_iterations: input.max_iter,
            residual_tol: input.tol,
            update_tol: 0.0,
        },
        amg: input.solver == MoveSolver::Amg,
        layer: layer.map(|t| (t, base.as_slice())),
    };
    let mut out = pts.clone();
    let total = run.motion(input, &pre, &pts, &mut out, steps)?;
    let solved = (total.iterations, total.residual, total.converged, None);
    Ok(move_result(input, &pre, table.as_ref(), &pts, &out, solved))
}

/// The cell-pair graph of the stiffness: offsets and targets.
pub fn cell_pair_graph(cells: &deform_kernel::Cells<'_>) -> Result<(Vec<u32>, Vec<u32>), CliError> {
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
            let now = run.prescribed(&prescribe::<D>(&partial)?, pts)?;
            let step: Vec<[f64; D]> = now
                .iter()
                .zip(&before)
                .map(|(a, b)| std::array::from_fn(|c| a[c] - b[c]))
                .collect();
            total.add(run.increments(out, &step, 1)?);
            // The moved markers (and the rigid layer) exactly on the rotation by s·θ/N (not
            // the sum of the steps).
            for (i, _) in run.fixed.iter().enumerate().filter(|(_, &f)| f != 0) {
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
    constraints: Option<&'r Constraints<'r, f64, D>>,
    wall: Option<&'r [f64]>,
    modulus: Modulus,
    poisson: f64,
    options: SolveOptions<f64>,
    amg: bool,
    /// The rigid layer's thickness (`--rigid-layer`) and the fixed nodes without it.
    layer: Option<(f64, &'r [u8])>,
}

/// The prescribed displacement in `D` coordinates, extended to the rigid layer of
/// `thickness` (whose nodes are marked in `fixed`): each layer node takes the rigid motion of
/// its nearest moved node. Needs a rigid motion (`pre.rigid_q`).
fn with_layer<const D: usize>(
    pre: &Prescribed,
    pts: &[[f64; D]],
    thickness: f64,
    fixed: &mut [u8],
) -> Result<Vec<[f64; D]>, CliError> {
    let mut disp = points_d::<D>(&pre.disp);
    let Some(q) = pre.rigid_q else {
        return Err(CliError::NotAvailable {
            feature: "--rigid-layer with a displacement field",
            needs: "a rigid motion (--rotate or --translate)",
        });
    };
    let rotations = vec![q; pre.moved.len()];
    deform_kernel::elasticity::rigid_layer(
        pts, &pre.moved, &rotations, thickness, fixed, &mut disp,
    )
    .map_err(kernel("rigid layer"))?;
    Ok(disp)
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
    /// The whole motion: a rotation in `steps > 1` is applied along its arc, anything else
    /// in the kernel's equal increments.
    fn motion(
        &self,
        input: &MoveInput<'_>,
        pre: &Prescribed,
        pts: &[[f64; D]],
        out: &mut [[f64; D]],
        steps: usize,
    ) -> Result<Totals, CliError> {
        if let (Motion::Rotate { degrees, axis, .. }, true) = (&input.motion, steps > 1) {
            let arc = Arc {
                input,
                degrees: *degrees,
                axis: *axis,
                center: pre.center,
            };
            return arc.run(self, pts, out, steps);
        }
        let mut total = Totals::default();
        total.add(self.increments(out, &self.prescribed(pre, pts)?, steps)?);
        Ok(total)
    }

    /// `pre`'s displacement in `D` coordinates, extended to the rigid layer when there is one.
    fn prescribed(&self, pre: &Prescribed, pts: &[[f64; D]]) -> Result<Vec<[f64; D]>, CliError> {
        match self.layer {
            Some((t, base)) => with_layer::<D>(pre, pts, t, &mut base.to_vec()),
            None => Ok(points_d::<D>(&pre.disp)),
        }
    }

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
        let solve = |sys: &ElasticSystem<'_, f64, D>, mesh: &[[f64; D]], u: &mut [[f64; D]]| {
            let r = if self.amg {
                solve_amg(sys, self, mesh, u)
            } else {
                solve_block_jacobi(sys, self.constraints, u, &self.options)
            };
            r.map_err(|e| {
                failure = Some(e);
                deform_kernel::Error::SingularSystem { iteration: 0 }
            })
        };
        let report = deform_incremental_on(
            self.cells, self.graph, self.fixed, &params, points, disp, buffers, solve,
        );
        if let Some(e) = failure {
            return Err(e);
        }
        report.map_err(kernel("elasticity"))
    }
}

/// One block-Jacobi-preconditioned solve (projected on the sliding nodes' planes).
fn solve_block_jacobi<const D: usize>(
    sys: &ElasticSystem<'_, f64, D>,
    constraints: Option<&Constraints<'_, f64, D>>,
    u: &mut [[f64; D]],
    options: &SolveOptions<f64>,
) -> Result<SolveReport<f64>, CliError> {
    let n = u.len();
    let r = match constraints {
        Some(c) => {
            let mut scratch = vec![[0.0; D]; elastic_sliding_scratch_len(n).unwrap_or(0)];
            sys.solve_sliding(c, u, options, &mut scratch)
        }
        None => {
            let mut scratch = vec![[0.0; D]; elastic_scratch_len(n).unwrap_or(0)];
            sys.solve(u, options, &mut scratch)
        }
    };
    r.map_err(kernel("elasticity solve"))
}

/// One multigrid-preconditioned solve: smoothed aggregation with the rigid-body modes of
/// `mesh` (the mesh the stiffness was assembled on) as near-null space.
fn solve_amg<const D: usize>(
    sys: &ElasticSystem<'_, f64, D>,
    run: &Run<'_, D>,
    mesh: &[[f64; D]],
    u: &mut [[f64; D]],
) -> Result<SolveReport<f64>, CliError> {
    let n = u.len();
    let err = kernel("elasticity multigrid");
    let w = vec![1.0; run.graph.edge_count()];
    let mut anchor = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let spring = SpringSystem::new(*run.graph, &w, run.fixed, &mut anchor).map_err(&err)?;
    let opts = AmgOptions {
        max_coarse: RIGID_MAX_COARSE,
        ..AmgOptions::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = RigidAmg::setup_len(&spring, D, &opts, &mut work).map_err(&err)?;
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0; sizes.values];
    let h = match run.constraints {
        Some(c) => {
            sys.rigid_amg_sliding(c, &spring, mesh, &opts, &mut work, &mut index, &mut values)
        }
        None => sys.rigid_amg(&spring, mesh, &opts, &mut work, &mut index, &mut values),
    }
    .map_err(&err)?;
    let r = match run.constraints {
        Some(c) => {
            let len = elastic_rigid_amg_sliding_scratch_len(n, sizes.coarse_scalars, D);
            let mut scratch = vec![[0.0; D]; len.unwrap_or(0)];
            sys.solve_rigid_amg_sliding(c, &h, u, &run.options, &mut scratch)
        }
        None => {
            let len = elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, D);
            let mut scratch = vec![[0.0; D]; len.unwrap_or(0)];
            sys.solve_rigid_amg(&h, u, &run.options, &mut scratch)
        }
    };
    r.map_err(kernel("elasticity solve"))
}

/// Coarsest level of the rigid-mode multigrid: at most this many nodes (3 or 6 unknowns
/// each), solved densely.
const RIGID_MAX_COARSE: usize = 64;
