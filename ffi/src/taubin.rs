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
#![allow(unsafe_code)] // `#[no_mangle] unsafe extern "C"`; raw pointers are only read via crate::slice.

use deform_kernel::taubin::{
    arclength, check_lines_increasing, graph_sweep, inverse_distance_weights, max_stretching,
    redistribute, redistribute_scratch_len, smooth_arclength, smooth_arclength_scratch_len,
    smooth_graph, smooth_structured, smooth_structured_coarse, stretching,
    structured_coarse_scratch_len, structured_scratch_len, structured_sweep, BlockRegion, Coarse,
    FilterReport, GraphOptions, Prolongation, SmoothOptions, SmoothReport, StructuredOptions,
    TaubinParams,
};
use deform_kernel::{Block, Direction, Directions, Graph, Real};

use crate::args::{
    assert_layout, block, by_components, by_dim, done, mul_len, optional, range, read_one,
    read_optional_points, read_points, write_len,
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
// Generic inner functions.
// ---------------------------------------------------------------------------------------------

fn params_paper<T: Real>(lambda_out: Out<'_, T>, mu_out: Out<'_, T>) -> dk_status {
    done((|| {
        let p = TaubinParams::<T>::paper();
        let l = out_one(lambda_out)?;
        let m = out_one(mu_out)?;
        *l = p.lambda;
        *m = p.mu;
        Ok(())
    })())
}

fn params_from_pass_band<T: Real>(
    lambda: T,
    pass_band: T,
    lambda_out: Out<'_, T>,
    mu_out: Out<'_, T>,
) -> dk_status {
    done((|| {
        let p = TaubinParams::from_pass_band(lambda, pass_band).map_err(dk_status::from)?;
        let l = out_one(lambda_out)?;
        let m = out_one(mu_out)?;
        *l = p.lambda;
        *m = p.mu;
        Ok(())
    })())
}

fn smooth_arclength_d<T: Real, const D: usize>(
    block: &Block,
    options: &dk_smooth_arclength_options,
    pinned: Option<&[u8]>,
    points: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_smooth_report>,
) -> Result<(), dk_status> {
    let opts = options.to_kernel::<T>(pinned)?;
    let p = chunks_mut::<T, D>(points)?;
    let s = output(scratch)?;
    let r = out_one(report)?;
    // The kernel validates everything before it moves a point: on Err `points` is unchanged.
    let rep = smooth_arclength(block, p, &opts, s).map_err(dk_status::from)?;
    *r = dk_smooth_report::of(rep);
    Ok(())
}

/// The structured filter, on the fine grid only (`coarse` None) or with a coarse-grid pass.
#[allow(clippy::too_many_arguments)]
fn smooth_structured_t<T: Real>(
    [ni, nj, nk]: [usize; 3],
    coarse: Option<In<'_, dk_taubin_coarse>>,
    lambda: T,
    mu: T,
    iterations: usize,
    options: In<'_, dk_structured_options>,
    field: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> dk_status {
    done((|| {
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
        let p = TaubinParams { lambda, mu };
        let rep = match c {
            None => smooth_structured(&b, f, p, iterations, &o, s),
            Some(c) => smooth_structured_coarse(&b, f, &c, p, iterations, &o, s),
        }
        .map_err(dk_status::from)?;
        *r = dk_filter_report::of(rep);
        Ok(())
    })())
}

#[allow(clippy::too_many_arguments)]
fn structured_sweep_t<T: Real>(
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
) -> dk_status {
    done((|| {
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
            let [a, z] = range(rl, rh, index_base)?;
            *l = a;
            *h = z;
        }
        let s = input(src)?;
        let d = output(dst)?;
        let m = out_one(max_change_out)?;
        let change = structured_sweep(&b, s, d, weight, &o, &BlockRegion { lo, hi })
            .map_err(dk_status::from)?;
        *m = change;
        Ok(())
    })())
}

/// Graph arguments shared by the graph filter functions.
struct GraphArgs<'a, T> {
    graph: In<'a, dk_graph>,
    weights: In<'a, T>,
    fixed: In<'a, u8>,
}

