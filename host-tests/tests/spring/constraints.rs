//! Sliding boundaries: constraint validation, plane fits, projected spring solves against a
//! dense reference, and half-models (2D annulus, 3D box with an inner box) whose symmetry
//! plane slides instead of being pinned.

use deform_kernel::quality::compare;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::spring::constraints::{
    fit_plane, plane_intersection, slide_points, Constraints, NodeKind,
};
use deform_kernel::spring::{
    batina_stiffness, solve_linear_sliding_scratch_len, AmgHierarchy, AmgOptions, AngleMethod,
    AngleSystem, LinearMethod, LinearSolver, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Error, Graph, Quat};
use deform_meshgen::{annulus, box_with_inner_box3, Mesh};
use nalgebra::{DMatrix, DVector};

#[path = "../support/mod.rs"]
mod support;
use support::spring::AmgBuffers;

/// A half-model: the cells of a meshgen mesh on one side of a symmetry plane.
struct Half<const D: usize> {
    points: Vec<[f64; D]>,
    offsets: Vec<u32>,
    nodes: Vec<u32>,
    kinds: Vec<u8>,
    wall: Vec<u32>,
    outer: Vec<u32>,
    sym: Vec<u32>,
    g_offsets: Vec<u32>,
    g_targets: Vec<u32>,
    k: Vec<f64>,
}

impl<const D: usize> Half<D> {
    /// Keeps the cells whose centroid has `p[axis] > cut`; symmetry nodes are kept nodes with
    /// `|p[axis] − cut| < 1e-9` that are on neither marker.
    fn new(mesh: &Mesh<D>, axis: usize, cut: f64) -> Self {
        let n = mesh.node_count();
        let mut map = vec![u32::MAX; n];
        let mut points = Vec::new();
        let (mut offsets, mut nodes, mut kinds) = (vec![0u32], Vec::new(), Vec::new());
        for c in 0..mesh.cell_count() {
            let (kind, cn) = mesh.cell(c).unwrap();
            let centroid: f64 = cn
                .iter()
                .map(|&i| mesh.points[i as usize][axis])
                .sum::<f64>()
                / cn.len() as f64;
            if centroid <= cut {
                continue;
            }
            for &i in cn {
                if map[i as usize] == u32::MAX {
                    map[i as usize] = points.len() as u32;
                    points.push(mesh.points[i as usize]);
                }
                nodes.push(map[i as usize]);
            }
            kinds.push(kind.vtk_code());
            offsets.push(nodes.len() as u32);
        }
        let marker = |name: &str| -> Vec<u32> {
            let m = mesh.require_marker(name).unwrap();
            let mut v: Vec<u32> = m
                .node_list
                .iter()
                .map(|&i| map[i as usize])
                .filter(|&i| i != u32::MAX)
                .collect();
            v.sort_unstable();
            v
        };
        let wall = marker("inner");
        let outer = marker("outer");
        let sym: Vec<u32> = (0..points.len() as u32)
            .filter(|&i| {
                (points[i as usize][axis] - cut).abs() < 1e-9
                    && !wall.contains(&i)
                    && !outer.contains(&i)
            })
            .collect();
        let mut h = Half {
            points,
            offsets,
            nodes,
            kinds,
            wall,
            outer,
            sym,
            g_offsets: Vec::new(),
            g_targets: Vec::new(),
            k: Vec::new(),
        };
        let cells = h.cells();
        let mut go = vec![0u32; h.points.len() + 1];
        let mut gt = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut go, &mut gt).unwrap();
        gt.truncate(used);
        let mut k = vec![0.0; used];
        batina_stiffness(&Graph::new(&go, &gt).unwrap(), &h.points, 1.0, &mut k).unwrap();
        h.g_offsets = go;
        h.g_targets = gt;
        h.k = k;
        h
    }

    fn cells(&self) -> Cells<'_> {
        Cells::new(self.points.len(), &self.offsets, &self.nodes, &self.kinds).unwrap()
    }

    fn graph(&self) -> Graph<'_> {
        Graph::new(&self.g_offsets, &self.g_targets).unwrap()
    }

    /// Kinds and directions: wall and outer fixed, symmetry nodes sliding on the plane fitted
    /// to them (or fixed when `pinned`).
    fn constraints(&self, pinned: bool) -> (Vec<u8>, Vec<[f64; D]>, [f64; D]) {
        let fit = fit_plane(&self.points, &self.sym, 1e-9).unwrap();
        let mut kinds = vec![NodeKind::Free.code(); self.points.len()];
        let mut dirs = vec![[0.0; D]; self.points.len()];
        for &i in self.wall.iter().chain(&self.outer) {
            kinds[i as usize] = NodeKind::Fixed.code();
        }
        for &i in &self.sym {
            kinds[i as usize] = if pinned {
                NodeKind::Fixed.code()
            } else {
                NodeKind::Plane.code()
            };
            dirs[i as usize] = fit.normal;
        }
        (kinds, dirs, fit.normal)
    }

    /// The wall nodes at `t`, every other node at zero.
    fn wall_at(&self, t: [f64; D]) -> Vec<[f64; D]> {
        let mut v = vec![[0.0; D]; self.points.len()];
        for &i in &self.wall {
            v[i as usize] = t;
        }
        v
    }

    /// The angle springs' dense projected solution (edge blocks `k (e eᵀ/|e|² + ε I)`).
    fn angle_reference(
        &self,
        kinds: &[u8],
        dirs: &[[f64; D]],
        fixed: &[[f64; D]],
        eps: f64,
    ) -> Vec<[f64; D]> {
        let p = &self.points;
        dense_reference(&self.graph(), &self.k, kinds, dirs, fixed, |i, j, k| {
            let e: [f64; D] = std::array::from_fn(|c| p[j][c] - p[i][c]);
            let e2: f64 = e.iter().map(|x| x * x).sum();
            std::array::from_fn(|r| {
                std::array::from_fn(|c| k * (e[r] * e[c] / e2 + if r == c { eps } else { 0.0 }))
            })
        })
    }

    /// Mesh size: the largest coordinate extent.
    fn size(&self) -> f64 {
        (0..D)
            .map(|c| {
                let lo = self
                    .points
                    .iter()
                    .map(|p| p[c])
                    .fold(f64::INFINITY, f64::min);
                let hi = self
                    .points
                    .iter()
                    .map(|p| p[c])
                    .fold(-f64::INFINITY, f64::max);
                hi - lo
            })
            .fold(0.0, f64::max)
    }

    /// Linear-spring displacements for a wall translation `t` with the given solver.
    fn solve(&self, t: [f64; D], pinned: bool, solver: LinearSolver<'_, f64>) -> Vec<[f64; D]> {
        let (kinds, dirs, _) = self.constraints(pinned);
        let c = Constraints::new(&kinds, &dirs).unwrap();
        let mut mask = vec![0u8; kinds.len()];
        c.fixed_mask(&mut mask).unwrap();
        let mut scratch = vec![0u32; self.points.len()];
        let sys = SpringSystem::new(self.graph(), &self.k, &mask, &mut scratch).unwrap();
        let mut d = vec![[0.0; D]; self.points.len()];
        for &i in &self.wall {
            d[i as usize] = t;
        }
        let mut work = vec![[0.0; D]; solve_linear_sliding_scratch_len(&solver, d.len())];
        let opts = SolveOptions {
            residual_tol: 1e-12,
            max_iterations: 200_000,
            ..SolveOptions::default()
        };
        let r = sys
            .solve_linear_sliding(&c, &mut d, solver, &opts, &mut work)
            .unwrap();
        assert!(r.converged, "{r:?}");
        d
    }

    fn moved(&self, d: &[[f64; D]]) -> Vec<[f64; D]> {
        self.points
            .iter()
            .zip(d)
            .map(|(p, d)| std::array::from_fn(|c| p[c] + d[c]))
            .collect()
    }

    fn min_ratio(&self, moved: &[[f64; D]]) -> f64 {
        let r = compare(&self.cells(), &self.points, moved, None, &mut []).unwrap();
        r.min_measure_ratio
    }

    /// Largest `|n · (x_new − x_old)|` over the symmetry nodes, relative to the mesh size.
    fn off_plane(&self, moved: &[[f64; D]], n: [f64; D]) -> f64 {
        self.sym
            .iter()
            .map(|&i| {
                let (a, b) = (moved[i as usize], self.points[i as usize]);
                (0..D).map(|c| n[c] * (a[c] - b[c])).sum::<f64>().abs()
            })
            .fold(0.0, f64::max)
            / self.size()
    }
}

