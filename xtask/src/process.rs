//! Running commands: echo, status, captured output.

use std::ffi::OsStr;
use std::fmt::Write as _;
use std::process::{Command, Stdio};

/// Shows and runs a command with inherited stdio; `true` when it exits with status 0.
pub(crate) fn run(cmd: &mut Command) -> bool {
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
pub(crate) fn capture(cmd: &mut Command) -> (bool, String, String) {
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
pub(crate) fn show(cmd: &Command) -> String {
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
