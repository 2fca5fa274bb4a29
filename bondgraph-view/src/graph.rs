//! `bondgraph graph`: a model's graph in one mode, as text, Graphviz DOT or SVG. A bond
//! graph shows its causal strokes, a linear graph its normal tree ([`crate::lg_graph`]).
//!
//! Here rather than in the binary so that the Python bindings draw exactly what the
//! command line prints.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_core::source::SourceFile;
use bondgraph_core::{causality, equations, graph, laws};

use crate::{Failure, bg_svg, lg_graph, with_source};

pub use crate::formats::GraphFormat;

/// The graph of `model` (read from `source`) in `mode`, in `format`.
///
/// # Errors
/// A failure when the mode's causality conflicts, or when its equations cannot be derived
/// (a drawing of a mode `check` rejects would mislead).
pub fn render(
    model: &Model,
    mode: &Mode,
    source: &Arc<SourceFile>,
    format: GraphFormat,
) -> Result<String, Failure> {
    if let Some(graph) = &model.linear_graph() {
        return lg_graph::render(model, graph, mode, format, source);
    }
    let laws = laws::for_mode(model, mode);
    let causality = causality::assign(model, &laws).map_err(|d| with_source(d, source))?;
    // A graph of a mode whose equations cannot be derived (a zero resistance in
    // conductance causality) would be a drawing of a model `check` rejects.
    if !model.is_nonlinear() {
        equations::derive(model, &laws, &equations::Options::default())
            .map_err(|d| with_source(d, source))?;
    }
    Ok(match format {
        GraphFormat::Text => format!(
            "{}\n{}",
            graph::describe(model),
            graph::describe_causality(model, &laws, &causality)
        ),
        GraphFormat::Dot => graph::to_dot_titled(
            model,
            Some(&causality),
            Some(&bg_svg::title(model, &mode.spec(model))),
        ),
        GraphFormat::Svg => bg_svg::draw(model, mode, &causality),
    })
}

/// The bond graph of `model` in Graphviz DOT with each sub-model drawn as one box, the bonds
/// to it labelled with the ports they join ([`graph::to_dot_collapsed`]).
///
/// # Errors
/// A failure for a linear graph (its sub-graphs are drawn expanded), for a model with no
/// sub-models to collapse, or when the mode's causality conflicts.
pub fn render_collapsed(
    model: &Model,
    mode: &Mode,
    source: &Arc<SourceFile>,
) -> Result<String, Failure> {
    if model.linear_graph().is_some() {
        return Err(Failure::message(
            bondgraph_core::diagnostics::DiagnosticKind::Submodel,
            "a linear graph is drawn with its sub-graphs expanded; leave out --collapse",
        ));
    }
    if model.parts().is_empty() {
        return Err(Failure::message(
            bondgraph_core::diagnostics::DiagnosticKind::Submodel,
            format!(
                "model '{}' has no sub-models to collapse; leave out --collapse",
                model.name()
            ),
        ));
    }
    let laws = laws::for_mode(model, mode);
    let causality = causality::assign(model, &laws).map_err(|d| with_source(d, source))?;
    Ok(graph::to_dot_collapsed(
        model,
        Some(&causality),
        Some(&bg_svg::title(model, &mode.spec(model))),
    ))
}
