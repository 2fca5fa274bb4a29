//! Calibration of a second system, in another domain than the flagship: the geared motor of
//! `models/examples/geared_motor/`, on data made by an independent script from known values.

use std::path::PathBuf;

use bondgraph_core::source::SourceFile;
use bondgraph_fit::calibration::calibrate;
use bondgraph_fit::data;
use bondgraph_fit::discover::Settings;
use bondgraph_fit::experiment::Experiment;

fn file(relative: &str) -> std::sync::Arc<SourceFile> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    SourceFile::new(relative, std::fs::read_to_string(path).unwrap())
}

#[test]
fn the_geared_motor_is_calibrated_back_to_its_known_values() {
    // data/generate.py: K = 0.05 N m/A, b = 0.05 N m s/rad, T_C = 0.15 N m, T_S = 0.3 N m,
    // noise 0.05 rad/s; the model file starts the fit elsewhere (0.04, 0.02, 0.2, 0.25).
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment =
        Experiment::from_source(&file("models/examples/geared_motor/experiment.ron")).unwrap();
    let csv = file("models/examples/geared_motor/data/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    let result = calibrate(&model, &experiment, &dataset, &Settings::default()).unwrap();
    let report = result.summary();
    // The least-squares optimum of the turning rows' closed form, computed independently
    // (Gauss-Newton on w = (alpha V - T_C - tau)/(b + beta), alpha = N K/R_a,
    // beta = N^2 K^2/R_a, over the 19 turning rows): K = 0.0500352, b = 0.0508621,
    // T_C = 0.1345153, SSE = 0.0259653. Its standard errors are sqrt(sigma^2 (J^T J)^-1) with
    // sigma^2 = SSE/(22 - 3): the breakaway torque is a threshold (an interval, not a
    // smooth parameter) and takes no degree of freedom, as the module documents:
    // K +- 1.6246e-4, b +- 1.5760e-3, T_C +- 9.3045e-3. The calibration must land on that
    // optimum (within a fifth of a standard error) with those errors (to 1%), and the optimum
    // lies within four standard errors of the truth.
    for (name, truth, optimum, se) in [
        ("K", 0.05, 0.0500352, 1.6246e-4),
        ("b", 0.05, 0.0508621, 1.5760e-3),
        ("T_C", 0.15, 0.1345153, 9.3045e-3),
    ] {
        let estimate = &result.params[name];
        let value = estimate.value;
        assert!((value - optimum).abs() < 0.2 * se, "{name}\n{report}");
        assert!((value - truth).abs() < 4.0 * se, "{name}\n{report}");
        let error = estimate.std_error.expect("a standard error");
        assert!((error - se).abs() < 0.01 * se, "{name}: {error}\n{report}");
    }
    // The breakaway torque is a threshold: the data put it between the drives of the last
    // stalled row and the first turning one, alpha V with alpha = N K/R_a = 0.5 N m/V at
    // 0.5 V and 0.8 V: [0.25, 0.40] N m (scaled by the fitted K/0.05).
    let (lo, hi) = result.params["T_S"]
        .interval
        .expect("an interval\n{report}");
    let scale = result.params["K"].value / 0.05;
    assert!(
        (lo - 0.25 * scale).abs() < 0.005 && (hi - 0.40 * scale).abs() < 0.005,
        "{lo} {hi}\n{report}"
    );
    // The noise is recovered: the residuals' standard deviation near 0.05 rad/s (19 turning
    // rows with noise, 3 stalled without; four parameters).
    let noise = result.noise["w_rad_s"];
    assert!((0.025..0.08).contains(&noise), "{noise}\n{report}");
    let stalled = result.residuals["w_rad_s"]
        .by_regime
        .iter()
        .find(|r| r.regime == "stalled")
        .expect("a stalled regime");
    assert_eq!((stalled.rows, stalled.rmse), (3, 0.0));
}

#[test]
fn a_cell_the_model_cannot_evaluate_names_its_row_and_column() {
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment =
        Experiment::from_source(&file("models/examples/geared_motor/experiment.ron")).unwrap();
    let error = data::read("d.csv", "V_V,w_rad_s\n1.797e308,1\n", &experiment);
    // A factor of 1 keeps 1.797e308 V finite; the model cannot settle there.
    let dataset = error.unwrap();
    let rows = [dataset.rows.clone(), dataset.rows.clone()].concat();
    let dataset = data::Dataset { rows, ..dataset };
    let error = calibrate(&model, &experiment, &dataset, &Settings::default())
        .expect_err("cannot be evaluated")
        .to_string();
    assert!(
        error.starts_with("d.csv:2: V_V = 179700000000000000"),
        "{error}"
    );
}
