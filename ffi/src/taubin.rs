//! Taubin λ|μ smoothing and the structured-grid line tools: `dk_taubin_*` (f64) and
//! `dk_taubin_*_f32`, plus Alter's whole-grid job `dk_taubin_smooth_arclength`.
//!
//! Conventions of this module:
//! - A structured block crosses the ABI as three `size_t` dimensions `ni, nj, nk` (each ≥ 1,
//!   `nk = 1` for 2D, `nj = nk = 1` for 1D); point `(i, j, k)` has the linear index
//!   `i + ni (j + nj k)` (i fastest: Plot3D and Fortran order).
//! - Points are flat arrays of `n * dim` scalars (`x0, y0, [z0,] x1, …`) with `dim` 2 or 3;
//!   per-node values on a graph are flat arrays of `n * components` scalars (`components`
//!   1 to 7: a scalar, a displacement, a quaternion, or a displacement and a quaternion).
//! - Options and reports are `#[repr(C)]` structs whose floating-point fields are `double`
//!   for both precisions: the `_f32` functions round them to `float` (exact for values that
//!   are `float`s, and the defaults round exactly as the Rust API's `f32` defaults do), and
//!   widen their `float` results exactly.
//! - Flags inside structs are `uint8_t` (nonzero = true), so a C `char`, `_Bool` or Fortran
//!   `integer(c_int8_t)` can be passed through without a conversion.
//! - Index ranges (`dk_block_region`, graph node ranges) honour `index_base`: with 0 they are
//!   C's `lo <= i < hi`, with 1 they are Fortran's inclusive `lo <= i <= hi`, 1-based.
//! - Routines that update a caller buffer in place (`points`, `field`, `values`) validate
//!   everything first: on any error the buffer and every output are unchanged. Scratch buffers
//!   are work space: their contents after any call are unspecified.
#![allow(unsafe_code)] // a parameter struct's arrays become `In`/`Out` tokens (`In::new`) here.

use deform_kernel::taubin::{
    arclength, check_lines_increasing, graph_sweep, inverse_distance_weights, max_stretching,
    redistribute, redistribute_scratch_len, smooth_arclength, smooth_arclength_scratch_len,
    smooth_graph, smooth_structured, smooth_structured_coarse, stretching,
    structured_coarse_scratch_len, structured_scratch_len, structured_sweep, BlockRegion, Coarse,
    FilterReport, GraphOptions, LineEnd, Prolongation, SmoothOptions, SmoothReport,
    StructuredOptions, TaubinParams,
};
use deform_kernel::{Block, Direction, Directions, Graph, Real};
use deform_kernel_ffi_export::export;

use crate::args::{
    assert_layout, block, mul_len, optional, range, read_one, read_optional_points, read_points,
    write_len, Components, Dim,
};
use crate::graph::{dk_graph, read_graph};
use crate::slice::{chunks, chunks_mut, input, out_one, output, whole_chunks_mut, In, Out};
use crate::status::dk_status;

// ---------------------------------------------------------------------------------------------
// repr(C) types.
// ---------------------------------------------------------------------------------------------

/// `dk_taubin_coarse::prolongation`: the fine field becomes the interpolated coarse field
/// (Alter's prolongation of the arclength functions; the default).
pub const DK_PROLONGATION_VALUES: u32 = 0;
/// `dk_taubin_coarse::prolongation`: the interpolated coarse *change* is added to the fine
/// field (keeps fine-scale content the coarse grid cannot see).
pub const DK_PROLONGATION_CORRECTION: u32 = 1;

/// Coarse-grid (multi-grid) settings: keep every `factor[d]`-th index in direction `d` (1 = do
/// not coarsen; the last index is always kept) and the prolongation rule
/// (`DK_PROLONGATION_VALUES` or `DK_PROLONGATION_CORRECTION`). Alter used `{4, 4, 1}` for
/// k-lines.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_taubin_coarse {
    /// Sampling factor per direction i, j, k (each ≥ 1).
    pub factor: [usize; 3],
    /// `DK_PROLONGATION_VALUES` (0) or `DK_PROLONGATION_CORRECTION` (1).
    pub prolongation: u32,
}
assert_layout!(dk_taubin_coarse, 32; factor = 0, prolongation = 24);

impl dk_taubin_coarse {
    fn to_kernel(self) -> Result<Coarse, dk_status> {
        // The kernel checks this too, but its size query treats 0 as 1: reject it here so
        // the scratch-length function agrees with the solver.
        if self.factor.contains(&0) {
            return Err(dk_status::DK_ERR_INVALID_PARAMETER);
        }
        let prolongation = match self.prolongation {
            DK_PROLONGATION_VALUES => Prolongation::Values,
            DK_PROLONGATION_CORRECTION => Prolongation::Correction,
            _ => return Err(dk_status::DK_ERR_INVALID_PARAMETER),
        };
        Ok(Coarse {
            factor: self.factor,
            prolongation,
        })
    }
}

