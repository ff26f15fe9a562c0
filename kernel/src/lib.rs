//! # deform-kernel
//!
//! A `#![no_std]`, allocation-free, panic-free mesh-deformation kernel for CFD and structural
//! solvers. Everything works on caller-provided slices: no heap, no global state, no threads,
//! and the same bits on every platform (libm for every transcendental function, no fused
//! multiply-add, fixed reduction order).
//!
//! Building blocks (this crate's foundation):
//! - [`Real`]: the sealed scalar trait for `f32` and `f64`.
//! - [`Quat`]: unit quaternions for rotations (scalar first, as in Samareh's paper).
//! - [`vector`]: dot/cross/norm helpers for `[T; 2]` and `[T; 3]` points.
//! - [`Graph`]: a validated CSR adjacency view, and [`graph_builder`] to derive one from an
//!   edge list or from mixed [`Cells`].
//! - [`Error`]: one error enum; every routine validates before it writes.
//!
//! ```
//! use deform_kernel::{graph_from_edges, graph_from_edges_len, Graph};
//! let edges = [[0, 1], [1, 2], [2, 0], [1, 0]];
//! let mut offsets = [0u32; 4];
//! let mut targets = [0u32; 8];
//! assert_eq!(graph_from_edges_len(&edges), 8);
//! let used = graph_from_edges(3, &edges, &mut offsets, &mut targets)?;
//! let g = Graph::new(&offsets, &targets[..used])?;
//! assert_eq!(g.neighbors(1), &[0, 2]);
//! # Ok::<(), deform_kernel::Error>(())
//! ```
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![warn(clippy::missing_errors_doc)]

pub mod block;
pub mod cells;
mod check;
pub mod design;
pub mod elasticity;
pub mod error;
pub mod exact_sum;
pub mod graph;
pub mod graph_builder;
pub mod order;
pub mod partition;
pub mod plan;
pub mod quality;
pub mod quat;
pub mod quaternion;
pub mod rbf;
pub mod real;
pub mod sensitivity;
pub mod spring;
pub mod taubin;
pub mod vector;

pub use block::{Block, Direction, Directions};
pub use cells::{CellKind, Cells};
pub use error::{Error, Result};
pub use graph::Graph;
pub use graph_builder::{
    graph_from_cells, graph_from_cells_len, graph_from_edges, graph_from_edges_len,
};
pub use quat::{Quat, QuatAverage};
pub use real::Real;

/// The README's example, compiled and run as a doctest so it stays true.
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeDoctests;
