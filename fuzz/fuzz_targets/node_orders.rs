//! Node orders (`deform_kernel::order`) on arbitrary input never panic: RCM on any valid graph
//! and the Hilbert order of any points (NaN and infinities included) return permutations or a
//! typed error with the buffers untouched; `Permutation::new` on arbitrary arrays accepts
//! exactly the pairs a naive check accepts; applying a permutation and its inverse to points,
//! node lists and the graph (with per-edge data) gives back every bit.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, renumber, Permutation,
};
use deform_kernel::{graph_from_edges, Graph};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    node_count: u8,
    edges: Vec<[u8; 2]>,
    coords: Vec<u64>,
    three_d: bool,
    order: Vec<u8>,
    inverse: Vec<u8>,
    indices: Vec<u8>,
}

/// The naive check: `order` a permutation of `0..n`, `inverse` its inverse.
fn is_permutation(order: &[u32], inverse: &[u32]) -> bool {
    let n = order.len();
    let mut seen = vec![false; n];
    inverse.len() == n
        && order.iter().enumerate().all(|(k, &o)| {
            (o as usize) < n
                && !std::mem::replace(&mut seen[o as usize], true)
                && inverse[o as usize] as usize == k
        })
}

/// Every bit of a permutation's round trip on the graph, points and node lists.
fn round_trips(p: Permutation<'_>, g: &Graph<'_>, points: &[[f64; 2]], indices: &[u32]) {
    let n = p.len();
    let e = g.edge_count();
    let (mut o, mut t, mut m) = (vec![0; n + 1], vec![0; e], vec![0; e]);
    permute_graph(p, g, &mut o, &mut t, Some(&mut m)).unwrap();
    let h = Graph::new(&o, &t).unwrap();
    h.check_symmetric().unwrap();
    let (mut o2, mut t2, mut m2) = (vec![0; n + 1], vec![0; e], vec![0; e]);
    permute_graph(p.inverted(), &h, &mut o2, &mut t2, Some(&mut m2)).unwrap();
    assert_eq!((o2.as_slice(), t2.as_slice()), (g.offsets(), g.targets()));
    let data: Vec<u32> = (0..e as u32).collect();
    let (mut d1, mut d2) = (vec![0; e], vec![0; e]);
    gather(&m, &data, &mut d1).unwrap();
    gather(&m2, &d1, &mut d2).unwrap();
    assert_eq!(d2, data);
    if points.len() == n {
        let (mut a, mut b) = (vec![[0.0; 2]; n], vec![[0.0; 2]; n]);
        permute(p, points, &mut a).unwrap();
        permute(p.inverted(), &a, &mut b).unwrap();
        let bits = |v: &[[f64; 2]]| v.iter().map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&b), bits(points));
    }
    let mut idx = indices.to_vec();
    if renumber(p, &mut idx).is_ok() {
        renumber(p.inverted(), &mut idx).unwrap();
        assert_eq!(idx, indices);
    } else {
        assert_eq!(idx, indices, "an Err changed the indices");
    }
    let d = index_distance(g, Some(p)).unwrap();
    assert!(d.edges == e as u64 && (d.max as usize) < n.max(1));
}

fuzz_target!(|inp: Input| {
    let n = inp.node_count as usize;
    let edges: Vec<[u32; 2]> = inp
        .edges
        .iter()
        .map(|e| [u32::from(e[0]), u32::from(e[1])])
        .filter(|e| e[0] != e[1] && (e[0] as usize) < n && (e[1] as usize) < n)
        .collect();
    let mut offsets = vec![0; n + 1];
    let mut targets = vec![0; 2 * edges.len()];
    let used = graph_from_edges(n, &edges, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let indices: Vec<u32> = inp.indices.iter().map(|&v| u32::from(v)).collect();
    let pts: Vec<[f64; 2]> = inp
        .coords
        .chunks_exact(2)
        .map(|c| [f64::from_bits(c[0]), f64::from_bits(c[1])])
        .collect();

    let (mut order, mut inverse) = (vec![u32::MAX; n], vec![u32::MAX; n]);
    rcm_order(&g, &mut order, &mut inverse).unwrap();
    let p = Permutation::new(&order, &inverse).unwrap();
    round_trips(p, &g, &pts, &indices);

    // Hilbert: any points, 2D or 3D; on error nothing written.
    let flat: Vec<f64> = pts.iter().flatten().copied().collect();
    let (mut ho, mut hi, mut keys) = (vec![7u32; n], vec![7u32; n], vec![7u64; n]);
    let r = if inp.three_d {
        let p3: Vec<[f64; 3]> = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        hilbert_order(&p3, &mut ho, &mut hi, &mut keys)
    } else {
        hilbert_order(&pts, &mut ho, &mut hi, &mut keys)
    };
    match r {
        Ok(()) => {
            let hp = Permutation::new(&ho, &hi).expect("hilbert returns a permutation");
            round_trips(hp, &g, &pts, &indices);
        }
        Err(_) => assert!(ho.iter().chain(&hi).all(|&x| x == 7) && keys.iter().all(|&k| k == 7)),
    }

    // Arbitrary arrays: accepted exactly when they are a permutation and its inverse.
    let o: Vec<u32> = inp.order.iter().map(|&v| u32::from(v)).collect();
    let i: Vec<u32> = inp.inverse.iter().map(|&v| u32::from(v)).collect();
    assert_eq!(Permutation::new(&o, &i).is_ok(), is_permutation(&o, &i));
});
