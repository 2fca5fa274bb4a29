//! The whole procedure: the base model and every candidate fitted and cross-validated,
//! then the verdicts, the separating measurements, the ranking and the report's table.

use std::sync::Arc;

use bondgraph_core::model::edit::{self, Edit};
use bondgraph_core::model::{self, Model};
use bondgraph_core::source::SourceFile;
use rayon::prelude::*;

use super::cross_validation::{assess_candidate, cross_validate};
use super::fit::{Assessment, FittedOnAll, fit_on_all, limit_to_settling};
use super::residuals::residuals;
use super::stability;
use super::verdicts::Verdicts;
use super::*;
use crate::data::{Dataset, Measurement};
use crate::experiment::Experiment;
use crate::noise::{self, NoiseLevel};
use crate::predict::Predictor;

/// A model with fitted values, ready to predict any condition.
pub(super) struct Fitted<'a> {
    pub(super) model: &'a Model,
    pub(super) source: &'a Arc<SourceFile>,
    pub(super) names: &'a [String],
    pub(super) values: &'a [f64],
}

impl Fitted<'_> {
    pub(super) fn predict(
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

/// The base model's assessment, the candidates' in order, and the base model's basins.
type FittedAll = (Assessment, Vec<Assessment>, Vec<Vec<f64>>);

/// What every fit of one discovery shares.
pub(super) struct Models<'a> {
    pub(super) base_model: &'a Model,
    pub(super) base: &'a Arc<SourceFile>,
    pub(super) experiment: &'a Experiment,
    pub(super) rows: &'a [Measurement],
    pub(super) candidates: &'a [Candidate],
    pub(super) settings: &'a Settings,
}

