//! Event detection on the nonlinear (integrated) path, against the three problems first
//! found on the linear path (`hardening.rs`): a guard that dips through zero and back
//! between two looks, a guard that starts at exactly zero, and a contact reversing through
//! zero velocity; and chattering reported as on the linear path. Every expected value is
//! computed here independently: RK4 with tiny steps, or a closed form.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::{Output, Run, Settings, Signal, SimError, Simulator, Trajectory};

use crate::support::{Constant, load};

fn run(
    model: &Model,
    outputs: &[&str],
    inputs: &[&dyn Signal],
    x0: Vec<f64>,
    end: f64,
) -> Trajectory {
    let outputs = outputs
        .iter()
        .map(|name| Output {
            name: (*name).into(),
            spec: OutputSpec::parse(model, name).unwrap(),
            integral: false,
        })
        .collect();
    let mut simulator = Simulator::new(model, outputs);
    simulator
        .run(&Run {
            inputs,
            initial_mode: Mode::initial(model),
            initial_state: x0,
            duration: end,
            sample: Some(end / 1000.0),
            audit_energy: true,
        })
        .unwrap_or_else(|e| panic!("{}: {e}", model.name()))
}

/// One RK4 step of `dy/dt = f(y)` for a state of two.
fn rk4_step(f: &impl Fn([f64; 2]) -> [f64; 2], y: [f64; 2], h: f64) -> [f64; 2] {
    let add = |a: [f64; 2], b: [f64; 2], s: f64| [a[0] + s * b[0], a[1] + s * b[1]];
    let k1 = f(y);
    let k2 = f(add(y, k1, h / 2.0));
    let k3 = f(add(y, k2, h / 2.0));
    let k4 = f(add(y, k3, h));
    [
        y[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
        y[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
    ]
}

/// The root in `(0, h)` of the cubic Hermite interpolant of `y` (values `y0`, `y1`,
/// slopes `d0`, `d1` at the ends of a step `h`), `y0 > 0 >= y1`, by bisection.
fn hermite_root(y0: f64, y1: f64, d0: f64, d1: f64, h: f64) -> f64 {
    let hermite = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * y0
            + (s3 - 2.0 * s2 + s) * h * d0
            + (-2.0 * s3 + 3.0 * s2) * y1
            + (s3 - s2) * h * d1
    };
    let (mut a, mut b) = (0.0, 1.0);
    for _ in 0..100 {
        let mid = (a + b) / 2.0;
        if hermite(mid) > 0.0 { a = mid } else { b = mid }
    }
    a * h
}

/// The stick-slip spring of `models/examples/nonlinear/stick_slip_spring.ron`: m = 1 kg,
/// `k q + k_3 q³` with k = 100 N/m and k_3 = 2e4 N/m³, F_S = 10 N, F_C = 6 N.
const BLOCK: f64 = 1.0;
const F_S: f64 = 10.0;
const F_C: f64 = 6.0;

fn hardening_spring(q: f64) -> f64 {
    100.0 * q + 2.0e4 * q * q * q
}

/// Where the stuck spring breaks away, `k q_0 + k_3 q_0³ = F_S`, by bisection.
fn breakaway_extension() -> f64 {
    let (mut low, mut high) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = (low + high) / 2.0;
        if hardening_spring(mid) < F_S {
            low = mid
        } else {
            high = mid
        }
    }
    low
}

/// The block slipping forward from `q_0` at the belt's speed `v`, `m u' = F_C - k q - k_3 q³`,
/// by RK4 with steps of 0.1 µs, until its velocity relative to the belt, `v - u`, which
/// starts at zero and rises, falls back through zero (a cubic Hermite root on the step):
/// the time after breakaway and the extension where it sticks.
fn slip_until_stuck(q0: f64, v: f64) -> (f64, f64) {
    let f = |y: [f64; 2]| [y[1], (F_C - hardening_spring(y[0])) / BLOCK];
    let h = 1e-7;
    let (mut y, mut t) = ([q0, v], 0.0);
    loop {
        let next = rk4_step(&f, y, h);
        if v - y[1] > 0.0 && v - next[1] <= 0.0 {
            let s = hermite_root(v - y[1], v - next[1], -f(y)[1], -f(next)[1], h);
            // The extension there, from the Hermite cubic of q (slopes u).
            let r = s / h;
            let (r2, r3) = (r * r, r * r * r);
            let q = (2.0 * r3 - 3.0 * r2 + 1.0) * y[0]
                + (r3 - 2.0 * r2 + r) * h * y[1]
                + (-2.0 * r3 + 3.0 * r2) * next[0]
                + (r3 - r2) * h * next[1];
            return (t + s, q);
        }
        (y, t) = (next, t + h);
    }
}

