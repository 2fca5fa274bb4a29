//! The hybrid simulation loop: modes, events, and the checks between them.
//!
//! Time is cut into segments where the mode is fixed and the inputs are linear; each segment
//! is propagated exactly from its own local time zero ([`crate::propagate`]) and ends at the
//! next input breakpoint or at the first guard crossing ([`crate::events`]). At an event the
//! full physical state is rebuilt from the old mode, the switching element changes mode, and
//! the new mode is checked for consistency *at that instant*: a guard of the new mode that is
//! already satisfied and moving further in (a contact that sticks while the force exceeds its
//! breakaway force, a string that tautens while being shortened) switches again, until a mode
//! holds. A switch to `stuck` happens only if static friction can hold in that mode.
//!
//! Numerical trouble is reported rather than ground through: a cycle of switches at one
//! instant (no consistent mode), many events in a short time (chattering, Zeno behaviour),
//! and states that are no longer finite, each naming the elements involved.

use std::collections::{HashMap, VecDeque};
use std::fmt;
use std::sync::Arc;

use bondgraph_core::diagnostics::{DiagnosticKind, Diagnostics};
use bondgraph_core::equations::{Options, OutputSpec};
use bondgraph_core::guards::Watched;
use bondgraph_core::model::{ElementId, ElementMode, Model};
use bondgraph_core::modes::{Mode, ModeCache};
use bondgraph_core::scenario::Book;

use crate::energy::{EnergyBalance, EnergyColumn, Increment, SegmentBooks};
use crate::events;

mod combinations;
mod crossing;
mod integrate;
mod recorder;
mod sample_times;
mod stall;
mod step_guards;
mod time_scale;
mod trajectory;
use crate::numeric::{ModeForms, NumericGuard, NumericMode, Storage, dot};
use crate::propagate::SegmentBuffers;
use crossing::{Crossed, Trigger};
use num_complex::Complex64;
use recorder::{Recorded, Recorder, Switched, Why};
use sample_times::SampleTimes;
pub use stall::{STALLED_SEGMENTS, Stall};
pub use time_scale::TimeScale;
pub use trajectory::{Event, Stats, Trajectory};

/// A time-varying input, piecewise linear between its breakpoints.
pub trait Signal {
    /// The value at time `t` (right-continuous at breakpoints).
    fn value(&self, t: f64) -> f64;
    /// The rate of change just after `t`.
    fn rate(&self, t: f64) -> f64;
    /// The times where the value or the rate changes abruptly.
    fn breakpoints(&self) -> Vec<f64>;
}

/// An output to record: a bond variable, or its integral over time (a displacement).
#[derive(Clone, Debug)]
pub struct Output {
    /// Its name, as the user wrote it.
    pub name: String,
    /// The bond variable.
    pub spec: OutputSpec,
    /// Whether to record its time integral.
    pub integral: bool,
}

/// Limits that turn numerical trouble into errors.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// The most events a run may have (by default
    /// [`bondgraph_core::limits::MAX_EVENTS`]).
    pub max_events: usize,
    /// The most steps a run may take: integration steps (each attempt, and each exact step
    /// that lands on an event) plus event-location samples (by default
    /// [`bondgraph_core::limits::MAX_STEPS`], a few seconds of work).
    pub max_steps: u64,
    /// This many events within `chatter_window` times the current time (at least one
    /// second) is chattering (Zeno behaviour).
    pub chatter_events: usize,
    /// See `chatter_events`.
    pub chatter_window: f64,
    /// `chatter_events` events in a row with the inputs steady (no breakpoint among them),
    /// closer on average than this many of the fastest time scale of the (linear) modes they
    /// entered, is chattering too: switching faster than the motion can move.
    pub chatter_time_scales: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_events: bondgraph_core::limits::MAX_EVENTS,
            max_steps: bondgraph_core::limits::MAX_STEPS,
            chatter_events: 200,
            chatter_window: 1e-6,
            chatter_time_scales: 1.0,
        }
    }
}

/// One run: inputs, initial condition, duration.
pub struct Run<'a> {
    /// One signal per model input, in the model's order.
    pub inputs: &'a [&'a dyn Signal],
    /// The mode to start in (made consistent at time zero).
    pub initial_mode: Mode,
    /// The full state at time zero: energy variables of the storage elements.
    pub initial_state: Vec<f64>,
    /// How long to simulate, in seconds.
    pub duration: f64,
    /// The output interval (`None`: a thousand samples).
    pub sample: Option<f64>,
    /// Whether to keep the energy books ([`Trajectory::energy`]): closed-form integrals over
    /// each segment (and between samples when the books are recorded).
    pub audit_energy: bool,
}

/// Why a simulation stopped.
#[derive(Clone, Debug)]
pub enum SimError {
    /// A mode could not be derived.
    Derivation(Diagnostics),
    /// The inputs do not match the model.
    Inputs(String),
    /// No mode is consistent at this instant.
    NoConsistentMode {
        /// When.
        t: f64,
        /// The modes tried, in order.
        tried: Vec<String>,
        /// The elements that kept switching.
        elements: Vec<String>,
    },
    /// Too many events in too short a time.
    Chattering {
        /// When it was detected.
        t: f64,
        /// How many events.
        events: usize,
        /// Over how long.
        window: f64,
        /// The elements that switched.
        elements: Vec<String>,
        /// Why the last of them switched (the quantity at its threshold).
        reason: String,
        /// The fastest time scale of the modes entered, when the events came faster than
        /// it with the inputs steady.
        time_scale: Option<f64>,
    },
    /// No single switch is consistent, and the modes of the elements that kept switching
    /// have more combinations than the search may derive.
    TooManyCombinations {
        /// When.
        t: f64,
        /// The elements that kept switching.
        elements: Vec<String>,
        /// How many combinations, in words.
        combinations: String,
        /// The limit.
        limit: usize,
    },
    /// More events than allowed.
    TooManyEvents {
        /// When.
        t: f64,
        /// The limit.
        limit: usize,
    },
    /// More steps than allowed (integration steps and event-location samples).
    TooManySteps {
        /// The time reached.
        t: f64,
        /// The limit.
        limit: u64,
        /// The last integration step's length, on the integrated path.
        step: Option<f64>,
        /// The fastest time scale of the mode there.
        time_scale: Option<TimeScale>,
    },
    /// Time stopped advancing: integration steps under the resolution of time at `t`, or
    /// segments that ended where they began.
    Stalled {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// What was seen.
        cause: Stall,
    },
    /// A recorded output became infinite or not a number, the states still finite (a
    /// velocity near the largest double times a gain).
    NonFiniteOutput {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// The outputs concerned.
        outputs: Vec<String>,
    },
    /// A state became infinite or not a number.
    NonFinite {
        /// When.
        t: f64,
        /// The mode.
        mode: String,
        /// The states concerned.
        states: Vec<String>,
    },
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Derivation(d) => write!(f, "{d}"),
            SimError::Inputs(message) => write!(f, "{message}"),
            SimError::NoConsistentMode { t, tried, elements } => write!(
                f,
                "at t = {} s no mode is consistent: switching {} cycles through {}",
                At(*t),
                quoted(elements),
                tried.join(" -> ")
            ),
            SimError::Chattering {
                t,
                events,
                window,
                elements,
                reason,
                time_scale,
            } => {
                write!(
                    f,
                    "chattering at t = {} s: {events} events in {window:e} s",
                    At(*t)
                )?;
                if let Some(scale) = time_scale {
                    write!(
                        f,
                        " with the inputs steady, faster than the modes' fastest time scale \
                         ({scale:e} s)"
                    )?;
                }
                write!(f, ", switching {} (the last: {reason})", quoted(elements))
            }
            SimError::Stalled { t, mode, cause } => write!(
                f,
                "time stopped advancing at t = {} s{}: {cause}",
                At(*t),
                in_mode(mode)
            ),
            SimError::TooManyCombinations {
                t,
                elements,
                combinations,
                limit,
            } => write!(
                f,
                "at t = {} s no single switch is consistent, and the modes of {} combine in {combinations} ways, over the limit of {limit} searched",
                At(*t),
                quoted(elements)
            ),
            SimError::TooManyEvents { t, limit } => {
                write!(f, "more than {limit} events by t = {} s", At(*t))
            }
            SimError::TooManySteps {
                t,
                limit,
                step,
                time_scale,
            } => {
                write!(
                    f,
                    "more than {limit} steps (integration steps and event-location samples) by t = {} s",
                    At(*t)
                )?;
                if let Some(step) = step {
                    write!(f, ", the last {step:e} s long")?;
                }
                write!(f, ": the duration is too long for the model's time scales")?;
                match time_scale {
                    Some(scale) => write!(f, " (the fastest there: {scale})"),
                    None => Ok(()),
                }
            }
            SimError::NonFiniteOutput { t, mode, outputs } => write!(
                f,
                "at t = {} s in mode {mode} the outputs {} are no longer finite",
                At(*t),
                quoted(outputs)
            ),
            SimError::NonFinite { t, mode, states } => write!(
                f,
                "at t = {} s in mode {mode} the states {} are no longer finite",
                At(*t),
                quoted(states)
            ),
        }
    }
}

