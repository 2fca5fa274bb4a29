//! Numbers in text for people to read: in plain decimals at ordinary magnitudes, in
//! scientific notation beyond them, so that `1e308` never prints as a 309-digit integer nor
//! `1e-300` as three hundred zeros.
//!
//! JSON keeps its own numbers (serde's shortest round-trip form); these are for the text
//! that commands print and the messages of diagnostics.

/// The shortest text that reads back as exactly `x`: plain for `1e-4 ≤ |x| < 1e16` (`0.5`,
/// `250`, `0.0001`), scientific beyond (`1e308`, `2.5e-7`); `0`, `inf`, `-inf`, `NaN` as
/// such.
pub fn shortest(x: f64) -> String {
    let magnitude = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e16).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` to `digits` significant digits (at least 1) without trailing zeros: plain for
/// `1e-4 ≤ |x| < 10^digits` (`0.5`, `1.23457` for 6 digits), scientific beyond
/// (`1.23457e-7`, `1e308`); `0`, `inf`, `-inf`, `NaN` as such.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let digits = digits.max(1);
    let precision = digits - 1;
    // The decimal exponent after rounding to `digits` digits (9.9999996 is 10 at 6 digits).
    let scientific = format!("{x:.precision$e}");
    let (mantissa, exponent) = scientific.split_once('e').unwrap_or((&scientific, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    if (-4..digits as i32).contains(&exponent) {
        let decimals = (precision as i32 - exponent).max(0) as usize;
        let text = trim_zeros(&format!("{x:.decimals$}"));
        if text == "-0" { "0".to_string() } else { text }
    } else {
        format!("{}e{exponent}", trim_zeros(mantissa))
    }
}

/// `1.500` is `1.5`, `2.000` is `2`, `300` stays.
fn trim_zeros(text: &str) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text.to_string()
    }
}

/// A number as people read it in messages: `0.0058`, `200000`, `1e6`, `1e-4`.
pub fn readable(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-3..1e6).contains(&magnitude) || !value.is_finite() {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_reads_back_and_stays_short() {
        for x in [
            0.5,
            250.0,
            1e-4,
            1e308,
            -1e308,
            2.5e-7,
            1e-310,
            f64::MAX,
            0.1 + 0.2,
            123456789012345.0,
        ] {
            let text = shortest(x);
            assert_eq!(text.parse::<f64>().unwrap(), x, "{text}");
            assert!(text.len() <= 24, "{text}");
        }
        assert_eq!(shortest(1e308), "1e308");
        assert_eq!(shortest(-2.5e-7), "-2.5e-7");
        assert_eq!(shortest(250.0), "250");
        assert_eq!(shortest(1e16), "1e16");
        assert_eq!(shortest(0.0), "0");
        assert_eq!(shortest(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn significant_digits() {
        assert_eq!(significant(0.5, 6), "0.5");
        assert_eq!(significant(1.0 / 3.0, 6), "0.333333");
        assert_eq!(significant(-1.0 / 3.0, 4), "-0.3333");
        assert_eq!(significant(123456.0, 6), "123456");
        assert_eq!(significant(1234567.0, 6), "1.23457e6");
        assert_eq!(significant(1.234567e-7, 6), "1.23457e-7");
        assert_eq!(significant(1e308, 6), "1e308");
        assert_eq!(significant(f64::MAX, 4), "1.798e308");
        assert_eq!(significant(5e-324, 6), "4.94066e-324");
        // Rounding carries into the exponent: 999999.6 is 1e6 at 6 digits.
        assert_eq!(significant(999_999.6, 6), "1e6");
        assert_eq!(significant(9.99999996, 6), "10");
        assert_eq!(significant(-1e-20, 6), "-1e-20");
        assert_eq!(significant(0.0, 6), "0");
        assert_eq!(significant(f64::INFINITY, 6), "inf");
    }
}
