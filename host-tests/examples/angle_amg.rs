//! Multigrid for the angle-inclusion springs (issue 14 item 8): the kernel's
//! `AngleSystem::solve_angle_amg` (CG preconditioned by the scalar spring hierarchy's V-cycle,
//! applied per component) against its block-Jacobi CG (`AngleMethod::Cg`), each beside an
//! independent CG on the angle operator `Σ_j B_ij (x_i − x_j)`, `B_ij = k_ij (d dᵀ/|d|² + ε I)`,
//! assembled here, preconditioned by
//! - block Jacobi (the kernel's `AngleMethod::Cg`), or
//! - the V-cycle through `SpringSystem::amg_precondition::<D>` (SPD, spectrally equivalent to
//!   the angle operator for ε > 0 with constants ε and 1 + ε),
//!
//! so the kernel's counts are checked against a second implementation.
//!
//! NACA 2412 triangulated O-grids, −10° pitch of the wall about the quarter chord, relative
//! residual 1e-8. Measured 2026-11-27 (iterations, kernel block-Jacobi CG → kernel AMG-CG; the
//! independent CGs agree within a few iterations):
//!
//! | nodes | ε = 0.01 | ε = 0.1 |
//! |---|---|---|
//! | 6,144 | 630 → 83 | 427 → 46 |
//! | 24,576 | 1,326 → 102 | 908 → 63 |
//! | 98,304 | 2,726 → 144 | 1,885 → 89 |
//!
//! With the far-field nodes sliding along the far-field circle (`solve_angle_sliding` with the
//! node blocks → `solve_angle_sliding_amg`), measured 2026-11-27:
//!
//! | nodes | ε = 0.01 | ε = 0.1 |
//! |---|---|---|
//! | 6,144 | 709 → 118 | 456 → 61 |
//! | 24,576 | 1,475 → 174 | 952 → 100 |
//! | 98,304 | 3,057 → 298 (21.5 s → 0.08 s setup + 3.1 s) | 1,968 → 174 |
//!
//! Run: `cargo run --release -p deform-host-tests --example angle_amg`.
#![allow(clippy::needless_range_loop)]

use std::time::Instant;

use deform_kernel::spring::constraints::{Constraints, NodeKind};
use deform_kernel::spring::{
    amg_precondition_scratch_len, batina_stiffness, AmgHierarchy, AmgOptions, AngleMethod,
    AngleSystem, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Graph};
use deform_meshgen::{naca_triangulated, AirfoilGrid};

const D: usize = 2;

struct Op<'a> {
    g: &'a Graph<'a>,
    k: &'a [f64],
    p: &'a [[f64; D]],
    fixed: &'a [u8],
    eps: f64,
}

impl Op<'_> {
    fn block(&self, i: usize, e: usize, j: usize) -> [[f64; D]; D] {
        let d = [self.p[j][0] - self.p[i][0], self.p[j][1] - self.p[i][1]];
        let d2 = d[0] * d[0] + d[1] * d[1];
        let k = self.k[e];
        let mut b = [[0.0; D]; D];
        for a in 0..D {
            for c in 0..D {
                b[a][c] = k * (d[a] * d[c] / d2 + if a == c { self.eps } else { 0.0 });
            }
        }
        b
    }
    /// y = A x on free nodes (A x)_i = Σ_j B_ij (x_i − x_j), with x zero on fixed nodes.
    fn apply(&self, x: &[[f64; D]], y: &mut [[f64; D]]) {
        let off = self.g.offsets();
        let t = self.g.targets();
        for i in 0..x.len() {
            let mut acc = [0.0; D];
            if self.fixed[i] == 0 {
                for e in off[i] as usize..off[i + 1] as usize {
                    let j = t[e] as usize;
                    let b = self.block(i, e, j);
                    let xj = if self.fixed[j] != 0 { [0.0; D] } else { x[j] };
                    for a in 0..D {
                        for c in 0..D {
                            acc[a] += b[a][c] * (x[i][c] - xj[c]);
                        }
                    }
                }
            }
            y[i] = acc;
        }
    }
    fn diag_solve(&self, r: &[[f64; D]], z: &mut [[f64; D]]) {
        let off = self.g.offsets();
        let t = self.g.targets();
        for i in 0..r.len() {
            if self.fixed[i] != 0 {
                z[i] = [0.0; D];
                continue;
            }
            let mut m = [[0.0; D]; D];
            for e in off[i] as usize..off[i + 1] as usize {
                let b = self.block(i, e, t[e] as usize);
                for a in 0..D {
                    for c in 0..D {
                        m[a][c] += b[a][c];
                    }
                }
            }
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            z[i] = [
                (m[1][1] * r[i][0] - m[0][1] * r[i][1]) / det,
                (m[0][0] * r[i][1] - m[1][0] * r[i][0]) / det,
            ];
        }
    }
}

/// `z = M⁻¹ r`.
type Precondition<'a> = dyn FnMut(&[[f64; D]], &mut [[f64; D]]) + 'a;

