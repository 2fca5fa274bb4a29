//! Greatest common divisors of multivariate polynomials over the integers.
//!
//! The gcd is recursive on the symbols (Knuth, TAOCP vol. 2, 4.6.1; Geddes, Czapor &
//! Labahn, *Algorithms for Computer Algebra*, ch. 7), with cheap steps first because most
//! gcds in a model derivation are trivial:
//!
//! 1. Fast paths: a zero, a constant or a single-term argument (integer gcd of the
//!    contents, smallest exponent of each symbol), equal arguments.
//! 2. Split off the integer content and the monomial content of both arguments; the gcd is
//!    the gcd of those times the gcd of what is left.
//! 3. Symbols that occur in only one argument, say in `a`, cannot occur in a common divisor,
//!    which therefore divides every coefficient of `a` seen as a polynomial in them:
//!    `gcd(a, b) = gcd(b, coeff_0, coeff_1, ...)`, each with fewer symbols.
//! 4. Modular images bound the gcd's degree in each symbol (see `modp`); symbols with bound
//!    0 are split off the same way. If the argument of smaller degree may be the gcd, a trial
//!    division settles it.
//! 5. What is left, two primitive polynomials whose gcd may involve all their symbols, goes
//!    to Brown's modular algorithm (see `modgcd`), which avoids the coefficient growth of
//!    remainder sequences.
//! 6. If that gives up (or the dense problem is huge): view both as univariate in the
//!    symbol `x` with the smallest degree bound, coefficients in Z[other symbols];
//!    `gcd = gcd(contents) * gcd(primitive parts)`, a content being the recursive gcd of the
//!    coefficients, and the primitive parts' gcd the primitive part of the last nonzero
//!    term of the subresultant remainder sequence (built on pseudo-division).
//!
//! Every recursive call has fewer symbols in total and a remainder sequence strictly
//! lowers the degree in `x`, so the computation terminates; it is exact throughout.

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Signed};

use super::poly::div_exact;
use super::{Monomial, Poly, Symbol, modgcd, modp};

/// The greatest common divisor of two polynomials over the integers, normalised to a
/// positive leading coefficient. `gcd(0, 0) = 0` and `gcd(a, 0)` is `a` normalised.
pub fn gcd(a: &Poly, b: &Poly) -> Poly {
    gcd_normalised(a, b)
}

/// `a / d` for a `d` known to divide `a` (a divisor computed by [`gcd`]).
pub(crate) fn div_known(a: &Poly, d: &Poly) -> Poly {
    if d.is_one() {
        return a.clone();
    }
    // The divisor is exact by construction; `unwrap_or_default` only avoids a panic path.
    div_exact(a, d).unwrap_or_default()
}

/// `a / d` for a `d` known to divide `a`, reusing `a`'s storage when `d` is a single term.
pub(crate) fn div_known_owned(a: Poly, d: &Poly) -> Poly {
    if d.is_one() {
        return a;
    }
    match d.leading_term() {
        Some((m, c)) if d.term_count() == 1 => a.div_term_owned(m, c).unwrap_or_default(),
        _ => div_exact(&a, d).unwrap_or_default(),
    }
}

fn gcd_normalised(a: &Poly, b: &Poly) -> Poly {
    if a.is_zero() {
        return b.clone().normalise_sign();
    }
    if b.is_zero() {
        return a.clone().normalise_sign();
    }
    if a.is_constant() || b.is_constant() {
        let (c, p) = if a.is_constant() { (a, b) } else { (b, a) };
        let c = c.leading_coefficient().abs();
        if c.is_one() {
            return Poly::one();
        }
        return Poly::constant(int_gcd_with_content(c, p));
    }
    if a.term_count() == 1 || b.term_count() == 1 {
        let (t, p) = if a.term_count() == 1 { (a, b) } else { (b, a) };
        let Some((m, c)) = t.leading_term() else {
            return Poly::one();
        };
        let c = int_gcd_with_content(c.abs(), p);
        return Poly::term(p.monomial_gcd_with(m), c);
    }
    if a == b {
        return a.clone().normalise_sign();
    }

    // Split off integer and monomial contents.
    let (ca, ma) = (a.content(), a.monomial_content());
    let (cb, mb) = (b.content(), b.monomial_content());
    let a1 = strip(a, &ma, &ca);
    let b1 = strip(b, &mb, &cb);
    let g = gcd_stripped(&a1, &b1);
    g.mul_term(&ma.gcd(&mb), &ca.gcd(&cb))
}

