//! Reference implementation: spring.
