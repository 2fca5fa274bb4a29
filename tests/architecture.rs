//! The guards of the workspace's layout (`docs/architecture.md`): crates depend only on lower
//! layers, no new cycle among a crate's top-level modules, and no new oversized file or
//! function.
//!
//! A crate boundary fails to compile when an arrow points up; a module rule does not, so these
//! tests make the rules fail the build. The layout is not there yet: the debts it still carries
//! (a dependency that points across, the cycles inside a crate, the files and functions over
//! budget) are listed here as they are today, each may only shrink, and one that is paid must
//! be taken off its list (the tests fail while a list names what no longer exists), so the
//! lists say what is left to do.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The layers of `docs/architecture.md`: a crate may depend only on crates of lower layers.
/// Crates of the target layout that do not exist yet are listed, so that they land in place.
const LAYERS: &[(&str, u32)] = &[
    ("bondgraph-symbolic", 0),
    ("bondgraph-core", 1),
    ("bondgraph-solver", 2),
    ("bondgraph-ron", 2),
    ("bondgraph-fit", 3),
    ("bondgraph-view", 4),
    ("bondgraph-eversion", 4),
    ("bondgraph", 5),
    ("bondgraph-python", 5),
];

/// Dependencies that break the layering today: (from, to, why it is still there).
const CROSSING_DEPENDENCIES: &[(&str, &str, &str)] = &[];

/// The cycles among each crate's top-level modules today (each may only shrink).
const MODULE_CYCLES: &[(&str, &[&str])] = &[];

/// Lines a source file may hold (tests apart) before it must be split.
const FILE_BUDGET: usize = 1000;
/// Lines a function may span before it must be split.
const FUNCTION_BUDGET: usize = 150;

/// Files over [`FILE_BUDGET`] today, with their size now (each may only shrink).
const OVERSIZED_FILES: &[(&str, usize)] = &[];

/// Functions over [`FUNCTION_BUDGET`] today: (file, function, lines now).
const OVERSIZED_FUNCTIONS: &[(&str, &str, usize)] =
    &[("bondgraph-solver/src/events.rs", "first_crossing", 347)];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The workspace's packages: name, source folder (relative), and normal dependencies on
/// other workspace packages, from `cargo metadata`.
fn workspace() -> Vec<(String, PathBuf, Vec<String>)> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(root())
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    let packages = metadata["packages"].as_array().unwrap();
    let names: BTreeSet<&str> = packages
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    packages
        .iter()
        .map(|p| {
            let manifest = PathBuf::from(p["manifest_path"].as_str().unwrap());
            let folder = manifest
                .parent()
                .unwrap()
                .strip_prefix(root())
                .unwrap()
                .join("src");
            let dependencies = p["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["kind"].is_null() || d["kind"] == "build")
                .map(|d| d["name"].as_str().unwrap())
                .filter(|d| names.contains(d))
                .map(String::from)
                .collect();
            (
                p["name"].as_str().unwrap().to_string(),
                folder,
                dependencies,
            )
        })
        .collect()
}

fn layer(name: &str) -> u32 {
    LAYERS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, l)| *l)
        .unwrap_or_else(|| panic!("crate '{name}' has no layer in LAYERS (docs/architecture.md)"))
}

#[test]
fn crates_depend_only_on_lower_layers() {
    let mut crossing = BTreeSet::new();
    for (name, _, dependencies) in workspace() {
        for dependency in dependencies {
            if layer(&dependency) >= layer(&name) {
                crossing.insert((name.clone(), dependency));
            }
        }
    }
    let known: BTreeSet<(String, String)> = CROSSING_DEPENDENCIES
        .iter()
        .map(|(a, b, _)| (a.to_string(), b.to_string()))
        .collect();
    let new: Vec<_> = crossing.difference(&known).collect();
    assert!(
        new.is_empty(),
        "dependencies on a crate of the same or a higher layer: {new:?}"
    );
    let paid: Vec<_> = known.difference(&crossing).collect();
    assert!(
        paid.is_empty(),
        "gone, take them off CROSSING_DEPENDENCIES: {paid:?}"
    );
}

