//! A model as written: what a model file says, and what a [`Builder`](super::Builder)
//! collects in code.
//!
//! These types mirror what the user writes and nothing more: names are plain strings,
//! expressions are unparsed text, and nothing is checked beyond the shape of the data.
//! Checking (duplicate names, unknown elements, bond counts, expressions) happens in later
//! stages, which need to see the file as written; in particular the maps of parameters,
//! inputs and elements are read as lists of entries in file order, so that a name defined
//! twice is reported instead of silently overwritten. Every struct and enum denies unknown
//! fields, so a misspelt field is an error rather than an ignored line.
//!
//! A model file looks like this (the outer `Model` name is optional, and optional fields
//! are written without `Some(...)`):
//!
//! ```ron
//! Model(
//!     name: "mass-spring-damper",
//!     parameters: {
//!         "m": (value: 1.0, unit: "kg"),
//!         "k": (value: 100.0, unit: "N/m"),
//!     },
//!     inputs: { "F": (unit: "N") },
//!     elements: {
//!         "force": Se(effort: "F"),
//!         "junction": One,
//!         "mass": I(inertance: "m"),
//!         "spring": C(stiffness: "k"),
//!     },
//!     bonds: [("force", "junction"), ("junction", "mass"), ("junction", "spring")],
//! )
//! ```

use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::{Deserializer, MapAccess, Visitor};

/// A whole model file.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Model", deny_unknown_fields)]
pub struct ModelSpec {
    /// The model's name.
    pub name: String,
    /// A description for people.
    pub description: Option<String>,
    /// Named parameters, in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub parameters: Vec<(String, ParameterSpec)>,
    /// Named external inputs (time-varying signals), in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub inputs: Vec<(String, InputSpec)>,
    /// Named elements, in file order, duplicates kept.
    #[serde(default, deserialize_with = "entries")]
    pub elements: Vec<(String, ElementSpec)>,
    /// The bonds between elements.
    #[serde(default)]
    pub bonds: Vec<BondSpec>,
}

/// A parameter: a constant with a value.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Parameter", deny_unknown_fields)]
pub struct ParameterSpec {
    /// The value, in the unit given.
    pub value: f64,
    /// The unit (SI symbols and prefixes, `"N*s/m"`, `"kPa"`): the value is converted to
    /// SI with it and the model's units are checked.
    pub unit: Option<String>,
    /// A description for people.
    pub description: Option<String>,
    /// The range a calibration may move the value in, `(low, high)`: physical limits (a
    /// friction force is not negative) or the plausible range of a fitted coefficient.
    pub bounds: Option<(f64, f64)>,
}

/// An external input: a signal given at simulation time.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Input", deny_unknown_fields)]
pub struct InputSpec {
    /// The unit: the signal is given in SI units of its dimension, and the model's units
    /// are checked with it.
    pub unit: Option<String>,
    /// A description for people.
    pub description: Option<String>,
}

