//! Reference implementation: deformation.
