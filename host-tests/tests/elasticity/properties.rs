//! Linear elasticity (kernel/src/elasticity): patch tests for every element kind in 2D and
//! 3D (f64 and f32), rigid-body modes in the null space of the unconstrained operator, the
//! CG solve against a dense direct solve, the multigrid-preconditioned solve against block
//! Jacobi, load increments, typed errors that leave every buffer unchanged, golden bits.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::elasticity::{
    assemble, cell_moduli, deform_incremental, elastic_amg_scratch_len, Block, ElasticSystem,
    IncrementBuffers, Increments, Modulus,
};
use deform_kernel::spring::{wall_distances, AmgHierarchy, AmgOptions, SolveOptions, SpringSystem};
use deform_kernel::{Error, Real};
use support::elasticity::{assembled, fnv, grid2, grid3, solve, Assembled, Kind, Mesh};

/// A linear field `A x + c` (the patch test's exact solution for a uniform material).
fn linear<const D: usize>(x: &[f64; D]) -> [f64; D] {
    affine(
        x,
        &[
            [0.11, -0.05, 0.02],
            [0.03, 0.07, -0.04],
            [-0.06, 0.01, 0.09],
        ],
    )
}

/// An infinitesimal rigid motion `W x + c` (`W` skew): stress-free, so it is the exact
/// solution whatever the moduli.
fn rigid<const D: usize>(x: &[f64; D]) -> [f64; D] {
    affine(
        x,
        &[[0.0, -0.05, 0.02], [0.05, 0.0, -0.04], [-0.02, 0.04, 0.0]],
    )
}

fn affine<const D: usize>(x: &[f64; D], a: &[[f64; 3]; 3]) -> [f64; D] {
    let c = [0.01, -0.02, 0.015];
    let mut out = [0.0; D];
    for (i, o) in out.iter_mut().enumerate() {
        *o = c[i] + (0..D).map(|j| a[i][j] * x[j]).sum::<f64>();
    }
    out
}

fn fixed_of<const D: usize>(m: &Mesh<D>) -> Vec<u8> {
    m.boundary.iter().map(|&b| b as u8).collect()
}

fn tight<T: Real>() -> SolveOptions<T> {
    SolveOptions {
        max_iterations: 20_000,
        residual_tol: T::from_f64(1e-13).max(T::from_f64(50.0) * T::EPSILON),
        update_tol: T::ZERO,
    }
}

/// Prescribes the linear field (the rigid one for non-uniform moduli) on the boundary,
/// solves, returns the largest interior error relative to the field's size.
fn patch_error<T: Real, const D: usize>(m: &Mesh<D>, modulus: Modulus, nu: f64) -> f64 {
    let field = if modulus == Modulus::Constant {
        linear::<D>
    } else {
        rigid::<D>
    };
    let points = m.points_as::<T>();
    let fixed = fixed_of(m);
    let wall: Vec<T> = if modulus == Modulus::WallDistance {
        let wall_nodes: Vec<u32> = (0..m.points.len() as u32)
            .filter(|&i| m.points[i as usize][0] == 0.0 && m.boundary[i as usize])
            .collect();
        let mut d = vec![T::ZERO; points.len()];
        wall_distances(&points, &wall_nodes, &mut d).unwrap();
        d
    } else {
        vec![]
    };
    let wall = (!wall.is_empty()).then_some(&wall[..]);
    let a = assembled(m, &points, modulus, wall, T::from_f64(nu));
    let mut u: Vec<[T; D]> = m
        .points
        .iter()
        .zip(&m.boundary)
        .map(|(p, &b)| {
            if b {
                field(p).map(T::from_f64)
            } else {
                [T::ZERO; D]
            }
        })
        .collect();
    let report = solve(&a, &fixed, &mut u, &tight());
    assert!(report.converged, "{report:?}");
    let mut worst = 0.0f64;
    for (p, u) in m.points.iter().zip(&u) {
        let exact = field(p);
        for (e, v) in exact.iter().zip(u) {
            worst = worst.max((e - v.to_f64()).abs() / 0.1);
        }
    }
    worst
}

