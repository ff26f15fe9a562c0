//! The fast (tree, far-field clusters) inverse-distance propagation against the exact kernel
//! IDW and the naive `f64` reference (`idw_ref`): the stated per-point bound holds on random
//! clouds and meshgen meshes (2D, 3D, `f32`, `f64`), `θ = 0` is the exact method up to
//! summation order, uniform boundary values (translation, rigid rotation) are reproduced,
//! the tolerance is honoured, the robust path takes over at extreme scales, and bad input
//! gives typed errors with the outputs unchanged.

use deform_host_tests::idw_ref::{a_priori_bound, idw_with_spread, IdwPoint};
use deform_kernel::quaternion::{
    propagate_idw, propagate_idw_fast, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, IdwFastOptions, IdwFastReport,
};
use deform_kernel::{Error, Quat, Real};
use deform_meshgen::{extrude, naca_ogrid, AirfoilGrid};

/// A deterministic pseudo-random value in `[-1, 1)` (splitmix64).
fn rnd(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Points and the mesh nodes that are boundary nodes.
struct Case<const D: usize> {
    name: String,
    points: Vec<[f64; D]>,
    boundary: Vec<u32>,
}

/// `nb` boundary points on a wavy closed curve/surface around the origin and `nf` field
/// points scattered in the box `[-3, 3]^D` (boundary points first).
fn cloud<const D: usize>(nb: usize, nf: usize, seed: u64) -> Case<D> {
    let mut s = seed;
    let mut points = Vec::new();
    for _ in 0..nb {
        let mut v = [(); D].map(|_| rnd(&mut s));
        let l = v.iter().map(|c| c * c).sum::<f64>().sqrt().max(1e-3);
        let r = 1.0 + 0.2 * rnd(&mut s);
        for c in v.iter_mut() {
            *c *= r / l;
        }
        points.push(v);
    }
    for _ in 0..nf {
        points.push([(); D].map(|_| 3.0 * rnd(&mut s)));
    }
    Case {
        name: format!("{D}D cloud {nb}+{nf}"),
        points,
        boundary: (0..nb as u32).collect(),
    }
}

/// A meshgen NACA 2412 O-grid: wall and far field are the boundary.
fn naca2d(opts: &AirfoilGrid) -> Case<2> {
    let mesh = naca_ogrid(opts).unwrap();
    let mut boundary: Vec<u32> = Vec::new();
    for name in ["airfoil", "farfield"] {
        for &n in &mesh.marker(name).unwrap().node_list {
            if !boundary.contains(&n) {
                boundary.push(n);
            }
        }
    }
    Case {
        name: format!("NACA O-grid {} nodes", mesh.points.len()),
        points: mesh.points,
        boundary,
    }
}

/// The tiny O-grid extruded into a wing; every marker is boundary.
fn wing3d() -> Case<3> {
    let mesh = extrude(&naca_ogrid(&AirfoilGrid::tiny()).unwrap(), 2.0, 6).unwrap();
    let mut seen = vec![false; mesh.points.len()];
    let mut boundary = Vec::new();
    for m in &mesh.markers {
        for &n in &m.node_list {
            if !seen[n as usize] {
                seen[n as usize] = true;
                boundary.push(n);
            }
        }
    }
    Case {
        name: format!("extruded wing {} nodes", mesh.points.len()),
        points: mesh.points,
        boundary,
    }
}

/// Boundary values: translations that vary smoothly with position plus noise, unit
/// quaternions near a common rotation with random signs (the kernel must align them).
fn values<const D: usize>(case: &Case<D>, seed: u64) -> (Vec<[f64; D]>, Vec<Quat<f64>>) {
    let mut s = seed;
    let t = case
        .boundary
        .iter()
        .map(|&b| {
            let x = case.points[b as usize];
            [(); D].map(|_| 0.5 * x[0].sin() + 0.3 * rnd(&mut s))
        })
        .collect();
    let q = case
        .boundary
        .iter()
        .map(|_| {
            let v = [
                0.8 + 0.1 * rnd(&mut s),
                0.3 * rnd(&mut s),
                0.3 * rnd(&mut s),
                0.5 + 0.2 * rnd(&mut s),
            ];
            let v = if D == 2 { [v[0], 0.0, 0.0, v[3]] } else { v };
            let q = Quat::from_array(v).normalize().unwrap();
            if rnd(&mut s) < 0.0 {
                -q
            } else {
                q
            }
        })
        .collect();
    (t, q)
}

/// Field arrays of `T` with the boundary values in place (NaN elsewhere: the kernel must not
/// read them).
fn fields<T: Real, const D: usize>(
    case: &Case<D>,
    bt: &[[f64; D]],
    bq: &[Quat<f64>],
) -> (Vec<[T; D]>, Vec<Quat<T>>) {
    let n = case.points.len();
    let mut t = vec![[T::from_f64(f64::NAN); D]; n];
    let nan = T::from_f64(f64::NAN);
    let mut q = vec![Quat::new(nan, nan, nan, nan); n];
    for (k, &i) in case.boundary.iter().enumerate() {
        t[i as usize] = bt[k].map(T::from_f64);
        let a = bq[k].to_array().map(T::from_f64);
        q[i as usize] = Quat::from_array(a);
    }
    (t, q)
}

/// Output of one fast run.
struct Fast<T, const D: usize> {
    t: Vec<[T; D]>,
    q: Vec<Quat<T>>,
    eta: Vec<T>,
    report: IdwFastReport<T>,
}

fn run_fast<T: Real, const D: usize>(
    case: &Case<D>,
    bt: &[[f64; D]],
    bq: &[Quat<f64>],
    p: f64,
    options: IdwFastOptions<T>,
) -> Fast<T, D> {
    let pts: Vec<[T; D]> = case.points.iter().map(|x| x.map(T::from_f64)).collect();
    let (mut t, mut q) = fields::<T, D>(case, bt, bq);
    let b = case.boundary.len();
    let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
    let mut scratch = vec![T::ZERO; propagate_idw_fast_scratch_len::<D>(b)];
    let mut eta = vec![T::from_f64(-1.0); pts.len()];
    let report = propagate_idw_fast(
        &pts,
        &case.boundary,
        T::from_f64(p),
        &options,
        &mut index,
        &mut scratch,
        &mut t,
        &mut q,
        Some(&mut eta),
    )
    .unwrap();
    Fast { t, q, eta, report }
}

fn run_exact<T: Real, const D: usize>(
    case: &Case<D>,
    bt: &[[f64; D]],
    bq: &[Quat<f64>],
    p: f64,
) -> (Vec<[T; D]>, Vec<Quat<T>>) {
    let pts: Vec<[T; D]> = case.points.iter().map(|x| x.map(T::from_f64)).collect();
    let (mut t, mut q) = fields::<T, D>(case, bt, bq);
    propagate_idw(&pts, &case.boundary, T::from_f64(p), &mut t, &mut q).unwrap();
    (t, q)
}

/// The reference, computed in `f64` from the values as `T` rounds them.
fn reference<T: Real, const D: usize>(
    case: &Case<D>,
    bt: &[[f64; D]],
    bq: &[Quat<f64>],
    p: f64,
) -> Vec<IdwPoint> {
    let r = |x: f64| T::from_f64(x).to_f64();
    let pts: Vec<Vec<f64>> = case.points.iter().map(|x| x.map(r).to_vec()).collect();
    let b: Vec<usize> = case.boundary.iter().map(|&i| i as usize).collect();
    let d: Vec<Vec<f64>> = bt.iter().map(|x| x.map(r).to_vec()).collect();
    let q: Vec<[f64; 4]> = bq.iter().map(|x| x.to_array().map(r)).collect();
    idw_with_spread(&pts, &b, &d, &q, p)
}

fn vdist<T: Real, const D: usize>(a: [T; D], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x.to_f64() - y) * (x.to_f64() - y))
        .sum::<f64>()
        .sqrt()
}

