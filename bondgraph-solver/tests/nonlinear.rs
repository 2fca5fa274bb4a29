//! Nonlinear modes against answers computed independently: the pendulum's period from the
//! complete elliptic integral (by the arithmetic-geometric mean), Torricelli's draining
//! law, the diode circuit by quadrature of `t(v)` and in closed form, the lever against the
//! exact linear propagation, the Duffing oscillator and the stick-slip spring against RK4
//! with tiny steps written here.

use bondgraph_core::equations::OutputSpec;
use bondgraph_core::model::Model;
use bondgraph_core::modes::Mode;
use bondgraph_solver::steady::{SteadySettings, steady_state};
use bondgraph_solver::{Output, Run, Signal, Simulator, Trajectory};

use crate::support::{Constant, load};

fn output(model: &Model, spec: &str) -> Output {
    let integral = spec.starts_with("integral:");
    let text = spec.strip_prefix("integral:").unwrap_or(spec);
    Output {
        name: spec.to_string(),
        spec: OutputSpec::parse(model, text).unwrap(),
        integral,
    }
}

fn simulate(
    model: &Model,
    records: &[&str],
    inputs: &[&dyn Signal],
    initial_state: Vec<f64>,
    duration: f64,
    sample: f64,
) -> Trajectory {
    let outputs = records.iter().map(|r| output(model, r)).collect();
    let mut simulator = Simulator::new(model, outputs);
    simulator
        .run(&Run {
            inputs,
            initial_mode: Mode::initial(model),
            initial_state,
            duration,
            sample: Some(sample),
            audit_energy: true,
        })
        .unwrap_or_else(|e| panic!("{}: {e}", model.name()))
}

/// The complete elliptic integral of the first kind, `K(k) = π / (2 AGM(1, √(1 - k²)))`.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Times where `values` crosses zero downwards, by linear interpolation of the samples.
fn downward_zeros(times: &[f64], values: &[f64]) -> Vec<f64> {
    (1..values.len())
        .filter(|&i| values[i - 1] > 0.0 && values[i] <= 0.0)
        .map(|i| {
            let f = values[i - 1] / (values[i - 1] - values[i]);
            times[i - 1] + f * (times[i] - times[i - 1])
        })
        .collect()
}

fn column(trajectory: &Trajectory, k: usize) -> Vec<f64> {
    (0..trajectory.times.len())
        .map(|i| trajectory.value(i, k).unwrap())
        .collect()
}

#[test]
fn the_pendulum_s_period_is_the_elliptic_integral_s() {
    let model = load("models/examples/nonlinear/pendulum.ron");
    let (l, g): (f64, f64) = (1.0, 9.81);
    for theta0 in [0.5, 2.0, 3.0] {
        let period = 4.0 * elliptic_k((theta0 / 2.0_f64).sin()) * (l / g).sqrt();
        let trajectory = simulate(
            &model,
            &["effort:gravity"],
            &[],
            vec![0.0, theta0],
            2.2 * period,
            1e-4,
        );
        // The torque m g l sin θ crosses zero downwards once a period.
        let zeros = downward_zeros(&trajectory.times, &column(&trajectory, 0));
        assert!(zeros.len() >= 2, "θ0 = {theta0}: {zeros:?}");
        let measured = zeros[1] - zeros[0];
        assert!(
            (measured - period).abs() < 1e-7 * period,
            "θ0 = {theta0}: period {measured} s, elliptic integral {period} s"
        );
        // Released from θ0 the first zero is a quarter period later.
        assert!((zeros[0] - period / 4.0).abs() < 1e-7 * period);
        // No damping: the energy books balance and the stored energy stays m g l (1 - cos θ0).
        let energy = trajectory.energy.unwrap();
        let stored = g * l * (1.0 - theta0.cos());
        assert!((energy.initial_stored - stored).abs() < 1e-12 * stored);
        assert!(
            (energy.final_stored - stored).abs() < 1e-8 * stored,
            "{energy:?}"
        );
    }
}

