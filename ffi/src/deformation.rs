//! Quaternion mesh deformation (Samareh, NASA TM-2002-211646): `dk_deform_*`.
//!
//! The one-call pipelines [`dk_deform_idw`], [`dk_deform_tfi`] and [`dk_deform_spring`] take
//! the prescribed boundary motion as a [`dk_boundary_motion`] (f64) or
//! [`dk_boundary_motion_f32`]; the building blocks (`dk_deform_boundary_normals`, …,
//! `dk_deform_update_points`, `dk_deform_localize_nodes`) expose each step of the kernel's
//! `deform_kernel::quaternion` module on its own, for callers who mix them.
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
#![allow(unsafe_code)] // a parameter struct's arrays become `In`/`Out` tokens (`In::new`) here.

use deform_kernel::quaternion::{
    boundary_normals, boundary_normals_scratch_len, boundary_origin, boundary_rotations,
    boundary_rotations_scratch_len, boundary_translations, deform_idw, deform_idw_scratch_len,
    deform_spring, deform_spring_scratch_len, deform_tfi, deform_tfi_scratch_len, displacement_tfi,
    localize_nodes, localize_nodes_scratch_len, propagate_idw, propagate_spring,
    propagate_spring_scratch_len, propagate_tfi, rigid_rotations, tfi_scratch_len, update_points,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::SpringSystem;
use deform_kernel::{Block, Cells, Directions, Quat, Real};
use deform_kernel_ffi_export::export;

use crate::args::{
    assert_layout, block, check_base, index_need, read_array, read_one, read_points, rebase,
    write_len, write_one, Dim,
};
use crate::graph::{dk_cells, CellsIn};
use crate::slice::{chunks, chunks_mut, input, out_one, output, quats, quats_mut, In, Out};
use crate::spring::{dk_spring_solve_options, dk_spring_solve_report, DkSpringSystem, SystemC};
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

/// The prescribed motion of a mesh boundary, double precision (the kernel's
/// `BoundaryMotion`): which mesh nodes move where, how they turn, and about which origin.
/// Fill it with [`dk_boundary_motion_default`] first, then set the fields you need.
///
/// The arrays are borrowed for the duration of the call that receives the struct; the library
/// never keeps the pointers.
#[export(twin = dk_boundary_motion)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct DkBoundaryMotion<T> {
    /// Mesh node of each of the `B` boundary points, in `index_base`, all distinct. Include
    /// fixed boundaries (far field) with `deformed` equal to their position: they anchor the
    /// propagation.
    pub nodes: *const u32,
    /// Number of entries of `nodes` (`B`, at least 1).
    pub nodes_len: usize,
    /// Deformed position of each boundary point (`B * dim` scalars); reproduced exactly in
    /// the output.
    pub deformed: *const T,
    /// Number of scalars in `deformed` (`B * dim`).
    pub deformed_len: usize,
    /// Optional boundary elements (every array NULL with length 0 for none), in `index_base`,
    /// their nodes as positions `0..B` in `nodes` (not mesh nodes; see
    /// [`dk_deform_localize_nodes`]): segments (VTK 3) in 2D, triangles/quadrilaterals (5, 9)
    /// in 3D, consistently ordered.
    pub elements: dk_cells,
    /// With [`DK_ROTATIONS_PER_NODE`]: one quaternion `(w, x, y, z)` per boundary node, in
    /// `nodes` order (`4 * B` scalars). Ignored otherwise.
    pub node_rotations: *const T,
    /// Number of scalars in `node_rotations`.
    pub node_rotations_len: usize,
    /// With [`DK_ROTATIONS_RIGID`]: the rotation `(w, x, y, z)` of the moving boundary nodes
    /// (normalised by the library). Ignored otherwise.
    pub rigid_rotation: [T; 4],
    /// The rotation origin, used when `has_origin` is nonzero (the first `dim` entries).
    pub origin: [T; 3],
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
    DkBoundaryMotion<f64>, 168;
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
pub(crate) fn write_optional<T: Real, const D: usize>(slot: Option<&mut [T]>, v: [T; D]) {
    if let Some(s) = slot {
        for (d, x) in s.iter_mut().zip(v) {
            *d = x;
        }
    }
}

/// The precision-independent view of a [`dk_boundary_motion`] or [`dk_boundary_motion_f32`].
#[derive(Clone, Copy)]
pub(crate) struct RawMotion<'a, T> {
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
pub(crate) trait MotionC: Copy {
    type T: Real;
    /// Reads the struct and wraps its arrays in tokens of the struct's lifetime.
    fn raw(p: In<'_, Self>) -> Result<RawMotion<'_, Self::T>, dk_status>;
    fn default_value() -> Self;
}

impl<T: Real> MotionC for DkBoundaryMotion<T> {
    type T = T;
    fn raw(p: In<'_, Self>) -> Result<RawMotion<'_, T>, dk_status> {
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
            rigid_rotation: [T::ONE, T::ZERO, T::ZERO, T::ZERO],
            origin: [T::ZERO; 3],
            index_base: 0,
            rotation_source: DK_ROTATIONS_SHAPE,
            has_origin: 0,
        }
    }
}

/// Reads the caller's motion struct.
pub(crate) fn read_raw<M: MotionC>(motion: In<'_, M>) -> Result<RawMotion<'_, M::T>, dk_status> {
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
    pub(crate) fn view<const D: usize>(
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
pub(crate) fn tfi_setup(
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

// ---------------------------------------------------------------------------------------------
// Pipelines and building blocks
// ---------------------------------------------------------------------------------------------

/// The borrowed pipeline buffers (validated pointers).
pub(crate) struct PipelineBufs<'a, T, const D: usize> {
    pub(crate) scratch: &'a mut [T],
    pub(crate) index_scratch: &'a mut [u32],
    pub(crate) translations: &'a mut [[T; D]],
    pub(crate) rotations: &'a mut [Quat<T>],
    pub(crate) out: &'a mut [[T; D]],
    pub(crate) origin_out: Option<&'a mut [T]>,
}

/// Borrows the output buffers every pipeline shares.
pub(crate) fn pipeline<'a, T: Real, const D: usize>(
    [scratch, translations, rotations, out, origin_out]: [Out<'a, T>; 5],
    index_scratch: Out<'a, u32>,
) -> Result<PipelineBufs<'a, T, D>, dk_status> {
    Ok(PipelineBufs {
        scratch: output(scratch)?,
        index_scratch: output(index_scratch)?,
        translations: chunks_mut::<T, D>(translations)?,
        rotations: quats_mut(rotations)?,
        out: chunks_mut::<T, D>(out)?,
        origin_out: optional_out::<T, D>(origin_out)?,
    })
}

/// A one-call pipeline: reads the motion and the points, borrows the buffers every pipeline
/// shares, runs `deform` (the kernel's pipeline on the points, the motion, the translations,
/// rotations, scratch and output) and writes the origin it returns.
fn run_pipeline<T: Real, const D: usize>(
    points: In<'_, T>,
    motion: In<'_, DkBoundaryMotion<T>>,
    outs: [Out<'_, T>; 5],
    index_scratch: Out<'_, u32>,
    deform: impl FnOnce(
        &[[T; D]],
        &BoundaryMotion<'_, T, D>,
        &mut [[T; D]],
        &mut [Quat<T>],
        &mut [T],
        &mut [[T; D]],
    ) -> deform_kernel::Result<[T; D]>,
) -> Result<(), dk_status> {
    let raw = read_raw(motion)?;
    let points = read_points::<T, D>(points)?;
    let b = pipeline::<T, D>(outs, index_scratch)?;
    let (motion, _) = raw.view::<D>(b.index_scratch)?;
    let origin = deform(
        points,
        &motion,
        b.translations,
        b.rotations,
        b.scratch,
        b.out,
    )?;
    write_optional(b.origin_out, origin);
    Ok(())
}

/// A required boundary element list over `boundary_len` points (offsets and nodes in
/// `index_base`; no elements is a length mismatch).
fn required_elements<'a>(
    elements: In<'a, dk_cells>,
    index_base: u32,
    index_scratch: Out<'a, u32>,
    boundary_len: usize,
) -> Result<Cells<'a>, dk_status> {
    let scratch = output(index_scratch)?;
    let elements = CellsIn::read(elements)?;
    read_required_elements(boundary_len, elements, index_base, scratch)
}

/// TFI of the translations and `rotations`, or of plain displacements without them.
fn propagate_tfi_for_dim<T: Real, const D: usize>(
    ([ni, nj, nk], directions, points): ([usize; 3], u32, In<'_, T>),
    scratch: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Option<Out<'_, T>>,
) -> Result<(), dk_status> {
    let (block, directions) = tfi_setup(ni, nj, nk, directions)?;
    let points = read_points::<T, D>(points)?;
    let scratch = output(scratch)?;
    let t = chunks_mut::<T, D>(translations)?;
    let Some(rotations) = rotations else {
        return Ok(displacement_tfi(&block, directions, points, t, scratch)?);
    };
    let q = quats_mut(rotations)?;
    Ok(propagate_tfi(&block, directions, points, t, q, scratch)?)
}

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

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// Fills `*out` with an empty motion: no nodes, no elements, `rotation_source`
/// [`DK_ROTATIONS_SHAPE`], identity `rigid_rotation` `(1, 0, 0, 0)`, zero `origin` with
/// `has_origin` 0 (default origin), `index_base` 0. Set the fields you need afterwards.
#[export(twin, out[1])]
pub(crate) fn dk_boundary_motion_default<T: Real>(
    out: Out<'_, DkBoundaryMotion<T>>,
) -> Result<(), dk_status> {
    write_one(out, DkBoundaryMotion::default_value())
}

/// Number of `uint32_t` entries the `index_scratch` of a pipeline needs for `*motion`:
/// `nodes_len + elements.offsets_len + elements.nodes_len` with `index_base` 1, 0 with
/// `index_base` 0 (then `index_scratch` may be NULL). [`dk_deform_spring`] needs `node_count`
/// more (see [`dk_deform_spring_index_scratch_len`]). Errors: `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_TOO_LARGE` (the sum overflows).
#[export(twin, motion[1], len_out[1])]
pub(crate) fn dk_boundary_motion_index_scratch_len<T: Real>(
    motion: In<'_, DkBoundaryMotion<T>>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    write_len(len_out, read_raw(motion)?.index_need()?)
}

/// Number of scalars the `scratch` of [`dk_deform_idw`] (and [`dk_deform_spring`]) needs for
/// `node_count` mesh nodes and `boundary_len` boundary nodes in dimension `dim` (2 or 3):
/// `max(node_count, 3 boundary_len)` in 2D, `max(node_count, 13 boundary_len)` in 3D (the
/// kernel's `deform_idw_scratch_len`). The same for both precisions.
#[export(len_out[1])]
pub(crate) fn dk_deform_idw_scratch_len<const D: usize>(
    node_count: usize,
    boundary_len: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let len = deform_idw_scratch_len::<D>(node_count, boundary_len);
    write_len(len_out, len)
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
#[export(twin, motion[1])]
pub(crate) fn dk_deform_idw<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    exponent: T,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
    origin_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let outs = [scratch, translations, rotations, out, origin_out];
    run_pipeline::<T, D>(points, motion, outs, index_scratch, |p, m, t, q, s, o| {
        deform_idw(p, m, exponent, t, q, s, o)
    })
}

/// Number of scalars the `scratch` of [`dk_deform_tfi`] needs for a `ni × nj × nk` block with
/// `boundary_len` boundary nodes in dimension `dim`: `max(dim · ni nj nk, boundary rotation
/// scratch)` (the kernel's `deform_tfi_scratch_len`). Errors: `DK_ERR_BAD_DIMENSIONS` (a zero
/// dimension, too many points), `DK_ERR_INVALID_PARAMETER` (`dim` not 2 or 3).
#[export(len_out[1])]
pub(crate) fn dk_deform_tfi_scratch_len<const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    boundary_len: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    write_len(len_out, deform_tfi_scratch_len::<D>(&b, boundary_len))
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
#[export(twin, motion[1])]
pub(crate) fn dk_deform_tfi<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
    origin_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let (block, directions) = tfi_setup(ni, nj, nk, directions)?;
    let outs = [scratch, translations, rotations, out, origin_out];
    run_pipeline::<T, D>(points, motion, outs, index_scratch, |p, m, t, q, s, o| {
        deform_tfi(&block, directions, p, m, t, q, s, o)
    })
}

/// Number of scalars the `scratch` of [`dk_deform_boundary_normals`] needs:
/// `3 * boundary_len` (saturating).
#[export(len_out[1])]
pub(crate) fn dk_deform_boundary_normals_scratch_len(
    boundary_len: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    write_len(len_out, boundary_normals_scratch_len(boundary_len))
}

/// Area-weighted unit normals of a boundary at its nodes (the kernel's `boundary_normals`;
/// Samareh's `n`, eq. 5): each node's normal is the normalised sum of the raw normals of its
/// elements (segment length in 2D, twice the face area in 3D). In 2D the normal of a segment
/// `a → b` is `(t_y, −t_x)` (outward for a counter-clockwise loop); in 3D the right-hand rule.
///
/// `points` holds the `B` boundary points (`B * dim` scalars, `dim` 2 or 3); the elements
/// (offsets, nodes as positions `0..B`, VTK kinds: segments in 2D, triangles/quads in 3D) are
/// read in `index_base`, converted into `index_scratch` with `index_base` 1
/// (`elements->offsets_len + elements->nodes_len` entries; NULL with 0 for `index_base` 0).
/// `scratch` needs [`dk_deform_boundary_normals_scratch_len`] scalars; `normals` receives
/// `B * dim` scalars.
///
/// Errors: pointer and length errors (no elements: `DK_ERR_LENGTH_MISMATCH`), the cell errors,
/// `DK_ERR_CELL_DIMENSION` (an element kind that does not fit `dim`), `DK_ERR_NON_FINITE`,
/// `DK_ERR_ISOLATED_NODE` (a point in no element), `DK_ERR_ZERO_LENGTH` (the element normals
/// cancel at a node). On error `normals` is unchanged.
#[export(twin, elements[1])]
pub(crate) fn dk_deform_boundary_normals<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    elements: In<'_, dk_cells>,
    index_base: u32,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    normals: Out<'_, T>,
) -> Result<(), dk_status> {
    let points = read_points::<T, D>(points)?;
    let cells = required_elements(elements, index_base, index_scratch, points.len())?;
    let scratch = output(scratch)?;
    let normals = chunks_mut::<T, D>(normals)?;
    Ok(boundary_normals(points, &cells, scratch, normals)?)
}

/// Number of scalars the `scratch` of [`dk_deform_boundary_rotations`] needs: `3 B` in 2D,
/// `13 B` in 3D (saturating). `DK_ERR_INVALID_PARAMETER` unless `dim` is 2 or 3.
#[export(len_out[1])]
pub(crate) fn dk_deform_boundary_rotations_scratch_len<const D: usize>(
    boundary_len: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    write_len(len_out, boundary_rotations_scratch_len::<D>(boundary_len))
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
#[export(twin, elements[1])]
pub(crate) fn dk_deform_boundary_rotations<T: Real, const D: usize>(
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    elements: In<'_, dk_cells>,
    index_base: u32,
    scratch: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    rotations: Out<'_, T>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let cells = required_elements(elements, index_base, index_scratch, u.len())?;
    let scratch = output(scratch)?;
    let q = quats_mut(rotations)?;
    Ok(boundary_rotations(u, d, &cells, scratch, q)?)
}

/// Fills `rotations` (`rotations_len` scalars, a multiple of 4) with copies of the rigid
/// rotation `q` (4 scalars, normalised here): for a marker whose motion is known (the kernel's
/// `rigid_rotations`). Errors: `DK_ERR_NON_FINITE`, `DK_ERR_ZERO_LENGTH` (`q`),
/// `DK_ERR_LENGTH_MISMATCH`; on error `rotations` is unchanged.
#[export(twin, q[4])]
pub(crate) fn dk_deform_rigid_rotations<T: Real>(
    q: In<'_, T>,
    rotations: Out<'_, T>,
) -> Result<(), dk_status> {
    let q = read_array::<T, 4>(q).map(Quat::from_array)?;
    Ok(rigid_rotations(q, quats_mut(rotations)?)?)
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
#[export(twin)]
pub(crate) fn dk_deform_boundary_origin<T: Real, const D: usize>(
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    origin_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    if origin_out.len() != D {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let o = output(origin_out)?;
    write_optional(Some(o), boundary_origin(u, d)?);
    Ok(())
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
#[export(twin)]
pub(crate) fn dk_deform_boundary_translations<T: Real, const D: usize>(
    origin: In<'_, T>,
    undeformed: In<'_, T>,
    deformed: In<'_, T>,
    _dim: Dim<D>,
    rotations: In<'_, T>,
    translations: Out<'_, T>,
) -> Result<(), dk_status> {
    let origin = read_array::<T, D>(origin)?;
    let u = read_points::<T, D>(undeformed)?;
    let d = read_points::<T, D>(deformed)?;
    let q = quats(rotations)?;
    let t = chunks_mut::<T, D>(translations)?;
    Ok(boundary_translations(origin, u, d, q, t)?)
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
#[export(twin)]
pub(crate) fn dk_deform_propagate_idw<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
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
    Ok(propagate_idw(points, boundary, exponent, t, q)?)
}

/// Number of scalars the `scratch` of [`dk_deform_propagate_tfi`] and
/// [`dk_deform_displacement_tfi`] needs: `dim · ni nj nk` (the kernel's `tfi_scratch_len`).
/// Errors: `DK_ERR_BAD_DIMENSIONS` (block), `DK_ERR_INVALID_PARAMETER` (`dim`).
#[export(len_out[1])]
pub(crate) fn dk_deform_propagate_tfi_scratch_len<const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    write_len(len_out, tfi_scratch_len::<D>(&b))
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
#[export(twin)]
pub(crate) fn dk_deform_propagate_tfi<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: In<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
) -> Result<(), dk_status> {
    let tfi = ([ni, nj, nk], directions, points);
    propagate_tfi_for_dim::<T, D>(tfi, scratch, translations, Some(rotations))
}

/// Plain displacement TFI (the kernel's `displacement_tfi`, Samareh eq. 1; for comparison
/// with [`dk_deform_propagate_tfi`]): the same arclength-blended boolean sum applied to
/// displacements `δ = r^d − r^u` given on the faces of the active directions; `displacements`
/// (`N * dim`) is updated in place everywhere else. New points are `points + δ`. It reproduces
/// translations but shears cells under rotation. Errors as [`dk_deform_propagate_tfi`]; on
/// error `displacements` is unchanged.
#[export(twin)]
pub(crate) fn dk_deform_displacement_tfi<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    directions: u32,
    points: In<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    displacements: Out<'_, T>,
) -> Result<(), dk_status> {
    let tfi = ([ni, nj, nk], directions, points);
    propagate_tfi_for_dim::<T, D>(tfi, scratch, displacements, None)
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
#[export(twin)]
pub(crate) fn dk_deform_update_points<T: Real, const D: usize>(
    origin: In<'_, T>,
    points: In<'_, T>,
    _dim: Dim<D>,
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
    Ok(update_points(origin, points, t, q, boundary, bd, out)?)
}

/// Number of `uint32_t` entries the `scratch` of [`dk_deform_localize_nodes`] needs:
/// `node_count` with `index_base` 0, `node_count + boundary_len + global_len` with 1.
/// Errors: `DK_ERR_BAD_INDEX_BASE`, `DK_ERR_TOO_LARGE` (overflow).
#[export(len_out[1])]
pub(crate) fn dk_deform_localize_nodes_scratch_len(
    node_count: usize,
    boundary_len: usize,
    global_len: usize,
    index_base: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let n = index_need(index_base, &[boundary_len, global_len])?;
    let len = n.checked_add(localize_nodes_scratch_len(node_count));
    write_len(len_out, len.ok_or(dk_status::DK_ERR_TOO_LARGE)?)
}

/// Rewrites mesh node numbers as positions in `boundary` (the kernel's `localize_nodes`):
/// `local[e] = k` where `boundary[k] == global[e]`. Boundary elements usually come in mesh
/// numbering (a marker's faces); the boundary-level functions and
/// [`dk_boundary_motion::elements`] want positions in the boundary list. Pass a marker's
/// element node array as `global`; use `local` with the same offsets and kinds.
///
/// `boundary` (`B` distinct mesh nodes) and `global` are read in `index_base` (0 or 1), and
/// `local` is written in the same base (positions `index_base .. B − 1 + index_base`), so a
/// Fortran caller passes and gets 1-based arrays. `scratch` needs
/// [`dk_deform_localize_nodes_scratch_len`] entries. Errors: `DK_ERR_BAD_INDEX_BASE`,
/// `DK_ERR_INDEX_OUT_OF_RANGE` (an entry `>= node_count`, or an element node not in
/// `boundary`), `DK_ERR_DUPLICATE_NODE`, `DK_ERR_LENGTH_MISMATCH` (`local_len != global_len`),
/// `DK_ERR_BUFFER_TOO_SMALL`, `DK_ERR_TOO_LARGE`. On error `local` is unchanged.
#[export]
pub(crate) fn dk_deform_localize_nodes(
    node_count: usize,
    boundary: In<'_, u32>,
    global: In<'_, u32>,
    index_base: u32,
    scratch: Out<'_, u32>,
    local: Out<'_, u32>,
) -> Result<(), dk_status> {
    check_base(index_base)?;
    let b = input(boundary)?;
    let g = input(global)?;
    let s = output(scratch)?;
    let l = output(local)?;
    if u32::try_from(b.len()).is_err() {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    let (b, s) = rebase(b, index_base, s)?;
    let (g, s) = rebase(g, index_base, s)?;
    localize_nodes(node_count, b, g, s, l)?;
    // Positions are < B <= u32::MAX (checked above), so adding a base of 0 or 1 cannot
    // overflow; wrapping_add keeps the arithmetic visibly panic-free.
    for x in l.iter_mut() {
        *x = x.wrapping_add(index_base);
    }
    Ok(())
}

/// Sizes for [`dk_deform_spring`]: `*scratch_len_out` scalars of `scratch` (as
/// [`dk_deform_idw_scratch_len`]) and `*values_len_out` scalars of the packed `values`
/// workspace (the kernel's `propagate_spring_scratch_len`: `dim + 4` scalars a node plus the
/// solver's; depends on `options->method`). The same for both precisions. Errors: `DK_ERR_INVALID_PARAMETER`
/// (`dim`, method, or the two outputs are one pointer), `DK_ERR_TOO_LARGE`; nothing is
/// written on error.
#[export(options[1], scratch_len_out[1], values_len_out[1])]
pub(crate) fn dk_deform_spring_scratch_len(
    node_count: usize,
    boundary_len: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
    scratch_len_out: Out<'_, usize>,
    values_len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
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
}

/// Number of `uint32_t` entries the `index_scratch` of [`dk_deform_spring`] needs:
/// [`dk_boundary_motion_index_scratch_len`] plus `node_count` (the spring system's anchoring
/// check).
#[export(twin, motion[1], len_out[1])]
pub(crate) fn dk_deform_spring_index_scratch_len<T: Real>(
    motion: In<'_, DkBoundaryMotion<T>>,
    node_count: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let need = read_raw(motion)?.index_need()?;
    let len = need.checked_add(SpringSystem::<T>::scratch_len(node_count));
    write_len(len_out, len.ok_or(dk_status::DK_ERR_TOO_LARGE)?)
}

/// The whole quaternion deformation with linear-spring propagation (the kernel's
/// `deform_spring`, Samareh's unstructured variant): boundary rotations and translations as in
/// [`dk_deform_idw`], then one linear-spring solve for `Δ` and the quaternion components
/// together (`dim + 4` values per node) with `options` (see `dk_spring_solve_options`; the
/// f32 twin rounds its tolerances to `float`), then the update.
///
/// The spring system (`*system`) is a 0-based CSR graph (from `dk_graph_from_*`), one
/// positive stiffness per directed edge (symmetric, e.g. from `dk_spring_batina_stiffness`)
/// and a fixed mask (one byte per node, nonzero = fixed) that must mark exactly the nodes of
/// `motion->nodes`. `scratch`: the first length of
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
/// # f32 twin
/// `f32` twin of [`dk_deform_spring`] (the options' tolerances and `omega` are rounded to
/// `float`; the report's values are widened exactly).
#[export(twin, motion[1], system[1], options[1], report[1])]
pub(crate) fn dk_deform_spring<T: Real, const D: usize>(
    points: In<'_, T>,
    _dim: Dim<D>,
    motion: In<'_, DkBoundaryMotion<T>>,
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    scratch: Out<'_, T>,
    values: Out<'_, T>,
    index_scratch: Out<'_, u32>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    out: Out<'_, T>,
    origin_out: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method::<T>()?;
    let raw = read_raw(motion)?;
    let points = read_points::<T, D>(points)?;
    let outs = [scratch, translations, rotations, out, origin_out];
    let b = pipeline::<T, D>(outs, index_scratch)?;
    let values = output(values)?;
    let report = out_one(report)?;
    let (motion, rest) = raw.view::<D>(b.index_scratch)?;
    let sys = DkSpringSystem::read(system)?.build(rest)?;
    let (stop, t, q, s, out) = (o.stopping(), b.translations, b.rotations, b.scratch, b.out);
    let (origin, rep) = deform_spring(points, &motion, &sys, method, &stop, t, q, s, values, out)?;
    write_optional(b.origin_out, origin);
    *report = dk_spring_solve_report::of(rep);
    Ok(())
}

/// Number of scalars the packed `values` workspace of [`dk_deform_propagate_spring`] needs:
/// the kernel's `propagate_spring_scratch_len(method, node_count)` (`dim + 4` scalars a node
/// plus the solver's). Errors: `DK_ERR_INVALID_PARAMETER` (`dim`, method), `DK_ERR_TOO_LARGE`.
#[export(options[1], len_out[1])]
pub(crate) fn dk_deform_propagate_spring_scratch_len(
    node_count: usize,
    dim: u32,
    options: In<'_, dk_spring_solve_options>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    write_len(len_out, spring_values_len(node_count, dim, options)?)
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
#[export(twin, system[1], options[1], report[1])]
pub(crate) fn dk_deform_propagate_spring<T: Real, const D: usize>(
    system: In<'_, DkSpringSystem<T>>,
    options: In<'_, dk_spring_solve_options>,
    _dim: Dim<D>,
    index_scratch: Out<'_, u32>,
    values: Out<'_, T>,
    translations: Out<'_, T>,
    rotations: Out<'_, T>,
    report: Out<'_, dk_spring_solve_report>,
) -> Result<(), dk_status> {
    let o = read_one(options)?;
    let method = o.method::<T>()?;
    let s = output(index_scratch)?;
    let values = output(values)?;
    let t = chunks_mut::<T, D>(translations)?;
    let q = quats_mut(rotations)?;
    let report = out_one(report)?;
    let sys = DkSpringSystem::read(system)?.build(s)?;
    let rep = propagate_spring(&sys, method, &o.stopping(), t, q, values)?;
    *report = dk_spring_solve_report::of(rep);
    Ok(())
}
