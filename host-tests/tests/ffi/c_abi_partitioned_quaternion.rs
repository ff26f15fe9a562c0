//! `dk_partitioned_deform_spring` (the quaternion deformation with spring propagation on
//! distributed data) through its C callbacks, without MPI: each "process" is a thread with its
//! own local view (meshgen's `local_view`: random owners, ghost layers, shuffled local
//! numbering), the callbacks of `c_exchange.rs`. Every owned node, the origin and the report
//! equal the serial `deform_spring_with` (CG + Jacobi) bit for bit, in 2D and 3D; bad
//! partitions and inconsistent boundary lists give a typed status on every thread with `out`,
//! the origin and the report untouched. The MPI version runs in `cargo xtask ci --step mpi`
//! (ffi/examples/mpi_partitioned.c).
#![allow(unsafe_code)] // calling the `extern "C"` functions and being called back is the point

#[path = "c_exchange.rs"]
mod c_exchange;
#[path = "../support/mod.rs"]
mod support;

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Barrier, Mutex};

use c_exchange::{c_cells, c_partition, halo, max, sum_words, Rank, Shared};
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_spring_scratch_len, deform_spring_with, propagate_spring_with_scratch_len,
    BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph};
use deform_kernel_ffi::deformation::{DK_ROTATIONS_PER_NODE, DK_ROTATIONS_SHAPE};
use deform_kernel_ffi::graph::dk_cells;
use deform_kernel_ffi::partition::dk_exchange;
use deform_kernel_ffi::partition_quaternion::{
    dk_partitioned_deform_spring, dk_partitioned_deform_spring_lens, dk_partitioned_motion,
};
use deform_kernel_ffi::spring::{
    dk_spring_solve_options, dk_spring_solve_options_default, dk_spring_solve_report,
};
use deform_kernel_ffi::status::dk_status;
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};
use support::partition_boundary::{self, boundary, moved, Bnd};

/// The C options (CG + Jacobi, the defaults) and the same as the kernel's stopping rule.
fn options() -> dk_spring_solve_options {
    let mut o = std::mem::MaybeUninit::uninit();
    // SAFETY: one writable struct.
    assert_eq!(
        unsafe { dk_spring_solve_options_default(o.as_mut_ptr()) },
        dk_status::DK_OK
    );
    // SAFETY: written on DK_OK.
    unsafe { o.assume_init() }
}

fn stopping() -> SolveOptions<f64> {
    let o = options();
    SolveOptions {
        residual_tol: o.residual_tol,
        max_iterations: o.max_iterations,
        update_tol: o.update_tol,
    }
}

/// The serial result: deformed points, origin, iterations and residual bits.
type Serial<const D: usize> = (Vec<[f64; D]>, [f64; D], usize, u64);

/// The serial `deform_spring_with` (CG + Jacobi, Batina `p = 1`, no face diagonals).
fn serial<const D: usize>(mesh: &Mesh<D>, bnd: &Bnd, deformed: &[[f64; D]]) -> Serial<D> {
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut ss).unwrap();
    let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds).unwrap();
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
    let (origin, rep) = deform_spring_with(
        &mesh.points,
        &motion,
        &sys,
        solver,
        &stopping(),
        &mut t,
        &mut q,
        &mut s,
        &mut values,
        &mut out,
    )
    .unwrap();
    assert!(rep.converged);
    (out, origin, rep.iterations, rep.residual.to_bits())
}

/// One thread's share of the boundary: its owned boundary nodes (local numbers) with their
/// positions and deformed points (flat), and the elements whose first node it owns.
#[derive(Clone)]
struct Share {
    nodes: Vec<u32>,
    positions: Vec<u32>,
    deformed: Vec<f64>,
    ids: Vec<u32>,
    offsets: Vec<u32>,
    elements: Vec<u32>,
    kinds: Vec<u8>,
    boundary_count: usize,
    element_count: usize,
    rotation_source: u32,
}

fn share<const D: usize>(v: &LocalView<D>, bnd: &Bnd, deformed: &[[f64; D]]) -> Share {
    let s = partition_boundary::share(v, bnd, deformed, |_, owns_first| owns_first);
    Share {
        nodes: s.nodes,
        positions: s.positions,
        deformed: s.deformed.concat(),
        ids: s.ids,
        offsets: s.offsets,
        elements: s.elements,
        kinds: s.kinds,
        boundary_count: bnd.nodes.len(),
        element_count: bnd.kinds.len(),
        rotation_source: DK_ROTATIONS_SHAPE,
    }
}

/// What one thread got: status, `out` (owned nodes, flat), origin, report, and whether
/// `out`, the origin and the report were left as they were.
struct Got {
    status: dk_status,
    out: Vec<f64>,
    origin: Vec<f64>,
    report: dk_spring_solve_report,
    untouched: bool,
}

const SENTINEL: f64 = -7.25e11;

