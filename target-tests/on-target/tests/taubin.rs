//! Taubin λ|μ smoothing (Alter) on target, in f32 and f64: the structured filter and its
//! coarse-grid variant keep linear fields and damp checkerboard noise with bounded growth, the
//! graph filter keeps constant fields and fixed nodes, the line tools (arclength,
//! redistribution, stretching) are exact where the algebra is, and `smooth_arclength` reduces
//! stretching while every point stays on its line and every line stays monotone; with a free
//! outer end (Alter's adapted grid) the outer points slide along their lines and the wall
//! stays, with fixed ends both faces stay, and a free end on a seam is refused.
#![no_std]
#![no_main]

use deform_kernel::Direction;
use deform_kernel::Directions;
use deform_on_target as _;

use deform_golden::XorShift;
use deform_kernel::taubin::{
    arclength, check_lines_increasing, graph_scratch_len, inverse_distance_weights, max_stretching,
    redistribute, redistribute_scratch_len, smooth_arclength, smooth_arclength_scratch_len,
    smooth_graph, smooth_structured, smooth_structured_coarse, stretching,
    structured_coarse_scratch_len, structured_scratch_len, structured_sweep, BlockRegion, Coarse,
    GraphOptions, LineEnd, Prolongation, SmoothOptions, StructuredOptions, TaubinParams,
};
use deform_kernel::{Block, Error, Real};
use deform_on_target::mesh::{Mesh, N, NE};
use deform_on_target::{max_abs, max_diff, precision, same_bits};

/// 5 × 5 × 3: `n − 1` divisible by the coarse factor 2, so coarse points are evenly spaced.
const BX: [usize; 3] = [5, 5, 3];
const BN: usize = 75;

fn linear_field<T: Real>(b: &Block) -> [T; BN] {
    let mut f = [T::ZERO; BN];
    for (p, v) in f.iter_mut().enumerate() {
        let [i, j, k] = b.ijk(p);
        *v = T::from_f64(0.5 + 1.25 * i as f64 - 0.75 * j as f64 + 2.0 * k as f64);
    }
    f
}

fn max1<T: Real>(a: &[T]) -> T {
    a.iter().fold(T::ZERO, |m, &x| m.max(x.abs()))
}

fn diff1<T: Real>(a: &[T], b: &[T]) -> T {
    a.iter()
        .zip(b)
        .fold(T::ZERO, |m, (&x, &y)| m.max((x - y).abs()))
}

