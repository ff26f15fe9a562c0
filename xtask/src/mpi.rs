//! The `mpi` step (issue 16): builds `mpi/` (its own workspace: the `mpi` crate needs
//! OpenMPI and libclang, installed by the `install` step) and runs it under
//! `mpirun --oversubscribe -np 1, 2, 3`. Each run compares linear-spring sweeps split across
//! the ranks (recursive coordinate bisection, exact residual sums merged with `MPI_SUM`) with
//! the serial sweeps bit for bit, on a generated 2D and 3D mesh.

use crate::ctx::Ctx;
use crate::install::is_root;
use crate::process::run;
use std::process::Command;

/// Rank counts the step runs.
pub(crate) const MPI_RANKS: &[usize] = &[1, 2, 3];

/// Builds and runs the MPI check for every rank count in [`MPI_RANKS`].
pub(crate) fn mpi_check(ctx: &Ctx) -> bool {
    let manifest = ctx.root.join("mpi/Cargo.toml");
    let manifest = manifest.to_string_lossy();
    if !run(&mut ctx.cargo(&["build", "--release", "--manifest-path", &manifest])) {
        return false;
    }
    let exe = ctx.root.join("mpi/target/release/deform-mpi-check");
    let mut ok = true;
    for &np in MPI_RANKS {
        let mut c = Command::new("mpirun");
        if is_root() {
            c.arg("--allow-run-as-root");
        }
        c.args(["--oversubscribe", "-np", &np.to_string()])
            .arg(&exe)
            .current_dir(&ctx.root);
        ok &= run(&mut c);
    }
    ok
}
