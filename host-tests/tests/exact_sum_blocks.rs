//! The blocked `ExactSum` (issue 27 item 6) against a copy of the per-term path it replaced:
//! the same exact sum (the normalized words, non-finite counts included) and so the same
//! bits, on random, adversarial and merge-order cases, for `f64` and `f32` terms.

use deform_kernel::exact_sum::{ExactSum, Gather, EXACT_SUM_WORDS};
use proptest::prelude::*;

/// Neal's small superaccumulator adding one term at a time: the code `ExactSum::add_f64`
/// ran before blocks (68 digits of 32 bits, then NaN, +∞, −∞ counts, then the load word).
struct PerTerm {
    words: [i64; EXACT_SUM_WORDS],
    terms: i64,
}

impl PerTerm {
    fn new() -> Self {
        PerTerm {
            words: [0; EXACT_SUM_WORDS],
            terms: 0,
        }
    }

    fn add(&mut self, x: f64) {
        let bits = x.to_bits();
        if bits << 1 == 0 {
            return;
        }
        let field = ((bits >> 52) & 0x7ff) as u32;
        let negative = bits >> 63 != 0;
        let mut m = bits & ((1u64 << 52) - 1);
        if field == 0x7ff {
            let slot = match (m != 0, negative) {
                (true, _) => 68,
                (false, false) => 69,
                (false, true) => 70,
            };
            self.words[slot] += 1;
            return;
        }
        let p = if field == 0 {
            0
        } else {
            m |= 1u64 << 52;
            field - 1
        };
        let shift = p & 31;
        let c = (p >> 5) as usize;
        let sign = -i64::from(negative);
        let lo = (((m << shift) & 0xffff_ffff) as i64 ^ sign) - sign;
        let high = m >> (32 - shift);
        let mid = ((high & 0xffff_ffff) as i64 ^ sign) - sign;
        let top = ((high >> 32) as i64 ^ sign) - sign;
        self.words[c] += lo;
        self.words[c + 1] += mid;
        self.words[c + 2] += top;
        self.terms += 1;
    }

    /// The words in `ExactSum::to_words` form (carries propagated, load 1).
    fn to_words(&self) -> [i64; EXACT_SUM_WORDS] {
        let mut w = self.words;
        w[EXACT_SUM_WORDS - 1] = self.terms; // bounds every digit: |d| ≤ (terms + 1) 2^32
        ExactSum::from_words(w).to_words()
    }
}

/// Asserts that the blocked sum of `xs` is the per-term one: words and `f64`/`f32` bits.
fn check(xs: &[f64]) {
    let mut s = ExactSum::new();
    let mut r = PerTerm::new();
    for &x in xs {
        s.add_f64(x);
        r.add(x);
    }
    let reference = ExactSum::from_words(r.to_words());
    assert_eq!(s.to_words(), r.to_words(), "words of {xs:?}");
    let (a, b) = (s.value::<f64>(), reference.value::<f64>());
    assert!(a.to_bits() == b.to_bits(), "{a:e} vs {b:e} for {xs:?}");
    let (a, b) = (s.value::<f32>(), reference.value::<f32>());
    assert!(a.to_bits() == b.to_bits(), "{a:e} vs {b:e} (f32)");
    assert_eq!(s, reference);
    check_gathered(xs, &r);
}

/// The per-term reference of `xs`.
fn per_term(xs: impl Iterator<Item = f64>) -> PerTerm {
    let mut r = PerTerm::new();
    xs.for_each(|x| r.add(x));
    r
}

/// Asserts that `xs` gathered into sums ([`Gather`], as the CG loops add their terms) gives
/// the per-term words `r`: one column into a sum already holding a few buffered terms, rows
/// of three into one sum, and two lanes (even and odd terms) against their own references.
fn check_gathered(xs: &[f64], r: &PerTerm) {
    let (head, tail) = xs.split_at(xs.len().min(5));
    let mut s = ExactSum::new();
    head.iter().for_each(|&x| s.add_f64(x));
    {
        let mut g = Gather::lanes(core::array::from_mut(&mut s));
        tail.iter().for_each(|&x| g.push([x]));
    }
    assert_eq!(s.to_words(), r.to_words(), "one column of {xs:?}");
    let mut s = ExactSum::new();
    {
        let mut g = Gather::<3>::one(&mut s);
        for row in xs.chunks(3) {
            let mut padded = [0.0; 3]; // +0 terms change no sum
            padded[..row.len()].copy_from_slice(row);
            g.push(padded);
        }
    }
    assert_eq!(s.to_words(), r.to_words(), "rows of three of {xs:?}");
    let mut lanes = [ExactSum::new(); 2];
    {
        let mut g = Gather::lanes(&mut lanes);
        xs.chunks_exact(2).for_each(|c| g.push([c[0], c[1]]));
    }
    let even = per_term(xs.chunks_exact(2).map(|c| c[0]));
    let odd = per_term(xs.chunks_exact(2).map(|c| c[1]));
    assert_eq!(lanes[0].to_words(), even.to_words(), "even lane of {xs:?}");
    assert_eq!(lanes[1].to_words(), odd.to_words(), "odd lane of {xs:?}");
    let (a, b) = (
        lanes[1].value::<f64>(),
        ExactSum::from_words(odd.to_words()).value::<f64>(),
    );
    assert!(a.to_bits() == b.to_bits(), "{a:e} vs {b:e}, odd lane");
}

/// Lengths around the block size (64 on 64-bit hosts, 8 on 32-bit targets).
const LENGTHS: [usize; 14] = [0, 1, 2, 7, 8, 9, 63, 64, 65, 127, 128, 129, 200, 1000];

