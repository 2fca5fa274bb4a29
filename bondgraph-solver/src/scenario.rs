//! Running a scenario file: the inputs, start and outputs it describes, simulated.
//!
//! [`bondgraph_core::scenario`] reads and checks scenario files; this module turns a checked
//! [`Scenario`] into a run of the [`Simulator`] (its signals are the solver's inputs, its
//! initial state by element becomes the full state, its records the outputs).

use bondgraph_core::scenario::{Record, Scenario, Signal as ScenarioSignal};

use crate::hybrid::{Output, Run, Signal, SimError, Simulator, Trajectory};

impl Signal for ScenarioSignal {
    fn value(&self, t: f64) -> f64 {
        ScenarioSignal::value(self, t)
    }
    fn rate(&self, t: f64) -> f64 {
        ScenarioSignal::rate(self, t)
    }
    fn breakpoints(&self) -> Vec<f64> {
        ScenarioSignal::breakpoints(self)
    }
}

/// The outputs a scenario records.
pub fn outputs(scenario: &Scenario) -> Vec<Output> {
    scenario
        .record
        .iter()
        .map(|record| Output {
            name: record.name(),
            spec: record.spec().clone(),
            integral: matches!(record, Record::Integral(_)),
        })
        .collect()
}

/// Simulates `scenario`, keeping the energy books if `audit_energy`.
///
/// # Errors
/// As [`Simulator::run`].
pub fn run(scenario: &Scenario, audit_energy: bool) -> Result<Trajectory, SimError> {
    let mut simulator = Simulator::new(&scenario.model, outputs(scenario));
    let mut initial_state = vec![0.0; simulator.storage().len()];
    for (element, value) in &scenario.initial_state {
        if let Some(i) = simulator.storage().index(*element) {
            initial_state[i] = *value;
        }
    }
    let inputs: Vec<&dyn Signal> = scenario.inputs.iter().map(|s| s as &dyn Signal).collect();
    simulator.run(&Run {
        inputs: &inputs,
        initial_mode: scenario.initial_mode.clone(),
        initial_state,
        duration: scenario.duration,
        sample: scenario.sample,
        audit_energy,
    })
}
