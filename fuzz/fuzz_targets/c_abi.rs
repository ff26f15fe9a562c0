//! Target 8: the C ABI with arbitrary lengths (never more than the real buffer), NULL pointers
//! and index bases: no crash, a documented status, outputs untouched unless `DK_OK`, and on
//! success the same bits as the Rust API (quaternions, graph builder), finite outputs for finite
//! inputs, and, for the deformation pipelines, boundary nodes reproduced bitwise.
//!
//! Beyond the quaternion and graph-builder calls, every input drives up to four of the solver
//! entry points (springs, the stateless multigrid solves, quality, Taubin, deformation, plans;
//! f64 or `_f32`) on a small structured grid (at most 64 nodes, at most 50 iterations). A
//! stream of "knob" bytes decides, buffer by buffer, whether the pointer is NULL and whether the
//! length passed is the real one, shorter (a lie downwards), or a longer allocation passed in
//! full (arrays carried by a parameter struct, `dk_graph`, `dk_cells`, `dk_spring_system`,
//! `dk_plan_mesh`, `dk_plan_pools`, are shaped the same way in its fields, and the struct
//! pointer itself may be NULL); a stream of `i16` codes gives the values (including NaN, ±Inf,
//! 1e300, −0 and subnormals).
#![no_main]

use std::fmt::Debug;
use std::marker::PhantomData;
use std::ptr;

use arbitrary::Arbitrary;
use deform_kernel::{graph_from_edges, Quat};
use deform_kernel_ffi::deformation::{self as de, dk_boundary_motion, dk_boundary_motion_f32};
use deform_kernel_ffi::deformation_fast as fa;
use deform_kernel_ffi::dk_status;
use deform_kernel_ffi::graph::{dk_cells, dk_graph, dk_graph_from_edges};
use deform_kernel_ffi::order::{self as or, dk_permutation};
use deform_kernel_ffi::plan::{
    self as pl, dk_plan_info, dk_plan_mesh, dk_plan_mesh_f32, dk_plan_options, dk_plan_pools,
    dk_plan_pools_f32, dk_plan_sizes, dk_plan_step_report,
};
use deform_kernel_ffi::quality::{self as qu, dk_cell_quality, dk_quality_report};
use deform_kernel_ffi::quat::{
    dk_quat_average, dk_quat_mul, dk_quat_rotate_points, dk_quat_rotate_points_2d,
};
use deform_kernel_ffi::rbf::{self as rb, dk_rbf_options, dk_rbf_report};
use deform_kernel_ffi::spring::{
    self as sp, dk_amg_options, dk_constraints, dk_constraints_f32, dk_spring_angle_options,
    dk_spring_solve_options, dk_spring_solve_report, dk_spring_sweep, dk_spring_system,
    dk_spring_system_f32,
};
use deform_kernel_ffi::stiffening as st;
use deform_kernel_ffi::taubin::{
    self as ta, dk_filter_report, dk_smooth_arclength_options, dk_smooth_report,
    dk_structured_options, dk_taubin_coarse,
};
use libfuzzer_sys::fuzz_target;

// ---------------------------------------------------------------------------------------------
// Input.
// ---------------------------------------------------------------------------------------------

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<u32>,
    edges_len_cut: u8,
    index_base: u8,
    offsets_len: u8,
    targets_len: u8,
    nulls: u8,
    quats: Vec<f64>,
    quats_len_cut: u8,
    points: Vec<f64>,
    mesh: MeshSpec,
    ops: Vec<Op>,
    knobs: Vec<u8>,
    vals: Vec<i16>,
    bits: Vec<u8>,
}

#[derive(Arbitrary, Debug)]
struct MeshSpec {
    ni: u8,
    nj: u8,
    nk: u8,
    /// Low bit: 3D storage; bits 1..: the `dim` passed (mostly the storage dimension).
    dim: u8,
    /// `index_base` passed: 0, 1 or something else.
    base: u8,
    /// Lie about the block dimensions passed to structured functions.
    dims_lie: u8,
    jitter: Vec<i16>,
    /// A raw (probably invalid) CSR graph instead of the grid's.
    raw_graph: Option<(Vec<u8>, Vec<u8>)>,
}

#[derive(Arbitrary, Debug)]
enum Op {
    Batina {
        exponent: i16,
        f32: bool,
    },
    SolveLinear {
        method: u8,
        precond: u8,
        omega: i16,
        max_iter: u8,
        comps: u8,
        res_tol: i16,
        upd_tol: i16,
        sys: SysSel,
        f32: bool,
    },
    JacobiSweep {
        start: u8,
        end: u8,
        comps: u8,
        sys: SysSel,
        f32: bool,
    },
    SolveAngle {
        method: u8,
        epsilon: i16,
        max_iter: u8,
        sys: SysSel,
        f32: bool,
    },
    /// `dk_spring_solve_linear_amg` or `dk_spring_solve_angle_amg` with their pool-size
    /// queries.
    SolveAmg {
        angle: bool,
        comps: u8,
        max_iter: u8,
        epsilon: i16,
        theta: i16,
        max_levels: u8,
        max_coarse: u8,
        sweeps: u8,
        smoother: u8,
        sys: SysSel,
        f32: bool,
    },
    /// The sliding solves (`dk_spring_solve_{linear,angle}_sliding` and their multigrid
    /// variants) with a knob-shaped `dk_constraints`.
    SolveSliding {
        which: u8,
        method: u8,
        omega: i16,
        max_iter: u8,
        epsilon: i16,
        kinds: u8,
        sys: SysSel,
        f32: bool,
    },
    CellQuality {
        kind: u8,
        from_mesh: bool,
        f32: bool,
    },
    Stiffening {
        wall_node: u8,
        exponent: i16,
        volumes: bool,
        f32: bool,
    },
    Compare {
        wall: bool,
        scale: i16,
        f32: bool,
    },
    SmoothStructured {
        lambda: i16,
        mu: i16,
        iterations: u8,
        pinned: bool,
        mirror: u8,
        f32: bool,
    },
    SmoothArclength {
        direction: u8,
        normalised: bool,
        use_coarse: bool,
        factor: [u8; 3],
        prolongation: u8,
        iterations: u8,
        coarse_iterations: u8,
        params: Option<(i16, i16)>,
        pinned: bool,
        mirror: u8,
        f32: bool,
    },
    SmoothGraph {
        lambda: i16,
        mu: i16,
        iterations: u8,
        comps: u8,
        weights: u8,
        fixed: u8,
        f32: bool,
    },
    Redistribute {
        direction: u8,
        normalised: bool,
        perturb: bool,
        f32: bool,
    },
    Deform(DeformSpec),
    /// `dk_deform_idw_fast` and its tangent and adjoint (and `_f32`).
    DeformFast(DeformSpec, FastSpec),
    /// Node orders: `dk_order_rcm`, `dk_order_hilbert` and `dk_order_permute` there and back.
    Order {
        f32: bool,
    },
    /// `dk_rbf_deform` (and `_f32`) with its two size queries, on the mesh's boundary.
    Rbf {
        kernel: u8,
        radius: i16,
        tolerance: i16,
        max_centres: u8,
        correction: i16,
        f32: bool,
    },
    Plan {
        quaternion: bool,
        amg: bool,
        steps: u8,
        corrupt: u8,
        cold: bool,
        f32: bool,
    },
}

#[derive(Arbitrary, Debug, Clone, Copy)]
struct SysSel {
    /// Stiffness: Batina (1/|d|), uniform, or raw values.
    stiffness: u8,
    /// Fixed mask: the grid boundary, raw bits, or none.
    fixed: u8,
}

#[derive(Arbitrary, Debug)]
struct DeformSpec {
    /// IDW, TFI or springs.
    method: u8,
    rotation_source: u8,
    has_origin: bool,
    origin: [i16; 3],
    rigid: [i16; 4],
    /// Boundary elements: the grid's, raw, or none.
    elements: u8,
    /// Boundary nodes: the grid's boundary, a subset, raw, or with a duplicate.
    boundary: u8,
    raw: Vec<u8>,
    translation: [i16; 3],
    exponent: i16,
    directions: u8,
    spring_method: u8,
    max_iter: u8,
    fixed_flip: u8,
    f32: bool,
}

/// The fast IDW's own parameters beside a [`DeformSpec`].
#[derive(Arbitrary, Debug)]
struct FastSpec {
    /// Deformation, tangent or adjoint.
    mode: u8,
    /// `theta` in twelfths below 1, or 1, NaN, negative.
    theta: u8,
    /// `tolerance` (a fuzzed value, or infinite).
    tolerance: i16,
}

// ---------------------------------------------------------------------------------------------
// Scalars and the per-precision entry points.
// ---------------------------------------------------------------------------------------------

type WallDistancesFn<T> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const u32,
    usize,
    u32,
    *mut u32,
    usize,
    *mut T,
    usize,
) -> dk_status;
type FactorsFn<T> = unsafe extern "C" fn(*mut T, usize, T) -> dk_status;
type DualVolumesFn<T> = unsafe extern "C" fn(
    *const dk_cells,
    u32,
    *mut u32,
    usize,
    *const T,
    usize,
    u32,
    *mut T,
    usize,
    *mut T,
    usize,
) -> dk_status;
type ScaleFn<T> =
    unsafe extern "C" fn(*const dk_graph, *const T, usize, *mut T, usize) -> dk_status;
type RbfFn<T> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const u32,
    usize,
    u32,
    *const T,
    usize,
    *const dk_rbf_options,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut dk_rbf_report,
) -> dk_status;
type BatinaFn<T> =
    unsafe extern "C" fn(*const dk_graph, *const T, usize, u32, T, *mut T, usize) -> dk_status;
type SolveLinearFn<T, S> = unsafe extern "C" fn(
    *const S,
    *const dk_spring_solve_options,
    u32,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut dk_spring_solve_report,
) -> dk_status;
type JacobiFn<T, S> = unsafe extern "C" fn(
    *const S,
    usize,
    usize,
    u32,
    u32,
    *const T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut dk_spring_sweep,
) -> dk_status;
type SolveAngleFn<T, S> = unsafe extern "C" fn(
    *const S,
    *const T,
    usize,
    u32,
    *const dk_spring_angle_options,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut dk_spring_solve_report,
) -> dk_status;
type AngleLenFn =
    unsafe extern "C" fn(usize, u32, *const dk_spring_angle_options, *mut usize) -> dk_status;
type CellQualityFn<T> =
    unsafe extern "C" fn(u8, *const T, usize, u32, *mut dk_cell_quality) -> dk_status;
type CompareFn<T> = unsafe extern "C" fn(
    *const dk_cells,
    u32,
    *mut u32,
    usize,
    *const dk_cells,
    *const dk_graph,
    *const T,
    usize,
    *const T,
    usize,
    u32,
    *mut T,
    usize,
    *mut dk_quality_report,
) -> dk_status;
type StructuredFn<T> = unsafe extern "C" fn(
    usize,
    usize,
    usize,
    T,
    T,
    usize,
    *const dk_structured_options,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut dk_filter_report,
) -> dk_status;
type ArclengthSmoothFn<T> = unsafe extern "C" fn(
    usize,
    usize,
    usize,
    *const dk_smooth_arclength_options,
    *mut T,
    usize,
    u32,
    *mut T,
    usize,
    *mut dk_smooth_report,
) -> dk_status;
type GraphSmoothFn<T> = unsafe extern "C" fn(
    *const dk_graph,
    *const T,
    usize,
    *const u8,
    usize,
    T,
    T,
    usize,
    u32,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut dk_filter_report,
) -> dk_status;
type ArclengthFn<T> = unsafe extern "C" fn(
    usize,
    usize,
    usize,
    *const T,
    usize,
    u32,
    u32,
    bool,
    *mut T,
    usize,
) -> dk_status;
type RedistributeFn<T> = unsafe extern "C" fn(
    usize,
    usize,
    usize,
    u32,
    *const T,
    usize,
    bool,
    *mut T,
    usize,
    u32,
    *mut T,
    usize,
    *mut T,
) -> dk_status;
type IdwFn<T, M> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const M,
    T,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
) -> dk_status;
/// `dk_deform_idw_fast(_f32)`.
type IdwFastFn<T, M> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const M,
    T,
    T,
    T,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
) -> dk_status;
/// `dk_deform_idw_fast_tangent` and `_adjoint` (and `_f32`).
type IdwFastDerivativeFn<T, M> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const M,
    T,
    T,
    T,
    *const T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
) -> dk_status;
type TfiFn<T, M> = unsafe extern "C" fn(
    usize,
    usize,
    usize,
    u32,
    *const T,
    usize,
    u32,
    *const M,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
) -> dk_status;
type SpringFn<T, M, S> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *const M,
    *const S,
    *const dk_spring_solve_options,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut dk_spring_solve_report,
) -> dk_status;
type MotionLenFn<M> = unsafe extern "C" fn(*const M, *mut usize) -> dk_status;
type SpringIndexLenFn<M> = unsafe extern "C" fn(*const M, usize, *mut usize) -> dk_status;

/// The motion arrays, before they become a `dk_boundary_motion(_f32)`.
struct MotionParts<T> {
    nodes: (*const u32, usize),
    deformed: (*const T, usize),
    element_offsets: (*const u32, usize),
    element_nodes: (*const u32, usize),
    element_kinds: (*const u8, usize),
    node_rotations: (*const T, usize),
    rigid: [f64; 4],
    origin: [f64; 3],
    index_base: u32,
    rotation_source: u32,
    has_origin: u32,
}

trait Sc: Copy + Debug + Default + 'static {
    type Motion: Copy;
    /// `dk_spring_system` or `dk_spring_system_f32`.
    type System: Copy;
    const SENT: Self;
    fn of(x: f64) -> Self;
    fn bits(self) -> u64;
    fn fin(self) -> bool;
    fn motion(p: &MotionParts<Self>) -> Self::Motion;
    /// The spring system of a graph, a stiffness and a fixed mask (pointers and lengths as
    /// passed).
    fn system(
        graph: dk_graph,
        stiffness: (*const Self, usize),
        fixed: (*const u8, usize),
    ) -> Self::System;
    const BATINA: BatinaFn<Self>;
    const RBF: RbfFn<Self>;
    const WALL_DISTANCES: WallDistancesFn<Self>;
    const WALL_FACTORS: FactorsFn<Self>;
    const DUAL_VOLUMES: DualVolumesFn<Self>;
    const VOLUME_FACTORS: FactorsFn<Self>;
    const SCALE: ScaleFn<Self>;
    const SOLVE_LINEAR: SolveLinearFn<Self, Self::System>;
    const LINEAR_DEFAULT: unsafe extern "C" fn(*mut dk_spring_solve_options) -> dk_status;
    const JACOBI: JacobiFn<Self, Self::System>;
    const SOLVE_ANGLE: SolveAngleFn<Self, Self::System>;
    const ANGLE_DEFAULT: unsafe extern "C" fn(*mut dk_spring_angle_options) -> dk_status;
    const ANGLE_LEN: AngleLenFn;
    const CELL_QUALITY: CellQualityFn<Self>;
    const COMPARE: CompareFn<Self>;
    const STRUCTURED: StructuredFn<Self>;
    const SMOOTH_ARCLENGTH: ArclengthSmoothFn<Self>;
    const SMOOTH_GRAPH: GraphSmoothFn<Self>;
    const ARCLENGTH: ArclengthFn<Self>;
    const REDISTRIBUTE: RedistributeFn<Self>;
    const IDW: IdwFn<Self, Self::Motion>;
    const IDW_FAST: IdwFastFn<Self, Self::Motion>;
    const IDW_FAST_TANGENT: IdwFastDerivativeFn<Self, Self::Motion>;
    const IDW_FAST_ADJOINT: IdwFastDerivativeFn<Self, Self::Motion>;
    const TFI: TfiFn<Self, Self::Motion>;
    const SPRING: SpringFn<Self, Self::Motion, Self::System>;
    const MOTION_LEN: MotionLenFn<Self::Motion>;
    const SPRING_INDEX_LEN: SpringIndexLenFn<Self::Motion>;
}

macro_rules! motion_of {
    ($m:ty, $def:path, $t:ty, $p:expr) => {{
        let p = $p;
        // SAFETY: a zeroed motion is a valid value (NULL pointers, zero lengths); the default
        // function then fills it.
        let mut m: $m = unsafe { std::mem::zeroed() };
        // SAFETY: one writable struct.
        assert_eq!(unsafe { $def(&mut m) }, dk_status::DK_OK);
        m.nodes = p.nodes.0;
        m.nodes_len = p.nodes.1;
        m.deformed = p.deformed.0;
        m.deformed_len = p.deformed.1;
        m.elements.offsets = p.element_offsets.0;
        m.elements.offsets_len = p.element_offsets.1;
        m.elements.nodes = p.element_nodes.0;
        m.elements.nodes_len = p.element_nodes.1;
        m.elements.kinds = p.element_kinds.0;
        m.elements.kinds_len = p.element_kinds.1;
        m.node_rotations = p.node_rotations.0;
        m.node_rotations_len = p.node_rotations.1;
        m.rigid_rotation = p.rigid.map(|x| x as $t);
        m.origin = p.origin.map(|x| x as $t);
        m.index_base = p.index_base;
        m.rotation_source = p.rotation_source;
        m.has_origin = p.has_origin;
        m
    }};
}

/// A `dk_spring_system(_f32)` from its parts.
macro_rules! system_of {
    ($s:ident, $graph:expr, $stiffness:expr, $fixed:expr) => {{
        let (stiffness, stiffness_len) = $stiffness;
        let (fixed, fixed_len) = $fixed;
        $s {
            graph: $graph,
            stiffness,
            stiffness_len,
            fixed,
            fixed_len,
        }
    }};
}

