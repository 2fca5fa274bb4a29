//! Event location on modes with widely separated time scales (issue 31): the lead-screw
//! actuator (`models/examples/actuator/`), whose sliding mode has an electrical time
//! constant of 0.34 ms beside a mechanical one of 38 ms, driven at 3 V for 5 s from rest
//! with its guide stuck (it breaks away at 55 µs and slides on), beside the same run at
//! 0.1 V, where the guide stays stuck (one state, one time scale).
//!
//! `cached` runs with the modes derived once (as in a sweep or a fit); `derived` derives
//! them in each run (a new simulator), as `bondgraph simulate` does once. The gcds of the
//! sliding mode's merged storage use a table of primes built the first time a process
//! takes one, which no in-process median shows: see the README's speed section.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, Simulator};
use criterion::{Criterion, criterion_group, criterion_main};

struct Constant(f64);
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

fn load(relative: &str) -> Model {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    bondgraph_ron::model::load_str(relative, &std::fs::read_to_string(path).expect("model"))
        .expect("valid")
}

fn outputs(model: &Model) -> Vec<Output> {
    vec![Output {
        name: "flow:carriage".into(),
        spec: OutputSpec::parse(model, "flow:carriage").expect("output"),
        integral: false,
    }]
}

fn actuator(c: &mut Criterion) {
    let model = load("models/examples/actuator/actuator.ron");
    let stuck = Mode::parse(&model, "guide=stuck").expect("mode");
    let no_load = Constant(0.0);
    let states = Simulator::new(&model, Vec::new()).storage().names.len();
    for (name, volts) in [("sliding_3V", 3.0), ("stuck_0.1V", 0.1)] {
        let supply = Constant(volts);
        let inputs: [&dyn Signal; 2] = [&supply, &no_load];
        let run = Run {
            inputs: &inputs,
            initial_mode: stuck.clone(),
            initial_state: vec![0.0; states],
            duration: 5.0,
            sample: None,
            audit_energy: false,
        };
        let mut simulator = Simulator::new(&model, outputs(&model));
        simulator.run(&run).expect("runs"); // derive the modes once
        c.bench_function(&format!("actuator_5s_{name}_cached"), |b| {
            b.iter(|| simulator.run(&run).expect("runs"))
        });
        c.bench_function(&format!("actuator_5s_{name}_derived"), |b| {
            b.iter(|| {
                Simulator::new(&model, outputs(&model))
                    .run(&run)
                    .expect("runs")
            })
        });
    }
}

criterion_group!(benches, actuator);
criterion_main!(benches);
