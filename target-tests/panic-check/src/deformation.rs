//! Panic-check calls for the kernel's deformation entry points (`deform_kernel::quaternion`),
//! for `f32` and `f64`, in 2D and 3D, with black-boxed inputs and outputs.

use core::hint::black_box;
use deform_kernel::Directions;

use deform_kernel::quaternion::{
    boundary_normals, boundary_normals_scratch_len, boundary_origin, boundary_rotations,
    boundary_rotations_scratch_len, boundary_translations, deform_idw, deform_idw_fast,
    deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_spring_with,
    deform_tfi, deform_tfi_scratch_len, displacement_tfi, limit_reach, localize_nodes,
    localize_nodes_scratch_len, propagate_idw, propagate_idw_fast, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, propagate_spring, propagate_spring_scratch_len,
    propagate_spring_with, propagate_spring_with_scratch_len, propagate_tfi, reach_weight,
    rigid_rotations, tfi_scratch_len, update_points, BoundaryMotion, IdwFastOptions,
    RotationSource,
};
use deform_kernel::spring::{
    AmgHierarchy, AmgOptions, LinearMethod, LinearSolver, Preconditioner, SolveOptions,
    SpringSystem,
};
use deform_kernel::{Block, Cells, Graph, Quat, Real};

/// Calls every deformation entry point with opaque inputs.
pub fn exercise() {
    run::<f32, 2, 6>();
    run::<f64, 2, 6>();
    run::<f32, 3, 7>();
    run::<f64, 3, 7>();
}

/// Number of mesh points used (a 3 × 3 × 2 block; 2D uses the first 9 as 3 × 3).
const N: usize = 18;
/// Number of boundary points.
const B: usize = 8;

