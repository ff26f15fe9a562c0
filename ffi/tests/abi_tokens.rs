//! The ABI boundary exercised from Rust, small enough for Miri (`cargo +nightly miri test -p
//! deform-kernel-ffi`): every kind of token (inputs, outputs, aliasing outputs, single values,
//! structs that carry arrays, optional arrays) on real calls, compared with the Rust API on
//! the same inputs, and the NULL / short-buffer paths, which must leave outputs untouched.
#![allow(unsafe_code)] // calling the `extern "C"` functions is the point of this module

use core::ptr::null;

use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::taubin::{smooth_structured, StructuredOptions, TaubinParams};
use deform_kernel::{graph_from_edges, graph_from_edges_len, Block, Quat};

use deform_kernel::spring::constraints::{slide_points, Constraints};
use deform_kernel::spring::{
    solve_linear_amg_scratch_len, solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions,
    LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel_ffi::deformation::{
    dk_boundary_motion, dk_boundary_motion_default, dk_deform_idw, dk_deform_idw_scratch_len,
    DK_ROTATIONS_RIGID,
};
use deform_kernel_ffi::graph::{dk_graph, dk_graph_from_edges, dk_graph_from_edges_len};
use deform_kernel_ffi::plan::{dk_plan_pools, dk_plan_sizes};
use deform_kernel_ffi::quat::{dk_quat_mul, dk_quat_rotate_points};
use deform_kernel_ffi::spring::{
    dk_amg_options, dk_amg_options_default, dk_constraints, dk_constraints_fixed_mask,
    dk_slide_points, dk_spring_amg_work_len, dk_spring_solve_linear, dk_spring_solve_linear_amg,
    dk_spring_solve_linear_amg_pool_sizes, dk_spring_solve_linear_sliding,
    dk_spring_solve_linear_sliding_scratch_len, dk_spring_solve_options,
    dk_spring_solve_options_default, dk_spring_solve_report, dk_spring_system,
};
use deform_kernel_ffi::status::dk_status;
use deform_kernel_ffi::taubin::{
    dk_filter_report, dk_structured_options, dk_taubin_smooth_structured,
    dk_taubin_smooth_structured_scratch_len,
};

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn quaternion_product_may_write_over_its_input() {
    let a = [0.9, 0.1, -0.3, 0.2];
    let b = [0.5, -0.5, 0.5, 0.5];
    let expected = (Quat::from_array(a) * Quat::from_array(b)).to_array();
    let mut q = a;
    // One pointer for both, as a C caller passes it (a shared and a mutable Rust borrow of
    // `q` could not coexist).
    let p = q.as_mut_ptr();
    // SAFETY: `p` and `b` hold 4 scalars; `out` may alias `a` (documented).
    let s = unsafe { dk_quat_mul(p, b.as_ptr(), p) };
    assert_eq!(s, dk_status::DK_OK);
    assert_eq!(bits(&q), bits(&expected));
}

#[test]
fn rotated_points_match_the_rust_api_and_null_writes_nothing() {
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.3).unwrap();
    let pts = [1.0, 0.0, 0.0, 0.0, 1.0, 0.5, -2.0, 3.0, 1.0];
    let mut out = [7.0; 9];
    let qa = q.to_array();
    // SAFETY: every buffer is as long as its length argument.
    let s = unsafe { dk_quat_rotate_points(qa.as_ptr(), null(), 9, out.as_mut_ptr(), 9) };
    assert_eq!(s, dk_status::DK_ERR_NULL_POINTER);
    assert_eq!(out, [7.0; 9]);
    // SAFETY: as above.
    let s = unsafe { dk_quat_rotate_points(qa.as_ptr(), pts.as_ptr(), 9, out.as_mut_ptr(), 9) };
    assert_eq!(s, dk_status::DK_OK);
    // The ABI normalises the quaternion it is given.
    let qn = q.normalize().unwrap();
    let expected: Vec<f64> = pts
        .chunks_exact(3)
        .flat_map(|p| qn.rotate([p[0], p[1], p[2]]))
        .collect();
    assert_eq!(bits(&out), bits(&expected));
}

