//! Change of the first grid-line angle at a wall (boundary-layer orthogonality).

use crate::cells::{CellKind, Cells};
use crate::check;
use crate::error::{Error, Result};
use crate::graph::Graph;
use crate::real::Real;
use crate::vector::{cross, dot, norm, normalize, sub};

/// A marked wall: its boundary elements (lines for 2D points, triangles or quads for 3D,
/// oriented consistently, e.g. with the right-hand normal pointing out of the domain) and
/// the mesh's edge graph (to find each wall node's off-wall neighbours).
#[derive(Clone, Copy, Debug)]
pub struct Wall<'a> {
    elements: Cells<'a>,
    graph: Graph<'a>,
}

impl<'a> Wall<'a> {
    /// Wraps wall elements and the edge graph; both must describe the same number of nodes.
    ///
    /// # Errors
    /// Node counts that differ ([`Error::LengthMismatch`] on `graph`).
    pub fn new(elements: Cells<'a>, graph: Graph<'a>) -> Result<Self> {
        check::len("graph", graph.node_count(), elements.node_count())?;
        Ok(Wall { elements, graph })
    }

    /// The wall elements.
    pub fn elements(&self) -> Cells<'a> {
        self.elements
    }

    /// The edge graph.
    pub fn graph(&self) -> Graph<'a> {
        self.graph
    }
}

/// Result of [`wall_angle_change`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct WallAngleChange<T> {
    /// Largest `|θ_deformed − θ_undeformed|` over the measured wall nodes, in radians (0 when
    /// no node was measured).
    pub max_change: T,
    /// The wall node where it occurs (the first one in node order on ties).
    pub node: Option<usize>,
    /// Wall nodes measured.
    pub measured: usize,
    /// Wall nodes skipped: no off-wall neighbour, a zero wall normal (undeformed or deformed)
    /// or a zero-length chosen edge.
    pub skipped: usize,
}

/// Scratch length (in `[T; D]` items) that [`wall_angle_change`] needs for `node_count` nodes.
pub fn wall_angle_scratch_len(node_count: usize) -> usize {
    node_count.saturating_mul(2)
}

/// Outward (as oriented) normal of a wall element, weighted by its length or area.
fn element_normal<T: Real, const D: usize>(
    kind: CellKind,
    nodes: &[u32],
    points: &[[T; D]],
) -> [T; D] {
    let mut p = [[T::ZERO; 3]; 4];
    for (slot, &n) in p.iter_mut().zip(nodes) {
        if let Some(q) = points.get(n as usize) {
            for (s, &x) in slot.iter_mut().zip(q.iter()) {
                *s = x;
            }
        }
    }
    let n3 = match kind {
        CellKind::Line => {
            let d = sub(p[1], p[0]);
            [d[1], -d[0], T::ZERO]
        }
        CellKind::Triangle => {
            let c = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            [T::HALF * c[0], T::HALF * c[1], T::HALF * c[2]]
        }
        _ => {
            let c = cross(sub(p[2], p[0]), sub(p[3], p[1]));
            [T::HALF * c[0], T::HALF * c[1], T::HALF * c[2]]
        }
    };
    let mut out = [T::ZERO; D];
    for (o, x) in out.iter_mut().zip(n3) {
        *o = x;
    }
    out
}

/// Angle between unit normal `n` and edge `e`: signed in 2D (`atan2(n × e, n · e)`),
/// unsigned in 3D (`atan2(|n × e|, n · e)`).
fn angle<T: Real, const D: usize>(n: [T; D], e: [T; D]) -> T {
    let mut a = [T::ZERO; 3];
    let mut b = [T::ZERO; 3];
    for (s, x) in a.iter_mut().zip(n) {
        *s = x;
    }
    for (s, x) in b.iter_mut().zip(e) {
        *s = x;
    }
    let c = cross(a, b);
    let d = dot(a, b);
    if D == 2 {
        c[2].atan2(d)
    } else {
        norm(c).atan2(d)
    }
}

#[inline]
fn is_wall<T: Real, const D: usize>(slot: Option<&[T; D]>) -> bool {
    match slot.and_then(|s| s.first()) {
        Some(x) => x.is_finite(),
        None => false,
    }
}

/// Validates wall elements against the point dimension and counts.
pub(crate) fn check_wall<T: Real, const D: usize>(
    wall: &Wall<'_>,
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
) -> Result<()> {
    let n = wall.elements.node_count();
    for (arg, pts) in [("undeformed", undeformed), ("deformed", deformed)] {
        check::len(arg, pts.len(), n)?;
    }
    for (e, &code) in wall.elements.kinds().iter().enumerate() {
        let ok = match CellKind::from_vtk(code) {
            Some(CellKind::Line) => D == 2,
            Some(CellKind::Triangle) | Some(CellKind::Quad) => D == 3,
            _ => false,
        };
        if !ok {
            return Err(Error::CellDimension {
                cell: e,
                kind: code,
                dimension: D,
            });
        }
    }
    Ok(())
}

