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
    let noise = result.noise["w_rad_s"].expect("a noise level");
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

/// A file named by its full path, so that what it names relative to itself (an experiment's
/// scenario) is found from any working folder.
fn file_at(relative: &str) -> std::sync::Arc<SourceFile> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).unwrap();
    SourceFile::new(path.display().to_string(), text)
}

fn step_experiment() -> Experiment {
    Experiment::from_source(&file_at("models/examples/geared_motor/experiment_step.ron")).unwrap()
}

fn step_data(experiment: &Experiment, name: &str) -> data::Dataset {
    let csv = file_at(&format!("models/examples/geared_motor/data/{name}"));
    data::read(csv.name(), csv.text(), experiment).unwrap()
}

/// The truth behind data/generate_step.py (an independent Runge-Kutta integration of the
/// motor's two equations with its friction's switches located by bisection).
const STEP_TRUTH: [(&str, f64); 5] = [
    ("K", 0.05),
    ("b", 0.05),
    ("T_C", 0.15),
    ("T_S", 0.3),
    ("J", 0.01),
];

#[test]
fn a_time_series_without_noise_is_calibrated_back_to_its_known_values() {
    // The motor from rest, driven by a recorded voltage (0, 6, 12, 0, 9 V) against a
    // recorded brake (1 N m from 0.7 s to 1 s, 0.5 N m from 1.8 s): it breaks away, settles,
    // stops and sticks, and breaks away again. From the model file's values
    // (K = 0.04, b = 0.02, T_C = 0.2, T_S = 0.25, J = 0.01) the fit must find the truth,
    // the inertia and the breakaway torque included, which steady speeds cannot give: the
    // data are rounded to 1e-6 rad/s, so the fit's RMSE is of that order, not more.
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let dataset = step_data(&experiment, "step_exact.csv");
    assert_eq!(dataset.rows.len(), 201);
    let result = calibrate(&model, &experiment, &dataset, &Settings::default()).unwrap();
    let report = result.summary();
    for (name, truth) in STEP_TRUTH {
        let value = result.params[name].value;
        assert!(
            (value - truth).abs() < 1e-4 * truth,
            "{name} = {value} against {truth}\n{report}"
        );
    }
    assert!(result.rmse["w_rad_s"] < 2e-6, "{report}");
    // The regimes along the run: stuck before the first breakaway (t < 0.0421 s, five
    // samples from 0 to 0.04 s) and while stopped (1.0558 s to 1.4917 s, the 44 samples
    // from 1.06 to 1.49 s), turning otherwise.
    let stuck = result.residuals["w_rad_s"]
        .by_regime
        .iter()
        .find(|r| r.regime == "stuck")
        .expect("a stuck regime");
    assert_eq!(stuck.rows, 5 + 44, "{report}");
}

#[test]
fn each_file_of_a_time_series_is_its_own_run() {
    // The same record twice, as two files: two runs from rest, each restarting at t = 0. Read
    // as one run its times would go back; read as two, the fit is the one-file fit.
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let one = step_data(&experiment, "step_exact.csv");
    let mut other = one.clone();
    other.name = "again.csv".into();
    let again: std::sync::Arc<str> = "again.csv".into();
    for row in &mut other.rows {
        row.file = again.clone();
    }
    let both = data::Dataset::join(vec![one, other]);
    let result = calibrate(&model, &experiment, &both, &Settings::default()).unwrap();
    assert_eq!(result.rows, 402);
    for (name, truth) in STEP_TRUTH {
        let value = result.params[name].value;
        assert!((value - truth).abs() < 1e-4 * truth, "{name} = {value}");
    }
}

