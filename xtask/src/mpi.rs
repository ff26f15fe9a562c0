//! The `mpi` step (issue 16), after the `install` step has put OpenMPI and libclang in place:
//!
//! 1. `mpi/`'s `deform-mpi-check` under `mpirun --oversubscribe -np 1, 2, 3`: spring sweeps
//!    and whole solves (CG + Jacobi, multigrid CG) split across the ranks by recursive
//!    coordinate bisection give the serial bits, on a generated 2D and 3D mesh;
//!    then `deform-mpi-check --partitioned` under `-np 1, 2, 3, 4, 7`: each rank holds only
//!    its partition (owned nodes, ghost layers of depth 1 or 2, local cells, the pattern;
//!    RCB and random partitions, shuffled local numbering) and the kernel's partitioned CG +
//!    Jacobi gives the serial bits; six bad partitions are rejected on every rank; and the
//!    partitioned quaternion deformation with spring propagation (`deform_spring_partitioned`,
//!    the boundary gathered through the exchange) gives the serial `deform_spring_with` bits
//!    on every owned node, with inconsistent boundaries rejected on every rank;
//! 2. the `deform` tool built with `--features mpi`: `mpirun -np N deform move …` writes a
//!    file byte-identical to the serial `deform move`, for the spring and quaternion methods,
//!    on a generated triangle mesh, a generated viscous (quad + triangle) mesh and the public
//!    3D SU2 half-model in `cli/tests/data`;
//!    then `deform move --distributed` under `-np 1, 2, 3` (each rank reads a byte range of
//!    the file, holds its block of nodes with one ghost layer, solves CG + Jacobi on it and
//!    writes its own rows), the linear springs on the two NACA meshes and the quaternion
//!    method on those and the 3D half-model: byte-identical to the serial `--solver cg` run,
//!    the same exit status as the serial run without `--allow-folds`, and options it does
//!    not run refused with nothing written;
//! 3. `ffi/examples/mpi_deform.c`, built with `mpicc` against the static C library: a C
//!    solver with its own (interleaved) partition sweeps its rows with the kernel, merges the
//!    exact residual words with `MPI_Allreduce` and checks the serial bits; and
//!    `ffi/examples/mpi_partitioned.c` under `-np 1, 2, 3, 4, 7`: each rank builds only its
//!    local view (owned columns, ghost columns, local cells, the lists), solves through
//!    `dk_partitioned_spring_solve` with the callbacks of `mpi/c/deform_kernel_mpi.c`, and
//!    the assembled field equals the serial `dk_spring_solve_linear` bit for bit; bad inputs
//!    (a duplicate global id, a short ghost list, failing callbacks) are rejected on every
//!    rank; then the same views through `dk_partitioned_deform_spring` (the quaternion
//!    deformation with spring propagation): the serial `dk_deform_spring` bits, and bad
//!    boundaries and a failing callback rejected on every rank;
//!    `ffi/examples/mpi_partitioned.f90`, the same from Fortran (built with `mpif90`, its
//!    communicator through `dk_mpi_exchange_new_f`), under the same rank counts;
//! 4. `make install` of `mpi/c` (`libdeform_kernel_mpi` and `deform_kernel_mpi.pc`) into a
//!    staging prefix, and `mpi_partitioned.c` built by `gcc` with nothing but `pkg-config
//!    --cflags --libs deform_kernel_mpi`, run under `-np 3`.

use crate::ctx::Ctx;
use crate::install::is_root;
use crate::process::run;
use std::path::Path;
use std::process::Command;

/// Rank counts the step runs.
pub(crate) const MPI_RANKS: &[usize] = &[1, 2, 3];

/// Rank counts of the partitioned-storage checks (7 oversubscribed on small machines).
pub(crate) const PARTITIONED_RANKS: &[usize] = &[1, 2, 3, 4, 7];

/// `mpirun [--allow-run-as-root] --oversubscribe -np N`.
fn mpirun(np: usize) -> Command {
    let mut c = Command::new("mpirun");
    if is_root() {
        c.arg("--allow-run-as-root");
    }
    c.args(["--oversubscribe", "-np", &np.to_string()]);
    c
}

