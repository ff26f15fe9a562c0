//! Propagation of `(Δ, Q)` (inverse distance, TFI, displacement TFI) against the naive `f64`
//! reference, the arbitrary-deformation property (boundary points reproduced bit for bit by
//! every pipeline, in `f32` and `f64`, 2D and 3D), and typed errors with outputs unchanged.

#[path = "../support/mod.rs"]
mod support;

use deform_host_tests::deformation_ref as r;
use deform_kernel::quality::inverted_cells;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len, deform_tfi,
    deform_tfi_scratch_len, displacement_tfi, propagate_idw, propagate_spring_scratch_len,
    propagate_tfi, tfi_scratch_len, update_points, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::Directions;
use deform_kernel::{graph_from_cells, graph_from_cells_len, Block, Error, Graph, Quat, Real};
use support::quaternion::{bits, block2, block3, to3, TestMesh};

/// A deterministic pseudo-random value in `[-1, 1)` (splitmix64).
fn rnd(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Random boundary values: translations in `[-1, 1)`, unit quaternions near a common
/// rotation with random signs (the kernel must hemisphere-align them).
fn random_values<const D: usize>(n: usize, seed: u64) -> (Vec<[f64; D]>, Vec<Quat<f64>>) {
    let mut s = seed;
    let t = (0..n).map(|_| [(); D].map(|_| rnd(&mut s))).collect();
    let q = (0..n)
        .map(|_| {
            let v = [
                0.8 + 0.1 * rnd(&mut s),
                0.3 * rnd(&mut s),
                0.3 * rnd(&mut s),
                0.5 + 0.2 * rnd(&mut s),
            ];
            let v = if D == 2 { [v[0], 0.0, 0.0, v[3]] } else { v };
            let q = Quat::from_array(v).normalize().unwrap();
            if rnd(&mut s) < 0.0 {
                -q
            } else {
                q
            }
        })
        .collect();
    (t, q)
}

fn qdiff(a: Quat<f64>, b: [f64; 4]) -> f64 {
    let s = if a.dot(Quat::from_array(b)) < 0.0 {
        -1.0
    } else {
        1.0
    };
    (0..4)
        .map(|c| (s * a.to_array()[c] - b[c]).abs())
        .fold(0.0, f64::max)
}

fn idw_parity<const D: usize>(m: &TestMesh<D>, p: f64) {
    let n = m.points.len();
    let (bt, bq) = random_values::<D>(m.boundary.len(), 42);
    let mut t = vec![[f64::NAN; D]; n];
    let mut q = vec![Quat::new(f64::NAN, 0.0, 0.0, 0.0); n];
    for (k, &i) in m.boundary.iter().enumerate() {
        t[i as usize] = bt[k];
        q[i as usize] = bq[k];
    }
    propagate_idw(&m.points, &m.boundary, p, &mut t, &mut q).unwrap();
    let p3: Vec<[f64; 3]> = m.points.iter().map(|&x| to3(x)).collect();
    let b: Vec<usize> = m.boundary.iter().map(|&i| i as usize).collect();
    let bt3: Vec<[f64; 3]> = bt.iter().map(|&x| to3(x)).collect();
    let bq4: Vec<[f64; 4]> = bq.iter().map(|x| x.to_array()).collect();
    let (et, eq) = r::idw(&p3, &b, &bt3, &bq4, p);
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for c in 0..D {
            worst = worst.max((t[i][c] - et[i][c]).abs());
        }
        worst = worst.max(qdiff(q[i], eq[i]));
    }
    println!("{D}D IDW p = {p}: max diff {worst:.2e}");
    assert!(worst < 1e-13, "{worst}");
    // Boundary entries untouched, bit for bit.
    for (k, &i) in m.boundary.iter().enumerate() {
        assert_eq!(bits(&[t[i as usize]]), bits(&[bt[k]]));
        assert_eq!(q[i as usize], bq[k]);
    }
}

#[test]
fn idw_matches_reference() {
    for p in [2.0, 3.0, 5.5] {
        idw_parity(&block2(11, 7), p);
        idw_parity(&block3(5, 5, 4), p);
    }
}

