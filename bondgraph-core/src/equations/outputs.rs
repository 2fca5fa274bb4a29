//! Output equations: any bond's effort or flow as `y = C x + D u + d`.
//!
//! Outputs are named on the command line and in scenarios as `effort:ELEMENT`,
//! `flow:ELEMENT` (the one bond of a one-port, e.g. `effort:damper` is the damper force) or
//! `effort:FROM->TO` for any bond (e.g. `flow:j1->j2`). A model read from a linear graph
//! also has `across:BRANCH` and `through:BRANCH`, its branches' across and through
//! variables (a bond variable, or minus one, in the bond graph it was translated into).

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::StateEquations;
use crate::linear::LinearForm;
use crate::model::{BondId, Model};

/// Which variable of a bond an output is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OutputQuantity {
    /// The bond's effort.
    Effort,
    /// The bond's flow (positive in the bond's direction).
    Flow,
}

/// A requested output: one bond variable.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct OutputSpec {
    /// The output's name, as the user wrote it (`effort:damper`).
    pub name: String,
    /// Effort or flow.
    pub quantity: OutputQuantity,
    /// The bond.
    pub bond: BondId,
    /// Whether the output is minus the bond variable (a linear-graph branch whose through
    /// or across variable is the opposite of its bond's effort or flow).
    pub negated: bool,
}

/// One output equation, an affine form of the states, inputs and the constant 1.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputEquation {
    /// The output's name.
    pub name: String,
    /// `y` as an affine form.
    pub row: LinearForm,
    /// Whether what is output is the time integral of `y` (`integral:flow:mass`).
    pub integral: bool,
}

impl OutputSpec {
    /// Parses `effort:ELEMENT`, `flow:ELEMENT`, `effort:FROM->TO` or `flow:FROM->TO`
    /// (`e:` and `f:` for short).
    ///
    /// # Errors
    /// [`DiagnosticKind::BadOutput`] naming what is wrong: an unknown quantity, element or
    /// bond, or an element with more than one bond named without its bond.
    pub fn parse(model: &Model, text: &str) -> Result<Self> {
        let bad = |message: String| Diagnostic::new(DiagnosticKind::BadOutput, message);
        if let Some((quantity @ ("across" | "through"), branch)) =
            text.split_once(':').map(|(q, t)| (q.trim(), t.trim()))
        {
            return Self::parse_branch(model, text, quantity == "across", branch);
        }
        let Some((quantity, target)) = text.split_once(':') else {
            return Err(bad(format!(
                "output '{text}' must be written effort:ELEMENT, flow:ELEMENT or effort:FROM->TO"
            ))
            .into());
        };
        let quantity = match quantity.trim() {
            "effort" | "e" => OutputQuantity::Effort,
            "flow" | "f" => OutputQuantity::Flow,
            other => {
                return Err(bad(format!(
                    "output '{text}': unknown quantity '{other}'; expected {}",
                    if model.linear_graph.is_some() {
                        "across, through, effort or flow"
                    } else {
                        "effort or flow"
                    }
                ))
                .into());
            }
        };
        let target = target.trim();
        let element_id = |name: &str| {
            model.element_named(name.trim()).ok_or_else(|| {
                Diagnostics::from(
                    bad(format!(
                        "output '{text}': the model has no element '{}'",
                        name.trim()
                    ))
                    .element(name.trim()),
                )
            })
        };
        let bond = if let Some((from, to)) = target.split_once("->") {
            let (from, to) = (element_id(from)?, element_id(to)?);
            model
                .bond_ids()
                .find(|&b| model.bond(b).from == from && model.bond(b).to == to)
                .ok_or_else(|| {
                    bad(format!(
                        "output '{text}': there is no bond from '{}' to '{}'",
                        model.element(from).name,
                        model.element(to).name
                    ))
                })?
        } else {
            let element = element_id(target)?;
            match model.element(element).bonds.as_slice() {
                [bond] => *bond,
                bonds => {
                    let choices: Vec<String> = bonds
                        .iter()
                        .map(|b| format!("'{}'", model.bond_label(*b)))
                        .collect();
                    return Err(bad(format!(
                        "output '{text}': '{target}' has {} bonds; name one as FROM->TO: {}",
                        bonds.len(),
                        choices.join(", ")
                    ))
                    .element(target)
                    .into());
                }
            }
        };
        Ok(Self {
            name: text.to_string(),
            quantity,
            bond,
            negated: false,
        })
    }

    /// `across:BRANCH` or `through:BRANCH` of a linear graph's one-port branch.
    fn parse_branch(model: &Model, text: &str, across: bool, name: &str) -> Result<Self> {
        let bad = |message: String| Diagnostic::new(DiagnosticKind::BadOutput, message);
        let Some(graph) = &model.linear_graph else {
            return Err(bad(format!(
                "output '{text}': across: and through: name branches of a linear graph, and model '{}' is a bond graph",
                model.name
            ))
            .note("write effort:ELEMENT or flow:ELEMENT")
            .into());
        };
        let Some(index) = graph.branch_named(name) else {
            let mut d = bad(format!(
                "output '{text}': the linear graph has no branch '{name}'"
            ))
            .element(name);
            if let Some(close) =
                crate::diagnostics::suggest(name, graph.branches.iter().map(|b| b.name.as_str()))
            {
                d = d.note(format!("did you mean '{close}'?"));
            }
            return Err(d.into());
        };
        let branch = &graph.branches[index];
        let [edge] = branch.edges[..] else {
            return Err(bad(format!(
                "output '{text}': '{name}' is a {} with two ports; name a one-port branch on the nodes of the port wanted",
                branch.kind.description()
            ))
            .element(name)
            .into());
        };
        let (quantity, sign) = if across {
            (OutputQuantity::Flow, edge.across_sign)
        } else {
            (OutputQuantity::Effort, edge.through_sign)
        };
        Ok(Self {
            name: text.to_string(),
            quantity,
            bond: edge.bond,
            negated: sign < 0,
        })
    }
}

impl StateEquations {
    /// The output equation of `spec` in this mode. It may involve the inputs' rates
    /// ([`Var::InputRate`](crate::linear::Var::InputRate)) where storage is driven directly
    /// by an input.
    pub fn output(&self, spec: &OutputSpec) -> OutputEquation {
        let row = match spec.quantity {
            OutputQuantity::Effort => self.bond_effort(spec.bond),
            OutputQuantity::Flow => self.bond_flow(spec.bond),
        };
        OutputEquation {
            name: spec.name.clone(),
            row: if spec.negated {
                row.scaled(&crate::symbolic::RatFunc::integer(-1))
            } else {
                row.clone()
            },
            integral: false,
        }
    }
}
