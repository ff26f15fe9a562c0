//! Kernel `quality` module: parity with the naive reference (`quality_ref`), exact values on
//! unit cells, properties (rigid motion, reflection, shear), error handling with untouched
//! buffers, f32 against f64.
//!
//! Tolerances: 2D corner Jacobians use the same formula and order as the reference and must
//! be exactly equal (`==`). Measures and 3D Jacobians are computed by different formulas
//! (closed forms versus shoelace/quadrature), so they must agree within `1e-12 · h^D` where
//! `h` is the cell's longest corner-to-corner distance. Wall angles within `1e-10` rad in
//! 2D (atan2 either way) and `1e-7` rad in 3D (the reference uses `acos`, which loses about
//! half the digits near 0 and π).

use deform_host_tests::quality_ref;
use deform_kernel::quality::{
    cell_measures, cell_qualities, cell_quality, compare, folded_cells, inverted_cells,
    min_corner_jacobians, wall_angle_change, wall_angle_scratch_len, Wall,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, CellKind, Cells, Error, Graph};
use deform_meshgen::{
    annulus, block2, block3, box_with_inner_box3, extrude, naca_hybrid, naca_ogrid,
    naca_triangulated, noisy_block3, AirfoilGrid, BlockSpec, Mesh,
};
use proptest::prelude::*;

fn pts<const D: usize>(p: &[[f64; D]]) -> Vec<Vec<f64>> {
    p.iter().map(|q| q.to_vec()).collect()
}

fn list<const D: usize>(m: &Mesh<D>) -> quality_ref::CellList {
    quality_ref::cell_list(&m.offsets, &m.nodes, &m.kinds)
}

/// Longest corner-to-corner distance of each cell.
fn sizes<const D: usize>(m: &Mesh<D>, p: &[[f64; D]]) -> Vec<f64> {
    list(m)
        .iter()
        .map(|(_, n)| {
            let mut h: f64 = 0.0;
            for &a in n {
                for &b in n {
                    let d: f64 = (0..D)
                        .map(|k| (p[a as usize][k] - p[b as usize][k]).powi(2))
                        .sum();
                    h = h.max(d.sqrt());
                }
            }
            h
        })
        .collect()
}

/// Kernel measures and Jacobians against the reference on one point set.
fn parity<const D: usize>(m: &Mesh<D>, p: &[[f64; D]], what: &str) {
    let cells = m.cells().unwrap();
    let n = cells.len();
    let (mut meas, mut jac, mut sj) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    cell_measures(&cells, p, &mut meas).unwrap();
    min_corner_jacobians(&cells, p, false, &mut jac).unwrap();
    min_corner_jacobians(&cells, p, true, &mut sj).unwrap();
    // The one-pass form gives the same bits.
    let (mut m1, mut j1, mut s1) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    cell_qualities(&cells, p, &mut m1, &mut j1, &mut s1).unwrap();
    assert_eq!(
        (&m1, &j1, &s1),
        (&meas, &jac, &sj),
        "{what}: cell_qualities"
    );
    let l = list(m);
    let rp = pts(p);
    let rm = quality_ref::measures(&l, &rp);
    let rj = quality_ref::min_jacobians(&l, &rp, false);
    let rs = quality_ref::min_jacobians(&l, &rp, true);
    let h = sizes(m, p);
    for c in 0..n {
        let tol = 1e-12 * h[c].powi(D as i32);
        assert!(
            (meas[c] - rm[c]).abs() <= tol,
            "{what}: cell {c} measure {} vs {}",
            meas[c],
            rm[c]
        );
        if D == 2 {
            assert_eq!(jac[c], rj[c], "{what}: cell {c} jacobian");
            assert_eq!(sj[c], rs[c], "{what}: cell {c} scaled jacobian");
        } else {
            assert!((jac[c] - rj[c]).abs() <= 8.0 * tol, "{what}: cell {c} jac");
            assert!((sj[c] - rs[c]).abs() <= 1e-12, "{what}: cell {c} scaled");
        }
    }
}

