//! A simulated trajectory written out as CSV or JSON.
//!
//! Output formats only: the numbers are written as the solver produced them, with nothing
//! resampled or derived.
//!
//! Numbers keep full precision: each is written in the shortest form that parses back to
//! the same `f64`, in plain decimal notation for magnitudes from 1e-4 to 1e16 (and zero) and
//! in scientific notation otherwise (`1e-7`, `2.5e20`), so that a column of times or
//! velocities stays readable without losing a bit. Values that are not finite are written
//! `NaN`, `inf` or `-inf` in CSV and `null` in JSON (which has no such numbers).

use bondgraph_fit::data::CsvWriter;
use bondgraph_solver::Trajectory;
use serde_json::{Map, Value, json};

/// The trajectory as CSV: a header `t,mode,<output names...>`, then one row per sample.
///
/// `t` is in seconds; `mode` is the mode's specification (e.g.
/// `fr_1=slip+,k=taut,fr_2=stuck`), quoted as RFC 4180 asks because it contains commas.
/// Output names are quoted the same way if they need it. Lines end with `\n`.
///
/// A sample whose mode or values are missing (a trajectory built inconsistently) gets empty
/// fields rather than a panic.
pub fn to_csv(trajectory: &Trajectory) -> String {
    let mut csv = CsvWriter::new(
        ["t", "mode"]
            .into_iter()
            .chain(trajectory.output_names.iter().map(String::as_str)),
    );
    for (i, &t) in trajectory.times.iter().enumerate() {
        let mut row = vec![
            number(t),
            mode_spec(trajectory, i).unwrap_or("").to_string(),
        ];
        row.extend(
            (0..trajectory.output_names.len())
                .map(|j| trajectory.value(i, j).map_or(String::new(), number)),
        );
        csv.row(row);
    }
    csv.finish()
}

/// The trajectory as one JSON document.
///
/// Fields:
/// - `model`, `scenario`: the names given;
/// - `outputs`: the output names, in order;
/// - `modes`: the specifications of the modes visited, in order of first visit;
/// - `samples`: `[{t, mode, values: {name: value}}]`, `t` in seconds, `mode` a specification;
/// - `intervals`: `[{start, end, mode}]`, the time spent in each mode, in seconds;
/// - `events`: `[{t, from, to, element, reason}]`, the mode changes;
/// - `final`: `{t, mode, states: {name: value}}`, the full state (energy variables) at the end;
/// - `stats`: `{segments, events, modes}`, the work the run took;
/// - `energy` (when the books are recorded): `{initial_stored, final_stored, supplied,
///   dissipated, lost_at_events, residual, error}` in joules, `residual` the first law's
///   (`Δstored - supplied + dissipated + lost`) and `error` the books' bound on their own.
///
/// Objects keyed by name (`values`, `states`) list their keys in sorted order; `outputs`
/// gives the outputs' order. Non-finite numbers are `null`; a mode index that names no mode
/// is `null`.
pub fn to_json(trajectory: &Trajectory, model_name: &str, scenario_name: &str) -> Value {
    let samples: Vec<Value> = trajectory
        .times
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let named: Map<String, Value> = trajectory
                .output_names
                .iter()
                .enumerate()
                .map(|(j, name)| {
                    let value = trajectory.value(i, j).map_or(Value::Null, |x| x.into());
                    (name.clone(), value)
                })
                .collect();
            json!({
                "t": t,
                "mode": mode_spec(trajectory, i),
                "values": named,
            })
        })
        .collect();
    let intervals: Vec<Value> = trajectory
        .intervals
        .iter()
        .map(|&(start, end, mode)| {
            json!({
                "start": start,
                "end": end,
                "mode": trajectory.modes.get(mode),
            })
        })
        .collect();
    let events: Vec<Value> = trajectory
        .events
        .iter()
        .map(|event| {
            json!({
                "t": event.t,
                "from": event.from,
                "to": event.to,
                "element": event.element,
                "reason": event.reason,
            })
        })
        .collect();
    let states: Map<String, Value> = trajectory
        .final_state
        .iter()
        .map(|(name, value)| (name.clone(), (*value).into()))
        .collect();
    let mut document = json!({
        "model": model_name,
        "scenario": scenario_name,
        "outputs": trajectory.output_names,
        "modes": trajectory.modes,
        "samples": samples,
        "intervals": intervals,
        "events": events,
        "final": {
            "t": trajectory.final_time,
            "mode": trajectory.final_mode,
            "states": states,
        },
        "stats": {
            "segments": trajectory.stats.segments,
            "events": trajectory.stats.events,
            "modes": trajectory.stats.modes,
        },
    });
    if let Some(books) = &trajectory.energy {
        document["energy"] = json!({
            "initial_stored": books.initial_stored,
            "final_stored": books.final_stored,
            "supplied": books.supplied,
            "dissipated": books.dissipated,
            "lost_at_events": books.lost_at_events,
            "residual": books.residual(),
            "error": books.error,
        });
    }
    document
}

