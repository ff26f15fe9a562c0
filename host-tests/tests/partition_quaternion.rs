//! The quaternion deformation with spring propagation on partitioned data
//! (kernel/src/quaternion/partitioned.rs), on in-process "processes" (support::threads): every
//! owned node must get the bits of the serial `deform_spring_with` with CG + Jacobi, in 2D
//! and 3D, for block and random partitions and ghost depths 1 and 2; inconsistent boundary
//! lists must fail on every thread with nothing written.

mod support;

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_spring_partitioned, deform_spring_partitioned_lens, deform_spring_scratch_len,
    deform_spring_with, propagate_spring_with_scratch_len, BoundaryElements, BoundaryMotion,
    PartitionedMotion, PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, partitioned_targets_len, LinearMethod, LinearSolver, LocalCells,
    PartitionedSprings, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph};
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};
use support::partition_boundary::{
    boundary, moved, per_node_rotations, share, share_rotations, Share,
};
use support::threads::on_threads;

fn options() -> SolveOptions<f64> {
    SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 20_000,
        update_tol: 0.0,
    }
}

/// The serial `deform_spring_with` (CG + Jacobi, Batina `p = 1`, no face diagonals).
fn serial<const D: usize>(mesh: &Mesh<D>, motion: &BoundaryMotion<'_, f64, D>) -> Vec<[f64; D]> {
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    motion.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut ss).unwrap();
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let (mut t, mut q) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
    let mut s = vec![0.0; deform_spring_scratch_len::<D>(n, motion.nodes.len())];
    let mut values = vec![0.0; propagate_spring_with_scratch_len::<D>(&solver, n)];
    let mut out = vec![[0.0; D]; n];
    let (_, rep) = deform_spring_with(
        &mesh.points,
        motion,
        &sys,
        solver,
        &options(),
        &mut t,
        &mut q,
        &mut s,
        &mut values,
        &mut out,
    )
    .unwrap();
    assert!(rep.converged);
    out
}

/// The kernel calls of one thread: partition, springs, then the partitioned deformation
/// into `out` (owned nodes; starts as NaN).
fn run_rank<const D: usize, E: Exchange<f64> + ?Sized>(
    v: &LocalView<D>,
    s: &Share<D>,
    motion_of: impl Fn(&Share<D>) -> PartitionedMotion<'_, f64, D>,
    ex: &E,
) -> (deform_kernel::Result<[f64; D]>, Vec<[f64; D]>) {
    let n = v.global_ids.len();
    let halo = Halo::new(&v.ranks, &v.send_offsets, &v.send, &v.recv_offsets, &v.recv);
    let mut ps = vec![0u32; Partition::scratch_len(n)];
    let (ids, count) = (&v.global_ids[..], v.global_count);
    let part = Partition::new(v.rank, v.size, v.owned, ids, count, halo, ex, &mut ps).unwrap();
    let cells = LocalCells {
        offsets: &v.cell_offsets,
        nodes: &v.cell_nodes,
        kinds: &v.cell_kinds,
        face_diagonals: false,
    };
    let len = partitioned_targets_len(&cells);
    let (mut o, mut t, mut k) = (vec![0u32; n + 1], vec![0u32; len], vec![0.0; len]);
    let springs = PartitionedSprings::new(
        part, cells, &v.points, 1.0, &v.fixed, &mut o, &mut t, &mut k, ex,
    )
    .unwrap();
    let motion = motion_of(s);
    let e = motion.elements.map_or(0, |e| e.count);
    let lens = deform_spring_partitioned_lens::<D>(n, motion.boundary_count, e);
    let (mut words, mut reals) = (vec![0i64; lens.words], vec![0.0; lens.reals]);
    let (mut index, mut kinds) = (vec![0u32; lens.index], vec![0u8; lens.kinds]);
    let mut values = vec![0.0; lens.values];
    let work = PartitionedWorkspace {
        words: &mut words,
        reals: &mut reals,
        index: &mut index,
        kinds: &mut kinds,
        values: &mut values,
    };
    let mut out = vec![[f64::NAN; D]; v.owned];
    let pre = Preconditioner::Jacobi;
    let r = deform_spring_partitioned(
        &springs,
        &v.points,
        &motion,
        pre,
        &options(),
        work,
        &mut out,
        ex,
    )
    .map(|(origin, _)| origin);
    (r, out)
}

