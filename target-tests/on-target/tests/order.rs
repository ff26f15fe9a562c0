//! Node orders on target, in f32 and f64: on the jittered 6 x 5 triangle mesh renumbered by a
//! fixed scramble, reverse Cuthill–McKee and the Hilbert order return permutations that bring
//! the band back to a grid row; points, fields, cell lists and the graph with per-edge data
//! permuted and put back keep every bit; the Hilbert order of integer grid points is the same
//! in f32 and f64; bad input gives typed errors with the buffers untouched.
#![no_std]
#![no_main]

use deform_on_target as _;

use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, renumber, Permutation,
};
use deform_kernel::{Error, Graph, Real};
use deform_on_target::mesh::{Mesh, N, NE, NT, NX};
use deform_on_target::same_bits;

/// A fixed scramble of the nodes (`i -> 7 i + 3 mod N`; 7 is prime to N = 30).
fn scramble() -> ([u32; N], [u32; N]) {
    let (mut order, mut inverse) = ([0u32; N], [0u32; N]);
    for (i, o) in order.iter_mut().enumerate() {
        *o = ((7 * i + 3) % N) as u32;
    }
    for (k, &o) in order.iter().enumerate() {
        inverse[o as usize] = k as u32;
    }
    (order, inverse)
}

fn orders_and_round_trips<T: Real>() {
    let m = Mesh::<T>::new(0.2);
    let g = m.graph();
    let (so, si) = scramble();
    let s = Permutation::new(&so, &si).unwrap();
    // The scrambled graph.
    let (mut off, mut tgt, mut map) = ([0u32; N + 1], [0u32; NE], [0u32; NE]);
    let e = g.edge_count();
    permute_graph(s, &g, &mut off, &mut tgt[..e], Some(&mut map[..e])).unwrap();
    let h = Graph::new(&off, &tgt[..e]).unwrap();
    let scrambled = index_distance(&h, None).unwrap().max;
    defmt::assert!(scrambled as usize > 2 * NX);
    // RCM brings the band back to about a grid row.
    let (mut order, mut inverse) = ([0u32; N], [0u32; N]);
    rcm_order(&h, &mut order, &mut inverse).unwrap();
    let p = Permutation::new(&order, &inverse).unwrap();
    defmt::assert!(index_distance(&h, Some(p)).unwrap().max as usize <= 2 * NX);
    // Hilbert on the scrambled points: a permutation with a smaller band than the scramble.
    let mut pts = [[T::ZERO; 2]; N];
    permute(s, &m.points, &mut pts).unwrap();
    let (mut ho, mut hi, mut keys) = ([0u32; N], [0u32; N], [0u64; N]);
    hilbert_order(&pts, &mut ho, &mut hi, &mut keys).unwrap();
    let hp = Permutation::new(&ho, &hi).unwrap();
    defmt::assert!(index_distance(&h, Some(hp)).unwrap().max < scrambled);
    // Round trips keep every bit: points, per-edge data, cell node lists, the graph.
    let mut back = [[T::ZERO; 2]; N];
    permute(s.inverted(), &pts, &mut back).unwrap();
    defmt::assert!(same_bits(&back, &m.points));
    let mut k = [[T::ZERO; 1]; NE];
    for (i, v) in k.iter_mut().enumerate() {
        *v = [T::ONE / T::from_usize(i + 3)];
    }
    let mut k2 = [[T::ZERO; 1]; NE];
    gather(&map[..e], &k[..e], &mut k2[..e]).unwrap();
    let (mut off2, mut tgt2, mut map2) = ([0u32; N + 1], [0u32; NE], [0u32; NE]);
    permute_graph(
        s.inverted(),
        &h,
        &mut off2,
        &mut tgt2[..e],
        Some(&mut map2[..e]),
    )
    .unwrap();
    defmt::assert!(off2 == m.graph_offsets && tgt2[..e] == m.targets[..e]);
    let mut k3 = [[T::ZERO; 1]; NE];
    gather(&map2[..e], &k2[..e], &mut k3[..e]).unwrap();
    defmt::assert!(same_bits(&k3[..e], &k[..e]));
    let mut nodes = m.nodes;
    renumber(s, &mut nodes).unwrap();
    renumber(s.inverted(), &mut nodes).unwrap();
    defmt::assert!(nodes == m.nodes && nodes.len() == 3 * NT);
}

/// Integer grid coordinates (exact in both precisions) give the same Hilbert order in f32 and
/// f64.
fn hilbert_same_in_both_precisions() {
    fn grid<T: Real>() -> [[T; 2]; N] {
        let mut p = [[T::ZERO; 2]; N];
        for (k, q) in p.iter_mut().enumerate() {
            *q = [T::from_usize(k % NX), T::from_usize(k / NX)];
        }
        p
    }
    let (p64, p32) = (grid::<f64>(), grid::<f32>());
    let (mut o64, mut i64_, mut k64) = ([0u32; N], [0u32; N], [0u64; N]);
    let (mut o32, mut i32_, mut k32) = ([0u32; N], [0u32; N], [0u64; N]);
    hilbert_order(&p64, &mut o64, &mut i64_, &mut k64).unwrap();
    hilbert_order(&p32, &mut o32, &mut i32_, &mut k32).unwrap();
    defmt::assert!(o64 == o32 && k64 == k32);
}

fn typed_errors<T: Real>() {
    let m = Mesh::<T>::new(0.2);
    let g = m.graph();
    let (mut o, mut i) = ([9u32; N], [9u32; N]);
    defmt::assert!(matches!(
        rcm_order(&g, &mut o[..N - 1], &mut i),
        Err(Error::LengthMismatch { arg: "order", .. })
    ));
    defmt::assert!(o == [9; N] && i == [9; N]);
    let mut pts = m.points;
    pts[3][1] = T::from_f64(f64::NAN);
    let mut keys = [7u64; N];
    defmt::assert!(matches!(
        hilbert_order(&pts, &mut o, &mut i, &mut keys),
        Err(Error::NonFinite {
            arg: "points",
            position: 3
        })
    ));
    defmt::assert!(o == [9; N] && keys == [7; N]);
    let bad = [0u32; N];
    defmt::assert!(matches!(
        Permutation::new(&bad, &bad),
        Err(Error::InvalidParameter { arg: "inverse", .. })
    ));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn orders_f64() {
        orders_and_round_trips::<f64>();
    }

    #[test]
    fn orders_f32() {
        orders_and_round_trips::<f32>();
    }

    #[test]
    fn hilbert_precisions() {
        hilbert_same_in_both_precisions();
    }

    #[test]
    fn errors() {
        typed_errors::<f64>();
        typed_errors::<f32>();
    }
}
