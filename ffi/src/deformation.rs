//! Quaternion mesh deformation (Samareh, NASA TM-2002-211646): `dk_deform_*`.
//!
//! The one-call pipelines [`dk_deform_idw`], [`dk_deform_tfi`] and [`dk_deform_spring`] take
//! the prescribed boundary motion as a [`dk_boundary_motion`] (f64) or
//! [`dk_boundary_motion_f32`]; the building blocks (`dk_deform_boundary_normals`, …,
//! `dk_deform_update_points`, `dk_deform_localize_nodes`) expose each step of the kernel's
//! `deform_kernel::deformation` module on its own, for callers who mix them.
//!
//! Points cross the ABI as flat arrays of `dim` (2 or 3) scalars per point, `*_len` counting
//! scalars; quaternions are 4 scalars `(w, x, y, z)` per node. Translations are `dim` scalars
//! per node.
//!
//! **Node indices** supplied by the caller (boundary node lists, boundary element offsets and
//! nodes) are read in `index_base` 0 or 1. The kernel wants 0-based slices, so with
//! `index_base` 1 the library converts them into a caller-supplied `uint32_t` `index_scratch`
//! (no allocation): it needs as many entries as the index arrays read (the sum of their
//! lengths; [`dk_boundary_motion_index_scratch_len`] computes it for a motion). With
//! `index_base` 0 the caller's arrays are used as they are and `index_scratch` may be NULL
//! with length 0.
//!
//! **Workspaces.** The pipelines take `translations` and `rotations` arrays (one entry per
//! mesh node) that receive the propagated fields on success. They are workspaces: on an error
//! detected after validation (a solver error, a rotation that cancels) they may have been
//! written. `out` and `origin_out` are written only on success.
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::deformation::{
    boundary_normals, boundary_normals_scratch_len, boundary_origin, boundary_rotations,
    boundary_rotations_scratch_len, boundary_translations, deform_idw, deform_idw_scratch_len,
    deform_spring, deform_spring_scratch_len, deform_tfi, deform_tfi_scratch_len, displacement_tfi,
    localize_nodes, localize_nodes_scratch_len, propagate_idw, propagate_spring,
    propagate_spring_scratch_len, propagate_tfi, rigid_rotations, tfi_scratch_len, update_points,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::SpringSystem;
use deform_kernel::{Block, Cells, Directions, Quat, Real};

use crate::args::{
    assert_layout, block, by_dim, check_base, done, index_need, read_array, read_one, read_points,
    rebase, write_len, write_one,
};
use crate::graph::{dk_cells, CellsIn};
use crate::slice::{chunks, chunks_mut, input, out_one, output, quats, quats_mut, In, Out};
use crate::spring::{
    dk_spring_solve_options, dk_spring_solve_report, dk_spring_system, dk_spring_system_f32,
    SystemC, SystemIn,
};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// Public constants and structs
// ---------------------------------------------------------------------------------------------

/// [`dk_boundary_motion::rotation_source`]: rotations from the undeformed and deformed boundary
/// shapes (needs the boundary elements).
pub const DK_ROTATIONS_SHAPE: u32 = 0;
/// [`dk_boundary_motion::rotation_source`]: one rigid rotation
/// ([`dk_boundary_motion::rigid_rotation`]) for the moving boundary; boundary nodes that stay
/// exactly in place although the rotation would move them (a fixed far field) get the
/// identity, as `deform move` does. Nodes on the rotation axis keep the rotation.
pub const DK_ROTATIONS_RIGID: u32 = 1;
/// [`dk_boundary_motion::rotation_source`]: one rotation per boundary node
/// ([`dk_boundary_motion::node_rotations`]).
pub const DK_ROTATIONS_PER_NODE: u32 = 2;

/// Bit of a TFI `directions` mask: interpolate along `i` (between the faces `i = 0` and
/// `i = ni - 1`).
pub const DK_DIRECTION_I: u32 = 1;
/// Bit of a TFI `directions` mask: interpolate along `j`.
pub const DK_DIRECTION_J: u32 = 2;
/// Bit of a TFI `directions` mask: interpolate along `k` (3D blocks only).
pub const DK_DIRECTION_K: u32 = 4;

// codegen: f32 twin
/// The prescribed motion of a mesh boundary, double precision (the kernel's
/// `BoundaryMotion`): which mesh nodes move where, how they turn, and about which origin.
/// Fill it with [`dk_boundary_motion_default`] first, then set the fields you need.
///
/// The arrays are borrowed for the duration of the call that receives the struct; the library
/// never keeps the pointers.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_boundary_motion {
    /// Mesh node of each of the `B` boundary points, in `index_base`, all distinct. Include
    /// fixed boundaries (far field) with `deformed` equal to their position: they anchor the
    /// propagation.
    pub nodes: *const u32,
    /// Number of entries of `nodes` (`B`, at least 1).
    pub nodes_len: usize,
    /// Deformed position of each boundary point (`B * dim` scalars); reproduced exactly in
    /// the output.
    pub deformed: *const f64,
    /// Number of scalars in `deformed` (`B * dim`).
    pub deformed_len: usize,
    /// Optional boundary elements (every array NULL with length 0 for none), in `index_base`,
    /// their nodes as positions `0..B` in `nodes` (not mesh nodes; see
    /// [`dk_deform_localize_nodes`]): segments (VTK 3) in 2D, triangles/quadrilaterals (5, 9)
    /// in 3D, consistently ordered.
    pub elements: dk_cells,
    /// With [`DK_ROTATIONS_PER_NODE`]: one quaternion `(w, x, y, z)` per boundary node, in
    /// `nodes` order (`4 * B` scalars). Ignored otherwise.
    pub node_rotations: *const f64,
    /// Number of scalars in `node_rotations`.
    pub node_rotations_len: usize,
    /// With [`DK_ROTATIONS_RIGID`]: the rotation `(w, x, y, z)` of the moving boundary nodes
    /// (normalised by the library). Ignored otherwise.
    pub rigid_rotation: [f64; 4],
    /// The rotation origin, used when `has_origin` is nonzero (the first `dim` entries).
    pub origin: [f64; 3],
    /// 0 (C) or 1 (Fortran): the base of `nodes` and of the elements' offsets and nodes.
    pub index_base: u32,
    /// Where the rotations come from: [`DK_ROTATIONS_SHAPE`], [`DK_ROTATIONS_RIGID`] or
    /// [`DK_ROTATIONS_PER_NODE`].
    pub rotation_source: u32,
    /// Nonzero: rotate about `origin`; 0: about the default origin (the centroid of the
    /// moving boundary points, see [`dk_deform_boundary_origin`]).
    pub has_origin: u32,
}

