//! Bad input through the C ABI, called from Rust: each `dk_*` call below gets one defect (NULL,
//! wrong length, out-of-range index, bad index base, NaN, too-small scratch) and must return its
//! documented status and leave every output bit-for-bit unchanged. The same calls with the
//! defect removed must succeed, so each check can fail. (The C programs in `ffi/tests/` cover
//! every function from C; this file shows the contract holds for a Rust caller too.)
#![allow(unsafe_code)] // calling the `extern "C"` functions is the point of this file

use core::ptr::{null, null_mut};

use deform_kernel_ffi::deformation::{
    dk_boundary_motion, dk_boundary_motion_default, dk_deform_idw, dk_deform_idw_scratch_len,
    DK_ROTATIONS_RIGID,
};
use deform_kernel_ffi::graph::{dk_graph, dk_graph_from_edges};
use deform_kernel_ffi::spring::{
    dk_spring_index_scratch_len, dk_spring_solve_linear, dk_spring_solve_linear_scratch_len,
    dk_spring_solve_options, dk_spring_solve_options_default, dk_spring_solve_report,
    dk_spring_system,
};
use deform_kernel_ffi::status::dk_status;
use deform_kernel_ffi::taubin::{
    dk_filter_report, dk_structured_options, dk_taubin_smooth_structured,
    dk_taubin_smooth_structured_scratch_len,
};

const SENTINEL: f64 = 12345.0;

