//! The Python that runs the tests' independent references (numpy, scipy, scikit-fem, meshio):
//! `$DEFORM_TEST_PYTHON` when set, else the venv `target/test-venv` that
//! `cargo xtask ci --step install` creates from `xtask/python-test-requirements.txt`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The interpreter; panics with the command that creates it when it is missing, so a machine
/// without the references fails loudly instead of skipping.
pub fn python() -> PathBuf {
    if let Some(p) = std::env::var_os("DEFORM_TEST_PYTHON") {
        return PathBuf::from(p);
    }
    let venv = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("target")
        .join("test-venv")
        .join("bin")
        .join("python");
    assert!(
        venv.exists(),
        "no reference Python at {}: run `cargo xtask ci --step install` \
         (or set DEFORM_TEST_PYTHON to a Python with numpy and scipy)",
        venv.display()
    );
    venv
}

/// Runs `script` (a path) with `args`; returns stdout, panicking with stderr on failure.
pub fn run_script(script: &Path, args: &[&str]) -> String {
    let out = Command::new(python())
        .arg(script)
        .args(args)
        .output()
        .expect("start the reference Python");
    assert!(
        out.status.success(),
        "{} failed:\n{}",
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 output")
}
