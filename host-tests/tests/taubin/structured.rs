//! Structured Taubin filter: spectral response, invariance of linear fields, stability,
//! bitwise parity with the naive reference, sweeps, the coarse-grid variant and input errors.

use deform_host_tests::taubin_ref;
use deform_kernel::taubin::{
    coarse_dims, mu_from_pass_band, smooth_structured, smooth_structured_coarse,
    structured_coarse_scratch_len, structured_scratch_len, structured_sweep, BlockRegion, Coarse,
    Prolongation, StructuredOptions, TaubinParams,
};
use deform_kernel::Directions;
use deform_kernel::{Block, Error};
use proptest::prelude::*;

/// A deterministic pseudo-random stream in [-1, 1) (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn one_iteration(
    dims: [usize; 3],
    field: &mut [f64],
    params: TaubinParams<f64>,
    mirror: [bool; 3],
) {
    let block = Block::new(dims).unwrap();
    let mut scratch = vec![0.0; structured_scratch_len(&block)];
    let opts = StructuredOptions {
        fixed: None,
        mirror: Directions::from_flags(mirror),
    };
    smooth_structured(&block, field, params, 1, &opts, &mut scratch).unwrap();
}

/// Dirichlet eigenmode `Π sin(π m_d i_d / (n_d − 1))` (zero on every face) and its
/// eigenvalue `k = 1 − (1/r) Σ cos θ_d` of `I − avg`, r = number of directions with n > 1.
fn sine_mode(dims: [usize; 3], m: [usize; 3]) -> (Vec<f64>, f64) {
    let mut field = vec![0.0; dims.iter().product()];
    let theta: Vec<f64> = (0..3)
        .map(|d| {
            if dims[d] > 1 {
                std::f64::consts::PI * m[d] as f64 / (dims[d] - 1) as f64
            } else {
                0.0
            }
        })
        .collect();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                let mut v = 1.0;
                for (d, &c) in [i, j, k].iter().enumerate() {
                    if dims[d] > 1 {
                        v *= (theta[d] * c as f64).sin();
                    }
                }
                field[i + dims[0] * (j + dims[1] * k)] = v;
            }
        }
    }
    let active: Vec<usize> = (0..3).filter(|&d| dims[d] > 1).collect();
    let k = 1.0 - active.iter().map(|&d| theta[d].cos()).sum::<f64>() / active.len() as f64;
    (field, k)
}

#[test]
fn spectral_response_of_sine_modes_1d_2d_3d() {
    let cases: &[([usize; 3], [usize; 3])] = &[
        ([33, 1, 1], [1, 0, 0]),
        ([33, 1, 1], [5, 0, 0]),
        ([33, 1, 1], [31, 0, 0]),
        ([17, 13, 1], [2, 3, 0]),
        ([17, 13, 1], [15, 11, 0]),
        ([9, 11, 7], [1, 1, 1]),
        ([9, 11, 7], [4, 7, 5]),
        ([9, 11, 7], [7, 9, 5]),
    ];
    for params in [
        TaubinParams::<f64>::paper(),
        TaubinParams::from_pass_band(0.5, 0.1).unwrap(),
    ] {
        for &(dims, m) in cases {
            let (mut field, k) = sine_mode(dims, m);
            let orig = field.clone();
            one_iteration(dims, &mut field, params, [false; 3]);
            let f = params.transfer(k);
            let err = field
                .iter()
                .zip(&orig)
                .map(|(a, b)| (a - f * b).abs())
                .fold(0.0, f64::max);
            println!("dims {dims:?} mode {m:?}: k = {k:.5}, f(k) = {f:.8}, max err {err:.2e}");
            assert!(err < 1e-14, "mode {m:?} on {dims:?}: err {err:e}");
        }
    }
}

