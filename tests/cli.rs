//! The `bondgraph` program on the bundled examples: exit codes, summaries, and the shape
//! and values of its JSON, text and LaTeX output.

use std::process::{Command, Output};

use serde_json::Value;

use crate::support::{ron_files, root};

const EXAMPLES: &str = "models/examples";

/// The number of states of every example, by file stem.
const STATES: &[(&str, usize)] = &[
    ("belt_friction", 1),
    ("dc_motor", 2),
    ("mass_spring_damper", 2),
    ("rigid_masses", 2),
    ("rlc", 2),
    ("series_dampers", 1),
    ("tank_pipe", 2),
    ("two_masses", 3),
];

/// Runs `bondgraph ARGS` in the repository root.
pub(crate) fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("the program runs")
}

fn stdout(output: &Output) -> String {
    String::from_utf8(output.stdout.clone()).expect("UTF-8 output")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// Runs `bondgraph ARGS`, expecting success.
pub(crate) fn succeed(args: &[&str]) -> String {
    let output = run(args);
    assert!(
        output.status.success(),
        "bondgraph {}: {:?}\n{}",
        args.join(" "),
        output.status,
        stderr(&output)
    );
    stdout(&output)
}

/// Runs `bondgraph ARGS`, expecting a clean failure (exit 1, not a panic); returns stderr.
pub(crate) fn fail(args: &[&str]) -> String {
    let output = run(args);
    let err = stderr(&output);
    assert_eq!(
        output.status.code(),
        Some(1),
        "bondgraph {}: exit code\n{err}",
        args.join(" ")
    );
    assert!(!err.contains("panicked"), "{err}");
    assert!(output.stdout.is_empty());
    err
}

/// Runs `equations ARGS --format json` and parses the result.
pub(crate) fn json(args: &[&str]) -> Value {
    let mut all = vec!["equations"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--format", "json"]);
    let text = succeed(&all);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}:\n{text}"))
}

fn stem(path: &str) -> &str {
    path.rsplit('/')
        .next()
        .and_then(|f| f.strip_suffix(".ron"))
        .expect("a .ron path")
}

fn states_of(path: &str) -> usize {
    let name = stem(path);
    STATES
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("{path}: add its state count to STATES"))
        .1
}

/// A JSON array of arrays as a matrix of numbers.
pub(crate) fn numbers(value: &Value) -> Vec<Vec<f64>> {
    value
        .as_array()
        .expect("an array of rows")
        .iter()
        .map(|row| {
            row.as_array()
                .expect("a row")
                .iter()
                .map(|x| x.as_f64().expect("a number"))
                .collect()
        })
        .collect()
}

/// Asserts `value` is `rows` arrays of `columns` entries each, strings or numbers.
fn assert_shape(what: &str, value: &Value, rows: usize, columns: usize, numeric: bool) {
    let array = value
        .as_array()
        .unwrap_or_else(|| panic!("{what}: not an array"));
    assert_eq!(array.len(), rows, "{what}: rows");
    for row in array {
        let row = row
            .as_array()
            .unwrap_or_else(|| panic!("{what}: a row is not an array"));
        assert_eq!(row.len(), columns, "{what}: columns");
        for entry in row {
            if numeric {
                let x = entry
                    .as_f64()
                    .unwrap_or_else(|| panic!("{what}: {entry} is not a number"));
                assert!(x.is_finite(), "{what}: {x}");
            } else {
                assert!(entry.is_string(), "{what}: {entry} is not a string");
            }
        }
    }
}

#[test]
fn every_example_has_a_state_count() {
    let examples: Vec<String> = ron_files(EXAMPLES)
        .iter()
        .map(|p| stem(p).to_string())
        .collect();
    let listed: Vec<&str> = STATES.iter().map(|(n, _)| *n).collect();
    assert_eq!(examples, listed);
}

