//! Helpers shared by the whole-program tests.

use std::path::{Path, PathBuf};

use bondgraph_core::equations::{self, Options, StateEquations, Variables};
use bondgraph_core::expr::{self, Expr, ExprKind};
use bondgraph_core::laws;
use bondgraph_core::model::Model;
use bondgraph_core::symbolic::RatFunc;

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Loads a model by its path relative to the repository root.
pub fn load(relative: &str) -> Model {
    let path = root().join(relative);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{relative}: {e}"));
    bondgraph_ron::model::load_str(relative, &text).unwrap_or_else(|e| panic!("{relative}:\n{e}"))
}

/// Derives the only mode of a plain model.
pub fn derive(model: &Model, variables: Variables) -> StateEquations {
    equations::derive(model, &laws::plain_laws(model), &Options { variables })
        .unwrap_or_else(|e| panic!("{}:\n{e}", model.name()))
}

/// A hand-written expression over the model's parameters, as an exact rational function.
///
/// This converter is deliberately separate from the model validator's, so that expected
/// values do not pass through the code under test beyond the parser and `RatFunc`'s
/// arithmetic.
pub fn expected(model: &Model, text: &str) -> RatFunc {
    fn convert(model: &Model, e: &Expr) -> RatFunc {
        match &e.kind {
            ExprKind::Number(n) => RatFunc::from_decimal(n).expect("number"),
            ExprKind::Symbol(s) => RatFunc::symbol(
                model
                    .symbols()
                    .get(s)
                    .unwrap_or_else(|| panic!("unknown parameter {s}")),
            ),
            ExprKind::Neg(a) => -convert(model, a),
            ExprKind::Add(a, b) => convert(model, a) + convert(model, b),
            ExprKind::Sub(a, b) => convert(model, a) - convert(model, b),
            ExprKind::Mul(a, b) => convert(model, a) * convert(model, b),
            ExprKind::Div(a, b) => convert(model, a)
                .checked_div(&convert(model, b))
                .expect("non-zero divisor"),
            ExprKind::Pow(a, n) => convert(model, a).powi(*n).expect("power"),
            ExprKind::RealPow(..) | ExprKind::Call(..) => {
                panic!(
                    "expected values are rational functions, not {text:?}",
                    text = e
                )
            }
        }
    }
    convert(
        model,
        &expr::parse(text).expect("expected expression parses"),
    )
}

/// Asserts a symbolic matrix equals hand-written entries, naming the first difference.
pub fn assert_symbolic(
    model: &Model,
    what: &str,
    actual: &[Vec<RatFunc>],
    expected_rows: &[&[&str]],
) {
    assert_eq!(actual.len(), expected_rows.len(), "{what}: row count");
    for (i, (row, want)) in actual.iter().zip(expected_rows).enumerate() {
        assert_eq!(row.len(), want.len(), "{what}: column count of row {i}");
        for (j, (entry, text)) in row.iter().zip(want.iter()).enumerate() {
            assert_eq!(
                entry,
                &expected(model, text),
                "{what}[{i}][{j}]: got {}, expected {text}",
                entry.text(model.symbols())
            );
        }
    }
}

/// Asserts numeric entries agree with expected numbers to a relative 1e-12.
pub fn assert_numeric(what: &str, actual: &[Vec<f64>], expected_rows: &[&[f64]]) {
    assert_eq!(actual.len(), expected_rows.len(), "{what}: row count");
    for (i, (row, want)) in actual.iter().zip(expected_rows).enumerate() {
        for (j, (a, e)) in row.iter().zip(want.iter()).enumerate() {
            let tolerance = 1e-12 * e.abs().max(1e-300);
            assert!(
                (a - e).abs() <= tolerance,
                "{what}[{i}][{j}]: got {a}, expected {e}"
            );
        }
    }
}

/// The numeric value of a parameter.
pub fn value(model: &Model, name: &str) -> f64 {
    model
        .parameters()
        .iter()
        .find(|p| p.name == name)
        .unwrap_or_else(|| panic!("no parameter {name}"))
        .value
}

/// Every bond-graph `.ron` file directly in `dir` (relative to the root), sorted: linear
/// graphs (`.lg.ron`) are left out, see [`linear_graph_files`].
pub fn ron_files(dir: &str) -> Vec<String> {
    files_ending(dir, ".ron")
        .into_iter()
        .filter(|f| !f.ends_with(".lg.ron"))
        .collect()
}

/// Every linear-graph file (`.lg.ron`) directly in `dir`, sorted.
pub fn linear_graph_files(dir: &str) -> Vec<String> {
    files_ending(dir, ".lg.ron")
}

fn files_ending(dir: &str, suffix: &str) -> Vec<String> {
    let mut files: Vec<String> = std::fs::read_dir(root().join(dir))
        .unwrap_or_else(|e| panic!("{dir}: {e}"))
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            let name = path.file_name()?.to_string_lossy().into_owned();
            name.ends_with(suffix).then(|| relative(&path))
        })
        .collect();
    files.sort();
    files
}

/// Every model file under `dir` (relative to the root), its subfolders included, sorted:
/// the `.ron` files whose text is a `Model(...)` or a `LinearGraph(...)`, not the
/// scenarios, experiments and extensions that lie beside them.
pub fn model_files_under(dir: &str) -> Vec<String> {
    fn walk(path: &Path, out: &mut Vec<String>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .map(|entry| entry.expect("a folder entry").path())
            .collect();
        entries.sort();
        for entry in entries {
            if entry.is_dir() {
                walk(&entry, out);
            } else if entry.extension().is_some_and(|e| e == "ron") && is_model(&entry) {
                out.push(relative(&entry));
            }
        }
    }
    let mut files = Vec::new();
    walk(&root().join(dir), &mut files);
    files
}

/// Whether the RON file at `path` is a model: its first value, after comments, is a
/// `Model(` or a `LinearGraph(`.
fn is_model(path: &Path) -> bool {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let code: String = text
        .lines()
        .filter(|l| !l.trim_start().starts_with("//"))
        .collect::<Vec<_>>()
        .join("\n");
    let head = code.trim_start();
    head.starts_with("Model(") || head.starts_with("LinearGraph(")
}

fn relative(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .to_string_lossy()
        .into_owned()
}
