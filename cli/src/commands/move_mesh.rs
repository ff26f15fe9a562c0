//! `deform move` on SU2 meshes: marker motions, displacement or surface-position files,
//! propagated by springs, the quaternion method or IDW.

use std::time::Instant;

use serde::Serialize;
use serde_json::json;

use crate::args::{Coords, Method, MoveArgs, Solver, StiffnessArg};
use crate::engine::{
    run_move_in_steps, Motion, MoveInput, MoveMethod, MoveSolver, QualitySummary, SlideMarker,
    Stiffness,
};
use crate::formats::displacements::{parse_displacements, parse_surface_positions};
use crate::formats::motions::{parse_motions, MarkerMotionSpec};
use crate::formats::su2::Su2Mesh;
use crate::formats::vtk::{write_vtu, VtkEncoding, VtkField};
use crate::formats::CellList;
use crate::output::Staged;
use crate::plot::{bounding_window, has_volume_cells, slice_z, zoom, Picture, Window};

use super::move_grid::move_grid;
use crate::error::CliError;
use crate::files::{
    file_kind, input_kind, io_err, is_cgns_path, marker_nodes, marker_union, read_bytes,
    read_su2_zone, write_su2_zone, FileKind,
};
use crate::report::{fmt_opt, seconds, value_name, volume_words, write_picture, Outcome};