#[test]
fn the_tank_s_level_falls_as_torricelli_says_until_it_is_empty() {
    let model = load("models/examples/nonlinear/orifice_tank.ron");
    let (area, orifice, c_d, rho, g): (f64, f64, f64, f64, f64) = (0.5, 0.001, 0.6, 1000.0, 9.81);
    let q0: f64 = 0.5;
    let k = c_d * orifice * (g / (2.0 * area)).sqrt();
    let empty = q0.sqrt() / k;
    let trajectory = simulate(
        &model,
        &["effort:tank", "flow:orifice"],
        &[],
        vec![q0],
        1.2 * empty,
        1.0,
    );
    // sqrt(q) falls linearly until the tank is empty.
    for (i, &t) in trajectory.times.iter().enumerate() {
        if t > empty - 5.0 {
            break;
        }
        let q = trajectory.value(i, 0).unwrap() * area / (rho * g);
        let expected = q0.sqrt() - k * t;
        assert!(
            (q.max(0.0).sqrt() - expected).abs() < 1e-7 * q0.sqrt(),
            "t = {t}: {}",
            q.sqrt() - expected
        );
    }
    // Then the event: the tank is empty (its pressure reaches zero) and stays empty.
    assert_eq!(trajectory.events.len(), 1, "{:?}", trajectory.events);
    let event = &trajectory.events[0];
    assert_eq!(
        (event.from.as_str(), event.to.as_str()),
        ("tank=taut", "tank=slack")
    );
    // The level reaches zero tangentially (q ∝ (t_e - t)²), so the event is located only as
    // well as the volume is known near zero: to sqrt(absolute tolerance)/k, with the
    // integrator's absolute tolerance on the volume (1e-12 scaled as its error estimate is,
    // about 2.2e-10 m³).
    let bound = 2.2e-10_f64.sqrt() / k;
    assert!(
        (event.t - empty).abs() < bound,
        "event at {} s, empty at {empty} s (bound {bound})",
        event.t
    );
    let (_, volume) = &trajectory.final_state[0];
    assert!(volume.abs() < 1e-9, "{volume}");
    let last = trajectory.times.len() - 1;
    assert_eq!(trajectory.value(last, 1), Some(0.0));
}

/// The diode circuit's parameters.
const C: f64 = 1.0e-6;
const R: f64 = 1.0e4;
const I_S: f64 = 1.0e-12;
const V_T: f64 = 0.025852;

fn diode_current(v: f64) -> f64 {
    I_S * ((v / V_T).exp() - 1.0)
}

/// `t(v)`: the time the circuit takes from `v0` down to `v`, `C ∫_v^v0 dv / i(v)`, by
/// Gauss–Legendre quadrature on many panels.
fn time_to_reach(v: f64, v0: f64, leak: bool) -> f64 {
    let current = |x: f64| diode_current(x) + if leak { x / R } else { 0.0 };
    let panels = 20_000;
    let nodes = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    let weights = [
        0.347_854_845_137_453_9,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_9,
    ];
    // Panels graded towards v0, where the current is largest and the integrand smallest.
    let mut total = 0.0;
    for p in 0..panels {
        let a = v + (v0 - v) * (p as f64 / panels as f64);
        let b = v + (v0 - v) * ((p + 1) as f64 / panels as f64);
        let (mid, half) = ((a + b) / 2.0, (b - a) / 2.0);
        for (x, w) in nodes.iter().zip(weights) {
            total += w * half * C / current(mid + half * x);
        }
    }
    total
}

