//! `cargo xtask`: the one place that knows how to install and run every check of deform-kernel.
//!
//! ```text
//! cargo xtask ci                      install what is missing, then run every step
//! cargo xtask ci --skip-install       run every step, install nothing
//! cargo xtask ci --step NAME          run one step (repeatable; no install unless named)
//! cargo xtask ci --list               list the step names
//! cargo xtask install                 only install what is missing
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
//!   it to the lists at the top of this file;
//! - a kernel feature: nothing to do, the feature list is read from `kernel/Cargo.toml` (every
//!   feature alone is clippy-checked and cross-built, and every feature not listed in
//!   `EMBEDDED_ONLY_FEATURES` is switched on for the second host test run);
//! - a kernel entry point: call it from `target-tests/panic-check/src/<module>.rs`;
//! - a step: add it to [`steps`].
//!
//! Only std is used, so the tool builds in a second.

use std::env;
use std::ffi::OsStr;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

/// Cross-compilation targets the kernel must build for (bare metal, no std).
const CROSS_TARGETS: &[&str] = &[
    "thumbv7em-none-eabihf",
    "thumbv6m-none-eabi",
    "riscv32imc-unknown-none-elf",
];

/// Rustup targets installed on the active toolchain.
const RUSTUP_TARGETS: &[&str] = CROSS_TARGETS;

/// Rustup components installed on the active toolchain. `rust-src` and `llvm-tools` serve the
/// embedded builds and `cargo xtask panic-locate` (llvm-objdump).
const RUSTUP_COMPONENTS: &[&str] = &["rustfmt", "clippy", "rust-src", "llvm-tools"];

/// Debian packages, installed with `apt-get install` when running as root (e.g. `gfortran`,
/// `qemu-system-arm`). Checked with `dpkg -s`.
/// `libssl-dev` and `pkg-config` are needed to build cargo-c, and `pkg-config` by the
/// `cinstall` step.
const APT_PACKAGES: &[&str] = &["gfortran", "qemu-system-arm", "libssl-dev", "pkg-config"];

/// A cargo tool installed with `cargo install --locked NAME --version VERSION`.
struct CargoTool {
    /// Crate name.
    name: &'static str,
    /// Exact version.
    version: &'static str,
}

/// Cargo tools at pinned versions (e.g. cargo-fuzz, defmt-print, cbindgen).
const CARGO_TOOLS: &[CargoTool] = &[
    CargoTool {
        name: "defmt-print",
        version: "1.2.0",
    },
    CargoTool {
        name: "cargo-fuzz",
        version: "0.13.1",
    },
    // The last cargo-c release that builds with the pinned stable rustc (1.95).
    CargoTool {
        name: "cargo-c",
        version: "0.10.24+cargo-0.98.0",
    },
];

/// The toolchain cargo-fuzz needs (sanitizer flags are nightly-only).
const FUZZ_TOOLCHAIN: &str = "nightly";

/// Seconds each fuzz target runs in `cargo xtask ci` (the smoke run).
const FUZZ_SMOKE_SECONDS: u64 = 30;

/// Symbol the panic-check's `#[panic_handler]` calls and that nothing defines.
const PANIC_SYMBOL: &str = "deform_kernel_panic_path_survived";

/// Kernel features that only make sense on embedded targets: left out of the host test run.
const EMBEDDED_ONLY_FEATURES: &[&str] = &["defmt"];

/// The C ABI crate (its lib is also named `deform_kernel`; see the `doc` step).
const FFI_PACKAGE: &str = "deform-kernel-ffi";

/// The embedded target of `target-tests/`.
const PANIC_CHECK_TARGET: &str = "thumbv7em-none-eabihf";

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

