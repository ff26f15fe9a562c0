//! Embedded steps: cross builds, the on-target suite under QEMU, the footprint figures.

use crate::ctx::Ctx;
use crate::panic::llvm_tool;
use crate::process::{capture, run, show};
use std::path::PathBuf;
use std::process::Command;

/// Builds the kernel for `target` with no features, each feature alone, and all features.
pub(crate) fn cross_build(ctx: &Ctx, target: &str) -> bool {
    let base = ["build", "-p", "deform-kernel", "--target", target];
    let mut ok = true;
    let mut no_features = base.to_vec();
    no_features.push("--no-default-features");
    ok &= run(&mut ctx.cargo(&no_features));
    for f in &ctx.kernel_features {
        let mut args = no_features.clone();
        args.extend(["--features", f.as_str()]);
        ok &= run(&mut ctx.cargo(&args));
    }
    let mut all = base.to_vec();
    all.push("--all-features");
    ok &= run(&mut ctx.cargo(&all));
    ok
}

/// Runs the defmt-test suite under QEMU and prints `on-target: N passed, N failed`, counted
/// from defmt-test's `(i/n) running ...` and `all tests passed!` lines (it prints no summary).
pub(crate) fn on_target(ctx: &Ctx) -> bool {
    // --no-fail-fast: every test binary runs even after one fails, so the counts are complete.
    // The `on-target` profile is release without the fat LTO the panic check needs (the bits
    // do not depend on it): 17 test binaries, one LTO each, were most of this step's time.
    let mut cmd = ctx.cargo_tt(&[
        "test",
        "--profile",
        "on-target",
        "--no-fail-fast",
        "-p",
        "deform-on-target",
    ]);
    println!("$ {}", show(&cmd));
    let (ok, stdout, stderr) = capture(&mut cmd);
    print!("{stdout}");
    eprint!("{stderr}");
    let (passed, failed) = count_defmt_tests(&format!("{stderr}\n{stdout}"));
    println!("on-target: {passed} passed, {failed} failed");
    ok && failed == 0 && passed > 0
}

/// Counts passed and failed tests in defmt-test output: in each binary, the tests announced
/// before `all tests passed!` passed; when a binary stops without it, its last announced test
/// failed (the panic handler exits QEMU at once).
pub(crate) fn count_defmt_tests(out: &str) -> (usize, usize) {
    let (mut passed, mut failed) = (0, 0);
    let mut running = 0usize; // tests announced in the current binary and not yet settled
    for line in out.lines() {
        let line = line.trim();
        if line.starts_with("Running ") {
            if running > 0 {
                // The previous binary ended without `all tests passed!`.
                passed += running - 1;
                failed += 1;
            }
            running = 0;
        } else if line.starts_with('(') && line.contains(") running `") {
            // `(1/n)` starts a binary. cargo's `Running` lines go to stderr and the tests'
            // output to stdout, so they do not interleave in the captured text: this is what
            // separates the binaries.
            if line.starts_with("(1/") && running > 0 {
                passed += running - 1;
                failed += 1;
                running = 0;
            }
            running += 1;
        } else if line.contains("all tests passed!") {
            passed += running;
            running = 0;
        }
    }
    if running > 0 {
        passed += running - 1;
        failed += 1;
    }
    (passed, failed)
}

// ---------------------------------------------------------------------------------------------
// footprint

/// Kernel feature sets of the size table: (label, features of `deform-footprint`).
pub(crate) const FOOTPRINT_FEATURE_SETS: &[(&str, &str)] = &[
    ("none", ""),
    ("micromath", "micromath"),
    ("defmt", "kernel-defmt"),
    ("all", "micromath,kernel-defmt,glam"),
];

/// Builds `target-tests/footprint` once per kernel feature set and prints its `llvm-size`
/// (flash = text + data, RAM = data + bss), then runs the default build under QEMU: a 960-node
/// deformation inside 64 KiB of RAM, with the painted-stack peak of each main entry point.
/// Fails when a build fails, llvm-size is missing, or the run fails (does not fit, a check
/// fails, a stack overflow is detected).
pub(crate) fn footprint(ctx: &Ctx) -> bool {
    let Some(size_tool) = llvm_tool(ctx, "llvm-size") else {
        println!("xtask: llvm-size not found (rustup component add llvm-tools)");
        return false;
    };
    let mut ok = true;
    let mut rows = Vec::new();
    for &(label, features) in FOOTPRINT_FEATURE_SETS {
        let mut args = vec![
            "build",
            "--release",
            "-p",
            "deform-footprint",
            "--message-format=json-render-diagnostics",
        ];
        if !features.is_empty() {
            args.extend(["--features", features]);
        }
        let mut cmd = ctx.cargo_tt(&args);
        println!("$ {}", show(&cmd));
        let (built, json, err) = capture(&mut cmd);
        eprint!("{err}");
        // The ELF of *this* feature set: cargo does not re-copy `target/.../footprint` when a
        // cached build is fresh, so take the path from the build's own artifact message.
        let elf = json
            .lines()
            .filter(|l| l.contains("\"reason\":\"compiler-artifact\""))
            .find_map(|l| {
                let rest = l.split("\"executable\":\"").nth(1)?;
                Some(PathBuf::from(rest.split('"').next()?))
            });
        let Some(elf) = elf.filter(|_| built) else {
            println!("xtask: footprint build failed ({label})");
            ok = false;
            continue;
        };
        let (size_ok, out, err) = capture(Command::new(&size_tool).arg(&elf));
        // Berkeley format: `text data bss dec hex filename`.
        let nums: Option<Vec<u64>> = out.lines().nth(1).map(|l| {
            l.split_whitespace()
                .take(3)
                .filter_map(|x| x.parse().ok())
                .collect()
        });
        match nums.as_deref() {
            Some(&[text, data, bss]) if size_ok => rows.push((label, text, data, bss)),
            _ => {
                println!("xtask: llvm-size failed: {out}{err}");
                ok = false;
            }
        }
    }
    println!();
    println!("footprint binary (thumbv7em-none-eabihf, release) per kernel feature set:");
    println!(
        "  {:<10} {:>8} {:>7} {:>7} {:>10} {:>9}",
        "features", "text", "data", "bss", "flash", "static RAM"
    );
    for (label, text, data, bss) in &rows {
        println!(
            "  {:<10} {:>8} {:>7} {:>7} {:>10} {:>9}",
            label,
            text,
            data,
            bss,
            text + data,
            data + bss
        );
    }
    println!("  (bss holds the caller's buffers of the 960-node run; the stack is on top)");
    println!();
    let mut cmd = ctx.cargo_tt(&["run", "--release", "-p", "deform-footprint"]);
    ok &= run(&mut cmd);
    ok
}

// ---------------------------------------------------------------------------------------------
// fuzzing
