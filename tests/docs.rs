//! Every command the README and the manual (`docs/*.md`) show is run, so the docs cannot go
//! stale.
//!
//! A command is a line of a fenced block that starts `$ bondgraph`, `bondgraph` or `cargo run
//! --release --` (a trailing `\` continues it; `[...]` is an optional part, left out; `# ...`
//! a remark; `> FILE` writes standard output to a file). Each block's commands run in order
//! in a scratch folder of their own, in which `models/` and `tests/` stand for the repository's,
//! so that the paths read as written and the files written land outside the repository.
//!
//! A `$` command's block shows its output: every line shown, except `...` (an elision), must
//! come in the command's output (standard output, then standard error) in the order shown. A
//! command whose shown output starts with `error:` must fail; any other must succeed.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::support::root;

/// Commands the docs show that this test leaves to others: (the command's start, who runs it).
const RUN_ELSEWHERE: &[(&str, &str)] = &[
    (
        "reproduce",
        "tests/cli.rs (reproduce_writes_its_results_and_the_json_contract)",
    ),
    (
        "cargo test --workspace",
        "CI (.ci/run), which is this test's own run",
    ),
    (
        "pip install ./python",
        "CI (.ci/run), then the Python tests",
    ),
];

/// A command found in the docs.
#[derive(Debug)]
struct Shown {
    /// `FILE:LINE` of the command.
    place: String,
    /// The arguments after `bondgraph`.
    arguments: Vec<String>,
    /// Where `> FILE` sends standard output.
    redirect: Option<String>,
    /// The output shown under a `$` command (empty when none is shown).
    output: Vec<String>,
    /// The block the command is in, within its file (commands of one block share a folder).
    block: usize,
}

/// The markdown files of the docs: the README and `docs/*.md`.
fn markdown_files() -> Vec<PathBuf> {
    let mut files = vec![root().join("README.md")];
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    files.extend(pages);
    files
}

/// The command of a line, as the words after `bondgraph`, or `None` when the line is none.
fn command_words(line: &str) -> Option<String> {
    let line = line.trim();
    let line = line.strip_prefix("$ ").unwrap_or(line);
    for start in ["bondgraph ", "cargo run --release -- "] {
        if let Some(rest) = line.strip_prefix(start) {
            return Some(rest.to_string());
        }
    }
    ["cargo test --workspace", "pip install ./python"]
        .iter()
        .find(|c| line.starts_with(*c))
        .map(|c| c.to_string())
}

/// The optional parts `[...]` and the remark `# ...` left out.
fn essential(words: &str) -> String {
    let without_remark = match words.find(" #") {
        Some(at) => &words[..at],
        None => words,
    };
    let mut kept = String::new();
    let mut depth = 0;
    for c in without_remark.chars() {
        match c {
            '[' => depth += 1,
            ']' if depth > 0 => depth -= 1,
            _ if depth == 0 => kept.push(c),
            _ => {}
        }
    }
    kept
}

fn commands_in(file: &Path) -> Vec<Shown> {
    let text = std::fs::read_to_string(file).unwrap();
    let name = file.strip_prefix(root()).unwrap().display().to_string();
    let lines: Vec<&str> = text.lines().collect();
    let mut shown: Vec<Shown> = Vec::new();
    let mut in_block = false;
    let mut block = 0;
    let mut k = 0;
    while k < lines.len() {
        let line = lines[k];
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            block += 1;
            k += 1;
            continue;
        }
        if !in_block {
            k += 1;
            continue;
        }
        let dollar = line.trim_start().starts_with("$ ");
        let Some(mut words) = command_words(line) else {
            // Output under the last `$` command of this block.
            if let Some(last) = shown.last_mut()
                && last.block == block
                && !last.output.is_empty()
            {
                last.output.push(line.trim_end().to_string());
            }
            k += 1;
            continue;
        };
        let place = format!("{name}:{}", k + 1);
        while words.trim_end().ends_with('\\') && k + 1 < lines.len() {
            words = format!(
                "{} {}",
                words.trim_end().trim_end_matches('\\'),
                lines[k + 1].trim()
            );
            k += 1;
        }
        let words = essential(&words);
        let (words, redirect) = match words.split_once(" > ") {
            Some((command, file)) => (command.to_string(), Some(file.trim().to_string())),
            None => (words, None),
        };
        shown.push(Shown {
            place,
            arguments: words.split_whitespace().map(String::from).collect(),
            redirect,
            // A `$` command's output follows it; mark it with an empty first line.
            output: if dollar {
                vec![String::new()]
            } else {
                Vec::new()
            },
            block,
        });
        k += 1;
    }
    for command in &mut shown {
        command.output.retain(|l| !l.is_empty());
    }
    shown
}

