//! Partition-independent aggregation (kernel/src/spring/amg/mis2.rs): the serial run against a
//! sequential reference written here from the definition (greedy MIS-2 in descending key
//! order, which the parallel rounds must reproduce), its structure (roots 3 apart, every node
//! within distance 2 of its root), and every partitioned run (threads as processes: stripes,
//! recursive coordinate bisection and random owners, 2 to 7 processes, ghost depth 1 and 2)
//! against the serial aggregates, bit for bit. Also the sizes against today's greedy
//! aggregation (printed with `--nocapture`) and the collective length error. Then the fine
//! level's prolongator on partitions against `setup_mis2`'s, bit for bit (1 to 5 processes).

#[path = "../support/mod.rs"]
mod support;

use std::collections::VecDeque;

use deform_kernel::error::{Error, PartitionFault};
use deform_kernel::partition::{Halo, Partition};
use deform_kernel::spring::{
    aggregate_mis2, aggregate_mis2_partitioned, batina_stiffness, mis2_exchange_len,
    mis2_scratch_len, partitioned_targets_len, prolongator_partitioned,
    prolongator_partitioned_len, solve_linear_amg_scratch_len, AmgHierarchy, AmgOptions,
    LocalCells as KernelCells, Mis2Report, PartitionedSprings, SolveOptions, SpringSystem,
    MIS2_NONE,
};
use deform_kernel::{graph_from_cells, graph_from_cells_len, Cells, Graph};
use deform_meshgen::partition::{local_view, mix, random_owner, LocalView};
use deform_meshgen::{block2, block3, naca_triangulated, AirfoilGrid, BlockSpec, Mesh};
use support::spring::AmgBuffers;
use support::threads::{on_threads, Threads};

/// A CSR graph (owned arrays).
struct Csr {
    offsets: Vec<u32>,
    targets: Vec<u32>,
}

impl Csr {
    fn of(cells: &Cells<'_>, n: usize) -> Csr {
        let mut offsets = vec![0u32; n + 1];
        let mut targets = vec![0u32; graph_from_cells_len(cells, false)];
        let used = graph_from_cells(cells, false, &mut offsets, &mut targets).unwrap();
        targets.truncate(used);
        Csr { offsets, targets }
    }
    fn graph(&self) -> Graph<'_> {
        Graph::new(&self.offsets, &self.targets).unwrap()
    }
}

/// A test case: the mesh (2D or 3D behind one type), its fixed mask and graph.
struct Case {
    name: &'static str,
    points: Vec<Vec<f64>>,
    mesh2: Option<Mesh<2>>,
    mesh3: Option<Mesh<3>>,
    fixed: Vec<u8>,
    csr: Csr,
}

impl Case {
    fn new2(name: &'static str, mesh: Mesh<2>, fixed: Vec<u8>) -> Case {
        let csr = Csr::of(&mesh.cells().unwrap(), mesh.node_count());
        let points = mesh.points.iter().map(|p| p.to_vec()).collect();
        Case {
            name,
            points,
            mesh2: Some(mesh),
            mesh3: None,
            fixed,
            csr,
        }
    }
    fn new3(name: &'static str, mesh: Mesh<3>, fixed: Vec<u8>) -> Case {
        let csr = Csr::of(&mesh.cells().unwrap(), mesh.node_count());
        let points = mesh.points.iter().map(|p| p.to_vec()).collect();
        Case {
            name,
            points,
            mesh2: None,
            mesh3: Some(mesh),
            fixed,
            csr,
        }
    }
    fn n(&self) -> usize {
        self.points.len()
    }
    /// `rank`'s view: global ids, owned count, fixed flags, local graph and pattern.
    fn view(&self, owner: &[u32], rank: u32, size: u32, depth: usize) -> View {
        let seed = 7 + depth as u64;
        let (ids, owned, fixed, cells, pattern) = match (&self.mesh2, &self.mesh3) {
            (Some(m), _) => parts(local_view(m, &self.fixed, owner, (rank, size), depth, seed)),
            (_, Some(m)) => parts(local_view(m, &self.fixed, owner, (rank, size), depth, seed)),
            _ => unreachable!(),
        };
        let c = Cells::new(ids.len(), &cells.0, &cells.1, &cells.2).unwrap();
        let csr = Csr::of(&c, ids.len());
        View {
            ids,
            owned,
            fixed,
            csr,
            pattern,
            count: self.n() as u64,
        }
    }
}

