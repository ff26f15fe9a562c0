//! `cargo xtask bench`: the kernel against the peers a user would otherwise pick, on the same
//! generated inputs, in one run (issue 14 item 9). Not part of `cargo xtask ci`: speed is
//! measured, never asserted.
//!
//! 1. `bench/` (its own workspace, release + LTO) times the kernel on the issue's sizes and
//!    writes the inputs and its results to `target/bench/`;
//! 2. `bench/peers/peers.py` (in a venv under `target/bench-venv`, pinned requirements) times
//!    numpy/scipy, scipy.ndimage, trimesh and pyamg on those very inputs and checks that their
//!    answers agree with the kernel's;
//! 3. the release `deform` tool moves the 234k-node NACA 2412 mesh with the spring and the
//!    quaternion method (wall time, peak resident memory), and runs `deform adjoint` of each
//!    method it differentiates on the same mesh ([`sensitivity_cost`]);
//! 4. `bench/peers/unordered.py` writes meshes numbered as users have them (the NACA mesh
//!    randomly permuted; a gmsh tetrahedral mesh in gmsh's numbering) and times the whole
//!    `deform move` (`--renumber off` and `auto`) against pyamg setup + solve of the same
//!    spring system (issue 34);
//! 5. `bench/python/deform_vs_cli.py` times a 234k-node spring move through the Python package
//!    against the same move in the tool (issue 32; [`python_call`]);
//! 6. linear elasticity (issue 28 item 4): the kernel's assembly + rigid-mode multigrid +
//!    CG (step 1) against scikit-fem assembly + pyamg `smoothed_aggregation_solver(A,
//!    B=rigid_modes)` (`bench/peers/elasticity.py`) on the same 2D and 3D meshes, and RBF
//!    (thin-plate spline, every boundary node a centre) against scipy's `RBFInterpolator`
//!    (`bench/peers/rbf.py`) on the NACA mesh;
//! 7. the figures and ratios (kernel ÷ peer, below 1 = kernel faster) go to stdout and to
//!    `target/bench/report.md`, with the machine, the date and the load.
//!
//! `--unordered-only` runs step 4 alone (with the NACA mesh it needs), `--python-only` step 5,
//! `--elasticity-only` step 6 (in `target/bench/elasticity/`; with `--quick`, 3 600 and
//! 2 744 nodes instead of 202 500 and 205 379).

mod python_call;
mod sensitivity_cost;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, ExitCode};
use std::time::{Duration, Instant};

use crate::ctx::Ctx;
use crate::process::run;

/// `name value` lines of a figures file.
pub(crate) fn read_figures(path: &Path) -> BTreeMap<String, String> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| l.split_once(' '))
        .map(|(k, v)| (k.to_string(), v.trim().to_string()))
        .collect()
}

pub(crate) fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

pub(crate) fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into())
}

