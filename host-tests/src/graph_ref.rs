//! Reference implementation of the graph builders and of cell validation, written naively
//! with `Vec` and `BTreeSet` and sharing no code with the kernel.
//!
//! The per-kind edge tables are *not* copied from the kernel: every element kind is described
//! here by its faces in VTK node numbering (each face listed as a polygon), the edges are the
//! sides of those polygons and the face diagonals are the two diagonals of every
//! four-node face. The kernel lists its edges and diagonals directly, so the two descriptions
//! check each other.
//!
//! The only thing shared with the kernel is its `Error` type, used to state which error the
//! reference expects.

use std::collections::BTreeSet;

use deform_kernel::Error;

/// A CSR graph produced by the reference: `offsets` (n + 1 entries) and `targets`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RefGraph {
    /// Row starts, `n + 1` entries.
    pub offsets: Vec<u32>,
    /// Concatenated sorted neighbour lists.
    pub targets: Vec<u32>,
}

/// Number of nodes of a VTK cell kind, `None` for codes the kernel does not support.
pub fn node_count_of(code: u8) -> Option<usize> {
    match code {
        3 => Some(2),  // VTK_LINE
        5 => Some(3),  // VTK_TRIANGLE
        9 => Some(4),  // VTK_QUAD
        10 => Some(4), // VTK_TETRA
        12 => Some(8), // VTK_HEXAHEDRON
        13 => Some(6), // VTK_WEDGE
        14 => Some(5), // VTK_PYRAMID
        _ => None,
    }
}

/// Faces of a VTK cell kind as polygons of local node numbers (a line is one "face" with two
/// nodes). Taken from the VTK file-format figures: hexahedron 0-1-2-3 bottom and 4-5-6-7 top
/// with 4 above 0; wedge 0-1-2 bottom and 3-4-5 top with 3 above 0; pyramid base 0-1-2-3 and
/// apex 4; tetrahedron base 0-1-2 and apex 3.
pub fn faces_of(code: u8) -> Vec<Vec<u8>> {
    match code {
        3 => vec![vec![0, 1]],
        5 => vec![vec![0, 1, 2]],
        9 => vec![vec![0, 1, 2, 3]],
        10 => vec![vec![0, 2, 1], vec![0, 1, 3], vec![1, 2, 3], vec![2, 0, 3]],
        12 => vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
        13 => vec![
            vec![0, 2, 1],
            vec![3, 4, 5],
            vec![0, 1, 4, 3],
            vec![1, 2, 5, 4],
            vec![2, 0, 3, 5],
        ],
        14 => vec![
            vec![0, 3, 2, 1],
            vec![0, 1, 4],
            vec![1, 2, 4],
            vec![2, 3, 4],
            vec![3, 0, 4],
        ],
        _ => vec![],
    }
}

/// Undirected edges of a kind (as ordered pairs `(min, max)` of local numbers): the sides of
/// its face polygons.
pub fn ref_edges(code: u8) -> BTreeSet<(u8, u8)> {
    let mut set = BTreeSet::new();
    for face in faces_of(code) {
        let k = face.len();
        if k == 2 {
            set.insert((face[0].min(face[1]), face[0].max(face[1])));
            continue;
        }
        for i in 0..k {
            let a = face[i];
            let b = face[(i + 1) % k];
            set.insert((a.min(b), a.max(b)));
        }
    }
    set
}

/// Diagonals of the four-node faces of a kind (as `(min, max)` pairs).
pub fn ref_diagonals(code: u8) -> BTreeSet<(u8, u8)> {
    let mut set = BTreeSet::new();
    for face in faces_of(code) {
        if face.len() == 4 {
            for (a, b) in [(face[0], face[2]), (face[1], face[3])] {
                set.insert((a.min(b), a.max(b)));
            }
        }
    }
    set
}

/// Builds the CSR graph from an adjacency given as one set per node.
fn to_csr(adj: &[BTreeSet<u32>]) -> RefGraph {
    let mut offsets = vec![0u32];
    let mut targets = Vec::new();
    for row in adj {
        targets.extend(row.iter().copied());
        offsets.push(targets.len() as u32);
    }
    RefGraph { offsets, targets }
}

/// The reference `graph_from_edges`: same contract as the kernel (errors in the order the
/// kernel documents them: each edge in input order checked for range, first endpoint first,
/// then for a self loop; then the `offsets` length; then the `targets` length).
pub fn graph_from_edges_ref(
    node_count: usize,
    edges: &[[u32; 2]],
    offsets_len: usize,
    targets_len: usize,
) -> Result<RefGraph, Error> {
    for (e, edge) in edges.iter().enumerate() {
        for (k, &v) in edge.iter().enumerate() {
            if (v as usize) >= node_count {
                return Err(Error::IndexOutOfRange {
                    arg: "edges",
                    position: 2 * e + k,
                    index: v as usize,
                    bound: node_count,
                });
            }
        }
        if edge[0] == edge[1] {
            return Err(Error::SelfLoop {
                node: edge[0] as usize,
            });
        }
    }
    if offsets_len != node_count + 1 {
        return Err(Error::LengthMismatch {
            arg: "offsets",
            expected: node_count + 1,
            actual: offsets_len,
        });
    }
    let needed = 2 * edges.len();
    if targets_len < needed {
        return Err(Error::BufferTooSmall {
            arg: "targets",
            needed,
            actual: targets_len,
        });
    }
    let mut adj = vec![BTreeSet::new(); node_count];
    for &[a, b] in edges {
        adj[a as usize].insert(b);
        adj[b as usize].insert(a);
    }
    Ok(to_csr(&adj))
}