#[test]
fn graph_from_one_based_edges_equals_the_kernel_graph() {
    let edges1 = [1u32, 2, 2, 3, 3, 4, 4, 1, 1, 3];
    let edges0: Vec<[u32; 2]> = edges1
        .chunks_exact(2)
        .map(|e| [e[0] - 1, e[1] - 1])
        .collect();
    let mut len = 0usize;
    // SAFETY: `len` is one writable size_t.
    let s = unsafe { dk_graph_from_edges_len(10, &mut len) };
    assert_eq!(s, dk_status::DK_OK);
    assert_eq!(len, graph_from_edges_len(&edges0));
    let (mut o, mut t, mut used) = ([0u32; 5], vec![0u32; len], 0usize);
    let mut index_scratch = [0u32; 10];
    // SAFETY: every buffer is as long as its length argument; `used` is one size_t.
    let s = unsafe {
        dk_graph_from_edges(
            4,
            edges1.as_ptr(),
            10,
            1,
            index_scratch.as_mut_ptr(),
            10,
            o.as_mut_ptr(),
            5,
            t.as_mut_ptr(),
            len,
            &mut used,
        )
    };
    assert_eq!(s, dk_status::DK_OK);
    let (mut ko, mut kt) = ([0u32; 5], vec![0u32; len]);
    let kused = graph_from_edges(4, &edges0, &mut ko, &mut kt).unwrap();
    assert_eq!((o, &t[..used]), (ko, &kt[..kused]));
}

#[test]
fn structured_smoothing_reads_the_pin_mask_through_the_options_struct() {
    let (ni, nj) = (4usize, 3usize);
    let field0: Vec<f64> = (0..ni * nj).map(|i| ((i * 7) % 5) as f64 - 1.5).collect();
    let pinned: Vec<u8> = (0..ni * nj).map(|i| u8::from(i % 4 == 0)).collect();
    let mut len = 0usize;
    // SAFETY: `len` is one writable size_t.
    let s = unsafe { dk_taubin_smooth_structured_scratch_len(ni, nj, 1, &mut len) };
    assert_eq!(s, dk_status::DK_OK);
    let opts = dk_structured_options {
        pinned: pinned.as_ptr(),
        pinned_len: pinned.len(),
        mirror: [1, 0, 0],
    };
    let mut field = field0.clone();
    let mut scratch = vec![0.0; len];
    let mut report = dk_filter_report {
        iterations: 0,
        last_change: 0.0,
    };
    // SAFETY: every buffer is as long as its length argument; the options' mask too.
    let s = unsafe {
        dk_taubin_smooth_structured(
            ni,
            nj,
            1,
            0.33,
            -0.34,
            3,
            &opts,
            field.as_mut_ptr(),
            field.len(),
            scratch.as_mut_ptr(),
            len,
            &mut report,
        )
    };
    assert_eq!(s, dk_status::DK_OK);
    let mut expected = field0.clone();
    let mut kscratch = vec![0.0; len];
    let kopts = StructuredOptions {
        fixed: Some(&pinned),
        mirror: deform_kernel::Directions::only(deform_kernel::Direction::I),
    };
    let block = Block::new([ni, nj, 1]).unwrap();
    let params = TaubinParams {
        lambda: 0.33,
        mu: -0.34,
    };
    smooth_structured(&block, &mut expected, params, 3, &kopts, &mut kscratch).unwrap();
    assert_eq!(bits(&field), bits(&expected));
    assert_ne!(bits(&field), bits(&field0), "the smoothing moved nothing");
}

