//! Panic-check calls for prepared plans (`deform_kernel::plan`): the work and pool size
//! queries, `init`, `open`, `step` (warm and cold, every rotation source), the tangent and
//! adjoint at the last step and the accessors,
//! for `f32` and `f64`, `D` = 2 and 3 (so `V` = 2, 3, 6 and 7), both methods, the multigrid
//! and a one-level solver; the capacity queries from counts and the fixed-capacity
//! `PlanStorage`.
//!
//! The mesh is an opaque 3 × 3 grid with diagonals (the ring of 8 nodes is the boundary, with
//! segment elements in 2D); 3D uses the same graph with `z = 0` and no elements.

use core::hint::black_box;

use deform_kernel::cells::Cells;
use deform_kernel::plan::{
    Plan, PlanCounts, PlanMethod, PlanMotion, PlanSolver, PlanSpec, PlanStiffness, PlanStorage,
    PlanWork, Start,
};
use deform_kernel::quaternion::RotationSource;
use deform_kernel::spring::{AmgOptions, LinearMethod, Preconditioner, SolveOptions};
use deform_kernel::{Graph, Quat, Real};

/// Nodes of the grid.
const N: usize = 9;
/// Boundary nodes (the ring).
const B: usize = 8;
/// Pool and work lengths (generous for the grid).
const REALS: usize = 2048;
const INDICES: usize = 1536;
const BYTES: usize = 64;
const WORK: usize = 512;

/// Calls every plan entry point with opaque inputs.
pub fn exercise() {
    run::<f32, 2>();
    run::<f64, 2>();
    run::<f32, 3>();
    run::<f64, 3>();
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
    // Row-major 3 × 3 grid, node 4 in the middle; edges along rows, columns and the diagonals
    // `i → i + 4`.
    let offsets: &[u32] = bb(&[0, 3, 7, 9, 13, 19, 23, 25, 29, 32]);
    let targets: &[u32] = bb(&[
        1, 3, 4, 0, 2, 4, 5, 1, 5, 0, 4, 6, 7, 0, 1, 3, 5, 7, 8, 1, 2, 4, 8, 3, 7, 3, 4, 6, 8, 4,
        5, 7,
    ]);
    let Ok(graph) = Graph::new(offsets, targets) else {
        return;
    };
    let mut points = [[T::ZERO; D]; N];
    for (i, p) in points.iter_mut().enumerate() {
        if let Some(x) = p.get_mut(0) {
            *x = T::from_usize(i % 3);
        }
        if let Some(y) = p.get_mut(1) {
            *y = T::from_usize(i / 3);
        }
    }
    let points = bb(points);
    let boundary: &[u32] = bb(&[0, 1, 2, 5, 8, 7, 6, 3]);
    let el_offsets: &[u32] = bb(&[0, 2, 4, 6, 8, 10, 12, 14, 16]);
    let el_nodes: &[u32] = bb(&[0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 0]);
    let el_kinds: &[u8] = bb(&[3; 8]);
    let elements = if D == 2 {
        Cells::new(B, el_offsets, el_nodes, el_kinds).ok()
    } else {
        None
    };
    let solvers = bb([
        PlanSolver::Amg(AmgOptions {
            max_coarse: 2,
            ..AmgOptions::default()
        }),
        PlanSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: T::ONE },
        }),
    ]);
    for method in bb([PlanMethod::Spring, PlanMethod::QuaternionSpring]) {
        for solver in solvers {
            let spec = bb(PlanSpec {
                points: &points[..],
                graph,
                boundary,
                elements,
                constraints: None,
                method,
                stiffness: PlanStiffness::Batina { exponent: T::ONE },
                solver,
                options: SolveOptions::default(),
                renumber: deform_kernel::plan::PlanOrder::AsGiven,
            });
            plan::<T, D>(&spec);
            storage::<T, D>(&spec);
        }
    }
}

