//! The teaching models of `models/teaching/` against their closed forms, so the README's
//! walk-through stays true: each scenario's end (or a time the README names), and each
//! analysis the README quotes, against the value derived by hand; and the folder's figures
//! against what the program writes now, so that they cannot go stale.

use std::path::{Path, PathBuf};
use std::process::Command;

use bondgraph_core::source::SourceFile;
use bondgraph_solver::Trajectory;
use bondgraph_view::analyze::{self, Request};
use serde_json::Value;

use crate::support::root;

fn run(model: &str, scenario_file: &str) -> Trajectory {
    let read = |relative: String| {
        let text = std::fs::read_to_string(root().join(&relative))
            .unwrap_or_else(|e| panic!("{relative}: {e}"));
        SourceFile::new(relative, text)
    };
    let model = read(format!("models/teaching/{model}.ron"));
    let scenario = read(format!("models/teaching/scenarios/{scenario_file}.ron"));
    let loaded = bondgraph_ron::scenario::load(&scenario, &model).unwrap_or_else(|e| panic!("{e}"));
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

// ---------------------------------------------------------------------------------------
// The analyses the README quotes, against their closed forms.

/// `bondgraph analyze models/teaching/MODEL.ron --input INPUT --output OUTPUT`, as JSON.
fn analysis(model: &str, input: &str, output: &str) -> Value {
    let path = root().join(format!("models/teaching/{model}.ron"));
    let (model, source) = bondgraph_view::load(&path).unwrap_or_else(|e| panic!("{e:?}"));
    let request = Request {
        input: Some(input.to_string()),
        output: Some(output.to_string()),
        ..Request::default()
    };
    analyze::analyze(&model, &source, &request)
        .unwrap_or_else(|e| panic!("{e:?}"))
        .json()
}

fn number(value: &Value, what: &str) -> f64 {
    value
        .as_f64()
        .unwrap_or_else(|| panic!("{what} is not a number: {value}"))
}

/// The eigenvalues as `(re, im)`, sorted by real part, then imaginary part.
fn eigenvalues(out: &Value) -> Vec<(f64, f64)> {
    let mut values: Vec<(f64, f64)> = out["eigenvalues"]
        .as_array()
        .expect("eigenvalues")
        .iter()
        .map(|e| (number(&e["re"], "re"), number(&e["im"], "im")))
        .collect();
    values.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    values
}

/// A first-order lag `G / (τ s + 1)`: its pole, DC gain and step metrics (rise from 10 % to
/// 90 % in `τ ln 9`, within 2 % after `τ ln 50`, no overshoot).
fn first_order(out: &Value, tau: f64, gain: f64) {
    let poles = eigenvalues(out);
    assert_eq!(poles.len(), 1);
    close(poles[0].0, -1.0 / tau, 1e-12);
    close(number(&out["dc_gain"], "dc_gain"), gain, 1e-12);
    let step = &out["step"];
    close(number(&step["final_value"], "final"), gain, 1e-9);
    close(number(&step["rise_time"], "rise"), tau * 9f64.ln(), 1e-6);
    close(
        number(&step["settling_time"], "settling"),
        tau * 50f64.ln(),
        1e-6,
    );
    assert!(number(&step["overshoot_percent"], "overshoot").abs() < 1e-9);
}

#[test]
fn first_order_models_have_the_time_constants_and_gains_the_readme_quotes() {
    // RC: V_C/V = 1/(R C s + 1), τ = R C = 1000 Ω × 1 mF.
    first_order(&analysis("rc", "V", "effort:capacitor"), 1.0, 1.0);
    // Tank: p/Q_in = R/(τ s + 1), τ = R A/(ρ g) = 98100 × 1/(1000 × 9.81) = 10 s.
    first_order(&analysis("tank", "Q_in", "effort:tank"), 10.0, 98100.0);
    // Body temperature per heater watt: R_th/(R_th C_th s + 1), τ = 0.1 × 500 = 50 s.
    first_order(&analysis("thermal", "P", "effort:body"), 50.0, 0.1);
}

#[test]
fn mass_spring_damper_step_response_against_its_closed_form() {
    let out = analysis("mass_spring_damper", "F", "q_spring");
    // m = 1, k = 100, b = 4: ω_n = 10, ζ = 0.2, poles -ζω_n ± iω_d.
    let (k, zeta, wn) = (100.0_f64, 0.2_f64, 10.0_f64);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let poles = eigenvalues(&out);
    close(poles[0].0, -zeta * wn, 1e-12);
    close(poles[0].1, -wd, 1e-12);
    close(poles[1].1, wd, 1e-12);
    close(number(&out["dc_gain"], "dc_gain"), 1.0 / k, 1e-12);
    // y(t) = (1 - e^{-ζω t}(cos ω_d t + ζ/√(1-ζ²) sin ω_d t))/k; its first peak at π/ω_d
    // is above 1/k by e^{-ζπ/√(1-ζ²)}.
    let y = |t: f64| {
        (1.0 - (-zeta * wn * t).exp()
            * ((wd * t).cos() + zeta / (1.0 - zeta * zeta).sqrt() * (wd * t).sin()))
            / k
    };
    let overshoot = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
    let step = &out["step"];
    close(
        number(&step["overshoot_percent"], "overshoot"),
        100.0 * overshoot,
        1e-9,
    );
    // The peak's time is found where y' = 0, to within the flat top's precision.
    close(
        number(&step["peak_time"], "peak time"),
        std::f64::consts::PI / wd,
        1e-7,
    );
    close(
        number(&step["peak_value"], "peak"),
        (1.0 + overshoot) / k,
        1e-9,
    );
    // The rise time: from y = 0.1/k to 0.9/k, both before the peak, by bisection.
    let crossing = |level: f64| {
        let (mut lo, mut hi) = (0.0, std::f64::consts::PI / wd);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if y(mid) < level { lo = mid } else { hi = mid }
        }
        lo
    };
    let rise = crossing(0.9 / k) - crossing(0.1 / k);
    close(number(&step["rise_time"], "rise"), rise, 1e-6);
}

