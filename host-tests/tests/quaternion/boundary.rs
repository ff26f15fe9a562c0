//! Boundary normals, rotations and translations (Samareh steps 1–3) against the naive `f64`
//! reference in `deform_host_tests::deformation_ref`, plus the degenerate inputs that must give
//! typed errors with every output left bit-for-bit unchanged.

#[path = "../support/mod.rs"]
mod support;

use deform_host_tests::deformation_ref as r;
use deform_kernel::quaternion::{
    boundary_normals, boundary_normals_scratch_len, boundary_origin, boundary_rotations,
    boundary_rotations_scratch_len, boundary_translations, rigid_rotations,
};
use deform_kernel::{Cells, Error, Quat};
use support::quaternion::{bits, block2, block3, to3, TestMesh};

/// A smooth, non-rigid deformation (bending, stretching, twisting); `amount` 0 is the identity.
fn warp<const D: usize>(p: [f64; D], amount: f64) -> [f64; D] {
    let x = to3(p);
    let a = amount * (0.8 * x[0] + 0.3 * x[2]);
    let (s, c) = a.sin_cos();
    let y = [
        c * x[0] - s * x[1] + 0.1 * amount * x[1] * x[1],
        s * x[0] + c * x[1] + 0.05 * amount * x[0],
        x[2] * (1.0 + 0.2 * amount * x[0]) + 0.1 * amount * x[1],
    ];
    let mut out = [0.0; D];
    out.copy_from_slice(&y[..D]);
    out
}

/// The boundary elements in the reference's form.
fn ref_elements<const D: usize>(m: &TestMesh<D>) -> Vec<r::Element> {
    (0..m.el_kinds.len())
        .map(|e| {
            let a = m.el_offsets[e] as usize;
            let b = m.el_offsets[e + 1] as usize;
            (
                m.el_kinds[e],
                m.el_nodes[a..b].iter().map(|&n| n as usize).collect(),
            )
        })
        .collect()
}

/// Undeformed and warped boundary points of a mesh.
fn boundary_points<const D: usize>(m: &TestMesh<D>, amount: f64) -> (Vec<[f64; D]>, Vec<[f64; D]>) {
    let u: Vec<[f64; D]> = m.boundary.iter().map(|&i| m.points[i as usize]).collect();
    let d = u.iter().map(|&p| warp(p, amount)).collect();
    (u, d)
}

fn normals_parity<const D: usize>(m: &TestMesh<D>) {
    let el = m.elements();
    let refel = ref_elements(m);
    for amount in [0.0, 0.3, 0.9] {
        let (_, d) = boundary_points(m, amount);
        let mut s = vec![0.0; boundary_normals_scratch_len(d.len())];
        let mut n = vec![[0.0; D]; d.len()];
        boundary_normals(&d, &el, &mut s, &mut n).unwrap();
        let d3: Vec<[f64; 3]> = d.iter().map(|&p| to3(p)).collect();
        let expect = r::node_normals(&d3, &refel);
        let mut worst: f64 = 0.0;
        for (a, b) in n.iter().zip(&expect) {
            let b = b.expect("reference normal");
            for k in 0..D {
                worst = worst.max((a[k] - b[k]).abs());
            }
        }
        println!("{D}D normals, warp {amount}: max diff {worst:.2e}");
        assert!(worst < 1e-13, "{worst}");
        // f32 agrees to f32 rounding.
        let d32: Vec<[f32; D]> = d.iter().map(|p| p.map(|x| x as f32)).collect();
        let mut s32 = vec![0.0f32; s.len()];
        let mut n32 = vec![[0.0f32; D]; d.len()];
        boundary_normals(&d32, &el, &mut s32, &mut n32).unwrap();
        for (a, b) in n32.iter().zip(&n) {
            for k in 0..D {
                assert!((a[k] as f64 - b[k]).abs() < 1e-5);
            }
        }
    }
}

#[test]
fn normals_match_reference_2d() {
    normals_parity(&block2(11, 7));
}

#[test]
fn normals_match_reference_3d() {
    normals_parity(&block3(6, 5, 4));
}

