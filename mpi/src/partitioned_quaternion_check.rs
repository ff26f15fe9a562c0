//! `deform-mpi-check --partitioned`, second part: the kernel's partitioned quaternion
//! deformation with spring propagation (`deform_spring_partitioned`, CG + Jacobi) under MPI
//! against the serial `deform_spring_with`, bit for bit on every owned node (and the origin,
//! the iteration count and the residual), and inconsistent boundaries or partitions rejected
//! on every rank with nothing written.
//!
//! Rank 0 runs the serial deformation on the whole mesh and broadcasts it (the reference
//! only). Each rank cuts its own view ([`local_view`]: RCB with ghost depth 1, a random
//! partition with depth 2, shuffled local numbering) and its share of the boundary (its owned
//! boundary nodes with their positions in the global boundary list, which is scrambled
//! against the node order, and the boundary elements whose first node it owns); the kernel
//! calls see that local data alone, the exchanges go through [`MpiExchange`].

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::partition::{Halo, Partition};
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_spring_partitioned, deform_spring_partitioned_lens, deform_spring_scratch_len,
    deform_spring_with, propagate_spring_with_scratch_len, BoundaryElements, BoundaryMotion,
    PartitionedMotion, PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::{
    partitioned_targets_len, LinearMethod, LinearSolver, LocalCells, PartitionedSprings,
    Preconditioner, SolveOptions, SolveReport,
};
use deform_kernel::Cells;
use deform_meshgen::partition::{local_view, owner_of, random_owner, LocalView};
use deform_meshgen::Mesh;
use deform_mpi::{rcb, MpiExchange, WholeSprings};
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

/// The serial boundary: every marker's nodes in a scrambled order (so that the boundary order
/// is not the node order), and every marker's elements in that numbering.
struct Bnd {
    nodes: Vec<u32>,
    offsets: Vec<u32>,
    elements: Vec<u32>,
    kinds: Vec<u8>,
}

fn boundary<const D: usize>(mesh: &Mesh<D>) -> Bnd {
    let mut seen = vec![false; mesh.node_count()];
    let mut nodes: Vec<u32> = Vec::new();
    for m in &mesh.markers {
        for &n in &m.node_list {
            if !std::mem::replace(&mut seen[n as usize], true) {
                nodes.push(n);
            }
        }
    }
    let b = nodes.len();
    // A stride coprime to `b` scrambles the order.
    let step = [7, 11, 13].into_iter().find(|s| b % s != 0).unwrap_or(1);
    nodes = (0..b).map(|k| nodes[(k * step + 3) % b]).collect();
    let mut pos = vec![u32::MAX; mesh.node_count()];
    for (k, &n) in nodes.iter().enumerate() {
        pos[n as usize] = k as u32;
    }
    let (mut offsets, mut elements, mut kinds) = (vec![0u32], Vec::new(), Vec::new());
    for m in &mesh.markers {
        for e in 0..m.kinds.len() {
            let el = &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize];
            elements.extend(el.iter().map(|&n| pos[n as usize]));
            kinds.push(m.kinds[e]);
            offsets.push(elements.len() as u32);
        }
    }
    Bnd {
        nodes,
        offsets,
        elements,
        kinds,
    }
}

/// A pitch by `deg` about the quarter chord plus a heave of the `"airfoil"` nodes; the rest of
/// the boundary stays.
fn moved<const D: usize>(mesh: &Mesh<D>, nodes: &[u32], deg: f64) -> Vec<[f64; D]> {
    let wall = &mesh.marker("airfoil").expect("airfoil marker").node_list;
    let (s, c) = deg.to_radians().sin_cos();
    nodes
        .iter()
        .map(|&n| {
            let mut p = mesh.points[n as usize];
            if wall.binary_search(&n).is_ok() {
                let (x, y) = (p[0] - 0.25, p[1]);
                p[0] = 0.25 + c * x - s * y;
                p[1] = s * x + c * y + 0.02;
            }
            p
        })
        .collect()
}

/// The fixed mask of the boundary nodes.
fn fixed_mask(n: usize, bnd: &Bnd) -> Vec<u8> {
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    fixed
}

