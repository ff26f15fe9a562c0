//! `dk_partitioned_deform_idw` (the quaternion deformation with inverse-distance propagation on
//! distributed data) through its C callbacks, without MPI: each "process" is a thread with its
//! own local view (meshgen's `local_view`: random owners, ghost layers, shuffled local
//! numbering), the callbacks of `c_exchange.rs`. Every owned node and the origin equal the
//! serial `deform_idw` bit for bit, in 2D and 3D, with rotations from the shape, one rigid
//! rotation or per node; bad partitions, inconsistent boundary lists, short buffers and NULL
//! pointers give a typed status on every thread with `out` and the origin untouched.
#![allow(unsafe_code)] // calling the `extern "C"` functions and being called back is the point

#[path = "c_exchange.rs"]
mod c_exchange;
#[path = "../support/mod.rs"]
mod support;

use std::collections::HashMap;
use std::ffi::c_void;
use std::sync::{Barrier, Mutex};

use c_exchange::{c_partition, halo, max, sum_words, Rank, Shared};
use deform_kernel::quat::Quat;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::Cells;
use deform_kernel_ffi::deformation::{
    DK_ROTATIONS_PER_NODE, DK_ROTATIONS_RIGID, DK_ROTATIONS_SHAPE,
};
use deform_kernel_ffi::graph::dk_cells;
use deform_kernel_ffi::partition::dk_exchange;
use deform_kernel_ffi::partition_idw::{dk_partitioned_deform_idw, dk_partitioned_deform_idw_lens};
use deform_kernel_ffi::partition_quaternion::dk_partitioned_motion;
use deform_kernel_ffi::status::dk_status;
use deform_meshgen::partition::{local_view, random_owner, LocalView};
use deform_meshgen::{extrude, naca_triangulated, AirfoilGrid, Mesh};
use support::partition_boundary::{self, boundary, moved, per_node_rotations, Bnd};

/// The rotation sources under test, with the exponent each runs with (`p = 2` takes the serial
/// code's path without `powf`, the others the `powf` path).
#[derive(Clone, Copy, Debug, PartialEq)]
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

    fn code(self) -> u32 {
        match self {
            Source::Shape => DK_ROTATIONS_SHAPE,
            Source::Rigid => DK_ROTATIONS_RIGID,
            Source::PerNode => DK_ROTATIONS_PER_NODE,
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
    bnd: &Bnd,
    deformed: &[[f64; D]],
    source: Source,
    deg: f64,
) -> (Vec<[f64; D]>, [f64; D]) {
    let all = per_node_rotations(bnd.nodes.len());
    let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds).unwrap();
    let motion = BoundaryMotion {
        nodes: &bnd.nodes,
        deformed,
        elements: Some(elements),
        rotations: match source {
            Source::Shape => RotationSource::Shape,
            Source::Rigid => RotationSource::Rigid(rigid(deg)),
            Source::PerNode => RotationSource::PerNode(&all),
        },
        origin: None,
    };
    let n = mesh.node_count();
    let (mut t, mut q) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
    let mut s = vec![0.0; deform_idw_scratch_len::<D>(n, bnd.nodes.len())];
    let mut out = vec![[0.0; D]; n];
    let p = source.exponent();
    let origin = deform_idw(&mesh.points, &motion, p, &mut t, &mut q, &mut s, &mut out).unwrap();
    (out, origin)
}

/// One thread's share of the boundary (flat), its rotations and the C call's other knobs.
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
    source: Source,
    /// `(w, x, y, z)` per listed node.
    rotations: Vec<f64>,
    rigid: [f64; 4],
    /// Doubles taken off `scratch`.
    scratch_short: usize,
    /// `out` passed as NULL.
    out_null: bool,
}

fn share<const D: usize>(
    v: &LocalView<D>,
    bnd: &Bnd,
    deformed: &[[f64; D]],
    source: Source,
    deg: f64,
) -> Share {
    let s = partition_boundary::share(v, bnd, deformed, |_, owns_first| owns_first);
    let all = per_node_rotations(bnd.nodes.len());
    let rotations = partition_boundary::share_rotations(&s, &all);
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
        source,
        rotations: rotations.iter().flat_map(|q| q.to_array()).collect(),
        rigid: rigid(deg).to_array(),
        scratch_short: 0,
        out_null: false,
    }
}

/// What one thread got: status, `out` (owned nodes, flat), origin, and whether `out` and the
/// origin were left as they were.
struct Got {
    status: dk_status,
    out: Vec<f64>,
    origin: Vec<f64>,
    untouched: bool,
}

const SENTINEL: f64 = -7.25e11;

/// The C motion struct of a share (borrowed).
fn c_motion(s: &Share) -> dk_partitioned_motion {
    dk_partitioned_motion {
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
        rigid_rotation: s.rigid,
        origin: [0.0; 3],
        rotation_source: s.source.code(),
        has_origin: 0,
    }
}

