//! Multivariate polynomials with exact integer coefficients, and exact division.
//!
//! A [`Poly`] is a sparse list of terms sorted from greatest to smallest in the term order
//! (see [`Monomial`]), with no zero coefficients; so equal polynomials are equal
//! structurally, and printing the terms in storage order is printing them alphabetically.

use std::collections::{BTreeMap, BTreeSet};

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};

use super::{Monomial, Scaled, Symbol};

/// A finite `f64` as `(mantissa, exponent)` with `value = mantissa * 2^exponent` exactly.
fn binary_fraction(value: f64) -> Option<(i64, i64)> {
    if !value.is_finite() {
        return None;
    }
    let bits = value.to_bits();
    let sign = if bits >> 63 == 0 { 1 } else { -1 };
    let biased = ((bits >> 52) & 0x7ff) as i64;
    let fraction = (bits & ((1 << 52) - 1)) as i64;
    Some(if biased == 0 {
        (sign * fraction, -1074)
    } else {
        (sign * (fraction | (1 << 52)), biased - 1075)
    })
}

/// Largest number of terms [`Poly::pow`] is willing to expand to (by an upper estimate).
const MAX_POWER_TERMS: f64 = 200_000.0;

/// Largest coefficient size, in bits, [`Poly::pow`] is willing to produce (by an upper
/// estimate).
const MAX_POWER_BITS: u64 = 1 << 20;

/// A multivariate polynomial with integer coefficients, in canonical form: terms sorted by
/// the term order, greatest first, no zero coefficients. Zero has no terms.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Poly {
    terms: Vec<(Monomial, BigInt)>,
}

impl Poly {
    /// The zero polynomial.
    pub fn zero() -> Self {
        Poly { terms: Vec::new() }
    }

    /// The constant 1.
    pub fn one() -> Self {
        Poly::constant(BigInt::one())
    }

    /// An integer constant.
    pub fn constant(c: BigInt) -> Self {
        Poly::term(Monomial::one(), c)
    }

    /// A single symbol.
    pub fn symbol(s: Symbol) -> Self {
        Poly::term(Monomial::symbol(s), BigInt::one())
    }

    /// A single term `c * m` (zero if `c` is zero).
    pub fn term(m: Monomial, c: BigInt) -> Self {
        if c.is_zero() {
            Poly::zero()
        } else {
            Poly {
                terms: vec![(m, c)],
            }
        }
    }

    /// The sum of the given terms, in any order; like terms are combined.
    pub fn from_terms(terms: impl IntoIterator<Item = (Monomial, BigInt)>) -> Self {
        let mut terms: Vec<(Monomial, BigInt)> = terms.into_iter().collect();
        terms.sort_unstable_by(|a, b| b.0.cmp(&a.0));
        Poly::from_sorted_with_duplicates(terms)
    }

    /// Combines adjacent like terms of a list sorted greatest first and drops zeros.
    fn from_sorted_with_duplicates(terms: Vec<(Monomial, BigInt)>) -> Self {
        let mut out: Vec<(Monomial, BigInt)> = Vec::with_capacity(terms.len());
        for (m, c) in terms {
            match out.last_mut() {
                Some((last, acc)) if *last == m => *acc += c,
                _ => {
                    if out.last().is_some_and(|(_, acc)| acc.is_zero()) {
                        out.pop();
                    }
                    out.push((m, c));
                }
            }
        }
        if out.last().is_some_and(|(_, acc)| acc.is_zero()) {
            out.pop();
        }
        Poly { terms: out }
    }

    /// Wraps terms that are already canonical (sorted greatest first, no zeros).
    pub(crate) fn from_canonical(terms: Vec<(Monomial, BigInt)>) -> Self {
        debug_assert!(terms.windows(2).all(|w| w[0].0 > w[1].0));
        debug_assert!(terms.iter().all(|(_, c)| !c.is_zero()));
        Poly { terms }
    }

    /// Whether this is the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    /// Whether this is the constant 1.
    pub fn is_one(&self) -> bool {
        matches!(self.terms.as_slice(), [(m, c)] if m.is_one() && c.is_one())
    }

