//! Reference implementation: taubin.
