//! Nonlinear and modulated laws: expressions that use functions, real powers, the energy
//! variables of storage elements (`q_spring`, `p_mass`), a resistor's port variable
//! (`flow`, `effort`), or inputs where a linear model allows parameters only.
//!
//! A source affine in inputs and states with parameter coefficients (a proportional
//! controller `Se(effort: "-K_c*q_spring")`) is not one of them: it is linear feedback,
//! and the source stays a linear element whose value names the states.
//!
//! Such a law is lowered to a symbolic expression ([`Sym`]) with every name resolved. Where
//! what was written is linear after all (`R(effort: "b*flow")`), it becomes the plain
//! linear element, so that a model is nonlinear only when a law really is. A resistor's law
//! is inverted symbolically where possible; otherwise it fixes the resistor's causality.

use crate::diagnostics::{Diagnostic, DiagnosticKind};
use crate::expr::{self, Expr, ExprKind};
use crate::model::checked::{
    Coefficient, ElementKind, NonlinearElement, NonlinearLaw, ResistorLaw,
};
use crate::source::Span;
use crate::symbolic::RatFunc;
use crate::symbolic::expr::{Atom, Node, Sym};

use super::{Scope, Validator, to_affine};
use crate::diagnostics::suggest;

/// Which storage states a law may name.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum States {
    /// None.
    None,
    /// Only the element's own (its raw index).
    Own(u32),
    /// Any.
    All,
}

/// What a law may name besides parameters, and how to say so.
#[derive(Clone, Copy)]
pub(super) struct Allowed {
    inputs: bool,
    states: States,
    /// The port variable's name in a resistor's law.
    port: Option<&'static str>,
    /// What the law is, for messages: "a compliance's effort".
    what: &'static str,
}