fn structured<T: Real>() {
    let b = Block::new(BX).unwrap();
    let params = TaubinParams::paper();
    // A linear field is a fixed point of every stencil (interior, face, edge; corners fixed).
    let lin = linear_field::<T>(&b);
    let mut f = lin;
    let mut scratch = [T::ZERO; BN];
    let opts = StructuredOptions {
        fixed: None,
        mirror: Directions::NONE,
    };
    let len = structured_scratch_len(&b);
    let r = smooth_structured(&b, &mut f, params, 10, &opts, &mut scratch[..len]).unwrap();
    defmt::assert_eq!(r.iterations, 10);
    let tol = T::from_f64(64.0) * T::EPSILON * max1(&lin);
    defmt::assert!(diff1(&f, &lin) <= tol, "fine");
    // The coarse-grid variant with value prolongation keeps it too (linear interpolation).
    let mut f = lin;
    let coarse = Coarse {
        factor: [2, 2, 1],
        prolongation: Prolongation::Values,
    };
    let mut cs = [T::ZERO; 2 * BN];
    let len = structured_coarse_scratch_len(&b, &coarse);
    smooth_structured_coarse(&b, &mut f, &coarse, params, 10, &opts, &mut cs[..len]).unwrap();
    defmt::assert!(diff1(&f, &lin) <= tol, "coarse");
    // Checkerboard noise is damped; random noise does not grow; pinned points keep their bits.
    let mut f = [T::ZERO; BN];
    for (p, v) in f.iter_mut().enumerate() {
        let [i, j, k] = b.ijk(p);
        *v = if (i + j + k) % 2 == 0 {
            T::ONE
        } else {
            -T::ONE
        };
    }
    let before: T = f.iter().fold(T::ZERO, |s, &x| s + x * x);
    smooth_structured(&b, &mut f, params, 10, &opts, &mut scratch[..BN]).unwrap();
    let after: T = f.iter().fold(T::ZERO, |s, &x| s + x * x);
    defmt::info!(
        "{=str} checkerboard energy {=f64} -> {=f64}",
        precision::<T>(),
        before.to_f64(),
        after.to_f64()
    );
    defmt::assert!(after < before * T::HALF);
    let mut rng = XorShift::new(0x7A0B_0001);
    let mut f = [T::ZERO; BN];
    for v in f.iter_mut() {
        *v = rng.uniform(-1.0, 1.0);
    }
    let orig = f;
    let mut pinned = [0u8; BN];
    pinned[17] = 1;
    pinned[42] = 1;
    let popts = StructuredOptions {
        fixed: Some(&pinned),
        mirror: Directions::from_flags([false, true, false]),
    };
    smooth_structured(&b, &mut f, params, 20, &popts, &mut scratch[..BN]).unwrap();
    defmt::assert!(max1(&f) <= max1(&orig) * T::from_f64(1.05));
    defmt::assert!(f[17] == orig[17] && f[42] == orig[42]);
    // One sweep over the whole region equals the sweep split into two boxes.
    let mut whole = [T::ZERO; BN];
    let mut split = [T::ZERO; BN];
    let w = params.lambda;
    structured_sweep(&b, &orig, &mut whole, w, &opts, &BlockRegion::all(&b)).unwrap();
    let lo = BlockRegion {
        lo: [0, 0, 0],
        hi: [5, 5, 1],
    };
    let hi = BlockRegion {
        lo: [0, 0, 1],
        hi: [5, 5, 3],
    };
    structured_sweep(&b, &orig, &mut split, w, &opts, &lo).unwrap();
    structured_sweep(&b, &orig, &mut split, w, &opts, &hi).unwrap();
    defmt::assert!(whole
        .iter()
        .zip(&split)
        .all(|(a, b)| a.to_bits_u64() == b.to_bits_u64()));
    // Typed errors, nothing written.
    defmt::assert!(matches!(
        smooth_structured(&b, &mut f[..BN - 1], params, 1, &opts, &mut scratch),
        Err(Error::LengthMismatch { .. })
    ));
    let bad = TaubinParams {
        lambda: T::ONE,
        mu: T::ONE,
    };
    let keep = f;
    defmt::assert!(matches!(
        smooth_structured(&b, &mut f, bad, 1, &opts, &mut scratch),
        Err(Error::InvalidParameter { .. })
    ));
    defmt::assert!(matches!(
        smooth_structured(&b, &mut f, params, 1, &opts, &mut scratch[..3]),
        Err(Error::BufferTooSmall { .. })
    ));
    defmt::assert!(f.iter().zip(&keep).all(|(a, b)| a == b));
}

