//! What a simulation records as it goes: samples of its outputs, the modes it visits and
//! when, and its events.
//!
//! Events are kept as the modes and guards themselves and put into words ([`Event`]) only
//! when read: a steady-state search records them by the thousand and reads none.

use std::fmt;
use std::sync::Arc;

use bondgraph_core::guards::Watched;
use bondgraph_core::model::{ElementId, ElementMode, Model};

use super::{Event, Stats, Trajectory};
use crate::numeric::{NumericGuard, NumericMode};

/// Why a guard switched its element, put into words only when an event is read: a
/// steady-state search records events by the thousand and reads none of them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Why {
    watched: Watched,
    leaves_to: ElementMode,
    /// Crossed while the mode ran, rather than found entered when the mode began.
    crossed: bool,
}

impl Why {
    /// Why `guard` fires, crossed while its mode ran or found entered at the mode's start.
    pub(super) fn of(guard: &NumericGuard, crossed: bool) -> Self {
        Why {
            watched: guard.watched,
            leaves_to: guard.leaves_to,
            crossed,
        }
    }
}

impl fmt::Display for Why {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let what = match (self.watched, self.leaves_to) {
            (Watched::HoldingForce, ElementMode::SlipPositive) => {
                "holding force reached the breakaway force"
            }
            (Watched::HoldingForce, _) => "holding force reached minus the breakaway force",
            (Watched::RelativeVelocity, ElementMode::Stuck) => {
                "relative velocity entered the dead band and static friction holds"
            }
            (Watched::RelativeVelocity, _) => "relative velocity passed through zero",
            (Watched::StribeckVelocity, ElementMode::SlipPositive | ElementMode::SlipNegative) => {
                "relative velocity passed the Stribeck velocity"
            }
            (Watched::StribeckVelocity, _) => "relative velocity fell below the Stribeck velocity",
            (Watched::Tension, _) => "tension fell to zero",
            (Watched::SlackLength, _) => "slack taken up",
            (Watched::LimitedFlow, _) => "flow reached its limit",
            (Watched::RestrainingEffort, _) => "restraining effort fell to zero",
        };
        let how = if self.crossed { "" } else { " (at entry)" };
        write!(f, "{what}{how}")
    }
}

/// The element an event switched: one, or a combination found together (by name, joined).
#[derive(Clone, Debug)]
pub(super) enum Switched {
    Element(ElementId),
    Elements(String),
}

/// An event as recorded: the modes themselves, worded as an [`Event`] when read.
#[derive(Clone, Debug)]
pub(super) struct Recorded {
    pub t: f64,
    pub from: Arc<NumericMode>,
    pub to: Arc<NumericMode>,
    pub element: Switched,
    /// `None`: no single switch was consistent and this combination was.
    pub why: Option<Why>,
}

impl Recorded {
    /// The event in words.
    pub fn to_event(&self, model: &Model) -> Event {
        Event {
            t: self.t,
            from: self.from.spec.clone(),
            to: self.to.spec.clone(),
            element: match &self.element {
                Switched::Element(id) => model.element(*id).name.clone(),
                Switched::Elements(names) => names.clone(),
            },
            reason: self.why.map_or_else(
                || "no single switch is consistent; this combination is".to_string(),
                |why| why.to_string(),
            ),
        }
    }
}

/// Collects samples, modes and events.
pub(super) struct Recorder {
    pub output_names: Vec<String>,
    times: Vec<f64>,
    values: Vec<f64>,
    sample_modes: Vec<usize>,
    pub modes: Vec<String>,
    intervals: Vec<(f64, f64, usize)>,
    pub events: Vec<Recorded>,
    /// The first sample with an output that is not finite: its time, mode index and the
    /// outputs concerned.
    pub non_finite: Option<(f64, usize, Vec<usize>)>,
}

impl Recorder {
    pub fn new(output_names: Vec<String>) -> Self {
        Self {
            output_names,
            times: Vec::new(),
            values: Vec::new(),
            sample_modes: Vec::new(),
            modes: Vec::new(),
            intervals: Vec::new(),
            events: Vec::new(),
            non_finite: None,
        }
    }

    pub fn mode_index(&mut self, spec: &str) -> usize {
        match self.modes.iter().position(|m| m == spec) {
            Some(i) => i,
            None => {
                self.modes.push(spec.to_string());
                self.modes.len() - 1
            }
        }
    }

    pub fn enter(&mut self, spec: &str, t: f64) {
        let index = self.mode_index(spec);
        if let Some(last) = self.intervals.last_mut() {
            last.1 = t;
            if last.2 == index {
                return;
            }
        }
        self.intervals.push((t, t, index));
    }

    pub fn sample(&mut self, t: f64, spec: &str, values: impl IntoIterator<Item = f64>) {
        let index = self.mode_index(spec);
        self.sample_in(t, index, values);
    }

    /// A sample in the mode of index `mode` (see [`Recorder::mode_index`]).
    pub fn sample_in(&mut self, t: f64, mode: usize, values: impl IntoIterator<Item = f64>) {
        let start = self.values.len();
        self.times.push(t);
        self.values.extend(values);
        self.sample_modes.push(mode);
        if self.non_finite.is_none() && self.values[start..].iter().any(|v| !v.is_finite()) {
            let bad = (0..self.values.len() - start)
                .filter(|&k| !self.values[start + k].is_finite())
                .collect();
            self.non_finite = Some((t, mode, bad));
        }
    }

    pub fn event(&mut self, event: Recorded) {
        self.events.push(event);
    }

    pub fn finish(
        mut self,
        model: &Model,
        end: f64,
        final_state: Vec<(String, f64)>,
        final_mode: String,
        stats: Stats,
    ) -> Trajectory {
        if let Some(last) = self.intervals.last_mut() {
            last.1 = end;
        }
        Trajectory {
            output_names: self.output_names,
            times: self.times,
            values: self.values,
            sample_modes: self.sample_modes,
            modes: self.modes,
            intervals: self.intervals,
            events: self.events.iter().map(|e| e.to_event(model)).collect(),
            final_time: end,
            final_state,
            final_mode,
            stats,
            energy: None,
        }
    }
}
