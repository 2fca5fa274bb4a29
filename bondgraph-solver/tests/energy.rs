//! Energy balance on every model: energy in = stored + dissipated (+ lost when bodies stick).

use bondgraph_core::modes::Mode;
use bondgraph_solver::{Run, Signal, Simulator};

use crate::support::{Constant, Ramp, load};

fn balance(
    file: &str,
    inputs: &[&dyn Signal],
    initial: Vec<f64>,
    duration: f64,
    mode: Option<&str>,
) {
    let model = load(file);
    let mut simulator = Simulator::new(&model, Vec::new());
    let initial_mode = match mode {
        Some(spec) => Mode::parse(&model, spec).unwrap(),
        None => Mode::initial(&model),
    };
    let run = Run {
        inputs,
        initial_mode,
        initial_state: initial,
        duration,
        sample: None,
        audit_energy: true,
    };
    let trajectory = simulator
        .run(&run)
        .unwrap_or_else(|e| panic!("{file}: {e}"));
    let energy = trajectory.energy.unwrap();
    assert!(energy.scale() > 0.0, "{file}: nothing happened");
    assert!(
        energy.residual().abs() <= 1e-9 * energy.scale(),
        "{file}: residual {:e} of {:?}",
        energy.residual(),
        energy
    );
    // The books' own bound on their rounding: far below the tolerance on these models.
    assert!(
        energy.error <= 1e-11 * energy.scale(),
        "{file}: error bound {:e} of {:?}",
        energy.error,
        energy
    );
}

/// A ramp from 0 to `top` over the first second, then constant.
fn ramp(top: f64) -> Ramp {
    Ramp {
        initial: 0.0,
        slope: top,
        ceiling: top,
    }
}

#[test]
fn textbook_models_balance_their_energy() {
    let one = ramp(1.0);
    for (file, states) in [
        ("models/examples/mass_spring_damper.ron", 2),
        ("models/examples/two_masses.ron", 3),
        ("models/examples/dc_motor.ron", 2),
        ("models/examples/rlc.ron", 2),
        ("models/examples/rigid_masses.ron", 3),
        ("models/examples/series_dampers.ron", 1),
    ] {
        // Start with some energy stored everywhere, drive with a ramp.
        let initial: Vec<f64> = (0..states).map(|i| 0.01 * (i + 1) as f64).collect();
        balance(file, &[&one], initial, 2.0, None);
    }
    // The tank: a small inflow ramp, a little water in the tank.
    let inflow = ramp(1e-3);
    balance(
        "models/examples/tank_pipe.ron",
        &[&inflow],
        vec![0.05, 0.0],
        20.0,
        None,
    );
}

#[test]
fn stick_slip_balances_its_energy_with_losses_at_sticking() {
    let belt = Constant(0.1);
    balance(
        "models/examples/belt_friction.ron",
        &[&belt],
        vec![0.1, 0.0],
        3.5,
        None,
    );
}
