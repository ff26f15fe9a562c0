//! Panic-check calls for the kernel's spring entry points (`deform_kernel::spring`): stiffness,
//! the validated systems, every sweep and every whole solve (all linear methods and
//! preconditioners, all angle methods and the multigrid-preconditioned angle CG), for `f32`
//! and `f64`, `D` = 2 and 3, and value widths `V` = 1, `D`, 4 and `D + 4`.
//!
//! Inputs are black-boxed (a four-node complete graph, so every buffer fits on the stack) and
//! every output is black-boxed.

use core::hint::black_box;

use deform_kernel::spring::{
    amg_cg_scratch_len, amg_sliding_cg_scratch_len, angle_scratch_items,
    angle_sliding_scratch_items, batina_stiffness, dual_volumes, inverse_volume_factors, is_fixed,
    scale_stiffness, solve_linear_scratch_len, wall_distance_factors, wall_distances, AmgHierarchy,
    AmgOptions, AmgSmoother, AngleMethod, AngleSystem, LinearMethod, Preconditioner, SolveOptions,
    SpringSystem, Sweep,
};
use deform_kernel::{Cells, Graph, Real};

/// Nodes in the test graph.
const N: usize = 4;

/// Calls every spring entry point with opaque inputs.
pub fn exercise() {
    keep(is_fixed(bb(3)));
    keep(amg_cg_scratch_len(bb(N), bb(3)));
    keep(amg_sliding_cg_scratch_len(bb(N), bb(3)));
    for m in [
        AngleMethod::DirectGaussSeidel,
        AngleMethod::DirectJacobi,
        AngleMethod::Cg,
    ] {
        keep(angle_scratch_items(bb(N), bb(m), bb(true)));
        keep(angle_sliding_scratch_items(bb(N), bb(m), bb(false)));
    }
    run::<f32, 2, 2, 6>();
    run::<f32, 3, 3, 7>();
    run::<f64, 2, 2, 6>();
    run::<f64, 3, 3, 7>();
    values::<f32, 2, 1>();
    values::<f64, 3, 4>();
}

/// An opaque value of type `T`.
#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

/// Keeps `x` alive.
#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// An opaque point set of `N` points in `D` dimensions.
#[inline(always)]
fn points<T: Real, const D: usize>() -> [[T; D]; N] {
    let mut p = [[T::ZERO; D]; N];
    for (i, q) in p.iter_mut().enumerate() {
        for (c, x) in q.iter_mut().enumerate() {
            *x = T::from_f64(((i * 7 + c * 3) % 5) as f64 * 0.25 + c as f64);
        }
    }
    bb(p)
}

/// All whole-solve linear methods.
#[inline(always)]
fn linear_methods<T: Real>() -> [LinearMethod<T>; 6] {
    bb([
        LinearMethod::Jacobi,
        LinearMethod::GaussSeidel,
        LinearMethod::Sor {
            omega: T::from_f64(1.5),
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::None,
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        },
        LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: T::ONE },
        },
    ])
}

