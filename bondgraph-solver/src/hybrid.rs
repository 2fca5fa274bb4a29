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

use std::collections::HashMap;
use std::sync::Arc;

use bondgraph_core::diagnostics::DiagnosticKind;
use bondgraph_core::equations::{Options, OutputSpec};
use bondgraph_core::guards::Watched;
use bondgraph_core::model::{ElementId, ElementMode, Model};
use bondgraph_core::modes::{Mode, ModeCache};
use bondgraph_core::scenario::Book;

use crate::energy::{EnergyColumn, Increment, SegmentBooks};
use crate::events;

mod combinations;
mod crossing;
mod error;
mod integrate;
mod recorder;
mod sample_times;
mod shared_forms;
mod stall;
mod step_guards;
mod stepper;
mod time_scale;
mod trajectory;
use crate::nonlinear::NonlinearForms;
use crate::numeric::{ModeForms, NumericGuard, NumericMode, Storage, dot};
use crate::ode::Tolerances;
use crate::propagate::SegmentBuffers;
use crossing::{Crossed, Trigger};
pub use error::SimError;
use recorder::{Recorded, Recorder, Switched, Why};
use sample_times::SampleTimes;
pub use stall::{STALLED_SEGMENTS, Stall};
pub use stepper::Stepper;
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
    /// The integrator's tolerances in nonlinear modes (linear modes are propagated
    /// exactly): by default [`TOLERANCES`].
    pub tolerances: Tolerances,
}

/// The integrator's default tolerances for nonlinear modes.
///
/// Relative 1e-10; the absolute part of each state's tolerance is 1e-3 of that times the
/// largest magnitude the state has had in the segment, with a floor of 1e-18 (in the state's
/// SI unit) for a state that starts at zero.
pub const TOLERANCES: Tolerances = Tolerances {
    relative: 1e-10,
    absolute: 1e-18,
    peak_fraction: 1e-3,
};

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_events: bondgraph_core::limits::MAX_EVENTS,
            max_steps: bondgraph_core::limits::MAX_STEPS,
            chatter_events: 200,
            chatter_window: 1e-6,
            chatter_time_scales: 1.0,
            tolerances: TOLERANCES,
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

/// Modes looked up by value, hashed fast (a fit looks one up at every event): the keys are
/// the model's own modes, never an adversary's.
type ModeMap<V> = HashMap<Mode, V, foldhash::fast::FixedState>;

pub use shared_forms::SharedForms;

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
    /// Each nonlinear mode's expressions, kept when the parameter values change.
    nonlinear_forms: ModeMap<Arc<NonlinearForms>>,
    /// The forms shared with other simulators of the model, if any.
    shared_forms: Option<Arc<SharedForms>>,
    /// Each mode with the current values in.
    numeric: ModeMap<Arc<NumericMode>>,
    /// Each mode with the values before the last change, whose eigendecompositions the
    /// new values may leave as they were ([`NumericMode::from_forms_beside`]).
    previous: ModeMap<Arc<NumericMode>>,
    settings: Settings,
    /// Energies recorded after the outputs, by name.
    energy_columns: Vec<(String, EnergyColumn)>,
    /// Event location's buffers, kept from segment to segment and run to run.
    scratch: events::Scratch,
    /// The last segment's vectors, for the next.
    segment_buffers: SegmentBuffers,
    /// The last integrated segment's integrator, its buffers for the next (boxed: it is
    /// about a kilobyte, moved in and out at every segment).
    integrator: Option<Box<crate::ode::Switching>>,
    /// The last integrated segment's tape buffers, for the next of its mode.
    workspace: Option<integrate::Workspace>,
}

