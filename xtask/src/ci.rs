//! `cargo xtask ci`: the step list and the runner that prints `N passed, N failed`.

use crate::codegen::codegen;
use crate::ctx::Ctx;
use crate::embedded::{cross_build, footprint, on_target};
use crate::fuzz::{fuzz, FUZZ_SMOKE_SECONDS, FUZZ_SMOKE_SEED};
use crate::help;
use crate::install::{cinstall, install, CROSS_TARGETS, FUZZ_TOOLCHAIN};
use crate::mpi::mpi_check;
use crate::panic::{panic_check, panic_check_deliberate};
use crate::process::run;
use crate::python::python_step;
use std::process::{Command, ExitCode};
use std::time::Instant;

/// Kernel features that only make sense on embedded targets: left out of the host test run.
pub(crate) const EMBEDDED_ONLY_FEATURES: &[&str] = &["defmt"];

/// The C library crate (`libdeform_kernel`): its own workspace, so built by manifest path.
pub(crate) const CAPI_MANIFEST: &str = "ffi/capi/Cargo.toml";

/// One CI step: a name, a one-line description and the work (`true` = passed).
pub(crate) struct Step<'a> {
    pub(crate) name: String,
    pub(crate) about: String,
    pub(crate) run: Box<dyn Fn() -> bool + 'a>,
}

impl<'a> Step<'a> {
    pub(crate) fn new(
        name: impl Into<String>,
        about: impl Into<String>,
        run: impl Fn() -> bool + 'a,
    ) -> Self {
        Step {
            name: name.into(),
            about: about.into(),
            run: Box::new(run),
        }
    }
}

