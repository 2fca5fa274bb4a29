//! Expressions, as users write them in model files: `1/k_ge`, `A*P_s`, `m_ct + m_ge`,
//! `m*g*l*sin(q_pendulum)`, `c_d*sign(effort)*sqrt(abs(effort))`.
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
//! power   := atom ('^' exponent)?
//! exponent := '-'? integer | '(' '-'? integer ')'           (an integer power)
//!           | ('-' | '+')* atom                             (a real power: x^1.5, x^(1/3), x^n)
//! atom    := number | identifier | function '(' expr (',' expr)* ')' | '(' expr ')'
//! function := sin | cos | tan | exp | ln | sqrt | abs | sign | tanh | atan | min | max
//! number  := digits ('.' digits?)? (('e' | 'E') ('+' | '-')? digits)?  |  '.' digits ...
//! identifier := name ('.' name)*                          (front.k_s: a sub-model's k_s)
//! name    := [A-Za-z_][A-Za-z0-9_]*
//! ```
//!
//! `^` binds tighter than unary minus (`-a^2` is `-(a^2)`); an exponent that is an integer
//! literal stays an integer power ([`ExprKind::Pow`], exact rational algebra), any other
//! exponent is a real power ([`ExprKind::RealPow`]). Numbers are kept as their literal text
//! so they can be turned into exact fractions (`0.5` is exactly 1/2). A function name that
//! is not one of the [`Function`]s, or a call with the wrong number of arguments, is an error
//! at its own place, with a suggestion for a near miss (`sn` for `sin`, `log` for `ln`).

use crate::source::Span;

pub use crate::symbolic::function::{Function, sign};

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
    /// `a ^ b` with any other exponent (`x^1.5`, `x^(1/3)`, `x^n`): a real power.
    RealPow(Box<Expr>, Box<Expr>),
    /// A function applied to its arguments: `sin(q)`, `max(a, b)`.
    Call(Function, Vec<Expr>),
}

/// Names people write for a function under another name.
const FUNCTION_ALIASES: [(&str, &str); 7] = [
    ("log", "ln"),
    ("sgn", "sign"),
    ("signum", "sign"),
    ("arctan", "atan"),
    ("fabs", "abs"),
    ("minimum", "min"),
    ("maximum", "max"),
];

/// Why an expression could not be parsed, and where (relative to the expression's start).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExprError {
    /// One sentence: what was expected and what was found.
    pub message: String,
    /// Byte range in the expression text.
    pub span: Span,
}

impl ExprError {
    fn new(message: impl Into<String>, span: Span) -> Self {
        Self {
            message: message.into(),
            span,
        }
    }
}

impl std::fmt::Display for ExprError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ExprError {}

/// Parses `text` by the grammar in the [module documentation](self).
///
/// Spans in the tree and in the error are byte offsets into `text`. Whitespace may appear
/// between any two tokens; an empty or all-blank text is an error.
pub fn parse(text: &str) -> Result<Expr, ExprError> {
    let tokens = lex(text)?;
    if tokens.len() > MAX_TOKENS {
        return Err(ExprError::new(
            format!("the expression is too long (more than {MAX_TOKENS} tokens)"),
            Span::new(0, text.len()),
        ));
    }
    let mut parser = Parser {
        tokens,
        pos: 0,
        end: text.len(),
    };
    if parser.peek().is_none() {
        return Err(ExprError::new(
            "the expression is empty; expected a number, a symbol or '('",
            Span::new(0, text.len()),
        ));
    }
    let (expr, _) = parser.expr(0)?;
    match parser.peek() {
        None => Ok(expr),
        Some(token) if token.kind == Tok::RParen => {
            Err(ExprError::new("unexpected ')'", token.span))
        }
        Some(token)
            if token.kind == Tok::Caret
                && matches!(expr.kind, ExprKind::Pow(..) | ExprKind::RealPow(..)) =>
        {
            Err(ExprError::new(
                "a power cannot be raised to another power directly; use parentheses, as in (a^2)^3",
                token.span,
            ))
        }
        Some(token) => Err(ExprError::new(
            format!(
                "expected an operator or the end of the expression, found {}",
                token.describe()
            ),
            token.span,
        )),
    }
}

impl Expr {
    /// The symbols the expression names, in order of appearance, with repeats, each with
    /// its span.
    pub fn symbols(&self) -> Vec<(&str, Span)> {
        let mut out = Vec::new();
        self.collect_symbols(&mut out);
        out
    }

    fn collect_symbols<'a>(&'a self, out: &mut Vec<(&'a str, Span)>) {
        match &self.kind {
            ExprKind::Number(_) => {}
            ExprKind::Symbol(name) => out.push((name, self.span)),
            ExprKind::Neg(a) | ExprKind::Pow(a, _) => a.collect_symbols(out),
            ExprKind::Add(a, b)
            | ExprKind::Sub(a, b)
            | ExprKind::Mul(a, b)
            | ExprKind::Div(a, b)
            | ExprKind::RealPow(a, b) => {
                a.collect_symbols(out);
                b.collect_symbols(out);
            }
            ExprKind::Call(_, args) => {
                for arg in args {
                    arg.collect_symbols(out);
                }
            }
        }
    }

