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

#[cfg(any(test, feature = "deserialize"))]
use serde::Deserialize;

/// A whole model file.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Model", deny_unknown_fields)
)]
pub struct ModelSpec {
    /// The model's name.
    pub name: String,
    /// A description for people.
    pub description: Option<String>,
    /// Named parameters, in file order, duplicates kept.
    #[cfg_attr(
        any(test, feature = "deserialize"),
        serde(default, deserialize_with = "entries")
    )]
    pub parameters: Vec<(String, ParameterSpec)>,
    /// Named external inputs (time-varying signals), in file order, duplicates kept.
    #[cfg_attr(
        any(test, feature = "deserialize"),
        serde(default, deserialize_with = "entries")
    )]
    pub inputs: Vec<(String, InputSpec)>,
    /// Named elements, in file order, duplicates kept.
    #[cfg_attr(
        any(test, feature = "deserialize"),
        serde(default, deserialize_with = "entries")
    )]
    pub elements: Vec<(String, ElementSpec)>,
    /// The bonds between elements.
    #[cfg_attr(any(test, feature = "deserialize"), serde(default))]
    pub bonds: Vec<BondSpec>,
    /// Named ports, in file order: the junctions that bonds from outside attach to when the
    /// model is used as a sub-model of another ([`ElementSpec::Submodel`]).
    #[cfg_attr(
        any(test, feature = "deserialize"),
        serde(default, deserialize_with = "entries")
    )]
    pub ports: Vec<(String, PortSpec)>,
    /// The sub-models this model was composed from, once a reader has flattened them into
    /// its elements (their elements named `front.spring`); never written in a file.
    #[cfg_attr(any(test, feature = "deserialize"), serde(skip))]
    pub parts: Vec<PartSpec>,
}

/// A port of a model used as a sub-model: a 0- or 1-junction of the model, to which the
/// using model's bonds attach (as many as it likes; each adds to the junction's bonds).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Port", deny_unknown_fields)
)]
pub struct PortSpec {
    /// The junction the port is (in a model with sub-models of its own, possibly a
    /// sub-model's port, `"wheel.axle"`).
    pub element: String,
    /// A description for people.
    pub description: Option<String>,
}

/// A value given to a sub-model's parameter where it is used.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(untagged)
)]
pub enum ParameterValue {
    /// A new value in the parameter's own unit (as the sub-model writes it): the parameter
    /// stays a parameter (`front.k_s`), with this value.
    Value(f64),
    /// An expression of the using model's parameters (`"k_front"`, `"2*k"`): the
    /// sub-model's parameter is replaced by it, and is a parameter no longer.
    Expression(String),
}

/// One use of a sub-model, recorded when it was flattened: what its name, file and ports
/// became.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartSpec {
    /// The use's name, the prefix of its elements (`front`; `front.rear` nested).
    pub name: String,
    /// The sub-model's file, as the using file names it.
    pub file: String,
    /// The sub-model's own name (its `name:` field).
    pub model: String,
    /// Its ports, each with the flattened element it is (`("hub", "front.hub_force")`).
    pub ports: Vec<(String, String)>,
    /// Where each of its elements (flattened names) is written in its own file, so that a
    /// problem found in the composed model can say so.
    pub origins: Vec<(String, crate::source::Location)>,
}

/// A parameter: a constant with a value.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Parameter", deny_unknown_fields)
)]
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
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Input", deny_unknown_fields)
)]
pub struct InputSpec {
    /// The unit: the signal is given in SI units of its dimension, and the model's units
    /// are checked with it.
    pub unit: Option<String>,
    /// A description for people.
    pub description: Option<String>,
}

/// An element, tagged with its kind (`I(inertance: "m")`, `Zero`); the coefficients are
/// unparsed expressions over parameters and inputs.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Element", deny_unknown_fields)
)]
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
        /// The name of its state, its momentum, in place of `p_NAME` (`"L_w"`, `"h"`).
        symbol: Option<String>,
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
        /// The name of its state, its displacement, in place of `q_NAME` (`"V_tank"`, `"x"`).
        symbol: Option<String>,
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
        /// The name of its state, its stretch, in place of `q_NAME`.
        symbol: Option<String>,
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
    #[cfg_attr(any(test, feature = "deserialize"), serde(skip))]
    Conductance {
        /// The conductance (1/resistance), positive.
        conductance: String,
    },
    /// A gyrator given by the reciprocal of its modulus, `e_in = f_out / ratio`. Model files
    /// do not write it (serde skips it): it is what a linear graph's `Gyrator(ratio: "G")`
    /// becomes, since a linear-graph gyrator relates an across variable (a bond graph's flow)
    /// to a through variable (effort), the inverse of a bond-graph gyrator.
    #[cfg_attr(any(test, feature = "deserialize"), serde(skip))]
    ReciprocalGY {
        /// The reciprocal of the gyrator modulus, non-zero.
        ratio: String,
    },
    /// A sub-model: another model file used here as one element, several times if need
    /// be, its bonds attaching to its ports (`"front.hub"`). Readers flatten it into its
    /// elements, named with the use's name in front (`front.spring`), before validation.
    Submodel {
        /// The model file, relative to the file that uses it.
        file: String,
        /// Values for the sub-model's parameters in this use, by the sub-model's names.
        #[cfg_attr(
            any(test, feature = "deserialize"),
            serde(default, deserialize_with = "entries")
        )]
        parameters: Vec<(String, ParameterValue)>,
        /// Signals for the sub-model's inputs in this use: expressions of the using model's
        /// inputs and parameters, by the sub-model's names. An input not given stays an
        /// input of the whole model (`front.V`).
        #[cfg_attr(
            any(test, feature = "deserialize"),
            serde(default, deserialize_with = "entries")
        )]
        inputs: Vec<(String, String)>,
    },
    /// Common-effort junction.
    Zero,
    /// Common-flow junction.
    One,
}