/// Builds and runs the MPI checks.
pub(crate) fn mpi_check(ctx: &Ctx) -> bool {
    let manifest = ctx.root.join("mpi/Cargo.toml");
    let manifest = manifest.to_string_lossy();
    if !run(&mut ctx.cargo(&["build", "--release", "--manifest-path", &manifest])) {
        return false;
    }
    let exe = ctx.root.join("mpi/target/release/deform-mpi-check");
    let mut ok = true;
    for &np in MPI_RANKS {
        ok &= run(mpirun(np).arg(&exe).current_dir(&ctx.root));
    }
    for &np in PARTITIONED_RANKS {
        ok &= run(mpirun(np)
            .arg(&exe)
            .arg("--partitioned")
            .current_dir(&ctx.root));
    }
    ok && deform_move_under_mpi(ctx) && distributed_move(ctx) && c_example(ctx)
}

/// `ffi/examples/mpi_deform.c` (replicated data) and `ffi/examples/mpi_partitioned.c`
/// (distributed data through `dk_partitioned_spring_solve` and `mpi/c/deform_kernel_mpi.c`)
/// under mpirun.
fn c_example(ctx: &Ctx) -> bool {
    // Where host-tests build the C library (CARGO_TARGET_TMPDIR/capi-build): reused.
    let target = ctx.root.join("target/tmp/capi-build");
    let capi = ctx.root.join(crate::ci::CAPI_MANIFEST);
    let mut build = ctx.cargo(&["build", "--release", "--manifest-path"]);
    build.arg(&capi).arg("--target-dir").arg(&target);
    if !run(&mut build) {
        return false;
    }
    let examples: [(&str, &[&str], &[usize]); 2] = [
        ("mpi_deform", &[], MPI_RANKS),
        (
            "mpi_partitioned",
            &["-Impi/c", "mpi/c/deform_kernel_mpi.c"],
            PARTITIONED_RANKS,
        ),
    ];
    let mut ok = true;
    for (name, extra, ranks) in examples {
        let exe = target.join(name);
        let mut cc = Command::new("mpicc");
        cc.args([
            "-std=c11",
            "-O2",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-Iffi/generated",
        ])
        .args(extra)
        .arg(format!("ffi/examples/{name}.c"))
        .arg(target.join("release/libdeform_kernel.a"))
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .current_dir(&ctx.root);
        if !run(&mut cc) {
            return false;
        }
        for &np in ranks {
            ok &= run(mpirun(np).arg(&exe).current_dir(&ctx.root));
        }
    }
    ok && fortran_example(ctx, &target) && installed_library(ctx)
}

