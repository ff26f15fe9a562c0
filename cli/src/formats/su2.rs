//! SU2 native ASCII meshes (2D and 3D, all element kinds, markers), read and write.
//!
//! Layout: `NDIME=`, then `NELEM=` with its element lines and `NPOIN=` with its point lines in
//! either order, then `NMARK=` with `MARKER_TAG=` / `MARKER_ELEMS=` blocks. Indices are
//! 0-based; trailing columns on point and element lines (SU2 writes a running index there) are
//! ignored; `%` starts a comment. Element lines are `code n0 n1 …` with VTK type codes.
//! `MARKERTAG=` is read as `MARKER_TAG=` (SU2 reads both). The sections SU2 reads that the
//! tool does not use — `NPERIODIC=` with its `PERIODIC_INDEX=` blocks and the `FFD_*`
//! free-form deformation boxes — are kept byte for byte ([`Su2Mesh::passthrough`]) and written
//! back unchanged; any other keyword is an error naming its line.

use std::io::{self, Write};

use deform_kernel::CellKind;

use super::error::{show, FormatError, FormatErrorKind, Location};
use super::line::{too_long, Line};
use super::CellList;

/// A boundary marker: its tag and its boundary elements (lines in 2D, triangles/quads in 3D).
#[derive(Clone, Debug, PartialEq)]
pub struct Su2Marker {
    /// `MARKER_TAG`.
    pub name: String,
    /// Boundary elements.
    pub elements: CellList,
}

/// An SU2 mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Su2Mesh {
    /// `NDIME`: 2 or 3.
    pub dim: usize,
    /// Point coordinates; `z` is 0 in 2D.
    pub points: Vec<[f64; 3]>,
    /// Volume elements (triangles/quads in 2D; tets, hexes, prisms, pyramids in 3D).
    pub elements: CellList,
    /// Boundary markers, in file order.
    pub markers: Vec<Su2Marker>,
    /// Sections SU2 reads that this tool does not use (`NPERIODIC=` / `PERIODIC_INDEX=`
    /// blocks, `FFD_*` free-form deformation boxes), byte for byte as they were in the file,
    /// comments and line endings included; [`write_su2`] writes them back after the markers.
    pub passthrough: Vec<u8>,
    /// The input's comment lines and line ends, written back by [`write_su2`].
    pub text: Su2Text,
}

/// The first line [`write_su2`] writes when the mesh has no comments of its own.
const BANNER: &[u8] = b"% SU2 mesh written by deform\n";

/// What an SU2 file says besides the mesh: its comment-only lines (`%…`), each kept before
/// the section keyword it preceded, and its line ends, so that a mesh read and written again
/// keeps them. Comments after data on the same line are not kept.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Su2Text {
    /// Comment lines (each ending in `\n`) before a section, keyed by the section: `NDIME`,
    /// `NELEM`, `NPOIN`, `NMARK`, `MARKER_TAG=name`, `passthrough` (before the first
    /// passed-through section), `end` (after the last line of the mesh).
    pub comments: Vec<(String, Vec<u8>)>,
    /// Lines end in `\r\n` (as the input's first line did).
    pub crlf: bool,
}

impl Su2Text {
    /// Keeps `lines` (possibly empty) as the comments before `key`.
    fn note(&mut self, key: &str, mut lines: Vec<u8>) {
        // The writer's own mark is not the user's comment: reading it back and writing
        // again gives the same file either way, and the mesh compares equal.
        if let Some(rest) = lines.strip_prefix(BANNER) {
            lines = rest.to_vec();
        }
        if !lines.is_empty() {
            self.comments.push((key.to_string(), lines));
        }
    }

    /// The comment lines kept before `key` (empty when none).
    fn before(&self, key: &str) -> &[u8] {
        self.comments
            .iter()
            .find(|(k, _)| k == key)
            .map_or(&[][..], |(_, c)| c.as_slice())
    }
}

impl Su2Mesh {
    /// The marker called `name`, if any.
    pub fn marker(&self, name: &str) -> Option<&Su2Marker> {
        self.markers.iter().find(|m| m.name == name)
    }
}

/// Reads lines, skipping blank and comment-only lines; strips `%` comments and `\r`.
pub(super) struct Lines<'a> {
    data: &'a [u8],
    pub(super) pos: usize,
    pub(super) line: usize,
    /// Byte offset where the line last returned by `next_content` starts.
    pub(super) start: usize,
    /// Comment-only lines read since the last [`Lines::take_comments`] (each ending in `\n`).
    comments: Vec<u8>,
    /// Whether the first line ended in `\r\n` (`None` before the first line end).
    pub(super) crlf: Option<bool>,
}