/// An element, tagged with its kind (`I(inertance: "m")`, `Zero`); the coefficients are
/// unparsed expressions over parameters and inputs.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename = "Element", deny_unknown_fields)]
pub enum ElementSpec {
    /// Effort source.
    Se {
        /// The effort it imposes.
        effort: String,
    },
    /// Flow source.
    Sf {
        /// The flow it imposes.
        flow: String,
    },
    /// Inertia (mass, inductance), given by exactly one of inertance or a nonlinear law.
    I {
        /// The inertance.
        inertance: Option<String>,
        /// A nonlinear law: the flow as an expression of the momentum `p_NAME`.
        flow: Option<String>,
    },
    /// Capacitance (spring, capacitor), given by exactly one of compliance, stiffness or a
    /// nonlinear law; the validator checks that exactly one is given.
    C {
        /// The compliance (1/stiffness).
        compliance: Option<String>,
        /// The stiffness (1/compliance).
        stiffness: Option<String>,
        /// A nonlinear law: the effort as an expression of the displacement `q_NAME`.
        effort: Option<String>,
    },
    /// Resistance (damper, resistor), given by exactly one of resistance, an effort law or
    /// a flow law.
    R {
        /// The resistance; may depend on inputs and states (modulated).
        resistance: Option<String>,
        /// A nonlinear law: the effort as an expression of the port's `flow`.
        effort: Option<String>,
        /// A nonlinear law: the flow as an expression of the port's `effort`.
        flow: Option<String>,
    },
    /// Transformer (lever, gear pair): relates the efforts and the flows of its two bonds.
    TF {
        /// The transformer modulus.
        ratio: String,
    },
    /// Gyrator (motor constant): relates each bond's effort to the other bond's flow.
    GY {
        /// The gyrator modulus.
        ratio: String,
    },
    /// Karnopp friction contact on its bond's relative velocity: stuck, or slipping with
    /// `viscous·v + coulomb·sgn(v)`; it breaks away when the force it must hold reaches
    /// `breakaway`. Modes `stuck`, `slip+`, `slip-`; with a Stribeck velocity also `creep+`,
    /// `creep-`.
    Friction {
        /// The breakaway (static) force; may depend on inputs.
        breakaway: String,
        /// The Coulomb (kinetic) force; may depend on inputs.
        coulomb: String,
        /// The viscous coefficient (default 0).
        viscous: Option<String>,
        /// Karnopp's dead band: slipping below this speed sticks, if the contact can hold
        /// (default 0).
        dead_band: Option<String>,
        /// The Stribeck velocity `v_s` (default none): slipping slower than it (modes
        /// `creep+`, `creep-`), the kinetic force falls linearly with speed from the
        /// breakaway force at rest to the Coulomb force at `v_s` (velocity weakening).
        stribeck: Option<String>,
        /// The mode at the start: `"stuck"` (default), `"slip+"` or `"slip-"`.
        initial: Option<String>,
    },
    /// A compliance that carries tension only (a string): `taut` it is a linear compliance,
    /// `slack` it carries no force while its slack length is tracked. Given by exactly one
    /// of compliance or stiffness.
    TensionOnly {
        /// The compliance when taut.
        compliance: Option<String>,
        /// The stiffness when taut.
        stiffness: Option<String>,
        /// The mode at the start: `"taut"` (default) or `"slack"`.
        initial: Option<String>,
    },
    /// A one-sided limit on the flow through its bond: `open` it carries no effort, and
    /// when the flow into it reaches `max_flow` it is `limiting`, holding the flow there
    /// with whatever effort that takes until that effort falls to zero.
    FlowLimit {
        /// The largest flow into the element; may depend on inputs.
        max_flow: String,
        /// The mode at the start: `"open"` (default) or `"limiting"`.
        initial: Option<String>,
    },
    /// A resistor given by its conductance, `f = conductance · e`. Model files do not write
    /// it (serde skips it): it is what a linear graph's `D(resistance: "R")` becomes, since a
    /// linear-graph resistance relates across to through, which are a bond graph's flow and
    /// effort.
    #[serde(skip)]
    Conductance {
        /// The conductance (1/resistance), positive.
        conductance: String,
    },
    /// A gyrator given by the reciprocal of its modulus, `e_in = f_out / ratio`. Model files
    /// do not write it (serde skips it): it is what a linear graph's `Gyrator(ratio: "G")`
    /// becomes, since a linear-graph gyrator relates an across variable (a bond graph's flow)
    /// to a through variable (effort), the inverse of a bond-graph gyrator.
    #[serde(skip)]
    ReciprocalGY {
        /// The reciprocal of the gyrator modulus, non-zero.
        ratio: String,
    },
    /// Common-effort junction.
    Zero,
    /// Common-flow junction.
    One,
}

/// A bond `("from", "to")`: power flows from the first element to the second.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename = "Bond", deny_unknown_fields)]
pub struct BondSpec(pub String, pub String);

impl ParameterSpec {
    /// A parameter of `value` in `unit` (`""` for none), with no description or bounds.
    pub fn new(value: f64, unit: &str) -> Self {
        Self {
            value,
            unit: (!unit.is_empty()).then(|| unit.to_owned()),
            description: None,
            bounds: None,
        }
    }
}

impl ElementSpec {
    /// An effort source `Se(effort: ...)`.
    pub fn effort_source(effort: &str) -> Self {
        Self::Se {
            effort: effort.into(),
        }
    }

    /// A flow source `Sf(flow: ...)`.
    pub fn flow_source(flow: &str) -> Self {
        Self::Sf { flow: flow.into() }
    }

