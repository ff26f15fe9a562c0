//! The C ABI on target, f32 and f64: the `dk_*` functions the C library exports, called the way
//! a C or Fortran solver on a Cortex-M4F would call them, give the bits of the Rust API.
//!
//! - `dk_graph_from_cells` with 1-based cells (Fortran's numbering, converted in a caller
//!   `index_scratch`) builds the kernel's graph; a short scratch is a typed error with the
//!   outputs untouched.
//! - A prepared plan stepped through `dk_plan_*` (linear springs, multigrid CG, warm starts)
//!   gives per step the bits, iterations and warm/extrapolated flags of the Rust `Plan`; a
//!   corrupted pool is `DK_ERR_BAD_PLAN` with `out` and the report untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use core::mem::MaybeUninit;

use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanSolver, PlanSpec, PlanStiffness, PlanWork,
};
use deform_kernel::spring::{AmgOptions, SolveOptions};
use deform_kernel::Real;
use deform_kernel_ffi::graph::{dk_cells, dk_graph};
use deform_kernel_ffi::plan::{
    dk_plan_info, dk_plan_mesh, dk_plan_mesh_f32, dk_plan_options, dk_plan_pools,
    dk_plan_pools_f32, dk_plan_sizes, dk_plan_step_report, DK_PLAN_SPRING, DK_PLAN_WARM,
};
use deform_kernel_ffi::status::dk_status;
use deform_on_target::abi::{cells, graph};
use deform_on_target::mesh::{turned_bottom_row as deformed, Mesh, N, NB, NE, NT, NX};

/// Pool and work lengths (generous for the 30-node mesh; the queried sizes must fit).
const REALS: usize = 3072;
const INDICES: usize = 2048;
const BYTES: usize = 128;
const WORK: usize = 4 * (N + NE) + 64;
/// Steps per run.
const STEPS: usize = 4;
/// CG iteration cap of both sides.
const MAX_ITERATIONS: usize = 500;

type OptionsFn = unsafe extern "C" fn(*mut dk_plan_options) -> dk_status;
type SizesFn<M> =
    unsafe extern "C" fn(*const M, u32, *const dk_plan_options, *mut dk_plan_sizes) -> dk_status;
type PoolSizesFn<M, P> = unsafe extern "C" fn(
    *const M,
    u32,
    *const dk_plan_options,
    *const P,
    *mut dk_plan_sizes,
) -> dk_status;
type InitFn<M, P> = unsafe extern "C" fn(
    *const M,
    u32,
    *const dk_plan_options,
    *const P,
    *const P,
    *mut dk_plan_info,
) -> dk_status;
type StepFn<T, P> = unsafe extern "C" fn(
    *const P,
    u32,
    *const T,
    usize,
    u32,
    *const T,
    usize,
    *const T,
    usize,
    u32,
    *mut T,
    usize,
    *mut dk_plan_step_report,
) -> dk_status;

/// No cells: every array NULL with length 0.
fn no_cells() -> dk_cells {
    cells(&[], &[], &[])
}

/// The f64 or `_f32` plan functions and structs, and the residual tolerance used with them.
trait Abi: Real {
    /// `dk_plan_mesh` or `dk_plan_mesh_f32`.
    type Mesh;
    /// `dk_plan_pools` or `dk_plan_pools_f32`.
    type Pools;
    const OPTIONS: OptionsFn;
    const WORK_SIZES: SizesFn<Self::Mesh>;
    const POOL_SIZES: PoolSizesFn<Self::Mesh, Self::Pools>;
    const INIT: InitFn<Self::Mesh, Self::Pools>;
    const STEP: StepFn<Self, Self::Pools>;
    const TOL: f64;
    /// The plan mesh borrowing `points`, `graph`'s arrays and `boundary`, without elements and
    /// with Batina's stiffness (NULL with length 0).
    fn mesh(points: &[Self], graph: dk_graph, boundary: &[u32]) -> Self::Mesh;
    /// Three pools (or work buffers) borrowing the slices, each with its own length.
    fn pools(reals: &mut [Self], indices: &mut [u32], bytes: &mut [u8]) -> Self::Pools;
}

