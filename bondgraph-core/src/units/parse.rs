//! Unit strings, as model files write them, to a dimension and a factor to SI.
//!
//! ```text
//! unit     := factor (('*' | '·' | '/' | ' ') factor)*      (left to right: N*s/m is (N*s)/m)
//! factor   := primary power?
//! power    := '^' number | '^' '(' number ('/' integer)? ')' | superscripts (m², s⁻¹)
//! number   := ('-' | '+')? digits ('.' digits)?              (0.5 is exactly 1/2)
//! primary  := symbol | positive decimal | '(' unit ')'
//! ```
//!
//! A symbol is a named unit, possibly with an SI prefix ([`super::names`]); a number (`1`,
//! `1000`) is dimensionless, and scales by its value. A power is an exact rational (`^1.5`
//! is 3/2) whose denominator divides 12, as [`Dim`] keeps exponents in twelfths. Anything
//! else is a [`UnitError`] naming the part that is not understood, so a diagnostic can say
//! which of `N*s/mm2` is wrong.
//!
//! [`parse_scaled`] gives the whole [`Unit`]: its dimension, its exact [`Scale`] to SI,
//! and whether it is a Celsius temperature (`degC` or `°C` alone, offset by 273.15 K; in a
//! compound unit such as `J/(kg*degC)` a Celsius degree is a temperature difference, the
//! size of a kelvin).

use std::fmt;

use num_bigint::BigInt;

use super::dimension::{Dim, PowError};
use super::names;
use super::scale::{Exact, Ratio, Scale};

/// A unit string that does not parse, and the part of it that is at fault.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnitError {
    /// The part not understood (`furlong`, `m2`, `^`).
    pub part: String,
    /// Why, in a few words.
    pub reason: String,
}

impl fmt::Display for UnitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} '{}'", self.reason, self.part)
    }
}

impl std::error::Error for UnitError {}

/// A unit: its dimension, how many SI units it is, and its offset.
#[derive(Clone, Debug, PartialEq)]
pub struct Unit {
    /// The dimension.
    pub dim: Dim,
    /// One of it in coherent SI units of its dimension (`kPa`: 1000 Pa).
    pub scale: Scale,
    /// What is added after scaling, in SI units: 273.15 K for a Celsius temperature
    /// written alone.
    pub offset: Option<Exact>,
}

/// The dimension of unit string `text` (`"N*s/m"`, `"kg*m^2"`, `"1/s"`, `"J/(kg*K)"`).
///
/// # Errors
/// A [`UnitError`] naming the unknown symbol, or the place where the string stops making
/// sense.
pub fn parse_unit(text: &str) -> Result<Dim, UnitError> {
    parse_scaled(text).map(|unit| unit.dim)
}

/// The [`Unit`] of unit string `text`: `"N/mm"` is kg/s^2 times 1000.
///
/// # Errors
/// As [`parse_unit`]; also a scale too large for a double to hold any value in it.
pub fn parse_scaled(text: &str) -> Result<Unit, UnitError> {
    let mut parser = Parser {
        chars: text.chars().collect(),
        at: 0,
    };
    parser.skip_spaces();
    if parser.peek().is_none() {
        return Err(UnitError {
            part: text.to_string(),
            reason: "empty unit".to_string(),
        });
    }
    let term = parser.product()?;
    parser.skip_spaces();
    if parser.peek().is_some() {
        return Err(parser.error_here("unexpected"));
    }
    if !term.scale.in_range() {
        return Err(UnitError {
            part: text.to_string(),
            reason: "a scale beyond what a 64-bit floating-point number can hold in".to_string(),
        });
    }
    Ok(Unit {
        dim: term.dim,
        scale: term.scale,
        offset: term
            .celsius
            .then(|| Exact::new(BigInt::from(27315), BigInt::from(100))),
    })
}

/// What a part of a unit string is.
struct Term {
    dim: Dim,
    scale: Scale,
    /// A Celsius symbol alone (possibly in parentheses): the only place it is offset.
    celsius: bool,
}

