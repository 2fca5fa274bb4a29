//! The `bondgraph` command-line program.

fn main() {}
