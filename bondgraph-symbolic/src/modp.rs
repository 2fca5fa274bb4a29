//! Arithmetic modulo a prime, dense univariate polynomials over Z_p, and cheap, rigorous
//! upper bounds on the degree of a gcd from modular images.
//!
//! The bound: reduce two polynomials `a`, `b` modulo a prime `p` and substitute values for
//! every symbol but `x`. If the leading coefficients in `x` survive (their images are
//! nonzero), then for any common divisor `g` of `a` and `b` the image of `g` divides both
//! images and keeps its degree in `x` (its leading coefficient divides theirs). So the
//! degree of the gcd of the images in Z_p[x] bounds `deg_x gcd(a, b)` from above. A bound of
//! 0 proves the gcd free of `x`, which is the common case (most pairs are coprime). An
//! unlucky evaluation can only make a bound too large, never too small, so results never
//! depend on it; only the speed does.

use std::sync::OnceLock;

use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::ToPrimitive;

use super::{Poly, Symbol};

/// Images are dense in `x`; larger degrees are not worth a bound.
const MAX_DEGREE: u32 = 4096;

/// The integers modulo a prime below 2^32 (so products fit `u64`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Zp {
    p: u64,
}

impl Zp {
    /// The field for the prime `p < 2^32` (primality is the caller's promise).
    pub(crate) fn new(p: u64) -> Self {
        Zp { p }
    }

    pub(crate) fn modulus(self) -> u64 {
        self.p
    }

    pub(crate) fn add(self, a: u64, b: u64) -> u64 {
        let s = a + b;
        if s >= self.p { s - self.p } else { s }
    }

    pub(crate) fn sub(self, a: u64, b: u64) -> u64 {
        if a >= b { a - b } else { a + self.p - b }
    }

    pub(crate) fn mul(self, a: u64, b: u64) -> u64 {
        a * b % self.p
    }

    pub(crate) fn pow(self, mut base: u64, mut e: u64) -> u64 {
        let mut acc = 1 % self.p;
        while e > 0 {
            if e & 1 == 1 {
                acc = self.mul(acc, base);
            }
            base = self.mul(base, base);
            e >>= 1;
        }
        acc
    }

    /// The inverse of a nonzero element (Fermat).
    pub(crate) fn inv(self, a: u64) -> u64 {
        self.pow(a, self.p - 2)
    }

    /// The residue of an integer.
    pub(crate) fn reduce(self, c: &BigInt) -> u64 {
        c.mod_floor(&BigInt::from(self.p)).to_u64().unwrap_or(0)
    }

    /// A deterministic pseudo-random element from a seed (SplitMix64).
    pub(crate) fn element(self, seed: u64) -> u64 {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        z % self.p
    }
}

/// Primes just below 2^31, largest first.
///
/// Found by a deterministic Miller–Rabin test rather than trial division: trial division
/// of the few thousand odd numbers below 2^31 that hold 256 primes took 15–25 ms, a fixed
/// cost of every process that merges storage; the test takes microseconds.
pub(crate) fn primes() -> &'static [u64] {
    static PRIMES: OnceLock<Vec<u64>> = OnceLock::new();
    PRIMES.get_or_init(|| {
        (1u64 << 20..1u64 << 31)
            .rev()
            .filter(|&n| is_prime(n))
            .take(256)
            .collect()
    })
}

/// Whether `n < 2^32` is prime: Miller–Rabin with the bases 2, 3, 5 and 7, which no
/// composite below 3,215,031,751 passes (Jaeschke, *Math. Comp.* 61, 1993), so the answer
/// is exact for every `n` this module asks about.
fn is_prime(n: u64) -> bool {
    debug_assert!(n < 1 << 32, "the bases are a proof only below 3.2e9");
    if n < 2 {
        return false;
    }
    for small in [2, 3, 5, 7] {
        if n.is_multiple_of(small) {
            return n == small;
        }
    }
    let (mut d, mut s) = (n - 1, 0);
    while d.is_multiple_of(2) {
        d /= 2;
        s += 1;
    }
    // Products of two residues below 2^32 fit in a u64.
    let mul = |a: u64, b: u64| a * b % n;
    let pow = |mut base: u64, mut e: u64| {
        let mut acc = 1;
        while e > 0 {
            if e & 1 == 1 {
                acc = mul(acc, base);
            }
            base = mul(base, base);
            e >>= 1;
        }
        acc
    };
    [2, 3, 5, 7].iter().all(|&a| {
        let mut x = pow(a, d);
        if x == 1 || x == n - 1 {
            return true;
        }
        (1..s).any(|_| {
            x = mul(x, x);
            x == n - 1
        })
    })
}

