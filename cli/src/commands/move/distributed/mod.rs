//! `mpirun -np N deform move … --distributed` (the `mpi` feature): the linear springs or
//! Samareh's quaternion method with spring propagation, solved by CG + Jacobi on data that no
//! process holds whole, with the serial run's output, byte for byte.
//!
//! Each process reads one byte range of the SU2 file ([`read`]), keeps a contiguous block of
//! global ids with the cells that touch it and one ghost layer ([`local`]), runs the kernel's
//! partitioned solve through `deform_mpi::MpiExchange` (`PartitionedSprings` for the springs,
//! [`solve`]; `quaternion::deform_spring_partitioned` for the quaternion method, which gathers
//! the boundary to every process, [`solve_quaternion`]), counts the cells the motion inverted
//! or folded with a summed reduction, and writes its own rows into their place of the output
//! ([`write`]). Only the boundary (the markers, small) is read whole by every process.
//!
//! What runs: a rigid `--rotate` or `--translate` of named markers, `--method spring` or
//! `quaternion` (without `--reach`), `--solver cg`, Batina stiffness, one step. Every other
//! option is refused with a message, never run differently. The serial run's quality table,
//! wall angles and `--vtk`/`--plot` are not computed; its failure policies are kept (an
//! unconverged solve exits 5; cells newly inverted or folded exit 4, counted per cell without
//! the serial check's discount for cells that overlap a neighbour in the input, so a mesh with
//! such cells may be refused where the serial run writes it, never the other way round).

mod comm;
mod local;
mod read;
mod solve;
mod solve_quaternion;
mod write;

use std::process::ExitCode;
use std::time::Instant;

use mpi::topology::SimpleCommunicator;
use serde_json::json;

use crate::args::{Cli, Method, MoveArgs, Solver, StiffnessArg};
use crate::error::CliError;
use crate::report::Outcome;
use comm::{Failed, World};

/// Refuses, before reading, every option the distributed path does not run.
fn check_options(a: &MoveArgs) -> Result<(), CliError> {
    super::checks::check_method(a, true)?;
    super::checks::check_su2_args(a)?;
    super::checks::check_method_options(a)?;
    let refuse = |what: &str| {
        Err(CliError::Invalid(format!(
            "--distributed runs linear springs or the quaternion method (--method spring or quaternion, --solver cg) with a rigid --rotate or --translate of named markers in one step: {what} (run it without --distributed)"
        )))
    };
    if crate::files::input_kind(&a.mesh)? != crate::files::FileKind::Su2
        || crate::files::is_cgns_path(&a.out)
        || crate::files::sniff(&a.mesh)? == Some(crate::args::InputFormat::Cgns)
    {
        return refuse("the input and the output must be SU2 files");
    }
    if !matches!(a.method(), Method::Spring | Method::Quaternion) || a.solver != Solver::Cg {
        return refuse("another --method or --solver");
    }
    if a.reach.is_some() {
        return refuse("--reach");
    }
    if !matches!(a.stiffness(), StiffnessArg::Batina | StiffnessArg::Constant) {
        return refuse("--stiffness other than batina");
    }
    let files = [&a.displacements, &a.surface_positions, &a.motions];
    if files.iter().any(|f| f.is_some()) || a.design_field.is_some() {
        return refuse("a displacement, surface-position or motions file");
    }
    if a.steps != 1 || !a.slide.is_empty() || a.vtk.is_some() || a.plot.is_some() {
        return refuse("--steps, --slide, --vtk or --plot");
    }
    if !matches!(
        a.renumber,
        crate::renumber::Renumber::Off | crate::renumber::Renumber::Auto
    ) {
        return refuse("--renumber rcm or hilbert");
    }
    Ok(())
}

/// Runs `deform move --distributed` on this process: the outcome on the first process,
/// `Outcome` with nothing to print on the others.
fn run(world: &World<'_>, cli: &Cli, a: &MoveArgs) -> Result<Outcome, Failed> {
    let started = Instant::now();
    let checked = check_common(cli).and_then(|()| check_options(a));
    world.agree(checked)?;
    let r = read::read(world, &a.mesh)?;
    let summary = match (a.method(), r.skeleton.dim) {
        (Method::Quaternion, 2) => solve_quaternion::run::<2>(world, a, &r)?,
        (Method::Quaternion, _) => solve_quaternion::run::<3>(world, a, &r)?,
        (_, 2) => solve::run::<2>(world, a, &r)?,
        _ => solve::run::<3>(world, a, &r)?,
    };
    let rows = write::Rows {
        skeleton: &r.skeleton,
        nelem: r.nelem,
        npoin: r.npoin,
        elements: &r.elements,
        first_element: r.first_element,
        points: &summary.deformed,
        first_point: comm::block_start(r.npoin, world.size, world.rank),
    };
    write::write(world, &a.out, &rows)?;
    Ok(report(world, a, &r, &summary, started))
}

