//! The crate's only `unsafe`: turning a C pointer and a length into a Rust slice.
#![allow(unsafe_code)]

use deform_kernel::{Quat, Real};

use crate::status::dk_status;

/// Borrows `len` elements at `ptr` as a shared slice. A NULL pointer is an error unless `len`
/// is 0 (then an empty slice is returned whatever the pointer).
///
/// # Safety
/// If `ptr` is non-NULL and `len > 0`, `ptr` must point to `len` initialised, properly aligned
/// elements that stay valid and are not written through another pointer for `'a`.
pub(crate) unsafe fn input<'a, T>(ptr: *const T, len: usize) -> Result<&'a [T], dk_status> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(dk_status::DK_ERR_NULL_POINTER);
    }
    // SAFETY: non-NULL and aligned (checked above); validity for `len` elements and the
    // absence of concurrent writes are the caller's contract, documented on every `dk_*`
    // function that takes this buffer.
    Ok(unsafe { core::slice::from_raw_parts(ptr, len) })
}

/// Borrows `len` elements at `ptr` as a mutable slice; NULL is an error unless `len` is 0.
///
/// # Safety
/// If `ptr` is non-NULL and `len > 0`, `ptr` must point to `len` properly aligned elements,
/// valid for reads and writes and not accessed through any other pointer for `'a`.
pub(crate) unsafe fn output<'a, T>(ptr: *mut T, len: usize) -> Result<&'a mut [T], dk_status> {
    if len == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(dk_status::DK_ERR_NULL_POINTER);
    }
    // SAFETY: non-NULL and aligned (checked above); exclusivity and validity for `len`
    // elements are the caller's contract, documented on every `dk_*` function.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, len) })
}

/// Borrows a single value (NULL is an error).
///
/// # Safety
/// `ptr` must be NULL or point to a valid, aligned, exclusively accessible `T`.
pub(crate) unsafe fn out_one<'a, T>(ptr: *mut T) -> Result<&'a mut T, dk_status> {
    // SAFETY: forwarded contract; a one-element slice of `ptr`.
    let s = unsafe { output(ptr, 1) }?;
    s.first_mut().ok_or(dk_status::DK_ERR_NULL_POINTER)
}

/// Reinterprets a flat buffer of `len` scalars as `len / D` items `[T; D]` (points with `D`
/// coordinates, values with `D` components). `len` must be a multiple of `D` (else
/// `DK_ERR_LENGTH_MISMATCH`); NULL is an error unless `len` is 0. [`chunks_mut`] is the
/// mutable twin.
///
/// # Safety
/// As [`input`].
pub(crate) unsafe fn chunks<'a, T, const D: usize>(
    ptr: *const T,
    len: usize,
) -> Result<&'a [[T; D]], dk_status> {
    // SAFETY: forwarded contract.
    let flat: &'a [T] = unsafe { input(ptr, len) }?;
    if D == 0 || len % D != 0 {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    // SAFETY: `[T; D]` has the size of `D` values `T` and the alignment of `T`, with no
    // padding, so `len / D` arrays occupy exactly the `len` initialised, aligned values of
    // `flat`, which stay borrowed (shared) for `'a`.
    Ok(unsafe { core::slice::from_raw_parts(flat.as_ptr().cast::<[T; D]>(), len / D) })
}

/// Mutable twin of [`chunks`].
///
/// # Safety
/// As [`output`].
pub(crate) unsafe fn chunks_mut<'a, T, const D: usize>(
    ptr: *mut T,
    len: usize,
) -> Result<&'a mut [[T; D]], dk_status> {
    // SAFETY: forwarded contract.
    let flat: &'a mut [T] = unsafe { output(ptr, len) }?;
    if D == 0 || len % D != 0 {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    // SAFETY: as in `chunks`; the exclusive borrow of `flat` moves into the returned slice,
    // so no other reference to these values exists for `'a`.
    Ok(unsafe { core::slice::from_raw_parts_mut(flat.as_mut_ptr().cast::<[T; D]>(), len / D) })
}

/// Reinterprets a flat buffer of `len` scalars as `len / 4` quaternions (scalar first, the
/// layout of the kernel's `#[repr(C)]` [`Quat`]). `len` must be a multiple of 4 (else
/// `DK_ERR_LENGTH_MISMATCH`); NULL is an error unless `len` is 0. [`quats_mut`] is the mutable
/// twin.
///
/// # Safety
/// As [`input`].
pub(crate) unsafe fn quats<'a, T: Real>(
    ptr: *const T,
    len: usize,
) -> Result<&'a [Quat<T>], dk_status> {
    // SAFETY: forwarded contract.
    let flat: &'a [[T; 4]] = unsafe { chunks::<T, 4>(ptr, len) }?;
    // SAFETY: `Quat<T>` is `#[repr(C)]` with exactly four fields of type `T` (asserted for
    // both scalar types below), so it has the size and alignment of `[T; 4]` and every bit
    // pattern of four `T` is a valid `Quat<T>`; the shared borrow carries over for `'a`.
    Ok(unsafe { core::slice::from_raw_parts(flat.as_ptr().cast::<Quat<T>>(), flat.len()) })
}

/// Mutable twin of [`quats`].
///
/// # Safety
/// As [`output`].
pub(crate) unsafe fn quats_mut<'a, T: Real>(
    ptr: *mut T,
    len: usize,
) -> Result<&'a mut [Quat<T>], dk_status> {
    // SAFETY: forwarded contract.
    let flat: &'a mut [[T; 4]] = unsafe { chunks_mut::<T, 4>(ptr, len) }?;
    // SAFETY: as in `quats`; the exclusive borrow of `flat` moves into the returned slice.
    Ok(unsafe { core::slice::from_raw_parts_mut(flat.as_mut_ptr().cast::<Quat<T>>(), flat.len()) })
}

const _: () = assert!(
    core::mem::size_of::<Quat<f64>>() == core::mem::size_of::<[f64; 4]>()
        && core::mem::align_of::<Quat<f64>>() == core::mem::align_of::<[f64; 4]>()
        && core::mem::size_of::<Quat<f32>>() == core::mem::size_of::<[f32; 4]>()
        && core::mem::align_of::<Quat<f32>>() == core::mem::align_of::<[f32; 4]>()
);
