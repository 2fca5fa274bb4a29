//! The unit symbols a model file may write, and the SI prefixes.
//!
//! A symbol is looked up whole first (`Pa`, `min`, `mol`, `cd`, `kg`), then as a prefix and
//! a symbol (`kPa`, `mm`, `ms`, `mA`, `uF`), so that `m` is a metre, `mm` a millimetre and
//! `min` a minute. Scale factors do not matter to a dimension check and are not kept.

use super::dimension::Dim;

/// `kg^a m^b s^c A^d K^e mol^f cd^g`.
const fn d(exponents: [i32; 7]) -> Dim {
    Dim::from_integers(exponents)
}

/// The named units, with their dimensions.
pub const UNITS: &[(&str, Dim)] = &[
    // Base units (the gram carries the kilogram's dimension).
    ("kg", d([1, 0, 0, 0, 0, 0, 0])),
    ("g", d([1, 0, 0, 0, 0, 0, 0])),
    ("t", d([1, 0, 0, 0, 0, 0, 0])),
    ("m", d([0, 1, 0, 0, 0, 0, 0])),
    ("s", d([0, 0, 1, 0, 0, 0, 0])),
    ("min", d([0, 0, 1, 0, 0, 0, 0])),
    ("h", d([0, 0, 1, 0, 0, 0, 0])),
    ("A", d([0, 0, 0, 1, 0, 0, 0])),
    ("K", d([0, 0, 0, 0, 1, 0, 0])),
    ("degC", d([0, 0, 0, 0, 1, 0, 0])),
    ("°C", d([0, 0, 0, 0, 1, 0, 0])),
    ("mol", d([0, 0, 0, 0, 0, 1, 0])),
    ("cd", d([0, 0, 0, 0, 0, 0, 1])),
    // Angles and counts are ratios.
    ("rad", Dim::NONE),
    ("sr", Dim::NONE),
    ("deg", Dim::NONE),
    ("°", Dim::NONE),
    ("rev", Dim::NONE),
    ("%", Dim::NONE),
    // Derived units.
    ("Hz", d([0, 0, -1, 0, 0, 0, 0])),
    ("rpm", d([0, 0, -1, 0, 0, 0, 0])),
    ("N", d([1, 1, -2, 0, 0, 0, 0])),
    ("Pa", d([1, -1, -2, 0, 0, 0, 0])),
    ("bar", d([1, -1, -2, 0, 0, 0, 0])),
    ("atm", d([1, -1, -2, 0, 0, 0, 0])),
    ("J", d([1, 2, -2, 0, 0, 0, 0])),
    ("Wh", d([1, 2, -2, 0, 0, 0, 0])),
    ("W", d([1, 2, -3, 0, 0, 0, 0])),
    ("C", d([0, 0, 1, 1, 0, 0, 0])),
    ("V", d([1, 2, -3, -1, 0, 0, 0])),
    ("ohm", d([1, 2, -3, -2, 0, 0, 0])),
    ("Ohm", d([1, 2, -3, -2, 0, 0, 0])),
    ("Ω", d([1, 2, -3, -2, 0, 0, 0])),
    ("S", d([-1, -2, 3, 2, 0, 0, 0])),
    ("F", d([-1, -2, 4, 2, 0, 0, 0])),
    ("Wb", d([1, 2, -2, -1, 0, 0, 0])),
    ("T", d([1, 0, -2, -1, 0, 0, 0])),
    ("H", d([1, 2, -2, -2, 0, 0, 0])),
    ("L", d([0, 3, 0, 0, 0, 0, 0])),
    ("l", d([0, 3, 0, 0, 0, 0, 0])),
];

/// The SI prefixes (`u` and `µ` both micro).
pub const PREFIXES: &[&str] = &[
    "Y", "Z", "E", "P", "T", "G", "M", "k", "h", "da", "d", "c", "m", "u", "µ", "μ", "n", "p", "f",
    "a",
];

/// The units a prefix may go on: the SI ones, not `min`, `h`, `deg`, `rpm` or `%`.
fn takes_prefix(symbol: &str) -> bool {
    !matches!(
        symbol,
        "kg" | "min" | "h" | "deg" | "°" | "rev" | "rpm" | "%" | "atm" | "degC" | "°C" | "t"
    )
}

/// The dimension of unit symbol `symbol` (`kPa`, `mm`, `ohm`), if it is one.
pub fn lookup(symbol: &str) -> Option<Dim> {
    if let Some((_, dim)) = UNITS.iter().find(|(name, _)| *name == symbol) {
        return Some(*dim);
    }
    PREFIXES.iter().find_map(|prefix| {
        let rest = symbol.strip_prefix(prefix)?;
        UNITS
            .iter()
            .find(|(name, _)| *name == rest && takes_prefix(name))
            .map(|(_, dim)| *dim)
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
}