fn half_annulus() -> Half<2> {
    // Cells with centroid y > 0: the symmetry line is y = 0 (two segments).
    Half::new(&annulus(32, 9, 0.5, 2.0).unwrap(), 1, 0.0)
}

fn half_box() -> Half<3> {
    // Box [-1, 1]³ with the inner box [-0.25, 0.25]³, cells with x > 0: symmetry plane x = 0.
    Half::new(&box_with_inner_box3(8, 2).unwrap(), 0, 0.0)
}

fn solvers<'a>(h: Option<&'a AmgHierarchy<'a, f64>>) -> Vec<LinearSolver<'a, f64>> {
    let mut v: Vec<LinearSolver<'a, f64>> = vec![
        LinearMethod::Jacobi.into(),
        LinearMethod::GaussSeidel.into(),
        LinearMethod::Sor { omega: 1.6 }.into(),
        LinearMethod::Cg {
            preconditioner: Preconditioner::None,
        }
        .into(),
        LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        }
        .into(),
        LinearMethod::Cg {
            preconditioner: Preconditioner::Ssor { omega: 1.2 },
        }
        .into(),
    ];
    if let Some(h) = h {
        v.push(LinearSolver::Amg(h));
    }
    v
}

/// Dense reference: assemble `K` (`D n × D n`), a basis `Z` of the allowed motions (identity
/// for free nodes, orthonormal tangents for plane nodes, the tangent for line nodes), and solve
/// `Zᵀ K Z y = −Zᵀ K d_fixed` by Cholesky; `d = d_fixed + Z y`. `edge_block(i, j, k)` is the
/// `D×D` block of edge `i → j`.
fn dense_reference<const D: usize>(
    g: &Graph<'_>,
    k: &[f64],
    kinds: &[u8],
    dirs: &[[f64; D]],
    fixed_values: &[[f64; D]],
    edge_block: impl Fn(usize, usize, f64) -> [[f64; D]; D],
) -> Vec<[f64; D]> {
    let n = kinds.len();
    let mut kmat = DMatrix::<f64>::zeros(D * n, D * n);
    for i in 0..n {
        for (e, &j) in g.edge_range(i).zip(g.neighbors(i)) {
            let b = edge_block(i, j as usize, k[e]);
            for r in 0..D {
                for c in 0..D {
                    kmat[(D * i + r, D * i + c)] += b[r][c];
                    kmat[(D * i + r, D * j as usize + c)] -= b[r][c];
                }
            }
        }
    }
    let mut cols: Vec<DVector<f64>> = Vec::new();
    let unit = |i: usize, v: [f64; D]| {
        let mut z = DVector::<f64>::zeros(D * n);
        for c in 0..D {
            z[D * i + c] = v[c];
        }
        z
    };
    for i in 0..n {
        let d = dirs[i];
        match kinds[i] {
            0 => {
                for c in 0..D {
                    let mut e = [0.0; D];
                    e[c] = 1.0;
                    cols.push(unit(i, e));
                }
            }
            1 => {}
            2 => {
                // Tangents of the plane: Gram–Schmidt of the axes against n.
                let mut basis: Vec<[f64; D]> = Vec::new();
                for c in 0..D {
                    let mut v = [0.0; D];
                    v[c] = 1.0;
                    let s: f64 = (0..D).map(|r| v[r] * d[r]).sum();
                    for r in 0..D {
                        v[r] -= s * d[r];
                    }
                    for b in &basis {
                        let s: f64 = (0..D).map(|r| v[r] * b[r]).sum();
                        for r in 0..D {
                            v[r] -= s * b[r];
                        }
                    }
                    let len = v.iter().map(|x| x * x).sum::<f64>().sqrt();
                    if len > 1e-6 && basis.len() < D - 1 {
                        basis.push(v.map(|x| x / len));
                    }
                }
                for b in basis {
                    cols.push(unit(i, b));
                }
            }
            3 => cols.push(unit(i, d)),
            _ => unreachable!(),
        }
    }
    let z = DMatrix::from_columns(&cols);
    let mut df = DVector::<f64>::zeros(D * n);
    for i in 0..n {
        if kinds[i] == 1 {
            for c in 0..D {
                df[D * i + c] = fixed_values[i][c];
            }
        }
    }
    let a = z.transpose() * &kmat * &z;
    let rhs = -(z.transpose() * (&kmat * &df));
    let y = a.cholesky().expect("SPD").solve(&rhs);
    let d = df + &z * y;
    (0..n)
        .map(|i| std::array::from_fn(|c| d[D * i + c]))
        .collect()
}

