//! Golden cases for the solvers on a small jittered triangle mesh and a small noisy structured
//! block: linear springs (CG and Jacobi, AMG-CG), angle-inclusion springs (direct, CG and
//! AMG-CG), the quaternion deformation (springs and IDW), mesh quality, and Taubin smoothing.
//! The hashes cover every output value and every report field.

use deform_kernel::quality::compare;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len,
    propagate_spring_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    amg_precondition_scratch_len, batina_stiffness, solve_linear_amg_scratch_len,
    solve_linear_scratch_len, AmgHierarchy, AmgOptions, AmgSmoother, AngleMethod, AngleSystem,
    LinearMethod, Preconditioner, SolveOptions, SolveReport, SpringSystem, DEFAULT_ANGLE_EPSILON,
};
use deform_kernel::taubin::{
    smooth_arclength, smooth_arclength_scratch_len, smooth_structured, structured_scratch_len,
    SmoothOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{
    graph_from_cells, Block, CellKind, Cells, Direction, Directions, Graph, Quat, Real,
};

use crate::{Fnv, XorShift};

/// Grid points along x and y of the triangle mesh.
pub(crate) const NX: usize = 7;
pub(crate) const NY: usize = 6;
/// Mesh nodes.
pub(crate) const N: usize = NX * NY;
/// Triangles (two per quad).
const NT: usize = 2 * (NX - 1) * (NY - 1);
/// Boundary nodes (the perimeter).
pub(crate) const NB: usize = 2 * (NX + NY) - 4;
/// Upper bound of directed edges: 3 per triangle, twice.
const NE: usize = 6 * NT;

/// The mesh: jittered points, triangle cells, the edge graph and the perimeter.
pub(crate) struct Mesh<T> {
    pub(crate) points: [[T; 2]; N],
    offsets: [u32; NT + 1],
    nodes: [u32; 3 * NT],
    kinds: [u8; NT],
    graph_offsets: [u32; N + 1],
    targets: [u32; NE],
    used: usize,
    pub(crate) boundary: [u32; NB],
    fixed: [u8; N],
}

pub(crate) fn mesh<T: Real>() -> Mesh<T> {
    let mut rng = XorShift::new(0x5EED_0003);
    let mut m = Mesh {
        points: [[T::ZERO; 2]; N],
        offsets: [0; NT + 1],
        nodes: [0; 3 * NT],
        kinds: [CellKind::Triangle.vtk_code(); NT],
        graph_offsets: [0; N + 1],
        targets: [0; NE],
        used: 0,
        boundary: [0; NB],
        fixed: [0; N],
    };
    let mut b = 0;
    for j in 0..NY {
        for i in 0..NX {
            let on_edge = i == 0 || j == 0 || i == NX - 1 || j == NY - 1;
            let jitter = if on_edge { 0.0 } else { 0.25 };
            let x = i as f64 + jitter * (rng.unit_f64() - 0.5);
            let y = j as f64 * 0.8 + jitter * (rng.unit_f64() - 0.5);
            let p = i + NX * j;
            if let Some(pt) = m.points.get_mut(p) {
                *pt = [T::from_f64(x), T::from_f64(y)];
            }
            if on_edge {
                if let (Some(slot), Some(f)) = (m.boundary.get_mut(b), m.fixed.get_mut(p)) {
                    *slot = p as u32;
                    *f = 1;
                }
                b += 1;
            }
        }
    }
    let mut c = 0;
    for j in 0..NY - 1 {
        for i in 0..NX - 1 {
            let a = (i + NX * j) as u32;
            let (b1, c1, d1) = (a + 1, a + 1 + NX as u32, a + NX as u32);
            let tris = if (i + j) % 2 == 0 {
                [[a, b1, c1], [a, c1, d1]]
            } else {
                [[a, b1, d1], [b1, c1, d1]]
            };
            for t in tris {
                for (k, v) in t.into_iter().enumerate() {
                    if let Some(slot) = m.nodes.get_mut(3 * c + k) {
                        *slot = v;
                    }
                }
                c += 1;
                if let Some(o) = m.offsets.get_mut(c) {
                    *o = 3 * c as u32;
                }
            }
        }
    }
    if let Ok(cells) = Cells::new(N, &m.offsets, &m.nodes, &m.kinds) {
        if let Ok(used) = graph_from_cells(&cells, false, &mut m.graph_offsets, &mut m.targets) {
            m.used = used;
        }
    }
    m
}

/// The prescribed motion: the bottom row (j = 0) turns by 20° about its midpoint; the rest of
/// the perimeter stays. Returns the displacement of every node (zero inside).
pub(crate) fn boundary_displacement<T: Real>(m: &Mesh<T>) -> [[T; 2]; N] {
    let q = Quat::from_rotation_z(T::from_f64(20f64.to_radians()));
    let centre = [T::from_f64((NX - 1) as f64 * 0.5), T::ZERO];
    let mut d = [[T::ZERO; 2]; N];
    for i in 0..NX {
        if let (Some(p), Some(di)) = (m.points.get(i), d.get_mut(i)) {
            let r = q.rotate_2d([p[0] - centre[0], p[1] - centre[1]]);
            *di = [r[0] + centre[0] - p[0], r[1] + centre[1] - p[1]];
        }
    }
    d
}

/// Builds the Batina spring system of the mesh (stiffness `1/|e|`, perimeter fixed) and runs
/// `f` on it with the stiffness slice; `None` when a step fails (never for this mesh).
pub(crate) fn with_system<T: Real, R>(
    m: &Mesh<T>,
    f: impl FnOnce(&SpringSystem<'_, T>, &[T]) -> R,
) -> Option<R> {
    let g = Graph::new(&m.graph_offsets, m.targets.get(..m.used)?).ok()?;
    let mut k = [T::ZERO; NE];
    let k = k.get_mut(..m.used)?;
    batina_stiffness(&g, &m.points, T::ONE, k).ok()?;
    let k: &[T] = k;
    let mut seen = [0u32; N];
    let sys = SpringSystem::new(g, k, &m.fixed, &mut seen).ok()?;
    Some(f(&sys, k))
}

pub(crate) fn hash_report<T: Real>(h: &mut Fnv, r: &SolveReport<T>) {
    h.usize(r.iterations);
    h.real(r.residual);
    h.real(r.max_update);
    h.byte(r.converged as u8);
}

pub(crate) fn hash_points<T: Real, const D: usize>(h: &mut Fnv, pts: &[[T; D]]) {
    for p in pts {
        h.reals(*p);
    }
}

/// Linear springs (Batina stiffness): CG with SSOR and 40 Jacobi sweeps on the 20° motion.
pub fn spring_linear<T: Real>() -> u64 {
    let m = mesh::<T>();
    with_system(&m, |sys, k| {
        let mut h = Fnv::new();
        for &x in k {
            h.real(x);
        }
        let methods = [
            (
                LinearMethod::Cg {
                    preconditioner: Preconditioner::Ssor {
                        omega: T::from_f64(1.2),
                    },
                },
                500,
            ),
            (LinearMethod::Jacobi, 40),
        ];
        for (method, max_iterations) in methods {
            let mut values = boundary_displacement(&m);
            let mut scratch = [[T::ZERO; 2]; 5 * N];
            let len = solve_linear_scratch_len(&method, N).min(scratch.len());
            let opts = SolveOptions {
                max_iterations,
                ..SolveOptions::default()
            };
            let scratch = scratch.get_mut(..len).unwrap_or(&mut []);
            match sys.solve_linear(&mut values, method, &opts, scratch) {
                Ok(r) => hash_report(&mut h, &r),
                Err(e) => h.error(&e),
            }
            hash_points(&mut h, &values);
        }
        h.finish()
    })
    .unwrap_or(0)
}

/// Linear springs with the multigrid-preconditioned CG: the hierarchy's sizes, one V-cycle
/// of a fixed residual and the whole solve, for both smoothers (coarse levels down to 4
/// unknowns, so the small mesh still has a coarse level).
pub fn spring_amg<T: Real>() -> u64 {
    spring_amg_with::<T>(None)
}

/// [`spring_amg`] with the strength threshold θ = 0.9, which makes the softer springs of this
/// mesh weak: the strength test's arithmetic and the aggregation it steers.
pub fn spring_amg_strength<T: Real>() -> u64 {
    spring_amg_with::<T>(Some(T::from_f64(0.9)))
}

/// [`spring_amg`] with the default options, or with `theta` as the strength threshold.
fn spring_amg_with<T: Real>(theta: Option<T>) -> u64 {
    let m = mesh::<T>();
    with_system(&m, |sys, _| {
        let mut h = Fnv::new();
        for smoother in [AmgSmoother::Jacobi, AmgSmoother::Chebyshev] {
            let base = AmgOptions::default();
            let opts = AmgOptions {
                smoother,
                max_coarse: 4,
                strength_theta: theta.unwrap_or(base.strength_theta),
                ..base
            };
            let mut work = [0u32; 4 * (N + NE) + 64];
            let mut index = [0u32; 2048];
            let mut vals = [T::ZERO; 1024];
            match AmgHierarchy::setup_len(sys, &opts, &mut work) {
                Ok(s) => {
                    h.usize(s.index);
                    h.usize(s.values);
                    h.usize(s.levels);
                    h.usize(s.coarse_unknowns);
                }
                Err(e) => h.error(&e),
            }
            let hier = match AmgHierarchy::setup(sys, &opts, &mut work, &mut index, &mut vals) {
                Ok(x) => x,
                Err(e) => {
                    h.error(&e);
                    continue;
                }
            };
            let mut scratch = [[T::ZERO; 2]; 8 * N];
            let r = boundary_displacement(&m);
            let mut z = [[T::ZERO; 2]; N];
            let len = amg_precondition_scratch_len(&hier).min(scratch.len());
            match sys.amg_precondition(&hier, &r, &mut z, scratch.get_mut(..len).unwrap_or(&mut []))
            {
                Ok(()) => hash_points(&mut h, &z),
                Err(e) => h.error(&e),
            }
            let mut values = boundary_displacement(&m);
            let len = solve_linear_amg_scratch_len(&hier).min(scratch.len());
            let stop = SolveOptions {
                max_iterations: 100,
                ..SolveOptions::default()
            };
            let sc = scratch.get_mut(..len).unwrap_or(&mut []);
            match sys.solve_linear_amg(&hier, &mut values, &stop, sc) {
                Ok(r) => hash_report(&mut h, &r),
                Err(e) => h.error(&e),
            }
            hash_points(&mut h, &values);
        }
        h.finish()
    })
    .unwrap_or(0)
}

/// Angle-inclusion springs (Yang & Özgen eq. 2): direct Gauss–Seidel (60 sweeps) and CG.
pub fn spring_angle<T: Real>() -> u64 {
    let m = mesh::<T>();
    with_system(&m, |sys, _| {
        let mut h = Fnv::new();
        let eps = T::from_f64(DEFAULT_ANGLE_EPSILON);
        let asys = match AngleSystem::new(*sys, &m.points, eps) {
            Ok(a) => a,
            Err(e) => {
                h.error(&e);
                return h.finish();
            }
        };
        for (method, max_iterations) in
            [(AngleMethod::DirectGaussSeidel, 60), (AngleMethod::Cg, 500)]
        {
            let mut values = boundary_displacement(&m);
            let mut scratch = [[T::ZERO; 2]; 4 * N];
            let len = asys.angle_scratch_len(method).min(scratch.len());
            let opts = SolveOptions {
                max_iterations,
                ..SolveOptions::default()
            };
            let scratch = scratch.get_mut(..len).unwrap_or(&mut []);
            match asys.solve_angle(&mut values, method, &opts, scratch) {
                Ok(r) => hash_report(&mut h, &r),
                Err(e) => h.error(&e),
            }
            hash_points(&mut h, &values);
        }
        h.finish()
    })
    .unwrap_or(0)
}

/// Angle-inclusion springs by the multigrid-preconditioned CG (`solve_angle_amg`): the scalar
/// hierarchy of the base system (coarse levels down to 4 unknowns), the scratch size, a short
/// scratch's error and the whole solve, for both smoothers and `ε` = 0.01 and 0 (the rigidity
/// probe first).
pub fn spring_angle_amg<T: Real>() -> u64 {
    let m = mesh::<T>();
    with_system(&m, |sys, _| {
        let mut h = Fnv::new();
        for smoother in [AmgSmoother::Jacobi, AmgSmoother::Chebyshev] {
            let opts = AmgOptions {
                smoother,
                max_coarse: 4,
                ..AmgOptions::default()
            };
            let mut work = [0u32; 4 * (N + NE) + 64];
            let mut index = [0u32; 2048];
            let mut vals = [T::ZERO; 1024];
            let hier = match AmgHierarchy::setup(sys, &opts, &mut work, &mut index, &mut vals) {
                Ok(x) => x,
                Err(e) => {
                    h.error(&e);
                    continue;
                }
            };
            h.usize(hier.levels());
            h.usize(hier.coarse_unknowns());
            for eps in [T::from_f64(DEFAULT_ANGLE_EPSILON), T::ZERO] {
                let asys = match AngleSystem::new(*sys, &m.points, eps) {
                    Ok(a) => a,
                    Err(e) => {
                        h.error(&e);
                        continue;
                    }
                };
                let len = asys.angle_amg_scratch_len(&hier);
                h.usize(len);
                let mut scratch = [[T::ZERO; 2]; 8 * N];
                let len = len.min(scratch.len());
                let stop = SolveOptions {
                    max_iterations: 100,
                    ..SolveOptions::default()
                };
                let mut values = boundary_displacement(&m);
                let short = scratch.get_mut(..len.saturating_sub(1)).unwrap_or(&mut []);
                match asys.solve_angle_amg(&hier, &mut values, &stop, short) {
                    Ok(r) => hash_report(&mut h, &r),
                    Err(e) => h.error(&e),
                }
                let sc = scratch.get_mut(..len).unwrap_or(&mut []);
                match asys.solve_angle_amg(&hier, &mut values, &stop, sc) {
                    Ok(r) => hash_report(&mut h, &r),
                    Err(e) => h.error(&e),
                }
                hash_points(&mut h, &values);
            }
        }
        h.finish()
    })
    .unwrap_or(0)
}

/// The quaternion deformation (Samareh) of the 20° motion, propagated by springs (CG) and by
/// inverse distance; then the quality comparison of the spring result.
pub fn quaternion_deformation<T: Real>() -> u64 {
    let m = mesh::<T>();
    with_system(&m, |sys, _| deformation_hash(&m, sys)).unwrap_or(0)
}

/// The body of [`quaternion_deformation`] once the spring system exists.
fn deformation_hash<T: Real>(m: &Mesh<T>, sys: &SpringSystem<'_, T>) -> u64 {
    let mut h = Fnv::new();
    let disp = boundary_displacement(m);
    let q = Quat::from_rotation_z(T::from_f64(20f64.to_radians()));
    let mut deformed = [[T::ZERO; 2]; NB];
    let mut rotations_b = [Quat::identity(); NB];
    for ((d, r), &node) in deformed
        .iter_mut()
        .zip(rotations_b.iter_mut())
        .zip(&m.boundary)
    {
        let n = node as usize;
        if let (Some(p), Some(u)) = (m.points.get(n), disp.get(n)) {
            *d = [p[0] + u[0], p[1] + u[1]];
        }
        if n < NX {
            *r = q;
        }
    }
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&rotations_b),
        origin: None,
    };
    let mut translations = [[T::ZERO; 2]; N];
    let mut rotations = [Quat::identity(); N];
    let mut scratch = [T::ZERO; 8 * N];
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut values = [T::ZERO; 36 * N];
    let vlen = propagate_spring_scratch_len::<2>(&method, N).min(values.len());
    let slen = deform_spring_scratch_len::<2>(N, NB).min(scratch.len());
    let mut out = [[T::ZERO; 2]; N];
    match deform_spring(
        &m.points,
        &motion,
        sys,
        method,
        &SolveOptions::default(),
        &mut translations,
        &mut rotations,
        scratch.get_mut(..slen).unwrap_or(&mut []),
        values.get_mut(..vlen).unwrap_or(&mut []),
        &mut out,
    ) {
        Ok((origin, r)) => {
            h.reals(origin);
            hash_report(&mut h, &r);
        }
        Err(e) => h.error(&e),
    }
    hash_points(&mut h, &out);
    if let Ok(cells) = Cells::new(N, &m.offsets, &m.nodes, &m.kinds) {
        match compare(&cells, &m.points, &out, None, &mut []) {
            Ok(r) => {
                h.usize(r.inverted_cells);
                h.usize(r.folded_cells);
                h.real(r.min_measure_ratio);
                h.real(r.max_measure_ratio);
                h.real(r.min_measure);
                h.real(r.min_scaled_jacobian);
            }
            Err(e) => h.error(&e),
        }
    }

    let slen = deform_idw_scratch_len::<2>(N, NB).min(scratch.len());
    match deform_idw(
        &m.points,
        &motion,
        T::TWO,
        &mut translations,
        &mut rotations,
        scratch.get_mut(..slen).unwrap_or(&mut []),
        &mut out,
    ) {
        Ok(origin) => h.reals(origin),
        Err(e) => h.error(&e),
    }
    hash_points(&mut h, &out);
    h.finish()
}

