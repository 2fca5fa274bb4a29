//! Steady rows settle on the model's own time scales, within budgets of work: the two-tank
//! rig (time constants of tens of seconds) calibrated on a steady sweep, a row that cannot
//! settle within its budget, and the count of failed trials in the report.

use serde_json::Value;

use crate::cli::{fail, succeed};

const MODEL: &str = "models/examples/two_tank/two_tank.ron";
const EXPERIMENT: &str = "tests/fixtures/timescales/two_tank_h1.ron";
/// `models/examples/two_tank/data/steady_exact.csv` with only the level of tank 1 observed.
const EXACT: &str = "tests/fixtures/timescales/two_tank_h1_exact.csv";

fn calibrate(extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> = [
        "calibrate",
        "--model",
        MODEL,
        "--experiment",
        EXPERIMENT,
        "--data",
        EXACT,
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn refs(args: &[String]) -> Vec<&str> {
    args.iter().map(String::as_str).collect()
}

/// The truth of `models/examples/two_tank/data/generate.py` (scipy, Brent's method on the
/// steady balance): R_12 = 8e6 Pa s/m^3, c_d = 2.2e-6 m^3/(s Pa^(1/2)). Each row takes
/// minutes of simulated time to settle (36 time constants of about 30 s); a fit that gave
/// each row 2 s found none settled.
#[test]
fn a_two_tank_steady_sweep_calibrates_back_to_the_generators_truth() {
    let args = calibrate(&["--format", "json"]);
    let fit: Value = serde_json::from_str(&succeed(&refs(&args))).expect("JSON");
    for (name, truth) in [("R_12", 8.0e6), ("c_d", 2.2e-6)] {
        let got = fit["params"][name]["value"].as_f64().expect(name);
        assert!(
            ((got - truth) / truth).abs() < 1e-5,
            "{name}: calibrated {got}, truth {truth}"
        );
    }
    assert!(fit["failed_trials"].is_array(), "{fit}");
}

/// With a budget of one stretch a row of the two-tank rig cannot settle (its first window is
/// its fastest time scale from empty, 4.4 s, against a slow time constant of tens of seconds,
/// and the Newton polish needs two windows that agree): the message names the row, the
/// model's only mode, the time reached and the state that still moves.
#[test]
fn a_row_that_cannot_settle_within_its_budget_says_where_and_what_still_moves() {
    let args = calibrate(&["--max-segments", "1"]);
    let err = fail(&refs(&args));
    assert!(
        err.contains(&format!(
            "{EXACT}:2: Q_p_mL_s = 20: no steady state by t = "
        )),
        "{err}"
    );
    assert!(
        err.contains(
            " s in the model's only mode: it had not settled after its budget of 1 segments; "
        ),
        "{err}"
    );
    assert!(err.contains("still moves (at "), "{err}");
    assert!(!err.contains("in mode :"), "{err}");
}
