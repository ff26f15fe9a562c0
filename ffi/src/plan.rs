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
#![allow(unsafe_code)] // a parameter struct's arrays become `In`/`Out` tokens (`In::new`) here.

use deform_kernel::plan::{
    Plan, PlanMethod, PlanMotion, PlanOrder, PlanSolver, PlanSpec, PlanStiffness, PlanWork, Start,
};
use deform_kernel::quaternion::RotationSource;
use deform_kernel::spring::AmgOptions;
use deform_kernel::{Quat, Real};
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, read_array, read_one, read_points, write_one, Dim};
use crate::graph::{dk_cells, dk_graph, CellsIn, GraphIn};
pub use crate::pools::{dk_plan_pools, dk_plan_pools_f32, dk_plan_sizes, DkPlanPools};
use crate::pools::{PoolArgs, PoolsC};
use crate::slice::{chunks_mut, input, out_one, output, quats, In, Out};
use crate::spring::{dk_amg_options, dk_spring_solve_options, dk_spring_solve_report};
use crate::status::dk_status;

/// `dk_plan_options.method`: linear (Batina) springs on the displacements.
pub const DK_PLAN_SPRING: u32 = 1;
/// `dk_plan_options.method`: Samareh's quaternion method with spring propagation (default).
pub const DK_PLAN_QUATERNION: u32 = 2;
/// `dk_plan_options.solver`: CG preconditioned by smoothed-aggregation multigrid, the
/// hierarchy built once at init (default).
pub const DK_PLAN_SOLVER_AMG: u32 = 0;
/// `dk_plan_options.solver`: the one-level method of `dk_plan_options.linear`.
pub const DK_PLAN_SOLVER_LINEAR: u32 = 1;
/// `renumber` of [`dk_plan_init_ordered`] and its sizing calls: the caller's numbering (as
/// [`dk_plan_init`]).
pub const DK_PLAN_ORDER_NONE: u32 = 0;
/// `renumber`: reverse Cuthill–McKee of the graph (as `dk_order_rcm`).
pub const DK_PLAN_ORDER_RCM: u32 = 1;
/// `renumber`: a Hilbert curve through the reference points (as `dk_order_hilbert`).
pub const DK_PLAN_ORDER_HILBERT: u32 = 2;
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

/// The mesh a plan is built from ([`dk_plan_work_sizes`], [`dk_plan_pool_sizes`],
/// [`dk_plan_init`]); borrowed for the call and copied into the plan.
#[export(twin = dk_plan_mesh)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct DkPlanMesh<T> {
    /// Undeformed node positions, `node_count * dim` scalars.
    pub points: *const T,
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
    pub stiffness: *const T,
    /// Entries of `stiffness`.
    pub stiffness_len: usize,
}
assert_layout!(
    DkPlanMesh<f64>, 128;
    points = 0, graph = 16, boundary = 48, elements = 64, stiffness = 112,
);

/// The mesh a plan is built from, its arrays as tokens, and the caller's options.
pub(crate) struct SpecArgs<'a, T> {
    points: In<'a, T>,
    graph: GraphIn<'a>,
    boundary: In<'a, u32>,
    elements: CellsIn<'a>,
    /// Per directed edge, or NULL with length 0 for Batina's with `stiffness_exponent`.
    stiffness: In<'a, T>,
    options: In<'a, dk_plan_options>,
    /// `DK_PLAN_ORDER_*`.
    renumber: u32,
}

impl<T: Real> DkPlanMesh<T> {
    /// Reads the mesh and wraps its arrays in tokens of the struct's lifetime, with the
    /// caller's options and node order (`DK_PLAN_ORDER_*`).
    fn spec<'a>(
        mesh: In<'a, Self>,
        options: In<'a, dk_plan_options>,
        renumber: u32,
    ) -> Result<SpecArgs<'a, T>, dk_status> {
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
                renumber,
            }
        })
    }
}

impl<'a, T: Real> PoolArgs<'a, T> {
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
        let renumber = match self.renumber {
            DK_PLAN_ORDER_NONE => PlanOrder::AsGiven,
            DK_PLAN_ORDER_RCM => PlanOrder::Rcm,
            DK_PLAN_ORDER_HILBERT => PlanOrder::Hilbert,
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
            renumber,
        })
    }
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

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Fills `*out` with the default plan options for f64: the quaternion method, multigrid-
/// preconditioned CG, Batina stiffness (exponent 1), the default stopping rules of
/// `dk_spring_solve_options_default` (10 000 iterations, residual tolerance 1e-10).
///
/// # f32 twin
/// As [`dk_plan_options_default`] with the f32 default residual tolerance (`100 ε_f32`).
#[export(twin, out[1])]
pub(crate) fn dk_plan_options_default<T: Real>(
    out: Out<'_, dk_plan_options>,
) -> Result<(), dk_status> {
    let v = dk_plan_options {
        method: DK_PLAN_QUATERNION,
        solver: DK_PLAN_SOLVER_AMG,
        stiffness_exponent: 1.0,
        linear: dk_spring_solve_options::default_for::<T>(),
        amg: dk_amg_options::of(AmgOptions::<T>::default()),
    };
    write_one(out, v)
}

