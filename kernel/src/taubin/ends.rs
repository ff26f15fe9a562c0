//! Line ends of [`smooth_arclength`](super::smooth_arclength): fixed (the default) or free
//! to slide along the line's extension (Alter's outer boundary), the seam check for free
//! ends, and the map of a fixed-end line's filtered arclength onto its original ends.

use crate::block::Direction;
use crate::error::{Error, Result};
use crate::real::Real;
use crate::vector;

use super::lines::{line_base, line_shape, same_point};

/// What the points at one end of every grid line do in
/// [`smooth_arclength`](super::smooth_arclength).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LineEnd {
    /// The end point stays bitwise where it is (O-grid seams, walls, block interfaces stay
    /// closed). With dimensional arclength the filtered field of each line is mapped onto its
    /// original end value before the points are redistributed.
    #[default]
    Fixed,
    /// The end point slides along its line to its filtered arclength: inside the line, or
    /// beyond its end along the extension of its last segment of non-zero length (Alter's
    /// extrapolation at the outer boundary). Only the last end of a line can be free, only
    /// with dimensional arclength, and only where no end point coincides with another grid
    /// point of its face (a seam or a collapsed axis; the face's rim is compared). The kernel
    /// sees one block: a face shared with another block is the caller's to check (`deform
    /// smooth` refuses a free face with any point shared with another grid point).
    Free,
}

/// Checks the end modes: the first end of a line is where arclength is measured from (`S = 0`
/// there, which the filter keeps), so it cannot be free; a free last end needs the
/// dimensional arclength (the normalised `s = 1` there never changes).
pub(crate) fn validate_ends(ends: [LineEnd; 2], normalised: bool) -> Result<()> {
    if ends[0] == LineEnd::Free {
        return Err(Error::InvalidParameter {
            arg: "options.ends",
            reason: "the first end of a line cannot be free: arclength is measured from it",
        });
    }
    if ends[1] == LineEnd::Free && normalised {
        return Err(Error::InvalidParameter {
            arg: "options.ends",
            reason: "a free end needs the dimensional arclength (normalised s = 1 never moves)",
        });
    }
    Ok(())
}

/// Linear index of the last point of line `l`.
#[inline]
fn last_point(dims: [usize; 3], direction: Direction, l: usize) -> usize {
    let (_, len, stride) = line_shape(dims, direction);
    line_base(dims, direction, l) + len.saturating_sub(1) * stride
}

/// Whether line `l` ends on the rim of the face of line ends (the face is `a × b` lines,
/// `l = u + a v`). Seams, wake cuts and collapsed axes of a structured block meet that face
/// on its rim.
#[inline]
fn on_rim(l: usize, a: usize, b: usize) -> bool {
    let (u, v) = (l % a.max(1), l / a.max(1));
    u == 0 || v == 0 || u + 1 >= a || v + 1 >= b
}

/// The shape `(a, b)` of the face of line ends: the two other dimensions, first the faster.
#[inline]
fn face_shape(dims: [usize; 3], direction: Direction) -> (usize, usize) {
    let [ni, nj, nk] = dims;
    match direction {
        Direction::I => (nj, nk),
        Direction::J => (ni, nk),
        Direction::K => (ni, nj),
    }
}

/// Refuses a free last end whose point coincides (bit for bit, `−0 = +0`) with the end point
/// of another line of the block: every rim point of the face of line ends is compared with
/// every other rim point (`O(rim²)`, no allocation).
pub(crate) fn check_free_face<T: Real, const D: usize>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
) -> Result<()> {
    let (count, len, _) = line_shape(dims, direction);
    if len < 2 {
        return Ok(());
    }
    let (a, b) = face_shape(dims, direction);
    let rim = |l: &usize| on_rim(*l, a, b);
    for l in (0..count).filter(rim) {
        let p = last_point(dims, direction, l);
        for m in (l + 1..count).filter(rim) {
            let q = last_point(dims, direction, m);
            if same_point(points, p, q) {
                return Err(Error::SharedFreeEnd { point: p, other: q });
            }
        }
    }
    Ok(())
}

/// Fixed last ends with dimensional arclength: maps every line's filtered field `S̃` onto its
/// original end value `E` (the first end stays 0), `S = (S̃ / S̃_end) · E`, so a line the
/// filter keeps increasing stays increasing. Points that `held(p)` keep their field value
/// (they do not move); the end gets `E` exactly. Collapsed lines and lines whose filtered
/// end is not positive (folded; the fold guard reports them) are left as they are.
pub(crate) fn map_onto_fixed_ends<T: Real, const D: usize, H: Fn(usize) -> bool>(
    dims: [usize; 3],
    points: &[[T; D]],
    direction: Direction,
    field: &mut [T],
    held: H,
) {
    let (count, len, stride) = line_shape(dims, direction);
    for l in 0..count {
        let base = line_base(dims, direction, l);
        let end = last_point(dims, direction, l);
        // The original total, summed in line order as `arclength` does.
        let mut total = T::ZERO;
        for t in 1..len {
            let p = base + t * stride;
            if let (Some(&x), Some(&y)) = (points.get(p - stride), points.get(p)) {
                total += vector::distance(x, y);
            }
        }
        let filtered = field.get(end).copied().unwrap_or(T::ZERO);
        if total <= T::ZERO || filtered <= T::ZERO {
            continue;
        }
        for t in 1..len {
            let p = base + t * stride;
            if let Some(s) = field.get_mut(p) {
                if p == end {
                    *s = total;
                } else if !held(p) {
                    *s = *s / filtered * total;
                }
            }
        }
    }
}