#[test]
fn a_bounded_prediction_of_a_time_series_stops_after_the_run_that_settles_it() {
    // Two runs: the motor's record, and a record whose time goes back, which cannot be
    // simulated. Asked in an order that starts with the good run's rows, a prediction that
    // has enough after the first row hands over only that run's rows and never reaches the
    // bad run; asked to the end, it hands over every row of the good run, each what a whole
    // prediction gives it, and then fails on the bad run.
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let good = step_data(&experiment, "step_exact.csv");
    let bad = data::read(
        "back.csv",
        "t_s,V_V,tau_mNm,w_rad_s\n0,0,0,0\n0.02,6,0,0\n0.01,6,0,1\n",
        &experiment,
    )
    .unwrap();
    let rows = data::Dataset::join(vec![bad, good.clone()]).rows;
    let loaded = bondgraph_ron::model::load_source(&model).unwrap();
    let predictor = bondgraph_fit::predict::Predictor::new(loaded, &model, &experiment).unwrap();
    let names: Vec<String> = STEP_TRUTH.iter().map(|(n, _)| n.to_string()).collect();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set(&STEP_TRUTH.map(|(_, v)| v));
    let whole = evaluator.predict_each(&good.rows);
    // The good run's rows, last first, then the bad run's.
    let order: Vec<usize> = (3..rows.len()).rev().chain(0..3).collect();
    let mut handed = Vec::new();
    assert!(evaluator.predict_until(&rows, &order, |i, _| {
        handed.push(i);
        true
    }));
    assert_eq!(handed, [rows.len() - 1]);
    let mut handed = Vec::new();
    let predicted = evaluator.predict_until(&rows, &order, |i, prediction| {
        assert_eq!(
            prediction.observed,
            whole[i - 3].as_ref().unwrap().observed,
            "row {i}"
        );
        handed.push(i);
        false
    });
    assert!(
        !predicted,
        "the run whose time goes back cannot be predicted"
    );
    assert_eq!(handed, order[..good.rows.len()]);
}

#[test]
fn a_time_series_at_a_breakaway_below_the_coulomb_torque_fails_before_simulating() {
    // The motor's bearings with their breakaway torque T_S below their Coulomb torque T_C:
    // at rest under a drive between the two they can neither hold nor slide, which a run
    // would find only at its first breakaway ("no mode is consistent"). The trial fails
    // as inconsistent, naming the contact and both values, for every way of predicting it.
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let good = step_data(&experiment, "step_exact.csv");
    let loaded = bondgraph_ron::model::load_source(&model).unwrap();
    let predictor = bondgraph_fit::predict::Predictor::new(loaded, &model, &experiment).unwrap();
    let names: Vec<String> = STEP_TRUTH.iter().map(|(n, _)| n.to_string()).collect();
    let t_s = names.iter().position(|n| n == "T_S").unwrap();
    let t_c = names.iter().position(|n| n == "T_C").unwrap();
    let mut values = STEP_TRUTH.map(|(_, v)| v);
    values[t_s] = 0.5 * values[t_c];
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set(&values);
    assert!(evaluator.predict_all(&good.rows).is_none());
    let order: Vec<usize> = (0..good.rows.len()).collect();
    assert!(!evaluator.predict_until(&good.rows, &order, |_, _| false));
    let trials = evaluator.trials();
    assert_eq!(trials.trials, 2);
    let failed = &trials.failed[&bondgraph_fit::budget::Failure::Inconsistent];
    assert_eq!(failed.count, 2);
    let expected = format!(
        "friction contact 'bearings': its breakaway level {} is below its Coulomb level {}",
        values[t_s], values[t_c]
    );
    assert!(failed.first.contains(&expected), "{}", failed.first);
    let each = evaluator.predict_each(&good.rows);
    assert!(
        each.iter()
            .all(|p| p.as_ref().is_err_and(|e| e.to_string().contains(&expected)))
    );
}

#[test]
fn a_negative_coulomb_torque_is_named_before_simulating() {
    // The motor's bearings with T_C = -0.1 N m (a fit's bounds may allow it where the model
    // file does not): a recorded run fails before any simulation, counted as
    // inconsistent, the message naming the contact and the value.
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let run = step_data(&experiment, "step_exact.csv");
    let loaded = bondgraph_ron::model::load_source(&model).unwrap();
    let predictor = bondgraph_fit::predict::Predictor::new(loaded, &model, &experiment).unwrap();
    let names: Vec<String> = STEP_TRUTH.iter().map(|(n, _)| n.to_string()).collect();
    let t_c = names.iter().position(|n| n == "T_C").unwrap();
    let mut values = STEP_TRUTH.map(|(_, v)| v);
    values[t_c] = -0.1;
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set(&values);
    assert!(evaluator.predict_all(&run.rows).is_none());
    let failed = &evaluator.trials().failed[&bondgraph_fit::budget::Failure::Inconsistent];
    assert_eq!(failed.count, 1);
    assert!(
        failed
            .first
            .contains("friction contact 'bearings': its Coulomb level -0.1 is negative"),
        "{}",
        failed.first
    );
}

