//! Bernstein FFD boxes (kernel/src/design/ffd.rs, variables.rs) against an independent numpy
//! tensor-product evaluation (ref_design.py), plus identity, rigid motion, f32, SU2's
//! design-variable control-point changes and error behaviour.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::design::ffd::{
    bernstein, ffd_control_point_count, ffd_displacements, ffd_displacements_between, ffd_eval,
    FfdBox, MAX_DEGREE,
};
use deform_kernel::design::variables::{
    ffd_camber, ffd_camber_2d, ffd_control_point, ffd_control_point_2d, ffd_thickness,
    ffd_thickness_2d,
};
use deform_kernel::Error;
use std::fmt::Write as _;
use std::path::Path;

/// Deterministic numbers in [0, 1) (splitmix64; test data only).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A lattice box (SU2's parallelepiped: P_ijk = origin + (i/l, j/m, k/n) · size) with each
/// control point jittered by up to `jitter`.
fn lattice<const D: usize>(degree: [usize; D], jitter: f64, rng: &mut Rng) -> Vec<[f64; D]> {
    let count = ffd_control_point_count(degree).unwrap();
    let mut out = Vec::with_capacity(count);
    for f in 0..count {
        let mut rest = f;
        let mut p = [0.0; D];
        for a in (0..D).rev() {
            let i = rest % (degree[a] + 1);
            rest /= degree[a] + 1;
            p[a] = -0.3
                + 1.7 * (a as f64 + 1.0) * i as f64 / degree[a] as f64
                + jitter * (rng.next() - 0.5);
        }
        out.push(p);
    }
    out
}

/// Parametric coordinates: random ones (some slightly outside [0, 1]) and the box corners.
fn params<const D: usize>(n: usize, rng: &mut Rng) -> Vec<[f64; D]> {
    let mut out: Vec<[f64; D]> = (0..n)
        .map(|_| core::array::from_fn(|_| -0.05 + 1.1 * rng.next()))
        .collect();
    out.push([0.0; D]);
    out.push([1.0; D]);
    out.push(core::array::from_fn(|a| if a == 0 { 1.0 } else { 0.0 }));
    out
}

