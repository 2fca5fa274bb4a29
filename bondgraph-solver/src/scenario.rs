//! Running a scenario file: the inputs, start and outputs it describes, simulated.
//!
//! [`bondgraph_core::scenario`] reads and checks scenario files; this module turns a checked
//! [`Scenario`] into a run of the [`Simulator`] (its signals are the solver's inputs, its
//! initial state by element becomes the full state, its records the outputs).
//!
//! Records are of three sorts. Bond outputs and their integrals are the simulator's
//! outputs; energies of storage elements and the books are its energy columns
//! ([`EnergyColumn`]), computed from the state it carries; a power is the product of two
//! outputs (the effort on the element's bond and the flow into it). The trajectory
//! returned has one column per record, in the scenario's order, named as written.

use bondgraph_core::scenario::{EnergyRecord, Record, Scenario, Signal as ScenarioSignal};

use crate::energy::EnergyColumn;
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

/// Where a record's column comes from in the simulator's columns.
enum Source {
    /// Output `k`.
    Output(usize),
    /// The product of outputs `k` and `k + 1`.
    Product(usize),
    /// Energy column `k`.
    Energy(usize),
}

/// The simulator's outputs and energy columns for a scenario's records, and where each
/// record's column comes from.
fn plan(scenario: &Scenario) -> (Vec<Output>, Vec<(String, EnergyColumn)>, Vec<Source>) {
    let mut outputs = Vec::new();
    let mut energies = Vec::new();
    let mut sources = Vec::new();
    for record in &scenario.record {
        match record {
            Record::Output(spec) | Record::Integral(spec) => {
                sources.push(Source::Output(outputs.len()));
                outputs.push(Output {
                    name: record.name(),
                    spec: spec.clone(),
                    integral: matches!(record, Record::Integral(_)),
                });
            }
            Record::Energy(name, EnergyRecord::Power { effort, flow, .. }) => {
                sources.push(Source::Product(outputs.len()));
                for (suffix, spec) in [("effort", effort), ("flow", flow)] {
                    outputs.push(Output {
                        name: format!("{name} ({suffix})"),
                        spec: spec.clone(),
                        integral: false,
                    });
                }
            }
            Record::Energy(name, energy) => {
                let column = match energy {
                    EnergyRecord::Stored(element) => EnergyColumn::Element(*element),
                    EnergyRecord::Book(book) => EnergyColumn::Book(*book),
                    EnergyRecord::Power { .. } => unreachable!("matched above"),
                };
                sources.push(Source::Energy(energies.len()));
                energies.push((name.clone(), column));
            }
        }
    }
    (outputs, energies, sources)
}

/// The bond outputs a scenario's records need from the simulator (a power needs two).
pub fn outputs(scenario: &Scenario) -> Vec<Output> {
    plan(scenario).0
}

/// Simulates `scenario`, keeping the energy books if `audit_energy`.
///
/// # Errors
/// As [`Simulator::run`].
pub fn run(scenario: &Scenario, audit_energy: bool) -> Result<Trajectory, SimError> {
    let (outputs, energies, sources) = plan(scenario);
    let width = outputs.len();
    let mut simulator = Simulator::new(&scenario.model, outputs).with_energy_columns(energies);
    let mut initial_state = vec![0.0; simulator.storage().len()];
    for (element, value) in &scenario.initial_state {
        if let Some(i) = simulator.storage().index(*element) {
            initial_state[i] = *value;
        }
    }
    let inputs: Vec<&dyn Signal> = scenario.inputs.iter().map(|s| s as &dyn Signal).collect();
    let mut trajectory = simulator.run(&Run {
        inputs: &inputs,
        initial_mode: scenario.initial_mode.clone(),
        initial_state,
        duration: scenario.duration,
        sample: scenario.sample,
        audit_energy,
    })?;
    let columns = trajectory.output_names.len();
    let mut values = Vec::with_capacity(trajectory.times.len() * sources.len());
    for row in trajectory.values.chunks(columns.max(1)) {
        values.extend(sources.iter().map(|source| match *source {
            Source::Output(k) => row[k],
            Source::Product(k) => row[k] * row[k + 1],
            Source::Energy(k) => row[width + k],
        }));
    }
    trajectory.values = values;
    trajectory.output_names = scenario.record.iter().map(Record::name).collect();
    Ok(trajectory)
}
