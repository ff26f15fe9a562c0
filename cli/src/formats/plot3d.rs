//! Plot3D whole grids (`.x`, `.xyz`, `.p3d`): 2D and 3D, single and multi-block, ASCII and
//! binary, little and big endian, 32- and 64-bit reals, with or without Fortran record
//! markers, with or without iblank; read and write.
//!
//! Layout of a whole grid: `[nblocks]`, the dimensions of every block (`ni nj` or `ni nj nk`),
//! then per block all `x`, all `y`, [all `z`], [all iblank], i fastest. Binary files written
//! by Fortran `unformatted` I/O wrap each of these groups in 4-byte record markers
//! (`[nblocks]`, `[all dims]`, then one record per block). Text files are read as Fortran
//! list-directed input ([`super::listdirected`]): `2*0.5` repeat counts, commas, `/` and line
//! breaks anywhere, as Fortran codes such as CFL3D write them.
//!
//! The reader detects the layout by trying every combination the [`Plot3dOptions`] allow and
//! keeping the ones whose headers, record markers and total size fit the file exactly. One fit
//! is read; none is an error explaining the closest candidate; several is an error listing them
//! (fix the layout with the options).

use std::fmt;
use std::io::{self, Write};

use super::error::{show, FormatError, FormatErrorKind, Location};
use super::listdirected::{parse_int, parse_real, Item, Values};

/// Byte order of a binary file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Endian {
    /// Little endian (x86, ARM).
    Little,
    /// Big endian.
    Big,
}

/// Width of the reals in a binary file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// 32-bit IEEE reals.
    Single,
    /// 64-bit IEEE reals.
    Double,
}

impl Precision {
    fn bytes(self) -> u64 {
        match self {
            Precision::Single => 4,
            Precision::Double => 8,
        }
    }
}

/// Text or binary, and for binary the byte-level details.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Whitespace-separated text.
    Ascii,
    /// Raw binary.
    Binary {
        /// Byte order.
        endian: Endian,
        /// Real width.
        precision: Precision,
        /// Fortran 4-byte record markers around each record.
        records: bool,
    },
}

/// A complete description of how a Plot3D grid file is laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Plot3dLayout {
    /// Text or binary.
    pub encoding: Encoding,
    /// 2 or 3.
    pub dim: usize,
    /// The file starts with the number of blocks (always true for more than one block).
    pub multi_block: bool,
    /// Each block ends with an integer iblank array.
    pub iblank: bool,
}

impl fmt::Display for Plot3dLayout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}D", self.dim)?;
        match self.encoding {
            Encoding::Ascii => write!(f, " ASCII")?,
            Encoding::Binary {
                endian,
                precision,
                records,
            } => {
                let e = if endian == Endian::Little {
                    "little-endian"
                } else {
                    "big-endian"
                };
                let p = if precision == Precision::Single {
                    "f32"
                } else {
                    "f64"
                };
                let r = if records {
                    "Fortran records"
                } else {
                    "no record markers"
                };
                write!(f, " binary {p} {e} {r}")?;
            }
        }
        write!(
            f,
            ", {}, {}",
            if self.multi_block {
                "multi-block header"
            } else {
                "single block"
            },
            if self.iblank { "iblank" } else { "no iblank" }
        )
    }
}

/// Constraints on layout detection; `None` means "detect".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Plot3dOptions {
    /// Force text (`Some(true)`) or binary (`Some(false)`).
    pub ascii: Option<bool>,
    /// Force 2 or 3 dimensions.
    pub dim: Option<usize>,
    /// Force the presence or absence of the number-of-blocks header.
    pub multi_block: Option<bool>,
    /// Force the presence or absence of iblank.
    pub iblank: Option<bool>,
    /// Force the byte order.
    pub endian: Option<Endian>,
    /// Force the real width.
    pub precision: Option<Precision>,
    /// Force the presence or absence of Fortran record markers.
    pub records: Option<bool>,
}

/// One structured block.
#[derive(Clone, Debug, PartialEq)]
pub struct Plot3dBlock {
    /// `[ni, nj, nk]`, `nk = 1` in 2D.
    pub dims: [usize; 3],
    /// Points, i fastest (`i + ni (j + nj k)`); `z = 0` in 2D.
    pub points: Vec<[f64; 3]>,
    /// iblank values, when the file has them.
    pub iblank: Option<Vec<i32>>,
}

