//! The structured scalar filter: Alter's stencils on a 1D/2D/3D block.

use crate::block::{Block, Directions};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::TaubinParams;

/// Options shared by the structured filter routines.
///
/// `fixed` is one byte per point, nonzero = the point keeps its value (a `u8` rather than a
/// `bool` so a C or Fortran caller can pass its own integer array). A direction `d` in `mirror`
/// switches the faces normal to `d` from the paper's rule (drop the normal derivative: in-plane
/// average) to a mirror/Neumann rule (the missing neighbour is the mirror image of the one
/// inside, so the face point averages `2 × inside` with its in-plane neighbours).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StructuredOptions<'a> {
    /// Optional fixed-point mask (`point_count` bytes, nonzero = fixed).
    pub fixed: Option<&'a [u8]>,
    /// The directions whose faces mirror (Neumann). [`Directions::NONE`] is the paper's rule.
    pub mirror: Directions,
}

/// A box of grid indices `lo[d] ≤ index[d] < hi[d]`: the points one [`structured_sweep`]
/// updates (for example the points a rank owns, between halo exchanges).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockRegion {
    /// First index per direction (inclusive).
    pub lo: [usize; 3],
    /// Last index per direction (exclusive).
    pub hi: [usize; 3],
}

impl BlockRegion {
    /// The whole block.
    pub fn all(block: &Block) -> Self {
        BlockRegion {
            lo: [0; 3],
            hi: block.dims(),
        }
    }

    /// Checks `lo ≤ hi ≤ dims` in every direction.
    fn validate(&self, dims: [usize; 3]) -> Result<()> {
        for (d, ((&lo, &hi), &n)) in self.lo.iter().zip(&self.hi).zip(&dims).enumerate() {
            if hi > n {
                return Err(Error::IndexOutOfRange {
                    arg: "region.hi",
                    position: d,
                    index: hi,
                    bound: n + 1,
                });
            }
            if lo > hi {
                return Err(Error::IndexOutOfRange {
                    arg: "region.lo",
                    position: d,
                    index: lo,
                    bound: hi + 1,
                });
            }
        }
        Ok(())
    }
}

/// What a whole filter run did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct FilterReport<T> {
    /// Iterations performed (one iteration = λ pass + μ pass).
    pub iterations: usize,
    /// Largest `|change|` of any value in either pass of the last iteration (0 when no
    /// iteration ran): a cheap "amount of movement" to decide whether to continue.
    pub last_change: T,
}

/// Scratch length (in `T` values) for [`smooth_structured`]: one field, `point_count`.
pub fn structured_scratch_len(block: &Block) -> usize {
    block.point_count()
}

/// Whether point `p` is fixed.
#[inline]
pub(crate) fn is_fixed(mask: Option<&[u8]>, p: usize) -> bool {
    match mask {
        Some(m) => m.get(p).is_some_and(|&b| b != 0),
        None => false,
    }
}

/// The paper's average at point `p = (i, j, k)` of a block with dimensions `dims`
/// (eqs. 2–4), or `None` when the point has no neighbour to average (a corner).
///
/// Directions are visited in the order i, j, k; in each the lower neighbour is added before
/// the upper one, and the sum is divided by the neighbour count.
#[inline]
pub(crate) fn stencil_average<T: Real>(
    dims: [usize; 3],
    src: &[T],
    idx: [usize; 3],
    p: usize,
    mirror: [bool; 3],
) -> Option<T> {
    let strides = [1, dims[0], dims[0] * dims[1]];
    let mut sum = T::ZERO;
    let mut count = 0usize;
    for (((&n, &s), &c), &m) in dims.iter().zip(&strides).zip(&idx).zip(&mirror) {
        if n < 2 {
            continue;
        }
        let (lower, upper) = if c == 0 {
            if !m {
                continue;
            }
            (p + s, p + s)
        } else if c + 1 >= n {
            if !m {
                continue;
            }
            (p - s, p - s)
        } else {
            (p - s, p + s)
        };
        let (Some(&a), Some(&b)) = (src.get(lower), src.get(upper)) else {
            continue;
        };
        sum += a;
        sum += b;
        count += 2;
    }
    if count == 0 {
        None
    } else {
        Some(sum / T::from_usize(count))
    }
}

