//! Tangent and adjoint of the deformations with sliding nodes (symmetry planes): single-step
//! elasticity (block Jacobi and multigrid) and the linear springs (CG with each one-level
//! preconditioner and multigrid) on the unit square / cube with the face `y = 0` (2D) or the
//! faces `z = 0` and `y = 0` (3D, their common edge sliding on a line) sliding and the other
//! faces fixed: the dot-product test, central differences of the deformation, a translation
//! along the planes reproduced, the sliding nodes' tangent in their planes, and typed errors
//! that write nothing.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::elasticity::{ElasticSystem, Modulus};
use deform_kernel::sensitivity::{
    elastic_sliding_adjoint, elastic_sliding_adjoint_scratch_len, elastic_sliding_tangent,
    elastic_sliding_tangent_scratch_len, spring_sliding_adjoint,
    spring_sliding_adjoint_scratch_len, spring_sliding_tangent, ElasticPreconditioner,
};
use deform_kernel::spring::constraints::{Constraints, NodeKind};
use deform_kernel::spring::{
    solve_linear_sliding_scratch_len, AmgOptions, LinearMethod, LinearSolver, Preconditioner,
    SolveOptions, SpringSystem,
};
use deform_kernel::{Error, Real};
use support::elasticity::{assembled, grid2, grid3, Kind, Mesh};
use support::spring::{AmgBuffers, Case, Lcg};

/// Node kinds and directions: the face `x_{D−1} = 0` slides (normal `e_{D−1}`), in 3D also
/// `y = 0` (their common edge on the line `e_x`); every other boundary node is fixed.
fn table<T: Real, const D: usize>(m: &Mesh<D>) -> (Vec<u8>, Vec<[T; D]>) {
    let unit = |c: usize| std::array::from_fn(|k| if k == c { T::ONE } else { T::ZERO });
    let on = |p: &[f64; D], c: usize, v: f64| (p[c] - v).abs() < 1e-12;
    let mut kinds = Vec::new();
    let mut dirs = Vec::new();
    for (p, &b) in m.points.iter().zip(&m.boundary) {
        let low: Vec<usize> = (1..D).filter(|&c| on(p, c, 0.0)).collect();
        let other = (0..D).any(|c| on(p, c, 1.0)) || on(p, 0, 0.0);
        let (k, d) = match (b, other, low.as_slice()) {
            (false, ..) => (0, [T::ZERO; D]),
            (true, false, [c]) if *c == D - 1 || D == 3 => (2, unit(*c)),
            (true, false, [_, _]) => (3, unit(0)),
            _ => (1, [T::ZERO; D]),
        };
        kinds.push(k);
        dirs.push(d);
    }
    (kinds, dirs)
}

/// `x` in f64 (the reference side of `rel_err`).
fn f64s<T: Real, const D: usize>(x: &[[T; D]]) -> Vec<[f64; D]> {
    x.iter().map(|v| v.map(|c| c.to_f64())).collect()
}

fn mask(kinds: &[u8]) -> Vec<u8> {
    kinds.iter().map(|&k| (k == 1) as u8).collect()
}

/// Random `v` at the fixed nodes and `w` everywhere.
fn fields<T: Real, const D: usize>(kinds: &[u8], seed: u64) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let mut rng = Lcg(seed);
    let v = random(kinds.len(), &mut rng, |i| kinds[i] == 1);
    let w = random(kinds.len(), &mut rng, |_| true);
    (v, w)
}

fn elastic_both<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    c: &Constraints<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let n = sys.node_count();
    let mut jv = v.to_vec();
    let mut s = vec![[T::ZERO; D]; elastic_sliding_tangent_scratch_len(&pre, n)];
    let r = elastic_sliding_tangent(sys, c, pre, &tight(), &mut jv, &mut s).unwrap();
    assert!(r.converged, "tangent {r:?}");
    let mut g = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; elastic_sliding_adjoint_scratch_len(&pre, n)];
    let r = elastic_sliding_adjoint(sys, c, pre, &tight(), w, &mut g, &mut s).unwrap();
    assert!(r.converged, "adjoint {r:?}");
    (jv, g)
}

