//! Tests of the deterministic mesh generators: orientation, markers, determinism, sizes and
//! the geometry the options promise. Orientation checks use the independent reference in
//! `deform_host_tests::quality_ref`, not the kernel.

use std::collections::BTreeMap;

use deform_host_tests::quality_ref;
use deform_meshgen::{
    annulus, block2, block3, box_with_inner_box2, box_with_inner_box3, cavity2, cavity3, extrude,
    naca_hybrid, naca_ogrid, naca_triangulated, noisy_block2, noisy_block3, rotate_markers2,
    rotate_markers3, twist_bend, AirfoilGrid, BlockSpec, Mesh, Naca4, TwistBend,
};

fn pts<const D: usize>(m: &Mesh<D>) -> Vec<Vec<f64>> {
    m.points.iter().map(|p| p.to_vec()).collect()
}

fn cells_of<const D: usize>(m: &Mesh<D>) -> quality_ref::CellList {
    quality_ref::cell_list(&m.offsets, &m.nodes, &m.kinds)
}

fn p3<const D: usize>(m: &Mesh<D>, n: u32) -> [f64; 3] {
    let p = m.points[n as usize];
    [p[0], p[1], if D == 3 { p[D - 1] } else { 0.0 }]
}

/// Every cell has positive measure and every corner Jacobian is positive.
fn check_orientation<const D: usize>(m: &Mesh<D>, what: &str) {
    let cells = cells_of(m);
    let points = pts(m);
    let measures = quality_ref::measures(&cells, &points);
    let jac = quality_ref::min_jacobians(&cells, &points, false);
    for (c, (a, j)) in measures.iter().zip(&jac).enumerate() {
        assert!(*a > 0.0, "{what}: cell {c} has measure {a}");
        assert!(*j > 0.0, "{what}: cell {c} has min corner Jacobian {j}");
    }
}

/// Key of an element: its sorted nodes.
fn key(n: &[u32]) -> Vec<u32> {
    let mut k = n.to_vec();
    k.sort_unstable();
    k
}

/// Local outward faces / edges of each kind (for the boundary-orientation check).
fn faces(kind: u8) -> Vec<Vec<usize>> {
    match kind {
        5 => vec![vec![0, 1], vec![1, 2], vec![2, 0]],
        9 => vec![vec![0, 1], vec![1, 2], vec![2, 3], vec![3, 0]],
        12 => vec![
            vec![0, 3, 2, 1],
            vec![4, 5, 6, 7],
            vec![0, 1, 5, 4],
            vec![1, 2, 6, 5],
            vec![2, 3, 7, 6],
            vec![3, 0, 4, 7],
        ],
        13 => vec![
            vec![0, 1, 2],
            vec![3, 5, 4],
            vec![0, 3, 4, 1],
            vec![1, 4, 5, 2],
            vec![2, 5, 3, 0],
        ],
        _ => panic!("unexpected kind {kind}"),
    }
}

fn centroid<const D: usize>(m: &Mesh<D>, nodes: &[u32]) -> [f64; 3] {
    let mut c = [0.0; 3];
    for &n in nodes {
        let p = p3(m, n);
        for d in 0..3 {
            c[d] += p[d] / nodes.len() as f64;
        }
    }
    c
}

