//! Stiffness choices beyond Batina's `1/L`: per-node factors that stiffen the springs where
//! the mesh must not deform, as SU2's `DEFORM_STIFFNESS_TYPE` does for its elasticity solver:
//!
//! - **wall distance** (SU2 `WALL_DISTANCE`, `E = 1/d`): springs near the walls are stiffer,
//!   so thin boundary-layer cells move almost rigidly with the wall; factors from
//!   [`wall_distances`] and [`wall_distance_factors`];
//! - **inverse cell volume** (SU2 `INVERSE_VOLUME`, `E = 1/V`): small cells are stiffer;
//!   factors from [`dual_volumes`] and [`inverse_volume_factors`].
//!
//! [`scale_stiffness`] multiplies every directed edge's stiffness by the mean factor of its two
//! nodes, `k_ij ← k_ij (f_i + f_j) / 2`. The mean is symmetric bit for bit (`f_i + f_j` and
//! `f_j + f_i` are the same float), so the result is still an exactly symmetric stiffness as
//! [`SpringSystem`](super::SpringSystem) requires. Factors are normalised so that the median
//! element of the mesh is of order one (dividing by the mean distance or volume): the solve
//! then sees stiffness values of the same magnitude as Batina's, whatever the mesh's units.

use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::vector;

/// The distance from every node to the nearest node of `wall` (node indices), into `out`.
/// Wall nodes get 0.
///
/// Exact distances to the wall *nodes*: an upper bound of the distance to the wall surface
/// that exceeds it by at most half a wall element's diagonal, which is what a stiffness needs.
/// The cost is `O(N·B)` distance evaluations (`N` nodes, `B` wall nodes): about 0.5 s for a
/// 2D mesh of 234k nodes and 1,024 wall nodes; for large 3D meshes compute the distances with a
/// spatial search of your own and pass them to [`wall_distance_factors`].
///
/// # Errors
/// Nothing is written on error: `out.len() != points.len()` ([`Error::LengthMismatch`]), an
/// empty `wall` ([`Error::InvalidParameter`]), a wall index out of range
/// ([`Error::IndexOutOfRange`]), a non-finite coordinate ([`Error::NonFinite`]).
pub fn wall_distances<T: Real, const D: usize>(
    points: &[[T; D]],
    wall: &[u32],
    out: &mut [T],
) -> Result<()> {
    check::len("out", out.len(), points.len())?;
    if wall.is_empty() {
        return Err(Error::InvalidParameter {
            arg: "wall",
            reason: "must name at least one node",
        });
    }
    for (position, &w) in wall.iter().enumerate() {
        if w as usize >= points.len() {
            return Err(Error::IndexOutOfRange {
                arg: "wall",
                position,
                index: w as usize,
                bound: points.len(),
            });
        }
    }
    check::finite_items("points", points)?;
    for (o, p) in out.iter_mut().zip(points) {
        let mut best = T::INFINITY;
        for &w in wall {
            if let Some(q) = points.get(w as usize) {
                let d = vector::norm_robust(vector::sub(*p, *q));
                if d < best {
                    best = d;
                }
            }
        }
        *o = best;
    }
    Ok(())
}

/// Turns wall distances into stiffness factors `f_i = (d̄ / max(d_i, d_min))^q` in place,
/// with `d̄` the mean distance and `d_min = 1e-3·d̄` (so wall nodes get a large but finite
/// factor). `q = 1` is SU2's `E = 1/d`; larger `q` concentrates the stiffening at the walls.
///
/// # Errors
/// Nothing is written on error: `exponent` not finite or negative ([`Error::InvalidParameter`]),
/// a distance that is negative or not finite ([`Error::NonFinite`] / [`Error::NonPositive`]
/// with its node), all distances 0 ([`Error::InvalidParameter`]).
pub fn wall_distance_factors<T: Real>(distances: &mut [T], exponent: T) -> Result<()> {
    let mean = checked_mean(distances, "distances")?;
    positive_factors(distances, exponent, mean, T::from_f64(1e-3))
}

/// The dual volume of every node: each cell's `|area|` (2D) or `|volume|` (3D) shared equally
/// among its nodes, into `out` (`out.len() == points.len()`). `scratch` needs `cells.len()`
/// items (the cell measures).
///
/// # Errors
/// Nothing is written on error: those of [`cell_measures`](crate::quality::cell_measures);
/// `out` or `scratch` of the wrong length ([`Error::LengthMismatch`] /
/// [`Error::BufferTooSmall`]).
pub fn dual_volumes<T: Real, const D: usize>(
    cells: &Cells<'_>,
    points: &[[T; D]],
    out: &mut [T],
    scratch: &mut [T],
) -> Result<()> {
    check::len("out", out.len(), points.len())?;
    let available = scratch.len();
    let measures = scratch
        .get_mut(..cells.len())
        .ok_or(Error::BufferTooSmall {
            arg: "scratch",
            needed: cells.len(),
            actual: available,
        })?;
    crate::quality::cell_measures(cells, points, measures)?;
    for o in out.iter_mut() {
        *o = T::ZERO;
    }
    for ((_, nodes), m) in cells.iter().zip(measures.iter()) {
        let share = m.abs() / T::from_usize(nodes.len().max(1));
        for &n in nodes {
            if let Some(o) = out.get_mut(n as usize) {
                *o += share;
            }
        }
    }
    Ok(())
}

