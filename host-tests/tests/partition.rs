//! Partitioned storage (kernel/src/partition, spring/partitioned.rs) without MPI: each
//! "process" is a thread with only its view of the mesh (deform_meshgen::partition), the
//! exchanges go through shared memory behind barriers, and the partitioned CG + Jacobi must
//! give the serial solve's bits; bad partitions must fail on every thread (none may hang).
//! The same checks run under mpirun in `cargo xtask ci --step mpi`.

mod support;

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::spring::{
    batina_stiffness, partitioned_cg_scratch_len, solve_linear_scratch_len, LinearMethod,
    Preconditioner, SolveOptions, SolveReport, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{naca_triangulated, AirfoilGrid, Mesh};
use support::threads::on_threads;

fn options() -> SolveOptions<f64> {
    SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 20_000,
        update_tol: 0.0,
    }
}

fn mesh() -> Mesh<2> {
    naca_triangulated(&AirfoilGrid {
        surface_points: 48,
        radial_points: 12,
        ..AirfoilGrid::default()
    })
    .unwrap()
}

/// A rotation of the fixed nodes; free nodes start at zero.
fn start(mesh: &Mesh<2>, fixed: &[u8]) -> Vec<[f64; 2]> {
    mesh.points
        .iter()
        .zip(fixed)
        .map(|(p, &f)| {
            if f != 0 {
                [-0.05 * p[1], 0.05 * p[0]]
            } else {
                [0.0; 2]
            }
        })
        .collect()
}

/// The serial CG + Jacobi solve of the whole mesh.
fn serial(mesh: &Mesh<2>, fixed: &[u8]) -> (Vec<[f64; 2]>, SolveReport<f64>) {
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let mut scratch = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, fixed, &mut scratch).unwrap();
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut x = start(mesh, fixed);
    let mut s = vec![[0.0; 2]; solve_linear_scratch_len(&method, n)];
    let r = sys
        .solve_linear(&mut x, method, &options(), &mut s)
        .unwrap();
    (x, r)
}

/// The view's starting values: owned from `x0`, ghosts garbage (taken from their owners).
fn local_start(v: &LocalView<2>, x0: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut x: Vec<[f64; 2]> = v.global_ids.iter().map(|&g| x0[g as usize]).collect();
    x[v.owned..].fill([1e300; 2]);
    x
}

#[test]
fn partitioned_cg_gives_the_serial_bits() {
    let mesh = mesh();
    let fixed = mesh.boundary_mask();
    let (x, sr) = serial(&mesh, &fixed);
    let x0 = start(&mesh, &fixed);
    let n = mesh.node_count();
    for size in [1usize, 2, 3, 4] {
        for (label, owner) in [
            ("stripes", (0..n).map(|g| (g * size / n) as u32).collect()),
            ("random", random_owner(n, size, 11)),
        ] {
            for depth in [1, 2] {
                let results = on_threads(size, |rank, ex| {
                    let v = local_view(&mesh, &fixed, &owner, (rank, size as u32), depth, 5);
                    let mut values = local_start(&v, &x0);
                    let len = partitioned_cg_scratch_len::<2>(v.global_ids.len());
                    let pre = Preconditioner::Jacobi;
                    let r = v.solve_cg(v.owned, &mut values, pre, &options(), len, ex);
                    (v.global_ids, values, r)
                });
                for (rank, (ids, values, r)) in results.into_iter().enumerate() {
                    let r = r.unwrap();
                    let what = format!("{label}, {size} threads, depth {depth}, rank {rank}");
                    assert_eq!(r.iterations, sr.iterations, "{what}");
                    assert_eq!(r.residual.to_bits(), sr.residual.to_bits(), "{what}");
                    for (&g, v) in ids.iter().zip(&values) {
                        let want = x[g as usize];
                        assert_eq!(
                            v.map(f64::to_bits),
                            want.map(f64::to_bits),
                            "{what}: node {g}"
                        );
                    }
                }
            }
        }
    }
}

/// Spoils one thread's view (and owned count).
type Spoil = Box<dyn Fn(&mut LocalView<2>, &mut usize) + Sync>;