// Dense univariate polynomials over Z_p: coefficients by increasing exponent, no trailing
// zeros; zero is empty.

pub(crate) fn trim(p: &mut Vec<u64>) {
    while p.last() == Some(&0) {
        p.pop();
    }
}

/// `a mod b` (and, if asked, the quotient) for a nonzero trimmed `b`.
fn div_rem(mut a: Vec<u64>, b: &[u64], f: Zp, mut quotient: Option<&mut Vec<u64>>) -> Vec<u64> {
    trim(&mut a);
    let Some(&lead) = b.last() else {
        return a;
    };
    let lead_inv = f.inv(lead);
    if let Some(q) = quotient.as_deref_mut() {
        q.clear();
        q.resize((a.len() + 1).saturating_sub(b.len()), 0);
    }
    while a.len() >= b.len() {
        let Some(&top) = a.last() else { break };
        let shift = a.len() - b.len();
        if top != 0 {
            let c = f.mul(top, lead_inv);
            for (i, &bi) in b.iter().enumerate() {
                a[shift + i] = f.sub(a[shift + i], f.mul(c, bi));
            }
            if let Some(q) = quotient.as_deref_mut() {
                q[shift] = c;
            }
        }
        a.pop();
    }
    trim(&mut a);
    a
}

/// The monic gcd (zero if both are zero).
pub(crate) fn uni_gcd(a: &[u64], b: &[u64], f: Zp) -> Vec<u64> {
    let (mut a, mut b) = (a.to_vec(), b.to_vec());
    trim(&mut a);
    trim(&mut b);
    while !b.is_empty() {
        let r = div_rem(a, &b, f, None);
        a = b;
        b = r;
    }
    uni_monic(a, f)
}

/// `a / b` if `b` divides `a`.
pub(crate) fn uni_div_exact(a: &[u64], b: &[u64], f: Zp) -> Option<Vec<u64>> {
    let mut b = b.to_vec();
    trim(&mut b);
    if b.is_empty() {
        return None;
    }
    let mut q = Vec::new();
    let r = div_rem(a.to_vec(), &b, f, Some(&mut q));
    trim(&mut q);
    r.is_empty().then_some(q)
}

pub(crate) fn uni_monic(mut a: Vec<u64>, f: Zp) -> Vec<u64> {
    if let Some(&lead) = a.last() {
        let inv = f.inv(lead);
        for c in &mut a {
            *c = f.mul(*c, inv);
        }
    }
    a
}

pub(crate) fn uni_mul(a: &[u64], b: &[u64], f: Zp) -> Vec<u64> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut out = vec![0; a.len() + b.len() - 1];
    for (i, &x) in a.iter().enumerate() {
        if x == 0 {
            continue;
        }
        for (j, &y) in b.iter().enumerate() {
            out[i + j] = f.add(out[i + j], f.mul(x, y));
        }
    }
    trim(&mut out);
    out
}

pub(crate) fn uni_eval(a: &[u64], x: u64, f: Zp) -> u64 {
    a.iter().rev().fold(0, |acc, &c| f.add(f.mul(acc, x), c))
}

/// Degree of a nonzero trimmed polynomial.
pub(crate) fn uni_degree(a: &[u64]) -> u32 {
    u32::try_from(a.len().saturating_sub(1)).unwrap_or(u32::MAX)
}

/// The image of `p` in Z_p[x] (index = exponent of `x`), other symbols evaluated at
/// pseudo-random points.
fn image(p: &Poly, x: Symbol, degree: u32, attempt: u64, f: Zp) -> Vec<u64> {
    let mut out = vec![0; degree as usize + 1];
    for (m, c) in p.terms() {
        let mut value = f.reduce(c);
        let mut e_x = 0;
        for (s, e) in m.iter() {
            if s == x {
                e_x = e;
            } else {
                let point = f.element((u64::from(s.0) << 8) | attempt);
                value = f.mul(value, f.pow(point, u64::from(e)));
            }
        }
        if let Some(slot) = out.get_mut(e_x as usize) {
            *slot = f.add(*slot, value);
        }
    }
    trim(&mut out);
    out
}