/// A whole grid: one or more blocks of the same dimension.
#[derive(Clone, Debug, PartialEq)]
pub struct Plot3dGrid {
    /// 2 or 3.
    pub dim: usize,
    /// The blocks, in file order.
    pub blocks: Vec<Plot3dBlock>,
}

fn candidates(opts: &Plot3dOptions, ascii: bool) -> Vec<Plot3dLayout> {
    let mut out = Vec::new();
    let encs: Vec<Encoding> = if ascii {
        vec![Encoding::Ascii]
    } else {
        let mut v = Vec::new();
        for records in [true, false] {
            for endian in [Endian::Little, Endian::Big] {
                for precision in [Precision::Double, Precision::Single] {
                    let ok = opts.records.is_none_or(|r| r == records)
                        && opts.endian.is_none_or(|e| e == endian)
                        && opts.precision.is_none_or(|p| p == precision);
                    if ok {
                        v.push(Encoding::Binary {
                            endian,
                            precision,
                            records,
                        });
                    }
                }
            }
        }
        v
    };
    for encoding in encs {
        for multi_block in [true, false] {
            for dim in [3, 2] {
                for iblank in [false, true] {
                    let ok = opts.multi_block.is_none_or(|m| m == multi_block)
                        && opts.dim.is_none_or(|d| d == dim)
                        && opts.iblank.is_none_or(|i| i == iblank);
                    if ok {
                        out.push(Plot3dLayout {
                            encoding,
                            dim,
                            multi_block,
                            iblank,
                        });
                    }
                }
            }
        }
    }
    out
}

/// The largest |iblank| accepted. Plot3D iblank is 1 (field), 0 (blanked), 2 (fringe in some
/// codes) or a negative donor-grid number for overset interpolation; a value beyond this is a
/// real or a dimension read as an iblank (a corrupted or misdetected file).
const IBLANK_LIMIT: u32 = 100_000;

fn check_iblank(v: i32, point: usize, block: usize, at: Location) -> Result<(), FormatError> {
    if v.unsigned_abs() > IBLANK_LIMIT {
        return Err(FormatError::new(
            at,
            FormatErrorKind::Expected {
                expected: format!(
                    "an iblank value for point {point} of block {} (0, 1, 2 or a negative grid number, |iblank| <= {IBLANK_LIMIT}); the dimensions or the layout are probably wrong",
                    block + 1
                ),
                found: v.to_string(),
            },
        ));
    }
    Ok(())
}

/// A UTF-8 byte-order mark, which some editors put before ASCII Plot3D files.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

fn looks_ascii(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .all(|&b| b.is_ascii_graphic() || b.is_ascii_whitespace())
}

/// Reads a Plot3D whole grid, detecting the layout within the limits of `opts`. Never panics.
pub fn parse_plot3d(
    bytes: &[u8],
    opts: &Plot3dOptions,
) -> Result<(Plot3dGrid, Plot3dLayout), FormatError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(FormatError::new(
            Location::File,
            FormatErrorKind::UnexpectedEof {
                expected: "a Plot3D grid (the file is empty)".into(),
            },
        ));
    }
    let text = bytes.strip_prefix(UTF8_BOM).unwrap_or(bytes);
    let ascii = opts.ascii.unwrap_or_else(|| looks_ascii(text));
    if ascii {
        let vals = Values::parse(text)?;
        let mut fits = Vec::new();
        let mut best: Option<(u64, FormatError, Plot3dLayout)> = None;
        for layout in candidates(opts, true) {
            match ascii_plan(&vals, &layout) {
                Ok(dims) => fits.push((layout, dims)),
                Err((progress, e)) => keep_best(&mut best, progress, e, layout),
            }
        }
        choose(fits, best, |layout, dims| {
            let grid = ascii_read(&vals, layout, dims)?;
            Ok((grid, line_rule_violations(&vals, layout, dims)))
        })
    } else {
        let mut fits = Vec::new();
        let mut best: Option<(u64, FormatError, Plot3dLayout)> = None;
        for layout in candidates(opts, false) {
            match binary_plan(bytes, &layout) {
                Ok(dims) => fits.push((layout, dims)),
                Err((verified, e)) => {
                    let progress = match e.location {
                        Location::Byte(b) => b,
                        _ => 0,
                    };
                    // Verified record markers are strong evidence: rank them first.
                    keep_best(
                        &mut best,
                        (verified << 40) | progress.min(1 << 39),
                        e,
                        layout,
                    )
                }
            }
        }
        choose(fits, best, |layout, dims| {
            Ok((binary_read(bytes, layout, dims)?, 0))
        })
    }
}

