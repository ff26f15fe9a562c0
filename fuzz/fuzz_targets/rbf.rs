//! RBF deformation (`deform_kernel::rbf`) on arbitrary small 2D/3D point sets, boundary
//! subsets (duplicates, out-of-range and coincident nodes included), motions, kernels,
//! radii, tolerances, centre budgets and correction radii (NaN, negative, zero included),
//! with short workspaces: never panics; an error leaves the output bit-identical; on success
//! every displacement is finite, the reported error is finite, the centres are within the
//! budget, the greedy stop is honest (error within the tolerance, budget spent or a dependent
//! node), and with a correction the boundary nodes get their motion exactly.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::rbf::{rbf_deform, rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    three_d: bool,
    thin_plate: bool,
    coords: Vec<[i8; 3]>,
    boundary: Vec<u8>,
    motion: Vec<[i8; 3]>,
    radius: u8,
    tolerance: u8,
    max_centres: u8,
    correction: u8,
    scale: i8,
    short: u8,
}

fn param(v: u8, div: f64) -> f64 {
    match v {
        250 => f64::NAN,
        251 => f64::INFINITY,
        252 => -1.0,
        v => f64::from(v) / div,
    }
}

fn run<const D: usize>(inp: &Input) {
    let n = inp.coords.len().min(60);
    let scale = 2f64.powi(i32::from(inp.scale) * 4);
    let points: Vec<[f64; D]> = inp.coords[..n]
        .iter()
        .map(|c| std::array::from_fn(|a| f64::from(c[a]) * scale / 16.0))
        .collect();
    let boundary: Vec<u32> = inp
        .boundary
        .iter()
        .take(30)
        .map(|&b| u32::from(b) % (n as u32 + 1)) // n itself is out of range
        .collect();
    let motion: Vec<[f64; D]> = (0..boundary.len())
        .map(|k| {
            let m = inp.motion.get(k).copied().unwrap_or([0; 3]);
            std::array::from_fn(|a| f64::from(m[a]) * scale / 64.0)
        })
        .collect();
    let kernel = if inp.thin_plate {
        RbfKernel::ThinPlate
    } else {
        RbfKernel::Wendland {
            radius: param(inp.radius, 16.0) * scale,
        }
    };
    let options = RbfOptions {
        kernel,
        tolerance: param(inp.tolerance, 200.0) * scale,
        max_centres: usize::from(inp.max_centres % 40),
        correction_radius: param(inp.correction, 32.0) * scale,
    };
    let b = boundary.len();
    let short = usize::from(inp.short % 3);
    let mut index = vec![0u32; rbf_index_len::<f64, D>(b, &options).saturating_sub(short & 1)];
    let mut scratch = vec![0.0; rbf_scratch_len::<f64, D>(b, &options).saturating_sub(short >> 1)];
    let mut out = vec![[f64::NAN; D]; n];
    let r = rbf_deform(
        &points,
        &boundary,
        &motion,
        &options,
        &mut index,
        &mut scratch,
        &mut out,
    );
    let Ok(report) = r else {
        assert!(out.iter().flatten().all(|v| v.is_nan()));
        return;
    };
    assert!(short == 0);
    assert!(out.iter().flatten().all(|v| v.is_finite()), "{out:?}");
    assert!(report.max_error.is_finite() && report.max_error >= 0.0);
    let budget = options.max_centres.min(b);
    assert!(report.centres <= budget);
    if options.tolerance > 0.0 || budget < b {
        assert!(
            report.max_error <= options.tolerance || report.centres == budget || report.dependent,
            "{report:?}"
        );
    }
    if options.correction_radius > 0.0 {
        for (&node, d) in boundary.iter().zip(&motion) {
            assert_eq!(out[node as usize], *d);
        }
    }
}

fuzz_target!(|inp: Input| {
    if inp.three_d {
        run::<3>(&inp);
    } else {
        run::<2>(&inp);
    }
});
