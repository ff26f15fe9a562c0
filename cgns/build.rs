//! Links libcgns and tells the crate the width of `cgsize_t` (`CG_BUILD_64BIT` in the
//! installed `cgnstypes.h`: Debian's libcgns-dev builds 32-bit sizes, other builds 64-bit).

use std::path::PathBuf;

fn main() {
    println!("cargo:rustc-link-lib=cgns");
    println!("cargo:rerun-if-env-changed=CGNS_INCLUDE_DIR");
    println!("cargo:rustc-check-cfg=cfg(cgsize64)");
    let mut dirs: Vec<PathBuf> = Vec::new();
    if let Some(d) = std::env::var_os("CGNS_INCLUDE_DIR") {
        dirs.push(d.into());
    }
    dirs.extend(["/usr/include", "/usr/local/include"].map(PathBuf::from));
    let header = dirs
        .iter()
        .map(|d| d.join("cgnstypes.h"))
        .find(|p| p.exists());
    let Some(header) = header else {
        // Without the library nothing that calls it links; the workspace still builds.
        println!("cargo:warning=cgnstypes.h not found: install libcgns-dev (or set CGNS_INCLUDE_DIR) to link deform-cgns");
        return;
    };
    println!("cargo:rerun-if-changed={}", header.display());
    let text = std::fs::read_to_string(&header).expect("read cgnstypes.h");
    let wide = text.lines().any(|l| {
        let t: Vec<&str> = l.split_whitespace().collect();
        t.len() >= 3 && t[0] == "#define" && t[1] == "CG_BUILD_64BIT" && t[2] == "1"
    });
    if wide {
        println!("cargo:rustc-cfg=cgsize64");
    }
}
