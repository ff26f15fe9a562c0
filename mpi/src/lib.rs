//! MPI for deform-kernel: a [`Collective`] over an MPI communicator, so the kernel's
//! distributed solves (`LinearSolver::Distributed`, `LinearSolver::DistributedAmg`) run across
//! processes, and a deterministic partition by recursive coordinate bisection.
//!
//! Replicated data: every process holds the whole mesh and field and computes its own rows;
//! `share` gathers every process's rows to all (`MPI_Allgatherv`), exact sums merge with
//! `MPI_SUM` on their `i64` words, maxima with `MPI_MAX`.

use std::ops::Range;

mod exchange;
mod whole;
pub use exchange::MpiExchange;
pub use whole::{boundary_values, WholeSprings};

use deform_kernel::exact_sum::ExactSum;
use deform_kernel::spring::Collective;
use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::traits::*;

/// The nodes each of `parts` processes owns: recursive coordinate bisection (split the
/// longest extent at the median, ties by node number, recursively). Deterministic, so every
/// process computes the same partition. Chosen over METIS because it needs no extra library
/// and the bits do not depend on the partition anyway; its surface is worse (see
/// docs/scaling.md).
pub fn rcb<const D: usize>(points: &[[f64; D]], parts: usize) -> Vec<Vec<u32>> {
    let mut out = Vec::with_capacity(parts);
    rcb_into(
        points,
        (0..points.len() as u32).collect(),
        parts.max(1),
        &mut out,
    );
    for p in &mut out {
        p.sort_unstable();
    }
    out
}

fn rcb_into<const D: usize>(
    points: &[[f64; D]],
    nodes: Vec<u32>,
    parts: usize,
    out: &mut Vec<Vec<u32>>,
) {
    if parts <= 1 || nodes.len() <= 1 {
        out.push(nodes);
        for _ in 1..parts {
            out.push(Vec::new());
        }
        return;
    }
    let mut extent = [0.0f64; D];
    for (a, e) in extent.iter_mut().enumerate() {
        let (lo, hi) = nodes.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &i| {
            let x = points[i as usize][a];
            (lo.min(x), hi.max(x))
        });
        *e = hi - lo;
    }
    let axis = (0..D)
        .max_by(|&a, &b| extent[a].total_cmp(&extent[b]).then(b.cmp(&a)))
        .unwrap_or(0);
    let mut sorted = nodes;
    sorted.sort_by(|&i, &j| {
        points[i as usize][axis]
            .total_cmp(&points[j as usize][axis])
            .then(i.cmp(&j))
    });
    let left_parts = parts / 2;
    let cut = sorted.len() * left_parts / parts;
    let right = sorted.split_off(cut);
    rcb_into(points, sorted, left_parts, out);
    rcb_into(points, right, parts - left_parts, out);
}

/// Maximal runs of consecutive numbers in a sorted list.
pub fn runs(sorted: &[u32]) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    for &i in sorted {
        let i = i as usize;
        match out.last_mut() {
            Some(r) if r.end == i => r.end = i + 1,
            _ => out.push(i..i + 1),
        }
    }
    out
}

/// A [`Collective`] over an MPI communicator for a given partition.
pub struct MpiCollective<'c, C: Communicator> {
    comm: &'c C,
    /// This process's node ranges.
    owned: Vec<Range<usize>>,
    /// This process's nodes (sorted).
    mine: Vec<u32>,
    /// All processes' nodes, concatenated in rank order (the order `MPI_Allgatherv` delivers).
    order: Vec<u32>,
    /// Nodes per process.
    counts: Vec<usize>,
    /// Halo exchange (when built with the graph): per process, the own nodes it reads, and
    /// its nodes this process reads (sorted; both sides compute the same lists).
    halo: Option<Halo>,
}

/// The node lists of a halo exchange.
struct Halo {
    send: Vec<Vec<u32>>,
    recv: Vec<Vec<u32>>,
}

impl<C: Communicator> std::fmt::Debug for MpiCollective<'_, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiCollective")
            .field("rank", &self.comm.rank())
            .field("size", &self.comm.size())
            .field("owned_nodes", &self.mine.len())
            .field("runs", &self.owned.len())
            .finish()
    }
}

impl<'c, C: Communicator> MpiCollective<'c, C> {
    /// The collective of this process, for `parts[r]` = the nodes of rank `r` (as [`rcb`]
    /// returns; every process must pass the same partition).
    pub fn new(comm: &'c C, parts: &[Vec<u32>]) -> Self {
        let rank = comm.rank() as usize;
        let mine = parts.get(rank).cloned().unwrap_or_default();
        MpiCollective {
            comm,
            owned: runs(&mine),
            mine,
            order: parts.iter().flatten().copied().collect(),
            counts: parts.iter().map(Vec::len).collect(),
            halo: None,
        }
    }