pub(crate) fn move_mesh(
    a: &MoveArgs,
    quiet: bool,
    split: Option<&dyn crate::split::Splitter>,
) -> Result<Outcome, CliError> {
    let su2 = input_kind(&a.mesh)? == FileKind::Su2;
    // Without --method: quaternion TFI on a Plot3D grid (`a.method()` gives quaternion else).
    let resolved;
    let a = if !su2 && a.method.is_none() {
        resolved = MoveArgs {
            method: Some(Method::Tfi),
            ..a.clone()
        };
        &resolved
    } else {
        a
    };
    let tfi = matches!(a.method(), Method::Tfi | Method::TfiDisplacement);
    if a.stiffness() != StiffnessArg::Batina && (tfi || a.method() == Method::Idw) {
        return Err(CliError::Invalid(format!(
            "--stiffness {} applies to the spring, angle-spring and quaternion methods; --method {} has no springs",
            value_name(&a.stiffness()),
            value_name(&a.method())
        )));
    }
    super::move_elasticity::check_args(a)?;
    if !su2 {
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
    if a.markers.is_empty() && a.motions.is_none() {
        return Err(CliError::Invalid(
            "--marker (or --motions FILE) is required for SU2 meshes (the markers that move)"
                .into(),
        ));
    }
    if file_kind(&a.out) != Some(FileKind::Su2) && !is_cgns_path(&a.out) {
        return Err(CliError::Invalid(format!(
            "{}: --out must be a .su2 file (or .cgns)",
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
    // A multi-zone file: the zone of the named markers (the others are written back unchanged).
    let names: [&[String]; 2] = [&a.markers, &a.slide];
    crate::files::check_su2_output(&a.mesh, &a.out)?;
    let (mesh, zoned) = read_su2_zone(&a.mesh, &names, a.motions.as_deref())?;
    crate::guard::check_memory(
        &a.mesh,
        "deform move on this mesh",
        crate::guard::move_estimate(mesh.points.len(), mesh.elements.nodes.len()),
    )?;
    // --motions: the markers and their own rigid motions, as one displacement field.
    let per_marker = match &a.motions {
        Some(path) => Some(marker_motions_field(&mesh, path, a.steps)?),
        None => None,
    };
    let markers: Vec<String> = match &per_marker {
        Some((specs, _)) => specs.iter().map(|m| m.marker.clone()).collect(),
        None => a.markers.clone(),
    };
    let moved = marker_nodes(&mesh, &markers, &a.mesh)?;
    if moved.is_empty() {
        return Err(CliError::Invalid("the named markers have no nodes".into()));
    }
    // --slide markers: known, not also moved, named once.
    marker_nodes(&mesh, &a.slide, &a.mesh)?;
    for (k, name) in a.slide.iter().enumerate() {
        if markers.contains(name) {
            return Err(CliError::Invalid(format!(
                "marker {name:?} is given to both --marker and --slide (a marker either moves or slides)"
            )));
        }
        if a.slide[..k].contains(name) {
            return Err(CliError::Invalid(format!("--slide {name} is given twice")));
        }
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
    let motion = if let Some((_, field)) = &per_marker {
        Motion::Field(field.clone())
    } else if let Some((path, absolute)) = table {
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
    if let Some(r) = a.reach {
        if !matches!(a.method(), Method::Quaternion | Method::Idw) {
            return Err(CliError::Invalid(format!(
                "--reach applies to the quaternion and idw methods, not {}",
                value_name(&a.method())
            )));
        }
        if !(r.is_finite() && r > 0.0) {
            return Err(CliError::Invalid(
                "--reach must be a positive distance".into(),
            ));
        }
    }
    if let Some(theta) = a.idw_theta {
        if a.method() != Method::Idw {
            return Err(CliError::Invalid(format!(
                "--idw-theta applies to --method idw, not {}",
                value_name(&a.method())
            )));
        }
        if !(0.0..1.0).contains(&theta) {
            return Err(CliError::Invalid("--idw-theta must be in [0, 1)".into()));
        }
        if a.idw_tolerance.is_nan() || a.idw_tolerance < 0.0 {
            return Err(CliError::Invalid(
                "--idw-tolerance must be a non-negative number (inf: θ alone)".into(),
            ));
        }
    }
    if !(a.idw_exponent.is_finite() && a.idw_exponent > 0.0) {
        return Err(CliError::Invalid("--idw-exponent must be positive".into()));
    }
    let t0 = Instant::now();
    let moved_lists: Vec<&CellList> = mesh
        .markers
        .iter()
        .filter(|m| markers.contains(&m.name))
        .map(|m| &m.elements)
        .collect();
    let fixed_lists: Vec<&CellList> = mesh
        .markers
        .iter()
        .filter(|m| !markers.contains(&m.name) && !a.slide.contains(&m.name))
        .map(|m| &m.elements)
        .collect();
    let slide_markers: Vec<SlideMarker<'_>> = mesh
        .markers
        .iter()
        .filter(|m| a.slide.contains(&m.name))
        .map(|m| SlideMarker {
            name: &m.name,
            elements: &m.elements,
        })
        .collect();
    let method = match a.method() {
        Method::Quaternion => MoveMethod::Quaternion,
        Method::Idw => MoveMethod::Idw,
        Method::Spring => MoveMethod::Spring,
        Method::AngleDirect => MoveMethod::AngleDirect,
        Method::AngleCg => MoveMethod::AngleCg,
        // Not a spring propagation: run by `move_elasticity::run`, which reads the rest.
        Method::Elasticity => MoveMethod::Spring,
        Method::Tfi | Method::TfiDisplacement => unreachable_tfi()?,
    };
    let solver = match a.solver {
        Solver::Amg => MoveSolver::Amg,
        Solver::Cg => MoveSolver::Cg,
        Solver::CgSsor => MoveSolver::CgSsor,
        Solver::Gs => MoveSolver::GaussSeidel,
        Solver::Jacobi => MoveSolver::Jacobi,
    };
    if let Some(s) = split {
        s.check_move(a)?;
    }
    let input = MoveInput {
        split,
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
        idw_fast: a.idw_theta.map(|theta| (theta, a.idw_tolerance)),
        reach: a.reach,
        stiffness: match a.stiffness() {
            StiffnessArg::Batina | StiffnessArg::Constant => Stiffness::Batina,
            StiffnessArg::WallDistance => Stiffness::WallDistance,
            StiffnessArg::InverseVolume => Stiffness::InverseVolume,
        },
    };
    let spinner = crate::progress::spinner("deforming", quiet);
    let result = if a.method() == Method::Elasticity {
        super::move_elasticity::run(a, &input)
    } else {
        run_move_in_steps(&input, &slide_markers, a.steps as usize)
    };
    spinner.finish_and_clear();
    let mut result = result.map_err(|e| e.in_file(&a.mesh))?;
    if !result.converged && !a.allow_unconverged {
        return Err(CliError::Unconverged(format!(
            "{}: the {} solve did not converge: relative residual {:.3e} after {} iterations (--tol {:e}, --max-iter {}); nothing was written (--allow-unconverged writes it anyway)",
            a.mesh.display(),
            value_name(&a.method()),
            result.residual,
            result.iterations,
            a.tol,
            a.max_iter
        )));
    }
    if split.is_some_and(|s| !s.is_root()) {
        // The other processes helped with the solves; the first one writes and reports.
        return Ok(Outcome {
            json: serde_json::Value::Null,
            text: String::new(),
        });
    }
    for (node, p) in &exact_positions {
        if let Some(x) = result.deformed.get_mut(*node as usize) {
            *x = *p;
        }
    }
    let wall = marker_union(&mesh, &markers, &a.mesh)?;
    let q = crate::engine::quality(
        mesh.dim,
        &mesh.elements,
        &result.deformed,
        Some(&mesh.points),
        Some(&wall),
    )
    .map_err(|e| e.in_file(&a.mesh))?;
    check_new_folds(&q, a.allow_folds, &a.mesh)?;
    let out_mesh = Su2Mesh {
        points: result.deformed.clone(),
        ..mesh.clone()
    };
    let mut staged = Staged::new();
    let mut outputs = vec![a.out.display().to_string()];
    staged
        .write(&a.out, |f| {
            write_su2_zone((&a.mesh, &a.out), zoned.as_ref(), &out_mesh, f)
        })
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
            value_name(&a.method()),
            q.inverted_cells.unwrap_or(0),
            q.folded_cells
        );
        let folded_or_inverted: Vec<bool> = q
            .inverted
            .iter()
            .zip(&q.scaled_jacobian)
            .map(|(&i, &j)| i || j <= 0.0)
            .collect();
        if has_volume_cells(&out_mesh.elements) {
            // A 3D mesh is drawn as its section by the plane through the middle of the moved
            // markers (z = const): all edges projected on x–y would be a tangle.
            let zs = moved_lists
                .iter()
                .flat_map(|l| l.nodes.iter())
                .filter_map(|&n| result.deformed.get(n as usize).map(|p| p[2]));
            let (lo, hi) = zs.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), z| {
                (lo.min(z), hi.max(z))
            });
            let z0 = if lo <= hi { 0.5 * (lo + hi) } else { 0.0 };
            let section = slice_z(&result.deformed, &out_mesh.elements, &moved_lists, z0);
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
            write_picture(&mut staged, p, &pic, window, 1200)?;
        } else {
            let pic = Picture {
                points: &result.deformed,
                cells: &out_mesh.elements,
                boundaries: &moved_lists,
                highlight: &folded_or_inverted,
                title: &title,
                shading: None,
            };
            write_picture(&mut staged, p, &pic, window, 1200)?;
        }
        outputs.push(p.display().to_string());
    }
    staged.commit().map_err(io_err(&a.out))?;
    let norm = |d: &[f64; 3]| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let motion_text = if let Some(p) = &a.motions {
        format!("motions from {}", p.display())
    } else if let Some(p) = &a.displacements {
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
    let marker_motions: Vec<MarkerMotion> = markers
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
                motion: match &per_marker {
                    Some((specs, _)) => specs
                        .iter()
                        .find(|x| x.marker == m.name)
                        .map_or_else(|| motion_text.clone(), |x| describe(&x.motion, mesh.dim)),
                    None => motion_text.clone(),
                },
                max_displacement: max,
            }
        })
        .collect();
    let max_displacement = result.displacement.iter().map(norm).fold(0.0, f64::max);
    let all_markers: Vec<&CellList> = mesh.markers.iter().map(|m| &m.elements).collect();
    let unmarked = crate::validity::unmarked_boundary(&mesh.elements, &all_markers, &mesh.points);
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
                .map_or_else(|| "-".to_string(), |p| super::quality::point_text(p, mesh.dim))
        );
    }
    let report = MoveReport {
        command: "move",
        mesh: a.mesh.display().to_string(),
        outputs,
        nodes: mesh.points.len(),
        cells: mesh.elements.len(),
        method: value_name(&a.method()),
        solver: match a.method() {
            Method::Idw | Method::Tfi | Method::TfiDisplacement => "none".to_string(),
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
        },
        stiffness: match a.method() {
            Method::Idw | Method::Tfi | Method::TfiDisplacement => "none".to_string(),
            _ => value_name(&a.stiffness()),
        },
        steps: a.steps,
        reach: a.reach,
        idw_max_bound: result.idw_max_bound,
        moved_nodes: result.moved_nodes,
        fixed_nodes: result.fixed_nodes,
        sliding_markers: a.slide.clone(),
        sliding_nodes: result.sliding_nodes,
        max_slide_offset: result.max_slide_offset,
        center: result.center,
        iterations: result.iterations,
        residual: result.residual,
        converged: result.converged,
        markers: marker_motions,
        max_displacement,
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
        seconds: seconds(t0),
    };
    if !report.converged {
        eprintln!(
            "deform: warning: the solver did not converge in {} iterations (residual {:.3e}); written because of --allow-unconverged",
            report.iterations, report.residual
        );
    }
    warn_new_folds(&q);
    let text = format!(
        "{} -> {}: {} nodes ({} moved, {} fixed), method {}{}, {} iterations, residual {:.3e}{}\n  {} mesh; inverted cells {}, folded cells {}, degenerate cells {}, {} ratio min {} max {}, max wall angle change {} deg, {:.2} s",
        report.mesh,
        report.outputs.join(", "),
        report.nodes,
        report.moved_nodes,
        report.fixed_nodes,
        report.method,
        if report.stiffness == "none" || report.stiffness == "batina" {
            String::new()
        } else {
            format!(" (stiffness {})", report.stiffness)
        } + &if report.steps > 1 {
            format!(" in {} steps", report.steps)
        } else {
            String::new()
        } + &a.reach.map_or_else(String::new, |r| format!(" (reach {r})"))
            + &report.idw_max_bound.map_or_else(String::new, |b| {
            format!(" (fast, θ {}, error bound {b:.2e} of the motion's spread)", a.idw_theta.unwrap_or(0.0))
        }),
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
    if report.listed_reversed_cells > 0 {
        text.push_str(&format!(
            "\n  {} cells {} in the input (valid: measured against their own orientation; SU2 reorders them)",
            report.listed_reversed_cells,
            crate::orientation::OrientationSummary::reversed_words(mesh.dim)
        ));
    }
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
    if !report.sliding_markers.is_empty() {
        text.push_str(&format!(
            "\n  sliding {}: {} nodes, max distance from their planes {:.3e}",
            report.sliding_markers.join(", "),
            report.sliding_nodes,
            report.max_slide_offset
        ));
    }
    Ok(Outcome {
        text,
        json: volume_words(
            serde_json::to_value(&report).unwrap_or_else(|e| json!({ "error": e.to_string() })),
            mesh.dim,
        ),
    })
}

