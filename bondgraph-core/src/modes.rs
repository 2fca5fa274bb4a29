//! Modes of a switching model: which mode each switching element is in.
//!
//! A friction contact is `stuck`, `slip+` or `slip-`; a tension-only element is `taut` or
//! `slack`. A mode of the whole model picks one for each, and in a mode every element has a
//! plain law ([`crate::laws::for_mode`]), so each mode is derived exactly like a model without
//! switching: causality, merging (a stuck contact makes storage dependent), equations. The
//! guards of a mode ([`crate::guards`]) say when it is left and for which mode.
//!
//! A mode itself, written as a specification (`fr_1=slip+,fr_2=stuck,string=taut`), is a
//! [`Mode`] ([`crate::mode`]).

use std::collections::{HashMap, VecDeque};
use std::sync::Arc;

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::equations::{self, Options, StateEquations};
use crate::model::AtElement;
use serde::Serialize;

use crate::equations::nonlinear::{self, NonlinearEquations};
use crate::guards::{self, Crossing, Guard};
use crate::laws;
pub use crate::mode::Mode;
use crate::model::{ElementId, ElementMode, Model};
use crate::symbolic::expr::Sym;

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
/// velocity sources) cannot be entered. Coefficients are checked at the model's values only
/// in a mode the model has there ([`Mode::exists_at_values`]).
pub fn derive(model: &Model, mode: &Mode, options: &Options) -> Result<ModeEquations> {
    let laws = laws::for_mode(model, mode);
    let equations = equations::derive_checking(model, &laws, options, mode.exists_at_values(model))
        .map_err(|d| crate::model::linear_graph::reword(model, d))?;
    let guards = guards::derive(model, mode, &equations);
    Ok(ModeEquations {
        mode: mode.clone(),
        equations,
        guards,
    })
}

/// The equations and guards of one mode of a nonlinear model.
#[derive(Clone, Debug)]
pub struct NonlinearModeEquations {
    /// The mode.
    pub mode: Mode,
    /// Its state equations `dx/dt = f(x, u)`.
    pub equations: NonlinearEquations,
    /// When it is left, and for which mode: expressions of its states.
    pub guards: Vec<Guard<Sym>>,
}