/// Normals point out of the domain for the test meshes (oriented elements).
#[test]
fn normals_point_outward() {
    let m = block2(9, 6);
    let (u, _) = boundary_points(&m, 0.0);
    let mut s = vec![0.0; boundary_normals_scratch_len(u.len())];
    let mut n = vec![[0.0; 2]; u.len()];
    boundary_normals(&u, &m.elements(), &mut s, &mut n).unwrap();
    let c = u.iter().fold([0.0, 0.0], |a, p| [a[0] + p[0], a[1] + p[1]]);
    let c = [c[0] / u.len() as f64, c[1] / u.len() as f64];
    for (p, nn) in u.iter().zip(&n) {
        assert!((p[0] - c[0]) * nn[0] + (p[1] - c[1]) * nn[1] > 0.0);
    }
}

#[test]
fn rotations_2d_match_reference() {
    let m = block2(13, 8);
    let refel = ref_elements(&m);
    let segs: Vec<[usize; 2]> = refel.iter().map(|e| [e.1[0], e.1[1]]).collect();
    for amount in [0.2, 0.8, 2.0] {
        let (u, d) = boundary_points(&m, amount);
        let mut s = vec![0.0; boundary_rotations_scratch_len::<2>(u.len())];
        let mut q = vec![Quat::identity(); u.len()];
        boundary_rotations(&u, &d, &m.elements(), &mut s, &mut q).unwrap();
        let expect = r::rotation_angles_2d(&u, &d, &segs);
        let mut worst: f64 = 0.0;
        for (a, &b) in q.iter().zip(&expect) {
            assert_eq!((a.x, a.y), (0.0, 0.0), "2D rotations are about z");
            let diff = (a.rotation_z_angle() - b).rem_euclid(2.0 * std::f64::consts::PI);
            let diff = diff.min(2.0 * std::f64::consts::PI - diff);
            worst = worst.max(diff);
        }
        println!("2D rotations, warp {amount}: max angle diff {worst:.2e}");
        assert!(worst < 1e-13, "{worst}");
    }
}

#[test]
fn rotations_3d_match_reference() {
    let m = block3(6, 5, 4);
    let refel = ref_elements(&m);
    for amount in [0.2, 0.7] {
        let (u, d) = boundary_points(&m, amount);
        let mut s = vec![0.0; boundary_rotations_scratch_len::<3>(u.len())];
        let mut q = vec![Quat::identity(); u.len()];
        boundary_rotations(&u, &d, &m.elements(), &mut s, &mut q).unwrap();
        let expect = r::rotations_3d(&u, &d, &refel);
        let mut worst: f64 = 0.0;
        for (a, b) in q.iter().zip(&expect) {
            worst = worst.max(r::mat_diff(&r::quat_matrix([a.w, a.x, a.y, a.z]), b));
        }
        println!("3D rotations, warp {amount}: max matrix diff {worst:.2e}");
        assert!(worst < 1e-12, "{worst}");
    }
}

