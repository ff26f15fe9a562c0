//! The crate's only pointer dereferences: turning a caller's pointer and length into a Rust
//! slice.
//!
//! An `extern "C"` function wraps each pointer it receives, with the length its contract
//! promises, in an [`In`] (read) or [`Out`] (write) token; that construction is `unsafe` and
//! carries the `// SAFETY:` note, at the ABI boundary and nowhere else. Everything below takes
//! tokens and is safe: the functions here check NULL, alignment and that no more than the
//! promised length is borrowed, so no safe code can read or write outside what the caller
//! promised. An [`Out`] is not `Copy` and each borrow consumes it, so it yields at most one
//! `&mut` slice.
#![allow(unsafe_code)]

use core::marker::PhantomData;

use deform_kernel::{Quat, Real};

use crate::status::dk_status;

/// A caller's input buffer: a pointer and the number of elements the caller promised are
/// readable there for `'a` (see [`In::new`]).
pub(crate) struct In<'a, T> {
    ptr: *const T,
    cap: usize,
    life: PhantomData<&'a [T]>,
}

impl<T> Clone for In<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for In<'_, T> {}

impl<'a, T> In<'a, T> {
    /// Wraps an input pointer.
    ///
    /// # Safety
    /// `ptr` is NULL, or points to `cap` initialised elements (properly aligned, or the token
    /// reports NULL) that stay valid and are not written through another pointer while any
    /// slice borrowed from this token lives (at most `'a`). An output the function's contract
    /// allows to alias this input is written only after the input was copied.
    pub(crate) unsafe fn new(ptr: *const T, cap: usize) -> Self {
        In {
            ptr,
            cap,
            life: PhantomData,
        }
    }

    /// Whether the caller left this optional array out: NULL with length 0.
    pub(crate) fn is_absent(&self) -> bool {
        self.ptr.is_null() && self.cap == 0
    }

    /// The number of elements the caller promised (its `_len` argument).
    pub(crate) fn len(&self) -> usize {
        self.cap
    }
}

/// A caller's output buffer: a pointer and the number of elements the caller promised are
/// writable there, exclusively, for `'a` (see [`Out::new`]).
pub(crate) struct Out<'a, T> {
    ptr: *mut T,
    cap: usize,
    life: PhantomData<&'a mut [T]>,
}

impl<'a, T> Out<'a, T> {
    /// Wraps an output pointer.
    ///
    /// # Safety
    /// `ptr` is NULL, or points to `cap` elements (properly aligned, or the token reports
    /// NULL) valid for reads and writes and not accessed through any other pointer while the
    /// slice borrowed from this token lives (at most `'a`), except inputs the function's
    /// contract allows to alias it, which are read before it is written.
    pub(crate) unsafe fn new(ptr: *mut T, cap: usize) -> Self {
        Out {
            ptr,
            cap,
            life: PhantomData,
        }
    }

    /// The number of elements the caller promised (its `_len` argument).
    pub(crate) fn len(&self) -> usize {
        self.cap
    }

    /// Whether two output tokens name the same address.
    pub(crate) fn same_address<U>(&self, other: &Out<'_, U>) -> bool {
        core::ptr::eq(self.ptr.cast::<u8>(), other.ptr.cast::<u8>())
    }
}

/// NULL (unless `len` is 0), misalignment, a length beyond the promised one and a length no
/// object can have (over `isize::MAX` bytes: no slice may be that long) are errors.
fn check<T>(ptr: *const T, cap: usize, len: usize) -> Result<(), dk_status> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(dk_status::DK_ERR_NULL_POINTER);
    }
    if len > cap {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    if len > isize::MAX as usize / core::mem::size_of::<T>().max(1) {
        return Err(dk_status::DK_ERR_TOO_LARGE);
    }
    Ok(())
}

/// Borrows all `p.len()` elements of `p` (the caller's whole buffer) as a shared slice; NULL
/// is an error unless the length is 0.
pub(crate) fn input<T>(p: In<'_, T>) -> Result<&[T], dk_status> {
    input_n(p, p.cap)
}

/// Borrows the first `len` elements of `p` as a shared slice. A NULL pointer is an error
/// unless `len` is 0 (then an empty slice is returned whatever the pointer).
pub(crate) fn input_n<T>(p: In<'_, T>, len: usize) -> Result<&[T], dk_status> {
    if len == 0 {
        return Ok(&[]);
    }
    check(p.ptr, p.cap, len)?;
    // SAFETY: non-NULL, aligned and `len <= cap` (checked above); by the contract of
    // `In::new`, `cap` initialised elements are readable and unaliased by writes for `'a`.
    Ok(unsafe { core::slice::from_raw_parts(p.ptr, len) })
}

/// Borrows all `p.len()` elements of `p` as a mutable slice; NULL is an error unless the
/// length is 0. Consumes the token, so this is the only slice of it.
pub(crate) fn output<'a, T>(p: Out<'a, T>) -> Result<&'a mut [T], dk_status> {
    let len = p.cap;
    output_n(p, len)
}

