//! SU2's Hicks–Henne bumps (kernel/src/design/hicks_henne.rs) against the formula written
//! independently in numpy (ref_design.py), and SU2's side selection by the normal.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::design::hicks_henne::{hicks_henne, hicks_henne_bump, HicksHenne};
use deform_kernel::Error;
use std::path::Path;

fn numpy_bumps(x_max: f64, xs: &[f64]) -> Vec<f64> {
    let text = format!(
        "{x_max:?}\n{}\n",
        xs.iter()
            .map(|v| format!("{v:?}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let dir = std::env::temp_dir().join(format!("dk_design_hh_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // One file per call: tests run in parallel threads of one process.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let file = dir.join(format!("hh_{x_max}_{call}.txt"));
    std::fs::write(&file, text).unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/design/ref_design.py");
    let out = support::python::run_script(&script, &["hh", file.to_str().unwrap()]);
    out.lines().map(|l| l.parse().unwrap()).collect()
}

/// A NACA 0012 outline (closed trailing edge), upper surface from TE to LE then lower, with
/// SU2-style normals (into the fluid: +y on the upper surface).
fn naca0012(n: usize) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let t = |x: f64| {
        0.6 * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
            - 0.1036 * x.powi(4))
    };
    let (mut p, mut nrm) = (Vec::new(), Vec::new());
    for i in 0..n {
        let x = 0.5 * (1.0 + (std::f64::consts::PI * i as f64 / (n - 1) as f64).cos());
        p.push([1.0 - x, t(1.0 - x)]);
        nrm.push([0.0, if i == n - 1 { 0.0 } else { 1.0 }]);
    }
    for i in 1..n - 1 {
        let x = 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / (n - 1) as f64).cos());
        p.push([1.0 - x, -t(1.0 - x)]);
        nrm.push([0.0, -1.0]);
    }
    (p, nrm)
}

#[test]
fn bump_matches_numpy() {
    let xs: Vec<f64> = (-5..=110)
        .map(|i| i as f64 / 100.0 + 1e-3)
        .chain([0.0, 1e-16, 1.0])
        .collect();
    for x_max in [0.05, 0.25, 0.5, 0.7, 0.95] {
        let reference = numpy_bumps(x_max, &xs);
        for (&x, &r) in xs.iter().zip(&reference) {
            let b = hicks_henne_bump(x, x_max);
            assert!(
                (b - r).abs() <= 1e-14 * r.abs().max(1e-300) + 1e-15,
                "x {x} x_max {x_max}: {b} vs {r}"
            );
        }
        // Peak of 1 at x_max, as the formula is built for.
        assert!((hicks_henne_bump(x_max, x_max) - 1.0).abs() < 1e-14);
    }
}

#[test]
fn surface_moves_on_the_chosen_side_only_and_accumulates() {
    let (points, normals) = naca0012(41);
    let nodes: Vec<u32> = (0..points.len() as u32).collect();
    let mut d = vec![[0.0; 2]; nodes.len()];
    let upper = HicksHenne {
        upper: true,
        x_max: 0.3,
        amplitude: 0.01,
    };
    let lower = HicksHenne {
        upper: false,
        x_max: 0.6,
        amplitude: 0.02,
    };
    hicks_henne(&points, &nodes, &normals, upper, &mut d).unwrap();
    hicks_henne(&points, &nodes, &normals, lower, &mut d).unwrap();
    let xs: Vec<f64> = points.iter().map(|p| p[0]).collect();
    let (fu, fl) = (numpy_bumps(0.3, &xs), numpy_bumps(0.6, &xs));
    for p in 0..points.len() {
        assert_eq!(d[p][0], 0.0);
        let want = if normals[p][1] > 0.0 {
            0.01 * fu[p]
        } else if normals[p][1] < 0.0 {
            -0.02 * fl[p]
        } else {
            0.0
        };
        assert!(
            (d[p][1] - want).abs() <= 1e-16,
            "node {p}: {} vs {want}",
            d[p][1]
        );
    }
    assert!(d.iter().any(|v| v[1] > 0.009) && d.iter().any(|v| v[1] < -0.019));
}

#[test]
fn three_d_and_f32() {
    let points = [[0.2f32, 0.0, 1.0], [0.5, 0.1, 2.0]];
    let normals = [[0.0f32, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut d = [[0.0f32; 3]; 2];
    let bump = HicksHenne {
        upper: true,
        x_max: 0.5f32,
        amplitude: 1.0,
    };
    hicks_henne(&points, &[1, 0], &normals, bump, &mut d).unwrap();
    assert!((d[0][1] - 1.0).abs() < 1e-6, "{d:?}");
    assert!((d[1][1] as f64 - hicks_henne_bump(0.2, 0.5)).abs() < 1e-6);
    assert_eq!([d[0][0], d[0][2], d[1][0], d[1][2]], [0.0; 4]);
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let points = [[0.5, 0.0], [0.2, 0.0]];
    let normals = [[0.0, 1.0]; 2];
    let mut d = [[3.0; 2]; 2];
    let ok = HicksHenne {
        upper: true,
        x_max: 0.5,
        amplitude: 1.0,
    };
    for x_max in [0.0, 1.0, -0.5, 2.0] {
        assert!(matches!(
            hicks_henne(
                &points,
                &[0, 1],
                &normals,
                HicksHenne { x_max, ..ok },
                &mut d
            ),
            Err(Error::InvalidParameter { arg: "x_max", .. })
        ));
    }
    assert!(matches!(
        hicks_henne(&points, &[0, 2], &normals, ok, &mut d),
        Err(Error::IndexOutOfRange { arg: "nodes", .. })
    ));
    assert!(matches!(
        hicks_henne(&points, &[0], &normals, ok, &mut d[..1]),
        Err(Error::LengthMismatch { arg: "normals", .. })
    ));
    assert!(matches!(
        hicks_henne(
            &[[f64::NAN, 0.0], [0.2, 0.0]],
            &[0, 1],
            &normals,
            ok,
            &mut d
        ),
        Err(Error::NonFinite {
            arg: "points",
            position: 0
        })
    ));
    let far = [[1e6, 0.0], [0.2, 0.0]];
    let near_one = HicksHenne {
        x_max: 1.0 - f64::EPSILON,
        ..ok
    };
    assert!(matches!(
        hicks_henne(&far, &[1, 0], &normals, near_one, &mut d),
        Err(Error::Overflow { arg: "x_max" })
    ));
    assert_eq!(d, [[3.0; 2]; 2]);
}
