//! A multigrid solve in two caller buffers, `reals` and `indices`: their exact lengths and
//! where the symbolic work, the hierarchy and the solve's scratch go, so that every caller
//! with one pair of buffers (the C ABI's stateless `dk_spring_solve_*_amg`, an embedded code)
//! sizes and splits them the same way.

use super::pcg::{amg_cg_scratch_len, amg_sliding_cg_scratch_len};
use super::{AmgHierarchy, AmgOptions};
use crate::error::{Error, Result};
use crate::real::Real;
use crate::spring::SpringSystem;

/// The CG a multigrid hierarchy preconditions, which decides the scratch it needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AmgSolve {
    /// [`SpringSystem::solve_linear_amg`] and the angle springs' multigrid CG
    /// ([`amg_cg_scratch_len`] items).
    Cg,
    /// The sliding solves with a multigrid preconditioner ([`amg_sliding_cg_scratch_len`]
    /// items).
    SlidingCg,
}

/// The layout of a multigrid solve in two buffers: `indices` holds the symbolic pass's work
/// ([`AmgHierarchy::setup_work_len`] entries, whose front may first serve the system's
/// validation) and then the hierarchy's index; `reals` holds the hierarchy's values and then
/// the solve's scratch items (`[T; V]` each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AmgPools {
    work: usize,
    index: usize,
    values: usize,
    items: usize,
}

impl AmgPools {
    /// Runs the hierarchy's symbolic pass for `sys` in the front of `indices` and lays the
    /// buffers of `solve` out. The layout depends on the graph and the fixed mask (and on the
    /// stiffness only when `strength_theta` > 0).
    ///
    /// # Errors
    /// `indices` shorter than [`AmgHierarchy::setup_work_len`] ([`Error::BufferTooSmall`]),
    /// those of [`AmgHierarchy::setup_len`], a scratch count that overflows
    /// ([`Error::TooLarge`]). Only the front of `indices` is written.
    pub fn layout<T: Real>(
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        solve: AmgSolve,
        indices: &mut [u32],
    ) -> Result<Self> {
        let (work, actual) = (AmgHierarchy::setup_work_len(sys), indices.len());
        let short = Error::BufferTooSmall {
            arg: "indices",
            needed: work,
            actual,
        };
        let sizes = AmgHierarchy::setup_len(sys, options, indices.get_mut(..work).ok_or(short)?)?;
        let (n, coarse) = (sys.node_count(), sizes.coarse_unknowns);
        let items = match solve {
            AmgSolve::Cg => amg_cg_scratch_len(n, coarse),
            AmgSolve::SlidingCg => amg_sliding_cg_scratch_len(n, coarse),
        };
        Ok(AmgPools {
            work,
            index: sizes.index,
            values: sizes.values,
            items: items.ok_or(Error::TooLarge {
                arg: "node_count",
                value: n,
            })?,
        })
    }

    /// The exact lengths `[reals, indices]` for scratch items of `components` scalars.
    ///
    /// # Errors
    /// A length that overflows `usize` ([`Error::TooLarge`]).
    pub fn lens(&self, components: usize) -> Result<[usize; 2]> {
        let reals = self
            .items
            .checked_mul(components)
            .and_then(|s| s.checked_add(self.values));
        let indices = self.work.checked_add(self.index);
        match (reals, indices) {
            (Some(r), Some(i)) => Ok([r, i]),
            _ => Err(Error::TooLarge {
                arg: "components",
                value: components,
            }),
        }
    }

    /// Checks both buffers against [`AmgPools::lens`] for `V` components, then sets the
    /// hierarchy of `sys` up in them (longer buffers give the same bits); returns it with the
    /// solve's scratch.
    ///
    /// # Errors
    /// A buffer shorter than its length ([`Error::BufferTooSmall`], before anything is
    /// written), those of [`AmgPools::lens`] and [`AmgHierarchy::setup`].
    pub fn setup<'p, T: Real, const V: usize>(
        &self,
        sys: &SpringSystem<'_, T>,
        options: &AmgOptions<T>,
        reals: &'p mut [T],
        indices: &'p mut [u32],
    ) -> Result<(AmgHierarchy<'p, T>, &'p mut [[T; V]])> {
        let [r, i] = self.lens(V)?;
        let short = |arg, needed, actual| Error::BufferTooSmall {
            arg,
            needed,
            actual,
        };
        let (rl, il) = (reals.len(), indices.len());
        if rl < r || il < i {
            return Err(if rl < r {
                short("reals", r, rl)
            } else {
                short("indices", i, il)
            });
        }
        let (work, index) =
            (indices.split_at_mut_checked(self.work)).ok_or(short("indices", i, il))?;
        let (values, rest) =
            (reals.split_at_mut_checked(self.values)).ok_or(short("reals", r, rl))?;
        let h = AmgHierarchy::setup(sys, options, work, index, values)?;
        Ok((h, rest.as_chunks_mut::<V>().0))
    }
}
