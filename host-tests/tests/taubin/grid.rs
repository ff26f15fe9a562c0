//! Alter's grid tools: arclength functions, redistribution, stretching, the whole-grid driver
//! (cavity stretching test, smooth-grid volume test, fold guard, coarse pass, multi-block
//! interfaces) and input errors.

use deform_host_tests::taubin_ref;
use deform_kernel::taubin::{
    arclength, check_lines_increasing, max_stretching, redistribute, redistribute_scratch_len,
    smooth_arclength, smooth_arclength_scratch_len, smooth_structured, stretching, Coarse, LineEnd,
    Prolongation, SmoothOptions, SmoothReport, StructuredOptions, TaubinParams,
};
use deform_kernel::Direction;
use deform_kernel::{Block, Error};
use proptest::prelude::*;

type P3 = [f64; 3];

fn grid(dims: [usize; 3], f: impl Fn(usize, usize, usize) -> P3) -> Vec<P3> {
    let mut out = Vec::new();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                out.push(f(i, j, k));
            }
        }
    }
    out
}

fn bits(p: &[P3]) -> Vec<u64> {
    p.iter().flatten().map(|c| c.to_bits()).collect()
}

fn run_smooth(
    dims: [usize; 3],
    points: &mut [P3],
    opts: &SmoothOptions<f64>,
) -> deform_kernel::Result<SmoothReport<f64>> {
    let block = Block::new(dims).unwrap();
    let mut scratch =
        vec![0.0; smooth_arclength_scratch_len::<3>(&block, opts.direction, opts.coarse.as_ref())];
    smooth_arclength(&block, points, opts, &mut scratch)
}

/// Cell lengths of the cavity line: near each end 10 cells growing geometrically by 1.08,
/// then an abrupt jump by 3.3 into 40 uniform cells (total normalised to `length`).
fn cavity_cells(length: f64) -> Vec<f64> {
    let mut cells: Vec<f64> = (0..10).map(|t| 1.08f64.powi(t)).collect();
    let big = cells[9] * 3.3;
    cells.extend(std::iter::repeat_n(big, 40));
    cells.extend((0..10).rev().map(|t| 1.08f64.powi(t)));
    let total: f64 = cells.iter().sum();
    cells.iter().map(|c| c * length / total).collect()
}

fn line_from_cells(cells: &[f64]) -> Vec<f64> {
    let mut x = vec![0.0];
    for c in cells {
        x.push(x.last().unwrap() + c);
    }
    x
}

#[test]
fn cavity_stretching_peaks_drop_while_points_barely_move_1d() {
    let x = line_from_cells(&cavity_cells(1.0));
    let n = x.len();
    let dims = [n, 1, 1];
    let block = Block::new(dims).unwrap();
    let orig: Vec<P3> = x.iter().map(|&v| [v, 0.0, 0.0]).collect();
    let mut before = vec![0.0; n];
    stretching(&block, &orig, Direction::I, &mut before).unwrap();
    let mut pts = orig.clone();
    let mut opts = SmoothOptions::new(Direction::I);
    opts.normalised = true;
    let report = run_smooth(dims, &mut pts, &opts).unwrap();
    let mut after = vec![0.0; n];
    stretching(&block, &pts, Direction::I, &mut after).unwrap();
    let peak = |s: &[f64], r: std::ops::Range<usize>| s[r].iter().cloned().fold(0.0, f64::max);
    let h = n / 2;
    let min_cell = cavity_cells(1.0).iter().cloned().fold(f64::MAX, f64::min);
    println!(
        "cavity 1D ({n} points): stretching peaks before {:.3} / {:.3}, after 30 iterations {:.3} / {:.3} \
         (paper: 3.25 -> 1.55); max point move {:.3e} of the line length = {:.2} smallest cells",
        peak(&before, 0..h), peak(&before, h..n), peak(&after, 0..h), peak(&after, h..n),
        report.max_displacement, report.max_displacement / min_cell
    );
    assert!((peak(&before, 0..h) - 3.3).abs() < 1e-9 && (peak(&before, h..n) - 3.3).abs() < 1e-9);
    assert_eq!(report.stretching_before.0, peak(&before, 0..n));
    assert_eq!(report.stretching_after.0, peak(&after, 0..n));
    // Substantial drop at both ends (the paper halved its peak).
    assert!(peak(&after, 0..h) < 2.0 && peak(&after, h..n) < 2.0);
    // Points barely move: under 1 % of the line length, and the ends not at all.
    assert!(report.max_displacement < 0.01);
    assert_eq!(pts[0], orig[0]);
    assert_eq!(pts[n - 1], orig[n - 1]);
    // Iteration history of the peak (printed for docs/taubin.md).
    for its in [1usize, 5, 10, 30, 100] {
        let mut p = orig.clone();
        let mut o = SmoothOptions::new(Direction::I);
        o.normalised = true;
        o.iterations = its;
        let r = run_smooth(dims, &mut p, &o).unwrap();
        println!(
            "  {its:3} iterations: peak {:.3}, max move {:.3e}",
            r.stretching_after.0, r.max_displacement
        );
    }
}

