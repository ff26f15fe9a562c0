//! Alter's two applications on the shared test grids from `deform-meshgen`: stretching
//! reduction on the cavity grids (jump 3.25, the paper's value) and smoothing of a rough
//! (noisy) volume grid along k.

use deform_kernel::taubin::{
    arclength, smooth_arclength, smooth_arclength_scratch_len, SmoothOptions,
};
use deform_kernel::Block;
use deform_kernel::Direction;
use deform_meshgen::{cavity2, cavity3, noisy_block3, BlockSpec};

fn smooth<const D: usize>(
    dims: [usize; 3],
    points: &mut [[f64; D]],
    opts: &SmoothOptions<f64>,
) -> deform_kernel::taubin::SmoothReport<f64> {
    let block = Block::new(dims).unwrap();
    let mut scratch =
        vec![0.0; smooth_arclength_scratch_len::<D>(&block, opts.direction, opts.coarse.as_ref())];
    smooth_arclength(&block, points, opts, &mut scratch).unwrap()
}

#[test]
fn meshgen_cavity_stretching_3_25() {
    // Normalised arclength along i (streamwise), 30 iterations, as in Alter §III.C.
    let m2 = cavity2(61, 9, 3.25).unwrap();
    let m3 = cavity3(61, 9, 6, 3.25).unwrap();
    let mut rows = Vec::new();
    for its in [30usize, 90] {
        let mut o = SmoothOptions::new(Direction::I);
        o.normalised = true;
        o.iterations = its;
        let mut p2 = m2.points.clone();
        let r2 = smooth(m2.dims.unwrap(), &mut p2, &o);
        let mut p3 = m3.points.clone();
        let r3 = smooth(m3.dims.unwrap(), &mut p3, &o);
        rows.push((its, r2, r3));
    }
    for (its, r2, r3) in &rows {
        println!(
            "cavity jump 3.25, {its} iterations: 2D 61x9 {:.3} -> {:.3} (move {:.2e}), 3D 61x9x6 {:.3} -> {:.3} (move {:.2e}); length 4",
            r2.stretching_before.0, r2.stretching_after.0, r2.max_displacement,
            r3.stretching_before.0, r3.stretching_after.0, r3.max_displacement
        );
    }
    let (_, r2, r3) = &rows[0];
    assert!((r2.stretching_before.0 - 3.25).abs() < 1e-9);
    assert!((r3.stretching_before.0 - 3.25).abs() < 1e-9);
    // A substantial drop, with points moving by a small fraction of the length (4).
    assert!(r2.stretching_after.0 < 0.75 * 3.25);
    assert!(r3.stretching_after.0 < 0.75 * 3.25);
    assert!(r2.max_displacement < 0.05 && r3.max_displacement < 0.05);
    // More iterations keep lowering the peak.
    assert!(rows[1].1.stretching_after.0 < r2.stretching_after.0);
}

/// Mean |avg(S) − S| over interior points: the high-frequency content of the k-arclength
/// field (the "roughness" of Alter's fig. 6).
fn roughness(dims: [usize; 3], s: &[f64]) -> f64 {
    let [ni, nj, nk] = dims;
    let at = |i: usize, j: usize, k: usize| s[i + ni * (j + nj * k)];
    let mut sum = 0.0;
    let mut count = 0;
    for k in 1..nk - 1 {
        for j in 1..nj - 1 {
            for i in 1..ni - 1 {
                let avg = (at(i - 1, j, k)
                    + at(i + 1, j, k)
                    + at(i, j - 1, k)
                    + at(i, j + 1, k)
                    + at(i, j, k - 1)
                    + at(i, j, k + 1))
                    / 6.0;
                sum += (avg - at(i, j, k)).abs();
                count += 1;
            }
        }
    }
    sum / count as f64
}

#[test]
fn meshgen_noisy_block_k_arclength_roughness() {
    let spec = BlockSpec {
        dims: [17, 15, 21],
        lengths: [2.0, 2.0, 1.0],
        ratios: [1.0, 1.0, 1.12],
    };
    let mesh = noisy_block3(&spec, 0.3, 7).unwrap();
    let clean = deform_meshgen::block3(&spec).unwrap();
    let dims = mesh.dims.unwrap();
    let block = Block::new(dims).unwrap();
    let s_of = |p: &[[f64; 3]]| {
        let mut s = vec![0.0; p.len()];
        arclength(&block, p, Direction::K, false, &mut s).unwrap();
        s
    };
    let r_clean = roughness(dims, &s_of(&clean.points));
    let r0 = roughness(dims, &s_of(&mesh.points));
    let mut p = mesh.points.clone();
    let rep = smooth(dims, &mut p, &SmoothOptions::new(Direction::K));
    let r1 = roughness(dims, &s_of(&p));
    println!(
        "noisy 17x15x21 block, k-arclength roughness: clean grid {r_clean:.3e}, noisy {r0:.3e}, after 30 iterations {r1:.3e}; max move {:.3e}",
        rep.max_displacement
    );
    assert!(r1 < 0.5 * r0);
}