#[test]
fn check_summarises_every_example_in_one_line() {
    for path in ron_files(EXAMPLES) {
        let out = succeed(&["check", &path]);
        let n = states_of(&path);
        let states = if n == 1 {
            "1 state".to_string()
        } else {
            format!("{n} states")
        };
        assert_eq!(out.lines().count(), 1, "{path}: {out}");
        let line = out.trim_end();
        assert!(
            line.starts_with(&format!("{path}: ok: model '{}' with ", stem(&path))),
            "{line}"
        );
        // Switching models also count their reachable modes (belt_friction: stuck, slip+,
        // slip-).
        let modes = if stem(&path) == "belt_friction" {
            ", 3 reachable modes"
        } else {
            ""
        };
        assert!(line.ends_with(&format!(" and {states}{modes}")), "{line}");
    }
    // One example in full.
    assert_eq!(
        succeed(&["check", "models/examples/mass_spring_damper.ron"]),
        "models/examples/mass_spring_damper.ron: ok: model 'mass_spring_damper' with \
         5 elements, 4 bonds, 3 parameters, 1 input and 2 states\n"
    );
}

#[test]
fn json_of_every_example_has_consistent_shapes() {
    for path in ron_files(EXAMPLES) {
        let json = json(&[&path]);
        let n = states_of(&path);
        let states = json["states"].as_array().expect("states");
        assert_eq!(states.len(), n, "{path}: states");
        for state in states {
            let name = state["name"].as_str().expect("state name");
            let element = state["element"].as_str().expect("state element");
            let quantity = state["quantity"].as_str().expect("state quantity");
            assert!(matches!(quantity, "p" | "q"), "{path}: {quantity}");
            assert_eq!(name, format!("{quantity}_{element}"), "{path}");
        }
        let inputs = json["inputs"].as_array().expect("inputs");
        assert!(inputs.iter().all(Value::is_string), "{path}: {inputs:?}");
        let m = inputs.len();
        for (key, numeric) in [("A", false), ("A_value", true)] {
            assert_shape(&format!("{path}: {key}"), &json[key], n, n, numeric);
        }
        for (key, numeric) in [("B", false), ("B_value", true)] {
            assert_shape(&format!("{path}: {key}"), &json[key], n, m, numeric);
        }
        let c = json["c"].as_array().expect("c");
        assert_eq!(c.len(), n, "{path}: c");
        assert!(c.iter().all(Value::is_string), "{path}: c");
        let c_value = json["c_value"].as_array().expect("c_value");
        assert_eq!(c_value.len(), n, "{path}: c_value");
        assert!(
            c_value
                .iter()
                .all(|x| x.as_f64().is_some_and(f64::is_finite)),
            "{path}: c_value"
        );
    }
}

#[test]
fn json_values_of_the_mass_spring_damper() {
    // m = 2, k = 200, b = 4: dp/dt = -(b/m) p - k q + F, dq/dt = p/m.
    let json = json(&["models/examples/mass_spring_damper.ron"]);
    assert_eq!(
        numbers(&json["A_value"]),
        [[-2.0, -200.0], [0.5, 0.0]],
        "{}",
        json["A_value"]
    );
    assert_eq!(numbers(&json["B_value"]), [[1.0], [0.0]]);
    assert_eq!(json["c_value"], serde_json::json!([0.0, 0.0]));
    assert_eq!(json["A"], serde_json::json!([["-b/m", "-k"], ["1/m", "0"]]));
    assert_eq!(json["inputs"], serde_json::json!(["F"]));
    // Zeros are written 0.0, not -0.0.
    let text = succeed(&[
        "equations",
        "models/examples/mass_spring_damper.ron",
        "--format",
        "json",
    ]);
    assert!(!text.contains("-0.0"), "{text}");
}

#[test]
fn coenergy_states_are_velocities_and_forces() {
    for path in ron_files(EXAMPLES) {
        let json = json(&[&path, "--states", "coenergy"]);
        assert_eq!(json["variables"], "coenergy", "{path}");
        for state in json["states"].as_array().expect("states") {
            let quantity = state["quantity"].as_str().expect("quantity");
            assert!(matches!(quantity, "v" | "f"), "{path}: {quantity}");
            assert!(
                state["name"]
                    .as_str()
                    .is_some_and(|n| n.starts_with(&format!("{quantity}_"))),
                "{path}: {state}"
            );
        }
    }
    let json = json(&[
        "models/examples/mass_spring_damper.ron",
        "--states",
        "coenergy",
    ]);
    let names: Vec<&str> = json["states"]
        .as_array()
        .expect("states")
        .iter()
        .map(|s| s["name"].as_str().expect("name"))
        .collect();
    assert_eq!(names, ["v_mass", "f_spring"]);
    // m dv/dt = F - f - b v, df/dt = k v.
    assert_eq!(numbers(&json["A_value"]), [[-2.0, -0.5], [200.0, 0.0]]);
}

