//! 3D extrusion of 2D meshes in `z`, and a twist/bend map for wing tests.

use deform_kernel::CellKind;

use crate::{invalid, Marker, Mesh2, Mesh3, Result};

/// Extrudes a 2D mesh over `0 ≤ z ≤ span` with `layers` cell layers.
///
/// Point `p` of layer `k` (`z = span k / layers`) gets index `p + n k` (n = 2D node count), so
/// a structured 2D block `[ni, nj, 1]` becomes `[ni, nj, layers + 1]`. Quads become hexes and
/// triangles become VTK wedges (base turned away from the top, see the crate docs). Every 2D
/// marker becomes a marker of the same name made of quads (an airfoil wall becomes wall
/// quads), and two markers `"zmin"` and `"zmax"` hold the end caps. All boundary faces have
/// their right-hand normal pointing out of the domain.
pub fn extrude(mesh: &Mesh2, span: f64, layers: usize) -> Result<Mesh3> {
    if layers == 0 {
        return invalid("layers must be >= 1");
    }
    if !(span > 0.0) || !span.is_finite() {
        return invalid("span must be a positive finite number");
    }
    let n = mesh.node_count();
    let total = n
        .checked_mul(layers + 1)
        .filter(|&t| u32::try_from(t).is_ok());
    if total.is_none() {
        return invalid("too many nodes for u32 indices");
    }
    let mut out = Mesh3::new();
    out.points.reserve(n * (layers + 1));
    for k in 0..=layers {
        let z = span * k as f64 / layers as f64;
        for p in &mesh.points {
            out.points.push([p[0], p[1], z]);
        }
    }
    let at = |p: u32, k: usize| p + (n * k) as u32;
    for k in 0..layers {
        for c in 0..mesh.cell_count() {
            let Some((kind, nodes)) = mesh.cell(c) else {
                continue;
            };
            match kind {
                CellKind::Quad => {
                    let mut h = [0u32; 8];
                    for (l, &p) in nodes.iter().enumerate() {
                        h[l] = at(p, k);
                        h[l + 4] = at(p, k + 1);
                    }
                    out.push_cell(CellKind::Hexahedron, &h);
                }
                CellKind::Triangle => {
                    let (a, b, c) = (nodes[0], nodes[1], nodes[2]);
                    out.push_cell(
                        CellKind::Prism,
                        &[
                            at(a, k),
                            at(c, k),
                            at(b, k),
                            at(a, k + 1),
                            at(c, k + 1),
                            at(b, k + 1),
                        ],
                    );
                }
                _ => return invalid(format!("cell {c} is not a triangle or quad")),
            }
        }
    }
    for m in &mesh.markers {
        let mut mm = Marker::new(&m.name);
        for k in 0..layers {
            for w in m.offsets.windows(2) {
                let e = &m.nodes[w[0] as usize..w[1] as usize];
                if let [a, b] = *e {
                    mm.push(
                        CellKind::Quad,
                        &[at(a, k), at(b, k), at(b, k + 1), at(a, k + 1)],
                    );
                }
            }
        }
        mm.finish();
        out.markers.push(mm);
    }
    let mut zmin = Marker::new("zmin");
    let mut zmax = Marker::new("zmax");
    for c in 0..mesh.cell_count() {
        let Some((kind, nodes)) = mesh.cell(c) else {
            continue;
        };
        let bottom: Vec<u32> = nodes.iter().rev().map(|&p| at(p, 0)).collect();
        let top: Vec<u32> = nodes.iter().map(|&p| at(p, layers)).collect();
        zmin.push(kind, &bottom);
        zmax.push(kind, &top);
    }
    zmin.finish();
    zmax.finish();
    out.markers.push(zmin);
    out.markers.push(zmax);
    out.dims = mesh.dims.map(|d| [d[0], d[1], layers + 1]);
    out.periodic_i = mesh.periodic_i;
    Ok(out)
}

/// A twist-and-bend map for extruded wings (spanwise coordinate `z ∈ [0, span]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwistBend {
    /// Span of the wing (`z` of the tip).
    pub span: f64,
    /// Twist at the tip in degrees, linear in `z`, positive counter-clockwise about `+z`
    /// (nose up for a wing whose chord runs along `+x`), about `centre`.
    pub tip_twist_deg: f64,
    /// Bend: `y` displacement of the tip, quadratic in `z` (zero slope at the root).
    pub tip_bend: f64,
    /// Centre of the twist in the `(x, y)` plane, e.g. the quarter chord `(0.25, 0)`.
    pub centre: [f64; 2],
}

impl TwistBend {
    /// Image of one point.
    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let eta = p[2] / self.span;
        let angle = self.tip_twist_deg.to_radians() * eta;
        let (s, c) = (libm::sin(angle), libm::cos(angle));
        let dx = p[0] - self.centre[0];
        let dy = p[1] - self.centre[1];
        // Displacement form, so the root (angle 0, no bend) is reproduced bit for bit.
        [
            p[0] + ((c - 1.0) * dx - s * dy),
            p[1] + ((s * dx + (c - 1.0) * dy) + self.tip_bend * eta * eta),
            p[2],
        ]
    }
}

/// Twisted and bent copy of every point of `mesh` (cells and markers unchanged): use the
/// marker nodes' new positions as prescribed boundary motion in deformation tests.
pub fn twist_bend(mesh: &Mesh3, map: &TwistBend) -> Result<Vec<[f64; 3]>> {
    if !(map.span > 0.0) || !map.span.is_finite() {
        return invalid("span must be a positive finite number");
    }
    Ok(mesh.points.iter().map(|&p| map.apply(p)).collect())
}
