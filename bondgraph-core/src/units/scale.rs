//! How many SI units one unit is, kept exactly.
//!
//! A number written beside a unit is in that unit (`0.2` beside `N/mm` is 200 N/m), so
//! reading a model file multiplies it by the unit's factor. Doing that in floating point
//! would round at every step of `g*cm^2` or `L/min` and again at the product, and `0.501`
//! beside `kN` would not always give the double nearest 501 N. So a factor is kept exactly:
//! a product of powers of integers (the primes below [`TRIAL_DIVISORS`], and whatever is
//! left of a number written in a unit) and of π, each with a rational exponent, so that
//! prefixes, `min`, `atm`, `rpm`, `deg`, products, quotients and roots (`mm^(1/2)`) all
//! compose without rounding. A value is then converted once: the decimal as written, times
//! the rational part of the factor, rounded to the nearest double; only a fractional power
//! (a root) is evaluated in floating point, and costs one more rounding.
//!
//! π is the double nearest π, taken exactly, so `rpm` is the double nearest
//! `2·PI/60` as anyone would compute it by hand in `f64`.

use std::collections::BTreeMap;
use std::fmt;

use num_bigint::{BigInt, Sign};
use num_integer::Integer;
use num_traits::{One, Signed, ToPrimitive, Zero};

use crate::symbolic::decimal::parse_decimal;

/// Numbers written in units are factored by trial division up to this; a cofactor left
/// over is kept as one base (the product stays exact; it only simplifies less).
pub const TRIAL_DIVISORS: u32 = 1000;

/// The largest power of ten a factor's part in one base may reach (`1e±700`), so that the
/// exact arithmetic stays small; a double holds 1e±308 at most, so no unit that can
/// convert a value is refused.
pub const MAX_DECADES: f64 = 700.0;

/// An exact rational exponent, in lowest terms with a positive denominator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Ratio {
    num: i64,
    den: i64,
}

impl Ratio {
    /// Zero.
    pub const ZERO: Ratio = Ratio { num: 0, den: 1 };
    /// One.
    pub const ONE: Ratio = Ratio { num: 1, den: 1 };

    /// `num/den` in lowest terms; `None` for a zero denominator or on overflow.
    pub fn new(num: i64, den: i64) -> Option<Ratio> {
        if den == 0 {
            return None;
        }
        let g = num.gcd(&den).max(1);
        let (mut num, mut den) = (num / g, den / g);
        if den < 0 {
            num = num.checked_neg()?;
            den = den.checked_neg()?;
        }
        Some(Ratio { num, den })
    }

    /// The integer `n`.
    pub const fn integer(n: i64) -> Ratio {
        Ratio { num: n, den: 1 }
    }

    /// The numerator.
    pub fn numer(self) -> i64 {
        self.num
    }

    /// The denominator (positive).
    pub fn denom(self) -> i64 {
        self.den
    }

    /// Whether this is zero.
    pub fn is_zero(self) -> bool {
        self.num == 0
    }

    fn checked_add(self, other: Ratio) -> Option<Ratio> {
        let num = self
            .num
            .checked_mul(other.den)?
            .checked_add(other.num.checked_mul(self.den)?)?;
        Ratio::new(num, self.den.checked_mul(other.den)?)
    }

    fn checked_mul(self, other: Ratio) -> Option<Ratio> {
        Ratio::new(
            self.num.checked_mul(other.num)?,
            self.den.checked_mul(other.den)?,
        )
    }

    /// The largest integer not above it.
    fn floor(self) -> i64 {
        self.num.div_euclid(self.den)
    }

    /// What is left above the floor, in `[0, 1)`.
    fn fract(self) -> Ratio {
        Ratio {
            num: self.num.rem_euclid(self.den),
            den: self.den,
        }
    }

    fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }
}

impl fmt::Display for Ratio {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

/// An exact signed rational `num/den`, `den > 0`: a value as written, or a part of a
/// factor.
#[derive(Clone, Debug)]
pub struct Exact {
    num: BigInt,
    den: BigInt,
}

impl PartialEq for Exact {
    fn eq(&self, other: &Exact) -> bool {
        &self.num * &other.den == &other.num * &self.den
    }
}

impl Eq for Exact {}

impl Exact {
    /// `num/den`; `den` must not be zero.
    pub fn new(num: BigInt, den: BigInt) -> Exact {
        if den.is_negative() {
            Exact {
                num: -num,
                den: -den,
            }
        } else {
            Exact { num, den }
        }
    }

