//! Rational functions in canonical form, and their arithmetic.
//!
//! A [`RatFunc`] is `num / den` with:
//! - `gcd(num, den) = 1` over Z[symbols] (so also the gcd of all integer coefficients of
//!   `num` and `den` together is 1);
//! - `den` with a positive leading coefficient (in the term order);
//! - zero as `0 / 1`.
//!
//! Every operation keeps this form, so equal rational functions are structurally equal.
//! Sums and products of reduced fractions use Henrici's formulas, which only take gcds of
//! the (small) inputs instead of reducing the (large) cross-multiplied result.

use std::collections::BTreeSet;

use num_bigint::BigInt;
use num_traits::Signed;

use super::gcd::{div_known, div_known_owned, gcd};
use super::{Poly, Scaled, Symbol, decimal};

/// A rational function of symbols with integer coefficients, in canonical form (see the
/// module documentation): equal values are equal structurally and print identically.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct RatFunc {
    num: Poly,
    den: Poly,
}

impl RatFunc {
    /// Zero.
    pub fn zero() -> Self {
        RatFunc {
            num: Poly::zero(),
            den: Poly::one(),
        }
    }

    /// One.
    pub fn one() -> Self {
        RatFunc::integer(1)
    }

    /// An integer.
    pub fn integer(n: i64) -> Self {
        RatFunc::from_poly(Poly::constant(BigInt::from(n)))
    }

    /// The fraction `num / den` reduced; `None` if `den` is zero.
    pub fn rational(num: BigInt, den: BigInt) -> Option<Self> {
        RatFunc::from_polys(Poly::constant(num), Poly::constant(den))
    }

    /// The exact value of a number literal (`0.5` is 1/2, `1e-3` is 1/1000, `2.5E+2` is 250,
    /// `5.` is 5, `.25` is 1/4). `None` if the text is not an unsigned number literal or its
    /// decimal exponent is larger than 400 in size.
    pub fn from_decimal(text: &str) -> Option<Self> {
        let (num, den) = decimal::parse_decimal(text)?;
        RatFunc::rational(num, den)
    }

    /// A single symbol.
    pub fn symbol(s: Symbol) -> Self {
        RatFunc::from_poly(Poly::symbol(s))
    }

    /// A polynomial, as a rational function with denominator 1.
    pub fn from_poly(p: Poly) -> Self {
        RatFunc {
            num: p,
            den: Poly::one(),
        }
    }

    /// `num / den` brought to canonical form; `None` if `den` is zero.
    pub fn from_polys(num: Poly, den: Poly) -> Option<Self> {
        if den.is_zero() {
            return None;
        }
        if num.is_zero() {
            return Some(RatFunc::zero());
        }
        let g = gcd(&num, &den);
        Some(RatFunc::from_coprime(
            div_known(&num, &g),
            div_known(&den, &g),
        ))
    }

    /// Canonical form of `num / den` when `gcd(num, den) = 1`: fixes the sign.
    fn from_coprime(num: Poly, den: Poly) -> Self {
        if num.is_zero() {
            return RatFunc::zero();
        }
        if den.leading_coefficient().is_negative() {
            RatFunc {
                num: -num,
                den: -den,
            }
        } else {
            RatFunc { num, den }
        }
    }

    /// `self / other`; `None` if `other` is zero.
    pub fn checked_div(&self, other: &Self) -> Option<Self> {
        Some(self * &other.inv()?)
    }

    /// `1 / self`; `None` for zero.
    pub fn inv(&self) -> Option<Self> {
        if self.is_zero() {
            return None;
        }
        Some(RatFunc::from_coprime(self.den.clone(), self.num.clone()))
    }

    /// `self^n`; `None` for zero to a negative power, and when the expansion would be
    /// unreasonably large (an exponent beyond `u32`, or over about 200 000 terms). `0^0`
    /// is 1.
    pub fn powi(&self, n: i32) -> Option<Self> {
        let base = if n < 0 { self.inv()? } else { self.clone() };
        let n = n.unsigned_abs();
        // Powers of coprime polynomials are coprime, and the leading coefficient of the
        // denominator stays positive.
        Some(RatFunc {
            num: base.num.pow(n)?,
            den: base.den.pow(n)?,
        })
    }

    /// Whether this is zero.
    pub fn is_zero(&self) -> bool {
        self.num.is_zero()
    }

