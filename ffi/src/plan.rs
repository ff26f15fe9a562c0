//! Prepared plans (`deform_kernel::plan`) through the C ABI: set a deformation up once in three
//! caller pools, then step it every time step with new boundary positions.
//!
//! The pools are the caller's memory: `reals` (`double` / `float`), `indices` (`uint32_t`)
//! and `bytes` (`uint8_t`), sized by [`dk_plan_pool_sizes`] after [`dk_plan_work_sizes`]
//! sized the transient work buffers. The plan stores no pointers (offsets follow from the counts in its header), so a caller may copy,
//! checkpoint or move the pools between steps. Every step reopens the pools with
//! `Plan::open` (header, layout and a checksum of every immutable part: one pass over the
//! pools, 11 ms against a warm 234k-node step of 231–328 ms), so pools that were overwritten
//! by mistake are a `DK_ERR_BAD_PLAN`, never a wrong mesh. Indices are 0-based.
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::deformation::RotationSource;
use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanSizes, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::spring::AmgOptions;
use deform_kernel::{Quat, Real};

use crate::args::{assert_layout, by_dim, done, read_array, read_one, read_points, write_one};
use crate::graph::{dk_cells, dk_graph, CellsIn, GraphIn};
use crate::slice::{chunks_mut, input, output, quats, In, Out};
use crate::spring::{dk_amg_options, dk_spring_solve_options};
use crate::status::dk_status;

mod abi;
pub use abi::*;

/// `dk_plan_options.method`: linear (Batina) springs on the displacements.
pub const DK_PLAN_SPRING: u32 = 1;
/// `dk_plan_options.method`: Samareh's quaternion method with spring propagation (default).
pub const DK_PLAN_QUATERNION: u32 = 2;
/// `dk_plan_options.solver`: CG preconditioned by smoothed-aggregation multigrid, the
/// hierarchy built once at init (default).
pub const DK_PLAN_SOLVER_AMG: u32 = 0;
/// `dk_plan_options.solver`: the one-level method of `dk_plan_options.linear`.
pub const DK_PLAN_SOLVER_LINEAR: u32 = 1;
/// `dk_plan_step` `start`: from the stored solutions (the last one or the extrapolation of
/// the last two, whichever has the smaller residual, or the cold guess when smaller still).
pub const DK_PLAN_WARM: u32 = 0;
/// `dk_plan_step` `start`: as the stateless calls (the same bits as `dk_deform_spring`).
pub const DK_PLAN_COLD: u32 = 1;

/// How a plan is built ([`dk_plan_options_default`] fills the defaults). The same struct
/// serves both precisions.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_plan_options {
    /// `DK_PLAN_QUATERNION` (default) or `DK_PLAN_SPRING`.
    pub method: u32,
    /// `DK_PLAN_SOLVER_AMG` (default) or `DK_PLAN_SOLVER_LINEAR`.
    pub solver: u32,
    /// Batina stiffness exponent `p` of `1 / |r_i − r_j|^p` (default 1; finite, ≥ 0).
    pub stiffness_exponent: f64,
    /// Stopping rules of every step's solve (`max_iterations`, `residual_tol`, `update_tol`)
    /// and, for `DK_PLAN_SOLVER_LINEAR`, the method (`method`, `preconditioner`, `omega`).
    pub linear: dk_spring_solve_options,
    /// The multigrid preconditioner of `DK_PLAN_SOLVER_AMG` (ignored otherwise).
    pub amg: dk_amg_options,
}
assert_layout!(
    dk_plan_options, 96;
    method = 0, solver = 4, stiffness_exponent = 8, linear = 16, amg = 56,
);

/// Lengths of the three plan pools, or of the transient work buffers.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_plan_sizes {
    /// Scalars (`double` for the f64 functions, `float` for the `_f32` ones).
    pub reals: usize,
    /// `uint32_t` entries.
    pub indices: usize,
    /// `uint8_t` entries.
    pub bytes: usize,
}
assert_layout!(dk_plan_sizes, 24; reals = 0, indices = 8, bytes = 16);

