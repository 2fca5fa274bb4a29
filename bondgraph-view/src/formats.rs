//! The output formats of the views, as plain enums that the command line (`clap`) and the
//! Python bindings both map onto, so that a view does not depend on another for its format.

/// How `bondgraph graph` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GraphFormat {
    /// The elements, bonds and causality (a linear graph: nodes, branches, normal tree).
    Text,
    /// Graphviz DOT (render with `dot -Tsvg`).
    Dot,
    /// SVG, drawn by the program.
    Svg,
}

/// How `bondgraph explain` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExplainFormat {
    /// Plain text.
    Text,
    /// Markdown (headings, numbered lists), for lecture notes.
    Markdown,
}
