//! Step 5 of `cargo xtask bench` (issue 32): a 234k-node spring move through the Python
//! package against the same move in the Rust tool.
//!
//! The release wheel is built by the pinned maturin (`python/requirements-ci.txt`) into
//! `target/python-release`, installed into the bench venv, and `bench/python/deform_vs_cli.py`
//! times `deform_kernel.deform` on numpy arrays against the seconds `deform --json move`
//! reports for the same move (the engine's work: input, renumbering, solve, quality; not the
//! file reading and writing, which the Python call does not do) and checks the bits.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use crate::ctx::Ctx;
use crate::process::run;

/// The pinned `maturin==X` line of the Python step's requirements.
fn maturin_pin(ctx: &Ctx) -> Option<String> {
    let reqs = std::fs::read_to_string(ctx.root.join("python").join("requirements-ci.txt")).ok()?;
    reqs.lines()
        .map(str::trim)
        .find(|l| l.starts_with("maturin=="))
        .map(str::to_string)
}

/// Builds the release wheel and installs it (and maturin) into the bench venv.
fn install_wheel(ctx: &Ctx, python: &Path) -> bool {
    let Some(pin) = maturin_pin(ctx) else {
        eprintln!("xtask bench: no maturin pin in python/requirements-ci.txt");
        return false;
    };
    let target = ctx.root.join("target").join("python-release");
    let wheels = target.join("wheels");
    let _ = std::fs::remove_dir_all(&wheels);
    let maturin = python.with_file_name("maturin");
    run(Command::new(python).args(["-m", "pip", "install", "--quiet", &pin]))
        && run(Command::new(maturin)
            .args([
                "build",
                "--release",
                "-m",
                "python/Cargo.toml",
                "--interpreter",
            ])
            .arg(python)
            .arg("--out")
            .arg(&wheels)
            .current_dir(&ctx.root)
            .env("CARGO_TARGET_DIR", &target))
        && run(Command::new(python)
            .args([
                "-m",
                "pip",
                "install",
                "--quiet",
                "--force-reinstall",
                "--no-deps",
            ])
            .args(["--no-index", "--find-links"])
            .arg(&wheels)
            .arg("deform-kernel"))
}

/// Runs the comparison; its report row, or `None` when a step failed or the bits differ.
pub(super) fn row(
    ctx: &Ctx,
    python: &Path,
    dir: &Path,
    deform: &Path,
    quick: bool,
) -> Option<String> {
    if !install_wheel(ctx, python) {
        return None;
    }
    let figures = dir.join("python.txt");
    let script = ctx
        .root
        .join("bench")
        .join("python")
        .join("deform_vs_cli.py");
    let mut c = super::peers_command(python, &script);
    c.arg("--deform").arg(deform).arg("--figures").arg(&figures);
    c.args([
        "--method",
        "spring",
        "--repeat",
        if quick { "1" } else { "3" },
    ]);
    if quick {
        c.args(["--n", "201"]);
    }
    if !run(&mut c) {
        eprintln!("xtask bench: deform_vs_cli.py failed (or its bits differ from the tool's)");
        return None;
    }
    Some(format_row(&super::read_figures(&figures)))
}

/// The report's row: the Python call's time against the tool's own move time.
fn format_row(f: &BTreeMap<String, String>) -> String {
    let get = |k: &str| f.get(k).and_then(|v| v.parse::<f64>().ok());
    let (py, tool) = (get("python_call_s"), get("python_tool_move_s"));
    let ratio = match (py, tool) {
        (Some(p), Some(t)) if t > 0.0 => format!("{:.2}", p / t),
        _ => "—".into(),
    };
    let s = |v: Option<f64>| v.map_or_else(|| "—".into(), |v| format!("{v:.3} s"));
    format!(
        "| spring move through Python, {} nodes: `deform_kernel.deform` on numpy arrays (with `out=`: {}), same bits | {} | the same move in the Rust tool {} (whole command {}) | {} | ≤ 1.10 |\n",
        f.get("python_nodes").map_or("—", String::as_str),
        s(get("python_call_out_s")),
        s(py),
        s(tool),
        s(get("python_tool_wall_s")),
        ratio
    )
}