impl std::error::Error for SimError {}

/// A time in a message: as a decimal, or in exponent form when that would run to dozens of
/// digits (a run stopped at 6e-256 s).
struct At(f64);

impl fmt::Display for At {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.0;
        if t != 0.0 && (t.abs() < 1e-4 || t.abs() >= 1e16) {
            write!(f, "{t:e}")
        } else {
            write!(f, "{t}")
        }
    }
}

/// ` in mode SPEC`, or nothing for a model without switching (whose mode is empty).
fn in_mode(mode: &str) -> String {
    if mode.is_empty() {
        String::new()
    } else {
        format!(" in mode {mode}")
    }
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("'{n}'"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Modes looked up by value, hashed fast (a fit looks one up at every event): the keys are
/// the model's own modes, never an adversary's.
type ModeMap<V> = HashMap<Mode, V, foldhash::fast::FixedState>;

/// Simulates one model: caches its modes across runs.
pub struct Simulator<'m> {
    model: &'m Model,
    storage: Storage,
    outputs: Vec<Output>,
    /// The parameter values substituted, indexed like [`Model::values`].
    values: Vec<f64>,
    symbolic: ModeCache<'m>,
    /// Each linear mode's symbolic pieces, kept when the parameter values change.
    forms: ModeMap<Arc<ModeForms>>,
    /// Each mode with the current values in.
    numeric: ModeMap<Arc<NumericMode>>,
    settings: Settings,
    /// Energies recorded after the outputs, by name.
    energy_columns: Vec<(String, EnergyColumn)>,
    /// Event location's buffers, kept from segment to segment and run to run.
    scratch: events::Scratch,
    /// The last segment's vectors, for the next.
    segment_buffers: SegmentBuffers,
}

impl<'m> Simulator<'m> {
    /// A simulator of `model` recording `outputs`.
    pub fn new(model: &'m Model, outputs: Vec<Output>) -> Self {
        Self {
            model,
            storage: Storage::of(model),
            outputs,
            values: model.values.clone(),
            symbolic: ModeCache::new(model, Options::default()),
            forms: ModeMap::default(),
            numeric: ModeMap::default(),
            settings: Settings::default(),
            energy_columns: Vec::new(),
            scratch: events::Scratch::default(),
            segment_buffers: SegmentBuffers::default(),
        }
    }

    /// Records these energies, by name, after the outputs at every sample: the
    /// trajectory's columns are the outputs' and then these. Columns of the supplied or
    /// dissipated book keep the books whether or not the run audits energy.
    pub fn with_energy_columns(mut self, columns: Vec<(String, EnergyColumn)>) -> Self {
        self.energy_columns = columns;
        self
    }

    /// The energies at a state of `mode`; `books` is `(supplied, dissipated)` so far.
    fn energy_values(
        &self,
        mode: &NumericMode,
        x: &[f64],
        u: &[f64],
        books: (f64, f64),
    ) -> impl Iterator<Item = f64> + use<'_> {
        let full = if self.energy_columns.is_empty() {
            Vec::new()
        } else {
            mode.reconstruct(x, u)
        };
        self.energy_columns
            .iter()
            .map(move |(_, column)| match column {
                EnergyColumn::Element(id) => self.storage.index(*id).map_or(f64::NAN, |i| {
                    NumericMode::element_energy(&self.storage, self.model, i, full[i])
                }),
                EnergyColumn::Book(Book::Stored) => {
                    NumericMode::stored_energy(&self.storage, self.model, &full)
                }
                EnergyColumn::Book(Book::Supplied) => books.0,
                EnergyColumn::Book(Book::Dissipated) => books.1,
            })
    }

    /// Replaces the limits on numerical trouble.
    pub fn with_settings(mut self, settings: Settings) -> Self {
        self.settings = settings;
        self
    }

    /// Substitutes other parameter values (indexed like [`Model::values`]) from now on,
    /// keeping the symbolic modes derived so far: the fast path of a calibration, which
    /// changes numbers but never the structure.
    ///
    /// # Errors
    /// [`SimError::Inputs`] when `values` does not have one value per parameter of the model.
    pub fn set_parameter_values(&mut self, values: &[f64]) -> Result<(), SimError> {
        if values.len() != self.model.values.len() {
            return Err(SimError::Inputs(format!(
                "{} parameter values given, but model '{}' has {} parameters",
                values.len(),
                self.model.name,
                self.model.values.len()
            )));
        }
        if values != self.values.as_slice() {
            self.values = values.to_vec();
            self.storage = Storage::with_values(self.model, values);
            self.numeric.clear();
        }
        Ok(())
    }

    /// The parameter values substituted, indexed like [`Model::values`].
    pub fn parameter_values(&self) -> &[f64] {
        &self.values
    }

    /// The storage elements making up the full state.
    pub fn storage(&self) -> &Storage {
        &self.storage
    }

    /// The model simulated.
    pub fn model(&self) -> &'m Model {
        self.model
    }

    /// The numeric form of `mode`, derived on first use; a contact said to creep whose
    /// Stribeck velocity is zero with the values substituted slips instead
    /// ([`Mode::at_values`]).
    ///
    /// # Errors
    /// [`SimError::Derivation`] if the mode cannot be derived.
    pub fn mode(&mut self, mode: &Mode) -> Result<Arc<NumericMode>, SimError> {
        if let Some(numeric) = self.numeric.get(mode) {
            return Ok(numeric.clone());
        }
        let bound = mode.at_values(self.model, &self.values);
        if bound != *mode {
            let numeric = self.mode(&bound)?;
            self.numeric.insert(mode.clone(), numeric.clone());
            return Ok(numeric);
        }
        if self.model.is_nonlinear() {
            let numeric = Arc::new(integrate::numeric_mode(self, mode)?);
            self.numeric.insert(mode.clone(), numeric.clone());
            return Ok(numeric);
        }
        let forms = match self.forms.get(mode) {
            Some(forms) => forms.clone(),
            None => {
                let derived = self.symbolic.get(mode).map_err(SimError::Derivation)?;
                let outputs: Vec<_> = self
                    .outputs
                    .iter()
                    .map(|o| derived.equations.output(&o.spec).row)
                    .collect();
                let forms = Arc::new(ModeForms::new(self.model, &derived, &outputs));
                self.forms.insert(mode.clone(), forms.clone());
                forms
            }
        };
        let numeric = Arc::new(NumericMode::from_forms(&forms, &self.values, &self.storage));
        self.numeric.insert(mode.clone(), numeric.clone());
        Ok(numeric)
    }

    /// Runs a simulation.
    ///
    /// # Errors
    /// [`SimError`] on inputs that do not match the model, modes that cannot be derived, no
    /// consistent mode, chattering, or non-finite states.
    pub fn run(&mut self, run: &Run<'_>) -> Result<Trajectory, SimError> {
        if !(run.duration > 0.0 && run.duration.is_finite()) {
            return Err(SimError::Inputs(format!(
                "the duration must be positive and finite, not {}",
                run.duration
            )));
        }
        let sample = run
            .sample
            .filter(|s| *s > 0.0 && s.is_finite())
            .unwrap_or(run.duration / 1000.0);
        let books = self.energy_columns.iter().any(|(_, c)| c.needs_books());
        let count = bondgraph_core::limits::sample_count(run.duration, sample);
        if count > bondgraph_core::limits::MAX_SAMPLES as f64 {
            return Err(SimError::Inputs(format!(
                "{} s sampled every {sample} s is {} samples, over the limit of {}",
                run.duration,
                bondgraph_core::limits::count_in_words(count),
                bondgraph_core::limits::MAX_SAMPLES
            )));
        }
        let mut stepper = Stepper::new(
            self,
            run.inputs,
            run.initial_mode.clone(),
            run.initial_state.clone(),
            Some(sample),
        )?;
        stepper.sample = stepper.sample.map(|times| times.ending_at(run.duration));
        if run.audit_energy || books {
            stepper.audit_energy();
        }
        while stepper.time() < run.duration {
            stepper.advance(run.duration)?;
        }
        let mut trajectory = stepper.finish();
        if !run.audit_energy && !books {
            trajectory.energy = None;
        }
        Ok(trajectory)
    }

    /// Output values at a state; integrals add `∫` over the segment so far.
    #[allow(clippy::too_many_arguments)]
    fn output_values(
        &self,
        mode: &NumericMode,
        x: &[f64],
        u: &[f64],
        rate: &[f64],
        integrals: &[f64],
        integral_state: &[f64],
        u0: &[f64],
        u1: &[f64],
        tau: f64,
    ) -> Vec<f64> {
        self.outputs
            .iter()
            .enumerate()
            .map(|(k, output)| {
                let row = &mode.outputs[k];
                if output.integral {
                    integrals[k] + integrated(row, integral_state, u0, u1, tau)
                } else {
                    row.eval(x, u, rate)
                }
            })
            .collect()
    }

    /// Finds the consistent mode starting from `candidate` at an instant, recording every
    /// switch as an event; `trigger` is the mode left and why.
    #[allow(clippy::too_many_arguments)]
    fn resolve(
        &mut self,
        candidate: Mode,
        full: &[f64],
        u: &[f64],
        rate: &[f64],
        t: f64,
        trigger: Option<Trigger<'_>>,
        recorder: &mut Recorder,
    ) -> Result<Arc<NumericMode>, SimError> {
        let crossed = trigger.as_ref().map(|trigger| trigger.crossed);
        let crossed = crossed.as_ref();
        let mut tried: Vec<Mode> = Vec::new();
        let mut switched_ids: Vec<ElementId> = Vec::new();
        let mut previous: Option<(Arc<NumericMode>, ElementId, Why)> =
            trigger.map(|trigger| (trigger.mode.clone(), trigger.element, trigger.why));
        let mut mode = candidate.at_values(self.model, &self.values);
        loop {
            if tried.contains(&mode) {
                let mut switched: Vec<String> = switched_ids
                    .iter()
                    .map(|&id| self.model.element(id).name.clone())
                    .collect();
                switched.sort();
                switched.dedup();
                let sizes = self.mode_counts(&switched);
                if combinations::count(sizes.iter().copied()).is_none() {
                    return Err(SimError::TooManyCombinations {
                        t,
                        elements: switched,
                        combinations: combinations::in_words(sizes),
                        limit: bondgraph_core::limits::MAX_MODES,
                    });
                }
                let last = self.mode(tried.last().expect("a mode was tried"))?;
                if let Some(found) =
                    self.search_consistent(&tried[0], &switched, full, u, rate, crossed)?
                {
                    recorder.event(Recorded {
                        t,
                        from: last,
                        to: found.clone(),
                        element: Switched::Elements(switched.join(",")),
                        why: None,
                    });
                    return Ok(found);
                }
                let specs = tried.iter().map(|m| m.spec(self.model)).collect();
                return Err(SimError::NoConsistentMode {
                    t,
                    tried: specs,
                    elements: switched,
                });
            }
            tried.push(mode.clone());
            let numeric = self.mode(&mode)?;
            if let Some((from, element, why)) = previous.take() {
                recorder.event(Recorded {
                    t,
                    from,
                    to: numeric.clone(),
                    element: Switched::Element(element),
                    why: Some(why),
                });
            }
            let x = numeric.project(full, u);
            let mut next = None;
            for guard in &numeric.guards {
                if !self.entered(&numeric, guard, &x, u, rate, crossed) {
                    continue;
                }
                if guard.requires_hold && !self.can_hold(&numeric, guard, full, u, rate)? {
                    continue;
                }
                next = Some((
                    numeric.mode.with(guard.element, guard.leaves_to),
                    guard.element,
                    Why::of(guard, false),
                ));
                break;
            }
            match next {
                None => return Ok(numeric),
                Some((mode_next, element, why)) => {
                    switched_ids.push(element);
                    previous = Some((numeric, element, why));
                    mode = mode_next;
                }
            }
        }
    }

    /// The consistent mode among every combination of the modes of `elements` (by name),
    /// the rest as in `candidate`: what [`Simulator::resolve`] falls back on when switching
    /// one element at a time cycles.
    ///
    /// Switching one contact at a time judges each against the others' current modes. Two
    /// contacts at rest can then send each other round in a circle: neither of two contacts
    /// on one body can hold it alone, and with both slipping each looks
    /// as if it could stick again because its velocity is still inside the dead band. Here a
    /// combination is consistent when no guard is entered, where a dead-band guard (back to
    /// stuck) counts only if its relative velocity is not already leaving the band: a contact
    /// at rest whose velocity grows in its slip direction is breaking away. Of several
    /// consistent combinations the one with the most contacts stuck wins (static friction
    /// holds where it can), then the one closest to `candidate`.
    fn search_consistent(
        &mut self,
        candidate: &Mode,
        elements: &[String],
        full: &[f64],
        u: &[f64],
        rate: &[f64],
        crossed: Option<&Crossed>,
    ) -> Result<Option<Arc<NumericMode>>, SimError> {
        let mut choices: Vec<(ElementId, &[ElementMode])> = Vec::new();
        for name in elements {
            let Some(id) = self.model.element_named(name) else {
                continue;
            };
            let options = self.model.element(id).kind.modes_at(&self.values);
            if !options.is_empty() {
                choices.push((id, options));
            }
        }
        // Within the limit: `resolve` checked the count before searching.
        let combinations = combinations::count(choices.iter().map(|(_, o)| o.len())).unwrap_or(0);
        let mut best: Option<((usize, usize), Arc<NumericMode>)> = None;
        for index in 0..combinations {
            let mut mode = candidate.clone();
            let mut rest = index;
            for (id, options) in &choices {
                mode = mode.with(*id, options[rest % options.len()]);
                rest /= options.len();
            }
            let numeric = match self.mode(&mode) {
                Ok(numeric) => numeric,
                Err(SimError::Derivation(_)) => continue,
                Err(e) => return Err(e),
            };
            if !self.consistent(&numeric, full, u, rate, crossed)? {
                continue;
            }
            let stuck = choices
                .iter()
                .filter(|(id, _)| mode.of(*id) == Some(ElementMode::Stuck))
                .count();
            let distance = choices
                .iter()
                .filter(|(id, _)| mode.of(*id) != candidate.of(*id))
                .count();
            let rank = (usize::MAX - stuck, distance);
            if best.as_ref().is_none_or(|(r, _)| rank < *r) {
                best = Some((rank, numeric));
            }
        }
        Ok(best.map(|(_, numeric)| numeric))
    }

    /// The number of modes of each switching element named in `elements`.
    fn mode_counts(&self, elements: &[String]) -> Vec<usize> {
        elements
            .iter()
            .filter_map(|name| self.model.element_named(name))
            .map(|id| self.model.element(id).kind.modes_at(&self.values).len())
            .filter(|&n| n > 0)
            .collect()
    }

    /// Whether no guard of `mode` is entered at this instant, counting a dead-band guard
    /// only while its relative velocity is not leaving the band.
    fn consistent(
        &mut self,
        mode: &NumericMode,
        full: &[f64],
        u: &[f64],
        rate: &[f64],
        crossed: Option<&Crossed>,
    ) -> Result<bool, SimError> {
        let x = mode.project(full, u);
        for guard in &mode.guards {
            if !self.entered(mode, guard, &x, u, rate, crossed) {
                continue;
            }
            if guard.requires_hold {
                let leaving = mode.row_rate(&guard.row, &x, u, rate) < 0.0;
                if leaving || !self.can_hold(mode, guard, full, u, rate)? {
                    continue;
                }
            }
            return Ok(false);
        }
        Ok(true)
    }

    /// Whether a guard is satisfied at entry and not moving out: the mode would be left at
    /// once.
    fn entered(
        &self,
        mode: &NumericMode,
        guard: &NumericGuard,
        x: &[f64],
        u: &[f64],
        rate: &[f64],
        crossed: Option<&Crossed>,
    ) -> bool {
        let value = guard.row.eval(x, u, rate);
        let tolerance = 1e-9 * guard.row.magnitude(x, u, rate) + f64::MIN_POSITIVE;
        let on_crossed_threshold = crossed.is_some_and(|c| c.watches_as(guard, value, tolerance));
        if !on_crossed_threshold {
            if value > tolerance {
                return true;
            }
            if value < -tolerance {
                return false;
            }
        }
        let first = mode.row_rate(&guard.row, x, u, rate);
        let rate_tolerance = 1e-9 * mode.row_rate_magnitude(&guard.row, x, u, rate);
        if first.abs() > rate_tolerance {
            return first > 0.0;
        }
        // On the threshold and level: a string at zero extension with its mass at rest, or a
        // contact whose breakaway force equals its Coulomb force slipping at the instant the
        // force it would have to hold is the breakaway force (its acceleration is then zero
        // up to rounding, whose sign must not decide). The second derivative (the rate an
        // instant later) decides; if it too is zero up to rounding the guard is at rest on its
        // threshold (a contact holding exactly its breakaway force, zero at a balance with no
        // breakaway), which leaves the mode nothing to leave for.
        let (second, rounding) = second_rate(mode, &guard.row, x, u, rate);
        second > rounding
    }

    /// Whether the element of a `requires_hold` guard can hold in the mode the guard leads
    /// to: a contact going stuck is within its breakaway force (the stuck mode's breakaway
    /// guards for it are not entered), a flow limit going limiting holds back a positive
    /// effort (its restraining-effort guard is not entered).
    fn can_hold(
        &mut self,
        mode: &NumericMode,
        guard: &NumericGuard,
        full: &[f64],
        u: &[f64],
        rate: &[f64],
    ) -> Result<bool, SimError> {
        let holding = mode.mode.with(guard.element, guard.leaves_to);
        // A contact whose relative velocity is imposed (a velocity source drives it) cannot
        // stick at all: it passes through zero velocity into the opposite slip. A limit on
        // a flow that is already imposed cannot limit it.
        let target = match self.mode(&holding) {
            Err(SimError::Derivation(d)) if d.has(DiagnosticKind::CausalConflict) => {
                return Ok(false);
            }
            other => other?,
        };
        let x = target.project(full, u);
        Ok(!target.guards.iter().any(|g| {
            g.element == guard.element
                && matches!(
                    g.watched,
                    Watched::HoldingForce | Watched::RestrainingEffort
                )
                && self.entered(&target, g, &x, u, rate, None)
        }))
    }

    fn non_finite(&self, t: f64, mode: &NumericMode, x: &[f64]) -> SimError {
        SimError::NonFinite {
            t,
            mode: mode.spec.clone(),
            states: mode
                .state_names
                .iter()
                .zip(x)
                .filter(|(_, v)| !v.is_finite())
                .map(|(n, _)| n.clone())
                .collect(),
        }
    }
}

