//! Motion files for `deform move --motions FILE`: a different rigid motion per marker in one
//! run. One line per marker, blank lines and `%` or `#` comments ignored:
//!
//! ```text
//! # marker  motion
//! airfoil   rotate -10 center 0.25,0
//! flap      rotate 20 center 0.8,0 axis 0,0,1
//! slat      translate -0.01,0.02
//! ```
//!
//! `rotate DEG` turns counter-clockwise about `axis` (default z; a 2D mesh only rotates about
//! z) through `center` (default: the centroid of the marker's nodes); `translate DX,DY[,DZ]`
//! shifts. Each marker appears once.

use super::error::{FormatError, FormatErrorKind, Location};

pub use crate::motion::Motion;

/// A line of a motion file.
#[derive(Clone, Debug, PartialEq)]
pub struct MarkerMotionSpec {
    /// Marker name.
    pub marker: String,
    /// Its motion (rigid: a rotation or a translation).
    pub motion: Motion,
    /// The 1-based line it came from (for messages).
    pub line: usize,
}

fn numbers(tok: &[u8], line: usize, what: &str) -> Result<Vec<f64>, FormatError> {
    let text = std::str::from_utf8(tok).unwrap_or("");
    let v: Option<Vec<f64>> = text
        .split(',')
        .map(|s| s.trim().parse::<f64>().ok())
        .collect();
    match v {
        Some(v) if v.iter().all(|x| x.is_finite()) => Ok(v),
        Some(_) => Err(FormatError::new(
            Location::Line(line),
            FormatErrorKind::NotFinite {
                what: what.to_string(),
                found: super::error::show(tok),
            },
        )),
        None => Err(FormatError::expected_at_line(
            line,
            format!("{what} (comma-separated numbers)"),
            tok,
        )),
    }
}

/// Parses a motion file for a mesh of dimension `dim` (2 or 3).
pub fn parse_motions(bytes: &[u8], dim: usize) -> Result<Vec<MarkerMotionSpec>, FormatError> {
    let mut out: Vec<MarkerMotionSpec> = Vec::new();
    for (l, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line = l + 1;
        let cut = raw
            .iter()
            .position(|&b| b == b'%' || b == b'#')
            .unwrap_or(raw.len());
        let content = raw.get(..cut).unwrap_or(&[]).trim_ascii();
        if content.is_empty() {
            continue;
        }
        let toks: Vec<&[u8]> = content
            .split(|b| b.is_ascii_whitespace())
            .filter(|t| !t.is_empty())
            .collect();
        let (Some(name), Some(kind), Some(value)) = (toks.first(), toks.get(1), toks.get(2)) else {
            return Err(FormatError::expected_at_line(
                line,
                "`MARKER rotate DEG [center X,Y[,Z]] [axis X,Y,Z]` or `MARKER translate DX,DY[,DZ]`",
                content,
            ));
        };
        let marker = String::from_utf8_lossy(name).into_owned();
        if out.iter().any(|m| m.marker == marker) {
            return Err(FormatError::expected_at_line(
                line,
                "each marker once",
                name,
            ));
        }
        let at = At { line, dim };
        let motion = match *kind {
            b"rotate" => at.rotate(value, toks.get(3..).unwrap_or(&[]), content)?,
            b"translate" => {
                if toks.len() > 3 {
                    return Err(FormatError::expected_at_line(
                        line,
                        "nothing after the translation",
                        toks[3],
                    ));
                }
                Motion::Translate(at.vector(value, "translation", at.point_lens())?)
            }
            _ => {
                return Err(FormatError::expected_at_line(
                    line,
                    "`rotate` or `translate`",
                    kind,
                ));
            }
        };
        out.push(MarkerMotionSpec {
            marker,
            motion,
            line,
        });
    }
    if out.is_empty() {
        return Err(FormatError::expected_at_line(
            1,
            "at least one `MARKER rotate|translate …` line",
            b"",
        ));
    }
    Ok(out)
}

/// Where a motion line is (for errors) and the mesh's dimension.
struct At {
    line: usize,
    dim: usize,
}

impl At {
    /// How many numbers a point or translation has.
    fn point_lens(&self) -> &'static [usize] {
        if self.dim == 2 {
            &[2]
        } else {
            &[3]
        }
    }

    /// A comma-separated vector of one of the lengths `lens` (missing components 0).
    fn vector(&self, tok: &[u8], what: &str, lens: &[usize]) -> Result<[f64; 3], FormatError> {
        let v = numbers(tok, self.line, what)?;
        if !lens.contains(&v.len()) {
            let n = if lens == [3] || self.dim != 2 {
                "3"
            } else {
                "2"
            };
            return Err(FormatError::expected_at_line(
                self.line,
                format!("{what} with {n} numbers"),
                tok,
            ));
        }
        Ok([
            v.first().copied().unwrap_or(0.0),
            v.get(1).copied().unwrap_or(0.0),
            v.get(2).copied().unwrap_or(0.0),
        ])
    }

    /// `rotate DEG [center X,Y[,Z]] [axis X,Y,Z]` (`rest`: the tokens after the angle).
    fn rotate(&self, value: &[u8], rest: &[&[u8]], content: &[u8]) -> Result<Motion, FormatError> {
        let line = self.line;
        let degrees = numbers(value, line, "an angle in degrees")?;
        let [degrees] = degrees[..] else {
            return Err(FormatError::expected_at_line(
                line,
                "one angle in degrees",
                value,
            ));
        };
        let (mut axis, mut center) = ([0.0, 0.0, 1.0], None);
        let mut rest = rest.iter();
        while let Some(key) = rest.next() {
            let Some(v) = rest.next() else {
                return Err(FormatError::expected_at_line(line, "a value after it", key));
            };
            match *key {
                b"center" => center = Some(self.vector(v, "center", self.point_lens())?),
                b"axis" => axis = self.vector(v, "axis", &[3])?,
                _ => {
                    return Err(FormatError::expected_at_line(
                        line,
                        "`center X,Y[,Z]` or `axis X,Y,Z`",
                        key,
                    ))
                }
            }
        }
        if axis == [0.0; 3] {
            return Err(FormatError::expected_at_line(
                line,
                "a non-zero axis",
                content,
            ));
        }
        if self.dim == 2 && (axis[0] != 0.0 || axis[1] != 0.0) {
            return Err(FormatError::expected_at_line(
                line,
                "the z axis (a 2D mesh rotates in its plane)",
                content,
            ));
        }
        Ok(Motion::Rotate {
            degrees,
            axis,
            center,
        })
    }
}
