//! Puts this crate's own `memory.x` (RAM limited to 64 KiB) on the linker search path, ahead of
//! nothing else: the footprint binary must not see the generous shared `target-tests/memory.x`.
//! Adds defmt's linker script.

use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let memory =
        PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo")).join("memory.x");
    fs::copy(&memory, out.join("memory.x")).expect("copy footprint/memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
    println!("cargo:rerun-if-changed={}", memory.display());
    println!("cargo:rerun-if-changed=build.rs");
}
