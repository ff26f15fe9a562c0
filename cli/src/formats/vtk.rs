//! VTK XML output for ParaView: `.vtu` (unstructured, mixed cells) and `.vts` (structured),
//! with point data (for example displacement) and cell data (for example quality) fields, in
//! ASCII or inline base64 binary (`format="binary"`, `header_type="UInt64"`, little endian).

use std::io::{self, Write};

use super::base64;
use super::CellList;

/// ASCII or inline base64 binary data arrays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VtkEncoding {
    /// Text numbers (readable, larger).
    Ascii,
    /// Base64 of the raw little-endian bytes, each array preceded by its 64-bit byte count.
    Base64,
}

/// A named data field: `values.len()` must be `components` × the number of points (point
/// data) or cells (cell data).
#[derive(Clone, Copy, Debug)]
pub struct VtkField<'a> {
    /// Name shown in ParaView.
    pub name: &'a str,
    /// 1 for scalars, 3 for vectors.
    pub components: usize,
    /// Values, component fastest.
    pub values: &'a [f64],
}

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

fn escape_attr(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Values of one DataArray, as typed data.
enum Data<'a> {
    F64(&'a [f64]),
    F64Owned(Vec<f64>),
    I64(Vec<i64>),
    U8(&'a [u8]),
}

impl Data<'_> {
    fn type_name(&self) -> &'static str {
        match self {
            Data::F64(_) | Data::F64Owned(_) => "Float64",
            Data::I64(_) => "Int64",
            Data::U8(_) => "UInt8",
        }
    }
}

fn data_array<W: Write>(
    w: &mut W,
    name: &str,
    components: usize,
    data: Data<'_>,
    enc: VtkEncoding,
) -> io::Result<()> {
    let format = match enc {
        VtkEncoding::Ascii => "ascii",
        VtkEncoding::Base64 => "binary",
    };
    writeln!(
        w,
        "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"{}\">",
        data.type_name(),
        escape_attr(name),
        components,
        format
    )?;
    match enc {
        VtkEncoding::Ascii => {
            let mut line = String::new();
            let mut push = |item: String, i: usize, line: &mut String| -> io::Result<()> {
                line.push_str(&item);
                if i % 9 == 8 {
                    writeln!(w, "          {}", line.trim_end())?;
                    line.clear();
                } else {
                    line.push(' ');
                }
                Ok(())
            };
            match &data {
                Data::F64(v) => {
                    for (i, x) in v.iter().enumerate() {
                        push(format!("{x:e}"), i, &mut line)?;
                    }
                }
                Data::F64Owned(v) => {
                    for (i, x) in v.iter().enumerate() {
                        push(format!("{x:e}"), i, &mut line)?;
                    }
                }
                Data::I64(v) => {
                    for (i, x) in v.iter().enumerate() {
                        push(x.to_string(), i, &mut line)?;
                    }
                }
                Data::U8(v) => {
                    for (i, x) in v.iter().enumerate() {
                        push(x.to_string(), i, &mut line)?;
                    }
                }
            }
            if !line.is_empty() {
                writeln!(w, "          {}", line.trim_end())?;
            }
        }
        VtkEncoding::Base64 => {
            let mut raw = Vec::new();
            match &data {
                Data::F64(v) => v
                    .iter()
                    .for_each(|x| raw.extend_from_slice(&x.to_le_bytes())),
                Data::F64Owned(v) => v
                    .iter()
                    .for_each(|x| raw.extend_from_slice(&x.to_le_bytes())),
                Data::I64(v) => v
                    .iter()
                    .for_each(|x| raw.extend_from_slice(&x.to_le_bytes())),
                Data::U8(v) => raw.extend_from_slice(v),
            }
            let mut bytes = (raw.len() as u64).to_le_bytes().to_vec();
            bytes.extend_from_slice(&raw);
            writeln!(w, "          {}", base64::encode(&bytes))?;
        }
    }
    writeln!(w, "        </DataArray>")
}

fn check_fields(fields: &[VtkField<'_>], count: usize, what: &str) -> io::Result<()> {
    for f in fields {
        if f.components == 0 || f.values.len() != f.components.saturating_mul(count) {
            return Err(invalid(format!(
                "{what} field {:?} has {} values, expected {} × {count}",
                f.name,
                f.values.len(),
                f.components
            )));
        }
    }
    Ok(())
}

fn header<W: Write>(w: &mut W, kind: &str) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"{kind}\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">"
    )
}

