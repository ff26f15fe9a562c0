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
use deform_kernel::{Block, Cells, Quat, Real};

use crate::args::{
    assert_layout, block, check_base, done, graph, mul_len, read_array, read_one, read_points,
    write_len, zero_based,
};
use crate::slice::{chunks, chunks_mut, input, out_one, output, quats, quats_mut, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// Public constants and structs
// ---------------------------------------------------------------------------------------------

/// [`dk_boundary_motion::rotation_source`]: rotations from the undeformed and deformed boundary
/// shapes (needs the boundary elements).
pub const DK_ROTATIONS_SHAPE: u32 = 0;
/// [`dk_boundary_motion::rotation_source`]: one rigid rotation
/// ([`dk_boundary_motion::rigid_rotation`]) for every boundary node.
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
    /// Boundary element offsets into `element_nodes` (one per element plus one, in
    /// `index_base` like graph.rs cell offsets), or NULL with length 0 for no elements.
    pub element_offsets: *const u32,
    /// Number of entries of `element_offsets` (0: no elements).
    pub element_offsets_len: usize,
    /// Element nodes as positions `0..B` in `nodes` (not mesh nodes; see
    /// [`dk_deform_localize_nodes`]), in `index_base`: segments (VTK 3) in 2D,
    /// triangles/quadrilaterals (5, 9) in 3D, consistently ordered.
    pub element_nodes: *const u32,
    /// Number of entries of `element_nodes`.
    pub element_nodes_len: usize,
    /// VTK kind code of each element.
    pub element_kinds: *const u8,
    /// Number of entries of `element_kinds` (elements).
    pub element_kinds_len: usize,
    /// With [`DK_ROTATIONS_PER_NODE`]: one quaternion `(w, x, y, z)` per boundary node, in
    /// `nodes` order (`4 * B` scalars). Ignored otherwise.
    pub node_rotations: *const f64,
    /// Number of scalars in `node_rotations`.
    pub node_rotations_len: usize,
    /// With [`DK_ROTATIONS_RIGID`]: the rotation `(w, x, y, z)` of every boundary node
    /// (normalised by the library). Ignored otherwise.
    pub rigid_rotation: [f64; 4],
    /// The rotation origin, used when `has_origin` is nonzero (the first `dim` entries).
    pub origin: [f64; 3],
    /// 0 (C) or 1 (Fortran): the base of `nodes`, `element_offsets` and `element_nodes`.
    pub index_base: u32,
    /// Where the rotations come from: [`DK_ROTATIONS_SHAPE`], [`DK_ROTATIONS_RIGID`] or
    /// [`DK_ROTATIONS_PER_NODE`].
    pub rotation_source: u32,
    /// Nonzero: rotate about `origin`; 0: about the default origin (the centroid of the
    /// moving boundary points, see [`dk_deform_boundary_origin`]).
    pub has_origin: u32,
}

/// Single-precision twin of [`dk_boundary_motion`] (same fields, `float` scalars).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct dk_boundary_motion_f32 {
    /// Mesh node of each boundary point, in `index_base`, all distinct.
    pub nodes: *const u32,
    /// Number of entries of `nodes` (`B`, at least 1).
    pub nodes_len: usize,
    /// Deformed position of each boundary point (`B * dim` scalars).
    pub deformed: *const f32,
    /// Number of scalars in `deformed`.
    pub deformed_len: usize,
    /// Boundary element offsets (in `index_base`), or NULL with length 0 for no elements.
    pub element_offsets: *const u32,
    /// Number of entries of `element_offsets` (0: no elements).
    pub element_offsets_len: usize,
    /// Element nodes as positions `0..B` in `nodes`, in `index_base`.
    pub element_nodes: *const u32,
    /// Number of entries of `element_nodes`.
    pub element_nodes_len: usize,
    /// VTK kind code of each element.
    pub element_kinds: *const u8,
    /// Number of entries of `element_kinds`.
    pub element_kinds_len: usize,
    /// With [`DK_ROTATIONS_PER_NODE`]: `4 * B` quaternion scalars. Ignored otherwise.
    pub node_rotations: *const f32,
    /// Number of scalars in `node_rotations`.
    pub node_rotations_len: usize,
    /// With [`DK_ROTATIONS_RIGID`]: the rotation of every boundary node. Ignored otherwise.
    pub rigid_rotation: [f32; 4],
    /// The rotation origin, used when `has_origin` is nonzero.
    pub origin: [f32; 3],
    /// 0 or 1: the base of `nodes`, `element_offsets` and `element_nodes`.
    pub index_base: u32,
    /// [`DK_ROTATIONS_SHAPE`], [`DK_ROTATIONS_RIGID`] or [`DK_ROTATIONS_PER_NODE`].
    pub rotation_source: u32,
    /// Nonzero: rotate about `origin`; 0: about the default origin.
    pub has_origin: u32,
}

#[cfg(target_pointer_width = "64")]
assert_layout!(
    dk_boundary_motion, 168;
    nodes_len = 8, deformed = 16, element_offsets = 32, element_nodes = 48, element_kinds = 64,
    node_rotations = 80, rigid_rotation = 96, origin = 128, index_base = 152, rotation_source = 156,
    has_origin = 160,
);

#[cfg(target_pointer_width = "64")]
assert_layout!(
    dk_boundary_motion_f32, 136;
    node_rotations = 80, rigid_rotation = 96, origin = 112, index_base = 124, rotation_source = 128,
    has_origin = 132,
);

// ---------------------------------------------------------------------------------------------
// Private plumbing
// ---------------------------------------------------------------------------------------------

/// A piece of work generic over the point dimension `D` and the packed spring value width
/// `V = D + 4` (unused by most jobs).
trait ByDim: Sized {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status>;
}

/// Runs `job` for `dim` 2 or 3; any other `dim` is `DK_ERR_INVALID_PARAMETER` (as in the
/// other modules of the ABI).
fn by_dim(dim: u32, job: impl ByDim) -> dk_status {
    done(match dim {
        2 => job.run::<2, 6>(),
        3 => job.run::<3, 7>(),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    })
}

/// The 0-based view of a caller's index array: the array itself (`index_base` 0), or a
/// converted copy in the front of `scratch` (`index_base` 1; an index below the base becomes
/// `u32::MAX`, which every bound rejects). Returns the view and the unused rest of `scratch`.
fn rebase<'a>(
    src: &'a [u32],
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(&'a [u32], &'a mut [u32]), dk_status> {
    match index_base {
        0 => Ok((src, scratch)),
        1 => {
            let (head, tail) = scratch
                .split_at_mut_checked(src.len())
                .ok_or(dk_status::DK_ERR_BUFFER_TOO_SMALL)?;
            for (d, &s) in head.iter_mut().zip(src) {
                *d = zero_based(s, index_base);
            }
            Ok((&*head, tail))
        }
        _ => Err(dk_status::DK_ERR_BAD_INDEX_BASE),
    }
}