macro_rules! abi_impl {
    ($t:ty, $mesh:ident, $pools:ident, $tol:expr,
     [$options:path, $work:path, $pool:path, $init:path, $step:path]) => {
        impl Abi for $t {
            type Mesh = $mesh;
            type Pools = $pools;
            const OPTIONS: OptionsFn = $options;
            const WORK_SIZES: SizesFn<$mesh> = $work;
            const POOL_SIZES: PoolSizesFn<$mesh, $pools> = $pool;
            const INIT: InitFn<$mesh, $pools> = $init;
            const STEP: StepFn<$t, $pools> = $step;
            const TOL: f64 = $tol;
            fn mesh(points: &[$t], graph: dk_graph, boundary: &[u32]) -> $mesh {
                $mesh {
                    points: points.as_ptr(),
                    points_len: points.len(),
                    graph,
                    boundary: boundary.as_ptr(),
                    boundary_len: boundary.len(),
                    elements: no_cells(),
                    stiffness: core::ptr::null(),
                    stiffness_len: 0,
                }
            }
            fn pools(reals: &mut [$t], indices: &mut [u32], bytes: &mut [u8]) -> $pools {
                $pools {
                    reals: reals.as_mut_ptr(),
                    reals_len: reals.len(),
                    indices: indices.as_mut_ptr(),
                    indices_len: indices.len(),
                    bytes: bytes.as_mut_ptr(),
                    bytes_len: bytes.len(),
                }
            }
        }
    };
}

abi_impl!(
    f64,
    dk_plan_mesh,
    dk_plan_pools,
    1e-9,
    [
        deform_kernel_ffi::plan::dk_plan_options_default,
        deform_kernel_ffi::plan::dk_plan_work_sizes,
        deform_kernel_ffi::plan::dk_plan_pool_sizes,
        deform_kernel_ffi::plan::dk_plan_init,
        deform_kernel_ffi::plan::dk_plan_step
    ]
);
abi_impl!(
    f32,
    dk_plan_mesh_f32,
    dk_plan_pools_f32,
    1e-4,
    [
        deform_kernel_ffi::plan::dk_plan_options_default_f32,
        deform_kernel_ffi::plan::dk_plan_work_sizes_f32,
        deform_kernel_ffi::plan::dk_plan_pool_sizes_f32,
        deform_kernel_ffi::plan::dk_plan_init_f32,
        deform_kernel_ffi::plan::dk_plan_step_f32
    ]
);

/// The Rust side: the same plan, built with the kernel API.
fn rust_plan<T: Abi>(
    m: &Mesh<T>,
    reals: &mut [T; REALS],
    indices: &mut [u32; INDICES],
    bytes: &mut [u8; BYTES],
) {
    let options = SolveOptions::<T> {
        max_iterations: MAX_ITERATIONS,
        residual_tol: T::from_f64(T::TOL),
        ..SolveOptions::default()
    };
    let spec = PlanSpec {
        points: &m.points,
        graph: m.graph(),
        boundary: &m.boundary,
        elements: None,
        constraints: None,
        method: PlanMethod::Spring,
        stiffness: PlanStiffness::Batina { exponent: T::ONE },
        solver: PlanSolver::Amg(AmgOptions::default()),
        options,
        renumber: deform_kernel::plan::PlanOrder::AsGiven,
    };
    let mut wr = [T::ZERO; NE];
    let mut wi = [0u32; WORK];
    let mut wb = [0u8; N];
    let mut work = PlanWork {
        reals: &mut wr,
        indices: &mut wi,
        bytes: &mut wb,
    };
    Plan::<T, 2>::init(&spec, &mut work, reals, indices, bytes).unwrap();
}

fn flat<T, const D: usize>(a: &[[T; D]]) -> &[T] {
    a.as_flattened()
}

fn flat_mut<T, const D: usize>(a: &mut [[T; D]]) -> &mut [T] {
    a.as_flattened_mut()
}

