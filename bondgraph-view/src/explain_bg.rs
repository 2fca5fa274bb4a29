//! `bondgraph explain` on a bond graph: the causality assignment (SCAP) as numbered steps in
//! plain words, as a teacher would do it on the board, in text or Markdown.
//!
//! The steps are the [`CausalityTrace`] of the very run that gave the causal strokes
//! (`bondgraph_core::causality::assign_traced`); this module only words them. What the
//! derivation then did with the result (dependent storage merged or held, algebraic loops
//! solved) comes from the derived equations' notes, so it too is what the program did.

use std::sync::Arc;

use bondgraph_core::causality::{
    self, Causality, CausalityTrace, Decision, Propagation, Rule, Step, Stroke, law_description,
};
use bondgraph_core::equations::{Note, Options, Quantity, StateVariable};
use bondgraph_core::laws::{self, Law};
use bondgraph_core::model::{BondId, ElementId, Model};
use bondgraph_core::modes::{self, Mode};
use bondgraph_core::source::SourceFile;

use crate::{Failure, print, with_source};

pub use crate::formats::ExplainFormat;

/// An explanation, and why the mode's equations cannot be derived where they cannot: the
/// causality is explained all the same, so a reader sees how far the assignment got.
pub struct Explanation {
    /// The explanation, in the format asked for.
    pub text: String,
    /// Why the mode's equations cannot be derived, if they cannot.
    pub underivable: Option<Failure>,
}

/// Prints the explanation of `model` in `mode` ([`explain`]); the command's error, after
/// it, if the mode's equations cannot be derived.
pub fn run(
    model: &Model,
    mode: &Mode,
    source: &Arc<SourceFile>,
    format: ExplainFormat,
) -> Result<(), Failure> {
    let explanation = explain(model, mode, source, format)?;
    print(&explanation.text);
    explanation.underivable.map_or(Ok(()), Err)
}

/// The explanation of `model` in `mode`: a bond graph's by [`document`], a linear graph's
/// by [`crate::explain_lg::document`].
///
/// # Errors
/// A failure when the causality cannot be assigned, or (a linear graph) when the mode's
/// equations cannot be derived.
pub fn explain(
    model: &Model,
    mode: &Mode,
    source: &Arc<SourceFile>,
    format: ExplainFormat,
) -> Result<Explanation, Failure> {
    if let Some(graph) = &model.linear_graph() {
        Ok(Explanation {
            text: crate::explain_lg::document(model, graph, mode, source, format)?,
            underivable: None,
        })
    } else {
        document(model, mode, source, format)
    }
}

/// The explanation of bond graph `model` in `mode`.
///
/// # Errors
/// A failure when the causality cannot be assigned (a causal conflict).
pub fn document(
    model: &Model,
    mode: &Mode,
    source: &Arc<SourceFile>,
    format: ExplainFormat,
) -> Result<Explanation, Failure> {
    let laws = laws::for_mode(model, mode);
    let (causal, trace) =
        causality::assign_traced(model, &laws).map_err(|d| with_source(d, source))?;
    let derived = derivation(model, mode);
    let derivation = derived.as_ref().ok();
    let explainer = Explainer {
        model,
        laws: &laws,
        causal: &causal,
        trace: &trace,
        derivation,
        markdown: format == ExplainFormat::Markdown,
    };
    let text = explainer.document(&mode.spec(model));
    Ok(Explanation {
        text,
        underivable: derived.err().map(|d| with_source(d, source)),
    })
}

/// What the derivation of the mode found: its states and its notes, and for a linear mode
/// the solved efforts and flows of the elements in algebraic loops.
struct Derivation {
    states: Vec<StateVariable>,
    notes: Vec<Note>,
    /// For each element in an algebraic loop (not junctions): its bond's effort and flow
    /// as solved, in text.
    solved: Vec<(String, String, String)>,
}