/// `|a − b|` for quaternions up to sign.
fn qdist<T: Real>(a: Quat<T>, b: [f64; 4]) -> f64 {
    let a = a.to_array().map(|c| c.to_f64());
    let d = |s: f64| {
        (0..4)
            .map(|c| (s * a[c] - b[c]) * (s * a[c] - b[c]))
            .sum::<f64>()
            .sqrt()
    };
    d(1.0).min(d(-1.0))
}

/// Rounding allowance: `4 B ε` times the value scale (the exact method's own order).
fn slack<T: Real>(b: usize, scale: f64) -> f64 {
    4.0 * b as f64 * T::EPSILON.to_f64() * scale
}

/// Checks the bound at every field point against the reference and the exact kernel, and
/// returns (max error / bound scale, max η, max error).
fn check_bound<T: Real, const D: usize>(case: &Case<D>, p: f64, theta: f64) -> (f64, f64, f64) {
    let (bt, bq) = values(case, 17);
    let b = case.boundary.len();
    let options = IdwFastOptions {
        theta: T::from_f64(theta),
        tolerance: T::INFINITY,
    };
    let fast = run_fast::<T, D>(case, &bt, &bq, p, options);
    let (et, eq) = run_exact::<T, D>(case, &bt, &bq, p);
    let refs = reference::<T, D>(case, &bt, &bq, p);
    let tscale = bt
        .iter()
        .flat_map(|v| v.iter())
        .fold(0.0f64, |m, c| m.max(c.abs()))
        * (D as f64).sqrt();
    let sl_t = slack::<T>(b, tscale);
    let sl_q = slack::<T>(b, 2.0);
    let prior = a_priori_bound(theta, p);
    let (mut worst_ratio, mut max_eta, mut max_err) = (0.0f64, 0.0f64, 0.0f64);
    for (i, r) in refs.iter().enumerate() {
        if r.boundary {
            // Boundary entries untouched, bounds entry untouched.
            assert_eq!(fast.eta[i].to_f64(), -1.0);
            continue;
        }
        let eta = fast.eta[i].to_f64();
        assert!(
            (0.0..=prior * (1.0 + 1e-6)).contains(&eta),
            "{}: eta {eta} a priori {prior}",
            case.name
        );
        let err = vdist(fast.t[i], &r.t);
        let allowed = eta * r.spread_t;
        assert!(
            err <= allowed + sl_t,
            "{} θ {theta} p {p} point {i}: |Δ̃ − Δ| = {err:e} > η {eta:e} · spread {:e}",
            case.name,
            r.spread_t
        );
        // Against the exact kernel method too (its own rounding added).
        let err_k = vdist(fast.t[i], &et[i].map(|c| c.to_f64()));
        assert!(err_k <= allowed + 2.0 * sl_t, "{} point {i}", case.name);
        // Rotations: the normalised mean moves by at most 2 η spread / |mean|.
        let l = r.q_mean.iter().map(|c| c * c).sum::<f64>().sqrt();
        let qerr = qdist(fast.q[i], r.q);
        assert!(
            qerr <= 2.0 * eta * r.spread_q / l + sl_q / l,
            "{} point {i}: rotation error {qerr:e}, η {eta:e}",
            case.name
        );
        let qe_k = eq[i].to_array().map(|c| c.to_f64());
        assert!(qdist(fast.q[i], qe_k) <= 2.0 * eta * r.spread_q / l + 2.0 * sl_q / l);
        if r.spread_t > 0.0 {
            worst_ratio = worst_ratio.max(err / r.spread_t);
        }
        max_eta = max_eta.max(eta);
        max_err = max_err.max(err);
    }
    assert_eq!(fast.report.max_bound.to_f64(), max_eta, "{}", case.name);
    println!(
        "{} {} θ {theta} p {p}: max |err|/spread {worst_ratio:.2e}, max η {max_eta:.2e}, \
         clusters {}, direct {} (exact: {})",
        case.name,
        core::any::type_name::<T>(),
        fast.report.clusters,
        fast.report.direct,
        (case.points.len() - b) * b
    );
    (worst_ratio, max_eta, max_err)
}

