//! Held-out errors: each fold refitted from the full fit's basins, scored on what it left
//! out; and a candidate's assessment, which skips its folds when it predicts as the base does.

use std::sync::Arc;

use bondgraph_core::model::Model;
use bondgraph_core::source::SourceFile;
use rayon::prelude::*;

use super::fit::{Assessment, FittedOnAll, fit_best, fit_on_all, limit_to_budget};
use super::{Candidate, DiscoverError, Settings};
use crate::budget::Trials;
use crate::calibrate::CalibrationError;
use crate::data::Measurement;
use crate::experiment::Experiment;
use crate::global::Search;
use crate::noise::{self, NoiseLevel};
use crate::predict::Predictor;

/// Two models whose fits predict every row within this fraction of the noise are one model
/// on the data ([`same_prediction`]).
///
/// Why a fiftieth: a candidate whose predictions stay within `δ = σ/50` of the base model's
/// can lower the base's sum of squares by at most `2δ/σ + (δ/σ)² ≈ 4 %` where the base fits
/// to the noise, far below what the F-test at 0.01 needs to select it; so its folds, which
/// would refit the base model, are skipped.
pub(super) const SAME_PREDICTION_NOISE: f64 = 1.0 / 50.0;

/// How close two fits' predictions must be to count as the same, in the observed column's
/// units: [`SAME_PREDICTION_NOISE`] of the noise level as the data give it before any
/// candidate is fitted (declared, else the pure error of replicated steady conditions, else
/// the base model's residual, [`crate::noise::NoiseLevel::estimate`]); for data the base model
/// fits exactly, rounding: [`crate::noise::ROUNDING`] of the column's root mean square.
pub(super) fn same_prediction(
    experiment: &Experiment,
    rows: &[Measurement],
    base: &Assessment,
) -> f64 {
    if experiment.observed.len() > 1 {
        // Several columns are fitted in their noise levels ([`crate::weights`]).
        return SAME_PREDICTION_NOISE;
    }
    let replicates = if experiment.time().is_none() {
        noise::pure_error(rows, 0)
    } else {
        None
    };
    let scale = noise::root_mean_square(rows, 0);
    let level = NoiseLevel::estimate(
        experiment.noise.first().copied(),
        replicates,
        noise::Residual {
            sse: base.fit.sse,
            dof: rows.len() as f64 - base.names.len() as f64,
            model: "the base model",
            scale,
        },
    );
    match level.sd {
        Some(sd) if sd > 0.0 && sd.is_finite() => SAME_PREDICTION_NOISE * sd,
        _ => noise::ROUNDING * scale,
    }
}

/// Whether two fits' predictions of every row are within `same` of each other
/// ([`same_prediction`]).
pub(super) fn predicts_as(predictions: &[f64], base_predictions: &[f64], same: f64) -> bool {
    predictions
        .iter()
        .zip(base_predictions)
        .all(|(a, b)| (a - b).abs() <= same)
}

pub(super) fn assess_candidate(
    candidate: &Candidate,
    experiment: &Experiment,
    rows: &[Measurement],
    warm: (&[String], &[Vec<f64>]),
    (base_predictions, same): (&[f64], f64),
    settings: &Settings,
) -> Result<(Assessment, bool), DiscoverError> {
    // A search that cannot start names the candidate it was fitting.
    let named = |error: DiscoverError| match error {
        DiscoverError::Calibration { data, error } => DiscoverError::Calibration {
            data,
            error: CalibrationError(format!("candidate '{}': {}", candidate.id, error.0)),
        },
        other => other,
    };
    let mut fitted = fit_on_all(
        &candidate.model,
        &candidate.source,
        experiment,
        rows,
        &candidate.parameters,
        Some(warm),
        settings,
    )
    .map_err(named)?;
    let same_as_base = predicts_as(&fitted.assessment.predictions, base_predictions, same);
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
    )
    .map_err(named)?;
    Ok((fitted.assessment, false))
}

/// The held-out errors of a model fitted on all rows: leave one level out of a condition
/// column, then k-fold, each fold refitted ([`crate::folds`]).
pub(super) fn cross_validate(
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
    let pick = |indices: &[usize]| -> (Vec<Measurement>, Vec<usize>, Vec<usize>) {
        let simulated = crate::folds::simulated(experiment, rows, indices);
        let picked = simulated.rows.iter().map(|&i| rows[i].clone()).collect();
        (picked, simulated.kept, simulated.rows)
    };
    let folds: Vec<_> = crate::folds::folds(experiment, rows, settings.folds)
        .into_iter()
        .map(|fold| (pick(&fold.train), pick(&fold.test)))
        .collect();
    let columns = experiment.observed.len();
    // A fold refits locally from each basin the full data's search found (its optimum
    // first), each start on its own face, and keeps the best: as the whole search would, it
    // may change basin when the rows held out favoured one, without screening again. Folds
    // are independent, each with its own evaluator, and run side by side.
    let starts: Vec<&[f64]> = basins.iter().map(Vec::as_slice).collect();
    let scored: Vec<Result<HeldOut, DiscoverError>> = folds
        .par_iter()
        .map(|((train, train_kept, _), (test, test_kept, test_rows))| {
            let mut evaluator = predictor.evaluator(&assessment.names)?;
            limit_to_budget(&mut evaluator, settings);
            evaluator.seed(&assessment.anchors, train);
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
                trials: evaluator.trials(),
                ..HeldOut::default()
            };
            held_out.by_column = vec![0.0; experiment.observed.len()];
            for &i in test_kept {
                match &predictions[i] {
                    Ok(p) => {
                        for (k, (y, m)) in p.observed.iter().zip(&test[i].observed).enumerate() {
                            let square = (y - m).powi(2);
                            held_out.sse += square;
                            held_out.by_column[k] += square;
                            held_out.count += 1;
                            held_out.cells.push((test_rows[i] * columns + k, square));
                        }
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
        assessment.trials.merge(&held_out.trials);
        assessment.heldout_sse += held_out.sse;
        assessment.heldout_count += held_out.count;
        for (total, part) in assessment
            .heldout_by_column
            .iter_mut()
            .zip(&held_out.by_column)
        {
            *total += part;
        }
        assessment.unsettled += held_out.unsettled;
        for (cell, square) in held_out.cells {
            let total = &mut assessment.heldout_cells[cell];
            *total = if total.is_nan() {
                square
            } else {
                *total + square
            };
        }
    }
    Ok(())
}

/// What one fold's refit scores on its held-out rows.
#[derive(Default)]
struct HeldOut {
    sse: f64,
    /// Each residual scored: its place in the assessment's `predictions`, and its square.
    cells: Vec<(usize, f64)>,
    by_column: Vec<f64>,
    count: usize,
    unsettled: usize,
    evaluations: usize,
    trials: Trials,
}
