//! The command implementations behind the `deform` binary. Each validates all of its inputs,
//! stages every output in a temporary file and renames them into place only on success.

use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::{
    BlockArgs, Cli, Command, ConvertArgs, Coords, Dims, Direction, EncodingArg, EndianArg, FaceArg,
    InputFormat, LayoutArgs, MeshCommand, Method, MoveArgs, NacaArgs, NacaKind, PrecisionArg,
    QualityArgs, SmoothArgs, Solver, YesNo,
};
use crate::engine::{run_move, Motion, MoveInput, MoveMethod, MoveSolver, QualitySummary};
use crate::formats::displacements::{parse_displacements, parse_surface_positions};
use crate::formats::plot3d::{
    parse_plot3d, write_plot3d, Encoding, Endian, Plot3dBlock, Plot3dGrid, Plot3dLayout,
    Plot3dOptions, Precision,
};
use crate::formats::su2::{parse_su2, write_su2, Su2Marker, Su2Mesh};
use crate::formats::vtk::{write_vts, write_vtu, VtkEncoding, VtkField};
use crate::formats::CellList;
use crate::output::Staged;
use crate::plot::{bounding_window, png, svg, zoom, Picture, Window};
use deform_meshgen::AirfoilGrid;

pub use crate::error::CliError;

/// What a successful command reports: a JSON value and the same for people.
#[derive(Debug)]
pub struct Outcome {
    /// The `--json` report.
    pub json: serde_json::Value,
    /// The human-readable report.
    pub text: String,
}

/// Runs the parsed command line.
pub fn run(cli: &Cli) -> Result<Outcome, CliError> {
    let quiet = cli.json;
    FORCED_FORMAT.with(|f| f.set(cli.format));
    let (inputs, outputs) = files_of(&cli.command);
    crate::guard::check_outputs(&inputs, &outputs)?;
    crate::guard::register_inputs(&inputs);
    match &cli.command {
        Command::Demo(a) => crate::demo::demo(a, quiet),
        Command::Mesh(MeshCommand::Naca(a)) => mesh_naca(a),
        Command::Mesh(MeshCommand::Block(a)) => mesh_block(a),
        Command::Move(a) => move_mesh(a, quiet),
        Command::Smooth(a) => smooth(a, quiet),
        Command::Quality(a) => quality(a),
        Command::Convert(a) => convert(a),
    }
}

/// The input and output files a command names on its command line.
fn files_of(command: &Command) -> (Vec<&Path>, Vec<&Path>) {
    fn opt(p: &Option<PathBuf>) -> Option<&Path> {
        p.as_deref()
    }
    match command {
        Command::Demo(_) => (vec![], vec![]),
        Command::Mesh(MeshCommand::Naca(a)) => (vec![], vec![&a.out]),
        Command::Mesh(MeshCommand::Block(a)) => (vec![], vec![&a.out]),
        Command::Move(a) => (
            [
                Some(a.mesh.as_path()),
                opt(&a.displacements),
                opt(&a.surface_positions),
            ]
            .into_iter()
            .flatten()
            .collect(),
            [Some(a.out.as_path()), opt(&a.vtk), opt(&a.plot)]
                .into_iter()
                .flatten()
                .collect(),
        ),
        Command::Smooth(a) => (vec![&a.grid], vec![&a.out]),
        Command::Quality(a) => (
            [Some(a.file.as_path()), opt(&a.reference)]
                .into_iter()
                .flatten()
                .collect(),
            opt(&a.vtk).into_iter().collect(),
        ),
        Command::Convert(a) => (vec![&a.input], vec![&a.output]),
    }
}

// ------------------------------------------------------------------------------ file helpers

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

fn read_bytes(path: &Path) -> Result<Vec<u8>, CliError> {
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

fn yes(v: Option<YesNo>) -> Option<bool> {
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

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> CliError + '_ {
    move |source| CliError::Io {
        path: path.to_path_buf(),
        source,
    }
}

thread_local! {
    /// `--format` of the running command, for [`input_kind`] (set by [`run`]).
    static FORCED_FORMAT: std::cell::Cell<Option<InputFormat>> = const { std::cell::Cell::new(None) };
}

/// What the first 64 KiB of a file look like: SU2 (an `NDIME=` keyword line), VTK XML, or
/// neither. A UTF-8 byte-order mark and leading whitespace are skipped.
fn sniff(path: &Path) -> Result<Option<InputFormat>, CliError> {
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
fn input_kind(path: &Path) -> Result<FileKind, CliError> {
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

fn seconds(t: Instant) -> f64 {
    t.elapsed().as_secs_f64()
}

// ---------------------------------------------------------------------------------- commands

fn mesh_error(e: deform_meshgen::MeshError) -> CliError {
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

fn su2_from_parts(
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

fn write_mesh_file(staged: &mut Staged, path: &Path, mesh: &Su2Mesh) -> Result<(), CliError> {
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

#[derive(Serialize)]
struct MeshReport {
    command: &'static str,
    output: String,
    kind: String,
    nodes: usize,
    cells: usize,
    markers: Vec<String>,
    seconds: f64,
}

fn mesh_naca(a: &NacaArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    if !matches!(file_kind(&a.out), Some(FileKind::Su2 | FileKind::Vtu)) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a .su2 (or .vtu) file",
            a.out.display()
        )));
    }
    let mut opts = match a.kind {
        NacaKind::Inviscid => AirfoilGrid::inviscid(),
        NacaKind::Viscous | NacaKind::Ogrid => AirfoilGrid::viscous(),
    };
    opts.code = a.code.clone();
    if let Some(v) = a.surface_points {
        opts.surface_points = v;
    }
    if let Some(v) = a.radial_points {
        opts.radial_points = v;
    }
    if let Some(v) = a.farfield {
        opts.farfield_chords = v;
    }
    if let Some(v) = a.first_layer {
        opts.first_layer = v;
    }
    if let Some(v) = a.boundary_layers {
        opts.boundary_layers = v;
    }
    let mesh = match a.kind {
        NacaKind::Inviscid => deform_meshgen::naca_triangulated(&opts),
        NacaKind::Viscous => deform_meshgen::naca_hybrid(&opts),
        NacaKind::Ogrid => deform_meshgen::naca_ogrid(&opts),
    }
    .map_err(mesh_error)?;
    let su2 = su2_from_mesh2(&mesh);
    let mut staged = Staged::new();
    write_mesh_file(&mut staged, &a.out, &su2)?;
    staged.commit().map_err(io_err(&a.out))?;
    let report = MeshReport {
        command: "mesh naca",
        output: a.out.display().to_string(),
        kind: format!("NACA {} {:?}", opts.code, a.kind).to_lowercase(),
        nodes: su2.points.len(),
        cells: su2.elements.len(),
        markers: su2.markers.iter().map(|m| m.name.clone()).collect(),
        seconds: seconds(t0),
    };
    Ok(mesh_outcome(&report))
}

fn mesh_outcome(report: &MeshReport) -> Outcome {
    Outcome {
        text: format!(
            "{}: {} with {} nodes, {} cells, markers {}",
            report.output,
            report.kind,
            report.nodes,
            report.cells,
            report.markers.join(", ")
        ),
        json: serde_json::to_value(report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
    }
}

fn mesh_block(a: &BlockArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let kind = file_kind(&a.out);
    if !matches!(kind, Some(FileKind::Plot3d | FileKind::Vts | FileKind::Su2)) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a Plot3D grid, .vts or .su2",
            a.out.display()
        )));
    }
    let Dims(d) = &a.dims;
    let dims = [
        d.first().copied().unwrap_or(2),
        d.get(1).copied().unwrap_or(2),
        d.get(2).copied().unwrap_or(1),
    ];
    let spec = deform_meshgen::BlockSpec {
        dims,
        lengths: [1.0; 3],
        ratios: [1.0; 3],
    };
    let (su2, dim) = if d.len() == 2 {
        let m = deform_meshgen::noisy_block2(&spec, a.noise, a.seed).map_err(mesh_error)?;
        (su2_from_mesh2(&m), 2)
    } else {
        let m = deform_meshgen::noisy_block3(&spec, a.noise, a.seed).map_err(mesh_error)?;
        (su2_from_mesh3(&m), 3)
    };
    let mut staged = Staged::new();
    match kind {
        Some(FileKind::Su2) => write_mesh_file(&mut staged, &a.out, &su2)?,
        Some(FileKind::Vts) => staged
            .write(&a.out, |f| {
                write_vts(f, dims, &su2.points, &[], &[], VtkEncoding::Base64)
            })
            .map_err(io_err(&a.out))?,
        _ => {
            let grid = Plot3dGrid {
                dim,
                blocks: vec![Plot3dBlock {
                    dims,
                    points: su2.points.clone(),
                    iblank: None,
                }],
            };
            let ext = a
                .out
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            let encoding = if ext == "xyz" || ext == "p3d" {
                Encoding::Ascii
            } else {
                Encoding::Binary {
                    endian: Endian::Little,
                    precision: Precision::Double,
                    records: true,
                }
            };
            let layout = Plot3dLayout {
                encoding,
                dim,
                multi_block: true,
                iblank: false,
            };
            staged
                .write(&a.out, |f| write_plot3d(&grid, &layout, f))
                .map_err(io_err(&a.out))?
        }
    }
    staged.commit().map_err(io_err(&a.out))?;
    let report = MeshReport {
        command: "mesh block",
        output: a.out.display().to_string(),
        kind: format!("{dim}D block {dims:?}, noise {}", a.noise),
        nodes: su2.points.len(),
        cells: su2.elements.len(),
        markers: su2.markers.iter().map(|m| m.name.clone()).collect(),
        seconds: seconds(t0),
    };
    Ok(mesh_outcome(&report))
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