#[test]
fn the_diode_circuit_follows_its_quadrature_and_closed_form() {
    let model = load("models/examples/nonlinear/diode_rc.ron");
    let v0 = 0.7;
    let trajectory = simulate(
        &model,
        &["effort:cap", "flow:diode"],
        &[],
        vec![C * v0],
        0.02,
        1e-4,
    );
    for (i, &t) in trajectory.times.iter().enumerate().skip(1).step_by(10) {
        let v = trajectory.value(i, 0).unwrap();
        // A time error is a voltage error of Δt·i(v)/C. Samples come from the steps'
        // collocation polynomials (order 3), so they are held to 1e-8, not the 1e-10 the
        // steps themselves are.
        let slope = (diode_current(v) + v / R) / C;
        let error = (time_to_reach(v, v0, true) - t) * slope;
        assert!(error.abs() < 1e-8 * v0, "t = {t}: v = {v}, error {error} V");
        // The diode's current is Shockley's at the capacitor's voltage.
        let current = trajectory.value(i, 1).unwrap();
        assert!((current - diode_current(v)).abs() <= 1e-12 * current.abs().max(1e-18));
    }
    // Without the leak, v(t) = -V_T ln(1 - (1 - e^{-v0/V_T}) e^{-I_s t/(C V_T)}).
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../models/examples/nonlinear/diode_rc.ron"
    ))
    .unwrap()
    .replace("\"leak\": R(resistance: \"R\"),", "")
    .replace("(\"node\", \"leak\"),", "");
    let alone = bondgraph_ron::model::load_str("diode_alone.ron", &text).unwrap();
    let trajectory = simulate(&alone, &["effort:cap"], &[], vec![C * v0], 1.0, 1e-3);
    let tau = C * V_T / I_S;
    for (i, &t) in trajectory.times.iter().enumerate().step_by(50) {
        let v = trajectory.value(i, 0).unwrap();
        // 1 - (1 - a) e^{-s} written as -expm1(-s) + a e^{-s}, without cancellation.
        let (a, s) = ((-v0 / V_T).exp(), t / tau);
        let exact = -V_T * (-(-s).exp_m1() + a * (-s).exp()).ln();
        assert!((v - exact).abs() < 1e-8 * v0, "t = {t}: {v} vs {exact}");
    }
}

/// A step, for the lever.
struct Step {
    at: f64,
    after: f64,
}

impl Signal for Step {
    fn value(&self, t: f64) -> f64 {
        if t >= self.at { self.after } else { 0.0 }
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        vec![self.at]
    }
}

#[test]
fn the_modulated_lever_moves_its_load_as_the_fixed_lever_does() {
    let modulated = load("models/examples/nonlinear/lever.ron");
    assert!(modulated.is_nonlinear());
    // The same lever with its ratio fixed at r_0*1.5 is linear: propagated exactly.
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../models/examples/nonlinear/lever.ron"
    ))
    .unwrap()
    .replace("TF(ratio: \"r_0*c_theta\")", "TF(ratio: \"r_0*1.5\")");
    let fixed = bondgraph_ron::model::load_str("lever_fixed.ron", &text).unwrap();
    assert!(!fixed.is_nonlinear());
    let force = Step {
        at: 0.1,
        after: 12.0,
    };
    let setting = Constant(1.5);
    let inputs: [&dyn Signal; 2] = [&force, &setting];
    let records = ["effort:spring", "flow:mass", "integral:flow:mass"];
    let a = simulate(&modulated, &records, &inputs, vec![0.0, 0.0], 1.0, 1e-3);
    let b = simulate(&fixed, &records, &inputs, vec![0.0, 0.0], 1.0, 1e-3);
    assert_eq!(a.times.len(), b.times.len());
    let scale = 4.0; // the load feels 12 N / 3
    for (k, record) in records.iter().enumerate() {
        for i in 0..a.times.len() {
            let (x, y) = (a.value(i, k).unwrap(), b.value(i, k).unwrap());
            assert!(
                (x - y).abs() < 1e-8 * scale,
                "{record} at {}: {x} vs {y}",
                a.times[i]
            );
        }
    }
    // The energy books balance: what the force supplied is stored or dissipated.
    let energy = a.energy.unwrap();
    assert!(
        energy.residual().abs() < 1e-8 * energy.scale(),
        "{energy:?}"
    );
}

/// RK4 of `(q, p)` for a mass `m` on a spring force `spring(q)` with a damper `b`.
fn rk4(
    spring: impl Fn(f64) -> f64,
    m: f64,
    b: f64,
    mut q: f64,
    mut p: f64,
    end: f64,
    steps: usize,
) -> (f64, f64) {
    let h = end / steps as f64;
    let f = |q: f64, p: f64| (p / m, -spring(q) - b * p / m);
    for _ in 0..steps {
        let (k1q, k1p) = f(q, p);
        let (k2q, k2p) = f(q + h / 2.0 * k1q, p + h / 2.0 * k1p);
        let (k3q, k3p) = f(q + h / 2.0 * k2q, p + h / 2.0 * k2p);
        let (k4q, k4p) = f(q + h * k3q, p + h * k3p);
        q += h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q);
        p += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
    }
    (q, p)
}