impl Term {
    fn combine(
        self,
        other: Term,
        divide: bool,
        error: impl Fn() -> UnitError,
    ) -> Result<Term, UnitError> {
        let (dim, scale) = if divide {
            (self.dim.per(other.dim), self.scale.per(&other.scale))
        } else {
            (self.dim.times(other.dim), self.scale.times(&other.scale))
        };
        Ok(Term {
            dim,
            scale: scale.ok_or_else(error)?,
            celsius: false,
        })
    }
}

struct Parser {
    chars: Vec<char>,
    at: usize,
}

const SUPERSCRIPTS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];

fn is_symbol_char(c: char) -> bool {
    !(c.is_whitespace()
        || matches!(c, '*' | '·' | '/' | '^' | '(' | ')' | '⁻')
        || SUPERSCRIPTS.contains(&c))
}

impl Parser {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn skip_spaces(&mut self) -> bool {
        let start = self.at;
        while self.peek().is_some_and(char::is_whitespace) {
            self.at += 1;
        }
        self.at > start
    }

    fn error_here(&self, reason: &str) -> UnitError {
        let rest: String = self.chars[self.at.min(self.chars.len())..].iter().collect();
        UnitError {
            part: if rest.is_empty() {
                "end of the unit".to_string()
            } else {
                rest
            },
            reason: reason.to_string(),
        }
    }

    /// An error naming `chars[start..end]`.
    fn error_in(&self, start: usize, end: usize, reason: &str) -> UnitError {
        UnitError {
            part: self.chars[start..end.min(self.chars.len())]
                .iter()
                .collect(),
            reason: reason.to_string(),
        }
    }

    fn product(&mut self) -> Result<Term, UnitError> {
        let start = self.at;
        let mut term = self.factor()?;
        loop {
            let spaced = self.skip_spaces();
            let divide = match self.peek() {
                Some('*' | '·') => {
                    self.at += 1;
                    false
                }
                Some('/') => {
                    self.at += 1;
                    true
                }
                Some(c) if spaced && c != ')' => false,
                _ => return Ok(term),
            };
            self.skip_spaces();
            let next = self.factor()?;
            let end = self.at;
            term = term.combine(next, divide, || {
                self.error_in(start, end, "a scale too large to keep in")
            })?;
        }
    }

    fn factor(&mut self) -> Result<Term, UnitError> {
        let base = self.primary()?;
        let start = self.at;
        let power = match self.peek() {
            Some('^') => {
                self.at += 1;
                self.exponent(start)?
            }
            Some(c) if c == '⁻' || SUPERSCRIPTS.contains(&c) => self.superscript()?,
            _ => return Ok(base),
        };
        let too_fine = || {
            self.error_in(
                start,
                self.at,
                "a power finer than twelfths cannot be kept exactly in",
            )
        };
        let too_large = || self.error_in(start, self.at, "a power too large in");
        // Dim keeps twelfths: a power whose denominator does not divide 12 cannot be kept.
        if 12 % power.denom() != 0 {
            return Err(too_fine());
        }
        let dim = match base.dim.checked_pow(power.numer(), power.denom()) {
            Ok(dim) => dim,
            Err(PowError::TooFine) => return Err(too_fine()),
            Err(PowError::TooLarge) => return Err(too_large()),
        };
        let scale = base.scale.pow(power).ok_or_else(too_large)?;
        Ok(Term {
            dim,
            scale,
            celsius: false,
        })
    }

    /// `m²`, `s⁻¹`: an integer power in superscripts.
    fn superscript(&mut self) -> Result<Ratio, UnitError> {
        let start = self.at;
        let negative = self.peek() == Some('⁻');
        if negative {
            self.at += 1;
        }
        let mut n: i64 = 0;
        let mut digits = 0;
        while let Some(d) = self
            .peek()
            .and_then(|c| SUPERSCRIPTS.iter().position(|s| *s == c))
        {
            n = n.saturating_mul(10).saturating_add(d as i64);
            digits += 1;
            self.at += 1;
        }
        if digits == 0 {
            return Err(self.error_here("a superscript minus needs digits before"));
        }
        if n > i64::from(i32::MAX) {
            return Err(self.error_in(start, self.at, "a power too large in"));
        }
        Ok(Ratio::integer(if negative { -n } else { n }))
    }

