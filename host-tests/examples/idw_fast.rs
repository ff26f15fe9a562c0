//! Exact against fast (tree, far-field clusters) inverse-distance propagation on an extruded
//! NACA 2412 wing, twisted 10° and bent at the tip, far field fixed: time, work, the reported
//! bound and the error actually observed against the exact method.
//!
//! `cargo run --release -p deform-host-tests --example idw_fast [-- SURFACE RADIAL LAYERS [SAMPLE]]`
//!
//! The default `500 20 20` gives 200,000 nodes with 20,000 on the wall and far field (the
//! boundary; the end caps are left free, as symmetry planes would be). With `SAMPLE > 1` the
//! exact method runs only on every `SAMPLE`-th field point (its full time is extrapolated from
//! the time per pair) and errors are measured there: `1000 20 50 100` is the 10⁶ × 10⁵ case.

use std::time::Instant;

use deform_kernel::quaternion::{
    propagate_idw, propagate_idw_fast, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, IdwFastOptions,
};
use deform_kernel::Quat;
use deform_meshgen::{extrude, naca_ogrid, twist_bend, AirfoilGrid, TwistBend};

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("SURFACE RADIAL LAYERS are whole numbers"))
        .collect();
    let (surface, radial, layers, sample) = match args.as_slice() {
        [] => (500, 20, 20, 1),
        [s, r, l] => (*s, *r, *l, 1),
        [s, r, l, k] => (*s, *r, *l, (*k).max(1)),
        _ => panic!("usage: idw_fast [SURFACE RADIAL LAYERS [SAMPLE]]"),
    };
    let grid = AirfoilGrid {
        surface_points: surface,
        radial_points: radial,
        first_layer: 1e-3,
        ..AirfoilGrid::default()
    };
    let span = 3.0;
    let mesh = extrude(&naca_ogrid(&grid).unwrap(), span, layers - 1).unwrap();
    let n = mesh.points.len();
    let map = TwistBend {
        span,
        tip_twist_deg: 10.0,
        tip_bend: 0.3,
        centre: [0.25, 0.0],
    };
    let moved = twist_bend(&mesh, &map).unwrap();
    let wall = &mesh.marker("airfoil").unwrap().node_list;
    let far = &mesh.marker("farfield").unwrap().node_list;
    let mut boundary: Vec<u32> = wall.clone();
    boundary.extend(far.iter().filter(|i| !wall.contains(i)));
    let b = boundary.len();
    let mut t0 = vec![[0.0f64; 3]; n];
    let mut q0 = vec![Quat::identity(); n];
    for &i in wall {
        let i = i as usize;
        let p = mesh.points[i];
        t0[i] = [0, 1, 2].map(|c| moved[i][c] - p[c]);
        q0[i] = Quat::from_rotation_z(map.tip_twist_deg.to_radians() * p[2] / span);
    }
    println!(
        "extruded NACA 2412 wing: {n} nodes, {b} boundary nodes ({} wall), p = 2",
        wall.len()
    );
    let max_disp = boundary
        .iter()
        .map(|&i| {
            let t = t0[i as usize];
            (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt()
        })
        .fold(0.0, f64::max);

    // Exact values at the sampled points: the boundary first (local indices 0..B), then
    // every `sample`-th field point.
    let is_b = {
        let mut m = vec![false; n];
        for &i in &boundary {
            m[i as usize] = true;
        }
        m
    };
    let sampled: Vec<usize> = (0..n).filter(|&i| !is_b[i]).step_by(sample).collect();
    let mut sub_pts: Vec<[f64; 3]> = boundary.iter().map(|&i| mesh.points[i as usize]).collect();
    sub_pts.extend(sampled.iter().map(|&i| mesh.points[i]));
    let sub_b: Vec<u32> = (0..b as u32).collect();
    let mut te: Vec<[f64; 3]> = boundary.iter().map(|&i| t0[i as usize]).collect();
    let mut qe: Vec<Quat<f64>> = boundary.iter().map(|&i| q0[i as usize]).collect();
    te.resize(sub_pts.len(), [0.0; 3]);
    qe.resize(sub_pts.len(), Quat::identity());
    let start = Instant::now();
    propagate_idw(&sub_pts, &sub_b, 2.0, &mut te, &mut qe).unwrap();
    let sub_s = start.elapsed().as_secs_f64();
    let per_pair = sub_s / (sub_pts.len() as f64 * b as f64);
    let exact_s = per_pair * n as f64 * b as f64;
    println!(
        "exact: {exact_s:.2} s{} ({:.2} ns per point-boundary pair); errors at {} field points",
        if sample > 1 { " (extrapolated)" } else { "" },
        per_pair * 1e9,
        sampled.len()
    );
    println!(
        "{:>5} {:>9} {:>8} {:>8} {:>10} {:>10} {:>12} {:>12} {:>10} {:>10}",
        "θ",
        "tol",
        "time s",
        "speedup",
        "max η",
        "mean η",
        "max |err|",
        "err/max|Δ|",
        "rot err °",
        "refined"
    );
    let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
    let mut scratch = vec![0.0f64; propagate_idw_fast_scratch_len::<3>(b)];
    let mut eta = vec![0.0f64; n];
    for (theta, tol) in [
        (0.2, f64::INFINITY),
        (0.3, f64::INFINITY),
        (0.5, f64::INFINITY),
        (0.7, f64::INFINITY),
        (0.5, 0.1),
        (0.5, 0.01),
        (0.3, 0.1),
        (0.3, 0.01),
    ] {
        let (mut t, mut q) = (t0.clone(), q0.clone());
        let options = IdwFastOptions {
            theta,
            tolerance: tol,
        };
        let start = Instant::now();
        let report = propagate_idw_fast(
            &mesh.points,
            &boundary,
            2.0,
            &options,
            &mut index,
            &mut scratch,
            &mut t,
            &mut q,
            Some(&mut eta),
        )
        .unwrap();
        let s = start.elapsed().as_secs_f64();
        let mut err: f64 = 0.0;
        let mut rot: f64 = 0.0;
        for (k, &i) in sampled.iter().enumerate() {
            let (te, qe) = (te[b + k], qe[b + k]);
            let d = [0, 1, 2].map(|c| t[i][c] - te[c]);
            err = err.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
            let c = q[i].dot(qe).abs().min(1.0);
            rot = rot.max(2.0 * c.acos().to_degrees());
        }
        let mean_eta = eta.iter().sum::<f64>() / (n - b) as f64;
        println!(
            "{theta:>5} {tol:>9} {s:>8.2} {:>8.1} {:>10.2e} {:>10.2e} {err:>12.2e} {:>12.2e} \
             {rot:>10.2e} {:>10}",
            exact_s / s,
            report.max_bound,
            mean_eta,
            err / max_disp,
            report.refined
        );
        println!(
            "      work: {} clusters + {} direct = {:.2}% of the exact method's {} pairs",
            report.clusters,
            report.direct,
            100.0 * (report.clusters + report.direct) as f64 / (n as f64 * b as f64),
            n * b
        );
    }
}