/// Fills face values of a block from random values at every point, runs the kernel TFI and
/// the written-out reference, and compares.
fn tfi_parity<const D: usize>(m: &TestMesh<D>, dirs: [bool; 3]) {
    let n = m.points.len();
    let block = m.block();
    let (t0, q0) = random_values::<D>(n, 7);
    // Keep quaternions in one hemisphere for the reference (the kernel aligns itself).
    let q_aligned: Vec<Quat<f64>> = q0.iter().map(|&q| if q.w < 0.0 { -q } else { q }).collect();
    let mut t = t0.clone();
    let mut q = q0.clone();
    let mut s = vec![0.0; tfi_scratch_len::<D>(&block)];
    propagate_tfi(
        &block,
        Directions::from_flags(dirs),
        &m.points,
        &mut t,
        &mut q,
        &mut s,
    )
    .unwrap();
    let mut disp = t0.clone();
    displacement_tfi(
        &block,
        Directions::from_flags(dirs),
        &m.points,
        &mut disp,
        &mut s,
    )
    .unwrap();
    let p3: Vec<[f64; 3]> = m.points.iter().map(|&x| to3(x)).collect();
    let mut f: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut v = t0[i].to_vec();
            v.extend(q_aligned[i].to_array());
            v
        })
        .collect();
    let [ni, nj, _] = m.dims;
    match (D, dirs) {
        (2, [true, true, false]) => r::tfi_2d(&p3, ni, nj, &mut f),
        (2, [false, true, false]) => r::tfi_2d_j(&p3, ni, nj, &mut f),
        (3, [true, true, true]) => r::tfi_3d(&p3, m.dims, &mut f),
        _ => unreachable!(),
    }
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let qn = {
            let v = &f[i][D..];
            let l = v.iter().map(|c| c * c).sum::<f64>().sqrt();
            [v[0] / l, v[1] / l, v[2] / l, v[3] / l]
        };
        for c in 0..D {
            worst = worst.max((t[i][c] - f[i][c]).abs());
            worst = worst.max((disp[i][c] - f[i][c]).abs());
        }
        worst = worst.max(qdiff(q[i], qn));
    }
    println!("{D}D TFI {dirs:?}: max diff {worst:.2e}");
    assert!(worst < 1e-13, "{worst}");
}

#[test]
fn tfi_matches_reference() {
    tfi_parity(&block2(12, 9), [true, true, false]);
    tfi_parity(&block2(12, 9), [false, true, false]);
    tfi_parity(&block3(6, 5, 5), [true, true, true]);
}

/// A uniform field is reproduced by TFI (weights sum to one) to rounding, and face values are
/// never written.
#[test]
fn tfi_reproduces_uniform_field() {
    let m = block3(6, 5, 4);
    let block = m.block();
    let n = m.points.len();
    let q0 = Quat::from_axis_angle([1.0, -2.0, 0.5], 1.3).unwrap();
    let mut t = vec![[0.3, -0.7, 1.9]; n];
    let mut q = vec![q0; n];
    let mut s = vec![0.0; tfi_scratch_len::<3>(&block)];
    propagate_tfi(
        &block,
        Directions::from_flags([true, true, true]),
        &m.points,
        &mut t,
        &mut q,
        &mut s,
    )
    .unwrap();
    for i in 0..n {
        for c in 0..3 {
            assert!((t[i][c] - [0.3, -0.7, 1.9][c]).abs() < 8.0 * f64::EPSILON * 2.0);
        }
        assert!(qdiff(q[i], q0.to_array()) < 8.0 * f64::EPSILON);
    }
}

// ---------------------------------------------------------------------------------------------
// Arbitrary deformation through each pipeline.

fn warp<const D: usize>(p: [f64; D], amount: f64) -> [f64; D] {
    let x = to3(p);
    let a = amount * (0.6 * x[0] + 0.2 * x[2]);
    let (s, c) = a.sin_cos();
    let y = [
        c * x[0] - s * x[1] + 0.05 * amount * x[1] * x[1] + 0.1,
        s * x[0] + c * x[1] + 0.03 * amount * x[0] - 0.05,
        x[2] * (1.0 + 0.1 * amount * x[0]) + 0.05 * amount * x[1],
    ];
    let mut out = [0.0; D];
    out.copy_from_slice(&y[..D]);
    out
}

