//! `ExactSum` against an independent exact reference (Shewchuk's partials, the algorithm of
//! Python's `math.fsum`, correctly rounded), and its order and split independence.

use deform_kernel::exact_sum::{ExactSum, EXACT_SUM_WORDS};
use proptest::prelude::*;

/// Correctly rounded sum by Shewchuk's non-overlapping partials (`math.fsum`), for finite
/// terms whose partial sums stay finite.
fn fsum(xs: &[f64]) -> f64 {
    let mut partials: Vec<f64> = Vec::new();
    for &x in xs {
        let mut x = x;
        let mut i = 0;
        for j in 0..partials.len() {
            let mut y = partials[j];
            if x.abs() < y.abs() {
                core::mem::swap(&mut x, &mut y);
            }
            let hi = x + y;
            let lo = y - (hi - x);
            if lo != 0.0 {
                partials[i] = lo;
                i += 1;
            }
            x = hi;
        }
        partials.truncate(i);
        partials.push(x);
    }
    // Round the partials' exact sum (as fsum does, with the half-way correction).
    let mut n = partials.len();
    if n == 0 {
        return 0.0;
    }
    n -= 1;
    let mut hi = partials[n];
    let mut lo = 0.0;
    while n > 0 {
        n -= 1;
        let x = hi;
        let y = partials[n];
        hi = x + y;
        let yr = hi - x;
        lo = y - yr;
        if lo != 0.0 {
            break;
        }
    }
    if n > 0 && ((lo < 0.0 && partials[n - 1] < 0.0) || (lo > 0.0 && partials[n - 1] > 0.0)) {
        let y = lo * 2.0;
        let x = hi + y;
        let yr = x - hi;
        if y == yr {
            hi = x;
        }
    }
    hi
}

fn exact(xs: &[f64]) -> f64 {
    let mut s = ExactSum::new();
    s.add_all(xs);
    s.value()
}

fn any_finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-1e3f64..1e3),
        any::<u64>().prop_map(|b| {
            let x = f64::from_bits(b);
            if x.is_finite() && x.abs() < 1e300 {
                x
            } else {
                0.5
            }
        }),
        (-1e-300f64..1e-300),
        Just(f64::MIN_POSITIVE / 8.0),
        Just(-5e-324),
    ]
}

#[test]
fn cancellation_is_exact() {
    assert_eq!(exact(&[1e300, 1.0, -1e300]), 1.0);
    assert_eq!(exact(&[1e308, 1e308, -1e308, -1e308, 3.0]), 3.0);
    assert_eq!(exact(&[0.1, 0.2, -0.3]), fsum(&[0.1, 0.2, -0.3]));
    assert_eq!(exact(&[5e-324, 5e-324, -1e-323]), 0.0);
    assert_eq!(exact(&[5e-324, 5e-324]), 1e-323);
    assert_eq!(exact(&[]), 0.0);
    assert_eq!(exact(&[-2.5]), -2.5);
}

#[test]
fn halfway_cases_round_to_even() {
    // 1 + 2^-53 is exactly half-way between 1 and its successor: ties to even gives 1.
    assert_eq!(exact(&[1.0, 2f64.powi(-53)]), 1.0);
    // ... and one more tiny term breaks the tie upwards.
    assert_eq!(exact(&[1.0, 2f64.powi(-53), 1e-300]), 1.0 + f64::EPSILON);
    let odd = 1.0 + f64::EPSILON;
    assert_eq!(exact(&[odd, 2f64.powi(-53)]), 1.0 + 2.0 * f64::EPSILON);
    assert_eq!(
        exact(&[-odd, -(2f64.powi(-53))]),
        -(1.0 + 2.0 * f64::EPSILON)
    );
}

#[test]
fn overflow_and_non_finite_terms() {
    assert_eq!(exact(&[f64::MAX, f64::MAX]), f64::INFINITY);
    assert_eq!(exact(&[-f64::MAX, -f64::MAX]), f64::NEG_INFINITY);
    // The exact sum comes back into range: no spurious overflow.
    assert_eq!(exact(&[f64::MAX, f64::MAX, -f64::MAX]), f64::MAX);
    assert_eq!(exact(&[1.0, f64::INFINITY]), f64::INFINITY);
    assert!(exact(&[f64::INFINITY, f64::NEG_INFINITY]).is_nan());
    assert!(exact(&[1.0, f64::NAN]).is_nan());
}

#[test]
fn f32_terms() {
    let mut s = ExactSum::new();
    s.add(1.0e19f32);
    s.add(1.0f32);
    s.add(-1.0e19f32);
    assert_eq!(s.value::<f32>(), 1.0);
    assert_eq!(s.value::<f64>(), 1.0);
}

#[test]
fn words_round_trip_and_sum_like_mpi() {
    let parts: Vec<Vec<f64>> = (0..5)
        .map(|r| {
            (0..1000)
                .map(|i| ((i * 7 + r * 13) as f64).sin() * 1e10f64.powi(r % 3))
                .collect()
        })
        .collect();
    let all: Vec<f64> = parts.concat();
    let mut summed = [0i64; EXACT_SUM_WORDS];
    for p in &parts {
        let mut s = ExactSum::new();
        s.add_all(p);
        for (a, b) in summed.iter_mut().zip(s.to_words()) {
            *a += b; // what MPI_SUM on MPI_INT64_T does
        }
    }
    let merged = ExactSum::from_words(summed);
    assert_eq!(merged.value::<f64>(), fsum(&all));
    assert_eq!(merged.value::<f64>(), exact(&all));
}

#[test]
fn many_terms_cross_the_carry_limit() {
    // 6e11 terms of a large magnitude (by merging a 1,000-term sum 6e8 times... in 6e5
    // merges of a 1e6-term block): carries propagate many times and nothing is lost.
    let big = f64::MAX / 2f64.powi(40);
    let mut block = ExactSum::new();
    for _ in 0..1000 {
        block.add_f64(big);
    }
    let mut s = ExactSum::new();
    for _ in 0..600_000 {
        s.merge(&block);
    }
    assert_eq!(s.value::<f64>(), 6e8 * big);
    let mut t = ExactSum::new();
    for _ in 0..600_000 {
        t.merge(&block);
        t.add_f64(-big);
    }
    assert_eq!(t.value::<f64>(), 599_400_000.0 * big);
}

proptest! {
    #[test]
    fn equals_fsum(xs in prop::collection::vec(any_finite(), 0..200)) {
        let (e, f) = (exact(&xs), fsum(&xs));
        // Same number, same bits (an exact zero is +0 here, fsum may give −0).
        prop_assert!(e == f && (e == 0.0 || e.to_bits() == f.to_bits()), "{e:e} vs {f:e}");
    }

    #[test]
    fn order_and_split_independent(
        xs in prop::collection::vec(any_finite(), 1..200),
        seed in any::<u64>(),
        cut in any::<prop::sample::Index>(),
    ) {
        let whole = exact(&xs);
        let mut shuffled = xs.clone();
        let mut state = seed | 1;
        for i in (1..shuffled.len()).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            shuffled.swap(i, (state % (i as u64 + 1)) as usize);
        }
        prop_assert_eq!(exact(&shuffled).to_bits(), whole.to_bits());
        let k = cut.index(xs.len() + 1);
        let (a, b) = xs.split_at(k);
        let mut sa = ExactSum::new();
        sa.add_all(a);
        let mut sb = ExactSum::new();
        sb.add_all(b);
        sb.merge(&sa);
        prop_assert_eq!(sb.value::<f64>().to_bits(), whole.to_bits());
    }
}
