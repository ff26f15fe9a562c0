//! Fortran list-directed input (`READ (unit, *)`), as Fortran programs such as CFL3D write
//! their text grids: values separated by blanks, by a comma (with blanks around it or not) or
//! by line ends, `r*c` for `r` copies of `c`, `r*` or two commas in a row for `r` or one null
//! value, and `/` ending the record (the rest of the line is not read). Line breaks may fall
//! between any two values.
//!
//! The file is read as one stream of values; repeat counts are kept as runs (a few bytes may
//! stand for millions of values) and expanded only when read. Null values are kept so that the
//! reader that needs a number there can refuse them with the line and the token: Fortran
//! leaves the variable unchanged, which a grid file cannot rely on.

use super::error::{FormatError, FormatErrorKind, Location};

/// At most this many values after expanding repeat counts (2^28: a grid of 89 million 3D
/// points). More is refused before anything of that size is allocated.
pub const MAX_VALUES: u64 = 1 << 28;

/// One item of the stream: a value or a null, repeated `repeat` times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Item<'a> {
    /// 1-based line of the token.
    pub line: usize,
    /// The whole token as written (`2*0.5`, `3*`, `0.5`, or `,` for a null between commas).
    pub token: &'a [u8],
    /// The value's text (`0.5` in `2*0.5`); `None` for a null value.
    pub value: Option<&'a [u8]>,
    /// How many values this item stands for (1 without a repeat count).
    pub repeat: u64,
}

/// The values of a list-directed file, with random access by value index.
#[derive(Debug, Default)]
pub struct Values<'a> {
    items: Vec<Item<'a>>,
    /// `ends[k]`: the number of values in items `0..=k`.
    ends: Vec<u64>,
}

/// Splits a line (without its end) into tokens: runs of non-separators, commas and the slash.
fn line_tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> + '_ {
    let mut rest = line;
    std::iter::from_fn(move || {
        let start = rest.iter().position(|b| !b.is_ascii_whitespace())?;
        rest = rest.get(start..).unwrap_or(&[]);
        let len = match rest.first() {
            Some(b',' | b'/') => 1,
            _ => rest
                .iter()
                .position(|&b| b.is_ascii_whitespace() || b == b',' || b == b'/')
                .unwrap_or(rest.len()),
        };
        let (tok, tail) = rest.split_at(len.min(rest.len()));
        rest = tail;
        Some(tok)
    })
}

/// Reads `r*c` or `r*`: the repeat count and the value (`None` for `r*`). A token without
/// `*` is one value.
fn repeat_item(line: usize, token: &[u8]) -> Result<Item<'_>, FormatError> {
    let Some(star) = token.iter().position(|&b| b == b'*') else {
        return Ok(Item {
            line,
            token,
            value: Some(token),
            repeat: 1,
        });
    };
    let (count, value) = (&token[..star], &token[star + 1..]);
    let repeat = std::str::from_utf8(count)
        .ok()
        .filter(|s| s.bytes().all(|b| b.is_ascii_digit()))
        .and_then(|s| s.parse::<u64>().ok())
        .filter(|&r| r >= 1);
    let Some(repeat) = repeat else {
        return Err(FormatError::expected_at_line(
            line,
            "a repeat count r*c with r a positive integer",
            token,
        ));
    };
    let value = (!value.is_empty()).then_some(value);
    Ok(Item {
        line,
        token,
        value,
        repeat,
    })
}

