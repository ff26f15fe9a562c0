//! The boundary of the partitioned quaternion tests: the serial boundary of a generated mesh
//! in a scrambled order with its elements, a prescribed motion, per-node rotations, and each
//! thread's share of it (its owned boundary nodes and the elements it gives).

use deform_kernel::quat::Quat;
use deform_meshgen::partition::LocalView;
use deform_meshgen::Mesh;

/// The serial boundary: mesh nodes of every marker in a scrambled order (so that the
/// boundary order is not the node order), and every marker's elements in that numbering.
pub struct Bnd {
    pub nodes: Vec<u32>,
    pub offsets: Vec<u32>,
    pub elements: Vec<u32>,
    pub kinds: Vec<u8>,
}

pub fn boundary<const D: usize>(mesh: &Mesh<D>) -> Bnd {
    let mut nodes: Vec<u32> = Vec::new();
    for m in &mesh.markers {
        for &n in &m.node_list {
            if !nodes.contains(&n) {
                nodes.push(n);
            }
        }
    }
    let b = nodes.len();
    // A stride coprime to `b` (a prime that does not divide it) scrambles the order.
    let step = [7, 11, 13].into_iter().find(|s| b % s != 0).unwrap();
    nodes = (0..b).map(|k| nodes[(k * step + 3) % b]).collect();
    let mut pos = vec![u32::MAX; mesh.points.len()];
    for (k, &n) in nodes.iter().enumerate() {
        pos[n as usize] = k as u32;
    }
    let (mut offsets, mut elements, mut kinds) = (vec![0u32], Vec::new(), Vec::new());
    for m in &mesh.markers {
        for e in 0..m.kinds.len() {
            let el = &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize];
            elements.extend(el.iter().map(|&n| pos[n as usize]));
            kinds.push(m.kinds[e]);
            offsets.push(elements.len() as u32);
        }
    }
    Bnd {
        nodes,
        offsets,
        elements,
        kinds,
    }
}

/// A pitch by `deg` about the quarter chord plus a heave of the `"airfoil"` nodes; the rest
/// of the boundary stays.
pub fn moved<const D: usize>(mesh: &Mesh<D>, nodes: &[u32], deg: f64) -> Vec<[f64; D]> {
    let wall = &mesh.marker("airfoil").unwrap().node_list;
    let (s, c) = deg.to_radians().sin_cos();
    nodes
        .iter()
        .map(|&n| {
            let mut p = mesh.points[n as usize];
            if wall.binary_search(&n).is_ok() {
                let (x, y) = (p[0] - 0.25, p[1]);
                p[0] = 0.25 + c * x - s * y;
                p[1] = s * x + c * y + 0.02;
            }
            p
        })
        .collect()
}

/// One thread's share of the boundary: its owned boundary nodes with their positions and
/// deformed points, and the elements whose first node it owns (or `give` decides).
pub struct Share<const D: usize> {
    pub nodes: Vec<u32>,
    pub positions: Vec<u32>,
    pub deformed: Vec<[f64; D]>,
    pub ids: Vec<u32>,
    pub offsets: Vec<u32>,
    pub elements: Vec<u32>,
    pub kinds: Vec<u8>,
    /// `RotationSource::PerNode` rotations at `positions` (empty unless set).
    pub rotations: Vec<Quat<f64>>,
}

pub fn share<const D: usize>(
    v: &LocalView<D>,
    bnd: &Bnd,
    deformed: &[[f64; D]],
    give: impl Fn(usize, bool) -> bool,
) -> Share<D> {
    let mut s = Share {
        nodes: Vec::new(),
        positions: Vec::new(),
        deformed: Vec::new(),
        ids: Vec::new(),
        offsets: vec![0],
        elements: Vec::new(),
        kinds: Vec::new(),
        rotations: Vec::new(),
    };
    let owns = |g: u32| {
        v.global_ids[..v.owned]
            .iter()
            .position(|&x| x == u64::from(g))
    };
    for (k, &g) in bnd.nodes.iter().enumerate() {
        if let Some(i) = owns(g) {
            s.nodes.push(i as u32);
            s.positions.push(k as u32);
            s.deformed.push(deformed[k]);
        }
    }
    for c in 0..bnd.kinds.len() {
        let el = &bnd.elements[bnd.offsets[c] as usize..bnd.offsets[c + 1] as usize];
        if give(c, owns(bnd.nodes[el[0] as usize]).is_some()) {
            s.ids.push(c as u32);
            s.elements.extend_from_slice(el);
            s.kinds.push(bnd.kinds[c]);
            s.offsets.push(s.elements.len() as u32);
        }
    }
    s
}

/// Per-node rotations for `RotationSource::PerNode`, in boundary order: a turn about `z` that
/// varies along the boundary, scaled away from unit length (the serial pipeline averages the
/// rotations as given and normalises them only for `Δ`, so the gather must carry them
/// exactly).
pub fn per_node_rotations(b: usize) -> Vec<Quat<f64>> {
    (0..b)
        .map(|k| {
            let angle = 0.3 * (k as f64 * 0.37).sin();
            let (s, c) = (0.5 * angle).sin_cos();
            let scale = 1.0 + 0.25 * (k as f64 * 0.11).cos();
            Quat::new(scale * c, 0.01 * scale, -0.02 * scale, scale * s)
        })
        .collect()
}

/// The entries of `all` (boundary order) at this share's positions: its `PerNode` rotations.
pub fn share_rotations<const D: usize>(s: &Share<D>, all: &[Quat<f64>]) -> Vec<Quat<f64>> {
    s.positions.iter().map(|&p| all[p as usize]).collect()
}
