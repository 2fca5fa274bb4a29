//! The speed of `discover` on the paper's Table III: the whole candidate library, each
//! candidate refitted from several starts and cross-validated (the goal: under 2 s on
//! the project's 2-core machine), and the inner loop it is made of, one prediction of all 27
//! rows with new parameter values.
//!
//! Run with `cargo bench -p bondgraph-fit`.

use std::path::{Path, PathBuf};

use bondgraph_core::model::{self, extension::Extension};
use bondgraph_core::source::SourceFile;
use bondgraph_fit::data;
use bondgraph_fit::discover::{self, Candidate, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::predict::Predictor;
use criterion::{Criterion, criterion_group, criterion_main};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn read(relative: &str) -> String {
    std::fs::read_to_string(root().join(relative)).expect("bundled file")
}

fn bench(c: &mut Criterion) {
    let base = SourceFile::new("robot.ron", read("models/eversion/robot.ron"));
    let experiment =
        Experiment::parse("experiment.ron", &read("models/eversion/experiment.ron")).unwrap();
    let table3 = data::read(
        "table3.csv",
        &read("models/eversion/data/table3.csv"),
        &experiment,
    )
    .unwrap();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("models/eversion/extensions"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    paths.sort();
    let library: Vec<Candidate> = paths
        .iter()
        .map(|p| Candidate::new(&base, &Extension::read(p).unwrap()).unwrap())
        .collect();

    let mut group = c.benchmark_group("discover");
    group.sample_size(10);
    group.bench_function("library on Table III", |b| {
        b.iter(|| {
            discover::discover(&base, &experiment, &table3, &library, &Settings::default()).unwrap()
        });
    });
    group.finish();

    let model = model::load_source(&base).unwrap();
    let predictor = Predictor::new(model, &base, &experiment).unwrap();
    let names: Vec<String> = ["F_C_ge", "b", "F_S_ge"].map(String::from).to_vec();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    // Alternate two parameter sets, as a calibration does, so nothing is reused but the modes.
    let sets = [[9.125, 1250.0, 11.7], [0.5, 2300.0, 11.6]];
    let mut k = 0;
    c.bench_function("predict Table III (27 steady states)", |b| {
        b.iter(|| {
            k ^= 1;
            evaluator.set(&sets[k]);
            evaluator.predict(&table3.rows).unwrap()
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
