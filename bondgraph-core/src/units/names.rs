//! The unit symbols a model file may write, the SI prefixes, and how many SI units each is.
//!
//! A symbol is looked up whole first (`Pa`, `min`, `mol`, `cd`, `kg`), then as a prefix and
//! a symbol (`kPa`, `mm`, `ms`, `mA`, `uF`), so that `m` is a metre, `mm` a millimetre and
//! `min` a minute. Each carries its dimension and its exact factor to the coherent SI unit
//! of that dimension (`g` is 1e-3 kg, `rpm` 2π/60 rad/s); the Celsius temperature is the
//! one unit with an offset as well (see [`Named::offset`]).

use super::dimension::Dim;
use super::scale::Scale;

/// `kg^a m^b s^c A^d K^e mol^f cd^g`.
const fn d(exponents: [i32; 7]) -> Dim {
    Dim::from_integers(exponents)
}

/// An exact factor `num/den · π^pi`, as the tables write it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Factor {
    /// Numerator.
    pub num: u64,
    /// Denominator.
    pub den: u64,
    /// The power of π.
    pub pi: i64,
}

/// Factor 1: a coherent SI unit.
const SI: Factor = f(1, 1);

const fn f(num: u64, den: u64) -> Factor {
    Factor { num, den, pi: 0 }
}

const fn with_pi(num: u64, den: u64) -> Factor {
    Factor { num, den, pi: 1 }
}

/// The named units, with their dimensions and factors to SI.
pub const UNITS: &[(&str, Dim, Factor)] = &[
    // Base units; the gram and the tonne are masses in kg.
    ("kg", d([1, 0, 0, 0, 0, 0, 0]), SI),
    ("g", d([1, 0, 0, 0, 0, 0, 0]), f(1, 1000)),
    ("t", d([1, 0, 0, 0, 0, 0, 0]), f(1000, 1)),
    ("m", d([0, 1, 0, 0, 0, 0, 0]), SI),
    ("s", d([0, 0, 1, 0, 0, 0, 0]), SI),
    ("min", d([0, 0, 1, 0, 0, 0, 0]), f(60, 1)),
    ("h", d([0, 0, 1, 0, 0, 0, 0]), f(3600, 1)),
    ("A", d([0, 0, 0, 1, 0, 0, 0]), SI),
    ("K", d([0, 0, 0, 0, 1, 0, 0]), SI),
    // A Celsius degree is a kelvin in size; alone, a temperature is also offset.
    ("degC", d([0, 0, 0, 0, 1, 0, 0]), SI),
    ("°C", d([0, 0, 0, 0, 1, 0, 0]), SI),
    ("mol", d([0, 0, 0, 0, 0, 1, 0]), SI),
    ("cd", d([0, 0, 0, 0, 0, 0, 1]), SI),
    // Angles and counts are ratios.
    ("rad", Dim::NONE, SI),
    ("sr", Dim::NONE, SI),
    ("deg", Dim::NONE, with_pi(1, 180)),
    ("°", Dim::NONE, with_pi(1, 180)),
    ("rev", Dim::NONE, with_pi(2, 1)),
    ("%", Dim::NONE, f(1, 100)),
    // Derived units.
    ("Hz", d([0, 0, -1, 0, 0, 0, 0]), SI),
    ("rpm", d([0, 0, -1, 0, 0, 0, 0]), with_pi(1, 30)),
    ("N", d([1, 1, -2, 0, 0, 0, 0]), SI),
    ("Pa", d([1, -1, -2, 0, 0, 0, 0]), SI),
    ("bar", d([1, -1, -2, 0, 0, 0, 0]), f(100_000, 1)),
    ("atm", d([1, -1, -2, 0, 0, 0, 0]), f(101_325, 1)),
    ("J", d([1, 2, -2, 0, 0, 0, 0]), SI),
    ("Wh", d([1, 2, -2, 0, 0, 0, 0]), f(3600, 1)),
    ("W", d([1, 2, -3, 0, 0, 0, 0]), SI),
    ("C", d([0, 0, 1, 1, 0, 0, 0]), SI),
    ("V", d([1, 2, -3, -1, 0, 0, 0]), SI),
    ("ohm", d([1, 2, -3, -2, 0, 0, 0]), SI),
    ("Ohm", d([1, 2, -3, -2, 0, 0, 0]), SI),
    ("Ω", d([1, 2, -3, -2, 0, 0, 0]), SI),
    ("S", d([-1, -2, 3, 2, 0, 0, 0]), SI),
    ("F", d([-1, -2, 4, 2, 0, 0, 0]), SI),
    ("Wb", d([1, 2, -2, -1, 0, 0, 0]), SI),
    ("T", d([1, 0, -2, -1, 0, 0, 0]), SI),
    ("H", d([1, 2, -2, -2, 0, 0, 0]), SI),
    ("L", d([0, 3, 0, 0, 0, 0, 0]), f(1, 1000)),
    ("l", d([0, 3, 0, 0, 0, 0, 0]), f(1, 1000)),
];

