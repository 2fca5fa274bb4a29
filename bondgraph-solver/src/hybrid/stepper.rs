//! A simulation in progress, advanced piece by piece: the event loop of a run (segments,
//! crossings, switches, samples), shared by runs to a fixed time and by steady-state
//! searches that decide how far to go as they learn the trajectory.

use std::collections::VecDeque;
use std::sync::Arc;

use bondgraph_core::model::ElementId;
use bondgraph_core::modes::Mode;
use num_complex::Complex64;

use super::*;
use crate::energy::EnergyBalance;
use crate::events;
use crate::numeric::{NumericGuard, NumericMode, dot};

/// A simulation in progress, advanced piece by piece: for runs to a fixed time and for
/// steady-state searches that decide how far to go as they learn the trajectory.
pub struct Stepper<'s, 'm> {
    pub(super) simulator: &'s mut Simulator<'m>,
    pub(super) inputs: &'s [&'s dyn Signal],
    pub(super) breakpoints: Vec<f64>,
    pub(super) t: f64,
    pub(super) x: Vec<f64>,
    pub(super) mode: Arc<NumericMode>,
    pub(super) armed: Vec<bool>,
    /// The level below which each guard is armed: zero, or minus the rounding tolerance
    /// after its switch was declined.
    pub(super) arm_below: Vec<f64>,
    /// The level each guard must rise to before it fires: zero, or the rounding of its terms
    /// for a guard whose crossing led straight back to the mode it left (see
    /// [`Stepper::switch_at`]).
    pub(super) fire_above: Vec<f64>,
    pub(super) integrals: Vec<f64>,
    /// The last switches: when, and the fastest rate (`max |λ|`) of the mode entered, zero
    /// where unknown (a nonlinear mode).
    pub(super) recent: VecDeque<(f64, f64)>,
    pub(super) sample: Option<SampleTimes>,
    /// The index of the next sample.
    pub(super) next_sample: u64,
    pub(super) recorder: Recorder,
    pub(super) stats: Stats,
    pub(super) energy: Option<EnergyBalance>,
    /// The element and reason of the last crossing found, and whether its switch was
    /// declined, for a stalled run's message.
    pub(super) last_crossing: Option<(ElementId, Why, bool)>,
    /// Steps taken: integration steps and event-location samples.
    pub(super) steps: u64,
}