/// Values that real grids rarely hold: subnormal or astronomically large reals, huge
/// iblank values. Used only to break ties between layouts that fit the file size.
fn weirdness(grid: &Plot3dGrid) -> u64 {
    let mut w = 0;
    for b in &grid.blocks {
        for p in &b.points {
            for &x in p {
                if x != 0.0 && !(1e-30..=1e30).contains(&x.abs()) {
                    w += 1;
                }
            }
        }
        if let Some(ib) = &b.iblank {
            w += ib.iter().filter(|v| v.unsigned_abs() > 1_000_000).count() as u64;
        }
    }
    w
}

/// ASCII tie-breaker: the number-of-blocks header alone on its line, each block's dimensions
/// on one line, and the data starting on a new line (as every writer we know does).
fn line_rule_violations(vals: &Values<'_>, layout: &Plot3dLayout, dims: &Dims) -> u64 {
    let line = |i: usize| vals.get(i as u64).map_or(0, |t| t.line);
    let mut v = 0;
    let mut i = 0;
    if layout.multi_block {
        if line(1) == line(0) {
            v += 1;
        }
        i = 1;
    }
    for _ in dims {
        let first = line(i);
        if (i..i + layout.dim).any(|k| line(k) != first) {
            v += 1;
        }
        i += layout.dim;
    }
    if i > 0 && line(i) == line(i - 1) {
        v += 1;
    }
    v
}

fn keep_best(
    best: &mut Option<(u64, FormatError, Plot3dLayout)>,
    progress: u64,
    e: FormatError,
    layout: Plot3dLayout,
) {
    if best.as_ref().is_none_or(|(p, _, _)| progress > *p) {
        *best = Some((progress, e, layout));
    }
}

type Dims = Vec<[usize; 3]>;

fn choose<F>(
    fits: Vec<(Plot3dLayout, Dims)>,
    best: Option<(u64, FormatError, Plot3dLayout)>,
    read: F,
) -> Result<(Plot3dGrid, Plot3dLayout), FormatError>
where
    F: Fn(&Plot3dLayout, &Dims) -> Result<(Plot3dGrid, u64), FormatError>,
{
    if fits.len() == 1 {
        if let Some((layout, dims)) = fits.first() {
            let (grid, _) = read(layout, dims)?;
            return Ok((grid, *layout));
        }
    }
    if fits.len() > 1 {
        // Several layouts fit the size: read each, drop those that fail (NaN, bad numbers),
        // and keep the single most plausible one.
        let mut scored = Vec::new();
        let mut first_err = None;
        for (layout, dims) in &fits {
            match read(layout, dims) {
                Ok((grid, rule)) => {
                    let score = (rule, weirdness(&grid));
                    scored.push((score, grid, *layout));
                }
                Err(e) => {
                    first_err.get_or_insert(e);
                }
            }
        }
        let min = scored.iter().map(|(s, _, _)| *s).min();
        let mut top: Vec<_> = scored
            .into_iter()
            .filter(|(s, _, _)| Some(*s) == min)
            .collect();
        if top.len() == 1 {
            if let Some((_, grid, layout)) = top.pop() {
                return Ok((grid, layout));
            }
        }
        if top.is_empty() {
            if let Some(e) = first_err {
                return Err(e);
            }
        }
        return Err(FormatError::new(
            Location::File,
            FormatErrorKind::Ambiguous {
                candidates: top.iter().map(|(_, _, l)| l.to_string()).collect(),
            },
        ));
    }
    match best {
        Some((_, e, layout)) => Err(FormatError::new(
            e.location,
            FormatErrorKind::NoLayout {
                reason: format!("{} (reading as the closest layout: {layout})", e.kind),
            },
        )),
        None => Err(FormatError::new(
            Location::File,
            FormatErrorKind::NoLayout {
                reason: "the layout options exclude every Plot3D layout".into(),
            },
        )),
    }
}

fn block_points(d: [usize; 3]) -> Option<u64> {
    (d[0] as u64)
        .checked_mul(d[1] as u64)?
        .checked_mul(d[2] as u64)
}

