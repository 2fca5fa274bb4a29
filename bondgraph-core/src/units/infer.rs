//! The dimension of an expression (`1/k`, `(m_1 + m_2)*g`, `K_p*x`, `sqrt(k/m)`), from the
//! dimensions of the symbols it names.
//!
//! A symbol whose dimension is not known (a parameter written without a `unit`) makes every
//! product it enters unknown: the check never guesses, so a model that omits units is not
//! rejected. A sum takes the dimension of whichever side is known. Adding, subtracting or
//! comparing (`min`, `max`) two known, different dimensions is a [`Mismatch`]; so is a
//! dimensioned argument to `sin`, `exp`, `ln`, ... An expression that names no symbol at all
//! (`"1"`, `"2"`) is a number written without a unit: unknown, not dimensionless.

use crate::expr::{Expr, ExprKind, Function};
use crate::source::Span;

use super::dimension::Dim;
use super::format::readable;

/// Two dimensions that an expression combines where they must agree.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// The span of the offending node, relative to the expression text.
    pub span: Span,
    /// What is wrong, naming both units: `'F + v' adds N (F) to m/s (v)`.
    pub message: String,
}

/// What an expression's symbols are: their dimension if known, and the unit as written.
pub trait Symbols {
    /// The dimension of `name`, if known.
    fn dim(&self, name: &str) -> Option<Dim>;
    /// The unit of `name` as the file writes it, if it has one.
    fn written(&self, _name: &str) -> Option<String> {
        None
    }
}

/// The dimension of `expr` (parsed from `text`), or `None` where it depends on symbols of
/// unknown dimension.
///
/// # Errors
/// The first [`Mismatch`] inside the expression.
pub fn infer(text: &str, expr: &Expr, symbols: &dyn Symbols) -> Result<Option<Dim>, Mismatch> {
    if expr.symbols().is_empty() {
        return Ok(None);
    }
    Inference { text, symbols }.dim(expr)
}

struct Inference<'a> {
    text: &'a str,
    symbols: &'a dyn Symbols,
}

