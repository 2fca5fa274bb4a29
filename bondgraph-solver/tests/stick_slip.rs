//! The block on a moving belt (`models/examples/belt_friction.ron`): stick-slip with known
//! event times and period.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Signal, Simulator};

use crate::support::{Constant, load};

/// The block's velocity, the one output both tests record.
fn block_velocity(model: &bondgraph_core::model::Model) -> Vec<Output> {
    vec![Output {
        name: "flow:block".into(),
        spec: OutputSpec::parse(model, "flow:block").unwrap(),
        integral: false,
    }]
}

/// By hand, with m = 1 kg, k = 100 N/m, F_S = 10 N, F_C = 6 N and the belt at V = 0.1 m/s,
/// starting stuck with the spring relaxed:
/// - stuck, the spring stretches at V and the contact holds k q; it breaks away when
///   k q = F_S, i.e. q = 0.1 m, after t₁ = 0.1/V = 1 s;
/// - slipping, m v' = F_C - k q: y = q - F_C/k = q - 0.06 oscillates at ω = √(k/m) = 10 rad/s
///   from y₀ = 0.04, y'₀ = V: v(τ) = V cos ωτ - ω y₀ sin ωτ; the block matches the belt again
///   (v = V, the relative velocity back to zero) at τ_s = 2(π - atan2(ω y₀, V))/ω... written
///   as v = R cos(ωτ + φ) with tan φ = ω y₀/V = 4: ωτ + φ = 2π - φ, τ_s = (π - atan 4)/5;
/// - there y = -y₀ (energy), q = 0.02 m, the contact must hold k q = 2 N < F_S: it sticks, and
///   the spring needs (0.1 - 0.02)/V = 0.8 s to reach breakaway again. Period 0.8 s + τ_s.
#[test]
fn event_times_and_period_match_the_closed_form() {
    let model = load("models/examples/belt_friction.ron");
    let mut simulator = Simulator::new(&model, block_velocity(&model));
    let belt = Constant(0.1);
    let inputs: [&dyn Signal; 1] = [&belt];
    let run = Run {
        inputs: &inputs,
        initial_mode: Mode::parse(&model, "friction=stuck").unwrap(),
        initial_state: vec![0.1, 0.0], // p_block = m V (riding with the belt), q_spring = 0
        duration: 3.5,
        sample: Some(0.01),
        audit_energy: false,
    };
    let trajectory = simulator.run(&run).unwrap();
    let slip = (std::f64::consts::PI - 4f64.atan()) / 5.0;
    // Within 3.5 s: the next breakaway-to-stick event would come at 2.6 + 3 τ_s ≈ 3.69 s.
    let expected = [
        1.0,
        1.0 + slip,
        1.8 + slip,
        1.8 + 2.0 * slip,
        2.6 + 2.0 * slip,
    ];
    let times: Vec<f64> = trajectory.events.iter().map(|e| e.t).collect();
    assert_eq!(times.len(), expected.len(), "{:#?}", trajectory.events);
    for (t, e) in times.iter().zip(expected) {
        assert!((t - e).abs() < 1e-9, "event at {t}, expected {e}");
    }
    let modes: Vec<&str> = trajectory.events.iter().map(|e| e.to.as_str()).collect();
    assert_eq!(
        modes,
        [
            "friction=slip+",
            "friction=stuck",
            "friction=slip+",
            "friction=stuck",
            "friction=slip+"
        ]
    );
    // Period: between successive breakaways.
    assert!(((times[2] - times[0]) - (0.8 + slip)).abs() < 1e-9);
    assert!(((times[4] - times[2]) - (0.8 + slip)).abs() < 1e-9);
}

/// The same stick-slip cycle never settles: a steady-state search gives up after the mode
/// changes it allows, at the event that exceeds them, and says why. With 20 allowed, the
/// 21st event is the 11th breakaway, at 1 s + 10 periods of 0.8 s + τ_s (events above).
#[test]
fn a_steady_state_search_gives_up_on_a_cycle_after_its_mode_changes() {
    use bondgraph_solver::steady::{SteadyError, SteadySettings, steady_state};
    let model = load("models/examples/belt_friction.ron");
    let mut simulator = Simulator::new(&model, block_velocity(&model));
    let settings = SteadySettings {
        max_mode_changes: 20,
        ..SteadySettings::default()
    };
    let error = steady_state(
        &mut simulator,
        &[0.1],
        Mode::parse(&model, "friction=stuck").unwrap(),
        vec![0.1, 0.0],
        &settings,
    )
    .unwrap_err();
    let SteadyError::NotSteady { t, why, .. } = &error else {
        panic!("{error}");
    };
    let slip = (std::f64::consts::PI - 4f64.atan()) / 5.0;
    let expected = 1.0 + 10.0 * (0.8 + slip);
    assert!(
        (t - expected).abs() < 1e-6,
        "gave up at {t}, expected {expected}"
    );
    assert_eq!(why, "it changed mode more than 20 times without settling");
}