// ---------------------------------------------------------------------------------- binary

struct Cursor<'a> {
    b: &'a [u8],
    pos: usize,
    endian: Endian,
    verified: u64,
}

impl<'a> Cursor<'a> {
    fn at(&self) -> Location {
        Location::Byte(self.pos as u64)
    }

    fn take(&mut self, n: u64, what: &str) -> Result<&'a [u8], FormatError> {
        let left = (self.b.len() - self.pos.min(self.b.len())) as u64;
        if n > left {
            return Err(FormatError::new(
                self.at(),
                FormatErrorKind::UnexpectedEof {
                    expected: format!("{what} ({n} bytes), only {left} bytes left"),
                },
            ));
        }
        let n = n as usize;
        let s = self.b.get(self.pos..self.pos + n).unwrap_or(&[]);
        self.pos += n;
        Ok(s)
    }

    fn i32(&mut self, what: &str) -> Result<i32, FormatError> {
        let s = self.take(4, what)?;
        let a: [u8; 4] = s.try_into().unwrap_or([0; 4]);
        Ok(match self.endian {
            Endian::Little => i32::from_le_bytes(a),
            Endian::Big => i32::from_be_bytes(a),
        })
    }

    fn positive(&mut self, what: &str) -> Result<usize, FormatError> {
        let loc = self.at();
        let v = self.i32(what)?;
        if v < 1 {
            return Err(FormatError::new(
                loc,
                FormatErrorKind::Expected {
                    expected: format!("{what} (a positive integer)"),
                    found: v.to_string(),
                },
            ));
        }
        Ok(v as usize)
    }

    fn record_start(&mut self, on: bool, len: u64, what: &str) -> Result<(), FormatError> {
        if !on {
            return Ok(());
        }
        let loc = self.at();
        let v = self.i32(&format!("record marker before {what}"))?;
        if v as i64 != len as i64 {
            return Err(FormatError::new(
                loc,
                FormatErrorKind::Expected {
                    expected: format!("record marker {len} before {what}"),
                    found: v.to_string(),
                },
            ));
        }
        self.verified += 1;
        Ok(())
    }

    fn record_end(&mut self, on: bool, len: u64, what: &str) -> Result<(), FormatError> {
        if !on {
            return Ok(());
        }
        let loc = self.at();
        let v = self.i32(&format!("record marker after {what}"))?;
        if v as i64 != len as i64 {
            return Err(FormatError::new(
                loc,
                FormatErrorKind::Expected {
                    expected: format!("record marker {len} after {what}"),
                    found: v.to_string(),
                },
            ));
        }
        self.verified += 1;
        Ok(())
    }
}

fn too_large(loc: Location, what: &str, value: u64) -> FormatError {
    FormatError::new(
        loc,
        FormatErrorKind::TooLarge {
            what: what.to_string(),
            value,
        },
    )
}

fn binary_params(layout: &Plot3dLayout) -> (Endian, Precision, bool) {
    match layout.encoding {
        Encoding::Binary {
            endian,
            precision,
            records,
        } => (endian, precision, records),
        Encoding::Ascii => (Endian::Little, Precision::Double, false),
    }
}

fn block_bytes(layout: &Plot3dLayout, npts: u64, prec: Precision) -> Option<u64> {
    let per = layout.dim as u64 * prec.bytes() + if layout.iblank { 4 } else { 0 };
    npts.checked_mul(per)
}

/// Walks headers and record markers; returns the block dimensions if the file fits exactly.
fn binary_plan(bytes: &[u8], layout: &Plot3dLayout) -> Result<Dims, (u64, FormatError)> {
    let (endian, _, _) = binary_params(layout);
    let mut c = Cursor {
        b: bytes,
        pos: 0,
        endian,
        verified: 0,
    };
    binary_plan_inner(&mut c, layout).map_err(|e| (c.verified, e))
}

