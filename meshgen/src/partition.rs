//! Partitioned views for the kernel's distributed-storage tests: one process's view of a
//! partitioned mesh, cut from a whole mesh the process read itself (as a solver's example
//! program would): owned nodes first, then ghost layers, in a
//! shuffled local numbering with global ids, the cells that touch the owned nodes (and, for
//! deeper ghost layers, the cells that reach them), and the communication pattern. The view
//! holds local arrays only; the whole-mesh arrays used to cut it are dropped with the call.

use crate::Mesh;
use deform_kernel::partition::{Exchange, Halo, Partition};
use deform_kernel::spring::{
    partitioned_targets_len, LocalCells, PartitionedSprings, Preconditioner, SolveOptions,
    SolveReport,
};

/// What one process passes to the kernel's partitioned solves.
#[derive(Clone, Debug, Default)]
pub struct LocalView<const D: usize> {
    /// This process's rank.
    pub rank: u32,
    /// Number of processes.
    pub size: u32,
    /// Nodes over all processes.
    pub global_count: u64,
    /// Local nodes `0..owned` are owned.
    pub owned: usize,
    /// Global id of every local node.
    pub global_ids: Vec<u64>,
    /// Coordinates of every local node.
    pub points: Vec<[f64; D]>,
    /// Fixed mask of every local node.
    pub fixed: Vec<u8>,
    /// Local cells (CSR, local node numbers) and their VTK kinds.
    pub cell_offsets: Vec<u32>,
    /// Local cells' nodes.
    pub cell_nodes: Vec<u32>,
    /// Local cells' kinds.
    pub cell_kinds: Vec<u8>,
    /// Neighbour ranks.
    pub ranks: Vec<u32>,
    /// Send lists (CSR over `ranks`), local owned nodes.
    pub send_offsets: Vec<u32>,
    /// Send entries.
    pub send: Vec<u32>,
    /// Receive lists (CSR over `ranks`), local ghosts.
    pub recv_offsets: Vec<u32>,
    /// Receive entries.
    pub recv: Vec<u32>,
}

/// A deterministic 64-bit mix (splitmix64).
pub fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A random partition: node `g` to rank `mix(g ^ seed) % parts`.
pub fn random_owner(n: usize, parts: usize, seed: u64) -> Vec<u32> {
    (0..n as u64)
        .map(|g| (mix(g ^ seed) % parts as u64) as u32)
        .collect()
}

/// The owner of every node from per-rank node lists (as `deform_mpi::rcb` returns).
pub fn owner_of(parts: &[Vec<u32>], n: usize) -> Vec<u32> {
    let mut owner = vec![0u32; n];
    for (r, p) in parts.iter().enumerate() {
        for &g in p {
            owner[g as usize] = r as u32;
        }
    }
    owner
}

