//! Scenarios: how a model is driven in a simulation.
//!
//! A model file says what the system is; a scenario file says what is done to it: the
//! signal on every input, the mode and state it starts in, how long it runs and what is
//! recorded, and which variant of the model is used (elements removed, parameter values
//! changed). Keeping these apart lets one model serve
//! every experiment (each figure of a paper is one scenario), and lets a scenario state
//! its variant of the model in two lines instead of a copy of the model file.
//!
//! `bondgraph_ron::scenario::load` reads a scenario file against its model file and returns
//! a [`Scenario`]: a
//! value free of RON in which every name is resolved against the edited model and every
//! number is checked, so that the solver that consumes it cannot fail on bad input. Every
//! problem is a [`Diagnostic`] pointing into the scenario file (the model's own problems
//! point into the model file).
//!
//! ```ron
//! Scenario(
//!     name: "ramp",
//!     description: "The rig without its second load, driven by a ramp.",   // optional
//!     remove: ["load_2", "fr_2", "v_2"],
//!     parameters: { "dv": 1e-6 },                   // optional: parameter values set
//!     inputs: {                                     // a signal for every input the model uses
//!         "F": Ramp(slope: 100.0, ceiling: 20.0),   // start: 0, initial: 0 by default
//!         "v_belt": Constant(5.8e-3),
//!     },
//!     initial_mode: "fr=stuck,k=slack",             // optional: the model's initial mode
//!     initial_state: { "k": -1.0e-4 },             // optional: p or q by storage element
//!     duration: 0.2,                                // seconds
//!     record: ["flow:mass", "effort:k", "integral:flow:mass"],
//!     sample: 1.0e-4,                               // optional: output interval
//! )
//! ```
//!
//! Besides bond outputs and their integrals, `record` takes energies ([`energy`]):
//! `energy:ELEMENT` (the energy a storage element holds, J), `power:ELEMENT` (the power into
//! a one-port along its bond, W) and the books `energy:supplied`, `energy:stored`,
//! `energy:dissipated` (J since time 0).
//!
//! The other signals are `Step(at: 0.05, before: 0.0, after: 6.3e-3)` and
//! `Table([(0.0, 0.0), (1.0, 2.0)])` (piecewise linear in time).

use std::fmt;
use std::sync::Arc;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Result};
use crate::equations::OutputSpec;
use crate::mode::Mode;
use crate::model::{ElementId, Model};
use crate::source::SourceFile;

pub mod energy;
mod table;
pub use energy::{Book, EnergyRecord};
pub use table::TableCursor;
use table::{segment, table_breakpoints, table_rate, table_value};

/// A time signal driving one input of the model.
#[derive(Clone, Debug, PartialEq)]
pub enum Signal {
    /// The same value at all times.
    Constant(f64),
    /// `before` until time `at`, `after` from then on.
    Step {
        /// When it steps, in seconds.
        at: f64,
        /// The value before `at`.
        before: f64,
        /// The value from `at` on.
        after: f64,
    },
    /// `initial` until `start`, then `initial + slope·(t - start)`, held once it reaches
    /// `ceiling` (a limit in the direction of the slope: below the start for a falling ramp).
    Ramp {
        /// When it starts to change, in seconds.
        start: f64,
        /// The value until `start`.
        initial: f64,
        /// The rate of change from `start` on, per second.
        slope: f64,
        /// The value it stops at, if any.
        ceiling: Option<f64>,
    },
    /// Piecewise linear through `(time, value)` points with strictly increasing times;
    /// the first value before the first point and the last after the last.
    Table(Vec<(f64, f64)>),
}

impl Signal {
    /// The value at time `t` (right-continuous: a step's value at `at` is `after`). An
    /// empty table, which a scenario file never gives, is 0.
    pub fn value(&self, t: f64) -> f64 {
        match self {
            Signal::Constant(value) => *value,
            Signal::Step { at, before, after } => {
                if t < *at {
                    *before
                } else {
                    *after
                }
            }
            Signal::Ramp {
                start,
                initial,
                slope,
                ceiling,
            } => {
                if t < *start {
                    return *initial;
                }
                let value = initial + slope * (t - start);
                match ceiling {
                    Some(c) if *slope > 0.0 => value.min(*c),
                    Some(c) if *slope < 0.0 => value.max(*c),
                    _ => value,
                }
            }
            Signal::Table(points) => table_value(points, segment(points, t), t),
        }
    }