fn help() -> String {
    let mut s = String::from(
        "cargo xtask: install and run every check of deform-kernel\n\
         \n\
         USAGE:\n\
         \x20   cargo xtask ci [--skip-install] [--step NAME]... [--list]\n\
         \x20   cargo xtask install\n\
         \x20   cargo xtask fuzz [--seconds N] [--target NAME]\n\
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
         \x20                 seconds (default 600) from fuzz/seeds/<target>, growing the corpus\n\
         \x20                 in fuzz/corpus/<target>; prints executions and findings per target.\n\
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

/// Paths and tools shared by every step.
struct Ctx {
    /// Repository root (the host workspace).
    root: PathBuf,
    /// `target-tests/` (its own workspace and `.cargo/config.toml`).
    target_tests: PathBuf,
    /// The cargo that runs us (same toolchain), or `cargo`.
    cargo: String,
    /// Kernel features (from `kernel/Cargo.toml`, without `default`).
    kernel_features: Vec<String>,
}

impl Ctx {
    fn new() -> Ctx {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let kernel_features = kernel_features(&root.join("kernel").join("Cargo.toml"));
        Ctx {
            target_tests: root.join("target-tests"),
            root,
            cargo: env::var("CARGO").unwrap_or_else(|_| "cargo".into()),
            kernel_features,
        }
    }

    /// A cargo command run from the repository root.
    fn cargo(&self, args: &[&str]) -> Command {
        let mut c = Command::new(&self.cargo);
        c.args(args).current_dir(&self.root);
        c
    }

    /// A cargo command run from `target-tests/` (so its `.cargo/config.toml` applies).
    fn cargo_tt(&self, args: &[&str]) -> Command {
        let mut c = Command::new(&self.cargo);
        c.args(args).current_dir(&self.target_tests);
        c
    }
}

/// Feature names of the `[features]` table of a Cargo.toml (without `default`). A tiny
/// line-based reader: enough for `name = [...]` entries, one per line.
fn kernel_features(manifest: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(manifest).unwrap_or_default();
    let mut in_features = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            in_features = line == "[features]";
            continue;
        }
        if !in_features || line.starts_with('#') {
            continue;
        }
        if let Some((name, _)) = line.split_once('=') {
            let name = name.trim().trim_matches('"');
            if !name.is_empty() && name != "default" {
                out.push(name.to_string());
            }
        }
    }
    out
}

/// One CI step: a name, a one-line description and the work (`true` = passed).
struct Step<'a> {
    name: String,
    about: String,
    run: Box<dyn Fn() -> bool + 'a>,
}

impl<'a> Step<'a> {
    fn new(name: impl Into<String>, about: impl Into<String>, run: impl Fn() -> bool + 'a) -> Self {
        Step {
            name: name.into(),
            about: about.into(),
            run: Box::new(run),
        }
    }
}

