//! The crate's only `unsafe`: turning a C pointer and a length into a Rust slice.
#![allow(unsafe_code)]

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
