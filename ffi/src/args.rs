//! Argument reading and writing shared by every entry point: status plumbing, single values,
//! size queries, optional arrays, index bases and ranges, CSR graphs, structured blocks,
//! points, and the dispatch on the point dimension or the number of value components.
//!
//! Every raw pointer is turned into a reference by [`crate::slice`]; the helpers here only
//! forward the contract of the public function that received the pointer.

use deform_kernel::Block;

use crate::slice::{chunks, input, input_n, out_one, output_n, In, Out};
use crate::status::dk_status;

/// `Ok(())` → `DK_OK`, `Err(s)` → `s`.
pub(crate) fn done(r: Result<(), dk_status>) -> dk_status {
    match r {
        Ok(()) => dk_status::DK_OK,
        Err(s) => s,
    }
}

/// Copies one `T` from `p` (NULL is an error).
pub(crate) fn read_one<T: Copy>(p: In<'_, T>) -> Result<T, dk_status> {
    let s = input_n(p, 1)?;
    s.first().copied().ok_or(dk_status::DK_ERR_NULL_POINTER)
}

/// Writes one `T` to `p` (NULL is an error).
pub(crate) fn write_one<T>(p: Out<'_, T>, v: T) -> Result<(), dk_status> {
    let out = out_one(p)?;
    *out = v;
    Ok(())
}

/// Writes a size query result to `len_out` (NULL is an error).
pub(crate) fn write_len(len_out: Out<'_, usize>, len: usize) -> Result<(), dk_status> {
    write_one(len_out, len)
}