/// A smooth, large, deterministic deformation that folds cells near the body.
fn swirl<const D: usize>(p: &[[f64; D]], amount: f64) -> Vec<[f64; D]> {
    p.iter()
        .map(|q| {
            let r2 = (q[0] - 0.25).powi(2) + q[1].powi(2);
            let a = amount * (-r2).exp();
            let (s, c) = a.sin_cos();
            let mut o = *q;
            o[0] = 0.25 + c * (q[0] - 0.25) - s * q[1] + 0.01 * (3.0 * q[1]).sin();
            o[1] = s * (q[0] - 0.25) + c * q[1] + 0.01 * (2.0 * q[0]).cos();
            o
        })
        .collect()
}

fn airfoils() -> Vec<(&'static str, Mesh<2>)> {
    let o = AirfoilGrid::tiny();
    let v = AirfoilGrid::viscous();
    vec![
        ("ogrid", naca_ogrid(&o).unwrap()),
        ("tri", naca_triangulated(&o).unwrap()),
        ("hybrid", naca_hybrid(&v).unwrap()),
    ]
}

fn solids() -> Vec<(&'static str, Mesh<3>)> {
    let o = AirfoilGrid::tiny();
    vec![
        (
            "hex wing",
            extrude(&naca_ogrid(&o).unwrap(), 2.0, 3).unwrap(),
        ),
        (
            "hybrid wing",
            extrude(&naca_hybrid(&o).unwrap(), 2.0, 3).unwrap(),
        ),
        ("box", box_with_inner_box3(6, 2).unwrap()),
        (
            "noisy",
            noisy_block3(&BlockSpec::uniform(6), 0.3, 3).unwrap(),
        ),
    ]
}

/// Mixed tets and pyramids: every hex of a block split into 6 pyramids about its centre
/// (base = hex face, outward order reversed so the base turns toward the apex), and each
/// pyramid of the first hex split into two tets.
fn mixed_3d() -> Mesh<3> {
    let b = block3(&BlockSpec {
        dims: [3, 3, 2],
        lengths: [1.0, 1.5, 0.7],
        ratios: [1.3, 1.0, 1.0],
    })
    .unwrap();
    let faces = [
        [0, 1, 2, 3],
        [4, 7, 6, 5],
        [0, 4, 5, 1],
        [1, 5, 6, 2],
        [2, 6, 7, 3],
        [3, 7, 4, 0],
    ];
    let mut m = Mesh::<3>::new();
    m.points = b.points.clone();
    for c in 0..b.cell_count() {
        let (_, n) = b.cell(c).unwrap();
        let mut centre = [0.0; 3];
        for &v in n {
            for (x, y) in centre.iter_mut().zip(b.points[v as usize]) {
                *x += y / 8.0;
            }
        }
        let apex = m.points.len() as u32;
        m.points.push(centre);
        for f in faces {
            let q = [n[f[0]], n[f[1]], n[f[2]], n[f[3]]];
            if c == 0 {
                m.push_cell(CellKind::Tetra, &[q[0], q[1], q[2], apex]);
                m.push_cell(CellKind::Tetra, &[q[0], q[2], q[3], apex]);
            } else {
                m.push_cell(CellKind::Pyramid, &[q[0], q[1], q[2], q[3], apex]);
            }
        }
    }
    m
}

#[test]
fn parity_with_reference_2d() {
    for (name, m) in airfoils() {
        parity(&m, &m.points, name);
        parity(&m, &swirl(&m.points, 1.2), name);
    }
    let a = annulus(20, 5, 0.5, 2.0).unwrap();
    parity(&a, &a.points, "annulus");
}

#[test]
fn parity_with_reference_3d() {
    let mut all = solids();
    all.push(("mixed", mixed_3d()));
    for (name, m) in all {
        parity(&m, &m.points, name);
        parity(&m, &swirl(&m.points, 1.2), name);
    }
}

#[test]
fn compare_matches_reference() {
    for (name, m) in airfoils() {
        for amount in [0.3, 1.5, 3.0] {
            let d = swirl(&m.points, amount);
            check_compare(&m, &d, name);
        }
    }
    for (name, m) in solids() {
        for amount in [0.3, 3.0] {
            let d = swirl(&m.points, amount);
            check_compare(&m, &d, name);
        }
    }
}