fn graph<T: Real>() {
    let m = Mesh::<T>::new(0.25);
    let g = m.graph();
    let mut w = [T::ZERO; NE];
    let w = &mut w[..m.used];
    inverse_distance_weights(&g, &m.points, w).unwrap();
    defmt::assert!(w.iter().all(|&x| x > T::ZERO && x.is_finite()));
    let w: &[T] = w;
    let params = TaubinParams::paper();
    let mut scratch = [[T::ZERO; 2]; N];
    let len = graph_scratch_len(&g);
    // A constant field stays constant (within rounding of the weighted mean).
    let c = [T::from_f64(1.375), T::from_f64(-2.5)];
    let mut v = [c; N];
    let opts = GraphOptions {
        weights: Some(w),
        fixed: None,
    };
    smooth_graph(&g, &mut v, params, 10, &opts, &mut scratch[..len]).unwrap();
    defmt::assert!(max_diff(&v, &[c; N]) <= T::from_f64(16.0) * T::EPSILON * T::from_f64(2.5));
    // Noisy coordinates: fixed nodes keep their bits, no growth, the noise shrinks.
    let mut rng = XorShift::new(0x7A0B_0002);
    let mut v = m.points;
    for (p, &f) in v.iter_mut().zip(&m.fixed) {
        if f == 0 {
            p[0] += rng.uniform::<T>(-0.2, 0.2);
            p[1] += rng.uniform::<T>(-0.2, 0.2);
        }
    }
    let noisy = v;
    let opts = GraphOptions {
        weights: None,
        fixed: Some(&m.fixed),
    };
    let r = smooth_graph(&g, &mut v, params, 30, &opts, &mut scratch[..len]).unwrap();
    defmt::assert_eq!(r.iterations, 30);
    for ((a, b), &f) in v.iter().zip(&noisy).zip(&m.fixed) {
        if f != 0 {
            defmt::assert!(same_bits(&[*a], &[*b]));
        }
    }
    defmt::assert!(max_abs(&v) <= max_abs(&noisy));
    let rough = |p: &[[T; 2]; N]| {
        let mut s = T::ZERO;
        for (i, _, row) in g.rows() {
            for &j in row {
                let (a, b) = (p[i], p[j as usize]);
                s += (a[0] - b[0]).sq() + (a[1] - b[1]).sq();
            }
        }
        s
    };
    defmt::info!(
        "{=str} graph roughness {=f64} -> {=f64}",
        precision::<T>(),
        rough(&noisy).to_f64(),
        rough(&v).to_f64()
    );
    defmt::assert!(rough(&v) < rough(&noisy));
    defmt::assert!(matches!(
        smooth_graph(&g, &mut v, params, 1, &opts, &mut scratch[..len - 1]),
        Err(Error::BufferTooSmall { .. })
    ));
}

/// A 6 × 3 block of straight i-lines with geometric spacing (ratio 1.5) along x.
fn stretched<T: Real>() -> (Block, [[T; 2]; 18]) {
    let b = Block::new([6, 3, 1]).unwrap();
    let mut p = [[T::ZERO; 2]; 18];
    for (n, pt) in p.iter_mut().enumerate() {
        let [i, j, _] = b.ijk(n);
        let x = ([1.0f64, 1.5, 2.25, 3.375, 5.0625, 7.59375][i] - 1.0) / 0.5;
        *pt = [T::from_f64(x), T::from_f64(j as f64)];
    }
    (b, p)
}

fn lines<T: Real>() {
    let (b, p) = stretched::<T>();
    let mut s = [T::ZERO; 18];
    arclength(&b, &p, Direction::I, false, &mut s).unwrap();
    for (n, &x) in s.iter().enumerate() {
        // Straight lines along x from x = 0: S = x up to rounding of the partial sums.
        defmt::assert!((x - p[n][0]).abs() <= T::from_f64(8.0) * T::EPSILON * T::from_f64(16.0));
    }
    let mut sn = [T::ZERO; 18];
    arclength(&b, &p, Direction::I, true, &mut sn).unwrap();
    defmt::assert!(sn[0] == T::ZERO && sn[5] == T::ONE && sn[17] == T::ONE);
    check_lines_increasing::<T, 2>(&b, &sn, Direction::I, 0, None).unwrap();
    // Stretching: 1.5 inside every line, 1 at the ends.
    let mut r = [T::ZERO; 18];
    stretching(&b, &p, Direction::I, &mut r).unwrap();
    defmt::assert!(r[0] == T::ONE && r[5] == T::ONE);
    defmt::assert!((r[2] - T::from_f64(1.5)).abs() <= T::from_f64(8.0) * T::EPSILON);
    let (worst, _) = max_stretching(&b, &p, Direction::I).unwrap();
    defmt::assert!((worst - T::from_f64(1.5)).abs() <= T::from_f64(8.0) * T::EPSILON);
    // Redistribution to the line's own arclength returns every point bit for bit.
    let mut q = p;
    let mut scratch = [T::ZERO; 32];
    let len = redistribute_scratch_len::<2>(&b, Direction::I);
    let moved = redistribute(&b, &mut q, Direction::I, &sn, true, &mut scratch[..len]).unwrap();
    defmt::assert!(moved == T::ZERO && same_bits(&q, &p));
    // Uniform targets give uniform spacing on the same lines (y unchanged, x monotone).
    let mut uniform = [T::ZERO; 18];
    for (n, u) in uniform.iter_mut().enumerate() {
        *u = T::from_usize(n % 6) / T::from_f64(5.0);
    }
    redistribute(
        &b,
        &mut q,
        Direction::I,
        &uniform,
        true,
        &mut scratch[..len],
    )
    .unwrap();
    let total = p[5][0];
    for (n, (a, o)) in q.iter().zip(&p).enumerate() {
        defmt::assert!(a[1].to_bits_u64() == o[1].to_bits_u64());
        let want = total * uniform[n];
        defmt::assert!((a[0] - want).abs() <= T::from_f64(16.0) * T::EPSILON * total);
    }
    let (worst, _) = max_stretching(&b, &q, Direction::I).unwrap();
    defmt::assert!(worst <= T::ONE + T::from_f64(64.0) * T::EPSILON);
    // A folded field is caught.
    let mut folded = sn;
    folded.swap(2, 3);
    defmt::assert!(matches!(
        check_lines_increasing::<T, 2>(&b, &folded, Direction::I, 7, None),
        Err(Error::FoldedLine {
            line: 0,
            iteration: 7
        })
    ));
}

