//! The fast (tree) IDW deformation and its derivatives through the C ABI: builds
//! `libdeform_kernel` (static and shared), compiles `ffi/tests/deformation_fast.c`
//! (`dk_deform_idw_fast_lens`, `dk_deform_idw_fast`, `dk_deform_idw_fast_tangent`,
//! `dk_deform_idw_fast_adjoint` and the `_f32` twins: boundary bits, the bound, the
//! dot-product identity, bad input), runs it, and recomputes what it printed with the kernel's
//! `deform_idw_fast`, `deform_idw_fast_tangent` and `deform_idw_fast_adjoint` on the same
//! inputs, bit for bit in both precisions. Needs `gcc` on PATH.

#[path = "../support/mod.rs"]
mod support;

use support::c_build::*;

use deform_kernel::quaternion::{
    deform_idw_fast, deform_idw_fast_adjoint, deform_idw_fast_sensitivity_scratch_len,
    deform_idw_fast_tangent, deform_idw_scratch_len, propagate_idw_fast_index_len,
    propagate_idw_fast_scratch_len, BoundaryMotion, IdwFastOptions, RotationSource,
};
use deform_kernel::{Cells, Quat, Real};

const MX: usize = 16;
const MY: usize = 12;
const N: usize = MX * MY;
const B: usize = 2 * (MX + MY) - 4;

/// The grid's perimeter in order, as the C program walks it.
fn ring() -> Vec<u32> {
    let mut r: Vec<usize> = (0..MX).collect();
    r.extend((1..MY).map(|j| MX - 1 + MX * j));
    r.extend((0..MX - 1).rev().map(|i| i + MX * (MY - 1)));
    r.extend((1..MY - 1).rev().map(|j| MX * j));
    r.into_iter().map(|i| i as u32).collect()
}

fn pairs<T: Real>(v: &[f64]) -> Vec<[T; 2]> {
    v.chunks(2)
        .map(|c| [T::from_f64(c[0]), T::from_f64(c[1])])
        .collect()
}

/// The kernel's deformed mesh, bound, tangent along `dir` and adjoint of `w` in precision
/// `T`, as `(flat values, bound)` lists.
fn kernel<T: Real>(p: &[f64], def: &[f64], dir: &[f64], w: &[f64]) -> [Vec<T>; 4] {
    let (points, deformed) = (pairs::<T>(p), pairs::<T>(def));
    let (dir, w) = (pairs::<T>(dir), pairs::<T>(w));
    let boundary = ring();
    let offsets: Vec<u32> = (0..=B as u32).map(|i| 2 * i).collect();
    let nodes: Vec<u32> = (0..B as u32)
        .flat_map(|i| [i, (i + 1) % B as u32])
        .collect();
    let kinds = vec![3u8; B];
    let elements = Cells::new(B, &offsets, &nodes, &kinds).unwrap();
    let motion = BoundaryMotion {
        nodes: &boundary,
        deformed: &deformed,
        elements: Some(elements),
        rotations: RotationSource::Shape,
        origin: None,
    };
    let o = IdwFastOptions {
        theta: T::HALF,
        tolerance: T::from_f64(0.1),
    };
    let e = T::from_f64(3.0);
    let mut index = vec![0u32; propagate_idw_fast_index_len(B)];
    let mut tree = vec![T::ZERO; propagate_idw_fast_scratch_len::<2>(B)];
    let (mut tr, mut rot) = (vec![[T::ZERO; 2]; N], vec![Quat::identity(); N]);
    let mut s = vec![T::ZERO; deform_idw_scratch_len::<2>(N, B)];
    let mut out = vec![[T::ZERO; 2]; N];
    let (_, report) = deform_idw_fast(
        &points, &motion, e, &o, &mut tr, &mut rot, &mut s, &mut index, &mut tree, &mut out,
    )
    .unwrap();
    let mut s = vec![T::ZERO; deform_idw_fast_sensitivity_scratch_len::<2>(N, B)];
    let (ix, tr2) = (&mut index, &mut tree);
    let mut tan = vec![[T::ZERO; 2]; N];
    deform_idw_fast_tangent(
        &points, &motion, e, &o, &dir, &mut tr, &mut rot, &mut s, ix, tr2, &mut tan,
    )
    .unwrap();
    let mut back = vec![[T::ZERO; 2]; B];
    let (ix, tr2) = (&mut index, &mut tree);
    deform_idw_fast_adjoint(
        &points, &motion, e, &o, &w, &mut tr, &mut rot, &mut s, ix, tr2, &mut back,
    )
    .unwrap();
    let flat = |x: &[[T; 2]]| -> Vec<T> { x.iter().flatten().copied().collect() };
    [flat(&out), vec![report.max_bound], flat(&tan), flat(&back)]
}

#[test]
fn fast_idw_from_c_equals_the_kernel_bit_for_bit() {
    for (link, name) in [
        (Link::Static, "deformation_fast_c_static"),
        (Link::Shared, "deformation_fast_c_shared"),
    ] {
        let printed = run_c_test("deformation_fast", name, link);
        let lines: Vec<&str> = printed.lines().collect();
        assert_eq!(
            lines.last(),
            Some(&"deformation_fast: every check held"),
            "{name}: {printed}"
        );
        let input = |k: usize, what: &str| parse_hex64(lines[k], what);
        let (p, def) = (input(0, "points"), input(1, "deformed"));
        let (dir, w) = (input(2, "direction"), input(3, "weights"));
        assert_eq!((p.len(), def.len()), (2 * N, 2 * B));
        let labels = ["out", "bound", "tangent", "adjoint"];
        let want64: String = labels
            .iter()
            .zip(kernel::<f64>(&p, &def, &dir, &w))
            .map(|(l, v)| hex64(l, &v))
            .collect();
        let want32: String = labels
            .iter()
            .zip(kernel::<f32>(&p, &def, &dir, &w))
            .map(|(l, v)| hex32(l, &v))
            .collect();
        assert_eq!(lines[4..8].join("\n") + "\n", want64, "{name} f64");
        assert_eq!(lines[8..12].join("\n") + "\n", want32, "{name} f32");
    }
}

/// The generated Fortran interfaces (`ffi/tests/deformation_fast.f90`): a `dk_boundary_motion`
/// built from Fortran arrays (1-based), a rigid turn reproduced at every node with clusters in
/// use and equal to the exact IDW, the tangent/adjoint dot product, the `_f32` twin's boundary
/// bit for bit, and a bad `theta` refused with the output untouched. Needs `gfortran`.
#[test]
fn fortran_fast_idw_interfaces() {
    assert_eq!(
        fortran_test("deformation_fast"),
        "deformation_fast: every check held\n"
    );
}
