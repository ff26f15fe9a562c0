//! Distributed solves: the caller's message passing behind a small trait.
//!
//! A [`Collective`] says which nodes this process computes and how partial results meet:
//! exact sums are merged by adding their words ([`ExactSum::to_words`], `MPI_SUM` on
//! `MPI_INT64_T`), maxima by `MPI_MAX`, and a field whose owned rows were just updated is
//! made current everywhere (`share`). Every process holds the whole system and whole value
//! fields (replicated data); only rows are divided. The linear-spring CG with a Jacobi or no
//! preconditioner and the multigrid-preconditioned CG take one through
//! [`LinearSolver`](super::LinearSolver), and give the serial bits for every partition
//! (their sums are exact, their row updates are the serial ones): the serial solves are the
//! same code with [`Serial`].

use core::ops::Range;

use crate::exact_sum::ExactSum;
use crate::real::Real;

/// The message passing a distributed solve needs (one implementation per process; methods
/// take `&self`, as an MPI communicator does).
pub trait Collective<T: Real>: core::fmt::Debug {
    /// The node ranges this process computes: sorted, disjoint, and over all processes each
    /// node exactly once.
    fn owned(&self) -> &[Range<usize>];
    /// Element-wise sum over all processes, in place (`MPI_Allreduce`, `MPI_SUM`, `i64`).
    fn sum_words(&self, words: &mut [i64]);
    /// Replaces every exact sum in `groups` by its sum over all processes. The default
    /// exchanges each sum's words in place with [`sum_words`](Self::sum_words) (no buffer:
    /// the kernel keeps no stack copies of its 584-byte accumulators on 32-bit targets); an implementation
    /// with a heap may pack all of them into one exchange, as `deform-mpi` does.
    fn sum_exact(&self, groups: &mut [&mut [ExactSum]]) {
        for sum in groups.iter_mut().flat_map(|g| g.iter_mut()) {
            sum.exchange(|words| self.sum_words(words));
        }
    }
    /// Element-wise maximum over all processes, in place (`MPI_Allreduce`, `MPI_MAX`).
    fn max(&self, values: &mut [T]);
    /// `field` holds `width` reals per node; on return every node holds the value its owner
    /// had (each process has just updated its own rows).
    fn share(&self, field: &mut [T], width: usize);
    /// As [`share`](Self::share), but only the nodes next to this process's own rows (its
    /// halo) need to be current afterwards: all a sweep over the own rows reads. Defaults to
    /// `share`.
    fn share_halo(&self, field: &mut [T], width: usize) {
        self.share(field, width);
    }
}

/// One process owning every node: the serial solves.
#[derive(Clone, Debug)]
pub struct Serial {
    all: [Range<usize>; 1],
}

impl Serial {
    /// Every node of an `n`-node system.
    pub fn new(n: usize) -> Self {
        Serial {
            all: [Range { start: 0, end: n }],
        }
    }
}

impl<T: Real> Collective<T> for Serial {
    fn owned(&self) -> &[Range<usize>] {
        &self.all
    }
    fn sum_words(&self, _: &mut [i64]) {}
    fn sum_exact(&self, _: &mut [&mut [ExactSum]]) {}
    fn max(&self, _: &mut [T]) {}
    fn share(&self, _: &mut [T], _: usize) {}
}

/// Merges per-component exact sums over all processes (one exchange) and rounds them.
pub(crate) fn merged<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    comm: &C,
    sums: &mut [ExactSum; V],
) -> [T; V] {
    comm.sum_exact(&mut [sums]);
    sums.each_ref().map(|s| s.value())
}

/// Merges one exact sum over all processes and rounds it.
pub(crate) fn merged_one<T: Real, C: Collective<T> + ?Sized>(comm: &C, sum: &mut ExactSum) -> T {
    comm.sum_exact(&mut [core::slice::from_mut(sum)]);
    sum.value()
}

/// Merges `first` and `rest` over all processes in one exchange and rounds them.
pub(crate) fn merged_with<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    comm: &C,
    first: &mut ExactSum,
    rest: &mut [ExactSum; V],
) -> (T, [T; V]) {
    comm.sum_exact(&mut [core::slice::from_mut(first), rest]);
    (first.value(), rest.each_ref().map(|s| s.value()))
}

/// Element-wise maximum over all processes.
pub(crate) fn merged_max<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    comm: &C,
    mut v: [T; V],
) -> [T; V] {
    comm.max(&mut v);
    v
}

/// Shares a `[T; V]` field's owned rows with every process.
pub(crate) fn share_field<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    comm: &C,
    field: &mut [[T; V]],
) {
    comm.share(field.as_flattened_mut(), V);
}

/// Checks a process's owned ranges: each within `0..n`, sorted and disjoint.
pub(crate) fn check_owned<T: Real, C: Collective<T> + ?Sized>(
    comm: &C,
    n: usize,
) -> crate::error::Result<()> {
    let mut end = 0;
    for r in comm.owned() {
        if r.start < end || r.start > r.end || r.end > n {
            return Err(crate::error::Error::InvalidParameter {
                arg: "owned",
                reason: "owned node ranges must be sorted, disjoint and within the node count",
            });
        }
        end = r.end;
    }
    Ok(())
}

/// Shares the halo of a `[T; V]` field's owned rows.
pub(crate) fn share_halo<T: Real, const V: usize, C: Collective<T> + ?Sized>(
    comm: &C,
    field: &mut [[T; V]],
) {
    comm.share_halo(field.as_flattened_mut(), V);
}