/// Block of the Taubin cases.
const BI: usize = 9;
const BJ: usize = 7;

/// Taubin λ|μ (Alter): arclength smoothing of a noisy 9 × 7 block along i (30 iterations), and
/// the scalar filter on a noisy 5 × 4 × 3 field (10 iterations).
pub fn taubin_smoothing<T: Real>() -> u64 {
    let mut rng = XorShift::new(0x7A0B_1234);
    let mut h = Fnv::new();
    let Ok(block) = Block::new([BI, BJ, 1]) else {
        return 0;
    };
    let mut points = [[T::ZERO; 2]; BI * BJ];
    for (p, pt) in points.iter_mut().enumerate() {
        let (i, j) = (p % BI, p / BI);
        let s = i as f64 / (BI - 1) as f64;
        let x = s * s * 4.0
            + if i > 0 && i < BI - 1 {
                0.05 * (rng.unit_f64() - 0.5)
            } else {
                0.0
            };
        *pt = [T::from_f64(x), T::from_f64(j as f64 * 0.5)];
    }
    let opts = SmoothOptions::new(Direction::I);
    let mut scratch = [T::ZERO; 8 * BI * BJ];
    let len = smooth_arclength_scratch_len::<2>(&block, Direction::I, None).min(scratch.len());
    match smooth_arclength(
        &block,
        &mut points,
        &opts,
        scratch.get_mut(..len).unwrap_or(&mut []),
    ) {
        Ok(r) => {
            h.usize(r.iterations);
            h.real(r.last_change);
            h.real(r.max_displacement);
            h.real(r.stretching_before.0);
            h.usize(r.stretching_before.1);
            h.real(r.stretching_after.0);
            h.usize(r.stretching_after.1);
        }
        Err(e) => h.error(&e),
    }
    hash_points(&mut h, &points);

    let Ok(block3) = Block::new([5, 4, 3]) else {
        return 1;
    };
    let mut field = [T::ZERO; 60];
    for f in field.iter_mut() {
        *f = rng.uniform(-1.0, 1.0);
    }
    let mut scratch3 = [T::ZERO; 60];
    let len = structured_scratch_len(&block3).min(scratch3.len());
    let sopts = StructuredOptions {
        fixed: None,
        mirror: Directions::only(Direction::J),
    };
    match smooth_structured(
        &block3,
        &mut field,
        TaubinParams::paper(),
        10,
        &sopts,
        scratch3.get_mut(..len).unwrap_or(&mut []),
    ) {
        Ok(r) => {
            h.usize(r.iterations);
            h.real(r.last_change);
        }
        Err(e) => h.error(&e),
    }
    for &x in &field {
        h.real(x);
    }
    h.finish()
}
