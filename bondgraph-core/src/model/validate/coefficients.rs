//! Coefficients and source values from their expressions: exact rational functions of the
//! parameters, affine in the inputs where a source may follow them, each refused with the
//! part of the expression at fault (an unknown symbol, a sign, a size past the limits).

use crate::diagnostics::{Diagnostic, DiagnosticKind, suggest};
use crate::expr::{Expr, ExprKind};
use crate::linear::{LinearForm, Var};
use crate::model::checked::{Coefficient, SourceValue};
use crate::source::Span;
use crate::symbolic::RatFunc;

use super::{Scope, Sign, Validator};

impl Validator<'_> {
    /// Breakaway and Coulomb levels that do not depend on inputs must satisfy
    /// `breakaway >= coulomb >= 0`.
    pub(super) fn check_friction_levels(
        &mut self,
        name: &str,
        breakaway: &SourceValue,
        coulomb: &SourceValue,
        scope: &Scope<'_>,
    ) -> Option<()> {
        let constant = |v: &SourceValue| {
            (!v.value.mentions(|var| matches!(var, Var::Input(_))))
                .then(|| v.value.coefficient(Var::Constant).eval(scope.values))
        };
        let (Some(f_s), Some(f_c)) = (constant(breakaway), constant(coulomb)) else {
            return Some(());
        };
        let problem = if f_c < 0.0 {
            Some((
                coulomb.span,
                format!(
                    "Coulomb force \"{}\" = {f_c} must not be negative",
                    coulomb.text
                ),
            ))
        } else if f_s < f_c {
            Some((
                breakaway.span,
                format!(
                    "breakaway force \"{}\" = {f_s} is below the Coulomb force \"{}\" = {f_c}",
                    breakaway.text, coulomb.text
                ),
            ))
        } else {
            None
        };
        if let Some((span, message)) = problem {
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!("friction contact '{name}': {message}"),
                )
                .at(&self.file, span)
                .element(name)
                .note("a contact breaks away at F_S and then slides at F_C, so F_S >= F_C >= 0"),
            );
            return None;
        }
        Some(())
    }

    /// Parses an expression and turns it into an affine form of the inputs (and, with
    /// `states`, of storage elements' energy variables: a source's feedback); with `inputs`
    /// false (a coefficient) it may name parameters only.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn affine(
        &mut self,
        element: &str,
        index: usize,
        field: &str,
        text: &str,
        scope: &Scope<'_>,
        inputs: bool,
        states: bool,
    ) -> Option<(LinearForm, Span)> {
        let (expr, base) = self.parse_field(element, index, field, text)?;
        let mut unknown = false;
        for (symbol, span) in expr.symbols() {
            if scope.symbols.get(symbol).is_none()
                && !scope.inputs.contains_key(symbol)
                && !(states && scope.states.contains_key(symbol))
            {
                unknown = true;
                let kinds = if states {
                    "a parameter, an input nor a state"
                } else {
                    "a parameter nor an input"
                };
                let mut diagnostic = Diagnostic::new(
                    DiagnosticKind::UnknownSymbol,
                    format!(
                        "element '{element}': {field} \"{text}\" uses '{symbol}', which is neither {kinds}"
                    ),
                )
                .at(&self.file, span.shifted(base.start))
                .element(element);
                let state_names = scope.states.keys().filter(|_| states).map(String::as_str);
                let candidates = scope
                    .symbols
                    .iter()
                    .map(|(_, n)| n)
                    .chain(scope.inputs.keys().copied())
                    .chain(state_names);
                if let Some(suggestion) = suggest(symbol, candidates) {
                    diagnostic = diagnostic.note(format!("did you mean '{suggestion}'?"));
                }
                self.problems.push(diagnostic);
            }
        }
        if unknown {
            return None;
        }
        let input = expr
            .symbols()
            .into_iter()
            .find(|(name, _)| scope.symbols.get(name).is_none())
            .map(|(name, _)| name);
        if let (false, Some(input)) = (inputs, input) {
            // Said before the algebra, which would otherwise complain of the way the input
            // enters (`m/u`: "divides by an input") rather than that it enters at all.
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::NotLinear,
                    format!(
                        "element '{element}': {field} \"{text}\" depends on input '{input}'; it may use parameters only"
                    ),
                )
                .at(&self.file, base)
                .element(element)
                .note("a coefficient that varies in time makes the model time-varying, which it cannot be"),
            );
            return None;
        }
        match to_affine(&expr, scope) {
            Ok(form) => Some((form, base)),
            Err((kind, message, span)) => {
                let rule = match (kind, inputs) {
                    (DiagnosticKind::NotLinear, true) => format!(
                        "; {field} must be linear in the inputs, with rational functions of the parameters as coefficients"
                    ),
                    (DiagnosticKind::NotLinear, false) => {
                        format!("; {field} must be a rational function of the parameters")
                    }
                    _ => String::new(),
                };
                self.problems.push(
                    Diagnostic::new(
                        kind,
                        format!("element '{element}': {field} \"{text}\": {message}{rule}"),
                    )
                    .at(&self.file, span.shifted(base.start))
                    .element(element),
                );
                None
            }
        }
    }

    /// The value of a source (`states`: which may feed back the states) or of a friction
    /// contact's or flow limit's level (which may not).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn source_value(
        &mut self,
        element: &str,
        index: usize,
        field: &str,
        text: &str,
        scope: &Scope<'_>,
        states: bool,
    ) -> Option<SourceValue> {
        let (value, span) = self.affine(element, index, field, text, scope, true, states)?;
        if let Some(constant) = value.get(Var::Constant) {
            let number = constant.eval(scope.values);
            if !number.is_finite() {
                self.problems.push(
                    Diagnostic::new(
                        DiagnosticKind::InvalidValue,
                        format!(
                            "element '{element}': {field} \"{text}\" evaluates to {}, which is not finite",
                            crate::number::shortest(number)
                        ),
                    )
                    .at(&self.file, span)
                    .element(element),
                );
                return None;
            }
        }
        Some(SourceValue {
            value,
            text: text.to_string(),
            span,
        })
    }

    pub(super) fn coefficient(
        &mut self,
        element: &str,
        index: usize,
        field: &str,
        text: &str,
        scope: &Scope<'_>,
        sign: Sign,
    ) -> Option<Coefficient> {
        let (form, span) = self.affine(element, index, field, text, scope, false, false)?;
        let value = form.coefficient(Var::Constant);
        let number = value.eval(scope.values);
        let bad = match sign {
            _ if !number.is_finite() => Some("finite"),
            Sign::Positive if value.is_zero() || number <= 0.0 => Some("positive"),
            Sign::NonNegative if number < 0.0 => Some("zero or positive"),
            Sign::NonZero if value.is_zero() || number == 0.0 => Some("non-zero"),
            _ => None,
        };
        // Zero in f64 while the exact value is not: the expression underflows.
        let underflows = number == 0.0
            && !value.is_zero()
            && value.numerator().vanishes_at(scope.values) == Some(false);
        if let (Some(requirement), true) = (bad, underflows) {
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "element '{element}': {field} \"{text}\" is not zero but underflows to 0 in double precision; it must be {requirement}"
                    ),
                )
                .at(&self.file, span)
                .element(element)
                .note("the smallest positive double is about 4.9e-324: choose units in which the value is nearer 1"),
            );
            return None;
        }
        if let Some(requirement) = bad {
            let used: Vec<String> = value
                .symbols()
                .into_iter()
                .map(|s| {
                    format!(
                        "{} = {}",
                        scope.symbols.name(s),
                        crate::number::shortest(scope.values[s.index()])
                    )
                })
                .collect();
            let with = if used.is_empty() || value.is_constant() {
                String::new()
            } else {
                format!(" (with {})", used.join(", "))
            };
            self.problems.push(
                Diagnostic::new(
                    DiagnosticKind::InvalidValue,
                    format!(
                        "element '{element}': {field} \"{text}\" = {}{with} must be {requirement}",
                        crate::number::shortest(number)
                    ),
                )
                .at(&self.file, span)
                .element(element),
            );
            return None;
        }
        Some(Coefficient {
            value,
            text: text.to_string(),
            span,
        })
    }
}

