//! Extension laws written as a user writes them, against answers computed independently: a
//! tank draining through a pipe whose loss is laminar plus turbulent,
//! `e = R_2 q + K_o q|q|`, which the tank's integral causality needs as `q(e)`.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, Simulator, Trajectory};

use crate::support::Constant;

fn simulate(model: &Model, records: &[&str], inputs: &[&dyn Signal], duration: f64) -> Trajectory {
    let outputs = records
        .iter()
        .map(|r| Output {
            name: r.to_string(),
            spec: OutputSpec::parse(model, r).unwrap(),
            integral: false,
        })
        .collect();
    let mut simulator = Simulator::new(model, outputs);
    simulator
        .run(&Run {
            inputs,
            initial_mode: Mode::initial(model),
            initial_state: vec![0.0],
            duration,
            sample: Some(10.0),
            audit_energy: true,
        })
        .unwrap_or_else(|e| panic!("{}: {e}", model.name()))
}

/// A tank (compliance 2) filled at 2 from empty, draining through a pipe whose pressure
/// drop is `4 q + 0.5 q|q|`: the law is written as an effort of the flow, the tank gives
/// the pipe its effort, so the pipe needs the law's inverse.
#[test]
fn a_laminar_and_turbulent_pipe_drains_a_tank() {
    let model = bondgraph_ron::model::load_str(
        "tank.ron",
        r#"Model(name: "tank",
            parameters: {"C": (value: 2.0), "R_2": (value: 4.0), "K_o": (value: 0.5)},
            inputs: {"Q": ()},
            elements: {"pump": Sf(flow: "Q"), "p": Zero, "tank": C(compliance: "C"),
                       "pipe": R(effort: "R_2*flow + K_o*flow*abs(flow)")},
            bonds: [("pump", "p"), ("p", "tank"), ("p", "pipe")])"#,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let trajectory = simulate(
        &model,
        &["effort:tank", "flow:pipe"],
        &[&Constant(2.0)],
        40.0,
    );
    // RK4 with h = 1e-3 s on C de/dt = Q - q(e), q(e) by bisection on 4q + 0.5q|q| = e
    // (Python, written for this test): e(10) = 6.045747001892, q = 1.300140941879; the
    // steady state is e = 4*2 + 0.5*4 = 10.
    let at_10 = trajectory.times.iter().position(|&t| t == 10.0).unwrap();
    let e = trajectory.value(at_10, 0).unwrap();
    let q = trajectory.value(at_10, 1).unwrap();
    assert!((e - 6.045747001892).abs() < 1e-7, "e(10) = {e}");
    assert!((q - 1.300140941879).abs() < 1e-7, "q(10) = {q}");
    assert!((4.0 * q + 0.5 * q * q.abs() - e).abs() < 1e-12);
}

/// A linear graph's D-type with a nonlinear law, written either way round: a through source
/// of 8 into a node with an A-type of capacitance 1 and a D-type carrying
/// `through = k across |across|` (or, the same law, `across = sign(through) sqrt(|through|/k)`),
/// `k = 2`.
/// From rest, `dv/dt = 8 - 2 v^2`, so `v(t) = 2 tanh(4 t)`.
#[test]
fn a_linear_graph_d_type_takes_a_nonlinear_law_either_way_round() {
    for law in [
        r#"through: "k*across*abs(across)""#,
        r#"across: "sign(through)*abs(through)^(1/2)/sqrt(k)""#,
    ] {
        let model = bondgraph_ron::model::load_str(
            "quadratic.lg.ron",
            &format!(
                r#"LinearGraph(name: "quadratic", ground: "g",
                    parameters: {{"C": (value: 1.0), "k": (value: 2.0)}},
                    inputs: {{"P": ()}},
                    branches: {{
                        "source": ThroughSource(value: "P", from: "g", to: "n"),
                        "store": A(capacitance: "C", from: "n", to: "g"),
                        "drag": D({law}, from: "n", to: "g"),
                    }})"#
            ),
        )
        .unwrap_or_else(|e| panic!("{law}: {e}"));
        // The source runs from the ground to n: its across variable is -v.
        let outputs = ["across:store", "across:source"]
            .into_iter()
            .map(|name| Output {
                name: name.into(),
                spec: OutputSpec::parse(&model, name).unwrap(),
                integral: false,
            })
            .collect();
        let trajectory = Simulator::new(&model, outputs)
            .run(&Run {
                inputs: &[&Constant(8.0)],
                initial_mode: Mode::initial(&model),
                initial_state: vec![0.0],
                duration: 0.5,
                sample: Some(0.1),
                audit_energy: true,
            })
            .unwrap_or_else(|e| panic!("{law}: {e}"));
        for (i, &t) in trajectory.times.iter().enumerate() {
            let v = trajectory.value(i, 0).unwrap();
            let expected = 2.0 * (4.0 * t).tanh();
            assert!(
                (v - expected).abs() < 1e-7,
                "{law}: v({t}) = {v}, expected {expected}"
            );
            let source = trajectory.value(i, 1).unwrap();
            assert!(
                (source + expected).abs() < 1e-7,
                "{law}: across:source({t}) = {source}, expected {}",
                -expected
            );
        }
    }
}