impl<'s, 'm> Stepper<'s, 'm> {
    /// Integrates nonlinear modes to `tolerances` from here on.
    pub(crate) fn set_tolerances(&mut self, tolerances: crate::ode::Tolerances) {
        self.simulator.set_tolerances(tolerances);
    }

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
        if inputs.len() != model.inputs().len() {
            return Err(SimError::Inputs(format!(
                "model '{}' has {} inputs but {} signals were given",
                model.name(),
                model.inputs().len(),
                inputs.len()
            )));
        }
        if initial_state.len() != simulator.storage.len() {
            return Err(SimError::Inputs(format!(
                "the initial state has {} values but model '{}' stores energy in {} elements",
                initial_state.len(),
                model.name(),
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
    pub(super) fn books(&self) -> (f64, f64) {
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
            // The first breakpoint after now (sorted: a search, as a recorded signal has
            // one at every sample).
            let next = self.breakpoints.partition_point(|&b| b <= self.t);
            let end = self.breakpoints.get(next).map_or(until, |&b| b.min(until));
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
        let (crossing, stop, stop_time) =
            self.locate_in_closed_form(&current, &mut segment, (&u0, &u1), length, end)?;

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
            let modal = modal_outputs(&current, &segment, &u0, &u1, n);
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

    /// Locates the first crossing of `current`'s guards within `length` of the segment
    /// (or as far as their samples follow its oscillations): the crossing, how far the
    /// segment goes, and the time it ends at.
    fn locate_in_closed_form(
        &mut self,
        current: &NumericMode,
        segment: &mut crate::propagate::Segment<'_>,
        (u0, u1): (&[f64], &[f64]),
        length: f64,
        end: f64,
    ) -> Result<(Option<events::Crossing>, f64, f64), SimError> {
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
            current,
            segment,
            u0,
            u1,
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
        Ok(match located {
            events::Located::Crossing(c) => (Some(c), c.tau, event_time(self.t, c.tau, end)),
            events::Located::Clear(reached) if reached < length => {
                (None, reached, self.t + reached)
            }
            events::Located::Clear(_) => (None, length, end),
        })
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
            self.arm_below[crossing.guard] = -threshold_rounding(&guard.row, &self.x, &u, &rate);
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
        // A guard the mode is entered on level (zero to the rounding of its terms, and its
        // rate too) whose second derivative takes it away from its threshold rests there, and
        // fires only once clearly past it. A contact breaking away at exactly its breakaway
        // force enters its creep at zero relative velocity with zero acceleration; read from
        // the segment's eigen-coordinates an instant later, the velocity was a rounding below
        // zero, the guard to stick fired, and the contact stuck and broke away again, 200
        // times at one instant.
        for (k, guard) in self.mode.guards.iter().enumerate() {
            if level_on_threshold(&self.mode, &guard.row, &self.x, &u, &rate)
                .is_some_and(|(second, rounding)| second < -rounding)
            {
                self.fire_above[k] = threshold_rounding(&guard.row, &self.x, &u, &rate);
            }
        }
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
        self.fire_above[k] = threshold_rounding(&guard.row, &self.x, u, rate);
    }

    /// Counts `count` more steps; whether the run is now past its limit.
    pub(super) fn over_step_limit(&mut self, count: u64) -> bool {
        self.steps += count;
        self.steps > self.simulator.settings.max_steps
    }

    /// The error of a run past its limit of steps at `t`, with the last integration step and
    /// the mode's fastest time scale there where known.
    pub(super) fn too_many_steps(
        &self,
        t: f64,
        step: Option<f64>,
        time_scale: Option<TimeScale>,
    ) -> SimError {
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

/// Each output of `current` on a segment with eigenvectors, as `(c, a, b)`: in
/// eigen-coordinates the output is Re(Σ c_j z_j(τ)) + a + b τ (and its integral
/// Re(Σ c_j ∫z_j) + a τ + b τ²/2), with c = row V, a = d·u₀ + r·u₁ + k, b = d·u₁. `None` for
/// a segment without eigenvectors.
#[allow(clippy::type_complexity)]
fn modal_outputs(
    current: &NumericMode,
    segment: &crate::propagate::Segment<'_>,
    u0: &[f64],
    u1: &[f64],
    n: usize,
) -> Option<Vec<(Vec<Complex64>, f64, f64)>> {
    segment.vectors().map(|v| {
        current
            .outputs
            .iter()
            .map(|row| {
                let c = (0..n)
                    .map(|j| (0..n).map(|i| v[(i, j)] * row.state[i]).sum())
                    .collect();
                let a = dot(&row.input, u0) + dot(&row.rate, u1) + row.constant;
                (c, a, dot(&row.input, u1))
            })
            .collect()
    })
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
    level_on_threshold(mode, &guard.row, x, u, rate)
        .is_some_and(|(second, rounding)| second <= rounding)
}

/// For a guard on its threshold and level there (its value and its rate zero to the
/// rounding of their terms), its second derivative and that derivative's rounding, which
/// decide whether it turns into the threshold, rests on it, or leaves it.
fn level_on_threshold(
    mode: &NumericMode,
    row: &crate::numeric::Row,
    x: &[f64],
    u: &[f64],
    rate: &[f64],
) -> Option<(f64, f64)> {
    if row.eval(x, u, rate).abs() > threshold_rounding(row, x, u, rate) {
        return None;
    }
    let first = mode.row_rate(row, x, u, rate);
    if first.abs() > 1e-9 * mode.row_rate_magnitude(row, x, u, rate) {
        return None;
    }
    Some(second_rate(mode, row, x, u, rate))
}

/// Whether a guard watches an effort (a holding force, a tension, a restraining effort).
fn watches_an_effort(guard: &NumericGuard) -> bool {
    matches!(
        guard.watched,
        Watched::HoldingForce | Watched::Tension | Watched::RestrainingEffort
    )
}
