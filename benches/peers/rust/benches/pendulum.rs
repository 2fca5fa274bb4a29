//! Nonlinear integration beside the Rust crates `differential-equations` (its DOP853) and
//! `diffsol` (its TSIT45, and its BDF for reference): the pendulum of
//! `models/examples/nonlinear/pendulum.ron` (m = l = 1, g = 9.81) from rest at 2 rad, 10 s,
//! 101 samples of its state, at equal accuracy.
//!
//! Equal accuracy: every error is measured at t = 10 s against `differential-equations`' DOP853
//! at rtol = atol = 1e-14 (checked against itself at 1e-13), and each peer is timed at the
//! loosest of its tolerances 1e-6 ... 1e-13 (rtol = atol) whose error is no larger than
//! bondgraph's at its default tolerance (at 1e-13, the tightest, if none is). bondgraph is timed
//! as a sweep runs it: the mode derived once, then `Simulator::run` (the symbolic right-hand side
//! evaluated by its tape, the samples written from the dense output). diffsol is timed from its
//! `OdeBuilder` (closures for the right-hand side and its Jacobian-vector product, nalgebra
//! matrices) through `solve_dense` at the sample times.
//!
//!     cargo bench --manifest-path benches/peers/rust/Cargo.toml

use std::hint::black_box;

use bondgraph_core::modes::Mode;
use bondgraph_solver::{Run, Signal, Simulator};
use criterion::{Criterion, criterion_group, criterion_main};
use differential_equations::prelude::*;
use diffsol::ode_solver::OdeSolverStatistics;
use diffsol::op::OpStatistics;
use diffsol::{
    MatrixCommon, NalgebraLU, NalgebraMat, OdeBuilder, OdeEquations, OdeSolverMethod, Op,
};

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

/// diffsol's methods timed here.
#[derive(Clone, Copy, Debug)]
enum Diffsol {
    /// The explicit Runge–Kutta method of Tsitouras, order 5(4).
    Tsit45,
    /// The variable-order BDF (NDF) method, with nalgebra's dense LU: implicit, for reference.
    Bdf,
}

/// diffsol's `method` at `tolerance`: the state at each sample time, the solver's counts and
/// those of the right-hand side.
fn diffsol(method: Diffsol, tolerance: f64) -> (Vec<[f64; 2]>, OdeSolverStatistics, OpStatistics) {
    let mut problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .rtol(tolerance)
        .atol([tolerance])
        .rhs_implicit(
            |y, _, _, dydt| {
                dydt[0] = y[1];
                dydt[1] = -9.81 * y[0].sin();
            },
            |y, _, _, v, jv| {
                jv[0] = v[1];
                jv[1] = -9.81 * y[0].cos() * v[0];
            },
        )
        .init(
            |_, _, y| {
                y[0] = THETA0;
                y[1] = 0.0;
            },
            2,
        )
        .build()
        .expect("diffsol builds the pendulum");
    // Lift the cap of 5000 steps, which BDF at the tighter tolerances would reach.
    problem.ode_options.max_number_timesteps = 1_000_000;
    let times = sample_times();
    let (ys, statistics) = match method {
        Diffsol::Tsit45 => {
            let mut solver = problem.tsit45().expect("a TSIT45 solver");
            let (ys, _) = solver
                .solve_dense(&times)
                .expect("diffsol solves the pendulum");
            (ys, solver.get_statistics().clone())
        }
        Diffsol::Bdf => {
            let mut solver = problem.bdf::<NalgebraLU<f64>>().expect("a BDF solver");
            let (ys, _) = solver
                .solve_dense(&times)
                .expect("diffsol solves the pendulum");
            (ys, solver.get_statistics().clone())
        }
    };
    let states = ys
        .inner()
        .column_iter()
        .map(|column| [column[0], column[1]])
        .collect();
    (states, statistics, problem.eqn.rhs().statistics())
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
    let model = bondgraph_ron::model::load_str("pendulum.ron", &text).expect("a valid model");
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
    let diffsol_final = |method, t| *diffsol(method, t).0.last().unwrap();
    let diffsol_matched = |method| {
        tolerances
            .iter()
            .copied()
            .find(|&t| error(diffsol_final(method, t)) <= ours)
            .unwrap_or(1e-13)
    };
    let (tsit45, bdf) = (
        diffsol_matched(Diffsol::Tsit45),
        diffsol_matched(Diffsol::Bdf),
    );
    for (method, tolerance) in [(Diffsol::Tsit45, tsit45), (Diffsol::Bdf, bdf)] {
        println!(
            "error at t = {DURATION} s: diffsol {method:?} at rtol = atol = {tolerance:e}: {:.2e}",
            error(diffsol_final(method, tolerance))
        );
    }

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
    for (method, tolerance) in [(Diffsol::Tsit45, tsit45), (Diffsol::Bdf, bdf)] {
        let (_, statistics, rhs) = diffsol(method, tolerance);
        println!(
            "work: diffsol {method:?} {} steps, {} rejected by the error test, {} right-hand \
             sides, {} Jacobian-vector products, {} Newton iterations, {} LU setups",
            statistics.number_of_steps,
            statistics.number_of_error_test_failures,
            rhs.number_of_calls,
            rhs.number_of_jac_muls,
            statistics.number_of_nonlinear_solver_iterations,
            statistics.number_of_linear_solver_setups
        );
    }

    let mut group = c.benchmark_group("pendulum_10s");
    group.bench_function("bondgraph", |b| {
        b.iter(|| black_box(simulator.run(&run).expect("runs")))
    });
    group.bench_function("differential_equations_dop853", |b| {
        b.iter(|| black_box(peer(matched)))
    });
    group.bench_function("diffsol_tsit45", |b| {
        b.iter(|| black_box(diffsol(Diffsol::Tsit45, tsit45)))
    });
    group.bench_function("diffsol_bdf", |b| {
        b.iter(|| black_box(diffsol(Diffsol::Bdf, bdf)))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
