//! A guard that creeps up to zero under a fast, undamped oscillation, hundreds of periods
//! into a segment: past the part of the segment the event locator samples once per
//! sixteenth of a period (10,000 samples, 625 periods), where its samples are a sixteenth of
//! the segment apart (about 150 periods).

use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Run, Signal, Simulator};

use crate::support::Constant;

/// A tug moving at `V` tows, through a tension-only string, a cart of mass `m` tied to the
/// wall by a spring of stiffness `k`. The string is slack: the cart oscillates on its spring
/// alone while the tug draws away.
fn towed_cart(k: f64) -> Model {
    let text = format!(
        r#"Model(
    name: "towed_cart",
    parameters: {{ "m": (value: 1.0), "k": (value: {k:?}), "k_r": (value: 1000.0) }},
    inputs: {{ "V": () }},
    elements: {{
        "tug": Sf(flow: "V"),
        "rope": Zero,
        "string": TensionOnly(stiffness: "k_r", initial: "slack"),
        "v_cart": One,
        "cart": I(inertance: "m"),
        "spring": C(stiffness: "k"),
    }},
    bonds: [("tug", "rope"), ("rope", "string"), ("rope", "v_cart"),
        ("v_cart", "cart"), ("v_cart", "spring")],
)"#
    );
    bondgraph_ron::model::load_str("towed_cart.ron", &text).unwrap_or_else(|e| panic!("{e}"))
}

/// The time the string goes taut, from the cart at rest with its spring stretched by
/// `q_s0` and the string's extension `q_r0`.
fn taut_at(k: f64, q_s0: f64, q_r0: f64, speed: f64, duration: f64) -> f64 {
    let model = towed_cart(k);
    let mut simulator = Simulator::new(&model, Vec::new());
    let names = simulator.storage().names.clone();
    let initial_state = names
        .iter()
        .map(|name| match name.as_str() {
            "p_cart" => 0.0,
            "q_spring" => q_s0,
            "q_string" => q_r0,
            other => panic!("unexpected state {other}"),
        })
        .collect();
    let tug = Constant(speed);
    let inputs: [&dyn Signal; 1] = [&tug];
    let trajectory = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state,
            duration,
            sample: None,
            audit_energy: false,
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let event = trajectory
        .events
        .first()
        .unwrap_or_else(|| panic!("the string never went taut: {:#?}", trajectory.events));
    assert_eq!(event.to, "string=taut", "{:#?}", trajectory.events);
    event.t
}

/// Slack, the cart swings on its spring, `q_s = q_s0 cos ωτ` with ω = √(k/m), and the
/// string's extension grows with the tug's lead: `q_r = q_r0 + V τ - (q_s - q_s0)`. With
/// m = 1 kg, k = 94.09 N/m (ω = 9.7 rad/s), V = 1 mm/s, q_s0 = 1 cm and q_r0 = -0.951 m,
/// `q_r = -0.941 + 0.001 τ - 0.01 cos 9.7τ`: its maxima (where `sin 9.7τ = -V/(q_s0 ω)`)
/// first reach zero at the one at τ = 931.1432 s (0.000143 m), and its first zero, by
/// bisection between that maximum and the minimum before it, is τ = 931.1257838636699 s.
/// Over 940 s the segment's samples were sixteen a period for 625 periods (to 404.8 s),
/// then a sixteenth of the segment apart: at 881.25 and 940 s the guard is below zero, and
/// between them its rate changes sign about 180 times. Looking for a peak from the rates,
/// the locator found one of those extrema, below zero, and the string never went taut
/// (exit 0).
#[test]
fn a_string_creeping_taut_under_a_fast_swing_goes_taut_at_its_first_zero() {
    let expected = 931.1257838636699;
    for duration in [940.0, 1600.0] {
        let t = taut_at(94.09, 0.01, -0.951, 1e-3, duration);
        assert!(
            (t - expected).abs() <= 1e-9 * expected,
            "over {duration} s: taut at {t} s, not {expected} s"
        );
    }
}

/// The same with ω = 10 rad/s and q_r0 = -0.95 m, `q_r = -0.94 + 0.001 τ - 0.01 cos 10τ`:
/// the first maximum above zero is at τ = 930.2266 s and the first zero, by bisection as
/// above, at τ = 930.205287264259 s. Over 940 s the string never went taut either (exit 0);
/// had samples bracketed the zero, they would have bracketed dozens of zeros (the guard
/// crosses zero twice a period from 930 to 950 s), for Brent's method to pick any one.
#[test]
fn a_string_creeping_taut_is_not_taut_at_a_later_zero() {
    let expected = 930.205287264259;
    for duration in [940.0, 1600.0] {
        let t = taut_at(100.0, 0.01, -0.95, 1e-3, duration);
        assert!(
            (t - expected).abs() <= 1e-9 * expected,
            "over {duration} s: taut at {t} s, not {expected} s"
        );
    }
}

/// After it first goes taut (above), the string snaps slack and taut again twice a swing:
/// every switch is at zero extension, where taut it carries no tension either, so no
/// energy is lost at them and the tug's work is what the cart, its spring and the string
/// store. Going slack at 951.5 s the string's extension was left at +1.1e-19 m while its
/// tension's root was found at or below zero: the slack mode's guard (extension rising to
/// zero) read the residue as already crossed, and taut and slack sent the string to each
/// other (`no mode is consistent`, the run stopped).
#[test]
fn a_string_snapping_slack_is_not_taut_again_at_once() {
    let model = towed_cart(94.09);
    let mut simulator = Simulator::new(&model, Vec::new());
    let initial_state = vec![-0.951, 0.0, 0.01];
    assert_eq!(
        simulator.storage().names,
        ["q_string", "p_cart", "q_spring"]
    );
    let tug = Constant(1e-3);
    let inputs: [&dyn Signal; 1] = [&tug];
    let trajectory = simulator
        .run(&Run {
            inputs: &inputs,
            initial_mode: Mode::initial(&model),
            initial_state,
            duration: 1600.0,
            sample: None,
            audit_energy: true,
        })
        .unwrap_or_else(|e| panic!("{e}"));
    for pair in trajectory.events.windows(2) {
        assert_ne!(pair[0].to, pair[1].to, "{pair:#?}");
    }
    let energy = trajectory.energy.unwrap();
    assert!(
        energy.lost_at_events.abs() <= 1e-9 * energy.scale(),
        "{energy:?}"
    );
    assert!(
        energy.residual().abs() <= 1e-9 * energy.scale(),
        "{energy:?}"
    );
}