#[test]
fn quarter_car_poles_zero_and_gain_from_the_textbook_quartic() {
    let out = analysis("quarter_car", "v_r", "flow:body");
    let (m_b, m_w, k_s, b_s, k_t) = (250.0, 35.0, 16000.0, 1000.0, 160000.0);
    // Body over road velocity: k_t (b_s s + k_s) / (m_b m_w s^4 + b_s (m_b + m_w) s^3
    //   + (k_s (m_b + m_w) + k_t m_b) s^2 + b_s k_t s + k_s k_t).
    let den = [
        m_b * m_w,
        b_s * (m_b + m_w),
        k_s * (m_b + m_w) + k_t * m_b,
        b_s * k_t,
        k_s * k_t,
    ];
    for (re, im) in eigenvalues(&out) {
        let z = bondgraph_solver::analysis::Complex64::new(re, im);
        let p = den.iter().fold(
            bondgraph_solver::analysis::Complex64::new(0.0, 0.0),
            |acc, c| acc * z + c,
        );
        assert!(p.norm() < 1e-9 * den[4], "{re} ± {im}i: {p}");
    }
    let zeros = out["zeros"].as_array().expect("zeros");
    assert_eq!(zeros.len(), 1);
    close(number(&zeros[0]["re"], "zero"), -k_s / b_s, 1e-12);
    close(number(&out["dc_gain"], "dc_gain"), 1.0, 1e-12);
    let monic: Vec<f64> = den.iter().map(|c| c / den[0]).collect();
    let tf = &out["transfer_function"];
    for (i, c) in monic.iter().enumerate() {
        close(number(&tf["denominator"][i], "denominator"), *c, 1e-12);
    }
    close(
        number(&tf["numerator"][0], "numerator"),
        k_t * b_s / den[0],
        1e-12,
    );
    close(
        number(&tf["numerator"][1], "numerator"),
        k_t * k_s / den[0],
        1e-12,
    );
}

#[test]
fn dc_motor_speed_per_volt_and_poles_by_hand() {
    let out = analysis("dc_motor", "V", "flow:load_inertia");
    let (r, l, kt, n, j, b) = (1.2_f64, 0.005, 0.05, 10.0, 0.002, 0.001);
    // ω/V = K N / ((L s + R)(J s + b) + K² N²): s² + (R/L + b/J) s + (R b + K² N²)/(L J).
    let (c1, c0) = (r / l + b / j, (r * b + kt * kt * n * n) / (l * j));
    let (re, im) = (-c1 / 2.0, (c0 - c1 * c1 / 4.0).sqrt());
    let poles = eigenvalues(&out);
    close(poles[0].0, re, 1e-12);
    close(poles[0].1, -im, 1e-12);
    close(poles[1].1, im, 1e-12);
    close(
        number(&out["dc_gain"], "dc_gain"),
        kt * n / (r * b + kt * kt * n * n),
        1e-12,
    );
}

// ---------------------------------------------------------------------------------------
// The figures: what commands.txt says, what the program writes now, what the README quotes.

const TEACHING: &str = "models/teaching";

/// One line of `models/teaching/commands.txt`: the file, the exit code, the arguments.
struct Line {
    file: String,
    code: i32,
    arguments: Vec<String>,
}

fn commands() -> Vec<Line> {
    let text =
        std::fs::read_to_string(root().join(TEACHING).join("commands.txt")).expect("commands.txt");
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(|l| {
            let mut words = l.split_whitespace();
            let file = words.next().expect("file").to_string();
            let code = words
                .next()
                .and_then(|c| c.parse().ok())
                .expect("exit code");
            Line {
                file,
                code,
                arguments: words.map(str::to_string).collect(),
            }
        })
        .collect()
}