/// Item 1 on the nonlinear path: the stick-slip spring on a fast belt. Stuck from rest, it
/// breaks away at `q_0`; slipping from `u = v`, it swings far out and back, and on the way
/// forward its velocity `u` passes the belt's `v` at `q_1 < q_0` (where `W(q_1) = W(q_0)`,
/// `W = k q²/2 + k_3 q⁴/4 - F_C q`), where it sticks: its velocity relative to the belt is
/// negative from `q_1` to `q_0` only, for about `(q_0 - q_1)/v` (0.33 ms of a 52 ms swing
/// at v = 100 m/s, 33 µs of 17 ms at 1000 m/s), a brief dip of the guard between two looks
/// of the integrator. Stuck, it rides with the belt back to `q_0` and breaks away again
/// after `(q_0 - q_1)/v`. The stick time is found here by RK4 with tiny steps (0.1 µs;
/// halving them moves it by 1e-11 s at v = 1000 m/s). The integrator keeps the velocity to
/// its relative tolerance, 1e-10 of the belt's speed (the block's velocity was within
/// 9e-8 m/s of RK4's through the swing at 1000 m/s), and the relative velocity crosses zero
/// at the rate `(k q_1 + k_3 q_1³ - F_C)/m ≈ -3.1 m/s²`: the stick time is then as good as
/// `1e-10 v / 3.1 m/s²`, 3e-8 s at 1000 m/s, and 1e-9 s is asked where that is less.
#[test]
fn a_fast_belt_sticks_the_hardening_spring_where_rk4_says() {
    let model = load("models/examples/nonlinear/stick_slip_spring.ron");
    let q0 = breakaway_extension();
    for v in [10.0, 100.0, 1000.0] {
        let belt = Constant(v);
        let trajectory = run(
            &model,
            &["effort:spring", "flow:block"],
            &[&belt],
            vec![0.0, 0.0],
            0.5,
        );
        let breakaway = q0 / v;
        let (slip, q_stick) = slip_until_stuck(q0, v);
        let stick = breakaway + slip;
        let slope = (F_C - hardening_spring(q_stick)) / BLOCK;
        let tolerance = (1e-10 * v / slope.abs()).max(1e-9);
        let expected = [
            (breakaway, "friction=slip+"),
            (stick, "friction=stuck"),
            (stick + (q0 - q_stick) / v, "friction=slip+"),
        ];
        assert!(
            trajectory.events.len() >= 3,
            "v = {v}: expected {expected:?}, got {:#?}",
            trajectory.events
        );
        for (event, (t, to)) in trajectory.events.iter().zip(expected) {
            assert_eq!(event.to, to, "v = {v}: {:#?}", trajectory.events);
            assert!(
                (event.t - t).abs() < tolerance,
                "v = {v}: {} {} against {t}",
                event.to,
                event.t
            );
        }
        let energy = trajectory.energy.unwrap();
        assert!(
            energy.residual().abs() < 1e-8 * energy.scale(),
            "v = {v}: {energy:?}"
        );
    }
}

/// Chattering and too many events on the nonlinear path, reported as on the linear one
/// (`trouble.rs`): the stick-slip spring at v = 0.1 m/s breaks away at `q_0/v`, sticks after
/// the slip RK4 gives, and breaks away again `(q_0 - q_1)/v` later. With a limit of three
/// events in any 10 s that third event is chattering; with a limit of two events in a run it
/// is one too many.
#[test]
fn chattering_and_too_many_events_on_the_nonlinear_path_are_errors_at_the_third_event() {
    let model = load("models/examples/nonlinear/stick_slip_spring.ron");
    let v = 0.1;
    let q0 = breakaway_extension();
    let (slip, q_stick) = slip_until_stuck(q0, v);
    let third = q0 / v + slip + (q0 - q_stick) / v;
    for settings in [
        Settings {
            max_events: 1000,
            chatter_events: 3,
            chatter_window: 10.0,
            ..Settings::default()
        },
        Settings {
            max_events: 2,
            ..Settings::default()
        },
    ] {
        let mut simulator = Simulator::new(&model, Vec::new()).with_settings(settings);
        let belt = Constant(v);
        let inputs: [&dyn Signal; 1] = [&belt];
        let error = simulator
            .run(&Run {
                inputs: &inputs,
                initial_mode: Mode::initial(&model),
                initial_state: vec![0.0, 0.0],
                duration: 10.0,
                sample: None,
                audit_energy: false,
            })
            .unwrap_err();
        match &error {
            SimError::Chattering {
                events,
                elements,
                t,
                ..
            } => {
                assert_eq!(settings.chatter_events, 3, "{error}");
                assert_eq!(*events, 3);
                assert_eq!(elements, &["friction"]);
                assert!((t - third).abs() < 1e-9, "{t} against {third}");
                assert!(error.to_string().contains("'friction'"), "{error}");
            }
            SimError::TooManyEvents { t, limit } => {
                assert_eq!(settings.max_events, 2, "{error}");
                assert_eq!(*limit, 2);
                assert!((t - third).abs() < 1e-9, "{t} against {third}");
            }
            other => panic!("expected chattering or too many events, got {other}"),
        }
    }
}