/// One defective smoothing call: name, field, field length, scratch length, options, whether a
/// report is passed, and the expected status.
type Case = (
    &'static str,
    Vec<f64>,
    usize,
    usize,
    *const dk_structured_options,
    bool,
    dk_status,
);

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The spring system over the CSR graph `offsets`/`targets`, borrowing the slices (each
/// length the slice's own).
fn spring_system(
    offsets: &[u32],
    targets: &[u32],
    stiffness: &[f64],
    fixed: &[u8],
) -> dk_spring_system {
    dk_spring_system {
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
    }
}

#[test]
fn graph_from_edges_rejects_bad_input_and_writes_nothing() {
    let edges = [0u32, 1, 1, 2, 2, 3];
    let edges1 = [1u32, 2, 2, 3, 3, 4];
    let build = |edges: *const u32, len: usize, base: u32, nodes: usize| {
        let mut offsets = [77u32; 5];
        let mut targets = [77u32; 6];
        let mut used = 99usize;
        let mut index_scratch = [0u32; 6];
        // SAFETY: every buffer is valid for the length passed with it.
        let s = unsafe {
            dk_graph_from_edges(
                nodes,
                edges,
                len,
                base,
                index_scratch.as_mut_ptr(),
                index_scratch.len(),
                offsets.as_mut_ptr(),
                offsets.len(),
                targets.as_mut_ptr(),
                targets.len(),
                &mut used,
            )
        };
        (s, offsets, targets, used)
    };
    let (s, offsets, targets, used) = build(edges.as_ptr(), 6, 0, 4);
    assert_eq!(s, dk_status::DK_OK);
    assert_eq!((offsets, used), ([0, 1, 3, 5, 6], 6));
    assert_eq!(targets, [1, 0, 2, 1, 3, 2]);
    assert_eq!(
        build(edges1.as_ptr(), 6, 1, 4).1,
        offsets,
        "1-based gives the same graph"
    );

    for (case, (s, o, t, u)) in [
        ("NULL edges", build(null(), 6, 0, 4)),
        ("odd length", build(edges.as_ptr(), 5, 0, 4)),
        ("index base 2", build(edges.as_ptr(), 6, 2, 4)),
        ("node 3 with 3 nodes", build(edges.as_ptr(), 6, 0, 3)),
        ("0 read 1-based", build(edges.as_ptr(), 6, 1, 4)),
    ] {
        assert_ne!(s, dk_status::DK_OK, "{case}");
        assert_eq!((o, t, u), ([77; 5], [77; 6], 99), "{case}: outputs written");
    }
    assert_eq!(build(null(), 6, 0, 4).0, dk_status::DK_ERR_NULL_POINTER);
    assert_eq!(
        build(edges.as_ptr(), 5, 0, 4).0,
        dk_status::DK_ERR_LENGTH_MISMATCH
    );
    assert_eq!(
        build(edges.as_ptr(), 6, 2, 4).0,
        dk_status::DK_ERR_BAD_INDEX_BASE
    );
    assert_eq!(
        build(edges.as_ptr(), 6, 0, 3).0,
        dk_status::DK_ERR_INDEX_OUT_OF_RANGE
    );
    assert_eq!(
        build(edges.as_ptr(), 6, 1, 4).0,
        dk_status::DK_ERR_INDEX_OUT_OF_RANGE
    );
}

/// A 4×3 structured field smoothed in place: NaN, a short field, a small scratch, NULL options
/// or report each fail and leave the field and the report unchanged.
#[test]
fn taubin_smooth_structured_rejects_bad_input_and_keeps_the_field() {
    let (ni, nj) = (4usize, 3usize);
    let original: Vec<f64> = (0..ni * nj).map(|p| ((p * 7) % 5) as f64).collect();
    let mut len = 0usize;
    // SAFETY: `len` is one writable size_t.
    let s = unsafe { dk_taubin_smooth_structured_scratch_len(ni, nj, 1, &mut len) };
    assert_eq!(s, dk_status::DK_OK);
    let options = dk_structured_options {
        pinned: null(),
        pinned_len: 0,
        mirror: [0; 3],
    };
    let run = |field: &mut Vec<f64>, field_len: usize, scratch_len: usize, opts, with_report| {
        let mut scratch = vec![0.0; len.max(scratch_len)];
        let mut report = dk_filter_report {
            iterations: 777,
            last_change: SENTINEL,
        };
        let rp: *mut dk_filter_report = if with_report { &mut report } else { null_mut() };
        // SAFETY: `field` holds at least `field_len` values, `scratch` at least `scratch_len`,
        // `opts` is NULL or points to `options`, `rp` is NULL or points to `report`.
        let s = unsafe {
            dk_taubin_smooth_structured(
                ni,
                nj,
                1,
                0.330,
                -0.334,
                5,
                opts,
                field.as_mut_ptr(),
                field_len,
                scratch.as_mut_ptr(),
                scratch_len,
                rp,
            )
        };
        (s, report.iterations, report.last_change)
    };
    let n = ni * nj;
    let mut good = original.clone();
    let (s, iterations, change) = run(&mut good, n, len, &options as *const _, true);
    assert_eq!(s, dk_status::DK_OK);
    assert_eq!(iterations, 5);
    assert!(change > 0.0 && bits(&good) != bits(&original));

    let mut with_nan = original.clone();
    with_nan[5] = f64::NAN;
    let cases: [Case; 5] = [
        (
            "NaN",
            with_nan,
            n,
            len,
            &options,
            true,
            dk_status::DK_ERR_NON_FINITE,
        ),
        (
            "short field",
            original.clone(),
            n - 1,
            len,
            &options,
            true,
            dk_status::DK_ERR_LENGTH_MISMATCH,
        ),
        (
            "small scratch",
            original.clone(),
            n,
            len - 1,
            &options,
            true,
            dk_status::DK_ERR_BUFFER_TOO_SMALL,
        ),
        (
            "NULL options",
            original.clone(),
            n,
            len,
            null(),
            true,
            dk_status::DK_ERR_NULL_POINTER,
        ),
        (
            "NULL report",
            original.clone(),
            n,
            len,
            &options,
            false,
            dk_status::DK_ERR_NULL_POINTER,
        ),
    ];
    for (case, mut field, field_len, scratch_len, opts, with_report, expected) in cases {
        let before = bits(&field);
        let (s, iterations, change) = run(&mut field, field_len, scratch_len, opts, with_report);
        assert_eq!(s, expected, "{case}");
        assert_eq!(bits(&field), before, "{case}: field written");
        assert_eq!(
            (iterations, change),
            (777, SENTINEL),
            "{case}: report written"
        );
    }
}

/// A chain 0–1–2–3–4 with both ends fixed: the CG solve interpolates linearly; a fixed mask of
/// the wrong length, a NaN value, an unanchored system or a NULL system fail and leave `values`
/// unchanged.
#[test]
fn spring_solve_linear_rejects_bad_input_and_keeps_values() {
    let offsets = [0u32, 1, 3, 5, 7, 8];
    let targets = [1u32, 0, 2, 1, 3, 2, 4, 3];
    let stiffness = [1.0f64; 8];
    let n = 5;
    let mut opts = dk_spring_solve_options {
        max_iterations: 0,
        residual_tol: 0.0,
        update_tol: 0.0,
        omega: 0.0,
        method: 0,
        preconditioner: 0,
    };
    // SAFETY: `opts` is one writable options struct.
    assert_eq!(
        unsafe { dk_spring_solve_options_default(&mut opts) },
        dk_status::DK_OK
    );
    let (mut len, mut ilen) = (0usize, 0usize);
    // SAFETY: `opts` is readable; the lengths are writable size_t values.
    unsafe {
        assert_eq!(
            dk_spring_solve_linear_scratch_len(n, 1, &opts, &mut len),
            dk_status::DK_OK
        );
        assert_eq!(dk_spring_index_scratch_len(n, &mut ilen), dk_status::DK_OK);
    }
    // `system` is NULL or points to a system whose arrays are valid for their lengths.
    let solve_system = |system: *const dk_spring_system, values: &mut [f64]| {
        let mut scratch = vec![0.0; len];
        let mut index = vec![0u32; ilen];
        let mut report = dk_spring_solve_report {
            iterations: 777,
            residual: SENTINEL,
            max_update: SENTINEL,
            converged: false,
        };
        // SAFETY: every buffer is valid for the length passed with it; `system` as above.
        let s = unsafe {
            dk_spring_solve_linear(
                system,
                &opts,
                1,
                values.as_mut_ptr(),
                values.len(),
                scratch.as_mut_ptr(),
                scratch.len(),
                index.as_mut_ptr(),
                index.len(),
                &mut report,
            )
        };
        (s, report.iterations)
    };
    let solve = |fixed: &[u8], values: &mut [f64]| {
        solve_system(
            &spring_system(&offsets, &targets, &stiffness, fixed),
            values,
        )
    };
    let fixed = [1u8, 0, 0, 0, 1];
    let mut values = [0.0, 0.0, 0.0, 0.0, 4.0];
    let (s, iterations) = solve(&fixed, &mut values);
    assert_eq!(s, dk_status::DK_OK);
    assert!(iterations > 0 && iterations != 777);
    for (i, v) in values.iter().enumerate() {
        assert!((v - i as f64).abs() < 1e-9, "node {i}: {v}");
    }

    let start = [0.0, 0.5, f64::NAN, 0.0, 4.0];
    let mut v = start;
    assert_eq!(solve(&fixed, &mut v), (dk_status::DK_ERR_NON_FINITE, 777));
    assert_eq!(bits(&v), bits(&start));
    let start = [0.0, 0.5, 0.25, 0.0, 4.0];
    let mut v = start;
    assert_eq!(
        solve(&fixed[..4], &mut v),
        (dk_status::DK_ERR_LENGTH_MISMATCH, 777)
    );
    assert_eq!(bits(&v), bits(&start));
    let mut v = start;
    assert_eq!(
        solve(&[0u8; 5], &mut v),
        (dk_status::DK_ERR_UNANCHORED, 777)
    );
    assert_eq!(bits(&v), bits(&start));
    let mut v = start;
    assert_eq!(
        solve_system(null(), &mut v),
        (dk_status::DK_ERR_NULL_POINTER, 777),
        "NULL system"
    );
    assert_eq!(bits(&v), bits(&start));
}

/// A 3×3 grid whose outer ring moves rigidly: IDW reproduces the rigid motion at the centre and
/// the ring bitwise; each defect in the motion fails with its status and leaves `out` alone.
#[test]
fn deform_idw_rejects_bad_motion_and_keeps_out() {
    let points: Vec<f64> = (0..9)
        .flat_map(|p| [(p % 3) as f64, (p / 3) as f64])
        .collect();
    let ring = [0u32, 1, 2, 3, 5, 6, 7, 8];
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    let moved = |x: f64, y: f64| [c * x - s * y + 0.5, s * x + c * y - 0.25];
    let deformed: Vec<f64> = ring
        .iter()
        .flat_map(|&p| moved(points[2 * p as usize], points[2 * p as usize + 1]))
        .collect();
    let half = 0.15f64;
    let q = [half.cos(), 0.0, 0.0, half.sin()];

    // SAFETY: a zeroed struct of pointers, lengths and numbers is a valid value to overwrite.
    let mut motion: dk_boundary_motion = unsafe { core::mem::zeroed() };
    // SAFETY: `motion` is one writable struct.
    assert_eq!(
        unsafe { dk_boundary_motion_default(&mut motion) },
        dk_status::DK_OK
    );
    motion.nodes = ring.as_ptr();
    motion.nodes_len = ring.len();
    motion.deformed = deformed.as_ptr();
    motion.deformed_len = deformed.len();
    motion.rotation_source = DK_ROTATIONS_RIGID;
    motion.rigid_rotation = q;
    let mut len = 0usize;
    // SAFETY: `len` is one writable size_t.
    assert_eq!(
        unsafe { dk_deform_idw_scratch_len(9, 8, 2, &mut len) },
        dk_status::DK_OK
    );

    let run = |m: &dk_boundary_motion, exponent: f64| {
        let mut scratch = vec![0.0; len];
        let mut index = vec![0u32; 2 * ring.len()];
        let mut translations = vec![0.0; 18];
        let mut rotations = vec![0.0; 36];
        let mut out = vec![SENTINEL; 18];
        // SAFETY: every buffer is valid for the length passed with it, and `m`'s arrays for
        // theirs.
        let s = unsafe {
            dk_deform_idw(
                points.as_ptr(),
                points.len(),
                2,
                m,
                exponent,
                scratch.as_mut_ptr(),
                scratch.len(),
                index.as_mut_ptr(),
                index.len(),
                translations.as_mut_ptr(),
                translations.len(),
                rotations.as_mut_ptr(),
                rotations.len(),
                out.as_mut_ptr(),
                out.len(),
                null_mut(),
                0,
            )
        };
        (s, out)
    };
    let (s, out) = run(&motion, 2.0);
    assert_eq!(s, dk_status::DK_OK);
    for (b, &p) in ring.iter().enumerate() {
        let p = p as usize;
        assert_eq!(
            bits(&out[2 * p..2 * p + 2]),
            bits(&deformed[2 * b..2 * b + 2])
        );
    }
    let centre = moved(1.0, 1.0);
    assert!((out[8] - centre[0]).abs() < 1e-12 && (out[9] - centre[1]).abs() < 1e-12);

    let untouched = |(s, out): (dk_status, Vec<f64>), expected: dk_status, case: &str| {
        assert_eq!(s, expected, "{case}");
        assert!(out.iter().all(|&v| v == SENTINEL), "{case}: out written");
    };
    let bad_nodes = [0u32, 1, 2, 3, 5, 6, 7, 9];
    let dup_nodes = [0u32, 1, 2, 3, 5, 6, 7, 7];
    let nodes1: Vec<u32> = ring.iter().map(|n| n + 1).collect();
    let mut nan = deformed.clone();
    nan[3] = f64::NAN;

    let mut m = motion;
    m.nodes = bad_nodes.as_ptr();
    untouched(
        run(&m, 2.0),
        dk_status::DK_ERR_INDEX_OUT_OF_RANGE,
        "node 9 of 9",
    );
    m.nodes = dup_nodes.as_ptr();
    untouched(
        run(&m, 2.0),
        dk_status::DK_ERR_DUPLICATE_NODE,
        "node 7 twice",
    );
    let mut m = motion;
    m.index_base = 2;
    untouched(
        run(&m, 2.0),
        dk_status::DK_ERR_BAD_INDEX_BASE,
        "index base 2",
    );
    m.index_base = 1;
    let (s, out1) = run(&m, 2.0);
    assert_eq!(
        s,
        dk_status::DK_ERR_INDEX_OUT_OF_RANGE,
        "node 0 read 1-based"
    );
    assert!(out1.iter().all(|&v| v == SENTINEL));
    m.nodes = nodes1.as_ptr();
    let (s, out1) = run(&m, 2.0);
    assert_eq!(s, dk_status::DK_OK, "the same motion 1-based");
    assert_eq!(bits(&out1), bits(&out), "1-based gives the same bits");
    let mut m = motion;
    m.deformed = nan.as_ptr();
    untouched(run(&m, 2.0), dk_status::DK_ERR_NON_FINITE, "NaN deformed");
    let mut m = motion;
    m.deformed = null();
    untouched(
        run(&m, 2.0),
        dk_status::DK_ERR_NULL_POINTER,
        "NULL deformed",
    );
    let mut m = motion;
    m.deformed_len = 15;
    untouched(
        run(&m, 2.0),
        dk_status::DK_ERR_LENGTH_MISMATCH,
        "short deformed",
    );
    let mut m = motion;
    m.rigid_rotation = [0.0; 4];
    untouched(run(&m, 2.0), dk_status::DK_ERR_ZERO_LENGTH, "zero rotation");
    untouched(
        run(&motion, f64::NAN),
        dk_status::DK_ERR_INVALID_PARAMETER,
        "NaN exponent",
    );
    untouched(
        run(&motion, -1.0),
        dk_status::DK_ERR_INVALID_PARAMETER,
        "negative exponent",
    );
}

#[test]
fn every_kernel_error_has_its_own_status_and_description() {
    use deform_kernel::Error;
    let cases = [
        (Error::Overflow { arg: "x" }, dk_status::DK_ERR_OVERFLOW, 26),
        (
            Error::NotUnit {
                arg: "directions",
                position: 3,
            },
            dk_status::DK_ERR_NOT_UNIT,
            27,
        ),
        (
            Error::NotPlanar {
                arg: "nodes",
                position: 1,
            },
            dk_status::DK_ERR_NOT_PLANAR,
            28,
        ),
        (
            Error::BadPlan {
                reason: "checksum mismatch",
            },
            dk_status::DK_ERR_BAD_PLAN,
            29,
        ),
        (
            Error::SharedFreeEnd { point: 7, other: 3 },
            dk_status::DK_ERR_SHARED_FREE_END,
            30,
        ),
        (
            Error::BadPartition {
                fault: deform_kernel::error::PartitionFault::Pattern,
                position: 0,
            },
            dk_status::DK_ERR_BAD_PARTITION,
            31,
        ),
    ];
    for (error, status, code) in cases {
        assert_eq!(dk_status::from(error), status);
        assert_eq!(status as i32, code);
        let text =
            unsafe { core::ffi::CStr::from_ptr(deform_kernel_ffi::status::dk_status_str(code)) };
        let text = text.to_str().expect("UTF-8");
        assert!(!text.contains("unknown"), "{code}: {text}");
    }
}

/// `dk_taubin_smooth_arclength_ends`: a free outer face gives the kernel's bits; faces that
/// cannot be free and free ends on a seam are refused with `points` unchanged.
#[test]
fn taubin_smooth_arclength_ends_frees_the_outer_face_and_refuses_the_rest() {
    use deform_kernel::taubin::{
        smooth_arclength, smooth_arclength_scratch_len, LineEnd, SmoothOptions,
    };
    use deform_kernel::{Block, Direction};
    use deform_kernel_ffi::taubin::{
        dk_smooth_arclength_options, dk_smooth_arclength_options_default, dk_smooth_report,
        dk_taubin_smooth_arclength_ends, DK_FACE_IMAX, DK_FACE_KMAX, DK_FACE_KMIN,
    };
    let dims = [5usize, 4, 6];
    let n = dims.iter().product::<usize>();
    let grid: Vec<[f64; 3]> = (0..n)
        .map(|p| {
            let (l, k) = (p % 20, p / 20);
            let len = 1.0 + 0.01 * ((l * 7) % 5) as f64;
            [
                (l % 5) as f64,
                (l / 5) as f64,
                len * (k as f64 / 5.0).powf(1.3),
            ]
        })
        .collect();
    let block = Block::new(dims).unwrap();
    let len = smooth_arclength_scratch_len::<3>(&block, Direction::K, None);
    let mut want = grid.clone();
    let mut o = SmoothOptions::new(Direction::K);
    o.ends[1] = LineEnd::Free;
    smooth_arclength(&block, &mut want, &o, &mut vec![0.0; len]).unwrap();

    let mut options = std::mem::MaybeUninit::<dk_smooth_arclength_options>::uninit();
    // SAFETY: `options` is one writable options struct.
    let s = unsafe { dk_smooth_arclength_options_default(2, options.as_mut_ptr()) };
    assert_eq!(s, dk_status::DK_OK);
    // SAFETY: written by the call above.
    let mut options = unsafe { options.assume_init() };
    let run = |pts: &mut Vec<[f64; 3]>, faces: u32, options: &dk_smooth_arclength_options| {
        let mut scratch = vec![0.0; len];
        let mut report = std::mem::MaybeUninit::<dk_smooth_report>::zeroed();
        // SAFETY: `pts` holds 3 n scalars, `scratch` `len`, `report` is one report.
        unsafe {
            dk_taubin_smooth_arclength_ends(
                dims[0],
                dims[1],
                dims[2],
                options,
                faces,
                pts.as_mut_ptr().cast(),
                3 * n,
                3,
                scratch.as_mut_ptr(),
                len,
                report.as_mut_ptr(),
            )
        }
    };
    let mut got = grid.clone();
    assert_eq!(run(&mut got, DK_FACE_KMAX, &options), dk_status::DK_OK);
    assert_eq!(got, want);
    let mut fixed = grid.clone();
    assert_eq!(run(&mut fixed, 0, &options), dk_status::DK_OK);
    assert_eq!(fixed[n - 20..], grid[n - 20..]);
    for faces in [DK_FACE_KMIN, DK_FACE_IMAX | DK_FACE_KMAX, 64] {
        let mut p = grid.clone();
        assert_eq!(
            run(&mut p, faces, &options),
            dk_status::DK_ERR_INVALID_PARAMETER
        );
        assert_eq!(p, grid);
    }
    let mut seam = grid.clone();
    seam[n - 19] = seam[n - 20];
    let before = seam.clone();
    assert_eq!(
        run(&mut seam, DK_FACE_KMAX, &options),
        dk_status::DK_ERR_SHARED_FREE_END
    );
    assert_eq!(seam, before);
    options.normalised = 1;
    let mut p = grid.clone();
    assert_eq!(
        run(&mut p, DK_FACE_KMAX, &options),
        dk_status::DK_ERR_INVALID_PARAMETER
    );
    assert_eq!(p, grid);
}
