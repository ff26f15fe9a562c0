//! `deform move`: an SU2 mesh (marker motions, displacement or surface-position files,
//! propagated by springs, the quaternion method or IDW; this module and its parts) or a
//! Plot3D grid (TFI from a moved wall face: [`grid`]).
//!
//! The SU2 path, in order: [`checks`] (arguments), read the zone, [`motion`] (what moves),
//! the engine's solve, the failure policy, [`outputs`] (staged files), [`report`].

mod checks;
#[cfg(feature = "mpi")]
pub(crate) mod distributed;
mod elasticity;
pub(crate) mod grid;
mod motion;
mod outputs;
mod report;

pub(crate) use elasticity::check_poisson;

use std::time::Instant;

use serde_json::json;

use crate::args::{Method, MoveArgs, Solver, StiffnessArg};
use crate::engine::{
    prepare_reference, MoveInput, MoveMethod, MoveResult, MoveSolver, PreparedReference,
    QualitySummary, SlideMarker, Stiffness,
};
use crate::error::CliError;
use crate::files::{input_kind, marker_nodes, marker_union, read_su2_zone, FileKind, ZonedSu2};
use crate::formats::su2::Su2Mesh;
use crate::formats::CellList;
use crate::report::{value_name, volume_words, Outcome};
use crate::split::Splitter;

/// `deform move`: Plot3D grids go to [`grid::move_grid`] (TFI by default), SU2 meshes through
/// the steps listed in the module's documentation.
pub(crate) fn move_mesh(
    a: &MoveArgs,
    quiet: bool,
    split: Option<&dyn Splitter>,
) -> Result<Outcome, CliError> {
    if a.distributed {
        // A build with the `mpi` feature runs it before reaching here (`main`).
        return Err(CliError::NotAvailable {
            feature: "deform move --distributed",
            needs: "the deform tool built with --features mpi (cargo build -p deform-cli --features mpi)",
        });
    }
    let su2 = input_kind(&a.mesh)? == FileKind::Su2;
    // Without --method: quaternion TFI on a Plot3D grid (`a.method()` gives quaternion else).
    let resolved;
    let a = if !su2 && a.method.is_none() {
        resolved = MoveArgs {
            method: Some(Method::Tfi),
            ..a.clone()
        };
        &resolved
    } else {
        a
    };
    checks::check_method(a, su2)?;
    if !su2 {
        return grid::move_grid(a);
    }
    checks::check_su2_args(a)?;
    move_su2(a, quiet, split)
}

/// The markers of a run, by role: moved, fixed (every other marker not sliding), sliding.
struct Roles<'m> {
    moved: Vec<&'m CellList>,
    fixed: Vec<&'m CellList>,
    slide: Vec<SlideMarker<'m>>,
}

impl<'m> Roles<'m> {
    fn new(mesh: &'m Su2Mesh, markers: &[String], slide: &[String]) -> Self {
        let lists = |keep: &dyn Fn(&String) -> bool| -> Vec<&'m CellList> {
            let m = mesh.markers.iter().filter(|m| keep(&m.name));
            m.map(|m| &m.elements).collect()
        };
        Roles {
            moved: lists(&|n| markers.contains(n)),
            fixed: lists(&|n| !markers.contains(n) && !slide.contains(n)),
            slide: (mesh.markers.iter())
                .filter(|m| slide.contains(&m.name))
                .map(|m| SlideMarker {
                    name: &m.name,
                    elements: &m.elements,
                })
                .collect(),
        }
    }
}

/// `deform move` on an SU2 mesh, after the arguments that need no mesh were checked.
fn move_su2(a: &MoveArgs, quiet: bool, split: Option<&dyn Splitter>) -> Result<Outcome, CliError> {
    // A multi-zone file: the zone of the named markers (the others are written back unchanged).
    let names: [&[String]; 2] = [&a.markers, &a.slide];
    crate::files::check_su2_output(&a.mesh, &a.out)?;
    let loaded = read_su2_zone(&a.mesh, &names, a.motions.as_deref())?;
    move_su2_read(a, quiet, split, loaded)
}

