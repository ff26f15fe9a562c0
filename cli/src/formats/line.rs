//! A text line assembled on the stack before one `write_all`: integers in decimal without
//! the formatting machinery, anything else through `core::fmt` (floats keep Rust's own
//! shortest round-trip digits). The writers emit millions of short lines; formatting each
//! number through `write!` on the output stream cost more than the numbers themselves.

use std::fmt;
use std::io::{self, Write};

/// `10^1 ..= 10^19`: a `u64` has one digit more than the powers it is at least.
const POW10: [u64; 19] = {
    let mut p = [10u64; 19];
    let mut i = 1;
    while i < 19 {
        p[i] = p[i - 1] * 10;
        i += 1;
    }
    p
};

/// `"00" "01" … "99"`.
const PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        t[2 * i] = b'0' + (i / 10) as u8;
        t[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    t
};

/// A line of at most [`Line::CAP`] bytes.
pub(crate) struct Line {
    buf: [u8; Line::CAP],
    len: usize,
}

impl Line {
    /// Longest line: eight node indices of 20 digits, a code, an index, separators.
    pub(crate) const CAP: usize = 256;

    pub(crate) const fn new() -> Self {
        Line {
            buf: [0; Line::CAP],
            len: 0,
        }
    }

    /// Appends `bytes`; `false` (nothing appended) when they do not fit.
    pub(crate) fn push(&mut self, bytes: &[u8]) -> bool {
        let end = self.len + bytes.len();
        match self.buf.get_mut(self.len..end) {
            Some(dst) => {
                dst.copy_from_slice(bytes);
                self.len = end;
                true
            }
            None => false,
        }
    }

    /// Appends `v` in decimal, the bytes `Display` writes: two digits at a time, straight
    /// into the line.
    pub(crate) fn push_uint(&mut self, v: u64) -> bool {
        let n = 1 + POW10.iter().take_while(|&&p| v >= p).count();
        let end = self.len + n;
        let Some(dst) = self.buf.get_mut(self.len..end) else {
            return false;
        };
        let (mut v, mut i) = (v, n);
        while i >= 2 {
            let d = (v % 100) as usize * 2;
            v /= 100;
            i -= 2;
            if let (Some(to), Some(from)) = (dst.get_mut(i..i + 2), PAIRS.get(d..d + 2)) {
                to.copy_from_slice(from);
            }
        }
        if let (1, Some(first)) = (i, dst.first_mut()) {
            *first = b'0' + v as u8;
        }
        self.len = end;
        true
    }

    /// Appends `x` as `{:e}` writes it (see [`super::float_exp`]).
    pub(crate) fn push_exp(&mut self, x: f64) -> bool {
        let mut text = [0u8; super::float_exp::EXP_CAP];
        match super::float_exp::exp_bytes(x, &mut text) {
            Some(len) => self.push(text.get(..len).unwrap_or(&[])),
            None => fmt::Write::write_fmt(self, format_args!("{x:e}")).is_ok(),
        }
    }

    /// Writes the line to `w` and empties it.
    pub(crate) fn flush_to<W: Write + ?Sized>(&mut self, w: &mut W) -> io::Result<()> {
        let r = w.write_all(self.buf.get(..self.len).unwrap_or(&[]));
        self.len = 0;
        r
    }
}

impl fmt::Write for Line {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        if self.push(s.as_bytes()) {
            Ok(())
        } else {
            Err(fmt::Error)
        }
    }
}

/// The error of a line that does not fit [`Line::CAP`] (cannot happen for the lines written
/// here; reported rather than truncated).
pub(crate) fn too_long() -> io::Error {
    io::Error::other("internal: output line longer than its buffer")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integers_match_display_and_overflow_is_refused() {
        let mut vals = vec![0u64, 1, 9, 10, 99, 100, 12345, u32::MAX as u64, u64::MAX];
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..10_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            vals.push(x >> (x % 64));
        }
        for v in vals {
            let mut l = Line::new();
            assert!(l.push_uint(v));
            let mut out = Vec::new();
            l.flush_to(&mut out).unwrap();
            assert_eq!(out, v.to_string().into_bytes());
        }
        let mut l = Line::new();
        for _ in 0..Line::CAP {
            assert!(l.push(b"x"));
        }
        assert!(!l.push(b"y") && !l.push_uint(1));
    }
}
