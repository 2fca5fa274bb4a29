//! The `bondgraph` command-line program.

// Not called by the program yet (no command loads a model so far); its tests use it.
#[allow(dead_code)]
mod diagnostics;

fn main() {}