/// One Jacobi pass over `region` of a field on a block with dimensions `dims`:
/// `dst = src + w (avg(src) − src)` at every point in the region whose `fixed(idx, p)` is
/// false, `dst = src` at fixed points. Returns the largest `|dst − src|`. No validation.
///
/// Rows (lines along i) whose j and k are interior take a straight loop over their interior
/// points ([`interior_run`]: row slices fetched once, no index tests); the boundary shell
/// takes the general rule ([`stencil_average`]). Both sum the same neighbours in the same
/// order and divide by the same count, so the bits are those of the general rule everywhere.
pub(crate) fn sweep_core<T: Real, P: Fn([usize; 3], usize) -> bool>(
    dims: [usize; 3],
    src: &[T],
    dst: &mut [T],
    weight: T,
    mirror: [bool; 3],
    region: &BlockRegion,
    fixed: P,
) -> T {
    let [ni, nj, nk] = dims;
    // The straight loop covers the blocks whose active directions are i, (i, j) or (i, j, k).
    let active = if ni < 2 {
        0
    } else if nj < 2 {
        if nk < 2 {
            1
        } else {
            0
        }
    } else if nk < 2 {
        2
    } else {
        3
    };
    // Interior i (both neighbours inside): 1 ≤ i < ni − 1, clipped to the region.
    let ilo = region.lo[0].max(1);
    let ihi = region.hi[0].min(ni.saturating_sub(1));
    let interior = |c: usize, n: usize| n < 2 || (c >= 1 && c + 1 < n);
    let mut max_change = T::ZERO;
    let general = |i: usize, j: usize, k: usize, dst: &mut [T], max_change: &mut T| {
        let p = i + ni * (j + nj * k);
        let Some(&x) = src.get(p) else { return };
        let idx = [i, j, k];
        let new = if fixed(idx, p) {
            x
        } else {
            match stencil_average(dims, src, idx, p, mirror) {
                Some(avg) => x + weight * (avg - x),
                None => x,
            }
        };
        if let Some(out) = dst.get_mut(p) {
            *out = new;
        }
        let change = (new - x).abs();
        if change > *max_change {
            *max_change = change;
        }
    };
    for k in region.lo[2]..region.hi[2] {
        for j in region.lo[1]..region.hi[1] {
            let fast = active > 0 && ilo < ihi && interior(j, nj) && interior(k, nk);
            if !fast {
                for i in region.lo[0]..region.hi[0] {
                    general(i, j, k, dst, &mut max_change);
                }
                continue;
            }
            for i in region.lo[0]..ilo {
                general(i, j, k, dst, &mut max_change);
            }
            let row = ni * (j + nj * k);
            let m = interior_run(
                src,
                dst,
                row,
                [ilo, ihi],
                [ni, ni * nj],
                active,
                weight,
                |i, p| fixed([i, j, k], p),
            );
            if m > max_change {
                max_change = m;
            }
            for i in ihi..region.hi[0] {
                general(i, j, k, dst, &mut max_change);
            }
        }
    }
    max_change
}

/// The straight loop over the interior points `i ∈ [lo, hi)` of the row starting at `row`:
/// the neighbours along i, then j (stride `strides[0]`), then k (`strides[1]`), lower before
/// upper, for the first `active` directions, summed from zero and divided by their count,
/// exactly as [`stencil_average`] does. Returns the largest change.
#[allow(clippy::too_many_arguments)]
#[inline]
fn interior_run<T: Real, P: Fn(usize, usize) -> bool>(
    src: &[T],
    dst: &mut [T],
    row: usize,
    [lo, hi]: [usize; 2],
    strides: [usize; 2],
    active: usize,
    weight: T,
    fixed: P,
) -> T {
    let len = hi - lo;
    let at = |offset: isize| -> &[T] {
        let start = (row + lo).wrapping_add_signed(offset);
        start
            .checked_add(len)
            .and_then(|end| src.get(start..end))
            .unwrap_or(&[])
    };
    let sj = strides[0] as isize;
    let sk = strides[1] as isize;
    let count = T::from_usize(2 * active);
    let (x0, im, ip) = (at(0), at(-1), at(1));
    let Some(out) = dst.get_mut(row + lo..row + hi) else {
        return T::ZERO;
    };
    let mut max_change = T::ZERO;
    let mut finish = |t: usize, x: T, sum: T, o: &mut T| {
        let new = if fixed(lo + t, row + lo + t) {
            x
        } else {
            x + weight * (sum / count - x)
        };
        *o = new;
        let change = (new - x).abs();
        if change > max_change {
            max_change = change;
        }
    };
    match active {
        1 => {
            for (t, (((o, &x), &a), &b)) in out.iter_mut().zip(x0).zip(im).zip(ip).enumerate() {
                let mut sum = T::ZERO;
                sum += a;
                sum += b;
                finish(t, x, sum, o);
            }
        }
        2 => {
            let (jm, jp) = (at(-sj), at(sj));
            for (t, (((((o, &x), &a), &b), &c), &d)) in out
                .iter_mut()
                .zip(x0)
                .zip(im)
                .zip(ip)
                .zip(jm)
                .zip(jp)
                .enumerate()
            {
                let mut sum = T::ZERO;
                sum += a;
                sum += b;
                sum += c;
                sum += d;
                finish(t, x, sum, o);
            }
        }
        _ => {
            let (jm, jp, km, kp) = (at(-sj), at(sj), at(-sk), at(sk));
            for (t, (((((((o, &x), &a), &b), &c), &d), &e), &f)) in out
                .iter_mut()
                .zip(x0)
                .zip(im)
                .zip(ip)
                .zip(jm)
                .zip(jp)
                .zip(km)
                .zip(kp)
                .enumerate()
            {
                let mut sum = T::ZERO;
                sum += a;
                sum += b;
                sum += c;
                sum += d;
                sum += e;
                sum += f;
                finish(t, x, sum, o);
            }
        }
    }
    max_change
}

