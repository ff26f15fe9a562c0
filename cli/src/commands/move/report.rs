//! What `deform move` on an SU2 mesh reports: the JSON report and its text form, per-marker
//! motions, and the warning about boundary faces in no marker.

use std::time::Instant;

use serde::Serialize;

use super::motion::{describe, PerMarker};
use crate::args::{Coords, Method, MoveArgs, Solver};
use crate::engine::{MoveResult, QualitySummary};
use crate::formats::su2::Su2Mesh;
use crate::formats::CellList;
use crate::report::{fmt_opt, seconds, value_name};

/// The JSON report of `deform move` on an SU2 mesh.
#[derive(Serialize)]
pub(crate) struct MoveReport {
    command: &'static str,
    pub(super) mesh: String,
    pub(super) outputs: Vec<String>,
    nodes: usize,
    cells: usize,
    method: String,
    solver: String,
    stiffness: String,
    steps: u32,
    reach: Option<f64>,
    idw_max_bound: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rbf: Option<crate::engine::RbfInfo>,
    moved_nodes: usize,
    fixed_nodes: usize,
    sliding_markers: Vec<String>,
    sliding_nodes: usize,
    max_slide_offset: f64,
    center: Option<[f64; 3]>,
    pub(super) iterations: usize,
    pub(super) residual: f64,
    pub(super) converged: bool,
    markers: Vec<MarkerMotion>,
    max_displacement: f64,
    /// Boundary faces in no marker, one's centroid, and how far their field nodes moved.
    unmarked_boundary_faces: usize,
    unmarked_boundary_sample: Option<[f64; 3]>,
    unmarked_boundary_max_displacement: f64,
    orientation: String,
    inverted_cells: usize,
    folded_cells: usize,
    /// Cells inverted or folded here that were valid in the input (the failure policy).
    new_invalid_cells: usize,
    /// Valid cells listed clockwise / mirrored in the input (SU2 reorders them).
    listed_reversed_cells: usize,
    degenerate_cells: usize,
    min_area_ratio: Option<f64>,
    max_area_ratio: Option<f64>,
    min_scaled_jacobian: f64,
    max_wall_angle_change_deg: Option<f64>,
    renumber: crate::renumber::RenumberReport,
    seconds: f64,
}

/// What `move` did to one marker.
#[derive(Serialize)]
pub(crate) struct MarkerMotion {
    marker: String,
    nodes: usize,
    motion: String,
    max_displacement: f64,
}

/// What a finished run knows, for its report.
pub(super) struct Run<'a> {
    pub mesh: &'a Su2Mesh,
    /// The moving markers' names.
    pub markers: &'a [String],
    pub per_marker: &'a PerMarker,
    pub result: &'a MoveResult,
    pub quality: &'a QualitySummary,
    pub outputs: Vec<String>,
    /// What `--renumber` did.
    pub renumbered: crate::renumber::RenumberReport,
    pub started: Instant,
}

fn norm(d: &[f64; 3]) -> f64 {
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// The report of a finished run (and, on stderr, the warning about unmarked boundary faces).
pub(super) fn move_report(a: &MoveArgs, run: Run<'_>) -> MoveReport {
    let (mesh, result, q) = (run.mesh, run.result, run.quality);
    let all_markers: Vec<&CellList> = mesh.markers.iter().map(|m| &m.elements).collect();
    let unmarked = crate::validity::unmarked_among(&q.boundary_faces, &all_markers, &mesh.points);
    let unmarked_moved = unmarked
        .free_nodes
        .iter()
        .filter_map(|&n| result.displacement.get(n as usize))
        .map(norm)
        .fold(0.0, f64::max);
    if unmarked_moved > 0.0 {
        eprintln!(
            "deform: warning: {} boundary face(s) belong to no marker (one at {}) and moved like the field, up to {unmarked_moved:.3e}; put them in a marker to hold them",
            unmarked.faces,
            unmarked
                .sample
                .map_or_else(|| "-".to_string(), |p| super::super::quality::point_text(p, mesh.dim))
        );
    }
    let spring_free = matches!(
        a.method(),
        Method::Idw | Method::Tfi | Method::TfiDisplacement
    );
    MoveReport {
        command: "move",
        mesh: a.mesh.display().to_string(),
        outputs: run.outputs,
        nodes: mesh.points.len(),
        cells: mesh.elements.len(),
        method: value_name(&a.method()),
        solver: solver_name(a, mesh),
        stiffness: if spring_free {
            "none".to_string()
        } else {
            value_name(&a.stiffness())
        },
        steps: a.steps,
        reach: a.reach,
        idw_max_bound: result.idw_max_bound,
        rbf: result.rbf,
        moved_nodes: result.moved_nodes,
        fixed_nodes: result.fixed_nodes,
        sliding_markers: a.slide.clone(),
        sliding_nodes: result.sliding_nodes,
        max_slide_offset: result.max_slide_offset,
        center: result.center,
        iterations: result.iterations,
        residual: result.residual,
        converged: result.converged,
        markers: marker_motions(a, run.mesh, run.markers, run.per_marker, result),
        max_displacement: result.displacement.iter().map(norm).fold(0.0, f64::max),
        unmarked_boundary_faces: unmarked.faces,
        unmarked_boundary_sample: unmarked.sample,
        unmarked_boundary_max_displacement: unmarked_moved,
        orientation: q.orientation.describe(mesh.dim),
        inverted_cells: q.inverted_cells.unwrap_or(0),
        folded_cells: q.folded_cells,
        new_invalid_cells: q.new_failures(),
        listed_reversed_cells: q.orientation.cells_listed_reversed,
        degenerate_cells: q.degenerate_cells,
        min_area_ratio: q.min_area_ratio,
        max_area_ratio: q.max_area_ratio,
        min_scaled_jacobian: q.min_scaled_jacobian,
        max_wall_angle_change_deg: q.max_wall_angle_change_deg,
        renumber: run.renumbered,
        seconds: seconds(run.started),
    }
}

/// The solver as the report names it (the angle springs pick theirs from the method).
fn solver_name(a: &MoveArgs, mesh: &Su2Mesh) -> String {
    match a.method() {
        Method::Idw | Method::Rbf | Method::Tfi | Method::TfiDisplacement => "none".to_string(),
        Method::AngleCg if a.solver == Solver::Amg && a.slide.is_empty() => "amg".to_string(),
        Method::AngleCg => "cg".to_string(),
        Method::Elasticity if a.solver == Solver::Amg => "amg".to_string(),
        Method::Elasticity => "cg".to_string(),
        Method::AngleDirect if a.solver == Solver::Jacobi => "jacobi".to_string(),
        Method::AngleDirect if a.solver == Solver::Gs => "gs".to_string(),
        Method::AngleDirect => format!(
            "sor {:.3}",
            crate::engine::angle_direct_omega(mesh.points.len(), mesh.dim)
        ),
        _ => value_name(&a.solver),
    }
}

/// Every moving marker: its nodes, its motion in words, its largest displacement.
fn marker_motions(
    a: &MoveArgs,
    mesh: &Su2Mesh,
    markers: &[String],
    per_marker: &PerMarker,
    result: &MoveResult,
) -> Vec<MarkerMotion> {
    let motion_text = if let Some(p) = &a.motions {
        format!("motions from {}", p.display())
    } else if let Some(p) = &a.displacements {
        format!("displacements from {}", p.display())
    } else if let Some(p) = &a.surface_positions {
        format!("surface positions from {}", p.display())
    } else if a.design_field.is_some() {
        "the config's design variables".to_string()
    } else if let Some(Coords(t)) = &a.translate {
        format!("translate {t:?}")
    } else {
        let c = result
            .center
            .map_or_else(|| "-".to_string(), |c| format!("{:?}", &c[..mesh.dim]));
        format!("rotate {} deg about {c}", a.rotate.unwrap_or(0.0))
    };
    let own_motion = |name: &str| match per_marker {
        Some((specs, _)) => specs
            .iter()
            .find(|x| x.marker == name)
            .map_or_else(|| motion_text.clone(), |x| describe(&x.motion, mesh.dim)),
        None => motion_text.clone(),
    };
    markers
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
                motion: own_motion(&m.name),
                max_displacement: max,
            }
        })
        .collect()
}

