//! The coarse-grid (multi-grid) variant of the structured filter (Alter §III.B, fig. 9).

use crate::block::Block;
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::structured::{is_fixed, sweep_core, BlockRegion, FilterReport, StructuredOptions};
use super::TaubinParams;

/// How the smoothed coarse field is brought back to the fine grid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Prolongation {
    /// The fine field becomes the (multi)linear interpolation of the smoothed coarse field:
    /// Alter's "prolongation of the arclength functions". Removes all fine-scale content
    /// between coarse points.
    #[default]
    Values,
    /// The fine field gets the interpolated coarse *change* added (`x += I(x_c' − x_c)`):
    /// keeps fine-scale content the coarse grid cannot see.
    Correction,
}

/// Coarse-grid settings: keep every `factor[d]`-th index in direction `d` (1 = do not
/// coarsen; the last index is always kept) and the prolongation rule.
///
/// Alter coarsened by 4 in the two directions tangent to the wall and not at all along the
/// smoothed (wall-normal) direction: `factor = [4, 4, 1]` for k-lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coarse {
    /// Sampling factor per direction (each ≥ 1).
    pub factor: [usize; 3],
    /// Prolongation rule.
    pub prolongation: Prolongation,
}

impl Coarse {
    /// Checks every factor ≥ 1.
    pub(crate) fn validate(&self) -> Result<()> {
        if self.factor.contains(&0) {
            return Err(Error::InvalidParameter {
                arg: "coarse.factor",
                reason: "every factor must be >= 1",
            });
        }
        Ok(())
    }
}

/// Coarse point count in one direction: indices `0, m, 2m, …` plus the last index `n − 1`.
#[inline]
fn coarse_len(n: usize, m: usize) -> usize {
    if m <= 1 || n <= 2 {
        n
    } else {
        (n - 2) / m + 2
    }
}

/// Fine index of coarse index `c`: `min(c m, n − 1)`.
#[inline]
fn fine_index(c: usize, n: usize, m: usize) -> usize {
    (c * m.max(1)).min(n.saturating_sub(1))
}

/// Dimensions of the coarse block for `factor` (see [`Coarse`]): `n_c = ⌊(n − 2)/m⌋ + 2`
/// for `n > 2`, `m > 1`, else `n`. Factors of 0 are treated as 1.
pub fn coarse_dims(block: &Block, factor: [usize; 3]) -> [usize; 3] {
    let d = block.dims();
    [
        coarse_len(d[0], factor[0]),
        coarse_len(d[1], factor[1]),
        coarse_len(d[2], factor[2]),
    ]
}

/// Scratch length (in `T` values) for [`smooth_structured_coarse`]: two coarse fields.
pub fn structured_coarse_scratch_len(block: &Block, coarse: &Coarse) -> usize {
    let [a, b, c] = coarse_dims(block, coarse.factor);
    2 * a * b * c
}

/// Fine linear index of a coarse `(i, j, k)`.
#[inline]
pub(crate) fn fine_of(dims: [usize; 3], factor: [usize; 3], idx: [usize; 3]) -> usize {
    let i = fine_index(idx[0], dims[0], factor[0]);
    let j = fine_index(idx[1], dims[1], factor[1]);
    let k = fine_index(idx[2], dims[2], factor[2]);
    i + dims[0] * (j + dims[1] * k)
}

/// The coarse interval holding fine index `i`: `(c0, c1, t)` with the fine value
/// `(1 − t) x_c0 + t x_c1`.
#[inline]
fn bracket<T: Real>(i: usize, n: usize, nc: usize, m: usize) -> (usize, usize, T) {
    if nc < 2 {
        return (0, 0, T::ZERO);
    }
    let m = if nc == n { 1 } else { m.max(1) };
    let c0 = (i / m).min(nc - 2);
    let f0 = fine_index(c0, n, m);
    let f1 = fine_index(c0 + 1, n, m);
    let t = if f1 > f0 {
        T::from_usize(i.saturating_sub(f0)) / T::from_usize(f1 - f0)
    } else {
        T::ZERO
    };
    (c0, c0 + 1, t)
}

/// Multilinear interpolation of the coarse field at fine `(i, j, k)`; terms with a zero weight
/// are skipped, so a fine point on a coarse point gets the coarse value exactly.
fn interpolate<T: Real>(
    dims: [usize; 3],
    cdims: [usize; 3],
    factor: [usize; 3],
    coarse: &[T],
    idx: [usize; 3],
) -> T {
    let bi = bracket::<T>(idx[0], dims[0], cdims[0], factor[0]);
    let bj = bracket::<T>(idx[1], dims[1], cdims[1], factor[1]);
    let bk = bracket::<T>(idx[2], dims[2], cdims[2], factor[2]);
    let side = |b: (usize, usize, T)| [(b.0, T::ONE - b.2), (b.1, b.2)];
    let mut acc = T::ZERO;
    for (ck, wk) in side(bk) {
        for (cj, wj) in side(bj) {
            for (ci, wi) in side(bi) {
                let w = wk * wj * wi;
                if w == T::ZERO {
                    continue;
                }
                let c = ci + cdims[0] * (cj + cdims[1] * ck);
                if let Some(&v) = coarse.get(c) {
                    acc += w * v;
                }
            }
        }
    }
    acc
}