/// Builds the opaque graph, stiffness and system, then runs the linear solvers for `V` and
/// `W` and the angle solvers in `D`.
#[inline(never)]
fn run<T: Real, const D: usize, const V: usize, const W: usize>() {
    let offsets: &[u32] = bb(&[0, 3, 6, 9, 12]);
    let targets: &[u32] = bb(&[1, 2, 3, 0, 2, 3, 0, 1, 3, 0, 1, 2]);
    let Ok(g) = Graph::new(offsets, targets) else {
        return;
    };
    let g = bb(g);
    let p = points::<T, D>();
    let mut k = [T::ZERO; 12];
    keep(batina_stiffness(&g, bb(&p[..]), bb(T::ONE), bb(&mut k[..])));
    keep(batina_stiffness(
        &g,
        bb(&p[..]),
        bb(T::from_f64(1.5)),
        bb(&mut k[..]),
    ));
    // The `micromath` fast path (second panic-check build).
    #[cfg(feature = "micromath")]
    keep(deform_kernel::spring::batina_stiffness_fast(
        &g,
        bb(&p[..]),
        bb(T::ONE),
        bb(&mut k[..]),
    ));
    keep(&k);
    // Stiffness choices: wall distance and inverse volume factors, edge scaling.
    let mut dist = [T::ZERO; N];
    keep(wall_distances(
        bb(&p[..]),
        bb(&[0u32, 3][..]),
        bb(&mut dist[..]),
    ));
    keep(wall_distance_factors(bb(&mut dist[..]), bb(T::ONE)));
    keep(inverse_volume_factors(
        bb(&mut dist[..]),
        bb(T::from_f64(1.5)),
    ));
    keep(scale_stiffness(&g, bb(&dist[..]), bb(&mut k[..])));
    let (c_offsets, c_nodes, c_kinds): (&[u32], &[u32], &[u8]) = if D == 2 {
        (bb(&[0, 3, 6]), bb(&[0, 1, 2, 0, 2, 3]), bb(&[5, 5]))
    } else {
        (bb(&[0, 4]), bb(&[0, 1, 2, 3]), bb(&[10]))
    };
    if let Ok(cells) = Cells::new(bb(N), c_offsets, c_nodes, c_kinds) {
        let mut volumes = [T::ZERO; N];
        let mut measures = [T::ZERO; 2];
        keep(dual_volumes(
            &cells,
            bb(&p[..]),
            bb(&mut volumes[..]),
            bb(&mut measures[..]),
        ));
        keep(&volumes);
    }
    keep(&k);
    let fixed: &[u8] = bb(&[1, 0, 0, 1]);
    let mut s = [0u32; N];
    keep(SpringSystem::<T>::scratch_len(bb(N)));
    let Ok(sys) = SpringSystem::new(g, bb(&k[..]), fixed, bb(&mut s[..])) else {
        return;
    };
    let sys = bb(sys);
    keep(sys.graph());
    keep(sys.stiffness());
    keep(sys.fixed());
    keep(sys.node_count());
    keep(sys.is_fixed(bb(2)));
    linear::<T, V>(&sys);
    linear::<T, W>(&sys);
    angle::<T, D>(&sys, &p);
}

/// Linear sweeps and solves with value width `V`.
#[inline(never)]
fn linear<T: Real, const V: usize>(sys: &SpringSystem<'_, T>) {
    let x: [[T; V]; N] = bb([[T::HALF; V]; N]);
    let mut out = [[T::ZERO; V]; N];
    let range = bb(1..3);
    let s: deform_kernel::Result<Sweep<T>> =
        sys.jacobi_sweep(range.clone(), bb(&x[..]), bb(&mut out[..]));
    keep(s);
    keep(&out);
    let mut y = x;
    keep(sys.sor_sweep(range, bb(&mut y[..]), bb(T::from_f64(1.2))));
    keep(sys.relative_residual(bb(&y[..])));
    keep(&y);
    let opts: SolveOptions<T> = bb(SolveOptions::default());
    for m in linear_methods::<T>() {
        let mut scratch = [[T::ZERO; V]; 5 * N];
        let len = solve_linear_scratch_len(&m, bb(N));
        let mut z = x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        keep(sys.solve_linear(bb(&mut z[..]), m, &opts, bb(sc)));
        keep(&z);
    }
}

