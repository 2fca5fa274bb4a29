//! Steady states: where a trajectory settles for constant inputs.
//!
//! A steady state here is steady motion, not rest: a carriage pulled through a damper
//! settles at a constant velocity while its position (and the slack of a string that
//! trails it) keeps changing at a constant rate. So the search simulates from the given start until the current mode's
//! decaying components have died out (36 time constants of its slowest decaying eigenvalue:
//! `e^-36 ≈ 2e-16`), then takes the asymptote `x∞ + ẋ∞ τ` exactly from the modal form
//! ([`Propagator::asymptote`](crate::propagate::Propagator::asymptote)): no component may grow
//! or oscillate undamped, and no guard may cross zero along it in the future (a slack string
//! being taken up will tauten). A mode that grows or oscillates undamped is simulated until
//! a guard ends it (velocity weakening runs away until the contact slides), if one does. Otherwise it simulates on to the predicted crossing and looks
//! again. The outputs are read off the asymptote, not the last state, so a stiff mode's
//! rounding noise does not reach them.

pub mod continuation;
mod nonlinear;

use bondgraph_core::modes::Mode;
use num_complex::Complex64;

use crate::hybrid::{Event, Signal, SimError, Simulator, Stepper};
use crate::numeric::{NumericMode, dot};
use crate::ode::Tolerances;

/// How long a mode's decaying motion is waited for, in its slowest time constants:
/// `e^-36 ≈ 2e-16`, below the rounding of the state.
pub const SETTLING_TIME_CONSTANTS: f64 = 36.0;

/// Limits of a steady-state search: in the model's own time scales and in work, never in
/// seconds.
///
/// The search waits in each mode for [`SteadySettings::settling_time_constants`] of its
/// slowest decaying time constant ([`settling_horizon`]: of the linear mode's `A`, or of a
/// nonlinear mode's linearisation at the current state), and extends that while the state
/// still moves (a guard the steady motion will cross, a nonlinear rate still changing). What
/// bounds it is work: segments (each horizon, window or predicted crossing simulated),
/// mode changes, and the simulator's steps ([`crate::hybrid::Settings::max_steps`]).
#[derive(Clone, Copy, Debug)]
pub struct SteadySettings {
    /// The horizon in each mode, in its slowest decaying time constants.
    pub settling_time_constants: f64,
    /// Eigenvalues smaller than this in magnitude (1/s) are integrators (drift).
    pub zero_eigenvalue: f64,
    /// Give up after this many mode changes: a cycle (stick-slip) that has not settled by
    /// then will not.
    pub max_mode_changes: usize,
    /// Give up after simulating this many stretches (a mode's horizon, a window of a
    /// nonlinear mode, the way to a predicted crossing): a state that still moves after
    /// them does not settle in any time a measurement would wait.
    pub max_segments: usize,
    /// Whether [`Steady::events`] lists the events on the way (a fit needs only where the
    /// search settles, and wording thousands of events was a few percent of its time).
    pub events: bool,
    /// The integrator's tolerances in nonlinear modes while the search follows the
    /// transient ([`SEARCH_TOLERANCES`]); the simulator's own finish it.
    pub tolerances: Tolerances,
}

/// The integrator's tolerances while a steady-state search follows a nonlinear mode's
/// transient: relative 1e-6, a floor of 1e-14 (the simulator's
/// [`TOLERANCES`](crate::hybrid::TOLERANCES), 1e-10 and 1e-18, scaled alike).
///
/// The transient only has to carry the state into the basin of the equilibrium it settles
/// at and to the guards it crosses; the equilibrium itself is polished by Newton's method to
/// double precision, whatever the tolerance. A state that the search judges settled without
/// that polish (steady motion, a rate no longer changing) is followed for one more window at
/// the simulator's own tolerances, and read there. What the looser tolerance saves is mostly
/// the crawl of a state held at zero by a law with an infinite slope there (a tank pinned
/// empty by its orifice's `√p` while the pipe upstream starts to flow): its chatter around
/// zero is resolved to the floor in steps of microseconds. A steady row of the two-tank rig
/// filled from empty takes 561 steps at the simulator's tolerances (524 of them in the first
/// 4.4 s), 173 at 1e-7 and 1e-15, 112 at these.
pub const SEARCH_TOLERANCES: Tolerances = Tolerances {
    relative: 1e-6,
    absolute: 1e-14,
    peak_fraction: 1e-3,
};

impl Default for SteadySettings {
    fn default() -> Self {
        Self {
            settling_time_constants: SETTLING_TIME_CONSTANTS,
            zero_eigenvalue: 1e-9,
            max_mode_changes: 10_000,
            max_segments: 100_000,
            events: true,
            tolerances: SEARCH_TOLERANCES,
        }
    }
}