/// Lengths of the transient work buffers [`dk_plan_pool_sizes`] and [`dk_plan_init`] need for this
/// mesh (free them after init).
///
/// The mesh (`*mesh`, a [`dk_plan_mesh`] shared by the three set-up calls; all indices
/// 0-based):
/// - `points`: the reference mesh, `N * dim` scalars, `dim` 2 or 3; every step deforms it;
/// - `graph`: the symmetric CSR graph of the mesh edges (as `dk_graph_from_cells` builds it);
/// - `boundary`: the mesh node of each of the `B` prescribed points (moving walls and fixed
///   far field alike), distinct; exactly these nodes are held by the springs;
/// - `elements`: boundary elements over `0..B` (segments in 2D, triangles/quadrilaterals in
///   3D) for shape rotations, or all three arrays NULL with length 0;
/// - `stiffness`: one spring stiffness per directed edge (`graph.targets_len` scalars, exactly
///   symmetric, finite and positive; for example Batina's scaled by
///   `dk_spring_wall_distance_factors` or `dk_spring_inverse_volume_factors` with
///   `dk_spring_scale_stiffness`), copied into the plan; or NULL with length 0 for Batina's
///   `1 / L^p` with `options->stiffness_exponent`;
/// - `options`: see [`dk_plan_options`] (the solver, its stopping rules and the multigrid
///   options).
///
/// Errors (nothing written): `DK_ERR_INVALID_PARAMETER` (`dim`, an unknown method or solver
/// code, an empty boundary), graph, cell, length (`points` not `N * dim` scalars, a given
/// `stiffness` not one per directed edge) and pointer errors, as [`dk_plan_pool_sizes`]
/// reports them.
#[export(twin, mesh[1], options[1], sizes_out[1])]
pub(crate) fn dk_plan_work_sizes<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    dk_plan_work_sizes_ordered::<T, D>(mesh, Dim, options, DK_PLAN_ORDER_NONE, sizes_out)
}

/// The exact lengths of the three plan pools for this mesh: validates the mesh and options
/// (as [`dk_plan_init`] does) and runs the multigrid hierarchy's symbolic pass in the work
/// buffers (lengths from [`dk_plan_work_sizes`]). Arguments as [`dk_plan_work_sizes`], plus
/// the work buffers. Errors: those of [`dk_plan_init`]'s validation; only the work buffers
/// are written.
#[export(twin, mesh[1], options[1], work[1], sizes_out[1])]
pub(crate) fn dk_plan_pool_sizes<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    work: In<'_, DkPlanPools<T>>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    let none = DK_PLAN_ORDER_NONE;
    dk_plan_pool_sizes_ordered::<T, D>(mesh, Dim, options, none, work, sizes_out)
}

/// Builds a plan in the pools `reals`, `indices`, `bytes` (each at least the length
/// [`dk_plan_pool_sizes`] gave; the tail of a longer pool is untouched): validates the mesh once
/// (points finite, boundary distinct and in range, graph symmetric, every free node
/// anchored, elements of the right kinds, options), copies the mesh in, computes the
/// stiffness and sets up the multigrid hierarchy. Arguments as [`dk_plan_pool_sizes`], plus the
/// pools and `info_out` (what the plan holds). The pools hold no pointers: copy or
/// checkpoint them freely, and reopen a copy with [`dk_plan_open`].
///
/// Errors: those of the validation (checked before any pool is written), `DK_ERR_BUFFER_TOO_SMALL`,
/// `DK_ERR_TOO_LARGE`; a hierarchy set-up that breaks down in floating point fails after
/// writing, and then the pools hold no plan.
#[export(twin, mesh[1], options[1], work[1], pools[1], info_out[1])]
pub(crate) fn dk_plan_init<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    work: In<'_, DkPlanPools<T>>,
    pools: In<'_, DkPlanPools<T>>,
    info_out: Out<'_, dk_plan_info>,
) -> Result<(), dk_status> {
    let none = DK_PLAN_ORDER_NONE;
    dk_plan_init_ordered::<T, D>(mesh, Dim, options, none, work, pools, info_out)
}