/// Change of the first grid-line angle at a wall, in radians.
///
/// Definition. For every wall node `w` (a node of some wall element):
/// - the wall normal `n(w)` is the normalised sum of the length- (2D) or area-weighted (3D)
///   normals of the wall elements containing `w`, computed separately in the undeformed and
///   the deformed mesh with the elements' own orientation (line `a → b`: `(dy, −dx)`; face:
///   right-hand rule);
/// - among the graph neighbours of `w` that are not wall nodes, the *first grid line* is the
///   edge `w → j` that is most normal in the undeformed mesh: largest `|n·e|/|e|` (the first
///   in neighbour order on ties);
/// - `θ` is the angle from `n` to that edge: signed in 2D, `atan2(n × e, n · e)` in `(−π, π]`,
///   unsigned in 3D, `atan2(|n × e|, n · e)` in `[0, π]` (so a 3D twist about the normal is
///   not seen);
/// - the change is `|θ_deformed − θ_undeformed|`, wrapped to `[0, π]` in 2D.
///
/// Returns the maximum over wall nodes (see [`WallAngleChange`]). A rigid motion of the whole
/// mesh gives 0 up to rounding; a sheared boundary layer shows the shear angle.
///
/// Coordinates are assumed small enough that element normals (products of coordinate
/// differences) do not overflow; a wall node whose normal sum overflows is treated as off-wall.
///
/// `scratch` needs [`wall_angle_scratch_len`] items and is overwritten.
///
/// # Errors
/// Nothing is written on error: point arrays not matching the wall's node count, non-finite
/// coordinates, wall elements of the wrong kind ([`Error::CellDimension`]), scratch too small.
pub fn wall_angle_change<T: Real, const D: usize>(
    wall: &Wall<'_>,
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
    scratch: &mut [[T; D]],
) -> Result<WallAngleChange<T>> {
    crate::check::mesh_dim::<D>();
    check_wall(wall, undeformed, deformed)?;
    crate::check::finite_items("undeformed", undeformed)?;
    crate::check::finite_items("deformed", deformed)?;
    let n = undeformed.len();
    let needed = wall_angle_scratch_len(n);
    check::buffer("scratch", scratch.len(), needed)?;
    Ok(compute(wall, undeformed, deformed, scratch))
}

/// The computation behind [`wall_angle_change`], on validated inputs.
pub(crate) fn compute<T: Real, const D: usize>(
    wall: &Wall<'_>,
    undeformed: &[[T; D]],
    deformed: &[[T; D]],
    scratch: &mut [[T; D]],
) -> WallAngleChange<T> {
    let n = undeformed.len();
    let empty = WallAngleChange {
        max_change: T::ZERO,
        node: None,
        measured: 0,
        skipped: 0,
    };
    let Some((nu, rest)) = scratch.split_at_mut_checked(n) else {
        return empty;
    };
    let Some(nd) = rest.get_mut(..n) else {
        return empty;
    };
    // Non-wall sentinel: infinite first component.
    for s in nu.iter_mut().chain(nd.iter_mut()) {
        *s = [T::INFINITY; D];
    }
    for (kind, nodes) in wall.elements.iter() {
        let eu = element_normal(kind, nodes, undeformed);
        let ed = element_normal(kind, nodes, deformed);
        for &v in nodes {
            let v = v as usize;
            for (slots, e) in [(&mut *nu, eu), (&mut *nd, ed)] {
                if let Some(s) = slots.get_mut(v) {
                    if is_wall::<T, D>(Some(s)) {
                        for (x, y) in s.iter_mut().zip(e) {
                            *x += y;
                        }
                    } else {
                        *s = e;
                    }
                }
            }
        }
    }
    let mut out = empty;
    let pairs = nu
        .iter()
        .zip(nd.iter())
        .zip(undeformed.iter().zip(deformed));
    for (w, ((su, sd), (&xu, &xd))) in pairs.enumerate() {
        if !is_wall::<T, D>(Some(su)) {
            continue;
        }
        let (Some(n_u), Some(n_d)) = (normalize(*su), normalize(*sd)) else {
            out.skipped += 1;
            continue;
        };
        let mut best: Option<(T, usize)> = None;
        for &j in wall.graph.neighbors(w) {
            let j = j as usize;
            if is_wall::<T, D>(nu.get(j)) {
                continue;
            }
            let Some(&pj) = undeformed.get(j) else {
                continue;
            };
            let e = sub(pj, xu);
            let len = norm(e);
            if len <= T::ZERO || !len.is_finite() {
                continue;
            }
            let score = dot(n_u, e).abs() / len;
            let better = match best {
                Some((b, _)) => score > b,
                None => true,
            };
            if better {
                best = Some((score, j));
            }
        }
        let Some((_, j)) = best else {
            out.skipped += 1;
            continue;
        };
        let (Some(&pu), Some(&pd)) = (undeformed.get(j), deformed.get(j)) else {
            out.skipped += 1;
            continue;
        };
        let eu = sub(pu, xu);
        let ed = sub(pd, xd);
        if norm(ed) <= T::ZERO {
            out.skipped += 1;
            continue;
        }
        let mut delta = angle(n_d, ed) - angle(n_u, eu);
        if D == 2 {
            if delta > T::PI {
                delta -= T::TWO * T::PI;
            } else if delta < -T::PI {
                delta += T::TWO * T::PI;
            }
        }
        let change = delta.abs();
        out.measured += 1;
        if out.node.is_none() || change > out.max_change {
            out.max_change = change;
            out.node = Some(w);
        }
    }
    out
}