/// A simulation in progress, advanced piece by piece: for runs to a fixed time and for
/// steady-state searches that decide how far to go as they learn the trajectory.
pub struct Stepper<'s, 'm> {
    simulator: &'s mut Simulator<'m>,
    inputs: &'s [&'s dyn Signal],
    breakpoints: Vec<f64>,
    t: f64,
    x: Vec<f64>,
    mode: Arc<NumericMode>,
    armed: Vec<bool>,
    /// The level below which each guard is armed: zero, or minus the rounding tolerance
    /// after its switch was declined.
    arm_below: Vec<f64>,
    /// The level each guard must rise to before it fires: zero, or the rounding of its terms
    /// for a guard whose crossing led straight back to the mode it left (see
    /// [`Stepper::switch_at`]).
    fire_above: Vec<f64>,
    integrals: Vec<f64>,
    /// The last switches: when, and the fastest rate (`max |λ|`) of the mode entered, zero
    /// where unknown (a nonlinear mode).
    recent: VecDeque<(f64, f64)>,
    sample: Option<SampleTimes>,
    /// The index of the next sample.
    next_sample: u64,
    recorder: Recorder,
    stats: Stats,
    energy: Option<EnergyBalance>,
    /// The element and reason of the last crossing found, and whether its switch was
    /// declined, for a stalled run's message.
    last_crossing: Option<(ElementId, Why, bool)>,
    /// Steps taken: integration steps and event-location samples.
    steps: u64,
}