/// A cart (m = 1 kg) with quadratic drag `c u |u|` (c = 10 N s²/m², the nonlinear law)
/// towed by a tension-only string (k_s = 1e4 N/m) from a tug moving at V = 10 m/s; the
/// string's extension grows at `V - u`.
fn towed_cart(initial: &str) -> Model {
    let text = format!(
        r#"Model(
    name: "towed_cart",
    parameters: {{ "m": (value: 1.0), "c": (value: 10.0), "k_s": (value: 1.0e4) }},
    inputs: {{ "V": () }},
    elements: {{
        "tug": Sf(flow: "V"),
        "hitch": Zero,
        "string": TensionOnly(stiffness: "k_s", initial: "{initial}"),
        "v_cart": One,
        "cart": I(inertance: "m"),
        "drag": R(effort: "c*flow*abs(flow)"),
    }},
    bonds: [("tug", "hitch"), ("hitch", "string"), ("hitch", "v_cart"),
        ("v_cart", "cart"), ("v_cart", "drag")],
)"#
    );
    bondgraph_ron::model::load_str("towed_cart.ron", &text).unwrap()
}

/// The towed cart from a slack string at zero extension, the cart moving at `u0`, for
/// `end` seconds; the storage's state in its own order.
fn tow(initial: &str, u0: f64, end: f64) -> Trajectory {
    let model = towed_cart(initial);
    let names = Simulator::new(&model, Vec::new()).storage().names.clone();
    let x0 = names
        .iter()
        .map(|name| match name.as_str() {
            "p_cart" => u0,
            "q_string" => 0.0,
            other => panic!("unexpected state {other}"),
        })
        .collect();
    let tug = Constant(10.0);
    run(&model, &["effort:string", "flow:cart"], &[&tug], x0, end)
}

/// The towed cart taut, `y = (e, u)`: `e' = V - u`, `m u' = k_s e - c u²` (u > 0).
fn taut_rate(y: [f64; 2]) -> [f64; 2] {
    let (m, c, k_s, v) = (1.0, 10.0, 1.0e4, 10.0);
    [v - y[1], (k_s * y[0] - c * y[1] * y[1].abs()) / m]
}

/// Item 2 on the nonlinear path, the start check: the string at zero extension and the cart
/// at the tug's speed. The extension and its rate are zero; its second derivative is the
/// drag's deceleration `c V²/m > 0`, so the string is taut at once (not slack for good), and
/// then pulls the cart as RK4 says, settling where the string holds the drag, `k_s e = c V²`.
#[test]
fn a_towed_cart_at_the_tug_s_speed_tautens_the_string_at_once() {
    let trajectory = tow("slack", 10.0, 1.0);
    assert_eq!(trajectory.events.len(), 1, "{:#?}", trajectory.events);
    assert_eq!(trajectory.events[0].t, 0.0);
    assert_eq!(trajectory.events[0].to, "string=taut");
    let mut y = [0.0, 10.0];
    let h = 1e-6;
    for i in 1..=1000 {
        for _ in 0..1000 {
            y = rk4_step(&taut_rate, y, h);
        }
        if i % 100 == 0 {
            let tension = trajectory.value(i, 0).unwrap();
            assert!((trajectory.times[i] - i as f64 * 1e-3).abs() < 1e-12);
            assert!(
                (tension - 1.0e4 * y[0]).abs() < 1e-7 * 1000.0,
                "t = {}: {tension} against {}",
                trajectory.times[i],
                1.0e4 * y[0]
            );
        }
    }
    let tension = trajectory.value(1000, 0).unwrap();
    assert!((tension - 1000.0).abs() < 1e-6, "{tension}");
}

