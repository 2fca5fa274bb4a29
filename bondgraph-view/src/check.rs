//! `bondgraph check` and `bondgraph modes`: what a model is, and the modes it reaches.
//!
//! Here rather than in the binary so that the Python bindings give the command line's
//! summary and documents, from the same code.

use std::sync::Arc;

use bondgraph_core::equations::{self, Variables};
use bondgraph_core::model::Model;
use bondgraph_core::modes;
use bondgraph_core::source::SourceFile;

use crate::{Failure, count, json, with_source};

/// The one-line summary `bondgraph check` prints (without its newline): the kind of model,
/// its size, its states and how many modes it reaches.
///
/// # Errors
/// A failure when some reachable mode has no equations.
pub fn summary(model: &Model, source: &Arc<SourceFile>) -> Result<String, Failure> {
    if !model.ports().is_empty() {
        return Ok(part_summary(model, source));
    }
    let options = equations::Options::default();
    let located = |d| with_source(d, source);
    let (states, reached, switching) = if model.is_nonlinear() {
        let reachable = modes::reachable_nonlinear(model, &options).map_err(located)?;
        let states = reachable.modes.first().map(|m| m.equations.state_count());
        (states, reachable.modes.len(), !reachable.initial.is_empty())
    } else {
        let reachable = modes::reachable(model, &options).map_err(located)?;
        let states = reachable.modes.first().map(|m| m.equations.state_count());
        (states, reachable.modes.len(), !reachable.initial.is_empty())
    };
    let (kind, parts) = match (&model.linear_graph(), model.is_nonlinear()) {
        (Some(graph), nonlinear) => (
            if nonlinear {
                "nonlinear linear graph"
            } else {
                "linear graph"
            },
            [
                (graph.nodes.len(), "node"),
                (graph.branches.len(), "branch"),
            ],
        ),
        (_, nonlinear) => (
            if nonlinear {
                "nonlinear model"
            } else {
                "model"
            },
            [
                (model.elements().len(), "element"),
                (model.bonds().len(), "bond"),
            ],
        ),
    };
    let modes = if switching {
        format!(", {}", count(reached, "reachable mode"))
    } else {
        String::new()
    };
    let composed = match model.parts().len() {
        0 => String::new(),
        1 if model.linear_graph().is_some() => ", composed from 1 sub-graph".to_string(),
        n if model.linear_graph().is_some() => format!(", composed from {n} sub-graphs"),
        n => format!(", composed from {}", count(n, "sub-model")),
    };
    Ok(format!(
        "{}: ok: {kind} '{}' with {}, {}, {}, {} and {}{modes}{composed}",
        source.name(),
        model.name(),
        count(parts[0].0, parts[0].1),
        count(parts[1].0, parts[1].1),
        count(model.parameters().len(), "parameter"),
        count(model.inputs().len(), "input"),
        count(states.unwrap_or(0), "state"),
    ))
}

/// The summary of a part (a model with ports): its size and its ports, each with its domain
/// where units tell it. It has no states of its own until a model bonds its ports.
fn part_summary(model: &Model, source: &Arc<SourceFile>) -> String {
    let ports: Vec<String> = model
        .ports()
        .iter()
        .map(|port| match model.element_domain(port.element) {
            Some(domain) => format!("'{}' ({})", port.name, domain.name),
            None => format!("'{}'", port.name),
        })
        .collect();
    let (size, port) = match model.linear_graph() {
        Some(graph) => (
            [
                count(graph.nodes.len(), "node"),
                count(graph.branches.len(), "branch"),
            ],
            "terminal",
        ),
        None => (
            [
                count(model.elements().len(), "element"),
                count(model.bonds().len(), "bond"),
            ],
            "port",
        ),
    };
    format!(
        "{}: ok: part '{}' with {}, {}, {}, {} and {}: {}",
        source.name(),
        model.name(),
        size[0],
        size[1],
        count(model.parameters().len(), "parameter"),
        count(model.inputs().len(), "input"),
        count(ports.len(), port),
        ports.join(", ")
    )
}

/// `bondgraph modes`: every mode reachable from the initial one, its states and guards
/// (in `variables`, the model's own if `None`), as text or as the JSON document.
///
/// # Errors
/// A failure when some reachable mode has no equations.
pub fn modes(
    model: &Model,
    source: &Arc<SourceFile>,
    variables: Option<Variables>,
    as_json: bool,
) -> Result<String, Failure> {
    let options = equations::Options {
        variables: variables.unwrap_or_else(|| Variables::preferred(model)),
    };
    let located = |d| with_source(d, source);
    if model.is_nonlinear() {
        let reachable = modes::reachable_nonlinear(model, &options).map_err(located)?;
        return if as_json {
            json(&reachable.to_json(model))
        } else {
            Ok(reachable.to_text(model))
        };
    }
    let reachable = modes::reachable(model, &options).map_err(located)?;
    if as_json {
        json(&reachable.to_json(model))
    } else {
        Ok(reachable.to_text(model))
    }
}