#[test]
fn cavity_block_3d_with_varying_lines() {
    // 61 × 6 × 5 block: i-lines follow the cavity distribution, lengths vary smoothly from
    // line to line, and the lines are slightly curved (a parabola in z).
    let dims = [61, 6, 5];
    let pts = grid(dims, |i, j, k| {
        let len = 1.0 + 0.05 * j as f64 + 0.03 * k as f64;
        let x = line_from_cells(&cavity_cells(len))[i];
        [x, 0.2 * j as f64, 0.2 * k as f64 + 0.1 * x * (len - x)]
    });
    let mut smoothed = pts.clone();
    let mut opts = SmoothOptions::new(Direction::I);
    opts.normalised = true;
    let r = run_smooth(dims, &mut smoothed, &opts).unwrap();
    println!(
        "cavity 3D {dims:?}: max stretching {:.3} -> {:.3}, max point move {:.3e}",
        r.stretching_before.0, r.stretching_after.0, r.max_displacement
    );
    assert!(r.stretching_before.0 > 3.2);
    // Inside a 3D block only 2 of the 6 stencil neighbours lie along the line, so the
    // along-line smoothing per iteration is a third of the 1D one: the peak drops less.
    assert!(r.stretching_after.0 < 0.7 * r.stretching_before.0);
    assert!(r.max_displacement < 0.012);
    for its in [60usize, 100, 200] {
        let mut p = pts.clone();
        let mut o = SmoothOptions::new(Direction::I);
        o.normalised = true;
        o.iterations = its;
        let r = run_smooth(dims, &mut p, &o).unwrap();
        println!(
            "  {its:3} iterations: peak {:.3}, max move {:.3e}",
            r.stretching_after.0, r.max_displacement
        );
    }
    // Both line ends stay where they were (normalised arclength 0 and 1 are kept exactly).
    let block = Block::new(dims).unwrap();
    for k in 0..5 {
        for j in 0..6 {
            for i in [0, 60] {
                let p = block.index(i, j, k);
                assert_eq!(smoothed[p], pts[p]);
            }
        }
    }
}

/// Volume enclosed by the boundary of a structured 3D block, every boundary quad split into
/// two triangles: `V = (1/6) Σ ± a · (b × c)`.
fn enclosed_volume(dims: [usize; 3], p: &[P3]) -> f64 {
    let idx = |i: usize, j: usize, k: usize| p[i + dims[0] * (j + dims[1] * k)];
    let triple = |a: P3, b: P3, c: P3| {
        a[0] * (b[1] * c[2] - b[2] * c[1])
            + a[1] * (b[2] * c[0] - b[0] * c[2])
            + a[2] * (b[0] * c[1] - b[1] * c[0])
    };
    let mut v = 0.0;
    for d in 0..3 {
        let (e, f) = ((d + 1) % 3, (d + 2) % 3);
        for (face, sign) in [(0usize, -1.0), (dims[d] - 1, 1.0)] {
            for u in 0..dims[e] - 1 {
                for w in 0..dims[f] - 1 {
                    let at = |du: usize, dw: usize| {
                        let mut ijk = [0; 3];
                        ijk[d] = face;
                        ijk[e] = u + du;
                        ijk[f] = w + dw;
                        idx(ijk[0], ijk[1], ijk[2])
                    };
                    let (a, b, c, q) = (at(0, 0), at(1, 0), at(1, 1), at(0, 1));
                    v += sign * (triple(a, b, c) + triple(a, c, q)) / 6.0;
                }
            }
        }
    }
    v
}

/// A smooth curved block: a 60° sector of a thick cylindrical shell, radial spacing growing
/// geometrically.
fn shell(dims: [usize; 3]) -> Vec<P3> {
    grid(dims, |i, j, k| {
        let s = (1.15f64.powi(i as i32) - 1.0) / (1.15f64.powi(dims[0] as i32 - 1) - 1.0);
        let r = 1.0 + s;
        let t = std::f64::consts::FRAC_PI_3 * j as f64 / (dims[1] - 1) as f64;
        [r * t.cos(), r * t.sin(), k as f64 / (dims[2] - 1) as f64]
    })
}

