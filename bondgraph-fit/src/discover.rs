//! What a model gets wrong on measured data, which candidate extension explains it, and the
//! gain on held-out data.
//!
//! The procedure, for a base model, its experiment, the data and a library of candidate
//! extensions:
//!
//! 1. **Baseline**: refit the parameters the experiment names as fitted (and those of
//!    `fitted_when_present` whose column has values) and score the model on held-out data:
//!    leave one level out of a condition column with three or more levels (fit on some
//!    settings of a condition, predict the others; [`crate::folds`] says which), and k-fold (k = 5, rows dealt
//!    round-robin in the order of the conditions). A time series is held out along time:
//!    one run (data file) at a time, or with one run, k contiguous blocks of it; a fold fits
//!    its training samples' residuals and scores its held-out ones, each time simulating
//!    the whole run, so that no held-out block cuts the measured inputs that drive it.
//! 2. **Residuals** of the baseline by operating regime (named by the mode each row settles
//!    in, or a sample is in) and along each condition column (in a time series, a measured
//!    input signal) and the time column, with the trend and whether it stands out of the
//!    noise.
//! 3. **Candidates**: each extension merged into the base model, refitted with the base's
//!    fitted parameters and its own, and scored the same way. A candidate whose parameters
//!    move no prediction anywhere in their bounds is untestable on this data (an effect of
//!    an element that every row removes); one whose effect the base parameters can mimic
//!    exactly (its Jacobian columns lie in the span of theirs, or its fit, with its own
//!    parameters away from their no-effect values, predicts every row as the base's does) is
//!    aliased with the base.
//! 4. **Selection**: a candidate qualifies when its gain is beyond the noise — an F-test of
//!    its sum of squares against the baseline's at level 0.01 divided by the number of
//!    candidates tried (Bonferroni), a lower corrected Akaike criterion, and a lower
//!    held-out RMSE. The qualifying candidate with the lowest held-out RMSE is selected; if
//!    none qualifies, `selected` is `null`.
//! 5. **Indistinguishable** candidates: those that also qualify and fit the data no worse
//!    than the selected one beyond the noise (or, when nothing is selected, those aliased
//!    with the base), each with the measurement that would separate them: a condition where
//!    the two fitted models' predictions differ by more than three noise levels, searched
//!    over a grid of conditions wider than the data's (for a time series: the time along the
//!    recorded run where they differ most), or, when no such observation separates them,
//!    what the extension's file says would show its effect directly.
//!
//! The noise level all of this is judged against is the experiment's declared one, else the
//! pure error of replicated conditions (steady data: a run's samples are not replicates),
//! else the best model's residual ([`crate::noise`]);
//! with a level that does not come from a model, the base model's lack of fit is tested too.

use std::collections::BTreeMap;
use std::sync::Arc;

use bondgraph_core::diagnostics::Diagnostics;
use bondgraph_core::model::edit::{self, Edit};
use bondgraph_core::model::extension::{self, Extension};
use bondgraph_core::model::{self, Model};
use bondgraph_core::source::SourceFile;
use rayon::prelude::*;
use serde::Serialize;

use crate::calibrate::{self, CalibrationError, Fit};
use crate::data::{Dataset, Measurement};
use crate::experiment::{Experiment, ExperimentError};
use crate::global::{self, Ordering, Search, Searched};
use crate::noise::{self, LackOfFit, NoiseLevel, PureError};
use crate::predict::{Evaluator, Predictor};
use crate::stats;

/// How `discover` tests.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// The family-wise significance level of the F-tests, shared among the candidates.
    pub alpha: f64,
    /// Folds of the k-fold cross-validation.
    pub folds: usize,
    /// The calibration's settings.
    pub calibration: calibrate::Settings,
    /// How widely each model's first fit searches (folds refit locally from it).
    pub search: Search,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            alpha: 0.01,
            folds: 5,
            calibration: calibrate::Settings::default(),
            search: Search::GLOBAL,
        }
    }
}

/// Why a calibration or a discovery failed.
#[derive(Clone, Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DiscoverError {
    /// A model, an extension or an edit that does not load: core's located diagnostics.
    #[error("{0}")]
    Model(#[from] Diagnostics),
    /// The experiment does not fit the model, or a row cannot be predicted.
    #[error("{0}")]
    Experiment(#[from] ExperimentError),
    /// The least-squares search could not start.
    #[error("{data}: {error}")]
    Calibration {
        /// The data's name.
        data: String,
        /// Why.
        error: CalibrationError,
    },
    /// A row whose residual the least-squares search cannot form at the starting values: a
    /// prediction that is not finite, or a residual whose square overflows (a cell such as
    /// `1.797e308`).
    #[error("{file}:{row}: {reason}")]
    Unfittable {
        /// The data file.
        file: String,
        /// Its line.
        row: usize,
        /// The column whose value the model cannot work with, where that is determinable:
        /// the observed column for a measured value too large, the largest condition cell
        /// for a prediction that overflows.
        column: Option<String>,
        /// That column's cell.
        value: Option<f64>,
        /// Why, naming the column and its cell.
        reason: String,
    },
    /// Too few rows to fit and hold some out.
    #[error("{data}: {rows} rows; discovery needs at least {needed} to fit and hold some out")]
    TooFewRows {
        /// The data's name.
        data: String,
        /// Rows it has.
        rows: usize,
        /// Rows needed.
        needed: usize,
    },
    /// Discovery compares one observed column.
    #[error("the experiment observes {0} columns; discovery compares one (calibrate fits several)")]
    ObservedColumns(usize),
    /// A fitted parameter that is not in the model, or has no bounds.
    #[error("{0}")]
    Fitted(Diagnostics),
}

/// A candidate extension, merged into the base model.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The extension's id.
    pub id: String,
    /// Its physical cause.
    pub cause: String,
    /// What would show it directly.
    pub evidence: Option<String>,
    /// Its own parameters with bounds (the ones calibration fits), in file order.
    pub parameters: Vec<String>,
    /// The extended model file.
    pub source: Arc<SourceFile>,
    /// The extended model.
    pub model: Model,
}

impl Candidate {
    /// Merges `extension` into the model file `base`.
    ///
    /// # Errors
    /// Every problem of the merge or of the merged model, located in the file it came from.
    pub fn new(base: &Arc<SourceFile>, extension: &Extension) -> Result<Self, DiscoverError> {
        let extended = extension::merge(base, std::slice::from_ref(extension))?;
        let model = extended.load()?;
        let parameters = extension
            .raw
            .parameters
            .iter()
            .filter(|(_, p)| p.bounds.is_some())
            .map(|(name, _)| name.clone())
            .collect();
        Ok(Self {
            id: extension.raw.id.clone(),
            cause: extension.raw.cause.clone(),
            evidence: extension.raw.evidence.clone(),
            parameters,
            source: extended.file,
            model,
        })
    }
}

