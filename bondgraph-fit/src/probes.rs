//! Conditions at which to look for a measurement that separates two fitted models.
//!
//! When two models fit the data equally well, the useful answer is where they would not: a
//! setting of the conditions at which their predictions differ by more than the noise. The
//! search runs over a grid wider than the data's range in every condition column, so that it
//! can propose a measurement outside what was done (a higher pressure, a faster drive).
//!
//! A time series is not probed on a grid: its conditions are input signals along a run, and
//! a steady setting of them says nothing of the run's dynamics. Its probes are the recorded
//! samples themselves, each predicted by simulating its whole run: the answer is where along
//! the run the two models differ most.

use crate::data::Measurement;
use crate::experiment::Experiment;

/// Probe rows at most, over all condition columns together.
const BUDGET: f64 = 200.0;

/// Where to look for a separating measurement: for steady data the [`grid`], for a time
/// series the recorded samples (`rows` themselves).
pub fn probes(experiment: &Experiment, rows: &[Measurement]) -> Vec<Measurement> {
    if experiment.time().is_some() {
        rows.to_vec()
    } else {
        grid(experiment, rows)
    }
}

/// A grid of conditions wider than the data's: for a column whose values are never negative,
/// from half the lowest to twice the highest; otherwise half the range beyond each end; a
/// column of one value `v`, from `v/2` to `2v`. An `absent` column keeps its empty level
/// where the data has one. Points per column: as many as fit in a budget of about 200 rows,
/// between 3 and 13.
pub fn grid(experiment: &Experiment, rows: &[Measurement]) -> Vec<Measurement> {
    let columns = experiment.condition_columns();
    let varying = columns.len().max(1) as f64;
    let points = (BUDGET.powf(1.0 / varying).floor() as usize).clamp(3, 13);
    let levels: Vec<Vec<Option<f64>>> = (0..columns.len())
        .map(|k| {
            let values: Vec<f64> = rows.iter().filter_map(|r| r.conditions[k]).collect();
            let mut levels: Vec<Option<f64>> = Vec::new();
            if rows.iter().any(|r| r.conditions[k].is_none()) {
                levels.push(None);
            }
            if values.is_empty() {
                return levels;
            }
            let (lo, hi) = values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            let (from, to) = if lo == hi {
                if lo == 0.0 {
                    (0.0, 0.0)
                } else {
                    (0.5 * lo, 2.0 * lo)
                }
            } else if lo >= 0.0 {
                (0.5 * lo, 2.0 * hi)
            } else {
                (lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo))
            };
            let n = if from == to { 1 } else { points };
            levels.extend((0..n).map(|m| {
                Some(if n == 1 {
                    from
                } else {
                    from + (to - from) * m as f64 / (n - 1) as f64
                })
            }));
            levels
        })
        .collect();
    let file = rows
        .first()
        .map_or_else(|| "probe".into(), |r| r.file.clone());
    let mut grid = vec![Vec::new()];
    for column in &levels {
        grid = grid
            .into_iter()
            .flat_map(|prefix: Vec<Option<f64>>| {
                column.iter().map(move |&v| {
                    let mut next = prefix.clone();
                    next.push(v);
                    next
                })
            })
            .collect();
    }
    grid.into_iter()
        .map(|conditions| Measurement {
            conditions,
            observed: vec![0.0; experiment.observed.len()],
            time: None,
            row: 0,
            file: file.clone(),
        })
        .collect()
}

/// `column = value, ...` with four significant digits, `column empty` for an empty cell; a
/// time series' sample as `t_s = 0.84 in the run of step.csv (V_V = 12, tau_mNm = 1000)`.
pub fn describe(experiment: &Experiment, row: &Measurement) -> String {
    let conditions = cells(experiment, row);
    match (experiment.time(), row.time) {
        (Some((column, _)), Some(t)) => format!(
            "{column} = {} in the run of {} ({conditions})",
            significant(t),
            row.file
        ),
        _ => conditions,
    }
}

fn cells(experiment: &Experiment, row: &Measurement) -> String {
    experiment
        .condition_columns()
        .iter()
        .zip(&row.conditions)
        .map(|(column, value)| match value {
            Some(v) => format!("{column} = {}", significant(*v)),
            None => format!("{column} empty"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

fn significant(v: f64) -> String {
    let text = format!("{v:.4e}");
    text.parse::<f64>().map_or(text, |r| r.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data;

    #[test]
    fn the_grid_is_wider_than_the_data() {
        let experiment = Experiment::parse(
            "e.ron",
            r#"Experiment(kind: Steady,
                conditions: [("u_V", "u", 1.0), ("tau_mNm", "tau_load", 0.001)],
                absent: [("tau_mNm", ["load"])],
                observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap();
        let text = "u_V,tau_mNm,w\n6,,1\n12,,2\n6,5,3\n";
        let rows = data::read("d.csv", text, &experiment).unwrap().rows;
        let grid = grid(&experiment, &rows);
        // Two columns: 200^(1/2) = 14, at most 13 points; u_V from 3 to 24; tau_mNm empty or
        // from 2.5 to 10 (one value, 5).
        assert_eq!(grid.len(), 13 * 14);
        assert_eq!(grid[0].conditions, [Some(3.0), None]);
        assert_eq!(grid[14].conditions, [Some(3.0 + 21.0 / 12.0), None]);
        assert_eq!(grid[1].conditions, [Some(3.0), Some(2.5)]);
        assert_eq!(grid.last().unwrap().conditions, [Some(24.0), Some(10.0)]);
        assert_eq!(
            describe(&experiment, &grid[15]),
            "u_V = 4.75, tau_mNm = 2.5"
        );
    }

    #[test]
    fn a_time_series_is_probed_at_its_samples() {
        let experiment = Experiment::parse(
            "e.ron",
            r#"Experiment(kind: TimeSeries(scenario: "step.ron", time: ("t_s", 1.0)),
                conditions: [("V_V", "V", 1.0), ("tau_mNm", "tau_load", 0.001)],
                observed: [("w", "flow:shaft", 1.0)])"#,
        )
        .unwrap();
        let text = "t_s,V_V,tau_mNm,w\n0,0,0,0\n0.84,12,1000,8.4\n";
        let rows = data::read("step.csv", text, &experiment).unwrap().rows;
        // No grid of steady conditions: the recorded samples themselves.
        assert_eq!(probes(&experiment, &rows), rows);
        assert_eq!(
            describe(&experiment, &rows[1]),
            "t_s = 0.84 in the run of step.csv (V_V = 12, tau_mNm = 1000)"
        );
    }
}
