//! Operating points and the linearisation of a nonlinear mode there.
//!
//! `dx/dt ≈ f(x₀, u₀) + A (x - x₀) + B (u - u₀)` with `A = ∂f/∂x`, `B = ∂f/∂u` at the
//! point, written as a linear mode's equations `dx/dt = A x + B u + c` (and its outputs
//! likewise), so that linear analysis applies to it unchanged. Entries stay exact where
//! substituting the point folds them to rational functions of the parameters
//! (`cos(0) = 1`: the pendulum at rest has `A = [0, -g*l*m; 1/(l^2*m), 0]`); other entries
//! are their value with the model's parameters, as an exact decimal.

use crate::diagnostics::suggest;
use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::{Note, StateEquations};
use crate::linear::{LinearForm, Var};
use crate::symbolic::RatFunc;
use crate::symbolic::expr::{Atom, Sym};

use super::{NonlinearEquations, form_to_sym};

/// Values of the states and inputs of a mode: where to evaluate or linearise it.
#[derive(Clone, Debug, PartialEq)]
pub struct OperatingPoint {
    /// The states' values, in state order.
    pub states: Vec<f64>,
    /// The inputs' values, in input order.
    pub inputs: Vec<f64>,
    /// The same, exactly, as given (states then inputs).
    exact: Vec<RatFunc>,
    /// The names given explicitly (the others are zero).
    pub given: Vec<String>,
}

/// Why an operating point could not be read (kept for the API's shape; errors are
/// [`Diagnostics`]).
pub type PointError = Diagnostics;

impl OperatingPoint {
    /// Every state and input at zero.
    pub fn zero(states: usize, inputs: usize) -> Self {
        Self {
            states: vec![0.0; states],
            inputs: vec![0.0; inputs],
            exact: vec![RatFunc::zero(); states + inputs],
            given: Vec::new(),
        }
    }

    /// A point from values (an equilibrium found numerically, say).
    pub fn from_values(states: Vec<f64>, inputs: Vec<f64>) -> Self {
        let exact = states
            .iter()
            .chain(&inputs)
            .map(|v| exact_decimal(*v))
            .collect();
        Self {
            states,
            inputs,
            exact,
            given: Vec::new(),
        }
    }

    /// Parses `NAME=VALUE,...` over the `states` and `inputs` names; what is not named is
    /// zero.
    ///
    /// # Errors
    /// [`DiagnosticKind::UnknownName`] for a name that is neither (with a suggestion),
    /// [`DiagnosticKind::InvalidValue`] for a value that is not a finite number, and a name
    /// given twice.
    pub fn parse(states: &[String], inputs: &[String], text: &str) -> Result<Self> {
        let mut point = Self::zero(states.len(), inputs.len());
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let bad = |kind, message: String| Diagnostics::from(Diagnostic::new(kind, message));
            let Some((name, value)) = part.split_once('=') else {
                return Err(bad(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "operating point '{part}' must be written NAME=VALUE, e.g. q_spring=0.1"
                    ),
                ));
            };
            let (name, value) = (name.trim(), value.trim());
            let index = states
                .iter()
                .chain(inputs)
                .position(|n| n == name)
                .ok_or_else(|| {
                    let mut d = Diagnostic::new(
                        DiagnosticKind::UnknownName,
                        format!(
                            "operating point '{part}': '{name}' is neither a state nor an input of this mode"
                        ),
                    );
                    if let Some(s) = suggest(name, states.iter().chain(inputs).map(String::as_str)) {
                        d = d.note(format!("did you mean '{s}'?"));
                    }
                    Diagnostics::from(d)
                })?;
            if point.given.iter().any(|g| g == name) {
                return Err(bad(
                    DiagnosticKind::InvalidValue,
                    format!("operating point gives '{name}' twice"),
                ));
            }
            let (negative, digits) = match value.strip_prefix('-') {
                Some(rest) => (true, rest),
                None => (false, value.strip_prefix('+').unwrap_or(value)),
            };
            let number: f64 = value
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite())
                .ok_or_else(|| {
                    bad(
                        DiagnosticKind::InvalidValue,
                        format!("operating point '{part}': '{value}' is not a finite number"),
                    )
                })?;
            let exact = RatFunc::from_decimal(digits)
                .map(|r| if negative { -r } else { r })
                .unwrap_or_else(|| exact_decimal(number));
            if index < states.len() {
                point.states[index] = number;
            } else {
                point.inputs[index - states.len()] = number;
            }
            point.exact[index] = exact;
            point.given.push(name.to_string());
        }
        Ok(point)
    }

    /// The exact value of each state and input, as an expression.
    fn substitution(&self) -> impl Fn(Atom) -> Option<Sym> + '_ {
        let states = self.states.len();
        move |a| match a {
            Atom::State(i) => Some(Sym::coefficient(self.exact[i as usize].clone())),
            Atom::Input(i) => Some(Sym::coefficient(self.exact[states + i as usize].clone())),
            // Inputs are held at the point: their rates are zero.
            Atom::InputRate(_) => Some(Sym::zero()),
            _ => None,
        }
    }
}