    /// The decimal `text` as written in a model file (`0.2`, `-1.5e-3`, `+7`), exactly.
    pub fn decimal(text: &str) -> Option<Exact> {
        let text = text.trim();
        let (negative, digits) = match text.as_bytes().first() {
            Some(b'-') => (true, &text[1..]),
            Some(b'+') => (false, &text[1..]),
            _ => (false, text),
        };
        let (num, den) = parse_decimal(digits)?;
        Some(Exact::new(if negative { -num } else { num }, den))
    }

    /// The double `x` (finite), exactly: every double is a dyadic rational.
    pub fn of_f64(x: f64) -> Exact {
        let bits = x.to_bits();
        let negative = bits >> 63 == 1;
        let exponent = ((bits >> 52) & 0x7ff) as i64;
        let fraction = bits & ((1 << 52) - 1);
        let (mantissa, power) = if exponent == 0 {
            (fraction, -1074)
        } else {
            (fraction | (1 << 52), exponent - 1075)
        };
        let mut num = BigInt::from(mantissa);
        if negative {
            num = -num;
        }
        if power >= 0 {
            Exact::new(num << power as usize, BigInt::one())
        } else {
            Exact::new(num, BigInt::one() << (-power) as usize)
        }
    }

    fn times(&self, other: &Exact) -> Exact {
        Exact::new(&self.num * &other.num, &self.den * &other.den)
    }

    fn plus(&self, other: &Exact) -> Exact {
        Exact::new(
            &self.num * &other.den + &other.num * &self.den,
            &self.den * &other.den,
        )
    }

    fn recip(&self) -> Option<Exact> {
        (!self.num.is_zero()).then(|| Exact::new(self.den.clone(), self.num.clone()))
    }

    /// The double nearest this value (ties to even): infinite beyond the largest double.
    pub fn to_f64(&self) -> f64 {
        round_ratio(&self.num, &self.den)
    }
}

/// The double nearest `num/den` (`den > 0`), ties to even, computed once from the exact
/// quotient: its leading 55 or 56 bits and whether anything is left.
fn round_ratio(num: &BigInt, den: &BigInt) -> f64 {
    if num.is_zero() {
        return 0.0;
    }
    let negative = num.sign() == Sign::Minus;
    let (n, d) = (num.abs(), den.abs());
    // n/d lies in [2^(nb - db - 1), 2^(nb - db + 1)); scale it to [2^54, 2^56).
    let shift = 55 - (n.bits() as i64 - d.bits() as i64);
    let (n, d) = if shift >= 0 {
        (n << shift as usize, d)
    } else {
        (n, d << (-shift) as usize)
    };
    let (q, r) = n.div_rem(&d);
    let mut q = q.to_u64().expect("a quotient below 2^56");
    if !r.is_zero() {
        // The sticky bit, below the rounding position: round to nearest stays right.
        q |= 1;
    }
    let magnitude = scale_by_power_of_two(q as f64, -shift);
    if negative { -magnitude } else { magnitude }
}

/// `x·2^power`, exactly while the result is a normal double.
fn scale_by_power_of_two(mut x: f64, mut power: i64) -> f64 {
    while power > 1000 {
        x *= 2f64.powi(1000);
        power -= 1000;
    }
    while power < -1000 {
        x *= 2f64.powi(-1000);
        power += 1000;
    }
    x * 2f64.powi(power as i32)
}

/// A positive factor, exactly: `Π base^exponent · π^pi` with rational exponents.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Scale {
    /// Bases above 1 (primes, or a cofactor trial division left), with non-zero exponents.
    bases: BTreeMap<BigInt, Ratio>,
    /// The exponent of π.
    pi: Ratio,
}

impl Default for Scale {
    fn default() -> Self {
        Scale::one()
    }
}