/// Checks that the pools hold a plan for this precision and `dim` (magic, version, counts,
/// pool lengths, the hierarchy's layout, a checksum of every immutable part, finite stored
/// solutions) and says what it holds. Use it after restoring a checkpoint. Errors:
/// `DK_ERR_BAD_PLAN`, `DK_ERR_INVALID_PARAMETER` (`dim`), pointer errors; nothing is written
/// but `info_out`.
#[export(twin, pools[1], info_out[1])]
pub(crate) fn dk_plan_open<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    _dim: Dim<D>,
    info_out: Out<'_, dk_plan_info>,
) -> Result<(), dk_status> {
    let pools = DkPlanPools::read(pools)?;
    let info_slot = out_one(info_out)?;
    *info_slot = info(&pools.open::<D>()?);
    Ok(())
}

/// One time step: the new boundary positions in, the deformed mesh out (`out`: `N * dim`
/// scalars). Each step deforms the reference mesh; the stored solutions of the previous
/// steps give the initial guess (`start` `DK_PLAN_WARM`), or the stateless calls' guess
/// (`DK_PLAN_COLD`, then the bits of `dk_deform_spring`). The pools are checked as
/// [`dk_plan_open`] checks them (one pass, a few percent of a step), so a plan overwritten by
/// mistake is an error, not a wrong mesh.
///
/// - `deformed`: the new position of each of the `B` boundary points, in the plan's boundary
///   order (`B * dim` scalars), reproduced exactly in `out`;
/// - `rotation_source` (quaternion method; the spring method ignores it and `rotations`):
///   `DK_ROTATIONS_SHAPE` (from the plan's elements; `rotations` NULL with length 0),
///   `DK_ROTATIONS_RIGID` (`rotations`: one quaternion, 4 scalars `w x y z`) or
///   `DK_ROTATIONS_PER_NODE` (`rotations`: `4 B` scalars);
/// - `origin`: the rotation origin (`dim` scalars), or NULL with length 0 for the centroid
///   of the moving points;
/// - `report_out`: iterations, residual, whether the solve converged (the mesh is written
///   either way), warm, extrapolated, the step count.
///
/// Errors (checked before `out` or the plan is written): `DK_ERR_BAD_PLAN`, length and
/// pointer errors, `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a zero rotation),
/// `DK_ERR_INVALID_PARAMETER` (`dim`, `rotation_source` of a quaternion plan, `start`, shape
/// rotations without elements), the boundary rotations' and the solver's errors. On error `out`, the stored
/// solutions and the step count are unchanged.
#[export(twin, pools[1], rotations?, origin?, report_out[1])]
pub(crate) fn dk_plan_step<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    _dim: Dim<D>,
    deformed: In<'_, T>,
    rotation_source: u32,
    rotations: In<'_, T>,
    origin: In<'_, T>,
    start: u32,
    out: Out<'_, T>,
    report_out: Out<'_, dk_plan_step_report>,
) -> Result<(), dk_status> {
    let mut plan = DkPlanPools::read(pools)?.open::<D>()?;
    let motion = MotionArgs {
        deformed,
        rotation_source,
        rotations,
        origin,
        start,
    };
    let motion = motion.motion::<D>(plan.method())?;
    let out = chunks_mut::<T, D>(out)?;
    let report_slot = out_one(report_out)?;
    let r = plan.step(&motion, out)?;
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

/// [`dk_plan_work_sizes`] for a plan that renumbers its mesh for memory locality at init
/// (`renumber`: `DK_PLAN_ORDER_RCM` or `DK_PLAN_ORDER_HILBERT`; `DK_PLAN_ORDER_NONE` is
/// [`dk_plan_work_sizes`]). Renumbered, the work holds the permutation and the permuted mesh
/// as well. Errors: those of [`dk_plan_work_sizes`], `DK_ERR_INVALID_PARAMETER` for an
/// unknown `renumber`.
#[export(twin, mesh[1], options[1], sizes_out[1])]
pub(crate) fn dk_plan_work_sizes_ordered<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    renumber: u32,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    let spec = DkPlanMesh::spec(mesh, options, renumber)?;
    let sizes = Plan::<T, D>::work_sizes(&spec.spec::<D>()?)?;
    write_one(sizes_out, sizes.into())
}