/// The sliding nodes' tangent lies in their planes / on their lines.
fn assert_in_planes<T: Real, const D: usize>(c: &Constraints<'_, T, D>, jv: &[[T; D]], tol: f64) {
    let scale = norm(jv);
    for (i, x) in jv.iter().enumerate() {
        if c.kind(i) == NodeKind::Fixed {
            continue;
        }
        let p = c.project(i, *x);
        let off: f64 = (0..D)
            .map(|k| (x[k].to_f64() - p[k].to_f64()).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(off <= tol * scale, "node {i}: {off:e} off its plane");
    }
}

fn elastic_dot<T: Real, const D: usize>(m: &Mesh<D>, tol: f64) {
    let a = assembled(
        m,
        &m.points_as::<T>(),
        Modulus::InverseVolume,
        None,
        T::from_f64(0.3),
    );
    let (kinds, dirs) = table::<T, D>(m);
    assert!(kinds.contains(&2), "no sliding node");
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let fixed = mask(&kinds);
    let sys = a.system(&fixed);
    let (v, w) = fields::<T, D>(&kinds, 11);
    let (jv, g) = elastic_both(&sys, &c, ElasticPreconditioner::Blocks, &v, &w);
    let what = format!("{D}D {:?} blocks", m.kinds[0]);
    check_dot(&jv, &w, &v, &g, tol, &what);
    assert_in_planes(&c, &jv, tol);
    let mut k = vec![T::ZERO; a.targets.len()];
    sys.amg_weights(&mut k).unwrap();
    let mut anchor = vec![0u32; m.points.len()];
    let spring = SpringSystem::new(a.graph(), &k, &fixed, &mut anchor).unwrap();
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&spring, &opts);
    let h = b.build(&spring, &opts);
    let pre = ElasticPreconditioner::Amg(&spring, &h);
    let (jv2, g2) = elastic_both(&sys, &c, pre, &v, &w);
    check_dot(&jv2, &w, &v, &g2, tol, &format!("{D}D multigrid"));
    // Both preconditioners solve the same projected system.
    let (e1, e2) = (rel_err(&jv2, &f64s(&jv)), rel_err(&g2, &f64s(&g)));
    assert!(e1 <= 100.0 * tol && e2 <= 100.0 * tol, "{e1:e} {e2:e}");
}

#[test]
fn elasticity_dot_product_f64() {
    elastic_dot::<f64, 2>(&grid2(6, Kind::Simplex, 0.3), 1e-11);
    elastic_dot::<f64, 2>(&grid2(6, Kind::Box, 0.3), 1e-11);
    elastic_dot::<f64, 3>(&grid3(3, Kind::Simplex, 0.2), 1e-11);
    elastic_dot::<f64, 3>(&grid3(3, Kind::Box, 0.2), 1e-11);
}

#[test]
fn elasticity_dot_product_f32() {
    elastic_dot::<f32, 2>(&grid2(6, Kind::Simplex, 0.3), 3e-5);
    elastic_dot::<f32, 3>(&grid3(3, Kind::Box, 0.2), 3e-5);
}

/// The spring case on the mesh's cell-pair graph with the table's fixed mask.
fn spring_case<T: Real, const D: usize>(m: &Mesh<D>, fixed: Vec<u8>) -> Case<T, D> {
    let a = assembled(m, &m.points, Modulus::Constant, None, 0.3);
    let g = a.graph();
    let mut edges = Vec::new();
    for i in 0..m.points.len() {
        for e in g.edge_range(i) {
            let j = g.targets()[e];
            if (i as u32) < j {
                edges.push([i as u32, j]);
            }
        }
    }
    Case::new(&m.points, &edges, fixed)
}

fn spring_both<T: Real, const D: usize>(
    sys: &SpringSystem<'_, T>,
    c: &Constraints<'_, T, D>,
    solver: LinearSolver<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let n = sys.node_count();
    let mut jv = v.to_vec();
    let mut s = vec![[T::ZERO; D]; solve_linear_sliding_scratch_len(&solver, n)];
    let r = spring_sliding_tangent(sys, c, solver, &tight(), &mut jv, &mut s).unwrap();
    assert!(r.converged, "tangent {r:?}");
    let mut g = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; spring_sliding_adjoint_scratch_len::<T, D>(&solver, n)];
    let r = spring_sliding_adjoint(sys, c, solver, &tight(), w, &mut g, &mut s).unwrap();
    assert!(r.converged, "adjoint {r:?}");
    (jv, g)
}

fn spring_dot<T: Real, const D: usize>(m: &Mesh<D>, tol: f64) {
    let (kinds, dirs) = table::<T, D>(m);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let case = spring_case::<T, D>(m, mask(&kinds));
    let sys = case.system();
    let (v, w) = fields::<T, D>(&kinds, 23);
    let mut first = None;
    for pre in [
        Preconditioner::None,
        Preconditioner::Jacobi,
        Preconditioner::Ssor { omega: T::ONE },
    ] {
        let cg = LinearSolver::Method(LinearMethod::Cg {
            preconditioner: pre,
        });
        let (jv, g) = spring_both(&sys, &c, cg, &v, &w);
        check_dot(&jv, &w, &v, &g, tol, &format!("{D}D springs {pre:?}"));
        assert_in_planes(&c, &jv, tol);
        first.get_or_insert(g);
    }
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&sys, &opts);
    let h = b.build(&sys, &opts);
    let (jv, g) = spring_both(&sys, &c, LinearSolver::Amg(&h), &v, &w);
    check_dot(&jv, &w, &v, &g, tol, &format!("{D}D springs multigrid"));
    let g0 = first.unwrap();
    let e = rel_err(&g, &f64s(&g0));
    assert!(e <= 100.0 * tol, "{e:e}");
}

