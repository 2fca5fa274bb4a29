//! Residuals by regime and trends along each condition: what a model gets wrong, and where.

use super::{FactorTrend, RegimeResiduals, Residuals};
use crate::data::Measurement;
use crate::experiment::Experiment;
use crate::stats;

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
