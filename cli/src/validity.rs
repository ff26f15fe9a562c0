//! Validity from geometry, whatever order each cell's nodes are listed in.
//!
//! SU2 reorders cells listed clockwise (2D) or mirrored (3D) one by one and runs such meshes, so
//! a cell listed "the other way" is not folded. A cell is folded when its geometry is:
//! - its corners disagree in sign with each other (a bow-tie, a dart, a twisted hexahedron), or
//! - it overlaps a neighbour: across a shared face (an edge in 2D) both cells lie on the same
//!   side. With every cell's outward face orientation taken from its own signed measure, two
//!   cells lie on opposite sides of a shared face exactly when they traverse it in opposite
//!   directions (exact, combinatorial: no rounding).
//!
//! Which of two overlapping cells is folded cannot be told from the pair alone; the cell whose
//! listing disagrees with the majority of its connected region ([`crate::orientation`]) is
//! blamed, else the one with the larger share of such faces, else both.

use crate::formats::CellList;

const EDGES_TRI: &[&[u8]] = &[&[0, 1], &[1, 2], &[2, 0]];
const EDGES_QUAD: &[&[u8]] = &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]];
const FACES_TET: &[&[u8]] = &[&[0, 2, 1], &[0, 1, 3], &[1, 2, 3], &[0, 3, 2]];
const FACES_HEX: &[&[u8]] = &[
    &[0, 3, 2, 1],
    &[4, 5, 6, 7],
    &[0, 1, 5, 4],
    &[1, 2, 6, 5],
    &[2, 3, 7, 6],
    &[3, 0, 4, 7],
];
// The kernel's (SU2's) prism is positive when its base 0,1,2 turns away from the top 3,4,5.
const FACES_PRISM: &[&[u8]] = &[
    &[0, 1, 2],
    &[3, 5, 4],
    &[0, 3, 4, 1],
    &[1, 4, 5, 2],
    &[2, 5, 3, 0],
];
const FACES_PYRAMID: &[&[u8]] = &[
    &[0, 3, 2, 1],
    &[0, 1, 4],
    &[1, 2, 4],
    &[2, 3, 4],
    &[3, 0, 4],
];

/// The faces (edges in 2D) of a cell kind, as local node cycles oriented outward for a cell with
/// a positive signed measure (in 2D: the edges in listing order, the cell on their left).
pub fn local_faces(kind: u8) -> &'static [&'static [u8]] {
    match kind {
        5 => EDGES_TRI,
        9 => EDGES_QUAD,
        10 => FACES_TET,
        12 => FACES_HEX,
        13 => FACES_PRISM,
        14 => FACES_PYRAMID,
        _ => &[],
    }
}

/// One face of one cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellFace {
    /// The face's nodes sorted ascending, unused slots `u32::MAX`: equal for the two cells that
    /// share the face.
    pub key: [u32; 4],
    /// The cell.
    pub cell: u32,
    /// The face's index in [`local_faces`] of the cell's kind.
    pub local: u8,
    /// +1 or −1: the cell's outward traversal of the face against the key's reference cycle;
    /// 0 when the cell's outward direction is unknown (a folded or zero-measure cell).
    pub side: i8,
}

/// The sorted key of a face cycle and the direction the cycle runs in (+1 or −1), so that two
/// cycles over the same nodes run the same way exactly when their directions are equal.
fn key_and_direction(cycle: &[u32]) -> ([u32; 4], i8) {
    let mut key = [u32::MAX; 4];
    for (k, &n) in key.iter_mut().zip(cycle) {
        *k = n;
    }
    sort4(&mut key);
    let len = cycle.len();
    let Some(m) = (0..len).min_by_key(|&i| cycle[i]) else {
        return (key, 1);
    };
    let direction = match len {
        2 => m == 0,
        _ => cycle[(m + 1) % len] < cycle[(m + len - 1) % len],
    };
    (key, if direction { 1 } else { -1 })
}

