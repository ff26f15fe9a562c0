//! Panic-check calls for the multigrid preconditioner (`deform_kernel::spring` AMG entry
//! points): the size query, the setup, one V-cycle and the AMG-CG solve, for `f32` and `f64`,
//! value widths 1, 2 and 6, both smoothers.
//!
//! The system is an opaque 8-node path with both ends fixed (small enough for stack buffers,
//! large enough to coarsen into two levels).

use core::hint::black_box;

use deform_kernel::spring::{
    amg_precondition_scratch_len, amg_setup_work_len, solve_linear_amg_scratch_len,
    solve_linear_with_scratch_len, AmgHierarchy, AmgOptions, AmgSmoother, LinearMethod,
    LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{Graph, Real};

/// Nodes of the path.
const N: usize = 8;
/// `u32` work entries (`4 (N + E) + 64` with `E = 14`).
const WORK: usize = 4 * (N + 14) + 64;
/// Hierarchy buffer entries (generous for the path).
const INDEX: usize = 256;
const VALUES: usize = 256;
/// Solve scratch items.
const SCRATCH: usize = 8 * N;

/// Calls every AMG entry point with opaque inputs.
pub fn exercise() {
    run::<f32, 1, 2>();
    run::<f64, 2, 6>();
}

#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

#[inline(never)]
fn run<T: Real, const V: usize, const W: usize>() {
    let offsets: &[u32] = bb(&[0, 1, 3, 5, 7, 9, 11, 13, 14]);
    let targets: &[u32] = bb(&[1, 0, 2, 1, 3, 2, 4, 3, 5, 4, 6, 5, 7, 6]);
    let Ok(g) = Graph::new(offsets, targets) else {
        return;
    };
    let k: [T; 14] = bb([T::ONE; 14]);
    let fixed: &[u8] = bb(&[1, 0, 0, 0, 0, 0, 0, 1]);
    let mut s = [0u32; N];
    let Ok(sys) = SpringSystem::new(bb(g), &k[..], fixed, &mut s[..]) else {
        return;
    };
    let sys = bb(sys);
    for smoother in bb([AmgSmoother::Jacobi, AmgSmoother::Chebyshev]) {
        let opts = bb(AmgOptions {
            smoother,
            max_coarse: 2,
            ..AmgOptions::<T>::default()
        });
        let mut work = [0u32; WORK];
        keep(AmgHierarchy::setup_work_len(&sys));
        keep(amg_setup_work_len(bb(N), bb(usize::MAX - 3)));
        keep(AmgHierarchy::setup_len(&sys, &opts, bb(&mut work[..])));
        let mut index = [0u32; INDEX];
        let mut values = [T::ZERO; VALUES];
        let Ok(h) = AmgHierarchy::setup(
            &sys,
            &opts,
            bb(&mut work[..]),
            bb(&mut index[..]),
            bb(&mut values[..]),
        ) else {
            continue;
        };
        let h = bb(h);
        keep(h.levels());
        keep(h.level_size(bb(1)));
        keep(h.level_entries(bb(1)));
        keep(h.coarse_unknowns());
        keep(h.prolongator_row(bb(0), bb(1)));
        solve::<T, V>(&sys, &h);
        solve::<T, W>(&sys, &h);
    }
}

#[inline(never)]
fn solve<T: Real, const V: usize>(sys: &SpringSystem<'_, T>, h: &AmgHierarchy<'_, T>) {
    let x: [[T; V]; N] = bb([[T::HALF; V]; N]);
    let mut scratch = [[T::ZERO; V]; SCRATCH];
    let len = solve_linear_amg_scratch_len(h);
    let mut y = x;
    let opts: SolveOptions<T> = bb(SolveOptions::default());
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    keep(sys.solve_linear_amg(h, bb(&mut y[..]), &opts, bb(sc)));
    keep(&y);
    let mut z = [[T::ZERO; V]; N];
    let len = amg_precondition_scratch_len(h);
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    keep(sys.amg_precondition(h, bb(&x[..]), bb(&mut z[..]), bb(sc)));
    keep(&z);
    // Through the solver handle, every kind, split ones with opaque owned ranges.
    let split = Opaque([bb(0..N / 2), bb(N / 2..N)]);
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    for solver in [
        LinearSolver::Amg(h),
        LinearSolver::Method(cg),
        LinearSolver::DistributedAmg(h, &split),
        LinearSolver::Distributed(bb(cg), &split),
    ] {
        let solver = bb(solver);
        let len = solve_linear_with_scratch_len(&solver, bb(N));
        let mut y = x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        keep(sys.solve_linear_with(bb(&mut y[..]), solver, &opts, bb(sc)));
        keep(&y);
    }
}

/// A collective whose owned ranges and messages the optimiser cannot see.
#[derive(Debug)]
struct Opaque([core::ops::Range<usize>; 2]);

impl<T: Real> deform_kernel::spring::Collective<T> for Opaque {
    fn owned(&self) -> &[core::ops::Range<usize>] {
        bb(&self.0[..])
    }
    fn sum_words(&self, words: &mut [i64]) {
        bb(words);
    }
    fn max(&self, values: &mut [T]) {
        bb(values);
    }
    fn share(&self, field: &mut [T], width: usize) {
        bb((field, width));
    }
}