#[test]
fn idw_deformation_reads_the_motion_struct_arrays() {
    // A 3 x 3 grid, the left column moves rigidly (rotation about z), the right column is fixed.
    let points: Vec<f64> = (0..9)
        .flat_map(|i| [(i % 3) as f64, (i / 3) as f64])
        .collect();
    let nodes = [1u32, 4, 7, 3, 6, 9]; // 1-based
    let q = Quat::from_axis_angle([0.0, 0.0, 1.0], 0.1).unwrap();
    let mut deformed = Vec::new();
    for (k, &n) in nodes.iter().enumerate() {
        let i = (n - 1) as usize;
        let p = [points[2 * i], points[2 * i + 1]];
        if k < 3 {
            let r = q.rotate([p[0], p[1], 0.0]);
            deformed.extend([r[0] + 0.05, r[1]]);
        } else {
            deformed.extend(p);
        }
    }
    let mut motion = core::mem::MaybeUninit::<dk_boundary_motion>::uninit();
    assert_eq!(
        // SAFETY: `motion` is one writable struct.
        unsafe { dk_boundary_motion_default(motion.as_mut_ptr()) },
        dk_status::DK_OK
    );
    // SAFETY: `dk_boundary_motion_default` returned DK_OK, so it wrote every field.
    let mut motion = unsafe { motion.assume_init() };
    motion.nodes = nodes.as_ptr();
    motion.nodes_len = nodes.len();
    motion.deformed = deformed.as_ptr();
    motion.deformed_len = deformed.len();
    motion.index_base = 1;
    motion.rotation_source = DK_ROTATIONS_RIGID;
    motion.rigid_rotation = q.to_array();
    let mut len = 0usize;
    assert_eq!(
        // SAFETY: `len` is one writable size_t.
        unsafe { dk_deform_idw_scratch_len(9, 6, 2, &mut len) },
        dk_status::DK_OK
    );
    assert_eq!(len, deform_idw_scratch_len::<2>(9, 6));
    let mut scratch = vec![0.0; len];
    let mut index_scratch = [0u32; 6];
    let (mut tr, mut rot, mut out, mut origin) =
        (vec![0.0; 18], vec![0.0; 36], vec![0.0; 18], [0.0; 2]);
    // SAFETY: every buffer is as long as its length argument; the motion's arrays too.
    let s = unsafe {
        dk_deform_idw(
            points.as_ptr(),
            18,
            2,
            &motion,
            2.0,
            scratch.as_mut_ptr(),
            len,
            index_scratch.as_mut_ptr(),
            6,
            tr.as_mut_ptr(),
            18,
            rot.as_mut_ptr(),
            36,
            out.as_mut_ptr(),
            18,
            origin.as_mut_ptr(),
            2,
        )
    };
    assert_eq!(s, dk_status::DK_OK);
    let pts: Vec<[f64; 2]> = points.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
    let def: Vec<[f64; 2]> = deformed.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
    let nodes0: Vec<u32> = nodes.iter().map(|n| n - 1).collect();
    let kmotion = BoundaryMotion {
        nodes: &nodes0,
        deformed: &def,
        elements: None,
        rotations: RotationSource::Rigid(q),
        origin: None,
    };
    let (mut ktr, mut krot) = (vec![[0.0; 2]; 9], vec![Quat::new(1.0, 0.0, 0.0, 0.0); 9]);
    let mut kout = vec![[0.0; 2]; 9];
    let mut ks = vec![0.0; len];
    let ko = deform_idw(&pts, &kmotion, 2.0, &mut ktr, &mut krot, &mut ks, &mut kout).unwrap();
    let kout: Vec<f64> = kout.concat();
    assert_eq!(bits(&out), bits(&kout));
    assert_eq!(bits(&origin), bits(&ko));
    assert_ne!(bits(&out), bits(&points), "nothing moved");
}

