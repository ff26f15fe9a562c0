//! The few MPI operations the distributed `deform move` needs, over `MPI_COMM_WORLD`, and the
//! rule by which every process agrees on an error before the next collective call.

use mpi::collective::SystemOperation;
use mpi::datatype::{Equivalence, Partition, PartitionMut};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use crate::error::CliError;

/// A failure of a collective step: this process's own error, or `None` when another process
/// failed (and reports it).
pub(super) type Failed = Option<CliError>;

/// The communicator and its shape.
pub(super) struct World<'w> {
    pub comm: &'w SimpleCommunicator,
    pub rank: usize,
    pub size: usize,
}

impl<'w> World<'w> {
    pub fn new(comm: &'w SimpleCommunicator) -> Self {
        World {
            comm,
            rank: comm.rank() as usize,
            size: comm.size() as usize,
        }
    }

    /// Every process passes its own result; all go on together or all fail together (the
    /// failing ones with their own error, the others with `None`). One `MPI_Allreduce`.
    pub fn agree<T>(&self, mine: Result<T, CliError>) -> Result<T, Failed> {
        let bad = u32::from(mine.is_err());
        let mut any = 0u32;
        self.comm
            .all_reduce_into(&bad, &mut any, SystemOperation::max());
        match mine {
            Err(e) => Err(Some(e)),
            Ok(_) if any != 0 => Err(None),
            Ok(v) => Ok(v),
        }
    }

    /// Element-wise sums of `values` over the processes.
    pub fn sum(&self, values: &[u64]) -> Vec<u64> {
        let mut out = vec![0u64; values.len()];
        self.comm
            .all_reduce_into(values, &mut out[..], SystemOperation::sum());
        out
    }

    /// The sum of `value` over the processes before this one.
    pub fn before(&self, value: u64) -> u64 {
        let all = self.gather_all(&[value]);
        all.iter().take(self.rank).map(|v| v[0]).sum()
    }

    /// Every process's `mine`, in rank order, on every process.
    pub fn gather_all<T: Equivalence + Default + Clone>(&self, mine: &[T]) -> Vec<Vec<T>> {
        let count = mine.len() as i32;
        let mut counts = vec![0i32; self.size];
        self.comm.all_gather_into(&count, &mut counts[..]);
        let displs = offsets(&counts);
        let total = counts.iter().map(|&c| c as usize).sum();
        let mut all = vec![T::default(); total];
        {
            let mut part = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
            self.comm.all_gather_varcount_into(mine, &mut part);
        }
        split(all, &counts)
    }

    /// `send` holds, one after the other, `counts[r]` items for each process `r`; returns
    /// what every process sent here, one after the other in rank order, and how many from
    /// each. One buffer each way: no copies.
    pub fn all_to_all<T: Equivalence + Default + Clone>(
        &self,
        send: &[T],
        counts: &[usize],
    ) -> (Vec<T>, Vec<usize>) {
        let counts: Vec<i32> = counts.iter().map(|&c| c as i32).collect();
        let mut rcounts = vec![0i32; self.size];
        self.comm.all_to_all_into(&counts[..], &mut rcounts[..]);
        let (sd, rd) = (offsets(&counts), offsets(&rcounts));
        let total = rcounts.iter().map(|&c| c as usize).sum();
        let mut recv = vec![T::default(); total];
        {
            let s = Partition::new(send, &counts[..], &sd[..]);
            let mut r = PartitionMut::new(&mut recv[..], &rcounts[..], &rd[..]);
            self.comm.all_to_all_varcount_into(&s, &mut r);
        }
        (recv, rcounts.iter().map(|&c| c as usize).collect())
    }

    /// The bytes `mine` of process `root`, on every process.
    pub fn broadcast_bytes(&self, root: usize, mine: &[u8]) -> Vec<u8> {
        let mut len = mine.len() as u64;
        let process = self.comm.process_at_rank(root as i32);
        process.broadcast_into(&mut len);
        let mut buf = if self.rank == root {
            mine.to_vec()
        } else {
            vec![0u8; len as usize]
        };
        process.broadcast_into(&mut buf[..]);
        buf
    }
}

/// Exclusive prefix sums of `counts`.
fn offsets(counts: &[i32]) -> Vec<i32> {
    counts
        .iter()
        .scan(0i32, |acc, &c| {
            let d = *acc;
            *acc += c;
            Some(d)
        })
        .collect()
}

/// `all` cut into pieces of `counts`.
fn split<T>(all: Vec<T>, counts: &[i32]) -> Vec<Vec<T>> {
    let mut it = all.into_iter();
    counts
        .iter()
        .map(|&c| it.by_ref().take(c as usize).collect())
        .collect()
}

/// The first global id of process `r`'s block when `n` nodes are cut into `p` contiguous
/// blocks (the partition: no global array).
pub(super) fn block_start(n: u64, p: usize, r: usize) -> u64 {
    (u128::from(n) * r as u128 / p as u128) as u64
}

/// The process whose block holds global id `g`.
pub(super) fn block_owner(n: u64, p: usize, g: u64) -> usize {
    let mut r = ((u128::from(g) * p as u128) / u128::from(n.max(1))) as usize;
    r = r.min(p - 1);
    while r + 1 < p && block_start(n, p, r + 1) <= g {
        r += 1;
    }
    while r > 0 && block_start(n, p, r) > g {
        r -= 1;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::{block_owner, block_start};

    /// Every id's owner is the block that holds it, for uneven and tiny cuts.
    #[test]
    fn owners_match_blocks() {
        for (n, p) in [
            (10u64, 3usize),
            (7, 7),
            (5, 8),
            (2_097_152, 8),
            (1_000_003, 7),
        ] {
            for r in 0..p {
                let (a, b) = (block_start(n, p, r), block_start(n, p, r + 1));
                for g in [a, b.saturating_sub(1)]
                    .into_iter()
                    .filter(|&g| g >= a && g < b)
                {
                    assert_eq!(block_owner(n, p, g), r, "n {n} p {p} g {g}");
                }
            }
            assert_eq!(block_start(n, p, p), n);
        }
    }
}