    /// Whether the expression calls a function or raises to a real power anywhere: such an
    /// expression is never a rational function of its symbols.
    pub fn is_transcendental(&self) -> bool {
        match &self.kind {
            ExprKind::Number(_) | ExprKind::Symbol(_) => false,
            ExprKind::Call(..) | ExprKind::RealPow(..) => true,
            ExprKind::Neg(a) | ExprKind::Pow(a, _) => a.is_transcendental(),
            ExprKind::Add(a, b)
            | ExprKind::Sub(a, b)
            | ExprKind::Mul(a, b)
            | ExprKind::Div(a, b) => a.is_transcendental() || b.is_transcendental(),
        }
    }

    /// Evaluates the expression in floating point, looking symbols up with `lookup`.
    ///
    /// Arithmetic follows `f64` (so `1/0` is infinite and `0/0` is NaN). A symbol that
    /// `lookup` does not know gives `Err((name, span))` for the first such symbol.
    pub fn eval(&self, lookup: &dyn Fn(&str) -> Option<f64>) -> Result<f64, (String, Span)> {
        Ok(match &self.kind {
            ExprKind::Number(text) => text.parse::<f64>().map_err(|_| (text.clone(), self.span))?,
            ExprKind::Symbol(name) => lookup(name).ok_or_else(|| (name.clone(), self.span))?,
            ExprKind::Neg(a) => -a.eval(lookup)?,
            ExprKind::Add(a, b) => a.eval(lookup)? + b.eval(lookup)?,
            ExprKind::Sub(a, b) => a.eval(lookup)? - b.eval(lookup)?,
            ExprKind::Mul(a, b) => a.eval(lookup)? * b.eval(lookup)?,
            ExprKind::Div(a, b) => a.eval(lookup)? / b.eval(lookup)?,
            ExprKind::Pow(a, n) => a.eval(lookup)?.powi(*n),
            ExprKind::RealPow(a, b) => a.eval(lookup)?.powf(b.eval(lookup)?),
            ExprKind::Call(function, args) => {
                let values = args
                    .iter()
                    .map(|a| a.eval(lookup))
                    .collect::<Result<Vec<_>, _>>()?;
                function.apply(&values)
            }
        })
    }
}

/// The message for a call of an unknown function, with the function meant where it is
/// close to one (by spelling, or by another common name).
fn unknown_function(name: &str) -> String {
    let alias = FUNCTION_ALIASES
        .iter()
        .find(|(alias, _)| alias.eq_ignore_ascii_case(name))
        .map(|(_, meant)| *meant);
    let meant =
        alias.or_else(|| crate::diagnostics::suggest(name, Function::ALL.iter().map(|f| f.name())));
    let known: Vec<&str> = Function::ALL.iter().map(|f| f.name()).collect();
    match meant {
        Some(meant) => format!("unknown function '{name}'; did you mean '{meant}'?"),
        None => format!(
            "unknown function '{name}'; the functions are {} (for a product write {name}*(...))",
            known.join(", ")
        ),
    }
}

/// Deepest nesting of parentheses and unary operators accepted, so that a hostile
/// expression cannot overflow the stack.
const MAX_DEPTH: usize = 200;

/// Longest expression accepted, in tokens: the tree of a long sum is as deep as the sum
/// is long, and walking or dropping it recurses.
const MAX_TOKENS: usize = 4096;

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Number(String),
    Ident(String),
    Plus,
    Minus,
    Star,
    Slash,
    Caret,
    LParen,
    RParen,
    Comma,
}

#[derive(Clone, Debug)]
struct Token {
    kind: Tok,
    span: Span,
}

impl Token {
    fn describe(&self) -> String {
        match &self.kind {
            Tok::Number(text) | Tok::Ident(text) => format!("'{text}'"),
            Tok::Plus => "'+'".into(),
            Tok::Minus => "'-'".into(),
            Tok::Star => "'*'".into(),
            Tok::Slash => "'/'".into(),
            Tok::Caret => "'^'".into(),
            Tok::LParen => "'('".into(),
            Tok::RParen => "')'".into(),
            Tok::Comma => "','".into(),
        }
    }
}

fn describe(token: Option<&Token>) -> String {
    token.map_or_else(|| "end of expression".to_string(), Token::describe)
}

fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let start = i;
        let c = bytes[i];
        let kind = match c {
            b' ' | b'\t' | b'\n' | b'\r' => {
                i += 1;
                continue;
            }
            b'+' => Tok::Plus,
            b'-' => Tok::Minus,
            b'*' => Tok::Star,
            b'/' => Tok::Slash,
            b'^' => Tok::Caret,
            b'(' => Tok::LParen,
            b')' => Tok::RParen,
            b',' => Tok::Comma,
            b'0'..=b'9' => {
                i = lex_number(text, start)?;
                tokens.push(Token {
                    kind: Tok::Number(text[start..i].to_string()),
                    span: Span::new(start, i),
                });
                continue;
            }
            b'.' if bytes.get(i + 1).is_some_and(u8::is_ascii_digit) => {
                i = lex_number(text, start)?;
                tokens.push(Token {
                    kind: Tok::Number(text[start..i].to_string()),
                    span: Span::new(start, i),
                });
                continue;
            }
            b'A'..=b'Z' | b'a'..=b'z' | b'_' => {
                i = identifier_end(bytes, i);
                tokens.push(Token {
                    kind: Tok::Ident(text[start..i].to_string()),
                    span: Span::new(start, i),
                });
                continue;
            }
            _ => {
                // `start` is always on a character boundary: every arm above consumes
                // whole ASCII characters.
                let ch = text[start..].chars().next().unwrap_or('?');
                return Err(ExprError::new(
                    format!("unexpected character '{}'", ch.escape_debug()),
                    Span::new(start, start + ch.len_utf8()),
                ));
            }
        };
        i += 1;
        tokens.push(Token {
            kind,
            span: Span::new(start, i),
        });
    }
    Ok(tokens)
}