assert_layout!(
    dk_boundary_motion, 168;
    nodes_len = 8, deformed = 16, elements = 32,
    node_rotations = 80, rigid_rotation = 96, origin = 128, index_base = 152, rotation_source = 156,
    has_origin = 160,
);

// ---------------------------------------------------------------------------------------------
// Private plumbing
// ---------------------------------------------------------------------------------------------

/// Reads a required element list (absent elements are a length mismatch).
fn read_required_elements<'a>(
    boundary_len: usize,
    elements: CellsIn<'a>,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<Cells<'a>, dk_status> {
    let (cells, _) = elements.optional_cells(boundary_len, index_base, scratch)?;
    cells.ok_or(dk_status::DK_ERR_LENGTH_MISMATCH)
}

/// An optional `D`-scalar output: length 0 (not wanted) or exactly `D` scalars.
fn optional_out<T: Real, const D: usize>(ptr: Out<'_, T>) -> Result<Option<&mut [T]>, dk_status> {
    match ptr.len() {
        0 => Ok(None),
        len if len == D => output(ptr).map(Some),
        _ => Err(dk_status::DK_ERR_LENGTH_MISMATCH),
    }
}

/// Writes `v` into an optional output (see [`optional_out`]).
fn write_optional<T: Real, const D: usize>(slot: Option<&mut [T]>, v: [T; D]) {
    if let Some(s) = slot {
        for (d, x) in s.iter_mut().zip(v) {
            *d = x;
        }
    }
}