    /// A linear inertia `I(inertance: ...)`.
    pub fn inertance(inertance: &str) -> Self {
        Self::I {
            inertance: Some(inertance.into()),
            flow: None,
        }
    }

    /// A linear capacitance `C(stiffness: ...)`.
    pub fn stiffness(stiffness: &str) -> Self {
        Self::C {
            compliance: None,
            stiffness: Some(stiffness.into()),
            effort: None,
        }
    }

    /// A linear capacitance `C(compliance: ...)`.
    pub fn compliance(compliance: &str) -> Self {
        Self::C {
            compliance: Some(compliance.into()),
            stiffness: None,
            effort: None,
        }
    }

    /// A resistance `R(resistance: ...)`.
    pub fn resistance(resistance: &str) -> Self {
        Self::R {
            resistance: Some(resistance.into()),
            effort: None,
            flow: None,
        }
    }

    /// A transformer `TF(ratio: ...)`.
    pub fn transformer(ratio: &str) -> Self {
        Self::TF {
            ratio: ratio.into(),
        }
    }

    /// A gyrator `GY(ratio: ...)`.
    pub fn gyrator(ratio: &str) -> Self {
        Self::GY {
            ratio: ratio.into(),
        }
    }

    /// A Karnopp friction contact `Friction(breakaway: ..., coulomb: ...)`, stuck at the
    /// start, with no viscous term, dead band or Stribeck velocity (set the fields of
    /// [`ElementSpec::Friction`] for those).
    pub fn friction(breakaway: &str, coulomb: &str) -> Self {
        Self::Friction {
            breakaway: breakaway.into(),
            coulomb: coulomb.into(),
            viscous: None,
            dead_band: None,
            stribeck: None,
            initial: None,
        }
    }
}

/// Reads a RON map as its entries in file order, keeping duplicate keys.
pub(crate) fn entries<'de, D, T>(deserializer: D) -> Result<Vec<(String, T)>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct EntriesVisitor<T>(PhantomData<T>);

    impl<'de, T: Deserialize<'de>> Visitor<'de> for EntriesVisitor<T> {
        type Value = Vec<(String, T)>;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a map of names to entries")
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut entries = Vec::with_capacity(map.size_hint().unwrap_or(0).min(1024));
            while let Some((key, value)) = map.next_entry::<String, T>()? {
                entries.push((key, value));
            }
            Ok(entries)
        }
    }

    deserializer.deserialize_map(EntriesVisitor(PhantomData))
}

impl ModelSpec {
    /// Reads a model from RON `text` with the options model files use (optional fields
    /// without `Some(...)`); errors are ron's, turned into diagnostics by
    /// [`parse_model`](super::parse::parse_model).
    #[cfg(test)]
    pub fn from_ron(text: &str) -> Result<Self, ron::error::SpannedError> {
        ron_options().from_str(text)
    }
}

/// The RON options model files are read with: `IMPLICIT_SOME`, so that users write
/// `unit: "kg"` rather than `unit: Some("kg")`.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
}

#[cfg(test)]
mod tests {
    use super::*;

    const MODEL: &str = r#"
        Model(
            name: "mass-spring-damper",
            description: "a mass on a spring and a damper",
            parameters: {
                "m": (value: 1.5, unit: "kg", description: "the mass"),
                "k": (value: 100, unit: "N/m"),
                "b": (value: 2.0),
            },
            inputs: { "F": (unit: "N") },
            elements: {
                "force": Se(effort: "F"),
                "j": One,
                "mass": I(inertance: "m"),
                "spring": C(stiffness: "k"),
                "damper": R(resistance: "b"),
            },
            bonds: [("force", "j"), ("j", "mass"), Bond("j", "spring"), ("j", "damper")],
        )
    "#;