fn max_diff<const D: usize>(a: &[[f64; D]], b: &[[f64; D]]) -> f64 {
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
        .fold(0.0, f64::max)
}

fn max_abs<const D: usize>(a: &[[f64; D]]) -> f64 {
    a.iter().flatten().fold(0.0, |m, x| m.max(x.abs()))
}

/// Every linear solver (and AMG) matches the dense projected solve, 2D and 3D.
#[test]
fn linear_matches_dense_reference() {
    fn check<const D: usize>(h: &Half<D>, t: [f64; D]) {
        let (kinds, dirs, _) = h.constraints(false);
        let mut fixed = vec![[0.0; D]; kinds.len()];
        for &i in &h.wall {
            fixed[i as usize] = t;
        }
        let g = h.graph();
        let reference = dense_reference(&g, &h.k, &kinds, &dirs, &fixed, |_, _, k| {
            std::array::from_fn(|r| std::array::from_fn(|c| if r == c { k } else { 0.0 }))
        });
        let c = Constraints::new(&kinds, &dirs).unwrap();
        let mut mask = vec![0u8; kinds.len()];
        c.fixed_mask(&mut mask).unwrap();
        let mut s = vec![0u32; kinds.len()];
        let sys = SpringSystem::new(g, &h.k, &mask, &mut s).unwrap();
        let opts = AmgOptions::default();
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(&sys)];
        let sizes = AmgHierarchy::setup_len(&sys, &opts, &mut work).unwrap();
        let mut index = vec![0u32; sizes.index];
        let mut values = vec![0.0; sizes.values];
        let amg = AmgHierarchy::setup(&sys, &opts, &mut work, &mut index, &mut values).unwrap();
        for solver in solvers(Some(&amg)) {
            let d = h.solve(t, false, solver);
            let err = max_diff(&d, &reference) / max_abs(&reference);
            assert!(err < 1e-8, "{solver:?}: {err:e}");
        }
    }
    check(&half_annulus(), [0.2, 0.0]);
    check(&half_box(), [0.0, 0.15, 0.05]);
}

