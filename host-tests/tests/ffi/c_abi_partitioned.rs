//! `dk_partitioned_spring_solve` through its C callbacks, without MPI: each "process" is a
//! thread with its own local view (meshgen's `local_view`: owned nodes, ghost layers,
//! shuffled local numbering, local cells, the lists), and the callbacks exchange through
//! shared memory and a barrier. The owned values, the iterations and the residual equal the
//! serial `dk_spring_solve_linear` (CG + Jacobi) bit for bit; bad partitions and failing
//! callbacks give the same typed status on every thread, the values untouched. The MPI
//! version of the same (ffi/examples/mpi_partitioned.c) runs in `cargo xtask ci --step mpi`.
#![allow(unsafe_code)] // calling the `extern "C"` functions and being called back is the point

#[path = "c_exchange.rs"]
mod c_exchange;

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Barrier, Mutex};

use c_exchange::{c_cells, c_partition, halo, max, sum_words, Rank, Shared};

use deform_kernel_ffi::graph::{dk_cells, dk_graph, dk_graph_from_cells, dk_graph_from_cells_len};
use deform_kernel_ffi::partition::{
    dk_exchange, dk_partitioned_spring_scratch_len, dk_partitioned_spring_solve,
};
use deform_kernel_ffi::spring::{
    dk_spring_batina_stiffness, dk_spring_solve_linear, dk_spring_solve_linear_scratch_len,
    dk_spring_solve_options, dk_spring_solve_options_default, dk_spring_solve_report,
    dk_spring_system,
};
use deform_kernel_ffi::status::{dk_status, dk_status_str};
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{naca_triangulated, AirfoilGrid, Mesh};

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

/// Boundary displacements at the fixed nodes (a rotation-like field), 0 elsewhere.
fn initial(points: &[[f64; 2]], fixed: &[u8]) -> Vec<f64> {
    points
        .iter()
        .zip(fixed)
        .flat_map(|(p, &f)| {
            if f == 0 {
                [0.0, 0.0]
            } else {
                [-0.05 * p[1] + 0.01 * p[0] * p[1], 0.05 * p[0]]
            }
        })
        .collect()
}

/// The serial C solve on the whole mesh: values and report.
fn serial(mesh: &Mesh<2>) -> (Vec<f64>, dk_spring_solve_report) {
    let n = mesh.node_count();
    let fixed = mesh.boundary_mask();
    let cells = dk_cells {
        offsets: mesh.offsets.as_ptr(),
        offsets_len: mesh.offsets.len(),
        nodes: mesh.nodes.as_ptr(),
        nodes_len: mesh.nodes.len(),
        kinds: mesh.kinds.as_ptr(),
        kinds_len: mesh.kinds.len(),
    };
    let (mut tl, mut used) = (0usize, 0usize);
    let mut offsets = vec![0u32; n + 1];
    let none = std::ptr::null_mut();
    // SAFETY: every pointer is live for its length.
    unsafe {
        assert_eq!(
            dk_graph_from_cells_len(n, &cells, 0, none, 0, false, &mut tl),
            dk_status::DK_OK
        );
        let mut targets = vec![0u32; tl];
        let s = dk_graph_from_cells(
            n,
            &cells,
            0,
            none,
            0,
            false,
            offsets.as_mut_ptr(),
            n + 1,
            targets.as_mut_ptr(),
            tl,
            &mut used,
        );
        assert_eq!(s, dk_status::DK_OK);
        let graph = dk_graph {
            offsets: offsets.as_ptr(),
            offsets_len: n + 1,
            targets: targets.as_ptr(),
            targets_len: used,
        };
        let mut k = vec![0.0; used];
        let pts = mesh.points.as_flattened();
        let s = dk_spring_batina_stiffness(
            &graph,
            pts.as_ptr(),
            pts.len(),
            2,
            1.0,
            k.as_mut_ptr(),
            used,
        );
        assert_eq!(s, dk_status::DK_OK);
        let sys = dk_spring_system {
            graph,
            stiffness: k.as_ptr(),
            stiffness_len: used,
            fixed: fixed.as_ptr(),
            fixed_len: n,
        };
        let o = options();
        let mut sl = 0;
        assert_eq!(
            dk_spring_solve_linear_scratch_len(n, 2, &o, &mut sl),
            dk_status::DK_OK
        );
        let mut x = initial(&mesh.points, &fixed);
        let (mut scratch, mut idx) = (vec![0.0; sl], vec![0u32; n]);
        let mut report = std::mem::zeroed();
        let s = dk_spring_solve_linear(
            &sys,
            &o,
            2,
            x.as_mut_ptr(),
            x.len(),
            scratch.as_mut_ptr(),
            sl,
            idx.as_mut_ptr(),
            n,
            &mut report,
        );
        assert_eq!(s, dk_status::DK_OK);
        (x, report)
    }
}