#[test]
fn spring_solve_reads_the_graph_inside_the_system_struct() {
    // A chain 0 - 1 - 2 - 3 - 4 with both ends fixed; two components.
    let offsets = [0u32, 1, 3, 5, 7, 8];
    let targets = [1u32, 0, 2, 1, 3, 2, 4, 3];
    let stiffness = [1.0, 1.0, 2.0, 2.0, 0.5, 0.5, 1.0, 1.0];
    let fixed = [1u8, 0, 0, 0, 1];
    let values0 = [0.0, 1.0, 0.3, 0.0, 0.0, 0.7, 0.2, 0.0, 4.0, -2.0];
    let mut o = core::mem::MaybeUninit::<dk_spring_solve_options>::uninit();
    assert_eq!(
        // SAFETY: `o` is one writable struct.
        unsafe { dk_spring_solve_options_default(o.as_mut_ptr()) },
        dk_status::DK_OK
    );
    // SAFETY: written by the call above (DK_OK).
    let o = unsafe { o.assume_init() };
    let mut system = dk_spring_system {
        graph: dk_graph {
            offsets: offsets.as_ptr(),
            offsets_len: offsets.len(),
            targets: targets.as_ptr(),
            targets_len: targets.len(),
        },
        stiffness: stiffness.as_ptr(),
        stiffness_len: stiffness.len(),
        fixed: fixed.as_ptr(),
        fixed_len: fixed.len(),
    };
    let (mut scratch, mut index_scratch) = ([0.0; 50], [0u32; 5]);
    let mut report = dk_spring_solve_report {
        iterations: 0,
        residual: 0.0,
        max_update: 0.0,
        converged: false,
    };
    let mut solve = |system: &dk_spring_system, values: &mut [f64]| {
        // SAFETY: every buffer is as long as its length argument; the struct's arrays too.
        unsafe {
            dk_spring_solve_linear(
                system,
                &o,
                2,
                values.as_mut_ptr(),
                values.len(),
                scratch.as_mut_ptr(),
                scratch.len(),
                index_scratch.as_mut_ptr(),
                index_scratch.len(),
                &mut report,
            )
        }
    };
    let mut values = values0;
    assert_eq!(solve(&system, &mut values), dk_status::DK_OK);
    let g = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    let mut ks = [0u32; 5];
    let sys = SpringSystem::new(g, &stiffness, &fixed, &mut ks).unwrap();
    let mut kv: Vec<[f64; 2]> = values0.chunks_exact(2).map(|v| [v[0], v[1]]).collect();
    let mut kscratch = vec![[0.0; 2]; 25];
    // The C defaults are the kernel's.
    let stop = SolveOptions::default();
    let method = LinearMethod::Cg {
        preconditioner: deform_kernel::spring::Preconditioner::Jacobi,
    };
    sys.solve_linear(&mut kv, method, &stop, &mut kscratch)
        .unwrap();
    assert_eq!(bits(&values), bits(&kv.concat()));
    assert_ne!(bits(&values), bits(&values0), "the solve moved nothing");
    // A NULL array inside the struct is refused and nothing is written.
    system.stiffness = null();
    let mut values = values0;
    assert_eq!(solve(&system, &mut values), dk_status::DK_ERR_NULL_POINTER);
    assert_eq!(bits(&values), bits(&values0));
}

