//! 3D quaternion deformation on generated meshes: a box whose inner cube is turned and moved
//! rigidly, and an extruded NACA 2412 wing twisted and bent (far field fixed). Rotations come
//! from the boundary shape (3D normal alignment and twist), including the cube's sharp edges
//! and corners and the wing's sharp trailing edge. Checked: boundary points bit for bit, no
//! inverted cells, no folded cells where stated, and (rigid inner cube) the recovered
//! rotations equal the rigid one. Print the counts with `-- --nocapture`.
//!
//! Known limitation (measured, not hidden): on the coarse twisted wing, quaternion springs fold
//! a few corners of the skewed first-layer hexes at the sharp trailing edge (3 cells at 8°
//! twist, scaled Jacobian about −0.1; plain displacement springs fold 14) where IDW folds
//! none. The inner cube turned by 40° in its tight gap folds 3 corners with IDW (none with
//! quaternion springs, 3 with displacement springs).

use deform_kernel::quality::compare;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, deform_spring, deform_spring_scratch_len,
    propagate_spring_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, LinearMethod, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph, Quat};
use deform_meshgen::{
    box_with_inner_box3, extrude, naca_ogrid, twist_bend, AirfoilGrid, Mesh3, TwistBend,
};

/// Boundary nodes of the named markers (in marker order, each once) and their elements in
/// boundary-local numbering.
fn boundary(mesh: &Mesh3, names: &[&str]) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u8>) {
    let mut local = vec![u32::MAX; mesh.points.len()];
    let (mut nodes, mut offsets, mut el, mut kinds) =
        (Vec::new(), vec![0u32], Vec::new(), Vec::new());
    for name in names {
        let m = mesh.marker(name).unwrap();
        for &n in &m.node_list {
            if local[n as usize] == u32::MAX {
                local[n as usize] = nodes.len() as u32;
                nodes.push(n);
            }
        }
        for e in 0..m.kinds.len() {
            for &n in &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize] {
                el.push(local[n as usize]);
            }
            kinds.push(m.kinds[e]);
            offsets.push(el.len() as u32);
        }
    }
    (nodes, offsets, el, kinds)
}

fn quat_matrix_apply(q: Quat<f64>, v: [f64; 3]) -> [f64; 3] {
    // Independent of the kernel's `rotate`: the rotation matrix of q.
    let (w, x, y, z) = (q.w, q.x, q.y, q.z);
    let m = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// `(inverted, folded)` cell counts.
type Counts = (usize, usize);

/// Runs IDW (p = 2), quaternion springs and (baseline) displacement springs; checks the
/// boundary bits; returns the rotations of the IDW run and the counts of the three runs.
fn deform_both(
    mesh: &Mesh3,
    names: &[&str],
    deformed: &[[f64; 3]],
    label: &str,
) -> (Vec<Quat<f64>>, Counts, Counts, Counts) {
    let n = mesh.points.len();
    let (nodes, offs, el, kinds) = boundary(mesh, names);
    assert_eq!(nodes.len(), deformed.len());
    let elements = Cells::new(nodes.len(), &offs, &el, &kinds).unwrap();
    let cells = mesh.cells().unwrap();
    let motion = BoundaryMotion {
        nodes: &nodes,
        deformed,
        elements: Some(elements),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let mut t = vec![[0.0; 3]; n];
    let mut q = vec![Quat::identity(); n];
    let mut out = vec![[0.0; 3]; n];
    let mut s = vec![0.0; deform_idw_scratch_len::<3>(n, nodes.len())];
    deform_idw(&mesh.points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out).unwrap();
    let idw_q = q.clone();
    let check = |out: &[[f64; 3]], method: &str| -> (usize, usize) {
        for (k, &i) in nodes.iter().enumerate() {
            assert_eq!(
                out[i as usize].map(f64::to_bits),
                deformed[k].map(f64::to_bits)
            );
        }
        let rep = compare(&cells, &mesh.points, out, None, &mut []).unwrap();
        println!(
            "{label} {method}: inverted {} folded {} min volume ratio {:.3}, min scaled Jacobian {:.3}",
            rep.inverted_cells, rep.folded_cells, rep.min_measure_ratio, rep.min_scaled_jacobian
        );
        (rep.inverted_cells, rep.folded_cells)
    };
    let idw = check(&out, "IDW");
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, true)];
    let used = graph_from_cells(&cells, true, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let mut k = vec![0.0; used];
    batina_stiffness(&graph, &mesh.points, 1.0, &mut k).unwrap();
    let mut fixed = vec![0u8; n];
    for &i in &nodes {
        fixed[i as usize] = 1;
    }
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(graph, &k, &fixed, &mut ss).unwrap();
    let cg = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let mut values = vec![0.0; propagate_spring_scratch_len::<3>(&cg, n)];
    let mut s = vec![0.0; deform_spring_scratch_len::<3>(n, nodes.len())];
    let mut spring_run = |motion: &BoundaryMotion<'_, f64, 3>, out: &mut [[f64; 3]]| {
        let (_, rep) = deform_spring(
            &mesh.points,
            motion,
            &sys,
            cg,
            &SolveOptions::default(),
            &mut t,
            &mut q,
            &mut s,
            &mut values,
            out,
        )
        .unwrap();
        assert!(rep.converged);
    };
    spring_run(&motion, &mut out);
    let springs = check(&out, "springs");
    // Baseline: the identity rotation everywhere is plain displacement springs.
    let plain = BoundaryMotion {
        rotations: RotationSource::Rigid(Quat::identity()),
        ..motion
    };
    spring_run(&plain, &mut out);
    let baseline = check(&out, "displacement springs");
    (idw_q, idw, springs, baseline)
}

