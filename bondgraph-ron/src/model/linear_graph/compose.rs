//! Sub-graphs: a linear-graph file used as a branch of another, flattened into its branches
//! before the graph is checked, as a bond graph's sub-models are ([`crate::model::compose`]).
//!
//! A graph declares `terminals` (its nodes that the outside's branches join) and another
//! uses it, `"wall": Subgraph(file: "layer.lg.ron", parameters: {"R_w": 0.02})`, naming its
//! terminals as nodes (`to: "wall.outside"`). Its ground is the using graph's ground (one
//! reference for the whole model, as Rowell and Wormley draw it); its other nodes and its
//! branches are named with the use's name in front (`wall.core`, `wall.capacity`), and its
//! parameters and inputs as in a bond graph's sub-model. Each sub-graph file is checked on
//! its own first, terminals open, so its mistakes are reported in it; a cycle of files, a
//! terminal it does not have or one left unconnected are reported in the file that uses it.

use std::collections::HashMap;
use std::path::PathBuf;

use bondgraph_core::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result, suggest};
use bondgraph_core::expr::rename_symbols;
use bondgraph_core::model::source_map::{EntrySpans, SourceMap};
use bondgraph_core::model::{PartSpec, state_element};
use bondgraph_core::source::SourceFile;

use super::format::{RawBranch, RawLinearGraph};
use crate::model::compose::{Given, MAX_ELEMENTS, key_span, list, names_of, part_path, use_error};
use crate::model::parse::{FileKind, parse_file};

/// Flattens the sub-graphs of `raw` (read from `source`, spans in `map`).
///
/// # Errors
/// A sub-graph file that cannot be read or is not a valid graph, and every composition
/// problem, each located in the file that caused it.
pub(crate) fn compose(
    source: &SourceFile,
    raw: RawLinearGraph,
    map: SourceMap,
) -> Result<(RawLinearGraph, SourceMap, Vec<PartSpec>)> {
    let mut composer = Composer::default();
    let (raw, map) = composer.flatten(source, raw, map)?;
    Ok((raw, map, composer.uses))
}

#[derive(Default)]
struct Composer {
    /// Sub-graphs read so far, by path, flattened and checked; `None` for one whose
    /// problems were reported at its first use.
    parts: HashMap<PathBuf, Option<(String, RawLinearGraph)>>,
    /// The files being composed, outermost first.
    stack: Vec<PathBuf>,
    /// The uses of the outermost file, each with its terminals' nodes.
    uses: Vec<PartSpec>,
}

/// One use of a sub-graph: its terminals (each with the node it became) and which of them
/// the using file joins.
struct Use {
    file: String,
    model: String,
    terminals: Vec<(String, String)>,
    connected: Vec<String>,
    entry: EntrySpans,
}

