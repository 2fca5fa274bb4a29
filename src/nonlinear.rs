//! The commands on nonlinear models: `equations` (with `--at` and `--equilibrium`),
//! `modes` and `check`, whose modes are `dx/dt = f(x, u)`.

use std::sync::Arc;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::nonlinear::{NonlinearOutput, OperatingPoint};
use bondgraph_core::equations::{self, Options};
use bondgraph_core::model::Model;
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::scenario::Record;
use bondgraph_core::source::SourceFile;

use crate::{Failure, Format, count, json, print, with_source};

/// What `bondgraph equations` was asked for a nonlinear model.
pub(crate) struct EquationsArgs<'a> {
    pub model: &'a Model,
    pub source: &'a Arc<SourceFile>,
    pub mode: &'a Mode,
    pub options: Options,
    pub format: Format,
    pub outputs: &'a [String],
    pub at: Option<&'a str>,
    pub equilibrium: bool,
}

/// `bondgraph equations` on a nonlinear model.
pub(crate) fn equations(args: &EquationsArgs<'_>) -> Result<(), Failure> {
    let (model, source) = (args.model, args.source);
    let derived = modes::derive_nonlinear(model, args.mode, &args.options)
        .map_err(|d| with_source(d, source))?;
    let eq = &derived.equations;
    let outputs = args
        .outputs
        .iter()
        .map(|spec| {
            Record::parse_output(model, spec).map(|(record, spec)| NonlinearOutput {
                integral: matches!(record, Record::Integral(_)),
                name: record.name(),
                ..eq.output(&spec)
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|d| with_source(d, source))?;
    let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
    let mut point = match args.at {
        Some(text) => Some(
            OperatingPoint::parse(&names, &eq.inputs, text).map_err(|d| with_source(d, source))?,
        ),
        None => None,
    };
    let mut found = None;
    if args.equilibrium {
        let start = point
            .clone()
            .unwrap_or_else(|| OperatingPoint::zero(names.len(), eq.inputs.len()));
        let equilibrium = bondgraph_solver::equilibrium::find(eq, &start)
            .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
        point = Some(equilibrium.point.clone());
        found = Some(equilibrium);
    }
    let text = match args.format {
        Format::Text => {
            let mut text = String::new();
            if !args.mode.is_empty() {
                text.push_str(&format!("mode {}\n", args.mode.spec(model)));
            }
            text.push_str(&eq.to_text(point.as_ref()));
            if let Some(found) = &found {
                text.push_str(&format!(
                    "\nequilibrium: f = 0 to {:e} after {} Newton iterations\n",
                    found.residual, found.iterations
                ));
            }
            if !outputs.is_empty() {
                text.push_str("\noutputs:\n");
                for output in &outputs {
                    text.push_str(&format!("  {}\n", eq.output_text(output)));
                }
            }
            if !derived.guards.is_empty() {
                text.push_str("\nguards:\n");
                for guard in &derived.guards {
                    let element = &model.element(guard.element).name;
                    text.push_str(&format!(
                        "  {element}: {} -> {element}={}\n",
                        guard.condition_text(eq),
                        guard.leaves_to.name()
                    ));
                }
            }
            text.push_str(&crate::conventions::text(model));
            text
        }
        Format::Latex => format!(
            "{}{}",
            crate::conventions::latex_preamble(model),
            eq.to_latex_with_outputs(&outputs)
        ),
        Format::Json => json(&eq.to_json(&args.mode.spec(model), &outputs, point.as_ref()))?,
    };
    print(&text);
    Ok(())
}

/// `bondgraph modes` on a nonlinear model.
pub(crate) fn modes(
    model: &Model,
    source: &Arc<SourceFile>,
    options: &Options,
    as_json: bool,
) -> Result<(), Failure> {
    let reachable =
        modes::reachable_nonlinear(model, options).map_err(|d| with_source(d, source))?;
    let text = if as_json {
        json(&reachable.to_json(model))?
    } else {
        reachable.to_text(model)
    };
    print(&text);
    Ok(())
}

/// `bondgraph check` on a nonlinear model.
pub(crate) fn check(model: &Model, source: &Arc<SourceFile>) -> Result<(), Failure> {
    let reachable = modes::reachable_nonlinear(model, &equations::Options::default())
        .map_err(|d| with_source(d, source))?;
    let states = reachable
        .modes
        .first()
        .map_or(0, |m| m.equations.state_count());
    let mode_count = if reachable.initial.is_empty() {
        String::new()
    } else {
        format!(", {}", count(reachable.modes.len(), "reachable mode"))
    };
    print(&format!(
        "{}: ok: nonlinear model '{}' with {}, {}, {}, {} and {}{mode_count}\n",
        source.name(),
        model.name,
        count(model.elements.len(), "element"),
        count(model.bonds.len(), "bond"),
        count(model.parameters.len(), "parameter"),
        count(model.inputs.len(), "input"),
        count(states, "state"),
    ));
    Ok(())
}