/// The specification of the mode at sample `i`, if the trajectory records one.
fn mode_spec(trajectory: &Trajectory, i: usize) -> Option<&str> {
    let index = *trajectory.sample_modes.get(i)?;
    trajectory.modes.get(index).map(String::as_str)
}

/// A number in the shortest text that parses back to it: plain decimals for ordinary
/// magnitudes, scientific notation for very small or very large ones.
fn number(x: f64) -> String {
    let magnitude = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e16).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bondgraph_solver::{Event, Stats};

    /// Two outputs, three samples, two modes, one event.
    fn trajectory() -> Trajectory {
        Trajectory {
            output_names: vec!["v_a".into(), "f_k".into()],
            times: vec![0.0, 0.05, 0.1],
            values: vec![0.0, 0.0, 1.5e-7, 12.25, 0.0029, -3.0e20],
            sample_modes: vec![0, 0, 1],
            modes: vec![
                "fr_a=stuck,k=slack,fr_b=slip-".into(),
                "fr_a=slip+,k=slack,fr_b=slip-".into(),
            ],
            intervals: vec![(0.0, 0.062, 0), (0.062, 0.1, 1)],
            events: vec![Event {
                t: 0.062,
                from: "fr_a=stuck,k=slack,fr_b=slip-".into(),
                to: "fr_a=slip+,k=slack,fr_b=slip-".into(),
                element: "fr_a".into(),
                reason: "holding force reached the breakaway force".into(),
            }],
            final_time: 0.1,
            final_state: vec![("p_ge".into(), 1.25e-6), ("q_k".into(), 0.0)],
            final_mode: "fr_a=slip+,k=slack,fr_b=slip-".into(),
            stats: Stats {
                segments: 3,
                events: 1,
                modes: 2,
            },
            energy: None,
        }
    }

    #[test]
    fn csv_has_a_header_and_one_quoted_row_per_sample() {
        assert_eq!(
            to_csv(&trajectory()),
            "t,mode,v_a,f_k\n\
             0,\"fr_a=stuck,k=slack,fr_b=slip-\",0,0\n\
             0.05,\"fr_a=stuck,k=slack,fr_b=slip-\",1.5e-7,12.25\n\
             0.1,\"fr_a=slip+,k=slack,fr_b=slip-\",0.0029,-3e20\n"
        );
    }

    #[test]
    fn csv_of_a_trajectory_without_samples_is_its_header() {
        let mut empty = trajectory();
        empty.times.clear();
        assert_eq!(to_csv(&empty), "t,mode,v_a,f_k\n");
    }

    #[test]
    fn csv_quotes_names_with_commas_and_quotes_and_leaves_gaps_empty() {
        let mut odd = trajectory();
        odd.output_names = vec!["effort:a,b".into(), "say \"hi\"".into()];
        odd.modes = vec![String::new()];
        odd.sample_modes = vec![0, 7];
        odd.times.truncate(2);
        // One sample recorded in full, the other not at all.
        odd.values = vec![1.0, f64::NAN];
        assert_eq!(
            to_csv(&odd),
            "t,mode,\"effort:a,b\",\"say \"\"hi\"\"\"\n0,,1,NaN\n0.05,,,\n"
        );
    }

    #[test]
    fn numbers_round_trip_and_stay_readable() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            6.3e-3,
            1e-4,
            9.999e-5,
            123456.789,
            1e16,
            9.999999999999998e15,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            -f64::MAX,
            std::f64::consts::PI * 1e-9,
        ] {
            let text = number(x);
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} written as {text}");
        }
        assert_eq!(number(0.0029), "0.0029");
        assert_eq!(number(6.3e-5), "6.3e-5");
        assert_eq!(number(110e3), "110000");
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn json_holds_samples_modes_intervals_events_final_state_and_stats() {
        let json = to_json(&trajectory(), "belt", "push");
        assert_eq!(json["model"], "belt");
        assert_eq!(json["scenario"], "push");
        assert_eq!(json["outputs"], json!(["v_a", "f_k"]));
        assert_eq!(
            json["modes"],
            json!([
                "fr_a=stuck,k=slack,fr_b=slip-",
                "fr_a=slip+,k=slack,fr_b=slip-"
            ])
        );
        let samples = json["samples"].as_array().unwrap();
        assert_eq!(samples.len(), 3);
        assert_eq!(
            samples[1],
            json!({
                "t": 0.05,
                "mode": "fr_a=stuck,k=slack,fr_b=slip-",
                "values": {"v_a": 1.5e-7, "f_k": 12.25},
            })
        );
        assert_eq!(samples[2]["mode"], "fr_a=slip+,k=slack,fr_b=slip-");
        assert_eq!(samples[2]["values"]["f_k"], -3.0e20);
        assert_eq!(
            json["intervals"],
            json!([
                {"start": 0.0, "end": 0.062, "mode": "fr_a=stuck,k=slack,fr_b=slip-"},
                {"start": 0.062, "end": 0.1, "mode": "fr_a=slip+,k=slack,fr_b=slip-"},
            ])
        );
        assert_eq!(
            json["events"],
            json!([{
                "t": 0.062,
                "from": "fr_a=stuck,k=slack,fr_b=slip-",
                "to": "fr_a=slip+,k=slack,fr_b=slip-",
                "element": "fr_a",
                "reason": "holding force reached the breakaway force",
            }])
        );
        assert_eq!(
            json["final"],
            json!({
                "t": 0.1,
                "mode": "fr_a=slip+,k=slack,fr_b=slip-",
                "states": {"p_ge": 1.25e-6, "q_k": 0.0},
            })
        );
        assert_eq!(
            json["stats"],
            json!({"segments": 3, "events": 1, "modes": 2})
        );
    }

    #[test]
    fn json_has_the_energy_books_only_when_they_were_kept() {
        assert!(to_json(&trajectory(), "m", "s").get("energy").is_none());
        let mut kept = trajectory();
        kept.energy = Some(bondgraph_solver::energy::EnergyBalance {
            initial_stored: 1.0,
            final_stored: 1.5,
            supplied: 2.0,
            dissipated: 0.25,
            lost_at_events: 0.125,
            error: 1e-15,
        });
        let json = to_json(&kept, "m", "s");
        assert_eq!(
            json["energy"],
            json!({
                "initial_stored": 1.0,
                "final_stored": 1.5,
                "supplied": 2.0,
                "dissipated": 0.25,
                "lost_at_events": 0.125,
                "residual": -1.125,
                "error": 1e-15,
            })
        );
    }

    #[test]
    fn json_writes_non_finite_numbers_and_missing_modes_as_null() {
        let mut odd = trajectory();
        odd.values[1] = f64::INFINITY;
        // Only the first sample recorded.
        odd.values.truncate(2);
        odd.sample_modes[2] = 9;
        odd.intervals.push((0.1, 0.2, 5));
        let json = to_json(&odd, "m", "s");
        assert_eq!(json["samples"][0]["values"]["f_k"], Value::Null);
        assert_eq!(
            json["samples"][1]["values"],
            json!({"v_a": null, "f_k": null})
        );
        assert_eq!(json["samples"][2]["mode"], Value::Null);
        assert_eq!(json["intervals"][2]["mode"], Value::Null);
    }
}
