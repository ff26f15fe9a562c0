//! Tangent and adjoint of single-step linear elasticity: the dot-product test (triangles,
//! quadrilaterals, tetrahedra, hexahedra; f32 and f64; block-Jacobi and multigrid), both
//! directions against the dense numpy Jacobian of the assembled matrix (the assembly itself
//! is checked against scikit-fem in `elasticity_skfem`), central differences of the
//! deformation, an infinitesimal rigid motion reproduced, and typed errors.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::elasticity::{ElasticSystem, Modulus};
use deform_kernel::sensitivity::{
    elastic_adjoint, elastic_adjoint_many, elastic_adjoint_scratch_len, elastic_tangent,
    elastic_tangent_scratch_len, ElasticPreconditioner,
};
use deform_kernel::spring::{AmgOptions, SolveOptions, SpringSystem};
use deform_kernel::{Error, Real};
use support::elasticity::{assembled, grid2, grid3, Assembled, Kind, Mesh};
use support::spring::{AmgBuffers, Lcg};

fn fixed_of<const D: usize>(m: &Mesh<D>) -> Vec<u8> {
    m.boundary.iter().map(|&b| b as u8).collect()
}

fn both<T: Real, const D: usize>(
    sys: &ElasticSystem<'_, T, D>,
    pre: ElasticPreconditioner<'_, T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let n = sys.node_count();
    let mut jv = v.to_vec();
    let mut s = vec![[T::ZERO; D]; elastic_tangent_scratch_len(&pre, n)];
    assert!(
        elastic_tangent(sys, pre, &tight(), &mut jv, &mut s)
            .unwrap()
            .converged
    );
    let mut g = vec![[T::ZERO; D]; n];
    let mut s = vec![[T::ZERO; D]; elastic_adjoint_scratch_len(&pre, n)];
    assert!(
        elastic_adjoint(sys, pre, &tight(), w, &mut g, &mut s)
            .unwrap()
            .converged
    );
    (jv, g)
}

/// Random `v` on the boundary and `w` everywhere, for mesh `m`.
fn fields<T: Real, const D: usize>(m: &Mesh<D>, seed: u64) -> (Vec<[T; D]>, Vec<[T; D]>) {
    let n = m.points.len();
    let mut rng = Lcg(seed);
    let v = random(n, &mut rng, |i| m.boundary[i]);
    let w = random(n, &mut rng, |_| true);
    (v, w)
}

fn dot_test<T: Real, const D: usize>(m: &Mesh<D>, tol: f64) {
    let a: Assembled<T, D> = assembled(
        m,
        &m.points_as(),
        Modulus::InverseVolume,
        None,
        T::from_f64(0.3),
    );
    let fixed = fixed_of(m);
    let sys = a.system(&fixed);
    let (v, w) = fields::<T, D>(m, 9);
    let (jv, g) = both(&sys, ElasticPreconditioner::Blocks, &v, &w);
    assert_dot(
        &jv,
        &w,
        &v,
        &g,
        tol,
        &format!("{D}D {:?} blocks", m.kinds[0]),
    );
    let mut k = vec![T::ZERO; a.targets.len()];
    sys.amg_weights(&mut k).unwrap();
    let mut anchor = vec![0u32; m.points.len()];
    let spring = SpringSystem::new(a.graph(), &k, &fixed, &mut anchor).unwrap();
    let opts = AmgOptions::default();
    let mut b = AmgBuffers::new(&spring, &opts);
    let h = b.build(&spring, &opts);
    let (jv, g) = both(&sys, ElasticPreconditioner::Amg(&spring, &h), &v, &w);
    assert_dot(
        &jv,
        &w,
        &v,
        &g,
        tol,
        &format!("{D}D {:?} multigrid", m.kinds[0]),
    );
}

#[test]
fn dot_product_f64() {
    dot_test::<f64, 2>(&grid2(6, Kind::Simplex, 0.3), 1e-11);
    dot_test::<f64, 2>(&grid2(6, Kind::Box, 0.3), 1e-11);
    dot_test::<f64, 3>(&grid3(3, Kind::Simplex, 0.2), 1e-11);
    dot_test::<f64, 3>(&grid3(3, Kind::Box, 0.2), 1e-11);
}

#[test]
fn dot_product_f32() {
    dot_test::<f32, 2>(&grid2(6, Kind::Simplex, 0.3), 3e-5);
    dot_test::<f32, 3>(&grid3(3, Kind::Box, 0.2), 3e-5);
}

/// The dense matrix of the kernel's blocks over node-major dofs.
fn dense_matrix<const D: usize>(a: &Assembled<f64, D>) -> Vec<Vec<f64>> {
    let n = a.diag.len();
    let g = a.graph();
    let mut k = vec![vec![0.0; n * D]; n * D];
    for i in 0..n {
        let mut put = |j: usize, b: &[[f64; D]; D]| {
            for r in 0..D {
                for c in 0..D {
                    k[i * D + r][j * D + c] = b[r][c];
                }
            }
        };
        put(i, &a.diag[i]);
        for e in g.edge_range(i) {
            put(g.targets()[e] as usize, &a.off[e]);
        }
    }
    k
}

