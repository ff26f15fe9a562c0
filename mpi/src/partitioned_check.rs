//! `deform-mpi-check --partitioned`: the kernel's partitioned linear-spring CG + Jacobi
//! (each rank holds only its partition: owned nodes, ghost layers, local cells, the pattern)
//! against the serial CG + Jacobi solve, bit for bit, and bad partitions rejected on every
//! rank alike.
//!
//! Each rank generates the mesh (2D NACA 2412 triangles; the same extruded into prisms), runs
//! the serial solve itself, cuts its own view ([`local_view`]: RCB or random partition, ghost
//! depth 1 or 2, shuffled local numbering) and keeps the serial values of its local nodes
//! only; every whole-mesh array is dropped before the partitioned solve, which sees the local
//! view alone.

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::spring::{
    partitioned_cg_scratch_len, solve_linear_scratch_len, LinearMethod, Preconditioner,
    SolveOptions, SolveReport,
};
use deform_meshgen::partition::{local_view, owner_of, random_owner, LocalView};
use deform_meshgen::Mesh;
use deform_mpi::{boundary_values, rcb, MpiExchange, WholeSprings};
use mpi::collective::SystemOperation;
use mpi::traits::*;

/// CG options of every case (serial and partitioned).
fn options() -> SolveOptions<f64> {
    SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 20_000,
        update_tol: 0.0,
    }
}

/// The serial CG + Jacobi solve on the whole mesh.
fn serial<const D: usize>(mesh: &Mesh<D>) -> (Vec<[f64; D]>, SolveReport<f64>) {
    let whole = WholeSprings::new(mesh);
    let sys = whole.system();
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut x = boundary_values(mesh, &whole.fixed);
    let mut s = vec![[0.0; D]; solve_linear_scratch_len(&method, mesh.node_count())];
    let r = sys
        .solve_linear(&mut x, method, &options(), &mut s)
        .expect("serial solve");
    (x, r)
}

/// What a bad-input case changes in one rank's view before the calls.
type Spoil<const D: usize> = fn(&mut LocalView<D>, &mut usize);

/// The partitioned solve on a local view (partition, rows, CG + Jacobi). `values` holds the
/// owned values (ghosts anything). Returns the report and the bytes this rank sent (halo,
/// reductions).
fn partitioned<const D: usize, C: Communicator>(
    world: &C,
    v: &LocalView<D>,
    owned: usize,
    values: &mut [[f64; D]],
) -> Result<(SolveReport<f64>, (u64, u64)), Error> {
    let ex = MpiExchange::new(world);
    let len = partitioned_cg_scratch_len::<D>(v.global_ids.len());
    let r = v.solve_cg(owned, values, Preconditioner::Jacobi, &options(), len, &ex)?;
    Ok((r, ex.bytes()))
}

/// `true` on every rank when `mine` holds on every rank.
fn all<C: Communicator>(world: &C, mine: bool) -> bool {
    let mut all = i32::from(mine);
    world.all_reduce_into(&i32::from(mine), &mut all, SystemOperation::min());
    all == 1
}

/// Every partition × ghost depth of one mesh against the serial solve.
fn mesh_cases<const D: usize, C: Communicator>(world: &C, name: &str, mesh: &Mesh<D>) -> bool {
    let (rank, size) = (world.rank() as u32, world.size() as usize);
    let fixed = mesh.boundary_mask();
    let (x, sr) = serial(mesh);
    let x0 = boundary_values(mesh, &fixed);
    let n = mesh.node_count();
    let mut ok = true;
    for (label, owner) in [
        ("RCB", owner_of(&rcb(&mesh.points, size), n)),
        ("random", random_owner(n, size, 0x5eed)),
    ] {
        for depth in [1, 2] {
            let view = local_view(
                mesh,
                &fixed,
                &owner,
                (rank, size as u32),
                depth,
                0xc0ffee + depth as u64,
            );
            // Keep the serial values of the local nodes only; ghosts start as garbage.
            let expected: Vec<[f64; D]> = view.global_ids.iter().map(|&g| x[g as usize]).collect();
            let mut values: Vec<[f64; D]> = view
                .global_ids
                .iter()
                .enumerate()
                .map(|(i, &g)| {
                    if i < view.owned {
                        x0[g as usize]
                    } else {
                        [1e300; D]
                    }
                })
                .collect();
            let result = partitioned(world, &view, view.owned, &mut values);
            let same = match &result {
                Ok((r, _)) => {
                    r.iterations == sr.iterations
                        && r.residual.to_bits() == sr.residual.to_bits()
                        && r.converged
                        && values
                            .iter()
                            .zip(&expected)
                            .all(|(a, b)| a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits()))
                }
                Err(e) => {
                    eprintln!("rank {rank}: {name} {label} depth {depth}: {e}");
                    false
                }
            };
            let (halo, reduce) = result.as_ref().map_or((0, 0), |(_, b)| *b);
            let mut max_halo = 0u64;
            world.all_reduce_into(&halo, &mut max_halo, SystemOperation::max());
            let all_same = all(world, same);
            if rank == 0 {
                let it = sr.iterations.max(1) as u64;
                println!(
                    "partitioned {name} ({n} nodes), {label}, ghost depth {depth}, {size} rank(s): {} ghosts on rank 0, {} CG iterations, per iteration {} B halo (rank 0; largest rank {} B) + {} B reductions: solution {}",
                    view.global_ids.len() - view.owned,
                    sr.iterations,
                    halo / it,
                    max_halo / it,
                    reduce / it,
                    if all_same { "bit-identical to serial on every rank" } else { "DIFFERS" }
                );
            }
            ok &= all_same;
        }
    }
    ok
}

