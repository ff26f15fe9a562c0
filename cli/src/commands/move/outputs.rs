//! The files `deform move` writes on an SU2 mesh: the mesh (SU2 or CGNS), `--vtk` with the
//! displacement and quality fields, `--plot` (a picture of the moved markers' surroundings, or
//! of a 3D mesh's section through them). All staged; nothing is renamed into place on failure.

use crate::args::MoveArgs;
use crate::engine::{MoveResult, QualitySummary};
use crate::error::CliError;
use crate::files::{io_err, write_su2_zone, ZonedSu2};
use crate::formats::su2::Su2Mesh;
use crate::formats::vtk::{write_vtu, VtkEncoding, VtkField};
use crate::formats::CellList;
use crate::output::Staged;
use crate::plot::{bounding_window, has_volume_cells, slice_z, zoom, Picture, Window};
use crate::report::{value_name, write_picture};

/// Writes every output of a successful run; returns their paths in the order written.
pub(super) fn write_outputs(
    a: &MoveArgs,
    zoned: Option<&ZonedSu2>,
    out_mesh: &Su2Mesh,
    result: &MoveResult,
    q: &QualitySummary,
    moved_lists: &[&CellList],
) -> Result<Vec<String>, CliError> {
    let mut staged = Staged::new();
    let mut outputs = vec![a.out.display().to_string()];
    staged
        .write(&a.out, |f| {
            write_su2_zone((&a.mesh, &a.out), zoned, out_mesh, f)
        })
        .map_err(io_err(&a.out))?;
    if let Some(v) = &a.vtk {
        write_vtk(&mut staged, v, out_mesh, result, q)?;
        outputs.push(v.display().to_string());
    }
    if let Some(p) = &a.plot {
        let title = format!(
            "{} {}: {} inverted, {} folded",
            a.mesh.display(),
            value_name(&a.method()),
            q.inverted_cells.unwrap_or(0),
            q.folded_cells
        );
        write_plot(&mut staged, p, &title, out_mesh, q, moved_lists)?;
        outputs.push(p.display().to_string());
    }
    staged.commit().map_err(io_err(&a.out))?;
    Ok(outputs)
}

/// `--vtk`: the moved mesh with its displacement (points) and quality (cells).
fn write_vtk(
    staged: &mut Staged,
    v: &std::path::Path,
    out_mesh: &Su2Mesh,
    result: &MoveResult,
    q: &QualitySummary,
) -> Result<(), CliError> {
    let disp: Vec<f64> = result.displacement.iter().flatten().copied().collect();
    let inverted: Vec<f64> = q
        .inverted
        .iter()
        .map(|&b| if b { 1.0 } else { 0.0 })
        .collect();
    let field = |name, values| VtkField {
        name,
        components: 1,
        values,
    };
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
                    field("scaled_jacobian", &q.scaled_jacobian),
                    field("area_ratio", &q.ratio),
                    field("inverted", &inverted),
                ],
                VtkEncoding::Base64,
            )
        })
        .map_err(io_err(v))
}

/// `--plot`: the moved markers' surroundings with inverted or folded cells highlighted; a 3D
/// mesh is drawn as its section by the plane through the middle of the moved markers
/// (z = const): all edges projected on x–y would be a tangle.
fn write_plot(
    staged: &mut Staged,
    p: &std::path::Path,
    title: &str,
    out_mesh: &Su2Mesh,
    q: &QualitySummary,
    moved_lists: &[&CellList],
) -> Result<(), CliError> {
    let points = &out_mesh.points;
    let folded_or_inverted: Vec<bool> = q
        .inverted
        .iter()
        .zip(&q.scaled_jacobian)
        .map(|(&i, &j)| i || j <= 0.0)
        .collect();
    if !has_volume_cells(&out_mesh.elements) {
        let pic = Picture {
            points,
            cells: &out_mesh.elements,
            boundaries: moved_lists,
            highlight: &folded_or_inverted,
            title,
            shading: None,
        };
        return write_picture(staged, p, &pic, marker_window(points, moved_lists), 1200);
    }
    let zs = moved_lists
        .iter()
        .flat_map(|l| l.nodes.iter())
        .filter_map(|&n| points.get(n as usize).map(|p| p[2]));
    let (lo, hi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
        (lo.min(z), hi.max(z))
    });
    let z0 = if lo <= hi { 0.5 * (lo + hi) } else { 0.0 };
    let section = slice_z(points, &out_mesh.elements, moved_lists, z0);
    let highlight: Vec<bool> = section
        .source
        .iter()
        .map(|&c| folded_or_inverted.get(c).copied().unwrap_or(false))
        .collect();
    let boundaries: Vec<&CellList> = section.boundaries.iter().collect();
    let title = format!("{title} (section z = {z0:.6})");
    let pic = Picture {
        points: &section.points,
        cells: &section.cells,
        boundaries: &boundaries,
        highlight: &highlight,
        title: &title,
        shading: None,
    };
    let window = if boundaries.iter().all(|b| b.is_empty()) {
        bounding_window(&section.points)
    } else {
        marker_window(&section.points, &boundaries)
    };
    write_picture(staged, p, &pic, window, 1200)
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
