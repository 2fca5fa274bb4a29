//! Values between a model file's units and SI.
//!
//! A number written in a model file beside a unit is in that unit: `"k": (value: 0.2,
//! unit: "N/mm")` is 200 N/m. The file is converted once, when it is read
//! ([`Unit::to_si`]); everything after works in SI units. Where a value is written back
//! into a file (a scenario's parameter, a fitted value), it goes in the file's own unit
//! ([`Unit::from_si`]), so that reading the file again gives the same SI value.

use num_bigint::BigInt;
use num_traits::Zero;

use super::parse::{Unit, si_spelling};
use super::scale::{Exact, factor_text};

impl Unit {
    /// Whether a value in this unit is already in SI units (factor 1, no offset).
    pub fn is_si(&self) -> bool {
        self.scale.is_one() && self.offset.is_none()
    }

    /// `value`, written in this unit as `text` (the decimal in the file, if known), in SI
    /// units: the decimal as written times the exact factor, rounded once. Without `text`,
    /// or if `text` does not read as `value`, the double itself is converted. Infinite where
    /// the result is beyond the largest double.
    pub fn to_si(&self, value: f64, text: Option<&str>) -> f64 {
        if !value.is_finite() || self.is_si() {
            return value;
        }
        let exact = text
            .and_then(Exact::decimal)
            .filter(|e| e.to_f64() == value)
            .unwrap_or_else(|| Exact::of_f64(value));
        match &self.offset {
            Some(offset) => self.scale.apply_with_offset(&exact, offset),
            None => self.scale.apply(&exact),
        }
    }

    /// The text to write in a file for SI value `si` in this unit: the shortest decimal that
    /// [`Unit::to_si`] reads back as exactly `si` (within a unit in the last place or two for
    /// a unit with a root, such as `mm^(1/2)`).
    pub fn from_si(&self, si: f64) -> String {
        if self.is_si() || !si.is_finite() {
            return format!("{si:?}");
        }
        let zero = Exact::new(BigInt::zero(), BigInt::from(1));
        self.scale
            .unapply(si, self.offset.as_ref().unwrap_or(&zero))
    }

    /// What `written` (this unit's text) is in SI units, for a message: `"kPa" = 1000 Pa`,
    /// `"%" = 0.01 (dimensionless)`, `"degC" = K - 273.15`.
    pub fn in_si_words(&self, written: &str) -> String {
        let si = self.si_text(written);
        if let Some(offset) = &self.offset {
            return format!("\"{written}\" = {si} - {}", factor_text(offset.to_f64()));
        }
        let factor = factor_text(self.scale.to_f64());
        if si == "1" {
            format!("\"{written}\" = {factor} (dimensionless)")
        } else {
            format!("\"{written}\" = {factor} {si}")
        }
    }

    /// The SI unit values in `written` (this unit's text) convert to: `N/m` for `N/mm`.
    pub fn si_text(&self, written: &str) -> String {
        si_spelling(written).unwrap_or_else(|| self.dim.si())
    }
}

#[cfg(test)]
mod tests {
    use crate::units::parse::parse_scaled;

    #[test]
    fn a_unit_names_its_si_unit_in_its_own_spelling() {
        let si = |text: &str| {
            let unit = parse_scaled(text).unwrap();
            unit.si_text(text)
        };
        for (written, expected) in [
            ("N/mm", "N/m"),
            ("kPa", "Pa"),
            ("L/min", "m^3/s"),
            ("g*cm^2", "kg*m^2"),
            ("kN*s/m", "N*s/m"),
            ("N*m/rpm", "N*m/(rad/s)"),
            ("rpm^2", "(rad/s)^2"),
            ("L²", "(m^3)²"),
            ("1/L", "1/m^3"),
            ("degC", "K"),
            ("J/(kg*°C)", "J/(kg*K)"),
            ("%", "1"),
            ("kWh", "J"),
            ("mm^(1/2)", "m^(1/2)"),
            ("m^3/(s*kPa^0.5)", "m^3/(s*Pa^0.5)"),
            ("N/m", "N/m"),
        ] {
            assert_eq!(si(written), expected, "{written}");
        }
    }