/// How long a mode with these eigenvalues takes to settle: `factor` times its slowest
/// decaying time constant `1/min(-Re λ)` over the eigenvalues with `Re λ < -zero`; `None`
/// when none decays (an integrator's drift, or growth, is not waited out).
///
/// A motor's 1 ms electrical mode beside its 30 s mechanical one settles on the 30 s one:
/// `36 × 30 s = 1080 s`.
pub fn settling_horizon(eigenvalues: &[Complex64], factor: f64, zero: f64) -> Option<f64> {
    let slowest = eigenvalues
        .iter()
        .filter(|v| v.re < -zero)
        .map(|v| -v.re)
        .fold(f64::INFINITY, f64::min);
    slowest.is_finite().then(|| factor / slowest)
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
    /// The energy variables of every storage element there (in the simulator's storage
    /// order); where the motion drifts, at [`Steady::time`].
    pub state: Vec<f64>,
    /// The work the search took.
    pub work: Work,
    /// The events on the way (none unless [`SteadySettings::events`]).
    pub events: Vec<Event>,
    /// Where it can be continued to nearby parameter values without simulating again
    /// ([`continuation`]): an isolated, stable equilibrium of a nonlinear mode, or the
    /// asymptote of a linear mode whose outputs read none of its integrators; path-dependent
    /// where the mode has guards or the search left a mode on the way; `None` otherwise.
    pub anchor: Option<continuation::Anchor>,
}

/// The work a steady-state search took, counted against its budgets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// Stretches simulated ([`SteadySettings::max_segments`]).
    pub segments: usize,
    /// The simulator's steps ([`crate::hybrid::Settings::max_steps`]): integration steps
    /// and event-location samples.
    pub steps: u64,
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
        /// The budget it ran out of, if that is why.
        exhausted: Option<Exhausted>,
    },
}

/// The budget a search ran out of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exhausted {
    /// [`SteadySettings::max_mode_changes`].
    ModeChanges,
    /// [`SteadySettings::max_segments`].
    Segments,
    /// The simulator's [`crate::hybrid::Settings::max_steps`].
    Steps,
}

impl std::fmt::Display for SteadyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SteadyError::Simulation(e) => write!(f, "{e}"),
            SteadyError::NotSteady { t, mode, why, .. } => {
                // In exponent form where decimals would run to dozens of digits.
                let t = if *t != 0.0 && (t.abs() < 1e-4 || t.abs() >= 1e16) {
                    format!("{t:e}")
                } else {
                    t.to_string()
                };
                write!(
                    f,
                    "no steady state by t = {t} s in {}: {why}",
                    mode_text(mode)
                )
            }
        }
    }
}

impl std::error::Error for SteadyError {}

/// `mode SPEC`, or `the model's only mode` for a model without switching elements (whose
/// mode's specification is empty).
pub fn mode_text(spec: &str) -> String {
    if spec.is_empty() {
        "the model's only mode".to_string()
    } else {
        format!("mode {spec}")
    }
}

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
/// [`SteadyError`] when the simulation fails, or does not settle within the work
/// `settings` and the simulator's steps allow (naming the mode, the time reached and the
/// state that still moves).
pub fn steady_state(
    simulator: &mut Simulator<'_>,
    inputs: &[f64],
    initial_mode: Mode,
    initial_state: Vec<f64>,
    settings: &SteadySettings,
) -> Result<Steady, SteadyError> {
    let own = simulator.settings().tolerances;
    simulator.set_tolerances(settings.tolerances);
    let steady = search_from(
        simulator,
        inputs,
        initial_mode,
        initial_state,
        settings,
        own,
    );
    simulator.set_tolerances(own);
    steady
}

