//! `--method quaternion --solver cg`: Samareh's quaternion method with spring propagation on
//! each process's local view, through the kernel's `deform_spring_partitioned` (which gathers
//! the boundary, small, to every process), given what the serial `deform move --method
//! quaternion` gives `deform_spring_with`: every marker node in ascending node order, the moved
//! ones' rigid rotation and the fixed ones' identity per node, the rotation centre as the origin
//! (for a translation none: the kernel's centroid of the moving boundary), CG + Jacobi.

use deform_kernel::partition::Exchange;
use deform_kernel::quaternion::{
    deform_spring_partitioned, deform_spring_partitioned_lens, PartitionedMotion,
    PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::Preconditioner;
use deform_kernel::Quat;
use deform_meshgen::partition::LocalView;
use deform_mpi::MpiExchange;

use super::comm::{Failed, World};
use super::read::Read;
use super::solve::{converged, displacement, finish, kernel, options, setup, Setup, Summary};
use crate::args::MoveArgs;

/// This process's owned boundary nodes as the kernel takes them.
struct Share<const D: usize> {
    /// Local node numbers (owned), ascending.
    nodes: Vec<u32>,
    /// Position of each in the serial boundary list (every marker node, ascending).
    positions: Vec<u32>,
    /// Prescribed position of each (`p + d` in `D` coordinates, the serial arithmetic).
    deformed: Vec<[f64; D]>,
    /// Rotation of each: the rigid rotation on the moved markers, the identity elsewhere.
    rotations: Vec<Quat<f64>>,
}

/// The owned boundary nodes, their positions, prescribed positions and rotations.
fn share<const D: usize>(s: &Setup<D>) -> Share<D> {
    let (q, _, _) = s.motion;
    let v = &s.l.view;
    let mut out = Share {
        nodes: Vec::new(),
        positions: Vec::new(),
        deformed: Vec::new(),
        rotations: Vec::new(),
    };
    for (i, (&g, &p)) in v.global_ids.iter().zip(&s.l.points3).enumerate() {
        let Some(k) = (i < v.owned)
            .then(|| s.boundary.binary_search(&(g as u32)).ok())
            .flatten()
        else {
            continue;
        };
        let moved = s.moved.binary_search(&(g as u32)).is_ok();
        let d = if moved {
            displacement::<D>(&s.motion, p)
        } else {
            [0.0; 3]
        };
        out.nodes.push(i as u32);
        out.positions.push(k as u32);
        out.deformed.push(core::array::from_fn(|c| p[c] + d[c]));
        out.rotations.push(match (moved, q) {
            (true, Some(q)) => q,
            _ => Quat::identity(),
        });
    }
    out
}

/// The quaternion method: the motion, the partitioned deformation, the failure policies.
pub(super) fn run<const D: usize>(
    world: &World<'_>,
    a: &MoveArgs,
    r: &Read,
) -> Result<Summary, Failed> {
    let s = setup::<D>(world, a, r)?;
    let mine = share::<D>(&s);
    let (q, c, _) = s.motion;
    let motion = PartitionedMotion {
        nodes: &mine.nodes,
        positions: &mine.positions,
        deformed: &mine.deformed,
        boundary_count: s.boundary.len(),
        elements: None,
        rotations: RotationSource::PerNode(&mine.rotations),
        origin: q.map(|_| core::array::from_fn(|k| c[k])),
    };
    let ex = MpiExchange::new(world.comm);
    let view = &s.l.view;
    let mut out = vec![[0.0; D]; view.owned];
    let solved = view
        .with_springs(view.owned, &ex, |springs| {
            let lens =
                deform_spring_partitioned_lens::<D>(view.global_ids.len(), s.boundary.len(), 0);
            let (mut words, mut reals) = (vec![0i64; lens.words], vec![0.0; lens.reals]);
            let (mut index, mut kinds) = (vec![0u32; lens.index], vec![0u8; lens.kinds]);
            let mut values = vec![0.0; lens.values];
            let work = PartitionedWorkspace {
                words: &mut words,
                reals: &mut reals,
                index: &mut index,
                kinds: &mut kinds,
                values: &mut values,
            };
            let pre = Preconditioner::Jacobi;
            let points = &view.points[..];
            deform_spring_partitioned(
                springs,
                points,
                &motion,
                pre,
                &options(a),
                work,
                &mut out,
                &ex,
            )
        })
        .map_err(kernel("quaternion springs (partitioned)"));
    let (_, report) = world.agree(solved)?;
    world.agree(converged(a, &report, "quaternion"))?;
    let deformed = with_ghosts(view, &out, &ex);
    finish(world, a, &s, &report, deformed)
}

/// The deformed local nodes in 3 coordinates: the owned ones of `out`, the ghosts from their
/// owners (one halo exchange), `z` = 0 in 2D.
fn with_ghosts<const D: usize>(
    view: &LocalView<D>,
    out: &[[f64; D]],
    ex: &impl Exchange<f64>,
) -> Vec<[f64; 3]> {
    let mut field = vec![0.0; view.global_ids.len() * D];
    for (f, p) in field.chunks_exact_mut(D).zip(out) {
        f.copy_from_slice(p);
    }
    ex.exchange(&view.halo(), &mut field, D);
    field
        .chunks_exact(D)
        .map(|p| core::array::from_fn(|k| p.get(k).copied().unwrap_or(0.0)))
        .collect()
}