/// A parameter's fitted value and how well the data determines it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Estimate {
    /// The fitted value.
    pub value: f64,
    /// Its standard error, where the Jacobian determines it.
    pub std_error: Option<f64>,
    /// For a threshold, the interval of values that fit equally well.
    pub interval: Option<(f64, f64)>,
    /// Whether the fit ended on a bound.
    pub at_bound: bool,
}

/// The base model's scores.
#[derive(Clone, Debug, Serialize)]
pub struct Baseline {
    /// RMSE of the fit on all rows, in the observed column's units.
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// The refitted parameters.
    pub params: BTreeMap<String, Estimate>,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
}

/// One candidate's result.
#[derive(Clone, Debug, Serialize)]
pub struct Ranked {
    /// The extension's id.
    pub id: String,
    /// Every refitted parameter (the base's and its own).
    pub params: BTreeMap<String, Estimate>,
    /// RMSE of the fit on all rows, in the observed column's units.
    pub rmse_fit: f64,
    /// RMSE on held-out rows.
    pub rmse_heldout: f64,
    /// The corrected Akaike criterion against the baseline's (negative: better).
    pub score: f64,
    /// The F-test's p-value against the baseline.
    pub p_value: f64,
    /// Predictions of every row made by its fit and its folds' refits: the search's cost.
    pub evaluations: usize,
    /// What the data says of it: `selected`, `indistinguishable`, `qualifies`,
    /// `not significant`, `aliased with the base`, `no effect on this data` or
    /// `worse than the base` (its bounds keep it from containing the base model here).
    pub verdict: String,
}

/// Residuals of one regime.
#[derive(Clone, Debug, Serialize)]
pub struct RegimeResiduals {
    /// The regime's physical name.
    pub regime: String,
    /// Rows in it.
    pub rows: usize,
    /// Mean residual (model minus measured), in the observed column's units.
    pub mean: f64,
    /// Root-mean-square residual.
    pub rmse: f64,
    /// Whether the mean stands out of the noise (beyond three standard errors).
    pub stands_out: bool,
}

/// The trend of the residuals along one condition column (or a time series' time column).
#[derive(Clone, Debug, Serialize)]
pub struct FactorTrend {
    /// The condition column, or the time column.
    pub condition: String,
    /// The regime the trend is taken in (`all` for every row).
    pub regime: String,
    /// Residual change per unit of the condition (observed units per unit).
    pub slope: f64,
    /// Its standard error.
    pub std_error: f64,
    /// Whether it stands out of the noise (|slope| > 3 standard errors).
    pub stands_out: bool,
}

/// Residuals by regime and by factor.
#[derive(Clone, Debug, Serialize)]
pub struct Residuals {
    /// By operating regime.
    pub by_regime: Vec<RegimeResiduals>,
    /// Along each condition column and, for a time series, along its time column (a trend
    /// in time), over all rows and within each regime with enough rows.
    pub by_condition: Vec<FactorTrend>,
}

/// One row with its predictions.
#[derive(Clone, Debug, Serialize)]
pub struct RowResult {
    /// A time series' sample time, in the time column's units.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The condition cells, by column (`None`: empty).
    pub conditions: BTreeMap<String, Option<f64>>,
    /// The measured value.
    pub measured: f64,
    /// The refitted base model's.
    pub baseline: f64,
    /// The selected extended model's.
    pub selected: Option<f64>,
    /// The regime the base model settles in.
    pub regime: String,
}

/// A measurement that would tell two candidates apart.
#[derive(Clone, Debug, Serialize)]
pub struct Separation {
    /// The candidate the selected one (or the baseline) is confused with.
    pub id: String,
    /// What to measure.
    pub measurement: String,
}

/// Held-out RMSE before and after the extension.
#[derive(Clone, Debug, Serialize)]
pub struct Gain {
    /// The baseline's.
    pub rmse_heldout_before: f64,
    /// The selected extension's (the baseline's when nothing is selected).
    pub rmse_heldout_after: f64,
}

/// Everything `discover` finds.
#[derive(Clone, Debug, Serialize)]
pub struct Discovery {
    /// The data's name.
    pub data: String,
    /// Rows used.
    pub rows: usize,
    /// The observed column's name (every RMSE and residual is in its units).
    pub observed: String,
    /// The noise level, in the observed column's units ([`crate::noise`]): the experiment's
    /// declared one, else the pure error of replicated conditions, else the best model's
    /// residual standard deviation; `None` when the data cannot estimate it (replicates
    /// that repeat exactly, an exact fit), and then nothing is judged in noise levels.
    pub noise: Option<f64>,
    /// Where `noise` came from: `declared in the experiment`, `pure error of N replicated
    /// conditions (D dof)`, `residual of the base model (D dof)`, `residual of 'ID' (D
    /// dof)`, or `cannot be estimated: ...` and why.
    pub noise_source: String,
    /// The scatter of replicated conditions, when some condition is measured twice.
    pub pure_error: Option<PureError>,
    /// The base model's lack-of-fit test, when the noise level does not come from a model's
    /// residuals (declared, or pure error).
    pub lack_of_fit: Option<LackOfFit>,
    /// The base model.
    pub baseline: Baseline,
    /// Candidates, best held-out RMSE first.
    pub ranking: Vec<Ranked>,
    /// The selected extension, or `None` when none gains beyond the noise.
    pub selected: Option<String>,
    /// Its physical cause.
    pub cause: Option<String>,
    /// Candidates the data cannot tell apart from the selected one (or from the baseline).
    pub indistinguishable: Vec<String>,
    /// For each of them, what would separate it.
    pub separation: Vec<Separation>,
    /// Candidates with no effect on this data.
    pub untestable: Vec<String>,
    /// The gain.
    pub gain: Gain,
    /// Residuals of the baseline.
    pub residuals_before: Residuals,
    /// Residuals of the selected extension.
    pub residuals_after: Option<Residuals>,
    /// Every row.
    pub table: Vec<RowResult>,
    /// The selected extended model with its fitted values, as a model file.
    #[serde(skip)]
    pub extended_model: Option<String>,
}

/// A model fitted and cross-validated.
struct Assessment {
    names: Vec<String>,
    fit: Fit,
    predictions: Vec<f64>,
    modes: Vec<String>,
    heldout_sse: f64,
    heldout_count: usize,
    /// Predictions (held out, or of the final fit) that did not settle.
    unsettled: usize,
    /// Predictions of every row made by the fit and the folds' refits.
    evaluations: usize,
}

/// Simulated time within which a row must settle; the experiments filmed steady growth
/// within seconds, and a model that has not settled after this is oscillating (a stick-slip
/// cycle), which a steady velocity cannot describe.
pub(crate) const SETTLE_WITHIN_S: f64 = 2.0;

