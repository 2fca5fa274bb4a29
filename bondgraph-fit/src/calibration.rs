//! Calibration of a model on measured data: the experiment's fitted parameters, their
//! standard errors (or, for a threshold, the interval of equally good values), and the
//! residuals by regime and along each condition (what `bondgraph calibrate` prints).
//!
//! The fit is a global search ([`crate::global`]) over the faces where friction thresholds
//! tie, started from the model file's values too. One observed column enters the sum of
//! squares in its own units; several enter it each divided by its noise ([`crate::weights`]):
//! declared, or the pure error of replicated conditions, else the residual of a first fit
//! that weighs each column by the spread of its values, after which the fit is made again,
//! locally, with those weights.

use std::collections::BTreeMap;
use std::sync::Arc;

use bondgraph_core::model;
use bondgraph_core::source::SourceFile;
use serde::Serialize;

use crate::data::Dataset;
use crate::discover::{
    self, DiscoverError, Estimate, Residuals, Settings, fit_best, fitted_parameters,
};
use crate::experiment::Experiment;
use crate::noise::{self, NoiseLevel};
use crate::predict::Predictor;

/// One row with its prediction.
#[derive(Clone, Debug, Serialize)]
pub struct CalibratedRow {
    /// The data file and line.
    pub file: String,
    /// Its line.
    pub row: usize,
    /// The condition cells, by column (`None`: empty).
    pub conditions: BTreeMap<String, Option<f64>>,
    /// The measured values, by observed column.
    pub measured: BTreeMap<String, f64>,
    /// The calibrated model's, by observed column.
    pub predicted: BTreeMap<String, f64>,
    /// The regime the row settles in.
    pub regime: String,
}

/// What a calibration finds.
#[derive(Clone, Debug, Serialize)]
pub struct Calibration {
    /// The data's name.
    pub data: String,
    /// The model's name.
    pub model: String,
    /// Rows fitted.
    pub rows: usize,
    /// The fitted parameters.
    pub params: BTreeMap<String, Estimate>,
    /// The root-mean-square residual of each observed column, in its units.
    pub rmse: BTreeMap<String, f64>,
    /// The noise the residuals are judged against, per observed column ([`crate::noise`]):
    /// the experiment's declared `noise`, else the pure error of replicated conditions
    /// (steady data), else the residuals' own standard deviation (`SSE/(n - p)`); `None`
    /// when the data cannot estimate it (an exact fit).
    pub noise: BTreeMap<String, Option<f64>>,
    /// Where each column's `noise` came from, as a phrase.
    pub noise_source: BTreeMap<String, String>,
    /// Whether `noise` is the experiment's declared one.
    pub noise_declared: bool,
    /// Residuals by regime and along each condition, per observed column.
    pub residuals: BTreeMap<String, Residuals>,
    /// Every row.
    pub table: Vec<CalibratedRow>,
    /// Forward-model evaluations used.
    pub evaluations: usize,
    /// Trial predictions of the fit that failed or ran out of their budget, by reason.
    pub failed_trials: Vec<crate::budget::FailedTrials>,
    /// Steady rows the fit's trials continued from a steady state simulated before instead
    /// of simulating them again ([`crate::budget::Trials::continued_rows`]).
    pub continued_rows: usize,
}

/// Calibrates the model in `source` on `data` (read against `experiment`).
///
/// # Errors
/// When the model or the experiment does not load or fit together (located diagnostics), a
/// fitted parameter is unknown or unbounded, or the model cannot be evaluated at the start
/// (naming the row).
pub fn calibrate(
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    data: &Dataset,
    settings: &Settings,
) -> Result<Calibration, DiscoverError> {
    let model = bondgraph_ron::model::load_source(source)?;
    let rows = &data.rows;
    let (names, bounds, file_start) = fitted_parameters(&model, experiment, rows, &[])?;
    let predictor = Predictor::new(model.clone(), source, experiment)?;
    let mut evaluator = predictor.evaluator(&names)?;
    discover::limit_to_budget(&mut evaluator, settings);
    let orderings = crate::global::orderings(&model, &names);
    let mut trials = crate::budget::Trials::default();
    let fit = if experiment.observed.len() == 1 {
        let fit = fit_best(
            &mut evaluator,
            rows,
            None,
            &[&file_start],
            &bounds,
            (&orderings, &settings.search),
            settings,
        )?
        .fit;
        trials.merge(&evaluator.trials());
        fit
    } else {
        weighted_fit(
            &model,
            source,
            experiment,
            rows,
            (&names, &bounds, &file_start),
            (&orderings, &mut trials),
            settings,
        )?
    };
    let failed_trials = crate::budget::failed_trials(model.name(), &trials, &settings.budget);
    evaluator.set(&fit.values);
    let predictions = evaluator.predict(rows)?;
    let observed = &experiment.observed;
    let m = observed.len();
    let n = rows.len();
    let free = fit
        .intervals
        .iter()
        .zip(&fit.at_bound)
        .filter(|(i, b)| i.is_none() && !**b)
        .count();
    let regimes: Vec<String> = predictions
        .iter()
        .map(|p| experiment.regime(&p.mode))
        .collect();
    let mut rmse = BTreeMap::new();
    let mut noise = BTreeMap::new();
    let mut noise_source = BTreeMap::new();
    let mut residuals = BTreeMap::new();
    for (k, column) in observed.iter().enumerate() {
        let predicted: Vec<f64> = predictions.iter().map(|p| p.observed[k]).collect();
        let sse: f64 = predicted
            .iter()
            .zip(rows)
            .map(|(p, r)| (p - r.observed[k]).powi(2))
            .sum();
        // Rows of a time series at the same conditions are samples of a run, not replicates.
        let replicates = crate::weights::replicates(experiment, rows, k);
        let level = NoiseLevel::estimate(
            experiment.declared_noise(k),
            replicates,
            noise::Residual {
                sse,
                dof: n as f64 - free as f64 / m as f64,
                model: "the calibrated model",
                scale: noise::root_mean_square(rows, k),
            },
        );
        let sd = level.sd;
        rmse.insert(column.column.clone(), (sse / n as f64).sqrt());
        noise.insert(column.column.clone(), sd);
        noise_source.insert(column.column.clone(), level.source);
        residuals.insert(
            column.column.clone(),
            discover::residuals(experiment, k, rows, &predicted, &regimes, sd),
        );
    }
    let table = rows
        .iter()
        .zip(&predictions)
        .zip(&regimes)
        .map(|((r, p), regime)| CalibratedRow {
            file: r.file.to_string(),
            row: r.row,
            conditions: data
                .conditions
                .iter()
                .cloned()
                .zip(r.conditions.iter().copied())
                .collect(),
            measured: observed
                .iter()
                .map(|o| o.column.clone())
                .zip(r.observed.iter().copied())
                .collect(),
            predicted: observed
                .iter()
                .map(|o| o.column.clone())
                .zip(p.observed.iter().copied())
                .collect(),
            regime: regime.clone(),
        })
        .collect();
    let params = names
        .iter()
        .enumerate()
        .map(|(j, name)| {
            (
                name.clone(),
                Estimate {
                    value: fit.values[j],
                    std_error: fit.std_errors[j],
                    interval: fit.intervals[j],
                    at_bound: fit.at_bound[j],
                },
            )
        })
        .collect();
    Ok(Calibration {
        data: data.name.clone(),
        model: model.name().to_string(),
        rows: n,
        params,
        rmse,
        noise,
        noise_source,
        noise_declared: !experiment.noise.is_empty(),
        residuals,
        table,
        evaluations: fit.evaluations,
        failed_trials,
        continued_rows: trials.continued_rows,
    })
}

