//! The energy books against independent values, and their cost: a step on dependent springs
//! (the state jumps by `E Δu`), a motor whose huge torque constant makes it ring at 3e32
//! rad/s, a step at the smallest positive double, and a lightly damped swing over 1000 s.
//!
//! Reference values come from closed forms derived by hand, or were computed with mpmath at
//! 90 digits (the exact exponential of the 2×2 system, augmented with its integral).

use std::sync::mpsc;
use std::time::{Duration, Instant};

use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;

fn model_file(relative: &str) -> std::sync::Arc<SourceFile> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    SourceFile::new(relative, text)
}

/// Runs a scenario on another thread, failing if it takes longer than `limit` (a hang
/// would otherwise stall the suite): the trajectory and the time taken.
fn simulate_within(model: &str, scenario_text: &str, limit: Duration) -> (Trajectory, Duration) {
    let scenario =
        bondgraph_ron::scenario::load(&SourceFile::new("s.ron", scenario_text), &model_file(model))
            .unwrap_or_else(|e| panic!("{e}"));
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let start = Instant::now();
        let result = bondgraph_solver::scenario::run(&scenario, false);
        let _ = send.send((result, start.elapsed()));
    });
    match receive.recv_timeout(limit) {
        Ok((Ok(trajectory), took)) => (trajectory, took),
        Ok((Err(e), _)) => panic!("{e}"),
        Err(_) => panic!("{model}: not done in {limit:?}"),
    }
}

fn column(trajectory: &Trajectory, name: &str) -> Vec<f64> {
    let k = trajectory
        .output_names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", trajectory.output_names));
    (0..trajectory.times.len())
        .map(|i| trajectory.value(i, k).unwrap())
        .collect()
}

fn at(trajectory: &Trajectory, name: &str, t: f64) -> f64 {
    let i = trajectory
        .times
        .iter()
        .position(|s| (s - t).abs() < 1e-9)
        .unwrap_or_else(|| panic!("no sample at {t}"));
    column(trajectory, name)[i]
}

const BOOKS: &str = r#"["energy:supplied", "energy:dissipated", "energy:stored"]"#;

/// Rowell & Wormley's dependent spring (m = 2, B = 8, K1 = 300, K2 = 100), F stepping from
/// 0 to F0 = 12 N at 0.1 s. The node between the springs has no mass, so both springs take
/// the step at once: f_K1 jumps to E F0 (E = K1/(K1 + K2)) and the stored energy by
/// F0²/(2(K1 + K2)) = 0.18 J. The step is the limit of a ramp, along which F rises while
/// the node moves by F0/(K1 + K2): the source does ∫F dx = F0²/(2(K1 + K2)), exactly what
/// the springs store. After the step F = F0, and the source's work is F0 times the node's
/// travel, (F0 - f_K1)/K2 from f_K1 = E F0: supplied(t) = 0.18 + F0 (E F0 - f_K1(t))/K2.
/// The values at 0.15, 0.5, 1 and 2 s are mpmath's (dissipated also checked there against
/// its quadrature of B v², 0.45443735216220938 at 0.5 s).
#[test]
fn a_force_step_on_dependent_springs_books_the_energy_of_the_jump() {
    let scenario = format!(
        r#"Scenario(name: "step", inputs: {{"F": Step(at: 0.1, before: 0.0, after: 12.0)}},
            duration: 2.0, sample: 0.05, record: {BOOKS})"#
    );
    let (trajectory, _) = simulate_within(
        "models/examples/rowell_wormley_dependent_spring.lg.ron",
        &scenario,
        Duration::from_secs(60),
    );
    // (t, supplied, stored).
    let expected = [
        (0.15, 0.227_047_961_180_195_5, 0.221_328_764_908_821_75),
        (0.5, 1.465_443_406_219_535_8, 1.011_006_054_057_326_4),
        (1.0, 1.229_155_759_181_080_8, 0.702_361_714_823_702_4),
        (2.0, 1.268_313_030_835_889_1, 0.728_647_535_610_403_1),
    ];
    for (t, supplied, stored) in expected {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * 1.5;
        let got = at(&trajectory, "energy:supplied", t);
        assert!(
            close(got, supplied),
            "t = {t}: supplied {got}, not {supplied}"
        );
        let got = at(&trajectory, "energy:stored", t);
        assert!(close(got, stored), "t = {t}: stored {got}, not {stored}");
        let got = at(&trajectory, "energy:dissipated", t);
        assert!(
            close(got, supplied - stored),
            "t = {t}: dissipated {got}, not {}",
            supplied - stored
        );
    }
    let books = trajectory.energy.expect("books recorded");
    assert!(books.residual().abs() <= 1e-12 * books.scale(), "{books:?}");
    assert!(books.error <= 1e-12 * books.scale(), "{books:?}");
    assert!(
        books.lost_at_events.abs() <= 1e-12 * books.scale(),
        "{books:?}"
    );
}

