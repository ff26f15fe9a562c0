//! The rigid wall layer of elasticity (`deform_kernel::elasticity::rigid_layer`): layer nodes
//! get the exact rigid motion (f64 and f32), nothing beyond the thickness or already fixed
//! is touched, a translated boundary with its layer gives the translation everywhere after
//! the increments (rigid-motion exactness), typed errors that leave every buffer unchanged,
//! golden bits; the C function `dk_elasticity_rigid_layer` (f64 and f32, 1-based) called from
//! Rust gives the kernel's bits.
#![allow(unsafe_code)] // calling the `extern "C"` functions in the last test

#[path = "../support/mod.rs"]
mod support;

use deform_kernel::elasticity::{
    deform_incremental, rigid_layer, ElasticSystem, IncrementBuffers, Increments, Modulus,
};
use deform_kernel::spring::SolveOptions;
use deform_kernel::{Error, Quat, Real};
use support::elasticity::{assembled, fnv, grid2, Kind, Mesh};

/// The wall: the nodes on the left side `x = 0`.
fn left_wall<const D: usize>(m: &Mesh<D>) -> Vec<u32> {
    (0..m.points.len() as u32)
        .filter(|&i| m.points[i as usize][0] == 0.0)
        .collect()
}

/// The exact rigid motion `c + R (x − c) − x` of a rotation by `deg` about `c` (f64).
fn rotation(x: [f64; 2], deg: f64, c: [f64; 2]) -> [f64; 2] {
    let (s, co) = deg.to_radians().sin_cos();
    let (u, v) = (x[0] - c[0], x[1] - c[1]);
    [c[0] + co * u - s * v - x[0], c[1] + s * u + co * v - x[1]]
}

/// The wall's displacement (rotation by `deg` about `c`) at the wall nodes, zero elsewhere;
/// `fixed` set on the wall.
fn wall_setup<T: Real>(m: &Mesh<2>, wall: &[u32], deg: f64) -> (Vec<u8>, Vec<[T; 2]>) {
    let n = m.points.len();
    let mut fixed = vec![0u8; n];
    let mut disp = vec![[T::ZERO; 2]; n];
    for &w in wall {
        fixed[w as usize] = 1;
        let d = rotation(m.points[w as usize], deg, [0.3, 0.4]);
        disp[w as usize] = [T::from_f64(d[0]), T::from_f64(d[1])];
    }
    (fixed, disp)
}

fn check_layer<T: Real>(tol: f64) {
    let m = grid2(10, Kind::Mixed, 0.25);
    let wall = left_wall(&m);
    let deg = 40.0;
    let (mut fixed, mut disp) = wall_setup::<T>(&m, &wall, deg);
    let q =
        Quat::from_axis_angle([T::ZERO, T::ZERO, T::ONE], T::from_f64(deg.to_radians())).unwrap();
    let rotations = vec![q; wall.len()];
    let points = m.points_as::<T>();
    let thickness = 0.25;
    let (fixed0, disp0) = (fixed.clone(), disp.clone());
    let added = rigid_layer(
        &points,
        &wall,
        &rotations,
        T::from_f64(thickness),
        &mut fixed,
        &mut disp,
    )
    .unwrap();
    let mut counted = 0;
    for (i, p) in m.points.iter().enumerate() {
        let near = wall
            .iter()
            .map(|&w| {
                let e = [
                    p[0] - m.points[w as usize][0],
                    p[1] - m.points[w as usize][1],
                ];
                (e[0] * e[0] + e[1] * e[1]).sqrt()
            })
            .fold(f64::INFINITY, f64::min);
        if fixed0[i] != 0 {
            assert_eq!(disp[i], disp0[i], "an already fixed node was written");
        } else if near <= thickness {
            counted += 1;
            assert_eq!(fixed[i], 1);
            let exact = rotation(*p, deg, [0.3, 0.4]);
            for c in 0..2 {
                let err = (disp[i][c].to_f64() - exact[c]).abs();
                assert!(err < tol, "node {i}: {err:e}");
            }
        } else {
            assert_eq!(
                (fixed[i], disp[i]),
                (0, [T::ZERO; 2]),
                "node {i} beyond the layer"
            );
        }
    }
    assert_eq!(added, counted);
    assert!(
        added > wall.len(),
        "the layer holds more than one line: {added}"
    );
}