    /// Whether the polynomial has no symbols (zero counts as constant).
    pub fn is_constant(&self) -> bool {
        match self.terms.as_slice() {
            [] => true,
            [(m, _)] => m.is_one(),
            _ => false,
        }
    }

    /// The value of a constant polynomial, `None` if it has symbols.
    pub fn to_constant(&self) -> Option<BigInt> {
        match self.terms.as_slice() {
            [] => Some(BigInt::zero()),
            [(m, c)] if m.is_one() => Some(c.clone()),
            _ => None,
        }
    }

    /// The terms, greatest first in the term order.
    pub fn terms(&self) -> impl Iterator<Item = (&Monomial, &BigInt)> {
        self.terms.iter().map(|(m, c)| (m, c))
    }

    /// Number of terms (0 for zero).
    pub fn term_count(&self) -> usize {
        self.terms.len()
    }

    /// The greatest term, `None` for zero.
    pub fn leading_term(&self) -> Option<(&Monomial, &BigInt)> {
        self.terms.first().map(|(m, c)| (m, c))
    }

    /// The coefficient of the greatest term; zero for the zero polynomial.
    pub fn leading_coefficient(&self) -> BigInt {
        self.terms
            .first()
            .map_or_else(BigInt::zero, |(_, c)| c.clone())
    }

    /// The total degree: the largest degree of a term (0 for constants and zero).
    pub fn degree(&self) -> u32 {
        self.terms
            .iter()
            .map(|(m, _)| m.degree())
            .max()
            .unwrap_or(0)
    }

    /// The largest exponent of `s` in any term.
    pub fn degree_in(&self, s: Symbol) -> u32 {
        self.terms
            .iter()
            .map(|(m, _)| m.exponent(s))
            .max()
            .unwrap_or(0)
    }

    /// The symbols that occur.
    pub fn symbols(&self) -> BTreeSet<Symbol> {
        self.terms
            .iter()
            .flat_map(|(m, _)| m.iter().map(|(s, _)| s))
            .collect()
    }

    /// Evaluates with `values[symbol.index()]`: the value rounded to `f64`, infinite only
    /// when the value itself overflows (a term's product that leaves the range of `f64` is
    /// carried with its own exponent, [`Scaled`]). A symbol without a value evaluates to NaN.
    pub fn eval(&self, values: &[f64]) -> f64 {
        let fast = self.eval_f64(values);
        if fast.is_finite() && fast.abs() >= f64::MIN_POSITIVE {
            return fast;
        }
        self.eval_scaled(values).to_f64()
    }

    /// The value with `values[symbol.index()]`, in extended range: no term overflows or
    /// underflows on the way.
    pub fn eval_scaled(&self, values: &[f64]) -> Scaled {
        self.terms
            .iter()
            .map(|(m, c)| {
                m.iter().fold(Scaled::from_bigint(c), |acc, (s, e)| {
                    let v = Scaled::from_f64(values.get(s.index()).copied().unwrap_or(f64::NAN));
                    acc * v.powi(e)
                })
            })
            .fold(Scaled::ZERO, |sum, term| sum + term)
    }

    /// Plain `f64` evaluation: fast, but a product may overflow or underflow on the way.
    fn eval_f64(&self, values: &[f64]) -> f64 {
        self.terms
            .iter()
            .map(|(m, c)| {
                let c = c.to_f64().unwrap_or(f64::NAN);
                m.iter().fold(c, |acc, (s, e)| {
                    let v = values.get(s.index()).copied().unwrap_or(f64::NAN);
                    acc * match i32::try_from(e) {
                        Ok(e) => v.powi(e),
                        Err(_) => v.powf(f64::from(e)),
                    }
                })
            })
            // Not `.sum()`: an empty f64 sum is -0.0, and zero must print as 0.
            .fold(0.0, |sum, term| sum + term)
    }