    /// Whether this is one.
    pub fn is_one(&self) -> bool {
        self.num.is_one() && self.den.is_one()
    }

    /// Whether this has no symbols.
    pub fn is_constant(&self) -> bool {
        self.num.is_constant() && self.den.is_constant()
    }

    /// The value of a constant as `(numerator, denominator)` in lowest terms with a
    /// positive denominator; `None` if there are symbols.
    pub fn to_constant(&self) -> Option<(BigInt, BigInt)> {
        Some((self.num.to_constant()?, self.den.to_constant()?))
    }

    /// The numerator.
    pub fn numerator(&self) -> &Poly {
        &self.num
    }

    /// The denominator (positive leading coefficient; 1 for polynomials).
    pub fn denominator(&self) -> &Poly {
        &self.den
    }

    /// The symbols that occur.
    pub fn symbols(&self) -> BTreeSet<Symbol> {
        let mut symbols = self.num.symbols();
        symbols.extend(self.den.symbols());
        symbols
    }

    /// Evaluates with `values[symbol.index()]`: the value rounded to `f64`, infinite only
    /// when the value itself overflows, whatever its numerator and denominator do on their
    /// own (see [`Scaled`]). A zero denominator gives an infinity or NaN; a symbol without a
    /// value gives NaN.
    pub fn eval(&self, values: &[f64]) -> f64 {
        if self.den.is_one() {
            return self.num.eval(values);
        }
        let in_range = |x: f64| x.is_finite() && x.abs() >= f64::MIN_POSITIVE;
        let (num, den) = (self.num.eval(values), self.den.eval(values));
        if in_range(num) && in_range(den) {
            return num / den;
        }
        self.eval_scaled(values).to_f64()
    }

    /// The value with `values[symbol.index()]` in extended range ([`Scaled`]): for numbers
    /// that may not fit in `f64`, such as the coefficients of a characteristic polynomial.
    pub fn eval_scaled(&self, values: &[f64]) -> Scaled {
        let num = self.num.eval_scaled(values);
        if self.den.is_one() {
            num
        } else {
            num / self.den.eval_scaled(values)
        }
    }

    /// `self + other`, by reference (the operators take values or references alike).
    pub fn add_ref(&self, other: &RatFunc) -> RatFunc {
        self.clone().add_owned(other)
    }

    /// `self - other`, by reference.
    pub fn sub_ref(&self, other: &RatFunc) -> RatFunc {
        self.clone().sub_owned(other)
    }

    /// `self * other`, by reference.
    pub fn mul_ref(&self, other: &RatFunc) -> RatFunc {
        self.clone().mul_owned(other)
    }

    /// `self - other`, reusing `self`'s storage.
    pub fn sub_owned(self, other: &RatFunc) -> RatFunc {
        self.add_owned(&-other)
    }

    /// `self + other`, reusing `self`'s storage; gcds only where Henrici's rule says one can
    /// cancel.
    pub fn add_owned(self, other: &RatFunc) -> RatFunc {
        if other.is_zero() {
            return self;
        }
        if self.is_zero() {
            return other.clone();
        }
        let RatFunc { num: a, den: b } = self;
        let (c, d) = (&other.num, &other.den);
        if b == *d {
            // a/b + c/b = (a + c)/b, then cancel what (a + c) shares with b.
            let t = a + c;
            if b.is_one() || t.is_zero() {
                return RatFunc::from_coprime(t, b);
            }
            let h = gcd(&t, &b);
            return RatFunc::from_coprime(div_known_owned(t, &h), div_known_owned(b, &h));
        }
        // Henrici: g = gcd(b, d), b = g b', d = g d', t = a d' + c b'. Then
        // gcd(t, b' d') = 1, so only gcd(t, g) can cancel.
        let g = gcd(&b, d);
        if g.is_one() {
            let t = a * d + c * &b;
            return RatFunc::from_coprime(t, b * d);
        }
        let b1 = div_known_owned(b, &g);
        let d1 = div_known(d, &g);
        let t = a * &d1 + c * &b1;
        if t.is_zero() {
            return RatFunc::zero();
        }
        let h = gcd(&t, &g);
        let g1 = div_known_owned(g, &h);
        RatFunc::from_coprime(div_known_owned(t, &h), b1 * &d1 * &g1)
    }