type Pattern = [Vec<u32>; 5];
type LocalCells = (Vec<u32>, Vec<u32>, Vec<u8>);

/// The parts of a view this test uses.
fn parts<const D: usize>(v: LocalView<D>) -> (Vec<u64>, usize, Vec<u8>, LocalCells, Pattern) {
    let cells = (v.cell_offsets, v.cell_nodes, v.cell_kinds);
    let pattern = [v.ranks, v.send_offsets, v.send, v.recv_offsets, v.recv];
    (v.global_ids, v.owned, v.fixed, cells, pattern)
}

/// One process's inputs.
struct View {
    ids: Vec<u64>,
    owned: usize,
    fixed: Vec<u8>,
    csr: Csr,
    pattern: Pattern,
    count: u64,
}

impl View {
    /// The partitioned aggregation on this view; `short` cuts the scratch (an error case).
    fn aggregate(
        &self,
        rank: u32,
        size: u32,
        ex: &Threads<'_>,
        short: bool,
    ) -> deform_kernel::Result<(Vec<u64>, Mis2Report)> {
        let [r, so, s, ro, rv] = &self.pattern;
        let halo = Halo::new(r, so, s, ro, rv);
        let n = self.ids.len();
        let count = self.count;
        let mut ps = vec![0u32; Partition::scratch_len(n)];
        let part = Partition::new(rank, size, self.owned, &self.ids, count, halo, ex, &mut ps)?;
        let mut agg = vec![0u64; n];
        let mut scratch = vec![0u64; mis2_scratch_len(n) - usize::from(short)];
        let mut reals = vec![0.0f64; mis2_exchange_len(n)];
        let g = self.csr.graph();
        let report = aggregate_mis2_partitioned(
            &part,
            &g,
            &self.fixed,
            ex,
            &mut agg,
            &mut scratch,
            &mut reals,
        )?;
        Ok((agg, report))
    }
}

/// The serial aggregation of a case.
fn serial(case: &Case) -> (Vec<u64>, Mis2Report) {
    let n = case.n();
    let mut agg = vec![0u64; n];
    let mut scratch = vec![0u64; mis2_scratch_len(n)];
    let r = aggregate_mis2(&case.csr.graph(), &case.fixed, &mut agg, &mut scratch).unwrap();
    (agg, r)
}

/// Free neighbours of `i` (self excluded).
fn free_neighbours(case: &Case, i: usize) -> Vec<usize> {
    let g = case.csr.graph();
    g.neighbors(i)
        .iter()
        .map(|&j| j as usize)
        .filter(|&j| j != i && case.fixed[j] == 0)
        .collect()
}

/// Free nodes with a free neighbour.
fn members(case: &Case) -> Vec<bool> {
    (0..case.n())
        .map(|i| case.fixed[i] == 0 && !free_neighbours(case, i).is_empty())
        .collect()
}

/// Distances from `s` over free nodes, up to `cap` (`usize::MAX` beyond).
fn distances(case: &Case, s: usize, cap: usize) -> Vec<usize> {
    let mut d = vec![usize::MAX; case.n()];
    d[s] = 0;
    let mut q = VecDeque::from([s]);
    while let Some(i) = q.pop_front() {
        if d[i] == cap {
            continue;
        }
        for j in free_neighbours(case, i) {
            if d[j] == usize::MAX {
                d[j] = d[i] + 1;
                q.push_back(j);
            }
        }
    }
    d
}

/// The kernel's priority of global id `g` (its definition, docs/amg.md): the splitmix64
/// finaliser's steps modulo `2^62`.
fn priority(g: usize) -> u64 {
    let m = (1u64 << 62) - 1;
    let mut x = g as u64 & m;
    x ^= x >> 31;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9) & m;
    x ^= x >> 29;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb) & m;
    x ^ (x >> 32)
}