/// The angle springs' constrained solves (direct GS, SOR, Jacobi order, CG) match the dense
/// projected solve with the same edge blocks `k (e eᵀ/|e|² + ε I)`.
#[test]
fn angle_matches_dense_reference() {
    fn check<const D: usize>(h: &Half<D>, t: [f64; D]) {
        let eps = 0.05;
        let (kinds, dirs, _) = h.constraints(false);
        let fixed = h.wall_at(t);
        let g = h.graph();
        let reference = h.angle_reference(&kinds, &dirs, &fixed, eps);
        let c = Constraints::new(&kinds, &dirs).unwrap();
        let mut mask = vec![0u8; kinds.len()];
        c.fixed_mask(&mut mask).unwrap();
        let mut s = vec![0u32; kinds.len()];
        let sys = SpringSystem::new(g, &h.k, &mask, &mut s).unwrap();
        let asys = AngleSystem::new(sys, &h.points, eps).unwrap();
        let opts = SolveOptions {
            residual_tol: 1e-12,
            max_iterations: 200_000,
            ..SolveOptions::default()
        };
        for (method, omega) in [
            (AngleMethod::DirectGaussSeidel, 1.0),
            (AngleMethod::DirectGaussSeidel, 1.5),
            (AngleMethod::Cg, 1.0),
            (AngleMethod::DirectJacobi, 1.0),
        ] {
            let mut d = fixed.clone();
            let mut work = vec![[0.0; D]; asys.solve_angle_sliding_scratch_len(method)];
            let r = asys
                .solve_angle_sliding(&c, &mut d, method, omega, &opts, &mut work)
                .unwrap();
            if method == AngleMethod::DirectJacobi && !r.converged {
                continue; // block Jacobi is not guaranteed to converge on this operator
            }
            assert!(r.converged, "{method:?}: {r:?}");
            let err = max_diff(&d, &reference) / max_abs(&reference);
            assert!(err < 1e-8, "{method:?} ω={omega}: {err:e}");
        }
    }
    check(&half_annulus(), [0.2, 0.0]);
    check(&half_box(), [0.0, 0.15, 0.05]);
}

/// The angle springs' projected CG preconditioned by the scalar multigrid V-cycle
/// (`solve_angle_sliding_amg`): the dense projected solution for ε = 0.05 and 1, sliding
/// nodes on their plane to rounding, the wall's values bit for bit, and typed errors with
/// `values` untouched. (On meshes this small the node blocks need fewer iterations; the
/// multigrid pays off at scale: `cargo run --release -p deform-host-tests --example angle_amg`.)
#[test]
fn angle_amg_matches_dense_reference_and_slides() {
    fn check<const D: usize>(h: &Half<D>, t: [f64; D], eps: f64) {
        let (kinds, dirs, normal) = h.constraints(false);
        let fixed = h.wall_at(t);
        let g = h.graph();
        let reference = h.angle_reference(&kinds, &dirs, &fixed, eps);
        let c = Constraints::new(&kinds, &dirs).unwrap();
        let mut mask = vec![0u8; kinds.len()];
        c.fixed_mask(&mut mask).unwrap();
        let mut s = vec![0u32; kinds.len()];
        let sys = SpringSystem::new(g, &h.k, &mask, &mut s).unwrap();
        let asys = AngleSystem::new(sys, &h.points, eps).unwrap();
        let amg_opts = AmgOptions::default();
        let mut bufs = AmgBuffers::new(asys.base(), &amg_opts);
        let amg = bufs.build(asys.base(), &amg_opts);
        let opts = SolveOptions {
            residual_tol: 1e-12,
            max_iterations: 10_000,
            ..SolveOptions::default()
        };
        let mut d = fixed.clone();
        let mut work = vec![[0.0; D]; asys.solve_angle_sliding_amg_scratch_len(&amg)];
        let r = asys
            .solve_angle_sliding_amg(&c, &mut d, &amg, &opts, &mut work)
            .unwrap();
        assert!(r.converged, "{r:?}");
        let err = max_diff(&d, &reference) / max_abs(&reference);
        assert!(err < 1e-8, "ε={eps}: {err:e}");
        let off = h
            .sym
            .iter()
            .map(|&i| {
                (0..D)
                    .map(|k| normal[k] * d[i as usize][k])
                    .sum::<f64>()
                    .abs()
            })
            .fold(0.0, f64::max);
        assert!(
            off <= 1e-13 * max_abs(&d),
            "ε={eps}: off the plane by {off:e}"
        );
        for &i in &h.wall {
            assert_eq!(d[i as usize].map(f64::to_bits), t.map(f64::to_bits));
        }
        // Errors: nothing written.
        let bits =
            |v: &[[f64; D]]| -> Vec<[u64; D]> { v.iter().map(|x| x.map(f64::to_bits)).collect() };
        let mut x = fixed.clone();
        let before = bits(&x);
        let mut short = vec![[0.0; D]; work.len() - 1];
        assert!(matches!(
            asys.solve_angle_sliding_amg(&c, &mut x, &amg, &opts, &mut short),
            Err(Error::BufferTooSmall { arg: "scratch", .. })
        ));
        let mut other_s = vec![0u32; 3];
        let other_sys = SpringSystem::new(
            Graph::new(&[0, 1, 2, 2], &[1, 0]).unwrap(),
            &[1.0, 1.0],
            &[1, 0, 0],
            &mut other_s,
        );
        if let Ok(other_sys) = other_sys {
            let mut ob = AmgBuffers::new(&other_sys, &amg_opts);
            let other = ob.build(&other_sys, &amg_opts);
            assert!(matches!(
                asys.solve_angle_sliding_amg(&c, &mut x, &other, &opts, &mut work),
                Err(Error::LengthMismatch {
                    arg: "hierarchy",
                    ..
                })
            ));
        }
        x[h.sym[0] as usize][0] = f64::NAN;
        let nan_before = bits(&x);
        assert!(matches!(
            asys.solve_angle_sliding_amg(&c, &mut x, &amg, &opts, &mut work),
            Err(Error::NonFinite { arg: "values", .. })
        ));
        assert_eq!(nan_before, bits(&x));
        x[h.sym[0] as usize][0] = fixed[h.sym[0] as usize][0];
        assert_eq!(before, bits(&x));
    }
    for eps in [0.05, 1.0] {
        check(&half_annulus(), [0.2, 0.0], eps);
        check(&half_box(), [0.0, 0.15, 0.05], eps);
    }
}

