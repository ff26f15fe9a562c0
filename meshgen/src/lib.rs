//! Deterministic mesh generators (std) shared by the tests, the benchmarks and the `deform demo`.
