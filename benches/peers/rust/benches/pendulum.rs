//! Nonlinear integration beside the Rust crate `differential-equations` (its DOP853): the
//! pendulum of `models/examples/nonlinear/pendulum.ron` (m = l = 1, g = 9.81) from rest at
//! 2 rad, 10 s, 101 samples of its state, at equal accuracy.
//!
//! Equal accuracy: both errors are measured at t = 10 s against the crate's own DOP853 at
//! rtol = atol = 1e-14 (checked against itself at 1e-13), and the crate is timed at the
//! loosest of its tolerances 1e-6 ... 1e-13 whose error is no larger than bondgraph's at its
//! default tolerance. bondgraph is timed as a sweep runs it: the mode derived once, then
//! `Simulator::run` (the symbolic right-hand side evaluated by its tape, the samples written
//! from the dense output).
//!
//!     cargo bench --manifest-path benches/peers/rust/Cargo.toml

use std::hint::black_box;

use bondgraph_core::model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Run, Signal, Simulator};
use criterion::{Criterion, criterion_group, criterion_main};
use differential_equations::prelude::*;

const DURATION: f64 = 10.0;
const THETA0: f64 = 2.0;

/// `dθ/dt = p/(m l²)`, `dp/dt = -m g l sin θ` with m = l = 1: state `[θ, p]`.
struct Pendulum;

impl ODE<f64, [f64; 2]> for Pendulum {
    fn diff(&self, _: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
        dydt[0] = y[1];
        dydt[1] = -9.81 * y[0].sin();
    }
}

fn sample_times() -> Vec<f64> {
    (0..=100).map(|k| k as f64 * DURATION / 100.0).collect()
}

/// The crate's DOP853 at `tolerance`: the state at each sample time.
fn peer(tolerance: f64) -> Vec<[f64; 2]> {
    let method = ExplicitRungeKutta::dop853().rtol(tolerance).atol(tolerance);
    IVP::ode(&Pendulum, 0.0, DURATION, [THETA0, 0.0])
        .t_eval(sample_times())
        .method(method)
        .solve()
        .expect("the crate solves the pendulum")
        .y
}

fn bench(c: &mut Criterion) {
    let reference = *peer(1e-14).last().unwrap();
    let check = *peer(1e-13).last().unwrap();
    let reference_error = (reference[0] - check[0])
        .abs()
        .max((reference[1] - check[1]).abs());
    let error = |state: [f64; 2]| {
        (state[0] - reference[0])
            .abs()
            .max((state[1] - reference[1]).abs())
    };

    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../models/examples/nonlinear/pendulum.ron"
    );
    let text = std::fs::read_to_string(path).expect("the pendulum model");
    let model = model::load_str("pendulum.ron", &text).expect("a valid model");
    let inputs: [&dyn Signal; 0] = [];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::initial(&model),
        // Energy states in file order: p_bob, q_gravity.
        initial_state: vec![0.0, THETA0],
        duration: DURATION,
        sample: Some(DURATION / 100.0),
        audit_energy: false,
    };
    let mut simulator = Simulator::new(&model, Vec::new());
    let trajectory = simulator
        .run(&run)
        .expect("bondgraph simulates the pendulum");
    let state = |name: &str| {
        trajectory
            .final_state
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
            .expect("a final state")
    };
    let ours = error([state("q_gravity"), state("p_bob")]);

    let tolerances = [1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13];
    let matched = tolerances
        .iter()
        .copied()
        .find(|&t| error(*peer(t).last().unwrap()) <= ours)
        .unwrap_or(1e-13);
    println!(
        "error at t = {DURATION} s: bondgraph {ours:.2e}; differential-equations DOP853 at \
         rtol = atol = {matched:e}: {:.2e} (reference checked to {reference_error:.1e})",
        error(*peer(matched).last().unwrap())
    );

    // The work of each: bondgraph's DOP853 alone on the same equations, at its tolerances.
    struct Own;
    impl bondgraph_solver::ode::System for Own {
        fn dimension(&self) -> usize {
            2
        }
        fn controlled(&self) -> usize {
            2
        }
        fn rhs(&mut self, _: f64, y: &[f64], dydt: &mut [f64]) {
            dydt[0] = y[1];
            dydt[1] = -9.81 * y[0].sin();
        }
        fn jacobian(&mut self, _: f64, y: &[f64], j: &mut [f64]) {
            j.copy_from_slice(&[0.0, 1.0, -9.81 * y[0].cos(), 0.0]);
        }
    }
    let mut dop =
        bondgraph_solver::ode::Dop853::new(2, 2, bondgraph_solver::ode::Tolerances::default());
    let (mut t, mut y) = (0.0, [THETA0, 0.0]);
    let mut h = dop.initial_step(&mut Own, t, &y, DURATION);
    while t < DURATION {
        let step = h.min(DURATION - t);
        match dop.step(&mut Own, t, &mut y, step) {
            bondgraph_solver::ode::StepOutcome::Accepted { h_next } => {
                t += step;
                h = h_next;
            }
            bondgraph_solver::ode::StepOutcome::Rejected { h_next } => h = h_next,
        }
    }
    let solved = IVP::ode(&Pendulum, 0.0, DURATION, [THETA0, 0.0])
        .t_eval(sample_times())
        .method(ExplicitRungeKutta::dop853().rtol(matched).atol(matched))
        .solve()
        .unwrap();
    println!(
        "work: bondgraph's DOP853 {:?}, error {:.2e}; the crate's {:?} {:?}",
        dop.stats,
        error(y),
        solved.evals,
        solved.steps
    );

    let mut group = c.benchmark_group("pendulum_10s");
    group.bench_function("bondgraph", |b| {
        b.iter(|| black_box(simulator.run(&run).expect("runs")))
    });
    group.bench_function("differential_equations_dop853", |b| {
        b.iter(|| black_box(peer(matched)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