#[test]
fn patch_test_2d_every_element_and_modulus() {
    for kind in [Kind::Simplex, Kind::Box, Kind::Mixed] {
        let m = grid2(6, kind, 0.25);
        for modulus in [
            Modulus::Constant,
            Modulus::InverseVolume,
            Modulus::WallDistance,
        ] {
            for nu in [0.0, 0.3, 0.45] {
                let e64 = patch_error::<f64, 2>(&m, modulus, nu);
                assert!(e64 < 1e-11, "{kind:?} {modulus:?} ν={nu}: {e64:e}");
            }
            let e32 = patch_error::<f32, 2>(&m, modulus, 0.3);
            assert!(e32 < 2e-4, "f32 {kind:?} {modulus:?}: {e32:e}");
        }
    }
}

#[test]
fn patch_test_3d_every_element() {
    for kind in [
        Kind::Simplex,
        Kind::Box,
        Kind::Prism,
        Kind::Pyramid,
        Kind::Mixed,
    ] {
        let m = grid3(3, kind, 0.2);
        for modulus in [Modulus::Constant, Modulus::InverseVolume] {
            let e64 = patch_error::<f64, 3>(&m, modulus, 0.3);
            assert!(e64 < 1e-11, "{kind:?} {modulus:?}: {e64:e}");
        }
        let e32 = patch_error::<f32, 3>(&m, Modulus::InverseVolume, 0.3);
        assert!(e32 < 2e-4, "f32 {kind:?}: {e32:e}");
    }
}

/// The rigid-body modes of dimension `D` at `points`: translations and infinitesimal
/// rotations.
fn rigid_modes<const D: usize>(points: &[[f64; D]]) -> Vec<Vec<[f64; D]>> {
    let mut modes = vec![];
    for c in 0..D {
        modes.push(
            points
                .iter()
                .map(|_| {
                    let mut t = [0.0; D];
                    t[c] = 1.0;
                    t
                })
                .collect(),
        );
    }
    let axes: &[(usize, usize)] = if D == 2 {
        &[(0, 1)]
    } else {
        &[(0, 1), (1, 2), (2, 0)]
    };
    for &(a, b) in axes {
        modes.push(
            points
                .iter()
                .map(|p| {
                    let mut r = [0.0; D];
                    r[a] = -p[b];
                    r[b] = p[a];
                    r
                })
                .collect(),
        );
    }
    modes
}

fn null_space_residual<const D: usize>(m: &Mesh<D>) -> f64 {
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.3);
    let mut fixed = vec![0u8; m.points.len()];
    fixed[0] = 1;
    let sys = a.system(&fixed);
    let kmax = a
        .diag
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |s, x| s.max(x.abs()));
    let mut worst = 0.0f64;
    for mode in rigid_modes(&m.points) {
        let mut y = vec![[0.0; D]; mode.len()];
        sys.multiply(&mode, &mut y).unwrap();
        let zmax = mode.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
        let ymax = y.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
        worst = worst.max(ymax / (kmax * zmax));
    }
    worst
}

#[test]
fn rigid_body_modes_span_the_null_space_of_the_unconstrained_operator() {
    for kind in [Kind::Simplex, Kind::Box, Kind::Mixed] {
        let r = null_space_residual(&grid2(5, kind, 0.3));
        assert!(r < 1e-13, "2D {kind:?}: {r:e}");
    }
    for kind in [
        Kind::Simplex,
        Kind::Box,
        Kind::Prism,
        Kind::Pyramid,
        Kind::Mixed,
    ] {
        let r = null_space_residual(&grid3(3, kind, 0.2));
        assert!(r < 1e-13, "3D {kind:?}: {r:e}");
    }
    // And nothing else: a non-rigid field (a linear strain) is not in it.
    let m = grid2(5, Kind::Box, 0.3);
    let a = assembled(&m, &m.points, Modulus::Constant, None, 0.3);
    let fixed = fixed_of(&m);
    let sys = a.system(&fixed);
    let strain: Vec<[f64; 2]> = m.points.iter().map(|p| [p[0], 0.0]).collect();
    let mut y = vec![[0.0; 2]; strain.len()];
    sys.multiply(&strain, &mut y).unwrap();
    assert!(y.iter().flatten().any(|v| v.abs() > 1e-3));
}