fn arbitrary<T: Real, const D: usize>(m: &TestMesh<D>, amount: f64) {
    let points = m.points_t::<T>();
    let n = points.len();
    let b = m.boundary.len();
    let deformed: Vec<[T; D]> = m
        .boundary
        .iter()
        .map(|&i| warp(m.points[i as usize], amount).map(T::from_f64))
        .collect();
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: Some(m.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let cells = m.cells();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
    let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![T::ZERO; used];
    batina_stiffness(&graph, &points, T::ONE, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    for &i in &m.boundary {
        fixed[i as usize] = 1;
    }
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut ss).unwrap();
    let method = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    for which in 0..3 {
        let mut t = vec![[T::ZERO; D]; n];
        let mut q = vec![Quat::identity(); n];
        let mut out = vec![[T::ZERO; D]; n];
        let block = m.block();
        let mut s = vec![
            T::ZERO;
            deform_idw_scratch_len::<D>(n, b)
                .max(deform_tfi_scratch_len::<D>(&block, b))
                .max(deform_spring_scratch_len::<D>(n, b))
        ];
        let mut values = vec![T::ZERO; propagate_spring_scratch_len::<D>(&method, n)];
        match which {
            0 => {
                deform_idw(
                    &points,
                    &motion,
                    T::from_f64(3.0),
                    &mut t,
                    &mut q,
                    &mut s,
                    &mut out,
                )
                .unwrap();
            }
            1 => {
                deform_tfi(
                    &block,
                    Directions::from_flags([true, true, D == 3]),
                    &points,
                    &motion,
                    &mut t,
                    &mut q,
                    &mut s,
                    &mut out,
                )
                .unwrap();
            }
            _ => {
                let (_, rep) = deform_spring(
                    &points,
                    &motion,
                    &sys,
                    method,
                    &SolveOptions::default(),
                    &mut t,
                    &mut q,
                    &mut s,
                    &mut values,
                    &mut out,
                )
                .unwrap();
                assert!(rep.converged);
            }
        }
        let got: Vec<[T; D]> = m.boundary.iter().map(|&i| out[i as usize]).collect();
        assert_eq!(
            bits(&got),
            bits(&deformed),
            "method {which}: boundary not bitwise"
        );
        assert!(out.iter().all(|p| p.iter().all(|c| c.is_finite())));
        let inv = inverted_cells(&cells, &points, &out).unwrap();
        println!(
            "{D}D {} method {which} warp {amount}: {inv} inverted cells",
            core::any::type_name::<T>()
        );
        // A mild warp must not invert anything; stronger warps are reported only (no
        // propagation method guarantees validity for arbitrary boundary motion).
        if amount <= 0.3 {
            assert_eq!(inv, 0);
        }
    }
}

#[test]
fn arbitrary_deformation_reproduces_boundary_bitwise() {
    for amount in [0.3, 0.8] {
        arbitrary::<f64, 2>(&block2(14, 10), amount);
        arbitrary::<f32, 2>(&block2(14, 10), amount);
        arbitrary::<f64, 3>(&block3(6, 6, 5), amount);
        arbitrary::<f32, 3>(&block3(6, 6, 5), amount);
    }
}

// ---------------------------------------------------------------------------------------------
// Errors, outputs unchanged.

const SENTINEL: f64 = -3.5;

#[test]
fn propagate_idw_errors() {
    let m = block2(6, 5);
    let n = m.points.len();
    let mut t = vec![[SENTINEL; 2]; n];
    let mut q = vec![Quat::identity(); n];
    let before = (bits(&t), q.clone());
    let check = |t: &Vec<[f64; 2]>, q: &Vec<Quat<f64>>| {
        assert_eq!(bits(t), before.0);
        assert_eq!(*q, before.1);
    };
    assert!(matches!(
        propagate_idw(&m.points, &[], 2.0, &mut t, &mut q),
        Err(Error::InvalidParameter {
            arg: "boundary",
            ..
        })
    ));
    for p in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            propagate_idw(&m.points, &m.boundary, p, &mut t, &mut q),
            Err(Error::InvalidParameter {
                arg: "exponent",
                ..
            })
        ));
    }
    assert_eq!(
        propagate_idw(&m.points, &[0, 99], 2.0, &mut t, &mut q),
        Err(Error::IndexOutOfRange {
            arg: "boundary",
            position: 1,
            index: 99,
            bound: n
        })
    );
    let mut pts = m.points.clone();
    pts[4][1] = f64::NAN;
    assert_eq!(
        propagate_idw(&pts, &m.boundary, 2.0, &mut t, &mut q),
        Err(Error::NonFinite {
            arg: "points",
            position: 4
        })
    );
    check(&t, &q);
    // A NaN boundary translation, a zero boundary rotation.
    let bnode = m.boundary[3] as usize;
    let mut t2 = t.clone();
    t2[bnode][0] = f64::NAN;
    let before2 = bits(&t2);
    assert_eq!(
        propagate_idw(&m.points, &m.boundary, 2.0, &mut t2, &mut q),
        Err(Error::NonFinite {
            arg: "translations",
            position: bnode
        })
    );
    assert_eq!(bits(&t2), before2);
    let mut q2 = q.clone();
    q2[bnode] = Quat::new(0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        propagate_idw(&m.points, &m.boundary, 2.0, &mut t, &mut q2),
        Err(Error::ZeroLength {
            arg: "rotations",
            position: bnode
        })
    );
    check(&t, &q);
    assert!(matches!(
        propagate_idw(&m.points, &m.boundary, 2.0, &mut t[..3], &mut q),
        Err(Error::LengthMismatch {
            arg: "translations",
            ..
        })
    ));
}