#[test]
fn latex_is_a_matrix_equation() {
    for path in ron_files(EXAMPLES) {
        let latex = succeed(&["equations", &path, "--format", "latex"]);
        assert!(latex.contains("\\begin{bmatrix}"), "{path}:\n{latex}");
        assert!(latex.contains("\\end{bmatrix}"), "{path}:\n{latex}");
    }
}

#[test]
fn text_output_shows_the_states_and_matrices() {
    let text = succeed(&["equations", "models/examples/mass_spring_damper.ron"]);
    assert!(
        text.starts_with("model 'mass_spring_damper': 2 states in energy variables, 1 input\n")
    );
    assert!(
        text.contains("dp_mass/dt   = -b/m*p_mass - k*q_spring + F\n"),
        "{text}"
    );
    assert!(text.contains("A = [ -b/m  -k ]\n"), "{text}");
}

#[test]
fn an_output_appears_in_text_and_json() {
    let text = succeed(&[
        "equations",
        "models/examples/mass_spring_damper.ron",
        "--output",
        "effort:damper",
    ]);
    // The damper force b v = (b/m) p.
    assert!(
        text.contains("\noutputs:\n  effort:damper = b/m*p_mass\n"),
        "{text}"
    );

    let json = json(&[
        "models/examples/mass_spring_damper.ron",
        "--output",
        "effort:damper",
    ]);
    let outputs = json["outputs"].as_array().expect("outputs");
    assert_eq!(outputs.len(), 1);
    assert_eq!(outputs[0]["name"], "effort:damper");
    assert_eq!(outputs[0]["C"], serde_json::json!(["b/m", "0"]));
    assert_eq!(
        numbers(&serde_json::json!([outputs[0]["C_value"]])),
        [[2.0, 0.0]]
    );
}

#[test]
fn a_missing_model_file_is_a_clear_error() {
    let err = fail(&["check", "models/examples/no_such_model.ron"]);
    assert!(
        err.starts_with("error: cannot read model file 'models/examples/no_such_model.ron': "),
        "{err}"
    );
    let err = fail(&["equations", "no/such/dir/model.ron", "--format", "json"]);
    assert!(
        err.contains("cannot read model file 'no/such/dir/model.ron'"),
        "{err}"
    );
}

#[test]
fn an_unknown_output_element_is_a_clear_error_naming_it() {
    let err = fail(&[
        "equations",
        "models/examples/mass_spring_damper.ron",
        "--output",
        "effort:dashpot",
    ]);
    assert_eq!(
        err,
        "error: output 'effort:dashpot': the model has no element 'dashpot'\n"
    );
    let err = fail(&[
        "equations",
        "models/examples/mass_spring_damper.ron",
        "--output",
        "flow:force->dashpot",
    ]);
    assert!(err.contains("the model has no element 'dashpot'"), "{err}");
}