/// Markers: valid nodes, node lists exact, every element a boundary element of exactly one
/// cell, oriented with its normal out of the domain, and every boundary element in exactly
/// one marker.
fn check_markers<const D: usize>(m: &Mesh<D>, what: &str) {
    let n = m.node_count() as u32;
    // Boundary elements of the mesh: faces used once.
    let mut count: BTreeMap<Vec<u32>, (usize, usize)> = BTreeMap::new();
    for (c, (kind, nodes)) in cells_of(m).iter().enumerate() {
        for f in faces(*kind) {
            let face: Vec<u32> = f.iter().map(|&l| nodes[l]).collect();
            count.entry(key(&face)).or_insert((0, c)).0 += 1;
        }
    }
    let mut covered = 0;
    for mk in &m.markers {
        assert!(!mk.is_empty(), "{what}: marker {} is empty", mk.name);
        assert_eq!(mk.offsets.len(), mk.kinds.len() + 1);
        assert!(
            mk.nodes.iter().all(|&v| v < n),
            "{what}: {} bad node",
            mk.name
        );
        let mut list = mk.nodes.clone();
        list.sort_unstable();
        list.dedup();
        assert_eq!(list, mk.node_list, "{what}: {} node_list", mk.name);
        mk.cells(m.node_count()).expect("marker elements validate");
        for w in mk.offsets.windows(2) {
            let e = &mk.nodes[w[0] as usize..w[1] as usize];
            let (uses, cell) = count
                .get(&key(e))
                .copied()
                .unwrap_or_else(|| panic!("{what}: {} element {e:?} is not a face", mk.name));
            assert_eq!(uses, 1, "{what}: {} element {e:?} is interior", mk.name);
            covered += 1;
            // Outward normal: right-hand rule.
            let a = p3(m, e[0]);
            let b = p3(m, e[1]);
            let normal = if e.len() == 2 {
                [b[1] - a[1], a[0] - b[0], 0.0]
            } else {
                let c = p3(m, e[2]);
                let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let v = [c[0] - b[0], c[1] - b[1], c[2] - b[2]];
                [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ]
            };
            let (_, cn) = m.cell(cell).unwrap();
            let cc = centroid(m, cn);
            let fc = centroid(m, e);
            let out: f64 = (0..3).map(|d| normal[d] * (fc[d] - cc[d])).sum();
            assert!(out > 0.0, "{what}: {} element {e:?} points inward", mk.name);
        }
    }
    let boundary = count.values().filter(|(u, _)| *u == 1).count();
    assert_eq!(
        covered, boundary,
        "{what}: markers must cover the boundary once"
    );
}

fn check_mesh<const D: usize>(m: &Mesh<D>, what: &str) {
    let cells = m.cells().expect("Cells::new accepts the mesh");
    assert_eq!(cells.len(), m.cell_count());
    check_orientation(m, what);
    check_markers(m, what);
}

fn same_bits<const D: usize>(a: &Mesh<D>, b: &Mesh<D>) {
    assert_eq!(a.points.len(), b.points.len());
    for (p, q) in a.points.iter().zip(&b.points) {
        for (x, y) in p.iter().zip(q) {
            assert_eq!(x.to_bits(), y.to_bits());
        }
    }
    assert_eq!(a, b);
}

#[test]
fn airfoil_meshes_are_valid() {
    for opts in [
        AirfoilGrid::tiny(),
        AirfoilGrid::default(),
        AirfoilGrid::inviscid(),
        AirfoilGrid::viscous(),
    ] {
        check_mesh(&naca_ogrid(&opts).unwrap(), "ogrid");
        check_mesh(&naca_triangulated(&opts).unwrap(), "triangulated");
        check_mesh(&naca_hybrid(&opts).unwrap(), "hybrid");
    }
    for code in ["0012", "4415", "6409", "2424"] {
        let opts = AirfoilGrid {
            code: code.into(),
            ..AirfoilGrid::viscous()
        };
        check_mesh(&naca_hybrid(&opts).unwrap(), code);
    }
}

#[test]
fn airfoil_quality_floor() {
    // Regression guard on the generator's worst corners (see the airfoil module docs).
    let min_scaled = |m: &Mesh<2>| {
        quality_ref::min_jacobians(&cells_of(m), &pts(m), true)
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    };
    let o = AirfoilGrid::inviscid();
    assert!(min_scaled(&naca_ogrid(&o).unwrap()) > 0.1);
    assert!(min_scaled(&naca_triangulated(&o).unwrap()) > 0.01);
    assert!(min_scaled(&naca_hybrid(&AirfoilGrid::viscous()).unwrap()) > 0.005);
}

