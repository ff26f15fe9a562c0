//! The parallel read of an SU2 mesh: each process reads one byte range of the file and
//! parses the element and point lines whose first byte lies in it; the rest of the file (the
//! header, the markers, passed-through sections: the boundary, small) is read by every
//! process and parsed by the serial parser with the two bodies cut out
//! ([`parse_su2_skeleton`]), so every check and every kept comment is the serial one.

use std::fs::File;
use std::os::unix::fs::FileExt;
use std::path::Path;

use deform_kernel::CellKind;

use super::comm::{Failed, World};
use crate::error::CliError;
use crate::formats::su2::{
    key_value, parse_element, parse_point, parse_su2_skeleton, Su2Mesh, VOLUME_2D, VOLUME_3D,
};
use crate::formats::{CellList, FormatError, FormatErrorKind, Location};

/// What one process holds after the read.
pub(super) struct Read {
    /// The mesh without elements and points: dimension, markers, comments, passthrough.
    pub skeleton: Su2Mesh,
    /// `NELEM=` and `NPOIN=`.
    pub nelem: u64,
    pub npoin: u64,
    /// This process's element lines: elements `first_element..` in file order.
    pub elements: CellList,
    pub first_element: u64,
    /// This process's point lines: points `first_point..`.
    pub points: Vec<[f64; 3]>,
    pub first_point: u64,
}

/// A keyword or comment-only line: where it starts, its 0-based line number, its bytes
/// (without the line end), and whether it is a keyword line.
struct Event {
    offset: u64,
    line: u64,
    keyword: bool,
    bytes: Vec<u8>,
}

/// This process's byte range of the file, extended to whole lines.
struct Range {
    /// File offset of `buf[0]`.
    base: u64,
    buf: Vec<u8>,
    /// Lines starting in `lo..hi` are this process's.
    lo: u64,
    hi: u64,
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> CliError + '_ {
    move |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    }
}

impl Range {
    /// Reads bytes `lo − 1 .. hi` and on to the end of the line that holds byte `hi − 1`.
    fn read(file: &File, size: u64, (lo, hi): (u64, u64)) -> std::io::Result<Self> {
        let base = lo.saturating_sub(1);
        let mut buf = vec![0u8; (hi - base) as usize];
        file.read_exact_at(&mut buf, base)?;
        let mut end = hi;
        while end < size && buf.last() != Some(&b'\n') {
            let more = (size - end).min(1 << 16);
            let mut extra = vec![0u8; more as usize];
            file.read_exact_at(&mut extra, end)?;
            match extra.iter().position(|&b| b == b'\n') {
                Some(p) => {
                    buf.extend_from_slice(&extra[..=p]);
                    end = size;
                }
                None => {
                    buf.extend_from_slice(&extra);
                    end += more;
                }
            }
        }
        Ok(Range { base, buf, lo, hi })
    }

    /// `(file offset, line without its end)` of every line that starts in `lo..hi`.
    fn lines(&self) -> impl Iterator<Item = (u64, &[u8])> + '_ {
        let mut pos = (self.lo - self.base) as usize;
        if self.lo > 0 && self.buf.first() != Some(&b'\n') {
            // The line that holds `lo` started before it: the previous process's.
            pos = match self.buf.iter().position(|&b| b == b'\n') {
                Some(p) => p + 1,
                None => self.buf.len(),
            };
        }
        let stop = (self.hi - self.base) as usize;
        std::iter::from_fn(move || {
            if pos >= stop || pos >= self.buf.len() {
                return None;
            }
            let rest = &self.buf[pos..];
            let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            let at = self.base + pos as u64;
            pos += len + 1;
            Some((at, &rest[..len]))
        })
    }
}

/// A line's content without comment, trimmed, and its comment.
fn content(raw: &[u8]) -> (&[u8], &[u8]) {
    match raw.iter().position(|&b| b == b'%') {
        Some(p) => (raw[..p].trim_ascii(), &raw[p..]),
        None => (raw.trim_ascii(), &[][..]),
    }
}