fn fields_section<W: Write>(
    w: &mut W,
    tag: &str,
    fields: &[VtkField<'_>],
    enc: VtkEncoding,
) -> io::Result<()> {
    writeln!(w, "      <{tag}>")?;
    for f in fields {
        data_array(w, f.name, f.components, Data::F64(f.values), enc)?;
    }
    writeln!(w, "      </{tag}>")
}

fn points_section<W: Write>(w: &mut W, points: &[[f64; 3]], enc: VtkEncoding) -> io::Result<()> {
    writeln!(w, "      <Points>")?;
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    data_array(w, "Points", 3, Data::F64Owned(flat), enc)?;
    writeln!(w, "      </Points>")
}

/// VTK's wedge (13) and SU2's prism differ in orientation: a prism that SU2 (and the kernel)
/// calls positive has its base `0,1,2` turning *away* from the top `3,4,5`, while VTK's own
/// volume and quality code (vtkMeshQuality, vtkCellSizeFilter) calls such a wedge negative. The
/// `.vtu` writer therefore lists prism nodes as `0,2,1,3,5,4` (both triangles reversed, the
/// vertical edges kept), so ParaView sees positive prisms where `deform quality` does.
const VTK_PRISM_ORDER: [usize; 6] = [0, 2, 1, 3, 5, 4];

/// Connectivity in VTK's node order (prisms reordered, every other kind as stored).
fn vtk_connectivity(cells: &CellList) -> Vec<i64> {
    let mut conn = Vec::with_capacity(cells.nodes.len());
    for (c, &kind) in cells.kinds.iter().enumerate() {
        let range = cells.offsets.get(c).zip(cells.offsets.get(c + 1));
        let nodes = range
            .and_then(|(&a, &b)| cells.nodes.get(a as usize..b as usize))
            .unwrap_or(&[]);
        if kind == 13 && nodes.len() == 6 {
            conn.extend(VTK_PRISM_ORDER.iter().map(|&k| i64::from(nodes[k])));
        } else {
            conn.extend(nodes.iter().map(|&n| i64::from(n)));
        }
    }
    conn
}

/// Writes an unstructured grid (`.vtu`). Cell node indices must be `< points.len()`; prisms
/// are written in VTK's orientation (prism nodes reordered `0,2,1,3,5,4`).
pub fn write_vtu<W: Write>(
    w: &mut W,
    points: &[[f64; 3]],
    cells: &CellList,
    point_data: &[VtkField<'_>],
    cell_data: &[VtkField<'_>],
    enc: VtkEncoding,
) -> io::Result<()> {
    check_fields(point_data, points.len(), "point")?;
    check_fields(cell_data, cells.len(), "cell")?;
    if let Some(bad) = cells.nodes.iter().find(|&&n| n as usize >= points.len()) {
        return Err(invalid(format!("cell node {bad} is out of range")));
    }
    if cells.offsets.len() != cells.kinds.len() + 1 {
        return Err(invalid("cell offsets do not match the cell count".into()));
    }
    let mut w = io::BufWriter::new(w);
    header(&mut w, "UnstructuredGrid")?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        cells.len()
    )?;
    fields_section(&mut w, "PointData", point_data, enc)?;
    fields_section(&mut w, "CellData", cell_data, enc)?;
    points_section(&mut w, points, enc)?;
    writeln!(w, "      <Cells>")?;
    let conn = vtk_connectivity(cells);
    data_array(&mut w, "connectivity", 1, Data::I64(conn), enc)?;
    let offs: Vec<i64> = cells.offsets.iter().skip(1).map(|&n| n as i64).collect();
    data_array(&mut w, "offsets", 1, Data::I64(offs), enc)?;
    data_array(&mut w, "types", 1, Data::U8(&cells.kinds), enc)?;
    writeln!(w, "      </Cells>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}

/// Writes a structured grid block (`.vts`) with dimensions `[ni, nj, nk]` (points i fastest).
/// Cell data has `max(ni-1,1) × max(nj-1,1) × max(nk-1,1)` entries.
pub fn write_vts<W: Write>(
    w: &mut W,
    dims: [usize; 3],
    points: &[[f64; 3]],
    point_data: &[VtkField<'_>],
    cell_data: &[VtkField<'_>],
    enc: VtkEncoding,
) -> io::Result<()> {
    let n = dims
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .unwrap_or(usize::MAX);
    if dims.contains(&0) || n != points.len() {
        return Err(invalid(format!(
            "structured dimensions {dims:?} do not match {} points",
            points.len()
        )));
    }
    let ncells: usize = dims.iter().map(|&d| (d - 1).max(1)).product();
    check_fields(point_data, points.len(), "point")?;
    check_fields(cell_data, ncells, "cell")?;
    let extent = format!("0 {} 0 {} 0 {}", dims[0] - 1, dims[1] - 1, dims[2] - 1);
    let mut w = io::BufWriter::new(w);
    header(&mut w, "StructuredGrid")?;
    writeln!(w, "  <StructuredGrid WholeExtent=\"{extent}\">")?;
    writeln!(w, "    <Piece Extent=\"{extent}\">")?;
    fields_section(&mut w, "PointData", point_data, enc)?;
    fields_section(&mut w, "CellData", cell_data, enc)?;
    points_section(&mut w, points, enc)?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </StructuredGrid>")?;
    writeln!(w, "</VTKFile>")?;
    w.flush()
}