impl Inference<'_> {
    fn source(&self, expr: &Expr) -> &str {
        self.text
            .get(expr.span.start..expr.span.end)
            .unwrap_or(self.text)
            .trim()
    }

    /// `N (F)` for a symbol with its written unit, else the readable unit.
    fn describe(&self, expr: &Expr, dim: Dim) -> String {
        match &expr.kind {
            ExprKind::Symbol(name) => {
                let unit = self.symbols.written(name).unwrap_or_else(|| readable(dim));
                format!("{unit} ({name})")
            }
            _ => format!("{} ({})", readable(dim), self.source(expr)),
        }
    }

    fn agree(&self, node: &Expr, verb: &str, a: &Expr, b: &Expr) -> Result<Option<Dim>, Mismatch> {
        let (da, db) = (self.dim(a)?, self.dim(b)?);
        match (da, db) {
            (Some(x), Some(y)) if x != y => Err(Mismatch {
                span: node.span,
                message: format!(
                    "'{}' {verb} {} and {}, which are different quantities",
                    self.source(node),
                    self.describe(a, x),
                    self.describe(b, y)
                ),
            }),
            (Some(x), _) | (None, Some(x)) => Ok(Some(x)),
            (None, None) => Ok(None),
        }
    }

    fn dim(&self, expr: &Expr) -> Result<Option<Dim>, Mismatch> {
        Ok(match &expr.kind {
            ExprKind::Number(_) => Some(Dim::NONE),
            ExprKind::Symbol(name) => self.symbols.dim(name),
            ExprKind::Neg(inner) => self.dim(inner)?,
            ExprKind::Add(a, b) => self.agree(expr, "adds", a, b)?,
            ExprKind::Sub(a, b) => self.agree(expr, "subtracts", a, b)?,
            ExprKind::Mul(a, b) => {
                let (da, db) = (self.dim(a)?, self.dim(b)?);
                da.zip(db).map(|(x, y)| x.times(y))
            }
            ExprKind::Div(a, b) => {
                let (da, db) = (self.dim(a)?, self.dim(b)?);
                da.zip(db).map(|(x, y)| x.per(y))
            }
            ExprKind::Pow(base, n) => self.dim(base)?.map(|d| d.powi(*n)),
            ExprKind::RealPow(base, exponent) => {
                let base_dim = self.dim(base)?;
                if let Some(d) = self.dim(exponent)?
                    && !d.is_dimensionless()
                {
                    return Err(self.not_a_number(expr, "a power", exponent, d));
                }
                let number = exponent.eval(&|_| None).ok();
                match (base_dim, number) {
                    (Some(d), _) if d.is_dimensionless() => Some(Dim::NONE),
                    (Some(d), Some(p)) => d.powf(p),
                    _ => None,
                }
            }
            ExprKind::Call(function, args) => self.call(expr, *function, args)?,
        })
    }

    fn not_a_number(&self, node: &Expr, what: &str, arg: &Expr, dim: Dim) -> Mismatch {
        Mismatch {
            span: node.span,
            message: format!(
                "'{}' takes {what} of {}, which must be a pure number",
                self.source(node),
                self.describe(arg, dim)
            ),
        }
    }

    fn call(
        &self,
        node: &Expr,
        function: Function,
        args: &[Expr],
    ) -> Result<Option<Dim>, Mismatch> {
        match function {
            Function::Min | Function::Max => {
                let mut known: Option<(Dim, &Expr)> = None;
                for arg in args {
                    let Some(d) = self.dim(arg)? else { continue };
                    match known {
                        Some((k, first)) if k != d => {
                            return Err(Mismatch {
                                span: node.span,
                                message: format!(
                                    "'{}' compares {} with {}, which are different quantities",
                                    self.source(node),
                                    self.describe(first, k),
                                    self.describe(arg, d)
                                ),
                            });
                        }
                        Some(_) => {}
                        None => known = Some((d, arg)),
                    }
                }
                Ok(known.map(|(d, _)| d))
            }
            Function::Abs => self.dim(&args[0]),
            Function::Sign => {
                self.dim(&args[0])?;
                Ok(Some(Dim::NONE))
            }
            Function::Sqrt => Ok(self.dim(&args[0])?.and_then(|d| d.pow_ratio(1, 2))),
            _ => {
                if let Some(d) = self.dim(&args[0])?
                    && !d.is_dimensionless()
                {
                    return Err(self.not_a_number(node, function.name(), &args[0], d));
                }
                Ok(Some(Dim::NONE))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse::parse_unit;
    use super::*;

    /// m in kg, k in N/m, b in N*s/m, F in N, v in m/s, x in m, K_p in N/m; u has no unit.
    struct Table;

    impl Symbols for Table {
        fn dim(&self, name: &str) -> Option<Dim> {
            let unit = self.written(name)?;
            parse_unit(&unit).ok()
        }
        fn written(&self, name: &str) -> Option<String> {
            let unit = match name {
                "m" => "kg",
                "k" | "K_p" => "N/m",
                "b" => "N*s/m",
                "F" => "N",
                "v" => "m/s",
                "x" => "m",
                "theta" => "rad",
                _ => return None,
            };
            Some(unit.to_string())
        }
    }

    fn dim_of(text: &str) -> Result<Option<Dim>, Mismatch> {
        infer(text, &crate::expr::parse(text).unwrap(), &Table)
    }

    fn unit(text: &str) -> Option<Dim> {
        Some(parse_unit(text).unwrap())
    }

    #[test]
    fn products_quotients_and_powers_follow_the_symbols() {
        // K_p*x: N/m * m = N.
        assert_eq!(dim_of("K_p*x"), Ok(unit("N")));
        // 1/k is a compliance, m/N.
        assert_eq!(dim_of("1/k"), Ok(unit("m/N")));
        // b*v + F: N + N.
        assert_eq!(dim_of("b*v + F"), Ok(unit("N")));
        // sqrt(k/m) is a rate, 1/s; (k/m)^0.5 the same.
        assert_eq!(dim_of("sqrt(k/m)"), Ok(unit("1/s")));
        assert_eq!(dim_of("(k/m)^0.5"), Ok(unit("1/s")));
        assert_eq!(dim_of("x^2*m"), Ok(unit("kg*m^2")));
        // sin of an angle is a number; radians are dimensionless.
        assert_eq!(dim_of("F*sin(theta)"), Ok(unit("N")));
        assert_eq!(dim_of("max(F, b*v)"), Ok(unit("N")));
    }

    #[test]
    fn unknown_symbols_and_bare_numbers_are_unknown_not_dimensionless() {
        assert_eq!(dim_of("u*x"), Ok(None));
        assert_eq!(dim_of("1"), Ok(None));
        assert_eq!(dim_of("2"), Ok(None));
        // A sum with one unknown side takes the known side's dimension.
        assert_eq!(dim_of("(u + x)*k"), Ok(unit("N")));
    }

    #[test]
    fn adding_a_force_to_a_velocity_names_both_units() {
        let error = dim_of("(F + v)*b").unwrap_err();
        assert_eq!(
            error.message,
            "'F + v' adds N (F) and m/s (v), which are different quantities"
        );
        assert_eq!(error.span, Span::new(1, 6));
        let error = dim_of("exp(x)").unwrap_err();
        assert_eq!(
            error.message,
            "'exp(x)' takes exp of m (x), which must be a pure number"
        );
        let error = dim_of("min(F, v)").unwrap_err();
        assert!(
            error.message.contains("N (F) with m/s (v)"),
            "{}",
            error.message
        );
    }
}