    /// Whether the polynomial is exactly zero at `values[symbol.index()]`, each `f64` taken
    /// as the exact binary fraction it is: where [`Poly::eval`] gives 0 by underflow, this
    /// tells it from a true zero. `None` if a value is missing or not finite.
    pub fn vanishes_at(&self, values: &[f64]) -> Option<bool> {
        // Every term is c * M * 2^e with integers c, M and e; sum them at the lowest e.
        let mut terms = Vec::with_capacity(self.terms.len());
        for (m, c) in &self.terms {
            let mut mantissa = c.clone();
            let mut exponent: i64 = 0;
            for (s, e) in m.iter() {
                let (value_mantissa, value_exponent) = binary_fraction(*values.get(s.index())?)?;
                mantissa *= num_traits::pow(BigInt::from(value_mantissa), e as usize);
                exponent += value_exponent * i64::from(e);
            }
            terms.push((mantissa, exponent));
        }
        let Some(lowest) = terms.iter().map(|(_, e)| *e).min() else {
            return Some(true);
        };
        let sum: BigInt = terms
            .into_iter()
            .map(|(mantissa, e)| mantissa << usize::try_from(e - lowest).unwrap_or(usize::MAX))
            .sum();
        Some(sum.is_zero())
    }

    /// The integer content: the positive gcd of all coefficients (0 for zero).
    pub fn content(&self) -> BigInt {
        let mut g = BigInt::zero();
        for (_, c) in &self.terms {
            g = g.gcd(c);
            if g.is_one() {
                break;
            }
        }
        g
    }

    /// The monomial content: the largest monomial dividing every term (1 for zero).
    pub fn monomial_content(&self) -> Monomial {
        let mut iter = self.terms.iter();
        let Some((first, _)) = iter.next() else {
            return Monomial::one();
        };
        let mut g = first.clone();
        for (m, _) in iter {
            if g.is_one() {
                break;
            }
            g = g.gcd(m);
        }
        g
    }

    /// `-self` if the leading coefficient is negative, so that it is positive.
    pub(crate) fn normalise_sign(self) -> Poly {
        if self.terms.first().is_some_and(|(_, c)| c.is_negative()) {
            -self
        } else {
            self
        }
    }

    /// `self * c * m`; keeps the term order, so needs no sorting.
    pub(crate) fn mul_term(&self, m: &Monomial, c: &BigInt) -> Poly {
        if c.is_zero() {
            return Poly::zero();
        }
        Poly {
            terms: self
                .terms
                .iter()
                .map(|(tm, tc)| (tm.mul(m), tc * c))
                .collect(),
        }
    }

