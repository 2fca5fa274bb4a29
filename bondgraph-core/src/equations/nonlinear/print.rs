//! A nonlinear mode as a reader wants it: `dx/dt = f(x, u)` per state, its Jacobians, and
//! at an operating point their values, in plain text, LaTeX and a JSON document.
//!
//! The JSON carries `f` (one string per state) and the symbolic Jacobians `df_dx`, `df_du`;
//! with an operating point also `A`, `B` (the Jacobians there, symbolic in the parameters)
//! and their `_value` twins, as a linear mode has them.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::equations::print::{matrix_text, state_latex};
use crate::equations::{StateJson, Variables};
use crate::number;
use crate::symbolic::expr::{Atom, Sym};
use crate::symbolic::latex_name;

use super::linearise::OperatingPoint;
use super::{NonlinearEquations, NonlinearOutput};

/// The JSON document of `bondgraph equations` for a nonlinear mode.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct NonlinearEquationsJson {
    /// The model's name.
    pub model: String,
    /// The mode, as a specification; empty for a model without switching.
    pub mode: String,
    /// `energy` or `coenergy`.
    pub variables: Variables,
    /// Always `true`: the equations are `dx/dt = f(x, u)`.
    pub nonlinear: bool,
    /// The states.
    pub states: Vec<StateJson>,
    /// The inputs' names.
    pub inputs: Vec<String>,
    /// `f`, one symbolic string per state.
    pub f: Vec<String>,
    /// `∂f/∂x`, symbolic, row by row.
    pub df_dx: Vec<Vec<String>>,
    /// `∂f/∂u`, symbolic.
    pub df_du: Vec<Vec<String>>,
    /// The operating point, with an operating point: every state and input by name.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at: Option<BTreeMap<String, f64>>,
    /// `∂f/∂x` at the point, symbolic in the parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub A: Option<Vec<Vec<String>>>,
    /// `∂f/∂u` at the point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub B: Option<Vec<Vec<String>>>,
    /// `A` with the parameter values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub A_value: Option<Vec<Vec<f64>>>,
    /// `B` with the parameter values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub B_value: Option<Vec<Vec<f64>>>,
    /// `f` at the point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub f_value: Option<Vec<f64>>,
    /// Output equations requested.
    pub outputs: Vec<NonlinearOutputJson>,
    /// What the derivation merged, held and solved.
    pub notes: Vec<String>,
}

/// One output equation `y = h(x, u)` in the JSON document.
#[derive(Clone, Debug, Serialize)]
#[allow(non_snake_case)]
pub struct NonlinearOutputJson {
    /// The output's name.
    pub name: String,
    /// `h`, symbolic.
    pub h: String,
    /// Whether the output is the time integral of `h`.
    pub integral: bool,
    /// With an operating point: `∂h/∂x` there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub C: Option<Vec<String>>,
    /// With an operating point: `∂h/∂u` there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub D: Option<Vec<String>>,
    /// With an operating point, where `h` has terms in the inputs' rates (storage driven
    /// directly by an input): `∂h/∂(du/dt)` there.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub F: Option<Vec<String>>,
    /// `C` with the parameter values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub C_value: Option<Vec<f64>>,
    /// `D` with the parameter values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub D_value: Option<Vec<f64>>,
    /// `F` with the parameter values.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub F_value: Option<Vec<f64>>,
    /// `h` at the point (the inputs' rates at zero).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h_value: Option<f64>,
}

impl NonlinearEquations {
    fn texts(&self, m: &[Vec<Sym>]) -> Vec<Vec<String>> {
        m.iter()
            .map(|row| row.iter().map(|e| self.sym_text(e)).collect())
            .collect()
    }

    fn latex_atom(&self, atom: Atom) -> String {
        match atom {
            Atom::State(i) => state_latex(&self.states[i as usize]),
            Atom::Input(i) => latex_name(&self.inputs[i as usize]),
            Atom::InputRate(i) => format!("\\dot{{{}}}", latex_name(&self.inputs[i as usize])),
            other => format!("{other:?}"),
        }
    }

