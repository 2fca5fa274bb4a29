//! Exact values of decimal number literals: `0.5` is 1/2, not the nearest `f64`.

use num_bigint::BigInt;
use num_traits::{One, Zero};

/// Largest decimal exponent accepted; `1e401` is refused rather than expanded.
const MAX_EXPONENT: i64 = 400;

/// Parses a number literal as written in model files,
/// `digits ('.' digits?)? ([eE] [+-]? digits)?` or `'.' digits ([eE] [+-]? digits)?`,
/// into an exact fraction `(numerator, denominator)` with `denominator = 10^k > 0` (not
/// reduced). `None` if the text is not such a literal or its exponent exceeds 400 in size.
pub fn parse_decimal(text: &str) -> Option<(BigInt, BigInt)> {
    let bytes = text.as_bytes();
    let mut i = 0;
    let mut digits = String::new();
    while i < bytes.len() && bytes[i].is_ascii_digit() {
        digits.push(char::from(bytes[i]));
        i += 1;
    }
    let int_digits = digits.len();
    let mut frac_digits: i64 = 0;
    if i < bytes.len() && bytes[i] == b'.' {
        i += 1;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            digits.push(char::from(bytes[i]));
            frac_digits += 1;
            i += 1;
        }
    }
    if digits.is_empty() || (int_digits == 0 && frac_digits == 0) {
        return None;
    }
    let mut exponent: i64 = 0;
    if i < bytes.len() && (bytes[i] == b'e' || bytes[i] == b'E') {
        i += 1;
        let negative = match bytes.get(i) {
            Some(b'-') => {
                i += 1;
                true
            }
            Some(b'+') => {
                i += 1;
                false
            }
            _ => false,
        };
        let start = i;
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            // Saturate: anything this large is refused below.
            exponent = exponent
                .saturating_mul(10)
                .saturating_add(i64::from(bytes[i] - b'0'));
            i += 1;
        }
        if i == start {
            return None;
        }
        if exponent > MAX_EXPONENT {
            return None;
        }
        if negative {
            exponent = -exponent;
        }
    }
    if i != bytes.len() {
        return None;
    }
    let mantissa: BigInt = digits.parse().ok()?;
    let scale = exponent - frac_digits;
    let ten = BigInt::from(10);
    let power = |n: i64| {
        u32::try_from(n)
            .ok()
            .map(|n| num_traits::pow(ten.clone(), n as usize))
    };
    if mantissa.is_zero() {
        return Some((BigInt::zero(), BigInt::one()));
    }
    if scale >= 0 {
        Some((mantissa * power(scale)?, BigInt::one()))
    } else {
        Some((mantissa, power(-scale)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frac(text: &str) -> Option<(i64, i64)> {
        parse_decimal(text).map(|(n, d)| {
            let g = num_integer::Integer::gcd(&n, &d);
            (
                i64::try_from(n / &g).unwrap(),
                i64::try_from(d / &g).unwrap(),
            )
        })
    }

    #[test]
    fn literals_are_exact() {
        assert_eq!(frac("0.5"), Some((1, 2)));
        assert_eq!(frac("1e-3"), Some((1, 1000)));
        assert_eq!(frac("2.5E+2"), Some((250, 1)));
        assert_eq!(frac("5."), Some((5, 1)));
        assert_eq!(frac(".25"), Some((1, 4)));
        assert_eq!(frac("5.E4"), Some((50000, 1)));
        assert_eq!(frac("0"), Some((0, 1)));
        assert_eq!(frac("0.000"), Some((0, 1)));
        assert_eq!(frac("007"), Some((7, 1)));
        assert_eq!(frac("1.25e-1"), Some((1, 8)));
        assert_eq!(frac("0e999999999999999999999"), None);
    }

    #[test]
    fn huge_and_tiny_exponents() {
        let (n, d) = parse_decimal("1e400").unwrap();
        assert_eq!(d, BigInt::one());
        assert_eq!(n.to_string().len(), 401);
        let (n, d) = parse_decimal("1e-400").unwrap();
        assert_eq!(n, BigInt::one());
        assert_eq!(d.to_string().len(), 401);
        assert_eq!(parse_decimal("1e401"), None);
        assert_eq!(parse_decimal("1e-401"), None);
        assert_eq!(parse_decimal("1e99999999999999999999999999"), None);
    }

    #[test]
    fn non_literals_are_refused() {
        for text in [
            "", ".", "e5", ".e5", "1e", "1e+", "1e-", "-1", "+1", "1.2.3", "1 ", " 1", "1x",
            "0x10", "inf", "NaN", "1_000", "١",
        ] {
            assert_eq!(parse_decimal(text), None, "{text:?}");
        }
    }
}