/// One warm `dk_plan_step` (or `_f32`) of the plan in the pools, rotations from the springs'
/// method (none), default origin.
fn step_abi<T: Abi>(
    reals: &mut [T; REALS],
    indices: &mut [u32; INDICES],
    bytes: &mut [u8; BYTES],
    d: &[[T; 2]; NB],
    out: &mut [[T; 2]; N],
    rep: &mut dk_plan_step_report,
) -> dk_status {
    let pools = T::pools(reals, indices, bytes);
    // SAFETY: the pools and `out` writable for their lengths, `d` readable, no rotations or
    // origin (NULL with length 0), `rep` one struct.
    unsafe {
        T::STEP(
            &pools,
            2,
            flat(d).as_ptr(),
            2 * NB,
            0,
            core::ptr::null(),
            0,
            core::ptr::null(),
            0,
            DK_PLAN_WARM,
            flat_mut(out).as_mut_ptr(),
            2 * N,
            rep,
        )
    }
}

/// A plan stepped through the C ABI equals the Rust plan bit for bit, step by step.
fn plan_through_the_abi<T: Abi>() {
    let m = Mesh::<T>::new(0.25);
    let mut o = MaybeUninit::<dk_plan_options>::zeroed();
    // SAFETY: `o` is one writable struct.
    defmt::assert!(unsafe { T::OPTIONS(o.as_mut_ptr()) } == dk_status::DK_OK);
    // SAFETY: every field is an integer or a float, so the zeroed struct was valid already, and
    // the call above filled it.
    let mut o = unsafe { o.assume_init() };
    o.method = DK_PLAN_SPRING;
    o.linear.max_iterations = MAX_ITERATIONS;
    o.linear.residual_tol = T::TOL;
    let g = &m.targets[..m.used];
    let mesh = T::mesh(flat(&m.points), graph(&m.graph_offsets, g), &m.boundary);
    let mut ws = dk_plan_sizes::default();
    // SAFETY: every array of `mesh` is valid for its length; the elements and the stiffness
    // are NULL with length 0; `mesh`, `o` and `ws` are one struct each.
    let s = unsafe { T::WORK_SIZES(&mesh, 2, &o, &mut ws) };
    defmt::assert!(s == dk_status::DK_OK && ws.reals <= NE && ws.indices <= WORK && ws.bytes <= N);
    let mut wr = [T::ZERO; NE];
    let mut wi = [0u32; WORK];
    let mut wb = [0u8; N];
    let mut sizes = dk_plan_sizes::default();
    let work = T::pools(&mut wr, &mut wi, &mut wb);
    // SAFETY: as above, plus the work buffers writable for their lengths.
    let s = unsafe { T::POOL_SIZES(&mesh, 2, &o, &work, &mut sizes) };
    defmt::assert!(s == dk_status::DK_OK);
    defmt::assert!(sizes.reals <= REALS && sizes.indices <= INDICES && sizes.bytes <= BYTES);
    let mut reals = [T::ZERO; REALS];
    let mut indices = [0u32; INDICES];
    let mut bytes = [0u8; BYTES];
    let mut info = dk_plan_info::default();
    let pools = T::pools(&mut reals, &mut indices, &mut bytes);
    // SAFETY: as above, plus the pools writable for their lengths and `info` one struct.
    let s = unsafe { T::INIT(&mesh, 2, &o, &work, &pools, &mut info) };
    defmt::assert!(s == dk_status::DK_OK && info.nodes == N && info.boundary == NB);
    defmt::assert!(info.used == sizes && info.amg_levels >= 1);

    let (mut rr, mut ri, mut rb) = ([T::ZERO; REALS], [0u32; INDICES], [0u8; BYTES]);
    rust_plan(&m, &mut rr, &mut ri, &mut rb);
    let mut iterations = 0;
    for step in 1..=STEPS {
        let d = deformed(&m, step);
        let mut out = [[T::ZERO; 2]; N];
        let mut rep = dk_plan_step_report::default();
        let s = step_abi(&mut reals, &mut indices, &mut bytes, &d, &mut out, &mut rep);
        defmt::assert!(s == dk_status::DK_OK && rep.step == step as u64 && rep.converged);
        let mut expect = [[T::ZERO; 2]; N];
        let r = Plan::<T, 2>::open(&mut rr, &mut ri, &mut rb)
            .unwrap()
            .step(&PlanMotion::new(&d), &mut expect)
            .unwrap();
        defmt::assert!(deform_on_target::same_bits(&out, &expect));
        defmt::assert!(r.solve.iterations == rep.iterations);
        defmt::assert!(r.warm == rep.warm && r.extrapolated == rep.extrapolated);
        defmt::assert!(rep.warm == (step > 1));
        iterations += rep.iterations;
    }
    defmt::info!(
        "{=str}: {=usize} steps through dk_plan_step, {=usize} CG iterations, Rust bits",
        deform_on_target::precision::<T>(),
        STEPS,
        iterations
    );

    // A corrupted pool: a typed error, `out` and the report untouched, the plan not stepped.
    reals[0] = T::from_f64(12345.0);
    let mut out = [[T::from_f64(7.0); 2]; N];
    let mut rep = dk_plan_step_report {
        iterations: 99,
        ..dk_plan_step_report::default()
    };
    let d = deformed(&m, STEPS + 1);
    let s = step_abi(&mut reals, &mut indices, &mut bytes, &d, &mut out, &mut rep);
    defmt::assert!(s == dk_status::DK_ERR_BAD_PLAN);
    defmt::assert!(rep.iterations == 99 && rep.step == 0);
    defmt::assert!(out.iter().flatten().all(|&x| x == T::from_f64(7.0)));
}