fn binary_plan_inner(c: &mut Cursor<'_>, layout: &Plot3dLayout) -> Result<Dims, FormatError> {
    let (_, prec, rec) = binary_params(layout);
    let bytes = c.b;
    let nb = if layout.multi_block {
        c.record_start(rec, 4, "the number of blocks")?;
        let nb = c.positive("the number of blocks")?;
        c.record_end(rec, 4, "the number of blocks")?;
        nb
    } else {
        1
    };
    let dims_len = (nb as u64) * (layout.dim as u64) * 4;
    if dims_len > bytes.len() as u64 {
        return Err(too_large(c.at(), "number of blocks", nb as u64));
    }
    c.record_start(rec, dims_len, "the block dimensions")?;
    let mut dims = Vec::new();
    for b in 0..nb {
        let mut d = [1usize; 3];
        for (k, slot) in d.iter_mut().take(layout.dim).enumerate() {
            let name = ["ni", "nj", "nk"].get(k).copied().unwrap_or("n");
            *slot = c.positive(&format!("{name} of block {}", b + 1))?;
        }
        dims.push(d);
    }
    c.record_end(rec, dims_len, "the block dimensions")?;
    for (b, d) in dims.iter().enumerate() {
        let what = format!("block {} data", b + 1);
        let len = block_points(*d)
            .and_then(|n| block_bytes(layout, n, prec))
            .ok_or_else(|| too_large(c.at(), &format!("size of block {}", b + 1), u64::MAX))?;
        if rec && len > i32::MAX as u64 {
            return Err(too_large(
                c.at(),
                &format!("record length of block {}", b + 1),
                len,
            ));
        }
        c.record_start(rec, len, &what)?;
        c.take(len, &what)?;
        c.record_end(rec, len, &what)?;
    }
    if c.pos != bytes.len() {
        return Err(FormatError::new(
            c.at(),
            FormatErrorKind::Expected {
                expected: format!("end of file after {nb} block(s)"),
                found: format!("{} more bytes", bytes.len() - c.pos),
            },
        ));
    }
    Ok(dims)
}

fn binary_read(
    bytes: &[u8],
    layout: &Plot3dLayout,
    dims: &Dims,
) -> Result<Plot3dGrid, FormatError> {
    let (endian, prec, rec) = binary_params(layout);
    let mut c = Cursor {
        b: bytes,
        pos: 0,
        endian,
        verified: 0,
    };
    let header = match (layout.multi_block, rec) {
        (false, _) => 0,
        (true, false) => 4,
        (true, true) => 12,
    };
    let dims_rec = dims.len() * layout.dim * 4 + if rec { 8 } else { 0 };
    c.pos = header + dims_rec;
    let mut blocks = Vec::new();
    for (b, d) in dims.iter().enumerate() {
        if rec {
            c.pos += 4;
        }
        let n = d[0] * d[1] * d[2];
        let mut points = vec![[0.0f64; 3]; n];
        for k in 0..layout.dim {
            for (i, p) in points.iter_mut().enumerate() {
                if let Some(slot) = p.get_mut(k) {
                    *slot = c.coordinate(prec, (k, i, b))?;
                }
            }
        }
        let iblank = if layout.iblank {
            let mut ib = Vec::with_capacity(n);
            for i in 0..n {
                let loc = c.at();
                let v = c.i32("an iblank value")?;
                check_iblank(v, i, b, loc)?;
                ib.push(v);
            }
            Some(ib)
        } else {
            None
        };
        if rec {
            c.pos += 4;
        }
        blocks.push(Plot3dBlock {
            dims: *d,
            points,
            iblank,
        });
    }
    Ok(Plot3dGrid {
        dim: layout.dim,
        blocks,
    })
}

impl Cursor<'_> {
    /// One binary coordinate: `axis` of point `i` of block `b` (0-based, for errors). Not
    /// finite, or subnormal (what reals read in the wrong byte order or at the wrong offset
    /// look like; no grid generator writes them), is an error.
    fn coordinate(
        &mut self,
        prec: Precision,
        (axis, i, b): (usize, usize, usize),
    ) -> Result<f64, FormatError> {
        let endian = self.endian;
        let axis = ["x", "y", "z"].get(axis).copied().unwrap_or("?");
        let loc = self.at();
        let s = self.take(prec.bytes(), "a coordinate")?;
        let v = match (prec, endian) {
            (Precision::Single, Endian::Little) => {
                f32::from_le_bytes(s.try_into().unwrap_or([0; 4])) as f64
            }
            (Precision::Single, Endian::Big) => {
                f32::from_be_bytes(s.try_into().unwrap_or([0; 4])) as f64
            }
            (Precision::Double, Endian::Little) => {
                f64::from_le_bytes(s.try_into().unwrap_or([0; 8]))
            }
            (Precision::Double, Endian::Big) => f64::from_be_bytes(s.try_into().unwrap_or([0; 8])),
        };
        if !v.is_finite() {
            return Err(FormatError::new(
                loc,
                FormatErrorKind::NotFinite {
                    what: format!("{axis} of point {i} of block {}", b + 1),
                    found: v.to_string(),
                },
            ));
        }
        let subnormal = match prec {
            Precision::Single => (v as f32).is_subnormal(),
            Precision::Double => v.is_subnormal(),
        };
        if subnormal {
            return Err(FormatError::new(
                loc,
                FormatErrorKind::Expected {
                    expected: format!(
                        "a plausible {axis} of point {i} of block {} ({endian:?}-endian {prec:?}; a subnormal value means the reals are in another byte order than the integers, or the layout is wrong)",
                        b + 1
                    ),
                    found: format!("{v:e}"),
                },
            ));
        }
        Ok(v)
    }
}