/// The partitioned motion of a share (boundary `b`, elements `e`).
fn motion<const D: usize>(s: &Share<D>, b: usize, e: usize) -> PartitionedMotion<'_, f64, D> {
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
        rotations: RotationSource::Shape,
        origin: None,
    }
}

/// [`motion`] with the share's `RotationSource::PerNode` rotations.
fn motion_per_node<const D: usize>(
    s: &Share<D>,
    b: usize,
    e: usize,
) -> PartitionedMotion<'_, f64, D> {
    PartitionedMotion {
        rotations: RotationSource::PerNode(&s.rotations),
        ..motion(s, b, e)
    }
}

/// Serial and partitioned runs on `mesh` for `sizes` threads, block and random owners, depths
/// 1 and 2: the owned nodes' bits must be the serial ones. Rotations from the shape, or
/// `PerNode` from [`per_node_rotations`] when `per_node`.
fn bits_equal_serial<const D: usize>(mesh: &Mesh<D>, deg: f64, per_node: bool, sizes: &[usize]) {
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, deg);
    let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds).unwrap();
    let all = per_node_rotations(bnd.nodes.len());
    let smotion = BoundaryMotion {
        nodes: &bnd.nodes,
        deformed: &deformed,
        elements: Some(elements),
        rotations: if per_node {
            RotationSource::PerNode(&all)
        } else {
            RotationSource::Shape
        },
        origin: None,
    };
    let want = serial(mesh, &smotion);
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let (b, e) = (bnd.nodes.len(), bnd.kinds.len());
    let reals = if per_node { 2 * D + 4 } else { 2 * D } * b;
    let bytes = 8 * (1 + 2 * b + 6 * e) + 8 * reals;
    println!("{D}D: {n} nodes, B = {b}, E = {e}: the gather is {bytes} bytes per rank");
    for &size in sizes {
        for (label, owner) in [
            ("blocks", (0..n).map(|g| (g * size / n) as u32).collect()),
            ("random", random_owner(n, size, 7)),
        ] {
            for depth in [1, 2] {
                let results = on_threads(size, |rank, ex| {
                    let v = local_view(mesh, &fixed, &owner, (rank, size as u32), depth, 5);
                    let mut s = share(&v, &bnd, &deformed, |_, first_owned| first_owned);
                    s.rotations = share_rotations(&s, &all);
                    let of = if per_node { motion_per_node } else { motion };
                    let (r, out) = run_rank(&v, &s, |s| of(s, b, e), ex);
                    (v.global_ids, r, out)
                });
                for (rank, (ids, r, out)) in results.into_iter().enumerate() {
                    let what = format!("{D}D {label}, {size} threads, depth {depth}, rank {rank}");
                    r.unwrap_or_else(|e| panic!("{what}: {e}"));
                    for (&g, o) in ids.iter().zip(&out) {
                        let w = want[g as usize];
                        assert_eq!(o.map(f64::to_bits), w.map(f64::to_bits), "{what}: node {g}");
                    }
                }
            }
        }
    }
}

#[test]
fn partitioned_quaternion_springs_give_the_serial_bits_2d() {
    let mesh = naca_triangulated(&AirfoilGrid {
        surface_points: 40,
        radial_points: 10,
        ..AirfoilGrid::default()
    })
    .unwrap();
    bits_equal_serial(&mesh, 12.0, false, &[1, 2, 3, 4]);
}

#[test]
fn partitioned_quaternion_springs_give_the_serial_bits_3d() {
    let mesh2 = naca_triangulated(&AirfoilGrid {
        surface_points: 16,
        radial_points: 5,
        ..AirfoilGrid::default()
    })
    .unwrap();
    let mesh = extrude(&mesh2, 1.0, 3).unwrap();
    bits_equal_serial(&mesh, 8.0, false, &[1, 2, 3, 4]);
}

