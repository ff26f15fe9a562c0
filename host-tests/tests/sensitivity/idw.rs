//! Tangent and adjoint of inverse-distance weighting of the boundary displacements: the
//! dot-product test (2D and 3D, f32 and f64, `p = 2` and `p = 3`), both directions against a
//! dense numpy Jacobian (weights recomputed there), central differences of the kernel's whole
//! `deform_idw` pipeline with identity rotations (its weights are the ones differentiated), a
//! uniform translation reproduced, several fields at once, and typed errors.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::sensitivity::{idw_adjoint, idw_adjoint_many, idw_tangent, idw_tangent_many};
use deform_kernel::{Error, Quat, Real};
use support::quaternion::{block2, block3, TestMesh};
use support::spring::Lcg;

fn is_boundary<const D: usize>(m: &TestMesh<D>) -> Vec<bool> {
    let mut b = vec![false; m.points.len()];
    for &i in &m.boundary {
        b[i as usize] = true;
    }
    b
}

fn both<T: Real, const D: usize>(m: &TestMesh<D>, p: f64, seed: u64) -> [Vec<[T; D]>; 4] {
    let pts = m.points_t::<T>();
    let n = pts.len();
    let on = is_boundary(m);
    let mut rng = Lcg(seed);
    let v: Vec<[T; D]> = random(n, &mut rng, |i| on[i]);
    let w: Vec<[T; D]> = random(n, &mut rng, |_| true);
    let mut jv = v.clone();
    idw_tangent(&pts, &m.boundary, T::from_f64(p), &mut jv).unwrap();
    let mut g = vec![[T::ZERO; D]; n];
    idw_adjoint(&pts, &m.boundary, T::from_f64(p), &w, &mut g).unwrap();
    [v, w, jv, g]
}

#[test]
fn dot_product_2d_and_3d() {
    for p in [2.0, 3.0] {
        let [v, w, jv, g] = both::<f64, 2>(&block2(9, 7), p, 1);
        assert_dot(&jv, &w, &v, &g, 1e-14, &format!("2D f64 p={p}"));
        let [v, w, jv, g] = both::<f64, 3>(&block3(5, 4, 4), p, 2);
        assert_dot(&jv, &w, &v, &g, 1e-14, &format!("3D f64 p={p}"));
        let [v, w, jv, g] = both::<f32, 2>(&block2(9, 7), p, 3);
        assert_dot(&jv, &w, &v, &g, 1e-5, &format!("2D f32 p={p}"));
        let [v, w, jv, g] = both::<f32, 3>(&block3(5, 4, 4), p, 4);
        assert_dot(&jv, &w, &v, &g, 1e-5, &format!("3D f32 p={p}"));
    }
}

fn dense<const D: usize>(m: &TestMesh<D>, p: f64) {
    let [v, w, jv, g] = both::<f64, D>(m, p, 5);
    let body = idw_input(&m.points, &m.boundary, p, &v, &w);
    let (jv_ref, g_ref) = reference::<D>("idw", body, m.points.len());
    let (e1, e2) = (rel_err(&jv, &jv_ref), rel_err(&g, &g_ref));
    assert!(
        e1 <= 1e-13 && e2 <= 1e-13,
        "{D}D p={p}: tangent {e1:e}, adjoint {e2:e}"
    );
}

#[test]
fn tangent_and_adjoint_match_dense_numpy() {
    dense(&block2(8, 6), 2.0);
    dense(&block2(8, 6), 3.5);
    dense(&block3(4, 4, 3), 2.0);
}

/// `deform_idw` with identity rotations at boundary positions `x_b + d`.
fn deform<const D: usize>(m: &TestMesh<D>, d: &[[f64; D]]) -> Vec<[f64; D]> {
    let n = m.points.len();
    let deformed: Vec<[f64; D]> = m
        .boundary
        .iter()
        .map(|&b| std::array::from_fn(|c| m.points[b as usize][c] + d[b as usize][c]))
        .collect();
    let ids = vec![Quat::identity(); m.boundary.len()];
    let motion = BoundaryMotion {
        nodes: &m.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&ids),
        origin: Some([0.0; D]),
    };
    let (mut t, mut q) = (vec![[0.0; D]; n], vec![Quat::identity(); n]);
    let mut s = vec![0.0; deform_idw_scratch_len::<D>(n, m.boundary.len())];
    let mut out = vec![[0.0; D]; n];
    deform_idw(&m.points, &motion, 2.0, &mut t, &mut q, &mut s, &mut out).unwrap();
    out
}

