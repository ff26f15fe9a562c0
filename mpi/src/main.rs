//! Linear-spring Jacobi sweeps split across MPI ranks give the serial bits.
//!
//! `mpirun -np N target/release/deform-mpi-check` (built with `cargo build --release` here;
//! `cargo xtask ci --step mpi` runs N = 1, 2, 3). On a generated 2D mesh (NACA 2412,
//! triangles) and a 3D one (the same mesh extruded into prisms):
//!
//! - nodes are partitioned by recursive coordinate bisection, so a rank owns an arbitrary set
//!   of node numbers, not a range;
//! - each rank sweeps its own nodes with the kernel's range sweep (`jacobi_sweep`, one call
//!   per run of consecutive owned numbers), exchanges its new values with the others
//!   (`MPI_Allgatherv`; replicated field, the simplest correct exchange), and merges the
//!   sweeps' exact residual sums (`ExactSum::to_words`, `MPI_Allreduce` with `MPI_SUM` on
//!   `i64`) and maximum changes (`MPI_MAX`);
//! - rank 0 runs the same sweeps serially over all nodes and compares every value and every
//!   sweep's residual bit for bit.
//!
//! Exit status 0 only if everything matches on every rank.

use deform_kernel::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use deform_kernel::spring::{
    solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, LinearMethod, LinearSolver,
    Preconditioner, SolveOptions,
};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};
use deform_mpi::{boundary_values, rcb, runs, MpiCollective, WholeSprings};
use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::traits::*;

/// Sweeps per case.
const SWEEPS: usize = 40;

/// One case: serial sweeps on rank 0, split sweeps on every rank, compared bit for bit.
fn check<const D: usize, C: Communicator>(world: &C, name: &str, mesh: &Mesh<D>) -> bool {
    let rank = world.rank() as usize;
    let size = world.size() as usize;
    let n = mesh.node_count();
    let whole = WholeSprings::new(mesh);
    let (offsets, targets, fixed) = (&whole.offsets, &whole.targets, &whole.fixed);
    let sys = whole.system();
    let x0 = boundary_values(mesh, fixed);

    // Serial reference (rank 0 only; the others take its verdict).
    let mut serial_residuals = Vec::new();
    let mut serial = x0.clone();
    if rank == 0 {
        let mut next = serial.clone();
        for _ in 0..SWEEPS {
            let s = sys.jacobi_sweep(0..n, &serial, &mut next).expect("sweep");
            serial_residuals.push((s.residual_sq.to_bits(), s.max_change.to_bits()));
            std::mem::swap(&mut serial, &mut next);
        }
    }

    // Partitioned sweeps.
    let parts = rcb(&mesh.points, size);
    let mine = parts[rank].clone();
    let my_runs = runs(&mine);
    let counts: Vec<i32> = parts.iter().map(|p| (p.len() * D) as i32).collect();
    let displs: Vec<i32> = counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect();
    let order: Vec<u32> = parts.iter().flatten().copied().collect();
    let mut x = x0.clone();
    let mut out = x0.clone();
    let mut residuals = Vec::new();
    let mut plain_residuals = Vec::new();
    for _ in 0..SWEEPS {
        let mut sum = ExactSum::new();
        let mut plain = 0.0f64;
        let mut max_change = 0.0f64;
        for r in &my_runs {
            let s = sys.jacobi_sweep(r.clone(), &x, &mut out).expect("sweep");
            sum.merge(&s.residual_sum);
            plain += s.residual_sq;
            max_change = max_change.max(s.max_change);
        }
        // Exchange the owned values (every rank ends with the whole new field).
        let send: Vec<f64> = mine.iter().flat_map(|&i| out[i as usize]).collect();
        let mut recv = vec![0.0f64; n * D];
        {
            let mut part = PartitionMut::new(&mut recv[..], &counts[..], &displs[..]);
            world.all_gather_varcount_into(&send[..], &mut part);
        }
        for (&i, v) in order.iter().zip(recv.chunks_exact(D)) {
            x[i as usize].copy_from_slice(v);
        }
        // Merge the exact sums and the maxima.
        let words = sum.to_words();
        let mut total = [0i64; EXACT_SUM_WORDS];
        world.all_reduce_into(&words[..], &mut total[..], SystemOperation::sum());
        let mut global_max = 0.0f64;
        world.all_reduce_into(&max_change, &mut global_max, SystemOperation::max());
        let residual: f64 = ExactSum::from_words(total).value();
        residuals.push((residual.to_bits(), global_max.to_bits()));
        // For contrast: the ranks' rounded residuals added as floats (what a plain MPI_SUM of
        // partial sums gives).
        let mut plain_total = 0.0f64;
        world.all_reduce_into(&plain, &mut plain_total, SystemOperation::sum());
        plain_residuals.push((plain_total.to_bits(), global_max.to_bits()));
    }

    let mut ok = 1i32;
    if rank == 0 {
        let values_equal = x
            .iter()
            .zip(&serial)
            .all(|(a, b)| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits()));
        let sums_equal = residuals == serial_residuals;
        let plain_differ = plain_residuals
            .iter()
            .zip(&serial_residuals)
            .filter(|(a, b)| a != b)
            .count();
        ok = i32::from(values_equal && sums_equal);
        println!(
            "{name}: {n} nodes, {SWEEPS} Jacobi sweeps on {size} rank(s) (owned: {:?}, rank 0 in {} runs): values {}, exact residual sums {} (plain float merge: {plain_differ} of {SWEEPS} differ)",
            parts.iter().map(Vec::len).collect::<Vec<_>>(),
            my_runs.len(),
            if values_equal { "bit-identical" } else { "DIFFER" },
            if sums_equal { "bit-identical" } else { "DIFFER" },
        );
    }
    // Whole solves with the rows split: CG + Jacobi and multigrid-preconditioned CG through
    // `LinearSolver::Distributed*`, against the serial solves.
    let comm = MpiCollective::with_graph(world, &parts, offsets, targets);
    let options = SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 20_000,
        update_tol: 0.0,
    };
    let amg_options = AmgOptions::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &amg_options, &mut work).expect("amg sizes");
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0f64; sizes.values];
    let h = AmgHierarchy::setup(&sys, &amg_options, &mut work, &mut index, &mut values)
        .expect("amg setup");
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    for (label, serial_solver, split_solver) in [
        (
            "CG + Jacobi",
            LinearSolver::Method(cg),
            LinearSolver::Distributed(cg, &comm),
        ),
        (
            "AMG-CG",
            LinearSolver::Amg(&h),
            LinearSolver::DistributedAmg(&h, &comm),
        ),
    ] {
        let mut a = x0.clone();
        let mut scratch = vec![[0.0; D]; solve_linear_with_scratch_len(&serial_solver, n)];
        let ra = sys
            .solve_linear_with(&mut a, serial_solver, &options, &mut scratch)
            .expect("serial solve");
        let mut b = x0.clone();
        let rb = sys
            .solve_linear_with(&mut b, split_solver, &options, &mut scratch)
            .expect("split solve");
        let same = a
            .iter()
            .zip(&b)
            .all(|(a, b)| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits()))
            && ra.iterations == rb.iterations
            && ra.residual.to_bits() == rb.residual.to_bits()
            && rb.converged;
        let mut all_same = i32::from(same);
        world.all_reduce_into(&i32::from(same), &mut all_same, SystemOperation::min());
        if rank == 0 {
            println!(
                "{name}: {label} on {size} rank(s): {} iterations, residual {:.3e}, solution {}",
                rb.iterations,
                rb.residual,
                if all_same == 1 {
                    "bit-identical to serial on every rank"
                } else {
                    "DIFFERS"
                }
            );
        }
        if all_same != 1 {
            ok = 0;
        }
    }
    world.process_at_rank(0).broadcast_into(&mut ok);
    ok == 1
}

