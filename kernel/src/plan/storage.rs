//! Fixed-capacity plan storage: the three pools as arrays whose lengths are const
//! parameters, for callers without a heap (a Cortex-M solver declares a `static` for its
//! mesh, sized at compile time by [`Plan::capacity`]).

use super::{Plan, PlanSizes, PlanSpec, PlanWork};
use crate::error::Result;
use crate::real::Real;

/// Owned pools of `REALS` reals, `INDICES` indices and `BYTES` bytes: a plan's storage, or
/// the transient [`PlanWork`] of its `init` ([`PlanStorage::work`]).
///
/// [`PlanStorage::new`] is `const`, so the storage can be a `static` (in a `static_cell`,
/// a `cortex_m::singleton!` or a mutex): nothing is sized by hand and nothing is allocated.
/// Sizes come from [`Plan::capacity`] (one-level solvers, exact) or from [`Plan::sizes`]
/// measured once (the multigrid solver); larger storage works, smaller is refused with
/// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall). Cloning the storage copies the
/// plan with its warm-start state (a checkpoint).
#[derive(Clone)]
pub struct PlanStorage<T, const REALS: usize, const INDICES: usize, const BYTES: usize> {
    reals: [T; REALS],
    indices: [u32; INDICES],
    bytes: [u8; BYTES],
}

impl<T: Real, const REALS: usize, const INDICES: usize, const BYTES: usize>
    PlanStorage<T, REALS, INDICES, BYTES>
{
    /// Zeroed storage.
    pub const fn new() -> Self {
        PlanStorage {
            reals: [T::ZERO; REALS],
            indices: [0; INDICES],
            bytes: [0; BYTES],
        }
    }

    /// The pool lengths: `REALS`, `INDICES`, `BYTES`.
    pub const fn capacity(&self) -> PlanSizes {
        PlanSizes {
            reals: REALS,
            indices: INDICES,
            bytes: BYTES,
        }
    }

    /// Builds a plan in this storage ([`Plan::init`]).
    ///
    /// # Errors
    /// Those of [`Plan::init`]; storage smaller than [`Plan::sizes`] is
    /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) with the length needed.
    pub fn init<const D: usize>(
        &mut self,
        spec: &PlanSpec<'_, T, D>,
        work: &mut PlanWork<'_, T>,
    ) -> Result<Plan<'_, T, D>> {
        Plan::init(
            spec,
            work,
            &mut self.reals,
            &mut self.indices,
            &mut self.bytes,
        )
    }

    /// Reopens the plan this storage holds ([`Plan::open`]).
    ///
    /// # Errors
    /// [`Error::BadPlan`](crate::Error::BadPlan) when it holds no plan of `T` and `D` (or a
    /// corrupted one).
    pub fn open<const D: usize>(&mut self) -> Result<Plan<'_, T, D>> {
        Plan::open(&mut self.reals, &mut self.indices, &mut self.bytes)
    }

    /// The storage as the transient work of [`Plan::sizes`] and [`Plan::init`] (sized by
    /// [`Plan::work_capacity`]).
    pub fn work(&mut self) -> PlanWork<'_, T> {
        PlanWork {
            reals: &mut self.reals,
            indices: &mut self.indices,
            bytes: &mut self.bytes,
        }
    }

    /// The three pools, read-only (to write a checkpoint).
    pub fn pools(&self) -> (&[T], &[u32], &[u8]) {
        (&self.reals, &self.indices, &self.bytes)
    }

    /// The three pools, writable (to read a checkpoint back; [`PlanStorage::open`] then
    /// checks it).
    pub fn pools_mut(&mut self) -> (&mut [T], &mut [u32], &mut [u8]) {
        (&mut self.reals, &mut self.indices, &mut self.bytes)
    }
}

/// The capacity, not the pools (which can hold hundreds of megabytes).
impl<T, const REALS: usize, const INDICES: usize, const BYTES: usize> core::fmt::Debug
    for PlanStorage<T, REALS, INDICES, BYTES>
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("PlanStorage")
            .field("reals", &REALS)
            .field("indices", &INDICES)
            .field("bytes", &BYTES)
            .finish()
    }
}

impl<T: Real, const REALS: usize, const INDICES: usize, const BYTES: usize> Default
    for PlanStorage<T, REALS, INDICES, BYTES>
{
    fn default() -> Self {
        Self::new()
    }
}