#[test]
fn spectral_response_with_mirror_faces() {
    // Neumann modes cos(π m i / (n − 1)): every point, corners included, is averaged.
    for (dims, m) in [([21usize, 1, 1], [3usize, 0]), ([12, 9, 1], [2, 5])] {
        let mut field = vec![0.0; dims[0] * dims[1]];
        let t0 = std::f64::consts::PI * m[0] as f64 / (dims[0] - 1) as f64;
        let t1 = if dims[1] > 1 {
            std::f64::consts::PI * m[1] as f64 / (dims[1] - 1) as f64
        } else {
            0.0
        };
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                field[i + dims[0] * j] = (t0 * i as f64).cos() * (t1 * j as f64).cos();
            }
        }
        let r = if dims[1] > 1 { 2.0 } else { 1.0 };
        let k = 1.0 - (t0.cos() + if dims[1] > 1 { t1.cos() } else { 0.0 }) / r;
        let orig = field.clone();
        let params = TaubinParams::<f64>::paper();
        one_iteration(dims, &mut field, params, [true, true, false]);
        let f = params.transfer(k);
        let err = field
            .iter()
            .zip(&orig)
            .map(|(a, b)| (a - f * b).abs())
            .fold(0.0, f64::max);
        println!("mirror {dims:?} mode {m:?}: f(k) = {f:.8}, max err {err:.2e}");
        assert!(err < 1e-14);
    }
}

#[test]
fn spectral_response_f32() {
    let (field64, k) = sine_mode([9, 11, 7], [3, 2, 1]);
    let mut field: Vec<f32> = field64.iter().map(|&v| v as f32).collect();
    let orig = field.clone();
    let block = Block::new([9, 11, 7]).unwrap();
    let mut scratch = vec![0.0f32; block.point_count()];
    let params = TaubinParams::<f32>::paper();
    smooth_structured(
        &block,
        &mut field,
        params,
        1,
        &StructuredOptions::default(),
        &mut scratch,
    )
    .unwrap();
    let f = params.transfer(k as f32);
    let err = field
        .iter()
        .zip(&orig)
        .map(|(a, b)| (a - f * b).abs())
        .fold(0.0, f32::max);
    assert!(err < 2e-6, "{err}");
}

#[test]
fn mu_from_pass_band_solves_taubins_relation() {
    for (lambda, kpb) in [(0.33f64, 0.1f64), (0.5, 0.01), (0.6307, 0.1)] {
        let mu = mu_from_pass_band(lambda, kpb).unwrap();
        assert!(mu < -lambda, "mu {mu} must be below -lambda");
        assert!((1.0 / lambda + 1.0 / mu - kpb).abs() < 1e-12);
        // The transfer function is 1 at the pass band (besides k = 0).
        let p = TaubinParams { lambda, mu };
        assert!((p.transfer(kpb) - 1.0).abs() < 1e-12);
        assert!((p.pass_band() - kpb).abs() < 1e-12);
    }
    assert!(matches!(
        mu_from_pass_band(0.33, 5.0),
        Err(Error::InvalidParameter {
            arg: "pass_band",
            ..
        })
    ));
    assert!(matches!(
        mu_from_pass_band(-0.33, 0.1),
        Err(Error::InvalidParameter { arg: "lambda", .. })
    ));
    assert!(matches!(
        mu_from_pass_band(0.33, f64::NAN),
        Err(Error::NonFinite {
            arg: "pass_band",
            ..
        })
    ));
}

