//! `deform mesh naca|block`: generated meshes written as SU2, VTK or Plot3D.

use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::{BlockArgs, Dims, NacaArgs, NacaKind};
use crate::formats::plot3d::{
    write_plot3d, Encoding, Endian, Plot3dBlock, Plot3dGrid, Plot3dLayout, Precision,
};
use crate::formats::vtk::{write_vts, VtkEncoding};
use crate::output::Staged;
use deform_meshgen::AirfoilGrid;

use crate::error::CliError;
use crate::files::{
    file_kind, io_err, mesh_error, su2_from_mesh2, su2_from_mesh3, write_mesh_file, FileKind,
};
use crate::report::{seconds, Outcome};

#[derive(Serialize)]
pub(crate) struct MeshReport {
    command: &'static str,
    output: String,
    kind: String,
    nodes: usize,
    cells: usize,
    markers: Vec<String>,
    seconds: f64,
}

pub(crate) fn mesh_naca(a: &NacaArgs) -> Result<Outcome, CliError> {
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
    crate::guard::check_memory(
        &a.out,
        "generating this mesh",
        crate::guard::mesh_estimate(&[opts.surface_points, opts.radial_points]),
    )?;
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

pub(crate) fn mesh_outcome(report: &MeshReport) -> Outcome {
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

/// One block as Plot3D: text for `.xyz`/`.p3d`, else little-endian double binary with
/// records.
fn write_block_plot3d(
    staged: &mut Staged,
    out: &std::path::Path,
    dim: usize,
    dims: [usize; 3],
    points: &[[f64; 3]],
) -> Result<(), CliError> {
    let grid = Plot3dGrid {
        dim,
        blocks: vec![Plot3dBlock {
            dims,
            points: points.to_vec(),
            iblank: None,
        }],
    };
    let ext = (out.extension().and_then(|e| e.to_str()))
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
        .write(out, |f| write_plot3d(&grid, &layout, f))
        .map_err(io_err(out))
}

pub(crate) fn mesh_block(a: &BlockArgs) -> Result<Outcome, CliError> {
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
    crate::guard::check_memory(
        &a.out,
        "generating this mesh",
        crate::guard::mesh_estimate(&dims),
    )?;
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
        _ => write_block_plot3d(&mut staged, &a.out, dim, dims, &su2.points)?,
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