/// Options of the structured filters (`dk_taubin_smooth_structured*`,
/// `dk_taubin_structured_sweep`). All zero (`{0}`) is the paper's setting: no pins, the
/// in-plane face rule everywhere.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_structured_options {
    /// Optional pin mask, one byte per point (nonzero = the point keeps its value); NULL (with
    /// `pinned_len` 0) for none.
    pub pinned: *const u8,
    /// Length of `pinned` (the point count when given).
    pub pinned_len: usize,
    /// Per direction i, j, k: nonzero = the faces normal to it use the mirror (Neumann) rule
    /// instead of the paper's in-plane average.
    pub mirror: [u8; 3],
}
assert_layout!(dk_structured_options, 24; pinned = 0, pinned_len = 8, mirror = 16);

/// Options structs that carry an optional pin mask.
trait HasPins: Copy {
    fn pins(&self) -> (*const u8, usize);
}

impl HasPins for dk_structured_options {
    fn pins(&self) -> (*const u8, usize) {
        (self.pinned, self.pinned_len)
    }
}

impl HasPins for dk_smooth_arclength_options {
    fn pins(&self) -> (*const u8, usize) {
        (self.pinned, self.pinned_len)
    }
}

/// Reads an options struct and borrows its optional pin mask for the struct's lifetime.
fn read_with_pins<S: HasPins>(p: In<'_, S>) -> Result<(S, Option<&[u8]>), dk_status> {
    let s = read_one(p)?;
    let (ptr, len) = s.pins();
    // SAFETY: a token for an options struct carries the contract of the functions that take
    // one: its pin mask is NULL or readable for `pinned_len` bytes while the struct is.
    let pins = unsafe { In::new(ptr, len) };
    Ok((s, optional(pins)?))
}

/// The grid direction 0 (i), 1 (j) or 2 (k); anything else is `DK_ERR_INVALID_PARAMETER`.
pub(crate) fn to_direction(d: u32) -> Result<Direction, dk_status> {
    usize::try_from(d)
        .ok()
        .and_then(Direction::from_index)
        .ok_or(dk_status::DK_ERR_INVALID_PARAMETER)
}

/// Bits of the `free_faces` mask of `dk_taubin_smooth_arclength_ends`: the face `i = 0`.
pub const DK_FACE_IMIN: u32 = 1;
/// The face `i = ni − 1`.
pub const DK_FACE_IMAX: u32 = 2;
/// The face `j = 0`.
pub const DK_FACE_JMIN: u32 = 4;
/// The face `j = nj − 1`.
pub const DK_FACE_JMAX: u32 = 8;
/// The face `k = 0`.
pub const DK_FACE_KMIN: u32 = 16;
/// The face `k = nk − 1`.
pub const DK_FACE_KMAX: u32 = 32;

/// The line ends of a `free_faces` mask for lines along `direction`: only the two faces at
/// the line ends may be named (bit `2d` the first, `2d + 1` the last); any other bit is
/// `DK_ERR_INVALID_PARAMETER`.
fn line_ends(direction: Direction, free_faces: u32) -> Result<[LineEnd; 2], dk_status> {
    let shift = 2 * direction.index() as u32;
    if free_faces & !(0b11 << shift) != 0 {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    let end = |bit: u32| {
        if free_faces & (1 << (shift + bit)) != 0 {
            LineEnd::Free
        } else {
            LineEnd::Fixed
        }
    };
    Ok([end(0), end(1)])
}

/// The mirror faces of an options struct: nonzero per direction i, j, k.
fn mirror(flags: [u8; 3]) -> Directions {
    Directions::from_flags(flags.map(|m| m != 0))
}

impl dk_structured_options {
    fn to_kernel(self, pinned: Option<&[u8]>) -> StructuredOptions<'_> {
        StructuredOptions {
            fixed: pinned,
            mirror: mirror(self.mirror),
        }
    }
}

/// A box of structured indices, the points one `dk_taubin_structured_sweep` updates. With
/// `index_base` 0: `lo[d] <= index[d] < hi[d]`; with 1: `lo[d] <= index[d] <= hi[d]`, 1-based.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_block_region {
    /// First index per direction i, j, k.
    pub lo: [usize; 3],
    /// End per direction: exclusive (index_base 0) or inclusive (index_base 1).
    pub hi: [usize; 3],
}
assert_layout!(dk_block_region, 48; lo = 0, hi = 24);

