//! `deform quality`: cell measures, orientation, folded/inverted counts and ratios against a
//! reference.

use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::QualityArgs;
use crate::engine::QualitySummary;
use crate::formats::vtk::{write_vts, write_vtu, VtkEncoding, VtkField};
use crate::output::Staged;

use crate::error::CliError;
use crate::files::{
    block_vts_path, cell_dim, file_kind, input_kind, io_err, marker_union, plot3d_options,
    read_plot3d, read_su2, FileKind,
};
use crate::report::{add_summary, fmt_opt, seconds, volume_words, Outcome};

#[derive(Serialize)]
pub(crate) struct QualityReport {
    command: &'static str,
    file: String,
    reference: Option<String>,
    format: String,
    dim: usize,
    nodes: usize,
    blocks: usize,
    /// SU2: boundary faces (edges in 2D) that belong to no marker.
    #[serde(skip_serializing_if = "Option::is_none")]
    unmarked_boundary_faces: Option<usize>,
    /// SU2: the centroid of one of them.
    #[serde(skip_serializing_if = "Option::is_none")]
    unmarked_boundary_sample: Option<[f64; 3]>,
    #[serde(flatten)]
    summary: QualitySummary,
    seconds: f64,
}

pub(crate) fn quality_text(r: &QualityReport) -> String {
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
    let reversed = match s.orientation.cells_listed_reversed {
        0 => "0".to_string(),
        k => format!("{k} (valid; SU2 reorders them, `deform convert --reorient` rewrites them)"),
    };
    let rows: [(String, String); 13] = [
        ("nodes".into(), r.nodes.to_string()),
        ("cells".into(), s.cells.to_string()),
        ("orientation".into(), s.orientation.describe(r.dim)),
        (
            crate::orientation::OrientationSummary::reversed_words(r.dim).into(),
            reversed,
        ),
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
    if let (Some(n @ 1..), Some(p)) = (r.unmarked_boundary_faces, r.unmarked_boundary_sample) {
        t.push_str(&format!(
            "  {:<28}{n} (one at {}): they move like the field in deform move\n",
            "boundary faces in no marker",
            point_text(p, r.dim)
        ));
    }
    t.trim_end().to_string()
}

/// `(x, y)` or `(x, y, z)`.
pub(crate) fn point_text(p: [f64; 3], dim: usize) -> String {
    let v: Vec<String> = p[..dim.clamp(1, 3)]
        .iter()
        .map(|x| format!("{x:.6}"))
        .collect();
    format!("({})", v.join(", "))
}

pub(crate) fn quality(a: &QualityArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let mut staged = Staged::new();
    let report = match input_kind(&a.file)? {
        FileKind::Su2 => quality_su2(a, &mut staged)?,
        _ => quality_plot3d(a, &mut staged)?,
    };
    staged.commit().map_err(io_err(&a.file))?;
    let report = QualityReport {
        seconds: seconds(t0),
        ..report
    };
    Ok(Outcome {
        text: quality_text(&report),
        json: volume_words(
            serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
            report.dim,
        ),
    })
}

/// The cell fields `--vtk` writes: measure and scaled Jacobian.
fn quality_fields(s: &QualitySummary) -> [VtkField<'_>; 2] {
    [
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
    ]
}

/// `--vtk` must name a file of the `kind` that goes with the input (`what`).
fn check_vtk_kind(a: &QualityArgs, kind: FileKind, what: &str) -> Result<(), CliError> {
    match &a.vtk {
        Some(v) if file_kind(v) != Some(kind) => Err(CliError::Invalid(format!(
            "{}: --vtk must be a {what}",
            v.display()
        ))),
        _ => Ok(()),
    }
}

/// The quality of an SU2 mesh (against `--reference`, wall angles on `--wall` markers).
fn quality_su2(a: &QualityArgs, staged: &mut Staged) -> Result<QualityReport, CliError> {
    check_vtk_kind(a, FileKind::Vtu, ".vtu file for an SU2 mesh")?;
    let m = read_su2(&a.file)?;
    let reference = match &a.reference {
        Some(r) => {
            let reference = read_su2(r)?;
            if reference.points.len() != m.points.len() || reference.elements != m.elements {
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
    let markers: Vec<_> = m.markers.iter().map(|k| &k.elements).collect();
    let unmarked = crate::validity::unmarked_among(&summary.boundary_faces, &markers, &m.points);
    if let Some(v) = &a.vtk {
        let cells = quality_fields(&summary);
        staged
            .write(v, |f| {
                write_vtu(f, &m.points, &m.elements, &[], &cells, VtkEncoding::Base64)
            })
            .map_err(io_err(v))?;
    }
    Ok(QualityReport {
        command: "quality",
        file: a.file.display().to_string(),
        reference: a.reference.as_ref().map(|r| r.display().to_string()),
        format: format!("SU2 {}D", m.dim),
        dim: m.dim,
        nodes: m.points.len(),
        blocks: 0,
        unmarked_boundary_faces: Some(unmarked.faces),
        unmarked_boundary_sample: unmarked.sample,
        summary,
        seconds: 0.0,
    })
}

/// The quality of a Plot3D grid, block by block (against `--reference`).
fn quality_plot3d(a: &QualityArgs, staged: &mut Staged) -> Result<QualityReport, CliError> {
    check_vtk_kind(a, FileKind::Vts, ".vts file for a Plot3D grid")?;
    if !a.walls.is_empty() {
        return Err(CliError::Invalid(
            "--wall applies to SU2 meshes only".into(),
        ));
    }
    let opts = plot3d_options(&a.layout);
    let (g, layout) = read_plot3d(&a.file, &opts)?;
    let reference = match &a.reference {
        Some(r) => {
            let (reference, _) = read_plot3d(r, &opts)?;
            let same = reference.blocks.len() == g.blocks.len()
                && (reference.blocks.iter().zip(&g.blocks)).all(|(x, y)| x.dims == y.dims);
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
        let rpts = (reference.as_ref())
            .and_then(|r| r.blocks.get(b))
            .map(|rb| rb.points.as_slice());
        let s = crate::engine::quality(dim, &cells, &blk.points, rpts, None)?;
        if let Some(v) = &a.vtk {
            let p = block_vts_path(v, b, g.blocks.len());
            let fields = quality_fields(&s);
            staged
                .write(&p, |f| {
                    write_vts(f, blk.dims, &blk.points, &[], &fields, VtkEncoding::Base64)
                })
                .map_err(io_err(&p))?;
        }
        add_summary(&mut total, s);
    }
    let Some(summary) = total else {
        return Err(CliError::Invalid("the grid has no blocks".into()));
    };
    Ok(QualityReport {
        command: "quality",
        file: a.file.display().to_string(),
        reference: a.reference.as_ref().map(|r| r.display().to_string()),
        format: format!("Plot3D {layout}"),
        // Planar k-planes of a 3D file are measured (and worded) as 2D.
        dim: (g.blocks.iter().map(|b| cell_dim(g.dim, b)).max()).unwrap_or(g.dim),
        nodes: g.blocks.iter().map(|b| b.points.len()).sum(),
        blocks: g.blocks.len(),
        unmarked_boundary_faces: None,
        unmarked_boundary_sample: None,
        summary,
        seconds: 0.0,
    })
}
