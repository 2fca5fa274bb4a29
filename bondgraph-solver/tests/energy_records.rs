//! Energy records in scenarios (`energy:ELEMENT`, `power:ELEMENT`, the books) against
//! closed forms: a mass-spring released from rest, a damped one pushed by a constant force,
//! a pendulum at large amplitude (nonlinear storage), and the same on a linear graph.

use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;

fn model_file(relative: &str) -> std::sync::Arc<SourceFile> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    SourceFile::new(relative, text)
}

fn simulate(model: &str, scenario_text: &str) -> Trajectory {
    let scenario =
        bondgraph_ron::scenario::load(&SourceFile::new("s.ron", scenario_text), &model_file(model))
            .unwrap_or_else(|e| panic!("{e}"));
    bondgraph_solver::scenario::run(&scenario, false).unwrap_or_else(|e| panic!("{e}"))
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

const MSD: &str = "models/examples/mass_spring_damper.ron";

/// m = 2 kg, k = 200 N/m, no damping, released from rest at q0 = 0.01 m: ω = 10 rad/s and
/// the stored energy k q0²/2 = 0.01 J swaps between the spring (E cos² ωt) and the mass
/// (E sin² ωt); the power into the spring is dE/dt = -E ω sin 2ωt.
#[test]
fn a_released_mass_spring_exchanges_a_constant_energy() {
    let trajectory = simulate(
        MSD,
        r#"Scenario(name: "release", parameters: {"b": 0.0}, inputs: {"F": Constant(0.0)},
            initial_state: {"spring": 0.01}, duration: 1.0, sample: 0.01,
            record: ["energy:spring", "energy:mass", "energy:stored", "power:spring",
                     "energy:supplied", "energy:dissipated"])"#,
    );
    assert_eq!(
        trajectory.output_names,
        [
            "energy:spring",
            "energy:mass",
            "energy:stored",
            "power:spring",
            "energy:supplied",
            "energy:dissipated"
        ]
    );
    let (e0, omega) = (0.01, 10.0);
    let spring = column(&trajectory, "energy:spring");
    let mass = column(&trajectory, "energy:mass");
    let stored = column(&trajectory, "energy:stored");
    let power = column(&trajectory, "power:spring");
    let supplied = column(&trajectory, "energy:supplied");
    let dissipated = column(&trajectory, "energy:dissipated");
    assert_eq!(trajectory.times.len(), 101);
    for (i, t) in trajectory.times.iter().enumerate() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * e0 * omega;
        assert!(close(spring[i], e0 * (omega * t).cos().powi(2)), "t = {t}");
        assert!(close(mass[i], e0 * (omega * t).sin().powi(2)), "t = {t}");
        assert!(close(stored[i], e0), "t = {t}: {}", stored[i]);
        assert!(
            close(power[i], -e0 * omega * (2.0 * omega * t).sin()),
            "t = {t}"
        );
        assert!(
            supplied[i].abs() <= 1e-15 && dissipated[i].abs() <= 1e-15,
            "t = {t}"
        );
    }
}

/// The damped mass-spring (m = 2, k = 200, b = 4) pushed from rest by F = 10 N: the force
/// supplies F·x(t), x(t) = F/k (1 - e^{-ζωt}(cos ω_d t + ζ/√(1-ζ²) sin ω_d t)) with ω = 10,
/// ζ = b/(2√(km)) = 0.1; what is not stored is dissipated; the damper takes in b v².
#[test]
fn a_pushed_damped_mass_dissipates_what_it_does_not_store() {
    let trajectory = simulate(
        MSD,
        r#"Scenario(name: "push", inputs: {"F": Constant(10.0)}, duration: 3.0, sample: 0.01,
            record: ["energy:supplied", "energy:stored", "energy:dissipated", "flow:mass",
                     "power:damper", "power:force"])"#,
    );
    let (f, k, b, omega, zeta) = (10.0, 200.0, 4.0, 10.0, 0.1_f64);
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let x = |t: f64| {
        f / k
            * (1.0
                - (-zeta * omega * t).exp()
                    * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin()))
    };
    let supplied = column(&trajectory, "energy:supplied");
    let stored = column(&trajectory, "energy:stored");
    let dissipated = column(&trajectory, "energy:dissipated");
    let v = column(&trajectory, "flow:mass");
    let damper = column(&trajectory, "power:damper");
    let force = column(&trajectory, "power:force");
    let scale = f * f / k; // 0.5 J
    for (i, t) in trajectory.times.iter().enumerate() {
        assert!(
            (supplied[i] - f * x(*t)).abs() <= 1e-9 * scale,
            "t = {t}: supplied {} against F x = {}",
            supplied[i],
            f * x(*t)
        );
        assert!(
            (dissipated[i] - (supplied[i] - stored[i])).abs() <= 1e-9 * scale,
            "t = {t}"
        );
        assert!(
            (damper[i] - b * v[i] * v[i]).abs() <= 1e-12 * scale,
            "t = {t}"
        );
        assert!((force[i] + f * v[i]).abs() <= 1e-12 * scale, "t = {t}");
    }
    // Dissipation only grows; at rest at x = F/k the spring would hold F²/2k = 0.25 J of the
    // F²/k = 0.5 J supplied, and by 3 s (three decay times 1/ζω = 1 s) the books are near it.
    assert!(dissipated.windows(2).all(|w| w[1] >= w[0] - 1e-15));
    let last = trajectory.times.len() - 1;
    assert!((supplied[last] - f * x(3.0)).abs() <= 1e-9 * scale);
    assert!(dissipated[last] > 0.2 && dissipated[last] < 0.3);
}

