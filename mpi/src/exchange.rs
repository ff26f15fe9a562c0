//! [`MpiExchange`]: the kernel's partitioned-data [`Exchange`] over an MPI communicator.
//!
//! Sums of `i64` words with `MPI_Allreduce` (`MPI_SUM`; all exact sums of a merge packed
//! into one call), maxima with `MPI_MAX`, and the halo exchange as one nonblocking send and
//! one nonblocking receive per neighbour (`MPI_Isend`/`MPI_Irecv`, then wait for all): only
//! the ghosts travel, never a whole vector.

use deform_kernel::exact_sum::ExactSum;
use deform_kernel::partition::{Exchange, Halo};
use mpi::collective::SystemOperation;
use mpi::traits::*;
use std::cell::Cell;

/// The [`Exchange`] of one process of an MPI communicator, counting what it sends.
pub struct MpiExchange<'c, C: Communicator> {
    comm: &'c C,
    /// Bytes this process has sent in halo exchanges.
    halo_bytes: Cell<u64>,
    /// Bytes this process has contributed to reductions.
    reduce_bytes: Cell<u64>,
}

impl<C: Communicator> std::fmt::Debug for MpiExchange<'_, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiExchange")
            .field("rank", &self.comm.rank())
            .field("size", &self.comm.size())
            .finish()
    }
}

impl<'c, C: Communicator> MpiExchange<'c, C> {
    /// The exchange of this process over `comm`.
    pub fn new(comm: &'c C) -> Self {
        MpiExchange {
            comm,
            halo_bytes: Cell::new(0),
            reduce_bytes: Cell::new(0),
        }
    }

    /// `(halo bytes sent, reduction bytes contributed)` so far by this process.
    pub fn bytes(&self) -> (u64, u64) {
        (self.halo_bytes.get(), self.reduce_bytes.get())
    }

    fn count_reduce(&self, bytes: usize) {
        self.reduce_bytes
            .set(self.reduce_bytes.get() + bytes as u64);
    }
}

impl<C: Communicator> Exchange<f64> for MpiExchange<'_, C> {
    fn sum_words(&self, words: &mut [i64]) {
        self.count_reduce(std::mem::size_of_val(words));
        let send = words.to_vec();
        self.comm
            .all_reduce_into(&send[..], words, SystemOperation::sum());
    }

    fn max(&self, values: &mut [f64]) {
        self.count_reduce(std::mem::size_of_val(values));
        let send = values.to_vec();
        self.comm
            .all_reduce_into(&send[..], values, SystemOperation::max());
    }

    /// All sums in one `MPI_Allreduce`.
    fn sum_exact(&self, groups: &mut [&mut [ExactSum]]) {
        crate::whole::sum_exact_packed(groups, |w| self.sum_words(w));
    }

    fn exchange(&self, halo: &Halo<'_>, field: &mut [f64], width: usize) {
        let send: Vec<f64> = halo
            .send_entries()
            .iter()
            .flat_map(|&i| {
                let a = i as usize * width;
                field[a..a + width].iter().copied()
            })
            .collect();
        self.halo_bytes
            .set(self.halo_bytes.get() + std::mem::size_of_val(&send[..]) as u64);
        let mut recv = vec![0.0f64; halo.receive_entries().len() * width];
        mpi::request::scope(|scope| {
            let mut requests = Vec::new();
            let mut rest_send = &send[..];
            let mut rest_recv = &mut recv[..];
            for (rank, s, r) in halo.neighbours() {
                let process = self.comm.process_at_rank(rank as i32);
                let (out, tail) = rest_send.split_at(s.len() * width);
                rest_send = tail;
                requests.push(process.immediate_send(scope, out));
                let (into, tail) = std::mem::take(&mut rest_recv).split_at_mut(r.len() * width);
                rest_recv = tail;
                requests.push(process.immediate_receive_into(scope, into));
            }
            for r in requests {
                r.wait();
            }
        });
        for (&i, v) in halo
            .receive_entries()
            .iter()
            .zip(recv.chunks_exact(width.max(1)))
        {
            let a = i as usize * width;
            field[a..a + width].copy_from_slice(v);
        }
    }
}