#[test]
fn a_time_series_at_a_load_dependent_breakaway_below_its_coulomb_force_fails_before_simulating() {
    // The actuator's guide with friction growing with the load force (its extension
    // `load-dependent-friction`): breakaway F_S + mu_L F_L, Coulomb F_C + mu_L F_L. Each
    // level reads the measured load, but their difference F_S - F_C does not: with F_S 4 N
    // below F_C the contact is inconsistent at any load, and a trial there fails before
    // simulating, naming the contact and the 4 N.
    use bondgraph_ron::extension::{Extension, merge};
    let base = file_at("models/examples/actuator/actuator.ron");
    let extension = Extension::load(&file_at(
        "models/examples/actuator/extensions/load-dependent-friction.ron",
    ))
    .unwrap();
    let merged = merge(&base, &[extension]).unwrap();
    let model = merged.load().unwrap();
    let experiment =
        Experiment::from_source(&file_at("models/examples/actuator/experiment_step.ron")).unwrap();
    let csv = file_at("models/examples/actuator/data/step_1.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    let predictor =
        bondgraph_fit::predict::Predictor::new(model, &merged.file, &experiment).unwrap();
    let names: Vec<String> = ["F_C", "F_S", "mu_L"].map(String::from).to_vec();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    evaluator.set(&[10.0, 6.0, 0.2]);
    assert!(evaluator.predict_all(&dataset.rows).is_none());
    let trials = evaluator.trials();
    let failed = &trials.failed[&bondgraph_fit::budget::Failure::Inconsistent];
    assert_eq!(failed.count, 1);
    assert!(
        failed
            .first
            .contains("friction contact 'guide': its breakaway level is below its Coulomb level by 4 at any input"),
        "{}",
        failed.first
    );
    // With the breakaway level above the Coulomb level the run is simulated.
    evaluator.set(&[10.0, 15.0, 0.2]);
    assert!(evaluator.predict_all(&dataset.rows).is_some());
}

#[test]
fn a_time_series_whose_time_goes_back_names_the_row() {
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment = step_experiment();
    let dataset = data::read(
        "back.csv",
        "t_s,V_V,tau_mNm,w_rad_s\n0,0,0,0\n0.02,6,0,0\n0.01,6,0,1\n",
        &experiment,
    )
    .unwrap();
    let error = calibrate(&model, &experiment, &dataset, &Settings::default())
        .expect_err("time goes back")
        .to_string();
    assert!(
        error.starts_with(
            "back.csv:4: V_V = 6, tau_mNm = 0: time `t_s` must increase from row to row"
        ),
        "{error}"
    );
}

#[test]
fn a_time_series_scenario_that_edits_the_model_is_refused_at_the_experiment() {
    let dir = std::env::temp_dir().join(format!("bondgraph-ts-edit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("edited.ron"),
        r#"Scenario(name: "edited", parameters: {"R_a": 3.0},
    inputs: {"tau_load": Constant(0.0)}, duration: 1.0, record: ["flow:load_inertia"])"#,
    )
    .unwrap();
    let path = dir.join("experiment.ron");
    let text = step_experiment()
        .source()
        .text()
        .replace("\"step.ron\"", "\"edited.ron\"");
    std::fs::write(&path, &text).unwrap();
    let experiment =
        Experiment::from_source(&SourceFile::new(path.display().to_string(), text.clone()))
            .unwrap();
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let dataset = step_data(&experiment, "step_exact.csv");
    let error = calibrate(&model, &experiment, &dataset, &Settings::default())
        .expect_err("the scenario edits the model")
        .to_string();
    // At the experiment's `kind`, where the scenario is named.
    let line = 1 + text
        .lines()
        .position(|l| l.contains("kind: TimeSeries"))
        .unwrap();
    assert!(
        error.contains(&format!("experiment.ron:{line}:")) && error.contains("edits the model"),
        "{error}"
    );
}

/// A fit that runs out of its budget of evaluations ends on the best point its searches found
/// by then; which points those are must not depend on how many threads run the searches side
/// by side, or a report (and a selection) would change from one run to the next. With a
/// budget of 60 evaluations (the geared motor's fit takes hundreds), one thread and four give
/// the same estimates and the same number of evaluations, and both say the budget was spent.
#[test]
fn a_fit_cut_short_by_its_budget_is_the_same_on_any_number_of_threads() {
    let model = file("models/examples/geared_motor/geared_motor.ron");
    let experiment =
        Experiment::from_source(&file("models/examples/geared_motor/experiment.ron")).unwrap();
    let csv = file("models/examples/geared_motor/data/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    let mut settings = Settings::default();
    settings.budget.evaluations = 60;
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| calibrate(&model, &experiment, &dataset, &settings).unwrap())
    };
    let one = on(1);
    assert!(
        one.failed_trials
            .iter()
            .any(|f| f.text.contains("budget of 60 evaluations")),
        "{:?}",
        one.failed_trials
    );
    for _ in 0..3 {
        let four = on(4);
        assert_eq!(four.evaluations, one.evaluations);
        for (name, estimate) in &one.params {
            assert_eq!(
                four.params[name].value.to_bits(),
                estimate.value.to_bits(),
                "{name}: {} on four threads, {} on one",
                four.params[name].value,
                estimate.value
            );
        }
    }
}