/// Borrows the first `len` elements of `p` as a mutable slice; NULL is an error unless `len`
/// is 0. Consumes the token, so this is the only slice of it.
pub(crate) fn output_n<T>(p: Out<'_, T>, len: usize) -> Result<&mut [T], dk_status> {
    if len == 0 {
        return Ok(&mut []);
    }
    check(p.ptr, p.cap, len)?;
    // SAFETY: non-NULL, aligned and `len <= cap` (checked above); by the contract of
    // `Out::new`, `cap` elements are writable and not accessed otherwise for `'a`, and the
    // token is consumed, so no second slice of it exists.
    Ok(unsafe { core::slice::from_raw_parts_mut(p.ptr, len) })
}

/// Borrows a single value (NULL is an error).
pub(crate) fn out_one<T>(p: Out<'_, T>) -> Result<&mut T, dk_status> {
    let s = output_n(p, 1)?;
    s.first_mut().ok_or(dk_status::DK_ERR_NULL_POINTER)
}

/// Reinterprets a flat buffer of `len` scalars (the token's length) as `len / D` items
/// `[T; D]` (points with `D` coordinates, values with `D` components). `len` must be a
/// multiple of `D` (else `DK_ERR_LENGTH_MISMATCH`); NULL is an error unless `len` is 0.
/// [`chunks_mut`] is the mutable twin.
pub(crate) fn chunks<T, const D: usize>(p: In<'_, T>) -> Result<&[[T; D]], dk_status> {
    let len = p.cap;
    let flat = input(p)?;
    if D == 0 || len % D != 0 {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    Ok(flat.as_chunks::<D>().0)
}

/// Mutable twin of [`chunks`].
pub(crate) fn chunks_mut<T, const D: usize>(p: Out<'_, T>) -> Result<&mut [[T; D]], dk_status> {
    let len = p.cap;
    chunks_mut_n(p, len)
}

/// The whole items of a scratch buffer that may be longer than needed (a length that is not a
/// multiple of `D` leaves its tail unused).
pub(crate) fn whole_chunks_mut<T, const D: usize>(
    p: Out<'_, T>,
) -> Result<&mut [[T; D]], dk_status> {
    let len = p.cap - p.cap % D.max(1);
    chunks_mut_n(p, len)
}

/// [`chunks_mut`] of the first `len` scalars.
fn chunks_mut_n<T, const D: usize>(p: Out<'_, T>, len: usize) -> Result<&mut [[T; D]], dk_status> {
    let flat = output_n(p, len)?;
    if D == 0 || len % D != 0 {
        return Err(dk_status::DK_ERR_LENGTH_MISMATCH);
    }
    Ok(flat.as_chunks_mut::<D>().0)
}

/// Reinterprets a flat buffer of `len` scalars (the token's length) as `len / 4` quaternions
/// (scalar first, the layout of the kernel's `#[repr(C)]` [`Quat`]). `len` must be a multiple
/// of 4 (else `DK_ERR_LENGTH_MISMATCH`); NULL is an error unless `len` is 0. [`quats_mut`] is
/// the mutable twin.
pub(crate) fn quats<T: Real>(p: In<'_, T>) -> Result<&[Quat<T>], dk_status> {
    let flat: &[[T; 4]] = chunks::<T, 4>(p)?;
    // SAFETY: `Quat<T>` is `#[repr(C)]` with exactly four fields of type `T` (asserted for
    // both scalar types below), so it has the size and alignment of `[T; 4]` and every bit
    // pattern of four `T` is a valid `Quat<T>`; the shared borrow carries over.
    Ok(unsafe { core::slice::from_raw_parts(flat.as_ptr().cast::<Quat<T>>(), flat.len()) })
}

/// Mutable twin of [`quats`].
pub(crate) fn quats_mut<T: Real>(p: Out<'_, T>) -> Result<&mut [Quat<T>], dk_status> {
    let flat: &mut [[T; 4]] = chunks_mut::<T, 4>(p)?;
    // SAFETY: as in `quats`; the exclusive borrow of `flat` moves into the returned slice.
    Ok(unsafe { core::slice::from_raw_parts_mut(flat.as_mut_ptr().cast::<Quat<T>>(), flat.len()) })
}

/// A scratch slice of `4 k` scalars (whole quaternions only: a tail of fewer than 4 is left
/// out) as `k` quaternions, as [`quats_mut`] does for a caller's buffer.
pub(crate) fn quats_of_mut<T: Real>(flat: &mut [T]) -> &mut [Quat<T>] {
    let flat: &mut [[T; 4]] = flat.as_chunks_mut::<4>().0;
    // SAFETY: as in `quats`; the exclusive borrow of `flat` moves into the returned slice.
    unsafe { core::slice::from_raw_parts_mut(flat.as_mut_ptr().cast::<Quat<T>>(), flat.len()) }
}

const _: () = assert!(
    core::mem::size_of::<Quat<f64>>() == core::mem::size_of::<[f64; 4]>()
        && core::mem::align_of::<Quat<f64>>() == core::mem::align_of::<[f64; 4]>()
        && core::mem::size_of::<Quat<f32>>() == core::mem::size_of::<[f32; 4]>()
        && core::mem::align_of::<Quat<f32>>() == core::mem::align_of::<[f32; 4]>()
);
