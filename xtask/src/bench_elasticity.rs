//! Step 5 of `cargo xtask bench` (issue 28 item 4): linear elasticity, the kernel's assembly,
//! rigid-mode smoothed aggregation and CG (`bench/src/elasticity.rs`, figures in
//! `kernel.txt`) against scikit-fem assembly, pyamg `smoothed_aggregation_solver(A,
//! B=rigid_modes)` and CG (`bench/peers/elasticity.py`, figures in `peers_elasticity.txt`) on
//! the same 2D and 3D meshes, to the same relative residual (1e-8). Goals: at most 0.5× the
//! peer's time, iterations within 1.5× of pyamg's. Beside it the other method of issue 28,
//! RBF: the kernel's thin-plate spline with every boundary node a centre on the NACA mesh
//! (`bench/src/rbf.rs`) against scipy's `RBFInterpolator` on the same centres
//! (`bench/peers/rbf.py`, figures in `peers_rbf.txt`).

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use crate::bench::{cpu_model, load_average, num, peers_command, peers_python, read_figures};
use crate::ctx::Ctx;
use crate::process::run;

/// Runs the peer scripts (elasticity, RBF) on the inputs step 1 wrote to `dir`.
pub(crate) fn peer(ctx: &Ctx, python: &Path, dir: &Path) -> bool {
    let peers = ctx.root.join("bench").join("peers");
    let quick = read_figures(&dir.join("kernel.txt"))
        .get("quick")
        .map(String::as_str)
        == Some("true");
    run(peers_command(python, &peers.join("elasticity.py")).arg(dir))
        && run(peers_command(python, &peers.join("rbf.py"))
            .arg(dir)
            .arg(if quick { "3" } else { "1" }))
}

/// The RBF row: fit + evaluation of each side, the ratio, the agreement.
fn rbf_row(dir: &Path) -> String {
    let k = read_figures(&dir.join("kernel.txt"));
    let p = read_figures(&dir.join("peers_rbf.txt"));
    let get = |m: &std::collections::BTreeMap<String, String>, key: &str| {
        m.get(key).cloned().unwrap_or_else(|| "—".into())
    };
    let secs = |m, key: &str| num(m, key).map_or("—".into(), |v| format!("{v:.3} s"));
    let ratio = match (num(&k, "rbf_s"), num(&p, "rbf_scipy_s")) {
        (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
        _ => "—".into(),
    };
    format!(
        "| RBF, NACA 2412 {} nodes, {} centres (every boundary node), thin-plate spline + linear polynomial: fit + evaluation | `rbf_deform` {} | scipy `RBFInterpolator` {} (fit {}, evaluation {}) | {ratio} (displacements differ by {} of the largest) | — |\n",
        get(&k, "rbf_nodes"),
        get(&k, "rbf_centres"),
        secs(&k, "rbf_s"),
        secs(&p, "rbf_scipy_s"),
        secs(&p, "rbf_scipy_fit_s"),
        secs(&p, "rbf_scipy_evaluate_s"),
        get(&p, "rbf_max_relative_difference"),
    )
}

/// The report's rows: time and iterations of each side, the ratio, the agreement.
pub(crate) fn rows(dir: &Path) -> String {
    let k = read_figures(&dir.join("kernel.txt"));
    let p = read_figures(&dir.join("peers_elasticity.txt"));
    let mut s = String::new();
    for (tag, what) in [
        ("elastic2d", "P1 triangles, plane strain"),
        ("elastic3d", "Q1 hexahedra"),
    ] {
        let get = |m: &std::collections::BTreeMap<String, String>, key: &str| {
            m.get(&format!("{tag}_{key}"))
                .cloned()
                .unwrap_or_else(|| "—".into())
        };
        let sum = |m, keys: [&str; 3]| {
            keys.iter()
                .map(|key| num(m, &format!("{tag}_{key}")))
                .sum::<Option<f64>>()
        };
        let kt = sum(&k, ["assembly_s", "amg_setup_s", "solve_s"]);
        let pt = sum(&p, ["skfem_assembly_s", "pyamg_setup_s", "pyamg_solve_s"]);
        let secs = |m, key: &str| {
            num(m, &format!("{tag}_{key}")).map_or("—".into(), |v| format!("{v:.3}"))
        };
        let total = |v: Option<f64>| v.map_or("—".into(), |v| format!("{v:.3} s"));
        let ratio = match (kt, pt) {
            (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
            _ => "—".into(),
        };
        let it_ratio = match (
            num(&k, &format!("{tag}_iterations")),
            num(&p, &format!("{tag}_pyamg_iterations")),
        ) {
            (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
            _ => "—".into(),
        };
        let _ = writeln!(
            s,
            "| elasticity, {} nodes, {what}, E = 1/V, ν = 0.3, to 1e-8: assembly + setup + solve | rigid-mode SA-CG {} ({} + {} + {}, {} it., {} levels) | scikit-fem + pyamg SA(B = rigid modes)-CG {} ({} + {} + {}, {} it., {} levels) | {ratio} (iterations {it_ratio}; solutions differ by {} of the largest displacement) | ≤ 0.5 (iterations ≤ 1.5) |",
            get(&k, "nodes"),
            total(kt),
            secs(&k, "assembly_s"),
            secs(&k, "amg_setup_s"),
            secs(&k, "solve_s"),
            get(&k, "iterations"),
            get(&k, "levels"),
            total(pt),
            secs(&p, "skfem_assembly_s"),
            secs(&p, "pyamg_setup_s"),
            secs(&p, "pyamg_solve_s"),
            get(&p, "pyamg_iterations"),
            get(&p, "pyamg_levels"),
            get(&p, "max_relative_difference"),
        );
    }
    s + &rbf_row(dir)
}

/// `--elasticity-only`: the kernel side (`--only elasticity,rbf`) and the peers in `dir`, the
/// rows as the report (`dir/report.md`).
pub(crate) fn alone(ctx: &Ctx, dir: &Path, quick: bool, load_before: &str) -> ExitCode {
    if std::fs::create_dir_all(dir).is_err() {
        eprintln!("xtask bench: cannot create {}", dir.display());
        return ExitCode::FAILURE;
    }
    let manifest = ctx.root.join("bench").join("Cargo.toml");
    let mut c = ctx.cargo(&["run", "--release", "--manifest-path"]);
    c.arg(&manifest)
        .args(["--", "--only", "elasticity,rbf", "--out"])
        .arg(dir);
    if quick {
        c.arg("--quick");
    }
    if !run(&mut c) {
        return ExitCode::FAILURE;
    }
    let Some(python) = peers_python(ctx) else {
        return ExitCode::FAILURE;
    };
    if !peer(ctx, &python, dir) {
        return ExitCode::FAILURE;
    }
    let report = format!(
        "## `cargo xtask bench --elasticity-only{}`\n\n{}; load average before {load_before}, after {}. \
         Kernel and peers single-threaded.\n\n\
         | work | kernel | peer | ratio (kernel ÷ peer) | target |\n|---|---|---|---|---|\n{}",
        if quick { " --quick" } else { "" },
        cpu_model(),
        load_average(),
        rows(dir)
    );
    print!("\n{report}");
    let path = dir.join("report.md");
    if std::fs::write(&path, &report).is_err() {
        eprintln!("xtask bench: cannot write {}", path.display());
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
