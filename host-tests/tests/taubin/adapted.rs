//! Alter's own case (issue 33): a solution-adapted grid with a rough outer boundary, smoothed
//! along k with a free outer end, checked against an independent numpy implementation of his
//! filter (ref_alter.py beside this file); and the fixed-end mode on the same grids.

#[path = "../support/python.rs"]
mod python;

use deform_kernel::taubin::{
    arclength, smooth_arclength, smooth_arclength_scratch_len, LineEnd, SmoothOptions,
};
use deform_kernel::{Block, Direction, Error};
use deform_meshgen::{adapted_block, AdaptedSpec};

type P3 = [f64; 3];

/// Smooths along k with the paper's settings and the given last end.
fn smooth(
    dims: [usize; 3],
    points: &mut [P3],
    last: LineEnd,
    fixed: Option<&[u8]>,
) -> Result<(), Error> {
    let block = Block::new(dims).unwrap();
    let mut o = SmoothOptions::new(Direction::K);
    o.ends = [LineEnd::Fixed, last];
    o.fixed = fixed;
    let mut scratch = vec![0.0; smooth_arclength_scratch_len::<3>(&block, Direction::K, None)];
    smooth_arclength(&block, points, &o, &mut scratch).map(|_| ())
}

/// The k-arclength at the outer boundary, `S(i, j, nk − 1)`, i fastest.
fn outer_arclength(dims: [usize; 3], points: &[P3]) -> Vec<f64> {
    let block = Block::new(dims).unwrap();
    let mut s = vec![0.0; points.len()];
    arclength(&block, points, Direction::K, false, &mut s).unwrap();
    let face = dims[0] * dims[1];
    s[face * (dims[2] - 1)..].to_vec()
}

/// RMS over the interior of the face of the 5-point Laplacian of `f` (`ni × nj`).
fn roughness(f: &[f64], ni: usize, nj: usize) -> f64 {
    let mut sum = 0.0;
    let mut count = 0.0;
    for j in 1..nj - 1 {
        for i in 1..ni - 1 {
            let c = i + ni * j;
            let l = f[c - 1] + f[c + 1] + f[c - ni] + f[c + ni] - 4.0 * f[c];
            sum += l * l;
            count += 1.0;
        }
    }
    (sum / count).sqrt()
}

/// The 8 corner Jacobians (triple products of the three edges at each corner) of every hex.
fn corner_jacobians(dims: [usize; 3], p: &[P3]) -> Vec<[f64; 8]> {
    let [ni, nj, nk] = dims;
    let at = |i: usize, j: usize, k: usize| p[i + ni * (j + nj * k)];
    let sub = |a: P3, b: P3| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let triple = |a: P3, b: P3, c: P3| {
        a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    };
    let mut out = Vec::new();
    for k in 0..nk - 1 {
        for j in 0..nj - 1 {
            for i in 0..ni - 1 {
                let mut cj = [0.0; 8];
                for (c, v) in cj.iter_mut().enumerate() {
                    let (di, dj, dk) = (c & 1, (c >> 1) & 1, c >> 2);
                    let o = at(i + di, j + dj, k + dk);
                    // Edges towards the other corner in each direction, signed so that a
                    // right-handed cell is positive at every corner.
                    let si = if di == 0 { 1.0 } else { -1.0 };
                    let sj = if dj == 0 { 1.0 } else { -1.0 };
                    let sk = if dk == 0 { 1.0 } else { -1.0 };
                    let ei = sub(at(i + 1 - di, j + dj, k + dk), o);
                    let ej = sub(at(i + di, j + 1 - dj, k + dk), o);
                    let ek = sub(at(i + di, j + dj, k + 1 - dk), o);
                    *v = si * sj * sk * triple(ei, ej, ek);
                }
                out.push(cj);
            }
        }
    }
    out
}

/// The volume of the block: the sum over hexes of the mean corner Jacobian (exact for
/// parallelepipeds; a consistent measure for the small changes compared here).
fn volume(dims: [usize; 3], p: &[P3]) -> f64 {
    corner_jacobians(dims, p)
        .iter()
        .map(|c| c.iter().sum::<f64>() / 8.0)
        .sum()
}

