//! Boundary rotations (Samareh steps 1–3), the default origin and the translations `Δ`.

use super::normals::{check_elements, unit_normals};
use super::{load, rotate_d, store, take, Pts};
use crate::cells::Cells;
use crate::check;
use crate::error::{Error, Result};
use crate::quat::Quat;
use crate::real::Real;
use crate::vector::{cross, dot, norm_sq, scale, sub};

/// Length of the `scratch` slice [`boundary_rotations`] needs: `3 B` in 2D, `13 B` in 3D.
#[inline]
pub fn boundary_rotations_scratch_len<const D: usize>(boundary_len: usize) -> usize {
    boundary_len.saturating_mul(if D == 2 { 3 } else { 13 })
}

/// Checks that no element edge has zero length in `points`.
fn check_edges<T: Real, const D: usize>(points: Pts<'_, T, D>, elements: &Cells<'_>) -> Result<()> {
    for (kind, nodes) in elements.iter() {
        for &[la, lb] in kind.edges() {
            let (Some(&a), Some(&b)) = (nodes.get(la as usize), nodes.get(lb as usize)) else {
                continue;
            };
            let l2 = norm_sq(sub(points.get(b as usize), points.get(a as usize)));
            if !(l2.is_finite() && l2 > T::ZERO) {
                return Err(Error::ZeroLengthEdge {
                    from: a as usize,
                    to: b as usize,
                });
            }
        }
    }
    Ok(())
}

/// Per-node rotations of a boundary from its undeformed and deformed shapes.
///
/// **3D** (Samareh steps 2–3, with the erratum in ARCHITECTURE.md): `Q1` turns the undeformed node
/// normal onto the deformed one ([`Quat::rotation_arc`]: half-way construction, antiparallel
/// normals turn by 180° about a tangent axis, which the twist then completes). The twist `θ`
/// about the deformed normal is the weighted circular mean
/// `atan2(Σ |p_u||p_d| sin θ_j, Σ |p_u||p_d| cos θ_j) = atan2(Σ (p_u × p_d)·n_d, Σ p_u · p_d)` of
/// the angles `θ_j` between each neighbour edge (the element edges at the node, one term per
/// element using the edge) rotated by `Q1` and the corresponding deformed edge, both projected
/// onto the deformed tangent plane (`p_u`, `p_d`). The weights (products of projected lengths)
/// keep edges that run nearly along the normal — at a sharp trailing edge, whose projections
/// are tiny and whose angles are ill-conditioned — from dominating. `Q2 = [cos θ/2, n_d sin θ/2]` and `Q = Q2 Q1` ("apply `Q1`, then `Q2`": the
/// paper's `Q1 Q2` would need `Q2` about the undeformed normal).
///
/// **2D**: rotations about z only (a rotation about the in-plane normal would leave the plane).
/// Each segment turns by the change of its direction, `atan2(t_u × t_d, t_u · t_d)` in
/// `(−π, π]`; a node takes the mean of its segments' angles, each unwrapped to within π of the
/// first. Edge normals are not used, so a sharp trailing edge (normals ~160° apart) is fine.
///
/// `undeformed` and `deformed` are the boundary's `B` points; `elements` index them (segments
/// in 2D, triangles/quadrilaterals in 3D, consistently ordered). `scratch` needs
/// [`boundary_rotations_scratch_len`] entries (contents unspecified afterwards).
///
/// # Errors
/// Length mismatches, non-finite points, wrong element kinds, [`Error::ZeroLengthEdge`]
/// (in either shape), [`Error::IsolatedNode`] (a point in no element, or in 3D one whose
/// twist is undetermined: the weighted sum cancels to below `ε Σ |p_u||p_d|`), [`Error::ZeroLength`] (`"normals"`, 3D: element normals cancel at a
/// node). On error `rotations` is unchanged.
pub fn boundary_rotations<T: Real, const D: usize>(
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
    elements: &Cells<'_>,
    scratch: &mut [T],
    rotations: &mut [Quat<T>],
) -> Result<()> {
    check::len("rotations", rotations.len(), undeformed.len())?;
    rotations_core(
        Pts::direct(undeformed),
        Pts::direct(deformed),
        elements,
        scratch,
        |i, q| {
            if let Some(r) = rotations.get_mut(i) {
                *r = q;
            }
        },
    )
}