/// Wall translation along the symmetry plane: sliding nodes stay on the plane to 1e-12 of
/// the mesh size, and the smallest area/volume ratio beats the pinned plane.
#[test]
fn half_models_slide_and_beat_pinned() {
    fn check<const D: usize>(h: &Half<D>, t: [f64; D], name: &str) {
        let solver: LinearSolver<'_, f64> = LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        }
        .into();
        let (_, _, n) = h.constraints(false);
        let slid = h.moved(&h.solve(t, false, solver));
        let pinned = h.moved(&h.solve(t, true, solver));
        let off = h.off_plane(&slid, n);
        assert!(off <= 1e-12, "{name}: off plane {off:e}");
        // Some symmetry node really moved.
        let moved = h
            .sym
            .iter()
            .map(|&i| {
                (0..D)
                    .map(|c| (slid[i as usize][c] - h.points[i as usize][c]).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max);
        assert!(
            moved > 1e-3,
            "{name}: symmetry nodes did not move ({moved:e})"
        );
        let (rs, rp) = (h.min_ratio(&slid), h.min_ratio(&pinned));
        eprintln!("{name}: min ratio sliding {rs:.4}, pinned {rp:.4}, off-plane {off:.2e}");
        assert!(rs > rp, "{name}: sliding {rs} <= pinned {rp}");
    }
    check(&half_annulus(), [0.3, 0.0], "2D half annulus");
    check(&half_box(), [0.0, 0.3, 0.0], "3D half box");
}

/// The quaternion/IDW pipeline with the symmetry nodes as field nodes, then
/// `slide_points`: on the plane to 1e-12 of the size, better than pinning them as sources.
/// The wall (inner circle) grows by 40 % and moves 0.2 along the symmetry line (a motion that
/// keeps the symmetry; IDW alone moves the symmetry nodes off the line).
#[test]
fn idw_then_slide_points() {
    let h = half_annulus();
    let t = [0.2, 0.0];
    let grow = 1.4;
    let run = |pinned: bool| -> Vec<[f64; 2]> {
        let mut nodes: Vec<u32> = h.wall.iter().chain(&h.outer).copied().collect();
        if pinned {
            nodes.extend(&h.sym);
        }
        let deformed: Vec<[f64; 2]> = nodes
            .iter()
            .map(|&i| {
                let p = h.points[i as usize];
                if h.wall.contains(&i) {
                    [grow * p[0] + t[0], grow * p[1] + t[1]]
                } else {
                    p
                }
            })
            .collect();
        let motion = BoundaryMotion {
            nodes: &nodes,
            deformed: &deformed,
            elements: None,
            rotations: RotationSource::Rigid(Quat::identity()),
            origin: None,
        };
        let n = h.points.len();
        let mut tr = vec![[0.0; 2]; n];
        let mut rot = vec![Quat::identity(); n];
        let mut scratch = vec![0.0; deform_idw_scratch_len::<2>(n, nodes.len())];
        let mut out = vec![[0.0; 2]; n];
        deform_idw(
            &h.points,
            &motion,
            3.0,
            &mut tr,
            &mut rot,
            &mut scratch,
            &mut out,
        )
        .unwrap();
        out
    };
    let (kinds, dirs, normal) = h.constraints(false);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut slid = run(false);
    let before = h.off_plane(&slid, normal);
    slide_points(&c, &h.points, &mut slid).unwrap();
    let off = h.off_plane(&slid, normal);
    assert!(before > 1e-3, "IDW alone leaves the plane ({before:e})");
    assert!(off <= 1e-12, "off plane {off:e}");
    let (rs, rp) = (h.min_ratio(&slid), h.min_ratio(&run(true)));
    eprintln!("IDW 2D half annulus: min ratio sliding {rs:.4}, pinned {rp:.4}");
    assert!(rs > rp, "sliding {rs} <= pinned {rp}");
}

/// Plane fit: matches nalgebra's SVD normal on a tilted noisy plane, reports the residual,
/// refuses non-planar and collinear sets.
#[test]
fn fit_plane_against_svd() {
    let n: [f64; 3] = [0.3, -0.5, 0.8];
    let len = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    let n = n.map(|x| x / len.sqrt());
    let u = [0.5 * n[1] - 0.0, -(0.5 * n[0]) + n[2], -n[1]]; // some vector
    let un = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let dot = (u[0] * n[0] + u[1] * n[1] + u[2] * n[2]) / un;
    let u: [f64; 3] = std::array::from_fn(|c| u[c] / un - dot * n[c]);
    let v = [
        n[1] * u[2] - n[2] * u[1],
        n[2] * u[0] - n[0] * u[2],
        n[0] * u[1] - n[1] * u[0],
    ];
    let mut pts = Vec::new();
    for k in 0..40 {
        let (a, b) = ((k % 7) as f64 * 0.37 - 1.0, (k / 7) as f64 * 0.29 - 0.8);
        let noise = 1e-7 * (((k * 37) % 11) as f64 - 5.0);
        pts.push(std::array::from_fn::<f64, 3, _>(|c| {
            10.0 + a * u[c] + b * v[c] + noise * n[c]
        }));
    }
    let nodes: Vec<u32> = (0..40).collect();
    let fit = fit_plane(&pts, &nodes, 1e-6).unwrap();
    // Reference: SVD of the centred points.
    let c: [f64; 3] = std::array::from_fn(|k| pts.iter().map(|p| p[k]).sum::<f64>() / 40.0);
    let m = DMatrix::from_fn(40, 3, |r, k| pts[r][k] - c[k]);
    let svd = m.svd(false, true);
    let vt = svd.v_t.unwrap();
    let imin = (0..3)
        .min_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]))
        .unwrap();
    let rn: [f64; 3] = std::array::from_fn(|k| vt[(imin, k)]);
    let cosine: f64 = (0..3).map(|k| rn[k] * fit.normal[k]).sum();
    assert!((cosine.abs() - 1.0).abs() < 1e-12, "{cosine}");
    let residual = pts
        .iter()
        .map(|p| {
            (0..3)
                .map(|k| fit.normal[k] * (p[k] - fit.point[k]))
                .sum::<f64>()
                .abs()
        })
        .fold(0.0, f64::max);
    assert_eq!(fit.residual, residual);
    assert!(fit.residual < 1e-6 && fit.residual > 1e-8);
    // Too tight a tolerance: refused, naming the farthest node.
    assert!(matches!(
        fit_plane(&pts, &nodes, 1e-9),
        Err(Error::NotPlanar { arg: "nodes", .. })
    ));
    // Never refuse with an infinite tolerance.
    let mut bent = pts.clone();
    bent[3][0] += 1.0;
    assert!(matches!(
        fit_plane(&bent, &nodes, 1e-6),
        Err(Error::NotPlanar {
            arg: "nodes",
            position: 3
        })
    ));
    assert!(fit_plane(&bent, &nodes, f64::INFINITY).unwrap().residual > 0.1);
    // Collinear, coincident, too few, out of range, NaN.
    let line: Vec<[f64; 3]> = (0..5).map(|k| [k as f64, 2.0 * k as f64, 0.5]).collect();
    assert!(matches!(
        fit_plane(&line, &[0, 1, 2, 3, 4], 1e-6),
        Err(Error::InvalidParameter { arg: "nodes", .. })
    ));
    assert!(matches!(
        fit_plane(&line, &[1, 1, 1], 1e-6),
        Err(Error::InvalidParameter { arg: "nodes", .. })
    ));
    assert!(matches!(
        fit_plane(&line, &[1, 2], 1e-6),
        Err(Error::InvalidParameter { arg: "nodes", .. })
    ));
    assert!(matches!(
        fit_plane(&line, &[1, 2, 9], 1e-6),
        Err(Error::IndexOutOfRange {
            arg: "nodes",
            position: 2,
            ..
        })
    ));
    let mut nan = line.clone();
    nan[2][1] = f64::NAN;
    assert!(matches!(
        fit_plane(&nan, &[0, 1, 2], 1e-6),
        Err(Error::NonFinite {
            arg: "points",
            position: 2
        })
    ));
    assert!(matches!(
        fit_plane(&pts, &nodes, f64::NAN),
        Err(Error::InvalidParameter {
            arg: "tolerance",
            ..
        })
    ));
    // 2D: a line y = 2x + 1 gives the normal ±(−2, 1)/√5.
    let l2: Vec<[f64; 2]> = (0..6)
        .map(|k| [k as f64 * 0.3, 2.0 * k as f64 * 0.3 + 1.0])
        .collect();
    let f2 = fit_plane(&l2, &[0, 1, 2, 3, 4, 5], 1e-12).unwrap();
    let s5 = 5f64.sqrt();
    assert!((f2.normal[0] - 2.0 / s5).abs() < 1e-14 && (f2.normal[1] + 1.0 / s5).abs() < 1e-14);
}

