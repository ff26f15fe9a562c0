//! Tangent and adjoint of inverse-distance weighting of the boundary displacements, as
//! [`propagate_idw`](crate::quaternion::propagate_idw) weighs them: with `d_k` the undeformed
//! distance from node `i` to boundary node `k`,
//!
//! ```text
//! ω_ik = (d_min / d_k)^p,   δx_i = Σ_k ω_ik δx_k / Σ_k ω_ik
//! ```
//!
//! (a node at zero distance from a boundary node takes that node's value, the first such in
//! boundary order; boundary nodes keep their own). The weights depend on the undeformed mesh
//! only, so the map is linear: this is the derivative of
//! [`deform_idw`](crate::quaternion::deform_idw) when the rotations are the identity
//! ([`RotationSource::PerNode`](crate::quaternion::RotationSource::PerNode) of identities),
//! and of any IDW of displacements. The adjoint is the transposed weighting. Both are direct
//! (no solve): `O(N · B)` weights, exact to rounding. Several fields share each node's
//! weights (computed once per node for all of them).

use crate::check;
use crate::error::{Error, Result};
use crate::quaternion::{idw_scan, idw_weight, IdwScan};
use crate::real::Real;

/// How node `i` takes its value.
enum Stencil<T> {
    /// A boundary node: keeps its own.
    Boundary,
    /// At zero distance from this boundary node: takes its value.
    Exact(u32),
    /// Weighted: `ω_k = (dmin / d_k)^p` from squared distances or, when those leave the
    /// normal range, from robust distances (`propagate_idw`'s scan and weights).
    Weighted(IdwScan<T>),
}

/// The stencil of node `i` at `x`: [`propagate_idw`](crate::quaternion::propagate_idw)'s own
/// scan (the same nearest node and range test).
fn stencil<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    i: usize,
    x: [T; D],
) -> Stencil<T> {
    match idw_scan(points, boundary, i, x) {
        None => Stencil::Boundary,
        Some(scan) if scan.dmin > T::ZERO => Stencil::Weighted(scan),
        Some(scan) => Stencil::Exact(scan.nearest),
    }
}

/// The checks both directions share: points finite, boundary non-empty and in range,
/// exponent finite and positive, `m ≥ 1` whole fields of `n` items in `len`.
fn check_inputs<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    arg: &'static str,
    len: usize,
) -> Result<usize> {
    let n = points.len();
    if boundary.is_empty() {
        return Err(Error::InvalidParameter {
            arg: "boundary",
            reason: "must not be empty",
        });
    }
    if !(exponent.is_finite() && exponent > T::ZERO) {
        return Err(Error::InvalidParameter {
            arg: "exponent",
            reason: "must be finite and positive",
        });
    }
    check::finite_items("points", points)?;
    check::indices("boundary", boundary, n)?;
    super::check_fields(arg, n, len)?;
    Ok(len / n)
}

/// The IDW tangent for `m` fields back to back in `dx` (`m · N` items): on entry each holds
/// `δx_b` at the boundary nodes (other entries ignored); on `Ok` every other node holds
/// `Σ_k ω_ik δx_k / Σ_k ω_ik`. Boundary entries are never written.
///
/// # Errors
/// Nothing is written on error: an empty boundary, an out-of-range boundary index, a bad
/// exponent ([`Error::InvalidParameter`], [`Error::IndexOutOfRange`]), non-finite points or
/// `dx` ([`Error::NonFinite`]), `dx` not `m ≥ 1` fields of `N` ([`Error::LengthMismatch`]).
pub fn idw_tangent_many<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    dx: &mut [[T; D]],
) -> Result<()> {
    let n = points.len();
    let m = check_inputs(points, boundary, exponent, "dx", dx.len())?;
    for f in 0..m {
        for &b in boundary {
            let at = f * n + b as usize;
            if dx.get(at).is_some_and(|v| v.iter().any(|c| !c.is_finite())) {
                return Err(Error::NonFinite {
                    arg: "dx",
                    position: at,
                });
            }
        }
    }
    for (i, &x) in points.iter().enumerate() {
        let get = |dx: &[[T; D]], f: usize, b: u32| {
            dx.get(f * n + b as usize).copied().unwrap_or([T::ZERO; D])
        };
        match stencil(points, boundary, i, x) {
            Stencil::Boundary => {}
            Stencil::Exact(b) => {
                for f in 0..m {
                    let v = get(dx, f, b);
                    if let Some(o) = dx.get_mut(f * n + i) {
                        *o = v;
                    }
                }
            }
            Stencil::Weighted(scan) => {
                let mut wsum = T::ZERO;
                for f in 0..m {
                    if let Some(o) = dx.get_mut(f * n + i) {
                        *o = [T::ZERO; D];
                    }
                }
                for &b in boundary {
                    let pb = points.get(b as usize).copied().unwrap_or(x);
                    let w = idw_weight(&scan, exponent, x, pb);
                    wsum += w;
                    for f in 0..m {
                        let v = get(dx, f, b);
                        if let Some(o) = dx.get_mut(f * n + i) {
                            for (o, c) in o.iter_mut().zip(v) {
                                *o += w * c;
                            }
                        }
                    }
                }
                for f in 0..m {
                    if let Some(o) = dx.get_mut(f * n + i) {
                        *o = o.map(|c| c / wsum);
                    }
                }
            }
        }
    }
    Ok(())
}

