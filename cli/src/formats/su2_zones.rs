//! Multi-zone SU2 files: `NZONE= N` (with an optional global `NDIME=` and comments), then N
//! zones, each an `IZONE= k` line followed by a whole SU2 mesh (`NDIME=`, `NELEM=`, `NPOIN=`,
//! `NMARK=`, pass-through sections), k = 1…N in order, as SU2 writes them for multi-physics and
//! sliding-interface cases.
//!
//! Every zone is read; each keeps its bytes, so that [`write_su2_zones`] writes the zones that
//! did not change byte for byte and only the ones given new meshes anew. Marker names are per
//! zone: two zones may both have a `wall`.

use std::io::{self, Write};
use std::ops::Range;

use super::error::{FormatError, FormatErrorKind, Location};
use super::su2::{key_value, parse_count, parse_su2, write_su2, Lines, Su2Mesh};

/// One zone: its number, its mesh, and where it is in the file.
#[derive(Clone, Debug, PartialEq)]
pub struct Su2Zone {
    /// `IZONE=` (1-based).
    pub number: usize,
    /// The zone's mesh (marker names as in the file).
    pub mesh: Su2Mesh,
    /// The zone's bytes: its `IZONE=` line up to the next zone's.
    pub bytes: Range<usize>,
    /// Its `IZONE=` line, line end included.
    pub izone_line: Range<usize>,
}

/// A multi-zone SU2 file.
#[derive(Clone, Debug, PartialEq)]
pub struct Su2Zones {
    /// Everything before the first `IZONE=` line (`NZONE=`, a global `NDIME=`, comments).
    pub header: Range<usize>,
    /// The zones, in file order (zone k at index k − 1).
    pub zones: Vec<Su2Zone>,
}

/// Moves a zone-relative line number in `e` to the file's numbering.
fn shift(mut e: FormatError, lines_before: usize) -> FormatError {
    if let Location::Line(n) = e.location {
        e.location = Location::Line(n + lines_before);
    }
    e
}

/// The `NZONE=`/`IZONE=` keyword lines: (line, start byte, end byte, key, count).
type ZoneLine = (usize, usize, usize, bool, usize);

fn zone_lines(bytes: &[u8]) -> Result<Vec<ZoneLine>, FormatError> {
    // Every NZONE= or IZONE= line holds a `z` or `Z`; a plain mesh (numbers, element and
    // marker lines) usually holds none, and one pass over the bytes tells (far cheaper than
    // splitting the lines).
    // (In chunks without an early exit inside, so the test vectorises.)
    let has_z = |c: &[u8]| c.iter().fold(false, |z, &b| z | (b | 0x20 == b'z'));
    if !bytes.chunks(256).any(has_z) {
        return Ok(Vec::new());
    }
    let mut lines = Lines::new(bytes);
    let mut out = Vec::new();
    while let Some((line, content)) = lines.next_content() {
        let Some((key, value)) = key_value(content) else {
            continue;
        };
        let nzone = key.eq_ignore_ascii_case(b"NZONE");
        if nzone || key.eq_ignore_ascii_case(b"IZONE") {
            let n = parse_count(line, value, if nzone { "NZONE" } else { "IZONE" })?;
            out.push((line, lines.start, lines.pos.min(bytes.len()), nzone, n));
        }
    }
    Ok(out)
}

/// Reads a multi-zone file. `Ok(None)` when the file has no `NZONE=` or `NZONE= 1` (a plain
/// mesh: read it with [`parse_su2`]). Errors name the file's line.
pub fn parse_su2_zones(bytes: &[u8]) -> Result<Option<Su2Zones>, FormatError> {
    let marks = zone_lines(bytes)?;
    let Some(&(nline, _, _, true, nzone)) = marks.first() else {
        if let Some(&(line, ..)) = marks.iter().find(|m| m.3) {
            return Err(zone_error(line, "NZONE= before the first IZONE=", "NZONE="));
        }
        return Ok(None);
    };
    if nzone <= 1 {
        return Ok(None);
    }
    let izones = marks.get(1..).unwrap_or(&[]);
    let header_end = izones.first().map_or(bytes.len(), |m| m.1);
    check_header(bytes.get(..header_end).unwrap_or(&[]))?;
    let mut zones = Vec::new();
    for (k, &(line, start, end, is_nzone, number)) in izones.iter().enumerate() {
        if is_nzone || number != k + 1 {
            let found = if is_nzone {
                "NZONE= again".to_string()
            } else {
                format!("IZONE= {number}")
            };
            return Err(zone_error(
                line,
                &format!("IZONE= {} (zones in order)", k + 1),
                &found,
            ));
        }
        let next = izones.get(k + 1).map_or(bytes.len(), |m| m.1);
        let body = bytes.get(end..next).unwrap_or(&[]);
        let mesh = parse_su2(body).map_err(|e| shift(e, line))?;
        zones.push(Su2Zone {
            number,
            mesh,
            bytes: start..next,
            izone_line: start..end,
        });
    }
    if zones.len() != nzone {
        return Err(FormatError::new(
            Location::Line(nline),
            FormatErrorKind::Expected {
                expected: format!("{nzone} zones (NZONE= {nzone})"),
                found: format!("{} IZONE= sections", zones.len()),
            },
        ));
    }
    Ok(Some(Su2Zones {
        header: 0..header_end,
        zones,
    }))
}