impl<'m> Simulator<'m> {
    /// A simulator of `model` recording `outputs`.
    pub fn new(model: &'m Model, outputs: Vec<Output>) -> Self {
        Self {
            model,
            storage: Storage::of(model),
            outputs,
            values: model.values().to_vec(),
            symbolic: ModeCache::new(model, Options::default()),
            forms: ModeMap::default(),
            nonlinear_forms: ModeMap::default(),
            shared_forms: None,
            numeric: ModeMap::default(),
            previous: ModeMap::default(),
            settings: Settings::default(),
            energy_columns: Vec::new(),
            scratch: events::Scratch::default(),
            segment_buffers: SegmentBuffers::default(),
            integrator: None,
            workspace: None,
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

    /// Takes linear modes' forms from `shared`, and puts those it derives there, where
    /// `shared` serves this model (this very value) with these outputs: the first simulator
    /// handed it binds it so ([`SharedForms`]); any other derives its own.
    pub fn with_shared_forms(mut self, shared: Arc<SharedForms>) -> Self {
        if shared.serves(self.model, &self.outputs) {
            self.shared_forms = Some(shared);
        }
        self
    }

    /// The limits on numerical trouble and the integrator's tolerances.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Integrates nonlinear modes to `tolerances` from now on.
    pub fn set_tolerances(&mut self, tolerances: Tolerances) {
        self.settings.tolerances = tolerances;
    }

    /// Substitutes other parameter values (indexed like [`Model::values`]) from now on,
    /// keeping the symbolic modes derived so far: the fast path of a calibration, which
    /// changes numbers but never the structure.
    ///
    /// # Errors
    /// [`SimError::Inputs`] when `values` does not have one value per parameter of the model.
    pub fn set_parameter_values(&mut self, values: &[f64]) -> Result<(), SimError> {
        if values.len() != self.model.values().len() {
            return Err(SimError::Inputs(format!(
                "{} parameter values given, but model '{}' has {} parameters",
                values.len(),
                self.model.name(),
                self.model.values().len()
            )));
        }
        if values != self.values.as_slice() {
            self.values = values.to_vec();
            self.storage = Storage::with_values(self.model, values);
            // The modes at the values before, where the new ones have any: a mode a fit's
            // trial no longer visits keeps its older form to be reused.
            for (mode, numeric) in self.numeric.drain() {
                self.previous.insert(mode, numeric);
            }
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
                let shared = self.shared_forms.as_ref().and_then(|s| s.get(mode));
                let forms = match shared {
                    Some(forms) => forms,
                    None => {
                        let derived = self.symbolic.get(mode).map_err(SimError::Derivation)?;
                        let outputs: Vec<_> = self
                            .outputs
                            .iter()
                            .map(|o| derived.equations.output(&o.spec).row)
                            .collect();
                        let forms = Arc::new(ModeForms::new(self.model, &derived, &outputs));
                        if let Some(shared) = &self.shared_forms {
                            shared.insert(mode, &forms);
                        }
                        forms
                    }
                };
                self.forms.insert(mode.clone(), forms.clone());
                forms
            }
        };
        let numeric = Arc::new(NumericMode::from_forms_beside(
            &forms,
            &self.values,
            &self.storage,
            self.previous.get(mode).map(|previous| &**previous),
        ));
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
        // A nonlinear mode's outputs are one tape: evaluated once for all of them.
        let compiled =
            (mode.nonlinear.as_ref()).filter(|_| self.outputs.iter().any(|o| !o.integral));
        let tape_values = compiled.map(|nl| {
            nl.outputs
                .eval_alloc(&crate::nonlinear::tape_input(x, u, rate))
        });
        self.outputs
            .iter()
            .enumerate()
            .map(|(k, output)| {
                let row = &mode.outputs[k];
                if output.integral {
                    integrals[k] + integrated(row, integral_state, u0, u1, tau)
                } else if let (Some(values), Some(program)) = (&tape_values, &row.program) {
                    values[program.value]
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
        // Where no combination is consistent, a guard entered only because it is level on
        // its threshold is set aside ([`Entry::Level`]): its rate, judged zero against the
        // rounding of its terms, may be real. A friction contact whose breakaway force
        // exceeds its Coulomb force by less than the rounding of its forces (1.7e-8 N at
        // 8.3 N) on a stiff body (a 5e-15 kg tip) slips with an acceleration (1.4e7 m/s²,
        // from that difference) that its terms (1.5e16) call level, and the second
        // derivative that then decides is the stiff body's relaxation (4e-18 s), not the
        // contact's motion: each slip direction sends it to the other, and stuck breaks
        // away. Setting the level guards aside leaves the slip the stuck mode breaks into.
        let mut best: Option<((usize, usize), Arc<NumericMode>)> = None;
        for level_counts in [true, false] {
            if best.is_some() {
                break;
            }
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
                if !self.consistent(&numeric, (full, u, rate), crossed, level_counts)? {
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
    /// only while its relative velocity is not leaving the band, and a guard entered only
    /// because it is level on its threshold ([`Entry::Level`]) only if `level_counts`.
    fn consistent(
        &mut self,
        mode: &NumericMode,
        (full, u, rate): (&[f64], &[f64], &[f64]),
        crossed: Option<&Crossed>,
        level_counts: bool,
    ) -> Result<bool, SimError> {
        let x = mode.project(full, u);
        for guard in &mode.guards {
            match self.entry(mode, guard, &x, u, rate, crossed) {
                Entry::Clear => continue,
                Entry::Level if !level_counts => continue,
                Entry::Level | Entry::Decided => {}
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
        self.entry(mode, guard, x, u, rate, crossed) != Entry::Clear
    }

    /// How a guard stands at entry: clear of its threshold, entered by its value or its
    /// rate, or entered only because it is level on its threshold and its second
    /// derivative turns it in ([`Entry::Level`]).
    fn entry(
        &self,
        mode: &NumericMode,
        guard: &NumericGuard,
        x: &[f64],
        u: &[f64],
        rate: &[f64],
        crossed: Option<&Crossed>,
    ) -> Entry {
        let value = guard.row.eval(x, u, rate);
        let tolerance = threshold_rounding(&guard.row, x, u, rate);
        let on_crossed_threshold = crossed.is_some_and(|c| c.watches_as(guard, value, tolerance));
        let decided = |entered: bool| {
            if entered {
                Entry::Decided
            } else {
                Entry::Clear
            }
        };
        if !on_crossed_threshold {
            if value > tolerance {
                return Entry::Decided;
            }
            if value < -tolerance {
                return Entry::Clear;
            }
        }
        let first = mode.row_rate(&guard.row, x, u, rate);
        let rate_tolerance = 1e-9 * mode.row_rate_magnitude(&guard.row, x, u, rate);
        if first.abs() > rate_tolerance {
            return decided(first > 0.0);
        }
        // On the threshold and level: a string at zero extension with its mass at rest, or a
        // contact whose breakaway force equals its Coulomb force slipping at the instant the
        // force it would have to hold is the breakaway force (its acceleration is then zero
        // up to rounding, whose sign must not decide). The second derivative (the rate an
        // instant later) decides; if it too is zero up to rounding the guard is at rest on its
        // threshold (a contact holding exactly its breakaway force, zero at a balance with no
        // breakaway), which leaves the mode nothing to leave for.
        let (second, rounding) = second_rate(mode, &guard.row, x, u, rate);
        if second > rounding {
            Entry::Level
        } else {
            Entry::Clear
        }
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

/// How a guard stands at the instant a mode is entered ([`Simulator::entry`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Entry {
    /// Below its threshold, or on it and moving away.
    Clear,
    /// Past its threshold, or on it and moving in.
    Decided,
    /// On its threshold and level there (value and rate zero to the rounding of their
    /// terms), its second derivative turning it in.
    Level,
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

/// The second time derivative of a guard row along the mode's flow, inputs moving at
/// `rate`, and the rounding it carries: the difference of its first derivative over a step
/// along `dx/dt`, exact for a linear mode (where the first derivative is affine) whatever the
/// step, judged against `1e-9` of the terms of the two rates (as a rate is judged against
/// its own terms; zero for a nonlinear mode, whose rates are judged exactly).
/// The rounding of a guard's value at `x`: `1e-9` of its terms, against which
/// [`Simulator::entered`] judges a value to be at its threshold.
fn threshold_rounding(row: &crate::numeric::Row, x: &[f64], u: &[f64], rate: &[f64]) -> f64 {
    1e-9 * row.magnitude(x, u, rate) + f64::MIN_POSITIVE
}

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