impl Scale {
    /// The factor 1.
    pub fn one() -> Scale {
        Scale {
            bases: BTreeMap::new(),
            pi: Ratio::ZERO,
        }
    }

    /// `num/den · π^pi` (`num`, `den` positive), for the unit tables.
    pub fn of(num: u64, den: u64, pi: i64) -> Scale {
        let integer = |n: u64| Scale::integer(BigInt::from(n)).unwrap_or_default();
        let mut scale = integer(num)
            .per(&integer(den))
            .expect("table factors are small");
        scale.pi = Ratio::integer(pi);
        scale
    }

    /// `10^power`, an SI prefix.
    pub fn power_of_ten(power: i64) -> Scale {
        let mut scale = Scale::one();
        scale.bases.insert(BigInt::from(2), Ratio::integer(power));
        scale.bases.insert(BigInt::from(5), Ratio::integer(power));
        scale.bases.retain(|_, e| !e.is_zero());
        scale
    }

    /// The positive decimal `text` (`1000`, `0.3048`, `1e3`); `None` if it is not one.
    pub fn decimal(text: &str) -> Option<Scale> {
        let (num, den) = parse_decimal(text)?;
        Scale::integer(num)?.per(&Scale::integer(den)?)
    }

    /// The positive integer `n`, factored by trial division up to [`TRIAL_DIVISORS`];
    /// `None` unless `n > 0`.
    fn integer(mut n: BigInt) -> Option<Scale> {
        if !n.is_positive() {
            return None;
        }
        let mut scale = Scale::one();
        let mut divisor = 2u32;
        while divisor <= TRIAL_DIVISORS && n > BigInt::one() {
            let d = BigInt::from(divisor);
            let mut count = 0i64;
            loop {
                let (q, r) = n.div_rem(&d);
                if !r.is_zero() {
                    break;
                }
                n = q;
                count += 1;
            }
            if count > 0 {
                scale.bases.insert(d, Ratio::integer(count));
            }
            divisor += 1;
        }
        if n > BigInt::one() {
            scale.bases.insert(n, Ratio::ONE);
        }
        Some(scale)
    }

    /// Whether this is exactly 1.
    pub fn is_one(&self) -> bool {
        self.bases.is_empty() && self.pi.is_zero()
    }

    /// The product; `None` if an exponent overflows.
    pub fn times(&self, other: &Scale) -> Option<Scale> {
        let mut out = self.clone();
        for (base, exponent) in &other.bases {
            let total = out
                .bases
                .get(base)
                .copied()
                .unwrap_or(Ratio::ZERO)
                .checked_add(*exponent)?;
            if total.is_zero() {
                out.bases.remove(base);
            } else {
                out.bases.insert(base.clone(), total);
            }
        }
        out.pi = out.pi.checked_add(other.pi)?;
        Some(out)
    }

    /// The quotient; `None` if an exponent overflows.
    pub fn per(&self, other: &Scale) -> Option<Scale> {
        self.times(&other.pow(Ratio::integer(-1))?)
    }

    /// `self^power`; `None` if an exponent overflows.
    pub fn pow(&self, power: Ratio) -> Option<Scale> {
        let mut out = Scale::one();
        for (base, exponent) in &self.bases {
            let e = exponent.checked_mul(power)?;
            if !e.is_zero() {
                out.bases.insert(base.clone(), e);
            }
        }
        out.pi = self.pi.checked_mul(power)?;
        Some(out)
    }

    /// Whether every base's part stays within 1e±[`MAX_DECADES`], so that the exact parts
    /// can be computed.
    pub fn in_range(&self) -> bool {
        let alone = |base: &BigInt, e: Ratio| Scale {
            bases: BTreeMap::from([(base.clone(), e)]),
            pi: Ratio::ZERO,
        };
        self.bases
            .iter()
            .all(|(b, e)| alone(b, *e).decades().abs() <= MAX_DECADES)
            && (self.pi.to_f64() * std::f64::consts::PI.log10()).abs() <= MAX_DECADES
    }