fn zone_error(line: usize, expected: &str, found: &str) -> FormatError {
    FormatError::expected_at_line(line, expected, found.as_bytes())
}

/// Before the first `IZONE=`: `NZONE=`, a global `NDIME=` and comments only.
fn check_header(header: &[u8]) -> Result<(), FormatError> {
    let mut lines = Lines::new(header);
    while let Some((line, content)) = lines.next_content() {
        let allowed = key_value(content).is_some_and(|(k, _)| {
            k.eq_ignore_ascii_case(b"NDIME") || k.eq_ignore_ascii_case(b"NZONE")
        });
        if !allowed {
            return Err(zone_error(
                line,
                "IZONE= 1 (the first zone) after NZONE=",
                &String::from_utf8_lossy(content),
            ));
        }
    }
    Ok(())
}

impl Su2Zones {
    /// All zones as one mesh (points and cells one zone after the other; markers named
    /// `k:NAME`), for reports and pictures of the whole file. `None` when the zones differ in
    /// dimension.
    pub fn merged(&self) -> Option<Su2Mesh> {
        let dim = self.zones.first()?.mesh.dim;
        let mut out = Su2Mesh {
            dim,
            points: Vec::new(),
            elements: super::CellList::new(),
            markers: Vec::new(),
            passthrough: Vec::new(),
            text: Default::default(),
        };
        for z in &self.zones {
            if z.mesh.dim != dim {
                return None;
            }
            let base = u32::try_from(out.points.len()).ok()?;
            for (code, nodes) in z.mesh.elements.iter() {
                let shifted: Vec<u32> = nodes.iter().map(|n| n + base).collect();
                out.elements.push_code(code, &shifted).then_some(())?;
            }
            for m in &z.mesh.markers {
                let mut elements = super::CellList::new();
                for (code, nodes) in m.elements.iter() {
                    let shifted: Vec<u32> = nodes.iter().map(|n| n + base).collect();
                    elements.push_code(code, &shifted).then_some(())?;
                }
                out.markers.push(super::su2::Su2Marker {
                    name: format!("{}:{}", z.number, m.name),
                    elements,
                });
            }
            out.points.extend_from_slice(&z.mesh.points);
        }
        Some(out)
    }
}

/// Writes the file `bytes` (read as `zones`) with zone `number` replaced by `mesh` (its marker
/// names are written as the zone had them: a mesh's markers may carry the user's `k:NAME`
/// spelling). The header and the other zones are copied byte for byte.
pub fn write_su2_zones<W: Write>(
    bytes: &[u8],
    zones: &Su2Zones,
    number: usize,
    mesh: &Su2Mesh,
    w: &mut W,
) -> io::Result<()> {
    let invalid = |m: String| io::Error::new(io::ErrorKind::InvalidInput, m);
    let slice = |r: &Range<usize>| bytes.get(r.clone()).unwrap_or(&[]);
    let zone = zones
        .zones
        .iter()
        .find(|z| z.number == number)
        .ok_or_else(|| invalid(format!("no zone {number}")))?;
    if zone.mesh.markers.len() != mesh.markers.len() {
        return Err(invalid(format!("zone {number}: the markers changed")));
    }
    let mut renamed = mesh.clone();
    for (m, orig) in renamed.markers.iter_mut().zip(&zone.mesh.markers) {
        m.name.clone_from(&orig.name);
    }
    w.write_all(slice(&zones.header))?;
    for z in &zones.zones {
        if z.number == number {
            w.write_all(slice(&z.izone_line))?;
            if !slice(&z.izone_line).ends_with(b"\n") {
                w.write_all(b"\n")?;
            }
            write_su2(&renamed, w)?;
        } else {
            w.write_all(slice(&z.bytes))?;
        }
    }
    w.flush()
}