#[test]
fn bound_holds_on_random_clouds() {
    for p in [2.0, 3.5] {
        for theta in [0.3, 0.6, 0.9] {
            let (_, eta2, err2) = check_bound::<f64, 2>(&cloud::<2>(300, 400, 1), p, theta);
            let (_, eta3, err3) = check_bound::<f64, 3>(&cloud::<3>(400, 300, 2), p, theta);
            check_bound::<f32, 2>(&cloud::<2>(300, 400, 3), p, theta);
            check_bound::<f32, 3>(&cloud::<3>(400, 300, 4), p, theta);
            // The approximation is in use (else the test could not fail).
            assert!(eta2 > 0.0 && eta3 > 0.0 && err2 > 1e-12 && err3 > 1e-12);
        }
    }
}

#[test]
fn bound_holds_on_meshgen_meshes() {
    for theta in [0.3, 0.7] {
        for p in [2.0, 3.0] {
            let (_, eta, _) = check_bound::<f64, 2>(&naca2d(&AirfoilGrid::default()), p, theta);
            assert!(eta > 0.0);
            check_bound::<f32, 2>(&naca2d(&AirfoilGrid::tiny()), p, theta);
            let (_, eta, _) = check_bound::<f64, 3>(&wing3d(), p, theta);
            assert!(eta > 0.0);
            check_bound::<f32, 3>(&wing3d(), p, theta);
        }
    }
}