/// 1-based cells (Fortran) through `dk_graph_from_cells`: the kernel's graph; a short
/// `index_scratch` is `DK_ERR_BUFFER_TOO_SMALL` with the outputs untouched.
fn graph_from_1_based_cells() {
    let m = Mesh::<f64>::new(0.25);
    let mut offsets1 = m.offsets;
    let mut nodes1 = m.nodes;
    for x in offsets1.iter_mut().chain(nodes1.iter_mut()) {
        *x += 1;
    }
    let mut scratch = [0u32; NT + 1 + 3 * NT];
    let mut offsets = [7u32; N + 1];
    let mut targets = [7u32; NE];
    let mut used = 99usize;
    let call = |scratch: &mut [u32],
                offsets: &mut [u32; N + 1],
                targets: &mut [u32; NE],
                used: &mut usize| {
        let c = cells(&offsets1, &nodes1, &m.kinds);
        // SAFETY: every array (the cells' too) is valid for the length passed with it; `used`
        // is one size_t.
        unsafe {
            deform_kernel_ffi::graph::dk_graph_from_cells(
                N,
                &c,
                1,
                scratch.as_mut_ptr(),
                scratch.len(),
                false,
                offsets.as_mut_ptr(),
                offsets.len(),
                targets.as_mut_ptr(),
                targets.len(),
                used,
            )
        }
    };
    let short = scratch.len() - 1;
    let s = call(&mut scratch[..short], &mut offsets, &mut targets, &mut used);
    defmt::assert!(s == dk_status::DK_ERR_BUFFER_TOO_SMALL && used == 99);
    defmt::assert!(offsets.iter().chain(&targets).all(|&x| x == 7));
    let s = call(&mut scratch, &mut offsets, &mut targets, &mut used);
    defmt::assert!(s == dk_status::DK_OK && used == m.used);
    defmt::assert!(offsets == m.graph_offsets && targets[..used] == m.targets[..m.used]);
}