fn figure(name: &str) -> PathBuf {
    root().join(TEACHING).join("figures").join(name)
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The first line where `fresh` and `committed` differ, for the message.
fn first_difference(fresh: &str, committed: &str) -> String {
    let (a, b): (Vec<&str>, Vec<&str>) = (fresh.lines().collect(), committed.lines().collect());
    let i = (0..a.len().max(b.len()))
        .find(|&i| a.get(i) != b.get(i))
        .unwrap_or(0);
    format!(
        "line {}: now {:?}, committed {:?}",
        i + 1,
        a.get(i).unwrap_or(&"<end>"),
        b.get(i).unwrap_or(&"<end>")
    )
}

/// Two CSVs with the same header and times, each cell within a relative 1e-9 of its
/// column's largest value (the last digits of a simulation may differ between machines).
fn same_table(fresh: &str, committed: &str, what: &str) {
    let rows = |text: &str| -> Vec<Vec<String>> {
        text.lines()
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    let (a, b) = (rows(fresh), rows(committed));
    assert_eq!(a.len(), b.len(), "{what}: row count");
    assert_eq!(a[0], b[0], "{what}: header");
    let columns = a[0].len();
    let scale: Vec<f64> = (0..columns)
        .map(|c| {
            b[1..]
                .iter()
                .filter_map(|r| r[c].parse::<f64>().ok())
                .fold(0.0, |m: f64, v| m.max(v.abs()))
        })
        .collect();
    for (i, (x, y)) in a.iter().zip(&b).enumerate().skip(1) {
        for c in 0..columns {
            match (x[c].parse::<f64>(), y[c].parse::<f64>()) {
                (Ok(u), Ok(v)) => assert!(
                    (u - v).abs() <= 1e-9 * scale[c].max(1e-300),
                    "{what}: row {i}, {}: now {u}, committed {v}",
                    a[0][c]
                ),
                _ => assert_eq!(x[c], y[c], "{what}: row {i}, {}", a[0][c]),
            }
        }
    }
}

/// The words of an SVG plot: the contents of its text elements that are not numbers
/// (titles, axis labels, legends), in order.
fn plot_words(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let inner = &t[t.find('>')? + 1..];
            let text = inner[..inner.find("</text>")?].trim().to_string();
            text.chars()
                .any(char::is_alphabetic)
                .then_some(text)
                .filter(|s| !s.starts_with("1e"))
        })
        .collect()
}

#[test]
fn committed_figures_are_what_the_program_writes_now() {
    let lines = commands();
    let scratch = std::env::temp_dir().join(format!("bondgraph-teaching-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).expect("scratch folder");
    let mut named = Vec::new();
    let stale = "is stale: run models/teaching/regenerate.sh";
    for line in &lines {
        let mut plots = Vec::new();
        let arguments: Vec<String> = line
            .arguments
            .iter()
            .map(|a| match a.strip_prefix('@') {
                Some(name) => {
                    plots.push(name.to_string());
                    scratch.join(name).to_string_lossy().into_owned()
                }
                None => a.clone(),
            })
            .collect();
        let output = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
            .args(&arguments)
            .current_dir(root().join(TEACHING))
            .output()
            .expect("the program runs");
        assert_eq!(
            output.status.code(),
            Some(line.code),
            "bondgraph {}\n{}",
            line.arguments.join(" "),
            String::from_utf8_lossy(&output.stderr)
        );
        let fresh = String::from_utf8(output.stdout).expect("UTF-8");
        let committed = read(&figure(&line.file));
        if line.file.ends_with(".csv") {
            same_table(&fresh, &committed, &line.file);
        } else {
            assert!(
                fresh == committed,
                "figures/{} {stale}; {}",
                line.file,
                first_difference(&fresh, &committed)
            );
        }
        named.push(line.file.clone());
        // Plots: present, with the same title, axis labels and legend as now.
        for plot in plots {
            let now = plot_words(&read(&scratch.join(&plot)));
            assert!(!now.is_empty(), "{plot}: no labels");
            assert_eq!(
                plot_words(&read(&figure(&plot))),
                now,
                "figures/{plot} {stale}"
            );
            named.push(plot);
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    // Nothing else lies in figures/: every file there is one a command writes.
    let mut present: Vec<String> = std::fs::read_dir(root().join(TEACHING).join("figures"))
        .expect("figures/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    present.sort();
    named.sort();
    assert_eq!(present, named, "figures/ against commands.txt");
}

#[test]
fn every_excerpt_in_the_readme_is_in_its_figure() {
    // An excerpt is a ```text block after `<!-- excerpt: figures/NAME -->`; its parts
    // between `...` lines appear in the figure whole and in order.
    let readme = read(&root().join(TEACHING).join("README.md"));
    let mut count = 0;
    let mut rest = readme.as_str();
    while let Some(start) = rest.find("<!-- excerpt: ") {
        rest = &rest[start + "<!-- excerpt: ".len()..];
        let name = rest[..rest.find(" -->").expect("closed comment")].trim();
        let text = read(&root().join(TEACHING).join(name));
        let block = rest.find("```text\n").expect("a text block") + "```text\n".len();
        let end = rest[block..].find("```\n").expect("closed block") + block;
        let mut at = 0;
        for part in rest[block..end].split("...\n") {
            let found = text[at..].find(part).unwrap_or_else(|| {
                panic!("README quotes {name}, which does not have, in order:\n{part}")
            });
            at += found + part.len();
        }
        count += 1;
        rest = &rest[end..];
    }
    assert!(count >= 12, "{count} excerpts");
}