impl Sc for f64 {
    type Motion = dk_boundary_motion;
    type System = dk_spring_system;
    const SENT: f64 = f64::from_bits(0x7ff0_dead_0000_0001);
    fn of(x: f64) -> f64 {
        x
    }
    fn bits(self) -> u64 {
        self.to_bits()
    }
    fn fin(self) -> bool {
        self.is_finite()
    }
    fn motion(p: &MotionParts<f64>) -> dk_boundary_motion {
        motion_of!(dk_boundary_motion, de::dk_boundary_motion_default, f64, p)
    }
    fn system(
        graph: dk_graph,
        stiffness: (*const f64, usize),
        fixed: (*const u8, usize),
    ) -> dk_spring_system {
        system_of!(dk_spring_system, graph, stiffness, fixed)
    }
    const BATINA: BatinaFn<f64> = sp::dk_spring_batina_stiffness;
    const RBF: RbfFn<f64> = rb::dk_rbf_deform;
    const WALL_DISTANCES: WallDistancesFn<f64> = st::dk_spring_wall_distances;
    const WALL_FACTORS: FactorsFn<f64> = st::dk_spring_wall_distance_factors;
    const DUAL_VOLUMES: DualVolumesFn<f64> = st::dk_spring_dual_volumes;
    const VOLUME_FACTORS: FactorsFn<f64> = st::dk_spring_inverse_volume_factors;
    const SCALE: ScaleFn<f64> = st::dk_spring_scale_stiffness;
    const SOLVE_LINEAR: SolveLinearFn<f64, dk_spring_system> = sp::dk_spring_solve_linear;
    const LINEAR_DEFAULT: unsafe extern "C" fn(*mut dk_spring_solve_options) -> dk_status =
        sp::dk_spring_solve_options_default;
    const JACOBI: JacobiFn<f64, dk_spring_system> = sp::dk_spring_jacobi_sweep;
    const SOLVE_ANGLE: SolveAngleFn<f64, dk_spring_system> = sp::dk_spring_solve_angle;
    const ANGLE_DEFAULT: unsafe extern "C" fn(*mut dk_spring_angle_options) -> dk_status =
        sp::dk_spring_angle_options_default;
    const ANGLE_LEN: AngleLenFn = sp::dk_spring_solve_angle_scratch_len;
    const CELL_QUALITY: CellQualityFn<f64> = qu::dk_quality_cell_quality;
    const COMPARE: CompareFn<f64> = qu::dk_quality_compare;
    const STRUCTURED: StructuredFn<f64> = ta::dk_taubin_smooth_structured;
    const SMOOTH_ARCLENGTH: ArclengthSmoothFn<f64> = ta::dk_taubin_smooth_arclength;
    const SMOOTH_GRAPH: GraphSmoothFn<f64> = ta::dk_taubin_smooth_graph;
    const ARCLENGTH: ArclengthFn<f64> = ta::dk_taubin_arclength;
    const REDISTRIBUTE: RedistributeFn<f64> = ta::dk_taubin_redistribute;
    const IDW: IdwFn<f64, dk_boundary_motion> = de::dk_deform_idw;
    const IDW_FAST: IdwFastFn<f64, dk_boundary_motion> = fa::dk_deform_idw_fast;
    const IDW_FAST_TANGENT: IdwFastDerivativeFn<f64, dk_boundary_motion> =
        fa::dk_deform_idw_fast_tangent;
    const IDW_FAST_ADJOINT: IdwFastDerivativeFn<f64, dk_boundary_motion> =
        fa::dk_deform_idw_fast_adjoint;
    const TFI: TfiFn<f64, dk_boundary_motion> = de::dk_deform_tfi;
    const SPRING: SpringFn<f64, dk_boundary_motion, dk_spring_system> = de::dk_deform_spring;
    const MOTION_LEN: MotionLenFn<dk_boundary_motion> = de::dk_boundary_motion_index_scratch_len;
    const SPRING_INDEX_LEN: SpringIndexLenFn<dk_boundary_motion> =
        de::dk_deform_spring_index_scratch_len;
}

impl Sc for f32 {
    type Motion = dk_boundary_motion_f32;
    type System = dk_spring_system_f32;
    const SENT: f32 = f32::from_bits(0x7fa0_dead);
    fn of(x: f64) -> f32 {
        x as f32
    }
    fn bits(self) -> u64 {
        u64::from(self.to_bits())
    }
    fn fin(self) -> bool {
        self.is_finite()
    }
    fn motion(p: &MotionParts<f32>) -> dk_boundary_motion_f32 {
        motion_of!(
            dk_boundary_motion_f32,
            de::dk_boundary_motion_default_f32,
            f32,
            p
        )
    }
    fn system(
        graph: dk_graph,
        stiffness: (*const f32, usize),
        fixed: (*const u8, usize),
    ) -> dk_spring_system_f32 {
        system_of!(dk_spring_system_f32, graph, stiffness, fixed)
    }
    const BATINA: BatinaFn<f32> = sp::dk_spring_batina_stiffness_f32;
    const RBF: RbfFn<f32> = rb::dk_rbf_deform_f32;
    const WALL_DISTANCES: WallDistancesFn<f32> = st::dk_spring_wall_distances_f32;
    const WALL_FACTORS: FactorsFn<f32> = st::dk_spring_wall_distance_factors_f32;
    const DUAL_VOLUMES: DualVolumesFn<f32> = st::dk_spring_dual_volumes_f32;
    const VOLUME_FACTORS: FactorsFn<f32> = st::dk_spring_inverse_volume_factors_f32;
    const SCALE: ScaleFn<f32> = st::dk_spring_scale_stiffness_f32;
    const SOLVE_LINEAR: SolveLinearFn<f32, dk_spring_system_f32> = sp::dk_spring_solve_linear_f32;
    const LINEAR_DEFAULT: unsafe extern "C" fn(*mut dk_spring_solve_options) -> dk_status =
        sp::dk_spring_solve_options_default_f32;
    const JACOBI: JacobiFn<f32, dk_spring_system_f32> = sp::dk_spring_jacobi_sweep_f32;
    const SOLVE_ANGLE: SolveAngleFn<f32, dk_spring_system_f32> = sp::dk_spring_solve_angle_f32;
    const ANGLE_DEFAULT: unsafe extern "C" fn(*mut dk_spring_angle_options) -> dk_status =
        sp::dk_spring_angle_options_default_f32;
    const ANGLE_LEN: AngleLenFn = sp::dk_spring_solve_angle_scratch_len_f32;
    const CELL_QUALITY: CellQualityFn<f32> = qu::dk_quality_cell_quality_f32;
    const COMPARE: CompareFn<f32> = qu::dk_quality_compare_f32;
    const STRUCTURED: StructuredFn<f32> = ta::dk_taubin_smooth_structured_f32;
    const SMOOTH_ARCLENGTH: ArclengthSmoothFn<f32> = ta::dk_taubin_smooth_arclength_f32;
    const SMOOTH_GRAPH: GraphSmoothFn<f32> = ta::dk_taubin_smooth_graph_f32;
    const ARCLENGTH: ArclengthFn<f32> = ta::dk_taubin_arclength_f32;
    const REDISTRIBUTE: RedistributeFn<f32> = ta::dk_taubin_redistribute_f32;
    const IDW: IdwFn<f32, dk_boundary_motion_f32> = de::dk_deform_idw_f32;
    const IDW_FAST: IdwFastFn<f32, dk_boundary_motion_f32> = fa::dk_deform_idw_fast_f32;
    const IDW_FAST_TANGENT: IdwFastDerivativeFn<f32, dk_boundary_motion_f32> =
        fa::dk_deform_idw_fast_tangent_f32;
    const IDW_FAST_ADJOINT: IdwFastDerivativeFn<f32, dk_boundary_motion_f32> =
        fa::dk_deform_idw_fast_adjoint_f32;
    const TFI: TfiFn<f32, dk_boundary_motion_f32> = de::dk_deform_tfi_f32;
    const SPRING: SpringFn<f32, dk_boundary_motion_f32, dk_spring_system_f32> =
        de::dk_deform_spring_f32;
    const MOTION_LEN: MotionLenFn<dk_boundary_motion_f32> =
        de::dk_boundary_motion_index_scratch_len_f32;
    const SPRING_INDEX_LEN: SpringIndexLenFn<dk_boundary_motion_f32> =
        de::dk_deform_spring_index_scratch_len_f32;
}

// ---------------------------------------------------------------------------------------------
// Knobs (pointer and length of every buffer), values, buffers and output slots.
// ---------------------------------------------------------------------------------------------

struct Knobs<'a> {
    k: &'a [u8],
    i: usize,
}

impl Knobs<'_> {
    fn next(&mut self) -> u8 {
        let b = self.k.get(self.i).copied().unwrap_or(0);
        self.i += 1;
        b
    }

    /// `(allocation, length passed, NULL)` for a buffer that needs `need` elements. The length
    /// passed never exceeds the allocation (unless the pointer is NULL).
    fn shape(&mut self, need: usize) -> (usize, usize, bool) {
        match self.next() {
            0..=0xbf => (need, need, false),
            k @ 0xc0..=0xdf => (need, need.saturating_sub(usize::from(k - 0xbf)), false),
            k @ 0xe0..=0xef => {
                let a = need + usize::from(k - 0xdf);
                (a, a, false)
            }
            k @ 0xf0..=0xf7 => (need, usize::from(k & 1) * need, true),
            k => (0, need + usize::from(k - 0xf7), true),
        }
    }

    fn null_one(&mut self) -> bool {
        self.next() >= 0xfc
    }
}

/// `i16` codes to reals: mostly `x / 256`, a few codes are special values.
fn real(x: i16) -> f64 {
    match x {
        i16::MIN => f64::NAN,
        -32767 => f64::INFINITY,
        -32766 => f64::NEG_INFINITY,
        -32765 => 1e300,
        -32764 => -0.0,
        -32763 => 1e-310,
        -32762 => -1e300,
        _ => f64::from(x) / 256.0,
    }
}

struct Vals<'a> {
    v: &'a [i16],
    i: usize,
    nonfinite: bool,
}

impl Vals<'_> {
    fn next(&mut self) -> f64 {
        if self.v.is_empty() {
            return 0.0;
        }
        let x = real(self.v[self.i % self.v.len()]);
        self.i += 1;
        self.note(x)
    }

    /// Records whether `x` is outside the "finite input" class of the finite-output
    /// invariant: NaN, ±Inf, and also huge values (the `±1e300` codes), whose squares overflow
    /// (a known overflow of the kernel's distances, reported separately) and which are not
    /// `float`s at all.
    fn note(&mut self, x: f64) -> f64 {
        if x.is_nan() || x.abs() > 1e30 {
            self.nonfinite = true;
        }
        x
    }
}

struct Buf<T> {
    v: Vec<T>,
    pass: usize,
    null: bool,
}

impl<T: Copy> Buf<T> {
    /// An input buffer holding `data` (the allocation may be longer, padded with `pad`).
    fn input(kn: &mut Knobs, data: &[T], pad: T) -> Self {
        let (alloc, pass, null) = kn.shape(data.len());
        let mut v = data.to_vec();
        v.resize(alloc, pad);
        Buf { v, pass, null }
    }

    /// An output buffer of `need` elements (or another shape) filled with `fill`.
    fn output(kn: &mut Knobs, need: usize, fill: T) -> Self {
        let (alloc, pass, null) = kn.shape(need);
        Buf {
            v: vec![fill; alloc],
            pass,
            null,
        }
    }

    fn p(&self) -> *const T {
        if self.null {
            ptr::null()
        } else {
            self.v.as_ptr()
        }
    }

    fn m(&mut self) -> *mut T {
        if self.null {
            ptr::null_mut()
        } else {
            self.v.as_mut_ptr()
        }
    }

    fn n(&self) -> usize {
        if !self.null {
            assert!(self.pass <= self.v.len());
        }
        self.pass
    }

    fn absent() -> Self {
        Buf {
            v: Vec::new(),
            pass: 0,
            null: true,
        }
    }

    fn pn(&self) -> (*const T, usize) {
        (self.p(), self.n())
    }
}

fn bits<T: Sc>(s: &[T]) -> Vec<u64> {
    s.iter().map(|x| x.bits()).collect()
}

fn all_sent<T: Sc>(s: &[T]) -> bool {
    s.iter().all(|x| x.bits() == T::SENT.bits())
}

fn all_fin<T: Sc>(s: &[T]) -> bool {
    s.iter().all(|x| x.fin())
}

const SLOT_WORD: u64 = 0xa5a5_5a5a_a5a5_5a5a;

/// One output struct, seen as words so that "unchanged" is checked bit for bit (padding too).
struct Slot<R> {
    w: Vec<u64>,
    null: bool,
    _r: PhantomData<R>,
}

impl<R: Copy> Slot<R> {
    fn new(kn: &mut Knobs) -> Self {
        assert!(std::mem::align_of::<R>() <= 8);
        Slot {
            w: vec![SLOT_WORD; std::mem::size_of::<R>().div_ceil(8)],
            null: kn.null_one(),
            _r: PhantomData,
        }
    }

    fn p(&mut self) -> *mut R {
        if self.null {
            ptr::null_mut()
        } else {
            self.w.as_mut_ptr().cast()
        }
    }

    fn untouched(&self) -> bool {
        self.w.iter().all(|&x| x == SLOT_WORD)
    }

    fn get(&self) -> R {
        assert!(!self.null);
        // SAFETY: the library wrote a whole `R` here (status OK); aligned words.
        unsafe { ptr::read(self.w.as_ptr().cast()) }
    }
}

/// A read-only struct argument, or NULL.
fn opt_ptr<R>(kn: &mut Knobs, r: &R) -> *const R {
    if kn.null_one() {
        ptr::null()
    } else {
        r
    }
}

/// A `dk_graph` of two buffers, each pointer and length as the knobs shaped them.
fn graph_of(offsets: &Buf<u32>, targets: &Buf<u32>) -> dk_graph {
    dk_graph {
        offsets: offsets.p(),
        offsets_len: offsets.n(),
        targets: targets.p(),
        targets_len: targets.n(),
    }
}

/// A `dk_graph` borrowing two slices whole.
fn graph_exact(offsets: &[u32], targets: &[u32]) -> dk_graph {
    dk_graph {
        offsets: offsets.as_ptr(),
        offsets_len: offsets.len(),
        targets: targets.as_ptr(),
        targets_len: targets.len(),
    }
}

/// A `dk_cells` of three buffers, each pointer and length as the knobs shaped them.
fn cells_of(offsets: &Buf<u32>, nodes: &Buf<u32>, kinds: &Buf<u8>) -> dk_cells {
    dk_cells {
        offsets: offsets.p(),
        offsets_len: offsets.n(),
        nodes: nodes.p(),
        nodes_len: nodes.n(),
        kinds: kinds.p(),
        kinds_len: kinds.n(),
    }
}

/// The spring system of four knob-shaped buffers.
fn system_of<T: Sc>(o: &Buf<u32>, t: &Buf<u32>, k: &Buf<T>, f: &Buf<u8>) -> T::System {
    T::system(graph_of(o, t), k.pn(), f.pn())
}

// ---------------------------------------------------------------------------------------------
// The mesh: a jittered structured grid, its edge graph, cells and boundary.
// ---------------------------------------------------------------------------------------------

struct Mesh {
    dims: [usize; 3],
    /// Storage dimension (2 or 3).
    d: usize,
    /// `dim` passed to the library.
    dim: u32,
    /// `index_base` passed.
    base: u32,
    /// Block dimensions passed (maybe a lie).
    pass_dims: [usize; 3],
    n: usize,
    pts: Vec<f64>,
    finite: bool,
    offsets: Vec<u32>,
    targets: Vec<u32>,
    /// Mesh nodes on the block's faces, in a counter-clockwise loop in 2D.
    boundary: Vec<u32>,
    is_boundary: Vec<u8>,
}