/// Restriction, coarse filtering and prolongation without validation. `check(coarse_field,
/// iteration)` runs after every coarse iteration (the fold guard of the driver); `fixed(p)`
/// takes a fine linear index. `scratch` holds at least two coarse fields.
#[allow(clippy::too_many_arguments)]
pub(crate) fn coarse_core<
    T: Real,
    P: Fn(usize) -> bool + Copy,
    C: FnMut(&[T], usize) -> Result<()>,
>(
    dims: [usize; 3],
    field: &mut [T],
    coarse: &Coarse,
    params: TaubinParams<T>,
    iterations: usize,
    mirror: [bool; 3],
    fixed: P,
    scratch: &mut [T],
    mut check: C,
) -> Result<FilterReport<T>> {
    let factor = coarse.factor;
    let cdims = [
        coarse_len(dims[0], factor[0]),
        coarse_len(dims[1], factor[1]),
        coarse_len(dims[2], factor[2]),
    ];
    let nc = cdims[0] * cdims[1] * cdims[2];
    let Some((a, rest)) = scratch.split_at_mut_checked(nc) else {
        return Ok(FilterReport {
            iterations: 0,
            last_change: T::ZERO,
        });
    };
    let Some(b) = rest.get_mut(..nc) else {
        return Ok(FilterReport {
            iterations: 0,
            last_change: T::ZERO,
        });
    };
    // Restriction: inject every m-th value (last index always included).
    let mut c = 0;
    for k in 0..cdims[2] {
        for j in 0..cdims[1] {
            for i in 0..cdims[0] {
                let f = fine_of(dims, factor, [i, j, k]);
                if let (Some(dst), Some(&v)) = (a.get_mut(c), field.get(f)) {
                    *dst = v;
                }
                c += 1;
            }
        }
    }
    let coarse_fixed = |idx: [usize; 3], _: usize| fixed(fine_of(dims, factor, idx));
    let region = BlockRegion {
        lo: [0; 3],
        hi: cdims,
    };
    let mut last_change = T::ZERO;
    for it in 1..=iterations {
        let x = sweep_core(cdims, a, b, params.lambda, mirror, &region, coarse_fixed);
        let y = sweep_core(cdims, b, a, params.mu, mirror, &region, coarse_fixed);
        last_change = x.max(y);
        check(a, it)?;
    }
    // Prolongation.
    if coarse.prolongation == Prolongation::Correction {
        let mut c = 0;
        for k in 0..cdims[2] {
            for j in 0..cdims[1] {
                for i in 0..cdims[0] {
                    let f = fine_of(dims, factor, [i, j, k]);
                    if let (Some(dst), Some(&v)) = (a.get_mut(c), field.get(f)) {
                        *dst -= v;
                    }
                    c += 1;
                }
            }
        }
    }
    let [ni, nj, nk] = dims;
    for k in 0..nk {
        for j in 0..nj {
            for i in 0..ni {
                let p = i + ni * (j + nj * k);
                if fixed(p) {
                    continue;
                }
                let v = interpolate(dims, cdims, factor, a, [i, j, k]);
                if let Some(x) = field.get_mut(p) {
                    match coarse.prolongation {
                        Prolongation::Values => *x = v,
                        Prolongation::Correction => *x += v,
                    }
                }
            }
        }
    }
    Ok(FilterReport {
        iterations,
        last_change,
    })
}

/// The coarse-grid variant of [`smooth_structured`](super::smooth_structured): restrict the
/// field to every `factor[d]`-th index (the last index always included), run `iterations`
/// λ|μ iterations there with the same stencils, then prolong back by multilinear
/// interpolation in index space (see [`Prolongation`]).
///
/// ```text
/// x_c[c] = x[min(c·m, n − 1)]                       (restriction, per direction)
/// x_c ← (1 − μ L)(1 − λ L) x_c, iterated            (coarse smoothing, L = I − avg)
/// x[i] = (1 − t) x_c[c] + t x_c[c + 1],  t = (i − f_c)/(f_{c+1} − f_c)   (prolongation)
/// ```
///
/// Ripples several fine cells long are high frequencies on the coarse grid, so a few coarse
/// iterations remove what many fine ones cannot; Alter smooths the fine grid first and the
/// coarse grid second. Fixed fine points keep their value (and fix their coarse image).
/// `scratch` needs [`structured_coarse_scratch_len`] values. On `Err` nothing is written.
///
/// # Errors
/// As [`smooth_structured`](super::smooth_structured), plus `InvalidParameter`
/// (`coarse.factor` with a zero).
pub fn smooth_structured_coarse<T: Real>(
    block: &Block,
    field: &mut [T],
    coarse: &Coarse,
    params: TaubinParams<T>,
    iterations: usize,
    options: &StructuredOptions<'_>,
    scratch: &mut [T],
) -> Result<FilterReport<T>> {
    let n = block.point_count();
    check::len("field", field.len(), n)?;
    check::mask("options.fixed", options.fixed, n)?;
    coarse.validate()?;
    let need = structured_coarse_scratch_len(block, coarse);
    check::buffer("scratch", scratch.len(), need)?;
    params.validate()?;
    check::finite("field", field)?;
    let fixed = options.fixed;
    coarse_core(
        block.dims(),
        field,
        coarse,
        params,
        iterations,
        options.mirror.flags(),
        |p| is_fixed(fixed, p),
        scratch,
        |_, _| Ok(()),
    )
}