/// A fresh directory under the system's temporary directory.
pub(crate) fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bondgraph-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn reproduce_writes_its_results_and_the_json_contract() {
    let dir = scratch("reproduce");
    let out = dir.to_string_lossy().to_string();
    let summary = succeed(&["reproduce", "--out", &out]);
    assert!(summary.contains("RMS error"), "{summary}");
    assert!(
        summary.contains(&format!("see {out}/report.md")),
        "{summary}"
    );
    for file in [
        "report.md",
        "reproduce.json",
        "table3.csv",
        "table6.csv",
        "fig6_robot.svg",
        "fig6_paper.svg",
        "fig6_robot.csv",
        "fig6_paper.csv",
    ] {
        assert!(dir.join(file).exists(), "{file} not written");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("reproduce.json")).unwrap())
            .unwrap();
    let table3 = json["table3"].as_array().unwrap();
    assert_eq!(table3.len(), 27);
    assert_eq!(json["table6"].as_array().unwrap().len(), 6);
    for row in table3 {
        for field in [
            "P_s_kPa",
            "v_ac_mm_s",
            "v_ct_mm_s",
            "exp_mm_s",
            "paper_sim_mm_s",
            "model_mm_s",
            "paper_model_mm_s",
        ] {
            assert!(row.get(field).is_some(), "missing {field}");
        }
    }
    // By hand: at 120 kPa the flagship's tip slides at (A P_s - F_C_ge)/b
    // = (12 - 9.125)/1250 m/s = 2.3 mm/s.
    let cell = table3
        .iter()
        .find(|r| r["P_s_kPa"] == 120.0 && r["v_ac_mm_s"] == 5.8)
        .unwrap();
    assert!((cell["model_mm_s"].as_f64().unwrap() - 2.3).abs() < 1e-9);
    let events = json["fig6"]["events"].as_array().unwrap();
    assert!(!events.is_empty());
    for field in ["t", "from", "to", "element", "reason"] {
        assert!(events[0].get(field).is_some(), "missing {field}");
    }
    // What the refitted model gets wrong on Table III, with every library candidate tried.
    let discrepancy = &json["discrepancy"];
    let library = std::fs::read_dir(root().join("models/eversion/extensions"))
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "ron")
        })
        .count();
    assert_eq!(discrepancy["ranking"].as_array().unwrap().len(), library);
    assert!(discrepancy.get("selected").is_some());
    assert!(discrepancy["baseline"]["rmse_heldout"].as_f64().unwrap() > 0.0);
    assert!(dir.join("discrepancy/residuals_before.svg").exists());
    // The same JSON on standard output with --format json.
    let printed: serde_json::Value =
        serde_json::from_str(&succeed(&["reproduce", "--out", &out, "--format", "json"])).unwrap();
    assert_eq!(printed["table3"], json["table3"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn simulate_prints_csv_and_json_and_plots() {
    let dir = scratch("simulate");
    let plot = dir.join("belt.svg").to_string_lossy().to_string();
    let csv = succeed(&[
        "simulate",
        "models/examples/belt_friction.ron",
        "--scenario",
        "models/scenarios/belt_stick_slip.ron",
        "--plot",
        &plot,
    ]);
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("t,mode,"), "{header}");
    assert!(std::fs::read_to_string(&plot).unwrap().contains("<svg"));
    let json: serde_json::Value = serde_json::from_str(&succeed(&[
        "simulate",
        "models/examples/belt_friction.ron",
        "--scenario",
        "models/scenarios/belt_stick_slip.ron",
        "--format",
        "json",
    ]))
    .unwrap();
    // The first breakaway: the spring holds k q = F_S after q = F_S/k = 0.1 m at 0.1 m/s.
    let events = json["events"].as_array().unwrap();
    assert!(
        (events[0]["t"].as_f64().unwrap() - 1.0).abs() < 1e-9,
        "{events:?}"
    );
    assert_eq!(events[0]["to"], "friction=slip+");
    assert!(json["final"]["states"].get("q_spring").is_some());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Recorded books come with their balance and their error bound in JSON; books whose bound
/// is past a millionth of their size say so. The motor of `models/examples/dc_motor.ron`
/// with K = 1e29 rings at 3e32 rad/s, its decay rate and its steady current below rounding
/// (`bondgraph-solver/tests/energy_books.rs`); the plain motor's books are exact to rounding.
#[test]
fn simulate_says_what_the_energy_books_are_worth() {
    let dir = scratch("books");
    std::fs::create_dir_all(&dir).unwrap();
    let scenario = |k: &str| {
        let path = dir.join(format!("motor_{k}.ron"));
        std::fs::write(
            &path,
            format!(
                "Scenario(name: \"motor\", parameters: {{\"K\": {k}}},\n\
                 inputs: {{\"V\": Step(at: 0.01, before: 0.0, after: 12.0)}},\n\
                 duration: 0.5, sample: 0.05,\n\
                 record: [\"energy:supplied\", \"energy:dissipated\", \"energy:stored\"])\n"
            ),
        )
        .unwrap();
        path.to_string_lossy().into_owned()
    };
    let simulate = |path: &str| {
        run(&[
            "simulate",
            "models/examples/dc_motor.ron",
            "--scenario",
            path,
            "--format",
            "json",
        ])
    };
    let plain = simulate(&scenario("0.05"));
    assert_eq!(plain.status.code(), Some(0), "{}", stderr(&plain));
    assert!(!stderr(&plain).contains("warning"), "{}", stderr(&plain));
    let json: serde_json::Value = serde_json::from_str(&stdout(&plain)).unwrap();
    let books = &json["energy"];
    let scale = books["supplied"].as_f64().unwrap();
    assert!(scale > 0.0, "{books}");
    assert!(
        books["residual"].as_f64().unwrap().abs() <= 1e-12 * scale,
        "{books}"
    );
    assert!(books["error"].as_f64().unwrap() <= 1e-9 * scale, "{books}");
    let stalled = simulate(&scenario("1e29"));
    assert_eq!(stalled.status.code(), Some(0), "{}", stderr(&stalled));
    let said = stderr(&stalled);
    assert!(
        said.contains("warning: the energy books are uncertain to"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn simulate_reports_a_bad_scenario_at_its_line() {
    let dir = scratch("bad-scenario");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.ron");
    std::fs::write(
        &path,
        "Scenario(\n    name: \"bad\",\n    inputs: { \"v_blet\": Constant(0.1) },\n    duration: 1.0,\n)\n",
    )
    .unwrap();
    let output = run(&[
        "simulate",
        "models/examples/belt_friction.ron",
        "--scenario",
        &path.to_string_lossy(),
    ]);
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("bad.ron:3:"), "{stderr}");
    assert!(stderr.contains("v_blet"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn discover_prints_the_json_contract() {
    let printed = succeed(&[
        "discover",
        "--model",
        "models/eversion/robot.ron",
        "--data",
        "models/eversion/data/table3.csv",
        "--format",
        "json",
    ]);
    let json: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(json["observed"], "v_ge_mm_s");
    assert!(json["noise"].as_f64().is_some_and(|n| n > 0.0));
    // Table III measures no condition twice: the noise is the best model's residual.
    assert!(
        json["noise_source"]
            .as_str()
            .is_some_and(|s| s.starts_with("residual of ")),
        "{}",
        json["noise_source"]
    );
    assert!(json["pure_error"].is_null() && json["lack_of_fit"].is_null());
    for field in ["rmse_fit", "rmse_heldout"] {
        assert!(
            json["baseline"][field].as_f64().is_some(),
            "missing {field}"
        );
    }
    for field in [
        "id",
        "params",
        "rmse_fit",
        "rmse_heldout",
        "p_value",
        "score",
    ] {
        assert!(json["ranking"][0].get(field).is_some(), "missing {field}");
    }
    assert!(json.get("selected").is_some() && json["indistinguishable"].is_array());
    for field in ["rmse_heldout_before", "rmse_heldout_after"] {
        assert!(json["gain"][field].as_f64().is_some(), "missing {field}");
    }
    // Best held-out RMSE first.
    let scores: Vec<f64> = json["ranking"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["rmse_heldout"].as_f64().unwrap())
        .collect();
    assert!(scores.windows(2).all(|w| w[0] <= w[1]), "{scores:?}");
}

#[test]
fn extend_writes_a_model_and_points_at_the_fragment_line() {
    let extended = succeed(&[
        "extend",
        "models/eversion/robot.ron",
        "models/eversion/extensions/ac-sheath-drag.ron",
    ]);
    assert!(extended.contains("name: \"eversion_robot+ac-sheath-drag\""));
    let dir = scratch("extend");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.ron");
    std::fs::write(
        &bad,
        "Extension(\n    id: \"bad\",\n    cause: \"a typo\",\n    elements: {\"drag\": R(resistance: \"b\")},\n    bonds: [(\"tipp\", \"drag\")],\n)\n",
    )
    .unwrap();
    let err = fail(&["extend", "models/eversion/robot.ron", bad.to_str().unwrap()]);
    assert!(err.contains("bad.ron:5:"), "{err}");
    assert!(err.contains("tipp"), "{err}");
    // The same fragment in a library handed to discover: the same located message.
    let err = fail(&[
        "discover",
        "--model",
        "models/eversion/robot.ron",
        "--data",
        "models/eversion/data/table3.csv",
        "--extensions",
        dir.to_str().unwrap(),
    ]);
    assert!(err.contains("bad.ron:5:"), "{err}");
    assert!(!err.contains("error: error"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The equations echo what the file's directions and ratios mean: the DC motor's gear
/// (`TF(ratio: "1/N")`, N = 10) is a reduction, its supply pushes into the armature.
#[test]
fn equations_echo_the_conventions_of_sources_and_transformers() {
    let text = succeed(&["equations", "models/examples/dc_motor.ron"]);
    let block = text
        .split("\nconventions (as written in the file):\n")
        .nth(1)
        .unwrap_or_else(|| panic!("no conventions block:\n{text}"));
    assert_eq!(
        block.lines().collect::<Vec<_>>(),
        [
            "  Se 'supply' imposes effort V on its bond to 'armature'; a positive V with a \
             positive flow out of the source delivers power",
            "  GY 'motor' (K = 0.05): effort on the side of 'armature' = K × flow to 'gear'; \
             effort on the side of 'gear' = K × flow from 'armature'",
            "  TF 'gear' (1/N = 0.1): effort on the side of 'motor' = 1/N × effort on the side \
             of 'load'; flow to 'load' = 1/N × flow from 'motor': the flow is reduced 10 times \
             and the effort amplified 10 times",
        ]
    );
    let latex = succeed(&[
        "equations",
        "models/examples/dc_motor.ron",
        "--format",
        "latex",
    ]);
    assert!(
        latex.starts_with(
            "% State equations of 'dc_motor' (bondgraph). The matrices need \\usepackage{amsmath}"
        ),
        "{latex}"
    );
}
#[test]
fn calibrate_and_discover_any_model_with_nothing_but_model_and_data() {
    // The geared motor: experiment.ron and extensions/ beside the model, found by default.
    let model = "models/examples/geared_motor/geared_motor.ron";
    let data = "models/examples/geared_motor/data/steady.csv";
    let printed = succeed(&[
        "calibrate",
        "--model",
        model,
        "--data",
        data,
        "--format",
        "json",
    ]);
    let json: serde_json::Value = serde_json::from_str(&printed).unwrap();
    // The independent optimum (bondgraph-fit/tests/calibration.rs): K = 0.050035 +- 1.7e-4.
    let k = json["params"]["K"]["value"].as_f64().unwrap();
    assert!((k - 0.050035).abs() < 0.2 * 1.7e-4, "{k}");
    assert!(json["params"]["T_S"]["interval"].is_array());
    assert_eq!(json["rows"], 22);
    let printed = succeed(&[
        "discover", "--model", model, "--data", data, "--format", "json",
    ]);
    let json: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(json["observed"], "w_rad_s");
    assert_eq!(json["ranking"].as_array().unwrap().len(), 3);
    // Nothing is hidden in the data: nothing may be selected. On steady speeds every
    // candidate is a base refit in disguise, w = (alpha V - T_C - tau)/(b + beta) with
    // alpha = N K/R_a and beta = N^2 K^2/R_a: windage adds to b; a brush drop U_b to T_C
    // (T_C + alpha U_b); bearings loaded by the brake, (1 + mu_b) tau, are the base with
    // K/(1 + mu_b), T_C/(1 + mu_b) and b + beta = (b_0 + beta_0)/(1 + mu_b). All three are
    // reported as indistinguishable from the base model.
    assert!(json["selected"].is_null());
    // No condition is measured twice and nothing is selected: the base model's residual,
    // 22 rows less 4 fitted parameters.
    assert_eq!(json["noise_source"], "residual of the base model (18 dof)");
    assert!(json["lack_of_fit"].is_null());
    assert_eq!(
        json["indistinguishable"],
        serde_json::json!([
            "brake-loaded-bearings",
            "brush-voltage-drop",
            "shaft-windage"
        ])
    );
}

#[test]
fn discover_takes_a_time_series() {
    // The recorded run of data/step.csv (data/generate_step.py: the base model's truth,
    // K = 0.05, b = 0.05, T_C = 0.15, T_S = 0.3, J = 0.01, plus noise of 0.05 rad/s):
    // held out in five contiguous blocks of the one run, each predicted by simulating the
    // whole run. Nothing is hidden in it, and on a run each candidate is still a base refit
    // in disguise (bondgraph-fit/tests/discover.rs derives them): windage of b, the brush
    // drop of T_C and T_S, the brake-loaded bearings of every torque scaled by 1/(1 + mu_b).
    let printed = succeed(&[
        "discover",
        "--model",
        "models/examples/geared_motor/geared_motor.ron",
        "--data",
        "models/examples/geared_motor/data/step.csv",
        "--experiment",
        "models/examples/geared_motor/experiment_step.ron",
        "--format",
        "json",
    ]);
    let json: Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(json["observed"], "w_rad_s");
    assert_eq!(json["rows"], 201);
    assert!(json["noise"].as_f64().is_some_and(|n| n > 0.0));
    // A run's samples are not replicates: the noise is a model's residual.
    assert!(
        json["noise_source"]
            .as_str()
            .is_some_and(|s| s.starts_with("residual of ")),
        "{}",
        json["noise_source"]
    );
    assert!(json["pure_error"].is_null() && json["lack_of_fit"].is_null());
    for field in ["rmse_fit", "rmse_heldout"] {
        assert!(
            json["baseline"][field].as_f64().is_some(),
            "missing {field}"
        );
    }
    let ranking = json["ranking"].as_array().unwrap();
    assert_eq!(ranking.len(), 3);
    for r in ranking {
        for field in [
            "id",
            "params",
            "rmse_fit",
            "rmse_heldout",
            "p_value",
            "score",
        ] {
            assert!(r.get(field).is_some(), "missing {field}");
        }
    }
    assert!(json.get("selected").is_some() && json["indistinguishable"].is_array());
    for field in ["rmse_heldout_before", "rmse_heldout_after"] {
        assert!(json["gain"][field].as_f64().is_some(), "missing {field}");
    }
    // Nothing selected; all three reported indistinguishable from the base model.
    assert!(json["selected"].is_null());
    assert_eq!(
        json["indistinguishable"],
        serde_json::json!([
            "brake-loaded-bearings",
            "brush-voltage-drop",
            "shaft-windage"
        ])
    );
    // Every sample in the table, with its time.
    let table = json["table"].as_array().unwrap();
    assert_eq!(table.len(), 201);
    assert_eq!(table[84]["time"], 0.84);
}

#[test]
fn a_bad_experiment_is_reported_at_its_line_and_field() {
    let dir = scratch("bad-experiment");
    std::fs::create_dir_all(&dir).unwrap();
    let experiment = dir.join("experiment.ron");
    std::fs::write(
        &experiment,
        "Experiment(\n    kind: Steady,\n    conditions: [(\"V_V\", \"V\", 1.0), (\"tau_mNm\", \"tau_load\", 0.001)],\n    absent: [(\"tau_mNm\", [\"gear\"])],\n    observed: [(\"w_rad_s\", \"flow:load_inertia\", 1.0)],\n)\n",
    )
    .unwrap();
    let err = fail(&[
        "calibrate",
        "--model",
        "models/examples/geared_motor/geared_motor.ron",
        "--data",
        "models/examples/geared_motor/data/steady.csv",
        "--experiment",
        experiment.to_str().unwrap(),
    ]);
    // Removing the gear leaves the motor's gyrator dangling: the `absent` entry is named.
    assert!(err.contains("experiment.ron:4:15"), "{err}");
    assert!(
        err.contains("the `absent` entry for `tau_mNm` removes 'gear'"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn discover_takes_the_noise_from_replicates_and_tests_the_fit() {
    // steady.csv twice, the second time 0.1 rad/s faster wherever the shaft turns: 22
    // conditions measured twice, 19 pairs 0.1 apart (a pair's squares about its mean sum to
    // 0.1^2/2) and 3 stalled pairs at 0. Pure error: SS = 19 x 0.005 = 0.095 on 22 dof,
    // sd = sqrt(0.095/22) = 0.065714.
    let steady =
        std::fs::read_to_string(root().join("models/examples/geared_motor/data/steady.csv"))
            .unwrap();
    let mut text = steady.clone();
    for line in steady.lines().skip(1) {
        let (conditions, w) = line.rsplit_once(',').unwrap();
        let w: f64 = w.parse().unwrap();
        let again = if w > 0.0 { w + 0.1 } else { w };
        text.push_str(&format!("{conditions},{again:.4}\n"));
    }
    let dir = scratch("replicates");
    std::fs::create_dir_all(&dir).unwrap();
    let data = dir.join("replicated.csv");
    std::fs::write(&data, text).unwrap();
    let printed = succeed(&[
        "discover",
        "--model",
        "models/examples/geared_motor/geared_motor.ron",
        "--data",
        data.to_str().unwrap(),
        "--format",
        "json",
    ]);
    let json: Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(
        json["noise_source"],
        "pure error of 22 replicated conditions (22 dof)"
    );
    let sd = (0.095f64 / 22.0).sqrt();
    assert!(
        (json["noise"].as_f64().unwrap() - sd).abs() < 1e-9,
        "{}",
        json["noise"]
    );
    assert_eq!(json["pure_error"]["dof"], 22);
    assert_eq!(json["pure_error"]["groups"], 22);
    // Lack of fit of the base model (4 parameters, 44 rows): (44 - 4) - 22 = 18 dof,
    // F = ((SSE - 0.095)/18)/(0.095/22) with SSE = 44 rmse_fit^2.
    let sse = 44.0 * json["baseline"]["rmse_fit"].as_f64().unwrap().powi(2);
    let f = ((sse - 0.095) / 18.0) / (0.095 / 22.0);
    let test = &json["lack_of_fit"];
    assert_eq!(test["dof"], serde_json::json!([18, 22]));
    assert!(
        (test["statistic"].as_f64().unwrap() - f).abs() < 1e-6 * f,
        "{test} against F = {f}"
    );
    let text = succeed(&[
        "discover",
        "--model",
        "models/examples/geared_motor/geared_motor.ron",
        "--data",
        data.to_str().unwrap(),
    ]);
    let first = text.lines().next().unwrap();
    assert!(
        first.ends_with("noise 0.066, pure error of 22 replicated conditions (22 dof)"),
        "{text}"
    );
    assert!(
        text.contains("lack of fit of the base model: F = "),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A scenario drives a model built from parts by its qualified names: a part's parameter
/// set, its element started displaced and recorded.
#[test]
fn a_scenario_names_a_sub_models_parameters_and_elements() {
    let dir = scratch("composed");
    std::fs::create_dir_all(&dir).unwrap();
    let scenario = dir.join("release.ron");
    std::fs::write(
        &scenario,
        r#"Scenario(
    name: "release",
    inputs: { "v_r": Constant(0.0) },
    parameters: { "suspension.k_s": 20000.0 },
    initial_state: { "suspension.spring": 0.01 },
    duration: 0.01,
    record: ["effort:suspension.spring", "flow:body"],
    sample: 0.01,
)"#,
    )
    .unwrap();
    let csv = succeed(&[
        "simulate",
        "models/examples/composed/quarter_car.ron",
        "--scenario",
        &scenario.to_string_lossy(),
    ]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("t,mode,effort:suspension.spring,flow:body")
    );
    // At the start the spring, stretched 1 cm at the scenario's 20 000 N/m, pushes 200 N
    // and the body is at rest.
    let first: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .filter_map(|c| c.parse().ok())
        .collect();
    assert_eq!(first[0], 0.0);
    assert!((first[1] - 200.0).abs() < 1e-9, "{csv}");
    assert!(first[2].abs() < 1e-12, "{csv}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A linear graph built from sub-graphs is explained in its own words, every branch
/// variable qualified as its state is; a nonlinear linear graph is summarised as a graph.
#[test]
fn a_composed_linear_graph_is_explained_with_qualified_variables() {
    let text = succeed(&["explain", "models/examples/composed/wall.lg.ron"]);
    assert!(
        text.contains("  plaster: 'wall_layer' from models/parts/wall_layer.lg.ron; plaster.inside is node 'surface', plaster.outside is node 'p_b'"),
        "{text}"
    );
    assert!(text.contains("its across variable plaster.v_capacity is a state"));
    assert!(text.contains(
        "States: v_air_capacity, plaster.v_capacity, brick.v_capacity, insulation.v_capacity"
    ));
    assert!(!text.contains("v_plaster."), "{text}");

    let dir = scratch("nonlinear-graph");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("duffing.lg.ron");
    std::fs::write(
        &path,
        r#"LinearGraph(name: "duffing",
    parameters: {"m": (value: 1.0, unit: "kg"), "k": (value: 100.0, unit: "N/m"),
        "k_3": (value: 1.0e4, unit: "N/m^3")},
    inputs: {"F": (unit: "N")},
    ground: "g",
    branches: {
        "force": ThroughSource(value: "F", from: "g", to: "v1"),
        "mass": A(capacitance: "m", from: "v1", to: "g"),
        "spring": T(through: "k*q_spring + k_3*q_spring^3", from: "v1", to: "g"),
    },
)"#,
    )
    .unwrap();
    let summary = succeed(&["check", &path.to_string_lossy()]);
    assert!(
        summary.ends_with(
            ": ok: nonlinear linear graph 'duffing' with 2 nodes, 3 branches, 3 parameters, 1 input and 2 states\n"
        ),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