/// The end of the identifier starting at `start`: names joined by `.` (`front.k_s`, the
/// parameter `k_s` of sub-model `front`), each a letter or `_` and then letters, digits and
/// `_`. A `.` not followed by a letter or `_` ends the identifier.
fn identifier_end(bytes: &[u8], start: usize) -> usize {
    let name_char = |b: &u8| b.is_ascii_alphanumeric() || *b == b'_';
    let mut i = start;
    loop {
        while bytes.get(i).is_some_and(name_char) {
            i += 1;
        }
        let next_starts_a_name = bytes
            .get(i + 1)
            .is_some_and(|b| b.is_ascii_alphabetic() || *b == b'_');
        if bytes.get(i) == Some(&b'.') && next_starts_a_name {
            i += 1;
        } else {
            return i;
        }
    }
}

/// `text` with each symbol `rename` gives a new name for replaced by it, everything else
/// (numbers, operators, spacing, function names) kept as written. A function's name is
/// not a symbol, so a call `sin(...)` is never renamed. Text that does not lex is returned
/// unchanged: the composer of sub-models renames expressions that were already checked.
///
/// ```
/// use bondgraph_core::expr::rename_symbols;
/// let renamed = rename_symbols("k_s*sin(q_spring) + 2", |name| match name {
///     "k_s" => Some("(2*k)".into()),
///     "q_spring" => Some("front.q_spring".into()),
///     _ => None,
/// });
/// assert_eq!(renamed, "(2*k)*sin(front.q_spring) + 2");
/// ```
pub fn rename_symbols(text: &str, rename: impl Fn(&str) -> Option<String>) -> String {
    let Ok(tokens) = lex(text) else {
        return text.to_string();
    };
    let mut out = String::with_capacity(text.len());
    let mut copied = 0;
    for (index, token) in tokens.iter().enumerate() {
        let Tok::Ident(name) = &token.kind else {
            continue;
        };
        let is_call = tokens
            .get(index + 1)
            .is_some_and(|next| next.kind == Tok::LParen);
        if is_call {
            continue;
        }
        if let Some(new_name) = rename(name) {
            out.push_str(&text[copied..token.span.start]);
            out.push_str(&new_name);
            copied = token.span.end;
        }
    }
    out.push_str(&text[copied..]);
    out
}

/// Scans a number literal starting at `start`; returns the end offset.
fn lex_number(text: &str, start: usize) -> Result<usize, ExprError> {
    let bytes = text.as_bytes();
    let digits = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    let mut i = digits(start);
    if bytes.get(i) == Some(&b'.') {
        i = digits(i + 1);
    }
    if matches!(bytes.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        let end = digits(j);
        if end == j {
            return Err(ExprError::new(
                format!(
                    "expected digits in the exponent of the number '{}'",
                    &text[start..j]
                ),
                Span::new(start, j),
            ));
        }
        i = end;
    }
    Ok(i)
}

struct Parser {
    tokens: Vec<Token>,
    pos: usize,
    /// Length of the text, for the position of "end of expression".
    end: usize,
}

/// A parsed node and the span of its text including any parentheses around it.
type Parsed = (Expr, Span);

impl Parser {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn peek_kind(&self) -> Option<&Tok> {
        self.peek().map(|t| &t.kind)
    }

    fn bump(&mut self) -> Option<Token> {
        let token = self.tokens.get(self.pos).cloned();
        if token.is_some() {
            self.pos += 1;
        }
        token
    }

    /// The span of the next token, or an empty span at the end of the text.
    fn here(&self) -> Span {
        self.peek()
            .map_or(Span::new(self.end, self.end), |t| t.span)
    }

    fn expected_operand(&self, after: Option<&Token>) -> ExprError {
        let found = describe(self.peek());
        let message = match after {
            Some(op) => format!("expected an operand after {}, found {found}", op.describe()),
            None => format!("expected an operand, found {found}"),
        };
        ExprError::new(message, self.here())
    }

    fn expr(&mut self, depth: usize) -> Result<Parsed, ExprError> {
        let (mut left, mut outer) = self.term(depth, None)?;
        while let Some(Tok::Plus | Tok::Minus) = self.peek_kind() {
            let Some(op) = self.bump() else { break };
            let (right, right_outer) = self.term(depth, Some(&op))?;
            let span = Span::new(outer.start, right_outer.end);
            let kind = if op.kind == Tok::Plus {
                ExprKind::Add(Box::new(left), Box::new(right))
            } else {
                ExprKind::Sub(Box::new(left), Box::new(right))
            };
            left = Expr { kind, span };
            outer = span;
        }
        Ok((left, outer))
    }

    fn term(&mut self, depth: usize, after: Option<&Token>) -> Result<Parsed, ExprError> {
        let (mut left, mut outer) = self.unary(depth, after)?;
        while let Some(Tok::Star | Tok::Slash) = self.peek_kind() {
            let Some(op) = self.bump() else { break };
            let (right, right_outer) = self.unary(depth, Some(&op))?;
            let span = Span::new(outer.start, right_outer.end);
            let kind = if op.kind == Tok::Star {
                ExprKind::Mul(Box::new(left), Box::new(right))
            } else {
                ExprKind::Div(Box::new(left), Box::new(right))
            };
            left = Expr { kind, span };
            outer = span;
        }
        Ok((left, outer))
    }