/// The exact rational of `value`'s shortest decimal form (`0.1` is 1/10).
fn exact_decimal(value: f64) -> RatFunc {
    let text = format!("{:e}", value.abs());
    let magnitude = RatFunc::from_decimal(&text).unwrap_or_else(RatFunc::zero);
    if value < 0.0 { -magnitude } else { magnitude }
}

/// `A`, `B` and `f` of a nonlinear mode at an operating point.
#[derive(Clone, Debug)]
pub struct Linearisation {
    /// `∂f/∂x` at the point, symbolic in the parameters.
    pub a: Vec<Vec<Sym>>,
    /// `∂f/∂u` at the point.
    pub b: Vec<Vec<Sym>>,
    /// `f` at the point.
    pub f: Vec<Sym>,
    /// `A` with the parameter values.
    pub a_value: Vec<Vec<f64>>,
    /// `B` with the parameter values.
    pub b_value: Vec<Vec<f64>>,
    /// `f` with the parameter values.
    pub f_value: Vec<f64>,
}

impl NonlinearEquations {
    /// An expression's value at `point` with the model's parameter values.
    pub fn evaluate(&self, expr: &Sym, point: &OperatingPoint) -> f64 {
        expr.eval(
            &|a| match a {
                Atom::State(i) => point.states[i as usize],
                Atom::Input(i) => point.inputs[i as usize],
                _ => 0.0,
            },
            &self.values,
        )
    }

    /// An expression at `point`, folded symbolically.
    pub fn at(&self, expr: &Sym, point: &OperatingPoint) -> Sym {
        expr.substitute(&point.substitution())
    }

    /// The Jacobians and `f` at `point`.
    pub fn linearisation(&self, point: &OperatingPoint) -> Linearisation {
        let at_point = |m: Vec<Vec<Sym>>| -> Vec<Vec<Sym>> {
            m.iter()
                .map(|row| row.iter().map(|e| self.at(e, point)).collect())
                .collect()
        };
        let a = at_point(self.jacobian_states());
        let b = at_point(self.jacobian_inputs());
        let f: Vec<Sym> = self.derivatives.iter().map(|e| self.at(e, point)).collect();
        let values = |m: &[Vec<Sym>]| -> Vec<Vec<f64>> {
            m.iter()
                .map(|row| row.iter().map(|e| self.evaluate(e, point)).collect())
                .collect()
        };
        Linearisation {
            a_value: values(&a),
            b_value: values(&b),
            f_value: f.iter().map(|e| self.evaluate(e, point)).collect(),
            a,
            b,
            f,
        }
    }

    /// The linearisation at `point` as a linear mode's equations
    /// (`dx/dt = A x + B u + c`, every bond variable likewise), for linear analysis.
    pub fn linearise(&self, point: &OperatingPoint) -> StateEquations {
        let n = self.states.len();
        let m = self.inputs.len();
        let affine = |expr: &Sym| -> LinearForm {
            // h(x, u) ≈ h₀ + ∇h·((x, u) - (x₀, u₀))
            let mut form = LinearForm::zero();
            let mut constant = self.exact_value(&self.at(expr, point), point);
            for j in 0..n + m {
                let (atom, var, x0) = if j < n {
                    (
                        Atom::State(j as u32),
                        Var::State(j as u32),
                        point.exact[j].clone(),
                    )
                } else {
                    let i = (j - n) as u32;
                    (Atom::Input(i), Var::Input(i), point.exact[j].clone())
                };
                let slope = self.exact_value(&self.at(&expr.diff(atom), point), point);
                constant = constant.sub_ref(&(&slope * &x0));
                form.add(&LinearForm::term(var, slope));
            }
            form.add(&LinearForm::constant(constant));
            form
        };
        let mut notes = self.notes.clone();
        notes.push(Note::Linearised {
            point: self.point_text(point),
        });
        StateEquations {
            model: self.model.clone(),
            variables: self.variables,
            states: self.states.clone(),
            inputs: self.inputs.clone(),
            derivatives: self.derivatives.iter().map(affine).collect(),
            notes,
            causality: self.causality.clone(),
            symbols: self.symbols.clone(),
            values: self.values.clone(),
            bond_vars: self.bond_vars.iter().map(affine).collect(),
            storage_energy: self
                .storage_energy
                .iter()
                .map(|(e, form)| (*e, affine(&form_to_sym(form))))
                .collect(),
            linear_graph: self.linear_graph,
        }
    }

    /// An expression free of states and inputs as an exact rational function: itself when
    /// it is one, else its value with the parameters as an exact decimal.
    fn exact_value(&self, expr: &Sym, point: &OperatingPoint) -> RatFunc {
        match expr.as_coefficient() {
            Some(c) => c.clone(),
            None => exact_decimal(self.evaluate(expr, point)),
        }
    }

    /// The point as text: `q_pendulum = 0.5, p_bob = 0`.
    pub fn point_text(&self, point: &OperatingPoint) -> String {
        self.states
            .iter()
            .map(|s| &s.name)
            .zip(&point.states)
            .chain(self.inputs.iter().zip(&point.inputs))
            .map(|(name, value)| format!("{name} = {}", crate::number::shortest(*value)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
