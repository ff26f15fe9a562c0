//! Golden cases for the sensitivities of the quaternion deformation with spring propagation
//! (`deform_spring_tangent`, `deform_spring_adjoint`) on the jittered triangle mesh of
//! [`mesh_cases`](crate::mesh_cases): the bottom row turned by 20°, rotations from the shape
//! of the perimeter loop, CG with the Jacobi preconditioner. The hashes cover every output
//! value and the merged solve report. The same motion through transfinite interpolation of the
//! grid as a structured block (`deform_tfi_tangent`, `deform_tfi_adjoint`, both directions).

use deform_kernel::quaternion::{
    deform_spring_adjoint, deform_spring_sensitivity_scratch_len, deform_spring_tangent,
    deform_tfi_adjoint, deform_tfi_sensitivity_scratch_len, deform_tfi_tangent, BoundaryMotion,
    RotationSource,
};
use deform_kernel::spring::{LinearMethod, LinearSolver, Preconditioner, SolveOptions};
use deform_kernel::{Block, Cells, Direction, Directions, Real};

use crate::mesh_cases::{
    boundary_displacement, hash_points, hash_report, mesh, with_system, Mesh, N, NB, NX, NY,
};
use crate::{Fnv, XorShift};

/// Scalars of scratch the cases provide (the kernel needs about 2 700 for this mesh).
const SCRATCH: usize = 4096;

/// The perimeter loop as segments in boundary-local numbering (positions in `m.boundary`).
fn segments<T: Real>(m: &Mesh<T>) -> [u32; 2 * NB] {
    let mut local = [0u32; N];
    for (k, &b) in m.boundary.iter().enumerate() {
        if let Some(l) = local.get_mut(b as usize) {
            *l = k as u32;
        }
    }
    let mut ring = [0usize; NB];
    let mut r = 0;
    let mut put = |node: usize| {
        if let Some(slot) = ring.get_mut(r) {
            *slot = node;
        }
        r += 1;
    };
    (0..NX - 1).for_each(&mut put);
    (0..NY - 1).for_each(|j| put(NX - 1 + NX * j));
    (0..NX - 1).for_each(|i| put(N - 1 - i));
    (0..NY - 1).for_each(|j| put(NX * (NY - 1 - j)));
    let mut seg = [0u32; 2 * NB];
    for (k, pair) in seg.chunks_exact_mut(2).enumerate() {
        let at = |i: usize| ring.get(i % NB).and_then(|&n| local.get(n)).copied();
        pair[0] = at(k).unwrap_or(0);
        pair[1] = at(k + 1).unwrap_or(0);
    }
    seg
}

/// Runs `f` on the linearisation point: the mesh, its spring system, CG + Jacobi and the
/// motion (bottom row turned, shape rotations, default origin); 0 when a step fails.
fn with_point<T: Real>(f: impl FnOnce(&Mesh<T>, Run<'_, '_, T>, &mut Fnv)) -> u64 {
    let m = mesh::<T>();
    let disp = boundary_displacement(&m);
    let mut deformed = [[T::ZERO; 2]; NB];
    for (d, &node) in deformed.iter_mut().zip(&m.boundary) {
        let n = node as usize;
        if let (Some(p), Some(u)) = (m.points.get(n), disp.get(n)) {
            *d = [p[0] + u[0], p[1] + u[1]];
        }
    }
    let seg = segments(&m);
    let offsets: [u32; NB + 1] = core::array::from_fn(|i| 2 * i as u32);
    let kinds = [3u8; NB];
    let mut h = Fnv::new();
    let Ok(elements) = Cells::new(NB, &offsets, &seg, &kinds) else {
        return 0;
    };
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: Some(elements),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let ok = with_system(&m, |sys, _| {
        let run = Run {
            motion: &motion,
            sys,
            solver: LinearSolver::Method(LinearMethod::Cg {
                preconditioner: Preconditioner::Jacobi,
            }),
        };
        f(&m, run, &mut h);
    });
    if ok.is_none() {
        return 0;
    }
    h.finish()
}

/// The fixed arguments of both modes.
struct Run<'a, 'm, T: Real> {
    motion: &'a BoundaryMotion<'m, T, 2>,
    sys: &'a deform_kernel::spring::SpringSystem<'a, T>,
    solver: LinearSolver<'a, T>,
}

