//! Grid-line tools: arclength distribution functions, redistribution along the original
//! polylines, stretching ratios and the fold check.

use core::cmp::Ordering;

use crate::block::{Block, Direction};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::vector;

/// The lines along `direction` of a block with dimensions `dims`: `(count, points per line,
/// stride)`.
#[inline]
pub(crate) fn line_shape(dims: [usize; 3], direction: Direction) -> (usize, usize, usize) {
    let [ni, nj, nk] = dims;
    match direction {
        Direction::I => (nj * nk, ni, 1),
        Direction::J => (ni * nk, nj, ni),
        Direction::K => (ni * nj, nk, ni * nj),
    }
}

/// Linear index of the first point of line `l` along `direction`.
#[inline]
pub(crate) fn line_base(dims: [usize; 3], direction: Direction, l: usize) -> usize {
    let [ni, nj, _] = dims;
    match direction {
        Direction::I => l * ni,
        Direction::J => {
            let ni1 = ni.max(1);
            (l % ni1) + ni * nj * (l / ni1)
        }
        Direction::K => l,
    }
}

/// Checks a points array against the block.
fn check_points<T: Real, const D: usize>(block: &Block, points: &[[T; D]]) -> Result<()> {
    let n = block.point_count();
    check::len("points", points.len(), n)?;
    check::finite_items("points", points)?;
    Ok(())
}

/// Writes the arclength of every line (no validation); see [`arclength`].
pub(crate) fn arclength_core<T: Real, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
    normalised: bool,
    out: &mut [T],
) {
    let (count, len, stride) = line_shape(dims, direction);
    for l in 0..count {
        let base = line_base(dims, direction, l);
        let mut s = T::ZERO;
        let mut prev: Option<[T; D]> = None;
        for t in 0..len {
            let p = base + t * stride;
            let Some(&x) = points.get(p) else { continue };
            if let Some(q) = prev {
                s += vector::distance(q, x);
            }
            prev = Some(x);
            if let Some(o) = out.get_mut(p) {
                *o = s;
            }
        }
        if normalised {
            let total = s;
            let last = T::from_usize(len.saturating_sub(1));
            for t in 0..len {
                let p = base + t * stride;
                if let Some(o) = out.get_mut(p) {
                    *o = if total > T::ZERO {
                        *o / total
                    } else if last > T::ZERO {
                        T::from_usize(t) / last
                    } else {
                        T::ZERO
                    };
                }
            }
        }
    }
}

/// Arclength distribution functions along `direction`: for every point
/// `p_t` of a line `p_0 … p_{n−1}`
///
/// ```text
/// S_0 = 0,   S_t = S_{t−1} + |p_t − p_{t−1}|            (dimensional)
/// s_t = S_t / S_{n−1}                                   (normalised, s_{n−1} = 1)
/// ```
///
/// Summed in line order. A line of zero total length (all points coincide) has `S_t = 0` and,
/// normalised, the uniform `s_t = t / (n − 1)` (no division by zero; `0` when `n = 1`).
/// Alter filters the dimensional function to smooth a grid and the normalised one to reduce
/// stretching.
///
/// # Errors
/// `LengthMismatch` (`points`, `out`), `NonFinite` (`points`).
pub fn arclength<T: Real, const D: usize>(
    block: &Block,
    points: &[[T; D]],
    direction: Direction,
    normalised: bool,
    out: &mut [T],
) -> Result<()> {
    check_points(block, points)?;
    check::len("out", out.len(), block.point_count())?;
    arclength_core(block.dims(), points, direction, normalised, out);
    Ok(())
}

/// Scratch length (in `T` values) for [`redistribute`]: `(D + 1) ×` points per line.
pub fn redistribute_scratch_len<const D: usize>(block: &Block, direction: Direction) -> usize {
    let (_, len, _) = line_shape(block.dims(), direction);
    (D + 1) * len
}

/// Reads point `t` of the line copy stored flat in `coords`.
#[inline]
fn line_point<T: Real, const D: usize>(coords: &[T], t: usize) -> [T; D] {
    let mut x = [T::ZERO; D];
    if let Some(c) = coords.get(t * D..t * D + D) {
        for (a, &b) in x.iter_mut().zip(c) {
            *a = b;
        }
    }
    x
}

/// `a + f (b − a)`, returning `a` itself when `f == 0`.
#[inline]
fn along<T: Real, const D: usize>(a: [T; D], b: [T; D], f: T) -> [T; D] {
    if f == T::ZERO {
        a
    } else {
        vector::add(a, vector::scale(vector::sub(b, a), f))
    }
}