/// numpy's evaluation of the box at `uvw`.
fn numpy_eval<const D: usize>(degree: [usize; D], cps: &[[f64; D]], uvw: &[[f64; D]]) -> Vec<f64> {
    let mut text = format!("{D}");
    for d in degree {
        write!(text, " {d}").unwrap();
    }
    text.push('\n');
    for v in cps.iter().flatten() {
        write!(text, "{v:?} ").unwrap();
    }
    text.push('\n');
    for v in uvw.iter().flatten() {
        write!(text, "{v:?} ").unwrap();
    }
    text.push('\n');
    let dir = std::env::temp_dir().join(format!("dk_design_ffd_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One file per call: tests run in parallel threads of one process.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let file = dir.join(format!("ffd_{D}_{:?}_{call}.txt", degree));
    std::fs::write(&file, text).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/design/ref_design.py");
    let out = support::python::run_script(&script, &["ffd", file.to_str().unwrap()]);
    out.lines().map(|l| l.parse().unwrap()).collect()
}

fn compare_to_numpy<const D: usize>(degree: [usize; D], seed: u64) {
    let mut rng = Rng(seed);
    let cps = lattice(degree, 0.4, &mut rng);
    let uvw = params::<D>(60, &mut rng);
    let reference = numpy_eval(degree, &cps, &uvw);
    let ffd = FfdBox::new(degree, &cps).unwrap();
    let mut out = vec![[0.0; D]; uvw.len()];
    ffd_eval(&ffd, &uvw, &mut out).unwrap();
    let scale = cps.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for (o, r) in out.iter().flatten().zip(&reference) {
        worst = worst.max((o - r).abs() / scale);
    }
    assert!(
        worst <= 1e-14,
        "degree {degree:?}: worst relative difference {worst:e}"
    );
}

#[test]
fn three_d_boxes_match_numpy() {
    for (seed, degree) in [[1, 1, 1], [3, 2, 4], [6, 5, 1], [10, 1, 2], [2, 12, 3]]
        .into_iter()
        .enumerate()
    {
        compare_to_numpy(degree, seed as u64 + 1);
    }
}

#[test]
fn two_d_boxes_match_numpy() {
    for (seed, degree) in [[1, 1], [4, 3], [14, 1], [20, 7]].into_iter().enumerate() {
        compare_to_numpy(degree, seed as u64 + 11);
    }
}

#[test]
fn bernstein_follows_su2_special_cases_and_sums_to_one() {
    assert_eq!(bernstein(3, 0, 0.0), 1.0);
    assert_eq!(bernstein(3, 0, 1.0), 0.0);
    assert_eq!(bernstein(3, 3, 0.0), 0.0);
    assert_eq!(bernstein(3, 3, 1.0), 1.0);
    assert_eq!(bernstein(3, 1, 0.0), 0.0);
    assert_eq!(bernstein(3, 4, 0.5), 0.0);
    assert_eq!(bernstein(4, 2, 0.5), 6.0 / 16.0);
    for n in 1..=MAX_DEGREE {
        let s: f64 = (0..=n).map(|i| bernstein(n, i, 0.37)).sum();
        assert!((s - 1.0).abs() < 1e-13, "degree {n}: sum {s}");
    }
}

/// An unjittered lattice is an affine map (linear precision of the Bernstein basis): the box
/// reproduces its parametric coordinates to rounding; and the displacement between a box and
/// itself is exactly zero.
#[test]
fn identity_to_rounding_and_zero_displacement_exactly() {
    let degree = [5, 3, 2];
    let cps = lattice(degree, 0.0, &mut Rng(3));
    let ffd = FfdBox::new(degree, &cps).unwrap();
    let uvw = params::<3>(40, &mut Rng(4));
    for u in &uvw {
        let x = ffd.eval(*u);
        for a in 0..3 {
            let affine = -0.3 + 1.7 * (a as f64 + 1.0) * u[a];
            assert!((x[a] - affine).abs() <= 8e-16 * 6.0, "{x:?} vs {u:?}");
        }
    }
    let mut d = vec![[1.0; 3]; uvw.len()];
    ffd_displacements_between(&ffd, &ffd, &uvw, &mut d).unwrap();
    assert!(d.iter().flatten().all(|&v| v == 0.0));
    // SU2's reference is the mesh point: points that are the box's own evaluations give 0.
    let mut points = vec![[0.0; 3]; uvw.len()];
    ffd_eval(&ffd, &uvw, &mut points).unwrap();
    let nodes: Vec<u32> = (0..uvw.len() as u32).rev().collect();
    let rev: Vec<[f64; 3]> = uvw.iter().rev().copied().collect();
    let mut d = vec![[1.0; 3]; uvw.len()];
    ffd_displacements(&ffd, &points, &nodes, &rev, &mut d).unwrap();
    assert!(d.iter().flatten().all(|&v| v == 0.0));
}

/// Moving every control point rigidly (a rotation plus a translation) moves every surface
/// point the same way, to rounding.
#[test]
fn a_rigidly_moved_box_moves_points_rigidly() {
    let degree = [4, 3, 2];
    let cps = lattice(degree, 0.3, &mut Rng(5));
    let (s, c) = (0.3f64.sin(), 0.3f64.cos());
    let motion = |p: [f64; 3]| {
        [
            c * p[0] - s * p[1] + 0.25,
            s * p[0] + c * p[1] - 0.5,
            p[2] + 1.0,
        ]
    };
    let moved: Vec<[f64; 3]> = cps.iter().map(|&p| motion(p)).collect();
    let (a, b) = (
        FfdBox::new(degree, &cps).unwrap(),
        FfdBox::new(degree, &moved).unwrap(),
    );
    let uvw = params::<3>(50, &mut Rng(6));
    let mut d = vec![[0.0; 3]; uvw.len()];
    ffd_displacements_between(&a, &b, &uvw, &mut d).unwrap();
    for (u, d) in uvw.iter().zip(&d) {
        let x = a.eval(*u);
        let y = motion(x);
        for k in 0..3 {
            assert!((x[k] + d[k] - y[k]).abs() < 1e-14, "{x:?} {d:?} {y:?}");
        }
    }
}

#[test]
fn f32_agrees_with_f64() {
    let degree = [3, 4, 2];
    let cps = lattice(degree, 0.4, &mut Rng(7));
    let cps32: Vec<[f32; 3]> = cps.iter().map(|p| p.map(|v| v as f32)).collect();
    let (a, b) = (
        FfdBox::new(degree, &cps).unwrap(),
        FfdBox::new(degree, &cps32).unwrap(),
    );
    for u in params::<3>(30, &mut Rng(8)) {
        let (x, y) = (a.eval(u), b.eval(u.map(|v| v as f32)));
        for k in 0..3 {
            assert!((x[k] - y[k] as f64).abs() < 2e-6, "{x:?} {y:?}");
        }
    }
}

#[test]
fn control_point_moves_exactly_the_named_points() {
    let degree = [3, 2, 1];
    let cps = lattice(degree, 0.2, &mut Rng(9));
    let ffd = FfdBox::new(degree, &cps).unwrap();
    let mut moved = cps.clone();
    ffd_control_point(
        degree,
        &mut moved,
        [Some(2), Some(1), Some(0)],
        [0.1, -0.2, 0.3],
    )
    .unwrap();
    let hit = ffd.index([2, 1, 0]).unwrap();
    for (f, (a, b)) in cps.iter().zip(&moved).enumerate() {
        if f == hit {
            assert_eq!(*b, [a[0] + 0.1, a[1] - 0.2, a[2] + 0.3]);
        } else {
            assert_eq!(a, b);
        }
    }
    // A -1 (None) index: the whole row along i.
    let mut row = cps.clone();
    ffd_control_point(degree, &mut row, [None, Some(1), Some(1)], [0.0, 1.0, 0.0]).unwrap();
    let changed = cps.iter().zip(&row).filter(|(a, b)| a != b).count();
    assert_eq!(changed, degree[0] + 1);
    // The surface moves by B_2(u) B_1(v) B_0(w) times the movement (linearity).
    let u = [0.3, 0.6, 0.2];
    let mut d = [[0.0; 3]];
    let b = FfdBox::new(degree, &moved).unwrap();
    ffd_displacements_between(&ffd, &b, &[u], &mut d).unwrap();
    let w = bernstein(3, 2, u[0]) * bernstein(2, 1, u[1]) * bernstein(1, 0, u[2]);
    assert!((d[0][1] + 0.2 * w).abs() < 1e-15);
    assert!(matches!(
        ffd_control_point(degree, &mut row, [None, None, None], [1.0; 3]),
        Err(Error::InvalidParameter { .. })
    ));
}

#[test]
fn two_d_variables_move_both_layers() {
    let degree = [4, 1, 1];
    let cps = lattice(degree, 0.0, &mut Rng(10));
    let index = |i, j, k| FfdBox::new(degree, &cps).unwrap().index([i, j, k]).unwrap();
    let mut a = cps.clone();
    ffd_control_point_2d(degree, &mut a, [Some(2), Some(1)], [0.0, 0.05]).unwrap();
    for k in 0..2 {
        assert_eq!(a[index(2, 1, k)][1], cps[index(2, 1, k)][1] + 0.05);
    }
    assert_eq!(cps.iter().zip(&a).filter(|(x, y)| x != y).count(), 2);
    let mut b = cps.clone();
    ffd_thickness_2d(degree, &mut b, 3, 0.01).unwrap();
    let mut c = cps.clone();
    ffd_camber_2d(degree, &mut c, 3, 0.01).unwrap();
    for k in 0..2 {
        assert_eq!(b[index(3, 0, k)][1], cps[index(3, 0, k)][1] - 0.01);
        assert_eq!(b[index(3, 1, k)][1], cps[index(3, 1, k)][1] + 0.01);
        assert_eq!(c[index(3, 0, k)][1], cps[index(3, 0, k)][1] + 0.01);
        assert_eq!(c[index(3, 1, k)][1], cps[index(3, 1, k)][1] + 0.01);
    }
}

#[test]
fn camber_and_thickness_move_z_as_su2() {
    let degree = [3, 3, 1];
    let cps = lattice(degree, 0.0, &mut Rng(11));
    let index = |i, j, k| FfdBox::new(degree, &cps).unwrap().index([i, j, k]).unwrap();
    let (mut c, mut t) = (cps.clone(), cps.clone());
    ffd_camber(degree, &mut c, 1, 2, 0.02).unwrap();
    ffd_thickness(degree, &mut t, 1, 2, 0.02).unwrap();
    assert_eq!(c[index(1, 2, 0)][2], cps[index(1, 2, 0)][2] + 0.02);
    assert_eq!(c[index(1, 2, 1)][2], cps[index(1, 2, 1)][2] + 0.02);
    assert_eq!(t[index(1, 2, 0)][2], cps[index(1, 2, 0)][2] - 0.02);
    assert_eq!(t[index(1, 2, 1)][2], cps[index(1, 2, 1)][2] + 0.02);
    assert_eq!(cps.iter().zip(&t).filter(|(x, y)| x != y).count(), 2);
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let degree = [2, 2, 1];
    let cps = lattice(degree, 0.1, &mut Rng(12));
    assert!(matches!(
        FfdBox::new([0, 2, 1], &cps),
        Err(Error::InvalidParameter { arg: "degree", .. })
    ));
    assert!(matches!(
        FfdBox::new([MAX_DEGREE + 1, 1, 1], &cps),
        Err(Error::InvalidParameter { arg: "degree", .. })
    ));
    assert!(matches!(
        FfdBox::new(degree, &cps[1..]),
        Err(Error::LengthMismatch {
            arg: "control_points",
            ..
        })
    ));
    let ffd = FfdBox::new(degree, &cps).unwrap();
    let mut out = [[7.0; 3]; 2];
    let bad = [[0.5; 3], [f64::NAN, 0.0, 0.0]];
    assert!(matches!(
        ffd_eval(&ffd, &bad, &mut out),
        Err(Error::NonFinite {
            arg: "params",
            position: 1
        })
    ));
    assert!(matches!(
        ffd_displacements(&ffd, &[[0.0; 3]], &[0, 1], &[[0.5; 3]; 2], &mut out),
        Err(Error::IndexOutOfRange {
            arg: "nodes",
            position: 1,
            ..
        })
    ));
    let far = [[0.5; 3], [1e300, 0.5, 0.5]];
    assert!(matches!(
        ffd_eval(&ffd, &far, &mut out),
        Err(Error::Overflow { arg: "params" })
    ));
    let mut d = [[7.0; 3]; 2];
    assert!(matches!(
        ffd_displacements_between(&ffd, &ffd, &far, &mut d),
        Err(Error::Overflow { .. })
    ));
    assert_eq!(d, [[7.0; 3]; 2]);
    assert_eq!(out, [[7.0; 3]; 2]);
    let mut moved = cps.clone();
    assert!(matches!(
        ffd_control_point(degree, &mut moved, [Some(3), Some(0), Some(0)], [1.0; 3]),
        Err(Error::IndexOutOfRange {
            arg: "index",
            position: 0,
            index: 3,
            bound: 3
        })
    ));
    assert!(matches!(
        ffd_camber(degree, &mut moved, 0, 0, f64::INFINITY),
        Err(Error::NonFinite { .. })
    ));
    assert_eq!(moved, cps);
}

/// One box and its surface points read from `data/<name>` (see data/README.md).
struct PublicBox {
    degree: [usize; 3],
    control_points: Vec<[f64; 3]>,
    nodes: Vec<u32>,
    params: Vec<[f64; 3]>,
    /// Mesh coordinates of each surface point's node (z = 0 on a 2D mesh).
    coords: Vec<[f64; 3]>,
}

fn read_public(name: &str) -> PublicBox {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/design/data")
        .join(name);
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<usize> = lines
        .next()
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let (dim, degree) = (head[0], [head[1], head[2], head[3]]);
    let mut control_points = vec![[f64::NAN; 3]; ffd_control_point_count(degree).unwrap()];
    let zeros = vec![[0.0; 3]; control_points.len()];
    let probe = FfdBox::new(degree, &zeros).unwrap();
    let mut pb = PublicBox {
        degree,
        control_points: vec![],
        nodes: vec![],
        params: vec![],
        coords: vec![],
    };
    for line in lines.by_ref() {
        if line.starts_with("surface") {
            break;
        }
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect();
        let at = probe
            .index([f[0] as usize, f[1] as usize, f[2] as usize])
            .unwrap();
        control_points[at] = [f[3], f[4], f[5]];
    }
    for line in lines {
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect();
        pb.nodes.push(pb.coords.len() as u32);
        pb.params.push([f[1], f[2], f[3]]);
        pb.coords
            .push([f[4], f[5], if dim == 3 { f[6] } else { 0.0 }]);
    }
    pb.control_points = control_points;
    pb
}

/// The parametric coordinates SU2 stored in two public test meshes (su2code/TestCases) put
/// the box's evaluation back on the mesh surface to rounding (numpy and the kernel both see
/// ≤ 2e-15 on these meshes), so SU2's displacement with no design variable is (nearly) zero. Then an SU2-style FFD_CONTROL_POINT_2D moves the surface as numpy's
/// evaluation of the moved box says.
#[test]
fn public_su2_meshes_stored_parametric_coordinates_reproduce_the_surface() {
    for name in ["naca0012_inv_ffd.txt", "brick_hex_ffd.txt"] {
        let pb = read_public(name);
        assert!(
            pb.control_points.iter().flatten().all(|v| v.is_finite()),
            "{name}: missing control points"
        );
        let ffd = FfdBox::new(pb.degree, &pb.control_points).unwrap();
        let mut d = vec![[0.0; 3]; pb.nodes.len()];
        ffd_displacements(&ffd, &pb.coords, &pb.nodes, &pb.params, &mut d).unwrap();
        let worst = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            worst < 1e-14,
            "{name}: surface reproduced to {worst:e} only"
        );

        let mut moved = pb.control_points.clone();
        ffd_control_point_2d(pb.degree, &mut moved, [Some(3), Some(1)], [0.0, 0.01]).unwrap();
        let b = FfdBox::new(pb.degree, &moved).unwrap();
        let mut out = vec![[0.0; 3]; pb.params.len()];
        ffd_eval(&b, &pb.params, &mut out).unwrap();
        let reference = numpy_eval(pb.degree, &moved, &pb.params);
        for (o, r) in out.iter().flatten().zip(&reference) {
            assert!((o - r).abs() <= 1e-14 * 2.0, "{name}: {o} vs {r}");
        }
        ffd_displacements(&b, &pb.coords, &pb.nodes, &pb.params, &mut d).unwrap();
        assert!(
            d.iter().any(|v| v[1] > 1e-4),
            "{name}: the design variable moved nothing"
        );
    }
}
