//! `deform tangent` and `deform adjoint` on Plot3D grids: the derivative of `deform move`'s
//! TFI (`--method tfi`, the quaternion TFI, or `tfi-displacement`) with respect to the
//! positions of the `--wall` face's nodes, linearised about the rigid motion of `--rotate` /
//! `--translate` (`--axis`, `--center`: the move's own options; none: the undeformed grid).
//! Nodes are numbered block by block in Plot3D order (`i` fastest), from 0; blocks the wall
//! does not name stay, as in the move, so their derivative is zero. The map of one block is
//! in `crate::engine::tfi_sensitivity`.

use serde_json::json;

use super::read::{parse_perturbation, parse_sensitivity};
use super::{outcome, write_csv};
use crate::args::{
    check_rbf_args, AdjointArgs, SensitivityMethod, SensitivitySetup, TangentArgs, WallArg,
    WallBlocks,
};
use crate::args::{DEFAULT_IDW_EXPONENT, DEFAULT_MAX_ITER, DEFAULT_TOL};
use crate::commands::r#move::grid::{block_dim, check_wall, rigid_motion, wall_face, wall_moves};
use crate::engine::{tfi_block_adjoint, tfi_block_tangent, tfi_wall_nodes, Motion};
use crate::error::CliError;
use crate::files::{io_err, read_bytes, read_plot3d};
use crate::formats::plot3d::{Plot3dGrid, Plot3dOptions};
use crate::output::Staged;
use crate::report::{value_name, Outcome};

/// An option the Plot3D path does not take.
fn refuse(what: &str) -> Result<(), CliError> {
    Err(CliError::Invalid(format!(
        "{what} does not apply to a Plot3D grid (TFI: --wall with --rotate or --translate, no \
         solve, no IDW, no markers)"
    )))
}

/// The setup with `--method` resolved (tfi by default), after every check that needs no file.
fn check(setup: &SensitivitySetup) -> Result<(SensitivitySetup, WallArg, Motion), CliError> {
    let method = setup.method.unwrap_or(SensitivityMethod::Tfi);
    if !matches!(
        method,
        SensitivityMethod::Tfi | SensitivityMethod::TfiDisplacement
    ) {
        return Err(CliError::NotAvailable {
            feature: "this method on Plot3D grids",
            needs: "--method tfi or tfi-displacement with --wall FACE (or an SU2 mesh)",
        });
    }
    let flags = [
        (
            setup.deformed.is_some(),
            "--deformed (the motion is --rotate/--translate)",
        ),
        (setup.stiffness.is_some(), "--stiffness"),
        (setup.poisson.is_some(), "--poisson"),
        (setup.steps != 1, "--steps"),
        (!setup.wall_markers.is_empty(), "--wall-markers"),
        (setup.idw_theta.is_some(), "--idw-theta"),
        (setup.idw_exponent != DEFAULT_IDW_EXPONENT, "--idw-exponent"),
        (setup.tol != DEFAULT_TOL, "--tol"),
        (setup.max_iter != DEFAULT_MAX_ITER, "--max-iter"),
        (setup.amg_strength.is_some(), "--amg-strength"),
    ];
    if let Some((_, what)) = flags.iter().find(|(given, _)| *given) {
        refuse(what)?;
    }
    check_rbf_args(&setup.rbf, false)?;
    let g = &setup.grid;
    let Some(wall) = g.wall else {
        return Err(CliError::Invalid(
            "--wall FACE (imin, imax, jmin, jmax, kmin, kmax) is required for a Plot3D grid: \
             the face `deform move --wall` moved"
                .into(),
        ));
    };
    let motion = if g.rotate.is_none() && g.translate.is_none() {
        Motion::Translate([0.0; 3])
    } else {
        rigid_motion(g.rotate, &g.translate, &g.axis, &g.center)?
    };
    let resolved = SensitivitySetup {
        method: Some(method),
        ..setup.clone()
    };
    Ok((resolved, wall, motion))
}