    fn unary(&mut self, depth: usize, after: Option<&Token>) -> Result<Parsed, ExprError> {
        if depth > MAX_DEPTH {
            return Err(ExprError::new(
                "the expression is nested too deeply",
                self.here(),
            ));
        }
        match self.peek_kind() {
            Some(Tok::Minus | Tok::Plus) => {
                let Some(op) = self.bump() else {
                    return Err(self.expected_operand(after));
                };
                let (operand, operand_outer) = self.unary(depth + 1, Some(&op))?;
                let span = Span::new(op.span.start, operand_outer.end);
                if op.kind == Tok::Plus {
                    // Unary plus changes nothing; keep the operand's node but cover the '+'.
                    return Ok((operand, span));
                }
                Ok((
                    Expr {
                        kind: ExprKind::Neg(Box::new(operand)),
                        span,
                    },
                    span,
                ))
            }
            _ => self.power(depth, after),
        }
    }

    fn power(&mut self, depth: usize, after: Option<&Token>) -> Result<Parsed, ExprError> {
        let (base, base_outer) = self.atom(depth, after)?;
        if self.peek_kind() != Some(&Tok::Caret) {
            return Ok((base, base_outer));
        }
        let Some(caret) = self.bump() else {
            return Ok((base, base_outer));
        };
        if !self.integer_exponent_ahead()
            && matches!(
                self.peek_kind(),
                Some(Tok::Number(_) | Tok::Ident(_) | Tok::LParen | Tok::Minus | Tok::Plus)
            )
        {
            let (exponent, exponent_outer) = self.exponent_operand(depth + 1, &caret)?;
            let span = Span::new(base_outer.start, exponent_outer.end);
            return Ok((
                Expr {
                    kind: ExprKind::RealPow(Box::new(base), Box::new(exponent)),
                    span,
                },
                span,
            ));
        }
        let (exponent, exponent_end) = self.exponent(&caret)?;
        let span = Span::new(base_outer.start, exponent_end);
        Ok((
            Expr {
                kind: ExprKind::Pow(Box::new(base), exponent),
                span,
            },
            span,
        ))
    }

    /// Whether the tokens after a `^` are an integer exponent: `n`, `-n`, `(n)` or `(-n)`.
    fn integer_exponent_ahead(&self) -> bool {
        let kinds: Vec<&Tok> = self.tokens[self.pos..]
            .iter()
            .take(4)
            .map(|t| &t.kind)
            .collect();
        let integer = |t: Option<&&Tok>| matches!(t, Some(Tok::Number(text)) if text.bytes().all(|b| b.is_ascii_digit()));
        match kinds.first() {
            Some(Tok::Minus) => integer(kinds.get(1)),
            Some(Tok::LParen) => match kinds.get(1) {
                Some(Tok::Minus) => integer(kinds.get(2)) && kinds.get(3) == Some(&&Tok::RParen),
                _ => integer(kinds.get(1)) && kinds.get(2) == Some(&&Tok::RParen),
            },
            _ => integer(kinds.first()),
        }
    }

    /// The exponent of a real power: signs, then an atom (`x^-a`, `x^(1/3)`, `x^1.5`).
    fn exponent_operand(&mut self, depth: usize, after: &Token) -> Result<Parsed, ExprError> {
        if depth > MAX_DEPTH {
            return Err(ExprError::new(
                "the expression is nested too deeply",
                self.here(),
            ));
        }
        match self.peek_kind() {
            Some(Tok::Minus | Tok::Plus) => {
                let Some(op) = self.bump() else {
                    return Err(self.expected_operand(Some(after)));
                };
                let (operand, operand_outer) = self.exponent_operand(depth + 1, &op)?;
                let span = Span::new(op.span.start, operand_outer.end);
                if op.kind == Tok::Plus {
                    return Ok((operand, span));
                }
                Ok((
                    Expr {
                        kind: ExprKind::Neg(Box::new(operand)),
                        span,
                    },
                    span,
                ))
            }
            _ => self.atom(depth, Some(after)),
        }
    }

    /// `name(args)` after the name; `name` is the identifier token.
    fn call(&mut self, depth: usize, name: &Token, text: &str) -> Result<Parsed, ExprError> {
        let Some(function) = Function::from_name(text) else {
            return Err(ExprError::new(unknown_function(text), name.span));
        };
        if depth >= MAX_DEPTH {
            return Err(ExprError::new(
                "the expression is nested too deeply",
                name.span,
            ));
        }
        let Some(open) = self.bump() else {
            return Err(self.expected_operand(Some(name)));
        };
        let mut args = Vec::new();
        loop {
            if matches!(self.peek_kind(), Some(Tok::RParen | Tok::Comma) | None) {
                let after = if args.is_empty() {
                    open.clone()
                } else {
                    self.tokens[self.pos - 1].clone()
                };
                return Err(self.expected_operand(Some(&after)));
            }
            let (arg, _) = self.expr(depth + 1)?;
            args.push(arg);
            match self.peek() {
                Some(t) if t.kind == Tok::Comma => self.pos += 1,
                Some(t) if t.kind == Tok::RParen => break,
                other => {
                    return Err(ExprError::new(
                        format!(
                            "expected ',' or ')' in the arguments of {}, found {}",
                            function.name(),
                            describe(other)
                        ),
                        self.here(),
                    ));
                }
            }
        }
        let close = self.bump().expect("peeked ')'");
        let span = Span::new(name.span.start, close.span.end);
        let arity_ok = if function.is_variadic() {
            args.len() >= 2
        } else {
            args.len() == 1
        };
        if !arity_ok {
            let wanted = if function.is_variadic() {
                "two or more arguments"
            } else {
                "one argument"
            };
            return Err(ExprError::new(
                format!("{}() takes {wanted}, found {}", function.name(), args.len()),
                span,
            ));
        }
        Ok((
            Expr {
                kind: ExprKind::Call(function, args),
                span,
            },
            span,
        ))
    }