/// Number of `index_scratch` entries that rebasing arrays of `lens` entries needs.
fn index_need(index_base: u32, lens: &[usize]) -> Result<usize, dk_status> {
    check_base(index_base)?;
    if index_base == 0 {
        return Ok(0);
    }
    lens.iter()
        .try_fold(0usize, |a, &l| a.checked_add(l))
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// Reads a boundary element list (offsets and nodes in `index_base`) over `boundary_len`
/// points; `None` when `offsets_len` is 0. Returns the rest of `scratch`.
#[allow(clippy::too_many_arguments)]
fn read_elements<'a>(
    boundary_len: usize,
    offsets: In<'a, u32>,
    offsets_len: usize,
    nodes: In<'a, u32>,
    nodes_len: usize,
    kinds: In<'a, u8>,
    kinds_len: usize,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(Option<Cells<'a>>, &'a mut [u32]), dk_status> {
    check_base(index_base)?;
    if offsets_len == 0 {
        if nodes_len != 0 || kinds_len != 0 {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        return Ok((None, scratch));
    }
    let o = input(offsets, offsets_len)?;
    let n = input(nodes, nodes_len)?;
    let k = input(kinds, kinds_len)?;
    let (o, scratch) = rebase(o, index_base, scratch)?;
    let (n, scratch) = rebase(n, index_base, scratch)?;
    let cells = Cells::new(boundary_len, o, n, k).map_err(dk_status::from)?;
    Ok((Some(cells), scratch))
}

/// Reads a required element list (absent elements are a length mismatch).
#[allow(clippy::too_many_arguments)]
fn read_required_elements<'a>(
    boundary_len: usize,
    offsets: In<'a, u32>,
    offsets_len: usize,
    nodes: In<'a, u32>,
    nodes_len: usize,
    kinds: In<'a, u8>,
    kinds_len: usize,
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<Cells<'a>, dk_status> {
    let (cells, _) = read_elements(
        boundary_len,
        offsets,
        offsets_len,
        nodes,
        nodes_len,
        kinds,
        kinds_len,
        index_base,
        scratch,
    )?;
    cells.ok_or(dk_status::DK_ERR_LENGTH_MISMATCH)
}

/// An optional `D`-scalar output: NULL with length 0 (not wanted) or exactly `D` scalars.
fn optional_out<'a, T: Real, const D: usize>(
    ptr: Out<'a, T>,
    len: usize,
) -> Result<Option<&'a mut [T]>, dk_status> {
    if len == 0 {
        return Ok(None);
    }
    if len != D {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    output(ptr, len).map(Some)
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
    nodes_len: usize,
    deformed: In<'a, T>,
    deformed_len: usize,
    element_offsets: In<'a, u32>,
    element_offsets_len: usize,
    element_nodes: In<'a, u32>,
    element_nodes_len: usize,
    element_kinds: In<'a, u8>,
    element_kinds_len: usize,
    node_rotations: In<'a, T>,
    node_rotations_len: usize,
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
                        nodes_len: m.nodes_len,
                        deformed: In::new(m.deformed, m.deformed_len),
                        deformed_len: m.deformed_len,
                        element_offsets: In::new(m.element_offsets, m.element_offsets_len),
                        element_offsets_len: m.element_offsets_len,
                        element_nodes: In::new(m.element_nodes, m.element_nodes_len),
                        element_nodes_len: m.element_nodes_len,
                        element_kinds: In::new(m.element_kinds, m.element_kinds_len),
                        element_kinds_len: m.element_kinds_len,
                        node_rotations: In::new(m.node_rotations, m.node_rotations_len),
                        node_rotations_len: m.node_rotations_len,
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
                    element_offsets: core::ptr::null(),
                    element_offsets_len: 0,
                    element_nodes: core::ptr::null(),
                    element_nodes_len: 0,
                    element_kinds: core::ptr::null(),
                    element_kinds_len: 0,
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
                self.nodes_len,
                self.element_offsets_len,
                self.element_nodes_len,
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
        let nodes = input(self.nodes, self.nodes_len)?;
        let (nodes, scratch) = rebase(nodes, self.index_base, scratch)?;
        let (elements, scratch) = read_elements(
            nodes.len(),
            self.element_offsets,
            self.element_offsets_len,
            self.element_nodes,
            self.element_nodes_len,
            self.element_kinds,
            self.element_kinds_len,
            self.index_base,
            scratch,
        )?;
        let deformed = read_points::<T, D>(self.deformed, self.deformed_len)?;
        let rotations = match self.rotation_source {
            DK_ROTATIONS_SHAPE => RotationSource::Shape,
            DK_ROTATIONS_RIGID => RotationSource::Rigid(Quat::from_array(self.rigid_rotation)),
            DK_ROTATIONS_PER_NODE => {
                let q = quats(self.node_rotations, self.node_rotations_len)?;
                RotationSource::PerNode(q)
            }
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        let origin = if self.has_origin != 0 {
            let mut o = [T::ZERO; D];
            for (d, &s) in o.iter_mut().zip(self.origin.iter()) {
                *d = s;
            }
            Some(o)
        } else {
            None
        };
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
) -> Result<(Block, [bool; 3]), dk_status> {
    let block = block(ni, nj, nk)?;
    if directions & !(DK_DIRECTION_I | DK_DIRECTION_J | DK_DIRECTION_K) != 0 {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    Ok((
        block,
        [
            directions & DK_DIRECTION_I != 0,
            directions & DK_DIRECTION_J != 0,
            directions & DK_DIRECTION_K != 0,
        ],
    ))
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
    done((|| {
        let o = out_one(out)?;
        *o = M::default_value();
        Ok(())
    })())
}

/// Fills `*out` with an empty motion: no nodes, no elements, `rotation_source`
/// [`DK_ROTATIONS_SHAPE`], identity `rigid_rotation` `(1, 0, 0, 0)`, zero `origin` with
/// `has_origin` 0 (default origin), `index_base` 0. Set the fields you need afterwards.
///
/// # Safety
/// `out` points to one writable `dk_boundary_motion` (or is NULL: `DK_ERR_NULL_POINTER`).
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_boundary_motion_default(out: *mut dk_boundary_motion) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    motion_default(out)
}

/// `f32` twin of [`dk_boundary_motion_default`].
///
/// # Safety
/// As [`dk_boundary_motion_default`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_boundary_motion_default_f32(
    out: *mut dk_boundary_motion_f32,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let out = unsafe { Out::new(out, 1) };
    motion_default(out)
}

fn motion_index_len<M: MotionC>(motion: In<'_, M>, len_out: Out<'_, usize>) -> dk_status {
    len_status(len_out, read_raw(motion).and_then(|m| m.index_need()))
}

/// Number of `uint32_t` entries the `index_scratch` of a pipeline needs for `*motion`:
/// `nodes_len + element_offsets_len + element_nodes_len` with `index_base` 1, 0 with
/// `index_base` 0 (then `index_scratch` may be NULL). [`dk_deform_spring`] needs `node_count`
/// more (see [`dk_deform_spring_index_scratch_len`]). Errors: `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_TOO_LARGE` (the sum overflows).
///
/// # Safety
/// `motion` points to one readable `dk_boundary_motion`; `len_out` to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_boundary_motion_index_scratch_len(
    motion: *const dk_boundary_motion,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (motion, len_out) = unsafe { (In::new(motion, 1), Out::new(len_out, 1)) };
    motion_index_len(motion, len_out)
}

/// `f32` twin of [`dk_boundary_motion_index_scratch_len`].
///
/// # Safety
/// As [`dk_boundary_motion_index_scratch_len`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_boundary_motion_index_scratch_len_f32(
    motion: *const dk_boundary_motion_f32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (motion, len_out) = unsafe { (In::new(motion, 1), Out::new(len_out, 1)) };
    motion_index_len(motion, len_out)
}

// ---------------------------------------------------------------------------------------------
// Pipelines: IDW
// ---------------------------------------------------------------------------------------------

/// Number of scalars the `scratch` of [`dk_deform_idw`] (and [`dk_deform_spring`]) needs for
/// `node_count` mesh nodes and `boundary_len` boundary nodes in dimension `dim` (2 or 3):
/// `max(node_count, 3 boundary_len)` in 2D, `max(node_count, 13 boundary_len)` in 3D (the
/// kernel's `deform_idw_scratch_len`). The same for both precisions.
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_idw_scratch_len(
    node_count: usize,
    boundary_len: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(
        len_out,
        match dim {
            2 => Ok(deform_idw_scratch_len::<2>(node_count, boundary_len)),
            3 => Ok(deform_idw_scratch_len::<3>(node_count, boundary_len)),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        },
    )
}

/// Outputs common to the pipelines.
struct PipelineOut<'a, T> {
    scratch: Out<'a, T>,
    scratch_len: usize,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
    translations: Out<'a, T>,
    translations_len: usize,
    rotations: Out<'a, T>,
    rotations_len: usize,
    out: Out<'a, T>,
    out_len: usize,
    origin_out: Out<'a, T>,
    origin_out_len: usize,
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
        let scratch = output(self.scratch, self.scratch_len)?;
        let index_scratch = output(self.index_scratch, self.index_scratch_len)?;
        let translations = chunks_mut::<T, D>(self.translations, self.translations_len)?;
        let rotations = quats_mut(self.rotations, self.rotations_len)?;
        let out = chunks_mut::<T, D>(self.out, self.out_len)?;
        let origin_out = optional_out::<T, D>(self.origin_out, self.origin_out_len)?;
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

struct Idw<'a, M: MotionC> {
    points: In<'a, M::T>,
    points_len: usize,
    motion: In<'a, M>,
    exponent: M::T,
    bufs: PipelineOut<'a, M::T>,
}

impl<'a, M: MotionC> ByDim for Idw<'a, M> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let raw = read_raw(self.motion)?;
        let points = read_points::<M::T, D>(self.points, self.points_len)?;
        let b = self.bufs.borrow::<D>()?;
        let (motion, _) = raw.view::<D>(b.index_scratch)?;
        let origin = deform_idw(
            points,
            &motion,
            self.exponent,
            b.translations,
            b.rotations,
            b.scratch,
            b.out,
        )
        .map_err(dk_status::from)?;
        write_optional(b.origin_out, origin);
        Ok(())
    }
}

