//! Nonlinear modes: two-state models over 10 s simulated, integrated by Radau IIA with the
//! symbolic Jacobian. The mode is derived and compiled on the first run; what is measured
//! is a run with it cached, as in a sweep. `benches/peers/scipy_compare.py` runs the same
//! models with scipy's `solve_ivp` for comparison.

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

fn bench(
    c: &mut Criterion,
    name: &str,
    file: &str,
    record: &str,
    inputs: &[&dyn Signal],
    initial: Vec<f64>,
) {
    let model = load(file);
    let outputs = vec![Output {
        name: record.to_string(),
        spec: OutputSpec::parse(&model, record).expect("output"),
        integral: false,
    }];
    let mut simulator = Simulator::new(&model, outputs);
    let run = Run {
        inputs,
        initial_mode: Mode::initial(&model),
        initial_state: initial,
        duration: 10.0,
        // 100 samples, as the comparison with scipy asks for.
        sample: Some(0.1),
        audit_energy: false,
    };
    simulator.run(&run).expect("runs");
    c.bench_function(name, |b| b.iter(|| simulator.run(&run).expect("runs")));
}

fn pendulum(c: &mut Criterion) {
    bench(
        c,
        "nonlinear_pendulum_10s",
        "models/examples/nonlinear/pendulum.ron",
        "effort:gravity",
        &[],
        vec![0.0, 2.0],
    );
}

fn duffing(c: &mut Criterion) {
    let force = Constant(0.0);
    bench(
        c,
        "nonlinear_duffing_10s",
        "models/examples/nonlinear/duffing.ron",
        "effort:spring",
        &[&force],
        vec![0.0, 1.5],
    );
}

criterion_group!(benches, pendulum, duffing);
criterion_main!(benches);