/// One thread's C calls on its view and share.
fn deform<const D: usize>(v: &LocalView<D>, s: &Share, me: &mut Rank<'_>) -> Got {
    let part = c_partition(v);
    let motion = c_motion(s);
    let ex = dk_exchange {
        user: me as *mut Rank as *mut c_void,
        sum_words: Some(sum_words),
        max: Some(max),
        halo: Some(halo),
    };
    let pts = v.points.as_flattened();
    let mut lens = [0usize; 4];
    let mut out = vec![SENTINEL; v.owned * D];
    let mut origin = vec![SENTINEL; D];
    let (b, e) = (s.boundary_count, s.element_count);
    // SAFETY: every pointer is live for its length; `ex.user` outlives the call.
    let st = unsafe { dk_partitioned_deform_idw_lens(&part, D as u32, b, e, lens.as_mut_ptr()) };
    assert_eq!(st, dk_status::DK_OK);
    let mut scratch = vec![0.0; lens[0] - s.scratch_short];
    let mut index = vec![0u32; lens[1]];
    let mut words = vec![0i64; lens[2]];
    let mut kinds = vec![0u8; lens[3]];
    let out_ptr = if s.out_null {
        std::ptr::null_mut()
    } else {
        out.as_mut_ptr()
    };
    // SAFETY: as above.
    let status = unsafe {
        dk_partitioned_deform_idw(
            &part,
            pts.as_ptr(),
            pts.len(),
            D as u32,
            s.source.exponent(),
            &motion,
            s.rotations.as_ptr(),
            s.rotations.len(),
            scratch.as_mut_ptr(),
            scratch.len(),
            index.as_mut_ptr(),
            index.len(),
            words.as_mut_ptr(),
            words.len(),
            kinds.as_mut_ptr(),
            kinds.len(),
            &ex,
            out_ptr,
            out.len(),
            origin.as_mut_ptr(),
            origin.len(),
        )
    };
    let untouched = out.iter().chain(&origin).all(|&x| x == SENTINEL);
    Got {
        status,
        out,
        origin,
        untouched,
    }
}

/// A change to one thread's view and share before its call.
type Spoil<'a, const D: usize> = &'a (dyn Fn(u32, &mut LocalView<D>, &mut Share) + Sync);

