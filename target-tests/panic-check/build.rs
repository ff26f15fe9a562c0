//! Puts `target-tests/link/panic-check-memory.x` on the linker search path as `memory.x`
//! (cortex-m-rt's `link.x` includes it; a larger FLASH than the shared map, since this binary
//! is only linked, never run) and adds defmt's linker script for this binary only.

use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let memory = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"))
        .join("..")
        .join("link")
        .join("panic-check-memory.x");
    fs::copy(&memory, out.join("memory.x")).expect("copy target-tests/link/panic-check-memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    println!("cargo:rerun-if-changed={}", memory.display());
    println!("cargo:rerun-if-changed=build.rs");
}
