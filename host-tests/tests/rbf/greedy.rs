//! Greedy centre selection and the wall correction of `deform_kernel::rbf`: the tolerance
//! and the budget are kept, the reduced interpolant leaves a boundary error that the
//! correction removes (the wall written exactly, the volume changed only within the
//! correction radius and by at most that error), the search grid gives the brute-force bits,
//! and bad input is a typed error that leaves the output untouched.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::Error;
use support::rbf::{case, max_norm, pitch_motion, run};

fn greedy(kernel: RbfKernel<f64>, tolerance: f64, max_centres: usize, rc: f64) -> RbfOptions<f64> {
    RbfOptions {
        kernel,
        tolerance,
        max_centres,
        correction_radius: rc,
    }
}

fn dist<const D: usize>(a: [f64; D], b: [f64; D]) -> f64 {
    a.iter()
        .zip(&b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

fn check_reduction<const D: usize>(kernel: RbfKernel<f64>) {
    let c = case::<D>(400, 60, 600);
    let motion = pitch_motion(&c, 50.0, 0.0);
    let b = c.boundary.len();
    let tol = 1e-3 * max_norm(&motion);
    let (raw, report) = run(
        &c.points,
        &c.boundary,
        &motion,
        &greedy(kernel, tol, b, 0.0),
    )
    .unwrap();
    eprintln!(
        "{kernel:?} D={D}: {} of {b} centres, max error {:.2e} (tol {tol:.2e})",
        report.centres, report.max_error
    );
    assert!(report.centres < b / 2, "{} centres", report.centres);
    assert!(report.max_error <= tol && report.max_error > 0.0);
    // The raw interpolant misses the wall by the reported error.
    let wall_err = c
        .boundary
        .iter()
        .zip(&motion)
        .map(|(&n, d)| dist(raw[n as usize], *d))
        .fold(0.0, f64::max);
    assert_eq!(wall_err.to_bits(), report.max_error.to_bits());
    // A budget stops the selection.
    let (_, capped) = run(
        &c.points,
        &c.boundary,
        &motion,
        &greedy(kernel, 0.0, 12, 0.0),
    )
    .unwrap();
    assert_eq!(capped.centres, 12);
    assert!(capped.max_error > report.max_error);

    // With the correction the wall is exact and the volume changes only within its radius.
    let rc = 0.5;
    let (fixed, corrected) =
        run(&c.points, &c.boundary, &motion, &greedy(kernel, tol, b, rc)).unwrap();
    assert_eq!(corrected, report);
    for (&n, d) in c.boundary.iter().zip(&motion) {
        assert_eq!(fixed[n as usize], *d, "wall node {n}");
    }
    let mut changed = 0;
    for (i, p) in c.points.iter().enumerate().skip(b) {
        let dmin = c
            .boundary
            .iter()
            .map(|&n| dist(*p, c.points[n as usize]))
            .fold(f64::INFINITY, f64::min);
        let delta = dist(fixed[i], raw[i]);
        if dmin >= rc {
            assert_eq!(fixed[i], raw[i], "point {i} beyond the correction radius");
        } else {
            changed += usize::from(delta > 0.0);
            assert!(
                delta <= report.max_error * (1.0 + 1e-12),
                "point {i}: {delta:e}"
            );
        }
    }
    assert!(changed > 0);
}

#[test]
fn greedy_wendland_keeps_the_tolerance_and_the_correction_makes_the_wall_exact_2d() {
    check_reduction::<2>(RbfKernel::Wendland { radius: 20.0 });
}

#[test]
fn greedy_thin_plate_keeps_the_tolerance_and_the_correction_makes_the_wall_exact_2d() {
    check_reduction::<2>(RbfKernel::ThinPlate);
}

#[test]
fn greedy_wendland_3d() {
    check_reduction::<3>(RbfKernel::Wendland { radius: 3.0 });
}

/// Near the wall the corrected field is continuous: a point at distance δ from a wall node
/// moves within O(δ) of that node's prescribed motion (the raw reduced field misses it by
/// the greedy error).
#[test]
fn the_corrected_field_meets_the_wall_continuously() {
    let mut c = case::<2>(400, 60, 0);
    let motion = pitch_motion(&c, 50.0, 0.0);
    let b = c.boundary.len();
    // Points just off each wall node, along the outward radial direction.
    for k in 0..c.inner {
        let p = c.points[k];
        let r = [p[0] - 0.5, p[1]];
        let l = (r[0] * r[0] + r[1] * r[1]).sqrt();
        c.points
            .push([p[0] + 1e-6 * r[0] / l, p[1] + 1e-6 * r[1] / l]);
    }
    let tol = 1e-3 * max_norm(&motion);
    let opts = |rc| greedy(RbfKernel::Wendland { radius: 20.0 }, tol, b, rc);
    let (fixed, _) = run(&c.points, &c.boundary, &motion, &opts(0.5)).unwrap();
    let (raw, report) = run(&c.points, &c.boundary, &motion, &opts(0.0)).unwrap();
    let gap = |d: &[[f64; 2]]| {
        (0..c.inner)
            .map(|k| dist(d[b + k], motion[k]))
            .fold(0.0, f64::max)
    };
    eprintln!(
        "off-wall gap: raw {:.2e}, corrected {:.2e}",
        gap(&raw),
        gap(&fixed)
    );
    assert!(gap(&raw) > 0.25 * report.max_error);
    // The prescribed motion itself varies by δ |R − I| = 1e-6 · 2 sin 25° over that step.
    assert!(gap(&fixed) < 1e-6);
}

/// Bad input: a typed error, the output untouched.
#[test]
fn bad_input_is_a_typed_error_and_writes_nothing() {
    let c = case::<2>(20, 8, 10);
    let motion = pitch_motion(&c, 10.0, 0.0);
    let good = greedy(RbfKernel::Wendland { radius: 2.0 }, 0.0, 28, 0.5);
    let n = c.points.len();
    let call = |points: &[[f64; 2]],
                boundary: &[u32],
                motion: &[[f64; 2]],
                o: &RbfOptions<f64>,
                short: usize| {
        let mut index =
            vec![0u32; rbf_index_len::<f64, 2>(boundary.len(), o).saturating_sub(short)];
        let mut scratch = vec![0.0; rbf_scratch_len::<f64, 2>(boundary.len(), o).min(1 << 20)];
        let mut out = vec![[7.0, -7.0]; n];
        let r = rbf_deform(
            points,
            boundary,
            motion,
            o,
            &mut index,
            &mut scratch,
            &mut out,
        );
        assert!(
            out.iter().all(|v| *v == [7.0, -7.0]),
            "output written on {r:?}"
        );
        r.unwrap_err()
    };
    let bad_radius = greedy(RbfKernel::Wendland { radius: 0.0 }, 0.0, 28, 0.5);
    assert!(matches!(
        call(&c.points, &c.boundary, &motion, &bad_radius, 0),
        Error::InvalidParameter {
            arg: "options.kernel.radius",
            ..
        }
    ));
    let bad_tol = RbfOptions {
        tolerance: -1.0,
        ..good
    };
    assert!(matches!(
        call(&c.points, &c.boundary, &motion, &bad_tol, 0),
        Error::InvalidParameter {
            arg: "options.tolerance",
            ..
        }
    ));
    let bad_rc = RbfOptions {
        correction_radius: f64::NAN,
        ..good
    };
    assert!(matches!(
        call(&c.points, &c.boundary, &motion, &bad_rc, 0),
        Error::InvalidParameter { .. }
    ));
    let tps_few = greedy(RbfKernel::ThinPlate, 0.0, 2, 0.0);
    assert!(matches!(
        call(&c.points, &c.boundary, &motion, &tps_few, 0),
        Error::InvalidParameter {
            arg: "options.max_centres",
            ..
        }
    ));
    assert!(matches!(
        call(&c.points, &c.boundary, &motion, &good, 1),
        Error::BufferTooSmall { arg: "index", .. }
    ));
    assert!(matches!(
        call(&c.points, &c.boundary, &motion[1..], &good, 0),
        Error::LengthMismatch { arg: "motion", .. }
    ));
    let mut dup = c.boundary.clone();
    dup[5] = dup[2];
    assert_eq!(
        call(&c.points, &dup, &motion, &good, 0),
        Error::DuplicateNode {
            arg: "boundary",
            position: 5,
            node: 2
        }
    );
    let mut oob = c.boundary.clone();
    oob[3] = n as u32;
    assert!(matches!(
        call(&c.points, &oob, &motion, &good, 0),
        Error::IndexOutOfRange {
            arg: "boundary",
            position: 3,
            ..
        }
    ));
    let mut nan = motion.clone();
    nan[4][1] = f64::INFINITY;
    assert!(matches!(
        call(&c.points, &c.boundary, &nan, &good, 0),
        Error::NonFinite {
            arg: "motion",
            position: 4
        }
    ));
    // Two boundary nodes at one place: the full Wendland matrix is singular.
    let mut twin = c.points.clone();
    twin[6] = twin[7];
    assert!(matches!(
        call(&twin, &c.boundary, &motion, &good, 0),
        Error::SingularSystem { .. }
    ));
    // Thin-plate splines on a wall that is a straight line: no affine frame.
    let line: Vec<[f64; 2]> = (0..n).map(|i| [i as f64, 2.0 * i as f64]).collect();
    let tps = greedy(RbfKernel::ThinPlate, 1e-9, 28, 0.0);
    assert!(matches!(
        call(&line, &c.boundary, &motion, &tps, 0),
        Error::InvalidParameter {
            arg: "boundary",
            ..
        }
    ));
}

/// A coincident node ends a greedy selection instead of breaking it.
#[test]
fn greedy_stops_at_a_numerically_dependent_node() {
    let mut c = case::<2>(40, 16, 20);
    c.points[3] = c.points[2];
    let mut motion = pitch_motion(&c, 10.0, 0.0);
    motion[3] = [motion[2][0] + 0.05, motion[2][1]];
    let opts = greedy(RbfKernel::Wendland { radius: 2.0 }, 1e-12, 56, 0.5);
    let (out, report) = run(&c.points, &c.boundary, &motion, &opts).unwrap();
    assert!(report.dependent, "{report:?}");
    assert!(out.iter().flatten().all(|v| v.is_finite()));
    assert_eq!(out[3], motion[3]);
}

/// Scaling every length by a power of two scales the result bit for bit (Wendland: `φ` reads
/// `r / R`; greedy and correction likewise), up to where squared distances leave the range:
/// there the call refuses (`Error::Overflow`) instead of reading them as "outside the
/// support".
#[test]
fn power_of_two_scaling_is_exact_and_overflow_is_refused() {
    let c = case::<2>(120, 30, 200);
    let motion = pitch_motion(&c, 30.0, 0.01);
    let tol = 1e-3 * max_norm(&motion);
    let opts = |s: f64| {
        greedy(
            RbfKernel::Wendland { radius: 8.0 * s },
            tol * s,
            150,
            0.5 * s,
        )
    };
    let (base, report) = run(&c.points, &c.boundary, &motion, &opts(1.0)).unwrap();
    assert!(report.centres < 150);
    for k in [-300, 200, 400] {
        let s = 2f64.powi(k);
        let scale = |v: &[[f64; 2]]| v.iter().map(|p| p.map(|x| x * s)).collect::<Vec<_>>();
        let (out, r) = run(&scale(&c.points), &c.boundary, &scale(&motion), &opts(s)).unwrap();
        assert_eq!(r.centres, report.centres, "2^{k}");
        assert_eq!(out, scale(&base), "2^{k}");
    }
    let s = 2f64.powi(600);
    let big: Vec<[f64; 2]> = c.points.iter().map(|p| p.map(|x| x * s)).collect();
    let e = run(&big, &c.boundary, &motion, &opts(1.0)).unwrap_err();
    assert_eq!(e, Error::Overflow { arg: "points" });
}