#[test]
fn springs_dot_product() {
    spring_dot::<f64, 2>(&grid2(6, Kind::Simplex, 0.3), 1e-11);
    spring_dot::<f64, 3>(&grid3(3, Kind::Box, 0.2), 1e-11);
    spring_dot::<f32, 2>(&grid2(6, Kind::Simplex, 0.3), 3e-5);
    spring_dot::<f32, 3>(&grid3(3, Kind::Simplex, 0.2), 3e-5);
}

/// Central differences of the deformations along `v` at several steps equal the tangent up
/// to tolerance over `h` (linear maps: no `h²` term).
#[test]
fn tangent_matches_central_differences() {
    fn run<const D: usize>(m: &Mesh<D>) {
        let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.3);
        let (kinds, dirs) = table::<f64, D>(m);
        let c = Constraints::new(&kinds, &dirs).unwrap();
        let fixed = mask(&kinds);
        let sys = a.system(&fixed);
        let case = spring_case::<f64, D>(m, fixed.clone());
        let springs = case.system();
        let cg = LinearSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        });
        let (d0, _) = fields::<f64, D>(&kinds, 31);
        let (v, _) = fields::<f64, D>(&kinds, 37);
        let n = v.len();
        let pre = ElasticPreconditioner::Blocks;
        let mut s = vec![[0.0; D]; elastic_sliding_tangent_scratch_len(&pre, n)];
        let mut jv = v.clone();
        elastic_sliding_tangent(&sys, &c, pre, &tight(), &mut jv, &mut s).unwrap();
        let mut ss = vec![[0.0; D]; solve_linear_sliding_scratch_len(&cg, n)];
        let mut jv_s = v.clone();
        spring_sliding_tangent(&springs, &c, cg, &tight(), &mut jv_s, &mut ss).unwrap();
        for k in 1..=6 {
            let h = 10f64.powi(-k);
            let shifted = |sgn: f64| -> Vec<[f64; D]> {
                (d0.iter().zip(&v))
                    .map(|(a, b)| std::array::from_fn(|c| a[c] + sgn * h * b[c]))
                    .collect()
            };
            let fd = |p: &[[f64; D]], q: &[[f64; D]]| -> Vec<[f64; D]> {
                (p.iter().zip(q))
                    .map(|(p, q)| std::array::from_fn(|c| (p[c] - q[c]) / (2.0 * h)))
                    .collect()
            };
            let (mut p, mut q) = (shifted(1.0), shifted(-1.0));
            sys.solve_sliding(&c, &mut p, &tight(), &mut s).unwrap();
            sys.solve_sliding(&c, &mut q, &tight(), &mut s).unwrap();
            let e = rel_err(&fd(&p, &q), &jv);
            assert!(e <= 1e-11 / h, "{D}D elasticity step {h:e}: {e:e}");
            let (mut p, mut q) = (shifted(1.0), shifted(-1.0));
            (springs.solve_linear_sliding(&c, &mut p, cg, &tight(), &mut ss)).unwrap();
            (springs.solve_linear_sliding(&c, &mut q, cg, &tight(), &mut ss)).unwrap();
            let e = rel_err(&fd(&p, &q), &jv_s);
            assert!(e <= 1e-11 / h, "{D}D springs step {h:e}: {e:e}");
        }
    }
    run::<2>(&grid2(6, Kind::Simplex, 0.3));
    run::<3>(&grid3(3, Kind::Box, 0.2));
}