/// `p / (c * m)` for a known integer and monomial content.
fn strip(p: &Poly, m: &Monomial, c: &BigInt) -> Poly {
    if m.is_one() && c.is_one() {
        p.clone()
    } else {
        p.div_term(m, c).unwrap_or_default()
    }
}

/// The positive gcd of the integer `c` and the coefficients of `p`.
fn int_gcd_with_content(mut c: BigInt, p: &Poly) -> BigInt {
    for (_, coefficient) in p.terms() {
        if c.is_one() {
            break;
        }
        c = c.gcd(coefficient);
    }
    c
}

/// The gcd of two polynomials without integer or monomial content.
fn gcd_stripped(a: &Poly, b: &Poly) -> Poly {
    // A constant without content is ±1; a single term without content is ±1.
    if a.term_count() <= 1 || b.term_count() <= 1 {
        return Poly::one();
    }
    if a == b {
        return a.clone().normalise_sign();
    }
    let (sa, sb) = (a.symbols(), b.symbols());
    let only_a: Vec<Symbol> = sa.difference(&sb).copied().collect();
    if !only_a.is_empty() {
        return gcd_with_coefficients(b, a, &only_a);
    }
    let only_b: Vec<Symbol> = sb.difference(&sa).copied().collect();
    if !only_b.is_empty() {
        return gcd_with_coefficients(a, b, &only_b);
    }

    // Bound the gcd's degree in each symbol by modular images. Symbols it cannot contain
    // are split off; of the others, the remainder sequence runs in the one where the gcd
    // has the smallest degree bound, which keeps it short.
    let mut free = Vec::new();
    let mut best: Option<(u32, u32, Symbol)> = None;
    for &x in &sa {
        match modp::gcd_degree_bound(a, b, x) {
            Some(0) => free.push(x),
            bound => {
                let key = (
                    bound.unwrap_or(u32::MAX),
                    a.degree_in(x).max(b.degree_in(x)),
                    x,
                );
                if best.is_none_or(|current| key < current) {
                    best = Some(key);
                }
            }
        }
    }
    let Some((bound, _, x)) = best else {
        // Free of every symbol: a constant, and the integer contents are gone.
        return Poly::one();
    };
    if !free.is_empty() {
        let mut parts = coefficients_in_all(a, &free);
        parts.extend(coefficients_in_all(b, &free));
        return gcd_of_all(parts);
    }

    // When the bound allows the argument of smaller degree to be the gcd, try dividing.
    let (da, db) = (a.degree_in(x), b.degree_in(x));
    if bound == db && db <= da && div_exact(a, b).is_some() {
        return b.clone().normalise_sign();
    }
    if bound == da && da <= db && div_exact(b, a).is_some() {
        return a.clone().normalise_sign();
    }

    // Brown's modular algorithm, when the dense problem it interpolates is not huge; the
    // subresultant sequence otherwise, or if it gives up.
    let dense_size: f64 = sa
        .iter()
        .map(|&v| f64::from(a.degree_in(v).min(b.degree_in(v))) + 2.0)
        .product();
    let max_degree = sa
        .iter()
        .map(|&v| a.degree_in(v).max(b.degree_in(v)))
        .max()
        .unwrap_or(0);
    if dense_size <= 1e6
        && max_degree <= modgcd::MAX_DEGREE
        && let Some(g) = modgcd::modular_gcd(a, b)
    {
        return g;
    }

    remainder_sequence_gcd(a, b, x, Sequence::Subresultant)
}

/// Which polynomial remainder sequence to run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sequence {
    Subresultant,
    #[cfg_attr(not(test), allow(dead_code))]
    Primitive,
}