/// Turns dual volumes into stiffness factors `f_i = (V̄ / max(V_i, V_min))^q` in place, with
/// `V̄` the mean dual volume and `V_min = 1e-12·V̄`. `q = 1` is SU2's `E = 1/V`.
///
/// # Errors
/// As [`wall_distance_factors`] (with `arg = "volumes"`).
pub fn inverse_volume_factors<T: Real>(volumes: &mut [T], exponent: T) -> Result<()> {
    let mean = checked_mean(volumes, "volumes")?;
    positive_factors(volumes, exponent, mean, T::from_f64(1e-12))
}

/// Multiplies the stiffness of every directed edge by the mean factor of its two nodes:
/// `k_ij ← k_ij (f_i + f_j) / 2`. Exactly symmetric stiffness stays exactly symmetric.
///
/// # Errors
/// Nothing is written on error: `factors.len() != graph.node_count()` or
/// `stiffness.len() != graph.edge_count()` ([`Error::LengthMismatch`]); a factor that is not
/// finite and positive ([`Error::NonFinite`] / [`Error::NonPositive`]); a product that is not
/// finite and positive ([`Error::NonPositive`] with `arg = "stiffness"` and the edge's node).
pub fn scale_stiffness<T: Real>(
    graph: &Graph<'_>,
    factors: &[T],
    stiffness: &mut [T],
) -> Result<()> {
    check::len("factors", factors.len(), graph.node_count())?;
    check::len("stiffness", stiffness.len(), graph.edge_count())?;
    for (position, &f) in factors.iter().enumerate() {
        if !f.is_finite() {
            return Err(Error::NonFinite {
                arg: "factors",
                position,
            });
        }
        if f <= T::ZERO {
            return Err(Error::NonPositive {
                arg: "factors",
                position,
            });
        }
    }
    let scaled = |i: usize, j: usize, k: T| -> Option<T> {
        let (fi, fj) = (*factors.get(i)?, *factors.get(j)?);
        // (f_i + f_j) / 2 without overflow for factors near MAX.
        let mean = fi * T::HALF + fj * T::HALF;
        let v = k * mean;
        (v.is_finite() && v > T::ZERO).then_some(v)
    };
    // Validate every edge first, then write.
    let mut e = 0usize;
    for (i, _, row) in graph.rows() {
        for &j in row {
            let k = stiffness.get(e).copied().unwrap_or(T::ZERO);
            if scaled(i, j as usize, k).is_none() {
                return Err(Error::NonPositive {
                    arg: "stiffness",
                    position: i,
                });
            }
            e += 1;
        }
    }
    let mut e = 0usize;
    for (i, _, row) in graph.rows() {
        for &j in row {
            if let Some(k) = stiffness.get_mut(e) {
                if let Some(v) = scaled(i, j as usize, *k) {
                    *k = v;
                }
            }
            e += 1;
        }
    }
    Ok(())
}

/// The mean of non-negative finite values (summed in order, scaled to avoid overflow), or the
/// error naming the first bad value; all zeros is an error.
fn checked_mean<T: Real>(values: &[T], arg: &'static str) -> Result<T> {
    let mut largest = T::ZERO;
    for (position, &v) in values.iter().enumerate() {
        if !v.is_finite() {
            return Err(Error::NonFinite { arg, position });
        }
        if v < T::ZERO {
            return Err(Error::NonPositive { arg, position });
        }
        if v > largest {
            largest = v;
        }
    }
    if largest == T::ZERO {
        return Err(Error::InvalidParameter {
            arg,
            reason: "must not be all zero",
        });
    }
    // Σ (v / largest) ≤ n cannot overflow.
    let mut sum = T::ZERO;
    for &v in values {
        sum += v / largest;
    }
    Ok(sum / T::from_usize(values.len()) * largest)
}

/// `f_i = (mean / max(value_i, floor·mean))^q` in place, after checking `q` and that every
/// factor is finite (a large `q` could overflow): nothing is written on error.
fn positive_factors<T: Real>(values: &mut [T], exponent: T, mean: T, floor: T) -> Result<()> {
    if !(exponent.is_finite() && exponent >= T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "exponent",
            reason: "must be finite and >= 0",
        });
    }
    let floor = mean * floor;
    let factor = |x: T| {
        let ratio = mean / if x > floor { x } else { floor };
        if exponent == T::ONE {
            ratio
        } else {
            ratio.powf(exponent)
        }
    };
    if values.iter().any(|&x| {
        let f = factor(x);
        !(f.is_finite() && f > T::ZERO)
    }) {
        return Err(Error::InvalidParameter {
            arg: "exponent",
            reason: "gives factors that overflow or underflow for these values",
        });
    }
    for v in values.iter_mut() {
        *v = factor(*v);
    }
    Ok(())
}
