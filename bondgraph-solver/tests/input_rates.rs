//! Equations with a term in the inputs' rates, `dx/dt = A x + B u + E du/dt + c`, propagated
//! exactly: a dependent spring in co-energy variables, against its closed-form solutions.
//!
//! A force source F drives node n, held to the ground by spring K2 and joined to a damper B
//! by spring K1 (node n has nothing else: K2 is dependent storage). The one state is K1's
//! force f; by hand (continuity at n: f_K2 = F - f; v_n = df_K2/dt / K2; the damper moves at
//! f/B):
//!   df/dt = K1 (v_n - f/B)  =>  df/dt = -a f + E dF/dt,   a = K1 K2/(B (K1 + K2)),
//!   E = K1/(K1 + K2).
//! A ramp F = r t from rest gives f = (E r/a)(1 - e^{-a t}); a step of F0 gives the jump
//! f = E F0 (the damper does not move at once, so the springs share F0 in proportion to
//! their stiffnesses), then f = E F0 e^{-a t}.

use bondgraph_core::equations::{Options, Variables};
use bondgraph_core::modes::{self, Mode};
use bondgraph_solver::numeric::{NumericMode, Storage};

const MODEL: &str = r#"LinearGraph(name: "dependent_spring_damper", ground: "g",
    parameters: {"K1": (value: 300.0), "K2": (value: 100.0), "B": (value: 15.0)},
    inputs: {"F": (unit: "N")},
    branches: {
        "push": ThroughSource(value: "F", from: "g", to: "n"),
        "K2": T(stiffness: "K2", from: "n", to: "g"),
        "K1": T(stiffness: "K1", from: "n", to: "m"),
        "B": D(conductance: "B", from: "m", to: "g"),
    })"#;

fn coenergy_mode() -> (bondgraph_core::model::Model, NumericMode) {
    let model = bondgraph_ron::model::load_str("dependent_spring_damper.lg.ron", MODEL).unwrap();
    let derived = modes::derive(
        &model,
        &Mode::initial(&model),
        &Options {
            variables: Variables::CoEnergy,
        },
    )
    .unwrap();
    assert_eq!(derived.equations.states[0].name, "f_K1");
    let storage = Storage::of(&model);
    let numeric = NumericMode::new(&model, model.values(), &storage, &derived, &[]);
    (model, numeric)
}

const K1: f64 = 300.0;
const K2: f64 = 100.0;
const B: f64 = 15.0;

#[test]
fn the_rate_matrix_is_the_hand_derived_one() {
    let (_, mode) = coenergy_mode();
    let e = K1 / (K1 + K2);
    let a = K1 * K2 / (B * (K1 + K2));
    assert!((mode.e[(0, 0)] - e).abs() < 1e-15);
    assert!((mode.a[(0, 0)] + a).abs() < 1e-12);
    // Carried as x' = x - E u: B' = B + A E = -a E.
    assert!((mode.b[(0, 0)] + a * e).abs() < 1e-12);
}

#[test]
fn a_ramp_is_propagated_exactly() {
    let (_, mode) = coenergy_mode();
    let (e, a, r) = (K1 / (K1 + K2), K1 * K2 / (B * (K1 + K2)), 40.0);
    let carried = mode.project(&[0.0; 2], &[0.0]);
    let mut segment = mode.propagator.start(&carried, &[0.0], &[r]);
    for t in [0.0, 0.01, 0.05, 0.1, 0.3] {
        let mut state = vec![0.0];
        segment.state_and_integral_into(t, &mut state, None);
        let f = mode.states(&state, &[r * t])[0];
        let exact = e * r / a * (1.0 - (-a * t).exp());
        assert!(
            (f - exact).abs() <= 1e-12 * (e * r / a),
            "t = {t}: {f} against {exact}"
        );
    }
}

#[test]
fn a_step_makes_the_state_jump_by_e_times_the_step() {
    let (_, mode) = coenergy_mode();
    let (e, a, step) = (K1 / (K1 + K2), K1 * K2 / (B * (K1 + K2)), 12.0);
    // Before the step, at rest with F = 0; the carried x' = x - E u does not jump.
    let carried = mode.project(&[0.0; 2], &[0.0]);
    assert_eq!(mode.states(&carried, &[0.0]), [0.0]);
    let after = mode.states(&carried, &[step]);
    assert!((after[0] - e * step).abs() < 1e-12, "{after:?}");
    let mut segment = mode.propagator.start(&carried, &[step], &[0.0]);
    for t in [0.01, 0.04, 0.2] {
        let mut state = vec![0.0];
        segment.state_and_integral_into(t, &mut state, None);
        let f = mode.states(&state, &[step])[0];
        let exact = e * step * (-a * t).exp();
        assert!(
            (f - exact).abs() <= 1e-12 * e * step,
            "t = {t}: {f} against {exact}"
        );
    }
}
