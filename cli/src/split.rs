//! `deform move` under `mpirun`: the spring solves' rows split across processes.
//!
//! Every process reads the mesh and runs the whole command; only the spring solves (linear
//! springs, and the quaternion method's propagation) divide their rows, through the kernel's
//! `LinearSolver::Distributed*` with a [`Splitter`]'s collective. Their sums are exact and
//! their row updates are the serial ones, so every process ends with the serial bits and the
//! first one writes a file byte-identical to a serial run. Methods whose solves visit nodes in
//! order (Gauss–Seidel, SSOR, the angle springs' node-wise method) and sliding solves are
//! refused with a message rather than run differently.

use deform_kernel::spring::Collective;

use crate::args::{Method, MoveArgs, Solver};
use crate::error::CliError;

/// The processes a `deform move` runs on (the `mpi` feature implements it over MPI).
pub trait Splitter: std::fmt::Debug {
    /// Number of processes.
    fn size(&self) -> usize;
    /// Whether this process writes files and reports.
    fn is_root(&self) -> bool;
    /// The collective for a mesh with these points and this (symmetric CSR) graph: a
    /// deterministic partition of the points, halo exchanges along the graph.
    fn collective<'s>(
        &'s self,
        points: &[[f64; 3]],
        offsets: &[u32],
        targets: &[u32],
    ) -> Box<dyn Collective<f64> + 's>;

    /// Refuses what cannot run split (with more than one process).
    fn check_move(&self, a: &MoveArgs) -> Result<(), CliError> {
        if self.size() <= 1 {
            return Ok(());
        }
        let refuse = |what: &str| {
            Err(CliError::Invalid(format!(
                "under mpirun with {} processes: {what} (run it without mpirun)",
                self.size()
            )))
        };
        if matches!(a.method(), Method::AngleDirect | Method::AngleCg) {
            return refuse("the angle-spring methods are not split across processes yet");
        }
        if !a.slide.is_empty() {
            return refuse("--slide solves are not split across processes yet");
        }
        let springs = matches!(a.method(), Method::Spring | Method::Quaternion);
        if springs && matches!(a.solver, Solver::Gs | Solver::CgSsor | Solver::Jacobi) {
            return refuse(
                "--solver gs, cg-ssor and jacobi are not split across processes (use amg or cg)",
            );
        }
        Ok(())
    }
}

#[cfg(feature = "mpi")]
pub use over_mpi::MpiSplitter;

#[cfg(feature = "mpi")]
mod over_mpi {
    use super::Splitter;
    use deform_kernel::spring::Collective;
    use deform_mpi::{rcb, MpiCollective};
    use mpi::topology::SimpleCommunicator;
    use mpi::traits::Communicator;

    /// All processes of `MPI_COMM_WORLD`, partitioned by recursive coordinate bisection.
    pub struct MpiSplitter<'w> {
        world: &'w SimpleCommunicator,
    }

    impl std::fmt::Debug for MpiSplitter<'_> {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.debug_struct("MpiSplitter")
                .field("size", &self.size())
                .finish()
        }
    }

    impl<'w> MpiSplitter<'w> {
        /// The splitter over `world`.
        pub fn new(world: &'w SimpleCommunicator) -> Self {
            MpiSplitter { world }
        }
    }

    impl Splitter for MpiSplitter<'_> {
        fn size(&self) -> usize {
            self.world.size() as usize
        }
        fn is_root(&self) -> bool {
            self.world.rank() == 0
        }
        fn collective<'s>(
            &'s self,
            points: &[[f64; 3]],
            offsets: &[u32],
            targets: &[u32],
        ) -> Box<dyn Collective<f64> + 's> {
            let parts = rcb(points, self.size());
            Box::new(MpiCollective::with_graph(
                self.world, &parts, offsets, targets,
            ))
        }
    }
}
