//! Mesh and grid files: the kind of a file (by name and by content, `--format`), reading SU2
//! and Plot3D with the command line's layout overrides, writing meshes, meshgen meshes as SU2,
//! and the marker and cell-dimension lookups the commands share.

use std::io;
use std::path::{Path, PathBuf};

use crate::args::{EncodingArg, EndianArg, InputFormat, LayoutArgs, PrecisionArg, YesNo};
use crate::formats::motions::parse_motions;
use crate::formats::plot3d::{
    parse_plot3d, Endian, Plot3dBlock, Plot3dGrid, Plot3dLayout, Plot3dOptions, Precision,
};
use crate::formats::su2::{parse_su2, write_su2, Su2Marker, Su2Mesh};
use crate::formats::su2_zones::{parse_su2_zones, write_su2_all_zones, write_su2_zones, Su2Zones};
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

/// The HDF5 signature and the start of an ADF file: a CGNS file, whatever its name.
fn looks_cgns(head: &[u8]) -> bool {
    // ADF starts with the "what" string `@(#)`, in newer files with its high bits set.
    head.starts_with(b"\x89HDF\r\n\x1a\n") || head.get(4..24) == Some(b"ADF Database Version")
}

/// Whether `path` is a CGNS output (by its name).
pub(crate) fn is_cgns_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("cgns"))
}

/// Why this build cannot read or write CGNS, and how to get one that can.
#[cfg(not(feature = "cgns"))]
fn cgns_missing() -> CliError {
    CliError::NotAvailable {
        feature: "CGNS files",
        needs: "a build with the cgns feature: install libcgns-dev, then cargo build --release -p deform-cli --features cgns",
    }
}

/// A CGNS problem: valid CGNS that the tool does not support exits 3, anything else 1.
#[cfg(feature = "cgns")]
fn cgns_err(path: &Path) -> impl FnOnce(String) -> CliError + '_ {
    use crate::formats::{cgns::UNSUPPORTED, FormatError, FormatErrorKind, Location};
    move |m| match m.strip_prefix(UNSUPPORTED) {
        Some(what) => CliError::Read {
            path: path.to_path_buf(),
            source: FormatError::new(
                Location::File,
                FormatErrorKind::Unsupported { what: what.into() },
            ),
        },
        None => CliError::Invalid(format!("{}: {m}", path.display())),
    }
}

/// A CGNS file is read as SU2 (unstructured zone) or Plot3D (structured zones).
#[cfg(feature = "cgns")]
fn cgns_kind(path: &Path) -> Result<FileKind, CliError> {
    let bases = crate::formats::cgns::read(path).map_err(cgns_err(path))?;
    match crate::formats::cgns::is_structured(&bases).map_err(cgns_err(path))? {
        true => Ok(FileKind::Plot3d),
        false => Ok(FileKind::Su2),
    }
}

#[cfg(not(feature = "cgns"))]
fn cgns_kind(_: &Path) -> Result<FileKind, CliError> {
    Err(cgns_missing())
}

/// The CGNS file `path` if it is one: its bases.
#[cfg(feature = "cgns")]
fn cgns_input(path: &Path) -> Result<Option<Vec<deform_cgns::Base>>, CliError> {
    if sniff(path)? != Some(InputFormat::Cgns) {
        return Ok(None);
    }
    crate::formats::cgns::read(path)
        .map(Some)
        .map_err(cgns_err(path))
}

/// Writes CGNS through the library into `w`: a CGNS input copied with the new `coords`, else
/// the file `fresh` builds. The library writes a file, whose bytes are copied (the staged
/// output is an open file, the library wants a name).
#[cfg(feature = "cgns")]
fn write_cgns<W: io::Write>(
    input: &Path,
    out: &Path,
    coords: &[&[[f64; 3]]],
    fresh: impl FnOnce() -> Result<Vec<deform_cgns::Base>, String>,
    w: &mut W,
) -> io::Result<()> {
    use crate::formats::cgns;
    let tmp = std::env::temp_dir().join(format!(
        "deform-{}-{}.cgns",
        std::process::id(),
        out.file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    ));
    let written = match sniff(input) {
        Ok(Some(InputFormat::Cgns)) => cgns::rewrite_coords(input, &tmp, coords),
        _ => fresh().and_then(|bases| cgns::write(&tmp, &bases)),
    };
    let result = written
        .map_err(io::Error::other)
        .and_then(|()| std::fs::read(&tmp))
        .and_then(|bytes| w.write_all(&bytes));
    let _ = std::fs::remove_file(&tmp);
    result
}

