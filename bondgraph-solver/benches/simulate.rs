//! The solver's speed on the flagship: the paper's Fig. 6 scenario (0.2 s simulated) and a
//! sweep of steady states like the paper's Tables III and VI. Modes are derived and
//! decomposed once per simulator (the first run); what is measured is a run with them cached,
//! as in a sweep.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
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

struct Ramp(f64);
impl Signal for Ramp {
    fn value(&self, t: f64) -> f64 {
        self.0 * t
    }
    fn rate(&self, _: f64) -> f64 {
        self.0
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

fn fig6(c: &mut Criterion) {
    let model = load("models/eversion/robot.ron");
    let outputs = ["flow:ge", "effort:k", "effort:fr_ct"]
        .iter()
        .map(|s| Output {
            name: s.to_string(),
            spec: OutputSpec::parse(&model, s).expect("output"),
            integral: false,
        })
        .chain(std::iter::once(Output {
            name: "integral:flow:ge".into(),
            spec: OutputSpec::parse(&model, "flow:ge").expect("output"),
            integral: true,
        }))
        .collect();
    let mut simulator = Simulator::new(&model, outputs);
    let (pressure, channel, catheter) = (Ramp(1e6), Constant(5.8e-3), Constant(6.3e-3));
    let inputs: [&dyn Signal; 3] = [&pressure, &channel, &catheter];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::parse(&model, "fr_ge=stuck,k=slack,fr_ct=slip-").expect("mode"),
        initial_state: vec![0.0, 0.0, 5e-4 * 6.19e-3],
        duration: 0.2,
        sample: Some(1e-3),
        audit_energy: false,
    };
    simulator.run(&run).expect("runs"); // derive the modes once
    c.bench_function("fig6_robot_0.2s", |b| {
        b.iter(|| simulator.run(&run).expect("runs"))
    });
}

fn table_cells(c: &mut Criterion) {
    // 33 cells: the paper's Table III conditions (27, with the catheter commanded still and
    // held) and Table VI (6). The cells without a catheter use the same model here; what is
    // measured is the steady-state search.
    let model = load("models/eversion/robot.ron");
    let outputs = vec![Output {
        name: "flow:ge".into(),
        spec: OutputSpec::parse(&model, "flow:ge").expect("output"),
        integral: false,
    }];
    let mut simulator = Simulator::new(&model, outputs);
    let start = Mode::parse(&model, "fr_ge=stuck,k=slack,fr_ct=stuck").expect("mode");
    let mut cells: Vec<[f64; 3]> = Vec::new();
    for v_ac in [5.8e-3, 8.7e-3, 11.6e-3] {
        for p in [
            110e3, 115e3, 120e3, 125e3, 130e3, 135e3, 140e3, 145e3, 150e3,
        ] {
            cells.push([p, v_ac, 0.0]);
        }
    }
    for v_ct in [0.0, 1.8e-3, 2.9e-3, 3.9e-3, 4.8e-3, 6.3e-3] {
        cells.push([110e3, 5.8e-3, v_ct]);
    }
    let settings = SteadySettings::default();
    let sweep = |simulator: &mut Simulator<'_>| {
        cells
            .iter()
            .map(|inputs| {
                steady_state(simulator, inputs, start.clone(), vec![0.0; 3], &settings)
                    .expect("steady")
                    .outputs[0]
            })
            .sum::<f64>()
    };
    sweep(&mut simulator);
    c.bench_function("steady_33_cells", |b| b.iter(|| sweep(&mut simulator)));
}

criterion_group!(benches, fig6, table_cells);
criterion_main!(benches);