/// Mode changes within which a row must settle: a steady state is reached after a handful
/// (a contact that sticks, then slides, a string that goes taut), and a trial value that
/// makes a row stick and slip hundreds of times is a cycle, not a steady state. Without this
/// a fit spends most of its time simulating such cycles to [`SETTLE_WITHIN_S`].
pub(crate) const MODE_CHANGES_WITHIN: usize = 200;

/// Limits an evaluator to what a steady row may take: [`SETTLE_WITHIN_S`] of simulated
/// time and [`MODE_CHANGES_WITHIN`] mode changes.
pub(crate) fn limit_to_settling(evaluator: &mut Evaluator<'_>) {
    evaluator.set_max_time(SETTLE_WITHIN_S);
    evaluator.set_max_mode_changes(MODE_CHANGES_WITHIN);
}

impl Assessment {
    fn rmse_fit(&self) -> f64 {
        (self.fit.sse / self.predictions.len() as f64).sqrt()
    }

    fn rmse_heldout(&self) -> f64 {
        (self.heldout_sse / self.heldout_count.max(1) as f64).sqrt()
    }

    fn estimates(&self) -> BTreeMap<String, Estimate> {
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

    fn aicc(&self) -> f64 {
        let n = self.predictions.len() as f64;
        let k = self.names.len() as f64;
        let sse = self.fit.sse.max(1e-300);
        n * (sse / n).ln() + 2.0 * k + 2.0 * k * (k + 1.0) / (n - k - 1.0).max(1.0)
    }
}

/// Names, bounds and starting values of the parameters to fit.
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
            .parameters
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
                                model.name
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
                            model.name
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
struct FittedOnAll {
    assessment: Assessment,
    bounds: Vec<(f64, f64)>,
    orderings: Vec<Ordering>,
    basins: Vec<Vec<f64>>,
}

/// Fits `model` on all `rows`: its own parameters `own` with the experiment's, by a global
/// search ([`crate::global`]) from the model file's values or, for a candidate, from the
/// base model's basins (`warm`). Held-out errors are left to [`cross_validate`].
fn fit_on_all(
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
    let active = |values: &[f64]| -> Vec<f64> {
        values
            .iter()
            .zip(&idle)
            .filter(|(_, i)| !**i)
            .map(|(v, _)| *v)
            .collect()
    };
    let names: Vec<String> = all_names
        .iter()
        .zip(&idle)
        .filter(|(_, i)| !**i)
        .map(|(n, _)| n.clone())
        .collect();
    let bounds: Vec<(f64, f64)> = all_bounds
        .iter()
        .zip(&idle)
        .filter(|(_, i)| !**i)
        .map(|(b, _)| *b)
        .collect();
    let orderings = global::orderings(model, &names);
    // Steady states are piecewise linear in the parameters, with basins that differ in which
    // rows slide (a low Coulomb force with a high viscous coefficient, or the reverse, or a
    // Coulomb force tied to its breakaway force), so the fit searches every face. The base
    // model starts from the model file's values; a candidate from each basin of the base
    // model's search, with its own parameters at their file values, their no-effect values
    // (a candidate contains the base model there, so it does no worse than the base), besides
    // the base model's full screening: a candidate's optimum can lie far from the base's, in
    // parameters the base does not have, and a lighter screening (a quarter of the points, or
    // one local fit per face) missed one candidate's optimum in 3 of the flagship study's 20
    // synthetic sets, and another's on its measured data (see the README). A candidate none
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
    limit_to_settling(&mut evaluator);
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
    let predictions: Vec<(f64, String)> = evaluator
        .predict_each(rows)
        .into_iter()
        .map(|p| match p {
            Ok(p) => (p.observed[0], p.mode),
            Err(_) => (f64::NAN, "does not settle".to_string()),
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
        predictions: predictions.iter().map(|p| p.0).collect(),
        modes: predictions.into_iter().map(|p| p.1).collect(),
        unsettled: 0,
        evaluations: fit.evaluations,
        fit,
        heldout_sse: 0.0,
        heldout_count: 0,
    };
    assessment.unsettled = assessment.predictions.iter().filter(|p| p.is_nan()).count();
    let orderings = global::orderings(model, &assessment.names);
    Ok(FittedOnAll {
        assessment,
        bounds: all_bounds,
        orderings,
        basins,
    })
}

/// Two models whose fits predict every row within this of each other are one model on the
/// data: a fiftieth of the smallest measurement noise the project works with.
const SAME_PREDICTION_MM_S: f64 = 1e-3;

/// A candidate fitted and cross-validated; `true` with it when it is not cross-validated and
/// takes the base model's held-out errors instead: when its fit predicts every row as the
/// base model's fit does (`base_predictions`, within [`SAME_PREDICTION_MM_S`]). At its best
/// it is then the base model on this data: its own parameters change no prediction
/// (friction at a contact the data never has, a ceiling above every row), or only as a
/// refit of the base's parameters would (an alias), so its folds would refit the base model.
fn assess_candidate(
    candidate: &Candidate,
    experiment: &Experiment,
    rows: &[Measurement],
    warm: (&[String], &[Vec<f64>]),
    base_predictions: &[f64],
    settings: &Settings,
) -> Result<(Assessment, bool), DiscoverError> {
    let mut fitted = fit_on_all(
        &candidate.model,
        &candidate.source,
        experiment,
        rows,
        &candidate.parameters,
        Some(warm),
        settings,
    )?;
    let same_as_base = fitted
        .assessment
        .predictions
        .iter()
        .zip(base_predictions)
        .all(|(a, b)| (a - b).abs() <= SAME_PREDICTION_MM_S);
    if same_as_base {
        return Ok((fitted.assessment, true));
    }
    cross_validate(
        &candidate.model,
        &candidate.source,
        experiment,
        rows,
        &mut fitted,
        settings,
    )?;
    Ok((fitted.assessment, false))
}

/// The held-out errors of a model fitted on all rows: leave one level out of a condition
/// column, then k-fold, each fold refitted ([`crate::folds`]).
fn cross_validate(
    model: &Model,
    source: &Arc<SourceFile>,
    experiment: &Experiment,
    rows: &[Measurement],
    fitted: &mut FittedOnAll,
    settings: &Settings,
) -> Result<(), DiscoverError> {
    let FittedOnAll {
        assessment,
        bounds,
        orderings,
        basins,
    } = fitted;
    let predictor = Predictor::new(model.clone(), source, experiment)?;
    // What each fold simulates (a time series: whole runs) and which residuals it keeps.
    let pick = |indices: &[usize]| -> (Vec<Measurement>, Vec<usize>) {
        let simulated = crate::folds::simulated(experiment, rows, indices);
        let picked = simulated.rows.iter().map(|&i| rows[i].clone()).collect();
        (picked, simulated.kept)
    };
    let folds: Vec<_> = crate::folds::folds(experiment, rows, settings.folds)
        .into_iter()
        .map(|fold| (pick(&fold.train), pick(&fold.test)))
        .collect();
    // A fold refits locally from each basin the full data's search found (its optimum
    // first), each start on its own face, and keeps the best: as the whole search would, it
    // may change basin when the rows held out favoured one, without screening again. Folds
    // are independent, each with its own evaluator, and run side by side.
    let starts: Vec<&[f64]> = basins.iter().map(Vec::as_slice).collect();
    let scored: Vec<Result<HeldOut, DiscoverError>> = folds
        .par_iter()
        .map(|((train, train_kept), (test, test_kept))| {
            let mut evaluator = predictor.evaluator(&assessment.names)?;
            limit_to_settling(&mut evaluator);
            let fit = fit_best(
                &mut evaluator,
                train,
                Some(train_kept),
                &starts,
                bounds,
                (orderings, &Search::LOCAL),
                settings,
            )?
            .fit;
            evaluator.set(&fit.values);
            let predictions = evaluator.predict_each(test);
            let mut held_out = HeldOut {
                evaluations: fit.evaluations,
                ..HeldOut::default()
            };
            for &i in test_kept {
                match &predictions[i] {
                    Ok(p) => {
                        held_out.sse += (p.observed[0] - test[i].observed[0]).powi(2);
                        held_out.count += 1;
                    }
                    Err(_) => held_out.unsettled += 1,
                }
            }
            Ok(held_out)
        })
        .collect();
    for held_out in scored {
        let held_out = held_out?;
        assessment.evaluations += held_out.evaluations;
        assessment.heldout_sse += held_out.sse;
        assessment.heldout_count += held_out.count;
        assessment.unsettled += held_out.unsettled;
    }
    Ok(())
}

/// What one fold's refit scores on its held-out rows.
#[derive(Default)]
struct HeldOut {
    sse: f64,
    count: usize,
    unsettled: usize,
    evaluations: usize,
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
    // Each search running side by side predicts with an evaluator of its own.
    let template = &*evaluator;
    let measured = &measured;
    let residuals = || -> global::Residuals<'_> {
        let mut evaluator = template.fork();
        Box::new(move |x: &[f64]| {
            evaluator.set(x);
            let predictions = evaluator.predict_all(train)?;
            Some(
                kept.iter()
                    .flat_map(|&i| predictions[i].observed.iter().copied())
                    .zip(measured)
                    .map(|(p, m)| p - m)
                    .collect(),
            )
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

/// The verdict of a candidate that fits worse than the base model it contains.
const WORSE_THAN_THE_BASE: &str = "worse than the base";

/// Whether the candidate's own parameters' Jacobian columns lie in the span of the base
/// parameters' (so the base refit can mimic its effect): the relative norm of what the
/// projection leaves, below 2%. Base columns that others already span (two thresholds tied
/// on a face move the residuals alike) add nothing to the span and are left out of it.
fn aliased_with_base(fit: &Fit, base: usize, own: usize) -> bool {
    let p = base + own;
    let n = fit.residuals.len();
    let column = |j: usize| -> Vec<f64> { (0..n).map(|i| fit.jacobian[i * p + j]).collect() };
    // An orthonormal basis of the base columns' span (modified Gram-Schmidt). A base
    // parameter held at a bound can mimic an effect in one direction only.
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for j in (0..base).filter(|&j| !fit.at_bound[j]) {
        let mut c = column(j);
        let norm = dot(&c, &c).sqrt();
        for q in &basis {
            let along = dot(q, &c);
            c.iter_mut().zip(q).for_each(|(v, q)| *v -= along * q);
        }
        let left = dot(&c, &c).sqrt();
        if left > 1e-9 * norm {
            basis.push(c.into_iter().map(|v| v / left).collect());
        }
    }
    (base..p).all(|j| {
        let mut c = column(j);
        let norm = dot(&c, &c).sqrt();
        if norm == 0.0 {
            return false;
        }
        for q in &basis {
            let along = dot(q, &c);
            c.iter_mut().zip(q).for_each(|(v, q)| *v -= along * q);
        }
        dot(&c, &c).sqrt() < 0.02 * norm
    })
}

/// Whether the candidate's fit, with its own parameters away from their no-effect values,
/// predicts every row as the base model's fit does (to a thousandth of the base model's
/// RMSE): on these rows its effect is then a refit of the base in disguise, wherever the
/// search stopped. (The Jacobian test of [`aliased_with_base`] looks only at the point where
/// the candidate's search ended: a brush drop found as a higher drop with a lower Coulomb
/// torque, predicting every row as the base does, has columns that a few rows keep apart.)
fn reproduced_by_base(candidate: &Candidate, fitted: &Assessment, base: &Assessment) -> bool {
    let first_own = fitted.names.len() - candidate.parameters.len();
    let active = (first_own..fitted.names.len()).any(|j| {
        candidate
            .model
            .parameters
            .iter()
            .find(|p| p.name == fitted.names[j])
            .is_some_and(|p| {
                let width = p.bounds.map_or(p.value.abs(), |(lo, hi)| hi - lo);
                (fitted.fit.values[j] - p.value).abs() > 1e-6 * width
            })
    });
    let tolerance = 1e-3 * base.rmse_fit();
    active
        && fitted.predictions.len() == base.predictions.len()
        && fitted
            .predictions
            .iter()
            .zip(&base.predictions)
            .all(|(a, b)| (a - b).abs() <= tolerance)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Whether the candidate's own parameters move no prediction anywhere in their bounds.
fn no_effect(candidate: &Candidate, assessment: &Assessment) -> bool {
    let base = assessment.names.len() - candidate.parameters.len();
    (base..assessment.names.len()).all(|j| {
        candidate
            .model
            .parameters
            .iter()
            .find(|p| p.name == assessment.names[j])
            .and_then(|p| p.bounds)
            .is_some_and(|bounds| spans_bounds(&assessment.fit, j, bounds))
    })
}

/// Whether parameter `j` fits equally well anywhere within its `bounds` (its interval is all
/// of them): it changes no prediction.
fn spans_bounds(fit: &Fit, j: usize, (a, b): (f64, f64)) -> bool {
    fit.intervals[j].is_some_and(|(lo, hi)| {
        (lo - a).abs() <= 1e-6 * (b - a) && (hi - b).abs() <= 1e-6 * (b - a)
    })
}

/// Residuals (model minus measured) of observed column `column` by regime and along each
/// condition column, and for a time series along time.
pub(crate) fn residuals(
    experiment: &Experiment,
    column: usize,
    rows: &[Measurement],
    predictions: &[f64],
    regimes: &[String],
    noise: Option<f64>,
) -> Residuals {
    let mut names: Vec<&String> = Vec::new();
    for regime in regimes {
        if !names.contains(&regime) {
            names.push(regime);
        }
    }
    let residual = |i: usize| predictions[i] - rows[i].observed[column];
    let settled = |i: &usize| predictions[*i].is_finite();
    let by_regime = names
        .iter()
        .map(|&name| {
            let members: Vec<usize> = (0..rows.len())
                .filter(|&i| &regimes[i] == name)
                .filter(settled)
                .collect();
            let n = members.len() as f64;
            let mean = members.iter().map(|&i| residual(i)).sum::<f64>() / n;
            let rmse = (members.iter().map(|&i| residual(i).powi(2)).sum::<f64>() / n).sqrt();
            RegimeResiduals {
                regime: name.clone(),
                rows: members.len(),
                mean,
                rmse,
                stands_out: noise.is_some_and(|sd| mean.abs() > 3.0 * sd / n.sqrt()),
            }
        })
        // A regime whose every row failed to settle has no residuals.
        .filter(|r| r.rows > 0)
        .collect();
    let columns = experiment.condition_columns();
    let mut by_factor = Vec::new();
    let groups = std::iter::once((
        "all".to_string(),
        (0..rows.len()).filter(settled).collect::<Vec<_>>(),
    ))
    .chain(names.iter().map(|&name| {
        (
            name.clone(),
            (0..rows.len())
                .filter(|&i| &regimes[i] == name)
                .filter(settled)
                .collect(),
        )
    }));
    // Along each condition column (in a time series, a measured input signal) and along
    // the time column.
    let time = experiment.time().map(|(column, _)| column);
    let along: Vec<(&str, Option<usize>)> = columns
        .iter()
        .enumerate()
        .map(|(k, c)| (*c, Some(k)))
        .chain(time.map(|t| (t, None)))
        .collect();
    for (group, members) in groups {
        for &(name, k) in &along {
            let at = |i: usize| match k {
                Some(k) => rows[i].conditions[k],
                None => rows[i].time,
            };
            let points: Vec<(f64, f64)> = members
                .iter()
                .filter_map(|&i| at(i).map(|x| (x, residual(i))))
                .collect();
            if points.len() < 4 {
                continue;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = points.into_iter().unzip();
            if let Some((slope, se)) = stats::slope(&x, &y) {
                by_factor.push(FactorTrend {
                    condition: name.to_string(),
                    regime: group.clone(),
                    slope,
                    std_error: se,
                    stands_out: slope.abs() > 3.0 * se.max(1e-12),
                });
            }
        }
    }
    Residuals {
        by_regime,
        by_condition: by_factor,
    }
}

/// A model with fitted values, ready to predict any condition.
struct Fitted<'a> {
    model: &'a Model,
    source: &'a Arc<SourceFile>,
    names: &'a [String],
    values: &'a [f64],
}

impl Fitted<'_> {
    fn predict(
        &self,
        experiment: &Experiment,
        rows: &[Measurement],
    ) -> Result<Vec<f64>, DiscoverError> {
        let predictor = Predictor::new(self.model.clone(), self.source, experiment)?;
        let mut evaluator = predictor.evaluator(self.names)?;
        limit_to_settling(&mut evaluator);
        evaluator.set(self.values);
        Ok(evaluator
            .predict_each(rows)
            .into_iter()
            .map(|p| p.map_or(f64::NAN, |p| p.observed[0]))
            .collect())
    }
}

/// What every fit of one discovery shares.
struct Models<'a> {
    base_model: &'a Model,
    base: &'a Arc<SourceFile>,
    experiment: &'a Experiment,
    rows: &'a [Measurement],
    candidates: &'a [Candidate],
    settings: &'a Settings,
}

impl Models<'_> {
    /// Cross-validates the base model's fit and fits and cross-validates every candidate
    /// from it, side by side: the base model's assessment, and the candidates' in order.
    fn fit_base_and_candidates(
        &self,
        mut base_fitted: FittedOnAll,
        done: &(dyn Fn() + Sync),
    ) -> Result<(Assessment, Vec<Assessment>), DiscoverError> {
        let warm_names = base_fitted.assessment.names.clone();
        let warm_basins = base_fitted.basins.clone();
        let warm = (warm_names.as_slice(), warm_basins.as_slice());
        let base_predictions = base_fitted.assessment.predictions.clone();
        let (base_validated, assessed) = rayon::join(
            || {
                let result = cross_validate(
                    self.base_model,
                    self.base,
                    self.experiment,
                    self.rows,
                    &mut base_fitted,
                    self.settings,
                );
                done();
                result
            },
            || {
                self.candidates
                    .par_iter()
                    .map(|c| {
                        let result = assess_candidate(
                            c,
                            self.experiment,
                            self.rows,
                            warm,
                            &base_predictions,
                            self.settings,
                        );
                        done();
                        result
                    })
                    .collect::<Vec<_>>()
            },
        );
        base_validated?;
        let baseline = base_fitted.assessment;
        let assessed = assessed
            .into_iter()
            .map(|result| {
                result.map(|(mut assessment, same_as_base)| {
                    if same_as_base {
                        assessment.heldout_sse = baseline.heldout_sse;
                        assessment.heldout_count = baseline.heldout_count;
                    }
                    assessment
                })
            })
            .collect::<Result<_, _>>()?;
        Ok((baseline, assessed))
    }

    /// The base parameters of the candidate fit that, put in the base model, fit it best,
    /// when that is better than the base model's own fit.
    fn better_base_start(
        &self,
        baseline: &Assessment,
        assessed: &[Assessment],
    ) -> Result<Option<Vec<f64>>, DiscoverError> {
        let predictor = Predictor::new(self.base_model.clone(), self.base, self.experiment)?;
        let mut evaluator = predictor.evaluator(&baseline.names)?;
        limit_to_settling(&mut evaluator);
        let p = baseline.names.len();
        let mut best: Option<(f64, Vec<f64>)> = None;
        for assessment in assessed {
            let values = &assessment.fit.values[..p];
            evaluator.set(values);
            let Some(predictions) = evaluator.predict_all(self.rows) else {
                continue;
            };
            let sse: f64 = predictions
                .iter()
                .zip(self.rows)
                .map(|(p, r)| (p.observed[0] - r.observed[0]).powi(2))
                .sum();
            let bar = best.as_ref().map_or(baseline.fit.sse, |(b, _)| *b);
            if sse < bar * (1.0 - 1e-6) {
                best = Some((sse, values.to_vec()));
            }
        }
        Ok(best.map(|(_, values)| values))
    }
}

/// Runs the whole procedure on `data` (read against `experiment`).
///
/// # Errors
/// When the base model or a candidate cannot be simulated on the data, or a fitted
/// parameter has no bounds.
pub fn discover(
    base: &Arc<SourceFile>,
    experiment: &Experiment,
    data: &Dataset,
    candidates: &[Candidate],
    settings: &Settings,
) -> Result<Discovery, DiscoverError> {
    discover_with_progress(base, experiment, data, candidates, settings, &|| {})
}

/// [`discover`], calling `done` each time a model (the base or a candidate, in any order)
/// has been fitted and cross-validated: for a progress bar.
///
/// # Errors
/// As [`discover`].
pub fn discover_with_progress(
    base: &Arc<SourceFile>,
    experiment: &Experiment,
    data: &Dataset,
    candidates: &[Candidate],
    settings: &Settings,
    done: &(dyn Fn() + Sync),
) -> Result<Discovery, DiscoverError> {
    let (data_name, rows) = (data.name.as_str(), data.rows.as_slice());
    if experiment.observed.len() != 1 {
        return Err(DiscoverError::ObservedColumns(experiment.observed.len()));
    }
    if rows.len() < 8 {
        return Err(DiscoverError::TooFewRows {
            data: data_name.to_string(),
            rows: rows.len(),
            needed: 8,
        });
    }
    let base_model = model::load_source(base)?;
    let observed = experiment.observed[0].column.as_str();
    let n = rows.len() as f64;
    let base_fitted = fit_on_all(&base_model, base, experiment, rows, &[], None, settings)?;
    let models = Models {
        base_model: &base_model,
        base,
        experiment,
        rows,
        candidates,
        settings,
    };
    let (mut baseline, mut assessed) = models.fit_base_and_candidates(base_fitted, done)?;
    // A candidate contains the base model, so its fit's base parameters may show the base a
    // better basin than its own search found: refit the base from there, and the candidates
    // from the new base fit, once.
    if let Some(start) = models.better_base_start(&baseline, &assessed)? {
        let basins = [start, baseline.fit.values.clone()];
        let warm = (baseline.names.as_slice(), basins.as_slice());
        let refitted = fit_on_all(
            &base_model,
            base,
            experiment,
            rows,
            &[],
            Some(warm),
            settings,
        )?;
        (baseline, assessed) = models.fit_base_and_candidates(refitted, &|| {})?;
    }
    let p0 = baseline.names.len();

    // Verdicts.
    let untestable: Vec<bool> = candidates
        .iter()
        .zip(&assessed)
        .map(|(c, a)| no_effect(c, a))
        .collect();
    let aliased: Vec<bool> = candidates
        .iter()
        .zip(&assessed)
        .map(|(c, a)| {
            aliased_with_base(&a.fit, p0, c.parameters.len()) || reproduced_by_base(c, a, &baseline)
        })
        .collect();
    // A candidate contains the base model at its own parameters' no-effect values, and its
    // search starts there, so it cannot fit worse; if it does, those values are not without
    // effect on these rows (a flow ceiling whose highest value is below speeds the data
    // reach), and the candidate is not the base model extended here.
    let worse: Vec<bool> = assessed
        .iter()
        .map(|a| a.fit.sse > baseline.fit.sse * (1.0 + 1e-6))
        .collect();
    let tried = untestable.iter().filter(|u| !**u).count().max(1);
    let level = settings.alpha / tried as f64;
    let p_values: Vec<f64> = assessed
        .iter()
        .map(|a| {
            let k = (a.names.len() - p0) as f64;
            let dof = n - a.names.len() as f64;
            if k == 0.0 || dof <= 0.0 || a.fit.sse >= baseline.fit.sse {
                return 1.0;
            }
            let f = ((baseline.fit.sse - a.fit.sse) / k) / (a.fit.sse.max(1e-300) / dof);
            stats::f_survival(f, k, dof)
        })
        .collect();
    let qualifies: Vec<bool> = (0..candidates.len())
        .map(|i| {
            !untestable[i]
                && assessed[i].unsettled == 0
                && p_values[i] < level
                && assessed[i].aicc() < baseline.aicc()
                && assessed[i].rmse_heldout() < baseline.rmse_heldout()
        })
        .collect();
    let selected = (0..candidates.len())
        .filter(|&i| qualifies[i])
        .min_by(|&a, &b| {
            assessed[a]
                .rmse_heldout()
                .total_cmp(&assessed[b].rmse_heldout())
        });
    let best = selected.map_or(&baseline, |i| &assessed[i]);
    let best_name = selected.map_or("the base model".to_string(), |s| {
        format!("'{}'", candidates[s].id)
    });
    // Samples of a run at the same input levels are not replicates.
    let replicates = if experiment.time().is_none() {
        noise::pure_error(rows, 0)
    } else {
        None
    };
    let noise_level = NoiseLevel::estimate(
        experiment.noise,
        replicates,
        noise::Residual {
            sse: best.fit.sse,
            dof: n - best.names.len() as f64,
            model: &best_name,
            scale: noise::root_mean_square(rows, 0),
        },
    );
    let lack_of_fit = noise::lack_of_fit(&noise_level, baseline.fit.sse, rows.len(), p0);
    let noise = noise_level.sd;
    let indistinguishable: Vec<usize> = match selected {
        // Those that also explain the effect (their F-test passes) and fit no worse than the
        // selected one beyond the noise: held-out scores are left out here, since they
        // measure extrapolation, in which aliased models can differ by the luck of a fold.
        Some(s) => (0..candidates.len())
            .filter(|&i| {
                i != s
                    && !untestable[i]
                    && p_values[i] < level
                    // Without a noise level, only a fit at least as good.
                    && assessed[i].fit.sse - assessed[s].fit.sse
                        <= 4.0 * noise.map_or(0.0, |sd| sd * sd)
            })
            .collect(),
        None => (0..candidates.len())
            .filter(|&i| aliased[i] && !untestable[i])
            .collect(),
    };

    // What would separate them: a steady condition, or where along the recorded run.
    let probes = crate::probes::probes(experiment, rows);
    let runs = rows
        .iter()
        .enumerate()
        .filter(|(i, r)| *i == 0 || rows[i - 1].file != r.file)
        .count();
    let nowhere = match (experiment.time(), runs) {
        (None, _) => "no steady",
        (Some(_), 1) => "nothing along the recorded run",
        (Some(_), _) => "nothing along the recorded runs",
    };
    let reference = match selected {
        Some(s) => Fitted {
            model: &candidates[s].model,
            source: &candidates[s].source,
            names: &assessed[s].names,
            values: &assessed[s].fit.values,
        },
        None => Fitted {
            model: &base_model,
            source: base,
            names: &baseline.names,
            values: &baseline.fit.values,
        },
    };
    let reference_predictions = reference.predict(experiment, &probes)?;
    let mut separation = Vec::new();
    for &i in &indistinguishable {
        let other = Fitted {
            model: &candidates[i].model,
            source: &candidates[i].source,
            names: &assessed[i].names,
            values: &assessed[i].fit.values,
        };
        let predictions = other.predict(experiment, &probes)?;
        let (k, difference) = predictions
            .iter()
            .zip(&reference_predictions)
            .map(|(a, b)| if (a - b).is_nan() { 0.0 } else { (a - b).abs() })
            .enumerate()
            .fold(
                (0, 0.0),
                |(bk, bd), (k, d)| if d > bd { (k, d) } else { (bk, bd) },
            );
        let against = selected.map_or("the base model".to_string(), |s| {
            format!("'{}'", candidates[s].id)
        });
        let measurement = if let Some(sd) = noise
            && difference > 3.0 * sd
        {
            format!(
                "`{observed}` at {}: '{}' predicts {:.4}, {against} {:.4} ({:.1} noise levels apart)",
                crate::probes::describe(experiment, &probes[k]),
                candidates[i].id,
                predictions[k],
                reference_predictions[k],
                difference / sd
            )
        } else if noise.is_none() && difference > SAME_PREDICTION_MM_S {
            format!(
                "`{observed}` at {}: '{}' predicts {:.4}, {against} {:.4} (the largest difference; \
                 with no noise level it is not judged in noise levels)",
                crate::probes::describe(experiment, &probes[k]),
                candidates[i].id,
                predictions[k],
                reference_predictions[k],
            )
        } else {
            format!(
                "{nowhere} `{observed}` tells '{}' from {against} (they differ by at most {:.4}); {}",
                candidates[i].id,
                difference,
                candidates[i]
                    .evidence
                    .as_deref()
                    .unwrap_or("a measurement of the effect itself is needed")
            )
        };
        separation.push(Separation {
            id: candidates[i].id.clone(),
            measurement,
        });
    }

    // Ranking.
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| {
        assessed[a]
            .rmse_heldout()
            .total_cmp(&assessed[b].rmse_heldout())
    });
    let ranking = order
        .iter()
        .map(|&i| {
            let verdict = if Some(i) == selected {
                "selected"
            } else if indistinguishable.contains(&i) {
                "indistinguishable"
            } else if untestable[i] {
                "no effect on this data"
            } else if aliased[i] {
                "aliased with the base"
            } else if qualifies[i] {
                "qualifies"
            } else if worse[i] {
                WORSE_THAN_THE_BASE
            } else {
                "not significant"
            };
            Ranked {
                id: candidates[i].id.clone(),
                params: assessed[i].estimates(),
                rmse_fit: assessed[i].rmse_fit(),
                rmse_heldout: assessed[i].rmse_heldout(),
                score: assessed[i].aicc() - baseline.aicc(),
                p_value: p_values[i],
                evaluations: assessed[i].evaluations,
                verdict: verdict.to_string(),
            }
        })
        .collect();

    let regimes: Vec<String> = baseline
        .modes
        .iter()
        .map(|m| experiment.regime(m))
        .collect();
    let residuals_before = residuals(experiment, 0, rows, &baseline.predictions, &regimes, noise);
    let residuals_after = selected.map(|s| {
        let regimes: Vec<String> = assessed[s]
            .modes
            .iter()
            .map(|m| experiment.regime(m))
            .collect();
        residuals(
            experiment,
            0,
            rows,
            &assessed[s].predictions,
            &regimes,
            noise,
        )
    });
    let table = rows
        .iter()
        .enumerate()
        .map(|(i, r)| RowResult {
            time: r.time,
            conditions: data
                .conditions
                .iter()
                .cloned()
                .zip(r.conditions.iter().copied())
                .collect(),
            measured: r.observed[0],
            baseline: baseline.predictions[i],
            selected: selected.map(|s| assessed[s].predictions[i]),
            regime: regimes[i].clone(),
        })
        .collect();
    let extended_model = match selected {
        Some(s) => {
            let edit = Edit {
                remove: Vec::new(),
                parameters: assessed[s]
                    .names
                    .iter()
                    .cloned()
                    .zip(assessed[s].fit.values.iter().copied())
                    .collect(),
            };
            Some(
                edit::apply(&candidates[s].source, &edit)?
                    .text()
                    .to_string(),
            )
        }
        None => None,
    };
    Ok(Discovery {
        data: data_name.to_string(),
        rows: rows.len(),
        observed: observed.to_string(),
        noise,
        noise_source: noise_level.source,
        pure_error: noise_level.pure_error,
        lack_of_fit,
        baseline: Baseline {
            rmse_fit: baseline.rmse_fit(),
            rmse_heldout: baseline.rmse_heldout(),
            params: baseline.estimates(),
            evaluations: baseline.evaluations,
        },
        ranking,
        selected: selected.map(|s| candidates[s].id.clone()),
        cause: selected.map(|s| candidates[s].cause.clone()),
        indistinguishable: indistinguishable
            .iter()
            .map(|&i| candidates[i].id.clone())
            .collect(),
        separation,
        untestable: (0..candidates.len())
            .filter(|&i| untestable[i])
            .map(|i| candidates[i].id.clone())
            .collect(),
        gain: Gain {
            rmse_heldout_before: baseline.rmse_heldout(),
            rmse_heldout_after: best.rmse_heldout(),
        },
        residuals_before,
        residuals_after,
        table,
        extended_model,
    })
}

impl Discovery {
    /// A readable report: what the base model gets wrong, the candidates, the selection and
    /// the gain.
    pub fn summary(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        match self.noise {
            Some(sd) => {
                let _ = writeln!(
                    s,
                    "{}: {} rows, observed `{}` (every RMSE and residual below is in its \
                     units); noise {sd:.3}, {}",
                    self.data, self.rows, self.observed, self.noise_source
                );
            }
            None => {
                let _ = writeln!(
                    s,
                    "{}: {} rows, observed `{}` (every RMSE and residual below is in its \
                     units); noise: {}",
                    self.data, self.rows, self.observed, self.noise_source
                );
                let _ = writeln!(
                    s,
                    "  so nothing below is judged in noise levels (no residual stands out of \
                     the noise; candidates count as indistinguishable only if they fit as well)"
                );
            }
        }
        // Replicates that did not give the noise level: too few, or a declared noise.
        if let Some(pe) = &self.pure_error
            && (pe.dof < noise::MIN_PURE_ERROR_DOF
                || self.noise_source == "declared in the experiment")
        {
            let _ = writeln!(
                s,
                "  replicates: pure error {:.3} of {} replicated condition(s) ({} dof{})",
                pe.sd,
                pe.groups,
                pe.dof,
                if pe.dof < noise::MIN_PURE_ERROR_DOF {
                    format!(", fewer than the {} needed", noise::MIN_PURE_ERROR_DOF)
                } else {
                    String::new()
                }
            );
        }
        if let Some(test) = &self.lack_of_fit {
            let _ = writeln!(s, "  lack of fit of the base model: {}", test.text());
        }
        let _ = writeln!(
            s,
            "\nbase model, refitted: RMSE {:.3} on the fit, {:.3} held out",
            self.baseline.rmse_fit, self.baseline.rmse_heldout
        );
        for (name, e) in &self.baseline.params {
            let _ = writeln!(s, "  {name} = {}", estimate_text(e));
        }
        let _ = writeln!(s, "\nwhat it gets wrong (model minus measured):");
        write_residuals(&mut s, &self.residuals_before);
        let _ = writeln!(s, "\ncandidates, best held-out RMSE first:");
        let _ = writeln!(
            s,
            "  {:<30} {:>9} {:>9} {:>8} {:>9}  verdict",
            "id", "fit", "held-out", "dAICc", "p"
        );
        for r in &self.ranking {
            let _ = writeln!(
                s,
                "  {:<30} {:>9.3} {:>9.3} {:>8.1} {:>9.2e}  {}",
                r.id, r.rmse_fit, r.rmse_heldout, r.score, r.p_value, r.verdict
            );
        }
        match &self.selected {
            Some(id) => {
                let _ = writeln!(
                    s,
                    "\nselected: {id}: {}",
                    self.cause.as_deref().unwrap_or("")
                );
                if let Some(r) = self.ranking.iter().find(|r| &r.id == id) {
                    for (name, e) in &r.params {
                        let _ = writeln!(s, "  {name} = {}", estimate_text(e));
                    }
                }
                if let Some(after) = &self.residuals_after {
                    let _ = writeln!(s, "residuals after:");
                    write_residuals(&mut s, after);
                }
            }
            None => {
                let _ = writeln!(
                    s,
                    "\nselected: null (no candidate gains beyond what the noise explains)"
                );
            }
        }
        let _ = writeln!(
            s,
            "held-out RMSE: {:.3} before, {:.3} after",
            self.gain.rmse_heldout_before, self.gain.rmse_heldout_after
        );
        if !self.separation.is_empty() {
            let against = self.selected.as_deref().unwrap_or("the base model");
            let _ = writeln!(s, "\ncannot be told apart from {against} on this data:");
            for sep in &self.separation {
                let _ = writeln!(s, "  {}: {}", sep.id, sep.measurement);
            }
        }
        if !self.untestable.is_empty() {
            let _ = writeln!(
                s,
                "\nno effect on this data (untestable here): {}",
                self.untestable.join(", ")
            );
        }
        let worse: Vec<&Ranked> = self
            .ranking
            .iter()
            .filter(|r| r.verdict == WORSE_THAN_THE_BASE)
            .collect();
        if !worse.is_empty() {
            let _ = writeln!(
                s,
                "\nworse than the base model even at their no-effect values, so within their \
                 bounds they cannot contain it on this data (widen the bounds in the extension \
                 file):"
            );
            for r in worse {
                let _ = writeln!(
                    s,
                    "  {}: RMSE {:.3} against the base model's {:.3}",
                    r.id, r.rmse_fit, self.baseline.rmse_fit
                );
            }
        }
        s
    }
}

/// An estimate as text: the value, `± SE`, the interval of a threshold, `(at its bound)`, or
/// that the data do not determine it.
pub fn estimate_text(e: &Estimate) -> String {
    let mut s = number(e.value, 6);
    if let Some(se) = e.std_error {
        s.push_str(&format!(" ± {se:.3e}"));
    }
    if let Some((lo, hi)) = e.interval {
        s.push_str(&format!(
            " (any value in [{}, {}] fits as well)",
            number(lo, 4),
            number(hi, 4)
        ));
    }
    if e.at_bound {
        s.push_str(" (at its bound)");
    }
    if e.std_error.is_none() && e.interval.is_none() && !e.at_bound {
        // Aliased with others, or moving the residuals too little to have an error.
        s.push_str(" (not determined by this data)");
    }
    s
}

/// `value` with `decimals` decimals, or in scientific notation with as many where fixed
/// decimals would hide it (a flow of 4e-7 m³/s) or bury it in digits.
fn number(value: f64, decimals: usize) -> String {
    if value == 0.0 || (1e-3..1e6).contains(&value.abs()) {
        format!("{value:.decimals$}")
    } else {
        format!("{value:.decimals$e}")
    }
}

/// Residuals as text, one line per regime and per trend beyond the noise.
pub fn write_residuals(s: &mut String, residuals: &Residuals) {
    use std::fmt::Write;
    for r in &residuals.by_regime {
        let _ = writeln!(
            s,
            "  {:<18} {:>2} rows: mean {:+.3}, RMS {:.3}{}",
            r.regime,
            r.rows,
            r.mean,
            r.rmse,
            if r.stands_out {
                "  <- beyond the noise"
            } else {
                ""
            }
        );
    }
    for t in residuals.by_condition.iter().filter(|t| t.stands_out) {
        let _ = writeln!(
            s,
            "  trend along {} ({}): {:+.4} ± {:.4} per unit  <- beyond the noise",
            t.condition, t.regime, t.slope, t.std_error
        );
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    /// A fit of three rows whose Jacobian has the columns `columns` (base ones first).
    fn fit_with(columns: &[[f64; 3]]) -> crate::calibrate::Fit {
        let p = columns.len();
        crate::calibrate::Fit {
            values: vec![0.0; p],
            residuals: vec![0.0; 3],
            sse: 0.0,
            std_errors: vec![None; p],
            intervals: vec![None; p],
            at_bound: vec![false; p],
            jacobian: (0..3)
                .flat_map(|i| columns.iter().map(move |c| c[i]))
                .collect(),
            evaluations: 0,
        }
    }

    #[test]
    fn an_alias_is_found_when_two_base_columns_tie() {
        // Two thresholds tied on a face move the residuals alike: columns 0 and 1 are
        // equal, and the candidate's column 3 = 2 x column 0 + column 2 is in their span.
        let base = [[1.0, 2.0, 0.0], [1.0, 2.0, 0.0], [0.0, 1.0, 1.0]];
        let alias = [2.0, 5.0, 1.0];
        let fit = fit_with(&[base[0], base[1], base[2], alias]);
        assert!(super::aliased_with_base(&fit, 3, 1));
        // One that leaves their span is not.
        let fit = fit_with(&[base[0], base[1], base[2], [1.0, 0.0, 0.0]]);
        assert!(!super::aliased_with_base(&fit, 3, 1));
    }

    #[test]
    fn an_estimate_says_what_the_data_determine() {
        let e = |std_error, interval, at_bound| {
            super::estimate_text(&super::Estimate {
                value: 2.0,
                std_error,
                interval,
                at_bound,
            })
        };
        assert_eq!(e(Some(0.5), None, false), "2.000000 ± 5.000e-1");
        assert_eq!(
            e(None, Some((1.0, 3.0)), false),
            "2.000000 (any value in [1.0000, 3.0000] fits as well)"
        );
        assert_eq!(e(None, None, true), "2.000000 (at its bound)");
        assert_eq!(
            e(None, None, false),
            "2.000000 (not determined by this data)"
        );
    }

    #[test]
    fn numbers_keep_their_digits_at_any_scale() {
        assert_eq!(number(1234.5678, 2), "1234.57");
        assert_eq!(number(0.0, 6), "0.000000");
        assert_eq!(number(3.767e-7, 6), "3.767000e-7");
        assert_eq!(number(-2.5e8, 4), "-2.5000e8");
    }
}