/// Every CI step, in order.
fn steps(ctx: &Ctx) -> Vec<Step<'_>> {
    let mut s = vec![
        Step::new(
            "install",
            "rustup targets/components, apt packages, cargo tools",
            || install(ctx),
        ),
        Step::new(
            "fmt",
            "cargo fmt --check: host workspace, target-tests, fuzz",
            || {
                let a = run(&mut ctx.cargo(&["fmt", "--all", "--check"]));
                // Not `--all` there: that would also check the kernel (a path dependency).
                let b = run(&mut ctx.cargo_tt(&["fmt", "--check"]));
                let c =
                    run(&mut ctx.cargo(&["fmt", "--check", "--manifest-path", "fuzz/Cargo.toml"]));
                a && b && c
            },
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
        Step::new("test", "cargo test --workspace", || {
            run(&mut ctx.cargo(&["test", "--workspace"]))
        }),
        Step::new(
            "test-all-features",
            "cargo test --workspace with every kernel feature that runs on a host (not defmt)",
            || {
                // Not `--all-features`: the kernel's `defmt` feature puts defmt's JSON-named
                // symbols into the C library's cdylib (a dependency of host-tests), whose
                // linker version script then fails to parse. defmt is for embedded targets;
                // it is clippy-checked, cross-built and linked by the panic check instead.
                let features: Vec<String> = ctx
                    .kernel_features
                    .iter()
                    .filter(|f| !EMBEDDED_ONLY_FEATURES.contains(&f.as_str()))
                    .map(|f| format!("deform-kernel/{f}"))
                    .collect();
                let features = features.join(",");
                run(&mut ctx.cargo(&["test", "--workspace", "--features", &features]))
            },
        ),
        Step::new(
            "doc",
            "cargo doc --workspace --no-deps (+ kernel --all-features), RUSTDOCFLAGS=-D warnings",
            || {
                // The ffi crate's lib is also named `deform_kernel` (for libdeform_kernel.a),
                // so `cargo doc --workspace` refuses to document both at once ("output filename
                // collision"). Document it on its own first; the workspace run then writes the
                // kernel's pages over it. rustdoc does not see the profile's `panic = "abort"`,
                // which the ffi crate insists on unless its `test-unwind` feature is on.
                let runs: [&[&str]; 3] = [
                    &[
                        "doc",
                        "-p",
                        FFI_PACKAGE,
                        "--no-deps",
                        "--features",
                        "test-unwind",
                    ],
                    &["doc", "--workspace", "--no-deps", "--exclude", FFI_PACKAGE],
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
            "1,000-node deformation in 64 KiB RAM + stack per entry point (QEMU); llvm-size per feature set",
            || footprint(ctx),
        ),
        Step::new(
            "fuzz-smoke",
            "build every cargo-fuzz target and run each for 30 s from its committed seeds",
            || fuzz(ctx, FUZZ_SMOKE_SECONDS, None),
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
fn name_width(steps: &[Step<'_>]) -> usize {
    steps.iter().map(|s| s.name.len()).max().unwrap_or(0) + 2
}

/// `clippy <extra> --all-targets -- -D warnings`.
fn clippy_args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["clippy"];
    v.extend_from_slice(extra);
    v.extend_from_slice(&["--all-targets", "--", "-D", "warnings"]);
    v
}

fn ci(ctx: &Ctx, args: &[String]) -> ExitCode {
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

/// Shows and runs a command with inherited stdio; `true` when it exits with status 0.
fn run(cmd: &mut Command) -> bool {
    println!("$ {}", show(cmd));
    match cmd.status() {
        Ok(status) if status.success() => true,
        Ok(status) => {
            println!("xtask: command failed ({status}): {}", show(cmd));
            false
        }
        Err(e) => {
            println!("xtask: cannot run {}: {e}", show(cmd));
            false
        }
    }
}

/// Runs a command capturing its output: `(success, stdout, stderr)`.
fn capture(cmd: &mut Command) -> (bool, String, String) {
    match cmd.stdin(Stdio::null()).output() {
        Ok(out) => (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        ),
        Err(e) => (
            false,
            String::new(),
            format!("cannot run {}: {e}", show(cmd)),
        ),
    }
}

/// `KEY=VALUE program args` for logs (with the directory when it is not the root).
fn show(cmd: &Command) -> String {
    let mut s = String::new();
    for (k, v) in cmd.get_envs() {
        if let Some(v) = v {
            let _ = write!(s, "{}={} ", k.to_string_lossy(), v.to_string_lossy());
        }
    }
    let program = cmd.get_program().to_string_lossy();
    let program = if program.ends_with("/cargo") || program.ends_with("\\cargo") {
        "cargo".into()
    } else {
        program
    };
    s.push_str(&program);
    for a in cmd.get_args() {
        s.push(' ');
        s.push_str(&a.to_string_lossy());
    }
    if let Some(dir) = cmd.get_current_dir() {
        if dir.file_name() == Some(OsStr::new("target-tests")) {
            s.push_str("   (in target-tests/)");
        }
    }
    s
}

// ---------------------------------------------------------------------------------------------
// install

/// Installs whatever is missing; `true` when everything is in place afterwards.
fn install(ctx: &Ctx) -> bool {
    let mut ok = true;
    let rustup = |args: &[&str]| {
        let mut c = Command::new("rustup");
        c.args(args).current_dir(&ctx.root);
        c
    };

    let (_, installed, _) = capture(&mut rustup(&["target", "list", "--installed"]));
    let installed: Vec<&str> = installed.lines().map(str::trim).collect();
    let missing: Vec<&str> = RUSTUP_TARGETS
        .iter()
        .copied()
        .filter(|t| !installed.contains(t))
        .collect();
    if missing.is_empty() {
        println!(
            "rustup targets: all present ({})",
            RUSTUP_TARGETS.join(", ")
        );
    } else {
        let mut args = vec!["target", "add"];
        args.extend(&missing);
        ok &= run(&mut rustup(&args));
    }

    let (_, installed, _) = capture(&mut rustup(&["component", "list", "--installed"]));
    // Listed as `name-<host triple>` (or `name` for rust-src).
    let has = |c: &str| {
        installed.lines().map(str::trim).any(|l| {
            l == c
                || l.strip_prefix(c)
                    .is_some_and(|rest| rest.starts_with('-') && rest.contains("-unknown-"))
        })
    };
    let missing: Vec<&str> = RUSTUP_COMPONENTS
        .iter()
        .copied()
        .filter(|c| !has(c))
        .collect();
    if missing.is_empty() {
        println!(
            "rustup components: all present ({})",
            RUSTUP_COMPONENTS.join(", ")
        );
    } else {
        let mut args = vec!["component", "add"];
        args.extend(&missing);
        ok &= run(&mut rustup(&args));
    }

    let missing: Vec<&str> = APT_PACKAGES
        .iter()
        .copied()
        .filter(|p| !capture(Command::new("dpkg").args(["-s", p])).0)
        .collect();
    if missing.is_empty() {
        if !APT_PACKAGES.is_empty() {
            println!("apt packages: all present ({})", APT_PACKAGES.join(", "));
        }
    } else if is_root() {
        let apt = |args: &[&str]| {
            let mut c = Command::new("apt-get");
            c.args(args)
                .env("DEBIAN_FRONTEND", "noninteractive")
                .stdin(Stdio::null());
            c
        };
        ok &= run(&mut apt(&["update", "-q"]));
        let mut args = vec!["install", "-y", "-q", "--no-install-recommends"];
        args.extend(&missing);
        ok &= run(&mut apt(&args));
    } else {
        println!(
            "xtask: missing apt packages and not root: sudo apt-get install {}",
            missing.join(" ")
        );
        ok = false;
    }

    if !CARGO_TOOLS.is_empty() {
        let (_, list, _) = capture(&mut ctx.cargo(&["install", "--list"]));
        for tool in CARGO_TOOLS {
            let line = format!("{} v{}:", tool.name, tool.version);
            if list.lines().any(|l| l.trim() == line) {
                println!("cargo tool {} {}: present", tool.name, tool.version);
            } else {
                ok &= run(&mut ctx.cargo(&[
                    "install",
                    "--locked",
                    tool.name,
                    "--version",
                    tool.version,
                ]));
            }
        }
    }

    let (_, toolchains, _) = capture(&mut rustup(&["toolchain", "list"]));
    if toolchains.lines().any(|l| l.starts_with(FUZZ_TOOLCHAIN)) {
        println!("rustup toolchain {FUZZ_TOOLCHAIN}: present (for cargo-fuzz)");
    } else {
        ok &= run(&mut rustup(&[
            "toolchain",
            "install",
            FUZZ_TOOLCHAIN,
            "--profile",
            "minimal",
        ]));
    }
    ok
}

/// `cargo cinstall` (cargo-c) of the C library into `target/cinstall/root` with prefix `/usr`:
/// checks that the static and shared libraries, `deform_kernel.pc` and the checked-in header
/// (byte-identical) are installed, then compiles `ffi/examples/mesh_basics.c` with the flags
/// `pkg-config` gives for the staged tree, links it to the shared library and runs it.
fn cinstall(ctx: &Ctx) -> bool {
    let base = ctx.root.join("target").join("cinstall");
    let root = base.join("root");
    let _ = std::fs::remove_dir_all(&root);
    let mut cmd = ctx.cargo(&[
        "cinstall",
        "-p",
        FFI_PACKAGE,
        "--release",
        "--prefix",
        "/usr",
        "--libdir",
        "/usr/lib",
    ]);
    cmd.arg("--destdir")
        .arg(&root)
        .arg("--target-dir")
        .arg(base.join("build"));
    if !run(&mut cmd) {
        return false;
    }
    let lib = root.join("usr/lib");
    let header = root.join("usr/include/deform_kernel.h");
    let mut ok = true;
    for f in [
        lib.join("libdeform_kernel.a"),
        lib.join("libdeform_kernel.so"),
        lib.join("pkgconfig/deform_kernel.pc"),
        header.clone(),
    ] {
        if !f.exists() {
            println!("xtask: cargo cinstall did not install {}", f.display());
            ok = false;
        }
    }
    let checked_in = ctx.root.join("ffi/include/deform_kernel.h");
    if std::fs::read(&header).ok() != std::fs::read(&checked_in).ok() {
        println!("xtask: the installed header differs from ffi/include/deform_kernel.h");
        ok = false;
    }
    if !ok {
        return false;
    }
    let mut pc = Command::new("pkg-config");
    pc.args(["--cflags", "--libs", "deform_kernel"])
        .env("PKG_CONFIG_PATH", lib.join("pkgconfig"))
        .env("PKG_CONFIG_SYSROOT_DIR", &root);
    let (found, flags, err) = capture(&mut pc);
    println!("$ {} -> {}", show(&pc), flags.trim());
    if !found {
        print!("{err}");
        return false;
    }
    let exe = base.join("mesh_basics");
    let mut cc = Command::new("gcc");
    cc.args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg(ctx.root.join("ffi/examples/mesh_basics.c"))
        .args(flags.split_whitespace())
        .arg("-o")
        .arg(&exe);
    if !run(&mut cc) {
        return false;
    }
    let mut prog = Command::new(&exe);
    prog.env("LD_LIBRARY_PATH", &lib);
    let (ran, out, err) = capture(&mut prog);
    if !ran || !out.starts_with("offsets ") {
        println!("xtask: the installed-library build of mesh_basics failed:\n{out}{err}");
        return false;
    }
    println!("cinstall: mesh_basics built with pkg-config against the installed tree and ran");
    true
}

fn is_root() -> bool {
    let (ok, out, _) = capture(Command::new("id").arg("-u"));
    ok && out.trim() == "0"
}

// ---------------------------------------------------------------------------------------------
// cross builds and the panic check

/// Builds the kernel for `target` with no features, each feature alone, and all features.
fn cross_build(ctx: &Ctx, target: &str) -> bool {
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

/// `cargo build --release -p panic-check <extra>` in target-tests/.
fn panic_check_cmd(ctx: &Ctx, extra: &[&str]) -> Command {
    let mut args = vec!["build", "--release", "-p", "panic-check"];
    args.extend_from_slice(extra);
    ctx.cargo_tt(&args)
}

/// The panic check must link, with the default feature set and with `micromath`. On failure
/// the surviving panic paths are located and printed.
fn panic_check(ctx: &Ctx) -> bool {
    unreferenced_entry_points(ctx);
    let mut ok = true;
    for extra in [&[][..], &["--features", "micromath"][..]] {
        let mut cmd = panic_check_cmd(ctx, extra);
        println!("$ {}", show(&cmd));
        let (linked, stdout, stderr) = capture(&mut cmd);
        print!("{stdout}");
        eprint!("{stderr}");
        if !linked {
            ok = false;
            if stderr.contains(PANIC_SYMBOL) {
                println!(
                    "xtask: PANIC PATH SURVIVED: some code called by target-tests/panic-check can \
                     panic. Locating it (cargo xtask panic-locate):"
                );
                panic_locate(ctx, extra);
            } else {
                println!("xtask: panic-check failed to build for another reason (see above)");
            }
        }
    }
    ok
}

/// Warns (does not fail) about kernel `pub fn`s whose name appears nowhere in
/// `target-tests/panic-check/src`: they are probably not proven panic-free yet. A heuristic:
/// names are matched as words, and a `pub fn` in a private module is listed too.
fn unreferenced_entry_points(ctx: &Ctx) {
    let mut kernel = Vec::new();
    rust_files(&ctx.root.join("kernel").join("src"), &mut kernel);
    let mut checks = Vec::new();
    rust_files(
        &ctx.target_tests.join("panic-check").join("src"),
        &mut checks,
    );
    let check_text: String = checks
        .iter()
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .collect::<Vec<_>>()
        .join("\n");
    let words: std::collections::BTreeSet<&str> = check_text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .collect();
    let mut missing = Vec::new();
    for file in &kernel {
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        let mut in_tests = false;
        for line in text.lines() {
            let t = line.trim_start();
            if t.starts_with("#[cfg(test)]") {
                in_tests = true;
            }
            if in_tests {
                continue;
            }
            let Some(rest) = t
                .strip_prefix("pub fn ")
                .or_else(|| t.strip_prefix("pub const fn "))
            else {
                continue;
            };
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && !words.contains(name.as_str()) {
                let rel = file.strip_prefix(&ctx.root).unwrap_or(file);
                missing.push(format!("{}: {name}", rel.display()));
            }
        }
    }
    if missing.is_empty() {
        println!("every kernel `pub fn` name appears in target-tests/panic-check/src");
    } else {
        println!(
            "warning: {} kernel `pub fn`(s) not referenced by target-tests/panic-check/src \
             (not proven panic-free):",
            missing.len()
        );
        for m in missing {
            println!("    {m}");
        }
    }
}

/// Every `.rs` file under `dir`, sorted.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension() == Some(OsStr::new("rs")) {
            out.push(p);
        }
    }
}

/// The deliberately panicking variant must fail to link, and for the right reason: the
/// undefined panic symbol.
fn panic_check_deliberate(ctx: &Ctx) -> bool {
    let mut cmd = panic_check_cmd(ctx, &["--features", "deliberate-panic"]);
    println!("$ {}", show(&cmd));
    let (linked, _, stderr) = capture(&mut cmd);
    let reason: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(PANIC_SYMBOL) && l.contains("undefined"))
        .collect();
    if linked {
        println!(
            "xtask: the deliberately panicking variant LINKED: the panic check proves nothing"
        );
        false
    } else if reason.is_empty() {
        eprint!("{stderr}");
        println!(
            "xtask: the deliberate-panic variant failed, but not on `{PANIC_SYMBOL}` (see above)"
        );
        false
    } else {
        for l in reason {
            println!("    {}", l.trim());
        }
        println!("xtask: as expected, the deliberate panic path kept `{PANIC_SYMBOL}` referenced");
        true
    }
}

/// Path of a tool from the `llvm-tools` rustup component.
fn llvm_tool(ctx: &Ctx, name: &str) -> Option<PathBuf> {
    let (ok, sysroot, _) = capture(
        Command::new("rustc")
            .args(["--print", "sysroot"])
            .current_dir(&ctx.target_tests),
    );
    let (ok2, vv, _) = capture(Command::new("rustc").arg("-vV"));
    let host = vv
        .lines()
        .find_map(|l| l.strip_prefix("host: "))?
        .trim()
        .to_string();
    if !(ok && ok2) {
        return None;
    }
    let p = Path::new(sysroot.trim())
        .join("lib")
        .join("rustlib")
        .join(host)
        .join("bin")
        .join(name);
    p.exists().then_some(p)
}

/// Builds panic-check with `locate` (panic handler defined, so it links), disassembles it, and
/// prints every function that calls into the panic machinery, with the source lines of the
/// calls. `extra` are further cargo arguments (features).
fn panic_locate(ctx: &Ctx, extra: &[&str]) -> bool {
    let mut features = String::from("locate");
    let mut rest = Vec::new();
    let mut it = extra.iter();
    while let Some(a) = it.next() {
        if *a == "--features" {
            if let Some(f) = it.next() {
                features.push(',');
                features.push_str(f);
            }
        } else {
            rest.push(*a);
        }
    }
    let mut args = vec!["--features", features.as_str()];
    args.extend(rest);
    if !run(&mut panic_check_cmd(ctx, &args)) {
        return false;
    }
    let Some(objdump) = llvm_tool(ctx, "llvm-objdump") else {
        println!("xtask: llvm-objdump not found (rustup component add llvm-tools)");
        return false;
    };
    let target_dir = env::var_os("CARGO_TARGET_DIR").map_or_else(
        || ctx.target_tests.join("target"),
        |d| ctx.target_tests.join(d),
    );
    let bin = target_dir
        .join(PANIC_CHECK_TARGET)
        .join("release")
        .join("panic-check");
    let (ok, dis, err) = capture(
        Command::new(&objdump)
            .args(["-d", "-C", "-l", "--no-show-raw-insn"])
            .arg(&bin),
    );
    if !ok {
        println!("xtask: llvm-objdump failed: {err}");
        return false;
    }
    let report = locate_report(&dis);
    print!("{report}");
    true
}

/// A disassembled function: name, calls `(address, source line, callee)`.
struct Func {
    name: String,
    calls: Vec<(String, String, String)>,
}

/// Parses `llvm-objdump -d -C -l` output.
fn parse_disassembly(dis: &str) -> Vec<Func> {
    let mut funcs: Vec<Func> = Vec::new();
    // Innermost source line of the current instruction, and the last one outside the
    // standard library and registry crates (the caller's line when core code is inlined).
    let mut line_info = String::new();
    let mut own_line = String::new();
    for line in dis.lines() {
        if let Some(name) = line
            .strip_suffix(">:")
            .and_then(|l| l.split_once(" <"))
            .filter(|(addr, _)| addr.chars().all(|c| c.is_ascii_hexdigit()))
            .map(|(_, n)| n)
        {
            funcs.push(Func {
                name: name.to_string(),
                calls: Vec::new(),
            });
            line_info.clear();
            own_line.clear();
            continue;
        }
        if let Some(src) = line.strip_prefix("; ") {
            line_info = src.trim().to_string();
            if !line_info.contains("/rustlib/src/") && !line_info.contains("/registry/src/") {
                own_line.clone_from(&line_info);
            }
            continue;
        }
        // `    addr:   mnemonic  operands <callee+0x..>`: any branch to another function.
        let t = line.trim_start();
        let Some((addr, insn)) = t.split_once(':') else {
            continue;
        };
        if addr.is_empty() || !addr.chars().all(|c| c.is_ascii_hexdigit()) {
            continue;
        }
        let insn = insn.trim_start();
        if !insn.starts_with('b') && !insn.starts_with("cb") && !insn.starts_with('j') {
            continue;
        }
        let (Some(open), Some(close)) = (insn.find('<'), insn.rfind('>')) else {
            continue;
        };
        if close <= open {
            continue;
        }
        let target = &insn[open + 1..close];
        let callee = target.split("+0x").next().unwrap_or(target);
        if let Some(f) = funcs.last_mut() {
            if callee != f.name {
                let src = if own_line.is_empty() || own_line == line_info {
                    line_info.clone()
                } else {
                    format!("{line_info}\n          near {own_line}")
                };
                f.calls.push((addr.to_string(), src, callee.to_string()));
            }
        }
    }
    funcs
}

/// The functions that reach the panic handler, kernel and test code first.
fn locate_report(dis: &str) -> String {
    let funcs = parse_disassembly(dis);
    let mut bad: Vec<String> = vec![
        PANIC_SYMBOL.into(),
        "__rustc::rust_begin_unwind".into(),
        "rust_begin_unwind".into(),
    ];
    loop {
        let mut changed = false;
        for f in &funcs {
            if !bad.contains(&f.name) && f.calls.iter().any(|c| bad.contains(&c.2)) {
                bad.push(f.name.clone());
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let is_core = |n: &str| {
        n.starts_with("core::")
            || n.starts_with("<core::")
            || n.starts_with("__rustc::")
            || n == "rust_begin_unwind"
            || n == PANIC_SYMBOL
    };
    let mut out = String::new();
    let mut found = false;
    for f in funcs
        .iter()
        .filter(|f| bad.contains(&f.name) && !is_core(&f.name))
    {
        let direct: Vec<&(String, String, String)> = f
            .calls
            .iter()
            .filter(|c| bad.contains(&c.2) && is_core(&c.2))
            .collect();
        if direct.is_empty() {
            continue;
        }
        found = true;
        let _ = writeln!(out, "  {}", f.name);
        for (addr, src, callee) in direct {
            let _ = writeln!(out, "      0x{addr}  {callee}\n          at {src}");
        }
    }
    if !found {
        let _ = writeln!(
            out,
            "  no direct caller of the panic machinery found outside core: the panic is \
             reached through a function pointer (e.g. a core::fmt Debug impl) or from core itself"
        );
        for f in funcs.iter().filter(|f| bad.contains(&f.name)) {
            let _ = writeln!(out, "    reaches the handler: {}", f.name);
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// on-target suite

/// Runs the defmt-test suite under QEMU and prints `on-target: N passed, N failed`, counted
/// from defmt-test's `(i/n) running ...` and `all tests passed!` lines (it prints no summary).
fn on_target(ctx: &Ctx) -> bool {
    // --no-fail-fast: every test binary runs even after one fails, so the counts are complete.
    let mut cmd = ctx.cargo_tt(&[
        "test",
        "--release",
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
fn count_defmt_tests(out: &str) -> (usize, usize) {
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
const FOOTPRINT_FEATURE_SETS: &[(&str, &str)] = &[
    ("none", ""),
    ("micromath", "micromath"),
    ("defmt", "kernel-defmt"),
    ("all", "micromath,kernel-defmt,glam"),
];

/// Builds `target-tests/footprint` once per kernel feature set and prints its `llvm-size`
/// (flash = text + data, RAM = data + bss), then runs the default build under QEMU: a 1,000-node
/// deformation inside 64 KiB of RAM, with the painted-stack peak of each main entry point.
/// Fails when a build fails, llvm-size is missing, or the run fails (does not fit, a check
/// fails, a stack overflow is detected).
fn footprint(ctx: &Ctx) -> bool {
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
    println!("  (bss holds the caller's buffers of the 1,000-node run; the stack is on top)");
    println!();
    let mut cmd = ctx.cargo_tt(&["run", "--release", "-p", "deform-footprint"]);
    ok &= run(&mut cmd);
    ok
}

// ---------------------------------------------------------------------------------------------
// fuzzing

/// `cargo xtask fuzz [--seconds N] [--target NAME]`.
fn fuzz_command(ctx: &Ctx, args: &[String]) -> ExitCode {
    let mut seconds = 600u64;
    let mut target = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match (a.as_str(), it.next()) {
            ("--seconds", Some(v)) => match v.parse() {
                Ok(n) => seconds = n,
                Err(_) => {
                    eprintln!("xtask: --seconds takes a whole number");
                    return ExitCode::from(2);
                }
            },
            ("--target", Some(v)) => target = Some(v.clone()),
            _ => {
                eprintln!("xtask: usage: cargo xtask fuzz [--seconds N] [--target NAME]");
                return ExitCode::from(2);
            }
        }
    }
    if fuzz(ctx, seconds, target.as_deref()) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Builds the fuzz targets with cargo-fuzz on nightly and runs each (or `only`) for `seconds`,
/// starting from the committed seeds; `true` when nothing crashed.
fn fuzz(ctx: &Ctx, seconds: u64, only: Option<&str>) -> bool {
    let dir = ctx.root.join("fuzz");
    let fuzz_cmd = |args: &[&str]| {
        let mut c = Command::new("cargo");
        c.arg(format!("+{FUZZ_TOOLCHAIN}"))
            .arg("fuzz")
            .args(args)
            .current_dir(&dir)
            .env_remove("RUSTUP_TOOLCHAIN")
            .env_remove("CARGO");
        c
    };
    if !run(&mut fuzz_cmd(&["build", "-O"])) {
        return false;
    }
    let (ok, list, _) = capture(&mut fuzz_cmd(&["list"]));
    if !ok {
        return false;
    }
    let targets: Vec<&str> = list
        .lines()
        .map(str::trim)
        .filter(|t| !t.is_empty() && only.is_none_or(|o| o == *t))
        .collect();
    if targets.is_empty() {
        println!("xtask: no fuzz target matches");
        return false;
    }
    let mut all_ok = true;
    let mut summary = String::new();
    for t in &targets {
        let corpus = dir.join("corpus").join(t);
        let seeds = dir.join("seeds").join(t);
        let _ = std::fs::create_dir_all(&corpus);
        let mut args: Vec<String> = vec![
            "run".into(),
            "-O".into(),
            (*t).into(),
            corpus.display().to_string(),
        ];
        if seeds.is_dir() {
            args.push(seeds.display().to_string());
        }
        args.push("--".into());
        args.push(format!("-max_total_time={seconds}"));
        args.push("-print_final_stats=1".into());
        let dict = dir.join("dicts").join(format!("{t}.dict"));
        if dict.is_file() {
            args.push(format!("-dict={}", dict.display()));
        }
        let argv: Vec<&str> = args.iter().map(String::as_str).collect();
        let mut cmd = fuzz_cmd(&argv);
        println!("$ {}", show(&cmd));
        let (ok, stdout, stderr) = capture(&mut cmd);
        let text = format!("{stdout}{stderr}");
        let execs = text
            .lines()
            .find_map(|l| l.strip_prefix("stat::number_of_executed_units:"))
            .map_or("?".to_string(), |v| v.trim().to_string());
        if !ok {
            print!("{text}");
        }
        let _ = writeln!(
            summary,
            "fuzz {t}: {} after {execs} executions in {seconds} s",
            if ok {
                "no findings"
            } else {
                "FAILED (see the output above)"
            }
        );
        all_ok &= ok;
    }
    print!("{summary}");
    all_ok
}