fn linear_field(dims: [usize; 3], c: [f64; 4]) -> Vec<f64> {
    let mut f = Vec::new();
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                f.push(c[0] + c[1] * i as f64 + c[2] * j as f64 + c[3] * k as f64);
            }
        }
    }
    f
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Alter's stencils reproduce linear functions (the interior 6-point average, the face
    /// 4-point and edge 2-point averages all equal the centre value), so a linear field is a
    /// fixed point of both passes: invariant within rounding.
    #[test]
    fn linear_fields_are_invariant(
        ni in 1usize..9, nj in 1usize..9, nk in 1usize..7,
        c in prop::array::uniform4(-10.0f64..10.0),
        iterations in 1usize..20,
    ) {
        let dims = [ni, nj, nk];
        let mut field = linear_field(dims, c);
        let orig = field.clone();
        let block = Block::new(dims).unwrap();
        let mut scratch = vec![0.0; block.point_count()];
        smooth_structured(&block, &mut field, TaubinParams::paper(), iterations,
            &StructuredOptions::default(), &mut scratch).unwrap();
        let scale = c.iter().map(|v| v.abs()).sum::<f64>() * 10.0 + 1.0;
        for (a, b) in field.iter().zip(&orig) {
            prop_assert!((a - b).abs() <= 1e-13 * scale * iterations as f64, "{a} vs {b}");
        }
    }

    /// With mirror faces the boundary sees a zero normal gradient, so a linear field changes
    /// near the faces, but points at least 3 cells inside are untouched by one iteration.
    #[test]
    fn linear_fields_invariant_in_the_interior_with_mirror_faces(
        c in prop::array::uniform4(-10.0f64..10.0),
    ) {
        let dims = [10, 9, 8];
        let mut field = linear_field(dims, c);
        let orig = field.clone();
        one_iteration(dims, &mut field, TaubinParams::paper(), [true; 3]);
        let block = Block::new(dims).unwrap();
        let scale = c.iter().map(|v| v.abs()).sum::<f64>() * 10.0 + 1.0;
        for (p, (a, b)) in field.iter().zip(&orig).enumerate() {
            let ijk = block.ijk(p);
            let inside = (0..3).all(|d| ijk[d] >= 3 && ijk[d] + 3 < dims[d]);
            if inside {
                prop_assert!((a - b).abs() <= 1e-13 * scale);
            }
        }
    }

    /// Bitwise parity of the whole filter with the naive reference: random dims (1D, 2D, 3D),
    /// fields, pins, mirror faces and parameters, in f64 and f32.
    #[test]
    fn parity_with_reference(
        ni in 1usize..8, nj in 1usize..7, nk in 1usize..6,
        seed in any::<u64>(),
        mirror in prop::array::uniform3(any::<bool>()),
        use_pins in any::<bool>(),
        lambda in 0.05f64..0.9, mu in -0.95f64..0.0,
        iterations in 0usize..6,
    ) {
        let dims = [ni, nj, nk];
        let n = ni * nj * nk;
        let mut rng = Rng(seed);
        let field: Vec<f64> = (0..n).map(|_| rng.next() * 100.0).collect();
        let pins: Vec<u8> = (0..n).map(|_| u8::from(rng.next() > 0.6) * 7).collect();
        let pinned = use_pins.then_some(&pins[..]);
        let block = Block::new(dims).unwrap();
        let opts = StructuredOptions { fixed: pinned, mirror: Directions::from_flags(mirror) };

        let mut got = field.clone();
        let mut scratch = vec![0.0; n];
        smooth_structured(&block, &mut got, TaubinParams { lambda, mu }, iterations, &opts,
            &mut scratch).unwrap();
        let want = taubin_ref::structured_filter(dims, &field, lambda, mu, iterations, mirror, pinned);
        for (p, (a, b)) in got.iter().zip(&want).enumerate() {
            prop_assert_eq!(a.to_bits(), b.to_bits(), "f64 point {}", p);
        }

        let field32: Vec<f32> = field.iter().map(|&v| v as f32).collect();
        let (l32, m32) = (lambda as f32, mu as f32);
        let mut got32 = field32.clone();
        let mut scratch32 = vec![0.0f32; n];
        smooth_structured(&block, &mut got32, TaubinParams { lambda: l32, mu: m32 }, iterations,
            &opts, &mut scratch32).unwrap();
        let want32 = taubin_ref::structured_filter(dims, &field32, l32, m32, iterations, mirror, pinned);
        for (p, (a, b)) in got32.iter().zip(&want32).enumerate() {
            prop_assert_eq!(a.to_bits(), b.to_bits(), "f32 point {}", p);
        }
    }

    /// A sweep over a sub-box equals the reference pass there and leaves the rest of `dst`
    /// alone; sweeping a partition of the block piece by piece equals one full sweep.
    #[test]
    fn sweep_over_region_matches_reference(
        seed in any::<u64>(),
        lo in prop::array::uniform3(0usize..4), ext in prop::array::uniform3(0usize..5),
        weight in -0.5f64..0.5,
    ) {
        let dims = [6, 5, 4];
        let n = 120;
        let mut rng = Rng(seed);
        let src: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let hi = [(lo[0] + ext[0]).min(6), (lo[1] + ext[1]).min(5), (lo[2] + ext[2]).min(4)];
        let lo = [lo[0].min(hi[0]), lo[1].min(hi[1]), lo[2].min(hi[2])];
        let block = Block::new(dims).unwrap();
        let sentinel = vec![-999.0; n];
        let mut dst = sentinel.clone();
        let opts = StructuredOptions::default();
        let change = structured_sweep(&block, &src, &mut dst, weight, &opts,
            &BlockRegion { lo, hi }).unwrap();
        let want = taubin_ref::structured_pass(dims, &src, weight, [false; 3], None, lo, hi);
        let mut max_change: f64 = 0.0;
        for p in 0..n {
            let ijk = block.ijk(p);
            let inside = (0..3).all(|d| ijk[d] >= lo[d] && ijk[d] < hi[d]);
            if inside {
                prop_assert_eq!(dst[p].to_bits(), want[p].to_bits());
                max_change = max_change.max((want[p] - src[p]).abs());
            } else {
                prop_assert_eq!(dst[p], -999.0);
            }
        }
        prop_assert_eq!(change, max_change);

        // Two slabs in k == the whole block.
        let mut a = sentinel.clone();
        let split = lo[2].min(4);
        structured_sweep(&block, &src, &mut a, weight, &opts,
            &BlockRegion { lo: [0; 3], hi: [6, 5, split] }).unwrap();
        structured_sweep(&block, &src, &mut a, weight, &opts,
            &BlockRegion { lo: [0, 0, split], hi: [6, 5, 4] }).unwrap();
        let mut b = sentinel.clone();
        structured_sweep(&block, &src, &mut b, weight, &opts, &BlockRegion::all(&block)).unwrap();
        prop_assert_eq!(a, b);
    }

    /// The coarse-grid variant equals the reference (injection, filter, multilinear
    /// prolongation) within rounding, for both prolongation rules.
    #[test]
    fn coarse_parity_with_reference(
        ni in 1usize..14, nj in 1usize..10, nk in 1usize..6,
        factor in prop::array::uniform3(1usize..5),
        seed in any::<u64>(), correction in any::<bool>(), use_pins in any::<bool>(),
        iterations in 0usize..5,
    ) {
        let dims = [ni, nj, nk];
        let n = ni * nj * nk;
        let mut rng = Rng(seed);
        let field: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let pins: Vec<u8> = (0..n).map(|_| u8::from(rng.next() > 0.7)).collect();
        let pinned = use_pins.then_some(&pins[..]);
        let block = Block::new(dims).unwrap();
        let coarse = Coarse {
            factor,
            prolongation: if correction { Prolongation::Correction } else { Prolongation::Values },
        };
        let mut got = field.clone();
        let mut scratch = vec![0.0; structured_coarse_scratch_len(&block, &coarse)];
        smooth_structured_coarse(&block, &mut got, &coarse, TaubinParams::paper(), iterations,
            &StructuredOptions { fixed: pinned, mirror: Directions::NONE }, &mut scratch).unwrap();
        let want = taubin_ref::coarse_filter(dims, &field, factor, 0.330, -0.334, iterations,
            pinned, correction);
        for (p, (a, b)) in got.iter().zip(&want).enumerate() {
            prop_assert!((a - b).abs() <= 1e-14, "point {}: {} vs {}", p, a, b);
            if pinned.is_some_and(|m| m[p] != 0) {
                prop_assert_eq!(a.to_bits(), field[p].to_bits());
            }
        }
    }
}