/// What each symbol stands for in coherent SI units, for writing a value's SI unit: the
/// symbols not listed stand for themselves (and prefixes are dropped).
pub const SI_SPELLING: &[(&str, &str)] = &[
    ("g", "kg"),
    ("t", "kg"),
    ("min", "s"),
    ("h", "s"),
    ("degC", "K"),
    ("°C", "K"),
    ("deg", "rad"),
    ("°", "rad"),
    ("rev", "rad"),
    ("%", "1"),
    ("rpm", "rad/s"),
    ("bar", "Pa"),
    ("atm", "Pa"),
    ("Wh", "J"),
    ("L", "m^3"),
    ("l", "m^3"),
];

/// The SI prefixes (`u`, `µ` and `μ` all micro) and their powers of ten.
pub const PREFIXES: &[(&str, i64)] = &[
    ("Y", 24),
    ("Z", 21),
    ("E", 18),
    ("P", 15),
    ("T", 12),
    ("G", 9),
    ("M", 6),
    ("k", 3),
    ("h", 2),
    ("da", 1),
    ("d", -1),
    ("c", -2),
    ("m", -3),
    ("u", -6),
    ("µ", -6),
    ("μ", -6),
    ("n", -9),
    ("p", -12),
    ("f", -15),
    ("a", -18),
    ("z", -21),
    ("y", -24),
];

/// The units a prefix may go on: the SI ones, not `min`, `h`, `deg`, `rpm` or `%`.
fn takes_prefix(symbol: &str) -> bool {
    !matches!(
        symbol,
        "kg" | "min" | "h" | "deg" | "°" | "rev" | "rpm" | "%" | "atm" | "degC" | "°C" | "t"
    )
}

/// What a unit symbol is.
#[derive(Clone, Debug, PartialEq)]
pub struct Named {
    /// Its dimension.
    pub dim: Dim,
    /// How many coherent SI units it is (prefix included).
    pub scale: Scale,
    /// Whether it is a Celsius temperature: alone, a value in it is offset by 273.15 K.
    pub offset: bool,
    /// The unit without its prefix (`Pa` of `kPa`).
    pub unprefixed: &'static str,
}

/// The dimension of unit symbol `symbol` (`kPa`, `mm`, `ohm`), if it is one.
pub fn lookup(symbol: &str) -> Option<Dim> {
    find(symbol).map(|(_, dim, _, _)| dim)
}

/// What unit symbol `symbol` is: its dimension, factor and offset.
pub fn lookup_scaled(symbol: &str) -> Option<Named> {
    let (name, dim, factor, prefix) = find(symbol)?;
    let scale = Scale::of(factor.num, factor.den, factor.pi)
        .times(&Scale::power_of_ten(prefix))
        .expect("table factors are small");
    Some(Named {
        dim,
        scale,
        offset: matches!(name, "degC" | "°C"),
        unprefixed: name,
    })
}

/// The table entry of `symbol` and its prefix's power of ten.
fn find(symbol: &str) -> Option<(&'static str, Dim, Factor, i64)> {
    if let Some((name, dim, factor)) = UNITS.iter().find(|(name, _, _)| *name == symbol) {
        return Some((name, *dim, *factor, 0));
    }
    PREFIXES.iter().find_map(|(prefix, power)| {
        let rest = symbol.strip_prefix(prefix)?;
        UNITS
            .iter()
            .find(|(name, _, _)| *name == rest && takes_prefix(name))
            .map(|(name, dim, factor)| (*name, *dim, *factor, *power))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_symbols_win_over_prefixes() {
        assert_eq!(lookup("m"), Some(Dim::LENGTH));
        assert_eq!(lookup("mm"), Some(Dim::LENGTH));
        assert_eq!(lookup("ms"), Some(Dim::TIME));
        assert_eq!(lookup("min"), Some(Dim::TIME));
        assert_eq!(lookup("cd"), Some(Dim::LUMINOUS));
        assert_eq!(lookup("kPa"), lookup("Pa"));
        assert_eq!(lookup("mA"), Some(Dim::CURRENT));
        assert_eq!(lookup("uF"), lookup("F"));
        assert_eq!(lookup("mkg"), None);
        assert_eq!(lookup("kmin"), None);
        assert_eq!(lookup("furlong"), None);
    }

    #[test]
    fn a_symbol_is_found_with_its_prefix_and_offset() {
        let kpa = lookup_scaled("kPa").unwrap();
        assert_eq!((kpa.unprefixed, kpa.scale.to_f64()), ("Pa", 1000.0));
        // `h` alone is the hour; before a unit, hecto.
        assert_eq!(lookup_scaled("h").unwrap().scale.to_f64(), 3600.0);
        assert_eq!(lookup_scaled("hPa").unwrap().scale.to_f64(), 100.0);
        // `da` before `d`: a decametre, not a deci-attometre.
        assert_eq!(lookup_scaled("dam").unwrap().scale.to_f64(), 10.0);
        assert!(lookup_scaled("°C").unwrap().offset);
        assert!(!lookup_scaled("K").unwrap().offset);
        assert_eq!(lookup_scaled("kdegC"), None);
    }
}
