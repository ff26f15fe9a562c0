//! Puts the shared `target-tests/link/memory.x` on the linker search path and adds the linker
//! scripts of cortex-m-rt (`link.x`) and defmt (`defmt.x`) for this crate's test binaries.

use std::path::PathBuf;
use std::{env, fs};

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR is set by cargo"));
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let memory = manifest.join("..").join("link").join("memory.x");
    fs::copy(&memory, out.join("memory.x")).expect("copy target-tests/link/memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed={}", memory.display());
    println!("cargo:rustc-link-arg-tests=-Tdefmt.x");
}
