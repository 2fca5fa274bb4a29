//! Unit strings, as model files write them, to a [`Dim`].
//!
//! ```text
//! unit    := factor (('*' | '·' | '/' | ' ') factor)*        (left to right: N*s/m is (N*s)/m)
//! factor  := primary power?
//! power   := '^' '-'? integer | '^' '(' '-'? integer ('/' integer)? ')' | superscripts (m², s⁻¹)
//! primary := symbol | number | '(' unit ')'
//! ```
//!
//! A symbol is a named unit, possibly with an SI prefix ([`super::names`]); a number (`1`,
//! `1000`) is dimensionless. Anything else is a [`UnitError`] naming the part that is not
//! understood, so a diagnostic can say which of `N*s/mm2` is wrong.

use std::fmt;

use super::dimension::Dim;
use super::names;

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

/// The dimension of unit string `text` (`"N*s/m"`, `"kg*m^2"`, `"1/s"`, `"J/(kg*K)"`).
///
/// # Errors
/// A [`UnitError`] naming the unknown symbol, or the place where the string stops making
/// sense.
pub fn parse_unit(text: &str) -> Result<Dim, UnitError> {
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
    let dim = parser.product()?;
    parser.skip_spaces();
    match parser.peek() {
        None => Ok(dim),
        Some(_) => Err(parser.error_here("unexpected")),
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

    fn product(&mut self) -> Result<Dim, UnitError> {
        let mut dim = self.factor()?;
        loop {
            let spaced = self.skip_spaces();
            match self.peek() {
                Some('*' | '·') => {
                    self.at += 1;
                    self.skip_spaces();
                    dim = dim.times(self.factor()?);
                }
                Some('/') => {
                    self.at += 1;
                    self.skip_spaces();
                    dim = dim.per(self.factor()?);
                }
                Some(c) if spaced && c != ')' => dim = dim.times(self.factor()?),
                _ => return Ok(dim),
            }
        }
    }

    fn factor(&mut self) -> Result<Dim, UnitError> {
        let base = self.primary()?;
        if self.peek() == Some('^') {
            self.at += 1;
            let (num, den) = self.exponent()?;
            return base
                .pow_ratio(num, den)
                .ok_or_else(|| self.error_here("a power too fine to keep exactly before"));
        }
        if self
            .peek()
            .is_some_and(|c| c == '⁻' || SUPERSCRIPTS.contains(&c))
        {
            let negative = self.peek() == Some('⁻');
            if negative {
                self.at += 1;
            }
            let mut n: i32 = 0;
            let mut digits = 0;
            while let Some(d) = self
                .peek()
                .and_then(|c| SUPERSCRIPTS.iter().position(|s| *s == c))
            {
                n = n.saturating_mul(10).saturating_add(d as i32);
                digits += 1;
                self.at += 1;
            }
            if digits == 0 {
                return Err(self.error_here("a superscript minus needs digits before"));
            }
            return Ok(base.powi(if negative { -n } else { n }));
        }
        Ok(base)
    }

    fn integer(&mut self) -> Result<i32, UnitError> {
        let negative = self.peek() == Some('-');
        if negative || self.peek() == Some('+') {
            self.at += 1;
        }
        let start = self.at;
        while self.peek().is_some_and(|c| c.is_ascii_digit()) {
            self.at += 1;
        }
        if self.at == start {
            return Err(self.error_here("a power needs an integer before"));
        }
        let text: String = self.chars[start..self.at].iter().collect();
        let n: i32 = text
            .parse()
            .map_err(|_| self.error_here("a power too large before"))?;
        Ok(if negative { -n } else { n })
    }

    fn exponent(&mut self) -> Result<(i32, i32), UnitError> {
        if self.peek() != Some('(') {
            return Ok((self.integer()?, 1));
        }
        self.at += 1;
        let num = self.integer()?;
        let den = if self.peek() == Some('/') {
            self.at += 1;
            self.integer()?
        } else {
            1
        };
        if self.peek() != Some(')') {
            return Err(self.error_here("a power's ')' is missing before"));
        }
        self.at += 1;
        if den == 0 {
            return Err(self.error_here("a power divides by zero before"));
        }
        Ok((num, den))
    }

    fn primary(&mut self) -> Result<Dim, UnitError> {
        match self.peek() {
            Some('(') => {
                self.at += 1;
                self.skip_spaces();
                let dim = self.product()?;
                self.skip_spaces();
                if self.peek() != Some(')') {
                    return Err(self.error_here("a ')' is missing before"));
                }
                self.at += 1;
                Ok(dim)
            }
            Some(c) if is_symbol_char(c) => {
                let start = self.at;
                while self.peek().is_some_and(is_symbol_char) {
                    self.at += 1;
                }
                let symbol: String = self.chars[start..self.at].iter().collect();
                if symbol.parse::<f64>().is_ok_and(f64::is_finite) {
                    return Ok(Dim::NONE);
                }
                names::lookup(&symbol).ok_or(UnitError {
                    part: symbol,
                    reason: "unknown unit".to_string(),
                })
            }
            _ => Err(self.error_here("a unit is missing before")),
        }
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
