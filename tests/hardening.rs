//! Regressions from the hardening issue (12) at the level of the program: exit codes and
//! messages on inputs and environments that once gave exit 0 or a panic.

use std::fs::File;
use std::process::{Command, Stdio};

use crate::support::root;

/// Runs `bondgraph ARGS` with its standard output going to `/dev/full`, where every write
/// fails with "no space left on device".
fn run_into_full_disk(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args(args)
        .current_dir(root())
        .stdout(Stdio::from(
            File::create("/dev/full").expect("/dev/full exists"),
        ))
        .stderr(Stdio::piped())
        .output()
        .expect("the program runs")
}

#[test]
fn a_failed_write_on_standard_output_is_an_error() {
    for args in [
        &["equations", "models/examples/mass_spring_damper.ron"][..],
        &["check", "models/examples/mass_spring_damper.ron"],
        &["check", "models/examples/nonlinear/pendulum.ron"],
    ] {
        let output = run_into_full_disk(args);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("could not write to standard output"),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

/// Writes `bytes` to a fresh file in the temporary folder and returns its path.
fn temporary(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("bondgraph-hardening-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A byte that is not UTF-8 once said only "stream did not contain valid UTF-8".
#[test]
fn a_byte_that_is_not_utf8_is_located() {
    let text =
        std::fs::read_to_string(root().join("models/examples/mass_spring_damper.ron")).unwrap();
    // Break the first letter of line 3.
    let line_start: usize = text.split_inclusive('\n').take(2).map(str::len).sum();
    let mut bytes = text.into_bytes();
    bytes[line_start] = 0xff;
    let path = temporary("not_utf8.ron", &bytes);
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}:3:1: byte 0xff is not valid UTF-8",
            path.display()
        )),
        "{stderr}"
    );
}

/// A file over the size limit is refused before it is parsed.
#[test]
fn a_file_over_the_size_limit_is_refused() {
    let size = usize::try_from(bondgraph_core::limits::MAX_FILE_BYTES).unwrap() + 1;
    let path = temporary("huge.ron", &vec![b' '; size]);
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("larger than the limit of 16777216 bytes"),
        "{stderr}"
    );
}