/// `1/c`, for a coefficient checked non-zero, with its text saying so.
pub(super) fn reciprocal(c: Coefficient) -> Coefficient {
    Coefficient {
        value: c.value.inv().expect("checked non-zero"),
        text: format!("1/({})", c.text),
        span: c.span,
    }
}

pub(super) type Failure = (DiagnosticKind, String, Span);

/// Turns an expression into an affine form of the inputs with parameter coefficients,
/// refusing any part of it that expands beyond [`crate::limits`].
pub(super) fn to_affine(
    expr: &Expr,
    scope: &Scope<'_>,
) -> std::result::Result<LinearForm, Failure> {
    let form = to_affine_unbounded(expr, scope)?;
    for (_, coefficient) in form.terms() {
        if let Some(why) = crate::limits::expression_too_large(coefficient) {
            return Err((DiagnosticKind::TooLarge, why, expr.span));
        }
    }
    Ok(form)
}

pub(super) fn to_affine_unbounded(
    expr: &Expr,
    scope: &Scope<'_>,
) -> std::result::Result<LinearForm, Failure> {
    let constant_of = |form: &LinearForm| -> Option<RatFunc> {
        if form.mentions(|v| v != Var::Constant) {
            None
        } else {
            Some(form.coefficient(Var::Constant))
        }
    };
    Ok(match &expr.kind {
        ExprKind::Number(text) => {
            let value = RatFunc::from_decimal(text).ok_or_else(|| {
                (
                    DiagnosticKind::BadExpression,
                    format!("'{text}' is not a number this program can represent exactly"),
                    expr.span,
                )
            })?;
            LinearForm::constant(value)
        }
        ExprKind::Symbol(name) => {
            match (scope.symbols.get(name), scope.inputs.get(name.as_str())) {
                (Some(symbol), _) => LinearForm::constant(RatFunc::symbol(symbol)),
                (None, Some(input)) => LinearForm::var(Var::Input(*input)),
                // Callers let through only parameters, inputs and (a source's) states.
                (None, None) => LinearForm::var(Var::Storage(scope.states[name.as_str()])),
            }
        }
        ExprKind::Neg(inner) => to_affine(inner, scope)?.scaled(&RatFunc::integer(-1)),
        ExprKind::Add(a, b) | ExprKind::Sub(a, b) => {
            let mut left = to_affine(a, scope)?;
            let right = to_affine(b, scope)?;
            let sign = if matches!(expr.kind, ExprKind::Add(..)) {
                1
            } else {
                -1
            };
            left.add_scaled(&right, &RatFunc::integer(sign));
            left
        }
        ExprKind::Mul(a, b) => {
            let (left, right) = (to_affine(a, scope)?, to_affine(b, scope)?);
            match (constant_of(&left), constant_of(&right)) {
                (Some(c), _) => right.scaled(&c),
                (_, Some(c)) => left.scaled(&c),
                _ => {
                    return Err((
                        DiagnosticKind::NotLinear,
                        "multiplies two inputs".into(),
                        expr.span,
                    ));
                }
            }
        }
        ExprKind::Div(a, b) => {
            let (left, right) = (to_affine(a, scope)?, to_affine(b, scope)?);
            let Some(divisor) = constant_of(&right) else {
                return Err((
                    DiagnosticKind::NotLinear,
                    "divides by an input".into(),
                    b.span,
                ));
            };
            let Some(inverse) = divisor.inv() else {
                return Err((
                    DiagnosticKind::InvalidValue,
                    "divides by zero".into(),
                    b.span,
                ));
            };
            left.scaled(&inverse)
        }
        ExprKind::Call(function, _) => {
            return Err((
                DiagnosticKind::NotLinear,
                format!("calls {}()", function.name()),
                expr.span,
            ));
        }
        ExprKind::RealPow(..) => {
            return Err((
                DiagnosticKind::NotLinear,
                "raises to a power that is not an integer literal".into(),
                expr.span,
            ));
        }
        ExprKind::Pow(base, exponent) => {
            let form = to_affine(base, scope)?;
            if *exponent == 1 {
                form
            } else {
                let Some(value) = constant_of(&form) else {
                    return Err((
                        DiagnosticKind::NotLinear,
                        "raises an input to a power".into(),
                        expr.span,
                    ));
                };
                let degree = value.numerator().degree().max(value.denominator().degree());
                let expanded = u64::from(degree) * u64::from(exponent.unsigned_abs());
                if expanded > u64::from(crate::limits::MAX_EXPRESSION_DEGREE) {
                    return Err((
                        DiagnosticKind::TooLarge,
                        format!(
                            "expands to degree {expanded}, over the limit of {}",
                            crate::limits::MAX_EXPRESSION_DEGREE
                        ),
                        expr.span,
                    ));
                }
                let Some(power) = value.powi(*exponent) else {
                    let why = if value.is_zero() {
                        "raises zero to a negative power".to_string()
                    } else {
                        "expands beyond the size exact algebra can hold".to_string()
                    };
                    let kind = if value.is_zero() {
                        DiagnosticKind::InvalidValue
                    } else {
                        DiagnosticKind::TooLarge
                    };
                    return Err((kind, why, expr.span));
                };
                LinearForm::constant(power)
            }
        }
    })
}