#[test]
fn smooth_grid_keeps_its_volume_with_lambda_mu_and_shrinks_with_lambda_only() {
    let dims = [21, 41, 11];
    let block = Block::new(dims).unwrap();
    let pts = shell(dims);
    let v0 = enclosed_volume(dims, &pts);
    let exact = std::f64::consts::FRAC_PI_3 / 2.0 * (4.0 - 1.0);
    assert!(
        (v0 - exact).abs() / exact < 2e-3,
        "polyhedral volume {v0} vs {exact}"
    );
    // The coordinates themselves filtered as three scalar fields (Taubin's setting).
    let filter = |params: TaubinParams<f64>| {
        let n = pts.len();
        let mut out = pts.clone();
        let mut scratch = vec![0.0; n];
        for c in 0..3 {
            let mut f: Vec<f64> = pts.iter().map(|p| p[c]).collect();
            smooth_structured(
                &block,
                &mut f,
                params,
                30,
                &StructuredOptions::default(),
                &mut scratch,
            )
            .unwrap();
            for (o, v) in out.iter_mut().zip(&f) {
                o[c] = *v;
            }
        }
        (enclosed_volume(dims, &out) - v0) / v0
    };
    let taubin = filter(TaubinParams::paper());
    let lambda_only = filter(TaubinParams {
        lambda: 0.330,
        mu: 0.0,
    });
    // The arclength driver on the same grid, all three directions in turn.
    let mut driven = pts.clone();
    let mut moved: f64 = 0.0;
    for d in 0..3 {
        let r = run_smooth(dims, &mut driven, &SmoothOptions::new(Direction::ALL[d])).unwrap();
        moved = moved.max(r.max_displacement);
    }
    let driver = (enclosed_volume(dims, &driven) - v0) / v0;
    let mut driven_l = pts.clone();
    let mut moved_l: f64 = 0.0;
    for d in 0..3 {
        let mut o = SmoothOptions::new(Direction::ALL[d]);
        o.params = TaubinParams {
            lambda: 0.330,
            mu: 0.0,
        };
        moved_l = moved_l.max(
            run_smooth(dims, &mut driven_l, &o)
                .unwrap()
                .max_displacement,
        );
    }
    let driver_l = (enclosed_volume(dims, &driven_l) - v0) / v0;
    println!(
        "shell sector {dims:?}, 30 iterations, relative volume change:\n  coordinates filtered: λ|μ {taubin:+.3e}, λ-only {lambda_only:+.3e}\n  \
         arclength driver (i, j, k): λ|μ {driver:+.3e} (max move {moved:.2e}), λ-only {driver_l:+.3e} (max move {moved_l:.2e})"
    );
    assert!(taubin.abs() <= 1e-4);
    assert!(lambda_only < -1e-3);
    assert!(driver.abs() <= 1e-4);
    assert!(moved < moved_l);
}

#[test]
fn fold_guard_stops_on_a_violent_jump_and_leaves_the_grid_alone() {
    // One cell 100× its neighbours: the μ pass overshoots next to it (see docs/taubin.md).
    let mut cells = vec![0.001; 30];
    cells[15] = 0.1;
    let x = line_from_cells(&cells);
    let dims = [x.len(), 1, 1];
    let orig: Vec<P3> = x.iter().map(|&v| [v, 0.0, 0.0]).collect();
    let mut pts = orig.clone();
    let err = run_smooth(dims, &mut pts, &SmoothOptions::new(Direction::I)).unwrap_err();
    println!("fold guard: {err}");
    assert_eq!(
        err,
        Error::FoldedLine {
            line: 0,
            iteration: 1
        }
    );
    assert_eq!(bits(&pts), bits(&orig));

    // Same in a 2D block: the folded line is reported by its first point's index.
    let dims2 = [x.len(), 3, 1];
    let orig2 = grid(dims2, |i, j, _| {
        let v = if j == 2 { x[i] } else { i as f64 * 0.01 };
        [v, j as f64, 0.0]
    });
    let mut pts2 = orig2.clone();
    let err = run_smooth(dims2, &mut pts2, &SmoothOptions::new(Direction::I)).unwrap_err();
    assert_eq!(
        err,
        Error::FoldedLine {
            line: 2 * x.len(),
            iteration: 1
        }
    );
    assert_eq!(bits(&pts2), bits(&orig2));

    // The check on its own.
    let block = Block::new([4, 2, 1]).unwrap();
    let field = [0.0, 1.0, 2.0, 3.0, 0.0, 1.0, 1.0, 2.0];
    assert_eq!(
        check_lines_increasing::<f64, 3>(&block, &field, Direction::I, 7, None),
        Err(Error::FoldedLine {
            line: 4,
            iteration: 7
        })
    );
    let up = [0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    assert_eq!(
        check_lines_increasing::<f64, 3>(&block, &up, Direction::J, 7, None),
        Ok(())
    );
    assert_eq!(
        check_lines_increasing::<f64, 3>(&block, &up, Direction::I, 7, None),
        Err(Error::FoldedLine {
            line: 0,
            iteration: 7
        })
    );
    let nan = [0.0, 1.0, f64::NAN, 3.0, 0.0, 1.0, 2.0, 3.0];
    assert_eq!(
        check_lines_increasing::<f64, 3>(&block, &nan, Direction::I, 0, None),
        Err(Error::FoldedLine {
            line: 0,
            iteration: 0
        })
    );
    // A collapsed line is exempt when the points are given.
    let pts = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [3.0, 0.0, 0.0],
        [5.0, 1.0, 0.0],
        [5.0, 1.0, 0.0],
        [5.0, 1.0, 0.0],
        [5.0, 1.0, 0.0],
    ];
    let zero_line = [0.0, 1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0];
    assert!(check_lines_increasing(&block, &zero_line, Direction::I, 1, None::<&[P3]>).is_err());
    assert_eq!(
        check_lines_increasing(&block, &zero_line, Direction::I, 1, Some(&pts[..])),
        Ok(())
    );
}

