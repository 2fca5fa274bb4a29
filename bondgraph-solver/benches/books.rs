//! The energy books' cost: a lightly damped mass-spring (Q = 2000) released and run for
//! 1000 s with the books recorded at each of its 1000 samples, about 1600 oscillations. The
//! books are closed forms between samples, so this costs what the samples cost; the goal is
//! under 50 ms. The mode is derived once per simulator (the first run); what is measured is
//! a run with it cached.

use bondgraph_core::modes::Mode;
use bondgraph_core::scenario::Book;
use bondgraph_solver::energy::EnergyColumn;
use bondgraph_solver::{Run, Signal, Simulator};
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

fn lightly_damped_books(c: &mut Criterion) {
    let relative = "models/examples/mass_spring_damper.ron";
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    // m = 2 kg, k = 200 N/m, b = 0.01 N·s/m: Q = √(k m)/b = 2000.
    let text = std::fs::read_to_string(path)
        .expect("model")
        .replace(r#""b": (value: 4.0"#, r#""b": (value: 0.01"#);
    assert!(text.contains(r#""b": (value: 0.01"#), "the damping is set");
    let model = bondgraph_ron::model::load_str(relative, &text).expect("valid");
    let books = [Book::Supplied, Book::Dissipated, Book::Stored]
        .into_iter()
        .map(|book| (format!("{book:?}"), EnergyColumn::Book(book)))
        .collect();
    let mut simulator = Simulator::new(&model, Vec::new()).with_energy_columns(books);
    let force = Constant(0.0);
    let inputs: [&dyn Signal; 1] = [&force];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::initial(&model),
        initial_state: vec![0.0, 0.1],
        duration: 1000.0,
        sample: Some(1.0),
        audit_energy: false,
    };
    simulator.run(&run).expect("runs"); // derive the mode once
    c.bench_function("books_q2000_1000s", |b| {
        b.iter(|| simulator.run(&run).expect("runs"))
    });
}

criterion_group!(benches, lightly_damped_books);
criterion_main!(benches);
