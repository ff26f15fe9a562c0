//! `deform adjoint` and `deform tangent`: the derivative of the linear deformations (Batina
//! springs, inverse-distance weighting) with respect to the boundary motion, through the
//! kernel's `sensitivity` module, of the angle springs (`angle.rs`), RBF (`rbf.rs`) and
//! linear elasticity (`elasticity.rs`, also in load increments), and of the quaternion method
//! with spring (`quaternion.rs`) or IDW (`idw.rs`) propagation linearised about a deformed
//! boundary; see docs/sensitivities.md.
//!
//! `adjoint` is SU2_DOT's first step: the volume sensitivity `dJ/dx` of a flow adjoint becomes
//! `dJ/dx_b` at the boundary nodes (one adjoint solve with the deformation's own operator and
//! multigrid hierarchy). `tangent` is the forward direction for one boundary perturbation.

mod angle;
mod design;
mod elasticity;
mod grid;
mod idw;
mod options;
mod quaternion;
mod rbf;
mod read;
mod slide;

use std::io::Write as _;
use std::path::Path;

use deform_kernel::sensitivity::{
    idw_adjoint, idw_tangent, spring_adjoint, spring_adjoint_scratch_len, spring_sliding_adjoint,
    spring_sliding_adjoint_scratch_len, spring_sliding_tangent, spring_tangent,
};
use deform_kernel::spring::constraints::Constraints;
use deform_kernel::spring::{
    batina_stiffness, solve_linear_sliding_scratch_len, solve_linear_with_scratch_len,
    AmgHierarchy, AmgOptions, LinearSolver, SolveOptions, SolveReport, SpringSystem,
};
use serde_json::json;

use crate::args::{AdjointArgs, SensitivityMethod, SensitivitySetup, TangentArgs};
use crate::engine::{cells_view, edge_graph, points_d};
use crate::error::CliError;
use crate::files::{input_kind, io_err, marker_nodes, read_bytes, read_su2, FileKind};
use crate::formats::su2::Su2Mesh;
use crate::output::Staged;
use crate::report::Outcome;
use read::{parse_perturbation, parse_sensitivity};
use slide::Slide;

fn kernel(context: &str) -> impl Fn(deform_kernel::Error) -> CliError + '_ {
    move |source| CliError::Kernel {
        context: context.to_string(),
        source,
    }
}

/// The mesh, its boundary nodes (every marker's but the sliding ones') and the sliding
/// markers' constraint table, after the option checks.
fn load(setup: &SensitivitySetup) -> Result<(Su2Mesh, Vec<u32>, Option<Slide>), CliError> {
    if !(setup.tol.is_finite() && setup.tol > 0.0) {
        return Err(CliError::Invalid(
            "--tol must be finite and positive".into(),
        ));
    }
    options::check(setup)?;
    slide::check(setup)?;
    crate::args::check_rbf_args(&setup.rbf, setup.method() == SensitivityMethod::Rbf)?;
    let mesh = read_su2(&setup.mesh)?;
    let (boundary, table) = slide::boundary(setup, &mesh)?;
    if boundary.is_empty() {
        return Err(CliError::Invalid(format!(
            "{}: no marker nodes: the deformation has no boundary to differentiate by",
            setup.mesh.display()
        )));
    }
    Ok((mesh, boundary, table))
}

