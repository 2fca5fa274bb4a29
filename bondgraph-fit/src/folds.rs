//! Held-out folds over whichever condition columns an experiment names.
//!
//! A model is scored on rows it was not fitted on, in two ways:
//!
//! - **leave one level out** of a condition column with three or more distinct values (with
//!   more levels than `k`, `k` runs of neighbouring levels, so that the refits do not grow
//!   with the data): fit on every other setting of that condition, predict the rows at this
//!   one (the way a model is validated on conditions it was not tuned on; with two levels,
//!   fitting on one would be a single extrapolation, not a validation). Of several such columns, the one with the
//!   fewest levels: the condition set at a few discrete settings (a drive speed, a load)
//!   rather than swept (a pressure in nine steps), whose neighbouring levels k-fold already
//!   holds out. Leaving every level of every sweep out as well multiplies the refits (27 on
//!   a three-factor sweep of nine levels instead of 9) and scores mostly extrapolation beyond the
//!   ends of a sweep, where a threshold-shaped effect cannot be checked;
//! - **k-fold**, always: rows in the order of their conditions dealt round-robin into `k`
//!   folds, so that the rows at one setting fall into different folds and no fold holds out a
//!   whole condition.
//!
//! A time series is held out along time instead, and never cut: with several runs (one per
//! data file), **leave one run out**; with one run, `k` **contiguous blocks** of its samples,
//! each held out in turn. A held-out block must not cut the measured input signals that
//! drive the run, so a fold is fitted on the training samples' residuals only, but every
//! prediction simulates the whole run ([`simulated`] says which rows to simulate for which
//! residuals).
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

/// The folds of `rows`: for steady data, leave one level out of the condition column with
/// the fewest levels among those with three or more, then `k`-fold; for a time series, leave
/// one run out, or with one run, `k` contiguous blocks of it.
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
    let candidates = if experiment.time().is_some() {
        along_time(rows, k)
    } else {
        across_conditions(experiment, rows, k)
    };
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

/// The held-out rows of a time series' folds: each run (the rows of one file) when there
/// are several, else `k` contiguous blocks of the one run, as even as they can be (the first
/// `n mod k` one row longer).
fn along_time(rows: &[Measurement], k: usize) -> Vec<Vec<usize>> {
    let mut files: Vec<&str> = Vec::new();
    for row in rows {
        if !files.contains(&&*row.file) {
            files.push(&row.file);
        }
    }
    if files.len() > 1 {
        return files
            .iter()
            .map(|file| {
                (0..rows.len())
                    .filter(|&i| &*rows[i].file == *file)
                    .collect()
            })
            .collect();
    }
    let n = rows.len();
    let k = k.min(n);
    if k < 2 {
        return Vec::new();
    }
    let mut start = 0;
    (0..k)
        .map(|f| {
            let end = start + n / k + usize::from(f < n % k);
            let block = (start..end).collect();
            start = end;
            block
        })
        .collect()
}

