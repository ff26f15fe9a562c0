//! Target 5: the quaternion deformation (Samareh) of arbitrary small boundary motions of a
//! structured triangle mesh, with arbitrary per-node boundary rotations: no panic, no NaN from
//! finite input, and every boundary node reproduced bit for bit.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::quaternion::{
    deform_idw, deform_idw_scratch_len, BoundaryMotion, RotationSource,
};
use deform_kernel::Quat;
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    nx: u8,
    ny: u8,
    moves: Vec<[i8; 2]>,
    angles: Vec<i8>,
    exponent: u8,
}

fuzz_target!(|inp: Input| {
    let (nx, ny) = ((inp.nx % 6) as usize + 2, (inp.ny % 6) as usize + 2);
    let n = nx * ny;
    let points: Vec<[f64; 2]> = (0..n)
        .map(|p| [(p % nx) as f64, (p / nx) as f64 * 0.7])
        .collect();
    let boundary: Vec<u32> = (0..n)
        .filter(|&p| p % nx == 0 || p % nx == nx - 1 || p / nx == 0 || p / nx == ny - 1)
        .map(|p| p as u32)
        .collect();
    let b = boundary.len();
    let deformed: Vec<[f64; 2]> = boundary
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let m = inp.moves.get(k).copied().unwrap_or([0, 0]);
            let q = points[p as usize];
            [
                q[0] + f64::from(m[0]) / 100.0,
                q[1] + f64::from(m[1]) / 100.0,
            ]
        })
        .collect();
    let rotations_b: Vec<Quat<f64>> = (0..b)
        .map(|k| Quat::from_rotation_z(f64::from(inp.angles.get(k).copied().unwrap_or(0)) / 100.0))
        .collect();
    let motion = BoundaryMotion {
        nodes: &boundary,
        deformed: &deformed,
        elements: None,
        rotations: RotationSource::PerNode(&rotations_b),
        origin: None,
    };
    let mut translations = vec![[0.0; 2]; n];
    let mut rotations = vec![Quat::identity(); n];
    let mut scratch = vec![0.0; deform_idw_scratch_len::<2>(n, b)];
    let mut out = vec![[f64::NAN; 2]; n];
    let exponent = 1.0 + f64::from(inp.exponent % 5);
    deform_idw(
        &points,
        &motion,
        exponent,
        &mut translations,
        &mut rotations,
        &mut scratch,
        &mut out,
    )
    .unwrap();
    for (k, &p) in boundary.iter().enumerate() {
        assert_eq!(
            out[p as usize].map(f64::to_bits),
            deformed[k].map(f64::to_bits)
        );
    }
    assert!(out.iter().all(|x| x[0].is_finite() && x[1].is_finite()));
});