#[test]
fn layer_nodes_get_the_exact_rigid_motion() {
    check_layer::<f64>(1e-15);
    check_layer::<f32>(2e-7);
}

/// Increments with block-Jacobi CG (ν = 0.45, the tool's choice with the layer).
fn increments<T: Real>(
    m: &Mesh<2>,
    fixed: &[u8],
    points: &mut [[T; 2]],
    disp: &[[T; 2]],
    steps: usize,
) {
    let a = assembled(m, points, Modulus::InverseVolume, None, T::from_f64(0.45));
    let cells = m.cells();
    let n = points.len();
    let mut moduli = vec![T::ZERO; cells.len()];
    let mut diag = vec![[[T::ZERO; 2]; 2]; n];
    let mut off = vec![[[T::ZERO; 2]; 2]; a.targets.len()];
    let (mut current, mut step) = (vec![[T::ZERO; 2]; n], vec![[T::ZERO; 2]; n]);
    let mut scratch = vec![[T::ZERO; 2]; 4 * n];
    let params = Increments {
        modulus: Modulus::InverseVolume,
        wall_distance: None,
        poisson: T::from_f64(0.45),
        steps,
    };
    let options = SolveOptions {
        max_iterations: 20_000,
        residual_tol: T::from_f64(1e-13).max(T::from_f64(50.0) * T::EPSILON),
        update_tol: T::ZERO,
    };
    let buffers = IncrementBuffers {
        moduli: &mut moduli,
        diag: &mut diag,
        off: &mut off,
        current: &mut current,
        step: &mut step,
    };
    let r = deform_incremental(
        &cells,
        &a.graph(),
        fixed,
        &params,
        points,
        disp,
        buffers,
        |sys: &ElasticSystem<'_, T, 2>, u: &mut [[T; 2]]| sys.solve(u, &options, &mut scratch),
    )
    .unwrap();
    assert!(r.converged);
}

#[test]
fn a_translated_boundary_and_layer_translate_everything() {
    let m = grid2(8, Kind::Mixed, 0.25);
    let wall = left_wall(&m);
    let n = m.points.len();
    let t = [0.07, -0.03];
    let mut fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
    let mut disp: Vec<[f64; 2]> = (0..n)
        .map(|i| if m.boundary[i] { t } else { [0.0; 2] })
        .collect();
    let rotations = vec![Quat::identity(); wall.len()];
    let added = rigid_layer(&m.points, &wall, &rotations, 0.3, &mut fixed, &mut disp).unwrap();
    assert!(added > 0);
    let mut p = m.points.clone();
    increments(&m, &fixed, &mut p, &disp, 3);
    for (a, b) in p.iter().zip(&m.points) {
        for c in 0..2 {
            assert!((a[c] - b[c] - t[c]).abs() < 1e-13, "{a:?} from {b:?}");
        }
    }
}

/// One bad call of `rigid_layer`: points, wall, rotations, thickness, the expected error.
type Case<'a> = (&'a [[f64; 2]], &'a [u32], &'a [Quat<f64>], f64, Error);