#[inline(never)]
fn plan<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>) {
    let mut wr = [T::ZERO; WORK];
    let mut wi = [0u32; WORK];
    let mut wb = [0u8; WORK];
    keep(Plan::<T, D>::work_sizes(spec));
    let mut work = PlanWork {
        reals: bb(&mut wr[..]),
        indices: bb(&mut wi[..]),
        bytes: bb(&mut wb[..]),
    };
    keep(Plan::<T, D>::sizes(spec, &mut work));
    let mut reals = [T::ZERO; REALS];
    let mut indices = [0u32; INDICES];
    let mut bytes = [0u8; BYTES];
    if let Ok(p) = Plan::init(
        spec,
        &mut work,
        bb(&mut reals[..]),
        bb(&mut indices[..]),
        bb(&mut bytes[..]),
    ) {
        keep((p.used(), p.node_count(), p.boundary_len(), p.method()));
        keep((p.steps(), p.amg_levels()));
        keep(p.buffers());
    }
    let Ok(mut p) =
        Plan::<T, D>::open(bb(&mut reals[..]), bb(&mut indices[..]), bb(&mut bytes[..]))
    else {
        return;
    };
    let mut deformed = [[T::ZERO; D]; B];
    for (d, &i) in deformed.iter_mut().zip(spec.boundary) {
        *d = spec.points.get(i as usize).copied().unwrap_or([T::ZERO; D]);
        if let Some(x) = d.get_mut(0) {
            *x += T::HALF;
        }
    }
    let deformed = bb(deformed);
    let q = bb([Quat::identity(); B]);
    let mut out = [[T::ZERO; D]; N];
    for (rotations, start) in bb([
        (RotationSource::Shape, Start::Cold),
        (RotationSource::Rigid(Quat::identity()), Start::Warm),
        (RotationSource::PerNode(&q[..]), Start::Warm),
    ]) {
        let motion = PlanMotion {
            deformed: &deformed[..],
            rotations,
            origin: bb(None),
            start,
        };
        keep(p.step(&motion, bb(&mut out[..])));
        keep(&out);
        derivatives(&p, &motion);
    }
}

/// The plan's tangent and adjoint at the last step (`sensitivity_scratch_len` first).
#[inline(never)]
fn derivatives<T: Real, const D: usize>(p: &Plan<'_, T, D>, motion: &PlanMotion<'_, T, D>) {
    keep(p.sensitivity_scratch_len());
    let mut scratch = [T::ZERO; WORK];
    let direction = bb([[T::HALF; D]; B]);
    let mut out = [[T::ZERO; D]; N];
    keep(p.tangent(motion, &direction, bb(&mut scratch[..]), bb(&mut out[..])));
    keep(&out);
    let weights = bb([[T::ONE; D]; N]);
    let mut g = [[T::ZERO; D]; B];
    keep(p.adjoint(motion, &weights, bb(&mut scratch[..]), bb(&mut g[..])));
    keep(&g);
}

/// The capacity queries (run-time counts) and a plan in `PlanStorage`.
#[inline(never)]
fn storage<T: Real, const D: usize>(spec: &PlanSpec<'_, T, D>) {
    let counts = bb(PlanCounts {
        nodes: spec.graph.node_count(),
        edges: spec.graph.edge_count(),
        boundary: spec.boundary.len(),
        elements: spec.elements.map(|c| (c.len(), c.nodes().len())),
    });
    keep(Plan::<T, D>::work_capacity(&counts));
    if let PlanSolver::Method(m) = spec.solver {
        keep(Plan::<T, D>::capacity(&counts, spec.method, &m));
    }
    let mut work = PlanStorage::<T, WORK, WORK, WORK>::new();
    let mut pools = PlanStorage::<T, REALS, INDICES, BYTES>::new();
    if let Ok(p) = pools.init(spec, &mut work.work()) {
        keep(p.used());
    }
    keep(pools.open::<D>().map(|p| p.used()));
    keep((pools.capacity(), pools.pools()));
    keep(pools.pools_mut());
}