/// The serial reference, as words every rank receives from rank 0: the deformed points
/// (`D` per node), the origin, the iteration count and the residual, all as bits.
fn serial_words<const D: usize, C: Communicator>(
    world: &C,
    mesh: &Mesh<D>,
    bnd: &Bnd,
    deformed: &[[f64; D]],
) -> Vec<u64> {
    let n = mesh.node_count();
    let mut words = vec![0u64; n * D + D + 2];
    if world.rank() == 0 {
        let fixed = fixed_mask(n, bnd);
        let mut whole = WholeSprings::new(mesh);
        whole.fixed = fixed;
        let sys = whole.system();
        let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds)
            .expect("boundary elements");
        let motion = BoundaryMotion {
            nodes: &bnd.nodes,
            deformed,
            elements: Some(elements),
            rotations: RotationSource::Shape,
            origin: None,
        };
        let solver = LinearSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        });
        let (mut t, mut q) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
        let mut s = vec![0.0; deform_spring_scratch_len::<D>(n, bnd.nodes.len())];
        let mut values = vec![0.0; propagate_spring_with_scratch_len::<D>(&solver, n)];
        let mut out = vec![[0.0; D]; n];
        let (origin, r) = deform_spring_with(
            &mesh.points,
            &motion,
            &sys,
            solver,
            &options(),
            &mut t,
            &mut q,
            &mut s,
            &mut values,
            &mut out,
        )
        .expect("serial deformation");
        let all = out.iter().flatten().chain(&origin).map(|x| x.to_bits());
        for (w, x) in words.iter_mut().zip(all) {
            *w = x;
        }
        words[n * D + D] = r.iterations as u64;
        words[n * D + D + 1] = r.residual.to_bits();
    }
    world.process_at_rank(0).broadcast_into(&mut words[..]);
    words
}

/// One rank's share of the boundary (see the module doc).
#[derive(Clone)]
struct Share<const D: usize> {
    nodes: Vec<u32>,
    positions: Vec<u32>,
    deformed: Vec<[f64; D]>,
    ids: Vec<u32>,
    offsets: Vec<u32>,
    elements: Vec<u32>,
    kinds: Vec<u8>,
    boundary_count: usize,
    element_count: usize,
}

fn share<const D: usize>(v: &LocalView<D>, bnd: &Bnd, deformed: &[[f64; D]]) -> Share<D> {
    let local: std::collections::HashMap<u64, usize> = v.global_ids[..v.owned]
        .iter()
        .enumerate()
        .map(|(i, &g)| (g, i))
        .collect();
    let owns = |g: u32| local.get(&u64::from(g)).copied();
    let mut s = Share {
        nodes: Vec::new(),
        positions: Vec::new(),
        deformed: Vec::new(),
        ids: Vec::new(),
        offsets: vec![0],
        elements: Vec::new(),
        kinds: Vec::new(),
        boundary_count: bnd.nodes.len(),
        element_count: bnd.kinds.len(),
    };
    for (k, &g) in bnd.nodes.iter().enumerate() {
        if let Some(i) = owns(g) {
            s.nodes.push(i as u32);
            s.positions.push(k as u32);
            s.deformed.push(deformed[k]);
        }
    }
    for c in 0..bnd.kinds.len() {
        let el = &bnd.elements[bnd.offsets[c] as usize..bnd.offsets[c + 1] as usize];
        if owns(bnd.nodes[el[0] as usize]).is_some() {
            s.ids.push(c as u32);
            s.elements.extend_from_slice(el);
            s.kinds.push(bnd.kinds[c]);
            s.offsets.push(s.elements.len() as u32);
        }
    }
    s
}

