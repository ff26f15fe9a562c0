//! Mesh and grid files: the kind of a file (by name and by content, `--format`), reading SU2
//! and Plot3D with the command line's layout overrides, writing meshes, meshgen meshes as SU2,
//! and the marker and cell-dimension lookups the commands share.

use std::io;
use std::path::{Path, PathBuf};

use crate::args::{EncodingArg, EndianArg, InputFormat, LayoutArgs, PrecisionArg, YesNo};
use crate::formats::plot3d::{
    parse_plot3d, Endian, Plot3dBlock, Plot3dGrid, Plot3dLayout, Plot3dOptions, Precision,
};
use crate::formats::su2::{parse_su2, write_su2, Su2Marker, Su2Mesh};
use crate::formats::vtk::{write_vtu, VtkEncoding};
use crate::formats::CellList;
use crate::output::Staged;

use crate::error::CliError;

/// The kinds of file the tool knows, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// `.su2`
    Su2,
    /// `.x`, `.xyz`, `.p3d`, `.g`, `.grd`, `.xy`, `.q`-less Plot3D grids.
    Plot3d,
    /// `.vtu`
    Vtu,
    /// `.vts`
    Vts,
}

/// The kind of `path` from its extension.
pub fn file_kind(path: &Path) -> Option<FileKind> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    Some(match ext.as_str() {
        "su2" => FileKind::Su2,
        "x" | "xyz" | "p3d" | "g" | "grd" | "xy" | "p2d" => FileKind::Plot3d,
        "vtu" => FileKind::Vtu,
        "vts" => FileKind::Vts,
        _ => return None,
    })
}

pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, CliError> {
    crate::guard::read_file(path)
}

/// Reads an SU2 mesh file.
pub fn read_su2(path: &Path) -> Result<Su2Mesh, CliError> {
    let bytes = read_bytes(path)?;
    parse_su2(&bytes).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a Plot3D grid file.
pub fn read_plot3d(
    path: &Path,
    opts: &Plot3dOptions,
) -> Result<(Plot3dGrid, Plot3dLayout), CliError> {
    let bytes = read_bytes(path)?;
    parse_plot3d(&bytes, opts).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })
}

pub(crate) fn yes(v: Option<YesNo>) -> Option<bool> {
    v.map(|v| v == YesNo::Yes)
}

/// Layout overrides from the command line.
pub fn plot3d_options(a: &LayoutArgs) -> Plot3dOptions {
    Plot3dOptions {
        ascii: a.encoding.map(|e| e == EncodingArg::Ascii),
        dim: a.dim.map(usize::from),
        multi_block: yes(a.multi_block),
        iblank: yes(a.iblank),
        endian: a.endian.map(|e| match e {
            EndianArg::Little => Endian::Little,
            EndianArg::Big => Endian::Big,
        }),
        precision: a.precision.map(|p| match p {
            PrecisionArg::F32 => Precision::Single,
            PrecisionArg::F64 => Precision::Double,
        }),
        records: yes(a.records),
    }
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(io::Error) -> CliError + '_ {
    move |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    }
}

thread_local! {
    /// `--format` of the running command, for [`input_kind`] (set by [`force_format`]).
    static FORCED_FORMAT: std::cell::Cell<Option<InputFormat>> = const { std::cell::Cell::new(None) };
}

/// Sets `--format` for the running command (called once by [`crate::commands::run`]).
pub fn force_format(format: Option<InputFormat>) {
    FORCED_FORMAT.with(|f| f.set(format));
}

/// What the first 64 KiB of a file look like: SU2 (an `NDIME=` keyword line), VTK XML, or
/// neither. A UTF-8 byte-order mark and leading whitespace are skipped.
pub(crate) fn sniff(path: &Path) -> Result<Option<InputFormat>, CliError> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(64 * 1024).read_to_end(&mut head))
        .map_err(io_err(path))?;
    let text = head
        .strip_prefix(b"\xEF\xBB\xBF")
        .unwrap_or(&head)
        .trim_ascii_start();
    if text.starts_with(b"<?xml") || text.starts_with(b"<VTKFile") {
        return Ok(Some(InputFormat::Vtk));
    }
    let su2 = text.split(|&b| b == b'\n').any(|line| {
        let line = line
            .split(|&b| b == b'%')
            .next()
            .unwrap_or(&[])
            .trim_ascii();
        line.len() >= 6
            && line[..5].eq_ignore_ascii_case(b"NDIME")
            && line[5..].trim_ascii_start().starts_with(b"=")
    });
    Ok(su2.then_some(InputFormat::Su2))
}