/// Writes every zone of `zones` anew (as [`write_su2`] writes a mesh) after the file's header
/// and each zone's `IZONE=` line, both byte for byte: `convert` of a multi-zone file.
pub fn write_su2_all_zones<W: Write>(bytes: &[u8], zones: &Su2Zones, w: &mut W) -> io::Result<()> {
    let slice = |r: &Range<usize>| bytes.get(r.clone()).unwrap_or(&[]);
    w.write_all(slice(&zones.header))?;
    for z in &zones.zones {
        w.write_all(slice(&z.izone_line))?;
        if !slice(&z.izone_line).ends_with(b"\n") {
            w.write_all(b"\n")?;
        }
        write_su2(&z.mesh, w)?;
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO: &str = "NZONE= 2\n% two zones\nIZONE= 1\nNDIME= 2\nNELEM= 1\n5 0 1 2\nNPOIN= 3\n0 0\n1 0\n0 1\nNMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 0 1\nIZONE= 2\nNDIME= 2\nNELEM= 1\n5 0 1 2\nNPOIN= 3\n5 0\n6 0\n5 1\nNMARK= 1\nMARKER_TAG= wall\nMARKER_ELEMS= 1\n3 1 2\n";

    #[test]
    fn zones_are_read_and_unchanged_zones_kept() {
        let z = parse_su2_zones(TWO.as_bytes()).unwrap().unwrap();
        assert_eq!(z.zones.len(), 2);
        assert_eq!(z.zones[1].mesh.points[0], [5.0, 0.0, 0.0]);
        let merged = z.merged().unwrap();
        assert_eq!(merged.points.len(), 6);
        assert_eq!(merged.markers[1].name, "2:wall");
        assert_eq!(merged.markers[1].elements.nodes, vec![4, 5]);
        let mut moved = z.zones[1].mesh.clone();
        moved.points[0][0] = 7.0;
        moved.markers[0].name = "2:wall".into();
        let mut out = Vec::new();
        write_su2_zones(TWO.as_bytes(), &z, 2, &moved, &mut out).unwrap();
        let split = TWO.find("IZONE= 2").unwrap();
        assert_eq!(
            &out[..split],
            &TWO.as_bytes()[..split],
            "zone 1 byte for byte"
        );
        let back = parse_su2_zones(&out).unwrap().unwrap();
        assert_eq!(back.zones[1].mesh.points[0], [7.0, 0.0, 0.0]);
        assert_eq!(back.zones[1].mesh.markers[0].name, "wall");
    }

    #[test]
    fn bad_zone_structure_names_the_line() {
        let cases = [
            (TWO.replace("IZONE= 2", "IZONE= 3"), 15),
            (TWO.replace("NZONE= 2", "NZONE= 3"), 1),
            (TWO.replace("% two zones", "NELEM= 0"), 2),
            (TWO.replace("5 0\n6 0", "5 0\n6 x"), 21),
        ];
        for (text, line) in cases {
            let e = parse_su2_zones(text.as_bytes()).unwrap_err();
            assert_eq!(e.location, Location::Line(line), "{e}");
        }
        assert_eq!(
            parse_su2_zones(b"NDIME= 2\nNELEM= 0\nNPOIN= 0\n").unwrap(),
            None
        );
    }

    /// Random edits of a two-zone file never panic the reader.
    #[test]
    fn random_edits_never_panic() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let alphabet = b"0123456789 =\nIZONENDIME%";
        for _ in 0..2000 {
            let mut b = TWO.as_bytes().to_vec();
            for _ in 0..1 + next() % 3 {
                if b.is_empty() {
                    break;
                }
                let i = (next() % b.len() as u64) as usize;
                let c = alphabet[(next() % alphabet.len() as u64) as usize];
                match next() % 3 {
                    0 => b[i] = c,
                    1 => b.insert(i, c),
                    _ => b.truncate(i),
                }
            }
            let _ = parse_su2_zones(&b);
        }
    }
}