/// Angle-inclusion sweeps and solves in `D` dimensions.
#[inline(never)]
fn angle<T: Real, const D: usize>(sys: &SpringSystem<'_, T>, p: &[[T; D]; N]) {
    for eps in [T::ZERO, T::from_f64(0.01)] {
        let Ok(a) = AngleSystem::new(*sys, bb(&p[..]), bb(eps)) else {
            continue;
        };
        let a = bb(a);
        keep(a.base());
        keep(a.points());
        keep(a.epsilon());
        let x: [[T; D]; N] = bb([[T::HALF; D]; N]);
        let mut out = [[T::ZERO; D]; N];
        let range = bb(0..N);
        keep(a.angle_jacobi_sweep(range.clone(), bb(&x[..]), bb(&mut out[..])));
        keep(&out);
        let mut y = x;
        keep(a.angle_gauss_seidel_sweep(range.clone(), bb(&mut y[..])));
        keep(&y);
        keep(a.angle_sor_sweep(range, bb(&mut y[..]), bb(T::from_f64(1.8))));
        keep(&y);
        let opts: SolveOptions<T> = bb(SolveOptions::default());
        let mut probe = [[T::ZERO; D]; 4 * N];
        let len = a.angle_probe_scratch_len();
        let sc = probe.get_mut(..len).unwrap_or(&mut []);
        keep(a.angle_rigidity_probe(&opts, bb(sc)));
        keep(&probe);
        for m in bb([
            AngleMethod::DirectGaussSeidel,
            AngleMethod::DirectJacobi,
            AngleMethod::Cg,
        ]) {
            let mut scratch = [[T::ZERO; D]; 4 * N];
            let len = a.angle_scratch_len(m);
            let mut z = x;
            let sc = scratch.get_mut(..len).unwrap_or(&mut []);
            keep(a.solve_angle(bb(&mut z[..]), m, &opts, bb(sc)));
            keep(&z);
        }
        let mut scratch = [[T::ZERO; D]; 4 * N];
        let len = a.angle_scratch_len(AngleMethod::DirectGaussSeidel);
        let mut z = x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        keep(a.solve_angle_sor(bb(&mut z[..]), bb(T::from_f64(1.8)), &opts, bb(sc)));
        keep(&z);
        angle_amg(&a, &x);
    }
}

/// The multigrid-preconditioned angle CG with a hierarchy of the base system (both
/// smoothers, one coarse unknown at most so the 4-node system coarsens).
#[inline(never)]
fn angle_amg<T: Real, const D: usize>(a: &AngleSystem<'_, T, D>, x: &[[T; D]; N]) {
    /// `u32` work entries (`4 (N + E) + 64` with `E = 12`) and hierarchy buffers.
    const WORK: usize = 4 * (N + 12) + 64;
    for smoother in bb([AmgSmoother::Jacobi, AmgSmoother::Chebyshev]) {
        let opts = bb(AmgOptions {
            smoother,
            max_coarse: 1,
            ..AmgOptions::<T>::default()
        });
        let mut work = [0u32; WORK];
        let mut index = [0u32; 256];
        let mut values = [T::ZERO; 256];
        let Ok(h) = AmgHierarchy::setup(
            a.base(),
            &opts,
            bb(&mut work[..]),
            bb(&mut index[..]),
            bb(&mut values[..]),
        ) else {
            continue;
        };
        let h = bb(h);
        let mut scratch = [[T::ZERO; D]; 8 * N];
        let len = a.angle_amg_scratch_len(&h);
        let mut z = *x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        let stop: SolveOptions<T> = bb(SolveOptions::default());
        keep(a.solve_angle_amg(&h, bb(&mut z[..]), &stop, bb(sc)));
        keep(&z);
    }
}

/// Extra value widths for the linear solvers on a freshly built system.
#[inline(never)]
fn values<T: Real, const D: usize, const V: usize>() {
    let offsets: &[u32] = bb(&[0, 1, 3, 4]);
    let targets: &[u32] = bb(&[1, 0, 2, 1]);
    let Ok(g) = Graph::new(offsets, targets) else {
        return;
    };
    let k_store = [T::ONE, T::ONE, T::TWO, T::TWO];
    let k: &[T] = bb(&k_store[..]);
    let fixed: &[u8] = bb(&[1, 0, 1]);
    let mut s = [0u32; 3];
    if let Ok(sys) = SpringSystem::new(g, k, fixed, bb(&mut s[..])) {
        let x: [[T; V]; 3] = bb([[T::ONE; V]; 3]);
        let mut scratch = [[T::ZERO; V]; 12];
        let mut z = x;
        keep(sys.solve_linear(
            bb(&mut z[..]),
            LinearMethod::Cg {
                preconditioner: Preconditioner::Ssor { omega: bb(T::ONE) },
            },
            &SolveOptions::default(),
            bb(&mut scratch[..]),
        ));
        keep(&z);
    }
    keep(D);
}