/// The whole quaternion deformation with inverse-distance propagation (the kernel's
/// `deform_idw`): boundary rotations from `motion->rotation_source`, the origin (given, or the
/// centroid of the moving boundary points), translations `Δ_i = (r_i^d − o) − Q_i (r_i^u − o)
/// Q_i*`, inverse-distance weighting of `(Δ, Q)` with weights `(d_min / d)^exponent`, and the
/// update `out = o + Δ + Q (points − o) Q*`; boundary nodes are set to `motion->deformed`
/// exactly.
///
/// - `points`: the undeformed mesh, `points_len = N * dim` scalars, `dim` 2 or 3.
/// - `motion`: the boundary motion (see [`dk_boundary_motion`]).
/// - `exponent`: finite and positive (2–5 is typical; larger is more local).
/// - `scratch`: [`dk_deform_idw_scratch_len`] scalars; `index_scratch`:
///   [`dk_boundary_motion_index_scratch_len`] entries (NULL with 0 for `index_base` 0).
/// - `translations` (`N * dim`), `rotations` (`4 N`): workspaces that receive the propagated
///   fields on success (and may have been written on error).
/// - `out` (`N * dim`): the deformed mesh; `origin_out`: the origin used (`dim` scalars), or
///   NULL with length 0.
///
/// Errors: pointer and length errors, `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_INDEX_OUT_OF_RANGE` (a boundary node or element node), `DK_ERR_DUPLICATE_NODE`,
/// `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a zero rotation), `DK_ERR_INVALID_PARAMETER` (no
/// boundary node, bad exponent, unknown rotation source, shape rotations without elements),
/// the cell errors of the elements and the errors of the shape rotations
/// (`DK_ERR_ISOLATED_NODE`, `DK_ERR_ZERO_LENGTH_EDGE`, `DK_ERR_CELL_DIMENSION` for an element
/// kind that does not fit `dim`). On error
/// `out` and `origin_out` are unchanged.
///
/// # Safety
/// `points` is readable for `points_len` scalars; `motion` points to one readable struct
/// whose arrays are readable for their lengths; every writable buffer is valid for its length;
/// no writable buffer overlaps another buffer or an input.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_idw(
    points: *const f64,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion,
    exponent: f64,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
    out: *mut f64,
    out_len: usize,
    origin_out: *mut f64,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, motion, scratch, index_scratch, translations, rotations, out, origin_out) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Idw {
            points,
            points_len,
            motion,
            exponent,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
        },
    )
}

/// `f32` twin of [`dk_deform_idw`].
///
/// # Safety
/// As [`dk_deform_idw`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_idw_f32(
    points: *const f32,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion_f32,
    exponent: f32,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
    out: *mut f32,
    out_len: usize,
    origin_out: *mut f32,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, motion, scratch, index_scratch, translations, rotations, out, origin_out) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Idw {
            points,
            points_len,
            motion,
            exponent,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Pipelines: TFI
// ---------------------------------------------------------------------------------------------

/// Number of scalars the `scratch` of [`dk_deform_tfi`] needs for a `ni × nj × nk` block with
/// `boundary_len` boundary nodes in dimension `dim`: `max(dim · ni nj nk, boundary rotation
/// scratch)` (the kernel's `deform_tfi_scratch_len`). Errors: `DK_ERR_BAD_DIMENSIONS` (a zero
/// dimension, too many points), `DK_ERR_INVALID_PARAMETER` (`dim` not 2 or 3).
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_tfi_scratch_len(
    ni: usize,
    nj: usize,
    nk: usize,
    boundary_len: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(
        len_out,
        block(ni, nj, nk).and_then(|b| match dim {
            2 => Ok(deform_tfi_scratch_len::<2>(&b, boundary_len)),
            3 => Ok(deform_tfi_scratch_len::<3>(&b, boundary_len)),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }),
    )
}

struct Tfi<'a, M: MotionC> {
    dims: [usize; 3],
    directions: u32,
    points: In<'a, M::T>,
    points_len: usize,
    motion: In<'a, M>,
    bufs: PipelineOut<'a, M::T>,
}

impl<'a, M: MotionC> ByDim for Tfi<'a, M> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let [ni, nj, nk] = self.dims;
        let (block, directions) = tfi_setup(ni, nj, nk, self.directions)?;
        let raw = read_raw(self.motion)?;
        let points = read_points::<M::T, D>(self.points, self.points_len)?;
        let b = self.bufs.borrow::<D>()?;
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
}

/// The whole quaternion deformation of a structured block with transfinite interpolation (the
/// kernel's `deform_tfi`): as [`dk_deform_idw`], with the arclength-blended TFI of `(Δ, Q)`
/// over the active `directions` (a mask of [`DK_DIRECTION_I`], [`DK_DIRECTION_J`],
/// [`DK_DIRECTION_K`]) instead of inverse-distance weighting.
///
/// The block has `ni × nj × nk` points (`nk = 1` in 2D), numbered `i + ni (j + nj k)`;
/// `points_len = ni nj nk · dim`. Every point on a face of an active direction must be listed
/// in `motion->nodes` (else `DK_ERR_UNANCHORED`); for an O-grid activate only
/// `DK_DIRECTION_J` (wall `j = 0`, far field `j = nj − 1`). `scratch` needs
/// [`dk_deform_tfi_scratch_len`] scalars. Further errors: `DK_ERR_BAD_DIMENSIONS` (block),
/// `DK_ERR_INVALID_PARAMETER` (no or unknown direction bits, a direction with one point).
/// On error `out` and `origin_out` are unchanged (`translations`, `rotations` are
/// workspaces).
///
/// # Safety
/// As [`dk_deform_idw`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_tfi(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
    out: *mut f64,
    out_len: usize,
    origin_out: *mut f64,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, motion, scratch, index_scratch, translations, rotations, out, origin_out) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Tfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            motion,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
        },
    )
}

/// `f32` twin of [`dk_deform_tfi`].
///
/// # Safety
/// As [`dk_deform_idw`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_tfi_f32(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion_f32,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
    out: *mut f32,
    out_len: usize,
    origin_out: *mut f32,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, motion, scratch, index_scratch, translations, rotations, out, origin_out) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Tfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            motion,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Building blocks: boundary level
// ---------------------------------------------------------------------------------------------

/// Number of scalars the `scratch` of [`dk_deform_boundary_normals`] needs:
/// `3 * boundary_len` (saturating).
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_normals_scratch_len(
    boundary_len: usize,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(len_out, Ok(boundary_normals_scratch_len(boundary_len)))
}

/// A boundary element list as it crosses the ABI (offsets and nodes in `index_base`).
struct ElementsIn<'a> {
    offsets: In<'a, u32>,
    offsets_len: usize,
    nodes: In<'a, u32>,
    nodes_len: usize,
    kinds: In<'a, u8>,
    kinds_len: usize,
    index_base: u32,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
}

impl<'a> ElementsIn<'a> {
    /// The validated cells over `boundary_len` points (required: no elements is a length
    /// mismatch).
    fn read(self, boundary_len: usize) -> Result<Cells<'a>, dk_status> {
        let scratch = output(self.index_scratch, self.index_scratch_len)?;
        read_required_elements(
            boundary_len,
            self.offsets,
            self.offsets_len,
            self.nodes,
            self.nodes_len,
            self.kinds,
            self.kinds_len,
            self.index_base,
            scratch,
        )
    }
}

struct Normals<'a, T> {
    points: In<'a, T>,
    points_len: usize,
    elements: ElementsIn<'a>,
    scratch: Out<'a, T>,
    scratch_len: usize,
    normals: Out<'a, T>,
    normals_len: usize,
}

impl<'a, T: Real> ByDim for Normals<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let points = read_points::<T, D>(self.points, self.points_len)?;
        let cells = self.elements.read(points.len())?;
        let scratch = output(self.scratch, self.scratch_len)?;
        let normals = chunks_mut::<T, D>(self.normals, self.normals_len)?;
        boundary_normals(points, &cells, scratch, normals).map_err(dk_status::from)
    }
}

/// Area-weighted unit normals of a boundary at its nodes (the kernel's `boundary_normals`;
/// Samareh's `n`, eq. 5): each node's normal is the normalised sum of the raw normals of its
/// elements (segment length in 2D, twice the face area in 3D). In 2D the normal of a segment
/// `a → b` is `(t_y, −t_x)` (outward for a counter-clockwise loop); in 3D the right-hand rule.
///
/// `points` holds the `B` boundary points (`B * dim` scalars, `dim` 2 or 3); the elements
/// (offsets, nodes as positions `0..B`, VTK kinds: segments in 2D, triangles/quads in 3D) are
/// read in `index_base`, converted into `index_scratch` with `index_base` 1
/// (`element_offsets_len + element_nodes_len` entries; NULL with 0 for `index_base` 0).
/// `scratch` needs [`dk_deform_boundary_normals_scratch_len`] scalars; `normals` receives
/// `B * dim` scalars.
///
/// Errors: pointer and length errors (no elements: `DK_ERR_LENGTH_MISMATCH`), the cell errors,
/// `DK_ERR_CELL_DIMENSION` (an element kind that does not fit `dim`), `DK_ERR_NON_FINITE`,
/// `DK_ERR_ISOLATED_NODE` (a point in no element), `DK_ERR_ZERO_LENGTH` (the element normals
/// cancel at a node). On error `normals` is unchanged.
///
/// # Safety
/// Every pointer is valid for its length (reads for inputs, writes for `scratch`,
/// `index_scratch`, `normals`); the writable buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_normals(
    points: *const f64,
    points_len: usize,
    dim: u32,
    element_offsets: *const u32,
    element_offsets_len: usize,
    element_nodes: *const u32,
    element_nodes_len: usize,
    element_kinds: *const u8,
    element_kinds_len: usize,
    index_base: u32,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    normals: *mut f64,
    normals_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, element_offsets, element_nodes, element_kinds, scratch, index_scratch, normals) = unsafe {
        (
            In::new(points, points_len),
            In::new(element_offsets, element_offsets_len),
            In::new(element_nodes, element_nodes_len),
            In::new(element_kinds, element_kinds_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(normals, normals_len),
        )
    };
    by_dim(
        dim,
        Normals {
            points,
            points_len,
            elements: ElementsIn {
                offsets: element_offsets,
                offsets_len: element_offsets_len,
                nodes: element_nodes,
                nodes_len: element_nodes_len,
                kinds: element_kinds,
                kinds_len: element_kinds_len,
                index_base,
                index_scratch,
                index_scratch_len,
            },
            scratch,
            scratch_len,
            normals,
            normals_len,
        },
    )
}

