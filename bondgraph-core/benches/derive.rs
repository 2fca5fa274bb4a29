//! How derivation time grows with model size: an N-mass chain, each pair of neighbours joined
//! by a spring and a damper in parallel, the first mass pushed by a force. It has 2N - 1
//! states and 6N - 3 elements; the goals: N = 1000 (1999 states) derived symbolically in under
//! a second, and N = 1667 (10,000 elements) parsed, checked and derived in under a second.
//!
//! Every mass, spring and damper has its own parameter, so the symbolic work is that of a
//! real model, not of one repeated symbol.

use std::fmt::Write;

use bondgraph_core::equations::{self, Options};
use bondgraph_core::laws;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

/// The RON text of an `n`-mass chain.
pub fn chain(n: usize) -> String {
    let mut parameters = String::new();
    let mut elements = String::from("\"force\": Se(effort: \"F\"),\n");
    let mut bonds = String::from("(\"force\", \"v1\"),\n");
    for i in 1..=n {
        let _ = writeln!(
            parameters,
            "\"m{i}\": (value: {}, unit: \"kg\"),",
            1.0 + i as f64 * 0.01
        );
        let _ = writeln!(
            elements,
            "\"v{i}\": One, \"mass{i}\": I(inertance: \"m{i}\"),"
        );
        let _ = writeln!(bonds, "(\"v{i}\", \"mass{i}\"),");
        if i < n {
            let _ = writeln!(
                parameters,
                "\"k{i}\": (value: {}, unit: \"N/m\"), \"b{i}\": (value: 0.5, unit: \"N*s/m\"),",
                100.0 + i as f64
            );
            let _ = writeln!(
                elements,
                "\"coupling{i}\": Zero, \"stretch{i}\": One, \"spring{i}\": C(stiffness: \"k{i}\"), \"damper{i}\": R(resistance: \"b{i}\"),"
            );
            let _ = writeln!(
                bonds,
                "(\"v{i}\", \"coupling{i}\"), (\"coupling{i}\", \"v{next}\"), (\"coupling{i}\", \"stretch{i}\"), (\"stretch{i}\", \"spring{i}\"), (\"stretch{i}\", \"damper{i}\"),",
                next = i + 1
            );
        }
    }
    format!(
        "Model(name: \"chain_{n}\", parameters: {{ {parameters} }}, inputs: {{ \"F\": (unit: \"N\") }}, elements: {{ {elements} }}, bonds: [ {bonds} ])"
    )
}

fn derive_chain(c: &mut Criterion) {
    let mut group = c.benchmark_group("derive_chain");
    group.sample_size(10);
    for n in [10, 100, 1000, 1667] {
        let text = chain(n);
        // Check once, outside the timing, that the chain is what it claims to be.
        let parsed =
            bondgraph_ron::model::load_str("chain.ron", &text).expect("chain model is valid");
        let eq = equations::derive(&parsed, &laws::plain_laws(&parsed), &Options::default())
            .expect("chain derives");
        assert_eq!(eq.state_count(), 2 * n - 1);

        group.bench_with_input(BenchmarkId::new("parse_and_derive", n), &text, |b, text| {
            b.iter(|| {
                let model = bondgraph_ron::model::load_str("chain.ron", text).expect("valid");
                equations::derive(&model, &laws::plain_laws(&model), &Options::default())
                    .expect("derives")
            })
        });
        group.bench_with_input(BenchmarkId::new("derive_only", n), &parsed, |b, model| {
            b.iter(|| {
                equations::derive(model, &laws::plain_laws(model), &Options::default())
                    .expect("derives")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, derive_chain);
criterion_main!(benches);