/// What a whole filter run did (`dk_taubin_smooth_structured*`, `dk_taubin_smooth_graph`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_filter_report {
    /// Iterations performed (one iteration = λ pass + μ pass).
    pub iterations: usize,
    /// Largest `|change|` of any value in either pass of the last iteration (0 when no
    /// iteration ran).
    pub last_change: f64,
}
assert_layout!(dk_filter_report, 16; iterations = 0, last_change = 8);

impl dk_filter_report {
    fn of<T: Real>(r: FilterReport<T>) -> Self {
        dk_filter_report {
            iterations: r.iterations,
            last_change: r.last_change.to_f64(),
        }
    }
}

/// Settings of `dk_taubin_smooth_arclength` (Alter's whole-grid smoothing). Fill with
/// `dk_smooth_arclength_options_default` and change fields as needed.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_smooth_arclength_options {
    /// Forward (smoothing) factor λ > 0 (default 0.330).
    pub lambda: f64,
    /// Backward (shape-recovery) factor μ ≤ 0 (default −0.334).
    pub mu: f64,
    /// Fine-grid iterations (default 30).
    pub iterations: usize,
    /// Coarse-grid iterations when `use_coarse` is nonzero (default 15).
    pub coarse_iterations: usize,
    /// Optional pin mask, one byte per point (nonzero = the point does not move); NULL (with
    /// `pinned_len` 0) for none.
    pub pinned: *const u8,
    /// Length of `pinned` (the point count when given).
    pub pinned_len: usize,
    /// Coarse-grid settings, used when `use_coarse` is nonzero (default `{1, 1, 1}`, values).
    pub coarse: dk_taubin_coarse,
    /// Direction of the smoothed grid lines: 0 = i, 1 = j, 2 = k.
    pub direction: u32,
    /// Nonzero: filter the normalised arclength `S / S_total` (both line ends stay put; reduces
    /// stretching). Zero (default): the dimensional arclength.
    pub normalised: u8,
    /// Nonzero: run the coarse-grid pass after the fine iterations (default 0).
    pub use_coarse: u8,
    /// Per direction i, j, k: nonzero = mirror (Neumann) faces. The entry for `direction` is
    /// ignored (the line-end faces always use the paper's rule).
    pub mirror: [u8; 3],
}
assert_layout!(
    dk_smooth_arclength_options, 96;
    lambda = 0, mu = 8, iterations = 16, coarse_iterations = 24, pinned = 32, pinned_len = 40,
    coarse = 48, direction = 80, normalised = 84, use_coarse = 85, mirror = 86,
);

impl dk_smooth_arclength_options {
    fn to_kernel<T: Real>(self, pinned: Option<&[u8]>) -> Result<SmoothOptions<'_, T>, dk_status> {
        Ok(SmoothOptions {
            direction: to_direction(self.direction)?,
            params: TaubinParams {
                lambda: T::from_f64(self.lambda),
                mu: T::from_f64(self.mu),
            },
            iterations: self.iterations,
            normalised: self.normalised != 0,
            ends: [LineEnd::Fixed; 2],
            fixed: pinned,
            mirror: mirror(self.mirror),
            coarse: if self.use_coarse != 0 {
                Some(self.coarse.to_kernel()?)
            } else {
                None
            },
            coarse_iterations: self.coarse_iterations,
        })
    }
}

/// What `dk_taubin_smooth_arclength` did.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(non_camel_case_types)]
pub struct dk_smooth_report {
    /// Iterations performed (fine + coarse).
    pub iterations: usize,
    /// Largest `|change|` of the arclength field in either pass of the last iteration.
    pub last_change: f64,
    /// Largest distance any point moved.
    pub max_displacement: f64,
    /// Maximum stretching along the smoothing direction before.
    pub stretching_before: f64,
    /// Maximum stretching along the smoothing direction after.
    pub stretching_after: f64,
    /// 0-based linear index `i + ni (j + nj k)` of the point of `stretching_before`.
    pub stretching_before_point: usize,
    /// 0-based linear index of the point of `stretching_after`.
    pub stretching_after_point: usize,
}
assert_layout!(
    dk_smooth_report, 56;
    iterations = 0, last_change = 8, max_displacement = 16, stretching_before = 24,
    stretching_after = 32, stretching_before_point = 40, stretching_after_point = 48,
);