/// `K_ff u_f = −K_fc u_c` by dense Gaussian elimination with partial pivoting.
fn dense_solve<const D: usize>(a: &Assembled<f64, D>, fixed: &[u8], u: &mut [[f64; D]]) {
    let n = u.len();
    let free: Vec<usize> = (0..n).filter(|&i| fixed[i] == 0).collect();
    let mut index = vec![usize::MAX; n];
    for (k, &i) in free.iter().enumerate() {
        index[i] = k;
    }
    let m = free.len() * D;
    let mut mat = vec![vec![0.0f64; m + 1]; m];
    let g = a.graph();
    let mut add = |i: usize, j: usize, b: &Block<f64, D>| {
        if index[i] == usize::MAX {
            return;
        }
        for (r, br) in b.iter().enumerate() {
            let row = index[i] * D + r;
            for (c, &k) in br.iter().enumerate() {
                if index[j] == usize::MAX {
                    mat[row][m] -= k * u[j][c];
                } else {
                    mat[row][index[j] * D + c] += k;
                }
            }
        }
    };
    for i in 0..n {
        add(i, i, &a.diag[i]);
        for e in g.edge_range(i) {
            add(i, g.targets()[e] as usize, &a.off[e]);
        }
    }
    for col in 0..m {
        let p = (col..m)
            .max_by(|&x, &y| mat[x][col].abs().total_cmp(&mat[y][col].abs()))
            .unwrap();
        mat.swap(col, p);
        let pivot = mat[col].clone();
        for row in mat.iter_mut().skip(col + 1) {
            let f = row[col] / pivot[col];
            for (x, &p) in row.iter_mut().zip(&pivot).skip(col) {
                *x -= f * p;
            }
        }
    }
    let mut x = vec![0.0; m];
    for r in (0..m).rev() {
        let s: f64 = (r + 1..m).map(|c| mat[r][c] * x[c]).sum();
        x[r] = (mat[r][m] - s) / mat[r][r];
    }
    for (k, &i) in free.iter().enumerate() {
        for c in 0..D {
            u[i][c] = x[k * D + c];
        }
    }
}

fn cg_against_dense<const D: usize>(m: &Mesh<D>) {
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.35);
    let fixed = fixed_of(m);
    // A non-polynomial boundary motion: the interior is not a patch-test field.
    let boundary: Vec<[f64; D]> = m
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut u = [0.0; D];
            if m.boundary[i] {
                for (c, u) in u.iter_mut().enumerate() {
                    *u = 0.1 * (3.0 * p[c] + c as f64).sin() * p[(c + 1) % D].powi(2);
                }
            }
            u
        })
        .collect();
    let mut cg = boundary.clone();
    let report = solve(&a, &fixed, &mut cg, &tight());
    assert!(report.converged);
    let mut dense = boundary.clone();
    dense_solve(&a, &fixed, &mut dense);
    let scale = dense.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
    let err = cg
        .iter()
        .flatten()
        .zip(dense.iter().flatten())
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    assert!(
        err < 1e-10 * scale,
        "CG vs dense: {err:e} (scale {scale:e})"
    );
    for i in 0..cg.len() {
        if fixed[i] != 0 {
            assert_eq!(cg[i].map(f64::to_bits), boundary[i].map(f64::to_bits));
        }
    }
}