/// Node → cells incidence (CSR).
fn incidence<const D: usize>(mesh: &Mesh<D>) -> (Vec<u32>, Vec<u32>) {
    let n = mesh.node_count();
    let mut offsets = vec![0u32; n + 1];
    for &v in &mesh.nodes {
        offsets[v as usize + 1] += 1;
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut cells = vec![0u32; mesh.nodes.len()];
    for c in 0..mesh.cell_count() {
        for &v in &mesh.nodes[mesh.offsets[c] as usize..mesh.offsets[c + 1] as usize] {
            cells[fill[v as usize] as usize] = c as u32;
            fill[v as usize] += 1;
        }
    }
    (offsets, cells)
}

/// Layer of every node for `rank`: 0 owned, `1..=depth` ghost layers, `u8::MAX` elsewhere.
fn layers<const D: usize>(
    mesh: &Mesh<D>,
    inc: &(Vec<u32>, Vec<u32>),
    owner: &[u32],
    rank: u32,
    depth: usize,
) -> Vec<u8> {
    let mut layer: Vec<u8> = owner
        .iter()
        .map(|&o| if o == rank { 0 } else { u8::MAX })
        .collect();
    for d in 1..=depth as u8 {
        let front: Vec<usize> = (0..layer.len()).filter(|&g| layer[g] == d - 1).collect();
        for g in front {
            for &c in &inc.1[inc.0[g] as usize..inc.0[g + 1] as usize] {
                let c = c as usize;
                for &h in &mesh.nodes[mesh.offsets[c] as usize..mesh.offsets[c + 1] as usize] {
                    if layer[h as usize] == u8::MAX {
                        layer[h as usize] = d;
                    }
                }
            }
        }
    }
    layer
}

/// A seeded shuffle (Fisher–Yates with [`mix`]).
fn shuffle(v: &mut [usize], seed: u64) {
    let mut s = seed;
    for i in (1..v.len()).rev() {
        s = mix(s);
        v.swap(i, (s % (i as u64 + 1)) as usize);
    }
}

/// `rank`'s view (of `size` ranks) of `mesh` partitioned by `owner`, with `depth` ghost
/// layers, owned and ghost nodes each in a shuffled local order (`seed`).
pub fn local_view<const D: usize>(
    mesh: &Mesh<D>,
    fixed: &[u8],
    owner: &[u32],
    (rank, size): (u32, u32),
    depth: usize,
    seed: u64,
) -> LocalView<D> {
    let n = mesh.node_count();
    let inc = incidence(mesh);
    let mine = layers(mesh, &inc, owner, rank, depth);
    let mut owned: Vec<usize> = (0..n).filter(|&g| mine[g] == 0).collect();
    let mut ghosts: Vec<usize> = (0..n)
        .filter(|&g| mine[g] != 0 && mine[g] != u8::MAX)
        .collect();
    shuffle(&mut owned, seed ^ u64::from(rank));
    shuffle(&mut ghosts, !seed ^ u64::from(rank));
    let mut local = vec![u32::MAX; n];
    for (l, &g) in owned.iter().chain(&ghosts).enumerate() {
        local[g] = l as u32;
    }
    let mut v = LocalView {
        rank,
        size,
        global_count: n as u64,
        owned: owned.len(),
        ..LocalView::default()
    };
    for &g in owned.iter().chain(&ghosts) {
        v.global_ids.push(g as u64);
        v.points.push(mesh.points[g]);
        v.fixed.push(fixed[g]);
    }
    v.cell_offsets.push(0);
    for c in 0..mesh.cell_count() {
        let nodes = &mesh.nodes[mesh.offsets[c] as usize..mesh.offsets[c + 1] as usize];
        if nodes.iter().any(|&h| (mine[h as usize] as usize) < depth) {
            v.cell_nodes
                .extend(nodes.iter().map(|&h| local[h as usize]));
            v.cell_offsets.push(v.cell_nodes.len() as u32);
            v.cell_kinds.push(mesh.kinds[c]);
        }
    }
    v.send_offsets.push(0);
    v.recv_offsets.push(0);
    for r in 0..size {
        if r == rank {
            continue;
        }
        // Receive: my ghosts that `r` owns; send: my nodes that are `r`'s ghosts; both by
        // global id (the order both sides compute).
        let recv: Vec<u32> = (0..n)
            .filter(|&g| owner[g] == r && mine[g] != 0 && mine[g] != u8::MAX)
            .map(|g| local[g])
            .collect();
        let theirs = layers(mesh, &inc, owner, r, depth);
        let send: Vec<u32> = (0..n)
            .filter(|&g| mine[g] == 0 && theirs[g] != 0 && theirs[g] != u8::MAX)
            .map(|g| local[g])
            .collect();
        if !(send.is_empty() && recv.is_empty()) {
            v.ranks.push(r);
            v.send.extend(send);
            v.recv.extend(recv);
            v.send_offsets.push(v.send.len() as u32);
            v.recv_offsets.push(v.recv.len() as u32);
        }
    }
    v
}

impl<const D: usize> LocalView<D> {
    /// The kernel calls a partitioned solver makes, in order, each collective over `ex`:
    /// the pattern and [`Partition::new`] (with `owned` owned nodes: the view's, or a wrong
    /// count in a test), [`PartitionedSprings::new`] on the local cells (Batina, `p = 1`),
    /// then [`PartitionedSprings::solve_cg`] with `scratch_len` items of scratch.
    ///
    /// # Errors
    /// Those of the kernel calls.
    pub fn solve_cg<E: Exchange<f64> + ?Sized>(
        &self,
        owned: usize,
        values: &mut [[f64; D]],
        pre: Preconditioner<f64>,
        options: &SolveOptions<f64>,
        scratch_len: usize,
        ex: &E,
    ) -> deform_kernel::Result<SolveReport<f64>> {
        self.with_springs(owned, ex, |springs| {
            let mut scratch = vec![[0.0; D]; scratch_len];
            springs.solve_cg(values, pre, options, &mut scratch, ex)
        })
    }

    /// The pattern of the view (its neighbours' send and receive lists).
    pub fn halo(&self) -> Halo<'_> {
        Halo::new(
            &self.ranks,
            &self.send_offsets,
            &self.send,
            &self.recv_offsets,
            &self.recv,
        )
    }

    /// [`Partition::new`] (with `owned` owned nodes) and [`PartitionedSprings::new`] on the
    /// local cells (Batina, `p = 1`), each collective over `ex`, then `f` on the springs: what
    /// every partitioned solve of the view (linear springs, the quaternion method) starts from.
    ///
    /// # Errors
    /// Those of the kernel calls and of `f`.
    pub fn with_springs<E: Exchange<f64> + ?Sized, R>(
        &self,
        owned: usize,
        ex: &E,
        f: impl FnOnce(&PartitionedSprings<'_, f64>) -> deform_kernel::Result<R>,
    ) -> deform_kernel::Result<R> {
        let n = self.global_ids.len();
        let mut s = vec![0u32; Partition::scratch_len(n)];
        let (ids, count) = (&self.global_ids[..], self.global_count);
        let part = Partition::new(
            self.rank,
            self.size,
            owned,
            ids,
            count,
            self.halo(),
            ex,
            &mut s,
        )?;
        let cells = LocalCells {
            offsets: &self.cell_offsets,
            nodes: &self.cell_nodes,
            kinds: &self.cell_kinds,
            face_diagonals: false,
        };
        let len = partitioned_targets_len(&cells);
        let (mut o, mut t, mut k) = (vec![0u32; n + 1], vec![0u32; len], vec![0.0; len]);
        let (points, fixed) = (&self.points[..], &self.fixed[..]);
        let springs =
            PartitionedSprings::new(part, cells, points, 1.0, fixed, &mut o, &mut t, &mut k, ex)?;
        f(&springs)
    }
}
