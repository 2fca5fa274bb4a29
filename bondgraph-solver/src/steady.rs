//! Steady states: where a trajectory settles for constant inputs.
//!
//! A steady state here is steady motion, not rest: a growing robot's tip settles at a
//! constant velocity while the slack length of its inner structure keeps changing at a
//! constant rate. So the search simulates from the given start until the current mode's
//! decaying components have died out (36 time constants of its slowest decaying eigenvalue:
//! `e^-36 ≈ 2e-16`), then takes the asymptote `x∞ + ẋ∞ τ` exactly from the modal form
//! ([`Propagator::asymptote`](crate::propagate::Propagator::asymptote)): no component may grow
//! or oscillate undamped, and no guard may cross zero along it in the future (a slack string
//! being taken up will tauten). A mode that grows or oscillates undamped is simulated until
//! a guard ends it (velocity weakening runs away until the contact slides), if one does. Otherwise it simulates on to the predicted crossing and looks
//! again. The outputs are read off the asymptote, not the last state, so a stiff mode's
//! rounding noise does not reach them.

use bondgraph_core::modes::Mode;

use crate::hybrid::{Event, Signal, SimError, Simulator, Stepper};
use crate::numeric::dot;

/// Limits of a steady-state search.
#[derive(Clone, Copy, Debug)]
pub struct SteadySettings {
    /// Give up after this much simulated time, in seconds; guard crossings predicted beyond
    /// it are ignored.
    pub max_time: f64,
    /// Eigenvalues smaller than this in magnitude (1/s) are integrators (drift).
    pub zero_eigenvalue: f64,
    /// Give up after this many mode changes: a cycle (stick-slip) that has not settled by
    /// then will not, and simulating it to `max_time` can take minutes.
    pub max_mode_changes: usize,
    /// Whether [`Steady::events`] lists the events on the way (a fit needs only where the
    /// search settles, and wording thousands of events was a few percent of its time).
    pub events: bool,
}

impl Default for SteadySettings {
    fn default() -> Self {
        Self {
            max_time: 1.0e4,
            zero_eigenvalue: 1e-9,
            max_mode_changes: 10_000,
            events: true,
        }
    }
}

/// A steady state found.
#[derive(Clone, Debug)]
pub struct Steady {
    /// The requested outputs at the steady state.
    pub outputs: Vec<f64>,
    /// Their constant rates of change there (zero for a velocity in steady motion).
    pub drift: Vec<f64>,
    /// The mode it settles in.
    pub mode: String,
    /// When it was judged settled.
    pub time: f64,
    /// The events on the way (none unless [`SteadySettings::events`]).
    pub events: Vec<Event>,
}

/// Why no steady state was found.
#[derive(Clone, Debug)]
pub enum SteadyError {
    /// The simulation failed.
    Simulation(SimError),
    /// It did not settle.
    NotSteady {
        /// When the search gave up.
        t: f64,
        /// The mode it was in.
        mode: String,
        /// Why.
        why: String,
    },
}

impl std::fmt::Display for SteadyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SteadyError::Simulation(e) => write!(f, "{e}"),
            SteadyError::NotSteady { t, mode, why } => {
                write!(f, "no steady state by t = {t} s in mode {mode}: {why}")
            }
        }
    }
}

impl std::error::Error for SteadyError {}

impl From<SimError> for SteadyError {
    fn from(error: SimError) -> Self {
        SteadyError::Simulation(error)
    }
}

struct Constant(f64);