/// [`boundary_rotations`] on point views: validates, computes, then calls `emit(node, Q)` for
/// every node in order (only when everything succeeded).
pub(crate) fn rotations_core<T: Real, const D: usize>(
    undeformed: Pts<'_, T, D>,
    deformed: Pts<'_, T, D>,
    elements: &Cells<'_>,
    scratch: &mut [T],
    emit: impl FnMut(usize, Quat<T>),
) -> Result<()> {
    check::mesh_dim::<D>();
    let b = undeformed.len();
    check_elements::<D>(elements, b)?;
    check::len("deformed", deformed.len(), b)?;
    check::buffer(
        "scratch",
        scratch.len(),
        boundary_rotations_scratch_len::<D>(b),
    )?;
    undeformed.check_finite("undeformed")?;
    deformed.check_finite("deformed")?;
    check_edges(undeformed, elements)?;
    check_edges(deformed, elements)?;
    if D == 2 {
        rotations_2d(undeformed, deformed, elements, scratch, emit)
    } else {
        rotations_3d(undeformed, deformed, elements, scratch, emit)
    }
}

/// The 2D branch of [`boundary_rotations`] (inputs validated).
fn rotations_2d<T: Real, const D: usize>(
    undeformed: Pts<'_, T, D>,
    deformed: Pts<'_, T, D>,
    elements: &Cells<'_>,
    scratch: &mut [T],
    mut emit: impl FnMut(usize, Quat<T>),
) -> Result<()> {
    // scratch: per node [reference angle, sum of unwrapped angles, count].
    let b = undeformed.len();
    let acc = match scratch.get_mut(..3 * b) {
        Some(s) => s,
        None => {
            return Err(Error::BufferTooSmall {
                arg: "scratch",
                needed: 3 * b,
                actual: scratch.len(),
            })
        }
    };
    for x in acc.iter_mut() {
        *x = T::ZERO;
    }
    let two_pi = T::TWO * T::PI;
    for (_, nodes) in elements.iter() {
        let (Some(&a), Some(&c)) = (nodes.first(), nodes.get(1)) else {
            continue;
        };
        let tu = sub(undeformed.get3(c as usize), undeformed.get3(a as usize));
        let td = sub(deformed.get3(c as usize), deformed.get3(a as usize));
        let angle = cross(tu, td)[2].atan2(dot(tu, td));
        for v in [a, c] {
            let [r, s, n]: [T; 3] = load(acc, v as usize);
            let (r, s, n) = if n == T::ZERO {
                (angle, angle, T::ONE)
            } else {
                let mut x = angle;
                if x - r > T::PI {
                    x -= two_pi;
                } else if x - r < -T::PI {
                    x += two_pi;
                }
                (r, s + x, n + T::ONE)
            };
            store(acc, v as usize, [r, s, n]);
        }
    }
    for i in 0..b {
        let [_, _, n]: [T; 3] = load(acc, i);
        if n == T::ZERO {
            return Err(Error::IsolatedNode { node: i });
        }
    }
    for i in 0..b {
        let [_, s, n]: [T; 3] = load(acc, i);
        emit(i, Quat::from_rotation_z(s / n));
    }
    Ok(())
}

