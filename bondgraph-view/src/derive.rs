//! `bondgraph equations`: the state equations of one mode (linear, or nonlinear at an
//! operating point or an equilibrium), its output equations and guards, as text, LaTeX or
//! JSON.
//!
//! Built here rather than in the binary so that the Python bindings show the very text,
//! LaTeX and JSON the command line prints, from the same code.

use std::sync::Arc;

use serde::Serialize;

use bondgraph_core::DiagnosticKind;
use bondgraph_core::equations::nonlinear::{NonlinearOutput, OperatingPoint};
use bondgraph_core::equations::{self, Layout, OutputEquation, Variables};
use bondgraph_core::guards::Guard;
use bondgraph_core::model::Model;
use bondgraph_core::modes::{self, ModeEquations, NonlinearModeEquations};
use bondgraph_core::scenario::Record;
use bondgraph_core::source::SourceFile;
use bondgraph_solver::equilibrium::{self, Equilibrium};

use crate::{Failure, conventions, json, parse_mode, with_source};

/// What `bondgraph equations` is asked.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// The mode (`fr=stuck,string=taut`); the initial mode if `None`.
    pub mode: Option<String>,
    /// Energy or co-energy states; the model's own ([`Variables::preferred`]) if `None`.
    pub variables: Option<Variables>,
    /// Output equations to add: `effort:ELEMENT`, `integral:flow:mass`, ...
    pub outputs: Vec<String>,
    /// An operating point `NAME=VALUE,...`: a nonlinear mode's Jacobians are evaluated
    /// there (a linear mode's matrices do not depend on it; it is checked all the same).
    pub at: Option<String>,
    /// Search a nonlinear mode's equilibrium (from `at`, or from zero) and linearise there.
    pub equilibrium: bool,
    /// How the JSON writes a linear mode's `A`, `B` and `E`; dense up to
    /// [`Layout::DENSE_UP_TO`] states and sparse above if `None`.
    pub matrices: Option<Layout>,
}

/// The equations of one mode, ready to be written in any of the three formats.
pub struct Derived {
    /// `mode SPEC`, when the model has switching elements.
    mode_line: Option<String>,
    /// The `guards:` lines, already worded with the elements' names.
    guards: Vec<String>,
    /// The `conventions:` block (possibly empty).
    conventions: String,
    /// The LaTeX comment saying what the matrices need.
    preamble: String,
    spec: String,
    /// How the JSON writes the matrices (`None`: by the number of states).
    matrices: Option<Layout>,
    kind: Kind,
    /// A nonlinear mode's operating point (given, or the equilibrium found).
    point: Option<OperatingPoint>,
    /// The equilibrium found, when one was searched.
    found: Option<Equilibrium>,
    /// The model's parameters, in SI units and as written.
    parameters: Vec<ParameterJson>,
    /// `k = 200 N/m (0.2 N/mm)` for each parameter whose unit is not SI.
    converted: Vec<String>,
}

/// A parameter in the JSON document: its SI value and unit, and as written where its unit
/// is not SI.
#[derive(Serialize)]
struct ParameterJson {
    name: String,
    value: f64,
    unit: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    as_written: Option<AsWritten>,
}

/// A value as the model file writes it.
#[derive(Serialize)]
struct AsWritten {
    value: f64,
    unit: String,
}

/// The equations' JSON document with the parameters added.
#[derive(Serialize)]
struct WithParameters<'a, T: Serialize> {
    #[serde(flatten)]
    equations: T,
    parameters: &'a [ParameterJson],
}

enum Kind {
    Linear {
        // Boxed: the two kinds of equations differ much in size.
        derived: Box<ModeEquations>,
        outputs: Vec<OutputEquation>,
    },
    Nonlinear {
        derived: Box<NonlinearModeEquations>,
        outputs: Vec<NonlinearOutput>,
    },
}