/// The definition, sequentially: visit members in descending priority; a node with no root
/// within distance 2 becomes a root. Then neighbours of a root join it, and the rest join the
/// highest-priority root among their neighbours' roots.
fn reference(case: &Case) -> Vec<u64> {
    let n = case.n();
    let key = priority;
    let member = members(case);
    let mut order: Vec<usize> = (0..n).filter(|&i| member[i]).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(key(i)));
    let mut root = vec![false; n];
    for &i in &order {
        let d = distances(case, i, 2);
        if !(0..n).any(|j| root[j] && d[j] <= 2) {
            root[i] = true;
        }
    }
    let mut agg = vec![MIS2_NONE; n];
    for i in 0..n {
        if root[i] {
            agg[i] = i as u64;
        } else if member[i] {
            if let Some(r) = free_neighbours(case, i).into_iter().find(|&j| root[j]) {
                agg[i] = r as u64;
            }
        }
    }
    let first = agg.clone();
    for i in 0..n {
        if member[i] && first[i] == MIS2_NONE {
            let best = free_neighbours(case, i)
                .into_iter()
                .filter(|&j| first[j] != MIS2_NONE)
                .map(|j| first[j] as usize)
                .max_by_key(|&r| key(r));
            agg[i] = best.expect("a node out of every distance-2 ball") as u64;
        }
    }
    agg
}

fn airfoil() -> Case {
    let grid = AirfoilGrid {
        surface_points: 48,
        radial_points: 12,
        ..AirfoilGrid::default()
    };
    let mesh = naca_triangulated(&grid).unwrap();
    let fixed = mesh.boundary_mask();
    Case::new2("naca 2D triangles", mesh, fixed)
}

fn quads() -> Case {
    let spec = BlockSpec {
        dims: [23, 17, 2],
        ..BlockSpec::uniform(2)
    };
    let mesh = block2(&spec).unwrap();
    // Free boundary, some scattered fixed nodes (isolated free nodes appear next to them).
    let fixed = (0..mesh.node_count())
        .map(|g| u8::from(mix(g as u64) % 9 == 0))
        .collect();
    Case::new2("2D quads, scattered fixed", mesh, fixed)
}

fn hexes() -> Case {
    let spec = BlockSpec {
        dims: [9, 8, 7],
        ..BlockSpec::uniform(2)
    };
    let mesh = block3(&spec).unwrap();
    let fixed = mesh.boundary_mask();
    Case::new3("3D hexes", mesh, fixed)
}

fn cases() -> Vec<Case> {
    vec![airfoil(), quads(), hexes()]
}

#[test]
fn serial_aggregation_is_the_greedy_definition() {
    for case in cases() {
        let (agg, report) = serial(&case);
        assert_eq!(agg, reference(&case), "{}", case.name);
        let roots = (0..case.n()).filter(|&i| agg[i] == i as u64).count();
        assert_eq!(report.aggregates, roots as u64, "{}", case.name);
        assert!(report.rounds >= 2 && report.rounds < 40, "{}", case.name);
    }
}

#[test]
fn roots_are_three_apart_and_every_node_within_two_of_its_root() {
    for case in cases() {
        let (agg, _) = serial(&case);
        let member = members(&case);
        for i in 0..case.n() {
            if !member[i] {
                assert_eq!(agg[i], MIS2_NONE, "{}: node {i}", case.name);
                continue;
            }
            let r = agg[i] as usize;
            assert_eq!(agg[r], r as u64, "{}: root of {i} is a root", case.name);
            let d = distances(&case, r, 3);
            assert!(
                d[i] <= 2,
                "{}: node {i} at {} from its root",
                case.name,
                d[i]
            );
            if i == r {
                for j in 0..case.n() {
                    let other = j != r && agg[j] == j as u64;
                    assert!(!(other && d[j] <= 2), "{}: roots {r}, {j}", case.name);
                }
            }
        }
    }
}

