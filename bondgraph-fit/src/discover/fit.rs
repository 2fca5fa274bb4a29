//! Fitting one model on rows: the parameters to fit, the global search on all rows, and
//! the least-squares fit a fold or a calibration makes.

use std::collections::BTreeMap;
use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;

use super::summary::number;
use super::{DiscoverError, Estimate, Settings};
use crate::budget::Trials;
use crate::calibrate::{CalibrationError, Fit};
use crate::data::Measurement;
use crate::experiment::Experiment;
use crate::global::{self, Ordering, Search, Searched};
use crate::predict::{Anchors, Evaluator, Predictor};

/// A model fitted and cross-validated.
pub(super) struct Assessment {
    pub(super) names: Vec<String>,
    pub(super) fit: Fit,
    /// Each row's prediction of each observed column, row by row (`NaN`: no prediction).
    pub(super) predictions: Vec<f64>,
    pub(super) modes: Vec<String>,
    pub(super) heldout_sse: f64,
    /// Held-out residuals counted, every column of every row.
    pub(super) heldout_count: usize,
    /// Of `heldout_sse`, each observed column's part.
    pub(super) heldout_by_column: Vec<f64>,
    /// Of `heldout_sse`, each residual's part (the squares of every fold that held it out;
    /// `NaN` where none scored it), laid out the same for every model of one analysis (as
    /// `predictions`, for the folds of all the rows), so that they pair up across models.
    pub(super) heldout_cells: Vec<f64>,
    /// Predictions (held out, or of the final fit) that did not settle.
    pub(super) unsettled: usize,
    /// Predictions of every row made by the fit and the folds' refits.
    pub(super) evaluations: usize,
    /// Those trial predictions, and the ones that failed.
    pub(super) trials: Trials,
    /// The steady states of the fit's own prediction of every row, where they can be
    /// continued: where refits on part of the rows (folds, resamples), which start at the
    /// fit's optimum, start from instead of simulating every row again.
    pub(super) anchors: Anchors,
}

/// Limits an evaluator to the work `settings` give each prediction ([`Budget`]): how long
/// a row takes to settle is the model's own time scale
/// ([`bondgraph_solver::steady::SteadySettings`]), and what bounds it is work. `calibrate`
/// and `discover` predict every row under this one rule.
pub(crate) fn limit_to_budget(evaluator: &mut Evaluator<'_>, settings: &Settings) {
    evaluator.set_budget(&settings.budget);
}

impl Assessment {
    pub(super) fn rmse_fit(&self) -> f64 {
        (self.fit.sse / self.predictions.len() as f64).sqrt()
    }

    pub(super) fn rmse_heldout(&self) -> f64 {
        (self.heldout_sse / self.heldout_count.max(1) as f64).sqrt()
    }

    pub(super) fn estimates(&self) -> BTreeMap<String, Estimate> {
        self.names
            .iter()
            .enumerate()
            .map(|(j, name)| {
                (
                    name.clone(),
                    Estimate {
                        value: self.fit.values[j],
                        std_error: self.fit.std_errors[j],
                        interval: self.fit.intervals[j],
                        at_bound: self.fit.at_bound[j],
                    },
                )
            })
            .collect()
    }

    pub(super) fn aicc(&self) -> f64 {
        let n = self.predictions.len() as f64;
        let k = self.names.len() as f64;
        let sse = self.fit.sse.max(1e-300);
        n * (sse / n).ln() + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0).max(1.0)
    }
}

pub(crate) type FittedParameters = (Vec<String>, Vec<(f64, f64)>, Vec<f64>);

/// The names of the parameters to fit for `rows`, with their bounds and starting values.
pub(crate) fn fitted_parameters(
    model: &Model,
    experiment: &Experiment,
    rows: &[Measurement],
    own: &[String],
) -> Result<FittedParameters, DiscoverError> {
    let names = fitted_names(experiment, rows, own);
    let mut bounds = Vec::new();
    let mut start = Vec::new();
    for name in &names {
        let field = if experiment.fitted.contains(name) {
            "fitted"
        } else {
            "fitted_when_present"
        };
        let parameter = model
            .parameters()
            .iter()
            .find(|p| &p.name == name)
            .ok_or_else(|| {
                DiscoverError::Fitted(
                    experiment
                        .error(
                            bondgraph_core::DiagnosticKind::UnknownName,
                            field,
                            name,
                            format!(
                                "experiment: `{field}` names '{name}', which is not a parameter of model '{}'",
                                model.name()
                            ),
                        )
                        .into(),
                )
            })?;
        let b = parameter.bounds.ok_or_else(|| {
            DiscoverError::Fitted(
                experiment
                    .error(
                        bondgraph_core::DiagnosticKind::MissingField,
                        field,
                        name,
                        format!(
                            "experiment: parameter '{name}' of model '{}' is fitted but has no bounds",
                            model.name()
                        ),
                    )
                    .note("give it bounds in the model file: bounds: (low, high)")
                    .into(),
            )
        })?;
        bounds.push(b);
        start.push(parameter.value);
    }
    Ok((names, bounds, start))
}