fn check_compare<const D: usize>(m: &Mesh<D>, d: &[[f64; D]], what: &str) {
    let cells = m.cells().unwrap();
    let r = compare(&cells, &m.points, d, None, &mut []).unwrap();
    let want = quality_ref::compare(&list(m), &pts(&m.points), &pts(d));
    assert_eq!(r.cells, m.cell_count());
    assert_eq!(r.inverted_cells, want.inverted, "{what}");
    assert_eq!(r.folded_cells, want.folded, "{what}");
    assert_eq!(r.folded_cells_undeformed, 0, "{what}");
    assert_eq!(
        r.inverted_cells,
        inverted_cells(&cells, &m.points, d).unwrap()
    );
    assert_eq!(r.folded_cells, folded_cells(&cells, d).unwrap());
    assert!((r.min_measure_ratio - want.min_ratio).abs() <= 1e-9 * want.min_ratio.abs().max(1.0));
    assert!((r.max_measure_ratio - want.max_ratio).abs() <= 1e-9 * want.max_ratio.abs().max(1.0));
    assert!(r.wall.is_none());
}

#[test]
fn large_deformations_do_invert_cells() {
    // The checks above must not pass vacuously: the strong swirl folds cells.
    let m = naca_triangulated(&AirfoilGrid::tiny()).unwrap();
    let cells = m.cells().unwrap();
    let r = compare(&cells, &m.points, &swirl(&m.points, 3.0), None, &mut []).unwrap();
    assert!(r.inverted_cells > 0 && r.folded_cells >= r.inverted_cells);
    assert!(r.min_measure_ratio < 0.0);
}

#[test]
fn unit_cells_exact() {
    let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let q = cell_quality(CellKind::Quad, &sq).unwrap();
    assert_eq!(
        (q.measure, q.min_jacobian, q.min_scaled_jacobian),
        (1.0, 1.0, 1.0)
    );
    let q = cell_quality(CellKind::Triangle, &sq[..3]).unwrap();
    assert_eq!(q.measure, 0.5);
    let cube = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.0, 1.0, 1.0],
    ];
    let q = cell_quality(CellKind::Hexahedron, &cube).unwrap();
    assert_eq!(
        (q.measure, q.min_jacobian, q.min_scaled_jacobian),
        (1.0, 1.0, 1.0)
    );
    let tet = [cube[0], cube[1], cube[3], cube[4]];
    let q = cell_quality(CellKind::Tetra, &tet).unwrap();
    assert_eq!((q.measure, q.min_jacobian), (1.0 / 6.0, 1.0));
    // VTK wedge: base 0,1,2 turns away from 3,4,5.
    let wedge = [cube[0], cube[3], cube[1], cube[4], cube[7], cube[5]];
    let q = cell_quality(CellKind::Prism, &wedge).unwrap();
    assert_eq!((q.measure, q.min_jacobian), (0.5, 1.0));
    let pyr: [[f64; 3]; 5] = [cube[0], cube[1], cube[2], cube[3], [0.5, 0.5, 1.0]];
    let q = cell_quality(CellKind::Pyramid, &pyr).unwrap();
    assert!((q.measure - 1.0 / 3.0).abs() < 1e-16);
    // A bow-tie quad: positive net area but folded.
    let bow = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.2]];
    let q = cell_quality(CellKind::Quad, &bow).unwrap();
    assert!(q.min_jacobian < 0.0);
    // Kind/dimension and corner-count errors.
    assert_eq!(
        cell_quality(CellKind::Hexahedron, &sq),
        Err(Error::CellDimension {
            cell: 0,
            kind: 12,
            dimension: 2
        })
    );
    assert!(matches!(
        cell_quality(CellKind::Quad, &sq[..3]),
        Err(Error::LengthMismatch { arg: "corners", .. })
    ));
    assert!(matches!(
        cell_quality(
            CellKind::Quad,
            &[[0.0, 0.0], [1.0, f64::NAN], [1.0, 1.0], [0.0, 1.0]]
        ),
        Err(Error::NonFinite {
            arg: "corners",
            position: 1
        })
    ));
}

