//! The whole procedure: the base model and every candidate fitted and cross-validated,
//! then the verdicts, the separating measurements, the ranking and the report's table.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use bondgraph_ron::model::edit::{self, Edit};
use rayon::prelude::*;

use super::cross_validation::{assess_candidate, cross_validate, predicts_as, same_prediction};
use super::fit::{Assessment, FittedOnAll, fit_on_all, limit_to_budget};
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
        settings: &Settings,
    ) -> Result<Vec<f64>, DiscoverError> {
        let predictor = Predictor::new(self.model.clone(), self.source, experiment)?;
        let mut evaluator = predictor.evaluator(self.names)?;
        limit_to_budget(&mut evaluator, settings);
        evaluator.set(self.values);
        let columns = experiment.observed.len();
        Ok(evaluator
            .predict_each(rows)
            .into_iter()
            .flat_map(|p| p.map_or(vec![f64::NAN; columns], |p| p.observed))
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
    /// The observed columns' names, and what a prediction in `experiment`'s units is
    /// multiplied by to be in the column's (1; with several columns, each one's noise).
    pub(super) columns: &'a [String],
    pub(super) scales: &'a [f64],
}

impl Models<'_> {
    /// The base model and every candidate fitted and cross-validated; then, when a
    /// candidate's fit shows the base model a better basin than its own search found (a
    /// candidate contains the base model, so its base parameters can), the base refitted
    /// from there, once, and the candidates whose fits are now worse than the base's
    /// refitted from the new base fit. A candidate contains the base model, so its fit
    /// must be at least as good as the base's for the two to be compared (the F-test's
    /// extra sum of squares is the base's minus the candidate's); a candidate already that
    /// good keeps its fit and its folds, which a refit from the new basin would repeat
    /// (on the actuator's runs with load-dependent friction hidden, three such refits
    /// ended on the sums of squares they started from, at half the analysis's time).
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
        let (baseline, assessed, basins) =
            self.fit_base_and_candidates(fit_base(None)?, Vec::new(), done)?;
        let Some(start) = self.better_base_start(&baseline, &assessed)? else {
            return Ok((baseline, assessed, basins));
        };
        let basins = [start, baseline.fit.values.clone()];
        let refitted = fit_base(Some((baseline.names.as_slice(), basins.as_slice())))?;
        // Kept: the fits at least as good as the new base's, with folds of their own (not
        // the held-out errors of the first base fit, lent to those that predicted as it).
        let bar = refitted.assessment.fit.sse;
        let same = same_prediction(self.experiment, self.rows, &baseline);
        let kept = assessed
            .into_iter()
            .map(|assessment| {
                let own_folds = !predicts_as(&assessment.predictions, &baseline.predictions, same);
                (assessment.fit.sse <= bar && own_folds).then_some(assessment)
            })
            .collect();
        self.fit_base_and_candidates(refitted, kept, &|| {})
    }

    /// `'id'` of candidate `selected`, or `the base model`.
    pub(super) fn name(&self, selected: Option<usize>) -> String {
        selected.map_or("the base model".to_string(), |s| {
            format!("'{}'", self.candidates[s].id)
        })
    }

    /// Cross-validates the base model's fit and fits and cross-validates every candidate
    /// from it, side by side: the base model's assessment, the candidates' in order, and the
    /// base model's basins. A candidate with an assessment in `kept` (in the candidates'
    /// order; missing or `None`: none) keeps it, with only its likeness to the base model's
    /// predictions judged again.
    fn fit_base_and_candidates(
        &self,
        mut base_fitted: FittedOnAll,
        mut kept: Vec<Option<Assessment>>,
        done: &(dyn Fn() + Sync),
    ) -> Result<FittedAll, DiscoverError> {
        kept.resize_with(self.candidates.len(), || None);
        let warm_names = base_fitted.assessment.names.clone();
        let warm_basins = base_fitted.basins.clone();
        let warm = (warm_names.as_slice(), warm_basins.as_slice());
        let base_predictions = base_fitted.assessment.predictions.clone();
        let same = same_prediction(self.experiment, self.rows, &base_fitted.assessment);
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
                    .zip(kept)
                    .map(|(c, kept)| {
                        let result = match kept {
                            Some(assessment) => {
                                let same_as_base =
                                    predicts_as(&assessment.predictions, &base_predictions, same);
                                Ok((assessment, same_as_base))
                            }
                            None => assess_candidate(
                                c,
                                self.experiment,
                                self.rows,
                                warm,
                                (&base_predictions, same),
                                self.settings,
                            ),
                        };
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
                        assessment.heldout_by_column = baseline.heldout_by_column.clone();
                        assessment.heldout_cells = baseline.heldout_cells.clone();
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
        limit_to_budget(&mut evaluator, self.settings);
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
                .flat_map(|(p, r)| p.observed.iter().zip(&r.observed))
                .map(|(p, m)| (p - m).powi(2))
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
    if rows.len() < 8 {
        return Err(DiscoverError::TooFewRows {
            data: data_name.to_string(),
            rows: rows.len(),
            needed: 8,
        });
    }
    let base_model = bondgraph_ron::model::load_source(base)?;
    let columns: Vec<String> = experiment
        .observed
        .iter()
        .map(|o| o.column.clone())
        .collect();
    if columns.len() == 1 {
        let models = Models {
            base_model: &base_model,
            base,
            experiment,
            rows,
            candidates,
            settings,
            columns: &columns,
            scales: &[1.0],
        };
        return models.discover(data, None, done);
    }
    let levels = column_levels(&base_model, base, experiment, rows, settings)?;
    let scales: Vec<f64> = levels
        .iter()
        .map(|l| l.sd.expect("a weighing level"))
        .collect();
    let (scaled_experiment, scaled_rows) = crate::weights::scaled(experiment, rows, &scales);
    let models = Models {
        base_model: &base_model,
        base,
        experiment: &scaled_experiment,
        rows: &scaled_rows,
        candidates,
        settings,
        columns: &columns,
        scales: &scales,
    };
    models.discover(data, Some(Weighed { experiment, levels }), done)
}

/// Several observed columns' noise levels, which weigh the fits: declared, or pure error,
/// else the residual of the base model fitted with each column weighed by the spread of its
/// values ([`crate::weights`]).
fn column_levels(
    base_model: &Model,
    base: &Arc<SourceFile>,
    experiment: &Experiment,
    rows: &[Measurement],
    settings: &Settings,
) -> Result<Vec<NoiseLevel>, DiscoverError> {
    use crate::weights;
    let m = experiment.observed.len();
    let known: Vec<Option<NoiseLevel>> = (0..m)
        .map(|k| weights::known_level(experiment, rows, k))
        .collect();
    if known.iter().all(Option::is_some) {
        return Ok(known.into_iter().flatten().collect());
    }
    let provisional: Vec<f64> = (0..m)
        .map(|k| {
            known[k]
                .as_ref()
                .and_then(|l| l.sd)
                .unwrap_or_else(|| weights::spread(rows, k))
        })
        .collect();
    let (scaled_experiment, scaled_rows) = weights::scaled(experiment, rows, &provisional);
    let fitted = fit_on_all(
        base_model,
        base,
        &scaled_experiment,
        &scaled_rows,
        &[],
        None,
        settings,
    )?
    .assessment;
    let n = rows.len() as f64;
    let p = fitted.names.len() as f64;
    Ok(known
        .into_iter()
        .enumerate()
        .map(|(k, level)| {
            level.unwrap_or_else(|| {
                let sse: f64 = rows
                    .iter()
                    .enumerate()
                    .map(|(i, r)| {
                        (fitted.predictions[i * m + k] * provisional[k] - r.observed[k]).powi(2)
                    })
                    .sum();
                let mut level = NoiseLevel::estimate(
                    None,
                    crate::weights::replicates(experiment, rows, k),
                    noise::Residual {
                        sse,
                        dof: n - p / m as f64,
                        model: "the base model",
                        scale: noise::root_mean_square(rows, k),
                    },
                );
                if level.sd.is_none() {
                    // An exact fit of this column: it weighs the others' by their spread.
                    level.sd = Some(provisional[k]);
                    level.source = format!("{}; weighed by its spread", level.source);
                }
                level
            })
        })
        .collect())
}

/// With several observed columns, what the report converts back to the columns' units: the
/// experiment as written (the fits ran in noise levels) and each column's noise.
struct Weighed<'a> {
    experiment: &'a Experiment,
    levels: Vec<NoiseLevel>,
}

impl Models<'_> {
    /// The procedure on this data: one observed column as it is, several in noise levels
    /// (`weighed`).
    fn discover(
        &self,
        data: &Dataset,
        weighed: Option<Weighed<'_>>,
        done: &(dyn Fn() + Sync),
    ) -> Result<Discovery, DiscoverError> {
        let (experiment, rows, candidates) = (self.experiment, self.rows, self.candidates);
        let m = self.columns.len();
        let (baseline, assessed, base_basins) = self.fit_all(done)?;
        let verdicts = Verdicts::judge(candidates, &assessed, &baseline, self.settings.alpha);
        let selected = verdicts.selected;
        let best = selected.map_or(&baseline, |i| &assessed[i]);
        // One column: its noise level. Several: every column is in its noise levels.
        let levels: Vec<NoiseLevel> = match &weighed {
            None => vec![noise_level(experiment, rows, best, &self.name(selected))],
            Some(w) => w.levels.clone(),
        };
        let lack_of_fit = self.lack_of_fit(weighed.as_ref(), &levels[0], &baseline);
        // What the verdicts are judged against, in the fits' units.
        let noise = match &weighed {
            None => levels[0].sd,
            Some(_) => Some(1.0),
        };
        let indistinguishable = verdicts.indistinguishable(&assessed, noise);
        let stability = stability::assess(
            self,
            &baseline,
            &base_basins,
            &assessed,
            &verdicts,
            &indistinguishable,
        );
        let separation =
            self.separations(&baseline, &assessed, selected, &indistinguishable, noise)?;
        let ranking = ranking(
            candidates,
            &assessed,
            &baseline,
            &verdicts,
            &indistinguishable,
            |a: &Assessment| self.column_scores(a),
        );
        let regimes = |a: &Assessment| -> Vec<String> {
            a.modes.iter().map(|m| experiment.regime(m)).collect()
        };
        let base_regimes = regimes(&baseline);
        let pooled = |a: &Assessment, regimes: &[String]| self.pooled_residuals(a, regimes, noise);
        let residuals_before = pooled(&baseline, &base_regimes);
        let residuals_after = selected.map(|s| pooled(&assessed[s], &regimes(&assessed[s])));
        let unscaled = |a: &Assessment, k: usize| -> Vec<f64> {
            (0..rows.len())
                .map(|i| a.predictions[i * m + k] * self.scales[k])
                .collect()
        };
        let columns = match &weighed {
            None => Vec::new(),
            Some(w) => (0..m)
                .map(|k| ColumnResiduals {
                    column: self.columns[k].clone(),
                    residuals_before: residuals(
                        w.experiment,
                        k,
                        &data.rows,
                        &unscaled(&baseline, k),
                        &base_regimes,
                        w.levels[k].sd,
                    ),
                    residuals_after: selected.map(|s| {
                        residuals(
                            w.experiment,
                            k,
                            &data.rows,
                            &unscaled(&assessed[s], k),
                            &regimes(&assessed[s]),
                            w.levels[k].sd,
                        )
                    }),
                })
                .collect(),
        };
        let table = self.table(
            data,
            &baseline,
            selected.map(|s| &assessed[s]),
            &base_regimes,
        );
        let extended_model = selected
            .map(|s| extended_model(&candidates[s], &assessed[s]))
            .transpose()?;
        Ok(Discovery {
            data: data.name.clone(),
            rows: rows.len(),
            observed: self.columns.to_vec(),
            noise: levels.iter().map(|l| l.sd).collect(),
            noise_source: levels.iter().map(|l| l.source.clone()).collect(),
            pure_error: levels.iter().map(|l| l.pure_error.clone()).collect(),
            lack_of_fit,
            baseline: Baseline {
                rmse_fit: baseline.rmse_fit(),
                rmse_heldout: baseline.rmse_heldout(),
                params: baseline.estimates(),
                evaluations: baseline.evaluations,
                columns: self.column_scores(&baseline),
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
            columns,
            table,
            stability,
            failed_trials: failed_trials(candidates, &baseline, &assessed, &self.settings.budget),
            extended_model,
        })
    }

    /// The base model's lack of fit against the noise, where the noise is known apart from
    /// it (one column: its level; several: each column's, declared or pure error).
    fn lack_of_fit(
        &self,
        weighed: Option<&Weighed<'_>>,
        level: &NoiseLevel,
        baseline: &Assessment,
    ) -> Option<noise::LackOfFit> {
        match weighed {
            None => noise::lack_of_fit(
                level,
                baseline.fit.sse,
                self.rows.len(),
                baseline.names.len(),
            ),
            Some(w) if w.levels.iter().all(|l| l.origin != noise::Origin::Residual) => {
                noise::lack_of_fit(
                    &NoiseLevel {
                        sd: Some(1.0),
                        origin: noise::Origin::Declared,
                        source: String::new(),
                        pure_error: None,
                    },
                    baseline.fit.sse,
                    self.rows.len() * self.columns.len(),
                    baseline.names.len(),
                )
            }
            Some(_) => None,
        }
    }

    /// Every column's residuals pooled (one column: its own).
    fn pooled_residuals(
        &self,
        a: &Assessment,
        regimes: &[String],
        noise: Option<f64>,
    ) -> Residuals {
        let m = self.columns.len();
        if m == 1 {
            return residuals(
                self.experiment,
                0,
                self.rows,
                &a.predictions,
                regimes,
                noise,
            );
        }
        let mut pooled_rows = Vec::with_capacity(self.rows.len() * m);
        let mut pooled_predictions = Vec::with_capacity(self.rows.len() * m);
        let mut pooled_regimes = Vec::with_capacity(self.rows.len() * m);
        for k in 0..m {
            for (i, row) in self.rows.iter().enumerate() {
                let mut row = row.clone();
                row.observed = vec![row.observed[k]];
                pooled_rows.push(row);
                pooled_predictions.push(a.predictions[i * m + k]);
                pooled_regimes.push(regimes[i].clone());
            }
        }
        residuals(
            self.experiment,
            0,
            &pooled_rows,
            &pooled_predictions,
            &pooled_regimes,
            noise,
        )
    }

    /// Each row: its conditions, what was measured, and what the base model and the selected
    /// candidate predict, in the columns' units.
    fn table(
        &self,
        data: &Dataset,
        baseline: &Assessment,
        selected: Option<&Assessment>,
        base_regimes: &[String],
    ) -> Vec<RowResult> {
        let m = self.columns.len();
        data.rows
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
                measured: r.observed.clone(),
                baseline: (0..m)
                    .map(|k| baseline.predictions[i * m + k] * self.scales[k])
                    .collect(),
                selected: selected.map(|s| {
                    (0..m)
                        .map(|k| s.predictions[i * m + k] * self.scales[k])
                        .collect()
                }),
                regime: base_regimes[i].clone(),
            })
            .collect()
    }

    /// With several observed columns, each one's RMSEs in its units; none with one.
    fn column_scores(&self, a: &Assessment) -> Vec<ColumnScore> {
        let m = self.columns.len();
        if m == 1 {
            return Vec::new();
        }
        let n = self.rows.len() as f64;
        let heldout_rows = (a.heldout_count / m).max(1) as f64;
        (0..m)
            .map(|k| {
                let sse: f64 = self
                    .rows
                    .iter()
                    .enumerate()
                    .map(|(i, r)| (a.predictions[i * m + k] - r.observed[k]).powi(2))
                    .sum();
                ColumnScore {
                    column: self.columns[k].clone(),
                    rmse_fit: (sse / n).sqrt() * self.scales[k],
                    rmse_heldout: (a.heldout_by_column[k] / heldout_rows).sqrt() * self.scales[k],
                }
            })
            .collect()
    }
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
    let replicates = crate::weights::replicates(experiment, rows, 0);
    NoiseLevel::estimate(
        experiment.declared_noise(0),
        replicates,
        noise::Residual {
            sse: best.fit.sse,
            dof: rows.len() as f64 - best.names.len() as f64,
            model: best_name,
            scale: noise::root_mean_square(rows, 0),
        },
    )
}

/// The failed trials of the base model's fits (`base`) and each candidate's.
fn failed_trials(
    candidates: &[Candidate],
    baseline: &Assessment,
    assessed: &[Assessment],
    budget: &crate::budget::Budget,
) -> Vec<crate::budget::FailedTrials> {
    std::iter::once(("base", baseline))
        .chain(candidates.iter().map(|c| c.id.as_str()).zip(assessed))
        .flat_map(|(model, a)| crate::budget::failed_trials(model, &a.trials, budget))
        .collect()
}

/// The candidates best held-out RMSE first, each with its verdict.
fn ranking(
    candidates: &[Candidate],
    assessed: &[Assessment],
    baseline: &Assessment,
    verdicts: &Verdicts,
    indistinguishable: &[usize],
    column_scores: impl Fn(&Assessment) -> Vec<ColumnScore>,
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
            columns: column_scores(&assessed[i]),
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
