//! Equilibria of nonlinear modes: where `f(x, u) = 0` for constant inputs.
//!
//! Two ways, for two questions. [`find`] solves `f(x, u) = 0` from a starting point by
//! Newton's method with the symbolic Jacobian, damped by a backtracking line search on
//! `|f|²`, and with a Levenberg–Marquardt shift where the Jacobian is singular (a free
//! body's position is any value at rest): it answers "where could this mode rest?", and
//! finds unstable equilibria too (the inverted pendulum). [`steady_by_integration`] is the
//! steady-state search of a simulation: it integrates until the motion settles, and so
//! finds the stable state a trajectory reaches, or steady motion (a constant drift).

use bondgraph_core::equations::nonlinear::{NonlinearEquations, OperatingPoint};
use bondgraph_core::symbolic::expr::{Atom, Sym, TapeBuilder};
use nalgebra::{DMatrix, DVector};

use crate::hybrid::{SimError, Stepper};
use crate::steady::{Steady, SteadyError, SteadySettings};

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
}

impl std::fmt::Display for EquilibriumError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EquilibriumError::NotFound {
                residual,
                states,
                names,
            } => {
                let at: Vec<String> = names
                    .iter()
                    .zip(states)
                    .map(|(n, v)| format!("{n} = {v}"))
                    .collect();
                write!(
                    f,
                    "no equilibrium found: Newton's method stopped with |f| = {residual:e} at {}; try another starting point (--at)",
                    at.join(", ")
                )
            }
        }
    }
}

impl std::error::Error for EquilibriumError {}

/// The equilibrium `f(x, u) = 0` nearest (in Newton's sense) to `start`, with the inputs
/// held at `start`'s; see the [module documentation](self).
///
/// Converged when every `|fᵢ|` is below `1e-12` of the size of its terms plus that of its
/// linear part `Σⱼ |∂fᵢ/∂xⱼ| |xⱼ|` (a term that vanishes at the equilibrium, `sin(q)` at
/// `q = π`, has no size of its own there).
///
/// # Errors
/// [`EquilibriumError::NotFound`] when 200 iterations do not converge.
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
            let linear: f64 = (0..n).map(|j| (out[2 * n + i * n + j] * x[j]).abs()).sum();
            if out[i].abs() > 1e-12 * (out[n + i] + linear) + f64::MIN_POSITIVE {
                converged = false;
            }
        }
        (worst, converged)
    };
    tape.eval(&x, &mut scratch, &mut out);
    // The size of f where the search starts: at an equilibrium at the origin the terms
    // themselves vanish, and f is judged against this instead.
    let start_scale: f64 = (0..n)
        .map(|i| {
            out[n + i]
                + (0..n)
                    .map(|j| (out[2 * n + i * n + j] * x[j]).abs())
                    .sum::<f64>()
        })
        .fold(0.0, f64::max);
    let mut lambda = 1e-9;
    for iteration in 0..200 {
        let (worst, converged) = residual(&out, &x);
        if converged || n == 0 || worst <= 1e-14 * start_scale {
            return Ok(Equilibrium {
                point: OperatingPoint::from_values(x, inputs),
                residual: worst,
                iterations: iteration,
            });
        }
        let fx = DVector::from_column_slice(&out[..n]);
        let j = DMatrix::from_row_slice(n, n, &out[2 * n..2 * n + n * n]);
        let cost = fx.norm_squared();
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
            let trial_cost: f64 = trial_out[..n].iter().map(|v| v * v).sum();
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
    if converged || worst <= 1e-14 * start_scale {
        return Ok(Equilibrium {
            point: OperatingPoint::from_values(x, inputs),
            residual: worst,
            iterations: 200,
        });
    }
    Err(EquilibriumError::NotFound {
        residual: worst,
        states: x,
        names: equations.states.iter().map(|s| s.name.clone()).collect(),
    })
}

fn exact(value: f64) -> bondgraph_core::symbolic::RatFunc {
    let text = format!("{:e}", value.abs());
    let magnitude = bondgraph_core::symbolic::RatFunc::from_decimal(&text)
        .unwrap_or_else(bondgraph_core::symbolic::RatFunc::zero);
    if value < 0.0 { -magnitude } else { magnitude }
}

/// The steady state a simulation of a nonlinear mode settles in: integrated over windows
/// that double until `f` stops changing (the change of `f` over a window would move the
/// state by less than 1e-9 of its size), so that steady motion (a constant drift) counts.
///
/// # Errors
/// As [`crate::steady::steady_state`].
pub fn steady_by_integration(
    mut stepper: Stepper<'_, '_>,
    settings: &SteadySettings,
) -> Result<Steady, SteadyError> {
    let mut window = 1e-3;
    loop {
        if stepper.time() > settings.max_time {
            return Err(SteadyError::NotSteady {
                t: stepper.time(),
                mode: stepper.mode().spec.clone(),
                why: "it had not settled".into(),
            });
        }
        let (u, rate) = stepper.inputs_at(stepper.time());
        let before = stepper.mode().derivative(stepper.state(), &u);
        let target = stepper.time() + window;
        if stepper.advance(target).map_err(SimError::into_steady)? {
            window = 1e-3;
            continue;
        }
        let mode = stepper.mode().clone();
        let x = stepper.state().to_vec();
        let after = mode.derivative(&x, &u);
        let change: f64 = before
            .iter()
            .zip(&after)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let size: f64 = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if change * window <= 1e-9 * size + 1e-300 {
            return Ok(Steady {
                outputs: mode.outputs.iter().map(|r| r.eval(&x, &u, &rate)).collect(),
                drift: mode
                    .outputs
                    .iter()
                    .map(|r| mode.row_rate(r, &x, &u, &rate))
                    .collect(),
                mode: mode.spec.clone(),
                time: stepper.time(),
                events: if settings.events {
                    stepper.events()
                } else {
                    Vec::new()
                },
            });
        }
        window *= 2.0;
    }
}

impl SimError {
    fn into_steady(self) -> SteadyError {
        SteadyError::Simulation(self)
    }
}