/// Derives the mode `request` names of `model` (read from `source`, which diagnostics
/// point into).
///
/// # Errors
/// A failure for an unknown mode, output or point, a mode without equations, an equilibrium
/// asked of a linear model, or an equilibrium search that does not converge.
pub fn derive(
    model: &Model,
    source: &Arc<SourceFile>,
    request: &Request,
) -> Result<Derived, Failure> {
    let mode = parse_mode(model, request.mode.as_deref(), source)?;
    let options = equations::Options {
        variables: request
            .variables
            .unwrap_or_else(|| Variables::preferred(model)),
    };
    let located = |d| with_source(d, source);
    let (mut point, mut found) = (None, None);
    let kind = if model.is_nonlinear() {
        let derived = modes::derive_nonlinear(model, &mode, &options).map_err(located)?;
        let eq = &derived.equations;
        let outputs = parse_outputs(model, &request.outputs, |record, spec| NonlinearOutput {
            integral: matches!(record, Record::Integral(_)),
            name: record.name(),
            ..eq.output(spec)
        })
        .map_err(located)?;
        let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
        point = request
            .at
            .as_deref()
            .map(|text| OperatingPoint::parse(&names, &eq.inputs, text))
            .transpose()
            .map_err(located)?;
        if request.equilibrium {
            let start = point
                .clone()
                .unwrap_or_else(|| OperatingPoint::zero(names.len(), eq.inputs.len()));
            let equilibrium = equilibrium::find(eq, &start)
                .map_err(|e| Failure::message(DiagnosticKind::Simulation, e.to_string()))?;
            point = Some(equilibrium.point.clone());
            found = Some(equilibrium);
        }
        Kind::Nonlinear {
            derived: Box::new(derived),
            outputs,
        }
    } else {
        if request.equilibrium {
            return Err(Failure::message(
                DiagnosticKind::NotLinear,
                "--equilibrium is for nonlinear models; a linear mode's equilibria solve A x + B u + c = 0",
            ));
        }
        let derived = modes::derive(model, &mode, &options).map_err(located)?;
        let eq = &derived.equations;
        if let Some(at) = &request.at {
            // A linear mode's matrices do not depend on the point; the point is checked.
            let names: Vec<String> = eq.states.iter().map(|s| s.name.clone()).collect();
            OperatingPoint::parse(&names, &eq.inputs, at).map_err(located)?;
        }
        let outputs = parse_outputs(model, &request.outputs, |record, spec| {
            let mut output = eq.output(spec);
            output.integral = matches!(record, Record::Integral(_));
            output.name = record.name();
            output
        })
        .map_err(located)?;
        Kind::Linear {
            derived: Box::new(derived),
            outputs,
        }
    };
    let guards = match &kind {
        Kind::Linear { derived, .. } => guard_lines(model, &derived.guards, |g| {
            g.condition_text(&derived.equations)
        }),
        Kind::Nonlinear { derived, .. } => guard_lines(model, &derived.guards, |g| {
            g.condition_text(&derived.equations)
        }),
    };
    Ok(Derived {
        mode_line: (!mode.is_empty()).then(|| format!("mode {}\n", mode.spec(model))),
        guards,
        conventions: conventions::text(model),
        preamble: conventions::latex_preamble(model),
        spec: mode.spec(model),
        matrices: request.matrices,
        kind,
        point,
        found,
        parameters: model
            .parameters()
            .iter()
            .map(|p| ParameterJson {
                name: p.name.clone(),
                value: p.value,
                unit: p.si_unit.clone(),
                as_written: p
                    .as_written
                    .zip(p.unit.clone())
                    .map(|(value, unit)| AsWritten { value, unit }),
            })
            .collect(),
        converted: model
            .parameters()
            .iter()
            .filter(|p| p.as_written.is_some())
            .map(|p| p.in_si_text())
            .collect(),
    })
}

/// The outputs `specs` names, each made by `make` from its record and specification.
fn parse_outputs<T>(
    model: &Model,
    specs: &[String],
    make: impl Fn(&Record, &equations::OutputSpec) -> T,
) -> Result<Vec<T>, bondgraph_core::diagnostics::Diagnostics> {
    specs
        .iter()
        .map(|spec| Record::parse_output(model, spec).map(|(record, spec)| make(&record, &spec)))
        .collect()
}

