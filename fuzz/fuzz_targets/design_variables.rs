//! SU2 design variables (kernel `design`): arbitrary FFD boxes (degrees 1 to 6, control
//! points, parametric coordinates anywhere, raw f64 bits including NaN and infinities),
//! arbitrary SU2 design-variable indices, and arbitrary Hicks–Henne parameters. Never a
//! panic; every error is typed and leaves its outputs unchanged; on valid finite input a box
//! minus itself is exactly zero, and translating every control point by t moves every
//! surface point by t (partition of unity, to rounding).
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::design::ffd::{
    ffd_control_point_count, ffd_displacements, ffd_displacements_between, FfdBox,
};
use deform_kernel::design::hicks_henne::{hicks_henne, HicksHenne};
use deform_kernel::design::variables::{ffd_camber, ffd_control_point, ffd_thickness_2d};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    degree: [u8; 3],
    coords: Vec<i16>,
    params: Vec<i16>,
    raw: [u64; 4],
    index: [i8; 3],
    upper: bool,
    nodes: Vec<u8>,
}

fn value(v: i16) -> f64 {
    f64::from(v) / 1024.0
}

fuzz_target!(|inp: Input| {
    let degree = inp.degree.map(|d| (d % 7) as usize);
    let count = ffd_control_point_count(degree).unwrap_or(8);
    let cps: Vec<[f64; 3]> = (0..count)
        .map(|i| core::array::from_fn(|a| value(inp.coords.get(3 * i + a).copied().unwrap_or(0))))
        .collect();
    let mut params: Vec<[f64; 3]> = inp
        .params
        .chunks_exact(3)
        .map(|c| [value(c[0]) / 16.0, value(c[1]) / 16.0, value(c[2]) / 16.0])
        .collect();
    let raw = inp.raw.map(f64::from_bits);
    if let Some(p) = params.first_mut() {
        p[0] = raw[0];
    }
    let Ok(ffd) = FfdBox::new(degree, &cps) else {
        assert!(ffd_control_point_count(degree).is_none());
        return;
    };
    let mut d = vec![[7.0; 3]; params.len()];
    match ffd_displacements_between(&ffd, &ffd, &params, &mut d) {
        Ok(()) => assert!(d.iter().flatten().all(|&v| v == 0.0), "box minus itself"),
        Err(_) => assert!(d.iter().flatten().all(|&v| v == 7.0)),
    }
    let t = [0.25, -0.5, 1.0];
    let moved: Vec<[f64; 3]> = cps
        .iter()
        .map(|p| [p[0] + t[0], p[1] + t[1], p[2] + t[2]])
        .collect();
    let shifted = FfdBox::new(degree, &moved).unwrap();
    if ffd_displacements_between(&ffd, &shifted, &params, &mut d).is_ok() {
        for (u, v) in params.iter().zip(&d) {
            let inside = u.iter().all(|&x| (0.0..=1.0).contains(&x));
            for a in 0..3 {
                if inside {
                    assert!((v[a] - t[a]).abs() < 1e-9, "translation {v:?} at {u:?}");
                }
            }
        }
    }
    // SU2-style displacements against arbitrary mesh points.
    let nodes: Vec<u32> = inp
        .nodes
        .iter()
        .map(|&n| u32::from(n % 40))
        .take(params.len())
        .collect();
    let mut d2 = vec![[7.0; 3]; nodes.len()];
    if ffd_displacements(&ffd, &moved, &nodes, &params[..nodes.len()], &mut d2).is_err() {
        assert!(d2.iter().flatten().all(|&v| v == 7.0));
    }
    // Design variables: errors change nothing.
    let ijk = inp
        .index
        .map(|i| if i < 0 { None } else { Some(i as usize % 8) });
    let mut c = cps.clone();
    if ffd_control_point(degree, &mut c, ijk, [raw[1], 0.5, raw[2]]).is_err() {
        assert_eq!(c, cps);
    }
    let mut c = cps.clone();
    let (i, j) = (inp.index[0] as usize % 8, inp.index[1] as usize % 8);
    if ffd_camber(degree, &mut c, i, j, raw[3]).is_err() {
        assert_eq!(c, cps);
    }
    let mut c = cps.clone();
    if ffd_thickness_2d(degree, &mut c, i, raw[1]).is_err() {
        assert_eq!(c, cps);
    }
    // Hicks–Henne with arbitrary parameters on the control points as a point cloud.
    let normals: Vec<[f64; 3]> = nodes
        .iter()
        .map(|&n| [0.0, f64::from(n) - 20.0, 0.0])
        .collect();
    let bump = HicksHenne {
        upper: inp.upper,
        x_max: raw[2],
        amplitude: raw[3],
    };
    let mut d3 = vec![[7.0; 3]; nodes.len()];
    let cloud: Vec<[f64; 3]> = (0..40).map(|n| cps[n % cps.len()]).collect();
    if hicks_henne(&cloud, &nodes, &normals, bump, &mut d3).is_err() {
        assert!(d3.iter().flatten().all(|&v| v == 7.0));
    } else {
        assert!(d3.iter().flatten().all(|v| v.is_finite()));
    }
});