/// A thin closed section with a sharp trailing edge (edge normals ~160° apart there), turned
/// rigidly: every node, the trailing edge included, must get the rigid angle.
#[test]
fn sharp_trailing_edge_2d() {
    // Upper and lower surfaces of a thin lens from x = 0 to x = 1, counter-clockwise,
    // trailing edge at node 0 with a 20° included angle.
    let k = 12;
    let mut u = Vec::new();
    for i in 0..k {
        let x = 1.0 - i as f64 / k as f64;
        u.push([x, 0.09 * x * (1.0 - x) * 4.0 * (1.0 - 0.5 * x) + 0.0]);
    }
    for i in 0..k {
        let x = i as f64 / k as f64;
        u.push([x, -0.06 * x * (1.0 - x) * 4.0]);
    }
    let b = u.len() as u32;
    let mut off = vec![0u32];
    let mut nodes = Vec::new();
    let mut kinds = Vec::new();
    for e in 0..b {
        nodes.extend([e, (e + 1) % b]);
        kinds.push(3u8);
        off.push(nodes.len() as u32);
    }
    let el = Cells::new(u.len(), &off, &nodes, &kinds).unwrap();
    // Included angle at the trailing edge (node 0).
    let t1 = [u[1][0] - u[0][0], u[1][1] - u[0][1]];
    let t0 = [
        u[0][0] - u[b as usize - 1][0],
        u[0][1] - u[b as usize - 1][1],
    ];
    let turn = (t0[0] * t1[1] - t0[1] * t1[0]).atan2(t0[0] * t1[0] + t0[1] * t1[1]);
    assert!(turn.abs().to_degrees() > 150.0, "{}", turn.to_degrees());
    for deg in [10.0f64, 25.0, 50.0, 170.0, -179.0] {
        let a = deg.to_radians();
        let (s, c) = a.sin_cos();
        let d: Vec<[f64; 2]> = u
            .iter()
            .map(|p| {
                [
                    c * (p[0] - 0.25) - s * p[1] + 0.25,
                    s * (p[0] - 0.25) + c * p[1],
                ]
            })
            .collect();
        let mut sc = vec![0.0; boundary_rotations_scratch_len::<2>(u.len())];
        let mut q = vec![Quat::identity(); u.len()];
        boundary_rotations(&u, &d, &el, &mut sc, &mut q).unwrap();
        for (i, qi) in q.iter().enumerate() {
            let diff = (qi.rotation_z_angle() - a).rem_euclid(2.0 * std::f64::consts::PI);
            let diff = diff.min(2.0 * std::f64::consts::PI - diff);
            assert!(diff < 1e-13, "node {i}, {deg}°: {diff}");
        }
    }
}

#[test]
fn translations_reproduce_boundary() {
    for amount in [0.3, 1.1] {
        let m = block3(5, 5, 4);
        let (u, d) = boundary_points(&m, amount);
        let mut s = vec![0.0; boundary_rotations_scratch_len::<3>(u.len())];
        let mut q = vec![Quat::identity(); u.len()];
        boundary_rotations(&u, &d, &m.elements(), &mut s, &mut q).unwrap();
        let o = boundary_origin(&u, &d).unwrap();
        let mut t = vec![[0.0; 3]; u.len()];
        boundary_translations(o, &u, &d, &q, &mut t).unwrap();
        for k in 0..u.len() {
            let mat = r::quat_matrix([q[k].w, q[k].x, q[k].y, q[k].z]);
            let back = r::apply(o, u[k], t[k], &mat);
            for c in 0..3 {
                assert!((back[c] - d[k][c]).abs() < 1e-14, "{k}");
            }
        }
    }
}

