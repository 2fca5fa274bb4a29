//! A mode of a switching model: which mode each switching element is in.
//!
//! A friction contact is `stuck`, `slip+` or `slip-`; a tension-only element is `taut` or
//! `slack`. A mode of the whole model picks one for each; it is written as a specification,
//! `fr_1=slip+,fr_2=stuck,string=taut`, whose elements not named keep their initial mode.
//! What each mode derives, and its guards, are [`crate::modes`]'.
//!
//! # Example
//! ```
//! use bondgraph_core::{model, modes::Mode};
//! let model = bondgraph_ron::model::load_str("belt.ron", r#"Model(name: "belt",
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

use crate::diagnostics::{Diagnostic, DiagnosticKind, Diagnostics, Result};
use crate::model::{ElementId, ElementKind, ElementMode, Model};

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

    /// This mode as it is with the parameter `values` (indexed like [`Model::values`]): a
    /// friction contact said to creep whose Stribeck velocity is zero there slips instead
    /// ([`crate::model::Friction::mode_at`]).
    pub fn at_values(&self, model: &Model, values: &[f64]) -> Self {
        Self(
            self.0
                .iter()
                .map(|&(e, m)| match &model.element(e).kind {
                    ElementKind::Friction(friction) => (e, friction.mode_at(m, values)),
                    _ => (e, m),
                })
                .collect(),
        )
    }

    /// Whether the model has this mode at its own values: not when a contact creeps whose
    /// Stribeck velocity is zero there. Such a mode is derived all the same, without
    /// refusing the coefficients that its zero Stribeck velocity makes infinite: a fit sets
    /// other values before it binds its numbers, and the simulator never binds them at zero
    /// ([`Mode::at_values`]).
    pub fn exists_at_values(&self, model: &Model) -> bool {
        self.at_values(model, &model.values) == *self
    }

    /// The switching elements and their modes, in element order.
    pub fn assignments(&self) -> &[(ElementId, ElementMode)] {
        &self.0
    }

    /// Whether the model has no switching elements.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The full specification, `fr_1=stuck,fr_2=slip+` (empty without switching elements).
    pub fn spec(&self, model: &Model) -> String {
        self.0
            .iter()
            .map(|(e, m)| format!("{}={}", model.element(*e).name, m.name()))
            .collect::<Vec<_>>()
            .join(",")
    }
}
