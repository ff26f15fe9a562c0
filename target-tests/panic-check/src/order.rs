//! Panic-check calls for node orders (`deform_kernel::order`): `Permutation::new` and its
//! accessors, `rcm_order`, `hilbert_order` (f32 and f64, `D` = 2 and 3), `index_distance`,
//! `permute` (scalars, points, bytes), `gather`, `renumber` and `permute_graph`, on an opaque
//! 6-node graph.

use core::hint::black_box;

use deform_kernel::order::{
    gather, hilbert_order, index_distance, permute, permute_graph, rcm_order, renumber, Permutation,
};
use deform_kernel::{Graph, Real};

const N: usize = 6;

#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// Calls every ordering entry point with opaque inputs.
pub fn exercise() {
    let offsets: [u32; N + 1] = bb([0, 1, 3, 5, 7, 9, 10]);
    let targets: [u32; 10] = bb([1, 0, 2, 1, 3, 2, 4, 3, 5, 4]);
    let (mut order, mut inverse) = ([0u32; N], [0u32; N]);
    if let Ok(g) = Graph::new(bb(&offsets), bb(&targets)) {
        keep(rcm_order(&g, bb(&mut order), bb(&mut inverse)));
        keep(index_distance(&g, None));
        if let Ok(p) = Permutation::new(bb(&order), bb(&inverse)) {
            keep(index_distance(&g, Some(p)));
            keep(p.is_identity());
            keep(p.inverted().len());
            let (mut o2, mut t2, mut map) = ([0u32; N + 1], [0u32; 10], [0u32; 10]);
            keep(permute_graph(
                p,
                &g,
                bb(&mut o2),
                bb(&mut t2),
                Some(bb(&mut map)),
            ));
            keep(permute_graph(p, &g, bb(&mut o2), bb(&mut t2), None));
            let mut idx = bb([5u32, 0, 3]);
            keep(renumber(p, &mut idx));
            let mut bytes = [0u8; N];
            keep(permute(p, bb(&[1u8; N]), bb(&mut bytes)));
            run::<f32>(p, &map);
            run::<f64>(p, &map);
        }
    }
}

#[inline(never)]
fn run<T: Real>(p: Permutation<'_>, map: &[u32]) {
    hilbert::<T, 2>();
    hilbert::<T, 3>();
    let src = bb([T::ONE; N]);
    let mut dst = [T::ZERO; N];
    keep(permute(p, &src, bb(&mut dst)));
    let pts = bb([[T::ONE; 3]; N]);
    let mut out = [[T::ZERO; 3]; N];
    keep(permute(p, &pts, bb(&mut out)));
    let edge = bb([T::ONE; 10]);
    let mut e2 = [T::ZERO; 10];
    keep(gather(bb(map), &edge, bb(&mut e2)));
}

#[inline(never)]
fn hilbert<T: Real, const D: usize>() {
    let pts = bb([[T::ONE; D]; N]);
    let (mut order, mut inverse, mut keys) = ([0u32; N], [0u32; N], [0u64; N]);
    keep(hilbert_order(
        &pts,
        bb(&mut order),
        bb(&mut inverse),
        bb(&mut keys),
    ));
}