/// One run on `size` threads: each cuts its view (random owners, ghost `depth`), takes its
/// share, lets `spoil` change them, and returns its view's global ids with what it got.
/// `fail_max`: a rank and the `max` call at which its callback reports a failure.
#[allow(clippy::too_many_arguments)]
fn run_ranks<const D: usize>(
    mesh: &Mesh<D>,
    bnd: &Bnd,
    deformed: &[[f64; D]],
    (source, deg): (Source, f64),
    size: u32,
    depth: usize,
    fail_max: Option<(u32, usize)>,
    spoil: Spoil<'_, D>,
) -> Vec<(Vec<u64>, Got)> {
    let n = mesh.node_count();
    let mut fixed = vec![0u8; n];
    bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
    let owner = random_owner(n, size as usize, 0x51 + u64::from(size));
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
                        local_view(mesh, fixed, owner, (rank, size), depth, 5 + rank as u64);
                    let mut s = share(&v, bnd, deformed, source, deg);
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

/// Every source, rank counts `sizes` and ghost depths 1–2: the owned nodes and the origin are
/// the serial bits.
fn bits_equal_serial<const D: usize>(mesh: &Mesh<D>, deg: f64, sizes: &[u32]) {
    let bnd = boundary(mesh);
    let deformed = moved(mesh, &bnd.nodes, deg);
    for source in [Source::Shape, Source::Rigid, Source::PerNode] {
        let (want, origin) = serial(mesh, &bnd, &deformed, source, deg);
        for &size in sizes {
            for depth in [1, 2] {
                let how = (source, deg);
                let results =
                    run_ranks(mesh, &bnd, &deformed, how, size, depth, None, &|_, _, _| {});
                for (rank, (ids, got)) in results.iter().enumerate() {
                    let what =
                        format!("{D}D {source:?}, {size} threads, depth {depth}, rank {rank}");
                    assert_eq!(got.status, dk_status::DK_OK, "{what}");
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
fn threads_give_the_serial_bits_2d() {
    bits_equal_serial(&mesh_2d(32, 8), 12.0, &[1, 2, 3, 4]);
}

#[test]
fn threads_give_the_serial_bits_3d() {
    let mesh = extrude(&mesh_2d(16, 5), 1.0, 2).unwrap();
    bits_equal_serial(&mesh, 8.0, &[1, 3]);
}

/// What a bad case changes on the culprit's rank.
type Bad = fn(&mut LocalView<2>, &mut Share);

/// A bad case: what, the source, the culprit, its spoil, a failing `max` at this call, the
/// culprit's status and the others'.
type Case = (
    &'static str,
    Source,
    u32,
    Bad,
    Option<usize>,
    dk_status,
    dk_status,
);

#[test]
fn bad_input_fails_on_every_rank_with_nothing_written() {
    use dk_status::{
        DK_ERR_BAD_PARTITION as BAD, DK_ERR_BUFFER_TOO_SMALL as SHORT, DK_ERR_EXCHANGE as EXCHANGE,
        DK_ERR_LENGTH_MISMATCH as LENGTH, DK_ERR_NULL_POINTER as NULL, DK_ERR_ZERO_LENGTH as ZERO,
    };
    let mesh = mesh_2d(24, 6);
    let bnd = boundary(&mesh);
    let deformed = moved(&mesh, &bnd.nodes, 10.0);
    let none: Bad = |_, _| {};
    let cases: [Case; 10] = [
        (
            "duplicate global ids",
            Source::Shape,
            1,
            |v, _| v.global_ids[1] = v.global_ids[0],
            None,
            BAD,
            BAD,
        ),
        (
            "a ghost in no receive list",
            Source::Rigid,
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
            Source::Shape,
            2,
            |_, s| s.boundary_count += 1,
            None,
            BAD,
            BAD,
        ),
        (
            "two ranks give one boundary position",
            Source::Rigid,
            0,
            |_, s| s.positions[0] = s.positions[1],
            None,
            BAD,
            BAD,
        ),
        (
            "a short scratch",
            Source::Shape,
            1,
            |_, s| s.scratch_short = 1,
            None,
            SHORT,
            BAD,
        ),
        (
            "a NULL out",
            Source::Shape,
            0,
            |_, s| s.out_null = true,
            None,
            NULL,
            BAD,
        ),
        (
            "per-node rotations not a whole number of quaternions",
            Source::PerNode,
            2,
            |_, s| {
                s.rotations.pop();
            },
            None,
            LENGTH,
            BAD,
        ),
        (
            "per-node rotations for one node too few",
            Source::PerNode,
            1,
            |_, s| s.rotations.truncate(s.rotations.len() - 4),
            None,
            LENGTH,
            BAD,
        ),
        (
            "a zero rigid rotation",
            Source::Rigid,
            1,
            |_, s| s.rigid = [0.0; 4],
            None,
            ZERO,
            BAD,
        ),
        (
            "a failing max callback",
            Source::Shape,
            1,
            none,
            Some(1),
            EXCHANGE,
            EXCHANGE,
        ),
    ];
    for (what, source, culprit, spoil, fail_at, own, others) in cases {
        let fail = fail_at.map(|c| (culprit, c));
        let results = run_ranks(
            &mesh,
            &bnd,
            &deformed,
            (source, 10.0),
            3,
            1,
            fail,
            &|rank, v, s| {
                if rank == culprit {
                    spoil(v, s);
                }
            },
        );
        for (rank, (_, got)) in results.iter().enumerate() {
            let want = if rank as u32 == culprit { own } else { others };
            assert_eq!(got.status, want, "{what}: rank {rank}");
            assert!(got.untouched, "{what}: rank {rank} wrote an output");
        }
    }
}

/// A NULL exchange, or one without a callback, is refused at once (no exchange: one thread
/// alone does not wait for the others).
#[test]
fn a_null_exchange_is_refused_at_once() {
    let mesh = mesh_2d(16, 5);
    let bnd = boundary(&mesh);
    let deformed = moved(&mesh, &bnd.nodes, 5.0);
    let n = mesh.node_count();
    let fixed = vec![0u8; n];
    let owner = random_owner(n, 2, 1);
    let v = local_view(&mesh, &fixed, &owner, (0, 2), 1, 1);
    let s = share(&v, &bnd, &deformed, Source::Rigid, 5.0);
    let (part, motion) = (c_partition(&v), c_motion(&s));
    let pts = v.points.as_flattened();
    let mut out = vec![SENTINEL; 2 * v.owned];
    let no_halo = dk_exchange {
        user: std::ptr::null_mut(),
        sum_words: Some(sum_words),
        max: Some(max),
        halo: None,
    };
    for ex in [std::ptr::null(), &no_halo as *const dk_exchange] {
        // SAFETY: live buffers; the callbacks are never called.
        let status = unsafe {
            dk_partitioned_deform_idw(
                &part,
                pts.as_ptr(),
                pts.len(),
                2,
                2.0,
                &motion,
                std::ptr::null(),
                0,
                std::ptr::null_mut(),
                0,
                std::ptr::null_mut(),
                0,
                std::ptr::null_mut(),
                0,
                std::ptr::null_mut(),
                0,
                ex,
                out.as_mut_ptr(),
                out.len(),
                std::ptr::null_mut(),
                0,
            )
        };
        assert_eq!(status, dk_status::DK_ERR_NULL_POINTER);
        assert!(out.iter().all(|&x| x == SENTINEL));
    }
}
