//! `dk_partitioned_prolongator` (the distributed multigrid's fine level: MIS-2 aggregates and
//! the smoothed-aggregation prolongator rows) through its C callbacks, without MPI: each
//! "process" is a thread with its own local view (meshgen's `local_view`: random owners, ghost
//! layers, shuffled local numbering), the callbacks of `c_exchange.rs`. Every owned row equals
//! the serial `AmgHierarchy::setup_mis2` hierarchy's level-0 prolongator row bit for bit (its
//! coarse numbers named by the aggregates' roots), in 2D and 3D; bad partitions, short or
//! wrong buffers and NULL pointers give a typed status on every thread with every output
//! untouched.
#![allow(unsafe_code)] // calling the `extern "C"` functions and being called back is the point

#[path = "c_exchange.rs"]
mod c_exchange;
#[path = "../support/mod.rs"]
mod support;

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Barrier, Mutex};

use c_exchange::{c_cells, c_partition, halo, max, sum_words, Rank, Shared};
use deform_kernel::spring::{
    aggregate_mis2, batina_stiffness, mis2_scratch_len, AmgHierarchy, AmgOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_kernel_ffi::partition::dk_exchange;
use deform_kernel_ffi::partition_prolongator::{
    dk_partitioned_prolongator, dk_partitioned_prolongator_lens,
};
use deform_kernel_ffi::status::dk_status;
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};

/// A prolongator row: `(root global id, value bits)`.
type Row = Vec<(u64, u64)>;

/// The fixed mask of a mesh: every marker's nodes.
fn fixed_of<const D: usize>(mesh: &Mesh<D>) -> Vec<u8> {
    let mut fixed = vec![0u8; mesh.node_count()];
    for m in &mesh.markers {
        m.node_list.iter().for_each(|&i| fixed[i as usize] = 1);
    }
    fixed
}

/// The serial MIS-2 hierarchy's fine prolongator (Batina `p = 1`, no face diagonals), every
/// node's row with its coarse numbers named by the aggregates' roots, and the coarse size.
fn serial<const D: usize>(mesh: &Mesh<D>) -> (Vec<Row>, usize) {
    let n = mesh.node_count();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let g = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let fixed = fixed_of(mesh);
    let mut agg = vec![0u64; n];
    let mut words = vec![0u64; mis2_scratch_len(n)];
    aggregate_mis2(&g, &fixed, &mut agg, &mut words).unwrap();
    let roots: Vec<u64> = (0..n as u64).filter(|&i| agg[i as usize] == i).collect();
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(g, &k, &fixed, &mut ss).unwrap();
    let opts = AmgOptions {
        max_coarse: 16,
        ..AmgOptions::default()
    };
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    let mut mwork = vec![0u64; AmgHierarchy::mis2_work_len(&sys)];
    let sizes = AmgHierarchy::setup_len_mis2(&sys, &opts, &mut work, &mut mwork).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0; sizes.values];
    let (w, m, i, v) = (&mut work, &mut mwork, &mut index, &mut values);
    let h = AmgHierarchy::setup_mis2(&sys, &opts, w, m, i, v).unwrap();
    assert!(h.levels() >= 2);
    assert_eq!(h.level_size(1), roots.len());
    let rows = (0..n)
        .map(|i| {
            let (c, v) = h.prolongator_row(0, i);
            let row = c.iter().zip(v);
            row.map(|(&c, &v)| (roots[c as usize], v.to_bits()))
                .collect()
        })
        .collect();
    (rows, roots.len())
}

/// The knobs of one thread's C call (all off: a good call).
#[derive(Clone, Copy, Default)]
struct Knobs {
    /// Entries taken off `values`.
    values_short: usize,
    /// Entries taken off `id_scratch`.
    ids_short: usize,
    /// One more entry of `offsets`.
    offsets_long: bool,
    /// `counts_out` passed as NULL.
    counts_null: bool,
    /// The dimension passed (0: the mesh's).
    dim: u32,
}

/// What one thread got: status, its owned rows by global id, the counts, and whether every
/// output was left as it was.
struct Got {
    status: dk_status,
    rows: Vec<(u64, Row)>,
    counts: [usize; 2],
    untouched: bool,
}