    /// The equations as plain text: `f` per state and the symbolic Jacobians; with a
    /// `point`, the Jacobians' values there.
    pub fn to_text(&self, point: Option<&OperatingPoint>) -> String {
        let mut out = String::new();
        let plural = |n: usize| if n == 1 { "" } else { "s" };
        let variables = match self.variables {
            Variables::Energy => "energy variables",
            Variables::CoEnergy => "co-energy variables",
        };
        out.push_str(&format!(
            "model '{}': {} state{} in {variables}, {} input{}, nonlinear: dx/dt = f(x, u)\n",
            self.model,
            self.states.len(),
            plural(self.states.len()),
            self.inputs.len(),
            plural(self.inputs.len())
        ));
        if !self.states.is_empty() {
            out.push_str("\nstates:\n");
            let width = self.states.iter().map(|s| s.name.len()).max().unwrap_or(0);
            // A linear graph's across variable is the bond graph's flow, its through the effort.
            let (flow, effort) = if self.linear_graph {
                ("across", "through")
            } else {
                ("flow", "effort")
            };
            for (state, law) in self.states.iter().zip(&self.storage_laws) {
                let detail = match (law, state.quantity) {
                    (Some(law), crate::equations::Quantity::Momentum) => {
                        format!(", {flow} = {}", self.sym_text(law))
                    }
                    (Some(law), _) => format!(", {effort} = {}", self.sym_text(law)),
                    (None, _) if !state.merged.is_empty() => format!(
                        ", with {} merged (storage {})",
                        state
                            .merged
                            .iter()
                            .map(|m| format!("'{m}'"))
                            .collect::<Vec<_>>()
                            .join(", "),
                        state.storage.text(&self.symbols)
                    ),
                    (None, _) => String::new(),
                };
                out.push_str(&format!(
                    "  {:width$}  {} of '{}'{detail}\n",
                    state.name,
                    state
                        .quantity
                        .description_in(state.domain, self.linear_graph),
                    state.element
                ));
            }
        }
        if !self.inputs.is_empty() {
            out.push_str(&format!("inputs: {}\n", self.inputs.join(", ")));
        }
        out.push('\n');
        let lhs: Vec<String> = self
            .states
            .iter()
            .map(|s| format!("d{}/dt", s.name))
            .collect();
        let width = lhs.iter().map(String::len).max().unwrap_or(0);
        for (name, f) in lhs.iter().zip(&self.derivatives) {
            out.push_str(&format!("{name:width$} = {}\n", self.sym_text(f)));
        }
        if self.states.is_empty() {
            out.push_str("(no states in this mode)\n");
        } else {
            out.push('\n');
            out.push_str(&matrix_text("df/dx", &self.texts(&self.jacobian_states())));
            if !self.inputs.is_empty() {
                out.push_str(&matrix_text("df/du", &self.texts(&self.jacobian_inputs())));
            }
            if let Some(point) = point {
                let l = self.linearisation(point);
                out.push_str(&format!("\nat {}:\n", self.point_text(point)));
                let numbers = |m: &[Vec<f64>]| -> Vec<Vec<String>> {
                    m.iter()
                        .map(|row| row.iter().map(|v| number::shortest(*v)).collect())
                        .collect()
                };
                let f: Vec<Vec<String>> = l
                    .f_value
                    .iter()
                    .map(|v| vec![number::shortest(*v)])
                    .collect();
                out.push_str(&matrix_text("f", &f));
                out.push_str(&matrix_text("A", &self.texts(&l.a)));
                out.push_str(&matrix_text("  ", &numbers(&l.a_value)));
                if !self.inputs.is_empty() {
                    out.push_str(&matrix_text("B", &self.texts(&l.b)));
                    out.push_str(&matrix_text("  ", &numbers(&l.b_value)));
                }
            }
        }
        if !self.notes.is_empty() {
            out.push_str("\nnotes:\n");
            for note in &self.notes {
                out.push_str(&format!("  - {}\n", note.text(&self.symbols)));
            }
        }
        out
    }

    /// `f` per state in LaTeX, one aligned equation per state.
    pub fn to_latex(&self) -> String {
        let mut out = String::from("\\begin{align}\n");
        if self.states.is_empty() {
            out.push_str("\\text{no states in this mode}\n\\end{align}\n");
            return out;
        }
        let names = |a: Atom| self.latex_atom(a);
        let rows: Vec<String> = self
            .derivatives
            .iter()
            .enumerate()
            .map(|(k, f)| {
                format!(
                    "\\frac{{d {}}}{{dt}} &= {}",
                    self.latex_atom(Atom::State(k as u32)),
                    f.latex(&self.symbols, &names)
                )
            })
            .collect();
        out.push_str(&rows.join(" \\\\\n"));
        out.push_str("\n\\end{align}\n");
        out
    }