/// Runs `f` with the spring system, its multigrid hierarchy and the stopping rules of `setup`.
fn with_springs<const D: usize, R>(
    setup: &SensitivitySetup,
    mesh: &Su2Mesh,
    boundary: &[u32],
    f: impl FnOnce(
        &SpringSystem<'_, f64>,
        LinearSolver<'_, f64>,
        &SolveOptions<f64>,
    ) -> Result<R, CliError>,
) -> Result<R, CliError> {
    let n = mesh.points.len();
    let cells = cells_view(&mesh.elements, n)?;
    // The angle springs run on the graph with face diagonals, as `deform move` builds it.
    let graph = edge_graph(&cells, setup.method() == SensitivityMethod::Angle)?;
    let g = graph.view()?;
    let points = points_d::<D>(&mesh.points);
    let mut k = vec![0.0; graph.targets.len()];
    batina_stiffness(&g, &points, 1.0, &mut k).map_err(kernel("stiffness"))?;
    let mut fixed = vec![0u8; n];
    for &b in boundary {
        fixed[b as usize] = 1;
    }
    let mut anchor = vec![0u32; SpringSystem::<f64>::scratch_len(n)];
    let sys = SpringSystem::new(g, &k, &fixed, &mut anchor).map_err(kernel("spring system"))?;
    let opts = AmgOptions {
        strength_theta: setup
            .amg_strength
            .unwrap_or_else(crate::engine::default_amg_strength),
        ..AmgOptions::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).map_err(kernel("multigrid"))?;
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![0.0; sizes.values]);
    let h = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values)
        .map_err(kernel("multigrid"))?;
    let stop = SolveOptions {
        residual_tol: setup.tol,
        max_iterations: setup.max_iter,
        ..SolveOptions::default()
    };
    f(&sys, LinearSolver::Amg(&h), &stop)
}

/// What the solves did (for the report).
#[derive(Clone, Copy, Debug)]
struct Report {
    iterations: usize,
    residual: f64,
}

/// A solve that did not converge is an error (nothing written).
fn converged(r: SolveReport<f64>) -> Result<Report, CliError> {
    if r.converged {
        Ok(Report {
            iterations: r.iterations,
            residual: r.residual,
        })
    } else {
        Err(CliError::Unconverged(format!(
            "the spring solve stopped after {} iterations at relative residual {:e}",
            r.iterations, r.residual
        )))
    }
}

/// A field and the solves' report (none for IDW).
type Solved<const D: usize> = (Vec<[f64; D]>, Option<Report>);

/// `Jᵀ w` for `D` components; the spring solve's report when there is one.
fn adjoint_d<const D: usize>(
    setup: &SensitivitySetup,
    (mesh, boundary, table): (&Su2Mesh, &[u32], Option<&Slide>),
    w: &[[f64; D]],
) -> Result<Solved<D>, CliError> {
    let n = w.len();
    let mut g = vec![[0.0; D]; n];
    match setup.method() {
        SensitivityMethod::IdwDisplacements => {
            let points = points_d::<D>(&mesh.points);
            idw_adjoint(&points, boundary, setup.idw_exponent, w, &mut g)
                .map_err(kernel("IDW adjoint"))?;
            Ok((g, None))
        }
        SensitivityMethod::Quaternion => quaternion::adjoint(setup, mesh, boundary, w),
        SensitivityMethod::Idw => idw::adjoint(setup, mesh, boundary, w),
        SensitivityMethod::Elasticity => elasticity::adjoint(setup, (mesh, boundary, table), w),
        SensitivityMethod::Angle => angle::adjoint(setup, mesh, boundary, w),
        SensitivityMethod::Rbf => rbf::adjoint(setup, mesh, boundary, w),
        SensitivityMethod::Tfi | SensitivityMethod::TfiDisplacement => Err(options::tfi_on_su2()),
        SensitivityMethod::Spring => {
            with_springs::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
                let r = match table {
                    Some(t) => {
                        let dirs = t.directions::<D>();
                        let c = Constraints::new(&t.kinds, &dirs).map_err(kernel("sliding"))?;
                        let len = spring_sliding_adjoint_scratch_len::<f64, D>(&solver, n);
                        let mut s = vec![[0.0; D]; len];
                        spring_sliding_adjoint(sys, &c, solver, stop, w, &mut g, &mut s)
                    }
                    None => {
                        let len = spring_adjoint_scratch_len::<f64, D>(&solver, n);
                        let mut s = vec![[0.0; D]; len];
                        spring_adjoint(sys, solver, stop, w, &mut g, &mut s)
                    }
                }
                .map_err(kernel("spring adjoint"))?;
                Ok((g, Some(converged(r)?)))
            })
        }
    }
}

