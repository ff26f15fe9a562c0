//! Exact (bitwise) parity of the kernel's graph builders and `Graph::new` with the naive
//! reference in `deform_host_tests::graph_ref` (Vec + BTreeSet, per-kind edges derived from
//! VTK face lists), on random edge lists and random mixed-cell meshes, including duplicate
//! edges, both orientations, isolated nodes and every error case. On `Err` the output buffers
//! must be untouched.

use deform_host_tests::graph_ref::{
    faces_of, first_unmatched_edge, graph_from_cells_len_ref, graph_from_cells_ref,
    graph_from_edges_ref, ref_diagonals, ref_edges, validate_graph_ref, RefGraph,
};
use deform_kernel::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len, CellKind,
    Cells, Error, Graph,
};
use proptest::prelude::*;

/// Sentinel written into output buffers before a call, to detect writes on `Err`.
const SENTINEL: u32 = 0xDEAD_BEEF;

/// Runs the kernel's `graph_from_edges` on sentinel-filled buffers of the given sizes.
fn kernel_edges(
    n: usize,
    edges: &[[u32; 2]],
    offsets_len: usize,
    targets_len: usize,
) -> (Result<usize, Error>, Vec<u32>, Vec<u32>) {
    let mut offsets = vec![SENTINEL; offsets_len];
    let mut targets = vec![SENTINEL; targets_len];
    let r = graph_from_edges(n, edges, &mut offsets, &mut targets);
    (r, offsets, targets)
}

/// Checks a kernel result against the reference: same `Ok` bits or same error, and untouched
/// buffers on error. Returns a description of the first difference.
fn compare(
    kernel: (Result<usize, Error>, Vec<u32>, Vec<u32>),
    reference: Result<RefGraph, Error>,
) -> Result<(), TestCaseError> {
    let (r, offsets, targets) = kernel;
    match (r, reference) {
        (Ok(used), Ok(g)) => {
            prop_assert_eq!(used, g.targets.len());
            prop_assert_eq!(&offsets, &g.offsets);
            prop_assert_eq!(&targets[..used], &g.targets[..]);
            let graph = Graph::new(&offsets, &targets[..used]);
            prop_assert!(graph.is_ok(), "builder output rejected: {:?}", graph);
            prop_assert_eq!(graph.unwrap().check_symmetric(), Ok(()));
        }
        (Err(e), Err(want)) => {
            prop_assert_eq!(e, want);
            prop_assert!(
                offsets.iter().all(|&o| o == SENTINEL),
                "offsets written on Err"
            );
            prop_assert!(
                targets.iter().all(|&t| t == SENTINEL),
                "targets written on Err"
            );
        }
        (got, want) => prop_assert!(false, "kernel {:?}, reference {:?}", got, want),
    }
    Ok(())
}