fn move_mesh(a: &MoveArgs, quiet: bool) -> Result<Outcome, CliError> {
    let tfi = matches!(a.method, Method::Tfi | Method::TfiDisplacement);
    if input_kind(&a.mesh)? != FileKind::Su2 {
        if !tfi {
            return Err(CliError::NotAvailable {
                feature: "this method on Plot3D grids",
                needs: "--method tfi or tfi-displacement with --wall FACE (or an SU2 mesh)",
            });
        }
        return move_grid(a);
    }
    if tfi {
        return Err(CliError::NotAvailable {
            feature: "transfinite interpolation on SU2 meshes",
            needs: "a structured Plot3D grid (TFI interpolates along grid lines)",
        });
    }
    if a.markers.is_empty() {
        return Err(CliError::Invalid(
            "--marker is required for SU2 meshes (the markers that move)".into(),
        ));
    }
    if file_kind(&a.out) != Some(FileKind::Su2) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a .su2 file",
            a.out.display()
        )));
    }
    if let Some(v) = &a.vtk {
        if file_kind(v) != Some(FileKind::Vtu) {
            return Err(CliError::Invalid(format!(
                "{}: --vtk must be a .vtu file",
                v.display()
            )));
        }
    }
    if !(a.tol.is_finite() && a.tol > 0.0) {
        return Err(CliError::Invalid("--tol must be a positive number".into()));
    }
    let mesh = read_su2(&a.mesh)?;
    crate::guard::check_memory(
        &a.mesh,
        "deform move on this mesh",
        crate::guard::move_estimate(mesh.points.len(), mesh.elements.nodes.len()),
    )?;
    let moved = marker_nodes(&mesh, &a.markers, &a.mesh)?;
    if moved.is_empty() {
        return Err(CliError::Invalid("the named markers have no nodes".into()));
    }
    if let Some(Coords(t)) = &a.translate {
        if mesh.dim == 2 && t.get(2).is_some_and(|&z| z != 0.0) {
            return Err(CliError::Invalid(
                "--translate: a 2D mesh cannot move in z".into(),
            ));
        }
        if mesh.dim == 3 && t.len() != 3 {
            return Err(CliError::Invalid(
                "--translate: a 3D mesh needs dx,dy,dz".into(),
            ));
        }
    }
    if let Some(r) = a.rotate {
        if !r.is_finite() {
            return Err(CliError::Invalid(
                "--rotate must be a finite angle in degrees".into(),
            ));
        }
        if let Some(Coords(ax)) = &a.axis {
            if ax.iter().all(|&v| v == 0.0) {
                return Err(CliError::Invalid(
                    "--axis must not be the zero vector".into(),
                ));
            }
            if mesh.dim == 2 && (ax.first() != Some(&0.0) || ax.get(1) != Some(&0.0)) {
                return Err(CliError::Invalid(
                    "--axis: a 2D mesh rotates about z only (axis 0,0,1)".into(),
                ));
            }
        }
        if let Some(Coords(c)) = &a.center {
            if mesh.dim == 3 && c.len() != 3 {
                return Err(CliError::Invalid("--center: a 3D mesh needs x,y,z".into()));
            }
            if mesh.dim == 2 && c.len() != 2 {
                return Err(CliError::Invalid(
                    "--center: a 2D mesh rotates about a point x,y (no z)".into(),
                ));
            }
        }
    }
    let table = match (&a.displacements, &a.surface_positions) {
        (Some(path), _) => Some((path, false)),
        (None, Some(path)) => Some((path, true)),
        (None, None) => None,
    };
    // Surface positions are placed exactly as given after the deformation (old + (new − old)
    // can differ from new in the last bit).
    let mut exact_positions: Vec<(u32, [f64; 3])> = Vec::new();
    let motion = if let Some((path, absolute)) = table {
        let bytes = read_bytes(path)?;
        let parse = if absolute {
            parse_surface_positions
        } else {
            parse_displacements
        };
        let mut list = parse(&bytes, mesh.dim).map_err(|source| CliError::Read {
            path: path.clone(),
            source,
        })?;
        if absolute {
            exact_positions = list.clone();
            // New positions → displacements from the mesh's own coordinates.
            for (node, p) in &mut list {
                let Some(old) = mesh.points.get(*node as usize) else {
                    return Err(CliError::Invalid(format!(
                        "{}: node {node} is not in the mesh ({} points)",
                        path.display(),
                        mesh.points.len()
                    )));
                };
                for (c, o) in p.iter_mut().zip(old) {
                    *c -= o;
                }
            }
        }
        for (node, _) in &list {
            if moved.binary_search(node).is_err() {
                return Err(CliError::Invalid(format!(
                    "{}: node {node} is not on the moved markers",
                    path.display()
                )));
            }
        }
        Motion::Field(list)
    } else if let Some(Coords(t)) = &a.translate {
        Motion::Translate([
            t.first().copied().unwrap_or(0.0),
            t.get(1).copied().unwrap_or(0.0),
            t.get(2).copied().unwrap_or(0.0),
        ])
    } else {
        let axis = match &a.axis {
            Some(Coords(v)) => [
                v.first().copied().unwrap_or(0.0),
                v.get(1).copied().unwrap_or(0.0),
                v.get(2).copied().unwrap_or(1.0),
            ],
            None => [0.0, 0.0, 1.0],
        };
        let center = a.center.as_ref().map(|Coords(c)| {
            [
                c.first().copied().unwrap_or(0.0),
                c.get(1).copied().unwrap_or(0.0),
                c.get(2).copied().unwrap_or(0.0),
            ]
        });
        Motion::Rotate {
            degrees: a.rotate.unwrap_or(0.0),
            axis,
            center,
        }
    };
    if let Some(p) = &a.plot {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !ext.eq_ignore_ascii_case("svg") && !ext.eq_ignore_ascii_case("png") {
            return Err(CliError::Invalid(format!(
                "{}: --plot must be a .svg or .png file",
                p.display()
            )));
        }
    }
    if !(a.idw_exponent.is_finite() && a.idw_exponent > 0.0) {
        return Err(CliError::Invalid("--idw-exponent must be positive".into()));
    }
    let t0 = Instant::now();
    let moved_lists: Vec<&CellList> = mesh
        .markers
        .iter()
        .filter(|m| a.markers.contains(&m.name))
        .map(|m| &m.elements)
        .collect();
    let fixed_lists: Vec<&CellList> = mesh
        .markers
        .iter()
        .filter(|m| !a.markers.contains(&m.name))
        .map(|m| &m.elements)
        .collect();
    let method = match a.method {
        Method::Quaternion => MoveMethod::Quaternion,
        Method::Idw => MoveMethod::Idw,
        Method::Spring => MoveMethod::Spring,
        Method::AngleDirect => MoveMethod::AngleDirect,
        Method::AngleCg => MoveMethod::AngleCg,
        Method::Tfi | Method::TfiDisplacement => unreachable_tfi()?,
    };
    let solver = match a.solver {
        Solver::Amg => MoveSolver::Amg,
        Solver::Cg => MoveSolver::Cg,
        Solver::CgSsor => MoveSolver::CgSsor,
        Solver::Gs => MoveSolver::GaussSeidel,
        Solver::Jacobi => MoveSolver::Jacobi,
    };
    let input = MoveInput {
        dim: mesh.dim,
        points: &mesh.points,
        cells: &mesh.elements,
        moved: moved_lists.clone(),
        fixed: fixed_lists,
        motion,
        method,
        solver,
        tol: a.tol,
        max_iter: a.max_iter,
        idw_exponent: a.idw_exponent,
    };
    let spinner = crate::progress::spinner("deforming", quiet);
    let result = run_move(&input);
    spinner.finish_and_clear();
    let mut result = result.map_err(|e| e.in_file(&a.mesh))?;
    for (node, p) in &exact_positions {
        if let Some(x) = result.deformed.get_mut(*node as usize) {
            *x = *p;
        }
    }
    let wall = marker_union(&mesh, &a.markers, &a.mesh)?;
    let q = crate::engine::quality(
        mesh.dim,
        &mesh.elements,
        &result.deformed,
        Some(&mesh.points),
        Some(&wall),
    )
    .map_err(|e| e.in_file(&a.mesh))?;
    let out_mesh = Su2Mesh {
        points: result.deformed.clone(),
        ..mesh.clone()
    };
    let mut staged = Staged::new();
    let mut outputs = vec![a.out.display().to_string()];
    staged
        .write(&a.out, |f| write_su2(&out_mesh, f))
        .map_err(io_err(&a.out))?;
    if let Some(v) = &a.vtk {
        let disp: Vec<f64> = result.displacement.iter().flatten().copied().collect();
        staged
            .write(v, |f| {
                write_vtu(
                    f,
                    &out_mesh.points,
                    &out_mesh.elements,
                    &[VtkField {
                        name: "displacement",
                        components: 3,
                        values: &disp,
                    }],
                    &[
                        VtkField {
                            name: "scaled_jacobian",
                            components: 1,
                            values: &q.scaled_jacobian,
                        },
                        VtkField {
                            name: "area_ratio",
                            components: 1,
                            values: &q.ratio,
                        },
                        VtkField {
                            name: "inverted",
                            components: 1,
                            values: &q
                                .inverted
                                .iter()
                                .map(|&b| if b { 1.0 } else { 0.0 })
                                .collect::<Vec<_>>(),
                        },
                    ],
                    VtkEncoding::Base64,
                )
            })
            .map_err(io_err(v))?;
        outputs.push(v.display().to_string());
    }
    if let Some(p) = &a.plot {
        let window = marker_window(&result.deformed, &moved_lists);
        let title = format!(
            "{} {}: {} inverted, {} folded",
            a.mesh.display(),
            value_name(&a.method),
            q.inverted_cells.unwrap_or(0),
            q.folded_cells
        );
        let folded_or_inverted: Vec<bool> = q
            .inverted
            .iter()
            .zip(&q.scaled_jacobian)
            .map(|(&i, &j)| i || j <= 0.0)
            .collect();
        let pic = Picture {
            points: &result.deformed,
            cells: &out_mesh.elements,
            boundaries: &moved_lists,
            highlight: &folded_or_inverted,
            title: &title,
        };
        write_picture(&mut staged, p, &pic, window, 1200)?;
        outputs.push(p.display().to_string());
    }
    staged.commit().map_err(io_err(&a.out))?;
    let norm = |d: &[f64; 3]| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let motion_text = if let Some(p) = &a.displacements {
        format!("displacements from {}", p.display())
    } else if let Some(p) = &a.surface_positions {
        format!("surface positions from {}", p.display())
    } else if let Some(Coords(t)) = &a.translate {
        format!("translate {t:?}")
    } else {
        let c = result
            .center
            .map_or_else(|| "-".to_string(), |c| format!("{:?}", &c[..mesh.dim]));
        format!("rotate {} deg about {c}", a.rotate.unwrap_or(0.0))
    };
    let marker_motions: Vec<MarkerMotion> = a
        .markers
        .iter()
        .filter_map(|name| mesh.marker(name))
        .map(|m| {
            let mut nodes = m.elements.nodes.clone();
            nodes.sort_unstable();
            nodes.dedup();
            let max = nodes
                .iter()
                .filter_map(|&n| result.displacement.get(n as usize))
                .map(norm)
                .fold(0.0, f64::max);
            MarkerMotion {
                marker: m.name.clone(),
                nodes: nodes.len(),
                motion: motion_text.clone(),
                max_displacement: max,
            }
        })
        .collect();
    let max_displacement = result.displacement.iter().map(norm).fold(0.0, f64::max);
    let report = MoveReport {
        command: "move",
        mesh: a.mesh.display().to_string(),
        outputs,
        nodes: mesh.points.len(),
        cells: mesh.elements.len(),
        method: value_name(&a.method),
        solver: match a.method {
            Method::Idw | Method::Tfi | Method::TfiDisplacement => "none".to_string(),
            Method::AngleCg => "cg".to_string(),
            Method::AngleDirect if a.solver == Solver::Jacobi => "jacobi".to_string(),
            Method::AngleDirect if a.solver == Solver::Gs => "gs".to_string(),
            Method::AngleDirect => format!(
                "sor {:.3}",
                crate::engine::angle_direct_omega(mesh.points.len(), mesh.dim)
            ),
            _ => value_name(&a.solver),
        },
        moved_nodes: result.moved_nodes,
        fixed_nodes: result.fixed_nodes,
        center: result.center,
        iterations: result.iterations,
        residual: result.residual,
        converged: result.converged,
        markers: marker_motions,
        max_displacement,
        orientation: q.orientation.describe(mesh.dim),
        inverted_cells: q.inverted_cells.unwrap_or(0),
        folded_cells: q.folded_cells,
        degenerate_cells: q.degenerate_cells,
        min_area_ratio: q.min_area_ratio,
        max_area_ratio: q.max_area_ratio,
        min_scaled_jacobian: q.min_scaled_jacobian,
        max_wall_angle_change_deg: q.max_wall_angle_change_deg,
        seconds: seconds(t0),
    };
    if !report.converged {
        eprintln!(
            "deform: warning: the solver did not converge in {} iterations (residual {:.3e})",
            report.iterations, report.residual
        );
    }
    let text = format!(
        "{} -> {}: {} nodes ({} moved, {} fixed), method {}, {} iterations, residual {:.3e}{}\n  {} mesh; inverted cells {}, folded cells {}, degenerate cells {}, {} ratio min {} max {}, max wall angle change {} deg, {:.2} s",
        report.mesh,
        report.outputs.join(", "),
        report.nodes,
        report.moved_nodes,
        report.fixed_nodes,
        report.method,
        report.iterations,
        report.residual,
        if report.converged { "" } else { " (NOT converged)" },
        report.orientation,
        report.inverted_cells,
        report.folded_cells,
        report.degenerate_cells,
        if mesh.dim == 3 { "volume" } else { "area" },
        fmt_opt(report.min_area_ratio),
        fmt_opt(report.max_area_ratio),
        fmt_opt(report.max_wall_angle_change_deg),
        report.seconds
    );
    let mut text = text;
    text.push_str(&format!(
        "\n  max displacement {:.6e}",
        report.max_displacement
    ));
    for m in &report.markers {
        text.push_str(&format!(
            "\n  marker {}: {} nodes, {}, max displacement {:.6e}",
            m.marker, m.nodes, m.motion, m.max_displacement
        ));
    }
    Ok(Outcome {
        text,
        json: serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
    })
}