/// Peak resident set (kB) of a child, read from `/proc/<pid>/status` (`VmHWM`, the high-water
/// mark) every 5 ms until it exits; the last reading before the exit is reported.
fn run_measured(cmd: &mut Command) -> Option<(Duration, u64, bool)> {
    let t = Instant::now();
    let mut child = cmd.spawn().ok()?;
    let status_path = format!("/proc/{}/status", child.id());
    let mut peak = 0u64;
    loop {
        if let Ok(s) = std::fs::read_to_string(&status_path) {
            if let Some(kb) = s
                .lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<u64>().ok())
            {
                peak = peak.max(kb);
            }
        }
        if let Ok(Some(status)) = child.try_wait() {
            return Some((t.elapsed(), peak, status.success()));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// Median of the wall times, and the largest peak memory, of `reps` runs.
fn move_figures(
    deform: &Path,
    dir: &Path,
    mesh: &Path,
    method: &str,
    reps: usize,
) -> Option<(f64, u64)> {
    let mut times = Vec::new();
    let mut peak = 0;
    for _ in 0..reps {
        let out = dir.join(format!("moved_{method}.su2"));
        let mut c = Command::new(deform);
        c.args(["--json", "move"])
            .arg(mesh)
            .args([
                "--marker", "airfoil", "--rotate", "-10", "--center", "0.25,0",
            ])
            // Linear springs invert cells at −10° on this mesh: written anyway (exit 4 otherwise).
            .args([
                "--method",
                method,
                "--tol",
                "1e-8",
                "--allow-folds",
                "--out",
            ])
            .arg(&out)
            .stdout(std::process::Stdio::null());
        let (t, kb, ok) = run_measured(&mut c)?;
        if !ok {
            eprintln!("bench: deform move --method {method} failed");
            return None;
        }
        times.push(t.as_secs_f64());
        peak = peak.max(kb);
    }
    times.sort_by(f64::total_cmp);
    Some((times[times.len() / 2], peak))
}

pub(crate) fn num(m: &BTreeMap<String, String>, k: &str) -> Option<f64> {
    m.get(k).and_then(|v| v.parse().ok())
}

/// The bench venv's Python with the pinned peers installed (created on first use).
pub(crate) fn peers_python(ctx: &Ctx) -> Option<std::path::PathBuf> {
    let venv = ctx.root.join("target").join("bench-venv");
    let python = venv.join("bin").join("python");
    if !python.exists() && !run(Command::new("python3").args(["-m", "venv"]).arg(&venv)) {
        return None;
    }
    let reqs = ctx
        .root
        .join("bench")
        .join("peers")
        .join("requirements.txt");
    run(Command::new(&python)
        .args(["-m", "pip", "install", "--quiet", "-r"])
        .arg(&reqs))
    .then_some(python)
}

/// A peers script run single-threaded: one thread for BLAS/OpenMP, as the kernel has (on a
/// shared 2-core machine idle-spinning BLAS threads slowed pyamg 40×: 20k mesh, 3.85 s
/// against 0.11 s single-threaded).
pub(crate) fn peers_command(python: &Path, script: &Path) -> Command {
    let mut c = Command::new(python);
    c.arg(script);
    for var in ["OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"] {
        c.env(var, "1");
    }
    c
}

/// Step 4: the unordered meshes (`bench/peers/unordered.py`); the report's rows, or `None`
/// when it failed.
fn unordered(ctx: &Ctx, python: &Path, dir: &Path, deform: &Path, quick: bool) -> Option<String> {
    let script = ctx.root.join("bench").join("peers").join("unordered.py");
    let mut c = peers_command(python, &script);
    c.arg(dir).arg(deform);
    if quick {
        c.arg("--quick");
    }
    if !run(&mut c) {
        return None;
    }
    std::fs::read_to_string(dir.join("unordered.md")).ok()
}

/// `cargo xtask bench [--quick] [--no-peers] [--unordered-only | --python-only |
/// --elasticity-only]`.
pub(crate) fn bench_command(ctx: &Ctx, args: &[String]) -> ExitCode {
    let quick = args.iter().any(|a| a == "--quick");
    let no_peers = args.iter().any(|a| a == "--no-peers");
    let unordered_only = args.iter().any(|a| a == "--unordered-only");
    let python_only = args.iter().any(|a| a == "--python-only");
    let elasticity_only = args.iter().any(|a| a == "--elasticity-only");
    if let Some(bad) = args.iter().find(|a| {
        !matches!(
            a.as_str(),
            "--quick" | "--no-peers" | "--unordered-only" | "--python-only" | "--elasticity-only"
        )
    }) {
        eprintln!(
            "xtask bench: unknown option `{bad}` (options: --quick, --no-peers, \
             --unordered-only, --python-only, --elasticity-only)"
        );
        return ExitCode::from(2);
    }
    let dir = ctx.root.join("target").join("bench");
    if std::fs::create_dir_all(&dir).is_err() {
        eprintln!("xtask bench: cannot create {}", dir.display());
        return ExitCode::FAILURE;
    }
    let load_before = load_average();
    let started = Instant::now();

    if unordered_only || python_only {
        return alone(ctx, &dir, quick, python_only, &load_before);
    }
    if elasticity_only {
        return crate::bench_elasticity::alone(ctx, &dir.join("elasticity"), quick, &load_before);
    }

    // 1. The kernel.
    let manifest = ctx.root.join("bench").join("Cargo.toml");
    let mut c = ctx.cargo(&["run", "--release", "--manifest-path"]);
    c.arg(&manifest).args(["--", "--out"]).arg(&dir);
    if quick {
        c.arg("--quick");
    }
    if !run(&mut c) {
        return ExitCode::FAILURE;
    }

    // 2. The peers.
    let python = if no_peers {
        None
    } else {
        let Some(python) = peers_python(ctx) else {
            return ExitCode::FAILURE;
        };
        let script = ctx.root.join("bench").join("peers").join("peers.py");
        if !run(peers_command(&python, &script).arg(&dir)) {
            return ExitCode::FAILURE;
        }
        Some(python)
    };

    // 3. The deform tool on the NACA 2412 mesh.
    let Some((deform, mesh)) = deform_and_naca(ctx, &dir, quick) else {
        return ExitCode::FAILURE;
    };
    let reps = if quick { 1 } else { 3 };
    let spring = move_figures(&deform, &dir, &mesh, "spring", reps);
    let quaternion = move_figures(&deform, &dir, &mesh, "quaternion", reps);
    let moves = [("spring", spring), ("quaternion", quaternion)].map(|(m, f)| (m, f.map(|f| f.0)));
    let adjoint_rows = sensitivity_cost::rows(&deform, &dir, &mesh, moves, reps);

    // 4. The unordered meshes; 5. the Python package; 6. linear elasticity (its kernel
    // figures are in kernel.txt).
    let mut rows = adjoint_rows;
    if let Some(python) = &python {
        let Some(unordered_rows) = unordered(ctx, python, &dir, &deform, quick) else {
            return ExitCode::FAILURE;
        };
        let Some(python_row) = python_call::row(ctx, python, &dir, &deform, quick) else {
            return ExitCode::FAILURE;
        };
        rows += &unordered_rows;
        rows += &python_row;
        if !crate::bench_elasticity::peer(ctx, python, &dir) {
            return ExitCode::FAILURE;
        }
    }
    rows.push_str(&crate::bench_elasticity::rows(&dir));

    let k = read_figures(&dir.join("kernel.txt"));
    let p = read_figures(&dir.join("peers.txt"));
    let report = report(&k, &p, (spring, quaternion), &rows, quick, &load_before);
    print!("\n{report}");
    let path = dir.join("report.md");
    if std::fs::write(&path, &report).is_err() {
        eprintln!("xtask bench: cannot write {}", path.display());
        return ExitCode::FAILURE;
    }
    println!(
        "\nwrote {} ({:.0} s in all)",
        path.display(),
        started.elapsed().as_secs_f64()
    );
    ExitCode::SUCCESS
}

/// A `deform move`'s median wall time and peak memory (kB), when it ran.
type MoveFigures = Option<(f64, u64)>;

/// The Markdown report: machine, load, figures and ratios against the issue's targets.
fn report(
    k: &BTreeMap<String, String>,
    p: &BTreeMap<String, String>,
    (spring, quaternion): (MoveFigures, MoveFigures),
    unordered_rows: &str,
    quick: bool,
    load_before: &str,
) -> String {
    let mut s = String::new();
    let cores = std::thread::available_parallelism().map_or(0, usize::from);
    let date = Command::new("date")
        .args(["-u", "+%Y-%m-%d %H:%M UTC"])
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let _ = writeln!(
        s,
        "## `cargo xtask bench{}`",
        if quick { " --quick" } else { "" }
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{date}; {} ({cores} cores); load average before {load_before}, after {}. \
         Kernel and peers single-threaded (peers with OPENBLAS/OMP/MKL_NUM_THREADS=1).",
        cpu_model(),
        load_average()
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "| work | kernel | peer | ratio (kernel ÷ peer) | target |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
        _ => "—".into(),
    };
    let f = |v: Option<f64>, unit: &str| v.map_or_else(|| "—".into(), |v| format!("{v:.3} {unit}"));
    let gk = num(k, "graph_ns_per_vertex_pass");
    let gp = num(p, "graph_scipy_ns_per_vertex_pass");
    let gt = num(p, "graph_trimesh_ns_per_vertex_pass");
    let _ = writeln!(
        s,
        "| graph Taubin, {} vertices, {} passes | {} | numpy/scipy CSR {} | {} | ≤ 0.33 |",
        k.get("graph_vertices").map_or("—", String::as_str),
        k.get("graph_passes").map_or("—", String::as_str),
        f(gk, "ns/vertex-pass"),
        f(gp, "ns"),
        ratio(gk, gp)
    );
    let _ = writeln!(
        s,
        "| | | trimesh filter_taubin {} | {} | |",
        f(gt, "ns"),
        ratio(gk, gt)
    );
    let sk = num(k, "structured_ns_per_point_pass");
    let sp = num(p, "structured_ndimage_ns_per_point_pass");
    let _ = writeln!(
        s,
        "| structured Taubin, {} points, {} passes | {} | scipy.ndimage {} | {} | ≤ 0.30 |",
        k.get("structured_points").map_or("—", String::as_str),
        k.get("structured_passes").map_or("—", String::as_str),
        f(sk, "ns/point-pass"),
        f(sp, "ns"),
        ratio(sk, sp)
    );
    let ks = num(k, "spring_amg_setup_s").zip(num(k, "spring_amg_solve_s"));
    let ps = num(p, "spring_pyamg_setup_s").zip(num(p, "spring_pyamg_solve_s"));
    let total = |v: Option<(f64, f64)>| v.map(|(a, b)| a + b);
    let _ = writeln!(
        s,
        "| spring solve, {} nodes, x and y to 1e-8, setup + solve | AMG-CG {} ({} + {}, {} it.) | pyamg SA-CG {} ({} it.) | {} | ≤ 1 |",
        k.get("spring_nodes").map_or("—", String::as_str),
        f(total(ks), "s"),
        f(ks.map(|v| v.0), "s"),
        f(ks.map(|v| v.1), "s"),
        k.get("spring_amg_iterations").map_or("—", String::as_str),
        f(total(ps), "s"),
        p.get("spring_pyamg_iterations").map_or("—", String::as_str),
        ratio(total(ks), total(ps))
    );
    let cgk = num(k, "spring_cg_jacobi_s");
    let cgp = num(p, "spring_scipy_cg_jacobi_s");
    let _ = writeln!(
        s,
        "| same, CG + Jacobi | {} ({} it.) | scipy CG + Jacobi {} ({} it.) | {} | |",
        f(cgk, "s"),
        k.get("spring_cg_jacobi_iterations")
            .map_or("—", String::as_str),
        f(cgp, "s"),
        p.get("spring_scipy_cg_jacobi_iterations")
            .map_or("—", String::as_str),
        ratio(cgk, cgp)
    );
    let rk = num(k, "rotation_kernel_ns_per_point");
    let rn = num(k, "rotation_nalgebra_ns_per_point");
    let _ = writeln!(
        s,
        "| rotate {} points, own quaternion each, f64 | {} | nalgebra {} | {} | ≤ 1.0 |",
        k.get("rotation_points").map_or("—", String::as_str),
        f(rk, "ns/point"),
        f(rn, "ns"),
        ratio(rk, rn)
    );
    let mv = |v: Option<(f64, u64)>| {
        v.map_or_else(
            || "—".into(),
            |(t, kb)| format!("{t:.2} s, peak {:.0} MiB", kb as f64 / 1024.0),
        )
    };
    let _ = writeln!(
        s,
        "| `deform move --method spring`, same mesh, −10° | {} | pyamg setup + solve {} | {} | ≤ 1 |",
        mv(spring),
        f(total(ps), "s"),
        ratio(spring.map(|v| v.0), total(ps))
    );
    let _ = writeln!(
        s,
        "| `deform move --method quaternion` | {} | pyamg setup + solve {} | {} | ≤ 2 |",
        mv(quaternion),
        f(total(ps), "s"),
        ratio(quaternion.map(|v| v.0), total(ps))
    );
    s.push_str(unordered_rows);
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "Agreement with the kernel's results (max difference): graph scipy {}, trimesh {}, \
         structured ndimage {}, spring pyamg {} (relative), rotation nalgebra {}. pyamg levels: {}.",
        p.get("graph_scipy_max_difference").map_or("—", String::as_str),
        p.get("graph_trimesh_max_difference").map_or("—", String::as_str),
        p.get("structured_ndimage_max_difference").map_or("—", String::as_str),
        p.get("spring_pyamg_max_relative_difference").map_or("—", String::as_str),
        k.get("rotation_max_difference_to_nalgebra").map_or("—", String::as_str),
        p.get("spring_pyamg_levels").map_or("—", String::as_str),
    );
    s
}

/// The release `deform` and the generated NACA 2412 mesh (line by line numbering).
fn deform_and_naca(
    ctx: &Ctx,
    dir: &Path,
    quick: bool,
) -> Option<(std::path::PathBuf, std::path::PathBuf)> {
    if !run(&mut ctx.cargo(&["build", "--release", "-p", "deform-cli"])) {
        return None;
    }
    let deform = ctx.root.join("target").join("release").join("deform");
    let mesh = dir.join("naca2412.su2");
    let (surface, radial) = if quick {
        ("256", "80")
    } else {
        ("1024", "229")
    };
    run(Command::new(&deform)
        .args([
            "mesh",
            "naca",
            "--kind",
            "inviscid",
            "--surface-points",
            surface,
        ])
        .args(["--radial-points", radial, "--first-layer", "1e-5", "--out"])
        .arg(&mesh))
    .then_some((deform, mesh))
}

/// `--unordered-only` (step 4) or `--python-only` (step 5) alone, its rows as the report.
fn alone(ctx: &Ctx, dir: &Path, quick: bool, python_step: bool, load_before: &str) -> ExitCode {
    let Some(python) = peers_python(ctx) else {
        return ExitCode::FAILURE;
    };
    let Some((deform, _)) = deform_and_naca(ctx, dir, quick) else {
        return ExitCode::FAILURE;
    };
    let (rows, option, file) = if python_step {
        let rows = python_call::row(ctx, &python, dir, &deform, quick);
        (rows, "--python-only", "report_python.md")
    } else {
        let rows = unordered(ctx, &python, dir, &deform, quick);
        (rows, "--unordered-only", "report_unordered.md")
    };
    let Some(rows) = rows else {
        return ExitCode::FAILURE;
    };
    let report = format!(
        "## `cargo xtask bench {option}{}`\n\n{}; load average before {load_before}, after {}.\n\n\
         | work | kernel | peer | ratio | target |\n|---|---|---|---|---|\n{rows}",
        if quick { " --quick" } else { "" },
        cpu_model(),
        load_average()
    );
    print!("\n{report}");
    let path = dir.join(file);
    if std::fs::write(&path, &report).is_err() {
        eprintln!("xtask bench: cannot write {}", path.display());
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
