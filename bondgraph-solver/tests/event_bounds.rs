//! Event location passes over what a bound of every guard clears: a block pushed into
//! steady sliding, against its closed form.
//!
//! The block (m = 1 kg) is pushed by F = 3 N against a contact with F_S = 2 N, F_C = 1 N and
//! b = 0.5 N s/m. It breaks away at once and slides with m v' = F - F_C - b v:
//! v(t) = 4 (1 - e^{-t/2}) m/s, so its guard (the velocity falling to zero, `-v`) is
//! `-4 + 4 e^{-t/2}`, bounded over `[t₀, ∞)` by `-4 + 4 e^{-t₀/2} < 0` for any `t₀ > 0`.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::hybrid::Settings;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};

fn pushed_block() -> Model {
    let text = r#"Model(
        name: "pushed_block",
        parameters: {
            "m": (value: 1.0), "F": (value: 3.0), "F_S": (value: 2.0), "F_C": (value: 1.0),
            "b": (value: 0.5),
        },
        elements: {
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C", viscous: "b"),
        },
        bonds: [("push", "v"), ("v", "block"), ("v", "contact")],
    )"#;
    bondgraph_ron::model::load_str("pushed_block.ron", text).unwrap()
}

#[test]
fn a_slide_whose_guard_is_bounded_below_zero_needs_few_samples() {
    let model = pushed_block();
    let outputs = vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(&model, "flow:block").unwrap(),
        integral: false,
    }];
    // Sampling all 72 s to its steady state (36 time constants of 2 s) takes 29 samples: 13
    // of the slow scale from 0.02 time constants on (×1.8 each), and 16 across. Once the transient has
    // fallen to e^{-1/4} of its start (0.5 s in), the bound clears the rest.
    let settings = Settings {
        max_steps: 12,
        ..Settings::default()
    };
    let mut simulator = Simulator::new(&model, outputs).with_settings(settings);
    let steady = steady_state(
        &mut simulator,
        &[],
        Mode::initial(&model),
        vec![0.0],
        &SteadySettings::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(steady.mode, "contact=slip+");
    // (F - F_C)/b = 4 m/s.
    assert!(
        (steady.outputs[0] - 4.0).abs() < 1e-12,
        "{:?}",
        steady.outputs
    );
}
