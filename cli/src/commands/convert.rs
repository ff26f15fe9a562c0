//! `deform convert`: SU2 ↔ VTK, Plot3D layouts and Plot3D → VTK structured.

use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::{ConvertArgs, EncodingArg, EndianArg, PrecisionArg};
use crate::formats::plot3d::{Encoding, Endian, Plot3dLayout, Precision};
use crate::formats::vtk::{write_vts, write_vtu, VtkEncoding};
use crate::output::Staged;

use crate::error::CliError;
use crate::files::{
    block_vts_path, check_su2_output, file_kind, input_kind, io_err, is_cgns_path, plot3d_options,
    read_plot3d, read_su2, write_grid, write_su2_like, yes, FileKind,
};
use crate::report::{seconds, Outcome};

#[derive(Serialize)]
pub(crate) struct ConvertReport {
    command: &'static str,
    input: String,
    outputs: Vec<String>,
    input_format: String,
    points: usize,
    cells: usize,
    blocks: usize,
    /// Cells rewritten in the SU2/VTK convention (`--reorient`).
    reoriented_cells: usize,
    seconds: f64,
}

pub(crate) fn convert(a: &ConvertArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let kin = input_kind(&a.input)?;
    // A Plot3D input may be written to any name that is not SU2 or VTK.
    let kout = match (kin, file_kind(&a.output)) {
        (FileKind::Plot3d, None) => Some(FileKind::Plot3d),
        (FileKind::Su2, None) if is_cgns_path(&a.output) => Some(FileKind::Su2),
        (_, k) => k,
    };
    let mut staged = Staged::new();
    let mut outputs = Vec::new();
    let report = match (kin, kout) {
        (FileKind::Su2, Some(k @ (FileKind::Su2 | FileKind::Vtu))) => {
            convert_su2(a, k, &mut staged, &mut outputs)?
        }
        (FileKind::Plot3d, Some(_)) if a.reorient => {
            return Err(CliError::Invalid(format!(
                "{}: --reorient applies to SU2 meshes (a structured block's cells all turn the way its i, j, k axes do)",
                a.input.display()
            )))
        }
        (FileKind::Plot3d, Some(k @ (FileKind::Plot3d | FileKind::Vts))) => {
            convert_plot3d(a, k, &mut staged, &mut outputs)?
        }
        _ => {
            return Err(CliError::Invalid(format!(
                "cannot convert {} to {}: SU2 converts to .su2 or .vtu, Plot3D to Plot3D or .vts",
                a.input.display(),
                a.output.display()
            )))
        }
    };
    staged.commit().map_err(io_err(&a.output))?;
    let report = ConvertReport {
        outputs,
        seconds: seconds(t0),
        ..report
    };
    let text = format!(
        "{} ({}): {} points, {} cells -> {}",
        report.input,
        report.input_format,
        report.points,
        report.cells,
        report.outputs.join(", ")
    );
    Ok(Outcome {
        json: serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
        text,
    })
}

/// The VTK encoding `--vtk-ascii` asks for.
fn encoding(a: &ConvertArgs) -> VtkEncoding {
    if a.vtk_ascii {
        VtkEncoding::Ascii
    } else {
        VtkEncoding::Base64
    }
}

/// An SU2 mesh (or CGNS file) to SU2/CGNS or `.vtu` (`k`), `--reorient` first.
fn convert_su2(
    a: &ConvertArgs,
    k: FileKind,
    staged: &mut Staged,
    outputs: &mut Vec<String>,
) -> Result<ConvertReport, CliError> {
    let mut m = read_su2(&a.input)?;
    check_su2_output(&a.input, &a.output)?;
    let reoriented = if a.reorient {
        reorient(&mut m).map_err(|e| e.in_file(&a.input))?
    } else {
        0
    };
    let enc = encoding(a);
    staged
        .write(&a.output, |f| {
            if k == FileKind::Su2 {
                write_su2_like(&a.input, &a.output, &m, f)
            } else {
                write_vtu(f, &m.points, &m.elements, &[], &[], enc)
            }
        })
        .map_err(io_err(&a.output))?;
    outputs.push(a.output.display().to_string());
    Ok(ConvertReport {
        command: "convert",
        input: a.input.display().to_string(),
        outputs: Vec::new(),
        input_format: format!("SU2 {}D, {} markers", m.dim, m.markers.len()),
        points: m.points.len(),
        cells: m.elements.len(),
        blocks: 0,
        reoriented_cells: reoriented,
        seconds: 0.0,
    })
}