/// Item 2 on the nonlinear path, the dip from zero: the string slack at zero extension and
/// the cart 1e-4 m/s faster than the tug. The extension falls below zero and the drag
/// (1000 N) brings it back within a fraction of a microsecond, where the string must go
/// taut. Slack, `m u' = -c u²` from `u_0`: the cart is at `(m/c) ln(1 + c u_0 t/m)`, the
/// tug at `V t`, so the string tautens at the root of `V t = (m/c) ln(1 + c u_0 t/m)`
/// (Newton here, from `2 m (u_0 - V)/(c V²)`); taut, the drag damps the swing (critically,
/// `2 c V = 2 √(k_s m)`), so it stays taut and settles at `k_s e = c V²`.
#[test]
fn a_towed_cart_a_little_faster_than_the_tug_tautens_the_string_on_its_return() {
    let (m, c, v, u0) = (1.0, 10.0, 10.0, 10.0001);
    let trajectory = tow("slack", u0, 1.0);
    let g = |t: f64| v * t - m / c * (1.0 + c * u0 * t / m).ln();
    let dg = |t: f64| v - u0 / (1.0 + c * u0 * t / m);
    let mut t1 = 2.0 * m * (u0 - v) / (c * v * v);
    for _ in 0..50 {
        t1 -= g(t1) / dg(t1);
    }
    assert!(t1 > 1e-7 && t1 < 3e-7, "{t1}");
    assert_eq!(
        trajectory.events.len(),
        1,
        "taut at {t1}: {:#?}",
        trajectory.events
    );
    let event = &trajectory.events[0];
    assert_eq!(event.to, "string=taut");
    assert!((event.t - t1).abs() < 1e-12, "{} against {t1}", event.t);
    let tension = trajectory.value(1000, 0).unwrap();
    assert!((tension - 1000.0).abs() < 1e-6, "{tension}");
    let energy = trajectory.energy.unwrap();
    assert!(
        energy.residual().abs() < 1e-8 * energy.scale(),
        "{energy:?}"
    );
}

/// Item 3 on the nonlinear path: the geared motor of `hardening.rs`'s reversal test (R_a =
/// 2 Ω, N = 20, K = 0.050035 N m/A, b = 0.05086 N m s/rad, T_C = 0.1345 N m, T_S = 0.325
/// N m) with windage `c_w w |w|` on its shaft (c_w = 5e-4 N m s²/rad², the nonlinear law),
/// at V = 12 V against a 1 N m brake from rest. The brake breaks the shaft away backwards at
/// once, the current builds, and the shaft turns through zero velocity into forward slip,
/// which it must keep: turning forward it settles where
///     N K V/R_a - T_C - tau_load = (b + N² K²/R_a) w + c_w w²,
/// the positive root of that quadratic. The integrated reversal once stopped with a
/// velocity residue of -1.1e-22 rad/s on the old side, and only the judging by its rate
/// (the linear path's fix, shared) kept the contact from going back and forth three more
/// times at that instant (seen with `Crossed::watches_as` disabled); the landing on a
/// crossing now ends at or past the zero, as on the closed-form path, so both guard it.
#[test]
fn a_contact_reversing_through_zero_velocity_under_windage_keeps_the_new_direction() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../models/examples/geared_motor/geared_motor.ron"
    );
    let mut text = std::fs::read_to_string(path).unwrap();
    for (from, to) in [
        (r#""K": (value: 0.04,"#, r#""K": (value: 0.050035,"#),
        (r#""b": (value: 0.02,"#, r#""b": (value: 0.05086,"#),
        (r#""T_S": (value: 0.25,"#, r#""T_S": (value: 0.325,"#),
        (r#""T_C": (value: 0.2,"#, r#""T_C": (value: 0.1345,"#),
        (
            r#""dw": (value:"#,
            r#""c_w": (value: 5.0e-4), "dw": (value:"#,
        ),
        (
            r#""viscous": R(resistance: "b"),"#,
            r#""viscous": R(resistance: "b"), "windage": R(effort: "c_w*flow*abs(flow)"),"#,
        ),
        (
            r#"("shaft", "viscous"),"#,
            r#"("shaft", "viscous"), ("shaft", "windage"),"#,
        ),
    ] {
        assert!(text.contains(from), "{from}");
        text = text.replace(from, to);
    }
    let model = bondgraph_ron::model::load_str("geared_motor_windage.ron", &text).unwrap();
    assert!(model.is_nonlinear());
    let (voltage, brake) = (Constant(12.0), Constant(1.0));
    let trajectory = run(
        &model,
        &["flow:load_inertia"],
        &[&voltage, &brake],
        vec![0.0, 0.0],
        3.0,
    );
    let to: Vec<&str> = trajectory.events.iter().map(|e| e.to.as_str()).collect();
    assert_eq!(
        to,
        ["bearings=slip-", "bearings=slip+"],
        "{:#?}",
        trajectory.events
    );
    let (n, k, v, r_a, b, c_w): (f64, f64, f64, f64, f64, f64) =
        (20.0, 0.050035, 12.0, 2.0, 0.05086, 5.0e-4);
    let drive = n * k * v / r_a - 0.1345 - 1.0;
    let linear = b + n * n * k * k / r_a;
    let expected = (-linear + (linear * linear + 4.0 * c_w * drive).sqrt()) / (2.0 * c_w);
    let last = trajectory.times.len() - 1;
    let speed = trajectory.value(last, 0).unwrap();
    assert!(
        (speed - expected).abs() < 1e-9 * expected,
        "{speed} rad/s against {expected}"
    );
    let energy = trajectory.energy.unwrap();
    assert!(
        energy.residual().abs() <= 1e-9 * energy.scale(),
        "{energy:?}"
    );
}