/// Places a point at arclength `target` on the polyline `coords` with cumulative arclength
/// `s` (`len` points, total `s[len − 1] > 0`). `seg` is the search hint, updated.
fn place<T: Real, const D: usize>(
    s: &[T],
    coords: &[T],
    len: usize,
    target: T,
    seg: &mut usize,
) -> [T; D] {
    let last = len.saturating_sub(1);
    let get = |t: usize| s.get(t).copied().unwrap_or(T::ZERO);
    let total = get(last);
    if target <= T::ZERO {
        if target == T::ZERO {
            return line_point(coords, 0);
        }
        // Before the start: extrapolate along the first non-zero segment.
        let mut f = 0;
        while f + 1 < last && get(f + 1) <= T::ZERO {
            f += 1;
        }
        let (a, b) = (get(f), get(f + 1));
        let pa: [T; D] = line_point(coords, f);
        let pb: [T; D] = line_point(coords, f + 1);
        return along(pa, pb, (target - a) / (b - a));
    }
    if target >= total {
        if target == total {
            return line_point(coords, last);
        }
        // Beyond the end: extrapolate along the last non-zero segment, from the end point.
        let mut g = last;
        while g > 1 && get(g - 1) >= total {
            g -= 1;
        }
        let (a, b) = (get(g - 1), get(g));
        let pa: [T; D] = line_point(coords, g - 1);
        let pb: [T; D] = line_point(coords, last);
        return along(
            pb,
            vector::add(pb, vector::sub(pb, pa)),
            (target - b) / (b - a),
        );
    }
    // Inside: find m with s[m] <= target < s[m + 1] (then s[m + 1] > s[m]).
    let mut m = (*seg).min(last.saturating_sub(1));
    while m + 1 < last && get(m + 1) <= target {
        m += 1;
    }
    while m > 0 && get(m) > target {
        m -= 1;
    }
    *seg = m;
    let (a, b) = (get(m), get(m + 1));
    let pa: [T; D] = line_point(coords, m);
    let pb: [T; D] = line_point(coords, m + 1);
    along(pa, pb, (target - a) / (b - a))
}

/// Redistributes lines (no validation); returns the largest point displacement.
/// `skip(p, zero)` leaves point `p` untouched; `zero` says whether `p` ends a segment of zero
/// length of the original line.
pub(crate) fn redistribute_core<T: Real, const D: usize, F: Fn(usize, bool) -> bool>(
    dims: [usize; 3],
    points: &mut [[T; D]],
    direction: Direction,
    targets: &[T],
    normalised: bool,
    scratch: &mut [T],
    skip: F,
) -> T {
    let (count, len, stride) = line_shape(dims, direction);
    let Some((s, rest)) = scratch.split_at_mut_checked(len) else {
        return T::ZERO;
    };
    let Some(coords) = rest.get_mut(..len * D) else {
        return T::ZERO;
    };
    let mut max_move = T::ZERO;
    for l in 0..count {
        let base = line_base(dims, direction, l);
        // Copy the original line and its arclength.
        let mut acc = T::ZERO;
        let mut prev: Option<[T; D]> = None;
        for (t, (st, c)) in s.iter_mut().zip(coords.chunks_exact_mut(D)).enumerate() {
            let x = points
                .get(base + t * stride)
                .copied()
                .unwrap_or([T::ZERO; D]);
            if let Some(q) = prev {
                acc += vector::distance(q, x);
            }
            prev = Some(x);
            *st = acc;
            for (a, &b) in c.iter_mut().zip(&x) {
                *a = b;
            }
        }
        let total = acc;
        if total <= T::ZERO {
            // Collapsed line: every target maps to the single point; nothing moves.
            continue;
        }
        let mut seg = 0;
        for t in 0..len {
            let p = base + t * stride;
            let x: [T; D] = line_point(coords, t);
            let coincides = |u: usize| line_point::<T, D>(coords, u) == x;
            let zero = (t > 0 && coincides(t - 1)) || (t + 1 < len && coincides(t + 1));
            if skip(p, zero) {
                continue;
            }
            let Some(&raw) = targets.get(p) else { continue };
            let target = if normalised {
                if raw == T::ONE {
                    total
                } else {
                    raw * total
                }
            } else {
                raw
            };
            let new: [T; D] = place(s, coords, len, target, &mut seg);
            if let Some(x) = points.get_mut(p) {
                // Robust: a finite move longer than √MAX must not report +∞.
                let moved = vector::norm_robust(vector::sub(*x, new));
                if moved > max_move {
                    max_move = moved;
                }
                *x = new;
            }
        }
    }
    max_move
}