/// `mpi/c/Makefile`'s `make install` of `libdeform_kernel_mpi` into a staging prefix, then
/// `ffi/examples/mpi_partitioned.c` built by plain `gcc` with only what `pkg-config --cflags
/// --libs deform_kernel_mpi` gives (deform_kernel's and MPI's flags through its `Requires`),
/// linked to both shared libraries and run under `mpirun -np 3`. deform_kernel comes from
/// the `cinstall` step's staged tree (installed again here when it is missing), seen through
/// a copy of its `.pc` file whose prefix points into the stage.
fn installed_library(ctx: &Ctx) -> bool {
    let staged = ctx.root.join("target/cinstall/root/usr");
    let staged_pc = staged.join("lib/pkgconfig/deform_kernel.pc");
    if !staged_pc.exists() && !crate::install::cinstall(ctx) {
        return false;
    }
    let prefix = ctx.root.join("target/cinstall/mpi");
    let _ = std::fs::remove_dir_all(&prefix);
    let mut make = Command::new("make");
    make.args(["-C", "mpi/c", "install"])
        .arg(format!("BUILD={}", prefix.join("build").display()))
        .arg(format!("PREFIX={}", prefix.display()))
        .arg(format!("DK_CFLAGS=-I{}", staged.join("include").display()))
        .current_dir(&ctx.root);
    if !run(&mut make) {
        return false;
    }
    let pc_dir = prefix.join("lib/pkgconfig");
    let relocated = std::fs::read_to_string(&staged_pc)
        .map(|pc| pc.replace("prefix=/usr\n", &format!("prefix={}\n", staged.display())));
    if relocated
        .and_then(|pc| std::fs::write(pc_dir.join("deform_kernel.pc"), pc))
        .is_err()
    {
        println!("xtask: cannot relocate {}", staged_pc.display());
        return false;
    }
    let mut pc = Command::new("pkg-config");
    pc.args(["--cflags", "--libs", "deform_kernel_mpi"])
        .env("PKG_CONFIG_PATH", &pc_dir);
    let (found, flags, err) = crate::process::capture(&mut pc);
    println!(
        "$ pkg-config --cflags --libs deform_kernel_mpi -> {}",
        flags.trim()
    );
    if !found {
        print!("{err}");
        return false;
    }
    let exe = prefix.join("mpi_partitioned_pc");
    let mut cc = Command::new("gcc");
    cc.args(["-std=c11", "-O2", "-Wall", "-Wextra", "-Werror"])
        .arg("ffi/examples/mpi_partitioned.c")
        .args(flags.split_whitespace())
        .args(["-lm", "-o"]) // the example's own sin and cos
        .arg(&exe)
        .current_dir(&ctx.root);
    let libs = format!(
        "{}:{}",
        staged.join("lib").display(),
        prefix.join("lib").display()
    );
    let ok = run(&mut cc)
        && run(mpirun(3)
            .args(["-x", "LD_LIBRARY_PATH"])
            .arg(&exe)
            .env("LD_LIBRARY_PATH", libs)
            .current_dir(&ctx.root));
    if ok {
        println!(
            "mpi: mpi_partitioned built with pkg-config deform_kernel_mpi (installed) and ran"
        );
    }
    ok
}

/// `ffi/examples/mpi_partitioned.f90` (the same solve from Fortran, its communicator through
/// `dk_mpi_exchange_new_f`) under mpirun, against the C library built in `target`.
fn fortran_example(ctx: &Ctx, target: &Path) -> bool {
    let work = target.join("fortran-mpi");
    if std::fs::create_dir_all(&work).is_err() {
        println!("xtask: cannot create {}", work.display());
        return false;
    }
    let object = work.join("deform_kernel_mpi.o");
    let mut cc = Command::new("mpicc");
    cc.args([
        "-std=c11",
        "-O2",
        "-Wall",
        "-Werror",
        "-Iffi/generated",
        "-c",
    ])
    .arg("mpi/c/deform_kernel_mpi.c")
    .arg("-o")
    .arg(&object)
    .current_dir(&ctx.root);
    let exe = work.join("mpi_partitioned_f90");
    let mut fc = Command::new("mpif90");
    fc.args(["-O2", "-J"])
        .arg(&work)
        .args([
            "ffi/generated/deform_kernel.f90",
            "ffi/examples/mpi_partitioned.f90",
        ])
        .arg(&object)
        .arg(target.join("release/libdeform_kernel.a"))
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe)
        .current_dir(&ctx.root);
    if !(run(&mut cc) && run(&mut fc)) {
        return false;
    }
    let mut ok = true;
    for &np in PARTITIONED_RANKS {
        ok &= run(mpirun(np).arg(&exe).current_dir(&ctx.root));
    }
    ok
}

