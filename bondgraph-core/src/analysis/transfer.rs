//! Transfer functions `G(s) = Y(s)/U(s)` of one input and one output of a linear mode, as
//! exact rational functions in `s` whose coefficients are rational functions of the
//! parameters.
//!
//! With `dx/dt = A x + b u + e du/dt` and `y = c x + d u + f du/dt`, Laplace-transformed from
//! rest, `G(s) = c adj(sI - A) (b + s e) / det(sI - A) + d + s f`. The numerator and
//! denominator are built from the Faddeev–LeVerrier matrices, then put over one exact
//! canonical fraction in the parameters and `s` together, which cancels every factor they
//! share (a pole the output cannot see, a mode the input cannot reach) exactly, whatever the
//! parameter values.

use num_traits::Signed;

use super::characteristic::Characteristic;
use crate::equations::StateEquations;
use crate::linear::{LinearForm, Var};
use crate::symbolic::{Monomial, Poly, RatFunc, Scaled, Symbol, SymbolTable};

/// One input-output pair of a linear mode: the columns and rows of `A, B, E, C, D, F` it uses.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// Column of `B` of the input.
    pub b: Vec<RatFunc>,
    /// Column of `E` (the input's rate) of the input.
    pub e: Vec<RatFunc>,
    /// The output's row of `C`.
    pub c: Vec<RatFunc>,
    /// The output's entry of `D` for the input.
    pub d: RatFunc,
    /// The output's entry of `F` (the input's rate) for the input.
    pub f: RatFunc,
    /// Whether the output is the time integral of `c x + d u + f du/dt`.
    pub integral: bool,
}

impl Channel {
    /// The channel from input `input` of `equations` to the output `row` (an affine form of
    /// states, inputs and inputs' rates; other inputs' terms and the constant do not enter a
    /// transfer function).
    pub fn new(equations: &StateEquations, input: usize, row: &LinearForm, integral: bool) -> Self {
        let u = Var::Input(input as u32);
        let rate = Var::InputRate(input as u32);
        let n = equations.state_count();
        Channel {
            b: equations
                .derivatives
                .iter()
                .map(|r| r.coefficient(u))
                .collect(),
            e: equations
                .derivatives
                .iter()
                .map(|r| r.coefficient(rate))
                .collect(),
            c: (0..n)
                .map(|j| row.coefficient(Var::State(j as u32)))
                .collect(),
            d: row.coefficient(u),
            f: row.coefficient(rate),
            integral,
        }
    }

    /// The channel from input `input` to state `state`.
    pub fn to_state(equations: &StateEquations, input: usize, state: usize) -> Self {
        Self::new(
            equations,
            input,
            &LinearForm::var(Var::State(state as u32)),
            false,
        )
    }
}

/// `G(s) = N(s)/D(s)` in lowest terms.
#[derive(Clone, Debug, PartialEq)]
pub struct TransferFunction {
    /// Coefficients of `N(s)`, highest power first: polynomials in the parameters.
    pub numerator: Vec<RatFunc>,
    /// Coefficients of `D(s)`, highest power first: polynomials in the parameters with no
    /// common factor with the numerator's, the leading one with a positive leading term.
    pub denominator: Vec<RatFunc>,
    /// How many roots of `det(sI - A)` (times `s` for an integral output) cancelled against
    /// the numerator: modes the output does not see or the input does not reach.
    pub cancelled: usize,
    /// The factor that cancelled, `det(sI - A)` (times `s`) over the denominator, as
    /// coefficients highest power first (`[1]` when nothing cancelled): its roots are the
    /// eigenvalues that are not poles.
    pub cancelled_factor: Vec<RatFunc>,
}