// ----------------------------------------------------------------------------------- ascii

/// Value `i` as a positive integer (a block count or dimension).
fn value_positive(vals: &Values<'_>, i: u64, what: &str) -> Result<usize, (u64, FormatError)> {
    let Some(t) = vals.get(i) else {
        return Err((
            i,
            FormatError::eof_at_line(vals.last_line(), what.to_string()),
        ));
    };
    let v = t
        .value
        .and_then(parse_int)
        .filter(|&v| v >= 1)
        .and_then(|v| i32::try_from(v).ok());
    match v {
        Some(v) => Ok(v as usize),
        None => Err((
            i,
            FormatError::expected_at_line(t.line, format!("{what} (a positive integer)"), t.token),
        )),
    }
}

fn ascii_plan(vals: &Values<'_>, layout: &Plot3dLayout) -> Result<Dims, (u64, FormatError)> {
    let mut i = 0u64;
    let nb = if layout.multi_block {
        i += 1;
        value_positive(vals, 0, "the number of blocks")?
    } else {
        1
    };
    if (nb as u64).saturating_mul(layout.dim as u64) > vals.len() {
        let line = vals.get(0).map_or(1, |t| t.line);
        return Err((
            0,
            too_large(Location::Line(line), "number of blocks", nb as u64),
        ));
    }
    let mut dims = Vec::new();
    for b in 0..nb {
        let mut d = [1usize; 3];
        for (k, slot) in d.iter_mut().take(layout.dim).enumerate() {
            let name = ["ni", "nj", "nk"].get(k).copied().unwrap_or("n");
            *slot = value_positive(vals, i, &format!("{name} of block {}", b + 1))?;
            i += 1;
        }
        dims.push(d);
    }
    let per = (layout.dim + usize::from(layout.iblank)) as u64;
    let mut need = 0u64;
    for d in &dims {
        need = block_points(*d)
            .and_then(|n| n.checked_mul(per))
            .and_then(|n| n.checked_add(need))
            .unwrap_or(u64::MAX);
    }
    let have = vals.len() - i;
    if need != have {
        let (line, found) = if have < need {
            (vals.last_line(), format!("{have} (the file ends early)"))
        } else {
            let extra = vals.get(i + need).map_or(vals.last_line(), |t| t.line);
            (extra, format!("{have} (extra values start here)"))
        };
        return Err((
            i + need.min(have),
            FormatError::new(
                Location::Line(line),
                FormatErrorKind::Expected {
                    expected: format!("{need} values after the dimensions of {nb} block(s)"),
                    found,
                },
            ),
        ));
    }
    Ok(dims)
}

/// The refusal of a null value (`,,` or `r*`) where a number is needed.
fn null_value(t: &Item<'_>, what: &str) -> FormatError {
    FormatError::expected_at_line(
        t.line,
        format!("{what} (a null value leaves it undefined)"),
        t.token,
    )
}

fn parse_ascii_real(t: &Item<'_>, what: &dyn Fn() -> String) -> Result<f64, FormatError> {
    let Some(text) = t.value else {
        return Err(null_value(t, &what()));
    };
    match parse_real(text) {
        Some(v) if v.is_finite() => Ok(v),
        Some(_) => Err(FormatError::new(
            Location::Line(t.line),
            FormatErrorKind::NotFinite {
                what: what(),
                found: show(t.token),
            },
        )),
        None => Err(FormatError::expected_at_line(
            t.line,
            format!("{} (a number)", what()),
            t.token,
        )),
    }
}