/// The fit of several observed columns, each divided by its noise ([`crate::weights`]): the
/// known ones (declared, pure error) at once; the others by a first fit weighted by each
/// column's spread, whose residuals give their noise, and a local refit weighted by it.
fn weighted_fit(
    model: &model::Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    rows: &[crate::data::Measurement],
    (names, bounds, file_start): (&[String], &[(f64, f64)], &[f64]),
    (orderings, trials): (&[crate::global::Ordering], &mut crate::budget::Trials),
    settings: &Settings,
) -> Result<crate::calibrate::Fit, DiscoverError> {
    use crate::weights;
    let m = experiment.observed.len();
    let known: Vec<Option<f64>> = (0..m)
        .map(|k| weights::known_level(experiment, rows, k).and_then(|l| l.sd))
        .collect();
    let scales: Vec<f64> = (0..m)
        .map(|k| known[k].unwrap_or_else(|| weights::spread(rows, k)))
        .collect();
    let mut fit_with = |scales: &[f64], starts: &[&[f64]], search: &crate::global::Search| {
        let (scaled_experiment, scaled_rows) = weights::scaled(experiment, rows, scales);
        let predictor = Predictor::new(model.clone(), source, &scaled_experiment)?;
        let mut evaluator = predictor.evaluator(names)?;
        discover::limit_to_budget(&mut evaluator, settings);
        let fit = fit_best(
            &mut evaluator,
            &scaled_rows,
            None,
            starts,
            bounds,
            (orderings, search),
            settings,
        )
        .map(|searched| searched.fit);
        trials.merge(&evaluator.trials());
        fit
    };
    let first = fit_with(&scales, &[file_start], &settings.search)?;
    if known.iter().all(Option::is_some) {
        return Ok(first);
    }
    // The columns' residual noise at the first fit, in their units.
    let predictor = Predictor::new(model.clone(), source, experiment)?;
    let mut evaluator = predictor.evaluator(names)?;
    discover::limit_to_budget(&mut evaluator, settings);
    evaluator.set(&first.values);
    let predicted: Vec<Vec<f64>> = evaluator
        .predict(rows)?
        .into_iter()
        .map(|p| p.observed)
        .collect();
    let free = first
        .intervals
        .iter()
        .zip(&first.at_bound)
        .filter(|(i, b)| i.is_none() && !**b)
        .count();
    let residual = weights::residual_sds(rows, &predicted, free);
    let scales: Vec<f64> = (0..m)
        .map(|k| {
            known[k].unwrap_or(if residual[k] > 0.0 && residual[k].is_finite() {
                residual[k]
            } else {
                scales[k]
            })
        })
        .collect();
    let mut refit = fit_with(&scales, &[&first.values], &crate::global::Search::LOCAL)?;
    refit.evaluations += first.evaluations;
    Ok(refit)
}

impl Calibration {
    /// A readable report: the values, the fit, and the residuals.
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}: model '{}' calibrated on {} rows ({} evaluations)",
            self.data, self.model, self.rows, self.evaluations
        );
        for (name, e) in &self.params {
            let _ = writeln!(s, "  {name} = {}", discover::estimate_text(e));
        }
        for (column, rmse) in &self.rmse {
            let source = &self.noise_source[column];
            let _ = match self.noise[column] {
                Some(sd) => writeln!(s, "\n`{column}`: RMSE {rmse:.4}; noise {sd:.4} ({source})"),
                None => writeln!(
                    s,
                    "\n`{column}`: RMSE {rmse:.4}; noise: {source} (no residual is judged \
                     against it)"
                ),
            };
            let _ = writeln!(s, "residuals (model minus measured):");
            discover::write_residuals(&mut s, &self.residuals[column]);
        }
        crate::budget::write_failed_trials(&mut s, &self.failed_trials);
        s
    }
}
