//! `deform move` on Plot3D grids: Samareh's TFI (quaternion or displacement) from a moved
//! wall face.

use std::time::Instant;

use deform_kernel::Direction;
use serde_json::json;

use crate::args::{Coords, FaceArg, Method, MoveArgs, WallArg, WallBlocks};
use crate::engine::QualitySummary;
use crate::formats::plot3d::{Plot3dGrid, Plot3dOptions};
use crate::output::Staged;

use crate::error::CliError;
use crate::files::{cell_dim, file_kind, io_err, read_plot3d, write_grid, FileKind};
use crate::report::{add_summary, fmt_opt, seconds, value_name, volume_words, Outcome};

/// `deform move` on a Plot3D grid: the `--wall` face of every block moves rigidly, the opposite
/// face stays, transfinite interpolation (quaternion or displacement) in between.
pub(crate) fn move_grid(a: &MoveArgs) -> Result<Outcome, CliError> {
    let t0 = Instant::now();
    let Some(WallArg { blocks, face }) = a.wall else {
        return Err(CliError::Invalid(
            "--wall FACE (imin, imax, jmin, jmax, kmin, kmax) is required for a Plot3D grid".into(),
        ));
    };
    check_grid_args(a)?;
    let (mut grid, layout) = read_plot3d(&a.mesh, &Plot3dOptions::default())?;
    let count = grid.blocks.len();
    check_wall(&a.mesh, blocks, face, count)?;
    let motion = grid_motion(a)?;
    let moves = |b: usize| wall_moves(blocks, count, b);
    let moved = move_blocks(a, &mut grid, face, &motion, &moves)?;
    let q = &moved.quality;
    super::check_new_folds(q, a.allow_folds, &a.mesh)?;
    let mut staged = Staged::new();
    staged
        .write(&a.out, |f| write_grid(&a.mesh, &a.out, &grid, &layout, f))
        .map_err(io_err(&a.out))?;
    staged.commit().map_err(io_err(&a.out))?;
    super::warn_new_folds(q);
    let moved_blocks: Vec<usize> = (0..count).filter(|&b| moves(b)).map(|b| b + 1).collect();
    let wall = match blocks {
        WallBlocks::Unnamed => value_name(&face),
        WallBlocks::One(n) => format!("{n}:{}", value_name(&face)),
        WallBlocks::All => format!("all:{}", value_name(&face)),
    };
    let json = json!({
        "command": "move",
        "mesh": a.mesh.display().to_string(),
        "outputs": [a.out.display().to_string()],
        "format": format!("Plot3D {layout}"),
        "blocks": count,
        "method": value_name(&a.method()),
        "wall": wall,
        "moved_blocks": moved_blocks,
        "max_displacement": moved.max_displacement,
        "inverted_cells": q.inverted_cells.unwrap_or(0),
        "folded_cells": q.folded_cells,
        "new_invalid_cells": q.new_failures(),
        "degenerate_cells": q.degenerate_cells,
        "orientation": q.orientation,
        "min_area_ratio": q.min_area_ratio,
        "max_area_ratio": q.max_area_ratio,
        "min_scaled_jacobian": q.min_scaled_jacobian,
        "seconds": seconds(t0),
    });
    let json = volume_words(json, moved.dim);
    let text = format!(
        "{} -> {}: {count} block(s), method {}, wall {wall}: max displacement {:.6e}, inverted cells {}, folded cells {}, degenerate cells {}, ratio min {} max {}",
        a.mesh.display(),
        a.out.display(),
        value_name(&a.method()),
        moved.max_displacement,
        q.inverted_cells.unwrap_or(0),
        q.folded_cells,
        q.degenerate_cells,
        fmt_opt(q.min_area_ratio),
        fmt_opt(q.max_area_ratio),
    );
    Ok(Outcome { json, text })
}