/// Reference size query for cells: twice the number of (edge + diagonal) occurrences.
pub fn graph_from_cells_len_ref(kinds: &[u8], face_diagonals: bool) -> usize {
    kinds
        .iter()
        .map(|&k| {
            let d = if face_diagonals {
                ref_diagonals(k).len()
            } else {
                0
            };
            2 * (ref_edges(k).len() + d)
        })
        .sum()
}

/// Reference validation of a mixed cell list, checking in the order the kernel documents:
/// sizes, the `offsets` length, `offsets[0]`, then cell by cell (offsets step, kind, node
/// count, then each node: range, then repetition of an earlier node of the cell), then the
/// last offset.
pub fn validate_cells_ref(
    node_count: usize,
    offsets: &[u32],
    nodes: &[u32],
    kinds: &[u8],
) -> Result<(), Error> {
    if offsets.len() != kinds.len() + 1 {
        return Err(Error::LengthMismatch {
            arg: "offsets",
            expected: kinds.len() + 1,
            actual: offsets.len(),
        });
    }
    if offsets[0] != 0 {
        return Err(Error::BadOffsets {
            arg: "offsets",
            position: 0,
        });
    }
    for c in 0..kinds.len() {
        let (a, b) = (offsets[c] as usize, offsets[c + 1] as usize);
        if b < a || b > nodes.len() {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: c + 1,
            });
        }
        let Some(expected) = node_count_of(kinds[c]) else {
            return Err(Error::UnknownCellKind {
                cell: c,
                kind: kinds[c],
            });
        };
        if b - a != expected {
            return Err(Error::WrongNodeCount {
                cell: c,
                kind: kinds[c],
                expected,
                actual: b - a,
            });
        }
        let mut seen = BTreeSet::new();
        for (p, &v) in nodes.iter().enumerate().take(b).skip(a) {
            if v as usize >= node_count {
                return Err(Error::IndexOutOfRange {
                    arg: "nodes",
                    position: p,
                    index: v as usize,
                    bound: node_count,
                });
            }
            if !seen.insert(v) {
                return Err(Error::RepeatedNode {
                    cell: c,
                    node: v as usize,
                });
            }
        }
    }
    if *offsets.last().unwrap() as usize != nodes.len() {
        return Err(Error::BadOffsets {
            arg: "offsets",
            position: kinds.len(),
        });
    }
    Ok(())
}

/// The reference `graph_from_cells` for a cell list already known to be valid: two nodes are
/// neighbours when they share a face side (or a four-node face diagonal when
/// `face_diagonals`).
pub fn graph_from_cells_ref(
    node_count: usize,
    offsets: &[u32],
    nodes: &[u32],
    kinds: &[u8],
    face_diagonals: bool,
) -> RefGraph {
    let mut adj = vec![BTreeSet::new(); node_count];
    for c in 0..kinds.len() {
        let cell = &nodes[offsets[c] as usize..offsets[c + 1] as usize];
        let mut pairs = ref_edges(kinds[c]);
        if face_diagonals {
            pairs.extend(ref_diagonals(kinds[c]));
        }
        for (la, lb) in pairs {
            let (a, b) = (cell[la as usize], cell[lb as usize]);
            adj[a as usize].insert(b);
            adj[b as usize].insert(a);
        }
    }
    to_csr(&adj)
}

/// Reference validation of a CSR graph, in the order the kernel documents: `offsets` must be
/// non-empty and start at 0; every step must not decrease nor pass `targets.len()`; the last
/// offset must equal `targets.len()`; then, row by row, every target must be `< n` and differ
/// from its row.
pub fn validate_graph_ref(offsets: &[u32], targets: &[u32]) -> Result<(), Error> {
    if offsets.is_empty() || offsets[0] != 0 {
        return Err(Error::BadOffsets {
            arg: "offsets",
            position: 0,
        });
    }
    let n = offsets.len() - 1;
    for i in 1..offsets.len() {
        if offsets[i] < offsets[i - 1] || offsets[i] as usize > targets.len() {
            return Err(Error::BadOffsets {
                arg: "offsets",
                position: i,
            });
        }
    }
    if offsets[n] as usize != targets.len() {
        return Err(Error::BadOffsets {
            arg: "offsets",
            position: n,
        });
    }
    for row in 0..n {
        let (a, b) = (offsets[row] as usize, offsets[row + 1] as usize);
        for (p, &t) in targets.iter().enumerate().take(b).skip(a) {
            let t = t as usize;
            if t >= n {
                return Err(Error::IndexOutOfRange {
                    arg: "targets",
                    position: p,
                    index: t,
                    bound: n,
                });
            }
            if t == row {
                return Err(Error::SelfLoop { node: row });
            }
        }
    }
    Ok(())
}

/// The first edge `i → j` (rows in order, targets in order) without its reverse, if any.
pub fn first_unmatched_edge(offsets: &[u32], targets: &[u32]) -> Option<(usize, usize)> {
    let n = offsets.len() - 1;
    let rows: Vec<BTreeSet<u32>> = (0..n)
        .map(|i| {
            targets[offsets[i] as usize..offsets[i + 1] as usize]
                .iter()
                .copied()
                .collect()
        })
        .collect();
    for (i, row) in (0..n).map(|i| (i, &targets[offsets[i] as usize..offsets[i + 1] as usize])) {
        for &j in row {
            if !rows[j as usize].contains(&(i as u32)) {
                return Some((i, j as usize));
            }
        }
    }
    None
}