/// The format of an input file: `--format` if given; else from its content (SU2 keywords,
/// VTK XML); else `.su2` by name (so a broken SU2 file gets the SU2 reader's message); else
/// Plot3D, whose reader detects the layout from the content.
pub(crate) fn input_kind(path: &Path) -> Result<FileKind, CliError> {
    let format = match FORCED_FORMAT.with(|f| f.get()) {
        Some(f) => f,
        None => match sniff(path)? {
            Some(f) => f,
            None if file_kind(path) == Some(FileKind::Su2) => InputFormat::Su2,
            None => InputFormat::Plot3d,
        },
    };
    match format {
        InputFormat::Su2 => Ok(FileKind::Su2),
        InputFormat::Plot3d => Ok(FileKind::Plot3d),
        InputFormat::Vtk => Err(CliError::NotAvailable {
            feature: "reading VTK files",
            needs: "an SU2 or Plot3D input (the tool writes .vtu/.vts for viewing; convert your mesh to SU2 or Plot3D first)",
        }),
    }
}

pub(crate) fn mesh_error(e: deform_meshgen::MeshError) -> CliError {
    CliError::Invalid(e.to_string())
}

/// Converts a meshgen 2D mesh into an SU2 mesh.
pub fn su2_from_mesh2(m: &deform_meshgen::Mesh2) -> Su2Mesh {
    su2_from_parts(
        2,
        m.points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
        (&m.offsets, &m.nodes, &m.kinds),
        &m.markers,
    )
}

/// Converts a meshgen 3D mesh into an SU2 mesh.
pub fn su2_from_mesh3(m: &deform_meshgen::Mesh3) -> Su2Mesh {
    su2_from_parts(
        3,
        m.points.clone(),
        (&m.offsets, &m.nodes, &m.kinds),
        &m.markers,
    )
}

pub(crate) fn su2_from_parts(
    dim: usize,
    points: Vec<[f64; 3]>,
    cells: (&[u32], &[u32], &[u8]),
    markers: &[deform_meshgen::Marker],
) -> Su2Mesh {
    let list = |o: &[u32], n: &[u32], k: &[u8]| CellList {
        offsets: o.to_vec(),
        nodes: n.to_vec(),
        kinds: k.to_vec(),
    };
    Su2Mesh {
        dim,
        points,
        elements: list(cells.0, cells.1, cells.2),
        markers: markers
            .iter()
            .map(|m| Su2Marker {
                name: m.name.clone(),
                elements: list(&m.offsets, &m.nodes, &m.kinds),
            })
            .collect(),
        passthrough: Vec::new(),
    }
}

pub(crate) fn write_mesh_file(
    staged: &mut Staged,
    path: &Path,
    mesh: &Su2Mesh,
) -> Result<(), CliError> {
    match file_kind(path) {
        Some(FileKind::Su2) => staged.write(path, |f| write_su2(mesh, f)),
        Some(FileKind::Vtu) => staged.write(path, |f| {
            write_vtu(
                f,
                &mesh.points,
                &mesh.elements,
                &[],
                &[],
                VtkEncoding::Base64,
            )
        }),
        _ => {
            return Err(CliError::Invalid(format!(
                "{}: expected a .su2 or .vtu output",
                path.display()
            )))
        }
    }
    .map_err(io_err(path))
}

/// Node indices of the named markers, sorted and unique.
pub fn marker_nodes(mesh: &Su2Mesh, names: &[String], path: &Path) -> Result<Vec<u32>, CliError> {
    let mut nodes = Vec::new();
    for name in names {
        let Some(m) = mesh.marker(name) else {
            let known: Vec<&str> = mesh.markers.iter().map(|m| m.name.as_str()).collect();
            return Err(CliError::Invalid(format!(
                "{}: marker {name:?} not found (markers: {})",
                path.display(),
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            )));
        };
        nodes.extend_from_slice(&m.elements.nodes);
    }
    nodes.sort_unstable();
    nodes.dedup();
    Ok(nodes)
}

/// Merges the elements of the named markers into one list.
pub(crate) fn marker_union(
    mesh: &Su2Mesh,
    names: &[String],
    path: &Path,
) -> Result<CellList, CliError> {
    let mut out = CellList::new();
    marker_nodes(mesh, names, path)?; // names exist
    for name in names {
        if let Some(m) = mesh.marker(name) {
            for (code, nodes) in m.elements.iter() {
                if let Some(kind) = deform_kernel::CellKind::from_vtk(code) {
                    out.push(kind, nodes);
                }
            }
        }
    }
    Ok(out)
}

/// The dimension a block's cells are measured in: 2 for a 2D grid and for a single k-plane
/// of a 3D grid whose `z` is constant (a 2D grid stored as 3D, as many codes write them),
/// else the grid's.
pub(crate) fn cell_dim(grid_dim: usize, blk: &Plot3dBlock) -> usize {
    let planar = blk.dims[2] == 1
        && blk
            .points
            .first()
            .is_some_and(|p0| blk.points.iter().all(|p| p[2] == p0[2]));
    if grid_dim == 3 && planar {
        2
    } else {
        grid_dim
    }
}

pub(crate) fn block_vts_path(out: &Path, b: usize, nblocks: usize) -> PathBuf {
    if nblocks == 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "grid".into());
    out.with_file_name(format!("{stem}_b{}.vts", b + 1))
}
