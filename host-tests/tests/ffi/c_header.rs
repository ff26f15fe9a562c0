//! The checked-in C header is exactly what cbindgen (pinned version, `ffi/cbindgen.toml`)
//! generates from the ffi crate today. Regenerate with
//! `DEFORM_BLESS=1 cargo test -p deform-host-tests --test c_header`.
//!
//! The ffi crate names its C symbols only with its `export-symbols` feature
//! (`#[cfg_attr(feature = "export-symbols", no_mangle)]`), which cbindgen does not evaluate; so
//! cbindgen reads a copy of `ffi/src` with that attribute written as the plain `#[no_mangle]`
//! the C library gets.

use std::path::Path;

/// The attribute as written in `ffi/src`, and what the C library build makes of it.
const EXPORT_ATTR: &str = "#[cfg_attr(feature = \"export-symbols\", no_mangle)]";

#[test]
fn checked_in_header_is_up_to_date() {
    let ffi = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("ffi");
    let config = cbindgen::Config::from_file(ffi.join("cbindgen.toml")).expect("cbindgen.toml");
    let src = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cbindgen-src");
    let _ = std::fs::remove_dir_all(&src);
    let exported = copy_exported(&ffi.join("src"), &src);
    assert!(exported > 0, "no `{EXPORT_ATTR}` found in ffi/src");
    let bindings = cbindgen::Builder::new()
        .with_src(src.join("lib.rs"))
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let generated = String::from_utf8(generated).unwrap();
    let path = ffi.join("include/deform_kernel.h");
    if std::env::var_os("DEFORM_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    let checked_in = std::fs::read_to_string(&path).unwrap();
    assert!(
        generated == checked_in,
        "ffi/include/deform_kernel.h is stale: run `DEFORM_BLESS=1 cargo test -p deform-host-tests --test c_header`"
    );
}

/// Copies the `.rs` files under `from` (recursively) to `to`, spelling the export attribute as
/// `#[no_mangle]`; returns how many attributes it rewrote.
fn copy_exported(from: &Path, to: &Path) -> usize {
    std::fs::create_dir_all(to).unwrap();
    let mut exported = 0;
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let dest = to.join(path.file_name().unwrap());
        if path.is_dir() {
            exported += copy_exported(&path, &dest);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let text = std::fs::read_to_string(&path).unwrap();
            exported += text.matches(EXPORT_ATTR).count();
            std::fs::write(dest, text.replace(EXPORT_ATTR, "#[no_mangle]")).unwrap();
        }
    }
    exported
}