/// `f32` twin of [`dk_deform_boundary_normals`].
///
/// # Safety
/// As [`dk_deform_boundary_normals`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_normals_f32(
    points: *const f32,
    points_len: usize,
    dim: u32,
    element_offsets: *const u32,
    element_offsets_len: usize,
    element_nodes: *const u32,
    element_nodes_len: usize,
    element_kinds: *const u8,
    element_kinds_len: usize,
    index_base: u32,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    normals: *mut f32,
    normals_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, element_offsets, element_nodes, element_kinds, scratch, index_scratch, normals) = unsafe {
        (
            In::new(points, points_len),
            In::new(element_offsets, element_offsets_len),
            In::new(element_nodes, element_nodes_len),
            In::new(element_kinds, element_kinds_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(normals, normals_len),
        )
    };
    by_dim(
        dim,
        Normals {
            points,
            points_len,
            elements: ElementsIn {
                offsets: element_offsets,
                offsets_len: element_offsets_len,
                nodes: element_nodes,
                nodes_len: element_nodes_len,
                kinds: element_kinds,
                kinds_len: element_kinds_len,
                index_base,
                index_scratch,
                index_scratch_len,
            },
            scratch,
            scratch_len,
            normals,
            normals_len,
        },
    )
}

/// Number of scalars the `scratch` of [`dk_deform_boundary_rotations`] needs: `3 B` in 2D,
/// `13 B` in 3D (saturating). `DK_ERR_INVALID_PARAMETER` unless `dim` is 2 or 3.
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_rotations_scratch_len(
    boundary_len: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(
        len_out,
        match dim {
            2 => Ok(boundary_rotations_scratch_len::<2>(boundary_len)),
            3 => Ok(boundary_rotations_scratch_len::<3>(boundary_len)),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        },
    )
}

struct Rotations<'a, T> {
    undeformed: In<'a, T>,
    undeformed_len: usize,
    deformed: In<'a, T>,
    deformed_len: usize,
    elements: ElementsIn<'a>,
    scratch: Out<'a, T>,
    scratch_len: usize,
    rotations: Out<'a, T>,
    rotations_len: usize,
}

impl<'a, T: Real> ByDim for Rotations<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let u = read_points::<T, D>(self.undeformed, self.undeformed_len)?;
        let d = read_points::<T, D>(self.deformed, self.deformed_len)?;
        let cells = self.elements.read(u.len())?;
        let scratch = output(self.scratch, self.scratch_len)?;
        let rotations = quats_mut(self.rotations, self.rotations_len)?;
        boundary_rotations(u, d, &cells, scratch, rotations).map_err(dk_status::from)
    }
}

/// Per-node rotations of a boundary from its undeformed and deformed shapes (the kernel's
/// `boundary_rotations`). 3D: `Q1` turns the undeformed node normal onto the deformed one,
/// then a twist about the deformed normal (weighted circular mean over the element edges at
/// the node), `Q = Q2 Q1`. 2D: a rotation about z by the mean change of direction of the
/// node's segments.
///
/// `undeformed`, `deformed`: the `B` boundary points (`B * dim` scalars each); elements as for
/// [`dk_deform_boundary_normals`] (same `index_base` and `index_scratch` rules). `scratch`:
/// [`dk_deform_boundary_rotations_scratch_len`] scalars; `rotations` receives `4 B` scalars
/// (unit quaternions `(w, x, y, z)`).
///
/// Errors: as [`dk_deform_boundary_normals`], plus `DK_ERR_ZERO_LENGTH_EDGE` (in either
/// shape) and `DK_ERR_ISOLATED_NODE` (in 3D also a node whose twist is undetermined). On error
/// `rotations` is unchanged.
///
/// # Safety
/// As [`dk_deform_boundary_normals`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_rotations(
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    element_offsets: *const u32,
    element_offsets_len: usize,
    element_nodes: *const u32,
    element_nodes_len: usize,
    element_kinds: *const u8,
    element_kinds_len: usize,
    index_base: u32,
    scratch: *mut f64,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        undeformed,
        deformed,
        element_offsets,
        element_nodes,
        element_kinds,
        scratch,
        index_scratch,
        rotations,
    ) = unsafe {
        (
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            In::new(element_offsets, element_offsets_len),
            In::new(element_nodes, element_nodes_len),
            In::new(element_kinds, element_kinds_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        Rotations {
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            elements: ElementsIn {
                offsets: element_offsets,
                offsets_len: element_offsets_len,
                nodes: element_nodes,
                nodes_len: element_nodes_len,
                kinds: element_kinds,
                kinds_len: element_kinds_len,
                index_base,
                index_scratch,
                index_scratch_len,
            },
            scratch,
            scratch_len,
            rotations,
            rotations_len,
        },
    )
}

/// `f32` twin of [`dk_deform_boundary_rotations`].
///
/// # Safety
/// As [`dk_deform_boundary_normals`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_rotations_f32(
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    element_offsets: *const u32,
    element_offsets_len: usize,
    element_nodes: *const u32,
    element_nodes_len: usize,
    element_kinds: *const u8,
    element_kinds_len: usize,
    index_base: u32,
    scratch: *mut f32,
    scratch_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        undeformed,
        deformed,
        element_offsets,
        element_nodes,
        element_kinds,
        scratch,
        index_scratch,
        rotations,
    ) = unsafe {
        (
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            In::new(element_offsets, element_offsets_len),
            In::new(element_nodes, element_nodes_len),
            In::new(element_kinds, element_kinds_len),
            Out::new(scratch, scratch_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        Rotations {
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            elements: ElementsIn {
                offsets: element_offsets,
                offsets_len: element_offsets_len,
                nodes: element_nodes,
                nodes_len: element_nodes_len,
                kinds: element_kinds,
                kinds_len: element_kinds_len,
                index_base,
                index_scratch,
                index_scratch_len,
            },
            scratch,
            scratch_len,
            rotations,
            rotations_len,
        },
    )
}

fn rigid<T: Real>(q: In<'_, T>, rotations: Out<'_, T>, rotations_len: usize) -> dk_status {
    done((|| {
        let q = read_array::<T, 4>(q, 4).map(Quat::from_array)?;
        let r = quats_mut(rotations, rotations_len)?;
        rigid_rotations(q, r).map_err(dk_status::from)
    })())
}

/// Fills `rotations` (`rotations_len` scalars, a multiple of 4) with copies of the rigid
/// rotation `q` (4 scalars, normalised here): for a marker whose motion is known (the kernel's
/// `rigid_rotations`). Errors: `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (`q`),
/// `DK_ERR_LENGTH_MISMATCH`; on error `rotations` is unchanged.
///
/// # Safety
/// `q` points to 4 readable scalars; `rotations` is writable for `rotations_len` scalars and
/// does not overlap `q`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_rigid_rotations(
    q: *const f64,
    rotations: *mut f64,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, rotations) = unsafe { (In::new(q, 4), Out::new(rotations, rotations_len)) };
    rigid(q, rotations, rotations_len)
}

/// `f32` twin of [`dk_deform_rigid_rotations`].
///
/// # Safety
/// As [`dk_deform_rigid_rotations`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_rigid_rotations_f32(
    q: *const f32,
    rotations: *mut f32,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (q, rotations) = unsafe { (In::new(q, 4), Out::new(rotations, rotations_len)) };
    rigid(q, rotations, rotations_len)
}

struct Origin<'a, T> {
    undeformed: In<'a, T>,
    undeformed_len: usize,
    deformed: In<'a, T>,
    deformed_len: usize,
    origin_out: Out<'a, T>,
    origin_out_len: usize,
}

impl<'a, T: Real> ByDim for Origin<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let u = read_points::<T, D>(self.undeformed, self.undeformed_len)?;
        let d = read_points::<T, D>(self.deformed, self.deformed_len)?;
        if self.origin_out_len != D {
            return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
        }
        let o = output(self.origin_out, self.origin_out_len)?;
        let origin = boundary_origin(u, d).map_err(dk_status::from)?;
        write_optional(Some(o), origin);
        Ok(())
    }
}

/// The default rotation origin (the kernel's `boundary_origin`): the centroid of the
/// undeformed positions of the boundary points that move (`deformed != undeformed`), or of all
/// points when none moves. A far origin turns small rotation differences into large spurious
/// displacements; this one keeps the lever arms short.
///
/// `undeformed`, `deformed`: `B * dim` scalars each; `origin_out` receives `dim` scalars
/// (`origin_out_len` must be `dim`). Errors: length and pointer errors,
/// `DK_ERR_INVALID_PARAMETER` (no points), `DK_ERR_NON_FINITE`. On error `origin_out` is
/// unchanged.
///
/// # Safety
/// The inputs are readable for their lengths; `origin_out` is writable for `origin_out_len`
/// scalars and overlaps no input.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_origin(
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    origin_out: *mut f64,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (undeformed, deformed, origin_out) = unsafe {
        (
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Origin {
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            origin_out,
            origin_out_len,
        },
    )
}