impl Mesh {
    fn new(s: &MeshSpec) -> Mesh {
        let d = if s.dim & 1 == 0 { 2 } else { 3 };
        let dim = match (s.dim >> 1) % 16 {
            0..=12 => d as u32,
            13 => 5 - d as u32,
            14 => 0,
            _ => u32::from(s.dim),
        };
        let base = match s.base % 8 {
            0..=3 => 0,
            4..=6 => 1,
            _ => 2 + u32::from(s.base),
        };
        let mut dims = [
            1 + usize::from(s.ni % 8),
            1 + usize::from(s.nj % 8),
            if d == 3 { 1 + usize::from(s.nk % 3) } else { 1 },
        ];
        while dims.iter().product::<usize>() > 64 {
            if dims[2] > 1 {
                dims[2] -= 1;
            } else {
                dims[1] -= 1;
            }
        }
        let [ni, nj, nk] = dims;
        let n = ni * nj * nk;
        let pass_dims = match s.dims_lie % 16 {
            0..=12 => dims,
            13 => [nj, ni, nk],
            14 => [ni, nj, 0],
            _ => [ni, usize::MAX / 2, 3],
        };
        let mut vals = Vals {
            v: &s.jitter,
            i: 0,
            nonfinite: false,
        };
        let mut pts = Vec::with_capacity(n * d);
        for c in 0..n {
            let ijk = [c % ni, c / ni % nj, c / (ni * nj)];
            for &x in &ijk[..d] {
                pts.push(x as f64 + vals.next() / 64.0);
            }
        }
        let at = |i: usize, j: usize, k: usize| (i + ni * (j + nj * k)) as u32;
        let (offsets, targets) = match &s.raw_graph {
            Some((o, t)) => (
                o.iter().map(|&x| u32::from(x)).collect(),
                t.iter().map(|&x| u32::from(x)).collect(),
            ),
            None => {
                let mut pairs = Vec::new();
                for c in 0..n {
                    let (i, j, k) = (c % ni, c / ni % nj, c / (ni * nj));
                    if i + 1 < ni {
                        pairs.push([c as u32, at(i + 1, j, k)]);
                    }
                    if j + 1 < nj {
                        pairs.push([c as u32, at(i, j + 1, k)]);
                    }
                    if k + 1 < nk {
                        pairs.push([c as u32, at(i, j, k + 1)]);
                    }
                }
                let mut o = vec![0u32; n + 1];
                let mut t = vec![0u32; 2 * pairs.len()];
                let used = graph_from_edges(n, &pairs, &mut o, &mut t).unwrap();
                t.truncate(used);
                (o, t)
            }
        };
        let mut boundary = Vec::new();
        if d == 2 && ni >= 2 && nj >= 2 {
            boundary.extend((0..ni).map(|i| at(i, 0, 0)));
            boundary.extend((1..nj).map(|j| at(ni - 1, j, 0)));
            boundary.extend((0..ni - 1).rev().map(|i| at(i, nj - 1, 0)));
            boundary.extend((1..nj - 1).rev().map(|j| at(0, j, 0)));
        } else {
            for c in 0..n {
                let (i, j, k) = (c % ni, c / ni % nj, c / (ni * nj));
                if i == 0
                    || i == ni - 1
                    || j == 0
                    || j == nj - 1
                    || (d == 3 && (k == 0 || k == nk - 1))
                {
                    boundary.push(c as u32);
                }
            }
        }
        let mut is_boundary = vec![0u8; n];
        for &b in &boundary {
            is_boundary[b as usize] = 1;
        }
        Mesh {
            dims,
            d,
            dim,
            base,
            pass_dims,
            n,
            pts,
            finite: !vals.nonfinite,
            offsets,
            targets,
            boundary,
            is_boundary,
        }
    }

    fn pts<T: Sc>(&self) -> Vec<T> {
        self.pts.iter().map(|&x| T::of(x)).collect()
    }

    /// The grid's cells (quads in 2D, hexahedra when `nk > 1`), 0-based.
    fn cells(&self) -> (Vec<u32>, Vec<u32>, Vec<u8>) {
        let [ni, nj, nk] = self.dims;
        let at = |i: usize, j: usize, k: usize| (i + ni * (j + nj * k)) as u32;
        let (mut o, mut c, mut kinds) = (vec![0u32], Vec::new(), Vec::new());
        for k in 0..nk.max(2) - 1 {
            for j in 0..nj.saturating_sub(1) {
                for i in 0..ni.saturating_sub(1) {
                    let quad = [
                        at(i, j, k),
                        at(i + 1, j, k),
                        at(i + 1, j + 1, k),
                        at(i, j + 1, k),
                    ];
                    c.extend(quad);
                    if nk > 1 {
                        c.extend([
                            at(i, j, k + 1),
                            at(i + 1, j, k + 1),
                            at(i + 1, j + 1, k + 1),
                            at(i, j + 1, k + 1),
                        ]);
                        kinds.push(12);
                    } else {
                        kinds.push(9);
                    }
                    o.push(c.len() as u32);
                }
            }
        }
        (o, c, kinds)
    }

    /// Shifts 0-based indices into the `index_base` passed.
    fn based(&self, v: &[u32]) -> Vec<u32> {
        let shift = if self.base == 1 { 1 } else { 0 };
        v.iter().map(|&x| x.wrapping_add(shift)).collect()
    }

    /// A 0-based half-open node range from a caller's `[start, end]` in `index_base`.
    fn range(&self, start: usize, end: usize) -> (usize, usize) {
        if self.base == 1 {
            (start.saturating_sub(1), end)
        } else {
            (start, end)
        }
    }
}

/// The spring system's stiffness and fixed mask.
fn system<T: Sc>(m: &Mesh, sel: SysSel, vals: &mut Vals, bits: &[u8]) -> (Vec<T>, Vec<u8>) {
    let e = m.targets.len();
    let stiffness: Vec<T> = match sel.stiffness % 4 {
        0 | 1 => {
            let mut k = vec![T::default(); e];
            let p = m.pts::<T>();
            let g = graph_exact(&m.offsets, &m.targets);
            // SAFETY: every buffer is exactly as long as passed.
            let s = unsafe {
                (T::BATINA)(
                    &g,
                    p.as_ptr(),
                    p.len(),
                    m.d as u32,
                    T::of(1.0),
                    k.as_mut_ptr(),
                    k.len(),
                )
            };
            if s != dk_status::DK_OK {
                k = vec![T::of(1.0); e];
            }
            k
        }
        2 => vec![T::of(1.0); e],
        _ => (0..e).map(|_| T::of(vals.next())).collect(),
    };
    let fixed = match sel.fixed % 4 {
        0 | 1 => m.is_boundary.clone(),
        2 => (0..m.n)
            .map(|i| bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
            .collect(),
        _ => vec![0; m.n],
    };
    (stiffness, fixed)
}

fn iterations(x: u8) -> usize {
    usize::from(x % 51)
}

fn components(x: u8) -> u32 {
    match x % 10 {
        0..=6 => u32::from(x % 10) + 1,
        7 => 0,
        8 => 8,
        _ => u32::from(x),
    }
}

/// Checks an output that must be unchanged on error; on success its tail past the length
/// passed is unchanged and, for finite inputs, the part written is finite.
fn check_out<T: Sc>(what: &str, s: dk_status, b: &Buf<T>, finite_in: bool) {
    if s != dk_status::DK_OK {
        assert!(all_sent(&b.v), "{what}: written on {s:?}");
    } else {
        let n = b.n().min(b.v.len());
        assert!(all_sent(&b.v[n..]), "{what}: written past its length");
        if finite_in {
            assert!(
                all_fin(&b.v[..n]),
                "{what}: non-finite output on finite input"
            );
        }
    }
}

/// Checks a buffer updated in place (`before` its contents on entry).
fn check_inplace<T: Sc>(what: &str, s: dk_status, b: &Buf<T>, before: &[u64], finite_in: bool) {
    if s != dk_status::DK_OK {
        assert!(bits(&b.v) == before, "{what}: changed on {s:?}");
    } else {
        let n = b.n().min(b.v.len());
        assert!(
            bits(&b.v[n..]) == before[n..],
            "{what}: written past its length"
        );
        if finite_in {
            assert!(
                all_fin(&b.v[..n]),
                "{what}: non-finite result on finite input"
            );
        }
    }
}

fn check_slot<R: Copy>(what: &str, s: dk_status, r: &Slot<R>) {
    if s != dk_status::DK_OK {
        assert!(r.untouched(), "{what}: report written on {s:?}");
    } else {
        assert!(!r.null && !r.untouched(), "{what}: OK without a report");
    }
}

struct Ctx<'a> {
    kn: Knobs<'a>,
    vals: Vals<'a>,
    bits: &'a [u8],
    m: &'a Mesh,
}

// ---------------------------------------------------------------------------------------------
// The operations.
// ---------------------------------------------------------------------------------------------

fn batina<T: Sc>(c: &mut Ctx, exponent: i16) {
    let m = c.m;
    let e = c.vals.note(real(exponent));
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let g = graph_of(&o, &t);
    let gp = opt_ptr(&mut c.kn, &g);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let mut k = Buf::output(&mut c.kn, m.targets.len(), T::SENT);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe { (T::BATINA)(gp, p.p(), p.n(), m.dim, T::of(e), k.m(), k.n()) };
    check_out("batina stiffness", s, &k, m.finite && !c.vals.nonfinite);
}

/// `dk_order_hilbert` or its `_f32` twin.
type HilbertFn<T> = unsafe extern "C" fn(
    *const T,
    usize,
    u32,
    *mut u32,
    usize,
    *mut u32,
    usize,
    *mut u64,
    usize,
) -> dk_status;
/// `dk_order_permute` or its `_f32` twin.
type PermuteFn<T> =
    unsafe extern "C" fn(*const dk_permutation, u32, *const T, usize, *mut T, usize) -> dk_status;

/// An order's two outputs: untouched on error; on success a permutation (as the kernel's
/// `Permutation::new` accepts) in the lengths passed, nothing written past them.
fn check_perm(what: &str, s: dk_status, order: &Buf<u32>, inverse: &Buf<u32>) {
    let untouched =
        |b: &Buf<u32>, from: usize| b.v[from.min(b.v.len())..].iter().all(|&x| x == u32::MAX);
    if s != dk_status::DK_OK {
        assert!(
            untouched(order, 0) && untouched(inverse, 0),
            "{what}: written on {s:?}"
        );
        return;
    }
    let (o, i) = (&order.v[..order.n()], &inverse.v[..inverse.n()]);
    assert!(
        deform_kernel::order::Permutation::new(o, i).is_ok(),
        "{what}: not a permutation"
    );
    assert!(
        untouched(order, order.n()) && untouched(inverse, inverse.n()),
        "{what}: past its length"
    );
}

/// Node orders of the grid: RCM of its graph, the Hilbert order of its points, and the points
/// permuted by that order and back (bit for bit when both calls succeed).
fn orders<T: Sc>(c: &mut Ctx, hilbert: HilbertFn<T>, permute: PermuteFn<T>) {
    let m = c.m;
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let g = graph_of(&o, &t);
    let gp = opt_ptr(&mut c.kn, &g);
    let (mut ro, mut ri) = (
        Buf::output(&mut c.kn, m.n, u32::MAX),
        Buf::output(&mut c.kn, m.n, u32::MAX),
    );
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe { or::dk_order_rcm(gp, ro.m(), ro.n(), ri.m(), ri.n()) };
    check_perm("rcm", s, &ro, &ri);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let (mut ho, mut hi) = (
        Buf::output(&mut c.kn, m.n, u32::MAX),
        Buf::output(&mut c.kn, m.n, u32::MAX),
    );
    let mut keys = Buf::output(&mut c.kn, m.n, u64::MAX);
    // SAFETY: as above.
    let s = unsafe {
        hilbert(
            p.p(),
            p.n(),
            m.dim,
            ho.m(),
            ho.n(),
            hi.m(),
            hi.n(),
            keys.m(),
            keys.n(),
        )
    };
    check_perm("hilbert", s, &ho, &hi);
    if s != dk_status::DK_OK {
        assert!(
            keys.v.iter().all(|&k| k == u64::MAX),
            "hilbert keys written on {s:?}"
        );
        return;
    }
    let perm = dk_permutation {
        order: ho.v.as_ptr(),
        order_len: ho.n(),
        inverse: hi.v.as_ptr(),
        inverse_len: hi.n(),
    };
    let back = dk_permutation {
        order: perm.inverse,
        order_len: perm.inverse_len,
        inverse: perm.order,
        inverse_len: perm.order_len,
    };
    let mut mid = Buf::output(&mut c.kn, p.n(), T::SENT);
    // SAFETY: as above; the permutation's arrays are `ho` and `hi`, alive here.
    let s = unsafe { permute(&perm, m.dim, p.p(), p.n(), mid.m(), mid.n()) };
    check_out("order permute", s, &mid, false);
    if s == dk_status::DK_OK {
        let mut out = vec![T::SENT; mid.n()];
        // SAFETY: as above.
        let s = unsafe { permute(&back, m.dim, mid.p(), mid.n(), out.as_mut_ptr(), out.len()) };
        assert_eq!(s, dk_status::DK_OK, "permuting back");
        assert!(
            bits(&out) == bits(&p.v[..out.len()]),
            "permuted there and back differs"
        );
    }
}