/// Derives the equations and guards of `mode` of a nonlinear model.
///
/// # Errors
/// As [`nonlinear::derive`].
pub fn derive_nonlinear(
    model: &Model,
    mode: &Mode,
    options: &Options,
) -> Result<NonlinearModeEquations> {
    let laws = laws::for_mode(model, mode);
    let equations =
        nonlinear::derive_checking(model, &laws, options, mode.exists_at_values(model))?;
    let guards = guards::derive_nonlinear(model, mode, &equations);
    Ok(NonlinearModeEquations {
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
    nonlinear: HashMap<Mode, std::result::Result<Arc<NonlinearModeEquations>, Diagnostics>>,
}

impl<'m> ModeCache<'m> {
    /// An empty cache for `model`.
    pub fn new(model: &'m Model, options: Options) -> Self {
        Self {
            model,
            options,
            derived: HashMap::new(),
            nonlinear: HashMap::new(),
        }
    }

    /// The equations of `mode` of a nonlinear model, derived on first use.
    ///
    /// # Errors
    /// As [`derive_nonlinear`], remembered for later calls.
    pub fn get_nonlinear(&mut self, mode: &Mode) -> Result<Arc<NonlinearModeEquations>> {
        self.nonlinear
            .entry(mode.clone())
            .or_insert_with(|| derive_nonlinear(self.model, mode, &self.options).map(Arc::new))
            .clone()
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
        self.derived.len() + self.nonlinear.len()
    }

    /// Whether nothing has been derived yet.
    pub fn is_empty(&self) -> bool {
        self.derived.is_empty() && self.nonlinear.is_empty()
    }
}

/// The modes reachable from the initial mode through guards (of a nonlinear model with
/// `M` = [`NonlinearModeEquations`]).
#[derive(Clone, Debug)]
pub struct Reachable<M = ModeEquations> {
    /// The initial mode.
    pub initial: Mode,
    /// Every mode that can be entered, in breadth-first order from the initial mode.
    pub modes: Vec<Arc<M>>,
    /// Modes some guard leads to that cannot be entered, with why.
    pub impossible: Vec<(Mode, Diagnostics)>,
}

/// A derived mode as the mode listing shows it.
pub trait ListedMode {
    /// The mode.
    fn mode(&self) -> &Mode;
    /// Its states' names.
    fn state_names(&self) -> Vec<String>;
    /// Its guards, as the listing shows them.
    fn guard_rows(&self, model: &Model) -> Vec<GuardRow>;
}

/// One guard of a listed mode.
#[derive(Clone, Debug)]
pub struct GuardRow {
    /// The switching element.
    pub element: ElementId,
    /// Its mode after the guard fires.
    pub leaves_to: ElementMode,
    /// The condition as text.
    pub condition: String,
    /// What is watched, in words.
    pub watched: String,
    /// The watched quantity as text.
    pub quantity: String,
    /// `>=` or `<=`.
    pub comparison: String,
    /// The threshold as text.
    pub threshold: String,
    /// Whether it switches only if the element can then hold.
    pub requires_hold: bool,
}

fn comparison(crossing: Crossing) -> String {
    match crossing {
        Crossing::Rises => ">=",
        Crossing::Falls => "<=",
    }
    .to_string()
}

impl ListedMode for ModeEquations {
    fn mode(&self) -> &Mode {
        &self.mode
    }
    fn state_names(&self) -> Vec<String> {
        self.equations
            .states
            .iter()
            .map(|s| s.name.clone())
            .collect()
    }
    fn guard_rows(&self, model: &Model) -> Vec<GuardRow> {
        let eq = &self.equations;
        self.guards
            .iter()
            .filter(|g| g.applies(model, &model.values))
            .map(|g| GuardRow {
                element: g.element,
                leaves_to: g.leaves_to,
                condition: g.condition_text(eq),
                watched: g.watched.description().to_string(),
                quantity: eq.form_text(&g.quantity),
                comparison: comparison(g.crossing),
                threshold: eq.form_text(&g.threshold),
                requires_hold: g.requires_hold,
            })
            .collect()
    }
}

impl ListedMode for NonlinearModeEquations {
    fn mode(&self) -> &Mode {
        &self.mode
    }
    fn state_names(&self) -> Vec<String> {
        self.equations
            .states
            .iter()
            .map(|s| s.name.clone())
            .collect()
    }
    fn guard_rows(&self, model: &Model) -> Vec<GuardRow> {
        let eq = &self.equations;
        self.guards
            .iter()
            .filter(|g| g.applies(model, &model.values))
            .map(|g| GuardRow {
                element: g.element,
                leaves_to: g.leaves_to,
                condition: g.condition_text(eq),
                watched: g.watched.description().to_string(),
                quantity: eq.sym_text(&g.quantity),
                comparison: comparison(g.crossing),
                threshold: eq.sym_text(&g.threshold),
                requires_hold: g.requires_hold,
            })
            .collect()
    }
}

/// Every mode reachable from the initial mode by following guards.
///
/// # Errors
/// When the initial mode itself cannot be derived, or more than
/// [`MAX_MODES`](crate::limits::MAX_MODES) modes are reachable; for a nonlinear model
/// ([`Model::is_nonlinear`]) use [`reachable_nonlinear`].
pub fn reachable(model: &Model, options: &Options) -> Result<Reachable> {
    let mut cache = ModeCache::new(model, *options);
    explore(model, |mode| cache.get(mode), |m| targets(model, &m.guards))
}

/// Every mode of a nonlinear model reachable from its initial mode.
///
/// # Errors
/// When the initial mode itself cannot be derived, or more than
/// [`MAX_MODES`](crate::limits::MAX_MODES) modes are reachable.
pub fn reachable_nonlinear(
    model: &Model,
    options: &Options,
) -> Result<Reachable<NonlinearModeEquations>> {
    let mut cache = ModeCache::new(model, *options);
    explore(
        model,
        |mode| cache.get_nonlinear(mode),
        |m| targets(model, &m.guards),
    )
}

/// Where the `guards` that apply at the model's own values lead: which element switches to
/// which of its modes.
fn targets<Q>(model: &Model, guards: &[Guard<Q>]) -> Vec<(ElementId, ElementMode)> {
    guards
        .iter()
        .filter(|g| g.applies(model, &model.values))
        .map(|g| (g.element, g.leaves_to))
        .collect()
}

/// Breadth-first search over the modes that guards lead to, at most
/// [`MAX_MODES`](crate::limits::MAX_MODES) of them.
///
/// # Errors
/// The initial mode cannot be derived, or more modes than the limit are reachable (a
/// [`DiagnosticKind::TooLarge`] at the first switching element).
fn explore<M>(
    model: &Model,
    mut derive: impl FnMut(&Mode) -> Result<Arc<M>>,
    targets: impl Fn(&M) -> Vec<(ElementId, ElementMode)>,
) -> Result<Reachable<M>> {
    let initial = Mode::initial(model).at_values(model, &model.values);
    derive(&initial)?;
    let mut seen = vec![initial.clone()];
    let mut queue = VecDeque::from([initial.clone()]);
    let mut modes = Vec::new();
    let mut impossible = Vec::new();
    while let Some(mode) = queue.pop_front() {
        match derive(&mode) {
            Ok(derived) => {
                for (element, leaves_to) in targets(&derived) {
                    let next = mode.with(element, leaves_to);
                    if !seen.contains(&next) {
                        if seen.len() >= crate::limits::MAX_MODES {
                            return Err(too_many_modes(model));
                        }
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

/// The diagnostic for a model with more reachable modes than
/// [`MAX_MODES`](crate::limits::MAX_MODES), at its first switching element.
fn too_many_modes(model: &Model) -> Diagnostics {
    let limit = crate::limits::MAX_MODES;
    let switching: Vec<ElementId> = model
        .element_ids()
        .filter(|&id| !model.element(id).kind.modes().is_empty())
        .collect();
    let combinations = switching
        .iter()
        .map(|&id| model.element(id).kind.modes().len() as f64)
        .product::<f64>();
    let mut diagnostic = Diagnostic::new(
        DiagnosticKind::TooLarge,
        format!(
            "model '{}' has more than {limit} modes, over the limit that `check` and `modes` enumerate: its {} switching elements combine into {} modes",
            model.name,
            switching.len(),
            crate::limits::count_in_words(combinations)
        ),
    )
    .note("a friction contact has three modes and a string or flow limit two; simulate the model instead, which derives only the modes it enters");
    if let Some(&first) = switching.first() {
        diagnostic = diagnostic
            .at_element(model, first)
            .element(model.element(first).name.clone());
    }
    diagnostic.into()
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

impl<M: ListedMode> Reachable<M> {
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
            let names = mode.state_names();
            out.push_str(&format!(
                "\nmode {}: {} state{} ({})\n",
                describe_spec(&mode.mode().spec(model)),
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                names.join(", ")
            ));
            for guard in mode.guard_rows(model) {
                out.push_str(&format!(
                    "  {}: {} -> {}={}\n",
                    model.element(guard.element).name,
                    guard.condition,
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
                    let states = mode.state_names();
                    ModeJson {
                        spec: mode.mode().spec(model),
                        state_count: states.len(),
                        states,
                        guards: mode
                            .guard_rows(model)
                            .into_iter()
                            .map(|g| GuardJson {
                                element: model.element(g.element).name.clone(),
                                expression: g.condition,
                                leaves_to: mode.mode().with(g.element, g.leaves_to).spec(model),
                                element_mode: g.leaves_to.name().to_string(),
                                watched: g.watched,
                                quantity: g.quantity,
                                comparison: g.comparison,
                                threshold: g.threshold,
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

    const BELT: &str = r#"Model(name: "belt",
        parameters: {"m": (value: 1.0), "k": (value: 10.0), "F_S": (value: 2.0), "F_C": (value: 1.5)},
        inputs: {"v_belt": ()},
        elements: {"belt": Sf(flow: "v_belt"), "contact": Zero,
                   "friction": Friction(breakaway: "F_S", coulomb: "F_C", initial: "slip+"),
                   "v": One, "block": I(inertance: "m"), "spring": C(stiffness: "k")},
        bonds: [("belt", "contact"), ("contact", "friction"), ("contact", "v"),
                ("v", "block"), ("v", "spring")])"#;

    fn error(text: &str) -> String {
        let model = crate::testing::model(BELT);
        let error = Mode::parse(&model, text).unwrap_err();
        assert_eq!(error.first().kind, DiagnosticKind::BadMode);
        error.first().message.clone()
    }

    #[test]
    fn initial_mode_comes_from_the_file_and_parsing_overrides_it() {
        let model = crate::testing::model(BELT);
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
        let model = crate::testing::model(BELT);
        let mut cache = ModeCache::new(&model, Options::default());
        let mode = Mode::parse(&model, "friction=stuck").unwrap();
        let first = cache.get(&mode).unwrap();
        let second = cache.get(&mode).unwrap();
        assert!(Arc::ptr_eq(&first, &second));
        assert_eq!(cache.len(), 1);
    }
}