/// `ELEMENT: CONDITION -> ELEMENT=MODE` for each guard that applies at the model's values.
fn guard_lines<E>(
    model: &Model,
    guards: &[Guard<E>],
    condition: impl Fn(&Guard<E>) -> String,
) -> Vec<String> {
    guards
        .iter()
        .filter(|guard| guard.applies(model, model.values()))
        .map(|guard| {
            let element = &model.element(guard.element).name;
            format!(
                "{element}: {} -> {element}={}",
                condition(guard),
                guard.leaves_to.name()
            )
        })
        .collect()
}

impl Derived {
    /// The text `bondgraph equations` prints: the mode, the equations (at the point, for
    /// a nonlinear mode), the equilibrium found, the outputs, the guards and the
    /// conventions.
    pub fn text(&self) -> String {
        let mut text = self.mode_line.clone().unwrap_or_default();
        let outputs: Vec<String> = match &self.kind {
            Kind::Linear { derived, outputs } => {
                text.push_str(&derived.equations.to_text());
                outputs
                    .iter()
                    .map(|o| derived.equations.output_text(o))
                    .collect()
            }
            Kind::Nonlinear { derived, outputs } => {
                text.push_str(&derived.equations.to_text(self.point.as_ref()));
                if let Some(found) = &self.found {
                    text.push_str(&format!(
                        "\nequilibrium: f = 0 to {:e} after {} Newton iterations\n",
                        found.residual, found.iterations
                    ));
                }
                outputs
                    .iter()
                    .map(|o| derived.equations.output_text(o))
                    .collect()
            }
        };
        for (heading, lines) in [
            ("outputs", outputs),
            ("guards", self.guards.clone()),
            (
                "parameters in SI units (as written in the file)",
                self.converted.clone(),
            ),
        ] {
            if !lines.is_empty() {
                text.push_str(&format!("\n{heading}:\n"));
                for line in lines {
                    text.push_str(&format!("  {line}\n"));
                }
            }
        }
        text.push_str(&self.conventions);
        text
    }

    /// The equations in LaTeX (amsmath), without the comment that opens `--format latex`:
    /// what a notebook renders.
    pub fn latex_body(&self) -> String {
        match &self.kind {
            Kind::Linear { derived, outputs } => derived.equations.to_latex_with_outputs(outputs),
            Kind::Nonlinear { derived, outputs } => {
                derived.equations.to_latex_with_outputs(outputs)
            }
        }
    }

    /// `--format latex`: the comment saying what the matrices need (and the parameters
    /// converted to SI units), then the equations.
    pub fn latex(&self) -> String {
        let mut converted = String::new();
        if !self.converted.is_empty() {
            converted.push_str("% parameters in SI units (as written in the file):\n");
            for line in &self.converted {
                converted.push_str(&format!("% {line}\n"));
            }
        }
        format!("{}{converted}{}", self.preamble, self.latex_body())
    }

    /// `--format json`: the equations' document, with `parameters` added (SI values and
    /// units, and `as_written` where the file's unit is not SI).
    ///
    /// # Errors
    /// Only if the document cannot be serialised.
    pub fn json(&self) -> Result<String, Failure> {
        let parameters = &self.parameters;
        match &self.kind {
            Kind::Linear { derived, outputs } => json(&WithParameters {
                equations: {
                    let layout = self
                        .matrices
                        .unwrap_or_else(|| Layout::for_states(derived.equations.states.len()));
                    derived.equations.to_json_as(&self.spec, outputs, layout)
                },
                parameters,
            }),
            Kind::Nonlinear { derived, outputs } => json(&WithParameters {
                equations: derived
                    .equations
                    .to_json(&self.spec, outputs, self.point.as_ref()),
                parameters,
            }),
        }
    }
}