#[test]
fn collapsed_lines_and_zero_length_segments_are_handled() {
    // A polar-axis-like block: the j = 0 line of every k-plane collapses to one point.
    let dims = [9, 4, 3];
    let pts = grid(dims, |i, j, k| {
        let r = j as f64 * 0.5;
        let t = i as f64 * 0.3;
        [
            r * t.cos() + 0.01 * ((i * 7 + k) % 3) as f64 * r,
            r * t.sin(),
            k as f64,
        ]
    });
    for normalised in [false, true] {
        let mut p = pts.clone();
        let mut o = SmoothOptions::new(Direction::I);
        o.normalised = normalised;
        let r = run_smooth(dims, &mut p, &o).unwrap();
        assert!(r.max_displacement.is_finite());
        let block = Block::new(dims).unwrap();
        for k in 0..3 {
            for i in 0..9 {
                let q = block.index(i, 0, k);
                assert_eq!(p[q], pts[q], "collapsed line moved");
            }
        }
        assert!(p.iter().flatten().all(|c| c.is_finite()));
    }
    // Normalised arclength of a collapsed line: t / (n − 1), no NaN.
    let block = Block::new(dims).unwrap();
    let mut s = vec![0.0; pts.len()];
    arclength(&block, &pts, Direction::I, true, &mut s).unwrap();
    for i in 0..9 {
        assert_eq!(s[block.index(i, 0, 1)], i as f64 / 8.0);
    }
    // A line with repeated points: zero-length segments are skipped, not divided by.
    let line: Vec<P3> = [0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 4.0, 4.0]
        .iter()
        .map(|&x| [x, 0.0, 0.0])
        .collect();
    let b = Block::new([8, 1, 1]).unwrap();
    let targets = [-1.0, 0.0, 0.5, 1.0, 1.5, 3.0, 4.0, 6.0];
    let mut p = line.clone();
    let mut scratch = vec![0.0; redistribute_scratch_len::<3>(&b, Direction::I)];
    redistribute(&b, &mut p, Direction::I, &targets, false, &mut scratch).unwrap();
    let got: Vec<f64> = p.iter().map(|q| q[0]).collect();
    assert_eq!(got, vec![-1.0, 0.0, 0.5, 1.0, 1.5, 3.0, 4.0, 6.0]);
}

