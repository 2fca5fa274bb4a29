//! Extreme mass ratios (hardening, third round, item 2): masses many orders of magnitude
//! apart in one mode, against references computed independently (the reduced system, and
//! mpmath's matrix exponential at 60 digits, `reference/expm_oracle.py`).

use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;

fn run(model_path: &str, scenario_text: &str, audit_energy: bool) -> Trajectory {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(model_path);
    let model = SourceFile::new(model_path, std::fs::read_to_string(path).unwrap());
    let file = SourceFile::new("extreme.ron", scenario_text);
    let scenario = bondgraph_ron::scenario::load(&file, &model).unwrap_or_else(|e| panic!("{e}"));
    bondgraph_solver::scenario::run(&scenario, audit_energy).unwrap_or_else(|e| panic!("{e}"))
}

fn last(trajectory: &Trajectory, name: &str) -> f64 {
    let column = trajectory
        .output_names
        .iter()
        .position(|n| n == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    trajectory
        .value(trajectory.times.len() - 1, column)
        .unwrap()
}

/// `two_masses.ron` with a first mass of 1e-80 to 1e-300 kg, pushed by F = 1 N for 1 s from
/// rest. As m1 → 0 the spring passes F on at once, so the second mass obeys
/// `dP/dt = F - b P/m2`: `P(1 s) = F m2/b (1 - e^{-b/m2}) = 0.67848214979150612`, to
/// `O(1/ω)` with `ω = sqrt(k/m1)` ≥ 7e40 rad/s (mpmath's exponential agrees for m1 = 1e-20).
/// The fast oscillation keeps the energy `F²/2k = 0.01 J` it starts with (its damping is of
/// order `b m1/m2²`), so the spring's force stays within `[0, 2F]`: its phase after 1e150
/// periods is beyond double precision, its amplitude is not. Were: p = -6.26e94 at 1e-300,
/// -1.0e16 at 1e-140, 6e-5 off at 1e-100, 'no longer finite' at 1e-200.
#[test]
fn a_vanishing_first_mass_leaves_the_second_to_the_reduced_system() {
    let (m2, k, b, force): (f64, f64, f64, f64) = (3.0, 50.0, 2.5, 1.0);
    let expected = force * m2 / b * (1.0 - (-b / m2).exp());
    assert!((expected - 0.678_482_149_791_506_1).abs() < 1e-15);
    for m1 in [1e-80, 1e-100, 1e-140, 1e-200, 1e-300] {
        let text = format!(
            r#"Scenario(name: "light", parameters: {{ "m1": {m1:e} }}, inputs: {{ "F": Constant(1.0) }},
               duration: 1.0, sample: 0.25, record: ["flow:mass2", "effort:spring", "flow:mass1"])"#
        );
        let trajectory = run("models/examples/two_masses.ron", &text, false);
        let p2 = last(&trajectory, "flow:mass2") * m2;
        assert!(
            (p2 - expected).abs() <= 1e-14 * expected,
            "m1 = {m1:e}: p2 = {p2} against {expected}"
        );
        let spring = last(&trajectory, "effort:spring");
        let p1 = last(&trajectory, "flow:mass1") * m1;
        let fast_energy = p1 * p1 / (2.0 * m1) + (spring - force).powi(2) / (2.0 * k);
        assert!(
            (fast_energy - force * force / (2.0 * k)).abs() <= 1e-9 * force * force / k,
            "m1 = {m1:e}: the fast oscillation holds {fast_energy} J, not 0.01 J"
        );
    }
}

