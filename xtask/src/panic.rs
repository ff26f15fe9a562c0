//! The link-time panic-freedom proof (`panic-check`, its deliberate-panic control) and
//! `cargo xtask panic-locate`.

use crate::ctx::Ctx;
use crate::process::{capture, run, show};
use std::env;
use std::ffi::OsStr;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Symbol the panic-check's `#[panic_handler]` calls and that nothing defines.
pub(crate) const PANIC_SYMBOL: &str = "deform_kernel_panic_path_survived";

/// The embedded target of `target-tests/`.
pub(crate) const PANIC_CHECK_TARGET: &str = "thumbv7em-none-eabihf";

/// `cargo build --release -p panic-check <extra>` in target-tests/.
pub(crate) fn panic_check_cmd(ctx: &Ctx, extra: &[&str]) -> Command {
    let mut args = vec!["build", "--release", "-p", "panic-check"];
    args.extend_from_slice(extra);
    ctx.cargo_tt(&args)
}

/// The panic check must link, with the default feature set and with `micromath`. The two builds
/// run at once, each in its own target directory: fat LTO with one codegen unit is
/// single-threaded, so one build alone leaves a core idle for most of its time. On failure the
/// surviving panic paths are located and printed.
pub(crate) fn panic_check(ctx: &Ctx) -> bool {
    unreferenced_entry_points(ctx);
    let variants: [(&[&str], Option<&str>); 2] = [
        (&[], None),
        (&["--features", "micromath"], Some("target/micromath")),
    ];
    let results: Vec<(bool, String, String)> = std::thread::scope(|scope| {
        let handles: Vec<_> = variants
            .iter()
            .map(|(extra, dir)| {
                let mut cmd = panic_check_cmd(ctx, extra);
                if let Some(d) = dir {
                    cmd.env("CARGO_TARGET_DIR", d);
                }
                println!("$ {}", show(&cmd));
                scope.spawn(move || capture(&mut cmd))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| (false, String::new(), "build thread panicked".into()))
            })
            .collect()
    });
    let mut ok = true;
    for ((extra, _), (linked, stdout, stderr)) in variants.iter().zip(results) {
        println!("panic-check {extra:?}:");
        print!("{stdout}");
        eprint!("{stderr}");
        if !linked {
            ok = false;
            if stderr.contains(PANIC_SYMBOL) {
                println!(
                    "xtask: PANIC PATH SURVIVED: some code called by target-tests/panic-check can \
                     panic. Locating it (cargo xtask panic-locate):"
                );
                panic_locate(ctx, extra);
            } else {
                println!("xtask: panic-check failed to build for another reason (see above)");
            }
        }
    }
    ok
}

/// Warns (does not fail) about kernel `pub fn`s whose name appears nowhere in
/// `target-tests/panic-check/src`: they are probably not proven panic-free yet. A heuristic:
/// names are matched as words, and a `pub fn` in a private module is listed too.
pub(crate) fn unreferenced_entry_points(ctx: &Ctx) {
    let mut kernel = Vec::new();
    rust_files(&ctx.root.join("kernel").join("src"), &mut kernel);
    let mut checks = Vec::new();
    rust_files(
        &ctx.target_tests.join("panic-check").join("src"),
        &mut checks,
    );
    let check_text: String = checks
        .iter()
        .filter_map(|p| std::fs::read_to_string(p).ok())
        .collect::<Vec<_>>()
        .join("\n");
    let words: std::collections::BTreeSet<&str> = check_text
        .split(|c: char| !(c.is_alphanumeric() || c == '_'))
        .collect();
    let mut missing = Vec::new();
    for file in &kernel {
        let Ok(text) = std::fs::read_to_string(file) else {
            continue;
        };
        let mut in_tests = false;
        for line in text.lines() {
            let t = line.trim_start();
            if t.starts_with("#[cfg(test)]") {
                in_tests = true;
            }
            if in_tests {
                continue;
            }
            let Some(rest) = t
                .strip_prefix("pub fn ")
                .or_else(|| t.strip_prefix("pub const fn "))
            else {
                continue;
            };
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && !words.contains(name.as_str()) {
                let rel = file.strip_prefix(&ctx.root).unwrap_or(file);
                missing.push(format!("{}: {name}", rel.display()));
            }
        }
    }
    if missing.is_empty() {
        println!("every kernel `pub fn` name appears in target-tests/panic-check/src");
    } else {
        println!(
            "warning: {} kernel `pub fn`(s) not referenced by target-tests/panic-check/src \
             (not proven panic-free):",
            missing.len()
        );
        for m in missing {
            println!("    {m}");
        }
    }
}