#[test]
fn coarse_dims_keep_the_last_index() {
    let block = Block::new([9, 10, 2]).unwrap();
    // 9 points by 4: 0 4 8; 10 by 4: 0 4 8 9; 2 by 4: 0 1.
    assert_eq!(coarse_dims(&block, [4, 4, 4]), [3, 4, 2]);
    assert_eq!(coarse_dims(&block, [1, 3, 1]), [9, 4, 2]);
}

#[test]
fn coarse_grid_removes_long_ripples_that_fine_smoothing_keeps() {
    // A ripple 8 cells long on a smooth ramp: high frequency for the grid sampled every 4th
    // point (k = 2 there), but low for the fine grid (k = 1 − cos(π/4) ≈ 0.29).
    let n = 65;
    let dims = [n, 1, 1];
    let block = Block::new(dims).unwrap();
    let ramp: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
    let ripple = |i: usize| 0.01 * (2.0 * std::f64::consts::PI * i as f64 / 8.0 + 0.3).sin();
    let field: Vec<f64> = (0..n).map(|i| ramp[i] + ripple(i)).collect();
    let amp = |f: &[f64]| {
        (4..n - 4)
            .map(|i| (f[i] - ramp[i]).abs())
            .fold(0.0, f64::max)
    };
    let mut fine = field.clone();
    let mut scratch = vec![0.0; 2 * n];
    smooth_structured(
        &block,
        &mut fine,
        TaubinParams::paper(),
        30,
        &StructuredOptions::default(),
        &mut scratch,
    )
    .unwrap();
    let mut coarse = field.clone();
    let c = Coarse {
        factor: [4, 1, 1],
        prolongation: Prolongation::Values,
    };
    smooth_structured_coarse(
        &block,
        &mut coarse,
        &c,
        TaubinParams::paper(),
        15,
        &StructuredOptions::default(),
        &mut scratch,
    )
    .unwrap();
    println!(
        "ripple amplitude: input {:.3e}, 30 fine iterations {:.3e}, 15 coarse (m = 4) {:.3e}",
        amp(&field),
        amp(&fine),
        amp(&coarse)
    );
    assert!(amp(&fine) > 0.5 * amp(&field));
    assert!(amp(&coarse) < 0.1 * amp(&field));
}