/// The held-out rows of steady data's folds: leave one level out, then `k`-fold.
fn across_conditions(experiment: &Experiment, rows: &[Measurement], k: usize) -> Vec<Vec<usize>> {
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
        for block in level_blocks(levels, k) {
            candidates.push(
                (0..rows.len())
                    .filter(|&i| rows[i].conditions[*c].is_some_and(|v| block.contains(&v)))
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
    candidates
}

/// The levels held out together: each level alone, or with more than `k` levels (`k` at
/// least 3), `k` runs of neighbouring levels, as even as they can be (the first
/// `levels mod k` one level longer). The number of refits then stays bounded as the data
/// grow (a condition swept in forty steps is held out a fifth of its range at a time), and
/// each fold still predicts settings it was not fitted on.
fn level_blocks(levels: &[f64], k: usize) -> Vec<&[f64]> {
    if k < 3 || levels.len() <= k {
        return levels.chunks(1).collect();
    }
    let (size, longer) = (levels.len() / k, levels.len() % k);
    let mut start = 0;
    (0..k)
        .map(|f| {
            let end = start + size + usize::from(f < longer);
            let block = &levels[start..end];
            start = end;
            block
        })
        .collect()
}

/// The rows to simulate so as to predict the rows `wanted` (indices into `rows`, in
/// order), and where each wanted row sits among them.
///
/// A steady row is its own simulation: the wanted rows themselves. A time series' row is a
/// sample of its run, which only the whole run predicts (its measured inputs complete): every
/// row of each file a wanted row comes from, in file order, so that a fold's fit and its
/// held-out score each simulate a run once and keep the residuals they need.
///
/// # Example
/// ```
/// use bondgraph_fit::{data, experiment::Experiment, folds};
///
/// let experiment = Experiment::parse("e.ron", r#"Experiment(
///     kind: TimeSeries(scenario: "s.ron", time: ("t_s", 1.0)),
///     conditions: [("u_V", "u", 1.0)], observed: [("w", "flow:shaft", 1.0)])"#).unwrap();
/// let text = "t_s,u_V,w\n0,1,0\n1,1,5\n2,1,7\n";
/// let rows = data::read("d.csv", text, &experiment).unwrap().rows;
/// let simulated = folds::simulated(&experiment, &rows, &[1]);
/// assert_eq!(simulated.rows, [0, 1, 2]);
/// assert_eq!(simulated.kept, [1]);
/// ```
pub fn simulated(experiment: &Experiment, rows: &[Measurement], wanted: &[usize]) -> Simulated {
    if experiment.time().is_none() {
        return Simulated {
            rows: wanted.to_vec(),
            kept: (0..wanted.len()).collect(),
        };
    }
    let files: Vec<&str> = wanted.iter().map(|&i| &*rows[i].file).collect();
    let simulated: Vec<usize> = (0..rows.len())
        .filter(|&i| files.contains(&&*rows[i].file))
        .collect();
    let kept = simulated
        .iter()
        .enumerate()
        .filter(|(_, i)| wanted.binary_search(i).is_ok())
        .map(|(k, _)| k)
        .collect();
    Simulated {
        rows: simulated,
        kept,
    }
}

/// Which rows to simulate, and whose residuals to keep ([`simulated`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Simulated {
    /// The rows to simulate, indices into the data, in order.
    pub rows: Vec<usize>,
    /// The positions in `rows` of the rows wanted.
    pub kept: Vec<usize>,
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
    fn more_levels_than_folds_are_held_out_in_runs_of_neighbours() {
        // u_V in seven levels (1..=7, two rows each, one of them also at tau 5) and three
        // folds: levels {1, 2, 3}, {4, 5}, {6, 7} held out in turn (7 = 3 + 2 + 2), then the
        // three round-robin folds.
        let text = "u_V,tau_mNm,w\n1,,1\n2,,2\n3,,3\n4,,4\n5,,5\n6,,6\n7,,7\n\
                    1,,8\n2,,9\n3,,10\n4,,11\n5,,12\n6,,13\n7,,14\n";
        let rows = data::read("d.csv", text, &experiment()).unwrap().rows;
        let folds = folds(&experiment(), &rows, 3);
        let tests: Vec<Vec<usize>> = folds.iter().map(|f| f.test.clone()).collect();
        assert_eq!(tests.len(), 6);
        assert_eq!(tests[0], vec![0, 1, 2, 7, 8, 9]);
        assert_eq!(tests[1], vec![3, 4, 10, 11]);
        assert_eq!(tests[2], vec![5, 6, 12, 13]);
        assert_eq!(
            level_blocks(&[1.0, 2.0, 3.0], 5),
            vec![&[1.0][..], &[2.0], &[3.0]]
        );
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

    fn time_series() -> Experiment {
        Experiment::parse(
            "e.ron",
            r#"Experiment(kind: TimeSeries(scenario: "step.ron", time: ("t_s", 1.0)),
                conditions: [("V_V", "V", 1.0), ("tau_mNm", "tau_load", 0.001)],
                observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap()
    }

    /// A run of `n` samples 10 ms apart, read as file `name`.
    fn run(name: &str, n: usize) -> Vec<Measurement> {
        let mut text = String::from("t_s,V_V,tau_mNm,w\n");
        for k in 0..n {
            text.push_str(&format!("{},{},0,{}\n", k as f64 * 0.01, k % 3, k));
        }
        data::read(name, &text, &time_series()).unwrap().rows
    }

    #[test]
    fn one_run_is_held_out_in_contiguous_blocks_that_partition_it() {
        // 23 samples in 5 blocks: 23 = 4 x 5 + 3, so the first three blocks hold 5 samples
        // and the last two 4: [0, 5), [5, 10), [10, 15), [15, 19), [19, 23).
        let rows = run("step.csv", 23);
        let folds = folds(&time_series(), &rows, 5);
        let blocks: Vec<(usize, usize)> = folds
            .iter()
            .map(|f| (f.test[0], *f.test.last().unwrap() + 1))
            .collect();
        assert_eq!(blocks, [(0, 5), (5, 10), (10, 15), (15, 19), (19, 23)]);
        let mut seen = vec![0; rows.len()];
        for fold in &folds {
            // Contiguous, and the training rows are all the others.
            assert!(fold.test.windows(2).all(|w| w[1] == w[0] + 1));
            let mut all: Vec<usize> = fold.train.iter().chain(&fold.test).copied().collect();
            all.sort_unstable();
            assert_eq!(all, (0..rows.len()).collect::<Vec<_>>());
            for &i in &fold.test {
                seen[i] += 1;
            }
        }
        // Every sample held out exactly once.
        assert!(seen.iter().all(|&s| s == 1), "{seen:?}");
        // Each fold fits on its training samples but simulates the whole run, and scores
        // its block from the whole run too.
        for fold in &folds {
            let fit = simulated(&time_series(), &rows, &fold.train);
            assert_eq!(fit.rows, (0..rows.len()).collect::<Vec<_>>());
            assert_eq!(fit.kept, fold.train);
            let score = simulated(&time_series(), &rows, &fold.test);
            assert_eq!(score.rows, (0..rows.len()).collect::<Vec<_>>());
            assert_eq!(score.kept, fold.test);
        }
    }

    #[test]
    fn several_runs_are_left_out_one_file_at_a_time() {
        let mut rows = run("a.csv", 4);
        rows.extend(run("b.csv", 6));
        rows.extend(run("c.csv", 5));
        let folds = folds(&time_series(), &rows, 5);
        assert_eq!(folds.len(), 3);
        for (fold, (file, range)) in
            folds
                .iter()
                .zip([("a.csv", 0..4), ("b.csv", 4..10), ("c.csv", 10..15)])
        {
            // Exactly one file held out, all of it, and nothing of the others.
            assert_eq!(fold.test, range.clone().collect::<Vec<_>>());
            assert!(fold.test.iter().all(|&i| &*rows[i].file == file));
            assert!(fold.train.iter().all(|&i| &*rows[i].file != file));
            assert_eq!(fold.train.len() + fold.test.len(), rows.len());
            // The held-out run is not simulated to fit, and alone to score.
            let fit = simulated(&time_series(), &rows, &fold.train);
            assert_eq!(fit.rows, fold.train);
            assert_eq!(fit.kept, (0..fold.train.len()).collect::<Vec<_>>());
            let score = simulated(&time_series(), &rows, &fold.test);
            assert_eq!(score.rows, fold.test);
        }
    }
}