/// The parameters fitted on `rows`: the experiment's `fitted`, those of `fitted_when_present`
/// whose column has a value in some row, then `own` (a candidate's).
pub fn fitted_names(experiment: &Experiment, rows: &[Measurement], own: &[String]) -> Vec<String> {
    let columns = experiment.condition_columns();
    let mut names: Vec<String> = experiment.fitted.clone();
    for (column, parameters) in &experiment.fitted_when_present {
        let k = columns.iter().position(|c| c == column);
        if k.is_some_and(|k| rows.iter().any(|r| r.conditions[k].is_some())) {
            for name in parameters {
                if !names.contains(name) {
                    names.push(name.clone());
                }
            }
        }
    }
    names.extend(own.iter().cloned());
    names
}

/// The base model's fitted parameters and the basins its search found (its optimum first):
/// where a candidate's fit starts.
type Warm<'a> = Option<(&'a [String], &'a [Vec<f64>])>;

/// A model fitted on every row, with what its cross-validation needs: the bounds, and the
/// basins the search found (a fold's fit starts from each).
pub(super) struct FittedOnAll {
    pub(super) assessment: Assessment,
    pub(super) bounds: Vec<(f64, f64)>,
    pub(super) orderings: Vec<Ordering>,
    pub(super) basins: Vec<Vec<f64>>,
}

/// Fits `model` on all `rows`: its own parameters `own` with the experiment's, by a global
/// search ([`crate::global`]) from the model file's values or, for a candidate, from the
/// base model's basins (`warm`). Held-out errors are left to [`cross_validate`].
pub(super) fn fit_on_all(
    model: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    rows: &[Measurement],
    own: &[String],
    warm: Warm<'_>,
    settings: &Settings,
) -> Result<FittedOnAll, DiscoverError> {
    let (all_names, all_bounds, file_start) = fitted_parameters(model, experiment, rows, own)?;
    let predictor = Predictor::new(model.clone(), source, experiment)?;
    // A candidate's parameter that no row's model uses (friction at a contact every row
    // removes) changes no prediction: it is not searched, and keeps its file value with its
    // whole bounds as the interval of values that fit as well.
    let idle: Vec<bool> = all_names
        .iter()
        .map(|n| own.contains(n) && !predictor.uses_parameter(n, rows))
        .collect();
    let active = |values: &[f64]| active_only(values, &idle);
    let names = active_only(&all_names, &idle);
    let bounds = active_only(&all_bounds, &idle);
    let orderings = global::orderings(model, &names);
    // Steady states are piecewise linear in the parameters, with basins that differ in which
    // rows slide (a low Coulomb force with a high viscous coefficient, or the reverse, or a
    // Coulomb force tied to its breakaway force), so the fit searches every face. The base
    // model starts from the model file's values; a candidate from each basin of the base
    // model's search, with its own parameters at their file values, their no-effect values
    // (a candidate contains the base model there, so it does no worse than the base), besides
    // the base model's full screening: a candidate's optimum can lie far from the base's, in
    // parameters the base does not have, and a lighter screening (a quarter of the points, or
    // one local fit per face) missed one candidate's optimum in 3 of 20 synthetic sets of
    // a two-contact model with a string, and another's on its measured data. A candidate none
    // of whose parameters is in use is the base model on these rows: it is refitted locally
    // from the base model's optimum.
    let (starts, search) = match warm {
        None => (vec![active(&file_start)], settings.search),
        Some((warm_names, basins)) => {
            let starts: Vec<Vec<f64>> = basins
                .iter()
                .map(|basin| {
                    let mut start = file_start.clone();
                    for (name, value) in warm_names.iter().zip(basin) {
                        if let Some(j) = all_names.iter().position(|n| n == name) {
                            start[j] = *value;
                        }
                    }
                    active(&start)
                })
                .collect();
            if names.len() == all_names.len() - own.len() {
                (starts[..1].to_vec(), Search::LOCAL)
            } else {
                (starts, settings.search)
            }
        }
    };
    let mut evaluator = predictor.evaluator(&names)?;
    limit_to_budget(&mut evaluator, settings);
    let start_refs: Vec<&[f64]> = starts.iter().map(Vec::as_slice).collect();
    let Searched { fit, basins } = fit_best(
        &mut evaluator,
        rows,
        None,
        &start_refs,
        &bounds,
        (&orderings, &search),
        settings,
    )?;
    evaluator.set(&fit.values);
    let columns = experiment.observed.len();
    let predictions: Vec<(Vec<f64>, String)> = evaluator
        .predict_each(rows)
        .into_iter()
        .map(|p| match p {
            Ok(p) => (p.observed, p.mode),
            Err(_) => (vec![f64::NAN; columns], "does not settle".to_string()),
        })
        .collect();
    let fit = fit.with_idle(&idle, &file_start, &all_bounds);
    let basins = basins
        .iter()
        .map(|basin| {
            let mut values = basin.iter();
            idle.iter()
                .zip(&file_start)
                .map(|(i, v)| {
                    if *i {
                        *v
                    } else {
                        *values.next().expect("one per active")
                    }
                })
                .collect()
        })
        .collect();
    let mut assessment = Assessment {
        names: all_names,
        predictions: predictions.iter().flat_map(|p| p.0.clone()).collect(),
        modes: predictions.into_iter().map(|p| p.1).collect(),
        unsettled: 0,
        evaluations: fit.evaluations,
        trials: evaluator.trials(),
        fit,
        heldout_sse: 0.0,
        heldout_count: 0,
        heldout_by_column: vec![0.0; columns],
        heldout_cells: Vec::new(),
        anchors: evaluator.anchors(),
    };
    assessment.heldout_cells = vec![f64::NAN; assessment.predictions.len()];
    assessment.unsettled = assessment
        .predictions
        .chunks(columns)
        .filter(|p| p.iter().any(|v| v.is_nan()))
        .count();
    let orderings = global::orderings(model, &assessment.names);
    Ok(FittedOnAll {
        assessment,
        bounds: all_bounds,
        orderings,
        basins,
    })
}

