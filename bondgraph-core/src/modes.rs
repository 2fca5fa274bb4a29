//! Modes of a switching model: which mode each switching element is in.
//!
//! A friction contact is `stuck`, `slip+` or `slip-`; a tension-only element is `taut` or
//! `slack`. A mode of the whole model picks one for each, and in a mode every element has a
//! plain law ([`crate::laws::for_mode`]), so each mode is derived exactly like a model without
//! switching: causality, merging (a stuck contact makes storage dependent), equations. The
//! guards of a mode ([`crate::guards`]) say when it is left and for which mode.
//!
//! Modes are written as specifications, `fr_ge=slip+,fr_ct=stuck,string=taut`; elements not
//! named keep their initial mode.
//!
//! # Example
//! ```
//! use bondgraph_core::{model, modes::Mode};
//! let model = model::load_str("belt.ron", r#"Model(name: "belt",
//!     parameters: {"m": (value: 1.0), "k": (value: 10.0), "F_S": (value: 2.0), "F_C": (value: 1.5)},
//!     inputs: {"v_belt": ()},
//!     elements: {"belt": Sf(flow: "v_belt"), "contact": Zero,
//!                "friction": Friction(breakaway: "F_S", coulomb: "F_C"),
//!                "v": One, "block": I(inertance: "m"), "spring": C(stiffness: "k")},
//!     bonds: [("belt", "contact"), ("contact", "friction"), ("contact", "v"),
//!             ("v", "block"), ("v", "spring")])"#).unwrap();
//! let mode = Mode::parse(&model, "friction=slip-").unwrap();
//! assert_eq!(mode.spec(&model), "friction=slip-");
//! assert_eq!(Mode::initial(&model).spec(&model), "friction=stuck");
//! ```

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::{self, Options, StateEquations};
use serde::Serialize;

use crate::guards::{self, Crossing, Guard};
use crate::laws;
use crate::model::{ElementId, ElementMode, Model};

/// The mode of every switching element of a model, in element order.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Mode(Vec<(ElementId, ElementMode)>);

impl Mode {
    /// The mode every switching element starts in.
    pub fn initial(model: &Model) -> Self {
        Self(
            model
                .element_ids()
                .filter_map(|id| model.element(id).kind.initial_mode().map(|m| (id, m)))
                .collect(),
        )
    }

    /// Parses `name=mode,...`; elements not named keep their initial mode.
    ///
    /// # Errors
    /// [`DiagnosticKind::BadMode`] naming an unknown element, an element that does not
    /// switch, a mode the element does not have, or an element named twice.
    pub fn parse(model: &Model, text: &str) -> Result<Self> {
        let mut mode = Self::initial(model);
        let mut named: Vec<ElementId> = Vec::new();
        let bad =
            |message: String| Diagnostics::from(Diagnostic::new(DiagnosticKind::BadMode, message));
        for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let Some((name, value)) = part.split_once('=') else {
                return Err(bad(format!(
                    "mode '{part}' must be written ELEMENT=MODE, e.g. fr=stuck"
                )));
            };
            let (name, value) = (name.trim(), value.trim());
            let Some(element) = model.element_named(name) else {
                return Err(bad(format!(
                    "mode '{part}': the model has no element '{name}'"
                )));
            };
            let kind = &model.element(element).kind;
            if kind.modes().is_empty() {
                let what = kind.description();
                let article = if what.starts_with(['a', 'e', 'i', 'o', 'u']) {
                    "an"
                } else {
                    "a"
                };
                return Err(bad(format!(
                    "mode '{part}': '{name}' is {article} {what} and has no modes"
                )));
            }
            let allowed = kind.modes();
            let Some(element_mode) = ElementMode::from_name(value).filter(|m| allowed.contains(m))
            else {
                let names: Vec<&str> = allowed.iter().map(|m| m.name()).collect();
                return Err(bad(format!(
                    "mode '{part}': '{name}' has modes {}, not '{value}'",
                    names.join(", ")
                )));
            };
            if named.contains(&element) {
                return Err(bad(format!("mode '{text}' names '{name}' twice")));
            }
            named.push(element);
            mode = mode.with(element, element_mode);
        }
        Ok(mode)
    }

    /// The mode of `element`, if it switches.
    pub fn of(&self, element: ElementId) -> Option<ElementMode> {
        self.0.iter().find(|(e, _)| *e == element).map(|(_, m)| *m)
    }

    /// This mode with `element` in `mode` instead.
    pub fn with(&self, element: ElementId, mode: ElementMode) -> Self {
        Self(
            self.0
                .iter()
                .map(|&(e, m)| if e == element { (e, mode) } else { (e, m) })
                .collect(),
        )
    }

    /// The switching elements and their modes, in element order.
    pub fn assignments(&self) -> &[(ElementId, ElementMode)] {
        &self.0
    }

    /// Whether the model has no switching elements.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The full specification, `fr_ge=stuck,fr_ct=slip+` (empty without switching elements).
    pub fn spec(&self, model: &Model) -> String {
        self.0
            .iter()
            .map(|(e, m)| format!("{}={}", model.element(*e).name, m.name()))
            .collect::<Vec<_>>()
            .join(",")
    }
}