#[test]
fn preset_20k_is_valid_and_sized() {
    let opts = AirfoilGrid::preset_20k();
    let m = naca_ogrid(&opts).unwrap();
    assert!((19_000..=21_000).contains(&m.node_count()));
    check_mesh(&m, "20k ogrid");
    check_mesh(&naca_hybrid(&opts).unwrap(), "20k hybrid");
}

#[test]
fn airfoil_sizes_as_requested() {
    let opts = AirfoilGrid {
        surface_points: 40,
        radial_points: 9,
        boundary_layers: 3,
        ..AirfoilGrid::default()
    };
    let (ni, nj) = (40, 9);
    let o = naca_ogrid(&opts).unwrap();
    assert_eq!(o.node_count(), ni * nj);
    assert_eq!(o.cell_count(), ni * (nj - 1));
    assert_eq!(o.dims, Some([ni, nj, 1]));
    assert!(o.periodic_i);
    let t = naca_triangulated(&opts).unwrap();
    assert_eq!(t.cell_count(), 2 * ni * (nj - 1));
    assert!(t.kinds.iter().all(|&k| k == 5));
    let h = naca_hybrid(&opts).unwrap();
    let quads = h.kinds.iter().filter(|&&k| k == 9).count();
    let tris = h.kinds.iter().filter(|&&k| k == 5).count();
    assert_eq!(quads, ni * 3);
    assert_eq!(tris, 2 * ni * (nj - 1 - 3));
    assert_eq!(o.require_marker("airfoil").unwrap().node_list.len(), ni);
    assert_eq!(o.require_marker("farfield").unwrap().node_list.len(), ni);
    // Far field at the requested radius about mid-chord.
    for &v in &o.marker("farfield").unwrap().node_list {
        let p = o.points[v as usize];
        let r = ((p[0] - 0.5).powi(2) + p[1].powi(2)).sqrt();
        assert!((r - opts.farfield_chords).abs() < 1e-12 * r);
    }
}

#[test]
fn first_layer_height_and_wall_orthogonality() {
    let opts = AirfoilGrid::viscous();
    let m = naca_ogrid(&opts).unwrap();
    let ni = opts.surface_points;
    let mut worst_deg: f64 = 0.0;
    for i in 0..ni {
        let s = m.points[i];
        let p = m.points[i + ni];
        let h = ((p[0] - s[0]).powi(2) + (p[1] - s[1]).powi(2)).sqrt();
        assert!(
            (h - opts.first_layer).abs() < 1e-3 * opts.first_layer,
            "line {i}: first layer {h}"
        );
        // Angle between the first radial edge and the wall tangent (neighbours i±1).
        let a = m.points[(i + ni - 1) % ni];
        let b = m.points[(i + 1) % ni];
        let t = [b[0] - a[0], b[1] - a[1]];
        let e = [p[0] - s[0], p[1] - s[1]];
        let cos = (t[0] * e[0] + t[1] * e[1]) / (t[0].hypot(t[1]) * h);
        if i != 0 {
            worst_deg = worst_deg.max((90.0 - cos.acos().to_degrees()).abs());
        }
    }
    // Orthogonal at the wall up to the O(first_layer / distance) bending of the line.
    assert!(
        worst_deg < 1.0,
        "wall orthogonality off by {worst_deg} degrees"
    );
}