#[test]
fn multigrid_solve_writes_only_through_the_pools_struct() {
    // A chain of 12 nodes, both ends fixed, coarsened to at most 2 unknowns (two levels or
    // more); one component.
    const N: usize = 12;
    let edges: Vec<[u32; 2]> = (0..N as u32 - 1).map(|i| [i, i + 1]).collect();
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let used = graph_from_edges(N, &edges, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let g = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    // Symmetric: k depends on the pair.
    let mut k = vec![0.0; used];
    for i in 0..N {
        for e in offsets[i] as usize..offsets[i + 1] as usize {
            let j = targets[e] as usize;
            k[e] = 1.0 + ((i.min(j) * 7) % 5) as f64;
        }
    }
    let mut fixed = [0u8; N];
    fixed[0] = 1;
    fixed[N - 1] = 1;
    let mut values0 = [0.0f64; N];
    values0[N - 1] = 1.0;
    values0[3] = 0.25;

    let mut amg = core::mem::MaybeUninit::<dk_amg_options>::uninit();
    let mut o = core::mem::MaybeUninit::<dk_spring_solve_options>::uninit();
    // SAFETY: one writable struct each.
    unsafe {
        assert_eq!(dk_amg_options_default(amg.as_mut_ptr()), dk_status::DK_OK);
        assert_eq!(
            dk_spring_solve_options_default(o.as_mut_ptr()),
            dk_status::DK_OK
        );
    }
    // SAFETY: written by the calls above (DK_OK).
    let (mut amg, o) = unsafe { (amg.assume_init(), o.assume_init()) };
    amg.max_coarse = 2;
    let system = dk_spring_system {
        graph: dk_graph {
            offsets: offsets.as_ptr(),
            offsets_len: offsets.len(),
            targets: targets.as_ptr(),
            targets_len: targets.len(),
        },
        stiffness: k.as_ptr(),
        stiffness_len: k.len(),
        fixed: fixed.as_ptr(),
        fixed_len: fixed.len(),
    };
    let mut work_len = 0usize;
    assert_eq!(
        // SAFETY: one writable value.
        unsafe { dk_spring_amg_work_len(N, used, &mut work_len) },
        dk_status::DK_OK
    );
    let mut work = vec![0u32; work_len];
    let mut sizes = dk_plan_sizes {
        reals: 0,
        indices: 0,
        bytes: 0,
    };
    // SAFETY: the struct's arrays and `work` are as long as their lengths.
    let s = unsafe {
        dk_spring_solve_linear_amg_pool_sizes(
            &system,
            1,
            &amg,
            work.as_mut_ptr(),
            work.len(),
            &mut sizes,
        )
    };
    assert_eq!(s, dk_status::DK_OK);
    let mut reals = vec![0.0f64; sizes.reals];
    let mut indices = vec![0u32; sizes.indices];
    let mut report = dk_spring_solve_report {
        iterations: 0,
        residual: 0.0,
        max_update: 0.0,
        converged: false,
    };
    let mut solve = |reals_len: usize, values: &mut [f64]| {
        let pools = dk_plan_pools {
            reals: reals.as_mut_ptr(),
            reals_len,
            indices: indices.as_mut_ptr(),
            indices_len: indices.len(),
            bytes: core::ptr::null_mut(),
            bytes_len: 0,
        };
        // SAFETY: every buffer is as long as its length argument; the structs' too.
        unsafe {
            dk_spring_solve_linear_amg(
                &system,
                &o,
                &amg,
                1,
                values.as_mut_ptr(),
                values.len(),
                &pools,
                &mut report,
            )
        }
    };
    // One scalar short: refused, nothing written.
    let mut values = values0;
    assert_eq!(
        solve(sizes.reals - 1, &mut values),
        dk_status::DK_ERR_BUFFER_TOO_SMALL
    );
    assert_eq!(bits(&values), bits(&values0));
    let mut values = values0;
    assert_eq!(solve(sizes.reals, &mut values), dk_status::DK_OK);

    // The kernel directly: the same sizes and the same bits.
    let mut ks = [0u32; N];
    let sys = SpringSystem::new(g, &k, &fixed, &mut ks).unwrap();
    let opts = AmgOptions {
        max_coarse: 2,
        ..AmgOptions::default()
    };
    let mut kwork = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
    assert_eq!(kwork.len(), work_len);
    let ksizes = AmgHierarchy::setup_len(&sys, &opts, &mut kwork).unwrap();
    assert!(ksizes.levels >= 2, "{ksizes:?}");
    let (mut ki, mut kv) = (vec![0u32; ksizes.index], vec![0.0; ksizes.values]);
    let h = AmgHierarchy::setup(&sys, &opts, &mut kwork, &mut ki, &mut kv).unwrap();
    let items = solve_linear_amg_scratch_len(&h);
    assert_eq!(sizes.reals, ksizes.values + items);
    assert_eq!(sizes.indices, work_len + ksizes.index);
    let mut x: Vec<[f64; 1]> = values0.iter().map(|&v| [v]).collect();
    let mut scratch = vec![[0.0]; items];
    let r = sys
        .solve_linear_amg(&h, &mut x, &SolveOptions::default(), &mut scratch)
        .unwrap();
    assert_eq!(bits(&values), bits(&x.concat()));
    assert_eq!(report.iterations, r.iterations);
    assert!(report.converged);
}

#[test]
fn sliding_solve_reads_the_constraints_struct() {
    // A 3 x 4 grid (node i + 3 j), bottom and top rows fixed (the top one moved), the left
    // column's middle nodes sliding on x = 0 (plane, normal (1, 0)), the right column's on a
    // line with tangent (0, 1); one free node in the middle.
    const NI: usize = 3;
    const N: usize = NI * 4;
    let mut edges = Vec::new();
    for n in 0..N as u32 {
        if (n as usize) % NI + 1 < NI {
            edges.push([n, n + 1]);
        }
        if (n as usize) + NI < N {
            edges.push([n, n + NI as u32]);
        }
    }
    let mut offsets = vec![0u32; N + 1];
    let mut targets = vec![0u32; graph_from_edges_len(&edges)];
    let used = graph_from_edges(N, &edges, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    let g = deform_kernel::Graph::new(&offsets, &targets).unwrap();
    let k = vec![1.0f64; used];
    let mut kinds = [0u8; N];
    let mut dirs = [0.0f64; 2 * N];
    let mut values0 = [0.0f64; 2 * N];
    for j in 0..4 {
        for i in 0..NI {
            let n = i + NI * j;
            kinds[n] = match (i, j) {
                (_, 0) | (_, 3) => 1,
                (0, _) => 2,
                (2, _) => 3,
                _ => 0,
            };
            if kinds[n] == 2 {
                dirs[2 * n] = 1.0;
            } else if kinds[n] == 3 {
                dirs[2 * n + 1] = 1.0;
            } else {
                dirs[2 * n] = f64::NAN; // never read
            }
            if j == 3 {
                values0[2 * n] = 0.1;
                values0[2 * n + 1] = 0.05;
            }
        }
    }
    let con = |directions_len: usize| dk_constraints {
        kinds: kinds.as_ptr(),
        kinds_len: N,
        directions: dirs.as_ptr(),
        directions_len,
    };
    let mut mask = [9u8; N];
    // SAFETY: the struct's arrays and `mask` are as long as their lengths.
    let s = unsafe { dk_constraints_fixed_mask(&con(2 * N), 2, mask.as_mut_ptr(), N) };
    assert_eq!(s, dk_status::DK_OK);
    assert!(mask
        .iter()
        .zip(&kinds)
        .all(|(&m, &k)| m == u8::from(k == 1)));

    let mut o = core::mem::MaybeUninit::<dk_spring_solve_options>::uninit();
    assert_eq!(
        // SAFETY: one writable struct.
        unsafe { dk_spring_solve_options_default(o.as_mut_ptr()) },
        dk_status::DK_OK
    );
    // SAFETY: written by the call above (DK_OK).
    let o = unsafe { o.assume_init() };
    let system = dk_spring_system {
        graph: dk_graph {
            offsets: offsets.as_ptr(),
            offsets_len: offsets.len(),
            targets: targets.as_ptr(),
            targets_len: targets.len(),
        },
        stiffness: k.as_ptr(),
        stiffness_len: k.len(),
        fixed: mask.as_ptr(),
        fixed_len: N,
    };
    let mut need = 0usize;
    // SAFETY: one readable struct, one writable value.
    let s = unsafe { dk_spring_solve_linear_sliding_scratch_len(N, 2, &o, &mut need) };
    assert_eq!(s, dk_status::DK_OK);
    let mut scratch = vec![0.0f64; need];
    let mut index = [0u32; N];
    let mut report = dk_spring_solve_report {
        iterations: 0,
        residual: 0.0,
        max_update: 0.0,
        converged: false,
    };
    let mut solve = |directions_len: usize, values: &mut [f64]| {
        // SAFETY: every buffer is as long as its length argument; the structs' arrays too
        // (`directions_len` at most 2 N).
        unsafe {
            dk_spring_solve_linear_sliding(
                &system,
                &con(directions_len),
                &o,
                2,
                values.as_mut_ptr(),
                values.len(),
                scratch.as_mut_ptr(),
                scratch.len(),
                index.as_mut_ptr(),
                index.len(),
                &mut report,
            )
        }
    };
    // One direction short: refused, nothing written.
    let mut values = values0;
    assert_eq!(
        solve(2 * N - 2, &mut values),
        dk_status::DK_ERR_LENGTH_MISMATCH
    );
    assert_eq!(bits(&values), bits(&values0));
    let mut values = values0;
    assert_eq!(solve(2 * N, &mut values), dk_status::DK_OK);
    assert!(report.converged);

    // The kernel directly: the same bits; the sliding nodes stayed on x = 0 / moved along y.
    let kdirs: Vec<[f64; 2]> = dirs.chunks_exact(2).map(|d| [d[0], d[1]]).collect();
    let c = Constraints::new(&kinds, &kdirs).unwrap();
    let mut ks = [0u32; N];
    let sys = SpringSystem::new(g, &k, &mask, &mut ks).unwrap();
    let solver = LinearSolver::Method(LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    });
    let mut x: Vec<[f64; 2]> = values0.chunks_exact(2).map(|v| [v[0], v[1]]).collect();
    let mut kscratch = vec![[0.0; 2]; solve_linear_sliding_scratch_len(&solver, N)];
    let r = sys
        .solve_linear_sliding(&c, &mut x, solver, &SolveOptions::default(), &mut kscratch)
        .unwrap();
    assert_eq!(bits(&values), bits(&x.concat()));
    assert_eq!(report.iterations, r.iterations);
    for (n, &kind) in kinds.iter().enumerate() {
        match kind {
            2 => assert_eq!(values[2 * n], 0.0),
            3 => assert_eq!(values[2 * n], 0.0),
            _ => {}
        }
    }
    assert!(values[2 * NI + 1] != 0.0);

    // dk_slide_points: the kernel's bits; a NULL constraints struct writes nothing.
    let points: Vec<f64> = (0..2 * N)
        .map(|i| (i / 2) as f64 * 0.5 + (i % 2) as f64)
        .collect();
    let moved0: Vec<f64> = points.iter().map(|p| p + 0.125).collect();
    let mut moved = moved0.clone();
    // SAFETY: NULL constraints; the arrays are as long as their lengths.
    let s = unsafe {
        dk_slide_points(
            null(),
            2,
            points.as_ptr(),
            points.len(),
            moved.as_mut_ptr(),
            moved.len(),
        )
    };
    assert_eq!(s, dk_status::DK_ERR_NULL_POINTER);
    assert_eq!(bits(&moved), bits(&moved0));
    // SAFETY: as above, with the struct.
    let s = unsafe {
        dk_slide_points(
            &con(2 * N),
            2,
            points.as_ptr(),
            points.len(),
            moved.as_mut_ptr(),
            moved.len(),
        )
    };
    assert_eq!(s, dk_status::DK_OK);
    let kp: Vec<[f64; 2]> = points.chunks_exact(2).map(|v| [v[0], v[1]]).collect();
    let mut km: Vec<[f64; 2]> = moved0.chunks_exact(2).map(|v| [v[0], v[1]]).collect();
    slide_points(&c, &kp, &mut km).unwrap();
    assert_eq!(bits(&moved), bits(&km.concat()));
}