fn parse_ascii_iblank(t: &Item<'_>, p: usize, b: usize) -> Result<i32, FormatError> {
    let what = format!("iblank of point {p} of block {} (an integer)", b + 1);
    let Some(text) = t.value else {
        return Err(null_value(t, &what));
    };
    let v = parse_int(text)
        .and_then(|v| i32::try_from(v).ok())
        .ok_or_else(|| FormatError::expected_at_line(t.line, what, t.token))?;
    check_iblank(v, p, b, Location::Line(t.line))?;
    Ok(v)
}

fn ascii_read(
    vals: &Values<'_>,
    layout: &Plot3dLayout,
    dims: &Dims,
) -> Result<Plot3dGrid, FormatError> {
    let start = (usize::from(layout.multi_block) + dims.len() * layout.dim) as u64;
    let mut it = vals.from(start);
    let eof = |what: &str| FormatError::eof_at_line(vals.last_line(), what.to_string());
    let mut blocks = Vec::new();
    for (b, d) in dims.iter().enumerate() {
        let n = d[0] * d[1] * d[2];
        let mut points = vec![[0.0f64; 3]; n];
        for k in 0..layout.dim {
            let axis = ["x", "y", "z"].get(k).copied().unwrap_or("?");
            for (p, pt) in points.iter_mut().enumerate() {
                let t = it.next().ok_or_else(|| eof("a coordinate"))?;
                let v = parse_ascii_real(t, &|| format!("{axis} of point {p} of block {}", b + 1))?;
                if let Some(slot) = pt.get_mut(k) {
                    *slot = v;
                }
            }
        }
        let iblank = if layout.iblank {
            let mut ib = Vec::with_capacity(n);
            for p in 0..n {
                let t = it.next().ok_or_else(|| eof("an iblank value"))?;
                ib.push(parse_ascii_iblank(t, p, b)?);
            }
            Some(ib)
        } else {
            None
        };
        blocks.push(Plot3dBlock {
            dims: *d,
            points,
            iblank,
        });
    }
    Ok(Plot3dGrid {
        dim: layout.dim,
        blocks,
    })
}

// ---------------------------------------------------------------------------------- writer

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

fn check_grid(grid: &Plot3dGrid, layout: &Plot3dLayout) -> io::Result<()> {
    if layout.dim != 2 && layout.dim != 3 {
        return Err(invalid(format!(
            "Plot3D dimension must be 2 or 3, not {}",
            layout.dim
        )));
    }
    if grid.blocks.is_empty() {
        return Err(invalid("a Plot3D grid needs at least one block".into()));
    }
    if grid.blocks.len() > 1 && !layout.multi_block {
        return Err(invalid(format!(
            "{} blocks need the multi-block header",
            grid.blocks.len()
        )));
    }
    if i32::try_from(grid.blocks.len()).is_err() {
        return Err(invalid("too many blocks".into()));
    }
    for (b, blk) in grid.blocks.iter().enumerate() {
        if blk
            .dims
            .iter()
            .any(|&d| d == 0 || i32::try_from(d).is_err())
        {
            return Err(invalid(format!(
                "block {} has invalid dimensions {:?}",
                b + 1,
                blk.dims
            )));
        }
        if layout.dim == 2 && blk.dims[2] != 1 {
            return Err(invalid(format!(
                "block {} is 3D (nk = {}) but the layout is 2D",
                b + 1,
                blk.dims[2]
            )));
        }
        let n = block_points(blk.dims).unwrap_or(u64::MAX);
        if blk.points.len() as u64 != n {
            return Err(invalid(format!(
                "block {} has {} points, its dimensions say {n}",
                b + 1,
                blk.points.len()
            )));
        }
        if let Some(ib) = &blk.iblank {
            if ib.len() as u64 != n {
                return Err(invalid(format!(
                    "block {} iblank has the wrong length",
                    b + 1
                )));
            }
        }
        if let Encoding::Binary {
            precision,
            records: true,
            ..
        } = layout.encoding
        {
            if block_bytes(layout, n, precision).is_none_or(|l| l > i32::MAX as u64) {
                return Err(invalid(format!(
                    "block {} is too large for a Fortran record",
                    b + 1
                )));
            }
        }
    }
    Ok(())
}