    /// `self * other`, reusing `self`'s storage.
    pub fn mul_owned(self, other: &RatFunc) -> RatFunc {
        if self.is_zero() || other.is_zero() {
            return RatFunc::zero();
        }
        // Henrici: (a/b)(c/d) = (a/g1)(c/g2) / ((b/g2)(d/g1)) with g1 = gcd(a, d) and
        // g2 = gcd(c, b); the result is reduced when both inputs are.
        let RatFunc { num: a, den: b } = self;
        let (c, d) = (&other.num, &other.den);
        let g1 = gcd(&a, d);
        let g2 = gcd(c, &b);
        let num = div_known_owned(a, &g1) * &div_known(c, &g2);
        let den = div_known_owned(b, &g2) * &div_known(d, &g1);
        RatFunc::from_coprime(num, den)
    }
}

/// Combines items pairwise, as a balanced tree: a long sum of fractions with distinct
/// denominators then costs O(n^2 log n) instead of the O(n^3) of adding one at a time.
fn balanced<I: Iterator<Item = RatFunc>>(
    items: I,
    empty: RatFunc,
    combine: fn(RatFunc, &RatFunc) -> RatFunc,
) -> RatFunc {
    // A binary counter of partial results: stack[k] combines a block of 2^level[k] items.
    let mut stack: Vec<(u32, RatFunc)> = Vec::new();
    for item in items {
        let mut level = 0;
        let mut acc = item;
        while let Some((top_level, _)) = stack.last() {
            if *top_level != level {
                break;
            }
            let Some((_, top)) = stack.pop() else { break };
            acc = combine(top, &acc);
            level += 1;
        }
        stack.push((level, acc));
    }
    let mut iter = stack.into_iter().rev();
    let Some((_, mut acc)) = iter.next() else {
        return empty;
    };
    for (_, earlier) in iter {
        acc = combine(earlier, &acc);
    }
    acc
}

impl std::iter::Sum for RatFunc {
    /// The sum, added as a balanced tree (much faster than `+=` in a loop for long sums of
    /// fractions with different denominators).
    fn sum<I: Iterator<Item = RatFunc>>(iter: I) -> RatFunc {
        balanced(iter, RatFunc::zero(), RatFunc::add_owned)
    }
}

impl<'a> std::iter::Sum<&'a RatFunc> for RatFunc {
    /// The sum, added as a balanced tree.
    fn sum<I: Iterator<Item = &'a RatFunc>>(iter: I) -> RatFunc {
        iter.cloned().sum()
    }
}

impl std::iter::Product for RatFunc {
    /// The product, multiplied as a balanced tree.
    fn product<I: Iterator<Item = RatFunc>>(iter: I) -> RatFunc {
        balanced(iter, RatFunc::one(), RatFunc::mul_owned)
    }
}

impl<'a> std::iter::Product<&'a RatFunc> for RatFunc {
    /// The product, multiplied as a balanced tree.
    fn product<I: Iterator<Item = &'a RatFunc>>(iter: I) -> RatFunc {
        iter.cloned().product()
    }
}

impl Default for RatFunc {
    /// Zero.
    fn default() -> Self {
        RatFunc::zero()
    }
}

impl std::ops::Neg for RatFunc {
    type Output = RatFunc;
    fn neg(self) -> RatFunc {
        RatFunc {
            num: -self.num,
            den: self.den,
        }
    }
}

impl std::ops::Neg for &RatFunc {
    type Output = RatFunc;
    fn neg(self) -> RatFunc {
        RatFunc {
            num: -&self.num,
            den: self.den.clone(),
        }
    }
}

impl From<Symbol> for RatFunc {
    fn from(s: Symbol) -> Self {
        RatFunc::symbol(s)
    }
}

impl From<Poly> for RatFunc {
    fn from(p: Poly) -> Self {
        RatFunc::from_poly(p)
    }
}

impl From<i64> for RatFunc {
    fn from(n: i64) -> Self {
        RatFunc::integer(n)
    }
}

super::forward_binops!(
    RatFunc, add_ref, sub_ref, mul_ref, add_owned, sub_owned, mul_owned
);

#[cfg(test)]
mod tests {
    use super::*;

    fn s(i: u32) -> RatFunc {
        RatFunc::symbol(Symbol(i))
    }