impl Composer {
    fn flatten(
        &mut self,
        source: &SourceFile,
        mut raw: RawLinearGraph,
        map: SourceMap,
    ) -> Result<(RawLinearGraph, SourceMap)> {
        if !raw
            .branches
            .iter()
            .any(|(_, b)| matches!(b, RawBranch::Subgraph { .. }))
        {
            return Ok((raw, map));
        }
        let written = std::mem::take(&mut raw.branches);
        let mut flat = Flat {
            raw,
            branches: Vec::new(),
            branch_spans: Vec::new(),
            own_branch: Vec::new(),
            parameter_spans: map.parameters.clone(),
            input_spans: map.inputs.clone(),
            problems: Vec::new(),
            uses: HashMap::new(),
        };
        for (index, (name, branch)) in written.into_iter().enumerate() {
            let entry = map.branches.get(index).cloned().unwrap_or(EntrySpans {
                key: name.clone(),
                key_span: map.root,
                value_span: map.root,
                kind: None,
                fields: Vec::new(),
            });
            let RawBranch::Subgraph {
                file,
                parameters,
                inputs,
                terminals: joined,
            } = branch
            else {
                flat.branches.push((name, branch));
                flat.branch_spans.push(entry);
                flat.own_branch.push(true);
                continue;
            };
            let (file_name, part) = match self.part(source, &entry, &name, &file) {
                Ok(part) => part,
                Err(diagnostics) => {
                    flat.problems.extend(diagnostics.0);
                    continue;
                }
            };
            let given = Given {
                parameters: &parameters,
                inputs: &inputs,
            };
            let found = given.check(
                source,
                &entry,
                ("sub-graph", &name),
                (
                    &file_name,
                    [names_of(&part.parameters), names_of(&part.inputs)],
                ),
            );
            if !found.is_empty() {
                flat.problems.extend(found);
                continue;
            }
            let used = flat.instantiate(
                source,
                (&name, &entry),
                (file_name, &part),
                (&given, &joined),
            );
            flat.uses.insert(name.clone(), used);
            if flat.branches.len() > MAX_ELEMENTS {
                flat.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::TooLarge,
                        format!(
                            "sub-graph '{name}': the composed graph has {} branches, over the \
                             limit of {MAX_ELEMENTS}",
                            flat.branches.len()
                        ),
                    )
                    .at(source, entry.key_span),
                );
                return Err(Diagnostics(flat.problems));
            }
        }
        flat.join_terminals(source);
        flat.check_connected(source);
        if !flat.problems.is_empty() {
            return Err(Diagnostics(flat.problems));
        }
        if self.stack.is_empty() {
            self.uses = flat.part_specs();
        }
        Ok(flat.finish(map))
    }

    /// The sub-graph `file` used as `name` (at `entry`): read, composed and checked once.
    fn part(
        &mut self,
        parent: &SourceFile,
        entry: &EntrySpans,
        name: &str,
        file: &str,
    ) -> Result<(String, RawLinearGraph)> {
        let fail =
            |kind, message: String| use_error(parent, entry, ("sub-graph", name), kind, message);
        let (path, key) = part_path(parent, entry, ("sub-graph", name), file, &self.stack)?;
        match self.parts.get(&key) {
            Some(Some(part)) => return Ok(part.clone()),
            Some(None) => return Err(Diagnostics(Vec::new())),
            None => {}
        }
        let text = crate::read::read_text(&path, "sub-graph file")
            .map_err(|message| fail(DiagnosticKind::Io, message))?;
        let part_source = SourceFile::new(path.display().to_string(), text);
        if crate::model::Format::of(part_source.text()) != crate::model::Format::LinearGraph {
            return Err(fail(
                DiagnosticKind::Submodel,
                format!("'{file}' is not a linear graph; a sub-graph is a LinearGraph(...) file"),
            ));
        }
        let (raw, map) = parse_file::<RawLinearGraph>(&part_source, FileKind::LinearGraph)?;
        if raw.terminals.is_empty() {
            return Err(fail(
                DiagnosticKind::Submodel,
                format!(
                    "'{file}' declares no terminals, so no branch can join it; add terminals: \
                     {{\"name\": (node: \"a node\")}}"
                ),
            ));
        }
        self.stack.push(key.clone());
        let composed = self.flatten(&part_source, raw, map);
        self.stack.pop();
        let checked = composed.and_then(|(raw, map)| {
            super::check_and_validate(&part_source, raw.clone(), &map, Vec::new()).map(|_| raw)
        });
        let part = checked.map(|raw| (part_source.name().to_string(), raw));
        self.parts.insert(key, part.as_ref().ok().cloned());
        part
    }
}

/// The flat graph being built, its source map in step.
struct Flat {
    /// The graph's own name, ground, terminals, and parameters and inputs (its sub-graphs'
    /// added); its branches are in `branches`.
    raw: RawLinearGraph,
    branches: Vec<(String, RawBranch)>,
    branch_spans: Vec<EntrySpans>,
    /// Whether each branch is the file's own (not a sub-graph's, already renamed).
    own_branch: Vec<bool>,
    parameter_spans: Vec<EntrySpans>,
    input_spans: Vec<EntrySpans>,
    problems: Vec<Diagnostic>,
    uses: HashMap<String, Use>,
}