/// `θ = 0`: no cluster, every boundary node weighted individually; the result is the exact
/// method's up to summation order (tree order instead of `boundary` order): within `4 B ε`
/// of the value scale.
fn theta_zero<T: Real, const D: usize>(case: &Case<D>, p: f64) {
    let (bt, bq) = values(case, 5);
    let b = case.boundary.len();
    let options = IdwFastOptions {
        theta: T::ZERO,
        tolerance: T::ZERO,
    };
    let fast = run_fast::<T, D>(case, &bt, &bq, p, options);
    let (et, eq) = run_exact::<T, D>(case, &bt, &bq, p);
    assert_eq!(fast.report.clusters, 0);
    assert_eq!(fast.report.refined, 0);
    assert_eq!(fast.report.max_bound.to_f64(), 0.0);
    let field = case.points.len() - b;
    assert_eq!(fast.report.direct, (field * b) as u64, "{}", case.name);
    let tol = slack::<T>(b, 1.0 + 0.3 * 2.0);
    let mut worst = 0.0f64;
    let mut bitwise = 0;
    for i in 0..case.points.len() {
        let d = vdist(fast.t[i], &et[i].map(|c| c.to_f64()));
        let dq = qdist(fast.q[i], eq[i].to_array().map(|c| c.to_f64()));
        worst = worst.max(d).max(dq);
        bitwise += usize::from(
            fast.t[i].map(|c| c.to_bits_u64()) == et[i].map(|c| c.to_bits_u64())
                && fast.q[i] == eq[i],
        );
    }
    println!(
        "{} {} θ = 0 p {p}: max diff to exact {worst:.2e} (allowed {tol:.2e}), {bitwise} of {} \
         points bitwise equal",
        case.name,
        core::any::type_name::<T>(),
        case.points.len()
    );
    assert!(worst <= tol, "{worst} > {tol}");
}

#[test]
fn theta_zero_is_the_exact_method() {
    for p in [2.0, 2.7] {
        theta_zero::<f64, 2>(&cloud::<2>(200, 300, 9), p);
        theta_zero::<f64, 3>(&cloud::<3>(200, 300, 10), p);
        theta_zero::<f32, 2>(&cloud::<2>(200, 300, 11), p);
        theta_zero::<f32, 3>(&wing3d(), p);
        theta_zero::<f64, 2>(&naca2d(&AirfoilGrid::tiny()), p);
    }
}

/// A uniform boundary translation and one rigid rotation (with random quaternion signs):
/// every field point gets exactly that translation and rotation, to rounding, while clusters
/// are in use.
fn uniform<T: Real, const D: usize>(case: &Case<D>, theta: f64) {
    let b = case.boundary.len();
    let mut s = 3u64;
    let shift = [(); D].map(|_| 10.0 * rnd(&mut s));
    let q0 = Quat::from_array([0.9, 0.1, -0.3, 0.2]).normalize().unwrap();
    let q0 = if D == 2 {
        Quat::from_array([0.9, 0.0, 0.0, 0.4]).normalize().unwrap()
    } else {
        q0
    };
    let bt = vec![shift; b];
    let bq: Vec<Quat<f64>> = (0..b)
        .map(|_| if rnd(&mut s) < 0.0 { -q0 } else { q0 })
        .collect();
    let options = IdwFastOptions {
        theta: T::from_f64(theta),
        tolerance: T::INFINITY,
    };
    let fast = run_fast::<T, D>(case, &bt, &bq, 2.0, options);
    assert!(fast.report.clusters > 0, "{}", case.name);
    let shift_t: Vec<f64> = shift.iter().map(|&c| T::from_f64(c).to_f64()).collect();
    let scale = shift_t.iter().map(|c| c * c).sum::<f64>().sqrt();
    let q0_t = q0.to_array().map(|c| T::from_f64(c).to_f64());
    let mut worst_t = 0.0f64;
    let mut worst_q = 0.0f64;
    for i in 0..case.points.len() {
        if case.boundary.contains(&(i as u32)) {
            continue;
        }
        worst_t = worst_t.max(vdist(fast.t[i], &shift_t));
        worst_q = worst_q.max(qdist(fast.q[i], q0_t));
    }
    let eps = T::EPSILON.to_f64();
    println!(
        "{} {}: uniform translation error {:.1} ε·|Δ|, rotation {:.1} ε",
        case.name,
        core::any::type_name::<T>(),
        worst_t / (eps * scale),
        worst_q / eps
    );
    assert!(worst_t <= 64.0 * eps * scale, "{worst_t}");
    assert!(worst_q <= 64.0 * eps, "{worst_q}");
}