impl dk_smooth_report {
    fn of<T: Real>(r: SmoothReport<T>) -> Self {
        dk_smooth_report {
            iterations: r.iterations,
            last_change: r.last_change.to_f64(),
            max_displacement: r.max_displacement.to_f64(),
            stretching_before: r.stretching_before.0.to_f64(),
            stretching_after: r.stretching_after.0.to_f64(),
            stretching_before_point: r.stretching_before.1,
            stretching_after_point: r.stretching_after.1,
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Shared argument handling.
// ---------------------------------------------------------------------------------------------

/// A structured filter's job: the Taubin parameters, the iteration count and the options.
type StructuredJob<'a, T> = (TaubinParams<T>, usize, In<'a, dk_structured_options>);

/// [`dk_taubin_smooth_structured`], or its coarse-grid variant when `coarse` is given.
fn smooth_structured_t<T: Real>(
    [ni, nj, nk]: [usize; 3],
    coarse: Option<In<'_, dk_taubin_coarse>>,
    (p, iterations, options): StructuredJob<'_, T>,
    field: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let c = match coarse {
        Some(c) => Some(read_one(c)?.to_kernel()?),
        None => None,
    };
    let (o, pinned) = read_with_pins(options)?;
    let o = o.to_kernel(pinned);
    let f = output(field)?;
    let s = output(scratch)?;
    let r = out_one(report)?;
    let rep = match c {
        None => smooth_structured(&b, f, p, iterations, &o, s),
        Some(c) => smooth_structured_coarse(&b, f, &c, p, iterations, &o, s),
    }?;
    *r = dk_filter_report::of(rep);
    Ok(())
}

/// The graph and the options (optional weights and fixed mask) of a graph filter.
fn graph_options<'a, T>(
    graph: In<'a, dk_graph>,
    weights: In<'a, T>,
    fixed: In<'a, u8>,
) -> Result<(Graph<'a>, GraphOptions<'a, T>), dk_status> {
    let g = read_graph(graph)?;
    let o = GraphOptions {
        weights: optional(weights)?,
        fixed: optional(fixed)?,
    };
    Ok((g, o))
}

/// [`dk_taubin_check_lines_increasing`] with the optional points in dimension `D`.
fn check_lines<T: Real, const D: usize>(
    b: &Block,
    field: &[T],
    direction: u32,
    iteration: usize,
    points: In<'_, T>,
) -> Result<(), dk_status> {
    let p = read_optional_points::<T, D>(points)?;
    check_lines_increasing(b, field, to_direction(direction)?, iteration, p)
        .map_err(dk_status::from)
}

// ---------------------------------------------------------------------------------------------
// The C functions (`cargo xtask codegen` exports each, see ffi/README.md).
// ---------------------------------------------------------------------------------------------

/// The λ|μ values Alter took from Taubin: `λ = 0.330`, `μ = −0.334` (pass band ≈ 0.0363).
#[export(twin, lambda_out[1], mu_out[1])]
pub(crate) fn dk_taubin_params_paper<T: Real>(
    lambda_out: Out<'_, T>,
    mu_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = TaubinParams::<T>::paper();
    let l = out_one(lambda_out)?;
    let m = out_one(mu_out)?;
    *l = p.lambda;
    *m = p.mu;
    Ok(())
}

/// `λ` with `μ` from Taubin's pass-band relation `1/λ + 1/μ = pass_band`. Needs `λ > 0` and
/// `0 < pass_band < 1/λ` (`DK_ERR_INVALID_PARAMETER`; NaN/∞: `DK_ERR_NON_FINITE`). Writes `λ`
/// unchanged to `*lambda_out` and `μ` to `*mu_out`.
#[export(twin, lambda_out[1], mu_out[1])]
pub(crate) fn dk_taubin_params_from_pass_band<T: Real>(
    lambda: T,
    pass_band: T,
    lambda_out: Out<'_, T>,
    mu_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = TaubinParams::from_pass_band(lambda, pass_band)?;
    let l = out_one(lambda_out)?;
    let m = out_one(mu_out)?;
    *l = p.lambda;
    *m = p.mu;
    Ok(())
}

/// Fills `*out` with the paper's settings for lines along `direction` (0 = i, 1 = j, 2 = k):
/// λ = 0.330, μ = −0.334, 30 iterations, dimensional arclength, no pins, no mirror faces, no
/// coarse pass (coarse factor `{1, 1, 1}`, values prolongation, 15 coarse iterations).
/// `direction > 2` gives `DK_ERR_INVALID_PARAMETER`.
#[export(out[1])]
pub(crate) fn dk_smooth_arclength_options_default(
    direction: u32,
    out: Out<'_, dk_smooth_arclength_options>,
) -> Result<(), dk_status> {
    let k = SmoothOptions::<f64>::new(crate::taubin::to_direction(direction)?);
    let v = dk_smooth_arclength_options {
        lambda: k.params.lambda,
        mu: k.params.mu,
        iterations: k.iterations,
        coarse_iterations: k.coarse_iterations,
        pinned: core::ptr::null(),
        pinned_len: 0,
        coarse: dk_taubin_coarse {
            factor: [1, 1, 1],
            prolongation: DK_PROLONGATION_VALUES,
        },
        direction,
        normalised: u8::from(k.normalised),
        use_coarse: 0,
        mirror: k.mirror.flags().map(u8::from),
    };
    let o = out_one(out)?;
    *o = v;
    Ok(())
}

/// Scratch length (in scalars of the precision used) for [`dk_taubin_smooth_arclength`] with
/// these dimensions, `dim` (2 or 3) and options (only `direction`, `use_coarse` and `coarse`
/// matter): `n + max(n, 2 n_coarse, (dim + 1) × points per line)`. A `direction` other than
/// 0, 1, 2 gives `DK_ERR_INVALID_PARAMETER`.
#[export(options[1], len_out[1])]
pub(crate) fn dk_taubin_smooth_arclength_scratch_len<const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    options: In<'_, dk_smooth_arclength_options>,
    _dim: Dim<D>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let o = read_one(options)?;
    let coarse = (o.use_coarse != 0)
        .then(|| o.coarse.to_kernel())
        .transpose()?;
    let d = crate::taubin::to_direction(o.direction)?;
    write_len(
        len_out,
        smooth_arclength_scratch_len::<D>(&b, d, coarse.as_ref()),
    )
}