    /// `'-'? integer | '(' '-'? integer ')'` after `caret`; returns the exponent and the
    /// end offset of its text.
    fn exponent(&mut self, caret: &Token) -> Result<(i32, usize), ExprError> {
        let open = if self.peek_kind() == Some(&Tok::LParen) {
            self.bump()
        } else {
            None
        };
        let minus = if self.peek_kind() == Some(&Tok::Minus) {
            self.bump()
        } else {
            None
        };
        let Some(token) = self.bump() else {
            let after = minus.as_ref().or(open.as_ref()).unwrap_or(caret);
            return Err(ExprError::new(
                format!(
                    "expected an exponent after {}, found end of expression",
                    after.describe()
                ),
                Span::new(self.end, self.end),
            ));
        };
        let digits = match &token.kind {
            Tok::Number(text) if text.bytes().all(|b| b.is_ascii_digit()) => text.clone(),
            Tok::Number(_) | Tok::Ident(_) | Tok::LParen => {
                let span = self.exponent_extent(&token, open.is_some());
                return Err(ExprError::new("exponent must be an integer", span));
            }
            _ => {
                let after = minus.as_ref().or(open.as_ref()).unwrap_or(caret);
                return Err(ExprError::new(
                    format!(
                        "expected an exponent after {}, found {}",
                        after.describe(),
                        token.describe()
                    ),
                    token.span,
                ));
            }
        };
        let start = minus.as_ref().map_or(token.span.start, |m| m.span.start);
        let signed = if minus.is_some() {
            format!("-{digits}")
        } else {
            digits
        };
        let Ok(value) = signed.parse::<i32>() else {
            return Err(ExprError::new(
                format!("exponent {signed} is too large"),
                Span::new(start, token.span.end),
            ));
        };
        let mut end = token.span.end;
        if open.is_some() {
            match self.bump() {
                Some(close) if close.kind == Tok::RParen => end = close.span.end,
                Some(_) => {
                    // More than an integer inside the parentheses, as in `a^(2*n)`.
                    let mut end = token.span.end;
                    let mut level = 0_usize;
                    for inner in &self.tokens[self.pos - 1..] {
                        match inner.kind {
                            Tok::LParen => level += 1,
                            Tok::RParen if level == 0 => break,
                            Tok::RParen => level -= 1,
                            _ => {}
                        }
                        end = inner.span.end;
                    }
                    return Err(ExprError::new(
                        "exponent must be an integer",
                        Span::new(start, end),
                    ));
                }
                other => {
                    let span = other
                        .as_ref()
                        .map_or(Span::new(self.end, self.end), |t| t.span);
                    return Err(ExprError::new(
                        format!(
                            "expected ')' to close the exponent's '(', found {}",
                            describe(other.as_ref())
                        ),
                        span,
                    ));
                }
            }
        }
        Ok((value, end))
    }

    /// The span of a non-integer exponent that starts with `first` (already taken): one
    /// token, a whole parenthesised group, or everything up to the ')' that closes the
    /// exponent's own '('.
    fn exponent_extent(&self, first: &Token, parenthesised: bool) -> Span {
        let mut level: usize = match first.kind {
            Tok::LParen => 1,
            _ if parenthesised => 0,
            _ => return first.span,
        };
        let mut end = first.span.end;
        for token in &self.tokens[self.pos..] {
            match token.kind {
                Tok::LParen => level += 1,
                Tok::RParen if level == 0 => break,
                Tok::RParen => {
                    level -= 1;
                    if level == 0 && !parenthesised {
                        end = token.span.end;
                        break;
                    }
                }
                _ => {}
            }
            end = token.span.end;
        }
        Span::new(first.span.start, end)
    }

