//! Where `discover`'s noise level comes from, on the geared motor of
//! `models/examples/geared_motor/`: the pure error of replicated conditions, an exact
//! repetition that gives no estimate, and a cell that cannot be fitted.

use std::sync::Arc;

use crate::motor::{self, file, library, motor};
use bondgraph_fit::calibration::calibrate;
use bondgraph_fit::data::{self, Dataset, Measurement};
use bondgraph_fit::discover::{self, DiscoverError, Discovery, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::stats;
use bondgraph_fit::synthetic::{self, Noise};

fn experiment() -> Experiment {
    motor::experiment("experiment.ron")
}

/// The truth of `data/generate.py`.
fn truth() -> Vec<(String, f64)> {
    [("K", 0.05), ("b", 0.05), ("T_C", 0.15), ("T_S", 0.3)]
        .iter()
        .map(|(n, v)| (n.to_string(), *v))
        .collect()
}

/// Every turning condition of 4 to 24 V (steps of 4) with the brake uncoupled and at
/// 1 N m, measured three times: 12 conditions, 36 rows.
fn replicated_design() -> Vec<Measurement> {
    let file: Arc<str> = Arc::from("replicated");
    let mut rows = Vec::new();
    for _ in 0..3 {
        for brake in [None, Some(1000.0)] {
            for k in 1..=6 {
                rows.push(Measurement {
                    conditions: vec![Some(4.0 * f64::from(k)), brake],
                    observed: vec![0.0],
                    time: None,
                    row: rows.len() + 2,
                    file: file.clone(),
                });
            }
        }
    }
    rows
}

/// `rows` as CSV, read back: what a user hands over.
fn dataset(rows: Vec<Measurement>) -> Dataset {
    let experiment = experiment();
    let csv = data::write(&Dataset {
        name: "replicated.csv".into(),
        conditions: vec!["V_V".into(), "tau_mNm".into()],
        observed: vec!["w_rad_s".into()],
        time: None,
        rows,
        ignored: Vec::new(),
    });
    data::read("replicated.csv", &csv, &experiment).unwrap()
}

/// The truth's speeds on the replicated design, with noise of 0.05 rad/s.
fn noisy_truth(seed: u64) -> Vec<Measurement> {
    let source = motor();
    let model = bondgraph_ron::model::load_source(&source).unwrap();
    synthetic::measure(
        &model,
        &source,
        &experiment(),
        &truth(),
        &replicated_design(),
        0.05,
        None,
        &mut Noise::new(seed),
    )
    .unwrap()
}

/// The pure error computed here, apart from the crate: `(SS, dof, groups)` over the rows
/// grouped by their CSV condition text.
fn pure_error_by_hand(dataset: &Dataset) -> (f64, usize, usize) {
    let mut groups: Vec<(String, Vec<f64>)> = Vec::new();
    for r in &dataset.rows {
        let key = format!("{:?}", r.conditions);
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, values)) => values.push(r.observed[0]),
            None => groups.push((key, vec![r.observed[0]])),
        }
    }
    let replicated: Vec<&Vec<f64>> = groups
        .iter()
        .map(|g| &g.1)
        .filter(|v| v.len() > 1)
        .collect();
    let ss = replicated
        .iter()
        .map(|v| {
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            v.iter().map(|y| (y - mean).powi(2)).sum::<f64>()
        })
        .sum();
    let dof = replicated.iter().map(|v| v.len() - 1).sum();
    (ss, dof, replicated.len())
}

fn run(dataset: &Dataset) -> Discovery {
    discover::discover(
        &motor(),
        &experiment(),
        dataset,
        &library(),
        &Settings::default(),
    )
    .unwrap()
}

