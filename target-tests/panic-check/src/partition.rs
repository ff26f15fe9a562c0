//! Panic-check calls for partitioned storage (`deform_kernel::partition` and
//! `deform_kernel::spring::PartitionedSprings`): the pattern, the partition's validation, the
//! local rows and the partitioned CG, the MIS-2 aggregation (serial and partitioned) and the
//! quaternion deformation on partitioned data (springs and IDW; rotations from the shape, rigid
//! and per node), for `f32` and `f64`, `D` = 2 and 3, through an exchange whose results the
//! optimiser cannot see.

use core::hint::black_box;

use deform_kernel::error::PartitionFault;
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::quaternion::{
    deform_idw_partitioned, deform_idw_partitioned_lens, deform_spring_partitioned,
    deform_spring_partitioned_lens, BoundaryElements, PartitionedIdwWorkspace, PartitionedMotion,
    PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::{
    aggregate_mis2, aggregate_mis2_partitioned, mis2_exchange_len, mis2_scratch_len,
    partitioned_cg_scratch_len, partitioned_targets_len, prolongator_partitioned,
    prolongator_partitioned_len, LocalCells, PartitionedSprings, Preconditioner, SolveOptions,
};
use deform_kernel::{Graph, Quat, Real};

/// Local nodes: two owned, two ghosts.
const N: usize = 4;

/// An opaque value of type `T`.
#[inline(always)]
fn bb<T>(x: T) -> T {
    black_box(x)
}

/// Keeps `x` alive.
#[inline(always)]
fn keep<T>(x: T) {
    black_box(x);
}

/// An exchange whose results the optimiser cannot see.
#[derive(Debug)]
struct Opaque;

impl<T: Real> Exchange<T> for Opaque {
    fn sum_words(&self, words: &mut [i64]) {
        bb(words);
    }
    fn max(&self, values: &mut [T]) {
        bb(values);
    }
    fn exchange(&self, halo: &Halo<'_>, field: &mut [T], width: usize) {
        bb((halo, field, width));
    }
}

/// Calls every partitioned-storage entry point with opaque inputs.
pub fn exercise() {
    keep(bb(PartitionFault::Pattern).describe());
    keep(Halo::empty());
    keep(Partition::scratch_len(bb(N)));
    keep(partitioned_cg_scratch_len::<3>(bb(N)));
    run::<f32, 2>();
    run::<f64, 3>();
}

/// Pattern, partition, rows and CG in `D` dimensions (`V = D`).
#[inline(never)]
fn run<T: Real, const D: usize>() {
    let ranks: &[u32] = bb(&[1]);
    let offsets: &[u32] = bb(&[0, 2]);
    let halo = Halo::new(ranks, offsets, bb(&[0, 1]), offsets, bb(&[2, 3]));
    keep(halo.neighbour_count());
    keep(halo.neighbour(bb(0)));
    keep(halo.neighbours().count());
    let ids: &[u64] = bb(&[0, 1, 2, 3]);
    let mut s = [0u32; N];
    let part = Partition::new::<T, _>(
        bb(0),
        bb(2),
        bb(2),
        ids,
        bb(4),
        halo,
        &Opaque,
        bb(&mut s[..]),
    );
    let Ok(part) = part else { return };
    keep((
        part.rank(),
        part.owned(),
        part.local_count(),
        part.global_ids(),
    ));
    keep((part.global_count(), part.halo()));
    let (c_offsets, c_nodes, c_kinds): (&[u32], &[u32], &[u8]) = if D == 2 {
        (bb(&[0, 3, 6]), bb(&[0, 1, 2, 0, 2, 3]), bb(&[5, 5]))
    } else {
        (bb(&[0, 4]), bb(&[0, 1, 2, 3]), bb(&[10]))
    };
    let cells = LocalCells {
        offsets: c_offsets,
        nodes: c_nodes,
        kinds: c_kinds,
        face_diagonals: bb(false),
    };
    keep(partitioned_targets_len(&cells));
    let mut p = [[T::ZERO; D]; N];
    for (i, q) in p.iter_mut().enumerate() {
        for (c, x) in q.iter_mut().enumerate() {
            *x = T::from_f64(((i * 7 + c * 3) % 5) as f64 * 0.25 + c as f64);
        }
    }
    let (mut o, mut t, mut k) = ([0u32; N + 1], [0u32; 12], [T::ZERO; 12]);
    let fixed: &[u8] = bb(&[1, 0, 0, 1]);
    let springs = PartitionedSprings::new(
        part,
        cells,
        bb(&p[..]),
        bb(T::ONE),
        fixed,
        bb(&mut o[..]),
        bb(&mut t[..]),
        bb(&mut k[..]),
        &Opaque,
    );
    let Ok(springs) = springs else { return };
    keep((springs.partition(), springs.system()));
    let mut x = bb([[T::ZERO; D]; N]);
    let mut scratch = [[T::ZERO; D]; 20];
    for pre in [Preconditioner::Jacobi, Preconditioner::None] {
        keep(springs.solve_cg(
            bb(&mut x[..]),
            bb(pre),
            &SolveOptions::default(),
            bb(&mut scratch[..]),
            &Opaque,
        ));
    }
    keep(&x);
    mis2::<T>(&springs);
    quaternion::<T, D>(&springs, &p);
}

/// The MIS-2 aggregation of opaque graphs, serial and on the partition.
#[inline(never)]
fn mis2<T: Real>(springs: &PartitionedSprings<'_, T>) {
    keep((mis2_scratch_len(bb(N)), mis2_exchange_len(bb(N))));
    let (offsets, targets): (&[u32], &[u32]) =
        (bb(&[0, 2, 4, 6, 8]), bb(&[1, 3, 0, 2, 1, 3, 0, 2]));
    let Ok(graph) = Graph::new(offsets, targets) else {
        return;
    };
    let fixed: &[u8] = bb(&[1, 0, 0, 1]);
    let (mut agg, mut scratch, mut reals) = ([0u64; N], [0u64; 64], [T::ZERO; 64]);
    keep(aggregate_mis2(
        &graph,
        fixed,
        bb(&mut agg[..]),
        bb(&mut scratch[..]),
    ));
    keep(aggregate_mis2_partitioned(
        springs.partition(),
        &graph,
        fixed,
        &Opaque,
        bb(&mut agg[..]),
        bb(&mut scratch[..]),
        bb(&mut reals[..]),
    ));
    keep(prolongator_partitioned_len(springs));
    let (mut offsets, mut columns, mut values) = ([0u32; N + 1], [0u64; 16], [T::ZERO; 16]);
    keep(prolongator_partitioned(
        springs,
        bb(&agg[..]),
        &Opaque,
        bb(&mut offsets[..]),
        bb(&mut columns[..]),
        bb(&mut values[..]),
    ));
}

/// Samareh's deformation with spring and with IDW propagation on the partition (shape, rigid
/// and per-node rotations), opaque boundary lists.
#[inline(never)]
fn quaternion<T: Real, const D: usize>(springs: &PartitionedSprings<'_, T>, p: &[[T; D]; N]) {
    keep(deform_spring_partitioned_lens::<D>(bb(N), bb(2), bb(2)));
    let deformed = bb([[T::ONE; D]; 2]);
    let elements = BoundaryElements {
        ids: bb(&[0, 1]),
        offsets: bb(&[0, 2, 4]),
        nodes: bb(&[0, 1, 1, 0]),
        kinds: bb(&[3, 3]),
        count: bb(2),
    };
    keep(deform_idw_partitioned_lens::<D>(bb(2), bb(2)));
    let (mut words, mut reals, mut index) = ([0i64; 96], [T::ZERO; 96], [0u32; 32]);
    let (mut kinds, mut values, mut out) = ([0u8; 8], [T::ZERO; 96], [[T::ZERO; D]; N]);
    let mut quats = [Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO); 2];
    let per_node = bb([Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO); 2]);
    for rotations in [
        RotationSource::Shape,
        RotationSource::Rigid(bb(Quat::new(T::ONE, T::ZERO, T::ZERO, T::ZERO))),
        RotationSource::PerNode(&per_node[..]),
    ] {
        let motion = PartitionedMotion {
            nodes: bb(&[0, 3]),
            positions: bb(&[0, 1]),
            deformed: &deformed,
            boundary_count: bb(2),
            elements: Some(elements),
            rotations,
            origin: bb(None),
        };
        let work = PartitionedWorkspace {
            words: bb(&mut words[..]),
            reals: bb(&mut reals[..]),
            index: bb(&mut index[..]),
            kinds: bb(&mut kinds[..]),
            values: bb(&mut values[..]),
        };
        keep(deform_spring_partitioned(
            springs,
            bb(&p[..]),
            &motion,
            bb(Preconditioner::Jacobi),
            &SolveOptions::default(),
            work,
            bb(&mut out[..]),
            &Opaque,
        ));
        let work = PartitionedIdwWorkspace {
            words: bb(&mut words[..]),
            reals: bb(&mut reals[..]),
            index: bb(&mut index[..]),
            kinds: bb(&mut kinds[..]),
            rotations: bb(&mut quats[..]),
        };
        keep(deform_idw_partitioned(
            springs.partition(),
            bb(&p[..]),
            &motion,
            bb(T::TWO),
            work,
            bb(&mut out[..N / 2]),
            &Opaque,
        ));
    }
}