/// `graph` once drew a model that `check` rejects: a zero resistance in conductance
/// causality (the effort source sets the resistor's effort, which must then set its flow).
#[test]
fn graph_refuses_a_model_that_check_rejects() {
    let path = temporary(
        "zero_resistance.ron",
        br#"Model(
    name: "zero_resistance",
    parameters: { "R": (value: 0.0), "C": (value: 1.0) },
    inputs: { "E": () },
    elements: { "push": Se(effort: "E"), "node": Zero, "damper": R(resistance: "R"), "tank": C(compliance: "C") },
    bonds: [("push", "node"), ("node", "damper"), ("node", "tank")],
)"#,
    );
    for command in ["check", "graph"] {
        let output = crate::cli::run(&[command, path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{command}: {stderr}");
        assert!(
            stderr.contains("its resistance is zero") && stderr.contains(":5:56"),
            "{command}: {stderr}"
        );
    }
}

/// A flow source `v` driving a mass `m` and a damper `b` on one 1-junction: the source's
/// effort is `b v + m dv/dt` (by hand: the damper's `b v` plus the mass's `m dv/dt`). The
/// JSON once dropped the `m dv/dt` term and LaTeX the whole output equation.
#[test]
fn outputs_keep_their_terms_in_input_derivatives_in_json_and_latex() {
    let path = temporary(
        "driven_mass.ron",
        br#"Model(
    name: "driven_mass",
    parameters: { "m": (value: 2.0), "b": (value: 3.0) },
    inputs: { "v": () },
    elements: { "drive": Sf(flow: "v"), "node": One, "mass": I(inertance: "m"), "damper": R(resistance: "b") },
    bonds: [("drive", "node"), ("node", "mass"), ("node", "damper")],
)"#,
    );
    let path = path.to_str().unwrap();
    let output = crate::cli::run(&[
        "equations",
        path,
        "--output",
        "effort:drive",
        "--format",
        "json",
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let equation = &json["outputs"][0];
    assert_eq!(equation["D"], serde_json::json!(["b"]));
    assert_eq!(equation["F"], serde_json::json!(["m"]));
    assert_eq!(equation["D_value"], serde_json::json!([3.0]));
    assert_eq!(equation["F_value"], serde_json::json!([2.0]));
    let output = crate::cli::run(&[
        "equations",
        path,
        "--output",
        "effort:drive",
        "--format",
        "latex",
    ]);
    let latex = String::from_utf8_lossy(&output.stdout);
    assert!(
        latex.contains(r"\mathrm{effort}(\mathrm{drive}) = b v + m \frac{dv}{dt}"),
        "{latex}"
    );
}

/// The same on a nonlinear model: a flow source `v` drives a mass `m`, a cubic damper
/// (`R(effort: "c*flow^3")`) and a spring `k` on one 1-junction, so the source's effort is
/// `m dv/dt + c v³ + k q_spring` (by hand). At `q_spring = 0.1`, `v = 2` (m = 2, c = 3,
/// k = 5) its gradients are `C = [k] = [5]`, `D = [3 c v²] = [36]` and, in the input's rate,
/// `F = [m] = [2]`. The JSON had `C` and `D` but no `F`, and LaTeX dropped the output
/// equation.
#[test]
fn nonlinear_outputs_keep_their_terms_in_input_derivatives_in_json_and_latex() {
    let path = temporary(
        "driven_cubic.ron",
        br#"Model(
    name: "driven_cubic",
    parameters: { "m": (value: 2.0), "c": (value: 3.0), "k": (value: 5.0) },
    inputs: { "v": () },
    elements: { "drive": Sf(flow: "v"), "node": One, "mass": I(inertance: "m"),
        "damper": R(effort: "c*flow^3"), "spring": C(stiffness: "k") },
    bonds: [("drive", "node"), ("node", "mass"), ("node", "damper"), ("node", "spring")],
)"#,
    );
    let path = path.to_str().unwrap();
    let run = |format: &str| {
        let output = crate::cli::run(&[
            "equations",
            path,
            "--output",
            "effort:drive",
            "--output",
            "integral:flow:spring",
            "--at",
            "q_spring=0.1,v=2",
            "--format",
            format,
        ]);
        let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(output.status.success(), "{format}: {stderr}");
        stdout
    };
    let json: serde_json::Value = serde_json::from_str(&run("json")).unwrap();
    let equation = &json["outputs"][0];
    assert_eq!(equation["C_value"], serde_json::json!([5.0]), "{equation}");
    assert_eq!(equation["D_value"], serde_json::json!([36.0]), "{equation}");
    assert_eq!(equation["F"], serde_json::json!(["m"]), "{equation}");
    assert_eq!(equation["F_value"], serde_json::json!([2.0]), "{equation}");
    // The spring's flow is `v`: no term in an input's rate, so no `F`.
    let integral = &json["outputs"][1];
    assert_eq!(integral["D_value"], serde_json::json!([1.0]), "{integral}");
    assert!(integral.get("F").is_none(), "{integral}");
    let latex = run("latex");
    for line in [
        r"\mathrm{effort}(\mathrm{drive}) = k q_{\mathrm{spring}} + c v^{3} + m \dot{v}",
        r"\mathrm{integral}(\mathrm{flow:spring}) = \int_0^t \left(v\right) dt",
    ] {
        assert!(latex.lines().any(|l| l == line), "{line} not in:\n{latex}");
    }
}

/// A mass `"2^-100000"` (or `m^-30` with m = 1e300) is not zero, but its value in double
/// precision is: the message once said `= 0 ... must be positive`, as if the file wrote 0.
#[test]
fn an_underflowing_coefficient_is_called_an_underflow() {
    for (law, m) in [("2^-100000", "2.0"), ("m^-30", "1e300")] {
        let text = format!(
            r#"Model(
    name: "tiny_mass",
    parameters: {{ "m": (value: {m}) }},
    inputs: {{ "F": () }},
    elements: {{ "push": Se(effort: "F"), "v": One, "mass": I(inertance: "{law}") }},
    bonds: [("push", "v"), ("v", "mass")],
)"#
        );
        let path = temporary("tiny_mass.ron", text.as_bytes());
        let output = crate::cli::run(&["check", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(
            stderr.contains(&format!(
                "element 'mass': inertance \"{law}\" is not zero but underflows to 0 in double \
                 precision; it must be positive"
            )),
            "{stderr}"
        );
    }
    // A true zero is still called zero.
    let path = temporary(
        "zero_mass.ron",
        br#"Model(
    name: "zero_mass",
    parameters: { "m": (value: 0.0) },
    inputs: { "F": () },
    elements: { "push": Se(effort: "F"), "v": One, "mass": I(inertance: "m") },
    bonds: [("push", "v"), ("v", "mass")],
)"#,
    );
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("inertance \"m\" = 0 (with m = 0) must be positive"),
        "{stderr}"
    );
}