    /// The rate of change at time `t`, from the right (so at a ramp's start it is the
    /// slope, and when it reaches its ceiling 0).
    pub fn rate(&self, t: f64) -> f64 {
        match self {
            Signal::Constant(_) | Signal::Step { .. } => 0.0,
            Signal::Ramp { start, slope, .. } => {
                let held = self.ceiling_time().is_some_and(|tc| t >= tc);
                if t < *start || held { 0.0 } else { *slope }
            }
            Signal::Table(points) => table_rate(segment(points, t)),
        }
    }

    /// The times at which the value or the rate jumps, in increasing order: a step's time,
    /// a ramp's start and the time it reaches its ceiling, a table's points where its slope
    /// changes (not the samples a held or ramped stretch passes through). An integrator
    /// should stop at each rather than step across it.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            Signal::Constant(_) => Vec::new(),
            Signal::Step { at, .. } => vec![*at],
            Signal::Ramp { start, .. } => {
                let mut times = vec![*start];
                times.extend(self.ceiling_time().filter(|tc| tc > start));
                times
            }
            Signal::Table(points) => table_breakpoints(points),
        }
    }

    /// When a ramp reaches its ceiling (at or after its start for a ramp that a scenario
    /// file may have); `None` for other signals and for a ramp without ceiling or slope.
    pub fn ceiling_time(&self) -> Option<f64> {
        match self {
            Signal::Ramp {
                start,
                initial,
                slope,
                ceiling: Some(c),
            } if *slope != 0.0 => Some(start + (c - initial) / slope),
            _ => None,
        }
    }
}

impl fmt::Display for Signal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Signal::Constant(value) => write!(f, "constant {}", crate::number::readable(*value)),
            Signal::Step { at, before, after } => write!(
                f,
                "step from {} to {} at t = {} s",
                crate::number::readable(*before),
                crate::number::readable(*after),
                crate::number::readable(*at)
            ),
            Signal::Ramp {
                start,
                initial,
                slope,
                ceiling,
            } => {
                write!(
                    f,
                    "ramp from {} at t = {} s with slope {}/s",
                    crate::number::readable(*initial),
                    crate::number::readable(*start),
                    crate::number::readable(*slope)
                )?;
                match ceiling {
                    Some(c) if *slope < 0.0 => {
                        write!(f, ", down to {}", crate::number::readable(*c))
                    }
                    Some(c) => write!(f, ", up to {}", crate::number::readable(*c)),
                    None => Ok(()),
                }
            }
            Signal::Table(points) => {
                let point = |(t, v): &(f64, f64)| {
                    format!(
                        "({}, {})",
                        crate::number::readable(*t),
                        crate::number::readable(*v)
                    )
                };
                if points.len() <= 4 {
                    let all: Vec<String> = points.iter().map(point).collect();
                    write!(f, "table through {}", all.join(", "))
                } else {
                    write!(
                        f,
                        "table of {} points from {} to {}",
                        points.len(),
                        point(&points[0]),
                        point(&points[points.len() - 1])
                    )
                }
            }
        }
    }
}

/// An output to record.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Record {
    /// A bond's effort or flow (`flow:ge`).
    Output(OutputSpec),
    /// The time integral of a bond's effort or flow (`integral:flow:ge`: a displacement).
    Integral(OutputSpec),
    /// An energy or a power (`energy:spring`, `power:damper`, `energy:supplied`; see
    /// [`energy`]), with its name as written.
    Energy(String, EnergyRecord),
}

impl Record {
    /// Parses an output as `--output` and scenarios' `record` write it: `effort:ELEMENT`,
    /// `flow:FROM->TO`, `integral:OUTPUT` for its time integral, or an energy record
    /// (`energy:ELEMENT`, `power:ELEMENT`, `energy:supplied|stored|dissipated`).
    ///
    /// # Errors
    /// As [`OutputSpec::parse`] and [`EnergyRecord::parse`].
    pub fn parse(model: &Model, text: &str) -> Result<Self> {
        let trimmed = text.trim();
        if let Some(energy) = EnergyRecord::parse(model, trimmed) {
            return Ok(Record::Energy(trimmed.to_string(), energy?));
        }
        match trimmed.strip_prefix("integral:") {
            Some(rest) => Ok(Record::Integral(OutputSpec::parse(model, rest.trim())?)),
            None => Ok(Record::Output(OutputSpec::parse(model, trimmed)?)),
        }
    }