/// The gcd of nonzero `a` and `b` seen as polynomials in `x`: the gcd of their contents
/// (recursively) times the gcd of their primitive parts by a remainder sequence.
fn remainder_sequence_gcd(a: &Poly, b: &Poly, x: Symbol, sequence: Sequence) -> Poly {
    let (fa, fb) = (UPoly::new(a, x), UPoly::new(b, x));
    let (cont_a, pp_a) = fa.content_and_primitive_part();
    let (cont_b, pp_b) = fb.content_and_primitive_part();
    let content = gcd_normalised(&cont_a, &cont_b);
    let primitive = match sequence {
        Sequence::Subresultant => subresultant_prs(pp_a, pp_b),
        Sequence::Primitive => primitive_prs(pp_a, pp_b),
    };
    (&content * &primitive).normalise_sign()
}

/// The coefficients of `p` seen as a polynomial in the symbols `vars` (with coefficients
/// in the other symbols), in no particular order.
fn coefficients_in_all(p: &Poly, vars: &[Symbol]) -> Vec<Poly> {
    let mut groups: std::collections::BTreeMap<Vec<u32>, Vec<(Monomial, BigInt)>> =
        std::collections::BTreeMap::new();
    for (m, c) in p.terms() {
        let mut rest = m.clone();
        let mut key = Vec::with_capacity(vars.len());
        for &s in vars {
            let (e, r) = rest.split_off(s);
            key.push(e);
            rest = r;
        }
        // Removing the same powers of `vars` from terms keeps their relative order.
        groups.entry(key).or_default().push((rest, c.clone()));
    }
    groups.into_values().map(Poly::from_canonical).collect()
}

/// `gcd(p, q)` where the symbols `vars` occur in `q` but not in `p`: the gcd of `p` and all
/// coefficients of `q` as a polynomial in `vars`.
fn gcd_with_coefficients(p: &Poly, q: &Poly, vars: &[Symbol]) -> Poly {
    let mut parts = coefficients_in_all(q, vars);
    parts.push(p.clone());
    gcd_of_all(parts)
}

/// The gcd of a list of polynomials, smallest first, stopping early at 1.
fn gcd_of_all(mut parts: Vec<Poly>) -> Poly {
    parts.sort_by_key(Poly::term_count);
    let mut iter = parts.into_iter();
    let Some(first) = iter.next() else {
        return Poly::zero();
    };
    let mut g = first.normalise_sign();
    for p in iter {
        if g.is_one() {
            break;
        }
        g = gcd_normalised(&g, &p);
    }
    g
}

/// A polynomial seen as univariate in `var`: nonzero coefficients (polynomials in the
/// other symbols) by decreasing exponent.
#[derive(Clone, Debug)]
struct UPoly {
    var: Symbol,
    coeffs: Vec<(u32, Poly)>,
}

impl UPoly {
    fn new(p: &Poly, var: Symbol) -> Self {
        let mut groups: std::collections::BTreeMap<u32, Vec<(Monomial, BigInt)>> =
            std::collections::BTreeMap::new();
        for (m, c) in p.terms() {
            let (e, rest) = m.split_off(var);
            // Removing the same power of `var` from terms keeps their relative order.
            groups.entry(e).or_default().push((rest, c.clone()));
        }
        UPoly {
            var,
            coeffs: groups
                .into_iter()
                .rev()
                .map(|(e, terms)| (e, Poly::from_canonical(terms)))
                .collect(),
        }
    }

    fn to_poly(&self) -> Poly {
        let mut terms = Vec::new();
        for (e, c) in &self.coeffs {
            let power = Monomial::new([(self.var, *e)]);
            terms.extend(c.terms().map(|(m, c)| (power.mul(m), c.clone())));
        }
        Poly::from_terms(terms)
    }

    fn is_zero(&self) -> bool {
        self.coeffs.is_empty()
    }

    fn degree(&self) -> u32 {
        self.coeffs.first().map_or(0, |(e, _)| *e)
    }

    fn leading(&self) -> Poly {
        self.coeffs
            .first()
            .map_or_else(Poly::zero, |(_, c)| c.clone())
    }

    /// The content (gcd of the coefficients, positive leading coefficient) and the
    /// primitive part.
    fn content_and_primitive_part(&self) -> (Poly, UPoly) {
        let content = gcd_of_all(self.coeffs.iter().map(|(_, c)| c.clone()).collect());
        if content.is_one() || content.is_zero() {
            return (content, self.clone());
        }
        let coeffs = self
            .coeffs
            .iter()
            .map(|(e, c)| (*e, div_known(c, &content)))
            .collect();
        (
            content,
            UPoly {
                var: self.var,
                coeffs,
            },
        )
    }

