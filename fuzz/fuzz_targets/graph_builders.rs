//! Target 2: graph and cell builders on arbitrary input never panic, give typed errors, leave
//! the buffers untouched on error, and when they succeed equal the naive std reference
//! (`host-tests/src/graph_ref.rs`) bit for bit.
#![no_main]

use arbitrary::Arbitrary;
use deform_host_tests::graph_ref;
use deform_kernel::{graph_from_cells, graph_from_cells_len, graph_from_edges, Cells, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<[u8; 2]>,
    offsets_slack: i8,
    targets_slack: i8,
    cell_kinds: Vec<u8>,
    cell_nodes: Vec<u8>,
    diagonals: bool,
}

fuzz_target!(|inp: Input| {
    let n = inp.node_count as usize;
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|e| [e[0] as u32, e[1] as u32])
        .collect();
    let offsets_len = (n as isize + 1 + (inp.offsets_slack as isize).signum()).max(0) as usize;
    let targets_len = (2 * edges.len() as isize + inp.targets_slack as isize).max(0) as usize;
    let mut offsets = vec![0xdead_beef_u32; offsets_len];
    let mut targets = vec![0xdead_beef_u32; targets_len];
    let got = graph_from_edges(n, &edges, &mut offsets, &mut targets);
    let want = graph_ref::graph_from_edges_ref(n, &edges, offsets_len, targets_len);
    match (got, want) {
        (Ok(used), Ok(r)) => {
            assert_eq!(offsets, r.offsets);
            assert_eq!(&targets[..used], &r.targets[..]);
            let g = Graph::new(&offsets, &targets[..used]).unwrap();
            g.check_symmetric().unwrap();
        }
        (Err(e), Err(r)) => {
            assert_eq!(e, r);
            assert!(offsets.iter().chain(&targets).all(|&x| x == 0xdead_beef));
        }
        (g, w) => panic!("kernel {g:?} vs reference {w:?}"),
    }

    // Cells: arbitrary kinds and nodes, offsets from the kinds' nominal sizes.
    let mut cell_offsets = vec![0u32];
    let mut at = 0u32;
    for &k in &inp.cell_kinds {
        at += graph_ref::node_count_of(k).unwrap_or((k % 9) as usize) as u32;
        cell_offsets.push(at);
    }
    let nodes: Vec<u32> = inp.cell_nodes.iter().map(|&v| v as u32).collect();
    let cells = Cells::new(n, &cell_offsets, &nodes, &inp.cell_kinds);
    let want = graph_ref::validate_cells_ref(n, &cell_offsets, &nodes, &inp.cell_kinds);
    match (cells, want) {
        (Ok(c), Ok(())) => {
            let len = graph_from_cells_len(&c, inp.diagonals);
            assert_eq!(
                len,
                graph_ref::graph_from_cells_len_ref(&inp.cell_kinds, inp.diagonals)
            );
            let mut o = vec![0u32; n + 1];
            let mut t = vec![0u32; len];
            let used = graph_from_cells(&c, inp.diagonals, &mut o, &mut t).unwrap();
            let r = graph_ref::graph_from_cells_ref(
                n,
                &cell_offsets,
                &nodes,
                &inp.cell_kinds,
                inp.diagonals,
            );
            assert_eq!(o, r.offsets);
            assert_eq!(&t[..used], &r.targets[..]);
        }
        (Err(e), Err(r)) => assert_eq!(e, r),
        (c, w) => panic!("kernel {:?} vs reference {w:?}", c.map(|_| ())),
    }
});
