//! Extreme parameter values through the program (issue 30: items 3, 7, 9 and 15): values
//! whose intermediate products overflow `f64` are evaluated right, coefficients that
//! overflow are refused with a located error, no command hangs, and huge numbers print in
//! scientific notation.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use serde_json::Value;

use crate::support::root;

/// A copy of the model file `relative` with `from` replaced by `to`, in a scratch directory.
fn variant(relative: &str, name: &str, from: &str, to: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join(relative)).unwrap();
    assert!(text.contains(from), "{relative} has no {from:?}");
    write(name, &text.replacen(from, to, 1))
}

fn write(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("bondgraph-overflow-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs `bondgraph ARGS`, killing it (and failing the test) after 60 s: these inputs once
/// made `analyze` loop for ever.
fn run(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
        .args(args)
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the program runs");
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("bondgraph {}: still running after 60 s", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn succeed(args: &[&str]) -> String {
    let output = run(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{args:?}: {stderr}");
    String::from_utf8(output.stdout).unwrap()
}

/// The standard error of a clean failure (exit 1, no panic, nothing on standard output).
fn fail(args: &[&str]) -> String {
    let output = run(args);
    let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(output.stdout.is_empty(), "{args:?}");
    stderr
}

fn json(args: &[&str]) -> Value {
    let text = succeed(args);
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}:\n{text}"))
}

fn close(x: f64, expected: f64, relative: f64) -> bool {
    (x - expected).abs() <= relative * expected.abs()
}

fn complex(v: &Value) -> Vec<(f64, f64)> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|z| (z["re"].as_f64().unwrap(), z["im"].as_f64().unwrap()))
        .collect()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The line of the first occurrence of `needle` in the file at `path`, 1-based.
fn line_of(path: &PathBuf, needle: &str) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    let offset = text.find(needle).unwrap();
    text[..offset].lines().count() + usize::from(text[..offset].ends_with('\n'))
}

#[test]
fn a_huge_damper_in_series_leaves_the_small_one() {
    // m p' = ... with dampers b1, b2 in series: one damper b = b1 b2/(b1 + b2). With
    // b1 = 1e308, b2 = 3: b = 3/(1 + 3e-308) = 3 to double precision, although b1*b2
    // overflows. dp/dt = F - (b/m) p with m = 1: the eigenvalue is -b/m = -3, and
    // P(s)/F(s) = 1/(s + 3): pole -3, no zero, DC gain 1/3; the step response from rest
    // starts at 0 and settles at 1/3.
    let model = variant(
        "models/examples/series_dampers.ron",
        "series_dampers.ron",
        "\"b1\": (value: 6.0",
        "\"b1\": (value: 1e308",
    );
    let doc = json(&["analyze", model.to_str().unwrap(), "--format", "json"]);
    let eigenvalues = complex(&doc["eigenvalues"]);
    assert_eq!(eigenvalues.len(), 1, "{doc}");
    assert!(close(eigenvalues[0].0, -3.0, 1e-15), "{eigenvalues:?}");
    assert_eq!(eigenvalues[0].1, 0.0);
    assert_eq!(complex(&doc["poles"]).len(), 1);
    assert!(close(complex(&doc["poles"])[0].0, -3.0, 1e-15), "{doc}");
    let tf = &doc["transfer_function"];
    assert_eq!(numbers(&tf["numerator"]), [1.0]);
    let denominator = numbers(&tf["denominator"]);
    assert_eq!(denominator[0], 1.0);
    assert!(close(denominator[1], 3.0, 1e-15), "{denominator:?}");
    let gain = doc["dc_gain"].as_f64().unwrap();
    assert!(close(gain, 1.0 / 3.0, 1e-15), "{gain}");
    assert_eq!(doc["step"]["initial_value"].as_f64(), Some(0.0));
    let last = doc["step"]["final_value"].as_f64().unwrap();
    assert!(close(last, 1.0 / 3.0, 1e-15), "{last}");
    // The text says the same, with no NaN and no integrator.
    let text = succeed(&["analyze", model.to_str().unwrap()]);
    assert!(text.contains("initial value y(0+) = 0\n"), "{text}");
    assert!(
        text.contains("DC gain G(0) = m*(b1 + b2)/(b1*b2) = 0.333333"),
        "{text}"
    );
    assert!(
        !text.contains("NaN") && !text.contains("integrator"),
        "{text}"
    );
}

#[test]
fn a_tiny_mass_keeps_the_slow_pole() {
    // Two masses: det(sI - A) = s^3 + (b/m2) s^2 + k (m1 + m2)/(m1 m2) s + b k/(m1 m2).
    // With m1 = 1e-300 (m2 = 3, k = 50, b = 2.5) the coefficients span 5e301, and the
    // roots are, to double precision, a slow real one at -(b k/(m1 m2))/(k (m1 + m2)/(m1 m2))
    // = -b/(m1 + m2) = -2.5/3 and a fast pair of magnitude sqrt(k (m1 + m2)/(m1 m2))
    // = sqrt(50/1e-300) = 7.0710678e150. The transfer function from F to p_mass1 cancels
    // nothing, so its poles are these three.
    let model = variant(
        "models/examples/two_masses.ron",
        "two_masses_tiny.ron",
        "\"m1\": (value: 1.0",
        "\"m1\": (value: 1e-300",
    );
    let doc = json(&["analyze", model.to_str().unwrap(), "--format", "json"]);
    let fast = (50.0f64 / 1e-300).sqrt();
    for field in ["eigenvalues", "poles"] {
        let values = complex(&doc[field]);
        assert_eq!(values.len(), 3, "{field}: {values:?}");
        let slow: Vec<_> = values.iter().filter(|z| z.1 == 0.0).collect();
        assert_eq!(slow.len(), 1, "{field}: {values:?}");
        assert!(close(slow[0].0, -2.5 / 3.0, 1e-12), "{field}: {values:?}");
        for z in values.iter().filter(|z| z.1 != 0.0) {
            assert!(close(z.0.hypot(z.1), fast, 1e-12), "{field}: {values:?}");
        }
    }
}

#[test]
fn a_coefficient_that_overflows_is_refused_where_it_is_written() {
    // L = 1e-310 H is a positive double, but the current's equation divides by it:
    // dp_inductor/dt has -R/L = -10/1e-310 = -1e311, beyond the largest double (1.8e308).
    // `check` refuses it at the inductor's line, and so does every command, promptly.
    let model = variant(
        "models/examples/rlc.ron",
        "rlc_tiny_inductance.ron",
        "\"L\": (value: 0.1",
        "\"L\": (value: 1e-310",
    );
    let path = model.to_str().unwrap();
    let line = line_of(&model, "\"inductor\": I(");
    for command in ["check", "equations", "analyze", "modes"] {
        let error = fail(&[command, path]);
        assert!(
            error.contains(&format!("rlc_tiny_inductance.ron:{line}:")),
            "{command}: {error}"
        );
        assert!(error.contains("element 'inductor'"), "{command}: {error}");
        assert!(error.contains("overflows"), "{command}: {error}");
        assert!(error.contains("L = 1e-310"), "{command}: {error}");
    }
}

/// A mass `m` pushed by `F`, joined through a lever (transformer) of ratio `r` to a damper
/// `b`: the damper's force on the mass is `r² b v`, so `dp/dt = F - (r² b/m) p`.
fn lever(m: &str, r: &str, b: &str) -> String {
    format!(
        r#"Model(
    name: "lever",
    parameters: {{ "m": (value: {m}), "r": (value: {r}), "b": (value: {b}) }},
    inputs: {{ "F": () }},
    elements: {{
        "force": Se(effort: "F"),
        "v": One,
        "mass": I(inertance: "m"),
        "lever": TF(ratio: "r"),
        "tip": One,
        "damper": R(resistance: "b"),
    }},
    bonds: [("force", "v"), ("v", "mass"), ("v", "lever"), ("lever", "tip"), ("tip", "damper")],
)"#
    )
}

#[test]
fn a_huge_lever_ratio_is_refused_or_printed_as_a_number() {
    // r = 1e308, m = b = 1: r² b/m = 1e616 overflows: refused, at the mass's line (its
    // state's equation holds the coefficient), without hanging.
    let path = write("lever_overflow.ron", &lever("1.0", "1e308", "1.0"));
    for command in ["check", "analyze"] {
        let error = fail(&[command, path.to_str().unwrap()]);
        assert!(error.contains("overflows"), "{command}: {error}");
        assert!(error.contains("element 'mass'"), "{command}: {error}");
    }
    // r = 1e308 with m = 1e300 and b = 1e-300: r² b/m = 1e616 · 1e-300/1e300 = 1e16, a
    // double; the eigenvalue is -1e16. The conventions say the lever amplifies 1e308 times.
    let path = write("lever_fine.ron", &lever("1e300", "1e308", "1e-300"));
    let doc = json(&["analyze", path.to_str().unwrap(), "--format", "json"]);
    let eigenvalues = complex(&doc["eigenvalues"]);
    assert!(close(eigenvalues[0].0, -1e16, 1e-14), "{eigenvalues:?}");
    let text = succeed(&["equations", path.to_str().unwrap()]);
    assert!(
        text.contains("the flow is amplified 1e308 times and the effort reduced 1e308 times"),
        "{text}"
    );
    assert!(!text.contains("inf"), "{text}");
}

#[test]
fn a_huge_mass_does_not_hang_analyze() {
    // Two masses with m2 = 1e308 (m1 = 1, k = 50, b = 2.5): the first mass oscillates on the
    // spring against a wall, s² = -k (m1 + m2)/(m1 m2) to double precision, so the
    // pair is ±sqrt(50) i; the slow root is -b/(m1 + m2) = -2.5e-308. The DC gain from F
    // to p_mass1 is m1 k/(b k) = m1/b = 0.4.
    let model = variant(
        "models/examples/two_masses.ron",
        "two_masses_huge.ron",
        "\"m2\": (value: 3.0",
        "\"m2\": (value: 1e308",
    );
    let doc = json(&["analyze", model.to_str().unwrap(), "--format", "json"]);
    let poles = complex(&doc["poles"]);
    assert_eq!(poles.len(), 3, "{poles:?}");
    let pair: Vec<_> = poles.iter().filter(|z| z.1 != 0.0).collect();
    assert_eq!(pair.len(), 2, "{poles:?}");
    for z in pair {
        assert!(close(z.1.abs(), 50f64.sqrt(), 1e-12), "{poles:?}");
    }
    // The slow root is far below the matrix's precision (its norm is 50), not below the
    // characteristic polynomial's: the eigenvalues agree with the poles.
    for field in ["poles", "eigenvalues"] {
        let values = complex(&doc[field]);
        let slow: Vec<_> = values.iter().filter(|z| z.1 == 0.0).collect();
        assert_eq!(slow.len(), 1, "{field}: {values:?}");
        assert!(close(slow[0].0, -2.5e-308, 1e-12), "{field}: {values:?}");
    }
    let gain = doc["dc_gain"].as_f64().unwrap();
    assert!(close(gain, 0.4, 1e-15), "{gain}");
}

#[test]
fn the_duffing_equilibrium_is_found_or_the_failure_said() {
    // k q + k_3 q³ = F with F = 0 (k = 1, k_3 = 5): the only real equilibrium is q = 0, p = 0.
    // From q = 1e103, k_3 q³ = 5e309 overflows: the search cannot start there and says so.
    let duffing = "models/examples/nonlinear/duffing.ron";
    let error = fail(&[
        "equations",
        duffing,
        "--equilibrium",
        "--at",
        "q_spring=1e103",
    ]);
    assert!(error.contains("not finite"), "{error}");
    assert!(error.contains("q_spring = 1e103"), "{error}");
    // From q = 1e20 Newton's method shrinks q by about 2/3 a step: it reaches 0, not a
    // point 1e-14 of the start's size away from it.
    let doc = json(&[
        "equations",
        duffing,
        "--equilibrium",
        "--at",
        "q_spring=1e20",
        "--format",
        "json",
    ]);
    let q = doc["at"]["q_spring"].as_f64().unwrap();
    let p = doc["at"]["p_mass"].as_f64().unwrap();
    assert!(q.abs() < 1e-12 && p.abs() < 1e-12, "{q}, {p}");
}

/// Whether `text` holds a run of at least 20 digits: a number printed in full that should
/// have been printed in scientific notation.
fn long_digit_run(text: &str) -> Option<&str> {
    text.split(|c: char| !c.is_ascii_digit())
        .find(|run| run.len() >= 20)
}

#[test]
fn huge_numbers_print_in_scientific_notation() {
    // The Duffing oscillator linearised at q = 1e100: the stiffness k + 3 k_3 q² is
    // k + 3e200 k_3, numerically 1 + 1.5e201; the point prints as 1e100.
    let text = succeed(&[
        "equations",
        "models/examples/nonlinear/duffing.ron",
        "--at",
        "q_spring=1e100",
    ]);
    assert_eq!(long_digit_run(&text), None, "{text}");
    assert!(text.contains("q_spring = 1e100"), "{text}");
    assert!(text.contains("3e200*k_3"), "{text}");
    assert!(text.contains("e201 ]"), "{text}");
    // A parameter of 1e200 in check's message: m1*m1 = 1e400 is not a double.
    let text = std::fs::read_to_string(root().join("models/examples/two_masses.ron")).unwrap();
    let text = text
        .replacen("\"m1\": (value: 1.0", "\"m1\": (value: 1e200", 1)
        .replacen("I(inertance: \"m1\")", "I(inertance: \"m1*m1\")", 1);
    let model = write("two_masses_square.ron", &text);
    let error = fail(&["check", model.to_str().unwrap()]);
    assert_eq!(long_digit_run(&error), None, "{error}");
    assert!(
        error.contains("inertance \"m1*m1\" = inf (with m1 = 1e200) must be finite"),
        "{error}"
    );
}

#[test]
fn an_energy_output_is_refused_as_an_output_not_a_record() {
    // `analyze --output` takes rows of y = C x + D u; an energy is not one, whatever the
    // element. The message speaks of --output, not of a scenario's record.
    for output in ["energy:diode", "energy:cap", "power:leak"] {
        let error = fail(&[
            "analyze",
            "models/examples/nonlinear/diode_rc.ron",
            "--output",
            output,
        ]);
        assert!(error.contains(&format!("--output '{output}'")), "{error}");
        assert!(!error.contains("record '"), "{error}");
    }
}