fn dot(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| x[0] * y[0] + x[1] * y[1])
        .sum()
}

/// PCG from zero for A x = b; returns iterations to ‖r‖ ≤ tol ‖b‖.
fn pcg(op: &Op, b: &[[f64; D]], prec: &mut Precondition, tol: f64) -> usize {
    let n = b.len();
    let mut x = vec![[0.0; D]; n];
    let mut r = b.to_vec();
    let mut z = vec![[0.0; D]; n];
    let mut q = vec![[0.0; D]; n];
    prec(&r, &mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let bn = dot(b, b).sqrt();
    for it in 1..=20000 {
        op.apply(&p, &mut q);
        let alpha = rz / dot(&p, &q);
        for i in 0..n {
            for c in 0..D {
                x[i][c] += alpha * p[i][c];
                r[i][c] -= alpha * q[i][c];
            }
        }
        if dot(&r, &r).sqrt() <= tol * bn {
            return it;
        }
        prec(&r, &mut z);
        let rz2 = dot(&r, &z);
        let beta = rz2 / rz;
        for i in 0..n {
            for c in 0..D {
                p[i][c] = z[i][c] + beta * p[i][c];
            }
        }
        rz = rz2;
    }
    20000
}

/// Relative residual 1e-8, as in the tables.
const STOP: SolveOptions<f64> = SolveOptions {
    max_iterations: 20000,
    residual_tol: 1e-8,
    update_tol: 0.0,
};

/// The default multigrid hierarchy of `sys` in `index` / `values` (resized to the exact
/// sizes), with the setup time in seconds.
fn setup<'h>(
    sys: &SpringSystem<'_, f64>,
    index: &'h mut Vec<u32>,
    values: &'h mut Vec<f64>,
) -> (AmgHierarchy<'h, f64>, f64) {
    let opts = AmgOptions::<f64>::default();
    let t0 = Instant::now();
    let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
    let sizes = AmgHierarchy::setup_len(sys, &opts, &mut work).unwrap();
    index.resize(sizes.index, 0);
    values.resize(sizes.values, 0.0);
    let h = AmgHierarchy::setup(sys, &opts, &mut work, index, values).unwrap();
    (h, t0.elapsed().as_secs_f64())
}

fn main() {
    for (ni, nj) in [(128, 48), (256, 96), (512, 192)] {
        let grid = AirfoilGrid {
            surface_points: ni,
            radial_points: nj,
            ..Default::default()
        };
        let mesh = naca_triangulated(&grid).unwrap();
        let cells = mesh.cells().unwrap();
        let n = mesh.node_count();
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        let g = Graph::new(&offsets, &targets).unwrap();
        let mut k = vec![0.0; used];
        batina_stiffness(&g, &mesh.points, 1.0, &mut k).unwrap();
        let mut fixed = vec![0u8; n];
        let mut disp = vec![[0.0; D]; n];
        // Both markers (airfoil and far field) are fixed; the airfoil turns, the far field stays.
        for m in &mesh.markers {
            for &v in &m.node_list {
                fixed[v as usize] = 1;
            }
        }
        let wall = mesh.marker("airfoil").expect("the airfoil marker");
        let th: f64 = -10f64.to_radians();
        for &v in &wall.node_list {
            let p = mesh.points[v as usize];
            let (s, c) = th.sin_cos();
            let q = [
                (p[0] - 0.25) * c - p[1] * s + 0.25,
                (p[0] - 0.25) * s + p[1] * c,
            ];
            disp[v as usize] = [q[0] - p[0], q[1] - p[1]];
        }
        let mut scratch = vec![0u32; n];
        let sys = SpringSystem::new(g, &k, &fixed, &mut scratch).unwrap();
        for eps in [0.01, 0.1] {
            let op = Op {
                g: &g,
                k: &k,
                p: &mesh.points,
                fixed: &fixed,
                eps,
            };
            // b = −Σ_j B_ij x_j over fixed neighbours j of free i.
            let mut b = vec![[0.0; D]; n];
            {
                let mut xf = vec![[0.0; D]; n];
                for i in 0..n {
                    if fixed[i] != 0 {
                        xf[i] = disp[i];
                    }
                }
                let off = g.offsets();
                for i in 0..n {
                    if fixed[i] != 0 {
                        continue;
                    }
                    for e in off[i] as usize..off[i + 1] as usize {
                        let j = targets[e] as usize;
                        if fixed[j] == 0 {
                            continue;
                        }
                        let bl = op.block(i, e, j);
                        for a in 0..D {
                            for c in 0..D {
                                b[i][a] += bl[a][c] * xf[j][c];
                            }
                        }
                    }
                }
            }
            let it_bj = pcg(&op, &b, &mut |r, z| op.diag_solve(r, z), 1e-8);
            let (mut index, mut values) = (Vec::new(), Vec::new());
            let (h, t_setup) = setup(&sys, &mut index, &mut values);
            let mut sc = vec![[0.0f64; D]; amg_precondition_scratch_len(&h)];
            let it_amg = pcg(
                &op,
                &b,
                &mut |r, z| sys.amg_precondition::<D>(&h, r, z, &mut sc).unwrap(),
                1e-8,
            );
            // The kernel's angle CGs: block Jacobi and multigrid.
            let asys = AngleSystem::<f64, D>::new(sys, &mesh.points, eps).unwrap();
            let stop = STOP;
            let mut x = disp.clone();
            let mut s2 = vec![[0.0; D]; asys.angle_scratch_len(AngleMethod::Cg)];
            let t0 = Instant::now();
            let rep = asys
                .solve_angle(&mut x, AngleMethod::Cg, &stop, &mut s2)
                .unwrap();
            let t_cg = t0.elapsed().as_secs_f64();
            let mut y = disp.clone();
            let mut s3 = vec![[0.0; D]; asys.angle_amg_scratch_len(&h)];
            let t0 = Instant::now();
            let rep_amg = asys.solve_angle_amg(&h, &mut y, &stop, &mut s3).unwrap();
            let t_amg = t0.elapsed().as_secs_f64();
            assert!(rep.converged && rep_amg.converged);
            let diff = x
                .iter()
                .zip(&y)
                .flat_map(|(a, b)| [(a[0] - b[0]).abs(), (a[1] - b[1]).abs()])
                .fold(0.0f64, f64::max);
            println!(
                "n {n:>7} eps {eps:<5} block-Jacobi CG: independent {it_bj:>5} kernel {:>5} ({t_cg:.2} s) | AMG CG: independent {it_amg:>4} kernel {:>4} (setup {t_setup:.2} s, solve {t_amg:.2} s) | max |difference| {diff:.1e}",
                rep.iterations, rep_amg.iterations
            );
            sliding(&mesh, &g, &k, &disp, eps);
        }
    }
}

