//! The elasticity solve preconditioned by smoothed aggregation with the rigid-body modes as
//! near-null space (`ElasticSystem::rigid_amg` / `solve_rigid_amg`): the same answer as block
//! Jacobi (2D, 3D, f32), fewer iterations than the scalar hierarchy per component, and
//! iteration counts against pyamg's `smoothed_aggregation_solver(A, B=rigid_modes)` on the
//! same matrix (`ref_pyamg_rigid.py` beside this file); typed errors that write nothing.

#[path = "../support/mod.rs"]
mod support;

use std::fmt::Write as _;
use std::path::Path;

use deform_kernel::elasticity::{elastic_amg_scratch_len, elastic_rigid_amg_scratch_len, Modulus};
use deform_kernel::spring::{AmgHierarchy, AmgOptions, RigidAmg, SolveOptions, SpringSystem};
use deform_kernel::{Error, Real};
use support::elasticity::{assembled, grid2, grid3, solve, Assembled, Kind, Mesh};
use support::python::run_script;

/// The options the tool uses (a coarsest level of at most 64 nodes).
fn options<T: Real>() -> AmgOptions<T> {
    AmgOptions {
        max_coarse: 64,
        ..AmgOptions::default()
    }
}

/// CG preconditioned by the rigid-mode hierarchy of `a` at `points`; the iterations.
fn rigid_solve<T: Real, const D: usize>(
    a: &Assembled<T, D>,
    fixed: &[u8],
    points: &[[T; D]],
    u: &mut [[T; D]],
) -> usize {
    let sys = a.system(fixed);
    let n = u.len();
    let w = vec![T::ONE; a.targets.len()];
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(a.graph(), &w, fixed, &mut anchor).unwrap();
    let opts = options();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = RigidAmg::setup_len(&spring, D, &opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![T::ZERO; sizes.values];
    let h = sys
        .rigid_amg(&spring, points, &opts, &mut work, &mut index, &mut values)
        .unwrap();
    assert!(h.levels() >= 2, "{sizes:?}");
    let len = elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, D).unwrap();
    let mut scratch = vec![[T::ZERO; D]; len];
    let r = sys
        .solve_rigid_amg(&h, u, &SolveOptions::default(), &mut scratch)
        .unwrap();
    assert!(r.converged, "{r:?}");
    r.iterations
}

/// CG preconditioned by the scalar hierarchy on every component; the iterations.
fn scalar_solve<const D: usize>(a: &Assembled<f64, D>, fixed: &[u8], u: &mut [[f64; D]]) -> usize {
    let sys = a.system(fixed);
    let n = u.len();
    let mut w = vec![0.0; a.targets.len()];
    sys.amg_weights(&mut w).unwrap();
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(a.graph(), &w, fixed, &mut anchor).unwrap();
    let opts = AmgOptions::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = AmgHierarchy::setup_len(&spring, &opts, &mut work).unwrap();
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![0.0; sizes.values]);
    let h = AmgHierarchy::setup(&spring, &opts, &mut work, &mut index, &mut values).unwrap();
    let mut scratch = vec![[0.0; D]; elastic_amg_scratch_len(n, h.coarse_unknowns()).unwrap()];
    let r = sys
        .solve_amg(&spring, &h, u, &SolveOptions::default(), &mut scratch)
        .unwrap();
    assert!(r.converged, "{r:?}");
    r.iterations
}

/// A smooth boundary motion (zero inside).
fn boundary_motion<const D: usize>(points: &[[f64; D]], boundary: &[bool]) -> Vec<[f64; D]> {
    points
        .iter()
        .zip(boundary)
        .map(|(p, &b)| {
            std::array::from_fn(|c| {
                if b {
                    0.05 * (4.0 * p[(c + 1) % D] + c as f64).sin()
                } else {
                    0.0
                }
            })
        })
        .collect()
}

fn max_diff<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()))
}

