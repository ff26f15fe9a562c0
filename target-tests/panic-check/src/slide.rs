//! Panic-check calls for sliding boundaries (`deform_kernel::spring::constraints` and the constrained spring
//! solves): the constraint table, projections, plane fit, plane intersection, `slide_points`,
//! and `solve_linear_sliding` (every linear method and AMG) / `solve_angle_sliding` (every
//! angle method, `ε` 0 and 0.01) / `solve_angle_sliding_amg`, for `f32` and `f64`, `D` = 2
//! and 3; the derivatives with sliding nodes (`deform_kernel::sensitivity`:
//! `spring_sliding_tangent` / `_adjoint` with CG and multigrid).
//!
//! The system is an opaque 8-node path (both ends fixed, one node on a plane, one on a line).

use core::hint::black_box;

use deform_kernel::sensitivity::{
    spring_sliding_adjoint, spring_sliding_adjoint_scratch_len, spring_sliding_tangent,
};
use deform_kernel::spring::constraints::{
    fit_plane, plane_intersection, slide_points, unit_tolerance, Constraints, NodeKind,
};
use deform_kernel::spring::{
    solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AngleMethod, AngleSystem,
    LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
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
const SCRATCH: usize = 16 * N;

/// Calls every sliding-boundary entry point with opaque inputs.
pub fn exercise() {
    keep(NodeKind::from_code(bb(2)));
    keep(NodeKind::Line.code());
    run::<f32, 2>();
    run::<f32, 3>();
    run::<f64, 2>();
    run::<f64, 3>();
    keep(plane_intersection(
        bb([1.0f64, 0.0, 0.0]),
        bb([0.0f64, 1.0, 0.0]),
    ));
    keep(plane_intersection(
        bb([1.0f32, 0.0, 0.0]),
        bb([0.0f32, 1.0, 0.0]),
    ));
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
fn run<T: Real, const D: usize>() {
    keep(unit_tolerance::<T>());
    let mut p = [[T::ZERO; D]; N];
    for (i, q) in p.iter_mut().enumerate() {
        for (c, x) in q.iter_mut().enumerate() {
            *x = T::from_f64(i as f64 + 0.25 * ((i * 3 + c) % 4) as f64);
        }
    }
    let p = bb(p);
    let nodes: &[u32] = bb(&[0, 2, 4, 6, 7]);
    keep(fit_plane(&p[..], nodes, bb(T::from_f64(1e-3))));
    let mut e = [T::ZERO; D];
    if let Some(x) = e.first_mut() {
        *x = T::ONE;
    }
    let dirs: [[T; D]; N] = bb([e; N]);
    let kinds: &[u8] = bb(&[1, 0, 2, 0, 3, 0, 0, 1]);
    let Ok(c) = Constraints::new(kinds, &dirs[..]) else {
        return;
    };
    let c = bb(c);
    keep(c.kinds());
    keep(c.directions());
    keep(c.len());
    keep(c.is_empty());
    keep(c.kind(bb(4)));
    keep(c.project(bb(2), bb(e)));
    let mut mask = [0u8; N];
    keep(c.fixed_mask(bb(&mut mask[..])));
    let mut moved = p;
    keep(slide_points(&c, bb(&p[..]), bb(&mut moved[..])));
    keep(&moved);

    let offsets: &[u32] = bb(&[0, 1, 3, 5, 7, 9, 11, 13, 14]);
    let targets: &[u32] = bb(&[1, 0, 2, 1, 3, 2, 4, 3, 5, 4, 6, 5, 7, 6]);
    let Ok(g) = Graph::new(offsets, targets) else {
        return;
    };
    let k: [T; 14] = bb([T::ONE; 14]);
    let mut s = [0u32; N];
    let Ok(sys) = SpringSystem::new(bb(g), &k[..], &mask[..], &mut s[..]) else {
        return;
    };
    let sys = bb(sys);
    let x: [[T; D]; N] = bb([[T::HALF; D]; N]);
    let opts: SolveOptions<T> = bb(SolveOptions::default());
    let mut scratch = [[T::ZERO; D]; SCRATCH];
    for m in bb([
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
    ]) {
        let solver = LinearSolver::Method(m);
        let len = solve_linear_sliding_scratch_len(&solver, bb(N));
        let mut y = x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        keep(sys.solve_linear_sliding(&c, bb(&mut y[..]), solver, &opts, bb(sc)));
        keep(&y);
        derivatives(&sys, &c, solver, &opts, &x, &mut scratch);
    }
    let amg_opts = bb(AmgOptions {
        max_coarse: 2,
        ..AmgOptions::<T>::default()
    });
    let mut work = [0u32; WORK];
    let mut index = [0u32; INDEX];
    let mut values = [T::ZERO; VALUES];
    if let Ok(h) = AmgHierarchy::setup(
        &sys,
        &amg_opts,
        bb(&mut work[..]),
        bb(&mut index[..]),
        bb(&mut values[..]),
    ) {
        let h = bb(h);
        let solver = LinearSolver::Amg(&h);
        let len = solve_linear_sliding_scratch_len(&solver, bb(N));
        let mut y = x;
        let sc = scratch.get_mut(..len).unwrap_or(&mut []);
        keep(sys.solve_linear_sliding(&c, bb(&mut y[..]), solver, &opts, bb(sc)));
        keep(&y);
        derivatives(&sys, &c, solver, &opts, &x, &mut scratch);
        for eps in [T::ZERO, T::from_f64(0.01)] {
            let Ok(a) = AngleSystem::new(sys, bb(&p[..]), bb(eps)) else {
                continue;
            };
            let a = bb(a);
            let len = a.solve_angle_sliding_amg_scratch_len(&h);
            let mut y = x;
            let sc = scratch.get_mut(..len).unwrap_or(&mut []);
            keep(a.solve_angle_sliding_amg(&c, bb(&mut y[..]), &h, &opts, bb(sc)));
            keep(&y);
        }
    }
    for eps in [T::ZERO, T::from_f64(0.01)] {
        let Ok(a) = AngleSystem::new(sys, bb(&p[..]), bb(eps)) else {
            continue;
        };
        let a = bb(a);
        for m in bb([
            AngleMethod::DirectGaussSeidel,
            AngleMethod::DirectJacobi,
            AngleMethod::Cg,
        ]) {
            let len = a.solve_angle_sliding_scratch_len(m);
            let mut y = x;
            let sc = scratch.get_mut(..len).unwrap_or(&mut []);
            keep(a.solve_angle_sliding(&c, bb(&mut y[..]), m, bb(T::from_f64(1.3)), &opts, bb(sc)));
            keep(&y);
        }
    }
}

/// The sliding tangent and adjoint of the linear springs with `solver`.
#[inline(never)]
fn derivatives<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    c: &Constraints<'_, T, D>,
    solver: LinearSolver<'_, T>,
    opts: &SolveOptions<T>,
    x: &[[T; D]; N],
    scratch: &mut [[T; D]; SCRATCH],
) {
    let len = solve_linear_sliding_scratch_len(&solver, bb(N));
    let mut y = *x;
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    keep(spring_sliding_tangent(
        sys,
        c,
        solver,
        opts,
        bb(&mut y[..]),
        bb(sc),
    ));
    keep(&y);
    let len = spring_sliding_adjoint_scratch_len::<T, D>(&solver, bb(N));
    let mut g = [[T::ZERO; D]; N];
    let sc = scratch.get_mut(..len).unwrap_or(&mut []);
    keep(spring_sliding_adjoint(
        sys,
        c,
        solver,
        opts,
        bb(&x[..]),
        bb(&mut g[..]),
        bb(sc),
    ));
    keep(&g);
}