const SENTINEL: f64 = -7.25e11;
const ID_SENTINEL: u64 = 0xdead_beef;

/// One thread's C calls on its view.
fn prolongator<const D: usize>(v: &LocalView<D>, k: Knobs, me: &mut Rank<'_>) -> Got {
    let (part, cells) = (c_partition(v), c_cells(v));
    let ex = dk_exchange {
        user: me as *mut Rank as *mut c_void,
        sum_words: Some(sum_words),
        max: Some(max),
        halo: Some(halo),
    };
    let pts = v.points.as_flattened();
    let mut lens = [0usize; 4];
    // SAFETY: every pointer is live for its length; `ex.user` outlives the call.
    let st = unsafe { dk_partitioned_prolongator_lens(&part, &cells, false, lens.as_mut_ptr()) };
    assert_eq!(st, dk_status::DK_OK);
    let mut scratch = vec![0.0; lens[0]];
    let mut index = vec![0u32; lens[1]];
    let mut ids = vec![0u64; lens[2] - k.ids_short];
    let mut offsets = vec![u32::MAX; v.owned + 1 + usize::from(k.offsets_long)];
    let mut columns = vec![ID_SENTINEL; lens[3]];
    let mut values = vec![SENTINEL; lens[3] - k.values_short];
    let mut counts = [usize::MAX; 2];
    let counts_ptr = if k.counts_null {
        std::ptr::null_mut()
    } else {
        counts.as_mut_ptr()
    };
    let dim = if k.dim == 0 { D as u32 } else { k.dim };
    // SAFETY: as above.
    let status = unsafe {
        dk_partitioned_prolongator(
            &part,
            &cells,
            false,
            pts.as_ptr(),
            pts.len(),
            dim,
            1.0,
            v.fixed.as_ptr(),
            v.fixed.len(),
            scratch.as_mut_ptr(),
            scratch.len(),
            index.as_mut_ptr(),
            index.len(),
            ids.as_mut_ptr(),
            ids.len(),
            &ex,
            offsets.as_mut_ptr(),
            offsets.len(),
            columns.as_mut_ptr(),
            columns.len(),
            values.as_mut_ptr(),
            values.len(),
            counts_ptr,
        )
    };
    let untouched = offsets.iter().all(|&o| o == u32::MAX)
        && columns.iter().all(|&c| c == ID_SENTINEL)
        && values.iter().all(|&x| x == SENTINEL)
        && counts == [usize::MAX; 2];
    let rows = if status == dk_status::DK_OK {
        (0..v.owned)
            .map(|i| {
                let (a, b) = (offsets[i] as usize, offsets[i + 1] as usize);
                let row = (a..b).map(|q| (columns[q], values[q].to_bits())).collect();
                (v.global_ids[i], row)
            })
            .collect()
    } else {
        Vec::new()
    };
    Got {
        status,
        rows,
        counts,
        untouched,
    }
}

/// A change to one thread's view and knobs before its call.
type Spoil<'a, const D: usize> = &'a (dyn Fn(u32, &mut LocalView<D>, &mut Knobs) + Sync);

