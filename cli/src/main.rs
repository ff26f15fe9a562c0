//! The `deform` command-line tool: see `deform --help`.

use std::process::ExitCode;

use clap::Parser;
use deform_cli::args::Cli;
use deform_cli::commands::run_split;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = deform_cli::guard::install_signal_cleanup() {
        eprintln!("deform: warning: cannot watch for interrupts ({e}); an interrupted run may leave a hidden .deform-tmp file");
    }
    #[cfg(feature = "mpi")]
    {
        use deform_cli::split::Splitter;
        // MPI lives as long as `universe`; one process is a serial run.
        let Some(universe) = mpi::initialize() else {
            eprintln!("deform: error: MPI is already initialised");
            return ExitCode::FAILURE;
        };
        let world = universe.world();
        if let deform_cli::args::Command::Move(a) = &cli.command {
            if a.distributed {
                return deform_cli::commands::run_distributed(&cli, a, &world);
            }
        }
        let splitter = deform_cli::split::MpiSplitter::new(&world);
        if splitter.size() > 1 {
            return finish(&cli, run_split(&cli, Some(&splitter)), splitter.is_root());
        }
    }
    finish(&cli, run_split(&cli, None), true)
}

/// Prints the outcome (on the reporting process) and maps it to the exit code.
fn finish(
    cli: &Cli,
    result: Result<deform_cli::report::Outcome, deform_cli::commands::CliError>,
    root: bool,
) -> ExitCode {
    match result {
        Ok(_) if !root => ExitCode::SUCCESS,
        Ok(outcome) => {
            if cli.json {
                println!("{}", outcome.json);
            } else {
                println!("{}", outcome.text);
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            let one_line = e.to_string().replace(['\n', '\r'], " ");
            eprintln!("deform: error: {one_line}");
            ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(1))
        }
    }
}