/// [`steady_state`], with the simulator integrating to the search's tolerances and `own`
/// the simulator's own, which finish a state settled without a polish.
fn search_from(
    simulator: &mut Simulator<'_>,
    inputs: &[f64],
    initial_mode: Mode,
    initial_state: Vec<f64>,
    settings: &SteadySettings,
    own: Tolerances,
) -> Result<Steady, SteadyError> {
    let constants: Vec<Constant> = inputs.iter().map(|&u| Constant(u)).collect();
    let signals: Vec<&dyn Signal> = constants.iter().map(|c| c as &dyn Signal).collect();
    let mut stepper = Stepper::new(simulator, &signals, initial_mode, initial_state, None)?;
    let mut search = Search::new(settings);
    // A mode whose events come ever closer together (Zeno) can stop the clock: steps below
    // the spacing of doubles at the current time. Say so rather than loop.
    let mut last_time = f64::NEG_INFINITY;
    let mut stalls = 0;
    loop {
        search.within_budget(&stepper)?;
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
            return nonlinear::steady_by_integration(stepper, settings, own);
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
                settings.settling_time_constants / v.re
            } else {
                4.0 * std::f64::consts::TAU / v.im.abs()
            };
            let target = stepper.time() + horizon;
            if search.advance(&mut stepper, target)? {
                continue;
            }
            return Err(not_steady(
                &stepper,
                format!("its motion has an eigenvalue {v} that does not decay"),
            ));
        }
        let horizon = settling_horizon(
            values,
            settings.settling_time_constants,
            settings.zero_eigenvalue,
        )
        .unwrap_or(0.0);
        let target = stepper.time() + horizon;
        if horizon > 0.0 && search.advance(&mut stepper, target)? {
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
        let next_crossing = next_crossing(&mode, &x, &u, &rate, &drift);
        if next_crossing.is_finite() {
            // Go past the predicted crossing; the event stops the advance where it happens.
            let step = (2.0 * next_crossing).max(horizon);
            let target = stepper.time() + step;
            search.advance(&mut stepper, target)?;
            continue;
        }
        let time = stepper.time();
        return Ok(Steady {
            work: search.work(&stepper),
            anchor: continuation::linear_anchor(
                &mode,
                &x,
                &u,
                &rate,
                time,
                stepper.event_count() > 0,
                settings,
            ),
            events: if settings.events {
                stepper.into_events()
            } else {
                Vec::new()
            },
            ..on_asymptote(&mode, &x, &u, &rate, &drift, time)
        });
    }
}

/// How long the steady motion `x + drift τ` of a linear mode takes to reach a guard
/// (infinite if it never does). No guard may be reached along the asymptote: a steady
/// motion still moving towards one will cross it, and the search follows it there, however
/// far (within its budget of segments). Along a straight line only a guard below zero and
/// rising can ever fire. A drift of rounding size does not move: a body at rest whose rate
/// is `1e-13` where its terms are `1e3` would reach a guard after `1e40` s, and then cycle.
/// So a slope counts only above [`ROUNDING`] of the size of the terms it is made of
/// ([`NumericMode::row_rate_magnitude`], as event location
/// judges a rate `≈ 0`).
pub(super) fn next_crossing(
    mode: &NumericMode,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
    drift: &[f64],
) -> f64 {
    let mut next = f64::INFINITY;
    for guard in &mode.guards {
        let value = guard.row.eval(x, u, rate);
        let slope = dot(&guard.row.state, drift);
        let size = mode.row_rate_magnitude(&guard.row, x, u, rate);
        if slope > ROUNDING * size && value < 0.0 {
            next = next.min(-value / slope);
        }
    }
    next
}

/// The steady state of a linear mode on its asymptote `x + drift τ`, judged reached at
/// `time`: the outputs read off the asymptote (not the last state, so a stiff mode's
/// rounding noise does not reach them) with their drift ([`read_at`]).
pub(super) fn on_asymptote(
    mode: &NumericMode,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
    drift: &[f64],
    time: f64,
) -> Steady {
    let drift = mode
        .outputs
        .iter()
        .map(|row| dot(&row.state, drift))
        .collect();
    read_at(mode, x, u, rate, drift, time)
}

/// The steady state `x` of `mode` at inputs `u` (rates `rate`), judged reached at `time`:
/// the outputs read at `x` with their rates `drift`, the full state rebuilt; no work,
/// events or anchor (the caller adds its own).
pub(super) fn read_at(
    mode: &NumericMode,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
    drift: Vec<f64>,
    time: f64,
) -> Steady {
    Steady {
        outputs: mode
            .outputs
            .iter()
            .map(|row| row.eval(x, u, rate))
            .collect(),
        drift,
        mode: mode.spec.clone(),
        time,
        state: mode.reconstruct(x, u),
        work: Work::default(),
        events: Vec::new(),
        anchor: None,
    }
}

/// A slope of a guard along the drift below this fraction of the size of the terms of the
/// rates it is made of is rounding (the fraction [`crate::hybrid`] takes for a value at its
/// threshold).
const ROUNDING: f64 = 1e-9;

/// The work a search has done against its budget.
pub(crate) struct Search<'a> {
    settings: &'a SteadySettings,
    segments: usize,
}

impl<'a> Search<'a> {
    pub(crate) fn new(settings: &'a SteadySettings) -> Self {
        Self {
            settings,
            segments: 0,
        }
    }

    /// The work done so far.
    pub(crate) fn work(&self, stepper: &Stepper<'_, '_>) -> Work {
        Work {
            segments: self.segments,
            steps: stepper.steps(),
        }
    }