impl<'a> Lines<'a> {
    pub(super) fn new(data: &'a [u8]) -> Self {
        Lines {
            data,
            pos: 0,
            line: 0,
            start: 0,
            comments: Vec::new(),
            crlf: None,
        }
    }

    /// The comment-only lines read since the last call.
    pub(super) fn take_comments(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.comments)
    }

    /// Next non-empty line: (1-based number, trimmed content without comment).
    pub(super) fn next_content(&mut self) -> Option<(usize, &'a [u8])> {
        while self.pos < self.data.len() {
            let rest = self.data.get(self.pos..).unwrap_or(&[]);
            // One scan finds the line's end or its comment, whichever comes first (a line
            // without a comment, every element and point line, is read once).
            let stop = memchr::memchr2(b'\n', b'%', rest).unwrap_or(rest.len());
            let len = match rest.get(stop) {
                Some(b'%') => {
                    let tail = rest.get(stop..).unwrap_or(&[]);
                    stop + memchr::memchr(b'\n', tail).unwrap_or(tail.len())
                }
                _ => stop,
            };
            let raw = rest.get(..len).unwrap_or(&[]);
            if self.crlf.is_none() && len < rest.len() {
                self.crlf = Some(raw.ends_with(b"\r"));
            }
            self.start = self.pos;
            self.pos += len + 1;
            self.line += 1;
            let (data, comment) = (
                raw.get(..stop.min(len)).unwrap_or(&[]),
                raw.get(stop.min(len)..).unwrap_or(&[]),
            );
            let t = data.trim_ascii();
            if !t.is_empty() {
                return Some((self.line, t));
            }
            if !comment.is_empty() {
                self.comments.extend_from_slice(comment.trim_ascii_end());
                self.comments.push(b'\n');
            }
        }
        None
    }

    /// The line number reported for an unexpected end of file: the line after the last one.
    fn eof_line(&self) -> usize {
        self.line + 1
    }
}

/// Keywords that start a section of the mesh proper.
fn is_mesh_keyword(key: &[u8]) -> bool {
    [
        b"NDIME".as_slice(),
        b"NELEM",
        b"NPOIN",
        b"NMARK",
        b"NZONE",
        b"IZONE",
    ]
    .iter()
    .any(|k| key.eq_ignore_ascii_case(k))
}

/// Keywords of sections SU2 reads and this tool passes through unchanged.
fn is_passthrough_keyword(key: &[u8]) -> bool {
    let upper = key.to_ascii_uppercase();
    upper == b"NPERIODIC" || upper == b"PERIODIC_INDEX" || upper.starts_with(b"FFD_")
}

pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
}

/// Splits `KEY= value` into (key, value) if the line has that shape.
pub(crate) fn key_value(line: &[u8]) -> Option<(&[u8], &[u8])> {
    let eq = memchr::memchr(b'=', line)?;
    let key = line.get(..eq)?.trim_ascii();
    let value = line.get(eq + 1..)?.trim_ascii();
    if key.is_empty() || !key.iter().all(|b| b.is_ascii_alphanumeric() || *b == b'_') {
        return None;
    }
    Some((key, value))
}

/// A non-negative integer of 1 to 19 ASCII digits (always fits a `u64`).
fn parse_uint(tok: &[u8]) -> Option<u64> {
    if tok.is_empty() || tok.len() > 19 {
        return None;
    }
    tok.iter().try_fold(0u64, |v, &b| {
        b.is_ascii_digit().then(|| v * 10 + u64::from(b - b'0'))
    })
}

pub(super) fn parse_count(line: usize, value: &[u8], keyword: &str) -> Result<usize, FormatError> {
    let first = tokens(value).next().unwrap_or(&[]);
    let n = parse_uint(first).ok_or_else(|| {
        FormatError::expected_at_line(line, format!("a count after {keyword}="), value)
    })?;
    usize::try_from(n)
        .ok()
        .filter(|&n| u32::try_from(n).is_ok())
        .ok_or_else(|| {
            FormatError::new(
                Location::Line(line),
                FormatErrorKind::TooLarge {
                    what: keyword.to_string(),
                    value: n,
                },
            )
        })
}

/// A finite number; `what()` names it, called only for an error.
fn parse_real(line: usize, tok: &[u8], what: impl Fn() -> String) -> Result<f64, FormatError> {
    let v: f64 = std::str::from_utf8(tok)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or_else(|| {
            FormatError::expected_at_line(line, format!("{} (a number)", what()), tok)
        })?;
    if !v.is_finite() {
        return Err(FormatError::new(
            Location::Line(line),
            FormatErrorKind::NotFinite {
                what: what(),
                found: show(tok),
            },
        ));
    }
    Ok(v)
}

