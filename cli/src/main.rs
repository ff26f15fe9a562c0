//! The `deform` command-line tool.

fn main() {}