fn derivation(
    model: &Model,
    mode: &Mode,
) -> Result<Derivation, bondgraph_core::diagnostics::Diagnostics> {
    let options = Options::default();
    if model.is_nonlinear() {
        let derived = modes::derive_nonlinear(model, mode, &options)?;
        return Ok(Derivation {
            states: derived.equations.states,
            notes: derived.equations.notes,
            solved: Vec::new(),
        });
    }
    let derived = modes::derive(model, mode, &options)?;
    let equations = derived.equations;
    let mut solved = Vec::new();
    for note in &equations.notes {
        if let Note::AlgebraicLoop { elements, .. } = note {
            for name in elements {
                if let Some(element) = model.element_named(name) {
                    let bond = model.element(element).bonds[0];
                    solved.push((
                        name.clone(),
                        equations.form_text(equations.bond_effort(bond)),
                        equations.form_text(equations.bond_flow(bond)),
                    ));
                }
            }
        }
    }
    Ok(Derivation {
        states: equations.states,
        notes: equations.notes,
        solved,
    })
}

/// A heading and the decisions listed under it.
type Phase = (&'static str, fn(&Decision) -> bool);

/// A numbered step with its sub-items.
struct Item {
    number: usize,
    text: String,
    details: Vec<String>,
}

struct Explainer<'a> {
    model: &'a Model,
    laws: &'a [Law],
    causal: &'a Causality,
    trace: &'a CausalityTrace,
    derivation: Option<&'a Derivation>,
    markdown: bool,
}