/// One thread's solve on its view: status, values, report.
fn solve(
    v: &LocalView<2>,
    me: &mut Rank<'_>,
) -> (dk_status, Vec<f64>, Vec<f64>, dk_spring_solve_report) {
    let part = c_partition(v);
    let cells = c_cells(v);
    let ex = dk_exchange {
        user: me as *mut Rank as *mut c_void,
        sum_words: Some(sum_words),
        max: Some(max),
        halo: Some(halo),
    };
    let (mut sl, mut il) = (0, 0);
    let o = options();
    let mut x = initial(&v.points, &v.fixed);
    x[2 * v.owned..].fill(1e300); // ghosts: anything
    let before = x.clone();
    let pts = v.points.as_flattened();
    // SAFETY: every pointer is live for its length; `ex.user` outlives the call.
    unsafe {
        let s = dk_partitioned_spring_scratch_len(&part, &cells, false, 2, &mut sl, &mut il);
        assert_eq!(s, dk_status::DK_OK);
        let (mut scratch, mut idx) = (vec![0.0; sl], vec![0u32; il]);
        let mut report = std::mem::zeroed();
        let s = dk_partitioned_spring_solve(
            &part,
            &cells,
            false,
            pts.as_ptr(),
            pts.len(),
            2,
            1.0,
            v.fixed.as_ptr(),
            v.fixed.len(),
            &o,
            2,
            x.as_mut_ptr(),
            x.len(),
            scratch.as_mut_ptr(),
            sl,
            idx.as_mut_ptr(),
            il,
            &ex,
            &mut report,
        );
        (s, x, before, report)
    }
}

/// What a thread checks of its result: its view, status, values, values before, report.
type Check<'a> =
    dyn Fn(&LocalView<2>, dk_status, &[f64], &[f64], dk_spring_solve_report) + Sync + 'a;

/// Runs `size` threads, each on its view (spoiled by `spoil` first) and returning what
/// `check` says of its result.
fn run_ranks(
    mesh: &Mesh<2>,
    size: u32,
    depth: usize,
    fail_max: Option<(u32, usize)>,
    spoil: &(dyn Fn(&mut LocalView<2>) + Sync),
    check: &Check<'_>,
) {
    let fixed = mesh.boundary_mask();
    let owner = random_owner(mesh.node_count(), size as usize, 0x5eed + u64::from(size));
    let shared = Shared {
        barrier: Barrier::new(size as usize),
        slots: Mutex::new(vec![Vec::new(); size as usize]),
        mail: Mutex::new(HashMap::new()),
    };
    std::thread::scope(|s| {
        for rank in 0..size {
            let (shared, owner, fixed) = (&shared, &owner, &fixed);
            s.spawn(move || {
                let mut v = local_view(
                    mesh,
                    fixed,
                    owner,
                    (rank, size),
                    depth,
                    11 + u64::from(rank),
                );
                spoil(&mut v);
                let mut me = Rank {
                    rank,
                    shared,
                    fail_max_at: fail_max.filter(|f| f.0 == rank).map(|f| f.1),
                    calls: 0,
                };
                let (st, x, before, report) = solve(&v, &mut me);
                check(&v, st, &x, &before, report);
            });
        }
    });
}

