//! The cost of a mesh adjoint against the deformation itself (issue 30 item 5): the whole
//! `deform adjoint` command on the 234k-node NACA 2412 mesh (read the mesh and a volume
//! sensitivity at every node, set up the operator and its multigrid, one solve, write the
//! surface sensitivities) against the whole `deform move` of step 3 with the same method and
//! tolerance.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// `node dJ/dx dJ/dy` rows at every node of an SU2 mesh (2D), with smooth made-up values.
fn write_sensitivity(mesh: &Path, path: &Path) -> Option<()> {
    let text = std::fs::read_to_string(mesh).ok()?;
    let n: usize = text
        .lines()
        .find_map(|l| l.trim().strip_prefix("NPOIN="))
        .and_then(|v| v.split_whitespace().next())
        .and_then(|v| v.parse().ok())?;
    let mut s = String::with_capacity(n * 48);
    for i in 0..n {
        let t = i as f64 * 1e-3;
        let _ = writeln!(s, "{i} {:e} {:e}", t.sin(), (0.7 * t).cos());
    }
    std::fs::write(path, s).ok()
}

/// Whether the tool's `adjoint` command takes `--method <method>`.
fn adjoint_has_method(deform: &Path, method: &str) -> bool {
    Command::new(deform)
        .args(["adjoint", "--help"])
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).contains(&format!("- {method}:")))
}

/// Median wall time of `reps` adjoint runs.
fn adjoint_seconds(
    deform: &Path,
    dir: &Path,
    mesh: &Path,
    method: &str,
    reps: usize,
) -> Option<f64> {
    let sens = dir.join("volume_sensitivity.txt");
    if !sens.exists() {
        write_sensitivity(mesh, &sens)?;
    }
    let mut times = Vec::new();
    for _ in 0..reps {
        let mut c = Command::new(deform);
        c.args(["--json", "adjoint"])
            .arg(mesh)
            .args(["--method", method, "--tol", "1e-8", "--sensitivity"])
            .arg(&sens)
            .arg("--out")
            .arg(dir.join(format!("surface_sensitivity_{method}.csv")))
            .stdout(std::process::Stdio::null());
        let (t, _, ok) = super::run_measured(&mut c)?;
        if !ok {
            eprintln!("bench: deform adjoint --method {method} failed");
            return None;
        }
        times.push(t.as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    times.get(times.len() / 2).copied()
}

/// The report's rows: for each method the tool's adjoint takes, its time against the move's.
pub(super) fn rows(
    deform: &Path,
    dir: &Path,
    mesh: &Path,
    moves: [(&str, Option<f64>); 2],
    reps: usize,
) -> String {
    let mut s = String::new();
    for (method, move_s) in moves {
        if !adjoint_has_method(deform, method) {
            continue;
        }
        let adjoint = adjoint_seconds(deform, dir, mesh, method, reps);
        let ratio = match (adjoint, move_s) {
            (Some(a), Some(m)) if m > 0.0 => format!("{:.2}", a / m),
            _ => "—".into(),
        };
        let secs = |v: Option<f64>| v.map_or_else(|| "—".into(), |v| format!("{v:.2} s"));
        let _ = writeln!(
            s,
            "| `deform adjoint --method {method}`, same mesh and tolerance (dJ/dx at every node → surface) | {} | `deform move --method {method}` {} | {} | ≤ 1.5 |",
            secs(adjoint),
            secs(move_s),
            ratio
        );
    }
    s
}