/// Smooths a structured grid along one family of lines, Alter's way: arclength along
/// `options->direction` → `options->iterations` Taubin λ|μ iterations on that scalar field
/// (then the optional coarse pass) → fold guard (`DK_ERR_FOLDED_LINE` if the filtered
/// arclength stops increasing along any line) → every point slides along its original grid
/// line to its filtered arclength. Pinned points do not move.
///
/// `points` holds `ni·nj·nk` points of `dim` (2 or 3) scalars, updated in place; `scratch`
/// needs [`dk_taubin_smooth_arclength_scratch_len`] scalars; `*report` receives what was done.
/// On any error (including `DK_ERR_FOLDED_LINE`) `points` and `*report` are unchanged; the
/// scratch contents are unspecified afterwards.
///
/// # f32 twin
/// `f32` twin of [`dk_taubin_smooth_arclength`] (`options->lambda`, `mu` are rounded to
/// `float`; the report's values are widened exactly).
#[export(twin, options[1], report[1])]
pub(crate) fn dk_taubin_smooth_arclength<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    options: In<'_, dk_smooth_arclength_options>,
    points: Out<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_smooth_report>,
) -> Result<(), dk_status> {
    dk_taubin_smooth_arclength_ends::<T, D>(ni, nj, nk, options, 0, points, Dim, scratch, report)
}

/// [`dk_taubin_smooth_arclength`] with a choice of line ends: `free_faces` is a mask of
/// `DK_FACE_*` bits naming the faces whose points may slide (0 = every end fixed, the same as
/// `dk_taubin_smooth_arclength`). Only the last face of the smoothing direction can be free
/// (`DK_FACE_KMAX` for k-lines: Alter's rough outer boundary), and only with dimensional
/// arclength; there every line's last point slides along its line to its filtered arclength,
/// past the end along the line's last segment of non-zero length. Errors as
/// [`dk_taubin_smooth_arclength`], and `DK_ERR_INVALID_PARAMETER` for a face that is not a line
/// end of `options->direction`, a free first face or a free face with `normalised`,
/// `DK_ERR_SHARED_FREE_END` when a free end coincides with another line's end (a seam or an
/// axis: keep that face fixed). On any error `points` and `*report` are unchanged.
#[allow(clippy::too_many_arguments)]
#[export(twin, options[1], report[1])]
pub(crate) fn dk_taubin_smooth_arclength_ends<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    options: In<'_, dk_smooth_arclength_options>,
    free_faces: u32,
    points: Out<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_smooth_report>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let (o, pinned) = read_with_pins(options)?;
    let mut opts = o.to_kernel::<T>(pinned)?;
    opts.ends = line_ends(opts.direction, free_faces)?;
    let p = chunks_mut::<T, D>(points)?;
    let s = output(scratch)?;
    let r = out_one(report)?;
    // The kernel validates everything before it moves a point: on Err `points` is unchanged.
    *r = dk_smooth_report::of(smooth_arclength(&b, p, &opts, s)?);
    Ok(())
}

/// Scratch length (in scalars) for [`dk_taubin_smooth_structured`]: the point count.
#[export(len_out[1])]
pub(crate) fn dk_taubin_smooth_structured_scratch_len(
    ni: usize,
    nj: usize,
    nk: usize,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    write_len(len_out, structured_scratch_len(&b))
}

