//! Prescribed boundary motion: rigid rotation of marker nodes (e.g. an airfoil pitched about
//! its quarter chord), returned as a displacement per marker node.

use crate::{invalid, Mesh2, Mesh3, Result};

/// Displacements prescribed on a set of nodes.
#[derive(Clone, Debug, PartialEq)]
pub struct Prescribed<const D: usize> {
    /// The moved nodes, ascending, each once.
    pub nodes: Vec<u32>,
    /// Displacement of each node in `nodes` (new position minus old).
    pub displacements: Vec<[f64; D]>,
}

impl<const D: usize> Prescribed<D> {
    /// A per-node displacement array of length `node_count`: the prescribed values on
    /// `nodes`, zero elsewhere (so with [`crate::Mesh::boundary_mask`] as the fixed mask,
    /// every other marker is held in place).
    pub fn to_field(&self, node_count: usize) -> Vec<[f64; D]> {
        let mut f = vec![[0.0; D]; node_count];
        for (&n, d) in self.nodes.iter().zip(&self.displacements) {
            if let Some(slot) = f.get_mut(n as usize) {
                *slot = *d;
            }
        }
        f
    }
}

fn union_nodes<const D: usize>(mesh: &crate::Mesh<D>, markers: &[&str]) -> Result<Vec<u32>> {
    let mut nodes = Vec::new();
    for name in markers {
        nodes.extend_from_slice(&mesh.require_marker(name)?.node_list);
    }
    nodes.sort_unstable();
    nodes.dedup();
    Ok(nodes)
}

/// Rotates the nodes of the named markers by `degrees` (counter-clockwise) about `centre`
/// and returns each node's displacement. For an airfoil with its chord along `+x`, a positive
/// (counter-clockwise) angle about the quarter chord raises the trailing edge: nose down.
pub fn rotate_markers2(
    mesh: &Mesh2,
    markers: &[&str],
    centre: [f64; 2],
    degrees: f64,
) -> Result<Prescribed<2>> {
    if !degrees.is_finite() || !centre.iter().all(|c| c.is_finite()) {
        return invalid("rotation angle and centre must be finite");
    }
    let nodes = union_nodes(mesh, markers)?;
    let a = degrees.to_radians();
    let (s, c) = (libm::sin(a), libm::cos(a));
    let displacements = nodes
        .iter()
        .map(|&n| {
            let p = mesh.points[n as usize];
            let dx = p[0] - centre[0];
            let dy = p[1] - centre[1];
            let q = [centre[0] + c * dx - s * dy, centre[1] + s * dx + c * dy];
            [q[0] - p[0], q[1] - p[1]]
        })
        .collect();
    Ok(Prescribed {
        nodes,
        displacements,
    })
}

/// Rotates the nodes of the named markers by `degrees` about the axis through `centre` along
/// `axis` (right-hand rule; the axis need not be unit length) and returns each displacement.
pub fn rotate_markers3(
    mesh: &Mesh3,
    markers: &[&str],
    centre: [f64; 3],
    axis: [f64; 3],
    degrees: f64,
) -> Result<Prescribed<3>> {
    let len = libm::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    if !(len > 0.0) || !len.is_finite() {
        return invalid("rotation axis must be non-zero and finite");
    }
    if !degrees.is_finite() || !centre.iter().all(|c| c.is_finite()) {
        return invalid("rotation angle and centre must be finite");
    }
    let k = axis.map(|x| x / len);
    let nodes = union_nodes(mesh, markers)?;
    let a = degrees.to_radians();
    let (s, c) = (libm::sin(a), libm::cos(a));
    let displacements = nodes
        .iter()
        .map(|&n| {
            let p = mesh.points[n as usize];
            let v = [p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]];
            // Rodrigues: v c + (k × v) s + k (k·v)(1 − c).
            let kv = [
                k[1] * v[2] - k[2] * v[1],
                k[2] * v[0] - k[0] * v[2],
                k[0] * v[1] - k[1] * v[0],
            ];
            let kd = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
            let mut d = [0.0; 3];
            for i in 0..3 {
                let r = v[i] * c + kv[i] * s + k[i] * kd * (1.0 - c);
                d[i] = r - v[i];
            }
            d
        })
        .collect();
    Ok(Prescribed {
        nodes,
        displacements,
    })
}