impl From<PlanSizes> for dk_plan_sizes {
    fn from(s: PlanSizes) -> Self {
        dk_plan_sizes {
            reals: s.reals,
            indices: s.indices,
            bytes: s.bytes,
        }
    }
}

/// What a plan holds (from `dk_plan_init` or `dk_plan_open`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_plan_info {
    /// Mesh nodes `N`.
    pub nodes: usize,
    /// Boundary points `B`.
    pub boundary: usize,
    /// Steps completed.
    pub steps: u64,
    /// Levels of the multigrid hierarchy (0 without one).
    pub amg_levels: usize,
    /// Pool lengths the plan uses.
    pub used: dk_plan_sizes,
    /// `DK_PLAN_SPRING` or `DK_PLAN_QUATERNION`.
    pub method: u32,
}
assert_layout!(
    dk_plan_info, 64;
    nodes = 0, boundary = 8, steps = 16, amg_levels = 24, used = 32, method = 56,
);

/// What one `dk_plan_step` did.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_plan_step_report {
    /// Iterations of the solve.
    pub iterations: usize,
    /// True relative residual at the end.
    pub residual: f64,
    /// Largest change of the last iteration.
    pub max_update: f64,
    /// Steps completed by the plan, this one included.
    pub step: u64,
    /// Whether the solve met its tolerance (the mesh is written either way).
    pub converged: bool,
    /// Whether the stored solutions gave the initial guess.
    pub warm: bool,
    /// Whether that guess was the extrapolation of the last two solutions.
    pub extrapolated: bool,
}
assert_layout!(
    dk_plan_step_report, 40;
    iterations = 0, residual = 8, max_update = 16, step = 24, converged = 32, warm = 33,
    extrapolated = 34,
);

fn method_code(m: PlanMethod) -> u32 {
    match m {
        PlanMethod::Spring => DK_PLAN_SPRING,
        PlanMethod::QuaternionSpring => DK_PLAN_QUATERNION,
    }
}

fn info<T: Real, const D: usize>(p: &Plan<'_, T, D>) -> dk_plan_info {
    dk_plan_info {
        nodes: p.node_count(),
        boundary: p.boundary_len(),
        steps: p.steps(),
        amg_levels: p.amg_levels(),
        used: p.used().into(),
        method: method_code(p.method()),
    }
}

pub(crate) fn options_default<T: Real>(out: Out<'_, dk_plan_options>) -> dk_status {
    done(write_one(
        out,
        dk_plan_options {
            method: DK_PLAN_QUATERNION,
            solver: DK_PLAN_SOLVER_AMG,
            stiffness_exponent: 1.0,
            linear: dk_spring_solve_options::default_for::<T>(),
            amg: dk_amg_options::of(AmgOptions::<T>::default()),
        },
    ))
}

// codegen: f32 twin
/// The mesh a plan is built from ([`dk_plan_work_sizes`], [`dk_plan_pool_sizes`],
/// [`dk_plan_init`]); borrowed for the call and copied into the plan.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_plan_mesh {
    /// Undeformed node positions, `node_count * dim` scalars.
    pub points: *const f64,
    /// Entries of `points`.
    pub points_len: usize,
    /// The 0-based CSR graph of the springs.
    pub graph: dk_graph,
    /// The 0-based boundary node list (`B` nodes, distinct): the nodes a step moves.
    pub boundary: *const u32,
    /// Entries of `boundary`.
    pub boundary_len: usize,
    /// Optional boundary elements over the boundary points `0..B` (0-based; all empty for
    /// none): with them the quaternion method derives rotations from the shape.
    pub elements: dk_cells,
    /// Optional stiffness per directed edge (NULL with length 0: Batina's with
    /// `dk_plan_options.stiffness_exponent`).
    pub stiffness: *const f64,
    /// Entries of `stiffness`.
    pub stiffness_len: usize,
}
assert_layout!(
    dk_plan_mesh, 128;
    points = 0, graph = 16, boundary = 48, elements = 64, stiffness = 112,
);