    /// `self / (c * m)` if every term is divisible by it.
    pub(crate) fn div_term(&self, m: &Monomial, c: &BigInt) -> Option<Poly> {
        if c.is_zero() {
            return None;
        }
        let terms = self
            .terms
            .iter()
            .map(|(tm, tc)| {
                let (q, r) = tc.div_rem(c);
                if r.is_zero() {
                    tm.div(m).map(|qm| (qm, q))
                } else {
                    None
                }
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Poly { terms })
    }

    /// `self^n` by repeated squaring; `None` if an exponent would overflow `u32` or the
    /// expansion would be unreasonably large (over about 200 000 terms, or coefficients
    /// over about a million bits).
    pub fn pow(&self, n: u32) -> Option<Poly> {
        if n == 0 {
            return Some(Poly::one());
        }
        // A coefficient of the power has at most n * (bits of the largest coefficient +
        // log2 of the number of terms) bits.
        let largest = self.terms.iter().map(|(_, c)| c.bits()).max().unwrap_or(0);
        let spread = u64::from(usize::BITS - self.terms.len().leading_zeros());
        let unit_monomial = matches!(self.terms.as_slice(), [(_, c)] if c.abs().is_one());
        if !unit_monomial && u64::from(n).saturating_mul(largest + spread) > MAX_POWER_BITS {
            return None;
        }
        match self.terms.as_slice() {
            [] => return Some(Poly::zero()),
            [(m, c)] => return Some(Poly::term(m.pow(n)?, c.pow(n))),
            _ => {}
        }
        self.degree().checked_mul(n)?;
        // A power of a t-term polynomial has at most C(n + t - 1, t - 1) terms.
        let mut bound = 1.0f64;
        for i in 1..self.terms.len() {
            bound = bound * (f64::from(n) + i as f64) / i as f64;
            if bound > MAX_POWER_TERMS {
                return None;
            }
        }
        let mut result = Poly::one();
        let mut base = self.clone();
        let mut n = n;
        loop {
            if n & 1 == 1 {
                result = &result * &base;
            }
            n >>= 1;
            if n == 0 {
                return Some(result);
            }
            base = &base * &base;
        }
    }

    /// `self += other` (or `-= other`), in place. A few terms are inserted by binary
    /// search; more are merged, moving this polynomial's terms rather than copying them.
    fn add_assign_impl(&mut self, other: &Poly, negate_other: bool) {
        let other_coefficient = |c: &BigInt| if negate_other { -c } else { c.clone() };
        if other.terms.len() <= 4 {
            for (m, c) in &other.terms {
                // Terms are sorted greatest first.
                match self.terms.binary_search_by(|(probe, _)| m.cmp(probe)) {
                    Ok(i) => {
                        if negate_other {
                            self.terms[i].1 -= c;
                        } else {
                            self.terms[i].1 += c;
                        }
                        if self.terms[i].1.is_zero() {
                            self.terms.remove(i);
                        }
                    }
                    Err(i) => self.terms.insert(i, (m.clone(), other_coefficient(c))),
                }
            }
            return;
        }
        let mine = std::mem::take(&mut self.terms);
        let theirs = &other.terms;
        let mut out = Vec::with_capacity(mine.len() + theirs.len());
        let mut j = 0;
        for (m, c) in mine {
            while j < theirs.len() && theirs[j].0 > m {
                out.push((theirs[j].0.clone(), other_coefficient(&theirs[j].1)));
                j += 1;
            }
            if j < theirs.len() && theirs[j].0 == m {
                let sum = if negate_other {
                    c - &theirs[j].1
                } else {
                    c + &theirs[j].1
                };
                j += 1;
                if !sum.is_zero() {
                    out.push((m, sum));
                }
            } else {
                out.push((m, c));
            }
        }
        out.extend(
            theirs[j..]
                .iter()
                .map(|(m, c)| (m.clone(), other_coefficient(c))),
        );
        self.terms = out;
    }

    /// `self * c * m` in place; keeps the term order.
    pub(crate) fn mul_term_assign(&mut self, m: &Monomial, c: &BigInt) {
        if c.is_zero() {
            self.terms.clear();
            return;
        }
        let unit = c.is_one();
        for (tm, tc) in &mut self.terms {
            tm.mul_assign(m);
            if !unit {
                *tc *= c;
            }
        }
    }

    /// `self / (c * m)` reusing this polynomial's storage, if every term is divisible.
    pub(crate) fn div_term_owned(mut self, m: &Monomial, c: &BigInt) -> Option<Poly> {
        if c.is_zero() {
            return None;
        }
        let unit = c.is_one();
        for (tm, tc) in &mut self.terms {
            if !tm.div_assign(m) {
                return None;
            }
            if !unit {
                let (q, r) = tc.div_rem(c);
                if !r.is_zero() {
                    return None;
                }
                *tc = q;
            }
        }
        Some(self)
    }

    /// The gcd of `m` and the monomial content, looking up only the symbols of `m`.
    pub(crate) fn monomial_gcd_with(&self, m: &Monomial) -> Monomial {
        Monomial::new(m.iter().map(|(s, e)| {
            let mut min = e;
            for (tm, _) in &self.terms {
                if min == 0 {
                    break;
                }
                min = min.min(tm.exponent(s));
            }
            (s, min)
        }))
    }

    pub(crate) fn add_ref(&self, other: &Poly) -> Poly {
        self.clone().add_owned(other)
    }

    pub(crate) fn sub_ref(&self, other: &Poly) -> Poly {
        self.clone().sub_owned(other)
    }

    pub(crate) fn add_owned(mut self, other: &Poly) -> Poly {
        self.add_assign_impl(other, false);
        self
    }

    pub(crate) fn sub_owned(mut self, other: &Poly) -> Poly {
        self.add_assign_impl(other, true);
        self
    }

    pub(crate) fn mul_owned(mut self, other: &Poly) -> Poly {
        match other.terms.as_slice() {
            [(m, c)] => {
                self.mul_term_assign(m, c);
                self
            }
            _ => self.mul_ref(other),
        }
    }

    pub(crate) fn mul_ref(&self, other: &Poly) -> Poly {
        match (self.terms.as_slice(), other.terms.as_slice()) {
            ([], _) | (_, []) => Poly::zero(),
            ([(m, c)], _) => other.mul_term(m, c),
            (_, [(m, c)]) => self.mul_term(m, c),
            (a, b) => {
                let mut products = Vec::with_capacity(a.len() * b.len());
                for (am, ac) in a {
                    for (bm, bc) in b {
                        products.push((am.mul(bm), ac * bc));
                    }
                }
                products.sort_unstable_by(|x, y| y.0.cmp(&x.0));
                Poly::from_sorted_with_duplicates(products)
            }
        }
    }

    pub(crate) fn neg_owned(mut self) -> Poly {
        for (_, c) in &mut self.terms {
            *c = -std::mem::take(c);
        }
        self
    }
}

/// `Some(a / b)` if `b` divides `a` exactly over the integers, `None` otherwise (including
/// when `b` is zero).
pub fn div_exact(a: &Poly, b: &Poly) -> Option<Poly> {
    let (lm_b, lc_b) = b.leading_term()?;
    if a.is_zero() {
        return Some(Poly::zero());
    }
    if b.terms.len() == 1 {
        return a.div_term(lm_b, lc_b);
    }
    if a == b {
        return Some(Poly::one());
    }
    // Cheap necessary conditions: the greatest and the smallest terms of a product are the
    // products of the greatest and of the smallest terms of the factors.
    let (lm_a, lc_a) = a.leading_term()?;
    let (tm_a, tc_a) = a.terms.last().map(|(m, c)| (m, c))?;
    let (tm_b, tc_b) = b.terms.last().map(|(m, c)| (m, c))?;
    if !lm_b.divides(lm_a)
        || !tm_b.divides(tm_a)
        || !(lc_a % lc_b).is_zero()
        || !(tc_a % tc_b).is_zero()
    {
        return None;
    }
    // Degree bounds per symbol: deg_s(q) = deg_s(a) - deg_s(b) for every symbol s.
    let mut bounds: BTreeMap<Symbol, u32> = BTreeMap::new();
    for (m, _) in &a.terms {
        for (s, e) in m.iter() {
            let bound = bounds.entry(s).or_insert(0);
            *bound = (*bound).max(e);
        }
    }
    for s in b.symbols() {
        let bound = bounds.get_mut(&s)?;
        *bound = bound.checked_sub(b.degree_in(s))?;
    }
    let within_bounds = |m: &Monomial| {
        m.iter()
            .all(|(s, e)| bounds.get(&s).is_some_and(|&bound| e <= bound))
    };

    // Long division; the remainder keeps its greatest term last for cheap removal.
    let mut rem: BTreeMap<Monomial, BigInt> = a.terms.iter().cloned().collect();
    let mut quotient: Vec<(Monomial, BigInt)> = Vec::new();
    while let Some((m, c)) = rem.pop_last() {
        let qm = m.div(lm_b)?;
        if !within_bounds(&qm) {
            return None;
        }
        let (qc, r) = c.div_rem(lc_b);
        if !r.is_zero() {
            return None;
        }
        for (bm, bc) in &b.terms[1..] {
            let product = qm.mul(bm);
            let delta = &qc * bc;
            match rem.entry(product) {
                std::collections::btree_map::Entry::Occupied(mut entry) => {
                    *entry.get_mut() -= delta;
                    if entry.get().is_zero() {
                        entry.remove();
                    }
                }
                std::collections::btree_map::Entry::Vacant(entry) => {
                    entry.insert(-delta);
                }
            }
        }
        quotient.push((qm, qc));
    }
    Some(Poly { terms: quotient })
}

impl std::ops::Neg for Poly {
    type Output = Poly;
    fn neg(self) -> Poly {
        self.neg_owned()
    }
}

impl std::ops::Neg for &Poly {
    type Output = Poly;
    fn neg(self) -> Poly {
        self.clone().neg_owned()
    }
}

super::forward_binops!(
    Poly, add_ref, sub_ref, mul_ref, add_owned, sub_owned, mul_owned
);

#[cfg(test)]
mod tests {
    use super::*;