#[test]
fn box_with_rotated_inner_cube() {
    let mesh = box_with_inner_box3(8, 2).unwrap();
    let (nodes, ..) = boundary(&mesh, &["inner", "outer"]);
    let inner: std::collections::BTreeSet<u32> = mesh
        .marker("inner")
        .unwrap()
        .node_list
        .iter()
        .copied()
        .collect();
    for degrees in [15.0, 40.0] {
        let rigid = Quat::from_axis_angle([1.0, 2.0, 0.5], f64::to_radians(degrees)).unwrap();
        let shift = [0.05, -0.08, 0.03];
        let deformed: Vec<[f64; 3]> = nodes
            .iter()
            .map(|&i| {
                let p = mesh.points[i as usize];
                if inner.contains(&i) {
                    let r = quat_matrix_apply(rigid, p);
                    [r[0] + shift[0], r[1] + shift[1], r[2] + shift[2]]
                } else {
                    p
                }
            })
            .collect();
        let label = format!("inner cube {degrees}°");
        let (q, idw, springs, _) = deform_both(&mesh, &["inner", "outer"], &deformed, &label);
        // The shape-derived rotation of every inner-cube node (faces, edges, corners) is the
        // rigid rotation.
        for &i in &inner {
            let d = q[i as usize].dot(rigid).abs();
            assert!((1.0 - d).abs() < 1e-12, "node {i}: |q·rigid| = {d}");
        }
        // Quaternion springs keep every cell valid; IDW keeps every volume positive and, at
        // 15°, every corner (at 40° in this tight gap it folds 3 corners, as do plain
        // displacement springs).
        assert_eq!(springs, (0, 0), "{label}");
        assert_eq!(idw.0, 0, "{label}");
        if degrees <= 15.0 {
            assert_eq!(idw.1, 0, "{label}");
        }
    }
}

#[test]
fn extruded_wing_twisted_and_bent() {
    let mesh2 = naca_ogrid(&AirfoilGrid::tiny()).unwrap();
    let mesh = extrude(&mesh2, 2.0, 6).unwrap();
    let names = ["airfoil", "farfield"];
    let (nodes, ..) = boundary(&mesh, &names);
    let wall: std::collections::BTreeSet<u32> = mesh
        .marker("airfoil")
        .unwrap()
        .node_list
        .iter()
        .copied()
        .collect();
    for (twist, bend) in [(8.0, 0.1), (20.0, 0.3)] {
        let map = TwistBend {
            span: 2.0,
            tip_twist_deg: twist,
            tip_bend: bend,
            centre: [0.25, 0.0],
        };
        let moved = twist_bend(&mesh, &map).unwrap();
        let deformed: Vec<[f64; 3]> = nodes
            .iter()
            .map(|&i| {
                if wall.contains(&i) {
                    moved[i as usize]
                } else {
                    mesh.points[i as usize]
                }
            })
            .collect();
        let label = format!("wing twist {twist}° bend {bend}");
        let (_, idw, springs, baseline) = deform_both(&mesh, &names, &deformed, &label);
        // Every volume stays positive; IDW keeps every corner valid at the mild setting. The
        // springs fold a few corners of the skewed first-layer cells at the sharp trailing
        // edge (reported, see the module docs).
        assert_eq!((idw.0, springs.0), (0, 0), "{label}");
        if twist <= 8.0 {
            assert_eq!(idw.1, 0, "{label}");
        }
        // Quaternion springs fold far fewer cells than displacement springs.
        assert!(
            2 * springs.1 < baseline.1,
            "{label}: {springs:?} vs {baseline:?}"
        );
    }
}
