//! Monomials (`a^2*b`) and the term order.
//!
//! A monomial is stored sparsely, as the symbols that occur in it with their exponents:
//! models have thousands of symbols, and a term mentions a handful of them.
//!
//! The term order is lexicographic with the smaller symbol id as the more significant
//! variable: `a^2 > a*b > a > b^2 > b > 1`. Sorting terms from greatest to smallest
//! therefore prints them alphabetically, higher powers first and constants last.

use std::cmp::Ordering;

use super::Symbol;

/// A product of symbol powers, as (symbol, exponent) pairs sorted by symbol with every
/// exponent at least 1. The empty product is the monomial 1.
///
/// `Ord` is the term order: `a.cmp(&b) == Greater` when `a` prints before `b`.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct Monomial(Vec<(Symbol, u32)>);

impl Monomial {
    /// The monomial 1.
    pub fn one() -> Self {
        Monomial(Vec::new())
    }

    /// A single symbol to the first power.
    pub fn symbol(s: Symbol) -> Self {
        Monomial(vec![(s, 1)])
    }

    /// The product of the given symbol powers, in any order; repeated symbols are
    /// multiplied and zero exponents dropped.
    pub fn new(factors: impl IntoIterator<Item = (Symbol, u32)>) -> Self {
        let mut pairs: Vec<(Symbol, u32)> = factors.into_iter().filter(|&(_, e)| e > 0).collect();
        pairs.sort_unstable_by_key(|&(s, _)| s);
        let mut merged: Vec<(Symbol, u32)> = Vec::with_capacity(pairs.len());
        for (s, e) in pairs {
            match merged.last_mut() {
                Some((last, exp)) if *last == s => *exp = exp.saturating_add(e),
                _ => merged.push((s, e)),
            }
        }
        Monomial(merged)
    }

    /// Whether this is the monomial 1.
    pub fn is_one(&self) -> bool {
        self.0.is_empty()
    }

    /// The (symbol, exponent) pairs, by increasing symbol id.
    pub fn iter(&self) -> impl Iterator<Item = (Symbol, u32)> + '_ {
        self.0.iter().copied()
    }

    /// The exponent of `s` (0 when `s` does not occur).
    pub fn exponent(&self, s: Symbol) -> u32 {
        self.0
            .binary_search_by_key(&s, |&(t, _)| t)
            .map_or(0, |i| self.0[i].1)
    }

    /// The total degree: the sum of the exponents (saturating at `u32::MAX`).
    pub fn degree(&self) -> u32 {
        self.0
            .iter()
            .fold(0u32, |acc, &(_, e)| acc.saturating_add(e))
    }

    /// The product of two monomials. Exponents saturate at `u32::MAX` instead of
    /// overflowing (far beyond anything a model writes).
    pub(crate) fn mul(&self, other: &Monomial) -> Monomial {
        if other.is_one() {
            return self.clone();
        }
        if self.is_one() {
            return other.clone();
        }
        let (a, b) = (&self.0, &other.0);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a[i].0.cmp(&b[j].0) {
                Ordering::Less => {
                    out.push(a[i]);
                    i += 1;
                }
                Ordering::Greater => {
                    out.push(b[j]);
                    j += 1;
                }
                Ordering::Equal => {
                    out.push((a[i].0, a[i].1.saturating_add(b[j].1)));
                    i += 1;
                    j += 1;
                }
            }
        }
        out.extend_from_slice(&a[i..]);
        out.extend_from_slice(&b[j..]);
        Monomial(out)
    }

    /// `self *= other`, in place; cheap when `other` is a single symbol power.
    pub(crate) fn mul_assign(&mut self, other: &Monomial) {
        match other.0.as_slice() {
            [] => {}
            [(s, e)] => match self.0.binary_search_by_key(s, |&(t, _)| t) {
                Ok(i) => self.0[i].1 = self.0[i].1.saturating_add(*e),
                Err(i) => self.0.insert(i, (*s, *e)),
            },
            _ => *self = self.mul(other),
        }
    }

    /// `self /= other` in place if `other` divides `self`; returns whether it did (and
    /// leaves `self` unchanged if not).
    pub(crate) fn div_assign(&mut self, other: &Monomial) -> bool {
        match other.0.as_slice() {
            [] => true,
            [(s, e)] => match self.0.binary_search_by_key(s, |&(t, _)| t) {
                Ok(i) => match self.0[i].1.cmp(e) {
                    Ordering::Less => false,
                    Ordering::Equal => {
                        self.0.remove(i);
                        true
                    }
                    Ordering::Greater => {
                        self.0[i].1 -= e;
                        true
                    }
                },
                Err(_) => false,
            },
            _ => match self.div(other) {
                Some(q) => {
                    *self = q;
                    true
                }
                None => false,
            },
        }
    }

    /// `self / other` if `other` divides `self`.
    pub(crate) fn div(&self, other: &Monomial) -> Option<Monomial> {
        if other.is_one() {
            return Some(self.clone());
        }
        let mut out = Vec::with_capacity(self.0.len());
        let mut j = 0;
        for &(s, e) in &self.0 {
            if j < other.0.len() && other.0[j].0 < s {
                return None; // `other` has a symbol that `self` lacks
            }
            if j < other.0.len() && other.0[j].0 == s {
                let f = other.0[j].1;
                j += 1;
                match e.checked_sub(f) {
                    None => return None,
                    Some(0) => {}
                    Some(d) => out.push((s, d)),
                }
            } else {
                out.push((s, e));
            }
        }
        (j == other.0.len()).then_some(Monomial(out))
    }

    /// Whether `self` divides `other`.
    pub(crate) fn divides(&self, other: &Monomial) -> bool {
        self.0.iter().all(|&(s, e)| other.exponent(s) >= e)
    }

    /// The greatest common divisor: each shared symbol to its smaller exponent.
    pub(crate) fn gcd(&self, other: &Monomial) -> Monomial {
        let mut out = Vec::new();
        let (a, b) = (&self.0, &other.0);
        let (mut i, mut j) = (0, 0);
        while i < a.len() && j < b.len() {
            match a[i].0.cmp(&b[j].0) {
                Ordering::Less => i += 1,
                Ordering::Greater => j += 1,
                Ordering::Equal => {
                    out.push((a[i].0, a[i].1.min(b[j].1)));
                    i += 1;
                    j += 1;
                }
            }
        }
        Monomial(out)
    }

    /// `self^n`, or `None` if an exponent would overflow `u32`.
    pub(crate) fn pow(&self, n: u32) -> Option<Monomial> {
        self.0
            .iter()
            .map(|&(s, e)| e.checked_mul(n).map(|e| (s, e)))
            .filter(|r| r.is_none_or(|(_, e)| e > 0))
            .collect::<Option<Vec<_>>>()
            .map(Monomial)
    }

    /// Splits off the power of `s`: `(e, m)` with `self = s^e * m`.
    pub(crate) fn split_off(&self, s: Symbol) -> (u32, Monomial) {
        match self.0.binary_search_by_key(&s, |&(t, _)| t) {
            Ok(i) => {
                let mut rest = self.0.clone();
                let (_, e) = rest.remove(i);
                (e, Monomial(rest))
            }
            Err(_) => (0, self.clone()),
        }
    }
}