/// The best least-squares fit on `train` of the parameters `evaluator` sets, searching
/// (`search`, under the parameters' `orderings`) from `starts`.
///
/// `train` is what the fit simulates; `kept`, the positions in it of the rows whose
/// residuals enter the sum of squares (`None`: every row). A time series' fold simulates
/// whole runs, so that the measured inputs are complete, and keeps its training samples'
/// residuals ([`crate::folds::simulated`]).
pub(crate) fn fit_best(
    evaluator: &mut Evaluator<'_>,
    train: &[Measurement],
    kept: Option<&[usize]>,
    starts: &[&[f64]],
    bounds: &[(f64, f64)],
    (orderings, search): (&[Ordering], &Search),
    settings: &Settings,
) -> Result<Searched, DiscoverError> {
    let all: Vec<usize>;
    let kept = match kept {
        Some(kept) => kept,
        None => {
            all = (0..train.len()).collect();
            &all
        }
    };
    let measured: Vec<f64> = kept
        .iter()
        .flat_map(|&i| train[i].observed.iter().copied())
        .collect();
    // Each search running side by side (a face's screening, a local fit from one start)
    // predicts with an evaluator of its own and has the budget of evaluations to itself, so
    // the trials each makes, and so the fit, are the same however the threads interleave. A
    // trial past its search's budget fails without a prediction, so that search ends on the
    // best point it found by then.
    let template = &*evaluator;
    let measured = &measured;
    let spent = std::sync::atomic::AtomicBool::new(false);
    let spent = &spent;
    let budget = settings.budget.evaluations;
    // Where each training row's cells start in `measured`, for the rows kept.
    let mut offsets = vec![None; train.len()];
    let mut offset = 0;
    for &i in kept {
        offsets[i] = Some(offset);
        offset += train[i].observed.len();
    }
    let offsets = &offsets;
    let residuals = || -> global::Residuals<'_> {
        Box::new(TrainingFit {
            evaluator: template.fork(),
            made: 0,
            budget,
            spent,
            train,
            kept,
            offsets,
            measured,
            order: (0..train.len()).collect(),
            largest: vec![0.0; train.len()],
            squares: vec![f64::NAN; train.len()],
        })
    };
    let result = global::least_squares(
        &residuals,
        starts,
        bounds,
        orderings,
        search,
        &settings.calibration,
    )
    .and_then(|searched| {
        if searched.fit.sse.is_finite() {
            Ok(searched)
        } else {
            Err(CalibrationError(
                "the sum of squares is not finite at the best point found".into(),
            ))
        }
    });
    if spent.load(std::sync::atomic::Ordering::Relaxed) {
        evaluator.spent_evaluations();
    }
    match result {
        Ok(searched) => Ok(searched),
        Err(error) => {
            // Name the row the model cannot evaluate, when it is one row.
            evaluator.set(starts[0]);
            let predictions = evaluator.predict(train)?;
            let rows: Vec<Measurement> = kept.iter().map(|&i| train[i].clone()).collect();
            let predictions: Vec<_> = kept.iter().map(|&i| predictions[i].clone()).collect();
            if let Some(error) = unfittable_row(evaluator.experiment(), &rows, &predictions) {
                return Err(error);
            }
            Err(DiscoverError::Calibration {
                data: train
                    .first()
                    .map_or_else(String::new, |r| r.file.to_string()),
                error,
            })
        }
    }
}

