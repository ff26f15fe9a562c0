//! The motion, the partitioned solve and the failure policies on each process's local view.

use deform_kernel::spring::{
    partitioned_cg_scratch_len, Preconditioner, SolveOptions, SolveReport,
};
use deform_kernel::Quat;
use deform_mpi::MpiExchange;

use super::comm::{Failed, World};
use super::local::{build, Local};
use super::read::Read;
use crate::args::MoveArgs;
use crate::engine::Motion;
use crate::error::CliError;
use crate::files::marker_nodes;
use crate::formats::CellList;

/// What the solve leaves for the writer and the report.
pub(super) struct Summary {
    /// Deformed coordinates of this process's owned nodes.
    pub deformed: Vec<[f64; 3]>,
    pub iterations: usize,
    pub residual: f64,
    pub converged: bool,
    /// Cells, over all processes, inverted or folded by the motion (valid before).
    pub new_failures: u64,
    /// Of those, the inverted ones (signed measure changed sign).
    pub inverted: u64,
    pub moved: usize,
    pub fixed: usize,
    /// Ghost nodes of this process (one layer).
    pub ghosts: u64,
}

pub(super) fn kernel(context: &str) -> impl Fn(deform_kernel::Error) -> CliError + '_ {
    move |source| CliError::Kernel {
        context: context.into(),
        source,
    }
}

/// The moved markers' nodes and every marker's nodes (moved and fixed), ascending.
fn marker_sets(a: &MoveArgs, r: &Read) -> Result<(Vec<u32>, Vec<u32>), CliError> {
    let mesh = &r.skeleton;
    let moved = marker_nodes(mesh, &a.markers, &a.mesh)?;
    if moved.is_empty() {
        return Err(CliError::Invalid("the named markers have no nodes".into()));
    }
    let others: Vec<String> = (mesh.markers.iter())
        .filter(|m| !a.markers.contains(&m.name))
        .map(|m| m.name.clone())
        .collect();
    let mut boundary = marker_nodes(mesh, &others, &a.mesh)?;
    boundary.extend_from_slice(&moved);
    boundary.sort_unstable();
    boundary.dedup();
    Ok((moved, boundary))
}

/// `--renumber auto` leaves the mesh as numbered (what the serial run decides from the index
/// distance across the cells' edges, summed over the processes); otherwise the serial run
/// would solve in another order, and its bits are not these.
fn check_renumber(world: &World<'_>, a: &MoveArgs, r: &Read) -> Result<(), Failed> {
    let d = crate::renumber::cell_distance(&r.elements);
    let t = world.sum(&[d.sum, d.edges]);
    let total = deform_kernel::order::IndexDistance {
        max: 0,
        sum: t[0],
        edges: t[1],
    };
    let mean = crate::renumber::mean(&total);
    let dim = r.skeleton.dim;
    let renumbers = crate::renumber::auto_renumbers(r.npoin as usize, dim, mean);
    let verdict = if a.renumber == crate::renumber::Renumber::Auto && renumbers {
        Err(CliError::Invalid(format!(
            "{}: --renumber auto would renumber this mesh by RCM (mean index distance {mean:.0}), which --distributed does not: renumber the file first (the serial run's bits come from that order), or pass --renumber off to both runs",
            a.mesh.display()
        )))
    } else {
        Ok(())
    };
    world.agree(verdict)
}

/// The centre of a rotation without `--center`: the mean of the moved nodes' coordinates,
/// summed in ascending node order as the serial run does (every process gathers the moved
/// nodes' coordinates: the boundary, small).
fn centroid<const D: usize>(world: &World<'_>, l: &Local<D>, moved: &[u32]) -> [f64; 3] {
    let mut mine = Vec::new();
    for (i, &g) in l.view.global_ids.iter().take(l.view.owned).enumerate() {
        if moved.binary_search(&(g as u32)).is_ok() {
            mine.extend_from_slice(&l.points3[i]);
        }
    }
    let all = world.gather_all(&mine).concat();
    let mut c = [0.0; 3];
    for p in all.chunks_exact(3) {
        for k in 0..3 {
            c[k] += p[k];
        }
    }
    c.map(|x| x / moved.len() as f64)
}

/// A rigid motion: the rotation and its centre, or (`None`) the translation.
pub(super) type Rigid = (Option<Quat<f64>>, [f64; 3], [f64; 3]);