#[derive(Serialize)]
struct MoveReport {
    command: &'static str,
    mesh: String,
    outputs: Vec<String>,
    nodes: usize,
    cells: usize,
    method: String,
    solver: String,
    moved_nodes: usize,
    fixed_nodes: usize,
    center: Option<[f64; 3]>,
    iterations: usize,
    residual: f64,
    converged: bool,
    markers: Vec<MarkerMotion>,
    max_displacement: f64,
    orientation: String,
    inverted_cells: usize,
    folded_cells: usize,
    degenerate_cells: usize,
    min_area_ratio: Option<f64>,
    max_area_ratio: Option<f64>,
    min_scaled_jacobian: f64,
    max_wall_angle_change_deg: Option<f64>,
    seconds: f64,
}

/// TFI never reaches the unstructured path (checked at the top of `move_mesh`).
fn unreachable_tfi() -> Result<MoveMethod, CliError> {
    Err(CliError::NotAvailable {
        feature: "transfinite interpolation on SU2 meshes",
        needs: "a structured Plot3D grid",
    })
}

/// `deform move` on a Plot3D grid: the `--wall` face of every block moves rigidly, the opposite
/// face stays, transfinite interpolation (quaternion or displacement) in between.
fn move_grid(a: &MoveArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let Some(face) = a.wall else {
        return Err(CliError::Invalid(
            "--wall FACE (imin, imax, jmin, jmax, kmin, kmax) is required for a Plot3D grid".into(),
        ));
    };
    if !a.markers.is_empty() || a.displacements.is_some() || a.surface_positions.is_some() {
        return Err(CliError::Invalid(
            "a Plot3D grid moves its --wall face with --rotate or --translate (no markers or node files)".into(),
        ));
    }
    if matches!(
        file_kind(&a.out),
        Some(FileKind::Su2 | FileKind::Vtu | FileKind::Vts)
    ) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a Plot3D grid (written in the input's layout)",
            a.out.display()
        )));
    }
    if a.vtk.is_some() || a.plot.is_some() {
        return Err(CliError::NotAvailable {
            feature: "--vtk and --plot for Plot3D grids in move",
            needs: "deform convert OUT out.vts after the move",
        });
    }
    let (mut grid, layout) = read_plot3d(&a.mesh, &Plot3dOptions::default())?;
    let (direction, max) = match face {
        FaceArg::Imin => (0, false),
        FaceArg::Imax => (0, true),
        FaceArg::Jmin => (1, false),
        FaceArg::Jmax => (1, true),
        FaceArg::Kmin => (2, false),
        FaceArg::Kmax => (2, true),
    };
    let coords = |c: &Option<Coords>, fill: f64| {
        c.as_ref().map(|Coords(v)| {
            [
                v.first().copied().unwrap_or(fill),
                v.get(1).copied().unwrap_or(fill),
                v.get(2).copied().unwrap_or(fill),
            ]
        })
    };
    let motion =
        match (a.rotate, coords(&a.translate, 0.0)) {
            (Some(deg), None) if deg.is_finite() => crate::engine::RigidMotion::Rotate {
                degrees: deg,
                axis: coords(&a.axis, 0.0).unwrap_or([0.0, 0.0, 1.0]),
                center: coords(&a.center, 0.0),
            },
            (None, Some(t)) if t.iter().all(|x| x.is_finite()) => {
                crate::engine::RigidMotion::Translate(t)
            }
            _ => return Err(CliError::Invalid(
                "--rotate DEG or --translate DX,DY[,DZ] (finite) moves the wall of a Plot3D grid"
                    .into(),
            )),
        };
    let quaternion = a.method == Method::Tfi;
    let mut total: Option<QualitySummary> = None;
    let mut max_displacement = 0.0f64;
    for (b, blk) in grid.blocks.iter_mut().enumerate() {
        let dim = cell_dim(grid.dim, blk);
        if dim == 2 && direction == 2 {
            return Err(CliError::Invalid(format!(
                "{}: block {}: --wall {} needs a 3D block",
                a.mesh.display(),
                b + 1,
                value_name(&face)
            )));
        }
        if dim == 3 && blk.dims.contains(&1) {
            return Err(CliError::NotAvailable {
                feature: "TFI on a surface block of a 3D grid",
                needs: "volume blocks, or constant-z k-planes",
            });
        }
        let new = crate::engine::tfi_block(
            dim,
            blk.dims,
            &blk.points,
            crate::engine::Face { direction, max },
            motion,
            quaternion,
        )
        .map_err(|e| e.within(&format!("block {}", b + 1)).in_file(&a.mesh))?;
        for (p, q) in blk.points.iter().zip(&new) {
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            max_displacement =
                max_displacement.max((d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt());
        }
        let cells = crate::engine::structured_cells(blk.dims, &blk.points, dim);
        let s = crate::engine::quality(dim, &cells, &new, Some(&blk.points), None)?;
        add_summary(&mut total, s);
        blk.points = new;
    }
    let Some(q) = total else {
        return Err(CliError::Invalid("the grid has no blocks".into()));
    };
    let mut staged = Staged::new();
    staged
        .write(&a.out, |f| write_plot3d(&grid, &layout, f))
        .map_err(io_err(&a.out))?;
    staged.commit().map_err(io_err(&a.out))?;
    let json = json!({
        "command": "move",
        "mesh": a.mesh.display().to_string(),
        "outputs": [a.out.display().to_string()],
        "format": format!("Plot3D {layout}"),
        "blocks": grid.blocks.len(),
        "method": value_name(&a.method),
        "wall": value_name(&face),
        "max_displacement": max_displacement,
        "inverted_cells": q.inverted_cells.unwrap_or(0),
        "folded_cells": q.folded_cells,
        "degenerate_cells": q.degenerate_cells,
        "orientation": q.orientation,
        "min_area_ratio": q.min_area_ratio,
        "max_area_ratio": q.max_area_ratio,
        "min_scaled_jacobian": q.min_scaled_jacobian,
        "seconds": seconds(t0),
    });
    let text = format!(
        "{} -> {}: {} block(s), method {}, wall {}: max displacement {:.6e}, inverted cells {}, folded cells {}, degenerate cells {}, ratio min {} max {}",
        a.mesh.display(),
        a.out.display(),
        grid.blocks.len(),
        value_name(&a.method),
        value_name(&face),
        max_displacement,
        q.inverted_cells.unwrap_or(0),
        q.folded_cells,
        q.degenerate_cells,
        fmt_opt(q.min_area_ratio),
        fmt_opt(q.max_area_ratio),
    );
    Ok(Outcome { json, text })
}

