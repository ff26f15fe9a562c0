//! Tangent and adjoint of the RBF deformation (`rbf_tangent`, `rbf_adjoint`): the dot-product
//! test (2D and 3D, f32 and f64, Wendland and thin-plate, every centre or greedy, with and
//! without the wall correction), against the dense Jacobian built column by column from
//! `rbf_deform` itself, against central differences of `rbf_deform` (greedy: the centres of
//! the linearisation point kept), affine motions reproduced by thin-plate splines, several
//! fields, typed errors that write nothing.

#[path = "../support/sensitivity_common.rs"]
mod common;
#[path = "../support/mod.rs"]
mod support;

use common::*;
use deform_kernel::rbf::{
    rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions, RbfReport,
};
use deform_kernel::sensitivity::{rbf_adjoint, rbf_tangent};
use deform_kernel::{Error, Real};
use support::spring::Lcg;

/// A jittered grid of `s^D` points in the unit box; the boundary is its outer layer.
fn grid<T: Real, const D: usize>(s: usize) -> (Vec<[T; D]>, Vec<u32>) {
    let mut rng = Lcg(31);
    let total = s.pow(D as u32);
    let (mut pts, mut bnd) = (vec![], vec![]);
    for i in 0..total {
        let idx: [usize; D] = std::array::from_fn(|a| (i / s.pow(a as u32)) % s);
        let outer = idx.iter().any(|&c| c == 0 || c == s - 1);
        let p: [T; D] = std::array::from_fn(|a| {
            let j = if outer { 0.0 } else { 0.15 * rng.next() };
            T::from_f64((idx[a] as f64 + j) / (s - 1) as f64)
        });
        pts.push(p);
        if outer {
            bnd.push(i as u32);
        }
    }
    (pts, bnd)
}

/// Options: every centre (`greedy` false) or a greedy fit of at most half of them.
fn options<T: Real>(kernel: RbfKernel<T>, b: usize, greedy: bool, rc: f64) -> RbfOptions<T> {
    RbfOptions {
        kernel,
        tolerance: T::from_f64(if greedy { 1e-3 } else { 0.0 }),
        max_centres: if greedy { b / 2 } else { b },
        correction_radius: T::from_f64(rc),
    }
}

/// The buffers of `rbf_deform` and its derivatives.
fn buffers<T: Real, const D: usize>(b: usize, o: &RbfOptions<T>) -> (Vec<u32>, Vec<T>) {
    (
        vec![0; rbf_index_len::<T, D>(b, o)],
        vec![T::ZERO; rbf_scratch_len::<T, D>(b, o)],
    )
}

/// A smooth boundary motion (a wave, a shear and a bump at `(1, 0.3, 0.3)` whose single
/// largest motion makes the greedy choice clear-cut), the linearisation point.
fn motion<T: Real, const D: usize>(pts: &[[T; D]], bnd: &[u32]) -> Vec<[T; D]> {
    bnd.iter()
        .map(|&i| {
            let p = pts[i as usize].map(|x| x.to_f64());
            let r2: f64 = (0..D)
                .map(|a| (p[a] - if a == 0 { 1.0 } else { 0.3 }).powi(2))
                .sum();
            std::array::from_fn(|a| {
                let q = p[(a + 1) % D];
                let bump = if a == 0 {
                    0.1 * (-10.0 * r2).exp()
                } else {
                    0.0
                };
                T::from_f64(0.05 * (3.0 * q).sin() + 0.02 * p[a] * q + bump)
            })
        })
        .collect()
}

type Run<T, const D: usize> = (Vec<[T; D]>, Vec<[T; D]>, RbfReport<T>);

/// `J v` and `Jᵀ w` at `d0`.
fn both<T: Real, const D: usize>(
    pts: &[[T; D]],
    bnd: &[u32],
    d0: &[[T; D]],
    o: &RbfOptions<T>,
    v: &[[T; D]],
    w: &[[T; D]],
) -> Run<T, D> {
    let (mut index, mut scratch) = buffers::<T, D>(bnd.len(), o);
    let mut jv = vec![[T::ZERO; D]; pts.len()];
    let r = rbf_tangent(pts, bnd, d0, o, &mut index, &mut scratch, v, &mut jv).unwrap();
    let mut g = vec![[T::ZERO; D]; bnd.len()];
    rbf_adjoint(pts, bnd, d0, o, &mut index, &mut scratch, w, &mut g).unwrap();
    (jv, g, r)
}