impl<'s, 'm> Stepper<'s, 'm> {
    /// Starts at time zero, making the initial mode consistent; records outputs every
    /// `sample` seconds (none when `None`, for searches that only need the end).
    ///
    /// # Errors
    /// As [`Simulator::run`].
    pub fn new(
        simulator: &'s mut Simulator<'m>,
        inputs: &'s [&'s dyn Signal],
        initial_mode: Mode,
        initial_state: Vec<f64>,
        sample: Option<f64>,
    ) -> Result<Self, SimError> {
        let model = simulator.model;
        if inputs.len() != model.inputs.len() {
            return Err(SimError::Inputs(format!(
                "model '{}' has {} inputs but {} signals were given",
                model.name,
                model.inputs.len(),
                inputs.len()
            )));
        }
        if initial_state.len() != simulator.storage.len() {
            return Err(SimError::Inputs(format!(
                "the initial state has {} values but model '{}' stores energy in {} elements",
                initial_state.len(),
                model.name,
                simulator.storage.len()
            )));
        }
        let mut breakpoints: Vec<f64> = inputs
            .iter()
            .flat_map(|s| s.breakpoints())
            .filter(|t| *t > 0.0 && t.is_finite())
            .collect();
        breakpoints.sort_by(f64::total_cmp);
        breakpoints.dedup();
        let names = simulator.outputs.iter().map(|o| o.name.clone());
        let energy_names = simulator.energy_columns.iter().map(|(n, _)| n.clone());
        let mut recorder = Recorder::new(names.chain(energy_names).collect());
        let (u, rate) = values_at(inputs, 0.0);
        let mode = simulator.resolve(
            initial_mode,
            &initial_state,
            &u,
            &rate,
            0.0,
            None,
            &mut recorder,
        )?;
        let x = mode.project(&initial_state, &u);
        recorder.enter(&mode.spec, 0.0);
        let outputs = simulator.outputs.len();
        Ok(Self {
            armed: vec![false; mode.guards.len()],
            arm_below: vec![0.0; mode.guards.len()],
            fire_above: vec![0.0; mode.guards.len()],
            simulator,
            inputs,
            breakpoints,
            t: 0.0,
            x,
            mode,
            integrals: vec![0.0; outputs],
            recent: VecDeque::new(),
            sample: sample
                .filter(|s| *s > 0.0 && s.is_finite())
                .map(SampleTimes::every),
            next_sample: 0,
            recorder,
            stats: Stats::default(),
            energy: None,
            last_crossing: None,
            steps: 0,
        })
    }

    /// Starts keeping the energy books from now on.
    pub fn audit_energy(&mut self) {
        let stored = NumericMode::stored_energy(
            &self.simulator.storage,
            self.simulator.model,
            &self.full_state(),
        );
        self.energy = Some(EnergyBalance {
            initial_stored: stored,
            final_stored: stored,
            ..EnergyBalance::default()
        });
    }

    /// The energy books so far, if kept.
    pub fn energy(&self) -> Option<EnergyBalance> {
        self.energy
    }

    /// `(supplied, dissipated)` so far, merges at events counted as dissipated (NaN when
    /// the books are not kept).
    fn books(&self) -> (f64, f64) {
        self.energy.map_or((f64::NAN, f64::NAN), |e| {
            (e.supplied, e.dissipated + e.lost_at_events)
        })
    }

    /// The current time.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The current mode.
    pub fn mode(&self) -> &Arc<NumericMode> {
        &self.mode
    }

    /// The current state of the current mode.
    pub fn state(&self) -> &[f64] {
        &self.x
    }

    /// The inputs and their rates at time `t`.
    pub fn inputs_at(&self, t: f64) -> (Vec<f64>, Vec<f64>) {
        values_at(self.inputs, t)
    }

    /// The current full state (energy variables of every storage element).
    pub fn full_state(&self) -> Vec<f64> {
        let (u, _) = self.inputs_at(self.t);
        self.mode.reconstruct(&self.x, &u)
    }

    /// The requested outputs now.
    pub fn outputs(&self) -> Vec<f64> {
        let (u, rate) = self.inputs_at(self.t);
        let zeros = vec![0.0; self.x.len()];
        let mut values = self.simulator.output_values(
            &self.mode,
            &self.x,
            &u,
            &rate,
            &self.integrals,
            &zeros,
            &u,
            &rate,
            0.0,
        );
        values.extend(
            self.simulator
                .energy_values(&self.mode, &self.x, &u, self.books()),
        );
        values
    }

    /// Whether each guard of the current mode has been seen below zero (can fire).
    pub fn armed(&self) -> &[bool] {
        &self.armed
    }

    /// The steps taken so far: integration steps and event-location samples.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The number of events so far.
    pub fn event_count(&self) -> usize {
        self.recorder.events.len()
    }

    /// The events so far.
    pub fn events(&self) -> Vec<Event> {
        let model = self.simulator.model;
        self.recorder
            .events
            .iter()
            .map(|e| e.to_event(model))
            .collect()
    }

    /// The events so far, ending the run.
    pub fn into_events(self) -> Vec<Event> {
        self.events()
    }

    /// Advances to `until` or to the first event before it, whichever comes first; returns
    /// whether it stopped at an event (the new mode already entered).
    ///
    /// # Errors
    /// As [`Simulator::run`].
    pub fn advance(&mut self, until: f64) -> Result<bool, SimError> {
        let mut progress = stall::Progress::default();
        while self.t < until {
            let before = self.t;
            let end = self
                .breakpoints
                .iter()
                .copied()
                .find(|&b| b > self.t)
                .map_or(until, |b| b.min(until));
            self.last_crossing = None;
            let switched = self.segment(end)?;
            self.check_outputs()?;
            if switched {
                return Ok(true);
            }
            let last_crossing = self.last_crossing.take();
            let declined = last_crossing.is_some_and(|(_, _, declined)| declined);
            let model = self.simulator.model;
            let crossing = || {
                last_crossing
                    .map(|(element, why, _)| (model.element(element).name.clone(), why.to_string()))
            };
            if let Some(cause) = progress.after_segment(before, self.t, crossing, declined) {
                return Err(SimError::Stalled {
                    t: self.t,
                    mode: self.mode.spec.clone(),
                    cause,
                });
            }
        }
        Ok(false)
    }

    /// An error when a sample recorded so far holds an output that is not finite.
    fn check_outputs(&self) -> Result<(), SimError> {
        match &self.recorder.non_finite {
            None => Ok(()),
            Some((t, mode, outputs)) => Err(SimError::NonFiniteOutput {
                t: *t,
                mode: self.recorder.modes[*mode].clone(),
                outputs: outputs
                    .iter()
                    .map(|&k| self.recorder.output_names[k].clone())
                    .collect(),
            }),
        }
    }

    /// Propagates the current mode to `end` or to its first event; true at an event.
    fn segment(&mut self, end: f64) -> Result<bool, SimError> {
        let crossing = if self.mode.nonlinear.is_some() {
            self.integrated_segment(end)?
        } else {
            self.closed_form_segment(end)?
        };
        match crossing {
            Some(crossing) => self.switch_at(crossing),
            None => Ok(false),
        }
    }

    /// Propagates a linear mode in closed form to `end` or to its first crossing.
    fn closed_form_segment(&mut self, end: f64) -> Result<Option<events::Crossing>, SimError> {
        let length = end - self.t;
        let (u0, u1) = self.inputs_at(self.t);
        let current = self.mode.clone();
        let buffers = std::mem::take(&mut self.simulator.segment_buffers);
        let mut segment = current.propagator.start_in(&self.x, &u0, &u1, buffers);
        self.stats.segments += 1;
        // Guards are located only as far as their samples follow the mode's oscillations:
        // the segment ends there, and the next one samples on from its end. (An oscillation
        // whose 625 periods are shorter than the spacing of doubles at `t` cannot be
        // followed at all: its segment is not cut, or time would stop.)
        let window = if current.guards.is_empty() {
            length
        } else {
            events::sampled_horizon(current.propagator.eigenvalues(), length)
        };
        let window = if self.t + window > self.t {
            window
        } else {
            length
        };
        let mut samples = 0;
        let located = events::first_crossing(
            &current,
            &mut segment,
            &u0,
            &u1,
            length,
            window,
            &mut self.armed,
            &self.arm_below,
            &self.fire_above,
            &mut samples,
            &mut self.simulator.scratch,
        );
        if self.over_step_limit(samples) {
            let scale = TimeScale::of_eigenvalues(current.propagator.eigenvalues());
            return Err(self.too_many_steps(self.t, None, scale));
        }
        // An event's state is the root's, where its guard is exactly at its threshold (see
        // `event_time` for its time).
        let (crossing, stop, stop_time) = match located {
            events::Located::Crossing(c) => (Some(c), c.tau, event_time(self.t, c.tau, end)),
            events::Located::Clear(reached) if reached < length => {
                (None, reached, self.t + reached)
            }
            events::Located::Clear(_) => (None, length, end),
        };

        let n = self.x.len();
        let mut state = vec![0.0; n];
        let integrals_wanted = self.simulator.outputs.iter().any(|o| o.integral);
        let mut integral_state = if integrals_wanted {
            vec![0.0; n]
        } else {
            Vec::new()
        };
        // The books over the segment, kept from sample to sample: `booked` holds what
        // `[0, booked_to]` added.
        let mut books = self
            .energy
            .is_some()
            .then(|| SegmentBooks::new(&current, &segment, &u0, &u1));
        let (mut booked, mut booked_to) = (Increment::default(), 0.0);
        if let Some(times) = self.sample {
            let mode_index = self.recorder.mode_index(&current.spec);
            // In eigen-coordinates each output is Re(Σ c_j z_j(τ)) + a + b τ (and its integral
            // Re(Σ c_j ∫z_j) + a τ + b τ²/2), with c = row V, a = d·u₀ + r·u₁ + k, b = d·u₁.
            let modal: Option<Vec<(Vec<Complex64>, f64, f64)>> = segment.vectors().map(|v| {
                current
                    .outputs
                    .iter()
                    .map(|row| {
                        let c = (0..n)
                            .map(|j| (0..n).map(|i| v[(i, j)] * row.state[i]).sum())
                            .collect();
                        let a = dot(&row.input, &u0) + dot(&row.rate, &u1) + row.constant;
                        (c, a, dot(&row.input, &u1))
                    })
                    .collect()
            });
            let mut u = vec![0.0; u0.len()];
            let mut energy_state = vec![0.0; n];
            let books_wanted = self
                .simulator
                .energy_columns
                .iter()
                .any(|(_, c)| c.needs_books());
            // One sample's values, the buffer reused from sample to sample.
            let mut values: Vec<f64> = Vec::new();
            loop {
                let time = times.time(self.next_sample);
                if time > stop_time {
                    break;
                }
                let tau = (time - self.t).clamp(0.0, stop);
                values.clear();
                match (&modal, segment.modal_state_and_integral(tau)) {
                    (Some(coefficients), Some((z, iz))) => values.extend(
                        self.simulator
                            .outputs
                            .iter()
                            .zip(coefficients)
                            .enumerate()
                            .map(|(k, (output, (c, a, b)))| {
                                let re = |w: &[Complex64]| -> f64 {
                                    c.iter()
                                        .zip(w)
                                        .map(|(x, y)| x.re * y.re - x.im * y.im)
                                        .sum()
                                };
                                if output.integral {
                                    self.integrals[k] + re(iz) + a * tau + b * tau * tau / 2.0
                                } else {
                                    re(z) + a + b * tau
                                }
                            }),
                    ),
                    _ => {
                        segment.state_and_integral_into(
                            tau,
                            &mut state,
                            integrals_wanted.then_some(&mut integral_state[..]),
                        );
                        for (k, slot) in u.iter_mut().enumerate() {
                            *slot = u0[k] + u1[k] * tau;
                        }
                        values.extend(self.simulator.output_values(
                            &current,
                            &state,
                            &u,
                            &u1,
                            &self.integrals,
                            &integral_state,
                            &u0,
                            &u1,
                            tau,
                        ));
                    }
                }
                if !self.simulator.energy_columns.is_empty() {
                    segment.state_and_integral_into(tau, &mut energy_state, None);
                    for (k, slot) in u.iter_mut().enumerate() {
                        *slot = u0[k] + u1[k] * tau;
                    }
                    let (mut supplied, mut dissipated) = self.books();
                    if let (true, Some(books)) = (books_wanted, &mut books) {
                        booked += books.over(&current, &mut segment, booked_to, tau);
                        booked_to = booked_to.max(tau);
                        supplied += booked.supplied;
                        dissipated += booked.dissipated;
                    }
                    values.extend(self.simulator.energy_values(
                        &current,
                        &energy_state,
                        &u,
                        (supplied, dissipated),
                    ));
                }
                self.recorder
                    .sample_in(time, mode_index, values.iter().copied());
                self.next_sample += 1;
            }
        }
        if let (Some(energy), Some(books)) = (&mut self.energy, &mut books) {
            booked += books.over(&current, &mut segment, booked_to, stop);
            energy.supplied += booked.supplied;
            energy.dissipated += booked.dissipated;
            energy.error += booked.error;
        }
        segment.state_and_integral_into(
            stop,
            &mut state,
            integrals_wanted.then_some(&mut integral_state[..]),
        );
        for (k, output) in self.simulator.outputs.iter().enumerate() {
            if output.integral {
                self.integrals[k] +=
                    integrated(&current.outputs[k], &integral_state, &u0, &u1, stop);
            }
        }
        self.simulator.segment_buffers = segment.into_buffers();
        // At the event's double, or exactly on the end of the segment (not a rounding
        // error short of it).
        self.t = stop_time;
        self.x = state;
        if self.x.iter().any(|v| !v.is_finite()) {
            return Err(self.simulator.non_finite(self.t, &current, &self.x));
        }
        if stop_time == end
            && self
                .breakpoints
                .binary_search_by(|b| b.total_cmp(&end))
                .is_ok()
        {
            let before: Vec<f64> = u0.iter().zip(&u1).map(|(a, b)| a + b * stop).collect();
            self.book_input_step(&current, &before);
        }
        Ok(crossing)
    }

    /// Books the energy of an input's step at the current time, from `before` (the left
    /// limits of the inputs) to their values now, in `mode`: what the ports took through
    /// the step's impulse ([`crate::energy::jump`]); what that leaves of the stored
    /// energy's jump is rounding, into the error bound, or, where the step's limit is
    /// unbounded, lost at the event.
    fn book_input_step(&mut self, mode: &NumericMode, before: &[f64]) {
        let Some(energy) = &mut self.energy else {
            return;
        };
        let (after, _) = values_at(self.inputs, self.t);
        if after == before {
            return;
        }
        let (increment, unbounded) = crate::energy::jump(mode, &self.x, before, &after);
        let storage = &self.simulator.storage;
        let model = self.simulator.model;
        let stored =
            |u: &[f64]| NumericMode::stored_energy(storage, model, &mode.reconstruct(&self.x, u));
        let jump = stored(&after) - stored(before);
        energy.supplied += increment.supplied;
        energy.dissipated += increment.dissipated;
        let left = (increment.supplied - increment.dissipated) - jump;
        energy.error += increment.error;
        if unbounded {
            energy.lost_at_events += left;
        } else {
            energy.error += left.abs();
        }
    }

    /// At a guard's crossing: rebuild the full state, switch, and make the new mode
    /// consistent; true when the mode changed.
    fn switch_at(&mut self, crossing: events::Crossing) -> Result<bool, SimError> {
        let current = self.mode.clone();
        // An event: rebuild the full state, switch, and make the new mode consistent.
        let t = self.t;
        let (u, rate) = self.inputs_at(t);
        let full = current.reconstruct(&self.x, &u);
        let guard = &current.guards[crossing.guard];
        if !guard.requires_hold && touches(&current, guard, &self.x, &u, &rate) {
            // At rest on its threshold rather than crossing it: a stuck contact at an exact
            // balance with no breakaway force, its holding force zero but for rounding, broke
            // away on the rounding's sign and stuck again at once, every few tens of
            // microseconds (100 000 events in 2.3 s). Nothing crosses, so nothing switches;
            // the guard fires once it is past its threshold by more than the rounding of its
            // terms. (A guard into `stuck` is left to its hold test: at rest at a balance the
            // contact sticks.)
            self.rest_on_threshold(crossing.guard, &u, &rate);
            return Ok(false);
        }
        if guard.requires_hold && !self.simulator.can_hold(&current, guard, &full, &u, &rate)? {
            self.last_crossing = Some((guard.element, Why::of(guard, true), true));
            // Static friction cannot hold (or a flow limit would hold back nothing): no
            // switch. The guard rests until it has been left again by more than rounding,
            // and the contact slips on to its next guard (through zero velocity).
            self.armed[crossing.guard] = false;
            self.arm_below[crossing.guard] =
                -(1e-9 * guard.row.magnitude(&self.x, &u, &rate) + f64::MIN_POSITIVE);
            return Ok(false);
        }
        let target = current.mode.with(guard.element, guard.leaves_to);
        let events_before = self.recorder.events.len();
        let next = self.simulator.resolve(
            target,
            &full,
            &u,
            &rate,
            t,
            Some(Trigger {
                mode: &current,
                element: guard.element,
                why: Why::of(guard, true),
                crossed: Crossed {
                    element: guard.element,
                    watched: guard.watched,
                    residue: guard.row.eval(&self.x, &u, &rate).abs(),
                },
            }),
            &mut self.recorder,
        )?;
        if next.mode == current.mode && watches_an_effort(guard) {
            // Straight back to the mode it left, at the same instant: the modes at this
            // instant say the guard did not cross (a contact at a balance breaking away and
            // sticking again at once, in a nonlinear mode, whose rates are judged exactly).
            // Nothing switched, so no event is recorded.
            self.recorder.events.truncate(events_before);
            self.rest_on_threshold(crossing.guard, &u, &rate);
            return Ok(false);
        }
        if self.sample.is_some() {
            let values = self.outputs();
            self.recorder.sample(t, &current.spec, values);
        }
        self.check_chattering(t, &next)?;
        self.mode = next;
        self.x = self.mode.project(&full, &u);
        if self.x.iter().any(|v| !v.is_finite()) {
            return Err(self.simulator.non_finite(t, &self.mode, &self.x));
        }
        if let Some(energy) = &mut self.energy {
            let storage = &self.simulator.storage;
            let model = self.simulator.model;
            let before = NumericMode::stored_energy(storage, model, &full);
            let after =
                NumericMode::stored_energy(storage, model, &self.mode.reconstruct(&self.x, &u));
            energy.lost_at_events += before - after;
        }
        self.armed = vec![false; self.mode.guards.len()];
        self.arm_below = vec![0.0; self.mode.guards.len()];
        self.fire_above = vec![0.0; self.mode.guards.len()];
        self.recorder.enter(&self.mode.spec, t);
        if self.sample.is_some() {
            let values = self.outputs();
            self.recorder.sample(t, &self.mode.spec, values);
        }
        Ok(true)
    }

    /// Rests guard `k` of the current mode on its threshold, where it was found crossing
    /// but nothing switched: it fires once past it by more than the rounding of its terms
    /// (`1e-9` of them, as [`Simulator::entered`] judges a value at its threshold).
    fn rest_on_threshold(&mut self, k: usize, u: &[f64], rate: &[f64]) {
        let guard = &self.mode.guards[k];
        self.last_crossing = Some((guard.element, Why::of(guard, true), true));
        self.armed[k] = true;
        self.fire_above[k] = 1e-9 * guard.row.magnitude(&self.x, u, rate) + f64::MIN_POSITIVE;
    }

    /// Counts `count` more steps; whether the run is now past its limit.
    fn over_step_limit(&mut self, count: u64) -> bool {
        self.steps += count;
        self.steps > self.simulator.settings.max_steps
    }

    /// The error of a run past its limit of steps at `t`, with the last integration step and
    /// the mode's fastest time scale there where known.
    fn too_many_steps(&self, t: f64, step: Option<f64>, time_scale: Option<TimeScale>) -> SimError {
        SimError::TooManySteps {
            t,
            limit: self.simulator.settings.max_steps,
            step,
            time_scale,
        }
    }

    /// The event limit and the chattering checks, after a switch at `t` into `entered`.
    ///
    /// Chattering is many switches in a short time: within a millionth of the time so far
    /// (Zeno behaviour), or, with the inputs steady, faster on average than the fastest time
    /// scale of the modes entered. A contact switching every 50 µs in a motor whose fastest
    /// time constant is 1.5 ms is not following its motion but rounding; a stick-slip cycle
    /// switches at its period, several time scales apart, and a table that reverses every
    /// microsecond sets off the switches by its breakpoints.
    fn check_chattering(&mut self, t: f64, entered: &NumericMode) -> Result<(), SimError> {
        let settings = self.simulator.settings;
        self.stats.events = self.recorder.events.len();
        if self.stats.events > settings.max_events {
            return Err(SimError::TooManyEvents {
                t,
                limit: settings.max_events,
            });
        }
        let rate = if entered.nonlinear.is_some() {
            0.0
        } else {
            entered
                .propagator
                .eigenvalues()
                .iter()
                .map(|v| v.norm())
                .filter(|r| r.is_finite())
                .fold(0.0, f64::max)
        };
        self.recent.push_back((t, rate));
        while self.recent.len() > settings.chatter_events {
            self.recent.pop_front();
        }
        if self.recent.len() < settings.chatter_events {
            return Ok(());
        }
        let first = self.recent.front().map_or(t, |r| r.0);
        let span = t - first;
        let zeno = settings.chatter_window * t.max(1.0);
        let fastest = self.recent.iter().map(|r| r.1).fold(0.0, f64::max);
        let steady = {
            let next = self.breakpoints.partition_point(|b| *b < first);
            self.breakpoints.get(next).is_none_or(|b| *b > t)
        };
        let time_scale = (fastest > 0.0 && steady)
            .then(|| 1.0 / fastest)
            .filter(|scale| {
                span < settings.chatter_events as f64 * settings.chatter_time_scales * scale
            });
        if span < zeno || time_scale.is_some() {
            let model = self.simulator.model;
            let mut elements: Vec<String> = self
                .recorder
                .events
                .iter()
                .rev()
                .take(settings.chatter_events)
                .map(|e| e.to_event(model).element)
                .collect();
            elements.sort();
            elements.dedup();
            let reason = self
                .recorder
                .events
                .last()
                .map(|e| e.to_event(model).reason)
                .unwrap_or_default();
            return Err(SimError::Chattering {
                t,
                events: settings.chatter_events,
                window: if span < zeno { zeno } else { span },
                elements,
                reason,
                time_scale: if span < zeno { None } else { time_scale },
            });
        }
        Ok(())
    }

    /// Ends the run: the trajectory recorded, with the final state.
    pub fn finish(mut self) -> Trajectory {
        let full = self.full_state();
        self.stats.events = self.recorder.events.len();
        self.stats.modes = self.recorder.modes.len();
        if let Some(energy) = &mut self.energy {
            energy.final_stored =
                NumericMode::stored_energy(&self.simulator.storage, self.simulator.model, &full);
        }
        let names = self.simulator.storage.names.clone();
        let mut trajectory = self.recorder.finish(
            self.simulator.model,
            self.t,
            names.into_iter().zip(full).collect(),
            self.mode.spec.clone(),
            self.stats,
        );
        trajectory.energy = self.energy;
        trajectory
    }
}

