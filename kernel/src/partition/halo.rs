//! The communication pattern ([`Halo`]), the caller's exchanges ([`Exchange`]), the verdict
//! every process agrees on ([`agree`]), and the [`Collective`] the solvers run on.

use core::ops::Range;

use super::fault;
use crate::check;
use crate::error::{Error, PartitionFault, Result};
use crate::exact_sum::ExactSum;
use crate::real::Real;
use crate::spring::Collective;

/// The exchanges a partitioned solve needs, implemented by the caller for one process (its
/// methods take `&self`, as an MPI communicator does). Every method is collective over the
/// processes of the partition (the halo exchange only between neighbours).
pub trait Exchange<T: Real>: core::fmt::Debug {
    /// Element-wise sum over all processes, in place (`MPI_Allreduce`, `MPI_SUM`, `i64`).
    fn sum_words(&self, words: &mut [i64]);
    /// Element-wise maximum over all processes, in place (`MPI_Allreduce`, `MPI_MAX`).
    fn max(&self, values: &mut [T]);
    /// The halo exchange: for every neighbour `k` of `halo`, send the `width` reals of each
    /// node of its send list (in list order) to rank `k`, and store the reals received from it
    /// at the nodes of its receive list (in list order). `field` holds `width` reals per local
    /// node; nothing else is written.
    fn exchange(&self, halo: &Halo<'_>, field: &mut [T], width: usize);
    /// Replaces every exact sum in `groups` by its sum over all processes. The default merges
    /// each sum's words with [`sum_words`](Self::sum_words); an implementation with a heap may
    /// pack them all into one reduction.
    fn sum_exact(&self, groups: &mut [&mut [ExactSum]]) {
        for sum in groups.iter_mut().flat_map(|g| g.iter_mut()) {
            sum.exchange(|words| self.sum_words(words));
        }
    }
}

/// Per neighbour process: its rank, the owned local nodes sent to it, the ghosts received
/// from it (CSR lists: neighbour `k`'s send list is `send[send_offsets[k]..send_offsets[k +
/// 1]]`, the same for receives).
#[derive(Clone, Copy, Debug)]
pub struct Halo<'a> {
    ranks: &'a [u32],
    send_offsets: &'a [u32],
    send: &'a [u32],
    recv_offsets: &'a [u32],
    recv: &'a [u32],
}

impl<'a> Halo<'a> {
    /// Wraps the lists. Nothing is checked here: [`Partition::new`](super::Partition::new)
    /// checks the shapes and the entries, collectively, so a bad list fails on every process
    /// together.
    pub const fn new(
        ranks: &'a [u32],
        send_offsets: &'a [u32],
        send: &'a [u32],
        recv_offsets: &'a [u32],
        recv: &'a [u32],
    ) -> Self {
        Halo {
            ranks,
            send_offsets,
            send,
            recv_offsets,
            recv,
        }
    }

    /// The shapes: offsets of `ranks.len() + 1` entries from 0, non-decreasing, ending at
    /// their list's length.
    pub(crate) fn check_shape(&self) -> Result<()> {
        check::len(
            "send_offsets",
            self.send_offsets.len(),
            self.ranks.len() + 1,
        )?;
        check::len(
            "recv_offsets",
            self.recv_offsets.len(),
            self.ranks.len() + 1,
        )?;
        check_offsets("send_offsets", self.send_offsets, self.send.len())?;
        check_offsets("recv_offsets", self.recv_offsets, self.recv.len())
    }

