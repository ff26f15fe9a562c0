//! The RBF sensitivities through the C ABI: builds `libdeform_kernel` (static and shared),
//! compiles `ffi/tests/sensitivity_rbf.c` (tangent and adjoint, thin-plate with greedy centres
//! and the correction in f64 0-based, Wendland with every centre in f32 1-based, bad input
//! that must return its status and write nothing), runs it, and compares the printed bits
//! with the kernel's `rbf_tangent` and `rbf_adjoint` on the same inputs. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::rbf::{rbf_index_len, rbf_scratch_len, RbfKernel, RbfOptions};
use deform_kernel::sensitivity::{rbf_adjoint, rbf_tangent};
use deform_kernel::Real;

const S: usize = 7;

fn pairs<T: Real>(flat: &[f64]) -> Vec<[T; 2]> {
    flat.chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect()
}

/// The kernel's tangent and adjoint on the C program's inputs, printed as it prints them.
fn expected<T: Real>(
    tag: &str,
    inputs: [&[f64]; 4],
    o: RbfOptions<T>,
    hex: fn(&str, &[T]) -> String,
) -> String {
    let [points, w, motion, v] = inputs.map(pairs::<T>);
    let boundary: Vec<u32> = (0..S * S)
        .filter(|n| {
            let (i, j) = (n % S, n / S);
            i == 0 || j == 0 || i == S - 1 || j == S - 1
        })
        .map(|n| n as u32)
        .collect();
    let b = boundary.len();
    let mut index = vec![0u32; rbf_index_len::<T, 2>(b, &o)];
    let mut s = vec![T::ZERO; rbf_scratch_len::<T, 2>(b, &o)];
    let (mut jv, mut g) = (vec![[T::ZERO; 2]; points.len()], vec![[T::ZERO; 2]; b]);
    let (p, m) = (&points, &motion);
    rbf_tangent(p, &boundary, m, &o, &mut index, &mut s, &v, &mut jv).unwrap();
    rbf_adjoint(p, &boundary, m, &o, &mut index, &mut s, &w, &mut g).unwrap();
    let flat = |x: &[[T; 2]]| x.iter().flatten().copied().collect::<Vec<T>>();
    hex(&format!("rbf tangent {tag}"), &flat(&jv)) + &hex(&format!("rbf adjoint {tag}"), &flat(&g))
}

#[test]
fn rbf_sensitivities_from_c_equal_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "sensitivity_rbf_c_static"),
        (Link::Shared, "sensitivity_rbf_c_shared"),
    ] {
        let printed = run_c_test("sensitivity_rbf", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"sensitivity_rbf: every check held"),
            "{name}: {printed}"
        );
        let names = ["points", "w", "motion", "v"];
        let parsed: Vec<Vec<f64>> = (0..4).map(|i| parse_hex64(lines[i], names[i])).collect();
        let inputs = [&parsed[0][..], &parsed[1], &parsed[2], &parsed[3]];
        let tps = RbfOptions {
            kernel: RbfKernel::ThinPlate,
            tolerance: 1e-3,
            max_centres: 12,
            correction_radius: 0.4,
        };
        let wendland = RbfOptions {
            kernel: RbfKernel::Wendland { radius: 0.8f32 },
            tolerance: 0.0,
            max_centres: usize::MAX,
            correction_radius: 0.0,
        };
        let want = expected::<f64>("f64", inputs, tps, hex64)
            + &expected::<f32>("f32", inputs, wendland, hex32);
        let got = lines[4..8].join("\n") + "\n";
        assert_eq!(got, want, "{name}");
    }
}