/// The time of an event found `tau` into a segment from `start` to `end`: the root's,
/// rounded to a double, and after `start` if the root is.
///
/// A root closer to the segment's start than the spacing of doubles there rounds back to the
/// start; time must still advance, or each segment finds the root again (a belt's speed
/// rising at 1e9 m/s² gains 8e-14 m/s in the 8e-23 s from 1 µs to such a root: time stood
/// still while state and inputs disagreed, and the same stick was declined until 'time
/// stopped advancing'). Such an event lands on the next double, its state still the root's:
/// taken there instead, a stiff state would move on by what it changes in an ulp of time
/// (a light tip, with a time constant of 4e-18 s, went through zero velocity and
/// back, and read as slipping both ways). Both the closed-form and the integrated path time
/// their events so.
fn event_time(start: f64, tau: f64, end: f64) -> f64 {
    let mut time = start + tau;
    if tau > 0.0 && time <= start {
        time = start.next_up();
    }
    time.min(end)
}

/// Whether a guard found crossing only touches its threshold: on it, level there (its value
/// and rate zero up to the rounding of their terms) and not turning into it (its second
/// derivative likewise). A guard past its threshold at a segment's start (an input that
/// jumped) does not.
///
/// Only guards on an effort (a contact's holding force, a string's tension, a flow limit's
/// restraining effort) are judged so: their terms are the forces that balance, the scale
/// rounding is judged against. A velocity or an extension is a state of its own, its one
/// term itself, and a velocity at rest on zero has no scale to be judged against.
fn touches(mode: &NumericMode, guard: &NumericGuard, x: &[f64], u: &[f64], rate: &[f64]) -> bool {
    if !watches_an_effort(guard) {
        return false;
    }
    let value = guard.row.eval(x, u, rate);
    if value.abs() > 1e-9 * guard.row.magnitude(x, u, rate) + f64::MIN_POSITIVE {
        return false;
    }
    let first = mode.row_rate(&guard.row, x, u, rate);
    if first.abs() > 1e-9 * mode.row_rate_magnitude(&guard.row, x, u, rate) {
        return false;
    }
    let (second, rounding) = second_rate(mode, &guard.row, x, u, rate);
    second <= rounding
}