fn dot_case<T: Real, const D: usize>(s: usize, tol: f64) {
    let (pts, bnd) = grid::<T, D>(s);
    let d0 = motion(&pts, &bnd);
    let mut rng = Lcg(41 + D as u64);
    let v: Vec<[T; D]> = random(bnd.len(), &mut rng, |_| true);
    let w: Vec<[T; D]> = random(pts.len(), &mut rng, |_| true);
    let b = bnd.len();
    for kernel in [
        RbfKernel::Wendland {
            radius: T::from_f64(0.8),
        },
        RbfKernel::ThinPlate,
    ] {
        for (greedy, rc) in [(false, 0.0), (false, 0.4), (true, 0.0), (true, 0.4)] {
            let o = options(kernel, b, greedy, rc);
            let (jv, g, r) = both(&pts, &bnd, &d0, &o, &v, &w);
            let what = format!(
                "{D}D {kernel:?} greedy {greedy} rc {rc}: {} centres",
                r.centres
            );
            assert!(!greedy || r.centres < b, "{what}");
            check_dot(&jv, &w, &v, &g, tol, &what);
        }
    }
}

#[test]
fn dot_product_2d_and_3d_f64() {
    dot_case::<f64, 2>(9, 1e-13);
    dot_case::<f64, 3>(5, 1e-13);
}

#[test]
fn dot_product_2d_and_3d_f32() {
    dot_case::<f32, 2>(9, 1e-4);
    dot_case::<f32, 3>(5, 1e-4);
}

/// With every boundary node a centre the map is linear: column `k` of `J` is `rbf_deform` of
/// the unit motion `e_k`. Tangent and adjoint against that dense Jacobian.
fn dense_case<const D: usize>(kernel: RbfKernel<f64>, rc: f64) {
    let (pts, bnd) = grid::<f64, D>(if D == 2 { 6 } else { 4 });
    let (n, b) = (pts.len(), bnd.len());
    let o = options(kernel, b, false, rc);
    let (mut index, mut scratch) = buffers::<f64, D>(b, &o);
    let mut cols = vec![]; // cols[k * D + c][i] = ∂u_i / ∂d_{k,c}
    for k in 0..b {
        for c in 0..D {
            let mut e = vec![[0.0; D]; b];
            e[k][c] = 1.0;
            let mut u = vec![[0.0; D]; n];
            rbf_deform(&pts, &bnd, &e, &o, &mut index, &mut scratch, &mut u).unwrap();
            cols.push(u);
        }
    }
    let mut rng = Lcg(43);
    let v: Vec<[f64; D]> = random(b, &mut rng, |_| true);
    let w: Vec<[f64; D]> = random(n, &mut rng, |_| true);
    let d0 = vec![[0.0; D]; b];
    let (jv, g, _) = both(&pts, &bnd, &d0, &o, &v, &w);
    let jv_ref: Vec<[f64; D]> = (0..n)
        .map(|i| {
            std::array::from_fn(|a| {
                (0..b * D)
                    .map(|kc| cols[kc][i][a] * v[kc / D][kc % D])
                    .sum()
            })
        })
        .collect();
    let g_ref: Vec<[f64; D]> = (0..b)
        .map(|k| std::array::from_fn(|c| dot(&cols[k * D + c], &w)))
        .collect();
    let (e1, e2) = (rel_err(&jv, &jv_ref), rel_err(&g, &g_ref));
    eprintln!("{D}D {kernel:?} rc {rc}: dense tangent {e1:.1e}, adjoint {e2:.1e}");
    assert!(
        e1 <= 1e-12 && e2 <= 1e-12,
        "{D}D {kernel:?} rc {rc}: tangent {e1:e}, adjoint {e2:e}"
    );
}

#[test]
fn tangent_and_adjoint_match_the_dense_jacobian_of_rbf_deform() {
    for rc in [0.0, 0.5] {
        dense_case::<2>(RbfKernel::Wendland { radius: 0.7 }, rc);
        dense_case::<2>(RbfKernel::ThinPlate, rc);
        dense_case::<3>(RbfKernel::Wendland { radius: 0.9 }, rc);
        dense_case::<3>(RbfKernel::ThinPlate, rc);
    }
}

