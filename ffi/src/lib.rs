//! # deform-kernel-ffi
//!
//! The C ABI of deform-kernel, for solvers written in C, C++ and Fortran. The header
//! `include/deform_kernel.h` is generated from this crate by cbindgen and checked in; the
//! Fortran module `fortran/deform_kernel.f90` binds the same functions with `iso_c_binding`.
//!
//! Conventions (every `dk_*` function):
//! - returns a [`dk_status`]; `DK_OK` is 0; [`dk_status_str`] describes any value;
//! - inputs first, outputs last; every buffer is followed by its length in elements;
//! - arrays that belong together travel in one `#[repr(C)]` parameter struct: a CSR graph
//!   ([`graph::dk_graph`]), cells ([`graph::dk_cells`]), a spring system
//!   ([`spring::dk_spring_system`]), a plan's mesh and pools ([`plan::dk_plan_mesh`],
//!   [`plan::dk_plan_pools`]), a boundary motion; their arrays follow the rules of
//!   arguments and are borrowed only for the call;
//! - outputs are written only on success: on any error the caller's buffers are unchanged;
//! - NULL pointers are checked (a NULL buffer is allowed only with length 0);
//! - f64 functions have an `_f32` twin with the same bits as the Rust API;
//! - mesh node indices supplied by the caller are read with an `index_base` of 0 or 1, so
//!   Fortran callers pass their arrays as they are;
//! - all memory belongs to the caller; `*_len` functions say how large buffers must be; the
//!   crate is `no_std` and never allocates (1-based indices are converted into the caller's
//!   `index_scratch`);
//! - the C library (`capi/`, crate `deform-kernel-capi`) is built with `panic = "abort"`, and
//!   every `dk_*` function is proven panic-free at link time (target-tests/panic-check calls
//!   each one, both precisions, with opaque arguments), so no panic can cross the ABI.
//!
//! This crate is an rlib: Rust code (tests, fuzzing) calls the `dk_*` functions by path and
//! unwinds normally. The C symbol names exist only with the `export-symbols` feature, which
//! the thin `deform-kernel-capi` crate turns on when it builds `libdeform_kernel.{a,so}`.
#![cfg_attr(not(test), no_std)]

/// argument reading and writing shared by every entry point
pub(crate) mod args;
mod slice;

pub mod deformation;
pub mod graph;
pub mod plan;
pub mod quality;
pub mod quat;
pub mod spring;
pub mod status;
pub mod stiffening;
pub mod taubin;

pub use status::{dk_status, dk_status_str};