#[test]
fn replicates_give_the_noise_and_test_the_base_model() {
    let dataset = dataset(noisy_truth(5));
    let (ss, dof, groups) = pure_error_by_hand(&dataset);
    assert_eq!((dof, groups), (24, 12));
    let discovery = run(&dataset);
    let report = discovery.summary();
    assert_eq!(
        discovery.noise_source[0],
        "pure error of 12 replicated conditions (24 dof)"
    );
    let sd = (ss / 24.0).sqrt();
    assert!((discovery.noise[0].unwrap() - sd).abs() < 1e-12, "{report}");
    // 24 dof of a 0.05 rad/s noise: within 30% (the chi-square's 99.9% range).
    assert!((0.035..0.065).contains(&sd), "{sd}");
    assert!(report.lines().next().unwrap().contains("pure error of 12"));
    // Nothing is hidden: the base model at its refit, SSE = n rmse_fit^2, leaves
    // (36 - 4) - 24 = 8 dof of lack of fit, and F = ((SSE - SS)/8)/(SS/24) is F(8, 24).
    let sse = 36.0 * discovery.baseline.rmse_fit.powi(2);
    let f = ((sse - ss) / 8.0) / (ss / 24.0);
    let test = discovery.lack_of_fit.as_ref().expect("a lack-of-fit test");
    assert_eq!(test.dof, [8, 24]);
    assert!((test.statistic - f).abs() < 1e-9 * f, "{test:?} {f}");
    assert!((test.p_value - stats::f_survival(f, 8.0, 24.0)).abs() < 1e-12);
    assert!(test.p_value > 0.01, "{report}");
    let json = serde_json::to_value(&discovery).unwrap();
    assert_eq!(json["pure_error"]["dof"], 24);
    assert_eq!(json["pure_error"]["groups"], 12);
    assert_eq!(json["lack_of_fit"]["dof"], serde_json::json!([8, 24]));
}

#[test]
fn a_misfit_inflates_the_residual_but_not_the_pure_error() {
    // The truth plus 0.3 rad/s on every row at 24 V: a saturation the model cannot bend to.
    // The replicates still scatter by 0.05 rad/s; the base model's residual takes in the
    // misfit, and the lack-of-fit test sees it.
    let mut rows = noisy_truth(5);
    for r in &mut rows {
        if r.conditions[0] == Some(24.0) {
            r.observed[0] += 0.3;
        }
    }
    let dataset = dataset(rows);
    let (ss, _, _) = pure_error_by_hand(&dataset);
    let discovery = run(&dataset);
    let report = discovery.summary();
    let sd = (ss / 24.0).sqrt();
    assert!((discovery.noise[0].unwrap() - sd).abs() < 1e-12, "{report}");
    let residual_sd = (36.0 * discovery.baseline.rmse_fit.powi(2) / 32.0).sqrt();
    assert!(residual_sd > 1.5 * sd, "{residual_sd} {sd}\n{report}");
    let test = discovery.lack_of_fit.as_ref().unwrap();
    assert!(test.p_value < 1e-6, "{report}");
    assert!(
        report.contains("the model misfits beyond the noise"),
        "{report}"
    );
}

#[test]
fn identical_rows_give_no_noise_level_and_say_so() {
    // 30 rows of one condition with one value: pure error 0 on 29 dof.
    let rows: Vec<Measurement> = (0..30)
        .map(|i| Measurement {
            conditions: vec![Some(12.0), None],
            observed: vec![10.6648],
            time: None,
            row: i + 2,
            file: Arc::from("same.csv"),
        })
        .collect();
    let dataset = dataset(rows);
    let discovery = run(&dataset);
    let report = discovery.summary();
    assert_eq!(discovery.noise[0], None, "{report}");
    assert_eq!(
        discovery.noise_source[0],
        "cannot be estimated: the 1 replicated condition repeats exactly (pure error 0 on 29 dof)"
    );
    assert!(discovery.lack_of_fit.is_none());
    assert!(
        report
            .lines()
            .next()
            .unwrap()
            .ends_with("noise: cannot be estimated: the 1 replicated condition repeats exactly (pure error 0 on 29 dof)"),
        "{report}"
    );
    assert!(
        !report.contains("inf") && !report.contains("NaN"),
        "{report}"
    );
    assert!(
        discovery
            .residuals_before
            .by_regime
            .iter()
            .all(|r| !r.stands_out),
        "{report}"
    );
    assert!(!report.contains("replicates: pure error"), "{report}");
    let json = serde_json::to_value(&discovery).unwrap();
    assert!(json["noise"].is_null());
}

#[test]
fn calibrate_takes_the_pure_error_too() {
    let dataset = dataset(noisy_truth(5));
    let (ss, _, _) = pure_error_by_hand(&dataset);
    let result = calibrate(&motor(), &experiment(), &dataset, &Settings::default()).unwrap();
    assert_eq!(
        result.noise_source["w_rad_s"],
        "pure error of 12 replicated conditions (24 dof)"
    );
    let sd = result.noise["w_rad_s"].unwrap();
    assert!((sd - (ss / 24.0).sqrt()).abs() < 1e-12, "{sd}");
    assert!(
        result
            .summary()
            .contains("(pure error of 12 replicated conditions (24 dof))")
    );
}