/// The pendulum's gravity is a nonlinear compliance (torque m g l sin q): its energy is
/// ∫ e dq = m g l (1 - cos q), with q = 2 + ∫ flow; with the bob's m l² ω²/2 it is constant.
#[test]
fn a_pendulum_keeps_its_energy_in_its_nonlinear_storage() {
    let trajectory = simulate(
        "models/examples/nonlinear/pendulum.ron",
        r#"Scenario(name: "release", inputs: {}, initial_state: {"gravity": 2.0},
            duration: 3.0, sample: 0.01,
            record: ["energy:gravity", "energy:bob", "energy:stored", "integral:flow:gravity",
                     "flow:bob"])"#,
    );
    let mgl = 9.81;
    let total = mgl * (1.0 - 2.0_f64.cos());
    let gravity = column(&trajectory, "energy:gravity");
    let bob = column(&trajectory, "energy:bob");
    let stored = column(&trajectory, "energy:stored");
    let angle = column(&trajectory, "integral:flow:gravity");
    let omega = column(&trajectory, "flow:bob");
    for (i, t) in trajectory.times.iter().enumerate() {
        // The angle from the integral output is good to about 1e-9 (a quadrature riding
        // along the integrator, not controlling its steps), the energy from the state itself.
        let q = 2.0 + angle[i];
        assert!(
            (gravity[i] - mgl * (1.0 - q.cos())).abs() <= 1e-8 * total,
            "t = {t}: {} against {} (q = {q})",
            gravity[i],
            mgl * (1.0 - q.cos())
        );
        assert!(
            (bob[i] - omega[i] * omega[i] / 2.0).abs() <= 1e-12 * total,
            "t = {t}"
        );
        assert!(
            (stored[i] - (gravity[i] + bob[i])).abs() <= 1e-12 * total,
            "t = {t}"
        );
        assert!(
            (stored[i] - total).abs() <= 1e-7 * total,
            "t = {t}: {} against {total}",
            stored[i]
        );
    }
}

/// On the linear graph the branch names reach the same elements: the mass's energy is
/// m v²/2 of its across variable, the damper's power b v² (a conductance: f = b v).
#[test]
fn linear_graph_branches_have_energies_and_powers() {
    let trajectory = simulate(
        "models/examples/mass_spring_damper.lg.ron",
        r#"Scenario(name: "push", inputs: {"F": Constant(10.0)}, duration: 1.0, sample: 0.01,
            record: ["energy:mass", "across:mass", "power:damper", "energy:spring",
                     "through:spring", "energy:supplied", "energy:stored", "energy:dissipated"])"#,
    );
    let mass = column(&trajectory, "energy:mass");
    let v = column(&trajectory, "across:mass");
    let damper = column(&trajectory, "power:damper");
    let spring = column(&trajectory, "energy:spring");
    let force = column(&trajectory, "through:spring");
    let (supplied, stored, dissipated) = (
        column(&trajectory, "energy:supplied"),
        column(&trajectory, "energy:stored"),
        column(&trajectory, "energy:dissipated"),
    );
    for i in 0..trajectory.times.len() {
        assert!((mass[i] - 2.0 * v[i] * v[i] / 2.0).abs() <= 1e-12);
        assert!((damper[i] - 4.0 * v[i] * v[i]).abs() <= 1e-12);
        assert!((spring[i] - force[i] * force[i] / (2.0 * 200.0)).abs() <= 1e-12);
        assert!((dissipated[i] - (supplied[i] - stored[i])).abs() <= 1e-9 * 0.5);
    }
}

fn problem(model: &str, record: &str) -> String {
    let text = format!(
        r#"Scenario(name: "s", inputs: {{"F": Constant(1.0)}}, duration: 1.0, record: ["{record}"])"#
    );
    let error = bondgraph_ron::scenario::load(&SourceFile::new("s.ron", text), &model_file(model))
        .unwrap_err();
    error.first().to_string()
}

#[test]
fn energy_records_of_the_wrong_element_are_located_errors() {
    assert_eq!(
        problem(MSD, "energy:damper"),
        "s.ron:1:76: error: record 'energy:damper': 'damper' is a resistor and stores no energy\n  \
         note: energy: is for storage elements (I, C, TensionOnly); power:damper is the power it takes in"
    );
    assert_eq!(
        problem(MSD, "power:v_mass"),
        "s.ron:1:76: error: record 'power:v_mass': 'v_mass' is a 1-junction with 4 bonds; power: is for one-port elements\n  \
         note: junctions, transformers and gyrators pass power on without taking any"
    );
    assert_eq!(
        problem(MSD, "energy:springs"),
        "s.ron:1:76: error: record 'energy:springs': the model has no element 'springs'\n  \
         note: or a book: energy:supplied, energy:stored, energy:dissipated"
    );
}