/// Every `.rs` file under `folder`.
fn sources(folder: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![folder.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The top-level modules of a crate whose source is in `folder`, and for each the others its
/// files name through `crate::` paths (comments left out).
fn module_graph(folder: &Path) -> BTreeMap<String, BTreeSet<String>> {
    // A module the crate root declares for tests only (`#[cfg(test)] mod testing;`) is not
    // part of what the crate builds: the tests that use it may sit anywhere.
    let root_file = ["lib.rs", "main.rs"]
        .iter()
        .find_map(|f| std::fs::read_to_string(folder.join(f)).ok())
        .unwrap_or_default();
    let test_only: BTreeSet<String> = root_file
        .lines()
        .zip(root_file.lines().skip(1))
        .filter(|(attribute, _)| attribute.trim() == "#[cfg(test)]")
        .filter_map(|(_, declaration)| {
            let name = declaration.trim().strip_prefix("mod ")?.strip_suffix(';')?;
            Some(name.to_string())
        })
        .collect();
    let modules: BTreeSet<String> = std::fs::read_dir(folder)
        .unwrap()
        .filter_map(|e| {
            let path = e.unwrap().path();
            let stem = path.file_stem()?.to_str()?.to_string();
            let module = path.is_dir() || path.extension().is_some_and(|e| e == "rs");
            (module && stem != "lib" && stem != "main" && !test_only.contains(&stem))
                .then_some(stem)
        })
        .collect();
    let mut graph: BTreeMap<String, BTreeSet<String>> = modules
        .iter()
        .map(|m| (m.clone(), BTreeSet::new()))
        .collect();
    for file in sources(folder) {
        let relative = file.strip_prefix(folder).unwrap();
        let first = relative.components().next().unwrap().as_os_str();
        let top = Path::new(first).file_stem().unwrap().to_str().unwrap();
        if !modules.contains(top) {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        for line in text.lines() {
            let code = line.split("//").next().unwrap();
            for target in crate_paths(code) {
                if target != top && modules.contains(&target) {
                    graph.get_mut(top).unwrap().insert(target);
                }
            }
        }
    }
    graph
}

/// The first segments of the `crate::` paths in a line: `crate::a::b` and `crate::{a, b::c}`.
fn crate_paths(code: &str) -> Vec<String> {
    let mut found = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        rest = &rest[at + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let inside = group.split('}').next().unwrap_or("");
            for item in inside.split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if !name.is_empty() {
                    found.push(name);
                }
            }
        } else {
            let name: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                found.push(name);
            }
        }
    }
    found
}

/// The strongly connected components of more than one module (Tarjan's algorithm).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        on_stack: BTreeSet<&'a str>,
        found: Vec<BTreeSet<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        let next = s.index.len();
        s.index.insert(v, next);
        s.low.insert(v, next);
        s.stack.push(v);
        s.on_stack.insert(v);
        for w in &s.graph[v] {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.on_stack.contains(w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = BTreeSet::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on_stack.remove(w);
                component.insert(w.to_string());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                s.found.push(component);
            }
        }
    }
    let mut state = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for v in graph.keys() {
        if !state.index.contains_key(v.as_str()) {
            visit(&mut state, v);
        }
    }
    state.found
}

#[test]
fn the_cycle_finder_finds_a_cycle_and_nothing_else() {
    let graph: BTreeMap<String, BTreeSet<String>> = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a", "d"]),
        ("d", vec![]),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.into_iter().map(String::from).collect()))
    .collect();
    let expected: BTreeSet<String> = ["a", "b", "c"].into_iter().map(String::from).collect();
    assert_eq!(cycles(&graph), vec![expected]);
    assert_eq!(
        crate_paths("use crate::{graph, model::Model}; crate::units::check(x)"),
        ["graph", "model", "units"]
    );
}

