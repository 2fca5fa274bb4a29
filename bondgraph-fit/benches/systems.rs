//! The speed of fits on the systems with independent reference data, each in another domain
//! than the flagship: `calibrate` on the two-tank rig's steady sweep (27 rows, a nonlinear
//! orifice, time constants near 30 s) and on the two heated blocks' runs (two runs of 540
//! samples, a linear graph), and `discover` with the two-tank rig's library of five
//! candidates on its steady sweep with the tank-1 leak hidden.
//!
//! Run with `cargo bench -p bondgraph-fit --bench systems`; the figures are in `docs/speed.md`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use bondgraph_core::source::SourceFile;
use bondgraph_fit::calibration::calibrate;
use bondgraph_fit::data::{self, Dataset};
use bondgraph_fit::discover::{self, Candidate, Settings};
use bondgraph_fit::experiment::Experiment;
use bondgraph_ron::extension::Extension;
use criterion::{Criterion, criterion_group, criterion_main};

/// The allocator the `bondgraph` binary runs with, so that these figures are a user's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn file(relative: &str) -> Arc<SourceFile> {
    // Named by its full path: a time series' experiment finds its scenario beside it.
    let path: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(relative);
    let text = std::fs::read_to_string(&path).expect("bundled file");
    SourceFile::new(path.to_string_lossy(), text)
}

fn dataset(experiment: &Experiment, files: &[&str]) -> Dataset {
    let parts = files
        .iter()
        .map(|f| {
            let csv = file(f);
            data::read(csv.name(), csv.text(), experiment).unwrap()
        })
        .collect();
    Dataset::join(parts)
}

fn fits(c: &mut Criterion) {
    let mut group = c.benchmark_group("systems");
    group.sample_size(10);

    let tanks = file("models/examples/two_tank/two_tank.ron");
    let steady = Experiment::from_source(&file("models/examples/two_tank/experiment.ron")).unwrap();
    let sweep = dataset(&steady, &["models/examples/two_tank/data/steady.csv"]);
    group.bench_function("calibrate two-tank steady sweep (27 rows)", |b| {
        b.iter(|| calibrate(&tanks, &steady, &sweep, &Settings::default()).unwrap())
    });

    let blocks = file("models/examples/thermal/thermal.lg.ron");
    let runs =
        Experiment::from_source(&file("models/examples/thermal/experiment_step.ron")).unwrap();
    let recorded = dataset(
        &runs,
        &[
            "models/examples/thermal/data/step_1.csv",
            "models/examples/thermal/data/step_2.csv",
        ],
    );
    group.bench_function("calibrate thermal runs (2 x 540 samples)", |b| {
        b.iter(|| calibrate(&blocks, &runs, &recorded, &Settings::default()).unwrap())
    });

    let leak = dataset(
        &steady,
        &["models/examples/two_tank/data/hidden/tank-1-leak/steady.csv"],
    );
    let candidates: Vec<Candidate> = std::fs::read_dir(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../models/examples/two_tank/extensions"),
    )
    .unwrap()
    .map(|e| e.unwrap().path())
    .map(|path| {
        let relative = format!(
            "models/examples/two_tank/extensions/{}",
            path.file_name().unwrap().to_string_lossy()
        );
        let extension = Extension::load(&file(&relative)).unwrap();
        Candidate::new(&tanks, &extension).unwrap()
    })
    .collect();
    let settings = Settings::default();
    group.bench_function("discover two-tank steady sweep, 5 candidates", |b| {
        b.iter(|| discover::discover(&tanks, &steady, &leak, &candidates, &settings).unwrap())
    });
    group.finish();
}

criterion_group!(benches, fits);
criterion_main!(benches);