/// `J v` for `D` components (`dx` holds `v` at the boundary on entry).
fn tangent_d<const D: usize>(
    setup: &SensitivitySetup,
    (mesh, boundary, table): (&Su2Mesh, &[u32], Option<&Slide>),
    mut dx: Vec<[f64; D]>,
) -> Result<Solved<D>, CliError> {
    match setup.method() {
        SensitivityMethod::IdwDisplacements => {
            let points = points_d::<D>(&mesh.points);
            idw_tangent(&points, boundary, setup.idw_exponent, &mut dx)
                .map_err(kernel("IDW tangent"))?;
            Ok((dx, None))
        }
        SensitivityMethod::Quaternion => quaternion::tangent(setup, mesh, boundary, &dx),
        SensitivityMethod::Idw => idw::tangent(setup, mesh, boundary, &dx),
        SensitivityMethod::Elasticity => elasticity::tangent(setup, (mesh, boundary, table), dx),
        SensitivityMethod::Angle => angle::tangent(setup, mesh, boundary, dx),
        SensitivityMethod::Rbf => rbf::tangent(setup, mesh, boundary, &dx),
        SensitivityMethod::Tfi | SensitivityMethod::TfiDisplacement => Err(options::tfi_on_su2()),
        SensitivityMethod::Spring => {
            with_springs::<D, _>(setup, mesh, boundary, |sys, solver, stop| {
                let r = match table {
                    Some(t) => {
                        let dirs = t.directions::<D>();
                        let c = Constraints::new(&t.kinds, &dirs).map_err(kernel("sliding"))?;
                        let len = solve_linear_sliding_scratch_len(&solver, dx.len());
                        let mut s = vec![[0.0; D]; len];
                        spring_sliding_tangent(sys, &c, solver, stop, &mut dx, &mut s)
                    }
                    None => {
                        let len = solve_linear_with_scratch_len(&solver, dx.len());
                        let mut s = vec![[0.0; D]; len];
                        spring_tangent(sys, solver, stop, &mut dx, &mut s)
                    }
                }
                .map_err(kernel("spring tangent"))?;
                Ok((dx, Some(converged(r)?)))
            })
        }
    }
}

/// One value per boundary node (in `boundary` order) spread to `n` nodes, zero elsewhere.
fn scatter<const D: usize>(boundary: &[u32], back: &[[f64; D]], n: usize) -> Vec<[f64; D]> {
    let mut g = vec![[0.0; D]; n];
    for (&b, x) in boundary.iter().zip(back) {
        g[b as usize] = *x;
    }
    g
}

/// `[f64; 3]` rows as `[f64; D]` and back.
fn to_d<const D: usize>(v: &[[f64; 3]]) -> Vec<[f64; D]> {
    points_d::<D>(v)
}
fn to_3<const D: usize>(v: &[[f64; D]]) -> Vec<[f64; 3]> {
    v.iter()
        .map(|x| std::array::from_fn(|c| x.get(c).copied().unwrap_or(0.0)))
        .collect()
}

/// Writes `rows` (node and values) as CSV with `header` through a staged file.
fn write_csv(
    staged: &mut Staged,
    path: &Path,
    header: &str,
    rows: &[(u32, Vec<f64>)],
) -> Result<(), CliError> {
    staged
        .write(path, |f| {
            let mut w = std::io::BufWriter::new(f);
            writeln!(w, "{header}")?;
            for (node, vals) in rows {
                write!(w, "{node}")?;
                for v in vals {
                    write!(w, ",{v:e}")?;
                }
                writeln!(w)?;
            }
            w.flush()
        })
        .map_err(io_err(path))
}

/// The JSON and text report of a run.
fn outcome(
    command: &str,
    a: &SensitivitySetup,
    rows: usize,
    r: Option<Report>,
    out: &Path,
) -> Outcome {
    let json = json!({
        "command": command,
        "mesh": a.mesh.display().to_string(),
        "method": crate::report::value_name(&a.method()),
        "rows": rows,
        "iterations": r.map(|r| r.iterations),
        "residual": r.map(|r| r.residual),
        "out": out.display().to_string(),
    });
    let solve = r.map_or(String::new(), |r| {
        format!(
            " ({} iterations, residual {:.2e})",
            r.iterations, r.residual
        )
    });
    let text = format!("{command}: wrote {rows} rows to {}{solve}\n", out.display());
    Outcome { json, text }
}

