//! The `deform` command-line tool: see `deform --help`.

use std::process::ExitCode;

use clap::Parser;
use deform_cli::args::Cli;
use deform_cli::commands::run;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = deform_cli::guard::install_signal_cleanup() {
        eprintln!("deform: warning: cannot watch for interrupts ({e}); an interrupted run may leave a hidden .deform-tmp file");
    }
    match run(&cli) {
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