impl Flat {
    /// Adds the branches, parameters and inputs of `part` used as `name` (at `entry`),
    /// renamed, its terminals joined where the use joins them.
    fn instantiate(
        &mut self,
        source: &SourceFile,
        (name, entry): (&str, &EntrySpans),
        (file_name, part): (String, &RawLinearGraph),
        (given, joined): (&Given<'_>, &[(String, String)]),
    ) -> Use {
        let qualified = |n: &str| format!("{name}.{n}");
        let at_use = |key: String| EntrySpans {
            key,
            ..entry.clone()
        };
        let values = given.values(name, &part.parameters, &part.inputs);
        for (parameter, spec) in values.parameters {
            self.parameter_spans.push(at_use(parameter.clone()));
            self.raw.parameters.push((parameter, spec));
        }
        for (input, spec) in values.inputs {
            self.input_spans.push(at_use(input.clone()));
            self.raw.inputs.push((input, spec));
        }
        let renames = values.renames;
        let part_branches: Vec<&str> = part.branches.iter().map(|(n, _)| n.as_str()).collect();
        let rename = |symbol: &str| -> Option<String> {
            if let Some(new) = renames.get(symbol) {
                return Some(new.clone());
            }
            let (_, element) = state_element(symbol)?;
            part_branches
                .contains(&element.as_str())
                .then(|| qualified(symbol))
        };
        // The terminals this use joins to its graph's nodes.
        let mut joined_nodes: HashMap<&str, &str> = HashMap::new();
        let mut connected = Vec::new();
        for (terminal, parent_node) in joined {
            match part.terminals.iter().find(|(t, _)| t == terminal) {
                Some((_, spec)) => {
                    joined_nodes.insert(spec.node.as_str(), parent_node.as_str());
                    connected.push(terminal.clone());
                }
                None => {
                    let names = crate::model::compose::names_of(&part.terminals);
                    self.problems.push(
                        Diagnostic::new(
                            DiagnosticKind::Submodel,
                            format!(
                                "sub-graph '{name}': '{terminal}' is not a terminal of '{file_name}'"
                            ),
                        )
                        .at(source, key_span(source, entry, "terminals", terminal))
                        .element(name.to_string())
                        .note(format!("its terminals: {}", list(&names))),
                    );
                }
            }
        }
        let ground = self.raw.ground.clone();
        let node = |n: &str| {
            if n == part.ground {
                ground.clone()
            } else if let Some(parent_node) = joined_nodes.get(n) {
                (*parent_node).to_string()
            } else {
                qualified(n)
            }
        };
        for (branch_name, branch) in &part.branches {
            let mut branch = branch.clone();
            for expression in branch.expressions_mut() {
                *expression = rename_symbols(expression, rename);
            }
            for n in branch.nodes_mut() {
                *n = node(n);
            }
            self.branches.push((qualified(branch_name), branch));
            self.branch_spans.push(at_use(qualified(branch_name)));
            self.own_branch.push(false);
        }
        let terminals = part
            .terminals
            .iter()
            .map(|(t, spec)| (t.clone(), node(&spec.node)))
            .collect();
        Use {
            file: file_name,
            model: part.name.clone(),
            terminals,
            connected,
            entry: entry.clone(),
        }
    }

    /// The file's own branches name a use's terminals as nodes (`"wall.outside"`), and so
    /// may its own terminals.
    fn join_terminals(&mut self, source: &SourceFile) {
        let own = self.branches.iter().zip(&self.branch_spans).enumerate();
        let mut renamed: Vec<(usize, usize, String)> = Vec::new();
        for (b, ((name, branch), entry)) in own.filter(|(b, _)| self.own_branch[*b]) {
            let mut branch = branch.clone();
            let fields = node_fields(&branch);
            for (k, n) in branch.nodes_mut().into_iter().enumerate() {
                let Some((use_name, terminal)) = n.split_once('.') else {
                    continue;
                };
                let Some(used) = self.uses.get_mut(use_name) else {
                    continue;
                };
                match used.terminals.iter().find(|(t, _)| t == terminal) {
                    Some((t, node)) => {
                        used.connected.push(t.clone());
                        renamed.push((b, k, node.clone()));
                    }
                    None => {
                        let names: Vec<&str> =
                            used.terminals.iter().map(|(t, _)| t.as_str()).collect();
                        let at = key_span(source, entry, fields[k], n);
                        let mut d = Diagnostic::new(
                            DiagnosticKind::Submodel,
                            format!(
                                "branch '{name}': '{terminal}' is not a terminal of sub-graph \
                                 '{use_name}' ('{}')",
                                used.file
                            ),
                        )
                        .at(source, at)
                        .element(name.clone());
                        d = match suggest(terminal, names.iter().copied()) {
                            Some(near) => d.note(format!("did you mean '{use_name}.{near}'?")),
                            None => d.note(format!("its terminals: {}", list(&names))),
                        };
                        self.problems.push(d);
                    }
                }
            }
        }
        for (b, k, node) in renamed {
            if let Some(n) = self.branches[b].1.nodes_mut().into_iter().nth(k) {
                *n = node;
            }
        }
        for (_, terminal) in &mut self.raw.terminals {
            if let Some((use_name, t)) = terminal.node.clone().split_once('.')
                && let Some(used) = self.uses.get_mut(use_name)
                && let Some((_, node)) = used.terminals.iter().find(|(u, _)| u == t)
            {
                terminal.node = node.clone();
                used.connected.push(t.to_string());
            }
        }
    }

    /// Every terminal of every use is joined.
    fn check_connected(&mut self, source: &SourceFile) {
        let mut names: Vec<&String> = self.uses.keys().collect();
        names.sort();
        for name in names {
            let used = &self.uses[name];
            for (terminal, _) in &used.terminals {
                if !used.connected.contains(terminal) {
                    self.problems.push(
                        Diagnostic::new(
                            DiagnosticKind::Submodel,
                            format!("sub-graph '{name}': terminal '{terminal}' is not connected"),
                        )
                        .at(source, used.entry.key_span)
                        .element(name.clone())
                        .note(format!(
                            "join it to a node, terminals: {{\"{terminal}\": \"NODE\"}}, or end a \
                             branch at \"{name}.{terminal}\""
                        )),
                    );
                }
            }
        }
    }

    /// The uses, in name order, as the model records them.
    fn part_specs(&self) -> Vec<PartSpec> {
        let mut names: Vec<&String> = self.uses.keys().collect();
        names.sort();
        names
            .into_iter()
            .map(|name| PartSpec {
                name: name.clone(),
                file: self.uses[name].file.clone(),
                model: self.uses[name].model.clone(),
                ports: self.uses[name].terminals.clone(),
                origins: Vec::new(),
            })
            .collect()
    }

    fn finish(mut self, map: SourceMap) -> (RawLinearGraph, SourceMap) {
        self.raw.branches = self.branches;
        let map = SourceMap {
            parameters: self.parameter_spans,
            inputs: self.input_spans,
            branches: self.branch_spans,
            ..map
        };
        (self.raw, map)
    }
}

/// The field each of a branch's nodes (in [`RawBranch::nodes_mut`]'s order) is written in.
fn node_fields(branch: &RawBranch) -> &'static [&'static str] {
    match branch {
        RawBranch::Transformer { .. } | RawBranch::Gyrator { .. } => {
            &["primary", "primary", "secondary", "secondary"]
        }
        _ => &["from", "to"],
    }
}