    #[test]
    fn reads_a_whole_model_in_file_order() {
        let model = ModelSpec::from_ron(MODEL).unwrap();
        assert_eq!(model.name, "mass-spring-damper");
        assert_eq!(
            model.description.as_deref(),
            Some("a mass on a spring and a damper")
        );
        let names: Vec<&str> = model.parameters.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["m", "k", "b"]);
        assert_eq!(
            model.parameters[0].1,
            ParameterSpec {
                value: 1.5,
                unit: Some("kg".into()),
                description: Some("the mass".into()),
                bounds: None,
            }
        );
        assert_eq!(model.parameters[1].1.value, 100.0);
        assert_eq!(model.inputs[0].0, "F");
        assert_eq!(model.inputs[0].1.unit.as_deref(), Some("N"));
        let elements: Vec<(&str, &ElementSpec)> = model
            .elements
            .iter()
            .map(|(n, e)| (n.as_str(), e))
            .collect();
        assert_eq!(
            elements,
            [
                ("force", &ElementSpec::Se { effort: "F".into() }),
                ("j", &ElementSpec::One),
                (
                    "mass",
                    &ElementSpec::I {
                        inertance: Some("m".into()),
                        flow: None,
                    }
                ),
                (
                    "spring",
                    &ElementSpec::C {
                        compliance: None,
                        stiffness: Some("k".into()),
                        effort: None,
                    }
                ),
                (
                    "damper",
                    &ElementSpec::R {
                        resistance: Some("b".into()),
                        effort: None,
                        flow: None,
                    }
                ),
            ]
        );
        assert_eq!(model.bonds[2], BondSpec("j".into(), "spring".into()));
        assert_eq!(model.bonds.len(), 4);
    }

    #[test]
    fn the_model_name_is_optional_and_sections_default_to_empty() {
        let model = ModelSpec::from_ron(r#"(name: "empty")"#).unwrap();
        assert_eq!(model.name, "empty");
        assert_eq!(model.description, None);
        assert!(model.parameters.is_empty() && model.inputs.is_empty());
        assert!(model.elements.is_empty() && model.bonds.is_empty());
        let named = ModelSpec::from_ron(MODEL).unwrap();
        let unnamed = ModelSpec::from_ron(MODEL.replacen("Model(", "(", 1).as_str()).unwrap();
        assert_eq!(named, unnamed);
    }

    #[test]
    fn duplicate_names_are_kept_for_later_diagnosis() {
        let model = ModelSpec::from_ron(
            r#"(name: "d", parameters: {"m": (value: 1), "m": (value: 2)},
                elements: {"a": Zero, "b": One, "a": I(inertance: "m")})"#,
        )
        .unwrap();
        let values: Vec<f64> = model.parameters.iter().map(|(_, p)| p.value).collect();
        assert_eq!(values, [1.0, 2.0]);
        let names: Vec<&str> = model.elements.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["a", "b", "a"]);
    }

    #[test]
    fn explicit_some_and_every_element_kind_are_accepted() {
        let model = ModelSpec::from_ron(
            r#"(name: "all", description: Some("d"), elements: {
                "se": Se(effort: "e"), "sf": Sf(flow: "f"), "i": I(inertance: "m"),
                "c": C(compliance: "1/k"), "r": R(resistance: "b"), "tf": TF(ratio: "n"),
                "gy": GY(ratio: "K"), "z": Zero, "o": One, "cc": C(),
            })"#,
        )
        .unwrap();
        assert_eq!(model.description.as_deref(), Some("d"));
        assert_eq!(model.elements.len(), 10);
        assert_eq!(
            model.elements[3].1,
            ElementSpec::C {
                compliance: Some("1/k".into()),
                stiffness: None,
                effort: None,
            }
        );
        // Neither or both of compliance and stiffness is the validator's business.
        assert_eq!(
            model.elements[9].1,
            ElementSpec::C {
                compliance: None,
                stiffness: None,
                effort: None,
            }
        );
    }

    #[test]
    fn unknown_fields_are_denied_everywhere() {
        let cases = [
            r#"(name: "x", extra: 1)"#,
            r#"(name: "x", parameters: {"m": (value: 1, units: "kg")})"#,
            r#"(name: "x", inputs: {"u": (value: 1)})"#,
            r#"(name: "x", elements: {"m": I(inertance: "m", mass: "m")})"#,
            r#"(name: "x", elements: {"c": C(compliance: "m", damping: "b")})"#,
        ];
        for case in cases {
            let error = ModelSpec::from_ron(case).unwrap_err();
            assert!(
                matches!(error.code, ron::Error::NoSuchStructField { .. }),
                "{case}: {error}"
            );
        }
    }
}