#[test]
fn typed_errors_write_nothing() {
    let m = grid2(4, Kind::Mixed, 0.25);
    let wall = left_wall(&m);
    let (fixed0, disp0) = wall_setup::<f64>(&m, &wall, 30.0);
    let q = vec![Quat::from_rotation_z(0.5); wall.len()];
    let mut bad_point = m.points.clone();
    bad_point[7][1] = f64::NAN;
    let zero = vec![Quat::from_array([0.0; 4]); wall.len()];
    let out_of_range = [0u32, 1000];
    let cases: Vec<Case<'_>> = vec![
        (&m.points, &wall, &q[1..], 0.2, len_err("rotations")),
        (&m.points, &[], &[], 0.2, param_err("wall")),
        (
            &m.points,
            &out_of_range,
            &q[..2],
            0.2,
            Error::IndexOutOfRange {
                arg: "wall",
                position: 1,
                index: 1000,
                bound: m.points.len(),
            },
        ),
        (
            &bad_point,
            &wall,
            &q,
            0.2,
            Error::NonFinite {
                arg: "points",
                position: 7,
            },
        ),
        (
            &m.points,
            &wall,
            &zero,
            0.2,
            Error::ZeroLength {
                arg: "rotations",
                position: 0,
            },
        ),
        (&m.points, &wall, &q, -0.1, param_err("thickness")),
        (&m.points, &wall, &q, f64::NAN, param_err("thickness")),
    ];
    for (points, wall, rotations, thickness, expected) in cases {
        let (mut fixed, mut disp) = (fixed0.clone(), disp0.clone());
        let e = rigid_layer(points, wall, rotations, thickness, &mut fixed, &mut disp);
        assert_eq!(e, Err(expected));
        assert_eq!((fixed, disp), (fixed0.clone(), disp0.clone()));
    }
    let (mut fixed, mut disp) = (fixed0.clone(), disp0.clone());
    let e = rigid_layer(&m.points, &wall, &q, 0.2, &mut fixed[1..], &mut disp);
    assert!(matches!(e, Err(Error::LengthMismatch { arg: "fixed", .. })));
    let mut nan_disp = disp0.clone();
    nan_disp[3][0] = f64::INFINITY;
    let e = rigid_layer(&m.points, &wall, &q, 0.2, &mut fixed, &mut nan_disp);
    assert_eq!(
        e,
        Err(Error::NonFinite {
            arg: "displacement",
            position: 3
        })
    );
    assert_eq!((fixed, disp), (fixed0, disp0));
}

fn len_err(arg: &'static str) -> Error {
    Error::LengthMismatch {
        arg,
        expected: 5,
        actual: 4,
    }
}

fn param_err(arg: &'static str) -> Error {
    match arg {
        "wall" => Error::InvalidParameter {
            arg,
            reason: "must name at least one node",
        },
        _ => Error::InvalidParameter {
            arg,
            reason: "must be finite and not negative",
        },
    }
}

/// The committed output bits of a fixed problem (a 30° rotation of the left wall with a
/// 0.25 layer, 10 increments, inverse-volume moduli, ν = 0.45, block-Jacobi CG): any
/// change in the arithmetic or its order shows here.
#[test]
fn golden_bits() {
    fn run<T: Real>() -> u64 {
        let m = grid2(6, Kind::Mixed, 0.25);
        let wall = left_wall(&m);
        let mut fixed: Vec<u8> = m.boundary.iter().map(|&b| b as u8).collect();
        let mut disp = vec![[T::ZERO; 2]; m.points.len()];
        let (s, c) = (0.5, 0.866_025_403_784_438_6); // 30°, no libm in the inputs
        for &w in &wall {
            let p = m.points[w as usize];
            let (x, y) = (p[0] - 0.3, p[1] - 0.4);
            disp[w as usize] = [
                T::from_f64(c * x - s * y - x),
                T::from_f64(s * x + c * y - y),
            ];
        }
        // cos 15°, sin 15°: the half angle of the 30° rotation, no libm in the inputs.
        let q = Quat::from_array(
            [0.965_925_826_289_068_3, 0.0, 0.0, 0.258_819_045_102_520_74].map(T::from_f64),
        );
        let rotations = vec![q; wall.len()];
        let points = m.points_as::<T>();
        rigid_layer(
            &points,
            &wall,
            &rotations,
            T::from_f64(0.25),
            &mut fixed,
            &mut disp,
        )
        .unwrap();
        let mut p = points.clone();
        increments(&m, &fixed, &mut p, &disp, 10);
        fnv(&p)
    }
    assert_eq!(run::<f64>(), GOLDEN_F64, "f64: {:#x}", run::<f64>());
    assert_eq!(run::<f32>(), GOLDEN_F32, "f32: {:#x}", run::<f32>());
}