/// `--bench`: the split solves on the 234,496-node NACA 2412 mesh of `cargo xtask bench`,
/// timed (median of 3, wall clock of the slowest rank), for docs/scaling.md.
fn bench<C: Communicator>(world: &C) {
    let grid = AirfoilGrid {
        surface_points: 1024,
        radial_points: 229,
        first_layer: 1e-5,
        boundary_layers: 40,
        ..AirfoilGrid::default()
    };
    let mesh = naca_triangulated(&grid).expect("mesh");
    let n = mesh.node_count();
    let whole = WholeSprings::new(&mesh);
    let (offsets, targets) = (&whole.offsets, &whole.targets);
    let sys = whole.system();
    let rot =
        deform_meshgen::rotate_markers2(&mesh, &["airfoil"], AirfoilGrid::quarter_chord(), -10.0)
            .expect("rotation");
    let x0: Vec<[f64; 2]> = rot.to_field(n);
    let parts = rcb(&mesh.points, world.size() as usize);
    let comm = MpiCollective::with_graph(world, &parts, offsets, targets);
    let options = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 100_000,
        update_tol: 0.0,
    };
    let amg_options = AmgOptions::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len(&sys, &amg_options, &mut work).expect("amg sizes");
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0f64; sizes.values];
    let h = AmgHierarchy::setup(&sys, &amg_options, &mut work, &mut index, &mut values)
        .expect("amg setup");
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    for (label, solver, reps) in [
        ("AMG-CG", LinearSolver::DistributedAmg(&h, &comm), 3),
        ("CG + Jacobi", LinearSolver::Distributed(cg, &comm), 1),
    ] {
        let mut times = Vec::new();
        let mut iterations = 0;
        for _ in 0..reps {
            let mut x = x0.clone();
            let mut s = vec![[0.0; 2]; solve_linear_with_scratch_len(&solver, n)];
            world.barrier();
            let t = std::time::Instant::now();
            let r = sys
                .solve_linear_with(&mut x, solver, &options, &mut s)
                .expect("solve");
            let mine = t.elapsed().as_secs_f64();
            let mut slowest = 0.0f64;
            world.all_reduce_into(&mine, &mut slowest, SystemOperation::max());
            times.push(slowest);
            iterations = r.iterations;
        }
        times.sort_by(f64::total_cmp);
        if world.rank() == 0 {
            println!(
                "bench: {label}, {n} nodes, {} rank(s), halo {} nodes on rank 0: {iterations} iterations, {:.3} s (median of {reps})",
                world.size(),
                comm.halo_len(),
                times[times.len() / 2]
            );
        }
    }
}

mod partitioned_check;
mod partitioned_quaternion_check;

fn main() {
    let universe = mpi::initialize().expect("MPI init");
    let world = universe.world();
    if std::env::args().any(|a| a == "--bench") {
        bench(&world);
        return;
    }
    let grid = AirfoilGrid {
        surface_points: 96,
        radial_points: 24,
        ..AirfoilGrid::default()
    };
    let mesh2 = naca_triangulated(&grid).expect("2D mesh");
    let mesh3 = extrude(&mesh2, 0.5, 4).expect("3D mesh");
    let ok = if std::env::args().any(|a| a == "--partitioned") {
        let springs = partitioned_check::run(&world, &mesh2, &mesh3);
        partitioned_quaternion_check::run(&world, &mesh2, &mesh3) && springs
    } else {
        let a = check(&world, "2D NACA 2412 triangles", &mesh2);
        let b = check(&world, "3D extruded prisms", &mesh3);
        a && b
    };
    if !ok {
        std::process::exit(1);
    }
}