/// The first row of `rows` whose residual cannot enter a sum of squares, given the model's
/// `predictions`: one that is not finite, or whose square overflows, or, when every square
/// is finite but their sum is not, the row with the largest. The column to blame is the
/// observed one when the measured value is the larger in magnitude, otherwise the condition
/// cell with the largest value in SI units (what the model was driven with).
fn unfittable_row(
    experiment: &Experiment,
    rows: &[Measurement],
    predictions: &[crate::predict::Prediction],
) -> Option<DiscoverError> {
    let mut squares = Vec::new();
    for (i, (row, p)) in rows.iter().zip(predictions).enumerate() {
        for (k, (&predicted, &measured)) in p.observed.iter().zip(&row.observed).enumerate() {
            squares.push((i, k, (predicted - measured).powi(2)));
        }
    }
    let total: f64 = squares.iter().map(|s| s.2).sum();
    let &(i, k, square) = squares.iter().find(|s| !s.2.is_finite()).or_else(|| {
        (!total.is_finite())
            .then(|| squares.iter().max_by(|a, b| a.2.total_cmp(&b.2)))
            .flatten()
    })?;
    let (row, predicted, measured) = (&rows[i], predictions[i].observed[k], rows[i].observed[k]);
    let observed = &experiment.observed[k].column;
    let overflow = if square.is_finite() {
        format!(
            "the squares of the residuals sum past the largest double (this row's is {square:.3e})"
        )
    } else {
        "the square of its residual overflows a double".to_string()
    };
    let (column, value, reason) = if predicted.is_finite() && measured.abs() >= predicted.abs() {
        (
            observed.clone(),
            measured,
            format!(
                "`{observed}` = {} cannot be fitted: the model predicts {} there, and \
                 {overflow}",
                cell_text(measured),
                number(predicted, 6)
            ),
        )
    } else {
        let columns = experiment.condition_columns();
        let largest = experiment
            .conditions
            .iter()
            .zip(&row.conditions)
            .enumerate()
            .filter_map(|(j, (c, cell))| cell.map(|v| (j, v, (c.factor * v).abs())))
            .max_by(|a, b| a.2.total_cmp(&b.2));
        let Some((j, cell, _)) = largest else {
            return Some(DiscoverError::Unfittable {
                file: row.file.to_string(),
                row: row.row,
                column: None,
                value: None,
                reason: format!(
                    "the model predicts `{observed}` = {predicted:e} on this row, which cannot \
                     be fitted"
                ),
            });
        };
        (
            columns[j].to_string(),
            cell,
            format!(
                "`{}` = {}: the model predicts `{observed}` = {} there, which cannot be \
                 fitted ({})",
                columns[j],
                cell_text(cell),
                number(predicted, 6),
                if predicted.is_finite() {
                    overflow.as_str()
                } else {
                    "the prediction is not finite"
                }
            ),
        )
    };
    Some(DiscoverError::Unfittable {
        file: row.file.to_string(),
        row: row.row,
        column: Some(column),
        value: Some(value),
        reason,
    })
}

/// A cell as the data would write it: `12.5`, or `1.797e308` where decimals would run on.
fn cell_text(value: f64) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        value.to_string()
    } else {
        format!("{value:e}")
    }
}