/// The 3D branch of [`boundary_rotations`] (inputs validated).
fn rotations_3d<T: Real, const D: usize>(
    undeformed: Pts<'_, T, D>,
    deformed: Pts<'_, T, D>,
    elements: &Cells<'_>,
    scratch: &mut [T],
    mut emit: impl FnMut(usize, Quat<T>),
) -> Result<()> {
    let b = undeformed.len();
    let (nu, rest) = take(scratch, 3 * b);
    let (nd, rest) = take(rest, 3 * b);
    let (q1s, rest) = take(rest, 4 * b);
    let (sc, _) = take(rest, 3 * b);
    unit_normals(undeformed, elements, nu)?;
    unit_normals(deformed, elements, nd)?;
    for i in 0..b {
        let q1 = Quat::rotation_arc(load(nu, i), load(nd, i))?;
        store(q1s, i, q1.to_array());
    }
    for x in sc.iter_mut() {
        *x = T::ZERO;
    }
    for (kind, nodes) in elements.iter() {
        for &[la, lb] in kind.edges() {
            let (Some(&a), Some(&c)) = (nodes.get(la as usize), nodes.get(lb as usize)) else {
                continue;
            };
            for (i, j) in [(a, c), (c, a)] {
                let n: [T; 3] = load(nd, i as usize);
                let q1 = Quat::from_array(load(q1s, i as usize));
                let eu = q1.rotate(sub(
                    undeformed.get3(j as usize),
                    undeformed.get3(i as usize),
                ));
                let ed = sub(deformed.get3(j as usize), deformed.get3(i as usize));
                let pu = sub(eu, scale(n, dot(eu, n)));
                let pd = sub(ed, scale(n, dot(ed, n)));
                let c = dot(pu, pd);
                let s = dot(cross(pu, pd), n);
                let h = s.hypot(c);
                let [ss, cc, hh]: [T; 3] = load(sc, i as usize);
                store(sc, i as usize, [ss + s, cc + c, hh + h]);
            }
        }
    }
    for i in 0..b {
        let [s, c, h]: [T; 3] = load(sc, i);
        let m = s.hypot(c);
        if !(m.is_finite() && h.is_finite() && m > T::EPSILON * h) {
            return Err(Error::IsolatedNode { node: i });
        }
        let theta = s.atan2(c);
        let (sh, ch) = (theta * T::HALF).sin_cos();
        let q2 = Quat::from_scalar_vector(ch, scale(load(nd, i), sh));
        let q = (q2 * Quat::from_array(load(q1s, i))).normalize()?;
        store(q1s, i, q.to_array());
    }
    for i in 0..b {
        emit(i, Quat::from_array(load(q1s, i)));
    }
    Ok(())
}

/// Fills `rotations` with one rigid rotation `q` (normalised here): for a marker whose motion
/// the caller knows (a rigid body, a prescribed pitch).
///
/// # Errors
/// `q` non-finite or zero; on
/// error `rotations` is unchanged.
pub fn rigid_rotations<T: Real>(q: Quat<T>, rotations: &mut [Quat<T>]) -> Result<()> {
    let q = q.normalize()?;
    for r in rotations.iter_mut() {
        *r = q;
    }
    Ok(())
}

/// The rotation [`RotationSource::Rigid`](super::RotationSource::Rigid) gives one boundary
/// node (`u` undeformed, `d` deformed): the unit `q`, except for a node that stays exactly in
/// place although `q` about `origin` would move it (by more than 16 ε of its lever arm): that
/// node is not part of the rigid body (a fixed far field, a fixed wall) and gets the identity.
/// A node that stays on the rotation axis, or at the origin, is part of the body and keeps `q`.
pub(crate) fn rigid_node_rotation<T: Real, const D: usize>(
    q: Quat<T>,
    origin: [T; D],
    u: [T; D],
    d: [T; D],
) -> Quat<T> {
    if u != d {
        return q;
    }
    let v = sub(u, origin);
    let w = rotate_d(q, v);
    let mut moved = T::ZERO;
    let mut arm = T::ZERO;
    for (a, b) in w.iter().zip(&v) {
        moved = moved.max((*a - *b).abs());
        arm = arm.max(b.abs());
    }
    if moved > T::from_f64(16.0) * T::EPSILON * arm {
        Quat::identity()
    } else {
        q
    }
}

