//! The teaching models of `models/teaching/` against their closed forms, so the README's
//! walk-through stays true: each scenario's end (or a time the README names) against the
//! value derived by hand.

use bondgraph_core::scenario;
use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;

use crate::support::root;

fn run(model: &str, scenario_file: &str) -> Trajectory {
    let read = |relative: String| {
        let text = std::fs::read_to_string(root().join(&relative))
            .unwrap_or_else(|e| panic!("{relative}: {e}"));
        SourceFile::new(relative, text)
    };
    let model = read(format!("models/teaching/{model}.ron"));
    let scenario = read(format!("models/teaching/scenarios/{scenario_file}.ron"));
    let loaded = scenario::load(&scenario, &model).unwrap_or_else(|e| panic!("{e}"));
    bondgraph_solver::scenario::run(&loaded, false).unwrap_or_else(|e| panic!("{e}"))
}

/// Output `name` at time `t` (a sample time).
fn at(trajectory: &Trajectory, name: &str, t: f64) -> f64 {
    let k = trajectory
        .output_names
        .iter()
        .position(|n| n == name)
        .unwrap();
    let i = trajectory
        .times
        .iter()
        .position(|s| (s - t).abs() < 1e-9)
        .unwrap_or_else(|| panic!("no sample at {t}"));
    trajectory.value(i, k).unwrap()
}

fn close(value: f64, expected: f64, relative: f64) {
    assert!(
        (value - expected).abs() <= relative * expected.abs(),
        "{value} against {expected}"
    );
}

#[test]
fn rc_charges_with_its_time_constant_and_loses_half() {
    let t = run("rc", "rc_step");
    // 10 V from 0.5 s, tau = 1 s.
    close(
        at(&t, "effort:capacitor", 1.5),
        10.0 * (1.0 - (-1.0_f64).exp()),
        1e-12,
    );
    let left = (-5.5_f64).exp();
    // Supplied C V² (1 - e^{-t/τ}), stored C V² (1 - e^{-t/τ})² / 2.
    close(at(&t, "energy:supplied", 6.0), 0.1 * (1.0 - left), 1e-9);
    close(
        at(&t, "energy:stored", 6.0),
        0.05 * (1.0 - left).powi(2),
        1e-12,
    );
}

#[test]
fn the_mass_spring_damper_dissipates_its_initial_energy() {
    let t = run("mass_spring_damper", "msd_release");
    // ζ = 0.2, ω_n = 10: q = q0 e^{-ζω t} (cos ω_d t + ζ/√(1-ζ²) sin ω_d t).
    let (zeta, wn) = (0.2_f64, 10.0);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let q = |t: f64| {
        0.1 * (-zeta * wn * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin())
    };
    for time in [0.1, 0.5, 1.0] {
        close(at(&t, "effort:spring", time), 100.0 * q(time), 1e-10);
    }
    let stored = at(&t, "energy:stored", 3.0);
    close(at(&t, "energy:dissipated", 3.0), 0.5 - stored, 1e-9);
}

#[test]
fn the_dc_motor_reaches_the_current_and_speed_friction_needs() {
    let t = run("dc_motor", "dc_motor_step");
    // Steady: i = V / (R_a + K² N² / b), load speed N K i / b; the supply delivers V i.
    let i = 12.0 / (1.2 + 0.05_f64.powi(2) * 100.0 / 0.001);
    close(at(&t, "flow:winding_inductance", 1.0), i, 1e-6);
    close(
        at(&t, "flow:load_inertia", 1.0),
        10.0 * 0.05 * i / 0.001,
        1e-6,
    );
    close(at(&t, "power:supply", 1.0), -12.0 * i, 1e-6);
}

#[test]
fn the_tank_and_the_body_settle_with_their_time_constants() {
    let tank = run("tank", "tank_fill");
    close(
        at(&tank, "effort:tank", 60.0),
        98.1 * (1.0 - (-6.0_f64).exp()),
        1e-10,
    );
    let body = run("thermal", "thermal_cooling");
    // 353 K in a 293 K room, tau = 50 s; 200 W from 100 s: towards 313 K.
    let t100 = 293.0 + 60.0 * (-2.0_f64).exp();
    close(at(&body, "effort:body", 100.0), t100, 1e-12);
    close(
        at(&body, "effort:body", 400.0),
        313.0 - (313.0 - t100) * (-6.0_f64).exp(),
        1e-12,
    );
}

#[test]
fn the_quarter_car_ends_a_bump_higher() {
    let t = run("quarter_car", "quarter_car_bump");
    // The road rose 1 m/s for 0.05 s: 5 cm; without gravity every spring relaxes again.
    let wheel = at(&t, "integral:flow:wheel", 2.0);
    let body = at(&t, "integral:flow:body", 2.0);
    assert!(
        (wheel - 0.05).abs() < 2e-3 && (body - 0.05).abs() < 2e-3,
        "{wheel} {body}"
    );
}