/// Runs `iterations` λ|μ iterations on `field` with ping-pong through `scratch` (no
/// validation). Returns the report.
pub(crate) fn filter_core<T: Real, P: Fn([usize; 3], usize) -> bool + Copy>(
    dims: [usize; 3],
    field: &mut [T],
    scratch: &mut [T],
    params: TaubinParams<T>,
    iterations: usize,
    mirror: [bool; 3],
    fixed: P,
) -> FilterReport<T> {
    let region = BlockRegion {
        lo: [0; 3],
        hi: dims,
    };
    let mut last_change = T::ZERO;
    for _ in 0..iterations {
        let a = sweep_core(dims, field, scratch, params.lambda, mirror, &region, fixed);
        let b = sweep_core(dims, scratch, field, params.mu, mirror, &region, fixed);
        last_change = a.max(b);
    }
    FilterReport {
        iterations,
        last_change,
    }
}

/// Smooths a scalar field on a structured block with `iterations` Taubin λ|μ iterations.
///
/// Each iteration is two Jacobi passes from the previous field (Alter eqs. 5, 6):
///
/// ```text
/// x' = x  + λ (avg(x)  − x)        (forward, smoothing)
/// x″ = x' + μ (avg(x') − x')       (backward, shape recovery)
/// avg = (1/6) Σ 6 neighbours (interior, eq. 2)
///     = (1/4) Σ 4 in-plane neighbours (face, eq. 3)
///     = (1/2) Σ 2 neighbours along the edge (edge, eq. 4); corners are not moved
/// ```
///
/// Directions with a single point are ignored, so the same rule serves 1D (`[n, 1, 1]`:
/// interior `(x₋ + x₊)/2`, ends fixed), 2D and 3D blocks. With ``d` in `options.mirror`` the faces
/// normal to `d` use the mirror image as the missing neighbour instead. Pinned points keep
/// their value. `scratch` needs [`structured_scratch_len`] values; its contents afterwards are
/// unspecified. On `Err` nothing is written.
///
/// # Errors
/// `LengthMismatch` (`field`, `options.fixed`), `BufferTooSmall` (`scratch`), `NonFinite`
/// (`field`, `lambda`, `mu`), `InvalidParameter` (`lambda ≤ 0`, `mu > 0`).
pub fn smooth_structured<T: Real>(
    block: &Block,
    field: &mut [T],
    params: TaubinParams<T>,
    iterations: usize,
    options: &StructuredOptions<'_>,
    scratch: &mut [T],
) -> Result<FilterReport<T>> {
    let n = block.point_count();
    check::len("field", field.len(), n)?;
    check::mask("options.fixed", options.fixed, n)?;
    check::buffer("scratch", scratch.len(), n)?;
    params.validate()?;
    check::finite("field", field)?;
    let fixed = options.fixed;
    Ok(filter_core(
        block.dims(),
        field,
        scratch,
        params,
        iterations,
        options.mirror.flags(),
        |_, p| is_fixed(fixed, p),
    ))
}

/// One Jacobi pass over `region` only: `dst = src + weight · (avg(src) − src)` at every free
/// point of the region (`dst = src` at fixed points); `dst` outside the region is not
/// touched. Returns the largest `|dst − src|` in the region (the local max change).
///
/// This is the building block for distributed runs: an iteration of [`smooth_structured`] is
/// `structured_sweep(field → tmp, λ)` then `structured_sweep(tmp → field, μ)` over the whole
/// block; an MPI code sweeps its own points and exchanges halo values of `src` before each
/// pass. `avg` is the stencil of [`smooth_structured`] evaluated on the whole `src`.
///
/// # Errors
/// `LengthMismatch` (`src`, `dst`, `options.fixed`), `IndexOutOfRange` (`region`),
/// `NonFinite` (`weight`, `src`).
pub fn structured_sweep<T: Real>(
    block: &Block,
    src: &[T],
    dst: &mut [T],
    weight: T,
    options: &StructuredOptions<'_>,
    region: &BlockRegion,
) -> Result<T> {
    let n = block.point_count();
    check::len("src", src.len(), n)?;
    check::len("dst", dst.len(), n)?;
    check::mask("options.fixed", options.fixed, n)?;
    region.validate(block.dims())?;
    check::scalar("weight", weight)?;
    check::finite("src", src)?;
    let fixed = options.fixed;
    Ok(sweep_core(
        block.dims(),
        src,
        dst,
        weight,
        options.mirror.flags(),
        region,
        |_, p| is_fixed(fixed, p),
    ))
}