/// One thread's C calls on its view and share.
fn deform<const D: usize>(v: &LocalView<D>, s: &Share, me: &mut Rank<'_>) -> Got {
    let part = c_partition(v);
    let cells = c_cells(v);
    let motion = dk_partitioned_motion {
        nodes: s.nodes.as_ptr(),
        nodes_len: s.nodes.len(),
        positions: s.positions.as_ptr(),
        positions_len: s.positions.len(),
        deformed: s.deformed.as_ptr(),
        deformed_len: s.deformed.len(),
        boundary_count: s.boundary_count,
        element_ids: s.ids.as_ptr(),
        element_ids_len: s.ids.len(),
        elements: dk_cells {
            offsets: s.offsets.as_ptr(),
            offsets_len: s.offsets.len(),
            nodes: s.elements.as_ptr(),
            nodes_len: s.elements.len(),
            kinds: s.kinds.as_ptr(),
            kinds_len: s.kinds.len(),
        },
        element_count: s.element_count,
        rigid_rotation: [1.0, 0.0, 0.0, 0.0],
        origin: [0.0; 3],
        rotation_source: s.rotation_source,
        has_origin: 0,
    };
    let ex = dk_exchange {
        user: me as *mut Rank as *mut c_void,
        sum_words: Some(sum_words),
        max: Some(max),
        halo: Some(halo),
    };
    let o = options();
    let pts = v.points.as_flattened();
    let mut lens = [0usize; 4];
    let mut out = vec![SENTINEL; v.owned * D];
    let mut origin = vec![SENTINEL; D];
    // SAFETY: every pointer is live for its length; `ex.user` outlives the call.
    unsafe {
        let (b, e) = (s.boundary_count, s.element_count);
        let st = dk_partitioned_deform_spring_lens(
            &part,
            &cells,
            false,
            D as u32,
            b,
            e,
            lens.as_mut_ptr(),
        );
        assert_eq!(st, dk_status::DK_OK);
        let mut scratch = vec![0.0; lens[0]];
        let mut index = vec![0u32; lens[1]];
        let mut words = vec![0i64; lens[2]];
        let mut kinds = vec![0u8; lens[3]];
        let mut report: dk_spring_solve_report = std::mem::zeroed();
        let status = dk_partitioned_deform_spring(
            &part,
            &cells,
            false,
            pts.as_ptr(),
            pts.len(),
            D as u32,
            1.0,
            v.fixed.as_ptr(),
            v.fixed.len(),
            &motion,
            &o,
            scratch.as_mut_ptr(),
            scratch.len(),
            index.as_mut_ptr(),
            index.len(),
            words.as_mut_ptr(),
            words.len(),
            kinds.as_mut_ptr(),
            kinds.len(),
            &ex,
            out.as_mut_ptr(),
            out.len(),
            origin.as_mut_ptr(),
            origin.len(),
            &mut report,
        );
        let untouched = out.iter().chain(&origin).all(|&x| x == SENTINEL)
            && report.iterations == 0
            && report.residual.to_bits() == 0;
        Got {
            status,
            out,
            origin,
            report,
            untouched,
        }
    }
}