    /// After `^`: `2`, `-1`, `0.5`, `(1/2)`, `(-1.5)`, `(3/-4)`. `start` is the `^`'s
    /// place, so an error names the whole power as written.
    fn exponent(&mut self, start: usize) -> Result<Ratio, UnitError> {
        if self.peek() != Some('(') {
            return self.number(start);
        }
        self.at += 1;
        let num = self.number(start)?;
        let den = if self.peek() == Some('/') {
            self.at += 1;
            self.number(start)?
        } else {
            Ratio::ONE
        };
        if self.peek() != Some(')') {
            return Err(self.error_here("a power's ')' is missing before"));
        }
        self.at += 1;
        if den.is_zero() {
            return Err(self.error_in(start, self.at, "a power divides by zero in"));
        }
        let quotient = num
            .numer()
            .checked_mul(den.denom())
            .zip(num.denom().checked_mul(den.numer()))
            .and_then(|(n, d)| Ratio::new(n, d));
        quotient.ok_or_else(|| self.error_in(start, self.at, "a power too large in"))
    }

    /// A signed decimal number in a power, exactly: `-0.5` is -1/2.
    fn number(&mut self, start: usize) -> Result<Ratio, UnitError> {
        let negative = self.peek() == Some('-');
        if negative || self.peek() == Some('+') {
            self.at += 1;
        }
        let whole = self.digits();
        if whole.is_empty() {
            if self.peek().is_none() {
                return Err(self.error_here("a power needs a number before"));
            }
            // Name the power as far as it goes: `^.5`, `^x`.
            let mut end = self.at + 1;
            while self.chars.get(end).is_some_and(|c| is_symbol_char(*c)) {
                end += 1;
            }
            return Err(self.error_in(start, end, "a power needs a number in"));
        }
        let mut fraction = String::new();
        if self.peek() == Some('.') {
            self.at += 1;
            fraction = self.digits();
            if fraction.is_empty() {
                return Err(self.error_in(
                    start,
                    self.at,
                    "a decimal point needs digits after it in",
                ));
            }
        }
        let too_large = || self.error_in(start, self.at, "a power too large in");
        let den = u32::try_from(fraction.len())
            .ok()
            .and_then(|k| 10i64.checked_pow(k))
            .ok_or_else(too_large)?;
        let num = format!("{whole}{fraction}")
            .parse::<i64>()
            .map_err(|_| too_large())?;
        Ratio::new(if negative { -num } else { num }, den).ok_or_else(too_large)
    }

    /// The ASCII digits from here on.
    fn digits(&mut self) -> String {
        let from = self.at;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.at += 1;
        }
        self.chars[from..self.at].iter().collect()
    }

    fn primary(&mut self) -> Result<Term, UnitError> {
        match self.peek() {
            Some('(') => {
                self.at += 1;
                self.skip_spaces();
                let term = self.product()?;
                self.skip_spaces();
                if self.peek() != Some(')') {
                    return Err(self.error_here("a ')' is missing before"));
                }
                self.at += 1;
                Ok(term)
            }
            Some(c) if is_symbol_char(c) => {
                let start = self.at;
                while self.peek().is_some_and(is_symbol_char) {
                    self.at += 1;
                }
                let symbol: String = self.chars[start..self.at].iter().collect();
                if symbol.parse::<f64>().is_ok_and(f64::is_finite) {
                    let scale = Scale::decimal(&symbol).ok_or_else(|| UnitError {
                        part: symbol.clone(),
                        reason: "a number in a unit must be a positive decimal, not".to_string(),
                    })?;
                    return Ok(Term {
                        dim: Dim::NONE,
                        scale,
                        celsius: false,
                    });
                }
                let named = names::lookup_scaled(&symbol).ok_or(UnitError {
                    part: symbol,
                    reason: "unknown unit".to_string(),
                })?;
                Ok(Term {
                    dim: named.dim,
                    scale: named.scale,
                    celsius: named.offset,
                })
            }
            _ => Err(self.error_here("a unit is missing before")),
        }
    }
}