/// Lines that already have a segment of zero length (two consecutive points coincide, the
/// line not collapsed) are smoothed with that segment held: its two points keep their bits,
/// the rest of the line is filtered and stays strictly increasing (issue 31: the fold guard
/// refused them at iteration 1), in both modes and with the coarse pass.
#[test]
fn zero_length_segments_are_held_not_folds() {
    let dims = [12, 5, 3];
    // Rough spacing along i; on every line, points i = 4 and 5 coincide.
    let pts = grid(dims, |i, j, k| {
        let x = |i: usize| i as f64 + 0.3 * ((i * 5 + j + 2 * k) % 4) as f64;
        let xi = if i == 5 { x(4) } else { x(i) };
        [xi, j as f64, k as f64]
    });
    let block = Block::new(dims).unwrap();
    for (normalised, coarse) in [(false, false), (true, false), (false, true)] {
        let mut p = pts.clone();
        let mut o = SmoothOptions::new(Direction::I);
        o.normalised = normalised;
        if coarse {
            o.coarse = Some(Coarse {
                factor: [1, 2, 2],
                prolongation: Prolongation::Correction,
            });
        }
        let r = run_smooth(dims, &mut p, &o).expect("a zero-length segment is not a fold");
        assert!(
            r.max_displacement > 0.01,
            "the rest of the line was smoothed"
        );
        let mut s = vec![0.0; pts.len()];
        arclength(&block, &p, Direction::I, false, &mut s).unwrap();
        for k in 0..dims[2] {
            for j in 0..dims[1] {
                for i in [4, 5] {
                    let q = block.index(i, j, k);
                    assert_eq!(bits(&p[q..q + 1]), bits(&pts[q..q + 1]), "held point moved");
                }
                for i in 1..dims[0] {
                    let (a, b) = (s[block.index(i - 1, j, k)], s[block.index(i, j, k)]);
                    assert!(
                        b > a || i == 5 && b == a,
                        "line ({j}, {k}) at {i}: {a} -> {b}"
                    );
                }
            }
        }
    }
    // The public fold guard exempts an equal value across such a segment only when the
    // points are given.
    let mut s = vec![0.0; pts.len()];
    arclength(&block, &pts, Direction::I, false, &mut s).unwrap();
    check_lines_increasing(&block, &s, Direction::I, 0, Some(&pts)).unwrap();
    assert!(matches!(
        check_lines_increasing::<f64, 3>(&block, &s, Direction::I, 0, None),
        Err(Error::FoldedLine { iteration: 0, .. })
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Arclength functions equal the reference bit for bit (dimensional and normalised, f64
    /// and f32, every direction, some collapsed lines).
    #[test]
    fn arclength_parity(
        ni in 1usize..7, nj in 1usize..6, nk in 1usize..5, dir in 0usize..3,
        normalised in any::<bool>(), collapse in any::<bool>(),
        coords in prop::collection::vec(prop::array::uniform3(-3.0f64..3.0), 210),
    ) {
        let dims = [ni, nj, nk];
        let n = ni * nj * nk;
        let block = Block::new(dims).unwrap();
        let mut pts: Vec<P3> = coords[..n].to_vec();
        if collapse {
            // Collapse the first line along `dir`.
            for line in taubin_ref::lines(dims, dir).iter().take(1) {
                for &p in line {
                    pts[p] = [1.0, 2.0, 3.0];
                }
            }
        }
        let mut got = vec![0.0; n];
        arclength(&block, &pts, Direction::ALL[dir], normalised, &mut got).unwrap();
        let want = taubin_ref::arclength(dims, &pts, dir, normalised);
        prop_assert_eq!(got.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            want.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
        let p32: Vec<[f32; 3]> = pts.iter().map(|p| p.map(|c| c as f32)).collect();
        let mut got32 = vec![0.0f32; n];
        arclength(&block, &p32, Direction::ALL[dir], normalised, &mut got32).unwrap();
        let want32 = taubin_ref::arclength(dims, &p32, dir, normalised);
        prop_assert_eq!(got32.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            want32.iter().map(|v| v.to_bits()).collect::<Vec<_>>());

        // Stretching against the reference; the maximum is the field's maximum.
        let mut st = vec![0.0; n];
        stretching(&block, &pts, Direction::ALL[dir], &mut st).unwrap();
        let want_st = taubin_ref::stretching(dims, &pts, dir);
        for (a, b) in st.iter().zip(&want_st) {
            prop_assert!(a == b || (a - b).abs() <= 1e-12 * b.abs());
        }
        let (mx, at) = max_stretching(&block, &pts, Direction::ALL[dir]).unwrap();
        prop_assert_eq!(mx, st.iter().cloned().fold(1.0, f64::max));
        prop_assert_eq!(st[at], mx);
    }

    /// Redistribution to the original arclength returns every point bit for bit; to random
    /// targets (inside and beyond the ends) it matches the reference's fresh search.
    #[test]
    fn redistribution_against_reference(
        ni in 2usize..9, nj in 1usize..4, nk in 1usize..3, dir in 0usize..3,
        normalised in any::<bool>(),
        coords in prop::collection::vec(prop::array::uniform3(-3.0f64..3.0), 72),
        repeat in 0usize..72,
        t in prop::collection::vec(-0.3f64..1.3, 72),
    ) {
        let dims = [ni, nj, nk];
        let n = ni * nj * nk;
        let block = Block::new(dims).unwrap();
        let mut pts: Vec<P3> = coords[..n].to_vec();
        // A zero-length segment somewhere.
        let r = repeat % n;
        if r + 1 < n { pts[r + 1] = pts[r]; }
        let mut scratch = vec![0.0; redistribute_scratch_len::<3>(&block, Direction::ALL[dir])];
        let mut s = vec![0.0; n];
        arclength(&block, &pts, Direction::ALL[dir], false, &mut s).unwrap();
        let mut same = pts.clone();
        let moved = redistribute(&block, &mut same, Direction::ALL[dir], &s, false, &mut scratch).unwrap();
        prop_assert_eq!(bits(&same), bits(&pts));
        prop_assert_eq!(moved, 0.0);

        // Random targets as fractions of each line's length.
        let lines = taubin_ref::lines(dims, dir);
        let mut targets = vec![0.0; n];
        for line in &lines {
            let total = s[*line.last().unwrap()];
            for (q, &p) in line.iter().enumerate() {
                targets[p] = if normalised { t[p] } else { t[p] * total };
                let _ = q;
            }
        }
        let mut got = pts.clone();
        redistribute(&block, &mut got, Direction::ALL[dir], &targets, normalised, &mut scratch).unwrap();
        for line in &lines {
            let poly: Vec<P3> = line.iter().map(|&p| pts[p]).collect();
            let total = s[*line.last().unwrap()];
            for &p in line {
                let target = if normalised { targets[p] * total } else { targets[p] };
                let want = taubin_ref::point_at(&poly, target);
                for c in 0..3 {
                    prop_assert!((got[p][c] - want[c]).abs() <= 1e-12 * (1.0 + want[c].abs()),
                        "point {}: {:?} vs {:?}", p, got[p], want);
                }
            }
        }
    }
}

#[test]
fn driver_pins_coarse_pass_and_f32() {
    // Straight k-lines whose lengths ripple along i with wavelength 8: with a free outer end
    // (Alter's case) fine smoothing keeps most of the ripple; the coarse pass (every 4th i)
    // removes it. With fixed ends every line keeps its length and the interior follows it.
    let dims = [65, 3, 12];
    let len = |i: usize| 1.0 + 0.05 * (2.0 * std::f64::consts::PI * i as f64 / 8.0).sin();
    let pts = grid(dims, |i, j, k| {
        [i as f64 * 0.1, j as f64 * 0.1, len(i) * k as f64 / 11.0]
    });
    // The ripple: the deviation of the k = 6 points from the mean across i.
    let ripple = |p: &[P3]| {
        let block = Block::new(dims).unwrap();
        let mean = (8..57).map(|i| p[block.index(i, 1, 6)][2]).sum::<f64>() / 49.0;
        (8..57)
            .map(|i| (p[block.index(i, 1, 6)][2] - mean).abs())
            .fold(0.0, f64::max)
    };
    let mut fine = pts.clone();
    let mut o = SmoothOptions::new(Direction::K);
    o.ends[1] = LineEnd::Free;
    run_smooth(dims, &mut fine, &o).unwrap();
    let mut coarse = pts.clone();
    o.coarse = Some(Coarse {
        factor: [4, 4, 1],
        prolongation: Prolongation::Values,
    });
    let r = run_smooth(dims, &mut coarse, &o).unwrap();
    assert_eq!(r.iterations, 45);
    let mut fixed = pts.clone();
    o.ends[1] = LineEnd::Fixed;
    run_smooth(dims, &mut fixed, &o).unwrap();
    println!(
        "interior (k = 6) ripple: input {:.3e}, free end: fine 30 iterations {:.3e}, fine 30 + coarse 15 {:.3e}; fixed ends, fine + coarse {:.3e}",
        ripple(&pts),
        ripple(&fine),
        ripple(&coarse),
        ripple(&fixed)
    );
    assert!(ripple(&fine) > 0.5 * ripple(&pts));
    assert!(ripple(&coarse) < 0.1 * ripple(&pts));
    assert!((ripple(&fixed) - ripple(&pts)).abs() < 0.1 * ripple(&pts));
    // Points still lie on their original vertical lines.
    for (a, b) in coarse.iter().zip(&pts) {
        assert_eq!((a[0], a[1]), (b[0], b[1]));
    }

    // Pinned points keep their bits.
    let n = pts.len();
    let pins: Vec<u8> = (0..n).map(|p| u8::from(p % 7 == 3)).collect();
    let mut pinned = pts.clone();
    let mut o = SmoothOptions::new(Direction::K);
    o.fixed = Some(&pins);
    o.coarse = Some(Coarse {
        factor: [4, 1, 1],
        prolongation: Prolongation::Correction,
    });
    run_smooth(dims, &mut pinned, &o).unwrap();
    for p in 0..n {
        if pins[p] != 0 {
            assert_eq!(pinned[p], pts[p]);
        }
    }

    // f32 and 2D points.
    let block = Block::new([20, 6, 1]).unwrap();
    let mut p2: Vec<[f32; 2]> = (0..120)
        .map(|p| {
            let (i, j) = (p % 20, p / 20);
            [i as f32 * (1.0 + 0.02 * ((i * j) % 3) as f32), j as f32]
        })
        .collect();
    let mut scratch = vec![0.0f32; smooth_arclength_scratch_len::<2>(&block, Direction::I, None)];
    let mut o = SmoothOptions::<f32>::new(Direction::I);
    o.normalised = true;
    let r = smooth_arclength(&block, &mut p2, &o, &mut scratch).unwrap();
    assert!(r.stretching_after.0 < r.stretching_before.0);
}

#[test]
fn point_matched_interfaces_stay_identical() {
    // Two blocks sharing the face i = 5 of A and i = 0 of B, with noisy k-lines.
    let dims = [6, 5, 9];
    let noise = |i: usize, j: usize, k: usize| {
        let h = (i * 7919 + j * 104729 + k * 1299709) % 1000;
        (h as f64 / 1000.0 - 0.5) * 0.03
    };
    let f = |gi: usize, j: usize, k: usize| -> P3 {
        let z = (k as f64 / 8.0).powf(1.3) * (1.0 + 0.1 * gi as f64)
            + if k > 0 && k < 8 { noise(gi, j, k) } else { 0.0 };
        [gi as f64 * 0.2, j as f64 * 0.2, z]
    };
    let a0 = grid(dims, f);
    let b0 = grid(dims, |i, j, k| f(i + 5, j, k));
    let block = Block::new(dims).unwrap();
    let face_equal = |a: &[P3], b: &[P3]| {
        (0..9).all(|k| (0..5).all(|j| a[block.index(5, j, k)] == b[block.index(0, j, k)]))
    };
    assert!(face_equal(&a0, &b0));
    for normalised in [false, true] {
        let (mut a, mut b) = (a0.clone(), b0.clone());
        let mut o = SmoothOptions::new(Direction::K);
        o.normalised = normalised;
        let ra = run_smooth(dims, &mut a, &o).unwrap();
        run_smooth(dims, &mut b, &o).unwrap();
        assert!(ra.max_displacement > 1e-3);
        assert!(
            face_equal(&a, &b),
            "interface tangent to the lines must stay matched"
        );
    }
    // Lines crossing the interface (direction i), dimensional: the far face of A slides, so
    // the interface opens up unless it is pinned.
    let (mut a, mut b) = (a0.clone(), b0.clone());
    run_smooth(dims, &mut a, &SmoothOptions::new(Direction::I)).unwrap();
    run_smooth(dims, &mut b, &SmoothOptions::new(Direction::I)).unwrap();
    let unpinned = face_equal(&a, &b);
    let pins_a: Vec<u8> = (0..a0.len())
        .map(|p| u8::from(block.ijk(p)[0] == 5))
        .collect();
    let pins_b: Vec<u8> = (0..a0.len())
        .map(|p| u8::from(block.ijk(p)[0] == 0))
        .collect();
    let (mut a, mut b) = (a0.clone(), b0.clone());
    let mut oa = SmoothOptions::new(Direction::I);
    oa.fixed = Some(&pins_a);
    let mut ob = SmoothOptions::new(Direction::I);
    ob.fixed = Some(&pins_b);
    run_smooth(dims, &mut a, &oa).unwrap();
    run_smooth(dims, &mut b, &ob).unwrap();
    println!(
        "interface crossing the lines: matched without pins = {unpinned}, with pins = {}",
        face_equal(&a, &b)
    );
    assert!(face_equal(&a, &b));
}

#[test]
fn bad_inputs_give_typed_errors_and_leave_the_grid_unchanged() {
    let dims = [5, 4, 3];
    let block = Block::new(dims).unwrap();
    let good = grid(dims, |i, j, k| [i as f64, j as f64 * 1.5, k as f64 * 0.7]);
    let n = good.len();
    let need = smooth_arclength_scratch_len::<3>(&block, Direction::J, None);
    let try_smooth = |pts: &[P3], o: &SmoothOptions<f64>, scratch_len: usize| {
        let mut p = pts.to_vec();
        let mut s = vec![0.0; scratch_len];
        let e = smooth_arclength(&block, &mut p, o, &mut s).unwrap_err();
        assert_eq!(bits(&p), bits(pts));
        e
    };
    let o = SmoothOptions::new(Direction::J);
    let mut nan = good.clone();
    nan[11][2] = f64::NAN;
    assert_eq!(
        try_smooth(&nan, &o, need),
        Error::NonFinite {
            arg: "points",
            position: 11
        }
    );
    assert_eq!(
        try_smooth(&good[..n - 1], &o, need),
        Error::LengthMismatch {
            arg: "points",
            expected: n,
            actual: n - 1
        }
    );
    assert_eq!(
        try_smooth(&good, &o, need - 1),
        Error::BufferTooSmall {
            arg: "scratch",
            needed: need,
            actual: need - 1
        }
    );
    // A direction other than i, j, k cannot be written: `Direction` has three values.
    assert_eq!(Direction::from_index(3), None);
    let mut bad = SmoothOptions::new(Direction::J);
    bad.params.mu = 0.5;
    assert!(matches!(
        try_smooth(&good, &bad, need),
        Error::InvalidParameter { arg: "mu", .. }
    ));
    let pins = [0u8; 3];
    let mut bad = SmoothOptions::new(Direction::J);
    bad.fixed = Some(&pins);
    assert_eq!(
        try_smooth(&good, &bad, need),
        Error::LengthMismatch {
            arg: "options.fixed",
            expected: n,
            actual: 3
        }
    );
    let mut bad = SmoothOptions::new(Direction::J);
    bad.coarse = Some(Coarse {
        factor: [2, 0, 1],
        prolongation: Prolongation::Values,
    });
    assert!(matches!(
        try_smooth(&good, &bad, 10_000),
        Error::InvalidParameter {
            arg: "coarse.factor",
            ..
        }
    ));

    // Line tools.
    let mut out = vec![-1.0; n];
    assert_eq!(
        arclength(&block, &nan, Direction::I, false, &mut out),
        Err(Error::NonFinite {
            arg: "points",
            position: 11
        })
    );
    assert_eq!(
        arclength(&block, &good, Direction::I, false, &mut out[..4]),
        Err(Error::LengthMismatch {
            arg: "out",
            expected: n,
            actual: 4
        })
    );
    assert!(out.iter().all(|&v| v == -1.0));
    let mut targets = vec![0.5; n];
    targets[9] = f64::INFINITY;
    let mut p = good.clone();
    let mut scratch = vec![0.0; redistribute_scratch_len::<3>(&block, Direction::I)];
    assert_eq!(
        redistribute(&block, &mut p, Direction::I, &targets, true, &mut scratch),
        Err(Error::NonFinite {
            arg: "targets",
            position: 9
        })
    );
    assert_eq!(
        redistribute(
            &block,
            &mut p,
            Direction::I,
            &targets[..2],
            true,
            &mut scratch
        ),
        Err(Error::LengthMismatch {
            arg: "targets",
            expected: n,
            actual: 2
        })
    );
    targets[9] = 0.5;
    assert_eq!(
        redistribute(
            &block,
            &mut p,
            Direction::I,
            &targets,
            true,
            &mut scratch[..3]
        ),
        Err(Error::BufferTooSmall {
            arg: "scratch",
            needed: 20,
            actual: 3
        })
    );
    assert_eq!(bits(&p), bits(&good));
}

/// Issue 13: in every mode (dimensional, normalised, with and without the coarse pass) the
/// first and last point of every line keep their bits, so faces at the line ends, O-grid seams
/// and block interfaces there cannot open. Before the fix, dimensional smoothing pushed the
/// last point of lines of unequal length past the end of the line.
#[test]
fn line_ends_keep_their_bits_in_every_mode() {
    let dims = [9, 7, 5];
    // Curved lines of unequal lengths with a noisy distribution.
    let pts = grid(dims, |i, j, k| {
        let noise = ((i * 7 + j * 13 + k * 29) % 11) as f64 * 0.004;
        let r = 1.0 + 0.1 * j as f64 + 0.03 * (i as f64 * 0.9).sin() + noise;
        let a = 0.3 * i as f64 + 0.02 * k as f64;
        [r * a.cos(), r * a.sin(), 0.2 * k as f64 + noise]
    });
    let block = Block::new(dims).unwrap();
    for direction in 0..3 {
        for normalised in [false, true] {
            for coarse in [None, Some([2, 2, 2])] {
                let mut o = SmoothOptions::new(Direction::ALL[direction]);
                o.normalised = normalised;
                o.coarse = coarse.map(|mut factor: [usize; 3]| {
                    factor[direction] = 1;
                    Coarse {
                        factor,
                        prolongation: Prolongation::Values,
                    }
                });
                let mut got = pts.clone();
                run_smooth(dims, &mut got, &o).unwrap();
                let len = dims[direction];
                let mut interior_moved = false;
                for k in 0..dims[2] {
                    for j in 0..dims[1] {
                        for i in 0..dims[0] {
                            let t = [i, j, k][direction];
                            let p = block.index(i, j, k);
                            if t == 0 || t + 1 == len {
                                assert_eq!(
                                    bits(&got[p..=p]),
                                    bits(&pts[p..=p]),
                                    "end point ({i},{j},{k}) moved: direction {direction}, normalised {normalised}, coarse {coarse:?}"
                                );
                            } else if got[p] != pts[p] {
                                interior_moved = true;
                            }
                        }
                    }
                }
                assert!(interior_moved, "the smoothing must do something");
            }
        }
    }
}