/// What `move` did to one marker.
#[derive(Serialize)]
struct MarkerMotion {
    marker: String,
    nodes: usize,
    motion: String,
    max_displacement: f64,
}

/// The command-line spelling of an enum value.
fn value_name<E: clap::ValueEnum>(v: &E) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
}

/// A square window around the moved markers (their bounding box, enlarged by half).
fn marker_window(points: &[[f64; 3]], lists: &[&CellList]) -> Window {
    let pts: Vec<[f64; 3]> = lists
        .iter()
        .flat_map(|l| l.nodes.iter())
        .filter_map(|&n| points.get(n as usize).copied())
        .collect();
    let w = bounding_window(&pts);
    let c = [(w[0] + w[2]) / 2.0, (w[1] + w[3]) / 2.0];
    let half = 0.75 * (w[2] - w[0]).max(w[3] - w[1]);
    zoom(c, half)
}

/// Stages a picture (.svg or .png by extension).
fn write_picture(
    staged: &mut Staged,
    path: &Path,
    pic: &Picture<'_>,
    window: Window,
    width: u32,
) -> Result<(), CliError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let bytes = if ext == "png" {
        png(pic, window, width).map_err(|e| CliError::Io {
            path: path.to_path_buf(),
            source: io::Error::other(e),
        })?
    } else {
        svg(pic, window, width).into_bytes()
    };
    staged
        .write(path, |f| io::Write::write_all(f, &bytes))
        .map_err(io_err(path))
}