impl Models<'_> {
    /// The base model and every candidate fitted and cross-validated; then, when a
    /// candidate's fit shows the base model a better basin than its own search found (a
    /// candidate contains the base model, so its base parameters can), the base refitted
    /// from there and the candidates from the new base fit, once.
    /// With them, the basins of the base model's search (its optimum first).
    fn fit_all(&self, done: &(dyn Fn() + Sync)) -> Result<FittedAll, DiscoverError> {
        let fit_base = |warm: Option<(&[String], &[Vec<f64>])>| {
            fit_on_all(
                self.base_model,
                self.base,
                self.experiment,
                self.rows,
                &[],
                warm,
                self.settings,
            )
        };
        let (baseline, assessed, basins) = self.fit_base_and_candidates(fit_base(None)?, done)?;
        let Some(start) = self.better_base_start(&baseline, &assessed)? else {
            return Ok((baseline, assessed, basins));
        };
        let basins = [start, baseline.fit.values.clone()];
        let refitted = fit_base(Some((baseline.names.as_slice(), basins.as_slice())))?;
        self.fit_base_and_candidates(refitted, &|| {})
    }

    /// `'id'` of candidate `selected`, or `the base model`.
    pub(super) fn name(&self, selected: Option<usize>) -> String {
        selected.map_or("the base model".to_string(), |s| {
            format!("'{}'", self.candidates[s].id)
        })
    }

    /// Cross-validates the base model's fit and fits and cross-validates every candidate
    /// from it, side by side: the base model's assessment, the candidates' in order, and the
    /// base model's basins.
    fn fit_base_and_candidates(
        &self,
        mut base_fitted: FittedOnAll,
        done: &(dyn Fn() + Sync),
    ) -> Result<FittedAll, DiscoverError> {
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
        Ok((baseline, assessed, warm_basins))
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
    let models = Models {
        base_model: &base_model,
        base,
        experiment,
        rows,
        candidates,
        settings,
    };
    let (baseline, assessed, base_basins) = models.fit_all(done)?;
    let verdicts = Verdicts::judge(candidates, &assessed, &baseline, settings.alpha);
    let selected = verdicts.selected;
    let best = selected.map_or(&baseline, |i| &assessed[i]);
    let noise_level = noise_level(experiment, rows, best, &models.name(selected));
    let lack_of_fit = noise::lack_of_fit(
        &noise_level,
        baseline.fit.sse,
        rows.len(),
        baseline.names.len(),
    );
    let noise = noise_level.sd;
    let indistinguishable = verdicts.indistinguishable(&assessed, noise);
    let stability = stability::assess(
        &models,
        &baseline,
        &base_basins,
        &assessed,
        &verdicts,
        &indistinguishable,
    );
    let separation =
        models.separations(&baseline, &assessed, selected, &indistinguishable, noise)?;
    let ranking = ranking(
        candidates,
        &assessed,
        &baseline,
        &verdicts,
        &indistinguishable,
    );
    let regimes =
        |a: &Assessment| -> Vec<String> { a.modes.iter().map(|m| experiment.regime(m)).collect() };
    let base_regimes = regimes(&baseline);
    let residuals_before = residuals(
        experiment,
        0,
        rows,
        &baseline.predictions,
        &base_regimes,
        noise,
    );
    let residuals_after = selected.map(|s| {
        residuals(
            experiment,
            0,
            rows,
            &assessed[s].predictions,
            &regimes(&assessed[s]),
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
            regime: base_regimes[i].clone(),
        })
        .collect();
    let extended_model = selected
        .map(|s| extended_model(&candidates[s], &assessed[s]))
        .transpose()?;
    Ok(Discovery {
        data: data_name.to_string(),
        rows: rows.len(),
        observed: experiment.observed[0].column.clone(),
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
            .filter(|&i| verdicts.untestable[i])
            .map(|i| candidates[i].id.clone())
            .collect(),
        gain: Gain {
            rmse_heldout_before: baseline.rmse_heldout(),
            rmse_heldout_after: best.rmse_heldout(),
        },
        residuals_before,
        residuals_after,
        table,
        stability,
        extended_model,
    })
}

/// The noise level the verdicts are judged against: the experiment's declared one, else
/// the pure error of replicated steady conditions, else the residual of `best` (named
/// `best_name`).
fn noise_level(
    experiment: &Experiment,
    rows: &[Measurement],
    best: &Assessment,
    best_name: &str,
) -> NoiseLevel {
    // Samples of a run at the same input levels are not replicates.
    let replicates = if experiment.time().is_none() {
        noise::pure_error(rows, 0)
    } else {
        None
    };
    NoiseLevel::estimate(
        experiment.noise,
        replicates,
        noise::Residual {
            sse: best.fit.sse,
            dof: rows.len() as f64 - best.names.len() as f64,
            model: best_name,
            scale: noise::root_mean_square(rows, 0),
        },
    )
}

/// The candidates best held-out RMSE first, each with its verdict.
fn ranking(
    candidates: &[Candidate],
    assessed: &[Assessment],
    baseline: &Assessment,
    verdicts: &Verdicts,
    indistinguishable: &[usize],
) -> Vec<Ranked> {
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| {
        assessed[a]
            .rmse_heldout()
            .total_cmp(&assessed[b].rmse_heldout())
    });
    order
        .iter()
        .map(|&i| Ranked {
            id: candidates[i].id.clone(),
            params: assessed[i].estimates(),
            rmse_fit: assessed[i].rmse_fit(),
            rmse_heldout: assessed[i].rmse_heldout(),
            score: assessed[i].aicc() - baseline.aicc(),
            p_value: verdicts.p_values[i],
            evaluations: assessed[i].evaluations,
            verdict: verdicts.word(i, indistinguishable).to_string(),
        })
        .collect()
}

/// The selected candidate's model file with its fitted values written in.
fn extended_model(candidate: &Candidate, fitted: &Assessment) -> Result<String, DiscoverError> {
    let edit = Edit {
        remove: Vec::new(),
        parameters: fitted
            .names
            .iter()
            .cloned()
            .zip(fitted.fit.values.iter().copied())
            .collect(),
    };
    Ok(edit::apply(&candidate.source, &edit)?.text().to_string())
}