impl<'a> Values<'a> {
    /// Tokenizes a whole file. Errors: a malformed repeat count, or more than [`MAX_VALUES`]
    /// values; both name the line and the token.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, FormatError> {
        let mut v = Values::default();
        // A comma right after the start of the stream or after another comma (blanks and line
        // ends between them are separators) gives a null value.
        let mut after_comma = true;
        for (l, line) in bytes.split(|&b| b == b'\n').enumerate() {
            let line_no = l + 1;
            for token in line_tokens(line) {
                match token {
                    b"/" => {
                        after_comma = true;
                        break;
                    }
                    b"," => {
                        if after_comma {
                            v.push(Item {
                                line: line_no,
                                token,
                                value: None,
                                repeat: 1,
                            })?;
                        }
                        after_comma = true;
                    }
                    _ => {
                        v.push(repeat_item(line_no, token)?)?;
                        after_comma = false;
                    }
                }
            }
        }
        Ok(v)
    }

    fn push(&mut self, item: Item<'a>) -> Result<(), FormatError> {
        let end = self.len().saturating_add(item.repeat);
        if end > MAX_VALUES {
            return Err(FormatError::new(
                Location::Line(item.line),
                FormatErrorKind::TooLarge {
                    what: format!(
                        "the number of values (after {:?}; at most {MAX_VALUES})",
                        String::from_utf8_lossy(item.token)
                    ),
                    value: end,
                },
            ));
        }
        self.items.push(item);
        self.ends.push(end);
        Ok(())
    }

    /// The number of values, repeat counts expanded.
    pub fn len(&self) -> u64 {
        self.ends.last().copied().unwrap_or(0)
    }

    /// True when the file holds no value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The item that value `i` (0-based, repeat counts expanded) comes from.
    pub fn get(&self, i: u64) -> Option<&Item<'a>> {
        let k = self.ends.partition_point(|&e| e <= i);
        self.items.get(k)
    }

    /// The line of the last token (1 for an empty file).
    pub fn last_line(&self) -> usize {
        self.items.last().map_or(1, |t| t.line)
    }

    /// Iterates over the values from value `i` on, one item per value.
    pub fn from(&self, i: u64) -> impl Iterator<Item = &Item<'a>> + '_ {
        let k = self.ends.partition_point(|&e| e <= i);
        let before = k
            .checked_sub(1)
            .and_then(|p| self.ends.get(p))
            .copied()
            .unwrap_or(0);
        let skip = i.saturating_sub(before);
        let mut first = true;
        self.items
            .get(k..)
            .unwrap_or(&[])
            .iter()
            .flat_map(move |it| {
                let n = if first {
                    it.repeat - skip.min(it.repeat)
                } else {
                    it.repeat
                };
                first = false;
                std::iter::repeat_n(it, n as usize)
            })
    }
}

/// A Fortran real: `1.5`, `1.5e3`, `1.5D+03` (double precision), `1.5+003` (exponent without
/// its letter, as some compilers write three-digit exponents), `.5`, `5.`, `-0.E+0`.
pub fn parse_real(text: &[u8]) -> Option<f64> {
    let s = std::str::from_utf8(text).ok()?;
    if let Ok(v) = s.parse::<f64>() {
        return Some(v);
    }
    let fixed: String = s
        .chars()
        .map(|c| {
            if matches!(c, 'd' | 'D' | 'q' | 'Q') {
                'e'
            } else {
                c
            }
        })
        .collect();
    if let Ok(v) = fixed.parse::<f64>() {
        return Some(v);
    }
    // `1.5-3`: a sign after the mantissa starts the exponent.
    let b = fixed.as_bytes();
    let at = (1..b.len()).find(|&k| {
        matches!(b.get(k), Some(b'+' | b'-'))
            && b.get(k - 1)
                .is_some_and(|c| c.is_ascii_digit() || *c == b'.')
    })?;
    let (mantissa, exponent) = fixed.split_at(at);
    if mantissa.contains(['e', 'E']) {
        return None;
    }
    format!("{mantissa}e{exponent}").parse::<f64>().ok()
}

