//! Stiffness choices (issue 15 item 4): wall distances, dual volumes, their factors and the
//! edge scaling, against independent computations; and what they are for: on the viscous
//! NACA 2412 hybrid mesh pitched 10°, wall-distance and inverse-volume stiffening leave fewer
//! inverted cells than Batina's `1/L` alone.

use deform_kernel::quality::inverted_cells;
use deform_kernel::spring::{
    batina_stiffness, dual_volumes, inverse_volume_factors, scale_stiffness,
    solve_linear_scratch_len, wall_distance_factors, wall_distances, LinearMethod, Preconditioner,
    SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Error, Graph};
use deform_meshgen::{naca_hybrid, rotate_markers2, AirfoilGrid, Mesh2};

fn lcg(s: &mut u64) -> f64 {
    *s = s
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*s >> 11) as f64 / (1u64 << 53) as f64
}

fn graph_of(mesh: &Mesh2, diagonals: bool) -> (Vec<u32>, Vec<u32>) {
    let cells = mesh.cells().unwrap();
    let n = mesh.node_count();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, diagonals)];
    let used = graph_from_cells(&cells, diagonals, &mut offsets, &mut targets).unwrap();
    targets.truncate(used);
    (offsets, targets)
}

#[test]
fn wall_distances_are_the_nearest_wall_node_distances() {
    let mut s = 11u64;
    let points: Vec<[f64; 3]> = (0..300)
        .map(|_| [lcg(&mut s) * 4.0 - 2.0, lcg(&mut s), lcg(&mut s) * 1e-3])
        .collect();
    let wall: Vec<u32> = (0..300).step_by(17).map(|i| i as u32).collect();
    let mut d = vec![-1.0; points.len()];
    wall_distances(&points, &wall, &mut d).unwrap();
    for (i, p) in points.iter().enumerate() {
        // Independent: the smallest hypot over the wall nodes, in reverse order.
        let expect = wall
            .iter()
            .rev()
            .map(|&w| {
                let q = points[w as usize];
                ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        assert!(
            (d[i] - expect).abs() <= 1e-15 * expect.max(1.0),
            "{i}: {} vs {expect}",
            d[i]
        );
    }
    for &w in &wall {
        assert_eq!(d[w as usize], 0.0);
    }
    // Bad input: nothing written.
    let mut untouched = vec![7.0; points.len()];
    assert!(matches!(
        wall_distances(&points, &[], &mut untouched),
        Err(Error::InvalidParameter { arg: "wall", .. })
    ));
    assert!(matches!(
        wall_distances(&points, &[0, 300], &mut untouched),
        Err(Error::IndexOutOfRange {
            arg: "wall",
            position: 1,
            index: 300,
            ..
        })
    ));
    let mut bad = points.clone();
    bad[5][1] = f64::NAN;
    assert!(matches!(
        wall_distances(&bad, &wall, &mut untouched),
        Err(Error::NonFinite {
            arg: "points",
            position: 5
        })
    ));
    assert!(untouched.iter().all(|&v| v == 7.0));
}

#[test]
fn dual_volumes_share_each_cell_among_its_nodes() {
    let mesh = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
    let cells = mesh.cells().unwrap();
    let n = mesh.node_count();
    let mut v = vec![0.0; n];
    let mut scratch = vec![0.0; cells.len()];
    dual_volumes(&cells, &mesh.points, &mut v, &mut scratch).unwrap();
    // Independent: shoelace areas, shared equally.
    let mut expect = vec![0.0; n];
    let mut total = 0.0;
    for c in 0..cells.len() {
        let (_, nodes) = cells.cell(c).unwrap();
        let m = nodes.len();
        let mut a = 0.0;
        for k in 0..m {
            let p = mesh.points[nodes[k] as usize];
            let q = mesh.points[nodes[(k + 1) % m] as usize];
            a += p[0] * q[1] - q[0] * p[1];
        }
        let a = (0.5 * a).abs();
        total += a;
        for &i in nodes {
            expect[i as usize] += a / m as f64;
        }
    }
    for i in 0..n {
        assert!((v[i] - expect[i]).abs() <= 1e-9 * expect[i] + 1e-300, "{i}");
    }
    let sum: f64 = v.iter().sum();
    assert!((sum - total).abs() <= 1e-12 * total);
    // Scratch too short: typed error, nothing written.
    let mut untouched = vec![3.0; n];
    let mut short = vec![0.0; cells.len() - 1];
    assert!(matches!(
        dual_volumes(&cells, &mesh.points, &mut untouched, &mut short),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    assert!(untouched.iter().all(|&x| x == 3.0));
}

#[test]
fn factors_are_normalised_by_the_mean_and_scaling_keeps_exact_symmetry() {
    let mut d = vec![0.0, 1.0, 2.0, 5.0];
    wall_distance_factors(&mut d, 1.0).unwrap();
    let mean: f64 = 8.0 / 4.0;
    // The wall node is floored at 1e-3 of the mean distance.
    assert_eq!(
        d,
        [mean / (1e-3 * mean), mean / 1.0, mean / 2.0, mean / 5.0]
    );
    let mut v = vec![1.0, 4.0];
    inverse_volume_factors(&mut v, 2.0).unwrap();
    assert_eq!(v, [2.5f64.powf(2.0), (2.5f64 / 4.0).powf(2.0)]);
    // Bad values and exponents: typed errors, nothing written.
    let mut z = vec![0.0, 0.0];
    assert!(wall_distance_factors(&mut z, 1.0).is_err());
    let mut neg = vec![1.0, -1.0];
    assert!(matches!(
        wall_distance_factors(&mut neg, 1.0),
        Err(Error::NonPositive { position: 1, .. })
    ));
    assert_eq!(neg, [1.0, -1.0]);
    let mut big = vec![1e-300, 1.0];
    assert!(matches!(
        inverse_volume_factors(&mut big, 400.0),
        Err(Error::InvalidParameter {
            arg: "exponent",
            ..
        })
    ));
    assert_eq!(big, [1e-300, 1.0]);

    let mesh = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
    let (offsets, targets) = graph_of(&mesh, true);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut k = vec![0.0; g.edge_count()];
    batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
    let k0 = k.clone();
    let mut s = 5u64;
    let f: Vec<f64> = (0..mesh.node_count())
        .map(|_| 0.5 + lcg(&mut s) * 100.0)
        .collect();
    scale_stiffness(&g, &f, &mut k).unwrap();
    let mut e = 0;
    for (i, _, row) in g.rows() {
        for &j in row {
            let expect = k0[e] * (f[i] + f[j as usize]) / 2.0;
            assert!((k[e] - expect).abs() <= 2e-16 * expect);
            // Exact symmetry: the reverse edge has the same bits.
            let back = g.neighbors(j as usize).binary_search(&(i as u32)).unwrap();
            let eb = offsets[j as usize] as usize + back;
            assert_eq!(k0[e].to_bits(), k0[eb].to_bits());
            assert_eq!(k[e].to_bits(), k[eb].to_bits());
            e += 1;
        }
    }
    // A bad factor: typed error, stiffness untouched.
    let mut f_bad = f.clone();
    f_bad[9] = 0.0;
    let before = k.clone();
    assert!(matches!(
        scale_stiffness(&g, &f_bad, &mut k),
        Err(Error::NonPositive {
            arg: "factors",
            position: 9
        })
    ));
    assert_eq!(before, k);
}

/// Linear springs on the displacements of the pitched airfoil with stiffness `k`: the number
/// of inverted cells.
fn inverted_after_pitch(
    mesh: &Mesh2,
    offsets: &[u32],
    targets: &[u32],
    k: &[f64],
    deg: f64,
) -> usize {
    let n = mesh.node_count();
    let g = Graph::new(offsets, targets).unwrap();
    let fixed = mesh.boundary_mask();
    let mut ss = vec![0u32; n];
    let sys = SpringSystem::new(g, k, &fixed, &mut ss).unwrap();
    let rot = rotate_markers2(mesh, &["airfoil"], AirfoilGrid::quarter_chord(), deg).unwrap();
    let mut disp: Vec<[f64; 2]> = rot.to_field(n);
    let m = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    };
    let opts = SolveOptions {
        residual_tol: 1e-10,
        max_iterations: 100_000,
        update_tol: 0.0,
    };
    let mut sc = vec![[0.0; 2]; solve_linear_scratch_len(&m, n)];
    assert!(
        sys.solve_linear(&mut disp, m, &opts, &mut sc)
            .unwrap()
            .converged
    );
    let moved: Vec<[f64; 2]> = mesh
        .points
        .iter()
        .zip(&disp)
        .map(|(p, d)| [p[0] + d[0], p[1] + d[1]])
        .collect();
    inverted_cells(&mesh.cells().unwrap(), &mesh.points, &moved).unwrap()
}

#[test]
fn wall_distance_and_inverse_volume_stiffening_invert_fewer_cells_than_batina_alone() {
    let mesh = naca_hybrid(&AirfoilGrid::viscous()).unwrap();
    let n = mesh.node_count();
    let (offsets, targets) = graph_of(&mesh, true);
    let g = Graph::new(&offsets, &targets).unwrap();
    let mut batina = vec![0.0; g.edge_count()];
    batina_stiffness(&g, &mesh.points, 1.0, &mut batina).unwrap();

    let wall: Vec<u32> = mesh.marker("airfoil").unwrap().node_list.clone();
    let mut f = vec![0.0; n];
    wall_distances(&mesh.points, &wall, &mut f).unwrap();
    wall_distance_factors(&mut f, 1.0).unwrap();
    let mut k_wall = batina.clone();
    scale_stiffness(&g, &f, &mut k_wall).unwrap();

    let cells = mesh.cells().unwrap();
    let mut v = vec![0.0; n];
    let mut scratch = vec![0.0; cells.len()];
    dual_volumes(&cells, &mesh.points, &mut v, &mut scratch).unwrap();
    inverse_volume_factors(&mut v, 1.0).unwrap();
    let mut k_vol = batina.clone();
    scale_stiffness(&g, &v, &mut k_vol).unwrap();

    let deg = -10.0;
    let plain = inverted_after_pitch(&mesh, &offsets, &targets, &batina, deg);
    let by_wall = inverted_after_pitch(&mesh, &offsets, &targets, &k_wall, deg);
    let by_volume = inverted_after_pitch(&mesh, &offsets, &targets, &k_vol, deg);
    println!("inverted cells at {deg}°: batina {plain}, wall distance {by_wall}, inverse volume {by_volume}");
    assert!(
        plain > 0,
        "the test needs a case where 1/L alone inverts cells"
    );
    assert!(by_wall < plain, "wall distance {by_wall} vs batina {plain}");
    assert!(
        by_volume < plain,
        "inverse volume {by_volume} vs batina {plain}"
    );
}