#[derive(Serialize)]
struct SmoothReport {
    command: &'static str,
    grid: String,
    output: String,
    format: String,
    blocks: usize,
    direction: String,
    normalized: bool,
    iterations: usize,
    max_stretching_before: f64,
    max_stretching_after: f64,
    max_point_move: f64,
    max_laplacian_s_before: f64,
    max_laplacian_s_after: f64,
    pinned_coincident_points: usize,
    flipped_cells: usize,
    unchecked_blocks: usize,
    folded_lines: usize,
    seconds: f64,
}

/// Per block, a mask of the points whose coordinates (bit for bit, `−0 = +0`) occur at more
/// than one grid position of the file: O-grid seams, C-grid wake cuts, block interfaces,
/// collapsed axes. Smoothing holds them so that what was closed stays closed.
fn coincident_points(grid: &Plot3dGrid) -> (Vec<Vec<u8>>, usize) {
    use std::collections::HashMap;
    let key = |p: &[f64; 3]| p.map(|x| (x + 0.0).to_bits());
    let mut count: HashMap<[u64; 3], u32> = HashMap::new();
    for b in &grid.blocks {
        for p in &b.points {
            *count.entry(key(p)).or_insert(0) += 1;
        }
    }
    let mut total = 0;
    let masks = grid
        .blocks
        .iter()
        .map(|b| {
            b.points
                .iter()
                .map(|p| {
                    let shared = count.get(&key(p)).copied().unwrap_or(0) > 1;
                    total += usize::from(shared);
                    u8::from(shared)
                })
                .collect()
        })
        .collect();
    (masks, total)
}