/// `deform adjoint`.
pub(crate) fn adjoint(a: &AdjointArgs) -> Result<Outcome, CliError> {
    if input_kind(&a.setup.mesh)? != FileKind::Su2 {
        slide::not_on_grid(&a.setup)?;
        return grid::adjoint(a);
    }
    let setup = design::with_symmetry_planes(a)?;
    let (mesh, boundary, table) = load(&setup)?;
    let n = mesh.points.len();
    let text = String::from_utf8_lossy(&read_bytes(&a.sensitivity)?).into_owned();
    let w = parse_sensitivity(&text, n, mesh.dim, &a.sensitivity)?;
    let problem = (&mesh, &boundary[..], table.as_ref());
    let (g, report) = if mesh.dim == 2 {
        let (g, r) = adjoint_d::<2>(&setup, problem, &to_d::<2>(&w))?;
        (to_3(&g), r)
    } else {
        let (g, r) = adjoint_d::<3>(&setup, problem, &to_d::<3>(&w))?;
        (g, r)
    };
    let nodes = if a.markers.is_empty() {
        boundary
    } else {
        marker_nodes(&mesh, &a.markers, &a.setup.mesh)?
    };
    let d = mesh.dim;
    let rows: Vec<(u32, Vec<f64>)> = nodes
        .iter()
        .map(|&i| {
            let (p, s) = (mesh.points[i as usize], g[i as usize]);
            (i, p[..d].iter().chain(&s[..d]).copied().collect())
        })
        .collect();
    let header = if d == 2 {
        "node,x,y,dJ/dx,dJ/dy"
    } else {
        "node,x,y,z,dJ/dx,dJ/dy,dJ/dz"
    };
    let gradient = design::gradient(a, &mesh, &g)?;
    let mut staged = Staged::new();
    write_csv(&mut staged, &a.out, header, &rows)?;
    if let (Some((text, _)), Some(path)) = (&gradient, &a.grad_out) {
        staged
            .write(path, |f| f.write_all(text.as_bytes()))
            .map_err(io_err(path))?;
    }
    staged.commit().map_err(io_err(&a.out))?;
    let mut o = outcome("adjoint", &a.setup, rows.len(), report, &a.out);
    if let Some((_, values)) = gradient {
        o.json["gradient"] = json!(values);
    }
    Ok(o)
}

/// `deform tangent`.
pub(crate) fn tangent(a: &TangentArgs) -> Result<Outcome, CliError> {
    if input_kind(&a.setup.mesh)? != FileKind::Su2 {
        slide::not_on_grid(&a.setup)?;
        return grid::tangent(a);
    }
    let (mesh, boundary, table) = load(&a.setup)?;
    let n = mesh.points.len();
    let text = String::from_utf8_lossy(&read_bytes(&a.perturbation)?).into_owned();
    let on = (&boundary[..], "on a marker (not a sliding one)");
    let v = parse_perturbation(&text, n, mesh.dim, on, &a.perturbation)?;
    let problem = (&mesh, &boundary[..], table.as_ref());
    let (dx, report) = if mesh.dim == 2 {
        let (dx, r) = tangent_d::<2>(&a.setup, problem, to_d::<2>(&v))?;
        (to_3(&dx), r)
    } else {
        tangent_d::<3>(&a.setup, problem, to_d::<3>(&v))?
    };
    let d = mesh.dim;
    let rows: Vec<(u32, Vec<f64>)> = (0..n).map(|i| (i as u32, dx[i][..d].to_vec())).collect();
    let header = if d == 2 {
        "node,dx,dy"
    } else {
        "node,dx,dy,dz"
    };
    let mut staged = Staged::new();
    write_csv(&mut staged, &a.out, header, &rows)?;
    staged.commit().map_err(io_err(&a.out))?;
    Ok(outcome("tangent", &a.setup, rows.len(), report, &a.out))
}
