//! The FFD boxes SU2 stores in a mesh file (the `FFD_*` sections that `parse_su2` keeps in
//! `passthrough`): each box's tag, level, degrees, corner points, control points (`i j k x y
//! z`) and the surface points inside it with their parametric coordinates (`marker node u v
//! w`), as `SU2_DEF` writes them with `DV_KIND= FFD_SETTING`.
//!
//! In 2D SU2 keeps a box three-dimensional: degree 1 in k, control points at z = ±0.5, and the
//! surface points at w = 0.5.

use super::error::{FormatError, FormatErrorKind, Location};

/// One FFD box.
#[derive(Clone, Debug, PartialEq)]
pub struct FfdBox {
    /// `FFD_TAG`.
    pub tag: String,
    /// `FFD_LEVEL` (0 for a box with no parent).
    pub level: usize,
    /// `FFD_DEGREE_I`, `_J`, `_K` (`K` is 1 when the file has none: 2D).
    pub degree: [usize; 3],
    /// `FFD_CORNER_POINTS` (4 in 2D, 8 in 3D).
    pub corners: Vec<[f64; 3]>,
    /// `FFD_CONTROL_POINTS`: `(i, j, k)` and the point, `(degree + 1)` per direction once each.
    pub control: Vec<([usize; 3], [f64; 3])>,
    /// `FFD_SURFACE_POINTS`: marker, node and parametric `(u, v, w)`.
    pub surface: Vec<FfdSurfacePoint>,
}

/// A surface node inside a box, with its parametric coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct FfdSurfacePoint {
    /// The marker it belongs to.
    pub marker: String,
    /// Its 0-based node index in the mesh.
    pub node: u32,
    /// Its parametric coordinates in the box.
    pub uvw: [f64; 3],
}

impl FfdBox {
    /// The control point `(i, j, k)`, if the file lists it.
    pub fn control_point(&self, ijk: [usize; 3]) -> Option<[f64; 3]> {
        self.control
            .iter()
            .find(|(c, _)| *c == ijk)
            .map(|(_, p)| *p)
    }
}

/// Line-by-line reader over the passthrough text (`line0`: the file line of its first line).
struct Reader<'t> {
    lines: std::iter::Peekable<std::iter::Enumerate<std::str::Lines<'t>>>,
    line0: usize,
}

impl<'t> Reader<'t> {
    /// The next non-blank line (comments removed) and its file line number.
    fn next(&mut self) -> Option<(usize, &'t str)> {
        for (k, l) in self.lines.by_ref() {
            let l = l.split('%').next().unwrap_or("").trim();
            if !l.is_empty() {
                return Some((self.line0 + k, l));
            }
        }
        None
    }

    /// `KEY= value` where KEY is `key`: its value.
    fn keyed(&mut self, key: &str) -> Result<(usize, &'t str), FormatError> {
        let (line, l) = self.next().ok_or_else(|| eof(key))?;
        match l.split_once('=') {
            Some((k, v)) if k.trim().eq_ignore_ascii_case(key) => Ok((line, v.trim())),
            _ => Err(FormatError::expected_at_line(
                line,
                format!("{key}="),
                l.as_bytes(),
            )),
        }
    }

    /// Whether the next line is `key=` (without consuming it).
    fn at(&mut self, key: &str) -> bool {
        while let Some((_, l)) = self.lines.peek() {
            let l = l.split('%').next().unwrap_or("").trim();
            if !l.is_empty() {
                return l
                    .split_once('=')
                    .is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case(key));
            }
            self.lines.next();
        }
        false
    }

    /// `KEY= n`.
    fn count(&mut self, key: &str) -> Result<usize, FormatError> {
        let (line, v) = self.keyed(key)?;
        v.parse().map_err(|_| {
            FormatError::expected_at_line(line, format!("a count after {key}="), v.as_bytes())
        })
    }

    /// A line of `n` numbers parsed by `parse` (what names it in errors).
    fn numbers<T: std::str::FromStr>(
        &mut self,
        n: usize,
        what: &str,
    ) -> Result<Vec<T>, FormatError> {
        let (line, l) = self.next().ok_or_else(|| eof(what))?;
        let v: Option<Vec<T>> = l.split_whitespace().map(|t| t.parse().ok()).collect();
        match v {
            Some(v) if v.len() == n => Ok(v),
            _ => Err(FormatError::expected_at_line(
                line,
                format!("{what}: {n} numbers"),
                l.as_bytes(),
            )),
        }
    }
}

fn eof(what: &str) -> FormatError {
    FormatError::new(
        Location::File,
        FormatErrorKind::UnexpectedEof {
            expected: what.to_string(),
        },
    )
}

