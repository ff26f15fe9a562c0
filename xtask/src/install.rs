//! What CI installs when missing: rustup targets and components, apt packages, pinned cargo
//! tools; and the `cinstall` step (the C library installed with cargo-c).

use crate::ci::CAPI_MANIFEST;
use crate::ctx::Ctx;
use crate::process::{capture, run, show};
use std::path::Path;
use std::process::{Command, Stdio};

/// Cross-compilation targets the kernel must build for (bare metal, no std).
pub(crate) const CROSS_TARGETS: &[&str] = &[
    "thumbv7em-none-eabihf",
    "thumbv6m-none-eabi",
    "riscv32imc-unknown-none-elf",
];

/// Rustup targets installed on the active toolchain.
pub(crate) const RUSTUP_TARGETS: &[&str] = CROSS_TARGETS;

/// Rustup components installed on the active toolchain. `rust-src` and `llvm-tools` serve the
/// embedded builds and `cargo xtask panic-locate` (llvm-objdump).
pub(crate) const RUSTUP_COMPONENTS: &[&str] = &["rustfmt", "clippy", "rust-src", "llvm-tools"];

/// Debian packages, installed with `apt-get install` when running as root (e.g. `gfortran`,
/// `qemu-system-arm`). Checked with `dpkg -s`.
/// `libssl-dev` and `pkg-config` are needed to build cargo-c, and `pkg-config` by the
/// `cinstall` step; OpenMPI and libclang (for the `mpi` crate's bindings) by the `mpi` step;
/// the CGNS library by deform-cli's `cgns` feature, and the CGNS and HDF5 tools
/// (`cgns_to_plot3d`, `adf2hdf`, `cgnscheck`, `h5dump`) by its tests; `python3-venv` by the
/// tests' reference venv.
pub(crate) const APT_PACKAGES: &[&str] = &[
    "gfortran",
    "qemu-system-arm",
    "libssl-dev",
    "pkg-config",
    "openmpi-bin",
    "libopenmpi-dev",
    "libclang-dev",
    "libcgns-dev",
    "cgns-convert",
    "hdf5-tools",
    "python3-venv",
];

/// A cargo tool installed with `cargo install --locked NAME --version VERSION`.
pub(crate) struct CargoTool {
    /// Crate name.
    name: &'static str,
    /// Exact version.
    version: &'static str,
}

/// Cargo tools at pinned versions (e.g. cargo-fuzz, defmt-print, cbindgen).
pub(crate) const CARGO_TOOLS: &[CargoTool] = &[
    CargoTool {
        name: "defmt-print",
        version: "1.2.0",
    },
    CargoTool {
        name: "cargo-fuzz",
        version: "0.13.1",
    },
    // The last cargo-c release that builds with the pinned stable rustc (1.95).
    CargoTool {
        name: "cargo-c",
        version: "0.10.24+cargo-0.98.0",
    },
];

/// The toolchain cargo-fuzz needs (sanitizer flags are nightly-only).
pub(crate) const FUZZ_TOOLCHAIN: &str = "nightly";