/// The junction 'v' has two bonds in the file, one of them to a rejected mass: only the
/// mass is reported, not a follow-on `1-junction 'v' has 1 bond`.
#[test]
fn a_rejected_element_does_not_make_its_junction_look_short_of_bonds() {
    let path = temporary(
        "rejected_mass.ron",
        br#"Model(
    name: "rejected_mass",
    parameters: { "m": (value: -1.0) },
    inputs: { "F": () },
    elements: { "push": Se(effort: "F"), "v": One, "mass": I(inertance: "m") },
    bonds: [("push", "v"), ("v", "mass")],
)"#,
    );
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("element 'mass': inertance"), "{stderr}");
    assert!(!stderr.contains("1-junction 'v'"), "{stderr}");
    // A junction that the file itself gives one bond is still reported.
    let path = temporary(
        "short_junction.ron",
        br#"Model(
    name: "short_junction",
    parameters: { "m": (value: 1.0) },
    inputs: { "F": () },
    elements: { "push": Se(effort: "F"), "v": One, "w": One, "mass": I(inertance: "m") },
    bonds: [("push", "v"), ("v", "mass"), ("push", "w")],
)"#,
    );
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("1-junction 'w' has 1 bond; a junction joins two or more"),
        "{stderr}"
    );
}

/// An error on a 20,000-character line echoes a window of it, not the whole line.
#[test]
fn a_diagnostic_on_a_very_long_line_echoes_a_window_of_it() {
    let padding = " ".repeat(20_000);
    let text = format!(
        r#"Model(
    name: "long_line",
    parameters: {{ "m": (value: 0.0) }},
    inputs: {{ "F": () }},
    elements: {{ {padding}"push": Se(effort: "F"), "v": One, "mass": I(inertance: "m") {padding}}},
    bonds: [("push", "v"), ("v", "mass")],
)"#
    );
    let path = temporary("long_line.ron", text.as_bytes());
    let output = crate::cli::run(&["check", path.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("must be positive"), "{stderr}");
    assert!(stderr.contains("\"mass\": I(inertance: \"m\")"), "{stderr}");
    assert!(stderr.contains("..."), "{stderr}");
    let longest = stderr.lines().map(str::len).max().unwrap();
    assert!(longest < 300, "a line of {longest} bytes in:\n{stderr}");
}