/// Rigorous one-iteration ℓ∞ gain of `F = (1 − μL)(1 − λL) = (1−λ)(1−μ) I + (λ+μ−2λμ) A +
/// λμ A²` for any row-stochastic non-negative averaging `A` (every stencil here is one):
/// `‖F‖∞ ≤ (1−λ)(1−μ) + |λ+μ−2λμ| + |λμ|` (1.2204 for the paper's values).
fn one_step_gain(p: TaubinParams<f64>) -> f64 {
    let (l, m) = (p.lambda, p.mu);
    ((1.0 - l) * (1.0 - m)).abs() + (l + m - 2.0 * l * m).abs() + (l * m).abs()
}

#[test]
fn stability_sup_norm_over_ten_thousand_iterations() {
    // The issue asks for "the sup-norm never grows". That is false for λ|μ = 0.330|−0.334:
    // the μ pass has a negative weight, so one iteration is not an ℓ∞ contraction (see
    // `one_iteration_can_raise_the_sup_norm`), and f(k) > 1 for 0 < k < k_PB. What holds, and
    // is asserted here on random fields over 10⁴ iterations: the sup-norm never exceeds the
    // initial sup-norm times the one-step gain bound, and it ends no higher than it started.
    // Mirror faces everywhere leave no point fixed, so corners cannot hold the maximum.
    let params = TaubinParams::<f64>::paper();
    let gain = one_step_gain(params);
    let cases = [
        (1u64, [40usize, 1, 1], [false; 3]),
        (9, [200, 1, 1], [false; 3]),
        (2, [24, 17, 1], [false; 3]),
        (3, [10, 9, 8], [false; 3]),
        (4, [7, 7, 7], [false; 3]),
        (5, [40, 1, 1], [true; 3]),
        (6, [24, 17, 1], [true; 3]),
        (7, [10, 9, 8], [true; 3]),
    ];
    for (seed, dims, mirror) in cases {
        let block = Block::new(dims).unwrap();
        let n = block.point_count();
        let mut rng = Rng(seed);
        let mut field: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let opts = StructuredOptions {
            fixed: None,
            mirror: Directions::from_flags(mirror),
        };
        let sup0 = field.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut scratch = vec![0.0; n];
        let mut worst = 0.0f64;
        let mut grew = 0;
        let mut prev = sup0;
        for _ in 0..10_000 {
            smooth_structured(&block, &mut field, params, 1, &opts, &mut scratch).unwrap();
            let sup = field.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            worst = worst.max(sup);
            grew += usize::from(sup > prev);
            prev = sup;
            assert!(
                sup.is_finite() && sup <= gain * sup0,
                "dims {dims:?}: sup {sup} vs {sup0}"
            );
        }
        println!(
            "dims {dims:?} mirror {mirror:?}: sup initial {sup0:.4}, max over 1e4 iterations \
             {worst:.4} (ratio {:.4}, bound {gain:.4}), iterations where it grew {grew}, final {prev:.4}",
            worst / sup0
        );
        assert!(prev <= sup0);
    }
}

#[test]
fn one_iteration_can_raise_the_sup_norm() {
    // x = (…, −1, 1, 1, 1, −1, …): the centre becomes c0 + 2c1 − 2c2 with the 1D coefficients
    // of F; c0 = (1−λ)(1−μ) + λμ/2, c1 = (λ+μ−2λμ)/2, c2 = λμ/4 (< 0), i.e. 1.1102 > 1.
    let p = TaubinParams::<f64>::paper();
    let (l, m) = (p.lambda, p.mu);
    let c0 = (1.0 - l) * (1.0 - m) + l * m / 2.0;
    let c1 = (l + m - 2.0 * l * m) / 2.0;
    let c2 = l * m / 4.0;
    let n = 15;
    let mut field: Vec<f64> = (0..n)
        .map(|i| if (6..=8).contains(&i) { 1.0 } else { -1.0 })
        .collect();
    let block = Block::new([n, 1, 1]).unwrap();
    let mut scratch = vec![0.0; n];
    smooth_structured(
        &block,
        &mut field,
        p,
        1,
        &StructuredOptions::default(),
        &mut scratch,
    )
    .unwrap();
    let want = c0 + 2.0 * c1 - 2.0 * c2;
    println!("centre after one iteration: {} (analytic {want})", field[7]);
    assert!((field[7] - want).abs() < 1e-15);
    assert!(field[7] > 1.1);
}