impl Validator<'_> {
    /// Whether `text` needs a nonlinear law: it calls a function, raises to a real power,
    /// names a state or a port variable, or (for a `coefficient`, which linear elements
    /// keep parameter-only) names an input. Text that does not parse takes the linear path,
    /// which reports it.
    pub(super) fn needs_law(&self, text: &str, scope: &Scope<'_>, coefficient: bool) -> bool {
        self.needs_law_where(text, scope, coefficient, true)
    }

    /// As [`Validator::needs_law`]; an input in a coefficient that may not be `modulated`
    /// (an inertance, a compliance) takes the linear path, which says it may use parameters
    /// only.
    pub(super) fn needs_law_where(
        &self,
        text: &str,
        scope: &Scope<'_>,
        coefficient: bool,
        modulated: bool,
    ) -> bool {
        if coefficient && plainly_parameters(text, scope) {
            // The common case, decided without parsing twice: `1/k_ge`, `m_ct + m_ge`.
            return false;
        }
        let Ok(expr) = expr::parse(text) else {
            return false;
        };
        let known = |name: &str| {
            scope.symbols.get(name).is_some()
                || scope.inputs.contains_key(name)
                || scope.states.contains_key(name)
                || name == "flow"
                || name == "effort"
        };
        if !expr.symbols().iter().all(|(name, _)| known(name)) {
            // An unknown name: the linear path reports it, with its suggestion.
            return false;
        }
        if expr.is_transcendental() {
            return true;
        }
        let neither =
            |name: &str| scope.symbols.get(name).is_none() && !scope.inputs.contains_key(name);
        let names_state = expr
            .symbols()
            .iter()
            .any(|(name, _)| neither(name) && scope.states.contains_key(*name));
        let names_port = expr.symbols().iter().any(|(name, _)| {
            neither(name) && !scope.states.contains_key(*name) && matches!(*name, "flow" | "effort")
        });
        if names_port || (coefficient && names_state) {
            return true;
        }
        let names_input = expr
            .symbols()
            .iter()
            .any(|(name, _)| scope.symbols.get(name).is_none() && scope.inputs.contains_key(name));
        if coefficient {
            return names_input && modulated;
        }
        // A source: nonlinear in its inputs and states (`u^2`, `u*v`, `1/u`, `q_spring*p_mass`)
        // needs a law; affine in them, it is a linear source, with state feedback
        // (`-K_c*q_spring`) where it names a state.
        matches!(
            to_affine(&expr, scope),
            Err((DiagnosticKind::NotLinear, _, _))
        )
    }

    /// An effort or flow source with a nonlinear law of inputs and states.
    pub(super) fn nonlinear_source(
        &mut self,
        element: &str,
        index: usize,
        field: &'static str,
        text: &str,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let allowed = Allowed {
            inputs: true,
            states: States::All,
            port: None,
            what: "a source",
        };
        let (law, span) = self.law(element, index, field, text, scope, allowed)?;
        let law = if field == "effort" {
            NonlinearLaw::EffortSource(law)
        } else {
            NonlinearLaw::FlowSource(law)
        };
        Some(nonlinear(law, field, text, span))
    }

    /// An inertia (`flow: f(p)`) or compliance (`effort: f(q)`) with a nonlinear law of its
    /// own energy variable; `field` is the law's field, or `inertance`, `compliance` or
    /// `stiffness` for a parameter-only coefficient that is not rational (`m*sin(a)^2`).
    pub(super) fn nonlinear_storage(
        &mut self,
        element: &str,
        index: usize,
        field: &'static str,
        text: &str,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let inertia = matches!(field, "flow" | "inertance");
        let own = Sym::atom(Atom::Storage(index as u32));
        let allowed = Allowed {
            inputs: false,
            states: if matches!(field, "flow" | "effort") {
                States::Own(index as u32)
            } else {
                States::None
            },
            port: None,
            what: if inertia {
                "an inertia's law"
            } else {
                "a compliance's law"
            },
        };
        let (value, span) = self.law(element, index, field, text, scope, allowed)?;
        let law = match field {
            "flow" | "effort" => value,
            "stiffness" => Sym::mul(&value, &own),
            _ => match Sym::div(&own, &value) {
                Some(law) => law,
                None => {
                    self.problems.push(
                        Diagnostic::new(
                            DiagnosticKind::InvalidValue,
                            format!("element '{element}': {field} \"{text}\" is zero"),
                        )
                        .at(&self.file, span)
                        .element(element),
                    );
                    return None;
                }
            },
        };
        // Linear after all: `k*q_spring` is a compliance 1/k.
        if let Some(slope) = linear_slope(&law, Atom::Storage(index as u32))
            && slope.eval(scope.values) > 0.0
            && let Some(coefficient) = slope.inv()
        {
            let coefficient = Coefficient {
                value: coefficient,
                text: text.to_string(),
                span,
            };
            return Some(if inertia {
                ElementKind::Inertia(coefficient)
            } else {
                ElementKind::Compliance(coefficient)
            });
        }
        let law = if inertia {
            NonlinearLaw::Inertia(law)
        } else {
            NonlinearLaw::Compliance(law)
        };
        Some(nonlinear(law, field, text, span))
    }

    /// A resistor with a law `effort: f(flow)`, `flow: g(effort)`, or a modulated (or
    /// port-dependent) `resistance`.
    pub(super) fn nonlinear_resistor(
        &mut self,
        element: &str,
        index: usize,
        field: &'static str,
        text: &str,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let port = Sym::atom(Atom::Port);
        let (effort, flow, span) = match field {
            "effort" | "flow" => {
                let allowed = Allowed {
                    inputs: true,
                    states: States::All,
                    port: Some(if field == "effort" { "flow" } else { "effort" }),
                    what: "a resistor's law",
                };
                let (law, span) = self.law(element, index, field, text, scope, allowed)?;
                if field == "effort" {
                    (Some(law), None, span)
                } else {
                    (None, Some(law), span)
                }
            }
            _ => {
                // resistance: e = R·f, where R may depend on the flow or on the effort
                // (BondGraphTools writes a diode as `V_T/I_s*exp(-e/V_T)`), never both.
                let names_effort = expr::parse(text).is_ok_and(|e| {
                    e.symbols()
                        .iter()
                        .any(|(n, _)| *n == "effort" && scope.symbols.get(n).is_none())
                });
                let allowed = Allowed {
                    inputs: true,
                    states: States::All,
                    port: Some(if names_effort { "effort" } else { "flow" }),
                    what: "a resistance",
                };
                let (resistance, span) = self.law(element, index, field, text, scope, allowed)?;
                if names_effort {
                    match Sym::div(&port, &resistance) {
                        Some(flow) => (None, Some(flow), span),
                        None => {
                            self.zero_law(element, field, text, span);
                            return None;
                        }
                    }
                } else {
                    (Some(Sym::mul(&resistance, &port)), None, span)
                }
            }
        };
        // Linear after all: `b*flow` is a resistance b, `effort/b` a resistance b.
        let linear = match (&effort, &flow) {
            (Some(e), None) => linear_slope(e, Atom::Port),
            (None, Some(f)) => linear_slope(f, Atom::Port).and_then(|c| c.inv()),
            _ => None,
        };
        if let Some(resistance) = linear
            && resistance.eval(scope.values) >= 0.0
        {
            return Some(ElementKind::Resistor(Coefficient {
                value: resistance,
                text: text.to_string(),
                span,
            }));
        }
        // The other causal form, where the law can be solved for its port variable.
        let placeholder = Atom::Bond(u32::MAX);
        let invert = |law: &Sym| {
            law.solve_for(Atom::Port, &Sym::atom(placeholder))
                .map(|inverse| {
                    inverse.substitute(&|a| (a == placeholder).then(|| Sym::atom(Atom::Port)))
                })
        };
        let law = match (effort, flow) {
            (Some(e), None) => ResistorLaw {
                flow: invert(&e),
                effort: Some(e),
            },
            (None, Some(f)) => ResistorLaw {
                effort: invert(&f),
                flow: Some(f),
            },
            _ => unreachable!("one form is given"),
        };
        Some(nonlinear(NonlinearLaw::Resistor(law), field, text, span))
    }

    /// A transformer or gyrator whose ratio depends on inputs and states.
    pub(super) fn modulated_two_port(
        &mut self,
        element: &str,
        index: usize,
        gyrator: bool,
        text: &str,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let allowed = Allowed {
            inputs: true,
            states: States::All,
            port: None,
            what: "a ratio",
        };
        let (ratio, span) = self.law(element, index, "ratio", text, scope, allowed)?;
        if ratio.is_zero() {
            self.zero_law(element, "ratio", text, span);
            return None;
        }
        let law = if gyrator {
            NonlinearLaw::Gyrator(ratio)
        } else {
            NonlinearLaw::Transformer(ratio)
        };
        Some(nonlinear(law, "ratio", text, span))
    }

    /// A linear graph's gyrator whose ratio depends on inputs and states: the bond-graph
    /// gyrator with the reciprocal ratio (see [`crate::model::spec::ElementSpec::ReciprocalGY`]),
    /// as for a constant ratio.
    pub(super) fn modulated_reciprocal_gyrator(
        &mut self,
        element: &str,
        index: usize,
        text: &str,
        scope: &Scope<'_>,
    ) -> Option<ElementKind> {
        let allowed = Allowed {
            inputs: true,
            states: States::All,
            port: None,
            what: "a ratio",
        };
        let (ratio, span) = self.law(element, index, "ratio", text, scope, allowed)?;
        let Some(reciprocal) = Sym::div(&Sym::one(), &ratio) else {
            self.zero_law(element, "ratio", text, span);
            return None;
        };
        Some(nonlinear(
            NonlinearLaw::Gyrator(reciprocal),
            "ratio",
            &format!("1/({text})"),
            span,
        ))
    }

    fn zero_law(&mut self, element: &str, field: &str, text: &str, span: Span) {
        self.problems.push(
            Diagnostic::new(
                DiagnosticKind::InvalidValue,
                format!("element '{element}': {field} \"{text}\" is zero"),
            )
            .at(&self.file, span)
            .element(element),
        );
    }

    /// Parses a law and resolves its names as `allowed` says, reporting every problem at
    /// its place in the file.
    fn law(
        &mut self,
        element: &str,
        index: usize,
        field: &str,
        text: &str,
        scope: &Scope<'_>,
        allowed: Allowed,
    ) -> Option<(Sym, Span)> {
        let (expr, base) = self.parse_field(element, index, field, text)?;
        let mut ok = true;
        for (name, span) in expr.symbols() {
            let problem = self.check_name_in_law(element, field, text, name, scope, allowed);
            if let Some(diagnostic) = problem {
                ok = false;
                self.problems.push(
                    diagnostic
                        .at(&self.file, span.shifted(base.start))
                        .element(element),
                );
            }
        }
        if !ok {
            return None;
        }
        match lower(&expr, scope, allowed) {
            Ok(sym) => {
                if let Some(zeros) = undefined_through_zeros(&sym, scope) {
                    let values = zeros
                        .iter()
                        .map(|name| format!("{name} = 0"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    self.problems.push(
                        Diagnostic::new(
                            DiagnosticKind::InvalidValue,
                            format!(
                                "element '{element}': {field} \"{text}\" is 0/0 at {values}, its value in the model, whatever the state"
                            ),
                        )
                        .at(&self.file, base)
                        .element(element)
                        .note(format!(
                            "a parameter's no-effect value must leave the law defined: write it without dividing by {0} (a difference of roots over {0} times its conjugate: (sqrt(x) - y)/a = (x - y^2)/(a*(sqrt(x) + y)), where a cancels), or give {0} a value other than 0",
                            zeros.join(", ")
                        )),
                    );
                    return None;
                }
                Some((sym, base))
            }
            Err((message, span)) => {
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidValue,
                        format!("element '{element}': {field} \"{text}\": {message}"),
                    )
                    .at(&self.file, span.shifted(base.start))
                    .element(element),
                );
                None
            }
        }
    }

    /// Why `name` may not appear in this law, if it may not.
    fn check_name_in_law(
        &self,
        element: &str,
        field: &str,
        text: &str,
        name: &str,
        scope: &Scope<'_>,
        allowed: Allowed,
    ) -> Option<Diagnostic> {
        if scope.symbols.get(name).is_some() || allowed.port == Some(name) {
            return None;
        }
        let what = allowed.what;
        if scope.inputs.contains_key(name) {
            return (!allowed.inputs).then(|| {
                Diagnostic::new(
                    DiagnosticKind::NotLinear,
                    format!(
                        "element '{element}': {field} \"{text}\" depends on input '{name}'; {what} may not depend on inputs"
                    ),
                )
                .note("storage whose law varies in time does not conserve energy; drive it through a source or a modulated element instead")
            });
        }
        if let Some(&owner) = scope.states.get(name) {
            let ok = match allowed.states {
                States::All => true,
                States::Own(own) => owner == own,
                States::None => false,
            };
            return (!ok).then(|| {
                let only = match allowed.states {
                    States::Own(own) => {
                        let own_name = scope
                            .states
                            .iter()
                            .find(|(_, e)| **e == own)
                            .map_or("its own state", |(n, _)| n.as_str());
                        format!(
                            "{what} may depend on its own state '{own_name}' and parameters only"
                        )
                    }
                    _ => format!("{what} may depend on parameters only"),
                };
                Diagnostic::new(
                    DiagnosticKind::NotLinear,
                    format!(
                        "element '{element}': {field} \"{text}\" uses the state '{name}'; {only}"
                    ),
                )
            });
        }
        let mut candidates: Vec<&str> = scope.symbols.iter().map(|(_, n)| n).collect();
        if allowed.inputs {
            candidates.extend(scope.inputs.keys().copied());
        }
        match allowed.states {
            States::All => candidates.extend(scope.states.keys().map(String::as_str)),
            States::Own(own) => candidates.extend(
                scope
                    .states
                    .iter()
                    .filter(|(_, e)| **e == own)
                    .map(|(n, _)| n.as_str()),
            ),
            States::None => {}
        }
        candidates.extend(allowed.port);
        let kinds = match (allowed.port, allowed.states != States::None) {
            (Some(port), _) => format!("a parameter, an input, a state nor the port's {port}"),
            (None, true) => "a parameter, an input nor a state".to_string(),
            (None, false) => "a parameter".to_string(),
        };
        let mut diagnostic = Diagnostic::new(
            DiagnosticKind::UnknownSymbol,
            format!(
                "element '{element}': {field} \"{text}\" uses '{name}', which is neither {kinds}"
            ),
        );
        if let Some(suggestion) = suggest(name, candidates.into_iter()) {
            diagnostic = diagnostic.note(format!("did you mean '{suggestion}'?"));
        }
        Some(diagnostic)
    }
}