/// A flow source on a 1-junction whose flow a flow source already sets: each file alone is
/// fine, the merged model is a causal conflict. `extend` once printed it with exit 0.
#[test]
fn extend_refuses_a_fragment_that_makes_the_model_inconsistent() {
    let base = temporary(
        "driven.ron",
        br#"Model(
    name: "driven",
    parameters: { "m": (value: 2.0), "b": (value: 4.0) },
    inputs: { "F": () },
    elements: { "push": Sf(flow: "F"), "v": One, "mass": I(inertance: "m"), "damper": R(resistance: "b") },
    bonds: [("push", "v"), ("v", "mass"), ("v", "damper")],
)"#,
    );
    let conflict = temporary(
        "second_drive.ron",
        br#"Extension(
    id: "second-drive",
    cause: "a second motor drives the same velocity",
    inputs: { "V": () },
    elements: { "drive": Sf(flow: "V") },
    bonds: [("drive", "v")],
)"#,
    );
    let (base, conflict) = (base.to_str().unwrap(), conflict.to_str().unwrap());
    let output = crate::cli::run(&["extend", base, conflict]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(output.stdout.is_empty(), "{stderr}");
    assert!(
        stderr.contains("causal conflict at 1-junction 'v'") && stderr.contains("'drive'"),
        "{stderr}"
    );
    // At the extension's element (line 5, column 17), with the junction's place in a note.
    assert!(stderr.contains(&format!("--> {conflict}:5:17")), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "'drive' comes from the extension {conflict}; the problem shows at {base}:5:40"
        )),
        "{stderr}"
    );
    // A consistent fragment (a damper in parallel) still merges.
    let drag = temporary(
        "drag.ron",
        br#"Extension(
    id: "drag",
    cause: "the air resists the mass in proportion to its speed",
    parameters: { "b_air": (value: 1.0) },
    elements: { "air": R(resistance: "b_air") },
    bonds: [("v", "air")],
)"#,
    );
    let output = crate::cli::run(&["extend", base, drag.to_str().unwrap()]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(String::from_utf8_lossy(&output.stdout).contains("\"air\": R(resistance: \"b_air\")"));
}

