//! RBF deformation from C (`ffi/tests/rbf.c`): the f64 Wendland fit and the f32 greedy
//! thin-plate fit with the wall correction give the Rust API's bits, statically and
//! dynamically linked; bad input returns the documented status and writes nothing. Needs
//! `gcc`.

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::rbf::{RbfKernel, RbfOptions};
use support::c_build::*;
use support::rbf::run as rust_rbf;

fn parse_hex(line: &str, name: &str) -> Vec<f64> {
    let rest = line
        .strip_prefix(name)
        .unwrap_or_else(|| panic!("expected {name}: {line}"));
    rest.split_whitespace()
        .map(|h| f64::from_bits(u64::from_str_radix(h, 16).expect("hex")))
        .collect()
}

fn pairs<T: Copy>(v: &[T]) -> Vec<[T; 2]> {
    v.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
}

#[test]
fn c_rbf_equals_the_rust_api_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "rbf_c_static"),
        (Link::Shared, "rbf_c_shared"),
    ] {
        let printed = run_c_test("rbf", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(lines.last(), Some(&"rbf: every check held"), "{name}");
        let points = pairs(&parse_hex(lines[0], "points"));
        let motion = pairs(&parse_hex(lines[1], "motion"));
        let boundary: Vec<u32> = (0..motion.len() as u32).collect();
        let o = RbfOptions {
            kernel: RbfKernel::Wendland { radius: 3.0 },
            tolerance: 0.0,
            max_centres: usize::MAX,
            correction_radius: 0.0,
        };
        let (d, report) = rust_rbf(&points, &boundary, &motion, &o).unwrap();
        let c = pairs(&parse_hex(lines[2], "wendland"));
        assert!(d
            .iter()
            .flatten()
            .zip(c.iter().flatten())
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(
            parse_hex(lines[3], "wendland_error")[0].to_bits(),
            report.max_error.to_bits()
        );

        let p32: Vec<[f32; 2]> = points.iter().map(|p| p.map(|x| x as f32)).collect();
        let m32: Vec<[f32; 2]> = motion.iter().map(|p| p.map(|x| x as f32)).collect();
        let o32 = RbfOptions {
            kernel: RbfKernel::ThinPlate,
            tolerance: 1e-3f32,
            max_centres: 30,
            correction_radius: 1.0,
        };
        let (d32, r32) = rust_rbf(&p32, &boundary, &m32, &o32).unwrap();
        let c32 = pairs(&parse_hex(lines[4], "tps32"));
        assert!(d32
            .iter()
            .flatten()
            .zip(c32.iter().flatten())
            .all(|(a, b)| f64::from(*a).to_bits() == b.to_bits()));
        assert_eq!(lines[5], format!("tps32_centres {}", r32.centres));
        assert!(r32.centres < boundary.len());
    }
}

/// The generated Fortran interfaces (`ffi/tests/rbf.f90`): thin-plate splines rigid, the
/// greedy Wendland fit's wall exact in `_f32` with a 1-based boundary, a bad kernel refused
/// with the output untouched. Needs `gfortran`.
#[test]
fn fortran_rbf_interfaces() {
    assert_eq!(fortran_test("rbf"), "rbf: every check held\n");
}
