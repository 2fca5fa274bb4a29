//! Symbolic expressions as a textbook writes them, in plain text and in LaTeX.
//!
//! A sum prints its terms in canonical order with the constant last (`-g/l*sin(q) - b*p`),
//! a coefficient is written the way [`RatFunc`] writes it and merged with its term as the
//! linear equations do (`p_mass/m`, `-(b + K_p)/M*v`), negative exponents go below the
//! fraction bar, `x^(1/2)` is `sqrt(x)`.

use crate::function::Function;
use crate::{RatFunc, SymbolTable};

use super::{Atom, Node, Rational, Sym};

/// Output flavour.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Style {
    Text,
    Latex,
}

/// Binding strength of what is printed, to decide on parentheses.
const SUM: u8 = 0;
const PRODUCT: u8 = 1;
const POWER: u8 = 2;

struct Printer<'a> {
    table: &'a SymbolTable,
    names: &'a dyn Fn(Atom) -> String,
    style: Style,
}

impl Sym {
    /// Plain text: `-g/l*sin(q_pendulum) - b*p_mass`; `names` names the variables.
    pub fn text(&self, table: &SymbolTable, names: &dyn Fn(Atom) -> String) -> String {
        Printer {
            table,
            names,
            style: Style::Text,
        }
        .expr(self, SUM)
    }

    /// LaTeX: `-\frac{g}{l} \sin\left(q\right)`; `names` gives the variables' LaTeX.
    pub fn latex(&self, table: &SymbolTable, names: &dyn Fn(Atom) -> String) -> String {
        Printer {
            table,
            names,
            style: Style::Latex,
        }
        .expr(self, SUM)
    }
}