impl Ord for Monomial {
    /// Lexicographic order, smaller symbol id most significant, higher exponent greater.
    fn cmp(&self, other: &Self) -> Ordering {
        let mut a = self.0.iter();
        let mut b = other.0.iter();
        loop {
            match (a.next(), b.next()) {
                (None, None) => return Ordering::Equal,
                (Some(_), None) => return Ordering::Greater,
                (None, Some(_)) => return Ordering::Less,
                (Some(&(s, e)), Some(&(t, f))) => {
                    if s != t {
                        // The side with the smaller symbol has it; the other side has it to
                        // the power 0.
                        return t.cmp(&s);
                    }
                    if e != f {
                        return e.cmp(&f);
                    }
                }
            }
        }
    }
}

impl PartialOrd for Monomial {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Symbol = Symbol(0);
    const B: Symbol = Symbol(1);
    const C: Symbol = Symbol(2);

    fn m(pairs: &[(Symbol, u32)]) -> Monomial {
        Monomial::new(pairs.iter().copied())
    }

    #[test]
    fn term_order_is_lex_with_smaller_ids_first() {
        // a^2 > a*b > a > b^2 > b > 1, and a*c < a*b.
        let chain = [
            m(&[(A, 2)]),
            m(&[(A, 1), (B, 1)]),
            m(&[(A, 1), (C, 1)]),
            m(&[(A, 1)]),
            m(&[(B, 2)]),
            m(&[(B, 1)]),
            Monomial::one(),
        ];
        for pair in chain.windows(2) {
            assert!(pair[0] > pair[1], "{:?} should be > {:?}", pair[0], pair[1]);
        }
    }

    #[test]
    fn new_sorts_merges_and_drops_zero_exponents() {
        let x = Monomial::new([(B, 1), (A, 2), (B, 2), (C, 0)]);
        assert_eq!(x.iter().collect::<Vec<_>>(), [(A, 2), (B, 3)]);
        assert_eq!(x.degree(), 5);
        assert_eq!(x.exponent(B), 3);
        assert_eq!(x.exponent(C), 0);
    }

    #[test]
    fn multiplication_division_and_gcd() {
        let x = m(&[(A, 2), (B, 1)]);
        let y = m(&[(B, 2), (C, 1)]);
        assert_eq!(x.mul(&y), m(&[(A, 2), (B, 3), (C, 1)]));
        assert_eq!(x.mul(&y).div(&y), Some(x.clone()));
        assert_eq!(x.div(&y), None);
        assert_eq!(m(&[(A, 1)]).div(&m(&[(B, 1)])), None);
        assert_eq!(x.div(&x), Some(Monomial::one()));
        assert_eq!(x.gcd(&y), m(&[(B, 1)]));
        assert!(m(&[(B, 1)]).divides(&x));
        assert!(!y.divides(&x));
        assert_eq!(x.pow(3), Some(m(&[(A, 6), (B, 3)])));
        assert_eq!(x.pow(0), Some(Monomial::one()));
        assert_eq!(x.pow(u32::MAX), None);
        assert_eq!(x.split_off(B), (1, m(&[(A, 2)])));
        let mut z = x.clone();
        z.mul_assign(&m(&[(C, 2)]));
        z.mul_assign(&m(&[(A, 1)]));
        assert_eq!(z, m(&[(A, 3), (B, 1), (C, 2)]));
        z.mul_assign(&y);
        assert_eq!(z, m(&[(A, 3), (B, 3), (C, 3)]));
        assert!(z.div_assign(&m(&[(C, 3)])));
        assert!(z.div_assign(&m(&[(B, 1)])));
        assert!(!z.div_assign(&m(&[(B, 3)])));
        assert!(!z.div_assign(&m(&[(C, 1)])));
        assert!(z.div_assign(&m(&[(A, 1), (B, 2)])));
        assert!(!z.div_assign(&m(&[(A, 1), (C, 1)])));
        assert_eq!(z, m(&[(A, 2)]));
        assert_eq!(x.split_off(C), (0, x.clone()));
    }
}