#[test]
fn a_measured_cell_too_large_to_square_names_its_row_and_column() {
    let experiment = experiment();
    let csv = file("models/examples/geared_motor/data/steady.csv");
    // Line 10 is the row at 12 V without the brake.
    let text = csv.text().replace("12,,10.6648", "12,,1.797e308");
    let dataset = data::read("d.csv", &text, &experiment).unwrap();
    let error = discover::discover(
        &motor(),
        &experiment,
        &dataset,
        &library(),
        &Settings::default(),
    )
    .expect_err("cannot be fitted");
    let message = error.to_string();
    match error {
        DiscoverError::Unfittable {
            file,
            row,
            column,
            value,
            ..
        } => {
            assert_eq!((file.as_str(), row), ("d.csv", 10), "{message}");
            assert_eq!(column.as_deref(), Some("w_rad_s"), "{message}");
            assert_eq!(value, Some(1.797e308));
        }
        other => panic!("{other:?}"),
    }
    assert!(
        message.starts_with("d.csv:10: `w_rad_s` = 1.797e308 cannot be fitted"),
        "{message}"
    );
}

#[test]
fn a_drive_that_overflows_the_prediction_names_the_condition_column() {
    // At 1e160 V, from the model file's values (K = 0.04, b = 0.02, N = 20, R_a = 2), the
    // motor turns at (N K/R_a) V/(b + N^2 K^2/R_a) = 0.4 V/0.34 = 1.18e160 rad/s: it
    // settles, but its residual's square overflows. The cell to blame is the voltage, the
    // largest drive of the row.
    let experiment = experiment();
    let csv = file("models/examples/geared_motor/data/steady.csv");
    let text = csv.text().replace("\n12,,10.6648", "\n1e160,,10.6648");
    let dataset = data::read("e.csv", &text, &experiment).unwrap();
    let error = calibrate(&motor(), &experiment, &dataset, &Settings::default())
        .expect_err("cannot be fitted");
    let message = error.to_string();
    match error {
        DiscoverError::Unfittable {
            row, column, value, ..
        } => {
            assert_eq!(row, 10, "{message}");
            assert_eq!(column.as_deref(), Some("V_V"), "{message}");
            assert_eq!(value, Some(1e160));
        }
        other => panic!("{other:?}"),
    }
    assert!(
        message.starts_with("e.csv:10: `V_V` = 1e160: the model predicts `w_rad_s` = 1.176471e160"),
        "{message}"
    );
}

#[test]
fn a_declared_noise_is_used_and_tests_the_base_model() {
    // steady.csv against a declared 0.05 rad/s: the base model's SSE = 22 rmse_fit^2 is a
    // chi-square on 22 - 4 = 18 dof if the model is right.
    let text = file("models/examples/geared_motor/experiment.ron")
        .text()
        .replace("kind: Steady,", "kind: Steady,\n    noise: 0.05,");
    let experiment = Experiment::parse("experiment.ron", &text).unwrap();
    let csv = file("models/examples/geared_motor/data/steady.csv");
    let dataset = data::read("steady.csv", csv.text(), &experiment).unwrap();
    let discovery = discover::discover(
        &motor(),
        &experiment,
        &dataset,
        &library(),
        &Settings::default(),
    )
    .unwrap();
    assert_eq!(discovery.noise[0], Some(0.05));
    assert_eq!(discovery.noise_source[0], "declared in the experiment");
    let chi2 = 22.0 * discovery.baseline.rmse_fit.powi(2) / 0.0025;
    let test = discovery.lack_of_fit.as_ref().expect("a test");
    assert_eq!(test.dof, [18]);
    assert!(
        (test.statistic - chi2).abs() < 1e-9 * chi2,
        "{test:?} {chi2}"
    );
    assert!((test.p_value - stats::chi_square_survival(chi2, 18.0)).abs() < 1e-12);
    // The data's noise is 0.05 rad/s on 19 of the 22 rows: no misfit beyond it.
    assert!(test.p_value > 0.01, "{}", discovery.summary());
}
