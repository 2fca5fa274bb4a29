//! Steady tip velocities of the flagship in each regime, against closed forms derived by hand.
//!
//! Parameters (Tables IV and V): A = 1e-4 m², F_S_ge = 11.7 N, F_C_ge = 9.125 N,
//! b = 1250 N·s/m, F_S_ct = 6.05 N, F_C_ct = 5.5 N, K_p = 5e4 N·s/m. The robot's eversion
//! transformer makes the inner structure move at 2 v_ge and doubles forces on the tip.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Simulator};

use crate::support;

fn load(relative: &str) -> Model {
    support::load(relative).0
}

const A: f64 = 1e-4;
const F_C_GE: f64 = 9.125;
const B: f64 = 1250.0;
const F_C_CT: f64 = 5.5;
const K_P: f64 = 5e4;

/// The steady tip velocity (m/s) and mode for constant inputs, from rest with the tip stuck,
/// the inner structure slack at zero length and the catheter stuck.
fn settle(model: &Model, inputs: [f64; 3]) -> (f64, String) {
    let outputs = vec![Output {
        name: "flow:ge".into(),
        spec: OutputSpec::parse(model, "flow:ge").unwrap(),
        integral: false,
    }];
    let mut simulator = Simulator::new(model, outputs);
    let n = simulator.storage().len();
    let start = Mode::parse(model, "fr_ge=stuck,k=slack,fr_ct=stuck").unwrap();
    let steady = steady_state(
        &mut simulator,
        &inputs,
        start,
        vec![0.0; n],
        &SteadySettings::default(),
    )
    .unwrap_or_else(|e| panic!("{inputs:?}: {e}"));
    assert!(
        steady.drift[0].abs() < 1e-12,
        "{inputs:?}: tip still accelerating"
    );
    (steady.outputs[0], steady.mode)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs().max(1e-6)
}

#[test]
fn catheter_locked_regime() {
    // Table VI's conditions, P_s = 110 kPa, v_ac = 5.8 mm/s, catheter commanded 1.8 mm/s.
    // Stuck to the inner structure, the catheter moves at 2 v and its servo pushes the single
    // body; the inner structure stays slack (2 v < v_ac). Force balance on the body, with the
    // servo force 2 K_p (v_des - 2 v) at the tip:
    //   A P_s - F_C_ge - b v + 2 K_p (v_des - 2 v) = 0
    //   v = (A P_s - F_C_ge + 2 K_p v_des)/(b + 4 K_p) = 0.903726... mm/s.
    let model = load("models/eversion/robot.ron");
    let (p, v_des) = (110e3, 1.8e-3);
    let (v, mode) = settle(&model, [p, 5.8e-3, v_des]);
    let expected = (A * p - F_C_GE + 2.0 * K_P * v_des) / (B + 4.0 * K_P);
    assert!(close(v, expected), "{v} vs {expected}");
    assert_eq!(mode, "fr_ge=slip+,k=slack,fr_ct=stuck");
    // The catheter holds: its servo force K_p (v_des - 2v) = 0.37 N is well below F_S_ct.
    assert!((K_P * (v_des - 2.0 * expected)).abs() < 6.05);

    // The paper's structure has no eversion ratio: the catheter locks the tip to its own speed,
    // v = (A P_s - F_C_ge + K_p v_des)/(b + K_p), twice as fast (Table VI measures 0.9 mm/s).
    let paper = load("models/eversion/paper.ron");
    let (v, mode) = settle(&paper, [p, 5.8e-3, v_des]);
    let expected = (A * p - F_C_GE + K_P * v_des) / (B + K_P);
    assert!(close(v, expected), "{v} vs {expected}");
    assert_eq!(mode, "fr_ge=slip+,k=slack,fr_ct=stuck");
}

#[test]
fn channel_limited_regime_with_the_catheter_slipping() {
    // Catheter commanded 6.3 mm/s: locked, the tip would run at about 3.15 mm/s, more than
    // v_ac/2 = 2.9 mm/s; the inner structure goes taut and holds the tip to exactly v_ac/2,
    // and the catheter, faster than the inner structure (5.8 mm/s), slips (slip-).
    let model = load("models/eversion/robot.ron");
    let (v, mode) = settle(&model, [110e3, 5.8e-3, 6.3e-3]);
    assert!(close(v, 2.9e-3), "{v}");
    assert_eq!(mode, "fr_ge=slip+,k=taut,fr_ct=slip-");
}

#[test]
fn static_regime_with_the_catheter_held() {
    // Catheter commanded 0: it holds the inner structure, and the pressure force
    // A P_s = 11 N is below the breakaway force F_S_ge = 11.7 N: nothing moves.
    let model = load("models/eversion/robot.ron");
    let (v, mode) = settle(&model, [110e3, 5.8e-3, 0.0]);
    assert_eq!(v, 0.0);
    assert_eq!(mode, "fr_ge=stuck,k=slack,fr_ct=stuck");
}

#[test]
fn catheter_slipping_and_pressure_driven_tip() {
    // Catheter commanded slower than the inner structure would move: P_s = 150 kPa drives the
    // tip; with the catheter held back at v_des = 0.5 mm/s while the inner structure runs
    // ahead, it slips (slip+) and drags the inner structure back with F_C_ct, i.e. 2 F_C_ct at
    // the tip. Slack inner structure: A P_s - F_C_ge - 2 F_C_ct - b v = 0,
    //   v = (15 - 9.125 - 11)/1250 < 0: the tip cannot move forward: it stays stuck...
    // so take P_s = 250 kPa: v = (25 - 9.125 - 11)/1250 = 3.9 mm/s, but v_ac/2 = 2.9 mm/s limits
    // it; with v_ac = 11.6 mm/s (limit 5.8 mm/s) the tip runs pressure-driven at 3.9 mm/s.
    let model = load("models/eversion/robot.ron");
    let p = 250e3;
    let (v, mode) = settle(&model, [p, 11.6e-3, 0.5e-3]);
    let expected = (A * p - F_C_GE - 2.0 * F_C_CT) / B;
    assert!(close(v, expected), "{v} vs {expected}");
    assert_eq!(mode, "fr_ge=slip+,k=slack,fr_ct=slip+");
}