/// `f32` twin of [`dk_deform_boundary_origin`].
///
/// # Safety
/// As [`dk_deform_boundary_origin`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_origin_f32(
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    origin_out: *mut f32,
    origin_out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (undeformed, deformed, origin_out) = unsafe {
        (
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            Out::new(origin_out, origin_out_len),
        )
    };
    by_dim(
        dim,
        Origin {
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            origin_out,
            origin_out_len,
        },
    )
}

struct Translations<'a, T> {
    origin: In<'a, T>,
    origin_len: usize,
    undeformed: In<'a, T>,
    undeformed_len: usize,
    deformed: In<'a, T>,
    deformed_len: usize,
    rotations: In<'a, T>,
    rotations_len: usize,
    translations: Out<'a, T>,
    translations_len: usize,
}

impl<'a, T: Real> ByDim for Translations<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let origin = read_array::<T, D>(self.origin, self.origin_len)?;
        let u = read_points::<T, D>(self.undeformed, self.undeformed_len)?;
        let d = read_points::<T, D>(self.deformed, self.deformed_len)?;
        let q = quats(self.rotations, self.rotations_len)?;
        let t = chunks_mut::<T, D>(self.translations, self.translations_len)?;
        boundary_translations(origin, u, d, q, t).map_err(dk_status::from)
    }
}

/// The boundary translations `Δ_i = (r_i^d − o) − Q_i (r_i^u − o) Q_i*` about `origin` (the
/// kernel's `boundary_translations`; Samareh's `Δ` with the undeformed point rotated), so
/// that `o + Δ_i + Q_i (r_i^u − o) Q_i*` is `r_i^d` up to rounding. Each rotation is
/// normalised first.
///
/// `origin`: `dim` scalars (`origin_len == dim`); `undeformed`, `deformed`: `B * dim`
/// scalars; `rotations`: `4 B`; `translations` receives `B * dim`. Errors: length and pointer
/// errors, `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a zero rotation). On error
/// `translations` is unchanged.
///
/// # Safety
/// The inputs are readable for their lengths; `translations` is writable for its length and
/// overlaps no input.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_translations(
    origin: *const f64,
    origin_len: usize,
    undeformed: *const f64,
    undeformed_len: usize,
    deformed: *const f64,
    deformed_len: usize,
    dim: u32,
    rotations: *const f64,
    rotations_len: usize,
    translations: *mut f64,
    translations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (origin, undeformed, deformed, rotations, translations) = unsafe {
        (
            In::new(origin, origin_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            In::new(rotations, rotations_len),
            Out::new(translations, translations_len),
        )
    };
    by_dim(
        dim,
        Translations {
            origin,
            origin_len,
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            rotations,
            rotations_len,
            translations,
            translations_len,
        },
    )
}

/// `f32` twin of [`dk_deform_boundary_translations`].
///
/// # Safety
/// As [`dk_deform_boundary_translations`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_boundary_translations_f32(
    origin: *const f32,
    origin_len: usize,
    undeformed: *const f32,
    undeformed_len: usize,
    deformed: *const f32,
    deformed_len: usize,
    dim: u32,
    rotations: *const f32,
    rotations_len: usize,
    translations: *mut f32,
    translations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (origin, undeformed, deformed, rotations, translations) = unsafe {
        (
            In::new(origin, origin_len),
            In::new(undeformed, undeformed_len),
            In::new(deformed, deformed_len),
            In::new(rotations, rotations_len),
            Out::new(translations, translations_len),
        )
    };
    by_dim(
        dim,
        Translations {
            origin,
            origin_len,
            undeformed,
            undeformed_len,
            deformed,
            deformed_len,
            rotations,
            rotations_len,
            translations,
            translations_len,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Building blocks: field level
// ---------------------------------------------------------------------------------------------

struct PropIdw<'a, T> {
    points: In<'a, T>,
    points_len: usize,
    boundary: In<'a, u32>,
    boundary_len: usize,
    index_base: u32,
    exponent: T,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
    translations: Out<'a, T>,
    translations_len: usize,
    rotations: Out<'a, T>,
    rotations_len: usize,
}

impl<'a, T: Real> ByDim for PropIdw<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let points = read_points::<T, D>(self.points, self.points_len)?;
        let boundary = input(self.boundary, self.boundary_len)?;
        let scratch = output(self.index_scratch, self.index_scratch_len)?;
        let (boundary, _) = rebase(boundary, self.index_base, scratch)?;
        let t = chunks_mut::<T, D>(self.translations, self.translations_len)?;
        let q = quats_mut(self.rotations, self.rotations_len)?;
        propagate_idw(points, boundary, self.exponent, t, q).map_err(dk_status::from)
    }
}

/// Inverse-distance weighting of boundary translations and rotations into the rest of the
/// mesh (the kernel's `propagate_idw`). On entry `translations` (`N * dim`) and `rotations`
/// (`4 N`) hold the boundary values at the nodes listed in `boundary`; on success every other
/// node holds `Δ = Σ w_k Δ_k / Σ w_k`, `Q = normalise(Σ w_k ±Q_k)` with `w_k = (d_min /
/// d_k)^exponent` (quaternions hemisphere-aligned to the nearest boundary node's). Boundary
/// entries are never written. Cost `O(N · B)`.
///
/// `boundary` lists `B` mesh nodes in `index_base` (0 or 1; with 1 they are converted into
/// `index_scratch`, `boundary_len` entries; NULL with 0 for `index_base` 0). `exponent` is
/// finite and positive. Errors: pointer and length errors, `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_INVALID_PARAMETER` (empty boundary, bad exponent),
/// `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (a zero boundary rotation). On error nothing is
/// written.
///
/// # Safety
/// Every pointer is valid for its length (`translations`, `rotations` for reads and writes);
/// the writable buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_idw(
    points: *const f64,
    points_len: usize,
    dim: u32,
    boundary: *const u32,
    boundary_len: usize,
    index_base: u32,
    exponent: f64,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, boundary, index_scratch, translations, rotations) = unsafe {
        (
            In::new(points, points_len),
            In::new(boundary, boundary_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        PropIdw {
            points,
            points_len,
            boundary,
            boundary_len,
            index_base,
            exponent,
            index_scratch,
            index_scratch_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
        },
    )
}

/// `f32` twin of [`dk_deform_propagate_idw`].
///
/// # Safety
/// As [`dk_deform_propagate_idw`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_idw_f32(
    points: *const f32,
    points_len: usize,
    dim: u32,
    boundary: *const u32,
    boundary_len: usize,
    index_base: u32,
    exponent: f32,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, boundary, index_scratch, translations, rotations) = unsafe {
        (
            In::new(points, points_len),
            In::new(boundary, boundary_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        PropIdw {
            points,
            points_len,
            boundary,
            boundary_len,
            index_base,
            exponent,
            index_scratch,
            index_scratch_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
        },
    )
}

/// Number of scalars the `scratch` of [`dk_deform_propagate_tfi`] and
/// [`dk_deform_displacement_tfi`] needs: `dim · ni nj nk` (the kernel's `tfi_scratch_len`).
/// Errors: `DK_ERR_BAD_DIMENSIONS` (block), `DK_ERR_INVALID_PARAMETER` (`dim`).
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_tfi_scratch_len(
    ni: usize,
    nj: usize,
    nk: usize,
    dim: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(
        len_out,
        block(ni, nj, nk).and_then(|b| match dim {
            2 => Ok(tfi_scratch_len::<2>(&b)),
            3 => Ok(tfi_scratch_len::<3>(&b)),
            _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
        }),
    )
}

struct PropTfi<'a, T> {
    dims: [usize; 3],
    directions: u32,
    points: In<'a, T>,
    points_len: usize,
    scratch: Out<'a, T>,
    scratch_len: usize,
    translations: Out<'a, T>,
    translations_len: usize,
    /// NULL with 0 and `displacement` set: plain displacement TFI.
    rotations: Out<'a, T>,
    rotations_len: usize,
    displacement: bool,
}

impl<'a, T: Real> ByDim for PropTfi<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let [ni, nj, nk] = self.dims;
        let (block, directions) = tfi_setup(ni, nj, nk, self.directions)?;
        let points = read_points::<T, D>(self.points, self.points_len)?;
        let scratch = output(self.scratch, self.scratch_len)?;
        let t = chunks_mut::<T, D>(self.translations, self.translations_len)?;
        if self.displacement {
            return displacement_tfi(&block, directions, points, t, scratch)
                .map_err(dk_status::from);
        }
        let q = quats_mut(self.rotations, self.rotations_len)?;
        propagate_tfi(&block, directions, points, t, q, scratch).map_err(dk_status::from)
    }
}