/// Smooths a scalar field on a structured block (`ni·nj·nk` values, in place) with
/// `iterations` Taubin λ|μ iterations, Alter's stencils: the average of the 6 neighbours
/// inside, the 4 in-plane ones on a face, the 2 along an edge; corners and pinned points keep
/// their value (see `dk_structured_options` for pins and mirror faces). `scratch` needs
/// [`dk_taubin_smooth_structured_scratch_len`] scalars. Errors: `DK_ERR_INVALID_PARAMETER`
/// (`λ ≤ 0`, `μ > 0`), `DK_ERR_NON_FINITE` (`λ`, `μ`, field), length and pointer errors. On
/// error `field` and `*report` are unchanged.
#[export(twin, options[1], report[1])]
pub(crate) fn dk_taubin_smooth_structured<T: Real>(
    ni: usize,
    nj: usize,
    nk: usize,
    lambda: T,
    mu: T,
    iterations: usize,
    options: In<'_, dk_structured_options>,
    field: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> Result<(), dk_status> {
    let p = TaubinParams { lambda, mu };
    let job = (p, iterations, options);
    smooth_structured_t([ni, nj, nk], None, job, field, scratch, report)
}

/// One Jacobi pass of the structured filter over `region` only: `dst = src + weight ·
/// (avg(src) − src)` at every free point of the region (`dst = src` at pinned points); `dst`
/// outside the region is not touched. `*max_change_out` receives the largest `|dst − src|` in
/// the region. One iteration of [`dk_taubin_smooth_structured`] is a sweep `field → tmp` with
/// `λ` then `tmp → field` with `μ` over the whole block; an MPI code sweeps its own box and
/// exchanges halo values of `src` between passes. `region` is read with `index_base` (0: C's
/// half-open `lo <= i < hi`; 1: Fortran's inclusive 1-based `lo <= i <= hi`). Errors
/// (nothing written): `DK_ERR_INDEX_OUT_OF_RANGE` (region), `DK_ERR_NON_FINITE` (`weight`,
/// `src`), `DK_ERR_BAD_INDEX_BASE`, length and pointer errors.
#[export(twin, options[1], region[1], max_change_out[1])]
pub(crate) fn dk_taubin_structured_sweep<T: Real>(
    ni: usize,
    nj: usize,
    nk: usize,
    src: In<'_, T>,
    weight: T,
    options: In<'_, dk_structured_options>,
    region: In<'_, dk_block_region>,
    index_base: u32,
    dst: Out<'_, T>,
    max_change_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let (o, pinned) = read_with_pins(options)?;
    let o = o.to_kernel(pinned);
    let reg = read_one(region)?;
    let mut lo = [0usize; 3];
    let mut hi = [0usize; 3];
    for ((l, h), (&rl, &rh)) in lo
        .iter_mut()
        .zip(hi.iter_mut())
        .zip(reg.lo.iter().zip(&reg.hi))
    {
        [*l, *h] = range(rl, rh, index_base)?;
    }
    let s = input(src)?;
    let d = output(dst)?;
    let m = out_one(max_change_out)?;
    *m = structured_sweep(&b, s, d, weight, &o, &BlockRegion { lo, hi })?;
    Ok(())
}

/// Scratch length (in scalars) for [`dk_taubin_smooth_structured_coarse`]: two coarse fields.
#[export(coarse[1], len_out[1])]
pub(crate) fn dk_taubin_smooth_structured_coarse_scratch_len(
    ni: usize,
    nj: usize,
    nk: usize,
    coarse: In<'_, dk_taubin_coarse>,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let c = read_one(coarse)?.to_kernel()?;
    write_len(len_out, structured_coarse_scratch_len(&b, &c))
}

/// The coarse-grid variant of [`dk_taubin_smooth_structured`] (Alter's multi-grid step):
/// restrict the field to every `coarse->factor[d]`-th index (the last index always kept), run
/// `iterations` λ|μ iterations there, prolong back by multilinear interpolation
/// (`coarse->prolongation`). Pinned fine points keep their value. `scratch` needs
/// [`dk_taubin_smooth_structured_coarse_scratch_len`] scalars. Errors as
/// [`dk_taubin_smooth_structured`], plus `DK_ERR_INVALID_PARAMETER` for a zero factor or an
/// unknown prolongation. On error `field` and `*report` are unchanged.
#[export(twin, coarse[1], options[1], report[1])]
pub(crate) fn dk_taubin_smooth_structured_coarse<T: Real>(
    ni: usize,
    nj: usize,
    nk: usize,
    coarse: In<'_, dk_taubin_coarse>,
    lambda: T,
    mu: T,
    iterations: usize,
    options: In<'_, dk_structured_options>,
    field: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> Result<(), dk_status> {
    let p = TaubinParams { lambda, mu };
    let job = (p, iterations, options);
    smooth_structured_t([ni, nj, nk], Some(coarse), job, field, scratch, report)
}

/// Scratch length (in scalars) for [`dk_taubin_smooth_graph`]: `node_count * components`
/// (`DK_ERR_TOO_LARGE` if that overflows `size_t`).
#[export(len_out[1])]
pub(crate) fn dk_taubin_smooth_graph_scratch_len(
    node_count: usize,
    components: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    if !(1..=7).contains(&components) {
        return Err(dk_status::DK_ERR_INVALID_PARAMETER);
    }
    write_len(len_out, mul_len(node_count, components as usize)?)
}

/// Taubin fairing of per-node values on a CSR graph (the classic unstructured variant):
/// `iterations` λ|μ iterations, each two Jacobi passes
/// `x_i ← x_i + w (Σ_j w_ij x_j / Σ_j w_ij − x_i)` with `w = λ`, then `w = μ`.
///
/// - `graph`: a 0-based CSR graph (from `dk_graph_from_*`);
/// - `weights`: per directed edge (`graph->targets_len` values, each finite and `> 0`), or NULL with
///   `weights_len` 0 for uniform weights (see [`dk_taubin_inverse_distance_weights`]);
/// - `fixed`: one byte per node (nonzero = keeps its value), or NULL with `fixed_len` 0;
/// - `values`: `node_count * components` scalars (`components` 1 to 7), updated in place;
/// - `scratch`: at least [`dk_taubin_smooth_graph_scratch_len`] scalars.
///
/// Fixed nodes and nodes without neighbours keep their values. On error `values` and
/// `*report` are unchanged.
#[export(twin, graph[1], weights?, fixed?, report[1])]
pub(crate) fn dk_taubin_smooth_graph<T: Real, const V: usize>(
    graph: In<'_, dk_graph>,
    weights: In<'_, T>,
    fixed: In<'_, u8>,
    lambda: T,
    mu: T,
    iterations: usize,
    _components: Components<V>,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> Result<(), dk_status> {
    let (g, o) = graph_options(graph, weights, fixed)?;
    let v = chunks_mut::<T, V>(values)?;
    // The scratch may be longer than needed: use only whole items.
    let s = whole_chunks_mut::<T, V>(scratch)?;
    let r = out_one(report)?;
    let rep = smooth_graph(&g, v, TaubinParams { lambda, mu }, iterations, &o, s)?;
    *r = dk_filter_report::of(rep);
    Ok(())
}

/// One Jacobi pass of the graph filter over the nodes `nodes_start..nodes_end` only:
/// `dst_i = src_i + weight · (avg_i(src) − src_i)` for every free node in the range
/// (`dst_i = src_i` for fixed ones); `dst` outside the range is not touched.
/// `*max_change_out` receives the largest component change in the range. The range is read
/// with `index_base` (0: `start <= i < end`; 1: 1-based inclusive `start <= i <= end`).
/// Graph, weights, fixed mask and `components` as in [`dk_taubin_smooth_graph`]. Nothing is
/// written on error.
#[export(twin, graph[1], weights?, fixed?, max_change_out[1])]
pub(crate) fn dk_taubin_graph_sweep<T: Real, const V: usize>(
    graph: In<'_, dk_graph>,
    weights: In<'_, T>,
    fixed: In<'_, u8>,
    src: In<'_, T>,
    _components: Components<V>,
    weight: T,
    nodes_start: usize,
    nodes_end: usize,
    index_base: u32,
    dst: Out<'_, T>,
    max_change_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let [a, b] = range(nodes_start, nodes_end, index_base)?;
    let (g, o) = graph_options(graph, weights, fixed)?;
    let s = chunks::<T, V>(src)?;
    let d = chunks_mut::<T, V>(dst)?;
    let m = out_one(max_change_out)?;
    *m = graph_sweep(&g, s, d, weight, &o, a..b)?;
    Ok(())
}

/// Fujiwara's inverse-distance weights `weights[e] = 1 / |x_i − x_j|` for every directed edge
/// `e = i → j` of the 0-based CSR graph (`weights_len` = `graph->targets_len`), for
/// [`dk_taubin_smooth_graph`] on meshes with uneven edge lengths. `points`: `node_count *
/// dim` scalars, `dim` 2 or 3. Errors (nothing written): `DK_ERR_ZERO_LENGTH_EDGE` (two
/// neighbours coincide), `DK_ERR_NON_FINITE`, length and pointer errors.
#[export(twin, graph[1], weights?)]
pub(crate) fn dk_taubin_inverse_distance_weights<T: Real, const D: usize>(
    graph: In<'_, dk_graph>,
    points: In<'_, T>,
    _dim: Dim<D>,
    weights: Out<'_, T>,
) -> Result<(), dk_status> {
    let g = read_graph(graph)?;
    let p = read_points::<T, D>(points)?;
    Ok(inverse_distance_weights(&g, p, output(weights)?)?)
}

/// Arclength along grid lines in `direction` (0 = i, 1 = j, 2 = k) at every point:
/// `S_0 = 0`, `S_t = S_{t−1} + |p_t − p_{t−1}|`, or with `normalised` `s_t = S_t / S_{n−1}`
/// (a zero-length line gives the uniform `t / (n − 1)`). `points`: `ni·nj·nk·dim` scalars;
/// `out`: `ni·nj·nk` scalars. Nothing is written on error.
#[export(twin)]
pub(crate) fn dk_taubin_arclength<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    points: In<'_, T>,
    _dim: Dim<D>,
    direction: u32,
    normalised: bool,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let p = read_points::<T, D>(points)?;
    let o = output(out)?;
    Ok(arclength(&b, p, to_direction(direction)?, normalised, o)?)
}

/// Scratch length (in scalars) for [`dk_taubin_redistribute`]: `(dim + 1) ×` points per line
/// in `direction` (`DK_ERR_INVALID_PARAMETER` for `dim` not 2 or 3 or `direction > 2`).
#[export(len_out[1])]
pub(crate) fn dk_taubin_redistribute_scratch_len<const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    _dim: Dim<D>,
    direction: u32,
    len_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let d = crate::taubin::to_direction(direction)?;
    write_len(len_out, redistribute_scratch_len::<D>(&b, d))
}

/// Alter's reverse transformation: moves every point of every line in `direction` (in place)
/// to the arclength `targets[p]` measured on the line's *original* polyline (with
/// `normalised`, targets are fractions of the line length). Targets beyond an end extrapolate
/// along the last non-zero segment; zero-length lines are left as they are.
/// `*max_displacement_out` receives the largest point displacement. `scratch` needs
/// [`dk_taubin_redistribute_scratch_len`] scalars. On error `points` is unchanged.
#[export(twin, max_displacement_out[1])]
pub(crate) fn dk_taubin_redistribute<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    direction: u32,
    targets: In<'_, T>,
    normalised: bool,
    points: Out<'_, T>,
    _dim: Dim<D>,
    scratch: Out<'_, T>,
    max_displacement_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let t = input(targets)?;
    let p = chunks_mut::<T, D>(points)?;
    let s = output(scratch)?;
    let m = out_one(max_displacement_out)?;
    // The kernel validates everything before it moves a point.
    *m = redistribute(&b, p, to_direction(direction)?, t, normalised, s)?;
    Ok(())
}

