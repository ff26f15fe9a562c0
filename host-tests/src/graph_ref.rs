//! Reference implementation: graph.