#[test]
fn naca_section_geometry() {
    let n = Naca4::parse("2412").unwrap();
    assert_eq!(n.max_camber, 0.02);
    assert_eq!(n.camber_position, 0.4);
    assert_eq!(n.thickness, 0.12);
    assert!(Naca4::parse("241").is_err());
    assert!(Naca4::parse("24a2").is_err());
    assert!(Naca4::parse("2400").is_err());
    // Closed trailing edge, thickness maximum about 12% near 30% chord.
    assert!(n.half_thickness(1.0).abs() < 1e-15);
    let (mut best, mut at) = (0.0, 0.0);
    for k in 0..=1000 {
        let x = k as f64 / 1000.0;
        let t = 2.0 * n.half_thickness(x);
        if t > best {
            best = t;
            at = x;
        }
    }
    assert!((best - 0.12).abs() < 2e-4 && (at - 0.3).abs() < 0.02);
    assert!((n.camber(0.4).0 - 0.02).abs() < 1e-15);
    let s = n.surface(64).unwrap();
    assert_eq!(s[0], [1.0, 0.0]);
    assert_eq!(s[32], [0.0, 0.0]);
    assert!(s[1..32].iter().all(|p| p[1] < 0.02) && s[33..].iter().all(|p| p[1] > 0.0));
    // Clockwise loop: negative shoelace area, about the section's area (~0.082 for 12%).
    let mut area = 0.0;
    for i in 0..64 {
        let (a, b) = (s[i], s[(i + 1) % 64]);
        area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
    }
    assert!(area < -0.07 && area > -0.09, "area {area}");
    // Cosine clustering: the spacing at the edges is much finer than at mid-chord.
    let d = |i: usize| (s[i + 1][0] - s[i][0]).abs();
    assert!(d(0) * 10.0 < d(16) && d(31) * 10.0 < d(16));
}

#[test]
fn deterministic_bits() {
    let o = AirfoilGrid::inviscid();
    same_bits(&naca_hybrid(&o).unwrap(), &naca_hybrid(&o).unwrap());
    let spec = BlockSpec::uniform(9);
    same_bits(
        &noisy_block2(&spec, 0.3, 7).unwrap(),
        &noisy_block2(&spec, 0.3, 7).unwrap(),
    );
    same_bits(
        &noisy_block3(&spec, 0.3, 7).unwrap(),
        &noisy_block3(&spec, 0.3, 7).unwrap(),
    );
    let e = |_: ()| extrude(&naca_triangulated(&AirfoilGrid::tiny()).unwrap(), 2.0, 3).unwrap();
    same_bits(&e(()), &e(()));
    // A different seed gives different noise.
    assert_ne!(
        noisy_block2(&spec, 0.3, 7).unwrap().points,
        noisy_block2(&spec, 0.3, 8).unwrap().points
    );
}

#[test]
fn extrusions_are_valid() {
    let tiny = AirfoilGrid::tiny();
    for (name, m2) in [
        ("ogrid", naca_ogrid(&tiny).unwrap()),
        ("tri", naca_triangulated(&tiny).unwrap()),
        ("hybrid", naca_hybrid(&tiny).unwrap()),
        ("annulus", annulus(16, 4, 1.0, 3.0).unwrap()),
    ] {
        let m3 = extrude(&m2, 3.0, 4).unwrap();
        assert_eq!(m3.node_count(), m2.node_count() * 5);
        assert_eq!(m3.cell_count(), m2.cell_count() * 4);
        for mk in &m2.markers {
            let e = m3.require_marker(&mk.name).unwrap();
            assert_eq!(e.len(), mk.len() * 4);
            assert!(e.kinds.iter().all(|&k| k == 9));
        }
        assert_eq!(m3.require_marker("zmin").unwrap().len(), m2.cell_count());
        assert_eq!(m3.require_marker("zmax").unwrap().len(), m2.cell_count());
        check_mesh(&m3, name);
    }
    assert!(extrude(&naca_ogrid(&tiny).unwrap(), 1.0, 0).is_err());
    assert!(extrude(&naca_ogrid(&tiny).unwrap(), f64::NAN, 2).is_err());
}