/// Reads an SU2 mesh file. A multi-zone file is read whole, as one mesh of all its zones
/// (markers named `k:NAME`, [`Su2Zones::merged`]).
pub fn read_su2(path: &Path) -> Result<Su2Mesh, CliError> {
    #[cfg(feature = "cgns")]
    if let Some(bases) = cgns_input(path)? {
        return crate::formats::cgns::to_su2(&bases).map_err(cgns_err(path));
    }
    let bytes = read_bytes(path)?;
    let read_err = |source| CliError::Read {
        path: path.to_path_buf(),
        source,
    };
    match parse_su2_zones(&bytes).map_err(read_err)? {
        Some(zones) => zones.merged().ok_or(CliError::NotAvailable {
            feature: "multi-zone SU2 files whose zones differ in dimension",
            needs: "zones of one dimension (NDIME) for quality and convert",
        }),
        None => parse_su2(&bytes).map_err(read_err),
    }
}

/// Refuses (exit 3) to write a multi-zone SU2 file as CGNS: the tool reads one unstructured
/// zone per CGNS file, so the zones would not come back.
pub(crate) fn check_su2_output(input: &Path, output: &Path) -> Result<(), CliError> {
    if is_cgns_path(output) && sniff(input)? == Some(InputFormat::Su2) {
        let bytes = read_bytes(input)?;
        if matches!(parse_su2_zones(&bytes), Ok(Some(_))) {
            return Err(CliError::NotAvailable {
                feature: "a multi-zone SU2 file written as CGNS",
                needs: "one zone per CGNS file (convert to .su2 or .vtu instead)",
            });
        }
    }
    Ok(())
}

/// Writes `mesh` (read by [`read_su2`] from `input`) as SU2: a multi-zone input keeps its
/// zones, each written anew, instead of becoming one zone.
pub fn write_su2_like<W: io::Write>(
    input: &Path,
    output: &Path,
    mesh: &Su2Mesh,
    w: &mut W,
) -> io::Result<()> {
    if is_cgns_path(output) {
        return write_mesh_cgns(input, output, mesh, w);
    }
    let bytes = std::fs::read(input)?;
    match parse_su2_zones(&bytes) {
        Ok(Some(zones)) => write_su2_all_zones(&bytes, &zones, w),
        _ => write_su2(mesh, w),
    }
}

/// `mesh` as CGNS: the input's CGNS file with new coordinates, or a new file.
#[cfg(feature = "cgns")]
fn write_mesh_cgns<W: io::Write>(
    input: &Path,
    output: &Path,
    mesh: &Su2Mesh,
    w: &mut W,
) -> io::Result<()> {
    let fresh = || crate::formats::cgns::from_su2(mesh);
    write_cgns(input, output, &[&mesh.points], fresh, w)
}

#[cfg(not(feature = "cgns"))]
fn write_mesh_cgns<W: io::Write>(_: &Path, _: &Path, _: &Su2Mesh, _: &mut W) -> io::Result<()> {
    Err(io::Error::other(cgns_missing().to_string()))
}

/// Writes a Plot3D grid read from `input` to `output`: CGNS when `output` ends in `.cgns`
/// (the input's CGNS file with new coordinates, or a new file), else Plot3D in `layout`.
pub fn write_grid<W: io::Write>(
    input: &Path,
    output: &Path,
    grid: &Plot3dGrid,
    layout: &Plot3dLayout,
    w: &mut W,
) -> io::Result<()> {
    if !is_cgns_path(output) {
        return crate::formats::plot3d::write_plot3d(grid, layout, w);
    }
    #[cfg(feature = "cgns")]
    {
        let coords: Vec<&[[f64; 3]]> = grid.blocks.iter().map(|b| b.points.as_slice()).collect();
        let fresh = || Ok(crate::formats::cgns::from_plot3d(grid));
        write_cgns(input, output, &coords, fresh, w)
    }
    #[cfg(not(feature = "cgns"))]
    {
        let _ = input;
        Err(io::Error::other(cgns_missing().to_string()))
    }
}

/// A multi-zone SU2 file as read for `move`: its bytes, its zones, and the zone that moves.
pub struct ZonedSu2 {
    bytes: Vec<u8>,
    zones: Su2Zones,
    zone: usize,
}

/// Reads the SU2 file `path` for `move`: a plain mesh, or the one zone of a multi-zone file
/// that holds the named markers (`--marker`, `--slide`, the `--motions` file's). A name is
/// `NAME` (in exactly one zone) or `K:NAME` (zone K); the returned zone mesh carries the names
/// as the user spelled them, and [`write_su2_zone`] writes the file back with the other zones
/// byte for byte.
pub fn read_su2_zone(
    path: &Path,
    names: &[&[String]],
    motions: Option<&Path>,
) -> Result<(Su2Mesh, Option<ZonedSu2>), CliError> {
    if sniff(path)? == Some(InputFormat::Cgns) {
        return Ok((read_su2(path)?, None));
    }
    let bytes = read_bytes(path)?;
    let read_err = |p: &Path| {
        let p = p.to_path_buf();
        move |source| CliError::Read { path: p, source }
    };
    let Some(zones) = parse_su2_zones(&bytes).map_err(read_err(path))? else {
        return Ok((parse_su2(&bytes).map_err(read_err(path))?, None));
    };
    let mut all: Vec<String> = names.iter().flat_map(|n| n.iter().cloned()).collect();
    if let Some(m) = motions {
        let dim = zones.zones.first().map_or(2, |z| z.mesh.dim);
        let specs = parse_motions(&read_bytes(m)?, dim).map_err(read_err(m))?;
        all.extend(specs.into_iter().map(|s| s.marker));
    }
    let (zone, mesh) = resolve_zone(&zones, &all, path)?;
    Ok((mesh, Some(ZonedSu2 { bytes, zones, zone })))
}