/// Every CI step, in order.
pub(crate) fn steps(ctx: &Ctx) -> Vec<Step<'_>> {
    let mut s = vec![
        Step::new(
            "install",
            "rustup targets/components, apt packages, cargo tools",
            || install(ctx),
        ),
        Step::new(
            "fmt",
            "cargo fmt --check: host workspace, target-tests, fuzz, bench, mpi",
            || {
                let a = run(&mut ctx.cargo(&["fmt", "--all", "--check"]));
                // Not `--all` there: that would also check the kernel (a path dependency).
                let b = run(&mut ctx.cargo_tt(&["fmt", "--check"]));
                let c =
                    run(&mut ctx.cargo(&["fmt", "--check", "--manifest-path", "fuzz/Cargo.toml"]));
                let d =
                    run(&mut ctx.cargo(&["fmt", "--check", "--manifest-path", "bench/Cargo.toml"]));
                let e =
                    run(&mut ctx.cargo(&["fmt", "--check", "--manifest-path", "mpi/Cargo.toml"]));
                a && b && c && d && e
            },
        ),
        Step::new(
            "codegen",
            "cargo xtask codegen --check: the generated C ABI and Fortran interfaces are current",
            || codegen(ctx, true),
        ),
        Step::new(
            "clippy",
            "clippy --workspace --all-targets -D warnings (default features)",
            || run(&mut ctx.cargo(&clippy_args(&["--workspace"]))),
        ),
        Step::new(
            "clippy-all-features",
            "clippy --workspace --all-targets --all-features -D warnings",
            || run(&mut ctx.cargo(&clippy_args(&["--workspace", "--all-features"]))),
        ),
        Step::new(
            "clippy-kernel-features",
            "clippy on deform-kernel with each feature alone, -D warnings",
            || {
                let mut ok = true;
                for f in &ctx.kernel_features {
                    let args = [
                        "-p",
                        "deform-kernel",
                        "--no-default-features",
                        "--features",
                        f,
                    ];
                    ok &= run(&mut ctx.cargo(&clippy_args(&args)));
                }
                ok
            },
        ),
        Step::new(
            "cinstall",
            "cargo cinstall into a staging root; a C program builds against it via pkg-config",
            || cinstall(ctx),
        ),
        Step::new(
            "miri",
            "cargo +nightly miri test -p deform-kernel-ffi (the ABI boundary's unsafe, under Miri)",
            || {
                // The rustup proxy (not `ctx.cargo`, the active toolchain's cargo) picks nightly.
                let mut c = Command::new("cargo");
                c.arg(format!("+{FUZZ_TOOLCHAIN}"))
                    .args(["miri", "test", "-p", "deform-kernel-ffi"])
                    .current_dir(&ctx.root)
                    .env_remove("RUSTUP_TOOLCHAIN")
                    .env_remove("CARGO");
                run(&mut c)
            },
        ),
        Step::new("test", "cargo test --workspace", || {
            run(&mut ctx.cargo(&["test", "--workspace"]))
        }),
        Step::new(
            "python",
            "the Python package (python/): maturin wheel in target/python-venv, pytest",
            || python_step(ctx),
        ),
        Step::new(
            "test-cgns",
            "deform-cli with --features cgns: CGNS files against the CGNS library's and HDF5's tools",
            || {
                let args = ["test", "-p", "deform-cli", "--features", "cgns", "--test", "cgns"];
                run(&mut ctx.cargo(&args))
            },
        ),
        Step::new(
            "test-all-features",
            "kernel tests with every host feature (glam, micromath), and the tests that need one",
            || {
                // The features only add items (glam conversions, micromath fast paths): the
                // kernel's own tests and the host tests that require a feature are what they
                // change; `clippy-all-features` already compiles everything with all features.
                // Not `defmt`: it is for embedded targets (in a cdylib its JSON-named symbols
                // break the linker's version script); the panic check links it instead.
                let features: Vec<String> = ctx
                    .kernel_features
                    .iter()
                    .filter(|f| !EMBEDDED_ONLY_FEATURES.contains(&f.as_str()))
                    .map(|f| format!("deform-kernel/{f}"))
                    .collect();
                let features = features.join(",");
                let kernel = ["test", "-p", "deform-kernel", "--features", &features];
                let mut ok = run(&mut ctx.cargo(&kernel));
                for test in &ctx.feature_tests {
                    let args = ["test", "-p", "deform-host-tests", "--features", &features];
                    ok &= run(ctx.cargo(&args).args(["--test", test]));
                }
                ok
            },
        ),
        Step::new(
            "doc",
            "cargo doc --workspace --no-deps (+ kernel --all-features), RUSTDOCFLAGS=-D warnings",
            || {
                let runs: [&[&str]; 2] = [
                    &["doc", "--workspace", "--no-deps"],
                    &["doc", "-p", "deform-kernel", "--no-deps", "--all-features"],
                ];
                let mut ok = true;
                for args in runs {
                    let mut c = ctx.cargo(args);
                    c.env("RUSTDOCFLAGS", "-D warnings");
                    ok &= run(&mut c);
                }
                ok
            },
        ),
    ];
    for &target in CROSS_TARGETS {
        s.push(Step::new(
            format!("cross-{target}"),
            format!("build deform-kernel for {target}: no features, each alone, all"),
            move || cross_build(ctx, target),
        ));
    }
    s.extend([
        Step::new(
            "panic-check",
            "target-tests/panic-check links (no panic path survives), also with micromath",
            || panic_check(ctx),
        ),
        Step::new(
            "panic-check-deliberate",
            "panic-check --features deliberate-panic fails to link on the panic symbol",
            || panic_check_deliberate(ctx),
        ),
        Step::new(
            "on-target",
            "defmt-test suite on a Cortex-M4F under QEMU (target-tests/on-target), bits = host",
            || on_target(ctx),
        ),
        Step::new(
            "footprint",
            "960-node deformation in 64 KiB RAM + stack per entry point (QEMU); llvm-size per feature set",
            || footprint(ctx),
        ),
        Step::new(
            "mpi",
            "mpirun --oversubscribe -np 1, 2, 3: split spring sweeps + exact sums = serial bits; -np 1..7: partitioned storage (each rank its part + ghosts) CG = serial bits (mpi/)",
            || mpi_check(ctx),
        ),
        Step::new(
            "fuzz-smoke",
            "build every cargo-fuzz target and run each for 15 s from its committed seeds, libFuzzer seed fixed",
            || fuzz(ctx, FUZZ_SMOKE_SECONDS, None, Some(FUZZ_SMOKE_SEED)),
        ),
        Step::new(
            "clippy-target-tests",
            "clippy on the target-tests workspace (default and all features), -D warnings",
            || {
                let a = run(&mut ctx.cargo_tt(&clippy_args(&["--workspace"])));
                let b = run(&mut ctx.cargo_tt(&clippy_args(&["--workspace", "--all-features"])));
                a && b
            },
        ),
    ]);
    s
}