/// A DC motor (models/examples/dc_motor.ron) with K = 1e29 N·m/A: the gear makes the
/// coupling K N = 1e30, the motor rings at K N/√(L J) ≈ 3e32 rad/s and stalls, 12 V applied at
/// 0.01 s. mpmath: by 0.5 s the supply has delivered 3.5856e-61 J, 1.44e-61 J is stored (the
/// load's steady motion) and 2.1456e-61 J dissipated. In double precision the mode's decay
/// rate (-120 1/s beside ±3e32i) and its steady current (1.2e-62 A, what is left of 12 V
/// against a back-EMF that cancels it to 60 digits) are below rounding: the modal terms of
/// the current cancel to far less than their own rounding. The books cannot be exact; they
/// must be near and say how near: their error bound holds, and it flags the run.
#[test]
fn a_motor_ringing_at_3e32_rad_per_s_says_how_uncertain_its_books_are() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/examples/dc_motor.ron"),
    )
    .unwrap();
    let scenario = format!(
        r#"Scenario(name: "stall", parameters: {{"K": 1e29}},
            inputs: {{"V": Step(at: 0.01, before: 0.0, after: 12.0)}},
            duration: 0.5, sample: 0.05, record: {BOOKS})"#
    );
    let scenario = bondgraph_ron::scenario::load(
        &SourceFile::new("s.ron", &scenario),
        &SourceFile::new("models/examples/dc_motor.ron", text),
    )
    .unwrap();
    let trajectory = bondgraph_solver::scenario::run(&scenario, false).unwrap();
    let books = trajectory.energy.unwrap();
    let (supplied, stored) = (3.5856e-61, 1.44e-61);
    let got = at(&trajectory, "energy:stored", 0.5);
    assert!(
        (got - stored).abs() <= 1e-6 * stored,
        "stored {got:e}, not {stored:e}"
    );
    for (name, exact) in [
        ("energy:supplied", supplied),
        ("energy:dissipated", supplied - stored),
    ] {
        let got = at(&trajectory, name, 0.5);
        assert!(
            (got - exact).abs() <= books.error,
            "{name} {got:e}, not {exact:e} within {:e}",
            books.error
        );
    }
    assert!(books.residual().abs() <= books.error, "{books:?}");
    assert!(books.error > 1e-6 * books.scale(), "{books:?}");
}

/// A force of 1 N from 4.9e-324 s (the smallest positive double) on the mass-spring-damper
/// (m = 2, k = 200, b = 4): the first segment is 4.9e-324 s long. From then on the mass
/// moves as the step response x(t) = (1/k)(1 - e^{-t}(cos ω t + sin(ω t)/ω)), ω = √99, and
/// the force supplies x(t) joules.
#[test]
fn a_step_at_the_smallest_double_keeps_its_books_in_bounded_time() {
    let scenario = format!(
        r#"Scenario(name: "tiny", inputs: {{"F": Step(at: 4.9e-324, before: 0.0, after: 1.0)}},
            duration: 1.0, sample: 0.1, record: {BOOKS})"#
    );
    let (trajectory, _) = simulate_within(
        "models/examples/mass_spring_damper.ron",
        &scenario,
        Duration::from_secs(60),
    );
    let omega = 99f64.sqrt();
    let x = |t: f64| (1.0 - (-t).exp() * ((omega * t).cos() + (omega * t).sin() / omega)) / 200.0;
    let supplied = column(&trajectory, "energy:supplied");
    for (i, &t) in trajectory.times.iter().enumerate() {
        assert!(
            (supplied[i] - x(t)).abs() <= 1e-12 * x(1.0),
            "t = {t}: {} against {}",
            supplied[i],
            x(t)
        );
    }
}

/// m = 2, k = 200, b = 0.01 (Q = √(k m)/b = 2000), released from 0.1 m, for 1000 s: about
/// 1600 periods, sampled each second. The energy left is the analytic
/// E(t) = (k x² + m v²)/2 with x = x0 e^{-σt}(cos ωd t + (σ/ωd) sin ωd t),
/// v = -x0 (ω0²/ωd) e^{-σt} sin ωd t, σ = b/2m; what the damper took is E0 - E(t). The books
/// cost what the samples cost, not what the oscillations do (measured by the solver's
/// `energy` bench, not here).
#[test]
fn a_lightly_damped_swing_keeps_its_books_for_1000_s() {
    let scenario = format!(
        r#"Scenario(name: "swing", parameters: {{"b": 0.01}}, inputs: {{"F": Constant(0.0)}},
            initial_state: {{"spring": 0.1}}, duration: 1000.0, record: {BOOKS})"#
    );
    let (trajectory, _) = simulate_within(
        "models/examples/mass_spring_damper.ron",
        &scenario,
        Duration::from_secs(60),
    );
    let (m, k, b, x0) = (2.0f64, 200.0f64, 0.01f64, 0.1f64);
    let (sigma, w0) = (b / (2.0 * m), (k / m).sqrt());
    let wd = (w0 * w0 - sigma * sigma).sqrt();
    let energy = |t: f64| {
        let decay = (-sigma * t).exp();
        let x = x0 * decay * ((wd * t).cos() + sigma / wd * (wd * t).sin());
        let v = -x0 * w0 * w0 / wd * decay * (wd * t).sin();
        (k * x * x + m * v * v) / 2.0
    };
    let e0 = energy(0.0);
    let dissipated = column(&trajectory, "energy:dissipated");
    let stored = column(&trajectory, "energy:stored");
    assert_eq!(trajectory.times.len(), 1001);
    let books = trajectory.energy.expect("books recorded");
    assert!(books.error <= 1e-12 * books.scale(), "{books:?}");
    for (i, &t) in trajectory.times.iter().enumerate() {
        // The phase after 1000 s carries the rounding of ωd t ≈ 1e4 rad (a few 1e-13 rad).
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * e0;
        assert!(close(stored[i], energy(t)), "t = {t}: stored {}", stored[i]);
        assert!(
            close(dissipated[i], e0 - energy(t)),
            "t = {t}: dissipated {} against {}",
            dissipated[i],
            e0 - energy(t)
        );
    }
}