/// An upper bound on the degree in `x` of `gcd(a, b)` for nonzero `a`, `b`, or `None` if
/// none was found cheaply (degree too large, or evaluations that kill a leading
/// coefficient).
pub(crate) fn gcd_degree_bound(a: &Poly, b: &Poly, x: Symbol) -> Option<u32> {
    let (da, db) = (a.degree_in(x), b.degree_in(x));
    if da > MAX_DEGREE || db > MAX_DEGREE || a.is_zero() || b.is_zero() {
        return None;
    }
    let f = Zp::new(*primes().first()?);
    for attempt in 0..2 {
        let ia = image(a, x, da, attempt, f);
        let ib = image(b, x, db, attempt, f);
        if ia.len() == da as usize + 1 && ib.len() == db as usize + 1 {
            return Some(uni_degree(&uni_gcd(&ia, &ib, f)));
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
    fn primes_are_prime() {
        let primes = primes();
        assert_eq!(primes[0], (1 << 31) - 1);
        assert!(primes.len() >= 100);
        assert!(primes.windows(2).all(|w| w[0] > w[1]));
        // 2^31 - 19 is the next prime below 2^31 - 1.
        assert_eq!(primes[1], (1 << 31) - 19);
    }

    #[test]
    fn the_prime_table_is_the_256_primes_below_2_31() {
        // The reference, from sympy 1.14 (`prevprime` from 2^31, 256 times): the last is
        // 2^31 - 5317, and the sum and a polynomial hash of the list, base 1000003 modulo
        // 2^61 - 1, are these.
        let primes = primes();
        assert_eq!(primes.len(), 256);
        assert_eq!(primes[255], (1 << 31) - 5317);
        assert_eq!(primes.iter().sum::<u64>(), 549_755_096_632);
        let modulus: u128 = (1 << 61) - 1;
        let hash = primes
            .iter()
            .fold(0u128, |h, &p| (h * 1_000_003 + p as u128) % modulus);
        assert_eq!(hash, 963_706_225_091_797_144);
    }

    /// Miller–Rabin against trial division on every number of two windows: the small
    /// numbers (where the bases themselves and their multiples sit) and the top of the
    /// range the table is drawn from, where it must find the same primes.
    #[test]
    fn miller_rabin_agrees_with_trial_division() {
        let by_division = |n: u64| {
            n >= 2
                && (2..)
                    .take_while(|d| d * d <= n)
                    .all(|d| !n.is_multiple_of(d))
        };
        for n in (0..20_000).chain((1 << 31) - 20_000..1 << 31) {
            assert_eq!(is_prime(n), by_division(n), "{n}");
        }
        // Strong pseudoprimes to the bases 2, 3 and 5 together (the smallest, 25,326,001),
        // and to 2 alone (2047, 3277), are composite.
        for n in [2047, 3277, 25_326_001, 3_215_031_751 - 2] {
            assert!(!is_prime(n) || by_division(n), "{n}");
        }
        assert!(!is_prime(25_326_001));
    }

    #[test]
    fn field_arithmetic() {
        let f = Zp::new(7);
        assert_eq!(f.mul(f.inv(3), 3), 1);
        assert_eq!(f.sub(1, 2), 6);
        assert_eq!(f.add(5, 4), 2);
        assert_eq!(f.pow(3, 6), 1);
        assert_eq!(f.reduce(&BigInt::from(-1)), 6);
        assert_eq!(f.modulus(), 7);
    }

    #[test]
    fn univariate() {
        let f = Zp::new(101);
        // (x + 1)(x + 2) and (x + 1)(x + 3): gcd x + 1
        let a = uni_mul(&[1, 1], &[2, 1], f);
        let b = uni_mul(&[1, 1], &[3, 1], f);
        assert_eq!(a, [2, 3, 1]);
        assert_eq!(uni_gcd(&a, &b, f), [1, 1]);
        assert_eq!(uni_div_exact(&a, &[1, 1], f), Some(vec![2, 1]));
        assert_eq!(uni_div_exact(&a, &[3, 1], f), None);
        assert_eq!(uni_eval(&a, 1, f), 6);
        assert_eq!(uni_monic(vec![2, 4], f), [51, 1]);
        assert_eq!(uni_gcd(&[], &[], f), Vec::<u64>::new());
        assert_eq!(uni_gcd(&[5], &a, f), [1]);
    }

    #[test]
    fn bounds() {
        let (x, y, z) = (s(0), s(1), s(2));
        // Coprime: the bound is 0 in every variable.
        let a = &x * &y + k(1);
        let b = &x + &y;
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(0)), Some(0));
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(1)), Some(0));
        // Shared factor x - y: degree 1 in x and in y, the cofactors don't matter.
        let f = &x - &y;
        let a = &f * &f * (&x + &z);
        let b = &f * (&x * &z + k(2));
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(0)), Some(1));
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(1)), Some(1));
        // A shared factor free of x: the bound in x is 0.
        let a = (&y + &z) * (&x + k(1));
        let b = (&y + &z) * (&x + k(2));
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(0)), Some(0));
        assert_eq!(gcd_degree_bound(&a, &b, Symbol(1)), Some(1));
    }
}
