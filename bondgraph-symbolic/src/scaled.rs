//! Numbers with an exponent of their own, so that a rational function whose value fits in
//! `f64` is evaluated right even where its numerator or denominator does not.
//!
//! Why: two dampers in series act as `b1*b2/(b1 + b2)`. At `b1 = 1e308` and `b2 = 3` the
//! value is 3, but `b1*b2` overflows to infinity in `f64` and the quotient with it; a tiny
//! mass underflows the same way. A [`Scaled`] keeps a mantissa in `[0.5, 1)` and an `i64`
//! binary exponent, so products, sums and powers of any finite doubles stay finite and keep
//! their 53 bits; only the final [`Scaled::to_f64`] rounds into the range of `f64`, giving
//! infinity or zero exactly when the value itself overflows or underflows.

use std::cmp::Ordering;

use num_bigint::BigInt;
use num_traits::{Signed, ToPrimitive};

/// `mantissa × 2^exponent`, with `0.5 ≤ |mantissa| < 1`, or a zero, infinite or NaN
/// mantissa (and exponent 0) for those values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scaled {
    mantissa: f64,
    exponent: i64,
}

/// `2^k` for `-1022 ≤ k ≤ 1023`, exactly.
fn power_of_two(k: i64) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

impl Scaled {
    /// Zero.
    pub const ZERO: Scaled = Scaled {
        mantissa: 0.0,
        exponent: 0,
    };

    /// One.
    pub const ONE: Scaled = Scaled {
        mantissa: 0.5,
        exponent: 1,
    };

    /// `x`, exactly.
    pub fn from_f64(x: f64) -> Self {
        if x == 0.0 || !x.is_finite() {
            return Scaled {
                mantissa: x,
                exponent: 0,
            };
        }
        // Subnormals: bring them into the normal range first (exact).
        let (x, shift) = if x.abs() < f64::MIN_POSITIVE {
            (x * power_of_two(64), -64)
        } else {
            (x, 0)
        };
        let bits = x.to_bits();
        let biased = ((bits >> 52) & 0x7ff) as i64;
        // Replace the exponent by that of [0.5, 1): biased 1022.
        let mantissa = f64::from_bits((bits & !(0x7ff << 52)) | (1022 << 52));
        Scaled {
            mantissa,
            exponent: biased - 1022 + shift,
        }
    }

    /// `n`, to double precision (rounded toward zero beyond 53 bits).
    pub fn from_bigint(n: &BigInt) -> Self {
        let bits = n.bits();
        if bits <= 1000 {
            return Scaled::from_f64(n.to_f64().unwrap_or(f64::NAN));
        }
        let shift = bits - 64;
        let top: BigInt = n.abs() >> shift;
        let magnitude = Scaled::from_f64(top.to_f64().unwrap_or(f64::NAN));
        let magnitude = Scaled {
            exponent: magnitude.exponent + shift as i64,
            ..magnitude
        };
        if n.is_negative() {
            -magnitude
        } else {
            magnitude
        }
    }

    /// The nearest `f64`: infinite when the value overflows it, zero (or subnormal) when it
    /// underflows.
    pub fn to_f64(self) -> f64 {
        if self.mantissa == 0.0 || !self.mantissa.is_finite() {
            return self.mantissa;
        }
        let e = self.exponent;
        if e > 1024 {
            return self.mantissa.signum() * f64::INFINITY;
        }
        if e < -1080 {
            return self.mantissa.signum() * 0.0;
        }
        if e >= -1021 {
            // The mantissa has 53 bits and the result is normal (or overflows): exact scaling.
            return if e > 1023 {
                self.mantissa * 2.0 * power_of_two(e - 1)
            } else {
                self.mantissa * power_of_two(e)
            };
        }
        // Subnormal: one exact step keeps the value normal, the last one rounds once.
        self.mantissa * power_of_two(-1000) * power_of_two(e + 1000)
    }

    /// `log₂ |x|` (`-inf` for zero).
    pub fn log2_abs(self) -> f64 {
        self.mantissa.abs().log2() + self.exponent as f64
    }

    /// Whether the value is zero.
    pub fn is_zero(self) -> bool {
        self.mantissa == 0.0
    }

    /// Whether the value is neither infinite nor NaN.
    pub fn is_finite(self) -> bool {
        self.mantissa.is_finite()
    }

    /// `|x|`.
    pub fn abs(self) -> Self {
        Scaled {
            mantissa: self.mantissa.abs(),
            ..self
        }
    }

    /// `x · 2^k`, exactly.
    pub fn times_power_of_two(self, k: i64) -> Self {
        if self.mantissa == 0.0 || !self.mantissa.is_finite() {
            return self;
        }
        Scaled {
            exponent: self.exponent.saturating_add(k),
            ..self
        }
    }

    /// The mantissa of `x` at the scale `2^exponent` (`x / 2^exponent` as an `f64`, zero
    /// where it underflows): how sums line up terms of different sizes.
    pub fn mantissa_at(self, exponent: i64) -> f64 {
        Scaled {
            exponent: self.exponent.saturating_sub(exponent),
            ..self
        }
        .to_f64()
    }

    /// `x^k`, by repeated squaring.
    pub fn powi(self, mut k: u32) -> Self {
        let mut result = Scaled::ONE;
        let mut base = self;
        while k > 0 {
            if k & 1 == 1 {
                result = result * base;
            }
            k >>= 1;
            if k > 0 {
                base = base * base;
            }
        }
        result
    }

    /// `mantissa × 2^exponent` renormalised.
    fn normalised(mantissa: f64, exponent: i64) -> Self {
        let n = Scaled::from_f64(mantissa);
        n.times_power_of_two(exponent)
    }
}