/// Central differences of `rbf_deform` along `v` at `d0`, steps 10⁻²…10⁻⁷, against the
/// tangent. With every centre the map is linear: there is no `h²` term, the difference is
/// the tangent up to rounding over `h` at every step. The greedy map is piecewise linear: its
/// centres change where the ranking of the boundary errors does (here up to `h = 10⁻⁵`:
/// two nodes' errors differ by about that); wherever both `d0 ± h v` keep
/// the centres of `d0` (at least the two smallest steps), the same bound holds.
#[test]
fn tangent_matches_central_differences_of_rbf_deform() {
    let (pts, bnd) = grid::<f64, 2>(9);
    let d0 = motion(&pts, &bnd);
    let (n, b) = (pts.len(), bnd.len());
    let mut rng = Lcg(47);
    let v: Vec<[f64; 2]> = random(b, &mut rng, |_| true);
    for kernel in [RbfKernel::Wendland { radius: 0.8 }, RbfKernel::ThinPlate] {
        for greedy in [false, true] {
            let o = options(kernel, b, greedy, 0.4);
            let (mut index, mut scratch) = buffers::<f64, 2>(b, &o);
            let mut jv = vec![[0.0; 2]; n];
            let r0 =
                rbf_tangent(&pts, &bnd, &d0, &o, &mut index, &mut scratch, &v, &mut jv).unwrap();
            let centres = index[..r0.centres].to_vec();
            let (mut same, mut errs) = (0, vec![]);
            for k in 2..=7 {
                let h = 10f64.powi(-k);
                let mut at = |sign: f64| {
                    let d: Vec<[f64; 2]> = d0
                        .iter()
                        .zip(&v)
                        .map(|(a, x)| [a[0] + sign * h * x[0], a[1] + sign * h * x[1]])
                        .collect();
                    let mut u = vec![[0.0; 2]; n];
                    let r = rbf_deform(&pts, &bnd, &d, &o, &mut index, &mut scratch, &mut u);
                    let kept = index[..r.unwrap().centres] == centres[..];
                    (u, kept)
                };
                let ((p, kp), (m, km)) = (at(1.0), at(-1.0));
                let fd: Vec<[f64; 2]> = p
                    .iter()
                    .zip(&m)
                    .map(|(p, m)| [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)])
                    .collect();
                let e = rel_err(&fd, &jv);
                errs.push((h, e, kp && km));
                assert!(
                    greedy || (kp && km),
                    "{kernel:?}: every centre, always kept"
                );
                if kp && km {
                    same += 1;
                    assert!(
                        e <= 1e-13 / h,
                        "{kernel:?} greedy {greedy} h {h:e}: {errs:?}"
                    );
                }
            }
            assert!(same >= 2, "{kernel:?} greedy {greedy}: {errs:?}");
            eprintln!("{kernel:?} greedy {greedy}: (h, error, centres kept) {errs:?}");
        }
    }
}

/// Thin-plate splines reproduce affine motions: the tangent of an infinitesimal rigid motion
/// `t + ω × y` of the boundary is that rigid field at every node (3D, with the correction,
/// every centre and greedy).
#[test]
fn thin_plate_tangent_of_a_rigid_motion_is_rigid() {
    let (pts, bnd) = grid::<f64, 3>(5);
    let d0 = motion(&pts, &bnd);
    let (t, om) = ([0.3, -0.2, 0.5], [0.4, -0.7, 0.25]);
    let rigid = |p: [f64; 3]| -> [f64; 3] {
        [
            t[0] + om[1] * p[2] - om[2] * p[1],
            t[1] + om[2] * p[0] - om[0] * p[2],
            t[2] + om[0] * p[1] - om[1] * p[0],
        ]
    };
    let v: Vec<[f64; 3]> = bnd.iter().map(|&i| rigid(pts[i as usize])).collect();
    let want: Vec<[f64; 3]> = pts.iter().map(|&p| rigid(p)).collect();
    for greedy in [false, true] {
        let o = options(RbfKernel::ThinPlate, bnd.len(), greedy, 0.4);
        let (mut index, mut scratch) = buffers::<f64, 3>(bnd.len(), &o);
        let mut jv = vec![[0.0; 3]; pts.len()];
        rbf_tangent(&pts, &bnd, &d0, &o, &mut index, &mut scratch, &v, &mut jv).unwrap();
        let e = rel_err(&jv, &want);
        eprintln!("greedy {greedy}: rigid field reproduced to {e:.1e}");
        assert!(e <= 1e-12, "greedy {greedy}: {e:e}");
    }
}

