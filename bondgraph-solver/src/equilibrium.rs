//! Equilibria of nonlinear modes: where `f(x, u) = 0` for constant inputs.
//!
//! [`find`] solves `f(x, u) = 0` from a starting point by Newton's method with the symbolic
//! Jacobian, damped by a backtracking line search on `|f|²`, and with a Levenberg–Marquardt
//! shift where the Jacobian is singular (a free body's position is any value at rest): it
//! answers "where could this mode rest?", and finds unstable equilibria too (the inverted
//! pendulum). Which of them a trajectory reaches is the steady-state search's question
//! ([`crate::steady`]), which integrates until the motion settles.

use bondgraph_core::equations::nonlinear::{NonlinearEquations, OperatingPoint};
use bondgraph_core::symbolic::expr::{Atom, Sym, TapeBuilder};
use nalgebra::{DMatrix, DVector};

/// An equilibrium found by [`find`].
#[derive(Clone, Debug, PartialEq)]
pub struct Equilibrium {
    /// The point: the states found, the inputs as given.
    pub point: OperatingPoint,
    /// `max |fᵢ|` there.
    pub residual: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// Newton iterations [`find`] takes at most. A cubic term far from its root shrinks by only
/// a third a step: from `q = 1e20` to 1 that is about 115 steps, from 1e-50 down to the
/// smallest doubles about 600.
pub const MAX_ITERATIONS: usize = 1000;

/// Why no equilibrium was found.
#[derive(Clone, Debug, PartialEq)]
pub enum EquilibriumError {
    /// The iteration stalled or ran out of iterations.
    NotFound {
        /// The best `max |fᵢ|` reached.
        residual: f64,
        /// Where.
        states: Vec<f64>,
        /// The states' names.
        names: Vec<String>,
    },
    /// `f` (or the size of its terms) is not finite at the starting point (a term
    /// overflows), so Newton's method cannot start there.
    NotFinite {
        /// The starting states.
        states: Vec<f64>,
        /// The states' names.
        names: Vec<String>,
    },
}

fn point_text(names: &[String], states: &[f64]) -> String {
    names
        .iter()
        .zip(states)
        .map(|(n, v)| format!("{n} = {}", bondgraph_core::number::shortest(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

impl std::fmt::Display for EquilibriumError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EquilibriumError::NotFound {
                residual,
                states,
                names,
            } => write!(
                f,
                "no equilibrium found: Newton's method stopped with |f| = {residual:e} at {}; try another starting point (--at)",
                point_text(names, states)
            ),
            EquilibriumError::NotFinite { states, names } => write!(
                f,
                "no equilibrium search from {}: f is not finite there (a term overflows double precision); start nearer the equilibrium (--at)",
                point_text(names, states)
            ),
        }
    }
}

impl std::error::Error for EquilibriumError {}

/// The equilibrium `f(x, u) = 0` nearest (in Newton's sense) to `start`, with the inputs
/// held at `start`'s; see the [module documentation](self).
///
/// Converged when every `|fᵢ|` is below `1e-12` of the size of its terms plus that of its
/// linear part `Σⱼ |∂fᵢ/∂xⱼ| |xⱼ|` (a term that vanishes at the equilibrium, `sin(q)` at
/// `q = π`, has no size of its own there) or below the smallest normal double (an
/// equilibrium at the origin, where every term vanishes with the state); or when the Newton
/// step would move the state by less than `1e-12` of its largest component. No tolerance
/// is taken from the starting point: from `q = 1e20` a residual of 1e-14 of the start's
/// size is still `q = 1e15`, not an equilibrium.
///
/// # Errors
/// [`EquilibriumError::NotFinite`] when `f` overflows at `start`;
/// [`EquilibriumError::NotFound`] when [`MAX_ITERATIONS`] iterations do not converge.
pub fn find(
    equations: &NonlinearEquations,
    start: &OperatingPoint,
) -> Result<Equilibrium, EquilibriumError> {
    let n = equations.states.len();
    let inputs = start.inputs.clone();
    let slot = |a: Atom| match a {
        Atom::State(i) => Some(i as usize),
        _ => None,
    };
    // Inputs are constants here: substitute them.
    let fixed = |e: &Sym| {
        e.substitute(&|a| match a {
            Atom::Input(i) => Some(Sym::coefficient(exact(inputs[i as usize]))),
            Atom::InputRate(_) => Some(Sym::zero()),
            _ => None,
        })
    };
    let mut builder = TapeBuilder::new(n, &slot, &equations.values);
    let f: Vec<Sym> = equations.derivatives.iter().map(fixed).collect();
    for e in &f {
        builder.push(e).expect("f is in states and inputs");
    }
    for e in &f {
        builder
            .push(&e.magnitude())
            .expect("f is in states and inputs");
    }
    for row in &equations.jacobian_states() {
        for e in row {
            builder
                .push(&fixed(e))
                .expect("the Jacobian is in states and inputs");
        }
    }
    let tape = builder.finish();
    let mut scratch = tape.scratch();
    let mut out = vec![0.0; tape.output_count()];
    let mut x = start.states.clone();
    let residual = |out: &[f64], x: &[f64]| -> (f64, bool) {
        let mut worst: f64 = 0.0;
        let mut converged = true;
        for i in 0..n {
            worst = worst.max(out[i].abs());
            let linear: f64 = (0..n)
                .filter(|&j| x[j] != 0.0)
                .map(|j| (out[2 * n + i * n + j] * x[j]).abs())
                .sum();
            // A size that overflows cannot vouch for f: only a finite one judges it.
            let tolerance = 1e-12 * (out[n + i] + linear);
            let small = out[i].abs() <= f64::MIN_POSITIVE
                || (tolerance.is_finite() && out[i].abs() <= tolerance);
            converged &= small;
        }
        if !converged && worst.is_finite() {
            // A row whose terms all vanish at the equilibrium (dq/dt = p/m at p = 0) has no
            // size of its own; there, a Newton step that moves the state by less than 1e-12
            // of its size says the point is the equilibrium to double precision.
            let j = DMatrix::from_row_slice(n, n, &out[2 * n..2 * n + n * n]);
            let f = DVector::from_column_slice(&out[..n]);
            let size = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if let Some(step) = j.lu().solve(&f) {
                let moved = step.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                converged = size > 0.0 && moved.is_finite() && moved <= 1e-12 * size;
            }
        }
        (worst, converged)
    };
    tape.eval(&x, &mut scratch, &mut out);
    // f itself must be finite to start from; an infinite slope (a square root at zero) is
    // for the damped step to cope with.
    if out[..2 * n].iter().any(|v| !v.is_finite()) {
        return Err(EquilibriumError::NotFinite {
            states: x,
            names: equations.states.iter().map(|s| s.name.clone()).collect(),
        });
    }
    let mut lambda = 1e-9;
    for iteration in 0..MAX_ITERATIONS {
        let (worst, converged) = residual(&out, &x);
        if converged || n == 0 {
            return Ok(Equilibrium {
                point: OperatingPoint::from_values(x, inputs),
                residual: worst,
                iterations: iteration,
            });
        }
        let fx = DVector::from_column_slice(&out[..n]);
        let j = DMatrix::from_row_slice(n, n, &out[2 * n..2 * n + n * n]);
        let cost = size(&out[..n]);
        let jt = j.transpose();
        let gradient = &jt * &fx;
        let normal = &jt * &j;
        let mut improved = false;
        for _ in 0..30 {
            let mut system = normal.clone();
            for i in 0..n {
                system[(i, i)] += lambda * (1.0 + normal[(i, i)]);
            }
            let Some(step) = system.lu().solve(&(-&gradient)) else {
                lambda *= 10.0;
                continue;
            };
            let trial: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            let mut trial_out = vec![0.0; out.len()];
            tape.eval(&trial, &mut scratch, &mut trial_out);
            let trial_cost = size(&trial_out[..n]);
            if trial_cost.is_finite() && trial_cost < cost {
                x = trial;
                out = trial_out;
                lambda = (lambda / 10.0).max(1e-15);
                improved = true;
                break;
            }
            lambda *= 10.0;
        }
        if !improved {
            break;
        }
    }
    let (worst, converged) = residual(&out, &x);
    if converged {
        return Ok(Equilibrium {
            point: OperatingPoint::from_values(x, inputs),
            residual: worst,
            iterations: MAX_ITERATIONS,
        });
    }
    Err(EquilibriumError::NotFound {
        residual: worst,
        states: x,
        names: equations.states.iter().map(|s| s.name.clone()).collect(),
    })
}

/// `‖f‖₂` without overflow or underflow in the squares: the damped step compares these,
/// and `|f|²` of 1e-175 is 0 in doubles (the search stalled there, short of convergence).
fn size(f: &[f64]) -> f64 {
    if f.iter().any(|v| v.is_nan()) {
        return f64::NAN;
    }
    let largest = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest * f.iter().map(|v| (v / largest).powi(2)).sum::<f64>().sqrt()
}

fn exact(value: f64) -> bondgraph_core::symbolic::RatFunc {
    let text = format!("{:e}", value.abs());
    let magnitude = bondgraph_core::symbolic::RatFunc::from_decimal(&text)
        .unwrap_or_else(bondgraph_core::symbolic::RatFunc::zero);
    if value < 0.0 { -magnitude } else { magnitude }
}
