//! The functions expressions may call (`sin`, `sqrt`, `abs`, `min`, ...): their names as
//! written and their values in floating point.
//!
//! They belong to the algebra, not to the grammar that reads them: symbolic expressions
//! ([`crate::expr`]) differentiate, invert, print and evaluate calls of them, and
//! the expression reader only looks their names up.

/// The functions expressions may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Function {
    /// Sine (radians).
    Sin,
    /// Cosine (radians).
    Cos,
    /// Tangent (radians).
    Tan,
    /// The exponential.
    Exp,
    /// The natural logarithm.
    Ln,
    /// The square root.
    Sqrt,
    /// The absolute value.
    Abs,
    /// The sign: -1, 0 or 1.
    Sign,
    /// The hyperbolic tangent.
    Tanh,
    /// The arctangent (radians).
    Atan,
    /// The smallest of its arguments.
    Min,
    /// The largest of its arguments.
    Max,
}

impl Function {
    /// Every function, in the order the documentation lists them.
    pub const ALL: [Function; 12] = [
        Function::Sin,
        Function::Cos,
        Function::Tan,
        Function::Exp,
        Function::Ln,
        Function::Sqrt,
        Function::Abs,
        Function::Sign,
        Function::Tanh,
        Function::Atan,
        Function::Min,
        Function::Max,
    ];

    /// The name as written in expressions.
    pub fn name(self) -> &'static str {
        match self {
            Function::Sin => "sin",
            Function::Cos => "cos",
            Function::Tan => "tan",
            Function::Exp => "exp",
            Function::Ln => "ln",
            Function::Sqrt => "sqrt",
            Function::Abs => "abs",
            Function::Sign => "sign",
            Function::Tanh => "tanh",
            Function::Atan => "atan",
            Function::Min => "min",
            Function::Max => "max",
        }
    }

    /// The function called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// Whether it takes two or more arguments (`min`, `max`) rather than exactly one.
    pub fn is_variadic(self) -> bool {
        matches!(self, Function::Min | Function::Max)
    }

    /// The function applied to `args` in floating point.
    pub fn apply(self, args: &[f64]) -> f64 {
        let x = args.first().copied().unwrap_or(f64::NAN);
        match self {
            Function::Sin => x.sin(),
            Function::Cos => x.cos(),
            Function::Tan => x.tan(),
            Function::Exp => x.exp(),
            Function::Ln => x.ln(),
            Function::Sqrt => x.sqrt(),
            Function::Abs => x.abs(),
            Function::Sign => sign(x),
            Function::Tanh => x.tanh(),
            Function::Atan => x.atan(),
            Function::Min => args.iter().copied().fold(f64::INFINITY, f64::min),
            Function::Max => args.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

/// The sign of `x`: -1, 0 or 1 (NaN for NaN), unlike `f64::signum`, which is 1 at zero.
pub fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        x
    }
}