impl<T: Real> Run<'_, '_, T> {
    /// The scratch length the kernel asks for, within [`SCRATCH`].
    fn scratch_len(&self) -> usize {
        deform_spring_sensitivity_scratch_len::<T, 2>(&self.solver, N, NB).min(SCRATCH)
    }
}

/// Tangent of the quaternion springs along a random boundary perturbation.
pub fn quaternion_spring_tangent<T: Real>() -> u64 {
    with_point::<T>(|m, run, h| {
        let mut rng = XorShift::new(0x5EED_0030);
        let dir: [[T; 2]; NB] =
            core::array::from_fn(|_| [rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)]);
        let mut scratch = [T::ZERO; SCRATCH];
        let len = run.scratch_len();
        let mut out = [[T::ZERO; 2]; N];
        match deform_spring_tangent(
            &m.points,
            run.motion,
            run.sys,
            run.solver,
            &SolveOptions::default(),
            &dir,
            scratch.get_mut(..len).unwrap_or(&mut []),
            &mut out,
        ) {
            Ok(r) => hash_report(h, &r),
            Err(e) => h.error(&e),
        }
        hash_points(h, &out);
    })
}

/// Adjoint of the quaternion springs for a random volume sensitivity.
pub fn quaternion_spring_adjoint<T: Real>() -> u64 {
    with_point::<T>(|m, run, h| {
        let mut rng = XorShift::new(0x5EED_0031);
        let w: [[T; 2]; N] =
            core::array::from_fn(|_| [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)]);
        let mut scratch = [T::ZERO; SCRATCH];
        let len = run.scratch_len();
        let mut out = [[T::ZERO; 2]; NB];
        match deform_spring_adjoint(
            &m.points,
            run.motion,
            run.sys,
            run.solver,
            &SolveOptions::default(),
            &w,
            scratch.get_mut(..len).unwrap_or(&mut []),
            &mut out,
        ) {
            Ok(r) => hash_report(h, &r),
            Err(e) => h.error(&e),
        }
        hash_points(h, &out);
    })
}

/// The grid as a TFI block over both directions and the scratch length it needs (within
/// [`SCRATCH`]); `None` when the block is refused.
fn tfi_block() -> Option<(Block, Directions, usize)> {
    let block = Block::new([NX, NY, 1]).ok()?;
    let dirs = Directions::only(Direction::I).with(Direction::J);
    let len = deform_tfi_sensitivity_scratch_len::<2>(&block, NB).min(SCRATCH);
    Some((block, dirs, len))
}

/// Tangent of the quaternion TFI along a random boundary perturbation.
pub fn quaternion_tfi_tangent<T: Real>() -> u64 {
    with_point::<T>(|m, run, h| {
        let mut rng = XorShift::new(0x5EED_0032);
        let dir: [[T; 2]; NB] =
            core::array::from_fn(|_| [rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)]);
        let mut scratch = [T::ZERO; SCRATCH];
        let mut out = [[T::ZERO; 2]; N];
        let Some((block, dirs, len)) = tfi_block() else {
            return;
        };
        let s = scratch.get_mut(..len).unwrap_or(&mut []);
        if let Err(e) = deform_tfi_tangent(&block, dirs, &m.points, run.motion, &dir, s, &mut out) {
            h.error(&e);
        }
        hash_points(h, &out);
    })
}

/// Adjoint of the quaternion TFI for a random volume sensitivity.
pub fn quaternion_tfi_adjoint<T: Real>() -> u64 {
    with_point::<T>(|m, run, h| {
        let mut rng = XorShift::new(0x5EED_0033);
        let w: [[T; 2]; N] =
            core::array::from_fn(|_| [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)]);
        let mut scratch = [T::ZERO; SCRATCH];
        let mut out = [[T::ZERO; 2]; NB];
        let Some((block, dirs, len)) = tfi_block() else {
            return;
        };
        let s = scratch.get_mut(..len).unwrap_or(&mut []);
        if let Err(e) = deform_tfi_adjoint(&block, dirs, &m.points, run.motion, &w, s, &mut out) {
            h.error(&e);
        }
        hash_points(h, &out);
    })
}
