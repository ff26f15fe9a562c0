//! Paths and tools every step shares.

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Paths and tools shared by every step.
pub(crate) struct Ctx {
    /// Repository root (the host workspace).
    pub(crate) root: PathBuf,
    /// `target-tests/` (its own workspace and `.cargo/config.toml`).
    pub(crate) target_tests: PathBuf,
    /// The cargo that runs us (same toolchain), or `cargo`.
    pub(crate) cargo: String,
    /// Kernel features (from `kernel/Cargo.toml`, without `default`).
    pub(crate) kernel_features: Vec<String>,
    /// Host tests that need a feature (`[[test]]` entries with `required-features` in
    /// `host-tests/Cargo.toml`): the normal test run skips them.
    pub(crate) feature_tests: Vec<String>,
}

impl Ctx {
    pub(crate) fn new() -> Ctx {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"))
            .parent()
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        let kernel_features = kernel_features(&root.join("kernel").join("Cargo.toml"));
        let feature_tests = feature_tests(&root.join("host-tests").join("Cargo.toml"));
        Ctx {
            target_tests: root.join("target-tests"),
            root,
            cargo: env::var("CARGO").unwrap_or_else(|_| "cargo".into()),
            kernel_features,
            feature_tests,
        }
    }

    /// A cargo command run from the repository root.
    pub(crate) fn cargo(&self, args: &[&str]) -> Command {
        let mut c = Command::new(&self.cargo);
        c.args(args).current_dir(&self.root);
        c
    }

    /// A cargo command run from `target-tests/` (so its `.cargo/config.toml` applies).
    pub(crate) fn cargo_tt(&self, args: &[&str]) -> Command {
        let mut c = Command::new(&self.cargo);
        c.args(args).current_dir(&self.target_tests);
        c
    }
}

/// Feature names of the `[features]` table of a Cargo.toml (without `default`). A tiny
/// line-based reader: enough for `name = [...]` entries, one per line.
pub(crate) fn kernel_features(manifest: &Path) -> Vec<String> {
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

/// Names of the `[[test]]` entries of a Cargo.toml that have `required-features`. The same
/// line-based reading as [`kernel_features`].
pub(crate) fn feature_tests(manifest: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(manifest).unwrap_or_default();
    let mut out = Vec::new();
    let mut in_test = false;
    let mut name = None;
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_test = line == "[[test]]";
            name = None;
        } else if let Some((key, value)) = line.split_once('=').filter(|_| in_test) {
            match key.trim() {
                "name" => name = Some(value.trim().trim_matches('"').to_string()),
                "required-features" => out.extend(name.clone()),
                _ => {}
            }
        }
    }
    out
}