#[test]
fn cg_agrees_with_a_dense_direct_solve() {
    cg_against_dense(&grid2(7, Kind::Mixed, 0.3));
    cg_against_dense(&grid3(3, Kind::Mixed, 0.2));
    cg_against_dense(&grid3(3, Kind::Simplex, 0.2));
}

/// The multigrid-preconditioned solve: the hierarchy of the scalar edge weights, applied
/// per component.
fn amg_solve<const D: usize>(
    a: &Assembled<f64, D>,
    fixed: &[u8],
    u: &mut [[f64; D]],
    options: &SolveOptions<f64>,
) -> usize {
    let sys = a.system(fixed);
    let n = u.len();
    let mut w = vec![0.0; a.targets.len()];
    sys.amg_weights(&mut w).unwrap();
    let mut anchor = vec![0u32; n];
    let spring = SpringSystem::new(a.graph(), &w, fixed, &mut anchor).unwrap();
    let opts = AmgOptions::default();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(&spring)];
    let sizes = AmgHierarchy::setup_len(&spring, &opts, &mut work).unwrap();
    let mut index = vec![0u32; sizes.index];
    let mut values = vec![0.0; sizes.values];
    let h = AmgHierarchy::setup(&spring, &opts, &mut work, &mut index, &mut values).unwrap();
    let mut scratch = vec![[0.0; D]; elastic_amg_scratch_len(n, h.coarse_unknowns()).unwrap()];
    let r = sys
        .solve_amg(&spring, &h, u, options, &mut scratch)
        .unwrap();
    assert!(r.converged, "{r:?}");
    r.iterations
}

#[test]
fn multigrid_preconditioning_agrees_with_block_jacobi_in_fewer_iterations() {
    let m = grid2(40, Kind::Mixed, 0.3);
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed = fixed_of(&m);
    let start: Vec<[f64; 2]> = m
        .points
        .iter()
        .zip(&m.boundary)
        .map(|(p, &b)| {
            if b {
                [0.05 * (6.0 * p[1]).sin(), 0.03 * p[0] * p[0]]
            } else {
                [0.0; 2]
            }
        })
        .collect();
    let mut bj = start.clone();
    let rb = solve(&a, &fixed, &mut bj, &tight());
    let mut mg = start.clone();
    let im = amg_solve(&a, &fixed, &mut mg, &tight());
    let err = bj
        .iter()
        .flatten()
        .zip(mg.iter().flatten())
        .fold(0.0f64, |s, (a, b)| s.max((a - b).abs()));
    assert!(err < 1e-10, "{err:e}");
    assert!(
        im * 2 < rb.iterations,
        "multigrid {im} vs block Jacobi {}",
        rb.iterations
    );
}

/// Runs the increments with block-Jacobi CG.
fn incremental<T: Real, const D: usize>(
    m: &Mesh<D>,
    points: &mut [[T; D]],
    displacement: &[[T; D]],
    steps: usize,
    modulus: Modulus,
) -> Result<usize, Error> {
    let a = assembled(m, points, modulus, None, T::from_f64(0.3));
    let fixed = fixed_of(m);
    let cells = m.cells();
    let n = points.len();
    let mut moduli = vec![T::ZERO; cells.len()];
    let mut diag = vec![[[T::ZERO; D]; D]; n];
    let mut off = vec![[[T::ZERO; D]; D]; a.targets.len()];
    let (mut current, mut step) = (vec![[T::ZERO; D]; n], vec![[T::ZERO; D]; n]);
    let mut scratch = vec![[T::ZERO; D]; 4 * n];
    let params = Increments {
        modulus,
        wall_distance: None,
        poisson: T::from_f64(0.3),
        steps,
    };
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut current,
        step: &mut step,
    };
    let r = deform_incremental(
        &cells,
        &a.graph(),
        &fixed,
        &params,
        points,
        displacement,
        buffers,
        |sys: &ElasticSystem<'_, T, D>, u: &mut [[T; D]]| sys.solve(u, &tight(), &mut scratch),
    )?;
    assert!(r.converged && r.steps == steps);
    Ok(r.iterations)
}