/// One run on `size` threads: each cuts its view (random owners, ghost `depth`), takes its
/// share, lets `spoil` change them, and returns its view's global ids with what it got.
/// `fail_max`: a rank and the `max` call at which its callback reports a failure.
fn run_ranks<const D: usize>(
    mesh: &Mesh<D>,
    bnd: &Bnd,
    deformed: &[[f64; D]],
    size: u32,
    depth: usize,
    fail_max: Option<(u32, usize)>,
    spoil: &(dyn Fn(u32, &mut LocalView<D>, &mut Share) + Sync),
) -> Vec<(Vec<u64>, Got)> {
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let owner = random_owner(n, size as usize, 0x9e37 + u64::from(size));
    let shared = Shared {
        barrier: Barrier::new(size as usize),
        slots: Mutex::new(vec![Vec::new(); size as usize]),
        mail: Mutex::new(HashMap::new()),
    };
    std::thread::scope(|sc| {
        let handles: Vec<_> = (0..size)
            .map(|rank| {
                let (shared, owner, fixed) = (&shared, &owner, &fixed);
                sc.spawn(move || {
                    let mut v =
                        local_view(mesh, fixed, owner, (rank, size), depth, 3 + rank as u64);
                    let mut s = share(&v, bnd, deformed);
                    spoil(rank, &mut v, &mut s);
                    let mut me = Rank {
                        rank,
                        shared,
                        fail_max_at: fail_max.filter(|f| f.0 == rank).map(|f| f.1),
                        calls: 0,
                    };
                    let got = deform(&v, &s, &mut me);
                    (v.global_ids, got)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Every rank count 1–4 and ghost depth 1–2: the owned nodes, the origin and the report are
/// the serial bits.
fn bits_equal_serial<const D: usize>(mesh: &Mesh<D>, deg: f64) {
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, deg);
    let (want, origin, iterations, residual) = serial(mesh, &bnd, &deformed);
    for size in 1..=4 {
        for depth in [1, 2] {
            let results = run_ranks(mesh, &bnd, &deformed, size, depth, None, &|_, _, _| {});
            for (rank, (ids, got)) in results.iter().enumerate() {
                let what = format!("{D}D, {size} threads, depth {depth}, rank {rank}");
                assert_eq!(got.status, dk_status::DK_OK, "{what}");
                assert_eq!(got.report.iterations, iterations, "{what}");
                assert_eq!(got.report.residual.to_bits(), residual, "{what}");
                assert!(got.report.converged, "{what}");
                let o: Vec<u64> = got.origin.iter().map(|x| x.to_bits()).collect();
                assert_eq!(o, origin.map(f64::to_bits), "{what}: origin");
                for (p, &g) in got.out.chunks_exact(D).zip(ids) {
                    let w = want[g as usize].map(f64::to_bits);
                    let p: Vec<u64> = p.iter().map(|x| x.to_bits()).collect();
                    assert_eq!(p, w, "{what}: node {g}");
                }
            }
        }
    }
}

#[test]
fn threads_give_the_serial_bits_2d() {
    let mesh = naca_triangulated(&AirfoilGrid {
        surface_points: 32,
        radial_points: 8,
        ..AirfoilGrid::default()
    })
    .unwrap();
    bits_equal_serial(&mesh, 12.0);
}

#[test]
fn threads_give_the_serial_bits_3d() {
    let mesh2 = naca_triangulated(&AirfoilGrid {
        surface_points: 16,
        radial_points: 5,
        ..AirfoilGrid::default()
    })
    .unwrap();
    let mesh = extrude(&mesh2, 1.0, 2).unwrap();
    bits_equal_serial(&mesh, 8.0);
}

/// What a bad case changes on the culprit's rank.
type Spoil = fn(&mut LocalView<2>, &mut Share);

/// A bad case: what, the culprit, its spoil, a failing `max` at this call, the culprit's
/// status and the others'.
type Case = (
    &'static str,
    u32,
    Spoil,
    Option<usize>,
    dk_status,
    dk_status,
);

#[test]
fn bad_partitions_and_boundaries_fail_on_every_rank() {
    use dk_status::{
        DK_ERR_BAD_PARTITION as BAD, DK_ERR_EXCHANGE as EXCHANGE,
        DK_ERR_INVALID_PARAMETER as INVALID,
    };
    let mesh = naca_triangulated(&AirfoilGrid {
        surface_points: 24,
        radial_points: 6,
        ..AirfoilGrid::default()
    })
    .unwrap();
    let bnd = boundary(&mesh);
    let deformed = moved(&mesh, &bnd.nodes, 10.0);
    let none: Spoil = |_, _| {};
    let cases: [Case; 8] = [
        (
            "duplicate global ids",
            1,
            |v, _| v.global_ids[1] = v.global_ids[0],
            None,
            BAD,
            BAD,
        ),
        (
            "a ghost in no receive list",
            2,
            |v, _| {
                v.recv.pop();
                *v.recv_offsets.last_mut().unwrap() -= 1;
            },
            None,
            BAD,
            BAD,
        ),
        (
            "another boundary count on one rank",
            2,
            |_, s| s.boundary_count += 1,
            None,
            BAD,
            BAD,
        ),
        (
            "another element count on one rank",
            0,
            |_, s| s.element_count += 1,
            None,
            BAD,
            BAD,
        ),
        (
            "two ranks give one boundary position",
            0,
            |_, s| s.positions[0] = s.positions[1],
            None,
            BAD,
            BAD,
        ),
        (
            "an owned fixed node not listed",
            1,
            |_, s| {
                s.nodes.pop();
                s.positions.pop();
                s.deformed.truncate(2 * s.nodes.len());
            },
            None,
            INVALID,
            BAD,
        ),
        (
            "per-node rotations (dk_partitioned_deform_idw only)",
            2,
            |_, s| s.rotation_source = DK_ROTATIONS_PER_NODE,
            None,
            INVALID,
            BAD,
        ),
        (
            "a failing max callback",
            1,
            none,
            Some(2),
            EXCHANGE,
            EXCHANGE,
        ),
    ];
    for (what, culprit, spoil, fail_at, own, others) in cases {
        let fail = fail_at.map(|c| (culprit, c));
        let results = run_ranks(&mesh, &bnd, &deformed, 3, 1, fail, &|rank, v, s| {
            if rank == culprit {
                spoil(v, s);
            }
        });
        for (rank, (_, got)) in results.iter().enumerate() {
            let want = if rank as u32 == culprit { own } else { others };
            assert_eq!(got.status, want, "{what}: rank {rank}");
            assert!(got.untouched, "{what}: rank {rank} wrote an output");
        }
    }
}
