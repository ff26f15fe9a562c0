//! The input files of `deform adjoint` and `deform tangent`: a volume sensitivity (SU2's
//! adjoint restart CSV with `Sensitivity_x/_y/_z` columns, or plain `node dJ/dx dJ/dy
//! [dJ/dz]` rows) and a boundary perturbation (`node dx dy [dz]` rows).

use std::path::Path;

use crate::error::CliError;

/// An error naming the file and line.
fn bad(path: &Path, line: usize, why: impl std::fmt::Display) -> CliError {
    CliError::Invalid(format!("{}:{line}: {why}", path.display()))
}

/// The non-empty, non-comment lines with their 1-based numbers.
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('%') && !l.starts_with('#'))
}

/// The fields of a row: comma-separated (quotes trimmed) or whitespace-separated.
fn fields(l: &str) -> Vec<&str> {
    if l.contains(',') {
        l.split(',').map(|f| f.trim().trim_matches('"')).collect()
    } else {
        l.split_whitespace().collect()
    }
}

fn number(path: &Path, line: usize, f: Option<&&str>) -> Result<f64, CliError> {
    let s = f.ok_or_else(|| bad(path, line, "too few columns"))?;
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(bad(path, line, format!("{s:?} is not a finite number"))),
    }
}

fn node(path: &Path, line: usize, f: Option<&&str>, n: usize) -> Result<usize, CliError> {
    let s = f.ok_or_else(|| bad(path, line, "too few columns"))?;
    match s.parse::<f64>() {
        Ok(x) if x >= 0.0 && x.fract() == 0.0 && x < n as f64 => Ok(x as usize),
        _ => Err(bad(
            path,
            line,
            format!(
                "{s:?} is not a node of the mesh (0 to {})",
                n.saturating_sub(1)
            ),
        )),
    }
}

/// Column positions of a header row: `(node column, value columns)`.
fn header_columns(l: &str, dim: usize) -> Option<(Option<usize>, Vec<usize>)> {
    let f = fields(l);
    let at = |name: &str| f.iter().position(|c| c.eq_ignore_ascii_case(name));
    let cols: Option<Vec<usize>> = ["Sensitivity_x", "Sensitivity_y", "Sensitivity_z"][..dim]
        .iter()
        .map(|c| at(c))
        .collect();
    Some((at("PointID"), cols?))
}

/// `dJ/dx` at every one of the `n` nodes, each listed exactly once.
pub(super) fn parse_sensitivity(
    text: &str,
    n: usize,
    dim: usize,
    path: &Path,
) -> Result<Vec<[f64; 3]>, CliError> {
    let mut rows = lines(text).peekable();
    let Some(&(first_line, first)) = rows.peek() else {
        return Err(bad(path, 1, "no data"));
    };
    let header = first
        .chars()
        .any(|c| c.is_ascii_alphabetic() && c != 'e' && c != 'E');
    let (node_col, value_cols) = if header {
        rows.next();
        header_columns(first, dim).ok_or_else(|| {
            bad(
                path,
                first_line,
                format!(
                    "a header needs Sensitivity_x, Sensitivity_y{} columns",
                    if dim == 3 { ", Sensitivity_z" } else { "" }
                ),
            )
        })?
    } else {
        (Some(0), (1..=dim).collect())
    };
    let mut out = vec![[0.0; 3]; n];
    let mut seen = vec![false; n];
    for (k, (line, l)) in rows.enumerate() {
        let f = fields(l);
        let i = match node_col {
            Some(c) => node(path, line, f.get(c), n)?,
            None if k < n => k,
            None => {
                return Err(bad(
                    path,
                    line,
                    format!("more rows than the mesh's {n} nodes"),
                ))
            }
        };
        if std::mem::replace(&mut seen[i], true) {
            return Err(bad(path, line, format!("node {i} is listed twice")));
        }
        for (c, &col) in value_cols.iter().enumerate() {
            out[i][c] = number(path, line, f.get(col))?;
        }
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        return Err(CliError::Invalid(format!(
            "{}: node {i} has no sensitivity (every one of the mesh's {n} nodes must be listed)",
            path.display()
        )));
    }
    Ok(out)
}

/// The perturbation of the boundary nodes (`boundary` sorted), zero elsewhere; a node
/// listed twice or one that is not a boundary node (`on`: where they are, for the message)
/// is an error.
pub(super) fn parse_perturbation(
    text: &str,
    n: usize,
    dim: usize,
    (boundary, on): (&[u32], &str),
    path: &Path,
) -> Result<Vec<[f64; 3]>, CliError> {
    let mut out = vec![[0.0; 3]; n];
    let mut seen = vec![false; n];
    for (line, l) in lines(text) {
        let f = fields(l);
        let i = node(path, line, f.first(), n)?;
        if boundary.binary_search(&(i as u32)).is_err() {
            return Err(bad(
                path,
                line,
                format!("node {i} is not {on}: only boundary nodes are prescribed"),
            ));
        }
        if std::mem::replace(&mut seen[i], true) {
            return Err(bad(path, line, format!("node {i} is listed twice")));
        }
        for (c, o) in out[i].iter_mut().enumerate().take(dim) {
            *o = number(path, line, f.get(c + 1))?;
        }
    }
    Ok(out)
}
