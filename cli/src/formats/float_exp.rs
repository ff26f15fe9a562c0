//! The bytes Rust's `{:e}` writes for an `f64`, several times faster: the shortest round-trip
//! digits from `zmij` (Schubfach), laid out as `{:e}` lays them out (`-1.25e-3`, `0e0`).
//!
//! Both pick the shortest digit string that reads back as the same double and, of the two
//! candidates of that length, the nearer one. They differ only on an exact tie (the double is
//! exactly halfway between the two, e.g. 2⁻²⁵ = 2.98023223876953125e-8): zmij keeps the even
//! digit, core's Dragon4 rounds up (`up && 2·remainder ≥ scale` in
//! `core::num::flt2dec::strategy::dragon::format_shortest`). [`is_exact`] finds such ties by
//! integer arithmetic and the last digit is raised as core would. The tests compare with `{:e}`
//! on edge cases, ties and random bit patterns.

/// `|x| == n · 10^j` exactly, for odd `n < 2^61` (`x`'s significand `m`, exponent `e`:
/// `m 2^e == n 5^j 2^j`). The odd parts must agree, so a power of 5 above `2^61` never does.
fn is_exact(x: f64, n: u64, j: i32) -> bool {
    let (m, e) = significand(x);
    let Some(&five) = POW5.get(j.unsigned_abs() as usize) else {
        return false;
    };
    if !may_tie(x, j) {
        return false;
    }
    let (m, n) = (u128::from(m), u128::from(n));
    // Both sides below 2^122 before a shift of at most 60 bits that must not lose bits.
    let shifted = |v: u128, s: i32| (s <= 60).then(|| v << s).filter(|w| w >> s == v);
    if j >= 0 {
        // m 2^(e − j) == n 5^j
        let (r, s) = (n * five, e - j);
        if s >= 0 {
            shifted(m, s) == Some(r)
        } else {
            shifted(r, -s) == Some(m)
        }
    } else {
        // n == m 5^|j| 2^(e + |j|)
        let (l, t) = (m * five, e - j);
        if t >= 0 {
            shifted(l, t) == Some(n)
        } else {
            shifted(n, -t) == Some(l)
        }
    }
}

/// `|x| = m 2^e` with an integer `m < 2^53`.
fn significand(x: f64) -> (u64, i32) {
    let bits = x.to_bits() & !(1u64 << 63);
    let (biased, frac) = ((bits >> 52) as i32, bits & ((1u64 << 52) - 1));
    if biased == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), biased - 1075)
    }
}

/// A necessary condition of [`is_exact`] for some odd `n`, cheap enough to reject almost
/// every double before any product: `n` and `5^|j|` are odd, so `m` must hold exactly the
/// power of two that `2^e` lacks against `2^j`, and `5^|j|` must not exceed `2^61`.
fn may_tie(x: f64, j: i32) -> bool {
    let (m, e) = significand(x);
    m != 0
        && j.unsigned_abs() < POW5.len() as u32
        && i64::from(m.trailing_zeros()) == i64::from(j) - i64::from(e)
}

/// `5^0 ..= 5^26` (all below `2^61`).
const POW5: [u128; 27] = {
    let mut p = [1u128; 27];
    let mut i = 1;
    while i < 27 {
        p[i] = p[i - 1] * 5;
        i += 1;
    }
    p
};

/// The decimal digits (no leading or trailing zeros) and the exponent of the first digit of
/// zmij's text for a finite `x` (`1.5e-7`, `0.001`, `123.0`, `1e+16`); no digits for zero.
fn digits(text: &[u8], out: &mut [u8; 24]) -> (usize, i32) {
    let (mant, exp) = match text.iter().position(|&c| c == b'e') {
        Some(i) => (
            text.get(..i).unwrap_or(&[]),
            text.get(i + 1..).unwrap_or(&[]),
        ),
        None => (text, &[][..]),
    };
    let (neg, exp) = match exp.split_first() {
        Some((b'-', r)) => (true, r),
        Some((b'+', r)) => (false, r),
        _ => (false, exp),
    };
    let e10 = exp
        .iter()
        .fold(0i32, |a, &c| a * 10 + i32::from(c.wrapping_sub(b'0')));
    let (mut n, mut int_len, mut dot) = (0usize, 0i32, false);
    for &c in mant {
        if c == b'.' {
            dot = true;
        } else if n == 0 && c == b'0' {
            int_len -= i32::from(dot);
        } else if let Some(slot) = out.get_mut(n) {
            *slot = c;
            n += 1;
            int_len += i32::from(!dot);
        }
    }
    while n > 0 && out.get(n - 1) == Some(&b'0') {
        n -= 1;
    }
    (n, int_len - 1 + if neg { -e10 } else { e10 })
}

/// Longest text: a sign, 17 digits, a point, `e-324`.
pub(crate) const EXP_CAP: usize = 32;

