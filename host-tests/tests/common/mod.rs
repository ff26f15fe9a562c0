//! Code shared by several integration tests.
#![allow(dead_code)]

pub mod c_build;
