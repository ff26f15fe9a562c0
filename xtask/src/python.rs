//! The Python package (python/, PyO3 + maturin): its venv and its CI step.
//!
//! The crate `deform-kernel-python` has its own manifest (not a member of the root workspace),
//! so `cargo test --workspace`, clippy and doc never compile PyO3; it builds into
//! `target/python` with the venv's pinned maturin.

use crate::ctx::Ctx;
use crate::process::run;
use std::path::PathBuf;
use std::process::Command;

/// The venv of the Python step.
fn venv(ctx: &Ctx) -> PathBuf {
    ctx.root.join("target").join("python-venv")
}

/// Creates `target/python-venv` (if missing) and installs `python/requirements-ci.txt`.
pub(crate) fn python_venv(ctx: &Ctx) -> bool {
    let venv = venv(ctx);
    let python = venv.join("bin").join("python");
    if !python.exists() && !run(Command::new("python3").args(["-m", "venv"]).arg(&venv)) {
        println!("xtask: `python3 -m venv` failed (Debian: apt-get install python3-venv)");
        return false;
    }
    let requirements = ctx.root.join("python").join("requirements-ci.txt");
    run(Command::new(&python)
        .args(["-m", "pip", "install", "-q", "-r"])
        .arg(requirements))
}

/// `cargo xtask ci --step python`: rustfmt and clippy on the crate, the `deform` tool (for the
/// bit-equality tests), the wheel built by maturin and installed into the venv, the examples,
/// then pytest.
/// The wheel is built in the dev profile (quicker to compile; the bits are the same as release,
/// which `pip install ./python` builds). Clippy has its own target directory: maturin sets
/// PyO3's environment differently, and in a shared one each would rebuild PyO3 for the other.
pub(crate) fn python_step(ctx: &Ctx) -> bool {
    let venv = venv(ctx);
    if !venv.join("bin").join("maturin").exists() && !python_venv(ctx) {
        return false;
    }
    let manifest = ["--manifest-path", "python/Cargo.toml"];
    let target = ctx.root.join("target").join("python");
    let wheels = target.join("wheels");
    let mut ok = run(ctx.cargo(&["fmt", "--check"]).args(manifest));
    ok &= run(ctx
        .cargo(&["clippy", "--all-targets"])
        .args(manifest)
        .args(["--", "-D", "warnings"])
        .env(
            "CARGO_TARGET_DIR",
            ctx.root.join("target").join("python-clippy"),
        )
        .env("PYO3_PYTHON", venv.join("bin").join("python")));
    ok &= run(&mut ctx.cargo(&["build", "-p", "deform-cli", "--bin", "deform"]));
    let _ = std::fs::remove_dir_all(&wheels);
    ok &= run(Command::new(venv.join("bin").join("maturin"))
        .args(["build", "-m", "python/Cargo.toml", "--interpreter"])
        .arg(venv.join("bin").join("python"))
        .arg("--out")
        .arg(&wheels)
        .current_dir(&ctx.root)
        .env("CARGO_TARGET_DIR", &target));
    ok &= run(Command::new(venv.join("bin").join("python"))
        .args([
            "-m",
            "pip",
            "install",
            "-q",
            "--force-reinstall",
            "--no-deps",
        ])
        .args(["--no-index", "--find-links"])
        .arg(&wheels)
        .arg("deform-kernel"));
    let python = venv.join("bin").join("python");
    let example = |name: &str| {
        run(Command::new(&python)
            .arg(format!("python/examples/{name}"))
            .current_dir(&ctx.root))
    };
    ok && example("pitch_body.py")
        && example("pitch_airfoil.py")
        && run(Command::new(&python)
            .args(["-m", "pytest", "-q", "python/tests"])
            .current_dir(&ctx.root)
            .env(
                "DEFORM_BIN",
                ctx.root.join("target").join("debug").join("deform"),
            )
            .env("DEFORM_REQUIRE_CLI", "1"))
}
