//! Shared helpers for the tests that build the C library and compile C and Fortran programs
//! against it (`c_abi*.rs`). Include with `mod common;` and `use common::c_build::*;`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace root")
        .to_path_buf()
}

/// Builds the C library (`ffi/capi`, its own workspace with `panic = "abort"`) once per test
/// run, in its own target directory (so it does not wait on the lock of the cargo running these
/// tests), and returns the directory holding `libdeform_kernel.{a,so}`.
pub fn library_dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let target = Path::new(env!("CARGO_TARGET_TMPDIR")).join("capi-build");
        let status = Command::new(env!("CARGO"))
            .current_dir(workspace())
            .args(["build", "--release", "--quiet", "--manifest-path"])
            .arg(workspace().join("ffi/capi/Cargo.toml"))
            .arg("--target-dir")
            .arg(&target)
            .status()
            .expect("run cargo");
        assert!(status.success(), "building deform-kernel-capi failed");
        target.join("release")
    })
}

pub enum Link {
    Static,
    Shared,
}

pub fn compile(compiler: &str, sources: &[PathBuf], flags: &[&str], link: Link, exe: &Path) {
    let lib = library_dir();
    let mut cmd = Command::new(compiler);
    cmd.args(flags).args(sources).arg("-o").arg(exe);
    match link {
        Link::Static => {
            cmd.arg(lib.join("libdeform_kernel.a"));
        }
        Link::Shared => {
            cmd.arg(format!("-L{}", lib.display()))
                .arg("-ldeform_kernel")
                .arg(format!("-Wl,-rpath,{}", lib.display()))
                .arg("-Wl,--disable-new-dtags");
        }
    }
    cmd.args(["-lm", "-lpthread", "-ldl"]);
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {compiler}: {e}"));
    assert!(
        out.status.success(),
        "{compiler} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

pub fn run(exe: &Path) -> String {
    // cargo puts its own target directories on LD_LIBRARY_PATH, which would override the
    // rpath of the shared-library builds and could load a stale libdeform_kernel.so.
    let out = Command::new(exe)
        .env_remove("LD_LIBRARY_PATH")
        .output()
        .expect("run example");
    assert!(
        out.status.success(),
        "{} failed:\n{}{}",
        exe.display(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("utf-8 output")
}

pub fn tmp(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Compiles the C program `ffi/tests/<name>.c` with [`c_flags`], links it as `link` into a
/// temporary executable called `exe` and returns what it printed.
pub fn run_c_test(name: &str, exe: &str, link: Link) -> String {
    let src = workspace().join(format!("ffi/tests/{name}.c"));
    let flags = c_flags();
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    let exe = tmp(exe);
    compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
    run(&exe)
}

/// Compiles `ffi/tests/<name>.c` against the static and the shared library (with
/// [`c_flags`] and `-Wl,--disable-new-dtags`), runs both and returns `(executable name,
/// printed text)` of each.
pub fn run_c_both(name: &str) -> Vec<(String, String)> {
    let src = workspace().join(format!("ffi/tests/{name}.c"));
    let mut flags = c_flags();
    flags.push("-Wl,--disable-new-dtags".to_string());
    let flags: Vec<&str> = flags.iter().map(String::as_str).collect();
    [(Link::Static, "static"), (Link::Shared, "shared")]
        .into_iter()
        .map(|(link, kind)| {
            let exe_name = format!("{name}_{kind}");
            let exe = tmp(&exe_name);
            compile("gcc", std::slice::from_ref(&src), &flags, link, &exe);
            (exe_name, run(&exe))
        })
        .collect()
}

pub fn c_flags() -> Vec<String> {
    let inc = workspace().join("ffi/generated");
    ["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("-I{}", inc.display())])
        .collect()
}

pub fn hex64(name: &str, v: &[f64]) -> String {
    let mut s = name.to_string();
    for x in v {
        s += &format!(" {:016X}", x.to_bits());
    }
    s + "\n"
}

pub fn hex32(name: &str, v: &[f32]) -> String {
    let mut s = name.to_string();
    for x in v {
        s += &format!(" {:08X}", x.to_bits());
    }
    s + "\n"
}

/// The doubles of a `name h h ...` line written by [`hex64`] (or a C program's `%016llx`).
pub fn parse_hex64(line: &str, name: &str) -> Vec<f64> {
    let rest = line
        .strip_prefix(name)
        .unwrap_or_else(|| panic!("expected {name}: {}", &line[..line.len().min(80)]));
    rest.split_whitespace()
        .map(|h| f64::from_bits(u64::from_str_radix(h, 16).expect("hex")))
        .collect()
}

/// Builds `ffi/tests/<name>.f90` with the Fortran module (strict: f2008, `-Wall -Werror`),
/// links the static library and returns what it prints.
pub fn fortran_test(name: &str) -> String {
    let module = workspace().join("ffi/generated/deform_kernel.f90");
    let src = workspace().join(format!("ffi/tests/{name}.f90"));
    let moddir = tmp(&format!("{name}_f_mod"));
    std::fs::create_dir_all(&moddir).unwrap();
    let jflag = format!("-J{}", moddir.display());
    let exe = tmp(&format!("{name}_f"));
    compile(
        "gfortran",
        &[module, src],
        &["-std=f2008", "-Wall", "-Werror", &jflag],
        Link::Static,
        &exe,
    );
    run(&exe)
}