/// The dimension a block's cells are measured in: 2 for a 2D grid and for a single k-plane
/// of a 3D grid whose `z` is constant (a 2D grid stored as 3D, as many codes write them),
/// else the grid's.
fn cell_dim(grid_dim: usize, blk: &Plot3dBlock) -> usize {
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

/// The cells (0-based, i-fastest) whose smallest corner Jacobian was > 0 and is ≤ 0.
fn flipped(before: &[f64], after: &[f64]) -> Vec<usize> {
    before
        .iter()
        .zip(after)
        .enumerate()
        .filter(|(_, (&b, &a))| b > 0.0 && a <= 0.0)
        .map(|(c, _)| c)
        .collect()
}

/// `i=…, j=…[, k=…]` (1-based, as Plot3D users count) of cell `c` of a block.
fn cell_name(dims: [usize; 3], dim: usize, c: usize) -> String {
    let ci = dims[0].saturating_sub(1).max(1);
    let cj = dims[1].saturating_sub(1).max(1);
    let (i, j, k) = (c % ci, (c / ci) % cj, c / (ci * cj));
    if dim == 2 {
        format!("i={}, j={}", i + 1, j + 1)
    } else {
        format!("i={}, j={}, k={}", i + 1, j + 1, k + 1)
    }
}

fn smooth(a: &SmoothArgs, quiet: bool) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    if matches!(
        file_kind(&a.out),
        Some(FileKind::Su2 | FileKind::Vtu | FileKind::Vts)
    ) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a Plot3D grid (written in the input's layout; any extension but .su2, .vtu, .vts)",
            a.out.display()
        )));
    }
    if input_kind(&a.grid)? != FileKind::Plot3d {
        return Err(CliError::Invalid(format!(
            "{}: smooth needs a structured Plot3D grid, this is an SU2 mesh",
            a.grid.display()
        )));
    }
    if !(a.lambda.is_finite() && a.lambda > 0.0 && a.mu.is_finite() && a.mu <= 0.0) {
        return Err(CliError::Invalid(
            "--lambda must be > 0 and --mu <= 0 (Taubin: mu slightly below -lambda)".into(),
        ));
    }
    if a.coarse == Some(0) {
        return Err(CliError::Invalid("--coarse must be at least 1".into()));
    }
    let (mut grid, layout) = read_plot3d(&a.grid, &plot3d_options(&a.layout))?;
    if grid.dim == 2 && a.direction == Direction::K {
        return Err(CliError::Invalid(format!(
            "{}: --direction k needs a 3D grid, this one is 2D",
            a.grid.display()
        )));
    }
    let direction = match a.direction {
        Direction::I => 0,
        Direction::J => 1,
        Direction::K => 2,
    };
    let bar = crate::progress::bar(grid.blocks.len() as u64, "smoothing", quiet);
    let mut report = SmoothReport {
        command: "smooth",
        grid: a.grid.display().to_string(),
        output: a.out.display().to_string(),
        format: format!("Plot3D {layout}"),
        blocks: grid.blocks.len(),
        direction: value_name(&a.direction),
        normalized: a.normalized,
        iterations: 0,
        max_stretching_before: 1.0,
        max_stretching_after: 1.0,
        max_point_move: 0.0,
        max_laplacian_s_before: 0.0,
        max_laplacian_s_after: 0.0,
        pinned_coincident_points: 0,
        flipped_cells: 0,
        unchecked_blocks: 0,
        folded_lines: 0,
        seconds: 0.0,
    };
    let (pins, shared) = coincident_points(&grid);
    report.pinned_coincident_points = shared;
    let dim = grid.dim;
    let in_block = |b: usize| move |e: CliError| e.within(&format!("block {}", b + 1));
    for (b, (blk, pin)) in grid.blocks.iter_mut().zip(&pins).enumerate() {
        let original = blk.points.clone();
        let smooth_copy = |iterations: usize, coarse: Option<usize>| {
            let mut pts = original.clone();
            crate::engine::smooth_block(
                dim,
                blk.dims,
                &mut pts,
                direction,
                a.normalized,
                iterations,
                a.lambda,
                a.mu,
                coarse,
                Some(pin),
            )
            .map(|r| (pts, r))
        };
        let (smoothed, r) = smooth_copy(a.iterations, a.coarse)
            .map_err(in_block(b))
            .map_err(|e| e.in_file(&a.grid))?;
        report.max_laplacian_s_before =
            report
                .max_laplacian_s_before
                .max(crate::engine::max_arclength_laplacian(
                    dim, blk.dims, &original, direction,
                )?);
        report.max_laplacian_s_after =
            report
                .max_laplacian_s_after
                .max(crate::engine::max_arclength_laplacian(
                    dim, blk.dims, &smoothed, direction,
                )?);
        // The cell check: every corner Jacobian against the input's.
        let cdim = cell_dim(dim, blk);
        if cdim == 3 && blk.dims.contains(&1) {
            report.unchecked_blocks += 1;
        } else {
            let cells = crate::engine::structured_cells(blk.dims, &original, cdim);
            let before = crate::engine::corner_jacobians(cdim, &cells, &original)?;
            let after = crate::engine::corner_jacobians(cdim, &cells, &smoothed)?;
            let bad = flipped(&before, &after);
            if !bad.is_empty() && !a.allow_folds {
                // Name the first iteration after which a cell is flipped (fine iterations
                // 1..N by bisection, assuming a flip persists; else the coarse pass).
                let flips_after = |k: usize| -> Result<bool, CliError> {
                    let (p, _) = smooth_copy(k, None).map_err(in_block(b))?;
                    let after = crate::engine::corner_jacobians(cdim, &cells, &p)?;
                    Ok(!flipped(&before, &after).is_empty())
                };
                let when = if a.iterations > 0 && flips_after(a.iterations)? {
                    let (mut lo, mut hi) = (1, a.iterations);
                    while lo < hi {
                        let mid = lo + (hi - lo) / 2;
                        if flips_after(mid)? {
                            hi = mid;
                        } else {
                            lo = mid + 1;
                        }
                    }
                    format!("after iteration {lo}")
                } else {
                    "in the coarse-grid pass".to_string()
                };
                return Err(CliError::Invalid(format!(
                    "{}: block {}: smoothing flips {} cell(s) (first: cell {}, {when}); nothing was written (--allow-folds writes them anyway)",
                    a.grid.display(),
                    b + 1,
                    bad.len(),
                    cell_name(blk.dims, dim, bad[0]),
                )));
            }
            report.flipped_cells += bad.len();
        }
        blk.points = smoothed;
        report.iterations = report.iterations.max(r.iterations);
        report.max_stretching_before = report.max_stretching_before.max(r.max_stretching_before);
        report.max_stretching_after = report.max_stretching_after.max(r.max_stretching_after);
        report.max_point_move = report.max_point_move.max(r.max_point_move);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let mut staged = Staged::new();
    staged
        .write(&a.out, |f| write_plot3d(&grid, &layout, f))
        .map_err(io_err(&a.out))?;
    staged.commit().map_err(io_err(&a.out))?;
    report.seconds = seconds(t0);
    let mut text = format!(
        "{} -> {}: {} block(s), {} iterations along {}{}, max stretching {:.4} -> {:.4}, max |∇²S| {:.4e} -> {:.4e}, max point move {:.3e}, {} coincident points held",
        report.grid,
        report.output,
        report.blocks,
        report.iterations,
        report.direction,
        if report.normalized { " (normalized)" } else { "" },
        report.max_stretching_before,
        report.max_stretching_after,
        report.max_laplacian_s_before,
        report.max_laplacian_s_after,
        report.max_point_move,
        report.pinned_coincident_points,
    );
    if report.flipped_cells > 0 {
        text.push_str(&format!(
            "\n  WARNING: {} cell(s) flipped (written because of --allow-folds)",
            report.flipped_cells
        ));
    }
    if report.unchecked_blocks > 0 {
        text.push_str(&format!(
            "\n  note: {} surface block(s) of a 3D grid have no volume cells; their cells were not checked",
            report.unchecked_blocks
        ));
    }
    Ok(Outcome {
        text,
        json: serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
    })
}