#[test]
fn increments_reproduce_one_solve_and_end_exactly_on_the_boundary() {
    let m = grid2(8, Kind::Mixed, 0.25);
    let n = m.points.len();
    // A rotation by 20° about the centre, prescribed on the boundary.
    let (s, c) = 20f64.to_radians().sin_cos();
    let disp: Vec<[f64; 2]> = m
        .points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] - 0.5, p[1] - 0.5);
            [c * x - s * y - x, s * x + c * y - y]
        })
        .collect();
    // One step = one solve from the undeformed mesh.
    let mut one = m.points.clone();
    incremental::<f64, 2>(&m, &mut one, &disp, 1, Modulus::InverseVolume).unwrap();
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed = fixed_of(&m);
    let mut u: Vec<[f64; 2]> = (0..n)
        .map(|i| if fixed[i] != 0 { disp[i] } else { [0.0; 2] })
        .collect();
    solve(&a, &fixed, &mut u, &tight());
    for i in 0..n {
        let moved = [m.points[i][0] + u[i][0], m.points[i][1] + u[i][1]];
        assert_eq!(
            one[i].map(f64::to_bits),
            moved.map(f64::to_bits),
            "node {i}"
        );
    }
    // Ten steps: the boundary ends exactly at points + displacement; the interior differs
    // from one solve (the stiffness followed the mesh).
    let mut ten = m.points.clone();
    incremental::<f64, 2>(&m, &mut ten, &disp, 10, Modulus::InverseVolume).unwrap();
    let mut differs = false;
    for i in 0..n {
        let goal = [m.points[i][0] + disp[i][0], m.points[i][1] + disp[i][1]];
        if fixed[i] != 0 {
            assert_eq!(ten[i].map(f64::to_bits), goal.map(f64::to_bits));
        } else {
            differs |= ten[i] != one[i];
        }
    }
    assert!(differs);
}

#[test]
fn increments_keep_a_linear_field_exact() {
    let m = grid3(3, Kind::Mixed, 0.2);
    let disp: Vec<[f64; 3]> = m.points.iter().map(linear).collect();
    let mut moved = m.points.clone();
    incremental::<f64, 3>(&m, &mut moved, &disp, 4, Modulus::Constant).unwrap();
    for (i, p) in m.points.iter().enumerate() {
        for c in 0..3 {
            let e = (moved[i][c] - (p[c] + disp[i][c])).abs();
            assert!(e < 1e-12, "node {i}: {e:e}");
        }
    }
}