#[test]
fn origin_is_centroid_of_moving_points() {
    let u = [[0.0, 0.0], [1.0, 0.0], [5.0, 1.0], [7.0, 3.0]];
    let d = [[0.0, 0.0], [1.0, 0.5], [5.0, 1.0], [7.5, 3.0]];
    assert_eq!(boundary_origin(&u, &d).unwrap(), [4.0, 1.5]);
    // Nothing moves: centroid of all.
    assert_eq!(boundary_origin(&u, &u).unwrap(), [3.25, 1.0]);
    assert!(matches!(
        boundary_origin::<f64, 2>(&[], &[]),
        Err(Error::InvalidParameter { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Degenerate input: typed errors, outputs unchanged.

const SENTINEL: f64 = 7.25;

fn lines(pairs: &[[u32; 2]]) -> (Vec<u32>, Vec<u32>, Vec<u8>) {
    let mut off = vec![0u32];
    let mut nodes = Vec::new();
    for p in pairs {
        nodes.extend(p);
        off.push(nodes.len() as u32);
    }
    (off, nodes, vec![3u8; pairs.len()])
}

/// Runs normals and rotations on 2D input and checks both fail with `want`, outputs untouched.
fn expect_2d_error(
    u: &[[f64; 2]],
    d: &[[f64; 2]],
    pairs: &[[u32; 2]],
    want: Error,
    rot_want: Error,
) {
    let (off, nodes, kinds) = lines(pairs);
    let el = Cells::new(u.len(), &off, &nodes, &kinds).unwrap();
    let mut s = vec![0.0; 64];
    let mut n = vec![[SENTINEL; 2]; u.len()];
    let before = bits(&n);
    assert_eq!(boundary_normals(d, &el, &mut s, &mut n), Err(want));
    assert_eq!(bits(&n), before);
    let mut q = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); u.len()];
    assert_eq!(boundary_rotations(u, d, &el, &mut s, &mut q), Err(rot_want));
    assert!(q.iter().all(|x| x.w == SENTINEL));
}

#[test]
fn antiparallel_normals_are_an_error() {
    // Polyline 0-1-2 folding back on itself at node 1: the two segment normals cancel.
    let u = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
    let d = [[0.0, 0.0], [1.0, 0.0], [0.0, 0.0]];
    let (off, nodes, kinds) = lines(&[[0, 1], [1, 2]]);
    let el = Cells::new(3, &off, &nodes, &kinds).unwrap();
    let mut s = vec![0.0; 9];
    let mut n = vec![[SENTINEL; 2]; 3];
    assert_eq!(
        boundary_normals(&d, &el, &mut s, &mut n),
        Err(Error::ZeroLength {
            arg: "normals",
            position: 1
        })
    );
    assert!(n.iter().all(|x| *x == [SENTINEL; 2]));
    let _ = u;
    // 3D: a triangle glued to itself with the opposite orientation (a folded sheet).
    let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let el = Cells::new(3, &[0, 3, 6], &[0, 1, 2, 0, 2, 1], &[5, 5]).unwrap();
    let mut s = vec![0.0; boundary_rotations_scratch_len::<3>(3)];
    let mut n = vec![[SENTINEL; 3]; 3];
    assert_eq!(
        boundary_normals(&p, &el, &mut s, &mut n),
        Err(Error::ZeroLength {
            arg: "normals",
            position: 0
        })
    );
    let mut q = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); 3];
    assert_eq!(
        boundary_rotations(&p, &p, &el, &mut s, &mut q),
        Err(Error::ZeroLength {
            arg: "normals",
            position: 0
        })
    );
    assert!(n.iter().all(|x| *x == [SENTINEL; 3]));
    assert!(q.iter().all(|x| x.w == SENTINEL));
}

#[test]
fn node_without_elements_is_an_error() {
    let u = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5], [3.0, 3.0]];
    expect_2d_error(
        &u,
        &u,
        &[[0, 1], [1, 2]],
        Error::IsolatedNode { node: 3 },
        Error::IsolatedNode { node: 3 },
    );
    // 3D: a node no face uses.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [4.0, 4.0, 4.0],
    ];
    let el = Cells::new(4, &[0, 3], &[0, 1, 2], &[5]).unwrap();
    let mut s = vec![0.0; boundary_rotations_scratch_len::<3>(4)];
    let mut q = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); 4];
    assert_eq!(
        boundary_rotations(&p, &p, &el, &mut s, &mut q),
        Err(Error::IsolatedNode { node: 3 })
    );
    assert!(q.iter().all(|x| x.w == SENTINEL));
}

#[test]
fn nan_is_an_error() {
    let u = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5]];
    let mut d = u;
    d[2][1] = f64::NAN;
    expect_2d_error(
        &u,
        &d,
        &[[0, 1], [1, 2]],
        Error::NonFinite {
            arg: "points",
            position: 2,
        },
        Error::NonFinite {
            arg: "deformed",
            position: 2,
        },
    );
    let mut t = vec![[SENTINEL; 2]; 3];
    let q = [Quat::identity(); 3];
    assert_eq!(
        boundary_translations([0.0, f64::INFINITY], &u, &u, &q, &mut t),
        Err(Error::NonFinite {
            arg: "origin",
            position: 0
        })
    );
    let mut bad_q = q;
    bad_q[1] = Quat::new(0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        boundary_translations([0.0, 0.0], &u, &u, &bad_q, &mut t),
        Err(Error::ZeroLength {
            arg: "rotations",
            position: 1
        })
    );
    assert!(t.iter().all(|x| *x == [SENTINEL; 2]));
}