/// Reads the next run of ASCII digits in `bytes` from `*at` (whitespace before it skipped):
/// its value when it has 1 to 9 digits (below 10⁹, so it fits a `u32`) and ends at
/// whitespace or the line's end; `None` for anything else.
#[inline]
fn next_small_uint(bytes: &[u8], at: &mut usize) -> Option<u32> {
    while bytes.get(*at).is_some_and(u8::is_ascii_whitespace) {
        *at += 1;
    }
    let start = *at;
    let mut v = 0u32;
    while let Some(&b) = bytes.get(*at).filter(|b| b.is_ascii_digit()) {
        if *at - start == 9 {
            return None; // a tenth digit
        }
        v = v * 10 + u32::from(b - b'0');
        *at += 1;
    }
    let ends = bytes.get(*at).is_none_or(u8::is_ascii_whitespace);
    (*at > start && ends).then_some(v)
}

/// The common element line in one pass: a type code of `allowed`, its node indices (plain
/// digits, fewer than ten each) and distinct nodes; whatever follows them is ignored, as
/// [`parse_element`] ignores it. `false` (nothing pushed) for any other line, which
/// [`parse_element`] then reads token by token, with its messages.
fn push_plain_element(content: &[u8], allowed: &[CellKind], cells: &mut CellList) -> bool {
    let mut at = 0usize;
    let Some(kind) = next_small_uint(content, &mut at)
        .and_then(|c| u8::try_from(c).ok())
        .and_then(CellKind::from_vtk)
        .filter(|k| allowed.contains(k))
    else {
        return false;
    };
    let mut nodes = [0u32; 8];
    let Some(cell) = nodes.get_mut(..kind.node_count()) else {
        return false;
    };
    for slot in cell.iter_mut() {
        let Some(v) = next_small_uint(content, &mut at) else {
            return false;
        };
        *slot = v;
    }
    let distinct = (1..cell.len()).all(|k| cell.iter().take(k).all(|&u| Some(&u) != cell.get(k)));
    distinct && cells.push(kind, cell)
}

/// Parses one element line into `cells`; `allowed` lists the codes valid here.
pub(crate) fn parse_element(
    line: usize,
    content: &[u8],
    allowed: &[CellKind],
    cells: &mut CellList,
) -> Result<(), FormatError> {
    if push_plain_element(content, allowed, cells) {
        return Ok(());
    }
    parse_element_tokens(line, content, allowed, cells)
}