    /// An error when the search has used its budget of mode changes.
    pub(crate) fn within_budget(&self, stepper: &Stepper<'_, '_>) -> Result<(), SteadyError> {
        if stepper.event_count() > self.settings.max_mode_changes {
            return Err(exhausted(
                stepper,
                Exhausted::ModeChanges,
                format!(
                    "it changed mode more than {} times without settling",
                    self.settings.max_mode_changes
                ),
            ));
        }
        Ok(())
    }

    /// Simulates one more stretch, to `target`: whether a mode changed on the way. The
    /// budget of segments or of the simulator's steps spent is a [`SteadyError::NotSteady`]
    /// that names the state still moving.
    pub(crate) fn advance(
        &mut self,
        stepper: &mut Stepper<'_, '_>,
        target: f64,
    ) -> Result<bool, SteadyError> {
        self.segments += 1;
        if self.segments > self.settings.max_segments {
            return Err(exhausted(
                stepper,
                Exhausted::Segments,
                format!(
                    "it had not settled after its budget of {} segments; {}",
                    self.settings.max_segments,
                    still_moving(stepper)
                ),
            ));
        }
        match stepper.advance(target) {
            Ok(switched) => Ok(switched),
            Err(SimError::TooManySteps { limit, .. }) => Err(exhausted(
                stepper,
                Exhausted::Steps,
                format!(
                    "it had not settled after its budget of {limit} steps; {}",
                    still_moving(stepper)
                ),
            )),
            Err(error) => Err(error.into()),
        }
    }
}

/// The search's give-up: at the stepper's time, in its mode.
pub(crate) fn not_steady(stepper: &Stepper<'_, '_>, why: String) -> SteadyError {
    SteadyError::NotSteady {
        t: stepper.time(),
        mode: stepper.mode().spec.clone(),
        why,
        exhausted: None,
    }
}

/// The search's give-up at a budget: [`not_steady`] with the budget named.
fn exhausted(stepper: &Stepper<'_, '_>, budget: Exhausted, why: String) -> SteadyError {
    let mut error = not_steady(stepper, why);
    if let SteadyError::NotSteady { exhausted, .. } = &mut error {
        *exhausted = Some(budget);
    }
    error
}

/// Which state still moves, in words: the one whose rate is largest against its own size
/// (`|ẋᵢ| / |xᵢ|`, so that states in different units compare), with that rate.
pub(crate) fn still_moving(stepper: &Stepper<'_, '_>) -> String {
    let mode = stepper.mode();
    let (u, _) = stepper.inputs_at(stepper.time());
    let x = stepper.state();
    let rates = mode.derivative(x, &u);
    let relative = |i: usize| {
        let r = rates[i].abs();
        if x[i] == 0.0 { r } else { r / x[i].abs() }
    };
    match (0..rates.len())
        .filter(|&i| rates[i].is_finite() && rates[i] != 0.0)
        .max_by(|&a, &b| relative(a).total_cmp(&relative(b)))
    {
        Some(i) => format!(
            "'{}' still moves (at {:e} per second, at {:e})",
            mode.state_names[i], rates[i], x[i]
        ),
        None => "no state moves at the end (the last stretch ended at a mode change)".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A motor's 1 ms electrical mode beside a 30 s mechanical one: the horizon is 36 of the
    /// slow time constant, 36 × 30 s = 1080 s, not 36 ms; an integrator (λ = 0) and a
    /// rounding-size rate are not waited for.
    #[test]
    fn the_settling_horizon_is_set_by_the_slowest_decaying_mode() {
        let values = [
            Complex64::new(-1.0 / 30.0, 0.0),
            Complex64::new(-1000.0, 0.0),
            Complex64::new(0.0, 0.0),
            Complex64::new(-1e-12, 0.0),
        ];
        let horizon = settling_horizon(&values, SETTLING_TIME_CONSTANTS, 1e-9).unwrap();
        assert!((horizon - 1080.0).abs() < 1e-9, "{horizon}");
        // An oscillation decaying at 0.5 /s (period aside): 36 / 0.5 = 72 s.
        let swinging = [Complex64::new(-0.5, 3.0), Complex64::new(-0.5, -3.0)];
        assert_eq!(settling_horizon(&swinging, 36.0, 1e-9), Some(72.0));
        assert_eq!(
            settling_horizon(&[Complex64::new(0.0, 0.0)], 36.0, 1e-9),
            None
        );
    }

    #[test]
    fn a_model_without_switching_is_named_in_words() {
        assert_eq!(mode_text(""), "the model's only mode");
        assert_eq!(mode_text("fr=stuck"), "mode fr=stuck");
        let error = SteadyError::NotSteady {
            t: 2.5,
            mode: String::new(),
            why: "it had not settled".into(),
            exhausted: None,
        };
        assert_eq!(
            error.to_string(),
            "no steady state by t = 2.5 s in the model's only mode: it had not settled"
        );
    }
}
