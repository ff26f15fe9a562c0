//! Code shared by several test binaries, one module a concern: `c_build` builds the C library
//! and compiles C/Fortran programs against it, `deformation` the structured test meshes and
//! rigid motions of the deformation tests, `spring` the spring systems, reference nets and
//! multigrid buffers of the spring tests, `python` the interpreter of the independent Python
//! references. A binary at the top of `tests/` declares
//! `mod support;`, one in a subdirectory `#[path = "../support/mod.rs"] mod support;`.
#![allow(dead_code)]

pub mod c_build;
pub mod deformation;
pub mod elasticity;
pub mod python;
pub mod spring;