/// Reads exactly `N` scalars (the length must be `N`, else `DK_ERR_LENGTH_MISMATCH`; NULL is
/// an error).
pub(crate) fn read_array<T: Copy, const N: usize>(ptr: In<'_, T>) -> Result<[T; N], dk_status> {
    if ptr.len() != N {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    let s = chunks::<T, N>(ptr)?;
    s.first().copied().ok_or(dk_status::DK_ERR_NULL_POINTER)
}

/// Writes `N` scalars to `ptr` (NULL is an error).
pub(crate) fn write_array<T, const N: usize>(ptr: Out<'_, T>, v: [T; N]) -> Result<(), dk_status> {
    let s = output_n(ptr, N)?;
    for (d, x) in s.iter_mut().zip(v) {
        *d = x;
    }
    Ok(())
}

/// An optional input array: `None` when `ptr` is NULL with length 0, else the borrowed
/// slice (so a non-NULL pointer with length 0 is an empty array, checked by the kernel).
pub(crate) fn optional<T>(ptr: In<'_, T>) -> Result<Option<&[T]>, dk_status> {
    if ptr.is_absent() {
        return Ok(None);
    }
    input(ptr).map(Some)
}

/// Borrows a point array of `D`-vectors (a multiple of `D` scalars).
pub(crate) fn read_points<T, const D: usize>(p: In<'_, T>) -> Result<&[[T; D]], dk_status> {
    chunks::<T, D>(p)
}

/// An optional point array, as [`optional`]: `None` when `p` is NULL with length 0.
pub(crate) fn read_optional_points<T, const D: usize>(
    p: In<'_, T>,
) -> Result<Option<&[[T; D]]>, dk_status> {
    if p.is_absent() {
        return Ok(None);
    }
    read_points::<T, D>(p).map(Some)
}

/// `n * m` or `DK_ERR_TOO_LARGE`.
pub(crate) fn mul_len(n: usize, m: usize) -> Result<usize, dk_status> {
    n.checked_mul(m).ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// Checks `index_base` (0 or 1; else `DK_ERR_BAD_INDEX_BASE`).
pub(crate) fn check_base(index_base: u32) -> Result<(), dk_status> {
    match index_base {
        0 | 1 => Ok(()),
        _ => Err(dk_status::DK_ERR_BAD_INDEX_BASE),
    }
}

/// A caller's index `i` in a checked `index_base` as a 0-based index. An index below the base
/// becomes `u32::MAX`, which every bound rejects.
pub(crate) fn zero_based(i: u32, index_base: u32) -> u32 {
    i.checked_sub(index_base).unwrap_or(u32::MAX)
}

/// The 0-based view of a caller's index array: the array itself (`index_base` 0), or a
/// converted copy in the front of `scratch` (`index_base` 1; an index below the base becomes
/// `u32::MAX`, which every bound rejects). Returns the view and the unused rest of `scratch`.
pub(crate) fn rebase<'a>(
    src: &'a [u32],
    index_base: u32,
    scratch: &'a mut [u32],
) -> Result<(&'a [u32], &'a mut [u32]), dk_status> {
    match index_base {
        0 => Ok((src, scratch)),
        1 => {
            let (head, tail) = scratch
                .split_at_mut_checked(src.len())
                .ok_or(dk_status::DK_ERR_BUFFER_TOO_SMALL)?;
            for (d, &s) in head.iter_mut().zip(src) {
                *d = zero_based(s, index_base);
            }
            Ok((&*head, tail))
        }
        _ => Err(dk_status::DK_ERR_BAD_INDEX_BASE),
    }
}

/// Number of `index_scratch` entries that rebasing arrays of `lens` entries needs.
pub(crate) fn index_need(index_base: u32, lens: &[usize]) -> Result<usize, dk_status> {
    check_base(index_base)?;
    if index_base == 0 {
        return Ok(0);
    }
    lens.iter()
        .try_fold(0usize, |a, &l| a.checked_add(l))
        .ok_or(dk_status::DK_ERR_TOO_LARGE)
}

/// Converts a caller's index range (`index_base` 0: `start <= i < end`; 1: 1-based inclusive
/// `start <= i <= end`) to a 0-based half-open range. A 1-based start of 0 is out of range.
pub(crate) fn range(start: usize, end: usize, index_base: u32) -> Result<[usize; 2], dk_status> {
    check_base(index_base)?;
    match start.checked_sub(index_base as usize) {
        Some(s) => Ok([s, end]),
        None => Err(dk_status::DK_ERR_INDEX_OUT_OF_RANGE),
    }
}

/// Validates the dimensions of a structured block.
pub(crate) fn block(ni: usize, nj: usize, nk: usize) -> Result<Block, dk_status> {
    Block::new([ni, nj, nk]).map_err(dk_status::from)
}

/// Asserts at compile time the size of a `#[repr(C)]` type and the offsets of its fields (the
/// layout the header promises) on 64-bit targets, where the figures are written for.
macro_rules! assert_layout {
    ($t:ty, $size:expr; $($field:ident = $offset:expr),+ $(,)?) => {
        #[cfg(target_pointer_width = "64")]
        const _: () = assert!(
            core::mem::size_of::<$t>() == $size
                $(&& core::mem::offset_of!($t, $field) == $offset)+
        );
    };
}
pub(crate) use assert_layout;

/// Dispatches on the point dimension `dim` (2 or 3; else `DK_ERR_INVALID_PARAMETER`).
macro_rules! by_dim {
    ($dim:expr, $f:ident :: <$t:ty>, ($($arg:expr),* $(,)?)) => {
        match $dim {
            2 => $f::<$t, 2>($($arg),*),
            3 => $f::<$t, 3>($($arg),*),
            _ => Err($crate::status::dk_status::DK_ERR_INVALID_PARAMETER),
        }
    };
}
pub(crate) use by_dim;

/// Dispatches on the number of value components `V` (1 to 7; else
/// `DK_ERR_INVALID_PARAMETER`).
macro_rules! by_components {
    ($v:expr, $f:ident :: <$t:ty>, ($($arg:expr),* $(,)?)) => {
        match $v {
            1 => $f::<$t, 1>($($arg),*),
            2 => $f::<$t, 2>($($arg),*),
            3 => $f::<$t, 3>($($arg),*),
            4 => $f::<$t, 4>($($arg),*),
            5 => $f::<$t, 5>($($arg),*),
            6 => $f::<$t, 6>($($arg),*),
            7 => $f::<$t, 7>($($arg),*),
            _ => Err($crate::status::dk_status::DK_ERR_INVALID_PARAMETER),
        }
    };
}
pub(crate) use by_components;

/// The point dimension `D` (2 or 3) of an exported function that takes `_dim: Dim<D>`: in C a
/// `uint32_t dim`, whose value the generated wrapper turns into `D` before anything else is
/// read (any other value is `DK_ERR_INVALID_PARAMETER`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Dim<const D: usize>;

/// The number of value components `V` (1 to 7) of an exported function that takes
/// `_components: Components<V>`: in C a `uint32_t components`, dispatched as [`Dim`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Components<const V: usize>;
