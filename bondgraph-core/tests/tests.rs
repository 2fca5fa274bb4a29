//! Integration tests of `bondgraph-core`, through its public interface only.
//!
//! One test binary with modules (rather than one binary per file) keeps link times down.

mod builder;
mod causality_conflicts;
mod causality_trace;
mod conventions;
mod feedback;
mod jacobian;
mod limits;
mod merging;
mod nonlinear;
mod random_graph;
mod regressions;
mod units;