/// A Plot3D grid to Plot3D (in `--layout`'s output options) or one `.vts` per block (`k`).
fn convert_plot3d(
    a: &ConvertArgs,
    k: FileKind,
    staged: &mut Staged,
    outputs: &mut Vec<String>,
) -> Result<ConvertReport, CliError> {
    let (g, layout) = read_plot3d(&a.input, &plot3d_options(&a.layout))?;
    if k == FileKind::Plot3d {
        let out_layout = output_layout(&layout, a);
        staged
            .write(&a.output, |f| {
                write_grid(&a.input, &a.output, &g, &out_layout, f)
            })
            .map_err(io_err(&a.output))?;
        outputs.push(a.output.display().to_string());
    } else {
        let enc = encoding(a);
        for (b, blk) in g.blocks.iter().enumerate() {
            let p = block_vts_path(&a.output, b, g.blocks.len());
            staged
                .write(&p, |f| write_vts(f, blk.dims, &blk.points, &[], &[], enc))
                .map_err(io_err(&p))?;
            outputs.push(p.display().to_string());
        }
    }
    let cells_of = |d: &[usize; 3]| {
        d.iter()
            .map(|&d| d.saturating_sub(1).max(1))
            .product::<usize>()
    };
    Ok(ConvertReport {
        command: "convert",
        input: a.input.display().to_string(),
        outputs: Vec::new(),
        input_format: format!("Plot3D {layout}"),
        points: g.blocks.iter().map(|b| b.points.len()).sum(),
        cells: g.blocks.iter().map(|b| cells_of(&b.dims)).sum(),
        blocks: g.blocks.len(),
        reoriented_cells: 0,
        seconds: 0.0,
    })
}

/// Rewrites the valid cells listed clockwise (2D) or mirrored (3D) in the SU2/VTK convention,
/// in place; returns how many. Folded cells are left as they are (no order makes them valid).
fn reorient(m: &mut crate::formats::su2::Su2Mesh) -> Result<usize, CliError> {
    let reversed = crate::engine::reversed_cells(m.dim, &m.elements, &m.points)?;
    let offsets = m.elements.offsets.clone();
    for (c, _) in reversed.iter().enumerate().filter(|(_, &r)| r) {
        let kind = m.elements.kinds[c];
        let (lo, hi) = (offsets[c] as usize, offsets[c + 1] as usize);
        crate::validity::reverse_cell(kind, &mut m.elements.nodes[lo..hi]);
    }
    Ok(reversed.iter().filter(|&&r| r).count())
}

pub(crate) fn output_layout(input: &Plot3dLayout, a: &ConvertArgs) -> Plot3dLayout {
    let (endian, precision, records) = match input.encoding {
        Encoding::Binary {
            endian,
            precision,
            records,
        } => (endian, precision, records),
        Encoding::Ascii => (Endian::Little, Precision::Double, true),
    };
    let endian = match a.out_endian {
        Some(EndianArg::Little) => Endian::Little,
        Some(EndianArg::Big) => Endian::Big,
        None => endian,
    };
    let precision = match a.out_precision {
        Some(PrecisionArg::F32) => Precision::Single,
        Some(PrecisionArg::F64) => Precision::Double,
        None => precision,
    };
    let records = yes(a.out_records).unwrap_or(records);
    let ascii = match a.out_encoding {
        Some(e) => e == EncodingArg::Ascii,
        None => input.encoding == Encoding::Ascii,
    };
    Plot3dLayout {
        encoding: if ascii {
            Encoding::Ascii
        } else {
            Encoding::Binary {
                endian,
                precision,
                records,
            }
        },
        ..*input
    }
}