fn agrees<const D: usize>(m: &Mesh<D>) -> (usize, usize, usize) {
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let start = boundary_motion(&m.points, &m.boundary);
    let mut bj = start.clone();
    let rb = solve(&a, &fixed, &mut bj, &SolveOptions::default());
    let mut rg = start.clone();
    let ir = rigid_solve(&a, &fixed, &m.points, &mut rg);
    let mut sc = start.clone();
    let is = scalar_solve(&a, &fixed, &mut sc);
    let err = max_diff(&bj, &rg);
    assert!(err < 1e-9, "rigid multigrid vs block Jacobi: {err:e}");
    // The same bits on a second run.
    let mut again = start;
    rigid_solve(&a, &fixed, &m.points, &mut again);
    assert_eq!(rg, again);
    (rb.iterations, is, ir)
}

#[test]
fn rigid_multigrid_agrees_with_block_jacobi_in_fewer_iterations_than_the_scalar_one() {
    for (name, (bj, scalar, rigid)) in [
        ("2D mixed 40x40", agrees(&grid2(40, Kind::Mixed, 0.3))),
        ("2D triangles 48x48", agrees(&grid2(48, Kind::Simplex, 0.3))),
        ("3D hexahedra 10^3", agrees(&grid3(10, Kind::Box, 0.2))),
        ("3D mixed 8^3", agrees(&grid3(8, Kind::Mixed, 0.2))),
    ] {
        eprintln!("{name}: block Jacobi {bj}, scalar SA {scalar}, rigid-mode SA {rigid}");
        assert!(rigid < scalar, "{name}: rigid {rigid} vs scalar {scalar}");
        assert!(3 * rigid < bj, "{name}: rigid {rigid} vs block Jacobi {bj}");
    }
}

#[test]
fn rigid_multigrid_in_f32() {
    let m = grid2(24, Kind::Mixed, 0.3);
    let p32: Vec<[f32; 2]> = m.points_as();
    let a = assembled(&m, &p32, Modulus::InverseVolume, None, 0.3f32);
    let fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let start = boundary_motion(&m.points, &m.boundary);
    let mut u: Vec<[f32; 2]> = start.iter().map(|v| v.map(|x| x as f32)).collect();
    rigid_solve(&a, &fixed, &p32, &mut u);
    let a64 = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let mut u64 = start;
    solve(&a64, &fixed, &mut u64, &SolveOptions::default());
    let err = u
        .iter()
        .flatten()
        .zip(u64.iter().flatten())
        .fold(0.0f64, |s, (&x, &y)| s.max((x as f64 - y).abs()));
    assert!(err < 1e-4, "f32 vs f64: {err:e}");
}

