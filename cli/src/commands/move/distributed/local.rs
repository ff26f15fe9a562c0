//! Each process's local view from its share of the read: the nodes of its contiguous block
//! of global ids (owned), the cells that touch them, one ghost layer (the other nodes of those
//! cells) and the pattern, built by three all-to-all exchanges. No process holds a global
//! array.

use deform_meshgen::partition::LocalView;

use super::comm::{block_owner, block_start, World};
use super::read::Read;

/// The local view, and what the later steps need besides it.
pub(super) struct Local<const D: usize> {
    pub view: LocalView<D>,
    /// Coordinates of every local node, 3D (`z` = 0 in 2D), as read.
    pub points3: Vec<[f64; 3]>,
}

/// Sends the points read here to the processes that own them; returns this process's owned
/// points, in global order.
fn owned_points(world: &World<'_>, r: &Read) -> Vec<[f64; 3]> {
    let (n, p) = (r.npoin, world.size);
    let mut counts = vec![0usize; p];
    for k in 0..r.points.len() {
        counts[block_owner(n, p, r.first_point + k as u64)] += 3;
    }
    // The points read are consecutive ids: already grouped by owner, in rank order.
    let send: Vec<f64> = r.points.iter().flatten().copied().collect();
    let (got, _) = world.all_to_all(&send, &counts);
    drop(send);
    got.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}

/// Sends every element read here to each process that owns one of its nodes, as
/// `[index, code, node count, nodes…]` (32-bit words: SU2 counts are below 2³²); returns
/// the cells received, ascending by index.
fn touching_cells(world: &World<'_>, r: &Read) -> Vec<u32> {
    let (n, p) = (r.npoin, world.size);
    let owners = |nodes: &[u32], to: &mut Vec<usize>| {
        to.clear();
        to.extend(nodes.iter().map(|&v| block_owner(n, p, u64::from(v))));
        to.sort_unstable();
        to.dedup();
    };
    let mut to: Vec<usize> = Vec::with_capacity(8);
    let mut counts = vec![0usize; p];
    for (_, nodes) in r.elements.iter() {
        owners(nodes, &mut to);
        for &q in &to {
            counts[q] += 3 + nodes.len();
        }
    }
    let mut at: Vec<usize> = counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect();
    let mut send = vec![0u32; counts.iter().sum()];
    for (c, (code, nodes)) in r.elements.iter().enumerate() {
        owners(nodes, &mut to);
        for &q in &to {
            let head = [
                (r.first_element as usize + c) as u32,
                u32::from(code),
                nodes.len() as u32,
            ];
            send[at[q]..at[q] + 3].copy_from_slice(&head);
            send[at[q] + 3..at[q] + 3 + nodes.len()].copy_from_slice(nodes);
            at[q] += 3 + nodes.len();
        }
    }
    // Senders hold ascending ranges of elements, so what arrives is ascending.
    world.all_to_all(&send, &counts).0
}

/// The local view of this process.
pub(super) fn build<const D: usize>(
    world: &World<'_>,
    r: &Read,
    fixed_of: &dyn Fn(u64) -> bool,
) -> Local<D> {
    let (n, p, me) = (r.npoin, world.size, world.rank);
    let first = block_start(n, p, me);
    let owned3 = owned_points(world, r);
    let cells = touching_cells(world, r);
    let owned = owned3.len();
    let is_owned = |g: u64| g >= first && g < first + owned as u64;
    let mut ghosts: Vec<u64> = Vec::new();
    walk(&cells, |_, _, nodes| {
        ghosts.extend((nodes.iter().map(|&g| u64::from(g))).filter(|&g| !is_owned(g)));
    });
    ghosts.sort_unstable();
    ghosts.dedup();
    let local_of = |g: u64| -> u32 {
        if is_owned(g) {
            (g - first) as u32
        } else {
            (owned + ghosts.binary_search(&g).unwrap_or(0)) as u32
        }
    };
    let mut v = LocalView::<D> {
        rank: me as u32,
        size: p as u32,
        global_count: n,
        owned,
        ..LocalView::default()
    };
    v.cell_offsets.push(0);
    walk(&cells, |_, code, nodes| {
        v.cell_kinds.push(code as u8);
        v.cell_nodes
            .extend(nodes.iter().map(|&g| local_of(u64::from(g))));
        v.cell_offsets.push(v.cell_nodes.len() as u32);
    });
    drop(cells);
    let ghost3 = ghost_points(world, n, first, &owned3, &ghosts, &mut v);
    let points3: Vec<[f64; 3]> = owned3.into_iter().chain(ghost3).collect();
    v.global_ids = (first..first + owned as u64).chain(ghosts).collect();
    v.points = points3
        .iter()
        .map(|x| core::array::from_fn(|k| x[k]))
        .collect();
    v.fixed = v
        .global_ids
        .iter()
        .map(|&g| u8::from(fixed_of(g)))
        .collect();
    Local { view: v, points3 }
}

/// Calls `f(index, code, nodes)` for every cell of the `[index, code, count, nodes…]` list.
fn walk(list: &[u32], mut f: impl FnMut(u32, u32, &[u32])) {
    let mut at = 0usize;
    while at + 3 <= list.len() {
        let count = list[at + 2] as usize;
        let end = (at + 3 + count).min(list.len());
        f(list[at], list[at + 1], &list[at + 3..end]);
        at = end;
    }
}

/// Asks each ghost's owner for its coordinates; fills the view's pattern (for each
/// neighbour: the owned nodes it asked for, the ghosts asked of it, both ascending by global
/// id); returns the ghosts' coordinates in `ghosts`' order.
fn ghost_points<const D: usize>(
    world: &World<'_>,
    n: u64,
    first: u64,
    owned3: &[[f64; 3]],
    ghosts: &[u64],
    v: &mut LocalView<D>,
) -> Vec<[f64; 3]> {
    let p = world.size;
    // Ghosts ascend by id and blocks by rank: `ghosts` is grouped by owner already.
    let mut ask = vec![0usize; p];
    for &g in ghosts {
        ask[block_owner(n, p, g)] += 1;
    }
    let (asked, from) = world.all_to_all(ghosts, &ask);
    let reply: Vec<f64> = (asked.iter())
        .flat_map(|&g| {
            owned3
                .get((g - first) as usize)
                .copied()
                .unwrap_or([0.0; 3])
        })
        .collect();
    let sizes: Vec<usize> = from.iter().map(|&c| 3 * c).collect();
    let (got, _) = world.all_to_all(&reply, &sizes);
    v.send_offsets.push(0);
    v.recv_offsets.push(0);
    let (mut next_ghost, mut next_asked) = (owned3.len() as u32, 0usize);
    for q in 0..p {
        if from[q] == 0 && ask[q] == 0 {
            continue;
        }
        v.ranks.push(q as u32);
        let theirs = &asked[next_asked..next_asked + from[q]];
        next_asked += from[q];
        v.send.extend(theirs.iter().map(|&g| (g - first) as u32));
        v.send_offsets.push(v.send.len() as u32);
        v.recv.extend(next_ghost..next_ghost + ask[q] as u32);
        next_ghost += ask[q] as u32;
        v.recv_offsets.push(v.recv.len() as u32);
    }
    got.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
}