/// [`parse_element`] token by token: any element line, with the messages for bad ones.
fn parse_element_tokens(
    line: usize,
    content: &[u8],
    allowed: &[CellKind],
    cells: &mut CellList,
) -> Result<(), FormatError> {
    let allowed_text = || {
        allowed
            .iter()
            .map(|k| k.vtk_code().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut it = tokens(content);
    let code_tok = it.next().unwrap_or(&[]);
    let code = (parse_uint(code_tok).and_then(|c| i64::try_from(c).ok()))
        .or_else(|| std::str::from_utf8(code_tok).ok()?.parse::<i64>().ok())
        .ok_or_else(|| {
            FormatError::expected_at_line(
                line,
                format!("an element line (type code {})", allowed_text()),
                content,
            )
        })?;
    let kind = u8::try_from(code)
        .ok()
        .and_then(CellKind::from_vtk)
        .filter(|k| allowed.contains(k))
        .ok_or_else(|| {
            FormatError::new(
                Location::Line(line),
                FormatErrorKind::BadElement {
                    code,
                    allowed: allowed_text(),
                },
            )
        })?;
    let mut nodes = [0u32; 8];
    let count = kind.node_count();
    for (k, slot) in nodes.iter_mut().take(count).enumerate() {
        let tok = it.next().ok_or_else(|| {
            FormatError::expected_at_line(
                line,
                format!("{count} node indices for element type {code}, found only {k}"),
                content,
            )
        })?;
        let v = parse_uint(tok).ok_or_else(|| {
            FormatError::expected_at_line(line, "a node index (non-negative integer)", tok)
        })?;
        *slot = u32::try_from(v).map_err(|_| {
            FormatError::new(
                Location::Line(line),
                FormatErrorKind::IndexOutOfRange {
                    index: v,
                    bound: u32::MAX as usize,
                },
            )
        })?;
    }
    let cell = nodes.get(..count).unwrap_or(&[]);
    for (k, &v) in cell.iter().enumerate() {
        if cell.iter().take(k).any(|&u| u == v) {
            return Err(FormatError::new(
                Location::Line(line),
                FormatErrorKind::RepeatedNode { node: v as u64 },
            ));
        }
    }
    if !cells.push(kind, cell) {
        return Err(FormatError::new(
            Location::Line(line),
            FormatErrorKind::TooLarge {
                what: "total element node count".into(),
                value: cells.nodes.len() as u64,
            },
        ));
    }
    Ok(())
}

/// One point line `c` (at line `l`): point `p` of `n` (`NPOIN=` at line `key`), `d`
/// coordinates (`z` is 0 in 2D); trailing columns ignored.
pub(crate) fn parse_point(
    d: usize,
    (l, c): (usize, &[u8]),
    (p, n, key): (usize, usize, usize),
) -> Result<[f64; 3], FormatError> {
    let mut it = tokens(c);
    let mut xyz = [0.0f64; 3];
    for (k, slot) in xyz.iter_mut().take(d).enumerate() {
        let name = ["x", "y", "z"].get(k).copied().unwrap_or("coordinate");
        let tok = it.next().ok_or_else(|| {
            FormatError::expected_at_line(
                l,
                format!(
                    "{d} coordinates for point {} of {n} (NPOIN= {n} at line {key})",
                    p + 1
                ),
                c,
            )
        })?;
        *slot = parse_real(l, tok, || format!("{name} of point {p}"))?;
    }
    Ok(xyz)
}

fn check_indices(cells: &CellList, lines: &[usize], npoin: usize) -> Result<(), FormatError> {
    for (c, (_, nodes)) in cells.iter().enumerate() {
        if let Some(&v) = nodes.iter().find(|&&v| v as usize >= npoin) {
            return Err(FormatError::new(
                Location::Line(lines.get(c).copied().unwrap_or(0)),
                FormatErrorKind::IndexOutOfRange {
                    index: v as u64,
                    bound: npoin,
                },
            ));
        }
    }
    Ok(())
}

pub(crate) const VOLUME_2D: [CellKind; 2] = [CellKind::Triangle, CellKind::Quad];
pub(crate) const VOLUME_3D: [CellKind; 4] = [
    CellKind::Tetra,
    CellKind::Hexahedron,
    CellKind::Prism,
    CellKind::Pyramid,
];
const SURFACE_2D: [CellKind; 1] = [CellKind::Line];
const SURFACE_3D: [CellKind; 2] = [CellKind::Triangle, CellKind::Quad];

/// Parses an SU2 native ASCII mesh. Never panics; errors name the line.
pub fn parse_su2(bytes: &[u8]) -> Result<Su2Mesh, FormatError> {
    parse_su2_with(bytes, false).map(|(mesh, _)| mesh)
}

/// [`parse_su2`] of a file whose element and point lines were cut out (`deform move
/// --distributed` reads those in parallel): `NELEM=` and `NPOIN=` read no lines; the mesh
/// comes back with no elements and no points, with the two counts `(nelem, npoin)`; marker
/// indices are checked against `npoin`.
pub fn parse_su2_skeleton(bytes: &[u8]) -> Result<(Su2Mesh, (usize, usize)), FormatError> {
    parse_su2_with(bytes, true)
}

fn parse_su2_with(bytes: &[u8], skeleton: bool) -> Result<(Su2Mesh, (usize, usize)), FormatError> {
    let mut p = Su2Parser {
        skeleton,
        counts: (0, 0),
        bytes,
        lines: Lines::new(bytes),
        dim: None,
        elements: None,
        points: None,
        markers: None,
        passthrough: Vec::new(),
        text: Su2Text::default(),
    };
    while let Some((line, content)) = p.lines.next_content() {
        p.section(line, content)?;
    }
    p.finish()
}

/// Cells (or marker elements) and the line each was read from.
type LinedCells = (CellList, Vec<usize>);

/// The state of [`parse_su2`]: the sections read so far.
struct Su2Parser<'b> {
    /// Element and point lines are not in `bytes` ([`parse_su2_skeleton`]).
    skeleton: bool,
    /// `NELEM=` and `NPOIN=` counts.
    counts: (usize, usize),
    bytes: &'b [u8],
    lines: Lines<'b>,
    dim: Option<usize>,
    elements: Option<LinedCells>,
    points: Option<Vec<[f64; 3]>>,
    markers: Option<Vec<(Su2Marker, Vec<usize>)>>,
    passthrough: Vec<u8>,
    text: Su2Text,
}

/// A keyword given twice.
fn duplicate(line: usize, keyword: String) -> FormatError {
    FormatError::new(Location::Line(line), FormatErrorKind::Duplicate { keyword })
}

/// What a line that should start a section says instead.
fn not_a_keyword(line: usize, content: &[u8]) -> FormatError {
    FormatError::expected_at_line(
        line,
        "a keyword line (NDIME=, NELEM=, NPOIN= or NMARK=)",
        content,
    )
}

impl<'b> Su2Parser<'b> {
    /// One section, from its keyword line (`content`, at `line`).
    fn section(&mut self, line: usize, content: &'b [u8]) -> Result<(), FormatError> {
        let Some((key, value)) = key_value(content) else {
            return Err(not_a_keyword(line, content));
        };
        let upper = key.to_ascii_uppercase();
        if is_mesh_keyword(&upper) {
            let comments = self.lines.take_comments();
            self.text.note(&String::from_utf8_lossy(&upper), comments);
        }
        match upper.as_slice() {
            b"NDIME" => self.ndime(line, value, content),
            b"NZONE" | b"IZONE" => {
                if parse_uint(tokens(value).next().unwrap_or(&[])) == Some(1) {
                    return Ok(());
                }
                Err(FormatError::new(
                    Location::Line(line),
                    FormatErrorKind::Unsupported {
                        what: "several zones (NZONE/IZONE other than 1) in one mesh: read the file with su2_zones::parse_su2_zones".into(),
                    },
                ))
            }
            b"NELEM" => self.nelem(line, value, content),
            b"NPOIN" => self.npoin(line, value, content),
            b"NMARK" => self.nmark(line, value, content),
            k if is_passthrough_keyword(k) => {
                self.passthrough_section();
                Ok(())
            }
            _ => Err(not_a_keyword(line, content)),
        }
    }

    fn ndime(&mut self, line: usize, value: &[u8], content: &[u8]) -> Result<(), FormatError> {
        if self.dim.is_some() {
            return Err(duplicate(line, "NDIME".into()));
        }
        match parse_uint(tokens(value).next().unwrap_or(&[])) {
            Some(d @ (2 | 3)) => {
                self.dim = Some(d as usize);
                Ok(())
            }
            _ => Err(FormatError::expected_at_line(
                line,
                "NDIME= 2 or NDIME= 3",
                content,
            )),
        }
    }

    /// The dimension, which `keyword` needs to come first.
    fn dim_before(&self, line: usize, keyword: &str, content: &[u8]) -> Result<usize, FormatError> {
        self.dim.ok_or_else(|| {
            FormatError::expected_at_line(line, format!("NDIME= before {keyword}="), content)
        })
    }

    fn nelem(&mut self, line: usize, value: &[u8], content: &[u8]) -> Result<(), FormatError> {
        let d = self.dim_before(line, "NELEM", content)?;
        if self.elements.is_some() {
            return Err(duplicate(line, "NELEM".into()));
        }
        let n = parse_count(line, value, "NELEM")?;
        self.counts.0 = n;
        if self.skeleton {
            self.elements = Some((CellList::new(), Vec::new()));
            return Ok(());
        }
        let allowed: &[CellKind] = if d == 2 { &VOLUME_2D } else { &VOLUME_3D };
        let cells = self.cells(n, allowed, |e, eof| match eof {
            true => format!("element {} of {n} (NELEM= {n})", e + 1),
            false => format!("element {} of {n} (NELEM= {n} at line {line})", e + 1),
        })?;
        self.elements = Some(cells);
        Ok(())
    }

    /// `n` element lines of the `allowed` kinds (`what(e, at_end_of_file)` names element `e`
    /// in errors).
    fn cells(
        &mut self,
        n: usize,
        allowed: &[CellKind],
        what: impl Fn(usize, bool) -> String,
    ) -> Result<LinedCells, FormatError> {
        let mut cells = CellList::new();
        let mut where_ = Vec::new();
        for e in 0..n {
            let (l, c) = self
                .lines
                .next_content()
                .ok_or_else(|| FormatError::eof_at_line(self.lines.eof_line(), what(e, true)))?;
            if key_value(c).is_some() {
                return Err(FormatError::expected_at_line(l, what(e, false), c));
            }
            parse_element(l, c, allowed, &mut cells)?;
            where_.push(l);
        }
        Ok((cells, where_))
    }

    fn npoin(&mut self, line: usize, value: &[u8], content: &[u8]) -> Result<(), FormatError> {
        let d = self.dim_before(line, "NPOIN", content)?;
        if self.points.is_some() {
            return Err(duplicate(line, "NPOIN".into()));
        }
        let n = parse_count(line, value, "NPOIN")?;
        self.counts.1 = n;
        if self.skeleton {
            self.points = Some(Vec::new());
            return Ok(());
        }
        let mut pts = Vec::new();
        for p in 0..n {
            let (l, c) = self.lines.next_content().ok_or_else(|| {
                FormatError::eof_at_line(
                    self.lines.eof_line(),
                    format!("point {} of {n} (NPOIN= {n})", p + 1),
                )
            })?;
            pts.push(parse_point(d, (l, c), (p, n, line))?);
        }
        self.points = Some(pts);
        Ok(())
    }

    fn nmark(&mut self, line: usize, value: &[u8], content: &[u8]) -> Result<(), FormatError> {
        let d = self.dim_before(line, "NMARK", content)?;
        if self.elements.is_none() || self.points.is_none() {
            return Err(FormatError::expected_at_line(
                line,
                "NELEM= and NPOIN= sections before NMARK=",
                content,
            ));
        }
        if self.markers.is_some() {
            return Err(duplicate(line, "NMARK".into()));
        }
        let m = parse_count(line, value, "NMARK")?;
        let allowed: &[CellKind] = if d == 2 { &SURFACE_2D } else { &SURFACE_3D };
        let mut list = Vec::new();
        for k in 0..m {
            let what = format!(
                "MARKER_TAG= (marker {} of {m}, NMARK= {m} at line {line})",
                k + 1
            );
            let marker = self.marker(what, allowed, &list)?;
            list.push(marker);
        }
        self.markers = Some(list);
        Ok(())
    }

    /// One marker: its `MARKER_TAG=` (`what` in errors; not one of `earlier`), its
    /// `MARKER_ELEMS=` and elements.
    fn marker(
        &mut self,
        what: String,
        allowed: &[CellKind],
        earlier: &[(Su2Marker, Vec<usize>)],
    ) -> Result<(Su2Marker, Vec<usize>), FormatError> {
        let (l, c) = self
            .lines
            .next_content()
            .ok_or_else(|| FormatError::eof_at_line(self.lines.eof_line(), what.clone()))?;
        let name = match key_value(c) {
            Some((kk, v))
                if (kk.eq_ignore_ascii_case(b"MARKER_TAG")
                    || kk.eq_ignore_ascii_case(b"MARKERTAG"))
                    && !v.is_empty() =>
            {
                std::str::from_utf8(v)
                    .map_err(|_| FormatError::expected_at_line(l, "a UTF-8 marker name", v))?
                    .to_string()
            }
            _ => return Err(FormatError::expected_at_line(l, what, c)),
        };
        let comments = self.lines.take_comments();
        self.text.note(&format!("MARKER_TAG={name}"), comments);
        if earlier.iter().any(|(mk, _)| mk.name == name) {
            return Err(duplicate(l, format!("MARKER_TAG= {name}")));
        }
        let what = format!("MARKER_ELEMS= for marker {name}");
        let (l2, c2) = self
            .lines
            .next_content()
            .ok_or_else(|| FormatError::eof_at_line(self.lines.eof_line(), what.clone()))?;
        let count = match key_value(c2) {
            Some((kk, v)) if kk.eq_ignore_ascii_case(b"MARKER_ELEMS") => {
                parse_count(l2, v, "MARKER_ELEMS")?
            }
            _ => return Err(FormatError::expected_at_line(l2, what, c2)),
        };
        let (cells, where_) = self.cells(count, allowed, |e, _| {
            format!(
                "element {} of {count} of marker {name} (MARKER_ELEMS= {count} at line {l2})",
                e + 1
            )
        })?;
        let marker = Su2Marker {
            name,
            elements: cells,
        };
        Ok((marker, where_))
    }

    /// Keeps the line just read and everything up to the next mesh keyword, byte for byte
    /// (comments inside included: they are not kept apart).
    fn passthrough_section(&mut self) {
        if self.passthrough.is_empty() {
            let comments = self.lines.take_comments();
            self.text.note("passthrough", comments);
        }
        let from = self.lines.start;
        let mut to = self.bytes.len();
        loop {
            let (pos, count) = (self.lines.pos, self.lines.line);
            match self.lines.next_content() {
                None => break,
                Some((_, c)) => {
                    if key_value(c).is_some_and(|(k, _)| is_mesh_keyword(k)) {
                        to = self.lines.start;
                        self.lines.pos = pos;
                        self.lines.line = count;
                        break;
                    }
                }
            }
        }
        self.lines.take_comments();
        let chunk = self.bytes.get(from..to).unwrap_or(&[]);
        if !self.passthrough.is_empty() && !self.passthrough.ends_with(b"\n") {
            self.passthrough.push(b'\n');
        }
        self.passthrough.extend_from_slice(chunk);
    }

    /// The mesh, once every required section was read and every index is in range.
    fn finish(mut self) -> Result<(Su2Mesh, (usize, usize)), FormatError> {
        let comments = self.lines.take_comments();
        self.text.note("end", comments);
        self.text.crlf = self.lines.crlf == Some(true);
        let end = self.lines.eof_line();
        let missing = |k: &str| {
            FormatError::new(
                Location::Line(end),
                FormatErrorKind::Missing {
                    keyword: format!("{k} section (end of file reached)"),
                },
            )
        };
        let dim = self.dim.ok_or_else(|| missing("NDIME="))?;
        let (elements, elem_lines) = self.elements.ok_or_else(|| missing("NELEM="))?;
        let points = self.points.ok_or_else(|| missing("NPOIN="))?;
        let npoin = if self.skeleton {
            self.counts.1
        } else {
            points.len()
        };
        check_indices(&elements, &elem_lines, npoin)?;
        let mut out = Vec::new();
        for (m, where_) in self.markers.unwrap_or_default() {
            check_indices(&m.elements, &where_, npoin)?;
            out.push(m);
        }
        let mesh = Su2Mesh {
            dim,
            points,
            elements,
            markers: out,
            passthrough: self.passthrough,
            text: self.text,
        };
        Ok((mesh, self.counts))
    }
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Writes `mesh` as SU2 native ASCII (with SU2's trailing index columns). Coordinates are
/// written in Rust's shortest round-trip form, so reading the file back gives the same bits.
pub fn write_su2<W: Write>(mesh: &Su2Mesh, w: &mut W) -> io::Result<()> {
    let mut w = io::BufWriter::new(w);
    write_su2_head(mesh, mesh.elements.len(), &mut w)?;
    let nl = su2_newline(mesh);
    for (c, (code, nodes)) in mesh.elements.iter().enumerate() {
        write_su2_element(&mut w, code, nodes, c, nl)?;
    }
    write_su2_points_head(mesh, mesh.points.len(), &mut w)?;
    for (i, p) in mesh.points.iter().enumerate() {
        write_su2_point(&mut w, p, mesh.dim, i, nl)?;
    }
    write_su2_tail(mesh, &mut w)?;
    w.flush()
}

/// The line end [`write_su2`] writes for `mesh`.
pub(crate) fn su2_newline(mesh: &Su2Mesh) -> &'static str {
    if mesh.text.crlf {
        "\r\n"
    } else {
        "\n"
    }
}

/// The comment lines kept before `key`, each ended by `nl`.
fn write_comments<W: Write>(w: &mut W, t: &Su2Text, key: &str, nl: &str) -> io::Result<()> {
    for line in t.before(key).split_inclusive(|&b| b == b'\n') {
        w.write_all(line.strip_suffix(b"\n").unwrap_or(line))?;
        w.write_all(nl.as_bytes())?;
    }
    Ok(())
}

/// What [`write_su2`] writes before the element lines, for `nelem` elements (the mesh's
/// dimension and marker names checked first).
pub(crate) fn write_su2_head<W: Write>(mesh: &Su2Mesh, nelem: usize, w: &mut W) -> io::Result<()> {
    if mesh.dim != 2 && mesh.dim != 3 {
        return Err(invalid(format!(
            "SU2 dimension must be 2 or 3, not {}",
            mesh.dim
        )));
    }
    for m in &mesh.markers {
        if m.name.is_empty() || m.name.contains(['\n', '\r', '%', '=']) || m.name.trim() != m.name {
            return Err(invalid(format!(
                "marker name {:?} cannot be written to SU2 (empty, padded, or contains a newline, % or =)",
                m.name
            )));
        }
    }
    let t = &mesh.text;
    let nl = su2_newline(mesh);
    if t.comments.is_empty() {
        let banner = BANNER.strip_suffix(b"\n").unwrap_or(BANNER);
        w.write_all(banner)?;
        w.write_all(nl.as_bytes())?;
    }
    write_comments(w, t, "NDIME", nl)?;
    write!(w, "NDIME= {}{nl}", mesh.dim)?;
    write_comments(w, t, "NELEM", nl)?;
    write!(w, "NELEM= {nelem}{nl}")
}

/// Element line `c` as [`write_su2`] writes it.
pub(crate) fn write_su2_element<W: Write>(
    w: &mut W,
    code: u8,
    nodes: &[u32],
    c: usize,
    nl: &str,
) -> io::Result<()> {
    let mut line = Line::new();
    if !(push_cell(&mut line, code, nodes)
        && line.push(b" ")
        && line.push_uint(c as u64)
        && line.push(nl.as_bytes()))
    {
        return Err(too_long());
    }
    line.flush_to(w)
}

/// `code n0 n1 …` of an element line; `false` when it does not fit.
fn push_cell(line: &mut Line, code: u8, nodes: &[u32]) -> bool {
    let mut fits = line.push_uint(code.into());
    for &n in nodes {
        fits = fits && line.push(b" ") && line.push_uint(n.into());
    }
    fits
}

/// What [`write_su2`] writes between the element lines and the `npoin` point lines.
pub(crate) fn write_su2_points_head<W: Write>(
    mesh: &Su2Mesh,
    npoin: usize,
    w: &mut W,
) -> io::Result<()> {
    let nl = su2_newline(mesh);
    write_comments(w, &mesh.text, "NPOIN", nl)?;
    write!(w, "NPOIN= {npoin}{nl}")
}

/// Point line `i` as [`write_su2`] writes it (`dim` coordinates).
pub(crate) fn write_su2_point<W: Write>(
    w: &mut W,
    p: &[f64; 3],
    dim: usize,
    i: usize,
    nl: &str,
) -> io::Result<()> {
    let mut line = Line::new();
    for &x in p.iter().take(dim) {
        if !(line.push_exp(x) && line.push(b" ")) {
            return Err(too_long());
        }
    }
    if !(line.push_uint(i as u64) && line.push(nl.as_bytes())) {
        return Err(too_long());
    }
    line.flush_to(w)
}

/// What [`write_su2`] writes after the point lines: the markers, the passed-through
/// sections, the last comments.
pub(crate) fn write_su2_tail<W: Write>(mesh: &Su2Mesh, w: &mut W) -> io::Result<()> {
    let (t, nl) = (&mesh.text, su2_newline(mesh));
    write_comments(w, t, "NMARK", nl)?;
    write!(w, "NMARK= {}{nl}", mesh.markers.len())?;
    for m in &mesh.markers {
        write_comments(w, t, &format!("MARKER_TAG={}", m.name), nl)?;
        write!(w, "MARKER_TAG= {}{nl}", m.name)?;
        write!(w, "MARKER_ELEMS= {}{nl}", m.elements.len())?;
        for (code, nodes) in m.elements.iter() {
            let mut line = Line::new();
            if !(push_cell(&mut line, code, nodes) && line.push(nl.as_bytes())) {
                return Err(too_long());
            }
            line.flush_to(w)?;
        }
    }
    write_comments(w, t, "passthrough", nl)?;
    w.write_all(&mesh.passthrough)?;
    write_comments(w, t, "end", nl)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass element reader pushes exactly what the token reader pushes, and leaves
    /// every line the token reader refuses (or reads differently) to it.
    #[test]
    fn plain_element_lines_read_as_tokens_read_them() {
        let lines: [&[u8]; 16] = [
            b"10 0 1 2 3 7",
            b"10 0 1 2 3",
            b"10\t4  5\t6 7",
            b"010 0001 2 3 4 99 extra",
            b"5 1 2 3 4",
            b"10 1 2 3",
            b"10 1 2 2 3",
            b"10 1 2 3 4294967296",
            b"10 1 2 3 999999999",
            b"10 1 2 3 1000000000",
            b"10 1 2 3x 4",
            b"+10 1 2 3 4",
            b"-10 1 2 3 4",
            b"12 0 1 2 3 4 5 6 7 8",
            b"256 0 1",
            b"10 1 2 3 4\x0c",
        ];
        let mut plain = 0;
        for content in lines {
            let (mut fast, mut slow) = (CellList::new(), CellList::new());
            let pushed = push_plain_element(content, &VOLUME_3D, &mut fast);
            let tokens = parse_element_tokens(1, content, &VOLUME_3D, &mut slow);
            let text = String::from_utf8_lossy(content);
            if pushed {
                assert!(tokens.is_ok(), "{text}");
                assert_eq!(fast, slow, "{text}");
                plain += 1;
            } else {
                assert!(fast.is_empty(), "{text}");
            }
        }
        assert_eq!(plain, 7, "the plain lines above");
    }
}
