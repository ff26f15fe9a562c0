//! The quaternion deformation on partitioned data (`deform_idw_partitioned`,
//! `deform_spring_partitioned`) as one process holding the whole mesh in an arbitrary local
//! numbering, with an arbitrary boundary order, motion and rotation source: every owned node
//! and the origin must be the serial result's bits (`deform_idw`, `deform_spring_with` on the
//! mesh in global numbering), the serial and partitioned runs must fail together, and spoiled
//! partitions (a duplicate global id, a boundary position given twice, a wrong boundary count)
//! must fail with `out` untouched. No panic anywhere.
#![no_main]

use arbitrary::Arbitrary;
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::quaternion::{
    deform_idw, deform_idw_partitioned, deform_idw_partitioned_lens, deform_idw_scratch_len,
    deform_spring_partitioned, deform_spring_partitioned_lens, deform_spring_scratch_len,
    deform_spring_with, propagate_spring_with_scratch_len, BoundaryElements, BoundaryMotion,
    PartitionedIdwWorkspace, PartitionedMotion, PartitionedWorkspace, RotationSource,
};
use deform_kernel::spring::{
    batina_stiffness, partitioned_targets_len, LinearMethod, LinearSolver, LocalCells,
    PartitionedSprings, Preconditioner, SolveOptions, SpringSystem,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph, Quat};
use libfuzzer_sys::fuzz_target;

#[derive(Arbitrary, Debug)]
struct Input {
    nx: u8,
    ny: u8,
    /// Drives the local numbering and the boundary order (Fisher–Yates draws).
    shuffle: Vec<u16>,
    moves: Vec<[i8; 2]>,
    angles: Vec<i8>,
    /// Rotation source (`% 3`), propagation (`/ 3 % 2`: IDW or springs).
    mode: u8,
    /// `% 8`: 0–4 a valid partition, 5 a duplicate global id, 6 a boundary position given
    /// twice, 7 a boundary count one too large.
    spoil: u8,
    exponent: u8,
}

/// One process: every collective is the identity, there are no neighbours.
#[derive(Debug)]
struct Solo;

impl Exchange<f64> for Solo {
    fn sum_words(&self, _: &mut [i64]) {}
    fn max(&self, _: &mut [f64]) {}
    fn exchange(&self, _: &Halo<'_>, _: &mut [f64], _: usize) {}
}

/// A permutation of `0..n` from the input's draws.
fn permutation(n: usize, draws: &mut impl Iterator<Item = u16>) -> Vec<u32> {
    let mut p: Vec<u32> = (0..n as u32).collect();
    for k in (1..n).rev() {
        let j = usize::from(draws.next().unwrap_or(0)) % (k + 1);
        p.swap(k, j);
    }
    p
}

/// The structured triangle mesh (global numbering): points, cells (VTK triangles), its
/// perimeter in walking order.
struct Mesh {
    points: Vec<[f64; 2]>,
    offsets: Vec<u32>,
    nodes: Vec<u32>,
    kinds: Vec<u8>,
    perimeter: Vec<u32>,
}

fn mesh(nx: usize, ny: usize) -> Mesh {
    let points = (0..nx * ny)
        .map(|p| [(p % nx) as f64, (p / nx) as f64 * 0.7])
        .collect();
    let (mut offsets, mut nodes, mut kinds) = (vec![0u32], Vec::new(), Vec::new());
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = (j * nx + i) as u32;
            let (b, c, d) = (a + 1, a + 1 + nx as u32, a + nx as u32);
            for t in [[a, b, c], [a, c, d]] {
                nodes.extend_from_slice(&t);
                kinds.push(5);
                offsets.push(nodes.len() as u32);
            }
        }
    }
    let mut perimeter: Vec<u32> = (0..nx).map(|i| i as u32).collect();
    perimeter.extend((1..ny).map(|j| (j * nx + nx - 1) as u32));
    perimeter.extend((0..nx - 1).rev().map(|i| ((ny - 1) * nx + i) as u32));
    perimeter.extend((1..ny - 1).rev().map(|j| (j * nx) as u32));
    Mesh {
        points,
        offsets,
        nodes,
        kinds,
        perimeter,
    }
}

/// The serial boundary: the perimeter's nodes in `order`, its segments (VTK lines) in that
/// numbering, the deformed points and per-node rotations.
struct Boundary {
    nodes: Vec<u32>,
    offsets: Vec<u32>,
    elements: Vec<u32>,
    kinds: Vec<u8>,
    deformed: Vec<[f64; 2]>,
    rotations: Vec<Quat<f64>>,
}

