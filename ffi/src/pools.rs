//! The pools vocabulary: three caller buffers (`reals`, `indices`, `bytes`) that hold a
//! prepared plan (`crate::plan`), its transient work, or the multigrid hierarchy and scratch
//! of a stateless solve (`crate::spring`), and their sizes.
#![allow(unsafe_code)] // the buffers of a pools struct become `Out` tokens here.

use deform_kernel::plan::PlanSizes;
use deform_kernel::Real;
use deform_kernel_ffi_export::export;

use crate::args::{assert_layout, read_one};
use crate::slice::{output, In, Out};
use crate::status::dk_status;

/// Lengths of the three plan pools, or of the transient work buffers.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub struct dk_plan_sizes {
    /// Scalars (`double` for the f64 functions, `float` for the `_f32` ones).
    pub reals: usize,
    /// `uint32_t` entries.
    pub indices: usize,
    /// `uint8_t` entries.
    pub bytes: usize,
}
assert_layout!(dk_plan_sizes, 24; reals = 0, indices = 8, bytes = 16);

impl From<PlanSizes> for dk_plan_sizes {
    fn from(s: PlanSizes) -> Self {
        dk_plan_sizes {
            reals: s.reals,
            indices: s.indices,
            bytes: s.bytes,
        }
    }
}

/// Three caller buffers: a plan's pools (sized by [`dk_plan_pool_sizes`], written by
/// [`dk_plan_init`], read and updated by every step), the transient work of init (sized by
/// [`dk_plan_work_sizes`]), or the multigrid hierarchy and scratch of a stateless solve
/// (`dk_spring_solve_linear_amg`, `dk_spring_solve_angle_amg`; sized by their `_pool_sizes`
/// queries, `bytes` unused). Each buffer is used only by the call that receives the struct.
#[export(twin = dk_plan_pools)]
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_camel_case_types)]
pub struct DkPlanPools<T> {
    /// Scalars.
    pub reals: *mut T,
    /// Entries of `reals`.
    pub reals_len: usize,
    /// Indices.
    pub indices: *mut u32,
    /// Entries of `indices`.
    pub indices_len: usize,
    /// Bytes.
    pub bytes: *mut u8,
    /// Entries of `bytes`.
    pub bytes_len: usize,
}
assert_layout!(DkPlanPools<f64>, 48; reals = 0, indices = 16, bytes = 32, bytes_len = 40);

/// Three caller buffers (a plan's pools, or its transient work) as tokens.
pub(crate) struct PoolArgs<'a, T> {
    reals: Out<'a, T>,
    indices: Out<'a, u32>,
    bytes: Out<'a, u8>,
}

/// The precision twins of [`dk_plan_pools`], seen through [`PoolArgs`] (the plans and the
/// stateless multigrid solves of `crate::spring` take them).
pub(crate) trait PoolsC: Copy {
    type T: Real;
    /// Reads a pools struct and wraps its buffers in tokens of the struct's lifetime.
    fn read(p: In<'_, Self>) -> Result<PoolArgs<'_, Self::T>, dk_status>;
}

impl<T: Real> PoolsC for DkPlanPools<T> {
    type T = T;
    fn read(p: In<'_, Self>) -> Result<PoolArgs<'_, T>, dk_status> {
        let b = read_one(p)?;
        // SAFETY: a token for a pools struct carries the contract of the functions
        // that take one: its buffers are writable for their lengths, exclusively,
        // while it is.
        Ok(unsafe {
            PoolArgs {
                reals: Out::new(b.reals, b.reals_len),
                indices: Out::new(b.indices, b.indices_len),
                bytes: Out::new(b.bytes, b.bytes_len),
            }
        })
    }
}

/// The borrowed buffers of a [`PoolArgs`].
pub(crate) type Pools<'a, T> = (&'a mut [T], &'a mut [u32], &'a mut [u8]);

impl<'a, T: Real> PoolArgs<'a, T> {
    /// The three buffers (each NULL only with length 0).
    pub(crate) fn borrow(self) -> Result<Pools<'a, T>, dk_status> {
        Ok((
            output(self.reals)?,
            output(self.indices)?,
            output(self.bytes)?,
        ))
    }
}