const GOLDEN_F64: u64 = 0x1f72_a36a_3a0e_2388;
const GOLDEN_F32: u64 = 0xa081_3a77_bd20_4ed3;

/// The C ABI (called by path) against the kernel, bit for bit: 1-based wall indices, f64 and
/// f32; a negative thickness is `DK_ERR_INVALID_PARAMETER` and writes nothing.
#[test]
fn c_abi_gives_the_kernel_bits() {
    use deform_kernel_ffi::elasticity_layer::{
        dk_elasticity_rigid_layer, dk_elasticity_rigid_layer_f32,
    };
    use deform_kernel_ffi::status::dk_status;
    fn check<T: Real>(
        call: unsafe extern "C" fn(
            *const T,
            usize,
            u32,
            *const u32,
            usize,
            u32,
            *mut u32,
            usize,
            *const T,
            usize,
            T,
            *mut u8,
            usize,
            *mut T,
            usize,
            *mut usize,
        ) -> dk_status,
    ) {
        let m = grid2(7, Kind::Mixed, 0.25);
        let wall = left_wall(&m);
        let (fixed0, disp0) = wall_setup::<T>(&m, &wall, 35.0);
        let q = Quat::from_axis_angle([T::ZERO, T::ZERO, T::ONE], T::from_f64(0.6)).unwrap();
        let rotations = vec![q; wall.len()];
        let points = m.points_as::<T>();
        let (mut fk, mut dk) = (fixed0.clone(), disp0.clone());
        let added = rigid_layer(
            &points,
            &wall,
            &rotations,
            T::from_f64(0.3),
            &mut fk,
            &mut dk,
        )
        .unwrap();
        let one: Vec<u32> = wall.iter().map(|w| w + 1).collect();
        let flat_q: Vec<T> = rotations.iter().flat_map(|q| q.to_array()).collect();
        let flat_p: Vec<T> = points.iter().flatten().copied().collect();
        for (thickness, status) in [
            (-1.0, dk_status::DK_ERR_INVALID_PARAMETER),
            (0.3, dk_status::DK_OK),
        ] {
            let (mut fc, mut dc) = (fixed0.clone(), disp0.clone());
            let mut scratch = vec![0u32; wall.len()];
            let mut count = usize::MAX;
            let s = unsafe {
                call(
                    flat_p.as_ptr(),
                    flat_p.len(),
                    2,
                    one.as_ptr(),
                    one.len(),
                    1,
                    scratch.as_mut_ptr(),
                    scratch.len(),
                    flat_q.as_ptr(),
                    flat_q.len(),
                    T::from_f64(thickness),
                    fc.as_mut_ptr(),
                    fc.len(),
                    dc.as_mut_ptr().cast::<T>(),
                    2 * dc.len(),
                    &mut count,
                )
            };
            assert_eq!(s, status);
            if status == dk_status::DK_OK {
                assert_eq!((count, &fc), (added, &fk));
                let bits = |v: &[[T; 2]]| -> Vec<u64> {
                    v.iter().flatten().map(|x| x.to_bits_u64()).collect()
                };
                assert_eq!(bits(&dc), bits(&dk));
            } else {
                assert_eq!((count, &fc, &dc), (usize::MAX, &fixed0, &disp0));
            }
        }
    }
    check::<f64>(dk_elasticity_rigid_layer);
    check::<f32>(dk_elasticity_rigid_layer_f32);
}