    /// The exact part (integer exponents, π as the double nearest it) and the rest, which
    /// only roots leave: `(Π base^floor(e) · PI^floor(e_π), Π base^fract(e) · π^fract(e_π))`
    /// with the rest as a double (exactly 1 when there is none). `None` unless
    /// [`Scale::in_range`], where the exact part would be too large to compute.
    fn split(&self) -> Option<(Exact, f64)> {
        if !self.in_range() {
            return None;
        }
        let mut num = BigInt::one();
        let mut den = BigInt::one();
        // The rest: Π base^(fract·L) under one root of order L, the lcm of the denominators.
        let mut order = 1i64;
        for e in self.bases.values().chain([&self.pi]) {
            if e.fract().num != 0 {
                order = order.lcm(&e.den);
            }
        }
        let mut inner = Exact::new(BigInt::one(), BigInt::one());
        for (base, e) in &self.bases {
            let whole = e.floor();
            let power = num_traits::pow(base.clone(), whole.unsigned_abs() as usize);
            if whole >= 0 {
                num *= power;
            } else {
                den *= power;
            }
            let fract = e.fract();
            if fract.num != 0 {
                let k = fract.num * (order / fract.den);
                inner = inner.times(&Exact::new(
                    num_traits::pow(base.clone(), k as usize),
                    BigInt::one(),
                ));
            }
        }
        let mut exact = Exact::new(num, den);
        let pi = Exact::of_f64(std::f64::consts::PI);
        let whole = self.pi.floor();
        for _ in 0..whole.unsigned_abs() {
            exact = if whole >= 0 {
                exact.times(&pi)
            } else {
                exact.times(&pi.recip().expect("π is not zero"))
            };
        }
        let mut rest = if order == 1 {
            1.0
        } else {
            let inner = inner.to_f64();
            match order {
                2 => inner.sqrt(),
                3 => inner.cbrt(),
                _ => inner.powf(1.0 / order as f64),
            }
        };
        if self.pi.fract().num != 0 {
            rest *= std::f64::consts::PI.powf(self.pi.fract().to_f64());
        }
        Some((exact, rest))
    }

    /// The factor's power of ten, roughly; for a factor beyond [`Scale::in_range`].
    fn decades(&self) -> f64 {
        let log = |base: &BigInt| {
            base.to_f64()
                .map(f64::log10)
                .filter(|l| l.is_finite())
                .unwrap_or(base.bits() as f64 * 2f64.log10())
        };
        self.bases
            .iter()
            .map(|(b, e)| log(b) * e.to_f64())
            .sum::<f64>()
            + self.pi.to_f64() * std::f64::consts::PI.log10()
    }

    /// The factor as the nearest double (to a unit in the last place or two, for a root).
    pub fn to_f64(&self) -> f64 {
        self.apply(&Exact::new(BigInt::one(), BigInt::one()))
    }

    /// `value·factor`, rounded once (twice for a factor with a root); beyond
    /// [`Scale::in_range`], infinite or zero.
    pub fn apply(&self, value: &Exact) -> f64 {
        let Some((exact, rest)) = self.split() else {
            return value.to_f64() * 10f64.powf(self.decades());
        };
        let product = value.times(&exact).to_f64();
        if rest == 1.0 { product } else { product * rest }
    }

    /// `value·factor + offset`, rounded once when the factor has no root.
    pub fn apply_with_offset(&self, value: &Exact, offset: &Exact) -> f64 {
        let Some((exact, rest)) = self.split() else {
            return self.apply(value) + offset.to_f64();
        };
        if rest == 1.0 {
            value.times(&exact).plus(offset).to_f64()
        } else {
            value.times(&exact).to_f64() * rest + offset.to_f64()
        }
    }