/// Pass 1: this process's keyword and comment-only lines, and its line count.
fn events(r: &Range) -> (Vec<Event>, u64) {
    let mut out = Vec::new();
    let mut count = 0u64;
    for (offset, raw) in r.lines() {
        let (t, comment) = content(raw);
        let keyword = !t.is_empty() && key_value(t).is_some();
        if keyword || (t.is_empty() && !comment.is_empty()) {
            out.push(Event {
                offset,
                line: count,
                keyword,
                bytes: raw.to_vec(),
            });
        }
        count += 1;
    }
    (out, count)
}

/// Every process's events, in file order, with global line numbers.
fn all_events(world: &World<'_>, mine: &[Event], lines: u64) -> Vec<Event> {
    let before = world.before(lines);
    let mut words: Vec<u64> = Vec::new();
    let mut bytes: Vec<u8> = Vec::new();
    for e in mine {
        words.extend([e.offset, e.line + before, u64::from(e.keyword)]);
        words.push(e.bytes.len() as u64);
        bytes.extend_from_slice(&e.bytes);
    }
    let (words, bytes) = (world.gather_all(&words), world.gather_all(&bytes));
    let mut out = Vec::new();
    for (w, b) in words.iter().zip(&bytes) {
        let mut at = 0usize;
        for e in w.chunks_exact(4) {
            let len = e[3] as usize;
            out.push(Event {
                offset: e[0],
                line: e[1],
                keyword: e[2] != 0,
                bytes: b[at..at + len].to_vec(),
            });
            at += len;
        }
    }
    out
}

/// The bodies of `NELEM=` and `NPOIN=`: the byte ranges after their keyword lines up to the
/// next keyword line, and the keyword lines' numbers.
type Bodies = [(std::ops::Range<u64>, u64); 2];

fn bodies(events: &[Event], size: u64) -> Bodies {
    let body = |name: &[u8]| {
        let keywords: Vec<&Event> = events.iter().filter(|e| e.keyword).collect();
        let at = keywords.iter().position(|e| {
            key_value(content(&e.bytes).0).is_some_and(|(k, _)| k.eq_ignore_ascii_case(name))
        });
        match at {
            Some(i) => {
                let e = keywords[i];
                let start = (e.offset + e.bytes.len() as u64 + 1).min(size);
                let end = keywords.get(i + 1).map_or(size, |n| n.offset);
                (start..end, e.line + 1)
            }
            None => (size..size, 0),
        }
    };
    [body(b"NELEM"), body(b"NPOIN")]
}

/// The file without the two bodies' data lines (their comment-only lines kept in place).
fn skeleton(file: &File, size: u64, events: &[Event], b: &Bodies) -> std::io::Result<Vec<u8>> {
    let mut cuts: Vec<&std::ops::Range<u64>> = b.iter().map(|(r, _)| r).collect();
    cuts.sort_by_key(|r| r.start);
    let mut out = Vec::new();
    let mut at = 0u64;
    for cut in cuts {
        if cut.start > at {
            let mut piece = vec![0u8; (cut.start - at) as usize];
            file.read_exact_at(&mut piece, at)?;
            out.extend_from_slice(&piece);
        }
        for e in events.iter().filter(|e| cut.contains(&e.offset)) {
            out.extend_from_slice(&e.bytes);
            out.push(b'\n');
        }
        at = at.max(cut.end);
    }
    if size > at {
        let mut piece = vec![0u8; (size - at) as usize];
        file.read_exact_at(&mut piece, at)?;
        out.extend_from_slice(&piece);
    }
    Ok(out)
}

