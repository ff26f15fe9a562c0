//! SU2's `HICKS_HENNE` design variable (`CSurfaceMovement::SetHicksHenne`).
//!
//! For `DV_PARAM = (side, x_max)` and `DV_VALUE = a`, SU2 moves each node of the `DV_MARKER`
//! surfaces in `y` by
//!
//! ```text
//! f(x) = sin(π x^e)^3,  e = log10(0.5) / log10(x_max),  x := max(0, x)   (f = 0 for x ≤ 1e-15)
//! dy   = +a f(x)  where side = 1 (upper) and the node's normal has n_y > 0
//! dy   = −a f(x)  where side = 0 (lower) and the node's normal has n_y < 0
//! ```
//!
//! What SU2 does *not* do (read from its source, SU2 v7–v8): although `SetHicksHenne` finds the
//! trailing edge (largest x), the leading edge (farthest from it), the chord and an angle of
//! attack, it then overwrites that angle with zero ("WARNING: AoA currently overwritten to
//! zero") and never uses the chord: `x` is the node's raw x coordinate clamped at 0, not
//! `(x − x_LE) / chord`. An airfoil with its leading edge at the origin and unit chord (the
//! SU2 test cases) is what the formula assumes. Nodes with `x > 1` still get `f(x)`.
//!
//! The normal is SU2's vertex normal, which points out of the body into the fluid (so an
//! airfoil's upper surface has `n_y > 0`); only its sign in y matters. A node exactly on
//! `n_y = 0` (a sharp leading edge, say) moves on neither side, as in SU2.

use crate::check;
use crate::error::{Error, Result};
use crate::real::Real;

/// One `HICKS_HENNE` design variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HicksHenne<T> {
    /// `DV_PARAM[0]`: `true` for 1 (upper surface, nodes with `n_y > 0`), `false` for 0
    /// (lower surface, nodes with `n_y < 0`, moved by `−amplitude · f`).
    pub upper: bool,
    /// `DV_PARAM[1]`: where the bump peaks, strictly between 0 and 1.
    pub x_max: T,
    /// `DV_VALUE` times SU2's `OPT_RELAX_FACTOR` (1 unless the config sets it).
    pub amplitude: T,
}

/// `log10` through libm at the precision of `T` (the trait has `ln`, SU2 uses `log10`, and
/// the two quotients round differently).
fn log10<T: Real>(x: T) -> T {
    if T::MANTISSA_DIGITS == 24 {
        T::from_f64(libm::log10f(x.to_f64() as f32) as f64)
    } else {
        T::from_f64(libm::log10(x.to_f64()))
    }
}

/// SU2's bump `sin(π max(0,x)^e)^3` with `e = log10(0.5) / log10(x_max)`, and 0 where
/// `max(0, x) ≤ 10 · SU2_EPS`. Same operations in the same order as SU2 (`pow` for both
/// powers), so in `f64` it agrees with SU2 to the last bit wherever libm's and the C library's
/// `pow`, `sin` and `log10` agree (they are within an ulp of each other).
///
/// `x_max` is not checked here (see [`hicks_henne`]); for `x_max` outside `(0, 1)` the
/// result is meaningless or NaN, as in SU2.
pub fn hicks_henne_bump<T: Real>(x: T, x_max: T) -> T {
    let x = T::ZERO.max(x);
    if x.to_f64() <= 10.0 * super::SU2_EPS {
        return T::ZERO;
    }
    let e = log10(T::HALF) / log10(x_max);
    (T::PI * x.powf(e)).sin().powf(T::from_f64(3.0))
}

/// Adds one Hicks–Henne bump to the displacements of the surface nodes `nodes`, as SU2's
/// `SetHicksHenne` adds it to each vertex's `VarCoord` (several design variables accumulate:
/// call once per variable on the same `displacements`).
///
/// - `points`: all mesh points (`D` = 2 or 3); only x of the listed nodes is read.
/// - `nodes`: the surface nodes (indices into `points`), e.g. those of the `DV_MARKER`s.
/// - `normals[p]`: the normal of `nodes[p]` (SU2's convention: pointing into the fluid); only
///   the sign of its y component is read.
/// - `displacements[p]`: the displacement of `nodes[p]`; its y component gets `±amplitude ·
///   f(x)` where the side matches, nothing else changes.
///
/// # Errors
/// [`Error::LengthMismatch`] when `normals` or `displacements` does not have one entry per
/// node; [`Error::IndexOutOfRange`] for a node outside `points`; [`Error::NonFinite`] for a
/// non-finite listed point, normal, displacement, `x_max` or `amplitude`;
/// [`Error::InvalidParameter`] when `x_max` is not strictly between 0 and 1;
/// [`Error::Overflow`] when a displacement would not be finite (`x^e` overflows for `x_max`
/// next to 1 and x far beyond 1). Nothing is written on error.
pub fn hicks_henne<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    normals: &[[T; D]],
    bump: HicksHenne<T>,
    displacements: &mut [[T; D]],
) -> Result<()> {
    check_inputs(
        points,
        nodes,
        normals,
        bump,
        ("displacements", displacements.len()),
    )?;
    check::finite_items("displacements", displacements)?;
    let moved = |p: usize| increment(points, nodes, normals, bump, p);
    let y = |d: &[T; D]| d.get(1).copied().unwrap_or(T::ZERO);
    let overflows = |(p, d): (usize, &[T; D])| moved(p).is_some_and(|dy| !(y(d) + dy).is_finite());
    if displacements.iter().enumerate().any(overflows) {
        return Err(Error::Overflow { arg: "x_max" });
    }
    for (p, d) in displacements.iter_mut().enumerate() {
        if let (Some(dy), Some(dv)) = (moved(p), d.get_mut(1)) {
            *dv += dy;
        }
    }
    Ok(())
}

/// The checks of [`hicks_henne`] on everything but the displacements (`values`: their name
/// and number, one per node).
pub(super) fn check_inputs<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    normals: &[[T; D]],
    bump: HicksHenne<T>,
    (name, values_len): (&'static str, usize),
) -> Result<()> {
    check::mesh_dim::<D>();
    check::len("normals", normals.len(), nodes.len())?;
    check::len(name, values_len, nodes.len())?;
    check::indices("nodes", nodes, points.len())?;
    check::scalar("x_max", bump.x_max)?;
    check::scalar("amplitude", bump.amplitude)?;
    if !(bump.x_max > T::ZERO && bump.x_max < T::ONE) {
        return Err(Error::InvalidParameter {
            arg: "x_max",
            reason: "must lie strictly between 0 and 1",
        });
    }
    check::finite_items("normals", normals)?;
    super::listed_points_finite(points, nodes)
}

/// The y increment `±amplitude · f(x)` of listed node `p` (`None`: not on the bump's side).
pub(super) fn increment<T: Real, const D: usize>(
    points: &[[T; D]],
    nodes: &[u32],
    normals: &[[T; D]],
    bump: HicksHenne<T>,
    p: usize,
) -> Option<T> {
    let ny = normals.get(p)?.get(1).copied()?;
    let on_side = if bump.upper {
        ny > T::ZERO
    } else {
        ny < T::ZERO
    };
    if !on_side {
        return None;
    }
    let x = points.get(*nodes.get(p)? as usize)?.first().copied()?;
    let f = hicks_henne_bump(x, bump.x_max);
    let a = if bump.upper {
        bump.amplitude
    } else {
        -bump.amplitude
    };
    Some(a * f)
}