    fn n(k: i64) -> RatFunc {
        RatFunc::integer(k)
    }

    fn q(num: i64, den: i64) -> RatFunc {
        RatFunc::rational(BigInt::from(num), BigInt::from(den)).unwrap()
    }

    fn div(a: &RatFunc, b: &RatFunc) -> RatFunc {
        a.checked_div(b).unwrap()
    }

    fn p(i: u32) -> Poly {
        Poly::symbol(Symbol(i))
    }

    fn pk(k: i64) -> Poly {
        Poly::constant(BigInt::from(k))
    }

    #[test]
    fn rationals_are_reduced_with_positive_denominator() {
        assert_eq!(
            q(6, -4).to_constant(),
            Some((BigInt::from(-3), BigInt::from(2)))
        );
        assert_eq!(q(0, -5), RatFunc::zero());
        assert_eq!(RatFunc::rational(BigInt::from(1), BigInt::from(0)), None);
        assert_eq!(q(4, 2), n(2));
        assert!(q(7, 7).is_one());
        assert!(q(1, 3).is_constant());
        assert_eq!(q(1, 2) + q(1, 3), q(5, 6));
        assert_eq!(q(1, 6) + q(1, 3), q(1, 2));
        assert_eq!(q(2, 3) * q(9, 4), q(3, 2));
    }

    #[test]
    fn decimals() {
        assert_eq!(RatFunc::from_decimal("0.5"), Some(q(1, 2)));
        assert_eq!(RatFunc::from_decimal("1e-3"), Some(q(1, 1000)));
        assert_eq!(RatFunc::from_decimal("2.5E+2"), Some(n(250)));
        assert_eq!(RatFunc::from_decimal("5."), Some(n(5)));
        assert_eq!(RatFunc::from_decimal(".25"), Some(q(1, 4)));
        assert_eq!(RatFunc::from_decimal("abc"), None);
        assert_eq!(RatFunc::from_decimal("1e500"), None);
    }

    #[test]
    fn canonical_form_examples() {
        let (a, b) = (s(0), s(1));
        // (2a)/(4b) has numerator a and denominator 2b.
        let r = div(&(n(2) * &a), &(n(4) * &b));
        assert_eq!(r.numerator(), &p(0));
        assert_eq!(r.denominator(), &(pk(2) * p(1)));
        // 0.5 * b has numerator b and denominator 2.
        let r = RatFunc::from_decimal("0.5").unwrap() * &b;
        assert_eq!(r.numerator(), &p(1));
        assert_eq!(r.denominator(), &pk(2));
        // (a^2 - b^2)/(a + b) = a - b, a polynomial.
        let r = div(&(&a * &a - &b * &b), &(&a + &b));
        assert_eq!(r, &a - &b);
        assert!(r.denominator().is_one());
        // (x y + x)/(x z) = (y + 1)/z
        let (x, y, z) = (s(0), s(1), s(2));
        let r = div(&(&x * &y + &x), &(&x * &z));
        assert_eq!(r.numerator(), &(p(1) + pk(1)));
        assert_eq!(r.denominator(), &p(2));
        // A negative denominator moves its sign up: a/(-b) = -a/b.
        let r = div(&a, &-&b);
        assert_eq!(r.numerator(), &-p(0));
        assert_eq!(r.denominator(), &p(1));
        // Zero is 0/1.
        let r = div(&(&a - &a), &b);
        assert_eq!(r.numerator(), &Poly::zero());
        assert_eq!(r.denominator(), &Poly::one());
    }

    #[test]
    fn equal_values_built_differently_are_structurally_equal() {
        let (a, b, x, y) = (s(0), s(1), s(2), s(3));
        // a/(a b + a) == 1/(b + 1)
        assert_eq!(div(&a, &(&a * &b + &a)), div(&n(1), &(&b + n(1))));
        // (a^2 - b^2)/(a - b) == a + b
        assert_eq!(div(&(&a * &a - &b * &b), &(&a - &b)), &a + &b);
        // x/(x + y) + y/(x + y) == 1
        let d = &x + &y;
        assert_eq!(div(&x, &d) + div(&y, &d), n(1));
        // 1/a - 1/b == (b - a)/(a b)
        assert_eq!(div(&n(1), &a) - div(&n(1), &b), div(&(&b - &a), &(&a * &b)));
        // 1/(a (a + b)) + 1/(b (a + b)) == 1/(a b): Henrici with a shared factor that
        // cancels.
        let ab = &a + &b;
        assert_eq!(
            div(&n(1), &(&a * &ab)) + div(&n(1), &(&b * &ab)),
            div(&n(1), &(&a * &b))
        );
        // (a/b) * (b/a) == 1 and (2a/3) * (3/(4a)) == 1/2
        assert!((div(&a, &b) * div(&b, &a)).is_one());
        assert_eq!(div(&(n(2) * &a), &n(3)) * div(&n(3), &(n(4) * &a)), q(1, 2));
    }