    /// A unit string made of symbols, numbers, operators and powers, as files write them.
    fn unit_string() -> impl proptest::strategy::Strategy<Value = String> {
        use proptest::prelude::*;
        let symbol = prop::sample::select(vec![
            "m", "mm", "kPa", "L", "min", "h", "rpm", "deg", "%", "g", "kg", "N", "degC", "°C",
            "µs", "kWh", "bar", "atm", "1000", "0.5", "Ω", "t", "rev",
        ]);
        let power = prop::sample::select(vec!["", "", "^2", "^-1", "²", "⁻³", "^3"]);
        let op = prop::sample::select(vec!["*", "/", " ", "·"]);
        (
            (symbol.clone(), power.clone()),
            prop::collection::vec((op, symbol, power), 0..4),
            any::<bool>(),
        )
            .prop_map(|((s0, p0), rest, grouped)| {
                let mut text = format!("{s0}{p0}");
                for (op, s, p) in rest {
                    text.push_str(&format!("{op}{s}{p}"));
                }
                if grouped {
                    text = format!("1/({text})");
                }
                text
            })
    }

    proptest::proptest! {
        // The same cases every run; `PROPTEST_RNG_SEED` draws others, to explore.
        #![proptest_config(proptest::prelude::ProptestConfig {
            cases: 512,
            rng_seed: proptest::test_runner::RngSeed::Fixed(1),
            ..proptest::prelude::ProptestConfig::default()
        })]

        /// What an edit writes in a file's unit reads back as exactly the SI value it was
        /// given, for every unit without a root; and the SI spelling is an SI unit of the
        /// same dimension.
        #[test]
        fn a_value_written_in_any_unit_reads_back_exactly(
            text in unit_string(),
            mantissa in 1i64..1_000_000,
            decade in -6i32..6,
            negative in proptest::prelude::any::<bool>(),
        ) {
            let Ok(unit) = parse_scaled(&text) else {
                return Ok(());
            };
            let si = unit.si_text(&text);
            let spelt = parse_scaled(&si).unwrap();
            proptest::prop_assert!(spelt.is_si() && spelt.dim == unit.dim, "{text}: {si}");
            let written = format!("{}{mantissa}e{decade}", if negative { "-" } else { "" });
            let value: f64 = written.parse().unwrap();
            let x = unit.to_si(value, Some(&written));
            proptest::prop_assume!(x.is_finite() && x != 0.0);
            let back = unit.from_si(x);
            proptest::prop_assert_eq!(unit.to_si(back.parse().unwrap(), Some(&back)), x, "{} in {}: {}", x, text, back);
        }
    }

    #[test]
    fn a_huge_power_is_refused_not_wrapped_around() {
        for (text, part) in [
            ("m⁹⁹⁹⁹⁹⁹⁹⁹⁹⁹⁹", "⁹⁹⁹⁹⁹⁹⁹⁹⁹⁹⁹"),
            ("m^99999999999999999999", "^99999999999999999999"),
            ("(m^100000)^100000", "^100000"),
        ] {
            let error = parse_scaled(text).unwrap_err();
            assert_eq!(error.part, part, "{text}");
            assert_eq!(error.reason, "a power too large in", "{text}");
        }
    }

    #[test]
    fn a_unit_is_said_in_si_words() {
        let words = |text: &str| parse_scaled(text).unwrap().in_si_words(text);
        assert_eq!(words("kPa"), "\"kPa\" = 1000 Pa");
        assert_eq!(words("L/min"), "\"L/min\" = 1.6666666666666667e-5 m^3/s");
        assert_eq!(words("%"), "\"%\" = 0.01 (dimensionless)");
        assert_eq!(words("°C"), "\"°C\" = K - 273.15");
    }
}