    /// `c * x^shift * self`.
    fn scaled(&self, c: &Poly, shift: u32) -> UPoly {
        UPoly {
            var: self.var,
            coeffs: self
                .coeffs
                .iter()
                .map(|(e, p)| (e.saturating_add(shift), p * c))
                .collect(),
        }
    }

    /// `self - other`.
    fn sub(&self, other: &UPoly) -> UPoly {
        let (a, b) = (&self.coeffs, &other.coeffs);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let ea = a.get(i).map(|(e, _)| *e);
            let eb = b.get(j).map(|(e, _)| *e);
            match (ea, eb) {
                (Some(x), Some(y)) if x == y => {
                    let d = &a[i].1 - &b[j].1;
                    if !d.is_zero() {
                        out.push((x, d));
                    }
                    i += 1;
                    j += 1;
                }
                (Some(x), Some(y)) if x > y => {
                    out.push(a[i].clone());
                    i += 1;
                }
                (Some(x), None) => {
                    out.push((x, a[i].1.clone()));
                    i += 1;
                }
                (_, Some(y)) => {
                    out.push((y, -&b[j].1));
                    j += 1;
                }
                (None, None) => break,
            }
        }
        UPoly {
            var: self.var,
            coeffs: out,
        }
    }

    /// The pseudo-remainder `prem(self, divisor)`: the remainder of
    /// `lc(divisor)^(deg self - deg divisor + 1) * self` divided by `divisor`, which has
    /// coefficients in the coefficient ring.
    fn pseudo_remainder(&self, divisor: &UPoly) -> UPoly {
        let db = divisor.degree();
        if self.degree() < db {
            return self.clone();
        }
        let lb = divisor.leading();
        let mut missing = self.degree() - db + 1;
        let mut r = self.clone();
        while !r.is_zero() && r.degree() >= db {
            let shift = r.degree() - db;
            let lr = r.leading();
            // The leading terms cancel: lb * lr * x^deg(r) on both sides.
            r = r.scaled(&lb, 0).sub(&divisor.scaled(&lr, shift));
            missing -= 1;
        }
        if missing > 0 && !r.is_zero() {
            match lb.pow(missing) {
                Some(factor) => r = r.scaled(&factor, 0),
                None => return r,
            }
        }
        r
    }

    /// Every coefficient divided exactly by `d`; `None` if one is not divisible.
    fn div_coefficients(&self, d: &Poly) -> Option<UPoly> {
        let coeffs = self
            .coeffs
            .iter()
            .map(|(e, c)| div_exact(c, d).map(|q| (*e, q)))
            .collect::<Option<Vec<_>>>()?;
        Some(UPoly {
            var: self.var,
            coeffs,
        })
    }
}

/// The gcd of two primitive polynomials in the same variable, by the subresultant PRS
/// (Collins; Brown and Traub): the remainder sequence divided at each step by a factor known
/// to divide it, which keeps coefficients small without any gcd computation; only the
/// last nonzero remainder's content is taken.
fn subresultant_prs(a: UPoly, b: UPoly) -> Poly {
    let (mut f, mut g) = if a.degree() >= b.degree() {
        (a, b)
    } else {
        (b, a)
    };
    let mut lead = Poly::one();
    let mut h = Poly::one();
    loop {
        if g.is_zero() {
            return f.content_and_primitive_part().1.to_poly().normalise_sign();
        }
        if g.degree() == 0 {
            // The gcd of primitive polynomials divides a nonzero element of the
            // coefficient ring, so it is a unit.
            return Poly::one();
        }
        let delta = f.degree() - g.degree();
        let r = f.pseudo_remainder(&g);
        if r.is_zero() {
            return g.content_and_primitive_part().1.to_poly().normalise_sign();
        }
        // The theory guarantees these divisions are exact; should one not be, fall back to
        // the primitive sequence rather than give a wrong answer.
        let Some(divisor) = h.pow(delta).map(|hd| &lead * &hd) else {
            return primitive_prs(f, g);
        };
        let Some(next) = r.div_coefficients(&divisor) else {
            return primitive_prs(f, g);
        };
        f = g;
        g = next;
        lead = f.leading();
        h = match delta {
            0 => h,
            1 => lead.clone(),
            _ => {
                let num = lead.pow(delta);
                let den = h.pow(delta - 1);
                match (num, den) {
                    (Some(num), Some(den)) => match div_exact(&num, &den) {
                        Some(q) => q,
                        None => return primitive_prs(f, g),
                    },
                    _ => return primitive_prs(f, g),
                }
            }
        };
    }
}