    #[test]
    fn division_by_zero_and_powers() {
        let (a, b) = (s(0), s(1));
        assert_eq!(a.checked_div(&RatFunc::zero()), None);
        assert_eq!(RatFunc::zero().inv(), None);
        assert_eq!(RatFunc::zero().powi(-1), None);
        assert_eq!(RatFunc::zero().powi(0), Some(n(1)));
        assert_eq!(div(&a, &b).inv(), Some(div(&b, &a)));
        assert_eq!((-&a).inv(), Some(div(&n(-1), &a)));
        assert_eq!(div(&a, &b).powi(-2), Some(div(&(&b * &b), &(&a * &a))));
        assert_eq!(q(-2, 3).powi(3), Some(q(-8, 27)));
        assert_eq!(q(-2, 3).powi(-3), Some(q(-27, 8)));
        assert_eq!(
            a.powi(i32::MIN).map(|r| r.denominator().degree()),
            Some(1 << 31)
        );
        assert_eq!((&a + &b).powi(i32::MAX), None);
    }

    #[test]
    fn assign_operators_and_symbols() {
        let (a, b) = (s(0), s(3));
        let mut r = a.clone();
        r += &b;
        r *= n(2);
        r -= a.clone();
        assert_eq!(r, &a + n(2) * &b);
        assert_eq!(r.symbols(), BTreeSet::from([Symbol(0), Symbol(3)]));
        assert!(n(5).symbols().is_empty());
    }

    #[test]
    fn evaluation() {
        let (a, b) = (s(0), s(1));
        // (a + 1)/(2b) at a = 3, b = 0.5: 4/1 = 4
        let r = div(&(&a + n(1)), &(n(2) * &b));
        assert_eq!(r.eval(&[3.0, 0.5]), 4.0);
        assert!(r.eval(&[3.0, 0.0]).is_infinite());
        assert!(div(&a, &b).eval(&[0.0, 0.0]).is_nan());
        assert!(r.eval(&[]).is_nan());
    }

    /// `x` within a few rounding errors of `expected`.
    fn close(x: f64, expected: f64) -> bool {
        (x - expected).abs() <= 4.0 * f64::EPSILON * expected.abs()
    }

    #[test]
    fn evaluation_does_not_overflow_in_between() {
        let (b1, b2, m) = (s(0), s(1), s(2));
        // Two dampers in series: b1*b2/(b1 + b2). At b1 = 1e308, b2 = 3 the product b1*b2
        // = 3e308 overflows, but the value is 3/(1 + 3e-308): 3 to double precision.
        let series = div(&(&b1 * &b2), &(&b1 + &b2));
        let value = series.eval(&[1e308, 3.0]);
        assert!(close(value, 3.0), "{value}");
        // Its inverse (b1 + b2)/(b1*b2) = 1/3 + 1e-308: 1/3 to double precision.
        let inverse = div(&(&b1 + &b2), &(&b1 * &b2));
        let value = inverse.eval(&[1e308, 3.0]);
        assert!(close(value, 1.0 / 3.0), "{value}");
        // Underflow in between: b1*b2/m^2 at 1e-200 each is 1 (each product is 1e-400).
        let ratio = div(&(&b1 * &b2), &(&m * &m));
        let value = ratio.eval(&[1e-200, 1e-200, 1e-200]);
        assert!(close(value, 1.0), "{value}");
        // Powers of two are exact: m^3/b1^2 at 2^700 each is 2^700 (m^3 = 2^2100 alone
        // overflows).
        let big = 2f64.powi(700);
        let power = div(&(&m * &m * &m), &(&b1 * &b1));
        assert_eq!(power.eval(&[big, 0.0, big]), big);
        // A value that truly overflows is still infinite, with its sign ...
        let product = -(&b1 * &b2);
        assert_eq!(product.eval(&[1e308, 3.0]), f64::NEG_INFINITY);
        let reciprocal = div(&n(1), &(&b1 * &b2));
        assert_eq!(reciprocal.eval(&[1e-200, 1e-200]), f64::INFINITY);
        // ... and one that truly underflows is zero.
        assert_eq!(reciprocal.eval(&[1e200, 1e200]), 0.0);
    }

