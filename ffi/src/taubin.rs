//! C ABI: taubin (in progress).
