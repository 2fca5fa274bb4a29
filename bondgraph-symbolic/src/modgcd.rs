//! Brown's dense modular gcd (Geddes, Czapor & Labahn, *Algorithms for Computer Algebra*,
//! algorithms 7.1 and 7.2), used by [`super::gcd`] for the hard core of a gcd: two
//! primitive polynomials in the same symbols, all of which the gcd may contain.
//!
//! Over Z, the gcd is computed modulo several primes and combined by the Chinese remainder
//! theorem; modulo a prime, the last symbol is evaluated at several points, the gcds of the
//! images (one symbol fewer, recursively) are interpolated. Unlucky primes and points show
//! up as images whose leading monomial is too large and are discarded. Coefficient growth,
//! the weakness of remainder sequences, never happens.
//!
//! Every answer is checked by exact division, and its leading monomial equals that of the
//! modular images; since the leading monomial of the true gcd divides those of all images
//! (for primes and points that keep leading coefficients), a checked common divisor with
//! that leading monomial *is* the gcd. Failing the check only costs more primes or points;
//! running out of them returns `None`, and the caller falls back to a remainder sequence.

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Zero};

use super::modp::{self, Zp};
use super::poly::div_exact;
use super::{Monomial, Poly, Symbol};

/// Largest degree in any one symbol the algorithm accepts (its images are dense in one
/// symbol at a time).
pub(crate) const MAX_DEGREE: u32 = 4096;

/// A polynomial over Z_p: terms sorted greatest first in the term order, no zeros.
#[derive(Clone, Debug, PartialEq, Eq)]
struct PolyP {
    terms: Vec<(Monomial, u64)>,
}

/// The terms of a polynomial over Z_p grouped by their part without `x`, `x` being the
/// largest symbol: (rest monomial, dense coefficients in `x`), greatest rest first.
type Groups = Vec<(Monomial, Vec<u64>)>;

impl PolyP {
    fn zero() -> Self {
        PolyP { terms: Vec::new() }
    }

    fn from_poly(p: &Poly, f: Zp) -> Self {
        PolyP {
            terms: p
                .terms()
                .map(|(m, c)| (m.clone(), f.reduce(c)))
                .filter(|(_, c)| *c != 0)
                .collect(),
        }
    }

    fn leading_monomial(&self) -> Option<&Monomial> {
        self.terms.first().map(|(m, _)| m)
    }

    fn is_constant(&self) -> bool {
        self.leading_monomial().is_none_or(Monomial::is_one)
    }

    fn monic(mut self, f: Zp) -> Self {
        if let Some(&(_, lead)) = self.terms.first() {
            let inv = f.inv(lead);
            for (_, c) in &mut self.terms {
                *c = f.mul(*c, inv);
            }
        }
        self
    }

    fn scale(mut self, k: u64, f: Zp) -> Self {
        if k == 0 {
            return PolyP::zero();
        }
        for (_, c) in &mut self.terms {
            *c = f.mul(*c, k);
        }
        self
    }

