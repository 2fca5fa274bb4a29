//! Physical dimensions as exponents of the SI base dimensions.
//!
//! A unit string, a parameter and an expression all come down to one [`Dim`]: the exponents
//! of kg, m, s, A, K, mol and cd. Only the dimension matters to the checks (a `kPa` is a
//! pressure like a `Pa`); scale factors are kept apart ([`super::scale`]). The radian is a ratio of lengths and
//! counts as dimensionless, so `rad/s` and `1/s` agree, as do a torque `N*m` and `N*m/rad`.
//!
//! Exponents are kept in twelfths, so that square roots (`sqrt(k/m)`), cube roots and the
//! real powers written in laws (`x^1.5`) stay exact; a power that is not a multiple of 1/12
//! has no dimension this type can hold, and the inference treats it as unknown.

use std::fmt;

/// The number of SI base dimensions kept (kg, m, s, A, K, mol, cd).
pub const BASE_COUNT: usize = 7;

/// The symbols of the base dimensions, in the order of [`Dim`]'s exponents.
pub const BASE_SYMBOLS: [&str; BASE_COUNT] = ["kg", "m", "s", "A", "K", "mol", "cd"];

/// Exponents are stored multiplied by this.
const SCALE: i32 = 12;

/// Why a power of a dimension has no [`Dim`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PowError {
    /// An exponent would not be a multiple of 1/12.
    TooFine,
    /// An exponent would not fit.
    TooLarge,
}

/// A physical dimension: the exponent of each SI base dimension, in twelfths.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct Dim([i32; BASE_COUNT]);

impl Dim {
    /// The dimension of a pure number (and of an angle).
    pub const NONE: Dim = Dim([0; BASE_COUNT]);

    /// Mass, kg.
    pub const MASS: Dim = Dim::base(0);
    /// Length, m.
    pub const LENGTH: Dim = Dim::base(1);
    /// Time, s.
    pub const TIME: Dim = Dim::base(2);
    /// Electric current, A.
    pub const CURRENT: Dim = Dim::base(3);
    /// Temperature, K.
    pub const TEMPERATURE: Dim = Dim::base(4);
    /// Amount of substance, mol.
    pub const AMOUNT: Dim = Dim::base(5);
    /// Luminous intensity, cd.
    pub const LUMINOUS: Dim = Dim::base(6);

    /// The base dimension with index `index` in [`BASE_SYMBOLS`].
    const fn base(index: usize) -> Dim {
        let mut exponents = [0; BASE_COUNT];
        exponents[index] = SCALE;
        Dim(exponents)
    }

    /// The dimension `kg^a m^b s^c A^d K^e mol^f cd^g` from integer exponents.
    pub const fn from_integers(exponents: [i32; BASE_COUNT]) -> Dim {
        let mut scaled = [0; BASE_COUNT];
        let mut i = 0;
        while i < BASE_COUNT {
            scaled[i] = exponents[i] * SCALE;
            i += 1;
        }
        Dim(scaled)
    }

    /// Whether this is the dimension of a pure number.
    pub fn is_dimensionless(self) -> bool {
        self == Dim::NONE
    }

    /// The product of two dimensions (exponents add).
    pub fn times(self, other: Dim) -> Dim {
        let mut out = self.0;
        for (o, x) in out.iter_mut().zip(other.0) {
            *o += x;
        }
        Dim(out)
    }

    /// The quotient of two dimensions (exponents subtract).
    pub fn per(self, other: Dim) -> Dim {
        self.times(other.recip())
    }

    /// The reciprocal (exponents negated).
    pub fn recip(self) -> Dim {
        Dim(self.0.map(|x| -x))
    }

    /// The integer power `self^n`.
    pub fn powi(self, n: i32) -> Dim {
        Dim(self.0.map(|x| x * n))
    }

    /// The rational power `self^(num/den)`, if every exponent stays a multiple of 1/12.
    pub fn pow_ratio(self, num: i32, den: i32) -> Option<Dim> {
        if den == 0 {
            return None;
        }
        let mut out = [0; BASE_COUNT];
        for (o, x) in out.iter_mut().zip(self.0) {
            let scaled = x.checked_mul(num)?;
            if scaled % den != 0 {
                return None;
            }
            *o = scaled / den;
        }
        Some(Dim(out))
    }