/// The grid, the first node of each block, which blocks move and their TFI dimension, and
/// the wall nodes (global numbers, ascending).
struct Loaded {
    grid: Plot3dGrid,
    layout: String,
    offsets: Vec<usize>,
    dims: Vec<Option<usize>>,
    wall_nodes: Vec<u32>,
}

impl Loaded {
    fn read(setup: &SensitivitySetup, wall: WallArg) -> Result<Self, CliError> {
        let (grid, layout) = read_plot3d(&setup.mesh, &Plot3dOptions::default())?;
        let count = grid.blocks.len();
        check_wall(&setup.mesh, wall.blocks, wall.face, count)?;
        let (mut offsets, mut dims, mut wall_nodes) = (vec![0], Vec::new(), Vec::new());
        for (b, blk) in grid.blocks.iter().enumerate() {
            let start = offsets[b];
            offsets.push(start + blk.points.len());
            if !wall_moves(wall.blocks, count, b) {
                dims.push(None);
                continue;
            }
            dims.push(Some(block_dim(grid.dim, blk, wall.face, b, &setup.mesh)?));
            let local = tfi_wall_nodes(blk.dims, wall_face(wall.face))?;
            wall_nodes.extend(local.iter().map(|&p| (start + p as usize) as u32));
        }
        if u32::try_from(offsets[count]).is_err() {
            return Err(CliError::Invalid(format!(
                "{}: more than 2^32 grid points",
                setup.mesh.display()
            )));
        }
        Ok(Loaded {
            grid,
            layout: layout.to_string(),
            offsets,
            dims,
            wall_nodes,
        })
    }