// codegen: f32 twin
/// Three caller buffers: a plan's pools (sized by [`dk_plan_pool_sizes`], written by
/// [`dk_plan_init`], read and updated by every step), the transient work of init (sized by
/// [`dk_plan_work_sizes`]), or the multigrid hierarchy and scratch of a stateless solve
/// (`dk_spring_solve_linear_amg`, `dk_spring_solve_angle_amg`; sized by their `_pool_sizes`
/// queries, `bytes` unused). Each buffer is used only by the call that receives the struct.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_plan_pools {
    /// Scalars.
    pub reals: *mut f64,
    /// Entries of `reals`.
    pub reals_len: usize,
    /// Indices.
    pub indices: *mut u32,
    /// Entries of `indices`.
    pub indices_len: usize,
    /// Bytes.
    pub bytes: *mut u8,
    /// Entries of `bytes`.
    pub bytes_len: usize,
}
assert_layout!(dk_plan_pools, 48; reals = 0, indices = 16, bytes = 32, bytes_len = 40);

/// The mesh a plan is built from, its arrays as tokens, and the caller's options.
pub(crate) struct SpecArgs<'a, T> {
    points: In<'a, T>,
    graph: GraphIn<'a>,
    boundary: In<'a, u32>,
    elements: CellsIn<'a>,
    /// Per directed edge, or NULL with length 0 for Batina's with `stiffness_exponent`.
    stiffness: In<'a, T>,
    options: In<'a, dk_plan_options>,
}

/// Three caller buffers (a plan's pools, or its transient work) as tokens.
pub(crate) struct PoolArgs<'a, T> {
    reals: Out<'a, T>,
    indices: Out<'a, u32>,
    bytes: Out<'a, u8>,
}

/// The precision twins of the plan structs, seen through [`SpecArgs`] and [`PoolArgs`].
pub(crate) trait PlanC: Copy {
    type T: Real;
    type Pools: Copy;
    /// Reads the mesh and wraps its arrays in tokens of the struct's lifetime.
    fn spec<'a>(
        mesh: In<'a, Self>,
        options: In<'a, dk_plan_options>,
    ) -> Result<SpecArgs<'a, Self::T>, dk_status>;
    /// Reads a pools struct and wraps its buffers in tokens of the struct's lifetime.
    fn pools(p: In<'_, Self::Pools>) -> Result<PoolArgs<'_, Self::T>, dk_status>;
}

/// The precision twins of [`dk_plan_pools`], seen through [`PoolArgs`] (the plans and the
/// stateless multigrid solves of `crate::spring` take them).
pub(crate) trait PoolsC: Copy {
    type T: Real;
    /// Reads a pools struct and wraps its buffers in tokens of the struct's lifetime.
    fn read(p: In<'_, Self>) -> Result<PoolArgs<'_, Self::T>, dk_status>;
}

macro_rules! plan_c {
    ($mesh:ty, $pools:ty, $t:ty) => {
        impl PlanC for $mesh {
            type T = $t;
            type Pools = $pools;
            fn spec<'a>(
                mesh: In<'a, Self>,
                options: In<'a, dk_plan_options>,
            ) -> Result<SpecArgs<'a, $t>, dk_status> {
                let m = read_one(mesh)?;
                // SAFETY: a token for a mesh struct carries the contract of the functions
                // that take one: its arrays are readable for their lengths while it is.
                Ok(unsafe {
                    SpecArgs {
                        points: In::new(m.points, m.points_len),
                        graph: m.graph.tokens(),
                        boundary: In::new(m.boundary, m.boundary_len),
                        elements: m.elements.tokens(),
                        stiffness: In::new(m.stiffness, m.stiffness_len),
                        options,
                    }
                })
            }
            fn pools(p: In<'_, $pools>) -> Result<PoolArgs<'_, $t>, dk_status> {
                PoolsC::read(p)
            }
        }
        impl PoolsC for $pools {
            type T = $t;
            fn read(p: In<'_, Self>) -> Result<PoolArgs<'_, $t>, dk_status> {
                let b = read_one(p)?;
                // SAFETY: a token for a pools struct carries the contract of the functions
                // that take one: its buffers are writable for their lengths, exclusively,
                // while it is.
                Ok(unsafe {
                    PoolArgs {
                        reals: Out::new(b.reals, b.reals_len),
                        indices: Out::new(b.indices, b.indices_len),
                        bytes: Out::new(b.bytes, b.bytes_len),
                    }
                })
            }
        }
    };
}
plan_c!(dk_plan_mesh, dk_plan_pools, f64);
plan_c!(dk_plan_mesh_f32, dk_plan_pools_f32, f32);

/// The borrowed buffers of a [`PoolArgs`].
pub(crate) type Pools<'a, T> = (&'a mut [T], &'a mut [u32], &'a mut [u8]);