impl Explainer<'_> {
    /// The whole explanation.
    fn document(&self, spec: &str) -> String {
        let model = self.model;
        let mut out = String::new();
        let mode = if spec.is_empty() {
            String::new()
        } else {
            format!(" in mode {spec}")
        };
        let title = format!(
            "bond graph {}{mode}: causality assigned step by step (SCAP)",
            self.name(model.name())
        );
        if self.markdown {
            out.push_str(&format!("# {title}\n\n"));
        } else {
            out.push_str(&format!("{title}\n\n"));
        }
        self.paragraph(
            &mut out,
            "The sequential causality assignment procedure (Karnopp, Margolis & Rosenberg): \
             every source takes its fixed causality; then each storage element in turn takes \
             its preferred integral causality (an inertia receives its effort, a compliance \
             its flow); resistors take what the junctions leave them, and whatever is still \
             free is chosen. After each decision the junctions propagate it: a 0-junction has \
             exactly one bond that brings its effort in, a 1-junction exactly one that brings \
             its flow in, a transformer passes causality through, a gyrator turns it over. \
             The causal stroke | is at the end of a bond that receives the effort.",
        );
        if !model.parts().is_empty() {
            self.heading(
                &mut out,
                "Sub-models, flattened: each element named with its use's name in front",
            );
            // Each port's domain, where the composed model's units tell it.
            let lines = crate::parts::part_lines(model, &|junction| {
                let domain = model
                    .element_named(junction)
                    .and_then(|id| model.element_domain(id))
                    .map_or(String::new(), |d| format!(" ({})", d.name));
                format!("'{junction}'{domain}")
            });
            self.block(&mut out, &lines);
        }
        self.heading(
            &mut out,
            "Bonds (power flows from -> to), numbered in file order",
        );
        let lines: Vec<String> = model
            .bond_ids()
            .map(|b| format!("{:>3}  {}", b.index() + 1, model.bond_label(b)))
            .collect();
        self.block(&mut out, &lines);

        let phases: [Phase; 4] = [
            ("Sources", |d| {
                matches!(d, Decision::Source | Decision::OneWayResistor)
            }),
            ("Storage", |d| {
                matches!(d, Decision::Integral | Decision::Derivative)
            }),
            ("Resistors forced by the steps above", |d| {
                matches!(d, Decision::ResistorForced)
            }),
            ("What nothing forced: free choices", |d| {
                matches!(
                    d,
                    Decision::ResistorChosen | Decision::BondChosen | Decision::Undone { .. }
                )
            }),
        ];
        for (heading, belongs) in phases {
            let items: Vec<Item> = self
                .trace
                .steps
                .iter()
                .enumerate()
                .filter(|(_, s)| belongs(&s.decision))
                .map(|(i, s)| self.step(i, s))
                .collect();
            if items.is_empty() {
                continue;
            }
            self.heading(&mut out, heading);
            self.items(&mut out, &items);
        }
        self.result(&mut out);
        out
    }

    // --- Words for one step ---------------------------------------------------------

    fn step(&self, index: usize, step: &Step) -> Item {
        let model = self.model;
        let e = step.element;
        let law = &self.laws[e.index()];
        let what = self.what(e);
        let bond = self.bond(step.bond);
        let stroked = self.code(&self.stroked(step.bond, step.stroke));
        let receiver = self.receiver(step.bond, step.stroke);
        let earlier = step
            .earlier
            .map(|k| format!("step {}", k + 1))
            .unwrap_or_else(|| "an earlier step".to_string());
        let text = match &step.decision {
            Decision::Source => {
                let gives = if law.gives_effort() { "effort" } else { "flow" };
                let mut text = format!(
                    "{what}{}: a source of {gives}, its causality is fixed. It sets the {gives} on {bond}, so the stroke is at the end of {}: {stroked}.",
                    source_meaning(law, &model.element(e).kind),
                    self.name(&model.element(receiver).name)
                );
                if !step.new {
                    text.push_str(&format!(" ({earlier} had already stroked it so.)"));
                }
                text
            }
            Decision::OneWayResistor => {
                let (law_text, receives, gives, causality) = if receiver == e {
                    ("flow: g(effort)", "effort", "flow", "conductance")
                } else {
                    ("effort: f(flow)", "flow", "effort", "resistance")
                };
                format!(
                    "{what} has its law as {law_text} only, so its causality is fixed: it receives the {receives} on {bond} and gives the {gives} ({causality} causality): {stroked}."
                )
            }
            Decision::Integral => {
                let state = model.storage_name(e).unwrap_or_default();
                let state = self.code(&state);
                let (receives, integrates, gives) = storage_words(model, e, law);
                if step.new {
                    format!(
                        "{what} takes its preferred integral causality: it receives the {receives} on {bond} and integrates it into its {integrates} {state}, a state; it gives its {gives} back: {stroked}."
                    )
                } else {
                    format!(
                        "{what} is already in integral causality: {earlier}{} stroked {bond} the way it prefers, {stroked}. Its {integrates} {state} is a state.",
                        self.via(step)
                    )
                }
            }
            Decision::Derivative => {
                let (receives, integrates, gives) = storage_words(model, e, law);
                let other = model.bond(step.bond).other(e);
                format!(
                    "{what} would take integral causality, receiving the {receives} on {bond}, but {earlier}{} stroked that bond the other way, {stroked}: {} imposes its {gives}. It is in derivative causality: its {integrates} follows from the rest of the graph, and is no state of its own.",
                    self.via(step),
                    self.name(&model.element(other).name)
                )
            }
            Decision::ResistorForced => {
                let words = resistor_words(receiver == e, &bond);
                format!(
                    "{what}: {earlier}{} decided its causality. {words}: {stroked}.",
                    self.via(step)
                )
            }
            Decision::ResistorChosen => {
                let words = resistor_words(receiver == e, &bond);
                format!(
                    "Nothing has forced the causality of {what}, so it is chosen ({}). {words}: {stroked}. A free choice like this is where an algebraic loop can start.",
                    if receiver == e {
                        "conductance causality, as resistance causality was undone"
                    } else {
                        "resistance causality first"
                    }
                )
            }
            Decision::BondChosen => {
                let b = model.bond(step.bond);
                format!(
                    "Nothing has forced the causality of {bond}, between {} and {}, so it is chosen: the effort goes to {}, {stroked}.",
                    self.what(b.from),
                    self.what(b.to),
                    self.name(&model.element(receiver).name)
                )
            }
            Decision::Undone { conflict } => format!(
                "Trying {stroked} for {what} led to a conflict ({conflict}); the choice is undone and the alternative tried."
            ),
        };
        let mut details = self.propagations(&step.propagated);
        if let Some(detail) = self.storage_outcome(step) {
            details.push(detail);
        }
        Item {
            number: index + 1,
            text,
            details,
        }
    }

    /// What the derivation did with a storage element in derivative causality.
    fn storage_outcome(&self, step: &Step) -> Option<String> {
        if step.decision != Decision::Derivative {
            return None;
        }
        let derivation = self.derivation?;
        let model = self.model;
        let name = &model.element(step.element).name;
        if let Some(state) = derivation.states.iter().find(|s| s.merged.contains(name)) {
            let others: Vec<String> = state
                .merged
                .iter()
                .filter(|m| *m != name)
                .map(|m| self.name(m))
                .collect();
            let also = if others.is_empty() {
                String::new()
            } else {
                format!(" (with {})", others.join(", "))
            };
            let storage = match model.element_named(&state.element) {
                Some(e) if self.laws[e.index()].gives_effort() => "compliance",
                _ => "inertance",
            };
            return Some(format!(
                "The derivation merges it{also} into {}: the state {} now has the {storage} {}.",
                self.name(&state.element),
                self.code(&state.name),
                self.code(&state.storage.text(model.symbols()))
            ));
        }
        derivation
            .notes
            .iter()
            .any(|n| matches!(n, Note::Held { element } if element == name))
            .then(|| {
                "It follows sources alone: it is held by them and has no state in this mode."
                    .to_string()
            })
    }

    /// The propagations of one step, those through one junction by one rule together.
    fn propagations(&self, propagated: &[Propagation]) -> Vec<String> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < propagated.len() {
            let first = &propagated[i];
            let mut j = i + 1;
            while j < propagated.len()
                && propagated[j].through == first.through
                && propagated[j].rule == first.rule
            {
                j += 1;
            }
            let group = &propagated[i..j];
            let bonds = list(
                group
                    .iter()
                    .map(|p| {
                        format!(
                            "bond {} {}",
                            p.bond.index() + 1,
                            self.code(&self.stroked(p.bond, p.stroke))
                        )
                    })
                    .collect(),
            );
            let what = self.what(first.through);
            let by = |from: BondId| {
                format!(
                    "bond {} (from {})",
                    from.index() + 1,
                    self.name(
                        &self
                            .model
                            .element(self.model.bond(from).other(first.through))
                            .name
                    )
                )
            };
            out.push(match first.rule {
                Rule::CommonEffort { from } => format!(
                    "{what} has its effort brought in by {}, so it gives that effort to {bonds}.",
                    by(from)
                ),
                Rule::LastSetsEffort => format!(
                    "Every other bond of {what} takes its effort, so the last, {bonds}, must bring it in."
                ),
                Rule::CommonFlow { from } => format!(
                    "{what} has its flow brought in by {}, so it gives that flow to {bonds}, each giving an effort back.",
                    by(from)
                ),
                Rule::LastSetsFlow => format!(
                    "Every other bond of {what} takes its flow, so the last, {bonds}, must bring it in."
                ),
                Rule::Transformer { from } => format!(
                    "{what} passes the causality of bond {} through to {bonds}: what comes in on one port goes out on the other.",
                    from.index() + 1
                ),
                Rule::Gyrator { from } => format!(
                    "{what} turns the causality of bond {} over on {bonds}: the effort on one port sets the flow on the other.",
                    from.index() + 1
                ),
            });
            i = j;
        }
        out
    }

    /// ` (through 1-junction 'v')`: the junction whose rule stroked the step's bond.
    fn via(&self, step: &Step) -> String {
        let Some(k) = step.earlier else {
            return String::new();
        };
        self.trace.steps[k]
            .propagated
            .iter()
            .find(|p| p.bond == step.bond)
            .map(|p| {
                format!(
                    " ({} {}, through {})",
                    self.what_kind(self.trace.steps[k].element),
                    self.name(&self.model.element(self.trace.steps[k].element).name),
                    self.what(p.through)
                )
            })
            .unwrap_or_default()
    }

    // --- The result -------------------------------------------------------------------

    fn result(&self, out: &mut String) {
        let model = self.model;
        self.heading(out, "Result: the causal strokes");
        let lines: Vec<String> = model
            .bond_ids()
            .map(|b| {
                let derivative = self
                    .causal
                    .dependent
                    .iter()
                    .any(|&e| model.element(e).bonds.contains(&b));
                format!(
                    "{:>3}  {}{}",
                    b.index() + 1,
                    self.stroked(b, self.causal.strokes[b.index()]),
                    if derivative {
                        "   derivative causality"
                    } else {
                        ""
                    }
                )
            })
            .collect();
        self.block(out, &lines);

        let decided = |e: ElementId| {
            let bond = model.element(e).bonds[0];
            self.trace
                .step_of(bond)
                .map(|k| format!(" (decided in step {})", k + 1))
                .unwrap_or_default()
        };
        let mut facts = Vec::new();
        let storage: Vec<String> = model
            .element_ids()
            .filter_map(|e| {
                self.causal.storage(e, self.laws).map(|c| {
                    format!(
                        "{} {}{}",
                        self.name(&model.element(e).name),
                        match c {
                            causality::StorageCausality::Integral => "integral",
                            causality::StorageCausality::Derivative => "derivative",
                        },
                        decided(e)
                    )
                })
            })
            .collect();
        if !storage.is_empty() {
            facts.push(format!("Storage: {}.", storage.join(", ")));
        }
        let resistors: Vec<String> = model
            .element_ids()
            .filter(|e| {
                matches!(self.laws[e.index()], Law::Resistor { .. })
                    || matches!(
                        self.laws[e.index()].nonlinear(),
                        Some(bondgraph_core::model::NonlinearLaw::Resistor(_))
                    )
            })
            .map(|e| {
                let bond = model.element(e).bonds[0];
                let conductance = self.causal.effort_receiver(model, bond) == e;
                format!(
                    "{} {} causality{}",
                    self.name(&model.element(e).name),
                    if conductance {
                        "conductance"
                    } else {
                        "resistance"
                    },
                    decided(e)
                )
            })
            .collect();
        if !resistors.is_empty() {
            facts.push(format!("Resistors: {}.", resistors.join(", ")));
        }
        match self.derivation {
            Some(derivation) => {
                let states: Vec<String> = derivation
                    .states
                    .iter()
                    .map(|s| {
                        if s.merged.is_empty() {
                            self.code(&s.name)
                        } else {
                            format!(
                                "{} ({} merged in)",
                                self.code(&s.name),
                                list(s.merged.iter().map(|m| self.name(m)).collect())
                            )
                        }
                    })
                    .collect();
                facts.push(format!(
                    "States: {}.",
                    if states.is_empty() {
                        "none".to_string()
                    } else {
                        states.join(", ")
                    }
                ));
                facts.extend(self.loops(derivation));
            }
            None => facts.push(
                "The equations of this mode cannot be derived; the error below says why."
                    .to_string(),
            ),
        }
        for fact in facts {
            self.paragraph(out, &fact);
        }
    }

    fn loops(&self, derivation: &Derivation) -> Vec<String> {
        let loops: Vec<(&Vec<String>, &Vec<String>)> = derivation
            .notes
            .iter()
            .filter_map(|n| match n {
                Note::AlgebraicLoop {
                    elements,
                    junctions,
                } => Some((elements, junctions)),
                _ => None,
            })
            .collect();
        if loops.is_empty() {
            return vec![if self.causal.arbitrary.is_empty() {
                "Algebraic loops: none; every resistor's causality followed from the sources and the storage.".to_string()
            } else {
                "Algebraic loops: none; the free choices above closed no loop.".to_string()
            }];
        }
        let mut out = Vec::new();
        for (elements, junctions) in loops {
            let names = |v: &[String]| list(v.iter().map(|n| self.name(n)).collect());
            let mut text = format!(
                "Algebraic loop through {} (at {}): their equations use one another's outputs with no storage in between, so they form a linear system, solved symbolically.",
                names(elements),
                names(junctions)
            );
            let solved: Vec<String> = derivation
                .solved
                .iter()
                .filter(|(name, _, _)| elements.contains(name))
                .map(|(name, effort, flow)| {
                    format!(
                        "{}: effort {}, flow {}",
                        self.name(name),
                        self.code(effort),
                        self.code(flow)
                    )
                })
                .collect();
            if !solved.is_empty() {
                text.push_str(&format!(" Solved: {}.", solved.join("; ")));
            }
            out.push(text);
        }
        out
    }

    // --- Names and layout -------------------------------------------------------------

    /// `'name'` in text, `` `name` `` in Markdown.
    fn name(&self, name: &str) -> String {
        if self.markdown {
            format!("`{name}`")
        } else {
            format!("'{name}'")
        }
    }

    /// Code (a bond with its stroke, an expression): as is in text, quoted in Markdown.
    fn code(&self, text: &str) -> String {
        if self.markdown {
            format!("`{text}`")
        } else {
            text.to_string()
        }
    }

    /// How the element acts in this mode, without its name: `stuck friction contact`.
    fn what_kind(&self, element: ElementId) -> &'static str {
        law_description(
            &self.laws[element.index()],
            &self.model.element(element).kind,
        )
    }

    /// `inertia 'mass'`.
    fn what(&self, element: ElementId) -> String {
        format!(
            "{} {}",
            self.what_kind(element),
            self.name(&self.model.element(element).name)
        )
    }

    /// `bond 3 (v -> mass2)`.
    fn bond(&self, bond: BondId) -> String {
        format!(
            "bond {} ({})",
            bond.index() + 1,
            self.code(&self.model.bond_label(bond))
        )
    }

    /// `v -> mass|` or `|v -> mass`.
    fn stroked(&self, bond: BondId, stroke: Stroke) -> String {
        let b = self.model.bond(bond);
        let (from, to) = (
            &self.model.element(b.from).name,
            &self.model.element(b.to).name,
        );
        match stroke {
            Stroke::AtFrom => format!("|{from} -> {to}"),
            Stroke::AtTo => format!("{from} -> {to}|"),
        }
    }

    fn receiver(&self, bond: BondId, stroke: Stroke) -> ElementId {
        let b = self.model.bond(bond);
        match stroke {
            Stroke::AtFrom => b.from,
            Stroke::AtTo => b.to,
        }
    }

    fn heading(&self, out: &mut String, text: &str) {
        if self.markdown {
            out.push_str(&format!("## {text}\n\n"));
        } else {
            out.push_str(&format!("{text}:\n"));
        }
    }

    fn paragraph(&self, out: &mut String, text: &str) {
        out.push_str(text);
        out.push_str("\n\n");
    }

    fn block(&self, out: &mut String, lines: &[String]) {
        if self.markdown {
            out.push_str("```text\n");
        }
        for line in lines {
            out.push_str(line);
            out.push('\n');
        }
        if self.markdown {
            out.push_str("```\n");
        }
        out.push('\n');
    }

    fn items(&self, out: &mut String, items: &[Item]) {
        for item in items {
            if self.markdown {
                out.push_str(&format!("{}. {}\n", item.number, item.text));
                for detail in &item.details {
                    out.push_str(&format!("   - {detail}\n"));
                }
            } else {
                out.push_str(&format!("  {}. {}\n", item.number, item.text));
                for detail in &item.details {
                    out.push_str(&format!("       - {detail}\n"));
                }
            }
        }
        out.push('\n');
    }
}

