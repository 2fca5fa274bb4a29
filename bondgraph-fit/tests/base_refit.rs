//! `discover` fitting the base model again when a candidate's fit shows it a better basin:
//! the lead-screw actuator's two recorded runs (`models/examples/actuator/`,
//! `experiment_step.ron`) with load-dependent friction hidden in them
//! (`data/hidden/load-dependent-friction/`).

use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::discover::{self, Candidate, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_ron::extension::Extension;

use crate::motor::file;

const ACTUATOR: &str = "models/examples/actuator";

fn candidate(id: &str) -> Candidate {
    let base = file(&format!("{ACTUATOR}/actuator.ron"));
    let extension = Extension::load(&file(&format!("{ACTUATOR}/extensions/{id}.ron"))).unwrap();
    Candidate::new(&base, &extension).unwrap()
}

#[test]
fn after_the_base_model_is_fitted_again_no_candidate_fits_worse_than_it() {
    // The base model's own search on these runs ends in a basin that guide-seal drag's fit
    // (its drag near zero, its other parameters elsewhere) beats with the base model's
    // parameters alone; the base model is fitted again from there, and its fit is better
    // than the one it gets alone. A candidate contains the base model, so every candidate's
    // fit is at least as good as the new base fit (the F-test's extra sum of squares is
    // never negative): guide-seal drag's and load-dependent friction's, kept from before as
    // they already are, and the Stribeck weakening's, which first fitted as the old base
    // did and is fitted again. The hidden cause is still selected.
    let base = file(&format!("{ACTUATOR}/actuator.ron"));
    let experiment =
        Experiment::from_source(&file(&format!("{ACTUATOR}/experiment_step.ron"))).unwrap();
    let runs: Vec<_> = ["step_1.csv", "step_2.csv"]
        .iter()
        .map(|name| {
            let csv = file(&format!(
                "{ACTUATOR}/data/hidden/load-dependent-friction/{name}"
            ));
            data::read(csv.name(), csv.text(), &experiment).unwrap()
        })
        .collect();
    let data = Dataset::join(runs);
    let mut settings = Settings::default();
    settings.resampling.count = Some(0);
    let alone = discover::discover(&base, &experiment, &data, &[], &settings).unwrap();
    let candidates = [
        candidate("guide-seal-drag"),
        candidate("load-dependent-friction"),
        candidate("stribeck-weakening"),
    ];
    let discovery = discover::discover(&base, &experiment, &data, &candidates, &settings).unwrap();
    assert!(
        discovery.baseline.rmse_fit < alone.baseline.rmse_fit * (1.0 - 1e-7),
        "the base model was not fitted again: {} alone, {} beside its candidates",
        alone.baseline.rmse_fit,
        discovery.baseline.rmse_fit
    );
    for ranked in &discovery.ranking {
        assert!(
            ranked.rmse_fit <= discovery.baseline.rmse_fit,
            "'{}' fits worse ({}) than the base model ({})",
            ranked.id,
            ranked.rmse_fit,
            discovery.baseline.rmse_fit
        );
    }
    assert_eq!(
        discovery.selected.as_deref(),
        Some("load-dependent-friction")
    );
}
