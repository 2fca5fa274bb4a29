//! The whole procedure: the base model and every candidate fitted and cross-validated,
//! then the verdicts, the separating measurements, the ranking and the report's table.

use std::sync::Arc;

use bondgraph_core::model::edit::{self, Edit};
use bondgraph_core::model::{self, Model};
use bondgraph_core::source::SourceFile;
use rayon::prelude::*;

use super::alias::{aliased_with_base, no_effect, reproduced_by_base};
use super::cross_validation::{SAME_PREDICTION_MM_S, assess_candidate, cross_validate};
use super::fit::{Assessment, FittedOnAll, fit_on_all, limit_to_settling};
use super::residuals::residuals;
use super::*;
use crate::data::{Dataset, Measurement};
use crate::experiment::Experiment;
use crate::noise::{self, NoiseLevel};
use crate::predict::Predictor;
use crate::stats;

/// The verdict of a candidate that fits worse than the base model it contains.
pub(super) const WORSE_THAN_THE_BASE: &str = "worse than the base";

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
