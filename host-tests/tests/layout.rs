//! The test layout holds together: every `.rs` file in a subdirectory of `tests/` (other than
//! `support/`) is a test binary named by a `[[test]]` entry of `host-tests/Cargo.toml`, or a
//! module that a test file includes with `#[path = "…"]`, and every entry's file exists. Cargo finds only the files at the top of `tests/` by itself, so
//! without this a new file in `tests/spring/` would compile nowhere and run never.

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

/// The `path = "..."` values of the manifest's `[[test]]` entries.
fn listed_paths(manifest: &str) -> BTreeSet<String> {
    manifest
        .lines()
        .filter_map(|line| line.trim().strip_prefix("path"))
        .filter_map(|rest| rest.trim_start().strip_prefix('='))
        .map(|value| value.trim().trim_matches('"').to_string())
        .collect()
}

/// The files that the `tests/*.rs` binaries (and the listed ones) include as modules with
/// `#[path = "…"]`, as `tests/…` paths (relative to the including file's directory).
fn path_modules(root: &Path, listed: &BTreeSet<String>) -> BTreeSet<String> {
    let top = fs::read_dir(root.join("tests"))
        .expect("tests/ is readable")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .filter_map(|p| p.strip_prefix(root).ok().map(|p| p.display().to_string()));
    let mut out = BTreeSet::new();
    for file in top.chain(listed.iter().cloned()) {
        let Ok(text) = fs::read_to_string(root.join(&file)) else {
            continue;
        };
        let dir = Path::new(&file).parent().unwrap_or(Path::new(""));
        for line in text.lines() {
            let rest = line.trim().strip_prefix("#[path = \"");
            if let Some(target) = rest.and_then(|r| r.strip_suffix("\"]")) {
                out.insert(dir.join(target).display().to_string());
            }
        }
    }
    out
}

/// `tests/<dir>/<file>.rs` for every subdirectory except `support`.
fn nested_test_files(tests: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for dir in fs::read_dir(tests).expect("tests/ is readable") {
        let dir = dir.expect("a directory entry").path();
        let name = dir
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default()
            .to_string();
        if !dir.is_dir() || name == "support" {
            continue;
        }
        for file in fs::read_dir(&dir).expect("a tests/ subdirectory is readable") {
            let file = file.expect("a directory entry").path();
            if file.extension().is_some_and(|e| e == "rs") {
                let stem = file
                    .file_name()
                    .and_then(|n| n.to_str())
                    .unwrap_or_default();
                out.insert(format!("tests/{name}/{stem}"));
            }
        }
    }
    out
}

#[test]
fn every_nested_test_file_is_a_listed_binary_and_every_listed_file_exists() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = fs::read_to_string(root.join("Cargo.toml")).expect("Cargo.toml is readable");
    let listed = listed_paths(&manifest);
    let nested = nested_test_files(&root.join("tests"));
    assert!(
        !nested.is_empty(),
        "no test files found in subdirectories of tests/"
    );
    let modules = path_modules(root, &listed);
    let unlisted: Vec<_> = nested
        .iter()
        .filter(|f| !listed.contains(*f) && !modules.contains(*f))
        .collect();
    assert!(
        unlisted.is_empty(),
        "test files with no [[test]] entry: {unlisted:?}"
    );
    let missing: Vec<_> = listed.iter().filter(|p| !root.join(p).is_file()).collect();
    assert!(
        missing.is_empty(),
        "[[test]] paths with no file: {missing:?}"
    );
}
