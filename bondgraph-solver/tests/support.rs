//! Helpers shared by the solver's tests.

use bondgraph_core::model::{self, Model};
use bondgraph_solver::Signal;

/// Loads a model by its path relative to the repository root.
pub fn load(relative: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    model::load_str(relative, &text).unwrap_or_else(|e| panic!("{relative}:\n{e}"))
}

/// A constant input.
pub struct Constant(pub f64);

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

/// `initial + slope·t`, clamped at `ceiling`.
pub struct Ramp {
    pub initial: f64,
    pub slope: f64,
    pub ceiling: f64,
}

impl Signal for Ramp {
    fn value(&self, t: f64) -> f64 {
        (self.initial + self.slope * t).min(self.ceiling)
    }
    fn rate(&self, t: f64) -> f64 {
        if t < self.breakpoints()[0] {
            self.slope
        } else {
            0.0
        }
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![(self.ceiling - self.initial) / self.slope]
    }
}