#[test]
fn no_new_cycle_among_a_crates_top_level_modules() {
    let mut problems = Vec::new();
    let mut seen = Vec::new();
    for (name, folder, _) in workspace() {
        for cycle in cycles(&module_graph(&root().join(&folder))) {
            let known = MODULE_CYCLES
                .iter()
                .filter(|(c, _)| *c == name)
                .find(|(_, modules)| cycle.iter().all(|m| modules.contains(&m.as_str())));
            match known {
                Some(entry) => seen.push(*entry),
                None => problems.push(format!("{name}: a new cycle {cycle:?}")),
            }
            if let Some((_, modules)) = known
                && modules.len() > cycle.len()
            {
                problems.push(format!(
                    "{name}: the cycle {modules:?} shrank to {cycle:?}: update MODULE_CYCLES"
                ));
            }
        }
    }
    for entry in MODULE_CYCLES {
        if !seen.contains(entry) {
            problems.push(format!("gone, take it off MODULE_CYCLES: {entry:?}"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// The lines of a file before its `#[cfg(test)]` module.
fn non_test_lines(text: &str) -> Vec<&str> {
    let lines: Vec<&str> = text.lines().collect();
    // The test module written inline ends the code; a test-only item or the declaration
    // of a test module in a file of its own (`#[cfg(test)] mod tests;`) does not.
    let end = (0..lines.len())
        .find(|&k| {
            lines[k].starts_with("#[cfg(test)]")
                && lines
                    .get(k + 1)
                    .is_some_and(|next| next.starts_with("mod ") && next.trim_end().ends_with('{'))
        })
        .unwrap_or(lines.len());
    lines[..end].to_vec()
}

#[test]
fn only_an_inline_test_module_ends_the_code_measured() {
    let text = "fn a() {}\n#[cfg(test)]\nmod units_tests;\n#[cfg(test)]\nfn hook() {}\nfn b() {}\n#[cfg(test)]\nmod tests {\n    fn t() {}\n}\n";
    assert_eq!(
        non_test_lines(text),
        [
            "fn a() {}",
            "#[cfg(test)]",
            "mod units_tests;",
            "#[cfg(test)]",
            "fn hook() {}",
            "fn b() {}"
        ]
    );
}

/// Functions of a file as rustfmt lays them out: `(name, lines)`, from the `fn` line to the
/// closing brace at its indentation.
fn functions(lines: &[&str]) -> Vec<(String, usize)> {
    let mut found = Vec::new();
    for (k, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        let mut words = trimmed.split_whitespace().peekable();
        while words
            .peek()
            .is_some_and(|w| w.starts_with("pub") || ["const", "async", "unsafe"].contains(w))
        {
            words.next();
        }
        if words.next() != Some("fn") || line.trim_end().ends_with(';') {
            continue;
        }
        let name: String = words
            .next()
            .unwrap_or("")
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        let closing = format!("{indent}}}");
        if let Some(end) = lines[k + 1..].iter().position(|l| *l == closing) {
            found.push((name, end + 2));
        }
    }
    found
}

#[test]
fn no_new_file_or_function_over_its_budget() {
    let mut problems = Vec::new();
    let mut files_seen = Vec::new();
    let mut functions_seen = Vec::new();
    for (_, folder, _) in workspace() {
        for file in sources(&root().join(&folder)) {
            let relative = file
                .strip_prefix(root())
                .unwrap()
                .to_str()
                .unwrap()
                .to_string();
            let name = file.file_name().unwrap().to_str().unwrap();
            if name == "tests.rs" || relative.contains("/tests/") {
                continue;
            }
            let text = std::fs::read_to_string(&file).unwrap();
            let lines = non_test_lines(&text);
            if lines.len() > FILE_BUDGET {
                match OVERSIZED_FILES.iter().find(|(f, _)| *f == relative) {
                    Some(&(_, allowed)) if lines.len() <= allowed => {
                        files_seen.push(relative.clone())
                    }
                    Some(&(_, allowed)) => problems.push(format!(
                        "{relative}: {} lines, more than the {allowed} it had: split it",
                        lines.len()
                    )),
                    None => problems.push(format!(
                        "{relative}: {} lines, over the budget of {FILE_BUDGET}: split it",
                        lines.len()
                    )),
                }
            }
            for (function, length) in functions(&lines) {
                if length <= FUNCTION_BUDGET {
                    continue;
                }
                let known = OVERSIZED_FUNCTIONS
                    .iter()
                    .find(|(f, n, _)| *f == relative && *n == function);
                match known {
                    Some(&(_, _, allowed)) if length <= allowed => {
                        functions_seen.push((relative.clone(), function))
                    }
                    Some(&(_, _, allowed)) => problems.push(format!(
                        "{relative}: fn {function} spans {length} lines, more than the {allowed} it had"
                    )),
                    None => problems.push(format!(
                        "{relative}: fn {function} spans {length} lines, over the budget of {FUNCTION_BUDGET}"
                    )),
                }
            }
        }
    }
    for (file, _) in OVERSIZED_FILES {
        if !files_seen.iter().any(|f| f == file) {
            problems.push(format!(
                "within budget now, take it off OVERSIZED_FILES: {file}"
            ));
        }
    }
    for (file, function, _) in OVERSIZED_FUNCTIONS {
        if !functions_seen
            .iter()
            .any(|(f, n)| f == file && n == function)
        {
            problems.push(format!(
                "within budget now, take it off OVERSIZED_FUNCTIONS: {file} fn {function}"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
