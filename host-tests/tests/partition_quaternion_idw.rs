//! The quaternion deformation with inverse-distance propagation on partitioned data
//! (kernel/src/quaternion/partitioned/idw.rs), on in-process "processes" (support::threads):
//! every owned node must get the bits of the serial `deform_idw`, in 2D and 3D, for 1–5
//! threads, block and random partitions, ghost depths 1 and 2, and rotations from the shape,
//! one rigid rotation or per node; bad input must fail on every thread, with the same error
//! everywhere, and nothing written.

mod support;

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_partitioned, deform_idw_partitioned_lens, deform_idw_scratch_len,
    BoundaryElements, BoundaryMotion, PartitionedIdwWorkspace, PartitionedMotion, RotationSource,
};
use deform_kernel::Cells;
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};
use support::partition_boundary::{
    boundary, moved, per_node_rotations, share, share_rotations, Bnd, Share,
};
use support::threads::on_threads;

/// The rotation sources under test, with the IDW exponent each runs with (`p = 2` takes the
/// serial code's path without `powf`, the others the `powf` path).
#[derive(Clone, Copy, Debug)]
enum Source {
    Shape,
    Rigid,
    PerNode,
}

impl Source {
    fn exponent(self) -> f64 {
        match self {
            Source::Shape => 2.0,
            Source::Rigid => 3.0,
            Source::PerNode => 2.5,
        }
    }
}

/// The rigid rotation of [`Source::Rigid`]: the pitch of [`moved`] about `z`.
fn rigid(deg: f64) -> Quat<f64> {
    Quat::from_axis_angle([0.0, 0.0, 1.0], deg.to_radians()).unwrap()
}

/// The serial `deform_idw`: the deformed points and the origin.
fn serial<const D: usize>(
    mesh: &Mesh<D>,
    motion: &BoundaryMotion<'_, f64, D>,
    exponent: f64,
) -> (Vec<[f64; D]>, [f64; D]) {
    let n = mesh.node_count();
    let (mut t, mut q) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
    let mut s = vec![0.0; deform_idw_scratch_len::<D>(n, motion.nodes.len())];
    let mut out = vec![[0.0; D]; n];
    let origin = deform_idw(
        &mesh.points,
        motion,
        exponent,
        &mut t,
        &mut q,
        &mut s,
        &mut out,
    )
    .unwrap();
    (out, origin)
}

/// The partitioned motion of a share (boundary `b`, elements `e`) with rotations from `source`.
fn motion<const D: usize>(
    s: &Share<D>,
    b: usize,
    e: usize,
    source: Source,
    deg: f64,
) -> PartitionedMotion<'_, f64, D> {
    PartitionedMotion {
        nodes: &s.nodes,
        positions: &s.positions,
        deformed: &s.deformed,
        boundary_count: b,
        elements: Some(BoundaryElements {
            ids: &s.ids,
            offsets: &s.offsets,
            nodes: &s.elements,
            kinds: &s.kinds,
            count: e,
        }),
        rotations: match source {
            Source::Shape => RotationSource::Shape,
            Source::Rigid => RotationSource::Rigid(rigid(deg)),
            Source::PerNode => RotationSource::PerNode(&s.rotations),
        },
        origin: None,
    }
}

/// The kernel calls of one thread: partition, then the partitioned IDW into `out` (owned
/// nodes; starts as NaN).
fn run_rank<const D: usize, E: Exchange<f64> + ?Sized>(
    v: &LocalView<D>,
    motion: &PartitionedMotion<'_, f64, D>,
    exponent: f64,
    ex: &E,
) -> (deform_kernel::Result<[f64; D]>, Vec<[f64; D]>) {
    let n = v.global_ids.len();
    let halo = Halo::new(&v.ranks, &v.send_offsets, &v.send, &v.recv_offsets, &v.recv);
    let mut ps = vec![0u32; Partition::scratch_len(n)];
    let (ids, count) = (&v.global_ids[..], v.global_count);
    let part = Partition::new(v.rank, v.size, v.owned, ids, count, halo, ex, &mut ps).unwrap();
    let e = motion.elements.map_or(0, |e| e.count);
    let lens = deform_idw_partitioned_lens::<D>(motion.boundary_count, e);
    let (mut words, mut reals) = (vec![0i64; lens.words], vec![0.0; lens.reals]);
    let (mut index, mut kinds) = (vec![0u32; lens.index], vec![0u8; lens.kinds]);
    let mut rotations = vec![Quat::identity(); lens.rotations];
    let work = PartitionedIdwWorkspace {
        words: &mut words,
        reals: &mut reals,
        index: &mut index,
        kinds: &mut kinds,
        rotations: &mut rotations,
    };
    let mut out = vec![[f64::NAN; D]; v.owned];
    let r = deform_idw_partitioned(&part, &v.points, motion, exponent, work, &mut out, ex);
    (r, out)
}