/// The zone that holds every marker in `names`, and its mesh with the markers renamed to the
/// `K:NAME` spellings used.
fn resolve_zone(
    zones: &Su2Zones,
    names: &[String],
    path: &Path,
) -> Result<(usize, Su2Mesh), CliError> {
    let err = |m: String| CliError::Invalid(format!("{}: {m}", path.display()));
    let mut chosen: Vec<(usize, &str, &str)> = Vec::new();
    for name in names {
        let holders: Vec<usize> = zones
            .zones
            .iter()
            .filter(|z| z.mesh.marker(name).is_some())
            .map(|z| z.number)
            .collect();
        let explicit = name.split_once(':').and_then(|(k, m)| {
            let k: usize = k.trim().parse().ok()?;
            let z = zones.zones.iter().find(|z| z.number == k)?;
            z.mesh.marker(m).map(|_| (k, m))
        });
        match (holders.as_slice(), explicit) {
            ([k], None) => chosen.push((*k, name, name)),
            ([], Some((k, m))) => chosen.push((k, name, m)),
            ([], None) => {
                return Err(err(format!(
                    "marker {name:?} is in no zone ({})",
                    zone_markers(zones)
                )))
            }
            (many, _) => {
                let alts: Vec<String> = many.iter().map(|k| format!("{k}:{name}")).collect();
                return Err(err(format!(
                    "marker {name:?} is in zones {many:?}: name one zone ({})",
                    alts.join(" or ")
                )));
            }
        }
    }
    let Some(&(zone, ..)) = chosen.first() else {
        return Err(err(
            "a multi-zone file needs the markers that move (--marker or --motions)".into(),
        ));
    };
    if chosen.iter().any(|c| c.0 != zone) {
        return Err(CliError::NotAvailable {
            feature: "moving markers of several zones in one run",
            needs: "the markers of one zone per run: move one zone, then run deform move on the output for the next",
        });
    }
    let z = zones
        .zones
        .iter()
        .find(|z| z.number == zone)
        .ok_or_else(|| err(format!("no zone {zone}")))?;
    let mut mesh = z.mesh.clone();
    for (_, spelled, plain) in &chosen {
        if let Some(m) = mesh.markers.iter_mut().find(|m| m.name == *plain) {
            m.name = spelled.to_string();
        }
    }
    Ok((zone, mesh))
}

/// "zone 1: a, b; zone 2: c", for messages.
fn zone_markers(zones: &Su2Zones) -> String {
    let per: Vec<String> = zones
        .zones
        .iter()
        .map(|z| {
            let names: Vec<&str> = z.mesh.markers.iter().map(|m| m.name.as_str()).collect();
            format!("zone {}: {}", z.number, names.join(", "))
        })
        .collect();
    per.join("; ")
}

/// Writes the mesh read by [`read_su2_zone`], moved: a plain SU2 file, or the multi-zone file
/// with the moved zone replaced and the others byte for byte.
pub fn write_su2_zone<W: io::Write>(
    (input, output): (&Path, &Path),
    zoned: Option<&ZonedSu2>,
    mesh: &Su2Mesh,
    w: &mut W,
) -> io::Result<()> {
    match zoned {
        Some(_) if is_cgns_path(output) => Err(io::Error::other(
            "a multi-zone SU2 file is written as SU2 (not CGNS)",
        )),
        Some(z) => write_su2_zones(&z.bytes, &z.zones, z.zone, mesh, w),
        None if is_cgns_path(output) => write_mesh_cgns(input, output, mesh, w),
        None => write_su2(mesh, w),
    }
}

/// Reads a Plot3D grid file.
pub fn read_plot3d(
    path: &Path,
    opts: &Plot3dOptions,
) -> Result<(Plot3dGrid, Plot3dLayout), CliError> {
    #[cfg(feature = "cgns")]
    if let Some(bases) = cgns_input(path)? {
        let g = crate::formats::cgns::to_plot3d(&bases).map_err(cgns_err(path))?;
        let layout = Plot3dLayout {
            encoding: crate::formats::plot3d::Encoding::Binary {
                endian: Endian::Little,
                precision: Precision::Double,
                records: false,
            },
            dim: g.dim,
            multi_block: true,
            iblank: false,
        };
        return Ok((g, layout));
    }
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
    if looks_cgns(&head) {
        return Ok(Some(InputFormat::Cgns));
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
        InputFormat::Cgns => cgns_kind(path),
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