impl<'a, T: Real> PoolArgs<'a, T> {
    /// The three buffers (each NULL only with length 0).
    pub(crate) fn borrow(self) -> Result<Pools<'a, T>, dk_status> {
        Ok((
            output(self.reals)?,
            output(self.indices)?,
            output(self.bytes)?,
        ))
    }

    fn work(self) -> Result<PlanWork<'a, T>, dk_status> {
        let (reals, indices, bytes) = self.borrow()?;
        Ok(PlanWork {
            reals,
            indices,
            bytes,
        })
    }

    fn open<const D: usize>(self) -> Result<Plan<'a, T, D>, dk_status> {
        let (reals, indices, bytes) = self.borrow()?;
        Plan::open(reals, indices, bytes).map_err(dk_status::from)
    }
}

impl<'a, T: Real> SpecArgs<'a, T> {
    /// The kernel's spec (borrowing the caller's arrays; everything is copied at init).
    fn spec<const D: usize>(&self) -> Result<PlanSpec<'a, T, D>, dk_status> {
        let o = read_one(self.options)?;
        let graph = self.graph.graph()?;
        // The length first: a points length that no graph of this size can have is refused
        // before the pointer is borrowed for it.
        if Some(self.points.len()) != graph.node_count().checked_mul(D) {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        let points = read_points::<T, D>(self.points)?;
        let boundary = input(self.boundary)?;
        let (elements, _) = self.elements.optional_cells(boundary.len(), 0, &mut [])?;
        let method = match o.method {
            DK_PLAN_SPRING => PlanMethod::Spring,
            DK_PLAN_QUATERNION => PlanMethod::QuaternionSpring,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        let solver = match o.solver {
            DK_PLAN_SOLVER_AMG => PlanSolver::Amg(o.amg.to_kernel()?),
            DK_PLAN_SOLVER_LINEAR => PlanSolver::Method(o.linear.method::<T>()?),
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        Ok(PlanSpec {
            points,
            graph,
            boundary,
            elements,
            constraints: None,
            method,
            stiffness: if self.stiffness.is_absent() {
                PlanStiffness::Batina {
                    exponent: T::from_f64(o.stiffness_exponent),
                }
            } else {
                PlanStiffness::Given(input(self.stiffness)?)
            },
            solver,
            options: o.linear.stopping::<T>(),
        })
    }
}

fn work_sizes_d<T: Real, const D: usize>(
    spec: &SpecArgs<'_, T>,
    out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    let s = spec.spec::<D>()?;
    let sizes = Plan::<T, D>::work_sizes(&s).map_err(dk_status::from)?;
    write_one(out, sizes.into())
}

fn sizes_d<T: Real, const D: usize>(
    spec: &SpecArgs<'_, T>,
    work: PoolArgs<'_, T>,
    out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    let s = spec.spec::<D>()?;
    let mut work = work.work()?;
    let sizes = Plan::<T, D>::sizes(&s, &mut work).map_err(dk_status::from)?;
    write_one(out, sizes.into())
}

fn init_d<T: Real, const D: usize>(
    spec: &SpecArgs<'_, T>,
    work: PoolArgs<'_, T>,
    pools: PoolArgs<'_, T>,
    info_out: Out<'_, dk_plan_info>,
) -> Result<(), dk_status> {
    let s = spec.spec::<D>()?;
    let mut work = work.work()?;
    let info_slot = crate::slice::out_one(info_out)?;
    let (reals, indices, bytes) = pools.borrow()?;
    let plan = Plan::<T, D>::init(&s, &mut work, reals, indices, bytes).map_err(dk_status::from)?;
    *info_slot = info(&plan);
    Ok(())
}

fn open_d<T: Real, const D: usize>(
    pools: PoolArgs<'_, T>,
    info_out: Out<'_, dk_plan_info>,
) -> Result<(), dk_status> {
    let info_slot = crate::slice::out_one(info_out)?;
    let plan = pools.open::<D>()?;
    *info_slot = info(&plan);
    Ok(())
}

/// One step's motion, as the C caller passed it.
pub(crate) struct MotionArgs<'a, T> {
    pub(crate) deformed: In<'a, T>,
    pub(crate) rotation_source: u32,
    pub(crate) rotations: In<'a, T>,
    pub(crate) origin: In<'a, T>,
    pub(crate) start: u32,
}

impl<'a, T: Real> MotionArgs<'a, T> {
    /// The kernel's motion; `rotation_source` and `rotations` are read only for the
    /// quaternion method (the spring method ignores them, as documented).
    fn motion<const D: usize>(self, method: PlanMethod) -> Result<PlanMotion<'a, T, D>, dk_status> {
        let deformed = read_points::<T, D>(self.deformed)?;
        let source = match method {
            PlanMethod::Spring => crate::deformation::DK_ROTATIONS_SHAPE,
            PlanMethod::QuaternionSpring => self.rotation_source,
        };
        let rotations = match source {
            crate::deformation::DK_ROTATIONS_SHAPE => {
                if method == PlanMethod::QuaternionSpring && self.rotations.len() != 0 {
                    return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
                }
                RotationSource::Shape
            }
            crate::deformation::DK_ROTATIONS_RIGID => {
                RotationSource::Rigid(Quat::from_array(read_array::<T, 4>(self.rotations)?))
            }
            crate::deformation::DK_ROTATIONS_PER_NODE => {
                RotationSource::PerNode(quats(self.rotations)?)
            }
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        let origin = match self.origin.len() {
            0 => None,
            _ => Some(read_array::<T, D>(self.origin)?),
        };
        let start = match self.start {
            DK_PLAN_WARM => Start::Warm,
            DK_PLAN_COLD => Start::Cold,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        Ok(PlanMotion {
            deformed,
            rotations,
            origin,
            start,
        })
    }
}

fn step_d<T: Real, const D: usize>(
    pools: Result<PoolArgs<'_, T>, dk_status>,
    motion: MotionArgs<'_, T>,
    out: Out<'_, T>,
    report_out: Out<'_, dk_plan_step_report>,
) -> Result<(), dk_status> {
    let mut plan = pools?.open::<D>()?;
    let motion = motion.motion::<D>(plan.method())?;
    let out = chunks_mut::<T, D>(out)?;
    let report_slot = crate::slice::out_one(report_out)?;
    let r = plan.step(&motion, out).map_err(dk_status::from)?;
    *report_slot = dk_plan_step_report {
        iterations: r.solve.iterations,
        residual: r.solve.residual.to_f64(),
        max_update: r.solve.max_update.to_f64(),
        step: r.step,
        converged: r.solve.converged,
        warm: r.warm,
        extrapolated: r.extrapolated,
    };
    Ok(())
}