/// Keeps `x` alive (and its `Result` used).
#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// An opaque value.
#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(never)]
fn run<T: Real, const D: usize, const V: usize>() {
    let mut points = [[T::ZERO; D]; N];
    for (i, p) in points.iter_mut().enumerate() {
        for (d, x) in p.iter_mut().enumerate() {
            *x = T::from_f64((i * (d + 1)) as f64 * 0.1);
        }
    }
    let points = bb(points);
    let deformed = bb([[T::HALF; D]; B]);
    let boundary = bb([0u32, 1, 2, 3, 4, 5, 6, 7]);
    let el_offsets = bb([0u32, 2, 4, 6, 8]);
    let el_nodes = bb([0u32, 1, 2, 3, 4, 5, 6, 7]);
    let el_kinds = bb([3u8, 9, 5, 3]);
    let q = Quat::new(bb(T::ONE), bb(T::ZERO), bb(T::ZERO), bb(T::HALF));
    let origin = bb([T::ZERO; D]);

    let mut scratch = [T::ZERO; 3 * N * 4];
    let mut normals = [[T::ZERO; D]; B];
    let mut rot_b = [Quat::identity(); B];
    let mut trans_b = [[T::ZERO; D]; B];
    let mut trans = [[T::ZERO; D]; N];
    let mut rot = [Quat::identity(); N];
    let mut out = [[T::ZERO; D]; N];
    let mut values = [[T::ZERO; V]; 6 * N];

    keep(boundary_normals_scratch_len(bb(B)));
    keep(boundary_rotations_scratch_len::<D>(bb(B)));
    keep(deform_idw_scratch_len::<D>(bb(N), bb(B)));
    keep(deform_spring_scratch_len::<D>(bb(N), bb(B)));

    if let Ok(elements) = Cells::new(bb(B), &el_offsets, &el_nodes, &el_kinds) {
        let s = bb(&mut scratch[..]);
        keep(boundary_normals(
            &points[..B],
            &elements,
            s,
            bb(&mut normals[..]),
        ));
        let s = bb(&mut scratch[..]);
        keep(boundary_rotations(
            &points[..B],
            &deformed,
            &elements,
            s,
            bb(&mut rot_b[..]),
        ));
        let motion = BoundaryMotion {
            nodes: &boundary,
            deformed: &deformed,
            elements: Some(elements),
            rotations: RotationSource::Shape,
            origin: None,
        };
        keep(deform_idw(
            &points,
            &motion,
            bb(T::TWO),
            bb(&mut trans[..]),
            bb(&mut rot[..]),
            bb(&mut scratch[..]),
            bb(&mut out[..]),
        ));
        let mut fast_index = [0u32; B];
        let mut tree = [T::ZERO; 128];
        let fast_options = IdwFastOptions {
            theta: bb(T::HALF),
            tolerance: bb(T::INFINITY),
        };
        keep(deform_idw_fast(
            &points,
            &motion,
            bb(T::TWO),
            &fast_options,
            bb(&mut trans[..]),
            bb(&mut rot[..]),
            bb(&mut scratch[..]),
            bb(&mut fast_index[..]),
            bb(&mut tree[..]),
            bb(&mut out[..]),
        ));
        let given = bb([q; B]);
        let motion2 = BoundaryMotion {
            nodes: &boundary,
            deformed: &deformed,
            elements: None,
            rotations: if bb(true) {
                RotationSource::Rigid(q)
            } else {
                RotationSource::PerNode(&given)
            },
            origin: Some(origin),
        };
        if let Ok(block) = Block::new(bb([3, 3, if D == 3 { 2 } else { 1 }])) {
            keep(tfi_scratch_len::<D>(&block));
            keep(deform_tfi_scratch_len::<D>(&block, bb(B)));
            let n = block.point_count().min(N);
            keep(deform_tfi(
                &block,
                bb(Directions::from_flags([true, true, false])),
                &points[..n],
                &motion2,
                bb(&mut trans[..n]),
                bb(&mut rot[..n]),
                bb(&mut scratch[..]),
                bb(&mut out[..n]),
            ));
            keep(propagate_tfi(
                &block,
                bb(Directions::from_flags([true, false, D == 3])),
                &points[..n],
                bb(&mut trans[..n]),
                bb(&mut rot[..n]),
                bb(&mut scratch[..]),
            ));
            keep(displacement_tfi(
                &block,
                bb(Directions::from_flags([true, true, true])),
                &points[..n],
                bb(&mut trans[..n]),
                bb(&mut scratch[..]),
            ));
        }
        // Springs on a path graph 0-1-2-…-(N−1).
        let mut offsets = [0u32; N + 1];
        let mut targets = [0u32; 2 * (N - 1)];
        let mut t = 0usize;
        for i in 0..N {
            if i > 0 {
                targets[t] = (i - 1) as u32;
                t += 1;
            }
            if i + 1 < N {
                targets[t] = (i + 1) as u32;
                t += 1;
            }
            offsets[i + 1] = t as u32;
        }
        let offsets = bb(offsets);
        let targets = bb(targets);
        let k = bb([T::ONE; 2 * (N - 1)]);
        let mut fixed = [0u8; N];
        for f in fixed.iter_mut().take(B) {
            *f = 1;
        }
        let fixed = bb(fixed);
        let mut sscratch = [0u32; N];
        if let Ok(graph) = Graph::new(&offsets, &targets) {
            if let Ok(sys) = SpringSystem::new(graph, &k, &fixed, bb(&mut sscratch[..])) {
                let method = if bb(true) {
                    LinearMethod::Cg {
                        preconditioner: Preconditioner::Jacobi,
                    }
                } else {
                    LinearMethod::GaussSeidel
                };
                let options = bb(SolveOptions::default());
                keep(propagate_spring_scratch_len::<D>(&method, bb(N)));
                keep(propagate_spring(
                    &sys,
                    method,
                    &options,
                    bb(&mut trans[..]),
                    bb(&mut rot[..]),
                    bb(values.as_flattened_mut()),
                ));
                keep(deform_spring(
                    &points,
                    &motion2,
                    &sys,
                    method,
                    &options,
                    bb(&mut trans[..]),
                    bb(&mut rot[..]),
                    bb(&mut scratch[..]),
                    bb(values.as_flattened_mut()),
                    bb(&mut out[..]),
                ));
                // The same pipelines with the multigrid-preconditioned CG.
                let amg_opts = bb(AmgOptions::<T>::default());
                let mut work = [0u32; 4 * (3 * N) + 64];
                let mut index = [0u32; 512];
                let mut hvals = [T::ZERO; 512];
                if let Ok(h) = AmgHierarchy::setup(
                    &sys,
                    &amg_opts,
                    bb(&mut work[..]),
                    bb(&mut index[..]),
                    bb(&mut hvals[..]),
                ) {
                    let solver = bb(LinearSolver::Amg(&h));
                    let mut big = [[T::ZERO; V]; 10 * N];
                    keep(propagate_spring_with_scratch_len::<D>(&solver, bb(N)));
                    keep(propagate_spring_with(
                        &sys,
                        solver,
                        &options,
                        bb(&mut trans[..]),
                        bb(&mut rot[..]),
                        bb(big.as_flattened_mut()),
                    ));
                    keep(deform_spring_with(
                        &points,
                        &motion2,
                        &sys,
                        solver,
                        &options,
                        bb(&mut trans[..]),
                        bb(&mut rot[..]),
                        bb(&mut scratch[..]),
                        bb(big.as_flattened_mut()),
                        bb(&mut out[..]),
                    ));
                }
            }
        }
    }
    keep(rigid_rotations(q, bb(&mut rot_b[..])));
    let mut map = [0u32; N];
    let mut local = [0u32; B];
    keep(localize_nodes_scratch_len(bb(N)));
    keep(localize_nodes(
        bb(N),
        &boundary,
        &el_nodes,
        bb(&mut map[..]),
        bb(&mut local[..]),
    ));
    keep(boundary_origin(&points[..B], &deformed));
    keep(boundary_translations(
        origin,
        &points[..B],
        &deformed,
        &rot_b,
        bb(&mut trans_b[..]),
    ));
    keep(propagate_idw(
        &points,
        &boundary,
        bb(T::from_f64(2.5)),
        bb(&mut trans[..]),
        bb(&mut rot[..]),
    ));
    keep(propagate_idw_fast_index_len(bb(B)));
    keep(propagate_idw_fast_scratch_len::<D>(bb(B)));
    let mut index = [0u32; B];
    let mut bounds = [T::ZERO; N];
    let options = IdwFastOptions {
        theta: bb(T::HALF),
        tolerance: bb(T::from_f64(0.05)),
    };
    keep(propagate_idw_fast(
        &points,
        &boundary,
        bb(T::from_f64(2.5)),
        &options,
        bb(&mut index[..]),
        bb(&mut scratch[..]),
        bb(&mut trans[..]),
        bb(&mut rot[..]),
        if bb(true) {
            Some(bb(&mut bounds[..]))
        } else {
            None
        },
    ));
    let mut reach_distances = [T::ZERO; N];
    for (k, d) in reach_distances.iter_mut().enumerate() {
        *d = bb(T::from_usize(k));
    }
    keep(reach_weight(bb(T::HALF), bb(T::TWO)));
    keep(limit_reach(
        &reach_distances,
        bb(T::TWO),
        bb(&mut trans[..]),
        bb(&mut rot[..]),
    ));
    keep(update_points(
        origin,
        &points,
        &trans,
        &rot,
        &boundary,
        &deformed,
        bb(&mut out[..]),
    ));
}
