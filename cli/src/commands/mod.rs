//! The commands behind the `deform` binary, one module each. Each validates all of its inputs,
//! stages every output in a temporary file and renames them into place only on success.
//!
//! Dependencies run one way: `commands` → [`crate::files`], [`crate::report`], [`crate::engine`],
//! [`crate::plot`], [`crate::output`], [`crate::formats`] → [`crate::error`]; nothing below imports
//! a command.

mod convert;
mod demo;
mod mesh;
mod r#move;
mod quality;
mod sensitivity;
mod smooth;
mod su2;

use std::path::{Path, PathBuf};

use crate::args::{Cli, Command, MeshCommand};

pub use crate::error::CliError;
use crate::report::Outcome;
use convert::convert;
use mesh::{mesh_block, mesh_naca};
use quality::quality;
use r#move::move_mesh;
use smooth::smooth;

/// Runs the parsed command line.
pub fn run(cli: &Cli) -> Result<Outcome, CliError> {
    run_split(cli, None)
}

/// Runs the parsed command line as one of several processes (`mpirun`, the `mpi` feature):
/// `deform move` splits its spring solves over them; other commands are refused.
pub fn run_split(
    cli: &Cli,
    split: Option<&dyn crate::split::Splitter>,
) -> Result<Outcome, CliError> {
    if split.is_some_and(|s| s.size() > 1) && !matches!(cli.command, Command::Move(_)) {
        return Err(CliError::Invalid(
            "under mpirun only `deform move` runs split across processes; run this command without mpirun".into(),
        ));
    }
    let quiet = cli.json;
    crate::files::force_format(cli.format);
    let (inputs, outputs) = files_of(&cli.command);
    crate::guard::check_outputs(&inputs, &outputs)?;
    crate::guard::register_inputs(&inputs);
    match &cli.command {
        Command::Demo(a) => demo::demo(a, quiet),
        Command::Mesh(MeshCommand::Naca(a)) => mesh_naca(a),
        Command::Mesh(MeshCommand::Block(a)) => mesh_block(a),
        Command::Move(a) => move_mesh(a, quiet, split),
        Command::Smooth(a) => smooth(a, quiet),
        Command::Su2(a) => su2::su2(a, quiet),
        Command::Adjoint(a) => sensitivity::adjoint(a),
        Command::Tangent(a) => sensitivity::tangent(a),
        Command::Quality(a) => quality(a),
        Command::Convert(a) => convert(a),
    }
}

/// `deform move --distributed` on every process of `world` (the `mpi` feature): the exit
/// status; the first process prints the outcome or the error.
#[cfg(feature = "mpi")]
pub fn run_distributed(
    cli: &Cli,
    a: &crate::args::MoveArgs,
    world: &mpi::topology::SimpleCommunicator,
) -> std::process::ExitCode {
    r#move::distributed::main(cli, a, world)
}

/// The input and output files a command names on its command line.
pub(crate) fn files_of(command: &Command) -> (Vec<&Path>, Vec<&Path>) {
    fn opt(p: &Option<PathBuf>) -> Option<&Path> {
        p.as_deref()
    }
    match command {
        Command::Demo(_) => (vec![], vec![]),
        Command::Mesh(MeshCommand::Naca(a)) => (vec![], vec![&a.out]),
        Command::Mesh(MeshCommand::Block(a)) => (vec![], vec![&a.out]),
        Command::Move(a) => (
            [
                Some(a.mesh.as_path()),
                opt(&a.displacements),
                opt(&a.surface_positions),
                opt(&a.motions),
            ]
            .into_iter()
            .flatten()
            .collect(),
            [Some(a.out.as_path()), opt(&a.vtk), opt(&a.plot)]
                .into_iter()
                .flatten()
                .collect(),
        ),
        Command::Smooth(a) => (vec![&a.grid], vec![&a.out]),
        // The mesh and output named in the configuration are checked when it is read.
        Command::Su2(a) => (vec![&a.config], vec![]),
        Command::Quality(a) => (
            [Some(a.file.as_path()), opt(&a.reference)]
                .into_iter()
                .flatten()
                .collect(),
            opt(&a.vtk).into_iter().collect(),
        ),
        Command::Convert(a) => (vec![&a.input], vec![&a.output]),
        Command::Adjoint(a) => (
            [&a.setup.mesh, &a.sensitivity]
                .into_iter()
                .chain(&a.config)
                .map(|p| p.as_path())
                .collect(),
            [&a.out]
                .into_iter()
                .chain(&a.grad_out)
                .map(|p| p.as_path())
                .collect(),
        ),
        Command::Tangent(a) => (vec![&a.setup.mesh, &a.perturbation], vec![&a.out]),
    }
}