/// The equations and guards of one mode.
#[derive(Clone, Debug)]
pub struct ModeEquations {
    /// The mode.
    pub mode: Mode,
    /// Its state equations.
    pub equations: StateEquations,
    /// When it is left, and for which mode.
    pub guards: Vec<Guard>,
}

/// Derives the equations and guards of `mode`.
///
/// # Errors
/// As [`equations::derive`]; a mode whose causality conflicts (a stuck contact between two
/// velocity sources) cannot be entered.
pub fn derive(model: &Model, mode: &Mode, options: &Options) -> Result<ModeEquations> {
    let laws = laws::for_mode(model, mode);
    let equations = equations::derive(model, &laws, options)
        .map_err(|d| crate::model::linear_graph::reword(model, d))?;
    let guards = guards::derive(model, mode, &equations);
    Ok(ModeEquations {
        mode: mode.clone(),
        equations,
        guards,
    })
}

/// Modes derived on demand and kept: switching models visit a few modes many times.
#[derive(Debug)]
pub struct ModeCache<'m> {
    model: &'m Model,
    options: Options,
    derived: HashMap<Mode, std::result::Result<Arc<ModeEquations>, Diagnostics>>,
}

impl<'m> ModeCache<'m> {
    /// An empty cache for `model`.
    pub fn new(model: &'m Model, options: Options) -> Self {
        Self {
            model,
            options,
            derived: HashMap::new(),
        }
    }

    /// The equations of `mode`, derived on first use.
    ///
    /// # Errors
    /// As [`derive()`], remembered for later calls.
    pub fn get(&mut self, mode: &Mode) -> Result<Arc<ModeEquations>> {
        self.derived
            .entry(mode.clone())
            .or_insert_with(|| derive(self.model, mode, &self.options).map(Arc::new))
            .clone()
    }

    /// How many modes have been derived (successfully or not).
    pub fn len(&self) -> usize {
        self.derived.len()
    }

    /// Whether nothing has been derived yet.
    pub fn is_empty(&self) -> bool {
        self.derived.is_empty()
    }
}

/// The modes reachable from the initial mode through guards.
#[derive(Clone, Debug)]
pub struct Reachable {
    /// The initial mode.
    pub initial: Mode,
    /// Every mode that can be entered, in breadth-first order from the initial mode.
    pub modes: Vec<Arc<ModeEquations>>,
    /// Modes some guard leads to that cannot be entered, with why.
    pub impossible: Vec<(Mode, Diagnostics)>,
}

