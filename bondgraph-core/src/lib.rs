//! Bond-graph models, from a checked model to symbolic state equations.
//!
//! `bondgraph-core` checks a lumped-parameter model given as a bond graph (sources,
//! inertias, compliances, resistors, transformers, gyrators and junctions), built in code
//! ([`model::Builder`]) or read from a RON file by `bondgraph-ron` (which also reads linear
//! graphs, [`model::linear_graph`], with their [`normal_tree`]), assigns causality, and
//! derives its state equations `dx/dt = A x + B u + c` with entries that read like a
//! textbook: `-(b + K_p)/M`.
//!
//! Each stage is a value that can be printed and tested on its own:
//! [`model`] (the checked model), [`causality`] (causal strokes, derivative causality,
//! arbitrary choices), [`equations`] (symbolic, sparse state equations, printable as text,
//! LaTeX and JSON), [`modes`] (the modes of switching elements), and [`scenario`] (how a
//! model is driven in a simulation: input signals, initial conditions, what to record, and
//! the model's variant).
//!
//! # Example
//!
//! A mass on a spring and a damper, pushed by a force: built in code (a [`model::Builder`]
//! runs the checks a model file goes through; `bondgraph_ron::model::load_str` reads the
//! same model from RON text), then derived.
//!
//! ```
//! use bondgraph_core::model::{Builder, ElementSpec};
//! use bondgraph_core::{equations, laws};
//!
//! let model = Builder::new("mass_spring_damper")
//!     .parameter("m", 2.0, "kg")
//!     .parameter("k", 200.0, "N/m")
//!     .parameter("b", 4.0, "N*s/m")
//!     .input("F", "N")
//!     .element("force", ElementSpec::effort_source("F"))
//!     .element("v", ElementSpec::One)
//!     .element("mass", ElementSpec::inertance("m"))
//!     .element("spring", ElementSpec::stiffness("k"))
//!     .element("damper", ElementSpec::resistance("b"))
//!     .bonds([("force", "v"), ("v", "mass"), ("v", "spring"), ("v", "damper")])
//!     .build()
//!     .unwrap();
//!
//! let options = equations::Options { variables: equations::Variables::CoEnergy };
//! let eq = equations::derive(&model, &laws::plain_laws(&model), &options).unwrap();
//! let a: Vec<Vec<String>> = eq.a().iter()
//!     .map(|row| row.iter().map(|e| e.text(&eq.symbols)).collect())
//!     .collect();
//! assert_eq!(a, [["-b/m", "-1/m"], ["k", "0"]]);
//! assert_eq!(eq.form_text(&eq.derivatives[0]), "-b/m*v_mass - f_spring/m + F/m");
//! ```
//!
//! # Crate features
//! None: the crate has no optional parts.

pub mod analysis;
pub mod causality;
pub mod conventions;
pub mod diagnostics;
pub mod diagram;
pub mod equations;
pub mod expr;
pub mod graph;
pub mod guards;
pub mod laws;
pub mod limits;
pub mod linear;
pub mod mode;
pub mod model;
pub mod modes;
pub mod normal_tree;
pub mod number;
pub mod scenario;
pub mod source;
#[cfg(test)]
mod testing;
/// The exact algebra, a crate of its own ([`bondgraph_symbolic`]), under its old path.
pub use bondgraph_symbolic as symbolic;
pub mod units;

pub use diagnostics::{Diagnostic, DiagnosticKind, Diagnostics};