fn dense<const D: usize>(m: &Mesh<D>) {
    let a = assembled(m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed = fixed_of(m);
    let sys = a.system(&fixed);
    let (v, w) = fields::<f64, D>(m, 21);
    let (jv, g) = both(&sys, ElasticPreconditioner::Blocks, &v, &w);
    let body = matrix_input(&dense_matrix(&a), &m.boundary, &v, &w);
    let (jv_ref, g_ref) = reference::<D>("matrix", body, m.points.len());
    let (e1, e2) = (rel_err(&jv, &jv_ref), rel_err(&g, &g_ref));
    assert!(
        e1 <= 1e-10 && e2 <= 1e-10,
        "{D}D: tangent {e1:e}, adjoint {e2:e}"
    );
}

#[test]
fn tangent_and_adjoint_match_dense_numpy() {
    dense(&grid2(5, Kind::Box, 0.3));
    dense(&grid3(3, Kind::Simplex, 0.2));
}

/// An infinitesimal rigid motion `δu = t + ω × x` of the whole boundary is reproduced at every
/// node (rigid motions are in the stiffness's null space), and its central differences too.
#[test]
fn rigid_motion_derivative_is_exact() {
    let m = grid3(3, Kind::Box, 0.2);
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed = fixed_of(&m);
    let sys = a.system(&fixed);
    let (t, om) = ([0.1, -0.2, 0.05], [0.3, 0.7, -0.4]);
    let rigid: Vec<[f64; 3]> = m
        .points
        .iter()
        .map(|p| {
            [
                t[0] + om[1] * p[2] - om[2] * p[1],
                t[1] + om[2] * p[0] - om[0] * p[2],
                t[2] + om[0] * p[1] - om[1] * p[0],
            ]
        })
        .collect();
    let mut dx: Vec<[f64; 3]> = rigid
        .iter()
        .zip(&m.boundary)
        .map(|(r, &b)| if b { *r } else { [0.0; 3] })
        .collect();
    let pre = ElasticPreconditioner::Blocks;
    let mut s = vec![[0.0; 3]; elastic_tangent_scratch_len(&pre, dx.len())];
    elastic_tangent(&sys, pre, &tight(), &mut dx, &mut s).unwrap();
    assert!(rel_err(&dx, &rigid) <= 1e-11, "{:e}", rel_err(&dx, &rigid));
}

/// Central differences of the deformation along `v` at several steps equal the tangent up to
/// rounding and tolerance over `h` (a linear map: no `h²` term).
#[test]
fn tangent_matches_central_differences() {
    let m = grid2(6, Kind::Simplex, 0.3);
    let a = assembled(&m, &m.points, Modulus::InverseVolume, None, 0.3);
    let fixed = fixed_of(&m);
    let sys = a.system(&fixed);
    let (d0, _) = fields::<f64, 2>(&m, 31);
    let (v, _) = fields::<f64, 2>(&m, 37);
    let pre = ElasticPreconditioner::Blocks;
    let mut s = vec![[0.0; 2]; elastic_tangent_scratch_len(&pre, v.len())];
    let mut jv = v.clone();
    elastic_tangent(&sys, pre, &tight(), &mut jv, &mut s).unwrap();
    for k in 1..=6 {
        let h = 10f64.powi(-k);
        let shifted = |sgn: f64| -> Vec<[f64; 2]> {
            d0.iter()
                .zip(&v)
                .map(|(a, b)| [a[0] + sgn * h * b[0], a[1] + sgn * h * b[1]])
                .collect()
        };
        let (mut p, mut q) = (shifted(1.0), shifted(-1.0));
        sys.solve(&mut p, &tight(), &mut s).unwrap();
        sys.solve(&mut q, &tight(), &mut s).unwrap();
        let fd: Vec<[f64; 2]> = p
            .iter()
            .zip(&q)
            .map(|(p, q)| [(p[0] - q[0]) / (2.0 * h), (p[1] - q[1]) / (2.0 * h)])
            .collect();
        let e = rel_err(&fd, &jv);
        assert!(e <= 1e-11 / h, "step {h:e}: {e:e}");
    }
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let m = grid2(4, Kind::Box, 0.2);
    let a = assembled(&m, &m.points, Modulus::Constant, None, 0.3);
    let fixed = fixed_of(&m);
    let sys = a.system(&fixed);
    let n = m.points.len();
    let pre = ElasticPreconditioner::Blocks;
    let len = elastic_adjoint_scratch_len(&pre, n);
    let mut s = vec![[0.0; 2]; len];
    let mut w = vec![[1.0; 2]; n];
    let mut g = vec![[5.0; 2]; n];
    let o = SolveOptions::default();
    let r = elastic_adjoint(&sys, pre, &o, &w, &mut g, &mut s[..len - 1]);
    assert!(matches!(r, Err(Error::BufferTooSmall { .. })));
    w[0][0] = f64::INFINITY;
    let r = elastic_adjoint(&sys, pre, &o, &w, &mut g, &mut s);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    let r = elastic_adjoint_many(&sys, pre, &o, &w[1..], &mut g[1..], &mut s);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
    assert!(g.iter().all(|x| *x == [5.0; 2]));
}
