//! std test harness for deform-kernel: independent reference implementations (written
//! naively, with `Vec` and `BTreeSet`, sharing no code with the kernel) used by the parity
//! tests in `tests/`.

pub mod deformation_ref;
pub mod graph_ref;
pub mod idw_ref;
pub mod quality_ref;
pub mod spring_ref;
pub mod taubin_ref;