/// Sorts four values ascending (a five-comparator network; unused slots hold `u32::MAX`, which
/// stays last).
fn sort4(k: &mut [u32; 4]) {
    for (i, j) in [(0, 1), (2, 3), (0, 2), (1, 3), (1, 2)] {
        let (a, b) = (k[i], k[j]);
        k[i] = a.min(b);
        k[j] = a.max(b);
    }
}

/// Every face of every cell, sorted by key (the two cells sharing a face come together).
/// `sense[c]`: +1 for a cell with positive signed measure, −1 for a negative one, 0 when its
/// outward direction is unknown.
pub fn cell_faces(cells: &CellList, sense: &[i8]) -> Vec<CellFace> {
    let mut faces = Vec::with_capacity(cells.len().saturating_mul(4));
    for (c, (kind, nodes)) in cells.iter().enumerate() {
        let s = sense.get(c).copied().unwrap_or(0);
        for (f, local) in local_faces(kind).iter().enumerate() {
            // A face has at most 4 nodes: no allocation per face.
            let mut cycle = [0u32; 4];
            let mut len = 0;
            for (slot, n) in cycle
                .iter_mut()
                .zip(local.iter().filter_map(|&i| nodes.get(i as usize)))
            {
                *slot = *n;
                len += 1;
            }
            if len != local.len() {
                continue;
            }
            let (key, direction) = key_and_direction(&cycle[..len]);
            faces.push(CellFace {
                key,
                cell: c as u32,
                local: f as u8,
                side: direction * s,
            });
        }
    }
    sort_by_key(faces)
}