#[test]
fn zero_length_edge_is_an_error() {
    let u = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5]];
    let d = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]];
    let (off, nodes, kinds) = lines(&[[0, 1], [1, 2]]);
    let el = Cells::new(3, &off, &nodes, &kinds).unwrap();
    let mut s = vec![0.0; 9];
    let mut q = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); 3];
    assert_eq!(
        boundary_rotations(&u, &d, &el, &mut s, &mut q),
        Err(Error::ZeroLengthEdge { from: 1, to: 2 })
    );
    assert!(q.iter().all(|x| x.w == SENTINEL));
}

#[test]
fn bad_sizes_and_kinds_are_errors() {
    let u = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5]];
    let (off, nodes, kinds) = lines(&[[0, 1], [1, 2]]);
    let el = Cells::new(3, &off, &nodes, &kinds).unwrap();
    let mut q = vec![Quat::new(SENTINEL, 0.0, 0.0, 0.0); 3];
    let mut s = vec![0.0; 8];
    assert!(matches!(
        boundary_rotations(&u, &u, &el, &mut s, &mut q),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    let mut s = vec![0.0; 9];
    assert!(matches!(
        boundary_rotations(&u, &u[..2], &el, &mut s, &mut q),
        Err(Error::LengthMismatch {
            arg: "deformed",
            ..
        })
    ));
    // Triangles are not 2D boundary elements.
    let tri = Cells::new(3, &[0, 3], &[0, 1, 2], &[5]).unwrap();
    assert!(matches!(
        boundary_rotations(&u, &u, &tri, &mut s, &mut q),
        Err(Error::CellDimension {
            cell: 0,
            kind: 5,
            dimension: 2
        })
    ));
    assert!(q.iter().all(|x| x.w == SENTINEL));
    // Zero rigid quaternion.
    assert!(rigid_rotations(Quat::new(0.0, 0.0, 0.0, 0.0), &mut q).is_err());
    assert!(rigid_rotations(Quat::new(f64::NAN, 0.0, 0.0, 0.0), &mut q).is_err());
    assert!(q.iter().all(|x| x.w == SENTINEL));
    rigid_rotations(Quat::new(2.0, 0.0, 0.0, 0.0), &mut q).unwrap();
    assert!(q.iter().all(|x| *x == Quat::identity()));
}

#[test]
fn localize_nodes_renumbers_and_validates() {
    use deform_kernel::quaternion::{localize_nodes, localize_nodes_scratch_len};
    let boundary = [7u32, 3, 9, 0];
    let global = [3u32, 9, 9, 0, 7, 3];
    let mut scratch = vec![0u32; localize_nodes_scratch_len(10)];
    let mut local = vec![99u32; global.len()];
    localize_nodes(10, &boundary, &global, &mut scratch, &mut local).unwrap();
    // Independent check: position of each global node in `boundary`.
    let expect: Vec<u32> = global
        .iter()
        .map(|g| boundary.iter().position(|b| b == g).unwrap() as u32)
        .collect();
    assert_eq!(local, expect);
    let mut local = vec![99u32; global.len()];
    assert_eq!(
        localize_nodes(10, &boundary, &[3, 5], &mut scratch, &mut local[..2]),
        Err(Error::IndexOutOfRange {
            arg: "global",
            position: 1,
            index: 5,
            bound: 4
        })
    );
    assert_eq!(
        localize_nodes(10, &[1, 2, 1], &[1], &mut scratch, &mut local[..1]),
        Err(Error::DuplicateNode {
            arg: "boundary",
            position: 2,
            node: 1
        })
    );
    assert!(matches!(
        localize_nodes(10, &boundary, &[3, 10], &mut scratch, &mut local[..2]),
        Err(Error::IndexOutOfRange { arg: "global", .. })
    ));
    assert!(matches!(
        localize_nodes(10, &boundary, &global, &mut scratch[..9], &mut local),
        Err(Error::BufferTooSmall { .. })
    ));
    assert!(local.iter().all(|&l| l == 99));
}