#[test]
fn uniform_motion_is_reproduced() {
    for theta in [0.5, 0.9] {
        uniform::<f64, 2>(&cloud::<2>(300, 300, 21), theta);
        uniform::<f64, 3>(&cloud::<3>(300, 300, 22), theta);
        uniform::<f32, 2>(&naca2d(&AirfoilGrid::tiny()), theta);
        uniform::<f32, 3>(&wing3d(), theta);
        uniform::<f64, 3>(&wing3d(), theta);
    }
}

#[test]
fn tolerance_is_honoured() {
    for tol in [0.1, 0.01, 0.001] {
        let case = cloud::<3>(500, 400, 31);
        let (bt, bq) = values(&case, 8);
        let options = IdwFastOptions {
            theta: 0.8,
            tolerance: tol,
        };
        let fast = run_fast::<f64, 3>(&case, &bt, &bq, 2.0, options);
        let refs = reference::<f64, 3>(&case, &bt, &bq, 2.0);
        assert!(fast.report.max_bound <= tol);
        assert!(fast.report.refined > 0, "tolerance {tol} never bit");
        for (i, r) in refs.iter().enumerate() {
            if !r.boundary {
                assert!(fast.eta[i] <= tol);
                let err = vdist(fast.t[i], &r.t);
                assert!(err <= fast.eta[i] * r.spread_t + slack::<f64>(500, 2.0));
            }
        }
        println!(
            "tolerance {tol}: max η {:.2e}, refined {} points, clusters {}, direct {}",
            fast.report.max_bound, fast.report.refined, fast.report.clusters, fast.report.direct
        );
    }
}

/// Coordinates near 1e155 (squared distances overflow) or 1e-160 (underflow): the points go
/// through the exact method's robust path and equal it bit for bit.
#[test]
fn extreme_scales_use_the_robust_path() {
    for scale in [1e155, 1e-160] {
        let mut case = cloud::<3>(100, 80, 41);
        for p in case.points.iter_mut() {
            *p = p.map(|c| c * scale);
        }
        let (bt, bq) = values(&case, 9);
        let options = IdwFastOptions {
            theta: 0.5,
            tolerance: f64::INFINITY,
        };
        let fast = run_fast::<f64, 3>(&case, &bt, &bq, 2.0, options);
        let (et, eq) = run_exact::<f64, 3>(&case, &bt, &bq, 2.0);
        assert_eq!(fast.report.robust, 80, "scale {scale}");
        for i in 0..case.points.len() {
            assert!(fast.t[i].iter().all(|c| c.is_finite()));
            assert_eq!(fast.t[i].map(f64::to_bits), et[i].map(f64::to_bits));
            assert_eq!(fast.q[i], eq[i]);
        }
    }
}

/// A field point on top of a boundary node copies it (the first in `boundary` order), as the
/// exact method does; a boundary node listed twice is still a boundary node.
#[test]
fn coincident_points_copy_the_first_boundary_node() {
    let mut case = cloud::<2>(50, 20, 51);
    // Field point 60 sits on boundary nodes 7 and 3 (both at the same place).
    case.points[3] = case.points[7];
    case.points[60] = case.points[7];
    case.boundary.push(7);
    let (bt, bq) = values(&case, 2);
    let fast = run_fast::<f64, 2>(&case, &bt, &bq, 2.0, IdwFastOptions::default());
    let (et, eq) = run_exact::<f64, 2>(&case, &bt, &bq, 2.0);
    assert_eq!(fast.t[60], bt[3]);
    assert_eq!(fast.t[60], et[60]);
    assert_eq!(fast.q[60], eq[60]);
    assert_eq!(fast.eta[60], 0.0);
}