/// Transfinite interpolation of translations and rotations from the faces of a structured
/// block into its interior (the kernel's `propagate_tfi`): the boolean sum of the linear
/// projectors of the active `directions` (mask of [`DK_DIRECTION_I`], [`DK_DIRECTION_J`],
/// [`DK_DIRECTION_K`]) with Soni's arclength blending along the undeformed grid lines;
/// quaternions hemisphere-aligned before blending and renormalised after.
///
/// Values are read on the faces of the active directions and written everywhere else.
/// `points`: `ni nj nk · dim` scalars (`i` fastest, `nk = 1` in 2D); `translations`
/// (`N * dim`) and `rotations` (`4 N`) are updated in place; `scratch`:
/// [`dk_deform_propagate_tfi_scratch_len`] scalars. Errors: `DK_ERR_BAD_DIMENSIONS` (block),
/// `DK_ERR_INVALID_PARAMETER` (directions), length and pointer errors, `DK_ERR_NON_FINITE`,
/// `DK_ERR_ZERO_LENGTH` (a zero face rotation, or a blended rotation that cancels). On error
/// the values are unchanged.
///
/// # Safety
/// Every pointer is valid for its length (`translations`, `rotations` for reads and writes);
/// the writable buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_tfi(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    scratch: *mut f64,
    scratch_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, scratch, translations, rotations) = unsafe {
        (
            In::new(points, points_len),
            Out::new(scratch, scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        PropTfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            scratch,
            scratch_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            displacement: false,
        },
    )
}

/// `f32` twin of [`dk_deform_propagate_tfi`].
///
/// # Safety
/// As [`dk_deform_propagate_tfi`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_tfi_f32(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    scratch: *mut f32,
    scratch_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, scratch, translations, rotations) = unsafe {
        (
            In::new(points, points_len),
            Out::new(scratch, scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
        )
    };
    by_dim(
        dim,
        PropTfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            scratch,
            scratch_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            displacement: false,
        },
    )
}

/// Plain displacement TFI (the kernel's `displacement_tfi`, Samareh eq. 1; for comparison
/// with [`dk_deform_propagate_tfi`]): the same arclength-blended boolean sum applied to
/// displacements `δ = r^d − r^u` given on the faces of the active directions; `displacements`
/// (`N * dim`) is updated in place everywhere else. New points are `points + δ`. It reproduces
/// translations but shears cells under rotation. Errors as [`dk_deform_propagate_tfi`]; on
/// error `displacements` is unchanged.
///
/// # Safety
/// Every pointer is valid for its length (`displacements` for reads and writes); the writable
/// buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_displacement_tfi(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f64,
    points_len: usize,
    dim: u32,
    scratch: *mut f64,
    scratch_len: usize,
    displacements: *mut f64,
    displacements_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, scratch, displacements) = unsafe {
        (
            In::new(points, points_len),
            Out::new(scratch, scratch_len),
            Out::new(displacements, displacements_len),
        )
    };
    by_dim(
        dim,
        PropTfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            scratch,
            scratch_len,
            translations: displacements,
            translations_len: displacements_len,
            rotations: Out::null(),
            rotations_len: 0,
            displacement: true,
        },
    )
}

/// `f32` twin of [`dk_deform_displacement_tfi`].
///
/// # Safety
/// As [`dk_deform_displacement_tfi`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_displacement_tfi_f32(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: *const f32,
    points_len: usize,
    dim: u32,
    scratch: *mut f32,
    scratch_len: usize,
    displacements: *mut f32,
    displacements_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (points, scratch, displacements) = unsafe {
        (
            In::new(points, points_len),
            Out::new(scratch, scratch_len),
            Out::new(displacements, displacements_len),
        )
    };
    by_dim(
        dim,
        PropTfi {
            dims: [ni, nj, nk],
            directions,
            points,
            points_len,
            scratch,
            scratch_len,
            translations: displacements,
            translations_len: displacements_len,
            rotations: Out::null(),
            rotations_len: 0,
            displacement: true,
        },
    )
}

struct Update<'a, T> {
    origin: In<'a, T>,
    origin_len: usize,
    points: In<'a, T>,
    points_len: usize,
    translations: In<'a, T>,
    translations_len: usize,
    rotations: In<'a, T>,
    rotations_len: usize,
    boundary: In<'a, u32>,
    boundary_len: usize,
    index_base: u32,
    boundary_deformed: In<'a, T>,
    boundary_deformed_len: usize,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
    out: Out<'a, T>,
    out_len: usize,
}

impl<'a, T: Real> ByDim for Update<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let origin = read_array::<T, D>(self.origin, self.origin_len)?;
        let points = read_points::<T, D>(self.points, self.points_len)?;
        let t = chunks::<T, D>(self.translations, self.translations_len)?;
        let q = quats(self.rotations, self.rotations_len)?;
        let boundary = input(self.boundary, self.boundary_len)?;
        let bd = read_points::<T, D>(self.boundary_deformed, self.boundary_deformed_len)?;
        let scratch = output(self.index_scratch, self.index_scratch_len)?;
        let (boundary, _) = rebase(boundary, self.index_base, scratch)?;
        let out = chunks_mut::<T, D>(self.out, self.out_len)?;
        update_points(origin, points, t, q, boundary, bd, out).map_err(dk_status::from)
    }
}

/// Moves every mesh point by its translation and rotation (the kernel's `update_points`,
/// Samareh eq. 6 about `origin`): `out_i = o + (Δ_i + Q_i (points_i − o) Q_i*)`, each `Q_i`
/// normalised first; then every node listed in `boundary` is set to its `boundary_deformed`
/// position exactly (a node listed twice takes its last entry).
///
/// `origin`: `dim` scalars; `points`, `translations`, `out`: `N * dim`; `rotations`: `4 N`;
/// `boundary`: `B` mesh nodes in `index_base` (with 1 converted into `index_scratch`,
/// `boundary_len` entries); `boundary_deformed`: `B * dim`. Errors: length and pointer errors,
/// `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_INDEX_OUT_OF_RANGE`, `DK_ERR_NON_FINITE`,
/// `DK_ERR_ZERO_LENGTH` (a zero rotation). On error `out` is unchanged.
///
/// # Safety
/// Every pointer is valid for its length; `out` and `index_scratch` overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_update_points(
    origin: *const f64,
    origin_len: usize,
    points: *const f64,
    points_len: usize,
    dim: u32,
    translations: *const f64,
    translations_len: usize,
    rotations: *const f64,
    rotations_len: usize,
    boundary: *const u32,
    boundary_len: usize,
    index_base: u32,
    boundary_deformed: *const f64,
    boundary_deformed_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    out: *mut f64,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (origin, points, translations, rotations, boundary, boundary_deformed, index_scratch, out) = unsafe {
        (
            In::new(origin, origin_len),
            In::new(points, points_len),
            In::new(translations, translations_len),
            In::new(rotations, rotations_len),
            In::new(boundary, boundary_len),
            In::new(boundary_deformed, boundary_deformed_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(out, out_len),
        )
    };
    by_dim(
        dim,
        Update {
            origin,
            origin_len,
            points,
            points_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            boundary,
            boundary_len,
            index_base,
            boundary_deformed,
            boundary_deformed_len,
            index_scratch,
            index_scratch_len,
            out,
            out_len,
        },
    )
}