const SI: usize = 9;
const SJ: usize = 7;

fn arclength_smoothing<T: Real>() {
    let b = Block::new([SI, SJ, 1]).unwrap();
    let mut rng = XorShift::new(0x7A0B_0003);
    let mut p = [[T::ZERO; 2]; SI * SJ];
    for (n, pt) in p.iter_mut().enumerate() {
        let (i, j) = (n % SI, n / SI);
        let s = i as f64 / (SI - 1) as f64;
        let noise = if i > 0 && i < SI - 1 {
            0.06 * (rng.unit_f64() - 0.5)
        } else {
            0.0
        };
        *pt = [
            T::from_f64(s * s * 4.0 + noise),
            T::from_f64(j as f64 * 0.5),
        ];
    }
    let orig = p;
    let mut opts = SmoothOptions::new(Direction::I);
    opts.normalised = true;
    let mut scratch = [T::ZERO; 8 * SI * SJ];
    let len = smooth_arclength_scratch_len::<2>(&b, Direction::I, None);
    let r = smooth_arclength(&b, &mut p, &opts, &mut scratch[..len]).unwrap();
    defmt::info!(
        "{=str} smooth_arclength: stretching {=f64} -> {=f64}, max move {=f64}",
        precision::<T>(),
        r.stretching_before.0.to_f64(),
        r.stretching_after.0.to_f64(),
        r.max_displacement.to_f64()
    );
    defmt::assert_eq!(r.iterations, 30);
    defmt::assert!(r.stretching_after.0 < r.stretching_before.0);
    for (n, (a, o)) in p.iter().zip(&orig).enumerate() {
        // Straight lines: every point stays on its line (y bits unchanged), ends stay put.
        defmt::assert!(a[1].to_bits_u64() == o[1].to_bits_u64());
        let i = n % SI;
        if i == 0 || i == SI - 1 {
            defmt::assert!(a[0].to_bits_u64() == o[0].to_bits_u64());
        }
    }
    let mut s = [T::ZERO; SI * SJ];
    arclength(&b, &p, Direction::I, false, &mut s).unwrap();
    check_lines_increasing(&b, &s, Direction::I, 0, Some(&p)).unwrap();
    let mut bad = SmoothOptions::new(Direction::I);
    bad.params.mu = T::HALF;
    defmt::assert!(matches!(
        smooth_arclength(&b, &mut p, &bad, &mut scratch[..len]),
        Err(Error::InvalidParameter { arg: "mu", .. })
    ));
}

const FI: usize = 6;
const FJ: usize = 5;
const FK: usize = 7;
const FN: usize = FI * FJ * FK;

/// Straight k-lines (x, y fixed) whose lengths are rough by ±1 %, clustered at both ends.
fn rough_lines<T: Real>() -> [[T; 3]; FN] {
    let mut rng = XorShift::new(0x7A0B_0033);
    let mut len = [0.0f64; FI * FJ];
    for l in len.iter_mut() {
        *l = 1.0 + 0.02 * (rng.unit_f64() - 0.5);
    }
    let mut p = [[T::ZERO; 3]; FN];
    for (n, pt) in p.iter_mut().enumerate() {
        let (l, k) = (n % (FI * FJ), n / (FI * FJ));
        let u = k as f64 / (FK - 1) as f64;
        let z = len[l] * (3.0 * u * u - 2.0 * u * u * u + 0.5 * u) / 1.5;
        *pt = [
            T::from_f64((l % FI) as f64 * 0.3),
            T::from_f64((l / FI) as f64 * 0.3),
            T::from_f64(z),
        ];
    }
    p
}