/// Whether `text` has no call, no power and names parameters only: a linear coefficient.
fn plainly_parameters(text: &str, scope: &Scope<'_>) -> bool {
    !text.contains(['(', '^'])
        && text
            .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .filter(|word| word.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_'))
            .all(|word| scope.symbols.get(word).is_some())
}

fn nonlinear(law: NonlinearLaw, field: &str, text: &str, span: Span) -> ElementKind {
    ElementKind::Nonlinear(Box::new(NonlinearElement {
        law,
        field: field.to_string(),
        text: text.to_string(),
        span,
    }))
}

/// `c` where `law = c·x` with `c` a parameter-only exact coefficient.
fn linear_slope(law: &Sym, x: Atom) -> Option<RatFunc> {
    if *law == Sym::atom(x) {
        return Some(RatFunc::one());
    }
    match law.node() {
        Node::Sum(constant, terms)
            if constant.is_zero() && terms.len() == 1 && terms[0].0 == Sym::atom(x) =>
        {
            Some(terms[0].1.clone())
        }
        _ => None,
    }
}

/// The expression with its names resolved (checked beforehand), its parameter-only parts
/// within [`crate::limits`].
fn lower(expr: &Expr, scope: &Scope<'_>, allowed: Allowed) -> Result<Sym, (String, Span)> {
    let value = if let ExprKind::Pow(a, n) = &expr.kind {
        let base = lower(a, scope, allowed)?;
        if let Some(c) = base.as_coefficient() {
            let degree = c.numerator().degree().max(c.denominator().degree());
            let expanded = u64::from(degree) * u64::from(n.unsigned_abs());
            if expanded > u64::from(crate::limits::MAX_EXPRESSION_DEGREE) {
                return Err((
                    format!(
                        "expands to degree {expanded}, over the limit of {}",
                        crate::limits::MAX_EXPRESSION_DEGREE
                    ),
                    expr.span,
                ));
            }
        }
        base.powi(i64::from(*n))
            .ok_or_else(|| ("raises zero to a negative power".to_string(), expr.span))?
    } else {
        lower_unbounded(expr, scope, allowed)?
    };
    if let Some(why) = value
        .as_coefficient()
        .and_then(crate::limits::expression_too_large)
    {
        return Err((why, expr.span));
    }
    Ok(value)
}

fn lower_unbounded(
    expr: &Expr,
    scope: &Scope<'_>,
    allowed: Allowed,
) -> Result<Sym, (String, Span)> {
    let zero_power = || ("raises zero to a negative power".to_string(), expr.span);
    Ok(match &expr.kind {
        ExprKind::Number(text) => {
            Sym::coefficient(RatFunc::from_decimal(text).ok_or_else(|| {
                (
                    format!("'{text}' is not a number this program can represent exactly"),
                    expr.span,
                )
            })?)
        }
        ExprKind::Symbol(name) => {
            if let Some(symbol) = scope.symbols.get(name) {
                Sym::coefficient(RatFunc::symbol(symbol))
            } else if let Some(input) = scope.inputs.get(name.as_str()) {
                Sym::atom(Atom::Input(*input))
            } else if allowed.port == Some(name.as_str()) {
                Sym::atom(Atom::Port)
            } else {
                Sym::atom(Atom::Storage(scope.states[name.as_str()]))
            }
        }
        ExprKind::Neg(a) => Sym::neg(&lower(a, scope, allowed)?),
        ExprKind::Add(a, b) => Sym::add(&lower(a, scope, allowed)?, &lower(b, scope, allowed)?),
        ExprKind::Sub(a, b) => Sym::sub(&lower(a, scope, allowed)?, &lower(b, scope, allowed)?),
        ExprKind::Mul(a, b) => Sym::mul(&lower(a, scope, allowed)?, &lower(b, scope, allowed)?),
        ExprKind::Div(a, b) => Sym::div(&lower(a, scope, allowed)?, &lower(b, scope, allowed)?)
            .ok_or_else(|| ("divides by zero".to_string(), b.span))?,
        ExprKind::Pow(a, n) => lower(a, scope, allowed)?
            .powi(i64::from(*n))
            .ok_or_else(zero_power)?,
        ExprKind::RealPow(a, b) => lower(a, scope, allowed)?
            .powf(&lower(b, scope, allowed)?)
            .ok_or_else(zero_power)?,
        ExprKind::Call(function, args) => Sym::call(
            *function,
            args.iter()
                .map(|a| lower(a, scope, allowed))
                .collect::<Result<_, _>>()?,
        ),
    })
}

/// The parameters at value zero that leave `law` undefined (not a number) at the model's
/// values whatever its variables, when it is defined with any one of them moved off zero:
/// a law singular at a parameter's no-effect value, as `(sqrt(A^2 + 2 a q) - A)/a` at
/// `a = 0`. `None` where the law is defined somewhere, or is undefined for another reason.
fn undefined_through_zeros(law: &Sym, scope: &Scope<'_>) -> Option<Vec<String>> {
    // Variables are probed at a few magnitudes of either sign; one defined value suffices.
    const PROBES: [f64; 6] = [0.5, 1.0, 2.0, -0.5, -1.0, -2.0];
    let defined = |values: &[f64]| PROBES.iter().any(|&x| law.eval(&|_| x, values).is_finite());
    if defined(scope.values) {
        return None;
    }
    let zeros: Vec<String> = law
        .parameters()
        .into_iter()
        .filter(|p| scope.values.get(p.index()) == Some(&0.0))
        .filter(|p| {
            let mut moved = scope.values.to_vec();
            moved[p.index()] = 1e-3;
            defined(&moved)
        })
        .map(|p| scope.symbols.name(p).to_string())
        .collect();
    (!zeros.is_empty()).then_some(zeros)
}
