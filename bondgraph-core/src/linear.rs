//! Sparse affine forms with symbolic coefficients: `Σ cᵢ·xᵢ + c₀`.
//!
//! Every bond effort and flow of a linear bond graph is an affine function of the states,
//! the inputs and (while elimination is under way) of other bond variables. Keeping these
//! as sparse sorted term lists makes elimination cost proportional to the number of
//! non-zero couplings, which is what lets a 2000-state chain derive in well under a second.

use std::fmt;

use crate::symbolic::RatFunc;

/// A variable that may appear in an affine form during derivation.
///
/// The declaration order is the print order: states, then inputs, then the rest, with the
/// constant term last.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Var {
    /// The `i`-th state of the equations being built.
    State(u32),
    /// The `i`-th input of the model.
    Input(u32),
    /// The time derivative of the `i`-th input: appears in the holding force of storage driven
    /// directly by an input (outputs and guards only, never in state equations).
    InputRate(u32),
    /// The effort (for an inertia) or flow (for a compliance) of the `i`-th dependent
    /// storage element, unknown until merging resolves it.
    Dependent(u32),
    /// The output of the `i`-th nonlinear law of a nonlinear mode, kept as an unknown while
    /// the linear junction structure is solved ([`crate::equations::nonlinear`]).
    Auxiliary(u32),
    /// The energy variable (momentum or displacement) of the storage element with this
    /// index, in a source's value: a linear feedback such as `Se(effort: "-K_c*q_spring")`.
    /// Only laws hold it; elimination writes it in the mode's states.
    Storage(u32),
    /// A bond variable not yet eliminated: effort of bond `b` is `2b`, flow is `2b + 1`.
    Bond(u32),
    /// The constant 1 (its coefficient is the affine offset).
    Constant,
}

/// `Σ coefficient · variable`, sorted by variable, without zero coefficients.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct LinearForm {
    terms: Vec<(Var, RatFunc)>,
}

impl LinearForm {
    /// The zero form.
    pub fn zero() -> Self {
        Self::default()
    }

    /// `coefficient · var` (zero if the coefficient is zero).
    pub fn term(var: Var, coefficient: RatFunc) -> Self {
        if coefficient.is_zero() {
            Self::zero()
        } else {
            Self {
                terms: vec![(var, coefficient)],
            }
        }
    }

    /// `1 · var`.
    pub fn var(var: Var) -> Self {
        Self::term(var, RatFunc::one())
    }

    /// The constant form `value`.
    pub fn constant(value: RatFunc) -> Self {
        Self::term(Var::Constant, value)
    }

    /// Whether every coefficient is zero.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// The non-zero terms, sorted by variable.
    pub fn terms(&self) -> &[(Var, RatFunc)] {
        &self.terms
    }

    /// The coefficient of `var` (zero when absent).
    pub fn coefficient(&self, var: Var) -> RatFunc {
        self.get(var).cloned().unwrap_or_else(RatFunc::zero)
    }

    /// The coefficient of `var`, if non-zero.
    pub fn get(&self, var: Var) -> Option<&RatFunc> {
        self.terms
            .binary_search_by(|(v, _)| v.cmp(&var))
            .ok()
            .map(|i| &self.terms[i].1)
    }

    /// Whether any variable satisfies `predicate`.
    pub fn mentions(&self, mut predicate: impl FnMut(Var) -> bool) -> bool {
        self.terms.iter().any(|(v, _)| predicate(*v))
    }

    /// `self + factor · other`.
    pub fn add_scaled(&mut self, other: &LinearForm, factor: &RatFunc) {
        if factor.is_zero() || other.is_zero() {
            return;
        }
        let mut merged = Vec::with_capacity(self.terms.len() + other.terms.len());
        let mut left = std::mem::take(&mut self.terms).into_iter().peekable();
        let mut right = other.terms.iter().peekable();
        loop {
            match (left.peek(), right.peek()) {
                (Some((lv, _)), Some((rv, _))) if lv == rv => {
                    let (var, a) = left.next().expect("peeked");
                    let (_, b) = right.next().expect("peeked");
                    let sum = a + &(b * factor);
                    if !sum.is_zero() {
                        merged.push((var, sum));
                    }
                }
                (Some((lv, _)), Some((rv, _))) if lv < rv => {
                    merged.push(left.next().expect("peeked"));
                }
                (_, Some(_)) => {
                    let (var, b) = right.next().expect("peeked");
                    merged.push((*var, b * factor));
                }
                (Some(_), None) => merged.push(left.next().expect("peeked")),
                (None, None) => break,
            }
        }
        self.terms = merged;
    }

    /// `self + other`.
    pub fn add(&mut self, other: &LinearForm) {
        self.add_scaled(other, &RatFunc::one());
    }

    /// `factor · self`.
    pub fn scaled(&self, factor: &RatFunc) -> LinearForm {
        if factor.is_zero() {
            return Self::zero();
        }
        Self {
            terms: self.terms.iter().map(|(v, c)| (*v, c * factor)).collect(),
        }
    }

    /// Removes `var` and returns its coefficient (zero if absent).
    pub fn take(&mut self, var: Var) -> RatFunc {
        match self.terms.binary_search_by(|(v, _)| v.cmp(&var)) {
            Ok(i) => self.terms.remove(i).1,
            Err(_) => RatFunc::zero(),
        }
    }

    /// Replaces every variable `v` for which `replacement(v)` is `Some(form)` by that form.
    pub fn substitute(&self, mut replacement: impl FnMut(Var) -> Option<LinearForm>) -> LinearForm {
        let mut kept = Vec::new();
        let mut replaced = Vec::new();
        for (var, coefficient) in &self.terms {
            match replacement(*var) {
                Some(form) => replaced.push((form, coefficient)),
                None => kept.push((*var, coefficient.clone())),
            }
        }
        let mut result = LinearForm { terms: kept };
        for (form, coefficient) in replaced {
            result.add_scaled(&form, coefficient);
        }
        result
    }

    /// Keeps only the terms whose variable satisfies `keep`.
    pub fn filtered(&self, mut keep: impl FnMut(Var) -> bool) -> LinearForm {
        LinearForm {
            terms: self
                .terms
                .iter()
                .filter(|(v, _)| keep(*v))
                .cloned()
                .collect(),
        }
    }
}

impl fmt::Display for Var {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Var::State(i) => write!(f, "x{i}"),
            Var::Input(i) => write!(f, "u{i}"),
            Var::InputRate(i) => write!(f, "der(u{i})"),
            Var::Dependent(i) => write!(f, "d{i}"),
            Var::Auxiliary(i) => write!(f, "w{i}"),
            Var::Storage(i) => write!(f, "x_element{i}"),
            Var::Bond(i) => write!(f, "{}{}", if i % 2 == 0 { "e" } else { "f" }, i / 2),
            Var::Constant => write!(f, "1"),
        }
    }
}