/// Every mode reachable from the initial mode by following guards.
///
/// # Errors
/// When the initial mode itself cannot be derived.
pub fn reachable(model: &Model, options: &Options) -> Result<Reachable> {
    let initial = Mode::initial(model);
    let mut cache = ModeCache::new(model, *options);
    cache.get(&initial)?;
    let mut seen = vec![initial.clone()];
    let mut queue = VecDeque::from([initial.clone()]);
    let mut modes = Vec::new();
    let mut impossible = Vec::new();
    while let Some(mode) = queue.pop_front() {
        match cache.get(&mode) {
            Ok(derived) => {
                for guard in &derived.guards {
                    let next = mode.with(guard.element, guard.leaves_to);
                    if !seen.contains(&next) {
                        seen.push(next.clone());
                        queue.push_back(next);
                    }
                }
                modes.push(derived);
            }
            Err(diagnostics) => impossible.push((mode, diagnostics)),
        }
    }
    Ok(Reachable {
        initial,
        modes,
        impossible,
    })
}

/// The JSON document of `bondgraph modes`.
#[derive(Clone, Debug, Serialize)]
pub struct ModesJson {
    /// The model's name.
    pub model: String,
    /// The initial mode's specification.
    pub initial: String,
    /// Every mode that can be entered.
    pub modes: Vec<ModeJson>,
    /// Modes a guard leads to that cannot be entered, with the reason.
    pub impossible: Vec<ImpossibleJson>,
}

/// One mode in the JSON document.
#[derive(Clone, Debug, Serialize)]
pub struct ModeJson {
    /// The mode's specification.
    pub spec: String,
    /// Its states' names.
    pub states: Vec<String>,
    /// How many states it has.
    pub state_count: usize,
    /// The guards that leave it.
    pub guards: Vec<GuardJson>,
}

/// One guard in the JSON document.
#[derive(Clone, Debug, Serialize)]
pub struct GuardJson {
    /// The switching element.
    pub element: String,
    /// The condition, as text: `holding force <expr> >= F_S`.
    pub expression: String,
    /// The full specification of the mode it leads to.
    pub leaves_to: String,
    /// The element's mode after it fires.
    pub element_mode: String,
    /// `holding force`, `relative velocity`, `tension` or `extension`.
    pub watched: String,
    /// The watched quantity.
    pub quantity: String,
    /// `>=` or `<=`.
    pub comparison: String,
    /// The threshold.
    pub threshold: String,
    /// Whether the switch happens only if the element can then hold (static friction
    /// within its breakaway force, a flow limit with a positive restraining effort).
    pub requires_hold: bool,
}

/// An unenterable mode in the JSON document.
#[derive(Clone, Debug, Serialize)]
pub struct ImpossibleJson {
    /// The mode's specification.
    pub spec: String,
    /// Why it cannot be entered.
    pub reason: String,
}

impl Reachable {
    /// The reachable modes and their guards as text.
    pub fn to_text(&self, model: &Model) -> String {
        let switching = self.initial.assignments().len();
        let mut out = format!(
            "model '{}': {} switching element{}, {} mode{} reachable from {}\n",
            model.name,
            switching,
            if switching == 1 { "" } else { "s" },
            self.modes.len(),
            if self.modes.len() == 1 { "" } else { "s" },
            describe_spec(&self.initial.spec(model))
        );
        for mode in &self.modes {
            let eq = &mode.equations;
            let names: Vec<&str> = eq.states.iter().map(|s| s.name.as_str()).collect();
            out.push_str(&format!(
                "\nmode {}: {} state{} ({})\n",
                describe_spec(&mode.mode.spec(model)),
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                names.join(", ")
            ));
            for guard in &mode.guards {
                out.push_str(&format!(
                    "  {}: {} -> {}={}\n",
                    model.element(guard.element).name,
                    guard.condition_text(eq),
                    model.element(guard.element).name,
                    guard.leaves_to.name()
                ));
            }
        }
        for (mode, why) in &self.impossible {
            out.push_str(&format!(
                "\nmode {} cannot be entered: {}\n",
                describe_spec(&mode.spec(model)),
                why.first().message
            ));
        }
        out
    }

