//! The rigid wall layer through the C ABI: builds `libdeform_kernel` (static and shared),
//! compiles `ffi/tests/elasticity_layer.c` (`dk_elasticity_rigid_layer` in f64 with a 0-based
//! wall, its `_f32` twin with a 1-based one, bad input that must return its status and write
//! nothing), runs it, and compares the printed masks and bits with the kernel's
//! `elasticity::rigid_layer` on the same inputs. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::elasticity::rigid_layer;
use deform_kernel::{Quat, Real};

const S: usize = 5;
const N: usize = S * S;

/// The kernel's layer on the C program's square, printed as the C program prints it.
fn expected<T: Real>(
    tag: &str,
    points: &[f64],
    rotation: &[f64],
    initial: &[f64],
    hex: fn(&str, &[T]) -> String,
) -> String {
    let pts: Vec<[T; 2]> = (points.chunks(2))
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect();
    let q = Quat::from_array([0, 1, 2, 3].map(|i| T::from_f64(rotation[i])));
    let wall: Vec<u32> = (0..S as u32).collect();
    let mut fixed: Vec<u8> = (0..N).map(|k| u8::from(k < S)).collect();
    // The wall's displacement as the C program printed it (f64), rounded to T.
    let mut disp: Vec<[T; 2]> = (initial.chunks(2))
        .map(|d| [T::from_f64(d[0]), T::from_f64(d[1])])
        .collect();
    let added = rigid_layer(
        &pts,
        &wall,
        &[q; S],
        T::from_f64(0.3),
        &mut fixed,
        &mut disp,
    )
    .unwrap();
    let mask: String = fixed.iter().map(|f| format!(" {f}")).collect();
    let flat: Vec<T> = disp.iter().flatten().copied().collect();
    format!(
        "{tag} added {added} fixed{mask}\n{}",
        hex(&format!("{tag} displacement"), &flat)
    )
}

#[test]
fn rigid_layer_from_c_equals_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "elasticity_layer_c_static"),
        (Link::Shared, "elasticity_layer_c_shared"),
    ] {
        let printed = run_c_test("elasticity_layer", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"elasticity_layer: every check held"),
            "{name}: {printed}"
        );
        let points = parse_hex64(lines[0], "points");
        let rotation = parse_hex64(lines[1], "rotation");
        let initial = parse_hex64(lines[2], "initial");
        let want = expected::<f64>("f64", &points, &rotation, &initial, hex64)
            + &expected::<f32>("f32", &points, &rotation, &initial, hex32);
        assert_eq!(lines[3..7].join("\n") + "\n", want, "{name}");
    }
}