    const A: Symbol = Symbol(0);
    const B: Symbol = Symbol(1);
    const C: Symbol = Symbol(2);

    fn s(x: Symbol) -> Poly {
        Poly::symbol(x)
    }

    fn k(n: i64) -> Poly {
        Poly::constant(BigInt::from(n))
    }

    /// 1e-200 * 1e-200 underflows to 0 in f64 but is not zero; 0.1 - 0.1, 3^2 - 2*4.5 and
    /// 0 * 5 are; the smallest subnormal is not.
    #[test]
    fn vanishes_at_tells_underflow_from_zero() {
        let product = s(A) * s(B);
        assert_eq!(product.eval(&[1e-200, 1e-200]), 0.0);
        assert_eq!(product.vanishes_at(&[1e-200, 1e-200]), Some(false));
        assert_eq!(product.vanishes_at(&[0.0, 5.0]), Some(true));
        let difference = s(A) - s(B);
        assert_eq!(difference.vanishes_at(&[0.1, 0.1]), Some(true));
        assert_eq!(difference.vanishes_at(&[0.1, 0.1 + 1.4e-17]), Some(false));
        let square = s(A) * s(A) - k(2) * s(B);
        assert_eq!(square.vanishes_at(&[3.0, 4.5]), Some(true));
        assert_eq!(square.vanishes_at(&[-3.0, 4.5]), Some(true));
        assert_eq!(s(A).vanishes_at(&[5e-324]), Some(false));
        assert_eq!(s(A).vanishes_at(&[f64::INFINITY]), None);
        assert_eq!(k(7).vanishes_at(&[]), Some(false));
        assert_eq!(Poly::zero().vanishes_at(&[]), Some(true));
    }