/// Three fields back to back equal three single calls, bit for bit.
#[test]
fn several_fields_match_single_calls() {
    let (pts, bnd) = grid::<f64, 2>(7);
    let (n, b) = (pts.len(), bnd.len());
    let d0 = motion(&pts, &bnd);
    let o = options(RbfKernel::ThinPlate, b, true, 0.4);
    let mut rng = Lcg(53);
    let v: Vec<[f64; 2]> = random(3 * b, &mut rng, |_| true);
    let w: Vec<[f64; 2]> = random(3 * n, &mut rng, |_| true);
    let (mut index, mut scratch) = buffers::<f64, 2>(b, &o);
    let mut jv = vec![[0.0; 2]; 3 * n];
    let mut g = vec![[0.0; 2]; 3 * b];
    rbf_tangent(&pts, &bnd, &d0, &o, &mut index, &mut scratch, &v, &mut jv).unwrap();
    rbf_adjoint(&pts, &bnd, &d0, &o, &mut index, &mut scratch, &w, &mut g).unwrap();
    for f in 0..3 {
        let (one_t, one_a, _) = both(
            &pts,
            &bnd,
            &d0,
            &o,
            &v[f * b..(f + 1) * b],
            &w[f * n..(f + 1) * n],
        );
        assert_eq!(one_t, jv[f * n..(f + 1) * n]);
        assert_eq!(one_a, g[f * b..(f + 1) * b]);
    }
}

#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let (pts, bnd) = grid::<f64, 2>(6);
    let (n, b) = (pts.len(), bnd.len());
    let d0 = motion(&pts, &bnd);
    let o = options(RbfKernel::Wendland { radius: 0.8 }, b, false, 0.4);
    let (mut index, mut scratch) = buffers::<f64, 2>(b, &o);
    let mut jv = vec![[7.0; 2]; n];
    let mut g = vec![[7.0; 2]; b];
    let v = vec![[1.0; 2]; b];
    let mut w = vec![[1.0; 2]; n];
    let t = |v: &[[f64; 2]], jv: &mut [[f64; 2]], s: &mut [f64], o: &RbfOptions<f64>| {
        rbf_tangent(&pts, &bnd, &d0, o, &mut index.clone(), s, v, jv)
    };
    assert!(matches!(
        t(&v[1..], &mut jv, &mut scratch, &o),
        Err(Error::LengthMismatch { .. })
    ));
    assert!(matches!(
        t(&v, &mut jv[1..], &mut scratch, &o),
        Err(Error::LengthMismatch { .. })
    ));
    let len = scratch.len();
    assert!(matches!(
        t(&v, &mut jv, &mut scratch[..len - 1], &o),
        Err(Error::BufferTooSmall { .. })
    ));
    let bad = RbfOptions {
        tolerance: -1.0,
        ..o
    };
    assert!(matches!(
        t(&v, &mut jv, &mut scratch, &bad),
        Err(Error::InvalidParameter { .. })
    ));
    let mut vn = v.clone();
    vn[2][0] = f64::NAN;
    assert!(matches!(
        t(&vn, &mut jv, &mut scratch, &o),
        Err(Error::NonFinite { .. })
    ));
    assert!(jv.iter().all(|x| *x == [7.0; 2]));
    w[4][1] = f64::INFINITY;
    let r = rbf_adjoint(&pts, &bnd, &d0, &o, &mut index, &mut scratch, &w, &mut g);
    assert!(matches!(r, Err(Error::NonFinite { arg: "w", .. })));
    w[4][1] = 0.0;
    let r = rbf_adjoint(
        &pts,
        &bnd,
        &d0,
        &o,
        &mut index,
        &mut scratch,
        &w,
        &mut g[1..],
    );
    assert!(matches!(r, Err(Error::LengthMismatch { .. })));
    let r = rbf_adjoint(
        &pts,
        &bnd,
        &d0[1..],
        &o,
        &mut index,
        &mut scratch,
        &w,
        &mut g,
    );
    assert!(matches!(
        r,
        Err(Error::LengthMismatch { arg: "motion", .. })
    ));
    assert!(g.iter().all(|x| *x == [7.0; 2]));
}
