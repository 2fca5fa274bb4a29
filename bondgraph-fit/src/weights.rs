//! Several observed columns in one fit: each column's residuals divided by its noise, so that
//! the sum of squares is a chi-square and columns in different units combine.
//!
//! A rig records levels in mm and flows in mL/s, positions and forces, currents and speeds.
//! Summed in their own units, the column with the largest numbers would decide the fit alone.
//! Divided by its noise (standard deviation), each column's residuals count as what they are
//! worth: `Σ_k Σ_i ((predicted - measured)/σ_k)²`, weighted least squares with weights
//! `1/σ_k²`. The noise of each column comes, as for one column ([`crate::noise`]), from the
//! experiment's declared `noise` (one per observed column), else the pure error of replicated
//! steady conditions, else the residual of a fit: for those columns a first fit weighs each
//! column by the spread of its measured values, its residuals give the noise, and the fit is
//! made again with it (two-step weighted least squares).
//!
//! The weighting is done by rescaling, not by a second kind of fit: [`scaled`] gives an
//! experiment whose observed factors are multiplied by the noise (so the model's predictions
//! come out in noise levels) and rows whose measured values are divided by it. Everything
//! that fits, cross-validates and tests one column then works unchanged in noise levels. One
//! observed column is never rescaled: its scores stay in its own units.

use crate::data::Measurement;
use crate::experiment::Experiment;
use crate::noise::{self, NoiseLevel};

/// The noise of observed column `k` that needs no model: the experiment's declared one, else
/// the pure error of replicated steady conditions with enough degrees of freedom; `None`
/// when only a fit's residual can give it.
pub fn known_level(experiment: &Experiment, rows: &[Measurement], k: usize) -> Option<NoiseLevel> {
    let replicates = replicates(experiment, rows, k);
    let usable = experiment.declared_noise(k).is_some()
        || replicates
            .as_ref()
            .is_some_and(|p| p.dof >= noise::MIN_PURE_ERROR_DOF);
    // Replicates that repeat exactly give no level: the residual gives it then.
    usable
        .then(|| {
            NoiseLevel::estimate(
                experiment.declared_noise(k),
                replicates,
                noise::Residual {
                    sse: f64::NAN,
                    dof: f64::NAN,
                    model: "",
                    scale: 0.0,
                },
            )
        })
        .filter(|level| level.sd.is_some())
}

/// The replicates' scatter in column `k`: steady data only, since a run's samples at the
/// same input levels are not replicates.
pub fn replicates(
    experiment: &Experiment,
    rows: &[Measurement],
    k: usize,
) -> Option<noise::PureError> {
    if experiment.time().is_none() {
        noise::pure_error(rows, k)
    } else {
        None
    }
}

/// A provisional scale of column `k`, for a first fit before its noise is known: the
/// standard deviation of its measured values (their root mean square if they are all equal,
/// 1 if they are all zero), so that every column counts alike.
pub fn spread(rows: &[Measurement], k: usize) -> f64 {
    let n = rows.len().max(1) as f64;
    let mean = rows.iter().map(|r| r.observed[k]).sum::<f64>() / n;
    let sd = (rows
        .iter()
        .map(|r| (r.observed[k] - mean).powi(2))
        .sum::<f64>()
        / n)
        .sqrt();
    let rms = noise::root_mean_square(rows, k);
    [sd, rms, 1.0]
        .into_iter()
        .find(|s| s.is_finite() && *s > 0.0)
        .unwrap_or(1.0)
}

/// `experiment` and `rows` in noise levels: observed column `k`'s factor multiplied by
/// `scales[k]` (the model's predictions come out divided by it) and its measured values
/// divided by it; no declared noise (every column's is 1 now).
pub fn scaled(
    experiment: &Experiment,
    rows: &[Measurement],
    scales: &[f64],
) -> (Experiment, Vec<Measurement>) {
    let mut scaled_experiment = experiment.clone();
    for (observed, scale) in scaled_experiment.observed.iter_mut().zip(scales) {
        observed.factor *= scale;
    }
    scaled_experiment.noise = Vec::new();
    let scaled_rows = rows
        .iter()
        .map(|row| {
            let mut row = row.clone();
            for (value, scale) in row.observed.iter_mut().zip(scales) {
                *value /= scale;
            }
            row
        })
        .collect();
    (scaled_experiment, scaled_rows)
}

/// Each column's residual standard deviation `sqrt(SSE_k/(n - p/m))` (the `p` fitted
/// parameters shared among the `m` columns), from `predicted[i][k]` in the columns' units.
pub fn residual_sds(rows: &[Measurement], predicted: &[Vec<f64>], params: usize) -> Vec<f64> {
    let m = rows.first().map_or(0, |r| r.observed.len());
    let n = rows.len() as f64;
    (0..m)
        .map(|k| {
            let sse: f64 = rows
                .iter()
                .zip(predicted)
                .map(|(r, p)| (p[k] - r.observed[k]).powi(2))
                .sum();
            (sse / (n - params as f64 / m as f64)).sqrt()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;

    fn row(x: f64, y: [f64; 2]) -> Measurement {
        Measurement {
            conditions: vec![Some(x)],
            observed: y.to_vec(),
            time: None,
            row: 2,
            file: Arc::from("hand.csv"),
        }
    }

    #[test]
    fn columns_are_put_in_noise_levels() {
        let experiment = Experiment::parse(
            "e.ron",
            r#"Experiment(kind: Steady, conditions: [("x", "u", 1.0)],
                observed: [("h_mm", "effort:tank", 9.81), ("q_mL_s", "flow:out", 1e-6)],
                noise: [2.0, 0.5])"#,
        )
        .unwrap();
        let rows = vec![row(1.0, [10.0, 3.0]), row(2.0, [20.0, 5.0])];
        let (e, r) = scaled(&experiment, &rows, &[2.0, 0.5]);
        assert_eq!((e.observed[0].factor, e.observed[1].factor), (19.62, 5e-7));
        assert!(e.noise.is_empty());
        assert_eq!(r[1].observed, [10.0, 10.0]);
        // Spread: values 10 and 20 about 15, and 3 and 5 about 4.
        assert_eq!((spread(&rows, 0), spread(&rows, 1)), (5.0, 1.0));
        let level = known_level(&experiment, &rows, 1).unwrap();
        assert_eq!(
            (level.sd, level.source.as_str()),
            (Some(0.5), "declared in the experiment")
        );
        // Residuals 1, -1 and 0, 2 with one parameter shared by two columns: n - 1/2 dof.
        let sds = residual_sds(&rows, &[vec![11.0, 3.0], vec![19.0, 7.0]], 1);
        assert!((sds[0] - (2.0f64 / 1.5).sqrt()).abs() < 1e-12);
        assert!((sds[1] - (4.0f64 / 1.5).sqrt()).abs() < 1e-12);
    }
}