#[test]
fn bad_input_is_a_typed_error_and_outputs_are_unchanged() {
    let case = cloud::<3>(40, 30, 61);
    let (bt, bq) = values(&case, 3);
    let pts = case.points.clone();
    let n = pts.len();
    let b = case.boundary.len();
    let (t0, q0) = fields::<f64, 3>(&case, &bt, &bq);
    let ok = IdwFastOptions::<f64>::default();
    type Mutator = fn(&mut Setup);
    struct Setup {
        pts: Vec<[f64; 3]>,
        boundary: Vec<u32>,
        p: f64,
        options: IdwFastOptions<f64>,
        index: usize,
        scratch: usize,
        t: Vec<[f64; 3]>,
        q: Vec<Quat<f64>>,
        bounds: Option<usize>,
    }
    let cases: Vec<(&str, Mutator, Error)> = vec![
        (
            "empty boundary",
            |s| s.boundary.clear(),
            Error::InvalidParameter {
                arg: "boundary",
                reason: "must not be empty",
            },
        ),
        (
            "theta 1",
            |s| s.options.theta = 1.0,
            Error::InvalidParameter {
                arg: "options.theta",
                reason: "must be in [0, 1)",
            },
        ),
        (
            "theta NaN",
            |s| s.options.theta = f64::NAN,
            Error::InvalidParameter {
                arg: "options.theta",
                reason: "must be in [0, 1)",
            },
        ),
        (
            "theta negative",
            |s| s.options.theta = -0.1,
            Error::InvalidParameter {
                arg: "options.theta",
                reason: "must be in [0, 1)",
            },
        ),
        (
            "tolerance negative",
            |s| s.options.tolerance = -1e-3,
            Error::InvalidParameter {
                arg: "options.tolerance",
                reason: "must be non-negative (+inf for no refinement)",
            },
        ),
        (
            "tolerance NaN",
            |s| s.options.tolerance = f64::NAN,
            Error::InvalidParameter {
                arg: "options.tolerance",
                reason: "must be non-negative (+inf for no refinement)",
            },
        ),
        (
            "exponent 0",
            |s| s.p = 0.0,
            Error::InvalidParameter {
                arg: "exponent",
                reason: "must be finite and positive",
            },
        ),
        (
            "index short",
            |s| s.index -= 1,
            Error::BufferTooSmall {
                arg: "index",
                needed: 40,
                actual: 39,
            },
        ),
        (
            "scratch short",
            |s| s.scratch -= 1,
            Error::BufferTooSmall {
                arg: "scratch",
                needed: propagate_idw_fast_scratch_len::<3>(40),
                actual: propagate_idw_fast_scratch_len::<3>(40) - 1,
            },
        ),
        (
            "bounds length",
            |s| s.bounds = Some(69),
            Error::LengthMismatch {
                arg: "bounds",
                expected: 70,
                actual: 69,
            },
        ),
        (
            "translations length",
            |s| {
                s.t.pop();
            },
            Error::LengthMismatch {
                arg: "translations",
                expected: 70,
                actual: 69,
            },
        ),
        (
            "NaN point",
            |s| s.pts[55][1] = f64::NAN,
            Error::NonFinite {
                arg: "points",
                position: 55,
            },
        ),
        (
            "boundary index",
            |s| s.boundary[5] = 70,
            Error::IndexOutOfRange {
                arg: "boundary",
                position: 5,
                index: 70,
                bound: 70,
            },
        ),
        (
            "boundary translation NaN",
            |s| s.t[12][0] = f64::INFINITY,
            Error::NonFinite {
                arg: "translations",
                position: 12,
            },
        ),
        (
            "zero rotation",
            |s| s.q[9] = Quat::new(0.0, 0.0, 0.0, 0.0),
            Error::ZeroLength {
                arg: "rotations",
                position: 9,
            },
        ),
    ];
    for (label, mutate, expected) in cases {
        let mut s = Setup {
            pts: pts.clone(),
            boundary: case.boundary.clone(),
            p: 2.0,
            options: ok,
            index: propagate_idw_fast_index_len(b),
            scratch: propagate_idw_fast_scratch_len::<3>(b),
            t: t0.clone(),
            q: q0.clone(),
            bounds: Some(n),
        };
        mutate(&mut s);
        let (t_before, q_before) = (s.t.clone(), s.q.clone());
        let mut index = vec![0u32; s.index];
        let mut scratch = vec![0.0; s.scratch];
        let mut bounds = s.bounds.map(|l| vec![7.0; l]);
        let r = propagate_idw_fast(
            &s.pts,
            &s.boundary,
            s.p,
            &s.options,
            &mut index,
            &mut scratch,
            &mut s.t,
            &mut s.q,
            bounds.as_deref_mut(),
        );
        assert_eq!(r, Err(expected), "{label}");
        let same_t =
            s.t.iter()
                .zip(&t_before)
                .all(|(a, b)| a.map(f64::to_bits) == b.map(f64::to_bits));
        let same_q =
            s.q.iter()
                .zip(&q_before)
                .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits));
        assert!(same_t && same_q, "{label}: outputs changed");
        if let Some(bd) = bounds {
            assert!(bd.iter().all(|&v| v == 7.0), "{label}: bounds changed");
        }
    }
}

