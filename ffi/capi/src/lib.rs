//! # deform-kernel-capi
//!
//! `libdeform_kernel.a` and `libdeform_kernel.so`: the C ABI of `deform-kernel-ffi` with its
//! `export-symbols` feature on, built with `panic = "abort"`. No code of its own; see
//! `ffi/README.md` for building, installing and linking.

pub use deform_kernel_ffi::*;