/// `faces` sorted by `(key, position in faces)`, which is `(key, cell, local)` for faces listed
/// by cell and local index as [`cell_faces`] lists them: a counting sort by the smallest node
/// (`key[0]`), then each small bucket sorted as plain integers (the rest of the key and the
/// position packed in one `u128`), the order a full sort gives at a fraction of its cost.
fn sort_by_key(faces: Vec<CellFace>) -> Vec<CellFace> {
    if u32::try_from(faces.len()).is_err() {
        let mut all = faces;
        all.sort_by_key(|f| f.key);
        return all;
    }
    let buckets = faces
        .iter()
        .map(|f| f.key[0] as usize + 1)
        .max()
        .unwrap_or(0);
    let mut start = vec![0usize; buckets + 1];
    for f in &faces {
        start[f.key[0] as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut cursor = start.clone();
    let mut packed = vec![0u128; faces.len()];
    for (i, f) in faces.iter().enumerate() {
        let k = |j: usize| u128::from(f.key[j]);
        let c = &mut cursor[f.key[0] as usize];
        packed[*c] = k(1) << 96 | k(2) << 64 | k(3) << 32 | i as u128;
        *c += 1;
    }
    for w in start.windows(2) {
        packed[w[0]..w[1]].sort_unstable();
    }
    packed
        .iter()
        .filter_map(|&p| faces.get(p as u32 as usize).copied())
        .collect()
}

/// Per cell: overlaps a neighbour across a shared face (both on the same side of it), and is
/// the one to blame (see the module doc). `sense` as in [`cell_faces`]; `against[c]`: the
/// cell's listing disagrees with its region's majority. When that does not tell the two cells
/// apart, the one with the larger share of such faces among its judged faces is blamed (a
/// triangle flipped over its neighbours: all of its faces, one of each neighbour's), both on a
/// tie. Faces shared by more than two cells are not judged.
pub fn overlapping(cells: &CellList, sense: &[i8], against: &[bool]) -> Vec<bool> {
    overlapping_and_boundary(cells, sense, against).0
}

/// [`overlapping`], and [`boundary_faces`] from the same sorted faces (one sort for both).
pub fn overlapping_and_boundary(
    cells: &CellList,
    sense: &[i8],
    against: &[bool],
) -> (Vec<bool>, Vec<Vec<u32>>) {
    let faces = cell_faces(cells, sense);
    // The judged pairs (both directions known) and, per cell, (bad faces, judged faces).
    let mut bad_pairs = Vec::new();
    let mut share = vec![(0u32, 0u32); cells.len()];
    let mut boundary = Vec::new();
    for group in faces.chunk_by(|a, b| a.key == b.key) {
        if let [f] = group {
            boundary.extend(face_cycle(cells, f));
        }
        let [a, b] = group else { continue };
        if a.side == 0 || b.side == 0 {
            continue;
        }
        let bad = a.side == b.side;
        for f in [a, b] {
            if let Some(s) = share.get_mut(f.cell as usize) {
                s.0 += u32::from(bad);
                s.1 += 1;
            }
        }
        if bad {
            bad_pairs.push((a.cell as usize, b.cell as usize));
        }
    }
    let against_of = |c: usize| against.get(c).copied().unwrap_or(false);
    // a's share of bad faces compared with b's (exact: cross-multiplied counts).
    let compare = |a: usize, b: usize| {
        let ((ba, ja), (bb, jb)) = (share[a], share[b]);
        (u64::from(ba) * u64::from(jb)).cmp(&(u64::from(bb) * u64::from(ja)))
    };
    let mut out = vec![false; cells.len()];
    for (a, b) in bad_pairs {
        let (blame_a, blame_b) = match (against_of(a), against_of(b)) {
            (true, false) => (true, false),
            (false, true) => (false, true),
            _ => match compare(a, b) {
                std::cmp::Ordering::Greater => (true, false),
                std::cmp::Ordering::Less => (false, true),
                std::cmp::Ordering::Equal => (true, true),
            },
        };
        out[a] |= blame_a;
        out[b] |= blame_b;
    }
    (out, boundary)
}

/// The node cycle of one cell face.
fn face_cycle(cells: &CellList, f: &CellFace) -> Option<Vec<u32>> {
    let (kind, nodes) = cells.cell(f.cell as usize);
    local_faces(kind).get(f.local as usize).map(|local| {
        local
            .iter()
            .filter_map(|&i| nodes.get(i as usize).copied())
            .collect()
    })
}

/// The faces (edges in 2D) that belong to one cell only: the mesh's boundary, as node cycles
/// (sorted by their keys).
pub fn boundary_faces(cells: &CellList) -> Vec<Vec<u32>> {
    let faces = cell_faces(cells, &[]);
    let mut out = Vec::new();
    for group in faces.chunk_by(|a, b| a.key == b.key) {
        if let [f] = group {
            out.extend(face_cycle(cells, f));
        }
    }
    out
}

/// The boundary faces of a mesh that belong to no marker.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Unmarked {
    /// How many.
    pub faces: usize,
    /// The centroid of the first one (in key order), to find them.
    pub sample: Option<[f64; 3]>,
    /// Their nodes that are on no marker either (sorted): these move as field nodes.
    pub free_nodes: Vec<u32>,
}

/// The boundary faces of `cells` (edges in 2D) that are elements of none of `markers`: a wall
/// left out of the marker list is moved like the field around it, so it is worth a warning.
pub fn unmarked_boundary(cells: &CellList, markers: &[&CellList], points: &[[f64; 3]]) -> Unmarked {
    unmarked_among(&boundary_faces(cells), markers, points)
}

/// [`unmarked_boundary`] of the mesh whose [`boundary_faces`] are `boundary` (e.g. the
/// quality pass's, [`crate::engine::QualitySummary::boundary_faces`]).
pub fn unmarked_among(
    boundary: &[Vec<u32>],
    markers: &[&CellList],
    points: &[[f64; 3]],
) -> Unmarked {
    let mut marked: Vec<[u32; 4]> = markers
        .iter()
        .flat_map(|m| m.iter().map(|(_, nodes)| face_key(nodes)))
        .collect();
    marked.sort_unstable();
    let mut on_marker: Vec<u32> = markers
        .iter()
        .flat_map(|m| m.nodes.iter().copied())
        .collect();
    on_marker.sort_unstable();
    let mut out = Unmarked::default();
    for face in boundary {
        if marked.binary_search(&face_key(face)).is_ok() {
            continue;
        }
        out.faces += 1;
        if out.sample.is_none() {
            let n = face.len().max(1) as f64;
            let sum = face.iter().fold([0.0; 3], |s, &v| {
                let p = points.get(v as usize).copied().unwrap_or([0.0; 3]);
                [s[0] + p[0], s[1] + p[1], s[2] + p[2]]
            });
            out.sample = Some(sum.map(|x| x / n));
        }
        out.free_nodes
            .extend(face.iter().filter(|v| on_marker.binary_search(v).is_err()));
    }
    out.free_nodes.sort_unstable();
    out.free_nodes.dedup();
    out
}

/// The sorted node key of a face (or boundary element) given as a node list.
pub fn face_key(nodes: &[u32]) -> [u32; 4] {
    key_and_direction(nodes).0
}

/// Rewrites cell `nodes` of `kind` in the opposite orientation (the same cell, its signed
/// measure negated): for `deform convert --reorient`. Kinds without a volume are unchanged.
pub fn reverse_cell(kind: u8, nodes: &mut [u32]) {
    let order: &[usize] = match kind {
        5 => &[0, 2, 1],
        9 => &[0, 3, 2, 1],
        10 => &[0, 2, 1, 3],
        12 => &[0, 3, 2, 1, 4, 7, 6, 5],
        13 => &[0, 2, 1, 3, 5, 4],
        14 => &[0, 3, 2, 1, 4],
        _ => return,
    };
    if nodes.len() != order.len() {
        return;
    }
    let old = nodes.to_vec();
    for (slot, &i) in nodes.iter_mut().zip(order) {
        *slot = old[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use deform_kernel::quality::cell_measures;
    use deform_kernel::Cells;

    #[test]
    fn bucketed_sort_is_the_full_sort() {
        // Pseudo-random faces with many shared smallest nodes and ties on the key.
        let mut x = 12345u64;
        let mut next = |m: u32| {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 33) as u32) % m
        };
        let mut faces: Vec<CellFace> = (0..5000)
            .map(|c| {
                let mut key = [next(300), next(300), next(300), u32::MAX];
                key[..3].sort_unstable();
                CellFace {
                    key,
                    cell: c % 700,
                    local: next(4) as u8,
                    side: 1,
                }
            })
            .collect();
        // Listed by cell and local index, as `cell_faces` lists them.
        faces.sort_by_key(|f| (f.cell, f.local));
        let mut full = faces.clone();
        full.sort_unstable_by_key(|f| (f.key, f.cell, f.local));
        assert_eq!(sort_by_key(faces), full);
        assert!(sort_by_key(Vec::new()).is_empty());
    }

    /// A positive cell of each 3D kind (kernel measure > 0): corners of the unit cube.
    fn shapes() -> Vec<(u8, Vec<[f64; 3]>)> {
        let cube = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        vec![
            (10, vec![cube[0], cube[1], cube[3], cube[4]]),
            (12, cube.to_vec()),
            (
                13,
                vec![cube[0], cube[3], cube[1], cube[4], cube[7], cube[5]],
            ),
            (
                14,
                vec![cube[0], cube[1], cube[2], cube[3], [0.5, 0.5, 1.0]],
            ),
        ]
    }

    fn measure(kind: u8, pts: &[[f64; 3]]) -> f64 {
        let conn: Vec<u32> = (0..pts.len() as u32).collect();
        let offsets = [0, pts.len() as u32];
        let kinds = [kind];
        let cells = Cells::new(pts.len(), &offsets, &conn, &kinds).expect("cell");
        let mut m = [0.0];
        cell_measures(&cells, pts, &mut m).expect("measure");
        m[0]
    }

    #[test]
    fn faces_point_outward_for_positive_cells_and_reversal_flips_the_sign() {
        for (kind, pts) in shapes() {
            assert!(measure(kind, &pts) > 0.0, "kind {kind} reference shape");
            let n = pts.len() as f64;
            let centre = pts
                .iter()
                .fold([0.0; 3], |s, p| [s[0] + p[0], s[1] + p[1], s[2] + p[2]])
                .map(|x| x / n);
            for face in local_faces(kind) {
                // Newell's normal of the cycle; outward = away from the centre.
                let mut normal = [0.0; 3];
                let mut fc = [0.0; 3];
                for (i, &a) in face.iter().enumerate() {
                    let p = pts[a as usize];
                    let q = pts[face[(i + 1) % face.len()] as usize];
                    normal[0] += (p[1] - q[1]) * (p[2] + q[2]);
                    normal[1] += (p[2] - q[2]) * (p[0] + q[0]);
                    normal[2] += (p[0] - q[0]) * (p[1] + q[1]);
                    for k in 0..3 {
                        fc[k] += p[k] / face.len() as f64;
                    }
                }
                let out: f64 = (0..3).map(|k| normal[k] * (fc[k] - centre[k])).sum();
                assert!(out > 0.0, "kind {kind} face {face:?} points inward");
            }
            let mut order: Vec<u32> = (0..pts.len() as u32).collect();
            reverse_cell(kind, &mut order);
            let reversed: Vec<[f64; 3]> = order.iter().map(|&i| pts[i as usize]).collect();
            assert!(measure(kind, &reversed) < 0.0, "kind {kind} reversed");
        }
    }

    #[test]
    fn a_cell_listed_the_other_way_is_not_an_overlap_but_a_flipped_one_is() {
        // Two triangles sharing edge 1–2: (0,1,2) counter-clockwise, (1,3,2) on the other side.
        let mut cells = CellList::new();
        cells.push(deform_kernel::CellKind::Triangle, &[0, 1, 2]);
        cells.push(deform_kernel::CellKind::Triangle, &[1, 2, 3]);
        // Listed clockwise but on the other side of the edge: sense −1, no overlap.
        assert_eq!(
            overlapping(&cells, &[1, -1], &[false, true]),
            [false, false]
        );
        // The same listing with node 3 on the same side as node 0 (sense +1): overlap, and
        // the cell against its region is blamed.
        assert_eq!(overlapping(&cells, &[1, 1], &[false, true]), [false, true]);
        assert_eq!(overlapping(&cells, &[1, 1], &[false, false]), [true, true]);
        // A third cell with a good face tips the share: cell 1 has 1 bad of 2 judged faces,
        // cell 0 1 of 1.
        let mut three = cells.clone();
        three.push(deform_kernel::CellKind::Triangle, &[1, 4, 3]);
        assert_eq!(
            overlapping(&three, &[1, 1, -1], &[false, false, false]),
            [true, false, false]
        );
        // Unknown outward direction: not judged.
        assert_eq!(
            overlapping(&cells, &[1, 0], &[false, false]),
            [false, false]
        );
        assert_eq!(boundary_faces(&cells).len(), 4);
    }

    #[test]
    fn the_sorting_network_sorts() {
        let mut x = 7u32;
        for _ in 0..10_000 {
            let mut k = [0u32; 4];
            for v in k.iter_mut() {
                x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
                *v = (x >> 16) % 6;
            }
            let mut want = k;
            want.sort_unstable();
            sort4(&mut k);
            assert_eq!(k, want);
        }
    }

    #[test]
    fn face_directions_agree_for_the_same_cycle_and_differ_for_the_reverse() {
        for cycle in [&[4u32, 9, 2][..], &[7, 3, 8, 1], &[5, 2]] {
            let (k, d) = key_and_direction(cycle);
            let mut rotated = cycle.to_vec();
            rotated.rotate_left(1);
            let mut reversed = cycle.to_vec();
            reversed.reverse();
            if cycle.len() > 2 {
                assert_eq!(key_and_direction(&rotated), (k, d));
            }
            assert_eq!(key_and_direction(&reversed), (k, -d));
        }
    }
}