/// Item 14: a ratio that divides by an input once read `sources must be linear in the
/// inputs`. A transformer's or gyrator's ratio may depend on inputs and states (a modulated
/// two-port); a linear graph's `Gyrator` now is one too, like its `Transformer`. The piston
/// of `tests/fixtures/linear_graph/piston.lg.ron` with its ratio `G` written `1/a`, `a` an
/// input, is at `a = 1/500` the fixture by hand: `dv/dt = -(B + R/G²)/M v - P_s/(G M)`, so
/// `A = -(30 + 3e8/500²)/4 = -307.5` and `B = -1/(500·4) = -5e-4`.
#[test]
fn a_linear_graph_gyrator_may_be_modulated_by_an_input() {
    let text = std::fs::read_to_string(root().join("tests/fixtures/linear_graph/piston.lg.ron"))
        .unwrap()
        .replace(
            r#"inputs: { "P_s": (unit: "Pa") },"#,
            r#"inputs: { "P_s": (unit: "Pa"), "a": (unit: "m^2") },"#,
        )
        .replace(r#"Gyrator(ratio: "G""#, r#"Gyrator(ratio: "1/a""#);
    assert!(text.contains(r#"ratio: "1/a""#));
    let path = temporary("modulated_piston.lg.ron", text.as_bytes());
    let output = crate::cli::run(&[
        "equations",
        path.to_str().unwrap(),
        "--at",
        "a=0.002",
        "--format",
        "json",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let a = json["A_value"][0][0].as_f64().unwrap();
    let b = json["B_value"][0][0].as_f64().unwrap();
    assert!((a + 307.5).abs() < 1e-12, "{a}");
    assert!((b + 5e-4).abs() < 1e-18, "{b}");
}

/// Item 14: a coefficient that may use parameters only says that an input enters it, however
/// it enters (`m/u` once said `divides by an input; sources must be linear in the inputs`);
/// a friction level, linear in the inputs, names its own field rather than "sources", at the
/// divisor.
#[test]
fn an_input_where_it_may_not_be_is_named_as_such() {
    let model = |element: &str| {
        format!(
            r#"Model(
    name: "pushed",
    parameters: {{ "m": (value: 1.0) }},
    inputs: {{ "F": (), "u": () }},
    elements: {{ "push": Se(effort: "F"), "v": One, "mass": {element} }},
    bonds: [("push", "v"), ("v", "mass")],
)"#
        )
    };
    for (element, column, message) in [
        (
            r#"I(inertance: "m/u")"#,
            74,
            "element 'mass': inertance \"m/u\" depends on input 'u'; it may use parameters only",
        ),
        (
            r#"I(inertance: "m*u*u")"#,
            74,
            "element 'mass': inertance \"m*u*u\" depends on input 'u'; it may use parameters \
             only",
        ),
        (
            r#"Friction(breakaway: "m/u", coulomb: "m")"#,
            83,
            "element 'mass': breakaway \"m/u\": divides by an input; breakaway must be linear \
             in the inputs, with rational functions of the parameters as coefficients",
        ),
    ] {
        let path = temporary("pushed.ron", model(element).as_bytes());
        let output = crate::cli::run(&["check", path.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains(message), "{element}: {stderr}");
        assert!(!stderr.contains("sources"), "{element}: {stderr}");
        assert!(
            stderr.contains(&format!("{}:5:{column}", path.display())),
            "{element}: {stderr}"
        );
    }
}

/// Writes a sparse file of `length` zero bytes (no room on the disk) and returns its path.
fn sparse(name: &str, length: u64) -> std::path::PathBuf {
    let path = temporary(name, b"");
    std::fs::File::options()
        .write(true)
        .open(&path)
        .unwrap()
        .set_len(length)
        .unwrap();
    path
}

/// Item 18: a data file and an experiment file beyond their limits are refused, naming the
/// file and the limit, without being read into memory.
#[test]
fn data_and_experiment_files_over_their_limits_are_refused() {
    use bondgraph_core::limits::{MAX_DATA_FILE_BYTES, MAX_FILE_BYTES};
    let model = "models/examples/geared_motor/geared_motor.ron";
    let huge = sparse("huge.csv", MAX_DATA_FILE_BYTES + 1);
    let output = crate::cli::run(&[
        "calibrate",
        "--model",
        model,
        "--data",
        huge.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}: the file is larger than the limit of {MAX_DATA_FILE_BYTES} bytes for a data file",
            huge.display()
        )),
        "{stderr}"
    );
    let experiment = sparse("experiment.ron", MAX_FILE_BYTES + 1);
    let output = crate::cli::run(&[
        "calibrate",
        "--model",
        model,
        "--experiment",
        experiment.to_str().unwrap(),
        "--data",
        "models/examples/geared_motor/data/steady.csv",
    ]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "cannot read the experiment file '{}': it is larger than the limit of \
             {MAX_FILE_BYTES} bytes",
            experiment.display()
        )),
        "{stderr}"
    );
}

/// A friction contact with no friction at all (`T_S = T_C = 0`) on the geared motor, 1 V
/// against a brake of exactly the stall torque (`N K V/R_a = 20·0.05·1/2 = 0.5 N m`): the
/// shaft swings about rest, and each time through zero the contact sticks and lets go at
/// once. It once flipped stuck -> slip -> stuck 29,604 times in 5 s, unreported, and then,
/// with a fast armature (0.01 H), stopped as chattering: once the swings had died out, the
/// speed read a rounding either side of zero in the segments' eigen-coordinates. A contact
/// entering a mode level on a guard's threshold now lets that guard fire only once past the
/// rounding of its terms, so both armatures come to rest (the speed zero to 1e-14 rad/s at
/// 5 s), the slow one (0.1 H) after its swings, the fast one in three events.
#[test]
fn a_contact_without_friction_at_exact_balance_does_not_chatter_unreported() {
    let scenario = |inductance: f64| {
        format!(
            r#"Scenario(name: "balance", parameters: {{ "T_S": 0.0, "T_C": 0.0, "K": 0.05, "L_a": {inductance} }},
    inputs: {{ "V": Constant(1.0), "tau_load": Constant(0.5) }}, initial_mode: "bearings=stuck",
    duration: 5.0, record: ["flow:load_inertia"], sample: 0.5)"#
        )
    };
    let model = "models/examples/geared_motor/geared_motor.ron";
    for (name, inductance, most_events) in [("slow", 0.1, 40), ("fast", 0.01, 5)] {
        let file = temporary(
            &format!("balance_{name}.ron"),
            scenario(inductance).as_bytes(),
        );
        let output = crate::cli::run(&["simulate", model, "--scenario", file.to_str().unwrap()]);
        let summary = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(output.status.success(), "{name}: {summary}");
        let trajectory = String::from_utf8_lossy(&output.stdout).into_owned();
        // The last sample is at the duration, at rest.
        let last = trajectory.lines().last().unwrap();
        assert!(last.starts_with("5,"), "{trajectory}");
        let speed: f64 = last.rsplit(',').next().unwrap().parse().unwrap();
        assert!(speed.abs() < 1e-14, "{name}: {trajectory}");
        let events: usize = summary
            .split(" events")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("{summary}"));
        assert!(events <= most_events, "{name}: {summary}");
    }
}