/// One run on `size` threads: each cuts its view (random owners, ghost `depth`), lets `spoil`
/// change it and its knobs, and returns what it got. `fail_max`: a rank and the `max` call at
/// which its callback reports a failure.
fn run_ranks<const D: usize>(
    mesh: &Mesh<D>,
    size: u32,
    depth: usize,
    fail_max: Option<(u32, usize)>,
    spoil: Spoil<'_, D>,
) -> Vec<Got> {
    let n = mesh.node_count();
    let fixed = fixed_of(mesh);
    let owner = random_owner(n, size as usize, 0x7a + u64::from(size));
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
                        local_view(mesh, fixed, owner, (rank, size), depth, 9 + rank as u64);
                    let mut k = Knobs::default();
                    spoil(rank, &mut v, &mut k);
                    let mut me = Rank {
                        rank,
                        shared,
                        fail_max_at: fail_max.filter(|f| f.0 == rank).map(|f| f.1),
                        calls: 0,
                    };
                    prolongator(&v, k, &mut me)
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// Rank counts `sizes` and ghost depths 1–2: every owned row, once over the ranks, is the
/// serial row; the counts are the entries written and the serial coarse size.
fn rows_equal_serial<const D: usize>(mesh: &Mesh<D>, sizes: &[u32]) {
    let (want, coarse) = serial(mesh);
    // Not a trivial operator: smoothed rows reach beyond their own aggregate.
    assert!(want.iter().any(|r| r.len() > 1));
    for &size in sizes {
        for depth in [1, 2] {
            let mut seen = 0;
            for (rank, got) in run_ranks(mesh, size, depth, None, &|_, _, _| {})
                .into_iter()
                .enumerate()
            {
                let what = format!("{D}D, {size} threads, depth {depth}, rank {rank}");
                assert_eq!(got.status, dk_status::DK_OK, "{what}");
                let entries: usize = got.rows.iter().map(|(_, r)| r.len()).sum();
                assert_eq!(got.counts, [entries, coarse], "{what}: counts");
                for (g, row) in got.rows {
                    assert_eq!(row, want[g as usize], "{what}: node {g}");
                    seen += 1;
                }
            }
            assert_eq!(seen, mesh.node_count(), "{size} threads: every row once");
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
fn threads_give_the_serial_rows_2d() {
    rows_equal_serial(&mesh_2d(32, 8), &[1, 2, 3, 4]);
}

#[test]
fn threads_give_the_serial_rows_3d() {
    let mesh = extrude(&mesh_2d(16, 5), 1.0, 2).unwrap();
    rows_equal_serial(&mesh, &[1, 3]);
}

/// What a bad case changes on the culprit's rank.
type Bad = fn(&mut LocalView<2>, &mut Knobs);

/// A bad case: what, the culprit, its spoil, a failing `max` at this call, the culprit's
/// status and the others'.
type Case = (&'static str, u32, Bad, Option<usize>, dk_status, dk_status);

#[test]
fn bad_input_fails_on_every_rank_with_nothing_written() {
    use dk_status::{
        DK_ERR_BAD_PARTITION as BAD, DK_ERR_BUFFER_TOO_SMALL as SHORT, DK_ERR_EXCHANGE as EXCHANGE,
        DK_ERR_INVALID_PARAMETER as INVALID, DK_ERR_LENGTH_MISMATCH as LENGTH,
        DK_ERR_NULL_POINTER as NULL,
    };
    let mesh = mesh_2d(24, 6);
    let cases: [Case; 9] = [
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
            "a fixed flag that disagrees with the owner's",
            0,
            |v, _| {
                let ghost = v.owned;
                v.fixed[ghost] ^= 1;
            },
            None,
            BAD,
            BAD,
        ),
        (
            "short values",
            1,
            |_, k| k.values_short = 1,
            None,
            SHORT,
            BAD,
        ),
        (
            "short id scratch",
            2,
            |_, k| k.ids_short = 1,
            None,
            SHORT,
            BAD,
        ),
        (
            "offsets one too long",
            0,
            |_, k| k.offsets_long = true,
            None,
            LENGTH,
            BAD,
        ),
        (
            "a NULL counts_out",
            1,
            |_, k| k.counts_null = true,
            None,
            NULL,
            BAD,
        ),
        ("dimension 4", 2, |_, k| k.dim = 4, None, INVALID, BAD),
        (
            "a failing max callback",
            1,
            |_, _| {},
            Some(1),
            EXCHANGE,
            EXCHANGE,
        ),
    ];
    for (what, culprit, spoil, fail_at, own, others) in cases {
        let fail = fail_at.map(|c| (culprit, c));
        let results = run_ranks(&mesh, 3, 1, fail, &|rank, v, k| {
            if rank == culprit {
                spoil(v, k);
            }
        });
        for (rank, got) in results.iter().enumerate() {
            let want = if rank as u32 == culprit { own } else { others };
            assert_eq!(got.status, want, "{what}: rank {rank}");
            assert!(got.untouched, "{what}: rank {rank} wrote an output");
        }
    }
}