/// `deform move` under mpirun against the serial run, byte for byte.
fn deform_move_under_mpi(ctx: &Ctx) -> bool {
    // The workspace's target directory: only deform-cli and the MPI crates compile anew.
    if !run(&mut ctx.cargo(&["build", "-p", "deform-cli", "--features", "mpi"])) {
        return false;
    }
    let target = ctx.root.join("target");
    let deform = target.join("debug/deform");
    let work = target.join("mpi-runs");
    if std::fs::create_dir_all(&work).is_err() {
        println!("xtask: cannot create {}", work.display());
        return false;
    }
    let mut ok = true;
    for kind in ["inviscid", "viscous"] {
        ok &= run(Command::new(&deform)
            .args(["mesh", "naca", "--kind", kind, "--out"])
            .arg(work.join(format!("{kind}.su2"))));
    }
    let sphere = ctx.root.join("cli/tests/data/sphere_slice_2syms.su2");
    let cases: [(&str, &Path, &[&str]); 3] = [
        (
            "inviscid",
            &work.join("inviscid.su2"),
            &[
                "--marker", "airfoil", "--rotate", "-10", "--center", "0.25,0",
            ],
        ),
        (
            "viscous",
            &work.join("viscous.su2"),
            &[
                "--marker", "airfoil", "--rotate", "-5", "--center", "0.25,0",
            ],
        ),
        (
            "sphere",
            &sphere,
            &["--marker", "wall", "--translate", "0.05,0,0"],
        ),
    ];
    for (name, mesh, motion) in cases {
        for method in ["spring", "quaternion"] {
            let serial = work.join(format!("{name}_{method}_serial.su2"));
            let mut c = Command::new(&deform);
            c.arg("move")
                .arg(mesh)
                .args(motion)
                // Spring runs may invert cells: compared anyway (exit 4 otherwise).
                .args(["--method", method, "--allow-folds", "--out"]);
            ok &= run(c.arg(&serial));
            for &np in MPI_RANKS {
                let split = work.join(format!("{name}_{method}_np{np}.su2"));
                let mut c = mpirun(np);
                c.arg(&deform).arg("move").arg(mesh).args(motion);
                ok &= run(c
                    .args(["--method", method, "--allow-folds", "--out"])
                    .arg(&split));
                let same = matches!(
                    (std::fs::read(&serial), std::fs::read(&split)),
                    (Ok(a), Ok(b)) if a == b
                );
                println!(
                    "deform move {name} --method {method}, {np} rank(s): {}",
                    if same {
                        "byte-identical to serial"
                    } else {
                        "DIFFERS from serial"
                    }
                );
                ok &= same;
            }
        }
    }
    ok
}

/// `deform move --distributed` (each rank reads, holds and writes only its part) against the
/// serial `--solver cg` run, for the linear springs and the quaternion method: the same
/// bytes, the same exit status without `--allow-folds`, and options the distributed path
/// does not run refused with nothing written.
fn distributed_move(ctx: &Ctx) -> bool {
    let target = ctx.root.join("target");
    let deform = target.join("debug/deform");
    let work = target.join("mpi-runs");
    // A small viscous mesh (2,048 nodes) keeps the quaternion runs short.
    let small = work.join("viscous_small.su2");
    let made = run(Command::new(&deform)
        .args([
            "mesh",
            "naca",
            "--kind",
            "viscous",
            "--boundary-layers",
            "12",
        ])
        .args(["--surface-points", "64", "--radial-points", "32", "--out"])
        .arg(&small));
    let sphere = ctx.root.join("cli/tests/data/sphere_slice_2syms.su2");
    let (inviscid, viscous) = (work.join("inviscid.su2"), work.join("viscous.su2"));
    // (name, mesh, motion, method, whether the exit status without --allow-folds is compared)
    let cases: [(&str, &Path, &[&str], &str, bool); 6] = [
        (
            "inviscid",
            &inviscid,
            &[
                "--marker", "airfoil", "--rotate", "-10", "--center", "0.25,0",
            ],
            "spring",
            true,
        ),
        // The rotation centre from the moved nodes (summed in the serial order).
        (
            "viscous",
            &viscous,
            &["--marker", "airfoil", "--rotate", "3"],
            "spring",
            true,
        ),
        // The quaternion method: rotations about the moved nodes' centroid (2D), about a
        // given centre (3D), and a translation (3D; the origin is then the kernel's centroid
        // of the gathered boundary, summed in the serial order).
        (
            "viscous_small",
            &small,
            &["--marker", "airfoil", "--rotate", "3"],
            "quaternion",
            false,
        ),
        // Stopped after 20 iterations: cells folded, exit 4 without --allow-folds.
        (
            "viscous_small_unconverged",
            &small,
            &[
                "--marker",
                "airfoil",
                "--rotate",
                "3",
                "--max-iter",
                "20",
                "--allow-unconverged",
            ],
            "quaternion",
            true,
        ),
        (
            "sphere_rotate",
            &sphere,
            &[
                "--marker", "wall", "--rotate", "5", "--axis", "0,0,1", "--center", "0,0,0",
            ],
            "quaternion",
            false,
        ),
        (
            "sphere_translate",
            &sphere,
            &["--marker", "wall", "--translate", "0.05,0.02,0"],
            "quaternion",
            false,
        ),
    ];
    let mut ok = made;
    for (name, mesh, motion, method, policy) in cases {
        ok &= distributed_case(&deform, &work, (name, mesh, motion), method, policy);
    }
    ok && distributed_refusals(&deform, &work)
}