    /// `self + k * other`.
    fn add_scaled(&self, other: &PolyP, k: u64, f: Zp) -> PolyP {
        let (a, b) = (&self.terms, &other.terms);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let order = match (a.get(i), b.get(j)) {
                (Some(x), Some(y)) => x.0.cmp(&y.0),
                (Some(_), None) => std::cmp::Ordering::Greater,
                (None, _) => std::cmp::Ordering::Less,
            };
            match order {
                std::cmp::Ordering::Greater => {
                    out.push(a[i].clone());
                    i += 1;
                }
                std::cmp::Ordering::Less => {
                    let c = f.mul(b[j].1, k);
                    if c != 0 {
                        out.push((b[j].0.clone(), c));
                    }
                    j += 1;
                }
                std::cmp::Ordering::Equal => {
                    let c = f.add(a[i].1, f.mul(b[j].1, k));
                    if c != 0 {
                        out.push((a[i].0.clone(), c));
                    }
                    i += 1;
                    j += 1;
                }
            }
        }
        PolyP { terms: out }
    }

    fn mul(&self, other: &PolyP, f: Zp) -> PolyP {
        let mut products = Vec::with_capacity(self.terms.len() * other.terms.len());
        for (am, ac) in &self.terms {
            for (bm, bc) in &other.terms {
                products.push((am.mul(bm), f.mul(*ac, *bc)));
            }
        }
        products.sort_unstable_by(|x, y| y.0.cmp(&x.0));
        let mut out: Vec<(Monomial, u64)> = Vec::with_capacity(products.len());
        for (m, c) in products {
            match out.last_mut() {
                Some((last, acc)) if *last == m => *acc = f.add(*acc, c),
                _ => {
                    if out.last().is_some_and(|(_, c)| *c == 0) {
                        out.pop();
                    }
                    out.push((m, c));
                }
            }
        }
        if out.last().is_some_and(|(_, c)| *c == 0) {
            out.pop();
        }
        PolyP { terms: out }
    }

    /// `self / d` if `d` divides `self` (long division in the term order, with the
    /// per-symbol degree bounds that make a failing division stop early).
    fn div_exact(&self, d: &PolyP, f: Zp) -> Option<PolyP> {
        let (lm_d, lc_d) = d.terms.first()?;
        let lc_inv = f.inv(*lc_d);
        let mut bounds: std::collections::BTreeMap<Symbol, u32> = Default::default();
        for (m, _) in &self.terms {
            for (s, e) in m.iter() {
                let bound = bounds.entry(s).or_insert(0);
                *bound = (*bound).max(e);
            }
        }
        for (m, _) in &d.terms {
            for (s, e) in m.iter() {
                if bounds.get(&s).is_none_or(|&bound| bound < e) {
                    return None;
                }
            }
        }
        let mut rem: std::collections::BTreeMap<Monomial, u64> =
            self.terms.iter().cloned().collect();
        let mut quotient = Vec::new();
        while let Some((m, c)) = rem.pop_last() {
            let qm = m.div(lm_d)?;
            if !qm
                .iter()
                .all(|(s, e)| bounds.get(&s).is_some_and(|&bound| e <= bound))
            {
                return None;
            }
            let qc = f.mul(c, lc_inv);
            for (dm, dc) in &d.terms[1..] {
                let entry = rem.entry(qm.mul(dm)).or_insert(0);
                *entry = f.sub(*entry, f.mul(qc, *dc));
                if *entry == 0 {
                    rem.remove(&qm.mul(dm));
                }
            }
            quotient.push((qm, qc));
        }
        Some(PolyP { terms: quotient })
    }

    /// Groups by the part without `x`, `x` being larger than every other symbol present,
    /// so that each group is contiguous.
    fn groups(&self, x: Symbol) -> Groups {
        let mut out: Groups = Vec::new();
        for (m, c) in &self.terms {
            let (e, rest) = m.split_off(x);
            let e = e as usize;
            match out.last_mut() {
                Some((last, dense)) if *last == rest => {
                    if dense.len() <= e {
                        dense.resize(e + 1, 0);
                    }
                    dense[e] = *c;
                }
                _ => {
                    let mut dense = vec![0; e + 1];
                    dense[e] = *c;
                    out.push((rest, dense));
                }
            }
        }
        out
    }

    fn from_groups(groups: &Groups, x: Symbol) -> PolyP {
        let mut terms = Vec::new();
        for (rest, dense) in groups {
            for (e, &c) in dense.iter().enumerate().rev() {
                if c != 0 {
                    let e = u32::try_from(e).unwrap_or(u32::MAX);
                    terms.push((rest.mul(&Monomial::new([(x, e)])), c));
                }
            }
        }
        PolyP { terms }
    }

    /// `self` with `x` (the largest symbol) set to `alpha`.
    fn eval_last(&self, x: Symbol, alpha: u64, f: Zp) -> PolyP {
        PolyP {
            terms: self
                .groups(x)
                .into_iter()
                .map(|(rest, dense)| (rest, modp::uni_eval(&dense, alpha, f)))
                .filter(|(_, c)| *c != 0)
                .collect(),
        }
    }
}

/// The content in Z_p[x] (monic gcd of the groups' coefficients) and the primitive part.
fn content_and_primitive_part(groups: &Groups, f: Zp) -> (Vec<u64>, Groups) {
    let mut content: Vec<u64> = Vec::new();
    for (_, dense) in groups {
        content = modp::uni_gcd(&content, dense, f);
        if content.len() == 1 {
            return (content, groups.clone());
        }
    }
    let primitive = groups
        .iter()
        .map(|(rest, dense)| {
            let q = modp::uni_div_exact(dense, &content, f).unwrap_or_default();
            (rest.clone(), q)
        })
        .collect();
    (content, primitive)
}

/// A budget of elementary steps, so that a pathological input gives up (and falls back to
/// a remainder sequence) instead of running for ever.
struct Budget(u64);

impl Budget {
    fn spend(&mut self, amount: usize) -> Option<()> {
        self.0 = self.0.checked_sub(amount as u64)?;
        Some(())
    }
}