/// Whether a guard watches an effort (a holding force, a tension, a restraining effort).
fn watches_an_effort(guard: &NumericGuard) -> bool {
    matches!(
        guard.watched,
        Watched::HoldingForce | Watched::Tension | Watched::RestrainingEffort
    )
}

/// The second time derivative of a guard row along the mode's flow, inputs moving at
/// `rate`, and the rounding it carries: the difference of its first derivative over a step
/// along `dx/dt`, exact for a linear mode (where the first derivative is affine) whatever the
/// step, judged against `1e-9` of the terms of the two rates (as a rate is judged against
/// its own terms; zero for a nonlinear mode, whose rates are judged exactly).
fn second_rate(
    mode: &NumericMode,
    row: &crate::numeric::Row,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
) -> (f64, f64) {
    let dx = mode.derivative(x, u);
    let step = if mode.nonlinear.is_some() { 1e-6 } else { 1.0 };
    let later: Vec<f64> = x.iter().zip(&dx).map(|(x, d)| x + step * d).collect();
    let u_later: Vec<f64> = u.iter().zip(rate).map(|(u, r)| u + step * r).collect();
    let second =
        (mode.row_rate(row, &later, &u_later, rate) - mode.row_rate(row, x, u, rate)) / step;
    let terms = mode.row_rate_magnitude(row, &later, &u_later, rate)
        + mode.row_rate_magnitude(row, x, u, rate);
    (second, 1e-9 * terms / step)
}

fn values_at(inputs: &[&dyn Signal], t: f64) -> (Vec<f64>, Vec<f64>) {
    (
        inputs.iter().map(|s| s.value(t)).collect(),
        inputs.iter().map(|s| s.rate(t)).collect(),
    )
}

/// `∫₀^τ y dt` of an output row over a segment, given `∫₀^τ x dt`.
fn integrated(
    row: &crate::numeric::Row,
    integral_state: &[f64],
    u0: &[f64],
    u1: &[f64],
    tau: f64,
) -> f64 {
    let integral_input: Vec<f64> = u0
        .iter()
        .zip(u1)
        .map(|(a, b)| a * tau + b * tau * tau / 2.0)
        .collect();
    let integral_rate: Vec<f64> = u1.iter().map(|b| b * tau).collect();
    dot(&row.state, integral_state)
        + dot(&row.input, &integral_input)
        + dot(&row.rate, &integral_rate)
        + row.constant * tau
}