/// Continuing steady states to nearby trial values ([`bondgraph_fit::budget::Budget::continuation`])
/// changes no conclusion: the two-tank rig calibrated on nine rows of its noise-free
/// reference (scipy, `data/generate.py`: R_12 = 8e6 Pa s/m^3, c_d = 2.2e-6 m^3/(s Pa^(1/2)),
/// written to four decimals) finds the truth with it and without it, the two values far
/// inside their standard error of each other (R_12 and c_d both at 5 % of theirs).
#[test]
fn continued_steady_states_change_no_conclusion() {
    use bondgraph_fit::budget::Budget;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let read = |relative: &str| std::fs::read_to_string(root.join(relative)).unwrap();
    let model = SourceFile::new(
        "two_tank.ron",
        read("models/examples/two_tank/two_tank.ron"),
    );
    let experiment = Experiment::parse(
        "experiment.ron",
        &read("models/examples/two_tank/experiment.ron"),
    )
    .unwrap();
    let text = read("models/examples/two_tank/data/steady_exact.csv");
    let subset: String = text
        .lines()
        .enumerate()
        .filter(|(k, _)| *k == 0 || k % 3 == 1)
        .map(|(_, line)| format!("{line}\n"))
        .collect();
    let dataset = data::read("steady_exact.csv", &subset, &experiment).unwrap();
    assert_eq!(dataset.rows.len(), 9);
    let fit = |continuation: f64| {
        let settings = Settings {
            budget: Budget {
                continuation,
                ..Budget::default()
            },
            ..Settings::default()
        };
        calibrate(&model, &experiment, &dataset, &settings).unwrap()
    };
    let (continued, simulated) = (fit(Budget::default().continuation), fit(0.0));
    for (name, truth) in [("R_12", 8e6), ("c_d", 2.2e-6)] {
        let (a, b) = (continued.params[name].value, simulated.params[name].value);
        assert!((a - truth).abs() < 1e-5 * truth, "{name} = {a}");
        // The descents differ by the rounding of the differenced steady states (each
        // equilibrium polished to 1e-12 of its scale, differenced over 1e-5 of the range):
        // where each stops, at a decrease of the sum of squares below 1e-9 of it, is a hair
        // apart.
        let error = continued.params[name].std_error.unwrap();
        assert!(
            (a - b).abs() < 0.1 * error,
            "{name}: {a} continued, {b} simulated, standard error {error}"
        );
    }
}