fn boundary(m: &Mesh, order: &[u32], inp: &Input) -> Boundary {
    let b = m.perimeter.len();
    let nodes: Vec<u32> = order.iter().map(|&k| m.perimeter[k as usize]).collect();
    let mut position = vec![0u32; b];
    for (k, &o) in order.iter().enumerate() {
        position[o as usize] = k as u32;
    }
    let (mut offsets, mut elements) = (vec![0u32], Vec::new());
    for s in 0..b {
        elements.extend_from_slice(&[position[s], position[(s + 1) % b]]);
        offsets.push(elements.len() as u32);
    }
    let deformed = nodes
        .iter()
        .enumerate()
        .map(|(k, &p)| {
            let d = inp.moves.get(k).copied().unwrap_or([0, 0]);
            let q = m.points[p as usize];
            [
                q[0] + f64::from(d[0]) / 100.0,
                q[1] + f64::from(d[1]) / 100.0,
            ]
        })
        .collect();
    let rotations = (0..b)
        .map(|k| Quat::from_rotation_z(f64::from(inp.angles.get(k).copied().unwrap_or(0)) / 50.0))
        .collect();
    Boundary {
        nodes,
        offsets,
        elements,
        kinds: vec![3; b],
        deformed,
        rotations,
    }
}

fn source<'a>(mode: u8, bnd: &'a Boundary, rotations: &'a [Quat<f64>]) -> RotationSource<'a, f64> {
    match mode % 3 {
        0 => RotationSource::Shape,
        1 => RotationSource::Rigid(bnd.rotations[0]),
        _ => RotationSource::PerNode(rotations),
    }
}

fn options() -> SolveOptions<f64> {
    SolveOptions {
        max_iterations: 400,
        ..SolveOptions::default()
    }
}

/// The serial deformation of the mesh in global numbering.
fn serial(m: &Mesh, bnd: &Boundary, inp: &Input) -> Option<(Vec<[f64; 2]>, [f64; 2])> {
    let n = m.points.len();
    let elements = Cells::new(bnd.nodes.len(), &bnd.offsets, &bnd.elements, &bnd.kinds).ok()?;
    let motion = BoundaryMotion {
        nodes: &bnd.nodes,
        deformed: &bnd.deformed,
        elements: Some(elements),
        rotations: source(inp.mode, bnd, &bnd.rotations),
        origin: None,
    };
    let (mut t, mut q) = (vec![[0.0; 2]; n], vec![Quat::identity(); n]);
    let mut out = vec![[0.0; 2]; n];
    let b = bnd.nodes.len();
    let origin = if inp.mode / 3 % 2 == 0 {
        let mut s = vec![0.0; deform_idw_scratch_len::<2>(n, b)];
        let p = 1.0 + f64::from(inp.exponent % 4) * 0.5;
        deform_idw(&m.points, &motion, p, &mut t, &mut q, &mut s, &mut out).ok()?
    } else {
        let cells = Cells::new(n, &m.offsets, &m.nodes, &m.kinds).ok()?;
        let mut go = vec![0u32; n + 1];
        let mut gt = vec![0u32; graph_from_cells_len(&cells, false)];
        let used = graph_from_cells(&cells, false, &mut go, &mut gt).ok()?;
        let g = Graph::new(&go, &gt[..used]).ok()?;
        let mut k = vec![0.0; used];
        batina_stiffness(&g, &m.points, 1.0, &mut k).ok()?;
        let mut fixed = vec![0u8; n];
        bnd.nodes.iter().for_each(|&i| fixed[i as usize] = 1);
        let mut ss = vec![0u32; n];
        let sys = SpringSystem::new(g, &k, &fixed, &mut ss).ok()?;
        let solver = LinearSolver::Method(LinearMethod::Cg {
            preconditioner: Preconditioner::Jacobi,
        });
        let mut s = vec![0.0; deform_spring_scratch_len::<2>(n, b)];
        let mut values = vec![0.0; propagate_spring_with_scratch_len::<2>(&solver, n)];
        let (origin, _) = deform_spring_with(
            &m.points,
            &motion,
            &sys,
            solver,
            &options(),
            &mut t,
            &mut q,
            &mut s,
            &mut values,
            &mut out,
        )
        .ok()?;
        origin
    };
    Some((out, origin))
}

