//! Whether a candidate's effect is the base model's in disguise, or no effect at all.

use super::Candidate;
use super::fit::Assessment;
use crate::calibrate::Fit;

/// Whether the candidate's own parameters' Jacobian columns lie in the span of the base
/// parameters' (so the base refit can mimic its effect): the relative norm of what the
/// projection leaves, below 2%. Base columns that others already span (two thresholds tied
/// on a face move the residuals alike) add nothing to the span and are left out of it.
pub(super) fn aliased_with_base(fit: &Fit, base: usize, own: usize) -> bool {
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
pub(super) fn reproduced_by_base(
    candidate: &Candidate,
    fitted: &Assessment,
    base: &Assessment,
) -> bool {
    let first_own = fitted.names.len() - candidate.parameters.len();
    let active = (first_own..fitted.names.len()).any(|j| {
        candidate
            .model
            .parameters()
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
pub(super) fn no_effect(candidate: &Candidate, assessment: &Assessment) -> bool {
    let base = assessment.names.len() - candidate.parameters.len();
    (base..assessment.names.len()).all(|j| {
        candidate
            .model
            .parameters()
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

#[cfg(test)]
mod tests {
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
}