    #[test]
    fn sum_and_product_of_iterators() {
        let terms: Vec<RatFunc> = (0..7).map(|i| div(&s(i), &s(i + 10))).collect();
        let mut sequential = RatFunc::zero();
        for t in &terms {
            sequential += t;
        }
        assert_eq!(terms.iter().sum::<RatFunc>(), sequential);
        assert_eq!(
            Vec::<RatFunc>::new().into_iter().sum::<RatFunc>(),
            RatFunc::zero()
        );
        let mut product = RatFunc::one();
        for t in &terms {
            product *= t;
        }
        assert_eq!(terms.iter().product::<RatFunc>(), product);
        assert_eq!(
            std::iter::empty::<RatFunc>().product::<RatFunc>(),
            RatFunc::one()
        );
        // prod_{i=1}^{5} (i + 1)/i telescopes to 6.
        let telescoping: RatFunc = (1..=5).map(|i| q(i + 1, i)).product();
        assert_eq!(telescoping, n(6));
    }

    /// Symbols `k_1..k_n, m_1..m_n` named so that the table's print order scatters the
    /// `m_i` (`m_1 < m_10 < m_100 < ...`), as in a real model.
    fn k_over_m(count: usize) -> (Vec<RatFunc>, Vec<f64>) {
        let names: Vec<String> = (1..=count)
            .flat_map(|i| [format!("k_{i}"), format!("m_{i}")])
            .collect();
        let table = super::super::SymbolTable::new(names);
        let mut values = vec![0.0; table.len()];
        let terms = (1..=count)
            .map(|i| {
                let k = table.get(&format!("k_{i}")).unwrap();
                let m = table.get(&format!("m_{i}")).unwrap();
                // k_i = i and m_i alternating 1/2 and 2, so that the product of the m_i (the
                // denominator) stays representable in f64.
                values[k.index()] = i as f64;
                values[m.index()] = if i % 2 == 0 { 2.0 } else { 0.5 };
                div(&RatFunc::symbol(k), &RatFunc::symbol(m))
            })
            .collect();
        (terms, values)
    }

    #[test]
    fn long_sum_with_distinct_denominators() {
        // sum_{i=1}^{n} k_i / m_i over distinct symbols is one fraction over m_1 ... m_n,
        // whose numerator has n terms of n symbols each.
        let count = 2000;
        let (terms, values) = k_over_m(count);
        let sum: RatFunc = terms.iter().sum();
        assert_eq!(sum.numerator().term_count(), count);
        assert_eq!(sum.denominator().term_count(), 1);
        assert_eq!(sum.denominator().degree(), count as u32);
        // Odd i contribute i / (1/2) = 2i, even i contribute i/2:
        // 2 (1 + 3 + ... + 1999) + (2 + 4 + ... + 2000)/2 = 2 * 1000^2 + 1000 * 1001 / 2.
        let expected = 2.0 * 1000.0 * 1000.0 + 1000.0 * 1001.0 / 2.0;
        assert!((sum.eval(&values) - expected).abs() <= 1e-9 * expected);
    }

    #[test]
    fn sequential_sum_agrees_and_cancels() {
        let count = 300;
        let (terms, values) = k_over_m(count);
        let mut sum = RatFunc::zero();
        for t in &terms {
            sum += t;
        }
        assert_eq!(sum, terms.iter().sum());
        // 2 (1 + 3 + ... + 299) + (2 + 4 + ... + 300)/2 = 2 * 150^2 + 150 * 151 / 2
        let expected = 2.0 * 150.0 * 150.0 + 150.0 * 151.0 / 2.0;
        assert!((sum.eval(&values) - expected).abs() <= 1e-9 * expected);
        for t in terms.iter().rev() {
            sum -= t;
        }
        assert!(sum.is_zero());
        assert!(sum.denominator().is_one());
    }
}