    /// As [`MpiCollective::new`], with halo exchanges for the graph `offsets`/`targets` (CSR,
    /// symmetric): `share_halo` then sends each process only the own nodes next to its rows.
    pub fn with_graph(comm: &'c C, parts: &[Vec<u32>], offsets: &[u32], targets: &[u32]) -> Self {
        let mut c = Self::new(comm, parts);
        let rank = comm.rank() as usize;
        let n = offsets.len().saturating_sub(1);
        let mut owner = vec![0usize; n];
        for (r, p) in parts.iter().enumerate() {
            for &i in p {
                owner[i as usize] = r;
            }
        }
        let neighbours = |i: usize| {
            targets[offsets[i] as usize..offsets[i + 1] as usize]
                .iter()
                .map(|&j| j as usize)
        };
        let size = parts.len();
        let mut send = vec![Vec::new(); size];
        let mut recv = vec![Vec::new(); size];
        for &i in &c.mine {
            let i = i as usize;
            for j in neighbours(i) {
                let q = owner[j];
                if q != rank {
                    // q reads my i (symmetric graph), and I read its j.
                    send[q].push(i as u32);
                    recv[q].push(j as u32);
                }
            }
        }
        for l in send.iter_mut().chain(recv.iter_mut()) {
            l.sort_unstable();
            l.dedup();
        }
        c.halo = Some(Halo { send, recv });
        c
    }

    /// Nodes this process receives in a halo exchange (0 without the graph).
    pub fn halo_len(&self) -> usize {
        self.halo
            .as_ref()
            .map_or(0, |h| h.recv.iter().map(Vec::len).sum())
    }

    /// Number of maximal runs of consecutive owned nodes.
    pub fn run_count(&self) -> usize {
        self.owned.len()
    }
}

/// Counts and displacements of `lists` (`width` values per node) for a varcount exchange.
fn layout(lists: &[Vec<u32>], width: usize) -> (Vec<i32>, Vec<i32>) {
    let counts: Vec<i32> = lists.iter().map(|l| (l.len() * width) as i32).collect();
    let displs = counts
        .iter()
        .scan(0, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect();
    (counts, displs)
}

impl<C: Communicator> Collective<f64> for MpiCollective<'_, C> {
    fn share_halo(&self, field: &mut [f64], width: usize) {
        let Some(h) = &self.halo else {
            return self.share(field, width);
        };
        let send: Vec<f64> = h
            .send
            .iter()
            .flatten()
            .flat_map(|&i| {
                let a = i as usize * width;
                field[a..a + width].iter().copied()
            })
            .collect();
        let (sc, sd) = layout(&h.send, width);
        let (rc, rd) = layout(&h.recv, width);
        let mut recv = vec![0.0f64; h.recv.iter().map(Vec::len).sum::<usize>() * width];
        {
            let s = Partition::new(&send[..], &sc[..], &sd[..]);
            let mut r = PartitionMut::new(&mut recv[..], &rc[..], &rd[..]);
            self.comm.all_to_all_varcount_into(&s, &mut r);
        }
        for (&i, v) in h.recv.iter().flatten().zip(recv.chunks_exact(width)) {
            let a = i as usize * width;
            field[a..a + width].copy_from_slice(v);
        }
    }

    fn owned(&self) -> &[Range<usize>] {
        &self.owned
    }

    fn sum_words(&self, words: &mut [i64]) {
        let send = words.to_vec();
        self.comm
            .all_reduce_into(&send[..], words, SystemOperation::sum());
    }

    /// All sums in one `MPI_Allreduce` (their words packed into one buffer).
    fn sum_exact(&self, groups: &mut [&mut [ExactSum]]) {
        whole::sum_exact_packed(groups, |w| self.sum_words(w));
    }

    fn max(&self, values: &mut [f64]) {
        let send = values.to_vec();
        self.comm
            .all_reduce_into(&send[..], values, SystemOperation::max());
    }

    fn share(&self, field: &mut [f64], width: usize) {
        let send: Vec<f64> = self
            .mine
            .iter()
            .flat_map(|&i| {
                let a = i as usize * width;
                field[a..a + width].iter().copied()
            })
            .collect();
        let counts: Vec<i32> = self.counts.iter().map(|&c| (c * width) as i32).collect();
        let displs: Vec<i32> = counts
            .iter()
            .scan(0, |acc, &c| {
                let d = *acc;
                *acc += c;
                Some(d)
            })
            .collect();
        let mut recv = vec![0.0f64; self.order.len() * width];
        {
            let mut part = PartitionMut::new(&mut recv[..], &counts[..], &displs[..]);
            self.comm.all_gather_varcount_into(&send[..], &mut part);
        }
        for (&i, v) in self.order.iter().zip(recv.chunks_exact(width)) {
            let a = i as usize * width;
            field[a..a + width].copy_from_slice(v);
        }
    }
}
