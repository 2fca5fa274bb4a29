//! Linear networks against an independent high-precision reference.
//!
//! `reference/oracle.json` holds random mechanical networks (masses from 1e-12 to 1e6 kg,
//! springs from 1e-2 to 1e8 N/m, dampers from 1e-3 to 1e4 N·s/m, constant and ramped forces,
//! random initial states and durations, from the fixed seeds listed in the script) and the
//! extreme cases of the third hardening round: `two_masses.ron` with a first mass of 1e-80 to
//! 1e-300 kg, two free masses of 2.5e6 and 2.5e-3 kg joined by parallel springs, and the
//! flagship's 5e-15 kg tip beside a 1250 N·s/m damper. For each, the final velocities, spring
//! forces and stored energy, from `reference/expm_oracle.py`: the script writes the equations
//! from Newton's laws and takes the matrix exponential in mpmath at 60 or more digits
//! (checked at 40 more).
//!
//! Why a committed fixture rather than multiprecision arithmetic in Rust: the reference is
//! then independent of this crate twice over (its own equations, and a matrix exponential
//! from a library with a long record), and the test needs nothing beyond `serde_json`. A
//! Rust multiprecision exponential would have to be written here (the crates that have one
//! bring GMP), and would share the author with the code it checks. Regenerate with
//! `python3 bondgraph-solver/tests/reference/expm_oracle.py > bondgraph-solver/tests/reference/oracle.json`.
//!
//! Tolerance. The fixture gives each quantity `y` its sensitivity to the data,
//! `S = Σ_d |d ∂y/∂d|` over every mass, stiffness, damping, force, slope, initial state and
//! the duration. A solver that is backward stable componentwise (the exact answer to data
//! within a few rounding units `ε` of the given) is within `ε S` of the reference, up to the
//! number of roundings each datum meets; [`ROUNDINGS`] allows for that. Where no
//! double-precision method can answer, the allowance says so by itself: after one second, the
//! phase of a 1e-300 kg mass's 7e151 rad/s oscillation has `S` near 1e150, so its velocity
//! and the spring's force are checked only for being finite, while the second mass's
//! velocity (`S` of order 1) is checked to 1e-13. The [`ENTRYWISE`] cases are checked against
//! their sensitivity to the solver's own numbers instead, with why.

use bondgraph_core::source::SourceFile;
use serde_json::Value;

/// Rounding units allowed per unit of sensitivity: the modes here have up to 12 states,
/// and each datum passes through the eigendecomposition, the change of coordinates and back,
/// and the output rows; a few roundings each, summed over up to a dozen terms. The largest
/// ratio `|error| / (ε (S + |y|))` over the fixture is printed by the test.
const ROUNDINGS: f64 = 64.0;

/// Cases checked against the sensitivity to the solver's own numbers, `S_A` (the fixture's
/// `entry_sensitivity`: each entry of the state matrix and input columns, each initial state,
/// output coefficient and the duration, perturbed on its own), rather than to the data. A
/// method that factorizes the matrix in floating point is backward stable in that sense at
/// best: it rounds entries apart that the data tie together (parallel springs' equal rows, a
/// damper's rows of opposite sign), so the relations the data keep exactly hold only to
/// rounding. Each is named with why the data's `S` is out of reach.
const ENTRYWISE: [(&str, &str); 3] = [
    (
        "random_12",
        "springs of 1.6e6 and 2.9e7 N/m side by side and two dampers between masses of \
         6.9e-8 and 3.3e-3 kg: a double zero beside decays of 5.7e8 and 7.8e9 /s; the \
         velocities are 1.6e3 ε·S off (S_A/S = 1e4)",
    ),
    (
        "random_18",
        "three springs side by side between 1.6e-10 and 1.2e-4 kg, one damped to the \
         ground: the motion has decayed to velocities of 1e-120 m/s (S = 1e-72) beside \
         conserved stretches of 1e-2 m, whose rounding leaves 1e-30 m/s (S_A/S = 1e74)",
    ),
    (
        "random_22",
        "springs of 1.0e5 and 4.9 N/m side by side and a 1478 N·s/m damper between 2.3e-8 \
         and 0.11 kg: a zero beside a decay of 6.3e10 /s; the weak spring's force is 7.8e4 \
         ε·S off (S_A/S = 1e6)",
    ),
];

struct Case {
    name: String,
    model: String,
    scenario: String,
    records: Vec<String>,
    expected: Vec<f64>,
    sensitivity: Vec<f64>,
    /// `S_A`, given for the [`ENTRYWISE`] cases.
    entry_sensitivity: Option<Vec<f64>>,
}

