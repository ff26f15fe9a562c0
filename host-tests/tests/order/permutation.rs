//! Permutations of `kernel/src/order.rs`: applying one and its inverse gives back every bit
//! (points, fields, cell node lists, graphs with per-edge data); the Hilbert order is a true
//! Hilbert curve (consecutive cells of a 2^k grid are neighbours); bad input is a typed error
//! that leaves every buffer as it was.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, renumber, Permutation,
};
use deform_kernel::Error;
use deform_meshgen::{naca_triangulated, AirfoilGrid};
use support::order::{edges_of, OwnedGraph, OwnedPerm};

/// Points whose bits are awkward: signed zeros, subnormals, huge and tiny values.
fn odd_points(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            [
                if i % 2 == 0 { -0.0 } else { 0.0 },
                f64::from_bits(1 + i as u64) * (t + 1.0),
                (t * 0.1).sin() * 1e300,
            ]
        })
        .collect()
}

fn bits<const D: usize>(p: &[[f64; D]]) -> Vec<[u64; D]> {
    p.iter().map(|x| x.map(f64::to_bits)).collect()
}

#[test]
fn points_fields_and_indices_round_trip_bit_for_bit() {
    let n = 1000;
    for seed in [1, 2, 3] {
        let p = OwnedPerm::random(n, seed);
        let perm = p.view();
        let pts = odd_points(n);
        let mut moved = vec![[0.0; 3]; n];
        let mut back = vec![[1.0; 3]; n];
        permute(perm, &pts, &mut moved).unwrap();
        for (k, &o) in p.order.iter().enumerate() {
            assert_eq!(
                moved[k].map(f64::to_bits),
                pts[o as usize].map(f64::to_bits)
            );
        }
        permute(perm.inverted(), &moved, &mut back).unwrap();
        assert_eq!(bits(&back), bits(&pts));
        // f32 fields and byte masks too.
        let field: Vec<f32> = (0..n).map(|i| (i as f32).sqrt() - 3.0).collect();
        let (mut f1, mut f2) = (vec![0.0f32; n], vec![0.0f32; n]);
        permute(perm, &field, &mut f1).unwrap();
        permute(perm.inverted(), &f1, &mut f2).unwrap();
        assert_eq!(
            f2.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            field.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        let cells: Vec<u32> = (0..3 * n as u32).map(|i| (i * 7919) % n as u32).collect();
        let mut c = cells.clone();
        renumber(perm, &mut c).unwrap();
        for (a, b) in c.iter().zip(&cells) {
            assert_eq!(*a, p.inverse[*b as usize]);
        }
        renumber(perm.inverted(), &mut c).unwrap();
        assert_eq!(c, cells);
    }
}

#[test]
fn graphs_and_edge_data_round_trip_and_stay_canonical() {
    let mesh = naca_triangulated(&AirfoilGrid::default()).unwrap();
    let og = OwnedGraph::from_cells(&mesh.cells().unwrap());
    let g = og.graph();
    let stiffness: Vec<f64> = (0..g.edge_count())
        .map(|e| 1.0 / (e as f64 + 0.5))
        .collect();
    let p = OwnedPerm::random(g.node_count(), 7);
    let perm = p.view();
    let (mut off, mut tgt, mut map) = (
        vec![0; g.node_count() + 1],
        vec![0; g.edge_count()],
        vec![0; g.edge_count()],
    );
    permute_graph(perm, &g, &mut off, &mut tgt, Some(&mut map)).unwrap();
    let h = deform_kernel::Graph::new(&off, &tgt).unwrap();
    h.check_symmetric().unwrap();
    // The permuted graph has exactly the renumbered edges, rows sorted.
    let mut expect: Vec<[u32; 2]> = edges_of(&g)
        .iter()
        .map(|&[a, b]| {
            let (x, y) = (p.inverse[a as usize], p.inverse[b as usize]);
            [x.min(y), x.max(y)]
        })
        .collect();
    expect.sort_unstable();
    assert_eq!(edges_of(&h), expect);
    for (_, _, row) in h.rows() {
        assert!(row.windows(2).all(|w| w[0] < w[1]));
    }
    // Per-edge data follows its edge.
    let mut k2 = vec![0.0; g.edge_count()];
    gather(&map, &stiffness, &mut k2).unwrap();
    for (i, first, row) in h.rows() {
        for (e, &j) in row.iter().enumerate() {
            let (oi, oj) = (p.order[i] as usize, p.order[j as usize] as usize);
            let old_e = g.find_edge(oi, oj).unwrap();
            assert_eq!(k2[first + e].to_bits(), stiffness[old_e].to_bits());
        }
    }
    // And back: the original arrays, bit for bit.
    let (mut off2, mut tgt2, mut map2) =
        (vec![0; off.len()], vec![0; tgt.len()], vec![0; tgt.len()]);
    permute_graph(perm.inverted(), &h, &mut off2, &mut tgt2, Some(&mut map2)).unwrap();
    assert_eq!((off2, tgt2), (og.offsets.clone(), og.targets.clone()));
    let mut k3 = vec![0.0; g.edge_count()];
    gather(&map2, &k2, &mut k3).unwrap();
    assert_eq!(
        k3.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        stiffness.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
}

/// `[x, y]` (or `[x, y, z]`) of grid point `i` of a `side^D` grid, shuffled by `p`.
fn grid<const D: usize>(side: u32, p: &OwnedPerm) -> Vec<[f64; D]> {
    p.order
        .iter()
        .map(|&i| core::array::from_fn(|k| f64::from((i / side.pow(k as u32)) % side)))
        .collect()
}

fn check_hilbert_walk<const D: usize>(side: u32) {
    let n = side.pow(D as u32) as usize;
    let shuffle = OwnedPerm::random(n, 11);
    let pts = grid::<D>(side, &shuffle);
    let (mut order, mut inverse, mut keys) = (vec![0; n], vec![0; n], vec![0; n]);
    hilbert_order(&pts, &mut order, &mut inverse, &mut keys).unwrap();
    Permutation::new(&order, &inverse).unwrap();
    assert_eq!(
        pts[order[0] as usize], [0.0; D],
        "the curve starts at the corner"
    );
    for w in order.windows(2) {
        let (a, b) = (pts[w[0] as usize], pts[w[1] as usize]);
        let step: f64 = (0..D).map(|k| (a[k] - b[k]).abs()).sum();
        assert_eq!(
            step, 1.0,
            "consecutive Hilbert cells {a:?} {b:?} are neighbours"
        );
    }
    // f32 coordinates (exact small integers) give the same order.
    let p32: Vec<[f32; D]> = pts.iter().map(|p| p.map(|x| x as f32)).collect();
    let (mut o32, mut i32_, mut k32) = (vec![0; n], vec![0; n], vec![0; n]);
    hilbert_order(&p32, &mut o32, &mut i32_, &mut k32).unwrap();
    assert_eq!(o32, order);
}

#[test]
fn hilbert_order_walks_a_grid_one_neighbour_at_a_time() {
    check_hilbert_walk::<2>(16);
    check_hilbert_walk::<2>(64);
    check_hilbert_walk::<3>(8);
}

#[test]
fn hilbert_order_brings_neighbours_together_on_a_shuffled_mesh() {
    let mesh = naca_triangulated(&AirfoilGrid::default()).unwrap();
    let n = mesh.node_count();
    let shuffle = OwnedPerm::random(n, 5);
    let (pts, nodes) = support::order::renumbered(&mesh.points, &mesh.nodes, &shuffle);
    let cells = deform_kernel::Cells::new(n, &mesh.offsets, &nodes, &mesh.kinds).unwrap();
    let og = OwnedGraph::from_cells(&cells);
    let g = og.graph();
    let (mut order, mut inverse, mut keys) = (vec![0; n], vec![0; n], vec![0; n]);
    hilbert_order(&pts, &mut order, &mut inverse, &mut keys).unwrap();
    let before = index_distance(&g, None).unwrap();
    let after = index_distance(&g, Some(Permutation::new(&order, &inverse).unwrap())).unwrap();
    // A random numbering's mean distance is about n/3; the curve's a few dozen.
    assert!(before.sum / before.edges > n as u64 / 4, "{before:?}");
    assert!(after.sum / after.edges < 200, "{after:?}");
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let order = [2u32, 0, 1];
    let inverse = [1u32, 2, 0];
    assert!(Permutation::new(&order, &inverse).is_ok());
    assert!(matches!(
        Permutation::new(&order, &inverse[..2]),
        Err(Error::LengthMismatch { arg: "inverse", .. })
    ));
    assert!(matches!(
        Permutation::new(&[0, 3, 1], &inverse),
        Err(Error::IndexOutOfRange {
            arg: "order",
            position: 1,
            ..
        })
    ));
    assert!(matches!(
        Permutation::new(&[0, 0, 1], &[0, 2, 1]),
        Err(Error::InvalidParameter { arg: "inverse", .. })
    ));
    let perm = Permutation::new(&order, &inverse).unwrap();
    let mut dst = [7.0f64; 3];
    assert!(matches!(
        permute(perm, &[1.0, 2.0], &mut dst),
        Err(Error::LengthMismatch { arg: "src", .. })
    ));
    assert_eq!(dst, [7.0; 3]);
    let mut idx = [0u32, 1, 3];
    assert!(matches!(
        renumber(perm, &mut idx),
        Err(Error::IndexOutOfRange {
            arg: "indices",
            position: 2,
            ..
        })
    ));
    assert_eq!(idx, [0, 1, 3]);
    assert!(matches!(
        gather(&[0, 5], &[1.0, 2.0], &mut dst[..2]),
        Err(Error::IndexOutOfRange {
            arg: "map",
            position: 1,
            ..
        })
    ));
    assert_eq!(dst, [7.0; 3]);
    // Orderings: wrong lengths and non-finite points write nothing.
    let og = OwnedGraph::from_edges(3, &[[0, 1], [1, 2]]);
    let g = og.graph();
    let (mut o, mut i) = ([9u32; 3], [9u32; 2]);
    assert!(matches!(
        rcm_order(&g, &mut o, &mut i),
        Err(Error::LengthMismatch { arg: "inverse", .. })
    ));
    assert_eq!((o, i), ([9; 3], [9; 2]));
    let pts = [[0.0, 0.0], [1.0, f64::NAN], [2.0, 0.0]];
    let (mut o, mut i, mut k) = ([9u32; 3], [9u32; 3], [9u64; 3]);
    assert!(matches!(
        hilbert_order(&pts, &mut o, &mut i, &mut k),
        Err(Error::NonFinite {
            arg: "points",
            position: 1
        })
    ));
    let ok = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]];
    assert!(matches!(
        hilbert_order(&ok, &mut o, &mut i, &mut k[..2]),
        Err(Error::BufferTooSmall {
            arg: "keys",
            needed: 3,
            ..
        })
    ));
    assert_eq!((o, i, k), ([9; 3], [9; 3], [9; 3]));
    let (mut off, mut tgt) = ([9u32; 4], [9u32; 3]);
    assert!(matches!(
        permute_graph(perm, &g, &mut off, &mut tgt, None),
        Err(Error::LengthMismatch { arg: "targets", .. })
    ));
    assert_eq!((off, tgt), ([9; 4], [9; 3]));
    assert!(matches!(
        index_distance(&g, Some(Permutation::new(&[0, 1], &[0, 1]).unwrap())),
        Err(Error::LengthMismatch { arg: "perm", .. })
    ));
}

#[test]
fn empty_and_single_node_inputs() {
    let og = OwnedGraph::from_edges(0, &[]);
    let (mut o, mut i) = ([0u32; 0], [0u32; 0]);
    rcm_order(&og.graph(), &mut o, &mut i).unwrap();
    let pts: [[f64; 3]; 1] = [[1.0, 2.0, 3.0]];
    let (mut o, mut i, mut k) = ([5u32], [5u32], [0u64]);
    hilbert_order(&pts, &mut o, &mut i, &mut k).unwrap();
    assert_eq!((o, i), ([0], [0]));
}