/// Moves every point of every line along `direction` to the arclength `targets[p]` measured on
/// the line's *original* polyline (Alter's reverse transformation). With `normalised`, targets
/// are fractions of the line length (`S = s · S_{n−1}`).
///
/// ```text
/// p_new = p_m + (S − S_m) / (S_{m+1} − S_m) · (p_{m+1} − p_m),   S_m ≤ S < S_{m+1}
/// ```
///
/// A target beyond the end is extrapolated along the last non-zero segment (before the
/// start: along the first non-zero segment); a target equal to an original `S_m` returns
/// `p_m` exactly, so zero-length segments are skipped rather than divided by. A line of zero
/// length is left as it is. Targets need not be monotone (a fold check is
/// [`check_lines_increasing`]). Returns the largest point displacement. `scratch` needs
/// [`redistribute_scratch_len`] values. On `Err` nothing is written.
///
/// # Errors
/// `LengthMismatch` (`points`, `targets`), `BufferTooSmall` (`scratch`), `NonFinite`
/// (`points`, `targets`).
pub fn redistribute<T: Real, const D: usize>(
    block: &Block,
    points: &mut [[T; D]],
    direction: Direction,
    targets: &[T],
    normalised: bool,
    scratch: &mut [T],
) -> Result<T> {
    check_points(block, points)?;
    let n = block.point_count();
    check::len("targets", targets.len(), n)?;
    let need = redistribute_scratch_len::<D>(block, direction);
    check::buffer("scratch", scratch.len(), need)?;
    check::finite("targets", targets)?;
    Ok(redistribute_core(
        block.dims(),
        points,
        direction,
        targets,
        normalised,
        scratch,
        |_, _| false,
    ))
}

/// Stretching ratio of two adjacent cell lengths: `max / min`, 1 when both are zero,
/// infinity when only one is.
#[inline]
fn ratio<T: Real>(a: T, b: T) -> T {
    let hi = a.max(b);
    let lo = a.min(b);
    if lo > T::ZERO {
        hi / lo
    } else if hi > T::ZERO {
        T::INFINITY
    } else {
        T::ONE
    }
}

/// Visits the stretching ratio at every point (no validation).
fn for_each_stretching<T: Real, const D: usize, F: FnMut(usize, T)>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
    mut f: F,
) {
    let (count, len, stride) = line_shape(dims, direction);
    for l in 0..count {
        let base = line_base(dims, direction, l);
        for t in 0..len {
            let p = base + t * stride;
            let r = if t == 0 || t + 1 >= len {
                T::ONE
            } else {
                match (
                    points.get(p - stride),
                    points.get(p),
                    points.get(p + stride),
                ) {
                    (Some(&a), Some(&b), Some(&c)) => {
                        ratio(vector::distance(a, b), vector::distance(b, c))
                    }
                    _ => T::ONE,
                }
            };
            f(p, r);
        }
    }
}

/// Grid stretching along `direction` at every point: the ratio of the larger to the smaller of
/// the two cells meeting there (Alter §II.C: 1 for uniform spacing, > 1 otherwise)
///
/// ```text
/// r_t = max(ΔS_t, ΔS_{t+1}) / min(ΔS_t, ΔS_{t+1}),   ΔS_t = |p_t − p_{t−1}|
/// ```
///
/// Line ends (one adjacent cell) get 1, two zero-length cells give 1, and one zero-length cell
/// next to a non-zero one gives `+∞`.
///
/// # Errors
/// `LengthMismatch` (`points`, `out`), `NonFinite` (`points`).
pub fn stretching<T: Real, const D: usize>(
    block: &Block,
    points: &[[T; D]],
    direction: Direction,
    out: &mut [T],
) -> Result<()> {
    check_points(block, points)?;
    check::len("out", out.len(), block.point_count())?;
    for_each_stretching(block.dims(), points, direction, |p, r| {
        if let Some(o) = out.get_mut(p) {
            *o = r;
        }
    });
    Ok(())
}