/// Reads `path` in parallel (see the module's documentation).
pub(super) fn read(world: &World<'_>, path: &Path) -> Result<Read, Failed> {
    let opened = File::open(path)
        .and_then(|f| f.metadata().map(|m| (f, m.len())))
        .map_err(io(path));
    let (file, size) = world.agree(opened)?;
    let (p, r) = (world.size as u64, world.rank as u64);
    let cut = |k: u64| (u128::from(size) * u128::from(k) / u128::from(p)) as u64;
    let range = world.agree(Range::read(&file, size, (cut(r), cut(r + 1))).map_err(io(path)))?;
    let (mine, lines) = events(&range);
    let every = all_events(world, &mine, lines);
    let b = bodies(&every, size);
    let parsed = skeleton(&file, size, &every, &b)
        .map_err(io(path))
        .and_then(|bytes| {
            parse_su2_skeleton(&bytes).map_err(|source| CliError::Read {
                path: path.to_path_buf(),
                source,
            })
        });
    let (skeleton, (nelem, npoin)) = world.agree(parsed)?;
    let line0 = world.before(lines) + 1;
    let parts = world.agree(parse_bodies(
        &range,
        &b,
        skeleton.dim,
        line0,
        npoin,
        (world, path),
    ))?;
    let parts = world.agree(check_counts(parts, world, (nelem, npoin), path))?;
    let (elements, first_element, points, first_point) = parts;
    Ok(Read {
        skeleton,
        nelem: nelem as u64,
        npoin: npoin as u64,
        elements,
        first_element,
        points,
        first_point,
    })
}

/// This process's elements and points, each with the number of the same before it.
type Parts = (CellList, u64, Vec<[f64; 3]>, u64);

/// Pass 2: the data lines of the two bodies in this process's range (`line0`: the 1-based
/// number of its first line).
fn parse_bodies(
    r: &Range,
    b: &Bodies,
    dim: usize,
    line0: u64,
    npoin: usize,
    (world, path): (&World<'_>, &Path),
) -> Result<Parts, CliError> {
    let data = |body: &std::ops::Range<u64>| data_lines(r, body.clone(), line0);
    let counts = [data(&b[0].0).count() as u64, data(&b[1].0).count() as u64];
    let before = [world.before(counts[0]), world.before(counts[1])];
    let allowed: &[CellKind] = if dim == 2 { &VOLUME_2D } else { &VOLUME_3D };
    let mut cells = CellList::new();
    let read_err = |source: FormatError| CliError::Read {
        path: path.to_path_buf(),
        source,
    };
    for (l, c) in data(&b[0].0) {
        parse_element(l, c, allowed, &mut cells).map_err(read_err)?;
        let (_, nodes) = cells.cell(cells.len() - 1);
        if let Some(&v) = nodes.iter().find(|&&v| v as usize >= npoin) {
            let kind = FormatErrorKind::IndexOutOfRange {
                index: u64::from(v),
                bound: npoin,
            };
            return Err(read_err(FormatError::new(Location::Line(l), kind)));
        }
    }
    let mut points = Vec::with_capacity(counts[1] as usize);
    for (k, (l, c)) in data(&b[1].0).enumerate() {
        let p = before[1] as usize + k;
        points.push(parse_point(dim, (l, c), (p, npoin, b[1].1 as usize)).map_err(read_err)?);
    }
    Ok((cells, before[0], points, before[1]))
}

/// `(1-based line number, content)` of the data lines of `body` in `r` (`line0`: the number
/// of `r`'s first line).
fn data_lines(
    r: &Range,
    body: std::ops::Range<u64>,
    line0: u64,
) -> impl Iterator<Item = (usize, &[u8])> + '_ {
    r.lines()
        .enumerate()
        .filter(move |(_, (at, _))| body.contains(at))
        .map(move |(k, (_, raw))| (line0 as usize + k, content(raw).0))
        .filter(|(_, c)| !c.is_empty())
}

/// The element and point lines must be as many as `NELEM=` and `NPOIN=` say.
fn check_counts(
    parts: Parts,
    world: &World<'_>,
    (nelem, npoin): (usize, usize),
    path: &Path,
) -> Result<Parts, CliError> {
    let total = world.sum(&[parts.0.len() as u64, parts.2.len() as u64]);
    for (what, found, want) in [("element", total[0], nelem), ("point", total[1], npoin)] {
        if found != want as u64 {
            return Err(CliError::Invalid(format!(
                "{}: {} {what} lines where the count says {want}",
                path.display(),
                found
            )));
        }
    }
    Ok(parts)
}