/// [`dk_plan_pool_sizes`] for a plan that renumbers its mesh (`renumber` as
/// [`dk_plan_work_sizes_ordered`]): `2 N` indices more than without (the stored permutation).
/// Errors: those of [`dk_plan_pool_sizes`], `DK_ERR_INVALID_PARAMETER` for an unknown
/// `renumber`.
#[export(twin, mesh[1], options[1], work[1], sizes_out[1])]
pub(crate) fn dk_plan_pool_sizes_ordered<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    renumber: u32,
    work: In<'_, DkPlanPools<T>>,
    sizes_out: Out<'_, dk_plan_sizes>,
) -> Result<(), dk_status> {
    let spec = DkPlanMesh::spec(mesh, options, renumber)?;
    let work = DkPlanPools::read(work)?;
    let s = spec.spec::<D>()?;
    let sizes = Plan::<T, D>::sizes(&s, &mut work.work()?)?;
    write_one(sizes_out, sizes.into())
}

/// [`dk_plan_init`] with the mesh renumbered for memory locality (`renumber`:
/// `DK_PLAN_ORDER_RCM`, reverse Cuthill–McKee of the graph, or `DK_PLAN_ORDER_HILBERT`, a
/// Hilbert curve through the points; sizes from [`dk_plan_work_sizes_ordered`] and
/// [`dk_plan_pool_sizes_ordered`]). The plan stores the permutation (checksummed, it travels
/// with copied pools) and solves in its numbering; the caller sees nothing of it:
/// [`dk_plan_step`] takes the boundary positions in the caller's boundary order and writes
/// `out` in the caller's numbering, bit for bit the un-permuted output of [`dk_plan_init`]'s
/// plan on the mesh renumbered by the same permutation (`dk_order_rcm`, `dk_order_permute_graph`).
/// Worth it on meshes numbered as a generator writes them; a solver that already orders its
/// mesh should use [`dk_plan_init`]. Node indices in errors are the caller's. Errors: those
/// of [`dk_plan_init`], `DK_ERR_INVALID_PARAMETER` for an unknown `renumber`.
#[export(twin, mesh[1], options[1], work[1], pools[1], info_out[1])]
pub(crate) fn dk_plan_init_ordered<T: Real, const D: usize>(
    mesh: In<'_, DkPlanMesh<T>>,
    _dim: Dim<D>,
    options: In<'_, dk_plan_options>,
    renumber: u32,
    work: In<'_, DkPlanPools<T>>,
    pools: In<'_, DkPlanPools<T>>,
    info_out: Out<'_, dk_plan_info>,
) -> Result<(), dk_status> {
    let spec = DkPlanMesh::spec(mesh, options, renumber)?;
    let work = DkPlanPools::read(work)?;
    let pools = DkPlanPools::read(pools)?;
    let s = spec.spec::<D>()?;
    let mut work = work.work()?;
    let info_slot = out_one(info_out)?;
    let (reals, indices, bytes) = pools.borrow()?;
    let plan = Plan::<T, D>::init(&s, &mut work, reals, indices, bytes)?;
    *info_slot = info(&plan);
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// The derivative of the last step (`Plan::tangent`, `Plan::adjoint`).
// ---------------------------------------------------------------------------------------------

/// Scalars of `scratch` that [`dk_plan_tangent`] and [`dk_plan_adjoint`] need for the plan in
/// the pools (one length for both; `Plan::sensitivity_scratch_len`). Errors:
/// `DK_ERR_BAD_PLAN`, `DK_ERR_INVALID_PARAMETER` (`dim`), pointer errors, `DK_ERR_TOO_LARGE`
/// when the length overflows.
#[export(twin, pools[1], len_out[1])]
pub(crate) fn dk_plan_sensitivity_scratch_len<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let plan = DkPlanPools::read(pools)?.open::<D>()?;
    match plan.sensitivity_scratch_len() {
        usize::MAX => Err(dk_status::DK_ERR_TOO_LARGE),
        len => write_one(len_out, len),
    }
}