/// The prescribed displacement of a moved node at `p` (the serial run's arithmetic).
pub(super) fn displacement<const D: usize>(rigid: &Rigid, p: [f64; 3]) -> [f64; 3] {
    let (q, c, t) = rigid;
    match q {
        Some(q) => {
            let r = q.rotate([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
            let mut d = [c[0] + r[0] - p[0], c[1] + r[1] - p[1], c[2] + r[2] - p[2]];
            if D == 2 {
                d[2] = 0.0;
            }
            d
        }
        None => *t,
    }
}

/// The rotation (with its centre) or the translation of the arguments.
fn rigid<const D: usize>(
    world: &World<'_>,
    a: &MoveArgs,
    r: &Read,
    l: &Local<D>,
    moved: &[u32],
) -> Result<Rigid, Failed> {
    let none = None;
    let (motion, _) = world.agree(super::super::motion::motion_from_args(
        a,
        &r.skeleton,
        moved,
        &none,
    ))?;
    match motion {
        Motion::Rotate {
            degrees,
            axis,
            center,
        } => {
            let c = center.unwrap_or_else(|| centroid(world, l, moved));
            let c = if D == 2 { [c[0], c[1], 0.0] } else { c };
            let q = Quat::from_axis_angle(axis, degrees.to_radians()).map_err(kernel("rotation"));
            Ok((Some(world.agree(q)?), c, [0.0; 3]))
        }
        Motion::Translate(t) => Ok((None, [0.0; 3], t)),
        // Refused before the read (`check_options`), on every process alike.
        Motion::Field(_) => Err(Some(CliError::Invalid(
            "--distributed moves markers rigidly only".into(),
        ))),
    }
}

/// What every distributed method starts from: the markers' nodes, the local view (fixed
/// mask on the boundary) and the rigid motion.
pub(super) struct Setup<const D: usize> {
    /// The moved markers' nodes, ascending.
    pub moved: Vec<u32>,
    /// Every marker's nodes (moved and fixed), ascending: the serial boundary order.
    pub boundary: Vec<u32>,
    pub l: Local<D>,
    pub motion: Rigid,
}

/// The checks every method shares, the local view and the motion.
pub(super) fn setup<const D: usize>(
    world: &World<'_>,
    a: &MoveArgs,
    r: &Read,
) -> Result<Setup<D>, Failed> {
    let (moved, boundary) = world.agree(marker_sets(a, r))?;
    world.agree(super::super::checks::check_rigid_args(a, D))?;
    check_renumber(world, a, r)?;
    let l = build::<D>(world, r, &|g| boundary.binary_search(&(g as u32)).is_ok());
    let motion = rigid(world, a, r, &l, &moved)?;
    Ok(Setup {
        moved,
        boundary,
        l,
        motion,
    })
}

/// The solve options of the arguments (as the serial run's).
pub(super) fn options(a: &MoveArgs) -> SolveOptions<f64> {
    SolveOptions {
        max_iterations: a.max_iter,
        residual_tol: a.tol,
        update_tol: 0.0,
    }
}

/// The linear springs: the motion, the partitioned solve, the failure policies (see the
/// module's documentation).
pub(super) fn run<const D: usize>(
    world: &World<'_>,
    a: &MoveArgs,
    r: &Read,
) -> Result<Summary, Failed> {
    let s = setup::<D>(world, a, r)?;
    let l = &s.l;
    let mut values: Vec<[f64; D]> = (l.view.global_ids.iter().zip(&l.points3))
        .map(|(&g, &p)| match s.moved.binary_search(&(g as u32)) {
            Ok(_) => {
                let d = displacement::<D>(&s.motion, p);
                core::array::from_fn(|k| d[k])
            }
            Err(_) => [0.0; D],
        })
        .collect();
    let ex = MpiExchange::new(world.comm);
    let len = partitioned_cg_scratch_len::<D>(l.view.global_ids.len());
    let solved = (l.view)
        .solve_cg(
            l.view.owned,
            &mut values,
            Preconditioner::Jacobi,
            &options(a),
            len,
            &ex,
        )
        .map_err(kernel("linear springs (partitioned)"));
    let report = world.agree(solved)?;
    world.agree(converged(a, &report, "spring"))?;
    let deformed: Vec<[f64; 3]> = (l.points3.iter().zip(&values))
        .map(|(p, v)| core::array::from_fn(|k| if k < D { p[k] + v[k] } else { 0.0 }))
        .collect();
    finish(world, a, &s, &report, deformed)
}

/// The fold policy on the deformed local nodes (owned and ghosts), and the summary.
pub(super) fn finish<const D: usize>(
    world: &World<'_>,
    a: &MoveArgs,
    s: &Setup<D>,
    report: &SolveReport<f64>,
    deformed: Vec<[f64; 3]>,
) -> Result<Summary, Failed> {
    let mine = world.agree(local_folds::<D>(&s.l, &deformed))?;
    let (new_failures, inverted) = world.agree(folds(a, &world.sum(&mine), world.rank == 0))?;
    let owned = s.l.view.owned;
    Ok(Summary {
        deformed: deformed.into_iter().take(owned).collect(),
        iterations: report.iterations,
        residual: report.residual,
        converged: report.converged,
        new_failures,
        inverted,
        moved: s.moved.len(),
        fixed: s.boundary.len() - s.moved.len(),
        ghosts: (s.l.view.global_ids.len() - owned) as u64,
    })
}

/// The serial run's policy: an unconverged solve is refused unless `--allow-unconverged`
/// (`what`: the method's solve, as the message names it).
pub(super) fn converged(a: &MoveArgs, r: &SolveReport<f64>, what: &str) -> Result<(), CliError> {
    if r.converged || a.allow_unconverged {
        return Ok(());
    }
    Err(CliError::Unconverged(format!(
        "{}: the {what} solve (CG + Jacobi, distributed) stopped at relative residual {:.3e} after {} iterations (--tol {:e}, --max-iter {}); nothing was written (--allow-unconverged writes it anyway)",
        a.mesh.display(),
        r.residual,
        r.iterations,
        a.tol,
        a.max_iter
    )))
}

/// Per cell: signed measure and smallest corner Jacobian at `p`, each relative to the cell's
/// orientation in the input (`negative`, or the sign of the measure at `p` when `None`:
/// evaluated on the points mirrored in x, as the serial quality check does), and `negative`.
type Relative = (Vec<f64>, Vec<f64>, Vec<bool>);

fn relative<const D: usize>(
    cells: &CellList,
    p: &[[f64; D]],
    negative: Option<&[bool]>,
) -> Result<Relative, CliError> {
    let view = crate::engine::cells_view(cells, p.len())?;
    let eval = |q: &[[f64; D]]| -> Result<(Vec<f64>, Vec<f64>), CliError> {
        let n = cells.len();
        let (mut m, mut j, mut s) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        deform_kernel::quality::cell_qualities(&view, q, &mut m, &mut j, &mut s)
            .map_err(kernel("quality"))?;
        Ok((m, j))
    };
    let (mut m, mut j) = eval(p)?;
    let negative: Vec<bool> =
        negative.map_or_else(|| m.iter().map(|&x| x < 0.0).collect(), <[bool]>::to_vec);
    if negative.iter().any(|&x| x) {
        let mirror = |x: &[f64; D]| {
            let mut y = *x;
            y[0] = -y[0];
            y
        };
        let (mm, jm) = eval(&p.iter().map(mirror).collect::<Vec<_>>())?;
        for c in (0..cells.len()).filter(|&c| negative[c]) {
            m[c] = mm[c];
            j[c] = jm[c];
        }
    }
    Ok((m, j, negative))
}

/// This process's cells (each counted on the process that owns its first node) that the
/// motion inverted or folded and that were not folded before, and the inverted ones among
/// them.
fn local_folds<const D: usize>(l: &Local<D>, deformed: &[[f64; 3]]) -> Result<[u64; 2], CliError> {
    let v = &l.view;
    let mut cells = CellList::new();
    for (c, &kind) in v.cell_kinds.iter().enumerate() {
        let nodes = &v.cell_nodes[v.cell_offsets[c] as usize..v.cell_offsets[c + 1] as usize];
        if nodes.first().is_some_and(|&n| (n as usize) < v.owned) {
            cells.push_code(kind, nodes);
        }
    }
    let after: Vec<[f64; D]> = deformed
        .iter()
        .map(|x| core::array::from_fn(|k| x[k]))
        .collect();
    let (m0, j0, negative) = relative(&cells, &v.points, None)?;
    let (m1, j1, _) = relative(&cells, &after, Some(&negative))?;
    let mut out = [0u64; 2];
    for c in 0..cells.len() {
        let inverted = (m0[c] > 0.0 && m1[c] <= 0.0) || (m0[c] < 0.0 && m1[c] >= 0.0);
        // As the serial check: folded before means a negative corner (a NaN is not).
        let folded_before = j0[c] < 0.0;
        if (inverted || j1[c] < 0.0) && !folded_before {
            out[0] += 1;
            out[1] += u64::from(inverted);
        }
    }
    Ok(out)
}

/// The serial run's policy on the summed counts: cells newly inverted or folded are refused
/// unless `--allow-folds`.
fn folds(a: &MoveArgs, t: &[u64], root: bool) -> Result<(u64, u64), CliError> {
    if t[0] > 0 && !a.allow_folds {
        return Err(CliError::Folded(format!(
            "{}: the result has {} cell(s) inverted or folded that were valid in the input ({} inverted); nothing was written (--allow-folds writes it anyway)",
            a.mesh.display(),
            t[0],
            t[1]
        )));
    }
    if t[0] > 0 && root {
        eprintln!("deform: warning: {} cell(s) inverted or folded that were valid in the input; written because of --allow-folds", t[0]);
    }
    Ok((t[0], t[1]))
}
