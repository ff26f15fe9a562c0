//! Distributed storage: each process holds only its partition of the mesh, in its own
//! numbering, and the kernel never sees a global array.
//!
//! **What a process passes** ([`Partition`]): its local nodes, the owned ones first
//! (`0..owned`) and then one or more layers of ghosts (copies of other processes' nodes), each
//! with its global id; and the communication pattern ([`Halo`]): for each neighbour process,
//! the owned local nodes it sends there and the ghosts it receives from there, both lists in
//! the order the two processes agree on (position `q` of one process's send list is position
//! `q` of the other's receive list). Cells and edges come later, with the solve that needs
//! them ([`crate::spring::PartitionedSprings`]).
//!
//! **Exchanges** go through the caller's [`Exchange`] (MPI, a GPU-aware MPI, or anything
//! else): sums of `i64` words, maxima of reals, and the halo exchange over the pattern. The
//! kernel stays `no_std` and MPI-free.
//!
//! **Agreeing on errors.** Every check a process can make alone (counts, ranges, duplicate
//! global ids, the lists) runs first; then *one* `sum_words` carries a fault flag together with
//! checksums of what only all processes together can check (owned counts add up to the global
//! count; the owned ids and their squares sum to those of `0..N`; every send entry meets the
//! receive entry at the same position on the other side with the same global id, as hashes
//! that cancel). Every process sees the same merged words and so takes the same decision: all
//! return `Ok`, or all return [`Error::BadPartition`] (their own fault, or
//! [`PartitionFault::OtherProcess`]). No process goes on to a halo exchange that a faulty
//! pattern could hang, and nothing is written before the decision. The hashes are 31-bit
//! residues in two independent words: a mismatch escapes with probability about `2^−62`.

pub(crate) mod check;
mod halo;

pub(crate) use halo::{agree, HaloCollective};
pub use halo::{Exchange, Halo};

use crate::error::{Error, PartitionFault, Result};

/// One process's partition: local nodes (owned first, then ghosts) with their global ids, and
/// the communication pattern. Validated against every other process's by [`Partition::new`].
#[derive(Clone, Copy, Debug)]
pub struct Partition<'a> {
    rank: u32,
    owned: usize,
    global_ids: &'a [u64],
    global_count: u64,
    halo: Halo<'a>,
}

impl<'a> Partition<'a> {
    /// Length of the `u32` scratch [`Partition::new`] needs: one entry per local node.
    pub const fn scratch_len(local_count: usize) -> usize {
        local_count
    }

    /// Validates this process's partition against every other process's. **Collective**: every
    /// process of the exchange calls it (once `sum_words`), and all return `Ok` or all `Err`.
    ///
    /// `rank` of `size` processes; local nodes `0..owned` are owned, the rest are ghosts;
    /// `global_ids[i]` is local node `i`'s global id, below `global_count`.
    ///
    /// # Errors
    /// [`Error::BadPartition`] with the [`PartitionFault`] found (see there), on every process;
    /// `scratch` shorter than [`Partition::scratch_len`], `rank >= size` and halo offsets
    /// that do not fit their lists ([`Error::BadOffsets`]) also count as this process's
    /// fault (reported as themselves here, as `OtherProcess` elsewhere). Only `scratch` is
    /// written.
    #[allow(clippy::too_many_arguments)]
    pub fn new<T: crate::Real, E: Exchange<T> + ?Sized>(
        rank: u32,
        size: u32,
        owned: usize,
        global_ids: &'a [u64],
        global_count: u64,
        halo: Halo<'a>,
        exchange: &E,
        scratch: &mut [u32],
    ) -> Result<Self> {
        let part = Partition {
            rank,
            owned,
            global_ids,
            global_count,
            halo,
        };
        let local = check::local(&part, size, scratch);
        let mut words = [0i64; check::WORDS];
        if let Ok(t) = &local {
            words = t.words();
        }
        agree(exchange, local.map(|_| ()), &mut words)?;
        check::global(&words, global_count)?;
        Ok(part)
    }

    /// This process's rank.
    pub fn rank(&self) -> u32 {
        self.rank
    }

    /// Number of owned nodes (local nodes `0..owned`).
    pub fn owned(&self) -> usize {
        self.owned
    }

    /// Number of local nodes, owned and ghosts.
    pub fn local_count(&self) -> usize {
        self.global_ids.len()
    }

    /// The global id of every local node.
    pub fn global_ids(&self) -> &'a [u64] {
        self.global_ids
    }

    /// Number of nodes over all processes.
    pub fn global_count(&self) -> u64 {
        self.global_count
    }

    /// The communication pattern.
    pub fn halo(&self) -> &Halo<'a> {
        &self.halo
    }

    /// Global id of local node `i` (`u64::MAX` past the end).
    #[inline]
    pub(crate) fn global_id(&self, i: usize) -> u64 {
        self.global_ids.get(i).copied().unwrap_or(u64::MAX)
    }
}

/// A [`Error::BadPartition`] at `position`.
pub(crate) fn fault(fault: PartitionFault, position: usize) -> Error {
    Error::BadPartition { fault, position }
}
