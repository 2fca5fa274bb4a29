//! A nonlinear model whose every body a stuck contact holds: its stuck mode has no states
//! left, and integrating it must hand on to the next mode rather than fail.
//!
//! A block (m = 1 kg) with a quadratic drag c v|v| (c = 0.1 N s²/m²) on a Karnopp contact
//! (F_S = 2 N, F_C = 1 N), pushed by F(t) = 3t N up to 3 N at t = 1 s, held to 2 s, let go
//! linearly to 0 at 2.5 s. Stuck, nothing moves (no states); it breaks away at F = F_S,
//! t = 2/3 s, slides with m v' = F - F_C - c v|v|, and after the push ends comes to rest
//! where v' = -1 - 0.1 v² brings it: v = √10 tan(atan(v₀/√10) - (t - 2.5)/√10).
//! `reference/dragged_block.py` integrates the slide independently (classical RK4, fine
//! steps, two step sizes agreeing to 1e-13): v(1.5 s) = 1.44593593714941 m/s, at rest at
//! t = 4.44613061856587 s.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::modes::Mode;
use bondgraph_core::scenario::Signal as Table;
use bondgraph_solver::{Output, Run, Signal, Simulator};

#[test]
fn a_block_held_with_no_states_left_breaks_away_and_comes_to_rest() {
    let model = bondgraph_ron::model::load_str(
        "dragged_block.ron",
        r#"Model(
        name: "dragged_block",
        parameters: {
            "m": (value: 1.0), "F_S": (value: 2.0), "F_C": (value: 1.0), "c": (value: 0.1),
        },
        inputs: {"F": ()},
        elements: {
            "push": Se(effort: "F"),
            "v": One,
            "block": I(inertance: "m"),
            "drag": R(effort: "c*flow*abs(flow)"),
            "contact": Friction(breakaway: "F_S", coulomb: "F_C"),
        },
        bonds: [("push", "v"), ("v", "block"), ("v", "drag"), ("v", "contact")],
    )"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(model.is_nonlinear());
    let outputs = vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(&model, "flow:block").unwrap(),
        integral: false,
    }];
    let push = Table::Table(vec![(0.0, 0.0), (1.0, 3.0), (2.0, 3.0), (2.5, 0.0)]);
    let inputs: [&dyn Signal; 1] = [&push];
    let run = Simulator::new(&model, outputs)
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state: vec![0.0],
            duration: 6.0,
            sample: Some(0.01),
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let events: Vec<(f64, &str)> = run.events.iter().map(|e| (e.t, e.to.as_str())).collect();
    assert_eq!(events.len(), 2, "{events:?}");
    assert_eq!(events[0].1, "contact=slip+", "{events:?}");
    assert!((events[0].0 - 2.0 / 3.0).abs() < 1e-12, "{events:?}");
    assert_eq!(events[1].1, "contact=stuck", "{events:?}");
    // The integrator's relative tolerance is 1e-10.
    assert!((events[1].0 - 4.44613061856587).abs() < 1e-9, "{events:?}");
    let k = run.times.iter().position(|&t| t == 1.5).unwrap();
    assert!(
        (run.values[k] - 1.44593593714941).abs() < 1e-9,
        "{}",
        run.values[k]
    );
    assert_eq!(*run.values.last().unwrap(), 0.0);
}