    fn atom(&mut self, depth: usize, after: Option<&Token>) -> Result<Parsed, ExprError> {
        let Some(token) = self.peek().cloned() else {
            return Err(self.expected_operand(after));
        };
        match token.kind {
            Tok::Number(text) => {
                self.pos += 1;
                let expr = Expr {
                    kind: ExprKind::Number(text),
                    span: token.span,
                };
                Ok((expr, token.span))
            }
            Tok::Ident(ref text)
                if self.tokens.get(self.pos + 1).map(|t| &t.kind) == Some(&Tok::LParen) =>
            {
                self.pos += 1;
                let text = text.clone();
                self.call(depth, &token, &text)
            }
            Tok::Ident(name) => {
                self.pos += 1;
                let expr = Expr {
                    kind: ExprKind::Symbol(name),
                    span: token.span,
                };
                Ok((expr, token.span))
            }
            Tok::LParen => {
                self.pos += 1;
                if depth >= MAX_DEPTH {
                    return Err(ExprError::new(
                        "the expression is nested too deeply",
                        token.span,
                    ));
                }
                let open = token;
                let (inner, _) = match self.peek_kind() {
                    Some(Tok::RParen) | None => return Err(self.expected_operand(Some(&open))),
                    _ => self.expr(depth + 1)?,
                };
                match self.peek() {
                    Some(close) if close.kind == Tok::RParen => {
                        let end = close.span.end;
                        self.pos += 1;
                        Ok((inner, Span::new(open.span.start, end)))
                    }
                    other => Err(ExprError::new(
                        format!("expected ')' to close '(', found {}", describe(other)),
                        self.here(),
                    )),
                }
            }
            _ => Err(self.expected_operand(after)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tree in prefix form, to compare shapes compactly.
    fn tree(expr: &Expr) -> String {
        match &expr.kind {
            ExprKind::Number(text) => text.clone(),
            ExprKind::Symbol(name) => name.clone(),
            ExprKind::Neg(a) => format!("(neg {})", tree(a)),
            ExprKind::Add(a, b) => format!("(+ {} {})", tree(a), tree(b)),
            ExprKind::Sub(a, b) => format!("(- {} {})", tree(a), tree(b)),
            ExprKind::Mul(a, b) => format!("(* {} {})", tree(a), tree(b)),
            ExprKind::Div(a, b) => format!("(/ {} {})", tree(a), tree(b)),
            ExprKind::Pow(a, n) => format!("(^ {} {n})", tree(a)),
            ExprKind::RealPow(a, b) => format!("(^r {} {})", tree(a), tree(b)),
            ExprKind::Call(f, args) => format!(
                "({} {})",
                f.name(),
                args.iter().map(tree).collect::<Vec<_>>().join(" ")
            ),
        }
    }

    fn shape(text: &str) -> String {
        match parse(text) {
            Ok(expr) => tree(&expr),
            Err(e) => panic!("{text:?} did not parse: {e:?}"),
        }
    }

    fn error(text: &str) -> (String, (usize, usize)) {
        match parse(text) {
            Ok(expr) => panic!("{text:?} parsed as {}", tree(&expr)),
            Err(e) => (e.message, (e.span.start, e.span.end)),
        }
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(shape("a+b*c"), "(+ a (* b c))");
        assert_eq!(shape("a*b+c"), "(+ (* a b) c)");
        assert_eq!(shape("-a^2"), "(neg (^ a 2))");
        assert_eq!(shape("a/b/c"), "(/ (/ a b) c)");
        assert_eq!(shape("a-b-c"), "(- (- a b) c)");
        assert_eq!(shape("a-b+c"), "(+ (- a b) c)");
        assert_eq!(shape("2^-1"), "(^ 2 -1)");
        assert_eq!(shape("a^(-2)"), "(^ a -2)");
        assert_eq!(shape("a^( 3 )"), "(^ a 3)");
        assert_eq!(shape("-a*b"), "(* (neg a) b)");
        assert_eq!(shape("a*-b"), "(* a (neg b))");
        assert_eq!(shape("--a"), "(neg (neg a))");
        assert_eq!(shape("+a"), "a");
        assert_eq!(shape("(a+b)*c"), "(* (+ a b) c)");
        assert_eq!(shape("(a*b)^2"), "(^ (* a b) 2)");
        assert_eq!(shape("1/k_ge"), "(/ 1 k_ge)");
        assert_eq!(shape("A*P_s"), "(* A P_s)");
        assert_eq!(shape("m_ct + m_ge"), "(+ m_ct m_ge)");
    }

    #[test]
    fn number_literals_are_kept_as_written() {
        assert_eq!(shape("2"), "2");
        assert_eq!(shape("0.5"), "0.5");
        assert_eq!(shape("1e-3"), "1e-3");
        assert_eq!(shape("5.E4"), "5.E4");
        assert_eq!(shape("5."), "5.");
        assert_eq!(shape(".25e+2"), ".25e+2");
    }

    #[test]
    fn whitespace_is_allowed_between_all_tokens() {
        assert_eq!(shape(" \t( a\n+ b ) ^ - 2 / c "), "(/ (^ (+ a b) -2) c)");
    }

    #[test]
    fn node_spans_cover_their_text_including_inner_parentheses() {
        let expr = parse(" (a+b)*c ").unwrap();
        assert_eq!(expr.span, Span::new(1, 8));
        let ExprKind::Mul(left, right) = &expr.kind else {
            panic!("not a product");
        };
        // A parenthesised node's own span is the text inside the parentheses.
        assert_eq!(left.span, Span::new(2, 5));
        assert_eq!(right.span, Span::new(7, 8));
        assert_eq!(parse("-a^2").unwrap().span, Span::new(0, 4));
        assert_eq!(parse("a^(-2)").unwrap().span, Span::new(0, 6));
    }

    #[test]
    fn symbols_in_order_with_repeats_and_spans() {
        let expr = parse("  k_1 * (m+ k_1)^2 / 3").unwrap();
        assert_eq!(
            expr.symbols(),
            vec![
                ("k_1", Span::new(2, 5)),
                ("m", Span::new(9, 10)),
                ("k_1", Span::new(12, 15)),
            ]
        );
        assert!(parse("2*3").unwrap().symbols().is_empty());
    }

    #[test]
    fn eval_uses_f64_semantics() {
        let lookup = |name: &str| match name {
            "m" => Some(2.0),
            "k" => Some(8.0),
            "zero" => Some(0.0),
            _ => None,
        };
        let eval = |text: &str| parse(text).unwrap().eval(&lookup);
        assert_eq!(eval("2*m + k/2"), Ok(8.0));
        assert_eq!(eval("-m^2"), Ok(-4.0));
        assert_eq!(eval("2^-1"), Ok(0.5));
        assert_eq!(eval("k^(-2)"), Ok(1.0 / 64.0));
        assert_eq!(eval("5.E4 + .5 + 1e-3 + 5."), Ok(50_005.501));
        assert_eq!(eval("1/zero"), Ok(f64::INFINITY));
        assert!(eval("zero/zero").unwrap().is_nan());
        assert_eq!(eval("m + x*y"), Err(("x".to_string(), Span::new(4, 5))));
    }

    #[test]
    fn empty_expressions_are_errors() {
        let message = "the expression is empty; expected a number, a symbol or '('".to_string();
        assert_eq!(error(""), (message.clone(), (0, 0)));
        assert_eq!(error(" \t "), (message, (0, 3)));
    }

    #[test]
    fn missing_operands() {
        assert_eq!(
            error("a *"),
            (
                "expected an operand after '*', found end of expression".into(),
                (3, 3)
            )
        );
        assert_eq!(
            error("a + )"),
            ("expected an operand after '+', found ')'".into(), (4, 5))
        );
        assert_eq!(
            error("*a"),
            ("expected an operand, found '*'".into(), (0, 1))
        );
        assert_eq!(
            error("a*/b"),
            ("expected an operand after '*', found '/'".into(), (2, 3))
        );
        assert_eq!(
            error("-"),
            (
                "expected an operand after '-', found end of expression".into(),
                (1, 1)
            )
        );
        assert_eq!(
            error("( )"),
            ("expected an operand after '(', found ')'".into(), (2, 3))
        );
    }

    #[test]
    fn unbalanced_parentheses() {
        assert_eq!(error("a)"), ("unexpected ')'".into(), (1, 2)));
        assert_eq!(error("(a))"), ("unexpected ')'".into(), (3, 4)));
        assert_eq!(
            error("(a + b"),
            (
                "expected ')' to close '(', found end of expression".into(),
                (6, 6)
            )
        );
        assert_eq!(
            error("(a b)"),
            ("expected ')' to close '(', found 'b'".into(), (3, 4))
        );
    }

    #[test]
    fn missing_operators() {
        assert_eq!(
            error("a b"),
            (
                "expected an operator or the end of the expression, found 'b'".into(),
                (2, 3)
            )
        );
        assert_eq!(
            error("2x"),
            (
                "expected an operator or the end of the expression, found 'x'".into(),
                (1, 2)
            )
        );
        assert_eq!(
            error("(a) (b)"),
            (
                "expected an operator or the end of the expression, found '('".into(),
                (4, 5)
            )
        );
        assert_eq!(
            error("a (b)").0,
            "unknown function 'a'; the functions are sin, cos, tan, exp, ln, sqrt, abs, sign, tanh, atan, min, max (for a product write a*(...))"
        );
    }

    #[test]
    fn integer_literal_exponents_are_integer_powers_and_others_real_powers() {
        assert_eq!(shape("a^b"), "(^r a b)");
        assert_eq!(shape("a^2.5"), "(^r a 2.5)");
        assert_eq!(shape("a^-x"), "(^r a (neg x))");
        assert_eq!(shape("a^(x + 1)"), "(^r a (+ x 1))");
        assert_eq!(shape("a^(-x)"), "(^r a (neg x))");
        assert_eq!(shape("a^(1/3)"), "(^r a (/ 1 3))");
        assert_eq!(shape("a^-(2)"), "(^r a (neg 2))");
        assert_eq!(shape("a^1e3"), "(^r a 1e3)");
        assert_eq!(shape("-x^0.5*y"), "(* (neg (^r x 0.5)) y)");
        assert_eq!(shape("a^(-2)"), "(^ a -2)");
        assert_eq!(
            error("a^"),
            (
                "expected an exponent after '^', found end of expression".into(),
                (2, 2)
            )
        );
        assert_eq!(
            error("a^ *"),
            ("expected an exponent after '^', found '*'".into(), (3, 4))
        );
        assert_eq!(
            error("a^(-"),
            (
                "expected an operand after '-', found end of expression".into(),
                (4, 4)
            )
        );
        assert_eq!(
            error("a^(2"),
            (
                "expected ')' to close '(', found end of expression".into(),
                (4, 4)
            )
        );
        assert_eq!(
            error("a^99999999999"),
            ("exponent 99999999999 is too large".into(), (2, 13))
        );
        assert_eq!(
            error("a^2^3"),
            (
                "a power cannot be raised to another power directly; use parentheses, as in (a^2)^3"
                    .into(),
                (3, 4)
            )
        );
        assert_eq!(error("a^b^c").1, (3, 4));
    }

    #[test]
    fn function_calls() {
        assert_eq!(shape("m*g*l*sin(q)"), "(* (* (* m g) l) (sin q))");
        assert_eq!(
            shape("c*sign(effort)*sqrt(abs(effort))"),
            "(* (* c (sign effort)) (sqrt (abs effort)))"
        );
        assert_eq!(shape("max(0, v - 2*w)"), "(max 0 (- v (* 2 w)))");
        assert_eq!(shape("min(a, b, c)"), "(min a b c)");
        assert_eq!(shape("-exp(x)^2"), "(neg (^ (exp x) 2))");
        assert_eq!(shape("exp(-e/V_T)"), "(exp (/ (neg e) V_T))");
        let call = parse(" tanh( x ) ").unwrap();
        assert_eq!(call.span, Span::new(1, 10));
        assert_eq!(
            parse("2*atan(k_1*x)").unwrap().symbols(),
            vec![("k_1", Span::new(7, 10)), ("x", Span::new(11, 12))]
        );
    }

    #[test]
    fn bad_calls_are_located() {
        assert_eq!(
            error("2*sqr(x)"),
            (
                "unknown function 'sqr'; did you mean 'sqrt'?".into(),
                (2, 5)
            )
        );
        assert_eq!(
            error("log(x)"),
            ("unknown function 'log'; did you mean 'ln'?".into(), (0, 3))
        );
        assert_eq!(
            error("frobnicate(x)").0,
            "unknown function 'frobnicate'; the functions are sin, cos, tan, exp, ln, sqrt, abs, sign, tanh, atan, min, max (for a product write frobnicate*(...))"
        );
        assert_eq!(
            error("a + sin(x, y)"),
            ("sin() takes one argument, found 2".into(), (4, 13))
        );
        assert_eq!(
            error("max(x)"),
            ("max() takes two or more arguments, found 1".into(), (0, 6))
        );
        assert_eq!(
            error("sin()"),
            ("expected an operand after '(', found ')'".into(), (4, 5))
        );
        assert_eq!(
            error("min(a,)"),
            ("expected an operand after ',', found ')'".into(), (6, 7))
        );
        assert_eq!(
            error("cos(a b)"),
            (
                "expected ',' or ')' in the arguments of cos, found 'b'".into(),
                (6, 7)
            )
        );
        assert_eq!(
            error("exp(x"),
            (
                "expected ',' or ')' in the arguments of exp, found end of expression".into(),
                (5, 5)
            )
        );
    }

    #[test]
    fn functions_evaluate_in_floating_point() {
        let lookup = |name: &str| match name {
            "x" => Some(-4.0),
            _ => None,
        };
        let eval = |text: &str| parse(text).unwrap().eval(&lookup).unwrap();
        assert_eq!(eval("sqrt(abs(x))"), 2.0);
        assert_eq!(eval("sign(x)*abs(x)^0.5"), -2.0);
        assert_eq!(eval("max(x, 1, -7)"), 1.0);
        assert_eq!(eval("min(x, 1, -7)"), -7.0);
        assert_eq!(eval("sign(0)"), 0.0);
        assert_eq!(eval("ln(exp(2))"), 2.0);
        assert_eq!(eval("2^(1/2)"), 2f64.sqrt());
    }

    #[test]
    fn bad_characters_and_numbers() {
        assert_eq!(error("a $ b"), ("unexpected character '$'".into(), (2, 3)));
        // A multi-byte character is reported whole.
        assert_eq!(error("m·g"), ("unexpected character '·'".into(), (1, 3)));
        // A '.' joins names (`front.k_s`) only when a name follows it.
        assert_eq!(error("a. b"), ("unexpected character '.'".into(), (1, 2)));
        assert_eq!(
            error("a.1"),
            (
                "expected an operator or the end of the expression, found '.1'".into(),
                (1, 3)
            )
        );
        assert_eq!(
            error("2e + 1"),
            (
                "expected digits in the exponent of the number '2e'".into(),
                (0, 2)
            )
        );
        assert_eq!(
            error("1.5E-"),
            (
                "expected digits in the exponent of the number '1.5E-'".into(),
                (0, 5)
            )
        );
    }

    #[test]
    fn hostile_inputs_are_errors_not_crashes() {
        let deep = format!("{}a{}", "(".repeat(10_000), ")".repeat(10_000));
        assert_eq!(
            error(&deep).0,
            "the expression is too long (more than 4096 tokens)"
        );
        let nested = format!("{}a{}", "(".repeat(1_000), ")".repeat(1_000));
        assert_eq!(error(&nested).0, "the expression is nested too deeply");
        let negations = format!("{}a", "-".repeat(1_000));
        assert_eq!(error(&negations).0, "the expression is nested too deeply");
        let long = vec!["a"; 5_000].join("+");
        assert_eq!(
            error(&long).0,
            "the expression is too long (more than 4096 tokens)"
        );
        let ok = vec!["a"; 2_000].join("+");
        assert_eq!(parse(&ok).unwrap().symbols().len(), 2_000);
    }

    proptest::proptest! {
        #[test]
        fn any_text_parses_or_gives_an_error_inside_it(text in "[ a-c0-9.eE+\\-*/^()_$é]{0,40}") {
            match parse(&text) {
                Ok(expr) => {
                    for (name, span) in expr.symbols() {
                        proptest::prop_assert_eq!(&text[span.start..span.end], name);
                    }
                }
                Err(e) => {
                    proptest::prop_assert!(e.span.start <= e.span.end && e.span.end <= text.len());
                    proptest::prop_assert!(text.is_char_boundary(e.span.start));
                    proptest::prop_assert!(text.is_char_boundary(e.span.end));
                }
            }
        }
    }
}
