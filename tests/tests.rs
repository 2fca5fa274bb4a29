//! Whole-program tests: the libraries and the `bondgraph` command on real model files.
//!
//! One test binary with modules (rather than one binary per file) keeps link times down.

mod analyze;
mod architecture;
mod bond_graph_views;
mod cli;
mod diagnostics;
mod docs;
mod every_model;
mod examples;
mod feedback;
mod hardening;
mod large_models;
mod linear_graph_diagnostics;
mod linear_graphs;
mod new_systems;
mod nonlinear;
mod overflow;
mod scenarios;
mod snapshots;
mod stribeck_zero;
mod support;
mod teaching;
mod timescales;
mod units;