/// [`idw_tangent_many`] for one field (`N` items).
///
/// # Errors
/// Those of [`idw_tangent_many`] (`dx` must have exactly `N` items).
pub fn idw_tangent<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    dx: &mut [[T; D]],
) -> Result<()> {
    check::len("dx", dx.len(), points.len())?;
    idw_tangent_many(points, boundary, exponent, dx)
}

/// The IDW adjoint for `m` fields `w = dJ/dx` back to back (`m · N` items): `g` (as long)
/// gets `g_k = w_k + Σ_i w_i ω_ik / Σ_j ω_ij` at the boundary nodes (the sum over every
/// other node `i`; a node listed twice in `boundary` gets both entries' terms, as the
/// tangent sums both) and zero elsewhere. Summed in node order.
///
/// # Errors
/// Nothing is written on error: those of [`idw_tangent_many`] for `w`, and `g` of another
/// length than `w` ([`Error::LengthMismatch`]).
pub fn idw_adjoint_many<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    w: &[[T; D]],
    g: &mut [[T; D]],
) -> Result<()> {
    let n = points.len();
    let m = check_inputs(points, boundary, exponent, "w", w.len())?;
    check::len("g", g.len(), w.len())?;
    check::finite_items("w", w)?;
    g.iter_mut().for_each(|v| *v = [T::ZERO; D]);
    for f in 0..m {
        for &b in boundary {
            let at = f * n + b as usize;
            if let (Some(o), Some(&v)) = (g.get_mut(at), w.get(at)) {
                *o = v;
            }
        }
    }
    for (i, &x) in points.iter().enumerate() {
        match stencil(points, boundary, i, x) {
            Stencil::Boundary => {}
            Stencil::Exact(b) => scatter(g, w, n, m, i, b, T::ONE),
            Stencil::Weighted(scan) => {
                let at = |b: u32| points.get(b as usize).copied().unwrap_or(x);
                let wsum = boundary
                    .iter()
                    .fold(T::ZERO, |s, &b| s + idw_weight(&scan, exponent, x, at(b)));
                for &b in boundary {
                    let c = idw_weight(&scan, exponent, x, at(b)) / wsum;
                    scatter(g, w, n, m, i, b, c);
                }
            }
        }
    }
    Ok(())
}

/// `g_b += c · w_i` in each of the `m` fields.
#[inline]
fn scatter<T: Real, const D: usize>(
    g: &mut [[T; D]],
    w: &[[T; D]],
    n: usize,
    m: usize,
    i: usize,
    b: u32,
    c: T,
) {
    for f in 0..m {
        let wi = w.get(f * n + i).copied().unwrap_or([T::ZERO; D]);
        if let Some(o) = g.get_mut(f * n + b as usize) {
            for (o, v) in o.iter_mut().zip(wi) {
                *o += c * v;
            }
        }
    }
}

/// [`idw_adjoint_many`] for one field (`N` items).
///
/// # Errors
/// Those of [`idw_adjoint_many`] (`w` must have exactly `N` items).
pub fn idw_adjoint<T: Real, const D: usize>(
    points: &[[T; D]],
    boundary: &[u32],
    exponent: T,
    w: &[[T; D]],
    g: &mut [[T; D]],
) -> Result<()> {
    check::len("w", w.len(), points.len())?;
    idw_adjoint_many(points, boundary, exponent, w, g)
}
