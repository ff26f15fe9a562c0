//! `Cells::new` validation and the `Cells`/`CellKind` accessors, against the naive reference
//! validator in `deform_host_tests::graph_ref` (same documented check order, so the first
//! error must be identical).

use deform_host_tests::graph_ref::{node_count_of, validate_cells_ref};
use deform_kernel::{CellKind, Cells, Error};
use proptest::prelude::*;

/// Every VTK code: `from_vtk` knows exactly the seven supported kinds, with the reference's
/// node counts, and round-trips through `vtk_code`.
#[test]
fn kinds_match_vtk_codes() {
    for code in 0..=255u8 {
        match (CellKind::from_vtk(code), node_count_of(code)) {
            (Some(kind), Some(n)) => {
                assert_eq!(kind.vtk_code(), code);
                assert_eq!(kind.node_count(), n);
                let dim = match code {
                    3 => 1,
                    5 | 9 => 2,
                    _ => 3,
                };
                assert_eq!(kind.dimension(), dim);
            }
            (None, None) => {}
            (k, n) => panic!("code {code}: kernel {k:?}, reference {n:?}"),
        }
    }
    let codes: Vec<u8> = CellKind::ALL.iter().map(|k| k.vtk_code()).collect();
    assert_eq!(codes, vec![3, 5, 9, 10, 12, 13, 14]);
}