#[derive(Serialize)]
pub(crate) struct MoveReport {
    command: &'static str,
    mesh: String,
    outputs: Vec<String>,
    nodes: usize,
    cells: usize,
    method: String,
    solver: String,
    stiffness: String,
    steps: u32,
    reach: Option<f64>,
    idw_max_bound: Option<f64>,
    moved_nodes: usize,
    fixed_nodes: usize,
    sliding_markers: Vec<String>,
    sliding_nodes: usize,
    max_slide_offset: f64,
    center: Option<[f64; 3]>,
    iterations: usize,
    residual: f64,
    converged: bool,
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
    seconds: f64,
}

/// The failure policy `move` and `smooth` share: a result with cells that the input did not
/// have inverted or folded is refused (nothing written) unless `allow` (`--allow-folds`).
pub(crate) fn check_new_folds(
    q: &QualitySummary,
    allow: bool,
    mesh: &std::path::Path,
) -> Result<(), CliError> {
    let bad = q.new_failures();
    if bad == 0 || allow {
        return Ok(());
    }
    Err(CliError::Folded(format!(
        "{}: the result has {bad} cell(s) inverted or folded that were valid in the input ({} inverted, {} folded in all); nothing was written (--allow-folds writes it anyway)",
        mesh.display(),
        q.inverted_cells.unwrap_or(0),
        q.folded_cells
    )))
}