fn number(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The network as a bond-graph model file and a scenario file.
fn case(net: &Value) -> Case {
    let name = net["name"].as_str().unwrap().to_string();
    let masses: Vec<f64> = net["masses"]
        .as_array()
        .unwrap()
        .iter()
        .map(number)
        .collect();
    let elements = net["elements"].as_array().unwrap();
    let forces = net["forces"].as_array().unwrap();
    let mut parameters = Vec::new();
    let mut items = Vec::new();
    let mut bonds = Vec::new();
    let mut records = Vec::new();
    for (i, m) in masses.iter().enumerate() {
        parameters.push(format!("\"m{i}\": (value: {m:e})"));
        items.push(format!(
            "\"v{i}\": One, \"mass{i}\": I(inertance: \"m{i}\")"
        ));
        bonds.push(format!("(\"v{i}\", \"mass{i}\")"));
        records.push(format!("flow:mass{i}"));
    }
    for (j, e) in elements.iter().enumerate() {
        let value = number(&e["value"]);
        parameters.push(format!("\"e{j}\": (value: {value:e})"));
        let element = match e["kind"].as_str().unwrap() {
            "spring" => {
                records.push(format!("effort:el{j}"));
                format!("\"el{j}\": C(stiffness: \"e{j}\")")
            }
            _ => format!("\"el{j}\": R(resistance: \"e{j}\")"),
        };
        items.push(element);
        let from = e["from"].as_u64().unwrap();
        match e["to"].as_u64() {
            // Between two masses: a 0-junction carries the one force to both and the
            // difference of their velocities into the element.
            Some(to) => {
                items.push(format!("\"j{j}\": Zero"));
                bonds.push(format!(
                    "(\"v{from}\", \"j{j}\"), (\"j{j}\", \"v{to}\"), (\"j{j}\", \"el{j}\")"
                ));
            }
            None => bonds.push(format!("(\"v{from}\", \"el{j}\")")),
        }
    }
    let mut inputs = Vec::new();
    let mut signals = Vec::new();
    for (k, f) in forces.iter().enumerate() {
        let mass = f["mass"].as_u64().unwrap();
        inputs.push(format!("\"F{k}\": ()"));
        items.push(format!("\"push{k}\": Se(effort: \"F{k}\")"));
        bonds.push(format!("(\"push{k}\", \"v{mass}\")"));
        let (initial, slope) = (number(&f["initial"]), number(&f["slope"]));
        signals.push(if slope == 0.0 {
            format!("\"F{k}\": Constant({initial:e})")
        } else {
            format!("\"F{k}\": Ramp(slope: {slope:e}, initial: {initial:e})")
        });
    }
    let mut initial = Vec::new();
    for (i, p) in net["momenta"].as_array().unwrap().iter().enumerate() {
        if number(p) != 0.0 {
            initial.push(format!("\"mass{i}\": {:e}", number(p)));
        }
    }
    for (j, q) in net["stretches"].as_array().unwrap().iter().enumerate() {
        if number(q) != 0.0 {
            initial.push(format!("\"el{j}\": {:e}", number(q)));
        }
    }
    records.push("energy:stored".into());
    let duration = number(&net["duration"]);
    let model = format!(
        "Model(name: \"{name}\", parameters: {{ {} }}, inputs: {{ {} }}, elements: {{ {} }}, bonds: [ {} ])",
        parameters.join(", "),
        inputs.join(", "),
        items.join(", "),
        bonds.join(", ")
    );
    let quoted: Vec<String> = records.iter().map(|r| format!("\"{r}\"")).collect();
    let scenario = format!(
        "Scenario(name: \"oracle\", inputs: {{ {} }}, initial_state: {{ {} }}, duration: {duration:e}, record: [{}], sample: {duration:e})",
        signals.join(", "),
        initial.join(", "),
        quoted.join(", ")
    );
    Case {
        name,
        model,
        scenario,
        records,
        expected: net["expected"]
            .as_array()
            .unwrap()
            .iter()
            .map(number)
            .collect(),
        sensitivity: net["sensitivity"]
            .as_array()
            .unwrap()
            .iter()
            .map(number)
            .collect(),
        entry_sensitivity: net
            .get("entry_sensitivity")
            .and_then(Value::as_array)
            .map(|a| a.iter().map(number).collect()),
    }
}

fn fixture() -> Vec<Case> {
    let text = include_str!("reference/oracle.json");
    let json: Value = serde_json::from_str(text).expect("oracle.json is JSON");
    json["cases"].as_array().unwrap().iter().map(case).collect()
}

/// The final row of each recorded quantity, simulated.
fn simulate(case: &Case) -> Result<Vec<f64>, String> {
    let model = SourceFile::new(format!("{}.ron", case.name), case.model.clone());
    let file = SourceFile::new("oracle_scenario.ron", case.scenario.clone());
    let scenario = bondgraph_ron::scenario::load(&file, &model).map_err(|e| format!("{e}"))?;
    let trajectory =
        bondgraph_solver::scenario::run(&scenario, false).map_err(|e| format!("{e}"))?;
    let last = trajectory.times.len() - 1;
    Ok((0..case.records.len())
        .map(|k| trajectory.value(last, k).unwrap())
        .collect())
}

#[test]
fn linear_networks_match_a_high_precision_exponential() {
    let mut failures = Vec::new();
    let mut worst = (0.0f64, String::new());
    for case in fixture() {
        let got = match simulate(&case) {
            Ok(got) => got,
            Err(e) => {
                failures.push(format!("{}: {e}", case.name));
                continue;
            }
        };
        let entrywise = ENTRYWISE.iter().any(|(name, _)| *name == case.name);
        for (k, record) in case.records.iter().enumerate() {
            let expected = case.expected[k];
            let sensitivity = if entrywise {
                let Some(entries) = &case.entry_sensitivity else {
                    failures.push(format!(
                        "{}: the fixture has no entry_sensitivity",
                        case.name
                    ));
                    break;
                };
                entries[k]
            } else {
                case.sensitivity[k]
            };
            let scale = f64::EPSILON * (sensitivity + expected.abs());
            let error = (got[k] - expected).abs();
            let ratio = error / scale;
            if ratio.is_nan() || ratio > ROUNDINGS {
                failures.push(format!(
                    "{} {record}: {} against {expected} (off by {error:.3e}, {ratio:.3e} ε·S with S = {sensitivity:.3e})",
                    case.name, got[k]
                ));
            } else if ratio > worst.0 {
                worst = (ratio, format!("{} {record}", case.name));
            }
        }
    }
    println!("largest error: {:.1} ε·S ({})", worst.0, worst.1);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