/// Writes `dims` and `points` for ref_alter.py.
fn write_grid(path: &std::path::Path, dims: [usize; 3], points: &[P3]) {
    let mut bytes = Vec::new();
    for d in dims {
        bytes.extend_from_slice(&(d as u64).to_le_bytes());
    }
    for x in points.iter().flatten() {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    std::fs::write(path, bytes).unwrap();
}

/// Runs ref_alter.py (30 iterations, the paper's λ, μ) on `points`; its smoothed points.
fn numpy_reference(name: &str, dims: [usize; 3], points: &[P3]) -> Vec<P3> {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let (src, dst) = (
        dir.join(format!("{name}.in")),
        dir.join(format!("{name}.out")),
    );
    write_grid(&src, dims, points);
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/taubin/ref_alter.py");
    python::run_script(
        &script,
        &[src.to_str().unwrap(), dst.to_str().unwrap(), "30"],
    );
    let bytes = std::fs::read(&dst).unwrap();
    let v: Vec<f64> = bytes
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Whether the k-arclength increases strictly along every line.
fn lines_increasing(dims: [usize; 3], points: &[P3]) -> bool {
    let block = Block::new(dims).unwrap();
    let mut s = vec![0.0; points.len()];
    arclength(&block, points, Direction::K, false, &mut s).unwrap();
    let face = dims[0] * dims[1];
    (face..s.len()).all(|p| s[p] > s[p - face])
}

/// Whether every corner Jacobian of every cell is positive.
fn no_flipped_cell(dims: [usize; 3], points: &[P3]) -> bool {
    corner_jacobians(dims, points)
        .iter()
        .flatten()
        .all(|&j| j > 0.0)
}

/// The generated adapted grids: the 65 × 49 × 65 and a smaller one, other noise.
fn grids() -> Vec<(AdaptedSpec, Vec<P3>)> {
    [
        AdaptedSpec::default(),
        AdaptedSpec {
            dims: [41, 33, 49],
            seed: 7,
            ..AdaptedSpec::default()
        },
    ]
    .into_iter()
    .map(|spec| (spec, adapted_block(&spec).unwrap()))
    .collect()
}

#[test]
fn free_outer_end_reproduces_alters_filter_on_adapted_grids() {
    for (n, (spec, grid)) in grids().into_iter().enumerate() {
        let dims = spec.dims;
        let face = dims[0] * dims[1];
        assert!(no_flipped_cell(dims, &grid) && lines_increasing(dims, &grid));
        let mut smoothed = grid.clone();
        smooth(dims, &mut smoothed, LineEnd::Free, None).unwrap();
        // Against the independent numpy implementation of the paper.
        let reference = numpy_reference(&format!("adapted{n}"), dims, &grid);
        let worst = smoothed
            .iter()
            .zip(&reference)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0, f64::max);
        assert!(worst <= 1e-12, "{dims:?}: kernel vs numpy {worst:e}");
        // The wall never moves; the outer boundary does.
        assert_eq!(smoothed[..face], grid[..face]);
        assert_ne!(
            smoothed[face * (dims[2] - 1)..],
            grid[face * (dims[2] - 1)..]
        );
        let before = roughness(&outer_arclength(dims, &grid), dims[0], dims[1]);
        let after = roughness(&outer_arclength(dims, &smoothed), dims[0], dims[1]);
        let dv = (volume(dims, &smoothed) / volume(dims, &grid) - 1.0).abs();
        println!(
            "{dims:?}: outer roughness {before:.3e} -> {after:.3e} ({:.2}x), volume change {:.2e} %, kernel vs numpy {worst:.1e}",
            before / after,
            100.0 * dv
        );
        assert!(before >= 9.0 * after, "roughness cut {}", before / after);
        assert!(dv <= 1e-4, "volume change {dv:e}");
        assert!(lines_increasing(dims, &smoothed), "a line folded");
        assert!(no_flipped_cell(dims, &smoothed), "a cell flipped");
    }
}

/// Item 2 of the issue: holding the rough far face in the filter (what the fixed-end mode
/// did, reproduced here by pinning that face) folds the lines under it; filtering the face
/// and mapping each line onto its original ends keeps every line the free filter keeps
/// increasing, with the wall and the outer face bitwise in place.
#[test]
fn fixed_ends_keep_monotone_what_the_free_filter_keeps_monotone() {
    for (spec, grid) in grids() {
        let dims = spec.dims;
        let face = dims[0] * dims[1];
        let outer = face * (dims[2] - 1);
        let mut pins = vec![0u8; grid.len()];
        pins[outer..].fill(1);
        let mut held = grid.clone();
        let err = smooth(dims, &mut held, LineEnd::Fixed, Some(&pins)).unwrap_err();
        println!("{dims:?}: far face held in the filter: {err}");
        assert!(matches!(err, Error::FoldedLine { iteration, .. } if iteration < 30));
        assert_eq!(held, grid, "nothing written on a fold");

        let mut free = grid.clone();
        smooth(dims, &mut free, LineEnd::Free, None).unwrap();
        let mut fixed = grid.clone();
        smooth(dims, &mut fixed, LineEnd::Fixed, None).unwrap();
        assert_eq!(fixed[..face], grid[..face], "wall");
        assert_eq!(fixed[outer..], grid[outer..], "outer face");
        assert!(lines_increasing(dims, &fixed) && no_flipped_cell(dims, &fixed));
        assert_ne!(fixed, grid);
    }
}

/// An O-grid shell around the z axis: i around (i = 0 and i = ni − 1 coincide bit for bit:
/// the seam), j along the axis, k outward over rough line lengths.
fn o_grid(dims: [usize; 3]) -> Vec<P3> {
    let [ni, nj, nk] = dims;
    let mut rng = deform_meshgen::rng::XorShift64::new(5);
    let rough: Vec<f64> = (0..(ni - 1) * nj).map(|_| 0.01 * rng.symmetric()).collect();
    let mut p = vec![[0.0; 3]; ni * nj * nk];
    for k in 0..nk {
        let u = (k as f64 / (nk - 1) as f64).powf(1.5);
        for j in 0..nj {
            for i in 0..ni {
                let a = i % (ni - 1);
                let phi = 2.0 * std::f64::consts::PI * a as f64 / (ni - 1) as f64;
                let r = 1.0 + u * (1.0 + rough[a + (ni - 1) * j]);
                p[i + ni * (j + nj * k)] = [r * phi.cos(), r * phi.sin(), 0.2 * j as f64];
            }
        }
    }
    p
}

#[test]
fn free_ends_on_a_seam_are_refused_and_fixed_ends_keep_seams_and_faces_in_place() {
    let dims = [33, 9, 17];
    let [ni, nj, nk] = dims;
    let grid = o_grid(dims);
    let mut p = grid.clone();
    let err = smooth(dims, &mut p, LineEnd::Free, None).unwrap_err();
    // The first rim pair found: line (0, 0) and line (ni − 1, 0) of the outer face.
    let outer = ni * nj * (nk - 1);
    assert_eq!(
        err,
        Error::SharedFreeEnd {
            point: outer,
            other: outer + ni - 1
        }
    );
    assert!(err.to_string().contains("keep that end fixed"), "{err}");
    assert_eq!(p, grid, "nothing written");

    smooth(dims, &mut p, LineEnd::Fixed, None).unwrap();
    assert_ne!(p, grid);
    for k in 0..nk {
        for j in 0..nj {
            let row = ni * (j + nj * k);
            assert_eq!(p[row], p[row + ni - 1], "seam open at j = {j}, k = {k}");
        }
    }
    assert_eq!(p[..ni * nj], grid[..ni * nj], "wall");
    assert_eq!(p[outer..], grid[outer..], "outer face");
    assert!(lines_increasing(dims, &p));
}

#[test]
fn end_modes_that_cannot_hold_are_typed_errors() {
    let spec = AdaptedSpec {
        dims: [9, 7, 11],
        ..AdaptedSpec::default()
    };
    let grid = adapted_block(&spec).unwrap();
    let block = Block::new(spec.dims).unwrap();
    let mut scratch = vec![0.0; smooth_arclength_scratch_len::<3>(&block, Direction::K, None)];
    let mut bad = |ends: [LineEnd; 2], normalised: bool| {
        let mut o = SmoothOptions::new(Direction::K);
        o.ends = ends;
        o.normalised = normalised;
        let mut p = grid.clone();
        let err = smooth_arclength(&block, &mut p, &o, &mut scratch).unwrap_err();
        assert_eq!(p, grid, "nothing written");
        err
    };
    for (ends, normalised) in [
        ([LineEnd::Free, LineEnd::Fixed], false),
        ([LineEnd::Free, LineEnd::Free], false),
        ([LineEnd::Fixed, LineEnd::Free], true),
    ] {
        let err = bad(ends, normalised);
        assert!(
            matches!(
                err,
                Error::InvalidParameter {
                    arg: "options.ends",
                    ..
                }
            ),
            "{ends:?} {normalised}: {err}"
        );
    }
    // Normalised with fixed ends is accepted, and the free end accepts this grid.
    let mut p = grid.clone();
    let mut o = SmoothOptions::new(Direction::K);
    o.normalised = true;
    smooth_arclength(&block, &mut p, &o, &mut scratch).unwrap();
    smooth(spec.dims, &mut grid.clone(), LineEnd::Free, None).unwrap();
}
