//! What a run gives back: the recorded outputs at their sample times, the modes and events on
//! the way, the final state, the work it took and the energy books.

use crate::energy::EnergyBalance;

/// A mode change.
#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    /// When, in seconds.
    pub t: f64,
    /// The mode left.
    pub from: String,
    /// The mode entered.
    pub to: String,
    /// The switching element.
    pub element: String,
    /// Why, in words.
    pub reason: String,
}

/// Counts that show the work a run took.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Segments propagated.
    pub segments: usize,
    /// Events (mode changes).
    pub events: usize,
    /// Distinct modes used.
    pub modes: usize,
}

/// A simulated trajectory.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// The outputs' names.
    pub output_names: Vec<String>,
    /// Sample times.
    pub times: Vec<f64>,
    /// The outputs at the sample times, row-major: output `j` of sample `k` is
    /// `values[k * output_names.len() + j]` (see [`Trajectory::value`]).
    pub values: Vec<f64>,
    /// The mode at each sample time (index into `modes`).
    pub sample_modes: Vec<usize>,
    /// The modes visited, by specification.
    pub modes: Vec<String>,
    /// The time intervals spent in each mode: `(start, end, mode index)`.
    pub intervals: Vec<(f64, f64, usize)>,
    /// The mode changes.
    pub events: Vec<Event>,
    /// The end time.
    pub final_time: f64,
    /// The full state at the end: energy variable names and values.
    pub final_state: Vec<(String, f64)>,
    /// The final mode.
    pub final_mode: String,
    /// Work counts.
    pub stats: Stats,
    /// The energy books, when asked for or recorded.
    pub energy: Option<EnergyBalance>,
}

impl Trajectory {
    /// Output `output` at sample `sample`, if recorded.
    pub fn value(&self, sample: usize, output: usize) -> Option<f64> {
        let width = self.output_names.len();
        if output >= width {
            return None;
        }
        self.values.get(sample * width + output).copied()
    }

    /// Every output at sample `sample`, if recorded in full.
    pub fn row(&self, sample: usize) -> Option<&[f64]> {
        let width = self.output_names.len();
        self.values.get(sample * width..(sample + 1) * width)
    }
}