/// Every `.rs` file under `dir`, sorted.
pub(crate) fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension() == Some(OsStr::new("rs")) {
            out.push(p);
        }
    }
}

/// The deliberately panicking variant must fail to link, and for the right reason: the
/// undefined panic symbol.
pub(crate) fn panic_check_deliberate(ctx: &Ctx) -> bool {
    let mut cmd = panic_check_cmd(ctx, &["--features", "deliberate-panic"]);
    println!("$ {}", show(&cmd));
    let (linked, _, stderr) = capture(&mut cmd);
    let reason: Vec<&str> = stderr
        .lines()
        .filter(|l| l.contains(PANIC_SYMBOL) && l.contains("undefined"))
        .collect();
    if linked {
        println!(
            "xtask: the deliberately panicking variant LINKED: the panic check proves nothing"
        );
        false
    } else if reason.is_empty() {
        eprint!("{stderr}");
        println!(
            "xtask: the deliberate-panic variant failed, but not on `{PANIC_SYMBOL}` (see above)"
        );
        false
    } else {
        for l in reason {
            println!("    {}", l.trim());
        }
        println!("xtask: as expected, the deliberate panic path kept `{PANIC_SYMBOL}` referenced");
        true
    }
}

/// Path of a tool from the `llvm-tools` rustup component.
pub(crate) fn llvm_tool(ctx: &Ctx, name: &str) -> Option<PathBuf> {
    let (ok, sysroot, _) = capture(
        Command::new("rustc")
            .args(["--print", "sysroot"])
            .current_dir(&ctx.target_tests),
    );
    let (ok2, vv, _) = capture(Command::new("rustc").arg("-vV"));
    let host = vv
        .lines()
        .find_map(|l| l.strip_prefix("host: "))?
        .trim()
        .to_string();
    if !(ok && ok2) {
        return None;
    }
    let p = Path::new(sysroot.trim())
        .join("lib")
        .join("rustlib")
        .join(host)
        .join("bin")
        .join(name);
    p.exists().then_some(p)
}

/// Builds panic-check with `locate` (panic handler defined, so it links), disassembles it, and
/// prints every function that calls into the panic machinery, with the source lines of the
/// calls. `extra` are further cargo arguments (features).
pub(crate) fn panic_locate(ctx: &Ctx, extra: &[&str]) -> bool {
    let mut features = String::from("locate");
    let mut rest = Vec::new();
    let mut it = extra.iter();
    while let Some(a) = it.next() {
        if *a == "--features" {
            if let Some(f) = it.next() {
                features.push(',');
                features.push_str(f);
            }
        } else {
            rest.push(*a);
        }
    }
    let mut args = vec!["--features", features.as_str()];
    args.extend(rest);
    if !run(&mut panic_check_cmd(ctx, &args)) {
        return false;
    }
    let Some(objdump) = llvm_tool(ctx, "llvm-objdump") else {
        println!("xtask: llvm-objdump not found (rustup component add llvm-tools)");
        return false;
    };
    let target_dir = env::var_os("CARGO_TARGET_DIR").map_or_else(
        || ctx.target_tests.join("target"),
        |d| ctx.target_tests.join(d),
    );
    let bin = target_dir
        .join(PANIC_CHECK_TARGET)
        .join("release")
        .join("panic-check");
    let (ok, dis, err) = capture(
        Command::new(&objdump)
            .args(["-d", "-C", "-l", "--no-show-raw-insn"])
            .arg(&bin),
    );
    if !ok {
        println!("xtask: llvm-objdump failed: {err}");
        return false;
    }
    let report = locate_report(&dis);
    print!("{report}");
    true
}