/// Writes `grid` with `layout`. Blocks without iblank get iblank = 1 when the layout has
/// iblank; iblank is dropped when it does not. ASCII reals use Rust's shortest round-trip form.
pub fn write_plot3d<W: Write>(
    grid: &Plot3dGrid,
    layout: &Plot3dLayout,
    w: &mut W,
) -> io::Result<()> {
    check_grid(grid, layout)?;
    let mut w = io::BufWriter::new(w);
    match layout.encoding {
        Encoding::Ascii => write_ascii(grid, layout, &mut w)?,
        Encoding::Binary {
            endian,
            precision,
            records,
        } => write_binary(grid, layout, (endian, precision, records), &mut w)?,
    }
    w.flush()
}

/// A block's IBLANK value at point `i` (1 when the block has none).
fn iblank_at(blk: &Plot3dBlock, i: usize) -> i32 {
    blk.iblank
        .as_ref()
        .and_then(|ib| ib.get(i).copied())
        .unwrap_or(1)
}

/// Plot3D text: dimensions, then each block's coordinates (five to a line) and IBLANK (ten).
fn write_ascii<W: Write>(grid: &Plot3dGrid, layout: &Plot3dLayout, w: &mut W) -> io::Result<()> {
    if layout.multi_block {
        writeln!(w, "{}", grid.blocks.len())?;
    }
    for blk in &grid.blocks {
        let d: Vec<String> = (blk.dims.iter().take(layout.dim))
            .map(|d| d.to_string())
            .collect();
        writeln!(w, "{}", d.join(" "))?;
    }
    for blk in &grid.blocks {
        for k in 0..layout.dim {
            for (i, p) in blk.points.iter().enumerate() {
                let v = p.get(k).copied().unwrap_or(0.0);
                let last = i % 5 == 4 || i + 1 == blk.points.len();
                write!(w, "{v:e}{}", if last { "\n" } else { " " })?;
            }
        }
        if layout.iblank {
            let n = blk.points.len();
            for i in 0..n {
                let last = i % 10 == 9 || i + 1 == n;
                write!(w, "{}{}", iblank_at(blk, i), if last { "\n" } else { " " })?;
            }
        }
    }
    Ok(())
}

/// Plot3D binary in the given byte order and precision, with Fortran record markers when
/// `records`.
fn write_binary<W: Write>(
    grid: &Plot3dGrid,
    layout: &Plot3dLayout,
    (endian, precision, records): (Endian, Precision, bool),
    w: &mut W,
) -> io::Result<()> {
    let int = |v: i32| match endian {
        Endian::Little => v.to_le_bytes(),
        Endian::Big => v.to_be_bytes(),
    };
    let marker = |w: &mut W, len: u64| -> io::Result<()> {
        if records {
            w.write_all(&int(len as i32))?;
        }
        Ok(())
    };
    if layout.multi_block {
        marker(w, 4)?;
        w.write_all(&int(grid.blocks.len() as i32))?;
        marker(w, 4)?;
    }
    let dims_len = (grid.blocks.len() * layout.dim * 4) as u64;
    marker(w, dims_len)?;
    for blk in &grid.blocks {
        for d in blk.dims.iter().take(layout.dim) {
            w.write_all(&int(*d as i32))?;
        }
    }
    marker(w, dims_len)?;
    for blk in &grid.blocks {
        let n = blk.points.len() as u64;
        let len = block_bytes(layout, n, precision).unwrap_or(0);
        marker(w, len)?;
        for k in 0..layout.dim {
            for p in &blk.points {
                let v = p.get(k).copied().unwrap_or(0.0);
                match (precision, endian) {
                    (Precision::Single, Endian::Little) => {
                        w.write_all(&(v as f32).to_le_bytes())?
                    }
                    (Precision::Single, Endian::Big) => w.write_all(&(v as f32).to_be_bytes())?,
                    (Precision::Double, Endian::Little) => w.write_all(&v.to_le_bytes())?,
                    (Precision::Double, Endian::Big) => w.write_all(&v.to_be_bytes())?,
                }
            }
        }
        if layout.iblank {
            for i in 0..blk.points.len() {
                w.write_all(&int(iblank_at(blk, i)))?;
            }
        }
        marker(w, len)?;
    }
    Ok(())
}