impl TransferFunction {
    /// The transfer function of `channel`, given the characteristic polynomial and adjugate
    /// of `A` (`symbols`: the table the entries are written over).
    ///
    /// # Complexity
    /// `O(n³)` products for the numerator, then one multivariate gcd.
    pub fn new(characteristic: &Characteristic, channel: &Channel, symbols: &SymbolTable) -> Self {
        let n = characteristic.adjugate.len();
        // Lowest power first: c M_k b at s^(n-k), c M_k e at s^(n-k+1), (d + f s) det.
        let mut numerator = vec![RatFunc::zero(); n + 2];
        for (k, m) in characteristic.adjugate.iter().enumerate() {
            let power = n - (k + 1);
            numerator[power] += quadratic(&channel.c, m, &channel.b);
            numerator[power + 1] += quadratic(&channel.c, m, &channel.e);
        }
        for (power, coefficient) in characteristic.coefficients.iter().enumerate() {
            numerator[power] += &channel.d * coefficient;
            numerator[power + 1] += &channel.f * coefficient;
        }
        let mut denominator = characteristic.coefficients.clone();
        if channel.integral {
            denominator.insert(0, RatFunc::zero());
        }
        let full_degree = denominator.len() - 1;
        // Put N/D over one canonical fraction in (parameters, s): the gcd cancels.
        let s = Symbol(u32::try_from(symbols.len()).unwrap_or(u32::MAX));
        let in_s = |coefficients: &[RatFunc]| -> RatFunc {
            let variable = RatFunc::symbol(s);
            let mut power = RatFunc::one();
            let mut sum = RatFunc::zero();
            for c in coefficients {
                if !c.is_zero() {
                    sum += c * &power;
                }
                power = &power * &variable;
            }
            sum
        };
        let full = in_s(&denominator);
        let g = in_s(&numerator)
            .checked_div(&full)
            .expect("det(sI - A) is monic, so not zero");
        if g.is_zero() {
            return TransferFunction {
                numerator: vec![RatFunc::zero()],
                denominator: vec![RatFunc::one()],
                cancelled: full_degree,
                cancelled_factor: denominator.into_iter().rev().collect(),
            };
        }
        // det(sI - A) over the lowest-terms denominator: a polynomial in s, since every
        // factor of the denominator with s in it divides det(sI - A).
        let factor = full
            .checked_div(&RatFunc::from_poly(g.denominator().clone()))
            .expect("the denominator is not zero");
        let cancelled_factor = if factor.denominator().degree_in(s) == 0 {
            let scale = RatFunc::from_poly(factor.denominator().clone())
                .inv()
                .expect("not zero");
            split(factor.numerator(), s)
                .into_iter()
                .map(|c| c * &scale)
                .collect()
        } else {
            vec![RatFunc::one()]
        };
        let mut numerator = split(g.numerator(), s);
        let mut denominator = split(g.denominator(), s);
        let leading_negative = denominator
            .first()
            .is_some_and(|c| c.numerator().leading_coefficient().is_negative());
        if leading_negative {
            numerator = numerator.into_iter().map(|c| -c).collect();
            denominator = denominator.into_iter().map(|c| -c).collect();
        }
        let cancelled = full_degree - (denominator.len() - 1);
        TransferFunction {
            numerator,
            denominator,
            cancelled,
            cancelled_factor,
        }
    }

    /// The coefficients divided by the denominator's leading one (highest power first): the
    /// denominator is monic.
    pub fn monic(&self) -> (Vec<RatFunc>, Vec<RatFunc>) {
        let lead = self.denominator[0]
            .inv()
            .expect("leading coefficient not zero");
        let scale = |v: &[RatFunc]| v.iter().map(|c| c * &lead).collect();
        (scale(&self.numerator), scale(&self.denominator))
    }

    /// The monic coefficients evaluated with parameter `values`: `(numerator, denominator)`,
    /// highest power first, `denominator[0] = 1`.
    pub fn monic_values(&self, values: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (num, den) = self.monic();
        let eval = |v: Vec<RatFunc>| v.iter().map(|c| c.eval(values)).collect();
        (eval(num), eval(den))
    }

    /// As [`TransferFunction::monic_values`], in extended range ([`Scaled`]): coefficients
    /// that do not fit in `f64` (a 1e-300 kg mass's stiffness over mass) keep their value.
    pub fn monic_scaled(&self, values: &[f64]) -> (Vec<Scaled>, Vec<Scaled>) {
        let (num, den) = self.monic();
        let eval = |v: Vec<RatFunc>| v.iter().map(|c| c.eval_scaled(values)).collect();
        (eval(num), eval(den))
    }

    /// The coefficients of [`TransferFunction::cancelled_factor`] with parameter `values`,
    /// in extended range.
    pub fn cancelled_scaled(&self, values: &[f64]) -> Vec<Scaled> {
        self.cancelled_factor
            .iter()
            .map(|c| c.eval_scaled(values))
            .collect()
    }

    /// `N(s)` as text: `m*s^2 + b*s + k`.
    pub fn numerator_text(&self, symbols: &SymbolTable) -> String {
        polynomial_text(&self.numerator, symbols)
    }

    /// `D(s)` as text.
    pub fn denominator_text(&self, symbols: &SymbolTable) -> String {
        polynomial_text(&self.denominator, symbols)
    }
}

