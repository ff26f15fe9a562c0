//! # deform-kernel-ffi
//!
//! The C ABI of deform-kernel, for solvers written in C, C++ and Fortran. Each C function is
//! written once, in `src/<module>.rs`, as a safe function marked `#[export]`; `cargo xtask
//! codegen` writes `generated/` from them: the `extern "C"` functions (each module here is
//! `generated/<module>.rs`, whose child `imp` is `src/<module>.rs`), the header
//! `generated/deform_kernel.h` (cbindgen) and the Fortran module `generated/deform_kernel.f90`
//! (`iso_c_binding`). See ffi/README.md, "Adding a C function".
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

#[path = "../generated/deformation.rs"]
pub mod deformation;
#[path = "../generated/deformation_fast.rs"]
pub mod deformation_fast;
#[path = "../generated/deformation_sensitivity.rs"]
pub mod deformation_sensitivity;
#[path = "../generated/design.rs"]
pub mod design;
#[path = "../generated/design_sensitivity.rs"]
pub mod design_sensitivity;
#[path = "../generated/elasticity.rs"]
pub mod elasticity;
#[path = "../generated/graph.rs"]
pub mod graph;
#[path = "../generated/order.rs"]
pub mod order;
#[path = "../generated/partition.rs"]
pub mod partition;
#[path = "../generated/partition_idw.rs"]
pub mod partition_idw;
#[path = "../generated/partition_prolongator.rs"]
pub mod partition_prolongator;
#[path = "../generated/partition_quaternion.rs"]
pub mod partition_quaternion;
#[path = "../generated/plan.rs"]
pub mod plan;
#[path = "../generated/pools.rs"]
pub mod pools;
#[path = "../generated/quality.rs"]
pub mod quality;
#[path = "../generated/quat.rs"]
pub mod quat;
#[path = "../generated/rbf.rs"]
pub mod rbf;
#[path = "../generated/sensitivity.rs"]
pub mod sensitivity;
#[path = "../generated/sensitivity_angle.rs"]
pub mod sensitivity_angle;
#[path = "../generated/sensitivity_rbf.rs"]
pub mod sensitivity_rbf;
#[path = "../generated/spring.rs"]
pub mod spring;
#[path = "../generated/status.rs"]
pub mod status;
#[path = "../generated/stiffening.rs"]
pub mod stiffening;
#[path = "../generated/taubin.rs"]
pub mod taubin;
// Last, so the header keeps its earlier declarations where they were (cbindgen emits structs
// in the order of first use).
#[path = "../generated/elasticity_layer.rs"]
pub mod elasticity_layer;
#[path = "../generated/elasticity_sensitivity.rs"]
pub mod elasticity_sensitivity;
#[path = "../generated/elasticity_solvers.rs"]
pub mod elasticity_solvers;
#[path = "../generated/sliding_sensitivity.rs"]
pub mod sliding_sensitivity;

pub use status::{dk_status, dk_status_str};
