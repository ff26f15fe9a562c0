//! The checked-in C header is exactly what cbindgen (pinned version, `ffi/cbindgen.toml`)
//! generates from the ffi crate today. Regenerate with
//! `DEFORM_BLESS=1 cargo test -p deform-host-tests --test c_header`.

use std::path::Path;

#[test]
fn checked_in_header_is_up_to_date() {
    let ffi = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .join("ffi");
    let config = cbindgen::Config::from_file(ffi.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(&ffi)
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