/// Two free masses of 2.5e6 and 2.5e-3 kg joined by springs of 1e3 and 3e3 N/m side by side,
/// the heavy one pushed by F = 1 N for 1 s from rest. Both springs stretch at `v1 - v2` from
/// zero, so their stretches are equal at all times (exact); the mode matrix has a double zero
/// (the total momentum and `q1 - q2` are free), which is diagonalisable. References from
/// mpmath's exponential at 60 digits: `q = 3.5194505039825319e-13 m`,
/// `v1 = 3.9999999960028874e-7`, `v2 = 3.997112583138043e-7 m/s`. The energy books close:
/// `stored(1) - stored(0) = supplied - dissipated` (nothing dissipates here). Were: the
/// stretches 0.5 % apart.
#[test]
fn parallel_springs_between_disparate_masses_stretch_alike() {
    let text = r#"Scenario(name: "push", inputs: { "F": Constant(1.0) }, duration: 1.0, sample: 0.1,
        record: ["flow:mass1", "flow:mass2", "effort:spring1", "effort:spring2",
                 "energy:supplied", "energy:stored", "energy:dissipated"])"#;
    let trajectory = run(
        "bondgraph-solver/tests/reference/parallel_springs.ron",
        text,
        true,
    );
    let (k1, k2) = (1.0e3, 3.0e3);
    let q1 = last(&trajectory, "effort:spring1") / k1;
    let q2 = last(&trajectory, "effort:spring2") / k2;
    let (q, v1_exact, v2_exact) = (
        3.519_450_503_982_532e-13,
        3.999_999_996_002_887_4e-7,
        3.997_112_583_138_043e-7,
    );
    // The stretch integrates v1 - v2, 7e-4 of v1: a rounding of the velocities shows in it
    // magnified by v1/(v1 - v2) = 1.4e3. Allowed: eight such roundings.
    let stretch_tolerance = 8.0 * f64::EPSILON * v1_exact / (v1_exact - v2_exact);
    assert!(
        (q1 - q2).abs() <= stretch_tolerance * q,
        "stretches {q1} and {q2}"
    );
    for stretch in [q1, q2] {
        assert!(
            (stretch - q).abs() <= stretch_tolerance * q,
            "stretch {stretch} against {q}"
        );
    }
    let v1 = last(&trajectory, "flow:mass1");
    let v2 = last(&trajectory, "flow:mass2");
    assert!((v1 - v1_exact).abs() <= 1e-13 * v1_exact, "v1 = {v1}");
    assert!((v2 - v2_exact).abs() <= 1e-13 * v2_exact, "v2 = {v2}");
    let supplied = last(&trajectory, "energy:supplied");
    let stored = last(&trajectory, "energy:stored");
    let dissipated = last(&trajectory, "energy:dissipated");
    let residual = stored - (supplied - dissipated);
    assert!(
        residual.abs() <= 1e-12 * supplied,
        "books: stored {stored}, supplied {supplied}, dissipated {dissipated}"
    );
}

/// The damping of the fast oscillation in `two_masses.ron` with a vanishing first mass: the
/// spring's force `k Q sin ωt` (`ω² = k/m1`) moves the second mass at `k Q/(m2 ω)`, which
/// dissipates `b k² Q²/(2 m2² ω²)` of the energy `k Q²/2`, so the amplitude decays at
/// `σ = -b m1/(2 m2²)` to first order in `m1/m2`. The mode matrix in both state orders the
/// solver may meet. Was, for m1 = 1e-200: σ = +5.3e36 /s (the states became non-finite),
/// the energy weights carrying the rounding of a logarithm of 1e200.
#[test]
fn a_vanishing_mass_oscillates_at_its_exact_damping() {
    let (m2, k, b) = (3.0f64, 50.0f64, 2.5f64);
    for m1 in [1e-80f64, 1e-100, 1e-140, 1e-200, 1e-300] {
        let expected = -b * m1 / (2.0 * m2 * m2);
        // States (p1, q, p2) and (q, p1, p2).
        let orders = [
            [0.0, -k, 0.0, 1.0 / m1, 0.0, -1.0 / m2, 0.0, k, -b / m2],
            [0.0, 1.0 / m1, -1.0 / m2, -k, 0.0, 0.0, k, 0.0, -b / m2],
        ];
        for entries in orders {
            let a = nalgebra::DMatrix::from_row_slice(3, 3, &entries);
            let eigen = bondgraph_solver::linalg::eigen(&a).expect("diagonalisable");
            let fast: Vec<_> = eigen.values.iter().filter(|v| v.im != 0.0).collect();
            assert_eq!(fast.len(), 2, "m1 = {m1:e}: {:?}", eigen.values);
            for value in fast {
                assert!(
                    (value.re - expected).abs() <= 1e-12 * expected.abs(),
                    "m1 = {m1:e}: σ = {} against {expected}",
                    value.re
                );
            }
        }
    }
}