#[derive(Serialize)]
struct QualityReport {
    command: &'static str,
    file: String,
    reference: Option<String>,
    format: String,
    dim: usize,
    nodes: usize,
    blocks: usize,
    #[serde(flatten)]
    summary: QualitySummary,
    seconds: f64,
}

/// Merges the elements of the named markers into one list.
fn marker_union(mesh: &Su2Mesh, names: &[String], path: &Path) -> Result<CellList, CliError> {
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

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.6}"))
}

fn quality_text(r: &QualityReport) -> String {
    let s = &r.summary;
    let mut t = format!(
        "quality of {} ({})
",
        r.file, r.format
    );
    if let Some(reference) = &r.reference {
        t.push_str(&format!(
            "  reference                   {reference}
"
        ));
    }
    let measure = if r.dim == 3 { "volume" } else { "area" };
    let rows: [(String, String); 12] = [
        ("nodes".into(), r.nodes.to_string()),
        ("cells".into(), s.cells.to_string()),
        ("orientation".into(), s.orientation.describe(r.dim)),
        (
            "inverted cells".into(),
            s.inverted_cells.map_or("-".into(), |v| v.to_string()),
        ),
        ("folded cells".into(), s.folded_cells.to_string()),
        ("degenerate cells".into(), s.degenerate_cells.to_string()),
        (
            format!("cells with {measure} <= 0"),
            s.nonpositive_cells.to_string(),
        ),
        (format!("min {measure}"), format!("{:.6e}", s.min_measure)),
        (
            "min scaled Jacobian".into(),
            format!("{:.6}", s.min_scaled_jacobian),
        ),
        (format!("min {measure} ratio"), fmt_opt(s.min_area_ratio)),
        (format!("max {measure} ratio"), fmt_opt(s.max_area_ratio)),
        (
            "max wall angle change (deg)".into(),
            fmt_opt(s.max_wall_angle_change_deg),
        ),
    ];
    for (k, v) in rows {
        t.push_str(&format!("  {k:<28}{v}\n"));
    }
    t.trim_end().to_string()
}

fn add_summary(total: &mut Option<QualitySummary>, s: QualitySummary) {
    let Some(t) = total.as_mut() else {
        *total = Some(s);
        return;
    };
    let add_opt = |a: Option<usize>, b: Option<usize>| match (a, b) {
        (Some(x), Some(y)) => Some(x + y),
        _ => None,
    };
    let min_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    };
    let max_opt = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.max(y)),
        (x, None) => x,
        (None, y) => y,
    };
    t.cells += s.cells;
    t.inverted_cells = add_opt(t.inverted_cells, s.inverted_cells);
    t.folded_cells += s.folded_cells;
    t.degenerate_cells += s.degenerate_cells;
    t.nonpositive_cells += s.nonpositive_cells;
    t.orientation.regions += s.orientation.regions;
    t.orientation.positive_regions += s.orientation.positive_regions;
    t.orientation.negative_regions += s.orientation.negative_regions;
    t.orientation.cells_against_region += s.orientation.cells_against_region;
    t.min_measure = t.min_measure.min(s.min_measure);
    t.min_scaled_jacobian = t.min_scaled_jacobian.min(s.min_scaled_jacobian);
    t.min_area_ratio = min_opt(t.min_area_ratio, s.min_area_ratio);
    t.max_area_ratio = max_opt(t.max_area_ratio, s.max_area_ratio);
    t.max_wall_angle_change_deg = max_opt(t.max_wall_angle_change_deg, s.max_wall_angle_change_deg);
}

