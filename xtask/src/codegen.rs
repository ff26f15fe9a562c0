//! `cargo xtask codegen [--check]`: everything of the C ABI that follows from the ffi crate's
//! source, written into `ffi/generated/` and checked in.
//!
//! Each C function is written once, in `ffi/src/<module>.rs`, as a safe function that takes
//! `In`/`Out` tokens (`crate::slice`) and returns `Result<(), dk_status>` (or a `dk_status`),
//! marked with the inert `#[export(...)]` attribute (`ffi/export-macro`): `fn quat_mul`
//! exports `dk_quat_mul`;
//! `twin` also exports `dk_quat_mul_f32` (the function is generic over `T: Real`); `name[N]`
//! reads the pointer `name` for `N` elements without a `name_len` argument; `name?` lets it be
//! NULL (Fortran `type(c_ptr)`). A doc section `# f32 twin` is the twin's first paragraph.
//! An argument `_dim: Dim<D>` or `_components: Components<V>` is a `uint32_t dim` (or
//! `components`) in C whose value the wrapper turns into the const parameter by a `match`
//! (2–3, 1–7; any other value is `DK_ERR_INVALID_PARAMETER`).
//! A `#[repr(C)]` struct generic over the real type marked `#[export(twin = dk_name)]` is
//! the C structs `dk_name` and `dk_name_f32` (type aliases of its two instances).
//!
//! Written from them (see [`generate`]):
//! - `ffi/generated/<module>.rs`: the `extern "C"` functions (doc, C symbol name behind the
//!   `export-symbols` feature, the pointers wrapped in tokens with their promised lengths under
//!   one `// SAFETY:` note, the call), and the twin structs' type aliases;
//! - `ffi/generated/deform_kernel.h`: cbindgen (as a library, `ffi/cbindgen.toml`) on a copy of
//!   the crate whose generated functions carry a plain `#[no_mangle]`;
//! - `ffi/generated/deform_kernel.f90`: the hand-kept module `ffi/fortran/deform_kernel.in.f90`
//!   with the header's constants and types, the `bind(C)` interfaces and the `_f32` twins of
//!   the tagged wrappers (see [`fortran`]);
//! - `ffi/generated/panic_check.rs`: a call of every function with opaque arguments, so the
//!   link-time panic proof (target-tests/panic-check) covers the whole C ABI;
//! - `ffi/generated/symbols.txt`: the exported symbols.
//!
//! `--check` writes nothing and fails when a checked-in file differs (a CI step).

mod fortran;
mod rust;
mod table;

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};

use crate::ctx::Ctx;
use rust::Symbols;
use table::{read_text, Module};

/// The folder of every generated file.
const GENERATED: &str = "ffi/generated";