impl Printer<'_> {
    fn latex(&self) -> bool {
        self.style == Style::Latex
    }

    fn coefficient(&self, c: &RatFunc) -> (bool, String) {
        if self.latex() {
            c.signed_latex(self.table)
        } else {
            c.signed_text(self.table)
        }
    }

    fn parens(&self, text: String) -> String {
        if self.latex() {
            format!("\\left({text}\\right)")
        } else {
            format!("({text})")
        }
    }

    /// `expr` printed where binding strength `context` is needed.
    fn expr(&self, expr: &Sym, context: u8) -> String {
        let (text, strength) = match expr.node() {
            Node::Coefficient(c) => {
                let (negative, magnitude) = self.coefficient(c);
                let simple = !negative
                    && !has_top_level_sum(&magnitude)
                    && !magnitude.contains('/')
                    && !magnitude.contains("\\frac");
                let text = if negative {
                    format!("-{magnitude}")
                } else {
                    magnitude.clone()
                };
                let strength = if simple && !magnitude.contains('*') && !magnitude.contains(' ') {
                    u8::MAX
                } else if negative || has_top_level_sum(&magnitude) {
                    SUM
                } else {
                    PRODUCT
                };
                (text, strength)
            }
            Node::Atom(a) => ((self.names)(*a), u8::MAX),
            Node::Sum(constant, terms) => (self.sum(constant, terms), SUM),
            Node::Product(factors) => {
                let text = self.term("1", factors);
                (text, PRODUCT)
            }
            Node::Power(base, exponent) => {
                let text = if self.latex() {
                    format!(
                        "{}^{{{}}}",
                        self.expr(base, u8::MAX),
                        self.expr(exponent, SUM)
                    )
                } else {
                    format!(
                        "{}^{}",
                        self.expr(base, u8::MAX),
                        self.expr(exponent, u8::MAX)
                    )
                };
                (text, POWER)
            }
            Node::Call(function, args) => (self.call(*function, args), u8::MAX),
        };
        if strength < context {
            self.parens(text)
        } else {
            text
        }
    }

    fn sum(&self, constant: &RatFunc, terms: &[(Sym, RatFunc)]) -> String {
        let mut out = String::new();
        let mut push = |negative: bool, text: String| match (out.is_empty(), negative) {
            (true, false) => out.push_str(&text),
            (true, true) => {
                out.push('-');
                out.push_str(&text);
            }
            (false, false) => {
                out.push_str(" + ");
                out.push_str(&text);
            }
            (false, true) => {
                out.push_str(" - ");
                out.push_str(&text);
            }
        };
        for (term, c) in terms {
            let (negative, magnitude) = self.coefficient(c);
            let factors = match term.node() {
                Node::Product(factors) => factors.clone(),
                _ => vec![(term.clone(), Rational::integer(1))],
            };
            push(negative, self.term(&magnitude, &factors));
        }
        if !constant.is_zero() {
            let (negative, magnitude) = self.coefficient(constant);
            push(negative, magnitude);
        }
        if out.is_empty() {
            out.push('0');
        }
        out
    }

    /// `magnitude · Π factors`, numerator factors first and negative exponents below.
    fn term(&self, magnitude: &str, factors: &[(Sym, Rational)]) -> String {
        let mut numerator = Vec::new();
        let mut denominator = Vec::new();
        for (base, exponent) in factors {
            if exponent.numerator() > 0 {
                numerator.push(self.factor(base, *exponent));
            } else {
                let positive = Rational::new(-exponent.numerator(), exponent.denominator())
                    .expect("non-zero denominator");
                denominator.push(self.factor(base, positive));
            }
        }
        let separator = if self.latex() { " " } else { "*" };
        let num = numerator.join(separator);
        let den = denominator.join(separator);
        if self.latex() {
            let coefficient = if magnitude == "1" {
                String::new()
            } else if has_top_level_sum(magnitude) {
                format!("{} ", self.parens(magnitude.to_string()))
            } else {
                format!("{magnitude} ")
            };
            let body = match (num.is_empty(), den.is_empty()) {
                (_, true) if num.is_empty() => "1".to_string(),
                (_, true) => num,
                (true, false) => format!("\\frac{{1}}{{{den}}}"),
                (false, false) => format!("\\frac{{{num}}}{{{den}}}"),
            };
            if coefficient.is_empty() {
                return body;
            }
            if body == "1" {
                return magnitude.to_string();
            }
            return format!("{coefficient}{body}");
        }
        let mut text = if magnitude == "1" {
            if num.is_empty() { "1".to_string() } else { num }
        } else if let Some(rest) = magnitude.strip_prefix("1/") {
            let num = if num.is_empty() { "1".to_string() } else { num };
            if !den.is_empty() {
                // One fraction bar: `F/(r_0*c_theta)`, not `F/r_0/c_theta`.
                return format!("{num}/({rest}*{den})");
            }
            format!("{num}/{rest}")
        } else {
            let magnitude = if has_top_level_sum(magnitude) {
                format!("({magnitude})")
            } else {
                magnitude.to_string()
            };
            if num.is_empty() {
                magnitude
            } else {
                format!("{magnitude}*{num}")
            }
        };
        if !den.is_empty() {
            text.push('/');
            if denominator.len() > 1 {
                text.push_str(&format!("({den})"));
            } else {
                text.push_str(&den);
            }
        }
        text
    }

    /// `base^exponent` for a positive exponent.
    fn factor(&self, base: &Sym, exponent: Rational) -> String {
        if exponent == Rational::integer(1) {
            return self.expr(base, POWER + 1);
        }
        if exponent.numerator() == 1 && exponent.denominator() == 2 {
            return if self.latex() {
                format!("\\sqrt{{{}}}", self.expr(base, SUM))
            } else {
                format!("sqrt({})", self.expr(base, SUM))
            };
        }
        let base_text = self.expr(base, POWER + 1);
        let exponent_text = if exponent.is_integer() {
            exponent.numerator().to_string()
        } else if self.latex() {
            format!("{}/{}", exponent.numerator(), exponent.denominator())
        } else {
            format!("({}/{})", exponent.numerator(), exponent.denominator())
        };
        if self.latex() {
            format!("{base_text}^{{{exponent_text}}}")
        } else {
            format!("{base_text}^{exponent_text}")
        }
    }

    fn call(&self, function: Function, args: &[Sym]) -> String {
        let inner: Vec<String> = args.iter().map(|a| self.expr(a, SUM)).collect();
        let inner = inner.join(", ");
        if !self.latex() {
            return format!("{}({inner})", function.name());
        }
        match function {
            Function::Abs => format!("\\left|{inner}\\right|"),
            Function::Sign => format!("\\operatorname{{sign}}\\left({inner}\\right)"),
            Function::Sqrt => format!("\\sqrt{{{inner}}}"),
            Function::Atan => format!("\\arctan\\left({inner}\\right)"),
            _ => format!("\\{}\\left({inner}\\right)", function.name()),
        }
    }
}

/// Whether `text` has a `+` or `-` outside parentheses (after its first character).
fn has_top_level_sum(text: &str) -> bool {
    let mut depth = 0i32;
    for (i, c) in text.char_indices() {
        match c {
            '(' | '{' => depth += 1,
            ')' | '}' => depth -= 1,
            '+' | '-' if depth == 0 && i > 0 => return true,
            _ => {}
        }
    }
    false
}