/// A random valid mixed mesh.
fn mixed_mesh() -> impl Strategy<Value = (usize, Vec<u32>, Vec<u32>, Vec<u8>)> {
    (8usize..20).prop_flat_map(|n| {
        let cell = (
            0usize..7,
            Just((0..n as u32).collect::<Vec<u32>>()).prop_shuffle(),
        );
        (Just(n), prop::collection::vec(cell, 0..12)).prop_map(|(n, cells)| {
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

/// One defect injected into a valid mesh.
#[derive(Clone, Debug)]
enum Defect {
    None,
    KindCode(prop::sample::Index, u8),
    NodeValue(prop::sample::Index, u32),
    OffsetValue(prop::sample::Index, u32),
    DropOffset,
    ExtraOffset(u32),
    DropNode,
    ExtraNode(u32),
}

fn defect() -> impl Strategy<Value = Defect> {
    prop_oneof![
        Just(Defect::None),
        (any::<prop::sample::Index>(), any::<u8>()).prop_map(|(i, c)| Defect::KindCode(i, c)),
        (any::<prop::sample::Index>(), 0u32..24).prop_map(|(i, v)| Defect::NodeValue(i, v)),
        (any::<prop::sample::Index>(), 0u32..60).prop_map(|(i, v)| Defect::OffsetValue(i, v)),
        Just(Defect::DropOffset),
        (0u32..60).prop_map(Defect::ExtraOffset),
        Just(Defect::DropNode),
        (0u32..24).prop_map(Defect::ExtraNode),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    /// Valid meshes are accepted and read back unchanged; meshes with one injected defect
    /// (unknown or different kind code, out-of-range or repeated node, bad offset, wrong
    /// offsets length, wrong nodes length) get exactly the reference's first error.
    #[test]
    fn validation_matches_reference((n, mut offsets, mut nodes, mut kinds) in mixed_mesh(), d in defect()) {
        match d {
            Defect::None => {}
            Defect::KindCode(i, c) => if !kinds.is_empty() { let k = i.index(kinds.len()); kinds[k] = c },
            Defect::NodeValue(i, v) => if !nodes.is_empty() { let k = i.index(nodes.len()); nodes[k] = v },
            Defect::OffsetValue(i, v) => { let k = i.index(offsets.len()); offsets[k] = v },
            Defect::DropOffset => { offsets.pop(); }
            Defect::ExtraOffset(v) => offsets.push(v),
            Defect::DropNode => { nodes.pop(); }
            Defect::ExtraNode(v) => nodes.push(v),
        }
        let got = Cells::new(n, &offsets, &nodes, &kinds);
        let want = validate_cells_ref(n, &offsets, &nodes, &kinds);
        match (got, want) {
            (Ok(cells), Ok(())) => {
                prop_assert_eq!(cells.node_count(), n);
                prop_assert_eq!(cells.len(), kinds.len());
                prop_assert_eq!(cells.is_empty(), kinds.is_empty());
                prop_assert_eq!(cells.offsets(), &offsets[..]);
                prop_assert_eq!(cells.nodes(), &nodes[..]);
                prop_assert_eq!(cells.kinds(), &kinds[..]);
                let listed: Vec<_> = cells.iter().collect();
                prop_assert_eq!(listed.len(), kinds.len());
                for (c, (kind, cell_nodes)) in listed.into_iter().enumerate() {
                    let want_nodes = &nodes[offsets[c] as usize..offsets[c + 1] as usize];
                    prop_assert_eq!(kind.vtk_code(), kinds[c]);
                    prop_assert_eq!(cell_nodes, want_nodes);
                    prop_assert_eq!(cells.cell(c), Some((kind, want_nodes)));
                }
                prop_assert_eq!(cells.cell(kinds.len()), None);
            }
            (Err(e), Err(w)) => prop_assert_eq!(e, w),
            (got, want) => prop_assert!(false, "kernel {:?}, reference {:?}", got.map(|_| ()), want),
        }
    }

    /// Arbitrary small arrays (almost always invalid): the same first error as the reference.
    #[test]
    fn arbitrary_arrays_match_reference(
        n in 0usize..10,
        offsets in prop::collection::vec(0u32..12, 0..5),
        nodes in prop::collection::vec(0u32..11, 0..12),
        kinds in prop::collection::vec(prop::sample::select(vec![0u8, 3, 5, 9, 10, 12, 13, 14, 255]), 0..4),
    ) {
        let got = Cells::new(n, &offsets, &nodes, &kinds).map(|_| ());
        prop_assert_eq!(got, validate_cells_ref(n, &offsets, &nodes, &kinds));
    }
}

#[test]
fn error_cases() {
    // A triangle and a quad over 5 nodes.
    let offsets = [0u32, 3, 7];
    let nodes = [0u32, 1, 2, 1, 2, 3, 4];
    let kinds = [5u8, 9];
    assert!(Cells::new(5, &offsets, &nodes, &kinds).is_ok());
    // Unknown kind.
    assert_eq!(
        Cells::new(5, &offsets, &nodes, &[5, 7]).map(|_| ()),
        Err(Error::UnknownCellKind { cell: 1, kind: 7 })
    );
    // Wrong node count: a quad code on three nodes.
    assert_eq!(
        Cells::new(5, &offsets, &nodes, &[9, 9]).map(|_| ()),
        Err(Error::WrongNodeCount {
            cell: 0,
            kind: 9,
            expected: 4,
            actual: 3
        })
    );
    // Out of range.
    assert_eq!(
        Cells::new(4, &offsets, &nodes, &kinds).map(|_| ()),
        Err(Error::IndexOutOfRange {
            arg: "nodes",
            position: 6,
            index: 4,
            bound: 4
        })
    );
    // Repeated node.
    assert_eq!(
        Cells::new(5, &offsets, &[0, 1, 0, 1, 2, 3, 4], &kinds).map(|_| ()),
        Err(Error::RepeatedNode { cell: 0, node: 0 })
    );
    // Bad offsets: not starting at 0, decreasing, past the end, not ending at nodes.len().
    let bad = |position| {
        Err(Error::BadOffsets {
            arg: "offsets",
            position,
        })
    };
    assert_eq!(
        Cells::new(5, &[1, 3, 7], &nodes, &kinds).map(|_| ()),
        bad(0)
    );
    assert_eq!(
        Cells::new(5, &[0, 3, 2], &nodes, &kinds).map(|_| ()),
        bad(2)
    );
    assert_eq!(
        Cells::new(5, &[0, 3, 8], &nodes, &kinds).map(|_| ()),
        bad(2)
    );
    assert_eq!(
        Cells::new(5, &offsets, &[0, 1, 2, 1, 2, 3, 4, 0], &kinds).map(|_| ()),
        bad(2)
    );
    // Offsets length.
    assert_eq!(
        Cells::new(5, &[0, 3], &nodes, &kinds).map(|_| ()),
        Err(Error::LengthMismatch {
            arg: "offsets",
            expected: 3,
            actual: 2
        })
    );
    // A node count beyond the u32 index type.
    let huge = u32::MAX as usize + 1;
    assert_eq!(
        Cells::new(huge, &[0], &[], &[]).map(|_| ()),
        Err(Error::TooLarge {
            arg: "node_count",
            value: huge
        })
    );
    // No cells at all is valid; an empty offsets array is not.
    assert!(Cells::new(0, &[0], &[], &[]).unwrap().is_empty());
    assert_eq!(
        Cells::new(0, &[], &[], &[]).map(|_| ()),
        Err(Error::LengthMismatch {
            arg: "offsets",
            expected: 1,
            actual: 0
        })
    );
}
