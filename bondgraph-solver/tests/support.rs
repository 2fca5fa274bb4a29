//! Helpers shared by the solver's tests.

use bondgraph_core::model::Model;
use bondgraph_solver::Signal;

/// Loads a model by its path relative to the repository root.
pub fn load(relative: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    bondgraph_ron::model::load_str(relative, &text).unwrap_or_else(|e| panic!("{relative}:\n{e}"))
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

/// A mass in a double well, `m q̈ + b q̇ - k q + k₃ q³ = 0`: wells at `q = ±√(k/k₃) = ±1`, a
/// saddle at 0.
pub const DOUBLE_WELL: &str = r#"Model(
    name: "double_well",
    parameters: {
        "m": (value: 1.0, unit: "kg"),
        "k": (value: 1.0, unit: "N/m"),
        "k_3": (value: 1.0, unit: "N/m^3"),
        "b": (value: 0.1, unit: "N*s/m"),
    },
    elements: {
        "v": One,
        "mass": I(inertance: "m"),
        "spring": C(effort: "-k*q_spring + k_3*q_spring^3"),
        "damper": R(resistance: "b"),
    },
    bonds: [
        ("v", "mass"),
        ("v", "spring"),
        ("v", "damper"),
    ],
)"#;