/// What `run_split` checks for every command: the output is not an input, the format flag.
fn check_common(cli: &Cli) -> Result<(), CliError> {
    crate::files::force_format(cli.format);
    let (inputs, outputs) = super::super::files_of(&cli.command);
    crate::guard::check_outputs(&inputs, &outputs)?;
    crate::guard::register_inputs(&inputs);
    Ok(())
}

/// The report (text and JSON) and the peak memory of every process.
fn report(
    world: &World<'_>,
    a: &MoveArgs,
    r: &read::Read,
    s: &solve::Summary,
    started: Instant,
) -> Outcome {
    let per_rank = world.gather_all(&[peak_rss_kib(), s.ghosts]);
    let peak: Vec<u64> = per_rank.iter().map(|v| v[0]).collect();
    let ghosts: Vec<u64> = per_rank.iter().map(|v| v[1]).collect();
    let largest = peak.iter().copied().max().unwrap_or(0);
    let (method, method_text) = match a.method() {
        Method::Quaternion => ("quaternion", "quaternion method, spring propagation"),
        _ => ("spring", "linear springs"),
    };
    let text = format!(
        "moved {} -> {} on {} processes (distributed, contiguous blocks of global ids): {} nodes, {} cells, {} moved and {} fixed nodes\n{method_text}, CG + Jacobi: {} iterations, relative residual {:.3e}{}\ncells newly inverted or folded: {} ({} inverted)\npeak memory per process: largest {:.1} MiB\ntime {:.2} s",
        a.mesh.display(),
        a.out.display(),
        world.size,
        r.npoin,
        r.nelem,
        s.moved,
        s.fixed,
        s.iterations,
        s.residual,
        if s.converged { "" } else { " (not converged; written because of --allow-unconverged)" },
        s.new_failures,
        s.inverted,
        largest as f64 / 1024.0,
        started.elapsed().as_secs_f64(),
    );
    let json = json!({
        "mesh": a.mesh.display().to_string(),
        "out": a.out.display().to_string(),
        "processes": world.size,
        "method": method,
        "solver": "cg",
        "nodes": r.npoin,
        "cells": r.nelem,
        "moved_nodes": s.moved,
        "fixed_nodes": s.fixed,
        "iterations": s.iterations,
        "residual": s.residual,
        "converged": s.converged,
        "new_failures": s.new_failures,
        "inverted_cells": s.inverted,
        "peak_rss_kib": peak,
        "ghost_nodes": ghosts,
        "seconds": started.elapsed().as_secs_f64(),
    });
    Outcome { json, text }
}

/// This process's peak resident memory (`VmHWM`, KiB; 0 where unknown).
fn peak_rss_kib() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap_or(0)
}

/// `deform move --distributed` on every process of `comm`: the first process prints the
/// report, or the error of the first process that failed; every process returns its exit
/// status.
pub(crate) fn main(cli: &Cli, a: &MoveArgs, comm: &SimpleCommunicator) -> ExitCode {
    let world = World::new(comm);
    let result = run(&world, cli, a);
    let own = matches!(result, Err(Some(_)));
    let failing = world.gather_all(&[u8::from(own)]);
    let first = failing.iter().position(|v| v[0] != 0);
    let Some(first) = first else {
        return match result {
            Ok(outcome) if world.rank == 0 => {
                let shown = if cli.json {
                    outcome.json.to_string()
                } else {
                    outcome.text
                };
                println!("{shown}");
                ExitCode::SUCCESS
            }
            Ok(_) => ExitCode::SUCCESS,
            // Every process failed with `None`: cannot happen (a failure is someone's own).
            Err(_) => ExitCode::FAILURE,
        };
    };
    let (code, message) = match &result {
        Err(Some(e)) => (e.exit_code(), e.to_string().replace(['\n', '\r'], " ")),
        _ => (1, String::new()),
    };
    let mut packet = (code as u32).to_le_bytes().to_vec();
    packet.extend_from_slice(message.as_bytes());
    let packet = world.broadcast_bytes(first, &packet);
    let code = packet
        .get(..4)
        .map_or(1, |b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if world.rank == 0 {
        eprintln!("deform: error: {}", String::from_utf8_lossy(&packet[4..]));
    }
    ExitCode::from(u8::try_from(code).unwrap_or(1))
}