/// `move_mesh` on an SU2 mesh already read with `read_su2_zone` (`deform su2` reads it once
/// for its design variables): the same checks and run, no second read.
pub(crate) fn move_loaded(
    a: &MoveArgs,
    quiet: bool,
    loaded: (Su2Mesh, Option<ZonedSu2>),
) -> Result<Outcome, CliError> {
    checks::check_method(a, true)?;
    checks::check_su2_args(a)?;
    crate::files::check_su2_output(&a.mesh, &a.out)?;
    move_su2_read(a, quiet, None, loaded)
}

/// The deformed mesh's quality against the input (wall angles at the moved markers); an
/// error when cells that were valid are now inverted or folded, unless `--allow-folds`.
fn moved_quality(
    a: &MoveArgs,
    mesh: &Su2Mesh,
    markers: &[String],
    result: &crate::engine::MoveResult,
    prepared: Option<Result<PreparedReference, CliError>>,
) -> Result<crate::engine::QualitySummary, CliError> {
    let wall = marker_union(mesh, markers, &a.mesh)?;
    // A failed preparation is left to the full pass, which reports it as before.
    let prepared = prepared.and_then(Result::ok);
    let q = crate::engine::quality_prepared(
        mesh.dim,
        &mesh.elements,
        &result.deformed,
        Some(&mesh.points),
        prepared,
        Some(&wall),
        result.graph.as_ref(),
    )
    .map_err(|e| e.in_file(&a.mesh))?;
    check_new_folds(&q, a.allow_folds, &a.mesh)?;
    Ok(q)
}

/// `move_su2` after the read.
fn move_su2_read(
    a: &MoveArgs,
    quiet: bool,
    split: Option<&dyn Splitter>,
    (mesh, zoned): (Su2Mesh, Option<ZonedSu2>),
) -> Result<Outcome, CliError> {
    crate::guard::check_memory(
        &a.mesh,
        "deform move on this mesh",
        crate::guard::move_estimate(mesh.points.len(), mesh.elements.nodes.len()),
    )?;
    // --motions: the markers and their own rigid motions, as one displacement field.
    let per_marker = match &a.motions {
        Some(path) => Some(motion::marker_motions_field(&mesh, path, a.steps)?),
        None => None,
    };
    let markers: Vec<String> = match &per_marker {
        Some((specs, _)) => specs.iter().map(|m| m.marker.clone()).collect(),
        None => a.markers.clone(),
    };
    let moved = marker_nodes(&mesh, &markers, &a.mesh)?;
    if moved.is_empty() {
        return Err(CliError::Invalid("the named markers have no nodes".into()));
    }
    marker_nodes(&mesh, &a.slide, &a.mesh)?;
    checks::check_slide_markers(a, &markers)?;
    checks::check_rigid_args(a, mesh.dim)?;
    let (motion, exact_positions) = motion::motion_from_args(a, &mesh, &moved, &per_marker)?;
    checks::check_method_options(a)?;
    let started = Instant::now();
    let roles = Roles::new(&mesh, &markers, &a.slide);
    if let Some(s) = split {
        s.check_move(a)?;
    }
    let input = move_input(a, &mesh, &roles, motion, split)?;
    let spinner = crate::progress::spinner("deforming", quiet);
    // The process that writes (not the others of a split run) checks the quality.
    let writes = split.is_none_or(|s| s.is_root());
    let (result, prepared) = solve_beside_reference(a, &mesh, &input, &roles, writes);
    spinner.finish_and_clear();
    let (mut result, renumbered) = result.map_err(|e| e.in_file(&a.mesh))?;
    check_converged(a, &result)?;
    if split.is_some_and(|s| !s.is_root()) {
        // The other processes helped with the solves; the first one writes and reports.
        return Ok(Outcome {
            json: serde_json::Value::Null,
            text: String::new(),
        });
    }
    for (node, p) in &exact_positions {
        if let Some(x) = result.deformed.get_mut(*node as usize) {
            *x = *p;
        }
    }
    let q = moved_quality(a, &mesh, &markers, &result, prepared)?;
    let out_mesh = Su2Mesh {
        points: result.deformed.clone(),
        ..mesh.clone()
    };
    let outputs = outputs::write_outputs(a, zoned.as_ref(), &out_mesh, &result, &q, &roles.moved)?;
    let run = report::Run {
        mesh: &mesh,
        markers: &markers,
        per_marker: &per_marker,
        result: &result,
        quality: &q,
        outputs,
        renumbered,
        started,
    };
    let report = report::move_report(a, run);
    finish(a, report, &q, mesh.dim)
}