fn rotate2(p: &[[f64; 2]], a: f64, t: [f64; 2]) -> Vec<[f64; 2]> {
    let (s, c) = a.sin_cos();
    p.iter()
        .map(|q| [c * q[0] - s * q[1] + t[0], s * q[0] + c * q[1] + t[1]])
        .collect()
}

fn rotate3(p: &[[f64; 3]], a: f64, b: f64, t: [f64; 3]) -> Vec<[f64; 3]> {
    let (sa, ca) = a.sin_cos();
    let (sb, cb) = b.sin_cos();
    p.iter()
        .map(|q| {
            // About z by a, then about x by b.
            let r = [ca * q[0] - sa * q[1], sa * q[0] + ca * q[1], q[2]];
            [
                r[0] + t[0],
                cb * r[1] - sb * r[2] + t[1],
                sb * r[1] + cb * r[2] + t[2],
            ]
        })
        .collect()
}

struct WallData {
    offsets: Vec<u32>,
    targets: Vec<u32>,
}

fn graph_of(cells: &Cells<'_>) -> WallData {
    let mut offsets = vec![0u32; cells.node_count() + 1];
    let mut targets = vec![0u32; graph_from_cells_len(cells, false)];
    let used = graph_from_cells(cells, false, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    WallData { offsets, targets }
}

fn measures_rigid<const D: usize>(m: &Mesh<D>, moved: &[[f64; D]], what: &str) {
    let cells = m.cells().unwrap();
    let n = cells.len();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    cell_measures(&cells, &m.points, &mut a).unwrap();
    cell_measures(&cells, moved, &mut b).unwrap();
    let h = sizes(m, &m.points);
    // Rounding of the moved coordinates (|x| up to ~20) dominates: 64 ulp of |x| times h^(D−1).
    let xmax = m
        .points
        .iter()
        .flat_map(|p| p.iter())
        .fold(1.0f64, |s, x| s.max(x.abs()));
    for c in 0..n {
        let tol = 64.0 * f64::EPSILON * xmax * h[c].powi(D as i32 - 1);
        assert!(
            (a[c] - b[c]).abs() <= tol,
            "{what}: cell {c}: {} vs {}",
            a[c],
            b[c]
        );
    }
    let r = compare(&cells, &m.points, moved, None, &mut []).unwrap();
    assert_eq!((r.inverted_cells, r.folded_cells), (0, 0), "{what}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn rigid_motion_keeps_measures_and_wall_angles(
        a in -3.2f64..3.2, b in -3.2f64..3.2, tx in -5.0f64..5.0, ty in -5.0f64..5.0,
    ) {
        let m = naca_hybrid(&AirfoilGrid::tiny()).unwrap();
        let moved = rotate2(&m.points, a, [tx, ty]);
        measures_rigid(&m, &moved, "hybrid");
        let cells = m.cells().unwrap();
        let g = graph_of(&cells);
        let graph = Graph::new(&g.offsets, &g.targets).unwrap();
        let wall_m = m.marker("airfoil").unwrap();
        let wall = Wall::new(wall_m.cells(m.node_count()).unwrap(), graph).unwrap();
        let mut scratch = vec![[0.0; 2]; wall_angle_scratch_len(m.node_count())];
        let w = wall_angle_change(&wall, &m.points, &moved, &mut scratch).unwrap();
        prop_assert!(w.max_change < 1e-12, "{}", w.max_change);
        prop_assert_eq!(w.measured, wall_m.node_list.len());

        let m3 = box_with_inner_box3(6, 2).unwrap();
        let moved3 = rotate3(&m3.points, a, b, [tx, ty, 1.0]);
        measures_rigid(&m3, &moved3, "box3");
        let cells3 = m3.cells().unwrap();
        let g3 = graph_of(&cells3);
        let graph3 = Graph::new(&g3.offsets, &g3.targets).unwrap();
        let inner = m3.marker("inner").unwrap();
        let wall3 = Wall::new(inner.cells(m3.node_count()).unwrap(), graph3).unwrap();
        let mut s3 = vec![[0.0; 3]; wall_angle_scratch_len(m3.node_count())];
        let w3 = wall_angle_change(&wall3, &m3.points, &moved3, &mut s3).unwrap();
        // Unsigned 3D angles near 0 or π lose digits to atan2 of a tiny |n × e|: still ≪ 1e-6.
        prop_assert!(w3.max_change < 1e-7, "{}", w3.max_change);
    }

    #[test]
    fn random_cells_match_reference(
        jitter in proptest::collection::vec(-0.3f64..0.3, 24),
        kind_index in 0usize..6,
    ) {
        let kinds = [5u8, 9, 10, 12, 13, 14];
        let kind = kinds[kind_index];
        let base: Vec<[f64; 3]> = match kind {
            5 => vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            9 => vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
            10 => vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            12 => vec![
                [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0],
            ],
            13 => vec![
                [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0],
                [0.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 0.0, 1.0],
            ],
            _ => vec![
                [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0],
                [0.5, 0.5, 1.0],
            ],
        };
        let p: Vec<[f64; 3]> = base
            .iter()
            .enumerate()
            .map(|(i, q)| [q[0] + jitter[3 * i], q[1] + jitter[3 * i + 1], q[2] + jitter[3 * i + 2]])
            .collect();
        let k = CellKind::from_vtk(kind).unwrap();
        let (got, got32) = if k.dimension() == 2 {
            let q: Vec<[f64; 2]> = p.iter().map(|x| [x[0], x[1]]).collect();
            let q32: Vec<[f32; 2]> = q.iter().map(|x| [x[0] as f32, x[1] as f32]).collect();
            (cell_quality(k, &q).unwrap(), cell_quality(k, &q32).unwrap())
        } else {
            let q32: Vec<[f32; 3]> = p.iter().map(|x| x.map(|v| v as f32)).collect();
            (cell_quality(k, &p).unwrap(), cell_quality(k, &q32).unwrap())
        };
        let flat: Vec<[f64; 3]> = if k.dimension() == 2 {
            p.iter().map(|x| [x[0], x[1], 0.0]).collect()
        } else {
            p.clone()
        };
        let want = quality_ref::measure(kind, &flat);
        let corners = quality_ref::corner_jacobians(kind, &flat);
        let wj = corners.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
        let ws = corners.iter().map(|c| c.1).fold(f64::INFINITY, f64::min);
        prop_assert!((got.measure - want).abs() < 1e-14, "{} vs {}", got.measure, want);
        prop_assert!((got.min_jacobian - wj).abs() < 1e-14);
        prop_assert!((got.min_scaled_jacobian - ws).abs() < 1e-14);
        // f32 agrees with f64 to f32 rounding.
        prop_assert!((got32.measure as f64 - want).abs() < 1e-5);
        prop_assert!((got32.min_jacobian as f64 - wj).abs() < 1e-5);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Scaling by a power of two is exact in floating point: measures and Jacobians scale by
    /// exactly `2^(kD)`, scaled Jacobians not at all (bitwise).
    #[test]
    fn power_of_two_scaling_is_exact(k in -20i32..20, which in 0usize..4) {
        let s = 2f64.powi(k);
        match which {
            0 => scaling_exact(&naca_hybrid(&AirfoilGrid::tiny()).unwrap(), s),
            1 => scaling_exact(&annulus(12, 4, 0.5, 1.5).unwrap(), s),
            2 => scaling_exact(&mixed_3d(), s),
            _ => scaling_exact(&solids().remove(1).1, s),
        }
    }
}

fn eval<const D: usize>(m: &Mesh<D>, p: &[[f64; D]]) -> [Vec<f64>; 3] {
    let cells = m.cells().unwrap();
    let n = cells.len();
    let (mut a, mut j, mut sj) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    cell_measures(&cells, p, &mut a).unwrap();
    min_corner_jacobians(&cells, p, false, &mut j).unwrap();
    min_corner_jacobians(&cells, p, true, &mut sj).unwrap();
    [a, j, sj]
}

fn scaling_exact<const D: usize>(m: &Mesh<D>, s: f64) {
    let scaled: Vec<[f64; D]> = m.points.iter().map(|p| p.map(|x| x * s)).collect();
    let [a, ja, sa] = eval(m, &m.points);
    let [b, jb, sb] = eval(m, &scaled);
    let f = s.powi(D as i32);
    for c in 0..a.len() {
        assert_eq!(b[c], a[c] * f, "cell {c} measure");
        assert_eq!(jb[c], ja[c] * f, "cell {c} jacobian");
        assert_eq!(sb[c].to_bits(), sa[c].to_bits(), "cell {c} scaled jacobian");
    }
}

#[test]
fn reflection_inverts_every_cell() {
    let m = naca_hybrid(&AirfoilGrid::tiny()).unwrap();
    let refl: Vec<[f64; 2]> = m.points.iter().map(|p| [-p[0], p[1]]).collect();
    let cells = m.cells().unwrap();
    let r = compare(&cells, &m.points, &refl, None, &mut []).unwrap();
    assert_eq!(r.inverted_cells, m.cell_count());
    assert_eq!(r.folded_cells, m.cell_count());
    assert_eq!((r.min_measure_ratio, r.max_measure_ratio), (-1.0, -1.0));
    for (name, m3) in solids() {
        let refl: Vec<[f64; 3]> = m3.points.iter().map(|p| [p[0], p[1], -p[2]]).collect();
        let c3 = m3.cells().unwrap();
        let r = compare(&c3, &m3.points, &refl, None, &mut []).unwrap();
        assert_eq!(r.inverted_cells, m3.cell_count(), "{name}");
        assert_eq!(r.folded_cells, m3.cell_count(), "{name}");
        assert!((r.max_measure_ratio + 1.0).abs() < 1e-12, "{name}");
    }
}

#[test]
fn shear_changes_wall_angle_by_its_angle() {
    let s = 0.3f64;
    let m = block2(&BlockSpec {
        dims: [9, 6, 1],
        lengths: [2.0, 1.0, 1.0],
        ratios: [1.0, 1.2, 1.0],
    })
    .unwrap();
    let sheared: Vec<[f64; 2]> = m.points.iter().map(|p| [p[0] + s * p[1], p[1]]).collect();
    let cells = m.cells().unwrap();
    let g = graph_of(&cells);
    let graph = Graph::new(&g.offsets, &g.targets).unwrap();
    let wall = Wall::new(
        m.marker("jmin").unwrap().cells(m.node_count()).unwrap(),
        graph,
    )
    .unwrap();
    let mut scratch = vec![[0.0; 2]; wall_angle_scratch_len(m.node_count())];
    let r = compare(&cells, &m.points, &sheared, Some(&wall), &mut scratch).unwrap();
    let w = r.wall.unwrap();
    assert_eq!((w.measured, w.skipped), (9, 0));
    assert!((w.max_change - s.atan()).abs() < 1e-14, "{}", w.max_change);
    // A shear keeps every area: ratios are 1.
    assert!((r.min_measure_ratio - 1.0).abs() < 1e-14 && (r.max_measure_ratio - 1.0).abs() < 1e-14);

    let m3 = block3(&BlockSpec::uniform(4)).unwrap();
    let sh3: Vec<[f64; 3]> = m3
        .points
        .iter()
        .map(|p| [p[0] + s * p[2], p[1], p[2]])
        .collect();
    let c3 = m3.cells().unwrap();
    let g3 = graph_of(&c3);
    let graph3 = Graph::new(&g3.offsets, &g3.targets).unwrap();
    let wall3 = Wall::new(
        m3.marker("kmin").unwrap().cells(m3.node_count()).unwrap(),
        graph3,
    )
    .unwrap();
    let mut s3 = vec![[0.0; 3]; wall_angle_scratch_len(m3.node_count())];
    let w3 = wall_angle_change(&wall3, &m3.points, &sh3, &mut s3).unwrap();
    assert_eq!(w3.measured, 16);
    assert!(
        (w3.max_change - s.atan()).abs() < 1e-12,
        "{}",
        w3.max_change
    );
}

#[test]
fn wall_angle_matches_reference() {
    for (name, m) in airfoils() {
        let cells = m.cells().unwrap();
        let g = graph_of(&cells);
        let graph = Graph::new(&g.offsets, &g.targets).unwrap();
        let wm = m.marker("airfoil").unwrap();
        let wall = Wall::new(wm.cells(m.node_count()).unwrap(), graph).unwrap();
        let adj = quality_ref::adjacency(&list(&m), m.node_count());
        let wl = quality_ref::cell_list(&wm.offsets, &wm.nodes, &wm.kinds);
        let mut scratch = vec![[0.0; 2]; wall_angle_scratch_len(m.node_count())];
        for amount in [0.2, 0.9] {
            let d = swirl(&m.points, amount);
            let w = wall_angle_change(&wall, &m.points, &d, &mut scratch).unwrap();
            let (max, node, measured, skipped) =
                quality_ref::wall_angle_change(&wl, &adj, &pts(&m.points), &pts(&d));
            assert!(
                (w.max_change - max).abs() < 1e-10,
                "{name}: {} vs {max}",
                w.max_change
            );
            assert_eq!(
                (w.node, w.measured, w.skipped),
                (node, measured, skipped),
                "{name}"
            );
            assert!(
                w.max_change > 1e-3,
                "{name}: the deformation must shear the wall"
            );
        }
    }
    for (name, m) in solids().into_iter().take(2) {
        let cells = m.cells().unwrap();
        let g = graph_of(&cells);
        let graph = Graph::new(&g.offsets, &g.targets).unwrap();
        let wm = m.marker("airfoil").unwrap();
        let wall = Wall::new(wm.cells(m.node_count()).unwrap(), graph).unwrap();
        let adj = quality_ref::adjacency(&list(&m), m.node_count());
        let wl = quality_ref::cell_list(&wm.offsets, &wm.nodes, &wm.kinds);
        let mut scratch = vec![[0.0; 3]; wall_angle_scratch_len(m.node_count())];
        let d = swirl(&m.points, 0.5);
        let w = wall_angle_change(&wall, &m.points, &d, &mut scratch).unwrap();
        let (max, node, measured, skipped) =
            quality_ref::wall_angle_change(&wl, &adj, &pts(&m.points), &pts(&d));
        assert!(
            (w.max_change - max).abs() < 1e-7,
            "{name}: {} vs {max}",
            w.max_change
        );
        assert_eq!((w.measured, w.skipped), (measured, skipped), "{name}");
        assert!(node.is_some() && w.max_change > 1e-3);
    }
}

#[test]
fn f32_counts_match_f64() {
    let m = naca_hybrid(&AirfoilGrid::inviscid()).unwrap();
    let cells = m.cells().unwrap();
    let p32 = m.points_f32();
    let d = swirl(&m.points, 1.0);
    let d32: Vec<[f32; 2]> = d.iter().map(|p| p.map(|x| x as f32)).collect();
    let r64 = compare(&cells, &m.points, &d, None, &mut []).unwrap();
    let r32 = compare(&cells, &p32, &d32, None, &mut []).unwrap();
    assert_eq!(r32.folded_cells_undeformed, 0);
    // Counts can differ only for cells whose measure is within f32 rounding of zero.
    assert!(r32.inverted_cells.abs_diff(r64.inverted_cells) <= 2);
    assert!(
        (r32.max_measure_ratio as f64 - r64.max_measure_ratio).abs() < 1e-3 * r64.max_measure_ratio
    );
}

#[test]
fn errors_leave_buffers_untouched() {
    let m = naca_hybrid(&AirfoilGrid::tiny()).unwrap();
    let cells = m.cells().unwrap();
    let n = cells.len();
    let sentinel = -12345.0;
    let mut out = vec![sentinel; n];
    // Wrong lengths.
    let short = &m.points[..m.node_count() - 1];
    assert_eq!(
        cell_measures(&cells, short, &mut out),
        Err(Error::LengthMismatch {
            arg: "points",
            expected: m.node_count(),
            actual: m.node_count() - 1
        })
    );
    let mut small = vec![sentinel; n - 1];
    assert!(matches!(
        cell_measures(&cells, &m.points, &mut small),
        Err(Error::LengthMismatch { arg: "out", .. })
    ));
    assert!(small.iter().all(|&x| x == sentinel));
    // One pass of three outputs: a short one is named and nothing is written.
    let (mut a, mut b) = (vec![sentinel; n], vec![sentinel; n]);
    assert!(matches!(
        cell_qualities(&cells, &m.points, &mut a, &mut b, &mut small),
        Err(Error::LengthMismatch {
            arg: "min_scaled_jacobian",
            ..
        })
    ));
    assert!(a.iter().chain(&b).chain(&small).all(|&x| x == sentinel));
    // Non-finite coordinates, named by argument and node.
    let mut bad = m.points.clone();
    bad[17][1] = f64::INFINITY;
    assert_eq!(
        min_corner_jacobians(&cells, &bad, true, &mut out),
        Err(Error::NonFinite {
            arg: "points",
            position: 17
        })
    );
    assert_eq!(
        inverted_cells(&cells, &m.points, &bad),
        Err(Error::NonFinite {
            arg: "deformed",
            position: 17
        })
    );
    bad[17][1] = f64::NAN;
    assert!(folded_cells(&cells, &bad).is_err());
    assert!(out.iter().all(|&x| x == sentinel));
    // 3D points with 2D cells.
    let p3: Vec<[f64; 3]> = m.points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    assert_eq!(
        cell_measures(&cells, &p3, &mut out),
        Err(Error::CellDimension {
            cell: 0,
            kind: 9,
            dimension: 3
        })
    );
    // D = 4 is not a mesh dimension: refused at compile time (the compile_fail doctest of
    // `cell_measures`).

    // Wall errors leave the scratch untouched.
    let g = graph_of(&cells);
    let graph = Graph::new(&g.offsets, &g.targets).unwrap();
    let wm = m.marker("airfoil").unwrap();
    let wall = Wall::new(wm.cells(m.node_count()).unwrap(), graph).unwrap();
    let len = wall_angle_scratch_len(m.node_count());
    let mut scratch = vec![[sentinel; 2]; len];
    bad[17][1] = f64::NAN;
    assert!(matches!(
        wall_angle_change(&wall, &m.points, &bad, &mut scratch),
        Err(Error::NonFinite {
            arg: "deformed",
            ..
        })
    ));
    assert!(matches!(
        compare(&cells, &m.points, &bad, Some(&wall), &mut scratch),
        Err(Error::NonFinite {
            arg: "deformed",
            ..
        })
    ));
    let mut short_scratch = vec![[sentinel; 2]; len - 1];
    assert_eq!(
        compare(
            &cells,
            &m.points,
            &m.points,
            Some(&wall),
            &mut short_scratch
        ),
        Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: len,
            actual: len - 1
        })
    );
    assert!(short_scratch.iter().all(|p| *p == [sentinel; 2]));
    // Cells as a "wall" in 2D are the wrong kind.
    let wrong = Wall::new(cells, graph).unwrap();
    assert_eq!(
        wall_angle_change(&wrong, &m.points, &m.points, &mut scratch),
        Err(Error::CellDimension {
            cell: 0,
            kind: 9,
            dimension: 2
        })
    );
    assert!(scratch.iter().all(|p| *p == [sentinel; 2]));
    // Graph and wall over different node counts.
    let other = annulus(8, 3, 1.0, 2.0).unwrap();
    let oc = other.cells().unwrap();
    let og = graph_of(&oc);
    let ograph = Graph::new(&og.offsets, &og.targets).unwrap();
    assert!(matches!(
        Wall::new(wm.cells(m.node_count()).unwrap(), ograph),
        Err(Error::LengthMismatch { arg: "graph", .. })
    ));
}