    /// Parses an output of the state equations (`--output`): as [`Record::parse`], with the
    /// bond output it stands for; an energy record is an error, since energies and powers
    /// are products of bond variables, not rows of `y = C x + D u`.
    ///
    /// # Errors
    /// As [`Record::parse`], and a [`DiagnosticKind::BadOutput`] for an energy record.
    pub fn parse_output(model: &Model, text: &str) -> Result<(Self, OutputSpec)> {
        let not_a_row = || -> crate::diagnostics::Diagnostics {
            Diagnostic::new(
                DiagnosticKind::BadOutput,
                format!(
                    "--output '{}': energies and powers are not rows of the output equations y = C x + D u",
                    text.trim()
                ),
            )
            .note("record them in a scenario (bondgraph simulate) instead")
            .into()
        };
        // Any energy or power, valid for a scenario's record or not, is the wrong kind of
        // output here: say that, not what a record would need.
        if EnergyRecord::parse(model, text.trim()).is_some() {
            return Err(not_a_row());
        }
        let record = Self::parse(model, text)?;
        match record.spec().cloned() {
            Some(spec) => Ok((record, spec)),
            None => Err(not_a_row()),
        }
    }

    /// The bond output being recorded, or integrated; `None` for an energy record.
    pub fn spec(&self) -> Option<&OutputSpec> {
        match self {
            Record::Output(spec) | Record::Integral(spec) => Some(spec),
            Record::Energy(..) => None,
        }
    }

    /// The record's name as written: `flow:ge`, `integral:flow:ge`, `energy:spring`.
    pub fn name(&self) -> String {
        match self {
            Record::Output(spec) => spec.name.clone(),
            Record::Integral(spec) => format!("integral:{}", spec.name),
            Record::Energy(name, _) => name.clone(),
        }
    }

    /// Whether two records record the same quantity, however written.
    pub fn same_as(&self, other: &Record) -> bool {
        let bond = |a: &OutputSpec, b: &OutputSpec| {
            a.quantity == b.quantity && a.bond == b.bond && a.negated == b.negated
        };
        match (self, other) {
            (Record::Output(a), Record::Output(b)) | (Record::Integral(a), Record::Integral(b)) => {
                bond(a, b)
            }
            (Record::Energy(_, a), Record::Energy(_, b)) => match (a, b) {
                (
                    EnergyRecord::Power { element: x, .. },
                    EnergyRecord::Power { element: y, .. },
                ) => x == y,
                _ => a == b,
            },
            _ => false,
        }
    }
}

/// A validated scenario: the edited model and how to drive it.
#[derive(Clone, Debug)]
pub struct Scenario {
    /// The scenario's name.
    pub name: String,
    /// What it shows.
    pub description: Option<String>,
    /// The model, with the scenario's edits applied (its source is the edited text when
    /// there are edits).
    pub model: Model,
    /// The signal of each input, indexed like [`Model::inputs`]. An input that no element
    /// of the edited model uses (one that only removed elements used) and that the scenario
    /// does not give is held at `Constant(0.0)`.
    pub inputs: Vec<Signal>,
    /// The mode at time 0.
    pub initial_mode: Mode,
    /// The energy variable at time 0 (momentum of an inertia, displacement of a compliance
    /// or tension-only element) of each storage element given one, in file order; the
    /// others start at 0.
    pub initial_state: Vec<(ElementId, f64)>,
    /// How long to simulate, in seconds (positive, finite).
    pub duration: f64,
    /// What to record, in file order.
    pub record: Vec<Record>,
    /// The interval between recorded samples, in seconds, if given (positive, finite).
    pub sample: Option<f64>,
    /// The scenario file.
    pub source: Arc<SourceFile>,
}

impl Scenario {
    /// Every input's breakpoints within `[0, duration]`, sorted, without repeats.
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut times: Vec<f64> = self
            .inputs
            .iter()
            .flat_map(Signal::breakpoints)
            .filter(|t| (0.0..=self.duration).contains(t))
            .collect();
        times.sort_by(f64::total_cmp);
        times.dedup();
        times
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_cursor_reads_as_the_table_does_in_any_order() {
        // Values and rates from the right: before the first point, on every point, between
        // points, after the last; read forwards (a run's order), backwards and jumping.
        let points = vec![(0.0, 1.0), (0.5, 3.0), (1.0, 3.0), (2.0, -1.0), (2.5, 0.25)];
        let table = Signal::Table(points.clone());
        let cursor = TableCursor::new(&points);
        let mut times: Vec<f64> = (-4..=12).map(|k| k as f64 * 0.25).collect();
        times.extend([0.1, 0.49999999999999994, 2.5000000000000004, 1e9]);
        let forwards = times.clone();
        let mut backwards = times.clone();
        backwards.reverse();
        let jumping: Vec<f64> = (0..times.len())
            .map(|k| times[(k * 7) % times.len()])
            .collect();
        for order in [forwards, backwards, jumping] {
            for &t in &order {
                assert_eq!(cursor.value(t), table.value(t), "value at {t}");
                assert_eq!(cursor.rate(t), table.rate(t), "rate at {t}");
            }
        }
        // By hand: at 0.25, halfway from 1 to 3, the value 2 and the slope (3 - 1)/0.5 = 4;
        // at the knot 2.0, the knot's value -1 and the next segment's slope (0.25 + 1)/0.5.
        assert_eq!(cursor.value(0.25), 2.0);
        assert_eq!(cursor.rate(0.25), 4.0);
        assert_eq!(cursor.value(2.0), -1.0);
        assert_eq!(cursor.rate(2.0), 2.5);
        assert_eq!(cursor.breakpoints(), vec![0.0, 0.5, 1.0, 2.0, 2.5]);
    }

