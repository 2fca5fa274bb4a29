//! A steady-state search waits on the model's own time scales: a circuit with a 1 ms and a
//! 30 s mode settles after 36 time constants of the slow one, and no limit in seconds stops it.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};

/// A voltage source driving an inductor L = 0.06 H and a resistor R_1 = 60 Ω in series into a
/// capacitor C = 1 F with R_2 = 60 Ω across it: a fast mode near L/R_1 = 1 ms and a slow one
/// near C (R_1 ∥ R_2) = 30 s. The characteristic polynomial of the states (p_coil, q_cap) is
/// `s² + (R_1/L + 1/(R_2 C)) s + (R_1/(L R_2 C) + 1/(L C))`
/// `= s² + (1000 + 1/60) s + 100/3`, whose slow root is
/// `λ = 2c / (-b - √(b² - 4c)) = -0.03333388891666836` (mpmath, 30 digits).
const TWO_SCALES: &str = r#"Model(
    name: "two_scales",
    parameters: {
        "L": (value: 0.06, unit: "H"),
        "R_1": (value: 60.0, unit: "Ohm"),
        "C": (value: 1.0, unit: "F"),
        "R_2": (value: 60.0, unit: "Ohm"),
    },
    inputs: { "V": (unit: "V") },
    elements: {
        "source": Se(effort: "V"),
        "loop": One,
        "coil": I(inertance: "L"),
        "wire": R(resistance: "R_1"),
        "node": Zero,
        "cap": C(compliance: "C"),
        "leak": R(resistance: "R_2"),
    },
    bonds: [
        ("source", "loop"),
        ("loop", "coil"),
        ("loop", "wire"),
        ("loop", "node"),
        ("node", "cap"),
        ("node", "leak"),
    ],
)"#;

fn output(model: &Model, spec: &str) -> Output {
    Output {
        name: spec.to_string(),
        spec: OutputSpec::parse(model, spec).unwrap(),
        integral: false,
    }
}

#[test]
fn a_search_settles_on_the_slowest_time_constant_not_a_time_limit() {
    let model = bondgraph_ron::model::load_str("two_scales.ron", TWO_SCALES).unwrap();
    let outputs = vec![output(&model, "flow:coil"), output(&model, "effort:cap")];
    let mut simulator = Simulator::new(&model, outputs);
    let storage = simulator.storage().len();
    let steady = steady_state(
        &mut simulator,
        &[2.0],
        Mode::initial(&model),
        vec![0.0; storage],
        &SteadySettings::default(),
    )
    .unwrap();
    // 36 time constants of the slow mode, 36 / 0.03333388891666836 s = 1079.981999 s: the
    // 1 ms mode does not set it (36 ms), and no limit in seconds cuts it short.
    let expected = 36.0 / 0.033_333_888_916_668_36;
    assert!(
        (steady.time - expected).abs() < 1e-9 * expected,
        "{} against {expected}",
        steady.time
    );
    // i = V/(R_1 + R_2) = 1/60 A; the capacitor's voltage V R_2/(R_1 + R_2) = 1 V.
    assert!(
        (steady.outputs[0] - 1.0 / 60.0).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
    assert!(
        (steady.outputs[1] - 1.0).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
}
