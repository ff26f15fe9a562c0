//! Reference implementation: quality.