/// A bad partition on one rank: every rank must return an error (the spoiled rank's own
/// fault, `expect_here`; `expect_others` elsewhere), none may hang.
fn bad_case<C: Communicator>(
    world: &C,
    view: &LocalView<2>,
    label: &str,
    culprit: u32,
    spoil: Spoil<2>,
    expect_here: PartitionFault,
    expect_others: PartitionFault,
) -> bool {
    let rank = world.rank() as u32;
    let mut v = view.clone();
    let mut owned = v.owned;
    if rank == culprit {
        spoil(&mut v, &mut owned);
    }
    let mut values = vec![[0.0; 2]; v.global_ids.len()];
    let want = if rank == culprit {
        expect_here
    } else {
        expect_others
    };
    let got = partitioned(world, &v, owned, &mut values).err();
    let right = matches!(got, Some(Error::BadPartition { fault, .. }) if fault == want);
    if !right {
        eprintln!("rank {rank}: {label}: expected {want:?}, got {got:?}");
    }
    let all_right = all(world, right);
    if rank == 0 {
        println!(
            "bad partition ({label}): {}",
            if all_right {
                "rejected on every rank as expected"
            } else {
                "NOT REJECTED AS EXPECTED"
            }
        );
    }
    all_right
}

/// The bad partitions (two ranks or more).
fn bad_inputs<C: Communicator>(world: &C, mesh: &Mesh<2>) -> bool {
    use PartitionFault::*;
    let (rank, size) = (world.rank() as u32, world.size() as usize);
    let fixed = mesh.boundary_mask();
    let n = mesh.node_count();
    let owner = owner_of(&rcb(&mesh.points, size), n);
    let view = local_view(mesh, &fixed, &owner, (rank, size as u32), 1, 7);
    let last = (size - 1) as u32;
    let cases: [(&str, u32, Spoil<2>, PartitionFault, PartitionFault); 6] = [
        (
            "a ghost in no receive list",
            last,
            |v, _| {
                v.recv.pop();
                *v.recv_offsets.last_mut().unwrap() -= 1;
            },
            GhostNotReceived,
            OtherProcess,
        ),
        (
            "a send list one short of its receive list",
            0,
            |v, _| {
                v.send.remove(0);
                v.send_offsets.iter_mut().skip(1).for_each(|o| *o -= 1);
            },
            Pattern,
            Pattern,
        ),
        (
            "a rank with no nodes",
            last,
            |_, owned| *owned = 0,
            NoOwnedNodes,
            OtherProcess,
        ),
        (
            "duplicate global ids on one rank",
            0,
            |v, _| v.global_ids[1] = v.global_ids[0],
            DuplicateGlobalId,
            OtherProcess,
        ),
        (
            "an owned id claimed twice across ranks",
            0,
            |v, _| {
                // An id this rank does not hold: a node of another rank's that is no ghost here.
                let held: std::collections::HashSet<u64> = v.global_ids.iter().copied().collect();
                let g = (0..v.global_count).find(|g| !held.contains(g)).unwrap();
                let i = (0..v.owned)
                    .find(|i| !v.send.contains(&(*i as u32)))
                    .unwrap();
                v.global_ids[i] = g;
            },
            OwnedIds,
            OwnedIds,
        ),
        (
            "a ghost's coordinates differ from its owner's",
            last,
            |v, _| {
                let g = v.recv[0] as usize;
                v.points[g][0] += 1e-9;
            },
            Rows,
            Rows,
        ),
    ];
    let mut ok = true;
    for (label, culprit, spoil, here, others) in cases {
        ok &= bad_case(world, &view, label, culprit, spoil, here, others);
    }
    ok
}

/// All partitioned checks; `true` when every one passed on every rank.
pub fn run<C: Communicator>(world: &C, mesh2: &Mesh<2>, mesh3: &Mesh<3>) -> bool {
    let mut ok = mesh_cases(world, "2D NACA 2412 triangles", mesh2);
    ok &= mesh_cases(world, "3D extruded prisms", mesh3);
    if world.size() >= 2 {
        ok &= bad_inputs(world, mesh2);
    }
    ok
}
