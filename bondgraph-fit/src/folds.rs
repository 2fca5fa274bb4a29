//! Held-out folds over whichever condition columns an experiment names.
//!
//! A model is scored on rows it was not fitted on, in two ways:
//!
//! - **leave one level out** of a condition column with three or more distinct values: fit
//!   on every other setting of that condition, predict the rows at this one (the way a model
//!   is validated on conditions it was not tuned on; with two levels, fitting on one would be
//!   a single extrapolation, not a validation). Of several such columns, the one with the
//!   fewest levels: the condition set at a few discrete settings (a drive speed, a load)
//!   rather than swept (a pressure in nine steps), whose neighbouring levels k-fold already
//!   holds out. Leaving every level of every sweep out as well multiplies the refits (27 on
//!   a three-factor sweep of nine levels instead of 9) and scores mostly extrapolation beyond the
//!   ends of a sweep, where a threshold-shaped effect cannot be checked;
//! - **k-fold**, always: rows in the order of their conditions dealt round-robin into `k`
//!   folds, so that the rows at one setting fall into different folds and no fold holds out a
//!   whole condition.
//!
//! A fold whose held-out rows need a model variant the training rows do not (rows with an
//! `absent` cell filled while every training row has it empty, or the reverse) leaves nothing
//! to fit that part of the model on; it would test the starting values, not the model, and is
//! left out.

use crate::data::Measurement;
use crate::experiment::Experiment;

/// One fold: the rows fitted and the rows held out (indices into the data).
#[derive(Clone, Debug, PartialEq)]
pub struct Fold {
    /// Rows fitted.
    pub train: Vec<usize>,
    /// Rows held out.
    pub test: Vec<usize>,
}