#[test]
fn l2_stability_bounded_by_the_transfer_function_1d() {
    // On a 1D line with fixed ends the operator on the free points is symmetric, so the
    // deviation from the linear interpolant h of the end values obeys
    // ‖x_N − h‖₂ ≤ max_k f(k)^N ‖x_0 − h‖₂, with max f = 1 + (λ+μ)²/(4|λμ|) at k = (λ+μ)/(2λμ).
    let p = TaubinParams::<f64>::paper();
    let (l, m) = (p.lambda, p.mu);
    let fmax = 1.0 + (l + m).powi(2) / (4.0 * (l * m).abs());
    for (seed, n) in [(11u64, 30usize), (12, 120), (13, 400)] {
        let block = Block::new([n, 1, 1]).unwrap();
        let mut rng = Rng(seed);
        let mut field: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let h: Vec<f64> = (0..n)
            .map(|i| field[0] + (field[n - 1] - field[0]) * i as f64 / (n - 1) as f64)
            .collect();
        let norm = |f: &[f64]| {
            f.iter()
                .zip(&h)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
        };
        let e0 = norm(&field);
        let mut scratch = vec![0.0; n];
        let mut worst_ratio = 0.0f64;
        for it in 1..=10_000 {
            smooth_structured(
                &block,
                &mut field,
                p,
                1,
                &StructuredOptions::default(),
                &mut scratch,
            )
            .unwrap();
            let ratio = norm(&field) / e0;
            worst_ratio = worst_ratio.max(ratio);
            assert!(
                ratio <= fmax.powi(it) * (1.0 + 1e-12),
                "n {n} iteration {it}: {ratio}"
            );
        }
        println!("n {n}: max ‖x−h‖₂ ratio over 1e4 iterations {worst_ratio:.4} (f_max = {fmax:.7}, f_max^1e4 = {:.3})", fmax.powi(10_000));
    }
}

#[test]
fn pinned_points_keep_their_bits() {
    let dims = [7, 6, 5];
    let block = Block::new(dims).unwrap();
    let n = block.point_count();
    let mut rng = Rng(9);
    let field: Vec<f64> = (0..n).map(|_| rng.next()).collect();
    let pins: Vec<u8> = (0..n).map(|p| u8::from(p % 3 == 0)).collect();
    let mut got = field.clone();
    let mut scratch = vec![0.0; n];
    smooth_structured(
        &block,
        &mut got,
        TaubinParams::paper(),
        10,
        &StructuredOptions {
            fixed: Some(&pins),
            mirror: Directions::ALL,
        },
        &mut scratch,
    )
    .unwrap();
    let mut moved = 0;
    for p in 0..n {
        if pins[p] != 0 {
            assert_eq!(got[p].to_bits(), field[p].to_bits());
        } else if got[p] != field[p] {
            moved += 1;
        }
    }
    assert!(moved > n / 2);
}