    fn len(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// `f(block, TFI dimension, the block's slice of values)` on every moving block, into a
    /// field of the whole grid (zero on the blocks that stay).
    fn per_block(
        &self,
        values: &[[f64; 3]],
        f: impl Fn(usize, usize, &[[f64; 3]]) -> Result<Vec<[f64; 3]>, CliError>,
    ) -> Result<Vec<[f64; 3]>, CliError> {
        let mut out = vec![[0.0; 3]; self.len()];
        for (b, dim) in self.dims.iter().enumerate() {
            let Some(dim) = *dim else { continue };
            let range = self.offsets[b]..self.offsets[b + 1];
            let r = f(b, dim, &values[range.clone()])?;
            out[range].copy_from_slice(&r);
        }
        Ok(out)
    }

    /// A perturbation out of the plane of a block measured in 2D (a constant-z plane of a
    /// 3D file) is refused: TFI keeps its `z`, so the map does not see it.
    fn check_planar(&self, v: &[[f64; 3]], path: &std::path::Path) -> Result<(), CliError> {
        for (b, dim) in self.dims.iter().enumerate() {
            let range = self.offsets[b]..self.offsets[b + 1];
            if *dim == Some(2) && self.grid.dim == 3 {
                if let Some(i) = range.clone().find(|&i| v[i][2] != 0.0) {
                    return Err(CliError::Invalid(format!(
                        "{}: node {i}: block {} is a constant-z plane, moved in 2D: its dz \
                         must be 0",
                        path.display(),
                        b + 1
                    )));
                }
            }
        }
        Ok(())
    }

    /// The run's facts for the JSON report.
    fn report(&self, o: &mut Outcome, wall: WallArg) {
        let moved: Vec<usize> = (self.dims.iter().enumerate())
            .filter(|(_, d)| d.is_some())
            .map(|(b, _)| b + 1)
            .collect();
        let face = value_name(&wall.face);
        o.json["format"] = json!(format!("Plot3D {}", self.layout));
        o.json["blocks"] = json!(self.grid.blocks.len());
        o.json["wall"] = json!(match wall.blocks {
            WallBlocks::Unnamed => face,
            WallBlocks::One(n) => format!("{n}:{face}"),
            WallBlocks::All => format!("all:{face}"),
        });
        o.json["moved_blocks"] = json!(moved);
        o.json["wall_nodes"] = json!(self.wall_nodes.len());
    }
}

/// `deform tangent` on a Plot3D grid.
pub(super) fn tangent(a: &TangentArgs) -> Result<Outcome, CliError> {
    let (setup, wall, motion) = check(&a.setup)?;
    let quaternion = setup.method() == SensitivityMethod::Tfi;
    let g = Loaded::read(&setup, wall)?;
    let text = String::from_utf8_lossy(&read_bytes(&a.perturbation)?).into_owned();
    let on = (&g.wall_nodes[..], "on a moving --wall face");
    let v = parse_perturbation(&text, g.len(), g.grid.dim, on, &a.perturbation)?;
    g.check_planar(&v, &a.perturbation)?;
    let face = wall_face(wall.face);
    let dx = g.per_block(&v, |b, dim, v| {
        let blk = &g.grid.blocks[b];
        tfi_block_tangent(dim, blk.dims, &blk.points, face, &motion, quaternion, v)
            .map_err(|e| e.within(&format!("block {}", b + 1)).in_file(&setup.mesh))
    })?;
    let d = g.grid.dim;
    let rows: Vec<(u32, Vec<f64>)> = (dx.iter().enumerate())
        .map(|(i, x)| (i as u32, x[..d].to_vec()))
        .collect();
    let header = if d == 2 {
        "node,dx,dy"
    } else {
        "node,dx,dy,dz"
    };
    let mut staged = Staged::new();
    write_csv(&mut staged, &a.out, header, &rows)?;
    staged.commit().map_err(io_err(&a.out))?;
    let mut o = outcome("tangent", &setup, rows.len(), None, &a.out);
    g.report(&mut o, wall);
    Ok(o)
}

/// `deform adjoint` on a Plot3D grid.
pub(super) fn adjoint(a: &AdjointArgs) -> Result<Outcome, CliError> {
    let (setup, wall, motion) = check(&a.setup)?;
    if !a.markers.is_empty() {
        refuse("--markers (the rows are the --wall faces' nodes)")?;
    }
    if a.config.is_some() || a.grad_out.is_some() {
        refuse("--config/--grad-out (SU2 design variables)")?;
    }
    let quaternion = setup.method() == SensitivityMethod::Tfi;
    let g = Loaded::read(&setup, wall)?;
    let text = String::from_utf8_lossy(&read_bytes(&a.sensitivity)?).into_owned();
    let w = parse_sensitivity(&text, g.len(), g.grid.dim, &a.sensitivity)?;
    let face = wall_face(wall.face);
    let back = g.per_block(&w, |b, dim, w| {
        let blk = &g.grid.blocks[b];
        tfi_block_adjoint(dim, blk.dims, &blk.points, face, &motion, quaternion, w)
            .map_err(|e| e.within(&format!("block {}", b + 1)).in_file(&setup.mesh))
    })?;
    let points: Vec<&[f64; 3]> = g.grid.blocks.iter().flat_map(|b| &b.points).collect();
    let d = g.grid.dim;
    let rows: Vec<(u32, Vec<f64>)> = (g.wall_nodes.iter())
        .map(|&i| {
            let (p, s) = (points[i as usize], back[i as usize]);
            (i, p[..d].iter().chain(&s[..d]).copied().collect())
        })
        .collect();
    let header = if d == 2 {
        "node,x,y,dJ/dx,dJ/dy"
    } else {
        "node,x,y,z,dJ/dx,dJ/dy,dJ/dz"
    };
    let mut staged = Staged::new();
    write_csv(&mut staged, &a.out, header, &rows)?;
    staged.commit().map_err(io_err(&a.out))?;
    let mut o = outcome("adjoint", &setup, rows.len(), None, &a.out);
    g.report(&mut o, wall);
    Ok(o)
}
