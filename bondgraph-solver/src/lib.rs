//! Simulation of the state equations that `bondgraph-core` derives.