/// The monic gcd of nonzero `a`, `b` over Z_p, whose symbols are among `vars` (sorted).
fn gcd_mod_p(a: &PolyP, b: &PolyP, vars: &[Symbol], f: Zp, budget: &mut Budget) -> Option<PolyP> {
    budget.spend(a.terms.len() + b.terms.len())?;
    let Some((&x, rest_vars)) = vars.split_last() else {
        return Some(PolyP {
            terms: vec![(Monomial::one(), 1)],
        });
    };
    let (ga, gb) = (a.groups(x), b.groups(x));
    if rest_vars.is_empty() {
        // Univariate: Euclid.
        let da = ga.first().map(|(_, d)| d.as_slice()).unwrap_or_default();
        let db = gb.first().map(|(_, d)| d.as_slice()).unwrap_or_default();
        budget.spend(da.len() * db.len())?;
        let g = modp::uni_gcd(da, db, f);
        return Some(PolyP::from_groups(&vec![(Monomial::one(), g)], x));
    }

    // Contents in Z_p[x] and primitive parts, seen as polynomials in the other symbols.
    let (ca, pa) = content_and_primitive_part(&ga, f);
    let (cb, pb) = content_and_primitive_part(&gb, f);
    let content = modp::uni_gcd(&ca, &cb, f);
    let content_poly = PolyP::from_groups(&vec![(Monomial::one(), content)], x);
    let (lead_a, lead_b) = (pa.first()?.1.clone(), pb.first()?.1.clone());
    let lead_gcd = modp::uni_gcd(&lead_a, &lead_b, f);
    let (pa, pb) = (PolyP::from_groups(&pa, x), PolyP::from_groups(&pb, x));
    let degree_x = |g: &Groups| {
        g.iter()
            .map(|(_, d)| modp::uni_degree(d))
            .max()
            .unwrap_or(0)
    };
    let limit =
        u64::from(degree_x(&ga).min(degree_x(&gb))) + u64::from(modp::uni_degree(&lead_gcd));

    // Interpolate the images' gcds in x, normalised to have leading coefficient
    // lead_gcd(alpha) so that they are images of one polynomial.
    let mut h: Option<PolyP> = None;
    let mut h_lead: Option<Monomial> = None;
    let mut q: Vec<u64> = vec![1];
    let attempts = 2 * limit + 16;
    for attempt in 0..attempts {
        let alpha = f.element(attempt ^ 0x5EED_0000);
        if modp::uni_eval(&lead_a, alpha, f) == 0 || modp::uni_eval(&lead_b, alpha, f) == 0 {
            continue;
        }
        if modp::uni_eval(&q, alpha, f) == 0 {
            continue; // a point already used
        }
        let image = gcd_mod_p(
            &pa.eval_last(x, alpha, f),
            &pb.eval_last(x, alpha, f),
            rest_vars,
            f,
            budget,
        )?;
        if image.is_constant() {
            // The primitive parts are coprime.
            return Some(content_poly.monic(f));
        }
        let image = image.scale(modp::uni_eval(&lead_gcd, alpha, f), f);
        // Compare with the leading monomial of the images interpolated so far (in the
        // symbols other than x).
        let restart = match &h {
            None => true,
            Some(_) => match image.leading_monomial().cmp(&h_lead.as_ref()) {
                std::cmp::Ordering::Less => true, // all earlier points were unlucky
                std::cmp::Ordering::Greater => continue, // this point is unlucky
                std::cmp::Ordering::Equal => false,
            },
        };
        let linear = vec![f.sub(0, alpha), 1]; // x - alpha
        if restart {
            h_lead = image.leading_monomial().cloned();
            h = Some(image);
            q = linear;
        } else if let Some(current) = h.take() {
            // Newton: h + (image - h(alpha)) * q / q(alpha).
            let difference = image.add_scaled(&current.eval_last(x, alpha, f), f.p_minus_one(), f);
            let k = f.inv(modp::uni_eval(&q, alpha, f));
            let correction = difference.mul(
                &PolyP::from_groups(&vec![(Monomial::one(), q.clone())], x),
                f,
            );
            budget.spend(correction.terms.len() + current.terms.len())?;
            h = Some(current.add_scaled(&correction, k, f));
            q = modp::uni_mul(&q, &linear, f);
        }
        if u64::from(modp::uni_degree(&q)) > limit {
            let candidate = h.as_ref()?;
            let (_, primitive) = content_and_primitive_part(&candidate.groups(x), f);
            let candidate = PolyP::from_groups(&primitive, x);
            budget.spend(candidate.terms.len() * (pa.terms.len() + pb.terms.len()))?;
            if pa.div_exact(&candidate, f).is_some() && pb.div_exact(&candidate, f).is_some() {
                return Some(candidate.mul(&content_poly, f).monic(f));
            }
        }
    }
    None
}

impl Zp {
    /// -1, to subtract with [`PolyP::add_scaled`].
    fn p_minus_one(self) -> u64 {
        self.modulus() - 1
    }
}

