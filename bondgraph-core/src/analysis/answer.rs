//! A student's answer: states and `A`, `B` (and optionally `E`) as exact rational functions
//! of the model's parameters, to compare with a derivation ([`super::compare`]). Answer
//! files are read by `bondgraph-ron`; an entry's text becomes a rational function here
//! ([`rational`]): `+ - * /`, integer powers, numbers, parameter names.

use crate::expr::{self, Expr, ExprKind};
use crate::source::Span;
use crate::symbolic::{RatFunc, SymbolTable};

use super::Matrix;

/// An answer, its entries exact rational functions of the model's parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Answer {
    /// The states' names, if the answer gives them.
    pub states: Option<Vec<String>>,
    /// `A` (states × states).
    pub a: Matrix,
    /// `B` (states × inputs).
    pub b: Matrix,
    /// `E` (states × inputs), if given.
    pub e: Option<Matrix>,
}

/// `text` as an exact rational function of `symbols`: the error and its span in `text`.
pub fn rational(text: &str, symbols: &SymbolTable) -> std::result::Result<RatFunc, (String, Span)> {
    rational_with(text, &|name| symbols.get(name).map(RatFunc::symbol))
}

/// `text` as an exact rational function, each name's value given by `resolve` (`None`: not
/// a parameter of the model).
pub fn rational_with(
    text: &str,
    resolve: &dyn Fn(&str) -> Option<RatFunc>,
) -> std::result::Result<RatFunc, (String, Span)> {
    let parsed = expr::parse(text).map_err(|e| (e.message, e.span))?;
    lower(&parsed, resolve)
}

fn lower(
    e: &Expr,
    symbols: &dyn Fn(&str) -> Option<RatFunc>,
) -> std::result::Result<RatFunc, (String, Span)> {
    let zero_division = || ("divides by zero".to_string(), e.span);
    Ok(match &e.kind {
        ExprKind::Number(text) => RatFunc::from_decimal(text).ok_or_else(|| {
            (
                format!("'{text}' is not a number this program can represent exactly"),
                e.span,
            )
        })?,
        ExprKind::Symbol(name) => match symbols(name) {
            Some(value) => value,
            None => {
                return Err((format!("'{name}' is not a parameter of the model"), e.span));
            }
        },
        ExprKind::Neg(x) => -lower(x, symbols)?,
        ExprKind::Add(x, y) => lower(x, symbols)? + lower(y, symbols)?,
        ExprKind::Sub(x, y) => lower(x, symbols)? - lower(y, symbols)?,
        ExprKind::Mul(x, y) => lower(x, symbols)? * lower(y, symbols)?,
        ExprKind::Div(x, y) => lower(x, symbols)?
            .checked_div(&lower(y, symbols)?)
            .ok_or_else(zero_division)?,
        ExprKind::Pow(x, n) => lower(x, symbols)?.powi(*n).ok_or_else(zero_division)?,
        ExprKind::RealPow(..) | ExprKind::Call(..) => {
            return Err((
                "an entry of A, B or E must be rational in the parameters (+ - * /, integer powers)"
                    .to_string(),
                e.span,
            ));
        }
    })
}