/// `c · M · b`.
fn quadratic(c: &[RatFunc], m: &[Vec<RatFunc>], b: &[RatFunc]) -> RatFunc {
    let mut sum = RatFunc::zero();
    for (i, ci) in c.iter().enumerate() {
        if ci.is_zero() {
            continue;
        }
        for (j, bj) in b.iter().enumerate() {
            if !bj.is_zero() && !m[i][j].is_zero() {
                sum += ci * &(&m[i][j] * bj);
            }
        }
    }
    sum
}

/// A polynomial in the parameters and `s` as its coefficients in `s`, highest power first.
fn split(p: &Poly, s: Symbol) -> Vec<RatFunc> {
    let degree = p.degree_in(s) as usize;
    let mut terms: Vec<Vec<(Monomial, num_bigint::BigInt)>> = vec![Vec::new(); degree + 1];
    for (monomial, coefficient) in p.terms() {
        let power = monomial.exponent(s) as usize;
        let rest = Monomial::new(monomial.iter().filter(|(x, _)| *x != s));
        terms[degree - power].push((rest, coefficient.clone()));
    }
    terms
        .into_iter()
        .map(|t| RatFunc::from_poly(Poly::from_terms(t)))
        .collect()
}

/// A polynomial in `s` (coefficients highest power first) as text: `m*s^2 + b*s + k`,
/// `(b + K_p)*s - 2`.
pub fn polynomial_text(coefficients: &[RatFunc], symbols: &SymbolTable) -> String {
    let degree = coefficients.len().saturating_sub(1);
    let mut text = String::new();
    for (i, c) in coefficients.iter().enumerate() {
        if c.is_zero() {
            continue;
        }
        let power = degree - i;
        let (negative, mut magnitude) = match c.to_constant() {
            // An exact decimal of a linearisation prints as its value, not as p/10^16.
            Some((_, den)) if den.to_string().len() > 7 => {
                let value = c.eval(&[]);
                (value < 0.0, crate::number::shortest(value.abs()))
            }
            _ => c.signed_text(symbols),
        };
        let compound =
            !c.is_constant() && (c.numerator().term_count() > 1 || !c.denominator().is_one());
        if power > 0 && compound && magnitude.contains([' ', '/']) {
            magnitude = format!("({magnitude})");
        }
        let s = match power {
            0 => String::new(),
            1 => "s".to_string(),
            p => format!("s^{p}"),
        };
        let term = match (power, magnitude.as_str()) {
            (0, _) => magnitude.clone(),
            (_, "1") => s,
            _ => format!("{magnitude}*{s}"),
        };
        match (text.is_empty(), negative) {
            (true, true) => text.push_str(&format!("-{term}")),
            (true, false) => text.push_str(&term),
            (false, true) => text.push_str(&format!(" - {term}")),
            (false, false) => text.push_str(&format!(" + {term}")),
        }
    }
    if text.is_empty() {
        text.push('0');
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::characteristic;

    fn n(k: i64) -> RatFunc {
        RatFunc::integer(k)
    }

    #[test]
    fn the_cancelled_factor_holds_the_modes_the_channel_misses() {
        // A = diag(-1, -2), the input drives the first state only, the output sees both:
        // G = 1/(s + 1), and det(sI - A) = (s + 1)(s + 2) lost the factor s + 2.
        let a = vec![vec![n(-1), n(0)], vec![n(0), n(-2)]];
        let channel = Channel {
            b: vec![n(1), n(0)],
            e: vec![n(0), n(0)],
            c: vec![n(1), n(1)],
            d: n(0),
            f: n(0),
            integral: false,
        };
        let tf = TransferFunction::new(&characteristic(&a), &channel, &SymbolTable::default());
        assert_eq!(tf.numerator, [n(1)]);
        assert_eq!(tf.denominator, [n(1), n(1)]);
        assert_eq!(tf.cancelled, 1);
        assert_eq!(tf.cancelled_factor, [n(1), n(2)]);
        // An integral output of the same: 1/(s (s + 1)), still s + 2 cancelled.
        let integral = Channel {
            integral: true,
            ..channel.clone()
        };
        let tf = TransferFunction::new(&characteristic(&a), &integral, &SymbolTable::default());
        assert_eq!(tf.denominator, [n(1), n(1), n(0)]);
        assert_eq!(tf.cancelled_factor, [n(1), n(2)]);
        // Nothing reaches the output: everything cancelled.
        let blind = Channel {
            c: vec![n(0), n(0)],
            ..channel
        };
        let tf = TransferFunction::new(&characteristic(&a), &blind, &SymbolTable::default());
        assert_eq!(tf.cancelled_factor, [n(1), n(3), n(2)]);
        assert_eq!(tf.monic_scaled(&[]).1.len(), 1);
    }
}