#[test]
fn the_tip_mass_is_parasitic_and_nothing_else_is() {
    // m_ge/b = 5e-15/1250 = 4e-18 s against, at the fastest, the catheter servo's
    // m_ct/K_p = 1e-8 s and the inner structure's b/(4 k_ge) = 6.25e-4 s.
    let model = load("models/eversion/robot.ron");
    let mut simulator = Simulator::new(&model, Vec::new());
    let found = bondgraph_solver::parasitic::find(&mut simulator, 1e6).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!(found[0].element, "ge");
    assert!((found[0].time_constant - 4e-18).abs() < 1e-30);
    assert!(found[0].ratio > 1e9);
    // The textbook examples have nothing parasitic.
    for file in [
        "models/examples/two_masses.ron",
        "models/examples/dc_motor.ron",
    ] {
        let model = load(file);
        let mut simulator = Simulator::new(&model, Vec::new());
        assert!(
            bondgraph_solver::parasitic::find(&mut simulator, 1e6)
                .unwrap()
                .is_empty()
        );
    }
}

#[test]
fn new_parameter_values_keep_the_derived_modes_and_change_the_numbers() {
    // A calibration changes numbers, never the structure: one simulator, three values of
    // the nozzle's viscous coefficient b, each against the catheter-locked closed form
    // (`catheter_locked_regime`), v = (A P_s - F_C_ge + 2 K_p v_des)/(b + 4 K_p).
    let model = load("models/eversion/robot.ron");
    let outputs = vec![Output {
        name: "flow:ge".into(),
        spec: OutputSpec::parse(&model, "flow:ge").unwrap(),
        integral: false,
    }];
    let mut simulator = Simulator::new(&model, outputs);
    let n = simulator.storage().len();
    let start = Mode::parse(&model, "fr_ge=stuck,k=slack,fr_ct=stuck").unwrap();
    let inputs = [110e3, 5.8e-3, 1.8e-3];
    let b_index = model
        .parameters()
        .iter()
        .find(|p| p.name == "b")
        .unwrap()
        .symbol
        .index();
    for b in [1250.0, 2500.0, 600.0] {
        let mut values = model.values().to_vec();
        values[b_index] = b;
        simulator.set_parameter_values(&values).unwrap();
        let steady = steady_state(
            &mut simulator,
            &inputs,
            start.clone(),
            vec![0.0; n],
            &SteadySettings::default(),
        )
        .unwrap();
        let expected = (A * 110e3 - F_C_GE + 2.0 * K_P * 1.8e-3) / (b + 4.0 * K_P);
        assert!(
            close(steady.outputs[0], expected),
            "b = {b}: {} against {expected}",
            steady.outputs[0]
        );
    }
    assert!(simulator.set_parameter_values(&[1.0]).is_err());
}

#[test]
fn a_catheter_contact_whose_two_friction_forces_differ_by_rounding_still_slips() {
    // The catheter contact's breakaway force exceeds its Coulomb force by 1.7e-8 N (2e-9 of
    // 8.28 N), below the rounding of the forces its guards weigh. From rest, the tip breaks
    // away and the catheter slips backwards against the contact; when the contact's relative
    // velocity first reaches zero, stuck breaks away at once and each slip direction's
    // acceleration is judged level against the stiff tip's terms: the run once stopped there
    // ("no mode is consistent: switching 'fr_ct' cycles"). It must slip on as it does with
    // the two forces equal or 1 mN apart, the tip at v = (P_s A + 2 F_C_ct - F_C_ge)/b.
    let (f_c_ct, f_c_ge, b, p_s) = (8.27680505338857, 9.0, 1300.0, 1.1e5);
    let text = format!(
        r#"Scenario(name: "edge",
            parameters: {{"F_C_ct": {f_c_ct:?}, "F_S_ct": 8.276805070605269,
                          "F_C_ge": {f_c_ge:?}, "F_S_ge": 11.5, "b": {b:?}}},
            inputs: {{"P_s": Constant({p_s:?}), "v_ac": Constant(0.05), "v_ct_des": Constant(0.03)}},
            duration: 2.0, record: ["flow:ge"], sample: 0.5)"#
    );
    let root = support::root();
    let model = bondgraph_core::source::SourceFile::new(
        "models/eversion/robot.ron",
        std::fs::read_to_string(root.join("models/eversion/robot.ron")).unwrap(),
    );
    let scenario = bondgraph_core::source::SourceFile::new("edge.ron", text);
    let scenario = bondgraph_ron::scenario::load(&scenario, &model).unwrap();
    let trajectory = bondgraph_solver::scenario::run(&scenario, false).unwrap();
    let last = trajectory.times.len() - 1;
    let v = trajectory.value(last, 0).unwrap();
    let expected = (p_s * A + 2.0 * f_c_ct - f_c_ge) / b;
    assert!(close(v, expected), "{v} against {expected}");
    let mode = &trajectory.modes[trajectory.sample_modes[last]];
    assert_eq!(mode, "fr_ge=slip+,k=slack,fr_ct=slip-");
}