/// The lead-screw actuator with the Stribeck weakening of its guide, 1.8 V against a 40 N
/// load, at values a fold of a `discover` fitted: the current's rise brings the drive to
/// the breakaway force 1.24 ms in, and the guide enters its creep at zero speed with zero
/// acceleration. An instant later the speed read a rounding below zero in the segment's
/// eigen-coordinates, the guide stuck and broke away again, and the run stopped as
/// chattering after 200 events at that instant. It creeps, and settles where the creep
/// mode's equations put it, derived by hand: with `s = (F_S - F_C - b v_s)/v_s` the
/// creep's falling friction, `V = R_a i + K ω` and `K i + n_s² s ω = n_s (F_L + F_S)`
/// give `ω = (n_s (F_L + F_S) - K V/R_a)/(n_s² s - K²/R_a)` and the speed `n_s ω`.
#[test]
fn a_guide_breaking_away_into_its_creep_at_exact_balance_creeps_on() {
    let (k, b, f_c, f_s, v_s) = (
        0.029993017266183596,
        39.76055179212536,
        10.183438358545615,
        15.164628353065245,
        0.010325420266742755,
    );
    let (n_s, r_a, v, f_l) = (7.957747e-4, 1.2, 1.8, 40.0);
    let s = (f_s - f_c - b * v_s) / v_s;
    let omega = (n_s * (f_l + f_s) - k * v / r_a) / (n_s * n_s * s - k * k / r_a);
    let expected = n_s * omega;
    assert!(expected > 0.0 && expected < v_s, "{expected}");
    let model = temporary("actuator_stribeck.ron", b"");
    crate::cli::succeed(&[
        "extend",
        "models/examples/actuator/actuator.ron",
        "models/examples/actuator/extensions/stribeck-weakening.ron",
        "--out",
        model.to_str().unwrap(),
    ]);
    let scenario = format!(
        r#"Scenario(name: "creep", parameters: {{ "K": {k:?}, "b": {b:?}, "F_C": {f_c:?}, "F_S": {f_s:?}, "v_s": {v_s:?} }},
    inputs: {{ "V": Constant({v:?}), "F_L": Constant({f_l:?}) }}, initial_mode: "guide=stuck",
    duration: 2.0, record: ["flow:carriage"], sample: 0.5)"#
    );
    let scenario = temporary("creep_entry.ron", scenario.as_bytes());
    let trajectory = crate::cli::succeed(&[
        "simulate",
        model.to_str().unwrap(),
        "--scenario",
        scenario.to_str().unwrap(),
    ]);
    let last = trajectory.lines().last().unwrap();
    assert!(last.starts_with("2,guide=creep+,"), "{trajectory}");
    let speed: f64 = last.rsplit(',').next().unwrap().parse().unwrap();
    assert!(
        (speed - expected).abs() < 1e-9 * expected,
        "{speed} against {expected}\n{trajectory}"
    );
}