/// The text form of the report.
pub(super) fn report_text(a: &MoveArgs, r: &MoveReport, dim: usize) -> String {
    let mut options = String::new();
    if r.stiffness != "none" && r.stiffness != "batina" {
        options += &format!(" (stiffness {})", r.stiffness);
    }
    if r.steps > 1 {
        options += &format!(" in {} steps", r.steps);
    }
    if let Some(reach) = a.reach {
        options += &format!(" (reach {reach})");
    }
    if let Some(b) = r.idw_max_bound {
        options += &format!(
            " (fast, θ {}, error bound {b:.2e} of the motion's spread)",
            a.idw_theta.unwrap_or(0.0)
        );
    }
    if let Some(rbf) = &r.rbf {
        options += &rbf_words(rbf);
    }
    let mut text = format!(
        "{} -> {}: {} nodes ({} moved, {} fixed), method {}{options}, {} iterations, residual {:.3e}{}\n  {} mesh; inverted cells {}, folded cells {}, degenerate cells {}, {} ratio min {} max {}, max wall angle change {} deg, {:.2} s",
        r.mesh,
        r.outputs.join(", "),
        r.nodes,
        r.moved_nodes,
        r.fixed_nodes,
        r.method,
        r.iterations,
        r.residual,
        if r.converged { "" } else { " (NOT converged)" },
        r.orientation,
        r.inverted_cells,
        r.folded_cells,
        r.degenerate_cells,
        if dim == 3 { "volume" } else { "area" },
        fmt_opt(r.min_area_ratio),
        fmt_opt(r.max_area_ratio),
        fmt_opt(r.max_wall_angle_change_deg),
        r.seconds
    );
    if r.listed_reversed_cells > 0 {
        text.push_str(&format!(
            "\n  {} cells {} in the input (valid: measured against their own orientation; SU2 reorders them)",
            r.listed_reversed_cells,
            crate::orientation::OrientationSummary::reversed_words(dim)
        ));
    }
    text.push_str(&format!("\n  max displacement {:.6e}", r.max_displacement));
    for m in &r.markers {
        text.push_str(&format!(
            "\n  marker {}: {} nodes, {}, max displacement {:.6e}",
            m.marker, m.nodes, m.motion, m.max_displacement
        ));
    }
    if !r.sliding_markers.is_empty() {
        text.push_str(&format!(
            "\n  sliding {}: {} nodes, max distance from their planes {:.3e}",
            r.sliding_markers.join(", "),
            r.sliding_nodes,
            r.max_slide_offset
        ));
    }
    text
}

/// ` (wendland radius 12, 80 of 460 centres, boundary error 1.2e-4 corrected over 1.0)`.
fn rbf_words(r: &crate::engine::RbfInfo) -> String {
    format!(
        " ({}{}, {} of {} centres, boundary error {:.2e} corrected over {})",
        match r.kernel {
            crate::engine::RbfFunction::Wendland => "wendland",
            crate::engine::RbfFunction::Tps => "tps",
        },
        r.radius
            .map_or_else(String::new, |x| format!(" radius {x}")),
        r.centres,
        r.boundary_nodes,
        r.max_error,
        r.correction_radius
    )
}