    fn coefficients(p: &Poly) -> Vec<i64> {
        p.terms().map(|(_, c)| c.to_i64().unwrap()).collect()
    }

    fn monomials(p: &Poly) -> Vec<Vec<(Symbol, u32)>> {
        p.terms().map(|(m, _)| m.iter().collect()).collect()
    }

    #[test]
    fn sums_are_sorted_and_cancel() {
        // (b + 1) + (a - 1) = a + b
        let p = (s(B) + k(1)) + (s(A) - k(1));
        assert_eq!(monomials(&p), [vec![(A, 1)], vec![(B, 1)]]);
        assert_eq!(coefficients(&p), [1, 1]);
        assert!((&p - &p).is_zero());
        assert_eq!(p.term_count(), 2);
    }

    #[test]
    fn products_expand_in_term_order() {
        // (a + b)^2 = a^2 + 2ab + b^2
        let p = (s(A) + s(B)) * (s(A) + s(B));
        assert_eq!(
            monomials(&p),
            [vec![(A, 2)], vec![(A, 1), (B, 1)], vec![(B, 2)]]
        );
        assert_eq!(coefficients(&p), [1, 2, 1]);
        assert_eq!((s(A) + s(B)).pow(2), Some(p.clone()));
        assert_eq!(p.degree(), 2);
        // (a - b)(a + b) = a^2 - b^2
        let q = (s(A) - s(B)) * (s(A) + s(B));
        assert_eq!(coefficients(&q), [1, -1]);
        assert_eq!(monomials(&q), [vec![(A, 2)], vec![(B, 2)]]);
    }

