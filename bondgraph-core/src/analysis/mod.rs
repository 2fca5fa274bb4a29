//! Analysis of a linear mode: its characteristic polynomial, the transfer function of any
//! input-output pair, and the check of a student's `A`, `B` against the model's.
//!
//! Everything here is exact: the characteristic polynomial and transfer functions are
//! rational functions of the parameters (and `s`), computed with the canonical algebra of
//! [`crate::symbolic`], so a cancelled pole is cancelled for every parameter value and two
//! answers are equal only if they are equal on paper. Numbers (eigenvalues, roots, step
//! responses) are the solver's job; this module gives it exact coefficients.
//!
//! Modes with more than [`SYMBOLIC_STATES`] states are analysed with the parameters'
//! values substituted as exact decimals ([`Analysis::new`]): the same exact algorithm, free
//! of the symbolic expression swell that large systems would bring, and nothing to print
//! that a textbook would.
//!
//! Submodules, one job each: `characteristic` (Faddeev–LeVerrier), `transfer` (transfer
//! functions and their textbook printing), `answer` (reading an answer file), `similarity`
//! (the change of state variables `T` between two `(A, B)`, if any), `compare` (the verdict
//! on an answer).
//!
//! # Example
//!
//! ```
//! use bondgraph_core::analysis::{Analysis, Channel};
//! use bondgraph_core::{equations, laws, model};
//!
//! let model = bondgraph_ron::model::load_str("rc.ron", r#"Model(
//!     name: "rc",
//!     parameters: { "R": (value: 1000.0, unit: "ohm"), "C": (value: 0.001, unit: "F") },
//!     inputs: { "V": (unit: "V") },
//!     elements: { "source": Se(effort: "V"), "j": One, "resistor": R(resistance: "R"),
//!                 "capacitor": C(compliance: "C") },
//!     bonds: [("source", "j"), ("j", "resistor"), ("j", "capacitor")],
//! )"#).unwrap();
//! let eq = equations::derive(&model, &laws::plain_laws(&model), &Default::default()).unwrap();
//! let analysis = Analysis::new(&eq);
//! // The charge q_capacitor from V: G(s) = C/(C*R*s + 1).
//! let tf = analysis.transfer(&Channel::to_state(&eq, 0, 0));
//! assert_eq!(tf.numerator_text(analysis.symbols()), "C");
//! assert_eq!(tf.denominator_text(analysis.symbols()), "C*R*s + 1");
//! ```

pub mod answer;
mod characteristic;
pub mod compare;
pub(crate) mod similarity;
mod transfer;

pub use characteristic::{Characteristic, Matrix, characteristic};
pub use transfer::{Channel, TransferFunction, polynomial_text};

use crate::equations::StateEquations;
use crate::symbolic::{RatFunc, Scaled, SymbolTable};

/// Modes with at most this many states are analysed symbolically; larger ones with the
/// parameter values substituted exactly.
pub const SYMBOLIC_STATES: usize = 4;

/// The characteristic polynomial of a mode's `A`, ready for its transfer functions.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// `det(sI - A)` and `adj(sI - A)`.
    pub characteristic: Characteristic,
    /// Whether the coefficients are symbolic in the parameters (else exact numbers).
    pub symbolic: bool,
    symbols: SymbolTable,
    values: Vec<f64>,
}

impl Analysis {
    /// The analysis of `equations`' `A`: symbolic up to [`SYMBOLIC_STATES`] states, with
    /// exact parameter values beyond.
    pub fn new(equations: &StateEquations) -> Self {
        let symbolic = equations.state_count() <= SYMBOLIC_STATES;
        let a = equations.a();
        let a = if symbolic {
            a
        } else {
            valued_matrix(&a, &equations.values)
        };
        Analysis {
            characteristic: characteristic(&a),
            symbolic,
            symbols: if symbolic {
                equations.symbols.clone()
            } else {
                SymbolTable::default()
            },
            values: equations.values.clone(),
        }
    }

    /// The symbols the coefficients are written over (none when not symbolic).
    pub fn symbols(&self) -> &SymbolTable {
        &self.symbols
    }

    /// The transfer function of `channel` (a channel of the same equations).
    pub fn transfer(&self, channel: &Channel) -> TransferFunction {
        if self.symbolic {
            return TransferFunction::new(&self.characteristic, channel, &self.symbols);
        }
        let v =
            |x: &[RatFunc]| -> Vec<RatFunc> { x.iter().map(|c| valued(c, &self.values)).collect() };
        let channel = Channel {
            b: v(&channel.b),
            e: v(&channel.e),
            c: v(&channel.c),
            d: valued(&channel.d, &self.values),
            f: valued(&channel.f, &self.values),
            integral: channel.integral,
        };
        TransferFunction::new(&self.characteristic, &channel, &self.symbols)
    }

    /// The coefficients of `det(sI - A)` with the parameter values, highest power first.
    pub fn characteristic_values(&self) -> Vec<f64> {
        self.characteristic
            .coefficients
            .iter()
            .rev()
            .map(|c| c.eval(&self.values))
            .collect()
    }

    /// As [`Analysis::characteristic_values`], in extended range ([`Scaled`]).
    pub fn characteristic_scaled(&self) -> Vec<Scaled> {
        self.characteristic
            .coefficients
            .iter()
            .rev()
            .map(|c| c.eval_scaled(&self.values))
            .collect()
    }

    /// `det(sI - A)` as text: `s^2 + b/m*s + k/m`.
    pub fn characteristic_text(&self) -> String {
        let highest_first: Vec<RatFunc> = self
            .characteristic
            .coefficients
            .iter()
            .rev()
            .cloned()
            .collect();
        polynomial_text(&highest_first, &self.symbols)
    }
}

/// `x` evaluated with `values`, as an exact decimal constant.
pub fn valued(x: &RatFunc, values: &[f64]) -> RatFunc {
    if x.is_constant() {
        return x.clone();
    }
    let value = x.eval(values);
    let magnitude = RatFunc::from_decimal(&format!("{:e}", value.abs())).unwrap_or_default();
    if value < 0.0 { -magnitude } else { magnitude }
}

fn valued_matrix(m: &[Vec<RatFunc>], values: &[f64]) -> Matrix {
    m.iter()
        .map(|row| row.iter().map(|x| valued(x, values)).collect())
        .collect()
}