/// A folder in which `models/` and `tests/` are the repository's.
fn scratch(file: &Path, block: usize) -> PathBuf {
    let stem = file.file_stem().unwrap().to_string_lossy();
    let dir = std::env::temp_dir().join(format!(
        "bondgraph-docs-{stem}-{block}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for linked in ["models", "tests"] {
        std::os::unix::fs::symlink(root().join(linked), dir.join(linked)).unwrap();
    }
    dir
}

#[test]
fn every_command_in_the_docs_runs_and_prints_what_they_show() {
    let mut problems = Vec::new();
    let mut ran = 0;
    for file in markdown_files() {
        let mut folder: Option<(usize, PathBuf)> = None;
        for shown in commands_in(&file) {
            let joined = shown.arguments.join(" ");
            if RUN_ELSEWHERE
                .iter()
                .any(|(start, _)| joined.starts_with(start))
            {
                continue;
            }
            if folder.as_ref().is_none_or(|(b, _)| *b != shown.block) {
                folder = Some((shown.block, scratch(&file, shown.block)));
            }
            let dir = &folder.as_ref().unwrap().1;
            let output = Command::new(env!("CARGO_BIN_EXE_bondgraph"))
                .args(&shown.arguments)
                .current_dir(dir)
                .output()
                .unwrap();
            ran += 1;
            let stdout = String::from_utf8_lossy(&output.stdout).to_string();
            let stderr = String::from_utf8_lossy(&output.stderr).to_string();
            if let Some(target) = &shown.redirect {
                std::fs::write(dir.join(target), &stdout).unwrap();
            }
            let fails = shown
                .output
                .first()
                .is_some_and(|l| l.starts_with("error:"));
            if output.status.success() == fails {
                problems.push(format!(
                    "{}: `bondgraph {joined}` {} (exit {:?}): {}",
                    shown.place,
                    if fails {
                        "succeeded where the docs show an error"
                    } else {
                        "failed"
                    },
                    output.status.code(),
                    stderr.lines().next().unwrap_or("")
                ));
                continue;
            }
            let printed: Vec<&str> = stdout
                .lines()
                .chain(stderr.lines())
                .map(str::trim_end)
                .collect();
            let mut at = 0;
            for expected in shown.output.iter().filter(|l| l.trim() != "...") {
                match printed[at..].iter().position(|l| l == expected) {
                    Some(found) => at += found + 1,
                    None => {
                        problems.push(format!(
                            "{}: `bondgraph {joined}` does not print, where the docs show it:\n  {expected}",
                            shown.place
                        ));
                        break;
                    }
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // The docs show commands: a parser that found none would pass vacuously.
    assert!(ran >= 12, "only {ran} commands found in the docs");
}

#[test]
fn the_docs_command_reader_takes_what_the_docs_write() {
    assert_eq!(
        essential("discover --model m.ron --data d.csv [--out DIR] [--format json]"),
        "discover --model m.ron --data d.csv  "
    );
    assert_eq!(
        essential("check bad.ron       # \"damper\": R(resistance: \"(b + k)*x\")"),
        "check bad.ron      "
    );
    assert_eq!(
        command_words("$ bondgraph check x.ron").as_deref(),
        Some("check x.ron")
    );
    assert_eq!(
        command_words("cargo run --release -- reproduce").as_deref(),
        Some("reproduce")
    );
    assert_eq!(command_words("A = [ 0 ]"), None);
}
