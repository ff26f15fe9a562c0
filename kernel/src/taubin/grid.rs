//! The whole-grid driver: arclength functions → Taubin filter (fine, then optionally coarse)
//! → fold guard → redistribution along the original lines.

use crate::block::{Block, Direction, Directions};
use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

use super::coarse::{coarse_core, coarse_dims, fine_of, Coarse};
use super::ends::{check_free_face, map_onto_fixed_ends, validate_ends, LineEnd};
use super::lines::{
    arclength_core, check_increasing_core, line_collapsed, line_shape, max_stretching_core,
    on_zero_segment, redistribute_core, same_point,
};
use super::structured::{is_fixed, sweep_core, BlockRegion};
use super::TaubinParams;

/// Settings of [`smooth_arclength`]. Build with [`SmoothOptions::new`] (the paper's values)
/// and change fields as needed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothOptions<'a, T> {
    /// Direction of the grid lines whose arclength is smoothed.
    pub direction: Direction,
    /// λ and μ (default: the paper's 0.330 and −0.334).
    pub params: TaubinParams<T>,
    /// Fine-grid iterations (default 30, as in the paper).
    pub iterations: usize,
    /// Filter the normalised arclength `s = S / S_total` (Alter: reduces stretching) instead
    /// of the dimensional `S` (smooths the grid). Normalised, both line ends always stay
    /// where they are. Default `false`.
    pub normalised: bool,
    /// What the first and the last point of every line do: [`LineEnd::Fixed`] (default,
    /// both) or, for the last end with dimensional arclength, [`LineEnd::Free`] (Alter's
    /// outer boundary slides along its lines).
    pub ends: [LineEnd; 2],
    /// Optional fixed-point mask (`point_count` bytes, nonzero = the point does not move).
    pub fixed: Option<&'a [u8]>,
    /// Mirror (Neumann) faces per direction. The entry for `direction` itself is ignored: the
    /// faces at the line ends always use the paper's in-plane rule, so `S = 0` on the first
    /// face stays exactly 0.
    pub mirror: Directions,
    /// Optional coarse-grid pass after the fine iterations (Alter's multi-grid step).
    pub coarse: Option<Coarse>,
    /// Iterations on the coarse grid (default 15: Alter halved the count there).
    pub coarse_iterations: usize,
}

impl<'a, T: Real> SmoothOptions<'a, T> {
    /// The paper's settings for lines along `direction`: λ = 0.330, μ = −0.334, 30
    /// iterations, dimensional arclength, no fixed points, no mirror faces, no coarse pass.
    pub fn new(direction: Direction) -> Self {
        SmoothOptions {
            direction,
            params: TaubinParams::paper(),
            iterations: 30,
            normalised: false,
            ends: [LineEnd::Fixed; 2],
            fixed: None,
            mirror: Directions::NONE,
            coarse: None,
            coarse_iterations: 15,
        }
    }
}

/// What [`smooth_arclength`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct SmoothReport<T> {
    /// Iterations performed (fine + coarse).
    pub iterations: usize,
    /// Largest `|change|` of the arclength field in either pass of the last iteration.
    pub last_change: T,
    /// Largest distance any point moved.
    pub max_displacement: T,
    /// Maximum stretching along `direction` before, and the point where it occurs.
    pub stretching_before: (T, usize),
    /// Maximum stretching along `direction` after, and the point where it occurs.
    pub stretching_after: (T, usize),
}

/// Scratch length (in `T` values) for [`smooth_arclength`]:
/// `n + max(n, 2 n_coarse, (D + 1) × points per line)`.
pub fn smooth_arclength_scratch_len<const D: usize>(
    block: &Block,
    direction: Direction,
    coarse: Option<&Coarse>,
) -> usize {
    let n = block.point_count();
    let (_, len, _) = line_shape(block.dims(), direction);
    let nc = match coarse {
        Some(c) => {
            let [a, b, d] = coarse_dims(block, c.factor);
            2 * a * b * d
        }
        None => 0,
    };
    n + n.max(nc).max((D + 1) * len)
}