/// `f32` twin of [`dk_deform_update_points`].
///
/// # Safety
/// As [`dk_deform_update_points`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_update_points_f32(
    origin: *const f32,
    origin_len: usize,
    points: *const f32,
    points_len: usize,
    dim: u32,
    translations: *const f32,
    translations_len: usize,
    rotations: *const f32,
    rotations_len: usize,
    boundary: *const u32,
    boundary_len: usize,
    index_base: u32,
    boundary_deformed: *const f32,
    boundary_deformed_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    out: *mut f32,
    out_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (origin, points, translations, rotations, boundary, boundary_deformed, index_scratch, out) = unsafe {
        (
            In::new(origin, origin_len),
            In::new(points, points_len),
            In::new(translations, translations_len),
            In::new(rotations, rotations_len),
            In::new(boundary, boundary_len),
            In::new(boundary_deformed, boundary_deformed_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(out, out_len),
        )
    };
    by_dim(
        dim,
        Update {
            origin,
            origin_len,
            points,
            points_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            boundary,
            boundary_len,
            index_base,
            boundary_deformed,
            boundary_deformed_len,
            index_scratch,
            index_scratch_len,
            out,
            out_len,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Renumbering
// ---------------------------------------------------------------------------------------------

/// Number of `uint32_t` entries the `scratch` of [`dk_deform_localize_nodes`] needs:
/// `node_count` with `index_base` 0, `node_count + boundary_len + global_len` with 1.
/// Errors: `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_TOO_LARGE` (overflow).
///
/// # Safety
/// `len_out` points to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_localize_nodes_scratch_len(
    node_count: usize,
    boundary_len: usize,
    global_len: usize,
    index_base: u32,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let len_out = unsafe { Out::new(len_out, 1) };
    len_status(
        len_out,
        index_need(index_base, &[boundary_len, global_len]).and_then(|n| {
            n.checked_add(localize_nodes_scratch_len(node_count))
                .ok_or(dk_status::DK_ERR_TOO_LARGE)
        }),
    )
}

/// Rewrites mesh node numbers as positions in `boundary` (the kernel's `localize_nodes`):
/// `local[e] = k` where `boundary[k] == global[e]`. Boundary elements usually come in mesh
/// numbering (a marker's faces); the boundary-level functions and
/// [`dk_boundary_motion::element_nodes`] want positions in the boundary list. Pass a marker's
/// element node array as `global`; use `local` with the same offsets and kinds.
///
/// `boundary` (`B` distinct mesh nodes) and `global` are read in `index_base` (0 or 1), and
/// `local` is written in the same base (positions `index_base .. B − 1 + index_base`), so a
/// Fortran caller passes and gets 1-based arrays. `scratch` needs
/// [`dk_deform_localize_nodes_scratch_len`] entries. Errors: `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_INDEX_OUT_OF_RANGE` (an entry `>= node_count`, or an element node not in
/// `boundary`), `DK_ERR_DUPLICATE_NODE`, `DK_ERR_LENGTH_MISMATCH` (`local_len != global_len`),
/// `DK_ERR_BUFFER_TOO_SMALL`, `DK_ERR_TOO_LARGE`. On error `local` is unchanged.
///
/// # Safety
/// `boundary`, `global` are readable for their lengths; `scratch`, `local` are writable for
/// theirs; the writable buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_localize_nodes(
    node_count: usize,
    boundary: *const u32,
    boundary_len: usize,
    global: *const u32,
    global_len: usize,
    index_base: u32,
    scratch: *mut u32,
    scratch_len: usize,
    local: *mut u32,
    local_len: usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (boundary, global, scratch, local) = unsafe {
        (
            In::new(boundary, boundary_len),
            In::new(global, global_len),
            Out::new(scratch, scratch_len),
            Out::new(local, local_len),
        )
    };
    done((|| {
        check_base(index_base)?;
        let b = input(boundary, boundary_len)?;
        let g = input(global, global_len)?;
        let s = output(scratch, scratch_len)?;
        let l = output(local, local_len)?;
        if u32::try_from(b.len()).is_err() {
            return Err(dk_status::DK_ERR_TOO_LARGE);
        }
        let (b, s) = rebase(b, index_base, s)?;
        let (g, s) = rebase(g, index_base, s)?;
        localize_nodes(node_count, b, g, s, l).map_err(dk_status::from)?;
        // Positions are < B <= u32::MAX (checked above), so adding a base of 0 or 1 cannot
        // overflow; wrapping_add keeps the arithmetic visibly panic-free.
        for x in l.iter_mut() {
            *x = x.wrapping_add(index_base);
        }
        Ok(())
    })())
}

// ---------------------------------------------------------------------------------------------
// Springs (options and report types from the spring module)
// ---------------------------------------------------------------------------------------------

/// Number of scalars of the packed `values` workspace of the spring propagation:
/// `propagate_spring_scratch_len` items of `dim + 4` scalars.
fn spring_values_len(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
) -> Result<usize, dk_status> {
    let o = read_one(options)?;
    let method = o.method::<f64>()?;
    let v = match dim {
        2 => 6usize,
        3 => 7,
        _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
    };
    // The kernel's item count saturates; a saturated count is too large to allocate anyway.
    let items = propagate_spring_scratch_len(&method, node_count);
    if items == usize::MAX {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    mul_len(items, v)
}

/// The arguments describing a spring system (0-based CSR graph, per-edge stiffness, fixed
/// mask); validated into a `SpringSystem` with a `node_count` slice of index scratch.
#[derive(Clone, Copy)]
struct SystemIn<'a, T> {
    offsets: In<'a, u32>,
    offsets_len: usize,
    targets: In<'a, u32>,
    targets_len: usize,
    stiffness: In<'a, T>,
    stiffness_len: usize,
    fixed: In<'a, u8>,
    fixed_len: usize,
}

impl<'a, T: Real> SystemIn<'a, T> {
    fn build(&self, scratch: &mut [u32]) -> Result<SpringSystem<'a, T>, dk_status> {
        let k = input(self.stiffness, self.stiffness_len)?;
        let f = input(self.fixed, self.fixed_len)?;
        // All four arrays are NULL-checked before the graph is validated (unlike
        // `dk_spring_*`, which validate the graph first).
        let g = graph(
            self.offsets,
            self.offsets_len,
            self.targets,
            self.targets_len,
        )?;
        SpringSystem::new(g, k, f, scratch).map_err(dk_status::from)
    }
}

/// Sizes for [`dk_deform_spring`]: `*scratch_len_out` scalars of `scratch` (as
/// [`dk_deform_idw_scratch_len`]) and `*values_len_out` scalars of the packed `values`
/// workspace (the kernel's `propagate_spring_scratch_len` items of `dim + 4` scalars; depends
/// on `options->method`). The same for both precisions. Errors: `DK_ERR_INVALID_PARAMETER`
/// (`dim`, method, or the two outputs are one pointer), `DK_ERR_TOO_LARGE`; nothing is
/// written on error.
///
/// # Safety
/// `options` points to one readable `dk_spring_solve_options`; `scratch_len_out` and
/// `values_len_out` each to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_spring_scratch_len(
    node_count: usize,
    boundary_len: usize,
    dim: u32,
    options: *const dk_spring_solve_options,
    scratch_len_out: *mut usize,
    values_len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (options, scratch_len_out, values_len_out) = unsafe {
        (
            In::new(options, 1),
            Out::new(scratch_len_out, 1),
            Out::new(values_len_out, 1),
        )
    };
    done((|| {
        let values = spring_values_len(node_count, dim, options)?;
        if scratch_len_out.same_address(&values_len_out) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        let scratch = match dim {
            2 => deform_spring_scratch_len::<2>(node_count, boundary_len),
            _ => deform_spring_scratch_len::<3>(node_count, boundary_len),
        };
        let a = out_one(scratch_len_out)?;
        let b = out_one(values_len_out)?;
        *a = scratch;
        *b = values;
        Ok(())
    })())
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

/// Number of `uint32_t` entries the `index_scratch` of [`dk_deform_spring`] needs:
/// [`dk_boundary_motion_index_scratch_len`] plus `node_count` (the spring system's anchoring
/// check).
///
/// # Safety
/// `motion` points to one readable `dk_boundary_motion`; `len_out` to one writable `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_spring_index_scratch_len(
    motion: *const dk_boundary_motion,
    node_count: usize,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (motion, len_out) = unsafe { (In::new(motion, 1), Out::new(len_out, 1)) };
    spring_index_len(motion, node_count, len_out)
}

/// `f32` twin of [`dk_deform_spring_index_scratch_len`].
///
/// # Safety
/// As [`dk_deform_spring_index_scratch_len`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_spring_index_scratch_len_f32(
    motion: *const dk_boundary_motion_f32,
    node_count: usize,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (motion, len_out) = unsafe { (In::new(motion, 1), Out::new(len_out, 1)) };
    spring_index_len(motion, node_count, len_out)
}

struct Spring<'a, M: MotionC> {
    points: In<'a, M::T>,
    points_len: usize,
    motion: In<'a, M>,
    system: SystemIn<'a, M::T>,
    options: In<'a, dk_spring_solve_options>,
    values: Out<'a, M::T>,
    values_len: usize,
    bufs: PipelineOut<'a, M::T>,
    report: Out<'a, dk_spring_solve_report>,
}

impl<'a, M: MotionC> ByDim for Spring<'a, M> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let o = read_one(self.options)?;
        let method = o.method::<M::T>()?;
        let stop = o.stopping::<M::T>();
        let raw = read_raw(self.motion)?;
        let points = read_points::<M::T, D>(self.points, self.points_len)?;
        let b = self.bufs.borrow::<D>()?;
        // Only whole items of the values workspace are used.
        let values_len = self.values_len - self.values_len % V;
        let values = chunks_mut::<M::T, V>(self.values, values_len)?;
        let report = out_one(self.report)?;
        let (motion, rest) = raw.view::<D>(b.index_scratch)?;
        let sys = self.system.build(rest)?;
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
}

/// The whole quaternion deformation with linear-spring propagation (the kernel's
/// `deform_spring`, Samareh's unstructured variant): boundary rotations and translations as in
/// [`dk_deform_idw`], then one linear-spring solve for `Δ` and the quaternion components
/// together (`dim + 4` values per node) with `options` (see `dk_spring_solve_options`; the
/// f32 twin rounds its tolerances to `float`), then the update.
///
/// The spring system is a 0-based CSR graph (`offsets`, `targets` from `dk_graph_from_*`),
/// one positive stiffness per directed edge (symmetric, e.g. from
/// `dk_spring_batina_stiffness`) and a fixed mask (one byte per node, nonzero = fixed) that
/// must mark exactly the nodes of `motion->nodes`. `scratch`: the first length of
/// [`dk_deform_spring_scratch_len`]; `values`: the second (a workspace); `index_scratch`:
/// [`dk_deform_spring_index_scratch_len`] entries. `*report` receives the solver's report:
/// `out` is written even when the solver did not converge (status `DK_OK`, `converged` false).
///
/// Errors: those of [`dk_deform_idw`] (but not the exponent), the spring system's
/// (`DK_ERR_NOT_SYMMETRIC`, `DK_ERR_NON_POSITIVE`, `DK_ERR_UNANCHORED`, graph errors),
/// `DK_ERR_INVALID_PARAMETER` (method, preconditioner, `omega`, tolerances, a fixed mask that
/// differs from the boundary), `DK_ERR_SINGULAR_SYSTEM` (CG breakdown), `DK_ERR_ZERO_LENGTH`
/// (a solved quaternion cancels). On error `out`, `origin_out` and `*report` are unchanged;
/// `translations`, `rotations`, `scratch`, `values` are workspaces (solver errors are
/// detected after the boundary entries of `translations` and `rotations` were written).
///
/// # Safety
/// As [`dk_deform_idw`]; also the graph, stiffness and fixed arrays are readable for their
/// lengths, `options` points to one readable struct, `values` is writable for `values_len`
/// scalars and `report` points to one writable report, none overlapping another buffer.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_spring(
    points: *const f64,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion,
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    scratch: *mut f64,
    scratch_len: usize,
    values: *mut f64,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
    out: *mut f64,
    out_len: usize,
    origin_out: *mut f64,
    origin_out_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        points,
        motion,
        offsets,
        targets,
        stiffness,
        fixed,
        options,
        scratch,
        values,
        index_scratch,
        translations,
        rotations,
        out,
        origin_out,
        report,
    ) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(scratch, scratch_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
            Out::new(report, 1),
        )
    };
    by_dim(
        dim,
        Spring {
            points,
            points_len,
            motion,
            system: SystemIn {
                offsets,
                offsets_len,
                targets,
                targets_len,
                stiffness,
                stiffness_len,
                fixed,
                fixed_len,
            },
            options,
            values,
            values_len,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
            report,
        },
    )
}