/// Recursive coordinate bisection of `ids` into `parts` parts (longest extent first).
fn rcb(points: &[Vec<f64>], mut ids: Vec<usize>, parts: u32, first: u32, owner: &mut [u32]) {
    if parts == 1 {
        ids.iter().for_each(|&g| owner[g] = first);
        return;
    }
    let dim = points[0].len();
    let extent = |d: usize| {
        let (lo, hi) = ids.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &g| {
            (lo.min(points[g][d]), hi.max(points[g][d]))
        });
        hi - lo
    };
    let axis = (0..dim)
        .max_by(|&a, &b| extent(a).total_cmp(&extent(b)))
        .unwrap();
    ids.sort_by(|&a, &b| points[a][axis].total_cmp(&points[b][axis]).then(a.cmp(&b)));
    let left = parts / 2;
    let cut = ids.len() * left as usize / parts as usize;
    let right = ids.split_off(cut);
    rcb(points, ids, left, first, owner);
    rcb(points, right, parts - left, first + left, owner);
}

/// The owners of every partition kind for `size` processes.
fn owners(case: &Case, size: usize) -> Vec<(&'static str, Vec<u32>)> {
    let n = case.n();
    let mut by_rcb = vec![0u32; n];
    rcb(&case.points, (0..n).collect(), size as u32, 0, &mut by_rcb);
    vec![
        ("stripes", (0..n).map(|g| (g * size / n) as u32).collect()),
        ("rcb", by_rcb),
        ("random", random_owner(n, size, 3)),
    ]
}