/// Whether point `p` is the first (`[true, _]`) or the last (`[_, true]`) point of its line
/// along `direction`.
fn line_end(dims: [usize; 3], direction: Direction, p: usize) -> [bool; 2] {
    let [ni, nj, _] = dims;
    let (stride, len) = match direction {
        Direction::I => (1, ni),
        Direction::J => (ni, nj),
        Direction::K => (ni.saturating_mul(nj), dims[2]),
    };
    let t = (p / stride.max(1)) % len.max(1);
    [t == 0, t + 1 == len]
}

/// Smooths a structured grid along one family of lines, Alter's way:
///
/// 1. `S(i, j, k)` = arclength along `direction` from each line's first point ([`arclength`],
///    normalised with `options.normalised`);
/// 2. `options.iterations` λ|μ iterations on `S` with the paper's 3D stencils
///    (`S ← (1 − μL)(1 − λL) S`, `L = I − avg`, [`smooth_structured`]), then, with
///    `options.coarse`, `options.coarse_iterations` more on the coarse grid and prolongation
///    ([`smooth_structured_coarse`]);
/// 3. the **fold guard**: after every iteration `S` must increase strictly along every line
///    whose points do not all coincide, else `Err(FoldedLine { line, iteration })` (fine
///    iterations count 1…N, coarse ones N+1…N+M; the check after prolongation uses N+M);
/// 4. every point moves along its original polyline to its filtered arclength
///    ([`redistribute`]); fixed points are not touched.
///
/// **Line ends** (`options.ends`). The first point of every line never moves (`S = 0`
/// there). With [`LineEnd::Fixed`] (the default) the last point stays bitwise where it was
/// too, so the boundary faces at the line ends, and whatever meets them there (an O-grid
/// seam, a block interface), do not move. Normalised, both ends are held in the filter
/// (`s = 0` and `1`). Dimensional, the far face is filtered in-plane like every face (the
/// paper's rule) and, for fixed ends, each line's filtered field is then mapped onto its
/// original end value, `S ← (S / S_end) · S_end⁰`, before the fold guard's last check and
/// the redistribution: a line the free-end filter keeps increasing stays increasing.
/// (Holding the far face in the filter instead pins its roughness while the points below
/// it are averaged across lines; where the last cells are shorter than that roughness, as
/// under a bow shock, the lines fold.) With [`LineEnd::Free`] the last points slide along
/// their lines to the filtered arclength, past the end along the last segment of non-zero
/// length (Alter's outer boundary, his figures 6 and 7); a free end that coincides with
/// another line's end ([`SharedFreeEnd`](Error::SharedFreeEnd)) is refused.
///
/// Segments that already have zero length (two consecutive points coincide, e.g. a
/// duplicated point) are held: their arclength stays equal, which the fold guard accepts
/// there and only there.
///
/// The grid is only written in step 4, so on **any** `Err` (including `FoldedLine`) `points`
/// is unchanged; `scratch` ([`smooth_arclength_scratch_len`] values) is then unspecified.
///
/// [`arclength`]: super::arclength
/// [`redistribute`]: super::redistribute
/// [`smooth_structured`]: super::smooth_structured
/// [`smooth_structured_coarse`]: super::smooth_structured_coarse
///
/// # Errors
/// `InvalidParameter` (`direction`, `lambda`, `mu`, `coarse.factor`, `options.ends`: a free
/// first end, or a free end with normalised arclength), `LengthMismatch` (`points`,
/// `options.fixed`), `BufferTooSmall` (`scratch`), `NonFinite` (`points`, `lambda`, `mu`),
/// `SharedFreeEnd` (a free end on a seam), `FoldedLine`.
pub fn smooth_arclength<T: Real, const D: usize>(
    block: &Block,
    points: &mut [[T; D]],
    options: &SmoothOptions<'_, T>,
    scratch: &mut [T],
) -> Result<SmoothReport<T>> {
    let direction = options.direction;
    let n = block.point_count();
    check::len("points", points.len(), n)?;
    check::mask("options.fixed", options.fixed, n)?;
    options.params.validate()?;
    validate_ends(options.ends, options.normalised)?;
    if let Some(c) = &options.coarse {
        c.validate()?;
    }
    let need = smooth_arclength_scratch_len::<D>(block, direction, options.coarse.as_ref());
    check::buffer("scratch", scratch.len(), need)?;
    check::finite_items("points", points)?;
    let dims = block.dims();
    let free_end = options.ends[1] == LineEnd::Free;
    if free_end {
        check_free_face(dims, points, direction)?;
    }
    let mirror = options.mirror.without(direction).flags();
    let fixed = options.fixed;
    let params = options.params;
    let stretching_before = max_stretching_core(dims, points, direction);

    let Some((field, rest)) = scratch.split_at_mut_checked(n) else {
        return Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: need,
            actual: scratch.len(),
        });
    };
    arclength_core(dims, points, direction, options.normalised, field);

    let pts: &[[T; D]] = points;
    let collapsed = |base: usize| line_collapsed(dims, pts, direction, base);
    // Held in the filter: fixed points, first ends (S = 0), last ends when normalised
    // (s = 1), the ends of segments that already have zero length (their arclength stays
    // equal). Dimensional last ends are filtered in-plane, fixed or free.
    let normalised = options.normalised;
    let held_ends = |p: usize| {
        let [first, last] = line_end(dims, direction, p);
        is_fixed(fixed, p) || first || (last && normalised)
    };
    let held = |p: usize| held_ends(p) || on_zero_segment(dims, pts, direction, p);
    // Not moved by the redistribution: the held points and the fixed last ends.
    let stays = |p: usize| held_ends(p) || (!free_end && line_end(dims, direction, p)[1]);
    let zero_segment = |p: usize, q: usize| same_point(pts, p, q);
    let pin = |_: [usize; 3], p: usize| held(p);
    let region = BlockRegion {
        lo: [0; 3],
        hi: dims,
    };
    let mut last_change = T::ZERO;
    {
        let Some(tmp) = rest.get_mut(..n) else {
            return Err(Error::BufferTooSmall {
                arg: "scratch",
                needed: need,
                actual: n,
            });
        };
        for it in 1..=options.iterations {
            let a = sweep_core(dims, field, tmp, params.lambda, mirror, &region, pin);
            let b = sweep_core(dims, tmp, field, params.mu, mirror, &region, pin);
            last_change = a.max(b);
            check_increasing_core(dims, field, direction, it, collapsed, zero_segment)?;
        }
    }
    let mut iterations = options.iterations;
    if let Some(coarse) = &options.coarse {
        let factor = coarse.factor;
        let cdims = coarse_dims(block, factor);
        // The fine point under a coarse point.
        let fine = |c: usize| {
            let ci = c % cdims[0].max(1);
            let rest = c / cdims[0].max(1);
            let cj = rest % cdims[1].max(1);
            let ck = rest / cdims[1].max(1);
            fine_of(dims, factor, [ci, cj, ck])
        };
        let coarse_collapsed = |cbase: usize| line_collapsed(dims, pts, direction, fine(cbase));
        let coarse_zero = |p: usize, q: usize| same_point(pts, fine(p), fine(q));
        let report = coarse_core(
            dims,
            field,
            coarse,
            params,
            options.coarse_iterations,
            mirror,
            held,
            rest,
            |cfield, it| {
                check_increasing_core(
                    cdims,
                    cfield,
                    direction,
                    options.iterations + it,
                    coarse_collapsed,
                    coarse_zero,
                )
            },
        )?;
        iterations += options.coarse_iterations;
        if options.coarse_iterations > 0 {
            last_change = report.last_change;
        }
        check_increasing_core(dims, field, direction, iterations, collapsed, zero_segment)?;
    }
    if !normalised && !free_end {
        let interior_held =
            |p: usize| is_fixed(fixed, p) || on_zero_segment(dims, pts, direction, p);
        map_onto_fixed_ends(dims, pts, direction, field, interior_held);
        check_increasing_core(dims, field, direction, iterations, collapsed, zero_segment)?;
    }

    let max_displacement = redistribute_core(
        dims,
        points,
        direction,
        field,
        options.normalised,
        rest,
        |p, zero| zero || stays(p),
    );
    let stretching_after = max_stretching_core(dims, points, direction);
    Ok(SmoothReport {
        iterations,
        last_change,
        max_displacement,
        stretching_before,
        stretching_after,
    })
}