/// A bond `("from", "to")`: power flows from the first element to the second.
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(
    any(test, feature = "deserialize"),
    derive(Deserialize),
    serde(rename = "Bond", deny_unknown_fields)
)]
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
    /// The element's expressions (coefficients and laws), each with its field's name, in
    /// field order; a sub-model's and a junction's are none.
    pub fn expressions_mut(&mut self) -> Vec<(&'static str, &mut String)> {
        let mut out: Vec<(&'static str, &mut String)> = Vec::new();
        match self {
            Self::Se { effort } => out.push(("effort", effort)),
            Self::Sf { flow } => out.push(("flow", flow)),
            Self::I {
                inertance, flow, ..
            } => {
                out.extend(inertance.as_mut().map(|e| ("inertance", e)));
                out.extend(flow.as_mut().map(|e| ("flow", e)));
            }
            Self::C {
                compliance,
                stiffness,
                effort,
                ..
            } => {
                out.extend(compliance.as_mut().map(|e| ("compliance", e)));
                out.extend(stiffness.as_mut().map(|e| ("stiffness", e)));
                out.extend(effort.as_mut().map(|e| ("effort", e)));
            }
            Self::R {
                resistance,
                effort,
                flow,
            } => {
                out.extend(resistance.as_mut().map(|e| ("resistance", e)));
                out.extend(effort.as_mut().map(|e| ("effort", e)));
                out.extend(flow.as_mut().map(|e| ("flow", e)));
            }
            Self::TF { ratio } | Self::GY { ratio } | Self::ReciprocalGY { ratio } => {
                out.push(("ratio", ratio));
            }
            Self::Friction {
                breakaway,
                coulomb,
                viscous,
                dead_band,
                stribeck,
                initial: _,
            } => {
                out.push(("breakaway", breakaway));
                out.push(("coulomb", coulomb));
                out.extend(viscous.as_mut().map(|e| ("viscous", e)));
                out.extend(dead_band.as_mut().map(|e| ("dead_band", e)));
                out.extend(stribeck.as_mut().map(|e| ("stribeck", e)));
            }
            Self::TensionOnly {
                compliance,
                stiffness,
                ..
            } => {
                out.extend(compliance.as_mut().map(|e| ("compliance", e)));
                out.extend(stiffness.as_mut().map(|e| ("stiffness", e)));
            }
            Self::FlowLimit {
                max_flow,
                initial: _,
            } => out.push(("max_flow", max_flow)),
            Self::Conductance { conductance } => out.push(("conductance", conductance)),
            Self::Submodel { .. } | Self::Zero | Self::One => {}
        }
        out
    }

    /// The state name the element gives itself (`symbol:`), if it is storage that does.
    pub fn symbol(&self) -> Option<&str> {
        match self {
            Self::I { symbol, .. } | Self::C { symbol, .. } | Self::TensionOnly { symbol, .. } => {
                symbol.as_deref()
            }
            _ => None,
        }
    }

    /// The state name the element gives itself, to rename it (a sub-model's, qualified).
    pub fn symbol_mut(&mut self) -> Option<&mut String> {
        match self {
            Self::I { symbol, .. } | Self::C { symbol, .. } | Self::TensionOnly { symbol, .. } => {
                symbol.as_mut()
            }
            _ => None,
        }
    }

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
            symbol: None,
        }
    }

    /// A linear capacitance `C(stiffness: ...)`.
    pub fn stiffness(stiffness: &str) -> Self {
        Self::C {
            compliance: None,
            stiffness: Some(stiffness.into()),
            effort: None,
            symbol: None,
        }
    }

    /// A linear capacitance `C(compliance: ...)`.
    pub fn compliance(compliance: &str) -> Self {
        Self::C {
            compliance: Some(compliance.into()),
            stiffness: None,
            effort: None,
            symbol: None,
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

#[cfg(any(test, feature = "deserialize"))]
/// Reads a map as its entries in file order, keeping duplicate keys.
pub fn entries<'de, D, T>(deserializer: D) -> Result<Vec<(String, T)>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: serde::Deserialize<'de>,
{
    use serde::de::{MapAccess, Visitor};
    use std::fmt;
    use std::marker::PhantomData;

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
