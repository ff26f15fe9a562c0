//! C ABI: deformation (in progress).
