//! Target 11: the fast (tree, far-field clusters) inverse-distance propagation on arbitrary
//! small 2D/3D point sets, boundary subsets (duplicates and coincident points included),
//! values, exponents, `θ` and tolerances (NaN, negative, ≥ 1 included): never panics; an
//! error leaves the outputs bit-identical; on success every value is finite, every bound is
//! at most the tolerance, and the translation at each field point is within `η ·
//! max_k |Δ_k − Δ(x)|` (plus rounding) of the independent `f64` reference.
#![no_main]

use arbitrary::Arbitrary;
use deform_host_tests::idw_ref::idw_with_spread;
use deform_kernel::quaternion::{
    propagate_idw_fast, propagate_idw_fast_index_len, propagate_idw_fast_scratch_len,
    IdwFastOptions,
};
use deform_kernel::Quat;
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    three_d: bool,
    coords: Vec<[i8; 3]>,
    boundary: Vec<u8>,
    values: Vec<([i8; 3], [i8; 4])>,
    exponent: u8,
    theta: u8,
    tolerance: u8,
    scale: i8,
    short_scratch: bool,
}

fn run<const D: usize>(inp: &Input) {
    let n = inp.coords.len().min(80);
    if n == 0 {
        return;
    }
    let scale = 2f64.powi(i32::from(inp.scale) * 4);
    let points: Vec<[f64; D]> = inp.coords[..n]
        .iter()
        .map(|c| {
            let mut p = [0.0; D];
            for (a, v) in p.iter_mut().zip(c) {
                *a = f64::from(*v) * scale / 16.0;
            }
            p
        })
        .collect();
    let boundary: Vec<u32> = inp
        .boundary
        .iter()
        .take(40)
        .map(|&b| u32::from(b) % (n as u32 + 1)) // n itself is out of range
        .collect();
    let mut t = vec![[f64::NAN; D]; n];
    let mut q = vec![Quat::new(f64::NAN, 0.0, 0.0, 0.0); n];
    for (k, &b) in boundary.iter().enumerate() {
        let (tv, qv) = inp.values.get(k).copied().unwrap_or(([0; 3], [1, 0, 0, 0]));
        if let (Some(tt), Some(qq)) = (t.get_mut(b as usize), q.get_mut(b as usize)) {
            for (a, v) in tt.iter_mut().zip(tv) {
                *a = f64::from(v) / 8.0;
            }
            *qq = Quat::from_array(qv.map(f64::from));
        }
    }
    let exponent = 0.5 + f64::from(inp.exponent % 12) * 0.5;
    let theta = match inp.theta {
        250 => f64::NAN,
        251 => 1.0,
        252 => -0.25,
        v => f64::from(v % 100) / 100.0,
    };
    let tolerance = match inp.tolerance {
        250 => f64::NAN,
        251 => f64::INFINITY,
        252 => -1.0,
        v => f64::from(v) / 50.0,
    };
    let options = IdwFastOptions { theta, tolerance };
    let b = boundary.len();
    let mut index = vec![0u32; propagate_idw_fast_index_len(b)];
    let need = propagate_idw_fast_scratch_len::<D>(b);
    let mut scratch = vec![0.0; need.saturating_sub(usize::from(inp.short_scratch))];
    let mut eta = vec![-1.0; n];
    let (t0, q0) = (t.clone(), q.clone());
    let r = propagate_idw_fast(
        &points,
        &boundary,
        exponent,
        &options,
        &mut index,
        &mut scratch,
        &mut t,
        &mut q,
        Some(&mut eta),
    );
    let bits_t = |v: &[[f64; D]]| v.iter().map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
    let bits_q = |v: &[Quat<f64>]| {
        v.iter()
            .map(|x| x.to_array().map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    let Ok(report) = r else {
        assert_eq!(bits_t(&t), bits_t(&t0));
        assert_eq!(bits_q(&q), bits_q(&q0));
        assert!(eta.iter().all(|&e| e == -1.0));
        return;
    };
    assert!(b > 0 && (0.0..1.0).contains(&theta) && tolerance >= 0.0 && need > 0);
    assert!(report.max_bound <= tolerance);
    // Reference (duplicates in `boundary` keep their last values in the field arrays, which
    // is what both methods read).
    let pts: Vec<Vec<f64>> = points.iter().map(|p| p.to_vec()).collect();
    let bidx: Vec<usize> = boundary.iter().map(|&i| i as usize).collect();
    let bt: Vec<Vec<f64>> = bidx.iter().map(|&i| t0[i].to_vec()).collect();
    let bq: Vec<[f64; 4]> = bidx.iter().map(|&i| q0[i].to_array()).collect();
    let refs = idw_with_spread(&pts, &bidx, &bt, &bq, exponent);
    let tscale = bt
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    for (i, r) in refs.iter().enumerate() {
        if r.boundary {
            assert_eq!(eta[i], -1.0);
            continue;
        }
        assert!(t[i].iter().all(|c| c.is_finite()), "point {i}");
        assert!(q[i].to_array().iter().all(|c| c.is_finite()));
        assert!(eta[i] >= 0.0 && eta[i] <= tolerance);
        if scale != 1.0 || r.coincident {
            // The reference's plain distances are not scale-safe; coincident points copy a
            // value whose choice depends on rounding of tiny distances.
            continue;
        }
        let err =
            r.t.iter()
                .zip(t[i])
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
        let slack = 1e-10 * tscale * b as f64;
        assert!(
            err <= eta[i] * r.spread_t + slack,
            "point {i}: err {err:e}, η {}, spread {}",
            eta[i],
            r.spread_t
        );
    }
}

fuzz_target!(|inp: Input| {
    if inp.three_d {
        run::<3>(&inp);
    } else {
        run::<2>(&inp);
    }
});
