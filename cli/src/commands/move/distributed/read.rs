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

/// Bytes read at a time: the reads stream through the file, never holding a process's whole
/// range.
const BLOCK: u64 = 1 << 22;

/// Calls `f(file offset, line without its end)` for every line that starts in `lo..hi`, in
/// order, reading blocks of [`BLOCK`] bytes.
fn for_each_line(
    file: &File,
    size: u64,
    (lo, hi): (u64, u64),
    f: &mut dyn FnMut(u64, &[u8]),
) -> std::io::Result<()> {
    let mut a = lo;
    while a < hi {
        let b = (a + BLOCK).min(hi);
        let r = Range::read(file, size, (a, b))?;
        for (at, raw) in r.lines() {
            f(at, raw);
        }
        a = b;
    }
    Ok(())
}

/// A line's content without comment, trimmed, and its comment.
fn content(raw: &[u8]) -> (&[u8], &[u8]) {
    match raw.iter().position(|&b| b == b'%') {
        Some(p) => (raw[..p].trim_ascii(), &raw[p..]),
        None => (raw.trim_ascii(), &[][..]),
    }
}

/// Pass 1: the keyword and comment-only lines among the lines that start in `lo..hi`, and
/// the number of those lines.
fn events(file: &File, size: u64, range: (u64, u64)) -> std::io::Result<(Vec<Event>, u64)> {
    let mut out = Vec::new();
    let mut count = 0u64;
    for_each_line(file, size, range, &mut |offset, raw| {
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
    })?;
    Ok((out, count))
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
    let scanned = events(&file, size, (cut(r), cut(r + 1))).map_err(io(path));
    let (mine, lines) = world.agree(scanned)?;
    let every = all_events(world, &mine, lines);
    let b = bodies(&every, size);
    let parsed = skeleton(&file, size, &every, &b)
        .map_err(io(path))
        .and_then(|bytes| {
            parse_su2_skeleton(&bytes).map_err(|source| match source.kind {
                // The serial parser's only `Unsupported`: `NZONE=`/`IZONE=` other than 1.
                FormatErrorKind::Unsupported { .. } => CliError::NotAvailable {
                    feature: "a multi-zone SU2 file with --distributed",
                    needs: "a single-zone file, or a run without --distributed",
                },
                _ => CliError::Read {
                    path: path.to_path_buf(),
                    source,
                },
            })
        });
    let (skeleton, (nelem, npoin)) = world.agree(parsed)?;
    let parts = parse_bodies(&file, size, &b, (skeleton.dim, npoin), (world, path))?;
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

/// This process's share of a body: an even cut of its bytes.
fn share(body: &std::ops::Range<u64>, world: &World<'_>) -> (u64, u64) {
    let len = u128::from(body.end - body.start);
    let at = |k: usize| body.start + (len * k as u128 / world.size as u128) as u64;
    (at(world.rank), at(world.rank + 1))
}

/// Calls `f(1-based line number, content)` for the data lines of this process's share of
/// `body`, whose first line has number `line0`.
fn each_data_line(
    file: &File,
    size: u64,
    share: (u64, u64),
    line0: u64,
    f: &mut dyn FnMut(usize, &[u8]),
) -> std::io::Result<()> {
    let mut line = line0 as usize;
    for_each_line(file, size, share, &mut |_, raw| {
        let c = content(raw).0;
        if !c.is_empty() {
            f(line, c);
        }
        line += 1;
    })
}

/// The lines and the data lines of this process's share of each body.
fn count_shares(file: &File, size: u64, shares: &[(u64, u64); 2]) -> std::io::Result<[u64; 4]> {
    let mut out = [0u64; 4];
    for (k, &s) in shares.iter().enumerate() {
        let (mut lines, mut data) = (0u64, 0u64);
        for_each_line(file, size, s, &mut |_, raw| {
            lines += 1;
            data += u64::from(!content(raw).0.is_empty());
        })?;
        out[2 * k] = lines;
        out[2 * k + 1] = data;
    }
    Ok(out)
}

/// Pass 2: each process parses an even share of the element lines' bytes and of the point
/// lines' bytes (two streaming reads: one to count the lines before its share, one to
/// parse).
fn parse_bodies(
    file: &File,
    size: u64,
    b: &Bodies,
    (dim, npoin): (usize, usize),
    (world, path): (&World<'_>, &Path),
) -> Result<Parts, Failed> {
    let shares = [share(&b[0].0, world), share(&b[1].0, world)];
    let counts = world.agree(count_shares(file, size, &shares).map_err(io(path)))?;
    let before: Vec<u64> = counts.iter().map(|&c| world.before(c)).collect();
    let read_err = |source: FormatError| CliError::Read {
        path: path.to_path_buf(),
        source,
    };
    let allowed: &[CellKind] = if dim == 2 { &VOLUME_2D } else { &VOLUME_3D };
    let mut cells = CellList::new();
    let mut points = Vec::with_capacity(counts[3] as usize);
    let mut failed: Option<CliError> = None;
    let line0 = |k: usize| b[k].1 + 1 + before[2 * k];
    let elements = each_data_line(file, size, shares[0], line0(0), &mut |l, c| {
        if failed.is_none() {
            failed = parse_element(l, c, allowed, &mut cells)
                .and_then(|()| check_nodes(&cells, l, npoin))
                .map_err(read_err)
                .err();
        }
    });
    let first_point = before[3] as usize;
    let points_read = each_data_line(file, size, shares[1], line0(1), &mut |l, c| {
        if failed.is_none() {
            let p = (first_point + points.len(), npoin, b[1].1 as usize);
            match parse_point(dim, (l, c), p) {
                Ok(x) => points.push(x),
                Err(e) => failed = Some(read_err(e)),
            }
        }
    });
    let done = elements.and(points_read).map_err(io(path));
    world.agree(done.and_then(|()| failed.map_or(Ok(()), Err)))?;
    Ok((cells, before[1], points, before[3]))
}

/// The last cell's nodes must be below `npoin` (the serial parser's index check).
fn check_nodes(cells: &CellList, l: usize, npoin: usize) -> Result<(), FormatError> {
    let (_, nodes) = cells.cell(cells.len() - 1);
    match nodes.iter().find(|&&v| v as usize >= npoin) {
        Some(&v) => Err(FormatError::new(
            Location::Line(l),
            FormatErrorKind::IndexOutOfRange {
                index: u64::from(v),
                bound: npoin,
            },
        )),
        None => Ok(()),
    }
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
