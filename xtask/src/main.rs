//! `cargo xtask`: the one place that knows how to install and run every check of deform-kernel.
//!
//! ```text
//! cargo xtask ci                      install what is missing, then run every step
//! cargo xtask ci --skip-install       run every step, install nothing
//! cargo xtask ci --step NAME          run one step (repeatable; no install unless named)
//! cargo xtask ci --list               list the step names
//! cargo xtask install                 only install what is missing
//! cargo xtask bench [--quick]        kernel vs peers on the same inputs (docs/performance.md)
//! cargo xtask codegen [--check]       C ABI extern fns, Fortran interfaces and types (ffi/abi, header)
//! cargo xtask panic-locate [ARGS]     show which functions still reach the panic handler
//! cargo xtask help                    this text
//! ```
//!
//! `cargo xtask ci` prints a header and the elapsed seconds for each step, carries on after a
//! failed step, and ends with a summary: the failed steps, then the line `N passed, N failed`.
//! It exits non-zero when any step failed.
//!
//! Adding things:
//! - a rustup target or component, an apt package (installed only when running as root, after
//!   one `apt-get update`), or a cargo tool at a pinned version (`cargo install --locked`): add
//!   it to the lists at the top of `install.rs`;
//! - a kernel feature: nothing to do, the feature list is read from `kernel/Cargo.toml` (every
//!   feature alone is clippy-checked and cross-built, and every feature not listed in
//!   `EMBEDDED_ONLY_FEATURES` is switched on for the kernel's tests in `test-all-features`; a
//!   host test that needs a feature gets `required-features`, and `test-all-features` runs it);
//! - a kernel entry point: call it from `target-tests/panic-check/src/<module>.rs`;
//! - a step: add it to `ci::steps`.
//!
//! One file a concern: `ci` (steps and runner), `codegen` (C ABI from its table), `header`
//! (Fortran declarations from the C header), `install`, `panic` (panic-freedom proof),
//! `embedded` (cross builds, QEMU, footprint), `fuzz`, `process` (running commands), `ctx`.
//!
//! Only std is used, so the tool builds in a second.

mod bench;
mod bench_elasticity;
mod ci;
mod codegen;
mod ctx;
mod embedded;
mod fuzz;
mod header;
mod install;
mod mpi;
mod panic;
mod process;
mod python;

use crate::ci::{ci, name_width, steps};
use crate::ctx::Ctx;
use crate::fuzz::fuzz_command;
use crate::install::install;
use crate::panic::panic_locate;
use std::env;
use std::fmt::Write as _;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    let ctx = Ctx::new();
    match args.first().map(String::as_str) {
        Some("ci") => ci(&ctx, &args[1..]),
        Some("install") => {
            if install(&ctx) {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        Some("fuzz") => fuzz_command(&ctx, &args[1..]),
        Some("codegen") => codegen::codegen_command(&ctx, &args[1..]),
        Some("bench") => bench::bench_command(&ctx, &args[1..]),
        Some("panic-locate") => {
            let extra: Vec<&str> = args[1..].iter().map(String::as_str).collect();
            if panic_locate(&ctx, &extra) {
                ExitCode::SUCCESS
            } else {
                ExitCode::FAILURE
            }
        }
        None | Some("help" | "-h" | "--help") => {
            print!("{}", help());
            ExitCode::SUCCESS
        }
        Some(other) => {
            eprintln!("xtask: unknown command `{other}`\n");
            eprint!("{}", help());
            ExitCode::from(2)
        }
    }
}

pub(crate) fn help() -> String {
    let mut s = String::from(
        "cargo xtask: install and run every check of deform-kernel\n\
         \n\
         USAGE:\n\
         \x20   cargo xtask ci [--skip-install] [--step NAME]... [--list]\n\
         \x20   cargo xtask install\n\
         \x20   cargo xtask fuzz [--seconds N] [--target NAME]\n\
         \x20   cargo xtask bench [--quick] [--no-peers] [--unordered-only | --python-only | --elasticity-only]\n\
         \x20   cargo xtask codegen [--check]\n\
         \x20   cargo xtask panic-locate [--features F]\n\
         \x20   cargo xtask help\n\
         \n\
         COMMANDS:\n\
         \x20   ci            Install what is missing (rustup targets and components, apt packages\n\
         \x20                 when root, pinned cargo tools), then run every step below. Prints a\n\
         \x20                 header and elapsed seconds per step, carries on after failures, ends\n\
         \x20                 with the failed steps and `N passed, N failed`; exits non-zero on any\n\
         \x20                 failure. This is the project's single test command (.ci/run runs it).\n\
         \x20   install       Only the install part.\n\
         \x20   fuzz          Build the cargo-fuzz targets (fuzz/, nightly) and run each for N\n\
         \x20                 seconds (default 600), one per core, from fuzz/seeds/<target>, growing\n\
         \x20                 the corpus in fuzz/corpus/<target>; prints executions and findings.\n\
         \x20   bench         The kernel against numpy/scipy, scipy.ndimage, trimesh, pyamg and\n\
         \x20                 nalgebra on the same generated inputs (bench/, bench/peers/), and\n\
         \x20                 `deform move` on the 234k NACA 2412 mesh and on unordered meshes, and\n\
         \x20                 the Python package against the tool; ratios and load to stdout and\n\
         \x20                 target/bench/report.md (see docs/performance.md). --unordered-only\n\
         \x20                 and --python-only run one of those steps alone.\n\
         \x20   codegen       Write ffi/generated/ from the #[export] items of ffi/src: the extern \"C\"\n\
         \x20                 functions (f64 and _f32), the C header (cbindgen), the Fortran module,\n\
         \x20                 the panic-check calls and symbols.txt; --check only compares (CI).\n\
         \x20   panic-locate  Build target-tests/panic-check with its `locate` feature (the panic\n\
         \x20                 handler defined, so it links) and list the functions that still reach\n\
         \x20                 it, with the source lines of the calls. Run it when `panic-check` fails;\n\
         \x20                 extra arguments go to that cargo build (e.g. --features micromath).\n\
         \n\
         OPTIONS (ci):\n\
         \x20   --skip-install  Do not install anything.\n\
         \x20   --step NAME     Run only this step (repeatable). No install unless `--step install`.\n\
         \x20   --list          Print the step names and what each runs.\n\
         \n\
         STEPS:\n",
    );
    let ctx = Ctx::new();
    let all = steps(&ctx);
    let w = name_width(&all);
    for step in &all {
        let _ = writeln!(s, "    {:<w$}{}", step.name, step.about);
    }
    s
}