#[test]
fn bad_inputs_give_typed_errors_and_leave_buffers_unchanged() {
    let block = Block::new([4, 3, 2]).unwrap();
    let n = 24;
    let good: Vec<f64> = (0..n).map(|p| p as f64 * 0.5).collect();
    let p = TaubinParams::<f64>::paper();
    let o = StructuredOptions::default();
    let check = |field: &[f64],
                 params: TaubinParams<f64>,
                 opts: &StructuredOptions,
                 scratch_len: usize,
                 want: Error| {
        let mut f = field.to_vec();
        let mut s = vec![1.25; scratch_len];
        let e = smooth_structured(&block, &mut f, params, 3, opts, &mut s).unwrap_err();
        assert_eq!(e, want);
        assert_eq!(
            f.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            field.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        assert!(s.iter().all(|&v| v == 1.25));
        // The coarse variant validates the same way.
        let mut f2 = field.to_vec();
        let c = Coarse {
            factor: [2, 2, 1],
            prolongation: Prolongation::Values,
        };
        let mut s2 = vec![1.25; scratch_len];
        assert!(smooth_structured_coarse(&block, &mut f2, &c, params, 3, opts, &mut s2).is_err());
        assert_eq!(
            f2.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            field.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
    };
    let mut nan = good.clone();
    nan[17] = f64::NAN;
    check(
        &nan,
        p,
        &o,
        n,
        Error::NonFinite {
            arg: "field",
            position: 17,
        },
    );
    let mut inf = good.clone();
    inf[3] = f64::NEG_INFINITY;
    check(
        &inf,
        p,
        &o,
        n,
        Error::NonFinite {
            arg: "field",
            position: 3,
        },
    );
    check(
        &good[..23],
        p,
        &o,
        n,
        Error::LengthMismatch {
            arg: "field",
            expected: 24,
            actual: 23,
        },
    );
    check(
        &good,
        p,
        &o,
        10,
        Error::BufferTooSmall {
            arg: "scratch",
            needed: 24,
            actual: 10,
        },
    );
    let pins = [0u8; 5];
    check(
        &good,
        p,
        &StructuredOptions {
            fixed: Some(&pins),
            mirror: Directions::NONE,
        },
        n,
        Error::LengthMismatch {
            arg: "options.fixed",
            expected: 24,
            actual: 5,
        },
    );
    check(
        &good,
        TaubinParams {
            lambda: f64::NAN,
            mu: -0.3,
        },
        &o,
        n,
        Error::NonFinite {
            arg: "lambda",
            position: 0,
        },
    );
    check(
        &good,
        TaubinParams {
            lambda: 0.3,
            mu: f64::INFINITY,
        },
        &o,
        n,
        Error::NonFinite {
            arg: "mu",
            position: 0,
        },
    );
    check(
        &good,
        TaubinParams {
            lambda: 0.0,
            mu: -0.3,
        },
        &o,
        n,
        Error::InvalidParameter {
            arg: "lambda",
            reason: "must be > 0",
        },
    );
    check(
        &good,
        TaubinParams {
            lambda: 0.3,
            mu: 0.3,
        },
        &o,
        n,
        Error::InvalidParameter {
            arg: "mu",
            reason: "must be <= 0",
        },
    );

    // Coarse factor 0.
    let mut f = good.clone();
    let mut s = vec![0.0; 100];
    let c = Coarse {
        factor: [0, 1, 1],
        prolongation: Prolongation::Values,
    };
    assert!(matches!(
        smooth_structured_coarse(&block, &mut f, &c, p, 1, &o, &mut s),
        Err(Error::InvalidParameter {
            arg: "coarse.factor",
            ..
        })
    ));
    assert_eq!(f, good);

    // Sweep: bad region, bad lengths, non-finite weight and source.
    let mut dst = vec![7.0; n];
    let bad_region = BlockRegion {
        lo: [0; 3],
        hi: [5, 3, 2],
    };
    assert!(matches!(
        structured_sweep(&block, &good, &mut dst, 0.3, &o, &bad_region),
        Err(Error::IndexOutOfRange {
            arg: "region.hi",
            position: 0,
            index: 5,
            ..
        })
    ));
    let inverted = BlockRegion {
        lo: [2, 0, 0],
        hi: [1, 3, 2],
    };
    assert!(matches!(
        structured_sweep(&block, &good, &mut dst, 0.3, &o, &inverted),
        Err(Error::IndexOutOfRange {
            arg: "region.lo",
            ..
        })
    ));
    assert_eq!(
        structured_sweep(
            &block,
            &good,
            &mut dst,
            f64::NAN,
            &o,
            &BlockRegion::all(&block)
        ),
        Err(Error::NonFinite {
            arg: "weight",
            position: 0
        })
    );
    assert_eq!(
        structured_sweep(&block, &nan, &mut dst, 0.3, &o, &BlockRegion::all(&block)),
        Err(Error::NonFinite {
            arg: "src",
            position: 17
        })
    );
    assert_eq!(
        structured_sweep(
            &block,
            &good,
            &mut dst[..3],
            0.3,
            &o,
            &BlockRegion::all(&block)
        ),
        Err(Error::LengthMismatch {
            arg: "dst",
            expected: 24,
            actual: 3
        })
    );
    assert!(dst.iter().all(|&v| v == 7.0));
}