#[test]
fn the_duffing_oscillator_s_energy_decays_as_rk4_says() {
    let model = load("models/examples/nonlinear/duffing.ron");
    let (m, k, k3, b) = (1.0, 1.0, 5.0, 0.1);
    let spring = |q: f64| k * q + k3 * q * q * q;
    let energy = |q: f64, p: f64| p * p / (2.0 * m) + k * q * q / 2.0 + k3 * q.powi(4) / 4.0;
    let force = Constant(0.0);
    let trajectory = simulate(
        &model,
        &["effort:spring", "flow:mass"],
        &[&force],
        vec![0.0, 1.5],
        20.0,
        0.01,
    );
    for t in [1.0, 5.0, 10.0, 20.0] {
        let i = (t / 0.01_f64).round() as usize;
        assert!((trajectory.times[i] - t).abs() < 1e-12);
        let (q, p) = rk4(spring, m, b, 1.5, 0.0, t, (t * 20_000.0) as usize);
        // The spring force k q + k_3 q³ and the velocity p/m, against RK4 with tiny steps.
        let force_error = trajectory.value(i, 0).unwrap() - spring(q);
        let velocity_error = trajectory.value(i, 1).unwrap() - p / m;
        assert!(
            force_error.abs() < 1e-7 * spring(1.5),
            "t = {t}: {force_error}"
        );
        assert!(velocity_error.abs() < 1e-7, "t = {t}: {velocity_error}");
        if t == 20.0 {
            let books = trajectory.energy.unwrap();
            let (decayed, initial) = (energy(q, p), energy(1.5, 0.0));
            assert!(
                (books.final_stored - decayed).abs() < 1e-7 * initial,
                "{books:?}"
            );
            assert!((books.dissipated - (initial - decayed)).abs() < 1e-7 * initial);
            assert!(books.residual().abs() < 1e-8 * books.scale());
        }
    }
}

#[test]
fn a_nonlinear_steady_state_balances_the_spring() {
    let model = load("models/examples/nonlinear/duffing.ron");
    let outputs = vec![output(&model, "effort:spring"), output(&model, "flow:mass")];
    let mut simulator = Simulator::new(&model, outputs);
    let steady = steady_state(
        &mut simulator,
        &[2.0],
        Mode::initial(&model),
        vec![0.0, 0.0],
        &SteadySettings::default(),
    )
    .unwrap();
    assert!((steady.outputs[0] - 2.0).abs() < 1e-8, "{steady:?}");
    assert!(steady.outputs[1].abs() < 1e-8);
}