/// The precision-independent view of a [`dk_boundary_motion`] or [`dk_boundary_motion_f32`].
#[derive(Clone, Copy)]
struct RawMotion<'a, T> {
    nodes: In<'a, u32>,
    deformed: In<'a, T>,
    elements: CellsIn<'a>,
    node_rotations: In<'a, T>,
    rigid_rotation: [T; 4],
    origin: [T; 3],
    index_base: u32,
    rotation_source: u32,
    has_origin: u32,
}

/// The two C motion structs, seen through [`RawMotion`].
trait MotionC: Copy {
    type T: Real;
    /// Reads the struct and wraps its arrays in tokens of the struct's lifetime.
    fn raw(p: In<'_, Self>) -> Result<RawMotion<'_, Self::T>, dk_status>;
    fn default_value() -> Self;
}

macro_rules! motion_c {
    ($ty:ty, $t:ty) => {
        impl MotionC for $ty {
            type T = $t;
            fn raw(p: In<'_, Self>) -> Result<RawMotion<'_, $t>, dk_status> {
                let m = read_one(p)?;
                // SAFETY: a token for a motion struct carries the contract of the functions
                // that take one: its arrays are readable for their lengths while it is.
                let raw = unsafe {
                    RawMotion {
                        nodes: In::new(m.nodes, m.nodes_len),
                        deformed: In::new(m.deformed, m.deformed_len),
                        elements: m.elements.tokens(),
                        node_rotations: In::new(m.node_rotations, m.node_rotations_len),
                        rigid_rotation: m.rigid_rotation,
                        origin: m.origin,
                        index_base: m.index_base,
                        rotation_source: m.rotation_source,
                        has_origin: m.has_origin,
                    }
                };
                Ok(raw)
            }
            fn default_value() -> Self {
                Self {
                    nodes: core::ptr::null(),
                    nodes_len: 0,
                    deformed: core::ptr::null(),
                    deformed_len: 0,
                    elements: dk_cells::NONE,
                    node_rotations: core::ptr::null(),
                    node_rotations_len: 0,
                    rigid_rotation: [1.0, 0.0, 0.0, 0.0],
                    origin: [0.0; 3],
                    index_base: 0,
                    rotation_source: DK_ROTATIONS_SHAPE,
                    has_origin: 0,
                }
            }
        }
    };
}
motion_c!(dk_boundary_motion, f64);
motion_c!(dk_boundary_motion_f32, f32);

/// Reads the caller's motion struct.
fn read_raw<M: MotionC>(motion: In<'_, M>) -> Result<RawMotion<'_, M::T>, dk_status> {
    M::raw(motion)
}

impl<'a, T: Real> RawMotion<'a, T> {
    /// `index_scratch` entries this motion needs.
    fn index_need(&self) -> Result<usize, dk_status> {
        index_need(
            self.index_base,
            &[
                self.nodes.len(),
                self.elements.offsets.len(),
                self.elements.nodes.len(),
            ],
        )
    }

    /// The kernel's view of the motion (indices rebased into `scratch`); returns the rest of
    /// `scratch`.
    fn view<const D: usize>(
        &self,
        scratch: &'a mut [u32],
    ) -> Result<(BoundaryMotion<'a, T, D>, &'a mut [u32]), dk_status> {
        check_base(self.index_base)?;
        let nodes = input(self.nodes)?;
        let (nodes, scratch) = rebase(nodes, self.index_base, scratch)?;
        let (elements, scratch) =
            self.elements
                .optional_cells(nodes.len(), self.index_base, scratch)?;
        let deformed = read_points::<T, D>(self.deformed)?;
        let rotations = match self.rotation_source {
            DK_ROTATIONS_SHAPE => RotationSource::Shape,
            DK_ROTATIONS_RIGID => RotationSource::Rigid(Quat::from_array(self.rigid_rotation)),
            DK_ROTATIONS_PER_NODE => {
                let q = quats(self.node_rotations)?;
                RotationSource::PerNode(q)
            }
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        let origin = (self.has_origin != 0)
            .then(|| core::array::from_fn(|d| self.origin.get(d).copied().unwrap_or(T::ZERO)));
        Ok((
            BoundaryMotion {
                nodes,
                deformed,
                elements,
                rotations,
                origin,
            },
            scratch,
        ))
    }
}

/// Validated TFI setup: the block and the active directions.
fn tfi_setup(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
) -> Result<(Block, Directions), dk_status> {
    let block = block(ni, nj, nk)?;
    // `DK_DIRECTION_I | _J | _K` are the kernel's bits; any other bit is refused.
    let directions =
        Directions::from_bits(directions).ok_or(dk_status::DK_ERR_INVALID_PARAMETER)?;
    Ok((block, directions))
}

/// Writes the size `v` to a `size_t` out-parameter, or returns the error that computing it
/// gave (then `len_out` is not checked).
fn len_status(len_out: Out<'_, usize>, v: Result<usize, dk_status>) -> dk_status {
    done(v.and_then(|v| write_len(len_out, v)))
}

// ---------------------------------------------------------------------------------------------
// The motion struct
// ---------------------------------------------------------------------------------------------

fn motion_default<M: MotionC>(out: Out<'_, M>) -> dk_status {
    done(write_one(out, M::default_value()))
}

fn motion_index_len<M: MotionC>(motion: In<'_, M>, len_out: Out<'_, usize>) -> dk_status {
    len_status(len_out, read_raw(motion).and_then(|m| m.index_need()))
}

// ---------------------------------------------------------------------------------------------
// Pipelines: IDW
// ---------------------------------------------------------------------------------------------

/// Outputs common to the pipelines.
struct PipelineOut<'a, T> {
    scratch: Out<'a, T>,
    index_scratch: Out<'a, u32>,
    translations: Out<'a, T>,
    rotations: Out<'a, T>,
    out: Out<'a, T>,
    origin_out: Out<'a, T>,
}

/// The borrowed pipeline buffers (validated pointers).
struct PipelineBufs<'a, T, const D: usize> {
    scratch: &'a mut [T],
    index_scratch: &'a mut [u32],
    translations: &'a mut [[T; D]],
    rotations: &'a mut [Quat<T>],
    out: &'a mut [[T; D]],
    origin_out: Option<&'a mut [T]>,
}

impl<'a, T: Real> PipelineOut<'a, T> {
    fn borrow<const D: usize>(self) -> Result<PipelineBufs<'a, T, D>, dk_status> {
        let scratch = output(self.scratch)?;
        let index_scratch = output(self.index_scratch)?;
        let translations = chunks_mut::<T, D>(self.translations)?;
        let rotations = quats_mut(self.rotations)?;
        let out = chunks_mut::<T, D>(self.out)?;
        let origin_out = optional_out::<T, D>(self.origin_out)?;
        Ok(PipelineBufs {
            scratch,
            index_scratch,
            translations,
            rotations,
            out,
            origin_out,
        })
    }
}

fn idw_d<M: MotionC, const D: usize>(
    points: In<'_, M::T>,
    motion: In<'_, M>,
    exponent: M::T,
    bufs: PipelineOut<'_, M::T>,
) -> Result<(), dk_status> {
    let raw = read_raw(motion)?;
    let points = read_points::<M::T, D>(points)?;
    let b = bufs.borrow::<D>()?;
    let (motion, _) = raw.view::<D>(b.index_scratch)?;
    let origin = deform_idw(
        points,
        &motion,
        exponent,
        b.translations,
        b.rotations,
        b.scratch,
        b.out,
    )
    .map_err(dk_status::from)?;
    write_optional(b.origin_out, origin);
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Pipelines: TFI
// ---------------------------------------------------------------------------------------------

fn tfi_d<M: MotionC, const D: usize>(
    [ni, nj, nk]: [usize; 3],
    directions: u32,
    points: In<'_, M::T>,
    motion: In<'_, M>,
    bufs: PipelineOut<'_, M::T>,
) -> Result<(), dk_status> {
    let (block, directions) = tfi_setup(ni, nj, nk, directions)?;
    let raw = read_raw(motion)?;
    let points = read_points::<M::T, D>(points)?;
    let b = bufs.borrow::<D>()?;
    let (motion, _) = raw.view::<D>(b.index_scratch)?;
    let origin = deform_tfi(
        &block,
        directions,
        points,
        &motion,
        b.translations,
        b.rotations,
        b.scratch,
        b.out,
    )
    .map_err(dk_status::from)?;
    write_optional(b.origin_out, origin);
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Building blocks: boundary level
// ---------------------------------------------------------------------------------------------

/// A boundary element list as it crosses the ABI (offsets and nodes in `index_base`).
struct ElementsIn<'a> {
    elements: In<'a, dk_cells>,
    index_base: u32,
    index_scratch: Out<'a, u32>,
}

impl<'a> ElementsIn<'a> {
    /// The validated cells over `boundary_len` points (required: no elements is a length
    /// mismatch).
    fn read(self, boundary_len: usize) -> Result<Cells<'a>, dk_status> {
        let scratch = output(self.index_scratch)?;
        let elements = CellsIn::read(self.elements)?;
        read_required_elements(boundary_len, elements, self.index_base, scratch)
    }
}

fn normals_d<T: Real, const D: usize>(
    points: In<'_, T>,
    elements: ElementsIn<'_>,
    scratch: Out<'_, T>,
    normals: Out<'_, T>,
) -> Result<(), dk_status> {
    let points = read_points::<T, D>(points)?;
    let cells = elements.read(points.len())?;
    let scratch = output(scratch)?;
    let normals = chunks_mut::<T, D>(normals)?;
    boundary_normals(points, &cells, scratch, normals).map_err(dk_status::from)
}

fn rotations_d<T: Real, const D: usize>(
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    elements: ElementsIn<'_>,
    scratch: Out<'_, T>,
    rotations: Out<'_, T>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let cells = elements.read(u.len())?;
    let scratch = output(scratch)?;
    let rotations = quats_mut(rotations)?;
    boundary_rotations(u, d, &cells, scratch, rotations).map_err(dk_status::from)
}

fn rigid<T: Real>(q: In<'_, T>, rotations: Out<'_, T>) -> dk_status {
    done((|| {
        let q = read_array::<T, 4>(q).map(Quat::from_array)?;
        let r = quats_mut(rotations)?;
        rigid_rotations(q, r).map_err(dk_status::from)
    })())
}

fn origin_d<T: Real, const D: usize>(
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    origin_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    if origin_out.len() != D {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let o = output(origin_out)?;
    let origin = boundary_origin(u, d).map_err(dk_status::from)?;
    write_optional(Some(o), origin);
    Ok(())
}

fn translations_d<T: Real, const D: usize>(
    origin: In<'_, T>,
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    rotations: In<'_, T>,
    translations: Out<'_, T>,
) -> Result<(), dk_status> {
    let origin = read_array::<T, D>(origin)?;
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let q = quats(rotations)?;
    let t = chunks_mut::<T, D>(translations)?;
    boundary_translations(origin, u, d, q, t).map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// Building blocks: field level
// ---------------------------------------------------------------------------------------------

fn propagate_idw_d<T: Real, const D: usize>(
    points: In<'_, T>,
    boundary: In<'_, u32>,
    index_base: u32,
    exponent: T,
    index_scratch: Out<'_, u32>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
) -> Result<(), dk_status> {
    let points = read_points::<T, D>(points)?;
    let boundary = input(boundary)?;
    let scratch = output(index_scratch)?;
    let (boundary, _) = rebase(boundary, index_base, scratch)?;
    let t = chunks_mut::<T, D>(translations)?;
    let q = quats_mut(rotations)?;
    propagate_idw(points, boundary, exponent, t, q).map_err(dk_status::from)
}

/// `rotations` NULL with length 0 and `displacement` set: plain displacement TFI.
#[allow(clippy::too_many_arguments)]
fn propagate_tfi_d<T: Real, const D: usize>(
    [ni, nj, nk]: [usize; 3],
    directions: u32,
    points: In<'_, T>,
    scratch: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    displacement: bool,
) -> Result<(), dk_status> {
    let (block, directions) = tfi_setup(ni, nj, nk, directions)?;
    let points = read_points::<T, D>(points)?;
    let scratch = output(scratch)?;
    let t = chunks_mut::<T, D>(translations)?;
    if displacement {
        return displacement_tfi(&block, directions, points, t, scratch).map_err(dk_status::from);
    }
    let q = quats_mut(rotations)?;
    propagate_tfi(&block, directions, points, t, q, scratch).map_err(dk_status::from)
}

#[allow(clippy::too_many_arguments)]
fn update_d<T: Real, const D: usize>(
    origin: In<'_, T>,
    points: In<'_, T>,
    translations: In<'_, T>,
    rotations: In<'_, T>,
    boundary: In<'_, u32>,
    index_base: u32,
    boundary_deformed: In<'_, T>,
    index_scratch: Out<'_, u32>,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let origin = read_array::<T, D>(origin)?;
    let points = read_points::<T, D>(points)?;
    let t = chunks::<T, D>(translations)?;
    let q = quats(rotations)?;
    let boundary = input(boundary)?;
    let bd = read_points::<T, D>(boundary_deformed)?;
    let scratch = output(index_scratch)?;
    let (boundary, _) = rebase(boundary, index_base, scratch)?;
    let out = chunks_mut::<T, D>(out)?;
    update_points(origin, points, t, q, boundary, bd, out).map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// Springs (options and report types from the spring module)
// ---------------------------------------------------------------------------------------------

/// Number of scalars of the packed `values` workspace of the spring propagation (the
/// kernel's `propagate_spring_scratch_len`).
fn spring_values_len(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
) -> Result<usize, dk_status> {
    let o = read_one(options)?;
    let method = o.method::<f64>()?;
    let len = match dim {
        2 => propagate_spring_scratch_len::<2>(&method, node_count),
        3 => propagate_spring_scratch_len::<3>(&method, node_count),
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    // The kernel's length saturates; a saturated length is too large to allocate anyway.
    if len == usize::MAX {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    Ok(len)
}

fn spring_index_len<M: MotionC>(
    motion: In<'_, M>,
    node_count: usize,
    len_out: Out<'_, usize>,
) -> dk_status {
    len_status(
        len_out,
        read_raw(motion).and_then(|m| {
            m.index_need()?
                .checked_add(SpringSystem::<M::T>::scratch_len(node_count))
                .ok_or(dk_status::DK_ERR_TOO_LARGE)
        }),
    )
}

#[allow(clippy::too_many_arguments)]
fn spring_d<M: MotionC, const D: usize>(
    points: In<'_, M::T>,
    motion: In<'_, M>,
    system: Result<SystemIn<'_, M::T>, dk_status>,
    options: In<'_, dk_spring_solve_options>,
    values: Out<'_, M::T>,
    bufs: PipelineOut<'_, M::T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method::<M::T>()?;
    let stop = o.stopping::<M::T>();
    let raw = read_raw(motion)?;
    let points = read_points::<M::T, D>(points)?;
    let b = bufs.borrow::<D>()?;
    let values = output(values)?;
    let report = out_one(report)?;
    let (motion, rest) = raw.view::<D>(b.index_scratch)?;
    let sys = system?.build(rest)?;
    let (origin, rep) = deform_spring(
        points,
        &motion,
        &sys,
        method,
        &stop,
        b.translations,
        b.rotations,
        b.scratch,
        values,
        b.out,
    )
    .map_err(dk_status::from)?;
    write_optional(b.origin_out, origin);
    *report = dk_spring_solve_report::of(rep);
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn propagate_spring_d<T: Real, const D: usize>(
    system: Result<SystemIn<'_, T>, dk_status>,
    options: In<'_, dk_spring_solve_options>,
    index_scratch: Out<'_, u32>,
    values: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method::<T>()?;
    let stop = o.stopping::<T>();
    let s = output(index_scratch)?;
    let values = output(values)?;
    let t = chunks_mut::<T, D>(translations)?;
    let q = quats_mut(rotations)?;
    let report = out_one(report)?;
    let sys = system?.build(s)?;
    let rep = propagate_spring(&sys, method, &stop, t, q, values).map_err(dk_status::from)?;
    *report = dk_spring_solve_report::of(rep);
    Ok(())
}

mod abi;
pub use abi::*;
