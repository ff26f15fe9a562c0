//! RBF interpolation (`deform_kernel::rbf`, every boundary node a centre): parity with
//! scipy's `RBFInterpolator` (thin-plate spline, degree 1) and a numpy Wendland C2 solve
//! (`ref_rbf.py` beside this file) on the same centres, exactness at the centres, affine
//! motions reproduced by thin-plate splines, Wendland's compact support, f32 against f64.

#[path = "../support/mod.rs"]
mod support;

use std::fmt::Write as _;
use std::path::Path;

use deform_kernel::rbf::{RbfKernel, RbfOptions};
use support::python::run_script;
use support::rbf::{case, cast, max_norm, pitch_motion, rotate, run, Case};

fn options(kernel: RbfKernel<f64>, b: usize) -> RbfOptions<f64> {
    RbfOptions {
        kernel,
        tolerance: 0.0,
        max_centres: b,
        correction_radius: 0.0,
    }
}

/// The reference's interpolant at every point of `case`, from `ref_rbf.py`.
fn reference<const D: usize>(
    case: &Case<D>,
    motion: &[[f64; D]],
    kernel: RbfKernel<f64>,
) -> Vec<[f64; D]> {
    let (name, radius) = match kernel {
        RbfKernel::Wendland { radius } => ("wendland", radius),
        RbfKernel::ThinPlate => ("tps", 0.0),
    };
    let nb = case.boundary.len();
    let mut text = format!("{name} {radius:e} {D} {nb} {}\n", case.points.len());
    let row = |t: &mut String, v: &[f64]| {
        for x in v {
            write!(t, "{x:e} ").unwrap();
        }
        t.push('\n');
    };
    for (&n, d) in case.boundary.iter().zip(motion) {
        let mut v = case.points[n as usize].to_vec();
        v.extend_from_slice(d);
        row(&mut text, &v);
    }
    for p in &case.points {
        row(&mut text, p);
    }
    // One file per call: tests run in parallel threads of one process.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let file = std::env::temp_dir().join(format!(
        "dk_rbf_{name}_{D}_{}_{call}.txt",
        std::process::id()
    ));
    std::fs::write(&file, text).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/rbf/ref_rbf.py");
    let out = run_script(&script, &[file.to_str().unwrap()]);
    std::fs::remove_file(&file).ok();
    out.lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            std::array::from_fn(|a| v[a])
        })
        .collect()
}

/// Largest difference relative to the largest boundary motion.
fn rel_diff<const D: usize>(a: &[[f64; D]], b: &[[f64; D]], scale: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    let d: Vec<[f64; D]> = a
        .iter()
        .zip(b)
        .map(|(x, y)| std::array::from_fn(|k| x[k] - y[k]))
        .collect();
    max_norm(&d) / scale
}

fn parity<const D: usize>(kernel: RbfKernel<f64>, n_in: usize, n_out: usize) {
    let c = case::<D>(n_in, n_out, 300);
    let motion = pitch_motion(&c, 20.0, 0.02);
    let (ours, report) = run(
        &c.points,
        &c.boundary,
        &motion,
        &options(kernel, c.boundary.len()),
    )
    .unwrap();
    assert_eq!(report.centres, c.boundary.len());
    let refs = reference(&c, &motion, kernel);
    let scale = max_norm(&motion);
    let err = rel_diff(&ours, &refs, scale);
    eprintln!("{kernel:?} D={D}: max relative difference to the reference {err:.2e}");
    assert!(err < 1e-10, "{kernel:?} D={D}: {err:e}");
    // Exact at the centres (to the conditioning of the solve).
    let at_centres: Vec<[f64; D]> = c.boundary.iter().map(|&n| ours[n as usize]).collect();
    let err = rel_diff(&at_centres, &motion, scale);
    assert!(err < 1e-11, "{kernel:?} D={D} at the centres: {err:e}");
    assert!(report.max_error / scale < 1e-11);
}

#[test]
fn thin_plate_matches_scipy_rbf_interpolator_2d() {
    parity::<2>(RbfKernel::ThinPlate, 60, 24);
}

#[test]
fn thin_plate_matches_scipy_rbf_interpolator_3d() {
    parity::<3>(RbfKernel::ThinPlate, 80, 40);
}

#[test]
fn wendland_matches_a_dense_numpy_solve_2d() {
    parity::<2>(RbfKernel::Wendland { radius: 3.0 }, 60, 24);
}