/// With `--allow-folds`: says on stderr how many cells the written result spoiled.
pub(crate) fn warn_new_folds(q: &QualitySummary) {
    let bad = q.new_failures();
    if bad > 0 {
        eprintln!(
            "deform: warning: {bad} cell(s) inverted or folded that were valid in the input; written because of --allow-folds"
        );
    }
}

/// TFI never reaches the unstructured path (checked at the top of `move_mesh`).
pub(crate) fn unreachable_tfi() -> Result<MoveMethod, CliError> {
    Err(CliError::NotAvailable {
        feature: "transfinite interpolation on SU2 meshes",
        needs: "a structured Plot3D grid",
    })
}

/// What `move` did to one marker.
#[derive(Serialize)]
pub(crate) struct MarkerMotion {
    marker: String,
    nodes: usize,
    motion: String,
    max_displacement: f64,
}

/// A square window around the moved markers (their bounding box, enlarged by half).
pub(crate) fn marker_window(points: &[[f64; 3]], lists: &[&CellList]) -> Window {
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

/// `(node, displacement)` pairs, ascending by node.
type NodeDisplacements = Vec<(u32, [f64; 3])>;

/// A marker's rigid motion in words, for the report.
fn describe(m: &Motion, dim: usize) -> String {
    match m {
        Motion::Rotate {
            degrees, center, ..
        } => match center {
            Some(c) => format!("rotate {degrees} deg about {:?}", &c[..dim]),
            None => format!("rotate {degrees} deg about its centroid"),
        },
        Motion::Translate(t) => format!("translate {:?}", &t[..dim]),
        Motion::Field(list) => format!("displacements of {} nodes", list.len()),
    }
}

/// Reads a `--motions` file and turns every marker's rigid motion into displacements of its
/// nodes (`(node, d)`, ascending): `c + Q (p − c) − p` for a rotation (centre: given, or the
/// centroid of the marker's nodes), `t` for a translation. A node on two markers must get the
/// same displacement (bit for bit) from both. `--steps` > 1 scales displacements linearly, which
/// would shrink a rotating marker between steps, so it is refused when any marker rotates.
fn marker_motions_field(
    mesh: &Su2Mesh,
    path: &std::path::Path,
    steps: u32,
) -> Result<(Vec<MarkerMotionSpec>, NodeDisplacements), CliError> {
    let bytes = read_bytes(path)?;
    let specs = parse_motions(&bytes, mesh.dim).map_err(|source| CliError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    if steps > 1
        && specs
            .iter()
            .any(|m| matches!(m.motion, Motion::Rotate { .. }))
    {
        return Err(CliError::NotAvailable {
            feature: "--steps with per-marker rotations from --motions",
            needs: "one step, or --rotate for a single rigid rotation in steps",
        });
    }
    let mut field: std::collections::BTreeMap<u32, ([f64; 3], usize)> =
        std::collections::BTreeMap::new();
    for (k, spec) in specs.iter().enumerate() {
        let nodes = marker_nodes(mesh, std::slice::from_ref(&spec.marker), path)?;
        let point = |n: u32| mesh.points.get(n as usize).copied().unwrap_or([0.0; 3]);
        let displacement: Box<dyn Fn([f64; 3]) -> [f64; 3]> = match &spec.motion {
            Motion::Translate(t) => {
                let t = *t;
                Box::new(move |_| t)
            }
            Motion::Rotate {
                degrees,
                axis,
                center,
            } => {
                let c = center.unwrap_or_else(|| {
                    let n = nodes.len().max(1) as f64;
                    let s = nodes.iter().fold([0.0; 3], |s, &i| {
                        let p = point(i);
                        [s[0] + p[0], s[1] + p[1], s[2] + p[2]]
                    });
                    [s[0] / n, s[1] / n, s[2] / n]
                });
                let q = deform_kernel::Quat::from_axis_angle(*axis, degrees.to_radians()).map_err(
                    |source| CliError::Kernel {
                        context: format!("{}: line {}: rotation", path.display(), spec.line),
                        source,
                    },
                )?;
                let dim = mesh.dim;
                Box::new(move |p: [f64; 3]| {
                    let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
                    let mut d = [0, 1, 2].map(|i| c[i] + r[i] - p[i]);
                    if dim == 2 {
                        d[2] = 0.0;
                    }
                    d
                })
            }
            // parse_motions gives rigid motions only.
            Motion::Field(_) => {
                return Err(CliError::Invalid(format!(
                    "{}: line {}: a motion file gives rigid motions only",
                    path.display(),
                    spec.line
                )))
            }
        };
        for &n in &nodes {
            let d = displacement(point(n));
            match field.get(&n) {
                Some((other, j)) if other.map(f64::to_bits) != d.map(f64::to_bits) => {
                    return Err(CliError::Invalid(format!(
                        "{}: node {n} is on markers {:?} and {:?}, which move it differently (lines {} and {})",
                        path.display(),
                        specs[*j].marker,
                        spec.marker,
                        specs[*j].line,
                        spec.line
                    )));
                }
                _ => {
                    field.insert(n, (d, k));
                }
            }
        }
    }
    Ok((specs, field.into_iter().map(|(n, (d, _))| (n, d)).collect()))
}
