//! Hidden-effect tests on the second system with data, the geared motor of
//! `models/examples/geared_motor/`: synthetic steady speeds with one candidate of its library
//! hidden (parameter drawn from a seed, noise 0.05 rad/s), handed to `discover` as CSV.
//!
//! The truth is `data/generate.py`'s (K = 0.05 N m/A, b = 0.05 N m s/rad, T_C = 0.15 N m,
//! T_S = 0.3 N m, R_a = 2 ohm, N = 20). A turning shaft settles at
//! `w = (N K V/R_a - T_C - tau)/D` with `D = b + N² K²/R_a`, so on steady speeds each
//! candidate is a refit in disguise, derived by hand:
//! - `shaft-windage` adds `b_w` to `b`: the refit gives `b + b_w`;
//! - `brush-voltage-drop` takes `U_b` off `V`, which is `N K U_b/R_a = 0.5 U_b` more Coulomb
//!   (and breakaway) torque: the refit gives `T_C + 0.5 U_b`;
//! - `brake-loaded-bearings` adds `mu_b tau` to the friction, scaling the brake's coefficient
//!   by `1 + mu_b`; matching the coefficients of `V`, `tau` and 1 gives
//!   `K' = K/(1 + mu_b)`, `T_C' = T_C/(1 + mu_b)` and `b' = D/(1 + mu_b) - N² K'²/R_a`,
//!   which predict every row (the brake's absent rows too) exactly as the truth.
//!
//! So nothing may be selected, and the refit must carry the effect within four standard
//! errors. Detection rates over 20 seeds are an ignored test (figures in the README).

use std::path::PathBuf;