/// The gcd of two primitive polynomials in the same variable, by the primitive PRS: slower
/// than the subresultant sequence but needing no exact-division theorem.
fn primitive_prs(a: UPoly, b: UPoly) -> Poly {
    let (mut f, mut g) = if a.degree() >= b.degree() {
        (a, b)
    } else {
        (b, a)
    };
    loop {
        if g.is_zero() {
            return f.content_and_primitive_part().1.to_poly().normalise_sign();
        }
        if g.degree() == 0 {
            // A primitive polynomial of degree 0 is a unit.
            return Poly::one();
        }
        let r = f.pseudo_remainder(&g);
        f = g;
        g = r.content_and_primitive_part().1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(i: u32) -> Poly {
        Poly::symbol(Symbol(i))
    }

    fn k(n: i64) -> Poly {
        Poly::constant(BigInt::from(n))
    }

    #[test]
    fn trivial_cases() {
        assert_eq!(gcd(&Poly::zero(), &Poly::zero()), Poly::zero());
        assert_eq!(gcd(&(k(0) - s(0)), &Poly::zero()), s(0));
        assert_eq!(gcd(&Poly::zero(), &(k(-2) * s(0))), k(2) * s(0));
        assert_eq!(gcd(&k(12), &k(-18)), k(6));
        assert_eq!(gcd(&(s(0) + s(1)), &(s(0) + s(1))), s(0) + s(1));
        assert_eq!(gcd(&(s(1) - s(0)), &(s(1) - s(0))), s(0) - s(1));
    }

    #[test]
    fn content_only() {
        // gcd(6x + 6, 4) = 2
        assert_eq!(gcd(&(k(6) * s(0) + k(6)), &k(4)), k(2));
        // gcd(6x + 6, 4x) = 2
        assert_eq!(gcd(&(k(6) * s(0) + k(6)), &(k(4) * s(0))), k(2));
        // gcd(6x + 6, 9y + 9) = 3
        assert_eq!(gcd(&(k(6) * s(0) + k(6)), &(k(9) * s(1) + k(9))), k(3));
    }

    #[test]
    fn monomial_factors() {
        // gcd(x^2 y + x y^2, 2 x y^3) = x y
        let x = s(0);
        let y = s(1);
        let a = &x * &x * &y + &x * &y * &y;
        let b = k(2) * &x * &y * &y * &y;
        assert_eq!(gcd(&a, &b), &x * &y);
        // gcd(x^2 y + x y^2, x^3 y + x y^3) = x y
        let c = &x * &x * &x * &y + &x * &y * &y * &y;
        assert_eq!(gcd(&a, &c), &x * &y);
    }

    #[test]
    fn univariate_and_bivariate() {
        let x = s(0);
        let y = s(1);
        // gcd(x^2 - 1, x^2 + 2x + 1) = x + 1
        assert_eq!(
            gcd(&(&x * &x - k(1)), &(&x * &x + k(2) * &x + k(1))),
            &x + k(1)
        );
        // gcd((x + y)(x - y)^2, (x - y)(x + 2y)) = x - y
        let a = (&x + &y) * (&x - &y) * (&x - &y);
        let b = (&x - &y) * (&x + k(2) * &y);
        assert_eq!(gcd(&a, &b), &x - &y);
        // The sign is normalised: gcd(y - x, x^2 - y^2) = x - y.
        assert_eq!(gcd(&(&y - &x), &(&x * &x - &y * &y)), &x - &y);
    }

    #[test]
    fn three_and_four_variables() {
        let (x, y, z, w) = (s(0), s(1), s(2), s(3));
        // Shared factor (x y + z) in three variables.
        let f = &x * &y + &z;
        let a = &f * (&x + &z + k(1));
        let b = &f * (&y - k(2) * &z);
        assert_eq!(gcd(&a, &b), f.clone());
        // Shared factor (x z - y w + 3) * (w + 1), with different cofactors.
        let f2 = (&x * &z - &y * &w + k(3)) * (&w + k(1));
        let a2 = &f2 * (&x * &x + &y);
        let b2 = &f2 * (&z * &w - &x) * k(4);
        assert_eq!(gcd(&a2, &b2), f2.clone().normalise_sign());
        // Content times a shared factor: gcd(6 (x + y) z, 4 (x + y) w) = 2 (x + y)
        let a3 = k(6) * (&x + &y) * &z;
        let b3 = k(4) * (&x + &y) * &w;
        assert_eq!(gcd(&a3, &b3), k(2) * (&x + &y));
    }

    #[test]
    fn coprime_polynomials() {
        let (x, y, z) = (s(0), s(1), s(2));
        assert_eq!(gcd(&(&x + &y), &(&x - &y)), Poly::one());
        assert_eq!(gcd(&(&x * &y + k(1)), &(&x + &z)), Poly::one());
        assert_eq!(gcd(&(&x * &x + &y * &y), &(&x * &x * &y + &z)), Poly::one());
        // Symbols in only one argument: gcd(x y + x + 1, z + 2) = 1
        assert_eq!(gcd(&(&x * &y + &x + k(1)), &(&z + k(2))), Poly::one());
        // gcd(x y + x, x z) = x
        assert_eq!(gcd(&(&x * &y + &x), &(&x * &z)), x.clone());
        // gcd((y + 1) x + (y + 1), y + 1) = y + 1
        assert_eq!(gcd(&((&y + k(1)) * (&x + k(1))), &(&y + k(1))), &y + k(1));
    }

    #[test]
    fn huge_exponents_stay_sparse() {
        // x^(2^31) (x + y) and (x + y)(x - y): the modular algorithm, dense in one symbol,
        // must not be used; the sparse remainder sequence handles it.
        let (x, y) = (s(0), s(1));
        let huge = Poly::term(Monomial::new([(Symbol(0), 1 << 31)]), BigInt::one());
        let a = &huge * (&x + &y) + &x + &y;
        let b = (&x + &y) * (&x - &y);
        assert_eq!(gcd(&a, &b), &x + &y);
    }

    #[test]
    fn div_known_divides() {
        let (x, y) = (s(0), s(1));
        let a = (&x + &y) * (&x - &y);
        assert_eq!(div_known(&a, &(&x + &y)), &x - &y);
        assert_eq!(div_known(&a, &Poly::one()), a);
    }

    /// Small random polynomials in 3 symbols.
    fn small() -> impl proptest::strategy::Strategy<Value = Poly> {
        use proptest::prelude::*;
        let term = (prop::collection::vec(0u32..=2, 3), -4i64..=4);
        prop::collection::vec(term, 1..=4).prop_map(|terms| {
            Poly::from_terms(terms.into_iter().map(|(exponents, c)| {
                let m = Monomial::new(exponents.into_iter().zip(0..).map(|(e, i)| (Symbol(i), e)));
                (m, BigInt::from(c))
            }))
        })
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(128))]

        /// The remainder sequences (now only fallbacks) and the modular algorithm agree with
        /// each other and with `gcd`.
        #[test]
        fn all_algorithms_agree(a in small(), b in small(), c in small()) {
            let (a, b) = (&a * &c, &b * &c);
            proptest::prop_assume!(!a.is_zero() && !b.is_zero());
            let expected = gcd(&a, &b);
            for x in [Symbol(0), Symbol(2)] {
                proptest::prop_assert_eq!(
                    &remainder_sequence_gcd(&a, &b, x, Sequence::Subresultant),
                    &expected
                );
                proptest::prop_assert_eq!(
                    &remainder_sequence_gcd(&a, &b, x, Sequence::Primitive),
                    &expected
                );
            }
            let (pa, pb) = (strip(&a, &Monomial::one(), &a.content()), strip(&b, &Monomial::one(), &b.content()));
            let expected = gcd(&pa, &pb);
            if let Some(g) = modgcd::modular_gcd(&pa, &pb) {
                proptest::prop_assert_eq!(g, expected);
            }
        }
    }
}