/// Installs whatever is missing; `true` when everything is in place afterwards.
pub(crate) fn install(ctx: &Ctx) -> bool {
    let mut ok = true;
    let rustup = |args: &[&str]| {
        let mut c = Command::new("rustup");
        c.args(args).current_dir(&ctx.root);
        c
    };

    let (_, installed, _) = capture(&mut rustup(&["target", "list", "--installed"]));
    let installed: Vec<&str> = installed.lines().map(str::trim).collect();
    let missing: Vec<&str> = RUSTUP_TARGETS
        .iter()
        .copied()
        .filter(|t| !installed.contains(t))
        .collect();
    if missing.is_empty() {
        println!(
            "rustup targets: all present ({})",
            RUSTUP_TARGETS.join(", ")
        );
    } else {
        let mut args = vec!["target", "add"];
        args.extend(&missing);
        ok &= run(&mut rustup(&args));
    }

    let (_, installed, _) = capture(&mut rustup(&["component", "list", "--installed"]));
    // Listed as `name-<host triple>` (or `name` for rust-src).
    let has = |c: &str| {
        installed.lines().map(str::trim).any(|l| {
            l == c
                || l.strip_prefix(c)
                    .is_some_and(|rest| rest.starts_with('-') && rest.contains("-unknown-"))
        })
    };
    let missing: Vec<&str> = RUSTUP_COMPONENTS
        .iter()
        .copied()
        .filter(|c| !has(c))
        .collect();
    if missing.is_empty() {
        println!(
            "rustup components: all present ({})",
            RUSTUP_COMPONENTS.join(", ")
        );
    } else {
        let mut args = vec!["component", "add"];
        args.extend(&missing);
        ok &= run(&mut rustup(&args));
    }

    let missing: Vec<&str> = APT_PACKAGES
        .iter()
        .copied()
        .filter(|p| !capture(Command::new("dpkg").args(["-s", p])).0)
        .collect();
    if missing.is_empty() {
        if !APT_PACKAGES.is_empty() {
            println!("apt packages: all present ({})", APT_PACKAGES.join(", "));
        }
    } else if is_root() {
        let apt = |args: &[&str]| {
            let mut c = Command::new("apt-get");
            c.args(args)
                .env("DEBIAN_FRONTEND", "noninteractive")
                .stdin(Stdio::null());
            c
        };
        ok &= run(&mut apt(&["update", "-q"]));
        let mut args = vec!["install", "-y", "-q", "--no-install-recommends"];
        args.extend(&missing);
        ok &= run(&mut apt(&args));
    } else {
        println!(
            "xtask: missing apt packages and not root: sudo apt-get install {}",
            missing.join(" ")
        );
        ok = false;
    }

    if !CARGO_TOOLS.is_empty() {
        let (_, list, _) = capture(&mut ctx.cargo(&["install", "--list"]));
        for tool in CARGO_TOOLS {
            let line = format!("{} v{}:", tool.name, tool.version);
            if list.lines().any(|l| l.trim() == line) {
                println!("cargo tool {} {}: present", tool.name, tool.version);
            } else {
                ok &= run(&mut ctx.cargo(&[
                    "install",
                    "--locked",
                    tool.name,
                    "--version",
                    tool.version,
                ]));
            }
        }
    }

    let (_, toolchains, _) = capture(&mut rustup(&["toolchain", "list"]));
    if toolchains.lines().any(|l| l.starts_with(FUZZ_TOOLCHAIN)) {
        println!("rustup toolchain {FUZZ_TOOLCHAIN}: present (for cargo-fuzz and Miri)");
    } else {
        ok &= run(&mut rustup(&[
            "toolchain",
            "install",
            FUZZ_TOOLCHAIN,
            "--profile",
            "minimal",
        ]));
    }
    // Miri (the `miri` step) runs on the same nightly; it needs `rust-src` for its sysroot.
    let (_, nightly, _) = capture(&mut rustup(&[
        "component",
        "list",
        "--installed",
        "--toolchain",
        FUZZ_TOOLCHAIN,
    ]));
    let missing: Vec<&str> = ["miri", "rust-src"]
        .into_iter()
        .filter(|c| !nightly.lines().any(|l| l.starts_with(c)))
        .collect();
    if missing.is_empty() {
        println!("rustup components on {FUZZ_TOOLCHAIN}: miri, rust-src present");
    } else {
        let mut args = vec!["component", "add", "--toolchain", FUZZ_TOOLCHAIN];
        args.extend(missing);
        ok &= run(&mut rustup(&args));
    }
    ok & test_venv(ctx) & crate::python::python_venv(ctx)
}

/// The venv `target/test-venv` with the Python packages the tests use as independent
/// references, pinned in `xtask/python-test-requirements.txt`.
fn test_venv(ctx: &Ctx) -> bool {
    let venv = ctx.root.join("target").join("test-venv");
    let python = venv.join("bin").join("python");
    let requirements = ctx.root.join("xtask").join("python-test-requirements.txt");
    if !python.exists() && !run(Command::new("python3").args(["-m", "venv"]).arg(&venv)) {
        println!("xtask: `python3 -m venv` failed (Debian: apt-get install python3-venv)");
        return false;
    }
    let mut pip = Command::new(&python);
    pip.args(["-m", "pip", "install", "-q", "-r"])
        .arg(&requirements);
    run(&mut pip)
}

