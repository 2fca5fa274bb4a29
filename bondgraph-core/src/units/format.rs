//! A dimension written the way an engineer would: `N/m`, `kg*m^2`, `Pa*s/m^3`, `1/F`.
//!
//! The checks report the unit an element needs; `kg/s^2` is correct for a translational
//! stiffness but reads worse than `N/m`. [`readable`] tries short combinations of common
//! units (one, then two, then three symbols, in a fixed order of preference) and falls back
//! on SI base units.

use super::dimension::Dim;
use super::names::lookup;

/// The units tried, most preferred first.
const PREFERRED: &[&str] = &[
    "N", "m", "kg", "s", "Pa", "V", "A", "ohm", "F", "H", "W", "J", "K", "C", "Wb", "m^2", "m^3",
    "s^2", "mol",
];

fn dim_of(symbol: &str) -> Dim {
    match symbol {
        "m^2" => Dim::LENGTH.powi(2),
        "m^3" => Dim::LENGTH.powi(3),
        "s^2" => Dim::TIME.powi(2),
        _ => lookup(symbol).unwrap_or(Dim::NONE),
    }
}

/// `target` as the first of `hints` (unit strings) that has its dimension, else as
/// [`readable`] writes it: a domain passes the units its textbooks use (`N*s/m`, not `kg/s`).
pub fn readable_with(target: Dim, hints: &[&str]) -> String {
    hints
        .iter()
        .find(|hint| super::parse::parse_unit(hint) == Ok(target))
        .map_or_else(|| readable(target), |hint| (*hint).to_string())
}

/// `target` as a short combination of common units, or in SI base units.
pub fn readable(target: Dim) -> String {
    if target.is_dimensionless() {
        return "1 (dimensionless)".to_string();
    }
    let units: Vec<(&str, Dim)> = PREFERRED.iter().map(|s| (*s, dim_of(s))).collect();
    for (name, dim) in &units {
        if *dim == target {
            return (*name).to_string();
        }
        if dim.recip() == target {
            return format!("1/{name}");
        }
    }
    for (a, da) in &units {
        for (b, db) in &units {
            if da.times(*db) == target {
                return product(a, b);
            }
            if da.per(*db) == target {
                return format!("{a}/{b}");
            }
        }
    }
    for (a, da) in &units {
        for (b, db) in &units {
            for (c, dc) in &units {
                if da.times(*db).per(*dc) == target {
                    return format!("{}/{c}", product(a, b));
                }
            }
        }
    }
    target.si()
}

/// `a*b` with a derived unit before a base one (`Pa*s`, `N*m`, `kg*m^2`).
fn product(a: &str, b: &str) -> String {
    let base = |u: &str| {
        matches!(
            u,
            "kg" | "m" | "s" | "A" | "K" | "mol" | "m^2" | "m^3" | "s^2"
        )
    };
    if base(a) && !base(b) {
        format!("{b}*{a}")
    } else {
        format!("{a}*{b}")
    }
}

#[cfg(test)]
mod tests {
    use super::super::parse::parse_unit;
    use super::*;

    #[test]
    fn the_laws_own_units_read_as_textbooks_write_them() {
        let cases = [
            ("kg*m/s^2", "N"),
            ("kg/s^2", "N/m"),
            ("kg/s", "kg/s"),
            ("kg*m^2", "kg*m^2"),
            ("kg*m^2/s^2", "J"),
            ("kg/(m^4*s)", "Pa*s/m^3"),
            ("s^4*A^2/(kg*m^2)", "F"),
            ("kg*m^2/(s^4*A^2)", "1/F"),
            ("m/s", "m/s"),
            ("1/s", "1/s"),
        ];
        for (si, expected) in cases {
            assert_eq!(readable(parse_unit(si).unwrap()), expected, "{si}");
        }
        assert_eq!(readable(Dim::NONE), "1 (dimensionless)");
        let damping = parse_unit("kg/s").unwrap();
        assert_eq!(readable_with(damping, &["N/m", "N*s/m"]), "N*s/m");
        assert_eq!(readable_with(damping, &["N/m"]), "kg/s");
    }
}