/// The same deformation by one process holding every node, local node `i` being global node
/// `ids[i]`; `Err(())` when any call fails (then `out` must still be NaN).
fn partitioned(
    m: &Mesh,
    bnd: &Boundary,
    ids: &[u64],
    inp: &Input,
) -> Result<(Vec<[f64; 2]>, [f64; 2]), Vec<[f64; 2]>> {
    let n = m.points.len();
    let spoil = inp.spoil % 8;
    let mut local_of = vec![0u32; n];
    for (i, &g) in ids.iter().enumerate() {
        local_of[(g as usize).min(n - 1)] = i as u32;
    }
    let points: Vec<[f64; 2]> = ids
        .iter()
        .map(|&g| m.points[(g as usize).min(n - 1)])
        .collect();
    let mut out = vec![[f64::NAN; 2]; n];
    let halo = Halo::new(&[], &[0], &[], &[0], &[]);
    let mut ps = vec![0u32; Partition::scratch_len(n)];
    let Ok(part) = Partition::new(0, 1, n, ids, n as u64, halo, &Solo, &mut ps) else {
        return Err(out);
    };
    // The boundary in local numbering, in the serial boundary order.
    let nodes: Vec<u32> = bnd.nodes.iter().map(|&g| local_of[g as usize]).collect();
    let mut positions: Vec<u32> = (0..nodes.len() as u32).collect();
    if spoil == 6 && positions.len() > 1 {
        positions[1] = positions[0];
    }
    let count = nodes.len() + usize::from(spoil == 7);
    let ids_e: Vec<u32> = (0..bnd.kinds.len() as u32).collect();
    let motion = PartitionedMotion {
        nodes: &nodes,
        positions: &positions,
        deformed: &bnd.deformed,
        boundary_count: count,
        elements: Some(BoundaryElements {
            ids: &ids_e,
            offsets: &bnd.offsets,
            nodes: &bnd.elements,
            kinds: &bnd.kinds,
            count: bnd.kinds.len(),
        }),
        rotations: source(inp.mode, bnd, &bnd.rotations),
        origin: None,
    };
    let e = bnd.kinds.len();
    let origin = if inp.mode / 3 % 2 == 0 {
        let lens = deform_idw_partitioned_lens::<2>(count, e);
        let (mut words, mut reals) = (vec![0i64; lens.words], vec![0.0; lens.reals]);
        let (mut index, mut kinds) = (vec![0u32; lens.index], vec![0u8; lens.kinds]);
        let mut rotations = vec![Quat::identity(); lens.rotations];
        let work = PartitionedIdwWorkspace {
            words: &mut words,
            reals: &mut reals,
            index: &mut index,
            kinds: &mut kinds,
            rotations: &mut rotations,
        };
        let p = 1.0 + f64::from(inp.exponent % 4) * 0.5;
        deform_idw_partitioned(&part, &points, &motion, p, work, &mut out, &Solo)
    } else {
        let cell_nodes: Vec<u32> = m.nodes.iter().map(|&g| local_of[g as usize]).collect();
        let cells = LocalCells {
            offsets: &m.offsets,
            nodes: &cell_nodes,
            kinds: &m.kinds,
            face_diagonals: false,
        };
        let mut fixed = vec![0u8; n];
        nodes.iter().for_each(|&i| fixed[i as usize] = 1);
        let len = partitioned_targets_len(&cells);
        let (mut o, mut t, mut k) = (vec![0u32; n + 1], vec![0u32; len], vec![0.0; len]);
        let Ok(springs) = PartitionedSprings::new(
            part, cells, &points, 1.0, &fixed, &mut o, &mut t, &mut k, &Solo,
        ) else {
            return Err(out);
        };
        let lens = deform_spring_partitioned_lens::<2>(n, count, e);
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
        deform_spring_partitioned(
            &springs,
            &points,
            &motion,
            pre,
            &options(),
            work,
            &mut out,
            &Solo,
        )
        .map(|(origin, _)| origin)
    };
    match origin {
        Ok(o) => Ok((out, o)),
        Err(_) => Err(out),
    }
}

fuzz_target!(|inp: Input| {
    let (nx, ny) = ((inp.nx % 6) as usize + 2, (inp.ny % 6) as usize + 2);
    let m = mesh(nx, ny);
    let n = m.points.len();
    let mut draws = inp.shuffle.iter().copied().cycle().take(4 * n);
    let mut ids: Vec<u64> = permutation(n, &mut draws)
        .into_iter()
        .map(u64::from)
        .collect();
    let order = permutation(m.perimeter.len(), &mut draws);
    let bnd = boundary(&m, &order, &inp);
    let spoil = inp.spoil % 8;
    if spoil == 5 {
        ids[1] = ids[0];
    }
    let got = partitioned(&m, &bnd, &ids, &inp);
    if spoil >= 5 {
        let untouched = got.expect_err("a spoiled partition was accepted");
        assert!(
            untouched.iter().flatten().all(|x| x.is_nan()),
            "out written on error"
        );
        return;
    }
    match (serial(&m, &bnd, &inp), got) {
        (Some((want, origin)), Ok((out, o))) => {
            assert_eq!(o.map(f64::to_bits), origin.map(f64::to_bits), "origin");
            for (i, &g) in ids.iter().enumerate() {
                assert_eq!(
                    out[i].map(f64::to_bits),
                    want[g as usize].map(f64::to_bits),
                    "local node {i} = global {g}"
                );
            }
        }
        (None, Err(untouched)) => {
            assert!(
                untouched.iter().flatten().all(|x| x.is_nan()),
                "out written on error"
            );
        }
        (Some(_), Err(_)) => panic!("the partitioned run failed where the serial one did not"),
        (None, Ok(_)) => panic!("the partitioned run succeeded where the serial one failed"),
    }
});