/// The largest stretching ratio along `direction` (see [`stretching`]) and the first point
/// where it occurs (lines in order, points along each line in order). `(1, 0)` for a block
/// with fewer than three points per line.
pub(crate) fn max_stretching_core<T: Real, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
) -> (T, usize) {
    let mut best = (T::ONE, 0);
    for_each_stretching(dims, points, direction, |p, r| {
        if r > best.0 {
            best = (r, p);
        }
    });
    best
}

/// The maximum of [`stretching`] over the block and the first point where it occurs (line by
/// line; `(1, 0)` when no point has two adjacent cells).
///
/// # Errors
/// `LengthMismatch` (`points`), `NonFinite` (`points`).
pub fn max_stretching<T: Real, const D: usize>(
    block: &Block,
    points: &[[T; D]],
    direction: Direction,
) -> Result<(T, usize)> {
    check_points(block, points)?;
    Ok(max_stretching_core(block.dims(), points, direction))
}

/// Fold check without validation; `collapsed(line_base)` exempts a line.
pub(crate) fn check_increasing_core<T: Real, F: Fn(usize) -> bool, Z: Fn(usize, usize) -> bool>(
    dims: [usize; 3],
    field: &[T],
    direction: Direction,
    iteration: usize,
    collapsed: F,
    zero_segment: Z,
) -> Result<()> {
    let (count, len, stride) = line_shape(dims, direction);
    for l in 0..count {
        let base = line_base(dims, direction, l);
        let mut prev: Option<(usize, T)> = None;
        for t in 0..len {
            let p = base + t * stride;
            let Some(&v) = field.get(p) else {
                continue;
            };
            if let Some((q, w)) = prev {
                // Anything but "greater" (equal, smaller, NaN) is a fold, but for an equal
                // value across a segment of zero length (held, so it stays equal).
                let ok = match v.partial_cmp(&w) {
                    Some(Ordering::Greater) => true,
                    Some(Ordering::Equal) => zero_segment(q, p),
                    _ => false,
                };
                if !ok && !collapsed(base) {
                    return Err(Error::FoldedLine {
                        line: base,
                        iteration,
                    });
                }
            }
            prev = Some((p, v));
        }
    }
    Ok(())
}

/// Whether points `p` and `q` coincide (a segment of zero length). For finite points,
/// coordinate equality is `distance == 0` without the square root: this runs for every point
/// in every filter sweep.
pub(crate) fn same_point<T: Real, const D: usize>(points: &[[T; D]], p: usize, q: usize) -> bool {
    match (points.get(p), points.get(q)) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// Whether point `p` ends a segment of zero length along `direction` (it coincides with its
/// predecessor or successor on its line).
pub(crate) fn on_zero_segment<T: Real, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
    p: usize,
) -> bool {
    let (_, len, stride) = line_shape(dims, direction);
    let t = (p / stride.max(1)) % len.max(1);
    (t > 0 && same_point(points, p - stride, p))
        || (t + 1 < len && same_point(points, p, p + stride))
}

/// The fold guard: checks that `field` (an arclength function) increases strictly along every
/// line in `direction`, `field_{t+1} > field_t`, else returns `FoldedLine { line, iteration }`
/// with `line` = the linear index of the line's first point and the caller's `iteration`.
/// When `points` is given, lines whose points all coincide (collapsed lines, e.g. a polar
/// axis) are exempt, and so is an equal value across a segment of zero length in `points`.
///
/// # Errors
/// `LengthMismatch` (`field`, `points`), `NonFinite` (`points`), `FoldedLine`.
pub fn check_lines_increasing<T: Real, const D: usize>(
    block: &Block,
    field: &[T],
    direction: Direction,
    iteration: usize,
    points: Option<&[[T; D]]>,
) -> Result<()> {
    let n = block.point_count();
    check::len("field", field.len(), n)?;
    if let Some(pts) = points {
        check_points(block, pts)?;
    }
    let dims = block.dims();
    check_increasing_core(
        dims,
        field,
        direction,
        iteration,
        |base| points.is_some_and(|pts| line_collapsed(dims, pts, direction, base)),
        |p, q| points.is_some_and(|pts| same_point(pts, p, q)),
    )
}

/// Whether every point of the line starting at `base` equals its first point.
pub(crate) fn line_collapsed<T: Real, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
    base: usize,
) -> bool {
    let (_, len, stride) = line_shape(dims, direction);
    let Some(&first) = points.get(base) else {
        return false;
    };
    (1..len).all(|t| {
        points
            .get(base + t * stride)
            .is_some_and(|&x| vector::distance(first, x) == T::ZERO)
    })
}