/// The tangent of the plan's last step: `out = δx` (`N * dim` scalars, every mesh node) for
/// the perturbation `direction = δd` of the deformed boundary positions (`B * dim` scalars,
/// in the plan's boundary order); boundary nodes get `δd` exactly. One solve with the plan's
/// solver and multigrid hierarchy, linearised at the last step (for the quaternion method
/// with its stored solved field, so the deformation's solve is not repeated); after a
/// `DK_PLAN_COLD` step the bits of the stateless derivatives (`dk_deform_spring_tangent`,
/// `dk_spring_solve_linear` with `δd` as the fixed values).
///
/// - `deformed`, `rotation_source`, `rotations`, `origin`: the last step's motion, exactly as
///   passed to [`dk_plan_step`] (checked against the plan's stored boundary values);
/// - `scratch`: [`dk_plan_sensitivity_scratch_len`] scalars;
/// - `report_out`: the solve's report (not converged is `DK_OK` with `converged` false).
///
/// Errors (nothing written but `scratch`; the plan is never written): `DK_ERR_BAD_PLAN`,
/// length and pointer errors, `DK_ERR_NON_FINITE` (`direction`), `DK_ERR_BUFFER_TOO_SMALL`,
/// `DK_ERR_INVALID_PARAMETER` (`dim`, `rotation_source`, a plan that has not stepped yet, a
/// motion that is not the last step's), the boundary rotations' and the solver's errors.
#[export(twin, pools[1], rotations?, origin?, report_out[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_plan_tangent<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    _dim: Dim<D>,
    deformed: In<'_, T>,
    rotation_source: u32,
    rotations: In<'_, T>,
    origin: In<'_, T>,
    direction: In<'_, T>,
    scratch: Out<'_, T>,
    out: Out<'_, T>,
    report_out: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let motion = last_motion(deformed, rotation_source, rotations, origin);
    let buffers = (direction, scratch, out, report_out);
    derivative::<T, D>(pools, motion, buffers, |p, m, i, s, o| {
        p.tangent(m, i, s, o)
    })
}

/// The adjoint of the plan's last step: `out = dJ/dd` (`B * dim` scalars, in the plan's
/// boundary order) for `weights = dJ/dx` at every mesh node (`N * dim` scalars), the
/// transpose of [`dk_plan_tangent`]: one CG solve with the plan's operator and
/// preconditioner (the multigrid hierarchy reused), linearised at the last step. The plan's
/// solver must be multigrid or CG. Arguments and errors as [`dk_plan_tangent`], with
/// `DK_ERR_INVALID_PARAMETER` for a stationary solver (Jacobi, Gauss–Seidel, SOR); on error
/// `out` is unchanged.
#[export(twin, pools[1], rotations?, origin?, report_out[1])]
#[allow(clippy::too_many_arguments)]
pub(crate) fn dk_plan_adjoint<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    _dim: Dim<D>,
    deformed: In<'_, T>,
    rotation_source: u32,
    rotations: In<'_, T>,
    origin: In<'_, T>,
    weights: In<'_, T>,
    scratch: Out<'_, T>,
    out: Out<'_, T>,
    report_out: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let motion = last_motion(deformed, rotation_source, rotations, origin);
    let buffers = (weights, scratch, out, report_out);
    derivative::<T, D>(pools, motion, buffers, |p, m, i, s, o| {
        p.adjoint(m, i, s, o)
    })
}

/// The input field, scratch, output and report of a derivative call.
type DerivativeBuffers<'a, T> = (
    In<'a, T>,
    Out<'a, T>,
    Out<'a, T>,
    Out<'a, dk_spring_solve_report>,
);

/// Opens the plan, reads the motion and the buffers, runs `f` (the tangent or the adjoint)
/// and writes its report.
fn derivative<T: Real, const D: usize>(
    pools: In<'_, DkPlanPools<T>>,
    motion: MotionArgs<'_, T>,
    (input, scratch, out, report_out): DerivativeBuffers<'_, T>,
    f: impl FnOnce(
        &Plan<'_, T, D>,
        &PlanMotion<'_, T, D>,
        &[[T; D]],
        &mut [T],
        &mut [[T; D]],
    ) -> deform_kernel::Result<deform_kernel::spring::SolveReport<T>>,
) -> Result<(), dk_status> {
    let plan = DkPlanPools::read(pools)?.open::<D>()?;
    let motion = motion.motion::<D>(plan.method())?;
    let input = read_points::<T, D>(input)?;
    let scratch = output(scratch)?;
    let out = chunks_mut::<T, D>(out)?;
    let report_slot = out_one(report_out)?;
    let r = f(&plan, &motion, input, scratch, out)?;
    *report_slot = dk_spring_solve_report::of(r);
    Ok(())
}

/// The last step's motion as a derivative call passes it (the start code is not used).
fn last_motion<'a, T>(
    deformed: In<'a, T>,
    rotation_source: u32,
    rotations: In<'a, T>,
    origin: In<'a, T>,
) -> MotionArgs<'a, T> {
    MotionArgs {
        deformed,
        rotation_source,
        rotations,
        origin,
        start: DK_PLAN_WARM,
    }
}
