//! Parameter expressions, as users write them in model files: `1/k_ge`, `A*P_s`, `m_ct + m_ge`.
//!
//! An expression is parsed once into an [`Expr`] tree that keeps, for every node, the byte
//! span inside the expression text, so that an unknown symbol is reported at its own column
//! of the model file. Turning the tree into symbolic algebra is the model validator's job;
//! this module only knows the grammar:
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/') unary)*
//! unary   := '-' unary | '+' unary | power
//! power   := atom ('^' exponent)?          exponent := '-'? integer | '(' '-'? integer ')'
//! atom    := number | identifier | '(' expr ')'
//! number  := digits ('.' digits?)? (('e' | 'E') ('+' | '-')? digits)?  |  '.' digits ...
//! identifier := [A-Za-z_][A-Za-z0-9_]*
//! ```
//!
//! `^` binds tighter than unary minus (`-a^2` is `-(a^2)`), exponents are integers, and
//! numbers are kept as their literal text so they can be turned into exact fractions
//! (`0.5` is exactly 1/2).

use crate::source::Span;

/// A parsed expression node and the span of its text (relative to the expression's start).
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// What the node is.
    pub kind: ExprKind,
    /// Byte range in the expression text.
    pub span: Span,
}

/// The kinds of expression node.
#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    /// A number literal, as written (`2`, `0.5`, `1e-3`, `5.E4`).
    Number(String),
    /// A parameter or input name.
    Symbol(String),
    /// `-x`.
    Neg(Box<Expr>),
    /// `a + b`.
    Add(Box<Expr>, Box<Expr>),
    /// `a - b`.
    Sub(Box<Expr>, Box<Expr>),
    /// `a * b`.
    Mul(Box<Expr>, Box<Expr>),
    /// `a / b`.
    Div(Box<Expr>, Box<Expr>),
    /// `a ^ n` with an integer exponent.
    Pow(Box<Expr>, i32),
}

/// Why an expression could not be parsed, and where (relative to the expression's start).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExprError {
    /// One sentence: what was expected and what was found.
    pub message: String,
    /// Byte range in the expression text.
    pub span: Span,
}