/// The engine's result and how the mesh was renumbered for it.
type Solved = Result<(MoveResult, crate::renumber::RenumberReport), CliError>;

/// The engine's solve, with the reference mesh's half of the quality check prepared beside it
/// on a second thread when `quality` (it does not depend on the solve).
fn solve_beside_reference(
    a: &MoveArgs,
    mesh: &Su2Mesh,
    input: &MoveInput<'_>,
    roles: &Roles<'_>,
    quality: bool,
) -> (Solved, Option<Result<PreparedReference, CliError>>) {
    std::thread::scope(|s| {
        let prepared =
            quality.then(|| s.spawn(|| prepare_reference(mesh.dim, &mesh.elements, &mesh.points)));
        let result = if a.method() == Method::Elasticity {
            elasticity::run(a, input, &roles.slide).map(|r| (r, crate::renumber::off_report()))
        } else {
            let how = renumbering(a);
            crate::renumber::run_move_renumbered(input, &roles.slide, a.steps as usize, how)
        };
        let prepared = prepared.map(|h| h.join().unwrap_or_else(|p| std::panic::resume_unwind(p)));
        (result, prepared)
    })
}

/// `--renumber`, except that `auto` leaves IDW alone (no graph solve to speed up).
fn renumbering(a: &MoveArgs) -> crate::renumber::Renumber {
    match a.method() {
        Method::Idw if a.renumber == crate::renumber::Renumber::Auto => {
            crate::renumber::Renumber::Off
        }
        _ => a.renumber,
    }
}

/// The engine's input: the mesh, the markers by role, the motion and the method's options.
fn move_input<'a>(
    a: &MoveArgs,
    mesh: &'a Su2Mesh,
    roles: &Roles<'a>,
    motion: crate::engine::Motion,
    split: Option<&'a dyn Splitter>,
) -> Result<MoveInput<'a>, CliError> {
    let method = match a.method() {
        Method::Quaternion => MoveMethod::Quaternion,
        Method::Idw => MoveMethod::Idw,
        Method::Spring => MoveMethod::Spring,
        Method::AngleDirect => MoveMethod::AngleDirect,
        Method::AngleCg => MoveMethod::AngleCg,
        Method::Rbf => MoveMethod::Rbf(rbf_settings(&a.rbf)),
        // Not a spring propagation: run by `elasticity::run`, which reads the rest.
        Method::Elasticity => MoveMethod::Spring,
        Method::Tfi | Method::TfiDisplacement => unreachable_tfi()?,
    };
    let solver = match a.solver {
        Solver::Amg => MoveSolver::Amg,
        Solver::Cg => MoveSolver::Cg,
        Solver::CgSsor => MoveSolver::CgSsor,
        Solver::Gs => MoveSolver::GaussSeidel,
        Solver::Jacobi => MoveSolver::Jacobi,
    };
    Ok(MoveInput {
        split,
        graph: None,
        dim: mesh.dim,
        points: &mesh.points,
        cells: &mesh.elements,
        moved: roles.moved.clone(),
        fixed: roles.fixed.clone(),
        motion,
        method,
        solver,
        amg_strength: a
            .amg_strength
            .unwrap_or_else(crate::engine::default_amg_strength),
        tol: a.tol,
        max_iter: a.max_iter,
        idw_exponent: a.idw_exponent,
        idw_fast: a.idw_theta.map(|theta| (theta, a.idw_tolerance)),
        reach: a.reach,
        stiffness: match a.stiffness() {
            StiffnessArg::Batina | StiffnessArg::Constant => Stiffness::Batina,
            StiffnessArg::WallDistance => Stiffness::WallDistance,
            StiffnessArg::InverseVolume => Stiffness::InverseVolume,
        },
    })
}