/// `f32` twin of [`dk_deform_spring`] (the options' tolerances and `omega` are rounded to
/// `float`; the report's values are widened exactly).
///
/// # Safety
/// As [`dk_deform_spring`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_spring_f32(
    points: *const f32,
    points_len: usize,
    dim: u32,
    motion: *const dk_boundary_motion_f32,
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    scratch: *mut f32,
    scratch_len: usize,
    values: *mut f32,
    values_len: usize,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
    out: *mut f32,
    out_len: usize,
    origin_out: *mut f32,
    origin_out_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        points,
        motion,
        offsets,
        targets,
        stiffness,
        fixed,
        options,
        scratch,
        values,
        index_scratch,
        translations,
        rotations,
        out,
        origin_out,
        report,
    ) = unsafe {
        (
            In::new(points, points_len),
            In::new(motion, 1),
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(scratch, scratch_len),
            Out::new(values, values_len),
            Out::new(index_scratch, index_scratch_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(out, out_len),
            Out::new(origin_out, origin_out_len),
            Out::new(report, 1),
        )
    };
    by_dim(
        dim,
        Spring {
            points,
            points_len,
            motion,
            system: SystemIn {
                offsets,
                offsets_len,
                targets,
                targets_len,
                stiffness,
                stiffness_len,
                fixed,
                fixed_len,
            },
            options,
            values,
            values_len,
            bufs: PipelineOut {
                scratch,
                scratch_len,
                index_scratch,
                index_scratch_len,
                translations,
                translations_len,
                rotations,
                rotations_len,
                out,
                out_len,
                origin_out,
                origin_out_len,
            },
            report,
        },
    )
}

/// Number of scalars the packed `values` workspace of [`dk_deform_propagate_spring`] needs:
/// the kernel's `propagate_spring_scratch_len(method, node_count)` items of `dim + 4`
/// scalars. Errors: `DK_ERR_INVALID_PARAMETER` (`dim`, method), `DK_ERR_TOO_LARGE`.
///
/// # Safety
/// `options` points to one readable `dk_spring_solve_options`; `len_out` to one writable
/// `size_t`.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_spring_scratch_len(
    node_count: usize,
    dim: u32,
    options: *const dk_spring_solve_options,
    len_out: *mut usize,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (options, len_out) = unsafe { (In::new(options, 1), Out::new(len_out, 1)) };
    len_status(len_out, spring_values_len(node_count, dim, options))
}

struct PropSpring<'a, T> {
    system: SystemIn<'a, T>,
    options: In<'a, dk_spring_solve_options>,
    index_scratch: Out<'a, u32>,
    index_scratch_len: usize,
    values: Out<'a, T>,
    values_len: usize,
    translations: Out<'a, T>,
    translations_len: usize,
    rotations: Out<'a, T>,
    rotations_len: usize,
    report: Out<'a, dk_spring_solve_report>,
}

impl<'a, T: Real> ByDim for PropSpring<'a, T> {
    fn run<const D: usize, const V: usize>(self) -> Result<(), dk_status> {
        let o = read_one(self.options)?;
        let method = o.method::<T>()?;
        let stop = o.stopping::<T>();
        let s = output(self.index_scratch, self.index_scratch_len)?;
        let values_len = self.values_len - self.values_len % V;
        let values = chunks_mut::<T, V>(self.values, values_len)?;
        let t = chunks_mut::<T, D>(self.translations, self.translations_len)?;
        let q = quats_mut(self.rotations, self.rotations_len)?;
        let report = out_one(self.report)?;
        let sys = self.system.build(s)?;
        let rep = propagate_spring(&sys, method, &stop, t, q, values).map_err(dk_status::from)?;
        *report = dk_spring_solve_report::of(rep);
        Ok(())
    }
}

/// Propagates translations and rotations through a linear spring network (the kernel's
/// `propagate_spring`): `Δ` and the four quaternion components are packed into one field of
/// `dim + 4` values per node and solved together with `options`. On entry `translations`
/// (`N * dim`) and `rotations` (`4 N`) hold the boundary values at the fixed nodes (nonzero
/// bytes of `fixed`); fixed quaternions are hemisphere-aligned to the first fixed node's,
/// free nodes start from the mean of the fixed values, and every free quaternion is
/// renormalised after the solve. Fixed entries are never written.
///
/// The system is as for [`dk_deform_spring`] (any fixed mask with at least one fixed node);
/// `index_scratch` needs `node_count` entries (`dk_spring_index_scratch_len`); `values`:
/// [`dk_deform_propagate_spring_scratch_len`] scalars (a workspace). `*report` receives the
/// solver report (non-convergence is `DK_OK` with `converged` false).
///
/// Errors: the system's and solver's errors (as [`dk_deform_spring`]), length and pointer
/// errors, `DK_ERR_INVALID_PARAMETER` (no fixed node, options), `DK_ERR_NON_FINITE`,
/// `DK_ERR_ZERO_LENGTH`. On error `translations`, `rotations` and `*report` are unchanged.
///
/// # Safety
/// Every pointer is valid for its length (`translations`, `rotations` for reads and writes);
/// `options` points to one readable struct and `report` to one writable report; the writable
/// buffers overlap nothing else.
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_spring(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f64,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    dim: u32,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    values: *mut f64,
    values_len: usize,
    translations: *mut f64,
    translations_len: usize,
    rotations: *mut f64,
    rotations_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        options,
        index_scratch,
        values,
        translations,
        rotations,
        report,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(index_scratch, index_scratch_len),
            Out::new(values, values_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(report, 1),
        )
    };
    by_dim(
        dim,
        PropSpring {
            system: SystemIn {
                offsets,
                offsets_len,
                targets,
                targets_len,
                stiffness,
                stiffness_len,
                fixed,
                fixed_len,
            },
            options,
            index_scratch,
            index_scratch_len,
            values,
            values_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            report,
        },
    )
}

/// `f32` twin of [`dk_deform_propagate_spring`].
///
/// # Safety
/// As [`dk_deform_propagate_spring`].
#[cfg_attr(feature = "export-symbols", no_mangle)]
pub unsafe extern "C" fn dk_deform_propagate_spring_f32(
    offsets: *const u32,
    offsets_len: usize,
    targets: *const u32,
    targets_len: usize,
    stiffness: *const f32,
    stiffness_len: usize,
    fixed: *const u8,
    fixed_len: usize,
    options: *const dk_spring_solve_options,
    dim: u32,
    index_scratch: *mut u32,
    index_scratch_len: usize,
    values: *mut f32,
    values_len: usize,
    translations: *mut f32,
    translations_len: usize,
    rotations: *mut f32,
    rotations_len: usize,
    report: *mut dk_spring_solve_report,
) -> dk_status {
    // SAFETY: the contract under `# Safety` above: each pointer is NULL or valid for the
    // length given here (its `_len` argument, one struct or value, a 3-vector or quaternion).
    let (
        offsets,
        targets,
        stiffness,
        fixed,
        options,
        index_scratch,
        values,
        translations,
        rotations,
        report,
    ) = unsafe {
        (
            In::new(offsets, offsets_len),
            In::new(targets, targets_len),
            In::new(stiffness, stiffness_len),
            In::new(fixed, fixed_len),
            In::new(options, 1),
            Out::new(index_scratch, index_scratch_len),
            Out::new(values, values_len),
            Out::new(translations, translations_len),
            Out::new(rotations, rotations_len),
            Out::new(report, 1),
        )
    };
    by_dim(
        dim,
        PropSpring {
            system: SystemIn {
                offsets,
                offsets_len,
                targets,
                targets_len,
                stiffness,
                stiffness_len,
                fixed,
                fixed_len,
            },
            options,
            index_scratch,
            index_scratch_len,
            values,
            values_len,
            translations,
            translations_len,
            rotations,
            rotations_len,
            report,
        },
    )
}