impl Signal for Constant {
    fn value(&self, _: f64) -> f64 {
        self.0
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

/// Steps in a row that do not advance time before the search gives up.
const STALLS_BEFORE_ZENO: usize = 1000;

/// The steady state reached from `initial_state` in `initial_mode` with constant `inputs`.
///
/// # Errors
/// [`SteadyError`] when the simulation fails or does not settle by `settings.max_time`.
pub fn steady_state(
    simulator: &mut Simulator<'_>,
    inputs: &[f64],
    initial_mode: Mode,
    initial_state: Vec<f64>,
    settings: &SteadySettings,
) -> Result<Steady, SteadyError> {
    let constants: Vec<Constant> = inputs.iter().map(|&u| Constant(u)).collect();
    let signals: Vec<&dyn Signal> = constants.iter().map(|c| c as &dyn Signal).collect();
    let mut stepper = Stepper::new(simulator, &signals, initial_mode, initial_state, None)?;
    let not_steady = |stepper: &Stepper<'_, '_>, why: String| SteadyError::NotSteady {
        t: stepper.time(),
        mode: stepper.mode().spec.clone(),
        why,
    };
    // A mode whose events come ever closer together (Zeno) can stop the clock: steps below
    // the spacing of doubles at the current time. Say so rather than loop.
    let mut last_time = f64::NEG_INFINITY;
    let mut stalls = 0;
    loop {
        if stepper.time() > settings.max_time {
            return Err(not_steady(&stepper, "it had not settled".into()));
        }
        if stepper.event_count() > settings.max_mode_changes {
            return Err(not_steady(
                &stepper,
                format!(
                    "it changed mode more than {} times without settling",
                    settings.max_mode_changes
                ),
            ));
        }
        if stepper.time() > last_time {
            last_time = stepper.time();
            stalls = 0;
        } else {
            stalls += 1;
            if stalls > STALLS_BEFORE_ZENO {
                return Err(not_steady(
                    &stepper,
                    format!(
                        "time stopped advancing: {STALLS_BEFORE_ZENO} steps without progress (Zeno behaviour)"
                    ),
                ));
            }
        }
        let mode = stepper.mode().clone();
        if mode.nonlinear.is_some() {
            return crate::equilibrium::steady_by_integration(stepper, settings);
        }
        let values = mode.propagator.eigenvalues();
        if let Some(v) = values.iter().find(|v| {
            v.re > settings.zero_eigenvalue
                || (v.re.abs() <= settings.zero_eigenvalue && v.im.abs() > settings.zero_eigenvalue)
        }) {
            // A mode that grows (a contact whose friction weakens faster than viscosity
            // grows) or oscillates undamped is no steady state, but a guard may end it: give
            // it 36 e-foldings of its growth (or four periods) to do so.
            let horizon = if v.re > settings.zero_eigenvalue {
                36.0 / v.re
            } else {
                4.0 * std::f64::consts::TAU / v.im.abs()
            };
            let target = stepper.time() + horizon;
            if target <= settings.max_time && stepper.advance(target)? {
                continue;
            }
            return Err(not_steady(
                &stepper,
                format!("its motion has an eigenvalue {v} that does not decay"),
            ));
        }
        let slowest = values
            .iter()
            .filter(|v| v.re < -settings.zero_eigenvalue)
            .map(|v| -v.re)
            .fold(f64::INFINITY, f64::min);
        let horizon = if slowest.is_finite() {
            36.0 / slowest
        } else {
            0.0
        };
        let target = stepper.time() + horizon;
        if horizon > 0.0 && stepper.advance(target)? {
            continue; // an event: a new mode, look again
        }
        let (u, rate) = stepper.inputs_at(stepper.time());
        let Some((x, drift)) =
            mode.propagator
                .asymptote(stepper.state(), &u, settings.zero_eigenvalue)
        else {
            return Err(not_steady(
                &stepper,
                "its matrix is defective, so its asymptote is not known".into(),
            ));
        };
        // No guard may be reached along the asymptote.
        // Along a straight line only a guard below zero and rising can ever fire.
        let mut next_crossing = f64::INFINITY;
        for guard in &mode.guards {
            let value = guard.row.eval(&x, &u, &rate);
            let slope = dot(&guard.row.state, &drift);
            if slope > 0.0 && value < 0.0 {
                next_crossing = next_crossing.min(-value / slope);
            }
        }
        // A crossing predicted beyond the search horizon (from a slope of rounding size, say)
        // does not change the regime.
        if next_crossing.is_finite() && stepper.time() + next_crossing <= settings.max_time {
            // Go past the predicted crossing; the event stops the advance where it happens.
            let step = (2.0 * next_crossing).max(horizon);
            stepper.advance(stepper.time() + step)?;
            continue;
        }
        let outputs = mode
            .outputs
            .iter()
            .map(|row| row.eval(&x, &u, &rate))
            .collect();
        let drift_outputs = mode
            .outputs
            .iter()
            .map(|row| dot(&row.state, &drift))
            .collect();
        return Ok(Steady {
            outputs,
            drift: drift_outputs,
            mode: mode.spec.clone(),
            time: stepper.time(),
            events: if settings.events {
                stepper.into_events()
            } else {
                Vec::new()
            },
        });
    }
}