impl<'a, T> GraphArgs<'a, T> {
    fn read(&self) -> Result<(Graph<'a>, GraphOptions<'a, T>), dk_status> {
        let g = read_graph(self.graph)?;
        let o = GraphOptions {
            weights: optional(self.weights)?,
            fixed: optional(self.fixed)?,
        };
        Ok((g, o))
    }
}

fn smooth_graph_v<T: Real, const V: usize>(
    args: &GraphArgs<T>,
    params: TaubinParams<T>,
    iterations: usize,
    values: Out<'_, T>,
    scratch: Out<'_, T>,
    report: Out<'_, dk_filter_report>,
) -> Result<(), dk_status> {
    let (g, o) = args.read()?;
    let v = chunks_mut::<T, V>(values)?;
    // The scratch may be longer than needed: use only whole items.
    let s = whole_chunks_mut::<T, V>(scratch)?;
    let r = out_one(report)?;
    let rep = smooth_graph(&g, v, params, iterations, &o, s).map_err(dk_status::from)?;
    *r = dk_filter_report::of(rep);
    Ok(())
}

fn graph_sweep_v<T: Real, const V: usize>(
    args: &GraphArgs<T>,
    src: In<'_, T>,
    weight: T,
    nodes: [usize; 2],
    dst: Out<'_, T>,
    max_change_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let (g, o) = args.read()?;
    let s = chunks::<T, V>(src)?;
    let d = chunks_mut::<T, V>(dst)?;
    let m = out_one(max_change_out)?;
    let [a, b] = nodes;
    *m = graph_sweep(&g, s, d, weight, &o, a..b).map_err(dk_status::from)?;
    Ok(())
}

fn inverse_distance_weights_d<T: Real, const D: usize>(
    g: &Graph<'_>,
    points: In<'_, T>,
    weights: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let w = output(weights)?;
    inverse_distance_weights(g, p, w).map_err(dk_status::from)
}

fn arclength_d<T: Real, const D: usize>(
    b: &Block,
    points: In<'_, T>,
    direction: u32,
    normalised: bool,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let o = output(out)?;
    arclength(b, p, to_direction(direction)?, normalised, o).map_err(dk_status::from)
}

fn redistribute_d<T: Real, const D: usize>(
    b: &Block,
    direction: u32,
    targets: In<'_, T>,
    normalised: bool,
    points: Out<'_, T>,
    scratch: Out<'_, T>,
    max_displacement_out: Out<'_, T>,
) -> Result<(), dk_status> {
    let t = input(targets)?;
    let p = chunks_mut::<T, D>(points)?;
    let s = output(scratch)?;
    let m = out_one(max_displacement_out)?;
    // The kernel validates everything before it moves a point.
    *m = redistribute(b, p, to_direction(direction)?, t, normalised, s).map_err(dk_status::from)?;
    Ok(())
}

fn stretching_d<T: Real, const D: usize>(
    b: &Block,
    points: In<'_, T>,
    direction: u32,
    out: Out<'_, T>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let o = output(out)?;
    stretching(b, p, to_direction(direction)?, o).map_err(dk_status::from)
}

fn max_stretching_d<T: Real, const D: usize>(
    b: &Block,
    points: In<'_, T>,
    direction: u32,
    value_out: Out<'_, T>,
    point_out: Out<'_, usize>,
) -> Result<(), dk_status> {
    let p = read_points::<T, D>(points)?;
    let v = out_one(value_out)?;
    let i = out_one(point_out)?;
    let (r, at) = max_stretching(b, p, to_direction(direction)?).map_err(dk_status::from)?;
    *v = r;
    *i = at;
    Ok(())
}

fn check_lines_d<T: Real, const D: usize>(
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

#[allow(clippy::too_many_arguments)]
fn check_lines_t<T: Real>(
    ni: usize,
    nj: usize,
    nk: usize,
    field: In<'_, T>,
    direction: u32,
    iteration: usize,
    points: In<'_, T>,
    dim: u32,
) -> dk_status {
    done((|| {
        let b = block(ni, nj, nk)?;
        let f = input(field)?;
        if points.is_absent() {
            // No points: `dim` is not used.
            return check_lines_d::<T, 3>(&b, f, direction, iteration, points);
        }
        by_dim!(
            dim,
            check_lines_d::<T>,
            (&b, f, direction, iteration, points)
        )
    })())
}

mod abi;
pub use abi::*;