    /// The rational power `self^(num/den)` (`den > 0`), or why it has no dimension this
    /// type can hold.
    ///
    /// # Errors
    /// [`PowError::TooFine`] if some exponent would not be a multiple of 1/12,
    /// [`PowError::TooLarge`] if one would not fit.
    pub fn checked_pow(self, num: i64, den: i64) -> Result<Dim, PowError> {
        let mut out = [0; BASE_COUNT];
        for (o, x) in out.iter_mut().zip(self.0) {
            let scaled = i64::from(x).checked_mul(num).ok_or(PowError::TooLarge)?;
            if den == 0 || scaled % den != 0 {
                return Err(PowError::TooFine);
            }
            *o = i32::try_from(scaled / den).map_err(|_| PowError::TooLarge)?;
        }
        Ok(Dim(out))
    }

    /// The real power `self^p`, if `p` is a multiple of 1/12 (or `self` is dimensionless).
    pub fn powf(self, p: f64) -> Option<Dim> {
        if self.is_dimensionless() {
            return Some(Dim::NONE);
        }
        let twelfths = p * f64::from(SCALE);
        if !twelfths.is_finite() || (twelfths - twelfths.round()).abs() > 1e-9 {
            return None;
        }
        self.pow_ratio(twelfths.round() as i32, SCALE)
    }

    /// The exponent of base dimension `index` as `(numerator, denominator)` in lowest
    /// terms.
    pub fn exponent(self, index: usize) -> (i32, i32) {
        let x = self.0[index];
        let g = gcd(x.abs(), SCALE);
        (x / g, SCALE / g)
    }

    /// The dimension in SI base units: `kg*m^2/s^2`, `1/s`, `1` for none.
    pub fn si(self) -> String {
        let mut up = Vec::new();
        let mut down = Vec::new();
        for (i, symbol) in BASE_SYMBOLS.iter().enumerate() {
            let (num, den) = self.exponent(i);
            if num == 0 {
                continue;
            }
            let target = if num > 0 { &mut up } else { &mut down };
            target.push(power_text(symbol, num.abs(), den));
        }
        match (up.is_empty(), down.is_empty()) {
            (true, true) => "1".to_string(),
            (false, true) => up.join("*"),
            (true, false) => format!("1/{}", group(&down)),
            (false, false) => format!("{}/{}", up.join("*"), group(&down)),
        }
    }
}

fn power_text(symbol: &str, num: i32, den: i32) -> String {
    match (num, den) {
        (1, 1) => symbol.to_string(),
        (n, 1) => format!("{symbol}^{n}"),
        (n, d) => format!("{symbol}^({n}/{d})"),
    }
}

fn group(parts: &[String]) -> String {
    if parts.len() == 1 {
        parts[0].clone()
    } else {
        format!("({})", parts.join("*"))
    }
}

fn gcd(a: i32, b: i32) -> i32 {
    if b == 0 { a.max(1) } else { gcd(b, a % b) }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.si())
    }
}

/// What the check found of one bond: the dimensions of its effort and flow, where known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BondDimensions {
    /// The effort's dimension.
    pub effort: Option<Dim>,
    /// The flow's dimension.
    pub flow: Option<Dim>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_quotients_and_powers_add_exponents() {
        // N = kg*m/s^2, so N/m = kg/s^2.
        let newton = Dim::MASS.times(Dim::LENGTH).per(Dim::TIME.powi(2));
        assert_eq!(
            newton.per(Dim::LENGTH),
            Dim::from_integers([1, 0, -2, 0, 0, 0, 0])
        );
        assert_eq!(newton.si(), "kg*m/s^2");
        assert_eq!(Dim::TIME.recip().si(), "1/s");
        assert_eq!(Dim::NONE.si(), "1");
        assert_eq!(
            Dim::from_integers([-1, -2, 4, 2, 0, 0, 0]).si(),
            "s^4*A^2/(kg*m^2)"
        );
    }

    #[test]
    fn a_square_root_halves_exponents_and_stays_exact() {
        // sqrt(k/m) with k in N/m and m in kg is 1/s.
        let k_over_m = Dim::from_integers([0, 0, -2, 0, 0, 0, 0]);
        assert_eq!(k_over_m.powf(0.5), Some(Dim::TIME.recip()));
        assert_eq!(Dim::LENGTH.powf(0.5).unwrap().si(), "m^(1/2)");
        assert_eq!(Dim::LENGTH.powf(0.1), None);
        assert_eq!(Dim::NONE.powf(0.1), Some(Dim::NONE));
    }
}