#[test]
fn wendland_matches_a_dense_numpy_solve_3d() {
    parity::<3>(RbfKernel::Wendland { radius: 4.0 }, 80, 40);
}

/// Thin-plate splines with linear terms reproduce an affine motion everywhere: the whole
/// boundary (wall and far field) turned by 50° and shifted moves every point the same way.
#[test]
fn thin_plate_reproduces_rigid_motions() {
    let c = case::<2>(60, 24, 300);
    let shift = [0.3, -0.7];
    let moved = |p: [f64; 2]| {
        let q = rotate(p, 50.0);
        [q[0] + shift[0] - p[0], q[1] + shift[1] - p[1]]
    };
    let motion: Vec<[f64; 2]> = c
        .boundary
        .iter()
        .map(|&n| moved(c.points[n as usize]))
        .collect();
    let opts = options(RbfKernel::ThinPlate, c.boundary.len());
    let (ours, _) = run(&c.points, &c.boundary, &motion, &opts).unwrap();
    let exact: Vec<[f64; 2]> = c.points.iter().map(|&p| moved(p)).collect();
    let err = rel_diff(&ours, &exact, max_norm(&motion));
    eprintln!("thin-plate rigid motion: {err:.2e}");
    assert!(err < 1e-11, "{err:e}");
}

/// Wendland C2 has no polynomial: a rigid translation of every boundary node comes out
/// exactly at the centres, within a few per cent inside a support much wider than the
/// node spacing, and exactly zero farther than the support radius from every centre.
#[test]
fn wendland_translation_is_exact_at_centres_and_vanishes_beyond_the_support() {
    let c = case::<2>(80, 0, 400);
    let motion = vec![[0.1, 0.05]; c.boundary.len()];
    let radius = 2.0;
    let opts = options(RbfKernel::Wendland { radius }, c.boundary.len());
    let (ours, report) = run(&c.points, &c.boundary, &motion, &opts).unwrap();
    assert!(report.max_error < 1e-12);
    let mut near = 0;
    for (p, d) in c.points.iter().zip(&ours) {
        let dist = c.boundary.iter().map(|&n| {
            let q = c.points[n as usize];
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        });
        let dmin = dist.fold(f64::INFINITY, f64::min);
        if dmin >= radius {
            assert_eq!(*d, [0.0, 0.0], "beyond the support at {p:?}");
        } else if dmin < 0.05 {
            near += 1;
            let rel = ((d[0] - 0.1).powi(2) + (d[1] - 0.05).powi(2)).sqrt() / 0.1118;
            assert!(rel < 0.05, "near the wall at {p:?}: {d:?}");
        }
    }
    assert!(near > 0);
}

/// f32 follows f64 to its precision (thin-plate splines and a moderate Wendland support).
#[test]
fn f32_follows_f64() {
    let c = case::<2>(40, 16, 200);
    let motion = pitch_motion(&c, 20.0, 0.02);
    for kernel in [RbfKernel::ThinPlate, RbfKernel::Wendland { radius: 1.5 }] {
        let (d64, _) = run(
            &c.points,
            &c.boundary,
            &motion,
            &options(kernel, c.boundary.len()),
        )
        .unwrap();
        let k32 = match kernel {
            RbfKernel::Wendland { radius } => RbfKernel::Wendland {
                radius: radius as f32,
            },
            RbfKernel::ThinPlate => RbfKernel::ThinPlate,
        };
        let o32 = RbfOptions {
            kernel: k32,
            tolerance: 0.0f32,
            max_centres: c.boundary.len(),
            correction_radius: 0.0,
        };
        let (d32, _) = run(
            &cast::<f32, 2>(&c.points),
            &c.boundary,
            &cast::<f32, 2>(&motion),
            &o32,
        )
        .unwrap();
        let d32: Vec<[f64; 2]> = d32.iter().map(|p| p.map(f64::from)).collect();
        let err = rel_diff(&d32, &d64, max_norm(&motion));
        eprintln!("{kernel:?}: f32 against f64 {err:.2e}");
        assert!(err < 1e-3, "{kernel:?}: {err:e}");
    }
}

/// A support small against the domain: the search grid has many cells, and its results
/// still match the dense reference (a missed neighbour would show here).
#[test]
fn wendland_small_support_matches_the_dense_reference() {
    parity::<2>(RbfKernel::Wendland { radius: 0.8 }, 60, 24);
    parity::<3>(RbfKernel::Wendland { radius: 1.2 }, 80, 40);
}
