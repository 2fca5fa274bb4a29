//! Whole commands on small models, as the binary runs them but without starting a process:
//! the files read from disk and parsed, the model checked, its modes derived, the work done
//! and the output written to a string. What a user waits for, less the process's own start.
//!
//!     cargo bench --bench commands

use std::hint::black_box;
use std::path::Path;

use bondgraph_view::{derive, read_source, simulate};
use criterion::{Criterion, criterion_group, criterion_main};

fn file(relative: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn commands(c: &mut Criterion) {
    let mut group = c.benchmark_group("command");
    let simulations = [
        (
            "simulate_msd_release",
            "models/teaching/mass_spring_damper.ron",
            "models/teaching/scenarios/msd_release.ron",
        ),
        (
            "simulate_fig6",
            "models/eversion/robot.ron",
            "models/scenarios/robot_growth.ron",
        ),
    ];
    for (name, model, scenario) in simulations {
        let (model, scenario) = (file(model), file(scenario));
        group.bench_function(name, |b| {
            b.iter(|| {
                let model = read_source(&model).expect("model");
                let scenario = read_source(&scenario).expect("scenario");
                let run = simulate::simulate(&model, &scenario).expect("runs");
                black_box(run.csv())
            })
        });
    }
    let msd = file("models/teaching/mass_spring_damper.ron");
    group.bench_function("equations_msd_json", |b| {
        b.iter(|| {
            let (model, source) = bondgraph_view::load(&msd).expect("model");
            let derived =
                derive::derive(&model, &source, &derive::Request::default()).expect("derives");
            black_box(derived.json().expect("json"))
        })
    });
    group.bench_function("check_msd", |b| {
        b.iter(|| {
            let (model, source) = bondgraph_view::load(&msd).expect("model");
            black_box(bondgraph_view::check::summary(&model, &source).expect("summary"))
        })
    });
    group.finish();
}

criterion_group!(benches, commands);
criterion_main!(benches);