/// The same pitch with the far-field nodes sliding along the far-field circle (a plane
/// constraint with the radial normal) instead of fixed: the kernel's projected angle CG with
/// the node blocks (`solve_angle_sliding`, `AngleMethod::Cg`) against the multigrid V-cycle
/// (`solve_angle_sliding_amg`).
fn sliding(mesh: &deform_meshgen::Mesh<D>, g: &Graph<'_>, k: &[f64], disp: &[[f64; D]], eps: f64) {
    let n = mesh.node_count();
    let far = mesh.marker("farfield").expect("the far-field marker");
    let wall = mesh.marker("airfoil").expect("the airfoil marker");
    let mut centre = [0.0; D];
    for &v in &far.node_list {
        for c in 0..D {
            centre[c] += mesh.points[v as usize][c] / far.node_list.len() as f64;
        }
    }
    let mut kinds = vec![NodeKind::Free.code(); n];
    let mut dirs = vec![[0.0; D]; n];
    for &v in &wall.node_list {
        kinds[v as usize] = NodeKind::Fixed.code();
    }
    for &v in &far.node_list {
        let p = mesh.points[v as usize];
        let r = [p[0] - centre[0], p[1] - centre[1]];
        let len = r[0].hypot(r[1]);
        kinds[v as usize] = NodeKind::Plane.code();
        dirs[v as usize] = [r[0] / len, r[1] / len];
    }
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = vec![0u8; n];
    c.fixed_mask(&mut mask).unwrap();
    let mut scratch = vec![0u32; n];
    let sys = SpringSystem::new(*g, k, &mask, &mut scratch).unwrap();
    let (mut index, mut values) = (Vec::new(), Vec::new());
    let (h, t_setup) = setup(&sys, &mut index, &mut values);
    let asys = AngleSystem::<f64, D>::new(sys, &mesh.points, eps).unwrap();
    let stop = STOP;
    let mut x = disp.to_vec();
    let mut s1 = vec![[0.0; D]; asys.solve_angle_sliding_scratch_len(AngleMethod::Cg)];
    let t0 = Instant::now();
    let rep = asys
        .solve_angle_sliding(&c, &mut x, AngleMethod::Cg, 1.0, &stop, &mut s1)
        .unwrap();
    let t_cg = t0.elapsed().as_secs_f64();
    let mut y = disp.to_vec();
    let mut s2 = vec![[0.0; D]; asys.solve_angle_sliding_amg_scratch_len(&h)];
    let t0 = Instant::now();
    let rep_amg = asys
        .solve_angle_sliding_amg(&c, &mut y, &h, &stop, &mut s2)
        .unwrap();
    let t_amg = t0.elapsed().as_secs_f64();
    assert!(rep.converged && rep_amg.converged);
    let diff = x
        .iter()
        .zip(&y)
        .flat_map(|(a, b)| [(a[0] - b[0]).abs(), (a[1] - b[1]).abs()])
        .fold(0.0f64, f64::max);
    println!(
        "  far field sliding: node-block CG {:>5} ({t_cg:.2} s) | AMG CG {:>4} (setup {t_setup:.2} s, solve {t_amg:.2} s) | max |difference| {diff:.1e}",
        rep.iterations, rep_amg.iterations
    );
}