impl std::ops::Neg for Scaled {
    type Output = Scaled;
    fn neg(self) -> Scaled {
        Scaled {
            mantissa: -self.mantissa,
            ..self
        }
    }
}

impl std::ops::Mul for Scaled {
    type Output = Scaled;
    fn mul(self, other: Scaled) -> Scaled {
        let mantissa = self.mantissa * other.mantissa;
        if mantissa == 0.0 || !mantissa.is_finite() {
            return Scaled::from_f64(mantissa);
        }
        Scaled::normalised(mantissa, self.exponent.saturating_add(other.exponent))
    }
}

impl std::ops::Div for Scaled {
    type Output = Scaled;
    fn div(self, other: Scaled) -> Scaled {
        let mantissa = self.mantissa / other.mantissa;
        if mantissa == 0.0 || !mantissa.is_finite() {
            return Scaled::from_f64(mantissa);
        }
        Scaled::normalised(mantissa, self.exponent.saturating_sub(other.exponent))
    }
}

impl std::ops::Add for Scaled {
    type Output = Scaled;
    fn add(self, other: Scaled) -> Scaled {
        if !self.mantissa.is_finite() || !other.mantissa.is_finite() {
            return Scaled::from_f64(self.mantissa + other.mantissa);
        }
        if other.mantissa == 0.0 {
            return self;
        }
        if self.mantissa == 0.0 {
            return other;
        }
        // Line both up at the larger exponent; a term more than 1100 binary orders smaller
        // vanishes there, as it would in any rounding.
        let top = self.exponent.max(other.exponent);
        let sum = self.mantissa_at(top) + other.mantissa_at(top);
        Scaled::normalised(sum, top)
    }
}

impl std::ops::Sub for Scaled {
    type Output = Scaled;
    fn sub(self, other: Scaled) -> Scaled {
        self + -other
    }
}

impl PartialOrd for Scaled {
    /// Orders by value (`None` with a NaN).
    fn partial_cmp(&self, other: &Scaled) -> Option<Ordering> {
        let (a, b) = (*self, *other);
        if !a.is_finite() || !b.is_finite() || a.is_zero() || b.is_zero() {
            return a.mantissa.partial_cmp(&b.mantissa);
        }
        let difference = a - b;
        difference.mantissa.partial_cmp(&0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_every_kind_of_double() {
        for x in [
            1.0,
            -1.5,
            0.1,
            1e308,
            f64::MAX,
            -f64::MIN_POSITIVE,
            5e-324,
            1e-310,
            3.0,
        ] {
            let s = Scaled::from_f64(x);
            assert_eq!(s.to_f64(), x, "{x}");
            assert!((0.5..1.0).contains(&s.mantissa.abs()), "{x}: {s:?}");
        }
        assert_eq!(Scaled::from_f64(0.0).to_f64(), 0.0);
        assert_eq!(Scaled::from_f64(f64::INFINITY).to_f64(), f64::INFINITY);
        assert!(Scaled::from_f64(f64::NAN).to_f64().is_nan());
    }

    #[test]
    fn products_leave_the_range_of_doubles_and_come_back() {
        let big = Scaled::from_f64(2f64.powi(1000));
        // 2^3000 / 2^2000 = 2^1000, exactly.
        assert_eq!(
            (big.powi(3) / big.powi(2)).to_f64(),
            2f64.powi(1000),
            "powers of two are exact"
        );
        assert_eq!(big.powi(2).to_f64(), f64::INFINITY);
        assert_eq!((-big.powi(3)).to_f64(), f64::NEG_INFINITY);
        let small = Scaled::from_f64(2f64.powi(-1000));
        assert_eq!(small.powi(2).to_f64(), 0.0);
        // 2^-1074 is the smallest subnormal; 2^-1075 rounds to even, zero.
        assert_eq!(small.times_power_of_two(-74).to_f64(), 5e-324);
        assert_eq!(Scaled::ONE.times_power_of_two(-1075).to_f64(), 0.0);
        assert_eq!((big.powi(2) * small.powi(2)).to_f64(), 1.0);
        // A subnormal result is rounded once: 3·2^-1076 is 0.75 of the smallest
        // subnormal, which rounds to it.
        let three = Scaled::from_f64(3.0);
        assert_eq!((three.times_power_of_two(-1076)).to_f64(), 5e-324);
    }

    #[test]
    fn sums_line_up_exponents() {
        let big = Scaled::from_f64(1e300).powi(2);
        // 1e600 - 1e600 + 1 = 1; 1e600 + 1 - 1e600 = 0 (the 1 is below its rounding).
        assert_eq!((big - big + Scaled::ONE).to_f64(), 1.0);
        assert_eq!((big + Scaled::ONE - big).to_f64(), 0.0);
        let third = Scaled::from_f64(1.0 / 3.0);
        assert_eq!(
            (third + third + third).to_f64(),
            1.0 / 3.0 + 1.0 / 3.0 + 1.0 / 3.0
        );
        assert!(big > Scaled::ONE && -big < Scaled::ZERO);
        assert!((big.log2_abs() - 2.0 * 1e300f64.log2()).abs() < 1e-9);
    }

    #[test]
    fn big_integers_beyond_doubles() {
        let n: BigInt = BigInt::from(3) * num_traits::pow(BigInt::from(10), 400);
        let third: BigInt = num_traits::pow(BigInt::from(10), 400);
        let ratio = Scaled::from_bigint(&n) / Scaled::from_bigint(&third);
        assert!((ratio.to_f64() - 3.0).abs() <= 4.0 * f64::EPSILON);
        assert_eq!(Scaled::from_bigint(&-n).to_f64(), f64::NEG_INFINITY);
        assert_eq!(Scaled::from_bigint(&BigInt::from(-7)).to_f64(), -7.0);
    }
}