/// The folds of `rows`: leave one level out of the condition column with the fewest levels
/// among those with three or more, then `k`-fold.
///
/// # Complexity
/// `O(c n log n)` for `n` rows and `c` condition columns, plus the folds' own size.
///
/// # Example
/// ```
/// use bondgraph_fit::{data, experiment::Experiment, folds};
///
/// let experiment = Experiment::parse("e.ron", r#"Experiment(kind: Steady,
///     conditions: [("u_V", "u", 1.0)], observed: [("w", "flow:shaft", 1.0)])"#).unwrap();
/// let text = "u_V,w\n1,10\n2,20\n3,30\n1,11\n2,21\n3,31\n";
/// let rows = data::read("d.csv", text, &experiment).unwrap().rows;
/// let folds = folds::folds(&experiment, &rows, 3);
/// // Three levels of u_V held out in turn, then three folds dealt round-robin.
/// assert_eq!(folds.len(), 6);
/// assert_eq!(folds[0].test, [0, 3]);
/// assert_eq!(folds[3].test, [0, 4]);
/// ```
pub fn folds(experiment: &Experiment, rows: &[Measurement], k: usize) -> Vec<Fold> {
    let columns = experiment.condition_columns().len();
    let mut candidates: Vec<Vec<usize>> = Vec::new();
    let levels: Vec<(usize, Vec<f64>)> = (0..columns)
        .map(|c| {
            let mut levels: Vec<f64> = rows.iter().filter_map(|r| r.conditions[c]).collect();
            levels.sort_by(f64::total_cmp);
            levels.dedup();
            (c, levels)
        })
        .filter(|(_, levels)| levels.len() >= 3)
        .collect();
    if let Some((c, levels)) = levels.iter().min_by_key(|(_, levels)| levels.len()) {
        for &level in levels {
            candidates.push(
                (0..rows.len())
                    .filter(|&i| rows[i].conditions[*c] == Some(level))
                    .collect(),
            );
        }
    }
    let k = k.min(rows.len());
    if k >= 2 {
        let mut order: Vec<usize> = (0..rows.len()).collect();
        order.sort_by(|&a, &b| {
            let key = |i: usize| {
                rows[i]
                    .conditions
                    .iter()
                    .map(|v| v.unwrap_or(f64::NEG_INFINITY))
            };
            key(a)
                .zip(key(b))
                .map(|(x, y)| x.total_cmp(&y))
                .find(|o| o.is_ne())
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        for f in 0..k {
            let mut test: Vec<usize> = (f..rows.len()).step_by(k).map(|r| order[r]).collect();
            test.sort_unstable();
            candidates.push(test);
        }
    }
    let variant = |i: usize| variant(experiment, &rows[i]);
    candidates
        .into_iter()
        .filter_map(|test| {
            let train: Vec<usize> = (0..rows.len()).filter(|i| !test.contains(i)).collect();
            let trained: Vec<u64> = train.iter().map(|&i| variant(i)).collect();
            let covered = test.iter().all(|&i| trained.contains(&variant(i)));
            (covered && !train.is_empty()).then_some(Fold { train, test })
        })
        .collect()
}

/// Which `absent` columns of a row are empty, as a bit mask.
fn variant(experiment: &Experiment, row: &Measurement) -> u64 {
    let columns = experiment.condition_columns();
    experiment
        .absent
        .iter()
        .enumerate()
        .filter(|(_, a)| {
            columns
                .iter()
                .position(|c| *c == a.column)
                .is_some_and(|k| row.conditions[k].is_none())
        })
        .fold(0, |mask, (j, _)| mask | (1 << j))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data;

    fn experiment() -> Experiment {
        Experiment::parse(
            "e.ron",
            r#"Experiment(kind: Steady,
                conditions: [("u_V", "u", 1.0), ("tau_mNm", "tau_load", 0.001)],
                absent: [("tau_mNm", ["load"])],
                observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap()
    }

    #[test]
    fn two_levels_are_not_left_out_and_uncovered_variants_are_skipped() {
        // u_V has two levels (no leave-one-level-out); tau_mNm three levels (5, 10, 20)
        // plus empty cells. Holding out tau = 5 leaves loaded rows to train on: kept.
        let text = "u_V,tau_mNm,w\n6,,1\n12,,2\n6,5,3\n12,10,4\n6,20,5\n12,,6\n";
        let rows = data::read("d.csv", text, &experiment()).unwrap().rows;
        let folds = folds(&experiment(), &rows, 2);
        let tests: Vec<Vec<usize>> = folds.iter().map(|f| f.test.clone()).collect();
        // Order by (u_V, tau): rows 0 (6,-), 2 (6,5), 4 (6,20), 1 (12,-), 5 (12,-), 3 (12,10);
        // dealt into two folds: [0, 4, 5] and [2, 1, 3].
        assert_eq!(
            tests,
            vec![vec![2], vec![3], vec![4], vec![0, 4, 5], vec![1, 2, 3]]
        );
    }

    #[test]
    fn the_column_with_the_fewest_levels_is_left_out() {
        // u_V in four levels, tau_mNm in three: tau is left out level by level.
        let text = "u_V,tau_mNm,w\n1,5,1\n2,10,2\n3,20,3\n4,5,4\n";
        let rows = data::read("d.csv", text, &experiment()).unwrap().rows;
        let folds = folds(&experiment(), &rows, 1);
        let tests: Vec<Vec<usize>> = folds.iter().map(|f| f.test.clone()).collect();
        assert_eq!(tests, vec![vec![0, 3], vec![1], vec![2]]);
    }

    #[test]
    fn a_fold_holding_out_every_loaded_row_is_left_out() {
        let text = "u_V,tau_mNm,w\n1,,1\n2,,2\n3,,3\n1,5,4\n";
        let rows = data::read("d.csv", text, &experiment()).unwrap().rows;
        let folds = folds(&experiment(), &rows, 2);
        // Leave-one-level-out of u_V = 1 holds out rows 0 and 3 (the only loaded one): left
        // out; as is the k-fold fold holding row 3 (in the order 0, 3, 1, 2: folds [0, 1]
        // and [3, 2]).
        let tests: Vec<Vec<usize>> = folds.iter().map(|f| f.test.clone()).collect();
        assert_eq!(tests, vec![vec![1], vec![2], vec![0, 1]]);
    }
}