/// The free-free block and right-hand side as text for the reference; runs it and returns
/// pyamg's iterations and solution (free nodes).
fn pyamg_reference<const D: usize>(
    a: &Assembled<f64, D>,
    fixed: &[u8],
    points: &[[f64; D]],
    u: &[[f64; D]],
) -> (usize, Vec<f64>) {
    let n = points.len();
    let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
    let mut id = vec![usize::MAX; n];
    for (k, &i) in free.iter().enumerate() {
        id[i] = k;
    }
    let mut trip = String::new();
    let mut nnz = 0;
    let mut rhs = vec![0.0; free.len() * D];
    let mut put = |r: usize, c: usize, blk: &[[f64; D]; D], trip: &mut String| {
        for (x, row) in blk.iter().enumerate() {
            for (y, v) in row.iter().enumerate() {
                writeln!(trip, "{} {} {v:e}", r * D + x, c * D + y).unwrap();
                nnz += 1;
            }
        }
    };
    for &i in &free {
        put(id[i], id[i], &a.diag[i], &mut trip);
        let (s, e) = (a.offsets[i] as usize, a.offsets[i + 1] as usize);
        for q in s..e {
            let j = a.targets[q] as usize;
            if fixed[j] == 0 {
                put(id[i], id[j], &a.off[q], &mut trip);
            } else {
                for (x, row) in a.off[q].iter().enumerate() {
                    for (v, uy) in row.iter().zip(&u[j]) {
                        rhs[id[i] * D + x] -= v * uy;
                    }
                }
            }
        }
    }
    let mut s = format!("{D} {} {nnz}\n", free.len());
    for &i in &free {
        let row: Vec<String> = points[i].iter().map(|x| format!("{x:e}")).collect();
        writeln!(s, "{}", row.join(" ")).unwrap();
    }
    s.push_str(&trip);
    for v in &rhs {
        writeln!(s, "{v:e}").unwrap();
    }
    let dir = std::env::temp_dir().join(format!("deform-rigid-amg-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let input = dir.join(format!("k{D}-{call}.txt"));
    std::fs::write(&input, s).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/elasticity/ref_pyamg_rigid.py");
    let out = run_script(&script, &[input.to_str().unwrap()]);
    let mut lines = out.lines();
    let it = lines.next().unwrap().trim().parse().unwrap();
    (it, lines.map(|l| l.trim().parse().unwrap()).collect())
}

/// Ours against pyamg on one mesh: the same solution, and our iterations within `ratio`
/// of pyamg's.
fn against_pyamg<const D: usize>(name: &str, m: &Mesh<D>, start: &[[f64; D]], ratio: f64) {
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let (theirs, u_ref) = pyamg_reference(&a, &fixed, &m.points, start);
    let mut u = start.to_vec();
    let ours = rigid_solve(&a, &fixed, &m.points, &mut u);
    let free: Vec<f64> = (0..u.len())
        .filter(|&i| fixed[i] == 0)
        .flat_map(|i| u[i])
        .collect();
    let scale = start.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    let err = free
        .iter()
        .zip(&u_ref)
        .fold(0.0f64, |s, (x, y)| s.max((x - y).abs()));
    eprintln!("{name}: ours {ours} iterations, pyamg {theirs}; solutions differ by {err:e}");
    // Both stop at a relative residual of 1e-10 on an ill-conditioned operator (E = 1/V).
    assert!(err < 1e-5 * scale, "{name}: {err:e}");
    assert!(
        (ours as f64) <= ratio * theirs as f64,
        "{name}: ours {ours} vs pyamg {theirs}"
    );
}

/// The generated NACA 2412 O-grid (6,144 nodes) with its wall turned 10° about the quarter
/// chord (the displacement of the rotation), the far field fixed.
fn naca_ogrid() -> (Mesh<2>, Vec<[f64; 2]>) {
    let g = deform_meshgen::naca_ogrid(&deform_meshgen::AirfoilGrid::default()).unwrap();
    let mut boundary = vec![false; g.points.len()];
    let wall = &g
        .markers
        .iter()
        .find(|m| m.name == "airfoil")
        .unwrap()
        .node_list;
    for mk in &g.markers {
        for &i in &mk.node_list {
            boundary[i as usize] = true;
        }
    }
    let th = -10f64.to_radians();
    let mut start = vec![[0.0; 2]; g.points.len()];
    for &i in wall {
        let [x, y] = g.points[i as usize];
        let (dx, dy) = (x - 0.25, y);
        start[i as usize] = [
            0.25 + th.cos() * dx - th.sin() * dy - x,
            th.sin() * dx + th.cos() * dy - y,
        ];
    }
    let m = Mesh {
        points: g.points,
        offsets: g.offsets,
        nodes: g.nodes,
        kinds: g.kinds,
        boundary,
    };
    (m, start)
}

#[test]
fn iterations_against_pyamg_with_rigid_modes() {
    let (m, start) = naca_ogrid();
    against_pyamg("NACA 2412 O-grid 128x48, 10 deg", &m, &start, 1.5);
    // pyamg smooths with symmetric block Gauss–Seidel, the kernel with Chebyshev in the point
    // diagonal (partition-independent): on this small 3D block the gap is 2× (16 vs 8).
    let m = grid3(12, Kind::Box, 0.2);
    let start = boundary_motion(&m.points, &m.boundary);
    against_pyamg("3D hexahedra 12^3", &m, &start, 2.0);
}

#[test]
fn typed_errors_write_nothing() {
    let m = grid2(8, Kind::Mixed, 0.2);
    let a = assembled(&m, &m.points, Modulus::Constant, None, 0.3);
    let fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let sys = a.system(&fixed);
    let n = m.points.len();
    let w = vec![1.0; a.targets.len()];
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(a.graph(), &w, &fixed, &mut anchor).unwrap();
    let opts = options();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    assert!(matches!(
        RigidAmg::setup_len(&spring, 4, &opts, &mut work),
        Err(Error::InvalidParameter { arg: "dim", .. })
    ));
    let sizes = RigidAmg::setup_len(&spring, 2, &opts, &mut work).unwrap();
    // Short values buffer: refused, nothing written.
    let mut index = vec![7u32; sizes.index];
    let mut short = vec![3.0; sizes.values - 1];
    let e = sys.rigid_amg(&spring, &m.points, &opts, &mut work, &mut index, &mut short);
    assert!(
        matches!(e, Err(Error::BufferTooSmall { arg: "values", .. })),
        "{e:?}"
    );
    assert!(index.iter().all(|&x| x == 7) && short.iter().all(|&x| x == 3.0));
    // Another fixed mask.
    let mut other = fixed.clone();
    other[n / 2] = 1;
    let mut anchor2 = vec![0u32; n];
    let spring2 = SpringSystem::new(a.graph(), &w, &other, &mut anchor2).unwrap();
    let mut values = vec![0.0; sizes.values];
    let e = sys.rigid_amg(
        &spring2,
        &m.points,
        &opts,
        &mut work,
        &mut index,
        &mut values,
    );
    assert!(
        matches!(e, Err(Error::InvalidParameter { arg: "spring", .. })),
        "{e:?}"
    );
    // Short scratch: the values stay as they were.
    let h = sys
        .rigid_amg(
            &spring,
            &m.points,
            &opts,
            &mut work,
            &mut index,
            &mut values,
        )
        .unwrap();
    let len = elastic_rigid_amg_scratch_len(n, sizes.coarse_scalars, 2).unwrap();
    let mut scratch = vec![[0.0; 2]; len - 1];
    let mut u = boundary_motion(&m.points, &m.boundary);
    let before = u.clone();
    let e = sys.solve_rigid_amg(&h, &mut u, &SolveOptions::default(), &mut scratch);
    assert!(
        matches!(e, Err(Error::BufferTooSmall { arg: "scratch", .. })),
        "{e:?}"
    );
    assert_eq!(u, before);
}

/// The constrained problem solved densely on its own unknowns: both components at free
/// nodes, `y` only at the sliding nodes (`x = 0` there: the plane `x = 0`), the rest given.
fn dense_sliding(a: &Assembled<f64, 2>, kind: &[u8], u: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = u.len();
    let mut k = vec![vec![0.0; 2 * n]; 2 * n];
    for i in 0..n {
        for (x, row) in a.diag[i].iter().enumerate() {
            for (y, &v) in row.iter().enumerate() {
                k[2 * i + x][2 * i + y] += v;
            }
        }
        for q in a.offsets[i] as usize..a.offsets[i + 1] as usize {
            let j = a.targets[q] as usize;
            for (x, row) in a.off[q].iter().enumerate() {
                for (y, &v) in row.iter().enumerate() {
                    k[2 * i + x][2 * j + y] += v;
                }
            }
        }
    }
    let unknown = |dof: usize| match kind[dof / 2] {
        0 => true,
        2 => dof % 2 == 1,
        _ => false,
    };
    let dofs: Vec<usize> = (0..2 * n).filter(|&d| unknown(d)).collect();
    let given: Vec<f64> = (0..2 * n)
        .map(|d| {
            if unknown(d) || kind[d / 2] == 2 {
                0.0
            } else {
                u[d / 2][d % 2]
            }
        })
        .collect();
    let m = dofs.len();
    let mut sys: Vec<Vec<f64>> = dofs
        .iter()
        .map(|&r| {
            let mut row: Vec<f64> = dofs.iter().map(|&c| k[r][c]).collect();
            row.push(-(0..2 * n).map(|c| k[r][c] * given[c]).sum::<f64>());
            row
        })
        .collect();
    for p in 0..m {
        for r in p + 1..m {
            let f = sys[r][p] / sys[p][p];
            let pivot = sys[p].clone();
            for (v, pv) in sys[r].iter_mut().zip(&pivot).skip(p) {
                *v -= f * pv;
            }
        }
    }
    let mut x = vec![0.0; m];
    for p in (0..m).rev() {
        let s: f64 = (p + 1..m).map(|c| sys[p][c] * x[c]).sum();
        x[p] = (sys[p][m] - s) / sys[p][p];
    }
    let mut out: Vec<[f64; 2]> = (0..n).map(|i| [given[2 * i], given[2 * i + 1]]).collect();
    for (&d, &v) in dofs.iter().zip(&x) {
        out[d / 2][d % 2] = v;
    }
    out
}

#[test]
fn sliding_nodes_against_a_dense_constrained_solve() {
    use deform_kernel::elasticity::{
        elastic_rigid_amg_sliding_scratch_len, elastic_sliding_scratch_len,
    };
    use deform_kernel::spring::constraints::Constraints;
    let m = grid2(16, Kind::Mixed, 0.3);
    let n = m.points.len();
    // The side x = 0 (corners excepted) slides on its plane; the rest of the boundary moves.
    let kind: Vec<u8> = (0..n)
        .map(|i| {
            let [x, y] = m.points[i];
            match (m.boundary[i], x == 0.0 && y > 0.0 && y < 1.0) {
                (true, true) => 2,
                (true, false) => 1,
                _ => 0,
            }
        })
        .collect();
    let dirs = vec![[1.0, 0.0]; n];
    let c = Constraints::new(&kind, &dirs).unwrap();
    let fixed: Vec<u8> = kind.iter().map(|&k| u8::from(k == 1)).collect();
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let sys = a.system(&fixed);
    let start: Vec<[f64; 2]> = m
        .points
        .iter()
        .zip(&kind)
        .map(|(p, &k)| {
            if k == 1 {
                [0.05 * (3.0 * p[1]).sin(), 0.04 * p[0]]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let reference = dense_sliding(&a, &kind, &start);
    let opts = SolveOptions::default();
    let mut bj = start.clone();
    let mut scratch = vec![[0.0; 2]; elastic_sliding_scratch_len(n).unwrap()];
    let rb = sys.solve_sliding(&c, &mut bj, &opts, &mut scratch).unwrap();
    // The multigrid of K + s N (a stiff spring across each sliding node's plane).
    let w = vec![1.0; a.targets.len()];
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(a.graph(), &w, &fixed, &mut anchor).unwrap();
    let o = options();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = RigidAmg::setup_len(&spring, 2, &o, &mut work).unwrap();
    let (mut index, mut values) = (vec![0u32; sizes.index], vec![0.0; sizes.values]);
    let h = sys
        .rigid_amg_sliding(
            &c,
            &spring,
            &m.points,
            &o,
            &mut work,
            &mut index,
            &mut values,
        )
        .unwrap();
    let len = elastic_rigid_amg_sliding_scratch_len(n, sizes.coarse_scalars, 2).unwrap();
    let mut scratch = vec![[0.0; 2]; len];
    let mut mg = start.clone();
    let rm = sys
        .solve_rigid_amg_sliding(&c, &h, &mut mg, &opts, &mut scratch)
        .unwrap();
    eprintln!(
        "sliding: block Jacobi {} iterations, rigid multigrid {}",
        rb.iterations, rm.iterations
    );
    assert!(rb.converged && rm.converged);
    let scale = start.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    for (name, u) in [("block Jacobi", &bj), ("multigrid", &mg)] {
        let err = max_diff(u, &reference);
        assert!(err < 1e-8 * scale, "{name}: {err:e}");
        for i in (0..n).filter(|&i| kind[i] == 2) {
            assert_eq!(u[i][0], 0.0, "{name}: sliding node {i} left its plane");
        }
    }
    // Some sliding node does slide.
    assert!((0..n).any(|i| kind[i] == 2 && mg[i][1].abs() > 1e-3 * scale));
    assert!(rm.iterations < rb.iterations);
}
