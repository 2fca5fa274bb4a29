//! Each element's kind from its fields as written: the law of every one-port and two-port
//! kind, a compliance written as a stiffness, the optional coefficients, a switching
//! element's initial mode.

use crate::diagnostics::{Diagnostic, DiagnosticKind};
use crate::model::checked::{Coefficient, ElementKind, ElementMode, FlowLimit, TensionOnly};
use crate::model::spec::ElementSpec;
use crate::symbolic::RatFunc;

use super::coefficients::reciprocal;
use super::{Scope, Sign, Validator};

impl Validator<'_> {
    pub(super) fn element_kind(
        &mut self,
        name: &str,
        raw: &ElementSpec,
        index: usize,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        Some(match raw {
            ElementSpec::Se { effort } if self.needs_law(effort, scope, false) => {
                self.nonlinear_source(name, index, "effort", effort, scope)?
            }
            ElementSpec::Sf { flow } if self.needs_law(flow, scope, false) => {
                self.nonlinear_source(name, index, "flow", flow, scope)?
            }
            ElementSpec::Se { effort } => ElementKind::EffortSource(
                self.source_value(name, index, "effort", effort, scope, true)?,
            ),
            ElementSpec::Sf { flow } => {
                ElementKind::FlowSource(self.source_value(name, index, "flow", flow, scope, true)?)
            }
            ElementSpec::I {
                inertance, flow, ..
            } => self.inertia(name, index, (inertance, flow), scope)?,
            ElementSpec::C {
                compliance,
                stiffness,
                effort,
                ..
            } => self.compliance_kind(name, index, (compliance, stiffness, effort), scope)?,
            ElementSpec::Friction {
                breakaway,
                coulomb,
                viscous,
                dead_band,
                stribeck,
                initial,
            } => {
                let levels = (breakaway, coulomb);
                let optional = [viscous, dead_band, stribeck, initial];
                self.friction(name, index, levels, optional, scope)?
            }
            ElementSpec::TensionOnly {
                compliance,
                stiffness,
                initial,
                ..
            } => self.tension_only(name, index, (compliance, stiffness, initial), scope)?,
            ElementSpec::FlowLimit { max_flow, initial } => {
                self.flow_limit(name, index, (max_flow, initial), scope)?
            }
            ElementSpec::R {
                resistance,
                effort,
                flow,
            } => {
                match (resistance, effort, flow) {
                    (Some(text), None, None) if self.needs_law(text, scope, true) => {
                        self.nonlinear_resistor(name, index, "resistance", text, scope)?
                    }
                    (Some(resistance), None, None) => ElementKind::Resistor(self.coefficient(
                        name,
                        index,
                        "resistance",
                        resistance,
                        scope,
                        Sign::NonNegative,
                    )?),
                    (None, Some(text), None) => {
                        self.nonlinear_resistor(name, index, "effort", text, scope)?
                    }
                    (None, None, Some(text)) => {
                        self.nonlinear_resistor(name, index, "flow", text, scope)?
                    }
                    (r, e, f) => {
                        let given = [r, e, f].iter().filter(|x| x.is_some()).count() > 1;
                        self.one_of(name, index, "resistance", given, "resistance: \"b\", effort: \"EXPR of flow\" or flow: \"EXPR of effort\"");
                        return None;
                    }
                }
            }
            ElementSpec::TF { ratio } if self.needs_law(ratio, scope, true) => {
                self.modulated_two_port(name, index, false, ratio, scope)?
            }
            ElementSpec::GY { ratio } if self.needs_law(ratio, scope, true) => {
                self.modulated_two_port(name, index, true, ratio, scope)?
            }
            ElementSpec::TF { ratio } => ElementKind::Transformer(self.coefficient(
                name,
                index,
                "ratio",
                ratio,
                scope,
                Sign::NonZero,
            )?),
            ElementSpec::GY { ratio } => ElementKind::Gyrator(self.coefficient(
                name,
                index,
                "ratio",
                ratio,
                scope,
                Sign::NonZero,
            )?),
            ElementSpec::Conductance { conductance } => {
                let coefficient = self.coefficient(
                    name,
                    index,
                    "conductance",
                    conductance,
                    scope,
                    // A linear graph's zero resistance (across = 0·through): well defined
                    // where the branch takes its through variable, which causality prefers.
                    Sign::NonNegative,
                )?;
                ElementKind::Resistor(reciprocal(coefficient))
            }
            ElementSpec::ReciprocalGY { ratio } if self.needs_law(ratio, scope, true) => {
                self.modulated_reciprocal_gyrator(name, index, ratio, scope)?
            }
            ElementSpec::ReciprocalGY { ratio } => {
                let coefficient =
                    self.coefficient(name, index, "ratio", ratio, scope, Sign::NonZero)?;
                ElementKind::Gyrator(reciprocal(coefficient))
            }
            ElementSpec::Submodel { .. } => {
                // Files are read, and sub-models flattened, by a reader (`bondgraph-ron`).
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::UnknownElementKind,
                        format!(
                            "element '{name}': a sub-model must be flattened into its elements \
                             before validation"
                        ),
                    )
                    .at(&self.file, self.entry_span(&self.map.elements, index))
                    .element(name)
                    .note("load the model with bondgraph_ron::model::load_source, which reads sub-model files"),
                );
                return None;
            }
            ElementSpec::Zero => ElementKind::ZeroJunction,
            ElementSpec::One => ElementKind::OneJunction,
        })
    }

    /// An inertia from its inertance, or from its flow law in its momentum.
    fn inertia(
        &mut self,
        name: &str,
        index: usize,
        (inertance, flow): (&Option<String>, &Option<String>),
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        Some(match (inertance, flow) {
            (Some(inertance), None) if self.needs_law_where(inertance, scope, true, false) => {
                self.nonlinear_storage(name, index, "inertance", inertance, scope)?
            }
            (Some(inertance), None) => ElementKind::Inertia(self.coefficient(
                name,
                index,
                "inertance",
                inertance,
                scope,
                Sign::Positive,
            )?),
            (None, Some(flow)) => self.nonlinear_storage(name, index, "flow", flow, scope)?,
            (given, _) => {
                self.one_of(
                    name,
                    index,
                    "inertance",
                    given.is_some(),
                    "inertance: \"m\" or flow: \"EXPR of p_NAME\"",
                );
                return None;
            }
        })
    }

    /// A compliance from its compliance or stiffness, or from its effort law in its
    /// displacement.
    fn compliance_kind(
        &mut self,
        name: &str,
        index: usize,
        fields: (&Option<String>, &Option<String>, &Option<String>),
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        Some(match fields {
            (compliance, stiffness, Some(effort)) => {
                if compliance.is_some() || stiffness.is_some() {
                    self.one_of(
                        name,
                        index,
                        "compliance",
                        true,
                        "stiffness: \"k\", compliance: \"1/k\" or effort: \"EXPR of q_NAME\"",
                    );
                    return None;
                }
                self.nonlinear_storage(name, index, "effort", effort, scope)?
            }
            (Some(text), None, None) if self.needs_law_where(text, scope, true, false) => {
                self.nonlinear_storage(name, index, "compliance", text, scope)?
            }
            (None, Some(text), None) if self.needs_law_where(text, scope, true, false) => {
                self.nonlinear_storage(name, index, "stiffness", text, scope)?
            }
            (compliance, stiffness, None) => ElementKind::Compliance(self.compliance(
                "compliance",
                name,
                index,
                compliance.as_deref(),
                stiffness.as_deref(),
                scope,
            )?),
        })
    }

    /// A tension-only element from its compliance or stiffness and its initial mode.
    fn tension_only(
        &mut self,
        name: &str,
        index: usize,
        (compliance, stiffness, initial): (&Option<String>, &Option<String>, &Option<String>),
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let compliance = self.compliance(
            "tension-only element",
            name,
            index,
            compliance.as_deref(),
            stiffness.as_deref(),
            scope,
        );
        let initial = self.initial_mode(
            name,
            index,
            initial.as_deref(),
            &[ElementMode::Taut, ElementMode::Slack],
        );
        Some(ElementKind::TensionOnly(TensionOnly {
            compliance: compliance?,
            initial: initial?,
        }))
    }

    /// A flow limit from its largest flow and its initial mode.
    fn flow_limit(
        &mut self,
        name: &str,
        index: usize,
        (max_flow, initial): (&String, &Option<String>),
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let max_flow = self.source_value(name, index, "max_flow", max_flow, scope, false);
        let initial = self.initial_mode(
            name,
            index,
            initial.as_deref(),
            &[ElementMode::Open, ElementMode::Limiting],
        );
        Some(ElementKind::FlowLimit(FlowLimit {
            max_flow: max_flow?,
            initial: initial?,
        }))
    }

    /// A compliance given as exactly one of `compliance` or `stiffness`.
    pub(super) fn compliance(
        &mut self,
        what: &str,
        name: &str,
        index: usize,
        compliance: Option<&str>,
        stiffness: Option<&str>,
        scope: &Scope<'_>,
    ) -> Option<Coefficient> {
        match (compliance, stiffness) {
            (Some(text), None) => {
                self.coefficient(name, index, "compliance", text, scope, Sign::Positive)
            }
            (None, Some(text)) => {
                let stiffness =
                    self.coefficient(name, index, "stiffness", text, scope, Sign::Positive)?;
                Some(Coefficient {
                    value: stiffness.value.inv().expect("stiffness checked positive"),
                    ..stiffness
                })
            }
            (compliance, _) => {
                let span = self.entry_span(&self.map.elements, index);
                let (kind, message) = if compliance.is_some() {
                    (
                        DiagnosticKind::ConflictingFields,
                        format!("{what} '{name}' gives both compliance and stiffness; give one"),
                    )
                } else {
                    (
                        DiagnosticKind::MissingField,
                        format!("{what} '{name}' needs a compliance or a stiffness"),
                    )
                };
                self.problems.push(
                    Diagnostic::new(kind, message)
                        .at(&self.file, span)
                        .element(name)
                        .note("write stiffness: \"k\" or compliance: \"1/k\""),
                );
                None
            }
        }
    }

    /// Reports an element given none, or more than one, of its alternative fields
    /// (`field` is the linear one, as missing fields are named).
    pub(super) fn one_of(
        &mut self,
        name: &str,
        index: usize,
        field: &str,
        several: bool,
        fields: &str,
    ) {
        let span = self.map.elements.get(index).map_or_else(
            || self.entry_span(&self.map.elements, index),
            |e| e.value_span,
        );
        let (kind, message) = if several {
            (
                DiagnosticKind::ConflictingFields,
                format!("element '{name}' gives more than one law; give one"),
            )
        } else {
            (
                DiagnosticKind::MissingField,
                format!("element '{name}': missing field '{field}'"),
            )
        };
        self.problems.push(
            Diagnostic::new(kind, message)
                .at(&self.file, span)
                .element(name)
                .note(format!("write {fields}")),
        );
    }

    /// A non-negative coefficient that defaults to zero when the field is absent.
    pub(super) fn optional_coefficient(
        &mut self,
        name: &str,
        index: usize,
        field: &str,
        text: &Option<String>,
        scope: &Scope<'_>,
    ) -> Option<Coefficient> {
        match text {
            Some(text) => self.coefficient(name, index, field, text, scope, Sign::NonNegative),
            None => Some(Coefficient {
                value: RatFunc::zero(),
                text: "0".to_string(),
                span: self.entry_span(&self.map.elements, index),
            }),
        }
    }

    /// The initial mode of a switching element: the first of `allowed` unless given.
    pub(super) fn initial_mode(
        &mut self,
        name: &str,
        index: usize,
        given: Option<&str>,
        allowed: &[ElementMode],
    ) -> Option<ElementMode> {
        let Some(text) = given else {
            return Some(allowed[0]);
        };
        match ElementMode::from_name(text).filter(|m| allowed.contains(m)) {
            Some(mode) => Some(mode),
            None => {
                let span = self
                    .string_span(index, "initial")
                    .unwrap_or_else(|| self.entry_span(&self.map.elements, index));
                let names: Vec<String> = allowed
                    .iter()
                    .map(|m| format!("\"{}\"", m.name()))
                    .collect();
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::BadMode,
                        format!(
                            "element '{name}': initial mode \"{text}\" is not one of {}",
                            names.join(", ")
                        ),
                    )
                    .at(&self.file, span)
                    .element(name),
                );
                None
            }
        }
    }
}
