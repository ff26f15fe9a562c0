//! # deform-cli
//!
//! The library half of the `deform` tool: mesh and grid file formats ([`formats`]: SU2 native
//! ASCII, Plot3D whole grids, VTK XML output), safe output files ([`output`]), and the command
//! implementations ([`commands`]) that the `deform` binary dispatches to. Readers take bytes and
//! never panic, so fuzzers and tests call them directly:
//!
//! ```
//! let mesh = deform_cli::formats::su2::parse_su2(b"NDIME= 2\nNELEM= 0\nNPOIN= 0\n").unwrap();
//! assert_eq!(mesh.dim, 2);
//! let err = deform_cli::formats::su2::parse_su2(b"NDIME= 4\n").unwrap_err();
//! assert_eq!(err.to_string(), "line 1: expected NDIME= 2 or NDIME= 3, found \"NDIME= 4\"");
//! ```
#![forbid(unsafe_code)]

pub mod args;
pub mod commands;
pub mod engine;
pub mod error;
pub mod files;
pub mod formats;
pub mod guard;
pub mod motion;
pub mod orientation;
pub mod output;
pub mod plot;
pub mod progress;
pub mod renumber;
pub mod report;
pub mod split;
pub mod validity;

pub use formats::plot3d::parse_plot3d;
pub use formats::su2::parse_su2;
pub use formats::{FormatError, FormatErrorKind, Location};