/// Wall distances or dual volumes, their stiffness factors, and a stiffness of ones scaled
/// by them: each step checked for untouched outputs on error, and the scaled stiffness for
/// exact symmetry.
fn stiffening<T: Sc>(c: &mut Ctx, wall_node: u8, exponent: i16, volumes: bool) {
    let m = c.m;
    let e = c.vals.note(real(exponent));
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let mut f = Buf::output(&mut c.kn, m.n, T::SENT);
    let s = if volumes {
        let (co, cn, ck) = m.cells();
        let index_need = if m.base == 1 { co.len() + cn.len() } else { 0 };
        let cob = Buf::input(&mut c.kn, &m.based(&co), 0);
        let cnb = Buf::input(&mut c.kn, &m.based(&cn), 0);
        let ckb = Buf::input(&mut c.kn, &ck, 9);
        let cells = cells_of(&cob, &cnb, &ckb);
        let cp = opt_ptr(&mut c.kn, &cells);
        let mut iscr = Buf::output(&mut c.kn, index_need, 0u32);
        let mut cs = Buf::output(&mut c.kn, ck.len(), T::SENT);
        // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
        // arrays too).
        unsafe {
            (T::DUAL_VOLUMES)(
                cp,
                m.base,
                iscr.m(),
                iscr.n(),
                p.p(),
                p.n(),
                m.dim,
                f.m(),
                f.n(),
                cs.m(),
                cs.n(),
            )
        }
    } else {
        let wb = Buf::input(&mut c.kn, &m.based(&[u32::from(wall_node)]), 0);
        let mut iscr = Buf::output(&mut c.kn, usize::from(m.base == 1), 0u32);
        // SAFETY: every pointer is NULL or valid for the length passed with it.
        unsafe {
            (T::WALL_DISTANCES)(
                p.p(),
                p.n(),
                m.dim,
                wb.p(),
                wb.n(),
                m.base,
                iscr.m(),
                iscr.n(),
                f.m(),
                f.n(),
            )
        }
    };
    check_out("stiffening measure", s, &f, m.finite);
    if s != dk_status::DK_OK {
        return;
    }
    let before = bits(&f.v);
    let factors = if volumes {
        T::VOLUME_FACTORS
    } else {
        T::WALL_FACTORS
    };
    // SAFETY: `f` is valid for the length passed with it.
    let s = unsafe { factors(f.m(), f.n(), T::of(e)) };
    check_inplace("stiffening factors", s, &f, &before, false);
    if s != dk_status::DK_OK {
        return;
    }
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let g = graph_of(&o, &t);
    let gp = opt_ptr(&mut c.kn, &g);
    let fb = Buf::input(&mut c.kn, &f.v[..f.n().min(f.v.len())], T::of(1.0));
    let mut k = Buf::input(&mut c.kn, &vec![T::of(1.0); m.targets.len()], T::of(1.0));
    let before = bits(&k.v);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe { (T::SCALE)(gp, fb.p(), fb.n(), k.m(), k.n()) };
    check_inplace("scale stiffness", s, &k, &before, true);
    if s == dk_status::DK_OK {
        for i in 0..m.n {
            let row = m.offsets[i] as usize..m.offsets[i + 1] as usize;
            for e in row {
                let j = m.targets[e] as usize;
                let back = (m.offsets[j] as usize..m.offsets[j + 1] as usize)
                    .find(|&r| m.targets[r] as usize == i)
                    .expect("symmetric graph");
                assert_eq!(
                    k.v[e].bits(),
                    k.v[back].bits(),
                    "scaled stiffness not symmetric"
                );
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn solve_linear<T: Sc>(
    c: &mut Ctx,
    method: u8,
    precond: u8,
    omega: i16,
    max_iter: u8,
    comps: u8,
    res_tol: i16,
    upd_tol: i16,
    sel: SysSel,
) {
    let m = c.m;
    let (k, fixed) = system::<T>(m, sel, &mut c.vals, c.bits);
    let mut opts = dk_spring_solve_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        omega: 0.0,
        method: 0,
        preconditioner: 0,
    };
    // SAFETY: one writable struct.
    assert_eq!(unsafe { (T::LINEAR_DEFAULT)(&mut opts) }, dk_status::DK_OK);
    opts.max_iterations = iterations(max_iter);
    opts.method = if method < 250 {
        u32::from(method % 4)
    } else {
        u32::from(method)
    };
    opts.preconditioner = if precond < 250 {
        u32::from(precond % 3)
    } else {
        u32::from(precond)
    };
    if omega != 0 {
        opts.omega = c.vals.note(real(omega) / 64.0);
    }
    if res_tol != 0 {
        opts.residual_tol = c.vals.note(real(res_tol) / 1e4);
    }
    if upd_tol != 0 {
        opts.update_tol = c.vals.note(real(upd_tol) / 1e4);
    }
    let comps = components(comps);
    let nv = m.n * comps as usize;
    let values: Vec<T> = (0..nv).map(|_| T::of(c.vals.next())).collect();
    let mut need = 0usize;
    // SAFETY: valid options and output.
    if unsafe { sp::dk_spring_solve_linear_scratch_len(m.n, comps, &opts, &mut need) }
        != dk_status::DK_OK
    {
        need = 4 * nv;
    }
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
    let fb = Buf::input(&mut c.kn, &fixed, 1);
    let sys = system_of(&o, &t, &kb, &fb);
    let sysp = opt_ptr(&mut c.kn, &sys);
    let optp = opt_ptr(&mut c.kn, &opts);
    let mut v = Buf::input(&mut c.kn, &values, T::of(0.25));
    let before = bits(&v.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut idx = Buf::output(&mut c.kn, m.n, 0u32);
    let mut rep = Slot::<dk_spring_solve_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe {
        (T::SOLVE_LINEAR)(
            sysp,
            optp,
            comps,
            v.m(),
            v.n(),
            scratch.m(),
            scratch.n(),
            idx.m(),
            idx.n(),
            rep.p(),
        )
    };
    let finite_in = m.finite && !c.vals.nonfinite;
    check_inplace("solve_linear values", s, &v, &before, finite_in);
    check_slot("solve_linear", s, &rep);
    if s == dk_status::DK_OK {
        let r = rep.get();
        assert!(r.iterations <= opts.max_iterations, "{r:?}");
        // Fixed nodes keep their values.
        let cs = comps as usize;
        for (i, &f) in fb.v.iter().take(fb.n()).enumerate() {
            if f != 0 {
                // Bit for bit, −0.0 included (CG used to turn a fixed −0.0 into +0.0; found
                // here, regression test in host-tests/tests/fuzz_regressions.rs).
                let now = &v.v[i * cs..(i + 1) * cs];
                let was = &before[i * cs..(i + 1) * cs];
                assert!(
                    now.iter().zip(was).all(|(&x, &b)| x.bits() == b),
                    "fixed node {i} changed: {now:?} ({opts:?}, components {comps})"
                );
            }
        }
    }
}

fn jacobi<T: Sc>(c: &mut Ctx, start: u8, end: u8, comps: u8, sel: SysSel) {
    let m = c.m;
    let (k, fixed) = system::<T>(m, sel, &mut c.vals, c.bits);
    let comps = components(comps);
    let nv = m.n * comps as usize;
    let src: Vec<T> = (0..nv).map(|_| T::of(c.vals.next())).collect();
    let span = m.n + 3;
    let (start, end) = (usize::from(start) % span, usize::from(end) % span);
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
    let fb = Buf::input(&mut c.kn, &fixed, 1);
    let sys = system_of(&o, &t, &kb, &fb);
    let sysp = opt_ptr(&mut c.kn, &sys);
    let sb = Buf::input(&mut c.kn, &src, T::of(0.0));
    let mut dst = Buf::output(&mut c.kn, nv, T::SENT);
    let mut idx = Buf::output(&mut c.kn, m.n, 0u32);
    let mut sw = Slot::<dk_spring_sweep>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe {
        (T::JACOBI)(
            sysp,
            start,
            end,
            m.base,
            comps,
            sb.p(),
            sb.n(),
            dst.m(),
            dst.n(),
            idx.m(),
            idx.n(),
            sw.p(),
        )
    };
    check_slot("jacobi_sweep", s, &sw);
    if s != dk_status::DK_OK {
        assert!(all_sent(&dst.v), "jacobi dst written on {s:?}");
        return;
    }
    let finite_in = m.finite && !c.vals.nonfinite;
    let cs = comps as usize;
    let (a, b) = m.range(start, end);
    for i in 0..dst.n() / cs {
        let d = &dst.v[i * cs..(i + 1) * cs];
        if i < a || i >= b {
            assert!(all_sent(d), "jacobi wrote node {i} outside {a}..{b}");
        } else if fb.v[i] != 0 {
            assert!(
                bits(d) == bits(&sb.v[i * cs..(i + 1) * cs]),
                "fixed node {i} not copied"
            );
        } else if finite_in {
            assert!(all_fin(d), "jacobi non-finite at {i}");
        }
    }
    assert!(all_sent(&dst.v[dst.n()..]), "jacobi wrote past dst_len");
}

fn solve_angle<T: Sc>(c: &mut Ctx, method: u8, epsilon: i16, max_iter: u8, sel: SysSel) {
    let m = c.m;
    let (k, fixed) = system::<T>(m, sel, &mut c.vals, c.bits);
    let mut opts = dk_spring_angle_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        epsilon: 0.0,
        method: 0,
    };
    // SAFETY: one writable struct.
    assert_eq!(unsafe { (T::ANGLE_DEFAULT)(&mut opts) }, dk_status::DK_OK);
    opts.max_iterations = iterations(max_iter);
    opts.method = if method < 250 {
        u32::from(method % 3)
    } else {
        u32::from(method)
    };
    if epsilon != 0 {
        opts.epsilon = c.vals.note(real(epsilon) / 256.0);
    }
    let nv = m.n * m.d;
    let values: Vec<T> = (0..nv).map(|_| T::of(c.vals.next() / 16.0)).collect();
    let mut need = 0usize;
    // SAFETY: valid options and output.
    if unsafe { (T::ANGLE_LEN)(m.n, m.dim, &opts, &mut need) } != dk_status::DK_OK {
        need = 4 * nv;
    }
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
    let fb = Buf::input(&mut c.kn, &fixed, 1);
    let sys = system_of(&o, &t, &kb, &fb);
    let sysp = opt_ptr(&mut c.kn, &sys);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let optp = opt_ptr(&mut c.kn, &opts);
    let mut v = Buf::input(&mut c.kn, &values, T::of(0.25));
    let before = bits(&v.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut idx = Buf::output(&mut c.kn, m.n, 0u32);
    let mut rep = Slot::<dk_spring_solve_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe {
        (T::SOLVE_ANGLE)(
            sysp,
            p.p(),
            p.n(),
            m.dim,
            optp,
            v.m(),
            v.n(),
            scratch.m(),
            scratch.n(),
            idx.m(),
            idx.n(),
            rep.p(),
        )
    };
    check_inplace(
        "solve_angle values",
        s,
        &v,
        &before,
        m.finite && !c.vals.nonfinite,
    );
    check_slot("solve_angle", s, &rep);
}

fn cell_quality<T: Sc>(c: &mut Ctx, kind: u8, from_mesh: bool) {
    let m = c.m;
    let (kind, nodes) = match kind % 10 {
        0 => (3, 2),
        1 => (5, 3),
        2 => (9, 4),
        3 => (10, 4),
        4 => (12, 8),
        5 => (13, 6),
        6 => (14, 5),
        7 => (0, 4),
        8 => (7, 4),
        _ => (kind, usize::from(kind % 9)),
    };
    let len = nodes * m.d;
    let corners: Vec<T> = if from_mesh {
        let (_, cn, _) = m.cells();
        (0..len)
            .map(|i| {
                let node = cn.get(i / m.d).map_or(i / m.d, |&x| x as usize) % m.n;
                T::of(m.pts[node * m.d + i % m.d])
            })
            .collect()
    } else {
        (0..len).map(|_| T::of(c.vals.next())).collect()
    };
    let cb = Buf::input(&mut c.kn, &corners, T::of(0.0));
    let mut out = Slot::<dk_cell_quality>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe { (T::CELL_QUALITY)(kind, cb.p(), cb.n(), m.dim, out.p()) };
    check_slot("cell_quality", s, &out);
    if s == dk_status::DK_OK && m.finite && !c.vals.nonfinite {
        let q = out.get();
        assert!(q.measure.is_finite() && q.min_jacobian.is_finite(), "{q:?}");
        assert!(q.min_scaled_jacobian.abs() <= 1.0 + 1e-5, "{q:?}");
    }
}

fn compare<T: Sc>(c: &mut Ctx, wall: bool, scale: i16) {
    let m = c.m;
    let (co, cn, ck) = m.cells();
    let scale = c.vals.note(real(scale)) / 64.0;
    let deformed: Vec<T> = m
        .pts
        .iter()
        .map(|&x| T::of(x + scale * c.vals.next()))
        .collect();
    let [ni, nj, _] = m.dims;
    let (mut wo, mut wn, mut wk) = (vec![0u32], Vec::new(), Vec::new());
    if wall {
        if m.d == 2 {
            for i in 0..ni.saturating_sub(1) {
                wn.extend([i as u32, i as u32 + 1]);
                wk.push(3u8);
                wo.push(wn.len() as u32);
            }
        } else {
            for j in 0..nj.saturating_sub(1) {
                for i in 0..ni.saturating_sub(1) {
                    let a = |i: usize, j: usize| (i + ni * j) as u32;
                    wn.extend([a(i, j), a(i, j + 1), a(i + 1, j + 1), a(i + 1, j)]);
                    wk.push(9u8);
                    wo.push(wn.len() as u32);
                }
            }
        }
    }
    let mut need = 0usize;
    // SAFETY: one writable size_t.
    if !wall
        || unsafe { qu::dk_quality_wall_angle_scratch_len(m.n, m.dim, &mut need) }
            != dk_status::DK_OK
    {
        need = 0;
    }
    let cob = Buf::input(&mut c.kn, &m.based(&co), 0);
    let cnb = Buf::input(&mut c.kn, &m.based(&cn), 0);
    let ckb = Buf::input(&mut c.kn, &ck, 9);
    let cells = cells_of(&cob, &cnb, &ckb);
    let cp = opt_ptr(&mut c.kn, &cells);
    let (wob, wnb, wkb, go, gt) = if wall {
        (
            Buf::input(&mut c.kn, &m.based(&wo), 0),
            Buf::input(&mut c.kn, &m.based(&wn), 0),
            Buf::input(&mut c.kn, &wk, 3),
            Buf::input(&mut c.kn, &m.offsets, 0),
            Buf::input(&mut c.kn, &m.targets, 0),
        )
    } else {
        (
            Buf::absent(),
            Buf::absent(),
            Buf::absent(),
            Buf::absent(),
            Buf::absent(),
        )
    };
    // Without a wall every array is NULL with length 0; the structs are still passed.
    let wall_cells = cells_of(&wob, &wnb, &wkb);
    let wp = opt_ptr(&mut c.kn, &wall_cells);
    let wall_graph = graph_of(&go, &gt);
    let wgp = opt_ptr(&mut c.kn, &wall_graph);
    let u = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let d = Buf::input(&mut c.kn, &deformed, T::of(0.5));
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    // 1-based cells and wall are copied 0-based into the index scratch.
    let index_need = if m.base == 1 {
        co.len() + cn.len() + wo.len() + wn.len()
    } else {
        0
    };
    let mut index_scratch = Buf::output(&mut c.kn, index_need, 0u32);
    let mut rep = Slot::<dk_quality_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the structs'
    // arrays too).
    let s = unsafe {
        (T::COMPARE)(
            cp,
            m.base,
            index_scratch.m(),
            index_scratch.n(),
            wp,
            wgp,
            u.p(),
            u.n(),
            d.p(),
            d.n(),
            m.dim,
            scratch.m(),
            scratch.n(),
            rep.p(),
        )
    };
    check_slot("quality_compare", s, &rep);
    if s == dk_status::DK_OK {
        let r = rep.get();
        let cells = ckb.n();
        assert_eq!(r.cells, cells, "{r:?}");
        assert!(
            r.inverted_cells <= cells && r.folded_cells <= cells,
            "{r:?}"
        );
        assert!(
            r.folded_cells_undeformed <= cells && r.degenerate_cells <= cells,
            "{r:?}"
        );
        let absent = wob.null
            && wnb.null
            && wkb.null
            && go.null
            && gt.null
            && wob.n() + wnb.n() + wkb.n() + go.n() + gt.n() == 0;
        assert_eq!(r.has_wall, !absent, "{r:?}");
        if r.has_wall {
            assert!(r.wall_measured + r.wall_skipped <= m.n, "{r:?}");
            if m.finite && !c.vals.nonfinite {
                assert!(r.wall_max_change.is_finite(), "{r:?}");
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn smooth_structured<T: Sc>(
    c: &mut Ctx,
    lambda: i16,
    mu: i16,
    iters: u8,
    pinned: bool,
    mirror: u8,
) {
    let m = c.m;
    let [ni, nj, nk] = m.pass_dims;
    let (lambda, mu) = (
        c.vals.note(real(lambda) / 128.0),
        c.vals.note(real(mu) / 128.0),
    );
    let field: Vec<T> = (0..m.n).map(|_| T::of(c.vals.next())).collect();
    let pins: Vec<u8> = (0..m.n)
        .map(|i| c.bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
        .collect();
    let mut need = 0usize;
    // SAFETY: one writable size_t.
    if unsafe {
        ta::dk_taubin_smooth_structured_scratch_len(m.dims[0], m.dims[1], m.dims[2], &mut need)
    } != dk_status::DK_OK
    {
        need = m.n;
    }
    let pb = if pinned {
        Buf::input(&mut c.kn, &pins, 0)
    } else {
        Buf::absent()
    };
    let opts = dk_structured_options {
        pinned: pb.p(),
        pinned_len: pb.n(),
        mirror: [mirror & 1, mirror & 2, mirror & 4],
    };
    let optp = opt_ptr(&mut c.kn, &opts);
    let mut f = Buf::input(&mut c.kn, &field, T::of(0.0));
    let before = bits(&f.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut rep = Slot::<dk_filter_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe {
        (T::STRUCTURED)(
            ni,
            nj,
            nk,
            T::of(lambda),
            T::of(mu),
            iterations(iters),
            optp,
            f.m(),
            f.n(),
            scratch.m(),
            scratch.n(),
            rep.p(),
        )
    };
    check_inplace("smooth_structured field", s, &f, &before, !c.vals.nonfinite);
    check_slot("smooth_structured", s, &rep);
    if s == dk_status::DK_OK {
        assert!(rep.get().iterations <= iterations(iters));
        // Only when the mask really reached the library (a knob may pass it as NULL with 0).
        if pinned && !opts.pinned.is_null() && opts.pinned_len > 0 {
            for (i, &p) in pb.v.iter().enumerate().take(f.n()) {
                if p != 0 {
                    assert_eq!(f.v[i].bits(), before[i], "pinned point {i} moved");
                }
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn smooth_arclength<T: Sc>(
    c: &mut Ctx,
    direction: u8,
    normalised: bool,
    use_coarse: bool,
    factor: [u8; 3],
    prolongation: u8,
    iters: u8,
    coarse_iters: u8,
    params: Option<(i16, i16)>,
    pinned: bool,
    mirror: u8,
) {
    let m = c.m;
    let [ni, nj, nk] = m.pass_dims;
    let direction = if direction < 250 {
        u32::from(direction % 3)
    } else {
        u32::from(direction)
    };
    let mut opts = dk_smooth_arclength_options {
        lambda: 0.0,
        mu: 0.0,
        iterations: 0,
        coarse_iterations: 0,
        pinned: ptr::null(),
        pinned_len: 0,
        coarse: dk_taubin_coarse {
            factor: [1; 3],
            prolongation: 0,
        },
        direction: 0,
        normalised: 0,
        use_coarse: 0,
        mirror: [0; 3],
    };
    // SAFETY: one writable struct.
    let s0 = unsafe { ta::dk_smooth_arclength_options_default(direction, &mut opts) };
    assert_eq!(s0 == dk_status::DK_OK, direction <= 2);
    opts.direction = direction;
    opts.iterations = iterations(iters);
    opts.coarse_iterations = iterations(coarse_iters) / 2;
    if let Some((l, mu)) = params {
        opts.lambda = c.vals.note(real(l) / 128.0);
        opts.mu = c.vals.note(real(mu) / 128.0);
    }
    opts.normalised = u8::from(normalised);
    opts.use_coarse = u8::from(use_coarse);
    opts.coarse.factor = factor.map(|f| usize::from(f % 5));
    opts.coarse.prolongation = u32::from(prolongation % 3);
    opts.mirror = [mirror & 1, mirror & 2, mirror & 4];
    let pins: Vec<u8> = (0..m.n)
        .map(|i| c.bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
        .collect();
    let pb = if pinned {
        Buf::input(&mut c.kn, &pins, 0)
    } else {
        Buf::absent()
    };
    opts.pinned = pb.p();
    opts.pinned_len = pb.n();
    let mut need = 0usize;
    // SAFETY: valid options, one writable size_t.
    if unsafe {
        ta::dk_taubin_smooth_arclength_scratch_len(
            m.dims[0], m.dims[1], m.dims[2], &opts, m.d as u32, &mut need,
        )
    } != dk_status::DK_OK
    {
        need = 8 * m.n;
    }
    let optp = opt_ptr(&mut c.kn, &opts);
    let mut p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let before = bits(&p.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut rep = Slot::<dk_smooth_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe {
        (T::SMOOTH_ARCLENGTH)(
            ni,
            nj,
            nk,
            optp,
            p.m(),
            p.n(),
            m.dim,
            scratch.m(),
            scratch.n(),
            rep.p(),
        )
    };
    check_inplace(
        "smooth_arclength points",
        s,
        &p,
        &before,
        m.finite && !c.vals.nonfinite,
    );
    check_slot("smooth_arclength", s, &rep);
    // Only when the mask really reached the library (a knob may pass it as NULL with 0).
    let pins_passed = !opts.pinned.is_null() && opts.pinned_len > 0;
    if s == dk_status::DK_OK && pinned && pins_passed && m.dim as usize == m.d {
        let d = m.d;
        for (i, &q) in pb.v.iter().enumerate().take(p.n() / d) {
            if q != 0 {
                assert!(
                    bits(&p.v[i * d..(i + 1) * d]) == before[i * d..(i + 1) * d],
                    "pinned point {i} moved"
                );
            }
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn smooth_graph<T: Sc>(
    c: &mut Ctx,
    lambda: i16,
    mu: i16,
    iters: u8,
    comps: u8,
    weights: u8,
    fixed: u8,
) {
    let m = c.m;
    let (lambda, mu) = (
        c.vals.note(real(lambda) / 128.0),
        c.vals.note(real(mu) / 128.0),
    );
    let comps = components(comps);
    let nv = m.n * comps as usize;
    let values: Vec<T> = (0..nv).map(|_| T::of(c.vals.next())).collect();
    let d = m.d;
    let w: Option<Vec<T>> = match weights % 3 {
        0 => None,
        1 => Some(
            (0..m.n)
                .flat_map(|i| {
                    let (a, b) = (m.offsets.get(i).copied(), m.offsets.get(i + 1).copied());
                    let r = match (a, b) {
                        (Some(a), Some(b)) if a <= b => a as usize..b as usize,
                        _ => 0..0,
                    };
                    r.map(move |e| (i, e))
                })
                .map(|(i, e)| {
                    let j = m.targets.get(e).map_or(0, |&j| j as usize) % m.n;
                    let dd: f64 = (0..d)
                        .map(|k| (m.pts[i * d + k] - m.pts[j * d + k]).powi(2))
                        .sum();
                    T::of(1.0 / dd.sqrt())
                })
                .collect(),
        ),
        _ => Some((0..m.targets.len()).map(|_| T::of(c.vals.next())).collect()),
    };
    let f: Option<Vec<u8>> = match fixed % 3 {
        0 => None,
        1 => Some(m.is_boundary.clone()),
        _ => Some(
            (0..m.n)
                .map(|i| c.bits.get(i / 8).map_or(0, |b| (b >> (i % 8)) & 1))
                .collect(),
        ),
    };
    let mut need = 0usize;
    // SAFETY: one writable size_t.
    if unsafe { ta::dk_taubin_smooth_graph_scratch_len(m.n, comps, &mut need) } != dk_status::DK_OK
    {
        need = nv;
    }
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let wb = match &w {
        Some(w) => Buf::input(&mut c.kn, w, T::of(1.0)),
        None => Buf::absent(),
    };
    let fb = match &f {
        Some(f) => Buf::input(&mut c.kn, f, 0),
        None => Buf::absent(),
    };
    let g = graph_of(&o, &t);
    let gp = opt_ptr(&mut c.kn, &g);
    let mut v = Buf::input(&mut c.kn, &values, T::of(0.0));
    let before = bits(&v.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut rep = Slot::<dk_filter_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe {
        (T::SMOOTH_GRAPH)(
            gp,
            wb.p(),
            wb.n(),
            fb.p(),
            fb.n(),
            T::of(lambda),
            T::of(mu),
            iterations(iters),
            comps,
            v.m(),
            v.n(),
            scratch.m(),
            scratch.n(),
            rep.p(),
        )
    };
    check_inplace(
        "smooth_graph values",
        s,
        &v,
        &before,
        m.finite && !c.vals.nonfinite,
    );
    check_slot("smooth_graph", s, &rep);
    if s == dk_status::DK_OK {
        let cs = comps as usize;
        for (i, &q) in fb.v.iter().enumerate().take(v.n() / cs) {
            if q != 0 {
                assert!(
                    bits(&v.v[i * cs..(i + 1) * cs]) == before[i * cs..(i + 1) * cs],
                    "fixed node {i} moved"
                );
            }
        }
    }
}

fn redistribute<T: Sc>(c: &mut Ctx, direction: u8, normalised: bool, perturb: bool) {
    let m = c.m;
    let [ni, nj, nk] = m.pass_dims;
    let direction = if direction < 250 {
        u32::from(direction % 3)
    } else {
        u32::from(direction)
    };
    let pts = m.pts::<T>();
    let mut targets = vec![T::default(); m.n];
    // SAFETY: exact buffers.
    let s0 = unsafe {
        (T::ARCLENGTH)(
            m.dims[0],
            m.dims[1],
            m.dims[2],
            pts.as_ptr(),
            pts.len(),
            m.d as u32,
            direction,
            normalised,
            targets.as_mut_ptr(),
            targets.len(),
        )
    };
    if s0 != dk_status::DK_OK {
        targets = (0..m.n).map(|_| T::of(c.vals.next())).collect();
    } else if perturb {
        let extra: Vec<f64> = (0..m.n).map(|_| c.vals.next() / 64.0).collect();
        for (t, e) in targets.iter_mut().zip(extra) {
            // Perturb through f64 (exact for both precisions' values of this size).
            *t = T::of(to_f64(*t) + e);
        }
    }
    let mut need = 0usize;
    // SAFETY: one writable size_t.
    if unsafe {
        ta::dk_taubin_redistribute_scratch_len(
            m.dims[0], m.dims[1], m.dims[2], m.d as u32, direction, &mut need,
        )
    } != dk_status::DK_OK
    {
        need = 4 * m.n;
    }
    let tb = Buf::input(&mut c.kn, &targets, T::of(0.0));
    let mut p = Buf::input(&mut c.kn, &pts, T::of(0.5));
    let before = bits(&p.v);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut md = Buf::output(&mut c.kn, 1, T::SENT);
    // A single-scalar output: non-NULL means at least one element was allocated.
    let mdp = md.m();
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe {
        (T::REDISTRIBUTE)(
            ni,
            nj,
            nk,
            direction,
            tb.p(),
            tb.n(),
            normalised,
            p.m(),
            p.n(),
            m.dim,
            scratch.m(),
            scratch.n(),
            mdp,
        )
    };
    let finite_in = m.finite && !c.vals.nonfinite;
    check_inplace("redistribute points", s, &p, &before, finite_in);
    if s != dk_status::DK_OK {
        assert!(all_sent(&md.v));
    } else {
        assert!(!mdp.is_null());
        if finite_in {
            assert!(md.v[0].fin(), "max displacement {:?}", md.v[0]);
        }
    }
}

fn to_f64<T: Sc>(x: T) -> f64 {
    // Via the bit pattern: f32 bits are < 2^32.
    let b = x.bits();
    if std::mem::size_of::<T>() == 4 {
        f64::from(f32::from_bits(b as u32))
    } else {
        f64::from_bits(b)
    }
}

/// A knob-shaped `dk_boundary_motion(_f32)` of a [`DeformSpec`] on the mesh's boundary, with
/// the buffers its pointers lead into (moving this struct keeps them valid).
struct MotionBuild<T: Sc> {
    /// Boundary positions (0..B) -> mesh nodes, 0-based.
    nodes: Vec<u32>,
    /// The deformed boundary positions passed.
    deformed: Vec<T>,
    /// The arrays `motion` points into: nodes and element offsets and nodes; element kinds.
    _index: [Buf<u32>; 3],
    _kinds: Buf<u8>,
    /// Deformed positions and node rotations.
    _reals: [Buf<T>; 2],
    motion: T::Motion,
}

fn build_motion<T: Sc>(c: &mut Ctx, sp_: &DeformSpec) -> MotionBuild<T> {
    let m = c.m;
    let d = m.d;
    // Boundary positions (0..B) -> mesh nodes, 0-based.
    let mut nodes: Vec<u32> = match sp_.boundary % 8 {
        0..=4 => m.boundary.clone(),
        5 => m
            .boundary
            .iter()
            .enumerate()
            .filter(|(i, _)| c.bits.get(i / 8).is_none_or(|b| (b >> (i % 8)) & 1 == 0))
            .map(|(_, &x)| x)
            .collect(),
        6 => sp_
            .raw
            .iter()
            .map(|&x| u32::from(x) % (m.n as u32 + 2))
            .collect(),
        _ => {
            let mut v = m.boundary.clone();
            if let Some(&x) = v.first() {
                v.push(x);
            }
            v
        }
    };
    nodes.truncate(64);
    let bl = nodes.len();
    let t = sp_.translation.map(|x| c.vals.note(real(x) / 64.0));
    let mut deformed = Vec::with_capacity(bl * d);
    for &node in &nodes {
        for (k, &tk) in t.iter().enumerate().take(d) {
            let base = m.pts.get(node as usize * d + k).copied().unwrap_or(0.0);
            deformed.push(T::of(base + tk + c.vals.next() / 512.0));
        }
    }
    // Boundary elements, numbered by position in `nodes`.
    let (mut eo, mut en, mut ek) = (Vec::new(), Vec::new(), Vec::new());
    match sp_.elements % 4 {
        0 | 1 if d == 2 && sp_.boundary % 8 <= 4 && m.dims[0] >= 2 && m.dims[1] >= 2 => {
            eo.push(0u32);
            for i in 0..bl {
                en.extend([i as u32, ((i + 1) % bl) as u32]);
                ek.push(3u8);
                eo.push(en.len() as u32);
            }
        }
        2 => {
            let per = if d == 2 { 2 } else { 3 };
            eo.push(0u32);
            for ch in sp_.raw.chunks_exact(per) {
                en.extend(ch.iter().map(|&x| u32::from(x) % (bl as u32 + 1)));
                ek.push(if d == 2 { 3 } else { 5 });
                eo.push(en.len() as u32);
            }
        }
        _ => {}
    }
    let rotations: Vec<T> = (0..4 * bl)
        .map(|i| T::of(if i % 4 == 0 { 1.0 } else { 0.0 } + c.vals.next() / 256.0))
        .collect();
    let rigid = sp_.rigid.map(|x| c.vals.note(real(x) / 64.0));
    let rigid = [1.0 + rigid[0], rigid[1], rigid[2], rigid[3]];
    let origin = sp_.origin.map(|x| c.vals.note(real(x) / 64.0));
    let rotation_source = match sp_.rotation_source % 8 {
        0..=2 => 0,
        3..=4 => 1,
        5..=6 => 2,
        _ => u32::from(sp_.rotation_source),
    };
    let nb = Buf::input(&mut c.kn, &m.based(&nodes), 0);
    let db = Buf::input(&mut c.kn, &deformed, T::of(0.0));
    let (eob, enb, ekb) = if eo.is_empty() {
        (Buf::absent(), Buf::absent(), Buf::absent())
    } else {
        (
            Buf::input(&mut c.kn, &m.based(&eo), 0),
            Buf::input(&mut c.kn, &m.based(&en), 0),
            Buf::input(&mut c.kn, &ek, 3),
        )
    };
    let rb = Buf::input(&mut c.kn, &rotations, T::of(0.0));
    let parts = MotionParts {
        nodes: nb.pn(),
        deformed: db.pn(),
        element_offsets: eob.pn(),
        element_nodes: enb.pn(),
        element_kinds: ekb.pn(),
        node_rotations: rb.pn(),
        rigid,
        origin,
        index_base: m.base,
        rotation_source,
        has_origin: u32::from(sp_.has_origin),
    };
    let motion = T::motion(&parts);
    MotionBuild {
        nodes,
        deformed,
        _index: [nb, eob, enb],
        _kinds: ekb,
        _reals: [db, rb],
        motion,
    }
}

fn deform<T: Sc>(c: &mut Ctx, sp_: &DeformSpec) {
    let m = c.m;
    let d = m.d;
    let mb = build_motion::<T>(c, sp_);
    let (nodes, deformed, bl) = (&mb.nodes, &mb.deformed, mb.nodes.len());
    let motion = mb.motion;
    let mp = opt_ptr(&mut c.kn, &motion);
    let method = sp_.method % 3;
    let dims = m.dims;
    let pdims = m.pass_dims;

    // Spring system and options.
    let (k, mut fixed) = system::<T>(
        m,
        SysSel {
            stiffness: sp_.spring_method >> 4,
            fixed: 0,
        },
        &mut c.vals,
        c.bits,
    );
    if sp_.fixed_flip != 0 && !fixed.is_empty() {
        let i = usize::from(sp_.fixed_flip) % fixed.len();
        fixed[i] ^= 1;
    }
    let mut opts = dk_spring_solve_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        omega: 0.0,
        method: 0,
        preconditioner: 0,
    };
    // SAFETY: one writable struct.
    assert_eq!(unsafe { (T::LINEAR_DEFAULT)(&mut opts) }, dk_status::DK_OK);
    opts.max_iterations = iterations(sp_.max_iter);
    opts.method = u32::from(sp_.spring_method % 5);
    opts.preconditioner = u32::from((sp_.spring_method >> 3) % 3);

    // Sizes.
    let mut need = 0usize;
    let mut vneed = 0usize;
    // SAFETY: valid arguments, writable size_t outputs.
    let q = unsafe {
        match method {
            0 => de::dk_deform_idw_scratch_len(m.n, bl, m.d as u32, &mut need),
            1 => {
                de::dk_deform_tfi_scratch_len(dims[0], dims[1], dims[2], bl, m.d as u32, &mut need)
            }
            _ => {
                de::dk_deform_spring_scratch_len(m.n, bl, m.d as u32, &opts, &mut need, &mut vneed)
            }
        }
    };
    if q != dk_status::DK_OK {
        need = 16 * (m.n + bl);
        vneed = 7 * m.n;
    }
    let mut ineed = 0usize;
    // SAFETY: `motion` is valid (its arrays as described), writable size_t.
    let q = unsafe {
        if method == 2 {
            (T::SPRING_INDEX_LEN)(&motion, m.n, &mut ineed)
        } else {
            (T::MOTION_LEN)(&motion, &mut ineed)
        }
    };
    if q != dk_status::DK_OK {
        ineed = 3 * bl + m.n + 4;
    }
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut idx = Buf::output(&mut c.kn, ineed, 0u32);
    let mut tr = Buf::output(&mut c.kn, m.n * d, T::SENT);
    let mut rot = Buf::output(&mut c.kn, 4 * m.n, T::SENT);
    let mut out = Buf::output(&mut c.kn, m.n * d, T::SENT);
    let mut org = if c.kn.next() & 1 == 0 {
        Buf::absent()
    } else {
        Buf::output(&mut c.kn, d, T::SENT)
    };
    let e = c.vals.note(real(sp_.exponent) / 16.0);
    let s;
    let mut rep = Slot::<dk_spring_solve_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    unsafe {
        match method {
            0 => {
                s = (T::IDW)(
                    p.p(),
                    p.n(),
                    m.dim,
                    mp,
                    T::of(e),
                    scratch.m(),
                    scratch.n(),
                    idx.m(),
                    idx.n(),
                    tr.m(),
                    tr.n(),
                    rot.m(),
                    rot.n(),
                    out.m(),
                    out.n(),
                    org.m(),
                    org.n(),
                );
            }
            1 => {
                let dirs = u32::from(sp_.directions % 9);
                s = (T::TFI)(
                    pdims[0],
                    pdims[1],
                    pdims[2],
                    dirs,
                    p.p(),
                    p.n(),
                    m.dim,
                    mp,
                    scratch.m(),
                    scratch.n(),
                    idx.m(),
                    idx.n(),
                    tr.m(),
                    tr.n(),
                    rot.m(),
                    rot.n(),
                    out.m(),
                    out.n(),
                    org.m(),
                    org.n(),
                );
            }
            _ => {
                let o = Buf::input(&mut c.kn, &m.offsets, 0);
                let t = Buf::input(&mut c.kn, &m.targets, 0);
                let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
                let fb = Buf::input(&mut c.kn, &fixed, 1);
                let sys = system_of(&o, &t, &kb, &fb);
                let sysp = opt_ptr(&mut c.kn, &sys);
                let optp = opt_ptr(&mut c.kn, &opts);
                let mut vals = Buf::output(&mut c.kn, vneed, T::SENT);
                s = (T::SPRING)(
                    p.p(),
                    p.n(),
                    m.dim,
                    mp,
                    sysp,
                    optp,
                    scratch.m(),
                    scratch.n(),
                    vals.m(),
                    vals.n(),
                    idx.m(),
                    idx.n(),
                    tr.m(),
                    tr.n(),
                    rot.m(),
                    rot.n(),
                    out.m(),
                    out.n(),
                    org.m(),
                    org.n(),
                    rep.p(),
                );
            }
        }
    }
    let finite_in = m.finite && !c.vals.nonfinite;
    check_out("deform out", s, &out, finite_in);
    check_out("deform origin_out", s, &org, finite_in);
    if method == 2 {
        check_slot("deform_spring", s, &rep);
    } else {
        assert!(rep.untouched());
    }
    if s == dk_status::DK_OK && m.dim as usize == d {
        assert_boundary_bits("deform", &out.v, nodes, deformed, d);
    }
}

/// The fast IDW's C functions: `dk_deform_idw_fast_lens` for the sizes, then
/// `dk_deform_idw_fast`, its tangent or its adjoint (`mode % 3`) with knob-shaped buffers and
/// fuzzed `theta` and `tolerance` (valid, out of range or NaN).
fn deform_fast<T: Sc>(c: &mut Ctx, sp_: &DeformSpec, f: &FastSpec) {
    let m = c.m;
    let d = m.d;
    let mb = build_motion::<T>(c, sp_);
    let bl = mb.nodes.len();
    let motion = mb.motion;
    let mp = opt_ptr(&mut c.kn, &motion);
    let mut lens = [0usize; 4];
    // SAFETY: four writable size_t.
    let q = unsafe { fa::dk_deform_idw_fast_lens(m.n, bl, m.d as u32, lens.as_mut_ptr()) };
    if q != dk_status::DK_OK {
        lens = [16 * (m.n + bl), 2 * bl + 4, 16 * bl + 16, 16 * (m.n + bl)];
    }
    let mode = f.mode % 3;
    let mut ineed = 0usize;
    // SAFETY: `motion` is valid (its arrays as described), writable size_t.
    if unsafe { (T::MOTION_LEN)(&motion, &mut ineed) } != dk_status::DK_OK {
        ineed = 3 * bl + m.n + 4;
    }
    let theta = T::of(match f.theta {
        0..=239 => f64::from(f.theta % 12) / 12.0,
        240..=247 => 1.0,
        248..=251 => f64::NAN,
        _ => -0.25,
    });
    let tolerance = T::of(match f.tolerance {
        i16::MIN..=-30000 => f64::INFINITY,
        t => c.vals.note(real(t) / 64.0),
    });
    let e = T::of(c.vals.note(real(sp_.exponent) / 16.0));
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let field_len = if mode == 1 { bl * d } else { m.n * d };
    let field: Vec<T> = (0..field_len).map(|_| T::of(c.vals.next())).collect();
    let fb = Buf::input(&mut c.kn, &field, T::of(0.0));
    let scratch_need = if mode == 0 { lens[0] } else { lens[3] };
    let mut scratch = Buf::output(&mut c.kn, scratch_need, T::SENT);
    let mut idx = Buf::output(&mut c.kn, ineed, 0u32);
    let mut ti = Buf::output(&mut c.kn, lens[1], 0u32);
    let mut tree = Buf::output(&mut c.kn, lens[2], T::SENT);
    let mut tr = Buf::output(&mut c.kn, m.n * d, T::SENT);
    let mut rot = Buf::output(&mut c.kn, 4 * m.n, T::SENT);
    let out_len = if mode == 2 { bl * d } else { m.n * d };
    let mut out = Buf::output(&mut c.kn, out_len, T::SENT);
    let wants = usize::from(c.kn.next());
    let mut org = Buf::output(&mut c.kn, d * (wants & 1), T::SENT);
    let mut bound = Buf::output(&mut c.kn, (wants >> 1) & 1, T::SENT);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe {
        match mode {
            0 => (T::IDW_FAST)(
                p.p(),
                p.n(),
                m.dim,
                mp,
                e,
                theta,
                tolerance,
                scratch.m(),
                scratch.n(),
                idx.m(),
                idx.n(),
                ti.m(),
                ti.n(),
                tree.m(),
                tree.n(),
                tr.m(),
                tr.n(),
                rot.m(),
                rot.n(),
                out.m(),
                out.n(),
                org.m(),
                org.n(),
                bound.m(),
                bound.n(),
            ),
            _ => (if mode == 1 {
                T::IDW_FAST_TANGENT
            } else {
                T::IDW_FAST_ADJOINT
            })(
                p.p(),
                p.n(),
                m.dim,
                mp,
                e,
                theta,
                tolerance,
                fb.p(),
                fb.n(),
                scratch.m(),
                scratch.n(),
                idx.m(),
                idx.n(),
                ti.m(),
                ti.n(),
                tree.m(),
                tree.n(),
                tr.m(),
                tr.n(),
                rot.m(),
                rot.n(),
                out.m(),
                out.n(),
            ),
        }
    };
    let finite_in = m.finite && !c.vals.nonfinite;
    check_out("deform_idw_fast out", s, &out, finite_in);
    if mode == 0 {
        // The derivatives take neither.
        check_out("deform_idw_fast origin_out", s, &org, finite_in);
        check_out("deform_idw_fast bound_out", s, &bound, finite_in);
    }
    if s != dk_status::DK_OK || m.dim as usize != d || mode == 2 {
        return;
    }
    // Boundary nodes get the deformed positions (deformation) or `δd` (tangent) bitwise.
    let given = if mode == 0 { &mb.deformed } else { &field };
    assert_boundary_bits("deform_idw_fast", &out.v, &mb.nodes, given, d);
}

/// `out` (`d` values per mesh node) holds `given` (`d` per boundary position) at every boundary
/// node `nodes[b]`, bit for bit.
fn assert_boundary_bits<T: Sc>(what: &str, out: &[T], nodes: &[u32], given: &[T], d: usize) {
    for (b, &node) in nodes.iter().enumerate() {
        let node = node as usize;
        let (o, g) = (&out[node * d..(node + 1) * d], &given[b * d..(b + 1) * d]);
        assert!(
            bits(o) == bits(g),
            "{what}: boundary node {node} (position {b}) not reproduced: {o:?} vs {g:?}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Prepared plans.
// ---------------------------------------------------------------------------------------------

type PlanSizesFn<M> =
    unsafe extern "C" fn(*const M, u32, *const dk_plan_options, *mut dk_plan_sizes) -> dk_status;
type PlanPoolsFn<M, P> = unsafe extern "C" fn(
    *const M,
    u32,
    *const dk_plan_options,
    *const P,
    *mut dk_plan_sizes,
) -> dk_status;
type PlanInitFn<M, P> = unsafe extern "C" fn(
    *const M,
    u32,
    *const dk_plan_options,
    *const P,
    *const P,
    *mut dk_plan_info,
) -> dk_status;
type PlanStepFn<T, P> = unsafe extern "C" fn(
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

/// The plan arrays, before they become a `dk_plan_mesh(_f32)`.
struct PlanMeshParts<T> {
    points: (*const T, usize),
    graph: dk_graph,
    boundary: (*const u32, usize),
    elements: dk_cells,
    stiffness: (*const T, usize),
}

/// The plan entry points and structs of one precision.
trait PlanSc: Sc {
    /// `dk_plan_mesh` or `dk_plan_mesh_f32`.
    type Mesh: Copy;
    /// `dk_plan_pools` or `dk_plan_pools_f32`.
    type Pools: Copy;
    const DEFAULT: unsafe extern "C" fn(*mut dk_plan_options) -> dk_status;
    const WORK: PlanSizesFn<Self::Mesh>;
    const POOLS: PlanPoolsFn<Self::Mesh, Self::Pools>;
    const INIT: PlanInitFn<Self::Mesh, Self::Pools>;
    const STEP: PlanStepFn<Self, Self::Pools>;
    fn mesh(p: &PlanMeshParts<Self>) -> Self::Mesh;
    /// Three knob-shaped buffers as one pools struct.
    fn pools(reals: &mut Buf<Self>, indices: &mut Buf<u32>, bytes: &mut Buf<u8>) -> Self::Pools;
}

macro_rules! plan_sc {
    ($t:ty, $mesh:ident, $pools:ident,
     [$default:path, $work:path, $sizes:path, $init:path, $step:path]) => {
        impl PlanSc for $t {
            type Mesh = $mesh;
            type Pools = $pools;
            const DEFAULT: unsafe extern "C" fn(*mut dk_plan_options) -> dk_status = $default;
            const WORK: PlanSizesFn<$mesh> = $work;
            const POOLS: PlanPoolsFn<$mesh, $pools> = $sizes;
            const INIT: PlanInitFn<$mesh, $pools> = $init;
            const STEP: PlanStepFn<$t, $pools> = $step;
            fn mesh(p: &PlanMeshParts<$t>) -> $mesh {
                $mesh {
                    points: p.points.0,
                    points_len: p.points.1,
                    graph: p.graph,
                    boundary: p.boundary.0,
                    boundary_len: p.boundary.1,
                    elements: p.elements,
                    stiffness: p.stiffness.0,
                    stiffness_len: p.stiffness.1,
                }
            }
            fn pools(reals: &mut Buf<$t>, indices: &mut Buf<u32>, bytes: &mut Buf<u8>) -> $pools {
                $pools {
                    reals: reals.m(),
                    reals_len: reals.n(),
                    indices: indices.m(),
                    indices_len: indices.n(),
                    bytes: bytes.m(),
                    bytes_len: bytes.n(),
                }
            }
        }
    };
}

plan_sc!(
    f64,
    dk_plan_mesh,
    dk_plan_pools,
    [
        pl::dk_plan_options_default,
        pl::dk_plan_work_sizes,
        pl::dk_plan_pool_sizes,
        pl::dk_plan_init,
        pl::dk_plan_step
    ]
);
plan_sc!(
    f32,
    dk_plan_mesh_f32,
    dk_plan_pools_f32,
    [
        pl::dk_plan_options_default_f32,
        pl::dk_plan_work_sizes_f32,
        pl::dk_plan_pool_sizes_f32,
        pl::dk_plan_init_f32,
        pl::dk_plan_step_f32
    ]
);

type AmgSizesFn<S> = unsafe extern "C" fn(
    *const S,
    u32,
    *const dk_amg_options,
    *mut u32,
    usize,
    *mut dk_plan_sizes,
) -> dk_status;
type SolveLinearAmgFn<T, S, P> = unsafe extern "C" fn(
    *const S,
    *const dk_spring_solve_options,
    *const dk_amg_options,
    u32,
    *mut T,
    usize,
    *const P,
    *mut dk_spring_solve_report,
) -> dk_status;
type SolveAngleAmgFn<T, S, P> = unsafe extern "C" fn(
    *const S,
    *const T,
    usize,
    u32,
    *const dk_spring_angle_options,
    *const dk_amg_options,
    *mut T,
    usize,
    *const P,
    *mut dk_spring_solve_report,
) -> dk_status;

/// The stateless multigrid solves of one precision.
trait AmgSc: PlanSc {
    const LINEAR_SIZES: AmgSizesFn<Self::System>;
    const LINEAR: SolveLinearAmgFn<Self, Self::System, Self::Pools>;
    const ANGLE_SIZES: AmgSizesFn<Self::System>;
    const ANGLE: SolveAngleAmgFn<Self, Self::System, Self::Pools>;
}

impl AmgSc for f64 {
    const LINEAR_SIZES: AmgSizesFn<dk_spring_system> = sp::dk_spring_solve_linear_amg_pool_sizes;
    const LINEAR: SolveLinearAmgFn<f64, dk_spring_system, dk_plan_pools> =
        sp::dk_spring_solve_linear_amg;
    const ANGLE_SIZES: AmgSizesFn<dk_spring_system> = sp::dk_spring_solve_angle_amg_pool_sizes;
    const ANGLE: SolveAngleAmgFn<f64, dk_spring_system, dk_plan_pools> =
        sp::dk_spring_solve_angle_amg;
}

impl AmgSc for f32 {
    const LINEAR_SIZES: AmgSizesFn<dk_spring_system_f32> =
        sp::dk_spring_solve_linear_amg_pool_sizes_f32;
    const LINEAR: SolveLinearAmgFn<f32, dk_spring_system_f32, dk_plan_pools_f32> =
        sp::dk_spring_solve_linear_amg_f32;
    const ANGLE_SIZES: AmgSizesFn<dk_spring_system_f32> =
        sp::dk_spring_solve_angle_amg_pool_sizes_f32;
    const ANGLE: SolveAngleAmgFn<f32, dk_spring_system_f32, dk_plan_pools_f32> =
        sp::dk_spring_solve_angle_amg_f32;
}

/// A stateless multigrid solve (linear springs with 1 to 7 components, or the angle springs):
/// the pool sizes from the exact system, then the size query and the solve with every buffer
/// and struct shaped by the knobs (pools too short, NULL, longer), arbitrary multigrid options.
/// No crash, a documented status, values and report untouched unless `DK_OK`, fixed nodes kept
/// bit for bit, finite results for finite input, no more iterations than allowed.
#[allow(clippy::too_many_arguments)]
fn solve_amg<T: AmgSc>(
    c: &mut Ctx,
    angle: bool,
    comps: u8,
    max_iter: u8,
    epsilon: i16,
    theta: i16,
    levels: u8,
    coarse: u8,
    sweeps: u8,
    smoother: u8,
    sel: SysSel,
) {
    let m = c.m;
    let (k, fixed) = system::<T>(m, sel, &mut c.vals, c.bits);
    let mut amg = dk_amg_options {
        strength_theta: 0.0,
        max_levels: 0,
        max_coarse: 0,
        sweeps: 0,
        smoother: 0,
    };
    // SAFETY: one writable struct.
    assert_eq!(
        unsafe { sp::dk_amg_options_default(&mut amg) },
        dk_status::DK_OK
    );
    if theta != 0 {
        amg.strength_theta = c.vals.note(real(theta) / 4096.0);
    }
    amg.max_levels = usize::from(levels % 18);
    amg.max_coarse = match coarse {
        0..=63 => usize::from(coarse) + 1,
        64..=127 => usize::from(coarse) * 40,
        _ => 256,
    };
    amg.sweeps = usize::from(sweeps % 18);
    amg.smoother = if smoother < 250 {
        u32::from(smoother % 2)
    } else {
        u32::from(smoother)
    };
    let mut lopts = dk_spring_solve_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        omega: 0.0,
        method: 0,
        preconditioner: 0,
    };
    let mut aopts = dk_spring_angle_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        epsilon: 0.0,
        method: 0,
    };
    // SAFETY: one writable struct each.
    unsafe {
        assert_eq!((T::LINEAR_DEFAULT)(&mut lopts), dk_status::DK_OK);
        assert_eq!((T::ANGLE_DEFAULT)(&mut aopts), dk_status::DK_OK);
    }
    lopts.max_iterations = iterations(max_iter);
    aopts.max_iterations = iterations(max_iter);
    if epsilon != 0 {
        aopts.epsilon = c.vals.note(real(epsilon) / 256.0);
    }
    let comps = if angle { m.dim } else { components(comps) };
    let nv = m.n * comps as usize;
    let values: Vec<T> = (0..nv).map(|_| T::of(c.vals.next() / 16.0)).collect();

    // The exact sizes, from the exact system (or a guess when the query refuses).
    let mut work_len = 0usize;
    // SAFETY: one writable value.
    let s = unsafe { sp::dk_spring_amg_work_len(m.n, m.targets.len(), &mut work_len) };
    assert_eq!(s, dk_status::DK_OK);
    assert_eq!(work_len, 4 * (m.n + m.targets.len()) + 64);
    let exact = T::system(
        graph_exact(&m.offsets, &m.targets),
        (k.as_ptr(), k.len()),
        (fixed.as_ptr(), fixed.len()),
    );
    let mut work = vec![0u32; work_len];
    let mut need = dk_plan_sizes {
        reals: 0,
        indices: 0,
        bytes: 0,
    };
    let sizes = if angle {
        T::ANGLE_SIZES
    } else {
        T::LINEAR_SIZES
    };
    // SAFETY: valid structs and buffers of the lengths passed.
    let s = unsafe { sizes(&exact, comps, &amg, work.as_mut_ptr(), work_len, &mut need) };
    if s == dk_status::DK_OK {
        assert_eq!(need.bytes, 0);
        // The hierarchy's index entries may be none (a single level without coarse
        // unknowns on a tiny mesh).
        assert!(need.indices >= work_len && need.reals >= 5 * nv, "{need:?}");
    } else {
        need = dk_plan_sizes {
            reals: 6 * nv + 64,
            indices: work_len + 64,
            bytes: 0,
        };
    }

    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
    let fb = Buf::input(&mut c.kn, &fixed, 1);
    let sys = system_of(&o, &t, &kb, &fb);
    let sysp = opt_ptr(&mut c.kn, &sys);
    let amgp = opt_ptr(&mut c.kn, &amg);

    // The size query, knob-shaped.
    let mut wb = Buf::output(&mut c.kn, work_len, 0u32);
    let mut got = Slot::<dk_plan_sizes>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe { sizes(sysp, comps, amgp, wb.m(), wb.n(), got.p()) };
    check_slot("amg pool sizes", s, &got);

    let mut reals = Buf::output(&mut c.kn, need.reals, T::SENT);
    let mut indices = Buf::output(&mut c.kn, need.indices, 0u32);
    let mut bytes = Buf::output(&mut c.kn, 0, 0xa5u8);
    let pools = T::pools(&mut reals, &mut indices, &mut bytes);
    let poolsp = opt_ptr(&mut c.kn, &pools);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let mut v = Buf::input(&mut c.kn, &values, T::of(0.25));
    let before = bits(&v.v);
    let mut rep = Slot::<dk_spring_solve_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the structs'
    // arrays and buffers too).
    let s = unsafe {
        if angle {
            let optp = opt_ptr(&mut c.kn, &aopts);
            (T::ANGLE)(
                sysp,
                p.p(),
                p.n(),
                m.dim,
                optp,
                amgp,
                v.m(),
                v.n(),
                poolsp,
                rep.p(),
            )
        } else {
            let optp = opt_ptr(&mut c.kn, &lopts);
            (T::LINEAR)(sysp, optp, amgp, comps, v.m(), v.n(), poolsp, rep.p())
        }
    };
    let what = if angle {
        "solve_angle_amg"
    } else {
        "solve_linear_amg"
    };
    check_inplace(what, s, &v, &before, m.finite && !c.vals.nonfinite);
    check_slot(what, s, &rep);
    assert!(
        bytes.v.iter().all(|&b| b == 0xa5),
        "{what}: wrote the unused bytes pool"
    );
    if s == dk_status::DK_OK {
        let r = rep.get();
        assert!(r.iterations <= lopts.max_iterations, "{what}: {r:?}");
        let cs = comps as usize;
        for (i, &f) in fb.v.iter().take(fb.n()).enumerate() {
            if f != 0 {
                let now = &v.v[i * cs..(i + 1) * cs];
                let was = &before[i * cs..(i + 1) * cs];
                assert!(
                    now.iter().zip(was).all(|(&x, &b)| x.bits() == b),
                    "{what}: fixed node {i} changed"
                );
            }
        }
    }
}

type LinearSlidingFn<T, S, C> = unsafe extern "C" fn(
    *const S,
    *const C,
    *const dk_spring_solve_options,
    u32,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut dk_spring_solve_report,
) -> dk_status;
type AngleSlidingFn<T, S, C> = unsafe extern "C" fn(
    *const S,
    *const T,
    usize,
    u32,
    *const C,
    *const dk_spring_angle_options,
    T,
    *mut T,
    usize,
    *mut T,
    usize,
    *mut u32,
    usize,
    *mut dk_spring_solve_report,
) -> dk_status;
type LinearSlidingAmgFn<T, S, C, P> = unsafe extern "C" fn(
    *const S,
    *const C,
    *const dk_spring_solve_options,
    *const dk_amg_options,
    u32,
    *mut T,
    usize,
    *const P,
    *mut dk_spring_solve_report,
) -> dk_status;
type AngleSlidingAmgFn<T, S, C, P> = unsafe extern "C" fn(
    *const S,
    *const T,
    usize,
    u32,
    *const C,
    *const dk_spring_angle_options,
    *const dk_amg_options,
    *mut T,
    usize,
    *const P,
    *mut dk_spring_solve_report,
) -> dk_status;

/// The sliding solves of one precision.
trait SlideSc: AmgSc {
    /// `dk_constraints` or `dk_constraints_f32`.
    type Con: Copy;
    fn con(kinds: (*const u8, usize), directions: (*const Self, usize)) -> Self::Con;
    const LINEAR_SLIDING: LinearSlidingFn<Self, Self::System, Self::Con>;
    const ANGLE_SLIDING: AngleSlidingFn<Self, Self::System, Self::Con>;
    const ANGLE_SLIDING_LEN: AngleLenFn;
    const LINEAR_SLIDING_SIZES: AmgSizesFn<Self::System>;
    const LINEAR_SLIDING_AMG: LinearSlidingAmgFn<Self, Self::System, Self::Con, Self::Pools>;
    const ANGLE_SLIDING_SIZES: AmgSizesFn<Self::System>;
    const ANGLE_SLIDING_AMG: AngleSlidingAmgFn<Self, Self::System, Self::Con, Self::Pools>;
}

macro_rules! slide_sc {
    ($t:ty, $con:ident, $sys:ty, $pools:ty, $($f:ident = $path:path),+ $(,)?) => {
        impl SlideSc for $t {
            type Con = $con;
            fn con(kinds: (*const u8, usize), directions: (*const $t, usize)) -> $con {
                $con {
                    kinds: kinds.0,
                    kinds_len: kinds.1,
                    directions: directions.0,
                    directions_len: directions.1,
                }
            }
            $(slide_sc!(@c $f, $t, $con, $sys, $pools, $path);)+
        }
    };
    (@c LINEAR_SLIDING, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const LINEAR_SLIDING: LinearSlidingFn<$t, $sys, $con> = $path;
    };
    (@c ANGLE_SLIDING, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const ANGLE_SLIDING: AngleSlidingFn<$t, $sys, $con> = $path;
    };
    (@c ANGLE_SLIDING_LEN, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const ANGLE_SLIDING_LEN: AngleLenFn = $path;
    };
    (@c LINEAR_SLIDING_SIZES, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const LINEAR_SLIDING_SIZES: AmgSizesFn<$sys> = $path;
    };
    (@c LINEAR_SLIDING_AMG, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const LINEAR_SLIDING_AMG: LinearSlidingAmgFn<$t, $sys, $con, $pools> = $path;
    };
    (@c ANGLE_SLIDING_SIZES, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const ANGLE_SLIDING_SIZES: AmgSizesFn<$sys> = $path;
    };
    (@c ANGLE_SLIDING_AMG, $t:ty, $con:ty, $sys:ty, $pools:ty, $path:path) => {
        const ANGLE_SLIDING_AMG: AngleSlidingAmgFn<$t, $sys, $con, $pools> = $path;
    };
}

slide_sc!(
    f64,
    dk_constraints,
    dk_spring_system,
    dk_plan_pools,
    LINEAR_SLIDING = sp::dk_spring_solve_linear_sliding,
    ANGLE_SLIDING = sp::dk_spring_solve_angle_sliding,
    ANGLE_SLIDING_LEN = sp::dk_spring_solve_angle_sliding_scratch_len,
    LINEAR_SLIDING_SIZES = sp::dk_spring_solve_linear_sliding_amg_pool_sizes,
    LINEAR_SLIDING_AMG = sp::dk_spring_solve_linear_sliding_amg,
    ANGLE_SLIDING_SIZES = sp::dk_spring_solve_angle_sliding_amg_pool_sizes,
    ANGLE_SLIDING_AMG = sp::dk_spring_solve_angle_sliding_amg,
);
slide_sc!(
    f32,
    dk_constraints_f32,
    dk_spring_system_f32,
    dk_plan_pools_f32,
    LINEAR_SLIDING = sp::dk_spring_solve_linear_sliding_f32,
    ANGLE_SLIDING = sp::dk_spring_solve_angle_sliding_f32,
    ANGLE_SLIDING_LEN = sp::dk_spring_solve_angle_sliding_scratch_len_f32,
    LINEAR_SLIDING_SIZES = sp::dk_spring_solve_linear_sliding_amg_pool_sizes_f32,
    LINEAR_SLIDING_AMG = sp::dk_spring_solve_linear_sliding_amg_f32,
    ANGLE_SLIDING_SIZES = sp::dk_spring_solve_angle_sliding_amg_pool_sizes_f32,
    ANGLE_SLIDING_AMG = sp::dk_spring_solve_angle_sliding_amg_f32,
);

/// A sliding solve (`which` % 4: linear one-level, angle one-level, linear multigrid, angle
/// multigrid) on the grid: kinds from the bits (fixed nodes of the system's mask are kind 1,
/// the others free, plane or line, now and then an invalid code or a kind that contradicts the
/// mask), directions mostly unit (an angle, or a normalised triple), now and then raw values;
/// every buffer and struct shaped by the knobs. No crash, a documented status, values and
/// report untouched unless `DK_OK`, fixed nodes kept bit for bit, finite results for finite
/// input, no more iterations than allowed, and plane nodes' displacements in their plane.
#[allow(clippy::too_many_arguments)]
fn solve_sliding<T: SlideSc>(
    c: &mut Ctx,
    which: u8,
    method: u8,
    omega: i16,
    max_iter: u8,
    epsilon: i16,
    kinds_sel: u8,
    sel: SysSel,
) {
    let m = c.m;
    let (k, fixed) = system::<T>(m, sel, &mut c.vals, c.bits);
    let d = m.d;
    // Kinds and directions.
    let mut kinds = Vec::with_capacity(m.n);
    let mut dirs: Vec<T> = Vec::with_capacity(m.n * d);
    for (i, &f) in fixed.iter().enumerate() {
        let b = c.bits.get(i % c.bits.len().max(1)).copied().unwrap_or(0);
        let kind = if f != 0 {
            if kinds_sel == 255 && i == 0 {
                0
            } else {
                1
            }
        } else {
            match (b >> (kinds_sel % 6)) % 4 {
                0 | 1 => 0,
                2 => 2,
                _ => {
                    if kinds_sel >= 250 && i == 0 {
                        4 + (b % 8)
                    } else {
                        3
                    }
                }
            }
        };
        kinds.push(kind);
        let raw = kinds_sel == 249 && i % 3 == 0;
        if raw {
            for _ in 0..d {
                dirs.push(T::of(c.vals.next()));
            }
        } else if d == 2 {
            let a = c.vals.next();
            let a = if a.is_finite() { a } else { 0.0 };
            dirs.push(T::of(a.cos()));
            dirs.push(T::of(a.sin()));
        } else {
            let v = [c.vals.next(), c.vals.next(), c.vals.next()];
            let v = if v.iter().all(|x| x.is_finite() && x.abs() < 1e30) {
                v
            } else {
                [0.0, 0.0, 1.0]
            };
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let v = if len > 1e-3 {
                v.map(|x| x / len)
            } else {
                [1.0, 0.0, 0.0]
            };
            dirs.extend(v.map(T::of));
        }
    }
    let mut lopts = dk_spring_solve_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        omega: 0.0,
        method: 0,
        preconditioner: 0,
    };
    let mut aopts = dk_spring_angle_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        epsilon: 0.0,
        method: 0,
    };
    let mut amg = dk_amg_options {
        strength_theta: 0.0,
        max_levels: 0,
        max_coarse: 0,
        sweeps: 0,
        smoother: 0,
    };
    // SAFETY: one writable struct each.
    unsafe {
        assert_eq!((T::LINEAR_DEFAULT)(&mut lopts), dk_status::DK_OK);
        assert_eq!((T::ANGLE_DEFAULT)(&mut aopts), dk_status::DK_OK);
        assert_eq!(sp::dk_amg_options_default(&mut amg), dk_status::DK_OK);
    }
    lopts.max_iterations = iterations(max_iter);
    aopts.max_iterations = iterations(max_iter);
    lopts.method = if method < 250 {
        u32::from(method % 4)
    } else {
        u32::from(method)
    };
    lopts.preconditioner = u32::from(method / 4 % 3);
    aopts.method = if method < 250 {
        u32::from(method % 3)
    } else {
        u32::from(method)
    };
    let omega = if omega != 0 {
        c.vals.note(real(omega) / 64.0)
    } else {
        1.0
    };
    lopts.omega = omega;
    if epsilon != 0 {
        aopts.epsilon = c.vals.note(real(epsilon) / 256.0);
    }
    let nv = m.n * d;
    let values: Vec<T> = (0..nv).map(|_| T::of(c.vals.next() / 16.0)).collect();
    let which = which % 4;

    // Scratch and pool lengths from the exact arguments (or a guess when a query refuses).
    let mut need = 0usize;
    // SAFETY: valid options and output.
    let s = unsafe {
        if which == 0 {
            sp::dk_spring_solve_linear_sliding_scratch_len(m.n, m.dim, &lopts, &mut need)
        } else {
            (T::ANGLE_SLIDING_LEN)(m.n, m.dim, &aopts, &mut need)
        }
    };
    if s != dk_status::DK_OK {
        need = 6 * nv;
    }
    let mut work_len = 0usize;
    // SAFETY: one writable value.
    let s = unsafe { sp::dk_spring_amg_work_len(m.n, m.targets.len(), &mut work_len) };
    assert_eq!(s, dk_status::DK_OK);
    let exact = T::system(
        graph_exact(&m.offsets, &m.targets),
        (k.as_ptr(), k.len()),
        (fixed.as_ptr(), fixed.len()),
    );
    let mut work = vec![0u32; work_len];
    let mut sizes = dk_plan_sizes {
        reals: 0,
        indices: 0,
        bytes: 0,
    };
    let query = if which == 3 {
        T::ANGLE_SLIDING_SIZES
    } else {
        T::LINEAR_SLIDING_SIZES
    };
    // SAFETY: valid structs and buffers of the lengths passed.
    let s = unsafe { query(&exact, m.dim, &amg, work.as_mut_ptr(), work_len, &mut sizes) };
    if s == dk_status::DK_OK {
        assert_eq!(sizes.bytes, 0);
        // Per component of the `dim` passed (which may differ from the storage dimension).
        assert!(
            sizes.indices >= work_len && sizes.reals >= 6 * m.n * m.dim as usize,
            "{sizes:?}"
        );
    } else {
        sizes = dk_plan_sizes {
            reals: 7 * nv + 64,
            indices: work_len + 64,
            bytes: 0,
        };
    }

    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let kb = Buf::input(&mut c.kn, &k, T::of(1.0));
    let fb = Buf::input(&mut c.kn, &fixed, 1);
    let sys = system_of(&o, &t, &kb, &fb);
    let sysp = opt_ptr(&mut c.kn, &sys);
    let kin = Buf::input(&mut c.kn, &kinds, 0u8);
    let dir = Buf::input(&mut c.kn, &dirs, T::of(0.0));
    let con = T::con(kin.pn(), dir.pn());
    let conp = opt_ptr(&mut c.kn, &con);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let mut v = Buf::input(&mut c.kn, &values, T::of(0.25));
    let before = bits(&v.v);
    let mut rep = Slot::<dk_spring_solve_report>::new(&mut c.kn);
    let mut scratch = Buf::output(&mut c.kn, need, T::SENT);
    let mut idx = Buf::output(&mut c.kn, m.n, 0u32);
    let mut reals = Buf::output(&mut c.kn, sizes.reals, T::SENT);
    let mut indices = Buf::output(&mut c.kn, sizes.indices, 0u32);
    let mut bytes = Buf::output(&mut c.kn, 0, 0xa5u8);
    let pools = T::pools(&mut reals, &mut indices, &mut bytes);
    let poolsp = opt_ptr(&mut c.kn, &pools);
    let amgp = opt_ptr(&mut c.kn, &amg);
    let lp = opt_ptr(&mut c.kn, &lopts);
    let ap = opt_ptr(&mut c.kn, &aopts);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the structs'
    // arrays and buffers too).
    let s = unsafe {
        match which {
            0 => (T::LINEAR_SLIDING)(
                sysp,
                conp,
                lp,
                m.dim,
                v.m(),
                v.n(),
                scratch.m(),
                scratch.n(),
                idx.m(),
                idx.n(),
                rep.p(),
            ),
            1 => (T::ANGLE_SLIDING)(
                sysp,
                p.p(),
                p.n(),
                m.dim,
                conp,
                ap,
                T::of(omega),
                v.m(),
                v.n(),
                scratch.m(),
                scratch.n(),
                idx.m(),
                idx.n(),
                rep.p(),
            ),
            2 => {
                (T::LINEAR_SLIDING_AMG)(sysp, conp, lp, amgp, m.dim, v.m(), v.n(), poolsp, rep.p())
            }
            _ => (T::ANGLE_SLIDING_AMG)(
                sysp,
                p.p(),
                p.n(),
                m.dim,
                conp,
                ap,
                amgp,
                v.m(),
                v.n(),
                poolsp,
                rep.p(),
            ),
        }
    };
    let what = [
        "linear_sliding",
        "angle_sliding",
        "linear_sliding_amg",
        "angle_sliding_amg",
    ][usize::from(which)];
    check_inplace(what, s, &v, &before, m.finite && !c.vals.nonfinite);
    check_slot(what, s, &rep);
    assert!(
        bytes.v.iter().all(|&b| b == 0xa5),
        "{what}: wrote the unused bytes pool"
    );
    if s == dk_status::DK_OK {
        let r = rep.get();
        let cap = if which.is_multiple_of(2) {
            lopts.max_iterations
        } else {
            aopts.max_iterations
        };
        assert!(r.iterations <= cap, "{what}: {r:?}");
        for i in 0..m.n.min(kin.n()) {
            let now = &v.v[i * d..(i + 1) * d];
            let was = &before[i * d..(i + 1) * d];
            if kin.v[i] == 1 {
                assert!(
                    now.iter().zip(was).all(|(&x, &b)| x.bits() == b),
                    "{what}: fixed node {i} changed"
                );
            } else if kin.v[i] == 2 {
                // The displacement lies in the plane, to rounding.
                let n: Vec<f64> = dir.v[i * d..(i + 1) * d]
                    .iter()
                    .map(|&x| to_f64(x))
                    .collect();
                let x: Vec<f64> = now.iter().map(|&x| to_f64(x)).collect();
                let len = x.iter().map(|a| a * a).sum::<f64>().sqrt();
                let dot: f64 = n.iter().zip(&x).map(|(a, b)| a * b).sum();
                if len.is_finite() && len > 1e-30 {
                    assert!(dot.abs() <= 1e-3 * len, "{what}: node {i} left its plane");
                }
            }
        }
    }
}

/// A plan on the grid (boundary fixed, 2D boundary loops as segment elements): sizes, init
/// and up to three steps with arbitrary boundary positions, every buffer shaped by the knobs;
/// `corrupt` overwrites the plan's magic before one step. Statuses documented, outputs
/// untouched unless OK, boundary points reproduced bitwise on OK.
fn plan<T: PlanSc>(c: &mut Ctx, quaternion: bool, amg: bool, steps: u8, corrupt: u8, cold: bool) {
    let m = c.m;
    let b = m.boundary.len();
    let loop2d = m.d == 2 && b >= 3 && m.dims[0] >= 2 && m.dims[1] >= 2;
    let (eo, en, ek): (Vec<u32>, Vec<u32>, Vec<u8>) = if loop2d {
        (
            (0..=b).map(|i| 2 * i as u32).collect(),
            (0..b)
                .flat_map(|i| [i as u32, ((i + 1) % b) as u32])
                .collect(),
            vec![3; b],
        )
    } else {
        (Vec::new(), Vec::new(), Vec::new())
    };
    let mut opts = dk_plan_options {
        method: 0,
        solver: 0,
        stiffness_exponent: 0.0,
        linear: unsafe { std::mem::zeroed() },
        amg: unsafe { std::mem::zeroed() },
    };
    // SAFETY: one writable struct.
    assert_eq!(unsafe { (T::DEFAULT)(&mut opts) }, dk_status::DK_OK);
    opts.method = if quaternion {
        pl::DK_PLAN_QUATERNION
    } else {
        pl::DK_PLAN_SPRING
    };
    opts.solver = if amg {
        pl::DK_PLAN_SOLVER_AMG
    } else {
        pl::DK_PLAN_SOLVER_LINEAR
    };
    opts.linear.max_iterations = 50;
    // Multigrid knobs: the coarsest size and the smoother (out-of-range values must be refused).
    opts.amg.max_coarse = usize::from(c.kn.next() % 64);
    opts.amg.smoother = u32::from(c.kn.next() % 3);
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let o = Buf::input(&mut c.kn, &m.offsets, 0);
    let t = Buf::input(&mut c.kn, &m.targets, 0);
    let bn = Buf::input(&mut c.kn, &m.boundary, 0);
    let (eo, en, ek) = if eo.is_empty() {
        (Buf::absent(), Buf::absent(), Buf::absent())
    } else {
        (
            Buf::input(&mut c.kn, &eo, 0),
            Buf::input(&mut c.kn, &en, 0),
            Buf::input(&mut c.kn, &ek, 3),
        )
    };
    // A given stiffness (1 on every directed edge: symmetric and positive) or Batina's.
    let k = if c.kn.next() & 1 == 1 {
        Buf::input(&mut c.kn, &vec![T::of(1.0); m.targets.len()], T::of(1.0))
    } else {
        Buf::absent()
    };
    let mesh = T::mesh(&PlanMeshParts {
        points: p.pn(),
        graph: graph_of(&o, &t),
        boundary: bn.pn(),
        elements: cells_of(&eo, &en, &ek),
        stiffness: k.pn(),
    });
    let meshp = opt_ptr(&mut c.kn, &mesh);
    let op = opt_ptr(&mut c.kn, &opts);
    let mut work = Slot::<dk_plan_sizes>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it (the struct's
    // arrays too).
    let s = unsafe { (T::WORK)(meshp, m.dim, op, work.p()) };
    check_slot("plan work sizes", s, &work);
    if s != dk_status::DK_OK {
        return;
    }
    let ws = work.get();
    let mut wr = Buf::output(&mut c.kn, ws.reals, T::SENT);
    let mut wi = Buf::output(&mut c.kn, ws.indices, 0u32);
    let mut wb = Buf::output(&mut c.kn, ws.bytes, 0u8);
    let work_pools = T::pools(&mut wr, &mut wi, &mut wb);
    let wp = opt_ptr(&mut c.kn, &work_pools);
    let mut sizes = Slot::<dk_plan_sizes>::new(&mut c.kn);
    // SAFETY: as above.
    let s = unsafe { (T::POOLS)(meshp, m.dim, op, wp, sizes.p()) };
    check_slot("plan pool sizes", s, &sizes);
    if s != dk_status::DK_OK {
        return;
    }
    let ps = sizes.get();
    let mut reals = Buf::output(&mut c.kn, ps.reals, T::SENT);
    let mut indices = Buf::output(&mut c.kn, ps.indices, 0u32);
    let mut bytes = Buf::output(&mut c.kn, ps.bytes, 0u8);
    let plan_pools = T::pools(&mut reals, &mut indices, &mut bytes);
    let pp = opt_ptr(&mut c.kn, &plan_pools);
    let mut info = Slot::<dk_plan_info>::new(&mut c.kn);
    // SAFETY: as above.
    let s = unsafe { (T::INIT)(meshp, m.dim, op, wp, pp, info.p()) };
    check_slot("plan init", s, &info);
    if s != dk_status::DK_OK {
        return;
    }
    let d = m.d;
    for step in 0..steps % 4 {
        if corrupt % 4 == step {
            if let Some(w) = indices.v.first_mut() {
                *w ^= 1;
            }
        }
        let mut deformed = Vec::with_capacity(b * d);
        for &node in &m.boundary {
            for k in 0..d {
                let x = m.pts[node as usize * d + k] + c.vals.next() / 16.0;
                deformed.push(T::of(x));
            }
        }
        let df = Buf::input(&mut c.kn, &deformed, T::of(0.0));
        let rigid = [T::of(1.0), T::of(0.0), T::of(0.0), T::of(0.0)];
        let (source, rot) = if loop2d {
            (de::DK_ROTATIONS_SHAPE, Buf::absent())
        } else {
            (
                de::DK_ROTATIONS_RIGID,
                Buf::input(&mut c.kn, &rigid, T::of(0.0)),
            )
        };
        let mut out = Buf::output(&mut c.kn, m.n * d, T::SENT);
        let mut report = Slot::<dk_plan_step_report>::new(&mut c.kn);
        let start = if cold {
            pl::DK_PLAN_COLD
        } else {
            pl::DK_PLAN_WARM
        };
        let step_pools = T::pools(&mut reals, &mut indices, &mut bytes);
        let sp = opt_ptr(&mut c.kn, &step_pools);
        // SAFETY: as above.
        let s = unsafe {
            (T::STEP)(
                sp,
                m.dim,
                df.p(),
                df.n(),
                source,
                rot.p(),
                rot.n(),
                ptr::null(),
                0,
                start,
                out.m(),
                out.n(),
                report.p(),
            )
        };
        check_slot("plan step", s, &report);
        if corrupt % 4 == step && !sp.is_null() && !indices.null && indices.n() > 0 {
            assert_eq!(
                s,
                dk_status::DK_ERR_BAD_PLAN,
                "a plan with a broken magic stepped"
            );
        }
        if s != dk_status::DK_OK {
            assert!(all_sent(&out.v), "plan step: out written on {s:?}");
            return;
        }
        assert_boundary_bits("plan step", &out.v, &m.boundary, &deformed, d);
        let r = report.get();
        if r.converged && m.finite && !c.vals.nonfinite {
            assert!(all_fin(&out.v[..m.n * d]), "plan step: non-finite output");
        }
    }
}

/// RBF deformation: the size queries, then the call with buffers the knobs may shorten or
/// null; an error leaves the output and the report untouched, success on finite input gives
/// finite displacements, and with a correction the boundary moves exactly as asked.
fn rbf<T: Sc>(c: &mut Ctx, o: &dk_rbf_options) {
    let m = c.m;
    let (nb, d) = (m.boundary.len(), m.d);
    let (mut len, mut ilen) = (0usize, 0usize);
    // SAFETY: `o` and the lengths are valid for one read / one write each.
    let sizes = unsafe {
        (
            rb::dk_rbf_scratch_len(nb, m.dim, o, &mut len),
            rb::dk_rbf_index_scratch_len(nb, m.dim, m.base, o, &mut ilen),
        )
    };
    if sizes != (dk_status::DK_OK, dk_status::DK_OK) {
        return;
    }
    let motion: Vec<T> = (0..nb * d).map(|_| T::of(c.vals.next())).collect();
    let p = Buf::input(&mut c.kn, &m.pts::<T>(), T::of(0.5));
    let b = Buf::input(&mut c.kn, &m.based(&m.boundary), 0);
    let mo = Buf::input(&mut c.kn, &motion, T::of(0.0));
    let mut iscr = Buf::output(&mut c.kn, ilen, 0u32);
    let mut scr = Buf::output(&mut c.kn, len, T::SENT);
    let mut out = Buf::output(&mut c.kn, m.n * d, T::SENT);
    let mut report = Slot::<dk_rbf_report>::new(&mut c.kn);
    // SAFETY: every pointer is NULL or valid for the length passed with it.
    let s = unsafe {
        (T::RBF)(
            p.p(),
            p.n(),
            m.dim,
            b.p(),
            b.n(),
            m.base,
            mo.p(),
            mo.n(),
            o,
            iscr.m(),
            iscr.n(),
            scr.m(),
            scr.n(),
            out.m(),
            out.n(),
            report.p(),
        )
    };
    check_out("rbf", s, &out, m.finite && !c.vals.nonfinite);
    check_slot("rbf", s, &report);
    if s == dk_status::DK_OK
        && m.dim as usize == d
        && T::of(o.correction_radius).bits() != T::of(0.0).bits()
    {
        for (k, &node) in m.boundary.iter().enumerate() {
            for a in 0..d {
                assert_eq!(
                    out.v[node as usize * d + a].bits(),
                    motion[k * d + a].bits(),
                    "rbf: wall moved off its motion"
                );
            }
        }
    }
}

fn run_op(c: &mut Ctx, op: &Op) {
    macro_rules! prec {
        ($f32:expr, $f:ident ( $($a:expr),* )) => {
            if $f32 { $f::<f32>(c, $($a),*) } else { $f::<f64>(c, $($a),*) }
        };
    }
    match *op {
        Op::Batina { exponent, f32 } => prec!(f32, batina(exponent)),
        Op::SolveLinear {
            method,
            precond,
            omega,
            max_iter,
            comps,
            res_tol,
            upd_tol,
            sys,
            f32,
        } => {
            prec!(
                f32,
                solve_linear(method, precond, omega, max_iter, comps, res_tol, upd_tol, sys)
            )
        }
        Op::JacobiSweep {
            start,
            end,
            comps,
            sys,
            f32,
        } => prec!(f32, jacobi(start, end, comps, sys)),
        Op::SolveAngle {
            method,
            epsilon,
            max_iter,
            sys,
            f32,
        } => {
            prec!(f32, solve_angle(method, epsilon, max_iter, sys))
        }
        Op::SolveAmg {
            angle,
            comps,
            max_iter,
            epsilon,
            theta,
            max_levels,
            max_coarse,
            sweeps,
            smoother,
            sys,
            f32,
        } => {
            prec!(
                f32,
                solve_amg(
                    angle, comps, max_iter, epsilon, theta, max_levels, max_coarse, sweeps,
                    smoother, sys
                )
            )
        }
        Op::SolveSliding {
            which,
            method,
            omega,
            max_iter,
            epsilon,
            kinds,
            sys,
            f32,
        } => {
            prec!(
                f32,
                solve_sliding(which, method, omega, max_iter, epsilon, kinds, sys)
            )
        }
        Op::CellQuality {
            kind,
            from_mesh,
            f32,
        } => prec!(f32, cell_quality(kind, from_mesh)),
        Op::Compare { wall, scale, f32 } => prec!(f32, compare(wall, scale)),
        Op::Stiffening {
            wall_node,
            exponent,
            volumes,
            f32,
        } => prec!(f32, stiffening(wall_node, exponent, volumes)),
        Op::SmoothStructured {
            lambda,
            mu,
            iterations,
            pinned,
            mirror,
            f32,
        } => {
            prec!(
                f32,
                smooth_structured(lambda, mu, iterations, pinned, mirror)
            )
        }
        Op::SmoothArclength {
            direction,
            normalised,
            use_coarse,
            factor,
            prolongation,
            iterations,
            coarse_iterations,
            params,
            pinned,
            mirror,
            f32,
        } => prec!(
            f32,
            smooth_arclength(
                direction,
                normalised,
                use_coarse,
                factor,
                prolongation,
                iterations,
                coarse_iterations,
                params,
                pinned,
                mirror
            )
        ),
        Op::SmoothGraph {
            lambda,
            mu,
            iterations,
            comps,
            weights,
            fixed,
            f32,
        } => {
            prec!(
                f32,
                smooth_graph(lambda, mu, iterations, comps, weights, fixed)
            )
        }
        Op::Redistribute {
            direction,
            normalised,
            perturb,
            f32,
        } => {
            prec!(f32, redistribute(direction, normalised, perturb))
        }
        Op::Order { f32 } => {
            if f32 {
                orders::<f32>(c, or::dk_order_hilbert_f32, or::dk_order_permute_f32)
            } else {
                orders::<f64>(c, or::dk_order_hilbert, or::dk_order_permute)
            }
        }
        Op::Plan {
            quaternion,
            amg,
            steps,
            corrupt,
            cold,
            f32,
        } => {
            if f32 {
                plan::<f32>(c, quaternion, amg, steps, corrupt, cold)
            } else {
                plan::<f64>(c, quaternion, amg, steps, corrupt, cold)
            }
        }
        Op::Rbf {
            kernel,
            radius,
            tolerance,
            max_centres,
            correction,
            f32,
        } => {
            let o = dk_rbf_options {
                kernel: u32::from(kernel % 3),
                radius: c.vals.note(real(radius)),
                tolerance: c.vals.note(real(tolerance)).abs(),
                max_centres: usize::from(max_centres),
                correction_radius: c.vals.note(real(correction)).abs(),
            };
            prec!(f32, rbf(&o))
        }
        Op::Deform(ref s) => {
            if s.f32 {
                deform::<f32>(c, s)
            } else {
                deform::<f64>(c, s)
            }
        }
        Op::DeformFast(ref s, ref f) => {
            if s.f32 {
                deform_fast::<f32>(c, s, f)
            } else {
                deform_fast::<f64>(c, s, f)
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The target.
// ---------------------------------------------------------------------------------------------

const SENTINEL: u32 = 0x5a5a_5a5a;

fn ptr_or_null<T>(p: *const T, null: bool) -> *const T {
    if null {
        ptr::null()
    } else {
        p
    }
}

fuzz_target!(|inp: Input| {
    legacy(&inp);
    let mesh = Mesh::new(&inp.mesh);
    let mut kn = Knobs {
        k: &inp.knobs,
        i: 0,
    };
    for (i, op) in inp.ops.iter().take(4).enumerate() {
        let mut c = Ctx {
            kn: Knobs { k: kn.k, i: kn.i },
            vals: Vals {
                v: &inp.vals,
                i: 7 * i,
                nonfinite: false,
            },
            bits: &inp.bits,
            m: &mesh,
        };
        run_op(&mut c, op);
        kn.i = c.kn.i;
    }
});

/// The quaternion and graph-builder calls.
fn legacy(inp: &Input) {
    // --- dk_graph_from_edges ---
    let edges_len = inp.edges.len().saturating_sub(inp.edges_len_cut as usize);
    let mut offsets = vec![SENTINEL; inp.offsets_len as usize];
    let mut targets = vec![SENTINEL; inp.targets_len as usize];
    let mut used = usize::MAX;
    let base = (inp.index_base % 3) as u32;
    // Base 1 needs `edges_len` entries; the fuzzer's cut makes it short at times.
    let mut index_scratch = vec![0u32; edges_len.saturating_sub(inp.edges_len_cut as usize % 3)];
    // SAFETY: every pointer is valid for the length passed with it (or NULL).
    let s = unsafe {
        dk_graph_from_edges(
            inp.node_count as usize,
            ptr_or_null(inp.edges.as_ptr(), inp.nulls & 1 != 0),
            edges_len,
            base,
            index_scratch.as_mut_ptr(),
            index_scratch.len(),
            if inp.nulls & 2 != 0 {
                ptr::null_mut()
            } else {
                offsets.as_mut_ptr()
            },
            offsets.len(),
            targets.as_mut_ptr(),
            targets.len(),
            if inp.nulls & 4 != 0 {
                ptr::null_mut()
            } else {
                &mut used
            },
        )
    };
    if s == dk_status::DK_OK {
        assert!(base <= 1 && edges_len.is_multiple_of(2));
        assert!(base == 0 || index_scratch.len() >= edges_len);
        let pairs: Vec<[u32; 2]> = inp.edges[..edges_len]
            .chunks_exact(2)
            .map(|c| [c[0].wrapping_sub(base), c[1].wrapping_sub(base)])
            .collect();
        let mut o = vec![0u32; offsets.len()];
        let mut t = vec![0u32; targets.len()];
        let n = graph_from_edges(inp.node_count as usize, &pairs, &mut o, &mut t).unwrap();
        assert_eq!(n, used);
        assert_eq!(o, offsets);
        assert_eq!(&t[..n], &targets[..n]);
    } else {
        assert!(
            offsets.iter().chain(&targets).all(|&x| x == SENTINEL),
            "{s:?}"
        );
        assert_eq!(used, usize::MAX);
    }

    // --- dk_quat_mul / dk_quat_average / dk_quat_rotate_points ---
    let q4: Vec<f64> = inp.quats.iter().copied().chain([1.0; 8]).take(8).collect();
    let mut out = [f64::from_bits(0x7ff0_dead_0000_0001); 4];
    let before = out.map(f64::to_bits);
    // SAFETY: 4 scalars each, or NULL.
    let s = unsafe {
        dk_quat_mul(
            ptr_or_null(q4.as_ptr(), inp.nulls & 8 != 0),
            q4[4..].as_ptr(),
            out.as_mut_ptr(),
        )
    };
    if s == dk_status::DK_OK {
        let want = Quat::from_array([q4[0], q4[1], q4[2], q4[3]])
            * Quat::from_array([q4[4], q4[5], q4[6], q4[7]]);
        assert_eq!(out.map(f64::to_bits), want.to_array().map(f64::to_bits));
    } else {
        assert_eq!(out.map(f64::to_bits), before);
    }
    let quats_len = inp.quats.len().saturating_sub(inp.quats_len_cut as usize);
    let mut out = [f64::from_bits(0x7ff0_dead_0000_0001); 4];
    // SAFETY: `quats_len` <= quats.len(); weights NULL with length 0.
    let s = unsafe {
        dk_quat_average(
            ptr_or_null(inp.quats.as_ptr(), inp.nulls & 16 != 0),
            quats_len,
            ptr::null(),
            0,
            out.as_mut_ptr(),
        )
    };
    if s != dk_status::DK_OK {
        assert_eq!(out.map(f64::to_bits), before);
    } else {
        assert!(out.iter().all(|x| x.is_finite()));
    }
    let mut rotated = vec![-0.0f64; inp.points.len()];
    // SAFETY: both buffers have `points.len()` elements.
    let s = unsafe {
        dk_quat_rotate_points(
            q4.as_ptr(),
            inp.points.as_ptr(),
            inp.points.len(),
            rotated.as_mut_ptr(),
            rotated.len(),
        )
    };
    if s != dk_status::DK_OK {
        assert!(rotated.iter().all(|x| x.to_bits() == (-0.0f64).to_bits()));
    }
    // The plane variant: the bits of the 3D rotation of (x, y, 0), or nothing written. With
    // `nulls & 32` the quaternion is made a rotation about z, so both outcomes are reached.
    let mut qz = [q4[0], q4[1], q4[2], q4[3]];
    if inp.nulls & 32 != 0 {
        qz[1] = 0.0;
        qz[2] = 0.0;
    }
    let mut plane = vec![-0.0f64; inp.points.len()];
    // SAFETY: both buffers have `points.len()` elements.
    let s = unsafe {
        dk_quat_rotate_points_2d(
            qz.as_ptr(),
            inp.points.as_ptr(),
            inp.points.len(),
            plane.as_mut_ptr(),
            plane.len(),
        )
    };
    if s == dk_status::DK_OK {
        let q = Quat::from_array(qz).normalize().unwrap();
        for (p, o) in inp.points.chunks_exact(2).zip(plane.chunks_exact(2)) {
            let r = q.rotate([p[0], p[1], 0.0]);
            assert_eq!(
                [o[0].to_bits(), o[1].to_bits()],
                [r[0].to_bits(), r[1].to_bits()]
            );
        }
    } else {
        assert!(plane.iter().all(|x| x.to_bits() == (-0.0f64).to_bits()));
    }
}