/// Writes into `out` the bytes `format!("{x:e}")` gives for a finite `x` and returns their
/// length; `None` for NaN and infinities, which the caller formats with `{:e}` itself.
pub(crate) fn exp_bytes(x: f64, out: &mut [u8; EXP_CAP]) -> Option<usize> {
    if !x.is_finite() {
        return None;
    }
    let mut buf = zmij::Buffer::new();
    let text = buf.format_finite(x).as_bytes();
    let body = text.strip_prefix(b"-").unwrap_or(text);
    let mut d = [0u8; 24];
    let (n, e) = digits(body, &mut d);
    let mut w = Cursor { out, len: 0 };
    if x.is_sign_negative() {
        w.put(b"-");
    }
    let Some(last) = n.checked_sub(1) else {
        w.put(b"0e0");
        return Some(w.len);
    };
    let digits = d.get_mut(..n)?;
    let j = e - n as i32;
    if digits.last().is_some_and(|&c| (c - b'0') % 2 == 0) && may_tie(x, j) {
        let v = digits.iter().fold(0u64, |a, &c| {
            a.wrapping_mul(10).wrapping_add(u64::from(c - b'0'))
        });
        // Halfway above the even digit (it is never a 9, so no carry): core rounds up.
        if is_exact(x, v.wrapping_mul(10).wrapping_add(5), j) {
            if let Some(l) = digits.get_mut(last) {
                *l += 1;
            }
        }
    }
    let (first, rest) = digits.split_first()?;
    w.put(&[*first]);
    if !rest.is_empty() {
        w.put(b".");
        w.put(rest);
    }
    w.put(if e < 0 { b"e-" } else { b"e" });
    let mut tmp = [0u8; 4];
    let mut at = tmp.len();
    let mut v = e.unsigned_abs();
    while at > 0 {
        at -= 1;
        if let Some(t) = tmp.get_mut(at) {
            *t = b'0' + (v % 10) as u8;
        }
        v /= 10;
        if v == 0 {
            break;
        }
    }
    w.put(tmp.get(at..).unwrap_or(&[]));
    Some(w.len)
}

/// Appends to a fixed buffer (the text always fits [`EXP_CAP`]).
struct Cursor<'a> {
    out: &'a mut [u8; EXP_CAP],
    len: usize,
}

impl Cursor<'_> {
    fn put(&mut self, bytes: &[u8]) {
        // Byte by byte: the pieces are a few bytes, shorter than a call to `memcpy`.
        for &b in bytes {
            if let Some(d) = self.out.get_mut(self.len) {
                *d = b;
                self.len += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn same(x: f64) {
        let mut got = [0u8; EXP_CAP];
        match exp_bytes(x, &mut got) {
            Some(len) => assert_eq!(
                String::from_utf8_lossy(&got[..len]),
                format!("{x:e}"),
                "bits {:#x}",
                x.to_bits()
            ),
            None => assert!(!x.is_finite()),
        }
    }

    #[test]
    fn edge_cases_and_ties_are_core_fmts_bytes() {
        let mut v = vec![
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            f64::EPSILON,
            5e-324,
            -5e-324,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.1,
            1.0 / 3.0,
            100.0,
            1e15,
            1e16,
            1e17,
            123456.0,
            // Exact ties: core rounds up, zmij to even.
            2.980_232_238_769_531_2e-8,
            1_125_899_906_842_624.2,
        ];
        for k in -1074..=1023 {
            let p = 2f64.powi(k);
            v.extend([p, -p, 3.0 * p, 5.0 * p]);
        }
        for k in -330..=310 {
            v.push(format!("1e{k}").parse().unwrap());
        }
        for bits in 0..2000u64 {
            v.push(f64::from_bits(bits));
            v.push(f64::from_bits(0x7fef_ffff_ffff_ffff - bits));
            v.push(f64::from_bits(0x0010_0000_0000_0000 + bits - 1000));
        }
        for i in 0..20_000i32 {
            let x = f64::from(i);
            v.extend([x, x / 1024.0, x * 0.001, x / 10.0, x * 1e-7, x * 1e20]);
        }
        let next: Vec<f64> = v
            .iter()
            .flat_map(|x| [x.to_bits().wrapping_add(1), x.to_bits().wrapping_sub(1)])
            .map(f64::from_bits)
            .collect();
        for x in v.into_iter().chain(next) {
            same(x);
        }
    }

    #[test]
    fn random_bits_dyadics_and_coordinates_are_core_fmts_bytes() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..200_000 {
            let r = rnd();
            same(f64::from_bits(r));
            same(f64::from_bits(r & 0x000f_ffff_ffff_ffff));
            let u = (rnd() >> 11) as f64 / (1u64 << 53) as f64;
            same(4.0 * u - 2.0);
            // Few significant bits: many exact ties.
            let d = ((r >> 11) >> (r % 53)) as f64 * 2f64.powi((r % 181) as i32 - 90);
            same(d);
            same(f64::from_bits(d.to_bits() + 1));
        }
    }
}