#[test]
fn typed_errors_leave_every_buffer_unchanged() {
    let m = grid2(3, Kind::Box, 0.2);
    let cells = m.cells();
    let a = assembled(&m, &m.points, Modulus::Constant, None, 0.3);
    let g = a.graph();
    let (mut diag, mut off) = (a.diag.clone(), a.off.clone());
    let nan = f64::NAN;
    let (d0, o0) = (diag.clone(), off.clone());
    let bad_nu = assemble(&cells, &m.points, &g, &a.moduli, 0.5, &mut diag, &mut off);
    assert!(matches!(
        bad_nu,
        Err(Error::InvalidParameter { arg: "poisson", .. })
    ));
    let mut bad_e = a.moduli.clone();
    bad_e[2] = 0.0;
    let r = assemble(&cells, &m.points, &g, &bad_e, 0.3, &mut diag, &mut off);
    assert!(matches!(
        r,
        Err(Error::NonPositive {
            arg: "moduli",
            position: 2
        })
    ));
    // A collapsed cell: node 5 moved onto node 0's position... of its own cell's corner.
    let mut flat = m.points.clone();
    flat[5] = flat[0];
    flat[6] = flat[1];
    flat[4] = [flat[0][0] - 1e-300, flat[0][1]];
    let r = assemble(&cells, &flat, &g, &a.moduli, 0.3, &mut diag, &mut off);
    assert!(
        matches!(r, Err(Error::NonPositive { arg: "cells", .. })),
        "{r:?}"
    );
    let mut moduli = vec![7.0; cells.len()];
    let r = cell_moduli(&cells, &flat, Modulus::InverseVolume, None, &mut moduli);
    assert!(
        matches!(r, Err(Error::NonPositive { arg: "cells", .. })),
        "{r:?}"
    );
    let r = cell_moduli(&cells, &m.points, Modulus::WallDistance, None, &mut moduli);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter {
            arg: "wall_distance",
            ..
        })
    ));
    assert!(moduli.iter().all(|&e| e == 7.0));
    assert_eq!(diag, d0);
    assert_eq!(off, o0);
    // Solve: non-finite values, short scratch, no fixed node, an asymmetric block.
    let fixed = fixed_of(&m);
    let sys = a.system(&fixed);
    let mut u = vec![[0.0; 2]; m.points.len()];
    u[1] = [nan, 0.0];
    let u0 = u.clone();
    let mut scratch = vec![[0.0; 2]; 4 * u.len()];
    let r = sys.solve(&mut u, &SolveOptions::default(), &mut scratch);
    assert!(matches!(
        r,
        Err(Error::NonFinite {
            arg: "values",
            position: 1
        })
    ));
    u[1] = [0.0; 2];
    let r = sys.solve(&mut u, &SolveOptions::default(), &mut scratch[..7]);
    assert!(matches!(
        r,
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    assert_eq!(u[0], u0[0]);
    let none = vec![0u8; u.len()];
    let r = ElasticSystem::new(g, &a.diag, &a.off, &none);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter { arg: "fixed", .. })
    ));
    let mut skew = a.off.clone();
    skew[0][0][1] += 1e-9;
    let r = ElasticSystem::new(g, &a.diag, &skew, &fixed);
    assert!(matches!(r, Err(Error::NotSymmetric { .. })));
    // Increments: a step count of zero.
    let mut p = m.points.clone();
    let disp = vec![[0.1, 0.0]; p.len()];
    assert!(matches!(
        incremental::<f64, 2>(&m, &mut p, &disp, 0, Modulus::Constant),
        Err(Error::InvalidParameter { arg: "steps", .. })
    ));
    assert_eq!(p, m.points);
}

/// The committed output bits of a fixed problem (10 increments of a 30° rotation on a mixed
/// mesh, inverse-volume moduli, ν = 0.3, block-Jacobi CG): any change in the arithmetic or
/// its order shows here (and would show on other platforms, whose bits must agree).
#[test]
fn golden_bits() {
    fn run<T: Real>() -> u64 {
        let m = grid2(6, Kind::Mixed, 0.25);
        let (s, c) = (0.5, 0.866_025_403_784_438_6); // 30°, no libm in the inputs
        let disp: Vec<[T; 2]> = m
            .points
            .iter()
            .map(|p| {
                let (x, y) = (p[0] - 0.5, p[1] - 0.5);
                [
                    T::from_f64(c * x - s * y - x),
                    T::from_f64(s * x + c * y - y),
                ]
            })
            .collect();
        let mut p = m.points_as::<T>();
        incremental::<T, 2>(&m, &mut p, &disp, 10, Modulus::InverseVolume).unwrap();
        fnv(&p)
    }
    assert_eq!(run::<f64>(), GOLDEN_F64, "f64: {:#x}", run::<f64>());
    assert_eq!(run::<f32>(), GOLDEN_F32, "f32: {:#x}", run::<f32>());
}

const GOLDEN_F64: u64 = 0xa138_ace7_daea_ad34;
const GOLDEN_F32: u64 = 0xa92b_5fae_1ed4_fb2e;
