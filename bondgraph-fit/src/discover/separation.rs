//! What would separate two candidates the data cannot tell apart: a steady condition where
//! their fitted models' predictions differ by more than three noise levels (searched over a
//! grid wider than the data's), or where along the recorded run they differ most; or, when
//! no observation separates them, what the extension's file says would show its effect.

use super::cross_validation::same_prediction;
use super::fit::Assessment;
use super::procedure::{Fitted, Models};
use super::{DiscoverError, Separation};

impl Models<'_> {
    /// For each of `indistinguishable`, the measurement that would tell it from the
    /// selected candidate (or, when none is, from the base model).
    pub(super) fn separations(
        &self,
        baseline: &Assessment,
        assessed: &[Assessment],
        selected: Option<usize>,
        indistinguishable: &[usize],
        noise: Option<f64>,
    ) -> Result<Vec<Separation>, DiscoverError> {
        let (experiment, rows, candidates) = (self.experiment, self.rows, self.candidates);
        let m = self.columns.len();
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
        let fitted = |i: usize| Fitted {
            model: &candidates[i].model,
            source: &candidates[i].source,
            names: &assessed[i].names,
            values: &assessed[i].fit.values,
        };
        let reference = match selected {
            Some(s) => fitted(s),
            None => Fitted {
                model: self.base_model,
                source: self.base,
                names: &baseline.names,
                values: &baseline.fit.values,
            },
        };
        let reference_predictions = reference.predict(experiment, &probes, self.settings)?;
        let against = self.name(selected);
        let same = same_prediction(experiment, rows, baseline);
        let mut separation = Vec::new();
        for &i in indistinguishable {
            let predictions = fitted(i).predict(experiment, &probes, self.settings)?;
            let (k, difference) = predictions
                .iter()
                .zip(&reference_predictions)
                .map(|(a, b)| if (a - b).is_nan() { 0.0 } else { (a - b).abs() })
                .enumerate()
                .fold(
                    (0, 0.0),
                    |(bk, bd), (k, d)| if d > bd { (k, d) } else { (bk, bd) },
                );
            // The probe and the column where they differ most, in the column's units.
            let (probe, column) = (k / m, k % m);
            let observed = self.columns[column].as_str();
            let scale = self.scales[column];
            let (predicted, reference_predicted) =
                (predictions[k] * scale, reference_predictions[k] * scale);
            let measurement = if let Some(sd) = noise
                && difference > 3.0 * sd
            {
                format!(
                    "`{observed}` at {}: '{}' predicts {:.4}, {against} {:.4} ({:.1} noise levels apart)",
                    crate::probes::describe(experiment, &probes[probe]),
                    candidates[i].id,
                    predicted,
                    reference_predicted,
                    difference / sd
                )
            } else if noise.is_none() && difference > same {
                format!(
                    "`{observed}` at {}: '{}' predicts {:.4}, {against} {:.4} (the largest difference; \
                     with no noise level it is not judged in noise levels)",
                    crate::probes::describe(experiment, &probes[probe]),
                    candidates[i].id,
                    predicted,
                    reference_predicted,
                )
            } else {
                format!(
                    "{nowhere} `{observed}` tells '{}' from {against} (they differ by at most {:.4}); {}",
                    candidates[i].id,
                    difference * scale,
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
        Ok(separation)
    }
}