#[test]
fn partitioned_quaternion_springs_with_per_node_rotations_give_the_serial_bits_2d() {
    let mesh = naca_triangulated(&AirfoilGrid {
        surface_points: 40,
        radial_points: 10,
        ..AirfoilGrid::default()
    })
    .unwrap();
    bits_equal_serial(&mesh, 12.0, true, &[1, 2, 5]);
}

#[test]
fn partitioned_quaternion_springs_with_per_node_rotations_give_the_serial_bits_3d() {
    let mesh2 = naca_triangulated(&AirfoilGrid {
        surface_points: 16,
        radial_points: 5,
        ..AirfoilGrid::default()
    })
    .unwrap();
    let mesh = extrude(&mesh2, 1.0, 3).unwrap();
    bits_equal_serial(&mesh, 8.0, true, &[1, 3, 5]);
}

/// What a spoiled share should give: the culprit's error, and every other rank's.
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

fn own_then_others(e: &Option<Error>, culprit: bool) -> bool {
    match e {
        Some(Error::InvalidParameter { .. }) => culprit,
        Some(Error::BadPartition {
            fault: PartitionFault::OtherProcess,
            ..
        }) => !culprit,
        _ => false,
    }
}

#[test]
fn inconsistent_boundary_lists_fail_on_every_thread() {
    let mesh = naca_triangulated(&AirfoilGrid {
        surface_points: 24,
        radial_points: 6,
        ..AirfoilGrid::default()
    })
    .unwrap();
    let bnd = boundary(&mesh);
    let deformed = moved(&mesh, &bnd.nodes, 10.0);
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let (b, e) = (bnd.nodes.len(), bnd.kinds.len());
    // Random owners: every thread holds boundary nodes and elements to spoil.
    let owner = random_owner(n, 3, 5);
    type Spoil = fn(&mut Share<2>, &mut usize);
    let cases: [(&str, u32, Spoil, Expect); 5] = [
        (
            "an element given by nobody",
            1,
            |s, _| {
                s.ids.pop();
                s.kinds.pop();
                s.offsets.pop();
                s.elements.truncate(*s.offsets.last().unwrap() as usize);
            },
            boundary_fault,
        ),
        ("another boundary count", 2, |_, b| *b += 1, boundary_fault),
        (
            "two ranks give one position",
            0,
            |s, _| {
                s.positions[0] = s.positions[1];
            },
            boundary_fault,
        ),
        (
            "an element given twice",
            0,
            |s, _| {
                s.ids.push(s.ids[0]);
                let el = s.elements[..2].to_vec();
                s.elements.extend(el);
                s.kinds.push(s.kinds[0]);
                s.offsets.push(s.elements.len() as u32);
            },
            boundary_fault,
        ),
        (
            "an owned fixed node not listed",
            1,
            |s, _| {
                s.nodes.pop();
                s.positions.pop();
                s.deformed.pop();
            },
            own_then_others,
        ),
    ];
    for (what, culprit, spoil, expect) in cases {
        let results = on_threads(3, |rank, ex| {
            let v = local_view(&mesh, &fixed, &owner, (rank, 3), 1, 5);
            let mut s = share(&v, &bnd, &deformed, |_, first_owned| first_owned);
            let mut bb = b;
            if rank == culprit {
                spoil(&mut s, &mut bb);
            }
            let (r, out) = run_rank(&v, &s, |s| motion(s, bb, e), ex);
            (r.err(), out.iter().flatten().all(|x| x.is_nan()))
        });
        for (rank, (err, untouched)) in results.into_iter().enumerate() {
            let here = rank as u32 == culprit;
            assert!(expect(&err, here), "{what}: rank {rank}: {err:?}");
            assert!(untouched, "{what}: rank {rank} wrote out");
        }
    }
}
