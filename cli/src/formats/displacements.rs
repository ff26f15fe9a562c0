//! Node tables for `deform move`: prescribed displacements (`--displacements`: `node dx dy
//! [dz]`) and SU2_DEF's surface-position files (`--surface-positions`, SU2's `SURFACE_FILE`:
//! `GlobalIndex x y [z]`, the new absolute positions). One line per node, 0-based node index,
//! blank lines and `%` or `#` comments ignored, each node at most once.

use super::error::{show, FormatError, FormatErrorKind, Location};

/// Parses a displacement file for a mesh of dimension `dim` (2 or 3). Returns `(node, d)` pairs
/// in file order, `d[2] = 0` in 2D. Each node may appear once.
pub fn parse_displacements(bytes: &[u8], dim: usize) -> Result<Vec<(u32, [f64; 3])>, FormatError> {
    parse_node_table(bytes, dim, "displacement")
}

/// Parses an SU2 surface-position file (`GlobalIndex x y [z]`: new absolute coordinates) for
/// a mesh of dimension `dim`. Returns `(node, position)` pairs in file order, `z = 0` in 2D.
pub fn parse_surface_positions(
    bytes: &[u8],
    dim: usize,
) -> Result<Vec<(u32, [f64; 3])>, FormatError> {
    parse_node_table(bytes, dim, "position")
}

fn parse_node_table(
    bytes: &[u8],
    dim: usize,
    value: &str,
) -> Result<Vec<(u32, [f64; 3])>, FormatError> {
    let mut out: Vec<(u32, [f64; 3])> = Vec::new();
    let mut seen = std::collections::BTreeMap::new();
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
        if toks.len() != dim + 1 {
            return Err(FormatError::expected_at_line(
                line,
                format!("`node d1 … d{dim}` ({} columns)", dim + 1),
                content,
            ));
        }
        let node = toks
            .first()
            .and_then(|t| std::str::from_utf8(t).ok())
            .and_then(|s| s.parse::<u32>().ok())
            .ok_or_else(|| {
                FormatError::expected_at_line(
                    line,
                    "a node index (non-negative integer)",
                    toks.first().copied().unwrap_or(&[]),
                )
            })?;
        let mut d = [0.0; 3];
        for (k, slot) in d.iter_mut().take(dim).enumerate() {
            let tok = toks.get(k + 1).copied().unwrap_or(&[]);
            let v = std::str::from_utf8(tok)
                .ok()
                .and_then(|s| s.parse::<f64>().ok())
                .ok_or_else(|| {
                    FormatError::expected_at_line(line, format!("a {value} (a number)"), tok)
                })?;
            if !v.is_finite() {
                return Err(FormatError::new(
                    Location::Line(line),
                    FormatErrorKind::NotFinite {
                        what: format!("{value} of node {node}"),
                        found: show(tok),
                    },
                ));
            }
            *slot = v;
        }
        if let Some(first) = seen.insert(node, line) {
            return Err(FormatError::new(
                Location::Line(line),
                FormatErrorKind::Duplicate {
                    keyword: format!("node {node} (first at line {first})"),
                },
            ));
        }
        out.push((node, d));
    }
    Ok(out)
}