    /// `f` per state and then the output equations `y = h(x, u)`, one LaTeX equation each
    /// (an integral output as `\int_0^t h \, dt`).
    pub fn to_latex_with_outputs(&self, outputs: &[NonlinearOutput]) -> String {
        let mut out = self.to_latex();
        let names = |a: Atom| self.latex_atom(a);
        for output in outputs {
            let h = output.value.latex(&self.symbols, &names);
            let rhs = if output.integral {
                format!("\\int_0^t \\left({h}\\right) dt")
            } else {
                h
            };
            out.push_str(&format!(
                "\\begin{{equation}}\n{} = {rhs}\n\\end{{equation}}\n",
                crate::equations::print::latex_output_name(&output.name)
            ));
        }
        out
    }

    /// An output equation as text: `effort:spring = k*q_spring^3`.
    pub fn output_text(&self, output: &NonlinearOutput) -> String {
        let h = self.sym_text(&output.value);
        if output.integral {
            format!("{} = integral of ({h}) dt", output.name)
        } else {
            format!("{} = {h}", output.name)
        }
    }

    /// The JSON document; `mode` is the mode's specification (empty for plain models).
    pub fn to_json(
        &self,
        mode: &str,
        outputs: &[NonlinearOutput],
        point: Option<&OperatingPoint>,
    ) -> NonlinearEquationsJson {
        let linearisation = point.map(|p| self.linearisation(p));
        let at = point.map(|p| {
            self.states
                .iter()
                .map(|s| s.name.clone())
                .zip(p.states.iter().copied())
                .chain(self.inputs.iter().cloned().zip(p.inputs.iter().copied()))
                .collect()
        });
        NonlinearEquationsJson {
            model: self.model.clone(),
            mode: mode.to_string(),
            variables: self.variables,
            nonlinear: true,
            states: self
                .states
                .iter()
                .zip(&self.storage_laws)
                .map(|(s, law)| StateJson {
                    name: s.name.clone(),
                    element: s.element.clone(),
                    quantity: s.quantity,
                    merged: s.merged.clone(),
                    storage: match law {
                        Some(law) => self.sym_text(law),
                        None => s.storage.text(&self.symbols),
                    },
                })
                .collect(),
            inputs: self.inputs.clone(),
            f: self.derivatives.iter().map(|f| self.sym_text(f)).collect(),
            df_dx: self.texts(&self.jacobian_states()),
            df_du: self.texts(&self.jacobian_inputs()),
            at,
            A: linearisation.as_ref().map(|l| self.texts(&l.a)),
            B: linearisation.as_ref().map(|l| self.texts(&l.b)),
            A_value: linearisation.as_ref().map(|l| l.a_value.clone()),
            B_value: linearisation.as_ref().map(|l| l.b_value.clone()),
            f_value: linearisation.as_ref().map(|l| l.f_value.clone()),
            outputs: outputs.iter().map(|o| self.output_json(o, point)).collect(),
            notes: self.notes.iter().map(|n| n.text(&self.symbols)).collect(),
        }
    }

    fn output_json(
        &self,
        output: &NonlinearOutput,
        point: Option<&OperatingPoint>,
    ) -> NonlinearOutputJson {
        let gradient =
            |atom: &dyn Fn(usize) -> Atom, count: usize, p: &OperatingPoint| -> Vec<Sym> {
                (0..count)
                    .map(|j| self.at(&output.value.diff(atom(j)), p))
                    .collect()
            };
        let c = point.map(|p| gradient(&|j| Atom::State(j as u32), self.states.len(), p));
        let d = point.map(|p| gradient(&|j| Atom::Input(j as u32), self.inputs.len(), p));
        let f = point
            .filter(|_| {
                output
                    .value
                    .mentions_any(&|a| matches!(a, Atom::InputRate(_)))
            })
            .map(|p| gradient(&|j| Atom::InputRate(j as u32), self.inputs.len(), p));
        let values = |row: &Option<Vec<Sym>>| {
            row.as_ref()
                .zip(point)
                .map(|(r, p)| r.iter().map(|e| self.evaluate(e, p)).collect())
        };
        NonlinearOutputJson {
            name: output.name.clone(),
            h: self.sym_text(&output.value),
            integral: output.integral,
            C_value: values(&c),
            D_value: values(&d),
            F_value: values(&f),
            C: c.map(|r| r.iter().map(|e| self.sym_text(e)).collect()),
            D: d.map(|r| r.iter().map(|e| self.sym_text(e)).collect()),
            F: f.map(|r| r.iter().map(|e| self.sym_text(e)).collect()),
            h_value: point.map(|p| self.evaluate(&output.value, p)),
        }
    }
}