/// The kernel calls of one rank: partition, springs, the partitioned deformation into `out`
/// (the owned nodes). Returns the origin and the report.
fn partitioned<const D: usize, C: Communicator>(
    world: &C,
    v: &LocalView<D>,
    s: &Share<D>,
    out: &mut [[f64; D]],
) -> Result<([f64; D], SolveReport<f64>), Error> {
    let ex = MpiExchange::new(world);
    let n = v.global_ids.len();
    let halo = Halo::new(&v.ranks, &v.send_offsets, &v.send, &v.recv_offsets, &v.recv);
    let mut ps = vec![0u32; Partition::scratch_len(n)];
    let (ids, count) = (&v.global_ids[..], v.global_count);
    let part = Partition::new(v.rank, v.size, v.owned, ids, count, halo, &ex, &mut ps)?;
    let cells = LocalCells {
        offsets: &v.cell_offsets,
        nodes: &v.cell_nodes,
        kinds: &v.cell_kinds,
        face_diagonals: false,
    };
    let len = partitioned_targets_len(&cells);
    let (mut o, mut t, mut k) = (vec![0u32; n + 1], vec![0u32; len], vec![0.0; len]);
    let (points, fixed) = (&v.points[..], &v.fixed[..]);
    let springs =
        PartitionedSprings::new(part, cells, points, 1.0, fixed, &mut o, &mut t, &mut k, &ex)?;
    let motion = PartitionedMotion {
        nodes: &s.nodes,
        positions: &s.positions,
        deformed: &s.deformed,
        boundary_count: s.boundary_count,
        elements: Some(BoundaryElements {
            ids: &s.ids,
            offsets: &s.offsets,
            nodes: &s.elements,
            kinds: &s.kinds,
            count: s.element_count,
        }),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let lens = deform_spring_partitioned_lens::<D>(n, s.boundary_count, s.element_count);
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
    let pre = Preconditioner::Jacobi;
    deform_spring_partitioned(&springs, points, &motion, pre, &options(), work, out, &ex)
}

/// `true` on every rank when `mine` holds on every rank.
fn all<C: Communicator>(world: &C, mine: bool) -> bool {
    let mut all = i32::from(mine);
    world.all_reduce_into(&i32::from(mine), &mut all, SystemOperation::min());
    all == 1
}

/// RCB with ghost depth 1 and a random partition with depth 2 of one mesh against the
/// serial deformation.
fn mesh_cases<const D: usize, C: Communicator>(
    world: &C,
    name: &str,
    mesh: &Mesh<D>,
    deg: f64,
) -> bool {
    let (rank, size) = (world.rank() as u32, world.size() as usize);
    let n = mesh.node_count();
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, deg);
    let want = serial_words(world, mesh, &bnd, &deformed);
    let fixed = fixed_mask(n, &bnd);
    let mut ok = true;
    for (label, owner, depth) in [
        ("RCB", owner_of(&rcb(&mesh.points, size), n), 1),
        ("random", random_owner(n, size, 0x5eed), 2),
    ] {
        let view = local_view(mesh, &fixed, &owner, (rank, size as u32), depth, 0xbead);
        let s = share(&view, &bnd, &deformed);
        let mut out = vec![[f64::NAN; D]; view.owned];
        let result = partitioned(world, &view, &s, &mut out);
        let same = match &result {
            Ok((origin, r)) => {
                let tail = &want[n * D..];
                let got_origin = origin.iter().map(|x| x.to_bits());
                r.converged
                    && got_origin.eq(tail[..D].iter().copied())
                    && r.iterations as u64 == tail[D]
                    && r.residual.to_bits() == tail[D + 1]
                    && view.global_ids[..view.owned]
                        .iter()
                        .zip(&out)
                        .all(|(&g, p)| {
                            let w = &want[g as usize * D..][..D];
                            p.iter().map(|x| x.to_bits()).eq(w.iter().copied())
                        })
            }
            Err(e) => {
                eprintln!("rank {rank}: quaternion {name} {label} depth {depth}: {e}");
                false
            }
        };
        let all_same = all(world, same);
        if rank == 0 {
            println!(
                "partitioned quaternion deformation {name} ({n} nodes, B = {}, E = {}), {label}, ghost depth {depth}, {size} rank(s): {} CG iterations: owned nodes, origin and report {}",
                bnd.nodes.len(),
                bnd.kinds.len(),
                want[n * D + D],
                if all_same { "bit-identical to serial on every rank" } else { "DIFFER" }
            );
        }
        ok &= all_same;
    }
    ok
}