/// Column width for step names.
pub(crate) fn name_width(steps: &[Step<'_>]) -> usize {
    steps.iter().map(|s| s.name.len()).max().unwrap_or(0) + 2
}

/// `clippy <extra> --all-targets -- -D warnings`.
pub(crate) fn clippy_args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["clippy"];
    v.extend_from_slice(extra);
    v.extend_from_slice(&["--all-targets", "--", "-D", "warnings"]);
    v
}

pub(crate) fn ci(ctx: &Ctx, args: &[String]) -> ExitCode {
    let mut skip_install = false;
    let mut only: Vec<String> = Vec::new();
    let mut it = args.iter();
    let all = steps(ctx);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--skip-install" => skip_install = true,
            "--step" => match it.next() {
                Some(name) => only.push(name.clone()),
                None => {
                    eprintln!("xtask: --step needs a step name (see --list)");
                    return ExitCode::from(2);
                }
            },
            "--list" => {
                let w = name_width(&all);
                for s in &all {
                    println!("{:<w$}{}", s.name, s.about);
                }
                return ExitCode::SUCCESS;
            }
            "-h" | "--help" => {
                print!("{}", help());
                return ExitCode::SUCCESS;
            }
            other => {
                eprintln!("xtask: unknown option `{other}`\n");
                eprint!("{}", help());
                return ExitCode::from(2);
            }
        }
    }
    for name in &only {
        if !all.iter().any(|s| &s.name == name) {
            eprintln!("xtask: unknown step `{name}`; steps are:");
            for s in &all {
                eprintln!("    {}", s.name);
            }
            return ExitCode::from(2);
        }
    }
    let selected: Vec<&Step<'_>> = all
        .iter()
        .filter(|s| {
            if only.is_empty() {
                !(skip_install && s.name == "install")
            } else {
                only.contains(&s.name)
            }
        })
        .collect();

    let total = Instant::now();
    let mut results: Vec<(&str, bool, f64)> = Vec::new();
    for (i, step) in selected.iter().enumerate() {
        println!(
            "\n==> [{}/{}] {}: {}",
            i + 1,
            selected.len(),
            step.name,
            step.about
        );
        let t = Instant::now();
        let ok = (step.run)();
        let secs = t.elapsed().as_secs_f64();
        println!(
            "<== {}: {} ({secs:.1} s)",
            step.name,
            if ok { "ok" } else { "FAILED" }
        );
        results.push((&step.name, ok, secs));
    }

    let failed: Vec<&str> = results.iter().filter(|r| !r.1).map(|r| r.0).collect();
    println!("\n==== summary ====");
    let width = results.iter().map(|r| r.0.len()).max().unwrap_or(0);
    for (name, ok, secs) in &results {
        println!(
            "  {:<7}{name:<width$}{secs:>9.1} s",
            if *ok { "ok" } else { "FAILED" }
        );
    }
    println!("  total: {:.1} s", total.elapsed().as_secs_f64());
    if failed.is_empty() {
        println!("failed steps: none");
    } else {
        println!("failed steps: {}", failed.join(", "));
    }
    println!(
        "{} passed, {} failed",
        results.len() - failed.len(),
        failed.len()
    );
    if failed.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