/// The default origin: the centroid of the undeformed positions of the boundary points that
/// move (`deformed != undeformed`), or of all points when none moves.
///
/// Why it matters: the field update `o + Δ + Q (R − o)` relies on the interpolated `Δ`
/// cancelling the interpolated rotation of the lever arm `R − o`. Between boundary nodes with
/// different rotations the two are interpolated independently, so the mismatch grows like
/// `|δQ| · |R − o|`: a far-away origin turns small rotation differences into large spurious
/// displacements, and makes `Δ` itself large (losing relative precision). An origin at the
/// moving body keeps the lever arms short.
///
/// # Errors
/// Length mismatch, empty input, non-finite points.
pub fn boundary_origin<T: Real, const D: usize>(
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
) -> Result<[T; D]> {
    origin_core(Pts::direct(undeformed), Pts::direct(deformed))
}

/// [`boundary_origin`] on point views.
pub(crate) fn origin_core<T: Real, const D: usize>(
    undeformed: Pts<'_, T, D>,
    deformed: Pts<'_, T, D>,
) -> Result<[T; D]> {
    check::mesh_dim::<D>();
    let b = undeformed.len();
    check::len("deformed", deformed.len(), b)?;
    if b == 0 {
        return Err(Error::InvalidParameter {
            arg: "undeformed",
            reason: "must not be empty",
        });
    }
    undeformed.check_finite("undeformed")?;
    deformed.check_finite("deformed")?;
    let mut sum = [T::ZERO; D];
    let mut count = 0usize;
    for k in 0..b {
        let u = undeformed.get(k);
        if u != deformed.get(k) {
            for (s, x) in sum.iter_mut().zip(u) {
                *s += x;
            }
            count += 1;
        }
    }
    if count == 0 {
        for k in 0..b {
            for (s, x) in sum.iter_mut().zip(undeformed.get(k)) {
                *s += x;
            }
        }
        count = b;
    }
    let c = T::from_usize(count);
    for s in sum.iter_mut() {
        *s /= c;
    }
    Ok(sum)
}

/// The translations `Δ_i = (r_i^d − o) − Q_i (r_i^u − o) Q_i*` (Samareh's `Δ` with the
/// erratum in ARCHITECTURE.md: the *undeformed* point is rotated), measured about `origin`, so that
/// `o + Δ_i + Q_i (r_i^u − o) Q_i*` is `r_i^d` up to rounding. Each rotation is normalised
/// first (as [`update_points`](super::update_points) does).
///
/// # Errors
/// Length mismatches, non-finite input, zero rotations. On error `translations` is
/// unchanged.
pub fn boundary_translations<T: Real, const D: usize>(
    origin: [T; D],
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
    rotations: &[Quat<T>],
    translations: &mut [[T; D]],
) -> Result<()> {
    check::mesh_dim::<D>();
    let b = undeformed.len();
    check::len("deformed", deformed.len(), b)?;
    check::len("rotations", rotations.len(), b)?;
    check::len("translations", translations.len(), b)?;
    for &x in origin.iter() {
        check::scalar("origin", x)?;
    }
    check::finite_items("undeformed", undeformed)?;
    check::finite_items("deformed", deformed)?;
    check::quats("rotations", rotations)?;
    for (((t, u), d), q) in translations
        .iter_mut()
        .zip(undeformed)
        .zip(deformed)
        .zip(rotations)
    {
        let q = q.normalize().unwrap_or(Quat::identity());
        *t = translation(origin, *u, *d, q);
    }
    Ok(())
}

/// `(d − o) − q (u − o) q*` for a unit `q`.
#[inline]
pub(crate) fn translation<T: Real, const D: usize>(
    origin: [T; D],
    u: [T; D],
    d: [T; D],
    q: Quat<T>,
) -> [T; D] {
    sub(sub(d, origin), rotate_d(q, sub(u, origin)))
}