/// Refits on part of the rows continued from the whole fit's steady states
/// ([`bondgraph_fit::budget::Budget::refit_continuation`]) change no conclusion: on the
/// two-tank rig's steady sweep with a leak in tank 1 hidden (scipy, `data/generate.py`,
/// G_l = 2e-9 m^3/(s Pa)), `discover` with the two leaks as candidates selects the same one
/// with it and without it, every verdict and every resample's selection the same, and every
/// held-out RMSE (scored on rows simulated either way) within 1e-6 of each other, against a
/// gain from the leak of a fifth.
#[test]
fn refits_continued_from_the_whole_fit_change_no_conclusion() {
    use bondgraph_fit::budget::Budget;
    use bondgraph_fit::discover::{Candidate, discover};
    use bondgraph_ron::extension::Extension;
    let model = file("models/examples/two_tank/two_tank.ron");
    let experiment = Experiment::parse(
        "experiment.ron",
        file("models/examples/two_tank/experiment.ron").text(),
    )
    .unwrap();
    let csv = file("models/examples/two_tank/data/hidden/tank-1-leak/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    let candidates: Vec<Candidate> = ["tank-1-leak", "tank-2-leak"]
        .iter()
        .map(|id| {
            let source = file(&format!("models/examples/two_tank/extensions/{id}.ron"));
            Candidate::new(&model, &Extension::load(&source).unwrap()).unwrap()
        })
        .collect();
    // As many resamples both ways (by default their number follows their cost, which the
    // continuation lowers).
    let run = |refit_continuation: f64| {
        let settings = Settings {
            budget: Budget {
                refit_continuation,
                ..Budget::default()
            },
            resampling: bondgraph_fit::discover::Resampling {
                count: Some(12),
                ..Default::default()
            },
            ..Settings::default()
        };
        discover(&model, &experiment, &dataset, &candidates, &settings).unwrap()
    };
    let (continued, simulated) = (run(Budget::default().refit_continuation), run(0.0));
    let report = continued.summary();
    assert_eq!(
        continued.selected.as_deref(),
        Some("tank-1-leak"),
        "{report}"
    );
    assert_eq!(continued.selected, simulated.selected);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * b.abs();
    assert!(close(
        continued.baseline.rmse_heldout,
        simulated.baseline.rmse_heldout
    ));
    for (a, b) in continued.ranking.iter().zip(&simulated.ranking) {
        assert_eq!((&a.id, &a.verdict), (&b.id, &b.verdict), "{report}");
        assert!(
            close(a.rmse_heldout, b.rmse_heldout),
            "{}: {} continued, {} simulated",
            a.id,
            a.rmse_heldout,
            b.rmse_heldout
        );
    }
    let selected = &continued.ranking[0];
    assert!(selected.rmse_heldout < 0.8 * continued.baseline.rmse_heldout);
    let counts = |d: &bondgraph_fit::discover::Discovery| {
        d.stability.as_ref().map(|s| s.selected_counts.clone())
    };
    assert!(counts(&continued).is_some());
    assert_eq!(counts(&continued), counts(&simulated));
}

/// Each of `continued`'s estimates within a tenth of its standard error of `simulated`'s, or,
/// for a threshold without one, `simulated`'s value within its interval of equally good
/// values; `report` is shown on failure.
fn assert_same_estimates(
    continued: &std::collections::BTreeMap<String, bondgraph_fit::discover::Estimate>,
    simulated: &std::collections::BTreeMap<String, bondgraph_fit::discover::Estimate>,
    report: &str,
) {
    for (name, estimate) in continued {
        let other = &simulated[name];
        match (estimate.std_error, estimate.interval) {
            (Some(error), _) => assert!(
                (estimate.value - other.value).abs() < 0.1 * error,
                "{name}: {} continued, {} simulated, standard error {error}",
                estimate.value,
                other.value
            ),
            (None, Some((low, high))) => assert!(
                (low..=high).contains(&other.value),
                "{name}: {} simulated, outside [{low}, {high}]",
                other.value
            ),
            (None, None) => panic!("{name}: neither an error nor an interval\n{report}"),
        }
    }
}

/// Continuing path-dependent steady states for a Jacobian's differences only
/// ([`bondgraph_fit::predict::Evaluator::predict_differenced`]) changes no conclusion: the
/// lead-screw actuator's steady sweep with the brushes' voltage drop hidden (scipy,
/// `data/generate.py`: U_b = 0.25 V), where every mode of the extended model has a guard (the
/// guide's breakaway, its stop) and so every row's equilibrium is path-dependent. With the
/// brush drop as the only candidate, `discover` selects it with and without continuation,
/// each fitted value within a tenth of its standard error of the other (the breakaway force,
/// which no difference moves, within the interval of values that fit as well), and `U_b`
/// within three standard errors of the truth.
#[test]
fn differences_continued_on_their_branch_change_no_conclusion() {
    use bondgraph_fit::budget::Budget;
    use bondgraph_fit::discover::{Candidate, Resampling, discover};
    use bondgraph_ron::extension::Extension;
    let model = file("models/examples/actuator/actuator.ron");
    let experiment = Experiment::parse(
        "experiment.ron",
        file("models/examples/actuator/experiment.ron").text(),
    )
    .unwrap();
    let csv = file("models/examples/actuator/data/hidden/brush-voltage-drop/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    let source = file("models/examples/actuator/extensions/brush-voltage-drop.ron");
    let candidates = vec![Candidate::new(&model, &Extension::load(&source).unwrap()).unwrap()];
    let run = |continuation: f64| {
        let settings = Settings {
            budget: Budget {
                continuation,
                ..Budget::default()
            },
            resampling: Resampling {
                count: Some(0),
                ..Default::default()
            },
            ..Settings::default()
        };
        discover(&model, &experiment, &dataset, &candidates, &settings).unwrap()
    };
    let (continued, simulated) = (run(Budget::default().continuation), run(0.0));
    let report = continued.summary();
    assert_eq!(
        continued.selected.as_deref(),
        Some("brush-voltage-drop"),
        "{report}"
    );
    assert_eq!(continued.selected, simulated.selected);
    let (a, b) = (&continued.ranking[0].params, &simulated.ranking[0].params);
    assert_same_estimates(a, b, &report);
    let u_b = &a["U_b"];
    assert!(
        (u_b.value - 0.25).abs() < 3.0 * u_b.std_error.unwrap(),
        "{report}"
    );
}

/// The same sweep calibrated with the actuator extended by the brush drop: every row's
/// equilibrium is path-dependent, so a fit continues rows only for its differences, from
/// the values each was simulated at. With continuation (the default) the fit's trials
/// continue rows, with `continuation = 0` none, and both end at the same optimum: every
/// fitted value within a tenth of its standard error of the other's (the breakaway force,
/// which no difference moves, within the other's interval), the same RMSE to 1e-6.
#[test]
fn a_calibration_continues_path_dependent_rows_for_its_differences_only() {
    use bondgraph_ron::extension::{Extension, merge};
    let base = file("models/examples/actuator/actuator.ron");
    let extension = Extension::load(&file(
        "models/examples/actuator/extensions/brush-voltage-drop.ron",
    ))
    .unwrap();
    let merged = merge(&base, &[extension]).unwrap();
    let text = file("models/examples/actuator/experiment.ron")
        .text()
        .replace(
            r#"fitted: ["K", "b", "F_C", "F_S"]"#,
            r#"fitted: ["K", "b", "F_C", "F_S", "U_b"]"#,
        );
    let experiment = Experiment::parse("experiment.ron", &text).unwrap();
    assert!(experiment.fitted.iter().any(|name| name == "U_b"));
    let csv = file("models/examples/actuator/data/hidden/brush-voltage-drop/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    assert_continuation_changes_no_calibration(&merged.file, &experiment, &dataset);
}

/// The actuator's base model on its own sweep (scipy, `data/generate.py`): every mode is
/// linear and guarded (the guide's breakaway, its stop), its speed and current read none of
/// the modes' integrators, so each row's asymptote is a path-dependent anchor and a fit
/// continues it for its differences only. With continuation (the default) rows are
/// continued, with `continuation = 0` none, and both end at the same optimum (each value
/// within a tenth of its standard error of the other's, or inside the other's interval; the
/// same RMSE to 1e-6).
#[test]
fn a_calibration_continues_linear_asymptotes_for_its_differences_only() {
    let model = file("models/examples/actuator/actuator.ron");
    let experiment = Experiment::parse(
        "experiment.ron",
        file("models/examples/actuator/experiment.ron").text(),
    )
    .unwrap();
    let csv = file("models/examples/actuator/data/steady.csv");
    let dataset = data::read(csv.name(), csv.text(), &experiment).unwrap();
    assert_continuation_changes_no_calibration(&model, &experiment, &dataset);
}

/// `calibrate` of `model` on `dataset` with continuation (the default) continues rows, with
/// `continuation = 0` none, and both end at the same optimum: every fitted value within a
/// tenth of its standard error of the other's (a threshold no difference moves within the
/// other's interval), the same RMSE to 1e-6.
fn assert_continuation_changes_no_calibration(
    model: &std::sync::Arc<bondgraph_core::source::SourceFile>,
    experiment: &Experiment,
    dataset: &data::Dataset,
) {
    use bondgraph_fit::budget::Budget;
    let run = |continuation: f64| {
        let settings = Settings {
            budget: Budget {
                continuation,
                ..Budget::default()
            },
            ..Settings::default()
        };
        calibrate(model, experiment, dataset, &settings).unwrap()
    };
    let (continued, simulated) = (run(Budget::default().continuation), run(0.0));
    assert!(continued.continued_rows > 0, "no row was continued");
    assert_eq!(simulated.continued_rows, 0);
    assert_same_estimates(&continued.params, &simulated.params, "");
    for (column, rmse) in &continued.rmse {
        let other = simulated.rmse[column];
        assert!(
            (rmse - other).abs() <= 1e-6 * other,
            "{column}: {rmse} against {other}"
        );
    }
}