fn mesh() -> Mesh<2> {
    let grid = AirfoilGrid {
        surface_points: 48,
        radial_points: 12,
        ..AirfoilGrid::default()
    };
    naca_triangulated(&grid).expect("mesh")
}

#[test]
fn threads_give_the_serial_bits() {
    let mesh = mesh();
    let (want, sr) = serial(&mesh);
    for size in [1, 2, 3, 4] {
        for depth in [1, 2] {
            run_ranks(&mesh, size, depth, None, &|_| {}, &|v, st, x, _, r| {
                assert_eq!(st, dk_status::DK_OK, "rank {} of {size}", v.rank);
                assert_eq!((r.iterations, r.converged), (sr.iterations, sr.converged));
                assert_eq!(r.residual.to_bits(), sr.residual.to_bits());
                for (l, &g) in v.global_ids.iter().enumerate() {
                    for c in 0..2 {
                        let (a, b) = (x[2 * l + c], want[2 * g as usize + c]);
                        assert_eq!(a.to_bits(), b.to_bits(), "rank {} node {g}", v.rank);
                    }
                }
            });
        }
    }
}

/// `want` on every rank, values and report untouched.
fn rejected(
    want: dk_status,
) -> impl Fn(&LocalView<2>, dk_status, &[f64], &[f64], dk_spring_solve_report) + Sync {
    rejected_at(0, want, want)
}

/// `own` on rank `culprit`, `others` elsewhere, values and report untouched.
fn rejected_at(
    culprit: u32,
    own: dk_status,
    others: dk_status,
) -> impl Fn(&LocalView<2>, dk_status, &[f64], &[f64], dk_spring_solve_report) + Sync {
    move |v, st, x, before, r| {
        let want = if v.rank == culprit { own } else { others };
        assert_eq!(st, want, "rank {}", v.rank);
        assert!(x
            .iter()
            .zip(before)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(r.iterations, 0);
    }
}

/// What a bad case changes in the culprit's view.
type Spoil = fn(&mut LocalView<2>);

#[test]
fn bad_partitions_fail_on_every_rank() {
    use dk_status::{DK_ERR_BAD_PARTITION as BAD, DK_ERR_LENGTH_MISMATCH as LENGTH};
    let mesh = mesh();
    // (ranks, culprit, its fault, its status); the others report BAD.
    let cases: [(u32, u32, Spoil, dk_status); 5] = [
        (3, 1, |v| v.global_ids[1] = v.global_ids[0], BAD), // a duplicate global id
        (
            3,
            2,
            |v| {
                // A ghost in no receive list.
                v.recv.pop();
                *v.recv_offsets.last_mut().unwrap() -= 1;
            },
            BAD,
        ),
        (2, 0, |v| v.owned = 0, BAD), // no owned node
        // A short fixed mask: found by the kernel's row check, its own status there.
        (2, 1, |v| v.fixed.truncate(v.fixed.len() - 1), LENGTH),
        // One more global id than values: found before any kernel call (the first one-word
        // agreement), its own status there.
        (3, 2, |v| v.global_ids.push(0), LENGTH),
    ];
    for (size, culprit, fault, own) in cases {
        let spoil = |v: &mut LocalView<2>| {
            if v.rank == culprit {
                fault(v);
            }
        };
        run_ranks(
            &mesh,
            size,
            1,
            None,
            &spoil,
            &rejected_at(culprit, own, BAD),
        );
    }
}

#[test]
fn a_failing_callback_fails_every_rank() {
    let mesh = mesh();
    for (rank, at) in [(0, 1), (2, 3), (1, 9)] {
        run_ranks(
            &mesh,
            3,
            1,
            Some((rank, at)),
            &|_| {},
            &rejected(dk_status::DK_ERR_EXCHANGE),
        );
    }
    // SAFETY: a static string.
    let text =
        unsafe { std::ffi::CStr::from_ptr(dk_status_str(dk_status::DK_ERR_EXCHANGE as i32)) };
    assert!(text.to_str().unwrap().contains("exchange"));
}
