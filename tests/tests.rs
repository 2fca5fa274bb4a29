//! Integration tests of the `bondgraph` program.
//!
//! `Cargo.toml` declares this single test target (one binary links faster than many); the
//! program's behaviour tests go here as the command-line interface grows.