/// The stiffness functions through the ABI give the kernel's bits: wall distances to the
/// bottom row and their factors, dual volumes and their factors, Batina's springs scaled by
/// them (exactly symmetric).
macro_rules! stiffening_case {
    ($name:ident, $t:ty, $sfx:ident) => {
        fn $name() {
            use deform_kernel::spring::{
                batina_stiffness, dual_volumes, inverse_volume_factors, scale_stiffness,
                wall_distance_factors, wall_distances,
            };
            use deform_kernel_ffi::stiffening as st;
            let m = Mesh::<$t>::new(0.25);
            let wall: [u32; NX] = core::array::from_fn(|i| i as u32);
            let mut k = [0.0 as $t; NE];
            let k = &mut k[..m.used];
            batina_stiffness(&m.graph(), &m.points, 1.0, k).unwrap();
            let mut expect = [0.0 as $t; N];
            wall_distances(&m.points, &wall, &mut expect).unwrap();
            wall_distance_factors(&mut expect, 1.0).unwrap();
            let mut volumes = [0.0 as $t; N];
            let mut cs = [0.0 as $t; NT];
            dual_volumes(&m.cells(), &m.points, &mut volumes, &mut cs).unwrap();
            inverse_volume_factors(&mut volumes, 1.0).unwrap();
            let mut kk = [0.0 as $t; NE];
            let kk = &mut kk[..m.used];
            kk.copy_from_slice(k);
            scale_stiffness(&m.graph(), &expect, kk).unwrap();

            let mut d = [0.0 as $t; N];
            let mut v = [0.0 as $t; N];
            let mut kc = [0.0 as $t; NE];
            let kc = &mut kc[..m.used];
            kc.copy_from_slice(k);
            let g = &m.targets[..m.used];
            let mg = graph(&m.graph_offsets, g);
            let mc = cells(&m.offsets, &m.nodes, &m.kinds);
            // SAFETY: every array (the graph's and the cells' too) is valid for the length
            // passed with it.
            let s = unsafe {
                [
                    paste_sfx!(st, dk_spring_wall_distances, $sfx)(
                        flat(&m.points).as_ptr(),
                        2 * N,
                        2,
                        wall.as_ptr(),
                        NX,
                        0,
                        core::ptr::null_mut(),
                        0,
                        d.as_mut_ptr(),
                        N,
                    ),
                    paste_sfx!(st, dk_spring_wall_distance_factors, $sfx)(d.as_mut_ptr(), N, 1.0),
                    paste_sfx!(st, dk_spring_dual_volumes, $sfx)(
                        &mc,
                        0,
                        core::ptr::null_mut(),
                        0,
                        flat(&m.points).as_ptr(),
                        2 * N,
                        2,
                        v.as_mut_ptr(),
                        N,
                        cs.as_mut_ptr(),
                        NT,
                    ),
                    paste_sfx!(st, dk_spring_inverse_volume_factors, $sfx)(v.as_mut_ptr(), N, 1.0),
                    paste_sfx!(st, dk_spring_scale_stiffness, $sfx)(
                        &mg,
                        d.as_ptr(),
                        N,
                        kc.as_mut_ptr(),
                        kc.len(),
                    ),
                ]
            };
            defmt::assert!(s.iter().all(|&s| s == dk_status::DK_OK));
            defmt::assert!(d
                .iter()
                .zip(&expect)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            defmt::assert!(v
                .iter()
                .zip(&volumes)
                .all(|(a, b)| a.to_bits() == b.to_bits()));
            defmt::assert!(kc
                .iter()
                .zip(kk.iter())
                .all(|(a, b)| a.to_bits() == b.to_bits()));
        }
    };
}

/// `st::name` or `st::name_f32`.
macro_rules! paste_sfx {
    ($m:ident, $f:ident, f64) => {
        $m::$f
    };
    ($m:ident, dk_spring_wall_distances, f32) => {
        $m::dk_spring_wall_distances_f32
    };
    ($m:ident, dk_spring_wall_distance_factors, f32) => {
        $m::dk_spring_wall_distance_factors_f32
    };
    ($m:ident, dk_spring_dual_volumes, f32) => {
        $m::dk_spring_dual_volumes_f32
    };
    ($m:ident, dk_spring_inverse_volume_factors, f32) => {
        $m::dk_spring_inverse_volume_factors_f32
    };
    ($m:ident, dk_spring_scale_stiffness, f32) => {
        $m::dk_spring_scale_stiffness_f32
    };
}

stiffening_case!(stiffening_f64, f64, f64);
stiffening_case!(stiffening_f32, f32, f32);

#[defmt_test::tests]
mod tests {
    #[test]
    fn stiffness_choices_through_the_abi_f64() {
        super::stiffening_f64();
    }

    #[test]
    fn stiffness_choices_through_the_abi_f32() {
        super::stiffening_f32();
    }

    #[test]
    fn graph_from_1_based_cells_through_the_abi() {
        super::graph_from_1_based_cells();
    }

    #[test]
    fn plan_through_the_abi_f64() {
        super::plan_through_the_abi::<f64>();
    }

    #[test]
    fn plan_through_the_abi_f32() {
        super::plan_through_the_abi::<f32>();
    }
}