/// A node count and a valid edge list with duplicates and reversed repeats.
fn edge_list() -> impl Strategy<Value = (usize, Vec<[u32; 2]>)> {
    (2usize..40).prop_flat_map(|n| {
        let edge = (0..n as u32, 1..n as u32).prop_map(move |(a, d)| [a, (a + d) % n as u32]);
        (
            Just(n),
            prop::collection::vec(edge, 0..120),
            prop::collection::vec((any::<prop::sample::Index>(), any::<bool>()), 0..30),
        )
            .prop_map(|(n, mut edges, dups)| {
                if !edges.is_empty() {
                    for (i, rev) in dups {
                        let [a, b] = edges[i.index(edges.len())];
                        edges.push(if rev { [b, a] } else { [a, b] });
                    }
                }
                (n, edges)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// Valid edge lists: identical offsets and targets to the reference, for `targets`
    /// exactly `graph_from_edges_len` long or longer, and for extra isolated nodes.
    #[test]
    fn edges_match_reference((n, edges) in edge_list(), extra_nodes in 0usize..3, slack in 0usize..5) {
        let n = n + extra_nodes;
        let len = graph_from_edges_len(&edges);
        prop_assert_eq!(len, 2 * edges.len());
        compare(
            kernel_edges(n, &edges, n + 1, len + slack),
            graph_from_edges_ref(n, &edges, n + 1, len + slack),
        )?;
    }

    /// Arbitrary (mostly invalid) inputs: out-of-range endpoints, self loops, wrong offsets
    /// length, short targets. Same error as the reference and untouched buffers, or the same
    /// graph.
    #[test]
    fn edge_errors_match_reference(
        n in 0usize..12,
        edges in prop::collection::vec(prop::array::uniform2(0u32..14), 0..20),
        offsets_delta in -1i64..=1,
        targets_delta in -3i64..=1,
    ) {
        let offsets_len = (n as i64 + 1 + offsets_delta).max(0) as usize;
        let targets_len = (2 * edges.len() as i64 + targets_delta).max(0) as usize;
        compare(
            kernel_edges(n, &edges, offsets_len, targets_len),
            graph_from_edges_ref(n, &edges, offsets_len, targets_len),
        )?;
    }

    /// Edge order and orientation do not matter: a shuffled, partly reversed copy of the list
    /// gives the same bits.
    #[test]
    fn edges_are_canonical((n, edges) in edge_list(), seed in any::<u64>()) {
        let mut shuffled = edges.clone();
        let mut s = seed | 1;
        for i in (1..shuffled.len()).rev() {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            shuffled.swap(i, (s % (i as u64 + 1)) as usize);
            if s & 1 == 1 {
                shuffled[i].reverse();
            }
        }
        let a = kernel_edges(n, &edges, n + 1, 2 * edges.len());
        let b = kernel_edges(n, &shuffled, n + 1, 2 * edges.len());
        let used = a.0.unwrap();
        prop_assert_eq!(b.0.unwrap(), used);
        prop_assert_eq!(a.1, b.1);
        prop_assert_eq!(&a.2[..used], &b.2[..used]);
    }
}

#[test]
fn edges_special_cases() {
    // No nodes, no edges.
    let (r, o, _) = kernel_edges(0, &[], 1, 0);
    assert_eq!(r, Ok(0));
    assert_eq!(o, vec![0]);
    // Nodes without edges.
    let (r, o, _) = kernel_edges(3, &[], 4, 0);
    assert_eq!(r, Ok(0));
    assert_eq!(o, vec![0, 0, 0, 0]);
    // One edge repeated in both orientations collapses to one undirected edge.
    let (r, o, t) = kernel_edges(2, &[[0, 1], [1, 0], [0, 1]], 3, 6);
    assert_eq!(r, Ok(2));
    assert_eq!(o, vec![0, 1, 2]);
    assert_eq!(&t[..2], &[1, 0]);
    // A node count beyond the u32 index type is rejected before any buffer is looked at.
    let huge = u32::MAX as usize + 1;
    assert_eq!(
        kernel_edges(huge, &[], 1, 0).0,
        Err(Error::TooLarge {
            arg: "node_count",
            value: huge
        })
    );
    // Errors name the argument and position.
    assert_eq!(
        kernel_edges(3, &[[0, 1], [2, 3]], 4, 4).0,
        Err(Error::IndexOutOfRange {
            arg: "edges",
            position: 3,
            index: 3,
            bound: 3
        })
    );
    assert_eq!(
        kernel_edges(3, &[[2, 2]], 4, 2).0,
        Err(Error::SelfLoop { node: 2 })
    );
    assert_eq!(
        kernel_edges(3, &[[0, 1]], 3, 2).0,
        Err(Error::LengthMismatch {
            arg: "offsets",
            expected: 4,
            actual: 3
        })
    );
    assert_eq!(
        kernel_edges(3, &[[0, 1], [1, 2]], 4, 3).0,
        Err(Error::BufferTooSmall {
            arg: "targets",
            needed: 4,
            actual: 3
        })
    );
}

// ---------------------------------------------------------------------------------------------
// Cells

/// Per-kind tables: the kernel's edges and face diagonals are exactly the sets derived from
/// the VTK face lists, without repeats, and the node counts agree.
#[test]
fn kind_tables_match_vtk_faces() {
    for kind in CellKind::ALL {
        let code = kind.vtk_code();
        let norm = |p: &[u8; 2]| (p[0].min(p[1]), p[0].max(p[1]));
        let edges: Vec<(u8, u8)> = kind.edges().iter().map(norm).collect();
        let diags: Vec<(u8, u8)> = kind.face_diagonals().iter().map(norm).collect();
        let edge_set: std::collections::BTreeSet<_> = edges.iter().copied().collect();
        let diag_set: std::collections::BTreeSet<_> = diags.iter().copied().collect();
        assert_eq!(edge_set.len(), edges.len(), "{kind:?} repeats an edge");
        assert_eq!(diag_set.len(), diags.len(), "{kind:?} repeats a diagonal");
        assert_eq!(edge_set, ref_edges(code), "{kind:?} edges");
        assert_eq!(diag_set, ref_diagonals(code), "{kind:?} diagonals");
        assert!(edge_set.is_disjoint(&diag_set));
        let max_local = faces_of(code).iter().flatten().copied().max().unwrap();
        assert_eq!(
            max_local as usize + 1,
            kind.node_count(),
            "{kind:?} node count"
        );
        // Edges and diagonals only use local node numbers of the kind.
        assert!(edges
            .iter()
            .chain(&diags)
            .all(|&(a, b)| a != b && (b as usize) < kind.node_count()));
    }
}

/// A random mixed mesh: node count, offsets, nodes, kinds (distinct nodes per cell).
fn mixed_mesh() -> impl Strategy<Value = (usize, Vec<u32>, Vec<u32>, Vec<u8>)> {
    (8usize..30).prop_flat_map(|n| {
        let cell = (
            0usize..7,
            Just((0..n as u32).collect::<Vec<u32>>()).prop_shuffle(),
        );
        (Just(n), prop::collection::vec(cell, 0..25)).prop_map(|(n, cells)| {
            let mut offsets = vec![0u32];
            let mut nodes = Vec::new();
            let mut kinds = Vec::new();
            for (k, perm) in cells {
                let kind = CellKind::ALL[k];
                nodes.extend_from_slice(&perm[..kind.node_count()]);
                offsets.push(nodes.len() as u32);
                kinds.push(kind.vtk_code());
            }
            (n, offsets, nodes, kinds)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2048))]

    /// Random mixed meshes, with and without face diagonals: the size query and the graph are
    /// identical to the reference.
    #[test]
    fn cells_match_reference((n, offsets, nodes, kinds) in mixed_mesh(), diagonals in any::<bool>(), slack in 0usize..4) {
        let cells = Cells::new(n, &offsets, &nodes, &kinds).unwrap();
        let len = graph_from_cells_len(&cells, diagonals);
        prop_assert_eq!(len, graph_from_cells_len_ref(&kinds, diagonals));
        let mut g_offsets = vec![SENTINEL; n + 1];
        let mut targets = vec![SENTINEL; len + slack];
        let r = graph_from_cells(&cells, diagonals, &mut g_offsets, &mut targets);
        let want = graph_from_cells_ref(n, &offsets, &nodes, &kinds, diagonals);
        compare((r, g_offsets, targets), Ok(want))?;
    }

    /// Buffer errors for cells: wrong offsets length or short targets give the reference's
    /// error and leave both buffers untouched.
    #[test]
    fn cells_buffer_errors((n, offsets, nodes, kinds) in mixed_mesh(), diagonals in any::<bool>(), od in -1i64..=1, td in -3i64..=0) {
        let cells = Cells::new(n, &offsets, &nodes, &kinds).unwrap();
        let len = graph_from_cells_len(&cells, diagonals);
        let offsets_len = (n as i64 + 1 + od) as usize;
        let targets_len = (len as i64 + td).max(0) as usize;
        let mut g_offsets = vec![SENTINEL; offsets_len];
        let mut targets = vec![SENTINEL; targets_len];
        let r = graph_from_cells(&cells, diagonals, &mut g_offsets, &mut targets);
        let want = if offsets_len != n + 1 {
            Err(Error::LengthMismatch { arg: "offsets", expected: n + 1, actual: offsets_len })
        } else if targets_len < len {
            Err(Error::BufferTooSmall { arg: "targets", needed: len, actual: targets_len })
        } else {
            Ok(graph_from_cells_ref(n, &offsets, &nodes, &kinds, diagonals))
        };
        compare((r, g_offsets, targets), want)?;
    }
}

#[test]
fn hexahedron_graph_by_hand() {
    // One hexahedron: every node has 3 edge neighbours, and 3 more with face diagonals (one
    // per incident face); the space diagonal (0, 6) is never an edge.
    let offsets = [0u32, 8];
    let nodes = [0u32, 1, 2, 3, 4, 5, 6, 7];
    let kinds = [12u8];
    let cells = Cells::new(8, &offsets, &nodes, &kinds).unwrap();
    for (diagonals, degree) in [(false, 3usize), (true, 6)] {
        let mut o = [0u32; 9];
        let mut t = vec![0u32; graph_from_cells_len(&cells, diagonals)];
        let used = graph_from_cells(&cells, diagonals, &mut o, &mut t).unwrap();
        assert_eq!(used, 8 * degree);
        let g = Graph::new(&o, &t[..used]).unwrap();
        for i in 0..8 {
            assert_eq!(g.neighbors(i).len(), degree);
        }
        assert_eq!(g.find_edge(0, 6), None);
        assert!(g.find_edge(0, 1).is_some());
        assert_eq!(g.find_edge(0, 5).is_some(), diagonals);
    }
}

// ---------------------------------------------------------------------------------------------
// Graph::new

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// Arbitrary small offsets/targets arrays: `Graph::new` accepts exactly what the reference
    /// accepts and reports the same first error; `check_symmetric` reports the same first
    /// unmatched edge.
    #[test]
    fn graph_new_matches_reference(
        offsets in prop::collection::vec(0u32..8, 0..7),
        targets in prop::collection::vec(0u32..7, 0..8),
    ) {
        let got = Graph::new(&offsets, &targets);
        let want = validate_graph_ref(&offsets, &targets);
        match (got, want) {
            (Ok(g), Ok(())) => {
                prop_assert_eq!(g.node_count(), offsets.len() - 1);
                prop_assert_eq!(g.edge_count(), targets.len());
                let sym = g.check_symmetric();
                match first_unmatched_edge(&offsets, &targets) {
                    None => prop_assert_eq!(sym, Ok(())),
                    Some((from, to)) => prop_assert_eq!(sym, Err(Error::NotSymmetric { from, to })),
                }
                for i in 0..g.node_count() {
                    let row = &targets[offsets[i] as usize..offsets[i + 1] as usize];
                    prop_assert_eq!(g.neighbors(i), row);
                    for (k, &j) in row.iter().enumerate() {
                        // find_edge returns the first occurrence.
                        let first = row.iter().position(|&x| x == j).unwrap();
                        prop_assert!(first <= k);
                        prop_assert_eq!(g.find_edge(i, j as usize), Some(offsets[i] as usize + first));
                    }
                }
                prop_assert_eq!(g.neighbors(g.node_count()), &[] as &[u32]);
            }
            (Err(e), Err(w)) => prop_assert_eq!(e, w),
            (got, want) => prop_assert!(false, "kernel {:?}, reference {:?}", got.map(|_| ()), want),
        }
    }
}

#[test]
fn graph_new_error_cases() {
    let bad = |position| {
        Err(Error::BadOffsets {
            arg: "offsets",
            position,
        })
    };
    assert_eq!(Graph::new(&[], &[]).map(|_| ()), bad(0));
    assert_eq!(Graph::new(&[1, 1], &[0]).map(|_| ()), bad(0));
    assert_eq!(Graph::new(&[0, 2, 1], &[1, 0]).map(|_| ()), bad(2));
    assert_eq!(Graph::new(&[0, 3, 3], &[1, 0]).map(|_| ()), bad(1));
    assert_eq!(Graph::new(&[0, 1, 1], &[1, 0]).map(|_| ()), bad(2));
    assert_eq!(
        Graph::new(&[0, 1, 2], &[2, 0]).map(|_| ()),
        Err(Error::IndexOutOfRange {
            arg: "targets",
            position: 0,
            index: 2,
            bound: 2
        })
    );
    assert_eq!(
        Graph::new(&[0, 1, 2], &[1, 1]).map(|_| ()),
        Err(Error::SelfLoop { node: 1 })
    );
    let g = Graph::new(&[0, 1, 1], &[1]).unwrap();
    assert_eq!(
        g.check_symmetric(),
        Err(Error::NotSymmetric { from: 0, to: 1 })
    );
    // The empty graph is valid.
    let g = Graph::new(&[0], &[]).unwrap();
    assert_eq!((g.node_count(), g.edge_count()), (0, 0));
    assert_eq!(g.check_symmetric(), Ok(()));
}