/// One mesh, motion and method: `deform move --distributed` under `-np 1, 2, 3` against the
/// serial `--solver cg` run, byte for byte, and with `policy` the same exit status without
/// `--allow-folds` under 2 ranks.
fn distributed_case(
    deform: &Path,
    work: &Path,
    (name, mesh, motion): (&str, &Path, &[&str]),
    method: &str,
    policy: bool,
) -> bool {
    let status = |c: &mut Command| c.status().ok().and_then(|s| s.code());
    // `np` = 0: the serial run; otherwise `--distributed` under `mpirun -np np`.
    let base = |np: usize| {
        let mut c = if np == 0 {
            Command::new(deform)
        } else {
            let mut c = mpirun(np);
            c.arg(deform);
            c
        };
        c.arg("move").arg(mesh).args(motion);
        c.args(["--method", method, "--solver", "cg"]);
        if np > 0 {
            c.arg("--distributed");
        }
        c
    };
    let serial = work.join(format!("{name}_{method}_distributed_serial.su2"));
    let mut ok = run(base(0).arg("--allow-folds").arg("--out").arg(&serial));
    for &np in MPI_RANKS {
        let out = work.join(format!("{name}_{method}_distributed_np{np}.su2"));
        ok &= run(base(np).arg("--allow-folds").arg("--out").arg(&out));
        let same = matches!(
            (std::fs::read(&serial), std::fs::read(&out)),
            (Ok(a), Ok(b)) if a == b
        );
        println!(
            "deform move --distributed {name} --method {method}, {np} rank(s): {}",
            if same {
                "byte-identical to serial"
            } else {
                "DIFFERS from serial"
            }
        );
        ok &= same;
    }
    if !policy {
        return ok;
    }
    // The failure policy without --allow-folds: the same exit status (4 when the motion
    // inverted cells).
    let serial = status(base(0).arg("--out").arg(work.join("policy.su2")));
    let split = status(base(2).arg("--out").arg(work.join("policy_np.su2")));
    println!(
        "deform move --distributed {name} --method {method} without --allow-folds, 2 ranks: exit status {split:?} (serial {serial:?})"
    );
    ok && split == serial && serial.is_some()
}

/// Options the distributed path does not run (the default multigrid solver, IDW, `--reach`),
/// refused under `-np 2` with nothing written.
fn distributed_refusals(deform: &Path, work: &Path) -> bool {
    let status = |c: &mut Command| c.status().ok().and_then(|s| s.code());
    let refusals: [(&str, &[&str]); 3] = [
        (
            "--method quaternion --solver amg (the default)",
            &["--method", "quaternion", "--solver", "amg"],
        ),
        (
            "--method idw --solver cg",
            &["--method", "idw", "--solver", "cg"],
        ),
        (
            "--method quaternion --solver cg --reach 1",
            &["--method", "quaternion", "--solver", "cg", "--reach", "1"],
        ),
    ];
    let mut ok = true;
    for (what, options) in refusals {
        let refused = work.join("refused.su2");
        let _ = std::fs::remove_file(&refused);
        let mut c = mpirun(2);
        c.arg(deform).arg("move").arg(work.join("inviscid.su2"));
        c.args(["--marker", "airfoil", "--rotate", "5", "--distributed"]);
        let code = status(c.args(options).arg("--out").arg(&refused));
        let clean = code.is_some_and(|c| c != 0) && !refused.exists();
        println!(
            "deform move --distributed with {what}: {}",
            if clean {
                "refused, nothing written"
            } else {
                "NOT REFUSED"
            }
        );
        ok &= clean;
    }
    ok
}