/// `cargo cinstall` (cargo-c) of the C library into `target/cinstall/root` with prefix `/usr`:
/// checks that the static and shared libraries, `deform_kernel.pc`, the checked-in header and
/// the Fortran module source (both byte-identical) are installed, then compiles `ffi/examples/mesh_basics.c` with the flags
/// `pkg-config` gives for the staged tree, links it to the shared library and runs it.
pub(crate) fn cinstall(ctx: &Ctx) -> bool {
    let base = ctx.root.join("target").join("cinstall");
    let root = base.join("root");
    let _ = std::fs::remove_dir_all(&root);
    let mut cmd = ctx.cargo(&[
        "cinstall",
        "--manifest-path",
        CAPI_MANIFEST,
        "--release",
        "--prefix",
        "/usr",
        "--libdir",
        "/usr/lib",
    ]);
    cmd.arg("--destdir")
        .arg(&root)
        .arg("--target-dir")
        .arg(base.join("build"));
    if !run(&mut cmd) {
        return false;
    }
    let lib = root.join("usr/lib");
    let header = root.join("usr/include/deform_kernel.h");
    let mut ok = true;
    for f in [
        lib.join("libdeform_kernel.a"),
        lib.join("libdeform_kernel.so"),
        lib.join("pkgconfig/deform_kernel.pc"),
        header.clone(),
    ] {
        if !f.exists() {
            println!("xtask: cargo cinstall did not install {}", f.display());
            ok = false;
        }
    }
    let module = root.join("usr/include/deform_kernel.f90");
    for (installed, checked_in) in [
        (&header, "ffi/generated/deform_kernel.h"),
        (&module, "ffi/generated/deform_kernel.f90"),
    ] {
        if std::fs::read(installed).ok() != std::fs::read(ctx.root.join(checked_in)).ok() {
            println!(
                "xtask: the installed {} differs from {checked_in}",
                installed.display()
            );
            ok = false;
        }
    }
    if !ok {
        return false;
    }
    let mut pc = Command::new("pkg-config");
    pc.args(["--cflags", "--libs", "deform_kernel"])
        .env("PKG_CONFIG_PATH", lib.join("pkgconfig"))
        .env("PKG_CONFIG_SYSROOT_DIR", &root);
    let (found, flags, err) = capture(&mut pc);
    println!("$ {} -> {}", show(&pc), flags.trim());
    if !found {
        print!("{err}");
        return false;
    }
    let exe = base.join("mesh_basics");
    if !build_and_run_mesh_basics(ctx, &flags, &exe, Some(&lib)) {
        return false;
    }
    println!("cinstall: mesh_basics built with pkg-config against the installed tree and ran");
    cinstall_static(ctx, &base, &root)
}

/// Compiles `ffi/examples/mesh_basics.c` with `flags` into `exe` and runs it (with
/// `LD_LIBRARY_PATH` = `lib` when given); `true` when it printed its graph.
fn build_and_run_mesh_basics(ctx: &Ctx, flags: &str, exe: &Path, lib: Option<&Path>) -> bool {
    let mut cc = Command::new("gcc");
    cc.args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"])
        .arg(ctx.root.join("ffi/examples/mesh_basics.c"))
        .args(flags.split_whitespace())
        .arg("-o")
        .arg(exe);
    if !run(&mut cc) {
        return false;
    }
    let mut prog = Command::new(exe);
    if let Some(lib) = lib {
        prog.env("LD_LIBRARY_PATH", lib);
    }
    let (ran, out, err) = capture(&mut prog);
    if !ran || !out.starts_with("offsets ") {
        println!("xtask: the build of mesh_basics with {flags} failed:\n{out}{err}");
        return false;
    }
    true
}

/// The second pkg-config file, `deform_kernel-static`, links the archive even though the
/// shared library is installed beside it: the program must not need `libdeform_kernel.so`
/// and must run without `LD_LIBRARY_PATH`.
fn cinstall_static(ctx: &Ctx, base: &Path, root: &Path) -> bool {
    let mut pc = Command::new("pkg-config");
    pc.args(["--cflags", "--libs", "deform_kernel-static"])
        .env("PKG_CONFIG_PATH", root.join("usr/share/pkgconfig"));
    let (found, flags, err) = capture(&mut pc);
    println!("$ {} -> {}", show(&pc), flags.trim());
    if !found {
        print!("{err}");
        return false;
    }
    let exe = base.join("mesh_basics_static");
    if !build_and_run_mesh_basics(ctx, &flags, &exe, None) {
        return false;
    }
    let (read, dynamic, _) = capture(Command::new("readelf").arg("-d").arg(&exe));
    if !read || dynamic.contains("libdeform_kernel") {
        println!("xtask: mesh_basics_static needs the shared library:\n{dynamic}");
        return false;
    }
    println!("cinstall: mesh_basics linked statically via deform_kernel-static.pc and ran");
    true
}

pub(crate) fn is_root() -> bool {
    let (ok, out, _) = capture(Command::new("id").arg("-u"));
    ok && out.trim() == "0"
}

// ---------------------------------------------------------------------------------------------
// cross builds and the panic check