/// The serial boundary motion of `bnd` with rotations from `source`.
fn serial_motion<'a, const D: usize>(
    bnd: &'a Bnd,
    deformed: &'a [[f64; D]],
    all: &'a [Quat<f64>],
    source: Source,
    deg: f64,
) -> BoundaryMotion<'a, f64, D> {
    let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds).unwrap();
    BoundaryMotion {
        nodes: &bnd.nodes,
        deformed,
        elements: Some(elements),
        rotations: match source {
            Source::Shape => RotationSource::Shape,
            Source::Rigid => RotationSource::Rigid(rigid(deg)),
            Source::PerNode => RotationSource::PerNode(all),
        },
        origin: None,
    }
}

/// Serial and partitioned runs on `mesh` for 1–5 threads, block and random owners, depths 1
/// and 2, every rotation source: the owned nodes' bits and the origin must be the serial ones.
fn bits_equal_serial<const D: usize>(mesh: &Mesh<D>, deg: f64) {
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, deg);
    let all = per_node_rotations(bnd.nodes.len());
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let (b, e) = (bnd.nodes.len(), bnd.kinds.len());
    let bytes = 8 * (1 + 2 * b + 6 * e) + 8 * 2 * D * b;
    println!("{D}D: {n} nodes, B = {b}, E = {e}: the gather is {bytes} bytes per rank");
    for source in [Source::Shape, Source::Rigid, Source::PerNode] {
        let p = source.exponent();
        let (want, origin) = serial(mesh, &serial_motion(&bnd, &deformed, &all, source, deg), p);
        for size in 1..=5usize {
            for (label, owner) in [
                ("blocks", (0..n).map(|g| (g * size / n) as u32).collect()),
                ("random", random_owner(n, size, 11)),
            ] {
                for depth in [1, 2] {
                    let results = on_threads(size, |rank, ex| {
                        let v = local_view(mesh, &fixed, &owner, (rank, size as u32), depth, 3);
                        let mut s = share(&v, &bnd, &deformed, |_, first_owned| first_owned);
                        s.rotations = share_rotations(&s, &all);
                        let m = motion(&s, b, e, source, deg);
                        let (r, out) = run_rank(&v, &m, p, ex);
                        (v.global_ids, r, out)
                    });
                    for (rank, (ids, r, out)) in results.into_iter().enumerate() {
                        let what = format!(
                            "{D}D {source:?} {label}, {size} threads, depth {depth}, rank {rank}"
                        );
                        let o = r.unwrap_or_else(|e| panic!("{what}: {e}"));
                        assert_eq!(o.map(f64::to_bits), origin.map(f64::to_bits), "{what}");
                        for (&g, o) in ids.iter().zip(&out) {
                            let w = want[g as usize];
                            assert_eq!(
                                o.map(f64::to_bits),
                                w.map(f64::to_bits),
                                "{what}: node {g}"
                            );
                        }
                    }
                }
            }
        }
    }
}

fn mesh_2d(surface_points: usize, radial_points: usize) -> Mesh<2> {
    naca_triangulated(&AirfoilGrid {
        surface_points,
        radial_points,
        ..AirfoilGrid::default()
    })
    .unwrap()
}

#[test]
fn partitioned_quaternion_idw_gives_the_serial_bits_2d() {
    bits_equal_serial(&mesh_2d(40, 10), 12.0);
}

#[test]
fn partitioned_quaternion_idw_gives_the_serial_bits_3d() {
    let mesh = extrude(&mesh_2d(16, 5), 1.0, 3).unwrap();
    bits_equal_serial(&mesh, 8.0);
}

/// What a spoiled share should give on the culprit (`true`) and on the other threads.
type Expect = fn(&Option<Error>, bool) -> bool;