/// Deterministic values for the adversarial cases.
fn lcg(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// `n` terms drawn by `f` from a seeded generator.
fn terms(n: usize, seed: u64, f: impl Fn(f64, usize) -> f64) -> Vec<f64> {
    let mut s = seed;
    (0..n).map(|i| f(lcg(&mut s), i)).collect()
}

#[test]
fn adversarial_cases_equal_the_per_term_path() {
    let p = f64::powi;
    for n in LENGTHS {
        // Products as CG forms them, and the same with a cancelling tail.
        check(&terms(n, 1, |x, i| x * (i as f64 + 0.5).sin()));
        let mut c = terms(n, 2, |x, _| x * 1e6);
        c.extend(c.clone().iter().map(|x| -x * (1.0 + f64::EPSILON)));
        check(&c);
        // 2^±1000 mixed, every binade between, subnormals, the largest finite values.
        check(&terms(n, 3, |x, i| {
            x * p(2.0, [1000, -1000, 0, 500][i % 4])
        }));
        check(&terms(n, 4, |x, i| {
            x * p(2.0, (i as i32 * 37) % 2000 - 1000)
        }));
        check(&terms(n, 5, |x, _| x * 1e-310));
        check(&terms(
            n,
            6,
            |x, i| if i % 3 == 0 { 5e-324 } else { x * 1e-300 },
        ));
        check(&terms(n, 7, |x, _| f64::MAX * x.signum()));
        check(&terms(n, 8, |_, _| f64::MAX)); // the plain sum overflows
        check(&terms(n, 9, |x, i| if i == n / 2 { f64::MAX } else { x }));
        check(&terms(n, 10, |x, i| x * p(2.0, 1013 + (i % 12) as i32)));
        // ±0 terms and sums that are exactly zero (+0), also of −0 terms only.
        check(&terms(n, 11, |_, i| if i % 2 == 0 { -0.0 } else { 0.0 }));
        check(&terms(n, 12, |_, i| if i % 2 == 0 { 1.5 } else { -1.5 }));
        // Non-finite terms anywhere: counted exactly as before.
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in [0, n / 2, n.saturating_sub(1)] {
                check(&terms(n, 13, |x, i| if i == at { bad } else { x }));
            }
        }
        check(&terms(n, 14, |x, i| {
            [f64::INFINITY, f64::NEG_INFINITY, x][i % 3]
        }));
        check(&terms(
            n,
            15,
            |x, i| if i % 5 == 0 { f64::NAN } else { x * 1e300 },
        ));
        // Ties: terms half an ulp apart from the running sum.
        check(&terms(n, 16, |_, i| if i == 0 { 1.0 } else { p(2.0, -53) }));
    }
}

#[test]
fn merge_orders_equal_the_per_term_path() {
    let xs = terms(1000, 21, |x, i| {
        x * f64::powi(2.0, (i as i32 * 7) % 120 - 60)
    });
    for cut in [1, 63, 64, 65, 300, 999] {
        let (a, b) = xs.split_at(cut);
        let (mut sa, mut sb) = (ExactSum::new(), ExactSum::new());
        a.iter().for_each(|&x| sa.add_f64(x));
        b.iter().for_each(|&x| sb.add_f64(x));
        let mut ab = sa;
        ab.merge(&sb);
        let mut ba = sb;
        ba.merge(&sa);
        let mut r = PerTerm::new();
        xs.iter().for_each(|&x| r.add(x));
        assert_eq!(ab.to_words(), r.to_words());
        assert_eq!(ba.to_words(), r.to_words());
        // Through the word protocol, as MPI_SUM would add them.
        let mut w = sa.to_words();
        for (w, v) in w.iter_mut().zip(sb.to_words()) {
            *w += v;
        }
        assert_eq!(ExactSum::from_words(w).to_words(), r.to_words());
        // In place, as `Collective::sum_exact` does.
        let mut x = sa;
        x.exchange(|words| {
            for (w, v) in words.iter_mut().zip(sb.to_words()) {
                *w += v;
            }
        });
        assert_eq!(x.to_words(), r.to_words());
        assert_eq!(x.value::<f64>().to_bits(), ab.value::<f64>().to_bits());
    }
}

#[test]
fn f32_terms_equal_the_per_term_path() {
    let xs: Vec<f32> = terms(500, 31, |x, i| {
        x * f64::powi(2.0, (i as i32 * 5) % 200 - 100)
    })
    .iter()
    .map(|&x| x as f32)
    .collect();
    let mut s = ExactSum::new();
    s.add_all(&xs);
    let mut r = PerTerm::new();
    xs.iter().for_each(|&x| r.add(f64::from(x)));
    assert_eq!(s.to_words(), r.to_words());
    let reference = ExactSum::from_words(r.to_words());
    assert_eq!(
        s.value::<f32>().to_bits(),
        reference.value::<f32>().to_bits()
    );
}

fn any_term() -> impl Strategy<Value = f64> {
    prop_oneof![
        (-1e3f64..1e3),
        any::<u64>().prop_map(f64::from_bits), // every bit pattern: NaN, ±∞, subnormals
        (-1e-300f64..1e-300),
        Just(f64::MAX),
        Just(-5e-324),
    ]
}

proptest! {
    #[test]
    fn random_terms_equal_the_per_term_path(xs in prop::collection::vec(any_term(), 0..300)) {
        check(&xs);
    }

    #[test]
    fn random_products_equal_the_per_term_path(
        xs in prop::collection::vec((-1e3f64..1e3, -20i32..20), 0..300),
    ) {
        let t: Vec<f64> = xs.iter().map(|&(x, e)| x * f64::powi(2.0, e) * x).collect();
        check(&t);
    }
}