/// What a switching element's source law means in its mode, after its description.
fn source_meaning(law: &Law, kind: &bondgraph_core::model::ElementKind) -> &'static str {
    use bondgraph_core::model::ElementKind;
    match (kind, law) {
        (ElementKind::Friction(_), Law::FlowSource(_)) => {
            " (it holds its relative velocity at zero)"
        }
        (ElementKind::Friction(_), Law::EffortSource(_)) => " (it resists with its Coulomb force)",
        (ElementKind::TensionOnly(_), Law::SlackStorage) => {
            " (it carries no force, while its slack length stays a state)"
        }
        (ElementKind::FlowLimit(_), Law::FlowSource(_)) => " (it holds the flow at its limit)",
        (ElementKind::FlowLimit(_), Law::EffortSource(_)) => " (it carries no effort)",
        _ => "",
    }
}

/// What storage element `e` receives, integrates and gives back in integral causality, in
/// its domain's words where the model's units tell them (as `equations` names its states):
/// a capacitor receives the flow (current) and integrates it into its charge, giving its
/// effort (voltage) back. The bond-graph words stay, as the strokes are drawn in them.
fn storage_words(model: &Model, e: ElementId, law: &Law) -> (String, &'static str, String) {
    let domain = model.element_domain(e);
    let word = |generic: &str, named: Option<&str>| match named {
        Some(named) => format!("{generic} ({named})"),
        None => generic.to_string(),
    };
    let (effort, flow) = (
        word("effort", domain.map(|d| d.effort.1)),
        word("flow", domain.map(|d| d.flow.1)),
    );
    if law.gives_effort() {
        (
            flow,
            Quantity::Displacement.description_in(domain, false),
            effort,
        )
    } else {
        (
            effort,
            Quantity::Momentum.description_in(domain, false),
            flow,
        )
    }
}

/// A resistor's causality in words: `It receives the flow on bond 4 (...) and gives the
/// effort (resistance causality)`.
fn resistor_words(conductance: bool, bond: &str) -> String {
    if conductance {
        format!(
            "It receives the effort on {bond} and gives the flow (conductance causality: the flow from the effort)"
        )
    } else {
        format!(
            "It receives the flow on {bond} and gives the effort (resistance causality: the effort from the flow)"
        )
    }
}

/// `a`, `a and b`, `a, b and c`.
fn list(items: Vec<String>) -> String {
    match items.len() {
        0 => String::new(),
        1 => items.into_iter().next().unwrap_or_default(),
        n => format!("{} and {}", items[..n - 1].join(", "), items[n - 1]),
    }
}