    /// No neighbour (a single process).
    pub const fn empty() -> Halo<'static> {
        Halo {
            ranks: &[],
            send_offsets: &[0],
            send: &[],
            recv_offsets: &[0],
            recv: &[],
        }
    }

    /// Number of neighbour processes.
    pub fn neighbour_count(&self) -> usize {
        self.ranks.len()
    }

    /// Neighbour `k`: `(rank, send list, receive list)`.
    pub fn neighbour(&self, k: usize) -> Option<(u32, &'a [u32], &'a [u32])> {
        let rank = *self.ranks.get(k)?;
        Some((
            rank,
            list(self.send_offsets, self.send, k),
            list(self.recv_offsets, self.recv, k),
        ))
    }

    /// Every neighbour in order: `(rank, send list, receive list)`.
    pub fn neighbours(&self) -> impl Iterator<Item = (u32, &'a [u32], &'a [u32])> + '_ {
        (0..self.ranks.len()).filter_map(|k| self.neighbour(k))
    }

    /// All send entries (every neighbour's list, concatenated).
    pub fn send_entries(&self) -> &'a [u32] {
        self.send
    }

    /// All receive entries (every neighbour's list, concatenated).
    pub fn receive_entries(&self) -> &'a [u32] {
        self.recv
    }
}

/// Entries `offsets[k]..offsets[k + 1]` of `items` (empty when out of range).
fn list<'a>(offsets: &[u32], items: &'a [u32], k: usize) -> &'a [u32] {
    match (offsets.get(k), offsets.get(k + 1)) {
        (Some(&a), Some(&b)) => items.get(a as usize..b as usize).unwrap_or(&[]),
        _ => &[],
    }
}

/// Offsets from 0, non-decreasing, ending at `len`.
fn check_offsets(arg: &'static str, offsets: &[u32], len: usize) -> Result<()> {
    let mut prev = 0u32;
    for (p, &o) in offsets.iter().enumerate() {
        if (p == 0 && o != 0) || o < prev || o as usize > len {
            return Err(Error::BadOffsets { arg, position: p });
        }
        prev = o;
    }
    if prev as usize != len {
        return Err(Error::BadOffsets {
            arg,
            position: offsets.len().saturating_sub(1),
        });
    }
    Ok(())
}

/// The verdict of every process: `words[0]` is set to this process's fault flag and all of
/// `words` is summed over the processes (one `sum_words`). `Err` on every process when any
/// had a fault: its own error, or [`PartitionFault::OtherProcess`].
pub(crate) fn agree<T: Real, E: Exchange<T> + ?Sized>(
    exchange: &E,
    local: Result<()>,
    words: &mut [i64],
) -> Result<()> {
    if let Some(flag) = words.first_mut() {
        *flag = i64::from(local.is_err());
    }
    exchange.sum_words(words);
    local?;
    if words.first().is_some_and(|&f| f != 0) {
        return Err(fault(PartitionFault::OtherProcess, 0));
    }
    Ok(())
}

/// The [`Collective`] of a partitioned solve: rows `0..owned`, sums and maxima through the
/// caller's [`Exchange`], and `share` / `share_halo` as its halo exchange (a ghost's value is
/// its owner's; the kernel's solvers read no farther than the ghosts).
#[derive(Debug)]
pub(crate) struct HaloCollective<'p, 'a, E: ?Sized> {
    owned: [Range<usize>; 1],
    halo: &'p Halo<'a>,
    exchange: &'p E,
}

impl<'p, 'a, E: ?Sized> HaloCollective<'p, 'a, E> {
    /// The collective over `owned` rows, `halo` and `exchange`.
    pub(crate) fn new(owned: usize, halo: &'p Halo<'a>, exchange: &'p E) -> Self {
        HaloCollective {
            owned: [Range {
                start: 0,
                end: owned,
            }],
            halo,
            exchange,
        }
    }
}

impl<T: Real, E: Exchange<T> + ?Sized> Collective<T> for HaloCollective<'_, '_, E> {
    fn owned(&self) -> &[Range<usize>] {
        &self.owned
    }
    fn sum_words(&self, words: &mut [i64]) {
        self.exchange.sum_words(words);
    }
    fn sum_exact(&self, groups: &mut [&mut [ExactSum]]) {
        self.exchange.sum_exact(groups);
    }
    fn max(&self, values: &mut [T]) {
        self.exchange.max(values);
    }
    fn share(&self, field: &mut [T], width: usize) {
        self.exchange.exchange(self.halo, field, width);
    }
    fn share_halo(&self, field: &mut [T], width: usize) {
        self.exchange.exchange(self.halo, field, width);
    }
}