#[test]
fn tfi_errors() {
    let m = block2(6, 5);
    let block = m.block();
    let n = m.points.len();
    let mut t = vec![[SENTINEL; 2]; n];
    let mut q = vec![Quat::identity(); n];
    let mut s = vec![0.0; tfi_scratch_len::<2>(&block)];
    let before = bits(&t);
    for dirs in [[false, false, false], [true, true, true]] {
        assert!(matches!(
            propagate_tfi(
                &block,
                Directions::from_flags(dirs),
                &m.points,
                &mut t,
                &mut q,
                &mut s
            ),
            Err(Error::InvalidParameter {
                arg: "directions",
                ..
            })
        ));
    }
    t[2][0] = f64::NAN; // on the j = 0 face
    let before_nan = bits(&t);
    assert_eq!(
        propagate_tfi(
            &block,
            Directions::from_flags([true, true, false]),
            &m.points,
            &mut t,
            &mut q,
            &mut s
        ),
        Err(Error::NonFinite {
            arg: "translations",
            position: 2
        })
    );
    assert_eq!(
        displacement_tfi(
            &block,
            Directions::from_flags([true, true, false]),
            &m.points,
            &mut t,
            &mut s
        ),
        Err(Error::NonFinite {
            arg: "displacements",
            position: 2
        })
    );
    assert_eq!(bits(&t), before_nan);
    t[2][0] = SENTINEL;
    assert_eq!(bits(&t), before);
    q[0] = Quat::new(0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        propagate_tfi(
            &block,
            Directions::from_flags([true, true, false]),
            &m.points,
            &mut t,
            &mut q,
            &mut s
        ),
        Err(Error::ZeroLength {
            arg: "rotations",
            position: 0
        })
    );
    q[0] = Quat::identity();
    assert!(matches!(
        propagate_tfi(
            &block,
            Directions::from_flags([true, true, false]),
            &m.points,
            &mut t,
            &mut q,
            &mut s[..3]
        ),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    let wrong = Block::new([5, 6, 1]).unwrap();
    assert!(matches!(
        propagate_tfi(
            &wrong,
            Directions::from_flags([true, true, false]),
            &m.points[..29],
            &mut t,
            &mut q,
            &mut s
        ),
        Err(Error::LengthMismatch { .. })
    ));
    // The interior was never written.
    assert_eq!(bits(&t), before);
    assert!(q.iter().all(|x| *x == Quat::identity()));
}

#[test]
fn update_points_errors() {
    let m = block2(5, 4);
    let n = m.points.len();
    let t = vec![[0.0; 2]; n];
    let q = vec![Quat::identity(); n];
    let d: Vec<[f64; 2]> = m.boundary.iter().map(|&i| m.points[i as usize]).collect();
    let mut out = vec![[SENTINEL; 2]; n];
    let before = bits(&out);
    let mut tn = t.clone();
    tn[7][1] = f64::INFINITY;
    assert_eq!(
        update_points([0.0, 0.0], &m.points, &tn, &q, &m.boundary, &d, &mut out),
        Err(Error::NonFinite {
            arg: "translations",
            position: 7
        })
    );
    let mut qz = q.clone();
    qz[5] = Quat::new(0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        update_points([0.0, 0.0], &m.points, &t, &qz, &m.boundary, &d, &mut out),
        Err(Error::ZeroLength {
            arg: "rotations",
            position: 5
        })
    );
    assert!(matches!(
        update_points(
            [0.0, 0.0],
            &m.points,
            &t,
            &q,
            &m.boundary,
            &d[1..],
            &mut out
        ),
        Err(Error::LengthMismatch {
            arg: "boundary_deformed",
            ..
        })
    ));
    assert!(matches!(
        update_points(
            [f64::NAN, 0.0],
            &m.points,
            &t,
            &q,
            &m.boundary,
            &d,
            &mut out
        ),
        Err(Error::NonFinite { arg: "origin", .. })
    ));
    assert_eq!(bits(&out), before);
    // Identity motion: every point unchanged, bit for bit.
    update_points([0.3, 0.1], &m.points, &t, &q, &m.boundary, &d, &mut out).unwrap();
    assert_eq!(bits(&out), bits(&m.points));
}

#[test]
fn pipeline_errors() {
    let m = block2(6, 5);
    let points = m.points.clone();
    let n = points.len();
    let b = m.boundary.len();
    let d: Vec<[f64; 2]> = m
        .boundary
        .iter()
        .map(|&i| warp(points[i as usize], 0.3))
        .collect();
    let mut t = vec![[0.0; 2]; n];
    let mut q = vec![Quat::identity(); n];
    let mut s = vec![0.0; deform_tfi_scratch_len::<2>(&m.block(), b)];
    let mut out = vec![[SENTINEL; 2]; n];
    let before = bits(&out);
    // Duplicate boundary node.
    let mut dup = m.boundary.clone();
    dup[4] = dup[1];
    let motion = BoundaryMotion {
        nodes: &dup,
        deformed: &d,
        elements: Some(m.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    assert_eq!(
        deform_idw(&points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out),
        Err(Error::DuplicateNode {
            arg: "motion.nodes",
            position: 4,
            node: dup[1] as usize
        })
    );
    // Shape rotations without elements.
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &d,
        elements: None,
        rotations: RotationSource::Shape,
        origin: None,
    };
    assert!(matches!(
        deform_idw(&points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out),
        Err(Error::InvalidParameter {
            arg: "motion.elements",
            ..
        })
    ));
    // TFI with a face point missing from the boundary.
    let missing = m.boundary[5];
    let nodes: Vec<u32> = m
        .boundary
        .iter()
        .copied()
        .filter(|&i| i != missing)
        .collect();
    let d2: Vec<[f64; 2]> = nodes.iter().map(|&i| points[i as usize]).collect();
    let motion = BoundaryMotion {
        nodes: &nodes,
        deformed: &d2,
        elements: None,
        rotations: RotationSource::Rigid(Quat::identity()),
        origin: None,
    };
    assert_eq!(
        deform_tfi(
            &m.block(),
            Directions::from_flags([true, true, false]),
            &points,
            &motion,
            &mut t,
            &mut q,
            &mut s,
            &mut out
        ),
        Err(Error::Unanchored {
            node: missing as usize
        })
    );
    // Bad TFI directions: rejected before any workspace is written.
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &d,
        elements: Some(m.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let mut t_s = vec![[SENTINEL; 2]; n];
    let mut q_s = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); n];
    assert!(matches!(
        deform_tfi(
            &m.block(),
            Directions::from_flags([true, false, true]),
            &points,
            &motion,
            &mut t_s,
            &mut q_s,
            &mut s,
            &mut out
        ),
        Err(Error::InvalidParameter {
            arg: "directions",
            ..
        })
    ));
    assert!(t_s.iter().all(|x| *x == [SENTINEL; 2]));
    assert!(q_s.iter().all(|x| x.w == SENTINEL));
    // A NaN deformed position, a wrong-length per-node rotation list.
    let mut dn = d.clone();
    dn[2][0] = f64::NAN;
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &dn,
        elements: Some(m.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    assert_eq!(
        deform_idw(&points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out),
        Err(Error::NonFinite {
            arg: "motion.deformed",
            position: 2
        })
    );
    let given = vec![Quat::identity(); b - 1];
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &d,
        elements: None,
        rotations: RotationSource::PerNode(&given),
        origin: None,
    };
    assert!(matches!(
        deform_idw(&points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out),
        Err(Error::LengthMismatch {
            arg: "motion.rotations",
            ..
        })
    ));
    // Degenerate boundary shape (two boundary points moved onto each other).
    let mut dz = d.clone();
    dz[1] = dz[0];
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &dz,
        elements: Some(m.elements()),
        rotations: RotationSource::Shape,
        origin: None,
    };
    assert_eq!(
        deform_idw(&points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out),
        Err(Error::ZeroLengthEdge { from: 0, to: 1 })
    );
    assert_eq!(bits(&out), before);
}

#[test]
fn spring_errors() {
    use deform_kernel::quaternion::propagate_spring;
    let m = block2(6, 5);
    let n = m.points.len();
    let cells = m.cells();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
    let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&graph, &m.points, 1.0, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    for &i in &m.boundary {
        fixed[i as usize] = 1;
    }
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut ss).unwrap();
    let method = LinearMethod::GaussSeidel;
    let opts = SolveOptions::default();
    let mut t = vec![[SENTINEL; 2]; n];
    let mut q = vec![Quat::identity(); n];
    let before = bits(&t);
    // The workspace is `D + 4` scalars a node plus the solver's: one scalar short is refused.
    let need = propagate_spring_scratch_len::<2>(&method, n);
    let mut values = vec![0.0; need];
    assert_eq!(
        propagate_spring(&sys, method, &opts, &mut t, &mut q, &mut values[..need - 1]),
        Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: need,
            actual: need - 1
        })
    );
    let bnode = m.boundary[2] as usize;
    t[bnode][1] = f64::NAN;
    let before_nan = bits(&t);
    assert_eq!(
        propagate_spring(&sys, method, &opts, &mut t, &mut q, &mut values),
        Err(Error::NonFinite {
            arg: "translations",
            position: bnode
        })
    );
    assert_eq!(bits(&t), before_nan);
    t[bnode][1] = SENTINEL;
    assert!(matches!(
        propagate_spring(&sys, method, &opts, &mut t, &mut q, &mut values[..n - 1]),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    assert_eq!(bits(&t), before);
    assert!(q.iter().all(|x| *x == Quat::identity()));
    // The pipeline: the fixed mask must mark exactly the boundary nodes.
    let fewer: Vec<u32> = m.boundary[1..].to_vec();
    let d: Vec<[f64; 2]> = fewer.iter().map(|&i| m.points[i as usize]).collect();
    let motion = BoundaryMotion {
        nodes: &fewer,
        deformed: &d,
        elements: None,
        rotations: RotationSource::Rigid(Quat::identity()),
        origin: None,
    };
    let mut s = vec![0.0; deform_spring_scratch_len::<2>(n, fewer.len())];
    let mut out = vec![[SENTINEL; 2]; n];
    assert!(matches!(
        deform_spring(
            &m.points,
            &motion,
            &sys,
            method,
            &opts,
            &mut t,
            &mut q,
            &mut s,
            &mut values,
            &mut out
        ),
        Err(Error::InvalidParameter { arg: "sys", .. })
    ));
    assert_eq!(bits(&out), before);
}