/// The FFD boxes in an SU2 file's passthrough text (`first_line`: the file line where it
/// starts; none when it has no `FFD_NBOX`).
pub fn parse_ffd_boxes(passthrough: &[u8], first_line: usize) -> Result<Vec<FfdBox>, FormatError> {
    let text = String::from_utf8_lossy(passthrough);
    let start = text.lines().position(|l| {
        l.split_once('=')
            .is_some_and(|(k, _)| k.trim().eq_ignore_ascii_case("FFD_NBOX"))
    });
    let Some(start) = start else {
        return Ok(Vec::new());
    };
    let rest = text.lines().skip(start).collect::<Vec<_>>().join("\n");
    let mut r = Reader {
        lines: rest.lines().enumerate().peekable(),
        line0: first_line + start,
    };
    let n = r.count("FFD_NBOX")?;
    r.count("FFD_NLEVEL")?;
    (0..n).map(|_| one_box(&mut r)).collect()
}

/// One box, from its `FFD_TAG=` line.
fn one_box(r: &mut Reader<'_>) -> Result<FfdBox, FormatError> {
    let tag = r.keyed("FFD_TAG")?.1.to_string();
    let level = r.count("FFD_LEVEL")?;
    let mut degree = [r.count("FFD_DEGREE_I")?, r.count("FFD_DEGREE_J")?, 1];
    if r.at("FFD_DEGREE_K") {
        degree[2] = r.count("FFD_DEGREE_K")?;
    }
    if r.at("FFD_BLENDING") {
        let (line, v) = r.keyed("FFD_BLENDING")?;
        if !v.eq_ignore_ascii_case("BEZIER") {
            return Err(FormatError::new(
                Location::Line(line),
                FormatErrorKind::Unsupported {
                    what: format!("FFD_BLENDING= {v} (Bezier boxes only)"),
                },
            ));
        }
    }
    for key in ["FFD_PARENTS", "FFD_CHILDREN"] {
        let n = r.count(key)?;
        for _ in 0..n {
            r.next().ok_or_else(|| eof(key))?;
        }
    }
    let nc = r.count("FFD_CORNER_POINTS")?;
    let dim = if nc == 4 { 2 } else { 3 };
    let corners = (0..nc)
        .map(|_| r.numbers::<f64>(dim, "a corner point").map(|v| lift(&v)))
        .collect::<Result<Vec<_>, _>>()?;
    let np = r.count("FFD_CONTROL_POINTS")?;
    let mut control = Vec::with_capacity(np);
    for _ in 0..np {
        let (line, l) = r.next().ok_or_else(|| eof("a control point"))?;
        let t: Vec<&str> = l.split_whitespace().collect();
        let parsed = (t.len() == 6)
            .then(|| {
                let ijk: Option<Vec<usize>> = t[..3].iter().map(|s| s.parse().ok()).collect();
                let xyz: Option<Vec<f64>> = t[3..].iter().map(|s| s.parse().ok()).collect();
                Some((ijk?, xyz?))
            })
            .flatten();
        let Some((ijk, xyz)) = parsed else {
            return Err(FormatError::expected_at_line(
                line,
                "a control point: i j k x y z",
                l.as_bytes(),
            ));
        };
        control.push(([ijk[0], ijk[1], ijk[2]], lift(&xyz)));
    }
    let ns = r.count("FFD_SURFACE_POINTS")?;
    let mut surface = Vec::with_capacity(ns);
    for _ in 0..ns {
        let (line, l) = r.next().ok_or_else(|| eof("a surface point"))?;
        let t: Vec<&str> = l.split_whitespace().collect();
        let node = t.get(1).and_then(|s| s.parse::<u32>().ok());
        let uvw: Option<Vec<f64>> = t
            .get(2..)
            .and_then(|s| s.iter().map(|x| x.parse().ok()).collect());
        match (t.len(), node, uvw) {
            (5, Some(node), Some(uvw)) => surface.push(FfdSurfacePoint {
                marker: t[0].to_string(),
                node,
                uvw: lift(&uvw),
            }),
            _ => {
                return Err(FormatError::expected_at_line(
                    line,
                    "a surface point: marker node u v w",
                    l.as_bytes(),
                ))
            }
        }
    }
    Ok(FfdBox {
        tag,
        level,
        degree,
        corners,
        control,
        surface,
    })
}

/// Up to three numbers as a point (missing coordinates 0).
fn lift(v: &[f64]) -> [f64; 3] {
    [0, 1, 2].map(|k| v.get(k).copied().unwrap_or(0.0))
}
