//! Golden cases for the graph builders: the hash covers the used length, the offsets and the
//! used targets, and the error codes of a few invalid calls.

use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, CellKind,
    Cells, Graph,
};

use crate::{Fnv, XorShift};

/// Nodes of the random edge list.
const EDGE_NODES: usize = 24;
/// Edges of the random edge list (duplicates and both orientations occur).
const EDGE_COUNT: usize = 80;

/// [`graph_from_edges`] on a random edge list with duplicates and reversed repeats.
pub fn from_edges() -> u64 {
    let mut rng = XorShift::new(0x6EA9_0001);
    let mut edges = [[0u32; 2]; EDGE_COUNT];
    let n = EDGE_NODES as u32;
    for (k, e) in edges.iter_mut().enumerate() {
        let a = rng.below(n);
        let b = (a + 1 + rng.below(n - 1)) % n;
        *e = if k % 7 == 3 { [b, a] } else { [a, b] };
    }
    // Exact duplicates and reversed duplicates of earlier edges.
    for k in (10..EDGE_COUNT).step_by(9) {
        let src = rng.below(k as u32) as usize;
        if let Some(&[a, b]) = edges.get(src) {
            if let Some(e) = edges.get_mut(k) {
                *e = if k % 2 == 0 { [b, a] } else { [a, b] };
            }
        }
    }
    let mut h = Fnv::new();
    let mut offsets = [0u32; EDGE_NODES + 1];
    let mut targets = [0u32; 2 * EDGE_COUNT];
    h.usize(graph_from_edges_len(&edges));
    hash_build(
        &mut h,
        graph_from_edges(EDGE_NODES, &edges, &mut offsets, &mut targets),
        &offsets,
        &targets,
    );
    // Isolated nodes at the end: the last rows are empty.
    let mut offsets_big = [0u32; EDGE_NODES + 5];
    hash_build(
        &mut h,
        graph_from_edges(EDGE_NODES + 4, &edges, &mut offsets_big, &mut targets),
        &offsets_big,
        &targets,
    );
    // Error outcomes: out of range, self loop, short targets, wrong offsets length.
    let mut small = [0u32; 3];
    for r in [
        graph_from_edges(3, &[[0, 3]], &mut offsets[..4], &mut targets),
        graph_from_edges(3, &[[1, 1]], &mut offsets[..4], &mut targets),
        graph_from_edges(3, &[[0, 1], [1, 2]], &mut offsets[..4], &mut small),
        graph_from_edges(3, &[[0, 1]], &mut offsets[..3], &mut targets),
    ] {
        match r {
            Ok(u) => h.usize(u),
            Err(e) => h.error(&e),
        }
    }
    h.finish()
}

/// Nodes of the random mixed mesh.
const CELL_NODES: usize = 40;
/// Cells of the random mixed mesh.
const CELL_COUNT: usize = 30;
/// Largest node count of a cell kind (hexahedron).
const MAX_CELL_NODES: usize = 8;
/// Largest (edges + face diagonals) count of a kind (hexahedron: 12 + 12).
const MAX_CELL_PAIRS: usize = 24;

/// A random mixed mesh of every kind with distinct nodes per cell.
fn mixed_mesh(
    offsets: &mut [u32; CELL_COUNT + 1],
    nodes: &mut [u32; CELL_COUNT * MAX_CELL_NODES],
    kinds: &mut [u8; CELL_COUNT],
) -> usize {
    let mut rng = XorShift::new(0x6EA9_0002);
    let mut used = 0usize;
    if let Some(o) = offsets.first_mut() {
        *o = 0;
    }
    for (c, kind_slot) in kinds.iter_mut().enumerate() {
        // Every kind appears (cycle through them first), then random kinds.
        let pick = if c < CellKind::ALL.len() {
            c
        } else {
            rng.below(CellKind::ALL.len() as u32) as usize
        };
        let kind = CellKind::ALL.get(pick).copied().unwrap_or(CellKind::Line);
        *kind_slot = kind.vtk_code();
        // Partial Fisher–Yates over the node pool.
        let mut pool = [0u32; CELL_NODES];
        for (i, p) in pool.iter_mut().enumerate() {
            *p = i as u32;
        }
        for i in 0..kind.node_count() {
            let j = i + rng.below((CELL_NODES - i) as u32) as usize;
            if i < CELL_NODES && j < CELL_NODES {
                pool.swap(i, j);
            }
            if let (Some(slot), Some(&v)) = (nodes.get_mut(used), pool.get(i)) {
                *slot = v;
            }
            used += 1;
        }
        if let Some(o) = offsets.get_mut(c + 1) {
            *o = used as u32;
        }
    }
    used
}

/// Builds the graph of the random mixed mesh, with or without face diagonals, and hashes it.
fn cells_case(face_diagonals: bool) -> u64 {
    let mut offsets = [0u32; CELL_COUNT + 1];
    let mut nodes = [0u32; CELL_COUNT * MAX_CELL_NODES];
    let mut kinds = [0u8; CELL_COUNT];
    let used = mixed_mesh(&mut offsets, &mut nodes, &mut kinds);
    let mut h = Fnv::new();
    let node_slice = nodes.get(..used).unwrap_or(&[]);
    h.u32s(&offsets);
    h.u32s(node_slice);
    match Cells::new(CELL_NODES, &offsets, node_slice, &kinds) {
        Ok(cells) => {
            let mut g_offsets = [0u32; CELL_NODES + 1];
            let mut targets = [0u32; 2 * CELL_COUNT * MAX_CELL_PAIRS];
            h.usize(graph_from_cells_len(&cells, face_diagonals));
            hash_build(
                &mut h,
                graph_from_cells(&cells, face_diagonals, &mut g_offsets, &mut targets),
                &g_offsets,
                &targets,
            );
        }
        Err(e) => h.error(&e),
    }
    h.finish()
}

/// [`graph_from_cells`] without face diagonals on a random mixed mesh.
pub fn from_cells() -> u64 {
    cells_case(false)
}

/// [`graph_from_cells`] with quadrilateral-face diagonals on the same mesh.
pub fn from_cells_diagonals() -> u64 {
    cells_case(true)
}

/// Hashes a builder result and, on success, the graph (also checked by [`Graph::new`]).
fn hash_build(h: &mut Fnv, r: deform_kernel::Result<usize>, offsets: &[u32], targets: &[u32]) {
    match r {
        Ok(used) => {
            h.usize(used);
            let t = targets.get(..used).unwrap_or(&[]);
            h.u32s(offsets);
            h.u32s(t);
            match Graph::new(offsets, t).and_then(|g| g.check_symmetric()) {
                Ok(()) => h.byte(1),
                Err(e) => h.error(&e),
            }
        }
        Err(e) => h.error(&e),
    }
}