/// Every thread's error when thread `culprit`'s view is spoiled by `spoil`.
fn errors_with(
    culprit: u32,
    spoil: impl Fn(&mut LocalView<2>, &mut usize) + Sync,
    pre: Preconditioner<f64>,
    short_scratch: bool,
) -> Vec<(Option<Error>, bool)> {
    let mesh = mesh();
    let fixed = mesh.boundary_mask();
    let x0 = start(&mesh, &fixed);
    let n = mesh.node_count();
    let owner: Vec<u32> = (0..n).map(|g| (g * 3 / n) as u32).collect();
    on_threads(3, |rank, ex| {
        let mut v = local_view(&mesh, &fixed, &owner, (rank, 3), 1, 5);
        let mut owned = v.owned;
        let mut len = partitioned_cg_scratch_len::<2>(v.global_ids.len());
        if rank == culprit {
            spoil(&mut v, &mut owned);
            len -= usize::from(short_scratch);
        }
        let mut values = local_start(&v, &x0);
        let before = values.clone();
        let e = v
            .solve_cg(owned, &mut values, pre, &options(), len, ex)
            .err();
        (e, values == before)
    })
}

/// The fault of a [`Error::BadPartition`].
fn fault(e: &Option<Error>) -> Option<PartitionFault> {
    match e {
        Some(Error::BadPartition { fault, .. }) => Some(*fault),
        _ => None,
    }
}

#[test]
fn a_bad_partition_fails_on_every_thread() {
    use PartitionFault::*;
    let unspoiled = |_: &mut LocalView<2>, _: &mut usize| {};
    let cases: [(&str, Spoil, [PartitionFault; 3]); 5] = [
        (
            "no owned node",
            Box::new(|_, o| *o = 0),
            [OtherProcess, NoOwnedNodes, OtherProcess],
        ),
        (
            "a ghost received twice",
            Box::new(|v, _| {
                let g = v.recv[0];
                *v.recv.last_mut().unwrap() = g;
            }),
            [OtherProcess, GhostReceivedTwice, OtherProcess],
        ),
        (
            "a send entry that is a ghost",
            Box::new(|v, _| v.send[0] = v.owned as u32),
            [OtherProcess, SendNotOwned, OtherProcess],
        ),
        (
            "a ghost received in another order than sent",
            Box::new(|v, _| v.recv.swap(0, 1)),
            [Pattern, Pattern, Pattern],
        ),
        (
            "a ghost's fixed flag differs from its owner's",
            Box::new(|v, _| {
                let g = v.owned;
                v.fixed[g] ^= 1;
            }),
            [Rows, Rows, Rows],
        ),
    ];
    for (label, spoil, want) in cases {
        let got = errors_with(1, spoil, Preconditioner::Jacobi, false);
        let faults: Vec<_> = got.iter().map(|(e, _)| fault(e)).collect();
        assert_eq!(faults, want.map(Some).to_vec(), "{label}");
        assert!(got.iter().all(|(_, same)| *same), "{label}: values written");
    }
    // Errors of the caller's own arrays (halo offsets, cells): this thread's own error, the
    // others' OtherProcess, at the stage that checks them.
    let bad_offsets: Spoil = Box::new(|v, _| v.send_offsets[1] = u32::MAX);
    let unknown_kind: Spoil = Box::new(|v, _| v.cell_kinds[0] = 99);
    for (label, spoil) in [("halo offsets", bad_offsets), ("cell kind", unknown_kind)] {
        let got = errors_with(1, spoil, Preconditioner::Jacobi, false);
        assert!(
            matches!(
                got[1].0,
                Some(Error::BadOffsets { .. } | Error::UnknownCellKind { .. })
            ),
            "{label}: {got:?}"
        );
        assert_eq!(fault(&got[0].0), Some(OtherProcess), "{label}");
        assert_eq!(fault(&got[2].0), Some(OtherProcess), "{label}");
    }
    // Solve-stage errors: agreed too, values untouched.
    let got = errors_with(2, unspoiled, Preconditioner::Jacobi, true);
    assert!(
        matches!(got[2].0, Some(Error::BufferTooSmall { .. })),
        "{got:?}"
    );
    assert_eq!(fault(&got[0].0), Some(OtherProcess));
    assert!(got.iter().all(|(_, same)| *same));
    let got = errors_with(0, unspoiled, Preconditioner::Ssor { omega: 1.0 }, false);
    assert!(got
        .iter()
        .all(|(e, same)| matches!(e, Some(Error::InvalidParameter { .. })) && *same));
}