#[test]
fn the_stick_slip_spring_breaks_away_and_sticks_when_rk4_says() {
    let model = load("models/examples/nonlinear/stick_slip_spring.ron");
    let (m, k, k3, f_s, f_c, v) = (1.0, 100.0, 2.0e4, 10.0, 6.0, 0.1);
    let spring = |q: f64| k * q + k3 * q * q * q;
    let belt = Constant(v);
    let trajectory = simulate(
        &model,
        &["effort:spring", "flow:block"],
        &[&belt],
        vec![0.0, 0.0],
        1.0,
        1e-3,
    );
    // Stuck, the spring stretches at the belt's speed: it breaks away where
    // k q + k_3 q³ = F_S (by bisection here), at t = q/v.
    let (mut low, mut high) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = (low + high) / 2.0;
        if spring(mid) < f_s {
            low = mid
        } else {
            high = mid
        }
    }
    let breakaway = low / v;
    let first = &trajectory.events[0];
    assert_eq!(first.to, "friction=slip+");
    assert!(
        (first.t - breakaway).abs() < 1e-9,
        "{} vs {breakaway}",
        first.t
    );
    // Slipping, m dv/dt = F_C - k q - k_3 q³ (kinetic friction drags it along) until the
    // block catches up with the belt; RK4 with tiny steps and a cubic Hermite root.
    let f = |q: f64, u: f64| (u, (f_c - spring(q)) / m);
    let (mut q, mut u, mut t) = (low, v, breakaway);
    let h = 1e-6;
    let stick = loop {
        let (k1q, k1u) = f(q, u);
        let (k2q, k2u) = f(q + h / 2.0 * k1q, u + h / 2.0 * k1u);
        let (k3q, k3u) = f(q + h / 2.0 * k2q, u + h / 2.0 * k2u);
        let (k4q, k4u) = f(q + h * k3q, u + h * k3u);
        let (q1, u1) = (
            q + h / 6.0 * (k1q + 2.0 * k2q + 2.0 * k3q + k4q),
            u + h / 6.0 * (k1u + 2.0 * k2u + 2.0 * k3u + k4u),
        );
        // Relative velocity v - u leaves zero upwards and comes back down.
        if t > breakaway + 1e-3 && v - u > 0.0 && v - u1 <= 0.0 {
            let (d0, d1) = (-(f(q, u).1), -(f(q1, u1).1));
            let (y0, y1) = (v - u, v - u1);
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
            break t + a * h;
        }
        (q, u, t) = (q1, u1, t + h);
    };
    let second = &trajectory.events[1];
    assert_eq!(second.to, "friction=stuck");
    assert!((second.t - stick).abs() < 1e-9, "{} vs {stick}", second.t);
    let energy = trajectory.energy.unwrap();
    assert!(
        energy.residual().abs() < 1e-8 * energy.scale(),
        "{energy:?}"
    );
}

/// A recorded signal that is zero at each of its 1000 samples and, as a measured signal's
/// samples are, a breakpoint at every one. (A table of zeros has none: its rate never
/// changes.)
struct ZeroAtEverySample;

impl Signal for ZeroAtEverySample {
    fn value(&self, _: f64) -> f64 {
        0.0
    }
    fn rate(&self, _: f64) -> f64 {
        0.0
    }
    fn breakpoints(&self) -> Vec<f64> {
        (0..=1000).map(|k| k as f64 * 1e-3).collect()
    }
}

/// A mass braked by a cubic drag, `m dv/dt = -c v³ + F(t)`, with `F` a recorded signal that is
/// zero at each of its 1000 samples, every one a breakpoint, so the run is 1000 integrated
/// segments of one nonlinear mode, each starting where the last left off (on the
/// simulator's one integrator, reset). The speed is `v(t) = v₀ / √(1 + 2 (c/m) v₀² t)`; with
/// m = 2 kg, c = 0.5 N s³/m³ and v₀ = 3 m/s, `v(1 s) = 3/√5.5`.
#[test]
fn a_nonlinear_mode_through_a_thousand_breakpoints_keeps_its_accuracy() {
    let model = bondgraph_ron::model::load_str(
        "drag.ron",
        r#"Model(
    name: "drag",
    parameters: {
        "m": (value: 2.0, unit: "kg"),
        "c": (value: 0.5, unit: "N*s^3/m^3"),
    },
    inputs: { "F": (unit: "N") },
    elements: {
        "push": Se(effort: "F"),
        "body": One,
        "mass": I(inertance: "m"),
        "drag": R(effort: "c*flow^3"),
    },
    bonds: [("push", "body"), ("body", "mass"), ("body", "drag")],
)"#,
    )
    .expect("valid");
    let trajectory = simulate(
        &model,
        &["flow:mass"],
        &[&ZeroAtEverySample],
        vec![2.0 * 3.0],
        1.0,
        0.25,
    );
    assert!(trajectory.stats.segments >= 1000, "{:?}", trajectory.stats);
    for (k, &t) in trajectory.times.iter().enumerate() {
        let exact = 3.0 / (1.0 + 2.0 * 0.25 * 9.0 * t).sqrt();
        let v = trajectory.value(k, 0).expect("a sample");
        assert!(
            (v - exact).abs() < 1e-9 * exact,
            "v({t}) = {v} against {exact}"
        );
    }
}