/// A Fortran integer: optional sign, digits.
pub fn parse_int(text: &[u8]) -> Option<i64> {
    std::str::from_utf8(text).ok()?.parse::<i64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn expand(text: &str) -> Vec<Option<String>> {
        let v = Values::parse(text.as_bytes()).unwrap();
        v.from(0)
            .map(|it| it.value.map(|s| String::from_utf8_lossy(s).into_owned()))
            .collect()
    }

    fn some(v: &[&str]) -> Vec<Option<String>> {
        v.iter().map(|s| Some(s.to_string())).collect()
    }

    #[test]
    fn separators_repeats_and_slash() {
        assert_eq!(
            expand(" 2,  25,65 ,2\n 2*-4.,\n 1.5 /ignored 7 8\n9"),
            some(&["2", "25", "65", "2", "-4.", "-4.", "1.5", "9"])
        );
    }

    #[test]
    fn nulls_from_commas_and_bare_repeats() {
        assert_eq!(
            expand("1,,2, ,3,\n,4 2* 5"),
            vec![
                Some("1".into()),
                None,
                Some("2".into()),
                None,
                Some("3".into()),
                None,
                Some("4".into()),
                None,
                None,
                Some("5".into()),
            ]
        );
        // A comma at the very start is a null; a comma ending a line is one separator.
        assert_eq!(expand(",1"), vec![None, Some("1".into())]);
        assert_eq!(expand("1,\n2"), some(&["1", "2"]));
    }

    #[test]
    fn random_access_matches_expansion() {
        let text = "3*1 2 4*3,5\n2*7";
        let v = Values::parse(text.as_bytes()).unwrap();
        let all: Vec<_> = v.from(0).map(|it| it.value).collect();
        assert_eq!(v.len(), all.len() as u64);
        for i in 0..v.len() {
            assert_eq!(v.get(i).map(|it| it.value), all.get(i as usize).copied());
            let tail: Vec<_> = v.from(i).map(|it| it.value).collect();
            assert_eq!(&tail[..], &all[i as usize..]);
        }
        assert!(v.get(v.len()).is_none());
    }

    #[test]
    fn bad_repeat_counts_name_line_and_token() {
        for bad in ["1\n0*5", "1\nx*5", "1\n-2*5", "1\n*5"] {
            let e = Values::parse(bad.as_bytes()).unwrap_err();
            assert_eq!(e.location, Location::Line(2), "{bad}");
            assert!(e.to_string().contains("repeat count"), "{e}");
        }
        let e = Values::parse(b"1 999999999999*0").unwrap_err();
        assert!(matches!(e.kind, FormatErrorKind::TooLarge { .. }), "{e}");
    }

    #[test]
    fn fortran_reals() {
        for (s, v) in [
            ("1.5", 1.5),
            ("-4.", -4.0),
            (".5", 0.5),
            ("0.E+0", 0.0),
            ("1.0D+00", 1.0),
            ("2.5d-3", 2.5e-3),
            ("1.5-3", 1.5e-3),
            ("-8.33333700000000038E-2", -8.333_337e-2),
            ("1.25+003", 1250.0),
        ] {
            assert_eq!(parse_real(s.as_bytes()), Some(v), "{s}");
        }
        for s in ["", "1.5e3-2", "abc", "-", "1..2"] {
            assert_eq!(parse_real(s.as_bytes()), None, "{s}");
        }
    }

    /// Random edits in list-directed text (repeat counts, commas, slashes, nulls) never make
    /// the Plot3D reader panic, and what it accepts has the values it says.
    #[test]
    fn random_list_directed_text_never_panics() {
        let base = b"2 / blocks\n 3,2, 2\n 2\n0.0, 0.5,1.0D0 0.0 0.5\n1.0 3*0.0, 3*1.5d0\n 6*1\n -1.,1.5-1\n 2*2.0 1.0\n 3.,4., 5.5\n  2*0 , -2 1\n";
        let alphabet = b"0123456789*,/ .-+eEdD\n";
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..3000 {
            let mut b = base.to_vec();
            for _ in 0..1 + next() % 4 {
                let i = (next() % b.len() as u64) as usize;
                let c = alphabet[(next() % alphabet.len() as u64) as usize];
                match next() % 3 {
                    0 => b[i] = c,
                    1 => b.insert(i, c),
                    _ => {
                        b.remove(i);
                    }
                }
            }
            let opts = super::super::plot3d::Plot3dOptions::default();
            if let Ok((g, _)) = super::super::plot3d::parse_plot3d(&b, &opts) {
                let n: usize = g.blocks.iter().map(|blk| blk.points.len()).sum();
                assert!(n > 0);
            }
        }
    }
}
