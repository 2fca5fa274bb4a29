//! The refusal of state equations whose coefficients overflow at the parameter values.
//!
//! Every element's own coefficient is checked where it is written (a positive inertance, a
//! finite resistance), but the equations combine them: `L = 1e-310` H is a positive double,
//! yet the current's equation divides by it, and `-R/L` is beyond the largest double. Such a
//! coefficient would reach the numbers as infinity and come out as a wrong answer, a NaN or
//! a loop that never ends; it is refused here, at the element whose equation holds it, so
//! that `check` and every command say so. Values are evaluated without overflow in between
//! ([`RatFunc::eval`]): only a coefficient whose value itself is not a double is refused.

use super::StateEquations;
use crate::diagnostics::{Diagnostic, DiagnosticKind, Result};
use crate::linear::{LinearForm, Var};
use crate::model::AtElement;
use crate::model::{BondId, ElementId, ElementKind, Model};
use crate::number;
use crate::symbolic::RatFunc;

/// `Ok` when every coefficient of the state equations (`A`, `B`, `E`, the constant term) and
/// of every bond's effort and flow (the rows of `C`, `D`, `F`) is finite at the model's
/// parameter values; else an [`DiagnosticKind::InvalidValue`] at the first element whose
/// equation holds one that is not.
pub(crate) fn check(
    model: &Model,
    equations: &StateEquations,
    state_elements: &[ElementId],
) -> Result<()> {
    for (k, row) in equations.derivatives.iter().enumerate() {
        let place = format!("d{}/dt", equations.states[k].name);
        if let Some((var, coefficient, value)) = first_infinite(row, &equations.values) {
            let element = state_elements[k];
            return Err(
                refusal(model, equations, element, &place, var, coefficient, value)
                    .at_element(model, element)
                    .element(model.element(element).name.clone())
                    .into(),
            );
        }
    }
    for (index, form) in equations.bond_vars.iter().enumerate() {
        if let Some((var, coefficient, value)) = first_infinite(form, &equations.values) {
            let bond = BondId((index / 2) as u32);
            let quantity = if index % 2 == 0 { "effort" } else { "flow" };
            let place = format!("the {quantity} of bond {}", model.bond_label(bond));
            let element = bond_element(model, bond);
            return Err(
                refusal(model, equations, element, &place, var, coefficient, value)
                    .at_location(model.locate_bond(bond))
                    .element(model.element(element).name.clone())
                    .into(),
            );
        }
    }
    Ok(())
}

/// The first term of `form` whose coefficient is not finite at `values`.
fn first_infinite<'a>(form: &'a LinearForm, values: &[f64]) -> Option<(Var, &'a RatFunc, f64)> {
    form.terms().iter().find_map(|(var, coefficient)| {
        let value = coefficient.eval(values);
        (!value.is_finite()).then_some((*var, coefficient, value))
    })
}

/// The element a bond's variables belong to: its end that is not a junction.
fn bond_element(model: &Model, bond: BondId) -> ElementId {
    let b = model.bond(bond);
    let junction = |e: ElementId| {
        matches!(
            model.element(e).kind,
            ElementKind::ZeroJunction | ElementKind::OneJunction
        )
    };
    if junction(b.to) && !junction(b.from) {
        b.from
    } else {
        b.to
    }
}

fn refusal(
    model: &Model,
    equations: &StateEquations,
    element: ElementId,
    place: &str,
    var: Var,
    coefficient: &RatFunc,
    value: f64,
) -> Diagnostic {
    let symbols = &equations.symbols;
    let element = &model.element(element).name;
    let term = match var {
        Var::Constant => "the constant term".to_string(),
        other => format!("the coefficient of {}", equations.var_name(other)),
    };
    let used: Vec<String> = coefficient
        .symbols()
        .into_iter()
        .map(|s| {
            format!(
                "{} = {}",
                symbols.name(s),
                number::shortest(equations.values[s.index()])
            )
        })
        .collect();
    let with = if used.is_empty() {
        String::new()
    } else {
        format!(" with {}", used.join(", "))
    };
    let why = if value.is_nan() {
        "is not a number in double precision"
    } else {
        "overflows double precision"
    };
    Diagnostic::new(
        DiagnosticKind::InvalidValue,
        format!(
            "element '{element}': in {place}, {term} is {} = {}{with}, which {why}",
            coefficient.text(symbols),
            number::shortest(value),
        ),
    )
    .note("the largest double is about 1.8e308: choose units in which the values are nearer 1")
}