use crate::motor::{self, library, motor};
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::discover::{self, Candidate, Discovery, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::synthetic::{self, Noise};
use bondgraph_ron::extension::Extension;

fn experiment() -> Experiment {
    motor::experiment("experiment.ron")
}

const TRUTH: [(&str, f64); 4] = [("K", 0.05), ("b", 0.05), ("T_C", 0.15), ("T_S", 0.3)];

/// The bundled `data/steady.csv`'s 22 conditions (its speeds replaced), the truth with
/// `hidden` (an id, its parameter and value) or nothing, noise 0.05 rad/s from `seed`,
/// written as CSV, read back and discovered.
fn discover_hidden(hidden: Option<(&str, &str, f64)>, seed: u64) -> Discovery {
    let experiment = experiment();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let design = data::read_file(
        &root.join("models/examples/geared_motor/data/steady.csv"),
        &experiment,
    )
    .unwrap()
    .rows;
    let library = library();
    let mut values: Vec<(String, f64)> = TRUTH.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    let (model, source) = match hidden {
        Some((id, parameter, value)) => {
            values.push((parameter.to_string(), value));
            let c = library.iter().find(|c| c.id == id).unwrap();
            (c.model.clone(), c.source.clone())
        }
        None => (
            bondgraph_ron::model::load_source(&motor()).unwrap(),
            motor(),
        ),
    };
    let rows = synthetic::measure(
        &model,
        &source,
        &experiment,
        &values,
        &design,
        0.05,
        // A shaft held by its bearings is measured standing still.
        Some(0.0),
        &mut Noise::new(seed),
    )
    .unwrap();
    let csv = data::write(&Dataset {
        name: "synthetic.csv".into(),
        conditions: vec!["V_V".into(), "tau_mNm".into()],
        observed: vec!["w_rad_s".into()],
        time: None,
        rows,
        ignored: Vec::new(),
    });
    let dataset = data::read("synthetic.csv", &csv, &experiment).unwrap();
    discover::discover(
        &motor(),
        &experiment,
        &dataset,
        &library,
        &Settings::default(),
    )
    .unwrap()
}

/// A value drawn uniformly in `[lo, hi]` from the seed.
fn draw(seed: u64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * Noise::new(seed ^ 0x5EED).uniform()
}

/// Whether the base model's refit of `name` is within four standard errors of `expected`.
fn carries(d: &Discovery, name: &str, expected: f64) -> bool {
    let e = &d.baseline.params[name];
    e.std_error
        .is_some_and(|se| (e.value - expected).abs() <= 4.0 * se)
}

/// What each id must give: nothing selected, the hidden id reported indistinguishable from
/// the base model, and the refit carrying the effect.
fn found(id: Option<&str>, value: f64, d: &Discovery) -> bool {
    let (k, t_c) = (TRUTH[0].1, TRUTH[2].1);
    let reported = id.is_none_or(|id| d.indistinguishable.iter().any(|i| i == id));
    d.selected.is_none()
        && reported
        && match id {
            None => true,
            Some("shaft-windage") => carries(d, "b", TRUTH[1].1 + value),
            Some("brush-voltage-drop") => carries(d, "T_C", t_c + 0.5 * value),
            Some("brake-loaded-bearings") => {
                let scale = 1.0 + value;
                let big_d = TRUTH[1].1 + 400.0 * k * k / 2.0;
                let k_refit = k / scale;
                carries(d, "K", k_refit)
                    && carries(d, "T_C", t_c / scale)
                    && carries(d, "b", big_d / scale - 400.0 * k_refit * k_refit / 2.0)
            }
            Some(other) => panic!("no rule for {other}"),
        }
}

/// The ids, their parameters and the ranges their values are drawn from.
const HIDDEN: [(&str, &str, f64, f64); 3] = [
    ("shaft-windage", "b_w", 0.01, 0.05),
    ("brush-voltage-drop", "U_b", 0.3, 1.0),
    ("brake-loaded-bearings", "mu_b", 0.1, 0.3),
];

fn check(index: usize, seed: u64) {
    let (id, parameter, lo, hi) = HIDDEN[index];
    let value = draw(seed, lo, hi);
    let d = discover_hidden(Some((id, parameter, value)), seed);
    assert!(
        found(Some(id), value, &d),
        "{id} = {value}:\n{}",
        d.summary()
    );
}

#[test]
fn hidden_windage_is_carried_by_the_viscous_coefficient() {
    check(0, 1);
}

#[test]
fn hidden_brush_drop_is_carried_by_the_coulomb_torque() {
    check(1, 2);
}

/// Seed 109's candidate search ends at a deeper drop (0.42 V for 0.32) with a lower Coulomb
/// torque, predicting every row as the base model's refit does; there its column is not
/// within 2 % of the base columns' span, and the drop read "not significant".
#[test]
fn a_brush_drop_found_deeper_than_hidden_is_still_a_refit_in_disguise() {
    check(1, 109);
}

#[test]
fn hidden_brake_loading_is_carried_by_the_torque_constant_and_friction() {
    check(2, 3);
}

#[test]
fn nothing_hidden_nothing_selected() {
    let d = discover_hidden(None, 4);
    assert!(found(None, 0.0, &d), "{}", d.summary());
}

/// A speed ceiling of at most 10 rad/s on the bundled `steady.csv`, whose shaft turns at up to
/// 21.45 rad/s: at no value within its bounds does it contain the base model there, so it
/// fits worse, and is said to. Every row measured faster than 10 rad/s is predicted at 10 at
/// most, which bounds its RMSE below by `sqrt(Σ (w - 10)² / n)` over those rows.
#[test]
fn a_candidate_whose_bounds_exclude_the_base_model_is_worse_than_the_base() {
    let experiment = experiment();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let dataset = data::read_file(
        &root.join("models/examples/geared_motor/data/steady.csv"),
        &experiment,
    )
    .unwrap();
    let ceiling = SourceFile::new(
        "shaft-speed-ceiling.ron",
        r#"Extension(
    id: "shaft-speed-ceiling",
    cause: "a governor that holds the shaft below a top speed",
    evidence: "the speed at the highest voltage",
    parameters: {
        "w_max": (value: 10.0, unit: "rad/s", bounds: (1.0, 10.0), description: "top speed"),
    },
    elements: {
        "governor": FlowLimit(max_flow: "w_max"),
    },
    bonds: [("shaft", "governor")],
)"#
        .to_string(),
    );
    let mut candidates = library();
    candidates.push(Candidate::new(&motor(), &Extension::load(&ceiling).unwrap()).unwrap());
    let d = discover::discover(
        &motor(),
        &experiment,
        &dataset,
        &candidates,
        &Settings::default(),
    )
    .unwrap();
    let ranked = d
        .ranking
        .iter()
        .find(|r| r.id == "shaft-speed-ceiling")
        .unwrap();
    let speeds: Vec<f64> = dataset.rows.iter().map(|r| r.observed[0]).collect();
    let floor = (speeds
        .iter()
        .filter(|&&w| w > 10.0)
        .map(|w| (w - 10.0).powi(2))
        .sum::<f64>()
        / speeds.len() as f64)
        .sqrt();
    assert!(floor > 1.0, "{floor}");
    assert!(ranked.rmse_fit >= floor, "{} < {floor}", ranked.rmse_fit);
    assert!(ranked.rmse_fit > d.baseline.rmse_fit);
    assert_eq!(ranked.verdict, "worse than the base", "{}", d.summary());
    assert!(
        d.summary().contains("shaft-speed-ceiling: RMSE"),
        "{}",
        d.summary()
    );
    // The library's candidates contain the base model: none is worse.
    for r in d.ranking.iter().filter(|r| r.id != "shaft-speed-ceiling") {
        assert_ne!(r.verdict, "worse than the base", "{}", r.id);
    }
}

#[test]
#[ignore = "slow: a statistic for the README, not a check"]
fn motor_detection_rate() {
    let seeds = 100..120;
    for (index, &(id, ..)) in HIDDEN.iter().enumerate() {
        let hits = seeds
            .clone()
            .filter(|&seed| {
                let (_, parameter, lo, hi) = HIDDEN[index];
                let value = draw(seed, lo, hi);
                let d = discover_hidden(Some((id, parameter, value)), seed);
                let ok = found(Some(id), value, &d);
                if !ok && std::env::var("DETECTION_VERBOSE").is_ok() {
                    println!("{id} = {value}, seed {seed}: missed\n{}", d.summary());
                }
                ok
            })
            .count();
        println!("{id}: {hits}/20");
    }
    let nulls = seeds
        .filter(|&seed| found(None, 0.0, &discover_hidden(None, seed)))
        .count();
    println!("nothing hidden: {nulls}/20");
}
