//! The checked [`Model`]: built in code ([`Builder`]) or read from a file by `bondgraph-ron`,
//! through one constructor ([`validate`]).
//!
//! A model as written is a [`spec::ModelSpec`] (names, unparsed expressions, bonds) and,
//! when it comes from a file, a [`source_map::SourceMap`] of where each part is. The
//! validator checks names, expressions, values, units and the graph, and builds the
//! [`Model`] every later stage works on, each problem a diagnostic naming its element (and,
//! for a file, its line). A linear graph becomes a bond graph before it is validated; its
//! drawing and words stay with the model ([`linear_graph`]).
mod builder;
mod checked;
pub mod linear_graph;
pub mod source_map;
pub mod spec;
pub mod validate;

pub use builder::Builder;
pub use checked::{
    Bond, BondId, Coefficient, Element, ElementId, ElementKind, ElementMode, FlowLimit, Friction,
    Input, InputId, Model, NonlinearElement, NonlinearLaw, Parameter, ResistorLaw, SourceValue,
    TensionOnly,
};
pub use spec::{BondSpec, ElementSpec, InputSpec, ModelSpec, ParameterSpec};