    /// A decimal that this factor (and `offset`) turns into exactly `si`, as short as can
    /// be: the text to write where a file's unit is this one. For a factor with a root the
    /// shortest text within a unit or two in the last place, if none is exact.
    pub fn unapply(&self, si: f64, offset: &Exact) -> String {
        let reads_back = |text: &str| {
            Exact::decimal(text).map(|v| self.apply_with_offset(&v, offset)) == Some(si)
        };
        let Some((exact, rest)) = self.split() else {
            return format!("{:?}", si / 10f64.powf(self.decades()));
        };
        // The value as written, exactly where the factor has no root.
        let target = Exact::of_f64(si).plus(&Exact::new(-offset.num.clone(), offset.den.clone()));
        let approximate = match exact.recip() {
            Some(inverse) if rest == 1.0 => target.times(&inverse),
            _ => Exact::of_f64(target.to_f64() / (exact.to_f64() * rest)),
        };
        for digits in 1..=20 {
            for candidate in significant(&approximate, digits) {
                let text = decimal_text(&candidate.0, candidate.1);
                if reads_back(&text) {
                    return text;
                }
            }
        }
        let (mantissa, power) = &significant(&approximate, 17)[0];
        decimal_text(mantissa, *power)
    }
}

/// `x` rounded to `digits` significant decimal digits, as `(mantissa, power of ten)`, and
/// its two neighbours at that precision (the interval that reads back need not be
/// centred on `x`).
fn significant(x: &Exact, digits: u32) -> Vec<(BigInt, i64)> {
    if x.num.is_zero() {
        return vec![(BigInt::zero(), 0)];
    }
    let ten = BigInt::from(10);
    let (n, d) = (x.num.abs(), x.den.clone());
    // The decade: 10^e <= |x| < 10^(e+1), from the digit counts and then exactly.
    let mut e = n.to_string().len() as i64 - d.to_string().len() as i64;
    let power = |k: i64| num_traits::pow(ten.clone(), k.unsigned_abs() as usize);
    let at_least = |e: i64| {
        if e >= 0 {
            n >= &d * power(e)
        } else {
            &n * power(e) >= d
        }
    };
    while !at_least(e) {
        e -= 1;
    }
    while at_least(e + 1) {
        e += 1;
    }
    let scale = e - i64::from(digits) + 1;
    // m = round(|x| / 10^scale), ties to even.
    let (num, den) = if scale >= 0 {
        (n.clone(), &d * power(scale))
    } else {
        (&n * power(scale), d.clone())
    };
    let (q, r) = num.div_rem(&den);
    let twice: BigInt = r * 2;
    let m = if twice > den || (twice == den && q.is_odd()) {
        q + 1
    } else {
        q
    };
    let sign = if x.num.is_negative() { -1 } else { 1 };
    [m.clone(), m.clone() - 1, m + 1]
        .into_iter()
        .filter(|m| !m.is_zero())
        .map(|m| (m * sign, scale))
        .collect()
}

/// `mantissa·10^power` as RON reads a float: `0.25`, `200.0`, `1.5e-7`.
fn decimal_text(mantissa: &BigInt, power: i64) -> String {
    let negative = mantissa.is_negative();
    let mut digits = mantissa.abs().to_string();
    let mut power = power;
    while digits.len() > 1 && digits.ends_with('0') {
        digits.pop();
        power += 1;
    }
    // The decade of the leading digit.
    let lead = power + digits.len() as i64 - 1;
    let body = if (-5..16).contains(&lead) {
        if power >= 0 {
            format!("{digits}{}.0", "0".repeat(power as usize))
        } else {
            let point = digits.len() as i64 + power;
            if point > 0 {
                format!(
                    "{}.{}",
                    &digits[..point as usize],
                    &digits[point as usize..]
                )
            } else {
                format!("0.{}{digits}", "0".repeat((-point) as usize))
            }
        }
    } else if digits.len() == 1 {
        format!("{digits}e{lead}")
    } else {
        format!("{}.{}e{lead}", &digits[..1], &digits[1..])
    };
    if negative { format!("-{body}") } else { body }
}