/// A disassembled function: name, calls `(address, source line, callee)`.
pub(crate) struct Func {
    name: String,
    calls: Vec<(String, String, String)>,
}

/// Parses `llvm-objdump -d -C -l` output.
pub(crate) fn parse_disassembly(dis: &str) -> Vec<Func> {
    let mut funcs: Vec<Func> = Vec::new();
    // Innermost source line of the current instruction, and the last one outside the
    // standard library and registry crates (the caller's line when core code is inlined).
    let mut line_info = String::new();
    let mut own_line = String::new();
    for line in dis.lines() {
        if let Some(name) = line
            .strip_suffix(">:")
            .and_then(|l| l.split_once(" <"))
            .filter(|(addr, _)| addr.chars().all(|c| c.is_ascii_hexdigit()))
            .map(|(_, n)| n)
        {
            funcs.push(Func {
                name: name.to_string(),
                calls: Vec::new(),
            });
            line_info.clear();
            own_line.clear();
            continue;
        }
        if let Some(src) = line.strip_prefix("; ") {
            line_info = src.trim().to_string();
            if !line_info.contains("/rustlib/src/") && !line_info.contains("/registry/src/") {
                own_line.clone_from(&line_info);
            }
            continue;
        }
        // `    addr:   mnemonic  operands <callee+0x..>`: any branch to another function.
        let t = line.trim_start();
        let Some((addr, insn)) = t.split_once(':') else {
            continue;
        };
        if addr.is_empty() || !addr.chars().all(|c| c.is_ascii_hexdigit()) {
            continue;
        }
        let insn = insn.trim_start();
        if !insn.starts_with('b') && !insn.starts_with("cb") && !insn.starts_with('j') {
            continue;
        }
        let (Some(open), Some(close)) = (insn.find('<'), insn.rfind('>')) else {
            continue;
        };
        if close <= open {
            continue;
        }
        let target = &insn[open + 1..close];
        let callee = target.split("+0x").next().unwrap_or(target);
        if let Some(f) = funcs.last_mut() {
            if callee != f.name {
                let src = if own_line.is_empty() || own_line == line_info {
                    line_info.clone()
                } else {
                    format!("{line_info}\n          near {own_line}")
                };
                f.calls.push((addr.to_string(), src, callee.to_string()));
            }
        }
    }
    funcs
}

/// The functions that reach the panic handler, kernel and test code first.
pub(crate) fn locate_report(dis: &str) -> String {
    let funcs = parse_disassembly(dis);
    let mut bad: Vec<String> = vec![
        PANIC_SYMBOL.into(),
        "__rustc::rust_begin_unwind".into(),
        "rust_begin_unwind".into(),
    ];
    loop {
        let mut changed = false;
        for f in &funcs {
            if !bad.contains(&f.name) && f.calls.iter().any(|c| bad.contains(&c.2)) {
                bad.push(f.name.clone());
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let is_core = |n: &str| {
        n.starts_with("core::")
            || n.starts_with("<core::")
            || n.starts_with("__rustc::")
            || n == "rust_begin_unwind"
            || n == PANIC_SYMBOL
    };
    let mut out = String::new();
    let mut found = false;
    for f in funcs
        .iter()
        .filter(|f| bad.contains(&f.name) && !is_core(&f.name))
    {
        let direct: Vec<&(String, String, String)> = f
            .calls
            .iter()
            .filter(|c| bad.contains(&c.2) && is_core(&c.2))
            .collect();
        if direct.is_empty() {
            continue;
        }
        found = true;
        let _ = writeln!(out, "  {}", f.name);
        for (addr, src, callee) in direct {
            let _ = writeln!(out, "      0x{addr}  {callee}\n          at {src}");
        }
    }
    if !found {
        let _ = writeln!(
            out,
            "  no direct caller of the panic machinery found outside core: the panic is \
             reached through a function pointer (e.g. a core::fmt Debug impl) or from core itself"
        );
        for f in funcs.iter().filter(|f| bad.contains(&f.name)) {
            let _ = writeln!(out, "    reaches the handler: {}", f.name);
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// on-target suite