/// The coherent SI unit of unit string `text`, spelt like it: `N/mm` is in `N/m`, `kPa` in
/// `Pa`, `L/min` in `m^3/s`, `g*cm^2` in `kg*m^2`. Each symbol becomes its SI unit (prefix
/// dropped), in parentheses where the replacement would otherwise bind differently
/// (`N*m/rpm` is in `N*m/(rad/s)`); `None` if `text` does not parse.
pub fn si_spelling(text: &str) -> Option<String> {
    let unit = parse_scaled(text).ok()?;
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::new();
    let mut at = 0;
    while at < chars.len() {
        let c = chars[at];
        if c == '^' {
            // A power is copied as written: `^3`, `^-0.5`, `^(1/2)`.
            let start = at;
            at += 1;
            if chars.get(at) == Some(&'(') {
                while at < chars.len() && chars[at] != ')' {
                    at += 1;
                }
                at = (at + 1).min(chars.len());
            } else {
                while chars
                    .get(at)
                    .is_some_and(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
                {
                    at += 1;
                }
            }
            out.extend(&chars[start..at]);
            continue;
        }
        if !is_symbol_char(c) {
            out.push(c);
            at += 1;
            continue;
        }
        let start = at;
        while at < chars.len() && is_symbol_char(chars[at]) {
            at += 1;
        }
        let symbol: String = chars[start..at].iter().collect();
        let si = if symbol.parse::<f64>().is_ok() {
            "1"
        } else {
            let named = names::lookup_scaled(&symbol)?;
            names::SI_SPELLING
                .iter()
                .find(|(from, _)| *from == named.unprefixed)
                .map_or(named.unprefixed, |(_, to)| to)
        };
        let before = chars[..start].iter().rev().find(|c| !c.is_whitespace());
        let after = chars.get(at);
        let powered = after.is_some_and(|c| *c == '^' || *c == '⁻' || SUPERSCRIPTS.contains(c));
        let wrap = (si.contains('/') && (before == Some(&'/') || powered))
            || (si.contains('^') && powered);
        if wrap {
            out.push_str(&format!("({si})"));
        } else {
            out.push_str(si);
        }
    }
    // The spelling must be the same dimension, in SI units; else the plain SI base units.
    match parse_scaled(&out) {
        Ok(si) if si.dim == unit.dim && si.scale.is_one() && si.offset.is_none() => Some(out),
        _ => Some(unit.dim.si()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `kg^a m^b s^c A^d K^e`.
    fn dim(kg: i32, m: i32, s: i32, a: i32, k: i32) -> Dim {
        Dim::from_integers([kg, m, s, a, k, 0, 0])
    }

    fn parsed(text: &str) -> Dim {
        parse_unit(text).unwrap_or_else(|e| panic!("{text}: {e}"))
    }

    #[test]
    fn every_unit_string_of_the_shipped_models_parses_to_its_hand_derived_dimension() {
        // N = kg m s^-2; each line is derived by hand from that and the SI definitions.
        let cases = [
            ("N", dim(1, 1, -2, 0, 0)),
            ("kg", dim(1, 0, 0, 0, 0)),
            ("N/m", dim(1, 0, -2, 0, 0)),
            ("N*s/m", dim(1, 0, -1, 0, 0)),
            ("m/s", dim(0, 1, -1, 0, 0)),
            ("V", dim(1, 2, -3, -1, 0)),
            ("ohm", dim(1, 2, -3, -2, 0)),
            ("m^2", dim(0, 2, 0, 0, 0)),
            ("m²", dim(0, 2, 0, 0, 0)),
            ("H", dim(1, 2, -2, -2, 0)),
            ("kg*m^2", dim(1, 2, 0, 0, 0)),
            // Pa*s/m^3 = kg m^-1 s^-2 * s * m^-3.
            ("Pa*s/m^3", dim(1, -4, -1, 0, 0)),
            ("F", dim(-1, -2, 4, 2, 0)),
            ("Pa", dim(1, -1, -2, 0, 0)),
            // N*m*s/rad: the radian is dimensionless.
            ("N*m*s/rad", dim(1, 2, -1, 0, 0)),
            ("m/s^2", dim(0, 1, -2, 0, 0)),
            ("m^3/s", dim(0, 3, -1, 0, 0)),
            ("m", dim(0, 1, 0, 0, 0)),
            ("kg/m^3", dim(1, -3, 0, 0, 0)),
            // N*m/A = V*s: kg m^2 s^-2 A^-1.
            ("N*m/A", dim(1, 2, -2, -1, 0)),
            ("N*m", dim(1, 2, -2, 0, 0)),
            ("1", Dim::NONE),
            ("N/m^3", dim(1, -2, -2, 0, 0)),
            ("K", dim(0, 0, 0, 0, 1)),
            ("A", dim(0, 0, 0, 1, 0)),
            ("rad/s", dim(0, 0, -1, 0, 0)),
            ("kg/m^4", dim(1, -4, 0, 0, 0)),
            ("W", dim(1, 2, -3, 0, 0)),
            ("K/W", dim(-1, -2, 3, 0, 1)),
            ("J/K", dim(1, 2, -2, 0, -1)),
            ("1/m^2", dim(0, -2, 0, 0, 0)),
            ("V*s/rad", dim(1, 2, -2, -1, 0)),
        ];
        for (text, expected) in cases {
            assert_eq!(parsed(text), expected, "{text}");
        }
    }

    #[test]
    fn rad_per_second_and_hertz_agree() {
        assert_eq!(parsed("rad/s"), parsed("1/s"));
        assert_eq!(parsed("Hz"), parsed("s^-1"));
        assert_eq!(parsed("rpm"), parsed("1/s"));
    }

    #[test]
    fn negative_powers_parentheses_prefixes_and_spaces() {
        assert_eq!(parsed("kg*m*s^-2"), parsed("N"));
        assert_eq!(parsed("s^(-1)"), parsed("1/s"));
        assert_eq!(parsed("s⁻¹"), parsed("1/s"));
        assert_eq!(parsed("J/(kg*K)"), dim(0, 2, -2, 0, -1));
        assert_eq!(parsed("N m"), parsed("J"));
        assert_eq!(parsed("N·m"), parsed("J"));
        assert_eq!(parsed("kPa"), parsed("Pa"));
        assert_eq!(parsed("mm/s"), parsed("m/s"));
        assert_eq!(parsed("g"), parsed("kg"));
        assert_eq!(parsed("L/min"), parsed("m^3/s"));
        assert_eq!(parsed("uF"), parsed("F"));
        assert_eq!(parsed("mA"), parsed("A"));
        assert_eq!(parsed("Wb"), parsed("V*s"));
        assert_eq!(parsed("C"), parsed("A*s"));
        assert_eq!(parsed("m^(1/2)").powi(2), parsed("m"));
        // Left to right: N/m/s is N/(m*s).
        assert_eq!(parsed("N/m/s"), dim(1, 0, -3, 0, 0));
    }

    #[test]
    fn an_unknown_symbol_is_named() {
        let error = parse_unit("N*s/furlong").unwrap_err();
        assert_eq!(error.part, "furlong");
        assert_eq!(error.to_string(), "unknown unit 'furlong'");
        assert_eq!(parse_unit("m2").unwrap_err().part, "m2");
        assert_eq!(parse_unit("kg*").unwrap_err().part, "end of the unit");
        assert_eq!(parse_unit("m^").unwrap_err().part, "end of the unit");
        assert_eq!(parse_unit("(m").unwrap_err().part, "end of the unit");
        assert_eq!(parse_unit("m)").unwrap_err().part, ")");
        assert_eq!(parse_unit("").unwrap_err().reason, "empty unit");
    }
}