#[test]
fn every_partition_gives_the_serial_aggregates() {
    for case in cases() {
        let (want, sr) = serial(&case);
        for size in [2usize, 3, 4, 7] {
            for (label, owner) in owners(&case, size) {
                for depth in [1, 2] {
                    let what = format!("{}, {label}, {size} processes, depth {depth}", case.name);
                    let got = on_threads(size, |rank, ex| {
                        let v = case.view(&owner, rank, size as u32, depth);
                        (v.ids.clone(), v.aggregate(rank, size as u32, ex, false))
                    });
                    for (rank, (ids, r)) in got.into_iter().enumerate() {
                        let (agg, report) = r.unwrap();
                        assert_eq!(report, sr, "{what}, rank {rank}");
                        for (&g, &a) in ids.iter().zip(&agg) {
                            assert_eq!(a, want[g as usize], "{what}, rank {rank}, node {g}");
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn a_short_scratch_fails_on_every_process() {
    let case = hexes();
    let owner = random_owner(case.n(), 3, 5);
    let got = on_threads(3, |rank, ex| {
        let v = case.view(&owner, rank, 3, 1);
        v.aggregate(rank, 3, ex, rank == 1).err()
    });
    assert!(matches!(got[1], Some(Error::BufferTooSmall { .. })));
    for r in [0, 2] {
        assert!(matches!(
            got[r],
            Some(Error::BadPartition {
                fault: PartitionFault::OtherProcess,
                ..
            })
        ));
    }
}

/// pyamg's standard aggregation with θ = 0 (what the serial hierarchy does today).
fn greedy(case: &Case) -> Vec<u64> {
    let n = case.n();
    let member = members(case);
    let mut agg = vec![MIS2_NONE; n];
    let mut roots = Vec::new();
    for i in (0..n).filter(|&i| member[i]) {
        let nb = free_neighbours(case, i);
        if agg[i] == MIS2_NONE && nb.iter().all(|&j| agg[j] == MIS2_NONE) {
            agg[i] = i as u64;
            nb.iter().for_each(|&j| agg[j] = i as u64);
            roots.push(i);
        }
    }
    let first = agg.clone();
    for i in (0..n).filter(|&i| member[i] && first[i] == MIS2_NONE) {
        if let Some(&j) = free_neighbours(case, i)
            .iter()
            .find(|&&j| first[j] != MIS2_NONE)
        {
            agg[i] = first[j];
        }
    }
    for i in 0..n {
        if !member[i] || agg[i] != MIS2_NONE {
            continue;
        }
        agg[i] = i as u64;
        for j in free_neighbours(case, i) {
            if agg[j] == MIS2_NONE {
                agg[j] = i as u64;
            }
        }
    }
    agg
}

/// Aggregate sizes: (count, min, mean, max).
fn sizes(agg: &[u64]) -> (usize, usize, f64, usize) {
    let mut count = std::collections::BTreeMap::new();
    for &a in agg.iter().filter(|&&a| a != MIS2_NONE) {
        *count.entry(a).or_insert(0usize) += 1;
    }
    let k = count.len();
    let total: usize = count.values().sum();
    let min = *count.values().min().unwrap();
    let max = *count.values().max().unwrap();
    (k, min, total as f64 / k as f64, max)
}

#[test]
fn aggregate_sizes_are_like_todays() {
    for case in cases() {
        let (agg, report) = serial(&case);
        let today = greedy(&case);
        // The greedy reference is the greedy hierarchy with every spring strong (θ = 0, as
        // MIS-2 aggregates): same first coarse level size.
        let level1 = with_system(&case, |sys| {
            let opts = AmgOptions {
                strength_theta: 0.0,
                ..AmgOptions::default()
            };
            let mut b = AmgBuffers::new(sys, &opts);
            b.build(sys, &opts).level_size(1)
        });
        let (kt, mint, meant, maxt) = sizes(&today);
        assert_eq!(level1, kt, "{}", case.name);
        let (km, minm, meanm, maxm) = sizes(&agg);
        eprintln!(
            "{}: {} nodes; today {kt} aggregates (sizes {mint}..{maxt}, mean {meant:.2}); \
             MIS-2 {km} (sizes {minm}..{maxm}, mean {meanm:.2}, {} rounds)",
            case.name,
            case.n(),
            report.rounds
        );
        let ratio = km as f64 / kt as f64;
        assert!((0.6..1.6).contains(&ratio), "{}: ratio {ratio}", case.name);
        assert!(maxm <= 4 * maxt, "{}", case.name);
    }
}

/// Runs `f` on the case's spring system (Batina stiffness, `p = 1`).
fn with_system<R>(case: &Case, f: impl FnOnce(&SpringSystem<'_, f64>) -> R) -> R {
    let mut k = vec![0.0; case.csr.targets.len()];
    let pts: Vec<[f64; 3]> = case
        .points
        .iter()
        .map(|p| [p[0], p[1], p.get(2).copied().unwrap_or(0.0)])
        .collect();
    let g = case.csr.graph();
    batina_stiffness(&g, &pts, 1.0, &mut k).unwrap();
    let mut s = vec![0u32; case.n()];
    let sys = SpringSystem::new(g, &k, &case.fixed, &mut s).unwrap();
    f(&sys)
}

/// The AMG-CG solve of a rotation of the fixed nodes with hierarchy `h`: iterations.
fn amg_cg(sys: &SpringSystem<'_, f64>, h: &AmgHierarchy<'_, f64>, case: &Case) -> usize {
    let mut x: Vec<[f64; 2]> = (0..case.n())
        .map(|i| {
            let p = &case.points[i];
            let f = if case.fixed[i] != 0 { 0.05 } else { 0.0 };
            [-f * p[1], f * p[0]]
        })
        .collect();
    let stop = SolveOptions {
        residual_tol: 1e-8,
        max_iterations: 1000,
        update_tol: 0.0,
    };
    let mut scratch = vec![[0.0; 2]; solve_linear_amg_scratch_len(h)];
    let r = sys
        .solve_linear_amg(h, &mut x, &stop, &mut scratch)
        .unwrap();
    assert!(r.converged);
    r.iterations
}

#[test]
fn the_hierarchy_built_on_mis2_aggregates_solves() {
    for case in [airfoil(), hexes()] {
        let (agg, report) = serial(&case);
        with_system(&case, |sys| {
            let opts = AmgOptions {
                max_coarse: 16,
                ..AmgOptions::default()
            };
            let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
            let mut mwork = vec![0u64; AmgHierarchy::mis2_work_len(sys)];
            let short = AmgHierarchy::setup_len_mis2(sys, &opts, &mut work, &mut mwork[1..]);
            assert!(matches!(short, Err(Error::BufferTooSmall { .. })));
            let sizes = AmgHierarchy::setup_len_mis2(sys, &opts, &mut work, &mut mwork).unwrap();
            let mut index = vec![0u32; sizes.index];
            let mut values = vec![0.0; sizes.values];
            let (w, m, i, v) = (&mut work, &mut mwork, &mut index, &mut values);
            let h = AmgHierarchy::setup_mis2(sys, &opts, w, m, i, v).unwrap();
            assert!(h.levels() >= 3, "{}", case.name);
            // The fine level's aggregates are those of aggregate_mis2.
            assert_eq!(h.level_size(1) as u64, report.aggregates, "{}", case.name);
            assert_eq!(
                agg.iter().filter(|&&a| a != MIS2_NONE).count(),
                (0..case.n()).filter(|&i| case.fixed[i] == 0).count(),
                "{}: every free node aggregated",
                case.name
            );
            let mis2 = amg_cg(sys, &h, &case);
            let mut b = AmgBuffers::new(sys, &opts);
            let greedy = amg_cg(sys, &b.build(sys, &opts), &case);
            eprintln!(
                "{}: AMG-CG iterations greedy {greedy}, MIS-2 {mis2}",
                case.name
            );
            assert!(mis2 <= 2 * greedy + 5, "{}: {mis2} vs {greedy}", case.name);
        });
    }
}

/// A view's points in 3D (`z = 0` in 2D, as [`with_system`] builds the serial system) and
/// its cells.
fn points_cells<const D: usize>(v: LocalView<D>) -> (Vec<[f64; 3]>, LocalCells) {
    let points = v.points.iter();
    let points = points.map(|p| [p[0], p[1], p.get(2).copied().unwrap_or(0.0)]);
    (
        points.collect(),
        (v.cell_offsets, v.cell_nodes, v.cell_kinds),
    )
}

/// `rank`'s view with its points (3D) and cells, numbered as [`Case::view`] numbers them (the
/// same seed).
fn springs_view(
    case: &Case,
    owner: &[u32],
    (rank, size, depth): (u32, u32, usize),
) -> (View, Vec<[f64; 3]>, LocalCells) {
    let seed = 7 + depth as u64;
    let at = (rank, size);
    let (points, cells) = match (&case.mesh2, &case.mesh3) {
        (Some(m), _) => points_cells(local_view(m, &case.fixed, owner, at, depth, seed)),
        (_, Some(m)) => points_cells(local_view(m, &case.fixed, owner, at, depth, seed)),
        _ => unreachable!(),
    };
    (case.view(owner, rank, size, depth), points, cells)
}

/// A prolongator row: `(root global id, value bits)` per entry.
type Row = Vec<(u64, u64)>;

/// One process's fine prolongator rows (owned nodes, by global id): `(root, value bits)`;
/// `short` cuts `values` by one (an error case).
fn partitioned_prolongator(
    case: &Case,
    owner: &[u32],
    (rank, size, depth): (u32, u32, usize),
    ex: &Threads<'_>,
    short: bool,
) -> deform_kernel::Result<Vec<(u64, Row)>> {
    let at = (rank, size, depth);
    let (v, points, (cell_offsets, cell_nodes, cell_kinds)) = springs_view(case, owner, at);
    let [r, so, s, ro, rv] = &v.pattern;
    let halo = Halo::new(r, so, s, ro, rv);
    let n = v.ids.len();
    let mut ps = vec![0u32; Partition::scratch_len(n)];
    let part = Partition::new(rank, size, v.owned, &v.ids, v.count, halo, ex, &mut ps)?;
    let cells = KernelCells {
        offsets: &cell_offsets,
        nodes: &cell_nodes,
        kinds: &cell_kinds,
        face_diagonals: false,
    };
    let len = partitioned_targets_len(&cells);
    let (mut o, mut t, mut k) = (vec![0u32; n + 1], vec![0u32; len], vec![0.0; len]);
    let springs = PartitionedSprings::new(
        part, cells, &points, 1.0, &v.fixed, &mut o, &mut t, &mut k, ex,
    )?;
    let (agg, _) = v.aggregate(rank, size, ex, false)?;
    let len = prolongator_partitioned_len(&springs);
    let mut offsets = vec![0u32; v.owned + 1];
    let mut cols = vec![0u64; len];
    let mut vals = vec![f64::NAN; len - usize::from(short)];
    let (p, vo) = (&mut offsets, &mut cols);
    let nnz = prolongator_partitioned(&springs, &agg, ex, p, vo, &mut vals)?;
    assert_eq!(offsets[v.owned] as usize, nnz);
    let rows = (0..v.owned).map(|i| {
        let (a, b) = (offsets[i] as usize, offsets[i + 1] as usize);
        let row = (a..b).map(|q| (cols[q], vals[q].to_bits())).collect();
        (v.ids[i], row)
    });
    Ok(rows.collect())
}

/// The serial MIS-2 hierarchy's fine prolongator, every node's row with its columns named by
/// the aggregates' roots: `(root, value bits)`.
fn serial_prolongator(case: &Case) -> Vec<Row> {
    let (agg, _) = serial(case);
    let roots: Vec<u64> = (0..case.n() as u64)
        .filter(|&i| agg[i as usize] == i)
        .collect();
    with_system(case, |sys| {
        let opts = AmgOptions {
            max_coarse: 16,
            ..AmgOptions::default()
        };
        let mut work = vec![0u32; AmgHierarchy::setup_work_len(sys)];
        let mut mwork = vec![0u64; AmgHierarchy::mis2_work_len(sys)];
        let sizes = AmgHierarchy::setup_len_mis2(sys, &opts, &mut work, &mut mwork).unwrap();
        let mut index = vec![0u32; sizes.index];
        let mut values = vec![0.0; sizes.values];
        let (w, m, i, v) = (&mut work, &mut mwork, &mut index, &mut values);
        let h = AmgHierarchy::setup_mis2(sys, &opts, w, m, i, v).unwrap();
        assert!(h.levels() >= 2, "{}", case.name);
        assert_eq!(h.level_size(1), roots.len(), "{}", case.name);
        (0..case.n())
            .map(|i| {
                let (c, v) = h.prolongator_row(0, i);
                let row = c.iter().zip(v);
                row.map(|(&c, &v)| (roots[c as usize], v.to_bits()))
                    .collect()
            })
            .collect()
    })
}

#[test]
fn every_partition_gives_the_serial_fine_prolongator() {
    for case in cases() {
        let want = serial_prolongator(&case);
        // Not a trivial operator: smoothed rows reach beyond their own aggregate.
        assert!(want.iter().any(|r| r.len() > 1), "{}", case.name);
        for size in 1..=5usize {
            for ((label, owner), depth) in owners(&case, size).into_iter().zip([1, 2, 1]) {
                let what = format!("{}, {label}, {size} processes, depth {depth}", case.name);
                let got = on_threads(size, |rank, ex| {
                    let at = (rank, size as u32, depth);
                    partitioned_prolongator(&case, &owner, at, ex, false)
                });
                let mut seen = 0;
                for (rank, rows) in got.into_iter().enumerate() {
                    for (g, row) in rows.unwrap() {
                        assert_eq!(row, want[g as usize], "{what}, rank {rank}, node {g}");
                        seen += 1;
                    }
                }
                assert_eq!(seen, case.n(), "{what}: every row once");
            }
        }
    }
}

#[test]
fn a_short_prolongator_buffer_fails_on_every_process() {
    let case = hexes();
    let owner = random_owner(case.n(), 3, 5);
    let got = on_threads(3, |rank, ex| {
        partitioned_prolongator(&case, &owner, (rank, 3, 1), ex, rank == 2).err()
    });
    assert!(matches!(got[2], Some(Error::BufferTooSmall { .. })));
    for r in [0, 1] {
        assert!(matches!(
            got[r],
            Some(Error::BadPartition {
                fault: PartitionFault::OtherProcess,
                ..
            })
        ));
    }
}