    #[test]
    fn a_table_breaks_only_where_its_rate_changes() {
        // A recorded set-point sampled every second: 0, a step to 6 between the samples at
        // 2 and 3 s, held, a ramp down through 4, 2 and 0 at 5-8 s, then 0. Its rate is 0
        // until 2 s, 6/s to 3 s, 0 to 5 s, -2/s to 8 s and 0 after: it breaks at 2, 3, 5
        // and 8 s only (the samples between are on one line).
        let values = [0.0, 0.0, 0.0, 6.0, 6.0, 6.0, 4.0, 2.0, 0.0, 0.0, 0.0];
        let points: Vec<(f64, f64)> = values
            .iter()
            .enumerate()
            .map(|(k, &v)| (k as f64, v))
            .collect();
        let expected = [2.0, 3.0, 5.0, 8.0];
        assert_eq!(Signal::Table(points.clone()).breakpoints(), expected);
        assert_eq!(TableCursor::new(&points).breakpoints(), expected);
        // The slopes are compared exactly: sampled at 10 ms (times not exact in binary), the
        // ramp's pieces differ by rounding and its samples stay breakpoints; a held stretch
        // has a slope of exactly zero on every piece, and none.
        let sampled: Vec<(f64, f64)> = points.iter().map(|&(t, v)| (t * 0.01, v)).collect();
        let breaks = Signal::Table(sampled.clone()).breakpoints();
        assert_eq!(breaks[..3], [sampled[2].0, sampled[3].0, sampled[5].0]);
        assert_eq!(breaks.last(), Some(&sampled[8].0));
        // A table's first and last points break where the signal leaves or reaches its
        // held value with a slope, and a constant table has no breakpoint at all.
        let ramp = [(1.0, 0.0), (2.0, 1.0), (3.0, 2.0)];
        assert_eq!(Signal::Table(ramp.to_vec()).breakpoints(), [1.0, 3.0]);
        let held = [(0.0, 5.0), (1.0, 5.0), (2.0, 5.0)];
        assert!(Signal::Table(held.to_vec()).breakpoints().is_empty());
    }

    #[test]
    fn signal_helpers_on_their_own() {
        let falling = Signal::Ramp {
            start: -1.0,
            initial: 10.0,
            slope: -4.0,
            ceiling: Some(2.0),
        };
        assert_eq!(falling.value(-2.0), 10.0);
        assert_eq!(falling.value(0.0), 6.0);
        assert_eq!(falling.value(1.0), 2.0);
        assert_eq!(falling.value(5.0), 2.0);
        assert_eq!((falling.rate(0.999), falling.rate(1.0)), (-4.0, 0.0));
        assert_eq!(falling.breakpoints(), [-1.0, 1.0]);
        assert_eq!(
            falling.to_string(),
            "ramp from 10 at t = -1 s with slope -4/s, down to 2"
        );
        let open = Signal::Ramp {
            start: 0.0,
            initial: 0.0,
            slope: 1.0e6,
            ceiling: None,
        };
        assert_eq!(open.value(1e-3), 1000.0);
        assert_eq!(open.breakpoints(), [0.0]);
        assert_eq!(open.to_string(), "ramp from 0 at t = 0 s with slope 1e6/s");
        assert_eq!(Signal::Constant(5.8e-3).to_string(), "constant 0.0058");
        assert_eq!(Signal::Constant(-2.5e-7).to_string(), "constant -2.5e-7");
        let long = Signal::Table((0..10).map(|i| (f64::from(i), f64::from(i * i))).collect());
        assert_eq!(
            long.to_string(),
            "table of 10 points from (0, 0) to (9, 81)"
        );
        assert_eq!(long.value(2.5), 6.5);
        let single = Signal::Table(vec![(1.0, 4.0)]);
        assert_eq!(
            (single.value(0.0), single.value(1.0), single.value(2.0)),
            (4.0, 4.0, 4.0)
        );
        assert_eq!(single.rate(1.0), 0.0);
        let empty = Signal::Table(Vec::new());
        assert_eq!((empty.value(0.0), empty.rate(0.0)), (0.0, 0.0));
    }
}