/// Grid stretching along `direction` at every point: the ratio of the larger to the smaller
/// of the two cells meeting there (1 at line ends and for uniform spacing, `+∞` where one of
/// the two cells has zero length). `out`: `ni·nj·nk` scalars. Nothing is written on error.
#[export(twin)]
pub(crate) fn dk_taubin_stretching<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    points: In<'_, T>,
    _dim: Dim<D>,
    direction: u32,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let p = read_points::<T, D>(points)?;
    Ok(stretching(&b, p, to_direction(direction)?, output(out)?)?)
}

/// The largest stretching along `direction` (see [`dk_taubin_stretching`]) into
/// `*value_out`, and the 0-based linear index of the first point where it occurs into
/// `*point_out` (`1` and `0` when no point has two adjacent cells). Nothing is written on
/// error.
#[export(twin, value_out[1], point_out[1])]
pub(crate) fn dk_taubin_max_stretching<T: Real, const D: usize>(
    ni: usize,
    nj: usize,
    nk: usize,
    points: In<'_, T>,
    _dim: Dim<D>,
    direction: u32,
    value_out: Out<'_, T>,
    point_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let p = read_points::<T, D>(points)?;
    let v = out_one(value_out)?;
    let i = out_one(point_out)?;
    (*v, *i) = max_stretching(&b, p, to_direction(direction)?)?;
    Ok(())
}

/// The fold guard: `DK_OK` when `field` (an arclength function, `ni·nj·nk` scalars) increases
/// strictly along every line in `direction`, else `DK_ERR_FOLDED_LINE` (`iteration` is only
/// carried into the Rust error). With `points` (`ni·nj·nk·dim` scalars; NULL with
/// `points_len` 0 for none, then `dim` is ignored), lines whose points all coincide are
/// exempt. Writes nothing.
#[export(twin, points?)]
pub(crate) fn dk_taubin_check_lines_increasing<T: Real>(
    ni: usize,
    nj: usize,
    nk: usize,
    field: In<'_, T>,
    direction: u32,
    iteration: usize,
    points: In<'_, T>,
    dim: u32,
) -> Result<(), dk_status> {
    let b = block(ni, nj, nk)?;
    let f = input(field)?;
    match (points.is_absent(), dim) {
        // No points: `dim` is not used.
        (true, _) | (false, 3) => check_lines::<T, 3>(&b, f, direction, iteration, points),
        (false, 2) => check_lines::<T, 2>(&b, f, direction, iteration, points),
        _ => Err(dk_status::DK_ERR_INVALID_PARAMETER),
    }
}