/// The engine's settings of `--method rbf`.
fn rbf_settings(r: &crate::args::RbfArgs) -> crate::engine::RbfSettings {
    crate::engine::RbfSettings {
        function: match r.rbf_kernel {
            crate::args::RbfKernelArg::Wendland => crate::engine::RbfFunction::Wendland,
            crate::args::RbfKernelArg::Tps => crate::engine::RbfFunction::Tps,
        },
        radius: r.rbf_radius,
        tolerance: r.rbf_tolerance,
        max_centres: r.rbf_max_centres,
        correction: r.rbf_correction,
    }
}

/// The failure policy for solves: an unconverged result is refused unless
/// `--allow-unconverged`.
fn check_converged(a: &MoveArgs, result: &MoveResult) -> Result<(), CliError> {
    if result.converged || a.allow_unconverged {
        return Ok(());
    }
    Err(CliError::Unconverged(format!(
        "{}: the {} solve did not converge: relative residual {:.3e} after {} iterations (--tol {:e}, --max-iter {}); nothing was written (--allow-unconverged writes it anyway)",
        a.mesh.display(),
        value_name(&a.method()),
        result.residual,
        result.iterations,
        a.tol,
        a.max_iter
    )))
}

/// The warnings of a written result, and its outcome (text and JSON).
fn finish(
    a: &MoveArgs,
    report: report::MoveReport,
    q: &QualitySummary,
    dim: usize,
) -> Result<Outcome, CliError> {
    if !report.converged {
        eprintln!(
            "deform: warning: the solver did not converge in {} iterations (residual {:.3e}); written because of --allow-unconverged",
            report.iterations, report.residual
        );
    }
    warn_new_folds(q);
    Ok(Outcome {
        text: report::report_text(a, &report, dim),
        json: volume_words(
            serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
            dim,
        ),
    })
}

/// The failure policy `move` and `smooth` share: a result with cells that the input did not
/// have inverted or folded is refused (nothing written) unless `allow` (`--allow-folds`).
pub(crate) fn check_new_folds(
    q: &QualitySummary,
    allow: bool,
    mesh: &std::path::Path,
) -> Result<(), CliError> {
    let bad = q.new_failures();
    if bad == 0 || allow {
        return Ok(());
    }
    Err(CliError::Folded(format!(
        "{}: the result has {bad} cell(s) inverted or folded that were valid in the input ({} inverted, {} folded in all); nothing was written (--allow-folds writes it anyway)",
        mesh.display(),
        q.inverted_cells.unwrap_or(0),
        q.folded_cells
    )))
}

/// With `--allow-folds`: says on stderr how many cells the written result spoiled.
pub(crate) fn warn_new_folds(q: &QualitySummary) {
    let bad = q.new_failures();
    if bad > 0 {
        eprintln!(
            "deform: warning: {bad} cell(s) inverted or folded that were valid in the input; written because of --allow-folds"
        );
    }
}

/// TFI never reaches the unstructured path (checked at the top of `move_mesh`).
pub(crate) fn unreachable_tfi() -> Result<MoveMethod, CliError> {
    Err(CliError::NotAvailable {
        feature: "transfinite interpolation on SU2 meshes",
        needs: "a structured Plot3D grid",
    })
}