fn boundary_fault(e: &Option<Error>, _culprit: bool) -> bool {
    matches!(
        e,
        Some(Error::BadPartition {
            fault: PartitionFault::Boundary,
            ..
        })
    )
}

/// The culprit's own argument error (any but a partition fault), `OtherProcess` elsewhere.
fn own_then_others(e: &Option<Error>, culprit: bool) -> bool {
    match e {
        Some(Error::BadPartition {
            fault: PartitionFault::OtherProcess,
            ..
        }) => !culprit,
        Some(Error::BadPartition { .. }) | None => false,
        Some(_) => culprit,
    }
}

/// A spoiled share: the thread's share, its boundary count and its exponent.
type Spoil = fn(&mut Share<2>, &mut usize, &mut f64);

#[test]
fn bad_input_fails_on_every_thread_with_nothing_written() {
    let mesh = mesh_2d(24, 6);
    let bnd = boundary(&mesh);
    let deformed = moved(&mesh, &bnd.nodes, 10.0);
    let all = per_node_rotations(bnd.nodes.len());
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let (b, e) = (bnd.nodes.len(), bnd.kinds.len());
    // Random owners: every thread holds boundary nodes and elements to spoil.
    let owner = random_owner(n, 3, 5);
    let cases: [(&str, u32, Spoil, Expect); 9] = [
        (
            "one global id at two positions",
            2,
            |s, _, _| {
                // The thread's first owned boundary node also takes its second one's place.
                s.nodes[1] = s.nodes[0];
                s.deformed[1] = s.deformed[0];
            },
            boundary_fault,
        ),
        (
            "two threads give one position",
            0,
            |s, _, _| s.positions[0] = s.positions[1],
            boundary_fault,
        ),
        (
            "another boundary count",
            1,
            |_, b, _| *b += 1,
            boundary_fault,
        ),
        (
            "an element given by nobody",
            1,
            |s, _, _| {
                s.ids.pop();
                s.kinds.pop();
                s.offsets.pop();
                s.elements.truncate(*s.offsets.last().unwrap() as usize);
            },
            boundary_fault,
        ),
        (
            "a boundary position given by nobody",
            2,
            |s, _, _| {
                s.nodes.pop();
                s.positions.pop();
                s.deformed.pop();
                s.rotations.pop();
            },
            boundary_fault,
        ),
        (
            "one rotation too few",
            1,
            |s, _, _| {
                s.rotations.pop();
            },
            own_then_others,
        ),
        (
            "a zero rotation",
            0,
            |s, _, _| s.rotations[0] = Quat::new(0.0, 0.0, 0.0, 0.0),
            own_then_others,
        ),
        (
            "a node that is not owned",
            2,
            |s, _, _| s.nodes[0] = u32::MAX,
            own_then_others,
        ),
        ("a bad exponent", 1, |_, _, p| *p = -1.0, own_then_others),
    ];
    for (what, culprit, spoil, expect) in cases {
        let results = on_threads(3, |rank, ex| {
            let v = local_view(&mesh, &fixed, &owner, (rank, 3), 1, 5);
            let mut s = share(&v, &bnd, &deformed, |_, first_owned| first_owned);
            s.rotations = share_rotations(&s, &all);
            let (mut bb, mut p) = (b, 2.0);
            if rank == culprit {
                assert!(s.nodes.len() >= 2, "{what}: rank {rank} owns too little");
                spoil(&mut s, &mut bb, &mut p);
            }
            let m = motion(&s, bb, e, Source::PerNode, 10.0);
            let (r, out) = run_rank(&v, &m, p, ex);
            (r.err(), out.iter().flatten().all(|x| x.is_nan()))
        });
        // A fault found in the merged data is the same error everywhere; an argument error is
        // the culprit's own, and `OtherProcess` alike on every other thread.
        let shared = boundary_fault(&results[culprit as usize].0, true);
        let other = &results[(culprit as usize + 1) % 3].0;
        for (rank, (err, untouched)) in results.iter().enumerate() {
            let here = rank as u32 == culprit;
            assert!(expect(err, here), "{what}: rank {rank}: {err:?}");
            if shared || !here {
                assert_eq!(
                    format!("{err:?}"),
                    format!("{other:?}"),
                    "{what}: rank {rank}"
                );
            }
            assert!(untouched, "{what}: rank {rank} wrote out");
        }
    }
}