/// A number for a message: `1000`, `0.001`, `1.6666666666666667e-5`, `0`.
pub fn factor_text(x: f64) -> String {
    if x == 0.0 || (1e-4..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(text: &str) -> Exact {
        Exact::decimal(text).unwrap()
    }

    #[test]
    fn a_ratio_rounds_once_to_the_nearest_double() {
        // Each against the double Rust's own parser (correctly rounded) gives.
        for (num, den, text) in [
            (1i64, 60000i64, "1.6666666666666667e-5"),
            (1, 3, "0.3333333333333333"),
            (2, 3, "0.6666666666666666"),
            (1, 10, "0.1"),
            (-7, 1000, "-0.007"),
            (12345678901234567, 1, "12345678901234568"),
            (9007199254740993, 1, "9007199254740992"), // 2^53 + 1: a tie, to even
            (9007199254740995, 1, "9007199254740996"), // 2^53 + 3: a tie, to even
        ] {
            let value = round_ratio(&BigInt::from(num), &BigInt::from(den));
            assert_eq!(value, text.parse::<f64>().unwrap(), "{num}/{den}");
        }
        assert_eq!(exact("1e-24").to_f64(), 1e-24);
        assert_eq!(exact("1e400").to_f64(), f64::INFINITY);
        assert_eq!(exact("4.9e-324").to_f64(), 4.9e-324);
    }

    #[test]
    fn doubles_are_exact_dyadic_rationals() {
        for x in [0.1, -2.5, 1e-310, f64::MAX, 3.0, std::f64::consts::PI] {
            assert_eq!(Exact::of_f64(x).to_f64(), x);
        }
        assert_eq!(Exact::of_f64(0.5), exact("0.5"));
    }

    #[test]
    fn factors_compose_exactly() {
        let milli = Scale::power_of_ten(-3);
        let litre_per_minute = milli.per(&Scale::of(60, 1, 0)).unwrap();
        assert_eq!(litre_per_minute.to_f64(), 1.0 / 60000.0);
        // (mm)^(1/2) squared is a mm again, exactly.
        let root = milli.pow(Ratio::new(1, 2).unwrap()).unwrap();
        assert_eq!(root.times(&root).unwrap(), milli);
        assert!(Scale::power_of_ten(3).times(&milli).unwrap().is_one());
        // π/30 · 30/π = 1.
        let rpm = Scale::of(1, 30, 1);
        assert!(rpm.times(&Scale::of(30, 1, -1)).unwrap().is_one());
        // A decimal is factored: 0.3048 = 3048/10000 = 2^3·3·127/(2^4·5^4).
        assert_eq!(Scale::decimal("0.3048").unwrap().to_f64(), 0.3048);
        assert_eq!(Scale::decimal("0"), None);
        // Beyond 1e±700 the exact part is not computed: the value is out of any double's
        // range anyway.
        let huge = Scale::power_of_ten(1_000_000_000_000);
        assert!(!huge.in_range());
        assert_eq!(huge.to_f64(), f64::INFINITY);
        assert_eq!(huge.pow(Ratio::integer(-1)).unwrap().to_f64(), 0.0);
    }

    #[test]
    fn a_value_is_converted_exactly_and_written_back_as_the_shortest_decimal() {
        let kilo = Scale::power_of_ten(3);
        let zero = Exact::new(BigInt::zero(), BigInt::one());
        // 1.001 as written is 1001/1000: times 1000, exactly 1001; the double nearest 1.001
        // is a little less, and times 1000 rounds below 1001.
        assert_eq!(kilo.apply(&exact("1.001")), 1001.0);
        assert_eq!(kilo.apply(&Exact::of_f64(1.001)), 1000.9999999999999);
        assert_eq!(kilo.unapply(1001.0, &zero), "1.001");
        let per_minute = Scale::of(1, 60, 0);
        assert_eq!(per_minute.unapply(0.1, &zero), "6.0");
        // 1/3 per minute is no short decimal: whatever is written must read back as it.
        let third = 1.0 / 3.0;
        let text = per_minute.unapply(third, &zero);
        assert_eq!(per_minute.apply(&exact(&text)), third, "{text}");
        let celsius = Exact::new(BigInt::from(27315), BigInt::from(100));
        assert_eq!(Scale::one().unapply(300.0, &celsius), "26.85");
        assert_eq!(
            Scale::one().apply_with_offset(&exact("26.85"), &celsius),
            300.0
        );
        assert_eq!(decimal_text(&BigInt::from(15), -8), "1.5e-7");
        assert_eq!(decimal_text(&BigInt::from(-25), -2), "-0.25");
        assert_eq!(decimal_text(&BigInt::from(2), 2), "200.0");
        assert_eq!(decimal_text(&BigInt::from(1), 20), "1e20");
    }
}