/// The same input twice gives the same bits (fixed build and traversal order).
#[test]
fn deterministic() {
    let case = cloud::<3>(300, 200, 71);
    let (bt, bq) = values(&case, 4);
    let a = run_fast::<f64, 3>(&case, &bt, &bq, 2.5, IdwFastOptions::default());
    let b = run_fast::<f64, 3>(&case, &bt, &bq, 2.5, IdwFastOptions::default());
    for i in 0..case.points.len() {
        assert_eq!(a.t[i].map(f64::to_bits), b.t[i].map(f64::to_bits));
        assert_eq!(
            a.q[i].to_array().map(f64::to_bits),
            b.q[i].to_array().map(f64::to_bits)
        );
        assert_eq!(a.eta[i].to_bits(), b.eta[i].to_bits());
    }
    assert_eq!(a.report, b.report);
}

/// The viscous NACA 2412 O-grid (first layer 1e-5 chords) pitched about the quarter chord
/// by the whole quaternion pipeline, propagated exactly and fast: the fast field inverts or
/// folds no cell the exact one does not, and keeps the boundary layer turning rigidly.
#[test]
fn fast_idw_keeps_the_naca_boundary_layer() {
    use deform_kernel::quality::{compare, wall_angle_scratch_len, Wall};
    use deform_kernel::quaternion::{
        deform_idw, deform_idw_scratch_len, update_points, BoundaryMotion, RotationSource,
    };
    use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph};

    let mesh = naca_ogrid(&AirfoilGrid::viscous()).unwrap();
    let n = mesh.points.len();
    let cells = mesh.cells().unwrap();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; graph_from_cells_len(&cells, false)];
    let used = graph_from_cells(&cells, false, &mut offsets, &mut targets).unwrap();
    let graph = Graph::new(&offsets, &targets[..used]).unwrap();
    let wall = Wall::new(mesh.marker("airfoil").unwrap().cells(n).unwrap(), graph).unwrap();
    // Boundary: airfoil then far field, elements in boundary numbering.
    let mut local = vec![u32::MAX; n];
    let (mut nodes, mut el_off, mut el, mut kinds) = (Vec::new(), vec![0u32], Vec::new(), vec![]);
    let mut airfoil = 0;
    for name in ["airfoil", "farfield"] {
        let m = mesh.marker(name).unwrap();
        for &i in &m.node_list {
            local[i as usize] = nodes.len() as u32;
            nodes.push(i);
        }
        if name == "airfoil" {
            airfoil = nodes.len();
        }
        for e in 0..m.kinds.len() {
            for &i in &m.nodes[m.offsets[e] as usize..m.offsets[e + 1] as usize] {
                el.push(local[i as usize]);
            }
            kinds.push(m.kinds[e]);
            el_off.push(el.len() as u32);
        }
    }
    let elements = Cells::new(nodes.len(), &el_off, &el, &kinds).unwrap();
    let qc = AirfoilGrid::quarter_chord();
    let measure = |out: &[[f64; 2]]| {
        let mut s = vec![[0.0; 2]; wall_angle_scratch_len(n)];
        let q = compare(&cells, &mesh.points, out, Some(&wall), &mut s).unwrap();
        (
            q.inverted_cells,
            q.folded_cells,
            q.min_measure_ratio,
            q.wall.map_or(f64::NAN, |w| w.max_change.to_degrees()),
        )
    };
    for degrees in [10.0f64, 25.0, 50.0] {
        let (s, c) = degrees.to_radians().sin_cos();
        let deformed: Vec<[f64; 2]> = nodes
            .iter()
            .enumerate()
            .map(|(k, &i)| {
                let p = mesh.points[i as usize];
                if k < airfoil {
                    let (dx, dy) = (p[0] - qc[0], p[1] - qc[1]);
                    [qc[0] + c * dx - s * dy, qc[1] + s * dx + c * dy]
                } else {
                    p
                }
            })
            .collect();
        let motion = BoundaryMotion {
            nodes: &nodes,
            deformed: &deformed,
            elements: Some(elements),
            rotations: RotationSource::Shape,
            origin: None,
        };
        let mut t = vec![[0.0; 2]; n];
        let mut q = vec![Quat::identity(); n];
        let mut out = vec![[0.0; 2]; n];
        let mut scratch = vec![0.0; deform_idw_scratch_len::<2>(n, nodes.len())];
        let origin = deform_idw(
            &mesh.points,
            &motion,
            2.0,
            &mut t,
            &mut q,
            &mut scratch,
            &mut out,
        )
        .unwrap();
        let exact = measure(&out);
        println!("{degrees}° exact: inverted, folded, min ratio, wall-angle change {exact:?}");
        for (theta, tol) in [(0.3, f64::INFINITY), (0.5, f64::INFINITY), (0.5, 0.1)] {
            let (mut tf, mut qf) = (t.clone(), q.clone());
            let b = nodes.len();
            let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
            let mut sc = vec![0.0; propagate_idw_fast_scratch_len::<2>(b)];
            let options = IdwFastOptions {
                theta,
                tolerance: tol,
            };
            propagate_idw_fast(
                &mesh.points,
                &nodes,
                2.0,
                &options,
                &mut index,
                &mut sc,
                &mut tf,
                &mut qf,
                None,
            )
            .unwrap();
            let mut outf = vec![[0.0; 2]; n];
            update_points(origin, &mesh.points, &tf, &qf, &nodes, &deformed, &mut outf).unwrap();
            let fast = measure(&outf);
            println!("{degrees}° fast θ {theta} τ {tol}: {fast:?}");
            assert!(
                fast.0 <= exact.0 && fast.1 <= exact.1,
                "{degrees}° θ {theta}"
            );
            assert!(fast.3 <= exact.3 + 0.05, "{degrees}° θ {theta}: wall angle");
        }
    }
}