/// Central differences of the pipeline equal the tangent up to rounding over `h` at every
/// step (the map is linear in the boundary displacement: no `h²` term).
fn fd<const D: usize>(m: &TestMesh<D>) {
    let n = m.points.len();
    let on = is_boundary(m);
    let mut rng = Lcg(17);
    let d0: Vec<[f64; D]> = random(n, &mut rng, |i| on[i]);
    let v: Vec<[f64; D]> = random(n, &mut rng, |i| on[i]);
    let mut jv = v.clone();
    idw_tangent(&m.points, &m.boundary, 2.0, &mut jv).unwrap();
    for k in 1..=6 {
        let h = 10f64.powi(-k);
        let shift = |s: f64| -> Vec<[f64; D]> {
            d0.iter()
                .zip(&v)
                .map(|(a, b)| std::array::from_fn(|c| a[c] + s * h * b[c]))
                .collect()
        };
        let (p, q) = (deform(m, &shift(1.0)), deform(m, &shift(-1.0)));
        let fd: Vec<[f64; D]> = p
            .iter()
            .zip(&q)
            .map(|(p, q)| std::array::from_fn(|c| (p[c] - q[c]) / (2.0 * h)))
            .collect();
        let e = rel_err(&fd, &jv);
        assert!(e <= 1e-14 / h, "{D}D step {h:e}: {e:e}");
    }
}

#[test]
fn tangent_matches_central_differences_of_deform_idw() {
    fd(&block2(9, 7));
    fd(&block3(4, 4, 3));
}

/// A uniform translation of the boundary moves every node by it, to rounding (free entries
/// of the input are ignored).
#[test]
fn uniform_translation_is_reproduced() {
    let m = block3(5, 4, 4);
    let t = [0.25, -1.5, 3.0];
    let on = is_boundary(&m);
    let mut dx: Vec<[f64; 3]> = on.iter().map(|&b| if b { t } else { [9.0; 3] }).collect();
    idw_tangent(&m.points, &m.boundary, 3.0, &mut dx).unwrap();
    // Σ ω t / Σ ω over B terms: rounding of order B ε.
    let e = rel_err(&dx, &vec![t; dx.len()]);
    assert!(e <= m.boundary.len() as f64 * f64::EPSILON, "{e:e}");
}

/// Three fields at once equal three single calls, bit for bit.
#[test]
fn several_fields_match_single_calls() {
    let m = block2(7, 6);
    let n = m.points.len();
    let on = is_boundary(&m);
    let mut rng = Lcg(23);
    let mut dx: Vec<[f64; 2]> = random(3 * n, &mut rng, |i| on[i % n]);
    let dx0 = dx.clone();
    let w: Vec<[f64; 2]> = random(3 * n, &mut rng, |_| true);
    let mut g = vec![[0.0; 2]; 3 * n];
    idw_tangent_many(&m.points, &m.boundary, 2.0, &mut dx).unwrap();
    idw_adjoint_many(&m.points, &m.boundary, 2.0, &w, &mut g).unwrap();
    for f in 0..3 {
        let mut one = dx0[f * n..(f + 1) * n].to_vec();
        idw_tangent(&m.points, &m.boundary, 2.0, &mut one).unwrap();
        assert_eq!(one, dx[f * n..(f + 1) * n]);
        let mut one = vec![[0.0; 2]; n];
        idw_adjoint(
            &m.points,
            &m.boundary,
            2.0,
            &w[f * n..(f + 1) * n],
            &mut one,
        )
        .unwrap();
        assert_eq!(one, g[f * n..(f + 1) * n]);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let m = block2(5, 5);
    let n = m.points.len();
    let mut w = vec![[1.0; 2]; n];
    let mut g = vec![[4.0; 2]; n];
    let r = idw_adjoint(&m.points, &[], 2.0, &w, &mut g);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter {
            arg: "boundary",
            ..
        })
    ));
    let r = idw_adjoint(&m.points, &m.boundary, 0.0, &w, &mut g);
    assert!(matches!(
        r,
        Err(Error::InvalidParameter {
            arg: "exponent",
            ..
        })
    ));
    let r = idw_adjoint(&m.points, &[n as u32], 2.0, &w, &mut g);
    assert!(matches!(r, Err(Error::IndexOutOfRange { .. })));
    w[2][0] = f64::NAN;
    let r = idw_adjoint(&m.points, &m.boundary, 2.0, &w, &mut g);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    assert!(g.iter().all(|x| *x == [4.0; 2]));
    let mut dx = vec![[2.0; 2]; n];
    dx[m.boundary[0] as usize][1] = f64::NAN;
    let before = dx.clone();
    let r = idw_tangent(&m.points, &m.boundary, 2.0, &mut dx);
    assert!(matches!(r, Err(Error::NonFinite { arg: "dx", .. })));
    assert_eq!(format!("{dx:?}"), format!("{before:?}"));
    let r = idw_tangent_many(&m.points, &m.boundary, 2.0, &mut dx[1..]);
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
}