/// A translation along every sliding plane (`e_x`) of the fixed nodes is reproduced at every
/// node, sliding ones included; the constrained adjoint of a field that vanishes off the
/// fixed nodes is that field (no solve needed: `λ = 0`).
#[test]
fn translation_along_the_planes_is_exact() {
    let m = grid3(3, Kind::Simplex, 0.2);
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let (kinds, dirs) = table::<f64, 3>(&m);
    assert!(kinds.contains(&3), "no node on a line");
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let fixed = mask(&kinds);
    let sys = a.system(&fixed);
    let t = [0.3, 0.0, 0.0];
    let mut dx: Vec<[f64; 3]> = fixed.iter().map(|&f| [t[0] * f as f64, 0.0, 0.0]).collect();
    let pre = ElasticPreconditioner::Blocks;
    let mut s = vec![[0.0; 3]; elastic_sliding_tangent_scratch_len(&pre, dx.len())];
    elastic_sliding_tangent(&sys, &c, pre, &tight(), &mut dx, &mut s).unwrap();
    let all = vec![t; dx.len()];
    assert!(rel_err(&dx, &all) <= 1e-11, "{:e}", rel_err(&dx, &all));
    let w: Vec<[f64; 3]> = fixed.iter().map(|&f| [f as f64, 2.0, -1.0]).collect();
    let w: Vec<[f64; 3]> = (w.iter().zip(&fixed))
        .map(|(x, &f)| if f == 1 { *x } else { [0.0; 3] })
        .collect();
    let mut g = vec![[9.0; 3]; w.len()];
    let mut s = vec![[0.0; 3]; elastic_sliding_adjoint_scratch_len(&pre, w.len())];
    elastic_sliding_adjoint(&sys, &c, pre, &tight(), &w, &mut g, &mut s).unwrap();
    assert_eq!(g, w);
}

/// The constrained derivative is not the unconstrained one: the sliding nodes' normal motion
/// is held, so the adjoint differs from the fixed-plane one (a test of the projection that
/// cannot pass with the planes left free or held fixed).
#[test]
fn sliding_differs_from_free_and_from_fixed() {
    use deform_kernel::sensitivity::{elastic_adjoint, elastic_adjoint_scratch_len};
    let m = grid2(6, Kind::Simplex, 0.3);
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let (kinds, dirs) = table::<f64, 2>(&m);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let fixed = mask(&kinds);
    let sys = a.system(&fixed);
    let (_, w) = fields::<f64, 2>(&kinds, 41);
    let pre = ElasticPreconditioner::Blocks;
    let mut g = vec![[0.0; 2]; w.len()];
    let mut s = vec![[0.0; 2]; elastic_sliding_adjoint_scratch_len(&pre, w.len())];
    elastic_sliding_adjoint(&sys, &c, pre, &tight(), &w, &mut g, &mut s).unwrap();
    // The planes held fixed: every sliding node fixed too.
    let held: Vec<u8> = kinds.iter().map(|&k| (k != 0) as u8).collect();
    let sys_held = a.system(&held);
    let mut gh = vec![[0.0; 2]; w.len()];
    let mut s = vec![[0.0; 2]; elastic_adjoint_scratch_len(&pre, w.len())];
    elastic_adjoint(&sys_held, pre, &tight(), &w, &mut gh, &mut s).unwrap();
    let gh: Vec<[f64; 2]> = (gh.iter().zip(&fixed))
        .map(|(x, &f)| if f == 1 { *x } else { [0.0; 2] })
        .collect();
    assert!(rel_err(&g, &gh) > 1e-3, "{:e}", rel_err(&g, &gh));
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let m = grid2(4, Kind::Box, 0.2);
    let a = assembled(&m, &m.points, Modulus::Constant, None, 0.3);
    let (kinds, dirs) = table::<f64, 2>(&m);
    let c = Constraints::new(&kinds, &dirs).unwrap();
    let fixed = mask(&kinds);
    let sys = a.system(&fixed);
    let n = m.points.len();
    let pre = ElasticPreconditioner::Blocks;
    let len = elastic_sliding_adjoint_scratch_len(&pre, n);
    let mut s = vec![[0.0; 2]; len];
    let mut w = vec![[1.0; 2]; n];
    let mut g = vec![[5.0; 2]; n];
    let o = SolveOptions::default();
    let r = elastic_sliding_adjoint(&sys, &c, pre, &o, &w, &mut g, &mut s[..len - 1]);
    assert!(matches!(r, Err(Error::BufferTooSmall { .. })), "{r:?}");
    // Constraints whose fixed nodes are not the system's.
    let other: Vec<u8> = kinds.iter().map(|&k| if k == 2 { 1 } else { k }).collect();
    let c2 = Constraints::new(&other, &dirs).unwrap();
    let r = elastic_sliding_adjoint(&sys, &c2, pre, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
    w[0][0] = f64::NAN;
    let r = elastic_sliding_adjoint(&sys, &c, pre, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })), "{r:?}");
    w[0][0] = 1.0;
    let case = spring_case::<f64, 2>(&m, fixed);
    let springs = case.system();
    let jacobi = LinearSolver::Method(LinearMethod::Jacobi);
    let r = spring_sliding_adjoint(&springs, &c, jacobi, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
    let r = spring_sliding_adjoint(&springs, &c2, jacobi, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
    assert!(g.iter().all(|x| *x == [5.0; 2]));
}
