//! Graphs and permutations of the ordering tests: owned CSR graphs from meshes and edge
//! lists, random permutations (a Fisher–Yates shuffle on an LCG), and a mesh renumbered by
//! one of them (what a mesh generator's numbering looks like to a solver).

use deform_kernel::order::Permutation;
use deform_kernel::{graph_from_cells, graph_from_cells_len, graph_from_edges, Cells, Graph};

/// An owned CSR graph.
pub struct OwnedGraph {
    pub offsets: Vec<u32>,
    pub targets: Vec<u32>,
}

impl OwnedGraph {
    /// The symmetric graph of an undirected edge list.
    pub fn from_edges(n: usize, edges: &[[u32; 2]]) -> Self {
        let mut offsets = vec![0; n + 1];
        let mut targets = vec![0; 2 * edges.len()];
        let used = graph_from_edges(n, edges, &mut offsets, &mut targets).expect("edges");
        targets.truncate(used);
        OwnedGraph { offsets, targets }
    }

    /// The edge graph of mixed cells.
    pub fn from_cells(cells: &Cells<'_>) -> Self {
        let mut offsets = vec![0; cells.node_count() + 1];
        let mut targets = vec![0; graph_from_cells_len(cells, false)];
        let used = graph_from_cells(cells, false, &mut offsets, &mut targets).expect("cells");
        targets.truncate(used);
        OwnedGraph { offsets, targets }
    }

    /// The validated view.
    pub fn graph(&self) -> Graph<'_> {
        Graph::new(&self.offsets, &self.targets).expect("a valid graph")
    }
}

/// An owned permutation: `order[new] = old`, `inverse[old] = new`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OwnedPerm {
    pub order: Vec<u32>,
    pub inverse: Vec<u32>,
}

impl OwnedPerm {
    /// From `order`, inverted here (independently of the kernel).
    pub fn from_order(order: Vec<u32>) -> Self {
        let mut inverse = vec![u32::MAX; order.len()];
        for (k, &v) in order.iter().enumerate() {
            assert_eq!(inverse[v as usize], u32::MAX, "order repeats {v}");
            inverse[v as usize] = k as u32;
        }
        OwnedPerm { order, inverse }
    }

    /// A uniformly random permutation of `n` nodes (Fisher–Yates on an LCG).
    pub fn random(n: usize, seed: u64) -> Self {
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut s = seed;
        for i in (1..n).rev() {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let j = ((s >> 33) % (i as u64 + 1)) as usize;
            order.swap(i, j);
        }
        Self::from_order(order)
    }

    /// The kernel's checked view.
    pub fn view(&self) -> Permutation<'_> {
        Permutation::new(&self.order, &self.inverse).expect("a permutation")
    }
}

/// Largest `|new(i) − new(j)|` over an edge list (computed here, not by the kernel).
pub fn bandwidth(edges: &[[u32; 2]], inverse: &[u32]) -> u32 {
    edges
        .iter()
        .map(|&[a, b]| inverse[a as usize].abs_diff(inverse[b as usize]))
        .max()
        .unwrap_or(0)
}

/// The undirected edges of a graph (`i < j`).
pub fn edges_of(g: &Graph<'_>) -> Vec<[u32; 2]> {
    g.rows()
        .flat_map(|(i, _, row)| row.iter().map(move |&j| [i as u32, j]))
        .filter(|&[i, j]| i < j)
        .collect()
}

/// A mesh's points and cells renumbered by `p` (new point `k` is old point `p.order[k]`).
pub fn renumbered<const D: usize>(
    points: &[[f64; D]],
    nodes: &[u32],
    p: &OwnedPerm,
) -> (Vec<[f64; D]>, Vec<u32>) {
    let pts = p.order.iter().map(|&o| points[o as usize]).collect();
    let nodes = nodes.iter().map(|&v| p.inverse[v as usize]).collect();
    (pts, nodes)
}