/// The entries of `items` whose parameter is not `idle` (a parameter no row's model uses,
/// which a fit does not search).
pub(super) fn active_only<T: Clone>(items: &[T], idle: &[bool]) -> Vec<T> {
    items
        .iter()
        .zip(idle)
        .filter(|(_, idle)| !**idle)
        .map(|(item, _)| item.clone())
        .collect()
}

/// One search's objective in [`fit_best`]: the residuals of the kept training rows, within
/// the search's budget of evaluations.
struct TrainingFit<'s, 'p> {
    evaluator: Evaluator<'p>,
    /// Evaluations made, against `budget`.
    made: usize,
    budget: usize,
    /// Set when a trial is refused for the budget.
    spent: &'s std::sync::atomic::AtomicBool,
    train: &'s [Measurement],
    kept: &'s [usize],
    /// Where each training row's cells start in `measured`; `None` for a row not kept.
    offsets: &'s [Option<usize>],
    measured: &'s [f64],
    /// The order in which a bounded evaluation predicts the training rows: those with the
    /// largest squared residuals so far first, so that a point that cannot be kept shows it
    /// after few rows.
    order: Vec<usize>,
    /// Each training row's largest sum of squared residuals so far.
    largest: Vec<f64>,
    /// Each training row's sum of squared residuals at the point being evaluated.
    squares: Vec<f64>,
}

impl TrainingFit<'_, '_> {
    /// Sets `x` if the budget allows another evaluation.
    fn start(&mut self, x: &[f64]) -> bool {
        if self.made >= self.budget {
            self.spent.store(true, std::sync::atomic::Ordering::Relaxed);
            return false;
        }
        self.made += 1;
        self.evaluator.set(x);
        true
    }
}

impl crate::calibrate::ResidualFunction for TrainingFit<'_, '_> {
    fn residuals(&mut self, x: &[f64]) -> Option<Vec<f64>> {
        self.residuals_from(x, None)
    }

    fn differenced(&mut self, x: &[f64], from: &[f64]) -> Option<Vec<f64>> {
        self.residuals_from(x, Some(from))
    }

    fn sum_of_squares(&mut self, x: &[f64], limit: f64) -> Option<f64> {
        if !self.start(x) {
            return None;
        }
        // The rows' partial sum only grows, whatever their order, so a point past `limit`
        // on some rows is past it on all; a margin keeps rounding (the partial sum in this
        // order against the whole in the rows' own) from stopping a point that is not.
        let stop = limit * (1.0 + 1e-9);
        let (offsets, measured, squares) = (self.offsets, self.measured, &mut self.squares);
        squares.fill(f64::NAN);
        let mut partial = 0.0;
        let predicted = self
            .evaluator
            .predict_until(self.train, &self.order, |i, prediction| {
                let square = offsets[i].map_or(0.0, |at| {
                    prediction
                        .observed
                        .iter()
                        .zip(&measured[at..])
                        .map(|(p, m)| (p - m) * (p - m))
                        .sum::<f64>()
                });
                squares[i] = square;
                partial += square;
                partial > stop
            });
        if !predicted {
            return None;
        }
        for (largest, square) in self.largest.iter_mut().zip(&self.squares) {
            if *square > *largest {
                *largest = *square;
            }
        }
        let largest = &self.largest;
        self.order
            .sort_by(|&a, &b| largest[b].total_cmp(&largest[a]).then(a.cmp(&b)));
        if self.squares.iter().any(|v| v.is_nan()) {
            // Stopped: any value above the limit will do.
            return Some(partial);
        }
        // Every row predicted: the sum in the rows' own order, as the residuals give it.
        Some(self.squares.iter().sum())
    }
}

impl TrainingFit<'_, '_> {
    /// The residuals at `x`, a difference step from `from` if given
    /// ([`crate::predict::Evaluator::predict_differenced`]).
    fn residuals_from(&mut self, x: &[f64], from: Option<&[f64]>) -> Option<Vec<f64>> {
        if !self.start(x) {
            return None;
        }
        let predictions = match from {
            Some(from) => self.evaluator.predict_differenced(self.train, from)?,
            None => self.evaluator.predict_all(self.train)?,
        };
        Some(
            self.kept
                .iter()
                .flat_map(|&i| predictions[i].observed.iter().copied())
                .zip(self.measured)
                .map(|(p, m)| p - m)
                .collect(),
        )
    }
}