/// The symmetric representative of `c` modulo `m`.
fn symmetric(c: BigInt, m: &BigInt) -> BigInt {
    let c = c.mod_floor(m);
    if &c * 2 > *m { c - m } else { c }
}

/// The gcd of primitive nonzero polynomials over Z (positive leading coefficient), or
/// `None` if the modular computation gave up.
pub(crate) fn modular_gcd(a: &Poly, b: &Poly) -> Option<Poly> {
    let mut vars: Vec<Symbol> = a.symbols().union(&b.symbols()).copied().collect();
    vars.sort_unstable();
    let (lead_a, lead_b) = (a.leading_coefficient(), b.leading_coefficient());
    let lead_gcd = lead_a.gcd(&lead_b);
    let mut budget = Budget(20_000_000);

    let mut h: Option<Poly> = None;
    let mut modulus = BigInt::one();
    for &prime in modp::primes() {
        let f = Zp::new(prime);
        let p = BigInt::from(prime);
        if (&lead_a % &p).is_zero() || (&lead_b % &p).is_zero() {
            continue;
        }
        let image = gcd_mod_p(
            &PolyP::from_poly(a, f),
            &PolyP::from_poly(b, f),
            &vars,
            f,
            &mut budget,
        )?;
        if image.is_constant() {
            return Some(Poly::one());
        }
        let image = image.scale(f.reduce(&lead_gcd), f);
        let order = h.as_ref().map(|current| {
            image
                .leading_monomial()
                .cmp(&current.leading_term().map(|(m, _)| m))
        });
        match order {
            Some(std::cmp::Ordering::Greater) => continue, // unlucky prime
            None | Some(std::cmp::Ordering::Less) => {
                h = Some(Poly::from_terms(
                    image
                        .terms
                        .iter()
                        .map(|(m, c)| (m.clone(), symmetric(BigInt::from(*c), &p))),
                ));
                modulus = p;
                continue;
            }
            Some(std::cmp::Ordering::Equal) => {}
        }
        let Some(current) = h.take() else { continue };
        // Chinese remainders, coefficient by coefficient (absent terms are zero).
        let inv = BigInt::from(f.inv(f.reduce(&modulus)));
        let combined_modulus = &modulus * &p;
        let mut terms: std::collections::BTreeMap<Monomial, BigInt> = current
            .terms()
            .map(|(m, c)| (m.clone(), c.clone()))
            .collect();
        for (m, _) in &image.terms {
            terms.entry(m.clone()).or_default();
        }
        let residues: std::collections::HashMap<&Monomial, u64> =
            image.terms.iter().map(|(m, c)| (m, *c)).collect();
        let combined = Poly::from_terms(terms.into_iter().map(|(m, c)| {
            let r = BigInt::from(residues.get(&m).copied().unwrap_or(0));
            let t = ((r - &c) * &inv).mod_floor(&p);
            let value = symmetric(c + &modulus * t, &combined_modulus);
            (m, value)
        }));
        let stable = combined == current;
        h = Some(combined);
        modulus = combined_modulus;
        if stable {
            let candidate = h.as_ref()?;
            let content = candidate.content();
            let candidate = candidate
                .div_term(&Monomial::one(), &content)?
                .normalise_sign();
            if div_exact(a, &candidate).is_some() && div_exact(b, &candidate).is_some() {
                return Some(candidate);
            }
        }
    }
    None
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
    fn shared_factors() {
        let (x, y, z) = (s(0), s(1), s(2));
        let g = &x * &y - k(3) * &z + k(2);
        let a = &g * (&x + &y + &z);
        let b = &g * (&x * &x - &y * &z + k(1));
        assert_eq!(modular_gcd(&a, &b), Some(g.clone()));
        // A gcd with a large coefficient needs several primes.
        let big = Poly::constant(BigInt::from(10).pow(30));
        let g2 = &x * &y + &big * &z + k(1);
        let a2 = &g2 * (&x - &y);
        let b2 = &g2 * (&x + &z);
        assert_eq!(modular_gcd(&a2, &b2), Some(g2));
        // Coprime.
        assert_eq!(modular_gcd(&(&x + &y), &(&x - &y)), Some(Poly::one()));
    }

    #[test]
    fn univariate_and_powers() {
        let x = s(0);
        let y = s(1);
        let f = &x - &y;
        let a = &f * &f * &f * (&x + k(1));
        let b = &f * &f * (&x * &y + k(1));
        assert_eq!(modular_gcd(&a, &b), Some(&f * &f));
        let u = &x * &x - k(1);
        assert_eq!(
            modular_gcd(&u, &(&x * &x + k(2) * &x + k(1))),
            Some(&x + k(1))
        );
    }
}
