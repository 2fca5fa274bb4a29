//! Bond-graph models, from RON model files to symbolic state equations.

pub mod diagnostics;
pub mod expr;
pub mod source;
pub mod symbolic;
