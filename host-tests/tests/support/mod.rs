//! Code shared by several test binaries, one module a concern: `c_build` builds the C library
//! and compiles C/Fortran programs against it, `quaternion` the structured test meshes and
//! rigid motions of the quaternion tests, `spring` the spring systems, reference nets and
//! multigrid buffers of the spring tests, `rbf` the point clouds of the RBF tests, `order` the
//! meshes of the ordering tests, `plan` owned plan pools, `threads` the
//! in-process exchange of the partitioned tests, `partition_boundary` their boundaries and
//! boundary shares, `python` the interpreter of the independent Python
//! references. A binary at the top of `tests/` declares
//! `mod support;`, one in a subdirectory `#[path = "../support/mod.rs"] mod support;`.
#![allow(dead_code)]

pub mod c_build;
pub mod elasticity;
pub mod order;
pub mod partition_boundary;
pub mod plan;
pub mod python;
pub mod quaternion;
pub mod rbf;
pub mod spring;
pub mod threads;
