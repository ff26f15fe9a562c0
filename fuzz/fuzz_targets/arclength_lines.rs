//! Target 7: arclength functions, redistribution and Alter's smoothing driver on arbitrary
//! small 2D blocks with monotone i-lines (zero-length segments included): arclength is
//! non-decreasing from 0 (and ends at 1 when normalised); after redistribution to monotone
//! targets, and after smoothing (last line ends fixed or free), lines stay monotone and first
//! ends stay; otherwise a typed error leaves the points unchanged.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::taubin::{
    arclength, redistribute, redistribute_scratch_len, smooth_arclength,
    smooth_arclength_scratch_len, LineEnd, SmoothOptions,
};
use deform_kernel::Direction;
use deform_kernel::{Block, Error};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    ni: u8,
    nj: u8,
    steps: Vec<u8>,
    wiggle: Vec<i8>,
    targets: Vec<u8>,
    normalised: bool,
    iterations: u8,
    free_end: bool,
}

fn monotone_lines(block: &Block, pts: &[[f64; 2]], normalised: bool) -> bool {
    let mut s = vec![0.0; pts.len()];
    arclength(block, pts, Direction::I, normalised, &mut s).unwrap();
    let [ni, nj, _] = block.dims();
    (0..nj).all(|j| s[j * ni..(j + 1) * ni].windows(2).all(|w| w[1] >= w[0]) && s[j * ni] == 0.0)
}

fuzz_target!(|inp: Input| {
    let (ni, nj) = ((inp.ni % 9) as usize + 2, (inp.nj % 4) as usize + 1);
    let block = Block::new([ni, nj, 1]).unwrap();
    let n = ni * nj;
    let mut points = vec![[0.0f64; 2]; n];
    for j in 0..nj {
        let mut x = 0.0;
        for i in 0..ni {
            let k = i + ni * j;
            if i > 0 {
                x += f64::from(inp.steps.get(k).copied().unwrap_or(1)) / 16.0;
            }
            let w = f64::from(inp.wiggle.get(k).copied().unwrap_or(0)) / 512.0;
            points[k] = [x, j as f64 + w];
        }
    }
    let mut s = vec![0.0; n];
    arclength(&block, &points, Direction::I, inp.normalised, &mut s).unwrap();
    for j in 0..nj {
        let line = &s[j * ni..(j + 1) * ni];
        assert_eq!(line[0], 0.0);
        assert!(line.windows(2).all(|w| w[1] >= w[0]));
        if inp.normalised && line[ni - 1] > 0.0 {
            assert!((line[ni - 1] - 1.0).abs() <= 1e-15);
        }
    }

    // Redistribute to monotone targets (sorted bytes scaled to each line's length).
    let mut t = vec![0.0; n];
    for j in 0..nj {
        let total = if inp.normalised {
            1.0
        } else {
            s[j * ni + ni - 1]
        };
        let mut v: Vec<f64> = (0..ni)
            .map(|i| f64::from(inp.targets.get(i + ni * j).copied().unwrap_or(0)) / 255.0 * total)
            .collect();
        v.sort_by(f64::total_cmp);
        t[j * ni..(j + 1) * ni].copy_from_slice(&v);
    }
    let mut moved = points.clone();
    let mut scratch = vec![0.0; redistribute_scratch_len::<2>(&block, Direction::I)];
    match redistribute(
        &block,
        &mut moved,
        Direction::I,
        &t,
        inp.normalised,
        &mut scratch,
    ) {
        Ok(d) => {
            assert!(d.is_finite());
            assert!(moved.iter().all(|p| p[0].is_finite() && p[1].is_finite()));
            assert!(monotone_lines(&block, &moved, false));
        }
        Err(_) => assert_eq!(moved, points),
    }

    // Alter's driver: smooth the arclength functions and redistribute.
    let mut smoothed = points.clone();
    let mut opts = SmoothOptions::new(Direction::I);
    opts.normalised = inp.normalised;
    opts.iterations = (inp.iterations % 40) as usize;
    if inp.free_end {
        opts.ends[1] = LineEnd::Free;
    }
    let mut scratch = vec![0.0; smooth_arclength_scratch_len::<2>(&block, Direction::I, None)];
    match smooth_arclength(&block, &mut smoothed, &opts, &mut scratch) {
        Ok(r) => {
            assert!(r.max_displacement.is_finite());
            assert!(monotone_lines(&block, &smoothed, false));
            for j in 0..nj {
                assert_eq!(smoothed[j * ni], points[j * ni]);
                if !inp.free_end {
                    assert_eq!(smoothed[j * ni + ni - 1], points[j * ni + ni - 1]);
                }
            }
        }
        Err(
            Error::FoldedLine { .. } | Error::InvalidParameter { .. } | Error::ZeroLength { .. },
        ) => {
            assert_eq!(smoothed, points)
        }
        Err(e) => {
            assert_eq!(smoothed, points, "{e:?}");
        }
    }
});