    #[test]
    fn constants_sort_last_and_zero_is_empty() {
        let p = k(3) + s(C) * k(2);
        assert_eq!(monomials(&p), [vec![(C, 1)], vec![]]);
        assert_eq!(coefficients(&p), [2, 3]);
        assert!(Poly::constant(BigInt::zero()).is_zero());
        assert!(Poly::zero().is_constant());
        assert!(k(5).is_constant());
        assert!(!p.is_constant());
        assert!(Poly::one().is_one());
        assert_eq!(k(-4).to_constant(), Some(BigInt::from(-4)));
        assert_eq!(p.to_constant(), None);
    }

    #[test]
    fn from_terms_combines_like_terms() {
        let p = Poly::from_terms([
            (Monomial::symbol(B), BigInt::from(2)),
            (Monomial::symbol(A), BigInt::from(1)),
            (Monomial::symbol(B), BigInt::from(-2)),
        ]);
        assert_eq!(p, s(A));
    }

    #[test]
    fn contents() {
        // 6a^2 b + 4ab^2 = 2ab (3a + 2b)
        let p = k(6) * s(A) * s(A) * s(B) + k(4) * s(A) * s(B) * s(B);
        assert_eq!(p.content(), BigInt::from(2));
        assert_eq!(p.monomial_content(), Monomial::new([(A, 1), (B, 1)]));
        assert_eq!(k(-6).content(), BigInt::from(6));
        assert_eq!(Poly::zero().content(), BigInt::zero());
    }

    #[test]
    fn evaluation() {
        // 2a^2 b - 3 at a = 1.5, b = -2: 2 * 2.25 * -2 - 3 = -12
        let p = k(2) * s(A) * s(A) * s(B) - k(3);
        assert_eq!(p.eval(&[1.5, -2.0]), -12.0);
        assert!(p.eval(&[1.0]).is_nan());
        // Zero is +0, not the -0 of an empty f64 sum.
        assert!(Poly::zero().eval(&[]).is_sign_positive());
    }

    #[test]
    fn exact_division() {
        let a2_b2 = s(A) * s(A) - s(B) * s(B);
        assert_eq!(div_exact(&a2_b2, &(s(A) + s(B))), Some(s(A) - s(B)));
        assert_eq!(div_exact(&a2_b2, &(s(A) - s(B))), Some(s(A) + s(B)));
        assert_eq!(div_exact(&a2_b2, &(s(A) + k(1))), None);
        assert_eq!(div_exact(&(k(6) * s(A)), &k(3)), Some(k(2) * s(A)));
        assert_eq!(div_exact(&(k(6) * s(A)), &k(4)), None);
        assert_eq!(div_exact(&(k(2) * s(A) + k(2)), &(k(2) * s(A))), None);
        assert_eq!(div_exact(&s(A), &Poly::zero()), None);
        assert_eq!(div_exact(&Poly::zero(), &s(A)), Some(Poly::zero()));
        // x^5 is not divisible by x - y (remainder y^5).
        assert_eq!(div_exact(&s(A).pow(5).unwrap(), &(s(A) - s(B))), None);
        // (x^5 - y^5) / (x - y) = x^4 + x^3 y + x^2 y^2 + x y^3 + y^4
        let q = div_exact(
            &(s(A).pow(5).unwrap() - s(B).pow(5).unwrap()),
            &(s(A) - s(B)),
        )
        .unwrap();
        assert_eq!(coefficients(&q), [1, 1, 1, 1, 1]);
        assert_eq!(q.degree(), 4);
    }

    #[test]
    fn powers_refuse_overflow_and_blow_up() {
        assert_eq!(
            s(A).pow(u32::MAX),
            Some(Poly::term(Monomial::new([(A, u32::MAX)]), BigInt::one()))
        );
        assert_eq!(s(A).pow(u32::MAX).unwrap().pow(2), None);
        assert_eq!((s(A) + s(B) + s(C)).pow(100_000), None);
        assert_eq!(k(-2).pow(3), Some(k(-8)));
        assert_eq!(k(-1).pow(u32::MAX), Some(k(-1)));
        assert_eq!(k(2).pow(1 << 30), None);
        assert_eq!(
            k(2).pow(1000).map(|p| p.leading_coefficient().bits()),
            Some(1001)
        );
        assert_eq!(Poly::zero().pow(0), Some(Poly::one()));
    }
}