#[test]
fn twist_bend_map() {
    let m = extrude(&naca_ogrid(&AirfoilGrid::tiny()).unwrap(), 4.0, 4).unwrap();
    let map = TwistBend {
        span: 4.0,
        tip_twist_deg: 10.0,
        tip_bend: 0.5,
        centre: [0.25, 0.0],
    };
    let moved = twist_bend(&m, &map).unwrap();
    for (p, q) in m.points.iter().zip(&moved) {
        if p[2] == 0.0 {
            assert_eq!(p, q, "the root does not move");
        }
        assert_eq!(p[2], q[2]);
        // Twist preserves the distance to the twist axis (after removing the bend).
        let eta = p[2] / 4.0;
        let r0 = (p[0] - 0.25).hypot(p[1]);
        let r1 = (q[0] - 0.25).hypot(q[1] - 0.5 * eta * eta);
        assert!((r0 - r1).abs() < 1e-12 * (1.0 + r0));
    }
    // The tip's trailing edge (node 0 of the top layer) turned by 10 degrees, nose up.
    let tip_te = moved[m.node_count() - m.node_count() / 5];
    let ang = (tip_te[1] - 0.5).atan2(tip_te[0] - 0.25).to_degrees();
    assert!((ang - 10.0).abs() < 1e-9, "{ang}");
}

#[test]
fn blocks_are_valid_and_sized() {
    let spec = BlockSpec {
        dims: [7, 5, 4],
        lengths: [2.0, 1.0, 3.0],
        ratios: [1.2, 0.9, 1.0],
    };
    let b2 = block2(&spec).unwrap();
    assert_eq!(b2.node_count(), 35);
    assert_eq!(b2.cell_count(), 24);
    assert_eq!(b2.dims, Some([7, 5, 1]));
    check_mesh(&b2, "block2");
    // Stretching: consecutive x spacings grow by the ratio; extents as requested.
    let dx: Vec<f64> = (0..6)
        .map(|i| b2.points[i + 1][0] - b2.points[i][0])
        .collect();
    for w in dx.windows(2) {
        assert!((w[1] / w[0] - 1.2).abs() < 1e-12);
    }
    assert!((b2.points[6][0] - 2.0).abs() < 1e-15);
    let b3 = block3(&spec).unwrap();
    assert_eq!(b3.node_count(), 7 * 5 * 4);
    assert_eq!(b3.cell_count(), 6 * 4 * 3);
    assert_eq!(b3.dims, Some([7, 5, 4]));
    check_mesh(&b3, "block3");
    let n2 = noisy_block2(&spec, 0.35, 1).unwrap();
    check_mesh(&n2, "noisy2");
    let n3 = noisy_block3(&spec, 0.35, 1).unwrap();
    check_mesh(&n3, "noisy3");
    // Noise moves interior points only.
    for mk in &n3.markers {
        for &v in &mk.node_list {
            assert_eq!(n3.points[v as usize], b3.points[v as usize]);
        }
    }
    assert_ne!(n3.points, b3.points);
    assert!(noisy_block2(&spec, 0.5, 1).is_err());
    assert!(block2(&BlockSpec {
        dims: [1, 5, 1],
        ..spec
    })
    .is_err());
}

#[test]
fn cavity_has_the_requested_stretching_jumps() {
    let c = cavity2(37, 9, 3.25).unwrap();
    check_mesh(&c, "cavity2");
    let dx: Vec<f64> = (0..36)
        .map(|i| c.points[i + 1][0] - c.points[i][0])
        .collect();
    let max_ratio = dx
        .windows(2)
        .map(|w| (w[1] / w[0]).max(w[0] / w[1]))
        .fold(0.0, f64::max);
    assert!((max_ratio - 3.25).abs() < 1e-9, "{max_ratio}");
    let jumps = dx
        .windows(2)
        .filter(|w| (w[1] / w[0]).max(w[0] / w[1]) > 1.5)
        .count();
    assert_eq!(jumps, 2);
    check_mesh(&cavity3(13, 5, 4, 3.25).unwrap(), "cavity3");
}