    /// The JSON document of `bondgraph modes`.
    pub fn to_json(&self, model: &Model) -> ModesJson {
        ModesJson {
            model: model.name.clone(),
            initial: self.initial.spec(model),
            modes: self
                .modes
                .iter()
                .map(|mode| {
                    let eq = &mode.equations;
                    ModeJson {
                        spec: mode.mode.spec(model),
                        states: eq.states.iter().map(|s| s.name.clone()).collect(),
                        state_count: eq.states.len(),
                        guards: mode
                            .guards
                            .iter()
                            .map(|g| GuardJson {
                                element: model.element(g.element).name.clone(),
                                expression: g.condition_text(eq),
                                leaves_to: mode.mode.with(g.element, g.leaves_to).spec(model),
                                element_mode: g.leaves_to.name().to_string(),
                                watched: g.watched.description().to_string(),
                                quantity: eq.form_text(&g.quantity),
                                comparison: match g.crossing {
                                    Crossing::Rises => ">=",
                                    Crossing::Falls => "<=",
                                }
                                .to_string(),
                                threshold: eq.form_text(&g.threshold),
                                requires_hold: g.requires_hold,
                            })
                            .collect(),
                    }
                })
                .collect(),
            impossible: self
                .impossible
                .iter()
                .map(|(mode, why)| ImpossibleJson {
                    spec: mode.spec(model),
                    reason: why.first().message.clone(),
                })
                .collect(),
        }
    }
}

/// A specification for messages; a model without switching elements has one, unnamed, mode.
fn describe_spec(spec: &str) -> &str {
    if spec.is_empty() {
        "(its only mode)"
    } else {
        spec
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model;

    const BELT: &str = r#"Model(name: "belt",
        parameters: {"m": (value: 1.0), "k": (value: 10.0), "F_S": (value: 2.0), "F_C": (value: 1.5)},
        inputs: {"v_belt": ()},
        elements: {"belt": Sf(flow: "v_belt"), "contact": Zero,
                   "friction": Friction(breakaway: "F_S", coulomb: "F_C", initial: "slip+"),
                   "v": One, "block": I(inertance: "m"), "spring": C(stiffness: "k")},
        bonds: [("belt", "contact"), ("contact", "friction"), ("contact", "v"),
                ("v", "block"), ("v", "spring")])"#;

    fn error(text: &str) -> String {
        let model = model::load_str("belt.ron", BELT).unwrap();
        let error = Mode::parse(&model, text).unwrap_err();
        assert_eq!(error.first().kind, DiagnosticKind::BadMode);
        error.first().message.clone()
    }

    #[test]
    fn initial_mode_comes_from_the_file_and_parsing_overrides_it() {
        let model = model::load_str("belt.ron", BELT).unwrap();
        assert_eq!(Mode::initial(&model).spec(&model), "friction=slip+");
        assert_eq!(Mode::parse(&model, "").unwrap(), Mode::initial(&model));
        let stuck = Mode::parse(&model, " friction = stuck ").unwrap();
        let friction = model.element_named("friction").unwrap();
        assert_eq!(stuck.of(friction), Some(ElementMode::Stuck));
    }

    #[test]
    fn bad_specifications_name_what_is_wrong() {
        assert_eq!(
            error("friction"),
            "mode 'friction' must be written ELEMENT=MODE, e.g. fr=stuck"
        );
        assert_eq!(
            error("frction=stuck"),
            "mode 'frction=stuck': the model has no element 'frction'"
        );
        assert_eq!(
            error("block=stuck"),
            "mode 'block=stuck': 'block' is an inertia and has no modes"
        );
        assert_eq!(
            error("spring=slack"),
            "mode 'spring=slack': 'spring' is a compliance and has no modes"
        );
        assert_eq!(
            error("friction=taut"),
            "mode 'friction=taut': 'friction' has modes stuck, slip+, slip-, not 'taut'"
        );
        assert_eq!(
            error("friction=stuck,friction=slip-"),
            "mode 'friction=stuck,friction=slip-' names 'friction' twice"
        );
    }

    #[test]
    fn the_cache_derives_each_mode_once() {
        let model = model::load_str("belt.ron", BELT).unwrap();
        let mut cache = ModeCache::new(&model, Options::default());
        let mode = Mode::parse(&model, "friction=stuck").unwrap();
        let first = cache.get(&mode).unwrap();
        let second = cache.get(&mode).unwrap();
        assert!(Arc::ptr_eq(&first, &second));
        assert_eq!(cache.len(), 1);
    }
}