fn rustfmt(src: &str) -> Result<String, String> {
    let mut child = Command::new("rustfmt")
        .args(["--edition", "2021", "--emit", "stdout"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run rustfmt: {e}"))?;
    child
        .stdin
        .take()
        .ok_or("rustfmt stdin")?
        .write_all(src.as_bytes())
        .map_err(|e| e.to_string())?;
    let out = child.wait_with_output().map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!(
            "rustfmt failed on generated code:\n{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    String::from_utf8(out.stdout).map_err(|e| e.to_string())
}

/// The C header: cbindgen on a copy of the crate with the generated functions written with
/// a plain `#[no_mangle]`; each twin struct's instances (`DkName_f64`, `DkName_f32` to
/// cbindgen) are named `dk_name` and `dk_name_f32`. cbindgen looks for a module at its default
/// path before a `#[path]` attribute, so the copy puts each generated module at
/// `src/<module>.rs` and its hand-kept child at `src/<module>/imp.rs`.
fn header(ffi: &Path, modules: &[Module]) -> Result<String, String> {
    let tmp = std::env::temp_dir().join(format!("deform-codegen-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&tmp);
    let io = |e: std::io::Error| format!("{}: {e}", tmp.display());
    std::fs::create_dir_all(tmp.join("src")).map_err(io)?;
    for entry in std::fs::read_dir(ffi.join("src")).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
            continue;
        };
        let Some(stem) = name.strip_suffix(".rs") else {
            continue;
        };
        let dest = match modules.iter().find(|m| m.name == stem) {
            Some(m) => {
                let dir = tmp.join("src").join(stem);
                std::fs::create_dir_all(&dir).map_err(io)?;
                let generated = rust::module(m, modules, Symbols::Plain);
                std::fs::write(tmp.join("src").join(name), generated).map_err(io)?;
                dir.join("imp.rs")
            }
            None => tmp.join("src").join(name),
        };
        std::fs::copy(&path, dest).map_err(io)?;
    }
    let mut config = cbindgen::Config::from_file(ffi.join("cbindgen.toml"))?;
    for t in modules.iter().flat_map(|m| &m.structs) {
        let rename = &mut config.export.rename;
        rename.insert(format!("{}_f64", t.rust), t.c.clone());
        rename.insert(format!("{}_f32", t.rust), format!("{}_f32", t.c));
    }
    let bindings = cbindgen::Builder::new()
        .with_src(tmp.join("src/lib.rs"))
        .with_config(config)
        .generate()
        .map_err(|e| format!("cbindgen: {e}"))?;
    let mut out = Vec::new();
    bindings.write(&mut out);
    if std::env::var_os("DEFORM_CODEGEN_KEEP").is_some() {
        let _ = std::fs::write(tmp.join("header.h"), &out);
    } else {
        let _ = std::fs::remove_dir_all(&tmp);
    }
    String::from_utf8(out).map_err(|e| e.to_string())
}

/// Every generated file with its content.
fn generate(root: &Path) -> Result<Vec<(PathBuf, String)>, String> {
    let ffi = root.join("ffi");
    let out = root.join(GENERATED);
    let modules = table::read(&ffi)?;
    let mut files = Vec::new();
    for m in &modules {
        files.push((
            out.join(format!("{}.rs", m.name)),
            rustfmt(&rust::module(m, &modules, Symbols::Feature))?,
        ));
    }
    let header = header(&ffi, &modules)?;
    let hand = read_text(&ffi.join("fortran/deform_kernel.in.f90"))?;
    files.push((
        out.join("deform_kernel.f90"),
        fortran::module(&hand, &header, &modules)?,
    ));
    files.push((out.join("deform_kernel.h"), header));
    files.push((
        out.join("panic_check.rs"),
        rustfmt(&rust::panic_check(&modules))?,
    ));
    files.push((out.join("symbols.txt"), rust::symbols(&modules)));
    Ok(files)
}

/// `cargo xtask codegen [--check]`.
pub(crate) fn codegen_command(ctx: &Ctx, args: &[String]) -> ExitCode {
    let check = match args {
        [] => false,
        [a] if a == "--check" => true,
        _ => {
            eprintln!("usage: cargo xtask codegen [--check]");
            return ExitCode::from(2);
        }
    };
    if codegen(ctx, check) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// Writes (or with `check`, compares) every generated file; `true` when all is well.
pub(crate) fn codegen(ctx: &Ctx, check: bool) -> bool {
    let files = match generate(&ctx.root) {
        Ok(f) => f,
        Err(e) => {
            println!("xtask codegen: {e}");
            return false;
        }
    };
    let mut ok = true;
    for (path, content) in files {
        let same = std::fs::read_to_string(&path).ok().as_deref() == Some(content.as_str());
        let shown = path.strip_prefix(&ctx.root).unwrap_or(&path).display();
        if same {
            continue;
        }
        if check {
            println!("xtask codegen: {shown} is stale: run `cargo xtask codegen`");
            ok = false;
        } else if let Err(e) = std::fs::create_dir_all(path.parent().unwrap_or(&ctx.root))
            .and_then(|()| std::fs::write(&path, content))
        {
            println!("xtask codegen: cannot write {shown}: {e}");
            ok = false;
        } else {
            println!("xtask codegen: wrote {shown}");
        }
    }
    if check && ok {
        println!(
            "xtask codegen: every file of {GENERATED} matches the `#[export]` items of ffi/src"
        );
    }
    ok
}