/// The one-call pipeline `deform_idw_fast`: with `θ = 0` it equals `deform_idw` to rounding
/// (boundary nodes bit for bit); at `θ = 0.5` it stays close; a bad `θ` or a short tree
/// buffer is a typed error with `out` unchanged.
#[test]
fn deform_idw_fast_pipeline() {
    use deform_kernel::quaternion::{
        deform_idw, deform_idw_fast, deform_idw_scratch_len, BoundaryMotion, RotationSource,
    };
    let case = naca2d(&AirfoilGrid::tiny());
    let n = case.points.len();
    let b = case.boundary.len();
    let deformed: Vec<[f64; 2]> = case
        .boundary
        .iter()
        .map(|&i| {
            let p = case.points[i as usize];
            if p[0].hypot(p[1]) < 2.0 {
                [p[0] + 0.02 * p[1], p[1] + 0.05 * p[0]]
            } else {
                p
            }
        })
        .collect();
    let q = Quat::from_rotation_z(0.05);
    let motion = BoundaryMotion {
        nodes: &case.boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::Rigid(q),
        origin: None,
    };
    let (mut t, mut r) = (vec![[0.0; 2]; n], vec![Quat::identity(); n]);
    let mut s = vec![0.0; deform_idw_scratch_len::<2>(n, b)];
    let mut exact = vec![[0.0; 2]; n];
    deform_idw(
        &case.points,
        &motion,
        2.0,
        &mut t,
        &mut r,
        &mut s,
        &mut exact,
    )
    .unwrap();
    let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
    let mut tree = vec![0.0; propagate_idw_fast_scratch_len::<2>(b)];
    for (theta, tol) in [(0.0, 1e-13), (0.5, 1e-2)] {
        let mut out = vec![[f64::NAN; 2]; n];
        let options = IdwFastOptions {
            theta,
            tolerance: 0.1,
        };
        let (_, report) = deform_idw_fast(
            &case.points,
            &motion,
            2.0,
            &options,
            &mut t,
            &mut r,
            &mut s,
            &mut index,
            &mut tree,
            &mut out,
        )
        .unwrap();
        let worst = (0..n)
            .map(|i| vdist(out[i], &exact[i]))
            .fold(0.0f64, f64::max);
        println!("deform_idw_fast θ {theta}: max diff to deform_idw {worst:.2e}, {report:?}");
        assert!(worst <= tol, "θ {theta}: {worst}");
        for (k, &i) in case.boundary.iter().enumerate() {
            assert_eq!(
                out[i as usize].map(f64::to_bits),
                deformed[k].map(f64::to_bits)
            );
        }
    }
    let mut out = vec![[7.0; 2]; n];
    let bad = IdwFastOptions {
        theta: 1.5,
        tolerance: 0.1,
    };
    let e = deform_idw_fast(
        &case.points,
        &motion,
        2.0,
        &bad,
        &mut t,
        &mut r,
        &mut s,
        &mut index,
        &mut tree,
        &mut out,
    );
    assert!(matches!(
        e,
        Err(Error::InvalidParameter {
            arg: "options.theta",
            ..
        })
    ));
    let e = deform_idw_fast(
        &case.points,
        &motion,
        2.0,
        &IdwFastOptions::default(),
        &mut t,
        &mut r,
        &mut s,
        &mut index,
        &mut tree[..1],
        &mut out,
    );
    assert!(matches!(e, Err(Error::BufferTooSmall { arg: "tree", .. })));
    assert!(out.iter().all(|p| *p == [7.0, 7.0]));
}