#[test]
fn plane_intersection_tangent() {
    let t = plane_intersection([1.0, 0.0, 0.0], [0.0, 0.0, 2.0]).unwrap();
    assert_eq!(t, [0.0, -1.0, 0.0]);
    assert!(matches!(
        plane_intersection([1.0, 0.0, 0.0], [-2.0, 0.0, 0.0]),
        Err(Error::ZeroLength { .. })
    ));
    assert!(matches!(
        plane_intersection([f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]),
        Err(Error::NonFinite { position: 0, .. })
    ));
}

/// A node on the line where two symmetry planes meet slides along it: the 3D half box cut
/// to a quarter (x > 0, y > 0), the edge x = y = 0 as a line constraint, matches the dense
/// reference and stays on both planes.
#[test]
fn line_constraint_on_quarter_box() {
    let mesh = box_with_inner_box3(8, 2).unwrap();
    let half = Half::new(&mesh, 0, 0.0);
    // Quarter: re-cut the half at y = 0 by building a Mesh from it.
    let mut m = Mesh::<3>::new();
    m.points = half.points.clone();
    for c in 0..half.kinds.len() {
        let (a, b) = (half.offsets[c] as usize, half.offsets[c + 1] as usize);
        m.push_cell(
            deform_kernel::CellKind::from_vtk(half.kinds[c]).unwrap(),
            &half.nodes[a..b],
        );
    }
    m.markers = mesh.markers.clone();
    // Markers index the full mesh: rebuild them through the half's wall/outer lists.
    for mk in &mut m.markers {
        mk.node_list = if mk.name == "inner" {
            half.wall.clone()
        } else {
            half.outer.clone()
        };
    }
    let q = Half::new(&m, 1, 0.0);
    let mut kinds = vec![0u8; q.points.len()];
    let mut dirs = vec![[0.0; 3]; q.points.len()];
    for &i in q.wall.iter().chain(&q.outer) {
        kinds[i as usize] = 1;
    }
    let t = plane_intersection([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
    let mut on_line = Vec::new();
    for (i, p) in q.points.iter().enumerate() {
        if kinds[i] == 1 {
            continue;
        }
        let (x0, y0) = (p[0].abs() < 1e-9, p[1].abs() < 1e-9);
        match (x0, y0) {
            (true, true) => {
                kinds[i] = 3;
                dirs[i] = t;
                on_line.push(i);
            }
            (true, false) => {
                kinds[i] = 2;
                dirs[i] = [1.0, 0.0, 0.0];
            }
            (false, true) => {
                kinds[i] = 2;
                dirs[i] = [0.0, 1.0, 0.0];
            }
            _ => {}
        }
    }
    assert!(!on_line.is_empty());
    let motion = [0.05, 0.05, 0.2];
    let mut fixed = vec![[0.0; 3]; kinds.len()];
    for &i in &q.wall {
        fixed[i as usize] = motion;
    }
    let g = q.graph();
    let reference = dense_reference(&g, &q.k, &kinds, &dirs, &fixed, |_, _, k| {
        std::array::from_fn(|r| std::array::from_fn(|c| if r == c { k } else { 0.0 }))
    });
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = vec![0u8; kinds.len()];
    c.fixed_mask(&mut mask).unwrap();
    let mut s = vec![0u32; kinds.len()];
    let sys = SpringSystem::new(g, &q.k, &mask, &mut s).unwrap();
    let solver: LinearSolver<'_, f64> = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    }
    .into();
    let mut d = fixed.clone();
    let mut work = vec![[0.0; 3]; solve_linear_sliding_scratch_len(&solver, d.len())];
    let opts = SolveOptions {
        residual_tol: 1e-12,
        ..SolveOptions::default()
    };
    let r = sys
        .solve_linear_sliding(&c, &mut d, solver, &opts, &mut work)
        .unwrap();
    assert!(r.converged);
    assert!(max_diff(&d, &reference) / max_abs(&reference) < 1e-8);
    for &i in &on_line {
        assert!(
            d[i][0].abs() <= 1e-15 && d[i][1].abs() <= 1e-15,
            "{:?}",
            d[i]
        );
        assert!(d[i][2].abs() > 1e-4, "line node {i} did not slide");
    }
}

/// Bad input: typed errors, outputs untouched.
#[test]
fn bad_input_is_refused_untouched() {
    let dirs = [[0.0, 1.0], [0.0, 1.0], [0.6, 0.8]];
    assert!(Constraints::new(&[0, 1, 2], &dirs).is_ok());
    assert!(matches!(
        Constraints::new(&[0, 4, 2], &dirs),
        Err(Error::IndexOutOfRange {
            arg: "kinds",
            position: 1,
            index: 4,
            bound: 4
        })
    ));
    assert!(matches!(
        Constraints::new(&[0, 1, 2], &[[0.0, 1.0], [0.0, 1.0], [0.6, 0.81]]),
        Err(Error::NotUnit {
            arg: "directions",
            position: 2
        })
    ));
    assert!(matches!(
        Constraints::new(&[0, 1, 3], &[[0.0, 1.0], [0.0, 1.0], [0.0, 0.0]]),
        Err(Error::NotUnit {
            arg: "directions",
            position: 2
        })
    ));
    assert!(matches!(
        Constraints::new(&[0, 1, 2], &[[0.0, 1.0], [0.0, 1.0], [f64::NAN, 1.0]]),
        Err(Error::NonFinite {
            arg: "directions",
            position: 2
        })
    ));
    // Directions of free and fixed nodes are ignored, NaN included.
    assert!(Constraints::new(&[0, 1], &[[f64::NAN; 2], [f64::INFINITY; 2]]).is_ok());
    assert!(matches!(
        Constraints::new(&[0, 1], &dirs),
        Err(Error::LengthMismatch {
            arg: "directions",
            ..
        })
    ));

    // Solves: mask mismatch and NaN values leave the values bit for bit.
    let h = half_annulus();
    let (kinds, dirs, _) = h.constraints(false);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let mut mask = vec![0u8; kinds.len()];
    c.fixed_mask(&mut mask).unwrap();
    let mut wrong = mask.clone();
    wrong[h.sym[0] as usize] = 1;
    let mut s = vec![0u32; kinds.len()];
    let sys_wrong = SpringSystem::new(h.graph(), &h.k, &wrong, &mut s).unwrap();
    let sys = SpringSystem::new(h.graph(), &h.k, &mask, &mut s).unwrap();
    let solver: LinearSolver<'_, f64> = LinearMethod::GaussSeidel.into();
    let mut work = vec![[0.0; 2]; solve_linear_sliding_scratch_len(&solver, kinds.len())];
    let opts = SolveOptions::default();
    let mut d = vec![[0.25, -0.0]; kinds.len()];
    let before = d.clone();
    assert!(matches!(
        sys_wrong.solve_linear_sliding(&c, &mut d, solver, &opts, &mut work),
        Err(Error::InvalidParameter {
            arg: "constraints",
            ..
        })
    ));
    d[5][1] = f64::NAN;
    let nan_before: Vec<[u64; 2]> = d.iter().map(|v| v.map(f64::to_bits)).collect();
    assert!(matches!(
        sys.solve_linear_sliding(&c, &mut d, solver, &opts, &mut work),
        Err(Error::NonFinite {
            arg: "values",
            position: 5
        })
    ));
    assert_eq!(
        nan_before,
        d.iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>()
    );
    d[5][1] = -0.0;
    assert_eq!(
        before
            .iter()
            .map(|v| v.map(f64::to_bits))
            .collect::<Vec<_>>(),
        d.iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>()
    );
    let mut short = vec![[0.0; 2]; 1];
    assert!(matches!(
        sys.solve_linear_sliding(&c, &mut d, LinearMethod::Jacobi.into(), &opts, &mut short),
        Err(Error::BufferTooSmall { arg: "scratch", .. })
    ));
    let bad = SolveOptions {
        residual_tol: f64::NAN,
        ..SolveOptions::default()
    };
    assert!(sys
        .solve_linear_sliding(&c, &mut d, solver, &bad, &mut work)
        .is_err());
    assert!(sys
        .solve_linear_sliding(
            &c,
            &mut d,
            LinearMethod::Sor { omega: 2.0 }.into(),
            &opts,
            &mut work
        )
        .is_err());
    // Overflowing stiffness × values.
    let mut huge = vec![[1e300, 1e300]; kinds.len()];
    let k_big: Vec<f64> = h.k.iter().map(|k| k * 1e300).collect();
    let sys_big = SpringSystem::new(h.graph(), &k_big, &mask, &mut s).unwrap();
    let hb: Vec<[u64; 2]> = huge.iter().map(|v| v.map(f64::to_bits)).collect();
    let r = sys_big.solve_linear_sliding(&c, &mut huge, solver, &opts, &mut work);
    if r.is_err() {
        assert_eq!(
            hb,
            huge.iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>()
        );
    } else {
        assert!(huge.iter().flatten().all(|x| x.is_finite()));
    }

    // slide_points: NaN and wrong lengths leave the points.
    let mut pts = h.points.clone();
    pts[0][0] = f64::NAN;
    let pb: Vec<[u64; 2]> = pts.iter().map(|v| v.map(f64::to_bits)).collect();
    assert!(matches!(
        slide_points(&c, &h.points, &mut pts),
        Err(Error::NonFinite {
            arg: "points",
            position: 0
        })
    ));
    assert_eq!(
        pb,
        pts.iter().map(|v| v.map(f64::to_bits)).collect::<Vec<_>>()
    );
    assert!(matches!(
        slide_points(&c, &h.points[1..], &mut pts),
        Err(Error::LengthMismatch {
            arg: "original",
            ..
        })
    ));
}

/// Scaling values by a power of two scales the constrained solution exactly.
#[test]
fn power_of_two_scaling_is_exact() {
    let h = half_box();
    let solver: LinearSolver<'_, f64> = LinearMethod::Cg {
        preconditioner: Preconditioner::Jacobi,
    }
    .into();
    let a = h.solve([0.0, 0.3, 0.1], false, solver);
    let b = h.solve(
        [0.0, 0.3 * 2f64.powi(40), 0.1 * 2f64.powi(40)],
        false,
        solver,
    );
    for (x, y) in a.iter().zip(&b) {
        for (p, q) in x.iter().zip(y) {
            assert_eq!((p * 2f64.powi(40)).to_bits(), q.to_bits());
        }
    }
}