/// Smooths along k with the given last end; the result or the error.
fn smooth_k<T: Real>(p: &mut [[T; 3]; FN], last: LineEnd, normalised: bool) -> Result<(), Error> {
    let b = Block::new([FI, FJ, FK]).unwrap();
    let mut opts = SmoothOptions::new(Direction::K);
    opts.ends = [LineEnd::Fixed, last];
    opts.normalised = normalised;
    let mut scratch = [T::ZERO; 2 * FN];
    let len = smooth_arclength_scratch_len::<3>(&b, Direction::K, None);
    smooth_arclength(&b, p, &opts, &mut scratch[..len]).map(|_| ())
}

fn free_end_smoothing<T: Real>() {
    let b = Block::new([FI, FJ, FK]).unwrap();
    let orig = rough_lines::<T>();
    let outer = FI * FJ * (FK - 1);
    let bits = |a: &[T; 3], o: &[T; 3]| (0..3).all(|c| a[c].to_bits_u64() == o[c].to_bits_u64());
    let mut p = orig;
    smooth_k(&mut p, LineEnd::Free, false).unwrap();
    for (n, (a, o)) in p.iter().zip(&orig).enumerate() {
        // On its own vertical line; the wall stays.
        defmt::assert!(a[0].to_bits_u64() == o[0].to_bits_u64());
        defmt::assert!(a[1].to_bits_u64() == o[1].to_bits_u64());
        if n < FI * FJ {
            defmt::assert!(bits(a, o));
        }
    }
    defmt::assert!((outer..FN).any(|n| !bits(&p[n], &orig[n])));
    let mut s = [T::ZERO; FN];
    arclength(&b, &p, Direction::K, false, &mut s).unwrap();
    check_lines_increasing(&b, &s, Direction::K, 0, Some(&p)).unwrap();
    // Fixed ends: both faces bit for bit.
    let mut f = orig;
    smooth_k(&mut f, LineEnd::Fixed, false).unwrap();
    for n in (0..FI * FJ).chain(outer..FN) {
        defmt::assert!(bits(&f[n], &orig[n]));
    }
    // A free end on a seam, and a free end with normalised arclength: refused, unchanged.
    let mut seam = orig;
    seam[outer + 1] = seam[outer];
    let before = seam;
    defmt::assert!(matches!(
        smooth_k(&mut seam, LineEnd::Free, false),
        Err(Error::SharedFreeEnd { point, other }) if point == outer && other == outer + 1
    ));
    let mut n = orig;
    defmt::assert!(matches!(
        smooth_k(&mut n, LineEnd::Free, true),
        Err(Error::InvalidParameter {
            arg: "options.ends",
            ..
        })
    ));
    defmt::assert!((0..FN).all(|q| bits(&seam[q], &before[q]) && bits(&n[q], &orig[q])));
}

#[defmt_test::tests]
mod tests {
    use super::*;

    #[test]
    fn free_end_smoothing_f64() {
        free_end_smoothing::<f64>();
    }

    #[test]
    fn free_end_smoothing_f32() {
        free_end_smoothing::<f32>();
    }

    #[test]
    fn structured_and_coarse_f64() {
        structured::<f64>();
    }

    #[test]
    fn structured_and_coarse_f32() {
        structured::<f32>();
    }

    #[test]
    fn graph_f64() {
        graph::<f64>();
    }

    #[test]
    fn graph_f32() {
        graph::<f32>();
    }

    #[test]
    fn arclength_redistribute_stretching_f64() {
        lines::<f64>();
    }

    #[test]
    fn arclength_redistribute_stretching_f32() {
        lines::<f32>();
    }

    #[test]
    fn smooth_arclength_f64() {
        arclength_smoothing::<f64>();
    }

    #[test]
    fn smooth_arclength_f32() {
        arclength_smoothing::<f32>();
    }
}
