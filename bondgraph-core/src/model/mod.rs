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
    AtElement, Bond, BondId, Coefficient, Element, ElementId, ElementKind, ElementMode, FlowLimit,
    Friction, Input, InputId, Model, NonlinearElement, NonlinearLaw, Parameter, Port, ResistorLaw,
    SourceValue, TensionOnly,
};
pub use spec::{
    BondSpec, ElementSpec, InputSpec, ModelSpec, ParameterSpec, ParameterValue, PartSpec, PortSpec,
};

/// The name of an element's energy variable: `letter` (`p` for a momentum, `q` for a
/// displacement; a linear graph's `v` and `f`) and the element's name, `p_mass`. An element
/// of a sub-model keeps the sub-model's prefix in front (`front.q_spring` for
/// `front.spring`), so that the state reads as the part's own, qualified.
///
/// ```
/// use bondgraph_core::model::{state_symbol, state_element};
/// assert_eq!(state_symbol("p", "mass"), "p_mass");
/// assert_eq!(state_symbol("q", "front.rear.spring"), "front.rear.q_spring");
/// assert_eq!(state_element("front.rear.q_spring"), Some(("q", "front.rear.spring".into())));
/// ```
pub fn state_symbol(letter: &str, element: &str) -> String {
    match element.rsplit_once('.') {
        Some((prefix, leaf)) => format!("{prefix}.{letter}_{leaf}"),
        None => format!("{letter}_{element}"),
    }
}

/// The letter and element of an energy variable's name written by [`state_symbol`], if
/// `symbol` has that form (whether such an element exists is the caller's to check).
pub fn state_element(symbol: &str) -> Option<(&str, String)> {
    let (prefix, leaf) = match symbol.rsplit_once('.') {
        Some((prefix, leaf)) => (Some(prefix), leaf),
        None => (None, symbol),
    };
    let (letter, element) = leaf.split_once('_')?;
    let element = match prefix {
        Some(prefix) => format!("{prefix}.{element}"),
        None => element.to_string(),
    };
    Some((letter, element))
}