fn quality(a: &QualityArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let kind = input_kind(&a.file)?;
    let opts = plot3d_options(&a.layout);
    let mut staged = Staged::new();
    let report = match kind {
        FileKind::Su2 => {
            if let Some(v) = &a.vtk {
                if file_kind(v) != Some(FileKind::Vtu) {
                    return Err(CliError::Invalid(format!(
                        "{}: --vtk must be a .vtu file for an SU2 mesh",
                        v.display()
                    )));
                }
            }
            let m = read_su2(&a.file)?;
            let reference = match &a.reference {
                Some(r) => {
                    let reference = read_su2(r)?;
                    if reference.points.len() != m.points.len() || reference.elements != m.elements
                    {
                        return Err(CliError::Invalid(format!(
                            "{}: the reference mesh has different points or elements",
                            r.display()
                        )));
                    }
                    Some(reference)
                }
                None => None,
            };
            if !a.walls.is_empty() && reference.is_none() {
                return Err(CliError::Invalid("--wall needs --reference".into()));
            }
            let wall = if a.walls.is_empty() {
                None
            } else {
                Some(marker_union(&m, &a.walls, &a.file)?)
            };
            let summary = crate::engine::quality(
                m.dim,
                &m.elements,
                &m.points,
                reference.as_ref().map(|r| r.points.as_slice()),
                wall.as_ref(),
            )?;
            if let Some(v) = &a.vtk {
                staged
                    .write(v, |f| {
                        write_vtu(
                            f,
                            &m.points,
                            &m.elements,
                            &[],
                            &[
                                VtkField {
                                    name: "measure",
                                    components: 1,
                                    values: &summary.measure,
                                },
                                VtkField {
                                    name: "scaled_jacobian",
                                    components: 1,
                                    values: &summary.scaled_jacobian,
                                },
                            ],
                            VtkEncoding::Base64,
                        )
                    })
                    .map_err(io_err(v))?;
            }
            QualityReport {
                command: "quality",
                file: a.file.display().to_string(),
                reference: a.reference.as_ref().map(|r| r.display().to_string()),
                format: format!("SU2 {}D", m.dim),
                dim: m.dim,
                nodes: m.points.len(),
                blocks: 0,
                summary,
                seconds: 0.0,
            }
        }
        _ => {
            if let Some(v) = &a.vtk {
                if file_kind(v) != Some(FileKind::Vts) {
                    return Err(CliError::Invalid(format!(
                        "{}: --vtk must be a .vts file for a Plot3D grid",
                        v.display()
                    )));
                }
            }
            if !a.walls.is_empty() {
                return Err(CliError::Invalid(
                    "--wall applies to SU2 meshes only".into(),
                ));
            }
            let (g, layout) = read_plot3d(&a.file, &opts)?;
            let reference = match &a.reference {
                Some(r) => {
                    let (reference, _) = read_plot3d(r, &opts)?;
                    let same = reference.blocks.len() == g.blocks.len()
                        && reference
                            .blocks
                            .iter()
                            .zip(&g.blocks)
                            .all(|(x, y)| x.dims == y.dims);
                    if !same {
                        return Err(CliError::Invalid(format!(
                            "{}: the reference grid has different blocks or dimensions",
                            r.display()
                        )));
                    }
                    Some(reference)
                }
                None => None,
            };
            let mut total = None;
            for (b, blk) in g.blocks.iter().enumerate() {
                let dim = cell_dim(g.dim, blk);
                if dim == 3 && blk.dims.contains(&1) {
                    return Err(CliError::NotAvailable {
                        feature: "quality of a curved surface block in a 3D grid",
                        needs: "volume blocks, or planar k-planes (constant z), which are measured as 2D",
                    });
                }
                let cells = crate::engine::structured_cells(blk.dims, &blk.points, dim);
                let rpts = reference
                    .as_ref()
                    .and_then(|r| r.blocks.get(b))
                    .map(|rb| rb.points.as_slice());
                let s = crate::engine::quality(dim, &cells, &blk.points, rpts, None)?;
                if let Some(v) = &a.vtk {
                    let p = block_vts_path(v, b, g.blocks.len());
                    staged
                        .write(&p, |f| {
                            write_vts(
                                f,
                                blk.dims,
                                &blk.points,
                                &[],
                                &[
                                    VtkField {
                                        name: "measure",
                                        components: 1,
                                        values: &s.measure,
                                    },
                                    VtkField {
                                        name: "scaled_jacobian",
                                        components: 1,
                                        values: &s.scaled_jacobian,
                                    },
                                ],
                                VtkEncoding::Base64,
                            )
                        })
                        .map_err(io_err(&p))?;
                }
                add_summary(&mut total, s);
            }
            let Some(summary) = total else {
                return Err(CliError::Invalid("the grid has no blocks".into()));
            };
            QualityReport {
                command: "quality",
                file: a.file.display().to_string(),
                reference: a.reference.as_ref().map(|r| r.display().to_string()),
                format: format!("Plot3D {layout}"),
                // Planar k-planes of a 3D file are measured (and worded) as 2D.
                dim: g
                    .blocks
                    .iter()
                    .map(|b| cell_dim(g.dim, b))
                    .max()
                    .unwrap_or(g.dim),
                nodes: g.blocks.iter().map(|b| b.points.len()).sum(),
                blocks: g.blocks.len(),
                summary,
                seconds: 0.0,
            }
        }
    };
    staged.commit().map_err(io_err(&a.file))?;
    let report = QualityReport {
        seconds: seconds(t0),
        ..report
    };
    Ok(Outcome {
        text: quality_text(&report),
        json: serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
    })
}

#[derive(Serialize)]
struct ConvertReport {
    command: &'static str,
    input: String,
    outputs: Vec<String>,
    input_format: String,
    points: usize,
    cells: usize,
    blocks: usize,
    seconds: f64,
}

fn block_vts_path(out: &Path, b: usize, nblocks: usize) -> PathBuf {
    if nblocks == 1 {
        return out.to_path_buf();
    }
    let stem = out
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "grid".into());
    out.with_file_name(format!("{stem}_b{}.vts", b + 1))
}

fn convert(a: &ConvertArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let kin = input_kind(&a.input)?;
    // A Plot3D input may be written to any name that is not SU2 or VTK.
    let kout = match (kin, file_kind(&a.output)) {
        (FileKind::Plot3d, None) => Some(FileKind::Plot3d),
        (_, k) => k,
    };
    let enc = if a.vtk_ascii {
        VtkEncoding::Ascii
    } else {
        VtkEncoding::Base64
    };
    let mut staged = Staged::new();
    let mut outputs = Vec::new();
    let report = match (kin, kout) {
        (FileKind::Su2, Some(k @ (FileKind::Su2 | FileKind::Vtu))) => {
            let m = read_su2(&a.input)?;
            staged
                .write(&a.output, |f| {
                    if k == FileKind::Su2 {
                        write_su2(&m, f)
                    } else {
                        write_vtu(f, &m.points, &m.elements, &[], &[], enc)
                    }
                })
                .map_err(io_err(&a.output))?;
            outputs.push(a.output.display().to_string());
            ConvertReport {
                command: "convert",
                input: a.input.display().to_string(),
                outputs: Vec::new(),
                input_format: format!("SU2 {}D, {} markers", m.dim, m.markers.len()),
                points: m.points.len(),
                cells: m.elements.len(),
                blocks: 0,
                seconds: 0.0,
            }
        }
        (FileKind::Plot3d, Some(k @ (FileKind::Plot3d | FileKind::Vts))) => {
            let (g, layout) = read_plot3d(&a.input, &plot3d_options(&a.layout))?;
            if k == FileKind::Plot3d {
                let out_layout = output_layout(&layout, a);
                staged
                    .write(&a.output, |f| write_plot3d(&g, &out_layout, f))
                    .map_err(io_err(&a.output))?;
                outputs.push(a.output.display().to_string());
            } else {
                for (b, blk) in g.blocks.iter().enumerate() {
                    let p = block_vts_path(&a.output, b, g.blocks.len());
                    staged
                        .write(&p, |f| write_vts(f, blk.dims, &blk.points, &[], &[], enc))
                        .map_err(io_err(&p))?;
                    outputs.push(p.display().to_string());
                }
            }
            ConvertReport {
                command: "convert",
                input: a.input.display().to_string(),
                outputs: Vec::new(),
                input_format: format!("Plot3D {layout}"),
                points: g.blocks.iter().map(|b| b.points.len()).sum(),
                cells: g
                    .blocks
                    .iter()
                    .map(|b| {
                        b.dims
                            .iter()
                            .map(|&d| d.saturating_sub(1).max(1))
                            .product::<usize>()
                    })
                    .sum(),
                blocks: g.blocks.len(),
                seconds: 0.0,
            }
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

fn output_layout(input: &Plot3dLayout, a: &ConvertArgs) -> Plot3dLayout {
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