/// What a bad case changes on the culprit rank.
type Spoil = fn(&mut LocalView<2>, &mut Share<2>);

/// Inconsistent boundaries and a bad partition on one rank (two ranks or more): every rank
/// must return the expected error, none may hang, and no rank may write `out`.
fn bad_inputs<C: Communicator>(world: &C, mesh: &Mesh<2>) -> bool {
    use PartitionFault::*;
    let (rank, size) = (world.rank() as u32, world.size() as usize);
    let n = mesh.node_count();
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, 10.0);
    let fixed = fixed_mask(n, &bnd);
    let owner = random_owner(n, size, 0xbad);
    let view = local_view(mesh, &fixed, &owner, (rank, size as u32), 1, 7);
    let base = share(&view, &bnd, &deformed);
    let last = (size - 1) as u32;
    let boundary_fault = |e: &Error, _: bool| {
        matches!(
            e,
            Error::BadPartition {
                fault: Boundary,
                ..
            }
        )
    };
    let own_then_others = |e: &Error, culprit: bool| match e {
        Error::InvalidParameter { .. } => culprit,
        Error::BadPartition {
            fault: OtherProcess,
            ..
        } => !culprit,
        _ => false,
    };
    let duplicate_then_others = |e: &Error, culprit: bool| match e {
        Error::BadPartition { fault, .. } => {
            *fault
                == if culprit {
                    DuplicateGlobalId
                } else {
                    OtherProcess
                }
        }
        _ => false,
    };
    type Expect<'e> = &'e dyn Fn(&Error, bool) -> bool;
    let cases: [(&str, u32, Spoil, Expect); 4] = [
        (
            "a boundary count that differs on one rank",
            last,
            |_, s| s.boundary_count += 1,
            &boundary_fault,
        ),
        (
            "a boundary element given twice",
            0,
            |_, s| {
                let (id, kind) = (s.ids[0], s.kinds[0]);
                let el = s.elements[..s.offsets[1] as usize].to_vec();
                s.ids.push(id);
                s.kinds.push(kind);
                s.elements.extend(el);
                s.offsets.push(s.elements.len() as u32);
            },
            &boundary_fault,
        ),
        (
            "an owned boundary node not listed",
            last,
            |_, s| {
                s.nodes.pop();
                s.positions.pop();
                s.deformed.pop();
            },
            &own_then_others,
        ),
        (
            "duplicate global ids on one rank",
            0,
            |v, _| v.global_ids[1] = v.global_ids[0],
            &duplicate_then_others,
        ),
    ];
    let mut ok = true;
    for (label, culprit, spoil, expect) in cases {
        let (mut v, mut s) = (view.clone(), base.clone());
        if rank == culprit {
            spoil(&mut v, &mut s);
        }
        let mut out = vec![[f64::NAN; 2]; v.owned];
        let got = partitioned(world, &v, &s, &mut out).err();
        let right = got.as_ref().is_some_and(|e| expect(e, rank == culprit))
            && out.iter().flatten().all(|x| x.is_nan());
        if !right {
            eprintln!("rank {rank}: quaternion, {label}: got {got:?}");
        }
        let all_right = all(world, right);
        if rank == 0 {
            println!(
                "partitioned quaternion deformation, bad input ({label}): {}",
                if all_right {
                    "rejected on every rank, nothing written"
                } else {
                    "NOT REJECTED AS EXPECTED"
                }
            );
        }
        ok &= all_right;
    }
    ok
}

/// All checks of the partitioned quaternion deformation; `true` when every one passed on
/// every rank.
pub fn run<C: Communicator>(world: &C, mesh2: &Mesh<2>, mesh3: &Mesh<3>) -> bool {
    let mut ok = mesh_cases(world, "2D NACA 2412 triangles", mesh2, 12.0);
    ok &= mesh_cases(world, "3D extruded prisms", mesh3, 8.0);
    if world.size() >= 2 {
        ok &= bad_inputs(world, mesh2);
    }
    ok
}
