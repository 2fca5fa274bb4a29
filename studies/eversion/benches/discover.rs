//! The speed of `discover` on the flagship: the whole candidate library on the paper's
//! Table III (27 rows), and on synthetic grids of 100 and 400 rows over Table III's ranges,
//! to show how the cost grows with the data; and the inner loop a fit is made of, one
//! prediction of Table III's 27 steady states with new parameter values.
//!
//! Run with `cargo bench -p bondgraph-eversion`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bondgraph_core::source::SourceFile;
use bondgraph_eversion::designs::grid_design;
use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::discover::{self, Candidate, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_fit::predict::Predictor;
use bondgraph_fit::synthetic::{self, Noise};
use bondgraph_ron::extension::Extension;
use criterion::{Criterion, criterion_group, criterion_main};

/// The allocator the `bondgraph` binary runs with, so that these figures are a user's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn read(relative: &str) -> String {
    std::fs::read_to_string(root().join(relative)).expect("bundled file")
}

/// Synthetic data on a grid of `pressures × channels` rows: the robot at the paper's
/// values, noise 0.1 mm/s (seed 1).
fn grid(
    base: &Arc<SourceFile>,
    experiment: &Experiment,
    columns: &Dataset,
    pressures: usize,
    channels: usize,
) -> Dataset {
    let model = bondgraph_ron::model::load_source(base).unwrap();
    let rows = synthetic::measure(
        &model,
        base,
        experiment,
        &[],
        &grid_design(pressures, channels),
        0.1,
        Some(0.0),
        &mut Noise::new(1),
    )
    .unwrap();
    Dataset {
        name: format!("grid {pressures}x{channels}"),
        rows,
        ..columns.clone()
    }
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
    let sets = [
        ("library on Table III (27 rows)", table3.clone()),
        (
            "library on 100 rows",
            grid(&base, &experiment, &table3, 20, 5),
        ),
        (
            "library on 400 rows",
            grid(&base, &experiment, &table3, 40, 10),
        ),
    ];
    for (name, data) in &sets {
        group.bench_function(*name, |b| {
            b.iter(|| {
                discover::discover(&base, &experiment, data, &library, &Settings::default())
                    .unwrap()
            });
        });
    }
    group.finish();

    let model = bondgraph_ron::model::load_source(&base).unwrap();
    let predictor = Predictor::new(model, &base, &experiment).unwrap();
    let names: Vec<String> = ["F_C_ge", "b", "F_S_ge"].map(String::from).to_vec();
    let mut evaluator = predictor.evaluator(&names).unwrap();
    // Alternate two parameter sets, as a calibration does, so nothing is reused but the modes.
    let values = [[9.125, 1250.0, 11.7], [0.5, 2300.0, 11.6]];
    let mut k = 0;
    c.bench_function("predict Table III (27 steady states)", |b| {
        b.iter(|| {
            k ^= 1;
            evaluator.set(&values[k]);
            evaluator.predict(&table3.rows).unwrap()
        });
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
