//! Panic-check calls for the quaternion deformation's derivatives
//! (`deform_kernel::quaternion`): the tangent and adjoint of the exact IDW, the fast
//! (tree) IDW and TFI, with their scratch queries, for `f32` and `f64`, in 2D and 3D.
//!
//! The mesh and motions are those of `deformation.rs`: opaque points, the first eight the
//! boundary (segments or triangles/quads as elements, or a rigid rotation for TFI).

use core::hint::black_box;

use deform_kernel::quaternion::{
    deform_idw_adjoint, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_sensitivity_scratch_len, deform_idw_tangent,
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent,
    propagate_idw_fast_index_len, BoundaryMotion, IdwFastOptions, RotationSource,
};
use deform_kernel::{Block, Cells, Directions, Quat, Real};

/// Mesh points (a 3 × 3 × 2 block; 2D uses the first 9 as 3 × 3).
const N: usize = 18;
/// Boundary points.
const B: usize = 8;
/// Scratch scalars (`32 B` plus the tree's node records, generous).
const SCRATCH: usize = 1024;

/// Calls every quaternion derivative with opaque inputs.
pub fn exercise() {
    run::<f32, 2>();
    run::<f64, 2>();
    run::<f32, 3>();
    run::<f64, 3>();
}

#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(never)]
fn run<T: Real, const D: usize>() {
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
    keep(deform_idw_sensitivity_scratch_len::<D>(bb(N), bb(B)));
    keep(deform_idw_fast_sensitivity_scratch_len::<D>(bb(N), bb(B)));
    if let Ok(elements) = Cells::new(bb(B), &el_offsets, &el_nodes, &el_kinds) {
        let motion = BoundaryMotion {
            nodes: &boundary,
            deformed: &deformed,
            elements: Some(elements),
            rotations: RotationSource::Shape,
            origin: None,
        };
        idw::<T, D>(&points, &motion);
    }
    let q = Quat::new(bb(T::ONE), bb(T::ZERO), bb(T::ZERO), bb(T::HALF));
    let given = bb([q; B]);
    let motion = BoundaryMotion {
        nodes: &boundary,
        deformed: &deformed,
        elements: None,
        rotations: if bb(true) {
            RotationSource::Rigid(q)
        } else {
            RotationSource::PerNode(&given)
        },
        origin: Some(bb([T::ZERO; D])),
    };
    tfi::<T, D>(&points, &motion);
}

/// Exact and fast IDW: tangent, then adjoint.
#[inline(never)]
fn idw<T: Real, const D: usize>(points: &[[T; D]], motion: &BoundaryMotion<'_, T, D>) {
    let mut scratch = [T::ZERO; SCRATCH];
    let mut trans = [[T::ZERO; D]; N];
    let mut rot = [Quat::identity(); N];
    let direction = bb([[T::HALF; D]; B]);
    let weights = bb([[T::ONE; D]; N]);
    let mut out = [[T::ZERO; D]; N];
    let mut g = [[T::ZERO; D]; B];
    let exponent = bb(T::TWO);
    keep(deform_idw_tangent(
        points,
        motion,
        exponent,
        &direction,
        bb(&mut scratch[..]),
        bb(&mut out[..]),
    ));
    keep(deform_idw_adjoint(
        points,
        motion,
        exponent,
        &weights,
        bb(&mut scratch[..]),
        bb(&mut g[..]),
    ));
    keep(propagate_idw_fast_index_len(bb(B)));
    let mut index = [0u32; B];
    let mut tree = [T::ZERO; 128];
    let options = bb(IdwFastOptions {
        theta: T::HALF,
        tolerance: T::from_f64(0.05),
    });
    keep(deform_idw_fast_tangent(
        points,
        motion,
        exponent,
        &options,
        &direction,
        bb(&mut trans[..]),
        bb(&mut rot[..]),
        bb(&mut scratch[..]),
        bb(&mut index[..]),
        bb(&mut tree[..]),
        bb(&mut out[..]),
    ));
    keep(deform_idw_fast_adjoint(
        points,
        motion,
        exponent,
        &options,
        &weights,
        bb(&mut trans[..]),
        bb(&mut rot[..]),
        bb(&mut scratch[..]),
        bb(&mut index[..]),
        bb(&mut tree[..]),
        bb(&mut g[..]),
    ));
    keep((&out, &g));
}

/// TFI on the 3 × 3 (× 2) block: tangent, then adjoint.
#[inline(never)]
fn tfi<T: Real, const D: usize>(points: &[[T; D]], motion: &BoundaryMotion<'_, T, D>) {
    let Ok(block) = Block::new(bb([3, 3, if D == 3 { 2 } else { 1 }])) else {
        return;
    };
    let n = block.point_count().min(N);
    let points = points.get(..n).unwrap_or(&[]);
    keep(deform_tfi_sensitivity_scratch_len::<D>(&block, bb(B)));
    let mut scratch = [T::ZERO; SCRATCH];
    let direction = bb([[T::HALF; D]; B]);
    let weights = bb([[T::ONE; D]; N]);
    let mut out = [[T::ZERO; D]; N];
    let mut g = [[T::ZERO; D]; B];
    let directions = bb(Directions::from_flags([true, true, D == 3]));
    keep(deform_tfi_tangent(
        &block,
        directions,
        points,
        motion,
        &direction,
        bb(&mut scratch[..]),
        bb(out.get_mut(..n).unwrap_or(&mut [])),
    ));
    keep(deform_tfi_adjoint(
        &block,
        directions,
        points,
        motion,
        weights.get(..n).unwrap_or(&[]),
        bb(&mut scratch[..]),
        bb(&mut g[..]),
    ));
    keep((&out, &g));
}