/// The options a Plot3D move does not take (checked before the grid is read).
fn check_grid_args(a: &MoveArgs) -> Result<(), CliError> {
    if a.steps > 1 {
        return Err(CliError::NotAvailable {
            feature: "--steps on Plot3D grids",
            needs: "one step (TFI interpolates the whole motion directly)",
        });
    }
    if !a.slide.is_empty() {
        return Err(CliError::NotAvailable {
            feature: "--slide on Plot3D grids",
            needs: "an SU2 mesh with the symmetry plane as a marker",
        });
    }
    if !a.markers.is_empty()
        || a.displacements.is_some()
        || a.surface_positions.is_some()
        || a.motions.is_some()
    {
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
    Ok(())
}

/// `--wall BLOCK:FACE` against the `count` blocks of the grid `mesh` (shared with the
/// sensitivities).
pub(crate) fn check_wall(
    mesh: &std::path::Path,
    blocks: WallBlocks,
    face: FaceArg,
    count: usize,
) -> Result<(), CliError> {
    match blocks {
        WallBlocks::Unnamed if count > 1 => Err(CliError::Invalid(format!(
            "{}: the grid has {count} blocks: say whose {} face moves, e.g. --wall 1:{1} (blocks 1 to {count}), or --wall all:{1} for every block",
            mesh.display(),
            value_name(&face)
        ))),
        WallBlocks::One(n) if n > count => Err(CliError::Invalid(format!(
            "{}: --wall {n}:{}: the grid has {count} block(s)",
            mesh.display(),
            value_name(&face)
        ))),
        _ => Ok(()),
    }
}

/// Whether block `b` (0-based) of a grid of `count` blocks moves under `--wall`.
pub(crate) fn wall_moves(blocks: WallBlocks, count: usize, b: usize) -> bool {
    match blocks {
        WallBlocks::All => true,
        WallBlocks::One(n) => n == b + 1,
        WallBlocks::Unnamed => count == 1,
    }
}

/// The wall's rigid motion: `--rotate` (about `--axis`, `--center`) or `--translate`.
fn grid_motion(a: &MoveArgs) -> Result<crate::motion::Motion, CliError> {
    rigid_motion(a.rotate, &a.translate, &a.axis, &a.center)
}

/// A wall's rigid motion from `--rotate` (about `--axis`, `--center`) or `--translate`
/// (shared with the sensitivities).
pub(crate) fn rigid_motion(
    rotate: Option<f64>,
    translate: &Option<Coords>,
    axis: &Option<Coords>,
    center: &Option<Coords>,
) -> Result<crate::motion::Motion, CliError> {
    let coords = |c: &Option<Coords>, fill: f64| {
        c.as_ref().map(|Coords(v)| {
            [
                v.first().copied().unwrap_or(fill),
                v.get(1).copied().unwrap_or(fill),
                v.get(2).copied().unwrap_or(fill),
            ]
        })
    };
    match (rotate, coords(translate, 0.0)) {
        (Some(deg), None) if deg.is_finite() => Ok(crate::motion::Motion::Rotate {
            degrees: deg,
            axis: coords(axis, 0.0).unwrap_or([0.0, 0.0, 1.0]),
            center: coords(center, 0.0),
        }),
        (None, Some(t)) if t.iter().all(|x| x.is_finite()) => {
            Ok(crate::motion::Motion::Translate(t))
        }
        _ => Err(CliError::Invalid(
            "--rotate DEG or --translate DX,DY[,DZ] (finite) moves the wall of a Plot3D grid"
                .into(),
        )),
    }
}

/// What moving the blocks did: their quality together, the largest displacement, the
/// dimension the cells were measured in.
struct MovedBlocks {
    quality: QualitySummary,
    max_displacement: f64,
    dim: usize,
}

/// TFI on every block `moves` names, in place.
fn move_blocks(
    a: &MoveArgs,
    grid: &mut Plot3dGrid,
    face: FaceArg,
    motion: &crate::motion::Motion,
    moves: &dyn Fn(usize) -> bool,
) -> Result<MovedBlocks, CliError> {
    let wall = wall_face(face);
    let quaternion = a.method() == Method::Tfi;
    let mut total: Option<QualitySummary> = None;
    let mut max_displacement = 0.0f64;
    let mut measured_dim = 2;
    for (b, blk) in grid.blocks.iter_mut().enumerate() {
        if !moves(b) {
            continue;
        }
        let dim = block_dim(grid.dim, blk, face, b, &a.mesh)?;
        measured_dim = measured_dim.max(dim);
        let new = crate::engine::tfi_block(dim, blk.dims, &blk.points, wall, motion, quaternion)
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
    let Some(quality) = total else {
        return Err(CliError::Invalid("the grid has no blocks".into()));
    };
    Ok(MovedBlocks {
        quality,
        max_displacement,
        dim: measured_dim,
    })
}

/// The engine's face of `--wall`'s face.
pub(crate) fn wall_face(face: FaceArg) -> crate::engine::Face {
    let (direction, max) = match face {
        FaceArg::Imin => (Direction::I, false),
        FaceArg::Imax => (Direction::I, true),
        FaceArg::Jmin => (Direction::J, false),
        FaceArg::Jmax => (Direction::J, true),
        FaceArg::Kmin => (Direction::K, false),
        FaceArg::Kmax => (Direction::K, true),
    };
    crate::engine::Face { direction, max }
}

/// The dimension TFI runs block `b` (0-based) in, or why it cannot move `face` (shared with
/// the sensitivities).
pub(crate) fn block_dim(
    grid_dim: usize,
    blk: &crate::formats::plot3d::Plot3dBlock,
    face: FaceArg,
    b: usize,
    mesh: &std::path::Path,
) -> Result<usize, CliError> {
    let dim = cell_dim(grid_dim, blk);
    if dim == 2 && wall_face(face).direction == Direction::K {
        return Err(CliError::Invalid(format!(
            "{}: block {}: --wall {} needs a 3D block",
            mesh.display(),
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
    Ok(dim)
}