#[test]
fn shapes_are_valid() {
    let a = annulus(24, 6, 0.5, 2.0).unwrap();
    assert_eq!(a.node_count(), 24 * 6);
    assert_eq!(a.cell_count(), 2 * 24 * 5);
    check_mesh(&a, "annulus");
    assert_eq!(a.require_marker("inner").unwrap().node_list.len(), 24);
    assert_eq!(a.require_marker("outer").unwrap().node_list.len(), 24);
    let b = box_with_inner_box2(10, 4).unwrap();
    assert_eq!(b.node_count(), 11 * 11 - 3 * 3);
    assert_eq!(b.cell_count(), 2 * (100 - 16));
    check_mesh(&b, "box2");
    assert_eq!(b.require_marker("inner").unwrap().len(), 16);
    assert_eq!(b.require_marker("outer").unwrap().len(), 40);
    let c = box_with_inner_box3(6, 2).unwrap();
    assert_eq!(c.node_count(), 7 * 7 * 7 - 1);
    assert_eq!(c.cell_count(), 216 - 8);
    check_mesh(&c, "box3");
    assert_eq!(c.require_marker("inner").unwrap().len(), 24);
    assert_eq!(c.require_marker("outer").unwrap().len(), 6 * 36);
    assert!(box_with_inner_box2(10, 3).is_err());
    assert!(annulus(5, 3, 1.0, 2.0).is_err());
}

#[test]
fn marker_rotation() {
    let m = naca_hybrid(&AirfoilGrid::tiny()).unwrap();
    let qc = AirfoilGrid::quarter_chord();
    let r = rotate_markers2(&m, &["airfoil"], qc, 25.0).unwrap();
    let wall = m.require_marker("airfoil").unwrap();
    assert_eq!(r.nodes, wall.node_list);
    let (s, c) = (-25f64.to_radians().sin(), 25f64.to_radians().cos());
    for (&v, d) in r.nodes.iter().zip(&r.displacements) {
        let p = m.points[v as usize];
        let q = [p[0] + d[0], p[1] + d[1]];
        let (rp, rq) = ((p[0] - qc[0]).hypot(p[1]), (q[0] - qc[0]).hypot(q[1]));
        assert!((rp - rq).abs() < 1e-14);
        // Undo the rotation independently.
        let back = [
            qc[0] + c * (q[0] - qc[0]) - s * (q[1] - qc[1]),
            qc[1] + s * (q[0] - qc[0]) + c * (q[1] - qc[1]),
        ];
        assert!((back[0] - p[0]).abs() < 1e-14 && (back[1] - p[1]).abs() < 1e-14);
    }
    // Counter-clockwise: the trailing edge (node 0, at (1, 0)) moves up.
    assert!(r.displacements[0][1] > 0.0);
    let field = r.to_field(m.node_count());
    let mask = m.fixed_mask(&[]);
    assert_eq!(mask, m.boundary_mask());
    for (v, (f, &fixed)) in field.iter().zip(&mask).enumerate() {
        if !wall.node_list.contains(&(v as u32)) {
            assert_eq!(*f, [0.0, 0.0]);
        }
        assert_eq!(
            fixed == 1,
            m.markers.iter().any(|k| k.node_list.contains(&(v as u32)))
        );
    }
    assert!(rotate_markers2(&m, &["nope"], qc, 1.0).is_err());
    // 3D about z through the quarter chord equals the 2D rotation layer by layer.
    let m3 = extrude(&m, 1.0, 2).unwrap();
    let r3 = rotate_markers3(&m3, &["airfoil"], [0.25, 0.0, 0.0], [0.0, 0.0, 2.0], 25.0).unwrap();
    let n = m.node_count() as u32;
    for (&v, d) in r3.nodes.iter().zip(&r3.displacements) {
        let k = r.nodes.binary_search(&(v % n)).unwrap();
        let d2 = r.displacements[k];
        assert!((d[0] - d2[0]).abs() < 1e-14 && (d[1] - d2[1]).abs() < 1e-14 && d[2] == 0.0);
    }
}
